"""The compiled filter's time update: the forces, RK4, the transition matrix, Q.

The filter's model of the spacecraft's motion at Mars is a Mars point mass plus the third
bodies of :class:`~xnavlab.mars.models.dynamics.ThirdBodyTable` (their positions interpolated by
cubic Hermite polynomials between the table's knots), integrated by the classical RK4 in
sub-steps of at most ``max_step``; the covariance follows the fourth-order transition
matrix ``exp(F h)`` of the point mass and the white-acceleration process noise ``Q``. The
readable version is :mod:`xnavlab.mars.models.time_update` (the tests compare them).

Examples
--------
>>> import numpy as np
>>> from xnavlab.core.constants import GM_MARS
>>> from xnavlab.mars.kernel import kernel_inputs as ki
>>> from xnavlab.mars.models import dynamics
>>> tab = dynamics.ThirdBodyTable(dynamics.MARS_T0, dynamics.MARS_T0 + 600.0)
>>> pr = ki.Propagation(1e-11, 10.0, GM_MARS, tab.t_start, tab.step, tab.pos, tab.vel, tab.gm)
>>> nb = tab.pos.shape[1]
>>> sc = ki.PredictScratch(*[np.empty((6, 6)) for _ in range(3)], np.empty(6),
...                        *[np.empty((nb, 3)) for _ in range(6)])
>>> x, P = dynamics.MARS_STATE0.copy(), np.eye(6)
>>> predict(x, P, dynamics.MARS_T0, 500.0, 1.0, pr, sc)
>>> truth = dynamics.propagate([dynamics.MARS_T0 + 500.0])[0]
>>> bool(np.abs(x - truth)[:3].max() < 1e-3), bool(np.allclose(P, P.T))
(True, True)
"""

from __future__ import annotations

import math

from xnavlab.mars.kernel.kernel_compile import HELPER, INLINE, jit
from xnavlab.mars.kernel.kernel_linalg import matmul6

__all__ = ["predict"]


@jit(**INLINE)
def _bodies(t, pr, s, ind):
    """Third bodies at t: positions ``s`` (nb, 3) by cubic Hermite interpolation of the
    table ``pr.tb_*`` (:class:`~xnavlab.mars.kernel.kernel_inputs.Propagation`, as
    :class:`~xnavlab.mars.models.dynamics.ThirdBodyTable`) and indirect terms ``ind = mu s / |s|^3``."""
    tb_t0, tb_step, tb_pos, tb_vel, tb_gm = pr.tb_t0, pr.tb_step, pr.tb_pos, pr.tb_vel, pr.tb_gm
    nk = tb_pos.shape[0]
    x = (t - tb_t0) / tb_step
    i = int(x)
    if i > nk - 2:
        i = nk - 2
    u = x - i
    h = tb_step
    u2 = u * u
    u3 = u2 * u
    h00 = 2 * u3 - 3 * u2 + 1
    h10 = (u3 - 2 * u2 + u) * h
    h01 = -2 * u3 + 3 * u2
    h11 = (u3 - u2) * h
    for b in range(tb_pos.shape[1]):
        for j in range(3):
            s[b, j] = (h00 * tb_pos[i, b, j] + h10 * tb_vel[i, b, j]
                       + h01 * tb_pos[i + 1, b, j] + h11 * tb_vel[i + 1, b, j])
        sn2 = s[b, 0] * s[b, 0] + s[b, 1] * s[b, 1] + s[b, 2] * s[b, 2]
        f = tb_gm[b] / (sn2 * math.sqrt(sn2))
        for j in range(3):
            ind[b, j] = f * s[b, j]


@jit(**INLINE)
def _accel(r0, r1, r2, gm_mars, tb_gm, s, ind):
    """Mars point mass plus the third bodies at (s, ind) from :func:`_bodies`."""
    rn2 = r0 * r0 + r1 * r1 + r2 * r2
    k = -gm_mars / (rn2 * math.sqrt(rn2))
    a0 = k * r0
    a1 = k * r1
    a2 = k * r2
    for b in range(s.shape[0]):
        d0 = s[b, 0] - r0
        d1 = s[b, 1] - r1
        d2 = s[b, 2] - r2
        dn2 = d0 * d0 + d1 * d1 + d2 * d2
        g = tb_gm[b] / (dn2 * math.sqrt(dn2))
        # a_k = mu_k [ (s - r)/|s - r|^3 - s/|s|^3 ]
        a0 += g * d0 - ind[b, 0]
        a1 += g * d1 - ind[b, 1]
        a2 += g * d2 - ind[b, 2]
    return a0, a1, a2


@jit(**INLINE)
def _rk4(x, t, h, pr, out, sc):
    """One classical Runge-Kutta step of r' = v, v' = a(t, r) with the model ``pr``
    (:class:`~xnavlab.mars.kernel.kernel_inputs.Propagation`; third bodies at t, t + h/2, t + h in
    the scratch pairs (s0, i0), (s1, i1), (s2, i2) of ``sc``, a
    :class:`~xnavlab.mars.kernel.kernel_inputs.PredictScratch`)."""
    gm_mars, tb_gm = pr.gm_mars, pr.tb_gm
    s0, i0, s1, i1, s2, i2 = sc.s0, sc.i0, sc.s1, sc.i1, sc.s2, sc.i2
    _bodies(t, pr, s0, i0)
    x0, x1, x2, x3, x4, x5 = x[0], x[1], x[2], x[3], x[4], x[5]
    hh = 0.5 * h
    a0, a1, a2 = _accel(x0, x1, x2, gm_mars, tb_gm, s0, i0)
    k10, k11, k12, k13, k14, k15 = x3, x4, x5, a0, a1, a2
    # the bodies at t + h/2 and t + h do not depend on the state: placed here, the CPU
    # computes them while it waits on the first stage
    _bodies(t + 0.5 * h, pr, s1, i1)
    _bodies(t + h, pr, s2, i2)
    a0, a1, a2 = _accel(x0 + hh * k10, x1 + hh * k11, x2 + hh * k12, gm_mars, tb_gm, s1, i1)
    k20, k21, k22 = x3 + hh * k13, x4 + hh * k14, x5 + hh * k15
    k23, k24, k25 = a0, a1, a2
    a0, a1, a2 = _accel(x0 + hh * k20, x1 + hh * k21, x2 + hh * k22, gm_mars, tb_gm, s1, i1)
    k30, k31, k32 = x3 + hh * k23, x4 + hh * k24, x5 + hh * k25
    k33, k34, k35 = a0, a1, a2
    a0, a1, a2 = _accel(x0 + h * k30, x1 + h * k31, x2 + h * k32, gm_mars, tb_gm, s2, i2)
    k40, k41, k42 = x3 + h * k33, x4 + h * k34, x5 + h * k35
    k43, k44, k45 = a0, a1, a2
    c = h / 6.0
    # x+ = x + h/6 (k1 + 2 k2 + 2 k3 + k4)
    out[0] = x0 + c * (k10 + 2.0 * k20 + 2.0 * k30 + k40)
    out[1] = x1 + c * (k11 + 2.0 * k21 + 2.0 * k31 + k41)
    out[2] = x2 + c * (k12 + 2.0 * k22 + 2.0 * k32 + k42)
    out[3] = x3 + c * (k13 + 2.0 * k23 + 2.0 * k33 + k43)
    out[4] = x4 + c * (k14 + 2.0 * k24 + 2.0 * k34 + k44)
    out[5] = x5 + c * (k15 + 2.0 * k25 + 2.0 * k35 + k45)


@jit(**INLINE)
def _transition(x, h, gm_mars, Phi):
    """Phi = exp(F h) to fourth order at x, F = [[0, I], [G, 0]] (into Phi), as
    :func:`xnavlab.mars.models.dynamics.transition_matrix`."""
    rn2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2]
    rn = math.sqrt(rn2)
    # gravity gradient G = mu (3 r r^T / |r|^5 - I / |r|^3)
    c3 = 3.0 * gm_mars / (rn2 * rn2 * rn)
    c1 = gm_mars / (rn2 * rn)
    G00 = c3 * x[0] * x[0] - c1
    G11 = c3 * x[1] * x[1] - c1
    G22 = c3 * x[2] * x[2] - c1
    G01 = c3 * x[0] * x[1]
    G02 = c3 * x[0] * x[2]
    G12 = c3 * x[1] * x[2]
    G = ((G00, G01, G02), (G01, G11, G12), (G02, G12, G22))
    # G^2
    Q00 = G00 * G00 + G01 * G01 + G02 * G02
    Q11 = G01 * G01 + G11 * G11 + G12 * G12
    Q22 = G02 * G02 + G12 * G12 + G22 * G22
    Q01 = G00 * G01 + G01 * G11 + G02 * G12
    Q02 = G00 * G02 + G01 * G12 + G02 * G22
    Q12 = G01 * G02 + G11 * G12 + G12 * G22
    G2 = ((Q00, Q01, Q02), (Q01, Q11, Q12), (Q02, Q12, Q22))
    h2 = h * h
    a = h2 / 2.0
    b = h2 * h2 / 24.0
    c = h2 * h / 6.0
    # [[I + G h^2/2 + G^2 h^4/24, I h + G h^3/6], [G h + G^2 h^3/6, I + G h^2/2 + G^2 h^4/24]]
    for i in range(3):
        for j in range(3):
            d = 1.0 if i == j else 0.0
            diag = d + G[i][j] * a + G2[i][j] * b
            Phi[i, j] = diag
            Phi[3 + i, 3 + j] = diag
            Phi[i, 3 + j] = d * h + G[i][j] * c
            Phi[3 + i, j] = G[i][j] * h + G2[i][j] * c


@jit(**HELPER)
def predict(x, P, t, dt, inv_scale, pr, sc):
    """EKF time update of ``(x, P)`` from ``t`` over ``dt``, in place, in
    ``n = ceil(dt / max_step)`` equal sub-steps.

    Each sub-step: one RK4 step of the state and the fourth-order transition matrix at its
    start; ``Phi = Phi_n ... Phi_1``; ``P = Phi P Phi^T + Q(dt) * inv_scale``, as
    :func:`xnavlab.mars.models.time_update.filter_propagate` and
    :func:`~xnavlab.mars.models.time_update.process_noise`. (In place: the first step reads all of
    ``x`` before it writes, and ``P`` is read only into ``T = Phi P``.)

    Parameters
    ----------
    x : ndarray, shape (6,)
        The state ``[r, v]`` (m, m/s, Mars-centred J2000), overwritten by its prediction.
    P : ndarray, shape (6, 6)
        Its covariance, overwritten.
    t, dt : float
        The epoch (s TDB past J2000) and the step (s).
    inv_scale : float
        Factor of the process noise (``1 / share`` for a local of the federated filter).
    pr : xnavlab.mars.kernel.kernel_inputs.Propagation
        The model: ``q``, ``max_step``, Mars and the third-body table.
    sc : xnavlab.mars.kernel.kernel_inputs.PredictScratch
        Working arrays.
    """
    q, max_step, gm_mars = pr.q, pr.max_step, pr.gm_mars
    Phi, Ph, T, xc = sc.Phi, sc.Ph, sc.T, sc.xc
    x_out, P_out = x, P
    nsub = int(math.ceil(dt / max_step - 1e-9))
    if nsub < 1:
        nsub = 1
    h = dt / nsub
    _transition(x, h, gm_mars, Phi)
    _rk4(x, t, h, pr, x_out, sc)
    for sub in range(1, nsub):
        _transition(x_out, h, gm_mars, Ph)
        matmul6(Ph, Phi, T)  # Phi = Phi_sub ... Phi_1
        for i in range(6):
            for j in range(6):
                Phi[i, j] = T[i, j]
        for j in range(6):
            xc[j] = x_out[j]
        _rk4(xc, t + sub * h, h, pr, x_out, sc)
    # P = Phi P Phi^T + Q, Q = q [[dt^3/3 I, dt^2/2 I], [dt^2/2 I, dt I]]
    matmul6(Phi, P, T)
    q33 = q * dt * dt * dt / 3.0 * inv_scale
    q22 = q * dt * dt / 2.0 * inv_scale
    q11 = q * dt * inv_scale
    for i in range(6):
        for j in range(i, 6):
            s = 0.0
            for m in range(6):
                s += T[i, m] * Phi[j, m]
            P_out[i, j] = s
    for i in range(3):
        P_out[i, i] += q33
        P_out[i, 3 + i] += q22
        P_out[3 + i, 3 + i] += q11
    for i in range(6):
        for j in range(i + 1, 6):
            P_out[j, i] = P_out[i, j]
