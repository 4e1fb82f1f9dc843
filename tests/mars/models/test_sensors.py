"""Measurement models (XNAV, UV, CNS): h(x), Jacobians against finite differences, noise models."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from xnavlab.core.constants import C
from xnavlab.mars.models import dynamics, sensors, stars
from xnavlab.mars.timing import pulsars, toa

ARCSEC = math.pi / (180 * 3600)


def _state(seed):
    """A random state around Mars (radius 3.6-20 Mm)."""
    rng = np.random.default_rng(seed)
    u = rng.standard_normal(3)
    r = u / np.linalg.norm(u) * rng.uniform(3.6e6, 2.0e7)
    return np.concatenate([r, rng.standard_normal(3) * 3e3])


def _fd_jacobian(h, x, step=1.0):
    """Central finite differences of h over the state (position steps in m)."""
    cols = []
    for j in range(6):
        e = np.zeros(6)
        e[j] = step
        cols.append((h(x + e) - h(x - e)) / (2 * step))
    return np.array(cols).T


@given(st.integers(0, 100_000))
def test_uv_jacobian_matches_finite_differences(seed):
    x = _state(seed)
    H = sensors.uv_jacobian(x)
    np.testing.assert_allclose(H, _fd_jacobian(sensors.uv_h, x), rtol=1e-6, atol=1e-13)
    z = sensors.uv_h(x)
    assert z[0] == pytest.approx(np.linalg.norm(x[:3]))
    assert np.linalg.norm(z[1:]) == pytest.approx(1.0)
    # the direction block is orthogonal to u: the radial residual carries no information
    np.testing.assert_allclose(z[1:] @ H[1:, :3], 0.0, atol=1e-20)


@given(st.integers(0, 100_000))
def test_cns_jacobian_matches_finite_differences(seed):
    x = _state(seed)
    s = stars.directions(stars.pick_three())
    H = sensors.cns_jacobian(x, s)
    np.testing.assert_allclose(H, _fd_jacobian(lambda y: sensors.cns_h(y, s), x),
                               rtol=1e-5, atol=1e-14)
    u = -x[:3] / np.linalg.norm(x[:3])
    np.testing.assert_allclose(sensors.cns_h(x, s), np.arccos(s @ u), atol=1e-12)  # eq. (6)


@given(st.integers(0, 100_000))
def test_xnav_jacobian_matches_finite_differences(seed):
    x = _state(seed)
    n, d = pulsars.directions()
    rm, rs = np.array([2.1e11, -4e10, 1e10]), np.array([1e8, 5e8, -2e7])
    H = sensors.xnav_jacobian(x, rm, rs, n, d)
    fd = _fd_jacobian(lambda y: sensors.xnav_h(y, rm, rs, n, d), x, step=100.0)
    np.testing.assert_allclose(H[:, :3], fd[:, :3], rtol=1e-6)
    assert not H[:, 3:].any()
    np.testing.assert_allclose(sensors.xnav_h(x, rm, rs, n, d), toa.delay(rm + x[:3], n, d, rs))


def test_xnav_sigma_from_ranging_accuracies():
    np.testing.assert_allclose(sensors.xnav_sigma() * C, [109, 344, 1866, 325], rtol=0.01)
    xs = sensors.XNAVSensor()
    assert xs.R().shape == (4, 4) and xs.dim == 4
    with pytest.raises(ValueError, match="sigma must hold 4"):
        sensors.XNAVSensor(sigma=[1e-7])
    with pytest.raises(ValueError):
        sensors.XNAVSensor(pulsar_names=("B0000+00",))


def test_xnav_sensor_uses_its_ephemeris():
    x = dynamics.MARS_STATE0
    t = dynamics.MARS_T0
    a = sensors.XNAVSensor(ephem="de421").h(x, t)
    b = sensors.XNAVSensor(ephem="de405").h(x, t)
    assert 0 < np.max(np.abs(a - b)) * C < 1e5     # km-level ephemeris difference


def test_perturb_direction_statistics():
    rng = np.random.default_rng(0)
    u = np.tile([0.6, 0.0, 0.8], (200_000, 1))
    sigma = math.radians(0.1)
    v = sensors.perturb_direction(u, sigma, rng.standard_normal((u.shape[0], 2)))
    np.testing.assert_allclose(np.linalg.norm(v, axis=1), 1.0, atol=1e-14)
    e1, e2 = sensors.tangent_basis(u[0])
    for e in (e1, e2):
        assert np.std(v @ e) == pytest.approx(sigma, rel=0.01)
    ang = np.arccos(np.clip(v @ u[0], -1, 1))
    assert ang.mean() == pytest.approx(sigma * math.sqrt(math.pi / 2), rel=0.01)  # Rayleigh


def test_tangent_basis_is_orthonormal_everywhere():
    for u in ([0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [0.3, -0.4, np.sqrt(0.75)]):
        u = np.array(u)
        e1, e2 = sensors.tangent_basis(u)
        B = np.array([u, e1, e2])
        np.testing.assert_allclose(B @ B.T, np.eye(3), atol=1e-14)
        assert np.linalg.det(B) == pytest.approx(1.0)


def test_uv_noise_matches_R():
    uv = sensors.UVSensor()
    x = dynamics.MARS_STATE0
    states = np.tile(x, (100_000, 1))
    z = uv.simulate(states, rng=1)
    res = z - uv.h(x)
    assert np.std(res[:, 0]) == pytest.approx(5000.0, rel=0.01)
    u = uv.h(x)[1:]
    C_dir = np.cov(res[:, 1:].T)
    np.testing.assert_allclose(C_dir, uv.sigma_dir**2 * (np.eye(3) - np.outer(u, u)),
                               atol=0.02 * uv.sigma_dir**2)


def test_cns_noise_matches_correlated_R():
    cns = sensors.CNSSensor()
    x = dynamics.MARS_STATE0
    z = cns.simulate(np.tile(x, (200_000, 1)), rng=2)
    emp = np.cov((z - cns.h(x)).T)
    R = cns.R(x)
    np.testing.assert_allclose(emp, R, atol=0.03 * R.max())
    assert abs(R[0, 1]) > 0.1 * R[0, 0]      # the horizon error is common to the three angles
    assert np.std(z - cns.h(x), axis=0) == pytest.approx(
        np.sqrt(cns.sigma_horizon**2 + cns.sigma_star**2), rel=0.02)


def test_cns_defaults_and_validation():
    cns = sensors.CNSSensor()
    assert cns.sigma_star == pytest.approx(3 * ARCSEC)
    assert cns.sigma_horizon == pytest.approx(math.radians(0.05))
    with pytest.raises(ValueError, match="unknown star"):
        sensors.CNSSensor(star_names=("Nostar",))
    with pytest.raises(ValueError, match="sigma_horizon_deg"):
        sensors.CNSSensor(sigma_horizon_deg=-1)
    with pytest.raises(ValueError, match="along the Mars direction"):
        sensors.cns_jacobian(np.array([-1e6, 0, 0, 0, 0, 0]), np.array([[1.0, 0, 0]]))
    with pytest.raises(ValueError, match="non-zero position"):
        sensors.uv_h(np.zeros(6))


def test_position_dop_observability():
    x = dynamics.MARS_STATE0
    uv = sensors.UVSensor()
    axes_uv = sensors.position_dop(uv.jacobian(x), uv.R())
    assert np.all(np.isfinite(axes_uv))                 # range + direction: full position
    assert axes_uv[-1] == pytest.approx(5000.0, rel=1e-6)                     # along the range
    assert axes_uv[0] == pytest.approx(np.linalg.norm(x[:3]) * uv.sigma_dir, rel=1e-6)  # across
    cns = sensors.CNSSensor()
    axes_cns = sensors.position_dop(cns.jacobian(x), cns.R(x))
    assert np.isinf(axes_cns[0]) and np.all(np.isfinite(axes_cns[1:]))   # no range


def test_star_table_hipparcos_and_proper_motion():
    assert len(stars.catalogue()) == 38
    ra, dec = stars.radec(stars.direction("Sirius", 0.0))
    # SIMBAD J2000 position of Sirius (Hipparcos propagated): 101.28715533, -16.71611586
    assert (ra - 101.28715533) * math.cos(math.radians(dec)) * 3.6e6 == pytest.approx(0, abs=2)
    assert (dec + 16.71611586) * 3.6e6 == pytest.approx(0, abs=2)
    ra91, dec91 = stars.radec(stars.direction("Sirius", stars.HIPPARCOS_EPOCH))
    assert ra91 == pytest.approx(101.28854105, abs=1e-8)
    with pytest.raises(ValueError, match="known stars"):
        stars.get("Nostar")


def test_pick_three_is_well_spread_and_respects_exclusions():
    trio = stars.pick_three()
    assert len(set(trio)) == 3
    assert stars.spread(stars.directions(trio)) > 0.95
    sun = stars.direction(trio[0])
    other = stars.pick_three(avoid=sun, avoid_deg=30.0)
    assert trio[0] not in other
    with pytest.raises(ValueError, match=r"^vmag_max = -1 leaves 1 of the catalogue.s stars"):
        stars.pick_three(vmag_max=-1.0)  # review 35j: the message leads with vmag_max


def test_optical_semi_axes_combine_the_information():
    x = dynamics.MARS_STATE0
    uv, cns = sensors.UVSensor(), sensors.CNSSensor(epoch=dynamics.MARS_T0)
    ax = sensors.optical_semi_axes(x, uv, cns)
    assert np.allclose(ax["UV"], sensors.position_dop(uv.jacobian(x), uv.R()))
    assert np.isinf(ax["CNS"][0]) and np.all(np.isfinite(ax["CNS"][1:]))  # no range
    # adding the CNS can only shrink every axis, and the range axis stays the UV's 5 km
    assert np.all(ax["UV + CNS"] <= ax["UV"] * (1 + 1e-12))
    assert ax["UV + CNS"][0] == pytest.approx(5000.0, rel=1e-6)
    with pytest.raises(ValueError, match="x"):
        sensors.optical_semi_axes(np.zeros(6), uv, cns)


def test_plot_optical_geometry_scales_with_the_noise():
    lines = sensors.plot_optical_geometry(0.1, 0.05, 1.0).axes[0].lines
    coarse = sensors.plot_optical_geometry(0.2, 0.1, 1.0).axes[0].lines
    assert len(lines) == 6 and lines[0].get_xdata().size == 35
    # the UV across-track axis is r sigma_dir; the CNS axes r sigma_horizon (star noise aside)
    np.testing.assert_allclose(coarse[0].get_ydata(), 2 * lines[0].get_ydata(), rtol=1e-9)
    np.testing.assert_allclose(coarse[2].get_ydata(), 2 * lines[2].get_ydata(), rtol=0.01)


def test_plot_optical_geometry_keeps_its_legend_off_the_curves_and_labels_plain_numbers():
    fig = sensors.plot_optical_geometry(0.1, 0.05, 1.0)
    ax = fig.axes[0]
    assert ax.get_legend() is None and len(fig.legends) == 1   # the legend is the figure's
    fig.canvas.draw()
    labels = [t.get_text() for t in ax.get_yticklabels(minor=True) + ax.get_yticklabels()]
    assert labels and not any("times" in t or "^" in t for t in labels)   # no 6 x 10^0


def test_plot_optical_geometry_updates_in_place_and_a_refused_update_changes_nothing():
    from xnavlab.core.plotting import updater

    fig = sensors.plot_optical_geometry(0.1, 0.05, 1.0)
    updater(fig)(0.2, 0.1, 1.0)
    fresh = sensors.plot_optical_geometry(0.2, 0.1, 1.0)
    for a, b in zip(fig.axes[0].lines, fresh.axes[0].lines, strict=True):
        np.testing.assert_array_equal(a.get_ydata(), b.get_ydata())
    before = [ln.get_ydata().copy() for ln in fig.axes[0].lines]
    with pytest.raises(ValueError, match="sigma_dir_deg"):
        updater(fig)(sigma_dir_deg=-1.0)
    for a, b in zip(fig.axes[0].lines, before, strict=True):
        np.testing.assert_array_equal(a.get_ydata(), b)


def test_direction_noise_and_xnav_model_refuse_complex_and_name_their_arguments():
    with pytest.raises(ValueError, match="^u must hold real numbers"):
        sensors.perturb_direction(np.array([0, 0, 1 + 0j]), 1e-3, np.zeros(2))
    with pytest.raises(ValueError, match="^u must hold unit vectors"):
        sensors.tangent_basis([0.0, 0.0, 2.0])
    n, d = pulsars.directions()
    with pytest.raises(ValueError, match="^r_mars_ssb must contain only finite"):
        sensors.xnav_h(np.r_[4e6, 0, 0, 0, 0, 0], [np.nan, 0, 0], [1e8, 0, 0], n, d)


def test_position_dop_refuses_an_indefinite_or_singular_r_and_keeps_unobservable_as_inf():
    """Review 35 D.13: an indefinite R gave [inf, 1, 1] as if a direction were unobservable."""
    H = np.hstack([np.eye(3), np.zeros((3, 3))])
    with pytest.raises(ValueError, match=r"^R must be positive definite, but it is indefinite"):
        sensors.position_dop(H, np.diag([1.0, -1.0, 1.0]))
    with pytest.raises(ValueError, match=r"^R must be positive definite, but it is singular"):
        sensors.position_dop(H, np.diag([1.0, 0.0, 1.0]))
    with pytest.raises(ValueError, match=r"^R must be a square matrix of shape \(\.\.\., 3, 3\)"):
        sensors.position_dop(H, np.eye(2))
    with pytest.raises(ValueError, match=r"^H must have shape \(m, n\) with n >= 3"):
        sensors.position_dop(np.eye(2), np.eye(2))
    assert np.all(np.isinf(sensors.position_dop(np.zeros((2, 6)), np.eye(2))))   # unobservable


def test_a_star_listed_twice_is_refused_as_by_the_scenario():
    with pytest.raises(ValueError, match=r"^star_names lists Sirius twice \(items 0 and 1\)"):
        sensors.CNSSensor(("Sirius", "Sirius", "Vega"))
    with pytest.raises(ValueError, match=r"^star_names must be a list of stars, got the string"):
        sensors.CNSSensor("Sirius")


def test_uv_R_refuses_a_range_noise_beyond_the_sensors_range():
    """Review 35e: sigma_range=1e308 was 'OverflowError: (34, 'Numerical result out of range')'."""
    with pytest.raises(ValueError, match=r"^sigma_range must be a real number in \[1e-100, 1e\+07\], got 1e"):
        sensors.uv_R(1e308, 0.5)


_X = np.array([-3437565.6, -1322042.9, -2631212.1, 1953.9, -253.7, -2198.7])


@pytest.mark.parametrize(("call", "words"), [
    (lambda: sensors.cns_h(_X, np.zeros((3, 3))), r"^star_dirs must hold unit vectors \(norm within "
                                                   r"1e-6 of 1\), got one of norm 0"),
    (lambda: sensors.cns_h(_X, 5 * np.eye(3)), r"^star_dirs must hold unit vectors .* norm 5"),
    (lambda: sensors.cns_jacobian(_X, 5 * np.eye(3)), r"^star_dirs must hold unit vectors"),
    (lambda: sensors.cns_R(_X, np.zeros((2, 3))), r"^star_dirs must hold unit vectors"),
    (lambda: sensors.tangent_basis(np.array([1e308, 1e308, 0])), r"^u must hold unit vectors .* norm inf"),
    (lambda: sensors.perturb_direction(np.array([1e308, 1e308, 0]), 0.1, np.zeros(2)),
     r"^u must hold unit vectors"),
    (lambda: sensors.uv_h(np.array([1e308, 1e308, 0, 0, 0, 0])), r"^x must have a non-zero position, "
                                                                  r"1 m to 1e\+13 m from Mars's centre"),
    (lambda: sensors.uv_jacobian(np.array([5e-324, 0, 0, 0, 0, 0])), r"^x must have a non-zero position"),
    (lambda: sensors.cns_h(np.array([1e200, 0, 0, 0, 0, 0]), np.eye(3)), r"^x must have a non-zero "),
])
def test_directions_must_be_unit_vectors_and_positions_in_range(call, words):
    """Issue 35, review 35f 39/46: zero or scaled star directions gave [0, 0, 0] or meaningless
    angles; a huge u or position overflowed its norm (RuntimeWarning)."""
    with pytest.raises(ValueError, match=words):
        call()


def test_xnav_sigma_names_background_as_given():
    """Issue 35: background=100 was refused as background_ph_cm2_s (pulsars' name)."""
    with pytest.raises(ValueError, match=r"^background must be a real number in \[0, 10\], got 100"):
        sensors.xnav_sigma(background=100.0)


@pytest.mark.parametrize("R", [5e-324 * np.eye(3), np.diag([1.0, 1.0, 5e-324])])
def test_position_dop_refuses_an_r_whose_inverse_overflows(R):
    """Issue 35, review 35f 41's class: R = 5e-324 I leaked numpy's LinAlgError 'Eigenvalues did
    not converge'."""
    H = np.hstack([np.eye(3), np.zeros((3, 3))])
    with pytest.raises(ValueError, match=r"^R must have an inverse within float64 \(smallest variance 4\.9"):
        sensors.position_dop(H, R)
    assert np.all(np.isfinite(sensors.position_dop(H, 1e-300 * np.eye(3))))


def test_an_edge_sigma_or_sensor_is_refused_by_name():
    """Issue 35 (review 35h): an empty ``sigma`` was numpy's broadcast error, and
    ``optical_semi_axes(x, True, cns)`` an AttributeError ('bool' has no 'jacobian')."""
    u, w = np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0])
    with pytest.raises(ValueError, match=r"^sigma must be one number, rad, or one per direction"):
        sensors.perturb_direction(u, [], w)
    with pytest.raises(ValueError, match=r"^sigma must be one number.*got shape \(3,\)$"):
        sensors.perturb_direction(u, [0.1, 0.2, 0.3], w)
    assert sensors.perturb_direction(u, [0.01], w).shape == (3,)
    x = np.array([4.0e6, 0.0, 0.0, 0.0, 3000.0, 0.0])
    cns = sensors.CNSSensor(("Sirius", "Canopus", "Vega"))
    with pytest.raises(ValueError, match=r"^uv must be a UVSensor, got bool True$"):
        sensors.optical_semi_axes(x, True, cns)
    with pytest.raises(ValueError, match=r"^cns must be a CNSSensor, got list \[\]$"):
        sensors.optical_semi_axes(x, sensors.UVSensor(), [])


def test_xnav_sensor_refuses_noise_settings_beside_sigma_and_an_unknown_ephemeris():
    """Review 35j (5) 6, (5) 19: area_m2 beside sigma was unused (MarsScenario refuses the
    same); ephem='x' was refused only at the first h."""
    for name, value in (("area_m2", 5.0), ("t_obs", 1000.0), ("background", 0.0)):
        with pytest.raises(ValueError, match=rf"^{name} = {value} is unused: sigma gives the delay "
                                             r"noise it would compute; give one of them$"):
            sensors.XNAVSensor(sigma=np.ones(4) * 1e-6, **{name: value})
    with pytest.raises(ValueError, match=r"^ephem must be one of 'de421', 'de405', got 'x'$"):
        sensors.XNAVSensor(ephem="x")
    assert sensors.XNAVSensor(sigma=np.ones(4) * 1e-6, area_m2=1.0).dim == 4  # the default


def test_one_state_of_another_shape_is_refused_as_x():
    """Review 35k (2) 3, (3) 8: a (1, 6) x was numpy's matmul message in cns_jacobian and
    cns_R, and 'uv_jacobian takes one state' (no parameter) in uv_jacobian and
    optical_semi_axes."""
    x = np.array([4.0e6, 0.0, 0.0, 0.0, 3000.0, 0.0])[None]
    dirs = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    cns = sensors.CNSSensor(("Sirius", "Canopus", "Vega"))
    for call in (lambda: sensors.cns_jacobian(x, dirs), lambda: sensors.cns_R(x, dirs, 1.0, 2.0),
                 lambda: sensors.uv_jacobian(x),
                 lambda: sensors.optical_semi_axes(x, sensors.UVSensor(), cns)):
        with pytest.raises(ValueError, match=r"^x must be a 1-D array \(shape \(6,\)\), got "
                                             r"shape \(1, 6\)$"):
            call()


@pytest.mark.parametrize("bad", [math.nan, None, "1.0", True, 1e300])
def test_a_cns_epoch_is_refused_as_epoch(bad):
    """Review 35k (3) 6: refused as pick_three's 't'."""
    with pytest.raises(ValueError, match=r"^epoch must be a real number in \[-1e\+11, 1e\+11\], "
                                         r"got "):
        sensors.CNSSensor(epoch=bad)


def test_a_subnormal_noise_is_refused_under_the_users_name():
    """Review 35k (3) 9: plot_optical_geometry(sigma_dir_deg=5e-324) was refused as
    'sigma_dir ... in (0, 3.14159], got 0.0' (radians, after conversion); a subnormal sigma
    made a zero variance."""
    for kw in ({"sigma_dir_deg": 5e-324}, {"sigma_horizon_deg": 5e-324}):
        (name,) = kw
        with pytest.raises(ValueError, match=rf"^{name} must be a real number in \[1e-100, 90\], "
                                             r"got 5e-324$"):
            sensors.plot_optical_geometry(**kw)
    with pytest.raises(ValueError, match=r"^sigma_range must be a real number in \[1e-100, "):
        sensors.UVSensor(sigma_range=5e-324)
    with pytest.raises(ValueError, match=r"^sigma_star_arcsec must be a real number in \[1e-100"):
        sensors.CNSSensor(sigma_star_arcsec=5e-324)
    with pytest.raises(ValueError, match=r"^sigma_dir must be a real number in \[1e-120, "):
        sensors.uv_R(1.0, 5e-324)
    tiny = sensors.CNSSensor(sigma_star_arcsec=1e-100, sigma_horizon_deg=1e-100)
    assert np.all(np.diag(tiny.R(np.array([4.0e6, 0.0, 0.0, 0.0, 3000.0, 0.0]))) > 0.0)
