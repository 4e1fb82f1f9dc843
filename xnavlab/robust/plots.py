"""Figures of chapter 10's slider: the four filters of Li et al. 2017 side by side on the Mars orbit.

Examples
--------
>>> fig = plot_filter_comparison(100.0, 100.0, "all four")
>>> [ax.get_ylabel() for ax in fig.axes]
['position error (m)', 'RMSE (m)']
"""

from __future__ import annotations

from xnavlab.core.validate import check_choice
from xnavlab.robust import filters

__all__ = ["FILTER_NAMES", "PULSAR_SETS", "plot_filter_comparison"]

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

    A pure function of its arguments (seed 0; 500 steps of 500 s, about 0.3 s), for
    chapter 10's slider: runs
    :func:`~xnavlab.robust.filters.compare_filters` with ``error="growing"``.

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

    check_choice("pulsar_set", pulsar_set, tuple(PULSAR_SETS))
    out = filters.compare_filters("mars", error="growing", size=size, eps=eps,
                                  pulsar_names=PULSAR_SETS[pulsar_set], seeds=(0,))
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
    return fig
