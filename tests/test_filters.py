"""EKF (Joseph form) and UKF step functions: linear-Gaussian identities and invariants."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from xnavlab.core import filters


def _spd(rng, n, scale=1.0):
    A = rng.standard_normal((n, n))
    return scale * (A @ A.T + n * np.eye(n))


def _kf(x, P, z, H, R):
    """Textbook Kalman update (the independent reference)."""
    S = H @ P @ H.T + R
    K = P @ H.T @ np.linalg.inv(S)
    return x + K @ (z - H @ x), (np.eye(len(x)) - K @ H) @ P


@given(st.integers(0, 10_000), st.integers(1, 6), st.integers(1, 4))
def test_ekf_update_equals_kalman_for_linear_models(seed, n, m):
    rng = np.random.default_rng(seed)
    x, P = rng.standard_normal(n), _spd(rng, n)
    H, R = rng.standard_normal((m, n)), _spd(rng, m, 0.1)
    z = rng.standard_normal(m)
    up = filters.ekf_update(x, P, z, lambda s: H @ s, H, R)
    x_ref, P_ref = _kf(x, P, z, H, R)
    np.testing.assert_allclose(up.x, x_ref, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(up.P, P_ref, rtol=1e-7, atol=1e-9)
    assert np.array_equal(up.P, up.P.T)


@given(st.integers(0, 10_000))
def test_joseph_form_stays_positive_definite_for_any_gain(seed):
    rng = np.random.default_rng(seed)
    P, R = _spd(rng, 4), _spd(rng, 2)
    K, H = rng.standard_normal((4, 2)) * 10, rng.standard_normal((2, 4))
    Pj = filters.joseph(P, K, H, R)
    assert np.array_equal(Pj, Pj.T)
    eig = np.linalg.eigvalsh(Pj)
    assert eig.min() > 1e-12 * eig.max()  # PD far above rounding (never the sign of ~0)


def test_skipped_update_is_time_update_only():
    x, P = np.ones(2), np.eye(2)
    x1, P1 = filters.ekf_predict(x, P, lambda s: 2 * s, 2 * np.eye(2), 0.5 * np.eye(2))
    up = filters.ekf_update(x1, P1, None, None, None, None)
    assert np.array_equal(up.x, x1) and np.array_equal(up.P, P1)
    assert up.innovation is None and np.isnan(up.nis)
    np.testing.assert_allclose(P1, 4.5 * np.eye(2))


def test_ekf_predict_symmetrises():
    P = np.array([[2.0, 1.0], [1.0 + 1e-12, 2.0]])
    _, P1 = filters.ekf_predict(np.zeros(2), P, np.zeros(2), np.eye(2), np.zeros((2, 2)))
    assert np.array_equal(P1, P1.T)


@given(st.integers(0, 10_000), st.integers(1, 5))
def test_ukf_is_exact_for_linear_models(seed, n):
    rng = np.random.default_rng(seed)
    F, Q = rng.standard_normal((n, n)), _spd(rng, n, 0.01)
    H, R = rng.standard_normal((2, n)), _spd(rng, 2, 0.1)
    x, P = rng.standard_normal(n), _spd(rng, n)
    xe, Pe = filters.ekf_predict(x, P, lambda s: F @ s, F, Q)
    xu, Pu = filters.ukf_predict(x, P, lambda s: F @ s, Q)
    np.testing.assert_allclose(xu, xe, atol=1e-9)
    np.testing.assert_allclose(Pu, Pe, rtol=1e-8, atol=1e-9)
    z = rng.standard_normal(2)
    ue = filters.ekf_update(xe, Pe, z, lambda s: H @ s, H, R)
    uu = filters.ukf_update(xu, Pu, z, lambda s: H @ s, R)
    np.testing.assert_allclose(uu.x, ue.x, rtol=1e-7, atol=1e-8)
    np.testing.assert_allclose(uu.P, ue.P, rtol=1e-6, atol=1e-8)
    assert uu.nis == pytest.approx(ue.nis, rel=1e-7)


@pytest.mark.parametrize("alpha,kappa", [(1.0, 0.0), (1e-3, 0.0), (0.5, 1.0)])
def test_unscented_weights_and_linear_transform(alpha, kappa):
    n = 3
    Wm, Wc, lam = filters.ukf_weights(n, alpha, 2.0, kappa)
    assert Wm.sum() == pytest.approx(1.0)
    rng = np.random.default_rng(1)
    x, P, A = rng.standard_normal(n) * 1e6, _spd(rng, n), rng.standard_normal((2, n))
    X = filters.sigma_points(x, P, lam)
    m, S = filters.unscented_transform(X @ A.T, Wm, Wc)
    np.testing.assert_allclose(m, A @ x, rtol=1e-9)
    np.testing.assert_allclose(S, A @ P @ A.T, rtol=1e-5, atol=1e-6)


def test_ukf_weights_reject_bad_parameters():
    with pytest.raises(ValueError, match="alpha"):
        filters.ukf_weights(3, alpha=0.0)
    with pytest.raises(ValueError, match="kappa"):
        filters.ukf_weights(3, kappa=-3.0)


def test_nees_nis_and_chi2_bounds():
    assert filters.nees([1.0, 2.0], np.diag([1.0, 4.0])) == pytest.approx(2.0)
    e = np.ones((5, 2))
    P = np.broadcast_to(np.eye(2), (5, 2, 2))
    np.testing.assert_allclose(filters.nees(e, P), 2.0)
    assert filters.nis([3.0], [[9.0]]) == pytest.approx(1.0)
    lo, hi = filters.chi2_bounds(3, 1000)
    assert lo < 3 < hi and hi - lo < 0.31
    with pytest.raises(ValueError, match="p must"):
        filters.chi2_bounds(3, 10, p=1.5)


def test_classes_hold_state_and_skip():
    kf = filters.EKF([0.0, 0.0], np.eye(2))
    kf.predict(lambda s: s, np.eye(2), np.eye(2) * 0.1)
    kf.update(None, None, None, None)
    assert np.isnan(kf.last.nis)
    kf.update([1.0], lambda s: s[:1], np.array([[1.0, 0.0]]), [[1.0]])
    assert 0 < kf.x[0] < 1
    uk = filters.UKF([0.0, 0.0], np.eye(2))
    uk.predict(lambda s: s, np.eye(2) * 0.1).update([1.0], lambda s: s[:1], [[1.0]])
    np.testing.assert_allclose(uk.x, kf.x, rtol=1e-9)
    with pytest.raises(ValueError, match="P0 must have shape"):
        filters.EKF([0.0], np.eye(2))
    with pytest.raises(ValueError, match="x0"):
        filters.EKF([np.nan], np.eye(1))
