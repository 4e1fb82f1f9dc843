"""Figures of chapter 10's slider: the four filters of Li et al. 2017 side by side on the Mars orbit.

Examples
--------
>>> fig = plot_filter_comparison(100.0, 100.0, "all four")
>>> [ax.get_ylabel() for ax in fig.axes]
['position error (m)', 'RMSE (m)']
"""

from __future__ import annotations

import functools

from xnavlab.core.plotting import sparse_log_minors
from xnavlab.core.validate import check_choice, check_real, make_rng
from xnavlab.robust import filters

__all__ = ["FILTER_NAMES", "PULSAR_SETS", "plot_filter_comparison", "filter_comparison"]

#: Display names of :data:`xnavlab.robust.filters.FILTERS`.
FILTER_NAMES = {"ukf": "UKF", "asukf": "ASUKF", "tdukf": "TDUKF", "rkf": "RKF"}

#: Pulsar sets of the chapter's dropdown: the paper's three and the alternatives from the
#: four pulsars of :mod:`xnavlab.mars.pulsars`.
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
        The RKF's scalar epsilon (> 1 in the paper; any value > 0 runs).
    pulsar_set : str
        A key of :data:`PULSAR_SETS`.

    Returns
    -------
    matplotlib.figure.Figure
        Left: each filter's position error (m) against time, the RMSE window shaded; right:
        the RMSE over the window (m). Not registered with pyplot.
    """
    from matplotlib.figure import Figure

    out = filter_comparison(size, eps, pulsar_set)
    # fixed margins, not the constrained layout: the live slider redraws this at every move
    fig = Figure(figsize=(11, 3.4))
    fig.subplots_adjust(left=0.07, right=0.99, bottom=0.14, top=0.91, wspace=0.25)
    ax1, ax2 = fig.subplots(1, 2, width_ratios=[3, 1])
    for f, err in out["error"].items():
        ax1.semilogy(out["tau"], err, lw=1, label=FILTER_NAMES[f])
    ax1.axvspan(*filters.WINDOWS["mars"], color="0.92", zorder=0)
    ax1.set(xlabel="time (s)", ylabel="position error (m)",
            title=f"Mars, ephemeris error {size:.0f} m, eps = {eps:g}")
    ax1.legend(ncol=4, fontsize=8)
    ax2.bar([FILTER_NAMES[f] for f in out["rmse"]], list(out["rmse"].values()))
    ax2.set(yscale="log", ylabel="RMSE (m)", title="RMSE 5e4-2.5e5 s")
    sparse_log_minors(ax1, ax2)
    return fig


def filter_comparison(size=5000.0, eps=100.0, pulsar_set="paper: B0531+21, B1821-24, B1937+21"):
    """The numbers of :func:`plot_filter_comparison`, with every filter's run kept in memory.

    The same numbers as :func:`xnavlab.robust.filters.compare_filters` ``("mars",
    error="growing", size=size, eps=eps, pulsar_names=PULSAR_SETS[pulsar_set], seeds=(0,))``
    (seed 0 draws the scenario, then the initial error that all four filters share), but
    each filter's run is cached on its own arguments: ``eps`` enters only the RKF, so the
    slider's ``eps`` reruns one filter of four, and a position seen before reruns none.

    Parameters
    ----------
    size : float
        Ephemeris error reached at the end of the RMSE window, m (> 0).
    eps : float
        The RKF's scalar epsilon (> 0).
    pulsar_set : str
        A key of :data:`PULSAR_SETS`.

    Returns
    -------
    dict
        ``rmse`` ({filter: RMSE over :data:`~xnavlab.robust.filters.WINDOWS` ``["mars"]``,
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
    size = check_real("size", size, 0.0, lo_open=True)
    eps = check_real("eps", eps, 0.0, lo_open=True)
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
    return filters.rmse(run, sc, *filters.WINDOWS["mars"]), err
