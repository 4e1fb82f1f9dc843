"""tools/book_build.py and book/_ext/xnav_parallel.py: the book's Sphinx build on several
processes, and the two extensions of Jupyter Book declared safe for it."""

import importlib.util
import sys
import types
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _load(name, path):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _app(**versions):
    """A stand-in Sphinx application holding extensions of the given module versions."""
    exts = {name: types.SimpleNamespace(parallel_read_safe=None) for name in versions}
    return types.SimpleNamespace(extensions=exts), exts


def test_the_judged_versions_are_declared_safe_and_no_other(monkeypatch):
    ext = _load("xnav_parallel", ROOT / "book" / "_ext" / "xnav_parallel.py")
    (name_a, ver_a), (name_b, _) = ext.JUDGED.items()
    monkeypatch.setitem(sys.modules, name_a, types.SimpleNamespace(__version__=ver_a))
    monkeypatch.setitem(sys.modules, name_b, types.SimpleNamespace(__version__="99.0"))
    app, exts = _app(**{name_a: ver_a, name_b: "99.0"})
    ext._config_inited(app, None)
    assert exts[name_a].parallel_read_safe is True
    assert exts[name_b].parallel_read_safe is None   # another version: Sphinx warns, -W fails


def test_the_installed_extensions_are_the_judged_versions():
    ext = _load("xnav_parallel", ROOT / "book" / "_ext" / "xnav_parallel.py")
    for name, version in ext.JUDGED.items():
        assert importlib.import_module(name).__version__ == version, name


def test_a_bad_jobs_count_is_refused(capsys):
    tool = _load("book_build", ROOT / "tools" / "book_build.py")
    assert tool.main(["--jobs", "0", "."]) == 2
    assert "--jobs must be at least 1, got 0" in capsys.readouterr().err
