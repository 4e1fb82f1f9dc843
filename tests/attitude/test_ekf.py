"""The attitude EKF (xnavlab.attitude.ekf): covariance invariants, the Jacobian against finite
differences, the quaternion sign, bad input and convergence to the gyro drifts."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from xnavlab import attitude as att
from xnavlab.core import quaternions as qt

DPH = att.DEG_PER_H


@st.composite
def unit_quat(draw):
    v = np.array(draw(st.lists(st.floats(-1, 1), min_size=4, max_size=4)))
    if np.linalg.norm(v) < 1e-3:
        v = qt.IDENTITY.copy()
    return v / np.linalg.norm(v)


small_rate = st.lists(st.floats(-0.05, 0.05), min_size=3, max_size=3).map(np.array)


def _random_state(q, b, scale):
    x = np.concatenate([q, b])
    rng = np.random.default_rng(int(1e6 * abs(scale)) % 1000)
    L = rng.normal(size=(7, 7)) * scale
    return x, L @ L.T + 1e-12 * np.eye(7)


@given(unit_quat(), small_rate, small_rate, unit_quat(), st.floats(1e-5, 1e-2))
def test_ekf_keeps_P_symmetric_positive_definite(q, b, w, qm, scale):
    x, P = _random_state(q, b * 1e-2, scale)
    x1, P1 = att.ekf_predict(x, P, w, 0.1, 1e-12, 1e-14)
    x2, P2, nu = att.ekf_update(x1, P1, qm, 1e-10)
    for M in (P1, P2):
        np.testing.assert_allclose(M, M.T, atol=1e-15)
        assert np.linalg.eigvalsh(M).min() > -1e-12 * np.abs(M).max()
    assert np.trace(P2) <= np.trace(P1) + 1e-18
    assert np.linalg.norm(x2[:4]) == pytest.approx(1.0, abs=1e-12)
    assert nu.shape == (4,)


@given(unit_quat(), small_rate, small_rate)
def test_ekf_jacobian_matches_finite_differences(q, b, w):
    """With P = I and no noise, P(k+1|k) = F F^T; compare with a central-difference F."""
    dt = 0.1
    x = np.concatenate([q, b])

    def f(xx):
        return np.concatenate([qt.quat_propagate(xx[:4], w - xx[4:], dt), xx[4:]])

    J = np.empty((7, 7))
    for i in range(7):
        e = np.zeros(7)
        e[i] = 1e-6
        J[:, i] = (f(x + e) - f(x - e)) / 2e-6
    _, P1 = att.ekf_predict(x, np.eye(7), w, dt, 0.0, 0.0)
    # F uses the first-order -dt/2 Xi(q) (paper eqs. (22)-(23)): error O(dt^2 |w - b|)
    np.testing.assert_allclose(P1, J @ J.T, atol=0.5 * dt**2 * np.linalg.norm(w - b) + 1e-8)


def test_ekf_update_is_sign_invariant():
    x, P = att.ekf_init(att.DEFAULT_Q0, attitude_sigma=1e-4, drift_sigma=1e-4)
    qm = qt.quat_product(qt.quat_from_rotvec([1e-4, 0, 0]), att.DEFAULT_Q0)
    a = att.ekf_update(x, P, qm, 1e-10)
    b = att.ekf_update(x, P, -qm, 1e-10)
    np.testing.assert_allclose(a[0], b[0])
    np.testing.assert_allclose(a[1], b[1])


def test_ekf_bad_inputs():
    x, P = att.ekf_init(att.DEFAULT_Q0, attitude_sigma=1e-4, drift_sigma=1e-4)
    with pytest.raises(ValueError, match="^dt "):
        att.ekf_predict(x, P, np.zeros(3), 0.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="^omega_g"):
        att.ekf_predict(x, P, np.zeros(4), 0.1, 0.0, 0.0)
    with pytest.raises(ValueError, match="^gyro_cov"):
        att.ekf_predict(x, P, np.zeros(3), 0.1, -1.0, 0.0)
    with pytest.raises(ValueError, match="^R "):
        att.ekf_update(x, P, att.DEFAULT_Q0, -np.eye(4))
    with pytest.raises(ValueError, match=r"^x\[\.\.\., :4\] must have a non-zero norm"):
        att.ekf_update(np.zeros(7), P, att.DEFAULT_Q0, 1e-10)
    with pytest.raises(ValueError, match="^P "):
        att.ekf_update(x, P[:6, :6], att.DEFAULT_Q0, 1e-10)
    with pytest.raises(ValueError, match="^attitude_sigma"):
        att.ekf_init(att.DEFAULT_Q0, attitude_sigma=0.0, drift_sigma=1.0)
    with pytest.raises(ValueError, match="^drift_sigma"):
        att.ekf_init(att.DEFAULT_Q0, attitude_sigma=1.0, drift_sigma=-1.0)


def test_attitude_ekf_converges_to_the_drifts():
    t, w, q = att.truth_motion(301, 0.1)
    wg = att.gyro_measurements(t, w, rng=2)
    qs = att.star_tracker_measurements(t, q, rng=3)
    f = att.AttitudeEKF(qs[0], 0.1, 0.05 * DPH, math.radians(att.PAPER_STAR_NOISE_DEG),
                        DPH, 100 * DPH)
    f.update(qs[0])
    for k in range(1, len(t)):
        f.predict(wg[k - 1, :3])
        f.update(qs[k])
    np.testing.assert_allclose(f.drift / DPH, att.PAPER_DRIFTS_DEG_PER_H[:3], atol=4.0)
    assert np.degrees(np.linalg.norm(qt.attitude_error(f.q, q[-1]))) < 0.005
    with pytest.raises(ValueError, match="^omega_g"):
        f.predict([0.0, np.nan, 0.0])
    with pytest.raises(ValueError, match="^q_meas"):
        f.update([0.0, 0.0, 1.0])
    with pytest.raises(ValueError, match="^dt "):
        att.AttitudeEKF(qs[0], -0.1, 0.0, 1e-4, 0.0, 1e-4)


def test_a_complex_sample_or_initial_attitude_is_refused_by_name():
    f = att.AttitudeEKF([0.0, 0.0, 0.0, 1.0], 0.1, 1e-6, 1e-4, 1e-7, 1e-6)
    with pytest.raises(ValueError, match="^omega_g must be 3 finite real numbers"):
        f.predict([0.0, 0.0, 1e-3 + 1e-9j])
    with pytest.raises(ValueError, match="^q_meas must be 4 finite real numbers"):
        f.update(np.array([0.0, 0.0, 0.0, 1.0]) + 0j)
    with pytest.raises(ValueError, match="^q0 must hold real numbers"):
        att.AttitudeEKF([0.0, 0.0, 1j, 1.0], 0.1, 1e-6, 1e-4, 1e-7, 1e-6)


@pytest.mark.parametrize(("call", "words"), [
    (lambda: att.ekf_init(att.DEFAULT_Q0, attitude_sigma=1e308, drift_sigma=1e-4),
     r"^attitude_sigma must be a real number in \(0, 3.14159\], got 1e\+308$"),
    (lambda: att.ekf_init(att.DEFAULT_Q0, attitude_sigma=1e-4, drift_sigma=1e308),
     r"^drift_sigma must be a real number in \(0, 1\], got 1e\+308$"),
    (lambda: att.ekf_predict(*att.ekf_init(att.DEFAULT_Q0, attitude_sigma=1e-4, drift_sigma=1e-4),
                             [0.0, 0.0, 0.0], 1e308, 1e-12, 0.0),
     r"^dt must be a real number in \(0, 10\], got 1e\+308$"),
    (lambda: att.ekf_predict(*att.ekf_init(att.DEFAULT_Q0, attitude_sigma=1e-4, drift_sigma=1e-4),
                             [0.0, 0.0, 0.0], 0.1, 1e300, 0.0),
     r"^gyro_cov must be a real number in \[0, 1\], got 1e\+300$"),
    (lambda: att.AttitudeEKF(att.DEFAULT_Q0, 0.1, 1e308, 1e-4, 0.0, 1e-4),
     r"^gyro_noise must be a real number in \[0, 1\], got 1e\+308$"),
    (lambda: att.AttitudeEKF(att.DEFAULT_Q0, 0.1, 0.0, 1e308, 0.0, 1e-4),
     r"^star_noise must be a real number in \(0, 3.14159\], got 1e\+308$"),
    (lambda: att.AttitudeEKF(att.DEFAULT_Q0, 0.1, 0.0, 1e-4, 1e308, 1e-4),
     r"^drift_walk must be a real number in \[0, 1\], got 1e\+308$"),
])
def test_a_setting_whose_square_overflows_is_refused_with_its_range(call, words):
    """Review 35e: 1e308 was an OverflowError or an overflow warning and an inf covariance."""
    with pytest.raises(ValueError, match=words):
        call()


def test_ekf_review_35i_refusals():
    """P, R as covariances; zero or scaled quaternions refused under the user's names."""
    x0, P0 = att.ekf_init(att.DEFAULT_Q0, attitude_sigma=1e-4, drift_sigma=1e-4)
    bad, skew = P0.copy(), P0.copy()
    bad[0, 0] = -1e-8
    skew[0, 1] = 1e-9
    with pytest.raises(ValueError, match=r"^P must be positive semi-definite"):
        att.ekf_predict(x0, bad, [0.0, 0.0, 0.0], 0.1, 1e-12, 0.0)
    with pytest.raises(ValueError, match=r"^P must be symmetric"):
        att.ekf_predict(x0, skew, [0.0, 0.0, 0.0], 0.1, 1e-12, 0.0)
    with pytest.raises(ValueError, match=r"^P must be positive semi-definite"):
        att.ekf_update(x0, bad, -att.DEFAULT_Q0, 1e-10)
    with pytest.raises(ValueError, match=r"^P must be positive semi-definite"):
        att.ekf_predict(x0[None], bad[None], [0.0, 0.0, 0.0], 0.1, 1e-12, 0.0)
    Rn = np.eye(4) * 1e-10 + np.triu(np.ones((4, 4)), 1) * 1e-11
    with pytest.raises(ValueError, match=r"^R must be symmetric"):
        att.ekf_update(x0, P0, -att.DEFAULT_Q0, Rn)
    with pytest.raises(ValueError, match=r"^q_meas must have a non-zero norm"):
        att.ekf_update(x0, P0, np.zeros(4), 1e-10)
    with pytest.raises(ValueError, match=r"^q_meas must be a unit quaternion"):
        att.ekf_update(x0, P0, 3 * att.DEFAULT_Q0, 1e-10)
    with pytest.raises(ValueError, match=r"^x\[\.\.\., :4\] must be a unit quaternion"):
        att.ekf_predict(np.r_[2 * att.DEFAULT_Q0, 0, 0, 0], P0, [0.0, 0.0, 0.0], 0.1, 1e-12, 0.0)
    with pytest.raises(ValueError, match=r"^q_meas must have a non-zero norm"):
        att.ekf_init(np.zeros(4), attitude_sigma=1e-4, drift_sigma=1e-4)
    with pytest.raises(ValueError, match=r"^q0 must have a non-zero norm"):
        att.SOSMonitor(np.zeros(4))
    for monitor in (att.SOSMonitor, att.DOSMonitor):
        with pytest.raises(ValueError, match=r"^q0 must be a 1-D array \(shape \(4,\)\)"):
            monitor(att.DEFAULT_Q0[None])


@pytest.mark.parametrize("q, words", [
    (np.zeros(4), "q_meas must have a non-zero norm"),
    (2.0 * np.asarray(att.DEFAULT_Q0), "q_meas must be a unit quaternion \\(norm 1 to 1e-06\\)")])
def test_attitude_ekf_update_refuses_a_zero_or_scaled_measurement(q, words):
    """Review 35l (5) 4: att.AttitudeEKF.update(np.zeros(4)) was taken and moved x and P."""
    f = att.AttitudeEKF(att.DEFAULT_Q0, 0.1, 0.05 * att.DEG_PER_H, 1e-4, att.DEG_PER_H, 100 * att.DEG_PER_H)
    f.predict([0.0, 0.0, 0.0])
    x, P = f.x.copy(), f.P.copy()
    with pytest.raises(ValueError, match=f"^{words}"):
        f.update(q)
    assert np.array_equal(f.x, x) and np.array_equal(f.P, P)
