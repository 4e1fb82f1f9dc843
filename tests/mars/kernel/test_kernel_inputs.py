"""xnavlab.mars.kernel.kernel_inputs: the compiled filter's named containers, as the kernel reads them."""

import numpy as np
import pytest

from xnavlab.mars.kernel import kernel_compile
from xnavlab.mars.kernel import kernel_inputs as ki
from xnavlab.mars.navigation import scenarios

CONTAINERS = (ki.FilterState, ki.Propagation, ki.Plan, ki.Sensors, ki.Records, ki.WatchState)
SCRATCH = (ki.PredictScratch, ki.Measurement, ki.UpdateScratch, ki.FusionScratch,
           ki.WatchScratch)


def test_the_layout_names_every_container_and_its_fields_in_order():
    rows = ki.layout()
    assert len(rows) == len(CONTAINERS)
    for row, c in zip(rows, CONTAINERS, strict=True):
        assert row == f"{c.__name__}({' '.join(c._fields)})"


def test_the_kernels_cache_is_keyed_by_this_files_source():
    """numba keys its cache by the fields' types, not their names: a reordering of the fields
    must recompile the kernels, and it does (this file is one of the digest's sources)."""
    assert "mars/kernel/kernel_inputs.py" in kernel_compile.SOURCES


def test_the_watch_columns_are_distinct_and_fit_their_arrays():
    wf = [getattr(ki, n) for n in ki.__all__ if n.startswith("WF_")]
    wi = [getattr(ki, n) for n in ki.__all__ if n.startswith("WI_")]
    assert sorted(wf) == list(range(10)) and sorted(wi) == list(range(15))


@pytest.mark.parametrize("container", CONTAINERS + SCRATCH, ids=lambda c: c.__name__)
def test_every_field_is_documented(container):
    """Each field appears in an Attributes entry (numpydoc allows ``a, b : type``)."""
    named = set()
    for line in container.__doc__.splitlines():
        head, sep, _ = line.strip().partition(" : ")
        if sep:
            named.update(name.strip() for name in head.split(","))
    missing = [f for f in container._fields if f not in named]
    assert not missing, f"{container.__name__}: {missing} not in its docstring's Attributes"


def test_the_containers_share_the_callers_arrays_not_copies():
    xs = np.zeros((3, 6))
    st = ki.FilterState(xs, np.tile(np.eye(6), (3, 1, 1)), np.full(3, 1 / 3), np.zeros(6),
                        np.eye(6))
    st.xs[0, 0] = 5.0
    assert xs[0, 0] == 5.0


def test_a_run_through_the_containers_is_the_same_run_twice():
    sc = scenarios.MarsScenario(days=0.05, record_dt=60.0, seed=3)
    a, b = scenarios.run(sc), scenarios.run(sc)
    assert np.array_equal(a.x, b.x) and np.array_equal(a.nis, b.nis, equal_nan=True)
