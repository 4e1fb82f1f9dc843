"""Find visible code that uses a name defined only in a hidden cell of a chapter.

A chapter's bookkeeping (glue, asserts, registry calls) sits in cells the page does not show
(tag ``remove-cell`` or ``remove-input``, or ``"jupyter": {"source_hidden": true}`` in
JupyterLab). A reader who copies the visible code must still be able to run it, so a visible
cell must not use a name that only a hidden cell defines. This tool walks a notebook's code
cells in order, parses each with :mod:`ast` (IPython magics are first turned into Python) and
reports a visible cell that loads a name

* whose first binding in the notebook was in a hidden cell,
* that no visible cell before it binds (a reader who copied those has the name), and
* that the visible cell does not bind itself,

one line per name and cell::

    book/12_fuzzy_parity.ipynb:cell 4: traj (first bound in hidden cell 2)

``cell N`` is ``nb["cells"][N]`` (counted from 0, markdown cells included), as in
``tools/typed_numbers.py``. Scopes are Python's: function arguments, names a function assigns,
comprehension variables, lambda arguments and class bodies are local and not loads of the
notebook's globals; a name a function loads but does not bind is a load (the function reads
it when it runs). Builtins and the names IPython puts in the namespace (``get_ipython``,
``display``, ``In``, ``Out``, ``_``, ``_i3``...) are never reported.

Usage (from the repository root)::

    .venv/bin/python tools/hidden_names.py                        # every book/NN_*.ipynb
    .venv/bin/python tools/hidden_names.py book/12_fuzzy_parity.ipynb

Exit status: 0 nothing found, 1 some finding, 2 a bad argument or a cell that does not parse.

Examples
--------
>>> sorted(global_loads("y = [x * k for k in range(3)]\\ndef f(a):\\n    return a + z"))
['range', 'x', 'z']
>>> sorted(global_binds("import numpy as np\\nfrom os import path as p\\nfor i in []: pass"))
['i', 'np', 'p']
"""

from __future__ import annotations

import ast
import builtins
import json
import re
import sys
from dataclasses import dataclass
from pathlib import Path

from chapter_files import ROOT, chosen, notebook_parser

#: cell tags that keep a cell's source off the built page
HIDDEN_TAGS = frozenset({"remove-cell", "remove-input"})

#: names IPython defines in a notebook's namespace (besides the builtins)
IPYTHON_NAMES = frozenset({
    "get_ipython", "display", "In", "Out", "exit", "quit", "_", "__", "___",
    "_i", "_ii", "_iii", "_ih", "_oh", "_dh",
})
_IPYTHON_NUMBERED = re.compile(r"_i?\d+$")
ALWAYS_DEFINED = frozenset(dir(builtins)) | IPYTHON_NAMES

_SCOPES = (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef,
           ast.ListComp, ast.SetComp, ast.DictComp, ast.GeneratorExp)
_COMPREHENSIONS = (ast.ListComp, ast.SetComp, ast.DictComp, ast.GeneratorExp)


@dataclass(frozen=True)
class Finding:
    """A visible cell that loads a name first bound in a hidden cell."""

    path: str
    cell: int
    name: str
    hidden_cell: int

    def __str__(self):
        return f"{self.path}:cell {self.cell}: {self.name} (first bound in hidden cell {self.hidden_cell})"


def _python_source(source):
    """The cell's source with IPython magics and shell escapes turned into Python calls."""
    try:
        from IPython.core.inputtransformer2 import TransformerManager
    except ImportError:  # pragma: no cover - IPython is a dependency of the book
        lines = [("pass" if ln.lstrip().startswith(("%", "!")) else ln) for ln in source.splitlines()]
        return "\n".join(lines)
    return TransformerManager().transform_cell(source)


def _outer_inputs(node):
    """The parts of a scope-making node that run in the enclosing scope."""
    if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
        a = node.args
        out = list(a.defaults) + [d for d in a.kw_defaults if d is not None]
        if not isinstance(node, ast.Lambda):
            out += node.decorator_list
            out += [x.annotation for x in (*a.posonlyargs, *a.args, *a.kwonlyargs,
                                           a.vararg, a.kwarg) if x is not None and x.annotation]
            out += [node.returns] if node.returns else []
        return out
    if isinstance(node, ast.ClassDef):
        return [*node.decorator_list, *node.bases, *(k.value for k in node.keywords)]
    return [node.generators[0].iter]  # a comprehension's first iterable


def _inner_parts(node):
    """The parts of a scope-making node that run in its own scope."""
    if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
        return list(node.body)
    if isinstance(node, ast.Lambda):
        return [node.body]
    gens = node.generators
    parts = [gens[0].target, *gens[0].ifs]
    for g in gens[1:]:
        parts += [g.iter, g.target, *g.ifs]
    if isinstance(node, ast.DictComp):
        return parts + [node.key, node.value]
    return parts + [node.elt]


def _params(node):
    if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
        a = node.args
        return {x.arg for x in (*a.posonlyargs, *a.args, *a.kwonlyargs, a.vararg, a.kwarg) if x}
    return set()


def _walk_scope(parts):
    """Every node of one scope: nested scopes are yielded but not entered (their outer parts are)."""
    stack = list(reversed(parts))
    while stack:
        node = stack.pop()
        yield node
        if isinstance(node, _SCOPES):
            stack.extend(reversed(_outer_inputs(node)))
        else:
            stack.extend(reversed(list(ast.iter_child_nodes(node))))


def _bindings(parts):
    """(names bound locally in one scope, globals it assigns, names it declares nonlocal)."""
    bound, declared_global, declared_nonlocal = set(), set(), set()
    for node in _walk_scope(parts):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            bound.add(node.name)
        elif isinstance(node, _COMPREHENSIONS):
            # an assignment expression in a comprehension binds in the enclosing scope
            for inner in ast.walk(node):
                if isinstance(inner, ast.NamedExpr):
                    bound.add(inner.target.id)
        elif isinstance(node, ast.Name) and isinstance(node.ctx, (ast.Store, ast.Del)):
            bound.add(node.id)
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            bound.update((a.asname or a.name.split(".")[0]) for a in node.names if a.name != "*")
        elif isinstance(node, ast.ExceptHandler) and node.name:
            bound.add(node.name)
        elif isinstance(node, (ast.MatchAs, ast.MatchStar)) and node.name:
            bound.add(node.name)
        elif isinstance(node, ast.MatchMapping) and node.rest:
            bound.add(node.rest)
        elif isinstance(node, ast.Global):
            declared_global.update(node.names)
        elif isinstance(node, ast.Nonlocal):
            declared_nonlocal.update(node.names)
    # a global declaration binds the notebook's name only where the scope assigns it
    return bound - declared_global - declared_nonlocal, declared_global & bound, declared_nonlocal


def _declared_global(parts):
    return {name for node in _walk_scope(parts) if isinstance(node, ast.Global) for name in node.names}


def _analyse(tree):
    """(global loads, global binds) of a parsed cell."""
    loads, binds = set(), set()

    def visit(parts, params, enclosing, kind):
        # kind: "module", "function" (also lambdas and comprehensions) or "class";
        # enclosing: the non-module scopes around this one, innermost last, as (names, is_class)
        bound, assigned_global, _ = _bindings(parts)
        declared_global = _declared_global(parts)
        if kind == "module":
            binds.update(bound | assigned_global)
            own = set()  # at the top of a cell every name is a global of the notebook
        else:
            binds.update(assigned_global)
            own = bound | params
        closures = [names for names, is_class in enclosing if not is_class]
        inner_enclosing = enclosing if kind == "module" else enclosing + [(own, kind == "class")]
        for node in _walk_scope(parts):
            if isinstance(node, _SCOPES):
                inner_kind = "class" if isinstance(node, ast.ClassDef) else "function"
                visit(_inner_parts(node), _params(node), inner_enclosing, inner_kind)
            elif isinstance(node, ast.Name) and isinstance(node.ctx, (ast.Load, ast.Del)):
                name = node.id
                if kind == "module" or name in declared_global:
                    loads.add(name)
                elif name not in own and not any(name in names for names in closures):
                    loads.add(name)

    visit(list(tree.body), set(), [], "module")
    return loads, binds


def _parse(source):
    return ast.parse(_python_source(source))


def global_loads(source):
    """Names a cell's code reads from the notebook's global namespace (builtins included)."""
    return _analyse(_parse(source))[0]


def global_binds(source):
    """Names a cell's code binds in the notebook's global namespace."""
    return _analyse(_parse(source))[1]


def is_hidden(cell):
    """True when the built page (or JupyterLab) does not show the cell's source."""
    meta = cell.get("metadata", {})
    tags = set(meta.get("tags", []))
    return bool(tags & HIDDEN_TAGS) or bool(meta.get("jupyter", {}).get("source_hidden"))


def _source(cell):
    src = cell.get("source", "")
    return "".join(src) if isinstance(src, list) else src


def check_cells(cells, path="<notebook>"):
    """Findings for a notebook's cell list (``nb["cells"]``), in cell order."""
    first_hidden = {}  # name -> index of the hidden cell that bound it first
    in_sight = set()   # names some visible cell has bound
    findings = []
    for index, cell in enumerate(cells):
        if cell.get("cell_type") != "code":
            continue
        try:
            loads, binds = _analyse(_parse(_source(cell)))
        except SyntaxError as exc:
            raise SyntaxError(f"{path}:cell {index}: {exc.msg}") from exc
        hidden = is_hidden(cell)
        if not hidden:
            for name in sorted(loads - binds):
                if name in first_hidden and name not in in_sight and not _always_defined(name):
                    findings.append(Finding(str(path), index, name, first_hidden[name]))
        if hidden:
            for name in binds - in_sight:
                first_hidden.setdefault(name, index)
        else:
            in_sight |= binds
    return findings


def _always_defined(name):
    return name in ALWAYS_DEFINED or bool(_IPYTHON_NUMBERED.match(name))


def check(path):
    """Findings for one notebook file."""
    nb = json.loads(Path(path).read_text(encoding="utf-8"))
    return check_cells(nb.get("cells", []), _shown(path))


def _shown(path):
    path = Path(path).resolve()
    try:
        return path.relative_to(ROOT).as_posix()
    except ValueError:
        return str(path)


def main(argv=None):
    ap = notebook_parser(__doc__.splitlines()[0], "notebooks to check (default: every book/NN_*.ipynb)")
    args = ap.parse_args(argv)
    paths = chosen("hidden_names", args.notebooks)
    if paths is None:
        return 2
    findings = []
    for path in paths:
        try:
            findings += check(path)
        except SyntaxError as exc:
            print(f"hidden_names: {exc}", file=sys.stderr)
            return 2
    for f in findings:
        print(f)
    print(f"hidden_names: {len(findings)} name(s) defined only in hidden cells, "
          f"in {len({f.path for f in findings})} of {len(paths)} notebook(s)"
          if findings else f"hidden_names: {len(paths)} notebook(s) clean")
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
