"""The main paper's Mars scenario: truth, sensors, three local EKFs and the federated master.

:class:`MarsScenario` holds every parameter (defaults: Fan et al. 2016, section 4.1);
:func:`prepare` builds the shared inputs once (time grid, truth trajectory, ephemeris
tables, every noisy measurement from one seeded generator); :func:`run` runs the
federated filter on them with one of two interchangeable back-ends:

``backend="numpy"``
    the readable loop: :class:`xnavlab.core.federated.FederatedFilter` with
    :class:`xnavlab.core.filters.EKF` locals, :mod:`xnavlab.mars.models.sensors` models and the
    :mod:`xnavlab.mars.models.dynamics` force model, one epoch at a time. The chapters teach with it.
``backend="numba"``
    the same filter compiled (:mod:`xnavlab.mars.kernel.kernels`), about a microsecond per epoch
    of three EKFs and the fusion; same estimates to rounding (the tests check 1e-9
    relative). In reset mode the kernel fuses through the identity that makes that mode
    optimal (the centralised update, :mod:`xnavlab.mars.kernel.kernels`) at the epochs whose
    local estimates are not recorded.

The time grid is the union of every sensor's measurement epochs (every 3 s for UV and CNS, every
500 s for XNAV, so the grid has a few extra epochs where 500 s is not a multiple of 3 s) and the
run's end, ``t0 + days``; the filters step from epoch to epoch and the master fuses at every epoch.
Fault handling hooks (used by the fault-tolerant chapters): ``active`` switches any subsystem out
of the measurement updates and the fusion and back in, epoch by epoch; ``gate`` rejects
innovations whose NIS exceeds a threshold; every NIS is recorded (``MarsRun.nis``, ``MarsRun.flags``).

Filter model (the paper gives no process noise): the same force model as the truth
(Mars point mass, Sun and Jupiter with the indirect term, from the filter's
ephemeris), classical RK4 sub-steps of at most ``max_step`` (10 s) between epochs, the
product of fourth-order transition matrices over the sub-steps, and white
acceleration noise of power spectral density ``q_acc`` (m^2/s^3) standing for
unmodelled accelerations: ``Q = q [[dt^3/3 I, dt^2/2 I], [dt^2/2 I, dt I]]``.

Error metric (the paper does not define one): :meth:`MarsRun.metrics` returns the RMS
over time of the norm of the fused position and velocity errors after the filter has
settled (from ``settle_days``, default 1 day, to the end). The RMS of the norm is the one
number that summarises a curve like the paper's Fig. 2, weighs every axis and every epoch
equally, and leaves the 5-km initial transient out.

Examples
--------
>>> sc = MarsScenario(days=0.05, seed=1)
>>> res = run(sc)
>>> res.t.shape == (res.x.shape[0],), res.x.shape[1]
(True, 6)
>>> bool(res.metrics(settle_days=0.0)["position_error_m"] < 5000.0)
True
"""

from __future__ import annotations

import functools
import hashlib
import math
import sys
import time
from collections import OrderedDict
from dataclasses import dataclass, field, fields, replace
from numbers import Real

import numpy as np

from xnavlab.core import dates, ephemeris
from xnavlab.core.constants import DAY, GM_MARS, C
from xnavlab.core.federated import MODES, FederatedFilter
from xnavlab.core.validate import (
    check_bool,
    check_choice,
    check_items,
    check_real,
    check_seed,
    make_rng,
)
from xnavlab.mars.kernel import compile_notice, kernels
from xnavlab.mars.kernel import kernel_inputs as ki
from xnavlab.mars.models import dynamics, force_models, model_noise, optics, sensors, stars
from xnavlab.mars.models.time_update import Propagation, process_noise
from xnavlab.mars.navigation import _run_checks, unused_inputs
from xnavlab.mars.timing import pulsar_specs, pulsars, timing_bound, toa

__all__ = ["alloc_records", "run_options", "filter_state", "run_kernel", "SUBSYSTEMS",
           "DEFAULT_Q_ACC", "MarsScenario", "default_settle_days", "Inputs", "MarsRun",
           "check_scenario", "check_overrides", "prepare", "run"]


#: The three subsystems of the paper, in its numbering (1 XNAV, 2 UV, 3 CNS).
SUBSYSTEMS = ("xnav", "uv", "cns")
_KIND = {"xnav": 0, "uv": 1, "cns": 2}

#: Default white-acceleration noise PSD of the filters, m^2/s^3 (see :class:`MarsScenario`).
DEFAULT_Q_ACC = 1.0e-11


def check_overrides(overrides):
    """``overrides`` (a dict of :class:`MarsScenario` fields), or one ValueError naming each
    unknown name and the fields (not a raw TypeError from the constructor).

    >>> check_overrides({"dayz": 1})  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ValueError: unknown override dayz: not a field of MarsScenario (the fields: days, dt_xnav, ...)
    >>> check_overrides([1])
    Traceback (most recent call last):
    ...
    ValueError: overrides must be a dict of MarsScenario fields ({name: value}), got list [1]
    """
    return _run_checks.check_names("overrides", overrides, [f.name for f in fields(MarsScenario)],
                                   "MarsScenario")


def check_scenario(name, value):
    """``value`` if it is a :class:`MarsScenario`, ``MarsScenario()`` for None, else one
    ValueError naming ``name`` (a dict of fields is not a scenario: ``MarsScenario(**fields)``).

    Examples
    --------
    >>> check_scenario("scenario", None).days
    30.0
    >>> check_scenario("scenario", {"days": 1})
    Traceback (most recent call last):
    ...
    ValueError: scenario must be a MarsScenario, got dict {'days': 1} (build one with MarsScenario(**fields))
    """
    return _run_checks.check_scenario(name, value, MarsScenario)


def default_settle_days(days):
    """The one default settling span of a run of ``days``: ``min(1, days / 2)`` days.

    The Python API (:meth:`MarsRun.metrics`, :meth:`MarsRun.summary`), the fault-tolerant
    run's wavelet training span and the command line all take it, so the same run gives
    the same summary every way: one day for the paper's 30 days (its filter has settled),
    half the run for a shorter one (so the RMS is never that of one sample).

    Examples
    --------
    >>> default_settle_days(30.0), default_settle_days(1.0)
    (1.0, 0.5)
    """
    days = check_real("days", days, 0.0, 365.0, lo_open=True)  # a scenario's range
    return min(1.0, days / 2.0)


@dataclass(frozen=True)
class MarsScenario:
    """Every parameter of the Mars navigation run (defaults: the main paper's).

    Parameters
    ----------
    days : float
        Simulated span, days (paper: 30): the run ends at ``t0 + days``, with a last, shorter
        step that only propagates where no sensor's interval ends there.
    dt_xnav, dt_uv, dt_cns : float
        Measurement intervals, s (paper: 500, 3, 3).
    pulsars : tuple
        XNAV pulsars (paper: B0531+21, B1937+21, B1957+20, B1821-24): catalogue names, paths
        of timing models (``.par``) or tables of their properties
        (:mod:`xnavlab.mars.timing.pulsar_specs`; a table is kept as its Pulsar).
    xnav_sigma_m : tuple of float or None
        Ranging accuracy of each pulsar, m; ``None`` computes it for ``area_m2``,
        ``dt_xnav`` (the integration time) and ``background`` with ``xnav_noise``.
    xnav_noise : {"paper", "crlb"}
        What ``None`` computes (:func:`xnavlab.mars.timing.timing_bound.xnav_noise_sigma`): the
        paper's formula or the Cramer-Rao bound (99, 454, 2637, 381 m); for noise and R alike.
    area_m2, background : float
        Detector area, m^2, and X-ray background, ph/cm^2/s.
    sigma_range_m, sigma_dir_deg : float
        UV range and per-axis direction noise (paper: 5000 m, 0.1 deg).
    sigma_star_arcsec, sigma_horizon_deg : float
        CNS star-sensor and horizon-sensor noise (paper: 3 arcsec, 0.05 deg).
    uv_range_model, limb, horizon_tau_s : str, str, float
        The optical sensors as instruments (:mod:`xnavlab.mars.models.optics`; the filter keeps its
        white ``R``): UV range ``"constant"`` (paper) or ``"radius"`` (from the apparent
        radius), limb ``"sphere"`` (paper) or ``"oblate"``, horizon errors white (``0``,
        paper) or Gauss-Markov with this correlation time, s.
    stars : tuple of str or None
        The CNS stars, one or more (none twice; one angle each); ``None`` applies
        :func:`xnavlab.mars.models.stars.pick_three`.
    pos_err0_m, vel_err0_mps : float
        Initial error per axis (paper: 5000 m and 1 m/s); also the initial 1-sigma.
    init_error : {"fixed", "random"}
        ``"fixed"``: the estimate starts at truth + (pos_err0, pos_err0, pos_err0,
        vel_err0, ...) as in the paper; ``"random"``: an N(0, P0) draw (Monte Carlo).
    q_acc : float
        Filter process noise, white-acceleration PSD, m^2/s^3. The paper gives none;
        the default 1e-11 stands for an unmodelled acceleration of 1e-7 m/s^2 (the
        size of solar radiation pressure on a Mars orbiter) correlated over about
        1000 s (``q = sigma_a^2 tau``). With ``q_acc = 0`` the filter grows
        overconfident and diverges; chapter 5 sweeps it.
    max_step : float
        Longest filter integration sub-step, s (a longer epoch gap is split).
    truth_ephem, filter_ephem : {"de421", "de405"}
        Ephemerides of the truth and of the filter (dynamics and XNAV).
    truth_model, filter_model : ForceModel or str
        Force models of the truth and of the filter (:mod:`xnavlab.mars.models.force_models`; the
        filter's: no harmonics, no SRP). Default both the paper's: the paper's set-up
        (:attr:`paper_setup`); :meth:`study` gives the studies' set-up.
    subsystems : tuple of str
        Which subsystems run, any of ``("xnav", "uv", "cns")``; a field set (not at its default)
        for one that does not run is refused (:mod:`xnavlab.mars.navigation.unused_inputs`).
    beta : tuple of float or None
        Information-sharing factors, one a subsystem, each in [1e-3, 1] (default equal); the run
        normalises them to sum 1, so only their ratios count ((1, 1, 1) is the default), and
        a run of one subsystem takes none.
    mode : {"reset", "no-reset"}
        Federated mode (:mod:`xnavlab.core.federated`).
    record_dt : float
        Spacing of the recorded estimates, s, at least the shortest measurement interval of
        the subsystems (one record an epoch; the default 60 s records every epoch of XNAV alone).
    seed : int
        Seed of the single generator that draws every noise sample.
    t0 : float
        Start epoch, s TDB past J2000 (:data:`xnavlab.mars.models.dynamics.MARS_T0`); the run, ``t0`` to
        ``t0 + days``, must lie in the coverage of both ephemerides.
    state0 : tuple of float
        True initial state, Mars-centred J2000, m and m/s (the paper's); above Mars and
        slower than any craft bound to the Sun (:func:`~xnavlab.mars.models.dynamics.check_state0`).

    Examples
    --------
    >>> MarsScenario().n_steps
    864000
    >>> MarsScenario(days=-1)
    Traceback (most recent call last):
    ...
    ValueError: days must be a real number in (0, 365], got -1
    """

    days: float = 30.0
    dt_xnav: float = 500.0
    dt_uv: float = 3.0
    dt_cns: float = 3.0
    pulsars: tuple = pulsars.PAPER_PULSARS
    xnav_sigma_m: tuple | None = None
    xnav_noise: str = "paper"
    area_m2: float = 1.0
    background: float = 0.005
    sigma_range_m: float = 5000.0
    sigma_dir_deg: float = 0.1
    sigma_star_arcsec: float = 3.0
    sigma_horizon_deg: float = 0.05
    stars: tuple | None = None
    uv_range_model: str = "constant"
    limb: str = "sphere"
    horizon_tau_s: float = 0.0
    pos_err0_m: float = 5000.0
    vel_err0_mps: float = 1.0
    init_error: str = "fixed"
    q_acc: float = DEFAULT_Q_ACC
    max_step: float = 10.0
    truth_ephem: str = "de421"
    filter_ephem: str = "de421"
    truth_model: force_models.ForceModel = force_models.PAPER
    filter_model: force_models.ForceModel = force_models.PAPER
    subsystems: tuple = SUBSYSTEMS
    beta: tuple | None = None
    mode: str = "reset"
    record_dt: float = 60.0
    seed: int = 0
    t0: float = dynamics.MARS_T0
    state0: tuple = tuple(dynamics.MARS_STATE0.tolist())

    def __post_init__(self):
        for f in (f for f in fields(self) if type(f.default) is float):  # reals kept as floats
            v = getattr(self, f.name)  # (a Fraction failed; np.float16 overflowed in days * DAY)
            # (a Python int or float is kept: the messages show it as given, 10**400 included)
            plain = isinstance(v, bool | np.bool_ | int | float)
            if isinstance(v, Real | np.floating | np.integer) and not plain:
                object.__setattr__(self, f.name, float(v))  # the range checks below refuse the rest
        check_real("days", self.days, 0.0, 365.0, lo_open=True)
        for name in ("dt_xnav", "dt_uv", "dt_cns"):
            check_real(name, getattr(self, name), 0.1, 86400.0)
        check_real("area_m2", self.area_m2, 0.0, 100.0, lo_open=True)
        check_real("background", self.background, 0.0, 10.0)
        check_real("sigma_range_m", self.sigma_range_m, 0.0, 1e7, lo_open=True)
        check_real("sigma_dir_deg", self.sigma_dir_deg, 0.0, 10.0, lo_open=True)
        check_real("sigma_star_arcsec", self.sigma_star_arcsec, 0.0, 3600.0, lo_open=True)
        check_real("sigma_horizon_deg", self.sigma_horizon_deg, 0.0, 10.0, lo_open=True)
        check_choice("uv_range_model", self.uv_range_model, optics.RANGE_MODELS)
        check_choice("limb", self.limb, optics.LIMBS)
        check_real("horizon_tau_s", self.horizon_tau_s, 0.0, 1e8)
        check_real("pos_err0_m", self.pos_err0_m, 0.0, 1e7, lo_open=True)
        check_real("vel_err0_mps", self.vel_err0_mps, 0.0, 1e3, lo_open=True)
        check_choice("init_error", self.init_error, ("fixed", "random"))
        check_real("q_acc", self.q_acc, 0.0, 1.0)
        check_real("max_step", self.max_step, 0.01, 3600.0)
        check_choice("truth_ephem", self.truth_ephem, ephemeris.EPHEMERIDES)
        check_choice("filter_ephem", self.filter_ephem, ephemeris.EPHEMERIDES)
        models = force_models.check_models(self.truth_model, self.filter_model)
        object.__setattr__(self, "truth_model", models[0])
        object.__setattr__(self, "filter_model", models[1])
        subs = check_items("subsystems", self.subsystems, "subsystem",
                           lambda label, s: check_choice(label, s, SUBSYSTEMS))
        object.__setattr__(self, "subsystems", subs)
        shortest = min(getattr(self, f"dt_{s}") for s in subs)
        if self.days * DAY < shortest:  # no measurement, one record: nothing to judge
            raise ValueError(f"days must span at least one measurement interval ({shortest:g} s "
                             f"= {shortest / DAY:.3g} days, the shortest of {', '.join(subs)}), "
                             f"got {self.days:g}")
        object.__setattr__(self, "pulsars", pulsar_specs.check_list(self.pulsars))
        if self.xnav_sigma_m is not None:
            sig = tuple(float(check_real(f"xnav_sigma_m[{i}]", s, 0.0, 1e9, lo_open=True))
                        for i, s in enumerate(check_items("xnav_sigma_m", self.xnav_sigma_m,
                                                          "number", lambda _, v: object())))
            if len(sig) != len(self.pulsars):
                n = len(self.pulsars)
                raise ValueError(f"xnav_sigma_m must hold {n} value{'s' if n > 1 else ''}, one "
                                 f"a pulsar, got {len(sig)}")
            object.__setattr__(self, "xnav_sigma_m", sig)
        check_choice("xnav_noise", self.xnav_noise, timing_bound.XNAV_NOISE)
        if self.stars is not None:
            object.__setattr__(self, "stars", check_items("stars", self.stars, "star",
                                                          lambda _, s: stars.get(s).name))
            object.__setattr__(self, "stars", tuple(stars.get(s).name for s in self.stars))
        if self.beta is not None:
            # from 1e-3: a local filter's covariance is P0 / beta (5e-324 divided by zero)
            b = tuple(float(check_real(f"beta[{i}]", v, 1e-3, 1.0))
                      for i, v in enumerate(check_items("beta", self.beta, "number",
                                                        lambda _, v: object())))
            if len(b) != len(subs) and len(subs) > 1:  # one: unused_inputs refuses any beta
                raise ValueError(f"beta must hold {len(subs)} factor{'s' if len(subs) > 1 else ''}"
                                 f", one a subsystem, got {len(b)}")
            object.__setattr__(self, "beta", b)
        check_choice("mode", self.mode, MODES)
        check_real("record_dt", self.record_dt, 0.1, 86400.0)
        object.__setattr__(self, "seed", check_seed("seed", self.seed))
        e = sorted({self.truth_ephem, self.filter_ephem})  # the run, t0 to t0 + span, on them
        lo, hi = (f(c[j] for c in map(ephemeris.coverage, e)) for j, f in ((0, max), (1, min)))
        if not lo <= check_real("t0", self.t0) <= hi - self.span:
            e = " and ".join(x.upper() for x in e)
            raise ValueError(f"t0 must be in {dates.epoch_range(lo, hi - self.span)} (the run, t0 to "
                             f"t0 + days, in {e}), got {dates.epoch_text(self.t0)}")
        s0 = dynamics.check_state0(self.state0)  # here, so scenario --check says so
        object.__setattr__(self, "state0", tuple(float(v) for v in s0))
        unused_inputs.check_fields(self)  # a field set but made inert by another is refused

    @classmethod
    def study(cls, **fields):
        """The studies' set-up: rich truth, the paper's filter, ``q_acc`` from their difference
        (:func:`xnavlab.mars.models.model_noise.study_fields`); ``fields`` replace any of them."""
        return cls(**model_noise.study_fields(lambda kw: cls(**kw), check_overrides(fields)))

    @property
    def paper_setup(self):
        """Whether truth and filter share the paper's force model and ephemeris (the paper's set-up)."""
        return (self.truth_model.is_paper and self.filter_model.is_paper
                and self.truth_ephem == self.filter_ephem)

    @property
    def span(self):
        """Simulated span, s."""
        return self.days * DAY

    @property
    def n_steps(self):
        """Number of 3-s (``dt_uv``) steps in the span."""
        return int(round(self.span / self.dt_uv))

    def sensors(self):
        """The sensor objects ``{"xnav": XNAVSensor, "uv": UVSensor, "cns": CNSSensor}``."""
        sig = (None if self.xnav_sigma_m is None else np.array(self.xnav_sigma_m) / C)
        if sig is None and self.xnav_noise == "crlb":
            sig = timing_bound.xnav_noise_sigma("crlb", self.pulsars, self.area_m2, self.dt_xnav,
                                                self.background)
        noise = {} if sig is not None else {"area_m2": self.area_m2, "t_obs": self.dt_xnav,
                                            "background": self.background}  # what sig replaces
        return {
            "xnav": sensors.XNAVSensor(tuple(p if p in pulsars.CATALOGUE else pulsars.get(p)
                                             for p in self.pulsars), sigma=sig, **noise,
                                       ephem=self.filter_ephem),
            "uv": sensors.UVSensor(self.sigma_range_m, self.sigma_dir_deg),
            "cns": sensors.CNSSensor(self.stars, self.sigma_star_arcsec, self.sigma_horizon_deg,
                                     epoch=self.t0),
        }

    @property
    def P0(self):
        """Initial covariance, diag(pos_err0^2 I3, vel_err0^2 I3)."""
        return np.diag([self.pos_err0_m**2] * 3 + [self.vel_err0_mps**2] * 3)


@dataclass
class Inputs:
    """Everything a run consumes, precomputed once (shared by both back-ends).

    Attributes
    ----------
    times : ndarray, shape (n,)
        Filter epochs, s TDB past J2000 (``times[0] = t0``).
    truth : ndarray, shape (n, 6)
        True states at ``times``.
    x0 : ndarray, shape (6,)
        Initial estimate.
    meas_idx : ndarray of int, shape (n, ns)
        Row of subsystem i's measurement array at epoch k, or -1.
    z : dict
        Noisy measurements by subsystem: ``xnav`` (m_x, k) s, ``uv`` (m_u, 4),
        ``cns`` (m_c, 3) rad.
    t_meas : dict
        Their epochs.
    xnav_bodies : tuple of ndarray
        Filter-ephemeris Mars and Sun SSB positions at the XNAV epochs, (m_x, 3) each.
    table : ThirdBodyTable
        Filter-ephemeris third bodies for the dynamics.
    record : ndarray of int
        Epoch indices recorded.
    sensors : dict
        The sensor objects.
    """

    scenario: MarsScenario
    times: np.ndarray
    truth: np.ndarray
    x0: np.ndarray
    meas_idx: np.ndarray
    z: dict
    t_meas: dict
    xnav_bodies: tuple
    table: dynamics.ThirdBodyTable
    record: np.ndarray
    sensors: dict = field(repr=False)

    @property
    def n(self):
        return self.times.size

    def check(self, name="inputs"):
        """``self`` if its arrays agree (shapes, keys, finite values, ``record`` increasing in
        [0, n)), else one ValueError naming ``<name>.<field>``: an Inputs edited by hand."""
        return _run_checks.check_inputs(name, self, Inputs, SUBSYSTEMS)


# ------------------------------------------------------------------ preparation

_TRUTH_CACHE: OrderedDict = OrderedDict()


def _truth(times, sc):
    key = (sc.t0, sc.state0, sc.truth_ephem, sc.truth_model, hashlib.sha1(times.tobytes()).digest())
    if key not in _TRUTH_CACHE:  # read-only: the runs of these settings share it (review 35r R1)
        x = force_models.truth(times, np.array(sc.state0), sc.t0, sc.truth_model, ephem=sc.truth_ephem)
        x.flags.writeable = False
        _TRUTH_CACHE[key] = x
        while len(_TRUTH_CACHE) > 2:
            _TRUTH_CACHE.popitem(last=False)
    return _TRUTH_CACHE[key]


def _epochs(span, dt):
    n = int(math.floor(span / dt + 1e-9))
    return dt * np.arange(1, n + 1)


#: Rows of noise drawn at a time for the long measurement series (a reused buffer).
_CHUNK = 65536


def _series(rng, truth, k, n_noise, n_meas, simulate, params):
    """A measurement series at the truth rows ``k``, drawn chunk by chunk.

    The noise comes in the same order, with the same values, as one
    ``rng.standard_normal((k.size, n_noise))``, through a buffer of :data:`_CHUNK` rows
    (the 30-day series would otherwise allocate 75 MB of draws and 40 MB of states);
    ``simulate(states, noise, *params, out)`` fills ``out`` (rows, n_meas).
    """
    out = np.empty((k.size, n_meas))
    buf = np.empty((min(k.size, _CHUNK), n_noise))
    for a in range(0, k.size, _CHUNK):
        b = min(a + _CHUNK, k.size)
        noise = buf[:b - a]
        rng.standard_normal(out=noise)
        simulate(truth[k[a:b]], noise, *params, out[a:b])
    return out


def prepare(scenario=None, **overrides):
    """Build the inputs of a run: grid, truth, measurements (one seeded generator).

    The truth comes from :func:`xnavlab.mars.models.dynamics.truth` (the tight DOP853 propagator,
    cached on disk); the last two distinct truths are also kept in memory. The UV and CNS
    series (864 000 epochs each over 30 days) are drawn by
    :func:`xnavlab.mars.models.series.simulate_uv` and :func:`~xnavlab.mars.models.series.simulate_cns`,
    the models of :meth:`xnavlab.mars.models.sensors.UVSensor.simulate` and
    :meth:`xnavlab.mars.models.sensors.CNSSensor.simulate` compiled: same
    draws, same values to rounding, without numpy's temporaries.

    Parameters
    ----------
    scenario : MarsScenario, optional
        Default ``MarsScenario()``.
    **overrides
        Fields to replace, e.g. ``days=1``.

    Returns
    -------
    Inputs

    Examples
    --------
    >>> inp = prepare(days=0.01)
    >>> inp.times[:3] - inp.times[0], inp.z["uv"].shape
    (array([0., 3., 6.]), (288, 4))
    """
    sc = check_scenario("scenario", scenario)
    if overrides:
        sc = replace(sc, **check_overrides(overrides))
    rng = make_rng(sc.seed)
    span = sc.span
    dts = {"xnav": sc.dt_xnav, "uv": sc.dt_uv, "cns": sc.dt_cns}
    offs = {dt: np.round(_epochs(span, dt), 6) for dt in {dts[s] for s in sc.subsystems}}
    unused_inputs.warn_unmeasured(sc, {s: offs[dts[s]].size for s in sc.subsystems})
    grid = np.unique(np.concatenate([[0.0], *offs.values(), [np.round(span, 6)]]))  # to t0 + days
    times = sc.t0 + grid
    truth = _truth(times, sc)
    meas_idx = np.full((times.size, len(sc.subsystems)), -1, dtype=np.int64)
    t_meas, z = {}, {}
    sens = sc.sensors()
    P0 = sc.P0  # draw order: initial error, then each subsystem in the paper's order
    if sc.init_error == "random":
        err0 = np.sqrt(np.diag(P0)) * rng.standard_normal(6)
    else:
        err0 = np.sqrt(np.diag(P0))
    x0 = np.array(sc.state0) + err0
    xnav_bodies = (np.zeros((0, 3)), np.zeros((0, 3)))
    rows = {dt: np.searchsorted(grid, off) for dt, off in offs.items()}  # measurement epochs
    for i, s in enumerate(sc.subsystems):
        k = rows[dts[s]]
        meas_idx[k, i] = np.arange(k.size)
        t = times[k]
        t_meas[s] = t
        if s == "xnav":
            xs = sens["xnav"]
            states = truth[k]
            rm_true = ephemeris.position("mars", t, sc.truth_ephem)
            rs_true = ephemeris.position("sun", t, sc.truth_ephem)
            noise = rng.standard_normal((t.size, xs.dim))
            z[s] = (toa.delay(rm_true + states[:, :3], xs.n, xs.distance, rs_true, shapiro="paper")
                    + xs.sigma * noise)  # paper eq. (1), as the compiled filter
            xnav_bodies = (ephemeris.position("mars", t, sc.filter_ephem).reshape(-1, 3),
                           ephemeris.position("sun", t, sc.filter_ephem).reshape(-1, 3))
        elif s == "uv":
            # the model of UVSensor.simulate, compiled (same draws, equal to rounding), or
            # the instrument options of xnavlab.mars.models.optics (same draws)
            z[s] = _series(rng, truth, k, 3, 4, *optics.uv_series_model(sc, sens["uv"]))
        else:
            # the model of CNSSensor.simulate, compiled (same draws, equal to rounding)
            cns = sens["cns"]
            z[s] = _series(rng, truth, k, 2 + 2 * cns.dim, cns.dim, *optics.cns_series_model(sc, cns))
    table = force_models.third_body_table(sc.filter_model, sc.t0, float(times[-1]),
                                          sc.filter_ephem)
    rec_t = sc.t0 + np.arange(0.0, span + 1e-9, sc.record_dt)
    record = np.unique(np.append(np.minimum(np.searchsorted(times, rec_t - 1e-6), times.size - 1),
                                 times.size - 1))
    return Inputs(sc, times, truth, x0, meas_idx, z, t_meas, xnav_bodies, table, record, sens)


# ------------------------------------------------------------------------ runs


@dataclass(frozen=True, eq=False)
class MarsRun:
    """The result of a run (frozen: ``dataclasses.replace`` checks the changed fields).

    Attributes
    ----------
    t : ndarray, shape (nr,)
        Recorded epochs, s TDB past J2000.
    x, P : ndarray, shapes (nr, 6), (nr, 6, 6)
        Fused (master) estimate and covariance.
    truth : ndarray, shape (nr, 6)
        True states.
    x_local : ndarray, shape (nr, ns, 6)
        Local estimates after their measurement updates (before any reset).
    P_local_diag : ndarray, shape (nr, ns, 6)
        Their variances.
    nis : ndarray, shape (n, ns)
        NIS of every measurement (NaN where none), all epochs.
    flags : ndarray of int8, shape (n, ns)
        0 no measurement, 1 updated, 2 rejected by the gate, 3 switched out.
    times : ndarray, shape (n,)
        All filter epochs.
    wall_time : float
        Filter run time, s.
    """

    scenario: MarsScenario
    t: np.ndarray
    x: np.ndarray
    P: np.ndarray
    truth: np.ndarray
    x_local: np.ndarray
    P_local_diag: np.ndarray
    nis: np.ndarray
    flags: np.ndarray
    times: np.ndarray
    backend: str
    wall_time: float

    def __post_init__(self):  # shapes agree, no NaN outside nis (review 35o C3)
        _run_checks.check_run(self, MarsScenario)

    @property
    def t_days(self):
        """Recorded epochs, days since the start."""
        return (self.t - self.t[0]) / DAY

    @property
    def error(self):
        """Fused estimate minus truth, shape (nr, 6)."""
        return self.x - self.truth

    def position_error(self):
        """Norm of the fused position error, m, shape (nr,)."""
        return np.linalg.norm(self.error[:, :3], axis=1)

    def velocity_error(self):
        """Norm of the fused velocity error, m/s, shape (nr,)."""
        return np.linalg.norm(self.error[:, 3:], axis=1)

    def metrics(self, settle_days=None):
        """The error metrics: RMS over time of the error norms after ``settle_days``.

        Parameters
        ----------
        settle_days : float, optional
            Start of the RMS window, days; default :func:`default_settle_days` of the run.

        Returns
        -------
        dict
            ``position_error_m``, ``velocity_error_mps`` (RMS after settling),
            ``position_error_max_m``, ``final_position_error_m``,
            ``final_velocity_error_mps``, ``settle_days``.
        """
        if settle_days is None:
            settle_days = default_settle_days(self.scenario.days)
        settle_days = check_real("settle_days", settle_days, 0.0, self.t_days[-1])
        m = self.t_days >= settle_days
        unused_inputs.warn_few_records(int(m.sum()), settle_days, self.scenario.record_dt)
        pe, ve = self.position_error(), self.velocity_error()
        return {
            "position_error_m": float(np.sqrt(np.mean(pe[m] ** 2))),
            "velocity_error_mps": float(np.sqrt(np.mean(ve[m] ** 2))),
            "position_error_max_m": float(pe[m].max()),
            "final_position_error_m": float(pe[-1]),
            "final_velocity_error_mps": float(ve[-1]),
            "settle_days": settle_days,
        }

    def nees(self):
        """NEES of the fused estimate at every record, shape (nr,)."""
        from xnavlab.core.filters import nees
        return nees(self.error, self.P)

    def sigma_position(self):
        """Fused 1-sigma position uncertainty ``sqrt(trace P_rr)``, m, shape (nr,)."""
        return np.sqrt(np.trace(self.P[:, :3, :3], axis1=1, axis2=2))

    def min_eigenvalue(self):
        """Smallest eigenvalue of each recorded fused covariance (positive when SPD)."""
        return np.linalg.eigvalsh(self.P)[:, 0]

    def summary(self, settle_days=None):
        """JSON-ready summary: metrics (settled as :meth:`metrics`), scenario, run time."""
        out = {"scenario": "mars", **self.metrics(settle_days),
               "run_time_s": self.wall_time, "backend": self.backend,
               "epochs": int(self.times.size), "days": self.scenario.days,
               "seed": self.scenario.seed, "mode": self.scenario.mode}
        for i, s in enumerate(self.scenario.subsystems):
            out[f"updates_{s}"] = int(np.sum(self.flags[:, i] == 1))
        return out

    def save_npz(self, path, **extra):
        """Write the recorded time series (and ``extra`` named arrays) to ``path`` (npz).

        ``path`` ends in ``.npz`` (numpy appends it to any other name); a missing parent folder
        is made; a folder, a file on the way, an unwritable folder or a leading ``~`` is one
        ValueError, before anything is written. ``extra``: identifiers, arrays of numbers or text."""
        own = dict(t=self.t, x=self.x, P=self.P, truth=self.truth, x_local=self.x_local,
                   P_local_diag=self.P_local_diag, position_error=self.position_error(),
                   velocity_error=self.velocity_error(), nis=self.nis, flags=self.flags,
                   times=self.times, subsystems=np.array(self.scenario.subsystems))
        path = _run_checks.check_npz(path, extra, [*own, "file", "allow_pickle"])  # savez's too
        np.savez_compressed(path, **own, **extra)


def run_options(inp, active, gate):
    """Checked run options ``(active, gate, beta)``, the defaults filled in: ``active`` (n, ns)
    bool (True/False or 1/0), all True by default; ``gate`` (ns,) NIS thresholds (>= 0, inf for
    none; one number for one subsystem), inf by default; ``beta`` (ns,) normalised to sum 1."""
    sc = _run_checks.check_object("inp", inp, Inputs).scenario
    ns = len(sc.subsystems)
    active = _run_checks.check_active(active, inp.n, sc.subsystems)
    gate = _run_checks.check_gate(gate, sc.subsystems)
    beta = np.full(ns, 1.0 / ns) if sc.beta is None else np.array(sc.beta) / np.sum(sc.beta)
    return active, gate, beta


def run(scenario=None, *, backend="numba", inputs=None, active=None, gate=None,
        progress=False, local_filter="ekf", **overrides):
    """Run the federated filter of the Mars scenario.

    Parameters
    ----------
    scenario : MarsScenario, optional
        Default ``MarsScenario()`` (the paper's 30-day run).
    backend : {"numba", "numpy"}
        Compiled kernel or the readable loop (same estimates).
    inputs : Inputs, optional
        Reuse :func:`prepare`'s output (same scenario; checked by :meth:`Inputs.check`).
    active : array_like of bool, shape (n, ns), optional
        Whether each subsystem is connected at each epoch (default all), True/False or 1/0
        (another number is refused, not cast): a switched-out subsystem does time updates
        only and is left out of the fusion.
    gate : array_like, shape (ns,), optional
        NIS thresholds above which a measurement is rejected, each non-negative (inf: no
        gate; default none); one number for a run of one subsystem.
    progress : bool
        Show a tqdm progress bar on stderr.
    local_filter : {"ekf", "ukf"}
        Local filter type; ``"ukf"`` (scaled unscented transform through the same RK4
        propagation and measurement models) needs ``backend="numpy"``.
    **overrides
        Scenario fields to replace.

    Returns
    -------
    MarsRun
    """
    check_choice("backend", backend, ("numba", "numpy"))
    check_choice("local_filter", local_filter, ("ekf", "ukf"))
    progress = check_bool("progress", progress)  # "no" is a true string
    if local_filter == "ukf" and backend != "numpy":
        raise ValueError("local_filter='ukf' runs with backend='numpy' only")
    if inputs is None:
        inputs = prepare(scenario, **overrides)
    elif scenario is not None or overrides:
        raise ValueError("pass either inputs or a scenario (with overrides), not both")
    else:  # shapes, finite values, keys and records agree (an Inputs edited by hand)
        _run_checks.check_object("inputs", inputs, Inputs).check()
    active, gate, beta = run_options(inputs, active, gate)
    if backend == "numpy":  # review 35p P8: hours without a word
        unused_inputs.warn_slow_loop(inputs.n, local_filter)
    t_start = time.perf_counter()
    if backend == "numba":
        out = _run_numba(inputs, active, gate, beta, progress)
    else:
        out = _run_numpy(inputs, active, gate, beta, progress, local_filter)
    wall = time.perf_counter() - t_start
    rec = inputs.record
    label = backend if local_filter == "ekf" else f"{backend}-ukf"
    return MarsRun(inputs.scenario, inputs.times[rec], out["x"], out["P"], inputs.truth[rec],
                   out["xl"], out["Pl"], out["nis"], out["flags"], inputs.times, label, wall)


def alloc_records(inp):
    """Output arrays of a run: fused and local estimates at the records, NIS and flags per epoch.

    Returns a dict with ``x`` (nr, 6), ``P`` (nr, 6, 6), ``xl`` (nr, ns, 6), ``Pl`` (nr, ns, 6)
    (local variances), ``nis`` (n, ns, NaN where no update) and ``flags`` (n, ns, int8).
    """
    _run_checks.check_object("inp", inp, Inputs)
    ns = len(inp.scenario.subsystems)
    nr = inp.record.size
    return {
        "x": np.zeros((nr, 6)), "P": np.zeros((nr, 6, 6)), "xl": np.zeros((nr, ns, 6)),
        "Pl": np.zeros((nr, ns, 6)), "nis": np.full((inp.n, ns), np.nan),
        "flags": np.zeros((inp.n, ns), dtype=np.int8),
    }


def _progress(n, enabled, desc):
    from tqdm import tqdm

    return tqdm(total=n, disable=not enabled, desc=desc, unit="epoch", unit_scale=True,
                file=sys.stderr, mininterval=0.5)


def _run_numpy(inp, active, gate, beta, progress, kind="ekf"):
    """The readable reference loop (one epoch at a time, pure numpy)."""
    sc = inp.scenario
    ns = len(sc.subsystems)
    out = alloc_records(inp)
    rec_pos = np.full(inp.n, -1)
    rec_pos[inp.record] = np.arange(inp.record.size)
    ff = FederatedFilter(inp.x0, sc.P0, n_local=ns, beta=beta, mode=sc.mode, kind=kind,
                         names=sc.subsystems)
    sens = inp.sensors
    xs = sens["xnav"]
    R_x, R_uv = xs.R(), sens["uv"].R()
    rm_x, rs_x = inp.xnav_bodies
    times = inp.times
    bar = _progress(inp.n, progress, f"mars (numpy, {kind})")  # ukf: the slowest path
    for k in range(inp.n):
        if k > 0:
            tp, dt = times[k - 1], times[k] - times[k - 1]
            prop = Propagation(tp, dt, inp.table, sc.max_step)
            ff.predict(prop.f, prop.F, process_noise(dt, sc.q_acc))  # P = F P F^T + Q
            for i, s in enumerate(sc.subsystems):
                j = inp.meas_idx[k, i]
                if j < 0:
                    continue
                z = inp.z[s][j]
                if s == "xnav":
                    up = ff.update(i, z, lambda x, j=j: sensors.xnav_h(x, rm_x[j], rs_x[j], xs.n,
                                                                       xs.distance),
                                   lambda x, j=j: sensors.xnav_jacobian(x, rm_x[j], rs_x[j], xs.n,
                                                                        xs.distance),
                                   R_x, gate[i])
                elif s == "uv":
                    up = ff.update(i, z, sensors.uv_h, sensors.uv_jacobian, R_uv, gate[i])
                else:
                    cns = sens["cns"]
                    R_c = cns.R(ff.locals[i].x)  # depends on the geometry
                    up = ff.update(i, z, cns.h, cns.jacobian, R_c, gate[i])
                out["nis"][k, i] = up.nis
                out["flags"][k, i] = 3 if not active[k, i] else (2 if up.nis > gate[i] else 1)
        r = rec_pos[k]
        if r >= 0:
            for i, lf in enumerate(ff.locals):
                out["xl"][r, i] = lf.x
                out["Pl"][r, i] = np.diag(lf.P)
        nxt = active[k + 1] if k + 1 < inp.n else active[k]
        if k == 0:
            ff.set_active(nxt)  # the initial split of P0 among the connected locals
        else:
            ff.fuse(next_active=nxt)  # master fusion (and reset in reset mode)
        if r >= 0:
            out["x"][r], out["P"][r] = ff.x, ff.P
        bar.update(1)
    bar.close()
    return out


def filter_state(inp, beta):
    """Initial local and master states for the compiled kernel: ``(xs, Ps, shares, xm, Pm)``.

    The kernel updates these arrays in place, epoch after epoch.
    """
    sc = _run_checks.check_object("inp", inp, Inputs).scenario
    beta = _run_checks.check_beta(beta, sc.subsystems)
    xs = np.tile(inp.x0, (len(sc.subsystems), 1))
    Ps = np.array([sc.P0 / b for b in beta])
    return xs, Ps, beta.copy(), inp.x0.copy(), sc.P0.copy()


def run_kernel(inp, state, a, b, active, beta, gate, rec_pos, records, nis, flags, watch=None):
    """Run the compiled federated filter over epochs ``[a, b)``.

    ``state`` comes from :func:`filter_state`; ``records`` is ``(x, P, xl, Pl)``, filled
    at the rows ``rec_pos`` gives for each epoch (-1: not recorded). All in place.
    ``watch``: the combined detector's state (:meth:`xnavlab.mars.faults.watch.Watch.arrays`) or
    None. Returns -1 or the epoch the kernel stopped after (:func:`~.kernels.run_epochs`).
    """
    sc = _run_checks.check_object("inp", inp, Inputs).scenario
    xnav, uv, cns = inp.sensors["xnav"], inp.sensors["uv"], inp.sensors["cns"]
    kinds = np.array([_KIND[s] for s in sc.subsystems], dtype=np.int64)
    z = inp.z
    tab = inp.table
    compile_notice.announce_compile()  # one line instead of a silent minute on a cold cache
    stop = kernels.run_epochs(
        a, b, ki.FilterState(*state),
        ki.Propagation(sc.q_acc, sc.max_step, GM_MARS, tab.t_start, tab.step, tab.pos, tab.vel,
                       tab.gm),
        ki.Plan(inp.times, kinds, inp.meas_idx, active, beta, sc.mode == "reset", gate),
        ki.Sensors(z.get("xnav", np.zeros((0, xnav.dim))), *inp.xnav_bodies, xnav.n,
                   xnav.distance, xnav.sigma, z.get("uv", np.zeros((0, 4))), uv.sigma_range,
                   uv.sigma_dir, z.get("cns", np.zeros((0, cns.dim))), cns.star_dirs,
                   cns.sigma_star, cns.sigma_horizon),
        ki.Records(rec_pos, *records, nis, flags),
        _no_watch(len(sc.subsystems)) if watch is None else watch)
    if stop == -2:
        raise kernels.FilterDivergence(
            f"the compiled filter stopped: a covariance lost positive definiteness near epoch "
            f"{b} (t = {inp.times[min(b, inp.n - 1)]:.0f} s): a measurement noise many orders "
            f"below the state's uncertainty (pos_err0_m = {sc.pos_err0_m:g} m) is beyond double "
            f"precision; {unused_inputs.divergence_advice(sc)}, or run the numpy backend")
    return int(stop)


@functools.lru_cache(maxsize=8)
def _no_watch(ns):
    """The combined detector's arrays with no subsystem watched (the kernel skips them)."""
    z = np.zeros     # wf, wi, wS, wsc, ring, ys (3), xbuf, xG, xthr, alarm
    return ki.WatchState(z((ns, 10)), z((ns, 15), dtype=np.int64), z((ns, 12)), np.ones((ns, 4)),
                         z((ns, 4, 1)), *[z((1, 4)) for _ in range(4)], z((0, 1)), z(0), z((ns, 4)))


def _run_numba(inp, active, gate, beta, progress):
    out = alloc_records(inp)
    rec_pos = np.full(inp.n, -1, dtype=np.int64)
    rec_pos[inp.record] = np.arange(inp.record.size)
    state = filter_state(inp, beta)
    records = (out["x"], out["P"], out["xl"], out["Pl"])
    n_chunks = 50 if progress else 1
    edges = np.linspace(0, inp.n, n_chunks + 1).astype(int)
    bar = _progress(inp.n, progress, "mars (numba)")
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        run_kernel(inp, state, a, b, active, beta, gate, rec_pos, records, out["nis"], out["flags"])
        bar.update(b - a)
    bar.close()
    return out
