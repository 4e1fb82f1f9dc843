"""Dynamics: accelerations, third-body table, compiled RHS vs numpy, propagator accuracy, STM."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from xnavlab.core import ephemeris
from xnavlab.core.constants import DAY, GM_MARS, GM_SUN, J2_MARS, J2_MARS_RADIUS, R_MARS
from xnavlab.mars.models import dynamics

T0, X0 = dynamics.MARS_T0, dynamics.MARS_STATE0


@pytest.fixture(scope="module")
def table():
    return dynamics.ThirdBodyTable(T0, T0 + 2 * DAY)


def test_table_interpolation_matches_ephemeris(table):
    t = T0 + 12345.6
    want = ephemeris.position("sun", t) - ephemeris.position("mars", t)
    assert np.linalg.norm(table.positions(t)[0] - want) < 1e-2  # metres, at 2e11 m
    with pytest.raises(ValueError, match="table's span"):
        table.positions(T0 - 1.0)


def test_third_body_indirect_term_is_tidal():
    # at the centre the perturbation vanishes; along the Sun line it pulls outward (tidal)
    s = np.array([[2.2e11, 0.0, 0.0]])
    assert np.allclose(dynamics.third_body(np.zeros(3), s, [GM_SUN]), 0.0)
    a = dynamics.third_body(np.array([4e6, 0, 0]), s, [GM_SUN])
    tidal = 2 * GM_SUN * 4e6 / 2.2e11**3
    assert abs(a[0] - tidal) / tidal < 1e-3


def test_compiled_rhs_matches_numpy_model(table):
    for j2 in (False, True):
        x = X0 + np.array([1e3, -2e3, 5e2, 0.1, 0.2, -0.3])
        t = T0 + 5000.0
        want = dynamics.acceleration(t, x[:3], table, j2=j2)
        got = dynamics._rhs(t, x, GM_MARS, table.t_start, table.step, table.pos, table.vel,
                            table.gm, J2_MARS if j2 else 0.0, J2_MARS_RADIUS, dynamics.MARS_POLE)
        np.testing.assert_allclose(got[3:], want, rtol=1e-13)
        np.testing.assert_array_equal(got[:3], x[3:])


def test_perturbation_sizes():
    r = X0[:3]
    tab = dynamics.ThirdBodyTable(T0, T0 + 3600.0, ("sun",))
    central = np.linalg.norm(dynamics.point_mass(r))
    sun = np.linalg.norm(dynamics.third_body(r, tab.positions(T0), tab.gm))
    j2 = np.linalg.norm(dynamics.j2_acceleration(r))
    assert 1e-9 < sun / central < 1e-6
    assert 1e-4 < j2 / central < 1e-2


def test_two_body_conserves_energy():
    t = T0 + np.linspace(0, DAY, 50)
    x = dynamics.propagate(t, third_bodies=())
    energy = 0.5 * np.sum(x[:, 3:] ** 2, axis=1) - GM_MARS / np.linalg.norm(x[:, :3], axis=1)
    assert np.ptp(energy) / abs(energy[0]) < 1e-11


def test_thirty_days_within_a_metre_of_a_tighter_run():
    t = T0 + np.array([0.0, 30 * DAY])
    default = dynamics.propagate(t)
    tighter = dynamics.propagate(t, rtol=3e-14, atol=1e-10)
    assert np.linalg.norm(default[-1, :3] - tighter[-1, :3]) < 1.0


def test_truth_cache_round_trip(tmp_path, monkeypatch):
    monkeypatch.setenv("XNAVLAB_CACHE", str(tmp_path))
    t = T0 + np.arange(0.0, 600.0, 60.0)
    a = dynamics.truth(t)
    assert list(tmp_path.glob("truth-*.npy"))
    b = dynamics.truth(t)
    np.testing.assert_array_equal(a, b)
    np.testing.assert_allclose(a, dynamics.propagate(t), rtol=0, atol=1e-6)


def test_a_changed_dynamics_code_computes_the_truth_again(tmp_path, monkeypatch):
    from xnavlab.core import diskcache

    monkeypatch.setenv("XNAVLAB_CACHE", str(tmp_path))
    t = T0 + np.arange(0.0, 180.0, 60.0)
    calls = []
    real = dynamics.propagate
    monkeypatch.setattr(dynamics, "propagate", lambda *a, **k: calls.append(1) or real(*a, **k))
    dynamics.truth(t)
    dynamics.truth(t)
    assert len(calls) == 1                                   # the second read the file
    monkeypatch.setattr(diskcache, "code_digest", lambda modules, root=None: "edited dynamics")
    dynamics.truth(t)
    assert len(calls) == 2 and len(list(tmp_path.glob("truth-*.npy"))) == 2


@given(st.floats(1.0, 10.0))  # filter steps are 3 s; longer steps are subdivided
def test_stm_matches_finite_differences(dt):
    r = X0[:3]
    Phi = dynamics.transition_matrix(r, dt)

    def step(x):
        return dynamics.propagate(np.array([T0 + dt]), x, T0, third_bodies=())[-1]

    eps = np.array([100.0, 100.0, 100.0, 0.1, 0.1, 0.1])
    fd = np.empty((6, 6))
    for i in range(6):
        e = np.zeros(6)
        e[i] = eps[i]
        fd[:, i] = (step(X0 + e) - step(X0 - e)) / (2 * eps[i])
    # G is held constant over the step: the error grows like dG/dt dt^3
    np.testing.assert_allclose(Phi, fd, atol=1e-6)


def test_gravity_gradient_matches_finite_differences():
    r = X0[:3]
    G = dynamics.gravity_gradient(r)
    h = 1.0
    fd = np.column_stack([
        (dynamics.point_mass(r + h * e) - dynamics.point_mass(r - h * e)) / (2 * h) for e in np.eye(3)
    ])
    np.testing.assert_allclose(G, fd, rtol=1e-6)


def test_bad_inputs():
    with pytest.raises(ValueError, match="t_eval must be a non-empty increasing"):
        dynamics.propagate(np.array([T0 + 10.0, T0]))
    with pytest.raises(ValueError, match="outside Mars"):
        dynamics.propagate(np.array([T0]), np.array([1e3, 0, 0, 0, 0, 0]))
    with pytest.raises(ValueError, match=r"bodies\[0\] must be one of"):
        dynamics.ThirdBodyTable(T0, T0 + 10.0, ("saturn",))
    with pytest.raises(ValueError, match="rtol"):
        dynamics.propagate(np.array([T0 + 1.0]), rtol=1e-16)
    with pytest.raises(ValueError, match="state0"):
        dynamics.propagate(np.array([T0 + 1.0]), np.zeros(5))


def test_orbital_elements_of_a_circular_equatorial_orbit():
    r = 4.0e6
    v = np.sqrt(GM_MARS / r)
    el = dynamics.orbital_elements([r, 0, 0, 0, v, 0], pole=np.array([0.0, 0.0, 1.0]))
    assert abs(el.a - r) < 1e-6 * r and el.e < 1e-12
    assert el.inclination < 1e-12 and el.inclination_pole < 1e-12
    assert abs(el.period - 2 * np.pi * np.sqrt(r**3 / GM_MARS)) < 1e-6


def test_orbital_elements_are_conserved_by_two_body_motion():
    t = T0 + np.array([0.0, 3000.0])
    x = dynamics.propagate(t, third_bodies=())
    a, b = dynamics.orbital_elements(x[0]), dynamics.orbital_elements(x[1])
    np.testing.assert_allclose(a[:4], b[:4], rtol=1e-9, atol=1e-12)


def test_orbital_elements_rejects_unbound_states():
    with pytest.raises(ValueError, match="bound orbit"):
        dynamics.orbital_elements([4e6, 0, 0, 0, 1e4, 0])


def test_model_difference_components_add_up():
    t = dynamics.MARS_T0 + np.arange(0.0, 86400.0 + 1.0, 600.0)
    d = dynamics.model_difference(t, third_bodies=("jupiter",))
    assert d["norm"][0] == 0.0 and d["norm"].max() > 0.0
    comp = np.sqrt(d["radial"] ** 2 + d["along"] ** 2 + d["cross"] ** 2)
    np.testing.assert_allclose(comp, d["norm"], rtol=1e-9, atol=1e-9)
    same = dynamics.model_difference(t)
    assert np.all(same["norm"] == 0.0)


def test_plot_model_difference_shows_the_sun_effect():
    fig = dynamics.plot_model_difference(sun=False, days_shown=30)
    norm = fig.axes[0].lines[0].get_ydata()
    assert norm.size == 30 * 1440 + 1
    assert 100.0 < norm.max() < 1000.0  # leaving the Sun out: a few hundred metres in 30 days
    assert [ln.get_label() for ln in fig.axes[1].lines] == ["radial", "along-track", "cross-track"]
    assert "Mars + Jupiter" in fig._suptitle.get_text()
    with pytest.raises(ValueError, match="days_shown"):
        dynamics.plot_model_difference(days_shown=31)


def test_plot_model_difference_updates_in_place_and_a_refused_update_changes_nothing():
    from xnavlab.core.plotting import updater

    fig = dynamics.plot_model_difference(sun=False, days_shown=2)
    updater(fig)(sun=True, jupiter=True, j2=True, days_shown=3)
    assert fig.axes[0].lines[0].get_xdata()[-1] == 3.0
    assert "Mars + Sun + Jupiter + J2" in fig._suptitle.get_text()
    before = fig.axes[0].lines[0].get_ydata().copy(), fig._suptitle.get_text()
    with pytest.raises(ValueError, match="days_shown"):
        updater(fig)(days_shown=0)
    assert np.array_equal(fig.axes[0].lines[0].get_ydata(), before[0])
    assert fig._suptitle.get_text() == before[1]


def test_j2_uses_the_mgs95j_reference_radius():
    """J2 acceleration against the MGS95J formula with R = 3396.0 km (not the IAU 3396.19 km)."""
    mu, j2, radius = 4.28283758e13, 1.95545e-3, 3396.0e3  # MGS95J field, typed independently
    pole = dynamics.MARS_POLE
    for r in (X0[:3], np.array([3.8e6, -1.2e6, 2.5e6]), 4.1e6 * pole + np.array([1e5, 0.0, 0.0])):
        rn = np.linalg.norm(r)
        z = r @ pole
        # gradient of U2 = -mu J2 R^2 / (2 r^3) (3 (z/r)^2 - 1), written out term by term
        want = (-1.5 * mu * j2 * radius**2 / rn**5) * ((1.0 - 5.0 * z**2 / rn**2) * r + 2.0 * z * pole)
        got = dynamics.j2_acceleration(r)
        assert np.linalg.norm(got - want) <= 1e-6 * np.linalg.norm(want)
        total = dynamics.acceleration(T0, r, None, j2=True) - dynamics.point_mass(r)
        assert np.linalg.norm(total - want) <= 1e-6 * np.linalg.norm(want)
    old = (-1.5 * mu * j2 * 3396.19e3**2 / np.linalg.norm(X0[:3]) ** 5)  # IAU radius: 1.1e-4 too strong
    assert abs(old / (-1.5 * mu * j2 * radius**2 / np.linalg.norm(X0[:3]) ** 5) - 1.0) > 1e-4


@pytest.mark.parametrize(("call", "name"), [
    (lambda b: dynamics.point_mass(np.array([4e6, 0.0, b])), "r"),
    (lambda b: dynamics.acceleration(dynamics.MARS_T0, np.array([4e6, 0.0, b])), "r"),
    (lambda b: dynamics.gravity_gradient(np.array([4e6, 0.0, b])), "r"),
    (lambda b: dynamics.transition_matrix(np.array([4e6, 0.0, 0.0]), b), "dt"),
    (lambda b: dynamics.j2_acceleration(np.array([4e6, 0.0, 0.0]), pole=np.array([0, 0, b])), "pole"),
    (lambda b: dynamics.third_body(np.zeros(3), np.array([[1e11, 0, 0]]), np.array([b])), "gm"),
])
@pytest.mark.parametrize("bad", [complex(1, 1), np.nan])
def test_the_force_model_refuses_complex_and_nan_by_name(call, name, bad):
    with pytest.raises(ValueError, match=f"^{name} must"):
        call(bad)


def test_the_centre_itself_is_refused_not_turned_into_nan():
    with pytest.raises(ValueError, match=r"^r must lie between 1 m and 1e\+15 m of the centre"):
        dynamics.point_mass(np.zeros(3))


def test_an_orbit_that_falls_into_mars_is_refused_naming_state0_and_the_time():
    # review 35d D2: a radial fall from 4000 km ended in scipy's "Required step size is less
    # than spacing between numbers" (a traceback from the CLI)
    with pytest.raises(ValueError, match=r"state0: the orbit reaches Mars's surface .* at t0 \+ "
                                         r"654\.\d+ s, before the end of the propagation"):
        dynamics.propagate(dynamics.MARS_T0 + np.array([0.0, 8640.0]),
                           state0=np.array([4e6, 0.0, 0.0, 0.0, 0.0, 0.0]))


@pytest.mark.parametrize(("bodies", "words"), [
    ("sun", "third_bodies must be a list of perturbers, got the string 'sun'"),
    (("sun", "sun"), "third_bodies lists sun twice (items 0 and 1)"),
    (("sun", "pluto"), "third_bodies[1] must be one of 'sun', 'jupiter', got 'pluto'"),
])
def test_third_bodies_are_a_list_of_distinct_names(bodies, words):
    # review 35d D40: a string was split into letters ('s'), and ("sun", "sun") pulled twice
    t = dynamics.MARS_T0 + np.array([0.0, 10.0])
    for call in (lambda: dynamics.propagate(t, third_bodies=bodies),
                 lambda: dynamics.truth(t, third_bodies=bodies, cache=False)):
        with pytest.raises(ValueError) as info:
            call()
        assert words in str(info.value)


@pytest.mark.parametrize("call", [
    lambda: dynamics.acceleration(dynamics.MARS_T0, dynamics.MARS_STATE0[:3], j2="no"),
    lambda: dynamics.propagate(dynamics.MARS_T0 + np.array([0.0, 10.0]), j2="no"),
    lambda: dynamics.truth(dynamics.MARS_T0 + np.array([0.0, 10.0]), cache="no"),
])
def test_flags_must_be_bools(call):  # review 35d D43: "no" switched J2 on
    with pytest.raises(ValueError, match="must be True or False, got 'no'"):
        call()


@pytest.mark.parametrize("pole", [np.zeros(3), np.array([0.0, 0.0, 5.0])])
def test_the_pole_must_be_a_unit_vector(pole):  # review 35d D41
    with pytest.raises(ValueError, match="pole must be a unit vector"):
        dynamics.j2_acceleration(dynamics.MARS_STATE0[:3], pole=pole)


@pytest.mark.parametrize("state", [np.zeros(6), np.array([4e6, 0.0, 0.0, 1e3, 0.0, 0.0])])
def test_elements_of_a_state_without_a_plane_are_refused(state):  # review 35d D42
    with pytest.raises(ValueError, match="state must have a position off the centre"):
        dynamics.orbital_elements(state)


def test_check_state0_bounds_the_speed_by_a_craft_bound_to_the_sun():
    # review 35d D5: a state0 at 3 c was accepted and propagated
    assert dynamics.V_INF_MAX == 65.0e3
    fast = np.array([4e6, 0.0, 0.0, 9e8, 0.0, 0.0])
    for call in (lambda: dynamics.propagate(np.array([T0 + 1.0]), fast),
                 lambda: dynamics.truth(np.array([T0 + 1.0]), fast, cache=False),
                 lambda: dynamics.check_state0(fast)):
        with pytest.raises(ValueError, match=r"^state0 speed must be below 65164.5 m/s at "
                                             r"\|r\| = 4e\+06 m .* got 9e\+08 m/s$"):
            call()
    with pytest.raises(ValueError, match=r"^x speed must be below"):
        dynamics.check_state0(fast, "x")
    with pytest.raises(ValueError, match=r"state0 position must lie outside Mars .* got \|r\| = 0 m"):
        dynamics.check_state0(np.zeros(6))
    with pytest.raises(ValueError, match="state0 must"):
        dynamics.check_state0([4e6, 0.0, 0.0, np.nan, 0.0, 0.0])


def test_check_state0_refuses_a_position_outside_the_hill_sphere():
    # (GM_MARS / 3 GM_SUN)^(1/3) at 1.381 au: 9.8e8 m (Murray & Dermott eq. 3.75)
    assert 9.7e8 < dynamics.R_HILL < 9.9e8
    inside = np.array([0.99 * dynamics.R_HILL, 0.0, 0.0, 0.0, 1e3, 0.0])
    assert np.array_equal(dynamics.check_state0(inside), inside)
    for r in (dynamics.R_HILL, 1e300):
        with pytest.raises(ValueError, match=r"^state0 position must lie inside Mars's Hill sphere "
                                             r"\(\|r\| < 9.8\d*e\+08 m; .*got \|r\| = "):
            dynamics.check_state0([r, 0.0, 0.0, 0.0, 1e3, 0.0])


@given(st.floats(1.0001, 280.0), st.floats(0.0, 2.0), st.floats(-1.0, 1.0))  # inside R_HILL
def test_check_state0_refuses_exactly_the_speeds_at_or_above_the_bound(r_over, frac, cos):
    r = R_MARS * r_over
    v_max = float(np.sqrt(dynamics.V_INF_MAX**2 + 2.0 * GM_MARS / r))
    v = frac * v_max
    s = np.sqrt(1.0 - cos**2)
    state = np.array([r, 0.0, 0.0, v * cos, v * s, 0.0])
    speed = float(np.linalg.norm(state[3:]))
    if speed < v_max:
        assert np.array_equal(dynamics.check_state0(state), state)
    else:
        with pytest.raises(ValueError, match="state0 speed must be below"):
            dynamics.check_state0(state)


@pytest.mark.parametrize("s_off", [0.0, 1e-120])
def test_third_body_at_the_spacecraft_is_refused_not_nan(s_off):  # review 35d D42: NaN warnings
    r = dynamics.MARS_STATE0[:3]
    s = np.stack([np.array([1.5e11, 0.0, 0.0]), r + s_off])
    with pytest.raises(ValueError, match=r"^s\[1\] must differ from r: a body at the spacecraft's"):
        dynamics.third_body(r, s, np.array([GM_SUN, 1e10]))


@pytest.mark.parametrize("r", [[1e-200, 0.0, 0.0], [0.0, 5e-61, 0.0], [0.0, 0.0, 0.999],
                               [1e200, 0.0, 0.0], [0.0, -2e15, 0.0]])
def test_a_position_at_the_centre_or_past_the_planets_is_refused(r):  # review 35d D42: 1/0, NaN
    # issue 35: the gradient's 1/|r|^5 overflowed below 1e-57 m, |r|^3 above 1e102 m
    for call in (dynamics.point_mass, dynamics.j2_acceleration, dynamics.gravity_gradient):
        with pytest.raises(ValueError, match=r"^r must lie between 1 m and 1e\+15 m of the "
                                             r"centre \(the field is singular at it\), got \|r\|"):
            call(np.array(r))


def test_transition_matrix_refuses_a_step_beyond_its_series():
    with pytest.raises(ValueError, match=r"dt must be a real number in \[-1e\+06, 1e\+06\]"):
        dynamics.transition_matrix(dynamics.MARS_STATE0[:3], 1e308)


def test_an_edge_value_of_acceleration_or_the_slider_is_refused_by_name(table):
    """Issue 35 (review 35h): a bool epoch, a table that is no ThirdBodyTable and a slider's
    switch that is no bool were taken (t unused without a table, ``table.bodies`` an
    AttributeError, ``sun=[]`` read as False)."""
    with pytest.raises(ValueError, match=r"^t must be a finite real number, got True$"):
        dynamics.acceleration(True, X0[:3])
    with pytest.raises(ValueError, match=r"^table must be a ThirdBodyTable or None, got float -0.0$"):
        dynamics.acceleration(T0, X0[:3], -0.0)
    with pytest.raises(ValueError, match=r"^sun must be True or False, got \[\]$"):
        dynamics.plot_model_difference(sun=[], days_shown=1)
    with pytest.raises(ValueError, match=r"^jupiter must be True or False"):
        dynamics.plot_model_difference(jupiter=1.0, days_shown=1)


def test_propagate_refuses_a_table_of_the_wrong_kind_bodies_ephemeris_or_span():
    """Review 35j (1) 20 and (5) 11: a dict raised AttributeError 't_start'; a table of other
    bodies or another ephemeris replaced third_bodies or ephem without a word (1.4e-5 m at
    5000 s); a table short of the run was extrapolated."""
    t0 = dynamics.MARS_T0
    te = np.array([t0 + 5000.0])
    tab = dynamics.ThirdBodyTable(t0, t0 + 1e4)
    with pytest.raises(ValueError, match=r"^table must be a ThirdBodyTable \(or None\), got dict"):
        dynamics.propagate(te, table={"x": 1})
    with pytest.raises(ValueError, match=r"^table tabulates \['sun', 'jupiter'\] about mars from "
                                         r"de421, but the run asks third_bodies = \['sun'\] about "
                                         r"mars from ephem = 'de421': the table's would be used"):
        dynamics.propagate(te, third_bodies=("sun",), table=tab)
    with pytest.raises(ValueError, match=r"^table tabulates .* ephem = 'de405'"):
        dynamics.propagate(te, ephem="de405", table=tab)
    with pytest.raises(ValueError, match=r"^table must cover the run, t0 = .* to t_eval\[-1\] = "):
        dynamics.propagate(np.array([t0 + 2e4]), table=tab)
    with pytest.raises(ValueError, match=r"^ephem must be one of 'de421', 'de405', got 'x'$"):
        dynamics.propagate(te, third_bodies=(), ephem="x")
    same = dynamics.propagate(te, third_bodies=("jupiter", "sun"), table=tab)  # any order
    assert np.array_equal(same, dynamics.propagate(te))


def test_j2_acceleration_refuses_a_point_inside_its_reference_sphere():
    """Review 35j (5) 29: 1 m from the centre gave 1e24 m/s^2."""
    with pytest.raises(ValueError, match=r"^r must lie outside the body, on or above the J2 "
                                         r"reference sphere \(\|r\| >= radius = 3.396e\+06 m; the "
                                         r"series diverges inside\), got \|r\| = 1 m$"):
        dynamics.j2_acceleration(np.array([1.0, 0.0, 0.0]))
    with pytest.raises(ValueError, match=r"^r must lie outside the body"):
        dynamics.acceleration(dynamics.MARS_T0, np.array([0.0, 0.0, 3.39e6]), None, j2=True)
    assert np.isfinite(dynamics.j2_acceleration(np.array([J2_MARS_RADIUS, 0.0, 0.0]))).all()


@pytest.mark.parametrize(("call", "message"), [
    (lambda: dynamics.j2_acceleration(np.array([[0.0, 0.0, 4e6]])),
     r"^r must be a 1-D array \(shape \(3,\)\), got shape \(1, 3\)$"),
    (lambda: dynamics.acceleration(T0, np.array([[4e6, 0.0, 0.0]])),
     r"^r must be a 1-D array \(shape \(3,\)\), got shape \(1, 3\)$"),
    (lambda: dynamics.third_body(np.zeros((1, 3)), np.array([[1e11, 0, 0]]), [GM_SUN]),
     r"^r must be a 1-D array \(shape \(3,\)\), got shape \(1, 3\)$"),
    (lambda: dynamics.orbital_elements(X0[None]),
     r"^state must be a 1-D array \(shape \(6,\)\), got shape \(1, 6\)$"),
])
def test_one_position_or_state_of_another_shape_is_refused_by_name(call, message):
    """Review 35k (2) 1, (2) 2: a (1, 3) r was numpy's matmul message, a (1, 6) state its
    two-line cross-product message."""
    with pytest.raises(ValueError, match=message):
        call()


def test_a_table_centre_is_refused_as_center():
    """Review 35k (3) 1: center='' was refused as the ephemeris's 'body'."""
    with pytest.raises(ValueError, match=r"^center must be one of 'sun', .*, got ''$"):
        dynamics.ThirdBodyTable(T0, T0 + 86400.0, center="")


@pytest.mark.parametrize("call", [dynamics.propagate,
                                  lambda t, **kw: dynamics.truth(t, cache=False, **kw)])
def test_propagate_refuses_float32_epochs_a_bad_t0_and_a_span_of_years(call):
    """Review 35k (5) 12, (1) 17 pattern A: float32 epochs (32 s resolution at 5e8 s) gave
    another trajectory; t0 = 0 with 2016 epochs integrated 16 years (minutes, unbounded);
    t0=None was a TypeError in truth's cache key."""
    t = T0 + np.array([0.0, 60.0])
    with pytest.raises(ValueError, match=r"^t_eval must resolve its epochs to 0.001 s: as "
                                         r"float32 it resolves 32 s at 5.04878e\+08 s; pass "
                                         r"float64 epochs$"):
        call(t.astype(np.float32))
    with pytest.raises(ValueError, match=r"^t0 must resolve its epochs"):
        call(t, t0=np.float32(T0))
    with pytest.raises(ValueError, match=r"^t_eval\[-1\] - t0 must be at most 731 days \(the "
                                         r"longest propagation\), got 5843.5 days"):
        call(t, t0=0.0)
    for bad in (None, "1.0", math.nan, True):
        with pytest.raises(ValueError, match=r"^t0 must be a finite real number, got "):
            call(t, t0=bad)
    with pytest.raises(ValueError, match=r"^t0 must be in \[.*\] s TDB past J2000 \(the coverage "
                                         r"of de421\), got 1e\+300$"):
        call(t, t0=1e300)
    # small float32 epochs resolve to 0.1 microsecond: taken
    assert call(np.array([0.0, 1.0], np.float32), t0=0.0, third_bodies=()).shape == (2, 6)
