"""tools/hidden_names.py: visible code never needs a name that only a hidden cell defines."""

import importlib
import json
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
TOOL = ROOT / "tools" / "hidden_names.py"

HIDE = {"tags": ["remove-cell"], "jupyter": {"source_hidden": True}}


@pytest.fixture
def tool(monkeypatch):
    monkeypatch.syspath_prepend(str(TOOL.parent))
    return importlib.import_module("hidden_names")


def _cells(*specs):
    """Cells from ("hidden" | "visible" | "md", source) pairs."""
    cells = []
    for kind, source in specs:
        if kind == "md":
            cells.append({"cell_type": "markdown", "metadata": {}, "source": source})
        else:
            meta = dict(HIDE) if kind == "hidden" else {}
            cells.append({"cell_type": "code", "metadata": meta, "source": source,
                          "outputs": [], "execution_count": None})
    return cells


def _names(tool, *specs):
    return [(f.cell, f.name, f.hidden_cell) for f in tool.check_cells(_cells(*specs))]


def test_a_visible_cell_using_a_hidden_name_is_found(tool):
    found = _names(tool, ("md", "# Title"), ("hidden", "crab = 1.0\nglue('x', crab)"),
                   ("visible", "print(crab * 2)"))
    assert found == [(2, "crab", 1)]


def test_a_name_bound_in_sight_first_is_not_a_finding(tool):
    # bound visibly first, rebound in a hidden cell later: a reader's copy still runs
    assert _names(tool, ("visible", "x = 1"), ("hidden", "x = 2"), ("visible", "print(x)")) == []


def test_a_name_a_visible_cell_rebinds_before_use_is_not_a_finding(tool):
    # hidden first, then rebound in sight: a reader's copy of the visible cells has it
    assert _names(tool, ("hidden", "near = [1]"), ("visible", "near = {'a': 1}"),
                  ("visible", "print(near['a'])")) == []


def test_a_visible_cell_that_binds_the_name_itself_is_not_a_finding(tool):
    assert _names(tool, ("hidden", "n = 3"), ("visible", "n = 10\nprint(n)")) == []


def test_imports_count_as_bindings(tool):
    found = _names(tool, ("hidden", "import numpy as np\nfrom os import path"),
                   ("visible", "np.zeros(3)\npath.join('a')"))
    assert [f[1] for f in found] == ["np", "path"]
    assert _names(tool, ("hidden", "import numpy as np"),
                  ("visible", "import numpy as np\nnp.ones(2)")) == []


def test_function_arguments_and_locals_are_not_global_loads(tool):
    hidden = ("hidden", "a = b = total = 1")
    visible = ("visible", "def f(a, *b, c=2, **kw):\n    total = a + c\n    return total\n"
                          "g = lambda a: a + 1")
    assert _names(tool, hidden, visible) == []


def test_a_function_body_that_reads_a_hidden_global_is_found(tool):
    found = _names(tool, ("hidden", "SCALE = 2"), ("visible", "def f(x):\n    return SCALE * x"))
    assert found == [(1, "SCALE", 0)]


def test_default_values_are_read_where_the_function_is_defined(tool):
    found = _names(tool, ("hidden", "N = 5"), ("visible", "def f(n=N):\n    return n"))
    assert found == [(1, "N", 0)]


def test_comprehension_variables_are_local(tool):
    hidden = ("hidden", "k = 1\nv = 2\nitems = {}")
    visible = ("visible", "a = [k for k in range(3)]\nb = {k: v for k, v in {}.items()}\n"
                          "c = sum(k * j for k in range(2) for j in range(k))")
    assert _names(tool, hidden, visible) == []
    # the first iterable is read outside: a hidden one is found
    assert _names(tool, ("hidden", "items = [1]"),
                  ("visible", "y = [i for i in items]")) == [(1, "items", 0)]


def test_closures_and_class_bodies(tool):
    hidden = ("hidden", "x = 1\nscale = 3")
    closure = ("visible", "def outer():\n    x = 2\n    def inner():\n        return x\n"
                          "    return inner")
    assert _names(tool, hidden, closure) == []
    # a method does not see its class body's names: it reads the global
    klass = ("visible", "class C:\n    scale = 2\n    def f(self):\n        return scale")
    assert _names(tool, hidden, klass) == [(1, "scale", 0)]


def test_global_declarations_bind_and_load_the_notebook_name(tool):
    assert _names(tool, ("hidden", "count = 0"),
                  ("visible", "def show():\n    global count\n    return count")) == [(1, "count", 0)]
    # a cell whose function assigns the global binds it itself
    assert _names(tool, ("hidden", "count = 0"),
                  ("visible", "def bump():\n    global count\n    count += 1")) == []
    assert sorted(tool.global_binds("def f():\n    global g\n    g = 1")) == ["f", "g"]


def test_builtins_and_ipython_names_are_never_findings(tool):
    hidden = ("hidden", "len = 0\ndisplay = print\n_ = 1\nIn = []\n_i3 = ''")
    visible = ("visible", "%matplotlib inline\nprint(len([1]))\ndisplay(_)\nIn\n_i3\n"
                          "get_ipython()")
    assert _names(tool, hidden, visible) == []


def test_magics_do_not_break_parsing_and_except_with_match_bind(tool):
    source = ("%matplotlib inline\ntry:\n    pass\nexcept ValueError as err:\n    pass\n"
              "match 1:\n    case [first, *rest]:\n        pass\n    case {'k': 1, **others}:\n"
              "        pass\n")
    assert {"err", "first", "rest", "others"} <= tool.global_binds(source)
    assert "y" in tool.global_binds("if (y := 3):\n    pass\nz = [w := i for i in range(2)]")


def test_remove_input_hides_the_source_too(tool):
    cells = _cells(("visible", "print(q)"))
    shown = {"cell_type": "code", "metadata": {"tags": ["remove-input"]}, "source": "q = 1",
             "outputs": [], "execution_count": None}
    assert [f.name for f in tool.check_cells([shown] + cells)] == ["q"]


def test_cli_prints_one_line_per_finding_and_exits_1(tool, tmp_path, capsys):
    nb = {"cells": _cells(("hidden", "traj = 1"), ("visible", "traj + 1")), "metadata": {},
          "nbformat": 4, "nbformat_minor": 5}
    path = tmp_path / "12_x.ipynb"
    path.write_text(json.dumps(nb))
    assert tool.main([str(path)]) == 1
    out = capsys.readouterr().out.splitlines()
    assert out[0].endswith("12_x.ipynb:cell 1: traj (first bound in hidden cell 0)")
    assert len(out) == 2  # the finding and the summary
    nb["cells"] = _cells(("visible", "traj = 1"), ("visible", "traj + 1"))
    path.write_text(json.dumps(nb))
    assert tool.main([str(path)]) == 0
    assert tool.main([str(tmp_path / "missing.ipynb")]) == 2


@pytest.mark.parametrize("chapter", sorted((ROOT / "book").glob("[0-9][0-9]_*.ipynb")),
                         ids=lambda p: p.name)
def test_every_chapter_defines_in_sight_what_its_visible_code_uses(tool, chapter):
    findings = tool.check(chapter)
    assert not findings, "\n".join(map(str, findings))
