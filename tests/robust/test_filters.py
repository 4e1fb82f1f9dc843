"""The four filters of Li et al. 2017 (xnavlab.robust.filters): the simulated measurements, the
UKF, ASUKF, TDUKF and RKF steps and their invariants, the RKF's bound, and the filter runs, one
at a time and in a batch."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from xnavlab import robust as rb
from xnavlab.robust import ephemeris_error as ee

N = ee.directions()


R = np.diag(np.square(ee.SIGMA_M))


def _spd(a, n):
    """A symmetric positive-definite matrix from an unconstrained array."""
    A = a.reshape(n, n)
    return A @ A.T + n * np.eye(n)


def _is_psd(P, rtol=1e-9):
    """Symmetric and positive semi-definite within ``rtol`` of the matrix's scale.

    A covariance that is singular by construction (the TDUKF's clone block) has a smallest
    eigenvalue at rounding level whose sign depends on the BLAS kernel, so the test allows
    ``-rtol * max|eig|`` and never decides on that sign.
    """
    scale = np.abs(P).max()
    eig = np.linalg.eigvalsh(0.5 * (P + P.T))
    return np.allclose(P, P.T, rtol=0, atol=1e-9 * scale) and eig.min() >= -rtol * np.abs(eig).max()


@pytest.fixture(scope="module")
def mars_sc():
    return rb.simulate("mars", n_steps=60, rng=3)


def test_simulate_shapes_and_measurement_model():
    sc = rb.simulate("earth", n_steps=8, error="none", rng=0)
    assert sc.t.shape == (8,) and sc.x_true.shape == (8, 6) and sc.y.shape == (8, 3)
    resid = sc.y - sc.x_true[:, :3] @ sc.n.T  # y = N r + N dr_E + v with dr_E = 0
    assert np.all(np.abs(resid) < 6 * np.array(ee.SIGMA_M))
    de = rb.simulate("earth", n_steps=3, rng=0)
    np.testing.assert_allclose(de.dr_e, ee.ephemeris_error("earth", de.t))
    other = rb.simulate("mars", n_steps=2, pulsar_names=("B0531+21", "B1937+21"), rng=0)
    assert other.R.shape == (2, 2)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [({"body": "venus"}, "body"), ({"n_steps": 0}, "n_steps"), ({"dt": 0.0}, "dt"),
     ({"error": "big"}, "error"), ({"size": -1.0}, "size"), ({"sigma_m": [1.0, 2.0]}, "sigma_m")],
)
def test_simulate_rejects_bad_input(kwargs, name):
    with pytest.raises(ValueError, match=name):
        rb.simulate(**({"n_steps": 2} | kwargs))


def test_predict_matches_propagation_for_tight_covariance():
    o = ee.orbit("mars")
    x, P = rb.predict(o.state0, np.eye(6) * 1e-6, 500.0, "mars", np.zeros((6, 6)))
    np.testing.assert_allclose(x, ee.propagate(o.state0, 500.0, "mars"), atol=1e-6)
    assert _is_psd(P + np.eye(6) * 1e-12)
    xa, Pa = rb.predict(np.r_[o.state0, 1.0, 2.0, 3.0], np.eye(9), 500.0, "mars", np.eye(9))
    np.testing.assert_allclose(xa[6:], [1.0, 2.0, 3.0], atol=1e-9)  # the bias is held
    with pytest.raises(ValueError, match="x must hold at least 6 entries"):
        rb.predict(np.zeros(3), np.eye(3), 1.0, "mars", np.eye(3))
    with pytest.raises(ValueError, match="body"):
        rb.predict(o.state0, np.eye(6), 1.0, "venus", np.eye(6))


@given(arrays(float, 36, elements=st.floats(-10, 10)), arrays(float, 3, elements=st.floats(-1e3, 1e3)))
def test_ukf_update_invariants(a, y):
    P = _spd(a, 6)
    x, P1, nu = rb.ukf_update(np.zeros(6), P, y, R, N)
    assert _is_psd(P1)
    assert np.all(np.diag(P1) <= np.diag(P) + 1e-9)  # a measurement never adds uncertainty
    np.testing.assert_allclose(nu, y)


@given(arrays(float, 81, elements=st.floats(-10, 10)))
def test_asukf_update_invariants(a):
    P = _spd(a, 9)
    x, P1, _ = rb.asukf_update(np.zeros(9), P, np.ones(3), R, N)
    assert x.shape == (9,) and _is_psd(P1)


def test_asukf_rejects_wrong_state_size():
    with pytest.raises(ValueError, match="x must have 6 \\+ 3"):
        rb.asukf_update(np.zeros(6), np.eye(6), np.ones(3), R, N)


def test_update_rejects_bad_shapes():
    with pytest.raises(ValueError, match="y must have shape"):
        rb.ukf_update(np.zeros(6), np.eye(6), np.ones(2), R, N)
    with pytest.raises(ValueError, match="n must"):
        rb.ukf_update(np.zeros(6), np.eye(6), np.ones(3), R, np.eye(2))
    with pytest.raises(ValueError, match="x must have 6"):
        rb.ukf_update(np.zeros(7), np.eye(7), np.ones(3), R, N)


def test_tdukf_steps():
    o = ee.orbit("earth")
    x, P = rb.tdukf_predict(np.r_[o.state0, np.zeros(3)], np.diag(np.r_[np.ones(6), ee.SIGMA_M]) ** 2,
                            500.0, "earth", np.eye(6) * 1e-6)
    assert x.shape == (15,) and _is_psd(P)
    np.testing.assert_allclose(x[6:12], o.state0, atol=1e-6)  # the clone
    x1, P1, nu = rb.tdukf_update(x, P, np.zeros(3), R, N, carry_noise=True)
    assert x1.shape == (9,) and _is_psd(P1)
    np.testing.assert_array_equal(P1, P1.T)  # symmetric by construction
    x2, P2, _ = rb.tdukf_update(x[:12], P[:12, :12], np.zeros(3), R, N)  # default: white 2R
    assert x2.shape == (6,) and _is_psd(P2)
    np.testing.assert_array_equal(P2, P2.T)
    with pytest.raises(ValueError, match="12 entries"):
        rb.tdukf_update(x, P, np.zeros(3), R, N, carry_noise=False)
    with pytest.raises(ValueError, match="Q"):
        rb.tdukf_predict(x[:9], P[:9, :9], 500.0, "earth", np.eye(3))


def test_tdukf_cancels_a_constant_bias():
    """Differenced measurements of a constant bias are bias-free: the TDUKF cannot tell the runs apart."""
    clean = rb.simulate("mars", n_steps=30, error="none", rng=5)
    biased = rb.simulate("mars", n_steps=30, error="constant", size=2000.0, rng=5)
    a = rb.run_filter("tdukf", clean, rng=1)
    b = rb.run_filter("tdukf", biased, rng=1)
    np.testing.assert_allclose(a.x, b.x, atol=1e-3)
    u = rb.run_filter("ukf", biased, rng=1)
    assert np.abs(u.x - a.x).max() > 100.0  # the UKF does see the bias


def test_rkf_gain_limits():
    Pzz, Pxz = N @ np.eye(3) @ N.T * 1e4, np.vstack([np.eye(3) * 1e4 @ N.T, np.zeros((3, 3))])
    kf = np.linalg.solve(Pzz + R, Pxz.T).T
    np.testing.assert_allclose(rb.rkf_gain(Pxz, Pzz, R, np.zeros((3, 3)), 1e15), kf, rtol=1e-9)
    b = N @ np.array([1e3, 0.0, 0.0])
    K = rb.rkf_gain(Pxz, Pzz, R, np.outer(b, b), 1e6)
    assert np.linalg.norm(K @ b) < 1e-3 * np.linalg.norm(kf @ b)  # the bias direction is rejected
    with pytest.raises(ValueError, match="eps"):
        rb.rkf_gain(Pxz, Pzz, R, np.zeros((3, 3)), 0.0)


@given(arrays(float, 6, elements=st.floats(-1e3, 1e3)), arrays(float, 6, elements=st.floats(-1e3, 1e3)),
       st.floats(1e-3, 1e4))
def test_matrix_inequality_behind_the_rkf(a, b, eps):
    """(a + b)(a + b)^T <= (1 + 1/eps) a a^T + (1 + eps) b b^T for every eps > 0."""
    lhs = np.outer(a + b, a + b)
    rhs = (1 + 1 / eps) * np.outer(a, a) + (1 + eps) * np.outer(b, b)
    scale = 1.0 + np.abs(rhs).max() + np.abs(lhs).max()
    assert np.linalg.eigvalsh(rhs - lhs).min() >= -1e-9 * scale


@given(arrays(float, 36, elements=st.floats(-10, 10)), st.floats(1.0, 1e4),
       arrays(float, 18, elements=st.floats(-1, 1)))
def test_rkf_gain_minimises_the_bound(a, eps, dK):
    """tr Sigma+(K) is smallest at the RKF gain."""
    S = _spd(a, 6) * 100.0
    H = np.hstack([N, np.zeros((3, 3))])
    b = N @ np.array([300.0, -100.0, 50.0])
    BB = np.outer(b, b)

    def bound(K):
        A = np.eye(6) - K @ H
        return np.trace((1 + 1 / eps) * A @ S @ A.T + K @ (R + (1 + eps) * BB) @ K.T)

    K = rb.rkf_gain(S @ H.T, H @ S @ H.T, R, BB, eps)
    assert bound(K) <= bound(K + 1e-3 * dK.reshape(6, 3)) * (1 + 1e-12)


@given(arrays(float, 36, elements=st.floats(-10, 10)), st.floats(1.0, 1e4))
def test_rkf_update_keeps_bound_spd(a, eps):
    P = _spd(a, 6)
    b = N @ np.array([100.0, 0.0, 0.0])
    x, P1, nu = rb.rkf_update(np.zeros(6), P, np.ones(3), R, N, np.outer(b, b), eps)
    assert _is_psd(P1)
    with pytest.raises(ValueError, match="BB"):
        rb.rkf_update(np.zeros(6), P, np.ones(3), R, N, np.eye(2), eps)


def test_rkf_bias_bound():
    S = np.eye(3) * 100.0
    assert np.allclose(rb.rkf_bias_bound(np.zeros(3), S, 0.1), 0.0)  # "otherwise 0"
    m = np.array([100.0, 0.0, 0.0])
    BB = rb.rkf_bias_bound(m, S, 0.1)
    assert np.linalg.eigvalsh(BB).min() >= -1e-9
    assert abs(BB[0, 0] - (1e4 - 0.1 / 1.9 * 100.0)) < 1e-6
    with pytest.raises(ValueError, match="lam"):
        rb.rkf_bias_bound(m, S, 0.0)


@pytest.mark.parametrize("name", rb.FILTERS)
def test_run_filter_invariants(mars_sc, name):
    run = rb.run_filter(name, mars_sc, rng=1)
    assert run.x.shape == (60, 6) and run.error.shape == (60,)
    assert np.all(np.isfinite(run.error))
    for P in run.P[::10]:
        assert _is_psd(P)
    assert run.error[-10:].mean() < run.error[:3].mean() + 5e3


def test_run_filter_options_and_errors(mars_sc):
    r1 = rb.run_filter("rkf", mars_sc, rkf_bias="residual", rng=1)
    assert r1.extra["bias_bound"].shape == (60,)
    r2 = rb.run_filter("rkf", mars_sc, rkf_bias="oracle", oracle_error=[0.0, 0.0, 0.0], eps=1e12, rng=1)
    u = rb.run_filter("ukf", mars_sc, rng=1)
    np.testing.assert_allclose(r2.x, u.x, atol=1.0)  # B = 0, eps large: close to the UKF
    assert rb.run_filter("tdukf", mars_sc, td_carry_noise=True, rng=1).x.shape == (60, 6)
    assert rb.run_filter("asukf", mars_sc, rng=1).extra["bias"].shape == (60, 3)
    for kwargs, name in (({"name": "ekf"}, "name"), ({"eps": -1.0}, "eps"), ({"rkf_bias": "x"}, "rkf_bias"),
                         ({"sigma_r0": 0.0}, "sigma_r0"), ({"oracle_error": [1.0]}, "oracle_error"),
                         ({"q_b": math.nan}, "q_b")):
        with pytest.raises(ValueError, match=name):
            rb.run_filter(**({"name": "rkf", "scenario": mars_sc} | kwargs))
    with pytest.raises(ValueError, match="scenario"):
        rb.run_filter("ukf", object())


def test_rkf_prior_bound_option(mars_sc):
    """``rkf_bias="prior"``: B B^T <= d_max^2 N N^T; d_max = 0 is the eps-inflated UKF gain, and a
    bias_max missing, negative or of the wrong length is refused naming it."""
    r = rb.run_filter("rkf", mars_sc, rkf_bias="prior", bias_max=0.0, rng=1)
    o = rb.run_filter("rkf", mars_sc, rkf_bias="oracle", oracle_error=[0.0, 0.0, 0.0], rng=1)
    np.testing.assert_allclose(r.x, o.x, rtol=0, atol=1e-6)
    big = rb.run_filter("rkf", mars_sc, rkf_bias="prior", bias_max=np.full(60, 5e4), rng=1)
    assert np.trace(big.P[-1, :3, :3]) > np.trace(r.P[-1, :3, :3])
    for bad in (None, -1.0, np.ones(59)):
        with pytest.raises(ValueError, match="bias_max"):
            rb.run_filter("rkf", mars_sc, rkf_bias="prior", bias_max=bad)


def test_growing_error_scenarios():
    g = rb.simulate("earth", n_steps=10, error="growing", size=1000.0, profile="quadratic", rng=0)
    np.testing.assert_allclose(np.linalg.norm(g.dr_e, axis=1), 1000.0 * (np.arange(1, 11) / 10) ** 2)
    d = rb.simulate("earth", n_steps=3, error="growing", size=10.0, direction="de405", rng=0)
    u = ee.ephemeris_error("earth", ee.EPOCH_1997)
    np.testing.assert_allclose(d.dr_e[-1], 10.0 * u / np.linalg.norm(u))
    drift = rb.simulate("mars", n_steps=3, error="de405-drift", rng=0)
    np.testing.assert_allclose(drift.dr_e, ee.ephemeris_drift("mars", drift.t, ee.EPOCH_1997))
    for kwargs, name in (({"growth_time": 0.0}, "growth_time"), ({"direction": "sun"}, "direction"),
                         ({"profile": "cubic"}, "profile")):
        with pytest.raises(ValueError, match=name):
            rb.simulate(**({"n_steps": 2, "error": "growing", "size": 1.0} | kwargs))


def test_rkf_residual_bound_is_default_and_sees_a_growing_error():
    """The residual bound stays zero-ish without error and grows with a growing error; the oracle
    variant uses the true bias."""
    sc = rb.simulate("mars", n_steps=200, error="growing", size=2e4, rng=2)
    run = rb.run_filter("rkf", sc, rng=1)
    assert run.extra["bias_bound"][0] == 0.0  # no residual seen yet: B B^T >= 0
    assert run.extra["bias_bound"][-20:].mean() > 1e3
    oracle = rb.run_filter("rkf", sc, rkf_bias="oracle", rng=1)
    want = np.linalg.norm(sc.dr_e @ sc.n.T, axis=1)  # sqrt(tr B B^T) = |N dr_E|
    np.testing.assert_allclose(oracle.extra["bias_bound"], want, rtol=1e-9)
    ukf = rb.run_filter("ukf", sc, rng=1)
    tau = sc.t - sc.t[0] + sc.dt
    late = tau > 5e4
    assert np.sqrt(np.mean(run.error[late] ** 2)) < 0.5 * np.sqrt(np.mean(ukf.error[late] ** 2))


def test_white_tdukf_differs_from_the_exact_form(mars_sc):
    white = rb.run_filter("tdukf", mars_sc, rng=1)
    exact = rb.run_filter("tdukf", mars_sc, td_carry_noise=True, rng=1)
    assert np.abs(white.x - exact.x).max() > 1.0
    for P in white.P[::10]:
        assert _is_psd(P)


def test_a_complex_differenced_measurement_is_named_dy():
    with pytest.raises(ValueError, match="^dy must hold real numbers"):
        rb.tdukf_update(np.zeros(12), np.eye(12), np.zeros(3) + 1j, np.eye(3), np.eye(3))


def test_rkf_gain_refuses_an_indefinite_bias_bound_or_R():
    """A negative BB (a bound on B B^T) returned a gain."""
    with pytest.raises(ValueError, match="BB must be positive semi-definite, got smallest eigenvalue -1"):
        rb.rkf_gain(np.eye(6, 1), np.eye(1), np.eye(1), -np.eye(1), 0.1)
    with pytest.raises(ValueError, match="R must be positive semi-definite"):
        rb.rkf_gain(np.eye(6, 1), np.eye(1), -np.eye(1), np.zeros((1, 1)), 0.1)


@pytest.mark.parametrize("name, kw, user", [
    ("ukf", {"eps": 0.1}, "rkf"), ("ukf", {"lam": 0.5}, "rkf"), ("asukf", {"rkf_bias": "oracle"}, "rkf"),
    ("ukf", {"td_carry_noise": True}, "tdukf"), ("rkf", {"q_b": 2.0}, "asukf")])
def test_run_filter_refuses_a_setting_of_another_filter(name, kw, user):
    """run_filter("ukf", sc, eps=0.1) returned a normal run: eps was silently unused."""
    sc = rb.simulate(n_steps=5)
    key = next(iter(kw))
    with pytest.raises(ValueError, match=f"^{key} is a setting of the {user} filter, not used by {name}"):
        rb.run_filter(name, sc, **kw)
    assert rb.run_filter(user, sc, **kw).x.shape == (5, 6)  # its own filter takes it


@pytest.mark.parametrize("name, kw", [
    ("ukf", {}), ("asukf", {}), ("tdukf", {}), ("tdukf", {"td_carry_noise": True}), ("rkf", {}),
    ("rkf", {"rkf_bias": "oracle"}), ("rkf", {"rkf_bias": "prior", "bias_max": 4e3})])
def test_run_filters_steps_a_batch_as_each_run_alone(name, kw):
    """The batch over seeds (what compare_filters runs) gives every run the numbers of run_filter:
    each run's products are its own (equal here to far below the tolerance)."""
    scs = [rb.simulate("mars", n_steps=40, error="growing", size=3000.0, rng=s) for s in (0, 1, 2)]
    runs = rb.run_filters(name, scs, (10, 11, 12), **kw)
    for j, (sc, run) in enumerate(zip(scs, runs, strict=True)):
        alone = rb.run_filter(name, sc, rng=10 + j, **kw)
        np.testing.assert_allclose(run.x, alone.x, rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(run.P, alone.P, rtol=1e-9, atol=1e-12)
        for key, series in alone.extra.items():
            np.testing.assert_allclose(run.extra[key], series, rtol=1e-9, atol=1e-9)


def test_run_filters_refuses_scenarios_of_different_settings():
    a = rb.simulate("mars", n_steps=5, rng=0)
    with pytest.raises(ValueError, match="scenarios must share"):
        rb.run_filters("ukf", [a, rb.simulate("mars", n_steps=6, rng=0)])
    with pytest.raises(ValueError, match="rngs must hold one entry per scenario"):
        rb.run_filters("ukf", [a, a], rngs=(1,))
    with pytest.raises(ValueError, match="^scenarios must hold at least one Scenario"):
        rb.run_filters("ukf", [])


def test_propagating_states_together_changes_no_state():
    """The compiled RK4 holds states component by component: a state's result does not depend on
    the others propagated with it (nor on their number)."""
    from xnavlab.robust._propagation import propagate_unchecked

    x0 = ee.orbit("earth").state0 + np.random.default_rng(0).normal(size=(7, 6)) * np.r_[[1e4] * 3, [1.0] * 3]
    together = propagate_unchecked(x0.reshape(1, 7, 6), 500.0, ee.PLANETS["earth"])[0]
    for row, x in zip(together, x0, strict=True):
        np.testing.assert_allclose(row, ee.propagate(x, 500.0, "earth", substep=20.0), rtol=1e-12)


@pytest.mark.parametrize("kw, words", [
    (dict(error="constant", profile="sqrt"), r"^profile shapes a growing error only \(error='growing'\), "
                                             r"got error = 'constant'; leave profile out"),
    (dict(error="none", growth_time=10.0), r"^growth_time shapes a growing error only"),
    (dict(error="constant", profile="cubic"), r"^profile must be one of"),
    (dict(error="growing", profile=lambda s: s + 1.0), r"^profile must be a vectorised callable"),
])
def test_simulate_checks_the_profile_always_and_refuses_growth_settings_of_another_error(kw, words):
    """profile="cubic" passed unchecked with a constant error, and profile/growth_time were ignored."""
    with pytest.raises(ValueError, match=words):
        rb.simulate("mars", n_steps=3, size=10.0, **kw)


def test_run_filters_takes_a_setting_per_run():
    """A study of a setting (lam, the process noise, the initial error) runs as one batch."""
    scs = [rb.simulate("mars", n_steps=30, error="growing", size=2000.0, rng=s) for s in (0, 1)]
    runs = rb.run_filters("rkf", scs, (3, 4), lam=(0.02, 0.5), q_v=(1e-4, 1e-3), sigma_r0=(1e3, 1e4))
    alone = rb.run_filter("rkf", scs[1], rng=4, lam=0.5, q_v=1e-3, sigma_r0=1e4)
    np.testing.assert_allclose(runs[1].x, alone.x, rtol=1e-9, atol=1e-9)
    with pytest.raises(ValueError, match=r"^lam must be one value or one per scenario \(2\), got 3"):
        rb.run_filters("rkf", scs, (3, 4), lam=(0.1, 0.2, 0.3))
    with pytest.raises(ValueError, match="q_b"):
        rb.run_filters("asukf", scs, (3, 4), q_b=(1.0, -1.0))


@pytest.mark.parametrize(("kw", "words"), [
    ({"size": 100.0}, r"^size shapes an injected error \(error='constant', 'slow' or 'growing'\), "
                      r"got error = 'de405'; leave size out$"),
    ({"direction": [1.0, 0.0, 0.0], "error": "none"}, r"^direction shapes an injected error"),
])
def test_simulate_refuses_a_size_or_direction_the_real_error_would_not_use(kw, words):
    """Review 35e: compare_filters(size=100) with the default error='de405' ran the real error
    and dropped the 100 m without a word."""
    with pytest.raises(ValueError, match=words):
        rb.simulate("mars", n_steps=5, rng=1, **kw)


@pytest.mark.parametrize(("kw", "words"), [
    ({"td_carry_noise": "yes"}, r"^td_carry_noise must be True or False, got 'yes'$"),
    ({"bias_max": math.nan}, r"^bias_max goes with rkf_bias='prior', got rkf_bias='residual'"),
    ({"oracle_error": [1.0, 2.0, 3.0]}, r"^oracle_error goes with rkf_bias='oracle'"),
])
def test_run_filter_refuses_a_setting_its_bias_rule_would_not_use(kw, words):
    """Review 35e: td_carry_noise='yes' ran as True; bias_max (even NaN) and oracle_error were
    dropped in silence unless their bias rule was chosen."""
    sc = rb.simulate("mars", n_steps=5, rng=1)
    name = "tdukf" if "td_carry_noise" in kw else "rkf"
    with pytest.raises(ValueError, match=words):
        rb.run_filter(name, sc, **kw)


def test_tdukf_update_takes_carry_noise_as_a_bool_only():
    """Review 35e: carry_noise="no" ran as True (a non-empty string)."""
    with pytest.raises(ValueError, match=r"^carry_noise must be True or False, got 'no'$"):
        rb.filters.tdukf_update(np.zeros(15), np.eye(15), np.zeros(3), np.eye(3), np.eye(3), "no")


@pytest.mark.parametrize("kw, match", [
    (dict(sigma_r0=5e-324), r"^sigma_r0 must be a real number in \[0.001, 1e\+08\]"),
    (dict(sigma_v0=1e-300), r"^sigma_v0 must be a real number in \[1e-06, 100000\]")])
def test_issue35_initial_sigmas_whose_squares_underflow_are_refused_by_name(kw, match):
    # Review 35f finding 35: the error named P, not sigma_r0.
    with pytest.raises(ValueError, match=match):
        rb.run_filter("ukf", rb.simulate(n_steps=5, rng=0), rng=0, **kw)


def test_issue35_a_millimetre_initial_sigma_runs():
    run = rb.run_filter("ukf", rb.simulate(n_steps=5, rng=0), sigma_r0=1e-3, sigma_v0=1e-6, rng=0)
    assert np.all(np.isfinite(run.x))


def test_step_functions_name_the_argument_whose_shape_disagrees():
    """Each argument is checked on its own, then against the earlier ones (issue 35)."""
    eye = np.eye(3)
    with pytest.raises(ValueError, match=r"^P must have shape \(n, n\), got shape \(\)"):
        rb.ukf_update(np.zeros(6), -0.0, np.ones(3), eye, eye)
    with pytest.raises(ValueError, match=r"^R must have shape \(n, n\), got shape \(\)"):
        rb.rkf_update(np.zeros(6), np.eye(6), np.ones(3), -0.0, eye, np.zeros((3, 3)), 1e3)
    with pytest.raises(ValueError, match=r"^x must have 6 \+ 3 entries"):
        rb.asukf_update([1.0], np.eye(9), np.ones(3), eye, eye)
    with pytest.raises(ValueError, match=r"^n must have shape \(3, 3\) \(k = size of dy and R\)"):
        rb.tdukf_update(np.zeros(12), np.eye(12), np.zeros(3), eye, np.eye(3)[:2])
    with pytest.raises(ValueError, match=r"^P must have shape \(6, 6\) \(m = size of x\)"):
        rb.predict(np.zeros(6), -0.0, 500.0, "mars", np.eye(6))
    with pytest.raises(ValueError, match=r"^Q must have shape \(6, 6\)"):
        rb.tdukf_predict(np.zeros(6), np.eye(6), 500.0, "mars", -0.0)
    with pytest.raises(ValueError, match=r"^S must have shape \(n, n\), got shape \(\)"):
        rb.rkf_bias_bound(np.zeros(2), -0.0, 0.1)
    with pytest.raises(ValueError, match=r"^m must have shape \(2,\) \(k = rows of S\)"):
        rb.rkf_bias_bound([1.0], np.eye(2), 0.1)
    for Pxz in (-0.0, [], np.zeros((2, 0))):
        with pytest.raises(ValueError, match=r"^Pxz must be a non-empty 2-D array \(n, k\), got shape"):
            rb.rkf_gain(Pxz, np.eye(1), np.eye(1), np.zeros((1, 1)), 10.0)
    with pytest.raises(ValueError, match=r"^Pzz must have shape \(1, 1\) \(k = columns of Pxz\)"):
        rb.rkf_gain(np.eye(1), [], np.eye(1), np.zeros((1, 1)), 10.0)


def test_run_filters_names_scenarios_and_rngs():
    a = rb.simulate("mars", n_steps=3, rng=0)
    for bad in (1.0, True, np.array(1.0)):
        with pytest.raises(ValueError, match="^scenarios must be a list of Scenarios"):
            rb.run_filters("ukf", bad)
        with pytest.raises(ValueError, match="^rngs must be a list of Generators or seeds"):
            rb.run_filters("ukf", [a], bad)
    with pytest.raises(ValueError, match=r"^scenarios\[1\] must be a Scenario"):
        rb.run_filters("ukf", [a, 1.0])
    with pytest.raises(ValueError, match=r"^rngs\[0\] must be a numpy Generator"):
        rb.run_filters("ukf", [a], [1.5])
    with pytest.raises(ValueError, match=r"^rng must be a numpy Generator"):
        rb.run_filter("ukf", a, rng=1.5)
    with pytest.raises(ValueError, match=r"^scenario must be a Scenario from simulate\(\), got bool True"):
        rb.run_filter("ukf", True)


def test_step_functions_check_covariances_directions_and_position():
    """Review 35i: P, Q, R and BB as covariances, n as unit directions, x outside the planet."""
    eye3, o = np.eye(3), ee.orbit("earth")
    bad = np.eye(6)
    bad[0, 0] = -1.0
    skew = np.eye(6)
    skew[0, 1] = 0.5
    with pytest.raises(ValueError, match=r"^P must be positive semi-definite"):
        rb.ukf_update(np.zeros(6), bad, np.ones(3), eye3, eye3)
    with pytest.raises(ValueError, match=r"^P must be symmetric"):
        rb.ukf_update(np.zeros(6), skew, np.ones(3), eye3, eye3)
    with pytest.raises(ValueError, match=r"^P must be positive semi-definite"):
        rb.asukf_update(np.zeros(9), np.diag([-2.0] + [1.0] * 8), np.ones(3), eye3, eye3)
    with pytest.raises(ValueError, match=r"^R must be positive definite"):
        rb.ukf_update(np.zeros(6), np.eye(6), np.ones(3), np.zeros((3, 3)), eye3)
    with pytest.raises(ValueError, match=r"^n must hold unit directions, got a zero row n\[0\]"):
        rb.ukf_update(np.zeros(6), np.eye(6), np.ones(3), eye3, np.zeros((3, 3)))
    with pytest.raises(ValueError, match=r"^n must hold unit directions \(norm 1 to 1e-06\)"):
        rb.ukf_update(np.zeros(6), np.eye(6), np.ones(3), eye3, 5 * eye3)
    with pytest.raises(ValueError, match=r"^BB must be positive semi-definite"):
        rb.rkf_update(np.zeros(6), np.eye(6), np.ones(3), eye3, eye3, -eye3, 1000.0)
    with pytest.raises(ValueError, match=r"^P must be positive definite"):
        rb.predict(o.state0, bad, 500.0, "earth", np.zeros((6, 6)))
    with pytest.raises(ValueError, match=r"^P must be symmetric"):
        rb.predict(o.state0, skew, 500.0, "earth", np.zeros((6, 6)))
    with pytest.raises(ValueError, match=r"^Q must be positive semi-definite"):
        rb.predict(o.state0, np.eye(6), 500.0, "earth", np.diag([-1.0] + [0.0] * 5))
    for x, P, f in ((np.zeros(6), np.eye(6), rb.predict), (np.zeros(12), np.eye(12), rb.tdukf_predict),
                    (o.state0[::-1].copy(), np.eye(6), rb.predict)):
        with pytest.raises(ValueError, match=r"^x\[:3\] must lie between the radius of earth"):
            f(x, P, 500.0, "earth", np.zeros((6, 6)))


def test_simulate_passes_no_growth_setting_to_another_error():
    """simulate's default growth_time is not passed on for a constant error (injected_error refuses it)."""
    sc = rb.simulate("mars", n_steps=3, error="constant", size=100.0, rng=1)
    np.testing.assert_allclose(np.linalg.norm(sc.dr_e, axis=1), 100.0)


def test_one_generator_listed_twice_is_drawn_from_in_order():
    """Review 35i asked: the same Generator for two runs is drawn from run after run, as
    run_filter called twice with it (documented, not refused)."""
    scs = [rb.simulate("mars", n_steps=10, rng=s) for s in (0, 1)]
    g = np.random.default_rng(1)
    runs = rb.run_filters("rkf", scs, [g, g])
    g = np.random.default_rng(1)
    one_by_one = [rb.run_filter("rkf", sc, rng=g) for sc in scs]
    for a, b in zip(runs, one_by_one, strict=True):
        np.testing.assert_allclose(a.x, b.x, rtol=1e-12, atol=1e-6)


@pytest.mark.parametrize("n_dyn", [None, "3", 2.5, -1, True, 7])
def test_review_35k_1_7_2_6_predict_n_dyn(n_dyn):
    """Review 35k (1) 7, (2) 6: n_dyn of None or text was a TypeError, 2.5 a slice TypeError,
    -1 and True numpy's reshape message."""
    o = ee.orbit("earth")
    with pytest.raises(ValueError, match=r"^n_dyn must be 6 \(the dynamics propagate"):
        rb.filters.predict(o.state0, np.eye(6), 500.0, "earth", np.zeros((6, 6)), n_dyn=n_dyn)


def test_review_35k_1_10_5_5_simulate_elements_t0():
    """Review 35k (1) 10, (5) 5: simulate's elements=1.0 was a TypeError, t0=1e300 gave epochs
    that were all 1e300; a run past the ephemerides was refused as the ephemeris' ``t``."""
    with pytest.raises(ValueError, match=r"^elements must be"):
        rb.filters.simulate("mars", n_steps=5, elements=1.0)
    with pytest.raises(ValueError, match=r"^t0 must be an epoch in \["):
        rb.filters.simulate("mars", n_steps=5, error="constant", size=100.0, rng=1, t0=1e300)
    with pytest.raises(ValueError, match=r"^n_steps must end the run within the ephemerides: t0 \+ "
                                         r"n_steps \* dt"):
        rb.filters.simulate("earth", n_steps=10**6, dt=1e5)
