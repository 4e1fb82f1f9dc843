"""Root pytest configuration: applies to doctests in xnavlab/, to tests/ and to book/."""

import os
import sys
from pathlib import Path

os.environ.setdefault("MPLBACKEND", "Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

# make test: nbval's run of the chapters kept for the book (tools/nbval_book.py, a plugin
# loaded only when XNAVLAB_NBVAL_BOOK names where; tools/ is a folder of scripts, not a package)
if os.environ.get("XNAVLAB_NBVAL_BOOK"):
    sys.path.insert(0, str(Path(__file__).resolve().parent / "tools"))
    pytest_plugins = ["nbval_book"]


@pytest.fixture(autouse=True)
def _doctest_numpy(doctest_namespace):
    """Doctests print NumPy scalars as plain numbers and see ``np``."""
    doctest_namespace["np"] = np
    with np.printoptions(legacy="1.25"):
        yield


#: Test files run first: they compute the reproductions that the chapters read from the disk
#: cache (:mod:`xnavlab.reproduce`). A chapter that reaches a reproduction while a test
#: computes it waits on the entry's lock, its pytest worker idle: chapter 9 waited about two
#: minutes of a quiet machine's time for mars-faults-wavelet (measured 2026-11-29).
FIRST = ("tests/test_verdicts.py",)


def pytest_collection_modifyitems(config, items):
    """Each file's tests stay together, in the order ``make test``'s workers take the files
    (pytest-xdist's ``--dist loadfile`` with ``--no-loadscope-reorder``): the :data:`FIRST`
    files, then the others by number of tests, most first (what xdist would do itself)."""
    files = {}
    for item in items:
        files.setdefault(item.nodeid.split("::")[0], []).append(item)
    order = sorted(files, key=lambda f: (f not in FIRST, -len(files[f])))  # stable: ties keep order
    items[:] = [item for f in order for item in files[f]]
