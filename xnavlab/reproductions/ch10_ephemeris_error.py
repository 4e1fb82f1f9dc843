"""Companion paper 002 (Li et al. 2017): planetary-ephemeris error in XNAV and the RKF.

IDs: ``ephemeris-error`` (Table 1, Figs. 2-3), ``ukf-vs-ephemeris-error`` (Fig. 4),
``rkf-earth`` and ``rkf-mars`` (Figs. 6-7, Table 2), ``rkf-sweep`` (Fig. 8).
"""

from __future__ import annotations

import numpy as np

from xnavlab import robust
from xnavlab.core.constants import DAY
from xnavlab.reproduce import Result, check_info, check_range, check_rel, check_true, register
from xnavlab.reproduce import figure as _figure
from xnavlab.robust import ephemeris_error as ee

__all__ = ["PAPER_IMPROVEMENT", "PAPER_SENSITIVITY", "PAPER_MARS_ERROR_M", "ukf_sensitivity"]

#: Paper Table 2 / text: improvement of the position RMSE over the UKF, percent.
PAPER_IMPROVEMENT = {
    "earth": {"asukf": 61.7, "tdukf": 64.1, "rkf": 67.4},
    "mars": {"asukf": 96.6, "tdukf": 97.5, "rkf": 98.3},
}
#: Paper Fig. 4: UKF estimation error per metre of ephemeris error (150 m per 100 m).
PAPER_SENSITIVITY = 1.5
#: Paper section 3.2: the Mars ephemeris error "grows to about 5e4 m" in orbit 2.
PAPER_MARS_ERROR_M = 5.0e4

_CHAPTER = "10_ephemeris_error"
_SOURCE = "Li et al. 2017 (J. Astronautics 38(1))"
_NAMES = {"ukf": "UKF", "asukf": "ASUKF", "tdukf": "TDUKF", "rkf": "RKF"}



@register("ephemeris-error", title="DE421 - DE405 error of Earth and Mars over 24 h and 1 year",
          source=f"{_SOURCE}, Table 1 and Figs. 2-3", chapter=_CHAPTER)
def ephemeris_error_repro(out=None, t0=ee.EPOCH_1997):
    """Mean ephemeris error over 24 h and one year from 1997-01-01 (values of Table 1 lost)."""
    rows = {}
    for body in ("earth", "mars"):
        for label, span in (("24h", DAY), ("1yr", ee.YEAR)):
            rows[(body, label)] = ee.error_summary(body, t0, span, n=97 if label == "24h" else 366)
    checks = []
    for body in ("earth", "mars"):
        day = rows[(body, "24h")]
        checks.append(check_range(f"{body}: mean error over 24 h (m)", "lost", day["mean_m"],
                                  100.0, 1e4, "DE405-class error: 0.1-10 km"))
        checks.append(check_true(f"{body}: change over 24 h below 1 % (slowly varying)",
                                 "slowly varying bias", abs(day["change_m"]) / day["mean_m"],
                                 abs(day["change_m"]) < 0.01 * day["mean_m"], "< 1 % of the mean"))
    e_yr, m_yr = rows[("earth", "1yr")], rows[("mars", "1yr")]
    for body, r in (("earth", e_yr), ("mars", m_yr)):
        checks.append(check_range(f"{body}: mean error over 1 year (m)", "lost", r["mean_m"], 100.0, 1e4,
                                  "DE405-class error: 0.1-10 km"))
    note = (
        "Truth DE421, filter DE405 (SSB-relative planet positions; Mars is the Mars-system "
        "barycentre), epoch 1997-01-01 00:00 TDB (the paper's Table 1 year). Table 1's values "
        "were lost. Mean error over 24 h / 1 year: Earth "
        f"{rows[('earth', '24h')]['mean_m']:.0f} / {e_yr['mean_m']:.0f} m, Mars "
        f"{rows[('mars', '24h')]['mean_m']:.0f} / {m_yr['mean_m']:.0f} m; over the year Mars ranges "
        f"{m_yr['norm'].min():.0f}-{m_yr['norm'].max():.0f} m, Earth "
        f"{e_yr['norm'].min():.0f}-{e_yr['norm'].max():.0f} m. Both change by only a few metres a "
        "day (the slowly varying bias the ASUKF and TDUKF rely on). The paper's statement that "
        "the Mars error reaches about 5e4 m is not borne out by the real DE405 and DE421 files "
        "(Mars stays below 2 km in 1997), and about 0.5 km of both errors is a common "
        "barycentre offset (the Sun's DE421 - DE405 difference is about 480 m); the Mars "
        "navigation runs therefore also use an injected error of the paper's 5e4 m."
    )
    data = {"rows": {f"{b}-{s}": {k: v for k, v in r.items()} for (b, s), r in rows.items()},
            "t0": t0}
    res = Result("ephemeris-error", checks, note, data)
    if out is not None:
        fig, axes = _figure(1, 2, figsize=(10, 3.5))
        for ax, label, scale, unit in ((axes[0], "24h", 3600.0, "h"), (axes[1], "1yr", 86400.0, "d")):
            for body in ("earth", "mars"):
                r = rows[(body, label)]
                ax.plot((r["t"] - t0) / scale, r["norm"], label=body.capitalize())
            ax.set_xlabel(f"time since 1997-01-01 ({unit})")
            ax.set_ylabel("|DE421 - DE405| (m)")
            ax.legend()
        fig.tight_layout()
        path = out / "ephemeris-error.png"
        fig.savefig(path, dpi=100)
        res.figures.append(str(path))
    return res


def ukf_sensitivity(sizes=(0.0, 250.0, 500.0, 750.0, 1000.0), body="earth", seeds=(0,)):
    """UKF RMSE against an injected constant ephemeris error (Fig. 4).

    Returns
    -------
    sizes : ndarray, shape (m,)
    rmse : ndarray, shape (m,)
        Mean RMSE over the seeds over the paper's window, m.

    Examples
    --------
    >>> sizes, r = ukf_sensitivity((0.0, 1000.0))
    >>> bool(r[1] - r[0] > 500.0)
    True
    """
    sizes = np.asarray(sizes, dtype=float)
    out = [robust.compare_filters(body, ("ukf",), error="constant", size=float(s), seeds=seeds)
           ["rmse"]["ukf"] for s in sizes]
    return sizes, np.array(out)


@register("ukf-vs-ephemeris-error", title="UKF position error against the ephemeris error (Earth)",
          source=f"{_SOURCE}, Fig. 4", chapter=_CHAPTER)
def ukf_vs_ephemeris_error(out=None, sizes=(0.0, 250.0, 500.0, 750.0, 1000.0), seeds=(0, 1)):
    """Slope of the UKF RMSE against a constant injected ephemeris error (paper: about 1.5)."""
    sizes, r = ukf_sensitivity(sizes, "earth", tuple(seeds))
    slope, icpt = np.polyfit(sizes, r, 1)
    fit = slope * sizes + icpt
    r2 = 1.0 - np.sum((r - fit) ** 2) / np.sum((r - r.mean()) ** 2)
    checks = [
        check_rel("UKF error per metre of ephemeris error", PAPER_SENSITIVITY, slope, 0.5),
        check_true("error grows linearly (R^2 of the line)", "linear", float(r2), r2 > 0.98, "R^2 > 0.98"),
    ]
    note = (
        "Earth orbit (representative OPS_5111 elements), three pulsars, 500-s steps; constant "
        "ephemeris error along (1,1,1)/sqrt(3) injected into the truth; UKF RMSE over "
        f"1e5-6e5 s, seeds {tuple(seeds)}. Ours: {slope:.2f} m per m (intercept {icpt:.0f} m) "
        "against the paper's 1.5. The slope depends on how readily the filter absorbs a "
        "position offset into the orbit, i.e. on the process noise and measurement rate, which "
        "the paper does not give (its Table of filter inputs was lost); with our Q the UKF "
        "absorbs a little more than the offset itself. Tolerance: within 50 %."
    )
    res = Result("ukf-vs-ephemeris-error", checks, note,
                 {"sizes": sizes, "rmse": r, "slope": float(slope), "intercept": float(icpt)})
    if out is not None:
        fig, ax = _figure(figsize=(5, 3.5))
        ax.plot(sizes, r, "o-", label="UKF (xnavlab)")
        ax.plot(sizes, PAPER_SENSITIVITY * sizes, "k--", label="paper: 1.5 m per m")
        ax.set_xlabel("ephemeris error (m)")
        ax.set_ylabel("UKF position RMSE (m)")
        ax.legend()
        fig.tight_layout()
        path = out / "ukf-vs-ephemeris-error.png"
        fig.savefig(path, dpi=100)
        res.figures.append(str(path))
    return res


def _figure_runs(cmp, body, out, name):
    fig, ax = _figure(figsize=(7, 3.5))
    for f, err in cmp["error"].items():
        ax.semilogy(cmp["tau"], err, label=_NAMES[f], lw=1)
    lo, hi = robust.WINDOWS[body]
    ax.axvspan(lo, hi, color="0.9", zorder=0)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("position error (m)")
    ax.legend(ncol=4)
    fig.tight_layout()
    path = out / f"{name}.png"
    fig.savefig(path, dpi=100)
    return str(path)


def _ranking(rmse):
    return " < ".join(_NAMES[f] for f in sorted(rmse, key=rmse.get))


@register("rkf-earth", title="UKF, ASUKF, TDUKF and RKF on the Earth orbit with the DE405 error",
          source=f"{_SOURCE}, Fig. 6 and Table 2", chapter=_CHAPTER)
def rkf_earth(out=None, seeds=(0, 1, 2, 3)):
    """Improvement over the UKF on the Earth orbit (paper 61.7 / 64.1 / 67.4 %)."""
    cmp = robust.compare_filters("earth", error="de405", seeds=tuple(seeds))
    imp = cmp["improvement"]
    paper = PAPER_IMPROVEMENT["earth"]
    checks = [
        check_range(f"{_NAMES[f]} improvement over UKF (%)", paper[f], imp[f], paper[f] - 10.0, 100.0,
                    "at least the paper's minus 10 pp (ours is larger: see note)")
        for f in ("asukf", "tdukf", "rkf")
    ]
    checks.append(check_info("ranking, best first", "RKF < TDUKF < ASUKF < UKF", _ranking(cmp["rmse"]),
                             "not reproduced: see note"))
    note = (
        f"RMSE over 1e5-6e5 s, mean of seeds {tuple(seeds)}: "
        + ", ".join(f"{_NAMES[f]} {v:.0f} m" for f, v in cmp["rmse"].items())
        + f". Ranking (best first): {_ranking(cmp['rmse'])}; the paper's is RKF < TDUKF < ASUKF. "
        "Not reproduced: (1) our improvements are about 20-30 pp larger than the paper's, because "
        "our bias-aware filters converge to about 60-140 m while the paper's must be at about a "
        "third of its UKF error; the paper's initial errors, P0 and Q were lost, so its absolute "
        "accuracy cannot be matched. (2) Our RKF is behind the ASUKF and TDUKF. The re-derived "
        "bound-minimising gain inflates R along the bias B = N dr_E by (1 + eps)/(1 + 1/eps) "
        "and so discards one measurement combination at every epoch, whereas the ASUKF learns "
        "a constant bias once and then uses all three measurements and the TDUKF cancels it; "
        "for a bias that is constant over the run this is a real loss of information, not a "
        "tuning matter (with eps -> inf the RKF error stays above the ASUKF's). The RKF's bias "
        "bound comes from the a priori ephemeris-error model (the DE421 - DE405 difference at "
        "the start epoch, held constant: the paper puts its section-1.2 analysis into the "
        "measurement model); with the purely residual-based bound (rkf_bias='residual') the "
        "bias is absorbed into the state before it can be detected and the RKF is no better "
        "than the UKF. Orbit: representative GPS Block I elements for OPS_5111 "
        "(a = 26,560 km, e = 0.01, i = 63 deg); epoch 1997-01-01; TDUKF with the exact "
        "treatment of the correlated differenced noise."
    )
    res = Result("rkf-earth", checks, note, cmp)
    if out is not None:
        res.figures.append(_figure_runs(cmp, "earth", out, "rkf-earth"))
    return res


@register("rkf-mars", title="UKF, ASUKF, TDUKF and RKF on the Mars orbit",
          source=f"{_SOURCE}, Fig. 7 and Table 2", chapter=_CHAPTER)
def rkf_mars(out=None, seeds=(0, 1, 2, 3), size=PAPER_MARS_ERROR_M):
    """Improvement over the UKF on the Mars orbit (paper 96.6 / 97.5 / 98.3 %).

    The main run injects the paper's 5e4-m slowly varying error; the real DE405 error
    (about 1.2 km) is run as well and reported in the note.
    """
    cmp = robust.compare_filters("mars", error="slow", size=float(size), seeds=tuple(seeds))
    real = robust.compare_filters("mars", error="de405", seeds=tuple(seeds))
    imp = cmp["improvement"]
    paper = PAPER_IMPROVEMENT["mars"]
    checks = [check_range(f"{_NAMES[f]} improvement over UKF (%)", paper[f], imp[f], paper[f] - 10.0,
                          min(100.0, paper[f] + 10.0), "within 10 pp") for f in ("asukf", "tdukf", "rkf")]
    checks.append(check_info("ranking, best first", "RKF < TDUKF < ASUKF < UKF", _ranking(cmp["rmse"]),
                             "not reproduced: see note"))
    note = (
        f"Injected slowly varying error of {size:.0f} m (the paper's Mars figure), RMSE over "
        f"5e4-2.5e5 s, mean of seeds {tuple(seeds)}: "
        + ", ".join(f"{_NAMES[f]} {v:.0f} m" for f, v in cmp["rmse"].items())
        + f"; ranking {_ranking(cmp['rmse'])} (paper: RKF < TDUKF < ASUKF). With the real "
        "DE405 error (about 1.2 km in 1997): "
        + ", ".join(f"{_NAMES[f]} {v:.0f} m" for f, v in real["rmse"].items())
        + ", improvements "
        + ", ".join(f"{_NAMES[f]} {v:.1f} %" for f, v in real["improvement"].items())
        + ". The three improvements match the paper within 10 pp at the paper's error size "
        "because the UKF error is then tens of km; the RKF ranks last of the three for the "
        "reason given under rkf-earth (it discards the biased measurement combination at every "
        "epoch). Mars orbit: the main paper's initial state (a = 4196 km, e = 0.09, i = 75 deg), "
        "since Wei et al. (2013)'s elements were not recoverable; eps = 100."
    )
    data = dict(cmp)
    data["real"] = real
    res = Result("rkf-mars", checks, note, data)
    if out is not None:
        res.figures.append(_figure_runs(cmp, "mars", out, "rkf-mars"))
    return res


@register("rkf-sweep", title="The four filters across ephemeris-error sizes",
          source=f"{_SOURCE}, Fig. 8", chapter=_CHAPTER)
def rkf_sweep(out=None, sizes=(0.0, 1000.0, 3000.0, 10000.0), body="mars", seeds=(0,)):
    """RMSE of each filter against the size of a slowly varying injected ephemeris error."""
    sizes = tuple(float(s) for s in sizes)
    table = {f: [] for f in robust.FILTERS}
    for s in sizes:
        cmp = robust.compare_filters(body, error="slow", size=s, seeds=tuple(seeds))
        for f in robust.FILTERS:
            table[f].append(cmp["rmse"][f])
    table = {f: np.array(v) for f, v in table.items()}
    big = int(np.argmax(sizes))
    others = [table[f][big] for f in ("asukf", "tdukf", "rkf")]
    ukf_growth = table["ukf"][big] - table["ukf"][0]
    other_growth = max(table[f][big] - table[f][0] for f in ("asukf", "tdukf", "rkf"))
    checks = [
        check_true("UKF error grows with the ephemeris error (m, largest minus none)",
                   "rises sharply", float(ukf_growth), ukf_growth > 0.5 * (sizes[big] - sizes[0]),
                   "grows by more than half the added error"),
        check_true("ASUKF, TDUKF, RKF stay small at the largest error (worst RMSE, m)",
                   "small", float(max(others)), max(others) < 0.1 * table["ukf"][big],
                   "below 10 % of the UKF's"),
        check_true("their growth is bounded (m)", "bounded", float(other_growth),
                   other_growth < 0.05 * (sizes[big] - sizes[0]), "less than 5 % of the added error"),
    ]
    note = (
        f"{body.capitalize()} orbit, slowly varying injected error, one run per size "
        f"(seeds {tuple(seeds)}). RMSE (m) at sizes {sizes}: "
        + "; ".join(f"{_NAMES[f]} " + ", ".join(f"{v:.0f}" for v in table[f]) for f in robust.FILTERS)
        + ". As in the paper, the UKF error rises steeply with the ephemeris error while the three "
        "bias-aware filters stay nearly flat; unlike the paper, the RKF is not the best of the "
        "three (see rkf-earth). The Mars orbit is used because its runs are 2.4 times shorter."
    )
    res = Result("rkf-sweep", checks, note, {"sizes": np.array(sizes), "rmse": table, "body": body})
    if out is not None:
        fig, ax = _figure(figsize=(5, 3.5))
        for f in robust.FILTERS:
            ax.plot(sizes, table[f], "o-", label=_NAMES[f])
        ax.set_yscale("log")
        ax.set_xlabel("ephemeris error (m)")
        ax.set_ylabel("position RMSE (m)")
        ax.legend()
        fig.tight_layout()
        path = out / "rkf-sweep.png"
        fig.savefig(path, dpi=100)
        res.figures.append(str(path))
    return res
