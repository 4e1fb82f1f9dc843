"""The paper's 7-state additive-quaternion EKF ``x = [q; b1 b2 b3]``.

Driven by the three orthogonal gyros and updated with the star-tracker quaternion, in the
form of Lefferts, Markley & Shuster (1982) and Crassidis & Junkins (2012, ch. 7), keeping
the paper's equation numbers (30)-(34) in the comments. The drifts get a small random walk
(``SimConfig.drift_walk_deg_per_h_sqrt_s`` in :mod:`xnavlab.attitude.simulation`) so that
the filter keeps tracking a drift change.

Pure step functions :func:`ekf_predict` and :func:`ekf_update` check their inputs; the
same steps without the checks (``ekf_predict_unchecked`` and ``ekf_update_unchecked`` of the
private ``xnavlab.attitude._ekf_steps``) serve inner loops over batches whose inputs were
checked once (the filter bank of :mod:`xnavlab.attitude.simulation`). :class:`AttitudeEKF`
is the thin stateful wrapper.

Quaternions scalar last; rates rad/s; covariances in (rad/s)^2 or quaternion units^2.
"""

from __future__ import annotations

import math

import numpy as np

from xnavlab.attitude._checks import check_covariances, check_quaternion, check_sample
from xnavlab.attitude._ekf_steps import ekf_predict_unchecked, ekf_update_unchecked
from xnavlab.core.quaternions import quat_normalize
from xnavlab.core.validate import check_finite_array, check_real, check_vector

__all__ = [
    "MAX_RATE",
    "ekf_init",
    "ekf_predict",
    "ekf_update",
    "AttitudeEKF",
]

#: The largest rate-like setting of the filter, rad/s (a drift's uncertainty, the gyro noise,
#: the drift random walk); a larger one would overflow the squares in the covariances.
MAX_RATE = 1.0


def ekf_init(q_meas, *, attitude_sigma, drift_sigma):
    """Initial state and covariance of the 7-state EKF: ``x0 = [q_meas; 0]``.

    Parameters
    ----------
    q_meas : array_like, shape (..., 4)
        First star-tracker quaternion; normalised.
    attitude_sigma : float
        1-sigma attitude uncertainty, rad, in (0, pi]; the quaternion block of ``P0`` is
        ``(attitude_sigma/2)^2 I4``.
    drift_sigma : float or array_like, shape (..., 3, 3)
        1-sigma drift uncertainty, rad/s, in (0, :data:`MAX_RATE`] (a scalar gives
        ``drift_sigma^2 I3``), or the
        full drift covariance block, (rad/s)^2.

    Returns
    -------
    x0 : ndarray, shape (..., 7)
    P0 : ndarray, shape (..., 7, 7)

    Examples
    --------
    >>> from xnavlab.attitude.motion import DEFAULT_Q0
    >>> x0, P0 = ekf_init(DEFAULT_Q0, attitude_sigma=1e-4, drift_sigma=1e-4)
    >>> x0.shape, P0.shape
    ((7,), (7, 7))
    """
    q = quat_normalize(check_quaternion("q_meas", q_meas, unit=False))  # zero refused, named
    sa = check_real("attitude_sigma", attitude_sigma, 0.0, math.pi, lo_open=True)
    if np.ndim(drift_sigma) == 0:
        sd = check_real("drift_sigma", drift_sigma, 0.0, MAX_RATE, lo_open=True)
        Pd = sd**2 * np.eye(3)
    else:
        Pd = check_covariances("drift_sigma", drift_sigma, 3)
    batch = np.broadcast_shapes(q.shape[:-1], Pd.shape[:-2])
    x = np.zeros(batch + (7,))
    x[..., :4] = q
    P = np.zeros(batch + (7, 7))
    P[..., :4, :4] = (0.5 * sa) ** 2 * np.eye(4)
    P[..., 4:, 4:] = Pd
    return x, P


def ekf_predict(x, P, omega_g, dt, gyro_cov, drift_cov):
    """EKF prediction over one gyro sample (paper eqs. (30)-(31)).

    ``q(k+1|k) = Phi(w_g1 - b_hat) q(k)`` (eq. (12)) and ``b(k+1|k) = b(k)``;
    ``P(k+1|k) = F P F^T + G Q G^T + Q_b`` with ``F = [[Phi, G], [0, I3]]`` and
    ``G = -dt/2 Xi(q_hat)``, the linearisation ``Omega(x) q = Xi(q) x`` (eqs. (20)-(23);
    Lefferts, Markley & Shuster 1982 in additive form).

    Parameters
    ----------
    x : array_like, shape (..., 7)
        ``[q (scalar last); b (rad/s)]``.
    P : array_like, shape (..., 7, 7)
    omega_g : array_like, shape (..., 3)
        The gyro rates driving the filter, rad/s (the orthogonal triad for SOS).
    dt : float
        Sample interval, s, in (0, 10].
    gyro_cov : float or array_like, shape (..., 3, 3)
        Covariance of the gyro noise per sample, (rad/s)^2 (scalar: times I3).
    drift_cov : float or array_like, shape (..., 3, 3)
        Drift random-walk covariance added per step, (rad/s)^2.

    Returns
    -------
    x : ndarray, shape (..., 7)
    P : ndarray, shape (..., 7, 7)

    Examples
    --------
    >>> from xnavlab.attitude.motion import DEFAULT_Q0
    >>> x0, P0 = ekf_init(DEFAULT_Q0, attitude_sigma=1e-4, drift_sigma=1e-4)
    >>> x1, P1 = ekf_predict(x0, P0, [0.0, 0.0, 0.0], 0.1, 1e-12, 0.0)
    >>> bool(np.allclose(x1, x0)), bool(np.all(np.diag(P1) >= np.diag(P0)))
    (True, True)
    """
    x, P = _state(x, P)
    w = check_finite_array("omega_g", omega_g, shape=(3,))
    dt = check_real("dt", dt, 0.0, 10.0, lo_open=True)
    gyro_cov, drift_cov = _cov3("gyro_cov", gyro_cov), _cov3("drift_cov", drift_cov)
    return ekf_predict_unchecked(x, P, w, dt, gyro_cov, drift_cov)


def ekf_update(x, P, q_meas, R):
    """EKF update with a star-tracker quaternion (paper eqs. (32)-(34)).

    Additive measurement ``q_s = q + v_q`` (paper eq. (24)), ``C = [I4 0]``;
    ``K = P C^T (C P C^T + R)^-1``, ``x = x + K (q_s - C x)``, ``P = (I7 - K C) P``.
    ``q_s`` is sign-aligned with the estimate first (``q`` and ``-q`` are one attitude),
    ``P`` is symmetrised and the quaternion renormalised after the update (the
    "brute-force" normalisation of Crassidis & Junkins 2012, ch. 7).

    Parameters
    ----------
    x : array_like, shape (..., 7)
    P : array_like, shape (..., 7, 7)
    q_meas : array_like, shape (..., 4)
        Star-tracker quaternion.
    R : float or array_like, shape (..., 4, 4)
        Measurement covariance (scalar: times I4). The paper's ``R = R0`` is exact for
        an isotropic ``R0 = (sigma/2)^2 I4``, our choice.

    Returns
    -------
    x : ndarray, shape (..., 7)
    P : ndarray, shape (..., 7, 7)
    innovation : ndarray, shape (..., 4)

    Examples
    --------
    >>> from xnavlab.attitude.motion import DEFAULT_Q0
    >>> x0, P0 = ekf_init(DEFAULT_Q0, attitude_sigma=1e-4, drift_sigma=1e-4)
    >>> x1, P1, nu = ekf_update(x0, P0, -DEFAULT_Q0, 1e-10)
    >>> float(np.abs(nu).max()), bool(np.trace(P1) < np.trace(P0))
    (0.0, True)
    """
    x, P = _state(x, P)
    qm = check_quaternion("q_meas", q_meas)  # additive: a scaled q_meas would pull x by its scale
    R = _cov3("R", R, 4, definite=True)
    return ekf_update_unchecked(x, P, qm, R)


def _state(x, P):
    x = check_finite_array("x", x, shape=(7,))
    P = check_finite_array("P", P, shape=(7, 7))
    check_quaternion("x[..., :4]", x[..., :4])  # the attitude: a zero or scaled one refused
    return x, check_covariances("P", P, 7)


def _cov3(name, c, n=3, definite=False):
    if np.ndim(c) == 0:
        return check_real(name, c, 0.0, MAX_RATE**2, lo_open=definite) * np.eye(n)
    return check_covariances(name, c, n, definite)


class AttitudeEKF:
    """The 7-state EKF ``[q; b1 b2 b3]`` of the paper as a thin stateful wrapper.

    Parameters
    ----------
    q0 : array_like, shape (4,)
        Initial attitude (usually the first star-tracker quaternion).
    dt : float
        Sample interval, s, in (0, 10].
    gyro_noise : float
        Gyro noise, 1 sigma per sample, rad/s, in [0, :data:`MAX_RATE`].
    star_noise : float
        Star-tracker noise per axis, 1 sigma, rad, in (0, pi]; ``R = (star_noise/2)^2 I4``.
    drift_walk : float
        Drift random walk, rad/s per sqrt(s), in [0, :data:`MAX_RATE`].
    drift_sigma : float
        Initial drift uncertainty, rad/s.

    Examples
    --------
    >>> from xnavlab.attitude.motion import DEFAULT_Q0
    >>> from xnavlab.attitude.sensors import DEG_PER_H
    >>> f = AttitudeEKF(DEFAULT_Q0, 0.1, 0.05 * DEG_PER_H, 1e-4, DEG_PER_H, 100 * DEG_PER_H)
    >>> f.predict([0.0, 0.0, 0.0]); nu = f.update(DEFAULT_Q0)
    >>> f.x.shape, f.drift.shape
    ((7,), (3,))
    """

    def __init__(self, q0, dt, gyro_noise, star_noise, drift_walk, drift_sigma):
        self.dt = check_real("dt", dt, 0.0, 10.0, lo_open=True)
        sg = check_real("gyro_noise", gyro_noise, 0.0, MAX_RATE)
        ss = check_real("star_noise", star_noise, 0.0, math.pi, lo_open=True)
        dw = check_real("drift_walk", drift_walk, 0.0, MAX_RATE)
        self.gyro_cov = sg**2 * np.eye(3)
        self.drift_cov = dw**2 * self.dt * np.eye(3)
        self.R = (0.5 * ss) ** 2 * np.eye(4)
        q0 = check_quaternion("q0", check_vector("q0", q0, 4), unit=False)  # one; normalised by ekf_init
        self.x, self.P = ekf_init(q0, attitude_sigma=ss, drift_sigma=drift_sigma)

    @property
    def q(self):
        """Attitude estimate, shape (4,)."""
        return self.x[:4]

    @property
    def drift(self):
        """Drift estimate of the orthogonal gyros, rad/s, shape (3,)."""
        return self.x[4:]

    def predict(self, omega_g):
        """Propagate over one sample with gyro rates ``omega_g`` (3,), rad/s (eqs. (30)-(31))."""
        w = check_sample("omega_g", omega_g, 3)
        self.x, self.P = ekf_predict_unchecked(self.x, self.P, w, self.dt, self.gyro_cov,
                                               self.drift_cov)

    def update(self, q_meas):
        """Update with a star-tracker quaternion (4,), of norm 1 to
        :data:`xnavlab.core.quaternions.UNIT_TOL` (a zero or scaled one is refused, as
        :func:`ekf_update`); returns the innovation (eqs. (32)-(34))."""
        qm = check_sample("q_meas", q_meas, 4, unit=True)
        self.x, self.P, nu = ekf_update_unchecked(self.x, self.P, qm, self.R)
        return nu
