"""The parity space (xnavlab.plins.parity.space): stacked matrices, parity bases orthogonal to the
state, their alignment and blending, identifiability and the residual threshold."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.stats import chi2

from xnavlab.plins import ins
from xnavlab.plins import parity as P
from xnavlab.plins import pseudolites as pl

from ._paper_design import MODELS, TRAJ, W_DESIGN

# ---------------------------------------------------------------------- parity space
small_systems = st.integers(0, 10_000).map(lambda seed: np.random.default_rng(seed))


@given(rng=small_systems, s=st.integers(1, 6))
def test_stacked_matrices_reproduce_a_simulation(rng, s):
    n, m, r = 3, 2, 2
    A = rng.normal(size=(n, n)) / 2
    C = rng.normal(size=(m, n))
    B = rng.normal(size=(n, r))
    x0 = rng.normal(size=n)
    w = rng.normal(size=(s + 1, r))
    x, ys = x0, []
    for k in range(s + 1):
        ys.append(C @ x)
        x = A @ x + B @ w[k]
    H0, Hw = P.stacked_matrices(A, C, s, B)
    np.testing.assert_allclose(H0 @ x0 + Hw @ w.ravel(), np.concatenate(ys), atol=1e-10)


@given(rng=small_systems, s=st.integers(4, 12))
def test_parity_vectors_are_orthogonal_to_the_state_observation_matrix(rng, s):
    n = 4
    A = np.eye(n) + rng.normal(size=(n, n)) / 5
    c = rng.normal(size=n)
    H0, _ = P.stacked_matrices(A, c, s)
    V = P.parity_basis(A, c, s)
    assert V.shape[1] == s + 1 - np.linalg.matrix_rank(H0)
    np.testing.assert_allclose(V.T @ V, np.eye(V.shape[1]), atol=1e-12)
    assert np.linalg.norm(V.T @ H0) <= 1e-9 * np.linalg.norm(H0)


@given(s=st.integers(5, 20), j=st.integers(0, 3))
def test_pl_ins_parity_space(s, j):
    lm = MODELS[1]
    H0, Hw = P.stacked_matrices(lm.A, lm.C[j], s, lm.B)
    # exact decoupling from the IMU noise leaves nothing for one pseudorange (constraint 1)
    assert P.parity_basis(lm.A, lm.C[j], s, B=lm.B).shape == (s + 1, 0)
    # the numerical left null space: state and noise leak less than tol metres
    V = P.parity_basis(lm.A, lm.C[j], s, B=lm.B, state_std=P.TYPICAL_STATE_STD, tol=0.6)
    assert V.shape[1] == s - 1  # constants and lines (clock, position, velocity) removed
    leak = np.linalg.svd(V.T @ np.hstack([H0 * P.TYPICAL_STATE_STD, Hw]), compute_uv=False)
    assert leak[0] <= 0.6


def test_parity_basis_bad_input():
    lm = MODELS[0]
    with pytest.raises(ValueError, match="s"):
        P.parity_basis(lm.A, lm.C[0], -1)
    with pytest.raises(ValueError, match="state_std"):
        P.parity_basis(lm.A, lm.C[0], 11, state_std=np.ones(3))
    with pytest.raises(ValueError, match="tol"):
        P.parity_basis(lm.A, lm.C[0], 11, tol=-1.0)
    with pytest.raises(ValueError, match="C"):
        P.stacked_matrices(lm.A, np.ones(3), 2)
    with pytest.raises(ValueError, match="A"):
        P.stacked_matrices(np.ones((2, 3)), np.ones(3), 2)
    with pytest.raises(ValueError, match="B"):
        P.stacked_matrices(lm.A, lm.C[0], 2, B=np.ones((3, 2)))


def test_align_bases():
    rng = np.random.default_rng(0)
    V, _ = np.linalg.qr(rng.normal(size=(6, 3)))
    R, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    a, b = P.align_bases([V @ R, V], ref=1)
    np.testing.assert_allclose(a, b, atol=1e-12)
    with pytest.raises(ValueError, match="bases"):
        P.align_bases([V, V[:, :2]])
    with pytest.raises(ValueError, match="bases"):
        P.align_bases([])
    with pytest.raises(ValueError, match="ref"):
        P.align_bases([V], ref=3)


@given(s=st.integers(5, 20))
def test_a_constant_fault_is_not_identifiable(s):
    """The paper's eq. 23 (same fault in the whole window) fails constraint 2: the clock."""
    lm = MODELS[2]
    V = P.parity_basis(lm.A, lm.C[0], s, B=lm.B, state_std=P.TYPICAL_STATE_STD, tol=0.6)
    tw = np.arange(s + 1.0)
    assert not P.check_identifiability(V, P.fault_signature(tw, "bias")).ok
    step = P.fault_signature(tw, "step", onset=tw[s // 2])
    assert P.check_identifiability(V, step).ok
    transit = np.stack([P.fault_signature(tw + k, "ramp", onset=s, time_origin="absolute")
                        for k in range(1, s + 1)])
    assert P.check_identifiability(V, transit).ok


def test_check_identifiability_edge_cases():
    rep = P.check_identifiability(np.zeros((4, 0)), np.ones((4, 1)))
    assert rep.null_dim == 0 and not rep.condition_1 and not rep.ok
    with pytest.raises(ValueError, match="M"):
        P.check_identifiability(np.eye(4)[:, :2], np.ones((3, 1)))
    with pytest.raises(ValueError, match="V"):
        P.check_identifiability(np.ones(4), np.ones((4, 1)))
    with pytest.raises(ValueError, match="rtol"):
        P.check_identifiability(np.eye(4)[:, :2], np.ones((4, 1)), rtol=0.0)


# ------------------------------------------------------------------------- residuals
def test_blended_residuals_ignore_the_ins_errors():
    x = ins.simulate_errors(TRAJ, rng=4)
    d = pl.simulate_pseudoranges(TRAJ, x, sigma=0.0)
    r = P.parity_residuals(d.z, W_DESIGN)
    assert r.shape == (190, 4, 10)
    assert np.abs(d.z).max() > 50.0  # the INS errors are there ...
    # ... and decoupled: what is left (the line of sight turning inside the window, which
    # the time-invariant local models do not describe) stays below half the noise
    assert np.linalg.norm(r, axis=2).max() < 0.5 * pl.DEFAULT_SIGMA
    with pytest.raises(ValueError, match="W"):
        P.parity_residuals(d.z, W_DESIGN[:, :3])
    with pytest.raises(ValueError, match="window"):
        P.parity_residuals(d.z[:5], W_DESIGN[:5])
    with pytest.raises(ValueError, match="weights"):
        P.blended_bases(np.ones((3, 2)), np.ones((3, 1, 2, 2)))


def test_residual_threshold_is_sigma_times_the_chi_quantile_and_checks_its_input():
    assert P.residual_threshold(2.0, 10, 1e-6) == pytest.approx(2.0 * math.sqrt(chi2.isf(1e-6, 10)))
    for kw, name in (({"q": 0}, "q"), ({"p_fa": 0.7}, "p_fa"), ({"sigma": 0.0}, "sigma")):
        args = {"sigma": 1.0, "q": 3, "p_fa": 1e-3, **kw}
        with pytest.raises(ValueError, match=name):
            P.residual_threshold(**args)


def test_residual_threshold_refuses_a_noise_or_dimension_beyond_its_range():
    """Review 35e: sigma=1e308 gave an inf threshold."""
    with pytest.raises(ValueError, match=r"^sigma must be a real number in \(0, 1e\+06\], got 1e\+308$"):
        P.residual_threshold(1e308, 1)
    with pytest.raises(ValueError, match=r"^q must be an integer in \[1, 1000\]"):
        P.residual_threshold(1.0, 10**30)


def test_each_matrix_is_checked_on_its_own_first():
    """Issue 35 (review 35h): A=-0.0 was an IndexError, bases=True a TypeError, and a 0-d W or
    bases was refused under the name of z or weights."""
    with pytest.raises(ValueError, match=r"^A must be a square matrix of shape \(n, n\), n >= 1, got "):
        P.stacked_matrices(-0.0, [1.0, 0.0], 2)
    with pytest.raises(ValueError, match=r"^A must be a square matrix"):
        P.parity_basis(-0.0, [1.0, 0.0], 3)
    for bad in (True, -0.0, np.array(1.0)):
        with pytest.raises(ValueError, match=r"^bases must be a list of arrays"):
            P.align_bases(bad)
    V = np.eye(3)[:, :2]
    with pytest.raises(ValueError, match=r"^bases\[1\] must have shape \(3, 2\) \(the shape of bases\[0\]\)"):
        P.align_bases([V, V[:, :1]])
    np.testing.assert_allclose(P.align_bases(np.stack([V, -V]))[0], -V)  # a stack is N bases
    with pytest.raises(ValueError, match=r"^W must have shape \(6, 1, n, n\)"):
        P.parity_residuals(np.zeros((6, 1)), -0.0)
    with pytest.raises(ValueError, match=r"^bases must have shape \(2, n, n, n\) \(N = 2 columns of"):
        P.blended_bases([[0.5, 0.5]], -0.0)


@pytest.mark.parametrize("weights", [[[2.0, 5.0]], [[-0.5, 1.5]], [[0.0, 0.0]]])
def test_blended_bases_takes_memberships_only(weights):
    """Issue 35 (review 35i): weights adding up to 7, or negative, scaled or flipped the basis;
    zero weights blended it to zeros."""
    b = np.stack([np.ones((1, 2, 1)), 3 * np.ones((1, 2, 1))])
    with pytest.raises(ValueError, match=r"^weights\[0\] must be memberships \(each >= 0, adding up to 1\)"):
        P.blended_bases(weights, b)
    assert P.blended_bases([[0.25, 0.75]], b)[0, 0, :, 0].tolist() == [2.5, 2.5]


def test_align_bases_refuses_a_basis_that_is_not_orthonormal():
    """Review 35i: a zero basis was 'aligned' (any rotation of zero is zero), a scaled one too."""
    V = np.eye(3)[:, :2]
    with pytest.raises(ValueError, match=r"^bases\[0\] must have orthonormal columns"):
        P.align_bases([np.zeros((3, 2)), V])
    with pytest.raises(ValueError, match=r"^bases\[1\] must have orthonormal columns.*off by 3"):
        P.align_bases([V, 2.0 * V])


def test_check_identifiability_refuses_a_signature_of_no_parameter():
    """Review 35i: M with zero columns gave numpy's reshape message."""
    with pytest.raises(ValueError, match=r"^M must have shape \(4, k\) or \(K, 4, k\), k >= 1"):
        P.check_identifiability(np.eye(4)[:, :2], np.zeros((4, 0)))
