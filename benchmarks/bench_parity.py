"""Fuzzy parity diagnosis of the PL/INS flight: time per flight, and the residual kernel.

Run: ``.venv/bin/python benchmarks/bench_parity.py``. Prints

- the one-time design of a flight (trajectory, error transitions, T-S local models, parity
  bases; cached afterwards);
- one seeded diagnosis of the 200 s flight (what each Monte Carlo run of ``plins-step`` and
  ``plins-ramp`` costs; target: 0.2 s or less, so that the chapter stays well under a minute);
- the sliding-window residuals (``parity.parity_residuals``, one einsum) against a plain
  per-window loop in this process: the ratio and the largest difference (must be < 1e-9 m).
"""

import time

import numpy as np
from _timing import Record

from xnavlab.core.faults import Fault
from xnavlab.plins import ins, parity, pseudolites
from xnavlab.plins.parity.diagnosis import flight_design


def best_of(fn, repeat=5):
    """Smallest wall time of ``repeat`` calls, s."""
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def loop_residuals(z, W):
    """Reference: one matrix-vector product per window and sensor."""
    s = W.shape[2] - 1
    out = np.empty((len(z) - s, z.shape[1], W.shape[3]))
    for k in range(s, len(z)):
        for j in range(z.shape[1]):
            out[k - s, j] = W[k, j].T @ z[k - s:k + 1, j]
    return out


def main():
    rec = Record("parity", "Fuzzy parity diagnosis of the PL/INS flight",
                 "The flight's one-time design, one seeded diagnosis of the 200 s flight (best "
                 "of 5) and the sliding-window residuals (one einsum) against a per-window loop.")
    faults = [Fault("pseudorange", "step", 300.0, 50.0, component=0)]
    t0 = time.perf_counter()
    parity.diagnose_flight(faults)
    rec.line("first flight (design + diagnosis)", f"{time.perf_counter() - t0:.3f} s")
    t_run = best_of(lambda: parity.diagnose_flight(faults, seed=1))
    rec.line("one diagnosis of the 200 s flight", f"{t_run:.3f} s", "0.2 s",
             "met" if t_run <= 0.2 else "missed")

    d = parity.diagnose_flight(faults)
    # the design diagnose_flight used (defaults: 200 s flight, s = 11, tol = 0.3 sigma; cached)
    W = flight_design(ins.paper_trajectory(), pseudolites.sites_ecef(), 11,
                      0.3 * pseudolites.DEFAULT_SIGMA)[2]
    fast = parity.parity_residuals(d.z, W)
    ref = loop_residuals(d.z, W)
    t_fast = best_of(lambda: parity.parity_residuals(d.z, W), repeat=20)
    t_ref = best_of(lambda: loop_residuals(d.z, W), repeat=5)
    rec.line("residuals, per-window loop (best of 5)", f"{t_ref * 1e3:.2f} ms")
    rec.line("residuals, einsum (best of 20)", f"{t_fast * 1e3:.2f} ms (ratio {t_ref / t_fast:.0f}x)")
    diff = np.abs(fast - ref).max()
    rec.line("largest difference", f"{diff:.1e} m", "below 1e-9 m", "met" if diff < 1e-9 else "missed")
    rec.write()


if __name__ == "__main__":
    main()
