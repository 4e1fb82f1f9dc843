"""Receiver operating characteristic of a fault detector: Pd against false alarms per day.

A ROC campaign sweeps one detector's threshold over a list of values and runs a user grid of
faults. Run ``i`` of the campaign (:func:`campaign`, resumable through
:mod:`xnavlab.core.campaign`) injects fault ``i mod F`` of the grid's ``F`` faults into a Mars
run of its own seed and runs the detector once per threshold on that *same* faulty run (same
noise, same onset: the thresholds are compared pairwise, so the curve is not jagged by noise
between runs). :func:`roc_curve` pools the runs per threshold:

``pd``
    faults detected over faults injected, with the Wilson (1927) score 95 % interval
    (:func:`xnavlab.core.montecarlo.wilson_interval`). Detected, late and false are decided
    by :func:`xnavlab.mars.faults.schedules.score_faults` (through
    :func:`~xnavlab.mars.faults.schedules.trial_outcome`): an alarm on the fault's subsystem raised
    while it acts, or the subsystem out of the fusion from before the onset to the end;
``late``
    faults whose first alarm came only after their end (within
    :data:`~xnavlab.mars.faults.schedules.LATE_WINDOW_S`): not detections, counted here;
``false_alarms_per_day``
    alarms that no fault explains (raised neither while the fault acts nor within
    :data:`~xnavlab.mars.faults.schedules.LATE_WINDOW_S` after its end on its subsystem; late
    alarms are not false alarms) that open after the
    training span, over the armed days, with the exact Poisson 95 % interval of Garwood
    (1936), ``chi2.ppf(0.025, 2k)/2`` to ``chi2.ppf(0.975, 2k + 2)/2`` events, divided by the
    armed days. The count includes alarms on every subsystem of a faulty run (a fault that
    drags the master off can raise alarms on the healthy subsystems: they count as false).

The threshold of each detector (:data:`THRESHOLDS`)
    ``"combined"``: ``rate_per_day``, the design false alarms per subsystem per day of
    :class:`~xnavlab.core.detection.CombinedDesign` (one CUSUM design, a few seconds, per
    value and process); ``"chi2"``: ``alpha``, the false-alarm probability per measurement of
    the innovation chi-square test; ``"wavelet"``: ``pfa``, the wavelet's design false-alarm
    probability per sample and sensor (arguments of
    :func:`xnavlab.mars.faults.fault_tolerance.run_fault_tolerant`).

The grid file (TOML or JSON; :func:`load_grid`, :func:`check_grid`)::

    detector = "combined"            # combined | chi2 | wavelet
    thresholds = [0.1, 0.3, 1, 3]    # 1-20 distinct values of the detector's threshold:
                                     # rate_per_day in [1e-3, 100], alpha or pfa in (0, 1)
    days = 0.5                       # run length, days, in [0.5, 5]

    [[faults]]                       # 1-50 faults, each a table
    fault_class = "step"             # step | ramp | spike | stuck | noise
    sensor = "xnav"                  # uv | cns | xnav
    size = 3.0                       # as xnavlab.mars.studies.trials.fault_for: sigma (step,
                                     # spike; ramp: reached at its end), total noise over
                                     # nominal (noise, > 1), seconds frozen (stuck), (0, 1e5]

In JSON the same keys: ``{"detector": "chi2", "thresholds": [...], "days": 0.5,
"faults": [{"fault_class": "step", "sensor": "uv", "size": 3}]}``. ``detector`` and ``days``
may be left out (``"combined"``, 0.5). Unknown keys are refused. The onsets are drawn in
55-70 % of the run and the detectors train on the first 40 %, as in
:func:`xnavlab.mars.studies.trials.detector_trial`.

The runs in pandas (:func:`xnavlab.core.campaign.load_runs`): one row a run, its thresholds
in the list ``metrics.per_threshold``; one row a (run, threshold)::

    import pandas as pd
    from xnavlab.core.campaign import load_runs
    df = load_runs(DIR).explode("metrics.per_threshold", ignore_index=True)
    long = pd.concat([df.drop(columns="metrics.per_threshold"),
                      pd.json_normalize(df["metrics.per_threshold"].tolist())], axis=1)
    long.groupby(["parameters.fault_class", "threshold"])["detected"].mean()

The shipped curves (:data:`CURVES_PATH`, :func:`load_curves`) are written by
``python benchmarks/bench_roc.py --write``: the combined and chi-square detectors on
:data:`DEFAULT_GRID`'s faults (a few minutes on two cores; chapter 9 reads them).

Examples
--------
>>> grid = check_grid({"detector": "chi2", "thresholds": [1e-6, 1e-3],
...                    "faults": [{"fault_class": "step", "sensor": "uv", "size": 5.0}]})
>>> run = roc_run(**campaign(grid).params(0), seed=3)
>>> [r["detected"] for r in run["per_threshold"]]
[True, True]
>>> row = roc_curve([{"status": "ok", "parameters": campaign(grid).params(0),
...                   "metrics": run}])[0]
>>> row["threshold"], row["trials"], row["pd"]
(1e-06, 1, 1.0)
"""

from __future__ import annotations

import csv
import io
import json
import math
from functools import partial
from importlib import resources
from pathlib import Path

import numpy as np

from xnavlab.core import montecarlo
from xnavlab.core.campaign import Campaign
from xnavlab.core.constants import DAY
from xnavlab.core.distributions import DOF_RANGE, chi2_ppf
from xnavlab.core.userfiles import as_path, check_rows, load_table, output_path, write_whole
from xnavlab.core.validate import (
    check_bool,
    check_choice,
    check_instance,
    check_int,
    check_items,
    check_real,
    check_records,
    check_seed,
    shown,
)
from xnavlab.mars.faults import fault_tolerance, schedules
from xnavlab.mars.navigation import scenarios
from xnavlab.mars.studies import trials
from xnavlab.mars.studies._metrics import why_not

__all__ = ["THRESHOLDS", "THRESHOLD_RANGES", "DEFAULT_GRID", "TRAIN_FRACTION", "CURVE_COLUMNS",
           "CURVES_PATH", "check_grid", "load_grid", "roc_run", "roc_curve", "campaign",
           "poisson_interval", "curve_csv", "write_curve", "load_curves", "plot_roc"]

#: The threshold argument of :func:`~xnavlab.mars.faults.fault_tolerance.run_fault_tolerant` each
#: detector is swept on.
THRESHOLDS = {"combined": "rate_per_day", "chi2": "alpha", "wavelet": "pfa"}
#: Allowed range of each threshold ``(lo, hi, lo_open, hi_open)``. A design rate below one
#: false alarm in 1,000 days asks the combined detector's CUSUM for an average run length past
#: its 1e12 samples at 10 samples a second (5e-324 underflowed to a probability of 0).
THRESHOLD_RANGES = {"rate_per_day": (*schedules.RATE_PER_DAY_RANGE, False, False),
                    "alpha": (0.0, 1.0, True, True),
                    "pfa": (0.0, 1.0, True, True)}
#: Fraction of the run the wavelets train on; alarms before its end are not counted.
TRAIN_FRACTION = 0.4
#: The default grid: faults near the edge of detection (chapter 9's table), half-day runs.
DEFAULT_GRID = {
    "detector": "combined",
    "thresholds": [0.03, 0.1, 0.3, 1.0, 3.0, 10.0],
    "days": 0.5,
    "faults": [{"fault_class": "step", "sensor": "xnav", "size": 3.0},
               {"fault_class": "ramp", "sensor": "xnav", "size": 2.5},
               {"fault_class": "noise", "sensor": "xnav", "size": 2.0},
               {"fault_class": "spike", "sensor": "uv", "size": 5.0}],
}
#: Columns of the curve (:func:`roc_curve`, :func:`curve_csv`).
CURVE_COLUMNS = ("threshold", "trials", "detected", "pd", "pd_lo", "pd_hi", "late", "false_alarms",
                 "armed_days", "false_alarms_per_day", "false_alarms_per_day_lo",
                 "false_alarms_per_day_hi", "delay_median_s")
#: The shipped curves (``python benchmarks/bench_roc.py --write``).
CURVES_PATH = Path(str(resources.files("xnavlab").joinpath("data/roc_curves.json")))

_GRID_KEYS = ("detector", "thresholds", "days", "faults")
_FAULT_KEYS = ("fault_class", "sensor", "size")


def _check_fault(i, f):
    name = f"faults[{i}]"
    if not isinstance(f, dict):
        raise ValueError(f"{name} must be a table with keys {', '.join(_FAULT_KEYS)}, got {f!r}")
    extra = sorted(set(f) - set(_FAULT_KEYS))
    missing = [k for k in _FAULT_KEYS if k not in f]
    if extra or missing:
        what = f"unknown key {extra[0]!r}" if extra else f"missing key {missing[0]!r}"
        raise ValueError(f"{name}: {what} (keys: {', '.join(_FAULT_KEYS)})")
    fc = check_choice(f"{name}.fault_class", f["fault_class"], trials.FAULT_CLASSES)
    sensor = check_choice(f"{name}.sensor", f["sensor"], trials.SENSORS)
    lo = 1.0 if fc == "noise" else 0.0
    size = check_real(f"{name}.size", f["size"], lo, 1e5, lo_open=True)
    return {"fault_class": fc, "sensor": sensor, "size": size}


def check_grid(grid):
    """Validate a ROC grid (module notes) and fill its defaults.

    Parameters
    ----------
    grid : dict
        ``detector``, ``thresholds``, ``days``, ``faults`` as in the grid file.

    Returns
    -------
    dict
        The grid with ``detector``, ``threshold_name``, ``thresholds`` (sorted floats),
        ``days`` and ``faults`` (dicts with float sizes).

    Raises
    ------
    ValueError
        One line naming the field and its allowed range.

    Examples
    --------
    >>> check_grid({"thresholds": [3, 1], "faults": [{"fault_class": "step",
    ...             "sensor": "uv", "size": 3}]})["thresholds"]
    [1.0, 3.0]
    >>> check_grid({"thresholds": [0], "faults": []})
    Traceback (most recent call last):
    ...
    ValueError: thresholds[0] (rate_per_day) must be a real number in [0.001, 100], got 0
    """
    if not isinstance(grid, dict):
        raise ValueError(f"grid must be a table of {', '.join(_GRID_KEYS)}, got {grid!r}")
    extra = sorted(set(grid) - set(_GRID_KEYS) - {"threshold_name"})
    if extra:
        raise ValueError(f"grid: unknown key {extra[0]!r} (keys: {', '.join(_GRID_KEYS)})")
    for key in ("thresholds", "faults"):
        if key not in grid:
            raise ValueError(f"grid: missing key {key!r} (keys: {', '.join(_GRID_KEYS)})")
    det = check_choice("detector", grid.get("detector", "combined"), tuple(THRESHOLDS))
    name = THRESHOLDS[det]
    lo, hi, lo_open, hi_open = THRESHOLD_RANGES[name]
    if "threshold_name" in grid and grid["threshold_name"] != name:  # it would be overwritten
        raise ValueError(f"threshold_name {grid['threshold_name']!r} does not match detector "
                         f"{det!r}, whose threshold is {name!r} (leave threshold_name out)")
    thr = grid["thresholds"]
    if not isinstance(thr, list) or not 1 <= len(thr) <= 20:
        raise ValueError(f"thresholds must be a list of 1 to 20 values of {name}, got {thr!r}")
    values = sorted(check_real(f"thresholds[{i}] ({name})", v, lo, hi, lo_open=lo_open,
                               hi_open=hi_open) for i, v in enumerate(thr))
    if len(set(values)) != len(values):
        raise ValueError(f"thresholds must be distinct values of {name}, got {thr!r}")
    days = check_real("days", grid.get("days", 0.5), 0.5, 5.0)
    faults = grid["faults"]
    if not isinstance(faults, list) or not 1 <= len(faults) <= 50:
        raise ValueError(f"faults must be a list of 1 to 50 fault tables, got {faults!r}")
    faults = [_check_fault(i, f) for i, f in enumerate(faults)]
    check_items("faults", faults, "fault", each=lambda label, f: tuple(f.values()))  # none twice
    return {"detector": det, "threshold_name": name, "thresholds": values, "days": days,
            "faults": faults}


def load_grid(path):
    """Read and validate a grid file (``.toml`` or ``.json``; module notes).

    Raises
    ------
    ValueError
        An unreadable file, a syntax error or a bad field: one line naming the file.
    """
    path = as_path(path, "grid file")
    grid = load_table(path, "grid file")
    try:
        return check_grid(grid)
    except ValueError as exc:
        raise ValueError(f"grid file {str(path)!r}: {exc}") from None


def roc_run(fault_class, sensor, size, detector, thresholds, *, seed, days=0.5):
    """One faulty Mars run under a detector at every threshold (the same run for each).

    Parameters
    ----------
    fault_class, sensor, size
        The fault (:func:`xnavlab.mars.studies.trials.fault_for`).
    detector : {"combined", "chi2", "wavelet"}
    thresholds : sequence of float
        Values of the detector's threshold (:data:`THRESHOLDS`), at least one, none twice, each
        in its range (:data:`THRESHOLD_RANGES`).
    seed : int
        Seeds the noise, the onset and a ``noise`` fault's extra noise through
        ``numpy.random.default_rng(seed)``.
    days : float
        Run length, days, in [0.5, 5].

    Returns
    -------
    dict
        JSON-ready: ``onset_s``, ``armed_days`` (after the training span), ``per_threshold``
        (list, one per threshold in order: ``threshold``, ``detected``, ``delay_s`` (None
        unless detected), ``out_at_onset``, ``late``, ``false_alarms`` (alarms no fault
        explains, after the training span): :func:`xnavlab.mars.faults.schedules.trial_outcome`).
    """
    check_choice("detector", detector, tuple(THRESHOLDS))
    name = THRESHOLDS[detector]
    lo, hi, lo_open, hi_open = THRESHOLD_RANGES[name]
    thresholds = check_items(  # () ran half a day for nothing
        "thresholds", thresholds, f"value of {name}",
        lambda label, v: check_real(f"{label} ({name})", v, lo, hi, lo_open=lo_open,
                                    hi_open=hi_open))
    trials.fault_for(fault_class, sensor, size, 0.0)  # the fault's own checks, before any run
    seed = check_seed("seed", seed)
    days = check_real("days", days, 0.5, 5.0)
    rng = np.random.default_rng(seed)
    run_seed, noise_seed = (int(v) for v in rng.integers(0, 2**62, size=2))
    onset = float(np.round(rng.uniform(0.55, 0.70) * days * DAY / 3.0) * 3.0 + 1.0)
    inp = scenarios.prepare(days=days, seed=run_seed)
    fault = trials.fault_for(fault_class, sensor, size, onset, inp.scenario)
    t_train = TRAIN_FRACTION * days * DAY
    per = []
    for thr in thresholds:
        ft = fault_tolerance.run_fault_tolerant(
            faults=[fault], detector=detector, inputs=inp, train_days=TRAIN_FRACTION * days,
            rng=np.random.default_rng(noise_seed), **{THRESHOLDS[detector]: thr})
        o = schedules.trial_outcome(ft, t_train)
        per.append({"threshold": float(thr), "detected": o["detected"], "delay_s": o["delay_s"],
                    "out_at_onset": o["out_at_onset"], "late": o["late"],
                    "false_alarms": o["false_alarms"]})
    return {"onset_s": onset, "armed_days": float(days * (1.0 - TRAIN_FRACTION)),
            "per_threshold": per}


def poisson_interval(k, level=0.95):
    """Exact (Garwood 1936) confidence interval of a Poisson mean from ``k`` events.

    ``chi2.ppf((1 - level)/2, 2k)/2`` (0 at ``k = 0``) to ``chi2.ppf((1 + level)/2, 2k + 2)/2``;
    ``k`` in [0, 5e11 - 1] (the chi-square's degrees of freedom at most 1e12).

    Examples
    --------
    >>> lo, hi = poisson_interval(0)
    >>> lo, round(hi, 3)
    (0.0, 3.689)
    """
    # at most 5e11 - 1 events: the upper limit's chi-square has 2k + 2 degrees of freedom, at
    # most DOF_RANGE's 1e12 (a count beyond was refused as dof)
    k = check_int("k", k, 0, int(DOF_RANGE[1]) // 2 - 1)
    level = check_real("level", level, 0.0, 1.0, lo_open=True, hi_open=True)
    a = (1.0 - level) / 2.0
    lo = chi2_ppf(a, 2 * k) / 2.0 if k else 0.0      # Garwood lower limit
    return lo, chi2_ppf(1.0 - a, 2 * k + 2) / 2.0   # Garwood upper limit


def _row(threshold, cells):
    n = len(cells)
    k = sum(c["detected"] for c in cells)
    late = sum(c["late"] for c in cells)
    lo, hi = montecarlo.wilson_interval(k, n)
    fa = sum(c["false_alarms"] for c in cells)
    if fa > int(DOF_RANGE[1]) // 2 - 1:  # poisson_interval's range
        raise ValueError(f"runs[i]['metrics']['per_threshold'][j]['false_alarms'] of threshold "
                         f"{threshold:g} sum to {fa}, more than {int(DOF_RANGE[1]) // 2 - 1} "
                         f"(the Poisson interval's range)")
    armed = sum(c["armed_days"] for c in cells)
    fa_lo, fa_hi = poisson_interval(fa)
    delays = [c["delay_s"] for c in cells if c["delay_s"] is not None]
    return {"threshold": threshold, "trials": n, "detected": k, "pd": k / n, "pd_lo": lo,
            "pd_hi": hi, "late": late, "false_alarms": fa, "armed_days": armed,
            "false_alarms_per_day": fa / armed, "false_alarms_per_day_lo": fa_lo / armed,
            "false_alarms_per_day_hi": fa_hi / armed,
            "delay_median_s": float(np.median(delays)) if delays else None}


def _ok_runs(runs):
    """The ok records of ``runs``, checked: one grid's runs, each once, with their metrics."""
    if isinstance(runs, dict | str | bytes) or not hasattr(runs, "__iter__"):
        raise ValueError(f"runs must be a list of run records (dicts), got {shown(runs)}")
    runs = list(runs)
    if not runs:
        raise ValueError("runs must hold at least one run record, got an empty list")
    ok, grid, seen = [], None, {}
    for i, r in enumerate(runs):
        name = f"runs[{i}]"
        if not isinstance(r, dict) or "status" not in r:
            raise ValueError(f"{name} must be a run record (a dict with status, parameters and "
                             f"metrics), got {shown(r)}")
        if r["status"] != "ok":
            continue
        try:
            p, m = r["parameters"], r["metrics"]
            _check_run_fault(f"{name}['parameters']", p)
            setup = (p.get("detector"), p.get("days"), tuple(p.get("thresholds", ())))
            why = why_not(m, _ROC_SPEC, f"{name}['metrics']", brackets=True)
            if why is not None:
                raise ValueError(why)
            why = _against_grid(m, p.get("thresholds"))
            if why is not None:
                raise ValueError(f"{name}['metrics']: {why}")
        except (KeyError, TypeError) as exc:
            raise ValueError(f"{name} must be an ok record of a ROC campaign run, but it has no "
                             f"{exc}") from None
        if grid is None:
            grid = (i, setup)
        elif setup != grid[1]:
            raise ValueError(f"{name} is a run of another grid (detector, days, thresholds "
                             f"{setup}) than runs[{grid[0]}] ({grid[1]}): a curve pools one "
                             f"grid's runs")
        if r.get("index") is not None:
            first = seen.setdefault(repr(r["index"]), i)
            if first != i:
                raise ValueError(f"runs lists run index {r['index']!r} twice (runs[{first}] and "
                                 f"{name}): each run counts once")
        ok.append(r)
    return ok


def _check_run_fault(name, p):
    """A run's ``parameters``: the fault of a grid (:func:`check_grid`'s rules), and its
    detector, days and thresholds where given; anything else is one ValueError naming the key
    (``runs[i]['parameters']['sensor']``), not a curve row of its own."""
    if not isinstance(p, dict):
        raise ValueError(f"{name} must be a table of a ROC run's parameters, got {shown(p)}")
    missing = [k for k in _FAULT_KEYS if k not in p]
    if missing:
        raise ValueError(f"{name} has no {missing[0]!r} (a ROC run's fault: "
                         f"{', '.join(_FAULT_KEYS)})")
    fc = check_choice(f"{name}['fault_class']", p["fault_class"], trials.FAULT_CLASSES)
    check_choice(f"{name}['sensor']", p["sensor"], trials.SENSORS)
    check_real(f"{name}['size']", p["size"], 1.0 if fc == "noise" else 0.0, 1e5, lo_open=True)
    if "days" in p:
        check_real(f"{name}['days']", p["days"], 0.5, 5.0)
    lo, hi, lo_open, hi_open = 0.0, math.inf, True, True
    if "detector" in p:
        det = check_choice(f"{name}['detector']", p["detector"], tuple(THRESHOLDS))
        lo, hi, lo_open, hi_open = THRESHOLD_RANGES[THRESHOLDS[det]]
    if "thresholds" in p:
        check_items(f"{name}['thresholds']", p["thresholds"], "threshold",
                    lambda label, v: check_real(label, v, lo, hi, lo_open=lo_open,
                                                hi_open=hi_open))


def roc_curve(runs, by_fault=False):
    """The curve of a ROC campaign's runs: one row per threshold (:data:`CURVE_COLUMNS`).

    Parameters
    ----------
    runs : list of dict
        Run records (:func:`xnavlab.core.campaign.public_record`) of :func:`campaign`; failed
        runs are skipped. An empty list, records of two grids, an index twice, a record
        without its metrics, or parameters that are no grid's fault (:func:`check_grid`'s
        rules; ``detector``, ``days`` and ``thresholds`` checked where given) is one
        ValueError naming the record or its key.
    by_fault : bool
        One row per (fault, threshold) instead, with the fault's ``fault_class``, ``sensor``
        and ``size`` in front.

    Returns
    -------
    list of dict
        ``pd`` with its Wilson 95 % interval, ``late`` (faults found only after their end:
        not in ``pd``), ``false_alarms_per_day`` with its exact Poisson (Garwood) 95 %
        interval, the median delay of the detected faults, s.
    """
    by_fault = check_bool("by_fault", by_fault)
    groups = {}
    for r in _ok_runs(runs):
        p = r["parameters"]
        fkey = (p["fault_class"], p["sensor"], p["size"]) if by_fault else ()
        for c in r["metrics"]["per_threshold"]:
            cell = dict(c, armed_days=r["metrics"]["armed_days"])
            groups.setdefault(fkey + (c["threshold"],), []).append(cell)
    rows = []
    for key in sorted(groups):
        row = _row(key[-1], groups[key])
        if by_fault:
            row = {"fault_class": key[0], "sensor": key[1], "size": key[2], **row}
        rows.append(row)
    return rows


def _summarise(runs):
    return roc_curve(runs)


def campaign(grid):
    """The ROC :class:`~xnavlab.core.campaign.Campaign` of a grid (:func:`check_grid`).

    Run ``i`` is fault ``i mod F``; every threshold runs on it. The manifest holds the grid,
    so a store of another grid is refused.

    Examples
    --------
    >>> camp = campaign(DEFAULT_GRID)
    >>> camp.name, camp.params(1)["fault_class"], len(camp.params(0)["thresholds"])
    ('roc', 'ramp', 6)
    """
    grid = check_grid(grid)
    faults = grid["faults"]

    def params(i):
        return {**faults[i % len(faults)], "detector": grid["detector"],
                "thresholds": grid["thresholds"], "days": grid["days"]}

    return Campaign("roc", roc_run, params, manifest={"grid": grid}, summarise=_summarise,
                    check_metrics=partial(_roc_metrics, thresholds=grid["thresholds"]))


#: What roc_curve reads of a run's metrics (``_metrics``'s kinds).
_ROC_SPEC = {"armed_days": "real>0",
             "per_threshold": ("list", -1, {"threshold": "real>0", "detected": "bool",
                                            "late": "bool", "false_alarms": "count",
                                            "delay_s": "real>=0?"})}


def _against_grid(metrics, thresholds):
    """Why ``per_threshold`` is not one row per threshold of the grid, in order, else None."""
    got = [c["threshold"] for c in metrics["per_threshold"]]
    if thresholds is None:  # a record without the grid: its thresholds once each
        return (f"per_threshold lists a threshold twice ({got})"[:300]
                if len(set(got)) != len(got) else None)
    if got != list(thresholds):
        return (f"per_threshold's thresholds {got} are not the grid's {list(thresholds)}, "
                f"in order"[:300])
    return None


def _roc_metrics(metrics, thresholds=None):
    """Why ``metrics`` is not a :func:`roc_run` result of the grid's ``thresholds``, else
    None (the campaign's check)."""
    return why_not(metrics, _ROC_SPEC) or _against_grid(metrics, thresholds)


def curve_csv(rows):
    """The curve as CSV text (header :data:`CURVE_COLUMNS`, or every key of a by-fault row).

    ``rows`` must be a list of at least one curve row (:func:`roc_curve`): dicts with every
    column of :data:`CURVE_COLUMNS` and the same keys as ``rows[0]``; anything else is one
    ValueError naming ``rows`` or ``rows[i]``.

    Examples
    --------
    >>> row = dict.fromkeys(CURVE_COLUMNS, 1)
    >>> curve_csv([row]).splitlines()[0].split(",")[:3]
    ['threshold', 'trials', 'detected']
    """
    rows = check_records("rows", rows, CURVE_COLUMNS, "curve row")
    if not rows:
        raise ValueError("rows must hold at least one curve row, got an empty list (a curve "
                         "of no run has no CSV)")
    for i, r in enumerate(rows):
        if list(r) != list(rows[0]):
            raise ValueError(f"rows[{i}] must have the columns of rows[0] "
                             f"({', '.join(map(str, rows[0]))}), got {', '.join(map(str, r))}")
    out = io.StringIO()
    w = csv.DictWriter(out, fieldnames=list(rows[0]), lineterminator="\n")
    w.writeheader()
    w.writerows({k: ("" if v is None else v) for k, v in r.items()} for r in rows)
    return out.getvalue()


def write_curve(directory, grid, runs, seed):
    """Write ``roc.json`` (grid, seed, intervals, ``curve``, ``by_fault``) and ``roc.csv``
    (the curve) into ``directory``; returns the JSON-ready dict written. ``seed`` is the
    campaign's (an integer, :func:`~xnavlab.core.validate.check_seed`: ``int()`` took 1.5 as 1)."""
    grid = check_grid(grid)
    seed = check_seed("seed", seed)
    runs = check_records("runs", runs, ("status",), "run record")  # a generator: counted, then read
    data = {"grid": grid, "seed": seed, "runs": len(runs),
            "intervals": {"pd": "Wilson score, 95 %",
                          "false_alarms_per_day": "exact Poisson (Garwood), 95 %"},
            "curve": roc_curve(runs), "by_fault": roc_curve(runs, by_fault=True)}
    directory = output_path(directory, "directory", folder=True)
    text = json.dumps(data, indent=1, allow_nan=False) + "\n"
    write_whole(directory / "roc.json", lambda tmp: tmp.write_text(text))  # whole or not at all
    csv = curve_csv(data["curve"]) if data["curve"] else ""  # no ok run: an empty CSV
    write_whole(directory / "roc.csv", lambda tmp: tmp.write_text(csv))
    return data


def load_curves(path=None):
    """The shipped curves: ``{"curves": {detector: roc.json dict}, "command": str}``; a file
    that is not such a table (a curve's row without its keys or with NaN) is one ValueError."""
    path = as_path(CURVES_PATH if path is None else path, "ROC curves")
    data = load_table(path, "ROC curves", (".json",))
    curves = data.get("curves")
    if not isinstance(curves, dict) or not curves:
        raise ValueError(f"ROC curves {str(path)!r} must hold a table 'curves' of detectors")
    for name, c in curves.items():
        what = f"ROC curves {str(path)!r}, {name}"
        check_rows(c.get("curve") if isinstance(c, dict) else None,
                   ("threshold", "trials", "pd", "pd_lo", "pd_hi", "false_alarms_per_day"), what)
    return data


def plot_roc(curves, ax=None):
    """Pd against false alarms per day, one curve per label, with both 95 % intervals.

    Parameters
    ----------
    curves : dict
        ``{label: rows}`` (:func:`roc_curve`); each point is annotated with its threshold.
        In each row ``threshold`` is a real number > 0; ``pd_lo <= pd <= pd_hi`` in [0, 1]
        and ``0 <= false_alarms_per_day_lo <= false_alarms_per_day <= false_alarms_per_day_hi``,
        each finite (to 1e-12 of the value, the rounding of an interval at ``pd`` 0 or 1).
    ax : matplotlib Axes, optional
        A 2-D rectilinear Axes of a figure (:func:`xnavlab.core.plotting.check_axes`); a new
        figure when omitted.

    Returns
    -------
    matplotlib.figure.Figure
        The figure of ``ax`` (its root figure, for an Axes of a subfigure).

    Examples
    --------
    >>> rows = [{"threshold": 1.0, "pd": 0.5, "pd_lo": 0.3, "pd_hi": 0.7,
    ...          "false_alarms_per_day": 2.0, "false_alarms_per_day_lo": 1.0,
    ...          "false_alarms_per_day_hi": 3.5}]
    >>> fig = plot_roc({"chi2": rows})
    >>> len(fig.axes)
    1
    """
    import matplotlib.pyplot as plt

    from xnavlab.core.plotting import check_axes

    check_instance("curves", curves, dict, "a dict of label -> roc_curve rows")
    if not curves:
        raise ValueError("curves must hold at least one labelled curve")
    curves = {label: [_plot_row(f"curves[{label!r}][{i}]", r) for i, r in enumerate(
        check_records(f"curves[{label!r}]", rows, _PLOT_KEYS, "roc_curve row"))]
        for label, rows in curves.items()}
    fig, ax = plt.subplots(figsize=(6.4, 4.2)) if ax is None else check_axes("ax", ax)
    for label, rows in curves.items():
        x = np.array([r["false_alarms_per_day"] for r in rows])
        y = np.array([r["pd"] for r in rows])
        # one (2, N) array each, matplotlib's documented form: a list of two arrays makes
        # matplotlib 3.10 (the last for Python 3.10) convert a one-point array to a scalar;
        # at least 0: an interval's end rounded past its value (pd_lo 6e-17 at pd 0)
        xerr = np.maximum(0.0, [x - [r["false_alarms_per_day_lo"] for r in rows],
                                np.array([r["false_alarms_per_day_hi"] for r in rows]) - x])
        yerr = np.maximum(0.0, [y - [r["pd_lo"] for r in rows],
                                np.array([r["pd_hi"] for r in rows]) - y])
        line = ax.errorbar(x, y, xerr=xerr, yerr=yerr, marker="o", capsize=3, label=label)
        for r in rows:
            ax.annotate(f"{r['threshold']:g}", (r["false_alarms_per_day"], r["pd"]),
                        textcoords="offset points", xytext=(4, -10), fontsize=7,
                        color=line[0].get_color())
    ax.set_xscale("symlog", linthresh=0.1)
    ax.set_xlabel("false alarms per day (all subsystems)")
    ax.set_ylabel("probability of detection $P_d$")
    ax.set_ylim(-0.02, 1.02)
    ax.grid(True, alpha=0.3)
    ax.legend(title="detector (threshold at each point)", fontsize=8)
    fig.tight_layout()
    return fig


#: The keys of a row :func:`plot_roc` draws.
_PLOT_KEYS = ("threshold", "pd", "pd_lo", "pd_hi", "false_alarms_per_day",
              "false_alarms_per_day_lo", "false_alarms_per_day_hi")


def _plot_row(name, row):
    """``row``'s values :func:`plot_roc` draws, as floats, if each is in its range and each
    interval holds its value (to 1e-12 of it: the rounding of a Wilson end), else one
    ValueError naming ``name['key']``."""
    out = {k: check_real(f"{name}[{k!r}]", row[k], 0.0, 1.0 if k.startswith("pd") else math.inf,
                         lo_open=k == "threshold")  # a threshold > 0, as a run's
           for k in _PLOT_KEYS}
    for value, lo, hi in (("pd", "pd_lo", "pd_hi"), ("false_alarms_per_day",
                          "false_alarms_per_day_lo", "false_alarms_per_day_hi")):
        tol = 1e-12 * max(1.0, out[value])
        if out[lo] > out[value] + tol:
            raise ValueError(f"{name}[{lo!r}] must be at most {value} ({out[value]:g}), "
                             f"got {shown(row[lo])}")
        if out[hi] < out[value] - tol:
            raise ValueError(f"{name}[{hi!r}] must be at least {value} ({out[value]:g}), "
                             f"got {shown(row[hi])}")
    return out
