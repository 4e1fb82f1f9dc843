"""Review 35p: orbits through the planet (P1), a growing error past its size range (P3) and the
wording of the directions' shape (P15)."""

import re

import numpy as np
import pytest

from xnavlab import robust as rb
from xnavlab.core.constants import GM_EARTH
from xnavlab.robust import ephemeris_error as ee


@pytest.mark.parametrize("elements, bound", [
    ((1.0, 0.1, 10.0, 0.0, 0.0, 0.0), "7.08682e+06"),      # a = 1 m: positions of 1e30 m
    ((7e6, 0.5, 10.0, 0.0, 0.0, 0.0), "1.27563e+07"),      # perigee 3500 km: through the Earth
    ((6.0e6, 0.0, 10.0, 0.0, 0.0, 0.0), "6.37814e+06"),    # circular, below the surface
])
def test_p1_simulate_refuses_an_orbit_below_the_planet(elements, bound):
    words = (r"^elements\[0\] must put the perigee elements\[0\] \(1 - elements\[1\]\) at or above the "
             rf"radius of earth \(6\.37814e\+06 m\): elements\[0\] >= {re.escape(bound)} m with "
             rf"elements\[1\] = {elements[1]:g}, got {re.escape(f'{elements[0]:g}')}$")
    with pytest.raises(ValueError, match=words):
        rb.simulate(n_steps=30, elements=elements)
    with pytest.raises(ValueError, match=words):
        ee.orbit("earth", elements=elements)


def test_p1_elements_to_state_bounds_the_perigee_and_the_apogee():
    with pytest.raises(ValueError, match=r"^a must put the perigee a \(1 - e\) at or above the radius "
                                         r"of earth \(6\.37814e\+06 m\): a >= 7\.08682e\+06 m with "
                                         r"e = 0\.1, got 1$"):
        ee.elements_to_state(1.0, 0.1, 10, 0, 0, 0, GM_EARTH)
    with pytest.raises(ValueError, match=r"^elements\[0\] must keep the apogee elements\[0\] \(1 \+ "
                                         r"elements\[1\]\) within 1e\+15 m of the centre"):
        ee.orbit("mars", elements=(1e15, 0.5, 0.0, 0.0, 0.0, 0.0))
    with pytest.raises(ValueError,
                       match=r"^gm must be earth's or mars' .* unless radius .* is given, got 3e\+14$"):
        ee.elements_to_state(1e7, 0.1, 10, 0, 0, 0, 3e14)
    x = ee.elements_to_state(10.0, 0.1, 10, 0, 0, 0, 3e14, radius=1.0)   # a small body, its radius given
    assert np.linalg.norm(x[:3]) == pytest.approx(9.0)
    with pytest.raises(ValueError, match=r"^a must put the perigee a \(1 - e\) at or above the radius of "
                                         r"the central body \(100 m\)"):
        ee.elements_to_state(10.0, 0.1, 10, 0, 0, 0, 3e14, radius=100.0)
    # the orbit just clearing the surface is used; the chapter's orbits are unchanged
    r_e = ee.PLANETS["earth"][2]
    assert np.linalg.norm(ee.orbit("earth", elements=(r_e, 0.0, 0.0, 0.0, 0.0, 0.0)).state0[:3]) == \
        pytest.approx(r_e)
    np.testing.assert_array_equal(ee.orbit("earth", elements=ee.EARTH_ELEMENTS).state0,
                                  ee.orbit("earth").state0)


def test_p3_a_growing_error_beyond_the_size_range_is_refused():
    with pytest.raises(ValueError, match=r"^growth_time must keep the growing error within 1e\+08 m "
                                         r"\(the size range\) over the run's span t - t0 <= 1e\+12 s: with "
                                         r"size = 1e\+08 m, growth_time = 1 s it reaches 1e\+20 m at "
                                         r"t - t0 = 1e\+12 s; growth_time >= 1e\+12 s keeps it$"):
        ee.injected_error([0.0, 1e12], 1e8, "growing", growth_time=1.0)
    with pytest.raises(ValueError, match=r"^growth_time must keep the growing error within 1e\+08 m .*span "
                                         r"t - t0 <= 2e\+07 s: with size = 1e\+08 m, growth_time = 1 s it "
                                         r"reaches 2e\+15 m"):
        rb.simulate(error="growing", size=1e8, growth_time=1.0, n_steps=200, dt=1e5)
    with pytest.raises(ValueError,
                       match=r"^growth_time must keep .* it reaches 8e\+24 m at t - t0 = 2e\+07 s$"):
        rb.simulate(error="growing", size=1e3, growth_time=1.0, n_steps=200, dt=1e5,
                    profile=lambda s: s**3)


def test_p3_growth_within_the_range_is_kept_as_it_was():
    # the chapter's runs: growth_time = the run's span, the error ends at size (1e8 m at most)
    g = rb.simulate("mars", n_steps=4, error="growing", size=1e8, rng=1)
    assert np.linalg.norm(g.dr_e, axis=1).max() == pytest.approx(1e8)
    # a shorter growth_time keeps growing past size (not held), as documented, within the range
    s = ee.injected_error([0.0, 50.0, 200.0], 10.0, "growing", (0, 0, 1), growth_time=100.0)
    assert s[:, 2].tolist() == [0.0, 5.0, 20.0]
    q = ee.injected_error([0.0, 1e4], 1e6, "growing", (0, 0, 1), growth_time=1e3, profile="quadratic")
    assert q[-1, 2] == pytest.approx(1e8)


@pytest.mark.parametrize("n", [[2.0, 0.0, 0.0], [[[1.0, 0.0, 0.0]]], [[1.0, 0.0]]])
def test_p15_directions_shape_is_said_as_the_docstring_says(n):
    shape = str(np.shape(n)).replace("(", r"\(").replace(")", r"\)")
    with pytest.raises(ValueError,
                       match=rf"^n must have shape \(k, 3\), one pulsar a row, got shape {shape}$"):
        ee.xnav_range([1e7, 0, 0], [1e11, 0, 0], n)
    with pytest.raises(ValueError, match=r"^n must have shape \(k, 3\), one pulsar a row"):
        rb.filters.asukf_update(np.zeros(9), np.eye(9), np.zeros(3), np.eye(3), n)
