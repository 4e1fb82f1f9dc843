"""The optical sensors as instruments (xnavlab.mars.models.optics): each model's noise against its formula
(sample statistics, autocorrelation), the oblate limb against an independent brute-force limb, the
paper's models kept as the defaults, and the scenario options drawing from the same noise."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from xnavlab.mars.models import optics, series, stars
from xnavlab.mars.models.sensors import tangent_basis
from xnavlab.mars.navigation import scenarios


def test_apparent_radius_and_its_inverse():
    rho = np.array([3.5e6, 4.2e6, 2.0e7])
    alpha = optics.apparent_radius(rho)
    np.testing.assert_allclose(optics.range_from_radius(alpha), rho, rtol=1e-12)
    with pytest.raises(ValueError, match="rho"):
        optics.apparent_radius(3.0e6)
    with pytest.raises(ValueError, match="alpha"):
        optics.range_from_radius(0.0)


def test_range_noise_from_the_apparent_radius_matches_rho_cot_alpha_sigma_alpha():
    """Sample std of the simulated range against ``rho cot(alpha) sigma_alpha`` at two ranges, and the
    orbit mean of that sigma equal to the paper's 5 km by the choice of sigma_alpha."""
    sim = optics.UVInstrument(5000.0, math.radians(0.1), "radius", "sphere")
    g = np.random.default_rng(3)
    n = 40_000
    for rho in (3.82e6, 4.57e6):
        states = np.tile([rho, 0.0, 0.0, 0.0, 3e3, 0.0], (n, 1))
        z = sim(states, g.standard_normal((n, 3)), np.empty((n, 4)))
        want = optics.radius_range_sigma(rho, sim.sigma_alpha)
        assert np.std(z[:, 0]) == pytest.approx(want, rel=0.02)
        assert abs(np.mean(z[:, 0]) - rho) < 5 * want / math.sqrt(n)
    sig = optics.radius_range_sigma(optics.orbit_ranges(), sim.sigma_alpha)
    assert np.mean(sig) == pytest.approx(5000.0, rel=1e-12)
    assert 2.0 < sig.max() / sig.min() < 2.2  # about 2x over the orbit: 3.2 to 6.7 km
    assert math.degrees(sim.sigma_alpha) == pytest.approx(0.0926, abs=1e-4)


def test_orbit_ranges_are_the_papers_perigee_and_apogee():
    r = optics.orbit_ranges()
    assert r.min() == pytest.approx(3.8166e6, rel=1e-4) and r.max() == pytest.approx(4.5754e6, rel=1e-4)
    with pytest.raises(ValueError, match="state0"):
        optics.orbit_ranges([4e6, 0, 0, 0, 1e4, 0])  # hyperbolic


@settings(max_examples=30, deadline=None)
@given(st.floats(-1.0, 1.0), st.floats(0.0, 2 * math.pi), st.floats(3.5e6, 2e7))
def test_limb_of_a_sphere_is_the_sphere(z, lon, rho):
    """With a = c the fitted circle is the sphere's: alpha = arcsin(R/rho), the centre exact."""
    s = math.sqrt(1.0 - z * z)
    r = rho * np.array([s * math.cos(lon), s * math.sin(lon), z])
    alpha, u = optics.limb_fit(r, a=3.4e6, c=3.4e6)
    assert alpha == pytest.approx(math.asin(3.4e6 / rho), rel=1e-9)
    np.testing.assert_allclose(u, -r / rho, atol=1e-9)


def test_limb_of_the_oblate_mars_against_closed_forms_and_tangency():
    a, c, p = optics.R_EQUATOR, optics.R_POLAR, np.array([0.0, 0.0, 1.0])
    rho = 4.2e6
    # over the pole the limb is a circle: tan(alpha) = a / sqrt(rho^2 - c^2)
    alpha, u = optics.limb_fit([0.0, 0.0, rho], p)
    assert math.tan(alpha) == pytest.approx(a / math.sqrt(rho**2 - c**2), rel=1e-12)
    # over the equator: half-angles arcsin(a/rho) (along the equator), atan(c / sqrt(rho^2 - a^2))
    r = np.array([rho, 0.0, 0.0])
    alpha, u = optics.limb_fit(r, p, n_azimuth=4)
    want = 0.5 * (math.asin(a / rho) + math.atan(c / math.sqrt(rho**2 - a**2)))
    assert alpha == pytest.approx(want, rel=1e-12)
    np.testing.assert_allclose(u, [-1.0, 0.0, 0.0], atol=1e-12)
    # the limb directions touch the ellipsoid: min over t of (r + t d)^T A (r + t d) is 1
    r = rho * np.array([math.cos(0.7), 0.0, math.sin(0.7)])
    alpha, u = optics.limb_fit(r, p)
    A = np.diag([1 / a**2, 1 / a**2, 1 / c**2])
    M = np.outer(A @ r, A @ r) - (r @ A @ r - 1.0) * A
    e1, e2 = tangent_basis(u)
    for phi in np.linspace(0.0, 2 * math.pi, 7):
        w = math.cos(phi) * e1 + math.sin(phi) * e2
        # tan(theta) on the cone d^T M d = 0, d = u + tau w
        mu, muw, mw = u @ M @ u, u @ M @ w, w @ M @ w
        tau = (-muw - math.sqrt(muw**2 - mu * mw)) / mw
        d = (u + tau * w) / math.hypot(1.0, tau)
        t = -(d @ A @ r) / (d @ A @ d)
        x = r + t * d
        assert x @ A @ x == pytest.approx(1.0, abs=1e-9)


def test_oblate_limb_centre_against_a_brute_force_limb():
    """Limb points from a sampled surface (the farthest direction from the true centre in each
    azimuth bin), a plane fitted through them: its centre and radius agree with limb_fit's to
    0.01 deg, and both sit about 0.2 deg off the true centre at 40 deg latitude, 4,200 km."""
    a, c = optics.R_EQUATOR, optics.R_POLAR
    r = 4.2e6 * np.array([math.cos(math.radians(40.0)), 0.0, math.sin(math.radians(40.0))])
    th = np.linspace(0.0, math.pi, 700)[:, None]
    ph = np.linspace(0.0, 2 * math.pi, 1400)[None, :]
    X = np.stack(np.broadcast_arrays(a * np.sin(th) * np.cos(ph), a * np.sin(th) * np.sin(ph),
                                     c * np.cos(th)), -1).reshape(-1, 3)
    d = X - r
    d /= np.linalg.norm(d, axis=1)[:, None]
    u0 = -r / np.linalg.norm(r)
    e1, e2 = tangent_basis(u0)
    ang = np.arccos(np.clip(d @ u0, -1.0, 1.0))
    b = np.digitize(np.arctan2(d @ e2, d @ e1), np.linspace(-math.pi, math.pi, 91))
    limb = np.array([d[np.argmax(np.where(b == k, ang, -1.0))] for k in range(1, 91)])
    n = np.linalg.eigh(np.cov(limb.T))[1][:, 0]
    n = n if n @ u0 > 0 else -n
    alpha, u = optics.limb_fit(r, (0.0, 0.0, 1.0))
    assert math.degrees(math.acos(min(1.0, n @ u))) < 0.01
    assert math.degrees(math.acos(n @ limb.mean(axis=0))) == pytest.approx(math.degrees(alpha), abs=0.01)
    assert 0.15 < math.degrees(math.acos(u @ u0)) < 0.3


def test_limb_bias_over_the_papers_orbit():
    """Range bias of a sphere of Mars's volume fitted to the limb: a few km, of both signs, over
    the orbit's latitudes (+-48 deg); the centre-direction bias up to about 0.26 deg."""
    inc = math.radians(48.1)
    lat = np.linspace(-inc, inc, 25)
    r = 4.2e6 * np.stack([np.cos(lat), np.zeros_like(lat), np.sin(lat)], axis=1)
    b = optics.limb_bias(r, pole=(0.0, 0.0, 1.0))
    assert -6e3 < b["range_m"].min() < 0.0 < b["range_m"].max() < 6e3
    assert 0.2 < math.degrees(b["direction_rad"].max()) < 0.3
    np.testing.assert_allclose(b["range_m"], b["range_m"][::-1], rtol=1e-9)  # symmetric in latitude
    np.testing.assert_allclose(b["latitude_deg"], np.degrees(lat), atol=1e-9)


def test_gauss_markov_variance_and_autocorrelation():
    """Unit variance, autocorrelation phi^lag (e^-1 at lag tau), and chunks carried = one run."""
    tau, dt = 30.0, 1.0
    phi = math.exp(-dt / tau)
    w = np.random.default_rng(7).standard_normal((1_000_000, 2))
    g = optics.gauss_markov(w, phi)
    assert np.var(g, axis=0) == pytest.approx([1.0, 1.0], rel=0.05)
    for lag, want in ((1, phi), (30, math.exp(-1.0)), (90, math.exp(-3.0))):
        rho = np.mean(g[lag:] * g[:-lag], axis=0) / np.var(g, axis=0)
        np.testing.assert_allclose(rho, want, atol=0.03)
    first = optics.gauss_markov(w[:1000], phi)
    rest = optics.gauss_markov(w[1000:2000], phi, first[-1])
    np.testing.assert_allclose(np.vstack([first, rest]), g[:2000], rtol=0, atol=1e-12)
    assert np.array_equal(optics.gauss_markov(w[:5], 0.0), w[:5])  # phi = 0: white
    with pytest.raises(ValueError, match="phi"):
        optics.gauss_markov(w[:5], 1.0)


def test_correlated_horizon_errors_in_the_starlight_angles():
    """The CNS angles' horizon error: a Gauss-Markov sequence of the chosen correlation time and the
    same steady-state sigma as the white one (star noise made negligible)."""
    s = stars.directions(("Arcturus",))
    r = np.array([4.2e6, 0.0, 0.0])
    n, dt, tau = 400_000, 3.0, 300.0
    states = np.tile(np.r_[r, 0.0, 0.0, 0.0], (n, 1))
    noise = np.random.default_rng(11).standard_normal((n, 4))
    sig = math.radians(0.05)
    true = np.arccos(-r @ s[0] / 4.2e6)
    white = optics.CNSInstrument(s, 1e-12, sig, dt)(states, noise, np.empty((n, 1)))[:, 0] - true
    sim = optics.CNSInstrument(s, 1e-12, sig, dt, tau_s=tau)
    half = n // 2  # two chunks: the sequence carries over
    gm = np.concatenate([sim(states[:half], noise[:half], np.empty((half, 1))),
                         sim(states[half:], noise[half:], np.empty((n - half, 1)))])[:, 0] - true
    assert np.std(white) == pytest.approx(sig, rel=0.02)
    assert np.std(gm) == pytest.approx(sig, rel=0.05)
    for e, lag, want in ((white, 1, 0.0), (gm, 1, math.exp(-dt / tau)), (gm, 100, math.exp(-1.0))):
        rho = np.mean((e[lag:] - e.mean()) * (e[:-lag] - e.mean())) / np.var(e)
        assert rho == pytest.approx(want, abs=0.03)


def test_instruments_with_the_papers_options_are_the_compiled_models():
    g = np.random.default_rng(2)
    states = np.c_[g.uniform(-5e6, 5e6, (50, 3)), np.zeros((50, 3))]
    states[:, 0] += np.sign(states[:, 0]) * 4e6
    noise = g.standard_normal((50, 8))
    uv = optics.UVInstrument(5000.0, 1e-3)(states, noise[:, :3], np.empty((50, 4)))
    np.testing.assert_allclose(uv, series.simulate_uv(states, noise[:, :3], 5000.0, 1e-3,
                                                      np.empty((50, 4))), rtol=1e-12, atol=1e-9)
    sd = stars.directions(("Arcturus", "Procyon", "Acrux"))
    cns = optics.CNSInstrument(sd, 1e-5, 1e-3, 3.0)(states, noise, np.empty((50, 3)))
    np.testing.assert_allclose(cns, series.simulate_cns(states, noise, sd, 1e-5, 1e-3,
                                                        np.empty((50, 3))), rtol=0, atol=1e-12)


def test_scenario_options_keep_the_papers_defaults_and_draw_the_same_noise():
    paper = scenarios.MarsScenario(days=0.01, subsystems=("uv", "cns"))
    assert optics.is_paper(paper)
    assert optics.uv_series_model(paper, paper.sensors()["uv"])[0] is series.simulate_uv
    real = scenarios.MarsScenario(days=0.01, subsystems=("uv", "cns"), uv_range_model="radius",
                                  horizon_tau_s=1000.0)
    assert not optics.is_paper(real)
    zp, zr = scenarios.prepare(paper), scenarios.prepare(real)
    rho = np.linalg.norm(zp.truth[zp.meas_idx[:, 0] >= 0, :3], axis=1)
    w = (zp.z["uv"][:, 0] - rho) / 5000.0  # the paper's draws, recovered
    sim = optics.UVInstrument(5000.0, math.radians(0.1), "radius")
    want = optics.R_EQUATOR / np.sin(np.arcsin(optics.R_EQUATOR / rho) + sim.sigma_alpha * w)
    np.testing.assert_allclose(zr.z["uv"][:, 0], want, rtol=1e-9)
    np.testing.assert_allclose(zr.z["uv"][:, 1:], zp.z["uv"][:, 1:], atol=1e-12)  # same draws
    assert not np.allclose(zr.z["cns"], zp.z["cns"])
    for kwargs, name in (({"uv_range_model": "lidar"}, "uv_range_model"), ({"limb": "flat"}, "limb"),
                         ({"horizon_tau_s": -1.0}, "horizon_tau_s")):
        with pytest.raises(ValueError, match=name):
            scenarios.MarsScenario(**kwargs)


def test_the_series_models_refuse_a_scenario_or_sensor_of_another_kind():
    sc = scenarios.MarsScenario()
    sensors = sc.sensors()
    for call, message in (
            (lambda: optics.is_paper({"limb": "sphere"}), r"^scenario must be a MarsScenario"),
            (lambda: optics.uv_series_model(None, sensors["uv"]), r"^scenario must be a MarsScenario"),
            (lambda: optics.uv_series_model(sc, sensors["cns"]), r"^uv must be a UVSensor"),
            (lambda: optics.cns_series_model(sc, sensors["uv"]), r"^cns must be a CNSSensor"),
            (lambda: optics.cns_series_model("paper", sensors["cns"]), r"^scenario must be a MarsScenario")):
        with pytest.raises(ValueError, match=message):
            call()


def test_radius_range_sigma_refuses_an_angle_noise_beyond_pi():
    """Review 35e: sigma_alpha=1e308 overflowed to an inf range noise."""
    with pytest.raises(ValueError, match=r"^sigma_alpha must be a real number in \[0, 3.14159\]"):
        optics.radius_range_sigma(2.0 * optics.R_MARS, 1e308)


@pytest.mark.parametrize(("call", "words"), [
    (lambda: optics.range_from_radius(5e-324), r"^alpha must be in \[1e-09, pi/2\) rad, got 4\.94066e-324"),
    (lambda: optics.range_from_radius(0.0), r"^alpha must be in \[1e-09, pi/2\) rad, got 0"),
    (lambda: optics.sigma_alpha_for(ranges=np.array([])), r"^ranges must be a 1-D array of at least one"),
    (lambda: optics.sigma_alpha_for(ranges=[[4e6, 5e6]]), r"^ranges must be a 1-D array"),
    (lambda: optics.sigma_alpha_for(ranges=[1.0]), r"^ranges must be in \(radius, radius / MIN_ALPHA\]"),
    (lambda: optics.sigma_alpha_for(ranges=[1e200]), r"^ranges must be in \(radius, radius / MIN_ALPHA\]"),
    (lambda: optics.radius_range_sigma(1e308, 1e-3), r"^rho must be in \(radius, radius / MIN_ALPHA\]"),
])
def test_no_range_or_apparent_radius_overflows_and_an_empty_orbit_has_no_mean(call, words):
    """Issue 35, review 35f 37/38: 'Mean of empty slice' (NaN) and 'overflow in scalar divide'."""
    with pytest.raises(ValueError, match=words):
        call()


def test_the_extreme_accepted_apparent_radius_and_range_are_finite():
    rho = optics.range_from_radius(optics.MIN_ALPHA)
    assert math.isfinite(float(rho)) and rho <= optics.R_MARS / optics.MIN_ALPHA * (1 + 1e-12)
    assert math.isfinite(float(optics.sigma_alpha_for(ranges=[optics.R_MARS / optics.MIN_ALPHA])))


def test_a_subnormal_radius_or_a_scalar_series_is_refused_by_name():
    """Issue 35 (review 35h): ``limb_fit(a=5e-324)`` divided by zero (1/a^2) and
    ``gauss_markov(-0.0, ...)`` was an IndexError."""
    r = np.array([0.0, 0.0, 2.0 * optics.R_MARS])
    with pytest.raises(ValueError, match=r"^a must be a real number in \[1, 1e\+09\], got 5e-324$"):
        optics.limb_fit(r, a=5e-324)
    with pytest.raises(ValueError, match=r"^c must be a real number in \[1, 1e\+09\], got 5e-324$"):
        optics.limb_fit(r, c=5e-324)
    with pytest.raises(ValueError, match=r"^w must be an array with time along axis 0, got a scalar"):
        optics.gauss_markov(-0.0, 0.5)
    assert optics.gauss_markov([], 0.5).shape == (0,)  # an empty chunk stays one


def test_gauss_markov_names_g0_of_the_wrong_shape():
    """Review 35j (2) 7: numpy's 'remapped shapes' broadcast message."""
    with pytest.raises(ValueError, match=r"^g0 must have shape \(2,\) \(w's shape past axis 0\), "
                                         r"or one that broadcasts to it, got shape \(3,\)$"):
        optics.gauss_markov(np.ones((5, 2)), 0.5, g0=np.ones(3))
    assert optics.gauss_markov(np.zeros((2, 2)), 0.5, g0=1.0)[0].tolist() == [0.5, 0.5]


def test_a_pole_unused_or_not_unit_is_refused():
    """Review 35j (5) 7, (5) 30: a pole with the sphere was unused; a pole of norm 2 was
    taken (the limb functions rescaled it, a zero one divided by zero)."""
    with pytest.raises(ValueError, match=r"^pole is unused with limb = 'sphere' \(a sphere has no "
                                         r"pole\): leave it out or take limb = 'oblate'$"):
        optics.UVInstrument(5000.0, 1e-3, limb="sphere", pole=np.array([0.0, 0.0, 1.0]))
    with pytest.raises(ValueError, match=r"^pole is unused with limb = 'sphere'"):
        optics.CNSInstrument(np.eye(3), 1e-5, 1e-3, 3.0, pole=np.array([0.0, 0.0, 1.0]))
    for call in (lambda p: optics.UVInstrument(5000.0, 1e-3, limb="oblate", pole=p),
                 lambda p: optics.limb_fit(np.array([4e6, 0.0, 0.0]), p),
                 lambda p: optics.limb_bias(np.array([4e6, 0.0, 0.0]), p)):
        with pytest.raises(ValueError, match=r"^pole must be a unit vector, shape \(3,\), norm "
                                             r"within 1e-06 of 1 \(not rescaled\), got norm 2$"):
            call(np.array([0.0, 0.0, 2.0]))
        with pytest.raises(ValueError, match=r"^pole must be a unit vector, .*, got norm 0$"):
            call(np.zeros(3))


@pytest.mark.parametrize(("star_dirs", "message"), [
    (2 * np.eye(3), r"^star_dirs\[0\] must be a unit vector \(norm within 1e-06 of 1, not "
                    r"rescaled\), got norm 2$"),
    (np.array([[1.0, 0, 0], [0, 1.0, 0], [1.0, 0, 0]]),
     r"^star_dirs lists one direction twice \(rows 0 and 2\)$"),
    (np.zeros((0, 3)), r"^star_dirs must have shape \(k, 3\), one unit vector a star, k >= 1, "
                       r"got shape \(0, 3\)$"),
    (np.array([1.0, 0, 0]), r"^star_dirs must have shape \(k, 3\), .*, got shape \(3,\)$"),
])
def test_cns_instrument_refuses_star_directions_not_unit_repeated_or_none(star_dirs, message):
    """Review 35j (5) 30: all three were accepted."""
    with pytest.raises(ValueError, match=message):
        optics.CNSInstrument(star_dirs, 1e-5, 1e-3, 3.0)


def test_orbit_ranges_takes_one_state_above_mars():
    """Review 35k (1) 15, (2) 4: a state at the centre was a divide-by-zero warning and a
    (1, 6) one numpy's matmul message."""
    with pytest.raises(ValueError, match=r"^state0 position must lie outside Mars"):
        optics.orbit_ranges(state0=np.zeros(6))
    with pytest.raises(ValueError, match=r"^state0 must be a 1-D array \(shape \(6,\)\), got "
                                         r"shape \(1, 6\)$"):
        optics.orbit_ranges(state0=optics.MARS_STATE0[None])


def test_a_subnormal_radius_is_refused_not_a_zero_angle():
    """Review 35k pattern D: radius=5e-324 (inside (0, 1e9]) gave an apparent radius of 0
    rad, and r_fit=5e-324 a range bias of -4500 km."""
    for call in (lambda: optics.apparent_radius(4e6, radius=5e-324),
                 lambda: optics.radius_range_sigma(7e6, 1e-3, radius=5e-324)):
        with pytest.raises(ValueError, match=r"^radius must be a real number in \[1, 1e\+09\], "
                                             r"got 5e-324$"):
            call()
    with pytest.raises(ValueError, match=r"^r_fit must be a real number in \[1, 1e\+09\]"):
        optics.limb_bias(np.array([4.2e6, 0.0, 0.0]), r_fit=5e-324)
