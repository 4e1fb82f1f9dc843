"""TOA equation: each term against a straightforward scalar implementation; gradient vs finite differences."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from xnavlab.core import ephemeris
from xnavlab.core.constants import GM_SUN, C
from xnavlab.mars import dynamics, pulsars, toa

N, D = pulsars.directions()


def _scalar_delay(R, n, D0, r_sun):
    """Paper eq. (1) written out with plain floats, one pulsar at a time."""
    nR = sum(n[i] * R[i] for i in range(3))
    RR = sum(R[i] * R[i] for i in range(3))
    b = [-r_sun[i] for i in range(3)]
    nb = sum(n[i] * b[i] for i in range(3))
    bb = math.sqrt(sum(x * x for x in b))
    roemer = nR / C
    parallax = (nR**2 - RR) / (2 * C * D0)
    shapiro = 2 * GM_SUN / C**3 * math.log(abs((nR + math.sqrt(RR)) / (nb + bb) + 1))
    return roemer, parallax, shapiro


def _mars_case(t=dynamics.MARS_T0):
    r_ssb = dynamics.MARS_STATE0[:3] + ephemeris.position("mars", t)
    return r_ssb, ephemeris.position("sun", t)


def test_terms_match_scalar_implementation():
    R, r_sun = _mars_case()
    parts = toa.terms(R, N, D, r_sun)
    total = toa.delay(R, N, D, r_sun)
    for k in range(len(D)):
        ro, pa, sh = _scalar_delay(R, N[k], D[k], r_sun)
        assert math.isclose(parts["roemer"][k], ro, rel_tol=1e-13)
        assert math.isclose(parts["parallax"][k], pa, rel_tol=1e-9)
        assert math.isclose(parts["shapiro"][k], sh, rel_tol=1e-9)
        assert math.isclose(total[k], ro + pa + sh, rel_tol=1e-13)


def test_term_sizes_for_a_mars_orbiter():
    R, r_sun = _mars_case()
    parts = toa.terms(R, N, D, r_sun)
    assert np.all(np.abs(parts["roemer"]) < 1000) and np.abs(parts["roemer"]).max() > 100  # s
    assert np.all(parts["parallax"] <= 0)
    assert np.all(np.abs(parts["parallax"]) * C < 1e3)  # below a kilometre
    # tens of km: the SSB lies about a solar radius from the Sun, so the log term is ~5
    assert np.all((parts["shapiro"] * C > 1e3) & (parts["shapiro"] * C < 1e5))


def test_vectorised_over_epochs():
    R, r_sun = _mars_case()
    Rs = np.stack([R, R * 1.01])
    out = toa.delay(Rs, N, D, np.stack([r_sun, r_sun]))
    assert out.shape == (2, 4)
    np.testing.assert_allclose(out[0], toa.delay(R, N, D, r_sun))


@given(
    st.floats(-5e6, 5e6), st.floats(-5e6, 5e6), st.floats(-5e6, 5e6),
    st.sampled_from([0.0, 1e6, 2.5e6]),
)
def test_gradient_matches_finite_differences(dx, dy, dz, dt_days):
    t = dynamics.MARS_T0 + dt_days
    R = dynamics.MARS_STATE0[:3] + np.array([dx, dy, dz]) + ephemeris.position("mars", t)
    r_sun = ephemeris.position("sun", t)
    g = toa.gradient(R, N, D, r_sun)
    h = 10.0
    for i in range(3):
        e = np.zeros(3)
        e[i] = h
        # difference the parts separately: the Roemer term's n.R/c is exact, the rest is small
        fd = (toa.parallax(R + e, N, D) + toa.shapiro(R + e, N, r_sun)
              - toa.parallax(R - e, N, D) - toa.shapiro(R - e, N, r_sun)) / (2 * h)
        fd += N[:, i] / C
        np.testing.assert_allclose(g[:, i], fd, rtol=1e-7, atol=1e-22)


def test_gradient_small_terms_are_small():
    R, r_sun = _mars_case()
    g = toa.gradient(R, N, D, r_sun)
    assert np.allclose(g * C, N, atol=1e-6)


def test_delays_at_uses_centre_and_sun():
    t = dynamics.MARS_T0
    r = dynamics.MARS_STATE0[:3]
    R, r_sun = _mars_case(t)
    np.testing.assert_allclose(toa.delays_at(r, t), toa.delay(R, N, D, r_sun), rtol=1e-15)
    assert toa.delays_at(np.tile(r, (3, 1)), t + np.array([0.0, 1.0, 2.0])).shape == (3, 4)


def test_bad_inputs():
    R, r_sun = _mars_case()
    with pytest.raises(ValueError, match="unit vectors"):
        toa.roemer(R, 2 * N)
    with pytest.raises(ValueError, match=r"n must have shape \(k, 3\)"):
        toa.roemer(R, N[0])
    with pytest.raises(ValueError, match="distance must be positive"):
        toa.parallax(R, N, -D)
    with pytest.raises(ValueError, match="r_ssb"):
        toa.delay(np.array([np.nan, 0, 0]), N, D, r_sun)
    with pytest.raises(ValueError, match="trailing shape"):
        toa.roemer(R[:2], N)


def test_pdop_against_explicit_least_squares():
    sigma = np.array([109.0, 344.0, 1866.0, 325.0])
    value, pos = toa.pdop(N, sigma)
    W = np.diag(sigma**-2)
    assert math.isclose(pos, math.sqrt(np.trace(np.linalg.inv(N.T @ W @ N))), rel_tol=1e-12)
    assert math.isclose(value, math.sqrt(np.trace(np.linalg.inv(N.T @ N))), rel_tol=1e-12)
    # adding a pulsar never hurts
    assert toa.pdop(N) <= toa.pdop(N[[0, 1, 3]])


def test_pdop_bad_geometry():
    with pytest.raises(ValueError, match="k >= 3"):
        toa.pdop(N[:2])
    with pytest.raises(ValueError, match="coplanar"):
        toa.pdop(np.array([[1.0, 0, 0], [0, 1.0, 0], [np.sqrt(0.5), np.sqrt(0.5), 0]]))
    with pytest.raises(ValueError, match="sigma must be positive"):
        toa.pdop(N, [1.0, 2.0])


def test_gradient_fd_matches_gradient_and_its_small_part():
    t = dynamics.MARS_T0
    R = ephemeris.position("mars", t) + dynamics.MARS_STATE0[:3]
    sun = ephemeris.position("sun", t)
    n, dist = pulsars.directions()
    g = toa.gradient(R, n, dist, sun)
    fd = toa.gradient_fd(R, n, dist, sun)
    assert np.abs(fd - g).max() / np.abs(g).max() < 1e-6
    small = toa.gradient_fd(R, n, dist, sun, which=("parallax", "shapiro"))
    assert np.abs(small - (g - n / C)).max() < 1e-3 * np.abs(g - n / C).max()
    with pytest.raises(ValueError, match="which"):
        toa.gradient_fd(R, n, dist, sun, which=("nope",))
    with pytest.raises(ValueError, match="step"):
        toa.gradient_fd(R, n, dist, sun, step=0.0)


def test_plot_orbit_terms_is_spacecraft_minus_mars():
    fig = toa.plot_orbit_terms("B0531+21", 0)
    roemer = fig.axes[0].lines[0].get_ydata()
    assert roemer.size == 1441
    # the Roemer part is n . r / c times c, in km
    n, _ = pulsars.directions(["B0531+21"])
    x0 = dynamics.MARS_STATE0[:3]
    assert roemer[0] == pytest.approx(float(n[0] @ x0) / 1e3, rel=1e-9)
    assert np.abs(fig.axes[1].lines[0].get_ydata()).max() < 100.0  # parallax below a metre, in cm
    with pytest.raises(ValueError, match="day"):
        toa.plot_orbit_terms(day=30)
    with pytest.raises(ValueError, match="pulsar"):
        toa.plot_orbit_terms("J0437-4715")
