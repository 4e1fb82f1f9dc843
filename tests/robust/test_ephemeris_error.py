"""Tests of xnavlab.robust.ephemeris_error: the DE421 - DE405 error, directions, measurement, dynamics."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from xnavlab.core import ephemeris
from xnavlab.core.constants import GM_EARTH, GM_MARS, J2_EARTH, J2_EARTH_RADIUS
from xnavlab.mars.timing import pulsars
from xnavlab.robust import ephemeris_error as ee


def test_ephemeris_error_is_de421_minus_de405():
    t = ee.EPOCH_1997 + np.array([0.0, 3600.0])
    d = ee.ephemeris_error("mars", t)
    want = ephemeris.position("mars", t, "de421") - ephemeris.position("mars", t, "de405")
    assert d.shape == (2, 3)
    np.testing.assert_allclose(d, want)
    assert np.allclose(ee.ephemeris_error("earth", 0.0, "de421", "de421"), 0.0)


def test_ephemeris_error_size_and_slow_variation():
    for body in ("earth", "mars"):
        s = ee.error_summary(body, ee.EPOCH_1997, ee.YEAR / 365.25, n=5)
        assert 100.0 < s["mean_m"] < 1e4
        assert abs(s["change_m"]) < 50.0  # metres per day
        assert s["t"].shape == s["norm"].shape == (5,)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [({"body": "venus"}, "body"), ({"span": -1.0}, "span"), ({"n": 1}, "n"), ({"t0": math.nan}, "t0")],
)
def test_error_summary_rejects_bad_input(kwargs, name):
    args = {"body": "earth"} | kwargs
    with pytest.raises(ValueError, match=name):
        ee.error_summary(**args)


def test_ephemeris_error_rejects_unknown_body():
    with pytest.raises(ValueError, match="body"):
        ee.ephemeris_error("pluto", 0.0)


def test_injected_error():
    d = ee.injected_error([0.0, 1.0], 300.0, direction=[0.0, 0.0, 2.0])
    np.testing.assert_allclose(d, [[0, 0, 300.0], [0, 0, 300.0]])
    slow = ee.injected_error(np.linspace(0, ee.YEAR, 101), 100.0, "slow")
    norms = np.linalg.norm(slow, axis=1)
    assert 119.0 < norms.max() <= 120.0 + 1e-9 and 80.0 - 1e-9 <= norms.min() < 81.0
    for kwargs, name in (({"size": -1.0}, "size"), ({"kind": "ramp"}, "kind"),
                         ({"direction": [0, 0, 0]}, "direction"), ({"period": 0.0}, "period"),
                         ({"kind": "growing"}, "growth_time"),
                         ({"kind": "growing", "growth_time": 1.0, "profile": "cubic"}, "profile")):
        with pytest.raises(ValueError, match=name):
            ee.injected_error(0.0, **({"size": 1.0} | kwargs))


@given(st.floats(0.0, 2.0), st.sampled_from(ee.PROFILES))
def test_growing_error_starts_at_zero_and_reaches_its_size(s, profile):
    t = np.array([-5.0, 0.0, s * 100.0, 100.0])
    g = np.linalg.norm(ee.injected_error(t, 50.0, "growing", growth_time=100.0, profile=profile), axis=1)
    assert g[0] == 0.0 and g[1] == 0.0  # zero before and at the start
    assert abs(g[3] - 50.0) < 1e-9  # the full size at growth_time
    assert 0.0 <= g[2] <= 50.0 * max(1.0, s * s, s) + 1e-9


def test_growth_profile_callable_and_drift():
    f = ee.growth_profile([0.0, 0.5, 1.0], lambda s: np.sin(np.pi / 2 * s))
    np.testing.assert_allclose(f, [0.0, np.sqrt(0.5), 1.0])
    with pytest.raises(ValueError, match="profile"):
        ee.growth_profile([0.5], lambda s: s + 1.0)
    t = ee.EPOCH_1997 + np.array([0.0, 86400.0])
    d = ee.ephemeris_drift("earth", t, ee.EPOCH_1997)
    assert np.linalg.norm(d[0]) == 0.0 and 1.0 < np.linalg.norm(d[1]) < 50.0


@given(st.floats(0.0, 360.0), st.floats(-90.0, 90.0))
def test_pulsar_direction_unit_and_orders(ra, dec):
    n = ee.pulsar_direction(ra, dec)
    p = ee.pulsar_direction(ra, dec, order="paper")
    assert abs(np.linalg.norm(n) - 1.0) < 1e-12
    np.testing.assert_allclose(p, n[[1, 0, 2]], atol=1e-15)  # the paper swaps x and y


def test_pulsar_direction_matches_catalogue():
    for name in ee.PULSARS:
        p = pulsars.get(name)
        np.testing.assert_allclose(ee.pulsar_direction(p.ra_deg, p.dec_deg), p.direction, atol=1e-15)
    assert ee.directions().shape == (3, 3)
    with pytest.raises(ValueError, match="order"):
        ee.pulsar_direction(0.0, 0.0, "weird")
    with pytest.raises(ValueError, match="dec_deg"):
        ee.pulsar_direction(0.0, 91.0)
    for names, message in (((), r"^names must name at least one pulsar"),
                           ("B0531+21", r"^names must be a list of pulsars, got the string"),
                           (("B0531+21", "B0531+21"), r"^names lists B0531\+21 twice")):
        with pytest.raises(ValueError, match=message):
            ee.directions(names)


def test_sigma_matches_ranging_accuracy():
    for name, sigma in zip(ee.PULSARS, ee.SIGMA_M, strict=True):
        assert abs(pulsars.ranging_accuracy(name) - sigma) / sigma < 0.02


def test_xnav_range():
    n = ee.directions()
    r, rp = np.array([7e6, 1e6, -2e6]), np.array([1.4e11, -3e10, 2e10])
    np.testing.assert_allclose(ee.xnav_range(r, rp, n), n @ (r + rp))
    assert ee.xnav_range(np.zeros((4, 3)), rp, n).shape == (4, 3)
    with pytest.raises(ValueError, match="r_planet"):
        ee.xnav_range(r, [1.0, 2.0], n)
    with pytest.raises(ValueError, match="n"):
        ee.xnav_range(r, rp, [[np.nan, 0, 0]])


def test_acceleration_two_body_plus_j2():
    r = np.array([7e6, 0.0, 0.0])
    a = ee.acceleration(r, "earth")
    pm = -GM_EARTH / 7e6**2
    j2 = -1.5 * J2_EARTH * GM_EARTH * J2_EARTH_RADIUS**2 / 7e6**4  # equatorial J2 term, EGM2008 radius
    np.testing.assert_allclose(a, [pm + j2, 0.0, 0.0], rtol=1e-12)
    assert ee.acceleration(np.tile(r, (3, 1)), "mars").shape == (3, 3)
    with pytest.raises(ValueError, match="body"):
        ee.acceleration(r, "moon")


def test_propagate_conserves_energy_without_j2_error_growth():
    o = ee.orbit("mars")
    x1 = ee.propagate(o.state0, 8252.0, "mars")
    x2 = ee.propagate(o.state0, 8252.0, "mars", substep=5.0)
    assert np.max(np.abs(x1[:3] - x2[:3])) < 0.5
    rows = ee.propagate(np.tile(o.state0, (2, 1)), 100.0, "mars")
    np.testing.assert_allclose(rows[0], rows[1])
    for kwargs, name in (({"dt": math.inf}, "dt"), ({"substep": 0.0}, "substep"), ({"body": "x"}, "body")):
        with pytest.raises(ValueError, match=name):
            ee.propagate(o.state0, **({"dt": 10.0, "body": "mars"} | kwargs))


def test_elements_to_state_circular():
    x = ee.elements_to_state(7e6, 0.0, 90.0, 0.0, 0.0, 90.0, GM_MARS)
    np.testing.assert_allclose(x[:3], [0.0, 0.0, 7e6], atol=1e-6)
    assert abs(np.linalg.norm(x[3:]) - math.sqrt(GM_MARS / 7e6)) < 1e-9
    with pytest.raises(ValueError, match="e"):
        ee.elements_to_state(7e6, 1.0, 0, 0, 0, 0, GM_MARS)


def test_orbit():
    e = ee.orbit("earth")
    assert e.body == "earth" and e.state0.shape == (6,) and e.t0 == ee.EPOCH_1997
    m = ee.orbit("mars", t0=0.0)
    assert m.t0 == 0.0
    u = ee.orbit("earth", elements=(8e6, 0.1, 30, 10, 20, 0))
    assert abs(np.linalg.norm(u.state0[:3]) - 7.2e6) < 1e-3
    with pytest.raises(ValueError, match="elements"):
        ee.orbit("earth", elements=(1.0, 2.0))


def test_compiled_model_matches_the_dynamics_module():
    # the batched RK4 model here and xnavlab.mars.models.dynamics must describe the same Mars physics
    from xnavlab.mars.models import dynamics

    r = dynamics.MARS_STATE0[:3]
    expected = dynamics.point_mass(r) + dynamics.j2_acceleration(r)
    np.testing.assert_allclose(ee.acceleration(r, "mars"), expected, rtol=1e-13)


def test_elements_to_state_takes_a_semi_major_axis_from_1_m():
    """Issue 35: a subnormal axis failed an eigendecomposition downstream (the speed overflowed)."""
    for a in (5e-324, 0.5):
        with pytest.raises(ValueError, match=r"^a must be a real number in \[1, 1e\+15\]"):
            ee.elements_to_state(a, 0.0, 0.0, 0.0, 0.0, 0.0, GM_MARS)
    # a body of 1 m radius (review 35p P1: by default the perigee must clear the planet)
    assert np.all(np.isfinite(ee.elements_to_state(1.0, 0.0, 0.0, 0.0, 0.0, 0.0, GM_MARS, radius=1.0)))


def test_review_35i_refusals():
    """A position inside the planet, zero or scaled directions, growth settings of a constant error."""
    with pytest.raises(ValueError, match=r"^r must lie between the radius of earth"):
        ee.acceleration([0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"^r must lie between the radius of earth"):
        ee.acceleration([1.0, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"^x\[:3\] must lie between the radius of earth"):
        ee.propagate(np.zeros(6), 500.0)
    with pytest.raises(ValueError, match=r"^n must hold unit directions, got a zero row"):
        ee.xnav_range([1.0, 2.0, 3.0], np.zeros(3), np.zeros((3, 3)))
    with pytest.raises(ValueError, match=r"^n must hold unit directions \(norm 1"):
        ee.xnav_range([1.0, 2.0, 3.0], np.zeros(3), 5 * np.eye(3))
    for kwargs, name in (({"profile": "sqrt"}, "profile"), ({"growth_time": 5.0}, "growth_time")):
        with pytest.raises(ValueError, match=rf"^{name} shapes a growing error only"):
            ee.injected_error(0.0, 100.0, **kwargs)
        with pytest.raises(ValueError, match=rf"^{name} shapes a growing error only"):
            ee.injected_error(0.0, 100.0, "slow", **kwargs)


@pytest.mark.parametrize("t0", [None, "1.0", math.nan, 1e300])
def test_review_35k_1_8_3_5_5_5_injected_error_t0(t0):
    """Review 35k (1) 8, (3) 5, (5) 5: a growing error's t0 of None or text was a TypeError, NaN
    was refused as the internal ``s``, and 1e300 put every epoch before the onset (all zeros)."""
    with pytest.raises(ValueError, match=r"^t0 must be an epoch in \["):
        ee.injected_error([0.0, 50.0, 100.0], 10.0, "growing", (0, 0, 1), growth_time=100.0, t0=t0)


@pytest.mark.parametrize("kwargs", [{"t0": None}, {"t0": "1.0"}, {"t0": math.nan}, {"period": 1e300}])
def test_review_35k_5_4_injected_error_unused_t0_period(kwargs):
    """Review 35k (5) 4: a constant error's t0 and period (unused) were accepted unchecked."""
    name = next(iter(kwargs))
    with pytest.raises(ValueError, match=rf"^{name} shapes a .*error only .*leave {name} out"):
        ee.injected_error(0.0, 100.0, **kwargs)
    with pytest.raises(ValueError, match=r"^period must be a real number in \[1, inf\)"):
        ee.injected_error(0.0, 100.0, "slow", period=5e-324)
    assert ee.injected_error(0.0, 100.0, t0=0.0).shape == (3,)  # the default, typed: accepted


def test_review_35k_1_9_propagate_substep():
    """Review 35k (1) 9: a subnormal substep was an OverflowError (the count of RK4 steps)."""
    x0 = ee.orbit("earth").state0
    for substep in (5e-324, 1e-9):
        with pytest.raises(ValueError, match=r"^substep must be at least \|dt\| / 1e\+07 = 5e-05 s"):
            ee.propagate(x0, 500.0, substep=substep)
    assert np.array_equal(ee.propagate(x0, 0.0, substep=5e-324), x0)  # no step at all


@pytest.mark.parametrize("elements", [1.0, True, -1, math.nan, "abcdef", [1.0] * 5])
def test_review_35k_1_10_orbit_elements(elements):
    """Review 35k (1) 10: elements that are no sequence were a TypeError ('not iterable')."""
    with pytest.raises(ValueError, match=r"^elements must be"):
        ee.orbit("earth", elements=elements)


def test_review_35k_1_10_orbit_elements_named_by_index():
    """Review 35k (1) 10 (pattern B): an element out of range was named a, e, ... (the inner
    function's names), not elements[i]."""
    with pytest.raises(ValueError, match=r"^elements\[1\] must be a real number in \[0, 1\)"):
        ee.orbit("earth", elements=(7e6, 1.5, 0.0, 0.0, 0.0, 0.0))
    with pytest.raises(ValueError, match=r"^elements\[0\] must be a real number"):
        ee.orbit("earth", elements=(math.nan, 0.0, 0.0, 0.0, 0.0, 0.0))
    o = ee.orbit("earth", elements=np.array(ee.EARTH_ELEMENTS))
    assert np.array_equal(o.state0, ee.orbit("earth").state0)


def test_review_35k_3_3_3_4_names_of_the_caller():
    """Review 35k (3) 3, (3) 4: truth/model were refused as ``ephem``, and t0 = 1e300 of
    error_summary as the ephemeris' ``t``."""
    t = [ee.EPOCH_1997, ee.EPOCH_1997 + 3600.0]
    with pytest.raises(ValueError, match=r"^truth must be one of 'de421', 'de405', got ''"):
        ee.ephemeris_error("mars", t, truth="")
    with pytest.raises(ValueError, match=r"^model must be one of"):
        ee.ephemeris_drift("earth", ee.EPOCH_1997, ee.EPOCH_1997, model="x")
    with pytest.raises(ValueError, match=r"^t_ref must be an epoch in \["):
        ee.ephemeris_drift("earth", ee.EPOCH_1997, 1e300)
    with pytest.raises(ValueError, match=r"^t0 must be an epoch in \["):
        ee.error_summary("earth", t0=1e300)
    with pytest.raises(ValueError, match=r"^span must end the run within the ephemerides"):
        ee.error_summary("earth", t0=6.3e9, span=5 * ee.YEAR)
    with pytest.raises(ValueError, match=r"^t0 must be an epoch in \["):
        ee.orbit("earth", t0=None)


def test_float32_epochs_are_refused():
    """Review 35 Q2: float32 epochs (32 s at 5e8 s) were used silently by ephemeris_error,
    injected_error and ephemeris_drift; refused by name, as the timing terms refuse them."""
    t0 = 504878400.0
    t = t0 + np.arange(0.0, 600.0, 60.0)
    rounded = r" must resolve its epochs to 0.001 s: as float32 it resolves 32 s at 5.0487[89]e\+08 s"
    for name, call in (
            ("t", lambda: ee.ephemeris_error("mars", t.astype(np.float32))),
            ("t", lambda: ee.injected_error(t.astype(np.float32), 100.0, "growing", growth_time=1e9, t0=t0)),
            ("t0", lambda: ee.injected_error(t, 100.0, "growing", growth_time=1e9, t0=np.float32(t0))),
            ("t", lambda: ee.ephemeris_drift("mars", t.astype(np.float32), t0)),
            ("t_ref", lambda: ee.ephemeris_drift("mars", t, np.float32(t0)))):
        with pytest.raises(ValueError, match=rf"^{name}{rounded}"):
            call()
    small = np.arange(0.0, 600.0, 60.0)  # a float32 that resolves them: the same result
    assert np.array_equal(ee.injected_error(small.astype(np.float32), 100.0, "slow"),
                          ee.injected_error(small, 100.0, "slow"))


def test_dates_are_refused_as_epochs():
    """Review 35 Q1: a datetime64 epoch names its unit."""
    with pytest.raises(ValueError, match=r"^t must be plain numbers in s TDB past J2000, got datetime64"):
        ee.injected_error(np.array(["2020-01-01"], dtype="datetime64[D]"), 100.0)
