"""Fault schedules: the paper's, the command line's, which faults a run can use, and the score.

A fault is a :class:`xnavlab.core.faults.Fault` with times in seconds since the start of
the run. :func:`paper_schedule` is the main paper's (Fan et al. 2016, section 4.1) with our
magnitudes and durations; :func:`parse_faults` reads the command line's spec;
:func:`check_schedule` refuses a fault the run cannot use; :func:`score_faults` is the
scoring rule, and :func:`score`, :func:`fault_detection_delays` and :func:`trial_outcome`
apply it to a run. The fault-tolerant loop itself is :mod:`xnavlab.mars.faults.fault_tolerance`,
which re-exports the schedules' names.

Scoring (:func:`score_faults`)
    The one place every Pd, delay and false-alarm rate of the book comes from. An *alarm* is a
    detector event raised on a sensor (a subsystem: UV, CNS, XNAV), at the
    event's onset. A fault acts on ``[onset, end)`` (a spike: on its one sample).

    * DETECTED: an alarm on its sensor is raised while it acts (delay: the first one's,
      from the onset), or its subsystem was already out of the fusion before the onset and
      stays out to the end (*out at onset*, delay 0; out at the onset but back in before the
      end is not credited).
    * LATE: not detected, and an alarm on its sensor is raised within
      :data:`LATE_WINDOW_S` after the end. Reported in its own field (``late_s``, the
      trials' ``late``), never as a detection: the whole fault went into the filter first.
    * MISSED: neither.
    * A FALSE ALARM is an alarm that no fault explains: not raised while a fault of its
      sensor acts nor within :data:`LATE_WINDOW_S` after one's end. Late alarms and a
      detected fault's end alarms are therefore not false alarms; the false-alarm rate is
      the one a detector's design rate promises.

    The only window is :data:`LATE_WINDOW_S` (XNAV 18000 s, UV and CNS 2000 s), which
    decides whether an alarm after a fault's end is put down to it (late, or an end alarm)
    or is a false alarm, and bounds the "inside the faults" window of the fused error.
"""

from __future__ import annotations

import math

import numpy as np

from xnavlab.core.constants import DAY
from xnavlab.core.faults import MAX_SIZE, Fault, check_faults, format_spec, parse_spec
from xnavlab.core.validate import check_bool, check_choice, check_instance, check_real, check_text, shown
from xnavlab.mars.faults import _checks
from xnavlab.mars.navigation import scenarios
from xnavlab.mars.timing import pulsar_specs

__all__ = [
    "PAPER_ONSETS",
    "MIN_FAULT_TAIL_S",
    "MIN_STEP_SIGMA",
    "MAX_DAYS",
    "RATE_PER_DAY_RANGE",
    "check_armed",
    "EARLIEST_ONSET_S",
    "LATE_WINDOW_S",
    "STATUSES",
    "MATCHES",
    "components",
    "sample_intervals",
    "paper_schedule",
    "parse_faults",
    "check_schedule",
    "RunTooShort",
    "TRAIN_SAMPLES",
    "scoring_span",
    "score_faults",
    "check_event_list",
    "fault_detection_delays",
    "score",
    "trial_outcome",
]

#: The paper's fault instants, s after the start (Fan et al. 2016, section 4.1).
PAPER_ONSETS = {
    "uv": (700000.0, 1200000.0, 1700000.0, 2200000.0, 2300000.0, 2400000.0),
    "xnav": (500000.0, 1000000.0, 1500000.0, 2000000.0, 2310000.0),
    "cns": (600000.0, 900000.0, 1500000.0, 2100000.0, 2400000.0),
}

#: The earliest fault onset the combined detector takes, s: the filter has settled by then
#: (fused position error 8.7 km at the start, 0.8 km after 5 minutes). Its innovation tests
#: watch from ``arm_s`` (by default this same 600 s) and the UV/CNS wavelets from the end of
#: their training (their MAD-based training is robust to a fault inside it), so a fault
#: between 600 s and the end of the training span is found by the innovation tests.
EARLIEST_ONSET_S = 600.0

#: The longest run of the command line, days (``run mars --days``).
MAX_DAYS = 365.0

#: The design false-alarm rates the combined detector takes, per subsystem per day: below one
#: false alarm in 1,000 days its CUSUM's average run length passes 1e12 samples at 10 samples a
#: second (and 5e-324 underflowed to a probability of 0, refused under another name).
RATE_PER_DAY_RANGE = (1e-3, 100.0)

#: The smallest UV or CNS step of :func:`paper_schedule`, in units of the sensor's noise: a
#: thousandth of it (a smaller step is no fault; 5e-324 underflowed to a zero-size fault).
MIN_STEP_SIGMA = 1e-3

#: Seconds a fault's onset must leave before the run's end for the message of
#: :func:`check_schedule` to suggest a long enough run (one XNAV integration).
MIN_FAULT_TAIL_S = 5000.0


def components(scenario=None):
    """Measurement component names per sensor, for :func:`xnavlab.core.faults.parse_spec`.

    ``xnav``: the pulsars as ``B0531``, ``B1937``, ... (or an index ``0..3``);
    ``uv``: ``range``, ``ux``, ``uy``, ``uz``; ``cns``: ``angle0``, ``angle1``, ``angle2``.

    Examples
    --------
    >>> components()["uv"]
    ('range', 'ux', 'uy', 'uz')
    """
    sc = scenarios.check_scenario("scenario", scenario)
    n_stars = len(sc.stars) if sc.stars else 3
    comps = {
        "xnav": pulsar_specs.fault_names(sc.pulsars),  # B1937, J0030, ... (any pulsar)
        "uv": ("range", "ux", "uy", "uz"),
        "cns": tuple(f"angle{i}" for i in range(n_stars)),
    }
    return {s: comps[s] for s in sc.subsystems}


def paper_schedule(uv_step_sigma=5.0, uv_duration=5000.0, xnav_step_s=1.0e-5,
                   xnav_ramp=2.0e-9, xnav_duration=5000.0, cns_step_sigma=8.0,
                   cns_duration=5000.0, scenario=None):
    """The paper's fault instants with our magnitudes and durations (module notes).

    Parameters
    ----------
    uv_step_sigma : float
        UV range step, in units of the range noise (5000 m), in [1e-3, 1000] (a thousandth of
        the noise at the least: below it the step is no fault, and a subnormal one underflowed).
    uv_duration, xnav_duration, cns_duration : float
        Fault durations, s, in (0, 1e5] (the paper's onsets are 1e5 s apart at the closest).
    xnav_step_s : float
        XNAV delay step, s, on every pulsar (1e-5 s = 3 km), nonzero, in [-1, 1].
    xnav_ramp : float
        XNAV delay drift, s/s, on pulsar 1 (2e-9 s/s = 0.6 m/s), nonzero, in [-1e-3, 1e-3].
    cns_step_sigma : float
        Horizon-sensor step on every starlight angle, in units of its noise (0.05 deg), in
        [1e-3, 1000] (as ``uv_step_sigma``).
    scenario : MarsScenario, optional
        Supplies the noise levels.

    Returns
    -------
    list of Fault

    Examples
    --------
    >>> fs = paper_schedule()
    >>> len(fs), fs[0].sensor, fs[0].magnitude
    (16, 'xnav', 1e-05)
    """
    sc = scenarios.check_scenario("scenario", scenario)
    uv_step_sigma = check_real("uv_step_sigma", uv_step_sigma, MIN_STEP_SIGMA, 1000.0)
    cns_step_sigma = check_real("cns_step_sigma", cns_step_sigma, MIN_STEP_SIGMA, 1000.0)
    for name, v in (("uv_duration", uv_duration), ("xnav_duration", xnav_duration),
                    ("cns_duration", cns_duration)):
        check_real(name, v, 0.0, 1e5, lo_open=True)
    xnav_step_s = check_real("xnav_step_s", xnav_step_s, -1.0, 1.0)
    xnav_ramp = check_real("xnav_ramp", xnav_ramp, -1e-3, 1e-3)
    for name, v, lim in (("xnav_step_s", xnav_step_s, "1"), ("xnav_ramp", xnav_ramp, "0.001")):
        if v == 0.0:
            raise ValueError(f"{name} must be a nonzero real number in [-{lim}, {lim}], got 0.0 "
                             "(a zero-size fault injects nothing)")
    faults = []
    for i, t in enumerate(PAPER_ONSETS["xnav"]):
        if i % 2 == 0:
            faults.append(Fault("xnav", "step", xnav_step_s, t, xnav_duration))
        else:
            faults.append(Fault("xnav", "ramp", xnav_ramp, t, xnav_duration, component=1))
    sig_h = math.radians(sc.sigma_horizon_deg)
    uv_m, cns_rad = uv_step_sigma * sc.sigma_range_m, cns_step_sigma * sig_h
    for name, size, noise in (("uv_step_sigma", uv_m, "sigma_range_m"),
                              ("cns_step_sigma", cns_rad, "sigma_horizon_deg")):
        if not size > 0.0:  # a subnormal noise level of the scenario's: the step underflows
            raise ValueError(f"scenario.{noise} ({getattr(sc, noise)!r}) times {name} underflows "
                             f"to a step of {size!r}: give the scenario a real noise level")
    for t in PAPER_ONSETS["uv"]:
        faults.append(Fault("uv", "step", uv_m, t, uv_duration, component=0))
    for t in PAPER_ONSETS["cns"]:
        faults.append(Fault("cns", "step", cns_rad, t, cns_duration))
    return sorted(faults, key=lambda f: f.onset)


def parse_faults(spec, scenario=None):
    """``"paper"`` -> :func:`paper_schedule`; otherwise :func:`xnavlab.core.faults.parse_spec`.

    Every number of an item is used or refused: a stuck output's MAGNITUDE must be written 0
    (the output freezes at its last fault-free value: a size would go unused) and a spike's
    DURATION 0 (it acts on one sample: a length would go unused); the messages lead with
    ``spec`` and name the item.

    Examples
    --------
    >>> [f.component for f in parse_faults("uv.range:step:5000@700000+3000,xnav.1:ramp:2e-9@5e5+5000")]
    [0, 1]
    """
    sc = scenarios.check_scenario("scenario", scenario)
    if not isinstance(spec, str) or not spec.strip():
        raise ValueError(f"spec must be 'paper' or a fault spec SENSOR[.COMPONENT]:KIND:"
                         f"MAGNITUDE@ONSET+DURATION[,...], got {shown(spec)}")
    if spec.strip() == "paper":
        return paper_schedule(scenario=sc)
    items = [item.strip() for item in spec.split(",")]
    if "xnav" in sc.subsystems:  # a pulsar named in full (xnav.B1937+21): its '+' is no duration's
        for name, short in zip(pulsar_specs.names(sc.pulsars), components(sc)["xnav"], strict=True):
            spec = spec.replace(f"xnav.{name}:", f"xnav.{short}:")
    faults = parse_spec(spec, components(sc))
    for item, f in zip(items, faults, strict=True):
        if f.kind == "spike" and f.duration != 0.0:  # a stuck one's size: Fault refuses it
            raise ValueError(f"spec: bad fault item {item!r}: a spike fault's DURATION must be 0 "
                             f"(it acts on one sample: a duration would go unused), got "
                             f"{f.duration:g}")
    return faults


def check_schedule(faults, scenario, detector="combined", train_days=None, paper=False):
    """Refuse a fault the run cannot use: one ``ValueError`` naming the fault, the span and the fix.

    This is the check :func:`~xnavlab.mars.faults.fault_tolerance.run_fault_tolerant` makes of
    its faults and training span before any run. A fault's sensor must be one of the run's
    subsystems and its component one of that sensor's (:func:`components`); the faults are
    checked first, then the training span: the UV/CNS wavelets of the ``"wavelet"`` and
    ``"combined"`` detectors train on ``train_days``, which must hold their first 356 samples
    (:data:`TRAIN_SAMPLES`). When ``train_days`` is left out (``min(1, days / 2)``) and that
    is too short, the message leads with ``days``: the run is too short. A fault is used
    when its onset lies inside the run, ``[0, span)`` s since the start,
    and it acts on at least one sample of its sensor (a step of 300 s between two XNAV
    samples 500 s apart would be injected as nothing and scored as missed);
    with the paper's ``"wavelet"`` detector a UV or CNS fault must start after the wavelets'
    fault-free training span (``train_days``), and with the ``"combined"`` detector any
    fault from :data:`EARLIEST_ONSET_S` (600 s) on is taken (its innovation tests watch
    while the wavelets train). A fault may end
    after the run (it is then cut at the end, which is a use). The check and the score agree
    on the end: a sample counts when it lies before the run's end, ``t < span``, as in
    :func:`scoring_span` (``[onset, min(end, span))``), so a fault that would act only on a
    sample at the end itself (``t = span``) is refused here rather than always scored
    missed.

    Parameters
    ----------
    faults : sequence of Fault
        The schedule, times s since the start.
    scenario : MarsScenario
        The run (its ``span``, s).
    detector : str
        One of :data:`~xnavlab.mars.faults.fault_tolerance.DETECTORS`.
    train_days : float, optional
        Training span of the UV/CNS wavelets, days, in (0, days) of the run; default
        :func:`~xnavlab.mars.navigation.scenarios.default_settle_days` of the run, as the run's.
        The ``"none"`` and ``"chi2"`` detectors train nothing and ignore it (a range is still
        checked), so that one call may be made for every detector.
    paper : bool
        The schedule is the paper's (the message then says how many days it needs).

    Examples
    --------
    >>> sc = scenarios.MarsScenario(days=5)
    >>> try:
    ...     check_schedule(paper_schedule(), sc, paper=True)
    ... except ValueError as exc:
    ...     print(str(exc).split("; ")[1])
    run at least --days 27.84 (this run: 5 days)
    """
    if scenario is None:
        raise ValueError("scenario must be a MarsScenario (the run the faults are for), got None")
    scenario = scenarios.check_scenario("scenario", scenario)
    check_choice("detector", detector, ("none", "wavelet", "chi2", "combined"))
    if train_days is not None:  # the run's own range: a span it can train on
        train_days = check_real("train_days", train_days, 0.0, scenario.days, lo_open=True,
                                hi_open=True)
    paper = check_bool("paper", paper)
    span = float(scenario.span)
    comps = components(scenario)
    faults = check_faults("faults", _in_run(faults, comps), comps)
    late = [f for f in faults if not 0.0 <= f.onset < span]
    if late and paper:
        last = max(f.onset for f in faults)
        need = (last + MIN_FAULT_TAIL_S) / DAY
        raise ValueError(f"faults: the paper's schedule has onsets up to {last:.0f} s "
                         f"({last / DAY:.2f} days); run at least --days {math.ceil(need * 100) / 100:g} "
                         f"(this run: {span / DAY:g} days)")
    for f in late:
        if f.onset < 0.0:
            raise ValueError(f"faults: {format_spec([f], comps)} starts at {f.onset:.6g} s, before "
                             f"the run's start: an onset is s since the start, in [0, {span:.0f})")
        need = math.ceil((f.onset + MIN_FAULT_TAIL_S) / DAY * 100) / 100
        longer = f" or run at least --days {need:g}" if need <= MAX_DAYS else ""
        raise ValueError(f"faults: {format_spec([f], comps)} starts at {f.onset:.6g} s, outside this "
                         f"run [0, {span:.0f}) s ({span / DAY:g} days): move its onset into the "
                         f"run{longer}")
    for f in faults:  # a ramp's size by the run's end, refused before any run (not an overflow)
        acts = min(f.end, span) - f.onset
        if f.kind == "ramp" and abs(f.magnitude) * acts > MAX_SIZE:
            raise ValueError(f"faults: {format_spec([f], comps)} reaches {abs(f.magnitude) * acts:.3g} "
                             f"by {f.onset + acts:.0f} s, beyond {MAX_SIZE:g} in the measurement's SI "
                             f"unit (xnavlab.core.faults.MAX_SIZE): a rate of at most "
                             f"{MAX_SIZE / acts:.3g} per s over this run")
    dts = sample_intervals(scenario)
    for f in faults:
        if f.sensor not in dts:
            continue                     # inject_inputs names a sensor the run lacks
        dt = dts[f.sensor]
        first = _first_sample(f.onset, dt)
        last = dt * math.floor(span / dt + 1e-9)  # the last sample, at or before the end
        if last >= span * (1.0 - 1e-12):          # one at the end: scored times are < span
            last -= dt
        if first > last or (f.kind != "spike" and first >= f.end):
            why = (f"lasts {f.duration:.6g} s between two {f.sensor} samples (one every "
                   f"{dt:g} s): make it last at least {dt:g} s or move it onto a sample"
                   if first <= last else f"comes after the last {f.sensor} sample before "
                   f"the run's end ({last:.0f} s; the sample at the end, {span:.0f} s, is not "
                   f"scored: scoring_span cuts a fault at the end)")
            raise ValueError(f"faults: {format_spec([f], comps)} acts on no sample: it {why}")
    train_days = _check_training(scenario, detector, train_days)
    if detector == "wavelet":
        for f in faults:
            if f.sensor in ("uv", "cns") and f.onset < train_days * DAY:
                raise ValueError(
                    f"faults: {format_spec([f], comps)} starts at {f.onset:.6g} s, inside the "
                    f"{train_days * DAY:.0f}-s span on which the {f.sensor} wavelet detector trains "
                    f"(it must be fault-free); move its onset to {train_days * DAY:.0f} s or later, "
                    f"or use detector combined")
    if detector == "combined":
        for f in faults:
            if f.onset < EARLIEST_ONSET_S:
                raise ValueError(
                    f"faults: {format_spec([f], comps)} starts at {f.onset:.6g} s, before the "
                    f"filter has settled ({EARLIEST_ONSET_S:.0f} s: its start-up error, kilometres, "
                    f"hides a fault from any detector); move its onset to "
                    f"{EARLIEST_ONSET_S:.0f} s or later")
    return faults


#: Samples the UV and CNS wavelets train on at least (their MAD thresholds need them).
TRAIN_SAMPLES = 356


def _in_run(faults, comps):
    """``faults`` (a list once read) with every Fault's sensor among the run's subsystems and
    its component among the sensor's (``comps``), else one ValueError naming ``faults[i]``."""
    if isinstance(faults, list | tuple) or (hasattr(faults, "__iter__") and not _checks.not_1d(faults)
                                           and not isinstance(faults, str | bytes | dict)):
        faults = list(faults)
        for i, f in enumerate(faults):
            if not isinstance(f, Fault):
                continue                   # check_faults names it
            if f.sensor not in comps:
                raise ValueError(f"faults[{i}]: sensor {f.sensor!r} is not in this run (its "
                                 f"subsystems: {', '.join(comps)})")
            names = comps[f.sensor]
            if f.component is not None and not f.component < len(names):
                raise ValueError(f"faults[{i}]: component must be in [0, {len(names) - 1}] for "
                                 f"sensor {f.sensor!r} ({', '.join(names)}), got {f.component}")
    return faults


def _check_training(scenario, detector, train_days):
    """The training span, days (the run's default when None), checked to hold the UV/CNS
    wavelets' first :data:`TRAIN_SAMPLES` samples with the detectors that train them."""
    given = train_days is not None
    if not given:
        train_days = scenarios.default_settle_days(scenario.days)
    if detector not in ("wavelet", "combined"):
        return train_days
    span = float(scenario.span)
    for s, dt in sample_intervals(scenario).items():
        if s not in ("uv", "cns"):
            continue
        n_all = int(math.floor(span / dt + 1e-9))   # the run's samples at k dt, k >= 1
        t = np.round(dt * np.arange(1, min(n_all, TRAIN_SAMPLES) + 1), 6)
        n = int(np.searchsorted(t, train_days * DAY))
        if n >= TRAIN_SAMPLES:
            continue
        need = (float(t[-1]) if n_all >= TRAIN_SAMPLES else TRAIN_SAMPLES * dt) / DAY * 1.001
        if given or need >= 1.0:
            raise ValueError(f"train_days = {train_days:g} days gives the {s} wavelet detector "
                             f"{n} samples to train on; it needs at least {TRAIN_SAMPLES}: give "
                             f"train_days >= {_up(need):g} (and days above it)")
        # the suggestions rounded up: a rounded-down days (0.0247) was itself too short
        raise RunTooShort(scenario.days, f"is too short for the {detector} detector: its {s} "
                          f"wavelet trains on the first min(1, days / 2) = {train_days:g} days "
                          f"({n} samples) and needs {TRAIN_SAMPLES}", _up(2.0 * need), _up(need))
    return train_days


class RunTooShort(ValueError):
    """:func:`check_schedule`'s refusal of a run too short for its wavelets' default training
    span; its parts are kept so that the CLI can name the run's length as the user gave it.

    Parameters
    ----------
    days : float
        The run's length, days, in (0, :data:`MAX_DAYS`].
    why : str
        What is too short, from "is too short ...".
    need_days, need_train_days : float
        The shortest run (up to twice :data:`MAX_DAYS`) and ``train_days`` that would do, days.

    Examples
    --------
    >>> str(RunTooShort(0.02, "is too short", 0.0248, 0.0124))
    'days = 0.02 is too short: run at least 0.0248 days, or give train_days >= 0.0124'
    """

    def __init__(self, days, why, need_days, need_train_days):
        self.days, self.why = check_real("days", days, 0.0, MAX_DAYS, lo_open=True), check_text("why", why)
        self.need_days = check_real("need_days", need_days, 0.0, 2.0 * MAX_DAYS, lo_open=True)
        self.need_train_days = check_real("need_train_days", need_train_days, 0.0, MAX_DAYS, lo_open=True)
        super().__init__(f"days = {self.days:g} {why}: run at least {self.need_days:g} days, or "
                         f"give train_days >= {self.need_train_days:g}")


def _up(x):
    """``x`` > 0 rounded up to three significant digits (a bound that still holds when shown)."""
    step = 10.0 ** (math.floor(math.log10(x)) - 2)
    return float(f"{math.ceil(x / step - 1e-9) * step:.3g}")


def check_armed(faults, arm_s, scenario):
    """Refuse a fault the combined detector cannot see: one that has ended (a spike: acted)
    before its tests arm at ``arm_s`` (s) would be scored missed (review 35f).

    Examples
    --------
    >>> sc = scenarios.MarsScenario(days=0.05)
    >>> check_armed(parse_faults("uv.range:step:25000@1000+100", sc), 600.0, sc)
    >>> try:
    ...     check_armed(parse_faults("uv.range:step:25000@1000+100", sc), 2000.0, sc)
    ... except ValueError as exc:
    ...     print(str(exc).split(", ")[1].split(":")[0])
    before the combined detector's tests arm (arm_s = 2000 s)
    """
    faults = _fault_list("faults", faults)
    arm_s = check_real("arm_s", arm_s, 0.0, MAX_DAYS * DAY)  # a run's longest span
    scenario = check_instance("scenario", scenario, scenarios.MarsScenario, "a MarsScenario")
    for f in faults:
        end = f.onset if f.kind == "spike" else f.onset + f.duration
        if end < arm_s:
            raise ValueError(f"faults: {format_spec([f], components(scenario))} ends at "
                             f"{end:.6g} s, before the combined detector's tests arm (arm_s = "
                             f"{arm_s:g} s): no test would see it; move it after arm_s or lower "
                             f"arm_s")


#: How long after a fault's end an alarm on its sensor is still put down to the fault, s
#: (module notes, "Scoring"): as the fault's LATE alarm when nothing found it while it
#: acted, as its END ALARM when something did; a later alarm is a false alarm. It bounds
#: the detectors' answer to a fault's end. XNAV: 18000 s, the window of its three-level
#: db3 innovation wavelet (36 samples of 500 s), which an end jump leaves after that long
#: by construction. UV and CNS: 2000 s, measured over the 2160 faulty runs of the shipped
#: detector table: alarms on the faulty sensor come at 10 to 1900 times the sensor's alarm
#: rate before the onset in the first 500 s after the end (the raw wavelets' five-level
#: window is 156 samples, 468 s), at 3.3 times it for CNS in 1000-1500 s (the innovation
#: tests after re-admission), and at 0.2-1.6 times it from 2000 s on; XNAV's last excess
#: was at 6000-8000 s (the wavelet's late answer). An alarm that noise raises at the background rate
#: (UV 5e-6/s, CNS 7e-6/s, XNAV 3e-6/s) falls in one window with probability 1-6 %. The
#: same span after each fault is the "inside the faults" window of the fused error in
#: :func:`score`.
LATE_WINDOW_S = {"xnav": 18000.0, "uv": 2000.0, "cns": 2000.0}

#: The scored outcome of a fault (:func:`score_faults`).
STATUSES = ("detected", "late", "missed")
#: What an alarm is to the faults (:func:`score_faults`).
MATCHES = ("detection", "late", "during fault", "after end", "false alarm")


def sample_intervals(scenario=None):
    """Sampling interval of each subsystem, s (its samples fall at ``k dt``, ``k >= 1``).

    Examples
    --------
    >>> sample_intervals()
    {'xnav': 500.0, 'uv': 3.0, 'cns': 3.0}
    """
    sc = scenarios.check_scenario("scenario", scenario)
    dts = {"xnav": sc.dt_xnav, "uv": sc.dt_uv, "cns": sc.dt_cns}
    return {s: float(dts[s]) for s in sc.subsystems}


def _first_sample(onset, dt):
    """The first sample time at or after ``onset`` on the grid ``k dt``, ``k >= 1``."""
    return dt * max(1.0, math.ceil(onset / dt - 1e-9))


def scoring_span(fault, dt=None, span=math.inf):
    """The alarm times that detect ``fault``: ``(onset, stop)``, the half-open ``[onset, stop)``, s.

    ``stop`` is the fault's end, ``onset + duration`` (it acts on the samples in ``[onset,
    end)``, :meth:`xnavlab.core.faults.Fault.active`), cut at the run's end ``span``. A spike
    acts on one sample, the first at or after its onset (its duration is ignored): ``stop``
    is half a sampling interval after that sample, so that only an alarm raised on the
    spiked sample itself detects it (a later one comes after the spike went into the filter).

    Parameters
    ----------
    fault : Fault
        Times s since the start.
    dt : dict of str to float, optional
        Sampling interval per sensor, s (:func:`sample_intervals`); read for a spike only,
        but checked whenever given: a dict whose every value is a real number in (0, inf).
    span : float
        The run's length, s, in (0, inf]; it must end after the fault's onset (else the
        window would be inverted, ``stop < onset``, and match alarms before the fault).

    Returns
    -------
    tuple of float
        ``onset < stop``.

    Examples
    --------
    >>> scoring_span(Fault("xnav", "spike", 1e-5, 61001.0, 0.0), dt={"xnav": 500.0})
    (61001.0, 61750.0)
    >>> scoring_span(Fault("uv", "step", 1.0, 100.0, 50.0))
    (100.0, 150.0)
    """
    if not isinstance(fault, Fault):
        raise ValueError(f"fault must be a Fault, got {shown(fault)}")
    span = _span(span)
    if dt is not None:
        if not isinstance(dt, dict):
            raise ValueError(f"dt must be a dict of sensor -> sampling interval, s, got {shown(dt)}")
        for sensor, step in dt.items():
            check_real(f"dt[{sensor!r}]", step, 0.0, lo_open=True, hi_open=True)
    if not span > fault.onset:
        raise ValueError(f"span must end after the fault's onset ({fault.onset:.6g} s): a fault "
                         f"that starts at or after the run's end is not in it, got {span:.6g}")
    if fault.kind == "spike":
        if dt is None or fault.sensor not in dt:
            raise ValueError(f"dt must give the sampling interval of sensor {fault.sensor!r} "
                             "to score a spike (one sample)")
        step = float(dt[fault.sensor])
        return fault.onset, min(_first_sample(fault.onset, step) + 0.5 * step, span)
    return fault.onset, min(fault.end, span)


def _fault_list(name, faults):
    """``faults`` as a list of Fault (``check_faults``), a numpy array that is no 1-D list
    (``np.array(1.0)``) refused too, naming ``name``."""
    if _checks.not_1d(faults):
        raise ValueError(f"{name} must be a sequence of Fault, got {shown(faults)}")
    return check_faults(name, faults)


def _span(span):
    """A run's span, s: a real number > 0 (inf: no end)."""
    if isinstance(span, bool) or not isinstance(span, int | float | np.integer | np.floating) \
            or not span > 0:
        raise ValueError(f"span must be a real number in (0, inf], s, got {span!r}")
    return float(span)


def score_faults(faults, events, isolations=(), *, span=math.inf, dt=None):
    """The scoring rule: every fault detected, late or missed; every alarm matched or false.

    This is the one place the book's detection numbers are decided (Pd, delays, false
    alarms per day: :func:`score`, the trials of :mod:`xnavlab.mars.studies.trials`, the ROC
    curves of :mod:`xnavlab.mars.studies.roc`). An *alarm* is a detector event's onset, the time
    it was raised (every detector here is causal); it belongs to a *sensor*, i.e. a
    subsystem, not to a measurement component: a subsystem is isolated as a whole, and the
    combined detector's whitened innovations mix the components of correlated sensors.

    A fault acts on the alarm times ``[onset, stop)`` of :func:`scoring_span` (its end, cut
    at the run's end; a spike: its one sample).

    DETECTED (``delay_s`` from the onset)
        an alarm on its sensor is raised in ``[onset, stop)``: the delay is the first one's;
        or *out at onset*: its subsystem was already switched out of the fusion before the
        onset (an earlier alarm) and stays out until ``stop`` or later, so that none of the
        fault reached the filter: delay 0, ``out_at_onset`` True. Out at the onset but back
        in before the end does not count (the rest of the fault went into the filter): the
        fault is then detected only by an alarm raised while it acts.
    LATE (``late_s`` after ``stop``)
        not detected, and an alarm on its sensor is raised in ``[stop, stop +
        LATE_WINDOW_S)`` (:data:`LATE_WINDOW_S`). Never a detection: the whole fault went
        into the filter first.
    MISSED
        neither.

    Every alarm gets one ``match`` (:data:`MATCHES`), the first that applies:
    ``"detection"`` (the alarm that detected a fault), ``"late"`` (the first alarm after the
    end of a fault that nothing detected, within :data:`LATE_WINDOW_S`), ``"during fault"``
    (any other alarm raised while a fault of its sensor acts), ``"after end"`` (any other
    alarm within :data:`LATE_WINDOW_S` after a fault's end: a detected step's end event),
    ``"false alarm"`` (the rest). Late alarms are counted apart and are *not* false alarms:
    the false-alarm count is the alarms that no fault explains, the quantity a detector's
    design rate promises; what a late alarm costs shows as the fault's LATE status and as
    the time its subsystem stays out after the end (:func:`score`, ``out_after_end_s``).

    Parameters
    ----------
    faults : sequence of Fault
        Times s since the start.
    events : dict of str to list of xnavlab.core.detection.Event
        The detector's events per sensor (``"uv"``, ``"cns"``, ``"xnav"``: another key is
        refused, its alarms would go unscored), same time base.
    isolations : sequence of dict, optional
        The run's isolation intervals (``sensor`` as in ``events``, ``out``, ``back``: s,
        ``back`` after ``out``, or None when still out at the end;
        :meth:`~xnavlab.mars.faults.fault_tolerance.FaultTolerantRun.isolation_intervals`).
    span : float
        The run's length, s (a fault that outlasts it is scored up to it).
    dt : dict of str to float, optional
        Sampling interval per sensor (needed to score a spike; :func:`sample_intervals`).

    Returns
    -------
    dict
        ``faults``: per fault ``sensor``, ``kind``, ``onset``, ``end`` (``stop``), ``status``,
        ``detected``, ``delay_s`` (None unless detected), ``detected_onset`` (the detecting
        alarm, the onset when out at onset, None), ``out_at_onset``, ``late_s`` (None unless
        late); ``alarms``: per event, in order of onset, ``sensor``, ``onset``, ``match``,
        ``fault`` (index into ``faults`` or None).

    Examples
    --------
    >>> from xnavlab.core.detection import Event
    >>> f = Fault("xnav", "step", 3e-6, onset=61000.0, duration=8000.0)
    >>> late = score_faults([f], {"xnav": [Event(69500.0, 69500.0, 70000.0, 2.0, "cusum")]})
    >>> late["faults"][0]["status"], late["faults"][0]["late_s"], late["alarms"][0]["match"]
    ('late', 500.0, 'late')
    >>> out = score_faults([f], {}, [{"sensor": "xnav", "out": 60000.0, "back": 71000.0}])
    >>> out["faults"][0]["status"], out["faults"][0]["delay_s"], out["faults"][0]["out_at_onset"]
    ('detected', 0.0, True)
    """
    faults = _fault_list("faults", faults)
    span = _span(span)
    events = _check_events(events)
    isolations = _checks.check_isolations(isolations, LATE_WINDOW_S)
    for f in faults:
        if f.sensor not in LATE_WINDOW_S:
            raise ValueError(f"faults: sensor {f.sensor!r} has no late window "
                             f"(known: {', '.join(LATE_WINDOW_S)})")
    stops = [scoring_span(f, dt, span)[1] for f in faults]
    alarms = sorted(((e.onset, s) for s, evs in events.items() for e in evs), key=lambda a: a[0])
    role = {}                            # alarm index -> (match, fault index): its main role
    per = []
    for k, (f, stop) in enumerate(zip(faults, stops, strict=True)):
        on = [j for j, (_, s) in enumerate(alarms) if s == f.sensor]
        inside = [j for j in on if f.onset <= alarms[j][0] < stop]
        after = [j for j in on if stop <= alarms[j][0] < stop + LATE_WINDOW_S[f.sensor]]
        covered = any(iv["sensor"] == f.sensor and iv["out"] < f.onset
                      and (iv["back"] is None or iv["back"] >= stop) for iv in isolations)
        rec = {"sensor": f.sensor, "kind": f.kind, "onset": f.onset, "end": stop,
               "status": "missed", "detected": False, "delay_s": None, "detected_onset": None,
               "out_at_onset": covered, "late_s": None}
        if covered:
            rec.update(status="detected", detected=True, delay_s=0.0, detected_onset=f.onset)
        elif inside:
            t = alarms[inside[0]][0]
            rec.update(status="detected", detected=True, delay_s=t - f.onset, detected_onset=t)
            if role.get(inside[0], ("",))[0] != "detection":    # a detection outranks
                role[inside[0]] = ("detection", k)                # another fault's late
        elif after:
            rec.update(status="late", late_s=alarms[after[0]][0] - stop)
            if role.get(after[0], ("",))[0] != "detection":
                role[after[0]] = ("late", k)
        per.append(rec)
    out = []
    for j, (t, s) in enumerate(alarms):
        if j not in role:
            mine = [k for k, f in enumerate(faults)
                    if f.sensor == s and f.onset <= t < stops[k] + LATE_WINDOW_S[s]]
            during = [k for k in mine if t < stops[k]]
            role[j] = (("during fault", during[0]) if during else ("after end", mine[0]) if mine
                       else ("false alarm", None))
        out.append({"sensor": s, "onset": t, "match": role[j][0], "fault": role[j][1]})
    return {"faults": per, "alarms": out}


def check_event_list(name, events):
    """``events`` as a list of :class:`~xnavlab.core.detection.Event` with a finite onset and end
    and a real peak (``cleared`` and ``peak`` may be inf, not NaN), else one ValueError naming
    ``name`` (a string, a dict or a number is no list; ``name[i]`` an item).

    Examples
    --------
    >>> from xnavlab.core.detection import Event
    >>> check_event_list("events", (Event(1.0, 2.0, 3.0, 4.0, "a"),))[0].onset
    1.0
    >>> check_event_list("events", "abc")
    Traceback (most recent call last):
    ...
    ValueError: events must be a list of detection Events (xnavlab.core.detection.Event), got 'abc'
    """
    from xnavlab.core.detection import Event

    check_text("name", name)
    what = "detection Event (xnavlab.core.detection.Event)"
    if isinstance(events, str | bytes | dict) or not hasattr(events, "__iter__") or _checks.not_1d(events):
        raise ValueError(f"{name} must be a list of {what.replace('Event ', 'Events ')}, "
                         f"got {shown(events)}")
    events = list(events)
    real = int | float | np.integer | np.floating
    for i, e in enumerate(events):  # cleared may be inf (still flagging at the end), not NaN
        times = (e.onset, e.end, e.cleared, e.peak) if isinstance(e, Event) else ()
        if not times or not all(isinstance(v, real) and not isinstance(v, bool) for v in times) \
                or not (math.isfinite(e.onset) and math.isfinite(e.end) and not math.isnan(e.cleared)
                        and not math.isnan(e.peak)):
            raise ValueError(f"{name}[{i}] must be a {what} with finite onset and end and a "
                             f"real peak, got {shown(e)}")
        if not e.onset <= e.end <= e.cleared:  # an event ends after it opens, clears after
            raise ValueError(f"{name}[{i}] must have onset <= end <= cleared (times of one "
                             f"alarm, in order), got onset {e.onset:g}, end {e.end:g}, cleared "
                             f"{e.cleared:g}")
    return events


def _check_events(events):
    """A detector's events: a dict of sensor -> sequence of objects with an ``onset``, s."""
    if not isinstance(events, dict):
        raise ValueError(f"events must be a dict of sensor -> list of detection Events, got "
                         f"{type(events).__name__} {shown(events)}")
    for sensor, evs in events.items():
        if sensor not in LATE_WINDOW_S:  # its alarms would be matched to no fault, unscored
            raise ValueError(f"events[{sensor!r}]: {sensor!r} is not a sensor (subsystem) this "
                             f"rule scores (known: {', '.join(LATE_WINDOW_S)})")
        if isinstance(evs, str | dict) or not hasattr(evs, "__iter__") or _checks.not_1d(evs):
            raise ValueError(f"events[{sensor!r}] must be a list of detection Events, got "
                             f"{shown(evs)}")
        for i, e in enumerate(evs):
            onset = getattr(e, "onset", None)
            if isinstance(onset, bool) or not isinstance(onset, int | float | np.integer
                                                         | np.floating) or not math.isfinite(onset):
                raise ValueError(f"events[{sensor!r}][{i}] must be a detection Event (with an "
                                 f"onset, s: xnavlab.core.detection.Event), got {shown(e)}")
    return events


def fault_detection_delays(faults, events, isolations=(), *, span=math.inf, dt=None):
    """For each fault, the delay from its onset to its detection (:func:`score_faults`).

    Parameters
    ----------
    faults, events, isolations, span, dt
        As :func:`score_faults`.

    Returns
    -------
    list of dict
        ``sensor``, ``kind``, ``onset``, ``delay`` (s; ``inf`` unless detected: an alarm
        raised after the fault's end is LATE, not a detection), ``detected_onset`` (``inf``
        unless detected), ``status`` (``"detected"``, ``"late"`` or ``"missed"``),
        ``late_s`` (s after the end; None unless late), ``out_at_onset``.

    Examples
    --------
    >>> f = Fault("uv", "step", 1.0, onset=10.0, duration=5.0)
    >>> from xnavlab.core.detection import Event
    >>> fault_detection_delays([f], {"uv": [Event(12.0, 13.0, 20.0, 2.0, "level 1")]})[0]["delay"]
    2.0
    >>> fault_detection_delays([f], {"uv": [Event(16.0, 16.0, 20.0, 2.0, "level 1")]})[0]["status"]
    'late'
    """
    res = score_faults(faults, events, isolations, span=span, dt=dt)["faults"]
    return [{"sensor": r["sensor"], "kind": r["kind"], "onset": r["onset"],
             "delay": r["delay_s"] if r["detected"] else math.inf,
             "detected_onset": r["detected_onset"] if r["detected"] else math.inf,
             "status": r["status"], "late_s": r["late_s"], "out_at_onset": r["out_at_onset"]}
            for r in res]


# ----------------------------------------------------------------------------- the run


def _out_after(sensor, stop, isolations, span):
    """Seconds ``sensor`` was out after ``stop`` in isolations opened before ``stop`` plus its
    late window (the one over the end, and those of its late or end alarms)."""
    total = 0.0
    for iv in isolations:
        back = span if iv["back"] is None else min(iv["back"], span)
        if iv["sensor"] == sensor and iv["out"] < stop + LATE_WINDOW_S[sensor] and back > stop:
            total += back - max(stop, iv["out"])
    return total


def score(ft, settle_days=None):
    """Score a fault-tolerant run against its injected faults (the rule: :func:`score_faults`).

    Parameters
    ----------
    ft : FaultTolerantRun
        The run (:func:`xnavlab.mars.faults.fault_tolerance.run_fault_tolerant`).
    settle_days : float, optional
        Start of the RMS windows, days (default that of the run's metrics).

    Returns
    -------
    dict
        ``faults`` (list of dicts: ``spec``, ``sensor``, ``kind``, ``onset``, ``end`` (the
        end of its scoring span, s), ``status`` (``"detected"``, ``"late"``, ``"missed"``),
        ``detected``, ``delay_s`` (None unless detected), ``out_at_onset`` (detected at delay
        0 because its subsystem was out of the fusion from before the onset to the end),
        ``late_s`` (s after the end of a LATE fault's first alarm, else None),
        ``out_after_end_s`` (time its subsystem was out after the end in isolations opened
        before ``end + LATE_WINDOW_S``; None when the fault outlasts the run),
        ``still_out_at_end``),
        ``detections`` (every alarm: the detection's dict plus ``match`` (:data:`MATCHES`),
        ``fault`` (the spec it is put down to, or None) and ``false_alarm``),
        ``counts`` (per subsystem: ``faults``, ``detected``, ``late``, ``missed``, ``alarms``,
        ``false_alarms``), ``fused_error`` (``inside_faults_m`` over ``[onset, end +
        LATE_WINDOW_S)`` of every fault, ``outside_faults_m``, ``settle_days``; None where a
        window is empty).
    """
    sc = _check_run(ft, "run", "faults", "events", "isolation_intervals").run.scenario
    comps = components(sc)
    span = float(sc.span)
    t_rec = ft.run.t - ft.run.times[0]   # records (the error series)
    isol = ft.isolation_intervals()
    core = score_faults(ft.faults, ft.events, isol, span=span, dt=sample_intervals(sc))
    specs = [format_spec([f], comps) for f in ft.faults]
    faults = []
    for f, r, spec in zip(ft.faults, core["faults"], specs, strict=True):
        i = sc.subsystems.index(f.sensor)
        ends = r["end"] < span
        faults.append({"spec": spec, **{k: r[k] for k in ("sensor", "kind", "onset", "end", "status",
                                                          "detected", "delay_s", "out_at_onset",
                                                          "late_s")},
                       "out_after_end_s": _out_after(f.sensor, r["end"], isol, span) if ends else None,
                       "still_out_at_end": bool(ends and ft.isolated[-1, i])})
    detections = []
    for det, a in zip(ft.detections, core["alarms"], strict=True):
        detections.append({**det, "match": a["match"],
                           "fault": None if a["fault"] is None else specs[a["fault"]],
                           "false_alarm": a["match"] == "false alarm"})
    counts = {}
    for s in sc.subsystems:
        fs = [f for f in faults if f["sensor"] == s]
        ds = [d for d in detections if d["sensor"] == s]
        counts[s] = {"faults": len(fs), **{k: sum(f["status"] == k for f in fs) for k in STATUSES},
                     "alarms": len(ds), "false_alarms": sum(d["false_alarm"] for d in ds)}
    settle = ft.run.metrics(settle_days)["settle_days"]
    pe = ft.run.position_error()
    inside = np.zeros(t_rec.size, dtype=bool)
    for f, r in zip(ft.faults, core["faults"], strict=True):
        inside |= (t_rec >= f.onset) & (t_rec < r["end"] + LATE_WINDOW_S[f.sensor])
    keep = ft.run.t_days >= settle

    def rms(mask):
        return float(np.sqrt(np.mean(pe[mask] ** 2))) if mask.any() else None

    return {"faults": faults, "detections": detections, "counts": counts,
            "fused_error": {"inside_faults_m": rms(keep & inside),
                            "outside_faults_m": rms(keep & ~inside), "settle_days": settle}}


def _check_run(ft, *needs):
    """``ft`` if it has what a FaultTolerantRun has (``needs``), else one ValueError naming it."""
    if not all(hasattr(ft, a) for a in needs):
        raise ValueError(f"ft must be a FaultTolerantRun (the result of run_fault_tolerant), got "
                         f"{shown(ft)}")
    return ft


def trial_outcome(ft, armed_from_s=0.0):
    """The Monte Carlo record of a run with one fault (:func:`score`): what the trials of
    :mod:`xnavlab.mars.studies.trials` and :mod:`xnavlab.mars.studies.roc` store.

    Parameters
    ----------
    ft : FaultTolerantRun
        A run with exactly one fault.
    armed_from_s : float
        False alarms are counted from this time on, s since the start (the detectors'
        training span), in [0, MAX_DAYS days].

    Returns
    -------
    dict
        ``detected``, ``delay_s`` (None unless detected), ``out_at_onset``, ``late`` (bool),
        ``late_s`` (s after the end, None unless late), ``false_alarms`` (alarms no fault
        explains raised from ``armed_from_s`` on; late alarms are not among them),
        ``time_out_s`` (``out_after_end_s``, 0 when the fault outlasts the run).
    """
    armed_from_s = check_real("armed_from_s", armed_from_s, 0.0, MAX_DAYS * DAY)
    if len(_check_run(ft, "faults").faults) != 1:
        raise ValueError(f"ft must hold exactly one fault, got {len(ft.faults)}")
    sc = score(ft)
    f = sc["faults"][0]
    fa = sum(d["false_alarm"] and d["detected_onset"] >= armed_from_s for d in sc["detections"])
    return {"detected": bool(f["detected"]), "delay_s": f["delay_s"],
            "out_at_onset": bool(f["out_at_onset"]), "late": f["status"] == "late",
            "late_s": f["late_s"], "false_alarms": int(fa),
            "time_out_s": float(f["out_after_end_s"] or 0.0)}
