"""Every numeric input is used or refused (issue 35): huge values in the public examples.

Each doctest example of a public function or class (``__all__`` of every public module of
``SUBPACKAGES`` in ``tests/example_calls.py``, which this test shares with
``tests/test_edge_inputs.py``) that calls it with numeric literal arguments is run again once per literal,
that literal replaced by a huge value (``1e308`` for a float, ``10**30`` for an int, keyword or
positional, its sign kept). The call passes when it raises a ``ValueError`` naming the parameter
(``check_real``'s "name must be a real number in [lo, hi]") or returns a result whose numbers
(scalars, arrays, tuple, list, dict and dataclass fields, a few levels deep) are finite; every
warning is an error, so an overflow or invalid value inside numpy fails it, as does any other
exception (``OverflowError``, ``MemoryError``).

Guards: every example is tried, the slow ones too (they take 0.2-1.7 s unmodified: whole
simulations whose huge inputs found overflows the fast ones did not); which cases run is
decided by the examples, not by a timing. Each huge call is stopped after ``LIMIT_S`` (20 s) by
an alarm (an endless loop fails, it does not hang) and may allocate at most ``HEADROOM`` (2 GiB)
more address space (a huge allocation fails with ``MemoryError``). :data:`SKIP` lists
calls that cannot be bounded, each with its reason.

Runtime (quiet machine, ``pytest -p no:randomly tests/test_huge_inputs.py``): about 30 s for
362 cases; 16 skip because the example's own call is a refusal.
"""

import ast

import pytest
from example_calls import (
    example_calls,
    finite,
    names_one,
    outcome,
    parameter_names,
    public_doctests,
    state,
    unmodified,
)

HUGE_FLOAT = 1e308
HUGE_INT = 10**30

#: ``test name:parameter`` -> why that substitution is not tried.
SKIP: dict[str, str] = {}

#: ``test name`` -> why an infinite result of a huge argument is the right answer.
ALLOW_INFINITE = {
    "xnavlab.core.detection.online.Detection.first_onset_after": "inf: no event after t0 (documented)",
}


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
    for i, node in example_calls(test):
        for j, arg in enumerate(node.args):
            if _literal(arg):
                yield i, node, j
        for kw in node.keywords:
            if kw.arg and _literal(kw.value):
                yield i, node, kw.arg


def _cases():
    out = []
    for test in public_doctests():
        for i, node, slot in _calls(test):
            lineno = (test.lineno or 0) + test.examples[i].lineno + 1
            ident = f"{test.name}:{lineno}:{slot}"
            if ident not in {p.id for p in out}:
                out.append(pytest.param(test, i, node, slot, id=ident))
    return out


CASES = _cases()


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


def test_the_examples_are_collected():
    names = {p.id.split(":")[0] for p in CASES}
    assert len(CASES) > 100
    assert "xnavlab.mars.timing.toa.parallax" in names


@pytest.mark.parametrize(("test", "i", "node", "slot"), CASES)
def test_a_huge_literal_is_used_or_refused(test, i, node, slot):
    ident = f"{test.name}:{slot}"
    if ident in SKIP:
        pytest.skip(SKIP[ident])
    base = unmodified(test, i, node)
    if base is None:
        pytest.skip("the unmodified call raises (an example of a refusal)")
    globs = state(test, i, node)
    call = _huge(node, slot)
    source = ast.unparse(call)
    err, result = outcome(call, globs, None, base)
    if isinstance(err, ValueError):
        names = parameter_names(node, globs)
        assert names_one(str(err), names), f"{source}: the ValueError names none of {sorted(names)}: {err}"
        return
    if err is not None:
        pytest.fail(f"{source}: {type(err).__name__}: {err}"[:500])
    if finite(base[1]) and test.name not in ALLOW_INFINITE:
        assert finite(result), f"{source}: a non-finite result"
