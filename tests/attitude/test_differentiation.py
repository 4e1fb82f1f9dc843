"""Differentiating the star-tracker quaternions (xnavlab.attitude.differentiation): the rate's
noise against its prediction and the gyro-fault estimates with their decision."""

import math

import numpy as np
import pytest

from xnavlab import attitude as att


def test_quaternion_rate_noise_matches_prediction():
    t, w, q = att.truth_motion(1001, 0.1, wobble_deg_s=0.0)
    qs = att.star_tracker_measurements(t, q, rng=5)
    wq = att.quaternion_rate(qs, 0.1, 10.0)
    assert wq.shape == (901, 3)
    M = 100
    sigma = math.radians(att.PAPER_STAR_NOISE_DEG) * math.sqrt(12 / (M * (M + 1) * (M + 2))) / 0.1
    assert np.std(wq - w[0]) == pytest.approx(sigma, rel=0.35)
    # sign flips of the measured quaternion do not matter
    flipped = qs.copy()
    flipped[::7] *= -1
    np.testing.assert_allclose(att.quaternion_rate(flipped, 0.1, 10.0), wq, atol=1e-15)
    with pytest.raises(ValueError, match="^window_s"):
        att.quaternion_rate(qs, 0.1, 0.1)
    with pytest.raises(ValueError, match="^q_meas"):
        att.quaternion_rate(qs[:50], 0.1, 10.0)


def test_qdiff_fault_estimates_and_decision():
    t, w, q = att.truth_motion(301, 0.1)
    f = att.qdiff_fault_estimates(w + [1e-4, 0, 0], q, 0.1, 5.0)
    assert f.shape == (251, 3)
    # the wobble's curvature over the 5 s window: ~3e-8 rad/s (0.006 deg/h)
    np.testing.assert_allclose(f, np.tile([1e-4, 0, 0], (251, 1)), atol=1e-7)
    assert att.qdiff_decide(np.array([False, False, False])) == "none"
    assert att.qdiff_decide(np.array([[False, True, False]])).tolist() == ["gyro_y"]
    with pytest.raises(ValueError, match="^omega_g"):
        att.qdiff_fault_estimates(w[:, :2], q, 0.1, 5.0)
    with pytest.raises(ValueError, match=r"^q_meas must have as many samples as omega_g \(300\), got 301$"):
        att.qdiff_fault_estimates(w[:-1], q, 0.1, 5.0)


def test_a_window_beyond_a_day_is_refused_not_an_overflow():
    """Review 35e: window_s=1e308 was 'OverflowError: cannot convert float infinity to integer'."""
    t, w, q = att.truth_motion(201, 0.1, wobble_deg_s=0.0)
    for call in (lambda: att.quaternion_rate(q, 0.1, 1e308),
                 lambda: att.qdiff_fault_estimates(w, q, 0.1, 1e308)):
        with pytest.raises(ValueError, match=r"^window_s must be a real number in \[0.2, 86400\]"):
            call()
    with pytest.raises(ValueError, match=r"^dt must be a real number in \[1e-06, 10\], got 1e\+308$"):
        att.quaternion_rate(q, 1e308)


def test_a_subnormal_sample_interval_is_refused_not_an_overflow():
    """Issue 35: dt=5e-324 made window_s / dt inf ('OverflowError: cannot convert float
    infinity to integer')."""
    t, w, q = att.truth_motion(201, 0.1, wobble_deg_s=0.0)
    for call in (lambda: att.quaternion_rate(q, 5e-324), lambda: att.qdiff_fault_estimates(w, q, 5e-324)):
        with pytest.raises(ValueError, match=r"^dt must be a real number in \[1e-06, 10\], got 5e-324$"):
            call()


def test_quaternion_rate_review_35i_refusals():
    """Zero rows (numpy's warning) and scaled quaternions (a scaled rate) refused."""
    t, w, q = att.truth_motion(201, 0.1, wobble_deg_s=0.0)
    with pytest.raises(ValueError, match=r"^q_meas must have a non-zero norm"):
        att.quaternion_rate(np.zeros((201, 4)), 0.1, 10.0)
    with pytest.raises(ValueError, match=r"^q_meas must be a unit quaternion"):
        att.quaternion_rate(3 * q, 0.1, 10.0)
    qz = q.copy()
    qz[5] = 0.0
    with pytest.raises(ValueError, match=r"^q_meas must have a non-zero norm"):
        att.qdiff_fault_estimates(w + 1e-4, qz, 0.1, 10.0)
