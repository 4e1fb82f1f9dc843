"""The compiled filter's measurements: the three sensors' models and the local updates.

The main paper's sensors see the position only: XNAV's pulse delays (paper eqs. (1), (4)),
the UV sensor's range and direction to Mars (eq. (5)), the CNS's star-to-Mars angles with
correlated noise (eq. (6)); readable versions: :mod:`xnavlab.mars.models.sensors`. A local takes
its measurement by the Joseph-form EKF update (:func:`update`) or, in reset mode, by the
information it adds (:func:`update_information`; why both agree:
:mod:`xnavlab.mars.kernel.kernel_fusion`); both give the NIS the gate and the detectors test.

Examples
--------
>>> KIND_XNAV, KIND_UV, KIND_CNS
(0, 1, 2)
"""

from __future__ import annotations

import math

import numpy as np

from xnavlab.core.constants import GM_SUN, C
from xnavlab.mars.kernel.kernel_compile import HELPER, INLINE, jit
from xnavlab.mars.kernel.kernel_linalg import backward, cholesky, forward

__all__ = ["KIND_XNAV", "KIND_UV", "KIND_CNS", "measure", "innovation_cov", "update",
           "update_information"]

KIND_XNAV = 0  #: Subsystem code of the XNAV filter in the kernels' integer arrays.
KIND_UV = 1    #: Subsystem code of the UV-sensor filter.
KIND_CNS = 2   #: Subsystem code of the CNS filter.

_SHAPIRO = 2.0 * GM_SUN / C**3


@jit(**INLINE)
def _h_xnav(x, jm, se, me):
    """Paper eq. (1) delays, eq. (4) rows (position columns) and the diagonal R of XNAV
    measurement ``jm``, for the spacecraft at rm + r; ``nu = z - h(x)`` (into ``me``)."""
    rm_x, rs_x, n_, dist, sig, z = se.rm_x, se.rs_x, se.n_x, se.d_x, se.sig_x, se.z_x
    nu, H, R = me.nu, me.H, me.R
    R0 = rm_x[jm, 0] + x[0]
    R1 = rm_x[jm, 1] + x[1]
    R2 = rm_x[jm, 2] + x[2]
    Rn = math.sqrt(R0 * R0 + R1 * R1 + R2 * R2)
    b0, b1, b2 = -rs_x[jm, 0], -rs_x[jm, 1], -rs_x[jm, 2]
    bn = math.sqrt(b0 * b0 + b1 * b1 + b2 * b2)
    Rv = (R0, R1, R2)
    m = n_.shape[0]
    for i in range(m):
        nr = n_[i, 0] * R0 + n_[i, 1] * R1 + n_[i, 2] * R2
        nb = n_[i, 0] * b0 + n_[i, 1] * b1 + n_[i, 2] * b2
        D = dist[i]
        u = nr + Rn
        w = nb + bn
        zp = (nr / C + (nr * nr - Rn * Rn) / (2.0 * C * D)
              + _SHAPIRO * math.log(abs(u / w + 1.0)))  # paper eq. (1)
        nu[i] = z[jm, i] - zp
        for j in range(3):
            H[i, j] = (n_[i, j] / C + (nr * n_[i, j] - Rv[j]) / (C * D)
                       + _SHAPIRO * (n_[i, j] + Rv[j] / Rn) / (u + w))  # paper eq. (4)
        for j in range(m):
            R[i, j] = 0.0
        R[i, i] = sig[i] * sig[i]


@jit(**INLINE)
def _h_uv(x, jm, se, me):
    """Paper eq. (5): ``[|r|, -r/|r|]``, its Jacobian and R of UV measurement ``jm``;
    ``nu = z - h(x)`` (into ``me``)."""
    z, sig_r, sig_u = se.z_u, se.sig_r, se.sig_u
    nu, H, R = me.nu, me.H, me.R
    x0, x1, x2 = x[0], x[1], x[2]
    rn = math.sqrt(x0 * x0 + x1 * x1 + x2 * x2)
    inv = 1.0 / rn
    r = (x0, x1, x2)
    nu[0] = z[jm, 0] - rn
    for j in range(3):
        e = r[j] * inv
        nu[1 + j] = z[jm, 1 + j] + e
        H[0, j] = e
    for i in range(3):
        for j in range(3):
            # d(-r/|r|)/dr = -(I - r r^T/|r|^2)/|r|
            H[1 + i, j] = -((1.0 if i == j else 0.0) - r[i] * r[j] * inv * inv) * inv
    for i in range(4):
        for j in range(4):
            R[i, j] = 0.0
    R[0, 0] = sig_r * sig_r
    for i in range(1, 4):
        R[i, i] = sig_u * sig_u


@jit(**INLINE)
def _h_cns(x, jm, se, me):
    """Paper eq. (6) angles, Jacobian rows a_j/|r| and the correlated R (scratch ``me.A``) of
    CNS measurement ``jm``; ``nu = z - h(x)`` (into ``me``)."""
    z, star, sig_s, sig_h = se.z_c, se.stars_c, se.sig_s, se.sig_h
    nu, H, R, A = me.nu, me.H, me.R, me.A
    k = star.shape[0]
    x0, x1, x2 = x[0], x[1], x[2]
    rn = math.sqrt(x0 * x0 + x1 * x1 + x2 * x2)
    inv = 1.0 / rn
    u0 = -x0 * inv
    u1 = -x1 * inv
    u2 = -x2 * inv
    for i in range(k):
        s0, s1, s2 = star[i, 0], star[i, 1], star[i, 2]
        us = u0 * s0 + u1 * s1 + u2 * s2
        c0 = u1 * s2 - u2 * s1
        c1 = u2 * s0 - u0 * s2
        c2 = u0 * s1 - u1 * s0
        nu[i] = z[jm, i] - math.atan2(math.sqrt(c0 * c0 + c1 * c1 + c2 * c2), us)  # eq. (6)
        a0 = s0 - us * u0
        a1 = s1 - us * u1
        a2 = s2 - us * u2
        tinv = 1.0 / math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
        A[i, 0] = a0 * tinv
        A[i, 1] = a1 * tinv
        A[i, 2] = a2 * tinv
        H[i, 0] = A[i, 0] * inv
        H[i, 1] = A[i, 1] * inv
        H[i, 2] = A[i, 2] * inv
    hh = sig_h * sig_h
    ss = sig_s * sig_s
    for i in range(k):
        for j in range(k):
            R[i, j] = hh * (A[i, 0] * A[j, 0] + A[i, 1] * A[j, 1] + A[i, 2] * A[j, 2])
        R[i, i] += ss


@jit(**INLINE)
def measure(kind, x, jm, se, me):
    """Innovation ``z - h(x)``, Jacobian (position columns) and R of one measurement.

    Parameters
    ----------
    kind : int
        :data:`KIND_XNAV`, :data:`KIND_UV` or :data:`KIND_CNS`.
    x : ndarray, shape (6,)
        The predicted state (m, m/s, Mars-centred J2000).
    jm : int
        The measurement's row in its series of ``se``.
    se : xnavlab.mars.kernel.kernel_inputs.Sensors
        The measurements and noise.
    me : xnavlab.mars.kernel.kernel_inputs.Measurement
        Written: ``nu``, ``H``, ``R`` in their first m rows.

    Returns
    -------
    int
        The measurement's size m.
    """
    if kind == KIND_UV:
        _h_uv(x, jm, se, me)
        return 4
    if kind == KIND_CNS:
        _h_cns(x, jm, se, me)
        return se.stars_c.shape[0]
    _h_xnav(x, jm, se, me)
    return se.n_x.shape[0]


@jit(**INLINE)
def innovation_cov(P, inv_s, me, m, up):
    """``up.PHt = P H^T * inv_s`` (6, m) and the lower triangle of ``up.S = H PHt + R``
    (``P`` (6, 6); ``H``, ``R`` of ``me``, size m, only ``H[:, :3]`` read: the velocity
    columns are zero)."""
    H, R, PHt, S = me.H, me.R, up.PHt, up.S
    for i in range(6):
        for j in range(m):
            PHt[i, j] = (P[i, 0] * H[j, 0] + P[i, 1] * H[j, 1] + P[i, 2] * H[j, 2]) * inv_s
    for i in range(m):
        for j in range(i + 1):
            S[i, j] = R[i, j] + H[i, 0] * PHt[0, j] + H[i, 1] * PHt[1, j] + H[i, 2] * PHt[2, j]


@jit(**INLINE)
def _nis(me, m, up):
    """NIS ``nu^T S^-1 nu = |L^-1 nu|^2`` (``up.L`` from :func:`cholesky` of S; scratch
    ``up.y``)."""
    nu, L, y = me.nu, up.L, up.y
    for i in range(m):
        y[i] = nu[i]
    forward(L, m, y)
    nis = 0.0
    for i in range(m):
        nis += y[i] * y[i]
    return nis


@jit(**INLINE)
def _update_m(st, i_, me, m, gate, do_update, up):
    """:func:`update` for a size m."""
    xs, Ps = st.xs, st.Ps
    nu, H, R = me.nu, me.H, me.R
    PHt, L, y, K, W, T = up.PHt, up.L, up.y, up.K, up.W, up.T
    innovation_cov(Ps[i_], 1.0, me, m, up)  # S = H P H^T + R
    nis = np.nan
    if cholesky(up.S, m, L):
        nis = _nis(me, m, up)
        if do_update and nis <= gate:
            # K = P H^T S^-1, row by row: S k_i = (P H^T)_i
            for i in range(6):
                for j in range(m):
                    y[j] = PHt[i, j]
                forward(L, m, y)
                backward(L, m, y)
                for j in range(m):
                    K[i, j] = y[j]
            # x+ = x- + K nu
            for i in range(6):
                s = 0.0
                for j in range(m):
                    s += K[i, j] * nu[j]
                xs[i_, i] += s
            # P+ = (I - K H) P (I - K H)^T + K R K^T  (Joseph form)
            for i in range(6):  # T = (I - K H) P = P - K (P H^T)^T
                for j in range(6):
                    s = Ps[i_, i, j]
                    for a in range(m):
                        s -= K[i, a] * PHt[j, a]
                    T[i, j] = s
            for i in range(6):  # W = K R - T H^T, so that P+ = T + W K^T
                for j in range(m):
                    s = -(T[i, 0] * H[j, 0] + T[i, 1] * H[j, 1] + T[i, 2] * H[j, 2])
                    for a in range(m):
                        s += K[i, a] * R[a, j]
                    W[i, j] = s
            for i in range(6):
                for j in range(i, 6):
                    s = T[i, j]
                    for a in range(m):
                        s += W[i, a] * K[j, a]
                    Ps[i_, i, j] = s
                    Ps[i_, j, i] = s
    return nis


@jit(**INLINE)
def update(st, i_, me, m, gate, do_update, up):
    """Joseph-form EKF update of local ``i_`` in place; its NIS (NaN if S is not PD).

    The update is applied only when ``do_update`` and NIS <= gate. The three sensors'
    Jacobians have zero velocity columns (paper eqs. (4)-(6)), so only ``H[:, :3]`` is used,
    and ``A = I - K H`` has identity velocity columns: the Joseph product ``A P A^T`` is
    formed as ``T = P - K (P H^T)^T``, ``T A^T = T - (T H^T) K^T``. Compiled for the common
    sizes m = 3 and 4 (unrolled) and, out of the loop's code, for any other.

    Parameters
    ----------
    st : xnavlab.mars.kernel.kernel_inputs.FilterState
        Local ``i_``'s ``xs[i_]``, ``Ps[i_]`` updated in place.
    i_, m : int
    me : xnavlab.mars.kernel.kernel_inputs.Measurement
        Its measurement at ``xs[i_]``, size m.
    gate : float
        The innovation gate's NIS threshold (inf: none).
    do_update : bool
        False: the NIS only (a switched-out subsystem).
    up : xnavlab.mars.kernel.kernel_inputs.UpdateScratch

    Returns
    -------
    float
    """
    if m == 4:
        return _update_m(st, i_, me, 4, gate, do_update, up)
    if m == 3:
        return _update_m(st, i_, me, 3, gate, do_update, up)
    return _update_any(st, i_, me, m, gate, do_update, up)


@jit(**HELPER)
def _update_any(st, i_, me, m, gate, do_update, up):
    """:func:`update` for any m (not inlined: compiled once, kept out of the loop's code)."""
    return _update_m(st, i_, me, m, gate, do_update, up)


@jit(**INLINE)
def _gain_information(me, m, up, fu):
    """``fu.J += H^T R^-1 H`` (3 x 3, lower triangle) and ``fu.bv += H^T R^-1 nu`` (3,) of the
    measurement ``me`` (scratch ``up.L``, ``up.y``)."""
    nu, H, R, L, y, J, b = me.nu, me.H, me.R, up.L, up.y, fu.J, fu.bv
    cholesky(R, m, L)  # R is positive definite by construction
    # with R = L L^T: H^T R^-1 H = (L^-1 H)^T (L^-1 H), H^T R^-1 nu = (L^-1 H)^T (L^-1 nu)
    for j in range(m):
        y[j] = nu[j]
    forward(L, m, y)
    for c in range(3):
        for j in range(m):
            s = H[j, c]
            for k in range(j):
                s -= L[j, k] * H[k, 3 + c]
            H[j, 3 + c] = s * L[j, j]  # column c of L^-1 H, kept in the unused columns 3..5
    for a in range(3):
        s = 0.0
        for j in range(m):
            s += H[j, 3 + a] * y[j]
        b[a] += s
        for c in range(a + 1):
            s = 0.0
            for j in range(m):
                s += H[j, 3 + a] * H[j, 3 + c]
            J[a, c] += s


@jit(**INLINE)
def _information_m(fu, i_, me, m, gate, do_update, up):
    """:func:`update_information` for a size m."""
    innovation_cov(fu.Pp, fu.inv_sh[i_], me, m, up)  # S = H P H^T / s + R
    nis = np.nan
    if cholesky(up.S, m, up.L):
        nis = _nis(me, m, up)
        if do_update and nis <= gate:
            _gain_information(me, m, up, fu)
    return nis


@jit(**INLINE)
def update_information(fu, i_, me, m, gate, do_update, up):
    """The reset mode's update of local ``i_`` in information form; its NIS.

    The local starts from the master's prediction ``(fu.xp, fu.Pp / s_i)``; when
    ``do_update`` and NIS <= gate, its information ``H^T R^-1 H`` and ``H^T R^-1 nu`` is
    added to ``fu.J`` and ``fu.bv`` (for :func:`xnavlab.mars.kernel.kernel_fusion.fuse_information`).

    Parameters
    ----------
    fu : xnavlab.mars.kernel.kernel_inputs.FusionScratch
        The master's prediction and ``1 / s_i`` read, ``J`` and ``bv`` added to.
    i_, me, m, gate, do_update, up
        As :func:`update` (``me`` at the master's prediction).

    Returns
    -------
    float
    """
    if m == 4:
        return _information_m(fu, i_, me, 4, gate, do_update, up)
    if m == 3:
        return _information_m(fu, i_, me, 3, gate, do_update, up)
    return _information_any(fu, i_, me, m, gate, do_update, up)


@jit(**HELPER)
def _information_any(fu, i_, me, m, gate, do_update, up):
    """:func:`update_information` for any m (not inlined)."""
    return _information_m(fu, i_, me, m, gate, do_update, up)
