"""Fault schedules: the paper's, the command line's, which faults a run can use, and the score.

A fault is a :class:`xnavlab.core.faults.Fault` with times in seconds since the start of
the run. :func:`paper_schedule` is the main paper's (Fan et al. 2016, section 4.1) with our
magnitudes and durations; :func:`parse_faults` reads the command line's spec;
:func:`check_schedule` refuses a fault the run cannot use; :func:`fault_detection_delays`
and :func:`score` set the detections of a run against its faults. The fault-tolerant loop
itself is :mod:`xnavlab.mars.fault_tolerance`, which re-exports these names.
"""

from __future__ import annotations

import math

import numpy as np

from xnavlab.core.constants import DAY
from xnavlab.core.faults import Fault, format_spec, parse_spec
from xnavlab.core.validate import check_real
from xnavlab.mars import pulsar_specs, scenarios

__all__ = [
    "PAPER_ONSETS",
    "MIN_FAULT_TAIL_S",
    "EARLIEST_ONSET_S",
    "MATCH_WINDOW",
    "components",
    "paper_schedule",
    "parse_faults",
    "check_schedule",
    "fault_detection_delays",
    "score",
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
    sc = scenario if scenario is not None else scenarios.MarsScenario()
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
        UV range step, in units of the range noise (5000 m), in (0, 1000].
    uv_duration, xnav_duration, cns_duration : float
        Fault durations, s, in (0, 1e5] (the paper's onsets are 1e5 s apart at the closest).
    xnav_step_s : float
        XNAV delay step, s, on every pulsar (1e-5 s = 3 km).
    xnav_ramp : float
        XNAV delay drift, s/s, on pulsar 1 (2e-9 s/s = 0.6 m/s).
    cns_step_sigma : float
        Horizon-sensor step on every starlight angle, in units of its noise (0.05 deg).
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
    sc = scenario if scenario is not None else scenarios.MarsScenario()
    uv_step_sigma = check_real("uv_step_sigma", uv_step_sigma, 0.0, 1000.0, lo_open=True)
    cns_step_sigma = check_real("cns_step_sigma", cns_step_sigma, 0.0, 1000.0, lo_open=True)
    for name, v in (("uv_duration", uv_duration), ("xnav_duration", xnav_duration),
                    ("cns_duration", cns_duration)):
        check_real(name, v, 0.0, 1e5, lo_open=True)
    xnav_step_s = check_real("xnav_step_s", xnav_step_s, -1.0, 1.0)
    xnav_ramp = check_real("xnav_ramp", xnav_ramp, -1e-3, 1e-3)
    faults = []
    for i, t in enumerate(PAPER_ONSETS["xnav"]):
        if i % 2 == 0:
            faults.append(Fault("xnav", "step", xnav_step_s, t, xnav_duration))
        else:
            faults.append(Fault("xnav", "ramp", xnav_ramp, t, xnav_duration, component=1))
    sig_h = math.radians(sc.sigma_horizon_deg)
    for t in PAPER_ONSETS["uv"]:
        faults.append(Fault("uv", "step", uv_step_sigma * sc.sigma_range_m, t, uv_duration,
                            component=0))
    for t in PAPER_ONSETS["cns"]:
        faults.append(Fault("cns", "step", cns_step_sigma * sig_h, t, cns_duration))
    return sorted(faults, key=lambda f: f.onset)


def parse_faults(spec, scenario=None):
    """``"paper"`` -> :func:`paper_schedule`; otherwise :func:`xnavlab.core.faults.parse_spec`.

    Examples
    --------
    >>> [f.component for f in parse_faults("uv.range:step:5000@700000+3000,xnav.1:ramp:2e-9@5e5+5000")]
    [0, 1]
    """
    sc = scenario if scenario is not None else scenarios.MarsScenario()
    if isinstance(spec, str) and spec.strip() == "paper":
        return paper_schedule(scenario=sc)
    if isinstance(spec, str) and "xnav" in sc.subsystems:
        # a pulsar may be named in full (xnav.B1937+21): its '+' is not the duration's
        for name, short in zip(pulsar_specs.names(sc.pulsars), components(sc)["xnav"],
                               strict=True):
            spec = spec.replace(f"xnav.{name}:", f"xnav.{short}:")
    return parse_spec(spec, components(sc))


def check_schedule(faults, scenario, detector="combined", train_days=1.0, paper=False):
    """Refuse a fault the run cannot use: one ``ValueError`` naming the fault, the span and the fix.

    A fault is used when its onset lies inside the run, ``[0, span)`` s since the start;
    with the paper's ``"wavelet"`` detector a UV or CNS fault must start after the wavelets'
    fault-free training span (``train_days``), and with the ``"combined"`` detector any
    fault from :data:`EARLIEST_ONSET_S` (600 s) on is taken (its innovation tests watch
    while the wavelets train). A fault may end
    after the run (it is then cut at the end, which is a use).

    Parameters
    ----------
    faults : sequence of Fault
        The schedule, times s since the start.
    scenario : MarsScenario
        The run (its ``span``, s).
    detector : str
        One of :data:`~xnavlab.mars.fault_tolerance.DETECTORS`.
    train_days : float
        Training span of the UV/CNS wavelets, days.
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
    span = float(scenario.span)
    faults = list(faults)
    late = [f for f in faults if not 0.0 <= f.onset < span]
    if late and paper:
        last = max(f.onset for f in faults)
        need = (last + MIN_FAULT_TAIL_S) / DAY
        raise ValueError(f"faults: the paper's schedule has onsets up to {last:.0f} s "
                         f"({last / DAY:.2f} days); run at least --days {math.ceil(need * 100) / 100:g} "
                         f"(this run: {span / DAY:g} days)")
    comps = components(scenario)
    for f in late:
        need = (f.onset + MIN_FAULT_TAIL_S) / DAY
        raise ValueError(f"faults: {format_spec([f], comps)} starts at {f.onset:.6g} s, outside this "
                         f"run [0, {span:.0f}) s ({span / DAY:g} days): move its onset into the run or "
                         f"run at least --days {math.ceil(need * 100) / 100:g}")
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


#: How long after a fault's end a detection still counts as detecting it (an end-jump
#: detection), s: the response time of each sensor's detector (XNAV: the 3-level window of
#: 36 samples at 500 s), at least 6000 s.
MATCH_WINDOW = {"xnav": 18000.0, "uv": 6000.0, "cns": 6000.0}


def fault_detection_delays(faults, events, window=None):
    """For each fault, the delay from its onset to the first detected onset at or after it.

    A detection counts if it opens in ``[onset, end + window)``: a detection of the fault's
    end jump (a slow ramp) still counts, with its long delay.

    Parameters
    ----------
    faults : sequence of Fault
    events : dict of str to list of xnavlab.core.detection.Event
        Per sensor, times in the faults' time base.
    window : float or dict, optional
        Seconds after the end; default :data:`MATCH_WINDOW` (6000 s for other sensors).

    Returns
    -------
    list of dict
        ``sensor``, ``kind``, ``onset``, ``delay`` (s; ``inf`` when missed),
        ``detected_onset``.

    Examples
    --------
    >>> f = Fault("uv", "step", 1.0, onset=10.0, duration=5.0)
    >>> from xnavlab.core.detection import Event
    >>> fault_detection_delays([f], {"uv": [Event(12.0, 13.0, 20.0, 2.0, "level 1")]})[0]["delay"]
    2.0
    """
    out = []
    for f in faults:
        if isinstance(window, dict):
            w = window.get(f.sensor, 6000.0)
        elif window is None:
            w = MATCH_WINDOW.get(f.sensor, 6000.0)
        else:
            w = check_real("window", window, 0.0)
        end = f.onset + (f.duration if math.isfinite(f.duration) else 0.0) + w
        hits = [e.onset for e in events.get(f.sensor, []) if f.onset <= e.onset < end]
        first = min(hits) if hits else math.inf
        out.append({"sensor": f.sensor, "kind": f.kind, "onset": f.onset,
                    "delay": first - f.onset, "detected_onset": first})
    return out


# ----------------------------------------------------------------------------- the run


def score(ft, settle_days=None):
    """Score a fault-tolerant run against its injected faults.

    Every fault is detected or missed (a detection of its sensor opening in ``[onset,
    end + MATCH_WINDOW)``, as :func:`fault_detection_delays`), with its delay and the
    time its subsystem stayed out of the fusion after the fault ended; every detection
    is matched to a fault or marked a false alarm; counts per subsystem; the fused
    position error (RMS after ``settle_days``) inside and outside the fault windows
    (``[onset, end + MATCH_WINDOW)`` of any fault).

    Parameters
    ----------
    ft : FaultTolerantRun
        The run (:func:`xnavlab.mars.fault_tolerance.run_fault_tolerant`).
    settle_days : float, optional
        Start of the RMS windows, days (default that of the run's metrics).

    Returns
    -------
    dict
        ``faults`` (list of dicts: ``spec``, ``sensor``, ``detected``, ``delay_s``,
        ``out_at_onset`` (its subsystem was already out of the fusion, e.g. after a false
        alarm, so the fault never entered it), ``out_after_end_s``, ``still_out_at_end``),
        ``detections`` (list of dicts: the detection plus ``fault`` (the spec it matches,
        or None) and ``false_alarm``),
        ``counts`` (per subsystem: ``faults``, ``detected``, ``missed``, ``detections``,
        ``false_alarms``), ``fused_error`` (``inside_faults_m``, ``outside_faults_m``,
        ``settle_days``; None where a window is empty).
    """
    sc = ft.run.scenario
    comps = components(sc)
    t = ft.run.times - ft.run.times[0]  # epochs (the isolation mask's rows)
    t_rec = ft.run.t - ft.run.times[0]   # records (the error series)
    windows = {f: (f.onset, f.onset + (f.duration if math.isfinite(f.duration) else sc.span)
                   + MATCH_WINDOW.get(f.sensor, 6000.0)) for f in ft.faults}
    faults = []
    for f, d in zip(ft.faults, ft.delays(), strict=True):
        found = math.isfinite(d["delay"])
        end = f.onset + (f.duration if math.isfinite(f.duration) else sc.span)
        i = sc.subsystems.index(f.sensor)
        after = (t >= end) & ft.isolated[:, i]
        rejoin = np.flatnonzero((t >= end) & ~ft.isolated[:, i])
        out_after = (float(t[rejoin[0]] - end) if rejoin.size else float(t[-1] - end)) \
            if after.any() else 0.0
        faults.append({"spec": format_spec([f], comps), "sensor": f.sensor, "kind": f.kind,
                       "onset": f.onset, "detected": found,
                       # out at the last epoch before the onset (an alarm at the onset
                       # epoch itself marks that epoch isolated: that is a detection)
                       "out_at_onset": bool(ft.isolated[max(np.searchsorted(t, f.onset) - 1,
                                                            0), i]),
                       "delay_s": d["delay"] if found else None,
                       "out_after_end_s": max(out_after, 0.0) if end < sc.span else None,
                       "still_out_at_end": bool(end < sc.span and ft.isolated[-1, i])})
    detections = []
    for det in ft.detections:
        hit = next((f for f, (a, b) in windows.items()
                    if f.sensor == det["sensor"] and a <= det["detected_onset"] < b), None)
        detections.append({**det, "fault": None if hit is None else format_spec([hit], comps),
                           "false_alarm": hit is None})
    counts = {}
    for s in sc.subsystems:
        fs = [f for f in faults if f["sensor"] == s]
        ds = [d for d in detections if d["sensor"] == s]
        counts[s] = {"faults": len(fs), "detected": sum(f["detected"] for f in fs),
                     "missed": sum(not f["detected"] for f in fs), "detections": len(ds),
                     "false_alarms": sum(d["false_alarm"] for d in ds)}
    settle = ft.run.metrics(settle_days)["settle_days"]
    pe = ft.run.position_error()
    inside = np.zeros(t_rec.size, dtype=bool)
    for a, b in windows.values():
        inside |= (t_rec >= a) & (t_rec < b)
    keep = ft.run.t_days >= settle

    def rms(mask):
        return float(np.sqrt(np.mean(pe[mask] ** 2))) if mask.any() else None

    return {"faults": faults, "detections": detections, "counts": counts,
            "fused_error": {"inside_faults_m": rms(keep & inside),
                            "outside_faults_m": rms(keep & ~inside), "settle_days": settle}}
