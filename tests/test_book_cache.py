"""tools/book_cache.py: a change to the package forgets every executed chapter, nothing else does."""

import importlib.util
from pathlib import Path

import pytest

TOOL = Path(__file__).resolve().parents[1] / "tools" / "book_cache.py"


@pytest.fixture
def cache_tool(tmp_path, monkeypatch):
    spec = importlib.util.spec_from_file_location("book_cache", TOOL)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    build = tmp_path / "_build"
    monkeypatch.setattr(mod, "CACHE", build / ".jupyter_cache")
    monkeypatch.setattr(mod, "STAMP", build / ".jupyter_cache.xnavlab-sha256")
    monkeypatch.setattr(mod, "DEPENDENT", (build / ".doctrees", build / "jupyter_execute"))
    digest = {"value": "a"}
    monkeypatch.setattr(mod, "package_hash", lambda: digest["value"])
    return mod, build, digest


def _fill(build):
    for name in (".jupyter_cache", ".doctrees", "jupyter_execute"):
        (build / name).mkdir(parents=True, exist_ok=True)
        (build / name / "x").write_text("old")


def _present(build):
    return {n for n in (".jupyter_cache", ".doctrees", "jupyter_execute") if (build / n).exists()}


def test_unchanged_package_keeps_the_cache(cache_tool):
    mod, build, _ = cache_tool
    assert mod.main([]) == 0              # first run: records the hash
    _fill(build)
    assert mod.main([]) == 0
    assert _present(build) == {".jupyter_cache", ".doctrees", "jupyter_execute"}


def test_changed_package_drops_cache_and_sphinx_environment(cache_tool):
    mod, build, digest = cache_tool
    mod.main([])
    _fill(build)
    digest["value"] = "b"
    mod.main([])
    # the Sphinx environment must go too, or unchanged chapters keep their old outputs
    assert _present(build) == set()
    assert mod.STAMP.read_text().strip() == "b"


def test_clear_forces_a_full_rebuild(cache_tool):
    mod, build, _ = cache_tool
    mod.main([])
    _fill(build)
    mod.main(["--clear"])
    assert _present(build) == set()


def test_package_hash_is_a_sha256_of_the_sources():
    spec = importlib.util.spec_from_file_location("book_cache_real", TOOL)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    assert len(mod.package_hash()) == 64
