"""Fault-tolerant federated navigation: the paper's fault schedule, detection, isolation, rejoining.

The main paper (Fan et al. 2016, section 4.1) injects sensor faults into the Mars run and,
with its wavelet detector, switches a faulty subsystem out of the federated filter: the
subsystem does time updates only, the master fuses the healthy ones, and the subsystem
rejoins when its fault is over. This module runs that loop on the numba kernel of
:mod:`xnavlab.mars.navigation.scenarios` with three detectors:

``"none"``
    faults go straight into the filter (the paper's Fig. 3).
``"wavelet"``
    the db3 singularity detector of :mod:`xnavlab.core.detection` (the paper's Fig. 4).
``"chi2"``
    the innovation chi-square test (the baseline): a measurement whose NIS exceeds
    ``chi2.isf(alpha, m)`` is rejected at once and isolates its subsystem.
``"combined"`` (the product's default, beyond the paper)
    :mod:`xnavlab.core.detection.combined`: the wavelet (as above, at the budget's
    ``pfa``) plus a per-sample chi-square, mean CUSUMs and variance CUSUMs on each
    subsystem's whitened innovations with an adaptive noise scale, at a stated design
    rate of false alarms per subsystem per day (``rate_per_day``, default 1).

Fault times
    Onsets and durations are seconds since the start of the run (the paper's fault
    instants, e.g. 700000 s, are counted from its start); so are the reported detections.

Scoring (:meth:`FaultTolerantRun.score`, :meth:`FaultTolerantRun.delays`)
    One rule, :func:`xnavlab.mars.faults.schedules.score_faults`: a fault is detected by an alarm
    on its subsystem raised while it acts, or when that subsystem was out of the fusion
    from before its onset to its end (delay 0); an alarm within
    :data:`~xnavlab.mars.faults.schedules.LATE_WINDOW_S` after the end of a fault nothing detected
    makes it LATE (never a detection); an alarm no fault explains is a false alarm.

The paper's schedule (:func:`~xnavlab.mars.faults.schedules.paper_schedule`)
    The paper gives only the onsets (UV 700000 ... 2400000 s, XNAV 500000 ... 2310000 s,
    CNS 600000 ... 2400000 s). Our magnitudes and durations, all arguments:
    UV range steps of 5 sigma (25 km) for 5000 s (a ranging-channel bias);
    XNAV: steps of 1e-5 s (3 km) on every pulsar at the 1st, 3rd and 5th onset (a clock
    jump of the X-ray detector's time tagging) and ramps of 2e-9 s/s (0.6 m/s, 3 km after
    the 5000 s) on pulsar 1 at the 2nd and 4th (a drifting delay of one pulsar's template);
    all for 5000 s (ten XNAV samples);
    CNS: steps of 8 sigma of the horizon sensor (0.4 deg on every starlight angle) for
    5000 s (a horizon-sensor bias). Every fault lasts 5000 s, 60 % of an orbit.

Detection per sensor (wavelet)
    UV: the raw range series (the paper's Fig. 5), db3, 5 levels, trained by MAD on the
    first ``train_days`` (1 day, 28800 samples; a fault in that day is not detected); the
    UV direction is a unit vector whose Cartesian components have geometry-dependent noise
    (none along the line of sight), so its MAD thresholds would not hold across the orbit and
    the wavelet watches the range only.
    CNS: the three raw starlight angles (one detector each, ``pfa / 3``), trained likewise.
    XNAV: 500 s per sample makes a 5-level window 21.7 h long and the raw delays swing with
    the orbit by far more than the noise between samples, so XNAV is watched on its
    *innovations* against the master's prediction, each divided by its predicted standard
    deviation ``sqrt(S_ii)`` (unit white noise when healthy, so the per-level thresholds follow
    from the filters' norms and no training is needed), db3 with 3 levels (window 36 samples,
    5 h), hold-off 12 samples.

Isolation and rejoining (our rule)
    A subsystem is switched out from the epoch of a detected onset (the flagged measurement
    is already left out). Because a wavelet detector sees changes, not levels (a step longer
    than the hold-off gives an onset and an end event with the detector clear in between),
    it rejoins only when both (1) the detector is clear and (2) the innovation chi-square
    test is quiet: the sum of the NIS of its last ``readmit_samples`` measurements (NIS
    against the master's prediction, computed while it is out) is below
    ``chi2.isf(readmit_alpha, W m)``. The chi-square detector uses the same rule (its
    "clear" is (2)). Rejoining is checked every ``check_every`` epochs (300 s) while a
    subsystem is out; UV and CNS leave at the epoch of their detected onset.

Combined detector in the loop
    Inside the compiled filter (:func:`xnavlab.mars.kernel.kernels.run_epochs`,
    :mod:`xnavlab.mars.faults.watch`): each measurement's innovation ``nu = z - h(x)`` against the
    master's one-step prediction is whitened by the Cholesky factor of ``S = H P H^T + R``
    (UV: the range and the two tangent axes of the direction, with the sensor's noise model;
    CNS: the three correlated starlight angles; XNAV: the four pulsars) and fed to the
    innovation parts of an :class:`~xnavlab.core.detection.InnovationMonitor` (and, for XNAV,
    to the innovation wavelet, on the same innovations over the adaptive scale) *before* the
    measurement is used. An alarm on a connected subsystem leaves that measurement out (as a
    gate would) and switches the subsystem out from the next epoch. Nothing is run ahead or
    rolled back: the kernel stops only after an alarm and, on the ``check_every`` grid, when
    an isolated subsystem's last innovations pass the re-admission test. The UV range and CNS
    angle wavelets run on the raw series as for ``"wavelet"``, a day at a time in a thread
    beside the filter (:class:`~xnavlab.core.detection.BlockWavelet`; the loop takes a day's
    onsets before it reaches that day). Re-admission: at the ``check_every`` grid, once the last
    ``readmit_samples`` scaled NIS sum below ``chi2.isf(readmit_alpha, W m)`` with no residual
    bias; the wavelet's "clear" is not waited for (it sees the end of a fault as a second
    change, and its window keeps XNAV's end jump for 36 samples: 23,000 s out after a 3000-s
    step), and the CUSUMs and the XNAV wavelet window restart empty at re-admission.

The loop (``"wavelet"``)
    The numba kernel of :mod:`xnavlab.mars.navigation.scenarios` runs in chunks with the ``active`` mask
    decided between them. XNAV's innovations need the filter's own prediction, so the
    kernel runs ahead speculatively (chunks of up to 7200 epochs, 6 h), the XNAV innovations
    of the chunk are then fed to the detector in order, and if it flags a connected XNAV at
    epoch ``e`` the chunk is rolled back and rerun to ``e`` with XNAV switched out from
    ``e``: the same result as deciding before every XNAV epoch (a test checks it), at the
    cost of a few reruns instead of 5184 kernel calls.

Examples
--------
>>> faults = [Fault("uv", "step", 50000.0, onset=6000.0, duration=1500.0, component=0)]
>>> ft = run_fault_tolerant(faults=faults, detector="wavelet", days=0.2, train_days=0.05)
>>> d = ft.detections[0]
>>> d["sensor"], 6000.0 <= d["detected_onset"] < 6100.0
('uv', True)
>>> bool(ft.isolated[:, 1].any())
True
"""

from __future__ import annotations

import math
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field, replace

import numpy as np

from xnavlab.core.constants import DAY, C
from xnavlab.core.detection import (
    MAX_SAMPLES,
    BlockWavelet,
    BlockWaveletSensor,
    CombinedDesign,
    Event,
    InnovationMonitor,
    chi2_threshold,
    events_from_alarms,
)
from xnavlab.core.distributions import chi2_isf, norm_isf
from xnavlab.core.faults import Fault, check_faults, format_spec, inject  # noqa: F401 - Fault: the doctest
from xnavlab.core.validate import (
    check_bool,
    check_choice,
    check_instance,
    check_int,
    check_real,
    make_rng,
    seed_after,
)
from xnavlab.mars.faults import _checks, innovations, schedules, watch
from xnavlab.mars.faults.schedules import (  # noqa: F401 - also importable from here, as before
    EARLIEST_ONSET_S,
    LATE_WINDOW_S,
    PAPER_ONSETS,
    check_schedule,
    components,
    fault_detection_delays,
    paper_schedule,
    parse_faults,
)
from xnavlab.mars.models import sensors
from xnavlab.mars.navigation import scenarios

__all__ = [
    "DETECTORS",
    "inject_inputs",
    "FaultTolerantRun",
    "run_fault_tolerant",
    "merge_events",
    "sensor_sigma",
]
# The schedules (PAPER_ONSETS, components, paper_schedule, parse_faults, check_schedule, ...) live
# in xnavlab.mars.faults.schedules (importable from here too), documented with the scoring rule.

#: The detectors of :func:`run_fault_tolerant`.
DETECTORS = ("none", "wavelet", "chi2", "combined")

_NIS_DOF_UV = 3  # range + two direction angles (the unit vector's radial part is ~0)

#: Reference of the combined detector's mean CUSUMs per subsystem, sigma: half the mean shift
#: they are tuned for. A drift reaching 5 sigma in 6000 s is 0.0025 sigma a sample at 3 s
#: (UV, CNS: alarms near 1-2 sigma, k = 0.25) and 0.42 sigma a sample at 500 s (XNAV:
#: alarms within a few samples, near 2 sigma, k = 0.5); measured in benchmarks/bench_detectors.py.
K_MEAN = {"uv": 0.25, "cns": 0.25, "xnav": 0.5}


def inject_inputs(inputs, faults, rng=None):
    """A copy of a run's :class:`~xnavlab.mars.navigation.scenarios.Inputs` with the faults in its
    measurements.

    Fault times are seconds since the start (``inputs.times[0]``). ``inputs`` must be an Inputs
    whose arrays agree (:meth:`~xnavlab.mars.navigation.scenarios.Inputs.check`).
    """
    check_instance("inputs", inputs, scenarios.Inputs, "an Inputs from scenarios.prepare()").check()
    t0 = float(inputs.times[0])
    rng = make_rng(rng)
    faults = check_faults("faults", faults)  # a spec string: read it with parse_faults first
    for f in faults:
        if f.sensor not in inputs.z:
            raise ValueError(f"faults: sensor {f.sensor!r} is not in this run "
                             f"(subsystems {tuple(inputs.z)})")
    z = {s: inject(inputs.t_meas[s] - t0, inputs.z[s], faults, s, rng) for s in inputs.z}
    return replace(inputs, z=z)


def merge_events(events):
    """Merge overlapping events (onset..cleared) of several detectors of one sensor; ``events``
    must be a list of Events, each with ``onset <= end <= cleared``
    (:func:`~xnavlab.mars.faults.schedules.check_event_list`).

    Examples
    --------
    >>> ev = merge_events([Event(1.0, 2.0, 5.0, 2.0, "a"), Event(4.0, 6.0, 9.0, 3.0, "b")])
    >>> [(e.onset, e.end, e.cleared, e.test) for e in ev]
    [(1.0, 6.0, 9.0, 'b')]
    """
    out = []  # events: refused unless a list of Events with finite times
    for e in sorted(schedules.check_event_list("events", events), key=lambda e: e.onset):
        if out and e.onset <= out[-1].cleared:
            p = out[-1]
            best = e if e.peak > p.peak else p
            out[-1] = Event(p.onset, max(p.end, e.end), max(p.cleared, e.cleared),
                            best.peak, best.test)
        else:
            out.append(e)
    return out


@dataclass(frozen=True, eq=False)
class FaultTolerantRun:
    """A faulty Mars run with a detector (frozen: ``dataclasses.replace`` checks the fields).

    Attributes
    ----------
    run : MarsRun
        The filter run (``run.metrics()``, ``run.position_error()``, ...).
    faults : list of Fault
    detector : str
    events : dict
        Detected :class:`~xnavlab.core.detection.online.Event` s per sensor (times s since the start).
    isolated : ndarray of bool, shape (n, ns)
        Whether each subsystem was switched out at each epoch.
    detection_data : dict
        Per sensor, the detector's series (``t`` s since start, ``ratio``, ``faulty``); with
        ``detector="combined"`` also ``innovations`` (N, m), the whitened innovations (unit
        white noise when healthy under the model; NaN where none was taken), ``scale`` (m,) the
        adaptive scale at the end, ``design`` (its :class:`~xnavlab.core.detection.CombinedDesign`)
        and ``innovation_events`` (the alarms of its innovation parts and, for XNAV, its
        innovation wavelet).
    wall_time : float
        Detection plus filter time, s.
    """

    run: scenarios.MarsRun
    faults: list
    detector: str
    events: dict
    isolated: np.ndarray
    detection_data: dict = field(default_factory=dict, repr=False)
    wall_time: float = 0.0

    def __post_init__(self):  # review 35o C3
        _checks.check_result(self, scenarios.MarsRun, DETECTORS, components)

    @property
    def detections(self):
        """Every detection as a dict: ``sensor``, ``detected_onset``, ``detected_end``, ``detector``."""
        out = [e.as_dict(s, self.detector) for s, evs in self.events.items() for e in evs]
        return sorted(out, key=lambda d: d["detected_onset"])

    def isolation_intervals(self):
        """Intervals each subsystem was out: dicts ``sensor``, ``out``, ``back`` (s since start;
        ``None`` when it was still out at the end)."""
        t = self.run.times - self.run.times[0]
        out = []
        for i, s in enumerate(self.run.scenario.subsystems):
            m = self.isolated[:, i].astype(np.int8)
            edges = np.flatnonzero(np.diff(np.concatenate([[0], m, [0]])))
            for a, b in zip(edges[::2], edges[1::2], strict=True):
                out.append({"sensor": s, "out": float(t[a]),
                            "back": float(t[b]) if b < t.size else None})
        return sorted(out, key=lambda d: d["out"])

    def delays(self):
        """Detection delay of each fault, s (:func:`~xnavlab.mars.faults.schedules.fault_detection_delays`:
        ``inf`` unless an alarm was raised while it acted or its subsystem was out from before
        its onset to its end; an alarm after the end is LATE, ``status`` says so)."""
        sc = self.run.scenario
        return fault_detection_delays(self.faults, self.events, self.isolation_intervals(),
                                      span=float(sc.span), dt=schedules.sample_intervals(sc))

    def score(self, settle_days=None):
        """Score the run against its injected faults (:func:`xnavlab.mars.faults.schedules.score`;
        the rule: :func:`~xnavlab.mars.faults.schedules.score_faults`)."""
        return schedules.score(self, settle_days)

    def save_npz(self, path):
        """Write the run's series (:meth:`~xnavlab.mars.navigation.scenarios.MarsRun.save_npz`) plus
        ``isolated`` (n, ns), the detector series per sensor (``det_<sensor>_t``, ``_ratio``, ``_faulty``, and
        ``_innovations`` with the combined detector) and the fault spec, to ``path`` (npz)."""
        extra = {"isolated": self.isolated, "detector": np.array(self.detector),
                 "faults": np.array(format_spec(self.faults, components(self.run.scenario))
                                    if self.faults else "")}
        for sensor, data in self.detection_data.items():
            for key in ("t", "ratio", "faulty", "innovations"):
                if isinstance(data, dict) and key in data and data[key] is not None:
                    extra[f"det_{sensor}_{key}"] = np.asarray(data[key])
        self.run.save_npz(path, **extra)

    def summary(self, settle_days=None):
        """JSON-ready: the run's summary, the detector, every injected fault (onset inside the
        run), every detection, and the score (:meth:`score`)."""
        out = self.run.summary(settle_days)
        comps = components(self.run.scenario)
        span = self.run.scenario.span
        out["detector"] = self.detector
        out["faults"] = [
            {"sensor": f.sensor, "component": f.component, "kind": f.kind,
             "magnitude": f.magnitude, "onset": f.onset,
             "duration": f.duration if math.isfinite(f.duration) else None,
             "spec": format_spec([f], comps)} for f in self.faults if f.onset < span]
        out["detections"] = self.detections
        out["isolations"] = self.isolation_intervals()
        out["score"] = self.score(settle_days)
        out["run_time_s"] = self.wall_time
        return out


def _nis_dof(sc):
    return {"xnav": len(sc.pulsars), "uv": _NIS_DOF_UV, "cns": len(sc.stars) if sc.stars else 3}


def run_fault_tolerant(scenario=None, faults=(), detector="combined", *, inputs=None,
                       pfa=1e-5, alpha=1e-5, train_days=None, readmit_samples=None,
                       readmit_alpha=0.01, readmit="quiet", xnav_level=3, xnav_holdoff=12, check_every=100,
                       rng=None, rate_per_day=1.0, adaptive=True, arm_s=EARLIEST_ONSET_S, **overrides):
    """Run the Mars scenario with faults, a detector, isolation and rejoining.

    Parameters
    ----------
    scenario : MarsScenario, optional
        Default the paper's (``**overrides`` replace fields, e.g. ``days=1``).
    faults : sequence of Fault or str
        The schedule (times s since the start) or a spec for
        :func:`~xnavlab.mars.faults.schedules.parse_faults`; checked by
        :func:`~xnavlab.mars.faults.schedules.check_schedule` (each sensor one of the run's,
        each component one of its sensor's, ``faults[i]`` named), then the training span.
    detector : {"none", "wavelet", "chi2", "combined"}
        Default ``"combined"``, the book's detector (chapter 9), as ``run mars --faults``.
    inputs : Inputs, optional
        Fault-free inputs from :func:`xnavlab.mars.navigation.scenarios.prepare` to reuse (not
        with a scenario or overrides; anything but an Inputs is refused).
    pfa : float
        Wavelet design false-alarm probability per sample and sensor, in (0, 1).
    alpha : float
        Chi-square false-alarm probability per measurement, in (0, 1).
    train_days : float, optional
        Wavelet training span of UV and CNS (their first days must be fault-free), in
        (0, days); default :func:`~xnavlab.mars.navigation.scenarios.default_settle_days` of the run.
        Ignored by ``"none"`` and ``"chi2"``, which train nothing (one call may then serve
        every detector, as the trials' paired runs do); its range is checked all the same.
    readmit_samples : dict, optional
        NIS window of the rejoining test per subsystem (default uv 100, cns 100, xnav 4),
        each in [1, MAX_SAMPLES]; a key for a subsystem the run lacks, or any with detector
        ``"none"`` (nothing rejoins) or ``readmit="clear"`` (no window test), is refused.
    readmit_alpha : float
        Significance of the rejoining test, in (0, 1); away from its default (0.01) with
        detector ``"none"`` or ``readmit="clear"`` it is refused.
    readmit : {"quiet", "clear"}
        ``"quiet"`` (default): rejoin when the detector is clear and the NIS window test passes;
        ``"clear"``: as soon as the detector is clear (the naive rule, for comparison; wavelet
        detector only, and ``readmit_samples`` or ``readmit_alpha`` given with it is refused).
    xnav_level, xnav_holdoff : int
        Levels (1..6) and hold-off (samples, in [1, 1e9]) of the XNAV innovation detector
        (wavelet and combined detectors); away from their defaults (3, 12) in a run without
        XNAV or with another detector they are refused.
    check_every : int
        Epochs between rejoining checks while a subsystem is out, in [1, MAX_SAMPLES]; away
        from its default (100) with detector ``"none"`` it is refused.
    rng : Generator or int, optional
        Extra noise of ``noise`` faults (default: from the scenario's seed).
    rate_per_day : float
        ``"combined"``: design false alarms per subsystem per day, all parts together, in
        :data:`~xnavlab.mars.faults.schedules.RATE_PER_DAY_RANGE`
        (:class:`~xnavlab.core.detection.CombinedDesign`).
    adaptive : bool
        ``"combined"``: adaptive noise scale of the innovation tests (default True).
        ``pfa``, ``alpha``, ``rate_per_day``, ``adaptive`` and ``arm_s`` away from their
        defaults with a detector that does not use them are refused, not dropped.
    arm_s : float
        ``"combined"``: seconds after the start before the innovation tests (and the XNAV
        innovation wavelet) see any innovation, in [0, days) (and at most 365 days). Default 600 s
        (:data:`~xnavlab.mars.faults.schedules.EARLIEST_ONSET_S`): the filters' start-up transient
        (fused position error 8.7 km at the start, 0.8 km after 5 min) makes consecutive
        innovations correlated, and a CUSUM armed at once sums them into an alarm within the
        first minutes (3 of 4 seeds at 63-66 s); armed at 600 s it raised 2.9 false alarms a
        day over 8 clean one-day seeds against 2.8 armed at 1800 s (design: 3). Armed later,
        a fault between 600 s and the arming reaches the filter unseen: a 6-sigma CNS step at
        1363 s armed at 1800 s pulled the master 6.5 km off, every subsystem then failed its
        tests and the run diverged; armed at 600 s it was found in 2 s. The innovation tests
        watch while the UV/CNS wavelets train (``train_days``), so a fault inside the
        training span is found too.

    Returns
    -------
    FaultTolerantRun
    """
    adaptive = check_bool("adaptive", adaptive)
    check_choice("detector", detector, DETECTORS)
    pfa = check_real("pfa", pfa, 0.0, 1.0, lo_open=True, hi_open=True)
    alpha = check_real("alpha", alpha, 0.0, 1.0, lo_open=True, hi_open=True)
    readmit_alpha = check_real("readmit_alpha", readmit_alpha, 0.0, 1.0, lo_open=True,
                               hi_open=True)
    xnav_level = check_int("xnav_level", xnav_level, 1, 6)
    xnav_holdoff = check_int("xnav_holdoff", xnav_holdoff, 1, 10**9)  # the detector's holdoff range
    check_every = check_int("check_every", check_every, 1, MAX_SAMPLES)
    check_choice("readmit", readmit, ("quiet", "clear"))
    if readmit == "clear" and detector != "wavelet":
        raise ValueError("readmit='clear' needs detector='wavelet' (the chi-square test's "
                         "'clear' is the NIS window test)")
    for key, given in (("readmit_alpha", readmit_alpha != _checks.DETECTOR_SETTINGS["readmit_alpha"][1]),
                       ("readmit_samples", readmit_samples is not None)):
        if readmit == "clear" and given:  # review 35l (5) 6: they were dropped
            raise ValueError(f"{key} is unused with readmit='clear': a subsystem rejoins as soon as "
                             f"its detector is clear, with no NIS window test; leave it out or "
                             f"use readmit='quiet'")
    rate_per_day = check_real("rate_per_day", rate_per_day, *schedules.RATE_PER_DAY_RANGE)
    arm_s = check_real("arm_s", arm_s, 0.0, schedules.MAX_DAYS * DAY)  # a run's longest span
    _checks.check_settings(detector, {"pfa": pfa, "alpha": alpha, "rate_per_day": rate_per_day,
                                      "adaptive": adaptive, "arm_s": arm_s,
                                      "readmit_alpha": readmit_alpha, "check_every": check_every})
    if inputs is None:
        inputs = scenarios.prepare(scenario, **overrides)
    else:
        check_instance("inputs", inputs, scenarios.Inputs, "an Inputs from scenarios.prepare()")
        if scenario is not None or overrides:  # its arrays: inject_inputs (Inputs.check)
            raise ValueError("pass either inputs or a scenario (with overrides), not both")
    sc = inputs.scenario
    _checks.check_settings(detector, {"xnav_level": xnav_level, "xnav_holdoff": xnav_holdoff},
                           sc.subsystems)
    win = _checks.readmit_windows(readmit_samples, detector, sc.subsystems)
    if detector == "combined" and not arm_s < sc.span:  # the message names the run's length
        raise ValueError(f"arm_s ({arm_s:g} s: the combined detector's tests start then) must be "
                         f"shorter than the run, days = {sc.days:g} ({sc.span:g} s): run at "
                         f"least days = {math.ceil(arm_s / DAY * 1e4 + 1) / 1e4:g} or lower arm_s")
    paper = isinstance(faults, str) and faults.strip() == "paper"
    if isinstance(faults, str) and not faults.strip():  # review 35o C1: as the CLI's --faults ""
        raise ValueError(f"faults is empty ({faults!r}): pass [] (or leave it out) for no faults, "
                         f"'paper', or a fault spec SENSOR[.COMPONENT]:KIND:MAGNITUDE@ONSET+DURATION")
    if isinstance(faults, str):
        try:
            faults = parse_faults(faults, sc)
        except ValueError as exc:  # parse_faults names its own parameter, spec: here, faults
            text = str(exc)
            raise ValueError(f"faults{text[4:]}" if text.startswith("spec") else text) from None
    # the run's check: the faults (sensor, component, onset, samples), then the training span
    faults = check_schedule(faults, sc, detector, train_days, paper=paper)
    if train_days is None:
        train_days = scenarios.default_settle_days(sc.days)
    if detector == "combined":
        schedules.check_armed(faults, arm_s, sc)
    rng = make_rng(seed_after(sc.seed) if rng is None else rng)
    t_start = time.perf_counter()
    faulty = inject_inputs(inputs, faults, rng)
    if detector == "none":
        res = scenarios.run(inputs=faulty)
        return FaultTolerantRun(res, faults, detector, {},
                                np.zeros((inputs.n, len(sc.subsystems)), dtype=bool),
                                {}, time.perf_counter() - t_start)
    loop = _Loop(faulty, faults, detector, pfa, alpha, train_days, win, readmit_alpha, xnav_level,
                 xnav_holdoff, check_every, rate_per_day, adaptive, arm_s)
    loop.readmit = readmit
    res = loop.run_combined() if detector == "combined" else loop.run()
    return FaultTolerantRun(res, faults, detector, loop.events(), ~loop.active,
                            loop.detection_data, time.perf_counter() - t_start)


class _Loop:
    """The closed loop: numba kernel in chunks, decisions at chunk boundaries."""

    def __init__(self, inp, faults, detector, pfa, alpha, train_days, win, readmit_alpha, xnav_level,
                 xnav_holdoff, check_every, rate_per_day=1.0, adaptive=True, arm_s=0.0):
        self.inp, self.detector, self.faults = inp, detector, faults
        self.readmit = "quiet"
        self.arm_s = arm_s         # combined: innovations before t0 + arm_s are not tested
        sc = inp.scenario
        self.subs = sc.subsystems
        self.ns = len(self.subs)
        self.t0 = float(inp.times[0])
        self.check_every = check_every
        dof = _nis_dof(sc)
        self.readmit_thr = {s: chi2_isf(readmit_alpha, win[s] * dof[s])
                            for s in self.subs}
        self.win = win
        self.readmit_alpha = readmit_alpha
        self.gate = np.array([chi2_threshold(alpha, dof[s]) if detector == "chi2" else np.inf
                              for s in self.subs])
        self.alpha_thr = {s: chi2_threshold(alpha, dof[s]) for s in self.subs}
        self.active = np.ones((inp.n, self.ns), dtype=bool)
        self.out = np.zeros(self.ns, dtype=bool)
        self.detection_data = {}
        self._events = {}
        # epoch of each measurement
        self.k_of = {s: np.flatnonzero(inp.meas_idx[:, i] >= 0) for i, s in enumerate(self.subs)}
        self.flag_of = {}          # precomputed wavelet flags (UV, CNS) per measurement
        self.onset_epochs = []     # epochs of precomputed detected onsets
        self._dj = 0               # onset_epochs[:_dj] have switched their subsystem out
        self._blocks, self._pending, self._known, self._pool = {}, [], 0, None
        self.xdet = None
        self.mon = {}
        if detector == "combined":
            self.design = {s: CombinedDesign(DAY / dt, dof[s], rate_per_day,
                                             k_mean=K_MEAN[s])
                           for s, dt in (("xnav", sc.dt_xnav), ("uv", sc.dt_uv), ("cns", sc.dt_cns))
                           if s in self.subs}
            self.mon = {s: InnovationMonitor(d, adaptive=adaptive) for s, d in self.design.items()}
            self._precompute({s: d.pfa_wavelet for s, d in self.design.items()}, train_days)
            if "xnav" in self.subs:
                self.xdet = innovations.XnavInnovationWavelet(len(sc.pulsars), xnav_level,
                                                self.design["xnav"].pfa_wavelet, xnav_holdoff)
        if detector == "wavelet":
            self._precompute(pfa, train_days)
            if "xnav" in self.subs:
                self.xdet = innovations.XnavInnovationWavelet(len(sc.pulsars), xnav_level, pfa, xnav_holdoff)

    # -- detection of UV and CNS on the raw measurements (causal batch = online)
    def _precompute(self, pfa, train_days):
        inp = self.inp
        subs = [s for s in ("uv", "cns") if s in self.subs]
        n_train = {}
        for s in subs:
            t = inp.t_meas[s]
            n_train[s] = int(np.searchsorted(t - self.t0, train_days * DAY))
            if n_train[s] < 356:
                raise ValueError(f"train_days must give at least 356 {s} samples, got "
                                 f"{n_train[s]}")
            for f in self.faults if self.detector == "wavelet" else ():
                if f.sensor == s and f.onset < train_days * DAY:
                    raise ValueError(
                        f"train_days: the wavelet detector of {s} trains on the first "
                        f"{train_days * DAY:g} s, which must be fault-free, but a {f.kind} fault "
                        f"starts at {f.onset:g} s; use a later onset or a shorter train_days")
        p = {s: pfa[s] if isinstance(pfa, dict) else pfa for s in subs}
        if "uv" in subs:
            self._blocks["uv"] = BlockWavelet(inp.t_meas["uv"], inp.z["uv"][:, 0], pfa=p["uv"],
                                              train=n_train["uv"])
        if "cns" in subs:
            self._blocks["cns"] = BlockWaveletSensor(inp.t_meas["cns"], inp.z["cns"],
                                                     pfa=p["cns"], train=n_train["cns"])
        # the series are computed in blocks of a day, in time order: in a thread of their own
        # for the combined detector (the loop takes the onsets of a block before it gets there;
        # the filter kernel releases the GIL), at once otherwise
        ends = self.t0 + DAY * np.arange(1.0, math.ceil(inp.scenario.span / DAY) + 1.0)
        ends[-1] = max(ends[-1], float(inp.times[-1]) + 1.0)
        if self.detector == "combined":
            self._pool = ThreadPoolExecutor(max_workers=1)
            self._pending = [(int(np.searchsorted(inp.times, e)),
                              self._pool.submit(self._block_onsets, e)) for e in ends]
            self._finished = self._pool.submit(self._finish_blocks)     # after the last block
        else:
            for e in ends:
                self._add_onsets(int(np.searchsorted(inp.times, e)), self._block_onsets(e))
            self._finish_blocks()

    def _block_onsets(self, t_end):
        """Compute the raw UV/CNS wavelets up to time ``t_end``; their new onsets as epochs."""
        out = []
        for s, b in self._blocks.items():
            j = b.new_onsets(int(np.searchsorted(self.inp.t_meas[s], t_end)))
            out += [(int(self.k_of[s][i]), self.subs.index(s)) for i in j]
        return sorted(out)

    def _add_onsets(self, known, onsets):
        self.onset_epochs += onsets
        self._known = known

    def _await_onsets(self, b):
        """Before deciding at epoch ``b``: the onsets up to epoch ``b + 1`` must be known."""
        while self._pending and b + 1 >= self._known:
            known, fut = self._pending.pop(0)
            self._add_onsets(known, fut.result())
        if not self._pending and self._pool is not None:
            self._pool.shutdown(wait=False)     # (its last task, the results, may still run)
            self._pool = None

    def _finish_blocks(self):
        """The wavelets' results once every block is done: flags, events, series."""
        for s, b in self._blocks.items():
            t = self.inp.t_meas[s]
            det = b.detection()
            self.flag_of[s] = det.faulty
            self._events[s] = [Event(e.onset - self.t0, e.end - self.t0, e.cleared - self.t0,
                                     e.peak, e.test) for e in det.events]
            self.detection_data[s] = {"t": t - self.t0, "ratio": det.ratio, "faulty": det.faulty}

    def events(self):
        if self.detector == "combined":
            return self._combined_events()
        ev = dict(self._events)
        if self.xdet is not None:
            ev["xnav"] = [Event(e.onset - self.t0, e.end - self.t0, e.cleared - self.t0, e.peak,
                                e.test) for e in self.xdet.tracker.all_events()]
        if self.detector == "chi2":
            for i, s in enumerate(self.subs):
                t = self.inp.t_meas[s]
                nis = self.out_arr["nis"][self.k_of[s], i]
                ratio = nis / self.alpha_thr[s]
                ev_s, _ = events_from_alarms(t - self.t0, ratio > 1.0, ratio, self.win[s],
                                             ["chi2"] * t.size)
                ev[s] = ev_s
                self.detection_data[s] = {"t": t - self.t0, "ratio": ratio}
        return ev

    # -- the kernel in chunks
    def run(self):
        inp, sc = self.inp, self.inp.scenario
        ns = self.ns
        out = scenarios.alloc_records(inp)
        self.out_arr = out
        active, gate, beta = scenarios.run_options(inp, self.active, self.gate)
        self.active = active
        ix = self.subs.index("xnav") if self.xdet is not None else -1
        x_epochs = self.k_of["xnav"] if ix >= 0 else np.zeros(0, dtype=np.int64)
        self.x_epochs = x_epochs
        self._x_set = set(x_epochs.tolist())
        # records: the book's (inp.record) plus the master after epoch e - 2 for every XNAV
        # epoch e (the prediction its innovation is taken against)
        rows = np.union1d(inp.record, np.maximum(x_epochs - 2, 0))
        rec_pos = np.full(inp.n, -1, dtype=np.int64)
        rec_pos[rows] = np.arange(rows.size)
        self.rec_pos = rec_pos
        rx, rP = np.zeros((rows.size, 6)), np.zeros((rows.size, 6, 6))
        rxl, rPl = np.zeros((rows.size, ns, 6)), np.zeros((rows.size, ns, 6))
        self.rx, self.rP = rx, rP
        state = scenarios.filter_state(inp, beta)
        xs, Ps, shares, xm, Pm = state
        self.xnav = inp.sensors["xnav"]

        def kernel(a, b):
            scenarios.run_kernel(inp, state, a, b, active, beta, gate, rec_pos,
                                  (rx, rP, rxl, rPl), out["nis"], out["flags"])

        t_start = time.perf_counter()
        self._oj = self._dj = 0
        self._xfed = 0          # XNAV measurements fed to the innovation detector
        a = 0
        while a < inp.n:
            b = self._next_boundary(a)
            snap = (xs.copy(), Ps.copy(), shares.copy(), xm.copy(), Pm.copy())
            kernel(a, b)
            e = self._feed_xnav(b, ix) if ix >= 0 else None
            if e is not None:
                # speculation failed: XNAV was connected at epoch e but its detector flags it.
                # Roll back to the chunk's start, rerun to epoch e - 2 and switch XNAV out from e.
                for arr, val in zip((xs, Ps, shares, xm, Pm), snap, strict=True):
                    arr[...] = val
                b = e - 1
                kernel(a, b)
                self.out[ix] = True
            if b < inp.n:
                self._plan_chunk(b, active)
            a = b
        wall = time.perf_counter() - t_start
        sel = rec_pos[inp.record]
        out["x"], out["P"], out["xl"], out["Pl"] = rx[sel], rP[sel], rxl[sel], rPl[sel]
        rec = inp.record
        return scenarios.MarsRun(sc, inp.times[rec], out["x"], out["P"], inp.truth[rec],
                                 out["xl"], out["Pl"], out["nis"], out["flags"], inp.times,
                                 "numba", wall)

    #: Epochs run between decisions when nothing is isolated (XNAV is checked after each
    #: chunk and the chunk rerun up to a detection: speculation).
    HORIZON = 7200

    def _next_boundary(self, a):
        """Next chunk end b > a: epochs < b run; then active[b + 1:] may change."""
        horizon = self.HORIZON
        if self.detector == "combined":
            horizon = self.HORIZON_COMBINED
        cands = [self.inp.n, a + horizon]
        if (self.out.any() and self.detector == "wavelet") or self.detector == "chi2":
            cands.append((a // self.check_every + 1) * self.check_every)
        while self._oj < len(self.onset_epochs) and self.onset_epochs[self._oj][0] - 1 <= a:
            self._oj += 1
        if self._oj < len(self.onset_epochs):
            cands.append(self.onset_epochs[self._oj][0] - 1)
        if self._pending:
            cands.append(self._known - 1)          # the onsets known so far
        b = max(a + 1, min(cands))
        if b in self._x_set and b < self.inp.n:
            # an XNAV epoch must not open a chunk: a rollback needs it after the chunk start
            b = b - 1 if b - 1 > a else b + 1
        return min(b, self.inp.n)

    def _feed_xnav(self, b, ix):
        """Feed the XNAV innovations of epochs < b to the detector; return the first epoch
        at which it flags a connected XNAV (None if none)."""
        xe = self.x_epochs
        hi = int(np.searchsorted(xe, b))
        lo = self._xfed
        if hi <= lo:
            return None
        e = xe[lo:hi]
        nu = self._innovations(e)
        for q in range(e.size):
            self._xfed = lo + q + 1
            if self.xdet.update(float(self.inp.times[e[q]]), nu[q]) and self.active[e[q], ix]:
                return int(e[q])
        return None

    def _innovations(self, e):
        """Normalised XNAV innovations at epochs e against the master predicted from e - 2."""
        inp, xs = self.inp, self.xnav
        r = self.rec_pos[np.maximum(e - 2, 0)]
        dt = inp.times[e] - inp.times[np.maximum(e - 2, 0)]
        nu, Prr = self._xnav_residual(r, dt, inp.meas_idx[e, self.subs.index("xnav")])
        # diag(H P H^T + R) with H ~ n^T / c (the other terms of eq. (4) are 1e-4 of it)
        S = np.einsum("ki,mij,kj->mk", xs.n, Prr, xs.n) / C**2 + xs.sigma**2
        return nu / np.sqrt(S)

    def _xnav_residual(self, r, dt, j):
        """XNAV innovations ``z - h(x)`` (N, m), s, of the measurements ``j`` against the master
        records ``r`` propagated by ``dt`` (N,) s, and those records' position covariances
        (N, 3, 3), m^2."""
        inp, xs = self.inp, self.xnav
        x = innovations.two_body_taylor(self.rx[r], dt[:, None])
        zp = sensors.xnav_h(x, inp.xnav_bodies[0][j], inp.xnav_bodies[1][j], xs.n,
                            xs.distance)                                # paper eq. (1)
        return inp.z["xnav"][j] - zp, self.rP[r][:, :3, :3]

    def _decide(self, c):
        """Epochs < c are done (active[c] is spent): set each subsystem's state from c + 1."""
        nxt = c + 1
        if nxt >= self.inp.n:
            return
        # isolation by the chi-square gate and rejoining are decided on a fixed grid of
        # epochs (multiples of check_every), whatever the chunking
        periodic = c % self.check_every == 0
        # wavelet on raw UV/CNS: every detected onset up to epoch c + 1 not decided yet switches
        # its subsystem out, also one at an epoch no chunk ended before (an XNAV epoch cannot
        # end a chunk, so an onset on the epoch after it was masked for its chunk alone)
        while self._dj < len(self.onset_epochs) and self.onset_epochs[self._dj][0] <= nxt:
            k, i = self.onset_epochs[self._dj]
            self._dj += 1
            if self.detector == "combined" and not self.out[i]:
                self.out_since[self.subs[i]] = k
            self.out[i] = True
        for i, s in enumerate(self.subs):
            if not periodic:
                continue
            if self.detector == "combined":
                if self.out[i] and self._quiet_combined(c, i, s):
                    self.out[i] = False
                    self._readmit(s)
                continue
            recent = self.out_arr["flags"][max(0, c - self.check_every):c, i]
            if self.detector == "chi2" and np.any(recent == 2):
                self.out[i] = True             # the gate rejected a measurement
            if self.out[i] and self._clear(nxt, i, s) and (self.readmit == "clear"
                                                           or self._quiet(c, i, s)):
                self.out[i] = False

    def _clear(self, k, i, s):
        """Whether the detector of subsystem i is clear after the measurements up to epoch k."""
        if s in self.flag_of:
            j = int(np.searchsorted(self.k_of[s], k, side="right")) - 1
            return j < 0 or not bool(self.flag_of[s][j])
        if s == "xnav" and self.xdet is not None:
            return not self.xdet.tracker.faulty
        return True

    def _quiet(self, c, i, s):
        k = self.k_of[s]
        hi = int(np.searchsorted(k, c))
        if hi < self.win[s]:
            return False
        nis = self.out_arr["nis"][k[hi - self.win[s]:hi], i]
        return bool(np.nansum(nis) < self.readmit_thr[s])

    def _plan_chunk(self, b, active):
        """Decide at epoch ``b`` and mask the coming chunk ``(b, next boundary]``: the
        switched-out subsystems, and each detected onset inside it from its epoch on."""
        self._decide(b)
        b2 = self._next_boundary(b)
        active[b + 1:b2 + 1] = ~self.out
        for k, i in self.onset_epochs[self._oj:]:
            if k > b2:
                break
            if k > b:           # a detected onset inside the coming chunk
                active[k:b2 + 1, i] = False

    def _since_start(self, events, prefix=""):
        """Events with times in s since the start of the run (the trackers keep absolute t)."""
        t0 = self.t0
        return [Event(e.onset - t0, e.end - t0, e.cleared - t0, e.peak, prefix + e.test)
                for e in events]

    # -- the combined detector: inside the compiled loop (xnavlab.mars.faults.watch)
    #: Longest kernel call of the combined run, epochs (a call also ends after an alarm, before
    #: a wavelet onset, at the end of the wavelets' computed days and where an isolated
    #: subsystem may rejoin; the result does not depend on it).
    HORIZON_COMBINED = 100_000

    def run_combined(self):
        inp, sc = self.inp, self.inp.scenario
        out = scenarios.alloc_records(inp)
        self.out_arr = out
        active, gate, beta = scenarios.run_options(inp, self.active, None)
        self.active = active
        rec = inp.record
        rec_pos = np.full(inp.n, -1, dtype=np.int64)
        rec_pos[rec] = np.arange(rec.size)
        records = (out["x"], out["P"], out["xl"], out["Pl"])
        state = scenarios.filter_state(inp, beta)
        zq = {s: norm_isf(self.readmit_alpha / (2 * self.design[s].m)) for s in self.subs}
        self.watch = watch.Watch(self.subs, self.mon, self.xdet,
                                 {s: inp.t_meas[s].size for s in self.subs}, self.t0 + self.arm_s,
                                 (self.win, self.readmit_thr, zq, self.check_every))
        self.watch.set_out(self.out)
        self.ys = self.watch.ys
        arrays = self.watch.arrays()
        self.out_since = {s: 0 for s in self.subs}
        t_start = time.perf_counter()
        self._oj = self._dj = 0
        self._x_set = set()
        try:
            a = 0
            while a < inp.n:
                b = self._next_boundary(a)
                e = scenarios.run_kernel(inp, state, a, b, active, beta, gate, rec_pos, records,
                                         out["nis"], out["flags"], arrays)
                if e >= 0:
                    # the kernel stopped after epoch e: an alarm there (that measurement was left
                    # out, the subsystem is out from e + 1) or a subsystem may rejoin at e + 1
                    b = e + 1
                    for s in self.watch.after_stop(float(inp.times[e])):
                        i = self.subs.index(s)
                        self.out[i] = True
                        self.out_since[s] = e
                        active[e, i] = False     # reported out from the epoch it was left out at
                if b < inp.n:
                    self._await_onsets(b)
                    self._plan_chunk(b, active)
                    self.watch.set_out(self.out)
                a = b
        except BaseException:   # the wavelets' thread stops too
            if self._pool is not None:
                self._pool.shutdown(cancel_futures=True)
            raise
        self._await_onsets(inp.n)
        self._finished.result()
        wall = time.perf_counter() - t_start
        for s in self.subs:
            self.mon[s].scale = self.watch.scale(s)
            d = self.detection_data.setdefault(s, {"t": inp.t_meas[s] - self.t0})
            d.update(innovations=self.ys[s], scale=self.mon[s].scale, design=self.design[s],
                     innovation_events=self._since_start(self.watch.events(s)))
        return scenarios.MarsRun(sc, inp.times[rec], out["x"], out["P"], inp.truth[rec],
                                 out["xl"], out["Pl"], out["nis"], out["flags"], inp.times,
                                 "numba", wall)

    def _quiet_combined(self, c, i, s):
        k = self.k_of[s]
        lo, hi = np.searchsorted(k, [self.out_since[s] + 1, c])
        w = self.win[s]
        if hi - lo < w:                  # W measurements taken since the isolation
            return False
        y = self.ys[s][hi - w:hi] / self.watch.scale(s)    # (not fed while out: a fixed scale)
        q = np.sum(np.square(y), axis=1)
        if not (np.all(np.isfinite(q)) and np.sum(q) < self.readmit_thr[s]):
            return False
        # and no residual bias: |sum_i y_c[i]| / sqrt(W) below the two-sided normal quantile
        zq = norm_isf(self.readmit_alpha / (2 * y.shape[1]))
        return bool(np.all(np.abs(y.sum(axis=0)) < zq * math.sqrt(w)))

    def _readmit(self, s):
        """Fresh CUSUMs and an empty XNAV wavelet window at re-admission."""
        self.watch.readmit(s)

    def _combined_events(self):
        ev = {}
        for s in self.subs:
            parts = list(self._events.get(s, []))
            parts += self._since_start(self.watch.events(s))
            ev[s] = merge_events(parts)
        return ev


# ----------------------------------------------------------------------------- sizes


def sensor_sigma(sensor, scenario=None):
    """One noise standard deviation of a sensor in its SI unit: UV range (m), the horizon
    sensor (rad, common to the CNS angles), the first pulsar's delay (s).

    ``sensor`` is one of ``"xnav"``, ``"uv"``, ``"cns"``; ``scenario`` a MarsScenario
    (default the paper's) whose noise levels are read.

    Examples
    --------
    >>> sensor_sigma("uv")
    5000.0
    """
    check_choice("sensor", sensor, scenarios.SUBSYSTEMS)
    sc = scenarios.check_scenario("scenario", scenario)  # a dict or a string: one line
    if sensor == "uv":
        return float(sc.sigma_range_m)
    if sensor == "cns":
        return math.radians(sc.sigma_horizon_deg)
    return float(sc.sensors()["xnav"].sigma[0])
