"""Chapter 11 reproductions: attitude-sensor fault diagnosis with one Kalman filter.

Source: Li, Niu, Shao & Shen, "Fault diagnosis for satellite attitude system by simplified
filter scheme", Journal of Astronautics 40(7), 2019, cited as Li, Niu et al. 2019 (our copy
lost most equations, the fault definitions (38)-(40) and the thresholds). Figures 3-6 are
judged qualitatively: which residuals cross, the isolation verdict, the detection delay of the
skew ramp; the 4x cost, an operation count that holds by construction of the schemes, is a
check of ours (the number of filters), shown beside the measured time. Each figure is one run of
the paper's; an outcome it shows is judged as one draw among :data:`RUNS` of ours
(:func:`xnavlab.verdicts.check_event`, the runs from
:func:`xnavlab.attitude.seeded_outcomes <xnavlab.attitude.montecarlo.seeded_outcomes>`),
and the run the chapter plots (the first seed) is kept beside it as a measurement. Fault sizes
and thresholds are ours (see
:data:`xnavlab.attitude.DEFAULT_MAGNITUDES <xnavlab.attitude.sensors.DEFAULT_MAGNITUDES>`
and :class:`xnavlab.attitude.SimConfig <xnavlab.attitude.simulation.SimConfig>`)
and were fixed before looking at the outcome.
"""

from __future__ import annotations

import math

import numpy as np

from xnavlab import attitude as att
from xnavlab.core.validate import SEED_MAX, check_int, check_real, check_seed
from xnavlab.reproduce import (
    Result,
    check_draw,
    check_event,
    check_lost,
    check_measure,
    check_sanity,
    figure,
    register,
    save_figure,
)
from xnavlab.verdicts import MIN_RUNS

__all__ = ["PAPER", "SOURCE", "CHAPTER", "RUNS", "SKEW_RATE_FACTORS", "crossed_after_onset"]

#: The source paper, as the registered reproductions name it.
SOURCE = "Li, Niu et al. 2019 (J. Astronautics 40(7))"
#: The chapter that shows these reproductions.
CHAPTER = "11_attitude_sos"

#: What the paper states (section 4), as far as our copy shows it.
PAPER = {
    "xgyro_crossed": "r1, r4",
    "xgyro_verdict": "gyro_x",
    "skew_crossed": "r4",
    "skew_delay_s": 2.5,
    "star_verdict": "star_tracker",
    "qdiff_verdict": "gyro fault (wrong)",
    "cost_ratio": 4.0,
}

_NAMES = ("r1", "r2", "r3", "r4")
#: Single runs (seeds ``seed`` to ``seed + RUNS - 1``, the plotted run first) each outcome of the
#: paper's one run is judged among: at most 40, so that one run showing it is 2.5 % of ours
#: (xnavlab.verdicts.check_event); 40 runs of 100 s take about 4 s, vectorised.
RUNS = 40
#: Runs of the skew ramp the paper's single-run delay is judged among (60 s each).
SKEW_RUNS = 32
#: The plausible ramp rates of the skew fault, as factors on ours (the paper's eq. (39) is
#: lost): half to twice our round 0.1 deg/h per second, the range chapter 8 gives the Mars
#: paper's lost fault sizes. The delay is the threshold over the rate (plus the persistence),
#: and the paper lost its threshold too: at our rate the factors span thresholds of 2.5 to 10
#: sigma, which holds the 3 to 6 sigma detectors commonly use.
SKEW_RATE_FACTORS = (0.5, 2.0)
_COMMON = (
    "Choices where the paper is silent: 10 Hz sampling; skewed gyro on [1,1,1]/sqrt3; an "
    "Earth-pointing truth motion (pitch -0.06 deg/s plus a 0.01 deg/s wobble); fault onset "
    "50 s; references learned in a fault-free window 20-40 s and detectors armed at 40 s "
    "(the paper instead shows start-up crossings while the drift estimates converge; ours "
    "appear in the grey, unarmed part of the figures); thresholds = 5 predicted sigma; a "
    "flag needs 3 consecutive samples; residuals crossing within 5 s of the detection "
    "form the isolation pattern. r4 is reconstructed as the gyro parity "
    "abs(w_g4 - h4^T w_g1 - p_ref) from the paper's operation count."
)


def crossed_after_onset(run, method="sos"):
    """Names of the residuals flagged at any time from the fault onset to the end.

    Examples
    --------
    >>> from xnavlab import attitude as att
    >>> run = att.simulate(att.make_fault("gyro_x", "step", 36 * att.DEG_PER_H), duration=60.0)
    >>> crossed_after_onset(run)
    'r1, r4'
    """
    diag = {"sos": run.sos, "dos": run.dos}[method]
    after = run.t >= run.onset
    hit = diag.flags[after].any(axis=0)
    names = _NAMES if method == "sos" else ("R1", "R2", "R3", "R4")
    return ", ".join(n for n, h in zip(names, hit, strict=True) if h) or "none"


def _sets(crossed):
    """The names of the flagged residuals of each run (rows of ``crossed``, shape (B, 4))."""
    return [", ".join(n for n, h in zip(_NAMES, row, strict=True) if h) or "none"
            for row in crossed]


def _spread(values):
    """Median and 95 % range of our runs, in words, for a measurement row."""
    lo, med, hi = np.percentile(values, [2.5, 50.0, 97.5])
    return f"median {med:.3g} [{lo:.3g}, {hi:.3g}]"


#: The most runs a reproduction takes (about 0.05 s a run of 100 s: a few minutes at most).
MAX_RUNS = 10_000


def _check_runs(seed, n_runs, span=0):
    """``(seed, n_runs)`` checked: the runs take seeds ``seed`` to ``seed + max(n_runs - 1,
    span)``, so the first seed's range ends that far below :data:`SEED_MAX`."""
    n_runs = check_int("n_runs", n_runs, MIN_RUNS, MAX_RUNS)  # the figure judged among them
    return check_int("seed", seed, 0, SEED_MAX - max(n_runs - 1, span)), n_runs


def _check_size(name, value, hi=att.MAX_DEG_PER_H):
    """A fault's size as the figure shows it: positive, at most ``hi`` (deg/h for the gyros,
    per second for a quaternion component, whose whole span is 1)."""
    return check_real(name, value, 0.0, hi, lo_open=True)


def _outcomes(fault, seed, n_runs, **changes):
    """The outcomes of ``n_runs`` runs of ``fault``, seeds ``seed`` on (the plotted run first)."""
    return att.seeded_outcomes(fault, range(seed, seed + n_runs), **changes)


def _false_alarm(run):
    before = run.t < run.onset
    return bool(run.sos.flags[before].any())


def _first_flag_delay(run, i):
    """Delay (s) from onset to the first flag of SOS residual ``i``; inf if never."""
    idx = np.flatnonzero(run.sos.flags[:, i] & (run.t >= run.onset))
    return float(run.t[idx[0]] - run.onset) if idx.size else math.inf


def _figure(run, out, name, method="sos"):
    m = 3 if method == "qdiff" else 4
    fig, axes = figure(m, 1, sharex=True, figsize=(7, 1.5 * m + 1), squeeze=False)
    att.plot_residuals(run, method, axes=axes[:, 0])
    return save_figure(fig, out, name)


@register(
    "attitude-xgyro-step",
    title="x-gyro step fault: r1 and r4 cross, the others do not; isolated as the x gyro",
    source=f"{SOURCE}, Fig. 3",
    chapter=CHAPTER,
)
def xgyro_step(out=None, magnitude_deg_per_h=36.0, seed=0, n_runs=RUNS):
    """Fig. 3: a step of ``magnitude_deg_per_h`` on the x gyro at t = 50 s."""
    seed, n_runs = _check_runs(seed, n_runs)
    magnitude_deg_per_h = _check_size("magnitude_deg_per_h", magnitude_deg_per_h)
    fault = att.make_fault("gyro_x", "step", magnitude_deg_per_h * att.DEG_PER_H)
    run = att.simulate(fault, rng=seed)
    mc = _outcomes(fault, seed, n_runs)
    crossed = crossed_after_onset(run)
    delay_r1 = _first_flag_delay(run, 0)
    window = run.config.confirm_s
    r1_runs = mc["first_flag_s"][:, 0]
    checks = [
        check_event("residuals over threshold", PAPER["xgyro_crossed"],
                    np.array(_sets(mc["crossed"])) == PAPER["xgyro_crossed"],
                    why="the same set, r1 and r4 and no other, flagged from the onset on"),
        check_measure(f"residuals over threshold, seed {seed}", crossed,
                      "the run the chapter plots", paper=PAPER["xgyro_crossed"]),
        check_event("SOS verdict", PAPER["xgyro_verdict"],
                    mc["sos_verdict"] == PAPER["xgyro_verdict"], why="the same sensor"),
        check_measure(f"SOS verdict, seed {seed}", run.sos.verdict, "the run the chapter plots",
                      paper=PAPER["xgyro_verdict"]),
        check_event(f"r1 flagged within {window:g} s of the onset", "quickly",
                    r1_runs <= window,
                    why=f"'quickly' read as within the {window:g}-s isolation window"),
        check_measure(f"r1 delay, {n_runs} runs (s)",
                      _spread(r1_runs) if np.all(np.isfinite(r1_runs)) else
                      f"{int(np.sum(~np.isfinite(r1_runs)))} of {n_runs} runs never flag r1",
                      "our spread (median, 95 % range); the paper gives no number",
                      paper="quickly"),
        check_measure(f"r1 delay, seed {seed} (s)", delay_r1, "the run the chapter plots",
                      paper="quickly"),
        check_sanity("runs with a false alarm before onset", "none",
                     f"{int(mc['false_alarm'].sum())} of {n_runs}",
                     not mc["false_alarm"].any(), "none once armed"),
    ]
    note = (
        f"Fault (paper eq. (38) lost): +{magnitude_deg_per_h:g} deg/h (0.01 deg/s) on the x "
        f"gyro from 50 s. r4 (gyro parity) flags after {_first_flag_delay(run, 3):.1f} s, r1 "
        f"(x drift estimate) after {delay_r1:.1f} s; r2 and r3 stay below "
        f"{np.max(run.sos_r[run.armed, 1:3] / run.sos_J[1:3]):.2f} of their thresholds. "
        f"DOS agrees ({run.dos.verdict}) after {run.dos.detect_time - run.onset:.1f} s. "
        f"That is seed {seed}, the run the chapter plots; the paper's one run is judged among "
        f"{n_runs} of ours (seeds {seed}-{seed + n_runs - 1}), in which r1 flags after "
        f"{_spread(r1_runs)} s. " + _COMMON
    )
    result = Result("attitude-xgyro-step", checks, note=note, data={"run": run, "outcomes": mc})
    if out is not None:
        result.figures.append(_figure(run, out, "attitude-xgyro-step"))
    return result


@register(
    "attitude-skew-ramp",
    title="skewed-gyro ramp fault: only r4 crosses, about 2.5 s after onset",
    source=f"{SOURCE}, Fig. 4",
    chapter=CHAPTER,
)
def skew_ramp(out=None, rate_deg_per_h_per_s=0.1, seed=0, n_runs=RUNS):
    """Fig. 4: a ramp of ``rate_deg_per_h_per_s`` on the skewed gyro from t = 50 s."""
    seed, n_runs = _check_runs(seed, n_runs, SKEW_RUNS)
    rate_deg_per_h_per_s = _check_size("rate_deg_per_h_per_s", rate_deg_per_h_per_s)
    rate = rate_deg_per_h_per_s * att.DEG_PER_H
    fault = att.make_fault("gyro_skew", "ramp", rate)
    run = att.simulate(fault, rng=seed)
    mc = _outcomes(fault, seed, n_runs)
    crossed = crossed_after_onset(run)
    delay = float(run.sos.detect_time - run.onset)
    persistence = (run.config.persist - 1) * run.config.dt  # s from the first sample over to the flag
    expected = run.sos_J[3] / rate + persistence
    def delays_at(r):  # the runs of 60 s, seeds seed + 1 on, as run one by one before
        return att.seeded_outcomes(att.make_fault("gyro_skew", "ramp", r),
                                   range(seed + 1, seed + 1 + SKEW_RUNS),
                                   duration=60.0)["sos_delay_s"]

    delays = delays_at(rate)
    # the lost rate over its plausible range (SKEW_RATE_FACTORS says why), ours among them
    reach = {f"ours, {rate_deg_per_h_per_s:g} deg/h/s": tuple(np.percentile(delays, [2.5, 97.5]))}
    for f in SKEW_RATE_FACTORS:
        reach[f"{f * rate_deg_per_h_per_s:g} deg/h/s"] = tuple(
            np.percentile(delays_at(f * rate), [2.5, 97.5]))
    rate_25 = run.sos_J[3] / (PAPER["skew_delay_s"] - persistence)  # gives the paper's delay
    checks = [
        check_event("residuals over threshold", PAPER["skew_crossed"],
                    np.array(_sets(mc["crossed"])) == PAPER["skew_crossed"],
                    why="the same set, r4 alone, flagged from the onset on"),
        check_measure(f"residuals over threshold, seed {seed}", crossed,
                      "the run the chapter plots", paper=PAPER["skew_crossed"]),
        check_event("SOS verdict", "gyro_skew", mc["sos_verdict"] == "gyro_skew",
                    why="the same sensor"),
        check_measure(f"SOS verdict, seed {seed}", run.sos.verdict, "the run the chapter plots",
                      paper="gyro_skew"),
        check_lost(check_draw("r4 delay (s)", PAPER["skew_delay_s"], delays),
                   "ramp rate (eq. (39)) over the threshold", reach,
                   "the paper's ramp rate and threshold", unit="s"),
        check_measure(f"r4 delay, seed {seed} (s)", delay, "the run the chapter plots",
                      paper=PAPER["skew_delay_s"]),
        check_sanity("runs with a false alarm before onset", "none",
                     f"{int(mc['false_alarm'].sum())} of {n_runs}",
                     not mc["false_alarm"].any(), "none once armed"),
    ]
    note = (
        f"Fault (paper eq. (39) lost): a ramp of {rate_deg_per_h_per_s:g} deg/h per second on "
        f"the skewed gyro from 50 s, a round number chosen before the run. The delay is set "
        f"by construction: threshold J4 = 5 x 0.05 deg/h x sqrt2 = {run.sos_J[3] / att.DEG_PER_H:.3f}"
        f" deg/h over the ramp rate, plus {run.config.persist - 1} samples of persistence = "
        f"{expected:.1f} s; ours "
        f"{delay:.1f} s against the paper's 2.5 s. A rate of "
        f"{run.sos_J[3] / att.DEG_PER_H / (PAPER['skew_delay_s'] - persistence):.2f} deg/h/s "
        f"would give 2.5 s ({rate_25 / rate:.2f} times ours): the paper's delay "
        f"is judged among {SKEW_RUNS} runs of 60 s (seeds {seed + 1}-{seed + SKEW_RUNS}) at each "
        "plausible rate, half to twice ours (the range chapter 8 gives lost fault sizes; since "
        "the delay is the threshold over the rate, it also spans thresholds of 2.5 to 10 sigma "
        "at our rate), and the paper's ramp rate and threshold, both lost, decide it (a claim a "
        "lost parameter decides: xnavlab.verdicts.check_lost). Caveat found "
        "here: an "
        "x-, y- or z-gyro ramp this slow also crosses r4 alone within the 5 s window and is "
        "called a skew fault too (see the Monte Carlo table in the chapter). The residual set "
        f"and the verdict are judged among {n_runs} runs of 100 s (seeds {seed}-"
        f"{seed + n_runs - 1}, the plotted run first). " + _COMMON
    )
    result = Result("attitude-skew-ramp", checks, note=note, data={"run": run, "outcomes": mc})
    if out is not None:
        result.figures.append(_figure(run, out, "attitude-skew-ramp"))
    return result


def _star_run(magnitude, seed):
    return att.simulate(att.make_fault("star_tracker", "ramp", magnitude), rng=seed)


@register(
    "attitude-star-tracker",
    title="star-tracker fault: drift residuals cross, the gyro parity does not; isolated",
    source=f"{SOURCE}, Fig. 5",
    chapter=CHAPTER,
)
def star_tracker(out=None, ramp_per_s=5e-5, seed=0, n_runs=RUNS):
    """Fig. 5: an additive ramp of ``ramp_per_s`` on the star-tracker's q1 from t = 50 s."""
    seed, n_runs = _check_runs(seed, n_runs)
    run = _star_run(_check_size("ramp_per_s", ramp_per_s, 1.0), seed)
    mc = _outcomes(run.faults, seed, n_runs)
    crossed = crossed_after_onset(run)
    hit = run.sos.flags[run.t >= run.onset].any(axis=0)
    checks = [
        # the paper's surviving text describes no pattern for Fig. 5 (its Table 1 is lost):
        # the pattern is our reconstruction's, checked, not a claim of the paper
        check_sanity("r4 over threshold", "no (our Table 1)", "yes" if hit[3] else "no", not hit[3],
                     "the gyro parity is blind to the star tracker"),
        check_sanity("any of r1-r3 over threshold", "yes (our Table 1)", crossed,
                     bool(hit[:3].any()), "at least one drift residual"),
        check_event("SOS verdict", PAPER["star_verdict"],
                    mc["sos_verdict"] == PAPER["star_verdict"], why="the same sensor"),
        check_measure(f"SOS verdict, seed {seed}", run.sos.verdict, "the run the chapter plots",
                      paper=PAPER["star_verdict"]),
        check_sanity("runs with a false alarm before onset", "none",
                     f"{int(mc['false_alarm'].sum())} of {n_runs}",
                     not mc["false_alarm"].any(), "none once armed"),
    ]
    note = (
        f"Fault (paper eq. (40) lost): an additive ramp f_q of {ramp_per_s:g} per second on "
        "the star-tracker quaternion component q1 from 50 s (a drifting star-tracker output, "
        f"an apparent rotation of about {2 * ramp_per_s / att.DEG_PER_H:.0f} deg/h); the "
        "measured quaternion is renormalised. The filter reads it as a drift change on all "
        f"three axes; here {crossed} flag, r4 cannot. Detected "
        f"{run.sos.detect_time - run.onset:.1f} s after onset; DOS says {run.dos.verdict}. "
        f"That is seed {seed}, the run the chapter plots (the pattern rows are checks of it); "
        f"the verdict is judged among {n_runs} runs (seeds {seed}-{seed + n_runs - 1}), in "
        f"which SOS detects after {_spread(mc['sos_delay_s'])} s. " + _COMMON
    )
    result = Result("attitude-star-tracker", checks, note=note, data={"run": run, "outcomes": mc})
    if out is not None:
        result.figures.append(_figure(run, out, "attitude-star-tracker"))
    return result


@register(
    "attitude-qdiff",
    title="quaternion differentiation (ref. [22]) blames the gyros for a star-tracker fault",
    source=f"{SOURCE}, Fig. 6",
    chapter=CHAPTER,
)
def qdiff(out=None, ramp_per_s=5e-5, seed=0, window_s=10.0, n_runs=RUNS):
    """Fig. 6: ref. [22] on the star-tracker fault of Fig. 5."""
    seed, n_runs = _check_runs(seed, n_runs)
    window_s = check_real("window_s", window_s, 0.0, 86400.0, lo_open=True)  # a day, as confirm_s
    run = _star_run(_check_size("ramp_per_s", ramp_per_s, 1.0), seed)
    if window_s != run.config.qdiff_window_s:
        run = att.simulate(run.faults, qdiff_window_s=window_s, rng=seed)
    mc = _outcomes(run.faults, seed, n_runs, qdiff_window_s=window_s)
    blames = np.char.startswith(mc["qd_verdict"], "gyro")
    v = run.qd.verdict
    peak = float(np.max(np.abs(run.qd_f[run.t_qd >= run.onset]) / run.qd_J))
    checks = [
        check_event("ref. [22] verdict", PAPER["qdiff_verdict"], blames,
                    why="it blames one or more gyros"),
        check_measure(f"ref. [22] verdict, seed {seed}", v, "the run the chapter plots",
                      paper=PAPER["qdiff_verdict"]),
        # the same claim on the same fault and data as attitude-star-tracker's "SOS verdict",
        # judged there: here a check, so the paper's claim is counted once
        check_sanity("SOS verdict on the same data", "star_tracker", run.sos.verdict,
                     run.sos.verdict == "star_tracker",
                     "the same sensor; attitude-star-tracker judges this claim of the paper"),
    ]
    note = (
        f"Ref. [22] as reconstructed: rate from a least-squares slope of the star-tracker "
        f"quaternions over a {window_s:g} s window, w = 2 Xi(q)^T q_dot, minus the gyro "
        f"average over the same window; references learned in 20-40 s; thresholds 5 sigma "
        f"({run.qd_J[0] / att.DEG_PER_H:.1f} deg/h). On the star-tracker ramp of Fig. 5 its "
        f"fault estimates reach {peak:.0f} times the threshold and it blames {v}, the wrong "
        f"sensor, {run.qd.detect_time - run.onset:.1f} s after onset; SOS says "
        f"{run.sos.verdict}. That is seed {seed}, the run the chapter plots; the verdict is "
        f"judged among {n_runs} runs (seeds {seed}-{seed + n_runs - 1}), in which ref. [22] "
        f"blames the gyros in {int(blames.sum())}. The paper shows only the three orthogonal "
        "gyros, as we do."
    )
    result = Result("attitude-qdiff", checks, note=note, data={"run": run, "outcomes": mc})
    if out is not None:
        result.figures.append(_figure(run, out, "attitude-qdiff", "qdiff"))
    return result


@register(
    "attitude-cost",
    title="cost of DOS (four filters) against SOS (one filter): counted and measured",
    source=f"{SOURCE}, section 3 (remark 3)",
    chapter=CHAPTER,
    cache=False,  # a timing of this process, not a function of the code alone
)
def cost(out=None, n_steps=400, repeats=3, seed=0):
    """DOS against SOS: the filters each runs per sample (the paper's 4x), and the measured time."""
    r = att.time_sos_dos(n_steps=n_steps, repeats=repeats, rng=check_seed("seed", seed))
    q0 = np.array([0.0, 0.0, 0.0, 1.0])
    n_dos, n_sos = len(att.DOSMonitor(q0).filters), len(att.SOSMonitor(q0).filters)
    ratio = n_dos / n_sos
    checks = [
        # the paper's 4x holds by construction of the schemes it describes (four filters of the
        # same size against one): a count of our code cannot contradict it, so it is a check of
        # our reconstruction, not a reproduced claim (review 34d)
        check_sanity("DOS/SOS Kalman filters run per sample", PAPER["cost_ratio"], ratio,
                     ratio == PAPER["cost_ratio"],
                     "the paper's 4x is an operation count, one filter of the same size per gyro "
                     "group against one filter (r4 adds a few operations); it holds by "
                     "construction of the two schemes as the paper describes them, so our count "
                     "checks the reconstruction and cannot test the paper's claim"),
        check_measure("DOS/SOS time per sample, measured", round(r["ratio"], 2),
                      "a timing of this process on this machine: it moves with the load and "
                      "the per-call overhead of Python, so it decides nothing",
                      paper=PAPER["cost_ratio"]),
    ]
    note = (
        f"SOS {r['sos_us']:.0f} µs, DOS {r['dos_us']:.0f} µs per sample (best of {repeats} "
        f"runs of {n_steps} samples, time.perf_counter, same process and data): a ratio of "
        f"{r['ratio']:.2f}. The paper's 4x is an operation count (four filters against one, r4 "
        f"costing 3 multiplications, 4 additions and 1 absolute value): DOS runs {n_dos} "
        f"filters of the same size where SOS runs {n_sos}. That holds by construction of the "
        "two schemes as the paper describes them, so it is shown as a check of our "
        "reconstruction, not as a reproduced claim; the measured ratio moves with the load. In "
        "Python the per-call overhead is the same for every filter, so the measured ratio "
        "tracks the number of filters. Use benchmarks/bench_attitude.py for a longer run."
    )
    return Result("attitude-cost", checks, note=note, data=r)
