"""Quaternion differentiation (the paper's ref. [22]): gyro faults from star-tracker rates.

The body rate is estimated from a least-squares slope of the star-tracker quaternions
over a trailing window (:func:`quaternion_rate`) and compared with the gyros
(:func:`qdiff_fault_estimates`). The method's model has no star-tracker fault, so a
star-tracker fault is blamed on the gyros (the paper's Fig. 6); its verdict is
:func:`xnavlab.attitude.diagnosis.qdiff_decide`.

Rates in rad/s, times in s.
"""

from __future__ import annotations

import numpy as np

from xnavlab.attitude._checks import check_quaternion
from xnavlab.core.quaternions import xi_matrix
from xnavlab.core.validate import check_finite_array, check_real

__all__ = [
    "quaternion_rate",
    "qdiff_fault_estimates",
]


def _window(dt, window_s):
    # dt from 1 us (faster than any star tracker; window_s / dt stays a countable number of
    # samples: a subnormal dt made it inf) to 10 s.
    dt = check_real("dt", dt, 1e-6, 10.0)
    window_s = check_real("window_s", window_s, 2.0 * dt, 86400.0)
    return dt, int(round(window_s / dt))


def quaternion_rate(q_meas, dt, window_s=10.0):
    """Body rate from star-tracker quaternions by numerical differentiation (ref. [22]).

    Over a trailing window of ``M + 1`` samples (``M = window_s/dt``) the quaternion
    components are fitted with a straight line; with ``q_dot = 1/2 Xi(q) w`` and
    ``Xi^T Xi = I3``, ``w = 2 Xi(q_mid)^T q_dot`` at the window's middle (the paper's
    ref. [22] differentiates the quaternions; the least-squares slope is our choice to
    tame the noise). Signs are first made continuous.

    Parameters
    ----------
    q_meas : array_like, shape (..., n, 4)
        Star-tracker quaternions at interval ``dt``, unit (norm 1 to 1e-6: a scaled one
        would scale the rate; a star tracker reports unit ones).
    dt : float
        Sample interval, s, in [1e-6, 10].
    window_s : float
        Window length, s, >= 2 dt.

    Returns
    -------
    ndarray, shape (..., n - M, 3)
        Rate at times ``t[M:] - window_s/2`` (the estimate for the window ending at
        sample ``k`` is ready at ``t[k]``), rad/s.

    Examples
    --------
    >>> from xnavlab.attitude.motion import truth_motion
    >>> t, w, q = truth_motion(201, 0.1, wobble_deg_s=0.0)
    >>> wq = quaternion_rate(q, 0.1, 10.0)
    >>> bool(np.allclose(wq, w[0], atol=1e-9))
    True
    """
    q = check_quaternion("q_meas", check_finite_array("q_meas", q_meas, shape=(None, 4)))  # unit rows
    dt, M = _window(dt, window_s)
    n = q.shape[-2]
    if n <= M:
        raise ValueError(f"q_meas must have more than window_s/dt = {M} samples, got {n}")
    # continuous signs: flip a sample whose dot product with the previous one is negative
    flips = np.sum(q[..., 1:, :] * q[..., :-1, :], axis=-1) < 0.0
    sign = np.concatenate([np.ones(q.shape[:-2] + (1,)), np.where(flips, -1.0, 1.0)], -1)
    q = q * np.cumprod(sign, axis=-1)[..., None]
    j = np.arange(n, dtype=float)[:, None]
    c0 = np.cumsum(q, axis=-2)
    c1 = np.cumsum(j * q, axis=-2)
    pad = np.zeros(q.shape[:-2] + (1, 4))
    c0 = np.concatenate([pad, c0], axis=-2)
    c1 = np.concatenate([pad, c1], axis=-2)
    s0 = c0[..., M + 1:, :] - c0[..., : n - M, :]  # sum over the window
    s1 = c1[..., M + 1:, :] - c1[..., : n - M, :]
    jbar = (np.arange(M, n) - 0.5 * M)[:, None]
    sxx = M * (M + 1) * (M + 2) / 12.0
    qdot = (s1 - jbar * s0) / (sxx * dt)  # least-squares slope
    qmid = s0 / (M + 1)
    qmid = qmid / np.linalg.norm(qmid, axis=-1, keepdims=True)
    return 2.0 * np.einsum("...ji,...j->...i", xi_matrix(qmid), qdot)  # w = 2 Xi^T q_dot


def qdiff_fault_estimates(omega_g, q_meas, dt, window_s=10.0):
    """Gyro fault estimates of the quaternion-differentiation method (ref. [22]), rad/s.

    ``f_hat = mean(w_g1 over the window) - w_hat`` with ``w_hat`` from
    :func:`quaternion_rate`: the gyros minus the star-tracker rate. The method's model
    has no star-tracker fault, so anything the star tracker does lands on the gyros.
    The estimate still contains the constant drifts; subtract a reference.

    Parameters
    ----------
    omega_g : array_like, shape (..., n, 4) or (..., n, 3)
        Gyro outputs at interval ``dt`` (only the orthogonal triad is used), rad/s.
    q_meas : array_like, shape (..., n, 4)
    dt, window_s : float
        As in :func:`quaternion_rate`.

    Returns
    -------
    ndarray, shape (..., n - M, 3)

    Examples
    --------
    >>> from xnavlab.attitude.motion import truth_motion
    >>> t, w, q = truth_motion(201, 0.1, wobble_deg_s=0.0)
    >>> f = qdiff_fault_estimates(w + 1e-4, q, 0.1, 10.0)
    >>> bool(np.allclose(f, 1e-4, atol=1e-9))
    True
    """
    wg = check_finite_array("omega_g", omega_g)
    if wg.ndim < 2 or wg.shape[-1] not in (3, 4):
        raise ValueError(f"omega_g must have shape (..., n, 3) or (..., n, 4), got {wg.shape}")
    wq = quaternion_rate(q_meas, dt, window_s)
    M = _window(dt, window_s)[1]
    n = wg.shape[-2]
    if np.shape(q_meas)[-2] != n:
        raise ValueError(f"q_meas must have as many samples as omega_g ({n}), got {np.shape(q_meas)[-2]}")
    c = np.concatenate([np.zeros(wg.shape[:-2] + (1, 3)), np.cumsum(wg[..., :3], -2)], -2)
    mean = (c[..., M:n, :] - c[..., : n - M, :]) / M  # gyro intervals k-M .. k-1
    return mean - wq
