"""``python -m xnavlab scenario``: write or check a scenario file for ``run mars --scenario``.

Usage::

    python -m xnavlab scenario --dump [--out FILE]   # the defaults, every key with its unit
    python -m xnavlab scenario --check FILE          # read it; print the settings it gives

A written file read back gives the same settings (:mod:`xnavlab.mars.scenario_files`).
Exit codes: 0 done; 2 a bad file or command line (one line on stderr).
"""

from __future__ import annotations

import json
from pathlib import Path

from xnavlab.cli import UsageError

__all__ = ["HELP", "configure", "execute"]

#: One-line help of the command (``python -m xnavlab --help``).
HELP = "write (--dump) or check (--check FILE) a scenario file for run mars --scenario"


def configure(parser):
    """Options of ``scenario``."""
    what = parser.add_mutually_exclusive_group()
    what.add_argument("--dump", action="store_true",
                      help="write the default scenario file (stdout, or --out)")
    what.add_argument("--check", metavar="FILE", help="read FILE and print the settings it gives")
    parser.add_argument("--out", metavar="FILE", help="with --dump: write here instead of stdout")


def execute(args):
    """Run ``scenario``; returns the exit code."""
    from xnavlab.mars import scenario_files

    if args.dump:
        text = scenario_files.dump()
        if args.out:
            out = Path(args.out)
            if out.is_dir():
                raise ValueError(f"out must be a file name, but {str(out)!r} is a directory")
            out.write_text(text, encoding="utf-8")
        else:
            print(text, end="")
        return 0
    if args.check:
        if args.out:
            raise UsageError("--out goes with --dump")
        sf = scenario_files.load(args.check)
        fields = {k: v for k, v in vars(sf.scenario).items()}
        print(json.dumps({"scenario": fields, "run": sf.run, "detector": sf.detector}, indent=1))
        return 0
    raise UsageError("scenario needs --dump or --check FILE")
