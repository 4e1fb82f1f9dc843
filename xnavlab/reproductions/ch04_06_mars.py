"""Main paper (Fan et al. 2016), Fig. 2: the fault-free federated Mars navigation run.

IDs: ``mars-sensors`` (section 4.1: the sensor accuracies, chapter 4, with the sizes of the
idealisations the paper's sensor models make), ``mars-subsystems`` (sections 0 and 3: each
subsystem alone and the fused result, chapter 5), ``mars-optics`` (chapter 5: the fused filter
with the optical sensors as instruments, :mod:`xnavlab.mars.models.optics`, beside the paper's
idealised ones), ``mars-nofault`` (Fig. 2, chapter 6) and ``mars-xnav-crlb`` (chapter 6: the
fused accuracy with XNAV noise at the Cramer-Rao bound beside the paper's ranging accuracies).
``mars-optics`` and ``mars-xnav-crlb`` judge no claim of the paper: they measure what the
paper's idealisations are worth (checks of ours, cached with the registry's results).

``mars-nofault``: the paper's 30-day scenario (section 4.1) with the three
subsystems (XNAV, UV sensor, CNS), one EKF each, fused by the federated filter in
reset mode, no faults and no detector. The paper reports a position error of
28.835 m and a velocity error of 0.02149 m/s without saying how the numbers were
formed.

Our metric: the RMS over time of the norm of the fused position (velocity) error,
from day 1 to day 30 (:meth:`xnavlab.mars.navigation.scenarios.MarsRun.metrics`). The RMS of the norm
summarises a curve like Fig. 2 in one number, weighs every axis and epoch equally and
leaves out the 5-km initial transient, which has died out well before day 1.
Acceptance: the paper's numbers come from one run, so each is judged as one draw from our
single runs over 32 noise seeds (:func:`xnavlab.verdicts.check_draw`, the runs of
:func:`xnavlab.mars.navigation.headline.headline_numbers`): reproduced when it falls inside their 95 %
range. The paper gives neither its process noise nor its metric; ours are stated in the note.
"""

from __future__ import annotations

import math

import numpy as np

from xnavlab.core.constants import DAY, C
from xnavlab.core.filters import chi2_bounds, judge_series
from xnavlab.core.validate import check_int, check_seed, check_seeds
from xnavlab.mars.models import dynamics, optics, sensors, stars
from xnavlab.mars.navigation import scenarios
from xnavlab.mars.timing import pulsars
from xnavlab.reproduce import (
    Check,
    Result,
    check_draw,
    check_lost,
    check_measure,
    check_order,
    check_sanity,
    part_of,
    register,
    save_figure,
)
from xnavlab.reproduce import figure as _figure

__all__ = ["PAPER_POSITION_ERROR_M", "PAPER_VELOCITY_ERROR_MPS", "PAPER_SENSORS",
           "OPTICS_CASES", "mars_sensors", "mars_subsystems", "mars_optics", "mars_nofault",
           "mars_xnav_crlb", "SUBSYSTEMS_CLAIM", "SUBSYSTEM_SEEDS", "LOST_Q_ACC", "q_shifts"]

#: The process noises the paper's fault-free numbers are judged over, m^2/s^3 (ours 1e-11 among
#: them): chapter 5's sweep without q = 0 (there the filter stops listening, mean NEES ~1.7e3).
LOST_Q_ACC = (1e-12, 1e-11, 1e-10, 1e-9)
#: Seeds each process noise is run with, paired with ours (q = 1e-11) on the same seeds.
_Q_SEEDS = (0, 1, 2, 3)


def q_shifts(q_values=LOST_Q_ACC, seeds=_Q_SEEDS, days=30.0, settle_days=1.0):
    """How far the process noise moves the fault-free fused errors (paired, 30 days).

    Returns
    -------
    dict
        q (m^2/s^3) -> (mean paired change of the position RMS, m; of the velocity RMS, m/s)
        against q = 1e-11 on the same seeds.
    """
    def one(q):
        return np.array([[m["position_error_m"], m["velocity_error_mps"]] for m in (
            scenarios.run(scenarios.MarsScenario(days=days, seed=s, q_acc=q)).metrics(
                settle_days=settle_days) for s in seeds)])
    ours = one(1e-11)
    return {float(q): tuple(float(x) for x in np.mean(one(q) - ours, axis=0)) if q != 1e-11
            else (0.0, 0.0) for q in q_values}

#: Paper section 4.1: sensor accuracies (1 sigma).
PAPER_SENSORS = {
    "UV range (m)": 5000.0,
    "UV direction per axis (deg)": 0.1,
    "star sensor per axis (arcsec)": 3.0,
    "horizon sensor per axis (deg)": 0.05,
    "B0531+21 ranging (m)": 109.0,
    "B1937+21 ranging (m)": 344.0,
    "B1957+20 ranging (m)": 1866.0,
    "B1821-24 ranging (m)": 325.0,
}

#: Paper section 4.2, Fig. 2: fault-free position error, m.
PAPER_POSITION_ERROR_M = 28.835
# What a mean of a few seeds shows in the paper column: the paper's 28.835 m is one run,
# judged among 32 of ours in mars-nofault, not set beside a mean
PAPER_ONE_RUN = "one run: judged in mars-nofault"
#: Paper section 4.2, Fig. 2: fault-free velocity error, m/s.
PAPER_VELOCITY_ERROR_MPS = 0.02149

#: The optical sensors of ``mars-optics``: the paper's idealised ones, each instrument option of
#: :mod:`xnavlab.mars.models.optics` alone, and all three (``MarsScenario`` fields).
OPTICS_CASES = {
    "paper": {},
    "radius range": {"uv_range_model": "radius"},
    "oblate limb": {"limb": "oblate"},
    "correlated horizon": {"horizon_tau_s": optics.HORIZON_TAU_S},
    "all three": {"uv_range_model": "radius", "limb": "oblate",
                  "horizon_tau_s": optics.HORIZON_TAU_S},
}


def _every(t_days, step_days):
    """Indices of the records ``step_days`` apart (for the curves a chapter plots)."""
    spacing = float(t_days[1] - t_days[0]) if t_days.size > 1 else step_days
    return np.arange(0, t_days.size, max(1, round(step_days / spacing)))



@register("mars-sensors", title="simulated sensor noise at the paper's accuracies",
          source="Fan et al. 2016, section 4.1", chapter="04_optical_geometry")
def mars_sensors(out=None, n=40_000, seed=0):
    """Monte Carlo of the three sensor models at the paper's initial state.

    ``n`` draws of each sensor (the XNAV rows take the first 2,000), in ``[2000, 10**6]``
    (10**6 states are 48 MB); ``seed`` in ``[0, SEED_MAX]``.
    """
    n = check_int("n", n, 2000, 10**6)
    rng = np.random.default_rng(check_seed("seed", seed))
    x = dynamics.MARS_STATE0
    states = np.tile(x, (n, 1))
    uv, cns = sensors.UVSensor(), sensors.CNSSensor()
    zu = uv.simulate(states, rng=rng)
    e1, e2 = sensors.tangent_basis(uv.h(x)[1:])
    du = zu[:, 1:] - uv.h(x)[1:]
    dir_deg = math.degrees(0.5 * (np.std(du @ e1) + np.std(du @ e2)))
    zc = cns.simulate(states, rng=rng)
    ang = zc - cns.h(x)
    xs = sensors.XNAVSensor()
    t = np.full(n, dynamics.MARS_T0)
    zx = xs.simulate(t[:2000], states[:2000], rng=rng) - xs.h(x, dynamics.MARS_T0)
    # a sample sigma's own relative scatter is 1/sqrt(2 n) (0.35 % at the 40,000 draws of the
    # default): 2 %, or five of those scatters where fewer draws are asked for
    tol = max(0.02, 5.0 / math.sqrt(2.0 * n))
    corr = float(np.abs(np.corrcoef(ang.T)[np.triu_indices(3, 1)]).max())

    def same(name, paper, ours, within):
        return check_sanity(name, paper, ours, abs(ours - paper) <= within * paper,
                            f"within {100 * within:.2g} % of the set-up's value")

    checks = [  # our simulators against the set-up of section 4.1: checks, not claims
        same("UV range (m)", 5000.0, float(np.std(zu[:, 0] - uv.h(x)[0])), tol),
        same("UV direction per axis (deg)", 0.1, dir_deg, tol),
        same("starlight angle (deg), horizon 0.05 deg + star 3 arcsec", 0.05,
             math.degrees(float(np.mean(np.std(ang, axis=0)))), tol),
        check_sanity("starlight-angle errors share the horizon error (max |correlation|)",
                     "correlated", corr, corr > 0.1, "> 0.1: R is not diagonal"),
    ]
    for i, p in enumerate(pulsars.PAPER_PULSARS):
        paper = PAPER_SENSORS[f"{p} ranging (m)"]
        checks.append(same(f"{p} ranging (m)", paper, float(xs.sigma[i] * C), 0.01))
        checks.append(same(f"{p} simulated delay scatter x c (m)", paper,
                           float(np.std(zx[:, i]) * C), 0.05))
    checks += _idealisations(rng, n)
    note = (
        f"{n} draws of each sensor at the paper's initial state. Direction noise is applied as a "
        "rotation of the true unit vector by a small random angle (two independent tangent "
        "components, each N(0, sigma^2)); the UV direction check measures those tangent "
        "components. A starlight angle combines the horizon sensor (0.05 deg, common to the three "
        "stars) and the star sensor (3 arcsec, per star): its scatter is "
        "sqrt(0.05^2 + (3/3600)^2) deg = 0.05 deg, and the three angles are correlated through "
        "the shared horizon error, which the filter's R accounts for. XNAV accuracies come from "
        "the Sheikh et al. (2006) formula of chapter 1 (500 s, 1 m^2, 0.005 ph/cm^2/s). "
        "The rows after the pulsars measure what the paper's idealised optical sensors leave out "
        "(xnavlab.mars.models.optics, xnavlab.mars.models.stars.starlight_geometry; the paper gives no such "
        "numbers): the range from Mars's apparent radius, the oblate limb fitted by a sphere and "
        "the stars hidden behind Mars, over the paper's 30-day orbit."
    )
    return Result("mars-sensors", checks, note, {"uv": zu, "cns": ang})


def _idealisations(rng, n):
    """Rows measuring the paper's optical idealisations over its 30-day orbit (checks of ours)."""
    sigma_alpha = optics.sigma_alpha_for(PAPER_SENSORS["UV range (m)"])
    s_rho = optics.radius_range_sigma(optics.orbit_ranges(), sigma_alpha)  # rho cot(alpha) s_a
    x = dynamics.MARS_STATE0
    sim = optics.UVInstrument(PAPER_SENSORS["UV range (m)"],
                              math.radians(PAPER_SENSORS["UV direction per axis (deg)"]), "radius")
    z = sim(np.tile(x, (n, 1)), rng.standard_normal((n, 3)), np.empty((n, 4)))
    want = float(optics.radius_range_sigma(np.linalg.norm(x[:3]), sigma_alpha))
    got = float(np.std(z[:, 0]))
    r = dynamics.truth(dynamics.MARS_T0 + np.arange(0.0, 30.0 * DAY, 60.0))[:, :3]
    bias = optics.limb_bias(r)
    rows = [
        check_sanity("apparent-radius range noise at the initial state (m)", "not tabulated", got,
                     abs(got / want - 1.0) <= 0.02,
                     f"simulated scatter within 2 % of rho cot(alpha) sigma_alpha = {want:.0f} m"),
        check_measure("apparent-radius range noise over the orbit (m)",
                      f"{s_rho.min():.0f} to {s_rho.max():.0f}",
                      f"rho cot(alpha) sigma_alpha, sigma_alpha {math.degrees(sigma_alpha):.4f} "
                      "deg so that the orbit mean is the paper's constant", paper=5000.0),
        check_measure("oblate limb fitted by a sphere: range bias (m)",
                      f"{bias['range_m'].min():+.0f} to {bias['range_m'].max():+.0f}",
                      "the IAU radii of Mars; the paper's limb is a sphere", paper="not modelled (a sphere)"),
        check_measure("oblate limb: centre-direction bias, largest (deg)",
                      float(np.degrees(bias["direction_rad"].max())),
                      f"{np.max(bias['direction_rad'] * np.linalg.norm(r, axis=1)) / 1e3:.1f} km "
                      "across the line of sight", paper="not modelled (a sphere)"),
    ]
    for name, g in stars.starlight_geometry(r, t=dynamics.MARS_T0).items():
        rows.append(check_measure(
            f"{name}: starlight angle over the orbit (deg)",
            f"{g['min_deg']:.1f} to {g['max_deg']:.1f}",
            f"hidden behind Mars {100 * g['occulted_fraction']:.1f} % of the time; the paper "
            "models no occultation", paper="not given"))
    return rows


#: The paper's claim the four "does not grow" rows of mars-subsystems are parts of.
SUBSYSTEMS_CLAIM = "every subsystem's error does not grow (sections 0 and 3)"
#: Seeds of mars-subsystems (each a 3-day run of the four configurations).
SUBSYSTEM_SEEDS = tuple(range(32))


def _growth_row(label, before, last):
    """"Does not grow": the per-seed ratio of the last day's RMS to the day before's.

    Three days can refute the paper's "does not grow" (an error still growing at the end) but
    cannot show it over the paper's 30 days, so a ratio that stays at or below 1.05 is
    UNDECIDED, with the runs that would decide it, never REPRODUCED.
    """
    ratio = np.asarray(last) / np.asarray(before)
    mean = float(ratio.mean())
    half = 1.96 * float(ratio.std(ddof=1)) / math.sqrt(ratio.size)
    lo, hi = mean - half, mean + half
    ours = f"last / day before {mean:.3f} [{lo:.3f}, {hi:.3f}]"
    tol = (f"95 % interval of the mean ratio over {ratio.size} seeds at most 1.05: a growth of "
           "5 % a day would be 4x over the paper's 30 days")
    name = f"{label}: error does not grow (last day vs the day before)"
    if hi <= 1.05:
        return Check(name, "bounded", ours, tol, "UNDECIDED",
                     f"not growing at the end of 3 days (single seeds {ratio.min():.2f}-"
                     f"{ratio.max():.2f}), which is convergence, not the paper's boundedness "
                     f"over 30 days: {ratio.size} runs of 30 days per subsystem (about 10 "
                     "times these runs' cost) would decide it")
    verdict = "NOT REPRODUCED" if lo > 1.0 else "UNDECIDED"
    return Check(name, "bounded", ours, tol, verdict,
                 "the error grows: the interval lies above 1" if lo > 1.0 else
                 "the interval holds 1 and reaches above 1.05")


@register("mars-subsystems", title="each subsystem alone vs the federated fusion (3 days, 32 seeds)",
          source="Fan et al. 2016, sections 0 and 3 (claims)", chapter="05_ekf_ukf")
def mars_subsystems(out=None, days=3.0, seeds=SUBSYSTEM_SEEDS):
    """Each subsystem's EKF alone and the three fused: errors that do not grow, fusion best."""
    labels = ("xnav", "uv", "cns", "xnav+uv+cns")
    per = {k: ([], []) for k in labels}  # (day before, last day) RMS per seed
    runs = {}
    for seed in seeds:
        for subs in (("xnav",), ("uv",), ("cns",), scenarios.SUBSYSTEMS):
            res = scenarios.run(days=days, seed=seed, subsystems=subs)
            label = "+".join(subs)
            d, pe = res.t_days, res.position_error()
            late = d >= days - 1.0
            mid = (d >= days - 2.0) & ~late
            per[label][0].append(float(np.sqrt(np.mean(pe[mid] ** 2))))
            per[label][1].append(float(np.sqrt(np.mean(pe[late] ** 2))))
            if seed == seeds[0]:
                runs[label] = (d, pe)
    rms = {k: (float(np.mean(v[0])), float(np.mean(v[1]))) for k, v in per.items()}
    fused = np.asarray(per["xnav+uv+cns"][1])
    best_single = np.min([per[s][1] for s in ("xnav", "uv", "cns")], axis=0)
    checks = part_of(SUBSYSTEMS_CLAIM, *(_growth_row(s, *per[s]) for s in labels))
    checks.append(check_order("fused better than the best subsystem alone (last-day RMS, m)",
                              "higher accuracy", fused - best_single, unit="m",
                              why="per seed, the fused run against its best single subsystem"))
    note = (
        "The paper argues (sections 0 and 3) that XNAV, UV and CNS navigation all have errors "
        "that do not grow with time and that federated fusion gives higher accuracy than each; "
        "it shows no figure for the single subsystems. Each runs here as its own EKF (the "
        f"federated code with one local, sharing factor 1) for {days:g} days, {len(seeds)} seeds; "
        "mean over the seeds of the RMS of |position error| over the last day (the day before): "
        + ", ".join(f"{k} {v[1]:.1f} m ({v[0]:.1f} m)" for k, v in rms.items())
        + ". Three days show that each error has converged and is still settling, not that it "
        "stays bounded over the paper's 30 days (the fused 30-day runs are mars-nofault's)."
    )
    return Result("mars-subsystems", checks, note, {"runs": runs, "rms": rms, "per_seed": per})


def _fused_runs(days, seeds, settle_days, **fields):
    """Fused 30-day runs of the paper's scenario with ``fields`` changed, one per seed.

    Returns the per-seed RMS errors after ``settle_days`` and time-mean NEES, the run-averaged
    NEES at every record and the first seed's |position error| (both every ~10 minutes).
    """
    pos, vel, nees_mean, nees = [], [], [], None
    for seed in seeds:
        res = scenarios.run(scenarios.MarsScenario(days=days, seed=seed, **fields))
        m = res.metrics(settle_days)
        e = res.nees()
        after = res.t_days >= settle_days
        pos.append(m["position_error_m"])
        vel.append(m["velocity_error_mps"])
        nees_mean.append(float(np.mean(e[after])))
        if nees is None:
            first, t_days = res.position_error(), res.t_days
        nees = e if nees is None else nees + e
    k = _every(t_days, 10.0 / 1440.0)
    return {"position_m": pos, "velocity_mps": vel, "nees_mean": nees_mean,
            "t_days": t_days[k], "position_error": first[k], "nees": (nees / len(seeds))[k],
            "nees_all": nees / len(seeds), "t_all": t_days}


@register("mars-optics", title="the fused filter with the optical sensors as instruments (30 days)",
          source="Fan et al. 2016, section 4.1 (the idealised sensors); xnavlab.mars.models.optics",
          chapter="05_ekf_ukf")
def mars_optics(out=None, days=30.0, seeds=(0, 1), settle_days=1.0):
    """The paper's 30-day fused run with each optical instrument model, and all three.

    The truth's measurements come from the instrument (:mod:`xnavlab.mars.models.optics`); the
    filter keeps the paper's white-noise ``R``. Per case of :data:`OPTICS_CASES`: the fused
    position error (RMS after ``settle_days``, mean over ``seeds``) and the fused NEES judged
    against the chi-square band of an average of ``len(seeds)`` runs.
    """
    seeds = check_seeds("seeds", seeds)
    lo, hi = chi2_bounds(6, len(seeds))
    checks, data = [], {"cases": {}, "nees_band": (lo, hi), "seeds": seeds}
    for case, fields in OPTICS_CASES.items():
        d = _fused_runs(days, seeds, settle_days, **fields)
        after = d.pop("t_all") >= settle_days
        judged = judge_series(d.pop("nees_all")[after], lo, hi)
        d.update(judged=judged, nees_avg=float(np.mean(d["nees_mean"])),
                 position_mean_m=float(np.mean(d["position_m"])))
        data["cases"][case] = d
        per_seed = ", ".join(f"{v:.1f}" for v in d["position_m"])
        checks += [
            check_measure(f"{case}: fused position error, RMS after day {settle_days:g} (m)",
                          d["position_mean_m"], f"mean of seeds {seeds}: {per_seed} m",
                          paper=PAPER_ONE_RUN if case == "paper" else "not given"),
            check_measure(f"{case}: fused NEES, mean after day {settle_days:g}", d["nees_avg"],
                          f"6 states; the run-averaged NEES is {judged['verdict']} against the "
                          f"95 % band [{lo:.2f}, {hi:.2f}] of {len(seeds)} runs at "
                          f"{100 * judged['inside']:.0f} % of the records"),
        ]
    paper, every = data["cases"]["paper"], data["cases"]["all three"]
    note = (
        f"The paper's {days:g}-day scenario (section 4.1) with the optical measurements made as "
        "instruments make them (xnavlab.mars.models.optics) while every filter keeps the paper's "
        "white-noise R: the UV range from Mars's apparent radius (noise rho cot(alpha) "
        "sigma_alpha, the paper's 5 km on the orbit's mean), the limb of an oblate Mars fitted "
        "by a sphere (a range and direction bias that follows the geometry), and horizon errors "
        f"correlated over {optics.HORIZON_TAU_S:g} s (first-order Gauss-Markov, the paper's "
        "0.05 deg). Each alone and all three; "
        f"seeds {seeds}, RMS after day {settle_days:g}. The paper's sensors give "
        f"{paper['position_mean_m']:.1f} m (mean NEES {paper['nees_avg']:.2g}); all three "
        f"instruments {every['position_mean_m']:.0f} m (mean NEES {every['nees_avg']:.2g}). "
        "The paper judges no such case: these rows measure what its idealisations are worth."
    )
    return Result("mars-optics", checks, note, data)


@register("mars-nofault", title="fault-free 30-day federated XNAV/UV/CNS run around Mars",
          source="Fan et al. 2016, section 4.2 and Fig. 2", chapter="06_federated")
def mars_nofault(out=None, days=30.0, seed=0, settle_days=1.0, mode="reset"):
    """Run the paper's scenario and compare the error metrics with Fig. 2."""
    sc = scenarios.MarsScenario(days=days, seed=seed, mode=mode)
    res = scenarios.run(sc)
    m = res.metrics(settle_days=settle_days)
    pos, vel = m["position_error_m"], m["velocity_error_mps"]
    min_eig = float(res.min_eigenvalue().min())
    sym = float(np.max(np.abs(res.P - np.swapaxes(res.P, 1, 2))))
    after = res.t_days >= settle_days
    inside = float(np.mean(res.position_error()[after] <= 3.0 * res.sigma_position()[after]))
    checks, q_reach = [], {}
    if (days, settle_days, mode) == (30.0, 1.0, "reset"):
        # the paper's numbers are single runs: judged among ours over 32 seeds
        from xnavlab.mars.navigation import headline

        runs = headline.headline_numbers(n_seeds=32)["runs"]
        # q is lost (the paper gives none) and moves both numbers beyond our noise; the NEES
        # does not narrow it: every q of LOST_Q_ACC keeps the matched filter cautious (chapter 5)
        shifts = q_shifts()
        for i, (name, paper, key, unit) in enumerate((
                ("fused position error (m), RMS after day 1", PAPER_POSITION_ERROR_M,
                 "fused_position_m", "m"),
                ("fused velocity error (m/s), RMS after day 1", PAPER_VELOCITY_ERROR_MPS,
                 "fused_velocity_mps", "m/s"))):
            lo, hi = np.percentile(runs[key], [2.5, 97.5])
            reach = {("ours, " if q == 1e-11 else "") + f"q {q:g}": (lo + d[i], hi + d[i])
                     for q, d in shifts.items()}
            q_reach[name] = reach
            checks.append(check_lost(check_draw(name, paper, runs[key]),
                                     "process noise q (the paper gives none)", reach,
                                     "the paper's process noise (the filter's consistency does "
                                     "not narrow it: every plausible q keeps chapter 5's NEES "
                                     "below its band, cautious, and q = 0 diverges)", unit=unit))
    checks += [
        check_measure(f"fused position error of the plotted run, seed {seed} (m)", pos,
                      "one single run, the one whose curves the chapter plots",
                      paper=PAPER_POSITION_ERROR_M),
        check_sanity("covariance SPD over the run (smallest eigenvalue)", "> 0", min_eig,
                     min_eig > 0.0 and sym == 0.0, "symmetric, all eigenvalues > 0"),
        check_sanity("|position error| within 3 sigma after day 1 (fraction)", ">= 0.99", inside,
                     inside >= 0.99, "the filter's covariance covers its error"),
    ]
    note = (
        f"Metric (the paper defines none): RMS over time of the norm of the fused error from "
        f"day {settle_days:g} to day {days:g}. Ours {pos:.2f} m and {vel:.4f} m/s against the "
        f"paper's {PAPER_POSITION_ERROR_M} m and {PAPER_VELOCITY_ERROR_MPS} m/s "
        f"(ratios {pos / PAPER_POSITION_ERROR_M:.2f} and {vel / PAPER_VELOCITY_ERROR_MPS:.2f}). "
        "Set-up as section 4.1 (initial state, 5000 m and 1 m/s initial error per axis, the four "
        "pulsars at 109/344/1866/325 m every 500 s, UV 0.1 deg and 5000 m every 3 s, CNS 3 arcsec "
        "and 0.05 deg every 3 s, 30 days, Mars + Sun + Jupiter); epoch 2016-01-01 TDB; three "
        "Hipparcos stars picked by xnavlab.mars.models.stars.pick_three; federated filter in reset mode with "
        "equal sharing factors, fused every epoch. The paper gives no process noise: we use white "
        f"acceleration noise q = {sc.q_acc:g} m^2/s^3 (1e-7 m/s^2 over ~1000 s); the result moves "
        "from about 20 m (q = 1e-12) to 52 m (q = 1e-9), which with the undefined metric is the "
        "main reason for any gap. Both numbers are therefore judged over q's plausible values "
        "(xnavlab.verdicts.check_lost): 1e-12 to 1e-9 m^2/s^3, an unmodelled acceleration of "
        "about 3e-8 to 1e-6 m/s^2 over 1000 s; each value's range is our 32-run range shifted by "
        "its mean paired change on seeds 0-3. The filter's consistency does not narrow it: over "
        "chapter 5's 8-day sweep every q of it keeps the matched filter cautious (mean NEES 1.2 "
        "to 2.0 against the 6 of a consistent filter, none inside the band), and q = 0 stops "
        "listening (mean NEES about 1.7e3); a consistent q lies between the two (not run). "
        "Both errors keep the paper's ratio: the velocity error is the "
        "position error times the orbital mean motion (7.6e-4 rad/s), the signature of errors "
        "that ride along the orbit."
    )
    data = {
        "t_days": res.t_days, "position_error": res.position_error(),
        "velocity_error": res.velocity_error(), "sigma_position": res.sigma_position(),
        "local_position_error": np.linalg.norm(res.x_local[:, :, :3] - res.truth[:, None, :3],
                                               axis=2),
        "subsystems": res.scenario.subsystems, "metrics": m, "run_time_s": res.wall_time,
        "q_acc": sc.q_acc, "q_reach": q_reach,
    }
    result = Result("mars-nofault", checks, note, data)
    if out is not None:
        fig, axes = _figure(2, 1, figsize=(8, 5), sharex=True)
        axes[0].semilogy(res.t_days, res.position_error(), lw=0.6, label="fused |error|")
        axes[0].semilogy(res.t_days, res.sigma_position(), lw=0.8, label="filter 1-sigma")
        axes[0].axhline(PAPER_POSITION_ERROR_M, color="k", ls="--", lw=0.8, label="paper")
        axes[0].set(ylabel="position error (m)")
        axes[0].legend(fontsize=8)
        axes[1].semilogy(res.t_days, res.velocity_error(), lw=0.6)
        axes[1].axhline(PAPER_VELOCITY_ERROR_MPS, color="k", ls="--", lw=0.8)
        axes[1].set(xlabel="time (days)", ylabel="velocity error (m/s)")
        fig.suptitle("mars-nofault (Fan et al. 2016, Fig. 2)")
        result.figures.append(save_figure(fig, out, "mars-nofault"))
    return result


@register("mars-xnav-crlb", title="the fused accuracy with XNAV noise at the Cramer-Rao bound",
          source="Fan et al. 2016, section 4.1 (the ranging accuracies); xnavlab.mars.timing.timing_bound",
          chapter="06_federated")
def mars_xnav_crlb(out=None, days=30.0, seeds=tuple(range(8)), settle_days=1.0):
    """The paper's fault-free run with XNAV noise at the Cramer-Rao bound, seed by seed.

    The same seeds (the same noise draws, scaled) with the paper's ranging accuracies
    (``xnav_noise="paper"``) and with the bound of the same photon rates, profile and
    background (``xnav_noise="crlb"``, :func:`xnavlab.mars.timing.timing_bound.xnav_noise_sigma`).
    """
    from xnavlab.mars.navigation.headline import mean_interval

    seeds = check_seeds("seeds", seeds)
    runs = {kind: _fused_runs(days, seeds, settle_days, xnav_noise=kind)
            for kind in ("paper", "crlb")}
    for r in runs.values():
        del r["nees_all"], r["t_all"]
    sig = {kind: scenarios.MarsScenario(xnav_noise=kind).sensors()["xnav"].sigma * C
           for kind in runs}
    diff = mean_interval(np.subtract(runs["crlb"]["position_m"], runs["paper"]["position_m"]))
    mean = {kind: float(np.mean(r["position_m"])) for kind, r in runs.items()}
    pulsar_list = scenarios.MarsScenario().pulsars
    checks = [
        check_measure(f"fused position error, paper's ranging accuracies, mean of {len(seeds)} "
                      f"seeds (m)", mean["paper"],
                      "XNAV sigma " + ", ".join(f"{v:.0f}" for v in sig["paper"]) + " m ("
                      + ", ".join(pulsar_list) + ")", paper=PAPER_ONE_RUN),
        check_measure(f"fused position error, XNAV at the Cramer-Rao bound, mean of {len(seeds)} "
                      f"seeds (m)", mean["crlb"],
                      "XNAV sigma " + ", ".join(f"{v:.0f}" for v in sig["crlb"]) + " m",
                      paper="not given"),
        check_measure("bound minus paper, paired over the seeds (m)", diff["mean"],
                      f"95 % interval of the mean [{diff['lo']:.2f}, {diff['hi']:.2f}] m, "
                      f"run-to-run sd {diff['sd']:.2f} m"),
    ]
    note = (
        f"The paper's {days:g}-day fault-free scenario over seeds {seeds[0]}-{seeds[-1]}, once with "
        "the paper's ranging accuracies (the Sheikh et al. 2006 formula) and once with the "
        "Cramer-Rao bound of the same rates, profile and background (chapter 1): the same noise "
        "draws, scaled by each pulsar's sigma. RMS of the fused position error after day "
        f"{settle_days:g}: {mean['paper']:.2f} m with the paper's accuracies, "
        f"{mean['crlb']:.2f} m at the bound (paired difference {diff['mean']:+.2f} m, 95 % "
        f"interval [{diff['lo']:+.2f}, {diff['hi']:+.2f}] m). The paper judges no such case."
    )
    data = {"runs": runs, "sigma_m": sig, "difference": diff, "mean_m": mean,
            "pulsars": pulsar_list}
    return Result("mars-xnav-crlb", checks, note, data)
