"""The attitude filter bank compiled: the EKF steps of :mod:`xnavlab.attitude.ekf` over a batch.

Plumbing of :mod:`xnavlab.attitude.simulation`: :func:`filter_bank_compiled` runs the same
predict and update as :func:`~xnavlab.attitude._ekf_steps.ekf_predict_unchecked` and
:func:`~xnavlab.attitude._ekf_steps.ekf_update_unchecked` (paper eqs. (12), (30)-(34)), in
loops numba compiles (``cache=True``: once per environment, ``python -m xnavlab warmup`` does
it at set-up): 0.04 s a run of 1,000 steps, against 0.6-1.8 s for numpy's small-array calls
(chapter 11's slider runs one at each move). The numpy steps stay the reference the book
teaches; a test holds the two together to 1e-10 of each array's scale. The file is
self-contained (numba keys its cache by this file's source).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["filter_bank_compiled"]


@njit(cache=True)
def _predict(x, P, w_g, dt, gyro_cov, drift_cov):
    """One predict step of one filter, in place: paper eqs. (12), (30), (31)."""
    q0, q1, q2, q3 = x[0], x[1], x[2], x[3]
    w0, w1, w2 = w_g[0] - x[4], w_g[1] - x[5], w_g[2] - x[6]  # paper eq. (18)
    half = 0.5 * math.sqrt(w0 * w0 + w1 * w1 + w2 * w2) * dt
    c = math.cos(half)  # paper eq. (11)
    s = 0.5 * dt * (math.sin(half) / half if half > 0.0 else 1.0)  # sin(half) / |w|
    a0, a1, a2 = s * w0, s * w1, s * w2
    F = np.zeros((7, 7))
    # Phi = c I4 + s Omega(n), Omega(w) = [[-[w x], w], [-w^T, 0]] (paper eq. (12))
    F[0, 0] = c
    F[0, 1] = a2
    F[0, 2] = -a1
    F[0, 3] = a0
    F[1, 0] = -a2
    F[1, 1] = c
    F[1, 2] = a0
    F[1, 3] = a1
    F[2, 0] = a1
    F[2, 1] = -a0
    F[2, 2] = c
    F[2, 3] = a2
    F[3, 0] = -a0
    F[3, 1] = -a1
    F[3, 2] = -a2
    F[3, 3] = c
    # G = -dt/2 Xi(q), Xi(q) = [[q4 I3 + [rho x]], [-rho^T]] (paper eqs. (20)-(23))
    g = -0.5 * dt
    F[0, 4] = g * q3
    F[0, 5] = -g * q2
    F[0, 6] = g * q1
    F[1, 4] = g * q2
    F[1, 5] = g * q3
    F[1, 6] = -g * q0
    F[2, 4] = -g * q1
    F[2, 5] = g * q0
    F[2, 6] = g * q3
    F[3, 4] = -g * q0
    F[3, 5] = -g * q1
    F[3, 6] = -g * q2
    for i in range(4, 7):
        F[i, i] = 1.0
    q = (q0, q1, q2, q3)
    for i in range(4):  # paper eq. (30): q = Phi q
        x[i] = F[i, 0] * q[0] + F[i, 1] * q[1] + F[i, 2] * q[2] + F[i, 3] * q[3]
    FP = np.zeros((7, 7))  # paper eq. (31): P = F P F^T + G Q G^T, in loops (no BLAS call
    for i in range(7):  # for 7 x 7: numba compiles these in seconds, not a minute)
        for k in range(7):
            if F[i, k] != 0.0:
                for j in range(7):
                    FP[i, j] += F[i, k] * P[k, j]
    for i in range(7):
        for j in range(7):
            acc = 0.0
            for k in range(7):
                acc += FP[i, k] * F[j, k]
            P[i, j] = acc
    GQ = np.zeros((4, 3))
    for i in range(4):
        for j in range(3):
            for k in range(3):
                GQ[i, j] += F[i, 4 + k] * gyro_cov[k, j]
    for i in range(4):
        for j in range(4):
            acc = 0.0
            for k in range(3):
                acc += GQ[i, k] * F[j, 4 + k]
            P[i, j] += acc
    for i in range(3):
        for j in range(3):
            P[4 + i, 4 + j] += drift_cov[i, j]


@njit(cache=True)
def _update(x, P, q_meas, R):
    """One update step of one filter, in place: paper eqs. (32)-(34), as ekf_update."""
    dot = x[0] * q_meas[0] + x[1] * q_meas[1] + x[2] * q_meas[2] + x[3] * q_meas[3]
    sign = -1.0 if dot < 0.0 else 1.0
    nu = np.empty(4)
    for i in range(4):
        nu[i] = sign * q_meas[i] - x[i]  # innovation, paper eqs. (24), (29)
    L = np.zeros((4, 4))  # S = C P C^T + R = L L^T (Cholesky; S is SPD)
    for i in range(4):
        for j in range(i + 1):
            acc = P[i, j] + R[i, j]
            for k in range(j):
                acc -= L[i, k] * L[j, k]
            L[i, j] = math.sqrt(acc) if i == j else acc / L[j, j]
    Kt = np.empty((4, 7))  # K^T = S^-1 C P (paper eq. (32)): L y = P[:4], then L^T K^T = y
    for c in range(7):
        for i in range(4):
            acc = P[i, c]
            for k in range(i):
                acc -= L[i, k] * Kt[k, c]
            Kt[i, c] = acc / L[i, i]
        for i in range(3, -1, -1):
            acc = Kt[i, c]
            for k in range(i + 1, 4):
                acc -= L[k, i] * Kt[k, c]
            Kt[i, c] = acc / L[i, i]
    for i in range(7):  # paper eq. (33): x = x + K nu
        x[i] += Kt[0, i] * nu[0] + Kt[1, i] * nu[1] + Kt[2, i] * nu[2] + Kt[3, i] * nu[3]
    P1 = np.empty((7, 7))  # paper eq. (34): P = (I7 - K C) P
    for i in range(7):
        for j in range(7):
            P1[i, j] = P[i, j] - (Kt[0, i] * P[0, j] + Kt[1, i] * P[1, j]
                                  + Kt[2, i] * P[2, j] + Kt[3, i] * P[3, j])
    for i in range(7):
        for j in range(7):
            P[i, j] = 0.5 * (P1[i, j] + P1[j, i])  # symmetric against round-off
    norm = math.sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2] + x[3] * x[3])
    for i in range(4):
        x[i] /= norm


@njit(cache=True)
def _bank(x, P, w_tilde, q_meas, dt, gyro_cov, drift_cov, R, q_hat, d_hat, P_dd):
    B, n, F = q_hat.shape[0], q_hat.shape[1], q_hat.shape[2]
    for b in range(B):
        for f in range(F):
            xf, Pf = x[b, f], P[b, f]
            for k in range(n):
                if k:
                    _predict(xf, Pf, w_tilde[b, k - 1, f], dt, gyro_cov[f], drift_cov[f])
                _update(xf, Pf, q_meas[b, k], R)
                q_hat[b, k, f] = xf[:4]
                d_hat[b, k, f] = xf[4:]
                P_dd[b, k, f] = Pf[4:, 4:]


def filter_bank_compiled(x, P, w_tilde, q_meas, dt, gyro_cov, drift_cov, R):
    """Run ``F`` attitude EKFs over ``B`` runs of ``n`` samples, compiled.

    The caller guarantees checked inputs (:func:`xnavlab.attitude.simulation.diagnose_batch`
    checks a batch once): finite float arrays of the shapes below, ``dt > 0``, SPD covariances.

    Parameters
    ----------
    x : ndarray, shape (B, F, 7)
        Initial states ``[q (scalar last); b (rad/s)]``.
    P : ndarray, shape (B, F, 7, 7)
        Initial covariances.
    w_tilde : ndarray, shape (B, n, F, 3)
        Each filter's gyro rates, rad/s.
    q_meas : ndarray, shape (B, n, 4)
        Star-tracker quaternions (every filter takes the same).
    dt : float
        Sample interval, s.
    gyro_cov, drift_cov : ndarray, shape (F, 3, 3)
        Gyro-noise covariance per sample and drift random walk per step, (rad/s)^2.
    R : ndarray, shape (4, 4)
        Measurement covariance.

    Returns
    -------
    q_hat : ndarray, shape (B, n, F, 4)
    d_hat : ndarray, shape (B, n, F, 3)
        Drift estimates, rad/s.
    P_dd : ndarray, shape (B, n, F, 3, 3)
        Drift covariance blocks, (rad/s)^2.

    Examples
    --------
    >>> from xnavlab.attitude.motion import DEFAULT_Q0
    >>> x = np.concatenate([DEFAULT_Q0, np.zeros(3)])[None, None]
    >>> P = 1e-8 * np.eye(7)[None, None]
    >>> q = np.broadcast_to(DEFAULT_Q0, (1, 3, 4))
    >>> out = filter_bank_compiled(x, P, np.zeros((1, 3, 1, 3)), q, 0.1, np.zeros((1, 3, 3)),
    ...                            np.zeros((1, 3, 3)), 1e-8 * np.eye(4))
    >>> [a.shape for a in out]
    [(1, 3, 1, 4), (1, 3, 1, 3), (1, 3, 1, 3, 3)]
    """
    B, n = q_meas.shape[:2]
    F = x.shape[1]
    q_hat = np.empty((B, n, F, 4))
    d_hat = np.empty((B, n, F, 3))
    P_dd = np.empty((B, n, F, 3, 3))
    c = np.ascontiguousarray
    _bank(np.array(x, dtype=float), np.array(P, dtype=float), c(w_tilde, dtype=float),
          c(q_meas, dtype=float), float(dt), c(gyro_cov, dtype=float), c(drift_cov, dtype=float),
          c(R, dtype=float), q_hat, d_hat, P_dd)
    return q_hat, d_hat, P_dd
