"""Isolation statistics of SOS and DOS over fault location, kind and size (Monte Carlo).

:func:`isolation_monte_carlo` simulates every case's seeded runs in vectorised batches
(:func:`xnavlab.attitude.simulation.diagnose_batch`, a chunk of about 0.5 GB at a time; the
outcomes are those of one batch, bit for bit) and counts correct isolations, missed
detections, false alarms and delays; :func:`isolation_table` prints the rows as a
Markdown table, SOS and DOS side by side. :func:`seeded_outcomes` keeps every run's outcome
instead of the rates: the runs of one fault, seed by seed, each equal to
:func:`~xnavlab.attitude.simulation.simulate` with that seed (the chapter's plotted run among
them), for judging a paper's single run as one draw among ours.
"""

from __future__ import annotations

import math

import numpy as np

from xnavlab.attitude import _checks
from xnavlab.attitude.motion import truth_motion
from xnavlab.attitude.sensors import DEFAULT_MAGNITUDES, DEG_PER_H, LOCATIONS, MAX_FACTOR, make_fault
from xnavlab.attitude.simulation import (
    SimConfig,
    check_faults_in_run,
    diagnose_batch,
    make_config,
    simulate_sensors,
)
from xnavlab.core.plotting import markdown_table
from xnavlab.core.validate import (
    check_choice,
    check_int,
    check_items,
    check_real,
    check_records,
    check_seeds,
    make_rng,
    shown,
)

#: Where the default SimConfig arms its detectors (t_cal[1], s): the earliest default onset.
_DEFAULT_T_ARM = SimConfig.__dataclass_fields__["t_cal"].default[1]
#: The latest onset of the default config (duration onset + 30 s, at most MAX_SAMPLES of 0.1 s,
#: rounded down to 10 s so that it is shown as is: 159969.9 would be printed 159970).
_MAX_DEFAULT_ONSET = 159960.0

__all__ = [
    "isolation_monte_carlo",
    "isolation_table",
    "seeded_outcomes",
]


def isolation_monte_carlo(
    n_runs=10,
    *,
    locations=LOCATIONS,
    kinds=("step", "ramp"),
    sizes=(0.3, 1.0, 10.0),
    onset=50.0,
    config=None,
    rng=None,
):
    """Isolation statistics of SOS and DOS over fault location, kind and size.

    Every case runs ``n_runs`` seeded runs (all cases in vectorised batches), plus
    ``n_runs`` fault-free runs. Per case and method:

    ``correct``
        fraction detected after the onset and isolated to the true location (for the
        fault-free runs: fraction that stayed silent);
    ``missed``
        fraction never detected;
    ``false_alarm``
        fraction detected before the onset (any detection for fault-free runs);
    ``delay_s``
        mean detection delay of the runs detected after the onset (``inf`` if none).

    Parameters
    ----------
    n_runs : int
        Runs per case, >= 1, such that the batch (``n_runs`` times the cases plus one, times
        ``config.n`` samples) holds at most 4e7 run-samples, about 9 minutes on two cores
        (``_checks.MAX_RUN_SAMPLES``): 1,610 runs of the default 31 cases (30 faults and the
        fault-free) of 80 s. A larger
        batch is refused with the largest ``n_runs`` that fits. Its memory stays about 0.5 GB
        whatever ``n_runs`` (the runs are diagnosed in chunks).
    locations : sequence of str
        Subset of :data:`~.sensors.LOCATIONS`.
    kinds : sequence of {"step", "ramp"}
    sizes : sequence of float
        Multiples of :data:`~.sensors.DEFAULT_MAGNITUDES`, in (0, MAX_FACTOR].
    onset : float
        Fault onset, s (after ``config.t_cal[1]``, before ``config.duration``; without a
        ``config``, in [40, 159960] s on the 0.1 s grid: from the default config's t_cal[1] to its
        longest run of onset + 30 s).
    config : SimConfig, optional
        Default: :class:`~.simulation.SimConfig` with ``duration = onset + 30``.
    rng : numpy.random.Generator or int, optional

    Returns
    -------
    list of dict
        One row per (location, kind, size, method) with the keys above plus
        ``location``, ``kind``, ``size`` (SI magnitude), ``factor`` and ``method``.

    Examples
    --------
    >>> rows = isolation_monte_carlo(1, locations=["gyro_x"], kinds=["step"], sizes=[1.0])
    >>> [(r["method"], r["correct"]) for r in rows if r["location"] == "gyro_x"]
    [('SOS', 1.0), ('DOS', 1.0)]
    """
    n_runs = check_int("n_runs", n_runs, 1, 10**6)
    for name, value in (("locations", locations), ("kinds", kinds), ("sizes", sizes)):
        if isinstance(value, set | frozenset):  # its order (the rows') would be the hash's
            raise ValueError(f"{name} must be a list (ordered: one row group each), got the set {value!r}")
    # lists of at least one item, none twice (a string is not split into letters): an empty
    # one would leave only the fault-free rows, a repeat would run its cases twice
    locations = check_items("locations", locations, "location",
                            lambda label, v: check_choice(label, v, LOCATIONS))
    kinds = check_items("kinds", kinds, "kind",
                        lambda label, v: check_choice(label, v, ("step", "ramp")))
    sizes = [check_real(label, s, 0.0, MAX_FACTOR, lo_open=True) for label, s in
             ((f"sizes[{i}]", s) for i, s in enumerate(check_items("sizes", sizes, "size")))]
    # the default config lasts onset + 30 s, at most SimConfig's MAX_SAMPLES of 0.1 s, and arms
    # its detectors at t_cal[1] = 40 s: an earlier onset was refused as SimConfig's t_cal
    if config is None:
        onset = check_real("onset", onset, _DEFAULT_T_ARM, _MAX_DEFAULT_ONSET)
        try:
            config = SimConfig(duration=onset + 30.0)
        except ValueError as err:  # a duration off the 0.1 s grid: the user's onset is at fault
            raise ValueError(f"onset = {onset:g} s makes the default config's duration onset + 30 s, "
                             f"which SimConfig refuses: {err}") from None
    else:
        onset = check_real("onset", onset, 0.0, lo_open=True)
    cfg = make_config(config, dos=True)
    if not (cfg.t_cal[1] <= onset < cfg.duration):
        raise ValueError(
            f"onset must be in [t_cal[1], duration) = [{cfg.t_cal[1]}, {cfg.duration}), "
            f"got {onset}"
        )
    rng = make_rng(rng)
    cases = [("none", "-", 0.0, 0.0)]
    for loc in locations:
        sensor = "star_tracker" if loc == "star_tracker" else "gyro"
        for kind in kinds:
            for s in sizes:
                cases.append((loc, kind, s, s * DEFAULT_MAGNITUDES[(sensor, kind)]))
    _check_work("n_runs", n_runs, len(cases), cfg)
    truth = truth_motion(
        cfg.n, cfg.dt, q0=cfg.q0, omega_orbit_deg_s=cfg.omega_orbit_deg_s,
        wobble_deg_s=cfg.wobble_deg_s, wobble_period=cfg.wobble_period,
    )

    def draws():  # the runs in the order they draw from rng: case by case, n_runs each
        for loc, kind, _, mag in cases:
            faults = () if loc == "none" else (make_fault(loc, kind, mag, onset),)
            for _ in range(n_runs):
                yield simulate_sensors(cfg, faults, rng, truth)[1:]

    res = _diagnose_in_chunks(draws(), len(cases) * n_runs, cfg)
    rows = []
    for i, (loc, kind, factor, mag) in enumerate(cases):
        sl = slice(i * n_runs, (i + 1) * n_runs)
        for method in ("SOS", "DOS"):
            det = np.asarray(res[method.lower() + "_time"][sl], dtype=float)
            verdict = np.asarray(res[method.lower() + "_verdict"][sl])
            if loc == "none":
                fa = np.isfinite(det)
                after = np.zeros_like(fa)
            else:
                fa = det < onset
                after = np.isfinite(det) & ~fa
            correct = ~fa if loc == "none" else after & (verdict == loc)
            delay = float(np.mean(det[after] - onset)) if after.any() else math.inf
            rows.append({
                "location": loc, "kind": kind, "factor": factor, "size": mag,
                "method": method, "correct": float(correct.mean()),
                "missed": float((~np.isfinite(det)).mean()) if loc != "none" else 0.0,
                "false_alarm": float(fa.mean()), "delay_s": delay,
            })
    return rows


def seeded_outcomes(faults, seeds, config=None, **changes):
    """Every run's outcome for one set of faults, one run per seed, in vectorised batches.

    Run ``k`` draws its noise from ``seeds[k]`` exactly as
    :func:`~xnavlab.attitude.simulation.simulate` does with ``rng=seeds[k]``, so the outcome
    of seed 0 is the run a chapter plots; the runs then go through
    :func:`~xnavlab.attitude.simulation.diagnose_batch` a chunk of about 0.5 GB at a time (the
    outcomes those of one batch, bit for bit).

    Parameters
    ----------
    faults : Fault or sequence of Fault
        From :func:`~xnavlab.attitude.sensors.make_fault`, at least one (an onset is needed).
    seeds : sequence of int
        One seed per run, at least one, none twice; at most 4e7 run-samples in all
        (``len(seeds) * config.n``, about 9 minutes on two cores, ``_checks.MAX_RUN_SAMPLES``:
        39,960 seeds of 100 s), else refused with the most seeds that fit.
    config : SimConfig, optional
        Settings (default :class:`~xnavlab.attitude.simulation.SimConfig`).
    **changes
        Overrides of ``config`` fields, e.g. ``duration=60.0``.

    Returns
    -------
    dict
        ``seeds`` (B,) int; ``onset`` (float, s); ``crossed`` (B, 4) bool, the SOS residuals
        r1-r4 flagged at any time from the onset to the end; ``first_flag_s`` (B, 4), the delay
        from the onset to each SOS residual's first flag, s (``inf`` if never);
        ``sos_delay_s`` (B,), the SOS detection delay, s (``inf`` if never; negative for an
        alarm before the onset); ``false_alarm`` (B,) bool, any SOS flag before the onset;
        ``sos_verdict``, ``dos_verdict`` (``"-"`` without DOS) and ``qd_verdict`` (ref. [22])
        (B,) str.

    Examples
    --------
    >>> from xnavlab.attitude.sensors import make_fault
    >>> out = seeded_outcomes(make_fault("gyro_x", "step", 36 * DEG_PER_H), [0, 1],
    ...                       duration=60.0)
    >>> out["sos_verdict"].tolist(), out["crossed"].tolist()[0]
    (['gyro_x', 'gyro_x'], [True, False, False, True])
    """
    cfg = make_config(config, **changes)
    faults = check_faults_in_run(faults, cfg)
    if not faults:
        raise ValueError("faults must hold at least one fault (the outcomes are after its onset)")
    seeds = check_seeds("seeds", seeds)
    onset = min(f.onset for f in faults)
    _check_work("seeds", len(seeds), 0, cfg)
    truth = truth_motion(
        cfg.n, cfg.dt, q0=cfg.q0, omega_orbit_deg_s=cfg.omega_orbit_deg_s,
        wobble_deg_s=cfg.wobble_deg_s, wobble_period=cfg.wobble_period,
    )
    res = _diagnose_in_chunks((simulate_sensors(cfg, faults, make_rng(seed), truth)[1:]
                               for seed in seeds), len(seeds), cfg)
    t = np.arange(cfg.n) * cfg.dt  # as diagnose_batch's
    flags = res["sos_flags"]                                    # (B, n, 4)
    after = t >= onset
    first = np.full(flags.shape[::2], math.inf)                 # (B, 4)
    hit = flags[:, after].any(axis=1)
    k_first = np.argmax(flags[:, after], axis=1)                # first flagged sample after onset
    first[hit] = t[after][k_first[hit]] - onset
    return {
        "seeds": np.array(seeds, dtype=int),
        "onset": onset,
        "crossed": hit,
        "first_flag_s": first,
        "sos_delay_s": np.asarray(res["sos_time"], dtype=float) - onset,
        "false_alarm": flags[:, ~after].any(axis=(1, 2)),
        "sos_verdict": np.asarray(res["sos_verdict"], dtype=str),
        "dos_verdict": (np.asarray(res["dos_verdict"], dtype=str) if cfg.dos
                        else np.full(len(seeds), "-")),
        "qd_verdict": np.asarray(res["qd_verdict"], dtype=str),
    }


def _check_work(name, count, cases, cfg):
    """``count`` runs (``n_runs`` each of ``cases`` cases, or ``count`` seeds with ``cases =
    0``) of ``cfg.n`` samples within :data:`~._checks.MAX_RUN_SAMPLES`, else one ValueError
    naming ``name`` with the estimate and the largest count that fits (review 35p P6)."""
    per = max(cases, 1) * cfg.n  # run-samples of one n_runs (or one seed)
    total = count * per
    if total <= _checks.MAX_RUN_SAMPLES:
        return
    most = _checks.MAX_RUN_SAMPLES // per
    minutes = total * _checks.SECONDS_PER_RUN_SAMPLE / 60.0
    if cases:
        what = (f"n_runs = {count}: {count} runs x {cases} cases ({cases - 1} and the fault-free) "
                f"x {cfg.n} samples")
        fits = (f"at most {most} runs with these cases and config" if most else
                "not one run fits: fewer locations, kinds or sizes, or a shorter config.duration, "
                "onset + 30 s by default")
    else:
        what = f"{count} seeds x {cfg.n} samples"
        fits = (f"at most {most} seeds of this duration and dt" if most else
                "not one run fits")
    raise ValueError(f"{name} must keep the batch at most {_checks.MAX_RUN_SAMPLES:.0e} "
                     f"run-samples (about {_checks.MAX_RUN_SAMPLES * _checks.SECONDS_PER_RUN_SAMPLE / 60:.0f}"
                     f" minutes at {_checks.SECONDS_PER_RUN_SAMPLE * 1e6:g} us each), got {what} = "
                     f"{total:.3g}, about {minutes:.0f} minutes ({fits})")


def _diagnose_in_chunks(draws, count, cfg):
    """:func:`~.simulation.diagnose_batch` over ``count`` runs, each ``(omega_g, q_meas)`` from
    the iterator ``draws``, :data:`~._checks.CHUNK_SAMPLES` run-samples at a time (one batch of
    every run took about 1.2 kB a run-sample: 250 GB for 10,000 runs of the 31 cases). Every
    run is diagnosed on its own inside a batch, so the outcomes equal one batch's bit for bit.

    Returns a dict of the runs' outcomes, stacked: ``sos_flags`` (count, n, 4), ``sos_time``,
    ``sos_verdict``, ``dos_time``, ``dos_verdict`` (with DOS) and ``qd_verdict`` (count,).
    """
    size = max(1, _checks.CHUNK_SAMPLES // cfg.n)
    parts = []
    for start in range(0, count, size):
        wgs, qss = zip(*(next(draws) for _ in range(min(size, count - start))), strict=True)
        res = diagnose_batch(np.stack(wgs), np.stack(qss), cfg)
        del wgs, qss
        part = {"sos_flags": res["sos"].flags, "qd_verdict": np.asarray(res["qd"].verdict)}
        for key in ("sos", "dos"):
            if res[key] is not None:
                part[f"{key}_time"] = np.asarray(res[key].detect_time)
                part[f"{key}_verdict"] = np.asarray(res[key].verdict)
        parts.append(part)
    return {key: np.concatenate([p[key] for p in parts]) for key in parts[0]}


def _size_label(loc, kind, size):
    if loc == "none":
        return "-"
    if loc == "star_tracker":
        return f"{size:.1e}" + ("/s" if kind == "ramp" else "")
    return f"{size / DEG_PER_H:g} deg/h" + ("/s" if kind == "ramp" else "")


def isolation_table(rows):
    """Markdown table of :func:`isolation_monte_carlo` rows, SOS and DOS side by side.

    Examples
    --------
    >>> print(isolation_table([]).splitlines()[0])
    | fault | kind | size | SOS correct | SOS missed | SOS false alarm | SOS delay (s) | DOS correct | DOS missed | DOS false alarm | DOS delay (s) |
    """  # noqa: E501
    head = ["fault", "kind", "size"]
    for m in ("SOS", "DOS"):
        head += [f"{m} correct", f"{m} missed", f"{m} false alarm", f"{m} delay (s)"]
    if not isinstance(rows, list | tuple):  # a 0-d array is no list (check_records iterates it)
        raise ValueError(f"rows must be a list of isolation_monte_carlo's rows (dicts), got {shown(rows)}")
    rows = check_records("rows", rows, ("location", "kind", "factor", "size", "method", "correct",
                                        "missed", "false_alarm", "delay_s"), "row")
    body = []
    by = {}
    for r in rows:
        by.setdefault((r["location"], r["kind"], r["factor"]), {})[r["method"]] = r
    for (loc, kind, _), pair in by.items():
        cells = [loc, kind, _size_label(loc, kind, next(iter(pair.values()))["size"])]
        for m in ("SOS", "DOS"):
            r = pair.get(m)
            if r is None:
                cells += ["-"] * 4
                continue
            delay = "-" if not math.isfinite(r["delay_s"]) else f"{r['delay_s']:.1f}"
            cells += [f"{r['correct']:.0%}", f"{r['missed']:.0%}",
                      f"{r['false_alarm']:.0%}", delay]
        body.append(cells)
    return markdown_table(body, head)  # escaped cells: no content can split a row
