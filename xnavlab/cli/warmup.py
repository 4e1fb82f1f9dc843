"""``python -m xnavlab warmup``: compile every numba kernel the chapters use, and fill the caches.

``make setup`` runs it once after installing, so no reader's chapter (and no timed first
``run mars``) pays for a compile: numba writes each compiled kernel to its on-disk cache
(``cache=True``, in ``__pycache__`` beside the source) and every later process loads it in
milliseconds. It also computes into the truth cache (``$XNAVLAB_CACHE``, default
``~/.cache/xnavlab``): the paper's 30-day Mars truth trajectory, which chapters 5, 6 and 8
and the Mars reproductions use; the table of matched vs mismatched force models of chapters
3, 5 and 6 (:func:`xnavlab.mars.navigation.model_mismatch.mismatch_table`, with the studies' rich truth
before it); chapter 10's Monte Carlo reproductions and its table of the RKF's bound
(:func:`xnavlab.robust.plots.bound_table`) and chapter 5's ``mars-subsystems`` (minutes
together, shared out over the cores once the kernel is compiled). No chapter cell then waits
minutes, and two chapters executed side by side (``make book``, ``pytest -n 2``) do not
wait for each other. (The headline campaign of chapters 6 and 8, 32 noise seeds of the 30-day
run, is shipped with the package: :data:`xnavlab.mars.navigation.headline.RUNS_PATH`.)

Each step runs a tiny case through the same public functions the chapters call, so the
kernels are compiled for exactly the argument types the chapters pass. Running it again
is cheap (everything is loaded from the caches).

The filter kernel's compile is the longest step (about two minutes on two cores: 92-110 s
measured) and uses one core. Where it is still to be done, and the machine has a second core, it runs
in a second process (:func:`compile_kernel`) while this one does the steps listed before it,
which need no kernel: the truths the chapters plot (chapters 2 and 3, every force-model
variant of chapter 3's slider) and PINT's witnesses of chapter 1, so that no chapter's
first run waits for them either. The steps after it wait for it.
"""

from __future__ import annotations

import concurrent.futures
import functools
import multiprocessing
import os
import subprocess
import sys
import time

__all__ = ["HELP", "STEPS", "KERNEL_STEP", "compile_kernel", "configure", "execute", "warm"]

#: One-line help of the command (``python -m xnavlab --help``).
HELP = "compile and cache the numba kernels and the 30-day Mars truth (make setup runs it)"


def _mars_truth():
    from xnavlab.mars.navigation import scenarios

    scenarios.prepare(scenarios.MarsScenario())  # the paper's 30 days: truth cached on disk


def compile_kernel():
    """Compile the federated filter kernel into numba's cache (a 0.02-day run).

    The step :data:`KERNEL_STEP` of :func:`warm`, which runs it in a second process
    (``python -c "from xnavlab.cli import warmup; warmup.compile_kernel()"``).
    """
    from xnavlab.mars.navigation import scenarios

    scenarios.run(scenarios.MarsScenario(days=0.02, record_dt=60.0))


def _force_models():
    from xnavlab.mars.models import dynamics

    dynamics.chapter_truths()  # the keys plot_model_difference and chapters 2 and 3 use


def _pint_witnesses():
    from xnavlab.mars.timing import pint_bridge

    pint_bridge.fermi_photon_phases()  # chapter 1's calls: stored under $XNAVLAB_CACHE
    pint_bridge.nanograv_residuals()


def _mars_fault_tolerant():
    from xnavlab.mars.faults import fault_tolerance
    from xnavlab.mars.navigation import scenarios

    sc = scenarios.MarsScenario(days=0.05, record_dt=60.0)
    for detector in fault_tolerance.DETECTORS:
        if detector != "none":
            fault_tolerance.run_fault_tolerant(sc, [], detector, train_days=0.02)


def _ephemeris_error():
    import numpy as np

    from xnavlab.robust import ephemeris_error as ee

    for body in ee.PLANETS:
        ee.propagate(np.array(ee.orbit(body).state0), 60.0, body)


def _study_truth():
    from xnavlab.mars.navigation.scenarios import MarsScenario, prepare

    # the rich truth (MRO95A 8x8, planets, SRP) on the runs' 30-day grid, and the first day's
    # truth behind its derived q_acc (MarsScenario.study)
    prepare(MarsScenario.study(days=30.0))


def _timing_tables():
    from xnavlab.mars.timing import fold_toa, timing_bound

    timing_bound.accuracy_table(cache=True)  # chapter 1's call: 2000 ML, 300 cross-correlation folds
    fold_toa.window_survey(cache=True)  # chapter 2's two surveys of the fold over one orbit
    fold_toa.window_survey(error=fold_toa.SETTLED_ERROR, cache=True)


def _model_mismatch():
    from xnavlab.mars.navigation import model_mismatch

    model_mismatch.mismatch_table()  # the chapters' call (3, 5, 6): stored under $XNAVLAB_CACHE


def _combined_detector():
    import numpy as np

    from xnavlab.core.detection import combined

    # compiles the detector's two numba scans (numba's disk cache): chapter 9's first run and
    # its slider's first move would otherwise pay about 8 s for them
    t = 3.0 * np.arange(3000)
    y = np.random.default_rng(0).normal(0.0, 1.0, (3000, 1))
    combined.combined_detect(t, y, train=1000)   # _scan_rows (ratios recorded)
    combined.InnovationMonitor(combined.CombinedDesign(28800.0, 1)).process(t, y)   # _scan


def _attitude_bank():
    from xnavlab.attitude import simulation

    # compiles the attitude filter bank (numba's disk cache): chapter 11's first run and its
    # slider's first move would otherwise pay 15-35 s for it
    simulation.simulate(duration=50.0)


def _bound_table():
    from xnavlab.robust import plots

    plots.bound_table()  # chapter 10's call: stored under $XNAVLAB_CACHE


def _reproduction(rid):
    from xnavlab import reproduce

    reproduce.run(rid)  # a registered Monte Carlo a chapter reads (reproduction cache)


def _reproduction_step(chapter, rid):
    """``(label, function)`` of the step computing the reproduction ``rid`` (a partial of a
    module-level function: a pool worker can import it)."""
    return (f"chapter {chapter}'s {rid} (reproduction cache)", functools.partial(_reproduction, rid))


def _ekf_and_ukf():
    from xnavlab.mars.navigation import linearisation

    linearisation.ekf_and_ukf()  # chapter 5's EKF/UKF comparison, numpy loop (about 50 s, cache)


#: The label of the filter kernel's compile in :data:`STEPS`.
KERNEL_STEP = "federated filter kernel"

#: (label, function) pairs run by :func:`warm`; those before :data:`KERNEL_STEP` need no filter
#: kernel (they run in order while it compiles), those after it do (they run on every core,
#: the longest first: each is a module-level function a worker process can import).
STEPS = (
    ("Mars truth, 30 days (truth cache)", _mars_truth),
    ("ephemeris-error propagator", _ephemeris_error),
    ("the chapters' truths of 8 force models, 30 days (truth cache)", _force_models),
    ("PINT's photon phases and residuals (chapter 1's cache)", _pint_witnesses),
    ("the studies' rich truth, 30 days, and its q_acc (truth cache)", _study_truth),
    ("chapter 1's TOA accuracies and chapter 2's fold surveys (cache)", _timing_tables),
    ("chapter 9's combined detector (numba compile)", _combined_detector),
    ("chapter 11's attitude filter bank (numba compile)", _attitude_bank),
    (KERNEL_STEP, compile_kernel),
    *(_reproduction_step(10, rid) for rid in ("rkf-earth", "rkf-mars", "rkf-sweep",
                                              "rkf-residual-memory", "ukf-vs-ephemeris-error")),
    ("chapter 10's table of the RKF's bound (cache)", _bound_table),
    _reproduction_step(5, "mars-subsystems"),
    ("chapter 5's EKF and UKF on the same UV data, half an hour (cache)", _ekf_and_ukf),
    ("matched vs mismatched models, 30 days x 5 seeds x 3 cases (cache)", _model_mismatch),
    ("fault-tolerant runs", _mars_fault_tolerant),
)


def warm(stream=sys.stderr, workers=None):
    """Run every step of :data:`STEPS`, printing one line each with its time.

    When the filter kernel is still to be compiled and the machine has two cores or more,
    its compile starts at once in a second process and the steps before :data:`KERNEL_STEP`
    run beside it, in order; its line then gives the compile's time from its start. The steps
    after it run in ``workers`` processes (default: one per core), each line printed as its
    step ends; with one worker they run here, in order.

    Parameters
    ----------
    stream : file-like
        Where the lines go.
    workers : int, optional
        Processes for the steps after the kernel, 1 to 64 (default ``os.cpu_count()``).

    Returns
    -------
    dict
        Seconds per step label.
    """
    from xnavlab.core.validate import check_int

    workers = check_int("workers", (os.cpu_count() or 1) if workers is None else workers,
                        1, 64)
    labels = [label for label, _ in STEPS]
    cut = labels.index(KERNEL_STEP) + 1 if KERNEL_STEP in labels else len(labels)
    child = _start_kernel_compile(stream) if _compile_beside() else None
    times = {}
    try:
        for label, func in STEPS[:cut]:
            t0 = time.perf_counter()
            if label == KERNEL_STEP and child is not None:
                proc, t0 = child
                if proc.wait() != 0:
                    raise RuntimeError(f"the filter kernel's compile failed (exit code "
                                       f"{proc.returncode}; its messages are above)")
                child = None
            else:
                func()
            times[label] = time.perf_counter() - t0
            print(f"warmup: {label}: {times[label]:.1f} s", file=stream, flush=True)
    finally:
        if child is not None and child[0].poll() is None:  # a step before it failed
            child[0].kill()
            child[0].wait()
    for label, seconds in _run_after(STEPS[cut:], workers):
        times[label] = seconds
        print(f"warmup: {label}: {seconds:.1f} s", file=stream, flush=True)
    return times


def _timed(func):
    """Seconds ``func()`` took (run in a worker process)."""
    t0 = time.perf_counter()
    func()
    return time.perf_counter() - t0


def _run_after(steps, workers):
    """``(label, seconds)`` of each step as it ends: here in order with one worker (or one
    step), else in a pool of fresh processes (``spawn``: no state shared with this one)."""
    if workers == 1 or len(steps) < 2:
        for label, func in steps:
            yield label, _timed(func)
        return
    ctx = multiprocessing.get_context("spawn")
    pool = concurrent.futures.ProcessPoolExecutor(min(workers, len(steps)), mp_context=ctx)
    try:
        futures = {pool.submit(_timed, func): label for label, func in steps}
        for fut in concurrent.futures.as_completed(futures):
            yield futures[fut], fut.result()
    finally:  # a step that failed: the others are not waited for
        pool.shutdown(wait=True, cancel_futures=True)


def _compile_beside():
    """Whether to compile the kernel in a second process: needed, and a second core."""
    if (os.cpu_count() or 1) < 2 or KERNEL_STEP not in dict(STEPS):
        return False
    from xnavlab.mars.kernel import compile_notice

    return not compile_notice.is_compiled()


def _start_kernel_compile(stream):
    """``(process, start time)`` of :func:`compile_kernel` in a second Python process."""
    print("warmup: the filter kernel compiles in a second process, beside the steps before "
          "it", file=stream, flush=True)
    code = "from xnavlab.cli import warmup; warmup.compile_kernel()"
    return subprocess.Popen([sys.executable, "-c", code]), time.perf_counter()


def configure(parser):
    """``warmup`` takes no options."""


def execute(args):
    """Run :func:`warm`; exit code 0."""
    warm(sys.stderr)  # the command's standard error (main's, whose failed write is one line)
    return 0
