"""The pieces of the XNAV innovation check (xnavlab.mars.faults.innovations): the short two-body
propagation, the per-level noise of the causal details, and the causal wavelet detector of the
whitened XNAV innovations."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from xnavlab.core.constants import GM_MARS
from xnavlab.core.detection import causal_filters
from xnavlab.mars.faults import innovations as inn


def _two_body(_, x):
    r = x[:3]
    return np.concatenate([x[3:], -GM_MARS * r / np.linalg.norm(r) ** 3])


@pytest.mark.parametrize("dt", [1.0, 6.0])
def test_two_body_taylor_errs_only_by_the_third_order_term(dt):
    """Second order in ``dt``: the error is below the jerk bound ``4 GM v / r^3 dt^3 / 6``."""
    x0 = np.array([4.0e6, 1.0e6, -5.0e5, -300.0, 2.9e3, 400.0])
    exact = solve_ivp(_two_body, (0.0, dt), x0, rtol=1e-12, atol=1e-9).y[:, -1]
    got = inn.two_body_taylor(x0, dt)
    jerk = 4.0 * GM_MARS * np.linalg.norm(x0[3:]) / np.linalg.norm(x0[:3]) ** 3
    assert np.linalg.norm(got[:3] - exact[:3]) < jerk * dt**3 / 6.0      # m
    assert np.linalg.norm(got[3:] - exact[3:]) < jerk * dt**2 / 2.0      # m/s


def test_two_body_taylor_broadcasts_over_leading_axes():
    x = np.array([[4.0e6, 0.0, 0.0, 0.0, 3.0e3, 0.0], [0.0, 5.0e6, 0.0, -2.5e3, 0.0, 0.0]])
    both = inn.two_body_taylor(x, 3.0)
    assert both.shape == (2, 6)
    np.testing.assert_array_equal(both[1], inn.two_body_taylor(x[1], 3.0))
    np.testing.assert_array_equal(inn.two_body_taylor(x, 0.0), x)


@pytest.mark.parametrize("level", [1, 3, 5])
def test_unit_sigma_is_the_norm_of_each_causal_filter(level):
    want = [np.linalg.norm(g) for g in causal_filters("db3", level)]
    np.testing.assert_allclose(inn.unit_sigma(level), want, rtol=1e-12)
    # the filtered details of unit white noise have that standard deviation
    rng = np.random.default_rng(1)
    g = causal_filters("db3", level)[-1]
    d = np.convolve(rng.standard_normal(200_000), g, mode="valid")
    assert np.std(d) == pytest.approx(inn.unit_sigma(level)[-1], rel=0.02)


def test_wavelet_stays_quiet_until_its_window_is_full_and_on_white_noise():
    w = inn.XnavInnovationWavelet(m=4, level=3, pfa=1e-6, holdoff=3)
    rng = np.random.default_rng(0)
    flags = [w.update(500.0 * k, rng.standard_normal(4)) for k in range(2000)]
    assert not any(flags[:w.window - 1])
    assert sum(flags) == 0 and not w.tracker.events


def test_wavelet_names_the_pulsar_of_a_step_and_clear_rearms_it():
    w = inn.XnavInnovationWavelet(m=3, level=3, pfa=1e-6, holdoff=3)
    rng = np.random.default_rng(2)
    onset = None
    for k in range(400):
        nu = rng.standard_normal(3)
        if k >= 200:
            nu[2] += 20.0
        if w.update(500.0 * k, nu) and onset is None:
            onset = k
            assert w.new_onset
    assert onset is not None and 200 <= onset < 200 + w.window
    assert w.tracker.events[0].test.startswith("pulsar 2, level ")
    w.clear()
    assert not w.tracker.faulty and w.count == w.window
    assert not w.update(500.0 * 400, np.zeros(3))              # a zero window: no detail


def test_two_body_taylor_refuses_complex_and_nan():
    with pytest.raises(ValueError, match="^x must hold real numbers"):
        inn.two_body_taylor(np.r_[4e6, 0, 0, 0, 3e3, 0] + 0j, 3.0)
    with pytest.raises(ValueError, match="^dt must contain only finite"):
        inn.two_body_taylor(np.r_[4e6, 0, 0, 0, 3e3, 0], np.nan)
