"""Main paper (Fan et al. 2016), Figs. 3-5: the faulty Mars run, without and with the wavelet detector.

IDs: ``mars-faults-ekf`` (Fig. 3: faults, no detector) and ``mars-faults-wavelet`` (Fig. 4:
wavelet detection, isolation and rejoining), both chapter 8; Fig. 5 (``wavelet-details``) is
:mod:`xnavlab.reproductions.ch08_wavelet_details`.

The paper gives the fault instants only; the magnitudes and durations are ours
(:func:`xnavlab.mars.faults.schedules.paper_schedule`: UV range steps of 5 sigma, XNAV delay steps
of 1e-5 s (3 km) and ramps of 2e-9 s/s, horizon-sensor steps of 8 sigma, 5000 s each). The
metric is the one of ``mars-nofault``: RMS of the fused error norm from day 1 to day 30; the
maximum is taken over the same span.

The paper's Figs. 3 and 4 numbers depend on those lost sizes, so they are judged by the rule
for a claim a lost parameter decides (:func:`xnavlab.verdicts.check_lost`): each size is
varied on its own over :data:`LOST_SIZES` on the headline campaign's first runs
(:func:`lost_size_runs`), and our 95 % range of single runs is shifted by each setting's mean
paired effect. The process noise q, which the paper does not give either, is varied likewise
over the interval in which the paper's fault-free numbers, from the same filter, lie inside our
range (:func:`q_interval`; :data:`Q_HELD` says why no further).
"""

from __future__ import annotations

import math
import time
from functools import lru_cache

import numpy as np

from xnavlab.core.faults import Fault
from xnavlab.mars.faults import fault_tolerance, schedules
from xnavlab.mars.navigation import scenarios
from xnavlab.mars.navigation.plots import plot_error_curves
from xnavlab.reproduce import (
    Result,
    check_draw,
    check_lost,
    check_measure,
    check_range,
    check_true,
    part_of,
    register,
    save_figure,
)

__all__ = ["PAPER_MAX_ERROR_FAULTS_M", "PAPER_POSITION_ERROR_M", "PAPER_VELOCITY_ERROR_MPS",
           "HAND_SCHEDULE", "HEADLINE_SEED", "LOST_SIZES", "LOST_RUNS", "Q_HELD", "FIG3_CLAIM",
           "Q_RUN", "Q_CLEAN_SEEDS", "q_runs", "q_interval", "q_reach", "JOINT_SIZES",
           "paper_runs",
           "wavelet_run", "lost_size_runs", "lost_reach", "fault_exposure", "describe_faults"]

#: Fig. 3: largest position error with faults and no detector, about 4 km.
PAPER_MAX_ERROR_FAULTS_M = 4000.0
#: Fig. 4: with wavelet detection and reconfiguration.
PAPER_POSITION_ERROR_M = 36.587
#: Fig. 4: the velocity error with wavelet detection and reconfiguration, m/s.
PAPER_VELOCITY_ERROR_MPS = 0.02293
#: Fig. 3's one sentence, judged in three rows (the fault-free level, the peak, the growth).
FIG3_CLAIM = "without a detector the error grows from the hundred-metre level to about 4 km (Fig. 3)"
#: Why the process noise q (lost too) is varied in Figs. 3 and 4 only over :func:`q_interval`
#: (``{lo}``, ``{hi}``: its ends, m^2/s^3): the paper ran them with the filter of its fault-free
#: Fig. 2, whose 28.835 m and 0.02149 m/s lie inside our fault-free range only for q inside it
#: (mars-nofault's range, shifted by q's paired effect); a q outside would judge the faulty runs
#: against fault-free levels the paper's own Fig. 2 rules out.
Q_HELD = ("the process noise q, lost too, is run only over {lo:.2g}-{hi:.2g} m^2/s^3, the q that put "
          "the paper's fault-free 28.835 m and 0.02149 m/s, from the same filter, inside our range "
          "(mars-nofault's 32 runs shifted by q's paired effect on seeds 0-3; the interval's ends "
          "interpolated in log q between the q run): another q contradicts the paper's own Fig. 2")
#: The process noises run for Figs. 2-4's q interval, m^2/s^3 (ours, 1e-11, among them).
Q_RUN = (3e-12, 5e-12, 1e-11, 2e-11)
#: Seeds of the fault-free q runs (those of mars-nofault's q shifts, paired with q = 1e-11).
Q_CLEAN_SEEDS = (0, 1, 2, 3)
#: Our process noise, m^2/s^3.
_Q_OURS = 1e-11
#: The code the cached runs of this module depend on (their cache key, with everything these
#: modules import): this module, whose functions are the runs' recipe, and the modules it runs.
#: No hand-raised version number: an edit of any of them computes the runs again.
_RUN_MODULES = ("xnavlab.reproductions.ch08_mars_faults", "xnavlab.core.detection",
                "xnavlab.core.faults", "xnavlab.mars.faults.fault_tolerance",
                "xnavlab.mars.faults.schedules", "xnavlab.mars.navigation.scenarios")

#: A schedule with onsets the paper does not use (s since the start), for a 3-day check.
HAND_SCHEDULE = (
    Fault("uv", "step", 30000.0, onset=123456.0, duration=4000.0, component=0),
    Fault("xnav", "step", 1.0e-5, onset=150321.0, duration=3000.0),
    Fault("cns", "step", math.radians(0.4), onset=177777.0, duration=3000.0),
    Fault("uv", "spike", 60000.0, onset=201234.0, duration=0.0, component=0),
    Fault("xnav", "ramp", 2.0e-9, onset=222222.0, duration=5000.0, component=1),
)


#: The seed of the headline campaign (:func:`xnavlab.mars.navigation.headline.headline_numbers`): its run
#: ``i`` uses child ``i`` of ``SeedSequence(HEADLINE_SEED)`` as its noise seed.
HEADLINE_SEED = 2016


#: The lost fault sizes, one varied at a time: label -> (keyword of
#: :func:`~xnavlab.mars.faults.schedules.paper_schedule`, factor on our value). The plausible range is
#: half to twice each of our magnitudes: at half our UV step (2.5 sigma) our detector already
#: misses or is late on some UV steps, while the paper finds every fault instant (its Fig. 5
#: and text), so smaller steps are not the paper's; the paper bounds them from above nowhere,
#: so the same factor is taken upwards. The XNAV drift (a kind of fault the paper does not name:
#: its faults are "sudden changes" of a sensor's output) runs from half ours to ten times ours,
#: which reaches our 3-km XNAV step within one 500-s XNAV interval: a step at XNAV's sampling.
LOST_SIZES = {
    "UV x0.5": ("uv_step_sigma", 0.5), "UV x2": ("uv_step_sigma", 2.0),
    "XNAV steps x0.5": ("xnav_step_s", 0.5), "XNAV steps x2": ("xnav_step_s", 2.0),
    "drift x0.5": ("xnav_ramp", 0.5), "drift x10": ("xnav_ramp", 10.0),
    "CNS x0.5": ("cns_step_sigma", 0.5), "CNS x2": ("cns_step_sigma", 2.0),
}
#: The headline campaign's first runs on which each lost size is run (paired with them).
LOST_RUNS = 2
#: The lost sizes that raise the wavelet run's fused error, varied together (:func:`q_runs`):
#: not one of the rule's one-at-a-time values, a measure of how far the sizes may move it jointly.
JOINT_SIZES = ("UV x0.5", "CNS x0.5", "drift x10", "XNAV steps x0.5")

#: Our magnitudes (:func:`~xnavlab.mars.faults.schedules.paper_schedule`'s defaults).
_OURS = {"uv_step_sigma": 5.0, "xnav_step_s": 1.0e-5, "xnav_ramp": 2.0e-9, "cns_step_sigma": 8.0}


@lru_cache(maxsize=2)
def _campaign_inputs(seed, days=30.0):
    """Prepared inputs, shared by :func:`wavelet_run` and :func:`lost_size_runs`."""
    return scenarios.prepare(days=days, seed=seed)


@lru_cache(maxsize=2)
def lost_size_runs(detector, n_runs=LOST_RUNS):
    """The paper's schedule with one lost fault size changed at a time (:data:`LOST_SIZES`).

    Runs the headline campaign's first ``n_runs`` seeds (30 days, its prepared inputs reused
    for every setting) under ``detector``; the campaign's own runs are the same seeds at our
    sizes, so each setting's effect is a paired difference.

    Parameters
    ----------
    detector : {"none", "wavelet"}
        The paper's Fig. 3 (no detector) or Fig. 4 (wavelet detection and isolation).
    n_runs : int
        How many of the campaign's first runs, at least 2.

    Returns
    -------
    dict
        Label of :data:`LOST_SIZES` -> dict of per-run lists: ``max_position_m`` (m) for
        ``"none"``; ``position_m`` (m), ``velocity_mps`` (m/s) and ``detected_fraction`` (share
        of the 16 faults detected while they act) for ``"wavelet"``.

    Examples
    --------
    >>> lost_size_runs("combined")
    Traceback (most recent call last):
    ...
    ValueError: detector must be 'none' or 'wavelet'; got 'combined'
    """
    from xnavlab.core.montecarlo import seeds as spawn_seeds

    if detector not in ("none", "wavelet"):
        raise ValueError(f"detector must be 'none' or 'wavelet'; got {detector!r}")
    if not (isinstance(n_runs, int) and 2 <= n_runs <= 32):
        raise ValueError(f"n_runs must be an integer in [2, 32]; got {n_runs!r}")
    out = {label: {} for label in LOST_SIZES}
    for s in spawn_seeds(HEADLINE_SEED, n_runs):
        inp = _campaign_inputs(int(s) % 2**31)
        for label, (key, factor) in LOST_SIZES.items():
            faults = schedules.paper_schedule(**{key: _OURS[key] * factor})
            ftr = fault_tolerance.run_fault_tolerant(faults=faults, detector=detector, inputs=inp)
            m = ftr.run.metrics()
            if detector == "none":
                row = {"max_position_m": m["position_error_max_m"]}
            else:
                found = sum(d["status"] == "detected" for d in ftr.delays())
                row = {"position_m": m["position_error_m"], "velocity_mps": m["velocity_error_mps"],
                       "detected_fraction": found / len(faults)}
            for k, v in row.items():
                out[label].setdefault(k, []).append(float(v))
    return out


def q_runs(q_values=Q_RUN, clean_seeds=Q_CLEAN_SEEDS, n_runs=LOST_RUNS):
    """The fault-free and the faulty Mars runs at each process noise ``q_values``.

    Each seed's inputs are prepared once and run at every q (the same draws: paired runs).
    Cached on disk, keyed by the code.

    Parameters
    ----------
    q_values : tuple of float
        Process noises, m^2/s^3; must hold ours, 1e-11.
    clean_seeds : tuple of int
        Seeds of the fault-free runs.
    n_runs : int
        The headline campaign's first runs on which the paper's schedule is run, with no
        detector and with the wavelet, at least 2.

    Returns
    -------
    dict of str -> ndarray
        ``q`` (nq,); ``clean`` (nq, len(clean_seeds), 2): fault-free fused position (m) and
        velocity (m/s) RMS after day 1; ``wavelet`` (nq, n_runs, 2): the same with the paper's
        faults and the wavelet detector; ``share`` (nq, n_runs): the share of its 16 faults
        detected while they act; ``joint`` (nq, n_runs, 2): as ``wavelet`` with the sizes
        :data:`JOINT_SIZES` together; ``none`` (nq, n_runs): the largest fused position error
        (m) with the faults and no detector.

    Examples
    --------
    >>> q_runs(q_values=(1e-12, 1e-10))
    Traceback (most recent call last):
    ...
    ValueError: q_values must hold ours, 1e-11; got (1e-12, 1e-10)
    """
    from dataclasses import replace

    from xnavlab.core.diskcache import cached_arrays, entry_path
    from xnavlab.core.montecarlo import seeds as spawn_seeds

    q_values = tuple(float(q) for q in q_values)
    if _Q_OURS not in q_values:
        raise ValueError(f"q_values must hold ours, {_Q_OURS:g}; got {q_values!r}")
    if not (isinstance(n_runs, int) and 2 <= n_runs <= 32):
        raise ValueError(f"n_runs must be an integer in [2, 32]; got {n_runs!r}")

    def at(inp, q):
        return replace(inp, scenario=replace(inp.scenario, q_acc=q))

    def compute():
        clean = np.zeros((len(q_values), len(clean_seeds), 2))
        wav = np.zeros((len(q_values), n_runs, 2))
        none = np.zeros((len(q_values), n_runs))
        share = np.zeros((len(q_values), n_runs))
        joint = np.zeros((len(q_values), n_runs, 2))
        together = schedules.paper_schedule(**{LOST_SIZES[k][0]: _OURS[LOST_SIZES[k][0]]
                                               * LOST_SIZES[k][1] for k in JOINT_SIZES})
        for j, s in enumerate(clean_seeds):
            inp = scenarios.prepare(days=30.0, seed=int(s))
            for i, q in enumerate(q_values):
                m = scenarios.run(inputs=at(inp, q)).metrics()
                clean[i, j] = m["position_error_m"], m["velocity_error_mps"]
        faults = schedules.paper_schedule()
        for j, s in enumerate(spawn_seeds(HEADLINE_SEED, n_runs)):
            inp = _campaign_inputs(int(s) % 2**31)
            for i, q in enumerate(q_values):
                ftr = fault_tolerance.run_fault_tolerant(faults=faults, detector="wavelet",
                                                         inputs=at(inp, q))
                m = ftr.run.metrics()
                wav[i, j] = m["position_error_m"], m["velocity_error_mps"]
                share[i, j] = np.mean([d["status"] == "detected" for d in ftr.delays()])
                m = fault_tolerance.run_fault_tolerant(faults=together, detector="wavelet",
                                                       inputs=at(inp, q)).run.metrics()
                joint[i, j] = m["position_error_m"], m["velocity_error_mps"]
                none[i, j] = fault_tolerance.run_fault_tolerant(
                    faults=faults, detector="none", inputs=at(inp, q)).run.metrics()[
                        "position_error_max_m"]
        return {"q": np.array(q_values), "clean": clean, "wavelet": wav, "share": share,
                "joint": joint, "none": none}

    path = entry_path("ch08-q-runs", (q_values, tuple(int(s) for s in clean_seeds), n_runs,
                                      JOINT_SIZES), modules=_RUN_MODULES)
    return cached_arrays(path, compute)


def q_interval(runs, q_data):
    """The process noises that put the paper's fault-free numbers inside our range.

    Our fault-free range at q is the 95 % range of our single runs at ours shifted by q's mean
    paired effect; between the q run, the effect is interpolated in log q.

    Parameters
    ----------
    runs : dict
        The headline campaign's single runs (``fused_position_m``, m; ``fused_velocity_mps``,
        m/s) at our q.
    q_data : dict
        :func:`q_runs`' result.

    Returns
    -------
    dict
        ``position`` and ``velocity``: (lo, hi) q (m^2/s^3) that put the paper's fault-free
        number inside our range; ``both``: their intersection (NaN ends when the number is
        inside at none of the q run).

    Examples
    --------
    >>> runs = {"fused_position_m": np.linspace(26.0, 32.0, 40),
    ...         "fused_velocity_mps": np.linspace(0.0196, 0.024, 40)}
    >>> q = {"q": np.array([1e-12, 1e-11, 1e-10]),
    ...      "clean": np.array([[[-6.0, -0.004]], [[0.0, 0.0]], [[6.0, 0.004]]])}
    >>> {k: tuple(round(float(x), 14) for x in v) for k, v in q_interval(runs, q).items()}
    {'position': (3.15e-12, 2.799e-11), 'velocity': (2.51e-12, 2.78e-11), 'both': (3.15e-12, 2.78e-11)}
    """
    from xnavlab.reproductions.ch04_06_mars import PAPER_POSITION_ERROR_M as P0
    from xnavlab.reproductions.ch04_06_mars import PAPER_VELOCITY_ERROR_MPS as V0

    q = np.asarray(q_data["q"], dtype=float)
    order = np.argsort(q)
    logq = np.log10(q[order])
    ours = int(np.flatnonzero(q[order] == _Q_OURS)[0])
    out = {}
    for i, (key, paper) in enumerate((("fused_position_m", P0), ("fused_velocity_mps", V0))):
        lo, hi = np.percentile(runs[key], [2.5, 97.5])
        d = np.asarray(q_data["clean"])[order, :, i]
        shift = np.mean(d - d[ours], axis=1)                      # increasing with q
        # inside while lo + shift <= paper <= hi + shift: shift in [paper - hi, paper - lo]
        fine = np.linspace(logq[0], logq[-1], 2001)
        s = np.interp(fine, logq, shift)
        ok = (s >= paper - hi) & (s <= paper - lo)
        name = "position" if i == 0 else "velocity"
        out[name] = ((float(10 ** fine[ok].min()), float(10 ** fine[ok].max())) if ok.any()
                     else (math.nan, math.nan))
    a = max(out["position"][0], out["velocity"][0])
    b = min(out["position"][1], out["velocity"][1])
    out["both"] = (a, b) if a <= b else (math.nan, math.nan)
    return out


def q_reach(runs, q_data, key, interval, column=None, clip=None):
    """Our faulty number's range at each process noise of the interval (:func:`q_interval`).

    Parameters
    ----------
    runs : array_like, shape (N,)
        Our single runs at our q (the headline campaign, in its order).
    q_data : dict
        :func:`q_runs`' result; its faulty runs are the first ones of ``runs``.
    key : {"wavelet", "share", "joint", "none"}
        Which faulty runs' number.
    interval : (float, float)
        The q interval, m^2/s^3.
    column : int, optional
        For ``"wavelet"`` and ``"joint"``: 0 position, 1 velocity.
    clip : (float, float), optional
        Bounds of the quantity (a share: (0, 1)).

    Returns
    -------
    dict of str -> (float, float)
        ``"ours, q 1e-11"``, each q run inside the interval and its two ends (``"q 3.9e-12"``;
        their effect interpolated in log q) -> our 95 % range shifted by the mean paired effect
        there (for ``"joint"``, of the joint sizes and q together; 0 at ours otherwise, where the
        runs are the campaign's own).

    Examples
    --------
    >>> q = {"q": np.array([1e-12, 1e-11, 1e-10]), "none": np.array([[1.0, 1.0], [2.0, 2.0],
    ...                                                              [4.0, 4.0]])}
    >>> r = q_reach(np.full(40, 2.0), q, "none", (3e-12, 3e-11))
    >>> {k: tuple(round(x, 3) for x in v) for k, v in r.items()}
    {'q 3e-12': (1.477, 1.477), 'ours, q 1e-11': (2.0, 2.0), 'q 3e-11': (2.954, 2.954)}
    """
    runs = np.asarray(runs, dtype=float)
    lo, hi = np.percentile(runs, [2.5, 97.5])
    q = np.asarray(q_data["q"], dtype=float)
    order = np.argsort(q)
    v = np.asarray(q_data[key], dtype=float)[order]
    if column is not None:
        v = v[..., column]
    effect = np.mean(v - runs[:v.shape[1]], axis=1)              # paired with the campaign
    logq = np.log10(q[order])
    points = {float(x): float(e) for x, e in zip(q[order], effect, strict=True)
              if interval[0] <= x <= interval[1]}
    for end in interval:
        points.setdefault(float(end), float(np.interp(np.log10(end), logq, effect)))
    reach = {}
    for x, e in sorted(points.items()):
        label = f"ours, q {x:g}" if x == _Q_OURS else f"q {x:.2g}"
        a, b = lo + e, hi + e
        if clip is not None:
            a, b = (float(np.clip(y, *clip)) for y in (a, b))
        reach[label] = (float(a), float(b))
    return reach


def lost_reach(runs, lost, key, clip=None):
    """Our number's range at each plausible lost size: our 95 % range shifted by its effect.

    Parameters
    ----------
    runs : array_like, shape (N,)
        Our single runs at our sizes (the headline campaign, in its order).
    lost : dict
        :func:`lost_size_runs`' result; its runs are the first ones of ``runs``.
    key : str
        The quantity in ``lost``.
    clip : (float, float), optional
        Bounds of the quantity (a share: (0, 1)).

    Returns
    -------
    dict of str -> (float, float)
        ``"ours"`` and each label of ``lost`` -> (lo, hi), for :func:`~xnavlab.verdicts.check_lost`.

    Examples
    --------
    >>> lost = {"x2": {"m": [3.0, 5.0]}, "x0.5": {"m": [1.0, 1.0]}}
    >>> r = lost_reach(np.arange(2.0, 42.0), lost, "m")
    >>> [tuple(round(x, 3) for x in v) for v in r.values()]
    [(2.975, 40.025), (4.475, 41.525), (1.475, 38.525)]
    """
    runs = np.asarray(runs, dtype=float)
    lo, hi = np.percentile(runs, [2.5, 97.5])
    reach = {"ours": (float(lo), float(hi))}
    for label, rows in lost.items():
        v = np.asarray(rows[key], dtype=float)
        d = float(np.mean(v - runs[:v.size]))
        a, b = lo + d, hi + d
        if clip is not None:
            a, b = (float(np.clip(x, *clip)) for x in (a, b))
        reach[label] = (float(a), float(b))
    return reach


def _with_q(sizes, q):
    """One reach of the lost sizes (:func:`lost_reach`) and of q (:func:`q_reach`): our own
    range once, labelled with our q."""
    if not np.allclose(sizes["ours"], q[f"ours, q {_Q_OURS:g}"]):
        raise ValueError("the size and q reaches must share our own range")
    return {**q, **{k: v for k, v in sizes.items() if k != "ours"}}


def _q_text(interval, q_data, key, runs, unit, scale=1.0, column=None):
    """Each q's mean paired effect on a faulty number over the interval, in words."""
    reach = q_reach(runs, q_data, key, interval, column)
    ours = np.mean(reach[f"ours, q {_Q_OURS:g}"])
    return ("across that interval q moves it by "
            + ", ".join(f"{(np.mean(v) - ours) / scale:+.3g} {unit} ({k})"
                        for k, v in reach.items() if not k.startswith("ours")))


def _q_sentence(q_data, runs, interval):
    """Where the paper's fault-free numbers place q, in words (:func:`q_interval`)."""
    iv = q_interval(runs, q_data)
    n_clean, n_faulty = np.shape(q_data["clean"])[1], np.shape(q_data["none"])[1]
    return (f"The process noise q, lost too, is run at {', '.join(f'{q:g}' for q in q_data['q'])} "
            f"m^2/s^3 (fault-free on {n_clean} seeds, faulty on the campaign's first {n_faulty} "
            f"runs, paired with ours): the paper's fault-free 28.835 m is inside our range for q "
            f"from {iv['position'][0]:.2g} to {iv['position'][1]:.2g}, its 0.02149 m/s from "
            f"{iv['velocity'][0]:.2g} to {iv['velocity'][1]:.2g}, both from {interval[0]:.2g} to "
            f"{interval[1]:.2g} m^2/s^3, the interval over which q is varied (another q "
            "contradicts the paper's own Fig. 2)")


def _effects(runs, lost, key):
    """Each lost setting's mean paired effect on ``key`` (label -> change of the quantity)."""
    runs = np.asarray(runs, dtype=float)
    return {k: float(np.mean(np.asarray(v[key]) - runs[:len(v[key])])) for k, v in lost.items()}


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


@lru_cache(maxsize=2)
def wavelet_run(days=30.0, seed=0):
    """The fault-free run and the paper's schedule under the wavelet detector, for one seed.

    Returns
    -------
    dict
        ``clean`` (MarsRun) and ``wavelet`` (FaultTolerantRun). Cached like :func:`paper_runs`.
    """
    inp = _campaign_inputs(seed, days)
    return {"clean": scenarios.run(inputs=inp),
            "wavelet": fault_tolerance.run_fault_tolerant(faults="paper", detector="wavelet",
                                                          inputs=inp)}


def fault_exposure(ftr, n_grid=500):
    """Each fault's score and how much of it reached the filter.

    Parameters
    ----------
    ftr : FaultTolerantRun
        A run with faults (:func:`xnavlab.mars.faults.fault_tolerance.run_fault_tolerant`).
    n_grid : int
        Points of each fault's span at which its subsystem's state is sampled.

    Returns
    -------
    list of dict
        Per fault, in schedule order: ``sensor``, ``kind``, ``onset``, ``end`` (s since the
        start), ``status`` and ``delay_s`` (:func:`xnavlab.mars.faults.schedules.score_faults`;
        ``delay_s`` None unless detected), ``late_s`` (None unless late), ``out_share`` (the
        share of ``[onset, end)`` during which its subsystem was out of the fusion: 1 when none
        of the fault reached the filter, 0 when all of it did) and ``back_s`` (s after the onset
        at which the subsystem rejoined while the fault still acted, None if it did not).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> f = Fault("cns", "step", 0.007, onset=100.0, duration=1000.0)
    >>> run = SimpleNamespace(faults=[f], isolation_intervals=lambda: [
    ...     {"sensor": "cns", "out": 103.0, "back": 106.0}], delays=lambda: [
    ...     {"status": "detected", "delay": 3.0, "late_s": None}])
    >>> e = fault_exposure(run)[0]
    >>> e["status"], e["delay_s"], e["out_share"], e["back_s"]
    ('detected', 3.0, 0.004, 6.0)
    """
    iso = ftr.isolation_intervals()
    out = []
    for f, d in zip(ftr.faults, ftr.delays(), strict=True):
        end = f.end if math.isfinite(f.end) else f.onset
        grid = f.onset + (end - f.onset) * (np.arange(n_grid) + 0.5) / n_grid
        isolated = np.zeros(n_grid, bool)
        back = None
        for iv in iso:
            if iv["sensor"] != f.sensor:
                continue
            stop = math.inf if iv["back"] is None else iv["back"]
            isolated |= (grid >= iv["out"]) & (grid < stop)
            if f.onset <= stop < end and (back is None or stop - f.onset < back):
                back = stop - f.onset
        detected = d["status"] == "detected"
        out.append({"sensor": f.sensor, "kind": f.kind, "onset": f.onset, "end": end,
                    "status": d["status"], "delay_s": float(d["delay"]) if detected else None,
                    "late_s": d.get("late_s"), "out_share": float(isolated.mean()),
                    "back_s": None if back is None else float(back)})
    return out


def describe_faults(rows):
    """The faults of :func:`fault_exposure` (or the scored rows of ``delays()``) in words.

    Examples
    --------
    >>> describe_faults([{"sensor": "uv", "kind": "step", "status": "detected", "delay": 40.0},
    ...                  {"sensor": "xnav", "kind": "ramp", "status": "late", "delay": math.inf,
    ...                   "late_s": 2000.0}])
    'uv step: 40 s; xnav ramp: late (flagged 2000 s after its end)'
    """
    parts = []
    for r in rows:
        delay = r.get("delay_s", r.get("delay"))
        if r["status"] == "detected":
            what = f"{delay:.0f} s"
        elif r["status"] == "late":
            what = f"late (flagged {r['late_s']:.0f} s after its end)"
        else:
            what = "missed"
        parts.append(f"{r['sensor']} {r['kind']}: {what}")
    return "; ".join(parts)


def _save(result, out, fig, name):
    if out is not None:
        result.figures.append(save_figure(fig, out, name, dpi=90, layout=False))


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
        from xnavlab.mars.navigation import headline

        runs = headline.headline_numbers(n_seeds=32)["runs"]
        ekf, clean = np.asarray(runs["ekf_max_position_m"]), np.asarray(runs["clean_max_position_m"])
        # the peak scales with the lost sizes: judged over them, one varied at a time
        lost = lost_size_runs("none")
        q_data = q_runs()
        q_iv = q_interval(runs, q_data)["both"]
        held = Q_HELD.format(lo=q_iv[0], hi=q_iv[1])
        effect = _effects(ekf, lost, "max_position_m")
        cns = {1.0: 0.0, **{f: effect[k] for k, (key, f) in LOST_SIZES.items()
                            if key == "cns_step_sigma"}}
        fs = sorted(cns)
        ekf_med = float(np.median(ekf))
        k_4km = float(np.interp(PAPER_MAX_ERROR_FAULTS_M, [ekf_med + cns[f] for f in fs], fs))
        checks += part_of(
            FIG3_CLAIM,
            check_lost(check_draw("max |position error|, faults, no detector (m)",
                                  PAPER_MAX_ERROR_FAULTS_M, ekf, slack=500.0, unit="m",
                                  why="the paper reads 'about 4 km' off its figure"),
                       "size of the faults and the process noise q",
                       _with_q(lost_reach(ekf, lost, "max_position_m"),
                               q_reach(ekf, q_data, "none", q_iv)),
                       f"the paper's horizon-sensor step ({k_4km * _OURS['cns_step_sigma']:.1f} "
                       "sigma gives 4 km at our q) and its q", unit="m", held=held),
            check_range("max |position error|, fault-free, largest of our runs (m)",
                        "hundred-metre level", float(clean.max()), 100 / np.sqrt(10), 100 * np.sqrt(10),
                        why="'hundred-metre level' read as the order of magnitude of 100 m "
                            "(a factor sqrt(10) either side)"),
            check_true("faults / fault-free max error, smallest of our runs", "grows to km level",
                       float((ekf / clean).min()), bool((ekf / clean).min() >= 10.0),
                       why="undetected faults raise the largest error by more than an order "
                           "of magnitude in every run"),
        )
    checks.append(check_measure(f"max |position error|, faults, no detector, seed {seed} (m)",
                                bad, "the run whose curve the chapter plots",
                                paper=PAPER_MAX_ERROR_FAULTS_M))
    checks.append(check_measure("RMS |position error|, faults, no detector (m)",
                                m_bad["position_error_m"],
                                "the paper gives only the maximum for Fig. 3"))
    err, td = r["none"].run.position_error(), r["none"].run.t_days * 86400.0
    peak = {}
    for f in r["faults"]:      # faults that overlap no other: the error is theirs alone
        if any(g is not f and g.onset < f.end and f.onset < g.end for g in r["faults"]):
            continue
        during = (td >= f.onset) & (td < f.end)
        peak[f.sensor] = max(peak.get(f.sensor, 0.0), float(err[during].max()))
    excursion = ", ".join(f"{s} {v / 1e3:.2f} km" for s, v in
                          sorted(peak.items(), key=lambda kv: -kv[1]))
    note = (
        f"The paper's fault instants with our magnitudes and durations (5000 s each: UV range "
        "steps of 5 sigma = 25 km; XNAV delay steps of 1e-5 s = 3 km on every pulsar and ramps "
        "of 2e-9 s/s on B1937+21; horizon-sensor steps of 8 sigma = 0.4 deg on the three "
        f"starlight angles). No detector: the federated filter takes every biased measurement. "
        f"Ours peaks at {bad / 1e3:.2f} km (paper about 4 km) against {ok:.0f} m fault-free; "
        f"the largest error while a fault of one sensor alone acts: {excursion}. The paper gives no "
        "magnitudes, so its 4 km is judged over their plausible values (xnavlab.verdicts."
        "check_lost): half to twice each of ours, one varied at a time (below half our UV step "
        "our detector misses UV steps the paper finds; the paper bounds them from above "
        "nowhere, so the same factor is taken upwards), the XNAV drift from half to ten times "
        "ours (ten times reaches the 3-km step within one 500-s XNAV interval)."
    )
    if (days, seed) == (30.0, 0):
        note += " " + _q_sentence(q_data, runs, q_iv) + (
            "; the peak: " + _q_text(q_iv, q_data, "none", ekf, "km", 1e3) + "."
        )
        note += (
            f" Run on the headline campaign's first {LOST_RUNS} runs, each setting's mean paired "
            "effect on the peak: " + ", ".join(f"{k} {v / 1e3:+.2f} km" for k, v in effect.items())
            + f" (ours a median {ekf_med / 1e3:.2f} km). The horizon-sensor step decides it: "
            f"{k_4km:.2f} times ours ({k_4km * _OURS['cns_step_sigma']:.1f} sigma, "
            f"{k_4km * _OURS['cns_step_sigma'] * scenarios.MarsScenario().sigma_horizon_deg:.2f} "
            "deg) gives the paper's 4 km at our q."
        )
    data = {"t_days": r["none"].run.t_days, "faulty": r["none"].run.position_error(),
            "clean": r["clean"].position_error(), "faults": r["faults"],
            "metrics": m_bad, "metrics_clean": m_ok}
    if (days, seed) == (30.0, 0):
        data.update(q_runs=q_data, q_interval=q_iv)
    result = Result("mars-faults-ekf", checks, note, data)
    if out is not None:
        fig = plot_error_curves({"faults, no detector": (data["t_days"], data["faulty"]),
                                 "fault-free": (data["t_days"], data["clean"])},
                                r["faults"], title="mars-faults-ekf (Fan et al. 2016, Fig. 3)")
        _save(result, out, fig, "mars-faults-ekf")
    return result


@register("mars-faults-wavelet",
          title="wavelet detection, isolation and rejoining in the faulty Mars run (Fig. 4)",
          source="Fan et al. 2016, section 4.2 and Fig. 4", chapter="08_fault_tolerant")
def mars_faults_wavelet(out=None, days=30.0, seed=0, hand_days=3.0):
    """RMS errors with the wavelet detector vs the paper and vs our fault-free run; which faults
    reached the filter (in the plotted run and in the headline campaign's first run)."""
    r = paper_runs(days, seed)
    ftr = r["wavelet"]
    m = ftr.run.metrics()
    m0 = r["clean"].metrics()
    pos, vel = m["position_error_m"], m["velocity_error_mps"]
    delays = ftr.delays()
    exposure = fault_exposure(ftr)
    found = [d for d in delays if d["status"] == "detected"]
    late = [d for d in delays if d["status"] == "late"]
    # a schedule with onsets the paper does not use (shorter run)
    hand = fault_tolerance.run_fault_tolerant(faults=list(HAND_SCHEDULE), detector="wavelet",
                                              days=hand_days, seed=seed)
    hand_clean = scenarios.run(days=hand_days, seed=seed)
    hd = hand.delays()
    hand_found = [d for d in hd if d["status"] == "detected"]
    hand_ratio = hand.run.metrics()["position_error_m"] / hand_clean.metrics()["position_error_m"]
    checks, campaign, first, lost, t_lost = [], None, None, None, None
    if (days, seed) == (30.0, 0):
        # the paper's Fig. 4 is one run: its numbers judged among our single runs over 32 seeds
        from xnavlab.core.montecarlo import seeds as spawn_seeds
        from xnavlab.mars.navigation import headline

        runs = headline.headline_numbers(n_seeds=32, seed=HEADLINE_SEED)["runs"]
        paper_ratio = PAPER_POSITION_ERROR_M / headline.PAPER["fused_position_m"]
        ratio = np.asarray(runs["wavelet_ratio"])
        share = np.asarray(runs["wavelet_detected_fraction"])
        # the lost sizes and drift rate, one varied at a time (check_lost)
        t_lost = time.perf_counter()
        lost = lost_size_runs("wavelet")
        t_lost = time.perf_counter() - t_lost
        w_pos, w_vel = np.asarray(runs["wavelet_position_m"]), np.asarray(runs["wavelet_velocity_mps"])
        q_data = q_runs()
        q_iv = q_interval(runs, q_data)["both"]
        held = Q_HELD.format(lo=q_iv[0], hi=q_iv[1])
        pos_reach = _with_q(lost_reach(w_pos, lost, "position_m"),
                            q_reach(w_pos, q_data, "wavelet", q_iv, 0))
        vel_reach = _with_q(lost_reach(w_vel, lost, "velocity_mps"),
                            q_reach(w_vel, q_data, "wavelet", q_iv, 1))
        sizes = "size of the faults (XNAV drift rate included) and the process noise q"
        checks += [
            check_lost(check_draw("fused position error with faults (m), RMS after day 1",
                                  PAPER_POSITION_ERROR_M, w_pos, unit="m"),
                       sizes, pos_reach,
                       "the paper's fault sizes, its UV step's most (at half ours some UV steps "
                       "are missed and leak in), and its q", unit="m", held=held),
            check_lost(check_draw("fused velocity error with faults (m/s), RMS after day 1",
                                  PAPER_VELOCITY_ERROR_MPS, w_vel, unit="m/s"),
                       sizes, vel_reach, "the paper's q and fault sizes", unit="m/s", held=held),
            check_true("close to fault-free: faulty / fault-free error, 95th percentile",
                       f"close ({paper_ratio:.2f} in the paper)",
                       float(np.percentile(ratio, 95)), np.percentile(ratio, 95) <= paper_ratio,
                       why="at most the paper's own ratio, which it calls close, in 95 % of runs"),
            check_lost(check_draw("every scheduled fault detected: share detected while acting, "
                                  "per run", 1.0, share,
                                  why="the paper finds every fault; detected means an alarm "
                                      "while the fault acts (an alarm after its end is late)"),
                       "rate of the XNAV drifts (and the size of the faults, the process noise q)",
                       _with_q(lost_reach(share, lost, "detected_fraction", clip=(0.0, 1.0)),
                               q_reach(share, q_data, "share", q_iv, clip=(0.0, 1.0))),
                       "the paper's XNAV fault kinds and drift rate (a drift ten times ours is "
                       "caught while it acts, as steps are)", held=held),
        ]
        # the campaign's first run, rerun with its faults scored one by one
        seed_first = spawn_seeds(HEADLINE_SEED, 1)[0] % 2**31
        w1 = wavelet_run(days, seed_first)
        first = {"seed": seed_first, "exposure": fault_exposure(w1["wavelet"]),
                 "t_days": w1["wavelet"].run.t_days,
                 "wavelet": w1["wavelet"].run.position_error(),
                 "clean": w1["clean"].position_error(),
                 "isolations": w1["wavelet"].isolation_intervals(),
                 "events": {k: [(e.onset, e.end, e.cleared) for e in v]
                            for k, v in w1["wavelet"].events.items()},
                 "metrics": w1["wavelet"].run.metrics(), "metrics_clean": w1["clean"].metrics()}
        campaign = {"position_m": np.asarray(runs["wavelet_position_m"]),
                    "clean_position_m": np.asarray(runs["fused_position_m"]),
                    "combined_position_m": np.asarray(runs["faulty_position_m"]),
                    "ratio": ratio, "detected_share": share, "paper_ratio": paper_ratio}
    leaked = [e for e in exposure if e["out_share"] < 0.5]
    checks += [
        check_measure(f"fused position error with faults, seed {seed} (m)", pos,
                      "the run whose curves the chapter plots", paper=PAPER_POSITION_ERROR_M),
        check_measure(f"scheduled faults detected while they act, seed {seed}",
                      f"{len(found)} of {len(delays)} ({len(late)} late)", "the plotted run",
                      paper="all"),
        check_measure(f"faults in the fusion for over half their span, seed {seed}",
                      f"{len(leaked)} of {len(delays)}",
                      "the plotted run: how many faults reached the filter"),
        check_measure(f"every subsystem connected at the end, seed {seed}",
                      bool(not ftr.isolated[-1].any()), "the plotted run", paper="yes"),
        check_measure(f"hand-made schedule ({hand_days:g} days, other onsets): detected",
                      f"{len(hand_found)} of {len(hd)}",
                      "faults at onsets the paper does not use"),
        check_measure("hand-made schedule: position error / fault-free", float(hand_ratio),
                      "faults at onsets the paper does not use"),
    ]
    if first is not None:
        leaked1 = [e for e in first["exposure"] if e["out_share"] < 0.5]
        checks.append(check_measure(
            "faults in the fusion for over half their span, the campaign's first run",
            f"{len(leaked1)} of {len(first['exposure'])}",
            f"fused position error {first['metrics']['position_error_m']:.0f} m against "
            f"{first['metrics_clean']['position_error_m']:.1f} m fault-free"))
    note = (
        "Wavelet detection (db3; UV range and CNS angles on the raw measurements, 5 levels, MAD "
        "thresholds trained on day 1; XNAV on its normalised innovations, 3 levels). A "
        "subsystem leaves the fusion at the epoch of a detected onset, whatever epoch that is, "
        "and rejoins only when its detector is clear and the NIS of its last measurements "
        "(100 UV/CNS, 4 XNAV) passes a 1 % chi-square test, checked every 300 s: it is never "
        "fused while its detector flags. A fault counts as "
        "detected only by an alarm on its subsystem while it acts (an alarm after its end makes "
        f"it late). Seed {seed}: {pos:.2f} m and {vel:.5f} m/s against the paper's "
        f"{PAPER_POSITION_ERROR_M} m and {PAPER_VELOCITY_ERROR_MPS} m/s and our fault-free "
        f"{m0['position_error_m']:.2f} m and {m0['velocity_error_mps']:.5f} m/s; "
        f"{len(found)} of {len(delays)} faults detected while they act ("
        + describe_faults(delays) + "); "
        + (f"{len(leaked)} stayed in the fusion for over half their span. " if leaked else
           "none stayed in the fusion for over half its span. ")
    )
    if campaign is not None:
        lo, med, hi = np.percentile(campaign["position_m"], [2.5, 50, 97.5])
        note += (
            f"Over the {campaign['position_m'].size} runs of the headline campaign the fused "
            f"error is a median {med:.1f} m (95 % range {lo:.1f}-{hi:.1f} m) against "
            f"{np.median(campaign['clean_position_m']):.1f} m fault-free; seed {seed} is below "
            f"{np.sum(campaign['position_m'] > pos)} of them. The faults cost each run "
            f"{100 * (campaign['ratio'].min() - 1):+.1f} % to "
            f"{100 * (campaign['ratio'].max() - 1):+.1f} % of its own fault-free error "
            f"(median {100 * (np.median(campaign['ratio']) - 1):+.1f} %); the paper's run "
            f"cost {100 * (campaign['paper_ratio'] - 1):.0f} % of its fault-free "
            f"{headline.PAPER['fused_position_m']} m. "
        )
        eff = _effects(w_pos, lost, "position_m")
        eff_share = _effects(share, lost, "detected_fraction")
        ratios = {k: np.asarray(v["position_m"]) / np.asarray(runs["fused_position_m"][:LOST_RUNS])
                  for k, v in lost.items()}
        top = max(ratios, key=lambda k: ratios[k].max())
        note += (
            "The paper's fault sizes and XNAV drift rate are lost, so its numbers are judged over "
            "their plausible values (xnavlab.verdicts.check_lost; the range and its reason as in "
            f"mars-faults-ekf), each run on the campaign's first {LOST_RUNS} runs; mean paired "
            "effect on the fused error: " + ", ".join(f"{k} {v:+.2f} m" for k, v in eff.items())
            + "; on the share of faults detected while acting (ours "
            f"{np.median(share):.3f}): " + ", ".join(f"{k} {v:+.3f}" for k, v in eff_share.items())
            + ". " + _q_sentence(q_data, runs, q_iv) + "; the fused error: "
            + _q_text(q_iv, q_data, "wavelet", w_pos, "m", column=0) + "; the velocity error: "
            + _q_text(q_iv, q_data, "wavelet", w_vel, "m/s", column=1)
            + f". The costliest setting, {top}, costs at most "
            f"{100 * (ratios[top].max() - 1):+.1f} % of a run's fault-free error (the paper's "
            f"{100 * (campaign['paper_ratio'] - 1):.0f} %), so 'close to fault-free' holds at "
            "every plausible size. "
        )
        high = max(pos_reach, key=lambda k: pos_reach[k][1])
        if pos_reach[high][1] < PAPER_POSITION_ERROR_M:
            together = q_reach(w_pos, q_data, "joint", q_iv, 0)
            top_q = max(together, key=lambda k: together[k][1])
            alone = sum(eff[k] for k in JOINT_SIZES)
            base = np.mean(pos_reach[f"ours, q {_Q_OURS:g}"])
            reached = together[top_q][1] >= PAPER_POSITION_ERROR_M
            why = ("That is why it is left UNDECIDED, not refuted: the lost sizes and q, varied "
                   "jointly within their plausible values, reach the paper's number, which the "
                   "rule's margin (the spread of the values run one at a time) stands for. "
                   if reached else "It is left UNDECIDED only by the rule's margin (the spread "
                   "of the values run one at a time). ")
            note += (
                f"No plausible value varied alone brings our range to the paper's "
                f"{PAPER_POSITION_ERROR_M} m (the highest, {high}, reaches "
                f"{pos_reach[high][1]:.1f} m). Varied together ({', '.join(JOINT_SIZES)}; run on "
                f"the same {LOST_RUNS} runs at each q), the sizes that raise it move it by "
                f"{np.mean(together[f'ours, q {_Q_OURS:g}']) - base:+.2f} m at our q (their "
                f"effects alone sum to {alone:+.2f} m) and by {np.mean(together[top_q]) - base:+.2f} "
                f"m at {top_q}, the top of q's interval: our range then reaches "
                f"{together[top_q][1]:.1f} m" + (", past the paper's number" if reached else "")
                + ". " + (why if checks[0].verdict == "UNDECIDED" else "")  # the campaign's rows first
            )
        note += (
            f"The campaign's first run ({first['metrics']['position_error_m']:.0f} m): "
            + (", ".join(f"{e['sensor']} {e['kind']} at {e['onset']:.0f} s "
                         f"(in the fusion {100 * (1 - e['out_share']):.0f} % of it)"
                         for e in first["exposure"] if e["out_share"] < 0.5)
               or "no fault")
            + " reached the filter. "
        )
    note += (
        f"Hand-made schedule ({len(hd)} faults at onsets the paper does not use, {hand_days:g} "
        "days): " + describe_faults(hd) + f"; error ratio {hand_ratio:.2f} to the fault-free run."
    )
    data = {"t_days": ftr.run.t_days, "wavelet": ftr.run.position_error(),
            "clean": r["clean"].position_error(), "velocity": ftr.run.velocity_error(),
            "faults": r["faults"], "delays": delays, "exposure": exposure,
            "isolations": ftr.isolation_intervals(),
            "detections": ftr.detections, "metrics": m, "metrics_clean": m0,
            "hand_delays": hd, "hand_ratio": hand_ratio, "campaign": campaign, "first": first,
            "lost": lost, "lost_wall_s": t_lost, "q_runs": q_data, "q_interval": q_iv}
    result = Result("mars-faults-wavelet", checks, note, data)
    if out is not None:
        fig = plot_error_curves({"wavelet detection + isolation": (data["t_days"], data["wavelet"]),
                                 "fault-free": (data["t_days"], data["clean"])}, r["faults"],
                                title="mars-faults-wavelet (Fan et al. 2016, Fig. 4)",
                                isolations=data["isolations"])
        _save(result, out, fig, "mars-faults-wavelet")
    return result
