"""WGS-84 geodesy, pseudoranges and the linearised PL/INS measurement (xnavlab.plins.pseudolites)."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from xnavlab.core.faults import Fault
from xnavlab.plins import ins
from xnavlab.plins import pseudolites as pl

finite = dict(allow_nan=False, allow_infinity=False)
lats = st.floats(-89.99, 89.99, **finite)
lons = st.floats(-179.99, 180.0, **finite)
heights = st.floats(-1000.0, 1e5, **finite)


@given(lat_deg=lats, lon_deg=lons, h=heights)
def test_geodetic_round_trip(lat_deg, lon_deg, h):
    lat, lon = math.radians(lat_deg), math.radians(lon_deg)
    lat2, lon2, h2 = pl.ecef_to_geodetic(pl.geodetic_to_ecef(lat, lon, h))
    assert abs(lat2 - lat) < 1e-11
    assert abs(math.remainder(lon2 - lon, 2 * math.pi)) < 1e-11
    assert abs(h2 - h) < 1e-6


@given(
    r=st.lists(st.floats(-8e6, 8e6, **finite), min_size=3, max_size=3).filter(
        lambda r: 6.2e6 < np.linalg.norm(r) < 8e6
    )
)
def test_ecef_round_trip(r):
    lat, lon, h = pl.ecef_to_geodetic(r)
    np.testing.assert_allclose(pl.geodetic_to_ecef(lat, lon, h), r, atol=1e-6)


def test_known_points_and_poles():
    b = ins.WGS84_A * (1 - ins.WGS84_F)
    np.testing.assert_allclose(pl.geodetic_to_ecef(math.pi / 2, 0.0, 0.0), [0, 0, b], atol=1e-6)
    lat, _, h = pl.ecef_to_geodetic([0.0, 0.0, -b - 100.0])
    assert lat == pytest.approx(-math.pi / 2) and h == pytest.approx(100.0, abs=1e-6)
    r = pl.geodetic_to_ecef(np.zeros(3), np.zeros(3), np.array([0.0, 1.0, 2.0]))
    assert r.shape == (3, 3)
    with pytest.raises(ValueError, match="lat"):
        pl.geodetic_to_ecef(2.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="h"):
        pl.geodetic_to_ecef(0.0, 0.0, -4e6)
    with pytest.raises(ValueError, match="r"):
        pl.ecef_to_geodetic([1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="r"):
        pl.ecef_to_geodetic([1.0, 2.0])


@given(lat_deg=lats, lon_deg=lons, h=heights)
def test_geodetic_jacobian_against_finite_differences(lat_deg, lon_deg, h):
    lat, lon = math.radians(lat_deg), math.radians(lon_deg)
    T = pl.geodetic_jacobian(lat, lon, h)
    steps = (1e-7, 1e-7, 1.0)
    for i, dx in enumerate(steps):
        e = np.zeros(3)
        e[i] = dx
        hi = pl.geodetic_to_ecef(lat + e[0], lon + e[1], h + e[2])
        lo = pl.geodetic_to_ecef(lat - e[0], lon - e[1], h - e[2])
        fd = (hi - lo) / (2 * dx)
        # rounding of ECEF coordinates (1e-9 m) over the step sets the absolute tolerance
        np.testing.assert_allclose(T[:, i], fd, rtol=1e-6, atol=1e-8 * np.linalg.norm(fd))


@given(lat_deg=lats, lon_deg=lons)
def test_enu_matrix(lat_deg, lon_deg):
    lat, lon = math.radians(lat_deg), math.radians(lon_deg)
    C = pl.enu_matrix(lat, lon)
    np.testing.assert_allclose(C @ C.T, np.eye(3), atol=1e-14)
    T = pl.geodetic_jacobian(lat, lon, 0.0)
    np.testing.assert_allclose(C[2], T[:, 2], atol=1e-14)  # up = d r / d h
    assert C[0] @ T[:, 1] > 0 and C[1] @ T[:, 0] > 0  # east ~ longitude, north ~ latitude


def test_enu_and_jacobian_bad_input():
    with pytest.raises(ValueError, match="lat"):
        pl.enu_matrix(4.0, 0.0)
    with pytest.raises(ValueError, match="lon"):
        pl.geodetic_jacobian(0.0, math.nan, 0.0)


def test_sites_pseudoranges_los():
    S = pl.sites_ecef()
    assert S.shape == (4, 3)
    lat, lon, h = pl.ecef_to_geodetic(S)
    np.testing.assert_allclose(np.degrees(lat), pl.DEFAULT_SITES_DEG[:, 0], atol=1e-10)
    r = pl.geodetic_to_ecef(math.radians(39.1), math.radians(116.0), 1e4)
    rho = pl.pseudoranges(r, S)
    assert rho.shape == (4,) and np.all((rho > 1e4) & (rho < 6e4))
    assert pl.pseudoranges(np.stack([r, r]), S).shape == (2, 4)
    E = pl.los_matrix(r, S)
    np.testing.assert_allclose(np.linalg.norm(E, axis=1), 1.0)
    np.testing.assert_allclose(r + rho[:, None] * E, S, atol=1e-6)
    with pytest.raises(ValueError, match="sites_deg"):
        pl.sites_ecef([[95.0, 0.0, 0.0]])
    with pytest.raises(ValueError, match="sites"):
        pl.pseudoranges(r, [1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="r"):
        pl.los_matrix(np.stack([r, r]), S)
    with pytest.raises(ValueError, match="r"):
        pl.los_matrix(S[0], S)


@given(
    lat_deg=st.floats(38.9, 39.4, **finite),
    dp=st.lists(st.floats(-1.0, 1.0, **finite), min_size=3, max_size=3),
)
def test_measurement_matrix_against_finite_differences(lat_deg, dp):
    """z = rho - rho_I: d z / d (INS position error) is E T (eq. 11)."""
    lat, lon, h = math.radians(lat_deg), math.radians(116.0), 1e4
    S = pl.sites_ecef()
    H = pl.measurement_matrix(lat, lon, h, S)
    assert not H[:, :6].any() and np.all(H[:, 9] == 1.0)
    step = np.array([1e-8, 1e-8, 1.0]) * (np.array(dp) + 1.5)

    def z(e):
        return -pl.pseudoranges(pl.geodetic_to_ecef(lat + e[0], lon + e[1], h + e[2]), S)

    fd = (z(step) - z(-step)) / 2.0
    np.testing.assert_allclose(H[:, 6:9] @ step, fd, rtol=1e-6, atol=1e-7)


def test_pdop():
    tr = ins.paper_trajectory()
    S = pl.sites_ecef()
    p = [pl.pdop(tr.lat[k], tr.lon[k], tr.h[k], S) for k in range(0, 201, 10)]
    assert 3.2 < min(p) and max(p) < 9.3
    with pytest.raises(ValueError, match="sites"):
        pl.pdop(tr.lat[0], tr.lon[0], tr.h[0], S[:3])


def test_simulate_pseudoranges_is_the_linear_model():
    tr = ins.paper_trajectory(duration=60.0)
    x = ins.simulate_errors(tr, rng=2)
    fault = Fault(pl.SENSOR, "ramp", 2.0, onset=20.0, component=3)
    d = pl.simulate_pseudoranges(tr, x, sigma=0.0, faults=[fault])
    assert d.z.shape == d.rho.shape == d.fault.shape == (61, 4) and d.r_ins.shape == (61, 3)
    np.testing.assert_allclose(d.fault[:, 3], np.where(tr.t >= 20.0, 2.0 * (tr.t - 20.0), 0.0))
    assert not d.fault[:, :3].any()
    S = pl.sites_ecef()
    for k in (0, 30, 60):
        H = pl.measurement_matrix(tr.lat[k], tr.lon[k], tr.h[k], S)
        # linearisation error of tens of metres of position error at 10-50 km: centimetres
        np.testing.assert_allclose(d.z[k], H @ x[k] + d.fault[k], atol=0.05)
    d1 = pl.simulate_pseudoranges(tr, x, rng=5)
    d2 = pl.simulate_pseudoranges(tr, x, rng=5)
    np.testing.assert_array_equal(d1.z, d2.z)
    clean = pl.simulate_pseudoranges(tr, x, sigma=0.0)
    assert np.std(d1.z - clean.z) == pytest.approx(pl.DEFAULT_SIGMA, rel=0.15)


def test_simulate_pseudoranges_bad_input():
    tr = ins.paper_trajectory(duration=5.0)
    x = np.zeros((6, 10))
    with pytest.raises(ValueError, match="traj"):
        pl.simulate_pseudoranges(None, x)
    with pytest.raises(ValueError, match="x_err"):
        pl.simulate_pseudoranges(tr, np.zeros((5, 10)))
    with pytest.raises(ValueError, match="sigma"):
        pl.simulate_pseudoranges(tr, x, sigma=-1.0)
    with pytest.raises(ValueError, match="component"):
        pl.simulate_pseudoranges(tr, x, faults=[Fault(pl.SENSOR, "step", 1.0, 0.0, component=7)])


@pytest.mark.parametrize(("fault", "words"), [
    (Fault("pseudorange", "step", 100.0, 1e9, component=0), r"starts outside this flight"),
    (Fault("pseudorange", "step", 100.0, -5.0, component=0), r"starts outside this flight"),
    (Fault("uv", "step", 100.0, 5.0, component=0), r"sensor must be 'pseudorange'"),
    (Fault("pseudorange", "step", 100.0, 5.2, 0.5, component=0), r"acts on no sample"),
])
def test_a_fault_the_flight_would_not_use_is_refused_naming_it(fault, words):
    """Review 35b N15's class in the pseudolite chapter: inject dropped these in silence."""
    tr = ins.paper_trajectory(duration=20.0)
    x = ins.simulate_errors(tr, rng=0)
    with pytest.raises(ValueError, match=rf"^faults\[0\] \(.*{words}"):
        pl.simulate_pseudoranges(tr, x, faults=[fault])


def test_a_height_beyond_a_million_km_is_refused_not_an_overflow():
    """Review 35e: h=1e308 gave an overflow warning and an inf geometry (measurement_matrix, pdop)."""
    with pytest.raises(ValueError, match=r"^h must be in \(-3\.18907e\+06, 1e\+09\] m$"):
        pl.geodetic_to_ecef(0.0, 0.0, 1e308)
    for call in (lambda: pl.measurement_matrix(0.68, 2.02, 1e308, pl.sites_ecef()),
                 lambda: pl.pdop(0.68, 2.02, 1e308, pl.sites_ecef())):
        with pytest.raises(ValueError, match=r"^h must be a real number in \(-3\.18907e\+06, 1e\+09\], "):
            call()
    assert np.all(np.isfinite(pl.geodetic_to_ecef(0.0, 0.0, pl.MAX_HEIGHT)))


@pytest.mark.parametrize("sites_deg", [[(39.0, 116.0, 0.0)] * 4,
                                       [(39, 116, 0), (39, 116, 0), (39.1, 116, 0), (39, 116.1, 0)]])
def test_issue35_sites_must_be_distinct(sites_deg):
    # Review 35f finding 33: a raw LinAlgError (Singular matrix) or "math domain error".
    with pytest.raises(ValueError, match=r"^sites_deg must be distinct sites at least 1 m apart"):
        pl.sites_ecef(sites_deg)
    E = pl.sites_ecef([(39, 116, 0), (39.1, 116, 0), (39, 116.1, 0), (39.1, 116.1, 0)])
    with pytest.raises(ValueError, match=r"^sites must be distinct sites at least 1 m apart"):
        pl.pdop(np.radians(39.05), np.radians(116.05), 1e4, E[[0, 0, 2, 3]])


def test_issue35_pdop_refuses_sites_on_one_line_of_sight():
    # Review 35f finding 33's class: distinct sites stacked on one vertical give a singular G.
    E = pl.sites_ecef([(39, 116, h) for h in (0, 100, 200, 300)])
    with pytest.raises(ValueError, match=r"^sites must surround the receiver in 3-D"):
        pl.pdop(np.radians(39.05), np.radians(116.05), 1e4, E)


@pytest.mark.parametrize("kw, words", [
    ({"lat": []}, r"^lat must be a latitude in radians in \[-1\.5708, 1\.5708\], got \[\]$"),
    ({"lon": [1.0]}, r"^lon must be a longitude in radians in \[-6\.28319, 6\.28319\], got \[1\.0\]$"),
    ({"h": True}, r"^h must be a real number in \(-3\.18907e\+06, 1e\+09\], got True$"),
])
def test_one_receiver_position_is_three_numbers_each_named(kw, words):
    """Issue 35 (review 35h): lat=[] in measurement_matrix or pdop was refused as
    'r must have shape (3,), got (0, 3)', a name the user never typed."""
    args = {"lat": 0.68, "lon": 2.02, "h": 1e4, **kw}
    for f in (pl.measurement_matrix, pl.pdop):
        with pytest.raises(ValueError, match=words):
            f(args["lat"], args["lon"], args["h"], pl.sites_ecef())


def test_simulate_pseudoranges_names_a_0d_array_of_faults():
    """Issue 35 (review 35h): faults=np.array(1.0) was 'TypeError: iteration over a 0-d array'."""
    tr = ins.paper_trajectory(duration=5.0)
    x = ins.simulate_errors(tr, rng=0)
    for bad in (np.array(1.0), True, -0.0):
        with pytest.raises(ValueError, match=r"^faults must be a sequence of Fault"):
            pl.simulate_pseudoranges(tr, x, faults=bad)


def test_no_pseudolite_site_is_refused():
    """Review 35k (5) 9: measurement_matrix(..., sites of 0 rows) returned an empty (0, 10)
    matrix (and pseudoranges, los_matrix no measurement at all)."""
    words = r"^sites must have shape \(m, 3\) with m >= 1 \(one row a pseudolite\), got shape \(0, 3\)"
    with pytest.raises(ValueError, match=words):
        pl.measurement_matrix(0.68, 2.02, 1e4, pl.sites_ecef()[:0])
    with pytest.raises(ValueError, match=words):
        pl.pseudoranges(pl.sites_ecef()[0] + 100.0, np.zeros((0, 3)))
