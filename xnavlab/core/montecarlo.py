"""Detection statistics by Monte Carlo: wavelet vs innovation chi-square, on any Executor.

Two kinds of trial, each a pure function of its parameters and one seed:

:func:`signal_trial`
    One fault in a white-noise series (the detectors' view of a sensor: the raw
    measurement for the wavelet, the innovation for the chi-square test, which for the UV and
    CNS sensors is the measurement noise to within a per cent because the filter's predicted
    uncertainty is far below the sensor noise). The wavelet detector (db3, 5 levels) is
    trained by MAD on a fault-free prefix of the series; the chi-square test uses the
    *modelled* noise (unit), as a filter's innovation covariance does. ``noise_scale`` makes
    the true noise differ from the modelled one. Returns, per detector, whether the fault was
    detected, the delay, the false alarms before it and the largest ratio (statistic /
    threshold) inside and outside the fault (for ROC curves).

(The Mars-run trials live with the Mars system: :mod:`xnavlab.mars.studies.trials`.)

:func:`run_tasks` maps a trial over a list of parameter dicts with any
:class:`concurrent.futures.Executor` (default: a local ``ProcessPoolExecutor`` with two
workers). Every task gets its own seed from one ``numpy.random.SeedSequence(seed).spawn``,
so results do not depend on the executor, the number of workers or the order of completion.
A Dask cluster plugs in through ``distributed.Client(...).get_executor()``.
:func:`detection_table` seeds each trial from its cell instead (:func:`cell_seeds`: the
fault kind, the size and the trial's index), so that a cell's row does not depend on the
other kinds and sizes of the call either.

Fault sizes are in noise standard deviations: a step's or spike's height; the excursion a ramp
reaches at its end; the standard deviation of the extra noise of a ``noise`` fault.

Examples
--------
>>> r = signal_trial("step", 8.0, seed=1)
>>> r["wavelet"]["detected"], r["chi2"]["detected"]
(True, True)
"""

from __future__ import annotations

import inspect
import math
import os
from concurrent.futures import Executor, ProcessPoolExecutor

import numpy as np

from xnavlab.core.detection import chi2_detect, wavelet_detect
from xnavlab.core.distributions import norm_isf
from xnavlab.core.faults import Fault, inject
from xnavlab.core.plotting import sparse_log_minors
from xnavlab.core.validate import (
    check_choice,
    check_finite_array,
    check_int,
    check_items,
    check_keywords,
    check_real,
    check_seed,
    check_text,
    shown,
)

__all__ = ["KINDS", "DETECTORS", "signal_trial", "run_tasks", "seeds", "cell_seeds",
           "detection_table", "roc_curve", "summarise", "plot_roc", "plot_pd",
           "wilson_interval", "runs_for_halfwidth", "plot_pd_error"]

#: Fault kinds of :func:`signal_trial`.
KINDS = ("step", "ramp", "spike", "noise")
#: Detectors compared.
DETECTORS = ("wavelet", "chi2")

_DT = 3.0


def seeds(seed, n):
    """``n`` independent integer seeds from one seed (``SeedSequence(seed).spawn(n)``).

    Examples
    --------
    >>> seeds(0, 3) == seeds(0, 3), len(set(seeds(0, 3)))
    (True, 3)
    """
    seed = check_seed("seed", seed)
    n = check_int("n", n, 0, 10**7)  # as a campaign's runs
    return _integers(np.random.SeedSequence(seed).spawn(n))


def _integers(sequences):
    """One integer seed in ``[0, 2**63)`` from each ``SeedSequence``."""
    return [int(s.generate_state(1, np.uint64)[0] >> np.uint64(1)) for s in sequences]


def cell_seeds(seed, kind, size_sigma, trials):
    """The seeds of trials ``0 .. trials - 1`` of one cell of :func:`detection_table`.

    Trial ``j`` of the cell ``(kind, size_sigma)`` is seeded from child ``j`` of
    ``SeedSequence(seed, spawn_key=(i, b))``, where ``i`` is ``kind``'s position in
    :data:`KINDS` and ``b`` the 64 bits of ``size_sigma`` as a float: a pure function of
    ``(seed, kind, size_sigma, j)``, whatever other kinds, sizes or trials a table holds.

    Parameters
    ----------
    seed : int
        The table's seed, in [0, 2^63 - 1].
    kind : {"step", "ramp", "spike", "noise"}
    size_sigma : float
        Fault size, noise standard deviations, in [0, 1000].
    trials : int
        Trials of the cell, 0 to 10^7.

    Returns
    -------
    list of int
        One seed a trial, each in [0, 2^63).

    Examples
    --------
    >>> cell_seeds(0, "step", 2.0, 3)[:2] == cell_seeds(0, "step", 2.0, 2)
    True
    >>> cell_seeds(0, "step", 2.0, 1) == cell_seeds(0, "step", 3.0, 1)
    False
    """
    seed = check_seed("seed", seed)
    check_choice("kind", kind, KINDS)
    size = check_real("size_sigma", size_sigma, 0.0, 1000.0) + 0.0  # -0.0 is 0.0
    trials = check_int("trials", trials, 0, 10**7)
    bits = int(np.float64(size).view(np.uint64))
    root = np.random.SeedSequence(seed, spawn_key=(KINDS.index(kind), bits))
    return _integers(root.spawn(trials))


def signal_trial(kind, size_sigma, *, seed=0, n=4000, train=1500, duration=300, noise_scale=1.0,
                 pfa=1e-5, window=None):
    """One fault in a unit white-noise series, seen by both detectors.

    Parameters
    ----------
    kind : {"step", "ramp", "spike", "noise"}
    size_sigma : float
        Fault size, noise standard deviations, in [0, 1000] (0: no fault, for false alarms).
    seed : int
        Seed of this trial's generator.
    n : int
        Samples (3 s apart), in [train + 2 duration + 400, 1e7].
    train : int
        Fault-free samples the wavelet trains on, in [356, 1e6]; both detectors decide after it.
    duration : int
        Fault length, samples, in [1, 1e6].
    noise_scale : float
        True noise / modelled noise, in (0, 100].
    pfa : float
        False-alarm probability per sample of both detectors (the chi-square ``alpha``).
    window : int, optional
        Samples after the fault's end in which a first alarm makes the fault *late* (default
        200); never a detection.

    Returns
    -------
    dict
        ``onset`` (s) and for each detector: ``detected`` (bool: an alarm raised while the
        fault acts, ``[onset, end)``; a spike acts on its own sample only), ``delay`` (s from
        the onset, inf unless detected), ``late`` (bool: not detected, and an alarm raised in
        the ``window`` samples after the end), ``false_alarms`` (alarm samples before the
        onset), ``armed_before`` (samples), ``peak_fault`` and ``peak_clean`` (largest ratio
        while the fault acts and in an equally long fault-free span before it).

    Notes
    -----
    The rule is the book's one scoring rule (:func:`xnavlab.mars.faults.schedules.score_faults`) on a
    single series: a fault counts as detected only by an alarm while it acts; an alarm after
    its end comes after the whole fault reached the filter, and is counted apart.
    """
    check_choice("kind", kind, KINDS)
    size_sigma = check_real("size_sigma", size_sigma, 0.0, 1000.0)
    train = check_int("train", train, 356, 10**6)
    duration = check_int("duration", duration, 1, 10**6)
    n = check_int("n", n, train + 2 * duration + 400, 10**7)
    noise_scale = check_real("noise_scale", noise_scale, 0.0, 100.0, lo_open=True)
    window = 200 if window is None else check_int("window", window, 0, 10**7)
    rng = np.random.default_rng(check_seed("seed", seed))
    t = _DT * np.arange(n)
    lo = train + duration + 200
    k_on = int(rng.integers(lo, n - duration - window)) if n - duration - window > lo else lo
    onset = t[k_on]
    x = noise_scale * rng.standard_normal(n)
    if size_sigma > 0:
        mag = size_sigma / (duration * _DT) if kind == "ramp" else size_sigma
        x = inject(t, x, [Fault("s", kind, mag, onset, duration * _DT)], "s", rng)
    stop = onset + (1 if kind == "spike" else duration) * _DT       # the fault acts in [onset, stop)
    fault_win = (t >= onset) & (t < stop)
    clean_win = (t >= 2 * onset - stop) & (t < onset)
    late_win = (t >= stop) & (t < stop + window * _DT)
    out = {"onset": float(onset)}
    wav = wavelet_detect(t, x, train=train, pfa=pfa)
    chi = chi2_detect(t, x, np.ones(n), alpha=pfa)
    chi.armed[:train] = False
    chi.alarm[:train] = False
    for name, det in (("wavelet", wav), ("chi2", chi)):
        first = t[det.alarm & fault_win][:1]
        before = det.armed & (t < onset)
        out[name] = {
            "detected": bool(first.size),
            "delay": float(first[0] - onset) if first.size else math.inf,
            "late": bool(not first.size and np.any(det.alarm & late_win)),
            "false_alarms": int(np.sum(det.alarm & before)),
            "armed_before": int(np.sum(before)),
            "peak_fault": float(np.max(det.ratio[fault_win])),
            "peak_clean": float(np.max(det.ratio[clean_win & det.armed])),
        }
    return out


def _call(args):
    func, params, seed = args
    return func(seed=seed, **params)


def _listed(name, value, what):
    """``value`` as a list (a list, tuple or 1-D array; items may repeat), else one ValueError."""
    if isinstance(value, str | bytes | dict) or not hasattr(value, "__iter__") or \
            isinstance(value, np.ndarray) and value.ndim != 1:
        raise ValueError(f"{name} must be a list of {what}, got {shown(value)}")
    return list(value)


def _signature(func):
    """``func``'s signature, or None when it has none to read (a builtin)."""
    try:
        return inspect.signature(func)
    except (TypeError, ValueError):
        return None


def _check_task(func, sig, i, p):
    """Task ``i``'s keywords ``p`` against ``func(seed=..., **p)``: one ValueError naming
    ``params[i]`` (a typo or a missing parameter was a TypeError inside the task)."""
    check_keywords("run_tasks", p, func, name=f"params[{i}]",
                   set_here={"seed": "one per task, from run_tasks' seed"})
    try:
        sig.bind(seed=0, **p)
    except TypeError as err:
        name = getattr(func, "__name__", "func")
        raise ValueError(f"params[{i}] does not fit {name}(seed=..., **params[{i}]): {err}") from None


def run_tasks(func, params, *, seed=0, executor=None, max_workers=2, chunksize=1):
    """Run ``func(seed=s_i, **params[i])`` for every task, on an Executor.

    Parameters
    ----------
    func : callable
        A module-level function (picklable), e.g. :func:`signal_trial`.
    params : sequence of dict
        One keyword dict per task: each must fit ``func``'s signature (a misspelt or missing
        keyword is refused, naming ``params[i]``), without ``seed`` (set here).
    seed : int
        The one seed; task ``i`` gets ``seeds(seed, len(params))[i]``.
    executor : concurrent.futures.Executor, optional
        Any executor: a ``ThreadPoolExecutor``, a ``ProcessPoolExecutor``, or a Dask cluster's
        ``Client.get_executor()``. Default: a local ``ProcessPoolExecutor(max_workers)``,
        created and shut down here.
    max_workers : int
        Workers of the default pool, 1 to the number of CPUs.
    chunksize : int
        Tasks per round trip of the default pool.

    Returns
    -------
    list
        The results in task order.

    Examples
    --------
    >>> from concurrent.futures import ThreadPoolExecutor
    >>> with ThreadPoolExecutor(2) as ex:
    ...     a = run_tasks(signal_trial, [{"kind": "spike", "size_sigma": 9.0}] * 2, executor=ex)
    >>> b = run_tasks(signal_trial, [{"kind": "spike", "size_sigma": 9.0}] * 2, max_workers=1)
    >>> a == b
    True
    """
    if not callable(func):
        raise ValueError(f"func must be callable, got {type(func).__name__}")
    params = _listed("params", params, "keyword dicts (one per task)")
    sig = _signature(func)
    for i, p in enumerate(params):
        if not isinstance(p, dict):
            raise ValueError(f"params[{i}] must be a dict of keywords, got {type(p).__name__} {shown(p)}")
        if sig is not None:
            _check_task(func, sig, i, p)
    return _map(func, params, seeds(seed, len(params)), executor, max_workers, chunksize)


def _map(func, params, task_seeds, executor, max_workers, chunksize):
    """``func(seed=task_seeds[i], **params[i])`` for every task, in task order, on
    ``executor`` (checked here) or the default pool."""
    args = list(zip([func] * len(params), params, task_seeds, strict=True))
    if executor is not None:
        if not isinstance(executor, Executor) and not hasattr(executor, "map"):
            raise ValueError(f"executor must be a concurrent.futures.Executor, got "
                             f"{type(executor).__name__}")
        return list(executor.map(_call, args))
    max_workers = check_int("max_workers", max_workers, 1, os.cpu_count() or 1)
    chunksize = check_int("chunksize", chunksize, 1, 10**7)
    if max_workers == 1:
        return [_call(a) for a in args]
    with ProcessPoolExecutor(max_workers=max_workers) as pool:
        return list(pool.map(_call, args, chunksize=chunksize))


def _trials(results, detector, keys):
    """Each trial's result of ``detector`` (a dict holding ``keys``), from ``results`` (trials
    of :func:`signal_trial`, at least one), else one ValueError naming ``results[i]``."""
    results = _listed("results", results, "trials (signal_trial)")
    check_choice("detector", detector, DETECTORS)
    if not results:  # an empty mean would be NaN
        raise ValueError("results must hold at least one trial (signal_trial)")
    for i, x in enumerate(results):
        part = x.get(detector) if isinstance(x, dict) else None
        if not isinstance(part, dict) or any(k not in part for k in keys):
            raise ValueError(f"results[{i}] must be a trial of signal_trial (a dict with "
                             f"{detector!r}: a dict of {', '.join(keys)}), got "
                             f"{type(x).__name__} {shown(x)}")
    return [x[detector] for x in results]


def summarise(results, detector):
    """Probability of detection, share of late trials (flagged only after the fault's end),
    false-alarm rate per sample and median delay of the detected trials.

    Examples
    --------
    >>> rs = [signal_trial("step", 10.0, seed=s) for s in range(3)]
    >>> summarise(rs, "wavelet")["pd"]
    1.0
    """
    r = _trials(results, detector, ("detected", "delay", "false_alarms", "armed_before"))
    found = [x["delay"] for x in r if x["detected"]]
    armed = sum(x["armed_before"] for x in r)
    return {"pd": float(np.mean([x["detected"] for x in r])),
            "late": float(np.mean([x.get("late", False) for x in r])),
            "far": float(sum(x["false_alarms"] for x in r) / armed) if armed else math.nan,
            "median_delay_s": float(np.median(found)) if found else math.inf,
            "trials": len(r)}


def detection_table(kinds=KINDS, sizes=(2.0, 4.0, 8.0), *, trials=20, seed=0, noise_scale=1.0,
                    executor=None, max_workers=2, **trial_kw):
    """Pd, false-alarm rate and median delay per fault kind and size for both detectors.

    ``**trial_kw`` are passed to every :func:`signal_trial` (``n``, ``train``, ``duration``,
    ``pfa``, ``window``); another keyword is refused, naming it (``kind``, ``size_sigma`` and
    ``seed`` are set here).

    Trial ``j`` of the cell ``(kind, size)`` is seeded by ``cell_seeds(seed, kind, size,
    trials)[j]`` (:func:`cell_seeds`): one cell gives one row whatever other kinds and sizes
    the call holds and in whichever order, the first ``k`` trials of a cell are the same for
    any ``trials >= k``, and the rows depend neither on the executor nor on the number of
    workers. ``noise_scale`` and ``**trial_kw`` are not part of a trial's seed: the same
    seed draws the same onset and unit noise (scaled) at every noise scale, so two tables
    that differ only there compare paired trials.

    Returns
    -------
    list of dict
        One row per (kind, size): ``kind``, ``size_sigma``, ``noise_scale`` and, per detector,
        ``{det}_pd``, ``{det}_late`` (share flagged only after the end), ``{det}_far``,
        ``{det}_delay_s`` (median over the detected trials, inf when none); plus ``winner``
        (higher Pd, then the shorter delay, then the lower false-alarm rate).

    Examples
    --------
    >>> rows = detection_table(("step", "spike"), (10.0,), trials=2, max_workers=1)
    >>> rows[0]["wavelet_pd"], rows[0]["chi2_pd"], rows[0]["winner"]
    (1.0, 1.0, 'chi2')
    >>> rows[1]["wavelet_pd"], rows[1]["wavelet_late"]        # a spike: flagged after its sample
    (0.0, 1.0)
    """
    trials = check_int("trials", trials, 1, 10**6)
    # signal_trial's range; a float in the rows (a Fraction was stored as given)
    noise_scale = check_real("noise_scale", noise_scale, 0.0, 100.0, lo_open=True)
    sizes = [check_real(f"sizes[{i}]", s, 0.0, 1000.0)  # signal_trial's size_sigma range
             for i, s in enumerate(check_items("sizes", sizes, "size"))]
    kinds = check_items("kinds", kinds, "kind", each=lambda label, k: check_choice(label, k, KINDS))
    trial_kw = check_keywords("detection_table", trial_kw, signal_trial, set_here={
        "kind": "from kinds", "size_sigma": "from sizes", "seed": "one per trial, from seed"})
    seed = check_seed("seed", seed)
    cells = [(k, float(s)) for k in kinds for s in sizes]
    params = [dict(kind=k, size_sigma=s, noise_scale=noise_scale, **trial_kw)
              for k, s in cells for _ in range(trials)]
    task_seeds = [x for k, s in cells for x in cell_seeds(seed, k, s, trials)]
    res = _map(signal_trial, params, task_seeds, executor, max_workers, 1)
    rows = []
    for c, (k, s) in enumerate(cells):
        chunk = res[c * trials:(c + 1) * trials]
        row = {"kind": k, "size_sigma": s, "noise_scale": noise_scale}
        for d in DETECTORS:
            sm = summarise(chunk, d)
            row[f"{d}_pd"], row[f"{d}_late"], row[f"{d}_far"], row[f"{d}_delay_s"] = (
                sm["pd"], sm["late"], sm["far"], sm["median_delay_s"])
        row["winner"] = _winner(row)
        rows.append(row)
    return rows


def _winner(row):
    w, c = row, DETECTORS
    key = {d: (-round(w[f"{d}_pd"], 2), w[f"{d}_delay_s"], w[f"{d}_far"]) for d in c}
    a, b = key["wavelet"], key["chi2"]
    if a == b:
        return "tie"
    return "wavelet" if a < b else "chi2"


def roc_curve(results, detector, thresholds=None):
    """ROC from trials: for each threshold on the ratio, the fraction of faults whose peak
    while they act exceeds it (Pd) and of equally long fault-free spans (Pfa per span).

    Parameters
    ----------
    results : sequence of dict
        Trials (:func:`signal_trial`), at least one.
    detector : str
        One of :data:`DETECTORS`.
    thresholds : array_like, optional
        Thresholds on the ratio, shape (k,), k >= 1, finite (default 200 from 0.2 to 20),
        in any order: they are taken in increasing order.

    Returns
    -------
    pfa, pd, thresholds : ndarray
        Shape (k,) each: the thresholds in increasing order, and at each the Pfa and Pd
        (hence both non-increasing).

    Examples
    --------
    >>> rs = [signal_trial("step", 4.0, seed=s) for s in range(3)]
    >>> pfa, pd, thr = roc_curve(rs, "wavelet", [3.0, 1.0, 2.0])
    >>> thr.tolist(), bool(all(pd[:-1] >= pd[1:]))
    ([1.0, 2.0, 3.0], True)
    """
    r = _trials(results, detector, ("peak_fault", "peak_clean"))
    pf = np.array([x["peak_fault"] for x in r])
    pc = np.array([x["peak_clean"] for x in r])
    if thresholds is None:
        thresholds = np.geomspace(0.2, 20.0, 200)
    thr = check_finite_array("thresholds", thresholds)
    if thr.ndim != 1 or thr.size < 1:
        raise ValueError(f"thresholds must be a sequence of at least one finite number "
                         f"(shape (k,)), got shape {thr.shape}")
    thr = np.sort(thr)
    return (np.mean(pc[None, :] > thr[:, None], axis=1),
            np.mean(pf[None, :] > thr[:, None], axis=1), thr)


def plot_roc(curves, title=""):
    """ROC curves: ``curves`` maps a label to ``(pfa, pd)`` (two equally long 1-D arrays of
    probabilities, as :func:`roc_curve` gives), at least one; returns a Figure.

    Each curve's points are drawn in order of increasing Pfa (then Pd), whatever their order
    in the arrays, as a staircase that holds a point's Pd up to the next point's Pfa: the Pd
    a threshold reaches without exceeding that false-alarm probability.

    Examples
    --------
    >>> fig = plot_roc({"a": ([0.5, 0.1, 0.3], [0.9, 0.2, 0.6])})
    >>> fig.axes[0].lines[0].get_xdata().tolist()
    [0.1, 0.3, 0.5]
    """
    from matplotlib.figure import Figure

    if not isinstance(curves, dict) or not curves:
        raise ValueError(f"curves must be a dict of label -> (pfa, pd), at least one, got "
                         f"{shown(curves)}")
    pairs = {}
    for label, pair in curves.items():
        if not isinstance(pair, tuple | list) or len(pair) != 2:
            raise ValueError(f"curves[{label!r}] must be a pair (pfa, pd), got {shown(pair)}")
        pf = check_finite_array(f"curves[{label!r}] pfa", pair[0])
        pd = check_finite_array(f"curves[{label!r}] pd", pair[1])
        if pf.ndim != 1 or pd.shape != pf.shape or np.any((pf < 0) | (pf > 1) | (pd < 0) | (pd > 1)):
            raise ValueError(f"curves[{label!r}] must be two equally long 1-D arrays of "
                             f"probabilities in [0, 1], got shapes {pf.shape} and {pd.shape}")
        order = np.lexsort((pd, pf))  # by Pfa, then Pd: the staircase runs left to right
        pairs[str(label)] = (pf[order], pd[order])
    title = check_text("title", title)
    fig = Figure(figsize=(5.0, 4.0), layout="constrained")
    ax = fig.add_subplot()
    for label, (pf, pd) in pairs.items():
        ax.plot(pf, pd, lw=1.2, label=label, drawstyle="steps-post")
    ax.plot([0, 1], [0, 1], color="0.7", lw=0.6, ls=":")
    ax.set(xlabel="false alarm probability per window", ylabel="probability of detection",
           xlim=(-0.02, 1.02), ylim=(-0.02, 1.02), title=title)
    ax.legend(fontsize=8, loc="lower right")
    return fig


def plot_pd(kind="step", noise_scale=1.0, trials=30, seed=0, sizes=(1.0, 2.0, 3.0, 4.0, 6.0, 8.0)):
    """Pd and median delay against fault size for both detectors (serial; the chapter's slider).

    ``sizes`` (each in [0, 1000] sigma, none twice) are drawn in increasing order, whatever
    their order in the call; each size's trials are seeded from its cell
    (:func:`detection_table`), so its point does not depend on the other sizes.

    Returns
    -------
    matplotlib.figure.Figure
        It carries an in-place update (:func:`xnavlab.core.plotting.in_place`) for the same
        ``sizes``: a live slider sets its data, limits and title.

    Examples
    --------
    >>> fig = plot_pd(kind="step", trials=2, sizes=(4.0, 8.0))
    >>> [ax.get_xlabel() for ax in fig.axes]
    ['fault size (sigma)', 'fault size (sigma)']
    >>> fig = plot_pd(kind="spike", trials=1, sizes=(1.0,))   # nothing detected
    >>> fig.axes[1].get_ylim()
    (0.0, 10000.0)
    """
    from matplotlib.figure import Figure

    from xnavlab.core.plotting import in_place

    built = _sorted_sizes(sizes)
    # the layout every frame shares; update() sets the curves, the delay axis and the title
    fig = Figure(figsize=(8.5, 3.2), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2)
    pd_lines, delay_lines = {}, {}
    for d in DETECTORS:
        pd_lines[d], = ax1.plot(built, np.zeros(len(built)), "o-", label=d)
        delay_lines[d], = ax2.plot(built, np.ones(len(built)), "o-", label=d)
    # symmetric log, linear below 1 s: a spike flagged at its own sample has a delay of 0 s,
    # which a log axis cannot show (it warned and dropped the point)
    ax2.set_yscale("symlog", linthresh=1.0)
    ax1.set(xlabel="fault size (sigma)", ylabel="probability of detection", ylim=(-0.05, 1.05))
    ax2.set(xlabel="fault size (sigma)", ylabel="median delay (s; linear below 1)")
    ax1.legend(fontsize=8)
    title = fig.suptitle("", fontsize=9)

    def update(kind="step", noise_scale=1.0, trials=30, seed=0,
               sizes=(1.0, 2.0, 3.0, 4.0, 6.0, 8.0)):
        check_choice("kind", kind, KINDS)
        trials = check_int("trials", trials, 1, 1000)
        if _sorted_sizes(sizes) != built:
            return False  # other sizes: a new figure
        rows = detection_table((kind,), built, trials=trials, seed=seed,
                               noise_scale=noise_scale, max_workers=1)
        noise_scale = rows[0]["noise_scale"]  # as detection_table checked it (a float)
        for d in DETECTORS:
            pd_lines[d].set_ydata([r[f"{d}_pd"] for r in rows])
            delay_lines[d].set_ydata([r[f"{d}_delay_s"] for r in rows])
        delays = np.array([r[f"{d}_delay_s"] for r in rows for d in DETECTORS])
        ax2.set_autoscaley_on(True)
        ax2.relim()
        if np.any(np.isfinite(delays)):
            ax2.autoscale_view()
            lo, hi = ax2.get_ylim()  # no negative margin below a delay of 0 s; 1 s at least
            ax2.set_ylim(max(lo, 0.0), max(hi, 1.0))
        else:  # nothing detected: no delay to scale the axis to
            ax2.set_ylim(0.0, 1e4)
            ax2.autoscale_view(scaley=False)
        far = {d: np.mean([r[f"{d}_far"] for r in rows]) for d in DETECTORS}
        title.set_text(f"{kind}, true/modelled noise {noise_scale:g}, {trials} trials per size; "
                       f"false alarms per sample: wavelet {far['wavelet']:.1e}, "
                       f"chi2 {far['chi2']:.1e}")
        return None

    update(kind, noise_scale, trials, seed, sizes)
    return in_place(fig, update)


def _sorted_sizes(sizes):
    """``sizes`` checked (a list of sizes in signal_trial's range, none twice), increasing."""
    return tuple(sorted(check_real(f"sizes[{i}]", s, 0.0, 1000.0)
                        for i, s in enumerate(check_items("sizes", sizes, "size"))))


def wilson_interval(k, n, level=0.95):
    """Wilson score interval of a probability from ``k`` successes in ``n`` trials.

    ``(p + z^2/2n -/+ z sqrt(p (1 - p)/n + z^2/4n^2)) / (1 + z^2/n)`` with ``p = k/n`` and
    ``z`` the two-sided normal quantile of ``level``; unlike ``p -/+ z sqrt(p (1 - p)/n)``
    it stays inside [0, 1] and does not shrink to a point at ``k = 0`` or ``k = n``.

    Parameters
    ----------
    k, n : int
        Successes (detections) and trials, ``0 <= k <= n``, ``n >= 1``.
    level : float
        Confidence level, in (0, 1).

    Returns
    -------
    lo, hi : float

    Examples
    --------
    >>> lo, hi = wilson_interval(9, 10)
    >>> round(lo, 3), round(hi, 3)
    (0.596, 0.982)
    """
    n = check_int("n", n, 1)
    k = check_int("k", k, 0, n)
    level = check_real("level", level, 0.0, 1.0, lo_open=True, hi_open=True)
    z = norm_isf((1.0 - level) / 2.0)
    p = k / n
    den = 1.0 + z * z / n
    centre = (p + z * z / (2 * n)) / den
    half = z * math.sqrt(p * (1.0 - p) / n + z * z / (4.0 * n * n)) / den
    return max(0.0, centre - half), min(1.0, centre + half)


def runs_for_halfwidth(pd, halfwidth, level=0.95):
    """Runs that make the normal-approximation interval of a probability ``pd`` as narrow as
    ``+/- halfwidth``: ``N = z^2 pd (1 - pd) / halfwidth^2`` (rounded up).

    Parameters
    ----------
    pd : float
        The probability, in (0, 1).
    halfwidth : float
        Half-width of the interval, in [1e-6, 0.5].
    level : float
        Confidence level, in (0, 1).

    Examples
    --------
    >>> runs_for_halfwidth(0.95, 0.01)
    1825
    """
    pd = check_real("pd", pd, 0.0, 1.0, lo_open=True, hi_open=True)
    # From 1e-6: about 1e12 runs, more than any Monte Carlo makes (1e-300 squared to 0).
    halfwidth = check_real("halfwidth", halfwidth, 1e-6, 0.5)
    level = check_real("level", level, 0.0, 1.0, lo_open=True, hi_open=True)
    z = norm_isf((1.0 - level) / 2.0)
    return math.ceil(z * z * pd * (1.0 - pd) / halfwidth**2)  # N = z^2 pd (1 - pd) / h^2


def plot_pd_error(runs=100, pd=0.9, campaigns=400, seed=0):
    """How the Monte Carlo error of a detection probability shrinks with the number of runs.

    Simulates ``campaigns`` independent campaigns of ``runs`` detection trials each, every
    trial a detection with probability ``pd`` (a binomial draw: the detector itself is not
    run), and plots the spread of their estimates ``k / runs`` with the 95 % half-width
    ``1.96 sqrt(pd (1 - pd) / runs)``; a second panel shows that half-width against the runs
    (the ``1 / sqrt(N)`` law) and the share of campaigns whose Wilson interval
    (:func:`wilson_interval`) holds the true ``pd``. A pure function of its arguments, for
    the campaigns chapter's slider.

    Parameters
    ----------
    runs : int
        Runs per campaign, 1 to 10^6.
    pd : float
        True detection probability, in (0, 1).
    campaigns : int
        Simulated campaigns, 10 to 10^5.
    seed : int
        Seed of the binomial draws.

    Returns
    -------
    matplotlib.figure.Figure
        Two axes; not registered with pyplot. It carries an in-place update
        (:func:`xnavlab.core.plotting.in_place`) that a live slider calls.

    Examples
    --------
    >>> fig = plot_pd_error(50, 0.9, campaigns=100)
    >>> fig.axes[0].get_xlabel()
    'estimated Pd (k / N)'
    """
    from matplotlib.figure import Figure

    from xnavlab.core.plotting import in_place

    # the layout every frame shares; update() draws the histogram and sets the rest
    fig = Figure(figsize=(8.5, 3.2), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2)
    truth = ax1.axvline(0.5, color="k", lw=1.0, label="true Pd")
    bounds = [ax1.axvline(0.5, color="C3", ls="--", lw=1.0,
                          label="+/- 1.96 sqrt(Pd(1-Pd)/N)" if sgn < 0 else None)
              for sgn in (-1, 1)]
    ax1.set(xlabel="estimated Pd (k / N)", ylabel="campaigns", xlim=(-0.02, 1.02))
    legend = ax1.legend(fontsize=7, loc="upper left")
    n_grid = np.unique(np.geomspace(1, 10**4, 60).astype(int))
    law, = ax2.loglog(n_grid, np.ones(n_grid.size), color="C3")
    point, = ax2.plot([1.0], [1.0], "o", color="C0")
    ax2.set(xlabel="runs N", ylabel="95 % half-width of the Pd estimate")
    ax2.grid(True, which="both", lw=0.3)
    sparse_log_minors(ax2)
    bars = []

    def update(runs=100, pd=0.9, campaigns=400, seed=0):
        runs = check_int("runs", runs, 1, 10**6)
        pd = check_real("pd", pd, 0.0, 1.0, lo_open=True, hi_open=True)
        campaigns = check_int("campaigns", campaigns, 10, 10**5)
        rng = np.random.default_rng(check_seed("seed", seed))
        k = rng.binomial(runs, pd, size=campaigns)
        est = k / runs
        half = 1.96 * math.sqrt(pd * (1.0 - pd) / runs)      # normal approximation, 95 %
        cover = np.mean([lo <= pd <= hi for lo, hi in (wilson_interval(int(x), runs) for x in k)])
        for bar in bars:
            bar.remove()
        edges = (np.arange(runs + 2) - 0.5) / runs if runs <= 200 else np.linspace(0, 1, 101)
        bars[:] = ax1.hist(est, bins=edges, color="C0", alpha=0.7)[2]
        truth.set_xdata([pd, pd])
        legend.get_texts()[0].set_text(f"true Pd {pd:g}")
        for sgn, line in zip((-1, 1), bounds, strict=True):
            line.set_xdata([pd + sgn * half] * 2)
        ax1.set_title(f"{campaigns} campaigns of N = {runs} runs")
        law.set_ydata(1.96 * np.sqrt(pd * (1.0 - pd) / n_grid))
        point.set_data([runs], [half])
        ax2.set_title(f"Wilson intervals holding the true Pd: {cover:.0%}")
        for ax in (ax1, ax2):
            ax.relim()
            ax.autoscale_view()
        return None

    update(runs, pd, campaigns, seed)
    return in_place(fig, update)
