"""The attitude EKF's predict and update steps without input checks, for the inner loops.

Plumbing of :mod:`xnavlab.attitude`: :func:`xnavlab.attitude.ekf.ekf_predict` and
:func:`xnavlab.attitude.ekf.ekf_update` check their inputs and call these, as does the
:class:`~xnavlab.attitude.ekf.AttitudeEKF` class. The simulations' filter bank runs the same
steps compiled (``_bank_kernel``), held to these by a test. Paper eqs. (30)-(34) as in
:mod:`xnavlab.attitude.ekf`.
"""

from __future__ import annotations

import numpy as np

from xnavlab.core.quaternions import kinematics_matrix_unchecked, xi_matrix_unchecked

__all__ = ["ekf_predict_unchecked", "ekf_update_unchecked"]


def ekf_predict_unchecked(x, P, w_g, dt, gyro_cov, drift_cov):
    """:func:`~xnavlab.attitude.ekf.ekf_predict` without the input checks, for loops over checked batches.

    The same step, paper eqs. (30)-(31). The caller guarantees what
    :func:`~xnavlab.attitude.ekf.ekf_predict`
    checks: finite arrays of the shapes below, a non-zero quaternion part and ``dt > 0``;
    the covariances must be arrays (no scalar shorthand).

    Parameters
    ----------
    x : ndarray, shape (..., 7)
        ``[q (scalar last); b (rad/s)]``.
    P : ndarray, shape (..., 7, 7)
    w_g : ndarray, shape (..., 3)
        Gyro rates driving the filter, rad/s.
    dt : float
        Sample interval, s.
    gyro_cov, drift_cov : ndarray, shape (..., 3, 3)
        Gyro-noise covariance per sample and drift random-walk covariance per step,
        (rad/s)^2.

    Returns
    -------
    x : ndarray, shape (..., 7)
    P : ndarray, shape (..., 7, 7)

    Examples
    --------
    >>> from xnavlab.attitude.ekf import ekf_init, ekf_predict
    >>> from xnavlab.attitude.motion import DEFAULT_Q0
    >>> x0, P0 = ekf_init(DEFAULT_Q0, attitude_sigma=1e-4, drift_sigma=1e-4)
    >>> args = (x0, P0, np.array([1e-3, 0.0, 0.0]), 0.1, 1e-12 * np.eye(3), np.zeros((3, 3)))
    >>> bool(np.array_equal(ekf_predict_unchecked(*args)[1], ekf_predict(*args)[1]))
    True
    """
    q, b = x[..., :4], x[..., 4:]
    w = w_g - b  # paper eq. (18): w = w_g1 - b - v_g1, noise-free part
    phi = kinematics_matrix_unchecked(w, dt)  # paper eq. (12)
    G = -0.5 * dt * xi_matrix_unchecked(q)  # d q(k+1) / d b = -dt/2 Xi(q), paper eqs. (20)-(23)
    F = np.zeros(x.shape + (7,))
    F[..., :4, :4] = phi
    F[..., :4, 4:] = G
    F[..., 4:, 4:] = np.eye(3)
    x1 = np.empty_like(x)
    x1[..., :4] = np.einsum("...ij,...j->...i", phi, q)  # paper eq. (30)
    x1[..., 4:] = b
    P1 = F @ P @ np.swapaxes(F, -1, -2)  # paper eq. (31): P = F P F^T + G Q G^T
    P1[..., :4, :4] += G @ gyro_cov @ np.swapaxes(G, -1, -2)
    P1[..., 4:, 4:] += drift_cov
    return x1, P1


def ekf_update_unchecked(x, P, q_meas, R):
    """:func:`~xnavlab.attitude.ekf.ekf_update` without the input checks, for loops over checked batches.

    The same step, paper eqs. (32)-(34), with the sign alignment, symmetrisation and
    renormalisation of :func:`~xnavlab.attitude.ekf.ekf_update`. The caller guarantees finite arrays of the
    shapes below and a positive-definite ``R`` given as an array.

    Parameters
    ----------
    x : ndarray, shape (..., 7)
    P : ndarray, shape (..., 7, 7)
    q_meas : ndarray, shape (..., 4)
        Star-tracker quaternion.
    R : ndarray, shape (..., 4, 4)
        Measurement covariance.

    Returns
    -------
    x : ndarray, shape (..., 7)
    P : ndarray, shape (..., 7, 7)
    innovation : ndarray, shape (..., 4)

    Examples
    --------
    >>> from xnavlab.attitude.ekf import ekf_init, ekf_predict
    >>> from xnavlab.attitude.motion import DEFAULT_Q0
    >>> x0, P0 = ekf_init(DEFAULT_Q0, attitude_sigma=1e-4, drift_sigma=1e-4)
    >>> x1, P1, nu = ekf_update_unchecked(x0, P0, -DEFAULT_Q0, 1e-10 * np.eye(4))
    >>> float(np.abs(nu).max())
    0.0
    """
    q = x[..., :4]
    sign = np.where(np.sum(q_meas * q, axis=-1, keepdims=True) < 0.0, -1.0, 1.0)
    nu = sign * q_meas - q  # innovation q_s - C x, C = [I4 0] (paper eqs. (24), (29))
    S = P[..., :4, :4] + R  # C P C^T + R
    Kt = np.linalg.solve(S, P[..., :4, :])  # K^T = S^-1 C P, so K = P C^T S^-1 (eq. (32))
    K = np.swapaxes(Kt, -1, -2)
    x1 = x + np.einsum("...ij,...j->...i", K, nu)  # paper eq. (33)
    P1 = P - K @ P[..., :4, :]  # paper eq. (34): P = (I7 - K C) P
    P1 = 0.5 * (P1 + np.swapaxes(P1, -1, -2))  # keep it symmetric against round-off
    x1[..., :4] /= np.linalg.norm(x1[..., :4], axis=-1, keepdims=True)  # brute-force norm
    return x1, P1, nu
