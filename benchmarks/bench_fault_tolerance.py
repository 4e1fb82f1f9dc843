"""Fault-tolerant Mars runs: the three detectors against the fault-free run; a Monte Carlo batch.

Run: ``.venv/bin/python benchmarks/bench_fault_tolerance.py``. Prints

- the full 30-day run with the paper's fault schedule under each detector (none, wavelet,
  chi2), end to end as ``python -m xnavlab run mars --faults paper --detector X`` runs it
  (prepare the inputs, inject, detect, filter with isolation and rejoining) against the
  fault-free run end to end (prepare, filter), in this process (target: ratio <= 1.5); and,
  for information, the same with the inputs prepared once (filter and detection only);
- a batch of 100 one-day runs (``xnavlab.mars.trials.mars_trial``: one UV step each, wavelet
  detector) on a local process pool of two workers (target: a few minutes, <= 180 s).
"""

import time

from _timing import best_of

from xnavlab.core import montecarlo
from xnavlab.mars import fault_tolerance, scenarios, trials


def main():
    scenarios.run(days=0.001)                                   # numba compile / cache load
    inp = scenarios.prepare(days=30.0)
    faults = fault_tolerance.paper_schedule()
    fault_tolerance.run_fault_tolerant(faults=faults, detector="wavelet", days=0.5,
                                       train_days=0.2)          # warm-up of every path
    t_ref = best_of(lambda: scenarios.run(days=30.0), repeat=2)
    t_ref_f = best_of(lambda: scenarios.run(inputs=inp), repeat=2)
    print(f"30-day fault-free run, end to end            : {t_ref:7.2f} s (filter only {t_ref_f:.2f} s)")
    for det in fault_tolerance.DETECTORS:
        t = best_of(lambda det=det: fault_tolerance.run_fault_tolerant(
            faults=faults, detector=det, days=30.0), repeat=2)
        t_f = best_of(lambda det=det: fault_tolerance.run_fault_tolerant(
            faults=faults, detector=det, inputs=inp), repeat=2)
        print(f"30-day run, paper faults, detector {det:8s}  : {t:7.2f} s  ratio {t / t_ref:5.2f} "
              f"(target <= 1.5) {'OK' if t / t_ref <= 1.5 else 'MISSED'}; inputs reused "
              f"{t_f:.2f} s, ratio {t_f / t_ref_f:.2f}")
    n = 100
    params = [dict(size_sigma=5.0, detector="wavelet", days=1.0)] * n
    t0 = time.perf_counter()
    res = montecarlo.run_tasks(trials.mars_trial, params, seed=0, max_workers=2)
    wall = time.perf_counter() - t0
    found = sum(r["delay"] < 1e9 for r in res)
    print(f"{n} one-day runs on 2 workers                 : {wall:7.2f} s (target <= 180 s) "
          f"{'OK' if wall <= 180 else 'MISSED'}; {found} of {n} UV steps detected")


if __name__ == "__main__":
    main()
