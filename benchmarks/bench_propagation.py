"""Truth propagation: the compiled right-hand side against the readable numpy one.

Run: ``.venv/bin/python benchmarks/bench_propagation.py``. Prints the wall time of the
30-day truth run (DOP853, rtol 1e-13, output every 3 s: 864,001 states) and the
speed-up of the compiled RHS over :func:`xnavlab.mars.models.dynamics.acceleration` on a one-day
span, both measured in this process.
"""

import time

import numpy as np
from _timing import Record, best_of
from scipy.integrate import solve_ivp

from xnavlab.mars.models import dynamics
from xnavlab.mars.models.dynamics import MARS_STATE0, MARS_T0


def _numpy_run(t_end, table):
    def rhs(t, x):
        return np.concatenate([x[3:], dynamics.acceleration(t, x[:3], table)])

    return solve_ivp(rhs, (MARS_T0, t_end), MARS_STATE0, method="DOP853", rtol=1e-13, atol=1e-9)


def main():
    rec = Record("propagation", "Truth propagation: compiled against numpy right-hand side",
                 "Mars point mass + Sun + Jupiter, DOP853, rtol 1e-13; one day best of 3 "
                 "(the numpy one once), then the 30-day truth once.")
    day = MARS_T0 + 86400.0
    dynamics.propagate(np.array([MARS_T0, MARS_T0 + 60.0]))  # compile (cached on disk)
    table = dynamics.ThirdBodyTable(MARS_T0, day)
    compiled = best_of(lambda: dynamics.propagate(np.array([day]), table=table), repeat=3)
    plain = best_of(lambda: _numpy_run(day, table), repeat=1)
    t_eval = MARS_T0 + np.arange(0.0, 30 * 86400.0 + 1.0, 3.0)
    t0 = time.perf_counter()
    dynamics.propagate(t_eval)
    full = time.perf_counter() - t0
    rec.line("one day, numpy RHS", f"{plain:.3f} s")
    rec.line("one day, compiled RHS", f"{compiled:.3f} s")
    rec.line("speed-up", f"{plain / compiled:.1f}x")
    rec.line("30 days, 864,001 states (dynamics.truth caches it on disk)", f"{full:.2f} s")
    rec.write()


if __name__ == "__main__":
    main()
