"""Command line: ``python -m xnavlab reproduce ID [--json] [--out DIR]``.

Usage errors print one line on stderr and exit with code 2.

Subcommands
-----------
reproduce ID | --list | --all
    Run a registered reproduction (see :mod:`xnavlab.reproduce`).
run SCENARIO
    Run a scenario (registered by :mod:`xnavlab.scenarios` when present).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from . import reproduce

__all__ = ["main", "UsageError", "add_runner"]


class UsageError(Exception):
    """A bad command line: reported as one line, exit code 2."""


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        raise UsageError(message)


# Scenario runners for ``xnavlab run NAME``: name -> (configure(parser), run(args) -> int).
_RUNNERS: dict = {}


def add_runner(name, configure, execute, help=""):
    """Register a scenario for ``python -m xnavlab run NAME``.

    ``configure(parser)`` adds the options; ``execute(args)`` runs it and returns the
    exit code. It may raise :class:`UsageError` or :class:`ValueError` for bad values.
    """
    _RUNNERS[name] = (configure, execute, help)


def _build_parser():
    parser = _Parser(prog="python -m xnavlab", description="xnavlab command line")
    sub = parser.add_subparsers(dest="command", parser_class=_Parser)
    rep = sub.add_parser("reproduce", help="run a registered paper reproduction")
    rep.add_argument("id", nargs="?", help="reproduction ID (see --list)")
    group = rep.add_mutually_exclusive_group()
    group.add_argument("--list", action="store_true", help="list the registered IDs")
    group.add_argument("--all", action="store_true", help="run every reproduction")
    rep.add_argument("--json", action="store_true", help="print JSON instead of a table")
    rep.add_argument("--out", metavar="DIR", help="write figures (and JSON for --all) here")
    _load_runners()
    if _RUNNERS:
        run = sub.add_parser("run", help="run a scenario")
        scen = run.add_subparsers(dest="scenario", parser_class=_Parser)
        for name, (configure, _, help_) in sorted(_RUNNERS.items()):
            configure(scen.add_parser(name, help=help_))
    return parser


def _load_runners():
    try:
        from . import scenarios  # noqa: F401  (registers runners on import)
    except ImportError as exc:
        if "scenarios" not in str(exc):
            raise


def main(argv=None):
    """Entry point; returns the process exit code."""
    try:
        args = _build_parser().parse_args(argv)
        if args.command == "reproduce":
            return _reproduce(args)
        if args.command == "run":
            if not args.scenario:
                raise UsageError("run needs a scenario: " + ", ".join(sorted(_RUNNERS)))
            return _RUNNERS[args.scenario][1](args)
        raise UsageError("a command is required: reproduce" + (", run" if _RUNNERS else ""))
    except (UsageError, ValueError) as exc:
        print(f"xnavlab: error: {exc}", file=sys.stderr)
        return 2


def _reproduce(args):
    if args.list:
        for rid in reproduce.ids():
            rep = reproduce.get(rid)
            print(f"{rid:28s} {rep.source}: {rep.title}")
        return 0
    if args.all:
        return _reproduce_all(args)
    if not args.id:
        raise UsageError("reproduce needs an ID, --list or --all")
    result = reproduce.run(args.id, out=args.out)
    if args.json:
        print(result.to_json())
    else:
        print(result.table())
        if result.note:
            print(result.note)
    return 0 if result.passed else 1


def _run_one(rid, out):
    """Run one reproduction for ``--all``; an exception becomes a failed result, not an abort."""
    try:
        return reproduce.run(rid, out=out)
    except Exception as exc:  # noqa: BLE001 - reported as a failure of that reproduction
        check = reproduce.Check("ran without error", "runs", f"{type(exc).__name__}: {exc}",
                                "must not raise", False)
        return reproduce.Result(rid, [check], note="the reproduction raised an exception")


def _reproduce_all(args):
    from tqdm import tqdm

    results = []
    for rid in tqdm(reproduce.ids(), desc="reproductions", unit="repro", file=sys.stderr):
        results.append(_run_one(rid, args.out))
    payload = [r.to_dict() for r in results]
    n_pass = sum(r.passed for r in results)
    if args.json:
        print(json.dumps(payload, default=reproduce._jsonable))
    else:
        print(reproduce.results_table(results))
        print(f"{n_pass} of {len(results)} reproductions pass")
    if args.out:
        path = Path(args.out) / "reproductions.json"
        path.write_text(json.dumps(payload, indent=2, default=reproduce._jsonable))
    return 0 if all(r.passed for r in results) else 1
