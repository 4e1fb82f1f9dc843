"""tools/book_execute.py: the book's notebook pages executed into myst-nb's cache, found there."""

import importlib
import json
import os
from pathlib import Path

import nbformat
import pytest

TOOL = Path(__file__).resolve().parents[1] / "tools" / "book_execute.py"
ROOT = TOOL.parents[1]


@pytest.fixture
def tool(tmp_path, monkeypatch):
    # importable by name: the worker processes find the page runner by its module's name
    monkeypatch.syspath_prepend(str(TOOL.parent))
    mod = importlib.import_module("book_execute")
    monkeypatch.setattr(mod, "ROOT", tmp_path)
    monkeypatch.setattr(mod, "CACHE", tmp_path / "_build" / ".jupyter_cache")
    monkeypatch.setattr(mod, "TIMES", tmp_path / "_build" / "times.json")
    return mod


def _book(root, code):
    (root / "book").mkdir()
    (root / "_toc.yml").write_text("format: jb-book\nroot: book/intro\nchapters:\n"
                                   "  - file: book/one\n  - file: book/notes\n")
    (root / "_config.yml").write_text("execute:\n  timeout: 60\n")
    (root / "book" / "intro.md").write_text("# Intro\n\nNot a notebook.\n")
    (root / "book" / "notes.md").write_text("# Notes\n")
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(code)])
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                 "language": "python"}
    nbformat.write(nb, root / "book" / "one.ipynb")


def test_the_books_own_notebook_pages_are_every_chapter_and_the_dashboard(tool):
    names = [p.name for p in tool.notebook_pages(ROOT)]
    assert "dashboard.md" in names and "bibliography.md" not in names
    assert sum(n.endswith(".ipynb") for n in names) == len(list((ROOT / "book").glob("[0-9][0-9]_*.ipynb")))
    assert tool.default_timeout(ROOT) >= 60


def test_a_page_is_executed_once_and_then_found_in_the_cache(tool, tmp_path, capsys):
    _book(tmp_path, "print(6 * 7)")
    assert [p.name for p in tool.notebook_pages()] == ["one.ipynb"]
    assert tool.main(["--jobs", "1"]) == 0
    with tool.open_cache() as cache:
        record = cache.match_cache_notebook(tool.read_page(tmp_path / "book" / "one.ipynb"))
    assert record.pk >= 1
    assert "one.ipynb" in json.loads(tool.TIMES.read_text())
    assert tool.main(["--jobs", "1"]) == 0
    assert "every page is in the execution cache" in capsys.readouterr().out


def test_a_failing_page_stops_with_its_error_and_is_not_cached(tool, tmp_path, capsys):
    _book(tmp_path, "raise RuntimeError('broken chapter')")
    assert tool.main(["--jobs", "1"]) == 1
    assert "broken chapter" in capsys.readouterr().err
    assert tool.main(["--jobs", "0"]) == 2


def test_each_page_names_its_slowest_cell_and_the_cache_holds_no_timing(tool, tmp_path, capsys):
    _book(tmp_path, "x = 1")
    nb = nbformat.read(tmp_path / "book" / "one.ipynb", as_version=4)
    nb.cells.append(nbformat.v4.new_code_cell("# waits\nimport time\ntime.sleep(0.5)"))
    nbformat.write(nb, tmp_path / "book" / "one.ipynb")
    assert tool.main(["--jobs", "1"]) == 0
    line = next(ln for ln in capsys.readouterr().out.splitlines() if "one.ipynb" in ln)
    assert "slowest: cell 1," in line and "`import time`" in line
    seconds = float(line.split("slowest: cell 1, ")[1].split(" s")[0])
    assert seconds >= 0.5
    with tool.open_cache() as cache:
        record = cache.match_cache_notebook(tool.read_page(tmp_path / "book" / "one.ipynb"))
        cached = cache.get_cache_bundle(record.pk).nb
    assert all("execution" not in cell.metadata for cell in cached.cells)


def test_a_page_is_executed_for_the_html_book(tool, tmp_path, monkeypatch):
    # its kernel draws the sliders' scrubber frames; the calling process is left as it was
    monkeypatch.delenv("XNAVLAB_SCRUBBER_FRAMES", raising=False)
    _book(tmp_path, "import os\nassert os.environ['XNAVLAB_SCRUBBER_FRAMES'] == '1'")
    assert tool.main(["--jobs", "1"]) == 0
    assert "XNAVLAB_SCRUBBER_FRAMES" not in os.environ


@pytest.mark.parametrize(("code", "status"), [("x = 1", 0), ("raise RuntimeError('broken')", 1)])
def test_the_cache_database_is_closed_when_the_run_ends(tool, tmp_path, code, status):
    # jupyter_cache never closes its sqlite connections; left to the garbage collector, each is a
    # ResourceWarning on Python 3.13. Every connection opened during a run is closed at its end.
    import sqlite3

    from sqlalchemy import event
    from sqlalchemy.engine import Engine

    opened = []

    def record(dbapi_connection, _record):
        opened.append(dbapi_connection)

    _book(tmp_path, code)
    event.listen(Engine, "connect", record)
    try:
        assert tool.main(["--jobs", "1"]) == status
    finally:
        event.remove(Engine, "connect", record)
    assert opened
    for connection in opened:
        with pytest.raises(sqlite3.ProgrammingError, match="closed database"):
            connection.execute("select 1")


def _prose_book(root, cells):
    """A book whose one page is ``cells``: ("code", source) and ("md", source) pairs."""
    _book(root, "from xnavlab.core.prose import glue, glued")
    nb = nbformat.read(root / "book" / "one.ipynb", as_version=4)
    for kind, source in cells:
        new = nbformat.v4.new_code_cell if kind == "code" else nbformat.v4.new_markdown_cell
        nb.cells.append(new(source))
    nbformat.write(nb, root / "book" / "one.ipynb")


def _evaluated(tool, root):
    with tool.open_cache() as cache:
        record = cache.match_cache_notebook(tool.read_page(root / "book" / "one.ipynb"))
        return record.data[tool.BOOK_CACHE_KEY]


def test_the_prose_eval_roles_are_evaluated_in_place_and_kept_with_the_page(tool, tmp_path):
    _prose_book(tmp_path, [
        ("code", 'glue("ch99_r_km", 4190.0)\nglue("ch99_v", "REPRODUCED")'),
        ("md", 'A range of {eval}`glued["ch99_r_km:,.0f"]` km: {eval}`glued["ch99_v"]`.'),
        ("code", 'glue("ch99_n", 12)'),
        ("md", '```{exercise}\n:label: ch99-ex1\n\n{eval}`glued["ch99_n:d"]` runs\n```'),
    ])
    assert tool.main(["--jobs", "1"]) == 0
    shown = {expr: res["data"]["text/plain"] for expr, res in _evaluated(tool, tmp_path).items()}
    assert shown == {'glued["ch99_r_km:,.0f"]': "4,190", 'glued["ch99_v"]': "REPRODUCED",
                     'glued["ch99_n:d"]': "12"}


def test_a_page_whose_prose_gained_an_expression_is_executed_again(tool, tmp_path, capsys):
    _prose_book(tmp_path, [("code", 'glue("ch99_a", 1.5)'), ("md", "No number yet.")])
    assert tool.main(["--jobs", "1"]) == 0
    nb = nbformat.read(tmp_path / "book" / "one.ipynb", as_version=4)
    nb.cells[-1].source = 'Now {eval}`glued["ch99_a:.1f"]`.'  # the code, and so its hash, is unchanged
    nbformat.write(nb, tmp_path / "book" / "one.ipynb")
    capsys.readouterr()
    assert tool.main(["--jobs", "1"]) == 0
    assert "book_execute: 1 pages" in capsys.readouterr().out
    assert _evaluated(tool, tmp_path)['glued["ch99_a:.1f"]']["data"]["text/plain"] == "1.5"
    assert tool.main(["--jobs", "1"]) == 0
    assert "every page is in the execution cache" in capsys.readouterr().out


@pytest.mark.parametrize(("cells", "message"), [
    ([("md", 'Too early: {eval}`glued["ch99_late"]`.'), ("code", 'glue("ch99_late", 1)')],
     "raised KeyError"),
    ([("code", "x = 3"), ("md", "Any code: {eval}`x`.")], "is not an entry of the glued table"),
    ([("code", 'glue("ch99_x", 1)'), ("md", '{eval}`glued["ch99_x"]`'), ("code", 'glue("ch99_x", 2)')],
     "after the last cell: a reader's JupyterLab may show either"),
    ([("code", 'glue("ch99_x", 1)'), ("md", '{eval}`glued["ch99_x"]`'), ("code", 'glue("ch99_x", 2)'),
      ("md", 'again {eval}`glued["ch99_x"]`')], "glue each name once"),
    ([("code", 'glue("ch99_x", "text")'), ("md", '{eval}`glued["ch99_x:.1f"]`')],
     "does not format the value"),
])
def test_a_prose_expression_that_cannot_be_shown_fails_the_page(tool, tmp_path, capsys, cells,
                                                                message):
    _prose_book(tmp_path, cells)
    assert tool.main(["--jobs", "1"]) == 1
    err = capsys.readouterr().err
    assert message in err and "book_execute: book/one.ipynb failed" in err


def _kept(tool, root, text):
    """``root``'s page as nbval would keep it for the book: its one cell printed ``text``."""
    nb = tool.read_page(root / "book" / "one.ipynb")
    nb.cells[0].outputs = [nbformat.v4.new_output("stream", name="stdout", text=text)]
    return tool.write_executed(root / "kept", root / "book" / "one.ipynb", nb, {}, 2.5)


def test_a_page_nbval_executed_for_the_book_is_stored_not_executed_again(tool, tmp_path, capsys):
    _book(tmp_path, "print(6 * 7)")
    _kept(tool, tmp_path, "kept by nbval\n")
    assert tool.main(["--jobs", "1", "--executed", str(tmp_path / "kept")]) == 0
    out = capsys.readouterr().out
    assert "book/one.ipynb executed by nbval in 2.5 s, stored" in out
    assert "every page is in the execution cache" in out
    with tool.open_cache() as cache:
        record = cache.match_cache_notebook(tool.read_page(tmp_path / "book" / "one.ipynb"))
        nb = cache.get_cache_bundle(record.pk).nb
    assert nb.cells[0].outputs[0].text == "kept by nbval\n"


def test_a_kept_execution_of_other_code_is_not_stored_and_the_page_runs(tool, tmp_path, capsys):
    _book(tmp_path, "print(6 * 7)")
    _kept(tool, tmp_path, "kept by nbval\n")
    nb = nbformat.read(tmp_path / "book" / "one.ipynb", as_version=4)
    nb.cells[0].source = "print(7 * 7)"   # edited after nbval ran it
    nbformat.write(nb, tmp_path / "book" / "one.ipynb")
    assert tool.main(["--jobs", "1", "--executed", str(tmp_path / "kept")]) == 0
    out = capsys.readouterr().out
    assert "is of another version of its code: executed here" in out
    assert "book_execute: 1 pages" in out


def test_a_missing_directory_of_kept_pages_is_refused(tool, tmp_path, capsys):
    _book(tmp_path, "print(6 * 7)")
    assert tool.main(["--executed", str(tmp_path / "nowhere")]) == 2
    assert "--executed" in capsys.readouterr().err
