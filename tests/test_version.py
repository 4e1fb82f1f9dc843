"""The version is written once (``xnavlab/__init__.py``) and every other place reads it.

``pyproject.toml`` declares it dynamic and points setuptools at ``xnavlab.__version__``;
``python -m xnavlab --version`` prints it; the book's front page (``book/intro.md``) computes it
in a hidden code cell; the installed package's metadata carries it. These tests check that
they all agree and that no other file types the number.
"""

import ast
import importlib.metadata
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import xnavlab
from xnavlab.cli import main

ROOT = Path(__file__).resolve().parents[1]
VERSION = xnavlab.__version__

try:
    import tomllib
except ImportError:  # Python 3.10
    tomllib = pytest.importorskip("tomli")


def test_version_is_a_release_number():
    assert re.fullmatch(r"\d+\.\d+\.\d+", VERSION), VERSION


def test_the_version_is_a_literal_in_the_package():
    """setuptools reads ``attr:`` statically only from a plain string assignment."""
    tree = ast.parse((ROOT / "xnavlab" / "__init__.py").read_text(encoding="utf-8"))
    values = [node.value.value for node in tree.body
              if isinstance(node, ast.Assign) and isinstance(node.value, ast.Constant)
              and any(isinstance(t, ast.Name) and t.id == "__version__" for t in node.targets)]
    assert values == [VERSION]


def test_pyproject_reads_the_version_from_the_package():
    meta = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    assert "version" not in meta["project"], "pyproject.toml must not type the version"
    assert "version" in meta["project"].get("dynamic", [])
    assert meta["tool"]["setuptools"]["dynamic"]["version"] == {"attr": "xnavlab.__version__"}


def test_setuptools_builds_metadata_with_the_version(tmp_path):
    """What ``pip install`` would record, built from a copy of the sources."""
    pytest.importorskip("setuptools")
    src = tmp_path / "src"
    src.mkdir()
    for name in ("pyproject.toml", "README.md"):
        shutil.copy(ROOT / name, src / name)
    shutil.copytree(ROOT / "xnavlab", src / "xnavlab",
                    ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    out = tmp_path / "meta"
    out.mkdir()
    code = ("import sys; from setuptools import build_meta; "
            "print(build_meta.prepare_metadata_for_build_wheel(sys.argv[1]))")
    done = subprocess.run([sys.executable, "-c", code, str(out)], cwd=src,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    info = done.stdout.strip().splitlines()[-1]
    metadata = (out / info / "METADATA").read_text(encoding="utf-8")
    assert f"\nVersion: {VERSION}\n" in metadata


def test_installed_metadata_agrees():
    try:
        installed = importlib.metadata.version("xnavlab")
    except importlib.metadata.PackageNotFoundError:
        pytest.skip("xnavlab is not installed (only imported from the source tree)")
    assert installed == VERSION, (
        f"the installed metadata says {installed}, the source {VERSION}: reinstall "
        "(make setup, or pip install --no-build-isolation -e .)")


def test_cli_prints_the_version(capsys):
    assert main(["--version"]) == 0
    out, err = capsys.readouterr()
    assert out == f"xnavlab {VERSION}\n" and err == ""


def test_python_m_xnavlab_version():
    done = subprocess.run([sys.executable, "-m", "xnavlab", "--version"], cwd=ROOT,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == [f"xnavlab {VERSION}"]


def code_cells(path):
    """The sources of the ``{code-cell}`` blocks of a MyST notebook, options left out."""
    text = path.read_text(encoding="utf-8")
    cells = re.findall(r"^```\{code-cell\}[^\n]*\n(.*?)^```", text, re.S | re.M)
    return [re.sub(r"\A(?::[\w-]+:.*\n)*", "", cell) for cell in cells]


def test_front_page_computes_the_version():
    """The front page's hidden cell shows ``xnavlab.__version__``; no page types the number."""
    intro = ROOT / "book" / "intro.md"
    cells = [c for c in code_cells(intro) if "__version__" in c]
    assert len(cells) == 1, "book/intro.md needs one code cell that shows xnavlab.__version__"
    tree = ast.parse(cells[0])
    last = tree.body.pop()
    assert isinstance(last, ast.Expr), "the cell must end with the displayed expression"
    scope = {}
    exec(compile(tree, str(intro), "exec"), scope)
    shown = eval(compile(ast.Expression(last.value), str(intro), "eval"), scope)
    text = getattr(shown, "data", str(shown))
    assert VERSION in text


@pytest.mark.parametrize("name", ["pyproject.toml", "README.md", "CONTRIBUTING.md",
                                  "book/intro.md", "xnavlab/cli/__init__.py"])
def test_no_other_file_types_the_version(name):
    text = (ROOT / name).read_text(encoding="utf-8")
    assert not re.search(rf"(?<![\d.]){re.escape(VERSION)}(?![\d.])", text), (
        f"{name} types the version {VERSION}; read xnavlab.__version__ instead")
