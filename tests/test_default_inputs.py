"""Every input is used or refused (issue 35): the parameters the public examples leave out.

``tests/test_edge_inputs.py`` and ``tests/test_huge_inputs.py`` change the arguments a doctest
example writes. A parameter the example leaves at its default (``t0``, ``seed``, ``residual``,
``ax``, ``ylim``, ``dof`` ...) was never tried there, and review 35k found most of its raw
exceptions among them. Here each example call of a public function or class is run again with
one parameter it leaves out given, in turn, each of :func:`odd_values` of its default's kind:
a value of the wrong kind (None, a bool, a string, a number where a text goes) and, for a
number, NaN. A changed call passes when

* it raises a ``ValueError`` that names the added parameter before any other parameter of the
  call, or
* it returns a result whose numbers are finite, with no warning, and the value was not a bool
  given where a number goes (a bool is never a count or a length).

A ``TypeError``, ``AttributeError`` or ``IndexError`` from inside, numpy's message, a warning or
a NaN fails. The examples in :data:`SLOW` (an unmodified call of a second or more, measured
once and written down: the choice never depends on this machine's speed) are passed over, their
parameters tried by their own tests; the rest cost about a minute of CPU.
"""

import ast
import inspect
import math

import pytest
from example_calls import (
    evaluate,
    example_calls,
    finite,
    first_name,
    outcome,
    parameter_names,
    plumbing,
    public_doctests,
    state,
    unmodified,
)

#: Examples whose unmodified call takes a second or more (measured on a quiet 2-core machine,
#: 2026-11-29; ten changed calls per parameter would take minutes): their own tests try them.
SLOW = {
    "xnavlab.mars.timing.pint_bridge": "PINT's timing models and photon files (80 s, 64 s, 17 s)",
    "xnavlab.mars.models.dynamics.chapter_truths": "eight 30-day truths (43 s)",
    "xnavlab.core.detection.combined": "the compiled CUSUM and wavelet designs (4-11 s)",
    "xnavlab.core.detection.batch.wavelet_detect": "a day of samples (7 s)",
    "xnavlab.mars.timing.photon_error.split_pulls": "a photon Monte Carlo (10 s)",
    "xnavlab.mars.timing.photon_plots.plot_fix": "a photon fix (2.6 s)",
    "xnavlab.mars.timing.photon_fix.build_reference": "a photon template (2.5 s)",
    "xnavlab.core.montecarlo.plot_pd": "a Monte Carlo of detections (2.3 s)",
    "xnavlab.core.montecarlo.plot_pd_error": "a Monte Carlo of detections (2.0 s)",
    "xnavlab.mars.timing.fold_toa.window_survey": "17 folded windows (1.8 s)",
    "xnavlab.mars.timing.fold_toa.fold_window": "a folded window (1.8 s)",
    "xnavlab.mars.models.dynamics.plot_model_difference": "a changed call propagates 30-day "
    "orbits afresh (46 s in all)",
    "xnavlab.mars.timing.toa.plot_orbit_terms": "a changed call computes a day's delays afresh "
    "(24 s in all)",
    "xnavlab.reproduce.run": "a whole reproduction (0.1 s cached, up to minutes afresh; out='x' "
    "would write its figures into the working folder): tests/test_reproduce.py tries out, fresh "
    "and the keywords",
}

#: ``test name:parameter`` -> why a refusal of an odd value of it names another parameter first.
JOINT = {
    "xnavlab.mars.timing.pulsars.from_par:width_s": "duty_cycle and width_s give the same pulse "
    "width: the conflict names both, duty_cycle (the example's) first",
}

#: ``test name:parameter`` -> why it is not tried.
SKIP = {}


def odd_values(default):
    """(label, value) pairs of the wrong kind for a parameter whose default is ``default``."""
    if isinstance(default, bool):
        return [("None", None), ("'yes'", "yes"), ("2", 2)]
    if isinstance(default, int | float):
        out = [("True", True), ("None", None), ("'1.0'", "1.0")]
        return out + ([("nan", math.nan)] if isinstance(default, float) else [("2.5", 2.5)])
    if default is None:
        return [("'x'", "x"), ("{}", {}), ("nan", math.nan)]
    if isinstance(default, str):
        return [("None", None), ("3", 3)]
    if isinstance(default, tuple | list):
        return [("None", None), ("3.0", 3.0)]
    return []


def _cases():
    out, seen = [], set()
    for test in public_doctests():
        for i, node in example_calls(test):
            func = ast.unparse(node.func)
            if (test.name, func) in seen:  # one call per function and docstring: the cost
                continue
            seen.add((test.name, func))
            lineno = (test.lineno or 0) + test.examples[i].lineno + 1
            out.append(pytest.param(test, i, node, id=f"{test.name}:{lineno}"))
    return out


CASES = _cases()


def _omitted(node, globs):
    """The parameters (inspect.Parameter) with a default that the call ``node`` leaves out."""
    params = list(inspect.signature(evaluate(node.func, globs)).parameters.values())
    fixed = [p for p in params if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
    given = {p.name for p in fixed[:len(node.args)]} | {k.arg for k in node.keywords}
    return [p for p in params if p.name not in given and p.default is not p.empty
            and p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)]


def _added(node, name):
    """A copy of the call with ``name=EDGE`` added."""
    new = ast.parse(ast.unparse(node), mode="eval").body
    new.keywords.append(ast.keyword(arg=name, value=ast.Name("EDGE", ast.Load())))
    return ast.fix_missing_locations(new)


def _judge(call, globs, label, value, base, name, names, key):
    """None if the call with ``name=value`` added is used or refused well, else what went wrong."""
    err, result = outcome(call, globs, value, base)
    if isinstance(err, ValueError):
        lead = first_name(str(err), names | {name})
        if lead == name or key in JOINT:
            return None
        return f"{name}={label}: the ValueError leads with {lead!r}: {err}"
    if err is not None:
        return f"{name}={label}: {type(err).__name__}: {err}"
    if label == "True":
        return f"{name}={label}: a bool was taken as a number"
    if finite(base[1]) and not finite(result):
        return f"{name}={label}: a non-finite result"
    return None


def test_the_calls_are_collected():
    assert len(CASES) > 300
    assert any(p.id.startswith("xnavlab.core.filters.ekf_update:") for p in CASES)


@pytest.mark.parametrize(("test", "i", "node"), CASES)
def test_a_parameter_left_at_its_default_is_used_or_refused(test, i, node):
    if plumbing(test):
        pytest.skip(plumbing(test))
    slow = [why for prefix, why in SLOW.items() if test.name == prefix or test.name.startswith(prefix + ".")]
    if slow:
        pytest.skip(slow[0])
    base = unmodified(test, i, node)
    if base is None:
        pytest.skip("the unmodified call raises (an example of a refusal)")
    globs = state(test, i, node)
    names = parameter_names(node, globs)
    problems = []
    for param in _omitted(node, globs):
        key = f"{test.name}:{param.name}"
        if key in SKIP:
            continue
        call = _added(node, param.name)
        problems += [_judge(call, globs, label, value, base, param.name, names, key)
                     for label, value in odd_values(param.default)]
    problems = [p for p in problems if p]
    assert not problems, f"{ast.unparse(node)}:\n" + "\n".join(p[:300] for p in problems)
