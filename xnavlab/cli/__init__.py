"""Command line: ``python -m xnavlab COMMAND ...``, the top layer of the package.

Usage errors print one line on stderr and exit with code 2. ``python -m xnavlab --version``
prints ``xnavlab`` and :data:`xnavlab.__version__` on one line and exits with code 0.

Commands are discovered through :data:`COMMANDS`, a table of the modules that implement
them; nothing below this package imports it, so the models never know about the command
line. A command module provides ``HELP`` (one line), ``configure(parser)`` (adds its
options) and ``execute(args) -> int`` (the exit code; it may raise :class:`UsageError` or
``ValueError`` for bad input).

Commands
--------
``reproduce ID | --list | --all``
    Run a registered reproduction (:mod:`xnavlab.cli.reproduce`).
``run SCENARIO``
    Run a scenario, e.g. ``run mars --days 30`` (:mod:`xnavlab.cli.runners`).
``warmup``
    Compile and cache every numba kernel the chapters use (:mod:`xnavlab.cli.warmup`).
``campaign NAME``
    A Monte Carlo campaign, local or on a Dask cluster, resumable (:mod:`xnavlab.cli.campaigns`).
``scenario --dump | --check FILE``
    Write or check a scenario file for ``run mars --scenario`` (:mod:`xnavlab.cli.scenario`).
"""

from __future__ import annotations

import argparse
import importlib
import sys

from xnavlab import __version__

__all__ = ["main", "UsageError", "Parser", "COMMANDS"]

#: Command name -> module implementing it (``HELP``, ``configure``, ``execute``).
COMMANDS = {
    "reproduce": "xnavlab.cli.reproduce",
    "run": "xnavlab.cli.runners",
    "warmup": "xnavlab.cli.warmup",
    "campaign": "xnavlab.cli.campaigns",
    "scenario": "xnavlab.cli.scenario",
}


class UsageError(Exception):
    """A bad command line: reported as one line, exit code 2."""


class Parser(argparse.ArgumentParser):
    """An ``ArgumentParser`` that raises :class:`UsageError` instead of exiting."""

    def error(self, message):
        raise UsageError(message)


def build_parser():
    """The full parser; each command module adds its own options."""
    parser = Parser(prog="python -m xnavlab", description="xnavlab command line")
    parser.add_argument("--version", action="store_true",
                        help="print the package version (xnavlab.__version__) and exit")
    sub = parser.add_subparsers(dest="command", parser_class=Parser)
    for name, modname in COMMANDS.items():
        module = importlib.import_module(modname)
        cmd = sub.add_parser(name, help=module.HELP)
        module.configure(cmd)
        cmd.set_defaults(execute=module.execute)
    return parser


def main(argv=None):
    """Entry point; returns the process exit code."""
    try:
        args = build_parser().parse_args(argv)
        if args.version:
            print(f"xnavlab {__version__}")
            return 0
        if args.command is None:
            raise UsageError("a command is required: " + ", ".join(COMMANDS))
        return args.execute(args)
    except (UsageError, ValueError) as exc:
        print(f"xnavlab: error: {exc}", file=sys.stderr)
        return 2
