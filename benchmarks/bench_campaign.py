"""Monte Carlo campaigns: 1,000 one-day fault-free runs on 2 local workers; speed-up; time split.

Run: ``.venv/bin/python benchmarks/bench_campaign.py [--runs 1000] [--reference 200] [--dask 200]``.
Prints

- where the time of one run goes, measured in this process over ``--sample`` runs of the
  ``consistency`` campaign's trial (:func:`xnavlab.mars.studies.campaigns.consistency_run`, one day):
  the truth trajectory (loaded once per worker from the disk cache, then kept in memory),
  the measurement simulation (``scenarios.prepare`` with the truth in memory), the compiled
  filter (``scenarios.run``) and the NEES/NIS reduction;
- the reference: ``--reference`` runs on a local pool of 1 worker (runs per second);
- the target: ``--runs`` runs on a local pool of 2 workers, as ``python -m xnavlab campaign
  consistency --runs 1000 --days 1`` runs them (with the store in a temporary directory),
  the wall time against the 180-s target and the speed-up over 1 worker (runs per second);
- the overhead beyond the trials (process start and imports, pickling to and from the
  workers, the store's appends), per run: ``workers x wall - sum of in-trial times``;
- with ``--dask N`` (default 200; 0 skips it), the same on a Dask ``LocalCluster`` of 2
  processes.

The machine may be shared: the script prints the load average before and after, and the
rates are what this machine gave at that moment. If ``--runs`` is below 1,000 the 1,000-run
wall time is extrapolated from the measured rate (and said so).
"""

import argparse
import tempfile
import time

import numpy as np
from _timing import Record

from xnavlab.core.campaign import run_campaign
from xnavlab.mars.models import dynamics
from xnavlab.mars.navigation import scenarios
from xnavlab.mars.studies import campaigns


def split(sample):
    """Median seconds per run: truth load (disk cache), measurements, filter, reduction."""
    campaigns.consistency_run(seed=0, days=1.0)          # numba cache load, truth into memory
    sc = scenarios.MarsScenario(days=1.0, init_error="random", record_dt=60.0)
    inp = scenarios.prepare(sc)
    t0 = time.perf_counter()
    dynamics.truth(inp.times, np.array(sc.state0), sc.t0, ("sun", "jupiter"),
                   ephem=sc.truth_ephem)                 # what a fresh worker pays once
    t_truth = time.perf_counter() - t0
    rows = []
    for s in range(1, sample + 1):
        sc_s = scenarios.MarsScenario(days=1.0, seed=s, init_error="random", record_dt=60.0)
        t0 = time.perf_counter()
        inp = scenarios.prepare(sc_s)
        t1 = time.perf_counter()
        scenarios.run(inputs=inp)
        t2 = time.perf_counter()
        campaigns.consistency_run(seed=s, days=1.0)
        t3 = time.perf_counter()
        rows.append((t1 - t0, t2 - t1, t3 - t2))
    prep, filt, total = np.median(rows, axis=0)
    return t_truth, prep, filt, max(total - prep - filt, 0.0), total


def campaign_rate(runs, engine, workers):
    """Run the one-day consistency campaign; returns (wall s, runs/s, sum of in-trial s)."""
    camp = campaigns.campaign("consistency", days=1.0)
    with tempfile.TemporaryDirectory() as out:
        t0 = time.perf_counter()
        res = run_campaign(camp, runs, seed=2026, out=out, engine=engine, workers=workers,
                           timeout=60.0, progress=True)
        wall = time.perf_counter() - t0
    if res.failed:
        raise RuntimeError(f"{res.failed} runs failed: {res.records[0]['error']}")
    busy = sum(r["elapsed_s"] for r in res.records)
    return wall, runs / wall, busy


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=1000, help="runs on 2 workers (default 1000)")
    ap.add_argument("--reference", type=int, default=200, help="runs on 1 worker (default 200)")
    ap.add_argument("--dask", type=int, default=200, help="runs on a 2-process LocalCluster")
    ap.add_argument("--sample", type=int, default=10, help="runs timed in this process")
    args = ap.parse_args()
    rec = Record("campaign", "Monte Carlo campaigns: one-day fault-free runs on local workers",
                 "The `consistency` campaign's trial: where one run's time goes (in this "
                 "process), then runs on a local pool of 1 and of 2 workers as `python -m "
                 "xnavlab campaign consistency` runs them, and on a Dask `LocalCluster` of 2.")
    t_truth, prep, filt, red, total = split(args.sample)
    rec.line(f"one run, in this process (median of {args.sample})",
             f"{total * 1e3:.1f} ms = measurements {prep * 1e3:.1f} ms + filter {filt * 1e3:.1f} ms "
             f"+ NEES/NIS {red * 1e3:.1f} ms; truth {t_truth * 1e3:.1f} ms once per worker")
    w1, r1, b1 = campaign_rate(args.reference, "local", 1)
    rec.line(f"{args.reference} runs, local pool of 1 worker",
             f"{w1:.1f} s, {r1:.2f} runs/s (in trials {b1 / args.reference * 1e3:.0f} ms/run, "
             f"overhead {(w1 - b1) / args.reference * 1e3:.0f} ms/run)")
    w2, r2, b2 = campaign_rate(args.runs, "local", 2)
    est = w2 if args.runs == 1000 else 1000 / r2
    tag = "measured" if args.runs == 1000 else f"extrapolated from {args.runs} runs"
    rec.line(f"{args.runs} runs, local pool of 2 workers",
             f"{w2:.1f} s, {r2:.2f} runs/s (in trials {b2 / args.runs * 1e3:.0f} ms/run, overhead "
             f"{(2 * w2 - b2) / args.runs * 1e3:.0f} ms/run of worker time)")
    rec.line("1000 one-day runs on 2 workers",
             f"{est:.1f} s ({tag}); speed-up 1 -> 2 workers {r2 / r1:.2f}x", "180 s",
             "met" if est <= 180 else "missed")
    if args.dask:
        wd, rd, bd = campaign_rate(args.dask, "local-cluster", 2)
        rec.line(f"{args.dask} runs, Dask LocalCluster of 2",
                 f"{wd:.1f} s, {rd:.2f} runs/s (cluster start included; overhead "
                 f"{(2 * wd - bd) / args.dask * 1e3:.0f} ms/run of worker time)")
    rec.write()


if __name__ == "__main__":
    main()
