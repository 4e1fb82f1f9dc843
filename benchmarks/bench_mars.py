"""The 30-day federated Mars run: wall time, and the compiled kernel against the numpy loop.

Run: ``.venv/bin/python benchmarks/bench_mars.py``. Prints

- the one-time numba compile (or cache load) on a tiny span;
- the full 30-day fault-free run (867 457 epochs, 3 EKFs + fusion each), split into
  preparing the inputs (truth from :func:`xnavlab.mars.dynamics.truth`, cached on disk after
  its first computation; ephemeris tables; every noisy measurement) and the filter, and
  their sum (target: 10 s or less);
- the plain numpy reference loop and the numba kernel on the same 0.05-day inputs in
  this process, their time per epoch, the ratio (target: 30x or more) and the largest
  relative difference of the estimates (must be below 1e-9).
"""

import time

import numpy as np
from _timing import best_of

from xnavlab.mars import dynamics, scenarios


def main():
    t0 = time.perf_counter()
    scenarios.run(days=0.001)
    print(f"numba compile or cache load (tiny run)      : {time.perf_counter() - t0:7.2f} s")

    sc = scenarios.MarsScenario()
    t0 = time.perf_counter()
    times = sc.t0 + np.unique(np.concatenate([[0.0], np.arange(1, 864001) * 3.0,
                                              np.arange(1, 5185) * 500.0]))
    dynamics.truth(times)              # make sure the disk cache holds the 30-day truth
    print(f"truth on disk (computed if missing)         : {time.perf_counter() - t0:7.2f} s")
    scenarios._TRUTH_CACHE.clear()      # the full run below reads it back from disk
    t0 = time.perf_counter()
    inp = scenarios.prepare(sc)
    t_prep = time.perf_counter() - t0
    t0 = time.perf_counter()
    res = scenarios.run(inputs=inp)
    t_run = time.perf_counter() - t0
    m = res.metrics()
    total = t_prep + t_run
    print(f"30-day run: prepare inputs                  : {t_prep:7.2f} s")
    print(f"30-day run: federated filter ({inp.n} epochs): {t_run:7.2f} s "
          f"({t_run / inp.n * 1e6:.2f} us/epoch)")
    print(f"30-day run: total wall time                 : {total:7.2f} s   (target <= 10 s) "
          f"{'OK' if total <= 10 else 'MISSED'}")
    print(f"  position / velocity error                 : {m['position_error_m']:.2f} m, "
          f"{m['velocity_error_mps']:.4f} m/s (paper 28.835 m, 0.02149 m/s)")

    short = scenarios.prepare(days=0.05)
    ref = scenarios.run(inputs=short, backend="numpy")
    fast = scenarios.run(inputs=short, backend="numba")
    t_np = best_of(lambda: scenarios.run(inputs=short, backend="numpy"), repeat=2)
    t_nb = best_of(lambda: scenarios.run(inputs=short, backend="numba"), repeat=5)
    diff = max(np.abs(fast.x[:, :3] - ref.x[:, :3]).max() / np.abs(ref.x[:, :3]).max(),
               np.abs(fast.x[:, 3:] - ref.x[:, 3:]).max() / np.abs(ref.x[:, 3:]).max())
    print(f"numpy loop, 0.05 day ({short.n} epochs)      : {t_np:7.3f} s "
          f"({t_np / short.n * 1e6:.0f} us/epoch)")
    print(f"numba kernel, same inputs                   : {t_nb:7.4f} s "
          f"({t_nb / short.n * 1e6:.2f} us/epoch)")
    ratio = t_np / t_nb
    print(f"speed-up numba / numpy                      : {ratio:7.0f}x   (target >= 30x) "
          f"{'OK' if ratio >= 30 else 'MISSED'}")
    print(f"largest relative difference of estimates    : {diff:.1e}   (must be < 1e-9) "
          f"{'OK' if diff < 1e-9 else 'MISSED'}")


if __name__ == "__main__":
    main()
