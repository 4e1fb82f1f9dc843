"""Chapter 10's figures and tables: the four filters of Li et al. 2017 side by side on the Mars
orbit (the slider), and whether the RKF's ``Sigma`` bounds its error (the bound table).

Examples
--------
>>> fig = plot_filter_comparison(100.0, 100.0, "all four")
>>> [ax.get_ylabel() for ax in fig.axes]
['position error (m)', 'RMSE (m)']
"""

from __future__ import annotations

import functools

import numpy as np

from xnavlab.core.diskcache import cached_arrays, entry_path
from xnavlab.core.plotting import html_table, sparse_log_minors
from xnavlab.core.validate import (
    check_bool,
    check_choice,
    check_int,
    check_items,
    check_real,
    check_records,
    check_seeds,
    make_rng,
    shown,
)
from xnavlab.robust import comparison, coverage, filters

__all__ = ["FILTER_NAMES", "PULSAR_SETS", "plot_filter_comparison", "filter_comparison",
           "BOUND_CASES", "BOUND_STATS", "BOUND_SOURCE_NAMES", "bound_table", "bound_table_html"]

#: Display names of :data:`xnavlab.robust.filters.FILTERS`.
FILTER_NAMES = {"ukf": "UKF", "asukf": "ASUKF", "tdukf": "TDUKF", "rkf": "RKF"}

#: Pulsar sets of the chapter's dropdown: the paper's three and the alternatives from the
#: four pulsars of :mod:`xnavlab.mars.timing.pulsars`.
PULSAR_SETS = {
    "paper: B0531+21, B1821-24, B1937+21": ("B0531+21", "B1821-24", "B1937+21"),
    "B0531+21, B1821-24, B1957+20": ("B0531+21", "B1821-24", "B1957+20"),
    "B0531+21, B1937+21, B1957+20": ("B0531+21", "B1937+21", "B1957+20"),
    "all four": ("B0531+21", "B1821-24", "B1937+21", "B1957+20"),
}


def plot_filter_comparison(size=5000.0, eps=100.0, pulsar_set="paper: B0531+21, B1821-24, B1937+21"):
    """UKF, ASUKF, TDUKF and RKF on the Mars orbit under a growing ephemeris error (one seed).

    A pure function of its arguments (seed 0; 500 steps of 500 s), for chapter 10's slider:
    draws :func:`filter_comparison`, which keeps its runs, so that a move of ``eps`` reruns
    only the RKF.

    Parameters
    ----------
    size : float
        Ephemeris error reached at the end of the RMSE window, m (> 0).
    eps : float
        The RKF's scalar epsilon, in :data:`~xnavlab.robust.filters.EPS_RANGE` (> 1 in the
        paper; a run that loses precision stops naming it).
    pulsar_set : str
        A key of :data:`PULSAR_SETS`.

    Returns
    -------
    matplotlib.figure.Figure
        Left: each filter's position error (m) against time, the RMSE window shaded; right:
        the RMSE over the window (m). Not registered with pyplot; it carries an in-place
        update (:func:`xnavlab.core.plotting.in_place`) that a live slider calls.
    """
    from matplotlib.figure import Figure

    from xnavlab.core.plotting import in_place

    # fixed margins, not the constrained layout: the live slider redraws this at every move;
    # the layout every frame shares, update() sets the curves, bars, limits and title
    fig = Figure(figsize=(11, 3.4))
    fig.subplots_adjust(left=0.07, right=0.99, bottom=0.14, top=0.91, wspace=0.25)
    ax1, ax2 = fig.subplots(1, 2, width_ratios=[3, 1])
    tau = np.arange(1.0, 501.0)  # placeholders until update()
    curves = {f: ax1.semilogy(tau, np.ones(tau.size), lw=1, label=name)[0]
              for f, name in FILTER_NAMES.items()}
    ax1.axvspan(*comparison.WINDOWS["mars"], color="0.92", zorder=0)
    ax1.set(xlabel="time (s)", ylabel="position error (m)")
    ax1.legend(ncol=4, fontsize=8)
    bars = dict(zip(FILTER_NAMES, ax2.bar(list(FILTER_NAMES.values()),
                                          np.ones(len(FILTER_NAMES))), strict=True))
    ax2.set(yscale="log", ylabel="RMSE (m)", title="RMSE 5e4-2.5e5 s")
    sparse_log_minors(ax1, ax2)

    def update(size=5000.0, eps=100.0, pulsar_set="paper: B0531+21, B1821-24, B1937+21"):
        out = filter_comparison(size, eps, pulsar_set)
        if list(out["error"]) != list(curves):
            return False  # other filters: a new figure
        for f, err in out["error"].items():
            curves[f].set_data(out["tau"], err)
            bars[f].set_height(out["rmse"][f])
        for ax in (ax1, ax2):
            ax.relim()
            ax.autoscale_view()
        ax1.set_title(f"Mars, ephemeris error {float(size):.0f} m, eps = {float(eps):g}")
        return None

    update(size, eps, pulsar_set)
    return in_place(fig, update)


def filter_comparison(size=5000.0, eps=100.0, pulsar_set="paper: B0531+21, B1821-24, B1937+21"):
    """The numbers of :func:`plot_filter_comparison`, with every filter's run kept in memory.

    The same numbers as :func:`xnavlab.robust.comparison.compare_filters` ``("mars",
    error="growing", size=size, eps=eps, pulsar_names=PULSAR_SETS[pulsar_set], seeds=(0,))``
    (seed 0 draws the scenario, then the initial error that all four filters share), but
    each filter's run is cached on its own arguments: ``eps`` enters only the RKF, so the
    slider's ``eps`` reruns one filter of four, and a position seen before reruns none.

    Parameters
    ----------
    size : float
        Ephemeris error reached at the end of the RMSE window, m, in (0, 1e8].
    eps : float
        The RKF's scalar epsilon, in :data:`~xnavlab.robust.filters.EPS_RANGE`.
    pulsar_set : str
        A key of :data:`PULSAR_SETS`.

    Returns
    -------
    dict
        ``rmse`` ({filter: RMSE over :data:`~xnavlab.robust.comparison.WINDOWS` ``["mars"]``,
        m}), ``tau`` ((500,) s since the start) and ``error`` ({filter: (500,) position
        error, m}), in the order of :data:`~xnavlab.robust.filters.FILTERS`. The arrays are
        shared with the cache: read them, do not write to them.

    Examples
    --------
    >>> out = filter_comparison(100.0, 100.0, "all four")
    >>> list(out["rmse"]) == list(filters.FILTERS), out["tau"].shape
    (True, (500,))
    """
    check_choice("pulsar_set", pulsar_set, tuple(PULSAR_SETS))
    size = check_real("size", size, 0.0, 1e8, lo_open=True)  # simulate's range
    eps = check_real("eps", eps, *filters.EPS_RANGE)
    runs = {f: _filter_run(f, size, eps if f == "rkf" else None, pulsar_set)
            for f in filters.FILTERS}
    tau = _mars_scenario(size, pulsar_set)[2]
    return {"rmse": {f: r[0] for f, r in runs.items()}, "tau": tau,
            "error": {f: r[1] for f, r in runs.items()}}


@functools.lru_cache(maxsize=16)
def _mars_scenario(size, pulsar_set):
    """Seed 0's scenario, the filters' shared initial-error seed and tau, as compare_filters."""
    g = make_rng(0)
    sc = filters.simulate("mars", rng=g, n_steps=500, error="growing", size=size,
                          pulsar_names=PULSAR_SETS[pulsar_set])
    init = int(g.integers(2**31))
    tau = sc.t - (sc.t[0] - sc.dt)
    tau.flags.writeable = False
    return sc, init, tau


@functools.lru_cache(maxsize=256)
def _filter_run(name, size, eps, pulsar_set):
    """(RMSE over the Mars window, m; position error (n,), m) of one filter, kept."""
    sc, init, _ = _mars_scenario(size, pulsar_set)
    run = filters.run_filter(name, sc, rng=init, eps=eps)
    err = run.error
    err.flags.writeable = False
    return comparison.rmse(run, sc, *comparison.WINDOWS["mars"]), err


#: The cases of chapter 10's bound table (:func:`bound_table`), both on the Mars orbit of 500
#: steps of 500 s: the paper's set-up (an error growing from 0 to 50 km along (1, 1, 1)/sqrt(3))
#: and the real DE421 - DE405 error of 1997. The ``"prior"`` source bounds ``|dr_E|`` by the
#: error's known size: the injected 50 km, or the largest real error of the run
#: (:func:`xnavlab.robust.coverage.prior_bias_max`).
BOUND_CASES = {
    "paper's set-up: error growing to 50 km": {"body": "mars", "error": "growing", "size": 5e4},
    "real DE421 - DE405 error": {"body": "mars", "error": "de405"},
}
#: The statistics :func:`bound_table` keeps per case and source
#: (:func:`xnavlab.robust.coverage.compare_bounds`).
BOUND_STATS = ("coverage", "median_ratio", "nees", "rmse_m", "median_sigma_m")
#: Display names of :data:`xnavlab.robust.coverage.BOUND_SOURCES`.
BOUND_SOURCE_NAMES = {"residual": "RKF, residual estimate (the paper's)",
                      "prior": "RKF, prior bound |dr_E| <= d_max",
                      "oracle": "RKF, true B (teaching only)", "ukf": "UKF (its own P)"}
_BOUND_VERSIONS = ("numpy", "scipy", "numba", "jplephem", "de421", "de405")


def bound_table(seeds=tuple(range(8)), sources=coverage.BOUND_SOURCES, n_steps=500, cache=True):
    """:func:`xnavlab.robust.coverage.compare_bounds` for each case of :data:`BOUND_CASES`.

    The runs take about a minute on a quiet machine (two cases, four sources, eight seeds), so
    the numbers are stored on disk (``$XNAVLAB_CACHE``), keyed by the seeds, the sources and the
    code that computes them (:func:`xnavlab.core.diskcache.entry_path`).

    Parameters
    ----------
    seeds : sequence of int
        Seeds of the scenarios and initial errors (at least one).
    sources : sequence of str
        Any of :data:`xnavlab.robust.coverage.BOUND_SOURCES`.
    n_steps : int
        Steps of 500 s per run (the paper's Mars run: 500).
    cache : bool
        Read and write the disk cache (False: compute, store nothing).

    Returns
    -------
    dict
        Case name (a key of :data:`BOUND_CASES`) -> list of dicts, one per source, with
        ``source``, the :data:`BOUND_STATS` (coverage as a fraction of the kept epochs, RMSE
        and ``median_sigma_m`` in m) and ``is_bound`` (coverage at least Chebyshev's 8/9 and
        mean NEES at most 3).

    Examples
    --------
    >>> t = bound_table(seeds=(0,), sources=("prior",), n_steps=40, cache=False)
    >>> [row["source"] for row in t["real DE421 - DE405 error"]]
    ['prior']
    """
    seeds = check_seeds("seeds", seeds)
    sources = check_items("sources", sources, "source",
                          lambda label, src: check_choice(label, src, coverage.BOUND_SOURCES))
    n_steps = check_int("n_steps", n_steps, 2, 10**6)
    cache = check_bool("cache", cache)  # "no" is a true string

    def compute():
        stats = np.empty((len(BOUND_CASES), len(sources), len(BOUND_STATS)))
        for i, case in enumerate(BOUND_CASES.values()):
            kw = dict(case)
            if kw["error"] == "de405":  # the prior: the real error's size over the run
                kw["bias_max"] = coverage.prior_bias_max(kw["body"], span=n_steps * 500.0)
            rows = coverage.compare_bounds(seeds, sources, n_steps=n_steps, **kw)
            stats[i] = [[row[k] for k in BOUND_STATS] for row in rows]
        return {"stats": stats}

    if cache:
        path = entry_path("bound-table", (seeds, sources, n_steps, tuple(BOUND_CASES)), (),
                          ("xnavlab.robust.plots", "xnavlab.robust.coverage"), _BOUND_VERSIONS)
        stats = cached_arrays(path, compute)["stats"]
    else:
        stats = compute()["stats"]
    level = coverage.CHEBYSHEV_LEVEL
    out = {}
    for i, name in enumerate(BOUND_CASES):
        out[name] = []
        for j, src in enumerate(sources):
            row = {"source": src, **{k: float(stats[i, j, n]) for n, k in enumerate(BOUND_STATS)}}
            row["is_bound"] = row["coverage"] >= level and row["nees"] <= 3.0
            out[name].append(row)
    return out


def bound_table_html(table):
    """:func:`bound_table`'s numbers as one escaped HTML table, a row per case and source.

    Columns: the case, the source of ``B B^T`` (:data:`BOUND_SOURCE_NAMES`), the share of
    epochs inside the 3-sigma ball (%), the median ``|e_r| / sqrt(tr Sigma_rr)``, the mean
    NEES, the RMSE (km) and whether ``Sigma`` behaves as a bound.

    Examples
    --------
    >>> row = {"source": "prior", "coverage": 1.0, "median_ratio": 0.3, "nees": 0.4,
    ...        "rmse_m": 1172.7, "median_sigma_m": 3092.0, "is_bound": True}
    >>> page = bound_table_html({"real DE421 - DE405 error": [row]})
    >>> page.count("<tr>"), "100" in page, "1.17" in page
    (2, True, True)
    """
    if not isinstance(table, dict) or not table:
        raise ValueError(f"table must be bound_table()'s dict case -> rows, got {shown(table)}")
    for case, rows in table.items():
        check_records(f"table[{case!r}]", rows, ("source",) + BOUND_STATS + ("is_bound",), "bound row")
        for i, r in enumerate(rows):  # a NaN printed as "nan", a string "no" read as yes: refused
            label = f"table[{case!r}][{i}]"
            check_real(f"{label}['coverage']", r["coverage"], 0.0, 1.0)
            for key in BOUND_STATS:
                check_real(f"{label}[{key!r}]", r[key])
            check_bool(f"{label}['is_bound']", r["is_bound"])
    header = ("case", "source of B B^T", "within 3 sigma (%)", "median |e| / sigma",
              "mean NEES", "RMSE (km)", "a bound?")
    rows = [(case, BOUND_SOURCE_NAMES[r["source"]], f"{100 * r['coverage']:.1f}",
             f"{r['median_ratio']:.2f}", f"{r['nees']:.3g}", f"{r['rmse_m'] / 1e3:.3g}",
             "yes" if r["is_bound"] else "no")
            for case, rows in table.items() for r in rows]
    return html_table(header, rows)
