"""``python -m xnavlab campaign NAME``: a Monte Carlo campaign, local or on a Dask cluster.

Usage::

    python -m xnavlab campaign NAME --runs N --days D --seed S --out DIR [--scenario FILE]
        [--workers K | --scheduler tcp://HOST:PORT | --local-cluster [--workers K]]
        [--timeout SECONDS] [--json] [--quiet]
    python -m xnavlab campaign roc --grid FILE --runs N --seed S --out DIR [...]

``NAME`` is one of :data:`xnavlab.mars.campaigns.CAMPAIGNS` (``consistency``, ``detectors``)
(``consistency --scenario FILE`` takes the pulsars, force models, ``q_acc``, subsystems and
horizon noise of a scenario file: a study's truth, or pulsars from timing models; its days and
seed are ``--days`` and ``--seed``'s) or ``roc``: the receiver operating characteristic of a
detector (:mod:`xnavlab.mars.roc`), its threshold swept over the values of a grid file (TOML
or JSON, the format in
:mod:`xnavlab.mars.roc`; without ``--grid``, :data:`xnavlab.mars.roc.DEFAULT_GRID`) on its
faults (run ``i`` is fault ``i mod F``, every threshold on the same run). The run length is
the grid's ``days`` (``--days`` is refused). Besides ``runs.jsonl`` and ``summary.json`` it
writes ``DIR/roc.json`` (the grid, the curve per threshold: Pd with its Wilson 95 % interval,
false alarms per day with its exact Poisson (Garwood) 95 % interval; and the same per fault)
and ``DIR/roc.csv`` (the curve); ``--json`` prints the contents of ``roc.json`` with the counts
(``computed``, ``reused``, ``failed``, ``wall_s``) instead of every run.
The runs execute on a local process pool of ``K`` workers (default 2), on the Dask cluster
whose scheduler is at ``--scheduler``, or on a Dask ``LocalCluster`` of ``K`` worker
processes (``--local-cluster``); run ``i`` draws its seed from ``SeedSequence(S)`` by its
index, so the records are the same on each. Every run is appended to ``DIR/runs.jsonl`` as it
completes (the header in ``DIR/campaign.json``, so ``runs.jsonl`` holds records only and
``pandas.read_json(DIR + "/runs.jsonl", lines=True)`` or
:func:`xnavlab.core.campaign.load_runs` reads it); running the same command again reuses
the finished runs and computes the missing ones (:mod:`xnavlab.core.campaign`). The summary
(everything but the runs) is written to ``DIR/summary.json``. A progress bar on stderr shows
the runs done, failed and the rate (none with ``--json`` or ``--quiet``).

Output: the summary table and a line of counts, or with ``--json`` one JSON object with
``campaign`` (the manifest), ``runs`` (one record per run in index order: ``index``,
``seed``, ``parameters``, ``metrics``, ``status``, ``error``), ``summary`` (the aggregated
table), ``computed``, ``reused``, ``failed`` and ``wall_s``.

Exit codes: 0 every run ok; 1 some runs failed (after their retry; they are in the output
and the store); 2 bad input (one line on stderr), including a DIR that holds another
campaign and an unreachable scheduler (``--timeout``, default 5 s); 130 interrupted (the
finished runs are stored).
"""

from __future__ import annotations

import json
import os
import sys

from xnavlab.cli import UsageError, number
from xnavlab.core.userfiles import output_path
from xnavlab.core.validate import check_int

__all__ = ["HELP", "COLUMNS", "configure", "execute"]

#: One-line help of the command (``python -m xnavlab --help``).
HELP = ("run a Monte Carlo campaign (consistency, detectors, roc) locally or on a Dask "
        "cluster")

#: Columns of the summary printed without ``--json``, per campaign.
COLUMNS = {
    "consistency": ("quantity", "t_days", "value", "lo", "hi", "verdict", "runs"),
    "detectors": ("fault_class", "sensor", "size", "detector", "trials", "pd", "late",
                  "delay_median_s", "delay_p95_s", "false_alarms_per_day", "rms_ratio"),
    "roc": ("threshold", "trials", "pd", "pd_lo", "pd_hi", "late", "false_alarms_per_day",
            "false_alarms_per_day_lo", "false_alarms_per_day_hi", "delay_median_s"),
}


def _number(name, text, kind, lo, hi, lo_open=False):
    return number(name, text, kind, lo, hi, lo_open=lo_open)


def configure(parser):
    """Options of ``campaign``."""
    # the names are listed, not imported: the parser stays light (xnavlab.mars.campaigns)
    parser.add_argument("name", metavar="NAME",
                        help="the campaign: consistency (NEES/NIS of the fault-free Mars run), "
                             "detectors (chapter 9's fault class x detector table) or roc "
                             "(Pd against false alarms per day over a detector's thresholds)")
    parser.add_argument("--runs", required=True,
                        help="number of runs, >= 1; detectors: run i is cell i mod 45 of "
                             "fault class x sensor x size, so a multiple of 45 covers every "
                             "cell equally (fewer leave cells empty, with a warning); roc: "
                             "run i is fault i mod F of the grid")
    parser.add_argument("--days", default=None,
                        help="days simulated per run (default 1); roc takes the grid's days "
                             "and refuses --days")
    parser.add_argument("--grid", metavar="FILE", default=None,
                        help="roc only: the threshold and fault grid, TOML or JSON (keys "
                             "detector, thresholds, days, faults: see xnavlab.mars.roc); "
                             "default xnavlab.mars.roc.DEFAULT_GRID")
    parser.add_argument("--seed", default="0", help="the campaign's seed (default 0)")
    parser.add_argument("--scenario", metavar="FILE", dest="scenario_file", default=None,
                        help="consistency only: take the pulsars, force models, q_acc, "
                             "subsystems and horizon noise of this scenario file")
    parser.add_argument("--out", required=True, metavar="DIR",
                        help="campaign directory: runs.jsonl is appended there and reused")
    parser.add_argument("--workers", default=None,
                        help="local worker processes (default 2), also of --local-cluster; "
                             "refused with --scheduler (its cluster has its own)")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="run on the Dask cluster of this scheduler, e.g. tcp://HOST:8786")
    where.add_argument("--local-cluster", action="store_true",
                       help="start a Dask LocalCluster of --workers processes and run on it")
    parser.add_argument("--timeout", default=None,
                        help="seconds to reach the scheduler and its first worker (default 5); "
                             "with --scheduler or --local-cluster only")
    parser.add_argument("--json", action="store_true",
                        help="print one JSON object (no progress bar)")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")


def execute(args):
    """Run ``campaign``; returns the exit code."""
    from xnavlab.core.campaign import SUMMARY_FILE
    from xnavlab.mars.campaigns import CAMPAIGNS, DAYS, campaign

    if args.name not in CAMPAIGNS and args.name != "roc":
        raise UsageError(f"campaign must be one of {', '.join(CAMPAIGNS)}, roc, "
                         f"got {args.name!r}")
    if args.grid is not None and args.name != "roc":
        raise UsageError("--grid is an option of campaign roc only")
    if args.scenario_file is not None and args.name != "consistency":
        raise UsageError("--scenario is an option of campaign consistency only")
    if args.name == "roc":
        return _execute_roc(args)
    runs, seed, where = _common(args)
    lo, hi = DAYS[args.name]  # the campaign's own range, checked again (with more) below
    days = _number("days", "1" if args.days is None else args.days, float, lo, hi,
                   lo_open=args.name == "consistency")
    scenario = None
    if args.scenario_file is not None:
        from xnavlab.mars import scenario_files

        scenario = scenario_files.load(args.scenario_file).scenario
    camp = campaign(args.name, days=days, scenario=scenario)
    if args.name == "detectors":
        from xnavlab.mars.campaigns import detector_cells

        cells = len(detector_cells())
        if runs % cells:
            covered = min(runs, cells)
            print(f"xnavlab: warning: --runs {runs} covers {covered} of the {cells} cells "
                  f"(fault class x sensor x size){' unequally' if runs > cells else ''}; "
                  f"a multiple of {cells} gives every cell the same number of trials",
                  file=sys.stderr)
    res = _run(args, camp, runs, seed, where)
    if res is None:
        return 130
    payload = res.to_json()
    _write_summary(args.out, payload)
    if args.json:
        print(json.dumps(payload, allow_nan=False))
    else:
        _print_table(res.summary or [], COLUMNS[args.name])
        print(f"{runs} runs of {args.name} ({days:g} days, seed {seed}): {res.computed} "
              f"computed, {res.reused} reused, {res.failed} failed, {res.wall_s:.1f} s; "
              f"records in {os.path.join(args.out, 'runs.jsonl')}, summary in "
              f"{os.path.join(args.out, SUMMARY_FILE)}")
        for rec in res.records:
            if rec["status"] != "ok":
                print(f"run {rec['index']} failed: {rec['error']}")
    return 1 if res.failed else 0


def _common(args):
    """The options every campaign shares: runs, seed and where to run (engine, workers,
    scheduler, timeout)."""
    if args.timeout is not None and not (args.scheduler or args.local_cluster):
        raise UsageError("--timeout is the wait for a Dask cluster: it goes with --scheduler "
                         "or --local-cluster (local workers need none)")
    runs = _number("runs", args.runs, int, 1, 10**7)
    seed = _number("seed", args.seed, int, 0, 2**63 - 1)
    output_path(args.out, "--out", folder=True)  # made and writable before any run
    timeout = (None if args.timeout is None  # None: run_campaign's own default
               else _number("timeout", args.timeout, float, 0.0, 3600.0, lo_open=True))
    if args.workers is not None and args.scheduler:
        raise UsageError("--workers sets local processes; the cluster at --scheduler has its own")
    workers = _number("workers", args.workers or "2", int, 1, 256)
    if not args.local_cluster and not args.scheduler:
        workers = check_int("workers", workers, 1, os.cpu_count() or 1)
    engine = "dask" if args.scheduler else ("local-cluster" if args.local_cluster else "local")
    where = {"engine": engine, "workers": workers, "scheduler": args.scheduler}
    return runs, seed, where if timeout is None else {**where, "timeout": timeout}


def _run(args, camp, runs, seed, where):
    """Run the campaign into ``args.out``; None when interrupted (the message printed)."""
    from xnavlab.core.campaign import run_campaign

    try:
        return run_campaign(camp, runs, seed=seed, out=args.out,
                            progress=not (args.quiet or args.json), **where)
    except KeyboardInterrupt:
        print(f"xnavlab: interrupted; the finished runs are in {args.out}; run the same "
              f"command to complete the campaign", file=sys.stderr)
        return None


def _write_summary(out, payload):
    """Everything but the runs, to ``out/summary.json`` (beside runs.jsonl, for later use)."""
    from xnavlab.core.campaign import SUMMARY_FILE

    summary = {k: v for k, v in payload.items() if k != "runs"}
    with open(os.path.join(out, SUMMARY_FILE), "w", encoding="utf-8") as fh:
        json.dump(summary, fh, indent=1, allow_nan=False)


def _execute_roc(args):
    """``campaign roc``: the curve of a grid's thresholds and faults (:mod:`xnavlab.mars.roc`)."""
    from xnavlab.mars import roc

    if args.days is not None:
        raise UsageError("campaign roc takes its run length from the grid file's days, "
                         "not --days")
    grid = roc.load_grid(args.grid) if args.grid is not None else roc.check_grid(roc.DEFAULT_GRID)
    runs, seed, where = _common(args)
    nf = len(grid["faults"])
    if runs % nf:
        print(f"xnavlab: warning: --runs {runs} gives the grid's {nf} faults unequal numbers "
              f"of trials; a multiple of {nf} gives each the same", file=sys.stderr)
    res = _run(args, roc.campaign(grid), runs, seed, where)
    if res is None:
        return 130
    payload = res.to_json()
    _write_summary(args.out, payload)
    data = roc.write_curve(args.out, grid, res.runs(), seed)
    counts = {k: payload[k] for k in ("computed", "reused", "failed", "wall_s")}
    if args.json:
        print(json.dumps({**data, **counts}, allow_nan=False))
    else:
        print(f"{grid['detector']} detector, threshold {grid['threshold_name']}, "
              f"{nf} faults, {grid['days']:g}-day runs")
        _print_table(data["curve"], COLUMNS["roc"])
        print(f"{runs} runs of roc (seed {seed}): {res.computed} computed, {res.reused} "
              f"reused, {res.failed} failed, {res.wall_s:.1f} s; curve in "
              f"{os.path.join(args.out, 'roc.json')} and roc.csv; Pd: Wilson 95 % interval, "
              f"false alarms per day: exact Poisson (Garwood) 95 % interval")
        for rec in res.records:
            if rec["status"] != "ok":
                print(f"run {rec['index']} failed: {rec['error']}")
    return 1 if res.failed else 0


def _print_table(rows, cols):
    def fmt(v):
        if isinstance(v, float):
            return f"{v:.4g}"
        return "-" if v is None else str(v)

    cells = [[fmt(r.get(c)) for c in cols] for r in rows]
    width = [max([len(c)] + [len(row[j]) for row in cells]) for j, c in enumerate(cols)]
    print("  ".join(c.rjust(w) for c, w in zip(cols, width, strict=True)))
    for row in cells:
        print("  ".join(v.rjust(w) for v, w in zip(row, width, strict=True)))
