"""One simulated run, or a batch: truth, sensors, faults, the filters and all three diagnoses.

:class:`SimConfig` holds every setting, with our choices where the paper is silent as the
defaults; :func:`simulate` runs the truth motion (:mod:`xnavlab.attitude.motion`), the
sensors with injected faults (:mod:`xnavlab.attitude.sensors`), the EKF bank
(:mod:`xnavlab.attitude.ekf`; the SOS filter is the DOS bank's filter 4, fed by the
orthogonal triad) and the three diagnoses (SOS, DOS, ref. [22]), vectorised over the
filters, and returns an :class:`AttitudeRun`.

The two building blocks are public for batched studies (:mod:`xnavlab.attitude.montecarlo`)
and the timing of the on-board monitors (:mod:`xnavlab.attitude.monitors`):
:func:`simulate_sensors` (one run's truth and sensor outputs) and :func:`diagnose_batch`
(filters, residuals, thresholds and diagnoses of a batch of runs); :func:`make_config`
resolves a ``config`` argument with field overrides.

Units are SI inside (rad, rad/s, s); names say otherwise (``drifts_deg_per_h``).
"""

from __future__ import annotations

import dataclasses
import inspect
import math
from dataclasses import dataclass, field

import numpy as np

from xnavlab.attitude._checks import BYTES_PER_SAMPLE, MAX_SAMPLES, check_quaternion
from xnavlab.attitude.diagnosis import (
    Diagnosis,
    diagnose,
    dos_decide,
    qdiff_decide,
    sos_decide,
)
from xnavlab.attitude.differentiation import qdiff_fault_estimates
from xnavlab.attitude.dos import DOS_GROUPS, dos_rate_matrices, dos_residuals
from xnavlab.attitude.ekf import ekf_init
from xnavlab.attitude.motion import DEFAULT_Q0, truth_motion
from xnavlab.attitude.sensors import (
    DEG_PER_H,
    LOCATIONS,
    MAX_DEG_PER_H,
    PAPER_DRIFTS_DEG_PER_H,
    PAPER_GYRO_NOISE_DEG_PER_H,
    PAPER_STAR_NOISE_DEG,
    SKEW_AXIS,
    gyro_matrix,
    gyro_measurements,
    star_tracker_measurements,
)
from xnavlab.attitude.sos import gyro_parity, sos_residuals
from xnavlab.core.distributions import chi2_isf
from xnavlab.core.faults import Fault, check_faults
from xnavlab.core.quaternions import MAX_ANGLE, attitude_error
from xnavlab.core.validate import (
    check_bool,
    check_finite_array,
    check_int,
    check_real,
    make_rng,
    shown,
)
from xnavlab.core.validate import check_shape as _check_shape

__all__ = [
    "SimConfig",
    "AttitudeRun",
    "simulate",
    "simulate_sensors",
    "diagnose_batch",
    "make_config",
    "SENSORS",
    "check_faults_in_run",
]


@dataclass(frozen=True)
class SimConfig:
    """Every setting of a run; our choices where the paper is silent are the defaults.

    Attributes
    ----------
    duration : float
        Run length, s, in (0, 1e6] and at most 1.6e6 samples, ``(1.6e6 - 1) dt`` (159,999.9 s
        at 0.1 s): a run takes about 1,200 bytes a sample at its peak, so 1.6e6 samples about
        2 GB (``_checks.MAX_SAMPLES``); default 100.
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
        Initial true attitude (non-zero; normalised by :func:`~.motion.truth_motion`).
    omega_orbit_deg_s, wobble_deg_s, wobble_period : float
        Truth motion, see :func:`~.motion.truth_rate` (rates in [0, 10] deg/s, the period
        at least 1e-3 s).
    drift_walk_deg_per_h_sqrt_s : float
        Filter drift random walk, deg/h per sqrt(s) (default 1): sets how fast the drift
        estimates follow a change (time constant about 3.4 s at 10 Hz, as chapter 11 measures).
    drift_sigma0_deg_per_h : float
        Initial drift uncertainty of the filters (default 100 deg/h).
    n_sigma : float
        Thresholds in predicted standard deviations of each residual, in [0.01, 30]
        (default 5; from about 38 the tail probability underflows to zero).
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

    def __new__(cls, *args, **kwargs):
        _check_settings(kwargs)  # a misspelt keyword was Python's TypeError from __init__
        return super().__new__(cls)

    def __post_init__(self):
        # every field is stored as checked (float, int, tuple of float), not as given: a numpy
        # scalar kept its dtype (np.float16(100.0) / dt overflowed)
        def put(name, value):
            object.__setattr__(self, name, value)
            return value

        duration = put("duration", check_real("duration", self.duration, 0.0, 1e6, lo_open=True))
        dt = put("dt", check_real("dt", self.dt, 0.0, 10.0, lo_open=True))
        if duration / dt > MAX_SAMPLES - 1:  # every array of the run holds n samples (review 35p P7)
            n = int(round(duration / dt)) + 1
            raise ValueError(f"duration must keep a run at most {MAX_SAMPLES} samples (about 2 GB at "
                             f"{BYTES_PER_SAMPLE} bytes a sample), got duration = {duration:g} s at dt "
                             f"= {dt:g} s: {n} samples, about {n * BYTES_PER_SAMPLE / 1e9:.3g} GB (at "
                             f"most {(MAX_SAMPLES - 1) * dt:.10g} s at this dt)")
        if duration < 2 * dt:
            raise ValueError(f"duration must be >= 2 dt = {2 * dt}, got {duration}")
        steps = duration / dt  # the run has samples 0, dt, ..., (n - 1) dt: it would
        if abs(steps - round(steps)) > 1e-9 * steps:  # end at round(steps) dt, not at duration
            lo, hi = math.floor(steps) * dt, math.ceil(steps) * dt
            raise ValueError(f"duration must be a whole number of steps dt = {dt:g} s, got "
                             f"{duration:g} s (nearest {lo:.6g} or {hi:.6g} s)")
        drifts = check_finite_array("drifts_deg_per_h", self.drifts_deg_per_h, shape=(4,))
        if drifts.ndim != 1:
            raise ValueError(f"drifts_deg_per_h must have shape (4,), got shape {drifts.shape}")
        if np.any(np.abs(drifts) > MAX_DEG_PER_H):
            raise ValueError(f"drifts_deg_per_h must lie in [-{MAX_DEG_PER_H:g}, "
                             f"{MAX_DEG_PER_H:g}] deg/h, got {drifts.tolist()}")
        put("drifts_deg_per_h", tuple(drifts.tolist()))
        put("gyro_noise_deg_per_h", check_real("gyro_noise_deg_per_h", self.gyro_noise_deg_per_h,
                                               0.0, MAX_DEG_PER_H, lo_open=True))
        put("star_noise_deg", check_real("star_noise_deg", self.star_noise_deg, 0.0, 1.0,
                                         lo_open=True))
        gyro_matrix(self.skew_axis)  # checks it (shape (3,), no zero component)
        put("skew_axis", tuple(np.asarray(self.skew_axis, dtype=float).tolist()))
        q0 = check_quaternion("q0", self.q0, unit=False)  # normalised by truth_motion; zero refused
        if q0.ndim != 1:
            raise ValueError(f"q0 must have shape (4,) (one quaternion), got shape {q0.shape}")
        put("q0", tuple(q0.tolist()))
        # the truth motion's settings, checked here as truth_rate does (they were used only
        # when the run started), the period from 1e-3 s (a subnormal one overflowed t / P)
        put("omega_orbit_deg_s", check_real("omega_orbit_deg_s", self.omega_orbit_deg_s, 0.0, 10.0))
        put("wobble_deg_s", check_real("wobble_deg_s", self.wobble_deg_s, 0.0, 10.0))
        put("wobble_period", check_real("wobble_period", self.wobble_period, 1e-3))
        put("drift_walk_deg_per_h_sqrt_s", check_real(
            "drift_walk_deg_per_h_sqrt_s", self.drift_walk_deg_per_h_sqrt_s, 0.0, MAX_DEG_PER_H))
        put("drift_sigma0_deg_per_h", check_real(
            "drift_sigma0_deg_per_h", self.drift_sigma0_deg_per_h, 0.0, MAX_DEG_PER_H,
            lo_open=True))
        # the thresholds' tail probability erfc(n_sigma / sqrt 2) must lie in (0, 1): it is 1
        # for a subnormal n_sigma and underflows to 0 from about 38
        put("n_sigma", check_real("n_sigma", self.n_sigma, 0.01, 30.0))
        cal = check_finite_array("t_cal", self.t_cal, shape=(2,))
        last = (self.n - 1) * dt  # the last sample's time (duration to 1e-9 of it)
        default_cal = tuple(cal.tolist()) == _default("t_cal")  # review 35o 3.1: the user gave
        if default_cal and cal[1] > last:  # duration only: name it, and the default it meets
            raise ValueError(f"duration must be at least {cal[1]:g} s with the default "
                             f"calibration window t_cal = ({cal[0]:g}, {cal[1]:g}) s, got "
                             f"{duration:g} s: lengthen it or give t_cal")
        if cal.ndim != 1 or not (0.0 <= cal[0] < cal[1] <= last):
            raise ValueError(f"t_cal must satisfy 0 <= t_cal[0] < t_cal[1] <= duration (the last "
                             f"sample, {last:g} s), got {cal}")
        if cal[1] - cal[0] < 2 * dt:
            raise ValueError("t_cal must span at least two samples")
        put("t_cal", tuple(cal.tolist()))
        put("persist", check_int("persist", self.persist, 1, 10**6))
        put("confirm_s", check_real("confirm_s", self.confirm_s, 0.0, 86400.0))
        w = self.qdiff_window_s
        w_default = isinstance(w, float) and w == _default("qdiff_window_s")
        if w_default and w < 2 * dt:  # dt given, the window the default
            raise ValueError(f"dt must be at most {w / 2:g} s with the default qdiff_window_s = "
                             f"{w:g} s (two samples at least), got {dt:g} s: lower it or give "
                             f"qdiff_window_s")
        w = put("qdiff_window_s", check_real("qdiff_window_s", w, 2 * dt))
        if max(w, cal[0] + 0.5 * w) >= cal[1] and w_default and not default_cal:  # t_cal given
            raise ValueError(f"t_cal must leave an estimate for the default qdiff_window_s = "
                             f"{w:g} s: need max(w, t_cal[0] + w/2) < t_cal[1], got t_cal = "
                             f"{tuple(cal.tolist())}: widen it or give qdiff_window_s")
        if max(w, cal[0] + 0.5 * w) >= cal[1]:
            raise ValueError(
                "qdiff_window_s must leave an estimate inside t_cal: need "
                f"max(w, t_cal[0] + w/2) < t_cal[1], got w = {w}, t_cal = {tuple(cal.tolist())}"
            )
        put("dos", check_bool("dos", self.dos))

    @property
    def n(self):
        """Number of samples."""
        return int(round(self.duration / self.dt)) + 1


def _default(name):
    """A SimConfig field's default (a message names a default the user did not give as such)."""
    return SimConfig.__dataclass_fields__[name].default


# the signature shown (help, the API page) is the fields', not __new__'s (*args, **kwargs)
SimConfig.__signature__ = inspect.signature(SimConfig.__init__).replace(
    parameters=list(inspect.signature(SimConfig.__init__).parameters.values())[1:])


@dataclass(frozen=True, eq=False)
class AttitudeRun:
    """One simulated run (from :func:`simulate`). Arrays are in SI units.

    Every field is checked when the run is made, a copy edited with
    ``dataclasses.replace`` too (shapes from ``config.n``, finite values, the diagnoses):
    one ValueError naming ``AttitudeRun.<field>`` (review 35p P11: a cut ``sos_r`` or
    ``sos=None`` reached :func:`~.plots.plot_residuals` as numpy's IndexError or an
    AttributeError, a NaN one drew an empty figure). The check takes about 0.2 ms, 1 % of a
    run of 100 s (16 ms) and less of a longer one (measured 2026-11-29).

    Attributes
    ----------
    t : ndarray, shape (n,)
    config : SimConfig
    faults : tuple of Fault
    truth : str
        Faulty sensor (a :data:`~.sensors.LOCATIONS` entry) or ``"none"``.
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

    def __post_init__(self):
        _check_run(self)


def _check_run(run):
    """The fields of an :class:`AttitudeRun`, each of the shape its config fixes and finite,
    else one ValueError naming ``AttitudeRun.<field>``; arrays stored as checked."""

    def shaped(name, value, shape, why):  # the fast path of a run as simulate makes it
        if (isinstance(value, np.ndarray) and value.dtype == np.float64 and value.ndim == len(shape)
                and all(s in (None, v) for s, v in zip(shape, value.shape, strict=True))
                and np.isfinite(value).all()):
            return value
        return _check_shape(name, value, shape, why)

    cfg = run.config
    if not isinstance(cfg, SimConfig):
        raise ValueError(f"AttitudeRun.config must be a SimConfig, got {type(cfg).__name__}")
    n = cfg.n
    put = object.__setattr__
    why = f"n = config.n = {n} samples"
    for name, cols in (("t", None), ("w_true", 3), ("q_true", 4), ("omega_g", 4), ("q_meas", 4),
                       ("q_hat", 4), ("drift_hat", 3), ("att_err", 3), ("sos_r", 4), ("dos_r", 4)):
        shape = (n,) if cols is None else (n, cols)
        put(run, name, shaped(f"AttitudeRun.{name}", getattr(run, name), shape, why))
    for name, size in (("sos_J", 4), ("dos_J", 4), ("qd_J", 3)):
        put(run, name, shaped(f"AttitudeRun.{name}", getattr(run, name), (size,),
                            "one threshold a residual"))
    t_qd = shaped("AttitudeRun.t_qd", run.t_qd, (None,), "the estimates' times")
    put(run, "t_qd", t_qd)
    put(run, "qd_f", shaped("AttitudeRun.qd_f", run.qd_f, (t_qd.size, 3),
                            f"m = {t_qd.size} estimates of t_qd"))
    armed = run.armed
    if not isinstance(armed, np.ndarray) or armed.dtype != bool or armed.shape != (n,):
        raise ValueError(f"AttitudeRun.armed must be a boolean array of shape ({n},) ({why}), got "
                         f"{shown(armed)}")
    if not isinstance(run.faults, tuple) or not all(isinstance(f, Fault) for f in run.faults):
        raise ValueError(f"AttitudeRun.faults must be a tuple of Fault, got {shown(run.faults)}")
    if not isinstance(run.truth, str):
        raise ValueError(f"AttitudeRun.truth must be a location or 'none' (a str), got {shown(run.truth)}")
    onset = run.onset
    if isinstance(onset, bool) or not isinstance(onset, int | float) or math.isnan(onset):
        raise ValueError(f"AttitudeRun.onset must be a time, s, or inf (no fault), got {shown(onset)}")
    for name, m, rows in (("sos", 4, n), ("dos", 4, n), ("qd", 3, t_qd.size)):
        d = getattr(run, name)
        if d is None and name == "dos" and not cfg.dos:
            continue
        if not isinstance(d, Diagnosis) or d.flags.shape != (rows, m):
            got = (f"flags of shape {d.flags.shape}" if isinstance(d, Diagnosis)
                   else type(d).__name__)
            extra = " (config.dos is True)" if name == "dos" else ""
            raise ValueError(f"AttitudeRun.{name} must be the run's Diagnosis, flags of shape "
                             f"({rows}, {m}){extra}, got {got}")
    if cfg.dos is False and run.dos is not None:
        raise ValueError("AttitudeRun.dos must be None when config.dos is False, got a Diagnosis")
    if not isinstance(run.refs, dict):
        raise ValueError(f"AttitudeRun.refs must be a dict of the learned references, got {shown(run.refs)}")


# -------------------------------------------------------------------- one run


def simulate(faults=(), config=None, *, rng=None, **changes):
    """Simulate one run: truth, sensors, faults, the filters and all three diagnoses.

    Parameters
    ----------
    faults : Fault or sequence of Fault
        From :func:`~.sensors.make_fault` (sensors ``"gyro"`` and ``"star_tracker"``). One Fault
        alone is taken as ``[fault]`` here (a run of one fault is this function's common call;
        :func:`xnavlab.core.faults.inject`, a building block, asks for the list). A fault is
        refused (:func:`check_faults_in_run`) when it is of another sensor, starts outside
        ``[0, duration)`` or acts on no sample, or (a gyro fault) turns the attitude by more
        than ``MAX_ANGLE / 10`` in one step.
    config : SimConfig, optional
        Settings (default :class:`SimConfig`).
    rng : numpy.random.Generator or int, optional
        Seed of the sensor noise (default 0: reproducible), drawn as :func:`simulate_sensors`
        says; the extra noise of a ``"noise"`` fault comes from a child stream of its own, so a
        run with faults and one without share their sensor noise.
    **changes
        Overrides of ``config`` fields, e.g. ``n_sigma=4``.

    Returns
    -------
    AttitudeRun

    Examples
    --------
    >>> from xnavlab.attitude.sensors import make_fault
    >>> run = simulate(make_fault("gyro_x", "step", 36 * DEG_PER_H), duration=60.0)
    >>> run.sos.verdict, run.dos.verdict
    ('gyro_x', 'gyro_x')
    """
    cfg = make_config(config, **changes)
    faults = check_faults_in_run(faults, cfg)
    rng = make_rng(rng)
    (t, w, q), wg, qs = simulate_sensors(cfg, faults, rng)
    res = diagnose_batch(wg[None], qs[None], cfg)
    q_hat = res["q_hat"][0]

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


def make_config(config=None, **changes):
    """The settings of a run: ``config`` (default :class:`SimConfig`) with fields overridden.

    Parameters
    ----------
    config : SimConfig, optional
        Starting settings (default ``SimConfig()``).
    **changes
        Field overrides, e.g. ``n_sigma=4.0``; checked by :class:`SimConfig`.

    Returns
    -------
    SimConfig

    Raises
    ------
    ValueError
        If ``config`` is not a SimConfig, a field is unknown or a value is out of range.

    Examples
    --------
    >>> make_config(n_sigma=4.0).n_sigma
    4.0
    >>> make_config(SimConfig(duration=60.0), dos=False).n
    601
    """
    if config is None:
        config = SimConfig()
    elif not isinstance(config, SimConfig):
        raise ValueError(f"config must be a SimConfig or None, got {type(config).__name__}")
    _check_settings(changes)
    return dataclasses.replace(config, **changes)


def _check_settings(changes):
    """Each keyword a field of SimConfig, else a ValueError naming it and listing the fields
    (a misspelt one was "unknown SimConfig setting: SimConfig.__init__() got ...")."""
    names = [f.name for f in dataclasses.fields(SimConfig)]
    for key, value in changes.items():
        if key not in names:
            raise ValueError(f"{key}={value!r:.60} is not a SimConfig setting (they are {', '.join(names)})")


def _config_arg(config):
    if not isinstance(config, SimConfig):
        raise ValueError(f"config must be a SimConfig, got {type(config).__name__}")
    return config


#: The sensors of an attitude run (a fault of another sensor would be injected nowhere).
SENSORS = ("gyro", "star_tracker")


def check_faults_in_run(faults, config):
    """The faults of a run as a tuple, each one the run uses, else one ValueError naming it.

    One Fault alone is taken as ``(fault,)``; a sequence is checked by
    :func:`xnavlab.core.faults.check_faults` (a spec string, a repeat or two overlapping faults
    on one component are refused). Then each fault must be of a sensor of the run
    (:data:`SENSORS`), start inside it (``0 <= onset < duration``), act on at least one sample
    (a step between two samples ``dt`` apart acts on none) and, on the gyros, stay below
    ``MAX_ANGLE / (10 dt)`` rad/s (a ramp: what it reaches in the run): a larger rate turns the
    attitude in one step by an angle a float cannot place on the circle
    (:data:`xnavlab.core.quaternions.MAX_ANGLE`).

    Parameters
    ----------
    faults : Fault or sequence of Fault
    config : SimConfig

    Returns
    -------
    tuple of Fault

    Examples
    --------
    >>> from xnavlab.attitude.sensors import make_fault
    >>> check_faults_in_run(make_fault("gyro_x", "step", 1e-4, onset=1e9), SimConfig())
    Traceback (most recent call last):
    ...
    ValueError: faults[0] (gyro step, component 0) starts at 1e+09 s, outside this run: an onset \
is s since the start, in [0, 100)
    """
    cfg = _config_arg(config)
    if isinstance(faults, np.ndarray) and faults.ndim != 1:  # a 0-d array is no list of faults
        raise ValueError(f"faults must be a Fault or a sequence of Fault, got {shown(faults)}")
    faults = (faults,) if isinstance(faults, Fault) else tuple(check_faults("faults", faults))
    t = np.arange(cfg.n) * cfg.dt
    for i, f in enumerate(faults):
        what = f"faults[{i}] ({f.sensor} {f.kind}" + (
            f", component {f.component})" if f.component is not None else ")")
        if f.sensor not in SENSORS:
            raise ValueError(f"{what}: sensor must be one of {', '.join(map(repr, SENSORS))} "
                             f"(make_fault builds them), got {f.sensor!r}")
        if not 0.0 <= f.onset < cfg.duration:
            raise ValueError(f"{what} starts at {f.onset:g} s, outside this run: an onset is s "
                             f"since the start, in [0, {cfg.duration:g})")
        acts = f.active(t)
        if not acts.any():
            raise ValueError(f"{what} acts on no sample: it lasts {f.duration:g} s from "
                             f"{f.onset:g} s between two samples ({cfg.dt:g} s apart)")
        size = abs(f.magnitude) * (t[acts][-1] - f.onset if f.kind == "ramp" else 1.0)
        if f.sensor == "gyro" and size * cfg.dt > 0.1 * MAX_ANGLE:
            raise ValueError(f"{what} reaches {size:.3g} rad/s, which turns the attitude by "
                             f"{size * cfg.dt:.3g} rad in one step of {cfg.dt:g} s: at most "
                             f"{0.1 * MAX_ANGLE / cfg.dt:.3g} rad/s (0.1 MAX_ANGLE per step)")
    return faults


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


def simulate_sensors(config, faults=(), rng=None, truth=None):
    """Truth motion and sensor outputs of one run, with faults injected.

    The gyro noise is drawn from ``rng`` first, then the star-tracker noise, so a batch of
    runs drawn from one generator is reproducible (:func:`simulate`,
    :func:`xnavlab.attitude.montecarlo.isolation_monte_carlo`). The faults draw nothing from
    ``rng``: a ``"noise"`` fault's extra noise comes from a child stream spawned from it
    (``numpy.random.Generator.spawn``, one for each sensor with such a fault, the gyros
    first), so the sensor noise depends on the seed alone, with or without faults.

    Parameters
    ----------
    config : SimConfig
        Settings (:func:`make_config`).
    faults : Fault or sequence of Fault
        From :func:`xnavlab.attitude.sensors.make_fault`.
    rng : numpy.random.Generator or int, optional
        Source of the sensor noise (default seed 0) and parent of the faults' stream.
    truth : tuple, optional
        ``(t, w, q)`` from :func:`xnavlab.attitude.motion.truth_motion` for ``config``,
        to reuse across the runs of a batch (shapes (n,), (n, 3), (n, 4), ``t`` the config's
        sample times, ``q`` unit quaternions); computed when omitted.

    Returns
    -------
    truth : tuple of ndarray
        ``t`` (n,), s; ``w`` (n, 3), rad/s; ``q`` (n, 4), true attitude.
    omega_g : ndarray, shape (n, 4)
        Gyro-assembly outputs, rad/s.
    q_meas : ndarray, shape (n, 4)
        Star-tracker quaternions.

    Examples
    --------
    >>> (t, w, q), wg, qs = simulate_sensors(SimConfig(duration=50.0))
    >>> t.shape, wg.shape, qs.shape
    ((501,), (501, 4), (501, 4))
    """
    cfg = _config_arg(config)
    faults = check_faults_in_run(faults, cfg)
    rng = make_rng(rng)
    t, w, q = _check_truth(truth, cfg) if truth is not None else truth_motion(
        cfg.n, cfg.dt, q0=cfg.q0, omega_orbit_deg_s=cfg.omega_orbit_deg_s,
        wobble_deg_s=cfg.wobble_deg_s, wobble_period=cfg.wobble_period,
    )
    wg = gyro_measurements(
        t, w, drifts_deg_per_h=cfg.drifts_deg_per_h,
        noise_deg_per_h=cfg.gyro_noise_deg_per_h, skew_axis=cfg.skew_axis,
        faults=[f for f in faults if f.sensor == "gyro"], rng=rng,  # each sensor its own faults
    )
    qs = star_tracker_measurements(t, q, noise_deg=cfg.star_noise_deg, rng=rng,
                                   faults=[f for f in faults if f.sensor == "star_tracker"])
    return (t, w, q), wg, qs


def _check_truth(truth, cfg):
    """``truth`` as ``(t, w, q)`` of ``cfg``'s samples, else one ValueError naming it (a float
    was "cannot unpack", a string numpy's "not enough values to unpack")."""
    what = "a tuple (t, w, q) from truth_motion for config"
    if not isinstance(truth, tuple | list) or len(truth) != 3:
        raise ValueError(f"truth must be {what}, got {shown(truth)}")
    n = cfg.n
    t = _check_shape("truth[0]", truth[0], (n,), f"t: the {n} sample times of config")
    w = _check_shape("truth[1]", truth[1], (n, 3), "w: the body rates, rad/s")
    q = check_quaternion("truth[2]", _check_shape("truth[2]", truth[2], (n, 4),
                                                 "q: the true attitudes"))
    times = np.arange(n) * cfg.dt
    if not np.allclose(t, times, rtol=0.0, atol=1e-9 * cfg.dt):
        k = int(np.argmax(np.abs(t - times)))
        raise ValueError(f"truth[0] must be config's sample times k dt (dt = {cfg.dt:g} s), got "
                         f"{t[k]:g} s at sample {k} (expected {times[k]:g} s)")
    return t, w, q


# ------------------------------------------------------------ a batch of runs


def diagnose_batch(omega_g, q_meas, config):
    """Filters, residuals, thresholds and diagnoses of a batch of runs, vectorised.

    Runs the EKF bank (the four DOS filters when ``config.dos``, else only filter 4, the
    SOS filter fed by the orthogonal triad) over every run at once, learns the references
    in the calibration window ``config.t_cal``, sets the thresholds at ``config.n_sigma``
    predicted standard deviations and applies the threshold logic
    (:func:`xnavlab.attitude.diagnosis.diagnose`) of SOS, DOS and ref. [22].

    Parameters
    ----------
    omega_g : array_like, shape (B, n, 4)
        Gyro-assembly outputs of ``B`` runs, rad/s, ``n = config.n``.
    q_meas : array_like, shape (B, n, 4)
        Star-tracker quaternions.
    config : SimConfig

    Returns
    -------
    dict
        ``t`` (n,); the SOS filter's ``q_hat`` (B, n, 4) and ``drift_hat`` (B, n, 3);
        ``sos_r`` (B, n, 4), ``sos_J`` (B, 4) and ``sos`` (a batched
        :class:`~xnavlab.attitude.diagnosis.Diagnosis`); ``dos_r``, ``dos_J``, ``dos``
        likewise (zeros and ``None`` without DOS); ``t_qd`` (m,), ``qd_f`` (B, m, 3),
        ``qd_J`` (3,) and ``qd`` for ref. [22]; ``refs`` (the learned references, see
        :class:`AttitudeRun`). Rates in rad/s.

    Examples
    --------
    >>> cfg = SimConfig(duration=50.0)
    >>> _, wg, qs = simulate_sensors(cfg)
    >>> out = diagnose_batch(wg[None], qs[None], cfg)
    >>> out["sos_r"].shape, out["sos"].verdict.tolist()
    ((1, 501, 4), ['none'])
    """
    cfg = _config_arg(config)
    omega_g = check_finite_array("omega_g", omega_g, shape=(cfg.n, 4))
    q_meas = check_finite_array("q_meas", q_meas, shape=(cfg.n, 4))
    if omega_g.ndim != 3 or q_meas.shape != omega_g.shape:
        raise ValueError(f"omega_g and q_meas must both have shape (B, {cfg.n}, 4), got "
                         f"{omega_g.shape} and {q_meas.shape}")

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
        dos_J = math.sqrt(chi2_isf(_tail_prob(cfg.n_sigma), 3)) * scale
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
    B, F = omega_g.shape[0], len(groups)
    x, P = ekf_init(
        np.broadcast_to(q_meas[:, :1, :], (B, F, 4)),
        attitude_sigma=math.radians(cfg.star_noise_deg),
        drift_sigma=(cfg.drift_sigma0_deg_per_h * DEG_PER_H) ** 2 * TT,
    )
    # the steps of ekf_predict and ekf_update (paper eqs. (30)-(34)) over the n samples,
    # compiled: 1,000 steps of numpy's small-array calls took 0.5-1 s, a slider's frame
    # (imported here: numba's import waits for the first run, not for `import attitude`)
    from xnavlab.attitude._bank_kernel import filter_bank_compiled

    return filter_bank_compiled(x, P, w_tilde, q_meas, dt, gyro_cov, drift_cov, R)


def _tail_prob(n_sigma):
    return math.erfc(n_sigma / math.sqrt(2.0))
