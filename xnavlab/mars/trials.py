"""Monte Carlo trials of the fault detectors on the Mars run (chapter 9).

Each trial is a pure function of its parameters and one seed, so it can be mapped over a
list of parameter dicts with :func:`xnavlab.core.montecarlo.run_tasks` on any executor.

:func:`mars_trial`
    A one-day Mars run with one UV range step at a random onset, under a detector
    (:func:`xnavlab.mars.fault_tolerance.run_fault_tolerant`).
"""

from __future__ import annotations

import math

import numpy as np

from xnavlab.core.faults import Fault
from xnavlab.core.validate import check_choice, check_int, check_real
from xnavlab.mars import fault_tolerance

__all__ = ["mars_trial"]


def mars_trial(size_sigma=5.0, detector="wavelet", *, seed=0, days=1.0, duration=3000.0):
    """A one-day Mars run with one UV range step at a random onset (60-80 % of the run).

    Returns
    -------
    dict
        ``delay`` (s, inf if missed), ``position_error_m``, ``velocity_error_mps`` (RMS after
        40 % of the run), ``max_position_error_m``, ``isolations`` (count), ``wall_time``.
    """
    size_sigma = check_real("size_sigma", size_sigma, 0.0, 1000.0)
    check_choice("detector", detector, fault_tolerance.DETECTORS)
    days = check_real("days", days, 0.5, 30.0)
    seed = check_int("seed", seed, 0)
    rng = np.random.default_rng(seed)
    onset = float(np.round(rng.uniform(0.6, 0.8) * days * 86400.0))
    fault = Fault("uv", "step", size_sigma * 5000.0, onset, duration, component=0)
    r = fault_tolerance.run_fault_tolerant(faults=[fault], detector=detector, days=days,
                                           seed=seed % (2**62), train_days=0.4 * days)
    m = r.run.metrics(0.4 * days)
    d = r.delays()[0]["delay"] if detector != "none" else math.inf
    return {"delay": d, "position_error_m": m["position_error_m"],
            "velocity_error_mps": m["velocity_error_mps"],
            "max_position_error_m": m["position_error_max_m"],
            "isolations": len(r.isolation_intervals()), "wall_time": r.wall_time}
