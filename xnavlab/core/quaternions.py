"""Attitude quaternions with the scalar last, as in the attitude chapter's source paper.

A quaternion is ``q = [q1, q2, q3, q4]`` with vector part ``rho = q[:3]`` and scalar
``q4`` (paper eq. (4)); a unit quaternion ``q = [e sin(theta/2); cos(theta/2)]``
describes a rotation by ``theta`` about the unit axis ``e``. The conventions are those
of Shuster (1993), Lefferts, Markley & Shuster (1982) and Crassidis & Junkins (2012):

- :func:`rotation_matrix` ``A(q)`` maps vectors from the reference (inertial, J2000)
  frame to the body frame, ``v_body = A(q) v_ref``;
- :func:`quat_product` composes like the matrices, ``A(p (x) q) = A(p) A(q)``;
- the kinematics is ``q_dot = 1/2 Omega(w) q = 1/2 Xi(q) w`` with ``w`` the body
  angular rate, rad/s (paper eqs. (5)-(8), (20)).

Every function accepts leading batch dimensions (``(..., 4)``, ``(..., 3)``), so a
bank of filters or a whole Monte Carlo batch is processed in one call. Angles and
rates are SI (rad, rad/s, s). Two arguments of one call (``p`` and ``q``; ``q`` and ``w``)
must have batch shapes that broadcast, else one ValueError names both.

A rotation angle (``|phi|``, ``|w| dt``) is at most :data:`MAX_ANGLE` (1e6 rad): a float
holds an angle only to ``|angle| 2^-52``, so a larger one keeps ever fewer digits of its
position on the circle (1.2e-10 rad at 1e6 rad, 0.1 rad at 1e15 rad, none from about
3e16 rad), and the quaternion of it would be finite but arbitrary.
"""

from __future__ import annotations

import numpy as np

from xnavlab.core.validate import check_finite_array, check_real, shown

__all__ = [
    "IDENTITY",
    "UNIT_TOL",
    "MAX_ANGLE",
    "skew",
    "quat_normalize",
    "quat_conjugate",
    "quat_product",
    "rotation_matrix",
    "omega_matrix",
    "xi_matrix",
    "psi_matrix",
    "kinematics_matrix",
    "kinematics_matrix_unchecked",
    "xi_matrix_unchecked",
    "quat_propagate",
    "quat_from_rotvec",
    "quat_to_rotvec",
    "attitude_error",
]

#: The identity rotation, scalar last.
IDENTITY = np.array([0.0, 0.0, 0.0, 1.0])

#: How far from 1 the norm of a quaternion a function takes as a unit one may be
#: (:func:`rotation_matrix`, :func:`attitude_error`): a float32 quaternion is within 1e-7.
UNIT_TOL = 1e-6

#: The largest rotation angle a function takes, rad (:func:`quat_from_rotvec`'s ``|phi|``,
#: :func:`quat_propagate`'s and :func:`kinematics_matrix`'s ``|w| dt``): about 160,000 turns,
#: where a float still places the angle on the circle to 1.2e-10 rad (its spacing there),
#: far finer than any attitude sensor. Beyond it the digits left mod 2 pi thin out (0.1 rad
#: at 1e15 rad, none from about 3e16 rad): the result would be finite but arbitrary, so such
#: an angle is refused rather than wrapped.
MAX_ANGLE = 1e6


def _quat(name, q, unit=False):
    """A quaternion (an attitude): finite, shape (..., 4), never zero; ``unit``: of norm 1 to
    :data:`UNIT_TOL` (a function that does not renormalise would scale its result by |q|^2)."""
    q = check_finite_array(name, q, shape=(4,))
    n = _norm(q)
    if np.any(n == 0.0):
        raise ValueError(f"{name} must have a non-zero norm, got a zero quaternion")
    if unit and np.any(np.abs(n - 1.0) > UNIT_TOL):
        worst = float(n.flat[int(np.argmax(np.abs(n - 1.0)))])
        raise ValueError(f"{name} must be a unit quaternion (|{name}| = 1 to {UNIT_TOL:g}; "
                         f"quat_normalize makes one), got |{name}| = {worst:.6g}")
    return q


def _norm(v):
    """Euclidean norm over the last axis, exact where the squares over- or underflow (1e300,
    1e-200): those rows are scaled by their largest entry first; the rest as numpy computes."""
    with np.errstate(over="ignore", under="ignore"):
        n = np.linalg.norm(v, axis=-1)
    odd = ~(n > 1e-150) | ~np.isfinite(n)
    if np.any(odd):
        m = np.max(np.abs(v), axis=-1)
        safe = np.where(odd & (m > 0.0), m, 1.0)
        with np.errstate(over="ignore"):  # beyond the float range: inf, refused by the caller
            n = np.where(odd, safe * np.linalg.norm(v / safe[..., None], axis=-1), n)
    return n


def _vec(name, v):
    return check_finite_array(name, v, shape=(3,))


def _batch(a_name, a, b_name, b):
    """The batch shape of two arguments (all axes but the last), refused when they do not
    broadcast: numpy's own message names no parameter."""
    try:
        return np.broadcast_shapes(a.shape[:-1], b.shape[:-1])
    except ValueError:
        raise ValueError(f"{a_name} and {b_name} must have batch shapes that broadcast (all "
                         f"axes but the last), got {a_name} of shape {a.shape} and {b_name} of "
                         f"shape {b.shape}") from None


def _check_angle(name, angle, unit=""):
    """A rotation angle (rad) of at most :data:`MAX_ANGLE`, else one ValueError naming it."""
    worst = float(np.max(angle, initial=0.0))
    if not worst <= MAX_ANGLE:
        raise ValueError(f"{name} must be a rotation angle of at most {MAX_ANGLE:g} rad (a "
                         f"float holds a larger one with few or no digits mod 2 pi), got "
                         f"{worst:.3g} rad{unit}")


def _skew(v):
    out = np.zeros(v.shape[:-1] + (3, 3))
    out[..., 0, 1] = -v[..., 2]
    out[..., 0, 2] = v[..., 1]
    out[..., 1, 0] = v[..., 2]
    out[..., 1, 2] = -v[..., 0]
    out[..., 2, 0] = -v[..., 1]
    out[..., 2, 1] = v[..., 0]
    return out


def _omega(w):
    out = np.zeros(w.shape[:-1] + (4, 4))
    out[..., :3, :3] = _skew(-w)
    out[..., :3, 3] = w
    out[..., 3, :3] = -w
    return out


def _xi(q):
    out = np.zeros(q.shape[:-1] + (4, 3))
    out[..., :3, :] = _skew(q[..., :3])
    for i in range(3):
        out[..., i, i] = q[..., 3]
    out[..., 3, :] = -q[..., :3]
    return out


def _phi(w, dt):
    with np.errstate(over="ignore"):
        half = 0.5 * _norm(w) * dt
    if not np.all(np.isfinite(half)):
        raise ValueError(f"w and dt must give a finite rotation angle |w| dt, rad, got |w| = "
                         f"{float(np.max(_norm(w))):.3g} rad/s over dt = {dt:g} s")
    if not float(np.max(2.0 * half, initial=0.0)) <= MAX_ANGLE:  # the message only when refused
        _check_angle("|w| dt", 2.0 * half, f" (|w| = {float(np.max(_norm(w), initial=0.0)):.3g} "
                     f"rad/s over dt = {dt:g} s)")
    c = np.cos(half)  # paper eq. (11)
    s_over = 0.5 * dt * np.sinc(half / np.pi)  # s / |w|, paper eq. (11)
    out = _omega(w * s_over[..., None])
    for i in range(4):
        out[..., i, i] = c
    return out  # c I4 + s Omega(n), paper eq. (12)


def skew(v):
    """Cross-product matrix ``[v x]``, so that ``skew(v) @ u == cross(v, u)``.

    Parameters
    ----------
    v : array_like, shape (..., 3)

    Returns
    -------
    ndarray, shape (..., 3, 3)

    Examples
    --------
    >>> skew([1.0, 2.0, 3.0]) @ np.array([4.0, 5.0, 6.0])
    array([-3.,  6., -3.])
    """
    return _skew(_vec("v", v))


def quat_normalize(q):
    """Return ``q / |q|``.

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Any quaternion with non-zero norm (1e300 and 1e-300 entries too: the norm is
        taken scaled where the squares would over- or underflow).

    Raises
    ------
    ValueError
        If some ``q`` has zero norm.

    Examples
    --------
    >>> quat_normalize([0.0, 0.0, 0.0, 2.0])
    array([0., 0., 0., 1.])
    """
    q = _quat("q", q)
    return q / _norm(q)[..., None]


def quat_conjugate(q):
    """Conjugate ``[-rho; q4]``: the inverse rotation of a unit quaternion.

    Parameters
    ----------
    q : array_like, shape (..., 4)

    Returns
    -------
    ndarray, shape (..., 4)

    Examples
    --------
    >>> quat_conjugate([0.1, 0.2, 0.3, 0.9])
    array([-0.1, -0.2, -0.3,  0.9])
    """
    q = _quat("q", q)
    return np.concatenate([-q[..., :3], q[..., 3:]], axis=-1)


def quat_product(p, q):
    """Quaternion product ``p (x) q`` with ``A(p (x) q) = A(p) A(q)``.

    ``p (x) q = [p4 rho_q + q4 rho_p - rho_p x rho_q;  p4 q4 - rho_p . rho_q]``
    (Shuster 1993; Crassidis & Junkins 2012, ch. 7, scalar last), equivalently
    ``[Psi(p) p] q`` with :func:`psi_matrix`.

    Parameters
    ----------
    p, q : array_like, shape (..., 4)

    Returns
    -------
    ndarray, shape (..., 4)

    Examples
    --------
    >>> q = quat_from_rotvec([0.0, 0.0, 0.3])
    >>> np.allclose(quat_product(q, quat_conjugate(q)), IDENTITY)
    True
    """
    p = _quat("p", p)
    q = _quat("q", q)
    _batch("p", p, "q", q)
    pv, ps = p[..., :3], p[..., 3:]
    qv, qs = q[..., :3], q[..., 3:]
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is refused below
        vec = ps * qv + qs * pv - np.cross(pv, qv)
        sca = ps * qs - np.sum(pv * qv, axis=-1, keepdims=True)
        out = np.concatenate([vec, sca], axis=-1)
        if not np.all(np.isfinite(out)):
            raise ValueError(f"p and q must have a finite product, got |p| |q| = "
                             f"{float(np.max(_norm(p) * _norm(q))):.3g} (normalise them first)")
    return out


def rotation_matrix(q):
    """Attitude matrix ``A(q)`` (reference-to-body), ``A = Xi(q)^T Psi(q)``.

    ``A(q) = (q4^2 - |rho|^2) I3 - 2 q4 [rho x] + 2 rho rho^T`` (Shuster 1993).

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Unit quaternion (not renormalised here: a norm further than :data:`UNIT_TOL` from
        1, or zero, is refused).

    Returns
    -------
    ndarray, shape (..., 3, 3)
        ``v_body = A @ v_ref``.

    Examples
    --------
    >>> A = rotation_matrix(quat_from_rotvec([0.0, 0.0, np.pi / 2]))
    >>> np.round(A @ np.array([1.0, 0.0, 0.0]), 12)
    array([ 0., -1.,  0.])
    """
    q = _quat("q", q, unit=True)
    rho, q4 = q[..., :3], q[..., 3]
    eye = np.eye(3)
    a = (q4**2 - np.sum(rho * rho, axis=-1))[..., None, None] * eye
    return a - 2.0 * q4[..., None, None] * _skew(rho) + 2.0 * rho[..., :, None] * rho[..., None, :]


def omega_matrix(w):
    """``Omega(w) = [[-[w x], w], [-w^T, 0]]`` (paper eq. (8)), shape (..., 4, 4).

    With it the kinematics reads ``q_dot = 1/2 Omega(w) q`` (paper eq. (7)).

    Parameters
    ----------
    w : array_like, shape (..., 3)
        Body angular rate, rad/s (or any 3-vector).

    Examples
    --------
    >>> omega_matrix([1.0, 2.0, 3.0])[3]
    array([-1., -2., -3.,  0.])
    """
    return _omega(_vec("w", w))


def xi_matrix(q):
    """``Xi(q) = [[q4 I3 + [rho x]], [-rho^T]]`` (paper eq. (21)), shape (..., 4, 3).

    It satisfies ``Omega(x) q = Xi(q) x`` (paper eq. (20)), ``Xi^T Xi = |q|^2 I3`` and
    ``Xi(q)^T q = 0``.

    Parameters
    ----------
    q : array_like, shape (..., 4)

    Examples
    --------
    >>> q = quat_from_rotvec([0.1, -0.2, 0.3]); x = np.array([1.0, 2.0, 3.0])
    >>> np.allclose(omega_matrix(x) @ q, xi_matrix(q) @ x)
    True
    """
    return _xi(_quat("q", q))


def psi_matrix(q):
    """``Psi(q) = [[q4 I3 - [rho x]], [-rho^T]]``, shape (..., 4, 3).

    ``p (x) q = [Psi(p) p] q`` and ``A(q) = Xi(q)^T Psi(q)`` (Shuster 1993).

    Parameters
    ----------
    q : array_like, shape (..., 4)

    Examples
    --------
    >>> q = quat_from_rotvec([0.1, -0.2, 0.3])
    >>> np.allclose(xi_matrix(q).T @ psi_matrix(q), rotation_matrix(q))
    True
    """
    q = _quat("q", q)
    rho, q4 = q[..., :3], q[..., 3]
    out = np.zeros(q.shape[:-1] + (4, 3))
    out[..., :3, :] = q4[..., None, None] * np.eye(3) - _skew(rho)
    out[..., 3, :] = -rho
    return out


def kinematics_matrix(w, dt):
    """Discrete transition ``Phi(w) = c I4 + s Omega(n)`` of the attitude kinematics.

    ``n = w/|w|``, ``c = cos(|w| dt/2)``, ``s = sin(|w| dt/2)`` (paper eqs. (10)-(12);
    Crassidis & Junkins 2012, ch. 7). ``s Omega(n)`` is evaluated as
    ``(dt/2) sinc(|w| dt/2) Omega(w)``, so ``w = 0`` is exact. ``Phi`` is orthogonal.

    Parameters
    ----------
    w : array_like, shape (..., 3)
        Body angular rate held constant over the step, rad/s.
    dt : float
        Step, s, >= 0; the angle ``|w| dt`` at most :data:`MAX_ANGLE`.

    Returns
    -------
    ndarray, shape (..., 4, 4)

    Examples
    --------
    >>> Phi = kinematics_matrix([0.01, -0.02, 0.03], 0.1)
    >>> np.allclose(Phi @ Phi.T, np.eye(4))
    True
    """
    return _phi(_vec("w", w), check_real("dt", dt, 0.0))


def kinematics_matrix_unchecked(w, dt):
    """:func:`kinematics_matrix` without the conversion and checks of its inputs, for inner loops.

    The caller guarantees what :func:`kinematics_matrix` checks: ``w`` a finite float ndarray
    of shape (..., 3), ``dt`` a float >= 0. The angle ``|w| dt`` is still refused when it is
    not finite or exceeds :data:`MAX_ANGLE` (a filter's estimate may run away). A step of the
    attitude filter bank costs about half as much without the checks of every input; only the
    types and the trailing shape are checked (a fraction of a microsecond), so that anything
    else (a list, a bool, a 0-d array, an ndarray subclass: a masked array) is refused naming
    it, not failed inside.

    Parameters
    ----------
    w : ndarray, shape (..., 3)
        Body angular rate, rad/s.
    dt : float
        Step, s.

    Returns
    -------
    ndarray, shape (..., 4, 4)

    Examples
    --------
    >>> w = np.array([0.01, -0.02, 0.03])
    >>> bool(np.array_equal(kinematics_matrix_unchecked(w, 0.1), kinematics_matrix(w, 0.1)))
    True
    """
    if type(w) is not np.ndarray or w.dtype.kind != "f" or w.shape[-1:] != (3,):  # no np.ma (35m)
        raise ValueError(f"w must be a float ndarray of shape (..., 3) (no conversion here), got "
                         f"{type(w).__name__} {shown(np.asarray(w) if isinstance(w, np.ndarray) else w)}")
    if isinstance(dt, bool) or not isinstance(dt, float | int | np.floating | np.integer) or not dt >= 0:
        raise ValueError(f"dt must be a real number in [0, inf), s, got {shown(dt)}")
    return _phi(w, dt)


def xi_matrix_unchecked(q):
    """:func:`xi_matrix` without the conversion and checks of ``q``, for inner loops.

    The caller guarantees a finite float ndarray of shape (..., 4), not zero; only the type (a
    plain ndarray, no subclass: a masked array's mask would be dropped) and the trailing shape
    are checked (a fraction of a microsecond), so that anything else is refused naming ``q``,
    not failed inside.

    Parameters
    ----------
    q : ndarray, shape (..., 4)

    Returns
    -------
    ndarray, shape (..., 4, 3)

    Examples
    --------
    >>> q = quat_from_rotvec([0.1, -0.2, 0.3])
    >>> bool(np.array_equal(xi_matrix_unchecked(q), xi_matrix(q)))
    True
    """
    if type(q) is not np.ndarray or q.dtype.kind != "f" or q.shape[-1:] != (4,):  # no np.ma (35m)
        raise ValueError(f"q must be a float ndarray of shape (..., 4) (no conversion here), got "
                         f"{type(q).__name__} {shown(np.asarray(q) if isinstance(q, np.ndarray) else q)}")
    return _xi(q)


def quat_propagate(q, w, dt):
    """Exact discrete kinematics for a rate held constant over ``dt``.

    ``q(k+1) = [c I4 + s Omega(n)] q(k)`` (paper eq. (12)), see
    :func:`kinematics_matrix`; equivalently ``q(k+1) = dq(w dt) (x) q(k)``. The norm of
    ``q`` is preserved.

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Attitude at step k.
    w : array_like, shape (..., 3)
        Body angular rate over the step, rad/s.
    dt : float
        Step, s, >= 0; the angle ``|w| dt`` at most :data:`MAX_ANGLE`.

    Returns
    -------
    ndarray, shape (..., 4)

    Examples
    --------
    >>> q1 = quat_propagate(IDENTITY, [0.0, 0.0, 0.1], 10.0)   # 1 rad about z
    >>> np.allclose(q1, quat_from_rotvec([0.0, 0.0, 1.0]))
    True
    """
    q = _quat("q", q)
    _batch("q", q, "w", _vec("w", w))
    phi = kinematics_matrix(w, dt)
    return np.einsum("...ij,...j->...i", phi, q)  # paper eq. (12)


def quat_from_rotvec(phi):
    """Unit quaternion of the rotation vector ``phi`` (axis times angle, rad).

    ``q = [sin(|phi|/2) phi/|phi|; cos(|phi|/2)]``.

    Parameters
    ----------
    phi : array_like, shape (..., 3)
        Rotation vector, rad; its norm at most :data:`MAX_ANGLE`.

    Returns
    -------
    ndarray, shape (..., 4)

    Examples
    --------
    >>> np.round(quat_from_rotvec([np.pi, 0.0, 0.0]), 12)
    array([1., 0., 0., 0.])
    """
    phi = _vec("phi", phi)
    ang = _norm(phi)
    if not np.all(np.isfinite(ang)):
        raise ValueError("phi must have a finite norm (the rotation angle, rad), got one beyond "
                         "the float range")
    _check_angle("|phi|", ang)
    vec = 0.5 * np.sinc(0.5 * ang / np.pi)[..., None] * phi  # sin(a/2)/a * phi
    return np.concatenate([vec, np.cos(0.5 * ang)[..., None]], axis=-1)


def quat_to_rotvec(q):
    """Rotation vector (rad) of a unit quaternion, angle in ``[0, pi]``.

    ``q`` and ``-q`` give the same rotation vector.

    Parameters
    ----------
    q : array_like, shape (..., 4)

    Returns
    -------
    ndarray, shape (..., 3)

    Examples
    --------
    >>> np.round(quat_to_rotvec(quat_from_rotvec([0.1, -0.2, 0.3])), 12)
    array([ 0.1, -0.2,  0.3])
    """
    q = quat_normalize(q)
    q = np.where(q[..., 3:] < 0.0, -q, q)
    vn = np.linalg.norm(q[..., :3], axis=-1)
    ang = 2.0 * np.arctan2(vn, q[..., 3])
    # ang / vn -> 2 as vn -> 0 (q4 -> 1)
    factor = np.where(vn > 1e-12, ang / np.where(vn > 1e-12, vn, 1.0), 2.0)
    return factor[..., None] * q[..., :3]


def attitude_error(q_est, q_true):
    """Small-angle attitude error ``dtheta`` with ``q_est = dq(dtheta) (x) q_true``.

    The rotation vector of ``q_est (x) q_true^-1``, in the body frame, rad.

    Parameters
    ----------
    q_est, q_true : array_like, shape (..., 4)
        Unit quaternions.

    Returns
    -------
    ndarray, shape (..., 3)

    Examples
    --------
    >>> dq = quat_from_rotvec([1e-4, 0.0, 0.0])
    >>> q = quat_from_rotvec([0.3, 0.2, 0.1])
    >>> np.allclose(attitude_error(quat_product(dq, q), q), [1e-4, 0.0, 0.0])
    True
    """
    q_est, q_true = _quat("q_est", q_est), _quat("q_true", q_true)
    _batch("q_est", q_est, "q_true", q_true)
    return quat_to_rotvec(quat_product(q_est, quat_conjugate(q_true)))
