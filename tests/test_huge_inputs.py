"""Every numeric input is used or refused (issue 35): huge values in the public examples.

Each doctest example of a public function or class (``__all__`` of every public module of
:data:`SUBPACKAGES`) that calls it with numeric literal arguments is run again once per literal,
that literal replaced by a huge value (``1e308`` for a float, ``10**30`` for an int, keyword or
positional, its sign kept). The call passes when it raises a ``ValueError`` naming the parameter
(``check_real``'s "name must be a real number in [lo, hi]") or returns a result whose numbers
(scalars, arrays, tuple, list, dict and dataclass fields, a few levels deep) are finite; every
warning is an error, so an overflow or invalid value inside numpy fails it, as does any other
exception (``OverflowError``, ``MemoryError``).

Guards: every example is tried, the slow ones too (they take 0.2-1.7 s unmodified: whole
simulations whose huge inputs found overflows the fast ones did not); which cases run is
decided by the examples, not by a timing. Each huge call is stopped after :data:`LIMIT_S` by
an alarm (an endless loop fails, it does not hang) and may allocate at most :data:`HEADROOM`
bytes more address space (a huge allocation fails with ``MemoryError``). :data:`SKIP` lists
calls that cannot be bounded, each with its reason.

Runtime (quiet machine, ``pytest -p no:randomly tests/test_huge_inputs.py``): about 25 s for
358 cases; 14 skip because the example's own call is a refusal.
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
import pytest

#: The subpackages whose public examples are tried.
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
)
HUGE_FLOAT = 1e308
HUGE_INT = 10**30
#: A huge call still running after this many seconds fails (an endless loop or huge work): ten
#: times the slowest example's unmodified call, for a loaded machine.
LIMIT_S = 20.0
#: Address space a huge call may add before numpy raises MemoryError.
HEADROOM = 2 * 2**30

#: ``test name:parameter`` -> why that substitution is not tried.
SKIP: dict[str, str] = {}

#: ``test name`` -> why an infinite result of a huge argument is the right answer.
ALLOW_INFINITE = {
    "xnavlab.core.detection.online.Detection.first_onset_after": "inf: no event after t0 (documented)",
}


def _public_modules():
    for sub in SUBPACKAGES:
        pkg = importlib.import_module(f"xnavlab.{sub}")
        names = [pkg.__name__]
        names += [m.name for m in pkgutil.walk_packages(pkg.__path__, pkg.__name__ + ".")]
        for name in names:
            if not any(p.startswith("_") for p in name.split(".")):
                yield importlib.import_module(name)


def _doctests():
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


def _literal(node):
    """The numeric literal a call argument is (sign kept), else None."""
    sign = 1
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub | ast.UAdd):
        sign = -1 if isinstance(node.op, ast.USub) else 1
        node = node.operand
    if isinstance(node, ast.Constant) and type(node.value) in (int, float):
        return sign, node.value
    return None


def _calls(test):
    """(example index, call node, argument slot) for every literal argument of a call."""
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
            if not (
                isinstance(f, ast.Name) and f.id == fname or isinstance(f, ast.Attribute) and f.attr == fname
            ):
                continue
            for j, arg in enumerate(node.args):
                if _literal(arg):
                    yield i, node, j
            for kw in node.keywords:
                if kw.arg and _literal(kw.value):
                    yield i, node, kw.arg


def _cases():
    out = []
    for test in _doctests():
        for i, node, slot in _calls(test):
            lineno = (test.lineno or 0) + test.examples[i].lineno + 1
            ident = f"{test.name}:{lineno}:{slot}"
            if ident not in {p.id for p in out}:
                out.append(pytest.param(test, i, node, slot, id=ident))
    return out


CASES = _cases()


@functools.cache
def _state(test, i):
    """The doctest's globals before its example ``i`` (the examples before it run once)."""
    globs = dict(test.globs, np=np)
    with contextlib.redirect_stdout(io.StringIO()), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for ex in test.examples[:i]:
            try:
                exec(compile(ex.source, test.name, "single"), globs)
            except Exception:
                pass
    plt.close("all")
    return globs


def _eval(node, globs):
    return eval(compile(ast.Expression(node), "<example>", "eval"), dict(globs))


@functools.cache
def _unmodified(test, i, node):
    """(seconds, result, the categories of warning it gives) of the call as the example
    writes it; None if it fails."""
    globs = _state(test, i)
    start = time.perf_counter()
    try:
        with contextlib.redirect_stdout(io.StringIO()), warnings.catch_warnings(record=True) as seen:
            warnings.simplefilter("always")
            result = _eval(node, globs)
    except Exception:
        return None
    finally:
        plt.close("all")
    own = tuple({w.category for w in seen if not issubclass(w.category, RuntimeWarning)})
    return time.perf_counter() - start, result, own


def _huge(node, slot):
    """A copy of the call with the literal at ``slot`` replaced by a huge value."""
    new = ast.parse(ast.unparse(node), mode="eval").body
    arg = new.args[slot] if isinstance(slot, int) else next(k for k in new.keywords if k.arg == slot)
    sign, value = _literal(arg if isinstance(slot, int) else arg.value)
    big = ast.Constant(sign * (HUGE_INT if isinstance(value, int) else HUGE_FLOAT))
    if isinstance(slot, int):
        new.args[slot] = big
    else:
        arg.value = big
    return ast.fix_missing_locations(new)


def _names(node, globs):
    """Names a refusal of this call may give: the callable's parameters, the call's keywords
    (a setting passed on by ``**kwargs``) and its text arguments (the name a ``check_*``
    helper is told to use)."""
    params = set(inspect.signature(_eval(node.func, globs)).parameters)
    text = {a.value for a in node.args if isinstance(a, ast.Constant) and isinstance(a.value, str)}
    return params | text | {k.arg for k in node.keywords if k.arg}


def _names_one(message, names):
    return any(re.search(rf"(?<![\w.]){re.escape(n)}(?!\w)", message) for n in names)


def finite(x, depth=0):
    """Whether every number in ``x`` is finite (a few levels of containers, cheaply)."""
    if depth > 4 or isinstance(x, bool | str | bytes | type(None)):
        return True
    if isinstance(x, numbers.Number | np.number):
        return cmath_finite(complex(x)) if not isinstance(x, numbers.Integral | np.integer) else True
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


def cmath_finite(z):
    return math.isfinite(z.real) and math.isfinite(z.imag)


class Endless(Exception):
    """A huge call ran past LIMIT_S."""


@contextlib.contextmanager
def _bounded():
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


def test_the_examples_are_collected():
    names = {p.id.split(":")[0] for p in CASES}
    assert len(CASES) > 100
    assert "xnavlab.mars.timing.toa.parallax" in names


@pytest.mark.parametrize(("test", "i", "node", "slot"), CASES)
def test_a_huge_literal_is_used_or_refused(test, i, node, slot):
    ident = f"{test.name}:{slot}"
    if ident in SKIP:
        pytest.skip(SKIP[ident])
    base = _unmodified(test, i, node)
    if base is None:
        pytest.skip("the unmodified call raises (an example of a refusal)")
    globs = _state(test, i)
    call = _huge(node, slot)
    source = ast.unparse(call)
    try:
        with _bounded(), warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
            warnings.simplefilter("error")
            if base[2]:  # a function that warns by design: its own warnings are its output
                warnings.simplefilter("ignore", base[2])
            result = _eval(call, globs)
    except ValueError as err:
        names = _names(node, globs)
        assert _names_one(str(err), names), f"{source}: the ValueError names none of {sorted(names)}: {err}"
        return
    except BaseException as err:
        if isinstance(err, KeyboardInterrupt):
            raise
        pytest.fail(f"{source}: {type(err).__name__}: {err}"[:500])
    if finite(base[1]) and test.name not in ALLOW_INFINITE:
        assert finite(result), f"{source}: a non-finite result"
