"""Root pytest configuration: applies to doctests in xnavlab/ and to tests/."""

import os

os.environ.setdefault("MPLBACKEND", "Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402


@pytest.fixture(autouse=True)
def _doctest_numpy(doctest_namespace):
    """Doctests print NumPy scalars as plain numbers and see ``np``."""
    doctest_namespace["np"] = np
    with np.printoptions(legacy="1.25"):
        yield
