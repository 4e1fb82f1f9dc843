"""xnavlab.mars.kernel.kernel_compile: the kernels' cache is keyed by all their sources."""

import importlib
import shutil
import sys

import numpy as np

from xnavlab.mars.kernel import kernel_compile as kc


def _copy_sources(root, dest):
    for rel in kc.SOURCES:
        (dest / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(root / rel, dest / rel)


def test_a_change_of_any_byte_of_any_source_changes_the_digest(tmp_path):
    _copy_sources(kc._PACKAGE, tmp_path)
    base = kc.sources_digest(tmp_path)
    assert base == kc.sources_digest()
    seen = {base}
    for rel in kc.SOURCES:
        path = tmp_path / rel
        data = path.read_bytes()
        path.write_bytes(data[:-1] + bytes([data[-1] ^ 1]))      # the last byte
        seen.add(kc.sources_digest(tmp_path))
        path.write_bytes(data)
    assert len(seen) == len(kc.SOURCES) + 1
    assert kc.sources_digest(tmp_path) == base


def test_every_module_that_compiles_with_jit_is_a_source():
    package = kc._PACKAGE
    users = {p.relative_to(package).as_posix() for p in (package / "mars").rglob("*.py")
             if "kernel_compile import" in p.read_text()}
    assert users and users <= set(kc.SOURCES)


def test_an_index_written_for_other_sources_is_not_loaded(tmp_path, monkeypatch):
    """The stamp replaces numba's own (the defining file's hash): code cached for another
    digest is compiled again, not loaded."""
    (tmp_path / "toy_kernel.py").write_text(
        "from xnavlab.mars.kernel.kernel_compile import HELPER, jit\n\n\n"
        "@jit(**HELPER)\ndef twice(x):\n    return 2.0 * x\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    toy = importlib.import_module("toy_kernel")
    try:
        assert toy.twice(np.float64(2.0)) == 4.0
        assert toy.twice._cache._cache_file._load_index()          # written under this digest
        monkeypatch.setattr(kc, "_DIGEST", "another")
        other = kc.SourcesCache(toy.twice.py_func)
        assert other._cache_file._load_index() == {}
    finally:
        sys.modules.pop("toy_kernel", None)
