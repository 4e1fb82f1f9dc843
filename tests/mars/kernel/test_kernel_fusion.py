"""xnavlab.mars.kernel.kernel_fusion: the two compiled fusions against the readable information form
(xnavlab.core.federated.fuse and the centralised update)."""

import numpy as np

from xnavlab.core import federated
from xnavlab.core.validate import make_rng
from xnavlab.mars.kernel import kernel_inputs as ki
from xnavlab.mars.kernel.kernel_fusion import fuse, fuse_information


def _cov(rng):
    """A covariance of a few km and m/s with moderate correlations (condition ~10)."""
    a = rng.normal(size=(6, 6)) / 3.0
    d = np.diag([1e3, 1e3, 1e3, 1.0, 1.0, 1.0])
    return d @ (a @ a.T + np.eye(6)) @ d


def _scratch(xp, Pp, use):
    e = np.empty
    return ki.FusionScratch(e(6), e((6, 6)), e(6), e((6, 6)), e((6, 6)), xp, Pp,
                            np.zeros((3, 3)), np.zeros(3), e((3, 3)), use, e(len(use)))


def test_fuse_is_the_information_form():
    rng = make_rng(7)
    xs = rng.normal(size=(3, 6)) * 1e3
    Ps = np.array([_cov(rng) for _ in range(3)])
    use = np.array([True, False, True])
    st = ki.FilterState(xs, Ps, np.full(3, 1 / 3), np.empty(6), np.empty((6, 6)))
    assert fuse(st, _scratch(np.empty(6), np.empty((6, 6)), use))
    x_ref, P_ref = federated.fuse(xs, Ps, use)
    assert np.allclose(st.xm, x_ref, rtol=1e-10, atol=1e-8)
    assert np.allclose(st.Pm, P_ref, rtol=1e-9)
    assert not fuse(st, _scratch(np.empty(6), np.empty((6, 6)), np.zeros(3, dtype=bool)))


def test_fuse_information_is_the_centralised_update():
    rng = make_rng(8)
    x, P = rng.normal(size=6) * 1e3, _cov(rng)
    Hr = rng.normal(size=(5, 3)) * 1e-3
    J = Hr.T @ Hr                       # gained information H^T R^-1 H (position block)
    b = rng.normal(size=3) * 1e-3
    ssum = 0.8
    fu = _scratch(x, P, np.ones(2, dtype=bool))
    fu.J[:] = np.tril(J)                # the kernel fills the lower triangle
    fu.bv[:] = b
    st = ki.FilterState(np.empty((2, 6)), np.empty((2, 6, 6)), np.ones(2), np.empty(6),
                        np.empty((6, 6)))
    assert fuse_information(st, fu, ssum)
    Jf = np.zeros((6, 6))
    Jf[:3, :3] = J
    P_ref = np.linalg.inv(ssum * np.linalg.inv(P) + Jf)     # P_f^-1 = ssum P^-1 + J
    assert np.allclose(st.Pm, P_ref, rtol=1e-8, atol=1e-10)
    assert np.allclose(st.xm, x + P_ref[:, :3] @ b, rtol=1e-10, atol=1e-8)
