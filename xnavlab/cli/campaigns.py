"""``python -m xnavlab campaign NAME``: a Monte Carlo campaign, local or on a Dask cluster.

Usage::

    python -m xnavlab campaign NAME --runs N --days D --seed S --out DIR [--scenario FILE]
        [--workers K | --scheduler tcp://HOST:PORT | --local-cluster [--workers K]]
        [--timeout SECONDS] [--json] [--quiet]
    python -m xnavlab campaign roc --grid FILE --runs N --seed S --out DIR [...]

``NAME`` is one of :data:`xnavlab.mars.studies.campaigns.CAMPAIGNS` (``consistency``, ``detectors``)
(``consistency --scenario FILE`` takes every setting of a scenario file that a fault-free
consistency run has: a study's truth, pulsars from timing models, the sensors' noise, mode,
beta, initial error sigmas, orbit, backend and local filter; its ``[run] days`` and ``seed``
are the campaign's days and seed, ``--days`` and ``--seed`` overriding them. A key the campaign
does not use, set to other than its default, is refused in one line naming it: ``[run]
record_dt`` and ``settle_days`` (the campaign records at min(60 s, span / 48) and averages from
a quarter of the run) and every ``[detector]`` key (the runs are fault-free); ``[filter]
init_error`` at its default is the campaign's random initial error) or ``roc``: the receiver
operating characteristic of a detector (:mod:`xnavlab.mars.studies.roc`), its threshold swept over the
values of a grid file (TOML or JSON, the format in :mod:`xnavlab.mars.studies.roc`; without ``--grid``,
:data:`xnavlab.mars.studies.roc.DEFAULT_GRID`) on its faults (run ``i`` is fault ``i mod F``, every
threshold on the same run). The run length is the grid's ``days`` (``--days`` is refused).
Besides ``runs.jsonl`` and ``summary.json`` it writes ``DIR/roc.json`` (the grid, the curve per
threshold: Pd with its Wilson 95 % interval, false alarms per day with its exact Poisson
(Garwood) 95 % interval; and the same per fault) and ``DIR/roc.csv`` (the curve); ``--json``
prints the contents of ``roc.json`` with the counts (``computed``, ``reused``, ``failed``,
``wall_s``) instead of every run. The runs execute on a local process pool of ``K`` workers
(default 2), on the Dask cluster whose scheduler is at ``--scheduler``, or on a Dask
``LocalCluster`` of ``K`` worker processes (``--local-cluster``); run ``i`` draws its seed from
``SeedSequence(S)`` by its index, so the records are the same on each. Every run is appended to
``DIR/runs.jsonl`` as it completes (the header in ``DIR/campaign.json``, so ``runs.jsonl``
holds records only and ``pandas.read_json(DIR + "/runs.jsonl", lines=True)`` or
:func:`xnavlab.core.campaign.load_runs` reads it); running the same command again reuses the
finished runs and computes the missing ones (:mod:`xnavlab.core.campaign`). The summary
(everything but the runs) is written to ``DIR/summary.json``. A progress bar on stderr shows
the runs done, failed and the rate (none with ``--json`` or ``--quiet``).

Output: the summary table and a line of counts, or with ``--json`` one JSON object with
``campaign`` (the manifest), ``runs`` (one record per run in index order: ``index``,
``seed``, ``parameters``, ``metrics``, ``status``, ``error``), ``summary`` (the aggregated
table), ``computed``, ``reused``, ``failed`` and ``wall_s``.

Exit codes: 0 every run ok; 1 some runs failed (after their retry; they are in the output
and the store); 2 bad input (one line on stderr), including a DIR that holds another
campaign, a malformed ``--scheduler`` address and an unreachable scheduler (``--timeout``,
default 5 s): a refused command makes no store in DIR, so the corrected one starts afresh;
130 interrupted (the finished runs are stored). A line of ``runs.jsonl`` that is not a
record (a last line torn by an interrupted write) is one warning line naming the file and
the line, and its run is computed again.
"""

from __future__ import annotations

import contextlib
import json
import os
import signal
import sys
import threading

from xnavlab.cli import UsageError, number
from xnavlab.core.diskcache import check_cache
from xnavlab.core.userfiles import output_path, write_whole
from xnavlab.core.validate import SEED_MAX, check_int

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
    # the names are listed, not imported: the parser stays light (xnavlab.mars.studies.campaigns)
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
                             "detector, thresholds, days, faults: see xnavlab.mars.studies.roc); "
                             "default xnavlab.mars.studies.roc.DEFAULT_GRID")
    parser.add_argument("--seed", default=None,
                        help="the campaign's seed (default 0, or the --scenario file's)")
    parser.add_argument("--scenario", metavar="FILE", dest="scenario_file", default=None,
                        help="consistency only: take every setting of this scenario file a "
                             "fault-free run has (--days and --seed override its days and "
                             "seed); a key the campaign does not use is refused")
    parser.add_argument("--out", required=True, metavar="DIR",
                        help="campaign directory (made if missing, with its parent folders): "
                             "runs.jsonl is appended there and reused")
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
    """Run ``campaign``; returns the exit code.

    The first SIGINT (a Ctrl-C) interrupts it and every later one is ignored
    (``_interrupt_once``): the local workers ignore it and are ended by the campaign
    process, which keeps the finished runs, prints one line and returns 130.
    """
    handler = signal.getsignal(signal.SIGINT)
    ours = (handler is signal.default_int_handler
            and threading.current_thread() is threading.main_thread())
    if ours:
        signal.signal(signal.SIGINT, _interrupt_once)
    try:
        return _execute(args)
    except KeyboardInterrupt:
        print(f"xnavlab: interrupted; the finished runs are in {args.out}; run the same "
              f"command to complete the campaign", file=sys.stderr)
        return 130
    finally:
        if ours and signal.getsignal(signal.SIGINT) is _interrupt_once:  # not interrupted
            signal.signal(signal.SIGINT, handler)


def _interrupt_once(signum, frame):
    """SIGINT handler of a running campaign: the first SIGINT raises KeyboardInterrupt and
    every later one is ignored (the process is ending), so that a second Ctrl-C, or
    ``timeout -s INT`` signalling the process and then its group, cannot break off ending the
    workers, closing the store or the interpreter's exit (a hang, a traceback)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    raise KeyboardInterrupt


def _execute(args):
    """:func:`execute`, SIGINT aside."""
    from xnavlab.core.campaign import SUMMARY_FILE
    from xnavlab.mars.studies.campaigns import CAMPAIGNS, DAYS, campaign

    if args.name not in CAMPAIGNS and args.name != "roc":
        raise UsageError(f"campaign must be one of {', '.join(CAMPAIGNS)}, roc, "
                         f"got {args.name!r}")
    if args.grid is not None and args.name != "roc":
        raise UsageError("--grid is an option of campaign roc only")
    if args.scenario_file is not None and args.name != "consistency":
        raise UsageError("--scenario is an option of campaign consistency only")
    if args.name == "roc":
        return _execute_roc(args)
    file_days = file_seed = scenario = None
    options = {}
    if args.scenario_file is not None:
        scenario, options, file_days, file_seed = _consistency_file(args.scenario_file)
    if args.seed is None and file_seed is not None:
        args.seed = str(file_seed)
    runs, seed, where = _common(args)
    lo, hi = DAYS[args.name]  # the campaign's own range, checked again (with more) below
    days = (file_days if args.days is None and file_days is not None else
            _number("--days", "1" if args.days is None else args.days, float, lo, hi,
                    lo_open=args.name == "consistency"))
    if scenario is not None:
        import dataclasses

        scenario = dataclasses.replace(scenario, days=days, seed=0)
    camp = campaign(args.name, days=days, scenario=scenario, **options)
    _check_store(args.out, camp, seed, runs)
    if args.name == "detectors":
        from xnavlab.mars.studies.campaigns import detector_cells

        cells = len(detector_cells())
        if runs % cells:
            covered = min(runs, cells)
            print(f"xnavlab: warning: --runs {runs} covers {covered} of the {cells} cells "
                  f"(fault class x sensor x size){' unequally' if runs > cells else ''}; "
                  f"a multiple of {cells} gives every cell the same number of trials",
                  file=sys.stderr)
    res = _run(args, camp, runs, seed, where)
    payload = res.to_dict()
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


def _consistency_file(path):
    """``campaign consistency --scenario FILE``: (scenario, run options, the file's days or
    None, its seed or None); a key the campaign does not use, set apart from its default, is
    one line naming it."""
    from pathlib import Path

    from xnavlab.core.userfiles import parse_toml, read_text
    from xnavlab.mars.navigation import scenario_files
    from xnavlab.mars.studies.campaigns import DAYS

    sf = scenario_files.load(path)
    try:
        given = parse_toml(read_text(Path(path), "scenario file"), "scenario file")
    except ValueError:  # load read it: not reached
        given = {}
    run, det = given.get("run", {}), given.get("detector", {})
    unused = {("run", "record_dt"): (sf.scenario.record_dt != 60.0,
                                     "its runs record at min(60 s, span / 48)"),
              ("run", "settle_days"): (sf.run["settle_days"] is not None,
                                       "its RMS errors are from a quarter of the run on")}
    for key in det:
        value, default = sf.detector[key], scenario_files.DETECTOR_DEFAULTS[key]
        at_default = value == default or (key == "name" and value == "none")
        unused[("detector", key)] = (not at_default, "its runs are fault-free")
    for (section, key), (refuse, why) in unused.items():
        if refuse:
            raise UsageError(f"scenario file {str(path)!r}: [{section}] {key} is not used by "
                             f"campaign consistency ({why}); remove it")
    days = None
    if "days" in run:
        days = sf.scenario.days
        lo, hi = DAYS["consistency"]
        if not lo < days <= hi:
            raise UsageError(f"scenario file {str(path)!r}: [run] days must be in ({lo:g}, "
                             f"{hi:g}] for campaign consistency (or give --days), got {days:g}")
    seed = sf.scenario.seed if "seed" in run else None
    options = {"backend": sf.run["backend"], "local_filter": sf.run["local_filter"]}
    return sf.scenario, options, days, seed


def _common(args):
    """The options every campaign shares: runs, seed and where to run (engine, workers,
    scheduler, timeout)."""
    if args.scheduler is not None and not args.scheduler.strip():  # an empty "$SCHEDULER"
        raise UsageError("--scheduler is empty: give the scheduler's address (tcp://HOST:8786), "
                         "or leave the flag out to run on local workers")
    if args.scheduler is not None:
        from xnavlab.core.campaign import check_scheduler

        check_scheduler("--scheduler", args.scheduler)  # malformed, not unreachable: one line
    if args.timeout is not None and not (args.scheduler or args.local_cluster):
        raise UsageError("--timeout is the wait for a Dask cluster: it goes with --scheduler "
                         "or --local-cluster (local workers need none)")
    runs = _number("--runs", args.runs, int, 1, 10**7)
    seed = _number("--seed", "0" if args.seed is None else args.seed, int, 0, SEED_MAX)
    timeout = (None if args.timeout is None  # None: run_campaign's own default
               else _number("--timeout", args.timeout, float, 0.0, 3600.0, lo_open=True))
    if args.workers is not None and args.scheduler:
        raise UsageError("--workers sets local processes; the cluster at --scheduler has its own")
    workers = _number("--workers", "2" if args.workers is None else args.workers, int, 1, 256)
    if not args.local_cluster and not args.scheduler:
        workers = check_int("--workers", workers, 1, os.cpu_count() or 1)
    if not args.scheduler:  # runs here read the cache: refused before the folder is made
        check_cache()
    output_path(args.out, "--out", folder=True)  # made and writable before any run, once the
    # flags are checked (a bad flag leaves no folder behind)
    engine = "dask" if args.scheduler else ("local-cluster" if args.local_cluster else "local")
    where = {"engine": engine, "workers": workers, "scheduler": args.scheduler}
    return runs, seed, where if timeout is None else {**where, "timeout": timeout}


def _check_store(out, camp, seed, runs):
    """A folder that holds another campaign (its header, or a stored run of the first
    ``runs`` with other parameters or seed) is refused now, in one line naming ``--out``,
    before any warning about the command as typed; the store is only read (no file is made
    before every check has passed: run_campaign reads it again, connects, then opens it)."""
    from xnavlab.core.campaign import SUMMARY_FILE, Store, differences, json_ready
    from xnavlab.core.montecarlo import seeds

    with _flags():
        run_seeds = seeds(seed, runs)
        for i, rec in Store.read(out, camp.header(seed), camp.check_metrics).items():
            if i >= runs:
                continue
            stored = {"seed": rec["seed"], "parameters": rec["parameters"]}
            asked = {"seed": run_seeds[i], "parameters": json_ready(camp.params(i))}
            if stored != asked:
                raise ValueError(f"--out {str(out)!r}: stored run {i} is another campaign's: "
                                 f"{differences(stored, asked)}; choose another --out")
    _check_outputs(out, SUMMARY_FILE)


class _flags:
    """Context: a ValueError of the campaign API that leads with its parameter ``out`` or
    ``scheduler`` is raised again leading with the flag, ``--out`` or ``--scheduler``."""

    def __enter__(self):
        return self

    def __exit__(self, kind, exc, tb):
        if kind is not ValueError:
            return False
        msg = str(exc)
        for name in ("out", "scheduler"):
            if msg.startswith(name + " "):
                raise ValueError(f"--{msg}") from None
        return False


def _check_outputs(out, *names):
    """The files written after the runs (summary.json; roc.json and roc.csv), checked before
    them: a folder or a pipe in their place is refused now, not after the campaign."""
    for name in names:
        output_path(os.path.join(out, name), f"--out {str(out)!r}: {name}")


def _run(args, camp, runs, seed, where):
    """Run the campaign into ``args.out`` (KeyboardInterrupt: the finished runs are stored)."""
    from xnavlab.core.campaign import run_campaign

    with _flags():
        return run_campaign(camp, runs, seed=seed, out=args.out,
                            progress=not (args.quiet or args.json), **where)


def _write_summary(out, payload):
    """Everything but the runs, to ``out/summary.json`` (beside runs.jsonl, for later use),
    whole or not at all; a write that fails (a full disk) is one line naming the file."""
    from xnavlab.core.campaign import SUMMARY_FILE

    summary = {k: v for k, v in payload.items() if k != "runs"}
    text = json.dumps(summary, indent=1, allow_nan=False)
    with _written(out, SUMMARY_FILE):
        write_whole(os.path.join(out, SUMMARY_FILE), lambda tmp: tmp.write_text(text))


@contextlib.contextmanager
def _written(out, name):
    """Context: an OSError writing the file ``name`` into ``--out`` (a full disk) is one
    ValueError naming them, as ``run mars`` words it."""
    try:
        yield
    except OSError as exc:
        raise ValueError(f"--out {str(out)!r}: {name} cannot be written "
                         f"({exc.strerror or exc})") from None


def _execute_roc(args):
    """``campaign roc``: the curve of a grid's thresholds and faults (:mod:`xnavlab.mars.studies.roc`)."""
    from xnavlab.mars.studies import roc

    if args.days is not None:
        raise UsageError("campaign roc takes its run length from the grid file's days, "
                         "not --days")
    grid = roc.load_grid(args.grid) if args.grid is not None else roc.check_grid(roc.DEFAULT_GRID)
    runs, seed, where = _common(args)
    nf = len(grid["faults"])
    camp = roc.campaign(grid)
    _check_store(args.out, camp, seed, runs)  # before any warning about the command as typed
    _check_outputs(args.out, "roc.json", "roc.csv")
    if runs % nf:
        print(f"xnavlab: warning: --runs {runs} gives the grid's {nf} faults unequal numbers "
              f"of trials; a multiple of {nf} gives each the same", file=sys.stderr)
    res = _run(args, camp, runs, seed, where)
    payload = res.to_dict()
    _write_summary(args.out, payload)
    with _written(args.out, "roc.json or roc.csv"):
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
