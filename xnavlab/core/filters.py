"""Extended and unscented Kalman filters as pure step functions, plus thin classes.

Every filter step is a pure function of ``(x, P, ...)`` that returns new arrays; the
classes :class:`EKF` and :class:`UKF` only hold the state between calls. A
measurement update can always be skipped (``z=None``): the filter then does its time
update only, which is what a subsystem flagged faulty does in the federated filter
(:mod:`xnavlab.core.federated`).

EKF
    time update ``x- = f(x)``, ``P- = F P F^T + Q``; measurement update with the
    Joseph form ``P+ = (I - K H) P- (I - K H)^T + K R K^T`` (Bucy and Joseph 1968),
    which keeps ``P`` symmetric positive definite for any gain; the covariance is
    re-symmetrised after every step.
UKF
    the scaled unscented transform of Julier (2002) with the weights of Wan and van
    der Merwe (2000); defaults ``alpha = 1, beta = 2, kappa = 0`` (all weights
    positive, sigma points at ``sqrt(n)`` standard deviations), see
    :func:`ukf_weights`.

Consistency statistics: :func:`nees` (normalised estimation error squared),
:func:`nis` (normalised innovation squared) and :func:`chi2_bounds` for their
Monte Carlo averages (Bar-Shalom, Li and Kirubarajan 2001, section 5.4).

Shapes: state ``x`` (n,), covariance ``P`` (n, n), measurement ``z`` (m,),
``H`` (m, n), ``R`` (m, m). Units are whatever the model uses (SI in xnavlab).

Guarded steps: every step checks its inputs by default (``check=True``): finite
arrays of the stated shapes, ``P`` and ``Q`` symmetric positive semi-definite, ``R``
positive definite, and the model's outputs ``f(x)``, ``h(x)``, ``F``, ``H`` finite and
of the right shape. A bad input raises one :class:`ValueError` naming the argument, so
no NaN and no negative NIS leaves a step. Loops that have checked their inputs once pass
``check=False`` and pay nothing.

Examples
--------
A constant-velocity target observed in position:

>>> F = np.array([[1.0, 1.0], [0.0, 1.0]]); H = np.array([[1.0, 0.0]])
>>> x, P = np.zeros(2), np.eye(2) * 100.0
>>> x, P = ekf_predict(x, P, lambda s: F @ s, F, np.eye(2) * 1e-3)
>>> up = ekf_update(x, P, np.array([1.0]), lambda s: H @ s, H, np.eye(1))
>>> bool(up.P[0, 0] < 1.0), round(float(up.nis), 3)
(True, 0.005)
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from xnavlab.core.distributions import DOF_RANGE, chi2_ppf
from xnavlab.core.validate import (
    check_bool,
    check_callable,
    check_covariance,
    check_definite,
    check_finite_array,
    check_int,
    check_real,
    check_symmetric,
    check_vector,
)

__all__ = [
    "Update",
    "symmetrize",
    "ekf_predict",
    "ekf_update",
    "joseph",
    "ukf_weights",
    "sigma_points",
    "unscented_transform",
    "ukf_predict",
    "ukf_update",
    "nees",
    "nis",
    "chi2_bounds",
    "CONSISTENCY_VERDICTS",
    "consistency_verdict",
    "judge_series",
    "EKF",
    "UKF",
]


class Update(NamedTuple):
    """Result of a measurement update.

    Attributes
    ----------
    x : ndarray, shape (n,)
        Updated state (the prior when the update was skipped).
    P : ndarray, shape (n, n)
        Updated covariance.
    innovation : ndarray, shape (m,) or None
        ``z - h(x-)`` (None when skipped).
    S : ndarray, shape (m, m) or None
        Innovation covariance ``H P- H^T + R``.
    nis : float
        Normalised innovation squared ``nu^T S^-1 nu`` (NaN when skipped).
    """

    x: np.ndarray
    P: np.ndarray
    innovation: np.ndarray | None
    S: np.ndarray | None
    nis: float


def symmetrize(P):
    """Return ``(P + P^T) / 2``.

    Examples
    --------
    >>> symmetrize(np.array([[1.0, 2.0], [0.0, 1.0]])).tolist()
    [[1.0, 1.0], [1.0, 1.0]]
    """
    return _sym(_square("P", P))


def _sym(P):
    return 0.5 * (P + P.T)


def _square(name, value, n=None):
    """A finite square matrix (of size ``n`` when given), or ValueError naming it."""
    arr = check_finite_array(name, value)
    if arr.ndim != 2 or arr.shape[0] != arr.shape[1] or (n is not None and arr.shape[0] != n):
        want = "(n, n)" if n is None else f"({n}, {n})"
        raise ValueError(f"{name} must be a square matrix of shape {want}, got shape {arr.shape}")
    return arr


def _scaled(name, M, definite=False):
    """``M`` with its variances (diagonal) in [0, 1e100], from 1e-100 if ``definite``."""
    # Variances within 1e+-100 in any unit keep H P H^T + R and e^2 / var inside the float
    # range (1e+-308): R = 5e-324 made S^-1 infinite (NaN state), 1e308 overflowed S.
    lo = 1e-100 if definite else 0.0
    M = check_finite_array(name, M)  # checked before validate's symmetrising sum overflows
    d = np.diagonal(M, axis1=-2, axis2=-1) if M.ndim >= 2 else M
    # a negative or zero variance is left to the definiteness check, which names it better
    if np.any((d > 1e100) | ((d > 0) & (d < lo))):
        raise ValueError(f"{name} must have variances (diagonal) in [{lo:g}, 1e+100], got "
                         f"{d.min():.3g} to {d.max():.3g}")
    return M


def _bounded(name, v):
    """``v`` with every entry in [-1e100, 1e100] (squared over a variance from 1e-100)."""
    if not np.all(np.abs(v) <= 1e100):
        raise ValueError(f"{name} must have entries in [-1e+100, 1e+100], got "
                         f"{np.abs(v).max():.3g} in magnitude")
    return v


def _call(f, x):
    return f(x) if callable(f) else f


def _checked_state(x, P, witness=None):
    """``x`` (n,) and ``P`` (n, n) symmetric positive semi-definite, or ValueError.

    When each is well formed but their sizes differ, ``x`` is named (its length is the odd
    one out against the square ``P``) unless ``witness``, the size of a third square matrix
    (``Q``), agrees with ``x``: then ``P`` is.
    """
    x = _bounded("x", _nonempty("x", check_vector("x", x), "state"))
    Pa = check_finite_array("P", P)
    if Pa.ndim == 2 and Pa.shape[0] == Pa.shape[1] != x.size and witness != x.size:
        raise ValueError(f"x must have length {Pa.shape[0]} (the size of P), got length {x.size}")
    return x, check_covariance("P", _scaled("P", P), x.size)


def _size(M, square=True):
    """The size of a square matrix (the columns of a matrix if not ``square``), else None: a
    witness for :func:`_checked_state`."""
    shape = np.shape(M) if isinstance(M, np.ndarray | list | tuple) else ()
    return shape[1] if len(shape) == 2 and (shape[0] == shape[1] or not square) else None


def _odd_length(m_z, m_model, model, R):
    """A measurement length the model (``H``'s rows, ``h(x)``) and ``R`` agree on but ``z``
    does not: name ``z`` (the model or ``R`` is named by its own shape check when it is the
    odd one out)."""
    if m_z != m_model:
        R = np.asarray(R)
        m_r = R.shape[0] if R.ndim == 2 and R.shape[0] == R.shape[1] else (1 if R.size == 1
                                                                             else None)
        if m_r != m_z:
            raise ValueError(f"z must have length {m_model} ({model}), got length {m_z}")


def _nonempty(name, v, what):
    """A vector with at least one entry (an empty state or measurement is no filter step)."""
    if v.shape[-1:] == (0,):
        raise ValueError(f"{name} must hold at least one {what} component, got shape {v.shape}")
    return v


def _checked_model(name, value, shape):
    """A model output (``f(x)``, ``h(x)``, ``F``, ``H``) finite and of ``shape``, or ValueError."""
    arr = check_finite_array(name, value)
    if arr.ndim != len(shape) or any(k is not None and k != a for k, a in zip(shape, arr.shape,
                                                                           strict=True)):
        want = "(" + ", ".join("m" if k is None else str(k) for k in shape) + \
            ("," if len(shape) == 1 else "") + ")"
        raise ValueError(f"{name} must have shape {want}, got shape {arr.shape}")
    return arr


def ekf_predict(x, P, f, F, Q, check=True):
    """EKF time update.

    Parameters
    ----------
    x : array_like, shape (n,)
        State at the previous epoch, entries in [-1e100, 1e100].
    P : array_like, shape (n, n)
        Its covariance, variances in [0, 1e100].
    f : callable or array_like
        ``f(x) -> x-`` (the propagated state), or the propagated state itself.
    F : callable or array_like, shape (n, n)
        State-transition matrix ``d f / d x`` at ``x`` (or a callable of ``x``), entries in
        [-1e100, 1e100].
    Q : array_like, shape (n, n)
        Process-noise covariance over the step, variances in [0, 1e100].
    check : bool
        Check the inputs and the model's outputs (see the module docstring).

    Returns
    -------
    x : ndarray, shape (n,)
    P : ndarray, shape (n, n)

    Examples
    --------
    >>> x, P = ekf_predict(np.zeros(2), np.eye(2), np.ones(2), np.eye(2), np.eye(2))
    >>> x.tolist(), P.tolist()
    ([1.0, 1.0], [[2.0, 0.0], [0.0, 2.0]])
    >>> ekf_predict(np.zeros(2), -np.eye(2), np.ones(2), np.eye(2), np.eye(2))
    Traceback (most recent call last):
    ...
    ValueError: P must be positive semi-definite, got smallest eigenvalue -1
    """
    check = check_bool("check", check)
    if check:
        x, P = _checked_state(x, P, _size(Q))
        Q = check_covariance("Q", _scaled("Q", Q), x.size)
        Phi = _bounded("F", _checked_model("F", _call(F, x), (x.size, x.size)))
        x_new = _checked_model("f(x)", _call(f, x), (x.size,))
    else:
        x = np.asarray(x, dtype=float)
        P = np.asarray(P, dtype=float)
        Phi = np.asarray(_call(F, x), dtype=float)
        x_new = np.asarray(_call(f, x), dtype=float)
    P_new = Phi @ P @ Phi.T + np.asarray(Q, dtype=float)  # P = F P F^T + Q
    return x_new, _sym(P_new)


def joseph(P, K, H, R):
    """Joseph-form covariance update ``(I - K H) P (I - K H)^T + K R K^T``.

    ``P`` (n, n) and ``R`` (m, m) must be symmetric positive semi-definite (ValueError naming
    the one that is not); ``R = 0`` is allowed (a noise carried in an augmented state, as the
    TDUKF's exact form does); ``K`` is (n, m) and ``H`` (m, n).

    Examples
    --------
    >>> joseph(np.eye(1) * 4.0, np.array([[0.8]]), np.eye(1), np.eye(1)).tolist()
    [[0.8]]
    """
    P = check_covariance("P", P)
    R = check_covariance("R", R)  # an indefinite R gave a singular "covariance"
    n, m = P.shape[0], R.shape[0]
    K = _checked_model("K", K, (n, m))
    H = _checked_model("H", H, (m, n))
    return _joseph(P, K, H, R)


def _joseph(P, K, H, R):
    A = np.eye(P.shape[0]) - K @ H
    return _sym(A @ P @ A.T + K @ R @ K.T)  # P = (I-KH) P (I-KH)^T + K R K^T


def ekf_update(x, P, z, h, H, R, residual=None, check=True):
    """EKF measurement update (Joseph form); ``z=None`` skips it.

    Parameters
    ----------
    x : array_like, shape (n,)
        Prior state, entries in [-1e100, 1e100].
    P : array_like, shape (n, n)
        Prior covariance, variances in [0, 1e100].
    z : array_like, shape (m,) or None
        Measurement, entries in [-1e100, 1e100]; ``None`` skips the update (time update
        only): then ``h``, ``H`` and ``R`` may all be None (no model is needed), and are
        otherwise checked as for an update, so that a wrong model is not hidden by a skip.
    h : callable or array_like
        ``h(x) -> z_pred``, or the predicted measurement itself.
    H : callable or array_like, shape (m, n)
        Measurement Jacobian at ``x`` (or a callable of ``x``), entries in [-1e100, 1e100].
    R : array_like, shape (m, m)
        Measurement-noise covariance, positive definite, variances in [1e-100, 1e100].
    residual : callable, optional
        ``residual(z, z_pred) -> innovation`` (default ``z - z_pred``).
    check : bool
        Check the inputs and the model's outputs (see the module docstring).

    Returns
    -------
    Update
        ``x``, ``P``, ``innovation``, ``S``, ``nis``. A skipped update has ``innovation`` and
        ``S`` None and ``nis`` NaN: no test was made, and NaN is the one value an average of
        NIS values (``np.nanmean``) drops instead of counting (0 would be a perfect NIS).

    Examples
    --------
    >>> up = ekf_update(np.zeros(1), np.eye(1), None, np.zeros(1), np.eye(1), np.eye(1))
    >>> up.x.tolist(), up.innovation, bool(np.isnan(up.nis))
    ([0.0], None, True)
    >>> ekf_update(np.zeros(1), np.eye(1), [np.nan], np.zeros(1), np.eye(1), np.eye(1))
    Traceback (most recent call last):
    ...
    ValueError: z must contain only finite numbers (no NaN or inf)
    """
    check = check_bool("check", check)
    if check:
        x, P = _checked_state(x, P, _size(H, square=False))
    else:
        x = np.asarray(x, dtype=float)
        P = np.asarray(P, dtype=float)
    if z is None and (not check or (h is None and H is None and R is None)):
        return Update(x, P, None, None, float("nan"))
    if check:
        if z is not None:
            z = _bounded("z", _nonempty("z", check_vector("z", z), "measurement"))
        _check_residual(residual, "residual(z, z_pred) -> innovation (None: z - z_pred)")
        Hm = _checked_model("H", np.atleast_2d(_call(H, x)), (None, x.size))
        m = Hm.shape[0] if z is None else z.size
        if z is not None:
            _odd_length(m, Hm.shape[0], "the rows of H", R)
        Hm = _bounded("H", _checked_model("H", Hm, (m, x.size)))
        z_pred = _checked_model("h(x)", _call(h, x), (m,))
        R = check_covariance("R", _scaled("R", np.atleast_2d(R), True), m, definite=True)
        if z is None:   # the model given with a skipped update is checked, not used
            return Update(x, P, None, None, float("nan"))
    else:
        z = np.asarray(z, dtype=float)
        z_pred = np.asarray(_call(h, x), dtype=float)
        Hm = np.atleast_2d(np.asarray(_call(H, x), dtype=float))
        R = np.atleast_2d(np.asarray(R, dtype=float))
    nu = residual(z, z_pred) if residual is not None else z - z_pred
    if check and residual is not None:
        nu = _checked_model("residual(z, h(x))", nu, (z.size,))
    S = _sym(Hm @ P @ Hm.T + R)  # S = H P H^T + R
    PHt = P @ Hm.T
    K = np.linalg.solve(S, PHt.T).T  # K = P H^T S^-1
    x_new = x + K @ nu  # x+ = x- + K (z - h(x-))
    P_new = _joseph(P, K, Hm, R)
    return Update(x_new, P_new, nu, S, float(nu @ np.linalg.solve(S, nu)))


# --------------------------------------------------------------------------- UKF


#: The range of the UKF's ``beta`` (:func:`ukf_weights`).
_BETA_RANGE = (-1e3, 1e3)


def ukf_weights(n, alpha=1.0, beta=2.0, kappa=0.0):
    """Weights of the scaled unscented transform.

    ``lambda = alpha^2 (n + kappa) - n``; ``Wm0 = lambda / (n + lambda)``,
    ``Wc0 = Wm0 + 1 - alpha^2 + beta``, ``Wm_i = Wc_i = 1 / (2 (n + lambda))``.

    Parameters
    ----------
    n : int
        State dimension.
    alpha : float
        Spread of the sigma points (``0 < alpha <= 1``; 1e-3 is Wan and van der Merwe's
        small-spread choice, 1 keeps all weights positive when ``kappa = 0``).
    beta : float
        Prior-knowledge term (2 is optimal for Gaussians), in [-1e3, 1e3]. A central
        covariance weight ``Wc0 < 0`` (``beta < alpha^2 - 1 - Wm0``; also the small-spread
        alpha's) makes a transformed covariance a difference: :func:`ukf_predict`,
        :func:`ukf_update` and :func:`unscented_transform` refuse one that comes out
        indefinite, naming ``beta`` (``Wc`` for the last).
    kappa : float
        Secondary scaling, in (-n, 1e5]; ``alpha^2 (n + kappa) >= 1e-150`` is required (the
        weights are ``1 / (n + lambda)``).

    Returns
    -------
    Wm, Wc : ndarray, shape (2n+1,)
        Mean and covariance weights.
    lam : float
        ``lambda``.

    Examples
    --------
    >>> Wm, Wc, lam = ukf_weights(2)
    >>> Wm.tolist(), lam
    ([0.0, 0.25, 0.25, 0.25, 0.25], 0.0)
    """
    n = check_int("n", n, 1, 10**4)
    alpha = check_real("alpha", alpha, 0.0, 1.0, lo_open=True)
    beta = check_real("beta", beta, *_BETA_RANGE)
    kappa = check_real("kappa", kappa, -n, 1e5, lo_open=True)
    lam = alpha**2 * (n + kappa) - n
    if not alpha**2 * (n + kappa) >= 1e-150:  # the weights 1 / (n + lam) would be inf
        raise ValueError(f"alpha and kappa must keep n + lambda = alpha^2 (n + kappa) >= 1e-150 "
                         f"(finite weights), got alpha = {alpha:g}, kappa = {kappa:g}")
    Wm = np.full(2 * n + 1, 1.0 / (2.0 * (n + lam)))
    Wc = Wm.copy()
    Wm[0] = lam / (n + lam)
    Wc[0] = Wm[0] + 1.0 - alpha**2 + beta
    return Wm, Wc, lam


def sigma_points(x, P, lam):
    """The ``2n + 1`` sigma points ``x, x +/- columns of sqrt((n + lambda) P)``.

    The matrix square root is the lower Cholesky factor. ``P`` must be symmetric (to 1e-8 of
    its largest entry, as every filter's covariance) and positive definite.

    Returns
    -------
    ndarray, shape (2n+1, n)

    Examples
    --------
    >>> sigma_points(np.zeros(1), np.eye(1) * 4.0, 0.0).ravel().tolist()
    [0.0, 2.0, -2.0]
    """
    x = _nonempty("x", check_vector("x", x), "state")
    n = x.size
    Pa = check_finite_array("P", P)
    if Pa.ndim == 2 and Pa.shape[0] == Pa.shape[1] != n:   # x the odd one out
        raise ValueError(f"x must have length {Pa.shape[0]} (the size of P), got length {n}")
    P = _square("P", P, n)
    check_symmetric("P", P)  # else the Cholesky factor would read only its lower triangle
    lam = check_real("lam", lam, -n, 1e6, lo_open=True)  # (n + lam) P stays finite
    try:
        L = np.linalg.cholesky((n + lam) * _sym(P))
    except np.linalg.LinAlgError:  # name what is wrong with P: indefinite or singular
        check_definite("P", P, n)
        raise ValueError("P must be positive definite (its Cholesky factor failed)") from None
    return np.vstack([x, x + L.T, x - L.T])


def unscented_transform(Y, Wm, Wc, noise=None, residual=None):
    """Mean and covariance of transformed sigma points ``Y`` (2n+1, m).

    Deviations are taken from the central point first, so that a large negative
    ``Wm0`` (small ``alpha``) does not cancel digits of a large mean.

    Examples
    --------
    >>> Wm, Wc, lam = ukf_weights(1)
    >>> m, S = unscented_transform(np.array([[0.0], [2.0], [-2.0]]), Wm, Wc)
    >>> m.tolist(), S.tolist()
    ([0.0], [[4.0]])

    Weights ``Wm`` that do not sum to 1 (the mean's weights) and a ``noise`` that is no
    covariance (indefinite, asymmetric) are refused: the result would be no mean or no
    covariance.
    """
    _check_residual(residual, "residual(a, b) of the rows of Y (None: a - b)")
    mean, cov = _transform(Y, Wm, Wc, noise, residual, check=True)
    total = float(np.sum(Wm))
    if not abs(total - 1.0) <= 1e-8 * max(1.0, float(np.sum(np.abs(Wm)))):
        raise ValueError(f"Wm must sum to 1 (the weights of a mean), got sum {total:.6g}")
    if noise is not None:
        check_covariance("noise", noise, cov.shape[0])
    _check_weighted(cov, Wc, "covariance", None, None, None)
    return mean, cov


def _check_residual(residual, what):
    """``residual`` None or a function (else one ValueError naming it)."""
    if residual is not None:
        check_callable("residual", residual, f"a function {what}")


def _check_weighted(cov, Wc, what, alpha, beta, kappa, definite=False):
    """A negative covariance weight ``Wc[0]`` (``Wm0 + 1 - alpha^2 + beta < 0``) makes the
    transformed covariance a difference, which may be indefinite: refuse such a ``cov``,
    naming ``beta`` (``Wc`` when the weights were given, ``alpha`` None). Nothing to check,
    and no cost, when ``Wc[0] >= 0``: every term is then positive semi-definite."""
    if not Wc[0] < 0.0:
        return
    try:
        check_covariance("cov", cov, definite=definite)
        return
    except ValueError:
        low = float(np.linalg.eigvalsh(cov)[0]) if np.all(np.isfinite(cov)) else float("nan")
    kind = "positive definite" if definite else "positive semi-definite"
    why = f"the {what} is not {kind} (smallest eigenvalue {low:.3g})"
    if alpha is None:
        raise ValueError(f"Wc[0] must be >= 0 here (a negative central weight made the "
                         f"covariance a difference), got {Wc[0]:.4g}: {why}")
    beta = float(beta)
    need = beta - float(Wc[0])  # Wc0 >= 0 from this beta on: alpha^2 - 1 - Wm0
    fix = (f"use beta >= {need:.4g}" if need <= _BETA_RANGE[1] else
           f"that needs beta >= {need:.3g}, beyond its range: raise alpha (1 with kappa = 0 "
           f"gives Wc0 = beta)")
    raise ValueError(f"beta must keep the central covariance weight Wc0 = Wm0 + 1 - alpha^2 + "
                     f"beta >= 0 here (alpha = {float(alpha):g}, kappa = {float(kappa):g}, beta = "
                     f"{beta:g}: Wc0 = {Wc[0]:.4g}): {why}; {fix}")


def _transform(Y, Wm, Wc, noise=None, residual=None, check=False):
    """:func:`unscented_transform` for the UKF's own calls (its noise already checked); with
    ``check``, a ``residual``'s outputs are checked for shape."""
    Y = check_finite_array("Y", Y)
    if Y.ndim != 2 or Y.shape[0] % 2 != 1 or Y.shape[1] == 0:
        raise ValueError(f"Y must have shape (2n+1, m) with m >= 1, got shape {Y.shape}")
    Wm = check_vector("Wm", Wm, Y.shape[0])
    Wc = check_vector("Wc", Wc, Y.shape[0])
    res = residual if residual is not None else (lambda a, b: a - b)
    D0 = res(Y, Y[0])
    if check and residual is not None:
        D0 = _checked_model("residual(a, b)", D0, Y.shape)
    mean = Y[0] + Wm @ D0
    D = res(Y, mean)
    if check and residual is not None:
        D = _checked_model("residual(a, b)", D, Y.shape)
    cov = (Wc[:, None] * D).T @ D
    if noise is not None:
        cov = cov + _square("noise", noise, Y.shape[1])
    return mean, _sym(cov)


def ukf_predict(x, P, f, Q, alpha=1.0, beta=2.0, kappa=0.0, check=True):
    """UKF time update: propagate the sigma points through ``f``.

    Parameters
    ----------
    f : callable
        ``f(x) -> x-`` for one state of shape (n,).
    check : bool
        Check the inputs and the model's outputs (see the module docstring).

    Returns
    -------
    x : ndarray, shape (n,)
    P : ndarray, shape (n, n)

    Examples
    --------
    >>> x, P = ukf_predict(np.zeros(2), np.eye(2), lambda s: 2 * s, np.zeros((2, 2)))
    >>> np.round(P, 12).tolist()
    [[4.0, 0.0], [0.0, 4.0]]
    """
    check = check_bool("check", check)
    if check:
        x, P = _checked_state(x, P, _size(Q))
        f = check_callable("f", f, "a function f(x) -> x- of one state")
        Q = check_covariance("Q", _scaled("Q", Q), x.size)
    x = np.asarray(x, dtype=float)
    Wm, Wc, lam = ukf_weights(x.size, alpha, beta, kappa)
    X = sigma_points(x, P, lam)
    Y = np.array([f(s) for s in X])
    if check:
        Y = _checked_model("f(x) of the sigma points", Y, X.shape)
    x_new, P_new = _transform(Y, Wm, Wc, noise=np.asarray(Q, dtype=float))
    if check:
        _check_weighted(P_new, Wc, "predicted covariance P", alpha, beta, kappa)
    return x_new, P_new


def ukf_update(x, P, z, h, R, alpha=1.0, beta=2.0, kappa=0.0, residual=None, check=True):
    """UKF measurement update; ``z=None`` skips it.

    Parameters
    ----------
    z : array_like, shape (m,) or None
        Measurement; ``None`` skips the update: then ``h`` and ``R`` may both be None, and are
        otherwise checked (``h`` a function, ``R`` a covariance of the length of ``h(x)``).
    h : callable
        ``h(x) -> z_pred`` for one state.
    residual : callable, optional
        ``residual(a, b)`` for measurement differences (default ``a - b``).
    check : bool
        Check the inputs and the model's outputs (see the module docstring).

    Returns
    -------
    Update

    Examples
    --------
    >>> up = ukf_update(np.zeros(1), np.eye(1), np.array([1.0]), lambda s: s, np.eye(1))
    >>> round(float(up.x[0]), 6), round(float(up.P[0, 0]), 6)
    (0.5, 0.5)
    """
    check = check_bool("check", check)
    if check:
        x, P = _checked_state(x, P)
    else:
        x = np.asarray(x, dtype=float)
        P = np.asarray(P, dtype=float)
    if z is None and (not check or (h is None and R is None)):
        return Update(x, P, None, None, float("nan"))
    if check:
        if z is not None:
            z = _bounded("z", _nonempty("z", check_vector("z", z), "measurement"))
        h = check_callable("h", h, "a function h(x) -> z_pred of one state")
        _check_residual(residual, "residual(a, b) of measurements (None: a - b)")
    Wm, Wc, lam = ukf_weights(x.size, alpha, beta, kappa)
    X = sigma_points(x, P, lam)
    Z = np.array([np.atleast_1d(h(s)) for s in X])
    if check:
        Z = _checked_model("h(x) of the sigma points", Z, (X.shape[0], None))
        m = Z.shape[1] if z is None else z.size
        if z is not None:
            _odd_length(m, Z.shape[1], "the length of h(x)", R)
        Z = _checked_model("h(x) of the sigma points", Z, (X.shape[0], m))
        R = check_covariance("R", _scaled("R", np.atleast_2d(R), True), m, definite=True)
        if z is None:   # the model given with a skipped update is checked, not used
            return Update(x, P, None, None, float("nan"))
    z = np.asarray(z, dtype=float)
    z_pred, S = _transform(Z, Wm, Wc, noise=np.atleast_2d(R), residual=residual, check=check)
    if check:
        _check_weighted(S, Wc, "innovation covariance S", alpha, beta, kappa, definite=True)
    res = residual if residual is not None else (lambda a, b: a - b)
    dZ = res(Z, z_pred)
    nu = res(z, z_pred)
    if check and residual is not None:
        dZ = _checked_model("residual(h(x), z_pred) of the sigma points", dZ, Z.shape)
        nu = _checked_model("residual(z, z_pred)", nu, z.shape)
    Pxz = (Wc[:, None] * (X - x)).T @ dZ
    K = np.linalg.solve(S, Pxz.T).T  # K = Pxz S^-1
    x_new = x + K @ nu
    P_new = _sym(P - K @ S @ K.T)  # P = P - K S K^T
    if check:
        _check_weighted(P_new, Wc, "updated covariance P", alpha, beta, kappa)
    return Update(x_new, P_new, nu, S, float(nu @ np.linalg.solve(S, nu)))


# -------------------------------------------------------------------- consistency


def nees(err, P):
    """Normalised estimation error squared ``e^T P^-1 e``; vectorised over leading axes.

    Parameters
    ----------
    err : array_like, shape (..., n)
        Estimate minus truth, entries in [-1e100, 1e100].
    P : array_like, shape (..., n, n)
        Covariance, positive definite, variances in [1e-100, 1e100] (so that ``e^2 / var``
        stays inside the float range).

    Raises
    ------
    ValueError
        Naming ``err`` or ``P``: a complex or non-finite entry, shapes that do not match, or
        a ``P`` that is not symmetric positive definite (indefinite or singular: the
        statistic would be negative or undefined).

    Examples
    --------
    >>> float(nees([1.0, 2.0], np.diag([1.0, 4.0])))
    2.0
    """
    return _normalised_square("err", err, "P", P)


def nis(nu, S):
    """Normalised innovation squared ``nu^T S^-1 nu`` (same form as :func:`nees`).

    Examples
    --------
    >>> float(nis([3.0], [[9.0]]))
    1.0
    """
    return _normalised_square("nu", nu, "S", S)


def _normalised_square(ename, err, pname, P):
    err = check_finite_array(ename, err)
    if err.ndim == 0:
        raise ValueError(f"{ename} must be a vector (shape (..., n)), got a scalar")
    if err.shape[-1] == 0:  # an empty sum is 0, a "perfect" statistic of nothing
        raise ValueError(f"{ename} must hold at least one component (shape (..., n), n >= 1), "
                         f"got shape {err.shape}")
    err = _bounded(ename, err)
    Pa = check_finite_array(pname, P)
    if Pa.ndim >= 2 and Pa.shape[-1] == Pa.shape[-2] != err.shape[-1]:   # err the odd one out
        raise ValueError(f"{ename} must have {Pa.shape[-1]} components (the size of {pname}), got "
                         f"shape {err.shape}")
    P = check_definite(pname, _scaled(pname, P, True), err.shape[-1])
    try:
        np.broadcast_shapes(err.shape[:-1], P.shape[:-2])
    except ValueError:
        raise ValueError(f"{ename} of shape {err.shape} and {pname} of shape {P.shape} do not "
                         f"match (leading axes)") from None
    sol = np.linalg.solve(P, err[..., None])[..., 0]
    return np.sum(err * sol, axis=-1)  # e^T P^-1 e


def chi2_bounds(dof, n_runs=1, p=0.95):
    """Two-sided ``p`` bounds of the average of ``n_runs`` independent chi-square(dof) values.

    ``n_runs * average`` is chi-square with ``n_runs * dof`` degrees of freedom, so the
    bounds are ``chi2.ppf((1 -/+ p) / 2, n_runs dof) / n_runs``.

    Parameters
    ----------
    dof : float
        Degrees of freedom of each value, in [1, 1e12]
        (:data:`xnavlab.core.distributions.DOF_RANGE`: a NEES or NIS sums at least one term).
    n_runs : float
        Values averaged, in [1, 1e12] (a Monte Carlo of more runs than a machine makes in a
        year), with ``n_runs * dof`` at most 1e12 (the pooled law's degrees of freedom).
    p : float
        Probability inside the bounds, in (0, 1).

    Returns
    -------
    lo, hi : float

    Examples
    --------
    >>> lo, hi = chi2_bounds(6, 50)
    >>> round(lo, 2), round(hi, 2)
    (5.08, 7.0)
    """
    dof = check_real("dof", dof, *DOF_RANGE)
    n_runs = check_real("n_runs", n_runs, 1.0, 1e12)
    k = dof * n_runs
    if k > DOF_RANGE[1]:   # the pooled law's degrees of freedom, as chi2_ppf takes them
        raise ValueError(f"n_runs must be at most {DOF_RANGE[1] / dof:g} with dof = {dof:g} (the "
                         f"pooled n_runs * dof degrees of freedom at most {DOF_RANGE[1]:g}), got {n_runs:g}")
    p = check_real("p", p, 0.0, 1.0, lo_open=True, hi_open=True)
    return chi2_ppf((1 - p) / 2, k) / n_runs, chi2_ppf((1 + p) / 2, k) / n_runs


#: The words of :func:`consistency_verdict`.
CONSISTENCY_VERDICTS = ("inside", "conservative", "optimistic")


def consistency_verdict(value, lo, hi):
    """Judge an averaged NEES or NIS against its chi-square band.

    ``"inside"`` when ``lo <= value <= hi``; ``"conservative"`` below the band (the filter's
    covariance is larger than its errors: it trusts its estimate less than it could);
    ``"optimistic"`` above it (the covariance is smaller than the errors: the dangerous
    side, where a filter ignores measurements it needs).

    ``value``, ``lo`` and ``hi`` are NEES/NIS values and chi-square quantiles, so each must be
    a real number >= 0 (a negative one is refused, not judged "conservative").

    Examples
    --------
    >>> lo, hi = chi2_bounds(6, 400)
    >>> consistency_verdict(4.99, lo, hi), consistency_verdict(6.0, lo, hi)
    ('conservative', 'inside')
    """
    value, lo, hi = (check_real(n, v, 0.0) for n, v in (("value", value), ("lo", lo), ("hi", hi)))
    if lo > hi:
        raise ValueError(f"hi must be at least lo = {lo:g} (the band's lower end), got {hi:g}")
    return "inside" if lo <= value <= hi else ("conservative" if value < lo else "optimistic")


def judge_series(values, lo, hi, inside_min=0.9):
    """Judge a series of averaged NEES (or NIS) values, one per epoch, against their band.

    Each epoch's value falls inside the 95 % band with probability 0.95 when the filter is
    consistent; the series is ``"inside"`` when at least ``inside_min`` of its epochs are,
    and otherwise ``"conservative"`` or ``"optimistic"`` after the side that holds more of
    the others (:func:`consistency_verdict`'s words). Every value must be finite and >= 0
    (a NEES or NIS is a quadratic form); a negative one is refused, naming ``values[i]``.

    Returns
    -------
    dict
        ``verdict``, ``inside``, ``below``, ``above`` (fractions of the epochs).

    Examples
    --------
    >>> judge_series([6.0, 5.9, 6.1, 2.0], 5.0, 7.0)["verdict"], judge_series([6.0] * 9, 5, 7)["inside"]
    ('conservative', 1.0)
    """
    v = check_finite_array("values", values).ravel()
    if v.size == 0:
        raise ValueError("values must hold at least one number")
    if np.any(v < 0):
        i = int(np.argmax(v < 0))
        raise ValueError(f"values[{i}] must be a NEES or NIS value in [0, inf), got {v[i]:g}")
    consistency_verdict(float(v[0]), lo, hi)  # checks lo, hi
    inside_min = check_real("inside_min", inside_min, 0.0, 1.0)
    below, above = float(np.mean(v < lo)), float(np.mean(v > hi))
    inside = 1.0 - below - above
    verdict = ("inside" if inside >= inside_min else
               "conservative" if below >= above else "optimistic")
    return {"verdict": verdict, "inside": inside, "below": below, "above": above}


# ------------------------------------------------------------------------ classes


class EKF:
    """A thin holder of ``x`` and ``P`` around :func:`ekf_predict` and :func:`ekf_update`.

    Parameters
    ----------
    x0 : array_like, shape (n,)
        Initial state.
    P0 : array_like, shape (n, n)
        Initial covariance.

    Attributes
    ----------
    x, P : ndarray
        Current estimate.
    last : Update or None
        Result of the last measurement update.

    Examples
    --------
    >>> kf = EKF([0.0], [[1.0]])
    >>> kf.predict(lambda s: s, np.eye(1), [[1.0]]).update(None, None, None, None)
    EKF(x=[0.], P diag=[2.])
    >>> _ = kf.update([2.0], lambda s: s, np.eye(1), [[2.0]])
    >>> kf.x.tolist()
    [1.0]
    """

    def __init__(self, x0, P0):
        self.x = _nonempty("x0", check_vector("x0", x0), "state").astype(float).copy()
        self.P = _sym(check_covariance("P0", P0, self.x.size))
        self.last = None

    def predict(self, f, F, Q):
        """Time update (see :func:`ekf_predict`); returns ``self``."""
        self.x, self.P = ekf_predict(self.x, self.P, f, F, Q)
        return self

    def update(self, z, h, H, R, residual=None):
        """Measurement update (see :func:`ekf_update`); ``z=None`` skips it. Returns ``self``."""
        up = ekf_update(self.x, self.P, z, h, H, R, residual)
        self.x, self.P, self.last = up.x, up.P, up
        return self

    def __repr__(self):
        return f"{type(self).__name__}(x={np.array2string(self.x)}, P diag={np.diag(self.P)})"


class UKF(EKF):
    """A thin holder around :func:`ukf_predict` and :func:`ukf_update`.

    Examples
    --------
    >>> kf = UKF([0.0], [[1.0]])
    >>> _ = kf.predict(lambda s: s, [[1.0]]).update([2.0], lambda s: s, [[2.0]])
    >>> np.round(kf.x, 12).tolist()
    [1.0]
    """

    def __init__(self, x0, P0, alpha=1.0, beta=2.0, kappa=0.0):
        super().__init__(x0, P0)
        ukf_weights(self.x.size, alpha, beta, kappa)  # validates
        self.alpha, self.beta, self.kappa = float(alpha), float(beta), float(kappa)  # np.float16

    def predict(self, f, Q):
        """Time update (see :func:`ukf_predict`); returns ``self``."""
        self.x, self.P = ukf_predict(self.x, self.P, f, Q, self.alpha, self.beta, self.kappa)
        return self

    def update(self, z, h, R, residual=None):
        """Measurement update (see :func:`ukf_update`); ``z=None`` skips it. Returns ``self``."""
        up = ukf_update(self.x, self.P, z, h, R, self.alpha, self.beta, self.kappa, residual)
        self.x, self.P, self.last = up.x, up.P, up
        return self
