"""SOS (one EKF) against DOS (a bank of four EKFs): time per sample, same process.

Run: ``.venv/bin/python benchmarks/bench_attitude.py``. Prints the time per sample of
:class:`xnavlab.attitude.SOSMonitor` and :class:`xnavlab.attitude.DOSMonitor` on the
same simulated data, their ratio (the paper claims about 4x), and the wall time of one
full :func:`xnavlab.attitude.simulate` run and of the chapter's Monte Carlo table.
"""

import time

from _timing import Record, best_of

from xnavlab import attitude as att


def main():
    rec = Record("attitude", "Attitude fault diagnosis: SOS against DOS",
                 "Per-sample cost of one EKF (SOS) and a bank of four (DOS) on the same data, "
                 "one process (2,000 samples, best of 5); the paper says DOS costs about 4 times SOS.")
    att.time_sos_dos(n_steps=50, repeats=1)  # warm-up (imports, caches)
    r = att.time_sos_dos(n_steps=2000, repeats=5)
    rec.line("SOS (1 EKF + 4 residuals)", f"{r['sos_us']:.1f} us/sample")
    rec.line("DOS (4 EKFs + 4 residuals)", f"{r['dos_us']:.1f} us/sample")
    rec.line("DOS / SOS", f"{r['ratio']:.2f}x", "paper: about 4x")
    sim = best_of(lambda: att.simulate(), repeat=3)
    rec.line("simulate(), 100 s at 10 Hz, SOS + DOS + ref. [22], best of 3", f"{sim:.2f} s")
    t0 = time.perf_counter()
    att.isolation_monte_carlo(10)
    rec.line("isolation_monte_carlo(10), 310 runs batched", f"{time.perf_counter() - t0:.2f} s")
    rec.write()


if __name__ == "__main__":
    main()
