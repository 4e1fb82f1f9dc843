"""Quaternion identities (scalar last) for xnavlab.core.quaternions."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from xnavlab.core import quaternions as qt

finite = st.floats(-1.0, 1.0, allow_nan=False, allow_infinity=False)
vec3 = st.lists(finite, min_size=3, max_size=3).map(np.array)
rate = st.lists(st.floats(-0.5, 0.5), min_size=3, max_size=3).map(np.array)


@st.composite
def unit_quat(draw):
    v = np.array(draw(st.lists(finite, min_size=4, max_size=4)))
    if np.linalg.norm(v) < 1e-3:
        v = qt.IDENTITY.copy()
    return v / np.linalg.norm(v)


@given(unit_quat(), unit_quat())
def test_product_preserves_norm(p, q):
    assert np.linalg.norm(qt.quat_product(p, q)) == pytest.approx(1.0, abs=1e-12)


@given(unit_quat(), unit_quat(), unit_quat())
def test_product_is_associative(p, q, r):
    left = qt.quat_product(qt.quat_product(p, q), r)
    right = qt.quat_product(p, qt.quat_product(q, r))
    np.testing.assert_allclose(left, right, atol=1e-12)


@given(unit_quat())
def test_conjugate_is_the_inverse(q):
    np.testing.assert_allclose(qt.quat_product(q, qt.quat_conjugate(q)), qt.IDENTITY, atol=1e-12)
    np.testing.assert_allclose(qt.quat_product(qt.quat_conjugate(q), q), qt.IDENTITY, atol=1e-12)


@given(vec3, unit_quat())
def test_omega_q_equals_xi_x(x, q):
    """Paper eq. (20): Omega(x) q = Xi(q) x."""
    np.testing.assert_allclose(qt.omega_matrix(x) @ q, qt.xi_matrix(q) @ x, atol=1e-12)


@given(unit_quat())
def test_xi_columns_orthonormal_and_orthogonal_to_q(q):
    Xi = qt.xi_matrix(q)
    np.testing.assert_allclose(Xi.T @ Xi, np.eye(3), atol=1e-12)
    np.testing.assert_allclose(Xi.T @ q, 0.0, atol=1e-12)


@given(unit_quat(), unit_quat())
def test_rotation_matrix_composes_like_the_product(p, q):
    A = qt.rotation_matrix(qt.quat_product(p, q))
    np.testing.assert_allclose(A, qt.rotation_matrix(p) @ qt.rotation_matrix(q), atol=1e-12)
    np.testing.assert_allclose(A @ A.T, np.eye(3), atol=1e-12)
    assert np.linalg.det(A) == pytest.approx(1.0, abs=1e-12)


@given(unit_quat(), unit_quat())
def test_psi_form_of_the_product(p, q):
    Pm = np.column_stack([qt.psi_matrix(p), p])
    np.testing.assert_allclose(qt.quat_product(p, q), Pm @ q, atol=1e-12)
    np.testing.assert_allclose(qt.xi_matrix(q).T @ qt.psi_matrix(q), qt.rotation_matrix(q),
                               atol=1e-12)


@given(vec3, vec3)
def test_skew_is_the_cross_product(a, b):
    np.testing.assert_allclose(qt.skew(a) @ b, np.cross(a, b), atol=1e-12)


@given(unit_quat(), rate, st.floats(0.0, 2.0))
def test_propagation_preserves_norm_and_is_orthogonal(q, w, dt):
    assert np.linalg.norm(qt.quat_propagate(q, w, dt)) == pytest.approx(1.0, abs=1e-12)
    Phi = qt.kinematics_matrix(w, dt)
    np.testing.assert_allclose(Phi @ Phi.T, np.eye(4), atol=1e-12)


@given(unit_quat(), rate, st.floats(0.01, 5.0))
def test_discrete_kinematics_matches_integration(q, w, dt):
    """Paper eq. (12) against a numerical integration of q_dot = 1/2 Omega(w) q."""
    Om = qt.omega_matrix(w)
    sol = solve_ivp(lambda t, y: 0.5 * Om @ y, (0.0, dt), q, rtol=1e-11, atol=1e-13)
    np.testing.assert_allclose(qt.quat_propagate(q, w, dt), sol.y[:, -1], atol=1e-8)


@given(unit_quat(), rate, st.floats(0.01, 1.0))
def test_propagation_is_a_body_rotation(q, w, dt):
    dq = qt.quat_from_rotvec(w * dt)
    np.testing.assert_allclose(qt.quat_propagate(q, w, dt), qt.quat_product(dq, q), atol=1e-12)


@given(st.lists(st.floats(-3.0, 3.0), min_size=3, max_size=3).map(np.array))
def test_rotvec_round_trip(phi):
    if np.linalg.norm(phi) >= np.pi:
        phi = phi / np.linalg.norm(phi) * 3.0
    np.testing.assert_allclose(qt.quat_to_rotvec(qt.quat_from_rotvec(phi)), phi, atol=1e-9)
    np.testing.assert_allclose(qt.quat_to_rotvec(-qt.quat_from_rotvec(phi)), phi, atol=1e-9)


@given(unit_quat(), st.lists(st.floats(-1e-3, 1e-3), min_size=3, max_size=3).map(np.array))
def test_attitude_error_recovers_small_rotation(q, dth):
    q_est = qt.quat_product(qt.quat_from_rotvec(dth), q)
    np.testing.assert_allclose(qt.attitude_error(q_est, q), dth, atol=1e-12)


def test_batches_broadcast():
    q = np.tile(qt.quat_from_rotvec([0.1, 0.2, 0.3]), (5, 2, 1))
    w = np.zeros((5, 2, 3))
    assert qt.quat_propagate(q, w, 0.1).shape == (5, 2, 4)
    assert qt.rotation_matrix(q).shape == (5, 2, 3, 3)
    assert qt.xi_matrix(q).shape == (5, 2, 4, 3)
    assert qt.omega_matrix(w).shape == (5, 2, 4, 4)


def test_normalize_and_conjugate():
    np.testing.assert_allclose(qt.quat_normalize([0, 0, 3.0, 4.0]), [0, 0, 0.6, 0.8])
    np.testing.assert_allclose(qt.quat_conjugate([1.0, 2, 3, 4]), [-1.0, -2, -3, 4])


@pytest.mark.parametrize(
    ("func", "args", "name"),
    [
        (qt.quat_normalize, ([0.0, 0.0, 0.0, 0.0],), "q"),
        (qt.quat_normalize, ([1.0, 2.0, 3.0],), "q"),
        (qt.quat_product, ([0, 0, 0, 1.0], [np.nan, 0, 0, 1.0]), "q"),
        (qt.quat_product, ([0, 0, 1.0], [0, 0, 0, 1.0]), "p"),
        (qt.omega_matrix, ([1.0, 2.0],), "w"),
        (qt.xi_matrix, ([1.0, 2.0, 3.0],), "q"),
        (qt.psi_matrix, (np.zeros(5),), "q"),
        (qt.skew, ([1.0, np.inf, 0.0],), "v"),
        (qt.quat_propagate, (qt.IDENTITY, [0.0, 0.0, 0.1], -1.0), "dt"),
        (qt.kinematics_matrix, ([0.0, 0.0, 0.1], float("nan")), "dt"),
        (qt.quat_from_rotvec, ([0.0, 0.0],), "phi"),
        (qt.rotation_matrix, ([0.0, 0.0, 1.0],), "q"),
        (qt.attitude_error, (qt.IDENTITY, [0.0, 0.0, 0.0, 0.0]), "q_true"),
    ],
)
def test_bad_input_names_the_parameter(func, args, name):
    with pytest.raises(ValueError, match=rf"^{name} "):
        func(*args)


def test_attitude_error_names_its_own_arguments():
    with pytest.raises(ValueError, match="^q_est must hold real numbers"):
        qt.attitude_error([1j, 0, 0, 1], [0, 0, 0, 1])
    with pytest.raises(ValueError, match="^q_true must contain only finite"):
        qt.attitude_error([0, 0, 0, 1], [np.nan, 0, 0, 1])


@pytest.mark.parametrize("scale", [1e300, 1e-300, 1e150, 1e-160])
def test_huge_and_tiny_quaternions_normalise_exactly(scale):
    """Review 35 D.11: [1e300, 1e300, 0, 0] gave [0, 0, 0, 0] (the squares overflowed)."""
    q = scale * np.array([1.0, 1.0, 0.0, 0.0])
    np.testing.assert_allclose(qt.quat_normalize(q), [2**-0.5, 2**-0.5, 0.0, 0.0], rtol=1e-15)
    np.testing.assert_allclose(qt.quat_to_rotvec(q), [np.pi / 2**0.5] * 2 + [0.0], rtol=1e-15)


@given(st.lists(st.floats(-1e3, 1e3), min_size=4, max_size=4).filter(lambda v: any(v)))
def test_normalise_is_numpy_s_own_division_in_the_usual_range(v):
    q = np.array(v)
    assert np.array_equal(qt.quat_normalize(q), q / np.linalg.norm(q, axis=-1, keepdims=True))


def test_a_rotation_of_a_huge_vector_or_rate_is_refused():
    """Review 35b N20: an angle of 1e300 rad gave a finite but arbitrary quaternion."""
    with pytest.raises(ValueError, match=r"^\|phi\| must be a rotation angle of at most 1e\+06 rad"):
        qt.quat_from_rotvec([1e300, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"^\|w\| dt must be a rotation angle of at most 1e\+06"):
        qt.quat_propagate(qt.IDENTITY, 1e300 * np.ones(3), 1.0)
    with pytest.raises(ValueError, match=r"^\|w\| dt must be a rotation angle"):
        qt.kinematics_matrix([2e6, 0.0, 0.0], 1.0)
    big = qt.quat_from_rotvec([qt.MAX_ANGLE, 0.0, 0.0])  # the bound itself is taken
    assert np.linalg.norm(big) == pytest.approx(1.0)
    with pytest.raises(ValueError, match="^w and dt must give a finite rotation angle"):
        qt.quat_propagate(qt.IDENTITY, 1e308 * np.ones(3), 10.0)
    with pytest.raises(ValueError, match="^phi must have a finite norm"):
        qt.quat_from_rotvec([1.7e308, 1.7e308, 0.0])
    with pytest.raises(ValueError, match="^p and q must have a finite product"):
        qt.quat_product([1e200, 0, 0, 1e200], [1e200, 0, 0, 0])


@pytest.mark.parametrize("q", [np.zeros(4), [0.0, 0.0, 0.0, 2.0], [1e200, 0.0, 0.0, 1e200],
                               [0.0, 0.0, 0.0, 1.0 + 2e-6]])
def test_rotation_matrix_refuses_a_quaternion_that_is_not_unit(q):
    """It does not renormalise: zeros gave the zero matrix, [0, 0, 0, 2] gave 4 I."""
    with pytest.raises(ValueError, match=r"^q must (be a unit quaternion|have a non-zero norm)"):
        qt.rotation_matrix(q)
    np.testing.assert_allclose(qt.rotation_matrix([0.0, 0.0, 0.0, 1.0 + 5e-7]), np.eye(3), atol=2e-6)


@pytest.mark.parametrize("func", [qt.quat_product, qt.quat_propagate, qt.xi_matrix, qt.psi_matrix,
                                  qt.quat_conjugate, qt.attitude_error])
def test_a_zero_quaternion_is_no_attitude(func):
    args = {qt.quat_product: (qt.IDENTITY, np.zeros(4)), qt.quat_propagate: (np.zeros(4), np.zeros(3), 1.0),
            qt.attitude_error: (qt.IDENTITY, np.zeros(4))}.get(func, (np.zeros(4),))
    with pytest.raises(ValueError, match=r"^q(_true)? must have a non-zero norm"):
        func(*args)


@pytest.mark.parametrize(("func", "args", "names"), [
    (qt.quat_product, (np.tile(qt.IDENTITY, (3, 1)), np.tile(qt.IDENTITY, (2, 1))), "p and q"),
    (qt.quat_propagate, (np.tile(qt.IDENTITY, (3, 1)), np.zeros((2, 3)), 1.0), "q and w"),
    (qt.attitude_error, (np.tile(qt.IDENTITY, (3, 1)), np.tile(qt.IDENTITY, (2, 1))),
     "q_est and q_true"),
])
def test_batches_that_do_not_broadcast_name_both_arguments(func, args, names):
    """Review 35b N18: numpy's 'operands could not be broadcast' named no parameter."""
    with pytest.raises(ValueError, match=rf"^{names} must have batch shapes that broadcast"):
        func(*args)
    assert qt.quat_product(np.tile(qt.IDENTITY, (3, 1)), qt.IDENTITY).shape == (3, 4)


@given(st.lists(st.floats(-10.0, 10.0), min_size=12, max_size=12),
       st.floats(0.0, 1.0))
def test_the_unchecked_matrices_are_the_checked_ones_bit_for_bit(values, dt):
    """The inner loops' variants skip only the conversion and checks of their inputs."""
    w = np.array(values[:9]).reshape(3, 3)
    q = np.array(values).reshape(3, 4)
    q[np.all(q == 0.0, axis=1)] = qt.IDENTITY
    assert np.array_equal(qt.kinematics_matrix_unchecked(w, dt), qt.kinematics_matrix(w, dt))
    assert np.array_equal(qt.xi_matrix_unchecked(q), qt.xi_matrix(q))


@pytest.mark.parametrize(("call", "match"), [
    (lambda: qt.kinematics_matrix_unchecked([1.0], 0.1), r"^w must be a float ndarray of shape \(\.\.\., 3"),
    (lambda: qt.kinematics_matrix_unchecked(np.array(1.0), 0.1), r"^w must be a float ndarray"),
    (lambda: qt.kinematics_matrix_unchecked(np.zeros(3), True), r"^dt must be a real number in \[0"),
    (lambda: qt.kinematics_matrix_unchecked(np.zeros(3), []), r"^dt must be a real number"),
    (lambda: qt.xi_matrix_unchecked(-0.0), r"^q must be a float ndarray of shape \(\.\.\., 4\)"),
])
def test_the_unchecked_forms_refuse_what_is_no_float_array_naming_it(call, match):
    with pytest.raises(ValueError, match=match):
        call()


@pytest.mark.parametrize("func, arg, name", [
    (lambda w: qt.kinematics_matrix_unchecked(w, 0.1), np.array([0.01, -0.02, 0.03]), "w"),
    (qt.xi_matrix_unchecked, qt.quat_from_rotvec([0.1, -0.2, 0.3]), "q")])
def test_the_unchecked_kernels_take_only_a_plain_ndarray(func, arg, name):
    """Review 35m (5) 1: a masked array passed their isinstance(ndarray) test and its masked
    entries were used; a read-only one is a plain ndarray and gives the same result."""
    masked = np.ma.masked_array(arg.copy())
    masked[0] = np.ma.masked
    for bad in (masked, np.ma.masked_array(arg.copy())):
        with pytest.raises(ValueError, match=rf"^{name} must be a float ndarray of shape .* got "
                                             rf"MaskedArray array\(\["):
            func(bad)
    ro = arg.copy()
    ro.setflags(write=False)
    assert np.array_equal(func(ro), func(arg))
