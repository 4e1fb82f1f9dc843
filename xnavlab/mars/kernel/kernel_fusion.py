"""The compiled filter's master: the federated fusion, in two forms that agree.

Two forms of the same filter
----------------------------
At every epoch the locals and the master predict, the locals update with their
measurements (Joseph form) and the master fuses them (information form, :func:`fuse`). That
is what :func:`xnavlab.mars.kernel.kernels.run_epochs` does in no-reset mode and, in reset mode, at
every epoch whose local estimates are recorded. At the other reset-mode epochs it uses the
fact that makes the reset mode optimal (Carlson 1990): every local starts the epoch from the
master, ``x_i = x``, ``P_i = P / s_i`` (its share ``s_i``; the shares of the connected
locals sum to 1), so its update gives ``P_i+^-1 = s_i P^-1 + H_i^T R_i^-1 H_i`` (exact for
the Kalman gain, whatever the form of the covariance update) and the fusion is

.. math::

   P_f^{-1} = \\sum_i s_i P^{-1} + J, \\quad J = \\sum_j H_j^T R_j^{-1} H_j, \\quad
   x_f = x + P_f \\sum_j H_j^T R_j^{-1} \\nu_j

(i over the connected locals, j over those whose update passed the gate): the centralised
EKF, all measurements taken at the master's prediction. The three sensors see the
position only, so ``J`` is 3 x 3 and the matrix inversion lemma gives
``P_f = P~ - P~[:, :3] J (I + P~_rr J)^-1 P~[:3, :]`` with ``P~ = P / sum_i s_i``
(:func:`fuse_information`): one 3 x 3 inverse instead of four 6 x 6 ones, and no local
covariance update. The NIS of every local (gating, fault detection) is computed as before
from ``S_i = H_i P H_i^T / s_i + R_i``
(:func:`xnavlab.mars.kernel.kernel_measurements.update_information`). The two forms agree to
rounding; the tests check both against the numpy loop.

Examples
--------
>>> import numpy as np
>>> from xnavlab.mars.kernel import kernel_inputs as ki
>>> P = np.diag([4.0, 4.0, 4.0, 1.0, 1.0, 1.0])
>>> st = ki.FilterState(np.array([np.zeros(6), np.ones(6)]), np.array([P, P]), np.full(2, 0.5),
...                     np.empty(6), np.empty((6, 6)))
>>> e = np.empty
>>> fu = ki.FusionScratch(e(6), e((6, 6)), e(6), e((6, 6)), e((6, 6)), e(6), e((6, 6)),
...                       e((3, 3)), e(3), e((3, 3)), np.ones(2, dtype=bool), e(2))
>>> bool(fuse(st, fu)), st.xm[:2].round(12).tolist(), round(float(st.Pm[0, 0]), 12)
(True, [0.5, 0.5], 2.0)
"""

from __future__ import annotations

import math

from xnavlab.mars.kernel.kernel_compile import HELPER, jit
from xnavlab.mars.kernel.kernel_linalg import cholesky, inverse_from_cholesky

__all__ = ["fuse", "fuse_information"]


@jit(**HELPER)
def fuse(st, fu):
    """Information-form fusion of the locals into the master.

    ``P_f = (sum P_i^-1)^-1``, ``x_f = P_f sum P_i^-1 x_i`` over the locals with
    ``fu.use[i]``, computed on Jacobi-scaled covariances and on deviations from the first
    used estimate (for precision), as :func:`xnavlab.core.federated.fuse`.

    Parameters
    ----------
    st : xnavlab.mars.kernel.kernel_inputs.FilterState
        The locals ``xs``, ``Ps`` read; the master ``xm``, ``Pm`` written.
    fu : xnavlab.mars.kernel.kernel_inputs.FusionScratch
        ``use`` read; working arrays.

    Returns
    -------
    bool
        False if no estimate is used or a matrix is not positive definite.
    """
    xs, Ps, x_out, P_out = st.xs, st.Ps, st.xm, st.Pm
    use, d, Y, yv, C, Cf = fu.use, fu.d, fu.Y, fu.yv, fu.Ci, fu.Cf
    ns = xs.shape[0]
    ref = -1
    for i in range(ns - 1, -1, -1):
        if use[i]:
            ref = i
    ok = ref >= 0
    if ok:
        for j in range(6):
            d[j] = 1.0 / math.sqrt(Ps[ref, j, j])  # Jacobi scaling D^-1
        for a in range(6):
            yv[a] = 0.0
            for b in range(6):
                Y[a, b] = 0.0
    for i in range(ns):
        if not (ok and use[i]):
            continue
        for a in range(6):
            for b in range(a + 1):
                C[a, b] = Ps[i, a, b] * d[a] * d[b]
        ok = cholesky(C, 6, C)
        inverse_from_cholesky(C, Cf)  # Cf = scaled P_i^-1 (lower)
        for a in range(6):
            for b in range(a + 1):
                Y[a, b] += Cf[a, b]
        for a in range(6):
            for b in range(a + 1, 6):
                Cf[a, b] = Cf[b, a]
        # y += P_i^-1 (x_i - x_ref), scaled
        for a in range(6):
            s = 0.0
            for b in range(6):
                s += Cf[a, b] * (xs[i, b] - xs[ref, b]) * d[b]
            yv[a] += s
    if ok:
        ok = cholesky(Y, 6, Y)
        inverse_from_cholesky(Y, Cf)  # P_f = (sum P_i^-1)^-1, scaled
        for a in range(6):
            for b in range(a + 1, 6):
                Cf[a, b] = Cf[b, a]
        for a in range(6):
            s = 0.0
            for b in range(6):
                s += Cf[a, b] * yv[b]
            x_out[a] = xs[ref, a] + s / d[a]  # x_f = x_ref + P_f sum P_i^-1 (x_i - x_ref)
            for b in range(6):
                P_out[a, b] = Cf[a, b] / (d[a] * d[b])
    return ok


@jit(**HELPER)
def fuse_information(st, fu, ssum):
    """Reset-mode fusion from the information the locals gained (module docstring).

    ``P_f^-1 = ssum P^-1 + J`` and ``x_f = x + P_f b``, by the matrix inversion lemma
    ``P_f = P~ - P~[:, :3] J (I + P~_rr J)^-1 P~[:3, :]``, ``P~ = P / ssum``.

    Parameters
    ----------
    st : xnavlab.mars.kernel.kernel_inputs.FilterState
        The master ``xm``, ``Pm`` written.
    fu : xnavlab.mars.kernel.kernel_inputs.FusionScratch
        The master's prediction ``x = xp``, ``P = Pp``; ``J`` (3, 3, lower triangle) and
        ``b = bv`` (3,) from :func:`xnavlab.mars.kernel.kernel_measurements.update_information`;
        working arrays ``Ci`` (6, 6), ``G`` (3, 3).
    ssum : float
        The sum of the connected locals' shares.

    Returns
    -------
    bool
        False if ``det(I + P~_rr J)`` is not positive (rounding gone wrong).
    """
    x, P, J, b, x_out, P_out = fu.xp, fu.Pp, fu.J, fu.bv, st.xm, st.Pm
    Pt, G = fu.Ci, fu.G
    for a in range(3):
        for c in range(a + 1, 3):
            J[a, c] = J[c, a]
    f = 1.0 / ssum
    for a in range(6):
        for c in range(6):
            Pt[a, c] = P[a, c] * f
    # M = I + P~_rr J and its inverse (adjugate / determinant)
    m00 = 1.0 + Pt[0, 0] * J[0, 0] + Pt[0, 1] * J[1, 0] + Pt[0, 2] * J[2, 0]
    m01 = Pt[0, 0] * J[0, 1] + Pt[0, 1] * J[1, 1] + Pt[0, 2] * J[2, 1]
    m02 = Pt[0, 0] * J[0, 2] + Pt[0, 1] * J[1, 2] + Pt[0, 2] * J[2, 2]
    m10 = Pt[1, 0] * J[0, 0] + Pt[1, 1] * J[1, 0] + Pt[1, 2] * J[2, 0]
    m11 = 1.0 + Pt[1, 0] * J[0, 1] + Pt[1, 1] * J[1, 1] + Pt[1, 2] * J[2, 1]
    m12 = Pt[1, 0] * J[0, 2] + Pt[1, 1] * J[1, 2] + Pt[1, 2] * J[2, 2]
    m20 = Pt[2, 0] * J[0, 0] + Pt[2, 1] * J[1, 0] + Pt[2, 2] * J[2, 0]
    m21 = Pt[2, 0] * J[0, 1] + Pt[2, 1] * J[1, 1] + Pt[2, 2] * J[2, 1]
    m22 = 1.0 + Pt[2, 0] * J[0, 2] + Pt[2, 1] * J[1, 2] + Pt[2, 2] * J[2, 2]
    c00 = m11 * m22 - m12 * m21
    c01 = m02 * m21 - m01 * m22
    c02 = m01 * m12 - m02 * m11
    c10 = m12 * m20 - m10 * m22
    c11 = m00 * m22 - m02 * m20
    c12 = m02 * m10 - m00 * m12
    c20 = m10 * m21 - m11 * m20
    c21 = m01 * m20 - m00 * m21
    c22 = m00 * m11 - m01 * m10
    det = m00 * c00 + m01 * c10 + m02 * c20
    ok = det > 0.0  # det(I + P J) >= 1 in exact arithmetic
    if ok:
        r = 1.0 / det
        Mi = ((c00 * r, c01 * r, c02 * r), (c10 * r, c11 * r, c12 * r),
              (c20 * r, c21 * r, c22 * r))
        # G = J (I + P~_rr J)^-1, symmetric
        for a in range(3):
            for c in range(3):
                G[a, c] = J[a, 0] * Mi[0][c] + J[a, 1] * Mi[1][c] + J[a, 2] * Mi[2][c]
        # P_f = P~ - P~[:, :3] G P~[:3, :]
        for a in range(6):
            g0 = Pt[a, 0] * G[0, 0] + Pt[a, 1] * G[1, 0] + Pt[a, 2] * G[2, 0]
            g1 = Pt[a, 0] * G[0, 1] + Pt[a, 1] * G[1, 1] + Pt[a, 2] * G[2, 1]
            g2 = Pt[a, 0] * G[0, 2] + Pt[a, 1] * G[1, 2] + Pt[a, 2] * G[2, 2]
            for c in range(a, 6):
                v = Pt[a, c] - (g0 * Pt[0, c] + g1 * Pt[1, c] + g2 * Pt[2, c])
                P_out[a, c] = v
                P_out[c, a] = v
        # x_f = x + P_f [b; 0]
        for a in range(6):
            x_out[a] = x[a] + P_out[a, 0] * b[0] + P_out[a, 1] * b[1] + P_out[a, 2] * b[2]
    return ok
