"""The public examples as calls a test can run again with other arguments (issue 35).

Shared by ``tests/test_huge_inputs.py`` (each numeric literal replaced by a huge value) and
``tests/test_edge_inputs.py`` (each argument replaced by an edge value: a bool, an empty or
one-element list, a 0-d array, zero, a subnormal...). Both take the doctest examples of every
public function and class (``__all__`` of every public module of :data:`SUBPACKAGES`) and the
calls in them of the function the docstring documents; they judge a changed call the same way:
a ``ValueError`` naming the parameter, or a result whose numbers are finite, with every warning
an error, each call stopped after :data:`LIMIT_S` and given at most :data:`HEADROOM` more bytes.
"""

import ast
import contextlib
import dataclasses
import doctest
import functools
import importlib
import inspect
import io
import math
import numbers
import pkgutil
import re
import resource
import signal
import time
import warnings

import matplotlib.pyplot as plt
import numpy as np

__all__ = [
    "SUBPACKAGES",
    "LIMIT_S",
    "HEADROOM",
    "Endless",
    "public_doctests",
    "example_calls",
    "state",
    "evaluate",
    "unmodified",
    "parameter_names",
    "names_one",
    "first_name",
    "finite",
    "bounded",
    "outcome",
    "PLUMBING",
    "plumbing",
]

#: The subpackages (and top-level modules) whose public examples are tried.
SUBPACKAGES = (
    "core",
    "mars.timing",
    "mars.models",
    "mars.faults",
    "mars.navigation",
    "mars.studies",
    "robust",
    "attitude",
    "plins",
    "line",
    "reproduce",
    "verdicts",
)
#: Module -> why its functions are not tried: the package's own plumbing, whose callers are
#: xnavlab's functions, chapters and CLI, which hand it values they have checked (a user's
#: value reaches it only through a public function tried here, or through the CLI, whose
#: grammar and files ``tests/cli`` tries).
PLUMBING = {
    "xnavlab.core.validate": "the checks themselves: name, lo, hi are the package's literals",
    "xnavlab.core.diskcache": "the result cache: keys and paths the package builds",
    "xnavlab.core.userfiles": "the CLI's file reader: argparse hands it text (tests/cli)",
    "xnavlab.core.prose": "the book's number formatting: the chapters' own glue",
    "xnavlab.core.plotting": "the book's tables and figure helpers: the chapters' own calls",
    "xnavlab.core.widgets": "the sliders' plumbing: the chapters' own calls",
    "xnavlab.core.campaign": "the campaign engine: tasks and records the package builds",
    "xnavlab.core.campaign_records": "the records reader: tests/core/test_campaign_records.py",
    "xnavlab.mars.navigation.unused_inputs": "the run's notes on settings, from checked settings",
    "xnavlab.mars.navigation.scenario_files": "the scenario-file reader: tests/cli and hypothesis",
    "xnavlab.mars.navigation.schematics": "the chapter's schematic texts",
    "xnavlab.mars.timing.pulsar_specs": "the scenario file's pulsar entries: tests/cli",
}

#: A changed call still running after this many seconds fails (an endless loop or huge work):
#: ten times the slowest example's unmodified call, for a loaded machine.
LIMIT_S = 20.0
#: Address space a changed call may add before numpy raises MemoryError.
HEADROOM = 2 * 2**30


def _public_modules():
    for sub in SUBPACKAGES:
        pkg = importlib.import_module(f"xnavlab.{sub}")
        names = [pkg.__name__]
        if hasattr(pkg, "__path__"):  # a subpackage: its modules too (a module is one)
            names += [m.name for m in pkgutil.walk_packages(pkg.__path__, pkg.__name__ + ".")]
        for name in names:
            if not any(p.startswith("_") for p in name.split(".")):
                yield importlib.import_module(name)


def public_doctests():
    """The doctests of every public function and class, each in the module that defines it."""
    finder = doctest.DocTestFinder(exclude_empty=True)
    for module in _public_modules():
        for name in getattr(module, "__all__", ()):
            obj = getattr(module, name)
            if getattr(obj, "__module__", None) != module.__name__:
                continue  # a re-export: tried in its own module
            if inspect.isfunction(obj) or inspect.isclass(obj):
                yield from finder.find(
                    obj, f"{module.__name__}.{name}", module=module, globs=dict(vars(module))
                )


def example_calls(test):
    """(example index, call node) for every call in ``test`` of the callable it documents."""
    fname = test.name.rsplit(".", 1)[-1]
    for i, ex in enumerate(test.examples):
        try:
            tree = ast.parse(ex.source)
        except SyntaxError:
            continue
        for node in ast.walk(tree):
            if not isinstance(node, ast.Call):
                continue
            f = node.func
            if isinstance(f, ast.Name) and f.id == fname or isinstance(f, ast.Attribute) and f.attr == fname:
                yield i, node


@functools.cache
def state(test, i, node=None):
    """The doctest's globals before the call ``node`` of its example ``i``: the examples before
    it run once, then the statements of example ``i`` that end before the call's line (a call
    on the line after ``w = ...`` sees ``w``), and a call inside a comprehension sees the
    comprehension's variable bound to the first item (``[f(n) for n in NAMES]`` sees ``n``)."""
    globs = dict(test.globs, np=np)
    sources = [ex.source for ex in test.examples[:i]]
    tree = ast.parse(test.examples[i].source) if node is not None else None
    if tree is not None:
        sources += [ast.unparse(stmt) for stmt in tree.body if stmt.end_lineno < node.lineno]
    with contextlib.redirect_stdout(io.StringIO()), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for source in sources:
            try:
                exec(compile(source, test.name, "single" if "\n" not in source else "exec"), globs)
            except Exception:
                pass
        if tree is not None:
            _bind_comprehensions(tree, node, globs)
    plt.close("all")
    return globs


def _bind_comprehensions(tree, node, globs):
    """Bind the variable of each comprehension around ``node`` to its first item."""
    where = (node.lineno, node.col_offset)
    for comp in ast.walk(tree):
        if not isinstance(comp, ast.ListComp | ast.SetComp | ast.GeneratorExp | ast.DictComp):
            continue
        if not any(isinstance(n, ast.Call) and (n.lineno, n.col_offset) == where for n in ast.walk(comp)):
            continue
        for gen in comp.generators:
            if isinstance(gen.target, ast.Name):
                try:
                    globs[gen.target.id] = next(iter(evaluate(gen.iter, globs)))
                except Exception:
                    return


def evaluate(node, globs, extra=None):
    """The value of the expression ``node`` in a copy of ``globs`` (plus ``extra``)."""
    return eval(compile(ast.Expression(node), "<example>", "eval"), dict(globs, **(extra or {})))


@functools.cache
def unmodified(test, i, node):
    """(seconds, result, the categories of warning it gives) of the call as the example
    writes it; None if it fails."""
    globs = state(test, i, node)
    start = time.perf_counter()
    try:
        with contextlib.redirect_stdout(io.StringIO()), warnings.catch_warnings(record=True) as seen:
            warnings.simplefilter("always")
            result = evaluate(node, globs)
    except Exception:
        return None
    finally:
        plt.close("all")
    own = tuple({w.category for w in seen if not issubclass(w.category, RuntimeWarning)})
    return time.perf_counter() - start, result, own


def parameter_names(node, globs):
    """Names a refusal of this call may give: the callable's parameters, the call's keywords
    (a setting passed on by ``**kwargs``) and its text arguments (the name a ``check_*``
    helper is told to use)."""
    params = set(inspect.signature(evaluate(node.func, globs)).parameters)
    text = {a.value for a in node.args if isinstance(a, ast.Constant) and isinstance(a.value, str)}
    return params | text | {k.arg for k in node.keywords if k.arg}


def _pattern(name):
    return rf"(?<![\w.]){re.escape(name)}(?!\w)"


def names_one(message, names):
    """Whether ``message`` names one of ``names`` (a whole word)."""
    return any(re.search(_pattern(n), message) for n in names)


def first_name(message, names):
    """The one of ``names`` that ``message`` names first (None if it names none)."""
    found = [(m.start(), n) for n in names for m in [re.search(_pattern(n), message)] if m]
    return min(found)[1] if found else None


def finite(x, depth=0):
    """Whether every number in ``x`` is finite (a few levels of containers, cheaply)."""
    if depth > 4 or isinstance(x, bool | str | bytes | type(None)):
        return True
    if isinstance(x, numbers.Number | np.number):
        if isinstance(x, numbers.Integral | np.integer):
            return True
        z = complex(x)
        return math.isfinite(z.real) and math.isfinite(z.imag)
    if isinstance(x, np.ndarray):
        if x.dtype.kind in "fc":
            return bool(np.all(np.isfinite(x)))
        if x.dtype.kind == "O":
            return all(finite(v, depth + 1) for v in x.ravel()[:200])
        return True
    if dataclasses.is_dataclass(x) and not isinstance(x, type):
        return all(finite(getattr(x, f.name), depth + 1) for f in dataclasses.fields(x))
    if isinstance(x, tuple | list):
        return all(finite(v, depth + 1) for v in x[:200])
    if isinstance(x, dict):
        return all(finite(v, depth + 1) for v in list(x.values())[:200])
    return True


class Endless(Exception):
    """A changed call ran past LIMIT_S."""


@contextlib.contextmanager
def bounded():
    """Stop the call after LIMIT_S and cap its extra address space at HEADROOM."""

    def alarm(signum, frame):
        raise Endless(f"still running after {LIMIT_S} s")

    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    with open("/proc/self/statm") as f:
        used = int(f.read().split()[0]) * resource.getpagesize()
    cap = used + HEADROOM if hard == resource.RLIM_INFINITY else min(hard, used + HEADROOM)
    old = signal.signal(signal.SIGALRM, alarm)
    resource.setrlimit(resource.RLIMIT_AS, (cap, hard))
    signal.setitimer(signal.ITIMER_REAL, LIMIT_S)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))
        plt.close("all")


def outcome(call, globs, value, base):
    """``(error, result)`` of the changed ``call`` with ``EDGE = value``: the exception it raised
    (None if it returned) and its result; every warning is an error but the ones the unmodified
    call gives by design (``base[2]``, its output), each call :func:`bounded`."""
    try:
        with bounded(), warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
            warnings.simplefilter("error")
            if base[2]:  # a function that warns by design: its own warnings are its output
                warnings.simplefilter("ignore", base[2])
            return None, evaluate(call, globs, {"EDGE": value})
    except KeyboardInterrupt:
        raise
    except BaseException as err:  # noqa: BLE001 - every other exception is the finding
        return err, None


def plumbing(test):
    """Why the doctest ``test``'s module is not tried (its entry of :data:`PLUMBING`), or ''."""
    module = test.name.rsplit(".", 1)[0]
    return PLUMBING.get(module) or PLUMBING.get(module.rsplit(".", 1)[0], "")
