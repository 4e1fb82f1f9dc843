"""``python -m xnavlab reproduce ID | --list | --all``: the registered paper reproductions."""

from __future__ import annotations

import json
import sys
from pathlib import Path

from xnavlab import reproduce
from xnavlab.cli import UsageError
from xnavlab.core.userfiles import output_path, write_whole

__all__ = ["HELP", "configure", "execute"]

#: One-line help of the command (``python -m xnavlab --help``).
HELP = "run a registered paper reproduction"


def configure(parser):
    """Add the options of ``reproduce``."""
    parser.add_argument("id", nargs="?", help="reproduction ID (see --list)")
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--list", action="store_true", help="list the registered IDs")
    group.add_argument("--all", action="store_true", help="run every reproduction")
    parser.add_argument("--json", action="store_true",
                        help="print JSON instead of a table (no progress bar)")
    parser.add_argument("--quiet", action="store_true", help="no progress bar (--all)")
    parser.add_argument("--out", metavar="DIR",
                        help="write figures (and JSON for --all) here (made if missing, with its "
                             "parent folders)")
    parser.add_argument("--fresh", action="store_true",
                        help="compute every result again, not from the reproduction cache "
                             "(results computed before by the same code on this machine)")


def execute(args):
    """Run ``reproduce``; exit code 0 when it ran and every check of ours holds, 1 otherwise.

    A paper claim that is not reproduced, or undecided, is a result, not an error: the exit code
    is 1 only for a reproduction that raised or whose check of ours failed (``ERROR``). The table
    and the JSON use the verdicts of :data:`xnavlab.verdicts.VERDICTS` and the headlines of
    :data:`xnavlab.verdicts.HEADLINES`; ``--all`` ends with
    :func:`xnavlab.reproduce.headline` (on stderr with ``--json``). A file under ``--out`` that
    cannot be written (a full disk) ends it in one line naming ``--out`` and the file, exit
    code 2; each file is written whole or not at all.
    """
    try:
        return _execute(args)
    except reproduce.OutputError as exc:  # "out 'DIR': NAME ...", as the user typed it
        raise ValueError(f"--{exc}") from None


def _execute(args):
    _refuse_unused(args)
    if args.out is not None:  # made and writable before any reproduction runs
        _check_out(args.out, args.all)
    if args.list:
        for rid in reproduce.ids():
            rep = reproduce.get(rid)
            print(f"{rid:28s} {rep.source}: {rep.title}")
        return 0
    if args.all:
        return _reproduce_all(args)
    if args.id is None:  # an empty ID is an unknown one, not a missing one
        raise UsageError("reproduce needs an ID, --list or --all")
    result = reproduce.run(args.id, out=args.out, fresh=args.fresh)
    if args.json:
        print(result.to_json())
    else:
        print(result.table())
        if result.note:
            print(result.note)
        print(f"{result.id}: {result.verdict}")
    return 0 if result.ok else 1


def _check_out(out, every):
    """``--out``: a folder that can be written, with no figure name (``*.png``) that is not a
    writable file (a folder, a link to nothing, a read-only file) and, with ``--all``, a
    writable ``reproductions.json``: refused now, not after the reproductions ran."""
    folder = output_path(out, "--out", folder=True)
    for entry in sorted(folder.iterdir()):
        if entry.name.endswith(".png"):
            output_path(entry, f"--out {str(out)!r}: the figure {entry.name}")
    if every:
        output_path(folder / "reproductions.json", f"--out {str(out)!r}: reproductions.json")


def _refuse_unused(args):
    """Every option given is used, or the command line is refused in one line."""
    if args.list:
        unused = ([f"ID ({args.id!r})"] if args.id is not None else []) + [
            flag for flag, given in (("--json", args.json), ("--out", args.out is not None),
                                     ("--fresh", args.fresh), ("--quiet", args.quiet)) if given]
        if unused:
            raise UsageError(f"--list takes no {', '.join(unused)}: it prints the registered IDs")
    elif args.all and args.id is not None:
        raise UsageError(f"--all takes no ID (got {args.id!r}): it runs every reproduction; "
                         f"give the ID alone to run one")
    elif args.quiet and not args.all:
        raise UsageError("--quiet goes with --all (one reproduction shows no progress bar)")


def run_one(rid, out, fresh=False):
    """Run one reproduction for ``--all``; an exception becomes an ERROR result, not an abort."""
    return reproduce.run_or_fail(rid, out=out, fresh=fresh)


def _reproduce_all(args):
    from tqdm import tqdm

    results = []
    # a bar on stderr as campaigns have, none with --json or --quiet (as for run and campaign)
    for rid in tqdm(reproduce.ids(), desc="reproductions", unit="repro", file=sys.stderr,
                    disable=args.json or args.quiet):
        results.append(run_one(rid, args.out, args.fresh))
    payload = [r.to_dict() for r in results]
    if args.json:
        print(json.dumps(payload, default=reproduce.jsonable, allow_nan=False))
        print(reproduce.headline(results), file=sys.stderr)
    else:
        print(reproduce.results_table(results))
        print(reproduce.headline(results))
    if args.out:
        text = json.dumps(payload, indent=2, default=reproduce.jsonable, allow_nan=False)
        try:
            write_whole(Path(args.out) / "reproductions.json", lambda tmp: tmp.write_text(text))
        except OSError as exc:
            raise reproduce.OutputError(f"out {str(args.out)!r}: reproductions.json cannot be "
                                        f"written ({exc.strerror or exc})") from None
    return 0 if all(r.ok for r in results) else 1
