"""The ROC curves chapter 9 shows: Pd against false alarms per day over each detector's threshold.

Run: ``.venv/bin/python benchmarks/bench_roc.py`` (prints the curves and the wall time) or
``.venv/bin/python benchmarks/bench_roc.py --write`` (also rewrites the shipped curves
``xnavlab/data/roc_curves.json`` that chapter 9 loads). ``--runs-per-fault N`` (default 24)
sets the trials of each fault of :data:`xnavlab.mars.studies.roc.DEFAULT_GRID`; ``--store DIR`` keeps
the two campaigns' runs there so that an interrupted run resumes.

The combined detector is swept on its design rate (``rate_per_day``, the grid's thresholds),
the chi-square detector on its per-measurement ``alpha`` (:data:`CHI2_THRESHOLDS`), both on
the default grid's four faults at the edge of detection, in half-day runs. The same command
line does one detector: ``python -m xnavlab campaign roc --grid FILE --runs N --out DIR``.
The precomputed curves are shipped because the combined detector's CUSUM design takes a few
seconds per threshold and the curves need hundreds of runs: minutes, not a chapter's seconds.
Each detector's first :data:`CHECK_RUNS` runs (one per fault of the grid) are stored beside its
curve (``checks``: index, seed, parameters, metrics), for ``tests/mars/studies/test_roc.py`` to
recompute. Detected, late and false alarms: :func:`xnavlab.mars.faults.schedules.score_faults`.
Measured (2026-11-27, two workers on the shared 2-core machine under a load of 7): the
combined curve 163 s, the chi-square curve 98 s, 123 s of CPU in all.
"""

import argparse
import tempfile
import time
from pathlib import Path

from _timing import machine_line, table, write_json

from xnavlab.core.campaign import run_campaign
from xnavlab.mars.studies import roc

#: The chi-square detector's thresholds: false-alarm probability per measurement.
CHI2_THRESHOLDS = [1e-9, 1e-7, 1e-5, 1e-4, 1e-3]
#: Runs of each curve stored with it for the tests to recompute (the grid's four faults).
CHECK_RUNS = 4


def checks(runs, n=CHECK_RUNS):
    """The first ``n`` runs of a campaign (index order) as stored check records."""
    return [{k: r[k] for k in ("index", "seed", "parameters", "metrics")}
            for r in sorted(runs, key=lambda r: r["index"])[:n]]


def grids():
    """The two grids: the default (combined) and the chi-square one on the same faults."""
    return {"combined": roc.check_grid(roc.DEFAULT_GRID),
            "chi2": roc.check_grid({**roc.DEFAULT_GRID, "detector": "chi2",
                                    "thresholds": CHI2_THRESHOLDS})}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="rewrite xnavlab/data/roc_curves.json")
    ap.add_argument("--runs-per-fault", type=int, default=24)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--store", default=None, help="campaign directory (default: a temporary one)")
    args = ap.parse_args()
    print(machine_line())
    store = Path(args.store or tempfile.mkdtemp(prefix="xnavlab-roc-"))
    out = {"command": f"python benchmarks/bench_roc.py --write --runs-per-fault "
                      f"{args.runs_per_fault} --seed {args.seed}", "curves": {}}
    for det, grid in grids().items():
        runs = args.runs_per_fault * len(grid["faults"])
        t0 = time.perf_counter()
        (store / det).mkdir(parents=True, exist_ok=True)
        res = run_campaign(roc.campaign(grid), runs, seed=args.seed, out=store / det,
                           workers=args.workers, progress=True)
        wall = time.perf_counter() - t0
        data = roc.write_curve(store / det, grid, res.runs(), args.seed)
        out["curves"][det] = {**data, "checks": checks(res.runs())}
        print(f"\n{det} ({grid['threshold_name']}), {runs} runs, {res.failed} failed, "
              f"{wall:.0f} s ({res.reused} reused)")
        table(roc.CURVE_COLUMNS, [[r[c] if not isinstance(r[c], float) else f"{r[c]:.4g}"
                                   for c in roc.CURVE_COLUMNS] for r in data["curve"]])
    print(machine_line())
    if args.write:
        write_json(roc.CURVES_PATH, out)


if __name__ == "__main__":
    main()
