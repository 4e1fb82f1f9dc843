"""EKF (Joseph form) and UKF step functions: linear-Gaussian identities and invariants."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from xnavlab.core import filters


def _spd(rng, n, scale=1.0):
    A = rng.standard_normal((n, n))
    return scale * (A @ A.T + n * np.eye(n))


def _kf(x, P, z, H, R):
    """Textbook Kalman update (the independent reference)."""
    S = H @ P @ H.T + R
    K = P @ H.T @ np.linalg.inv(S)
    return x + K @ (z - H @ x), (np.eye(len(x)) - K @ H) @ P


@given(st.integers(0, 10_000), st.integers(1, 6), st.integers(1, 4))
def test_ekf_update_equals_kalman_for_linear_models(seed, n, m):
    rng = np.random.default_rng(seed)
    x, P = rng.standard_normal(n), _spd(rng, n)
    H, R = rng.standard_normal((m, n)), _spd(rng, m, 0.1)
    z = rng.standard_normal(m)
    up = filters.ekf_update(x, P, z, lambda s: H @ s, H, R)
    x_ref, P_ref = _kf(x, P, z, H, R)
    np.testing.assert_allclose(up.x, x_ref, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(up.P, P_ref, rtol=1e-7, atol=1e-9)
    assert np.array_equal(up.P, up.P.T)


@given(st.integers(0, 10_000))
def test_joseph_form_stays_positive_definite_for_any_gain(seed):
    rng = np.random.default_rng(seed)
    P, R = _spd(rng, 4), _spd(rng, 2)
    K, H = rng.standard_normal((4, 2)) * 10, rng.standard_normal((2, 4))
    Pj = filters.joseph(P, K, H, R)
    assert np.array_equal(Pj, Pj.T)
    eig = np.linalg.eigvalsh(Pj)
    assert eig.min() > 1e-12 * eig.max()  # PD far above rounding (never the sign of ~0)


def test_skipped_update_is_time_update_only():
    x, P = np.ones(2), np.eye(2)
    x1, P1 = filters.ekf_predict(x, P, lambda s: 2 * s, 2 * np.eye(2), 0.5 * np.eye(2))
    up = filters.ekf_update(x1, P1, None, None, None, None)
    assert np.array_equal(up.x, x1) and np.array_equal(up.P, P1)
    assert up.innovation is None and np.isnan(up.nis)
    np.testing.assert_allclose(P1, 4.5 * np.eye(2))


def test_ekf_predict_symmetrises():
    P = np.array([[2.0, 1.0], [1.0 + 1e-12, 2.0]])
    _, P1 = filters.ekf_predict(np.zeros(2), P, np.zeros(2), np.eye(2), np.zeros((2, 2)))
    assert np.array_equal(P1, P1.T)


@given(st.integers(0, 10_000), st.integers(1, 5))
def test_ukf_is_exact_for_linear_models(seed, n):
    rng = np.random.default_rng(seed)
    F, Q = rng.standard_normal((n, n)), _spd(rng, n, 0.01)
    H, R = rng.standard_normal((2, n)), _spd(rng, 2, 0.1)
    x, P = rng.standard_normal(n), _spd(rng, n)
    xe, Pe = filters.ekf_predict(x, P, lambda s: F @ s, F, Q)
    xu, Pu = filters.ukf_predict(x, P, lambda s: F @ s, Q)
    np.testing.assert_allclose(xu, xe, atol=1e-9)
    np.testing.assert_allclose(Pu, Pe, rtol=1e-8, atol=1e-9)
    z = rng.standard_normal(2)
    ue = filters.ekf_update(xe, Pe, z, lambda s: H @ s, H, R)
    uu = filters.ukf_update(xu, Pu, z, lambda s: H @ s, R)
    np.testing.assert_allclose(uu.x, ue.x, rtol=1e-7, atol=1e-8)
    np.testing.assert_allclose(uu.P, ue.P, rtol=1e-6, atol=1e-8)
    assert uu.nis == pytest.approx(ue.nis, rel=1e-7)


@pytest.mark.parametrize("alpha,kappa", [(1.0, 0.0), (1e-3, 0.0), (0.5, 1.0)])
def test_unscented_weights_and_linear_transform(alpha, kappa):
    n = 3
    Wm, Wc, lam = filters.ukf_weights(n, alpha, 2.0, kappa)
    assert Wm.sum() == pytest.approx(1.0)
    rng = np.random.default_rng(1)
    x, P, A = rng.standard_normal(n) * 1e6, _spd(rng, n), rng.standard_normal((2, n))
    X = filters.sigma_points(x, P, lam)
    m, S = filters.unscented_transform(X @ A.T, Wm, Wc)
    np.testing.assert_allclose(m, A @ x, rtol=1e-9)
    np.testing.assert_allclose(S, A @ P @ A.T, rtol=1e-5, atol=1e-6)


def test_ukf_weights_reject_bad_parameters():
    with pytest.raises(ValueError, match="alpha"):
        filters.ukf_weights(3, alpha=0.0)
    with pytest.raises(ValueError, match="kappa"):
        filters.ukf_weights(3, kappa=-3.0)


def test_nees_nis_and_chi2_bounds():
    assert filters.nees([1.0, 2.0], np.diag([1.0, 4.0])) == pytest.approx(2.0)
    e = np.ones((5, 2))
    P = np.broadcast_to(np.eye(2), (5, 2, 2))
    np.testing.assert_allclose(filters.nees(e, P), 2.0)
    assert filters.nis([3.0], [[9.0]]) == pytest.approx(1.0)
    lo, hi = filters.chi2_bounds(3, 1000)
    assert lo < 3 < hi and hi - lo < 0.31
    with pytest.raises(ValueError, match="p must"):
        filters.chi2_bounds(3, 10, p=1.5)


def test_classes_hold_state_and_skip():
    kf = filters.EKF([0.0, 0.0], np.eye(2))
    kf.predict(lambda s: s, np.eye(2), np.eye(2) * 0.1)
    kf.update(None, None, None, None)
    assert np.isnan(kf.last.nis)
    kf.update([1.0], lambda s: s[:1], np.array([[1.0, 0.0]]), [[1.0]])
    assert 0 < kf.x[0] < 1
    uk = filters.UKF([0.0, 0.0], np.eye(2))
    uk.predict(lambda s: s, np.eye(2) * 0.1).update([1.0], lambda s: s[:1], [[1.0]])
    np.testing.assert_allclose(uk.x, kf.x, rtol=1e-9)
    with pytest.raises(ValueError, match="P0 must be a square matrix of shape"):
        filters.EKF([0.0], np.eye(2))
    with pytest.raises(ValueError, match="x0"):
        filters.EKF([np.nan], np.eye(1))


# ------------------------------------------------------------------ guarded steps

_GOOD = dict(x=np.zeros(2), P=np.eye(2), z=np.array([1.0]), H=np.array([[1.0, 0.0]]),
             R=np.eye(1))


def _ekf_update(**kw):
    a = {**_GOOD, **kw}
    H = a["H"]
    return filters.ekf_update(a["x"], a["P"], a["z"], lambda s: np.atleast_2d(H) @ s, H, a["R"])


@pytest.mark.parametrize("bad, name", [
    (dict(z=np.array([np.nan])), "z must contain only finite"),
    (dict(z=np.array([np.inf])), "z must contain only finite"),
    (dict(P=-np.eye(2)), "P must be positive semi-definite"),
    (dict(P=np.array([[1.0, 0.5], [0.0, 1.0]])), "P must be symmetric"),
    (dict(P=np.eye(3)), r"P must be a square matrix of shape \(2, 2\)"),
    (dict(x=np.zeros((2, 1))), r"x must be a 1-D array"),
    (dict(H=np.array([[1.0, 0.0, 0.0]])), r"h\(x\) must have shape|H must have shape"),
    (dict(R=np.eye(2)), r"R must be a square matrix of shape \(1, 1\)"),
    (dict(R=np.zeros((1, 1))), "R must be positive definite"),
])
def test_ekf_update_refuses_bad_input_naming_it(bad, name):
    with pytest.raises(ValueError, match=name):
        _ekf_update(**bad)


def test_ukf_update_refuses_nan_and_negative_covariance():
    h = lambda s: s[:1]  # noqa: E731
    with pytest.raises(ValueError, match="z must contain only finite"):
        filters.ukf_update(np.zeros(2), np.eye(2), [np.nan], h, np.eye(1))
    with pytest.raises(ValueError, match="P must be positive semi-definite"):
        filters.ukf_update(np.zeros(2), -np.eye(2), [1.0], h, np.eye(1))
    with pytest.raises(ValueError, match=r"h\(x\) of the sigma points must have shape"):
        filters.ukf_update(np.zeros(2), np.eye(2), [1.0, 2.0], h, np.eye(2))
    with pytest.raises(ValueError, match="Q must be positive semi-definite"):
        filters.ukf_predict(np.zeros(2), np.eye(2), lambda s: s, -np.eye(2))


def test_predict_refuses_model_outputs_of_the_wrong_shape_or_nan():
    with pytest.raises(ValueError, match=r"f\(x\) must contain only finite"):
        filters.ekf_predict(np.zeros(2), np.eye(2), lambda s: s * np.nan, np.eye(2), np.eye(2))
    with pytest.raises(ValueError, match=r"F must have shape \(2, 2\)"):
        filters.ekf_predict(np.zeros(2), np.eye(2), lambda s: s, np.eye(3), np.eye(2))


def test_classes_refuse_a_column_state():
    with pytest.raises(ValueError, match="x0 must be a 1-D array"):
        filters.EKF(np.zeros((2, 1)), np.eye(2))
    with pytest.raises(ValueError, match="x0 must be a 1-D array"):
        filters.UKF(np.zeros((2, 1)), np.eye(2))


def test_unchecked_steps_equal_checked_steps():
    rng = np.random.default_rng(3)
    x, P, H, R = rng.standard_normal(3), _spd(rng, 3), rng.standard_normal((2, 3)), _spd(rng, 2)
    z = rng.standard_normal(2)
    a = filters.ekf_update(x, P, z, lambda s: H @ s, H, R)
    b = filters.ekf_update(x, P, z, lambda s: H @ s, H, R, check=False)
    np.testing.assert_array_equal(a.x, b.x)
    np.testing.assert_array_equal(a.P, b.P)


@given(st.integers(0, 10_000), st.integers(1, 5), st.integers(1, 3),
       st.sampled_from(["nan_z", "neg_P", "asym_P", "nan_R", "shape_R"]))
def test_no_nan_and_no_negative_nis_leave_a_step(seed, n, m, corruption):
    """Valid inputs give finite outputs and NIS >= 0; each corrupted input is refused."""
    rng = np.random.default_rng(seed)
    x, P = rng.standard_normal(n), _spd(rng, n)
    H, R, z = rng.standard_normal((m, n)), _spd(rng, m, 0.1), rng.standard_normal(m)
    for step in (lambda *a: filters.ekf_update(a[0], a[1], a[2], lambda s: H @ s, H, a[3]),
                 lambda *a: filters.ukf_update(a[0], a[1], a[2], lambda s: H @ s, a[3])):
        up = step(x, P, z, R)
        assert np.all(np.isfinite(up.x)) and np.all(np.isfinite(up.P)) and up.nis >= 0.0
        bad = {"nan_z": (x, P, np.where(np.arange(m) == 0, np.nan, z), R),
               "neg_P": (x, -P, z, R),
               "asym_P": (x, P + np.triu(np.ones((n, n)), 1) * (1.0 if n > 1 else 0.0) - (
                   0.0 if n > 1 else 2.0 * P), z, R),
               "nan_R": (x, P, z, R * np.nan),
               "shape_R": (x, P, z, np.eye(m + 1))}[corruption]
        with pytest.raises(ValueError):
            step(*bad)


# ---- issue 35: complex numbers and bad covariances are refused by name ------------------------

def test_a_complex_measurement_is_refused_not_cut_to_its_real_part():
    with pytest.raises(ValueError, match="^z must hold real numbers, got complex values"):
        filters.ekf_update(np.zeros(2), np.eye(2), np.array([1.0 + 1.0j]), lambda x: x[:1],
                           np.array([[1.0, 0.0]]), np.eye(1))
    with pytest.raises(ValueError, match="^F must hold real numbers"):
        filters.ekf_predict(np.zeros(1), np.eye(1), np.zeros(1), np.array([[1.0 + 0j]]), np.eye(1))


@pytest.mark.parametrize(("stat", "matrix", "words"), [
    (filters.nis, [[1.0, 2.0], [2.0, 1.0]], r"^S must be positive definite, but it is indefinite"),
    (filters.nees, np.zeros((2, 2)), r"^P must be positive definite, but it is singular"),
    (filters.nees, [[1.0, 1.0], [1.0, 1.0]], r"^P must be positive definite, but it is singular"),
    (filters.nis, [[1.0, 0.3], [0.0, 1.0]], r"^S must be symmetric"),
])
def test_a_statistic_refuses_an_indefinite_or_singular_covariance(stat, matrix, words):
    # nis was -2.0 for the indefinite one, nees a raw LinAlgError for the singular one
    with pytest.raises(ValueError, match=words):
        stat(np.ones(2), np.asarray(matrix))


def test_nees_over_a_stack_names_the_bad_epoch_and_matching_axes():
    P = np.stack([np.eye(2)] * 4)
    assert filters.nees(np.ones((4, 2)), P).tolist() == [2.0] * 4
    P[3, 1, 1] = -1.0
    with pytest.raises(ValueError, match=r"^P\[3\] must be positive definite"):
        filters.nees(np.ones((4, 2)), P)
    with pytest.raises(ValueError, match="do not match"):
        filters.nees(np.ones((3, 2)), np.stack([np.eye(2)] * 4))


@pytest.mark.parametrize(("call", "name"), [
    (lambda b: filters.symmetrize(b * np.eye(2)), "P"),
    (lambda b: filters.joseph(np.eye(1), b * np.ones((1, 1)), np.eye(1), np.eye(1)), "K"),
    (lambda b: filters.sigma_points(b * np.ones(1), np.eye(1), 0.0), "x"),
    (lambda b: filters.sigma_points(np.zeros(1), np.eye(1), b), "lam"),
    (lambda b: filters.unscented_transform(b * np.ones((3, 1)), np.ones(3) / 3, np.ones(3) / 3), "Y"),
    (lambda b: filters.ukf_weights(2, alpha=b), "alpha"),
])
@pytest.mark.parametrize("bad", [complex(1, 1), np.nan])
def test_the_step_helpers_refuse_complex_and_nan_by_name(call, name, bad):
    with pytest.raises(ValueError, match=rf"^{name} must"):
        call(bad)


def test_a_ukf_step_on_a_singular_covariance_names_it():
    with pytest.raises(ValueError, match=r"^P must be positive definite, but it is singular"):
        filters.sigma_points(np.zeros(2), np.diag([1.0, 0.0]), 0.0)


I2 = np.eye(2)


@pytest.mark.parametrize("call, match", [
    (lambda: filters.joseph(I2, 0.5 * I2, I2, np.diag([1.0, -1.0])), r"^R must be positive semi-definite"),
    (lambda: filters.joseph(-I2, 0.5 * I2, I2, I2), r"^P must be positive semi-definite"),
    (lambda: filters.ekf_update(np.zeros(2), I2, np.zeros(2), np.zeros(2), I2, I2,
                                residual=lambda a, b: np.array([np.nan, 0.0])),
     r"^residual\(z, h\(x\)\) must contain only finite numbers"),
    (lambda: filters.ekf_update(np.zeros(2), I2, np.zeros(2), np.zeros(2), I2, I2,
                                residual=lambda a, b: np.zeros(3)),
     r"^residual\(z, h\(x\)\) must have shape \(2,\), got shape \(3,\)"),
    (lambda: filters.ekf_update(np.zeros(2), I2, np.zeros(3), np.zeros(2), I2, I2),
     r"^z must have length 2 \(the rows of H\), got length 3"),
    (lambda: filters.ekf_update(np.zeros(2), I2, np.zeros(3), np.zeros(2), I2, np.eye(3)),
     r"^H must have shape \(3, 2\)"),   # z and R agree: H is the odd one out
    (lambda: filters.ekf_update(np.zeros(2), I2, np.zeros(0), np.zeros(2), I2, I2),
     r"^z must hold at least one measurement component"),
    (lambda: filters.ukf_update(np.zeros(2), I2, np.zeros(3), lambda s: s, I2),
     r"^z must have length 2 \(the length of h\(x\)\), got length 3"),
    (lambda: filters.ukf_update(np.zeros(2), I2, np.zeros(2), lambda s: s, np.eye(3)),
     r"^R must be a square matrix of shape \(2, 2\)"),
    (lambda: filters.nees(np.zeros(0), np.zeros((0, 0))), r"^err must hold at least one component"),
    (lambda: filters.nis(np.zeros((5, 0)), np.zeros((5, 0, 0))), r"^nu must hold at least one"),
    (lambda: filters.ekf_predict(np.zeros(0), np.zeros((0, 0)), np.zeros(0), np.zeros((0, 0)),
                                 np.zeros((0, 0))), r"^x must hold at least one state component"),
    (lambda: filters.EKF(np.zeros(0), np.zeros((0, 0))), r"^x0 must hold at least one state"),
    (lambda: filters.unscented_transform(np.zeros((0, 2)), np.zeros(0), np.zeros(0)),
     r"^Y must have shape \(2n\+1, m\) with m >= 1, got shape \(0, 2\)"),
    (lambda: filters.unscented_transform(np.zeros((3, 0)), np.ones(3), np.ones(3)), r"^Y must have"),
])
def test_a_bad_matrix_or_length_is_named_for_what_it_is(call, match):
    """Review 35 D.14, D.15, D.17, E.24, F.27: an indefinite R made a singular covariance; a
    residual's NaN became the state; a wrong z blamed H (ekf) or R (ukf); empty states passed."""
    with pytest.raises(ValueError, match=match):
        call()


def test_the_unchecked_path_is_unchanged():
    up = filters.ekf_update(np.zeros(2), I2, np.ones(2), np.zeros(2), I2, I2, check=False)
    assert np.array_equal(up.x, filters.ekf_update(np.zeros(2), I2, np.ones(2), np.zeros(2), I2,
                                                   I2).x)


@pytest.mark.parametrize("call", [
    lambda c: filters.ekf_predict(np.zeros(2), np.eye(2), np.zeros(2), np.eye(2), np.eye(2), check=c),
    lambda c: filters.ekf_update(np.zeros(2), np.eye(2), np.ones(2), np.zeros(2), np.eye(2),
                                 np.eye(2), check=c),
    lambda c: filters.ukf_predict(np.zeros(2), np.eye(2), lambda s: s, np.eye(2), check=c),
    lambda c: filters.ukf_update(np.zeros(2), np.eye(2), np.ones(2), lambda s: s, np.eye(2),
                                 check=c),
])
@pytest.mark.parametrize("bad", ["no", 0])
def test_check_must_be_a_bool(call, bad):  # review 35d D29: check=0 skipped the checks
    with pytest.raises(ValueError, match="check must be True or False"):
        call(bad)


def test_unscented_transform_refuses_weights_and_noise_that_make_no_mean_or_covariance():
    # review 35d D28: noise = -I gave a covariance of -I; Wm summing to 5 a wrong mean
    Y = np.ones((5, 2))
    Wm, Wc, _ = filters.ukf_weights(2)
    with pytest.raises(ValueError, match="Wm must sum to 1 .* got sum 5"):
        filters.unscented_transform(Y, np.ones(5), Wc)
    with pytest.raises(ValueError, match="noise must be positive semi-definite"):
        filters.unscented_transform(Y, Wm, Wc, noise=-np.eye(2))
    mean, cov = filters.unscented_transform(Y, Wm, Wc, noise=np.eye(2))
    assert mean.tolist() == [1.0, 1.0] and cov.tolist() == [[1.0, 0.0], [0.0, 1.0]]


@pytest.mark.parametrize(("call", "words"), [
    (lambda: filters.judge_series([-1.0, 1.0], 1.0, 2.0),
     "values[0] must be a NEES or NIS value in [0, inf), got -1"),  # review 35d D29: judged
    (lambda: filters.judge_series([1.5, 1.5, -0.5], 1.0, 2.0),
     "values[2] must be a NEES or NIS value in [0, inf), got -0.5"),
    (lambda: filters.consistency_verdict(-1.0, 1.0, 2.0), "value must be a real number in [0, inf)"),
    (lambda: filters.consistency_verdict(1.0, -1.0, 2.0), "lo must be a real number in [0, inf)"),
    (lambda: filters.judge_series([1.0], -2.0, -1.0), "lo must be a real number in [0, inf)"),
])
def test_a_negative_nees_or_nis_or_band_is_refused(call, words):
    with pytest.raises(ValueError) as exc:
        call()
    assert str(exc.value).startswith(words), str(exc.value)


@given(st.lists(st.floats(-10.0, 10.0), min_size=1, max_size=20))
def test_judge_series_judges_exactly_the_series_of_values_at_or_above_zero(values):
    if min(values) >= 0.0:
        out = filters.judge_series(values, 1.0, 2.0)
        assert out["inside"] + out["below"] + out["above"] == pytest.approx(1.0)
    else:
        first = next(i for i, v in enumerate(values) if v < 0)
        with pytest.raises(ValueError, match=rf"^values\[{first}\] must be a NEES or NIS value"):
            filters.judge_series(values, 1.0, 2.0)


def test_sigma_points_refuse_a_spread_that_overflows():
    """Review 35e: lam=1e308 gave inf sigma points with an overflow warning."""
    with pytest.raises(ValueError, match=r"^lam must be a real number in \(-1, 1e\+06\], got 1e\+308$"):
        filters.sigma_points(np.zeros(1), np.eye(1) * 4.0, 1e308)


@pytest.mark.parametrize(("kw", "words"), [
    ({"alpha": 1e-200}, r"^alpha and kappa must keep n \+ lambda = alpha\^2 \(n \+ kappa\) >= 1e-150"),
    ({"alpha": 1e-80}, r"^alpha and kappa must keep n \+ lambda"),
    ({"kappa": 1e308}, r"^kappa must be a real number in \(-3, 100000\], got 1e\+308$"),
    ({"beta": 1e308}, r"^beta must be a real number in \[-1000, 1000\], got 1e\+308$"),
])
def test_ukf_weights_refuse_settings_whose_weights_are_not_finite(kw, words):
    """Review 35e: alpha=1e-200 was a ZeroDivisionError; kappa=1e308 reached sigma_points and
    was refused there as lam, a parameter never given; beta=1e308 gave an inf weight."""
    with pytest.raises(ValueError, match=words):
        filters.ukf_weights(3, **kw)


def test_chi2_bounds_refuses_more_runs_than_it_can_pool():
    with pytest.raises(ValueError, match=r"n_runs must be a real number in \[1, 1e\+12\]"):
        filters.chi2_bounds(3, 1e308)


@pytest.mark.parametrize("R, match", [
    ([[5e-324]], r"^R must have variances \(diagonal\) in \[1e-100, 1e\+100\]"),
    ([[1e308]], r"^R must have variances \(diagonal\) in \[1e-100, 1e\+100\]")])
@pytest.mark.parametrize("update", ["ekf", "ukf"])
def test_issue35_update_refuses_variances_outside_1e100(R, match, update):
    # Review 35f findings 19 and 20: R = 5e-324 gave a NaN state, 1e308 an overflow warning.
    H = np.array([[1.0, 0.0]])
    with pytest.raises(ValueError, match=match):
        if update == "ekf":
            filters.ekf_update(np.zeros(2), np.eye(2), np.array([1.0]), lambda x: H @ x, H, R)
        else:
            filters.ukf_update(np.zeros(2), np.eye(2), np.array([1.0]), lambda x: H @ x, R)


@pytest.mark.parametrize("err, P, match", [
    (np.ones(2), 1e-320 * np.eye(2), r"^P must have variances \(diagonal\) in \[1e-100"),
    (1e200 * np.ones(2), np.eye(2), r"^err must have entries in \[-1e\+100, 1e\+100\]")])
def test_issue35_nees_refuses_scales_that_leave_the_float_range(err, P, match):
    # Review 35f finding 21: nan, and an overflow warning.
    with pytest.raises(ValueError, match=match):
        filters.nees(err, P)


def test_issue35_jacobians_beyond_1e100_are_refused_by_name():
    # Review 35f finding 20's class: H P H^T and F P F^T overflowed.
    with pytest.raises(ValueError, match=r"^H must have entries in \[-1e\+100, 1e\+100\]"):
        filters.ekf_update(np.zeros(2), np.eye(2), [1.0], [0.0], [[1e200, 0.0]], [[1.0]])
    with pytest.raises(ValueError, match=r"^F must have entries in \[-1e\+100, 1e\+100\]"):
        filters.ekf_predict(np.zeros(2), np.eye(2), np.zeros(2), 1e200 * np.eye(2), np.eye(2))


# ------------------------------------------------------------------ edge inputs (issue 35)

@pytest.mark.parametrize(("call", "match"), [
    # a skipped update (z=None) checks the model it is given, naming it
    (lambda: filters.ekf_update(np.zeros(1), np.eye(1), None, True, np.eye(1), np.eye(1)),
     r"^h\(x\) must"),
    (lambda: filters.ekf_update(np.zeros(1), np.eye(1), None, np.zeros(1), [], np.eye(1)),
     r"^H must have shape"),
    (lambda: filters.ekf_update(np.zeros(1), np.eye(1), None, np.zeros(1), np.eye(1), True),
     r"^R must"),
    (lambda: filters.ukf_update(np.zeros(1), np.eye(1), None, 1.0, np.eye(1)), r"^h must be a function"),
    (lambda: filters.ukf_update(np.zeros(1), np.eye(1), [1.0], [], np.eye(1)), r"^h must be a function"),
    (lambda: filters.ukf_predict(np.zeros(1), np.eye(1), True, np.eye(1)), r"^f must be a function"),
    # a well-formed x of the wrong length is named when P (and Q, H) agree with each other
    (lambda: filters.ekf_predict([1.0], np.eye(2), np.ones(2), np.eye(2), np.eye(2)),
     r"^x must have length 2 \(the size of P\), got length 1"),
    (lambda: filters.ukf_predict([1.0], np.eye(2), lambda s: s, np.eye(2)), r"^x must have length 2"),
    (lambda: filters.sigma_points([], np.eye(1), 0.0), r"^x must hold at least one state"),
    (lambda: filters.nees([1.0], np.eye(2)), r"^err must have 2 components \(the size of P\)"),
    (lambda: filters.consistency_verdict(1.0, 5.0, -0.0), r"^hi must be at least lo = 5"),
    (lambda: filters.chi2_bounds(5e-324, 50), r"^dof must be a real number in \[1, 1e\+12\]"),
    (lambda: filters.chi2_bounds(6, 1e12), r"^n_runs must be at most 1\.66667e\+11 with dof = 6"),
])
def test_an_edge_input_is_refused_naming_it(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_a_skipped_update_with_its_model_is_checked_and_skips():
    up = filters.ekf_update(np.zeros(1), np.eye(1), None, np.zeros(1), np.eye(1), np.eye(1))
    assert up.innovation is None and np.isnan(up.nis)
    up = filters.ukf_update(np.zeros(1), np.eye(1), None, lambda s: s, np.eye(1))
    assert up.S is None and np.isnan(up.nis)


def test_sigma_points_refuses_a_non_symmetric_P():
    """Review 35j (4) 1: sigma_points used the silently symmetrised P (P and P.T gave the same
    points); every filter refuses a non-symmetric P."""
    P = np.array([[1.0, 0.5], [0.0, 1.0]])
    for bad in (P, P.T, 1e300 * P):
        with pytest.raises(ValueError, match=r"^P must be symmetric \(to 1e-08 of its largest entry\)"):
            filters.sigma_points(np.zeros(2), bad, 1.0)
    sym = np.array([[1.0, 0.5], [0.5 + 1e-12, 1.0]])         # symmetric to rounding: accepted
    assert filters.sigma_points(np.zeros(2), sym, 1.0).shape == (5, 2)


@pytest.mark.parametrize("bad", ["x", 1.0, True, [], {}])
def test_a_residual_that_cannot_be_called_is_refused_naming_it(bad):
    """Review 35k (1) 2: a residual that is no function reached the call (a raw TypeError
    "'str' object is not callable")."""
    Wm, Wc, _ = filters.ukf_weights(1)
    calls = (
        lambda: filters.ekf_update(np.zeros(1), np.eye(1), np.ones(1), lambda x: x, np.eye(1),
                                   np.eye(1), residual=bad),
        lambda: filters.ukf_update(np.zeros(1), np.eye(1), np.ones(1), lambda s: s, np.eye(1),
                                   residual=bad),
        lambda: filters.unscented_transform(np.array([[0.0], [2.0], [-2.0]]), Wm, Wc,
                                            residual=bad),
    )
    for call in calls:
        with pytest.raises(ValueError, match=r"^residual must be a function residual\("):
            call()


def test_a_residual_of_the_wrong_shape_is_refused_naming_it():
    """Review 35k (1) 2, the class: a residual's output reached the UKF's products unchecked."""
    with pytest.raises(ValueError, match=r"^residual\(a, b\) must have shape \(3, 1\)"):
        filters.ukf_update(np.zeros(1), np.eye(1), np.ones(1), lambda s: s, np.eye(1),
                           residual=lambda a, b: np.zeros(2))


def test_a_beta_that_makes_the_transformed_covariance_indefinite_is_refused():
    """Review 35k (4) 1: beta = -3 (or -1e3) made the central covariance weight Wc0 negative and
    ukf_predict returned an indefinite P (eigenvalues -2 and 6). Decision: beta keeps its range
    [-1e3, 1e3] (the chapter's alpha = 1e-3 has Wc0 = -1e6 with the default beta = 2, so no beta
    range alone keeps Wc0 >= 0); a covariance that comes out indefinite with Wc0 < 0 is
    refused, naming beta and the beta that keeps Wc0 >= 0."""
    f = lambda s: s**2  # noqa: E731
    for beta in (-3.0, -1e3):
        with pytest.raises(ValueError, match=r"^beta must keep the central covariance weight "
                                             r"Wc0 = .* >= 0 here .*the predicted covariance P is "
                                             r"not positive semi-definite .*; use beta >= 0$"):
            filters.ukf_predict(np.ones(2), np.eye(2), f, np.zeros((2, 2)), beta=beta)
    with pytest.raises(ValueError, match=r"^beta must keep .*the innovation covariance S is not "
                                         r"positive definite"):
        filters.ukf_update(np.ones(2), np.eye(2), np.ones(1), lambda s: s[:1] ** 2,
                           np.eye(1) * 1e-6, beta=-1e3)
    with pytest.raises(ValueError, match=r"^beta must keep"):
        filters.UKF(np.ones(2), np.eye(2), beta=-3.0).predict(f, np.zeros((2, 2)))
    Wm, Wc, _ = filters.ukf_weights(1, beta=-1e3)
    with pytest.raises(ValueError, match=r"^Wc\[0\] must be >= 0 here .*got -1000: the "
                                         r"covariance is not positive semi-definite"):
        filters.unscented_transform(np.array([[0.0], [2.0], [-1.0]]), Wm, Wc)
    # a negative Wc0 whose covariance stays positive is used; a linear f is exact for any beta
    x, P = filters.ukf_predict(np.ones(2), np.eye(2), lambda s: 2 * s, np.zeros((2, 2)), beta=-3.0)
    np.testing.assert_allclose(P, 4 * np.eye(2))
    x, P = filters.ukf_predict(np.ones(2), np.eye(2), f, np.zeros((2, 2)), alpha=1e-3)
    assert np.linalg.eigvalsh(P)[0] > 0


def test_ukf_stores_its_weights_parameters_as_floats():
    """Review 35k pattern C: UKF kept the user's numpy scalars for alpha, beta, kappa."""
    kf = filters.UKF([0.0], [[1.0]], alpha=np.float16(0.5), beta=np.int8(2), kappa=np.float32(0))
    assert [type(v) for v in (kf.alpha, kf.beta, kf.kappa)] == [float, float, float]
