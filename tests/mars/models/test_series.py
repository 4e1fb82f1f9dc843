"""The compiled UV and CNS measurement series (xnavlab.mars.models.series), by their properties: without
noise they are the exact range, direction and starlight angle; with noise the range error and the
direction's turn have the model's size, and every direction stays a unit vector. (Their equality
with the sensor models' numpy code is tested in tests/mars/navigation/test_scenarios.py.)"""

import numpy as np
import pytest

from xnavlab.mars.models import series

R = np.random.default_rng(11).normal(size=(4000, 3)) * 4e6
STATES = np.hstack([R, np.random.default_rng(12).normal(size=(4000, 3))])
STATES[0, :3] = [0.0, 0.0, 4e6]                 # on the pole of the tangent basis


def test_uv_without_noise_is_the_range_and_the_unit_vector_to_mars():
    z = series.simulate_uv(STATES, np.zeros((4000, 3)), 5000.0, 1e-3, np.empty((4000, 4)))
    rn = np.linalg.norm(STATES[:, :3], axis=1)
    np.testing.assert_allclose(z[:, 0], rn, rtol=1e-15)
    np.testing.assert_allclose(z[:, 1:], -STATES[:, :3] / rn[:, None], atol=1e-15)


def test_uv_noise_has_the_model_size_and_keeps_unit_vectors():
    w = np.random.default_rng(1).standard_normal((4000, 3))
    sigma_dir = 1e-3
    z = series.simulate_uv(STATES, w, 5000.0, sigma_dir, np.empty((4000, 4)))
    rn = np.linalg.norm(STATES[:, :3], axis=1)
    np.testing.assert_allclose(z[:, 0] - rn, 5000.0 * w[:, 0], rtol=1e-9, atol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(z[:, 1:], axis=1), 1.0, atol=1e-15)
    turn = np.arccos(np.clip(np.sum(z[:, 1:] * (-STATES[:, :3] / rn[:, None]), axis=1), -1, 1))
    # the turn is sigma |w|: its magnitude is the tangent draws' norm
    np.testing.assert_allclose(turn, sigma_dir * np.hypot(w[:, 1], w[:, 2]), rtol=1e-6, atol=1e-9)


def test_cns_without_noise_is_the_angle_between_mars_and_each_star():
    stars = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.6, 0.8]])
    a = series.simulate_cns(STATES, np.zeros((4000, 8)), stars, 1e-5, 1e-3, np.empty((4000, 3)))
    to_mars = -STATES[:, :3] / np.linalg.norm(STATES[:, :3], axis=1, keepdims=True)
    np.testing.assert_allclose(np.cos(a), to_mars @ stars.T, atol=1e-12)
    assert np.all((a >= 0.0) & (a <= np.pi))


def test_cns_angle_noise_is_the_horizon_and_star_noise_combined():
    stars = np.array([[0.0, 1.0, 0.0]])
    sig_s, sig_h = 1e-5, 1e-3
    clean = series.simulate_cns(STATES, np.zeros((4000, 4)), stars, sig_s, sig_h, np.empty((4000, 1)))
    w = np.random.default_rng(2).standard_normal((4000, 4))
    noisy = series.simulate_cns(STATES, w, stars, sig_s, sig_h, np.empty((4000, 1)))
    # one tangent axis of each direction moves the angle: std sqrt(sig_h^2 + sig_s^2)
    assert np.std(noisy - clean) == pytest.approx(np.hypot(sig_s, sig_h), rel=0.1)


def test_the_series_are_written_into_out():
    out = np.empty((4000, 4))
    assert series.simulate_uv(STATES, np.zeros((4000, 3)), 1.0, 1e-3, out) is out
