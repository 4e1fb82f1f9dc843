"""Monte Carlo trials of the fault detectors on the Mars run (chapter 9).

Each trial is a pure function of its parameters and one seed, so it can be mapped over a
list of parameter dicts with :func:`xnavlab.core.montecarlo.run_tasks` (or a Dask executor)
and its JSON-ready result aggregated by :func:`detector_table`.

:func:`mars_trial`
    A one-day Mars run with one UV range step at a random onset, under a detector.
:func:`detector_trial`
    One fault of a class (:data:`FAULT_CLASSES`), a sensor (:data:`SENSORS`) and a size
    (:data:`SIZES`) in a one-day run under a detector (:data:`DETECTORS`), against the
    fault-free run of the same seed: detected, delay, false alarms, fused RMS ratio.
:func:`detector_table`
    Aggregates such records per (class, sensor, size, detector) with Monte Carlo error bars.
:func:`detection_limit`
    What no detector can beat: the Neyman-Pearson bound on finding a fault within a window.

Fault model of :func:`detector_trial`
    Sizes are in noise standard deviations of :func:`xnavlab.mars.faults.fault_tolerance.sensor_sigma`
    (UV: the range, 5000 m; CNS: the horizon sensor, 0.05 deg, on every starlight angle, a
    horizon-sensor fault; XNAV: pulsar B0531+21's 109 m, on every pulsar, a clock fault).
    ``step`` and ``spike``: the size; ``ramp``: the size reached at the end of its 6000 s;
    ``noise``: the total noise standard deviation over the nominal one (extra white noise of
    ``sigma sqrt(r^2 - 1)``); ``stuck``: the output (every component) frozen for the size in
    seconds. Steps, noise and stuck outputs last 3000 s. The onset is drawn uniformly in
    55-70 % of the run; the wavelet detectors train on the first 40 %, and only alarms after
    that count as false alarms.

Scoring
    Every trial is scored by :func:`xnavlab.mars.faults.schedules.trial_outcome`, the rule of
    :func:`xnavlab.mars.faults.schedules.score_faults`: detected when an alarm on the fault's
    subsystem is raised while it acts, or when the subsystem was out of the fusion from
    before the onset to the end (delay 0); LATE (its own column, never a detection) when
    the first alarm comes within :data:`~xnavlab.mars.faults.schedules.LATE_WINDOW_S` after the
    end; false alarms are the alarms no fault explains (late alarms are not among them).
"""

from __future__ import annotations

import math
import time
from collections import OrderedDict
from importlib import resources
from pathlib import Path

import numpy as np

from xnavlab.core import montecarlo
from xnavlab.core.constants import DAY
from xnavlab.core.detection import limits
from xnavlab.core.distributions import chi2_ppf
from xnavlab.core.faults import Fault
from xnavlab.core.userfiles import as_path, check_rows, load_table
from xnavlab.core.validate import (
    check_choice,
    check_int,
    check_items,
    check_real,
    check_records,
    check_seed,
)
from xnavlab.mars.faults import fault_tolerance, schedules
from xnavlab.mars.navigation import scenarios
from xnavlab.mars.studies._metrics import refuse

__all__ = ["mars_trial", "FAULT_CLASSES", "SENSORS", "SIZES", "DETECTORS", "DURATIONS",
           "fault_for", "detection_limit", "detector_trial", "detector_trials", "detector_table",
           "marked_cells", "load_detector_table", "TABLE_PATH", "EARLY_ONSETS_S",
           "early_fault_trial", "EARLY_PATH", "load_early_faults", "RECORD_SPEC"]

#: Fault classes of :func:`detector_trial` (:mod:`xnavlab.core.faults` kinds).
FAULT_CLASSES = ("step", "ramp", "spike", "stuck", "noise")
#: Sensors of :func:`detector_trial`.
SENSORS = ("uv", "cns", "xnav")
#: The detectors compared (``"none"`` is the reference of Fig. 3, not a detector).
DETECTORS = ("wavelet", "chi2", "combined")
#: Three sizes per class: sigma (step, spike; ramp: reached at its end), total noise over
#: nominal (noise), seconds frozen (stuck).
SIZES = {"step": (3.0, 5.0, 8.0), "ramp": (2.5, 5.0, 10.0), "spike": (5.0, 8.0, 12.0),
         "stuck": (600.0, 1500.0, 3000.0), "noise": (2.0, 3.0, 4.0)}
#: Fault durations, s (a spike is one sample; a stuck output lasts its size).
DURATIONS = {"step": 3000.0, "ramp": 6000.0, "spike": 3.0, "stuck": None, "noise": 3000.0}

_TRAIN = 0.4          # fraction of the run the wavelet detectors train on
_CACHE: OrderedDict = OrderedDict()


def mars_trial(size_sigma=5.0, detector="wavelet", *, seed=0, days=1.0, duration=3000.0):
    """A one-day Mars run with one UV range step at a random onset (60-80 % of the run).

    Parameters
    ----------
    size_sigma : float
        The step, in sigma of the range noise (5000 m), in (0, 1000].
    detector : str
        One of :data:`xnavlab.mars.faults.fault_tolerance.DETECTORS`.
    seed : int
    days : float
        Run length, days, in [0.5, 30].
    duration : float
        The step's length, s, in (0, 0.2 days]: it ends inside the run whatever its onset.

    Returns
    -------
    dict
        ``delay`` (s, inf unless detected: :func:`~xnavlab.mars.faults.schedules.score_faults`),
        ``status`` (``"detected"``, ``"late"``, ``"missed"``), ``position_error_m``,
        ``velocity_error_mps`` (RMS after 40 % of the run), ``max_position_error_m``,
        ``isolations`` (count), ``wall_time``.
    """
    size_sigma = check_real("size_sigma", size_sigma, 0.0, 1000.0, lo_open=True)
    check_choice("detector", detector, fault_tolerance.DETECTORS)
    days = check_real("days", days, 0.5, 30.0)
    duration = check_real("duration", duration, 0.0, 0.2 * days * DAY, lo_open=True)
    seed = check_seed("seed", seed)
    rng = np.random.default_rng(seed)
    onset = float(np.round(rng.uniform(0.6, 0.8) * days * 86400.0))
    fault = Fault("uv", "step", size_sigma * 5000.0, onset, duration, component=0)
    r = fault_tolerance.run_fault_tolerant(faults=[fault], detector=detector, days=days,
                                           seed=seed % (2**62), train_days=0.4 * days)
    m = r.run.metrics(0.4 * days)
    d = r.delays()[0] if detector != "none" else {"delay": math.inf, "status": "missed"}
    return {"delay": d["delay"], "status": d["status"], "position_error_m": m["position_error_m"],
            "velocity_error_mps": m["velocity_error_mps"],
            "max_position_error_m": m["position_error_max_m"],
            "isolations": len(r.isolation_intervals()), "wall_time": r.wall_time}


def fault_for(fault_class, sensor, size, onset, scenario=None):
    """The :class:`~xnavlab.core.faults.Fault` of :func:`detector_trial` (module notes).

    Parameters
    ----------
    fault_class : {"step", "ramp", "spike", "stuck", "noise"}
    sensor : {"uv", "cns", "xnav"}
    size : float
        In the class's unit (module notes), in (0, 1e5]; a noise ratio > 1.
    onset : float
        s since the start, in [0, the scenario's span) (without a scenario: within the longest
        run, :data:`~xnavlab.mars.faults.schedules.MAX_DAYS` days).
    scenario : MarsScenario, optional
        Supplies the noise levels (default the paper's).

    Examples
    --------
    >>> f = fault_for("ramp", "uv", 5.0, 1000.0)
    >>> f.component, round(f.magnitude * 6000.0), f.duration
    (0, 25000, 6000.0)
    """
    check_choice("fault_class", fault_class, FAULT_CLASSES)
    check_choice("sensor", sensor, SENSORS)
    size = check_real("size", size, 0.0, 1e5, lo_open=True)
    end = schedules.MAX_DAYS * DAY if scenario is None else None
    sc = scenarios.check_scenario("scenario", scenario)
    onset = check_real("onset", onset, 0.0, sc.span if end is None else end, hi_open=True)
    sig = fault_tolerance.sensor_sigma(sensor, sc)
    comp = 0 if sensor == "uv" and fault_class in ("step", "ramp", "spike", "noise") else None
    dur = DURATIONS[fault_class]
    if fault_class == "stuck":
        return Fault(sensor, "stuck", 0.0, onset, size, None)
    if fault_class == "ramp":
        return Fault(sensor, "ramp", size * sig / dur, onset, dur, comp)
    if fault_class == "noise":
        if size <= 1.0:
            raise ValueError(f"size of a noise fault must be a ratio > 1, got {size}")
        return Fault(sensor, "noise", sig * math.sqrt(size**2 - 1.0), onset, dur, comp)
    return Fault(sensor, fault_class, size * sig, onset, dur, comp)


def _component_sigmas(sensor, scenario=None):
    """Noise standard deviation of each component the fault of :func:`fault_for` touches."""
    sc = scenarios.check_scenario("scenario", scenario)
    if sensor == "uv":
        return np.array([float(sc.sigma_range_m)])       # the range (component 0)
    return np.asarray(sc.sensors()["xnav"].sigma, dtype=float)   # every pulsar's delay, s


def detection_limit(fault_class, sensor, size, window_s=4000.0, rate_per_day=1.0, scenario=None):
    """Upper bound on the probability that any detector finds a fault within ``window_s``.

    The Neyman-Pearson limit of :mod:`xnavlab.core.detection.limits` for the fault of
    :func:`fault_for`, from the samples inside ``min(window_s, duration)`` after the onset (the
    first one a whole sample interval after it), at the window false-alarm probability of a
    detector with ``rate_per_day`` on this subsystem. The innovations' prediction covariance
    ``H P H^T`` is left out and the filter's absorption of a drift ignored: both only make
    detection harder, so the bound stays an upper bound.

    Parameters
    ----------
    fault_class : {"step", "ramp", "noise"}
    sensor : {"uv", "xnav"}
        The CNS fault is on the horizon sensor and enters every starlight angle through the
        geometry; its limit is not computed here.
    size : float
        As in :func:`fault_for`.
    window_s : float
        Detection window after the onset, s, > 0.
    rate_per_day : float
        Design false alarms of the subsystem per day, from 1e-12 to below the samples of a
        day over those of the window (a false-alarm probability in the window under 1).

    Returns
    -------
    float

    Examples
    --------
    >>> round(detection_limit("noise", "xnav", 3.0), 2)      # 6 samples of 500 s in the fault
    0.98
    >>> detection_limit("step", "uv", 3.0) > 0.999
    True
    """
    check_choice("fault_class", fault_class, ("step", "ramp", "noise"))
    check_choice("sensor", sensor, ("uv", "xnav"))
    size = check_real("size", size, 0.0, 1e5, lo_open=True)
    window_s = check_real("window_s", window_s, 0.0, lo_open=True)
    rate_per_day = check_real("rate_per_day", rate_per_day, 1e-12)  # 5e-324: alpha 0
    sc = scenarios.check_scenario("scenario", scenario)
    f = fault_for(fault_class, sensor, size, 0.0, sc)
    dt = sc.dt_uv if sensor == "uv" else sc.dt_xnav
    n = int(min(window_s, f.duration) // dt)
    if n < 1:
        return 0.0
    if rate_per_day * n * dt >= DAY:  # the window's false-alarm probability would be 1
        raise ValueError(f"rate_per_day must be below {DAY / (n * dt):.6g} (the {sensor} samples "
                         f"of a day, one every {dt:g} s, over the window's {n}), got "
                         f"{rate_per_day:g}")
    sig = _component_sigmas(sensor, sc)
    alpha = limits.window_false_alarm(rate_per_day, DAY / dt, n)
    if fault_class == "noise":
        return limits.noise_pd_limit(np.sqrt(sig**2 + f.magnitude**2) / sig, n, alpha)
    if fault_class == "ramp":
        mu = limits.ramp_means(f.magnitude * dt / sig, n)
    else:
        mu = np.tile(f.magnitude / sig, (n, 1))
    return limits.mean_shift_pd_limit(mu, alpha)


def _reference(days, seed):
    """Fault-free inputs and run of one seed (kept for the detectors of the same seed)."""
    key = (days, seed)
    if key not in _CACHE:
        inp = scenarios.prepare(days=days, seed=seed)
        _CACHE[key] = (inp, scenarios.run(inputs=inp).metrics(_TRAIN * days))
        while len(_CACHE) > 2:
            _CACHE.popitem(last=False)
    return _CACHE[key]


def detector_trial(fault_class, sensor, size_index, detector, *, seed, days=1.0):
    """One fault in a Mars run under a detector, against the fault-free run of the same seed.

    Parameters
    ----------
    fault_class : {"step", "ramp", "spike", "stuck", "noise"}
    sensor : {"uv", "cns", "xnav"}
    size_index : int
        0, 1 or 2: the size ``SIZES[fault_class][size_index]``.
    detector : {"wavelet", "chi2", "combined"}
    seed : int
        Seeds everything (noise, onset) through ``numpy.random.default_rng(seed)``; trials of
        different seeds are independent.
    days : float
        Run length, days, in [0.5, 5].

    Returns
    -------
    dict
        JSON-ready: the parameters, ``size``, ``onset_s``, and the outcome of
        :func:`xnavlab.mars.faults.schedules.trial_outcome`: ``detected`` (bool), ``delay_s``
        (float, ``None`` unless detected; 0 if the subsystem was already out at the onset and
        kept out through the fault: ``out_at_onset``), ``late`` (bool: first alarm after the
        end) and ``late_s`` (s after the end), ``false_alarms`` (alarms no fault explains,
        after the training span, int), ``time_out_s`` (time the faulty subsystem was out after
        the fault's end, s); ``armed_days``, ``rms_m`` and ``rms_ref_m`` (fused position RMS
        after the training span, faulty and fault-free), ``fused_rms_ratio``,
        ``wall_time_s``.

    Examples
    --------
    >>> r = detector_trial("step", "uv", 2, "combined", seed=1, days=0.5)
    >>> r["detected"], r["delay_s"] < 60.0, r["fused_rms_ratio"] < 1.5
    (True, True, True)
    """
    check_choice("fault_class", fault_class, FAULT_CLASSES)
    check_choice("sensor", sensor, SENSORS)
    size_index = check_int("size_index", size_index, 0, 2)
    check_choice("detector", detector, DETECTORS)
    seed = check_seed("seed", seed)
    days = check_real("days", days, 0.5, 5.0)
    rng = np.random.default_rng(seed)
    run_seed = int(rng.integers(0, 2**62))
    onset = float(np.round(rng.uniform(0.55, 0.70) * days * DAY / 3.0) * 3.0 + 1.0)
    size = SIZES[fault_class][size_index]
    inp, ref = _reference(days, run_seed)
    fault = fault_for(fault_class, sensor, size, onset, inp.scenario)
    t0 = time.perf_counter()
    r = fault_tolerance.run_fault_tolerant(faults=[fault], detector=detector, inputs=inp,
                                           train_days=_TRAIN * days, rng=rng)
    wall = time.perf_counter() - t0
    out = schedules.trial_outcome(r, _TRAIN * days * DAY)
    rms = r.run.metrics(_TRAIN * days)["position_error_m"]
    return {"fault_class": fault_class, "sensor": sensor, "size_index": size_index,
            "size": size, "detector": detector, "seed": seed, "days": days, "onset_s": onset,
            **out, "armed_days": float(days * (1.0 - _TRAIN)),
            "rms_m": float(rms), "rms_ref_m": float(ref["position_error_m"]),
            "fused_rms_ratio": float(rms / ref["position_error_m"]), "wall_time_s": float(wall)}


def detector_trials(fault_class, sensor, size_index, *, seed, days=1.0):
    """:func:`detector_trial` for every detector of :data:`DETECTORS` on one seed (paired:
    the same noise, onset and fault for the three). Returns the list of their records."""
    return [detector_trial(fault_class, sensor, size_index, d, seed=seed, days=days)
            for d in DETECTORS]


#: The shipped Monte Carlo table (``python benchmarks/bench_detectors.py --write``).
TABLE_PATH = Path(str(resources.files("xnavlab").joinpath("data/detector_table.json")))


def load_detector_table(path=None):
    """The shipped detector table: a dict with ``rows`` (:func:`detector_table`), ``marked``
    (:func:`marked_cells`), ``trials``, ``seed``, ``days`` and ``command``. A file that is not
    such a table (unreadable, not JSON, a row without its keys or with NaN) is one ValueError."""
    path = as_path(TABLE_PATH if path is None else path, "detector table")
    what = f"detector table {str(path)!r}"
    table = load_table(path, "detector table", (".json",))
    check_rows(table.get("rows"), ("fault_class", "sensor", "size", "detector", "trials", "pd",
                                   "late", "false_alarms_per_day", "delay_median_s"), what)
    return table


#: Onsets of :func:`early_fault_trial`: 1 h, 6 h and 20 h after the start, s.
EARLY_ONSETS_S = (3600.0, 21600.0, 72000.0)


def early_fault_trial(*, seed, onsets=EARLY_ONSETS_S, size_sigma=6.0, duration=4000.0):
    """Faults in the first day under the combined detector: delay and fused error per onset.

    For each sensor and onset, one one-day run with a ``size_sigma`` step of ``duration`` s
    on the sensor's first component, against the fault-free run of the same seed (the UV
    and CNS wavelets are still training before 12 h: the innovation tests find the fault).

    Parameters
    ----------
    seed : int
    onsets : sequence of float
        s since the start, at least one, none twice, each in [600, 86400): the combined
        detector takes a fault from
        :data:`~xnavlab.mars.faults.schedules.EARLIEST_ONSET_S` on, in the one-day run.
    size_sigma : float
        The step, in sigma of each sensor's noise, in (0, 1000].
    duration : float
        s, in (0, 86400].

    Returns
    -------
    list of dict
        ``sensor``, ``onset_s``, ``detected``, ``delay_s`` (None unless detected),
        ``out_at_onset`` (detected at delay 0: out of the fusion from before the onset to
        the end), ``late`` (first alarm after the end), ``rms_ratio`` (fused RMS over the
        run after settling, faulty over fault-free); scored by
        :func:`xnavlab.mars.faults.schedules.trial_outcome`.
    """
    seed = check_seed("seed", seed)  # int() took 1.5 as 1 and -1 as 2^31 - 1
    onsets = check_items("onsets", onsets, "onset",  # () ran the fault-free day for nothing
                         lambda label, t: check_real(label, t, schedules.EARLIEST_ONSET_S, DAY,
                                                     hi_open=True))
    size_sigma = check_real("size_sigma", size_sigma, 0.0, 1000.0, lo_open=True)
    duration = check_real("duration", duration, 0.0, DAY, lo_open=True)
    sc = scenarios.MarsScenario(days=1.0, seed=seed % 2**31)
    inp = scenarios.prepare(sc)
    ref = scenarios.run(inputs=inp).metrics()["position_error_m"]
    out = []
    for sensor in SENSORS:
        sig = fault_tolerance.sensor_sigma(sensor, sc)
        for onset in onsets:
            f = Fault(sensor, "step", size_sigma * sig, float(onset), duration,
                      0 if sensor == "uv" else None)
            r = fault_tolerance.run_fault_tolerant(faults=[f], detector="combined", inputs=inp)
            o = schedules.trial_outcome(r)
            out.append({"sensor": sensor, "onset_s": float(onset), "detected": o["detected"],
                        "delay_s": o["delay_s"], "out_at_onset": o["out_at_onset"],
                        "late": o["late"], "rms_ratio": r.run.metrics()["position_error_m"] / ref})
    return out


#: The shipped early-fault table (``python benchmarks/bench_early_faults.py --write``).
EARLY_PATH = Path(str(resources.files("xnavlab").joinpath("data/early_faults.json")))


def load_early_faults(path=None):
    """The shipped early-fault table: ``rows`` (per sensor and onset: ``trials``, ``found``
    (detected, :func:`xnavlab.mars.faults.schedules.score_faults`: an alarm while the fault acts, or
    its subsystem out of the fusion from before the onset to the end), ``out_at_onset`` (the
    latter), ``late`` (first alarm after the end: not found), ``delay_median_s`` and
    ``delay_max_s`` (of the faults found by an alarm), ``rms_ratio_max``), ``seeds``,
    ``command``. A file that is not such a table is one ValueError."""
    path = as_path(EARLY_PATH if path is None else path, "early-fault table")
    table = load_table(path, "early-fault table", (".json",))
    check_rows(table.get("rows"), ("sensor", "onset_s", "trials", "found", "late",
                                   "delay_median_s", "rms_ratio_max"),
               f"early-fault table {str(path)!r}")
    return table


def _quantile_ci(x, q, level=0.95):
    """Order-statistic confidence interval of the q-quantile of a sample (distribution free)."""
    from scipy import stats  # imported here: the binomial law only for this interval

    x = np.sort(np.asarray(x, dtype=float))
    n = x.size
    lo = int(stats.binom.ppf((1 - level) / 2, n, q))
    hi = int(stats.binom.isf((1 - level) / 2, n, q))
    return (float(x[max(lo - 1, 0)]), float(x[min(hi, n - 1)]) if hi < n else math.inf)


def _finite(v):
    return None if v is None or not math.isfinite(v) else float(v)


#: What :func:`detector_table` reads of each trial record.
_RECORD_KEYS = ("fault_class", "sensor", "size_index", "size", "detector", "detected", "delay_s",
                "false_alarms", "armed_days", "fused_rms_ratio", "late", "time_out_s")
#: The kind and range of each value :func:`detector_table` reads (``_metrics``'s kinds).
RECORD_SPEC = {"size": "real>0", "detected": "bool", "delay_s": "real>=0?", "late": "bool",
               "false_alarms": "count", "armed_days": "real>0", "fused_rms_ratio": "real>=0",
               "time_out_s": "real>=0"}
#: Most false alarms of one cell (the Poisson interval's chi-square has 2k + 2 <= 1e12 dof).
_FA_MAX = 5 * 10**11 - 1


def detector_table(records):
    """Aggregate :func:`detector_trial` records per (class, sensor, size, detector).

    ``records`` must be a list of trial records (dicts with the keys read here); anything
    else is one ValueError naming ``records`` or ``records[i]``. Each value must be of its
    kind and range, else one ValueError naming ``records[i]['key']``: ``fault_class``,
    ``sensor`` and ``detector`` of :data:`FAULT_CLASSES`, :data:`SENSORS` and
    :data:`DETECTORS`, ``size_index`` 0, 1 or 2 and ``size`` its ``SIZES[fault_class]``
    entry (a cell of :func:`detector_trial`); ``detected`` and
    ``late`` true or false, ``false_alarms`` an integer in [0, 1e9], ``armed_days`` and
    ``size`` in (0, 1e100], ``fused_rms_ratio`` and ``time_out_s`` in [0, 1e100],
    ``delay_s`` None or in [0, 1e100]; the records of a cell share its ``size``, and a cell's
    false alarms sum to at most 5e11 - 1.

    Returns
    -------
    list of dict
        One row per cell, JSON-ready: ``fault_class``, ``sensor``, ``size_index``, ``size``,
        ``detector``, ``trials``; ``pd`` with its Wilson 95 % interval ``pd_lo``, ``pd_hi``;
        ``late`` (trials whose first alarm came after the fault's end: not detections) and
        ``late_fraction``; ``delay_median_s`` and ``delay_p95_s`` over the detected trials,
        with order-statistic 95 % intervals (``*_lo``, ``*_hi``; ``None`` where undefined);
        ``false_alarms_per_day`` with its Poisson 95 % interval; ``rms_ratio`` (mean of
        ``fused_rms_ratio``) with a normal 95 % interval (``rms_ratio_err``) and its maximum
        ``rms_ratio_max``; ``time_out_median_s``.

    Examples
    --------
    >>> recs = [dict(fault_class="step", sensor="uv", size_index=0, size=3.0, detector="chi2",
    ...              detected=True, delay_s=float(d), late=False, false_alarms=0, armed_days=0.6,
    ...              fused_rms_ratio=1.0, time_out_s=300.0) for d in range(1, 21)]
    >>> row, = detector_table(recs)
    >>> row["pd"], row["delay_median_s"], row["trials"]
    (1.0, 10.5, 20)
    """
    cells, first = OrderedDict(), {}
    records = check_records("records", records, _RECORD_KEYS, "trial record")
    for i, r in enumerate(records):
        refuse(r, RECORD_SPEC, f"records[{i}]")
        # the cell: a fault class, sensor, size index and detector of detector_trial's
        fc = check_choice(f"records[{i}]['fault_class']", r["fault_class"], FAULT_CLASSES)
        check_choice(f"records[{i}]['sensor']", r["sensor"], SENSORS)
        si = check_int(f"records[{i}]['size_index']", r["size_index"], 0, len(SIZES[fc]) - 1)
        check_choice(f"records[{i}]['detector']", r["detector"], DETECTORS)
        key = (r["fault_class"], r["sensor"], r["size_index"], r["detector"])
        j = first.setdefault(key, i)
        if r["size"] != records[j]["size"]:
            raise ValueError(f"records[{i}]['size'] must be that of its cell's first record, "
                             f"records[{j}] ({records[j]['size']!r}), got {r['size']!r}")
        if r["size"] != SIZES[fc][si]:
            raise ValueError(f"records[{i}]['size'] must be its cell's size SIZES[{fc!r}]"
                             f"[{si}] = {SIZES[fc][si]!r}, got {r['size']!r}")
        cells.setdefault(key, []).append(r)
    rows = []
    z = 1.959963984540054                # two-sided 95 % normal quantile (RMS-ratio error)
    for (fc, s, si, det), rs in cells.items():
        n = len(rs)
        k = sum(bool(r["detected"]) for r in rs)
        pd_lo, pd_hi = montecarlo.wilson_interval(k, n)
        delays = [r["delay_s"] for r in rs if r["delay_s"] is not None]
        fa = sum(r["false_alarms"] for r in rs)
        if fa > _FA_MAX:
            raise ValueError(f"records[i]['false_alarms'] of the cell ({fc}, {s}, {si}, {det}) "
                             f"sum to {fa}, more than {_FA_MAX} (the Poisson interval's range)")
        armed = sum(r["armed_days"] for r in rs)
        fa_lo = chi2_ppf(0.025, 2 * fa) / 2 if fa else 0.0    # Poisson (Garwood) interval
        fa_hi = chi2_ppf(0.975, 2 * fa + 2) / 2
        ratio = np.array([r["fused_rms_ratio"] for r in rs])
        late = sum(bool(r["late"]) for r in rs)
        row = {"fault_class": fc, "sensor": s, "size_index": si, "size": rs[0]["size"],
               "detector": det, "trials": n, "pd": k / n, "pd_lo": pd_lo, "pd_hi": pd_hi,
               "late": late, "late_fraction": late / n}
        for name, q in (("delay_median_s", 0.5), ("delay_p95_s", 0.95)):
            if delays:
                lo, hi = _quantile_ci(delays, q)
                row[name] = float(np.quantile(delays, q))
                row[name + "_lo"], row[name + "_hi"] = _finite(lo), _finite(hi)
            else:
                row[name] = row[name + "_lo"] = row[name + "_hi"] = None
        row["false_alarms_per_day"] = fa / armed
        row["false_alarms_per_day_lo"] = fa_lo / armed
        row["false_alarms_per_day_hi"] = fa_hi / armed
        row["rms_ratio"] = float(ratio.mean())
        row["rms_ratio_err"] = float(z * ratio.std(ddof=1) / math.sqrt(n)) if n > 1 else None
        row["rms_ratio_max"] = float(ratio.max())
        row["time_out_median_s"] = float(np.median([r["time_out_s"] for r in rs]))
        rows.append(row)
    return rows


def marked_cells(rows):
    """Cells where ``combined`` is worse than the better of ``wavelet`` and ``chi2`` beyond
    Monte Carlo error: its Pd interval lies below the best Pd's interval, or the lower end of
    its median-delay interval lies above the upper end of the best median delay's interval.

    ``rows`` must be a list of :func:`detector_table` rows; anything else is one ValueError
    naming ``rows`` or ``rows[i]``.

    Returns
    -------
    list of dict
        ``fault_class``, ``sensor``, ``size_index``, ``why`` (``"pd"`` or ``"delay"``), the
        combined and best values.

    Examples
    --------
    >>> marked_cells([])
    []
    """
    by = {}
    for r in check_records("rows", rows, ("fault_class", "sensor", "size_index", "detector"),
                      "detector_table row"):
        by.setdefault((r["fault_class"], r["sensor"], r["size_index"]), {})[r["detector"]] = r
    out = []
    for key, d in by.items():
        if not {"wavelet", "chi2", "combined"} <= set(d):
            continue
        c = d["combined"]
        best_pd = max((d["wavelet"], d["chi2"]), key=lambda r: r["pd"])
        if c["pd_hi"] < best_pd["pd_lo"]:
            out.append({"fault_class": key[0], "sensor": key[1], "size_index": key[2],
                        "why": "pd", "combined": c["pd"], "best": best_pd["pd"],
                        "best_detector": best_pd["detector"]})
            continue
        cands = [r for r in (d["wavelet"], d["chi2"]) if r["delay_median_s"] is not None
                 and r["pd"] >= c["pd_lo"]]
        if not cands or c["delay_median_s"] is None:
            continue
        best = min(cands, key=lambda r: r["delay_median_s"])
        hi = best["delay_median_s_hi"] if best["delay_median_s_hi"] is not None else math.inf
        lo = c["delay_median_s_lo"] if c["delay_median_s_lo"] is not None else 0.0
        if lo > hi:
            out.append({"fault_class": key[0], "sensor": key[1], "size_index": key[2],
                        "why": "delay", "combined": c["delay_median_s"],
                        "best": best["delay_median_s"], "best_detector": best["detector"]})
    return out
