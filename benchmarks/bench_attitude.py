"""SOS (one EKF) against DOS (a bank of four EKFs): time per sample, same process.

Run: ``.venv/bin/python benchmarks/bench_attitude.py``. Prints the time per sample of
:class:`xnavlab.attitude.SOSMonitor` and :class:`xnavlab.attitude.DOSMonitor` on the
same simulated data, their ratio (the paper claims about 4x), and the wall time of one
full :func:`xnavlab.attitude.simulate` run and of the chapter's Monte Carlo table.
"""

import time

from _timing import best_of

from xnavlab import attitude as att


def main():
    att.time_sos_dos(n_steps=50, repeats=1)  # warm-up (imports, caches)
    r = att.time_sos_dos(n_steps=2000, repeats=5)
    print("attitude fault diagnosis: per-sample cost, one process, same data")
    print(f"  SOS (1 EKF + 4 residuals)   : {r['sos_us']:8.1f} us/sample")
    print(f"  DOS (4 EKFs + 4 residuals)  : {r['dos_us']:8.1f} us/sample")
    print(f"  DOS / SOS                   : {r['ratio']:8.2f}x   (paper: about 4x)")
    sim = best_of(lambda: att.simulate(), repeat=3)
    print(f"  simulate(), 100 s at 10 Hz, SOS+DOS+ref.[22] vectorised: {sim:6.2f} s")
    t0 = time.perf_counter()
    att.isolation_monte_carlo(10)
    print(f"  isolation_monte_carlo(10), 310 runs batched        : "
          f"{time.perf_counter() - t0:6.2f} s")


if __name__ == "__main__":
    main()
