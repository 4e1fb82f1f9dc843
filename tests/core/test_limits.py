"""Neyman-Pearson limits of fault detection (xnavlab.core.detection.limits)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

from xnavlab.core.detection import limits


def test_window_false_alarm_scales_with_the_window_and_caps_at_one():
    assert limits.window_false_alarm(1.0, 100.0, 10) == pytest.approx(0.1)
    assert limits.window_false_alarm(50.0, 100.0, 10) == 1.0
    for kwargs, name in (({"rate_per_day": 0.0}, "rate_per_day"),
                         ({"samples_per_day": -1.0}, "samples_per_day"), ({"n": 0}, "n")):
        with pytest.raises(ValueError, match=name):
            limits.window_false_alarm(**({"rate_per_day": 1.0, "samples_per_day": 100.0, "n": 5} | kwargs))


@given(st.floats(0.0, 6.0), st.floats(1e-4, 0.5))
def test_mean_shift_limit_is_the_size_at_zero_and_grows_with_the_shift(d, alpha):
    p0 = limits.mean_shift_pd_limit([0.0], alpha)
    assert p0 == pytest.approx(alpha, rel=1e-9)
    assert limits.mean_shift_pd_limit([d], alpha) >= p0 - 1e-12
    assert limits.mean_shift_pd_limit([d, 0.5], alpha) >= limits.mean_shift_pd_limit([d], alpha) - 1e-12


def test_mean_shift_limit_matches_a_simulated_likelihood_ratio_test():
    rng = np.random.default_rng(3)
    mu = limits.ramp_means([0.3, 0.1], 6)
    w = mu.ravel() / np.linalg.norm(mu)
    thr = stats.norm.isf(0.05)
    z = rng.normal(size=(200_000, mu.size)) + mu.ravel()
    assert np.mean(z @ w > thr) == pytest.approx(limits.mean_shift_pd_limit(mu, 0.05), abs=0.005)


def test_ramp_means_and_their_errors():
    np.testing.assert_allclose(limits.ramp_means([1.0, 2.0], 2, phase=0.5), [[0.5, 1.0], [1.5, 3.0]])
    with pytest.raises(ValueError, match="phase"):
        limits.ramp_means([1.0], 2, phase=0.0)


def test_noise_limit_single_component_matches_the_chi_square_form_and_is_reproducible():
    exact = stats.chi2.sf(stats.chi2.isf(0.03, 6) / 9.0, 6)
    p = limits.noise_pd_limit([3.0], 6, 0.03, rng=5)
    assert p == pytest.approx(exact, abs=0.005)
    assert limits.noise_pd_limit([3.0], 6, 0.03, rng=5) == p
    assert limits.noise_pd_limit([1.0, 1.0], 4, 0.02) == 0.02       # no change: only the size
    for bad, name in ((dict(ratios=[0.5]), "ratios"), (dict(alpha=1.0), "alpha"), (dict(n=0), "n"),
                      (dict(draws=10), "draws")):
        with pytest.raises(ValueError, match=name):
            limits.noise_pd_limit(**({"ratios": [2.0], "n": 3, "alpha": 0.1} | bad))


@settings(max_examples=20, deadline=None)
@given(st.floats(1.0, 4.0), st.floats(0.0, 2.0))
def test_noise_limit_grows_with_the_ratio(r, extra):
    assert limits.noise_pd_limit([r + extra], 5, 0.05, draws=20_000, rng=1) >= \
        limits.noise_pd_limit([r], 5, 0.05, draws=20_000, rng=1) - 0.02


@pytest.mark.parametrize(("call", "match"), [
    (lambda: limits.ramp_means([0.5], 10**30), r"n must be an integer in \[1, 10000000\]"),
    (lambda: limits.noise_pd_limit([3.0], 6, 0.03, draws=10**30), r"draws must be an integer in \[1000, "),
])
def test_a_count_beyond_max_samples_is_refused(call, match):
    with pytest.raises(ValueError, match=match):
        call()


@pytest.mark.parametrize(("call", "match"), [
    (lambda: limits.mean_shift_pd_limit([], 0.05), r"^mu must hold at least one mean"),
    (lambda: limits.ramp_means([], 3), r"^slopes must be a 1-D array of at least one"),
    (lambda: limits.noise_pd_limit([], 6, 0.05), r"^ratios must be a 1-D array of at least one value >= 1"),
])
def test_an_empty_input_is_refused_not_answered_with_alpha(call, match):
    with pytest.raises(ValueError, match=match):
        call()
