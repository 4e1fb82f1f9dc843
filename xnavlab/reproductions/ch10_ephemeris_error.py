"""Li et al. 2017: planetary-ephemeris error in XNAV and the RKF.

IDs: ``ephemeris-error`` (Table 1, Figs. 2-3), ``ukf-vs-ephemeris-error`` (Fig. 4),
``rkf-earth`` and ``rkf-mars`` (Figs. 6-7, Table 2), ``rkf-sweep`` (Fig. 8).

The navigation runs use the paper's filters as the paper means them: the RKF with its
bias bound from the measurement residuals, the TDUKF with white differenced noise
(``2 R``), and an ephemeris error that grows from zero over the run (paper section 1.2,
"the ephemeris error keeps increasing with time") and reaches the paper's size at the end
of the RMSE window. The same error held constant is run beside it, to show that the
paper's ranking needs the growth.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from xnavlab import robust
from xnavlab.core import ephemeris
from xnavlab.core.constants import DAY
from xnavlab.core.validate import check_real, check_seeds
from xnavlab.reproduce import (
    NOT_REPRODUCED,
    REPRODUCED,
    UNDECIDED,
    Check,
    Result,
    check_draw,
    check_lost,
    check_measure,
    check_order,
    check_range,
    check_sanity,
    check_true,
    part_of,
    register,
    save_figure,
)
from xnavlab.reproduce import figure as _figure
from xnavlab.robust import ephemeris_error as ee
from xnavlab.robust.sensitivity import (
    earth_error_size,
    sensitivity_directions,
    steepest_direction,
    ukf_sensitivity,
    ukf_sensitivity_by_direction,
)

__all__ = [
    "PAPER_IMPROVEMENT",
    "PAPER_SENSITIVITY",
    "PAPER_MARS_ERROR_M",
    "paired_difference",
    "RKF_LAMBDAS",
    "rkf_memory_sweep",
    "lost_settings",
    "LOST_LAMBDAS",
    "LOST_Q_B",
    "LOST_Q_V",
    "LOST_INITIAL",
    "LOST_MARS_A",
    "LOST_EARTH_ORIENTATION",
    "orbit_elements",
    "RANKING_CLAIM",
]

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
    e_yr, m_yr = rows[("earth", "1yr")], rows[("mars", "1yr")]
    for body, r in (("earth", e_yr), ("mars", m_yr)):
        first, last = float(np.mean(r["norm"][:30])), float(np.mean(r["norm"][-30:]))
        checks.append(check_true(f"{body}: error grows over the year (mean of the last 30 days, m)",
                                 "grows with time", last, last > first,
                                 why=f"larger than the first 30 days' mean, {first:.0f} m",
                                 reading="" if last > first else
                                 f"ours falls to {100 * last / first:.0f} % of the first 30 days' "
                                 f"mean ({last:.0f} m against {first:.0f} m)"))
    for body in ("earth", "mars"):
        day = rows[(body, "24h")]
        checks.append(check_true(f"{body}: change over 24 h / mean (slowly varying)",
                                 "slowly varying bias", abs(day["change_m"]) / day["mean_m"],
                                 abs(day["change_m"]) < 0.01 * day["mean_m"],
                                 why="below 1 % of the mean: a bias the ASUKF and TDUKF may "
                                     "treat as constant over a step"))
    ratio = m_yr["mean_m"] / e_yr["mean_m"]
    checks.append(check_true("Mars error / Earth error, 1-year means", "Mars far worse",
                             float(ratio), ratio > 3.0,
                             why="'far worse' read as more than three times the Earth's",
                             reading="" if ratio > 3.0 else
                             f"ours ({ratio:.2f}) is {3.0 / ratio:.1f} times short of 3: Mars's error is "
                             f"{100 * (ratio - 1):.0f} % above the Earth's"))
    checks.append(check_range("mars: largest error over 1997 (m)", "about 5e4", float(m_yr["norm"].max()),
                              2.5e4, 1e5, why="'about 5e4 m' read as within a factor of 2"))
    for body, r in (("earth", e_yr), ("mars", m_yr)):  # Table 1's values were lost: orders only
        checks.append(check_sanity(f"{body}: mean error over 1 year (m)", "lost", r["mean_m"],
                                   100.0 <= r["mean_m"] <= 1e4, "DE405-class error: 0.1-10 km"))
    sun = float(np.linalg.norm(ephemeris.position("sun", t0, "de421")
                               - ephemeris.position("sun", t0, "de405")))
    m_first, m_last = float(np.mean(m_yr["norm"][:30])), float(np.mean(m_yr["norm"][-30:]))
    day_change = max(abs(rows[(b, "24h")]["change_m"]) for b in ("earth", "mars"))
    peak = float(m_yr["norm"].max())
    note = (
        "Truth DE421, filter DE405 (SSB-relative planet positions; Mars is the Mars-system "
        f"barycentre), from {_epoch_text(t0)} TDB (the paper's Table 1 year is 1997). Table 1's "
        "values were lost. Mean error over 24 h / 1 year: Earth "
        f"{rows[('earth', '24h')]['mean_m']:.0f} / {e_yr['mean_m']:.0f} m, Mars "
        f"{rows[('mars', '24h')]['mean_m']:.0f} / {m_yr['mean_m']:.0f} m (a ratio of "
        f"{ratio:.2f}); over the year Mars ranges {m_yr['norm'].min():.0f}-{peak:.0f} m, Earth "
        f"{e_yr['norm'].min():.0f}-{e_yr['norm'].max():.0f} m. The Mars error "
        + ("falls" if m_last < m_first else "grows")
        + f" over the year, from a mean of {m_first:.0f} m over the first 30 days to {m_last:.0f} m "
        f"over the last 30. Both change by at most {day_change:.0f} m in a day (the slowly varying "
        "bias the ASUKF and TDUKF rely on). "
        + (f"The largest Mars error of the year is {peak:.0f} m, {PAPER_MARS_ERROR_M / peak:.0f} "
           "times below the paper's 'about 5e4 m'; the Mars navigation runs therefore also use an "
           "injected error of the paper's 5e4 m. " if peak < 0.5 * PAPER_MARS_ERROR_M else
           f"The largest Mars error of the year is {peak:.0f} m. ")
        + f"The Sun's own DE421 - DE405 difference at the start is {sun:.0f} m: that much of both "
        "planets' errors is a common offset of the barycentre."
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
        res.figures.append(save_figure(fig, out, "ephemeris-error"))
    return res


def _epoch_text(t0):
    """``t0`` (s TDB past J2000) as a date and time, for a note."""
    from datetime import datetime, timedelta

    when = datetime(2000, 1, 1, 12) + timedelta(seconds=float(t0))
    return when.strftime("%Y-%m-%d %H:%M")


def paired_difference(cmp, a, b):
    """Mean and standard error over seeds of ``RMSE_a - RMSE_b`` (same seeds), m.

    Examples
    --------
    >>> paired_difference({"rmse_runs": {"x": [1.0, 3.0], "y": [0.0, 0.0]}}, "x", "y")
    (2.0, 1.0)
    """
    d = np.asarray(cmp["rmse_runs"][a]) - np.asarray(cmp["rmse_runs"][b])
    se = float(d.std(ddof=1) / np.sqrt(d.size)) if d.size > 1 else float("inf")
    return float(d.mean()), se


def _improvement_runs(cmp, f):
    """Per-seed improvement of filter ``f`` over the UKF, percent (the paper's Table 2 metric)."""
    return 100.0 * (1.0 - np.asarray(cmp["rmse_runs"][f]) / np.asarray(cmp["rmse_runs"]["ukf"]))


#: The paper's ranking of the four filters (Li et al. 2017, Table 2), best first.
PAPER_RANKING = ("rkf", "tdukf", "asukf", "ukf")


#: The paper's main claim in rkf-earth and rkf-mars: its ranking (rows that are its parts).
RANKING_CLAIM = "ranking RKF < TDUKF < ASUKF < UKF (Table 2)"


def _order_checks(cmp, lost=None):
    """The paper's ranking as its three adjacent paired orders, and the ranking they decide
    (one claim, :data:`RANKING_CLAIM`); with ``lost``, whether a lost setting reverses the
    RKF's order against the TDUKF."""
    pairs = list(zip(PAPER_RANKING[:-1], PAPER_RANKING[1:], strict=True))
    rows = []
    for a, b in pairs:
        d = np.asarray(cmp["rmse_runs"][a]) - np.asarray(cmp["rmse_runs"][b])
        rows.append(check_order(f"{_NAMES[a]} better than {_NAMES[b]} (paired RMSE difference)",
                                f"{_NAMES[a]} < {_NAMES[b]}", d, unit="m"))
    found = [c.verdict for c in rows]
    verdict = (REPRODUCED if all(v == REPRODUCED for v in found)
               else NOT_REPRODUCED if NOT_REPRODUCED in found else UNDECIDED)
    reading = "; ".join(f"{c.paper}: {c.verdict}" for c in rows)
    rows.append(Check("ranking of the mean RMSE, best first", " < ".join(_NAMES[f] for f in PAPER_RANKING),
                      _ranking(cmp["rmse"]), "each adjacent pair of the paper's ranking decided in "
                      "its order over the seeds (the rows above)", verdict, reading))
    if lost is not None and rows[0].verdict != REPRODUCED:
        d = lost["rkf_minus_tdukf"]
        lo_k, hi_k = min(d, key=d.get), max(d, key=d.get)
        flips = [k for k, v in d.items() if v < 0]
        extra = (f"RKF - TDUKF over the lost settings run ({len(_LOST_SEEDS)} seeds each): "
                 f"{d[lo_k]:+.0f} m ({lo_k}) to {d[hi_k]:+.0f} m ({hi_k}); "
                 + (f"the mean turns in the paper's favour at {', '.join(flips)}" if flips else
                    "no lost setting we ran turns it in the paper's favour"))
        first = rows[0]
        rows[0] = Check(first.name, first.paper, first.ours, first.tolerance, first.verdict,
                        "; ".join(x for x in (first.reading, extra) if x))
    return part_of(RANKING_CLAIM, *rows)


#: Weights of the RKF's residual average run as its lost tuning (ours 0.02; 1: the current residual).
LOST_LAMBDAS = (0.05, 0.2, 1.0)
#: ASUKF bias random-walk steps run as its lost tuning, m per step (ours 1).
LOST_Q_B = (0.1, 10.0)
#: Process noise run as the paper's lost one, every filter, m/s per axis per step (ours 1e-4: x0.1, x10).
LOST_Q_V = (1e-5, 1e-3)
#: Initial errors run as the paper's lost one, every filter: (m, m/s) per axis (ours 1 km, 1 m/s: x0.1, x10).
LOST_INITIAL = ((100.0, 0.1), (1e4, 10.0))
#: The label of our own settings among the lost ones (:func:`_improvement_checks`).
_OURS = "ours (1,1,1), q 1e-4 m/s, initial 1 km, lam 0.02, walk 1 m/step"
#: Seeds each lost setting is run with (paired with the same seeds of ours).
_LOST_SEEDS = (0, 1)
#: Semi-major axes of the Mars orbits run as the paper's lost one (Wei et al.'s elements were not
#: recoverable), m; ours is the main paper's Mars state (a = 4196 km), whose eccentricity,
#: inclination and orientation every one keeps.
LOST_MARS_A = (1.0e7, 2.0e7)
#: Orientations of the Earth orbit run as the paper's lost one: (node, true anomaly at the epoch),
#: deg (ours 0, 0). The paper names the satellite, OPS 5111 (NAVSTAR 1, GPS Block I), whose class
#: places the size (a = 26,560 km, the 12-h GPS orbit) and the inclination (63 deg), and a
#: near-circular orbit (ours e = 0.01): those are held; its table of elements is lost, and
#: nothing places the orbit's orientation to the pulsars and the error, which is varied.
LOST_EARTH_ORIENTATION = ((120.0, 0.0), (240.0, 0.0), (0.0, 90.0))


def orbit_elements(state, gm):
    """Classical elements of a Cartesian state, the inverse of
    :func:`~xnavlab.robust.ephemeris_error.elements_to_state`.

    Parameters
    ----------
    state : array_like, shape (6,)
        Position (m) and velocity (m/s) relative to the central body.
    gm : float
        Its gravitational parameter, m^3/s^2.

    Returns
    -------
    tuple of 6 float
        ``(a_m, e, i_deg, raan_deg, argp_deg, nu_deg)`` (an elliptic, inclined orbit).

    Examples
    --------
    >>> gm = ee.PLANETS["mars"][0]
    >>> el = orbit_elements(ee.elements_to_state(5e6, 0.1, 30.0, 40.0, 50.0, 60.0, gm), gm)
    >>> [round(x, 6) for x in el]
    [5000000.0, 0.1, 30.0, 40.0, 50.0, 60.0]
    """
    r, v = np.asarray(state[:3], float), np.asarray(state[3:], float)
    h = np.cross(r, v)                                          # angular momentum
    node = np.cross([0.0, 0.0, 1.0], h)
    e_vec = np.cross(v, h) / gm - r / np.linalg.norm(r)        # eccentricity vector
    hn = h / np.linalg.norm(h)
    a = 1.0 / (2.0 / np.linalg.norm(r) - v @ v / gm)           # vis-viva
    i = np.arccos(hn[2])
    raan = np.arctan2(node[1], node[0])
    argp = np.arctan2(np.cross(node, e_vec) @ hn, node @ e_vec)
    nu = np.arctan2(np.cross(e_vec, r) @ hn, e_vec @ r)
    return (float(a), float(np.linalg.norm(e_vec)),
            *(float(np.degrees(x)) for x in (i, raan, argp, nu)))


def lost_settings(body, size, cmp, seeds=_LOST_SEEDS, profile="linear"):
    """How far the settings Li et al. 2017 lost move each filter's improvement over the UKF.

    One lost setting varied at a time from ours, each run on ``seeds`` (a subset of the seeds
    of ``cmp``) and compared with ours on the same seeds. For all four filters: the direction
    of the ephemeris error (every direction of
    :func:`~xnavlab.robust.sensitivity.sensitivity_directions` but ours), the process noise
    (:data:`LOST_Q_V`) and the initial error (:data:`LOST_INITIAL`); the RKF's residual-average
    weight (:data:`LOST_LAMBDAS`) and the ASUKF's bias random walk
    (:data:`LOST_Q_B`); on Mars, the size of the orbit (:data:`LOST_MARS_A`, the other
    elements ours); on Earth, the orbit's orientation (:data:`LOST_EARTH_ORIENTATION`: its node
    and its anomaly at the epoch; the size, inclination and eccentricity are placed by the
    paper's satellite and held). The pulsar table, lost too, is not varied (three catalogue
    pulsars whose ranging accuracies give the paper's R).
    All the settings run as one batch per filter (:func:`xnavlab.robust.compare_settings`).

    Parameters
    ----------
    body : {"earth", "mars"}
    size : float
        Final size of the growing error, m.
    cmp : dict
        Our run (:func:`xnavlab.robust.compare_filters`, its seeds starting with ``seeds``).
    seeds : sequence of int
    profile : str

    Returns
    -------
    dict
        ``shift`` ({filter: {setting: mean paired change of its improvement, percentage
        points}}), ``rkf_minus_tdukf`` and ``rkf_minus_asukf`` ({setting: mean paired RMSE
        difference, m}).
    """
    seeds = check_seeds("seeds", seeds)
    k = len(seeds)
    mine = {f: np.asarray(cmp["rmse_runs"][f])[:k] for f in robust.FILTERS}
    ours = {f: _improvement_runs(cmp, f)[:k] for f in ("asukf", "tdukf", "rkf")}
    every = robust.FILTERS
    settings = {f"direction {name}": ({"direction": u}, {}, every)
                for name, u in sensitivity_directions(body).items() if name != "(1,1,1)"}  # (1,1,1): ours
    settings.update({f"process noise {q:g} m/s": ({}, {"q_v": q}, every) for q in LOST_Q_V})
    settings.update({f"initial error {r / 1e3:g} km, {v:g} m/s": ({}, {"sigma_r0": r, "sigma_v0": v}, every)
                     for r, v in LOST_INITIAL})
    settings.update({f"RKF lam {lam:g}": ({}, {"lam": lam}, ("rkf",)) for lam in LOST_LAMBDAS})
    settings.update({f"ASUKF walk {q_b:g} m/step": ({}, {"q_b": q_b}, ("asukf",)) for q_b in LOST_Q_B})
    if body == "mars":
        el = orbit_elements(ee.orbit("mars").state0, ee.PLANETS["mars"][0])
        settings.update({f"orbit a {a / 1e3:,.0f} km": ({"elements": (a, *el[1:])}, {}, every)
                         for a in LOST_MARS_A})
    else:
        a, e, i, _, argp, _ = ee.EARTH_ELEMENTS
        settings.update({_orientation_label(node, nu): ({"elements": (a, e, i, node, argp, nu)}, {}, every)
                         for node, nu in LOST_EARTH_ORIENTATION})
    got = robust.compare_settings(body, settings, seeds, error="growing", size=float(size), profile=profile)
    shift = {f: {} for f in ours}
    order = {"tdukf": {}, "asukf": {}}
    for label, (_, _, filters) in settings.items():
        run = {f: np.asarray(got[label].get(f, mine[f])) for f in robust.FILTERS}  # ours where not rerun
        for f in ours:
            if f in filters:
                shift[f][label] = float(np.mean(100.0 * (1.0 - run[f] / run["ukf"]) - ours[f]))
        for o in order:
            if "rkf" in filters or o in filters:
                order[o][label] = float(np.mean(run["rkf"] - run[o]))
    return {"shift": shift, "rkf_minus_tdukf": order["tdukf"], "rkf_minus_asukf": order["asukf"]}


def _orientation_label(node, nu):
    """A lost Earth-orbit orientation's label: ``"orbit node 120 deg, anomaly 0 deg"``."""
    return f"orbit node {node:g} deg, anomaly {nu:g} deg"


#: The lost settings held at ours (not varied), with the reason, per orbit.
_HELD = {
    "earth": "the orbit's elements, lost too, are varied by its orientation to the pulsars and "
             "the error, node and anomaly at the epoch; its size, a = 26,560 km, its inclination, "
             "63 deg, and its near-circular shape, e 0.01, are held: the paper names the "
             "satellite, OPS 5111, a GPS Block I, whose 12-h, 63-deg orbit places them",
    "mars": "the orbit, lost too (Wei et al.'s elements were not recoverable), is varied by its "
            "size, which sets the dynamics the filters average over; its shape and orientation "
            "are held at the main paper's Mars state (e 0.09, i 75 deg)",
}
_PULSARS_HELD = "; the pulsars are held as the three whose ranging accuracies give the paper's R"


def _lost_what(f, body):
    """For an improvement of filter ``f``: the lost settings it is judged over (words), what
    would decide it, and the lost settings held at ours with their reason (:func:`check_lost`)."""
    what = "error direction, process noise, initial error" + (
        ", size of the orbit" if body == "mars" else ", orientation of the orbit") + (
        "" if f == "tdukf" else f" and {_NAMES[f]} tuning")
    decides = f"the paper's {what}"
    return what, decides, _HELD[body] + _PULSARS_HELD


def _lost_reach(runs, lost, f):
    """The 95 % range of our single runs of ``f`` (its improvement, %) at our settings and
    shifted by each lost setting's measured effect."""
    lo, hi = np.percentile(runs, [2.5, 97.5])
    reach = {_OURS: (lo, hi)}
    reach.update({k: (lo + d, hi + d) for k, d in lost["shift"][f].items()})
    return reach


def _improvement_checks(cmp, paper, lost=None, body="mars"):
    """The paper's single-run improvements, each judged among ours, one per seed; with
    ``lost`` (:func:`lost_settings`), judged again over the lost settings (:func:`check_lost`)."""
    rows = []
    for f in ("asukf", "tdukf", "rkf"):
        runs = _improvement_runs(cmp, f)
        row = check_draw(f"{_NAMES[f]} improvement over UKF (%)", paper[f], runs)
        if lost is not None:
            what, decides, held = _lost_what(f, body)
            row = check_lost(row, what, _lost_reach(runs, lost, f), decides, unit="%", held=held)
        rows.append(row)
    return rows


#: What ukf-vs-ephemeris-error does not vary, and why its verdict stands without it (an
#: UNDECIDED of check_lost stays one when values are added: they only widen what ours reaches),
#: or, for another verdict, that it may not.
_SLOPE_HELD = {
    True: "the orbit's orientation and the pulsar table (Table 4), lost too, are held at ours: they "
          "move the slope as well, but values added to those run only widen what ours reaches, "
          "so they cannot decide a slope the directions leave undecided",
    False: "the orbit's orientation and the pulsar table (Table 4), lost too, are held at ours and "
           "move the slope as well: varied, they could leave it undecided",
}


@register("ukf-vs-ephemeris-error", title="UKF position error against the ephemeris error (Earth)",
          source=f"{_SOURCE}, Fig. 4", chapter=_CHAPTER)
def ukf_vs_ephemeris_error(out=None, sizes=(0.0, 250.0, 500.0, 750.0, 1000.0), seeds=(0, 1)):
    """Slope of the UKF RMSE against a constant injected ephemeris error (paper: about 1.5)."""
    sizes, r = ukf_sensitivity(sizes, "earth", tuple(seeds))
    slope, icpt = np.polyfit(sizes, r, 1)
    fit = slope * sizes + icpt
    r2 = 1.0 - np.sum((r - fit) ** 2) / np.sum((r - r.mean()) ** 2)
    size = float(sizes.max())
    dirs = sensitivity_directions()
    by_dir = ukf_sensitivity_by_direction(dirs, size=size, seeds=tuple(seeds))
    # the steepest direction over the whole sphere (the slopes' quadratic form), then run
    u_top, predicted = steepest_direction(by_dir, dirs, float(r[0]), size)
    by_dir["steepest (searched)"] = ukf_sensitivity_by_direction(
        {"top": u_top}, size=size, seeds=tuple(seeds))["top"]
    lo, hi = min(by_dir.values()), max(by_dir.values())
    row = check_true("UKF error per metre of ephemeris error", PAPER_SENSITIVITY,
                     f"{slope:.2f} along (1,1,1), {lo:.2f}-{hi:.2f} over directions",
                     lo <= PAPER_SENSITIVITY <= hi,
                     why="the paper's value must lie in the range the error's directions span")
    reach = {("ours, " + k if k == "(1,1,1)" else k): (v, v) for k, v in by_dir.items()}
    decides = "the paper's orbit elements and pulsar table, with its error direction"
    open_ = check_lost(row, "error direction", reach, decides, unit="m per m").verdict == UNDECIDED
    checks = [  # one sentence of the paper (slope and line), counted once
        *part_of("every 100 m of ephemeris error adds about 150 m (Fig. 4)", check_lost(
            row, "error direction", reach, decides, unit="m per m", held=_SLOPE_HELD[open_]),
            check_true("error grows linearly (R^2 of the line)", "linear", float(r2), r2 > 0.98,
                       why="R^2 above 0.98: 'every 100 m adds 150 m' is a straight line")),
        check_measure("slope along (1,1,1), m per m", float(slope),
                      "the direction the chapter's runs use", paper=PAPER_SENSITIVITY),
    ]
    note = (
        "Earth orbit (representative OPS_5111 elements), three pulsars, 500-s steps; constant "
        "ephemeris error injected into the truth; UKF RMSE over 1e5-6e5 s, seeds "
        f"{tuple(seeds)}. Along (1,1,1)/sqrt(3): {slope:.2f} m per m (intercept {icpt:.0f} m) "
        "against the paper's 1.5. The slope is not a property of the filter's Q: it depends on "
        "the direction of the error relative to the pulsars and the orbit. Per direction "
        "(m per m): " + ", ".join(f"{k} {v:.2f}" for k, v in by_dir.items())
        + f" (range {lo:.2f}-{hi:.2f}; the steepest over the whole sphere, from the quadratic "
        f"form the six slopes determine, predicted {predicted:.2f} and run). No direction "
        f"reaches {PAPER_SENSITIVITY:g} with our orbit and pulsars, but the steepest misses it by "
        "less than the directions spread it, and the orbit's orientation and the pulsar table, "
        "held here, move it too. A constant offset along the accurate pulsar "
        "(B0531+21, 109 m) is believed and pulls the orbit; along the noisy pulsars it is "
        "averaged against the dynamics; the paper's error direction and pulsar set (Table 4 "
        "lost) decide its 1.5."
    )
    res = Result("ukf-vs-ephemeris-error", checks, note,
                 {"sizes": sizes, "rmse": r, "slope": float(slope), "intercept": float(icpt),
                  "by_direction": by_dir})
    if out is not None:
        fig, ax = _figure(figsize=(5, 3.5))
        ax.plot(sizes, r, "o-", label="UKF (xnavlab)")
        ax.plot(sizes, PAPER_SENSITIVITY * sizes, "k--", label="paper: 1.5 m per m")
        ax.set_xlabel("ephemeris error (m)")
        ax.set_ylabel("UKF position RMSE (m)")
        ax.legend()
        res.figures.append(save_figure(fig, out, "ukf-vs-ephemeris-error"))
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
    return save_figure(fig, out, name)


def _ranking(rmse):
    return " < ".join(_NAMES[f] for f in sorted(rmse, key=rmse.get))


def _rmse_text(cmp):
    return ", ".join(f"{_NAMES[f]} {v:.0f} m" for f, v in cmp["rmse"].items())


def _imp_text(cmp):
    return ", ".join(f"{_NAMES[f]} {v:.1f} %" for f, v in cmp["improvement"].items())


_SETTINGS = (
    "Filters: UKF; ASUKF with a 1-m-per-step bias random walk; TDUKF with white differenced "
    "noise 2R (the paper's competitor, Wang et al. 2014); RKF with the residual bias bound "
    "(running innovation mean, lam = 0.02) and the paper's eps. Initial error 1 km and "
    "1 m/s per axis, process noise 1e-4 m/s per axis per step (the paper's were lost)."
)


def _pair_order(cmp, a, b):
    """Paired ``RMSE_a - RMSE_b`` (m), its standard error, and the order it decides at 1.96
    standard errors (as :func:`xnavlab.reproduce.check_order`): ``"a"`` (a beats b), ``"b"`` (b
    beats a) or ``"tie"``."""
    d, se = paired_difference(cmp, a, b)
    return d, se, "a" if d + 1.96 * se < 0.0 else "b" if d - 1.96 * se > 0.0 else "tie"


def _asukf_last_text(cmp):
    """The paper's own argument against the ASUKF, when our means rank it last of the three."""
    r = cmp["rmse"]
    if r["asukf"] > max(r["tdukf"], r["rkf"]):
        return ("The ASUKF is last of the three, the paper's own argument (its random-walk bias "
                "follows a growing error only with a lag). ")
    return ""


def _draw_text(rows, body="earth"):
    """How the paper's single-run improvements are judged, and the verdict of each."""
    verdicts = ", ".join(f"{c.name.split(' improvement')[0]} {c.verdict}" for c in rows)
    # what each row's tolerance measured: the lost settings move it further than our noise, or less
    by = {k: [f"the {c.name.split(' improvement')[0]}'s" for c in rows
              if f"moves our number {k} than our noise" in c.tolerance] for k in ("further", "less")}
    moves = ("move each improvement further than our noise does" if not by["less"] else
             "move each improvement, by less than our noise does" if not by["further"] else
             f"move {' and '.join(by['further'])} improvement further than our noise does, and "
             f"{' and '.join(by['less'])} by less")
    return ("Settings the paper does not give (the direction of the error, which sets the UKF "
            "error every improvement is divided by, see ukf-vs-ephemeris-error; the process noise "
            f"({', '.join(f'{q:g}' for q in LOST_Q_V)} m/s per step against our 1e-4) and the initial "
            "error (100 m and 10 km against our 1 km); the ASUKF's bias random walk; the RKF's "
            "residual-average weight lam"
            + ("; the size of the orbit, a = " + " and ".join(f"{a / 1e3:,.0f}" for a in LOST_MARS_A)
               + " km against our 4,196 km, its other elements ours" if body == "mars" else
               "; the orientation of the orbit, node and anomaly at the epoch "
               + ", ".join(f"{n:g}/{v:g}" for n, v in LOST_EARTH_ORIENTATION)
               + " deg against our 0/0 deg, its size, inclination and shape held as the paper's "
                 "satellite, OPS 5111, a GPS Block I, places them")
            + f") {moves}; each improvement is judged over them (the rule is the same either way), "
            f"one varied at a time ({len(_LOST_SEEDS)} seeds each, "
            f"paired with ours): {verdicts}. "
            + "The pulsars are the three whose ranging accuracies give the paper's R. ")


def _pair_text(cmp, a, b):
    """One sentence on the paired order of ``a`` and ``b`` (decided or not)."""
    d, se, order = _pair_order(cmp, a, b)
    if order == "a":
        return f"{_NAMES[a]} beats {_NAMES[b]} ({d:+.0f} +- {se:.0f} m, decided)"
    if order == "b":
        return f"{_NAMES[b]} beats {_NAMES[a]} ({-d:+.0f} +- {se:.0f} m, decided: the paper's order reversed)"
    return f"{_NAMES[a]} and {_NAMES[b]} tie ({d:+.0f} +- {se:.0f} m, within 1.96 standard errors)"


@register("rkf-earth", title="UKF, ASUKF, TDUKF and RKF on the Earth orbit, growing ephemeris error",
          source=f"{_SOURCE}, Fig. 6 and Table 2", chapter=_CHAPTER)
def rkf_earth(out=None, seeds=tuple(range(32)), constant_seeds=(0, 1, 2, 3), profile="linear",
              max_workers=1):
    """Improvement over the UKF on the Earth orbit (paper 61.7 / 64.1 / 67.4 %).

    The error grows from zero to the real DE421 - DE405 Earth error size (1.49 km) over
    the run, along ``(1, 1, 1) / sqrt(3)``; the same error held constant is run beside it.
    32 seeds by default: the filters' RMSE varies from seed to seed by more than some of the
    differences the paper ranks, and the paired differences need that many to be decided;
    each filter runs them as one batch (:func:`xnavlab.robust.run_filters`); ``max_workers``
    spreads groups of seeds over processes (the numbers do not depend on it; on two shared
    cores one process is faster).
    """
    size = earth_error_size()
    cmp = robust.compare_filters("earth", error="growing", size=size, seeds=tuple(seeds), profile=profile,
                                 max_workers=max_workers)
    const = robust.compare_filters("earth", error="constant", size=size, seeds=tuple(constant_seeds))
    paper = PAPER_IMPROVEMENT["earth"]
    lost = lost_settings("earth", size, cmp, seeds=tuple(seeds)[:len(_LOST_SEEDS)], profile=profile)
    checks = _improvement_checks(cmp, paper, lost, "earth") + _order_checks(cmp, lost)
    checks.append(check_measure("ranking with the error held constant", _ranking(const["rmse"]),
                                "shows the paper's claim needs the growth",
                                paper="(growing error only)"))
    note = (
        f"Ephemeris error growing linearly from 0 to {size:.0f} m (the real DE421 - DE405 Earth "
        "error at 1997-01-01) over the run, along (1,1,1)/sqrt(3), ending at the end of the RMSE "
        f"window (1e5-6e5 s); mean of {len(seeds)} seeds: " + _rmse_text(cmp)
        + f"; improvements of the mean RMSE {_imp_text(cmp)} (paper 61.7 / 64.1 / 67.4 %; the rows "
        "judge each run's own). Ranking of the means: "
        f"{_ranking(cmp['rmse'])} (paper RKF < TDUKF < ASUKF < UKF). Paired over the same seeds: "
        f"{_pair_text(cmp, 'rkf', 'asukf')}; {_pair_text(cmp, 'tdukf', 'asukf')}; "
        f"{_pair_text(cmp, 'rkf', 'tdukf')}. " + _asukf_last_text(cmp)
        + "Whether the RKF beats the white TDUKF depends on the memory of the residual average "
        "(lam): rkf-residual-memory sweeps it. " + _draw_text(checks[:3]) + "The same "
        f"error held constant ({len(constant_seeds)} seeds): " + _rmse_text(const)
        + f", ranking {_ranking(const['rmse'])}: a constant bias is learnt by the ASUKF once and "
        "for all, and the residual bound of the RKF cannot see a bias the filter absorbed in "
        "its first steps (it then de-weights combinations whose residuals the absorbed bias "
        "keeps biased, and can end worse than the UKF); the paper's claim needs the growth. " + _SETTINGS
        + " Orbit: representative GPS Block I elements for OPS_5111 (a = 26,560 km, e = 0.01, "
        "i = 63 deg); epoch 1997-01-01; eps = 1000."
    )
    data = dict(cmp)
    data["constant"] = const
    data["size"] = size
    data["lost"] = lost
    res = Result("rkf-earth", checks, note, data, main=RANKING_CLAIM)
    if out is not None:
        res.figures.append(_figure_runs(cmp, "earth", out, "rkf-earth"))
    return res


#: Memories of the RKF's residual average swept by ``rkf-residual-memory`` (1: current residual only).
RKF_LAMBDAS = (0.01, 0.02, 0.05, 1.0)


def rkf_memory_sweep(lams=RKF_LAMBDAS, seeds=tuple(range(32)), body="earth", size=None):
    """RKF against the white TDUKF for each weight ``lam`` of the residual average.

    Parameters
    ----------
    lams : sequence of float
        Weights in (0, 1] (``1``: the current residual only, the paper's words read literally).
    seeds : sequence of int
    body : {"earth", "mars"}
    size : float, optional
        Final size of the growing error, m (default: the real Earth error, or the paper's
        5e4 m on Mars).

    Returns
    -------
    dict
        ``lams`` (k,), ``rkf`` (k,) mean RMSE m, ``diff`` and ``se`` (k,) the paired
        ``RMSE_RKF - RMSE_TDUKF`` and its standard error, m, ``tdukf`` and ``ukf`` mean RMSE, m.

    Examples
    --------
    >>> out = rkf_memory_sweep((0.02, 1.0), seeds=(0, 1), body="mars", size=5000.0)
    >>> out["diff"].shape
    (2,)
    """
    lams = tuple(check_real("lams", v, 0.0, 1.0, lo_open=True) for v in lams)
    if not lams:
        raise ValueError("lams must list at least one weight in (0, 1]")
    if size is None:
        size = earth_error_size() if body == "earth" else PAPER_MARS_ERROR_M
    seeds = check_seeds("seeds", seeds)
    settings = {"ours": ({}, {}, ("ukf", "tdukf"))}
    settings.update({f"lam {i}": ({}, {"lam": lam}, ("rkf",)) for i, lam in enumerate(lams)})
    got = robust.compare_settings(body, settings, seeds, error="growing", size=float(size))  # one batch each
    td = np.asarray(got["ours"]["tdukf"])
    rkf, diff, se = [], [], []
    for i in range(len(lams)):
        runs = np.asarray(got[f"lam {i}"]["rkf"])
        d, s = paired_difference({"rmse_runs": {"a": runs, "b": td}}, "a", "b")
        rkf.append(runs.mean())
        diff.append(d)
        se.append(s)
    return {"lams": np.array(lams), "rkf": np.array(rkf), "diff": np.array(diff), "se": np.array(se),
            "tdukf": float(td.mean()), "ukf": float(np.mean(got["ours"]["ukf"])), "size": float(size)}


@register("rkf-residual-memory", title="The RKF's residual average: its memory against the TDUKF (Earth)",
          source=f"{_SOURCE}, eqs. (8)-(26) (lost) and Table 2", chapter=_CHAPTER)
def rkf_residual_memory(out=None, lams=RKF_LAMBDAS, seeds=tuple(range(16))):
    """Does any memory of the residual bias bound put the RKF ahead of the TDUKF (paper: yes)?"""
    sw = rkf_memory_sweep(lams, seeds)
    lams = sw["lams"]
    best = int(np.argmin(sw["diff"]))
    one = np.flatnonzero(lams == 1.0)
    decided = sw["diff"] + 2.0 * sw["se"] < 0.0
    checks = [  # an exploration of our reconstruction, not a claim of the paper
        check_measure("RKF - TDUKF at the best memory (paired RMSE difference, m)",
                      f"lam {lams[best]:g}: {sw['diff'][best]:+.0f} +- {sw['se'][best]:.0f}",
                      ("below zero by two standard errors at this lam" if decided[best] else
                       "below zero by two standard errors at no lam")
                      + "; the paper gives no lam (its RKF < TDUKF is judged in rkf-earth)"),
        check_measure("RKF RMSE from the smallest to the largest lam (m)",
                      f"{sw['rkf'][0]:.0f} -> {sw['rkf'][-1]:.0f}",
                      "the weight of the current residual in the bias bound"),
    ]
    verdict = (f"lam {', '.join(f'{v:g}' for v in lams[decided])} make that order decided"
               if decided.any() else "no memory of the residual average makes that order decided")
    rows = ", ".join(f"lam {v:g}: RKF {r:.0f} m ({d:+.0f} +- {e:.0f})"
                     for v, r, d, e in zip(lams, sw["rkf"], sw["diff"], sw["se"], strict=True))
    lit = (f" The paper's words read literally (the current residual only, lam = 1) give "
           f"{sw['rkf'][one[0]]:.0f} m, an improvement of only "
           f"{robust.improvement(sw['rkf'][one[0]], sw['ukf']):.0f} %: one residual is mostly noise, "
           "so the bound de-weights the pulsars at random; a running average is the reconstruction "
           "that works, and lam = 0.02 (memory of about 50 steps, 7 h) the default.") if one.size else ""
    note = (
        f"Earth orbit, error growing from 0 to {sw['size']:.0f} m, {len(seeds)} seeds; TDUKF (white 2R) "
        f"{sw['tdukf']:.0f} m, UKF {sw['ukf']:.0f} m. RKF with the residual bias bound for each weight "
        f"lam of the residual average, paired difference RKF - TDUKF: {rows}. The paper ranks the RKF "
        f"first; in our reconstruction of its lost equations (8)-(26) {verdict} (two standard "
        f"errors); the RKF is best at lam {lams[best]:g}." + lit
    )
    res = Result("rkf-residual-memory", checks, note, sw)
    if out is not None:
        fig, ax = _figure(figsize=(5, 3.5))
        ax.errorbar(lams, sw["diff"], yerr=2.0 * sw["se"], fmt="o-", capsize=3)
        ax.axhline(0.0, color="k", lw=1)
        ax.set_xscale("log")
        ax.set_xlabel("weight of the current residual, lam")
        ax.set_ylabel("RMSE RKF - TDUKF (m), +- 2 SE")
        res.figures.append(save_figure(fig, out, "rkf-residual-memory"))
    return res


@register("rkf-mars", title="UKF, ASUKF, TDUKF and RKF on the Mars orbit, growing ephemeris error",
          source=f"{_SOURCE}, Fig. 7 and Table 2", chapter=_CHAPTER)
def rkf_mars(out=None, seeds=tuple(range(32)), constant_seeds=(0, 1), size=PAPER_MARS_ERROR_M,
             profile="linear", max_workers=1):
    """Improvement over the UKF on the Mars orbit (paper 96.6 / 97.5 / 98.3 %).

    The error grows from zero to the paper's 5e4 m over the run (the real DE405 Mars
    error is about 1.2 km in 1997); the same error held constant is run beside it.
    """
    cmp = robust.compare_filters("mars", error="growing", size=float(size), seeds=tuple(seeds),
                                 profile=profile, max_workers=max_workers)
    const = robust.compare_filters("mars", error="constant", size=float(size), seeds=tuple(constant_seeds))
    imp = cmp["improvement"]
    paper = PAPER_IMPROVEMENT["mars"]
    step = float(size) * 500.0 / robust.WINDOWS["mars"][1]  # mean growth per 500-s step, m
    lost = lost_settings("mars", float(size), cmp, seeds=tuple(seeds)[:len(_LOST_SEEDS)], profile=profile)
    checks = _improvement_checks(cmp, paper, lost, "mars") + _order_checks(cmp, lost)
    checks.append(check_measure("ranking with the error held constant", _ranking(const["rmse"]),
                                "shows the paper's claim needs the growth",
                                paper="(growing error only)"))
    note = (
        f"Ephemeris error growing linearly from 0 to {size:.0f} m (the paper's Mars figure) over "
        f"the run, along (1,1,1)/sqrt(3); RMSE over 5e4-2.5e5 s, mean of {len(seeds)} seeds: "
        + _rmse_text(cmp) + f"; improvements of the mean RMSE {_imp_text(cmp)} (paper 96.6 / 97.5 / "
        "98.3 %; the rows judge each run's own); "
        f"ranking {_ranking(cmp['rmse'])} (paper: RKF < TDUKF < ASUKF). Paired: "
        f"{_pair_text(cmp, 'rkf', 'tdukf')}. "
        + (f"Why the RKF trails the TDUKF here, measured: the error grows by {step:.0f} m per "
           f"500-s step on average, which the differencing of the TDUKF reduces to a {step:.0f}-m "
           "change, below its noise (sqrt(2) x 109-340 m), while the RKF's residual mean "
           "(lam = 0.02, a memory of about 50 steps) lags the growth and lets part of it into "
           "the state. " if _pair_order(cmp, "rkf", "tdukf")[2] == "b" else "")
        + f"The ASUKF's 1-m-per-step bias random walk follows a growth of {step:.0f} m per step "
        f"only with a lag (its improvement {imp['asukf']:.1f} % against the paper's "
        f"{paper['asukf']:g} %). " + _draw_text(checks[:3], "mars") + "With the error held "
        f"constant ({len(constant_seeds)} seeds): " + _rmse_text(const)
        + f", ranking {_ranking(const['rmse'])}. " + _SETTINGS + " Mars orbit: the main "
        "paper's initial state (a = 4196 km, e = 0.09, i = 75 deg), since Wei et al. (2013)'s "
        "elements were not recoverable (its size is varied among the lost settings); eps = 100."
    )
    data = dict(cmp)
    data["constant"] = const
    data["size"] = float(size)
    data["lost"] = lost
    res = Result("rkf-mars", checks, note, data, main=RANKING_CLAIM)
    if out is not None:
        res.figures.append(_figure_runs(cmp, "mars", out, "rkf-mars"))
    return res


#: 'Small' in Fig. 8 read as an improvement over the UKF of at least this much, % (below 10 % of its RMSE).
_SMALL_PCT = 90.0


def _small_check(cmp, f, lost, body):
    """Whether filter ``f`` stays small (Fig. 8), judged over the lost settings: per single run,
    how many points its improvement falls short of :data:`_SMALL_PCT` (0: small; the paper's
    curve is small, 0), its 95 % range at ours and shifted by each lost setting."""
    runs = _improvement_runs(cmp, f)
    row = check_draw(f"{_NAMES[f]} stays small at the largest error (points its improvement is below "
                     f"{_SMALL_PCT:g} %)", 0.0, np.maximum(0.0, _SMALL_PCT - runs),
                     why=f"'small' read as below {100 - _SMALL_PCT:g} % of the UKF's RMSE, 0 when met")
    reach = {k: (max(0.0, _SMALL_PCT - hi), max(0.0, _SMALL_PCT - lo))
             for k, (lo, hi) in _lost_reach(runs, lost, f).items()}
    what, decides, held = _lost_what(f, body)
    judged = check_lost(row, what, reach, decides, unit="points", held=held)
    # the paper gives words, not a number: its column says them (our 0 is in the tolerance)
    return dataclasses.replace(judged, paper="stays small")


def _best_check(sizes, cmps, lost, n_seeds):
    """'RKF best of the three at every size' (every non-zero size): each paired order, and at the
    largest size each order again over the lost settings (one that turns the order's mean leaves
    it undecided: REPRODUCED or NOT REPRODUCED only at every plausible value)."""
    big = max(sizes)
    found, against, turned = [], [], []
    for s in (v for v in sizes if v > 0):
        for o in ("asukf", "tdukf"):
            d = np.asarray(cmps[s]["rmse_runs"]["rkf"]) - np.asarray(cmps[s]["rmse_runs"][o])
            verdict = check_order(f"RKF better than {_NAMES[o]} at {s:g} m", f"RKF < {_NAMES[o]}", d).verdict
            pair = f"{_NAMES[o]} at {s:g} m"
            if s == big and verdict != UNDECIDED:
                means = lost[f"rkf_minus_{o}"]  # RKF - other, m, per lost setting
                flip = [k for k, v in means.items() if (v < 0) != (verdict == REPRODUCED)]
                if flip:
                    turned.append(f"{pair}: {', '.join(flip)}")
                    verdict = UNDECIDED
                elif verdict == NOT_REPRODUCED:
                    lo, hi = min(means.values()), max(means.values())
                    pair += f" and at every lost setting run (RKF - {_NAMES[o]} {lo:+.0f} to {hi:+.0f} m)"
            found.append(verdict)
            if verdict == NOT_REPRODUCED:
                against.append(pair)
    verdict = (REPRODUCED if all(v == REPRODUCED for v in found)
               else NOT_REPRODUCED if NOT_REPRODUCED in found else UNDECIDED)
    reading = "; ".join(x for x in (
        f"the RKF trails {'; '.join(against)}" if against else "",
        f"a lost setting turns the order of {'; '.join(turned)}" if turned else "",
        f"{found.count(REPRODUCED)} of {len(found)} pairs decided in the paper's order") if x)
    ours = f"{found.count(REPRODUCED)} of {len(found)} pairs"
    return Check("RKF best of the three at every size", "yes", ours,
                 f"every paired order (RKF against the ASUKF and the TDUKF, {n_seeds} seeds, each non-zero "
                 "size) decided in the paper's order, at the largest size at every lost setting run too "
                 f"({len(_LOST_SEEDS)} seeds each, paired with ours; on Mars the size of the orbit among "
                 "them; the order's mechanism, the RKF's residual average lagging a growing error that "
                 "the TDUKF's differencing removes, does not depend on the orbit)", verdict, reading)


@register("rkf-sweep", title="The four filters across ephemeris-error sizes",
          source=f"{_SOURCE}, Fig. 8", chapter=_CHAPTER)
def rkf_sweep(out=None, sizes=(0.0, 1000.0, 1e4, 5e4), body="mars", seeds=tuple(range(32)), profile="linear",
              max_workers=1):
    """RMSE of each filter against the final size of a growing injected ephemeris error.

    The paper's curves are judged at the largest size over the settings it lost
    (:func:`lost_settings`: at the default 5e4 m on Mars, the runs of ``rkf-mars``), and the
    RKF's order at every non-zero size (32 seeds each: at least 32 single runs)."""
    sizes = tuple(float(s) for s in sizes)
    seeds = check_seeds("seeds", seeds)
    table = {f: [] for f in robust.FILTERS}
    cmps = {}
    for s in sizes:
        cmps[s] = robust.compare_filters(body, error="growing", size=s, seeds=seeds, profile=profile,
                                         max_workers=max_workers)
        for f in robust.FILTERS:
            table[f].append(cmps[s]["rmse"][f])
    table = {f: np.array(v) for f, v in table.items()}
    big = int(np.argmax(sizes))
    lost = lost_settings(body, sizes[big], cmps[sizes[big]], seeds=seeds[:len(_LOST_SEEDS)], profile=profile)
    ukf_growth = table["ukf"][big] - table["ukf"][0]
    checks = [
        check_true("UKF error grows with the ephemeris error (m, largest minus none)",
                   "rises sharply", float(ukf_growth), ukf_growth > 0.25 * (sizes[big] - sizes[0]),
                   why="'sharply' read as more than a quarter of the added error"),
        *part_of("TDUKF and RKF stay small at the largest error",
                 *(_small_check(cmps[sizes[big]], f, lost, body) for f in ("tdukf", "rkf"))),
        _small_check(cmps[sizes[big]], "asukf", lost, body),
    ]
    if len(seeds) >= 2:
        checks.append(_best_check(sizes, cmps, lost, len(seeds)))
    verdicts = {c.name.split(" stays")[0]: c.verdict for c in checks if " stays small" in c.name}
    note = (
        f"{body.capitalize()} orbit, error growing linearly from zero to the size shown over the run, "
        f"mean of {len(seeds)} seeds per size. RMSE (m) at sizes {sizes}: "
        + "; ".join(f"{_NAMES[f]} " + ", ".join(f"{v:.0f}" for v in table[f]) for f in robust.FILTERS)
        + ". The UKF error rises by " + f"{ukf_growth:.0f} m from the smallest to the largest "
        f"error; at the largest the TDUKF and RKF end at {table['tdukf'][big]:.0f} and "
        f"{table['rkf'][big]:.0f} m and the ASUKF at {table['asukf'][big]:.0f} m"
        + (" (its random-walk bias model follows a fast growth only with a lag, the paper's own "
           "argument against it)" if table["asukf"][big] >= 0.1 * table["ukf"][big] else "")
        + f". 'Small' is read as below {100 - _SMALL_PCT:g} % of the UKF's RMSE, judged per single run at "
        "the largest size over the settings the paper lost (error direction, process noise, initial "
        "error, the ASUKF's walk and the RKF's lam" + (", the size of the orbit" if body == "mars" else "")
        + ", one at a time, "
        f"{len(_LOST_SEEDS)} seeds each): " + ", ".join(f"{k} {v}" for k, v in verdicts.items())
        + ". The RKF's order is judged at every non-zero size (an error of zero has nothing to be "
        "robust to) and, at the largest, over the same lost settings. The Mars orbit is used because "
        "its runs are 2.4 times shorter; at 5e4 m they are the runs of rkf-mars."
    )
    reach = {f: _lost_reach(_improvement_runs(cmps[sizes[big]], f), lost, f)  # % at each lost setting
             for f in ("asukf", "tdukf", "rkf")}
    res = Result("rkf-sweep", checks, note, {"sizes": np.array(sizes), "rmse": table, "body": body,
                                              "lost": lost, "improvement_reach": reach})
    if out is not None:
        fig, ax = _figure(figsize=(5, 3.5))
        for f in robust.FILTERS:
            ax.plot(sizes, table[f], "o-", label=_NAMES[f])
        ax.set_yscale("log")
        ax.set_xlabel("final ephemeris error (m)")
        ax.set_ylabel("position RMSE (m)")
        ax.legend()
        res.figures.append(save_figure(fig, out, "rkf-sweep"))
    return res
