"""Compiled (numba) kernels of the federated Mars navigation run.

The readable reference is the numpy loop of :mod:`xnavlab.mars.scenarios` (built from
:mod:`xnavlab.core.filters`, :mod:`xnavlab.mars.sensors`, :mod:`xnavlab.core.federated`
and :mod:`xnavlab.mars.dynamics`). :func:`run_epochs` computes the same estimates (the
tests compare them to 1e-9 relative) in about a microsecond per epoch of three EKFs and
the fusion (the measurement series are drawn by :mod:`xnavlab.mars.series`).

Two forms of the same filter
----------------------------
At every epoch the locals and the master predict, the locals update with their
measurements (Joseph form) and the master fuses them (information form). That is what
:func:`run_epochs` does in no-reset mode and, in reset mode, at every epoch whose local
estimates are recorded. At the other reset-mode epochs it uses the fact that makes the
reset mode optimal (Carlson 1990): every local starts the epoch from the master,
``x_i = x``, ``P_i = P / s_i`` (its share ``s_i``; the shares of the connected locals
sum to 1), so its update gives ``P_i+^-1 = s_i P^-1 + H_i^T R_i^-1 H_i`` (exact for the
Kalman gain, whatever the form of the covariance update) and the fusion is

.. math::

   P_f^{-1} = \\sum_i s_i P^{-1} + J, \\quad J = \\sum_j H_j^T R_j^{-1} H_j, \\quad
   x_f = x + P_f \\sum_j H_j^T R_j^{-1} \\nu_j

(i over the connected locals, j over those whose update passed the gate): the centralised
EKF, all measurements taken at the master's prediction. The three sensors see the
position only, so ``J`` is 3 x 3 and the matrix inversion lemma gives
``P_f = P~ - P~[:, :3] J (I + P~_rr J)^-1 P~[:3, :]`` with ``P~ = P / sum_i s_i``: one
3 x 3 inverse instead of four 6 x 6 ones, and no local covariance update. The NIS of every
local (gating, fault detection) is computed as before from ``S_i = H_i P H_i^T / s_i +
R_i``. The two forms agree to rounding; the tests check both against the numpy loop.

The combined detector inside the loop
-------------------------------------
For the subsystems it watches, :func:`run_epochs` whitens each measurement's innovation
against the master's one-step prediction and feeds the combined detector's innovation parts
(chi-square, mean and variance CUSUMs; XNAV's innovation wavelet) before the update; an alarm
leaves the measurement out and switches the subsystem out from the next epoch, and the call
returns after that epoch, as it does on the re-admission grid when an isolated subsystem's
last innovations are quiet (:mod:`xnavlab.mars.watch` holds the state; the adaptive scale is
recomputed here, its medians by selection). Unwatched runs pay one test per measurement.

Compilation
-----------
Every function is compiled with ``cache=True``: the first call in a fresh environment
compiles (tens of seconds; ``python -m xnavlab warmup`` does it at set-up) and stores
the machine code in ``__pycache__``; later processes load it in a fraction of a second.
The helpers are compiled with ``_nrt=False`` (numba's switch for functions that allocate
nothing): otherwise numba may wrap each call that passes arrays in atomic
reference-count updates, which cost more than the arithmetic of these 6 x 6 steps. No
fast-math, not even FMA contraction: with ``fastmath={"contract"}`` a process that compiled
the kernels and one that loaded them from numba's cache gave different last digits (30-day
RMS 26.412803132646456 m against 26.41280310716354 m); without it both give the same bits
(26.412803121293372 m) at the same cost (1.23 s against 1.24 s). The arguments come in the named
tuples of :mod:`xnavlab.mars.kernel_inputs` (why named tuples: there), the scratch arrays
in private ones that :func:`run_epochs` allocates once per call; every helper reads them by
field name (numba resolves a field at compile time) and takes a few of them.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from xnavlab.core.constants import GM_SUN, C
from xnavlab.mars import kernel_inputs

__all__ = ["run_epochs", "KIND_XNAV", "KIND_UV", "KIND_CNS"]

#: Subsystem code of the XNAV filter in the kernels' integer arrays.
KIND_XNAV = 0
#: Subsystem code of the UV-sensor filter.
KIND_UV = 1
#: Subsystem code of the CNS filter.
KIND_CNS = 2

_SHAPIRO = 2.0 * GM_SUN / C**3

# flags written per epoch and subsystem
NO_MEAS = 0
UPDATED = 1
REJECTED = 2  # innovation gate exceeded: time update only
ISOLATED = 3  # subsystem switched out: time update only

#: compile options of the helpers (no allocation inside; no fast-math: see the module docstring)
_HELPER = {"cache": True, "_nrt": False}
#: small helpers inlined into their caller (so that constant sizes propagate)
_INLINE = {"cache": True, "_nrt": False, "inline": "always"}


#: The containers' fields as the code below reads them. numba keys its cache by this file's
#: source and the fields' types, not their names: a change of :mod:`xnavlab.mars.kernel_inputs`
#: must change this literal too (checked here), which recompiles the kernels.
_LAYOUT = (
    "FilterState(xs Ps shares xm Pm)", "Plan(times kinds meas_idx active beta reset gate)",
    "Propagation(q max_step gm_mars tb_t0 tb_step tb_pos tb_vel tb_gm)",
    "Sensors(z_x rm_x rs_x n_x d_x sig_x z_u sig_r sig_u z_c stars_c sig_s sig_h)",
    "Records(pos x P xl Pl nis flags)", "WatchState(wf wi wS wsc ring ys_x ys_u ys_c xbuf xG xthr alarm)",
)
if sorted(kernel_inputs.layout()) != sorted(_LAYOUT):
    raise ImportError("xnavlab.mars.kernel_inputs changed its fields: update kernels._LAYOUT")
#: The scratch arrays :func:`run_epochs` allocates (their shapes there): of :func:`_predict`;
#: a measurement's innovation, Jacobian and noise (``A``: the CNS noise's scratch); of the
#: measurement updates; of the fusions; of the watch. :data:`_Args` and :data:`_Scratch` hold
#: the inputs and the scratch for the loop.
_Prop = namedtuple("_Prop", "Phi Ph T xc s0 i0 s1 i1 s2 i2")
_Meas = namedtuple("_Meas", "nu H R A")
_Upd = namedtuple("_Upd", "PHt S L y K W T")
_Fus = namedtuple("_Fus", "d Y yv Ci Cf xp Pp J bv G use inv_sh")
_Wat = namedtuple("_Wat", "alarmed zw med cnt")
_Args = namedtuple("_Args", "st pr pl se rec ws")
_Scratch = namedtuple("_Scratch", "sp me mw up fu wt")


# ----------------------------------------------------------------------- dynamics


@njit(**_INLINE)
def _bodies(t, pr, s, ind):
    """Third bodies at t: positions ``s`` (nb, 3) by cubic Hermite interpolation of the
    table ``pr.tb_*`` (:class:`~xnavlab.mars.kernel_inputs.Propagation`, as
    :class:`~xnavlab.mars.dynamics.ThirdBodyTable`) and indirect terms ``ind = mu s / |s|^3``."""
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


@njit(**_INLINE)
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


@njit(**_INLINE)
def _rk4(x, t, h, pr, out, sc):
    """One classical Runge-Kutta step of r' = v, v' = a(t, r) with the model ``pr``
    (:class:`~xnavlab.mars.kernel_inputs.Propagation`; third bodies at t, t + h/2, t + h in
    the scratch pairs (s0, i0), (s1, i1), (s2, i2) of ``sc``, a :data:`_Prop`)."""
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


@njit(**_INLINE)
def _transition(x, h, gm_mars, Phi):
    """Phi = exp(F h) to fourth order at x, F = [[0, I], [G, 0]] (into Phi), as
    :func:`xnavlab.mars.dynamics.transition_matrix`."""
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


@njit(**_INLINE)
def _matmul6(A, B, out):
    """``out = A B`` for 6 x 6 matrices (``out`` must alias neither)."""
    for i in range(6):
        for j in range(6):
            acc = 0.0
            for m in range(6):
                acc += A[i, m] * B[m, j]
            out[i, j] = acc


@njit(**_HELPER)
def _predict(x, P, t, dt, inv_scale, pr, sc):
    """EKF time update of ``x`` (6,) and ``P`` (6, 6) from t over dt, in place, in
    n = ceil(dt / max_step) equal sub-steps.

    Each sub-step: one RK4 step of the state and the fourth-order transition matrix at
    its start; ``Phi = Phi_n ... Phi_1``; ``P = Phi P Phi^T + Q(dt) * inv_scale``. The model
    ``pr`` (:class:`~xnavlab.mars.kernel_inputs.Propagation`: ``q``, ``max_step``, forces);
    scratch ``sc`` (:data:`_Prop`). (In place: the first step reads all of ``x`` before it
    writes, and ``P`` is read only into ``T = Phi P``.)
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
        _matmul6(Ph, Phi, T)  # Phi = Phi_sub ... Phi_1
        for i in range(6):
            for j in range(6):
                Phi[i, j] = T[i, j]
        for j in range(6):
            xc[j] = x_out[j]
        _rk4(xc, t + sub * h, h, pr, x_out, sc)
    # P = Phi P Phi^T + Q, Q = q [[dt^3/3 I, dt^2/2 I], [dt^2/2 I, dt I]]
    _matmul6(Phi, P, T)
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


# ---------------------------------------------------------------------- linear algebra


@njit(**_INLINE)
def _cholesky(A, n, L):
    """Lower Cholesky factor of the lower triangle of A (n x n); False if not positive
    definite. The diagonal of ``L`` holds the *reciprocals* ``1 / L_ii``."""
    ok = True
    for j in range(n):
        s = A[j, j]
        for k in range(j):
            s -= L[j, k] * L[j, k]
        if not s > 0.0:
            ok = False
            s = 1.0
        r = 1.0 / math.sqrt(s)
        L[j, j] = r
        for i in range(j + 1, n):
            s = A[i, j]
            for k in range(j):
                s -= L[i, k] * L[j, k]
            L[i, j] = s * r
    return ok


@njit(**_INLINE)
def _forward(L, n, b):
    """b = L^-1 b in place (L from :func:`_cholesky`)."""
    for i in range(n):
        s = b[i]
        for k in range(i):
            s -= L[i, k] * b[k]
        b[i] = s * L[i, i]


@njit(**_INLINE)
def _backward(L, n, b):
    """b = L^-T b in place (L from :func:`_cholesky`)."""
    for i in range(n - 1, -1, -1):
        s = b[i]
        for k in range(i + 1, n):
            s -= L[k, i] * b[k]
        b[i] = s * L[i, i]


@njit(**_INLINE)
def _inverse_from_cholesky(L, out):
    """``out = (L L^T)^-1`` for the 6 x 6 factor L of :func:`_cholesky` (L overwritten by
    L^-1). Fills the lower triangle of ``out``."""
    for j in range(6):
        for i in range(j + 1, 6):
            s = 0.0
            for k in range(j, i):
                s -= L[i, k] * L[k, j]
            L[i, j] = s * L[i, i]
    # A^-1 = L^-T L^-1
    for a in range(6):
        for b in range(a + 1):
            s = 0.0
            for k in range(a, 6):
                s += L[k, a] * L[k, b]
            out[a, b] = s


# ------------------------------------------------------------------ measurement models


@njit(**_INLINE)
def _h_xnav(x, jm, se, me):
    """Paper eq. (1) delays, eq. (4) rows (position columns) and the diagonal R of XNAV
    measurement ``jm`` of ``se``, for the spacecraft at rm + r; ``nu = z - h(x)`` (into
    ``me``, a :data:`_Meas`)."""
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


@njit(**_INLINE)
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


@njit(**_INLINE)
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


@njit(**_INLINE)
def _measure(kind, x, jm, se, me):
    """Innovation, Jacobian (position columns) and R of subsystem ``kind``'s measurement
    ``jm`` of ``se`` (:class:`~xnavlab.mars.kernel_inputs.Sensors`) for the state ``x``
    (6,), into ``me`` (:data:`_Meas`); returns the measurement size m."""
    if kind == KIND_UV:
        _h_uv(x, jm, se, me)
        return 4
    if kind == KIND_CNS:
        _h_cns(x, jm, se, me)
        return se.stars_c.shape[0]
    _h_xnav(x, jm, se, me)
    return se.n_x.shape[0]


# ------------------------------------------------------------------------ the updates


@njit(**_INLINE)
def _innovation_cov(P, inv_s, me, m, up):
    """``up.PHt = P H^T * inv_s`` (6, m) and the lower triangle of ``up.S = H PHt + R``
    (H, R of ``me``; H has zero velocity columns: only ``H[:, :3]`` is used)."""
    H, R, PHt, S = me.H, me.R, up.PHt, up.S
    for i in range(6):
        for j in range(m):
            PHt[i, j] = (P[i, 0] * H[j, 0] + P[i, 1] * H[j, 1] + P[i, 2] * H[j, 2]) * inv_s
    for i in range(m):
        for j in range(i + 1):
            S[i, j] = R[i, j] + H[i, 0] * PHt[0, j] + H[i, 1] * PHt[1, j] + H[i, 2] * PHt[2, j]


@njit(**_INLINE)
def _nis(me, m, up):
    """NIS ``nu^T S^-1 nu = |L^-1 nu|^2`` (``up.L`` from :func:`_cholesky` of S; scratch
    ``up.y``)."""
    nu, L, y = me.nu, up.L, up.y
    for i in range(m):
        y[i] = nu[i]
    _forward(L, m, y)
    nis = 0.0
    for i in range(m):
        nis += y[i] * y[i]
    return nis


@njit(**_INLINE)
def _update(st, i_, me, m, gate, do_update, up):
    """Joseph-form EKF update of local ``i_`` of ``st`` in place with the measurement ``me``
    (:data:`_Meas`, size m; scratch ``up``, :data:`_Upd`); returns the NIS (NaN if S is not PD).

    The update is applied only when ``do_update`` and NIS <= gate. The three sensors'
    Jacobians have zero velocity columns (paper eqs. (4)-(6)), so only ``H[:, :3]``
    is used, and ``A = I - K H`` has identity velocity columns: the Joseph product
    ``A P A^T`` is formed as ``T = P - K (P H^T)^T``, ``T A^T = T - (T H^T) K^T``.
    """
    xs, Ps = st.xs, st.Ps
    nu, H, R = me.nu, me.H, me.R
    PHt, L, y, K, W, T = up.PHt, up.L, up.y, up.K, up.W, up.T
    _innovation_cov(Ps[i_], 1.0, me, m, up)  # S = H P H^T + R
    nis = np.nan
    if _cholesky(up.S, m, L):
        nis = _nis(me, m, up)
        if do_update and nis <= gate:
            # K = P H^T S^-1, row by row: S k_i = (P H^T)_i
            for i in range(6):
                for j in range(m):
                    y[j] = PHt[i, j]
                _forward(L, m, y)
                _backward(L, m, y)
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


@njit(**_INLINE)
def _update_sized(st, i_, me, m, gate, do_update, up):
    """:func:`_update` compiled for the common sizes m = 3 and 4 (unrolled) and any other."""
    if m == 4:
        return _update(st, i_, me, 4, gate, do_update, up)
    if m == 3:
        return _update(st, i_, me, 3, gate, do_update, up)
    return _update_any(st, i_, me, m, gate, do_update, up)


@njit(**_HELPER)
def _update_any(st, i_, me, m, gate, do_update, up):
    """:func:`_update` for any m (not inlined: compiled once, kept out of the loop's code)."""
    return _update(st, i_, me, m, gate, do_update, up)


@njit(**_INLINE)
def _gain_information(me, m, up, fu):
    """``fu.J += H^T R^-1 H`` (3 x 3, lower triangle) and ``fu.bv += H^T R^-1 nu`` (3,) of the
    measurement ``me`` (scratch ``up.L``, ``up.y``)."""
    nu, H, R, L, y, J, b = me.nu, me.H, me.R, up.L, up.y, fu.J, fu.bv
    _cholesky(R, m, L)  # R is positive definite by construction
    # with R = L L^T: H^T R^-1 H = (L^-1 H)^T (L^-1 H), H^T R^-1 nu = (L^-1 H)^T (L^-1 nu)
    for j in range(m):
        y[j] = nu[j]
    _forward(L, m, y)
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


@njit(**_INLINE)
def _update_sized_info(fu, i_, me, m, gate, do_update, up):
    """NIS of local ``i_`` when it starts from the master's prediction ``(fu.xp, fu.Pp /
    s_i)`` and, when ``do_update`` and NIS <= gate, its information ``H^T R^-1 H``,
    ``H^T R^-1 nu`` added to ``fu.J`` and ``fu.bv`` (reset mode)."""
    _innovation_cov(fu.Pp, fu.inv_sh[i_], me, m, up)  # S = H P H^T / s + R
    nis = np.nan
    if _cholesky(up.S, m, up.L):
        nis = _nis(me, m, up)
        if do_update and nis <= gate:
            _gain_information(me, m, up, fu)
    return nis


@njit(**_INLINE)
def _info_sized(fu, i_, me, m, gate, do_update, up):
    """:func:`_update_sized_info` compiled for m = 3, 4 (unrolled) and any other."""
    if m == 4:
        return _update_sized_info(fu, i_, me, 4, gate, do_update, up)
    if m == 3:
        return _update_sized_info(fu, i_, me, 3, gate, do_update, up)
    return _info_any(fu, i_, me, m, gate, do_update, up)


@njit(**_HELPER)
def _info_any(fu, i_, me, m, gate, do_update, up):
    """:func:`_update_sized_info` for any m (not inlined)."""
    return _update_sized_info(fu, i_, me, m, gate, do_update, up)


# ----------------------------------------------------------------------------- fusion


@njit(**_HELPER)
def _fuse(st, fu):
    """Information-form fusion of the local estimates ``st.xs``, ``st.Ps`` with ``fu.use[i]``
    True into the master ``st.xm``, ``st.Pm`` (scratch ``fu``, :data:`_Fus`).

    P_f = (sum P_i^-1)^-1, x_f = P_f sum P_i^-1 x_i, computed on Jacobi-scaled
    covariances and on deviations from the first used estimate (for precision), as
    :func:`xnavlab.core.federated.fuse`. Returns False if no estimate is used or a
    matrix is not positive definite.
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
        ok = _cholesky(C, 6, C)
        _inverse_from_cholesky(C, Cf)  # Cf = scaled P_i^-1 (lower)
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
        ok = _cholesky(Y, 6, Y)
        _inverse_from_cholesky(Y, Cf)  # P_f = (sum P_i^-1)^-1, scaled
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


@njit(**_HELPER)
def _fuse_information(st, fu, ssum):
    """Reset-mode fusion from the information the locals gained (module docstring):
    ``P_f^-1 = ssum P^-1 + J`` and ``x_f = x + P_f b``, by the matrix inversion lemma
    ``P_f = P~ - P~[:, :3] J (I + P~_rr J)^-1 P~[:3, :]``, ``P~ = P / ssum``.

    ``x``, ``P`` the master's prediction ``fu.xp``, ``fu.Pp``; ``J = fu.J`` (3, 3) lower
    triangle, ``b = fu.bv`` (3,); into ``st.xm``, ``st.Pm``; scratch ``fu.Ci`` (6, 6),
    ``fu.G`` (3, 3).
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


# ------------------------------------------------- the combined detector, inside the loop

#: Columns of the watch's float parameters ``wf`` (ns, 10) (:mod:`xnavlab.mars.watch`): the
#: CUSUM references and thresholds, the chi-square threshold, the arming time, the scale's
#: prior weight and MAD factor, the re-admission test's threshold and normal quantile.
(WF_KMEAN, WF_KVAR, WF_CHI2, WF_HMEAN, WF_HVAR, WF_TARM, WF_PRIOR, WF_MAD, WF_RTHR,
 WF_ZQ) = range(10)
#: Columns of its integer state ``wi`` (ns, 15): watched, components, MAD window, its fill
#: and next row, samples fed, next scale update, XNAV wavelet samples, scale period, adaptive,
#: out, measurements since out, last measurement row, re-admission window, check period.
(WI_ON, WI_M, WI_W, WI_NRING, WI_POS, WI_NFED, WI_NEXT, WI_XCOUNT, WI_EVERY, WI_ADAPT, WI_OUT,
 WI_NOUT, WI_LAST, WI_RWIN, WI_CHECK) = range(15)


@njit(**_INLINE)
def _whiten_uv(x, P, jm, se, y):
    """UV measurement ``jm``'s innovation at the state ``x`` (6,) with covariance ``P``,
    whitened per component into ``y``: the range and the direction's two tangent axes, each
    ``nu / sqrt(g P g^T + sigma^2)`` (the unit vector's radial part carries no information)."""
    z, sig_r, sig_u = se.z_u, se.sig_r, se.sig_u
    rn = math.sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2])
    u0, u1, u2 = -x[0] / rn, -x[1] / rn, -x[2] / rn
    p00, p01, p02, p11, p12, p22 = P[0, 0], P[0, 1], P[0, 2], P[1, 1], P[1, 2], P[2, 2]
    s = (u0 * (p00 * u0 + p01 * u1 + p02 * u2) + u1 * (p01 * u0 + p11 * u1 + p12 * u2)
         + u2 * (p02 * u0 + p12 * u1 + p22 * u2))                   # u^T P u
    y[0] = (z[jm, 0] - rn) / math.sqrt(s + sig_r * sig_r)          # range, g = -u
    if abs(u2) > 1.0 - 1e-12:                     # tangent basis e1 = z x u (x x u at a pole)
        e1 = (0.0, -u2, u1)
    else:
        e1 = (-u1, u0, 0.0)
    m1 = math.sqrt(e1[0] ** 2 + e1[1] ** 2 + e1[2] ** 2)
    e1 = (e1[0] / m1, e1[1] / m1, e1[2] / m1)
    e2 = (u1 * e1[2] - u2 * e1[1], u2 * e1[0] - u0 * e1[2], u0 * e1[1] - u1 * e1[0])
    for c in range(2):
        e = e1 if c == 0 else e2
        d = (z[jm, 1] - u0) * e[0] + (z[jm, 2] - u1) * e[1] + (z[jm, 3] - u2) * e[2]
        s = (e[0] * (p00 * e[0] + p01 * e[1] + p02 * e[2]) + e[1] * (p01 * e[0] + p11 * e[1]
             + p12 * e[2]) + e[2] * (p02 * e[0] + p12 * e[1] + p22 * e[2]))   # e^T P e
        y[1 + c] = d / math.sqrt(s / (rn * rn) + sig_u * sig_u)    # g = -e / |r|


@njit(**_INLINE)
def _whiten_at(P, me, m, up):
    """``up.y = L^-1 nu`` with ``L L^T = H P H^T + R`` (``me``'s nu, H, R); False if S is
    not positive definite."""
    _innovation_cov(P, 1.0, me, m, up)                         # S = H P H^T + R
    ok = _cholesky(up.S, m, up.L)
    y, nu = up.y, me.nu
    for i in range(m):
        y[i] = nu[i]
    _forward(up.L, m, y)
    return ok


@njit(**_INLINE)
def _whiten(kind, jm, me, m, fu, se, up):
    """Subsystem ``kind``'s measurement ``jm`` (``me``: its innovation, Jacobian and R at the
    master's prediction ``fu.xp``, ``fu.Pp``), whitened into ``up.y``; returns its size (UV:
    3, the range and two tangent axes)."""
    if kind == KIND_UV:
        _whiten_uv(fu.xp, fu.Pp, jm, se, up.y)
        return 3
    _whiten_at(fu.Pp, me, m, up)
    return m


@njit(**_INLINE)
def _watch_monitor(i, jm, m, connected, y, ys, ws, wt):
    """The innovation parts of the combined detector on one whitened innovation ``y`` (m,)
    of subsystem ``i`` (:class:`xnavlab.core.detection.InnovationMonitor`, one sample), its
    state in ``ws`` (:class:`~xnavlab.mars.kernel_inputs.WatchState`).

    Writes ``y`` to ``ys[jm]`` and ``z = y / s`` (the adaptive scale) to ``wt.zw``; if
    ``connected`` (and armed): the chi-square ``q = sum z^2``, the CUSUMs
    ``S+ = max(0, S+ + z - k)``, ``S- = max(0, S- - z - k)``, ``V = max(0, V + z^2 - k_v)``;
    on an alarm the CUSUMs restart, ``alarm[i]`` gets the part and its ratio and True is
    returned; a healthy sample goes into the scale's window, and the scale is recomputed on
    the monitor's grid of samples fed (:func:`_rescale`)."""
    wf, wi, wS, wsc, ring, alarm = ws.wf, ws.wi, ws.wS, ws.wsc, ws.ring, ws.alarm
    z = wt.zw
    q = 0.0
    for c in range(m):
        ys[jm, c] = y[c]
        z[c] = y[c] / wsc[i, c]
        q += z[c] * z[c]                                       # chapter 9 eq. (ch9-chi2)
    if not connected:
        return False
    km, kv = wf[i, WF_KMEAN], wf[i, WF_KVAR]
    hm, hv = wf[i, WF_HMEAN], wf[i, WF_HVAR]
    over = q > wf[i, WF_CHI2]
    for c in range(m):
        a = max(0.0, wS[i, c] + z[c] - km)                    # S+ = max(0, S+ + z - k)
        b = max(0.0, wS[i, m + c] - z[c] - km)                # S- = max(0, S- - z - k)
        v = max(0.0, wS[i, 2 * m + c] + z[c] * z[c] - kv)     # V = max(0, V + z^2 - k_v)
        wS[i, c], wS[i, m + c], wS[i, 2 * m + c] = a, b, v
        over = over or a > hm or b > hm or v > hv
    best = 0.0
    if over:                  # (statistic / threshold > 1 needs statistic > threshold)
        best = q / wf[i, WF_CHI2]
        part = 0
        for j in range(3 * m):
            r = wS[i, j] / (hm if j < 2 * m else hv)
            if r > best:
                best = r
                part = 1 + j
    if best > 1.0:
        for j in range(3 * m):
            wS[i, j] = 0.0
        alarm[i, 0] = part
        alarm[i, 1] = best
        return True
    W = wi[i, WI_W]                                            # a healthy sample: the window
    pos = wi[i, WI_POS]
    for c in range(m):
        ring[i, c, pos] = y[c]
    wi[i, WI_POS] = (pos + 1) % W
    wi[i, WI_NRING] = min(W, wi[i, WI_NRING] + 1)
    wi[i, WI_NFED] += 1
    if wi[i, WI_NFED] >= wi[i, WI_NEXT]:
        if wi[i, WI_ADAPT]:
            _rescale(i, m, ws, wt)
        nxt = wi[i, WI_NEXT]                 # 100, 200, 400, ... then every scale_every
        wi[i, WI_NEXT] = min(2 * nxt, nxt + wi[i, WI_EVERY])
    return False


@njit(**_HELPER)
def _rescale(i, m, ws, wt):
    """The adaptive scale ``ws.wsc[i]`` from the MAD window ``ws.ring[i]``, as
    :meth:`xnavlab.core.detection.InnovationMonitor.scale_from`:
    ``s^2 = (n0 + n MAD^2) / (n0 + n)``, ``MAD = median|y| / 0.6745`` (scratch ``wt.med``,
    ``wt.cnt``)."""
    wf, wi, ring, wsc, med, cnt = ws.wf, ws.wi, ws.ring, ws.wsc, wt.med, wt.cnt
    n = wi[i, WI_NRING]
    n0 = wf[i, WF_PRIOR]
    for c in range(m):
        mad = _median_abs(ring[i, c], n, med, cnt) / wf[i, WF_MAD]
        wsc[i, c] = math.sqrt((n0 + n * (mad * mad)) / (n0 + n))


@njit(**_HELPER)
def _median_abs(x, n, med, cnt):
    """``median(|x[:n]|)`` exactly as numpy takes it (the mean of the two middle values for even
    ``n``), by :func:`_radix_select` (scratch ``med`` (>= n,), ``cnt`` (8192,) int64)."""
    for r in range(n):
        med[r] = abs(x[r])
    k = n // 2
    v = _radix_select(med, n, k, cnt)
    if n % 2 == 0:
        below, lo = 0, 0.0
        for r in range(n):          # (branch-free: the comparisons are coin flips)
            a = abs(x[r])
            lt = a < v
            below += lt
            lo = max(lo, a * lt)
        v = ((lo if below >= k else v) + v) / 2.0
    return v


@njit(**_HELPER)
def _radix_select(f, n, k, cnt):
    """The k-th smallest (0-based) of the nonnegative ``f[:n]``, destroying ``f``: histograms of
    the bit patterns (whose order is the values' order), 12 then 13 bits at a time, keep the
    bucket holding the k-th, until at most 32 are left (few branches, so few mispredictions:
    half a quickselect's time on a day of innovations)."""
    u = f.view(np.uint64)
    shift, width = 52, 12
    while True:
        mask = (1 << width) - 1
        sh, mk = np.uint64(shift), np.uint64(mask)
        for b in range(mask + 1):
            cnt[b] = 0
        for r in range(n):
            cnt[np.int64((u[r] >> sh) & mk)] += 1
        b = 0
        while cnt[b] <= k:
            k -= cnt[b]
            b += 1
        w = 0
        for r in range(n):          # compaction without a branch
            e = u[r]
            u[w] = e
            w += np.int64((e >> sh) & mk) == b
        n = w
        if n <= 32 or shift == 0:      # (at shift 0 the bucket holds one value, repeated)
            break
        width = min(13, shift)
        shift -= width
    for r in range(1, n):              # insertion sort of the last bucket
        v, j = f[r], r - 1
        while j >= 0 and f[j] > v:
            f[j + 1] = f[j]
            j -= 1
        f[j + 1] = v
    return f[k]


@njit(**_HELPER)
def _quiet(i, ws, ys):
    """Whether subsystem ``i``, out, may rejoin (a superset of the loop's own test, which
    decides): its last ``W`` scaled innovations since the isolation (in ``ys``) give a NIS
    sum below the threshold and no component sum beyond ``zq sqrt(W)``."""
    wf, wi, wsc = ws.wf, ws.wi, ws.wsc
    w = wi[i, WI_RWIN]
    if wi[i, WI_NOUT] < w:
        return False
    m = wi[i, WI_M]
    last = wi[i, WI_LAST]
    tot = 0.0
    for c in range(m):
        sc = 0.0
        for r in range(last - w + 1, last + 1):
            z = ys[r, c] / wsc[i, c]
            tot += z * z
            sc += z
        if abs(sc) > wf[i, WF_ZQ] * math.sqrt(w) * (1.0 + 1e-9):
            return False
    return tot < wf[i, WF_RTHR] * (1.0 + 1e-9)


@njit(**_HELPER)
def _watch_wavelet(i, z, m, ws):
    """The XNAV innovation wavelet on one scaled innovation ``z`` (m,) (newest first in
    ``ws.xbuf``; :class:`xnavlab.mars.innovations.XnavInnovationWavelet`): True when a level's
    ``|d_j| > k sigma_j`` for some pulsar; ``ws.alarm[i, 2:]`` get ``level * m + pulsar`` and
    the ratio."""
    wi, xbuf, xG, xthr, alarm = ws.wi, ws.xbuf, ws.xG, ws.xthr, ws.alarm
    nw = xG.shape[1]
    for r in range(nw - 1, 0, -1):
        for c in range(m):
            xbuf[r, c] = xbuf[r - 1, c]
    for c in range(m):
        xbuf[0, c] = z[c]
    wi[i, WI_XCOUNT] += 1
    if wi[i, WI_XCOUNT] < nw:
        return False
    best = -1.0
    code = 0
    for lv in range(xG.shape[0]):
        for c in range(m):
            d = 0.0
            for r in range(nw):
                d += xG[lv, r] * xbuf[r, c]                    # d_j = sum_r g_j[r] z[n - r]
            ratio = abs(d) / xthr[lv]
            if ratio > best:
                best = ratio
                code = lv * m + c
    if best > 1.0:
        alarm[i, 2] = code
        alarm[i, 3] = best
        return True
    return False


@njit(**_INLINE)
def _ys(kind, ws):
    """The innovation output (whitened, unscaled) of a subsystem kind (``ws`` a
    :class:`~xnavlab.mars.kernel_inputs.WatchState`)."""
    if kind == KIND_UV:
        return ws.ys_u
    if kind == KIND_CNS:
        return ws.ys_c
    return ws.ys_x


@njit(**_INLINE)
def _watch(kind, i, jm, connected, m, y, ws, wt):
    """Feed subsystem ``i``'s measurement ``jm``, whitened against the master's prediction
    (``y`` (m,), :func:`_whiten`), to the combined detector's parts (judged only if
    ``connected``, and armed). Returns True on an alarm.

    ``ws`` the detector's :class:`~xnavlab.mars.kernel_inputs.WatchState`; scratch ``wt``
    (:data:`_Wat`).
    """
    wi = ws.wi
    wi[i, WI_LAST] = jm
    if wi[i, WI_OUT]:
        wi[i, WI_NOUT] += 1
    hit = _watch_monitor(i, jm, m, connected, y, _ys(kind, ws), ws, wt)
    if connected and kind == KIND_XNAV and ws.xG.shape[0] > 0:
        hit = _watch_wavelet(i, wt.zw, m, ws) or hit
    return hit


# ---------------------------------------------------------------------------- the run


@njit(cache=True, nogil=True)
def run_epochs(k0, k1, st, pr, pl, se, rec, ws):
    """Run epochs ``k0 <= k < k1`` of the federated filter, updating the state in place.

    The containers are those of :mod:`xnavlab.mars.kernel_inputs` (their fields, shapes and
    units are documented there).

    Parameters
    ----------
    k0, k1 : int
        The epochs to run, ``0 <= k0 <= k1 <= n``.
    st : FilterState
        The local and master estimates and the shares, updated in place.
    pr : xnavlab.mars.kernel_inputs.Propagation
        The time update's model (process noise, sub-step, Mars and the third-body table).
    pl : Plan
        Epochs, subsystem codes, measurement rows, connections, sharing factors, mode and
        gates; ``pl.active[k + 1, i]`` is cleared when subsystem ``i`` alarms at epoch ``k``.
    se : Sensors
        The measurements and noise of XNAV, UV and CNS.
    rec : Records
        Written in place: the master's and the locals' estimates at the recorded epochs, every
        epoch's NIS and flag.
    ws : WatchState
        The combined detector's state (:mod:`xnavlab.mars.watch`), for the subsystems it
        watches (``ws.wi[i, WI_ON]``): each of their measurements is whitened against the
        master's prediction and fed to its parts before the update; an alarm leaves the
        measurement out and switches the subsystem out from the next epoch.

    Returns
    -------
    int
        -1 when the epochs ran to ``k1``; ``k`` when the run stopped after epoch ``k``
        because the combined detector alarmed there (``ws.alarm``) or an isolated subsystem
        may rejoin at epoch ``k + 1`` (a multiple of its check period); -2 on a numerical
        failure (a covariance lost positive definiteness).
    """
    ns = st.xs.shape[0]
    nb = pr.tb_pos.shape[1]
    mm = max(4, se.n_x.shape[0], se.stars_c.shape[0])
    e = np.empty     # (s*, i*: the third bodies' positions and indirect terms at t, t + h/2, t + h)
    sp = _Prop(e((6, 6)), e((6, 6)), e((6, 6)), e(6),
               e((nb, 3)), e((nb, 3)), e((nb, 3)), e((nb, 3)), e((nb, 3)), e((nb, 3)))
    A = e((mm, 3))                  # (the two measurement scratches share the CNS noise's)
    me = _Meas(e(mm), np.zeros((mm, 6)), np.zeros((mm, mm)), A)   # at the local's state
    mw = _Meas(e(mm), np.zeros((mm, 6)), np.zeros((mm, mm)), A)   # at the master's (watch)
    up = _Upd(e((6, mm)), e((mm, mm)), e((mm, mm)), e(mm), e((6, mm)), e((6, mm)), e((6, 6)))
    fu = _Fus(e(6), e((6, 6)), e(6), e((6, 6)), e((6, 6)),                # the fusion's
              e(6), e((6, 6)),                                             # xp, Pp
              np.zeros((3, 3)), np.zeros(3), e((3, 3)),                    # J, bv, G
              np.zeros(ns, dtype=np.bool_), e(ns))                         # use, 1 / shares
    wt = _Wat(np.zeros(ns, dtype=np.bool_), e(mm), e(ws.ring.shape[2]), e(8192, dtype=np.int64))
    return _run(k0, k1, _Args(st, pr, pl, se, rec, ws), _Scratch(sp, me, mw, up, fu, wt))


@njit(**_HELPER)
def _run(k0, k1, args, sc):
    """The epoch loop of :func:`run_epochs` (``args`` its arguments, a :data:`_Args`; ``sc``
    the scratch allocated there, a :data:`_Scratch`)."""
    st, pr, pl, se, rec, ws = args.st, args.pr, args.pl, args.se, args.rec, args.ws
    sp, me, mw, up, fu, wt = sc.sp, sc.me, sc.mw, sc.up, sc.fu, sc.wt
    xs, Ps, shares, xm, Pm = st.xs, st.Ps, st.shares, st.xm, st.Pm
    times, kinds, active, reset, gate = pl.times, pl.kinds, pl.active, pl.reset, pl.gate
    wf, wi = ws.wf, ws.wi
    xp, Pp, use, inv_sh = fu.xp, fu.Pp, fu.use, fu.inv_sh
    ns = xs.shape[0]
    for i in range(ns):
        inv_sh[i] = 1.0 / shares[i]
    for k in range(k0, k1):
        stop = False
        if k > 0:
            tp = times[k - 1]
            dt = times[k] - tp
            # master time update (full Q): xp, Pp
            for a in range(6):
                xp[a] = xm[a]
                for b in range(6):
                    Pp[a, b] = Pm[a, b]
            _predict(xp, Pp, tp, dt, 1.0, pr, sp)
            full = not reset or rec.pos[k] >= 0  # run the locals in full (else: information)
            if reset:
                # after a reset every local equals the master scaled by 1/share, and the time
                # update commutes with that scaling: P_i- = (Phi P_f Phi^T + Q) / share_i
                for i in range(ns):
                    for a in range(6):
                        xs[i, a] = xp[a]
                    if full:
                        for a in range(6):
                            for b in range(6):
                                Ps[i, a, b] = Pp[a, b] * inv_sh[i]
            else:
                for i in range(ns):
                    _predict(xs[i], Ps[i], tp, dt, inv_sh[i], pr, sp)
            # measurement updates
            for a in range(3):
                fu.bv[a] = 0.0
                for b in range(3):
                    fu.J[a, b] = 0.0
            for i in range(ns):
                j = pl.meas_idx[k, i]
                if j < 0:
                    rec.flags[k, i] = NO_MEAS
                    continue
                act = active[k, i]
                m = _measure(kinds[i], xs[i], j, se, me)
                wt.alarmed[i] = False
                if wi[i, WI_ON] != 0:
                    wm = me         # (in reset mode the local's prediction is the master's)
                    if not reset:
                        wm = mw
                        _measure(kinds[i], xp, j, se, mw)
                    armed = act and times[k] >= wf[i, WF_TARM]    # connected and armed
                    mz = _whiten(kinds[i], j, wm, m, fu, se, up)
                    if _watch(kinds[i], i, j, armed, mz, up.y, ws, wt):
                        act = False     # an alarm: this measurement stays out, and so does i
                        wt.alarmed[i] = True
                        stop = True
                if full:
                    nis = _update_sized(st, i, me, m, gate[i], act, up)
                else:
                    nis = _info_sized(fu, i, me, m, gate[i], act, up)
                rec.nis[k, i] = nis
                if not act:
                    rec.flags[k, i] = ISOLATED
                elif nis > gate[i]:
                    rec.flags[k, i] = REJECTED
                elif math.isnan(nis):
                    return -2
                else:
                    rec.flags[k, i] = UPDATED
            # master fusion of the connected locals
            any_used = False
            ssum = 0.0
            for i in range(ns):
                use[i] = active[k, i]
                any_used = any_used or use[i]
                if use[i]:
                    ssum += shares[i]
            if not any_used:
                for a in range(6):
                    xm[a] = xp[a]
                    for b in range(6):
                        Pm[a, b] = Pp[a, b]
            elif full:
                if not _fuse(st, fu):
                    return -2
            elif not _fuse_information(st, fu, ssum):
                return -2
        if stop and k + 1 < times.shape[0]:
            for i in range(ns):
                if wt.alarmed[i]:
                    active[k + 1, i] = False     # switched out from the next epoch
        for i in range(ns):      # the re-admission grid: stop where the loop may readmit
            if wi[i, WI_OUT] and (k + 1) % wi[i, WI_CHECK] == 0 and \
                    _quiet(i, ws, _ys(kinds[i], ws)):
                stop = True
        r = rec.pos[k]
        if r >= 0:
            for a in range(6):
                rec.x[r, a] = xm[a]
                for b in range(6):
                    rec.P[r, a, b] = Pm[a, b]
            for i in range(ns):
                for a in range(6):
                    rec.xl[r, i, a] = xs[i, a]
                    rec.Pl[r, i, a] = Ps[i, a, a]
        # reset: share the master among the locals connected at the next epoch (the locals
        # themselves are rebuilt from the master by the next time update; written at the end)
        if reset:
            kn = k + 1 if k + 1 < times.shape[0] else k
            tot = 0.0
            for i in range(ns):
                if active[kn, i]:
                    tot += pl.beta[i]
            for i in range(ns):
                shares[i] = pl.beta[i] / tot if active[kn, i] else 1.0
                inv_sh[i] = 1.0 / shares[i]
            if k == k1 - 1 or stop:
                for i in range(ns):
                    for a in range(6):
                        xs[i, a] = xm[a]
                        for b in range(6):
                            Ps[i, a, b] = Pm[a, b] * inv_sh[i]
        if stop:
            return k
    return -1
