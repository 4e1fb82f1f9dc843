"""``python -m xnavlab warmup``: compile every numba kernel the chapters use, and fill the caches.

``make setup`` runs it once after installing, so no reader's chapter (and no timed first
``run mars``) pays for a compile: numba writes each compiled kernel to its on-disk cache
(``cache=True``, in ``__pycache__`` beside the source) and every later process loads it in
milliseconds. It also computes the paper's 30-day Mars truth trajectory into the truth
cache (``$XNAVLAB_CACHE``, default ``~/.cache/xnavlab``), which chapters 5, 6 and 8 and
the Mars reproductions use, and the headline campaign of chapters 6 and 8 (32 noise seeds of
the 30-day run, clean and with the paper's faults: :func:`xnavlab.mars.headline.headline_numbers`)
into its campaign store there, so that no chapter cell waits minutes for it, and two chapters
executed side by side (``make book``, ``pytest -n 2``) do not wait for each other.

Each step runs a tiny case through the same public functions the chapters call, so the
kernels are compiled for exactly the argument types the chapters pass. Running it again
is cheap (everything is loaded from the caches).
"""

from __future__ import annotations

import sys
import time

__all__ = ["HELP", "STEPS", "configure", "execute", "warm"]

#: One-line help of the command (``python -m xnavlab --help``).
HELP = "compile and cache the numba kernels and the 30-day Mars truth (make setup runs it)"


def _mars_truth():
    from xnavlab.mars import scenarios

    scenarios.prepare(scenarios.MarsScenario())  # the paper's 30 days: truth cached on disk


def _mars_filter():
    from xnavlab.mars import scenarios

    scenarios.run(scenarios.MarsScenario(days=0.02, record_dt=60.0))


def _mars_fault_tolerant():
    from xnavlab.mars import fault_tolerance, scenarios

    sc = scenarios.MarsScenario(days=0.05, record_dt=60.0)
    for detector in fault_tolerance.DETECTORS:
        if detector != "none":
            fault_tolerance.run_fault_tolerant(sc, [], detector, train_days=0.02)


def _ephemeris_error():
    import numpy as np

    from xnavlab.robust import ephemeris_error as ee

    for body in ee.PLANETS:
        ee.propagate(np.array(ee.orbit(body).state0), 60.0, body)


def _headline_campaign():
    from xnavlab.mars import headline

    headline.headline_numbers()  # the chapters' call: stored under $XNAVLAB_CACHE/campaigns


#: (label, function) pairs run in order by :func:`warm`.
STEPS = (
    ("Mars truth, 30 days (truth cache)", _mars_truth),
    ("federated filter kernel", _mars_filter),
    ("fault-tolerant runs", _mars_fault_tolerant),
    ("ephemeris-error propagator", _ephemeris_error),
    ("headline campaign, 32 seeds (campaign cache)", _headline_campaign),
)


def warm(stream=sys.stderr):
    """Run every step of :data:`STEPS`, printing one line each with its time.

    Returns
    -------
    dict
        Seconds per step label.
    """
    times = {}
    for label, func in STEPS:
        t0 = time.perf_counter()
        func()
        times[label] = time.perf_counter() - t0
        print(f"warmup: {label}: {times[label]:.1f} s", file=stream, flush=True)
    return times


def configure(parser):
    """``warmup`` takes no options."""


def execute(args):
    """Run :func:`warm`; exit code 0."""
    warm()
    return 0
