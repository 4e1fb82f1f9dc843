"""The T-S fuzzy model (xnavlab.plins.parity.fuzzy): premises, operating points, triangular
memberships that partition unity, and the local linear models."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from xnavlab.plins import ins
from xnavlab.plins import parity as P
from xnavlab.plins import pseudolites as pl

finite = dict(allow_nan=False, allow_infinity=False)


TRAJ = ins.paper_trajectory()


SITES = pl.sites_ecef()


MODELS = P.local_models(P.operating_points(TRAJ), TRAJ.lon[0], TRAJ.h[0], SITES, TRAJ.dt)


# ------------------------------------------------------------------ T-S fuzzy model
def test_premises_and_operating_points():
    rho = P.premises(TRAJ)
    assert rho.shape == (201, 3)
    pts = P.operating_points(TRAJ, 5)
    assert pts.shape == (5, 3)
    np.testing.assert_allclose(pts[:, 1], [100.0, 125.0, 150.0, 175.0, 200.0])
    np.testing.assert_allclose(pts[:, 2], 0.5)
    with pytest.raises(ValueError, match="n_points"):
        P.operating_points(TRAJ, 0)
    with pytest.raises(ValueError, match="traj"):
        P.premises([1, 2, 3])


def test_triangular():
    np.testing.assert_allclose(P.triangular([-1.0, 0.0, 3.0, 4.0], 0.0, 2.0, 4.0),
                               [0.0, 0.0, 0.5, 0.0])
    np.testing.assert_allclose(P.triangular([5.0, 1.0], 0.0, 1.0, 1.0), [1.0, 1.0])  # shoulder
    with pytest.raises(ValueError, match="center"):
        P.triangular(0.0, 1.0, 0.0, 2.0)
    with pytest.raises(ValueError, match="right"):
        P.triangular(0.0, 0.0, 1.0, 0.5)
    with pytest.raises(ValueError, match="x"):
        P.triangular(math.nan, 0.0, 1.0, 2.0)


@given(
    x=st.lists(st.floats(-10.0, 10.0, **finite), min_size=1, max_size=20),
    gaps=st.lists(st.floats(0.1, 3.0, **finite), min_size=0, max_size=5),
)
def test_partition_of_unity(x, gaps):
    centers = np.cumsum([-1.0, *gaps])
    mu = P.partition_memberships(x, centers)
    assert mu.shape == (len(x), len(centers))
    np.testing.assert_allclose(mu.sum(axis=1), 1.0)
    assert np.all((mu >= 0.0) & (mu <= 1.0))


def test_memberships():
    pts = P.operating_points(TRAJ)
    w = P.memberships(P.premises(TRAJ), pts)
    assert w.shape == (201, 3)
    np.testing.assert_allclose(w.sum(axis=1), 1.0)
    np.testing.assert_allclose(w[[0, 100, 200]], np.eye(3), atol=1e-12)
    assert np.all(w[1:100, 2] == 0.0) and np.all(w[101:, 0] == 0.0)
    with pytest.raises(ValueError, match="centers"):
        P.partition_memberships([0.0], [1.0, 0.0])
    with pytest.raises(ValueError, match="rho"):
        # a premise no rule covers: north acceleration 5 m/s^2 with sets at 0 and 1
        P.memberships([[39.0, 100.0, 5.0]], [[39.0, 100.0, 0.0], [39.2, 200.0, 1.0]])
    with pytest.raises(ValueError, match="points"):
        P.memberships([[39.0, 100.0, 0.5]], [39.0, 100.0, 0.5])


def test_local_models():
    assert len(MODELS) == 3
    lm = MODELS[0]
    np.testing.assert_allclose(lm.point, [39.0, 100.0, 0.5], atol=1e-9)
    F = ins.error_matrix(TRAJ.lat[0], TRAJ.h[0], TRAJ.v_enu[0], TRAJ.f_enu[0])
    A, Qd = ins.discretize(F, ins.noise_matrix(), ins.imu_noise_psd(), 1.0)
    np.testing.assert_allclose(lm.A, A, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(lm.B @ lm.B.T, Qd, rtol=1e-6, atol=1e-18)
    np.testing.assert_allclose(
        lm.C, pl.measurement_matrix(TRAJ.lat[0], TRAJ.lon[0], TRAJ.h[0], SITES))
    with pytest.raises(ValueError, match="points"):
        P.local_models([1.0, 2.0, 3.0], 0.0, 0.0, SITES, 1.0)


def test_a_subnormal_width_is_a_shoulder_not_an_overflow():
    """Issue 35 (review 35h): center=5e-324 (a width of one subnormal) gave an overflow warning."""
    np.testing.assert_array_equal(P.triangular([0.0, 0.5, 1.0, 1.5, 2.0], 0.0, 5e-324, 2.0),
                                  [0.0, 0.75, 0.5, 0.25, 0.0])


def test_local_models_check_lon_and_h_under_their_names():
    """Issue 35 (review 35h): lon=[] was refused as 'r must have shape (3,), got (0, 3)'."""
    tr = ins.paper_trajectory(duration=10.0)
    args = (P.operating_points(tr), tr.lon[0], tr.h[0], pl.sites_ecef(), tr.dt)
    with pytest.raises(ValueError,
                       match=r"^lon must be a longitude in radians in \[-6\.28319, 6\.28319\], got \[\]$"):
        P.local_models(args[0], [], *args[2:])
    with pytest.raises(ValueError, match=r"^h must be a real number in \[-10000, 100000\], got \[1\.0\]$"):
        P.local_models(*args[:2], [1.0], *args[3:])


def test_memberships_name_premises_of_the_wrong_shape():
    """Issue 35 (review 35i): x=[[0.0, 0.25]] and rho of shape (1, 1, 3) were numpy's 'could not
    broadcast input array from shape (2,) into shape (1,)'."""
    with pytest.raises(ValueError, match=r"^x must have shape \(n,\) with n >= 1 \(one premise value "
                                         r"a sample\), got shape \(1, 2\)$"):
        P.partition_memberships([[0.0, 0.25]], [0.0, 1.0, 2.0])
    pts = np.array([[39.0, 100.0, 0.5], [39.2, 200.0, 0.5]])
    with pytest.raises(ValueError, match=r"^rho must have shape \(n, 3\) with n >= 1 \(one premise "
                                         r"a sample\), got shape \(1, 1, 3\)$"):
        P.memberships(np.zeros((1, 1, 3)), pts)
    assert P.partition_memberships(0.25, [0.0, 1.0]).tolist() == [[0.75, 0.25]]


def test_local_models_name_the_operating_point_its_error_model_cannot_take():
    """Issue 35 (review 35i): f_n = 60 m/s^2 was refused as 'F must have row sums ...' and a
    latitude of 100 deg as 'lat must be a real number in [-1.5708, 1.5708]' (radians)."""
    ops = P.operating_points(TRAJ)
    args = (TRAJ.lon[0], TRAJ.h[0], pl.sites_ecef(), TRAJ.dt)
    fast = ops.copy()
    fast[1, 2] = 60.0
    with pytest.raises(ValueError, match=r"^points\[1\] must give an error model with \|\|F\|\|_inf "
                                         r"dt <= 50 \(discretize's bound\), got 69.7"):
        P.local_models(fast, *args)
    polar = ops.copy()
    polar[0, 0] = 100.0
    with pytest.raises(ValueError, match=r"^points\[0\] must have a latitude in \[-89, 89\] deg"):
        P.local_models(polar, *args)
    with pytest.raises(ValueError, match=r"^dt must be a real number in \(0, 86400\]"):
        P.local_models(ops, *args[:3], 1e5)


def test_no_operating_point_no_premise_and_no_site_are_refused():
    """Review 35k (3) 17, (5) 9: memberships(rho, points of 0 rows) was refused as 'centers must
    be a non-empty ...' (an inner name); local_models(points[:0]) returned [] and
    local_models(..., sites[:0], ...) built models without pseudolites."""
    tr = ins.paper_trajectory()
    pts = P.operating_points(tr)
    with pytest.raises(ValueError, match=r"^points must have shape \(N, 3\) with N >= 1"):
        P.fuzzy.memberships([[39.1, 150.0, 0.5]], np.zeros((0, 3)))
    with pytest.raises(ValueError, match=r"^rho must have shape \(n, 3\) with n >= 1"):
        P.fuzzy.memberships(np.zeros((0, 3)), pts)
    with pytest.raises(ValueError, match=r"^x must have shape \(n,\) with n >= 1"):
        P.fuzzy.partition_memberships([], [0.0, 1.0])
    with pytest.raises(ValueError, match=r"^points must have shape \(N, 3\) with N >= 1"):
        P.fuzzy.local_models(pts[:0], tr.lon[0], tr.h[0], pl.sites_ecef(), tr.dt)
    with pytest.raises(ValueError, match=r"^sites must have shape \(m, 3\) with m >= 1"):
        P.fuzzy.local_models(pts, tr.lon[0], tr.h[0], pl.sites_ecef()[:0], tr.dt)
