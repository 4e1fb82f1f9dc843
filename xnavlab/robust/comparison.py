"""The filters of Li et al. 2017 compared over seeds: a Monte Carlo study (chapter 10's tables).

Each seed draws one scenario (its measurement noise) and one initial error that all the
filters share; every filter then runs over all the seeds at once
(:func:`xnavlab.robust.filters.run_filters`), and its RMSE over the paper's window is
averaged. The filters themselves are in :mod:`xnavlab.robust.filters`.

Examples
--------
>>> out = compare_filters("mars", ("ukf", "tdukf"), n_steps=40, window=(5e3, 2e4), seeds=(0, 1))
>>> len(out["rmse_runs"]["tdukf"]), "tdukf" in out["improvement"]
(2, True)
"""

from __future__ import annotations

import functools
import inspect
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from xnavlab.core import validate
from xnavlab.core.validate import check_choice, check_int, check_real, make_rng
from xnavlab.robust import ephemeris_error as ee
from xnavlab.robust._checks import check_run_of
from xnavlab.robust.filters import FILTERS, SETTINGS, FilterRun, Scenario, run_filters, simulate

__all__ = ["WINDOWS", "DT", "N_STEPS", "PER_RUN", "rmse", "improvement", "compare_filters",
           "compare_settings"]

#: The paper's stable intervals for the RMSE, s after the start.
WINDOWS = {"earth": (1e5, 6e5), "mars": (5e4, 2.5e5)}
#: The step of the compared runs, s (:func:`~xnavlab.robust.filters.simulate`'s default).
DT = inspect.signature(simulate).parameters["dt"].default
#: Run lengths of :func:`compare_filters`, steps of :data:`DT`: enough for :data:`WINDOWS`.
N_STEPS = {"earth": 1200, "mars": 500}
#: The filter settings :func:`compare_settings` may vary (numbers run_filters takes one per run).
PER_RUN = ("sigma_r0", "sigma_v0", "q_r", "q_v", "q_b", "sigma_b0", "lam")



def rmse(run, scenario, t_from, t_to):
    """Position RMSE over ``t_from <= t - t0 <= t_to`` (s since the start), m (paper eq. (27)).

    Parameters
    ----------
    run : FilterRun
    scenario : Scenario
    t_from, t_to : float
        Interval, s after the initial epoch (paper: Earth 1e5-6e5, Mars 5e4-2.5e5); ``t_to``
        at most the run's last epoch (a window past it is refused, not shortened).

    Examples
    --------
    >>> sc = simulate("earth", n_steps=10, rng=0)
    >>> rmse(run_filters("ukf", [sc])[0], sc, 0.0, 5000.0) > 0
    True
    """
    validate.check_instance("run", run, FilterRun, "a FilterRun from run_filter()")
    validate.check_instance("scenario", scenario, Scenario, "the Scenario the run ran on")
    check_run_of(run, scenario)  # its epochs and its truth
    t_from = check_real("t_from", t_from, 0.0)
    t_to = check_real("t_to", t_to, t_from)
    tau = scenario.t - (scenario.t[0] - scenario.dt)
    sel = (tau >= t_from) & (tau <= t_to)
    if not np.any(sel):  # the end that leaves the window empty is named (t_from past the run)
        which = "t_from" if t_from > tau[-1] else "t_to"
        raise ValueError(f"{which} leaves no epochs in [{t_from:g}, {t_to:g}] s; the run covers "
                         f"(0, {tau[-1]:g}] s, one epoch every {scenario.dt:g} s")
    if t_to > tau[-1] * (1.0 + 1e-12):  # the mean would be over a shorter window than asked
        raise ValueError(f"t_to = {t_to:g} s is past the run's last epoch ({tau[-1]:g} s after the "
                         f"start): give t_to <= {tau[-1]:g} s, or a longer run")
    return float(np.sqrt(np.mean(run.error[sel] ** 2)))  # RMSE = sqrt(mean |dr_k|^2)


def improvement(rmse_filter, rmse_ukf):
    """Improvement over the UKF, percent: ``100 (1 - RMSE / RMSE_UKF)``.

    Parameters
    ----------
    rmse_filter : float
        The filter's RMSE, m, in [0, 1e15].
    rmse_ukf : float
        The UKF's RMSE, m, in [1e-6, 1e15].

    Examples
    --------
    >>> improvement(25.0, 100.0)
    75.0
    """
    # RMSEs up to 1e15 m and the UKF's from 1 um (no navigation is better): the ratio stays
    # finite (5e-324 gave -inf).
    rmse_filter = check_real("rmse_filter", rmse_filter, 0.0, 1e15)
    rmse_ukf = check_real("rmse_ukf", rmse_ukf, 1e-6, 1e15)
    return 100.0 * (1.0 - rmse_filter / rmse_ukf)


def compare_filters(body="earth", filters=FILTERS, error="de405", size=0.0, eps=None, seeds=(0,),
                    pulsar_names=None, n_steps=None, window=None, direction=None, profile="linear",
                    growth_time=None, max_workers=1, **filter_kwargs):
    """Monte Carlo comparison of the filters: mean RMSE over seeds and improvement over the UKF.

    Each seed draws one scenario (measurement noise) and one initial error shared by
    all filters.

    Parameters
    ----------
    body : {"earth", "mars"}
    filters : sequence of str
        Subset of :data:`~xnavlab.robust.filters.FILTERS`; the improvement needs ``"ukf"``
        among them.
    error, size, pulsar_names, direction, profile, growth_time : see :func:`~xnavlab.robust.filters.simulate`
        (``growth_time`` defaults to the run's length, the end of the RMSE window).
    eps : float, optional
        RKF scalar (default :data:`~xnavlab.robust.filters.EPSILON`).
    seeds : sequence of int
        One run per seed.
    n_steps : int, optional
        Steps of :data:`DT`, in [1, 1e6] (default :data:`N_STEPS`, enough for the paper's window).
    window : (float, float), optional
        RMSE interval ``(t_from, t_to)``, s after the start, ``0 <= t_from < t_to <=
        n_steps DT`` (default :data:`WINDOWS`): a window past the run's end is refused, not
        shortened.
    max_workers : int
        Processes the seeds are spread over, in contiguous groups (1: in this process); the
        results do not depend on it.
    **filter_kwargs
        Passed to :func:`~xnavlab.robust.filters.run_filters`, each to the filters that use it.

    Returns
    -------
    dict
        ``rmse`` ({filter: mean RMSE, m}), ``rmse_runs`` ({filter: list}),
        ``improvement`` ({filter: percent}, filters other than the UKF), ``tau`` (n,) s
        since the start and ``error`` ({filter: (n,) position error of the first seed, m}).

    Examples
    --------
    >>> out = compare_filters("mars", ("ukf", "rkf"), n_steps=40, window=(5e3, 2e4))
    >>> sorted(out["rmse"]), "rkf" in out["improvement"]
    (['rkf', 'ukf'], True)
    """
    check_choice("body", body, tuple(ee.PLANETS))
    filters = validate.check_items("filters", filters, "filter",
                                   lambda lab, f: check_choice(lab, f, FILTERS))
    seeds = validate.check_seeds("seeds", seeds)
    max_workers = check_int("max_workers", max_workers, 1, 64)
    n_steps, window = _check_window(body, window, n_steps)
    _check_filter_kwargs(filters, dict(filter_kwargs, eps=eps))
    one = functools.partial(_group_runs, body, filters, dict(
        n_steps=n_steps, error=error, size=size, pulsar_names=pulsar_names, direction=direction,
        growth_time=growth_time, profile=profile), window, dict(filter_kwargs, eps=eps))
    workers = min(max_workers, len(seeds))
    if workers > 1:
        groups = [list(g) for g in np.array_split(np.asarray(seeds, dtype=object), workers)]
        with ProcessPoolExecutor(max_workers=workers) as pool:
            results = [r for part in pool.map(one, groups) for r in part]
    else:
        results = one(seeds)
    runs = {f: [r[0][f] for r in results] for f in filters}
    mean = {f: float(np.mean(v)) for f, v in runs.items()}
    imp = {}
    if "ukf" in mean:
        imp = {f: improvement(mean[f], mean["ukf"]) for f in filters if f != "ukf"}
    return {"rmse": mean, "rmse_runs": runs, "improvement": imp, "tau": results[-1][2],
            "error": results[0][1]}


def _check_window(body, window, n_steps):
    """``(n_steps, (t_from, t_to))``: the run's steps of 500 s (None: the body's :data:`N_STEPS`)
    and the RMSE window, 0 <= t_from < t_to <= the run's end, s (None: the body's :data:`WINDOWS`)."""
    n_steps = check_int("n_steps", N_STEPS[body] if n_steps is None else n_steps, 1, 10**6)
    end = n_steps * DT  # the last epoch, s after the start
    if window is None:
        window = WINDOWS[body]
        if window[1] > end:
            raise ValueError(f"n_steps = {n_steps} ends the run at {end:g} s, before the end of "
                             f"{body}'s RMSE window {window} s: give n_steps >= "
                             f"{int(np.ceil(window[1] / DT))}, or a window")
        return n_steps, window
    if isinstance(window, set | frozenset):  # unordered: which end is t_from would be chance
        raise ValueError(f"window must be an ordered pair (t_from, t_to), got the set {window!r}")
    times = validate.check_items("window", window, "time", lambda lab, v: (lab, check_real(lab, v, 0.0)), 2)
    if len(times) != 2 or not times[0] < times[1]:
        raise ValueError(f"window must be (t_from, t_to), 0 <= t_from < t_to, s, got {window!r}")
    if times[1] > end:  # an RMSE over fewer epochs than asked, without a word
        raise ValueError(f"window ends at {times[1]:g} s, past the run's end ({end:g} s = n_steps "
                         f"{n_steps} x {DT:g} s): give t_to <= {end:g} s, or more n_steps")
    return n_steps, tuple(float(v) for v in times)


def _check_filter_kwargs(filters, kwargs):
    """Every filter setting is one :func:`run_filters` takes and one of ``filters`` uses: else one
    ValueError (an unknown key was a TypeError of run_filters; a setting of a filter not run
    was dropped in silence)."""
    takes = set(inspect.signature(run_filters).parameters) - {"name", "scenarios", "rngs"}
    for key, value in kwargs.items():
        if key not in takes:
            raise ValueError(f"compare_filters got {key}={value!r:.60}: not a filter setting "
                             f"(they are {', '.join(sorted(takes))})")
        users, default = SETTINGS.get(key, (filters, None))
        if not _is_default(value, default) and not set(users) & set(filters):
            raise ValueError(f"{key} is a setting of the {'/'.join(users)} filter, which filters "
                             f"= {list(filters)} does not run; leave {key} out or run it")


def _is_default(value, default):
    """``value`` is a setting's default (a bool is no number, an array no scalar)."""
    if value is default:
        return True
    try:
        return default is not None and type(value) is not bool and bool(value == default)
    except (TypeError, ValueError):
        return False


def _draws(body, scenario_kwargs, seeds):
    """Each seed's scenario and the seed of its initial error (shared by the filters)."""
    scenarios, inits = [], []
    for seed in seeds:
        g = make_rng(seed, "seed")
        scenarios.append(simulate(body, rng=g, **scenario_kwargs))
        inits.append(int(g.integers(2**31)))
    return scenarios, inits


def _group_runs(body, filters, scenario_kwargs, window, run_kwargs, seeds):
    """Seeds of :func:`compare_filters`, each filter run over them at once: per seed
    ({filter: RMSE}, {filter: error (n,)}, tau (n,))."""
    scenarios, inits = _draws(body, scenario_kwargs, seeds)
    out, err = [{} for _ in seeds], [{} for _ in seeds]
    for f in filters:  # each filter takes the settings it uses (eps: the RKF's, ...)
        kw = {k: v for k, v in run_kwargs.items() if k not in SETTINGS or f in SETTINGS[k][0]}
        for j, (run, sc) in enumerate(zip(run_filters(f, scenarios, inits, **kw), scenarios, strict=True)):
            out[j][f] = rmse(run, sc, *window)
            err[j][f] = run.error
    return [(o, e, sc.t - (sc.t[0] - sc.dt)) for o, e, sc in zip(out, err, scenarios, strict=True)]


def compare_settings(body, settings, seeds=(0,), n_steps=None, window=None, **scenario_kwargs):
    """Several settings of a study over the same seeds, each filter's runs of all of them as one batch.

    A setting's RMSEs are those :func:`compare_filters` gives for it (the same draws and
    arithmetic, to the last bit); running every setting's seeds together costs about what one
    setting did.

    Parameters
    ----------
    body : {"earth", "mars"}
    settings : dict of str -> (dict, dict, sequence of str)
        Label -> (its :func:`~xnavlab.robust.filters.simulate` arguments, on top of
        ``scenario_kwargs``; its filter settings, names of :data:`PER_RUN`; the filters it runs).
    seeds : sequence of int
    n_steps, window
        As for :func:`compare_filters`.
    **scenario_kwargs
        :func:`~xnavlab.robust.filters.simulate` arguments shared by the settings.

    Returns
    -------
    dict
        Label -> {filter: list of RMSE, one per seed, m}.

    Examples
    --------
    >>> out = compare_settings("mars", {"lam 0.5": ({}, {"lam": 0.5}, ("rkf",)),
    ...                                 "z": ({"direction": (0, 0, 1)}, {}, ("ukf", "rkf"))},
    ...                        seeds=(0, 1), n_steps=40, window=(5e3, 2e4), error="growing", size=1e3)
    >>> sorted(out["z"]), len(out["lam 0.5"]["rkf"])
    (['rkf', 'ukf'], 2)
    """
    check_choice("body", body, tuple(ee.PLANETS))
    if not isinstance(settings, dict) or not settings:
        raise ValueError(f"settings must be a non-empty dict label -> (simulate arguments, filter "
                         f"settings, filters), got {validate.shown(settings)}")
    seeds = validate.check_seeds("seeds", seeds)
    steps, window = _check_window(body, window, n_steps)
    defaults = inspect.signature(run_filters).parameters
    drawn, per_filter = {}, {f: [] for f in FILTERS}
    for label, item in settings.items():
        if not (isinstance(item, tuple | list) and len(item) == 3 and isinstance(item[0], dict)
                and isinstance(item[1], dict)):
            raise ValueError(f"settings[{label!r}] must be (simulate arguments: dict, filter settings: "
                             f"dict, filters: list), got {validate.shown(item)}")
        scenario, kw, filters = item
        bad = [k for k in kw if k not in PER_RUN]
        if bad:
            raise ValueError(f"settings[{label!r}] sets {bad[0]}; only {', '.join(PER_RUN)} vary by setting")
        key = repr(sorted(scenario.items()))
        if key not in drawn:  # settings of the filters only share the draws
            drawn[key] = _draws(body, {**scenario_kwargs, "n_steps": steps, **scenario}, seeds)
        for f in validate.check_items(f"settings[{label!r}] filters", filters, "filter",
                                      lambda lab, f: check_choice(lab, f, FILTERS)):
            per_filter[f].append((label, *drawn[key], kw))
    out = {label: {} for label in settings}
    for f, items in per_filter.items():  # one batch per filter: every setting's seeds
        if not items:
            continue
        scenarios = [sc for item in items for sc in item[1]]
        inits = [i for item in items for i in item[2]]
        kw = {name: [item[3].get(name, defaults[name].default) for item in items for _ in seeds]
              for name in {k for item in items for k in item[3]}}  # one value per run
        runs = run_filters(f, scenarios, inits, **kw)
        for j, item in enumerate(items):
            part = range(j * len(seeds), (j + 1) * len(seeds))
            out[item[0]][f] = [rmse(runs[i], scenarios[i], *window) for i in part]
    return out
