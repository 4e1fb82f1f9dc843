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
