"""``python -m xnavlab scenario``: write or check a scenario file for ``run mars --scenario``.

Usage::

    python -m xnavlab scenario --dump [--setup study] [--out FILE]   # every key with its unit
    python -m xnavlab scenario --check FILE   # read it; print the settings it gives, with units

A written file read back gives the same settings (:mod:`xnavlab.mars.navigation.scenario_files`).
``--setup paper`` (the default) writes the paper's set-up (truth and filter share the
paper's force model), ``--setup study`` the studies'
(:meth:`xnavlab.mars.navigation.scenarios.MarsScenario.study`).
``--out`` must name a ``.toml`` file; its missing folders are made, as every ``--out`` of the
command line makes its own.
Exit codes: 0 done; 2 a bad file or command line (one line on stderr).
"""

from __future__ import annotations

import json
from pathlib import Path

from xnavlab.cli import UsageError
from xnavlab.core.userfiles import output_path, write_whole

__all__ = ["HELP", "configure", "execute"]

#: One-line help of the command (``python -m xnavlab --help``).
HELP = "write (--dump) or check (--check FILE) a scenario file for run mars --scenario"


def configure(parser):
    """Options of ``scenario``."""
    what = parser.add_mutually_exclusive_group()
    what.add_argument("--dump", action="store_true",
                      help="write the default scenario file (stdout, or --out)")
    what.add_argument("--check", metavar="FILE", help="read FILE and print the settings it gives")
    parser.add_argument("--out", metavar="FILE",
                        help="with --dump: write this .toml file instead of stdout (its missing "
                             "folders are made); another extension is refused")
    parser.add_argument("--setup", default=None,
                        help="with --dump: paper (default), truth and filter sharing the "
                             "paper's force model, or study, a rich truth and the paper's filter")


def execute(args):
    """Run ``scenario``; returns the exit code."""
    from xnavlab.mars.navigation import scenario_files

    if args.dump:
        from xnavlab.core.validate import check_choice
        from xnavlab.mars.navigation import scenarios

        setup = check_choice("--setup", "paper" if args.setup is None else args.setup,
                             scenario_files.SETUPS)
        # a missing folder is made; a folder, a file on the way or an unwritable folder is
        # one line, before the file is written
        # another extension before any folder is made (an empty name or a folder: output_path)
        if args.out is not None and args.out.strip() and not Path(args.out).is_dir() \
                and Path(args.out).suffix.lower() != ".toml":
            raise UsageError(f"--out must name a .toml file (scenario --dump writes TOML), got "
                             f"{args.out!r}")
        out = output_path(args.out, "--out") if args.out is not None else None
        sc = scenarios.MarsScenario.study() if setup == "study" else scenarios.MarsScenario()
        text = scenario_files.dump(sc)
        if out is not None:
            try:  # whole or not at all: a full disk leaves no file cut short
                write_whole(out, lambda tmp: tmp.write_text(text, encoding="utf-8"))
            except OSError as exc:
                raise ValueError(f"--out {str(out)!r} cannot be written ({exc.strerror})") from None
        else:
            print(text, end="")
        return 0
    if args.check is not None:  # --check "" is a file name too, refused when read
        if args.out is not None or args.setup is not None:
            raise UsageError(f"{'--out' if args.out is not None else '--setup'} goes with --dump")
        sf = scenario_files.load(args.check)
        units = {k: scenario_files.UNITS.get(k, "-") for k in scenario_files.scenario_json(sf.scenario)}
        print(json.dumps({"scenario": scenario_files.scenario_json(sf.scenario), "units": units,
                          "run": sf.run, "detector": sf.detector}, indent=1))
        return 0
    raise UsageError("scenario needs --dump or --check FILE")
