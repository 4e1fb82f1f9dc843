"""Command line: ``python -m xnavlab COMMAND ...``, the top layer of the package.

Usage errors print one line on stderr and exit with code 2; so does an option given twice
(``--faults A --faults B``: argparse would keep B and drop A without a word). ``python -m xnavlab --version``
prints ``xnavlab`` and :data:`xnavlab.__version__` on one line and exits with code 0; given
with anything else (``--version run mars --days -1``) it is refused, as the rest would go
unread. An unknown command or scenario is named as typed (``run: unknown scenario
'attitude' (choose from 'mars')``), not by argparse's internal name.

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
import errno
import importlib
import math
import os
import re
import sys
import warnings

from xnavlab import __version__

__all__ = ["main", "UsageError", "StreamError", "Parser", "COMMANDS", "EXIT_PIPE", "number",
           "join_negative_values"]

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


def _given_once(action, namespace, option_string):
    """Refuse an option given a second time on one command line (argparse would keep the last
    value and drop the earlier one without a word)."""
    if option_string is None:  # a positional argument: argparse takes it once
        return
    given = getattr(namespace, "given_options", None)
    if given is None:
        given = set()
        namespace.given_options = given
    if action.dest in given:
        name = max(action.option_strings, key=len)
        hint = "; join the fault specs with ','" if name == "--faults" else ""
        raise UsageError(f"{name} given twice; give each option once{hint}")
    given.add(action.dest)


class _StoreOnce(argparse.Action):
    """argparse's ``store``, given once."""

    def __call__(self, parser, namespace, values, option_string=None):
        _given_once(self, namespace, option_string)
        setattr(namespace, self.dest, values)


class _StoreTrueOnce(argparse.Action):
    """argparse's ``store_true``, given once."""

    def __init__(self, option_strings, dest, default=False, required=False, help=None):
        super().__init__(option_strings, dest, nargs=0, const=True, default=default,
                         required=required, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        _given_once(self, namespace, option_string)
        setattr(namespace, self.dest, self.const)


class Parser(argparse.ArgumentParser):
    """An ``ArgumentParser`` that raises :class:`UsageError` instead of exiting, and refuses an
    option given twice on one command line (``--days 0.2 --days 0.3``), which argparse would
    read as the last one alone, and an abbreviated one (``--da 0.2``: flags are written in full,
    so that a new flag never changes what an old command line means)."""

    def __init__(self, *args, **kwargs):
        # a flag as written in full: argparse would take --da for --days, --versio for --version
        super().__init__(*args, **{"allow_abbrev": False, **kwargs})
        self.register("action", None, _StoreOnce)
        self.register("action", "store", _StoreOnce)
        self.register("action", "store_true", _StoreTrueOnce)

    def parse_known_args(self, args=None, namespace=None):
        self.argv = list(sys.argv[1:] if args is None else args)  # for error's hint
        return super().parse_known_args(args, namespace)

    def print_help(self, file=None):
        """argparse's, without its silence on a failed write: ``--help > /dev/full`` is an
        error (:func:`main`), not a success that wrote nothing."""
        (sys.stdout if file is None else file).write(self.format_help())

    def error(self, message):
        """One line; an option written before the sub-command it belongs to (``run --days 0.02``,
        which argparse reports as ``invalid choice: '0.02'``) is named with the order to use."""
        bad = re.fullmatch(r"argument (\w+): invalid choice: '(.*)' \(choose from (.*)\)", message)
        argv = getattr(self, "argv", [])
        cmd = self.prog.removeprefix("python -m xnavlab").strip()
        if bad and cmd and bad[2] in argv and any(a.startswith("-") for a in
                                                  argv[:argv.index(bad[2])]):
            choices = [c.strip().strip("'") for c in bad[3].split(",")]
            given = [a for a in argv if a in choices]
            rest = [a for a in argv if a not in given[:1]]
            raise UsageError(f"{cmd} needs its {bad[1]} before the options (choose from "
                             f"{bad[3]}): write '{' '.join([cmd, (given or choices)[0], *rest])}'")
        if bad:  # argparse's dest ('argument scenario') is no word the user typed or read
            raise UsageError(f"{cmd or 'python -m xnavlab'}: unknown {bad[1]} {bad[2]!r} "
                             f"(choose from {bad[3]})")
        raise UsageError(message)


_REAL = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?|[+-]?(inf|infinity|nan)", re.I | re.A)
_INT = re.compile(r"[+-]?\d+", re.A)


def number(name, text, kind=float, lo=-math.inf, hi=math.inf, lo_open=False, hi_open=False):
    """A flag's number: plain decimal text (``1e-3``, ``30``), in range, or one ValueError that
    names the flag, its range and the text as typed.

    Python's own ``float``/``int`` would also take ``1_0`` (ten), ``0x10`` or surrounding
    blanks; a command line takes only what it shows.

    Examples
    --------
    >>> number("--days", "0.5", float, 0.0, 365.0, lo_open=True)
    0.5
    >>> number("--days", "1_0", float, 0.0, 365.0, lo_open=True)
    Traceback (most recent call last):
    ...
    ValueError: --days must be a real number in (0, 365], got '1_0'
    """
    from xnavlab.core.validate import check_int, check_real

    pattern = _INT if kind is int else _REAL
    try:
        if not isinstance(text, str) or not pattern.fullmatch(text):
            raise ValueError
        if kind is int:
            return check_int(name, int(text), lo, hi)
        return check_real(name, float(text), lo, hi, lo_open=lo_open, hi_open=hi_open)
    except ValueError as exc:  # the range as the check words it, the text as typed
        probe = "x" if kind is int else math.nan
        try:
            (check_int(name, probe, lo, hi) if kind is int else
             check_real(name, probe, lo, hi, lo_open=lo_open, hi_open=hi_open))
        except ValueError as words:
            head = str(words).rsplit(", got ", 1)[0]
        raise ValueError(f"{head}, got {text!r}") from exc.__cause__


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


#: Exit code of a command whose standard output was closed early (``... | head -1``): 128 +
#: SIGPIPE, what a shell reports for a command the signal ended.
EXIT_PIPE = 141


def _warning_printer(held):
    """``warnings.showwarning`` of one command: each warning as one line, each text once (a
    summary that computes a metric twice warns once). A warning about the user's input
    (:class:`~xnavlab.core.userfiles.InputWarning`) is printed at once; another library's
    (PINT's notes on a timing model) is held in ``held`` and printed when the command ends,
    unless it ends refused: then the error is its one line (review 35f)."""
    from xnavlab.core.userfiles import InputWarning

    shown = set()

    def show(message, category, filename, lineno, file=None, line=None):
        text = f"xnavlab: warning: {message}"
        if text not in shown:
            shown.add(text)
            if issubclass(category, InputWarning):
                print(text, file=sys.stderr)
            else:
                held.append(text)

    return show


def _stdout_closed(stream=None):
    """After a failed write (a closed pipe, a full device): point the stream's file (default
    the standard output) at the null device, so that the interpreter's last flush of what is
    left in its buffer finds no closed pipe or full disk (a traceback at exit)."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, (sys.stdout if stream is None else stream).fileno())
    except (OSError, ValueError, AttributeError):  # a stream without a file (a test's)
        pass


class StreamError(Exception):
    """A write to the standard output or error that failed (a full device, a closed file):
    its message names the stream, ``standard output: No space left on device``. Not an
    ``OSError``, so that no handler of a file's errors on the way takes it for its own.

    Attributes
    ----------
    stream : file-like or None
        The stream that failed (its file is pointed at the null device when the command ends).
    """

    def __init__(self, message, stream=None):
        super().__init__(message)
        self.stream = stream


class _Guarded:
    """A standard stream (or None: a closed one) whose failed write or flush is a
    :class:`StreamError` naming it; a closed pipe stays a BrokenPipeError (:data:`EXIT_PIPE`)."""

    def __init__(self, stream, name):
        self.stream, self.name = stream, name

    def _call(self, method, *args):
        if self.stream is None:  # Python's stream of a closed file descriptor (>&-)
            raise StreamError(f"{self.name}: {os.strerror(errno.EBADF)} (closed)")
        try:
            return getattr(self.stream, method)(*args)
        except BrokenPipeError:
            raise
        except OSError as exc:
            raise StreamError(f"{self.name}: {exc.strerror or exc}", self.stream) from None

    def write(self, text):
        return self._call("write", text)

    def flush(self):
        return None if self.stream is None else self._call("flush")

    def isatty(self):
        return self.stream is not None and self.stream.isatty()

    def __getattr__(self, name):
        return getattr(self.stream, name)


def _say(text):
    """Print ``text`` on the standard error; a stream that takes nothing (full, closed) is
    passed over: the exit code still tells."""
    try:
        print(text, file=sys.stderr)
    except (StreamError, OSError):
        _stdout_closed(sys.stderr)


def main(argv=None):
    """Entry point; returns the process exit code.

    A :class:`xnavlab.core.userfiles.InputWarning` (about the user's input: part of a file
    left unused, e.g. a corrupt line of a campaign store; a subsystem that gets no
    measurement; an RMS of one record) is printed as one line, ``xnavlab: warning: ...``,
    each text once, also under ``--quiet`` (which silences progress, not warnings about
    inputs). A standard output closed early (``python -m xnavlab reproduce --list | head -1``)
    ends every command quietly with :data:`EXIT_PIPE`, without a traceback. A standard
    stream that takes nothing (``> /dev/full``, ``>&-``) ends the command with one line on the
    standard error (``xnavlab: error: standard output: No space left on device``) and exit
    code 1, ``--help`` too; a usage error keeps its code 2 when its line cannot be printed.
    """
    saved = sys.stdout, sys.stderr
    sys.stdout = _Guarded(sys.stdout, "standard output")
    sys.stderr = _Guarded(sys.stderr, "standard error")
    code = None
    try:
        try:
            code = _main_warned(argv)
        finally:  # --help's SystemExit too: a closed pipe or full device shows here
            sys.stdout.flush()
        return code
    except BrokenPipeError:
        _stdout_closed()
        return EXIT_PIPE
    except StreamError as exc:  # the buffer left is dropped, not flushed again at exit
        if exc.stream is not None:
            _stdout_closed(exc.stream)
        _say(f"xnavlab: error: {exc}")
        return code or 1  # 2 kept for a usage error
    finally:
        sys.stdout, sys.stderr = saved


def _main_warned(argv):
    """:func:`_main`, the warnings printed as one line each (:func:`_warning_printer`)."""
    from xnavlab.core.userfiles import InputWarning

    held = []
    code = None
    try:
        with warnings.catch_warnings():
            warnings.filterwarnings("always", category=InputWarning)
            warnings.showwarning = _warning_printer(held)
            code = _main(argv)
            return code
    finally:
        if code != 2:  # a refused command: its error is the one line
            for text in held:  # a standard error that takes none: exit code 1 (main)
                print(text, file=sys.stderr)


#: A negative number argparse takes for an option (it knows -1 and -0.5 only): -1e-3, -1.,
#: -inf, -nan.
_NEGATIVE = re.compile(r"^-((\d+\.?\d*|\.\d+)[eE][-+]?\d+|\d+\.|inf|infinity|nan)$", re.IGNORECASE)


def join_negative_values(argv):
    """``--days -1e-3`` as ``--days=-1e-3``: argparse reads a negative number with an exponent
    as an unknown option ("expected one argument", the value not shown); joined, it reaches
    the option's own range check.

    Examples
    --------
    >>> join_negative_values(["run", "mars", "--days", "-1e-3", "--seed", "-1"])
    ['run', 'mars', '--days=-1e-3', '--seed', '-1']
    """
    out = []
    for tok in argv:
        if out and _NEGATIVE.match(tok) and out[-1].startswith("--") and "=" not in out[-1]:
            out[-1] = f"{out[-1]}={tok}"
        else:
            out.append(tok)
    return out


def _main(argv):
    try:
        argv = join_negative_values(sys.argv[1:] if argv is None else list(argv))
        args = build_parser().parse_args(argv)
        if args.version:
            if argv != ["--version"]:  # the rest would be dropped without a word
                raise UsageError(f"--version is given alone (python -m xnavlab --version), got "
                                 f"also {' '.join(a for a in argv if a != '--version')!r}")
            print(f"xnavlab {__version__}")
            return 0
        if args.command is None:
            raise UsageError("a command is required: " + ", ".join(COMMANDS))
        return args.execute(args)
    except (UsageError, ValueError) as exc:
        _say(f"xnavlab: error: {exc}")
        return 2
    except RuntimeError as exc:  # the compiled filter's stop on a covariance, in one line
        from xnavlab.mars.kernel.kernels import FilterDivergence

        if not isinstance(exc, FilterDivergence):
            raise
        _say(f"xnavlab: error: {exc}")
        return 1
