"""The ephemeris-error filters (chapter 10): the rkf reproductions' wall time, and the filters run
over seeds one at a time against all seeds at once.

Run: ``.venv/bin/python benchmarks/bench_robust.py`` (both parts), ``--part repro`` (the
registered reproductions, computed afresh) or ``--part filters`` (seconds). ``--ids`` picks
reproductions. The machine's load is printed before and after: the project's machine is
shared, and a reproduction's wall time follows the load; its CPU time (this process and the
processes it started) much less.

``filters`` times :func:`xnavlab.robust.compare_filters` (all seeds in one batch) against
:func:`xnavlab.robust.run_filter` called once per seed (the same arithmetic, one run at a
time) on the Mars case, and prints the largest relative difference of their RMSEs.
"""

import argparse
import os
import time

import numpy as np
from _timing import Record

RKF_IDS = ("rkf-earth", "rkf-mars", "rkf-residual-memory", "rkf-sweep")


def _cpu():
    """CPU time of this process and of its finished children, s (a load-independent measure)."""
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def time_reproductions(rec, ids):
    """Wall and CPU time of each reproduction computed afresh (its result is stored in the cache)."""
    from xnavlab import reproduce

    rows = []
    for rid in ids:
        t0, c0 = time.perf_counter(), _cpu()
        res = reproduce.run(rid, fresh=True)
        rows.append([rid, f"{time.perf_counter() - t0:.1f}", f"{_cpu() - c0:.1f}", res.verdict])
        print(f"  {rid}: {rows[-1][1]} s wall, {rows[-1][2]} s CPU", flush=True)
    rec.table(["reproduction", "wall time (s)", "CPU time (s)", "headline"], rows,
              "Reproductions computed afresh")


def time_filters(rec, seeds=tuple(range(8)), body="mars"):
    """compare_filters (one batch) against run_filter seed by seed, and their largest difference."""
    from xnavlab import robust
    from xnavlab.core.validate import make_rng

    robust.compare_filters(body, seeds=(0,), n_steps=20, window=(0.0, 1e4))  # compile, warm
    kw = dict(error="growing", size=5e4)
    t0 = time.perf_counter()
    out = robust.compare_filters(body, seeds=seeds, **kw)
    batched = time.perf_counter() - t0
    t0 = time.perf_counter()
    single = {f: [] for f in robust.FILTERS}
    for s in seeds:  # compare_filters' own draws, one run at a time
        g = make_rng(s, "seed")
        sc = robust.simulate(body, robust.N_STEPS[body], rng=g, **kw)
        init = int(g.integers(2**31))
        for f in robust.FILTERS:
            single[f].append(robust.rmse(robust.run_filter(f, sc, rng=init), sc, *robust.WINDOWS[body]))
    one = time.perf_counter() - t0
    rel = max(float(np.max(np.abs(np.subtract(out["rmse_runs"][f], single[f])) / np.abs(single[f])))
              for f in robust.FILTERS)
    rec.table(["four filters, " + f"{len(seeds)} seeds, {body}", "wall time (s)"],
              [["run_filter, one seed at a time", f"{one:.2f}"],
               ["compare_filters, one batch", f"{batched:.2f}"], ["speed-up", f"{one / batched:.1f}x"]],
              "The filters seed by seed against one batch")
    rec.note(f"Largest relative difference of the RMSEs, batch against seed by seed: {rel:.1e}.")


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--part", choices=("repro", "filters", "both"), default="both")
    p.add_argument("--ids", nargs="*", default=list(RKF_IDS))
    args = p.parse_args()
    rec = Record("robust", "The ephemeris-error filters (chapter 10)",
                 "The four filters over 8 seeds one at a time against one batch "
                 "(`xnavlab.robust.compare_filters`), and the rkf reproductions computed afresh "
                 "(wall and CPU time: the CPU time follows the load much less).")
    if args.part in ("filters", "both"):
        time_filters(rec)
    if args.part in ("repro", "both"):
        time_reproductions(rec, args.ids)
    rec.write()


if __name__ == "__main__":
    main()
