"""Ephemeris look-ups: one vectorised call against a loop of per-epoch calls.

Run: ``.venv/bin/python benchmarks/bench_ephemeris.py``. Prints the time per epoch of
both and their ratio (measured in the same process, so the ratio is what matters).
"""

import numpy as np
from _timing import Record, best_of

from xnavlab.core import ephemeris
from xnavlab.mars.models.dynamics import MARS_T0


def main(n=2000):
    t = MARS_T0 + np.linspace(0.0, 30 * 86400.0, n)
    ephemeris.state("mars", t[:2])  # load the file once
    vec = best_of(lambda: ephemeris.state("mars", t))
    loop = best_of(lambda: [ephemeris.state("mars", ti) for ti in t], repeat=3)
    rec = Record("ephemeris", "Ephemeris look-ups: one vectorised call against a loop",
                 f"`ephemeris.state('mars')` at {n} epochs over 30 days, best of 5 (the loop best of 3).")
    rec.line("vectorised", f"{vec / n * 1e6:.2f} us/epoch")
    rec.line("one call per epoch", f"{loop / n * 1e6:.2f} us/epoch")
    rec.line("speed-up", f"{loop / vec:.1f}x")
    rec.write()
    return loop / vec


if __name__ == "__main__":
    main()
