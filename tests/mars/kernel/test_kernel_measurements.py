"""xnavlab.mars.kernel.kernel_measurements: the compiled sensor models against the readable ones
(xnavlab.mars.models.sensors) and the two local updates against the textbook EKF."""

import numpy as np

from xnavlab.mars.kernel import kernel_inputs as ki
from xnavlab.mars.kernel import kernel_measurements as kme
from xnavlab.mars.models import sensors
from xnavlab.mars.timing import pulsars

X = np.array([3.1e6, -2.2e6, 1.4e6, 100.0, 2000.0, -300.0])
RM, RS = np.array([2.0e11, 5.0e10, 1.0e10]), np.array([1.0e8, -2.0e8, 3.0e7])
MM = 4


def _sensors():
    n, d = pulsars.directions()
    star = np.eye(3)
    return ki.Sensors(np.zeros((1, 4)), RM[None], RS[None], n, d, np.full(4, 1e-6),
                      np.zeros((1, 4)), 5000.0, 1e-3, np.zeros((1, 3)), star, 1.5e-5, 8e-4)


def _measurement():
    return ki.Measurement(np.empty(MM), np.zeros((MM, 6)), np.zeros((MM, MM)), np.empty((MM, 3)))


def test_the_three_sensors_are_the_readable_models():
    se = _sensors()
    cases = {
        kme.KIND_XNAV: (sensors.xnav_h(X, RM, RS, se.n_x, se.d_x),
                        sensors.xnav_jacobian(X, RM, RS, se.n_x, se.d_x), np.diag(se.sig_x**2)),
        kme.KIND_UV: (sensors.uv_h(X), sensors.uv_jacobian(X),
                      sensors.uv_R(se.sig_r, se.sig_u)),
        kme.KIND_CNS: (sensors.cns_h(X, se.stars_c), sensors.cns_jacobian(X, se.stars_c),
                       sensors.cns_R(X, se.stars_c, se.sig_s, se.sig_h)),
    }
    for kind, (h, H, R) in cases.items():
        me = _measurement()
        m = kme.measure(kind, X, 0, se, me)
        assert m == len(h)
        assert np.allclose(-me.nu[:m], h, rtol=1e-12, atol=1e-15), kind    # z = 0
        assert np.allclose(me.H[:m, :3], H[:, :3], rtol=1e-9, atol=1e-18), kind
        assert np.allclose(me.R[:m, :m], R, rtol=1e-12, atol=1e-24), kind


def _update_scratch():
    e = np.empty
    return ki.UpdateScratch(e((6, MM)), e((MM, MM)), e((MM, MM)), e(MM), e((6, MM)), e((6, MM)),
                            e((6, 6)))


def test_the_joseph_update_and_the_information_it_adds_are_the_textbook_ekf():
    se = _sensors()
    me = _measurement()
    m = kme.measure(kme.KIND_UV, X, 0, se, me)
    nu, H, R = me.nu[:m].copy(), me.H[:m].copy(), me.R[:m, :m].copy()
    H[:, 3:] = 0.0
    P = np.diag([4e6, 4e6, 4e6, 1.0, 1.0, 1.0])
    share = 0.25
    st = ki.FilterState(X[None].copy(), (P / share)[None].copy(), np.ones(1), X.copy(),
                        P.copy())
    nis = kme.update(st, 0, me, m, np.inf, True, _update_scratch())
    Pi = P / share
    S = H @ Pi @ H.T + R
    K = Pi @ H.T @ np.linalg.inv(S)
    A = np.eye(6) - K @ H
    assert np.isclose(nis, nu @ np.linalg.solve(S, nu), rtol=1e-10)
    assert np.allclose(st.xs[0], X + K @ nu, rtol=1e-12)
    assert np.allclose(st.Ps[0], A @ Pi @ A.T + K @ R @ K.T, rtol=1e-8, atol=1e-8)
    # the same local in information form: its NIS, and H^T R^-1 H, H^T R^-1 nu
    e = np.empty
    fu = ki.FusionScratch(e(6), e((6, 6)), e(6), e((6, 6)), e((6, 6)), X.copy(), P.copy(),
                          np.zeros((3, 3)), np.zeros(3), e((3, 3)), np.ones(1, dtype=bool),
                          np.array([1.0 / share]))
    nis_i = kme.update_information(fu, 0, me, m, np.inf, True, _update_scratch())
    assert np.isclose(nis_i, nis, rtol=1e-12)
    Ri = np.linalg.inv(R)
    assert np.allclose(np.tril(fu.J), np.tril(H[:, :3].T @ Ri @ H[:, :3]), rtol=1e-9)
    assert np.allclose(fu.bv, H[:, :3].T @ Ri @ nu, rtol=1e-9)


def test_the_gate_keeps_the_state_and_returns_the_nis():
    se = _sensors()
    me = _measurement()
    m = kme.measure(kme.KIND_CNS, X, 0, se, me)
    P = np.diag([4e6, 4e6, 4e6, 1.0, 1.0, 1.0])
    st = ki.FilterState(X[None].copy(), P[None].copy(), np.ones(1), X.copy(), P.copy())
    nis = kme.update(st, 0, me, m, 0.0, True, _update_scratch())
    assert nis > 0.0 and np.array_equal(st.xs[0], X) and np.array_equal(st.Ps[0], P)
