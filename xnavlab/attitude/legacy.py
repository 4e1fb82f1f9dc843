"""Attitude-sensor fault diagnosis with one Kalman filter (SOS) or a bank of four (DOS).

The attitude chapter's source paper (Li, Niu, Shao & Shen, HIT / Shanghai Institute of
Spaceflight Control Technology) diagnoses single faults of a gyro assembly (three
orthogonal gyros and one skewed gyro) and a star tracker with *one* extended Kalman
filter, where the earlier dedicated-observer scheme (its ref. [21]) ran four. Most of
its equations were lost from our copy; this module rebuilds them in the standard forms
of Lefferts, Markley & Shuster (1982) and Crassidis & Junkins (2012, ch. 7), keeping the
paper's equation numbers in the comments. What is reconstructed, and every choice made
where the paper is silent, is stated where it is made; in short:

Models
    Gyros ``w_g = H w + b + v_g + f_g`` (paper eq. (2)) with ``H = [I3; h4^T]`` and the
    skewed gyro on the equal-angle axis ``h4 = [1, 1, 1]/sqrt(3)`` (:data:`SKEW_AXIS`,
    paper eq. (3) lost). Star tracker ``q_s = q (x) q_v + f_q`` (paper eq. (17) with
    ``q_f = 1``), renormalised, as a star tracker reports unit quaternions. Truth: an
    Earth-pointing spacecraft in a 100-minute orbit (pitch rate -0.06 deg/s about body
    y) with a slow three-axis attitude-control wobble (:func:`truth_rate`); the rate is
    held over each sample (10 Hz), so the discrete kinematics (12) is exact for it.
The filter
    The 7-state additive-quaternion EKF of the paper, ``x = [q; b1 b2 b3]``, driven by the
    three orthogonal gyros and updated with the star-tracker quaternion
    (:func:`ekf_predict`, :func:`ekf_update`, :class:`AttitudeEKF`). The drifts get a
    small random walk (``SimConfig.drift_walk_deg_per_h_sqrt_s``) so that the filter keeps
    tracking a drift change.
SOS (the paper's scheme)
    ``r_i = |b_i_hat - b_i_ref|`` for the orthogonal gyros (paper eq. (35)) and the
    hardware-parity residual ``r4 = |w_g4 - h4^T w_g1 - p_ref|`` of the skewed gyro
    (eqs. (36)-(37), reconstructed from the paper's count of 3 multiplications, 4
    additions and 1 absolute value). The references are learned on board from a
    fault-free calibration window; thresholds are ``n_sigma`` times the residual's
    predicted standard deviation. Fault table and decision rule: :data:`SOS_TABLE`,
    :func:`sos_decide` (paper Tables 1-2, reconstructed).
DOS (ref. [21], the reference method)
    Four EKFs, filter ``j`` fed by the three gyros other than ``j``
    (:data:`DOS_GROUPS`); a fault of gyro ``j`` moves every residual but ``j``'s, a
    star-tracker fault moves all four (:func:`dos_decide`).
Quaternion differentiation (paper ref. [22])
    Rate from a least-squares slope of the star-tracker quaternions, compared with the
    gyros (:func:`quaternion_rate`, :func:`qdiff_fault_estimates`).
Running it
    :func:`simulate` runs truth, sensors, faults (:mod:`xnavlab.core.faults`) and all three
    diagnoses, vectorised over the filters; :class:`SOSMonitor` and :class:`DOSMonitor`
    do the same one sample at a time, as on board (:func:`time_sos_dos` times them);
    :func:`isolation_monte_carlo` batches hundreds of runs.

Units are SI inside (rad, rad/s, s); names say otherwise (``drifts_deg_per_h``).
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field

import numpy as np

from xnavlab.core.faults import KINDS, Fault, inject
from xnavlab.core.quaternions import (
    kinematics_matrix,
    quat_from_rotvec,
    quat_normalize,
    quat_product,
    xi_matrix,
)
from xnavlab.core.validate import (
    check_choice,
    check_finite_array,
    check_int,
    check_real,
    make_rng,
)

__all__ = [
    "DEG_PER_H",
    "PAPER_DRIFTS_DEG_PER_H",
    "PAPER_GYRO_NOISE_DEG_PER_H",
    "PAPER_STAR_NOISE_DEG",
    "SKEW_AXIS",
    "DEFAULT_Q0",
    "LOCATIONS",
    "VERDICTS",
    "DEFAULT_MAGNITUDES",
    "SOS_TABLE",
    "DOS_GROUPS",
    "DOS_TABLE",
    "gyro_matrix",
    "truth_rate",
    "truth_motion",
    "gyro_measurements",
    "star_tracker_measurements",
    "make_fault",
    "ekf_init",
    "ekf_predict",
    "ekf_update",
    "AttitudeEKF",
    "gyro_parity",
    "sos_residuals",
    "sos_decide",
    "dos_rate_matrices",
    "dos_residuals",
    "dos_decide",
    "quaternion_rate",
    "qdiff_fault_estimates",
    "qdiff_decide",
    "Diagnosis",
    "diagnose",
    "SimConfig",
    "AttitudeRun",
    "simulate",
    "SOSMonitor",
    "DOSMonitor",
    "time_sos_dos",
    "isolation_monte_carlo",
    "isolation_table",
    "plot_residuals",
    "plot_fault_case",
]

#: rad/s in one deg/h.
DEG_PER_H = math.pi / 180.0 / 3600.0
#: Constant drifts of gyros x, y, z and the skewed gyro, deg/h (paper section 4).
PAPER_DRIFTS_DEG_PER_H = (50.0, 40.0, -50.0, 45.0)
#: Gyro measurement noise, 1 sigma per sample, deg/h (paper section 4).
PAPER_GYRO_NOISE_DEG_PER_H = 0.05
#: Star-tracker noise, 1 sigma per axis, deg (paper section 4).
PAPER_STAR_NOISE_DEG = 0.00333
#: Our choice of skewed-gyro axis (paper eq. (3) lost): equal angles with x, y, z.
SKEW_AXIS = np.full(3, 1.0 / math.sqrt(3.0))
#: Our choice of initial attitude: rotation vector (0.3, -0.5, 0.8) rad.
DEFAULT_Q0 = quat_from_rotvec([0.3, -0.5, 0.8])
#: Where a single fault can be: the four gyros and the star tracker.
LOCATIONS = ("gyro_x", "gyro_y", "gyro_z", "gyro_skew", "star_tracker")
#: Every verdict of :func:`sos_decide` and :func:`dos_decide`.
VERDICTS = ("none",) + LOCATIONS + ("unknown",)
#: Our reference fault sizes (paper eqs. (38)-(40) lost), SI: a gyro step of 36 deg/h
#: (0.01 deg/s), a gyro ramp of 0.1 deg/h per second, a star-tracker step of 2e-4 and a
#: star-tracker ramp of 5e-5 per second on the quaternion component q1.
DEFAULT_MAGNITUDES = {
    ("gyro", "step"): 36.0 * DEG_PER_H,
    ("gyro", "ramp"): 0.1 * DEG_PER_H,
    ("star_tracker", "step"): 2e-4,
    ("star_tracker", "ramp"): 5e-5,
}

#: Paper Table 1 (reconstructed) for SOS: which residuals (r1, r2, r3, r4) each fault
#: drives over its threshold. ``None``: may cross; a star-tracker fault moves at least
#: one of r1-r3 and never the gyro parity r4.
SOS_TABLE = {
    "gyro_x": (True, False, False, True),
    "gyro_y": (False, True, False, True),
    "gyro_z": (False, False, True, True),
    "gyro_skew": (False, False, False, True),
    "star_tracker": (None, None, None, False),
}

#: DOS gyro groups: filter ``j`` uses the three gyros other than gyro ``j``.
DOS_GROUPS = ((1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2))

#: DOS structured-residual table: residuals (R1..R4) that each fault moves.
DOS_TABLE = {
    "gyro_x": (False, True, True, True),
    "gyro_y": (True, False, True, True),
    "gyro_z": (True, True, False, True),
    "gyro_skew": (True, True, True, False),
    "star_tracker": (True, True, True, True),
}


# --------------------------------------------------------------------------- models


def gyro_matrix(skew_axis=SKEW_AXIS):
    """Measurement matrix ``H = [I3; h4^T]`` of three orthogonal gyros and a skewed one.

    Paper eqs. (2)-(3) (eq. (3) lost): gyro ``i`` measures the body rate along its
    input axis, the rows of ``H``.

    Parameters
    ----------
    skew_axis : array_like, shape (3,)
        Input axis of the skewed gyro in the body frame; normalised here. All three
        components must be non-zero, so that any three of the four gyros span 3-D
        (needed by the DOS bank). Default: equal angles, ``[1, 1, 1]/sqrt(3)``.

    Returns
    -------
    ndarray, shape (4, 3)

    Examples
    --------
    >>> np.round(gyro_matrix()[3], 4)
    array([0.5774, 0.5774, 0.5774])
    """
    h4 = check_finite_array("skew_axis", skew_axis, shape=(3,))
    if h4.ndim != 1:
        raise ValueError(f"skew_axis must have shape (3,), got {h4.shape}")
    n = np.linalg.norm(h4)
    if n == 0.0 or np.min(np.abs(h4)) < 1e-3 * n:
        raise ValueError(
            "skew_axis must have three non-zero components (each >= 1e-3 of its norm), "
            f"got {h4.tolist()}"
        )
    return np.vstack([np.eye(3), h4 / n])


def truth_rate(t, *, omega_orbit_deg_s=0.06, wobble_deg_s=0.01, wobble_period=300.0):
    """Body angular rate of our truth motion (the paper does not give one), rad/s.

    An Earth-pointing spacecraft in a ~100-minute circular orbit turns at the orbital
    rate about the negative body y axis; the attitude control adds a slow three-axis
    wobble: ``w(t) = [a s(t), -w_o + a s(t + P/3), a s(t + 2P/3)]`` with
    ``s(t) = sin(2 pi t / P)``.

    Parameters
    ----------
    t : array_like, shape (n,)
        Time, s.
    omega_orbit_deg_s : float
        Orbital (pitch) rate ``w_o``, deg/s, >= 0. Default 0.06 (a 100-min orbit).
    wobble_deg_s : float
        Wobble amplitude ``a``, deg/s, >= 0.
    wobble_period : float
        Wobble period ``P``, s, > 0.

    Returns
    -------
    ndarray, shape (n, 3)

    Examples
    --------
    >>> np.round(np.degrees(truth_rate([0.0])), 4)
    array([[ 0.    , -0.0513, -0.0087]])
    """
    t = check_finite_array("t", t)
    wo = math.radians(check_real("omega_orbit_deg_s", omega_orbit_deg_s, 0.0, 10.0))
    a = math.radians(check_real("wobble_deg_s", wobble_deg_s, 0.0, 10.0))
    period = check_real("wobble_period", wobble_period, 0.0, lo_open=True)
    ph = 2.0 * math.pi * t[..., None] / period + np.array([0.0, 2.0, 4.0]) * math.pi / 3.0
    w = a * np.sin(ph)
    w[..., 1] -= wo
    return w


def truth_motion(n, dt, *, q0=DEFAULT_Q0, **motion):
    """Sample times, held body rates and true attitude of :func:`truth_rate`.

    The rate ``w[k] = truth_rate(t_k + dt/2)`` is held over ``[t_k, t_k + dt]`` and the
    attitude propagated with the exact discrete kinematics (paper eq. (12)), so the
    filter's model is exact for the truth apart from the sensor errors.

    Parameters
    ----------
    n : int
        Number of samples, >= 2.
    dt : float
        Sample interval, s, in (0, 10].
    q0 : array_like, shape (4,)
        Attitude at t = 0 (reference-to-body, scalar last); normalised.
    **motion
        Passed to :func:`truth_rate`.

    Returns
    -------
    t : ndarray, shape (n,)
    w : ndarray, shape (n, 3)
        Body rate held over each sample interval, rad/s.
    q : ndarray, shape (n, 4)

    Examples
    --------
    >>> t, w, q = truth_motion(11, 0.1)
    >>> t[-1], bool(np.allclose(np.linalg.norm(q, axis=1), 1.0))
    (1.0, True)
    """
    n = check_int("n", n, 2)
    dt = check_real("dt", dt, 0.0, 10.0, lo_open=True)
    q = quat_normalize(check_finite_array("q0", q0, shape=(4,)))
    t = np.arange(n) * dt
    w = truth_rate(t + 0.5 * dt, **motion)
    phi = kinematics_matrix(w, dt)  # paper eq. (12) for every interval
    out = np.empty((n, 4))
    out[0] = q
    for k in range(n - 1):
        out[k + 1] = phi[k] @ out[k]
    return t, w, out


def gyro_measurements(
    t,
    w,
    *,
    drifts_deg_per_h=PAPER_DRIFTS_DEG_PER_H,
    noise_deg_per_h=PAPER_GYRO_NOISE_DEG_PER_H,
    skew_axis=SKEW_AXIS,
    faults=(),
    rng=None,
):
    """Gyro-assembly outputs ``w_g = H w + b + v_g + f_g`` (paper eq. (2)), rad/s.

    Parameters
    ----------
    t : array_like, shape (n,)
        Sample times, s.
    w : array_like, shape (n, 3)
        True body rate, rad/s.
    drifts_deg_per_h : array_like, shape (4,)
        Constant drifts ``b`` of gyros x, y, z and skew, deg/h.
    noise_deg_per_h : float
        White noise ``v_g``, 1 sigma per sample, deg/h, >= 0.
    skew_axis : array_like, shape (3,)
        See :func:`gyro_matrix`.
    faults : sequence of Fault
        Faults of sensor ``"gyro"`` (components 0-3: x, y, z, skew) are injected with
        :func:`xnavlab.core.faults.inject`; magnitudes in rad/s (rad/s^2 for ramps).
    rng : numpy.random.Generator or int, optional

    Returns
    -------
    ndarray, shape (n, 4)

    Examples
    --------
    >>> t = np.arange(3.0)
    >>> wg = gyro_measurements(t, np.zeros((3, 3)), noise_deg_per_h=0.0)
    >>> np.round(wg[0] / DEG_PER_H, 6)
    array([ 50.,  40., -50.,  45.])
    """
    t = check_finite_array("t", t)
    w = check_finite_array("w", w, shape=(3,))
    if t.ndim != 1 or w.shape != (t.size, 3):
        raise ValueError(f"w must have shape (n, 3) with n = len(t) = {t.size}, got {w.shape}")
    b = check_finite_array("drifts_deg_per_h", drifts_deg_per_h, shape=(4,)) * DEG_PER_H
    sigma = check_real("noise_deg_per_h", noise_deg_per_h, 0.0) * DEG_PER_H
    rng = make_rng(rng)
    H = gyro_matrix(skew_axis)
    z = w @ H.T + b + rng.normal(0.0, 1.0, (t.size, 4)) * sigma  # paper eq. (2)
    return inject(t, z, list(faults), "gyro", rng=rng)  # + f_g


def star_tracker_measurements(t, q, *, noise_deg=PAPER_STAR_NOISE_DEG, faults=(), rng=None):
    """Star-tracker quaternions ``q_s = q (x) q_v + f_q``, renormalised (paper eq. (17)).

    ``q_v`` is the quaternion of a small rotation with independent N(0, sigma^2) angles
    about the three axes; the paper's fault rotation ``q_f`` is left at identity and
    faults enter through the additive ``f_q``, injected with :func:`xnavlab.core.faults.inject`
    (sensor ``"star_tracker"``, components 0-3: q1..q4, dimensionless; a ramp's
    magnitude is per second). The output is renormalised, as a star tracker reports
    unit quaternions.

    Parameters
    ----------
    t : array_like, shape (n,)
        Sample times, s.
    q : array_like, shape (n, 4)
        True attitude, scalar last.
    noise_deg : float
        Noise per axis, 1 sigma, deg, >= 0.
    faults : sequence of Fault
    rng : numpy.random.Generator or int, optional

    Returns
    -------
    ndarray, shape (n, 4)

    Examples
    --------
    >>> q = np.tile(DEFAULT_Q0, (2, 1))
    >>> bool(np.allclose(star_tracker_measurements([0.0, 1.0], q, noise_deg=0.0), q))
    True
    """
    t = check_finite_array("t", t)
    q = check_finite_array("q", q, shape=(4,))
    if t.ndim != 1 or q.shape != (t.size, 4):
        raise ValueError(f"q must have shape (n, 4) with n = len(t) = {t.size}, got {q.shape}")
    sigma = math.radians(check_real("noise_deg", noise_deg, 0.0))
    rng = make_rng(rng)
    qv = quat_from_rotvec(rng.normal(0.0, 1.0, (t.size, 3)) * sigma)
    qs = quat_product(q, qv)  # paper eq. (17), q_f = identity
    qs = inject(t, qs, list(faults), "star_tracker", rng=rng)  # + f_q
    return quat_normalize(qs)


def make_fault(location, kind, magnitude, onset=50.0, duration=math.inf):
    """A :class:`xnavlab.core.faults.Fault` on one of the attitude sensors.

    Parameters
    ----------
    location : {"gyro_x", "gyro_y", "gyro_z", "gyro_skew", "star_tracker"}
        A star-tracker fault acts on the quaternion component q1.
    kind : {"step", "ramp", "spike", "stuck", "noise"}
    magnitude : float
        SI: rad/s for a gyro step (rad/s^2 for a ramp); dimensionless quaternion units
        for the star tracker (per second for a ramp).
    onset : float
        Start, s.
    duration : float
        Length, s (``math.inf``: permanent).

    Examples
    --------
    >>> f = make_fault("gyro_skew", "ramp", 0.1 * DEG_PER_H)
    >>> (f.sensor, f.component, f.kind)
    ('gyro', 3, 'ramp')
    """
    check_choice("location", location, LOCATIONS)
    check_choice("kind", kind, KINDS)
    if location == "star_tracker":
        return Fault("star_tracker", kind, magnitude, onset, duration, 0)
    return Fault("gyro", kind, magnitude, onset, duration, LOCATIONS.index(location))


# --------------------------------------------------------------------------- the EKF


def ekf_init(q_meas, *, attitude_sigma, drift_sigma):
    """Initial state and covariance of the 7-state EKF: ``x0 = [q_meas; 0]``.

    Parameters
    ----------
    q_meas : array_like, shape (..., 4)
        First star-tracker quaternion; normalised.
    attitude_sigma : float
        1-sigma attitude uncertainty, rad, > 0; the quaternion block of ``P0`` is
        ``(attitude_sigma/2)^2 I4``.
    drift_sigma : float or array_like, shape (..., 3, 3)
        1-sigma drift uncertainty, rad/s (a scalar gives ``drift_sigma^2 I3``), or the
        full drift covariance block, (rad/s)^2.

    Returns
    -------
    x0 : ndarray, shape (..., 7)
    P0 : ndarray, shape (..., 7, 7)

    Examples
    --------
    >>> x0, P0 = ekf_init(DEFAULT_Q0, attitude_sigma=1e-4, drift_sigma=1e-4)
    >>> x0.shape, P0.shape
    ((7,), (7, 7))
    """
    q = quat_normalize(q_meas)
    sa = check_real("attitude_sigma", attitude_sigma, 0.0, lo_open=True)
    if np.ndim(drift_sigma) == 0:
        sd = check_real("drift_sigma", drift_sigma, 0.0, lo_open=True)
        Pd = sd**2 * np.eye(3)
    else:
        Pd = check_finite_array("drift_sigma", drift_sigma, shape=(3, 3))
    batch = np.broadcast_shapes(q.shape[:-1], Pd.shape[:-2])
    x = np.zeros(batch + (7,))
    x[..., :4] = q
    P = np.zeros(batch + (7, 7))
    P[..., :4, :4] = (0.5 * sa) ** 2 * np.eye(4)
    P[..., 4:, 4:] = Pd
    return x, P


def _predict(x, P, w_g, dt, gyro_cov, drift_cov):
    q, b = x[..., :4], x[..., 4:]
    w = w_g - b  # paper eq. (18): w = w_g1 - b - v_g1, noise-free part
    phi = kinematics_matrix(w, dt)  # paper eq. (12)
    G = -0.5 * dt * xi_matrix(q)  # d q(k+1) / d b = -dt/2 Xi(q), paper eqs. (20)-(23)
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


def _update(x, P, q_meas, R):
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


def _state(x, P):
    x = check_finite_array("x", x, shape=(7,))
    P = check_finite_array("P", P, shape=(7, 7))
    if np.any(np.linalg.norm(x[..., :4], axis=-1) == 0.0):
        raise ValueError("x must have a non-zero quaternion part x[..., :4]")
    return x, P


def _cov3(name, c, n=3):
    if np.ndim(c) == 0:
        return check_real(name, c, 0.0) * np.eye(n)
    return check_finite_array(name, c, shape=(n, n))


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
        Sample interval, s, > 0.
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
    >>> x0, P0 = ekf_init(DEFAULT_Q0, attitude_sigma=1e-4, drift_sigma=1e-4)
    >>> x1, P1 = ekf_predict(x0, P0, [0.0, 0.0, 0.0], 0.1, 1e-12, 0.0)
    >>> bool(np.allclose(x1, x0)), bool(np.all(np.diag(P1) >= np.diag(P0)))
    (True, True)
    """
    x, P = _state(x, P)
    w = check_finite_array("omega_g", omega_g, shape=(3,))
    dt = check_real("dt", dt, 0.0, lo_open=True)
    return _predict(x, P, w, dt, _cov3("gyro_cov", gyro_cov), _cov3("drift_cov", drift_cov))


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
    >>> x0, P0 = ekf_init(DEFAULT_Q0, attitude_sigma=1e-4, drift_sigma=1e-4)
    >>> x1, P1, nu = ekf_update(x0, P0, -DEFAULT_Q0, 1e-10)
    >>> float(np.abs(nu).max()), bool(np.trace(P1) < np.trace(P0))
    (0.0, True)
    """
    x, P = _state(x, P)
    qm = check_finite_array("q_meas", q_meas, shape=(4,))
    R = _cov3("R", R, 4)
    if np.ndim(R) == 2 and np.any(np.linalg.eigvalsh(R) <= 0.0):
        raise ValueError("R must be positive definite")
    return _update(x, P, qm, R)


class AttitudeEKF:
    """The 7-state EKF ``[q; b1 b2 b3]`` of the paper as a thin stateful wrapper.

    Parameters
    ----------
    q0 : array_like, shape (4,)
        Initial attitude (usually the first star-tracker quaternion).
    dt : float
        Sample interval, s.
    gyro_noise : float
        Gyro noise, 1 sigma per sample, rad/s.
    star_noise : float
        Star-tracker noise per axis, 1 sigma, rad; ``R = (star_noise/2)^2 I4``.
    drift_walk : float
        Drift random walk, rad/s per sqrt(s), >= 0.
    drift_sigma : float
        Initial drift uncertainty, rad/s.

    Examples
    --------
    >>> f = AttitudeEKF(DEFAULT_Q0, 0.1, 0.05 * DEG_PER_H, 1e-4, DEG_PER_H, 100 * DEG_PER_H)
    >>> f.predict([0.0, 0.0, 0.0]); nu = f.update(DEFAULT_Q0)
    >>> f.x.shape, f.drift.shape
    ((7,), (3,))
    """

    def __init__(self, q0, dt, gyro_noise, star_noise, drift_walk, drift_sigma):
        self.dt = check_real("dt", dt, 0.0, lo_open=True)
        sg = check_real("gyro_noise", gyro_noise, 0.0)
        ss = check_real("star_noise", star_noise, 0.0, lo_open=True)
        dw = check_real("drift_walk", drift_walk, 0.0)
        self.gyro_cov = sg**2 * np.eye(3)
        self.drift_cov = dw**2 * self.dt * np.eye(3)
        self.R = (0.5 * ss) ** 2 * np.eye(4)
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
        w = _sample("omega_g", omega_g, 3)
        self.x, self.P = _predict(self.x, self.P, w, self.dt, self.gyro_cov, self.drift_cov)

    def update(self, q_meas):
        """Update with a star-tracker quaternion (4,); returns the innovation (eqs. (32)-(34))."""
        qm = _sample("q_meas", q_meas, 4)
        self.x, self.P, nu = _update(self.x, self.P, qm, self.R)
        return nu


def _sample(name, value, n):
    """Light per-sample check for the on-board loops (shape and finiteness)."""
    arr = np.asarray(value, dtype=float)
    if arr.shape != (n,) or not np.isfinite(arr).all():
        raise ValueError(f"{name} must be {n} finite numbers, got {value!r}")
    return arr


# --------------------------------------------------------------------------- SOS


def gyro_parity(omega_g, skew_axis=SKEW_AXIS):
    """Hardware parity of the gyro assembly ``p = w_g4 - h4^T w_g1``, rad/s.

    Free of the body rate (``[-h4^T 1] H = 0``), so ``p = b4 - h4^T b1 + noise +
    f4 - h4^T f1``: it moves for a fault on any gyro and never for the star tracker
    (paper eq. (36), reconstructed).

    Parameters
    ----------
    omega_g : array_like, shape (..., 4)
        Gyro-assembly output, rad/s.
    skew_axis : array_like, shape (3,)

    Returns
    -------
    ndarray, shape (...)

    Examples
    --------
    >>> H = gyro_matrix()
    >>> abs(float(gyro_parity(H @ np.array([0.1, -0.2, 0.3])))) < 1e-15
    True
    """
    wg = check_finite_array("omega_g", omega_g, shape=(4,))
    h4 = gyro_matrix(skew_axis)[3]
    return wg[..., 3] - wg[..., :3] @ h4  # 3 multiplications, 3 additions


def sos_residuals(drift_hat, omega_g, drift_ref, parity_ref, skew_axis=SKEW_AXIS):
    """SOS residuals ``r1..r4`` (paper eqs. (35)-(37), reconstructed), rad/s.

    ``r_i = |b_i_hat - b_i_ref|`` (i = 1, 2, 3) from the one filter's drift estimates, and
    ``r4 = |w_g4 - h4^T w_g1 - p_ref|``: 3 multiplications, 4 additions, 1 absolute value,
    the paper's operation count. With ``drift_ref = 0`` the first three are the paper's
    literal ``|b_i_hat|``.

    Parameters
    ----------
    drift_hat : array_like, shape (..., 3)
        Drift estimates of the orthogonal gyros, rad/s.
    omega_g : array_like, shape (..., 4)
        Gyro outputs, rad/s.
    drift_ref : array_like, shape (..., 3)
        Fault-free drift references, rad/s.
    parity_ref : float or array_like, shape (...)
        Fault-free parity ``b4 - h4^T b1``, rad/s.
    skew_axis : array_like, shape (3,)

    Returns
    -------
    ndarray, shape (..., 4)

    Examples
    --------
    >>> r = sos_residuals([1.0, 2.0, 3.0], [0.0, 0.0, 0.0, 1.0], [1.0, 1.0, 1.0], 0.0)
    >>> r.tolist()
    [0.0, 1.0, 2.0, 1.0]
    """
    b = check_finite_array("drift_hat", drift_hat, shape=(3,))
    ref = check_finite_array("drift_ref", drift_ref, shape=(3,))
    pref = check_finite_array("parity_ref", parity_ref)
    p = gyro_parity(omega_g, skew_axis)
    r13 = np.abs(b - ref)  # paper eq. (35)
    r4 = np.abs(p - pref)  # paper eq. (37)
    return np.concatenate([r13, r4[..., None]], axis=-1)


def sos_decide(crossed):
    """SOS decision rule (paper Table 2, reconstructed) from the crossed residuals.

    ===================  ================================
    r4 crossed, and      verdict
    ===================  ================================
    none of r1-r3        ``"gyro_skew"``
    exactly r_i          ``"gyro_x"``, ``"gyro_y"``, ``"gyro_z"``
    two or more          ``"unknown"`` (not a single fault)
    ===================  ================================

    r4 not crossed: ``"star_tracker"`` if any of r1-r3 crossed, else ``"none"``.

    Parameters
    ----------
    crossed : array_like of bool, shape (..., 4)
        Which of r1..r4 exceeded their thresholds.

    Returns
    -------
    str or ndarray of str, shape (...)

    Examples
    --------
    >>> sos_decide([True, False, False, True]), sos_decide([False, True, True, False])
    ('gyro_x', 'star_tracker')
    """
    c = _bool_flags("crossed", crossed, 4)
    n13 = c[..., :3].sum(-1)
    which = np.array(["gyro_x", "gyro_y", "gyro_z"])[np.argmax(c[..., :3], axis=-1)]
    r4 = c[..., 3]
    out = np.select(
        [r4 & (n13 == 0), r4 & (n13 == 1), r4, n13 > 0],
        ["gyro_skew", which, "unknown", "star_tracker"],
        "none",
    )
    return out.item() if out.ndim == 0 else out


def _bool_flags(name, flags, n):
    try:
        arr = np.asarray(flags)
    except (TypeError, ValueError):
        arr = None
    if arr is None or arr.dtype != bool or arr.shape[-1:] != (n,):
        raise ValueError(f"{name} must be a boolean array of shape (..., {n})")
    return arr


# --------------------------------------------------------------------------- DOS


def dos_rate_matrices(skew_axis=SKEW_AXIS):
    """Rate reconstruction of each DOS filter: ``T_j = H[group_j]^-1``, shape (4, 3, 3).

    Filter ``j`` reads the body rate as ``T_j w_g[group_j]`` from the three gyros of
    :data:`DOS_GROUPS` ``[j]`` (all but gyro ``j``); its drift states are
    ``T_j b[group_j]``.

    Examples
    --------
    >>> np.allclose(dos_rate_matrices()[3], np.eye(3))
    True
    """
    H = gyro_matrix(skew_axis)
    return np.stack([np.linalg.inv(H[list(g)]) for g in DOS_GROUPS])


def dos_residuals(drift_hat, drift_ref):
    """DOS residuals: ``R_j = |d_j_hat - d_j_ref|`` (Euclidean norm), rad/s.

    Parameters
    ----------
    drift_hat : array_like, shape (..., 4, 3)
        Equivalent body-frame drift estimates of the four filters, rad/s.
    drift_ref : array_like, shape (..., 4, 3)
        Their fault-free references, rad/s.

    Returns
    -------
    ndarray, shape (..., 4)

    Examples
    --------
    >>> dos_residuals(np.ones((4, 3)), np.zeros((4, 3))).round(3).tolist()
    [1.732, 1.732, 1.732, 1.732]
    """
    d = check_finite_array("drift_hat", drift_hat, shape=(4, 3))
    ref = check_finite_array("drift_ref", drift_ref, shape=(4, 3))
    return np.linalg.norm(d - ref, axis=-1)


def dos_decide(crossed):
    """DOS decision rule (structured residuals, :data:`DOS_TABLE`).

    All four residuals crossed: ``"star_tracker"``; exactly three: the gyro excluded
    from the one quiet filter; one or two: ``"unknown"``; none: ``"none"``.

    Parameters
    ----------
    crossed : array_like of bool, shape (..., 4)

    Returns
    -------
    str or ndarray of str, shape (...)

    Examples
    --------
    >>> dos_decide([False, True, True, True]), dos_decide([True, True, True, True])
    ('gyro_x', 'star_tracker')
    """
    c = _bool_flags("crossed", crossed, 4)
    n = c.sum(-1)
    quiet = np.array(LOCATIONS[:4])[np.argmin(c, axis=-1)]
    out = np.select([n == 4, n == 3, n > 0], ["star_tracker", quiet, "unknown"], "none")
    return out.item() if out.ndim == 0 else out


# --------------------------------------------------------------------------- ref. [22]


def _window(dt, window_s):
    dt = check_real("dt", dt, 0.0, lo_open=True)
    window_s = check_real("window_s", window_s, 2.0 * dt)
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
        Star-tracker quaternions at interval ``dt``.
    dt : float
        Sample interval, s.
    window_s : float
        Window length, s, >= 2 dt.

    Returns
    -------
    ndarray, shape (..., n - M, 3)
        Rate at times ``t[M:] - window_s/2`` (the estimate for the window ending at
        sample ``k`` is ready at ``t[k]``), rad/s.

    Examples
    --------
    >>> t, w, q = truth_motion(201, 0.1, wobble_deg_s=0.0)
    >>> wq = quaternion_rate(q, 0.1, 10.0)
    >>> bool(np.allclose(wq, w[0], atol=1e-9))
    True
    """
    q = check_finite_array("q_meas", q_meas, shape=(None, 4))
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
    >>> t, w, q = truth_motion(201, 0.1, wobble_deg_s=0.0)
    >>> f = qdiff_fault_estimates(w + 1e-4, q, 0.1, 10.0)
    >>> bool(np.allclose(f, 1e-4, atol=1e-9))
    True
    """
    wg = check_finite_array("omega_g", omega_g)
    if wg.ndim < 2 or wg.shape[-1] not in (3, 4):
        raise ValueError(f"omega_g must have shape (..., n, 3) or (..., n, 4), got {wg.shape}")
    wq = quaternion_rate(q_meas, dt, window_s)
    M = int(round(window_s / dt))
    n = wg.shape[-2]
    if np.shape(q_meas)[-2] != n:
        raise ValueError("omega_g and q_meas must have the same number of samples")
    c = np.concatenate([np.zeros(wg.shape[:-2] + (1, 3)), np.cumsum(wg[..., :3], -2)], -2)
    mean = (c[..., M:n, :] - c[..., : n - M, :]) / M  # gyro intervals k-M .. k-1
    return mean - wq


def qdiff_decide(crossed):
    """Verdict of the quaternion-differentiation method: the gyros whose estimate crossed.

    Parameters
    ----------
    crossed : array_like of bool, shape (..., 3)

    Returns
    -------
    str or ndarray of str: ``"none"`` or the blamed gyros joined by ``"+"``.

    Examples
    --------
    >>> qdiff_decide([True, False, True])
    'gyro_x+gyro_z'
    """
    c = _bool_flags("crossed", crossed, 3)
    names = np.array(["gyro_x", "gyro_y", "gyro_z"])
    flat = c.reshape(-1, 3)
    out = np.array(["+".join(names[row]) or "none" for row in flat], dtype=object)
    out = out.reshape(c.shape[:-1])
    return out.item() if out.ndim == 0 else out


# --------------------------------------------------------------------------- detection


@dataclass
class Diagnosis:
    """Output of :func:`diagnose` (leading batch shape ``...``).

    Attributes
    ----------
    flags : ndarray of bool, shape (..., n, m)
        Residual over its threshold for ``persist`` consecutive armed samples.
    detect_time : ndarray, shape (...)
        First flagged sample time, s; ``inf`` when nothing was detected.
    crossed : ndarray of bool, shape (..., m)
        Residuals flagged within ``confirm_s`` of the detection.
    verdict : str or ndarray of str, shape (...)
        The decision rule applied to ``crossed``.

    Examples
    --------
    >>> d = diagnose(np.arange(5.0), np.ones((5, 4)), np.zeros(4), persist=1)
    >>> float(d.detect_time), d.verdict, d.flags.shape
    (0.0, 'unknown', (5, 4))
    """

    flags: np.ndarray
    detect_time: np.ndarray
    crossed: np.ndarray
    verdict: object


def diagnose(t, residuals, thresholds, *, t_arm=0.0, persist=3, confirm_s=5.0, decide=sos_decide):
    """Threshold logic shared by SOS, DOS and ref. [22].

    A residual is *flagged* at a sample once it has exceeded its threshold for
    ``persist`` consecutive samples at or after ``t_arm``. The first flag is the
    detection; the residuals flagged within ``confirm_s`` seconds after it are the
    *crossed* set, which ``decide`` turns into a verdict (so a residual that lags the
    first one, as a drift estimate lags the gyro parity, still counts).

    Parameters
    ----------
    t : array_like, shape (n,)
        Sample times, s.
    residuals : array_like, shape (..., n, m)
    thresholds : array_like, shape (..., m)
    t_arm : float
        No flag before this time, s.
    persist : int
        Consecutive samples over the threshold needed, >= 1.
    confirm_s : float
        Isolation window after the detection, s, >= 0.
    decide : callable
        ``crossed (..., m) -> verdict`` (:func:`sos_decide`, :func:`dos_decide`,
        :func:`qdiff_decide`).

    Returns
    -------
    Diagnosis

    Examples
    --------
    >>> t = np.arange(10.0); r = np.zeros((10, 4)); r[5:, [0, 3]] = 2.0
    >>> d = diagnose(t, r, np.ones(4), persist=2, confirm_s=1.0)
    >>> float(d.detect_time), d.verdict
    (6.0, 'gyro_x')
    """
    t = check_finite_array("t", t)
    r = check_finite_array("residuals", residuals)
    if t.ndim != 1 or r.ndim < 2 or r.shape[-2] != t.size:
        raise ValueError(f"residuals must have shape (..., n, m) with n = len(t) = {t.size}")
    J = check_finite_array("thresholds", thresholds, shape=(r.shape[-1],))
    t_arm = check_real("t_arm", t_arm)
    persist = check_int("persist", persist, 1, t.size)
    confirm_s = check_real("confirm_s", confirm_s, 0.0)
    over = (r > J[..., None, :]) & (t >= t_arm)[:, None]
    c = np.cumsum(over, axis=-2)
    lagged = np.concatenate([np.zeros_like(c[..., :persist, :]), c[..., :-persist, :]], -2)
    flags = (c - lagged) >= persist
    anyf = flags.any(-1)
    det = np.where(anyf.any(-1), np.argmax(anyf, axis=-1), -1)
    detect_time = np.where(det >= 0, t[np.maximum(det, 0)], math.inf)
    in_win = (t >= detect_time[..., None]) & (t <= detect_time[..., None] + confirm_s)
    crossed = (flags & in_win[..., None]).any(-2)
    return Diagnosis(flags, detect_time, crossed, decide(crossed))


# --------------------------------------------------------------------------- simulation


@dataclass(frozen=True)
class SimConfig:
    """Every setting of a run; our choices where the paper is silent are the defaults.

    Attributes
    ----------
    duration : float
        Run length, s (default 100).
    dt : float
        Gyro and star-tracker sample interval, s (default 0.1: 10 Hz).
    drifts_deg_per_h : tuple of 4 float
        Gyro drifts (paper: 50, 40, -50, 45 deg/h).
    gyro_noise_deg_per_h : float
        Gyro noise per sample, 1 sigma (paper: 0.05 deg/h).
    star_noise_deg : float
        Star-tracker noise per axis, 1 sigma (paper: 0.00333 deg).
    skew_axis : tuple of 3 float
        Skewed-gyro axis (default equal-angle ``[1, 1, 1]/sqrt(3)``).
    q0 : tuple of 4 float
        Initial true attitude.
    omega_orbit_deg_s, wobble_deg_s, wobble_period : float
        Truth motion, see :func:`truth_rate`.
    drift_walk_deg_per_h_sqrt_s : float
        Filter drift random walk, deg/h per sqrt(s) (default 1): sets how fast the drift
        estimates follow a change (time constant ~2 s at 10 Hz).
    drift_sigma0_deg_per_h : float
        Initial drift uncertainty of the filters (default 100 deg/h).
    n_sigma : float
        Thresholds in predicted standard deviations of each residual (default 5).
    t_cal : tuple of 2 float
        Fault-free window where references are learned, s (default 20-40 s); the
        detectors are armed at its end.
    persist : int
        Consecutive samples over threshold for a flag (default 3).
    confirm_s : float
        Isolation window after detection, s (default 5).
    qdiff_window_s : float
        Differentiation window of ref. [22], s (default 10).
    dos : bool
        Also run the DOS bank (the SOS filter is the bank's filter 4, fed by the
        orthogonal triad; the numbers are identical).

    Examples
    --------
    >>> cfg = SimConfig(duration=60.0, n_sigma=4.0)
    >>> cfg.n, cfg.t_cal
    (601, (20.0, 40.0))
    """

    duration: float = 100.0
    dt: float = 0.1
    drifts_deg_per_h: tuple = PAPER_DRIFTS_DEG_PER_H
    gyro_noise_deg_per_h: float = PAPER_GYRO_NOISE_DEG_PER_H
    star_noise_deg: float = PAPER_STAR_NOISE_DEG
    skew_axis: tuple = tuple(SKEW_AXIS)
    q0: tuple = tuple(DEFAULT_Q0)
    omega_orbit_deg_s: float = 0.06
    wobble_deg_s: float = 0.01
    wobble_period: float = 300.0
    drift_walk_deg_per_h_sqrt_s: float = 1.0
    drift_sigma0_deg_per_h: float = 100.0
    n_sigma: float = 5.0
    t_cal: tuple = (20.0, 40.0)
    persist: int = 3
    confirm_s: float = 5.0
    qdiff_window_s: float = 10.0
    dos: bool = True

    def __post_init__(self):
        check_real("duration", self.duration, 0.0, lo_open=True)
        check_real("dt", self.dt, 0.0, 10.0, lo_open=True)
        if self.duration < 2 * self.dt:
            raise ValueError(f"duration must be >= 2 dt = {2 * self.dt}, got {self.duration}")
        check_finite_array("drifts_deg_per_h", self.drifts_deg_per_h, shape=(4,))
        check_real("gyro_noise_deg_per_h", self.gyro_noise_deg_per_h, 0.0, lo_open=True)
        check_real("star_noise_deg", self.star_noise_deg, 0.0, 1.0, lo_open=True)
        gyro_matrix(self.skew_axis)
        quat_normalize(self.q0)
        check_real("drift_walk_deg_per_h_sqrt_s", self.drift_walk_deg_per_h_sqrt_s, 0.0)
        check_real("drift_sigma0_deg_per_h", self.drift_sigma0_deg_per_h, 0.0, lo_open=True)
        check_real("n_sigma", self.n_sigma, 0.0, lo_open=True)
        cal = check_finite_array("t_cal", self.t_cal, shape=(2,))
        if cal.ndim != 1 or not (0.0 <= cal[0] < cal[1] <= self.duration):
            raise ValueError(f"t_cal must satisfy 0 <= t_cal[0] < t_cal[1] <= duration, got {cal}")
        if cal[1] - cal[0] < 2 * self.dt:
            raise ValueError("t_cal must span at least two samples")
        check_int("persist", self.persist, 1)
        check_real("confirm_s", self.confirm_s, 0.0)
        w = check_real("qdiff_window_s", self.qdiff_window_s, 2 * self.dt)
        if max(w, cal[0] + 0.5 * w) >= cal[1]:
            raise ValueError(
                "qdiff_window_s must leave an estimate inside t_cal: need "
                f"max(w, t_cal[0] + w/2) < t_cal[1], got w = {w}, t_cal = {tuple(cal)}"
            )
        if not isinstance(self.dos, bool):
            raise ValueError(f"dos must be True or False, got {self.dos!r}")

    @property
    def n(self):
        """Number of samples."""
        return int(round(self.duration / self.dt)) + 1


@dataclass
class AttitudeRun:
    """One simulated run (from :func:`simulate`). Arrays are in SI units.

    Attributes
    ----------
    t : ndarray, shape (n,)
    config : SimConfig
    faults : tuple of Fault
    truth : str
        Faulty sensor (a :data:`LOCATIONS` entry) or ``"none"``.
    onset : float
        Earliest fault onset, s (``inf`` without faults).
    w_true, q_true : ndarray, shapes (n, 3), (n, 4)
    omega_g, q_meas : ndarray, shapes (n, 4), (n, 4)
    q_hat, drift_hat : ndarray, shapes (n, 4), (n, 3)
        The SOS filter's estimates.
    att_err : ndarray, shape (n, 3)
        Estimation error of the attitude, rad.
    armed : ndarray of bool, shape (n,)
        Detectors armed (``t >= t_cal[1]``); before, residuals use the references
        learned at arming and are shown for display only.
    sos_r, sos_J : ndarray, shapes (n, 4), (4,)
        SOS residuals and thresholds, rad/s.
    sos : Diagnosis
    dos_r, dos_J : ndarray, shapes (n, 4), (4,)
        DOS residuals and thresholds (zeros when ``config.dos`` is False).
    dos : Diagnosis or None
    t_qd : ndarray, shape (m,)
        Times (window middles) of the ref. [22] estimates.
    qd_f, qd_J : ndarray, shapes (m, 3), (3,)
        Ref. [22] gyro-fault estimates minus their references, and thresholds, rad/s.
    qd : Diagnosis
        Decided at the times the estimates become available.
    refs : dict
        References learned in the calibration window: ``"drift"`` (3,), ``"parity"``,
        ``"qdiff"`` (3,) and, with DOS, ``"dos"`` (4, 3); rad/s.

    Examples
    --------
    >>> run = simulate(duration=50.0, dos=False)
    >>> run.sos_r.shape, run.sos.verdict, run.dos is None
    ((501, 4), 'none', True)
    """

    t: np.ndarray
    config: SimConfig
    faults: tuple
    truth: str
    onset: float
    w_true: np.ndarray = field(repr=False)
    q_true: np.ndarray = field(repr=False)
    omega_g: np.ndarray = field(repr=False)
    q_meas: np.ndarray = field(repr=False)
    q_hat: np.ndarray = field(repr=False)
    drift_hat: np.ndarray = field(repr=False)
    att_err: np.ndarray = field(repr=False)
    armed: np.ndarray = field(repr=False)
    sos_r: np.ndarray = field(repr=False)
    sos_J: np.ndarray = field(repr=False)
    sos: Diagnosis = field(repr=False)
    dos_r: np.ndarray = field(repr=False)
    dos_J: np.ndarray = field(repr=False)
    dos: Diagnosis | None = field(repr=False)
    t_qd: np.ndarray = field(repr=False)
    qd_f: np.ndarray = field(repr=False)
    qd_J: np.ndarray = field(repr=False)
    qd: Diagnosis = field(repr=False)
    refs: dict = field(default_factory=dict, repr=False)


def _truth_of(faults):
    locs = set()
    for f in faults:
        if f.sensor == "star_tracker":
            locs.add("star_tracker")
        elif f.sensor == "gyro" and f.component is not None:
            locs.add(LOCATIONS[f.component])
        else:
            locs.add("unknown")
    if not locs:
        return "none"
    return locs.pop() if len(locs) == 1 else "unknown"


def _filter_bank(omega_g, q_meas, cfg, n_filters):
    """Run the DOS bank (or only its filter 4, the SOS filter) over a batch of runs.

    omega_g, q_meas: (B, n, 4). Returns q_hat (B, n, F, 4), d_hat (B, n, F, 3) and the
    drift covariance blocks at every sample (B, n, F, 3, 3), F = 4 or 1.
    """
    T = dos_rate_matrices(cfg.skew_axis)
    groups = DOS_GROUPS
    if n_filters == 1:
        T, groups = T[3:], groups[3:]
    mix = np.zeros((len(groups), 3, 4))  # w_tilde_j = T_j w_g[group_j]
    for j, g in enumerate(groups):
        mix[j][:, list(g)] = T[j]
    w_tilde = np.einsum("fij,bnj->bnfi", mix, omega_g)
    TT = T @ np.swapaxes(T, -1, -2)
    dt = cfg.dt
    sg = cfg.gyro_noise_deg_per_h * DEG_PER_H
    gyro_cov = sg**2 * TT
    drift_cov = (cfg.drift_walk_deg_per_h_sqrt_s * DEG_PER_H) ** 2 * dt * TT
    R = (0.5 * math.radians(cfg.star_noise_deg)) ** 2 * np.eye(4)
    B, n, _ = omega_g.shape
    F = len(groups)
    qm = np.broadcast_to(q_meas[:, :, None, :], (B, n, F, 4))
    x, P = ekf_init(
        qm[:, 0],
        attitude_sigma=math.radians(cfg.star_noise_deg),
        drift_sigma=(cfg.drift_sigma0_deg_per_h * DEG_PER_H) ** 2 * TT,
    )
    q_hat = np.empty((B, n, F, 4))
    d_hat = np.empty((B, n, F, 3))
    P_dd = np.empty((B, n, F, 3, 3))
    for k in range(n):
        if k:
            x, P = _predict(x, P, w_tilde[:, k - 1], dt, gyro_cov, drift_cov)
        x, P, _ = _update(x, P, qm[:, k], R)
        q_hat[:, k] = x[..., :4]
        d_hat[:, k] = x[..., 4:]
        P_dd[:, k] = P[..., 4:, 4:]
    return q_hat, d_hat, P_dd


def _tail_prob(n_sigma):
    return math.erfc(n_sigma / math.sqrt(2.0))


def _batch(omega_g, q_meas, cfg):
    """Filters, residuals, thresholds and diagnoses for a batch (B, n, 4) of runs."""
    from scipy.stats import chi2

    t = np.arange(cfg.n) * cfg.dt
    cal = (t >= cfg.t_cal[0]) & (t < cfg.t_cal[1])
    t_arm = cfg.t_cal[1]
    F = 4 if cfg.dos else 1
    q_hat, d_hat, P_dd = _filter_bank(omega_g, q_meas, cfg, F)
    k_arm = int(np.searchsorted(t, t_arm - 1e-9))
    k_arm = min(k_arm, cfg.n - 1)
    out = {"t": t, "q_hat": q_hat[:, :, -1], "drift_hat": d_hat[:, :, -1]}
    kw = dict(t_arm=t_arm, persist=cfg.persist, confirm_s=cfg.confirm_s)
    # SOS: the bank's last filter (orthogonal triad) plus the gyro parity
    b = d_hat[:, :, -1]
    parity = gyro_parity(omega_g, cfg.skew_axis)
    b_ref = b[:, cal].mean(axis=1)
    p_ref = parity[:, cal].mean(axis=1)
    sos_r = sos_residuals(b, omega_g, b_ref[:, None], p_ref[:, None], cfg.skew_axis)
    sig_b = np.sqrt(np.diagonal(P_dd[:, k_arm, -1], axis1=-2, axis2=-1))
    sig_p = cfg.gyro_noise_deg_per_h * DEG_PER_H * math.sqrt(2.0)  # |[-h4^T 1]| = sqrt(2)
    sos_J = cfg.n_sigma * np.concatenate([sig_b, np.full((len(b), 1), sig_p)], axis=1)
    out.update(sos_r=sos_r, sos_J=sos_J, sos=diagnose(t, sos_r, sos_J, decide=sos_decide, **kw))
    if cfg.dos:
        d_ref = d_hat[:, cal].mean(axis=1)
        dos_r = dos_residuals(d_hat, d_ref[:, None])
        scale = np.sqrt(np.trace(P_dd[:, k_arm], axis1=-2, axis2=-1) / 3.0)
        dos_J = math.sqrt(chi2.isf(_tail_prob(cfg.n_sigma), 3)) * scale
        dos = diagnose(t, dos_r, dos_J, decide=dos_decide, **kw)
    else:
        dos_r = np.zeros_like(sos_r)
        dos_J = np.zeros_like(sos_J)
        dos = None
    out.update(dos_r=dos_r, dos_J=dos_J, dos=dos)
    # ref. [22]: quaternion differentiation, decided when each estimate is available
    M = int(round(cfg.qdiff_window_s / cfg.dt))
    f = qdiff_fault_estimates(omega_g, q_meas, cfg.dt, cfg.qdiff_window_s)
    t_ready = t[M:]
    cal_q = (t_ready - 0.5 * M * cfg.dt >= cfg.t_cal[0]) & (t_ready < cfg.t_cal[1])
    f_ref = f[:, cal_q].mean(axis=1)
    f = f - f_ref[:, None]
    # slope of M + 1 samples with sigma/2 noise per component, times 2 (w = 2 Xi^T q_dot)
    sig_q = math.radians(cfg.star_noise_deg) * math.sqrt(12.0 / (M * (M + 1) * (M + 2))) / cfg.dt
    qd_J = np.full(3, cfg.n_sigma * sig_q)
    qd = diagnose(t_ready, np.abs(f), qd_J, decide=qdiff_decide, **kw)
    out.update(t_qd=t_ready - 0.5 * M * cfg.dt, qd_f=f, qd_J=qd_J, qd=qd)
    out["refs"] = {"drift": b_ref, "parity": p_ref, "qdiff": f_ref}
    if cfg.dos:
        out["refs"]["dos"] = d_ref
    return out


def _measurements(cfg, faults, rng, truth=None):
    t, w, q = truth if truth is not None else truth_motion(
        cfg.n, cfg.dt, q0=cfg.q0, omega_orbit_deg_s=cfg.omega_orbit_deg_s,
        wobble_deg_s=cfg.wobble_deg_s, wobble_period=cfg.wobble_period,
    )
    wg = gyro_measurements(
        t, w, drifts_deg_per_h=cfg.drifts_deg_per_h,
        noise_deg_per_h=cfg.gyro_noise_deg_per_h, skew_axis=cfg.skew_axis,
        faults=faults, rng=rng,
    )
    qs = star_tracker_measurements(t, q, noise_deg=cfg.star_noise_deg, faults=faults, rng=rng)
    return (t, w, q), wg, qs


def _config(config, changes):
    if config is None:
        config = SimConfig()
    elif not isinstance(config, SimConfig):
        raise ValueError(f"config must be a SimConfig or None, got {type(config).__name__}")
    try:
        return dataclasses.replace(config, **changes)
    except TypeError as exc:
        raise ValueError(f"unknown SimConfig setting: {exc}") from None


def _faults(faults):
    if isinstance(faults, Fault):
        faults = (faults,)
    faults = tuple(faults)
    for f in faults:
        if not isinstance(f, Fault):
            raise ValueError(f"faults must be Fault objects, got {type(f).__name__}")
    return faults


def simulate(faults=(), config=None, *, rng=None, **changes):
    """Simulate one run: truth, sensors, faults, the filters and all three diagnoses.

    Parameters
    ----------
    faults : Fault or sequence of Fault
        From :func:`make_fault` (sensors ``"gyro"`` and ``"star_tracker"``).
    config : SimConfig, optional
        Settings (default :class:`SimConfig`).
    rng : numpy.random.Generator or int, optional
        Seed of the sensor noise (default 0: reproducible).
    **changes
        Overrides of ``config`` fields, e.g. ``n_sigma=4``.

    Returns
    -------
    AttitudeRun

    Examples
    --------
    >>> run = simulate(make_fault("gyro_x", "step", 36 * DEG_PER_H), duration=60.0)
    >>> run.sos.verdict, run.dos.verdict
    ('gyro_x', 'gyro_x')
    """
    cfg = _config(config, changes)
    faults = _faults(faults)
    rng = make_rng(rng)
    (t, w, q), wg, qs = _measurements(cfg, faults, rng)
    res = _batch(wg[None], qs[None], cfg)
    q_hat = res["q_hat"][0]
    from xnavlab.core.quaternions import attitude_error

    def pick(d):
        if d is None:
            return None
        return Diagnosis(d.flags[0], d.detect_time[0], d.crossed[0], d.verdict[0])

    return AttitudeRun(
        t=t, config=cfg, faults=faults, truth=_truth_of(faults),
        onset=min((f.onset for f in faults), default=math.inf),
        w_true=w, q_true=q, omega_g=wg, q_meas=qs, q_hat=q_hat,
        drift_hat=res["drift_hat"][0], att_err=attitude_error(q_hat, q),
        armed=t >= cfg.t_cal[1],
        sos_r=res["sos_r"][0], sos_J=res["sos_J"][0], sos=pick(res["sos"]),
        dos_r=res["dos_r"][0], dos_J=res["dos_J"][0], dos=pick(res["dos"]),
        t_qd=res["t_qd"], qd_f=res["qd_f"][0], qd_J=res["qd_J"], qd=pick(res["qd"]),
        refs={k: (v[0] if np.ndim(v) else v) for k, v in res["refs"].items()},
    )


# --------------------------------------------------------------------------- per-step monitors


class SOSMonitor:
    """SOS on board, one sample at a time: one EKF plus the four residuals.

    Parameters
    ----------
    q0 : array_like, shape (4,)
        First star-tracker quaternion.
    config : SimConfig, optional
    drift_ref : array_like, shape (3,), optional
        Drift references, rad/s (default zeros: the paper's literal ``|b_hat|``).
    parity_ref : float
        Parity reference, rad/s.

    Examples
    --------
    >>> m = SOSMonitor(DEFAULT_Q0)
    >>> m.step(gyro_matrix() @ np.zeros(3), DEFAULT_Q0).shape
    (4,)
    """

    n_filters = 1

    def __init__(self, q0, config=None, drift_ref=None, parity_ref=0.0):
        cfg = _config(config, {})
        self.config = cfg
        self.filters = [self._make(q0, cfg, np.eye(3))]
        self.h4 = gyro_matrix(cfg.skew_axis)[3]
        self.drift_ref = np.zeros(3) if drift_ref is None else check_finite_array(
            "drift_ref", drift_ref, shape=(3,))
        self.parity_ref = check_real("parity_ref", parity_ref)
        self._first = True

    @staticmethod
    def _make(q0, cfg, T):
        TT = T @ T.T
        f = AttitudeEKF(
            q0, cfg.dt, cfg.gyro_noise_deg_per_h * DEG_PER_H,
            math.radians(cfg.star_noise_deg), cfg.drift_walk_deg_per_h_sqrt_s * DEG_PER_H,
            cfg.drift_sigma0_deg_per_h * DEG_PER_H,
        )
        f.gyro_cov = f.gyro_cov @ TT  # noise of T w_g: sigma^2 T T^T
        f.drift_cov = f.drift_cov @ TT
        f.P[4:, 4:] = f.P[4:, 4:] @ TT
        return f

    def step(self, omega_g, q_meas):
        """Process one gyro sample (4,) and star-tracker quaternion (4,); residuals (4,).

        The gyro sample of step ``k`` drives the prediction to ``k + 1``, as in
        :func:`simulate`.
        """
        wg = _sample("omega_g", omega_g, 4)
        f = self.filters[0]
        if not self._first:
            f.predict(self._w_prev)
        f.update(q_meas)
        self._first = False
        self._w_prev = wg[:3]
        r = np.abs(f.drift - self.drift_ref)  # paper eq. (35)
        r4 = abs(wg[3] - self.h4 @ wg[:3] - self.parity_ref)  # paper eq. (37)
        return np.append(r, r4)


class DOSMonitor(SOSMonitor):
    """DOS on board: four EKFs, filter ``j`` fed by the gyros of :data:`DOS_GROUPS` ``[j]``.

    Parameters
    ----------
    q0 : array_like, shape (4,)
    config : SimConfig, optional
    drift_ref : array_like, shape (4, 3), optional
        References of the four filters' drifts, rad/s (default zeros).

    Examples
    --------
    >>> m = DOSMonitor(DEFAULT_Q0)
    >>> m.step(gyro_matrix() @ np.zeros(3), DEFAULT_Q0).shape
    (4,)
    """

    n_filters = 4

    def __init__(self, q0, config=None, drift_ref=None):
        cfg = _config(config, {})
        self.config = cfg
        self.T = dos_rate_matrices(cfg.skew_axis)
        self.filters = [self._make(q0, cfg, T) for T in self.T]
        self.mix = np.zeros((4, 3, 4))  # w_tilde_j = T_j w_g[group_j] = mix_j w_g
        for j, g in enumerate(DOS_GROUPS):
            self.mix[j][:, list(g)] = self.T[j]
        self.drift_ref = np.zeros((4, 3)) if drift_ref is None else check_finite_array(
            "drift_ref", drift_ref, shape=(4, 3))
        self._first = True

    def step(self, omega_g, q_meas):
        """Process one sample; the four residuals ``|d_j_hat - d_j_ref|`` (4,), rad/s."""
        wg = _sample("omega_g", omega_g, 4)
        r = np.empty(4)
        for j, (f, mix) in enumerate(zip(self.filters, self.mix, strict=True)):
            if not self._first:
                f.predict(mix @ self._w_prev)
            f.update(q_meas)
            r[j] = np.linalg.norm(f.drift - self.drift_ref[j])
        self._first = False
        self._w_prev = wg
        return r


def time_sos_dos(n_steps=500, repeats=3, config=None, rng=None):
    """Measured cost per sample of :class:`DOSMonitor` against :class:`SOSMonitor`.

    Both run on the same simulated data in this process; each is timed with
    :func:`time.perf_counter` over ``n_steps`` samples, ``repeats`` times alternately,
    and the fastest repeat is kept (the least disturbed by the machine).

    Parameters
    ----------
    n_steps : int
        Samples per timing, >= 10.
    repeats : int
        Timings per scheme, >= 1.
    config : SimConfig, optional
    rng : numpy.random.Generator or int, optional

    Returns
    -------
    dict
        ``sos_us`` and ``dos_us`` (microseconds per sample) and ``ratio`` (DOS/SOS).

    Examples
    --------
    >>> r = time_sos_dos(n_steps=20, repeats=1)
    >>> r["ratio"] > 1.0
    True
    """
    n_steps = check_int("n_steps", n_steps, 10)
    repeats = check_int("repeats", repeats, 1)
    cfg = _config(config, {})
    if cfg.n < n_steps:
        cfg = dataclasses.replace(cfg, duration=n_steps * cfg.dt)
    (_, _, _), wg, qs = _measurements(cfg, (), make_rng(rng))
    best = {"sos": math.inf, "dos": math.inf}
    for _ in range(repeats):
        for name, cls in (("sos", SOSMonitor), ("dos", DOSMonitor)):
            mon = cls(qs[0], cfg)
            t0 = time.perf_counter()
            for k in range(n_steps):
                mon.step(wg[k], qs[k])
            best[name] = min(best[name], time.perf_counter() - t0)
    return {
        "sos_us": 1e6 * best["sos"] / n_steps,
        "dos_us": 1e6 * best["dos"] / n_steps,
        "ratio": best["dos"] / best["sos"],
    }


# --------------------------------------------------------------------------- Monte Carlo


def isolation_monte_carlo(
    n_runs=10,
    *,
    locations=LOCATIONS,
    kinds=("step", "ramp"),
    sizes=(0.3, 1.0, 10.0),
    onset=50.0,
    config=None,
    rng=None,
):
    """Isolation statistics of SOS and DOS over fault location, kind and size.

    Every case runs ``n_runs`` seeded runs (all cases in one vectorised batch), plus
    ``n_runs`` fault-free runs. Per case and method:

    ``correct``
        fraction detected after the onset and isolated to the true location (for the
        fault-free runs: fraction that stayed silent);
    ``missed``
        fraction never detected;
    ``false_alarm``
        fraction detected before the onset (any detection for fault-free runs);
    ``delay_s``
        mean detection delay of the runs detected after the onset (``inf`` if none).

    Parameters
    ----------
    n_runs : int
        Runs per case, >= 1.
    locations : sequence of str
        Subset of :data:`LOCATIONS`.
    kinds : sequence of {"step", "ramp"}
    sizes : sequence of float
        Multiples of :data:`DEFAULT_MAGNITUDES`, > 0.
    onset : float
        Fault onset, s (after ``config.t_cal[1]``).
    config : SimConfig, optional
        Default: :class:`SimConfig` with ``duration = onset + 30``.
    rng : numpy.random.Generator or int, optional

    Returns
    -------
    list of dict
        One row per (location, kind, size, method) with the keys above plus
        ``location``, ``kind``, ``size`` (SI magnitude), ``factor`` and ``method``.

    Examples
    --------
    >>> rows = isolation_monte_carlo(1, locations=["gyro_x"], kinds=["step"], sizes=[1.0])
    >>> [(r["method"], r["correct"]) for r in rows if r["location"] == "gyro_x"]
    [('SOS', 1.0), ('DOS', 1.0)]
    """
    n_runs = check_int("n_runs", n_runs, 1)
    for loc in locations:
        check_choice("locations", loc, LOCATIONS)
    for kind in kinds:
        check_choice("kinds", kind, ("step", "ramp"))
    sizes = [check_real("sizes", s, 0.0, lo_open=True) for s in sizes]
    onset = check_real("onset", onset, 0.0, lo_open=True)
    if config is None:
        config = SimConfig(duration=onset + 30.0)
    cfg = _config(config, {"dos": True})
    if not (cfg.t_cal[1] <= onset < cfg.duration):
        raise ValueError(
            f"onset must be in [t_cal[1], duration) = [{cfg.t_cal[1]}, {cfg.duration}), "
            f"got {onset}"
        )
    rng = make_rng(rng)
    cases = [("none", "-", 0.0, 0.0)]
    for loc in locations:
        sensor = "star_tracker" if loc == "star_tracker" else "gyro"
        for kind in kinds:
            for s in sizes:
                cases.append((loc, kind, s, s * DEFAULT_MAGNITUDES[(sensor, kind)]))
    truth = truth_motion(
        cfg.n, cfg.dt, q0=cfg.q0, omega_orbit_deg_s=cfg.omega_orbit_deg_s,
        wobble_deg_s=cfg.wobble_deg_s, wobble_period=cfg.wobble_period,
    )
    wgs, qss = [], []
    for loc, kind, _, mag in cases:
        faults = () if loc == "none" else (make_fault(loc, kind, mag, onset),)
        for _ in range(n_runs):
            _, wg, qs = _measurements(cfg, faults, rng, truth)
            wgs.append(wg)
            qss.append(qs)
    res = _batch(np.stack(wgs), np.stack(qss), cfg)
    rows = []
    for i, (loc, kind, factor, mag) in enumerate(cases):
        sl = slice(i * n_runs, (i + 1) * n_runs)
        for method in ("SOS", "DOS"):
            d = res[method.lower()]
            det = np.asarray(d.detect_time[sl], dtype=float)
            verdict = np.asarray(d.verdict[sl])
            if loc == "none":
                fa = np.isfinite(det)
                after = np.zeros_like(fa)
            else:
                fa = det < onset
                after = np.isfinite(det) & ~fa
            correct = ~fa if loc == "none" else after & (verdict == loc)
            delay = float(np.mean(det[after] - onset)) if after.any() else math.inf
            rows.append({
                "location": loc, "kind": kind, "factor": factor, "size": mag,
                "method": method, "correct": float(correct.mean()),
                "missed": float((~np.isfinite(det)).mean()) if loc != "none" else 0.0,
                "false_alarm": float(fa.mean()), "delay_s": delay,
            })
    return rows


def _size_label(loc, kind, size):
    if loc == "none":
        return "-"
    if loc == "star_tracker":
        return f"{size:.1e}" + ("/s" if kind == "ramp" else "")
    return f"{size / DEG_PER_H:g} deg/h" + ("/s" if kind == "ramp" else "")


def isolation_table(rows):
    """Markdown table of :func:`isolation_monte_carlo` rows, SOS and DOS side by side.

    Examples
    --------
    >>> print(isolation_table([]).splitlines()[0])
    | fault | kind | size | SOS correct | SOS missed | SOS false alarm | SOS delay (s) | DOS correct | DOS missed | DOS false alarm | DOS delay (s) |
    """  # noqa: E501
    head = ["fault", "kind", "size"]
    for m in ("SOS", "DOS"):
        head += [f"{m} correct", f"{m} missed", f"{m} false alarm", f"{m} delay (s)"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    by = {}
    for r in rows:
        by.setdefault((r["location"], r["kind"], r["factor"]), {})[r["method"]] = r
    for (loc, kind, _), pair in by.items():
        cells = [loc, kind, _size_label(loc, kind, next(iter(pair.values()))["size"])]
        for m in ("SOS", "DOS"):
            r = pair.get(m)
            if r is None:
                cells += ["-"] * 4
                continue
            delay = "-" if not math.isfinite(r["delay_s"]) else f"{r['delay_s']:.1f}"
            cells += [f"{r['correct']:.0%}", f"{r['missed']:.0%}",
                      f"{r['false_alarm']:.0%}", delay]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


# --------------------------------------------------------------------------- plotting


def plot_residuals(run, method="sos", axes=None):
    """Plot a run's residuals against their thresholds (deg/h), one panel per residual.

    Parameters
    ----------
    run : AttitudeRun
    method : {"sos", "dos", "qdiff"}
    axes : sequence of matplotlib Axes, optional
        Four axes (three for ``"qdiff"``); a new figure when omitted.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import matplotlib; matplotlib.use("Agg")
    >>> fig = plot_residuals(simulate(duration=50.0))
    >>> len(fig.axes)
    4
    """
    import matplotlib.pyplot as plt

    check_choice("method", method, ("sos", "dos", "qdiff"))
    if not isinstance(run, AttitudeRun):
        raise ValueError(f"run must be an AttitudeRun, got {type(run).__name__}")
    if method == "dos" and run.dos is None:
        raise ValueError("method='dos' needs a run simulated with dos=True")
    if method == "sos":
        t, r, J, d = run.t, run.sos_r, run.sos_J, run.sos
        names = ["$r_1$ (x)", "$r_2$ (y)", "$r_3$ (z)", "$r_4$ (parity)"]
    elif method == "dos":
        t, r, J, d = run.t, run.dos_r, run.dos_J, run.dos
        names = [f"$R_{j + 1}$ (no {g})" for j, g in enumerate(("x", "y", "z", "skew"))]
    else:
        t, r, J, d = run.t_qd, np.abs(run.qd_f), run.qd_J, run.qd
        names = ["$|f_x|$", "$|f_y|$", "$|f_z|$"]
    m = r.shape[1]
    if axes is None:
        fig, axes = plt.subplots(m, 1, sharex=True, figsize=(7, 1.5 * m + 1), squeeze=False)
        axes = axes[:, 0]
    fig = axes[0].figure
    for i, ax in enumerate(axes[:m]):
        ax.plot(t, r[:, i] / DEG_PER_H, lw=0.8)
        ax.axhline(J[i] / DEG_PER_H, color="C3", ls="--", lw=0.8)
        ax.axvspan(t[0], run.config.t_cal[1], color="0.9", lw=0)
        if math.isfinite(run.onset):
            ax.axvline(run.onset, color="k", ls=":", lw=0.8)
        top = max(4.0 * J[i], float(np.max(r[t >= run.config.t_cal[1], i], initial=0.0)) * 1.1)
        ax.set_ylim(0.0, top / DEG_PER_H)
        ax.set_ylabel(names[i] + "\n deg/h", fontsize=8)
    verdict = d.verdict
    det = float(d.detect_time)
    if not math.isfinite(det):
        when = "no detection"
    elif math.isfinite(run.onset):
        when = f"detected {det - run.onset:+.1f} s after onset"
    else:
        when = f"detected at {det:.1f} s"
    axes[0].set_title(f"{method.upper()}: verdict {verdict} ({when}); truth {run.truth}",
                      fontsize=9)
    axes[m - 1].set_xlabel("t (s)")
    return fig


def plot_fault_case(location="gyro_x", kind="ramp", size=10.0, n_sigma=5.0, *, rng=None):
    """Simulate one fault and plot its SOS and DOS residuals side by side.

    A pure function of its arguments (the sensor noise is seeded): the chapter's slider
    calls it.

    Parameters
    ----------
    location : {"gyro_x", "gyro_y", "gyro_z", "gyro_skew", "star_tracker"}
    kind : {"step", "ramp"}
    size : float
        Multiple of the reference size :data:`DEFAULT_MAGNITUDES` of ``(sensor, kind)``, > 0.
    n_sigma : float
        Threshold multiplier of :func:`simulate`, > 0.
    rng : numpy.random.Generator or int, optional
        Seed of the sensor noise (default 0, as :func:`simulate`).

    Returns
    -------
    matplotlib.figure.Figure
        Four rows (the residuals), SOS left and DOS right, as :func:`plot_residuals`; not
        registered with pyplot.

    Examples
    --------
    >>> fig = plot_fault_case("gyro_x", "step", 1.0)
    >>> len(fig.axes), fig.axes[0].get_title()[:23]
    (8, 'SOS: verdict gyro_x (de')
    """
    check_choice("location", location, LOCATIONS)
    check_choice("kind", kind, ("step", "ramp"))
    size = check_real("size", size, 0.0, lo_open=True)
    sensor = "star_tracker" if location == "star_tracker" else "gyro"
    run = simulate(make_fault(location, kind, size * DEFAULT_MAGNITUDES[(sensor, kind)]),
                   n_sigma=n_sigma, rng=rng)
    from matplotlib.figure import Figure

    fig = Figure(figsize=(12, 6.5), layout="constrained")
    axes = fig.subplots(4, 2, sharex=True)
    plot_residuals(run, "sos", axes=axes[:, 0])
    plot_residuals(run, "dos", axes=axes[:, 1])
    return fig
