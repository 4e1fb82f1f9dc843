"""Main paper (Fan et al. 2016), Fig. 5: the wavelet detail signals of the faulty UV range.

ID ``wavelet-details`` (chapter 8): the db3 5-level details D1..D5 of the UV range with the
paper's six UV fault instants (our 25-km steps of 5000 s,
:func:`xnavlab.mars.faults.schedules.paper_schedule`), the online detector's delays, and the
orbit's own signal in the details against the thresholds. The paper's figure is one run: its
two outcomes are judged among our single runs over :data:`DETAIL_SEEDS` (:func:`detail_runs`).
Figs. 3 and 4 are :mod:`xnavlab.reproductions.ch08_mars_faults`, whose runs this one shares
(:func:`~xnavlab.reproductions.ch08_mars_faults.paper_runs`).
"""

from __future__ import annotations

import time
from functools import lru_cache

import numpy as np

from xnavlab.core import detection
from xnavlab.core.faults import inject
from xnavlab.core.validate import check_seeds
from xnavlab.mars.faults import fault_tolerance, schedules
from xnavlab.mars.navigation import scenarios
from xnavlab.mars.navigation.plots import plot_details
from xnavlab.reproduce import Result, check_event, check_measure, part_of, register, save_figure
from xnavlab.reproductions.ch08_mars_faults import paper_runs

__all__ = ["DETAIL_SEEDS", "detail_runs", "wavelet_details"]

#: The code the cached runs depend on (their cache key, with everything these modules import):
#: this module, whose functions are the runs' recipe, and the detector it runs.
_RUN_MODULES = ("xnavlab.reproductions.ch08_wavelet_details", "xnavlab.core.detection",
                "xnavlab.core.faults", "xnavlab.mars.navigation.scenarios")

#: Seeds over which Fig. 5's outcomes are judged (the paper's one run as one draw among ours;
#: seed 0 is the run the chapter plots).
DETAIL_SEEDS = tuple(range(32))


def _uv_details(inp, faults, pfa, train_days):
    """The UV range of ``inp`` with ``faults`` injected, its D1..D5 and the online detector."""
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
    return t, x, details, det, k, n_train, delays, peaks


@lru_cache(maxsize=2)
def detail_runs(seeds=DETAIL_SEEDS, days=30.0, pfa=1e-5, train_days=1.0):
    """Fig. 5's two outcomes in each of our single runs: one per seed of the Mars scenario.

    Each seed's UV range is that of the full scenario's inputs with the same seed (drawn
    after the XNAV delays, before the CNS angles, which are not drawn here). Cached on disk,
    keyed by the code.

    Parameters
    ----------
    seeds : tuple of int
        Noise seeds of :class:`~xnavlab.mars.navigation.scenarios.MarsScenario`.
    days, pfa, train_days : float
        As :func:`wavelet_details`.

    Returns
    -------
    dict
        ``seeds``; per seed: ``min_peak`` (smallest over the six UV onsets of the largest
        detail ``|D_j|`` within 300 s of the onset over the detector's threshold) and
        ``delays_s`` (list of six onset delays of the online detector, s; inf if none);
        ``wall_s``, the run time when computed (s).

    Examples
    --------
    >>> detail_runs(seeds=(0,), days=0.5)
    Traceback (most recent call last):
    ...
    ValueError: days must be 30 (the paper's UV faults run to day 27); got 0.5
    """
    if days != 30.0:
        raise ValueError(f"days must be 30 (the paper's UV faults run to day 27); got {days!r}")
    from xnavlab.core.diskcache import cached_arrays, entry_path

    faults = [f for f in fault_tolerance.paper_schedule() if f.sensor == "uv"]
    seeds = check_seeds("seeds", seeds)

    def compute():
        start = time.perf_counter()
        peak, delay = np.zeros(len(seeds)), np.zeros((len(seeds), len(faults)))
        for j, s in enumerate(seeds):
            inp = scenarios.prepare(days=days, seed=s, subsystems=("xnav", "uv"))
            *_, delays, peaks = _uv_details(inp, faults, pfa, train_days)
            peak[j], delay[j] = min(peaks), delays
        return {"min_peak": peak, "delays_s": delay, "wall_s": time.perf_counter() - start}

    got = cached_arrays(entry_path("ch08-detail-runs", (seeds, float(days), float(pfa),
                                                         float(train_days)),
                                   modules=_RUN_MODULES), compute)
    return {"seeds": seeds, "min_peak": [float(x) for x in got["min_peak"]],
            "delays_s": [[float(x) for x in row] for row in got["delays_s"]],
            "wall_s": float(got["wall_s"])}


@register("wavelet-details", title="db3 5-level detail signals of the faulty UV range (Fig. 5)",
          source="Fan et al. 2016, section 4.2 and Fig. 5", chapter="08_fault_tolerant")
def wavelet_details(out=None, days=30.0, seed=0, pfa=1e-5, train_days=1.0):
    """Detail signals D1..D5 of the UV range with the paper's UV faults; each fault detected."""
    inp = paper_runs(days, seed)["inputs"]
    faults = [f for f in fault_tolerance.paper_schedule() if f.sensor == "uv"]
    t, x, details, det, k, n_train, delays, peaks = _uv_details(inp, faults, pfa, train_days)
    late = [d for d in delays if not d <= 600.0]
    # false alarms by the book's one scoring rule (an alarm no fault explains)
    scored = schedules.score_faults(faults, {"uv": det.events}, span=float(t[-1] - t[0]),
                                    dt={"uv": float(np.median(np.diff(t)))})
    false = sum(a["match"] == "false alarm" for a in scored["alarms"])
    # the orbit's own signal in the details: the noise-free UV range and CNS angles along the
    # truth, against each detector's thresholds (UV: one detector at pfa; CNS: one per angle
    # at pfa / 3, as in the Mars loop), with its noise levels trained by MAD on day 1
    subs = inp.scenario.subsystems
    k_uv = np.flatnonzero(inp.meas_idx[:, subs.index("uv")] >= 0)
    k_cns = np.flatnonzero(inp.meas_idx[:, subs.index("cns")] >= 0)
    range_true = np.linalg.norm(inp.truth[k_uv, :3], axis=1)                 # m
    angles_true = inp.sensors["cns"].h(inp.truth[k_cns])                     # (N, 3) rad
    window = len(detection.causal_filters("db3", 5)[-1])
    n_cns = int(np.searchsorted(inp.t_meas["cns"] - inp.times[0], train_days * 86400.0))

    def trained(z, n):
        return detection.mad_sigma(detection.causal_details(z[:n], "db3", 5)[:, window - 1:])

    signal_uv = detection.signal_threshold_ratio(range_true, trained(inp.z["uv"][:, 0], n_train),
                                                 pfa=pfa)
    signal_cns = np.array([detection.signal_threshold_ratio(
        angles_true[:, c], trained(inp.z["cns"][:, c], n_cns), pfa=pfa / 3)
        for c in range(angles_true.shape[1])])                               # (3, 5)
    checks = []
    runs = None
    if (days, pfa, train_days) == (30.0, 1e-5, 1.0):
        # the paper's Fig. 5 is one run: each of its outcomes judged as one draw among ours
        runs = detail_runs(DETAIL_SEEDS, days, pfa, train_days)
        min_peak = np.asarray(runs["min_peak"])
        within = np.array([max(d) <= 600.0 for d in runs["delays_s"]])
        checks += part_of(
            "Fig. 5 shows the fault instants",
            check_event("detail peak above the threshold at every UV onset, per run",
                        "fault instants shown", min_peak > 1.0,
                        why="each onset stands out above the detector's threshold in D1..D5 "
                            "within 300 s"),
            check_event("all scheduled UV faults detected within 600 s (online detector), "
                        "per run", f"all {len(faults)}", within,
                        why="the paper marks every fault instant; 600 s is 200 UV samples, our "
                            "criterion for 'at the instant'"))
        checks.append(check_measure(
            f"detail peak at each onset / threshold, min over faults, our {min_peak.size} runs",
            f"median {np.median(min_peak):.3g} [{min_peak.min():.3g}, {min_peak.max():.3g}]",
            "smallest over the six onsets, per run: median [smallest, largest] over the runs"))
    checks += [
        check_measure(f"detail peak at each onset / threshold (min over faults), seed {seed}",
                      float(min(peaks)), "the run the chapter plots"),
        check_measure(f"scheduled UV faults detected within 600 s, seed {seed}",
                      f"{len(faults) - len(late)} of {len(faults)}", "the run the chapter plots",
                      paper=f"all {len(faults)}"),
    ]
    checks += [
        check_measure("false alarms in 30 days (alarms no fault explains)", false,
                      f"design pfa {pfa:g} per sample; {x.size} samples"),
        check_measure("orbit's own signal in the UV range details / threshold, largest level",
                      float(signal_uv.max()), "the noise-free range along the truth"),
        check_measure("orbit's own signal in the CNS angle details / threshold, largest",
                      float(signal_cns.max()),
                      f"the noise-free starlight angles along the truth, at level "
                      f"{int(np.argmax(signal_cns.max(axis=0))) + 1}"),
    ]
    note = (
        "The UV range (5000 m noise, every 3 s) with the paper's six UV fault instants as 25-km "
        "(5 sigma) steps of 5000 s. The figure shows D1..D5 of the whole series (PyWavelets, "
        "db3, symmetric boundary; offline, as the paper plots it); the detection is the online "
        f"causal detector of chapter 7 (MAD thresholds from day 1, k = {k:.2f}). Delays at the "
        f"onsets (seed {seed}): " + ", ".join(f"{d:.0f} s" for d in delays) + ". Each step shows "
        "at both ends "
        "(onset and end), as a singularity must. The orbit's smooth swing of the range reaches "
        f"{100 * signal_uv.max():.2g} % of the UV thresholds at most; the starlight angles' "
        f"own swing reaches {100 * signal_cns.max():.0f} % of the CNS thresholds (level "
        f"{int(np.argmax(signal_cns.max(axis=0))) + 1}): there the signal shares the budget "
        "with the noise."
    )
    if runs is not None:
        worst = max(max(d) for d in runs["delays_s"])
        note += (
            f" The paper's figure is one run, so its two outcomes are judged among our "
            f"{len(runs['seeds'])} single runs (seeds {runs['seeds'][0]}-{runs['seeds'][-1]}, "
            f"{runs['wall_s']:.0f} s): the smallest onset peak over the threshold is "
            f"{min(runs['min_peak']):.2f} at worst, and the slowest of the "
            f"{len(runs['seeds']) * len(faults)} onsets is first flagged {worst:.0f} s after it"
            + (" (missed at its onset: the alarm is its end's)" if worst >= faults[0].duration
               else "") + "."
        )
    data = {"t_days": t / 86400.0, "x": x, "details": details, "faults": faults,
            "delays": delays, "peaks": peaks, "events": det.events,
            "signal_uv": signal_uv, "signal_cns": signal_cns, "runs": runs}
    result = Result("wavelet-details", checks, note, data)
    if out is not None:
        fig = plot_details(t / 86400.0, x, details, [f.onset / 86400.0 for f in faults],
                           title="wavelet-details (Fan et al. 2016, Fig. 5)")
        result.figures.append(save_figure(fig, out, "wavelet-details", dpi=90, layout=False))
    return result
