"""Main paper (Fan et al. 2016), Figs. 3-5: the faulty Mars run, without and with the wavelet detector.

IDs: ``mars-faults-ekf`` (Fig. 3: faults, no detector), ``mars-faults-wavelet`` (Fig. 4:
wavelet detection, isolation and rejoining) and ``wavelet-details`` (Fig. 5: db3 5-level
detail signals of the faulty UV range). All chapter 8.

The paper gives the fault instants only; the magnitudes and durations are ours
(:func:`xnavlab.mars.schedules.paper_schedule`: UV range steps of 5 sigma, XNAV delay steps
of 1e-5 s (3 km) and ramps of 2e-9 s/s, horizon-sensor steps of 8 sigma, 5000 s each). The
metric is the one of ``mars-nofault``: RMS of the fused error norm from day 1 to day 30; the
maximum is taken over the same span.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from xnavlab.core import detection
from xnavlab.core.faults import Fault, inject
from xnavlab.mars import fault_tolerance, scenarios
from xnavlab.mars.plots import plot_details, plot_error_curves
from xnavlab.reproduce import Result, check_draw, check_measure, check_range, check_true, register

__all__ = ["PAPER_MAX_ERROR_FAULTS_M", "PAPER_POSITION_ERROR_M", "PAPER_VELOCITY_ERROR_MPS",
           "HAND_SCHEDULE", "paper_runs"]

#: Fig. 3: largest position error with faults and no detector, about 4 km.
PAPER_MAX_ERROR_FAULTS_M = 4000.0
#: Fig. 4: with wavelet detection and reconfiguration.
PAPER_POSITION_ERROR_M = 36.587
#: Fig. 4: the velocity error with wavelet detection and reconfiguration, m/s.
PAPER_VELOCITY_ERROR_MPS = 0.02293

#: A schedule with onsets the paper does not use (s since the start), for a 3-day check.
HAND_SCHEDULE = (
    Fault("uv", "step", 30000.0, onset=123456.0, duration=4000.0, component=0),
    Fault("xnav", "step", 1.0e-5, onset=150321.0, duration=3000.0),
    Fault("cns", "step", math.radians(0.4), onset=177777.0, duration=3000.0),
    Fault("uv", "spike", 60000.0, onset=201234.0, duration=0.0, component=0),
    Fault("xnav", "ramp", 2.0e-9, onset=222222.0, duration=5000.0, component=1),
)


@lru_cache(maxsize=2)
def paper_runs(days=30.0, seed=0):
    """The fault-free run and the paper's schedule with no detector and with the wavelet.

    Returns
    -------
    dict
        ``inputs``, ``clean`` (MarsRun), ``faults``, ``none`` and ``wavelet``
        (FaultTolerantRun). Cached (two calls with the same arguments share the runs).
    """
    inp = scenarios.prepare(days=days, seed=seed)
    faults = fault_tolerance.paper_schedule()
    return {
        "inputs": inp, "faults": faults, "clean": scenarios.run(inputs=inp),
        "none": fault_tolerance.run_fault_tolerant(faults=faults, detector="none", inputs=inp),
        "wavelet": fault_tolerance.run_fault_tolerant(faults=faults, detector="wavelet",
                                                      inputs=inp),
    }


def _save(result, out, fig, name):
    if out is not None:
        path = out / name
        fig.savefig(path, dpi=90)
        result.figures.append(str(path))


@register("mars-faults-ekf", title="faults in the 30-day Mars run, no detector (Fig. 3)",
          source="Fan et al. 2016, section 4.2 and Fig. 3", chapter="08_fault_tolerant")
def mars_faults_ekf(out=None, days=30.0, seed=0):
    """Max position error with the paper's schedule and no detector vs the fault-free run."""
    r = paper_runs(days, seed)
    m_bad = r["none"].run.metrics()
    m_ok = r["clean"].metrics()
    bad, ok = m_bad["position_error_max_m"], m_ok["position_error_max_m"]
    checks = []
    if (days, seed) == (30.0, 0):
        # the paper's Fig. 3 is one run: judged among our single runs over 32 seeds
        from xnavlab.mars import headline

        runs = headline.headline_numbers(n_seeds=32)["runs"]
        ekf, clean = np.asarray(runs["ekf_max_position_m"]), np.asarray(runs["clean_max_position_m"])
        checks += [
            check_draw("max |position error|, faults, no detector (m)", PAPER_MAX_ERROR_FAULTS_M,
                       ekf, slack=500.0, unit="m",
                       why="the paper reads 'about 4 km' off its figure; the fault sizes behind "
                           "it are not given, ours are chosen (see the note)"),
            check_range("max |position error|, fault-free, largest of our runs (m)",
                        "hundred-metre level", float(clean.max()), 100 / np.sqrt(10), 100 * np.sqrt(10),
                        why="'hundred-metre level' read as the order of magnitude of 100 m "
                            "(a factor sqrt(10) either side)"),
            check_true("faults / fault-free max error, smallest of our runs", "grows to km level",
                       float((ekf / clean).min()), bool((ekf / clean).min() >= 10.0),
                       why="undetected faults raise the largest error by more than an order "
                           "of magnitude in every run"),
        ]
    checks.append(check_measure(f"max |position error|, faults, no detector, seed {seed} (m)",
                                bad, "the run whose curve the chapter plots",
                                paper=PAPER_MAX_ERROR_FAULTS_M))
    checks.append(check_measure("RMS |position error|, faults, no detector (m)",
                                m_bad["position_error_m"],
                                "the paper gives only the maximum for Fig. 3"))
    note = (
        f"The paper's fault instants with our magnitudes and durations (5000 s each: UV range "
        "steps of 5 sigma = 25 km; XNAV delay steps of 1e-5 s = 3 km on every pulsar and ramps "
        "of 2e-9 s/s on B1937+21; horizon-sensor steps of 8 sigma = 0.4 deg on the three "
        f"starlight angles). No detector: the federated filter takes every biased measurement. "
        f"Ours peaks at {bad / 1e3:.2f} km (paper about 4 km) against {ok:.0f} m fault-free; the "
        "CNS horizon bias causes the largest excursions, the UV range steps the smallest (the "
        "range noise is 5 km). The paper gives no magnitudes: its 4 km is judged among our "
        "runs with our magnitudes, with half a kilometre of slack for reading it off a figure."
    )
    data = {"t_days": r["none"].run.t_days, "faulty": r["none"].run.position_error(),
            "clean": r["clean"].position_error(), "faults": r["faults"],
            "metrics": m_bad, "metrics_clean": m_ok}
    result = Result("mars-faults-ekf", checks, note, data)
    if out is not None:
        fig = plot_error_curves({"faults, no detector": (data["t_days"], data["faulty"]),
                                 "fault-free": (data["t_days"], data["clean"])},
                                r["faults"], title="mars-faults-ekf (Fan et al. 2016, Fig. 3)")
        _save(result, out, fig, "mars-faults-ekf.png")
    return result


@register("mars-faults-wavelet",
          title="wavelet detection, isolation and rejoining in the faulty Mars run (Fig. 4)",
          source="Fan et al. 2016, section 4.2 and Fig. 4", chapter="08_fault_tolerant")
def mars_faults_wavelet(out=None, days=30.0, seed=0, hand_days=3.0):
    """RMS errors with the wavelet detector vs the paper and vs our fault-free run."""
    r = paper_runs(days, seed)
    ftr = r["wavelet"]
    m = ftr.run.metrics()
    m0 = r["clean"].metrics()
    pos, vel = m["position_error_m"], m["velocity_error_mps"]
    delays = ftr.delays()
    missed = [d for d in delays if not math.isfinite(d["delay"])]
    # a schedule with onsets the paper does not use (shorter run)
    hand = fault_tolerance.run_fault_tolerant(faults=list(HAND_SCHEDULE), detector="wavelet",
                                              days=hand_days, seed=seed)
    hand_clean = scenarios.run(days=hand_days, seed=seed)
    hd = hand.delays()
    hand_missed = [d for d in hd if not math.isfinite(d["delay"])]
    hand_ratio = hand.run.metrics()["position_error_m"] / hand_clean.metrics()["position_error_m"]
    checks = []
    if (days, seed) == (30.0, 0):
        # the paper's Fig. 4 is one run: its numbers judged among our single runs over 32 seeds
        from xnavlab.mars import headline

        runs = headline.headline_numbers(n_seeds=32)["runs"]
        paper_ratio = PAPER_POSITION_ERROR_M / headline.PAPER["fused_position_m"]
        ratio = np.asarray(runs["wavelet_ratio"])
        found = np.asarray(runs["wavelet_detected_fraction"])
        checks += [
            check_draw("fused position error with faults (m), RMS after day 1",
                       PAPER_POSITION_ERROR_M, runs["wavelet_position_m"]),
            check_draw("fused velocity error with faults (m/s), RMS after day 1",
                       PAPER_VELOCITY_ERROR_MPS, runs["wavelet_velocity_mps"]),
            check_true("close to fault-free: faulty / fault-free error, 95th percentile",
                       f"close ({paper_ratio:.2f} in the paper)",
                       float(np.percentile(ratio, 95)), np.percentile(ratio, 95) <= paper_ratio,
                       why="at most the paper's own ratio, which it calls close, in 95 % of runs"),
            check_true("every scheduled fault detected, share of our runs", "all detected",
                       float(np.mean(found == 1.0)), bool(np.all(found == 1.0)),
                       why="the paper shows every fault detected and isolated"),
        ]
    checks += [
        check_measure(f"fused position error with faults, seed {seed} (m)", pos,
                      "the run whose curves the chapter plots", paper=PAPER_POSITION_ERROR_M),
        check_measure(f"scheduled faults detected, seed {seed}",
                      f"{len(delays) - len(missed)} of {len(delays)}", "the plotted run",
                      paper="all"),
        check_measure(f"every subsystem connected at the end, seed {seed}",
                      bool(not ftr.isolated[-1].any()), "the plotted run", paper="yes"),
        check_measure(f"hand-made schedule ({hand_days:g} days, other onsets): detected",
                      f"{len(hd) - len(hand_missed)} of {len(hd)}",
                      "faults at onsets the paper does not use"),
        check_measure("hand-made schedule: position error / fault-free", float(hand_ratio),
                      "faults at onsets the paper does not use"),
    ]
    finite = [d["delay"] for d in delays if math.isfinite(d["delay"])]
    by = {}
    for d in delays:
        by.setdefault((d["sensor"], d["kind"]), []).append(d["delay"])
    delay_text = "; ".join(f"{s} {k}: " + ", ".join(f"{v:.0f}" for v in vs) + " s"
                           for (s, k), vs in by.items())
    note = (
        f"Wavelet detection (db3; UV range and CNS angles on the raw measurements, 5 levels, MAD "
        "thresholds trained on day 1; XNAV on its normalised innovations, 3 levels), isolation "
        "from the detected onset, rejoining when the detector is clear and the NIS of the last "
        "measurements (100 UV/CNS, 4 XNAV) passes a 1 % chi-square test. Ours "
        f"{pos:.2f} m and {vel:.5f} m/s against the paper's {PAPER_POSITION_ERROR_M} m and "
        f"{PAPER_VELOCITY_ERROR_MPS} m/s, and against our fault-free {m0['position_error_m']:.2f} m "
        f"and {m0['velocity_error_mps']:.5f} m/s: the isolated faults cost almost nothing, the "
        "paper's faults cost it 27 % (28.8 -> 36.6 m), which suggests its detector let more of "
        "each fault in (it does not state its detection delays). Detection delays: "
        f"{delay_text} (the XNAV ramps are 0.87 sigma per sample at onset and show at their end "
        f"jump; median of all {np.median(finite):.0f} s). "
        f"Hand-made schedule ({len(hd)} faults at onsets the paper does not use, {hand_days:g} "
        "days; UV step, XNAV step, CNS step, UV spike, XNAV ramp): delays "
        + ", ".join(f"{d['delay']:.0f} s" for d in hd)
        + f"; error ratio {hand_ratio:.2f} to the fault-free run."
    )
    data = {"t_days": ftr.run.t_days, "wavelet": ftr.run.position_error(),
            "clean": r["clean"].position_error(), "velocity": ftr.run.velocity_error(),
            "faults": r["faults"], "delays": delays, "isolations": ftr.isolation_intervals(),
            "detections": ftr.detections, "metrics": m, "metrics_clean": m0,
            "hand_delays": hd, "hand_ratio": hand_ratio}
    result = Result("mars-faults-wavelet", checks, note, data)
    if out is not None:
        fig = plot_error_curves({"wavelet detection + isolation": (data["t_days"], data["wavelet"]),
                                 "fault-free": (data["t_days"], data["clean"])}, r["faults"],
                                title="mars-faults-wavelet (Fan et al. 2016, Fig. 4)",
                                isolations=data["isolations"])
        _save(result, out, fig, "mars-faults-wavelet.png")
    return result


@register("wavelet-details", title="db3 5-level detail signals of the faulty UV range (Fig. 5)",
          source="Fan et al. 2016, section 4.2 and Fig. 5", chapter="08_fault_tolerant")
def wavelet_details(out=None, days=30.0, seed=0, pfa=1e-5, train_days=1.0):
    """Detail signals D1..D5 of the UV range with the paper's UV faults; each fault detected."""
    inp = paper_runs(days, seed)["inputs"]
    faults = [f for f in fault_tolerance.paper_schedule() if f.sensor == "uv"]
    t = inp.t_meas["uv"] - inp.times[0]
    x = inject(t, inp.z["uv"][:, 0], faults, "uv")
    details, _ = detection.detail_signals(x, "db3", 5)
    n_train = int(np.searchsorted(t, train_days * 86400.0))
    det = detection.wavelet_detect(t, x, pfa=pfa, train=n_train)
    sig = detection.mad_sigma(details[:, :n_train])
    k = detection.threshold_multiplier(pfa, 6)
    delays, peaks = [], []
    for f in faults:
        delays.append(det.first_onset_after(f.onset) - f.onset)
        near = np.abs(t - f.onset) <= 300.0
        peaks.append(float(np.max(np.abs(details[:, near]) / (k * sig[:, None]))))
    late = [d for d in delays if not d <= 600.0]
    matched = sum(1 for e in det.events
                  if any(f.onset <= e.onset <= f.end + 600.0 for f in faults))
    false = len(det.events) - matched
    checks = [
        check_true("detail peak at each onset / threshold (min over faults)", "fault instants shown",
                   min(peaks), min(peaks) > 1.0,
                   why="each onset stands out above the detector's threshold in D1..D5"),
        check_true("scheduled UV faults detected within 600 s (online detector)", "all 6",
                   f"{len(faults) - len(late)} of {len(faults)}", not late,
                   why="the paper marks every fault instant; 600 s is 200 UV samples, our "
                       "criterion for 'at the instant'"),
        check_measure("false alarms in 30 days (events away from faults)", false,
                      f"design pfa {pfa:g} per sample; {x.size} samples"),
    ]
    note = (
        "The UV range (5000 m noise, every 3 s) with the paper's six UV fault instants as 25-km "
        "(5 sigma) steps of 5000 s. The figure shows D1..D5 of the whole series (PyWavelets, "
        "db3, symmetric boundary; offline, as the paper plots it); the detection is the online "
        f"causal detector of chapter 7 (MAD thresholds from day 1, k = {k:.2f}). Delays at the "
        "onsets: " + ", ".join(f"{d:.0f} s" for d in delays) + ". Each step shows at both ends "
        "(onset and end), as a singularity must."
    )
    data = {"t_days": t / 86400.0, "x": x, "details": details, "faults": faults,
            "delays": delays, "peaks": peaks, "events": det.events}
    result = Result("wavelet-details", checks, note, data)
    if out is not None:
        fig = plot_details(t / 86400.0, x, details, [f.onset / 86400.0 for f in faults],
                           title="wavelet-details (Fan et al. 2016, Fig. 5)")
        _save(result, out, fig, "wavelet-details.png")
    return result
