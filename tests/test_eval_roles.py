"""tools/eval_roles.py: a chapter's prose converted to roles JupyterLab and the book both render."""

import importlib
from pathlib import Path

import nbformat
import pytest

TOOL = Path(__file__).resolve().parents[1] / "tools" / "eval_roles.py"


@pytest.fixture
def tool(monkeypatch):
    monkeypatch.syspath_prepend(str(TOOL.parent))
    return importlib.import_module("eval_roles")


def _chapter(folder, cells, name="08_x.ipynb"):
    nb = nbformat.v4.new_notebook()
    for kind, source in cells:
        new = nbformat.v4.new_code_cell if kind == "code" else nbformat.v4.new_markdown_cell
        nb.cells.append(new(source))
    path = folder / name
    nbformat.write(nb, path)
    return path


CHAPTER = [
    ("code", 'import numpy as np\nfrom myst_nb import glue\n\nglue("ch08_rms_m", 44.69, display=False)\n'
             'for k in ("a", "b"):\n    glue(f"ch08_{k}_s", 1.0, display=False)'),
    ("md", "The error is {glue:text}`ch08_rms_m:.1f` m and {glue:text}`ch08_a_s` s, see "
           "{doc}`chapter 7 <07_wavelets>` and {py:func}`~xnavlab.core.filters.ekf_update`, "
           "{py:func}`track.run_line <xnavlab.line.track.run_line>`, {py:mod}`xnavlab.core`, "
           "eq. {eq}`ch8-x` and {cite}`fan2016wavelet`."),
    ("md", "```{exercise}\n:label: ch08-ex1\n\nWhy {glue:text}`ch08_b_s:.0f` s?\n```"),
]


def test_a_chapter_is_converted_and_then_checks_clean(tool, tmp_path, capsys):
    (tmp_path / "07_wavelets.ipynb").write_text("{}")
    path = _chapter(tmp_path, CHAPTER)
    assert tool.check(path)  # not converted yet
    assert tool.main([str(path)]) == 0
    out = capsys.readouterr().out
    assert "08_x.ipynb: 1 doc, 3 glue:text, 1 import, 3 py" in out and "left:" not in out
    nb = nbformat.read(path, as_version=4)
    assert tool.IMPORT_NEW + "\n" in nb.cells[0].source
    assert 'glue("ch08_rms_m", 44.69, display=False)' in nb.cells[0].source  # the calls stay
    assert nb.cells[1].source == (
        'The error is {eval}`glued["ch08_rms_m:.1f"]` m and {eval}`glued["ch08_a_s"]` s, see '
        "[chapter 7](07_wavelets.ipynb) and [`ekf_update`](#xnavlab.core.filters.ekf_update), "
        "[`track.run_line`](#xnavlab.line.track.run_line), [`xnavlab.core`](#xnavlab.core), "
        "eq. {eq}`ch8-x` and {cite}`fan2016wavelet`.")
    assert 'Why {eval}`glued["ch08_b_s:.0f"]` s?' in nb.cells[2].source
    assert tool.check(path) == []
    assert tool.main(["--check", str(path)]) == 0
    assert tool.main([str(path)]) == 0  # converting again changes nothing
    assert "nothing to convert" in capsys.readouterr().out


@pytest.mark.parametrize(("cells", "problem"), [
    ([("code", "from myst_nb import glue")], "imports myst_nb"),
    ([("code", "from xnavlab.core.prose import glue, glued\nglued = 3")], "assigns the name `glued`"),
    ([("code", "x = 1"), ("md", '{eval}`glued["ch08_x"]`')], "no `from xnavlab.core.prose import"),
    ([("code", "from xnavlab.core.prose import glue, glued\nx = 1"), ("md", "{eval}`x`")],
     "is not evaluated by the book"),
    ([("md", "{glue:md}`ch08_table`")], "JupyterLab cannot show it"),
    ([("md", "see {doc}`07_wavelets`")], "write [text](NN_chapter.ipynb)"),
    ([("md", "see [chapter 9](09_nowhere.ipynb)")], "not a file of book/"),
    ([("md", "{py:class}`xnavlab.core.filters.EKF`")], "[`xnavlab.core.filters.EKF`](#xnavlab"),
])
def test_check_names_what_is_not_converted(tool, tmp_path, capsys, cells, problem):
    path = _chapter(tmp_path, cells)
    assert any(problem in p for p in tool.check(path)), tool.check(path)
    assert tool.main(["--check", str(path)]) == 1
    assert problem in capsys.readouterr().out


def test_saved_user_expressions_are_flagged_and_removed(tool, tmp_path):
    path = _chapter(tmp_path, [("md", "text")])
    nb = nbformat.read(path, as_version=4)
    nb.cells[0].metadata["user_expressions"] = [{"expression": "x", "result": {}}]
    nbformat.write(nb, path)
    assert "user_expressions" in tool.check(path)[0]
    assert tool.convert(path) == {"user_expressions": 1}
    assert tool.check(path) == []


def test_a_name_the_code_never_spells_is_a_note_not_a_problem(tool, tmp_path):
    path = _chapter(tmp_path, [
        ("code", 'from xnavlab.core.prose import glue, glued\nkey = "ch08_range_" + "x"\n'
                 'glue(key, 1.0)'),
        ("md", '{eval}`glued["ch08_range_x:.0f"]` and {eval}`glued["ch08_typo"]`'),
    ])
    notes = []
    assert tool.check(path, notes) == []
    assert len(notes) == 1 and "'ch08_typo'" in notes[0]


def test_a_bad_argument_exits_2(tool, tmp_path):
    assert tool.main([str(tmp_path / "missing.ipynb")]) == 2
