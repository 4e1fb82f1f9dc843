"""Compiled (numba) kernels of the federated Mars navigation run.

These are line-for-line translations of the readable numpy loop in
:mod:`xnavlab.mars.scenarios` (which is built from :mod:`xnavlab.core.filters`,
:mod:`xnavlab.mars.sensors`, :mod:`xnavlab.core.federated` and :mod:`xnavlab.mars.dynamics`),
written with explicit loops over small fixed-size arrays so that one epoch of three
EKFs and the fusion costs microseconds. Both paths consume identical precomputed
inputs (truth, ephemeris tables, noisy measurements) and give the same estimates to
rounding; the tests compare them.

Compiled with ``cache=True``: the first call in a fresh environment compiles (tens of
seconds) and stores the machine code in ``__pycache__``; later processes load it.

Private module: the public entry point is :func:`xnavlab.mars.scenarios.run`.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from xnavlab.core.constants import GM_SUN, C

__all__ = ["run_epochs", "KIND_XNAV", "KIND_UV", "KIND_CNS"]

KIND_XNAV = 0
KIND_UV = 1
KIND_CNS = 2

_SHAPIRO = 2.0 * GM_SUN / C**3

# flags written per epoch and subsystem
NO_MEAS = 0
UPDATED = 1
REJECTED = 2  # innovation gate exceeded: time update only
ISOLATED = 3  # subsystem switched out: time update only


#: Preallocated scratch arrays (no allocation inside the epoch loop).
Scratch = namedtuple("Scratch", [
    "tb", "a3", "k46", "y6", "G", "G2", "Phi", "T6",
    "PHt", "S", "Lm", "ym", "K", "row", "A6", "KR", "u3", "Ac",
    "d6", "Y6", "yv6", "Ci", "Yi", "Cf", "L6", "e6", "xc", "Pc",
])


@njit(cache=True)
def _scratch(nb, m, kc):
    return Scratch(
        np.empty((max(nb, 1), 3)), np.empty(3), np.empty((4, 6)), np.empty(6),
        np.empty((3, 3)), np.empty((3, 3)), np.zeros((6, 6)), np.empty((6, 6)),
        np.empty((6, m)), np.empty((m, m)), np.zeros((m, m)), np.empty(m), np.empty((6, m)),
        np.empty(m), np.empty((6, 6)), np.empty((6, m)), np.empty(3), np.empty((max(kc, 1), 3)),
        np.empty(6), np.empty((6, 6)), np.empty(6), np.empty((6, 6)), np.empty((6, 6)),
        np.empty((6, 6)), np.zeros((6, 6)), np.empty(6), np.empty(6), np.empty((6, 6)),
    )


# ----------------------------------------------------------------------- dynamics


@njit(cache=True, inline="always")
def _third_body_positions(t, tb_t0, tb_step, tb_pos, tb_vel, out):
    """Cubic Hermite interpolation of the tabulated third bodies (as ThirdBodyTable)."""
    nk = tb_pos.shape[0]
    x = (t - tb_t0) / tb_step
    i = int(x)
    if i > nk - 2:
        i = nk - 2
    s = x - i
    h = tb_step
    s2 = s * s
    s3 = s2 * s
    h00 = 2 * s3 - 3 * s2 + 1
    h10 = s3 - 2 * s2 + s
    h01 = -2 * s3 + 3 * s2
    h11 = s3 - s2
    for b in range(tb_pos.shape[1]):
        for j in range(3):
            out[b, j] = (h00 * tb_pos[i, b, j] + h10 * h * tb_vel[i, b, j]
                         + h01 * tb_pos[i + 1, b, j] + h11 * h * tb_vel[i + 1, b, j])


@njit(cache=True, inline="always")
def _accel(t, r, gm_mars, tb_t0, tb_step, tb_pos, tb_vel, tb_gm, work, out):
    rn = math.sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2])
    k = -gm_mars / (rn * rn * rn)
    for j in range(3):
        out[j] = k * r[j]
    nb = tb_pos.shape[1]
    if nb == 0:
        return
    _third_body_positions(t, tb_t0, tb_step, tb_pos, tb_vel, work)
    for b in range(nb):
        d0 = work[b, 0] - r[0]
        d1 = work[b, 1] - r[1]
        d2 = work[b, 2] - r[2]
        dn = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
        sn = math.sqrt(work[b, 0] ** 2 + work[b, 1] ** 2 + work[b, 2] ** 2)
        dn3 = dn * dn * dn
        sn3 = sn * sn * sn
        g = tb_gm[b]
        # a_k = mu_k [ (s - r)/|s - r|^3 - s/|s|^3 ]
        out[0] += g * (d0 / dn3 - work[b, 0] / sn3)
        out[1] += g * (d1 / dn3 - work[b, 1] / sn3)
        out[2] += g * (d2 / dn3 - work[b, 2] / sn3)


@njit(cache=True, inline="always")
def _rk4(x, t, dt, gm_mars, tb_t0, tb_step, tb_pos, tb_vel, tb_gm, out, work, a, k, y):
    """One classical Runge-Kutta step of r' = v, v' = a(t, r) (scratch: work, a, k, y)."""
    for j in range(6):
        y[j] = x[j]
    for stage in range(4):
        if stage == 0:
            ts = t
        elif stage == 3:
            ts = t + dt
        else:
            ts = t + 0.5 * dt
        if stage > 0:
            c = dt if stage == 3 else 0.5 * dt
            for j in range(6):
                y[j] = x[j] + c * k[stage - 1, j]
        _accel(ts, y[:3], gm_mars, tb_t0, tb_step, tb_pos, tb_vel, tb_gm, work, a)
        for j in range(3):
            k[stage, j] = y[3 + j]
            k[stage, 3 + j] = a[j]
    for j in range(6):
        out[j] = x[j] + dt / 6.0 * (k[0, j] + 2.0 * k[1, j] + 2.0 * k[2, j] + k[3, j])


@njit(cache=True, inline="always")
def _transition(x, h, gm_mars, G, G2, Phi):
    """Phi = exp(F h) to fourth order at x, F = [[0, I], [G, 0]] (into Phi)."""
    # gravity gradient G = mu (3 r r^T / |r|^5 - I / |r|^3) at the start of the step
    rn2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2]
    rn = math.sqrt(rn2)
    for i in range(3):
        for j in range(3):
            G[i, j] = gm_mars * (3.0 * x[i] * x[j] / (rn2 * rn2 * rn)
                                 - (1.0 if i == j else 0.0) / (rn2 * rn))
    for i in range(3):
        for j in range(3):
            G2[i, j] = G[i, 0] * G[0, j] + G[i, 1] * G[1, j] + G[i, 2] * G[2, j]
    # [[I + G h^2/2 + G^2 h^4/24, I h + G h^3/6], [G h + G^2 h^3/6, same as top left]]
    h2 = h * h
    for i in range(3):
        for j in range(3):
            d = 1.0 if i == j else 0.0
            diag = d + G[i, j] * h2 / 2.0 + G2[i, j] * h2 * h2 / 24.0
            Phi[i, j] = diag
            Phi[3 + i, 3 + j] = diag
            Phi[i, 3 + j] = d * h + G[i, j] * h2 * h / 6.0
            Phi[3 + i, j] = G[i, j] * h + G2[i, j] * h2 * h / 6.0


@njit(cache=True, inline="always")
def _matmul6(A, B, out):
    """``out = A B`` for 6 x 6 matrices (``out`` must alias neither)."""
    for i in range(6):
        for j in range(6):
            acc = 0.0
            for m in range(6):
                acc += A[i, m] * B[m, j]
            out[i, j] = acc


@njit(cache=True, inline="always")
def _predict(x, P, t, dt, q, scale, max_step, gm_mars, tb_t0, tb_step, tb_pos, tb_vel, tb_gm,
             x_out, P_out, sc):
    """EKF time update over dt in n = ceil(dt / max_step) equal sub-steps.

    Each sub-step: one RK4 step of the state and the fourth-order transition matrix at
    its start; ``Phi = Phi_n ... Phi_1``; ``P = Phi P Phi^T + Q(dt) / scale``.
    """
    nsub = int(math.ceil(dt / max_step - 1e-9))
    if nsub < 1:
        nsub = 1
    h = dt / nsub
    Phi = sc.Phi
    _transition(x, h, gm_mars, sc.G, sc.G2, Phi)
    _rk4(x, t, h, gm_mars, tb_t0, tb_step, tb_pos, tb_vel, tb_gm, x_out,
         sc.tb, sc.a3, sc.k46, sc.y6)
    for sub in range(1, nsub):
        Ph = sc.A6
        _transition(x_out, h, gm_mars, sc.G, sc.G2, Ph)
        T = sc.T6
        _matmul6(Ph, Phi, T)
        for i in range(6):
            for j in range(6):
                Phi[i, j] = T[i, j]
        for j in range(6):
            sc.xc[j] = x_out[j]
        _rk4(sc.xc, t + sub * h, h, gm_mars, tb_t0, tb_step, tb_pos, tb_vel, tb_gm, x_out,
             sc.tb, sc.a3, sc.k46, sc.y6)
    # P = Phi P Phi^T + Q
    T = sc.T6
    _matmul6(Phi, P, T)
    q33 = q * dt * dt * dt / 3.0 / scale
    q22 = q * dt * dt / 2.0 / scale
    q11 = q * dt / scale
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
    # symmetric: mirror the upper triangle (P_out[3+i, i] gets q22 through P_out[i, 3+i])
    for i in range(6):
        for j in range(i + 1, 6):
            P_out[j, i] = P_out[i, j]


# ---------------------------------------------------------------------- linear algebra


@njit(cache=True, inline="always")
def _cholesky(A, n, L):
    """Lower Cholesky factor of the leading n x n block; returns False if not positive definite.

    The diagonal of ``L`` holds the *reciprocals* ``1 / L_ii`` (so that the solves
    multiply instead of divide).
    """
    for i in range(n):
        for j in range(i + 1):
            s = A[i, j]
            for k in range(j):
                s -= L[i, k] * L[j, k]
            if i == j:
                if s <= 0.0:
                    return False
                L[i, i] = 1.0 / math.sqrt(s)
            else:
                L[i, j] = s * L[j, j]
        for j in range(i + 1, n):
            L[i, j] = 0.0
    return True


@njit(cache=True, inline="always")
def _chol_solve(L, n, b):
    """Solve (L L^T) y = b in place for a vector b (L from :func:`_cholesky`)."""
    for i in range(n):
        s = b[i]
        for k in range(i):
            s -= L[i, k] * b[k]
        b[i] = s * L[i, i]
    for i in range(n - 1, -1, -1):
        s = b[i]
        for k in range(i + 1, n):
            s -= L[k, i] * b[k]
        b[i] = s * L[i, i]


@njit(cache=True, inline="always")
def _spd_inverse(A, n, out, L, e):
    """Inverse of a symmetric positive-definite matrix via Cholesky; False if it fails.

    ``A = L L^T``, ``A^-1 = L^-T L^-1``; ``L`` (n, n) is scratch (overwritten by
    ``L^-1``), ``e`` (n,) holds the reciprocal diagonal.
    """
    if not _cholesky(A, n, L):
        return False
    # L^-1 in place (lower triangular), column by column
    for i in range(n):
        e[i] = L[i, i]  # already 1 / L_ii
    for j in range(n):
        L[j, j] = e[j]
        for i in range(j + 1, n):
            s = 0.0
            for k in range(j, i):
                s -= L[i, k] * L[k, j]
            L[i, j] = s * e[i]
    # A^-1 = L^-T L^-1 (symmetric)
    for i in range(n):
        for j in range(i + 1):
            s = 0.0
            for k in range(i, n):
                s += L[k, i] * L[k, j]
            out[i, j] = s
            out[j, i] = s
    return True


# ------------------------------------------------------------------ measurement models


@njit(cache=True, inline="always")
def _h_xnav(x, rm, rs, n_, dist, z_pred, H):
    """Paper eq. (1) delays and eq. (4) rows for the spacecraft at rm + r."""
    R0 = rm[0] + x[0]
    R1 = rm[1] + x[1]
    R2 = rm[2] + x[2]
    Rn = math.sqrt(R0 * R0 + R1 * R1 + R2 * R2)
    b0, b1, b2 = -rs[0], -rs[1], -rs[2]
    bn = math.sqrt(b0 * b0 + b1 * b1 + b2 * b2)
    for i in range(n_.shape[0]):
        nr = n_[i, 0] * R0 + n_[i, 1] * R1 + n_[i, 2] * R2
        nb = n_[i, 0] * b0 + n_[i, 1] * b1 + n_[i, 2] * b2
        D = dist[i]
        u = nr + Rn
        w = nb + bn
        z_pred[i] = (nr / C + (nr * nr - Rn * Rn) / (2.0 * C * D)
                     + _SHAPIRO * math.log(abs(u / w + 1.0)))  # paper eq. (1)
        Rv = (R0, R1, R2)
        for j in range(3):
            H[i, j] = (n_[i, j] / C + (nr * n_[i, j] - Rv[j]) / (C * D)
                       + _SHAPIRO * (n_[i, j] + Rv[j] / Rn) / (u + w))  # paper eq. (4)
            H[i, 3 + j] = 0.0


@njit(cache=True, inline="always")
def _h_uv(x, z_pred, H):
    """Paper eq. (5): [|r|, -r/|r|] and its Jacobian."""
    rn = math.sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2])
    z_pred[0] = rn
    for j in range(3):
        e = x[j] / rn
        z_pred[1 + j] = -e
        H[0, j] = e
        H[0, 3 + j] = 0.0
    inv = 1.0 / rn
    for i in range(3):
        for j in range(3):
            H[1 + i, j] = -((1.0 if i == j else 0.0) - x[i] * x[j] * inv * inv) * inv
            H[1 + i, 3 + j] = 0.0


@njit(cache=True, inline="always")
def _h_cns(x, star, sig_s, sig_h, z_pred, H, R, u, A):
    """Paper eq. (6) angles, Jacobian rows a_j/|r| and the correlated R (scratch u, A)."""
    k = star.shape[0]
    rn = math.sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2])
    for j in range(3):
        u[j] = -x[j] / rn
    for i in range(k):
        us = u[0] * star[i, 0] + u[1] * star[i, 1] + u[2] * star[i, 2]
        c0 = u[1] * star[i, 2] - u[2] * star[i, 1]
        c1 = u[2] * star[i, 0] - u[0] * star[i, 2]
        c2 = u[0] * star[i, 1] - u[1] * star[i, 0]
        z_pred[i] = math.atan2(math.sqrt(c0 * c0 + c1 * c1 + c2 * c2), us)  # paper eq. (6)
        tn = 0.0
        for j in range(3):
            A[i, j] = star[i, j] - us * u[j]
            tn += A[i, j] * A[i, j]
        tn = math.sqrt(tn)
        for j in range(3):
            A[i, j] /= tn
            H[i, j] = A[i, j] / rn
            H[i, 3 + j] = 0.0
    for i in range(k):
        for j in range(k):
            R[i, j] = sig_h * sig_h * (A[i, 0] * A[j, 0] + A[i, 1] * A[j, 1] + A[i, 2] * A[j, 2])
        R[i, i] += sig_s * sig_s


@njit(cache=True, inline="always")
def _update(x, P, nu, H, R, m, gate, do_update, sc):
    """Joseph-form EKF update in place; returns the NIS (NaN if S is not PD).

    The update is applied only when ``do_update`` and NIS <= gate. The three sensors'
    Jacobians have zero velocity columns (paper eqs. (4)-(6)), so only ``H[:, :3]``
    is used, and ``A = I - K H`` has identity velocity columns: the Joseph product
    ``A P A^T`` is formed as ``T = P - K (P H^T)^T``, ``T A^T = T - (T H^T) K^T``.
    """
    # S = H P H^T + R
    PHt = sc.PHt
    for i in range(6):
        for j in range(m):
            PHt[i, j] = P[i, 0] * H[j, 0] + P[i, 1] * H[j, 1] + P[i, 2] * H[j, 2]
    S = sc.S
    for i in range(m):
        for j in range(i + 1):
            v = (R[i, j] + H[i, 0] * PHt[0, j] + H[i, 1] * PHt[1, j] + H[i, 2] * PHt[2, j])
            S[i, j] = v
            S[j, i] = v
    L = sc.Lm
    if not _cholesky(S, m, L):
        return np.nan
    y = sc.ym
    for i in range(m):
        y[i] = nu[i]
    _chol_solve(L, m, y)
    nis = 0.0
    for i in range(m):
        nis += nu[i] * y[i]
    if not do_update or nis > gate:
        return nis
    # K = P H^T S^-1 (row by row: solve S k_i = (P H^T)_i)
    K = sc.K
    row = sc.row
    for i in range(6):
        for j in range(m):
            row[j] = PHt[i, j]
        _chol_solve(L, m, row)
        for j in range(m):
            K[i, j] = row[j]
    # x+ = x- + K nu
    for i in range(6):
        s = 0.0
        for j in range(m):
            s += K[i, j] * nu[j]
        x[i] += s
    # P+ = (I - K H) P (I - K H)^T + K R K^T  (Joseph form)
    T = sc.T6  # T = (I - K H) P = P - K (P H^T)^T
    for i in range(6):
        for j in range(6):
            s = P[i, j]
            for a in range(m):
                s -= K[i, a] * PHt[j, a]
            T[i, j] = s
    W = sc.KR  # W = K R - T H^T, so that P+ = T + W K^T
    for i in range(6):
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
            P[i, j] = s
            P[j, i] = s
    return nis


# ----------------------------------------------------------------------------- fusion


@njit(cache=True, inline="always")
def _fuse(xs, Ps, use, x_out, P_out, sc):
    """Information-form fusion of the local estimates with use[i] True.

    P_f = (sum P_i^-1)^-1, x_f = P_f sum P_i^-1 x_i, computed on Jacobi-scaled
    covariances and on deviations from the first used estimate (for precision).
    Returns False if no estimate is used or a matrix is not positive definite.
    """
    ns = xs.shape[0]
    ref = -1
    for i in range(ns):
        if use[i]:
            ref = i
            break
    if ref < 0:
        return False
    d = sc.d6
    for j in range(6):
        d[j] = 1.0 / math.sqrt(Ps[ref, j, j])  # Jacobi scaling D^-1
    Y = sc.Y6
    y = sc.yv6
    for a in range(6):
        y[a] = 0.0
        for b in range(6):
            Y[a, b] = 0.0
    Ci = sc.Ci
    Yi = sc.Yi
    for i in range(ns):
        if not use[i]:
            continue
        for a in range(6):
            for b in range(6):
                Ci[a, b] = Ps[i, a, b] * d[a] * d[b]
        if not _spd_inverse(Ci, 6, Yi, sc.L6, sc.e6):
            return False
        for a in range(6):
            for b in range(6):
                Y[a, b] += Yi[a, b]
        for a in range(6):
            s = 0.0
            for b in range(6):
                s += Yi[a, b] * (xs[i, b] - xs[ref, b]) * d[b]
            y[a] += s
    Cf = sc.Cf
    if not _spd_inverse(Y, 6, Cf, sc.L6, sc.e6):
        return False
    for a in range(6):
        s = 0.0
        for b in range(6):
            s += Cf[a, b] * y[b]
        x_out[a] = xs[ref, a] + s / d[a]
        for b in range(6):
            P_out[a, b] = Cf[a, b] / (d[a] * d[b])
    return True


# ---------------------------------------------------------------------------- the run


@njit(cache=True)
def run_epochs(k0, k1, times, xs, Ps, shares, xm, Pm, q, max_step, gm_mars,
               tb_t0, tb_step, tb_pos, tb_vel, tb_gm,
               kinds, meas_idx, active, beta, reset, gate,
               z_x, rm_x, rs_x, n_x, d_x, sig_x,
               z_u, sig_r, sig_u,
               z_c, stars_c, sig_s, sig_h,
               rec_pos, rec_x, rec_P, rec_xl, rec_Pl, nis_out, flag_out):
    """Run epochs ``k0 <= k < k1`` of the federated filter, updating the state in place.

    State: ``xs`` (ns, 6) and ``Ps`` (ns, 6, 6) local estimates, ``shares`` (ns,) the
    information share each local carries, ``xm`` (6,) and ``Pm`` (6, 6) the master.
    ``rec_pos[k]`` is the record row of epoch k or -1. Returns False on a numerical
    failure (a covariance lost positive definiteness).
    """
    ns = xs.shape[0]
    m_max = max(4, n_x.shape[0], stars_c.shape[0])
    sc = _scratch(tb_pos.shape[1], m_max, stars_c.shape[0])
    zp = np.empty(m_max)
    nu = np.empty(m_max)
    H = np.zeros((m_max, 6))
    R = np.zeros((m_max, m_max))
    xtmp = np.empty(6)
    Ptmp = np.empty((6, 6))
    use = np.zeros(ns, dtype=np.bool_)
    for k in range(k0, k1):
        if k > 0:
            tp = times[k - 1]
            dt = times[k] - tp
            # master time update (full Q)
            _predict(xm, Pm, tp, dt, q, 1.0, max_step, gm_mars, tb_t0, tb_step, tb_pos, tb_vel, tb_gm,
                     xtmp, Ptmp, sc)
            if reset:
                # after a reset every local equals the master scaled by 1/share, and the time
                # update commutes with that scaling: P_i- = (Phi P_f Phi^T + Q) / share_i
                for i in range(ns):
                    for a in range(6):
                        xs[i, a] = xtmp[a]
                        for b in range(6):
                            Ps[i, a, b] = Ptmp[a, b] / shares[i]
            else:
                for i in range(ns):
                    x_in = sc.xc
                    P_in = sc.Pc
                    for a in range(6):
                        x_in[a] = xs[i, a]
                        for b in range(6):
                            P_in[a, b] = Ps[i, a, b]
                    _predict(x_in, P_in, tp, dt, q, shares[i], max_step, gm_mars, tb_t0, tb_step, tb_pos,
                             tb_vel, tb_gm, xs[i], Ps[i], sc)
            for a in range(6):
                xm[a] = xtmp[a]
                for b in range(6):
                    Pm[a, b] = Ptmp[a, b]
            # measurement updates
            for i in range(ns):
                j = meas_idx[k, i]
                if j < 0:
                    flag_out[k, i] = NO_MEAS
                    continue
                kind = kinds[i]
                if kind == KIND_XNAV:
                    m = n_x.shape[0]
                    _h_xnav(xs[i], rm_x[j], rs_x[j], n_x, d_x, zp, H)
                    for a in range(m):
                        nu[a] = z_x[j, a] - zp[a]
                        for b in range(m):
                            R[a, b] = 0.0
                        R[a, a] = sig_x[a] * sig_x[a]
                elif kind == KIND_UV:
                    m = 4
                    _h_uv(xs[i], zp, H)
                    for a in range(m):
                        nu[a] = z_u[j, a] - zp[a]
                        for b in range(m):
                            R[a, b] = 0.0
                    R[0, 0] = sig_r * sig_r
                    for a in range(1, 4):
                        R[a, a] = sig_u * sig_u
                else:
                    m = stars_c.shape[0]
                    _h_cns(xs[i], stars_c, sig_s, sig_h, zp, H, R, sc.u3, sc.Ac)
                    for a in range(m):
                        nu[a] = z_c[j, a] - zp[a]
                nis = _update(xs[i], Ps[i], nu, H, R, m, gate[i], active[k, i], sc)
                nis_out[k, i] = nis
                if not active[k, i]:
                    flag_out[k, i] = ISOLATED
                elif nis > gate[i]:
                    flag_out[k, i] = REJECTED
                elif math.isnan(nis):
                    return False
                else:
                    flag_out[k, i] = UPDATED
            # master fusion of the connected locals
            for i in range(ns):
                use[i] = active[k, i]
            if _fuse(xs, Ps, use, xtmp, Ptmp, sc):
                for a in range(6):
                    xm[a] = xtmp[a]
                    for b in range(6):
                        Pm[a, b] = Ptmp[a, b]
            else:
                any_used = False
                for i in range(ns):
                    any_used = any_used or use[i]
                if any_used:
                    return False
        r = rec_pos[k]
        if r >= 0:
            for a in range(6):
                rec_x[r, a] = xm[a]
                for b in range(6):
                    rec_P[r, a, b] = Pm[a, b]
            for i in range(ns):
                for a in range(6):
                    rec_xl[r, i, a] = xs[i, a]
                    rec_Pl[r, i, a] = Ps[i, a, a]
        # reset: share the master among the locals connected at the next epoch
        if reset:
            kn = k + 1 if k + 1 < times.shape[0] else k
            tot = 0.0
            for i in range(ns):
                if active[kn, i]:
                    tot += beta[i]
            for i in range(ns):
                shares[i] = beta[i] / tot if active[kn, i] else 1.0
                for a in range(6):
                    xs[i, a] = xm[a]
                    for b in range(6):
                        Ps[i, a, b] = Pm[a, b] / shares[i]
    return True
