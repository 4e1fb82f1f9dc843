"""Every function of the package takes at most 20 parameters.

A longer signature is a call whose arguments are matched by position alone; the kernels group
theirs into named containers (:mod:`xnavlab.mars.kernel.kernel_inputs`) instead.
"""

import ast
from pathlib import Path

import xnavlab

#: The most parameters a function of ``xnavlab/`` may take (positional, keyword-only,
#: ``*args`` and ``**kwargs`` each count one).
MAX_PARAMETERS = 20

PACKAGE = Path(xnavlab.__file__).resolve().parent


def parameter_count(node):
    """Parameters of a ``def`` or ``lambda`` node, ``self`` included."""
    a = node.args
    return (len(a.posonlyargs) + len(a.args) + len(a.kwonlyargs)
            + (a.vararg is not None) + (a.kwarg is not None))


def long_signatures(limit=MAX_PARAMETERS):
    """``module:line name (count)`` of every function of the package over ``limit``."""
    bad = []
    for path in sorted(PACKAGE.rglob("*.py")):
        tree = ast.parse(path.read_text(), filename=str(path))
        for node in ast.walk(tree):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda):
                n = parameter_count(node)
                if n > limit:
                    name = getattr(node, "name", "<lambda>")
                    bad.append(f"{path.relative_to(PACKAGE.parent)}:{node.lineno} {name} ({n})")
    return bad


def test_parameter_count_counts_every_kind():
    """Positional-only, positional, keyword-only, *args and **kwargs each count one."""
    node = ast.parse("def f(a, /, b, c=1, *args, d, e=2, **kw): pass").body[0]
    assert parameter_count(node) == 7


def test_a_long_signature_is_found():
    """A function with 21 parameters in the walked text is reported by name and count."""
    src = "def g(" + ", ".join(f"p{i}" for i in range(21)) + "): pass"
    node = ast.parse(src).body[0]
    assert parameter_count(node) == 21 > MAX_PARAMETERS


def test_no_function_takes_more_than_20_parameters():
    """No function or method of ``xnavlab/`` has more than 20 parameters."""
    bad = long_signatures()
    assert not bad, "functions with more than 20 parameters:\n" + "\n".join(bad)
