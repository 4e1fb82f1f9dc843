"""What a truth the filter does not share does to accuracy and consistency: matched vs mismatched.

The paper's runs (and the book's reproductions) give the truth and the filter the same force
model (:attr:`xnavlab.mars.navigation.scenarios.MarsScenario.paper_setup`): the optimistic case of a filter
that knows the dynamics exactly. This module runs the same navigation three ways, every run
with a random initial error drawn from N(0, P0) (so the NEES is a fair test):

``matched``
    the paper's set-up: truth and filter under the paper's model, the book's default ``q_acc``
    (:data:`~xnavlab.mars.navigation.scenarios.DEFAULT_Q_ACC`; the paper gives no process noise).
``mismatched, derived q``
    the studies' set-up (:meth:`~xnavlab.mars.navigation.scenarios.MarsScenario.study`): the rich truth
    :data:`~xnavlab.mars.models.force_models.STUDY`, the paper's filter and the ``q_acc`` that
    :func:`~xnavlab.mars.models.model_noise.derived_q_acc` computes from the models' difference.
``mismatched, default q``
    the rich truth with the paper's filter and the default ``q_acc``: what happens when the
    model difference is not allowed for.

:func:`mismatch_table` returns one row per case (errors averaged over the seeds, the NEES
judged against its chi-square band); :func:`mismatch_runs` the per-seed numbers behind it;
:func:`subsystem_nis` the same runs seen by each local filter of the federated filter (its NIS,
the test a local can make without the truth); :func:`q_sweep` the matched set-up filtered with a
range of process noises (what too little or too much ``q`` costs).
All are cached on disk (keyed by their arguments and the package's source), so a chapter
that calls them after ``python -m xnavlab warmup`` (or a first call) reads the numbers back.

Examples
--------
>>> rows = mismatch_table(days=0.05, seeds=(0, 1), cache=False)
>>> [r["case"] for r in rows]
['matched', 'mismatched, derived q', 'mismatched, default q']
>>> rows[0]["paper_setup"], rows[1]["paper_setup"]
(True, False)
"""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np

from xnavlab.core.constants import DAY
from xnavlab.core.diskcache import cached_arrays, entry_path, store
from xnavlab.core.filters import chi2_bounds, consistency_verdict, judge_series
from xnavlab.core.validate import (
    check_bool,
    check_finite_array,
    check_items,
    check_real,
    check_seeds,
    shown,
)
from xnavlab.mars.navigation import scenarios

__all__ = ["CASES", "case_scenario", "mismatch_runs", "mismatch_table", "TABLE_COLUMNS",
           "setup_note", "subsystem_nis", "q_sweep", "SWEEP_Q_ACC"]

#: The three cases, in the order of the table.
CASES = ("matched", "mismatched, derived q", "mismatched, default q")

#: The process noises :func:`q_sweep` tries by default, m^2/s^3 (the book's default 1e-11 among them).
SWEEP_Q_ACC = (0.0, 1e-12, 1e-11, 1e-10, 1e-9)

#: Columns of :func:`mismatch_table` for a chapter's table (``html_table(rows, TABLE_COLUMNS)``).
TABLE_COLUMNS = ("case", "truth_model", "filter_model", "q_acc", "position_error_m",
                 "velocity_error_mps", "nees", "nees_lo", "nees_hi", "nees_inside",
                 "nees_verdict")


def case_scenario(case, days=30.0, seed=0):
    """The :class:`~xnavlab.mars.navigation.scenarios.MarsScenario` of one case of :data:`CASES`.

    Random initial error (``init_error="random"``); everything else the paper's.

    Examples
    --------
    >>> case_scenario("matched", days=1.0).paper_setup
    True
    >>> case_scenario("mismatched, default q", days=1.0).q_acc == scenarios.DEFAULT_Q_ACC
    True
    """
    if case not in CASES:
        raise ValueError(f"case must be one of {', '.join(repr(c) for c in CASES)}, got {case!r}")
    fields = {"days": days, "seed": seed, "init_error": "random"}
    if case == "matched":
        return scenarios.MarsScenario(**fields)
    sc = scenarios.MarsScenario.study(**fields)
    return sc if case == "mismatched, derived q" else replace(sc, q_acc=scenarios.DEFAULT_Q_ACC)


def setup_note(scenario):
    """One sentence that says which set-up a run has, for a chapter or a reproduction's note.

    ``scenario`` must be a :class:`~xnavlab.mars.navigation.scenarios.MarsScenario`; anything
    else is refused with a one-line ``ValueError`` naming it.

    Examples
    --------
    >>> setup_note(scenarios.MarsScenario())
    "Paper set-up: truth and filter share the paper's force model (Mars point mass + Sun, \
Jupiter); q_acc 1e-11 m^2/s^3."
    """
    if not isinstance(scenario, scenarios.MarsScenario):
        raise ValueError(f"scenario must be a MarsScenario, got {shown(scenario)}")
    sc = scenario
    if sc.paper_setup:
        return (f"Paper set-up: truth and filter share the paper's force model "
                f"({sc.filter_model.describe()}); q_acc {sc.q_acc:.3g} m^2/s^3.")
    return (f"Study set-up: the truth flies {sc.truth_model.describe()} "
            f"({sc.truth_ephem}), the filter {sc.filter_model.describe()} ({sc.filter_ephem}); "
            f"q_acc {sc.q_acc:.3g} m^2/s^3.")


def _key(kind, days, seeds, settle_days):
    return entry_path(f"mismatch-{kind}", (days, tuple(seeds), settle_days), (), (__name__,),
                      suffix=".json")


def _cached(path, compute, cache):
    if cache and path.exists():
        try:
            return json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            pass
    result = compute()
    if cache:
        store(path, lambda f: f.write(json.dumps(result).encode()))
    return result


def _check(days, seeds, settle_days):
    days = check_real("days", days, 0.0, 365.0, lo_open=True)
    # each seed is a run's MarsScenario seed: its range, under the list's own name (seeds[i])
    seeds = check_seeds("seeds", seeds)
    if settle_days is None:
        settle_days = scenarios.default_settle_days(days)
    settle_days = check_real("settle_days", settle_days, 0.0, days, hi_open=True)
    return days, seeds, settle_days


def mismatch_runs(days=30.0, seeds=(0, 1, 2, 3, 4), settle_days=None, cache=True):
    """Every case of :data:`CASES` on every seed: errors, NEES and the case's set-up.

    Parameters
    ----------
    days : float
        Run length, days, in (0, 365].
    seeds : sequence of int
        Distinct seeds (initial error and noise of each run), each in [0, 2**63 - 1]; a
        repeated seed is refused (its run would count twice).
    settle_days : float, optional
        Start of the RMS and NEES window, days, in [0, days); default
        :func:`~xnavlab.mars.navigation.scenarios.default_settle_days`.
    cache : bool
        Read and store the result on disk (keyed by the arguments and the package's source).

    Returns
    -------
    dict
        ``{case: {"q_acc", "truth_model", "filter_model", "paper_setup", "t_days" (list, the
        recorded epochs), "runs": [{"seed", "position_error_m", "velocity_error_mps",
        "nees_mean", "final_position_error_m", "nis_sum", "nis_count"}], "nees": list (the
        run-averaged NEES at each record), "nis_dof"}}``; ``nis_sum`` and ``nis_count`` hold,
        per subsystem, the sum and the number of the NIS of its accepted updates after
        ``settle_days``, ``nis_dof`` each subsystem's NIS degrees of freedom.
    """
    cache = check_bool("cache", cache)
    days, seeds, settle_days = _check(days, seeds, settle_days)

    def compute():
        out = {}
        for case in CASES:
            runs, nees = [], None
            for seed in seeds:
                sc = case_scenario(case, days, seed)
                res = scenarios.run(sc)
                m = res.metrics(settle_days)
                e = res.nees()
                k = res.t_days >= settle_days
                late = (res.times - res.times[0]) / DAY >= settle_days   # every filter epoch
                nis = {s: res.nis[late & (res.flags[:, i] == 1), i]
                       for i, s in enumerate(sc.subsystems)}
                runs.append({"seed": seed, "position_error_m": m["position_error_m"],
                             "velocity_error_mps": m["velocity_error_mps"],
                             "nees_mean": float(np.mean(e[k])),
                             "final_position_error_m": m["final_position_error_m"],
                             "nis_sum": {s: float(v.sum()) for s, v in nis.items()},
                             "nis_count": {s: int(v.size) for s, v in nis.items()}})
                nees = e if nees is None else nees + e
            out[case] = {"q_acc": sc.q_acc, "truth_model": sc.truth_model.describe(),
                         "filter_model": sc.filter_model.describe(),
                         "paper_setup": sc.paper_setup, "t_days": res.t_days.tolist(),
                         "runs": runs, "nees": (nees / len(seeds)).tolist(),
                         # NIS dof: XNAV one a pulsar; UV range + two angles; CNS one a star (3)
                         "nis_dof": {"xnav": len(sc.pulsars), "uv": 3,
                                     "cns": len(sc.stars) if sc.stars else 3}}
        return out

    return _cached(_key("runs", days, seeds, settle_days), compute, cache)


def mismatch_table(days=30.0, seeds=(0, 1, 2, 3, 4), settle_days=None, cache=True):
    """Matched vs mismatched, one row per case of :data:`CASES`.

    Parameters
    ----------
    days, seeds, settle_days, cache
        As :func:`mismatch_runs`.

    Returns
    -------
    list of dict
        Keys :data:`TABLE_COLUMNS` plus ``paper_setup``, ``position_error_min_m``,
        ``position_error_max_m`` (over the seeds) and ``seeds``: ``position_error_m`` and
        ``velocity_error_mps`` are the seeds' mean RMS after ``settle_days``; ``nees`` the
        time average (after ``settle_days``) of the run-averaged fused NEES (dof 6),
        ``nees_lo``/``nees_hi`` the 95 % band of an average of ``len(seeds)`` runs
        (:func:`xnavlab.core.filters.chi2_bounds`), ``nees_inside`` the fraction of records
        whose run-averaged NEES is inside it and ``nees_verdict`` the word of
        :func:`xnavlab.core.filters.judge_series` (``inside``, ``conservative``, ``optimistic``).
    """
    cache = check_bool("cache", cache)
    days, seeds, settle_days = _check(days, seeds, settle_days)
    data = mismatch_runs(days, seeds, settle_days, cache)
    lo, hi = chi2_bounds(6, len(seeds))
    rows = []
    for case in CASES:
        d = data[case]
        t = np.array(d["t_days"])
        nees = np.array(d["nees"])[t >= settle_days]
        pos = [r["position_error_m"] for r in d["runs"]]
        judged = judge_series(nees, lo, hi)
        rows.append({"case": case, "truth_model": d["truth_model"],
                     "filter_model": d["filter_model"], "q_acc": d["q_acc"],
                     "paper_setup": d["paper_setup"],
                     "position_error_m": float(np.mean(pos)),
                     "position_error_min_m": float(np.min(pos)),
                     "position_error_max_m": float(np.max(pos)),
                     "velocity_error_mps": float(np.mean([r["velocity_error_mps"]
                                                          for r in d["runs"]])),
                     "nees": float(np.mean(nees)), "nees_lo": lo, "nees_hi": hi,
                     "nees_inside": judged["inside"], "nees_verdict": judged["verdict"],
                     "seeds": len(seeds)})
    return rows


def subsystem_nis(days=30.0, seeds=(0, 1, 2, 3, 4), settle_days=None, cache=True):
    """Each local filter's NIS in each case of :data:`CASES`: the runs of :func:`mismatch_runs`.

    The fused NEES of :func:`mismatch_table` needs the truth; a local filter of the federated
    filter can only watch its own innovations. This averages, per case and subsystem, the NIS of
    every accepted update after ``settle_days`` over all the seeds, and judges the average
    against the two-sided 95 % band of an average of that many chi-square values.

    Parameters
    ----------
    days, seeds, settle_days, cache
        As :func:`mismatch_runs` (the same cached runs).

    Returns
    -------
    list of dict
        One row per case and subsystem, in the order of :data:`CASES` and of the scenario's
        subsystems: ``case``, ``subsystem``, ``nis`` (the average), ``dof``, ``nis_ratio``
        (``nis / dof``: 1 for a consistent local), ``nis_lo``, ``nis_hi`` (the band,
        :func:`xnavlab.core.filters.chi2_bounds`), ``nis_verdict``
        (:func:`xnavlab.core.filters.consistency_verdict`: ``inside``, ``conservative``,
        ``optimistic``) and ``updates`` (how many were averaged).

    Examples
    --------
    >>> rows = subsystem_nis(days=0.05, seeds=(0,), cache=False)
    >>> [(r["case"], r["subsystem"]) for r in rows][:3]
    [('matched', 'xnav'), ('matched', 'uv'), ('matched', 'cns')]
    """
    cache = check_bool("cache", cache)
    days, seeds, settle_days = _check(days, seeds, settle_days)
    data = mismatch_runs(days, seeds, settle_days, cache)
    rows = []
    for case in CASES:
        d = data[case]
        for s in d["runs"][0]["nis_sum"]:           # the scenario's subsystems, in order
            dof = d["nis_dof"][s]
            total = sum(r["nis_sum"][s] for r in d["runs"])
            count = sum(r["nis_count"][s] for r in d["runs"])
            nis = total / count if count else float("nan")
            lo, hi = chi2_bounds(dof, max(count, 1))
            rows.append({"case": case, "subsystem": s, "nis": nis, "dof": dof,
                         "nis_ratio": nis / dof, "nis_lo": lo, "nis_hi": hi,
                         "nis_verdict": consistency_verdict(nis, lo, hi) if count else "no updates",
                         "updates": count})
    return rows

def q_sweep(q_values=SWEEP_Q_ACC, days=8.0, cache=True):
    """The paper's navigation filtered with each process noise: error, claimed sigma, NEES.

    One truth and one set of noisy measurements (:func:`xnavlab.mars.navigation.scenarios.prepare`, the
    paper's set-up: truth and filter share the force model) are filtered once per ``q_acc``;
    each run is judged over its second half, when the initial error has gone. A ``q`` too small
    makes the filter claim more than it has (NEES above 6); a large one makes it trust its
    dynamics little between measurements. The result is cached on disk (keyed by the
    arguments and this code), as :func:`mismatch_table` is.

    Parameters
    ----------
    q_values : sequence of float
        White-acceleration PSDs to try, m^2/s^3, each >= 0 and none twice (a repeat would be
        run and returned twice).
    days : float
        Length of the run, days, in (0, 365].
    cache : bool
        Read and write the on-disk cache.

    Returns
    -------
    dict
        ``"q"``: shape (n,), the PSDs, m^2/s^3; ``"rms_sigma_nees"``: shape (n, 3), per PSD the
        RMS position error (m), the RMS of the filter's own 1-sigma position (m) and the mean
        NEES of the six-dimensional state, all over the second half of the run.

    Examples
    --------
    >>> out = q_sweep((0.0, 1e-11), days=0.05, cache=False)
    >>> out["q"].shape, out["rms_sigma_nees"].shape
    ((2,), (2, 3))
    """
    cache = check_bool("cache", cache)
    q = check_finite_array("q_values", q_values, shape=None)
    if q.ndim != 1 or q.size == 0 or np.any(q < 0):
        raise ValueError(f"q_values must be a non-empty sequence of PSDs >= 0, got {q_values!r}")
    check_items("q_values", q.tolist(), "PSD")  # one row per PSD: a repeat is refused
    days = check_real("days", days, 0.0, 365.0, lo_open=True)  # the scenario's range

    def compute():
        base = scenarios.prepare(days=days)                 # one truth, one set of noise
        rows = []
        for q_acc in q:
            base.scenario = scenarios.MarsScenario(days=days, q_acc=float(q_acc))
            res = scenarios.run(inputs=base)
            late = res.t_days >= days / 2                   # the second half of the run
            rows.append([res.metrics(days / 2)["position_error_m"],
                         np.sqrt(np.mean(res.sigma_position()[late] ** 2)),
                         res.nees()[late].mean()])
        return {"q": q.copy(), "rms_sigma_nees": np.array(rows)}

    if not cache:
        return compute()
    path = entry_path("q-sweep", (tuple(float(v) for v in q), days),
                      modules=(__name__,))
    return cached_arrays(path, compute)
