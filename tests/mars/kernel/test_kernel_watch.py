"""xnavlab.mars.kernel.kernel_watch: the compiled detector's pieces against numpy (the whole detector
is compared with the readable one through the fault-tolerant runs of
tests/mars/faults/test_fault_tolerance.py and tests/mars/faults/test_watch.py)."""

import numpy as np

from xnavlab.core.validate import make_rng
from xnavlab.mars.kernel import kernel_inputs as ki
from xnavlab.mars.kernel import kernel_measurements as kme
from xnavlab.mars.kernel import kernel_watch as kw


def test_the_median_by_selection_is_numpys():
    rng = make_rng(11)
    med, cnt = np.empty(3000), np.empty(8192, dtype=np.int64)
    for n in (1, 2, 7, 32, 33, 100, 1001, 3000):
        x = rng.standard_t(3, size=n)
        x[: n // 4] = x[n // 2]                    # ties
        assert kw._median_abs(x.copy(), n, med, cnt) == np.median(np.abs(x)), n


def test_a_whitened_innovation_carries_the_nis():
    rng = make_rng(12)
    m = 3
    H = np.zeros((4, 6))
    H[:m, :3] = rng.normal(size=(m, 3))
    R = np.zeros((4, 4))
    R[:m, :m] = np.diag([1.0, 2.0, 3.0])
    me = ki.Measurement(rng.normal(size=4), H, R, np.empty((4, 3)))
    a = rng.normal(size=(6, 6))
    P = a @ a.T + np.eye(6)
    e = np.empty
    fu = ki.FusionScratch(e(6), e((6, 6)), e(6), e((6, 6)), e((6, 6)), np.zeros(6), P,
                          np.zeros((3, 3)), np.zeros(3), e((3, 3)), np.ones(1, dtype=bool),
                          e(1))
    up = ki.UpdateScratch(e((6, 4)), e((4, 4)), e((4, 4)), e(4), e((6, 4)), e((6, 4)), e((6, 6)))
    z = np.zeros
    se = ki.Sensors(z((1, 4)), z((1, 3)), z((1, 3)), z((4, 3)), z(4), z(4), z((1, 4)), 1.0, 1.0,
                    z((1, 3)), np.eye(3), 1.0, 1.0)
    assert kw.whiten(kme.KIND_CNS, 0, me, m, fu, se, up) == m
    S = H[:m] @ P @ H[:m].T + R[:m, :m]
    nu = me.nu[:m]
    assert np.isclose(up.y[:m] @ up.y[:m], nu @ np.linalg.solve(S, nu), rtol=1e-12)
