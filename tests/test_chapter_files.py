"""tools/chapter_files.py: the chapters the book tools walk, and a path that is no notebook refused."""

import doctest
import importlib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture
def tool(monkeypatch):
    monkeypatch.syspath_prepend(str(ROOT / "tools"))
    return importlib.import_module("chapter_files")


def test_its_examples_run(tool):
    assert doctest.testmod(tool).failed == 0


def test_every_chapter_is_found_in_order(tool):
    names = [p.name for p in tool.chapters()]
    assert names == sorted(names) and names[0].startswith("00_")


def test_a_path_that_is_no_notebook_is_named_in_one_line(tool, capsys):
    assert tool.chosen("tool", [ROOT / "README.md", ROOT / "book" / "nope.ipynb"]) is None
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "README.md" in err and "nope.ipynb" in err


def test_the_notebooks_given_are_kept_in_their_order(tool):
    two = tool.chapters()[:2][::-1]
    assert tool.chosen("tool", two) == two
