"""The Mars system's Monte Carlo campaigns, for :func:`xnavlab.core.campaign.run_campaign`.

:data:`CAMPAIGNS` names them (``python -m xnavlab campaign NAME`` runs them):

``consistency``
    Filter consistency of the fault-free Mars scenario: run ``i`` is a run of
    :class:`~xnavlab.mars.navigation.scenarios.MarsScenario` with a random initial error drawn from
    N(0, P0) and its own measurement noise (both from run ``i``'s seed), and returns the NEES
    of the fused estimate averaged over :data:`NEES_BINS` equal spans of the run, every
    subsystem's NIS sum and count, and the fused RMS errors after a quarter of the run.
    The summary averages them over the runs and sets them against the chi-square 95 %
    bounds (:func:`xnavlab.core.filters.chi2_bounds`).
``detectors``
    Chapter 9's comparison of the fault detectors, fault class x sensor x size x detector
    (:mod:`xnavlab.mars.studies.trials`): run ``i`` is cell ``i mod 45`` of
    :data:`xnavlab.mars.studies.trials.FAULT_CLASSES` x :data:`~xnavlab.mars.studies.trials.SENSORS` x the
    three sizes, and runs every detector of :data:`xnavlab.mars.studies.trials.DETECTORS` on the
    *same* faulty run (same noise, same onset: a paired comparison, so a difference between
    detectors is not noise between runs). The summary is
    :func:`xnavlab.mars.studies.trials.detector_table` of the runs.

Both trials drop the wall times their callees measure, so a run's record is a pure function
of its seed and parameters, wherever it ran.

Examples
--------
>>> from xnavlab.core.campaign import run_campaign
>>> res = run_campaign(campaign("consistency", days=0.02), 2, seed=0, engine="serial")
>>> [r["status"] for r in res.runs()], len(res.runs()[0]["metrics"]["nees_bins"])
(['ok', 'ok'], 12)
"""

from __future__ import annotations

import dataclasses
from functools import partial
from itertools import product

import numpy as np

from xnavlab.core.campaign import Campaign
from xnavlab.core.filters import chi2_bounds, consistency_verdict
from xnavlab.core.validate import (
    check_choice,
    check_int,
    check_items,
    check_real,
    check_records,
    check_seed,
    shown,
)
from xnavlab.mars.navigation import scenario_files, scenarios
from xnavlab.mars.studies import trials
from xnavlab.mars.studies._metrics import why_not
from xnavlab.mars.timing import pulsar_specs, pulsars

__all__ = ["CAMPAIGNS", "NEES_BINS", "DAYS", "campaign", "consistency_run", "detectors_run",
           "summarise_consistency", "summarise_detectors", "detector_cells"]

#: Time bins of the per-run NEES average (equal spans of the run).
NEES_BINS = 12
#: Allowed run length of each campaign, days ``(lo, hi)`` (lo excluded for consistency).
DAYS = {"consistency": (0.0, 30.0), "detectors": (0.5, 5.0)}


# ------------------------------------------------------------------------- consistency


def consistency_run(*, seed, days=1.0, q_acc=scenarios.DEFAULT_Q_ACC,
                    subsystems=scenarios.SUBSYSTEMS, sigma_horizon_deg=0.05,
                    pulsars=pulsars.PAPER_PULSARS, truth_model="paper",
                    filter_model="paper", fields=None, backend="numba", local_filter="ekf"):
    """One fault-free Mars run with a random initial error: NEES, NIS and errors.

    Parameters
    ----------
    seed : int
        Seeds the initial error (N(0, P0)) and every measurement noise.
    days : float
        Run length, days, in (0, 30].
    q_acc : float
        Filter process noise PSD, m^2/s^3 (:class:`~xnavlab.mars.navigation.scenarios.MarsScenario`).
    subsystems : sequence of str
        The subsystems that run (one alone has the whole information share, beta = 1).
    sigma_horizon_deg : float
        Horizon-sensor noise of the CNS, deg (the paper's 0.05).
    pulsars : sequence
        The XNAV pulsars: names, ``.par`` paths or tables (:mod:`xnavlab.mars.timing.pulsar_specs`).
    truth_model, filter_model : str or dict
        Force models (:func:`xnavlab.mars.models.force_models.model`; default the paper's set-up).
    fields : dict, optional
        Further :class:`~xnavlab.mars.navigation.scenarios.MarsScenario` fields, JSON-ready (a scenario
        file's UV noise, mode, beta, initial error sigmas, orbit, ...); not ``days``,
        ``seed``, ``init_error`` or ``record_dt``, which the campaign sets.
    backend, local_filter : str
        Of :func:`xnavlab.mars.navigation.scenarios.run` (``"numba"``/``"numpy"``, ``"ekf"``/``"ukf"``).

    Returns
    -------
    dict
        JSON-ready: ``nees_bins`` (list of :data:`NEES_BINS` floats: the fused NEES, dof 6,
        averaged over the records in each twelfth of the run), ``bin_days`` (the bins' mid
        times, days), ``nis_sum`` and ``nis_count`` ({subsystem: sum of the NIS of its
        accepted updates, their number}), ``nis_dof`` ({subsystem: dof}),
        ``position_error_m`` and ``velocity_error_mps`` (fused RMS after a quarter of the
        run), ``final_position_error_m``.

    Examples
    --------
    >>> r = consistency_run(seed=3, days=0.02)
    >>> len(r["nees_bins"]), sorted(r["nis_dof"].items())
    (12, [('cns', 3), ('uv', 3), ('xnav', 4)])
    """
    subsystems = check_items("subsystems", subsystems, "subsystem")  # "uv" is no list of letters
    days = _consistency_days(days, subsystems)
    seed = check_seed("seed", seed)
    span = days * 86400.0
    # at least four records a bin, and no closer than the measurements (a record an epoch)
    record_dt = max(_shortest_dt(subsystems), min(60.0, span / (4 * NEES_BINS)))
    fields = _check_fields(fields)
    sc = scenarios.MarsScenario(days=days, seed=seed, init_error="random", record_dt=record_dt,
                                q_acc=q_acc, subsystems=tuple(subsystems),
                                sigma_horizon_deg=sigma_horizon_deg, pulsars=pulsars,
                                truth_model=truth_model, filter_model=filter_model, **fields)
    res = scenarios.run(sc, backend=backend, local_filter=local_filter)
    e = res.nees()                                       # e^T P^-1 e, fused estimate
    frac = np.clip((res.t - res.t[0]) / span, 0.0, 1.0 - 1e-12)
    k = (frac * NEES_BINS).astype(int)
    bins = [float(np.mean(e[k == b])) for b in range(NEES_BINS)]
    # NIS dof: XNAV one a pulsar; UV range + two direction angles; CNS one a star (3)
    dof = _nis_dof(sc)
    nis_sum, nis_count = {}, {}
    for i, s in enumerate(sc.subsystems):
        v = res.nis[:, i][res.flags[:, i] == 1]
        nis_sum[s], nis_count[s] = float(v.sum()), int(v.size)
    m = res.metrics(settle_days=days / 4)
    return {"nees_bins": bins,
            "bin_days": [(b + 0.5) * days / NEES_BINS for b in range(NEES_BINS)],
            "nis_sum": nis_sum, "nis_count": nis_count,
            "nis_dof": {s: dof[s] for s in sc.subsystems},
            "position_error_m": m["position_error_m"],
            "velocity_error_mps": m["velocity_error_mps"],
            "final_position_error_m": m["final_position_error_m"]}


#: What summarise_consistency reads of a run's metrics (a stored record without it is no run).
_CONSISTENCY_SPEC = {"nees_bins": ("list", NEES_BINS, "real>=0"),
                     "bin_days": ("list", NEES_BINS, "real>0"),
                     "nis_sum": ("map", "real>=0"), "nis_count": ("map", "count"),
                     "nis_dof": ("map", "count>=1"), "position_error_m": "real>=0",
                     "velocity_error_mps": "real>=0?", "final_position_error_m": "real>=0?"}


def _nis_dof(scenario):
    """{subsystem: NIS dof} of a scenario's runs: XNAV one a pulsar; UV range + two direction
    angles; CNS one a star (3 without a star list)."""
    dof = {"xnav": len(scenario.pulsars), "uv": 3,
           "cns": len(scenario.stars) if scenario.stars else 3}
    return {s: dof[s] for s in scenario.subsystems}


def _consistency_metrics(metrics, days=None, dof=None):
    """Why ``metrics`` is not a :func:`consistency_run` result (its first key at fault), else
    None (the campaign's ``check_metrics``, with the campaign's ``days`` and NIS ``dof``:
    the bins' times and the dof a run of it writes)."""
    why = why_not(metrics, _CONSISTENCY_SPEC)
    if why is None:
        for key in ("nis_sum", "nis_count"):
            if set(metrics[key]) != set(metrics["nis_dof"]):
                return (f"{key} names {sorted(metrics[key])}, not the subsystems of nis_dof "
                        f"{sorted(metrics['nis_dof'])}")
        for s, c in metrics["nis_count"].items():
            if c == 0 and metrics["nis_sum"][s] != 0:
                return f"nis_sum.{s} is {metrics['nis_sum'][s]!r} of nis_count.{s} = 0 updates"
        if metrics["nis_dof"].get("uv", 3) != 3:
            return f"nis_dof.uv is {metrics['nis_dof']['uv']!r}, not 3 (range and two angles)"
        times = metrics["bin_days"]
        if any(b <= a for a, b in zip(times, times[1:], strict=False)):
            return f"bin_days {times!r} is not increasing"[:300]
    if why is None and days is not None:
        want = [(b + 0.5) * days / NEES_BINS for b in range(NEES_BINS)]
        for b, (t, w) in enumerate(zip(metrics["bin_days"], want, strict=True)):
            if abs(t - w) > 1e-9 * days:
                return f"bin_days[{b}] is {t!r}, not the campaign's {w!r} (days = {days:g})"
    if why is None and dof is not None and metrics["nis_dof"] != dof:
        return f"nis_dof is {metrics['nis_dof']!r}, not the campaign's {dof!r}"[:300]
    return why


def summarise_consistency(runs, scenario=None):
    """The consistency table: run-averaged NEES per time bin and NIS per subsystem, with bounds.

    ``runs`` must be a list of campaign records (dicts with ``status``); anything else is
    one ValueError naming ``runs`` or ``runs[i]``.

    A bin's NEES is the average of ``n`` runs' time averages of chi-square(6) values. Each
    time average has at most the variance of one value, so the 95 % bounds of the average
    of ``n`` independent chi-square(6) values (``chi2_bounds(6, n)``) are conservative. The
    NIS bounds treat the pooled updates as independent (``chi2_bounds(dof, count)``).

    Parameters
    ----------
    runs : list of dict
        Run records (:func:`xnavlab.core.campaign.public_record`); failed runs are skipped.
        Their ``nis_dof`` and ``bin_days`` must agree with each other's.
    scenario : MarsScenario, optional
        The runs' scenario (its ``days`` the campaign's): their ``nis_dof`` (XNAV one a pulsar)
        and ``bin_days`` are also checked against it. A campaign's store does this for the
        records it reads (:func:`campaign`'s ``check_metrics``).

    Returns
    -------
    list of dict
        One row per NEES bin (``quantity`` "NEES", ``t_days``) and per subsystem (``quantity``
        "NIS <name>"): ``value``, ``dof``, ``lo``, ``hi`` (the 95 % chi-square band),
        ``inside`` (bool), ``verdict`` (:func:`~xnavlab.core.filters.consistency_verdict`:
        inside, conservative or optimistic), ``runs``; and a
        last row ``quantity`` "position RMS (m)" with the mean over runs and the 5th and 95th
        percentiles as ``lo`` and ``hi``.

    Examples
    --------
    >>> runs = [{"status": "ok", "metrics": consistency_run(seed=s, days=0.02)} for s in (1, 2)]
    >>> rows = summarise_consistency(runs)
    >>> rows[0]["quantity"], rows[0]["runs"], rows[-1]["quantity"]
    ('NEES', 2, 'position RMS (m)')
    """
    runs = check_records("runs", runs, ("status",), "campaign record")  # a string: one line
    given = {}
    if scenario is not None:
        if not isinstance(scenario, scenarios.MarsScenario):
            raise ValueError(f"scenario must be a MarsScenario (the runs' set-up), got "
                             f"{shown(scenario)}")
        given = {"days": scenario.days, "dof": _nis_dof(scenario)}
    ok = []
    for i, r in enumerate(runs):
        if r["status"] != "ok":
            continue
        why = _consistency_metrics(r.get("metrics"), **given)
        if why is None and ok and r["metrics"]["nis_dof"] != ok[0]["nis_dof"]:
            why = f"nis_dof is not the first ok run's ({ok[0]['nis_dof']})"
        if why is None and ok and r["metrics"]["bin_days"] != ok[0]["bin_days"]:
            why = "bin_days are not the first ok run's (one campaign's runs share their bins)"
        if why is not None:
            raise ValueError(f"runs[{i}]['metrics'] is not a consistency_run result: {why}")
        ok.append(r["metrics"])
    if not ok:
        return []
    n = len(ok)
    lo6, hi6 = chi2_bounds(6, n)
    nees = np.mean([m["nees_bins"] for m in ok], axis=0)
    rows = [{"quantity": "NEES", "t_days": float(t), "value": float(v), "dof": 6, "lo": lo6,
             "hi": hi6, "inside": bool(lo6 <= v <= hi6),
             "verdict": consistency_verdict(v, lo6, hi6), "runs": n}
            for t, v in zip(ok[0]["bin_days"], nees, strict=True)]
    for s, dof in ok[0]["nis_dof"].items():
        count = sum(m["nis_count"][s] for m in ok)
        if not count:
            continue
        if dof * count > 1e12:  # chi2_bounds' pooled law
            raise ValueError(f"runs[i]['metrics']['nis_count'][{s!r}] sum to {count} updates "
                             f"of nis_dof {dof}: more than 1e12 degrees of freedom in all")
        v = sum(m["nis_sum"][s] for m in ok) / count
        lo, hi = chi2_bounds(dof, count)
        rows.append({"quantity": f"NIS {s}", "t_days": None, "value": float(v), "dof": dof,
                     "lo": lo, "hi": hi, "inside": bool(lo <= v <= hi),
                     "verdict": consistency_verdict(v, lo, hi), "runs": n})
    pe = np.array([m["position_error_m"] for m in ok])
    rows.append({"quantity": "position RMS (m)", "t_days": None, "value": float(pe.mean()),
                 "dof": None, "lo": float(np.percentile(pe, 5)),
                 "hi": float(np.percentile(pe, 95)), "inside": None, "verdict": None,
                 "runs": n})
    return rows


# --------------------------------------------------------------------------- detectors


def detector_cells(fault_classes=trials.FAULT_CLASSES, sensors=trials.SENSORS):
    """The (fault class, sensor, size index) cells of the ``detectors`` campaign, in run order.

    Examples
    --------
    >>> len(detector_cells()), detector_cells()[:2]
    (45, [('step', 'uv', 0), ('step', 'uv', 1)])
    """
    # each item under its list's name (fault_classes[1]); a string or a repeat is refused
    fault_classes = check_items("fault_classes", fault_classes, "fault class",
                                lambda label, f: check_choice(label, f, trials.FAULT_CLASSES))
    sensors = check_items("sensors", sensors, "sensor",
                          lambda label, s: check_choice(label, s, trials.SENSORS))
    return [(f, s, i) for f, s in product(fault_classes, sensors)
            for i in range(len(trials.SIZES[f]))]


def detectors_run(fault_class, sensor, size_index, *, seed, days=1.0,
                  detectors=trials.DETECTORS):
    """One faulty Mars run seen by every detector (:func:`xnavlab.mars.studies.trials.detector_trial`).

    Every detector gets the same seed, hence the same noise, onset and fault-free reference
    run. The wall times measured by the trial are dropped.

    ``detectors`` is a list of :data:`xnavlab.mars.studies.trials.DETECTORS`, at least one,
    none twice.

    Returns
    -------
    dict
        ``{detector: the trial's record without its parameters and wall time}``.
    """
    detectors = check_items("detectors", detectors, "detector",  # () would run nothing
                            lambda label, d: check_choice(label, d, trials.DETECTORS))
    out = {}
    for det in detectors:
        r = trials.detector_trial(fault_class, sensor, size_index, det, seed=seed, days=days)
        out[det] = {k: v for k, v in r.items()
                    if k not in ("fault_class", "sensor", "size_index", "detector", "seed", "days")
                    and not k.startswith("wall_time")}
    return out


#: What summarise_detectors reads of each detector's record in a run's metrics.
_DETECTOR_SPEC = trials.RECORD_SPEC


def _detectors_metrics(metrics):
    """Why ``metrics`` is not a :func:`detectors_run` result, else None (``check_metrics``)."""
    if not isinstance(metrics, dict) or not metrics:
        return "not a table of detectors"
    for det in metrics:
        if det not in trials.DETECTORS:
            return f"{det!r} is not a detector ({', '.join(trials.DETECTORS)})"
    why = why_not(metrics, {det: _DETECTOR_SPEC for det in metrics})
    if why is None:
        sizes = {m["size"] for m in metrics.values()}
        if len(sizes) > 1:  # one run is one cell: every detector saw one fault
            return f"the detectors' sizes differ ({sorted(sizes)}): a run is one cell"
        if not sizes <= {v for f in trials.SIZES.values() for v in f}:
            return f"size {sizes.pop()!r} is none of the cells' sizes"
    return why


def summarise_detectors(runs):
    """:func:`xnavlab.mars.studies.trials.detector_table` of the ok runs (one record per detector).

    ``runs`` must be a list of campaign records (dicts with ``status``); anything else is
    one ValueError naming ``runs`` or ``runs[i]``. An ok run's ``parameters`` must be one of
    :func:`detector_cells` (``fault_class``, ``sensor``, ``size_index`` in range) and its
    metrics a :func:`detectors_run` result of that cell's size, else one ValueError naming
    the key (``runs[i]['parameters']['sensor']``).

    Examples
    --------
    >>> summarise_detectors([])
    []
    """
    recs = []
    for i, r in enumerate(check_records("runs", runs, ("status",), "campaign record")):
        if r["status"] != "ok":
            continue
        why = _detectors_metrics(r.get("metrics"))
        p = r.get("parameters")
        if why is not None:
            raise ValueError(f"runs[{i}]['metrics'] is not a detectors_run result: {why}")
        if not (isinstance(p, dict) and all(
                k in p for k in ("fault_class", "sensor", "size_index"))):
            raise ValueError(f"runs[{i}]['parameters'] must name fault_class, sensor and "
                             f"size_index, got {p!r}"[:300])
        # the cell: one of detector_cells(), not a row of its own (a hand-edited record)
        name = f"runs[{i}]['parameters']"
        fc = check_choice(f"{name}['fault_class']", p["fault_class"], trials.FAULT_CLASSES)
        check_choice(f"{name}['sensor']", p["sensor"], trials.SENSORS)
        sizes = trials.SIZES[fc]
        k = check_int(f"{name}['size_index']", p["size_index"], 0, len(sizes) - 1)
        for det, m in r["metrics"].items():
            if m["size"] != sizes[k]:
                raise ValueError(f"runs[{i}]['metrics'][{det!r}]['size'] must be the cell's "
                                 f"size {sizes[k]!r} ({p['fault_class']} size_index {k}), "
                                 f"got {m['size']!r}")
            recs.append({"fault_class": p["fault_class"], "sensor": p["sensor"],
                         "size_index": p["size_index"], "detector": det, **m})
    return trials.detector_table(recs)


# ---------------------------------------------------------------------------- registry


def _consistency_days(days, subsystems):
    """``days`` in (0, 30] and long enough that each of the NEES_BINS bins holds a measurement
    (the shortest interval of the subsystems, at the scenario's default rates), else one line."""
    days = check_real("days", days, *DAYS["consistency"], lo_open=True)
    shortest = _shortest_dt(subsystems)
    if days * 86400.0 < NEES_BINS * shortest:
        raise ValueError(f"days must be at least {NEES_BINS * shortest / 86400.0:.3g} for the "
                         f"consistency campaign: each of its {NEES_BINS} NEES bins needs a "
                         f"measurement (one every {shortest:g} s), got {days:g}")
    return days


def _shortest_dt(subsystems):
    """The shortest measurement interval of ``subsystems`` at the scenario's default rates, s."""
    dt = {"xnav": 500.0, "uv": 3.0, "cns": 3.0}
    return min(dt.get(s, 3.0) for s in subsystems)


#: MarsScenario fields a consistency campaign sets itself (a scenario's own are not used).
_SET_BY_CAMPAIGN = ("days", "seed", "init_error", "record_dt")
#: Fields consistency_run takes by name (the rest go in its ``fields``).
_NAMED = ("q_acc", "subsystems", "sigma_horizon_deg", "pulsars", "truth_model", "filter_model")


def _check_fields(fields):
    """``fields`` of :func:`consistency_run`: a dict of MarsScenario fields it does not set."""
    if fields is None:
        return {}
    if not isinstance(fields, dict):
        raise ValueError(f"fields must be a dict of MarsScenario fields, got {fields!r}")
    known = [f.name for f in dataclasses.fields(scenarios.MarsScenario)
             if f.name not in _SET_BY_CAMPAIGN + _NAMED]
    for k in fields:
        if k not in known:
            raise ValueError(f"fields: {k!r} is not a field consistency_run takes there "
                             f"(the fields: {', '.join(known)})")
    return {k: tuple(v) if isinstance(v, list) else v for k, v in fields.items()}


def _consistency(days, scenario=None, backend="numba", local_filter="ekf"):
    days = _consistency_days(days, scenarios.SUBSYSTEMS if scenario is None
                             else scenario.subsystems)
    if scenario is None:
        return Campaign("consistency", consistency_run, lambda i: {"days": days},
                        manifest={"days": days, "q_acc": scenarios.DEFAULT_Q_ACC,
                                  "nees_bins": NEES_BINS},
                        summarise=summarise_consistency,
                        check_metrics=partial(_consistency_metrics, days=days,
                                              dof=_nis_dof(scenarios.MarsScenario())))
    default = scenarios.MarsScenario()
    for name in ("seed", "record_dt"):  # set by the campaign: a scenario's own is refused
        if getattr(scenario, name) != getattr(default, name):
            raise ValueError(f"scenario.{name} is not used by campaign consistency (the runs' "
                             f"seeds come from the campaign's seed; they record at min(60 s, "
                             f"span / {4 * NEES_BINS})), got {getattr(scenario, name)!r}")
    if scenario.days not in (default.days, days):
        raise ValueError(f"scenario.days ({scenario.days:g}) differs from days ({days:g}): "
                         f"the campaign runs days")
    base = {"q_acc": scenario.q_acc, "subsystems": list(scenario.subsystems),
            "sigma_horizon_deg": scenario.sigma_horizon_deg,
            "pulsars": [pulsar_specs.to_json(p) for p in scenario.pulsars],
            "truth_model": scenario.truth_model.as_dict(),
            "filter_model": scenario.filter_model.as_dict()}
    # every other field the scenario sets apart from the default (the manifest stays that of
    # the named fields when there are none)
    mine, dflt = scenario_files.scenario_json(scenario), scenario_files.scenario_json(default)
    fields = {k: v for k, v in mine.items()
              if k not in _SET_BY_CAMPAIGN + _NAMED and v != dflt[k]}
    if fields:
        base["fields"] = fields
    for k, v, d in (("backend", backend, "numba"), ("local_filter", local_filter, "ekf")):
        if v != d:
            base[k] = v
    return Campaign("consistency", consistency_run, lambda i: {"days": days, **base},
                    manifest={"days": days, **base, "nees_bins": NEES_BINS},
                    summarise=summarise_consistency,
                    check_metrics=partial(_consistency_metrics, days=days,
                                          dof=_nis_dof(scenario)))


def _detectors(days):
    days = check_real("days", days, *DAYS["detectors"])
    cells = detector_cells()

    def params(i):
        f, s, k = cells[i % len(cells)]
        return {"fault_class": f, "sensor": s, "size_index": k, "days": days}

    return Campaign("detectors", detectors_run, params,
                    manifest={"days": days, "cells": [list(c) for c in cells],
                              "detectors": list(trials.DETECTORS),
                              "sizes": {f: list(v) for f, v in trials.SIZES.items()}},
                    summarise=summarise_detectors, check_metrics=_detectors_metrics)


#: Campaign name -> (builder(days) -> Campaign, one-line help).
CAMPAIGNS = {
    "consistency": (_consistency, "NEES/NIS of the fault-free Mars scenario, random initial "
                                  "errors (days in (0, 30])"),
    "detectors": (_detectors, "fault class x sensor x size x detector, chapter 9's table "
                              "(days in [0.5, 5]; run i is cell i mod 45)"),
}


def campaign(name, *, days=1.0, scenario=None, backend="numba", local_filter="ekf"):
    """The :class:`~xnavlab.core.campaign.Campaign` called ``name`` with runs of ``days`` days.

    ``scenario`` (``consistency`` only): a :class:`~xnavlab.mars.navigation.scenarios.MarsScenario` whose
    fields the runs take (``campaign consistency --scenario FILE``), except those the campaign
    sets: ``days`` (the argument; the scenario's must be it or the default), ``seed`` (each
    run's comes from the campaign's seed), ``init_error`` (random) and ``record_dt`` (min(60 s,
    span / 48)); a seed or record_dt other than the default is refused, naming it. Default the
    paper's scenario. ``backend`` and ``local_filter`` (``consistency`` only) are
    :func:`xnavlab.mars.navigation.scenarios.run`'s.

    Raises
    ------
    ValueError
        An unknown name, ``days`` outside the campaign's range (:data:`DAYS`), a ``scenario``
        that is no MarsScenario, or a ``backend`` / ``local_filter`` that
        :func:`~xnavlab.mars.navigation.scenarios.run` refuses (the UKF runs on numpy only):
        refused here, not by every run of the campaign.

    Examples
    --------
    >>> campaign("detectors", days=1.0).params(46)
    {'fault_class': 'step', 'sensor': 'uv', 'size_index': 1, 'days': 1.0}
    """
    check_choice("name", name, tuple(CAMPAIGNS))
    check_choice("backend", backend, ("numba", "numpy"))
    check_choice("local_filter", local_filter, ("ekf", "ukf"))
    if local_filter == "ukf" and backend != "numpy":  # as run() refuses it, before any run
        raise ValueError("local_filter='ukf' runs with backend='numpy' only")
    if scenario is not None:
        scenario = scenarios.check_scenario("scenario", scenario)
        if name != "consistency":
            raise ValueError(f"scenario goes with campaign consistency; campaign {name} runs "
                             f"the paper's scenario")
        return _consistency(days, scenario, backend, local_filter)
    if (backend, local_filter) != ("numba", "ekf"):
        if name != "consistency":
            raise ValueError(f"backend and local_filter go with campaign consistency; campaign "
                             f"{name} runs its own")
        return _consistency(days, scenarios.MarsScenario(), backend, local_filter)
    return CAMPAIGNS[name][0](days)
