"""``python -m xnavlab reproduce ID | --list | --all``: the registered paper reproductions."""

from __future__ import annotations

import json
import sys
from pathlib import Path

from xnavlab import reproduce
from xnavlab.cli import UsageError

__all__ = ["HELP", "configure", "execute"]

#: One-line help of the command (``python -m xnavlab --help``).
HELP = "run a registered paper reproduction"


def configure(parser):
    """Add the options of ``reproduce``."""
    parser.add_argument("id", nargs="?", help="reproduction ID (see --list)")
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--list", action="store_true", help="list the registered IDs")
    group.add_argument("--all", action="store_true", help="run every reproduction")
    parser.add_argument("--json", action="store_true", help="print JSON instead of a table")
    parser.add_argument("--out", metavar="DIR", help="write figures (and JSON for --all) here")


def execute(args):
    """Run ``reproduce``; exit code 0 when every check passes, 1 otherwise."""
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


def run_one(rid, out):
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
        results.append(run_one(rid, args.out))
    payload = [r.to_dict() for r in results]
    n_pass = sum(r.passed for r in results)
    if args.json:
        print(json.dumps(payload, default=reproduce.jsonable))
    else:
        print(reproduce.results_table(results))
        print(f"{n_pass} of {len(results)} reproductions pass")
    if args.out:
        path = Path(args.out) / "reproductions.json"
        path.write_text(json.dumps(payload, indent=2, default=reproduce.jsonable))
    return 0 if all(r.passed for r in results) else 1
