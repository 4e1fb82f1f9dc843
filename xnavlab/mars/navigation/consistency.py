"""The Mars filter's consistency over many runs: run-averaged NEES and NIS against chi-square.

A filter is consistent when its covariance describes its errors: the normalised estimation
error squared (NEES) of the 6-state fused estimate averages 6, and each subsystem's normalised
innovation squared (NIS) averages its measurement dimension. One run cannot show it (its
epochs are correlated); :func:`nees_monte_carlo` averages over independent runs with random
initial errors and gives the two-sided 95 % chi-square bounds of those averages
(Bar-Shalom, Li and Kirubarajan 2001, section 5.4). Chapter 5 judges each optical
idealisation with it; chapter 13 shows why the federated XNAV filter is conservative (a local
filter holds ``P / beta``), and ``tests/mars/navigation/test_consistency.py`` turns off the cause of each
departure.
"""

from __future__ import annotations

from dataclasses import replace

from xnavlab.core.filters import chi2_bounds
from xnavlab.core.validate import check_int
from xnavlab.mars.navigation.scenarios import MarsScenario, check_overrides, check_scenario, run

__all__ = ["nees_monte_carlo"]


def nees_monte_carlo(n_runs=20, scenario=None, seed=0, **overrides):
    """Average NEES of the fused estimate over ``n_runs`` runs with random initial errors.

    Each run redraws the initial error from N(0, P0) and all measurement noise
    (seeds ``seed, seed + 1, ...``); the truth is shared.

    Parameters
    ----------
    n_runs : int
        Runs, 1 to 100000.
    scenario : MarsScenario, optional
        The scenario (default: the paper's); ``overrides`` replace its fields, except
        ``init_error`` (random here) and ``seed`` (this function's own). Its seed must be left
        at the default 0 (the runs take theirs from ``seed``).
    seed : int
        Seed of the first run (run ``m`` uses ``seed + m``).

    Returns
    -------
    dict
        ``t`` (nr,), ``nees`` (nr,) run-averaged NEES, ``bounds`` (95 % two-sided for
        the average of ``n_runs`` chi-square(6)), ``nis`` {subsystem: run- and
        time-averaged NIS}, ``nis_dof`` {subsystem: its dof}, ``nis_bounds``.

    Examples
    --------
    >>> mc = nees_monte_carlo(3, days=0.01)
    >>> mc["nees"].shape == mc["t"].shape
    True
    """
    n_runs = check_int("n_runs", n_runs, 1, 10**5)
    seed = check_int("seed", seed, 0, 2**62)
    sc = check_scenario("scenario", scenario)
    if "init_error" in check_overrides(overrides):  # review 35j: replace()'s TypeError
        raise ValueError(f"init_error is set by nees_monte_carlo (random: each run draws its "
                         f"initial error from N(0, P0)), got init_error = {overrides['init_error']!r}")
    if sc.seed != MarsScenario.seed:  # the runs' seeds come from seed: the scenario's was dropped
        raise ValueError(f"scenario.seed = {sc.seed} is replaced by nees_monte_carlo's seeds (seed, "
                         f"seed + 1, ...): pass seed={sc.seed} instead")
    sc = replace(sc, init_error="random", **overrides)
    nees_sum, nis_sum, nis_cnt = None, {}, {}
    for m in range(n_runs):
        res = run(replace(sc, seed=seed + m))
        e = res.nees()
        nees_sum = e if nees_sum is None else nees_sum + e
        for i, s in enumerate(sc.subsystems):
            v = res.nis[:, i][res.flags[:, i] == 1]
            nis_sum[s] = nis_sum.get(s, 0.0) + v.sum()
            nis_cnt[s] = nis_cnt.get(s, 0) + v.size
    dof = {"xnav": len(sc.pulsars), "uv": 3, "cns": len(sc.stars) if sc.stars else 3}
    nis_avg = {s: nis_sum[s] / max(nis_cnt[s], 1) for s in sc.subsystems}
    return {
        "t": res.t, "nees": nees_sum / n_runs, "bounds": chi2_bounds(6, n_runs),
        "nis": nis_avg, "nis_dof": {s: dof[s] for s in sc.subsystems},
        "nis_count": nis_cnt,
        "nis_bounds": {s: chi2_bounds(dof[s], nis_cnt[s]) for s in sc.subsystems},
    }
