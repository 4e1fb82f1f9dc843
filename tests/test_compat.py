"""The deprecated module names (``xnavlab.compat.RENAMED``): release 0.1's flat names and the
Mars system's flat names from before its subpackages (``xnavlab.mars.<module>``).

Each old name must still import, warn with a ``DeprecationWarning`` that names the new
module, and give back the new module itself (the same object, so state and ``isinstance``
checks are shared), whether it is imported by name or taken from the package.
"""

import importlib
import re
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

import xnavlab
from xnavlab.compat import MARS_SUBPACKAGES, RENAMED

ROOT = Path(__file__).resolve().parents[1]

ALIASES = sorted(RENAMED.items())


def forget(monkeypatch, old):
    """Make the next import of ``old`` go through the alias finder again, and leave it
    afterwards as it was before the test (absent stays absent).

    ``setitem``/``setattr`` first record the state before the test (``delitem``/``delattr``
    of a missing entry record nothing), so the alias a test imports does not stay in
    ``sys.modules`` or on the package: a later test or doctest in the same worker (the
    ``xnavlab.compat`` doctest imports ``toa`` and expects its warning) meets the same
    fresh state, in any order pytest-xdist runs them.
    """
    parent, _, leaf = old.rpartition(".")
    monkeypatch.setitem(sys.modules, old, None)
    monkeypatch.delitem(sys.modules, old)
    monkeypatch.setattr(sys.modules[parent], leaf, None, raising=False)
    monkeypatch.delattr(sys.modules[parent], leaf)


def test_every_alias_points_into_the_package():
    for old, new in ALIASES:
        assert old.startswith("xnavlab.") and new.startswith("xnavlab.") and old != new
        if old.startswith("xnavlab.mars."):
            sub, module = new.split(".")[2:]
            assert old == f"xnavlab.mars.{module}" and module in MARS_SUBPACKAGES[sub], old
        else:
            assert old.count(".") == 1, f"{old}: the 0.1 names were flat"


def test_every_mars_module_has_its_old_flat_name():
    """Each public module of the six subpackages, and only those, has an alias
    ``xnavlab.mars.<module>`` (a ``_private`` module is its subpackage's plumbing: no 0.1 name)."""
    files = {(p.parent.name, p.stem) for p in (ROOT / "xnavlab" / "mars").glob("*/*.py")
             if not p.name.startswith("_")}
    listed = {(sub, m) for sub, modules in MARS_SUBPACKAGES.items() for m in modules}
    assert files == listed
    assert {old for old in RENAMED if old.startswith("xnavlab.mars.")} == {
        f"xnavlab.mars.{m}" for _, m in listed}


@pytest.mark.parametrize(("old", "new"), ALIASES, ids=[old for old, _ in ALIASES])
def test_import_by_old_name_warns_and_forwards(monkeypatch, old, new):
    forget(monkeypatch, old)
    with pytest.warns(DeprecationWarning, match=rf"{old} is deprecated; import {new}\b"):
        module = importlib.import_module(old)
    assert module is importlib.import_module(new)
    assert module.__name__ == new and module.__spec__.name == new


@pytest.mark.parametrize(("old", "new"), ALIASES, ids=[old for old, _ in ALIASES])
def test_from_package_import_warns_and_forwards(monkeypatch, old, new):
    forget(monkeypatch, old)
    parent, _, leaf = old.rpartition(".")
    with pytest.warns(DeprecationWarning, match=rf"import {new}\b"):
        namespace = {}
        exec(f"from {parent} import {leaf}", namespace)
    assert namespace[leaf] is importlib.import_module(new)


def test_new_names_do_not_warn():
    """Importing the new modules never goes through the aliases."""
    code = ("import importlib, warnings; warnings.simplefilter('error'); "
            "from xnavlab.compat import RENAMED; "
            "[importlib.import_module(n) for n in sorted(set(RENAMED.values()))]")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=600)
    assert done.returncode == 0, done.stderr


def test_unknown_flat_name_is_not_invented():
    with pytest.raises(ModuleNotFoundError):
        importlib.import_module("xnavlab.no_such_module")
    assert not hasattr(xnavlab, "no_such_module")


@pytest.mark.parametrize(("old", "new"), ALIASES, ids=[old for old, _ in ALIASES])
def test_from_old_module_import_a_name_warns_and_gives_the_new_object(monkeypatch, old, new):
    """``from xnavlab.toa import roemer`` still works: the name is the new module's own object."""
    forget(monkeypatch, old)
    name = importlib.import_module(new).__all__[0]
    with pytest.warns(DeprecationWarning, match=rf"{old} is deprecated; import {new}\b"):
        namespace = {}
        exec(f"from {old} import {name}", namespace)
    assert namespace[name] is getattr(importlib.import_module(new), name)


def test_the_second_import_of_an_old_name_does_not_warn_again(monkeypatch):
    old, new = ALIASES[0]
    forget(monkeypatch, old)
    with pytest.warns(DeprecationWarning):
        importlib.import_module(old)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert importlib.import_module(old) is importlib.import_module(new)


def test_a_test_leaves_an_alias_as_it_found_it():
    """What a test imports through ``forget`` is gone again after it, present or not before."""
    old, _ = ALIASES[0]
    parent, _, leaf = old.rpartition(".")
    before = (sys.modules.get(old), vars(sys.modules[parent]).get(leaf))
    with pytest.MonkeyPatch.context() as mp:
        forget(mp, old)
        with pytest.warns(DeprecationWarning):
            importlib.import_module(old)
        assert old in sys.modules
    assert (sys.modules.get(old), vars(sys.modules[parent]).get(leaf)) == before
    assert (old in sys.modules) == (before[0] is not None)


#: An old Mars path, dotted (``xnavlab.mars.scenarios``) or as a file (``mars/scenarios.py``,
#: ``mars/test_scenarios.py``).
OLD_MARS_PATH = re.compile(r"xnavlab\.mars\.(?:{0})\b|\bmars/(?:test_)?(?:{0})\.py\b".format(
    "|".join(m for modules in MARS_SUBPACKAGES.values() for m in modules)))


def test_the_old_mars_paths_are_used_nowhere():
    """Only the aliases know the old paths: the package, the book, the tests (but this one),
    the benchmarks and the tools import and name the subpackages' paths."""
    paths = [p for top in ("xnavlab", "book", "tests", "benchmarks", "tools")
             for p in (ROOT / top).rglob("*")
             if p.suffix in {".py", ".ipynb", ".md", ".bib", ".csv", ".toml", ".yml", ".txt"}
             and not {"__pycache__", "_build", ".ipynb_checkpoints"} & set(p.parts)]
    paths += [ROOT / name for name in ("README.md", "CONTRIBUTING.md", "Makefile")]
    assert len(paths) > 200
    this = Path(__file__).resolve()
    bad = [f"{p.relative_to(ROOT)}:{n}: {m.group(0)}" for p in paths if p.resolve() != this
           for n, line in enumerate(p.read_text(encoding="utf-8", errors="replace").splitlines(), 1)
           for m in OLD_MARS_PATH.finditer(line)]
    assert not bad, "\n".join(bad)
