"""TOA equation: each term against a straightforward scalar implementation; gradient vs finite differences."""

import math
from decimal import Decimal, localcontext

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from xnavlab.core import ephemeris
from xnavlab.core.constants import GM_SUN, C
from xnavlab.mars.models import dynamics
from xnavlab.mars.timing import pulsars, toa

N, D = pulsars.directions()


def _scalar_delay(R, n, D0, r_sun):
    """Paper eq. (1) written out with plain floats, one pulsar at a time (its Shapiro form)."""
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


def _exact_shapiro(R, n, r_sun, digits=50):
    """The exact Shapiro form in 50-digit decimal arithmetic: an independent evaluation.

    ``2 mu/c^3 ln[(n.x + |x|)/(n.b + |b|)]`` with ``x = R - r_sun``, ``b = -r_sun``; the
    float inputs are exact decimals, so the only rounding is at the 50th digit. ``n`` is
    normalised here: a float unit vector is one only to 1e-16, which matters behind the
    Sun, where ``n.x + |x|`` is ``|x| theta^2 / 2``.
    """
    with localcontext() as ctx:
        ctx.prec = digits
        x = [Decimal(float(R[i])) - Decimal(float(r_sun[i])) for i in range(3)]
        b = [-Decimal(float(r_sun[i])) for i in range(3)]
        nd = [Decimal(float(n[i])) for i in range(3)]
        norm = sum(c * c for c in nd).sqrt()
        nd = [c / norm for c in nd]

        def log_sum(v):
            return (sum(nd[i] * v[i] for i in range(3)) + sum(c * c for c in v).sqrt()).ln()

        two_t = 2 * Decimal(GM_SUN) / Decimal(C) ** 3
        return float(two_t * (log_sum(x) - log_sum(b)))


def test_terms_match_scalar_implementation():
    R, r_sun = _mars_case()
    parts = toa.terms(R, N, D, r_sun, shapiro="paper")
    total = toa.delay(R, N, D, r_sun, shapiro="paper")
    exact = toa.terms(R, N, D, r_sun)
    for k in range(len(D)):
        ro, pa, sh = _scalar_delay(R, N[k], D[k], r_sun)
        assert math.isclose(parts["roemer"][k], ro, rel_tol=1e-13)
        assert math.isclose(parts["parallax"][k], pa, rel_tol=1e-9)
        assert math.isclose(parts["shapiro"][k], sh, rel_tol=1e-9)
        assert math.isclose(total[k], ro + pa + sh, rel_tol=1e-13)
        assert exact["roemer"][k] == parts["roemer"][k]
        assert abs(exact["shapiro"][k] - _exact_shapiro(R, N[k], r_sun)) < 1e-12
    np.testing.assert_array_equal(toa.delay(R, N, D, r_sun),
                                  exact["roemer"] + exact["parallax"] + exact["shapiro"])


def _near_sun(R, r_sun, theta, azimuth):
    """Unit vectors at angles ``theta`` (rad) from the Sun as seen from ``R``, shape (k, 3)."""
    xh = (R - r_sun) / np.linalg.norm(R - r_sun)
    e1 = np.cross(xh, [0.0, 0.0, 1.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(xh, e1)
    perp = np.cos(azimuth)[:, None] * e1 + np.sin(azimuth)[:, None] * e2
    n = -np.cos(theta)[:, None] * xh + np.sin(theta)[:, None] * perp
    return n / np.linalg.norm(n, axis=1)[:, None]


@given(st.floats(1e-7, np.pi), st.floats(0.0, 2 * np.pi), st.floats(-3e8, 9e8))
def test_exact_shapiro_to_a_picosecond_everywhere(theta, azimuth, t):
    """Against 50-digit arithmetic, at any angle from the Sun down to 1e-7 rad, 1990-2030.

    Behind the Sun ``n.x + |x|`` cancels to ``|x| theta^2 / 2``; the stable rewrite keeps
    every digit of it (measured: largest error 8e-15 s over 300 random draws of the same ranges).
    """
    R = ephemeris.position("mars", t) + dynamics.MARS_STATE0[:3]
    r_sun = ephemeris.position("sun", t)
    n = _near_sun(R, r_sun, np.array([theta]), np.array([azimuth]))
    assert abs(toa.shapiro(R, n, r_sun)[0] - _exact_shapiro(R, n[0], r_sun)) < 1e-12


def test_exact_shapiro_within_a_degree_of_the_sun():
    R, r_sun = _mars_case()
    theta = np.radians(np.array([1.0, 0.5, 0.22, 0.1, 0.01, 1e-4]))
    n = _near_sun(R, r_sun, theta, np.linspace(0.0, 6.0, theta.size))
    ours = toa.shapiro(R, n, r_sun)
    for k in range(theta.size):
        assert abs(ours[k] - _exact_shapiro(R, n[k], r_sun)) < 1e-12
    # The naive sum n.x + |x| cancels behind the Sun: an error of about 4 mu/c^3 eps / theta^2,
    # a picosecond at 0.004 degree and nanoseconds at 1e-4 degree (within the solar disc, where
    # only the formula goes), which the stable rewrite avoids.
    x = R - r_sun
    naive = 2 * GM_SUN / C**3 * np.log((n @ x + np.linalg.norm(x)) / (n @ -r_sun + np.linalg.norm(r_sun)))
    assert abs(naive[-1] - _exact_shapiro(R, n[-1], r_sun)) > 1e-10


def test_exact_and_paper_forms_differ_by_what_the_geometry_says():
    """Paper minus exact: nanoseconds far from the Sun, tens of microseconds close to it."""
    R, r_sun = _mars_case()
    far = _near_sun(R, r_sun, np.radians(np.array([50.0, 90.0, 130.0, 180.0])), np.zeros(4))
    gap = np.abs(toa.shapiro(R, far, r_sun) - toa.shapiro_paper(R, far, r_sun))
    assert np.all((gap > 1e-10) & (gap < 3e-7))  # measured 1.3-7 ns on 2016-01-01
    near = _near_sun(R, r_sun, np.radians(np.array([0.22])), np.zeros(1))
    gap = abs(toa.shapiro(R, near, r_sun)[0] - toa.shapiro_paper(R, near, r_sun)[0])
    assert 1e-5 < gap < 1e-4  # measured 35 us


def test_offset_to_pint_is_the_reference_change():
    """exact - offset is the Sun's delay referred to 1 au: 2 mu/c^3 ln[(n.x + |x|) / 1 au]."""
    R, r_sun = _mars_case()
    off = toa.shapiro_offset_to_pint(N, r_sun)
    x = R - r_sun
    one_au = 2 * GM_SUN / C**3 * np.log((N @ x + np.linalg.norm(x)) / 1.495978707e11)
    np.testing.assert_allclose(toa.shapiro(R, N, r_sun) - off, one_au, rtol=0, atol=1e-15)
    # it does not depend on the spacecraft, and broadcasts over epochs
    assert off.shape == (4,) and toa.shapiro_offset_to_pint(N, np.stack([r_sun] * 3)).shape == (3, 4)
    assert np.all((off > 4e-5) & (off < 8e-5))  # about 5 ln-units of 2 mu/c^3 = 9.85 us


def test_shapiro_through_the_sun_and_bad_form():
    R, r_sun = _mars_case()
    with pytest.raises(ValueError, match="behind the Sun"):  # the pulsar exactly behind the Sun
        toa.shapiro(np.array([2.2e11, 0.0, 0.0]), np.array([[-1.0, 0.0, 0.0]]), np.array([1e8, 0.0, 0.0]))
    with pytest.raises(ValueError, match="shapiro"):
        toa.delay(R, N, D, r_sun, shapiro="sheikh")
    with pytest.raises(ValueError, match="shapiro"):
        toa.gradient(R, N, D, r_sun, shapiro=None)


@pytest.mark.parametrize("form", toa.SHAPIRO_FORMS)
def test_term_sizes_for_a_mars_orbiter(form):
    R, r_sun = _mars_case()
    parts = toa.terms(R, N, D, r_sun, shapiro=form)
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
    st.sampled_from([0.0, 1e6, 2.5e6]), st.sampled_from(toa.SHAPIRO_FORMS),
)
def test_gradient_matches_finite_differences(dx, dy, dz, dt_days, form):
    t = dynamics.MARS_T0 + dt_days
    R = dynamics.MARS_STATE0[:3] + np.array([dx, dy, dz]) + ephemeris.position("mars", t)
    r_sun = ephemeris.position("sun", t)
    g = toa.gradient(R, N, D, r_sun, shapiro=form)
    sh = toa.shapiro if form == "exact" else toa.shapiro_paper
    h = 10.0
    for i in range(3):
        e = np.zeros(3)
        e[i] = h
        # difference the parts separately: the Roemer term's n.R/c is exact, the rest is small
        fd = (toa.parallax(R + e, N, D) + sh(R + e, N, r_sun)
              - toa.parallax(R - e, N, D) - sh(R - e, N, r_sun)) / (2 * h)
        fd += N[:, i] / C
        np.testing.assert_allclose(g[:, i], fd, rtol=1e-7, atol=1e-22)


@given(st.floats(1e-3, 0.5), st.floats(0.0, 2 * np.pi))
def test_exact_shapiro_gradient_near_the_sun(theta, azimuth):
    """The exact gradient, 2 mu/c^3 (n + x/|x|)/(n.x + |x|), where it is large (pulsar near the Sun)."""
    R, r_sun = _mars_case()
    n = _near_sun(R, r_sun, np.array([theta]), np.array([azimuth]))
    g = toa.gradient(R, n, D[:1], r_sun)[0] - n[0] / C - toa.gradient_fd(R, n, D[:1], r_sun,
                                                                        which=("parallax",))[0]
    h = 1e-4 * theta**2 * np.linalg.norm(R - r_sun)  # well inside the scale |x| theta^2 of the log
    fd = np.array([(toa.shapiro(R + h * e, n, r_sun) - toa.shapiro(R - h * e, n, r_sun))[0] / (2 * h)
                   for e in np.eye(3)])
    np.testing.assert_allclose(g, fd, rtol=1e-5, atol=1e-6 * np.abs(fd).max())


def test_gradient_small_terms_are_small():
    R, r_sun = _mars_case()
    g = toa.gradient(R, N, D, r_sun)
    assert np.allclose(g * C, N, atol=1e-6)


def test_delays_at_uses_centre_and_sun():
    t = dynamics.MARS_T0
    r = dynamics.MARS_STATE0[:3]
    R, r_sun = _mars_case(t)
    np.testing.assert_allclose(toa.delays_at(r, t), toa.delay(R, N, D, r_sun), rtol=1e-15)
    np.testing.assert_allclose(toa.delays_at(r, t, shapiro="paper"),
                               toa.delay(R, N, D, r_sun, shapiro="paper"), rtol=1e-15)
    assert toa.delays_at(np.tile(r, (3, 1)), t + np.array([0.0, 1.0, 2.0])).shape == (3, 4)


def test_bad_inputs():
    R, r_sun = _mars_case()
    with pytest.raises(ValueError, match="unit vectors"):
        toa.roemer(R, 2 * N)
    with pytest.raises(ValueError, match=r"n must have shape \(k, 3\)"):
        toa.roemer(R, N[0])
    with pytest.raises(ValueError, match=r"^distance must be in \[3.09e\+16, 3.09e\+22\] m"):
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
    with pytest.raises(ValueError, match=r"^sigma must have shape \(4,\), one per pulsar, got \(2,\)"):
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
    for which, message in ((("nope",), r"^which\[0\] must be one of 'roemer'"),
                           ("roemer", r"^which must be a list of terms, got the string 'roemer'"),
                           ((), r"^which must name at least one term"),
                           (("roemer", "roemer"), r"^which lists roemer twice")):
        with pytest.raises(ValueError, match=message):
            toa.gradient_fd(R, n, dist, sun, which=which)
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


def test_proper_time_at_the_geocentre_is_tt():
    """A clock riding with the geocentre, Earth's potential left out: TT's rate and annual term.

    Over twelve years (Jupiter's period) the mean of d(tau - TDB)/dTDB is L_B - L_C = L_G
    (IAU 2000 B1.9 and 2006 B3; measured 6.96957e-10 against 6.96929e-10) and the annual
    term of TDB - TT is 1.656675 ms (Fairhead & Bretagnon 1990; measured 1.6535 ms).
    """
    t = np.arange(0.0, 12 * 365.25 * 86400.0, 86400.0)
    out = toa.proper_time_terms(t, center="earth")
    mean_rate = out["tau_minus_tdb"][-1] / (t[-1] - t[0])
    assert mean_rate == pytest.approx(toa.L_B - 1.48082686741e-8, rel=1e-3)
    w = 2 * np.pi / (365.2596 * 86400.0)
    design = np.column_stack([np.ones_like(t), t, np.sin(w * t), np.cos(w * t)])
    coef = np.linalg.lstsq(design, out["tau_minus_tdb"], rcond=None)[0]
    assert math.hypot(coef[2], coef[3]) == pytest.approx(1.656675e-3, rel=0.01)
    assert not out["orbit_term"].any()


def test_proper_time_on_the_paper_orbit():
    """Around Mars: the rate a Mars-orbiting clock gains, and the orbit term -V_Mars . r / c^2."""
    t = dynamics.MARS_T0 + np.arange(0.0, 86400.0 + 1.0, 60.0)
    x = dynamics.truth(dynamics.MARS_T0 + np.arange(0.0, 30 * 86400.0 + 1.0, 60.0))[: t.size]
    out = toa.proper_time_terms(t, x)
    centre = toa.proper_time_terms(t)
    _, v_mars = ephemeris.state("mars", t)
    np.testing.assert_allclose(out["orbit_term"], -np.sum(v_mars * x[:, :3], axis=1) / C**2, rtol=1e-12)
    assert np.all(np.abs(out["orbit_term"]) < 1e-6)  # -718 to +656 ns over the 30 days (measured)
    # the accumulated difference from the centre's clock is the orbit term, plus a rate
    # (Mars's potential and the orbital speed) and Mars's eccentric-orbit ripple of tens of ns
    diff = out["tau_minus_tdb"] - centre["tau_minus_tdb"]
    design = np.column_stack([np.ones_like(t), t - t[0]])
    rest = diff - out["orbit_term"]
    rest -= design @ np.linalg.lstsq(design, rest, rcond=None)[0]
    assert np.abs(rest).max() < 0.1 * np.ptp(out["orbit_term"])  # measured 28 ns against 1.37 us p-p
    assert 5e-9 < out["rate"].mean() < 8e-9  # measured 6.68e-9 on 2016-01-01
    with pytest.raises(ValueError, match="increasing"):
        toa.proper_time_terms(t[::-1])
    with pytest.raises(ValueError, match="center"):
        toa.proper_time_terms(t, center="pluto")


def test_a_distance_beyond_max_distance_and_a_huge_step_are_refused():
    n = np.array([[1.0, 0.0, 0.0]])
    with pytest.raises(ValueError, match=r"^distance must be in \[3\.09e\+16, 3\.09e\+22\] m"):
        toa.parallax(np.array([0.0, 1e11, 0.0]), n, 1e308)
    with pytest.raises(ValueError, match=r"step must be a real number in \(0, 1e\+12\]"):
        toa.gradient_fd([1e11, 0.0, 0.0], n, [1e20], [1e9, 2e9, 0.0], step=1e308)


@pytest.mark.parametrize(("call", "words"), [
    (lambda: toa.shapiro(np.array([2e11, 1e11, 0.0]), np.array([[0.6, 0.8, 0]]), np.zeros(3)),
     r"^r_sun_ssb must have a norm in \[1, 1e\+15\] m \(the Sun's centre is never on the SSB"),
    (lambda: toa.shapiro_paper(np.array([2e11, 1e11, 0.0]), np.array([[0.6, 0.8, 0]]), np.zeros(3)),
     r"^r_sun_ssb must have a norm in \[1, 1e\+15\] m"),
    (lambda: toa.shapiro(np.array([1e8, 0, 0.0]), np.array([[0.6, 0.8, 0]]), np.array([1e8, 0, 0])),
     r"^r_ssb must be at least 1 m from the Sun's centre, \|r_ssb - r_sun_ssb\| >= 1 m"),
    (lambda: toa.gradient(np.array([1e8, 0, 0.0]), np.array([[0.6, 0.8, 0]]), 1e20,
                          np.array([1e8, 0.1, 0])), r"^r_ssb must be at least 1 m from the Sun"),
    (lambda: toa.delay(np.array([1e300, 0, 0.0]), np.array([[0.6, 0.8, 0]]), 1e20,
                       np.array([1e8, 0, 0])), r"^r_ssb must have a norm in \[0, 1e\+15\] m"),
    (lambda: toa.parallax(np.array([2e11, 1e11, 0.0]), np.array([[1.0, 0, 0]]), 5e-324),
     r"^distance must be in \[3\.09e\+16, 3\.09e\+22\] m \(1 pc to pulsars.MAX_DISTANCE\), got 4\.9"),
    (lambda: toa.pdop(np.eye(3), sigma=np.full(3, 5e-324)), r"^sigma must be in \[0\.001, 1e\+13\] m, got 4"),
    (lambda: toa.pdop(np.eye(3), sigma=np.full(3, 1e308)), r"^sigma must be in \[0\.001, 1e\+13\] m"),
    (lambda: toa.pdop(1e200 * np.eye(3)), r"^n must hold unit vectors"),
])
def test_a_degenerate_sun_geometry_a_tiny_distance_or_sigma_is_refused_by_its_name(call, words):
    """Issue 35, review 35f 40/41: r_sun_ssb = 0 was refused as 'n: a pulsar lies exactly behind
    the Sun' (false); distance and sigma 5e-324 overflowed (RuntimeWarning)."""
    with pytest.raises(ValueError, match=words):
        call()


def test_the_paper_shapiro_form_is_finite_where_the_exact_one_is():
    R, r_sun = _mars_case()
    n = np.array([[0.6, 0.8, 0.0]])
    assert np.isfinite(toa.shapiro_paper(R, n, r_sun)).all()
    assert np.isfinite(toa.gradient(R, n, 1e20, r_sun, shapiro="paper")).all()


_R = np.array([2e11, 1e10, 3e9])


@pytest.mark.parametrize("call", [
    lambda n, d: toa.delay(np.zeros((5, 3)) + _R, n, d, np.zeros((3, 3)) + 1e8),
    lambda n, d: toa.gradient(np.zeros((5, 3)) + _R, n, d, np.zeros((3, 3)) + 1e8),
    lambda n, d: toa.terms(np.zeros((5, 3)) + _R, n, d, np.zeros((3, 3)) + 1e8, shapiro="paper"),
    lambda n, d: toa.shapiro_paper(np.zeros((5, 3)) + _R, n, np.zeros((3, 3)) + 1e8),
])
def test_a_sun_position_of_another_shape_than_r_ssb_is_named(call):
    """Review 35j (2) 1: r_ssb (5, 3) against r_sun_ssb (3, 3) gave numpy's "operands could not
    be broadcast together"."""
    n, d = pulsars.directions()
    with pytest.raises(ValueError, match=r"^r_sun_ssb must have shape \(3,\) or r_ssb's shape \(5, 3\) "
                                         r"\(one Sun position per spacecraft position\), got shape \(3, 3\)"):
        call(n, d)
    assert toa.delay(_R, n, d, np.zeros((2, 3)) + 1e8).shape == (2, 4)  # (3,) broadcasts still


def test_delays_at_names_t_of_another_length_than_r():
    """Review 35j (2) 2: r (3, 3) at t (2,) gave numpy's broadcast message."""
    with pytest.raises(ValueError, match=r"^t must be a scalar or have shape \(3,\) \(one epoch per row "
                                         r"of r\), got shape \(2,\)"):
        toa.delays_at(np.zeros((3, 3)) + 1e7, [5e8, 5e8 + 1])
    with pytest.raises(ValueError, match=r"^t must be a scalar or have shape \(n,\), got shape \(1, 1\)"):
        toa.delays_at([-3.4e6, -1.3e6, -2.6e6], [[5e8]])
    assert toa.delays_at([-3.4e6, -1.3e6, -2.6e6], [5e8, 5e8 + 1]).shape == (2, 4)  # one r, two epochs


def test_gradient_fd_refuses_more_than_one_position():
    """Review 35j (2)'s class: r_ssb (5, 3) gave a (5, 12) array of mixed columns."""
    n, d = pulsars.directions()
    with pytest.raises(ValueError, match=r"^r_ssb must have shape \(3,\) \(one position"):
        toa.gradient_fd(np.zeros((5, 3)) + _R, n, d, np.zeros(3) + 1e8)
    with pytest.raises(ValueError, match=r"^r_sun_ssb must have shape \(3,\)"):
        toa.gradient_fd(_R, n, d, np.zeros((2, 3)) + 1e8)


def test_proper_time_terms_refuses_a_clock_inside_a_body_and_x_of_another_length():
    """Review 35j (1) 22 and (2) 3: a craft at Mars's centre gave a RuntimeWarning (divide by
    zero); x (3, 6) against t (2,) numpy's "could not be broadcast" with remapped shapes."""
    t = np.array([0.0, 1.0])
    with pytest.raises(ValueError, match=r"^x must lie outside mars \(at least its polar radius, 3376\.2 km, "
                                         r"from its centre\), got x\[0\] at 0 km"):
        toa.proper_time_terms(t, np.zeros(6))
    with pytest.raises(ValueError, match=r"^x must lie outside moon .* got x\[0\] at 0 km"):
        toa.proper_time_terms(t, np.zeros(6), center="moon")
    state = np.array([4e6, 0.0, 0.0, 0.0, 3000.0, 0.0])
    for bad in (np.zeros((3, 6)) + state, np.zeros((1, 6)) + state, np.zeros((2, 2, 6)) + state):
        with pytest.raises(ValueError, match=r"^x must have shape \(6,\) or \(2, 6\) \(one state per epoch "
                                             r"of t\), got shape"):
            toa.proper_time_terms(t, bad)
    assert toa.proper_time_terms(t, state)["rate"].shape == (2,)


def test_delays_at_names_its_center():
    """Review 35k (tests/test_default_inputs.py): center=None was refused as the ephemeris's
    'body'."""
    with pytest.raises(ValueError, match=r"^center must be one of"):
        toa.delays_at([-3.4e6, -1.3e6, -2.6e6], 5.0e8, center=None)


def test_float32_directions_are_refused_by_their_dtype():
    """Review 35 Q20: a float32 catalogue was refused as "not unit vectors", with no word of
    float32 (its norms are off by 3e-8, and its components by up to 6e-8: 13 km of n . R at
    1.5 au, so it is refused rather than renormalised). A float32 row that is exactly a unit
    vector passes; a scaled row is refused with its norm."""
    r = np.array([2e11, 1e10, 5e9])
    with pytest.raises(ValueError, match=r"^n must hold float64 unit vectors \(\|n\| = 1 within 1e-9\), got "
                                         r"float32, whose rounding \(6e-08 a component; \|n\[0\]\| - 1 = "
                                         r"-3.1e-08\) moves n . R at 1.5 au by up to 13 km: pass float64 "
                                         r"directions$"):
        toa.roemer(r, N.astype(np.float32))
    with pytest.raises(ValueError, match=r"^n must hold float64 unit vectors .* got float32"):
        toa.pdop(N.astype(np.float32))
    assert toa.roemer(r, np.float32([[0.0, 0.0, 1.0]])).tolist() == [5e9 / C]
    with pytest.raises(ValueError, match=r"^n must hold unit vectors \(\|n\| = 1 within 1e-9\), got "
                                         r"\|n\[1\]\| = 2$"):
        toa.roemer(r, np.float32([[0.0, 0.0, 1.0], [0.0, 2.0, 0.0]]))
