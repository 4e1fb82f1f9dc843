"""Ephemeris: shapes, units, physical sanity, coverage errors, DE405 vs DE421."""

import numpy as np
import pytest

from xnavlab.core import ephemeris
from xnavlab.core.constants import AU, DAY


@pytest.mark.parametrize("body", ephemeris.BODIES)
def test_state_shapes(body):
    r, v = ephemeris.state(body, 0.0)
    assert r.shape == (3,) and v.shape == (3,)
    r, v = ephemeris.state(body, [0.0, DAY, 2 * DAY])
    assert r.shape == (3, 3) and v.shape == (3, 3)


def test_vectorised_equals_per_epoch():
    t = np.linspace(0, 30 * DAY, 7)
    r, v = ephemeris.state("mars", t)
    for i, ti in enumerate(t):
        ri, vi = ephemeris.state("mars", ti)
        np.testing.assert_allclose(r[i], ri, rtol=0, atol=1e-6)
        np.testing.assert_allclose(v[i], vi, rtol=0, atol=1e-9)


def test_velocity_is_derivative_of_position():
    t0, h = 5.0e8, 10.0
    r1 = ephemeris.position("mars", t0 - h)
    r2 = ephemeris.position("mars", t0 + h)
    _, v = ephemeris.state("mars", t0)
    np.testing.assert_allclose((r2 - r1) / (2 * h), v, rtol=1e-7)  # Chebyshev fit level


def test_distances_are_physical():
    t = np.linspace(0, 365 * DAY, 13)
    for body, lo, hi in [("earth", 0.98, 1.02), ("mars", 1.37, 1.67), ("jupiter", 4.9, 5.5)]:
        d = np.linalg.norm(ephemeris.position(body, t) - ephemeris.position("sun", t), axis=1) / AU
        assert np.all((d > lo) & (d < hi)), body
    # the Sun stays within ~0.01 au of the barycentre
    assert np.all(np.linalg.norm(ephemeris.position("sun", t), axis=1) < 0.015 * AU)


def test_earth_moon_barycentre():
    r_e = ephemeris.position("earth", 0.0)
    r_m = ephemeris.position("moon", 0.0)
    r_emb = ephemeris.position("earthmoon", 0.0)
    d = np.linalg.norm(r_m - r_e)
    assert 3.5e8 < d < 4.1e8  # Earth-Moon distance
    # the EMB lies between them, closer to the Earth by the mass ratio (~81.3)
    ratio = np.linalg.norm(r_emb - r_e) / np.linalg.norm(r_m - r_emb)
    assert abs(ratio - 1 / 81.3) < 1e-3


def test_de405_and_de421_agree_to_kilometres_near_j2000():
    d = ephemeris.position("mars", 0.0, "de405") - ephemeris.position("mars", 0.0, "de421")
    assert np.linalg.norm(d) < 10e3


@pytest.mark.parametrize("ephem", ephemeris.EPHEMERIDES)
def test_epoch_outside_coverage_is_a_clear_error(ephem):
    lo, hi = ephemeris.coverage(ephem)
    with pytest.raises(ValueError, match="coverage of " + ephem.upper()):
        ephemeris.state("mars", hi + DAY, ephem)
    with pytest.raises(ValueError, match="t must lie in"):
        ephemeris.state("mars", [0.0, lo - DAY], ephem)


def test_bad_names():
    with pytest.raises(ValueError, match="body must be one of"):
        ephemeris.state("pluto-x", 0.0)
    with pytest.raises(ValueError, match="ephem must be one of"):
        ephemeris.state("mars", 0.0, "de440")
    with pytest.raises(ValueError, match="finite"):
        ephemeris.state("mars", np.nan)


def test_time_conversions_round_trip():
    t = np.array([-1e9, 0.0, 5.05e8])
    np.testing.assert_allclose(ephemeris.t_from_jd(ephemeris.jd_from_t(t)), t, atol=1e-6)


@pytest.mark.parametrize("bad", [1j, np.nan, "0"])
def test_time_conversions_refuse_complex_nan_and_text(bad):
    with pytest.raises(ValueError, match="^t must"):
        ephemeris.jd_from_t(bad)
    with pytest.raises(ValueError, match="^jd must"):
        ephemeris.t_from_jd(bad)


def test_t_from_jd_refuses_a_date_whose_seconds_overflow():
    """Review 35e: jd=1e308 gave inf seconds with an overflow warning."""
    with pytest.raises(ValueError, match=r"^jd must lie in \[-1e\+15, 1e\+15\] days, got 1e\+308$"):
        ephemeris.t_from_jd([2457388.5, 1e308])


def test_issue35_state_refuses_a_2d_t_by_name():
    # Review 35f finding 45: numpy's broadcast error named no parameter.
    with pytest.raises(ValueError, match=r"^t must be a number or a 1-D array of epochs"):
        ephemeris.state("mars", np.full((2, 2), 5e8))


T0 = 504878400.0  # 2016-01-01 00:00 TDB


@pytest.mark.parametrize("call", [ephemeris.position, lambda body, t: ephemeris.state(body, t)[0]])
def test_float32_epochs_are_refused(call):
    """Review 35 Q2: float32 rounds 5e8 s to 32 s, which moved Mars by up to 353 km without a
    word; refused as the timing terms refuse it. Epochs a float32 resolves to 1 ms are taken."""
    t = T0 + np.arange(0.0, 600.0, 60.0)
    with pytest.raises(ValueError, match=r"^t must resolve its epochs to 0.001 s: as float32 it resolves "
                                         r"32 s at 5.04879e\+08 s; pass float64 epochs$"):
        call("mars", t.astype(np.float32))
    small = np.arange(0.0, 600.0, 60.0)
    assert np.array_equal(call("mars", small.astype(np.float32)), call("mars", small))


def test_dates_and_quantities_are_refused_as_epochs():
    """Review 35 Q1: 2020-01-01 as datetime64 was read as 1.58e9 s past J2000 (the year 2050),
    one day as a Quantity as 1 s."""
    u = pytest.importorskip("astropy.units")
    with pytest.raises(ValueError, match=r"^t must be plain numbers in s TDB past J2000, got datetime64\[s\] "
                                         r"values: a date is no number; convert it \(to s TDB past J2000: "
                                         r"xnavlab.core.ephemeris.t_from_jd\(astropy.time.Time\(t\).tdb.jd\)\)$"):
        ephemeris.position("mars", np.array(["2020-01-01T00:00:00"], dtype="datetime64[s]"))
    with pytest.raises(ValueError, match=r"^t must be plain numbers in s TDB past J2000, got a Quantity "
                                         r"in d: its unit is not read"):
        ephemeris.position("mars", [1.0] * u.day)


def test_the_date_hint_gives_the_epoch():
    """The conversion the message names gives 2020-01-01 00:00 UTC as 6.311e8 s TDB past J2000."""
    time = pytest.importorskip("astropy.time")
    t = ephemeris.t_from_jd(time.Time(np.array(["2020-01-01T00:00:00"], dtype="datetime64[s]")).tdb.jd)
    assert abs(float(t[0]) - (631108800.0 + 69.184)) < 2e-3  # TT - UTC = 37 s + 32.184 s; TDB - TT < 2 ms


def test_check_epoch_refuses_a_float32_epoch():
    assert ephemeris.check_epoch("t0", np.float32(100.0)) == 100.0
    with pytest.raises(ValueError, match=r"^t0 must resolve its epochs to 0.001 s: as float32"):
        ephemeris.check_epoch("t0", np.float32(T0))
