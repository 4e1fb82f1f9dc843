"""Diagnosis of a whole flight, and the chi-square detector it is compared with.

:func:`diagnose_flight` simulates the paper's flight with pseudorange faults and runs the
whole chain: trajectory and INS errors (:mod:`xnavlab.plins.ins`), pseudoranges
(:mod:`xnavlab.plins.pseudolites`), the T-S parity design of the flight
(:func:`flight_design`: :mod:`.fuzzy` and :mod:`.space`), global residuals, threshold and
first alarms (:func:`first_alarm`), onset search and identification of each alarmed
sensor (:mod:`.identification`). :func:`chi2_monitor` is the comparison detector of the
chapter's "Beyond the paper" (a Kalman filter with a residual chi-square test), and
:func:`compare_detectors` compares the two by fault size.
"""

from __future__ import annotations

import hashlib
import inspect
import math
from dataclasses import dataclass

import numpy as np

from xnavlab.core import faults as _faults
from xnavlab.core.distributions import chi2_isf
from xnavlab.core.validate import (
    SEED_MAX,
    check_bool,
    check_choice,
    check_covariance,
    check_finite_array,
    check_increasing,
    check_int,
    check_real,
    check_shape,
    check_vector,
    make_rng,
    shown,
)
from xnavlab.plins import ins as _ins
from xnavlab.plins import pseudolites as _pl
from xnavlab.plins._checks import check_sites
from xnavlab.plins.parity.fuzzy import local_models, memberships, operating_points, premises
from xnavlab.plins.parity.identification import SIGMA_MIN, Identification, estimate_onset, identify_fault
from xnavlab.plins.parity.space import (
    TYPICAL_STATE_STD,
    align_bases,
    blended_bases,
    parity_basis,
    parity_residuals,
    residual_threshold,
)

__all__ = [
    "first_alarm",
    "Chi2Monitor",
    "chi2_monitor",
    "Diagnosis",
    "flight_design",
    "diagnose_flight",
    "compare_detectors",
    "FLIGHT_S",
    "MAX_SAMPLES",
    "DESIGN_S_PER_SAMPLE",
    "RUN_S_PER_SAMPLE",
    "MAX_SECONDS",
]

#: Length of the simulated flight of :func:`diagnose_flight` by default, s.
FLIGHT_S = 200.0

#: Measured cost of a flight's samples on a 2-core machine, s a sample: a new flight (its
#: trajectory, error transitions and T-S design, cached after) about 6 ms; each further run of a
#: cached flight about 1 ms with the chi-square detector (0.1 ms without).
DESIGN_S_PER_SAMPLE, RUN_S_PER_SAMPLE = 6e-3, 1e-3
#: The most samples ``duration / dt + 1`` of one flight: about 5 minutes at
#: :data:`DESIGN_S_PER_SAMPLE` (the book's flights have 201; 1e6 samples took about 1.7 h).
MAX_SAMPLES = 50_000
#: The longest a call may be estimated to take, s (refused beyond it, naming its settings).
MAX_SECONDS = 600.0


def first_alarm(t, statistic, threshold, after=-math.inf):
    """Time of the first sample at or after ``after`` whose statistic exceeds the threshold.

    Parameters
    ----------
    t : array_like, shape (n,)
        Times, s, strictly increasing.
    statistic : array_like, shape (n,)
        Test statistic.
    threshold : float
        Threshold, >= 0 (a norm or a chi-square is never negative: a negative threshold
        would alarm at every sample).
    after : float
        Ignore alarms before this time, s.

    Returns
    -------
    float or None
        Alarm time, s; ``None`` if there is none.

    Examples
    --------
    >>> first_alarm([0.0, 1.0, 2.0], [0.1, 5.0, 5.0], 1.0)
    1.0
    >>> first_alarm([0.0, 1.0], [0.1, 0.2], 1.0) is None
    True
    """
    t = check_vector("t", t)
    check_increasing("t", t)  # the first alarm is the earliest sample: t read in order
    st = check_vector("statistic", statistic)
    if len(st) > len(t):  # two well-formed series: the shorter one is named (cut short)
        raise ValueError(f"t must hold one time per sample of statistic (n = {len(st)}), got {len(t)}")
    st = check_shape("statistic", st, t.shape, "n = len(t)")
    threshold = check_real("threshold", threshold, 0.0)  # below 0 every sample alarms
    if isinstance(after, bool) or not isinstance(after, int | float | np.integer | np.floating) \
            or math.isnan(after):
        raise ValueError(f"after must be a real number (s; -inf for any), got {after!r}")
    idx = np.flatnonzero((st > threshold) & (t >= after))
    return float(t[idx[0]]) if idx.size else None


# ------------------------------------------------------ chi-square comparison


def _store(obj, **fields):
    """Set the checked ``fields`` of a frozen result (as arrays of floats where they were lists)."""
    for name, value in fields.items():
        object.__setattr__(obj, name, value)


def _times(name, t):
    """Sample times: a non-empty, finite, increasing 1-D array."""
    t = check_vector(name, t)
    if t.size == 0:
        raise ValueError(f"{name} must hold at least one sample time, got an empty array")
    return check_increasing(name, t)


def _nonnegative(name, value, shape, why):
    """A finite array of ``shape`` (a norm or a chi-square value: at least 0)."""
    arr = check_shape(name, value, shape, why)
    if np.any(arr < 0.0):
        i = int(np.argmax(np.ravel(arr) < 0.0))
        raise ValueError(f"{name} must hold norms (at least 0), got {np.ravel(arr)[i]:g} at flat index {i}")
    return arr


def _alarm_list(name, value, m):
    """One entry per sensor: None or a time, s."""
    if not isinstance(value, list) or len(value) != m:
        raise ValueError(f"{name} must be a list of one entry per pseudolite (m = {m}), got {shown(value)}")
    for j, v in enumerate(value):
        if v is not None:
            check_real(f"{name}[{j}]", v)


@dataclass(frozen=True)
class Chi2Monitor:
    """Residual chi-square test of a PL/INS Kalman filter (Brumback & Srinath 1987).

    Attributes
    ----------
    t : ndarray, shape (n,)
        Time, s.
    statistic : ndarray, shape (n,)
        ``nu^T S^{-1} nu`` of the innovation ``nu`` with covariance ``S``.
    threshold : float
        ``chi2_m^{-1}(1 - p_fa)``.
    x : ndarray, shape (n, 10)
        Filtered error state.
    """

    t: np.ndarray
    statistic: np.ndarray
    threshold: float
    x: np.ndarray

    def __post_init__(self):
        """Check the fields (an edited copy, ``dataclasses.replace``, is checked again), each
        refusal naming ``Chi2Monitor.<field>``."""
        n = "Chi2Monitor."
        t = _times(n + "t", self.t)
        _store(self, t=t, statistic=_nonnegative(n + "statistic", self.statistic, (t.size,), "n = len(t)"),
               threshold=check_real(n + "threshold", self.threshold, 0.0, math.inf, lo_open=True),
               x=check_shape(n + "x", self.x, (t.size, _ins.N_STATES), "n = len(t)"))

    def first_alarm(self, after=-math.inf):
        """Time of the first alarm at or after ``after``, s, or ``None``."""
        return first_alarm(self.t, self.statistic, self.threshold, after)


def chi2_monitor(data, transitions, sites=None, x0_std=None, p_fa=1e-6):
    """Kalman filter of the PL/INS error state with a residual chi-square test.

    The comparison detector of "Beyond the paper": a 10-state linear Kalman filter on
    ``z = rho - rho_I`` with ``H`` linearised at the INS position, and the normalised
    innovation squared ``nu^T S^-1 nu ~ chi^2_m`` tested every sample. It detects but
    does not isolate, and after a fault it adapts (no exclusion).

    Parameters
    ----------
    data : xnavlab.plins.pseudolites.PseudorangeData
        Simulated measurements.
    transitions : tuple of ndarray
        ``(A, Qd)`` of the flight (:func:`xnavlab.plins.ins.error_transitions`), each
        ``Qd[k]`` a covariance (symmetric, positive semi-definite: a swapped pair is refused).
    sites : array_like, shape (m, 3), optional
        Pseudolite positions, ECEF (default :func:`xnavlab.plins.pseudolites.sites_ecef()`).
    x0_std : array_like, shape (10,), optional
        Initial 1-sigma, each >= 0 (default :data:`xnavlab.plins.ins.DEFAULT_INITIAL_STD`).
    p_fa : float
        False-alarm probability per sample, in (0, 0.5).

    Returns
    -------
    Chi2Monitor

    Examples
    --------
    >>> tr = _ins.paper_trajectory(duration=30.0)
    >>> tx = _ins.error_transitions(tr)
    >>> d = _pl.simulate_pseudoranges(tr, _ins.simulate_errors(tr, rng=0, transitions=tx))
    >>> mon = chi2_monitor(d, tx)
    >>> mon.first_alarm() is None
    True
    """
    if not isinstance(data, _pl.PseudorangeData):
        raise ValueError(f"data must be a PseudorangeData, got {type(data).__name__}")
    n, m = data.z.shape
    if not isinstance(transitions, list | tuple) or len(transitions) != 2:  # as simulate_errors
        raise ValueError(f"transitions must be a pair (A, Qd) from error_transitions, got "
                         f"{shown(transitions)}")
    A, Qd = (check_shape(f"transitions[{i}]", a, (n - 1, 10, 10), f"n - 1 = {n - 1} steps of data")
             for i, a in enumerate(transitions))
    # a covariance each (an indefinite Qd, or a swapped (Qd, A) pair): check_covariance's own
    # tests, vectorised over the flight, then its message for the first one it refuses
    scale = np.abs(Qd).max(axis=(1, 2), initial=0.0)
    asym = np.abs(Qd - Qd.transpose(0, 2, 1)).max(axis=(1, 2), initial=0.0) > 1e-8 * scale
    low = np.linalg.eigvalsh(0.5 * (Qd + Qd.transpose(0, 2, 1)))[:, 0] if len(Qd) else scale
    if np.any(asym | (low < -1e-8 * scale)):
        k = int(np.argmax(asym | (low < -1e-8 * scale)))
        check_covariance(f"transitions[1][{k}]", Qd[k], 10)
    sites = _pl.sites_ecef() if sites is None else check_finite_array("sites", sites, shape=(3,))
    x0_std = _ins.DEFAULT_INITIAL_STD if x0_std is None else check_shape("x0_std", x0_std, (10,))
    if np.any(x0_std < 0.0):  # squared into P: a negative sigma read as a positive one
        raise ValueError(f"x0_std must be >= 0 (1-sigma initial errors), got {x0_std.min():g}")
    p_fa = check_real("p_fa", p_fa, 0.0, 0.5, lo_open=True, hi_open=True)
    thr = chi2_isf(p_fa, m)
    R = max(data.sigma, 1e-3) ** 2 * np.eye(m)
    lat, lon, h = _pl.ecef_to_geodetic(data.r_ins)
    x = np.zeros(10)
    P = np.diag(x0_std**2)
    stat = np.empty(n)
    xs = np.empty((n, 10))
    for k in range(n):
        if k > 0:
            x = A[k - 1] @ x  # x = A x
            P = A[k - 1] @ P @ A[k - 1].T + Qd[k - 1]  # P = A P A^T + Q
        H = _pl.measurement_matrix(lat[k], lon[k], h[k], sites)
        nu = data.z[k] - H @ x
        S = H @ P @ H.T + R
        stat[k] = nu @ np.linalg.solve(S, nu)  # chi-square statistic
        K = np.linalg.solve(S, H @ P).T
        x = x + K @ nu
        IKH = np.eye(10) - K @ H
        P = IKH @ P @ IKH.T + K @ R @ K.T
        xs[k] = x
    return Chi2Monitor(data.t.copy(), stat, thr, xs)


# ----------------------------------------------------------- the whole flight


@dataclass(frozen=True, eq=False)
class Diagnosis:
    """Everything :func:`diagnose_flight` computed, for plots and checks.

    Frozen, and checked when made: an edited copy (``dataclasses.replace``) is checked again,
    each refusal naming ``Diagnosis.<field>`` (the threshold a positive real, the arrays of
    the shapes below and finite, ``identification`` Identifications of alarmed pseudolites);
    the checks cost a few array passes, nothing beside the flight's simulation.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Sample times, s.
    z : ndarray, shape (n, m)
        Measurements ``rho - rho_I``, m.
    fault : ndarray, shape (n, m)
        Injected faults, m.
    t_res : ndarray, shape (n - s,)
        Window end times, s.
    residual : ndarray, shape (n - s, m, q)
        Global parity residuals, m.
    statistic : ndarray, shape (n - s, m)
        ``||r_j||``, m.
    threshold : float
        ``r_t``, m.
    detection : list of (float or None)
        First alarm time of each sensor, s.
    onset : list of (float or None)
        Estimated onset of each alarmed sensor, s.
    identification : dict of int to Identification
        Identified faults of the alarmed sensors.
    s : int
        Window length minus one.
    null_dim : int
        Parity-space dimension ``q``.
    sigma : float
        Pseudorange noise, m.
    weights : ndarray, shape (n, N)
        Memberships of the operating points (read-only, as :func:`flight_design`'s cached
        arrays they come from).
    points : ndarray, shape (N, 3)
        Operating points ``[lat_deg, v_n, f_n]`` (read-only, as ``weights``).
    chi2 : Chi2Monitor or None
        The comparison detector (when requested).
    """

    t: np.ndarray
    z: np.ndarray
    fault: np.ndarray
    t_res: np.ndarray
    residual: np.ndarray
    statistic: np.ndarray
    threshold: float
    detection: list
    onset: list
    identification: dict
    s: int
    null_dim: int
    sigma: float
    weights: np.ndarray
    points: np.ndarray
    chi2: Chi2Monitor | None = None

    def __post_init__(self):
        # the threshold's range is diagnose_flight's, open above (a high one raises no alarm)
        n = "Diagnosis."
        t = _times(n + "t", self.t)
        s = check_int(n + "s", self.s, 2, 60)
        if t.size <= s:
            raise ValueError(f"{n}t must hold more than s + 1 = {s + 1} samples (one window), got {t.size}")
        z = check_shape(n + "z", self.z, (t.size, None), "n = len(t)")
        m = z.shape[1]
        t_res = check_shape(n + "t_res", self.t_res, (t.size - s,), "n - s window ends")
        if not np.array_equal(t_res, t[s:]):
            raise ValueError(f"{n}t_res must be the window ends t[s:] (s = {s})")
        q = check_int(n + "null_dim", self.null_dim, 1, (s + 1))
        _store(self, t=t, z=z, t_res=t_res,
               fault=check_shape(n + "fault", self.fault, (t.size, m), "n = len(t), m = columns of z"),
               residual=check_shape(n + "residual", self.residual, (t.size - s, m, q),
                                    "n - s windows, m = columns of z, q = null_dim"),
               statistic=_nonnegative(n + "statistic", self.statistic, (t.size - s, m),
                                      "n - s windows, m = columns of z"),
               threshold=check_real(n + "threshold", self.threshold, 0.0, math.inf, lo_open=True),
               sigma=check_real(n + "sigma", self.sigma, SIGMA_MIN, 1e6),
               weights=_read_only(check_shape(n + "weights", self.weights, (t.size, None),
                                              "n = len(t)")))
        _store(self, points=_read_only(check_shape(n + "points", self.points,
                                                   (self.weights.shape[1], 3),
                                                   "N = columns of weights")))
        _alarm_list(n + "detection", self.detection, m)
        _alarm_list(n + "onset", self.onset, m)
        if not isinstance(self.identification, dict) or any(
                isinstance(j, bool) or not isinstance(j, int) or not 0 <= j < m
                or not isinstance(v, Identification) for j, v in self.identification.items()):
            raise ValueError(f"{n}identification must map pseudolite indices in [0, {m - 1}] to "
                             f"Identifications, got {shown(self.identification)}")
        if self.chi2 is not None and not isinstance(self.chi2, Chi2Monitor):
            raise ValueError(f"{n}chi2 must be a Chi2Monitor or None, got {shown(self.chi2)}")


_FLIGHT_CACHE: dict = {}


def _flight(dt, duration):
    key = (dt, duration)
    if key not in _FLIGHT_CACHE:
        traj = _ins.paper_trajectory(dt=dt, duration=duration)
        _FLIGHT_CACHE.clear()
        _FLIGHT_CACHE[key] = (traj, _ins.error_transitions(traj))
    return _FLIGHT_CACHE[key]


_DESIGN_CACHE: dict = {}


def flight_design(traj, sites, s, tol, n_points=3):
    """T-S parity design of a flight: operating points, memberships, blended parity bases.

    Local models at ``n_points`` operating points (:func:`.fuzzy.local_models`), the
    single-sensor parity basis of each model and pseudolite (:func:`.space.parity_basis`
    with :data:`.space.TYPICAL_STATE_STD` and ``tol``), aligned across the models
    (:func:`.space.align_bases`) and blended with the memberships at every sample
    (:func:`.space.blended_bases`, paper eq. 25). The design depends on the flight, not on
    its noise, so it is cached (up to 17 designs, keyed on a digest of every trajectory array
    it reads and on the other arguments): a Monte Carlo pays for it once.

    Parameters
    ----------
    traj : xnavlab.plins.ins.Trajectory
        The flight.
    sites : array_like, shape (m, 3)
        Pseudolite positions, ECEF, m.
    s : int
        Window length minus one, in [0, 200].
    tol : float or None
        Numerical left-null-space tolerance, m, >= 0 (:func:`.space.parity_basis`;
        ``None``: exact).
    n_points : int
        Number of T-S operating points, in [1, 50].

    Returns
    -------
    points : ndarray, shape (N, 3)
        Operating points ``[lat_deg, v_n, f_n]``.
    weights : ndarray, shape (n, N)
        Memberships of every sample.
    W : ndarray, shape (n, m, s+1, q)
        Blended parity bases of every sample and sensor.
    q : int
        Parity-space dimension.

    The arrays are shared with the cache, so they are read-only (``flags.writeable`` False):
    an edit would change every later design of this flight. Copy one to change it.

    Raises
    ------
    ValueError
        If the local parity spaces differ in dimension or leave none (constraint 1).

    Examples
    --------
    >>> from xnavlab.plins import ins, pseudolites
    >>> tr = ins.paper_trajectory(duration=40.0)
    >>> points, weights, W, q = flight_design(tr, pseudolites.sites_ecef(), 11, 0.6)
    >>> points.shape, weights.shape, W.shape, q
    ((3, 3), (41, 3), (41, 4, 12, 10), 10)
    """
    if not isinstance(traj, _ins.Trajectory):
        raise ValueError(f"traj must be a Trajectory, got {type(traj).__name__}")
    sites = check_sites(sites)  # (m, 3), m >= 1 (none was an IndexError), distinct
    s = check_int("s", s, 0, 200)
    tol = None if tol is None else check_real("tol", tol, 0.0)
    n_points = check_int("n_points", n_points, 1, 50)
    return _design(traj, sites, s, tol, n_points,
                   ("tol", "None (exact)" if tol is None else f"{tol:g} m"))


def _design(traj, sites, s, tol, n_points, tol_named):
    """:func:`flight_design` of checked arguments; ``tol_named`` is (the user's name of the
    tolerance, its value as shown): the refusals name it (``leak_tol`` in diagnose_flight)."""
    name, shown_tol = tol_named
    key = (_digest(traj), sites.tobytes(), s, tol, n_points)
    if key in _DESIGN_CACHE:
        return _DESIGN_CACHE[key]
    points = operating_points(traj, n_points)
    models = local_models(points, traj.lon[0], traj.h[0], sites, traj.dt)
    bases = []
    for j in range(len(sites)):
        Vj = [parity_basis(lm.A, lm.C[j], s, B=lm.B, state_std=TYPICAL_STATE_STD, tol=tol)
              for lm in models]
        dims = {v.shape[1] for v in Vj}
        if len(dims) != 1:
            raise ValueError(f"{name} = {shown_tol} leaves local parity spaces of sensor {j} that "
                             f"differ in dimension {sorted(dims)}; change {name} or n_points")
        bases.append(align_bases(Vj))
    q = bases[0][0].shape[1]
    if q == 0 or any(b[0].shape[1] != q for b in bases):  # tol first: the edge a user moves
        raise ValueError(f"{name} = {shown_tol} leaves no common parity space with s = {s} "
                         f"(constraint 1); increase {name} or s")
    stacked = np.stack([np.stack([bases[j][l] for j in range(len(sites))])
                        for l in range(len(models))])
    weights = memberships(premises(traj), points)
    W = blended_bases(weights, stacked)  # (n, m, s+1, q)
    if len(_DESIGN_CACHE) > 16:
        _DESIGN_CACHE.clear()
    for arr in (points, weights, W):   # new arrays, shared by every later call: read-only
        arr.flags.writeable = False
    _DESIGN_CACHE[key] = (points, weights, W, q)
    return _DESIGN_CACHE[key]


def _digest(traj):
    """SHA-256 of every array of ``traj`` a design reads (times, position, velocity, specific
    force), with their shapes: two flights that differ anywhere get two designs."""
    h = hashlib.sha256()
    for arr in (traj.t, traj.lat, traj.lon, traj.h, traj.v_enu, traj.f_enu):
        h.update(repr(arr.shape).encode())
        h.update(np.ascontiguousarray(arr, dtype=float).tobytes())
    return h.hexdigest()


def _read_only(arr):
    """A read-only view of ``arr`` (the array's own flags stay as they were)."""
    view = arr.view()
    view.flags.writeable = False
    return view


def _check_samples(dt, duration):
    """Refuse a flight of more than :data:`MAX_SAMPLES` samples, naming dt and duration."""
    n = round(duration / dt) + 1
    if n > MAX_SAMPLES:
        raise ValueError(
            f"duration must give at most {MAX_SAMPLES} samples (duration / dt + 1; about "
            f"{MAX_SAMPLES * DESIGN_S_PER_SAMPLE / 60:.0f} min at the measured "
            f"{DESIGN_S_PER_SAMPLE * 1e3:g} ms a sample), got duration = {duration:g} s at dt = {dt:g} s: "
            f"{n} samples (about {n * DESIGN_S_PER_SAMPLE / 60:.3g} min); at this dt, duration <= "
            f"{(MAX_SAMPLES - 1) * dt:g} s")
    return n


def diagnose_flight(faults=(), *, model="step", s=11, threshold=None, sigma=_pl.DEFAULT_SIGMA,
                    p_fa=None, leak_tol=0.3, n_points=3, time_origin="absolute", seed=0,
                    dt=1.0, duration=FLIGHT_S, sites_deg=None, q_rw=1e-6, with_chi2=False):
    """Simulate the paper's flight with pseudorange faults and diagnose it.

    A pure function of its arguments (seeded): the chapter's slider calls it.

    Steps: trajectory and true INS errors (:mod:`xnavlab.plins.ins`); pseudoranges with
    ``faults`` injected (:mod:`xnavlab.plins.pseudolites`); T-S local models at ``n_points``
    operating points; single-sensor parity bases (numerical left null space with
    ``tol = leak_tol * sigma``), aligned and blended with the memberships; global
    residuals, threshold and alarms; onset search and Kalman identification for each
    alarmed sensor; optionally the chi-square comparison detector.

    Parameters
    ----------
    faults : sequence of xnavlab.core.faults.Fault
        Faults of sensor ``"pseudorange"`` (component = pseudolite index).
    model : {"step", "ramp"}
        Fault model used to identify alarmed sensors.
    s : int
        Window length minus one, in [2, 60] (paper: 11).
    threshold : float, optional
        ``r_t`` in metres, > 0 (default :func:`~.space.residual_threshold` at ``p_fa``).
    sigma : float
        Pseudorange noise, m, in [1e-6, 1e6] (:data:`~.identification.SIGMA_MIN`; default 2 m,
        see :mod:`xnavlab.plins.pseudolites`).
    p_fa : float, optional
        False-alarm probability per window and sensor, in (0, 0.5), of the default threshold
        and of the chi-square detector (default 1e-6). Refused beside a ``threshold`` unless
        ``with_chi2`` (it would be ignored).
    leak_tol : float
        Largest contribution of a typical state or noise left in the residual, in
        units of ``sigma``, in (0, 1e6] (sets the numerical left null space).
    n_points : int
        Number of T-S operating points.
    time_origin : {"absolute", "onset"}
        Reading of ``t`` in a ramp ``a t + b`` (:func:`~.identification.fault_signature`).
    seed : int or numpy.random.Generator
        Seed of INS errors and pseudorange noise.
    dt, duration : float
        Sample interval, s, in [1e-3, 3] (the T-S design of the paper's flight keeps one
        parity-space dimension across its operating points up to 3 s; at 3.5 s they differ),
        and flight time, s, in (0, 1e4], a whole number of steps ``dt``
        (:func:`xnavlab.plins.ins.paper_trajectory`), with at most :data:`MAX_SAMPLES`
        (50,000) samples ``duration / dt + 1``. Decision: a new flight costs about 6 ms a
        sample (:data:`DESIGN_S_PER_SAMPLE`, measured on 2 cores), so the cap keeps a call
        to about 5 minutes (the book's flight has 201 samples, 1 s); 1e6 samples (1.7 h) are
        refused, naming dt and duration.
    sites_deg : array_like, shape (m, 3), optional
        Pseudolite sites ``[lat_deg, lon_deg, h]`` (default
        :data:`xnavlab.plins.pseudolites.DEFAULT_SITES_DEG`).
    q_rw : float
        Random-walk variance of the fault parameters per step.
    with_chi2 : bool
        Also run the chi-square comparison detector (:func:`chi2_monitor`).

    Returns
    -------
    Diagnosis

    Examples
    --------
    >>> from xnavlab.core.faults import Fault
    >>> d = diagnose_flight([Fault("pseudorange", "step", 300.0, 50.0, component=0)])
    >>> d.detection[0], d.detection[1], round(float(d.identification[0].final[0]))
    (50.0, None, 300)
    """
    check_choice("model", model, ("step", "ramp"))
    with_chi2 = check_bool("with_chi2", with_chi2)
    if threshold is not None:
        threshold = check_real("threshold", threshold, 0.0, lo_open=True)
        if p_fa is not None and not with_chi2:  # it sets no threshold and no chi-square test
            raise ValueError("p_fa must be omitted when threshold is given without with_chi2 "
                             "(it would be ignored: it sets the default threshold and the "
                             "chi-square detector's)")
    p_fa = 1e-6 if p_fa is None else check_real("p_fa", p_fa, 0.0, 0.5, lo_open=True,
                                                 hi_open=True)
    s = check_int("s", s, 2, 60)
    sigma = check_real("sigma", sigma, SIGMA_MIN, 1e6)  # as identify_fault's (sigma^2 normal)
    leak_tol = check_real("leak_tol", leak_tol, 0.0, 1e6, lo_open=True)  # tol = leak_tol sigma finite
    check_choice("time_origin", time_origin, ("absolute", "onset"))
    # up to 3 s the flight's local parity spaces agree in dimension (at 3.5 s, 4 s and 4.5 s
    # they do not, refused as leak_tol's; from 5 s its error model outgrows discretize's bound)
    dt = check_real("dt", dt, 1e-3, 3.0)
    duration = check_real("duration", duration, 0.0, 1e4, lo_open=True)
    if duration / dt < s + 2:
        raise ValueError(f"duration must cover more than s + 2 = {s + 2} samples")
    _check_samples(dt, duration)
    if isinstance(faults, np.ndarray) and faults.ndim == 0:  # iterable to hasattr, not to list
        raise ValueError(f"faults must be a sequence of Fault, got {shown(faults)}")
    faults = _faults.check_faults("faults", faults)
    rng = make_rng(seed, "seed")
    traj, trans = _flight(dt, duration)
    sites = _pl.sites_ecef(sites_deg)
    x_err = _ins.simulate_errors(traj, rng=rng, transitions=trans)
    data = _pl.simulate_pseudoranges(traj, x_err, sites, sigma=sigma, faults=faults, rng=rng)
    m = data.z.shape[1]
    tol = leak_tol * sigma
    points, weights, W, q = _design(traj, sites, s, tol, n_points, (
        "leak_tol", f"{leak_tol:g} (tol = leak_tol x sigma = {tol:g} m)"))
    r = parity_residuals(data.z, W)
    stat = np.linalg.norm(r, axis=2)
    thr = residual_threshold(sigma, q, p_fa) if threshold is None else threshold
    t = traj.t.copy()   # the cached flight's own times stay out of the result
    t_res = t[s:]
    detection, onsets, ident = [], [], {}
    for j in range(m):
        ta = first_alarm(t_res, stat[:, j], thr)
        detection.append(ta)
        if ta is None:
            onsets.append(None)
            continue
        k_alarm = int(np.flatnonzero(traj.t == ta)[0])
        onset = estimate_onset(traj.t, data.z[:, j], W[:, j], k_alarm, model, time_origin)
        onsets.append(onset)
        ident[j] = identify_fault(traj.t, data.z[:, j], W[:, j], onset, model, sigma,
                                  time_origin, q_rw, sensor=j)
    chi = chi2_monitor(data, trans, sites, p_fa=p_fa) if with_chi2 else None  # checked above
    return Diagnosis(
        t=t, z=data.z, fault=data.fault, t_res=t_res, residual=r, statistic=stat,
        threshold=thr, detection=detection, onset=onsets, identification=ident, s=s,
        null_dim=q, sigma=sigma, weights=weights, points=points, chi2=chi,
    )


def compare_detectors(kind, sizes, *, onset=None, sensor=0, n_runs=5, seed=0, **kwargs):
    """Detection rate and delay of the parity test and the chi-square test, by fault size.

    For each size a fault of ``kind`` is put on pseudorange ``sensor`` and the flight of
    :func:`diagnose_flight` is simulated ``n_runs`` times (seeds ``seed, seed+1, ...``).

    Parameters
    ----------
    kind : {"step", "ramp"}
        Fault kind (a ramp starts from zero at the onset).
    sizes : sequence of float
        Step sizes (m) or ramp slopes (m/s).
    onset : float, optional
        Onset, s, in [0, duration] (default 50 s for a step, 30 s for a ramp, as in the paper).
    sensor : int
        Faulty pseudorange, 0-based, one of the sites (0..3 with the default four).
    n_runs : int
        Runs per size, in [1, 1000], and few enough that the whole call is estimated at
        most :data:`MAX_SECONDS` (10 minutes): ``samples x (DESIGN_S_PER_SAMPLE + len(sizes)
        x n_runs x RUN_S_PER_SAMPLE)``, measured rates (the book's 4 sizes x 5 runs of 201
        samples take about 5 s); a longer call is refused, naming n_runs.
    seed : int
        First seed, in ``[0, SEED_MAX - n_runs + 1]`` (the runs take ``seed`` to
        ``seed + n_runs - 1``).
    **kwargs
        Passed to :func:`diagnose_flight` (``sigma``, ``s``, ``threshold``, ``p_fa``...).

    Returns
    -------
    list of dict
        One row per size: ``size``, ``parity_rate`` and ``chi2_rate`` (fraction of runs
        with an alarm at or after the onset), ``parity_delay`` and ``chi2_delay`` (median
        delay of those alarms, s, or ``None``), ``isolated`` (fraction of runs in which
        the parity test alarmed on the faulty sensor only; the chi-square test cannot
        isolate).

    Examples
    --------
    >>> row, = compare_detectors("step", [100.0], n_runs=1)
    >>> row["parity_delay"], row["chi2_delay"], row["isolated"]
    (0.0, 0.0, 1.0)
    """
    check_choice("kind", kind, ("step", "ramp"))
    sizes = np.atleast_1d(check_finite_array("sizes", sizes))
    if sizes.ndim != 1 or not sizes.size:  # an empty table would come back without a word
        raise ValueError(f"sizes must be a list of at least one fault size (shape (n,), n >= 1), "
                         f"got shape {sizes.shape}")
    for i, size in enumerate(sizes):
        if size == 0.0 or abs(size) > _faults.MAX_SIZE:
            raise ValueError(f"sizes[{i}] must be a nonzero fault size of at most "
                             f"{_faults.MAX_SIZE:g} m (or m/s), got {size:g}")
        if size in sizes[:i]:  # the same runs twice: one row repeated, not a second size
            first = int(np.flatnonzero(sizes[:i] == size)[0])
            raise ValueError(f"sizes lists {size:g} twice (items {first} and {i})")
    takes = set(inspect.signature(diagnose_flight).parameters) - {"faults", "seed", "with_chi2"}
    for key in kwargs:
        if key not in takes:
            why = ("set by compare_detectors itself" if key in ("faults", "seed", "with_chi2")
                   else "not a setting of diagnose_flight")
            raise ValueError(f"compare_detectors got {key}={kwargs[key]!r:.60}: {why} (it passes "
                             f"on {', '.join(sorted(takes))})")
    # the onset checked under its own name (it was refused as "faults[0] ... starts outside this
    # flight", a list the user never gave), inside the flight [0, duration]
    duration = check_real("duration", kwargs.get("duration", FLIGHT_S), 0.0, 1e4, lo_open=True)
    onset = check_real("onset", (50.0 if kind == "step" else 30.0) if onset is None else onset,
                       0.0, duration)
    n_sites = len(_pl.sites_ecef(kwargs.get("sites_deg")))
    sensor = check_int("sensor", sensor, 0, n_sites - 1)  # one pseudorange per site
    n_runs = check_int("n_runs", n_runs, 1, 1000)
    seed = check_int("seed", seed, 0, SEED_MAX - (n_runs - 1))  # its runs take seed + i
    dt = check_real("dt", kwargs.get("dt", 1.0), 1e-3, 3.0)  # as diagnose_flight's
    n = _check_samples(dt, duration)
    cost = n * (DESIGN_S_PER_SAMPLE + len(sizes) * n_runs * RUN_S_PER_SAMPLE)
    if cost > MAX_SECONDS:  # the flight's design once, then every run of every size
        most = max(0, int((MAX_SECONDS / n - DESIGN_S_PER_SAMPLE) / RUN_S_PER_SAMPLE / len(sizes)))
        raise ValueError(
            f"n_runs must keep compare_detectors within about {MAX_SECONDS / 60:.0f} min: {len(sizes)} "
            f"sizes x {n_runs} runs of {n} samples (duration = {duration:g} s at dt = {dt:g} s) at the "
            f"measured {RUN_S_PER_SAMPLE * 1e3:g} ms a sample (and {DESIGN_S_PER_SAMPLE * 1e3:g} ms for "
            f"the flight's design) is about {cost / 60:.3g} min; at most {most} runs here")
    rows = []
    for size in sizes:
        fault = _faults.Fault(_pl.SENSOR, kind, float(size), onset, component=sensor)
        pd, cd, iso = [], [], 0
        for i in range(n_runs):
            d = diagnose_flight([fault], seed=seed + i, with_chi2=True, **kwargs)
            if sensor >= len(d.detection):
                raise ValueError(f"sensor must be in [0, {len(d.detection) - 1}], got {sensor}")
            ta = first_alarm(d.t_res, d.statistic[:, sensor], d.threshold, after=onset)
            tc = d.chi2.first_alarm(after=onset)
            if ta is not None:
                pd.append(ta - onset)
                others = [first_alarm(d.t_res, d.statistic[:, j], d.threshold)
                          for j in range(len(d.detection)) if j != sensor]
                iso += all(o is None for o in others)
            if tc is not None:
                cd.append(tc - onset)
        rows.append({
            "size": float(size),
            "parity_rate": len(pd) / n_runs,
            "parity_delay": float(np.median(pd)) if pd else None,
            "chi2_rate": len(cd) / n_runs,
            "chi2_delay": float(np.median(cd)) if cd else None,
            "isolated": iso / n_runs,
        })
    return rows
