"""Fully decoupled parity space over a data window (paper eqs. 15-22, 25-26).

Time-redundant measurement of sensor ``j`` over the ``s + 1`` latest samples
(eqs. 15-17, 20): ``Y_j(k) = H_0 x(k - s) + H_w W(k) + eps_j(k)`` with
``H_0 = [c_j; c_j A; ...; c_j A^s]`` and ``H_w`` the block-Toeplitz matrix of the Markov
parameters ``c_j A^i B`` (:func:`stacked_matrices`). The columns of ``V_j`` span the left
null space of ``H* = [H_0 H_w]`` (:func:`parity_basis`, eqs. 18-22), so ``r_j = V_j^T Z_j``
is decoupled from the state and the disturbance and, built from sensor ``j`` alone,
sensitive to that sensor only (Chow & Willsky 1984; Gertler 1998). The bases of the local
models are aligned (:func:`align_bases`) and blended with the memberships
(:func:`blended_bases`) into the global residual ``r_j(k) = sum_l mu_l(k) r_lj(k)``
(:func:`parity_residuals`, eq. 25), tested against ``r_t`` (:func:`residual_threshold`,
eq. 26). :func:`check_identifiability` tests the paper's two constraints.

*Exact* decoupling leaves no parity space for a single pseudorange (every new sample
brings new IMU noise into the window), and an exact left null space of ``H_0`` annihilates
polynomials of high degree, which costs most of the fault sensitivity. We therefore take
the **numerical** left null space: the directions in which a typical (1-sigma) state
(:data:`TYPICAL_STATE_STD`) or noise sample contributes less than ``tol`` metres to the
window (``tol = 0.3 sigma`` in :func:`xnavlab.plins.parity.diagnosis.diagnose_flight`).
The paper's exact version is ``tol=None``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from xnavlab.core.distributions import chi2_isf
from xnavlab.core.validate import check_arrays, check_finite_array, check_int, check_real, check_shape

__all__ = [
    "TYPICAL_STATE_STD",
    "ORTHONORMAL_TOL",
    "stacked_matrices",
    "parity_basis",
    "align_bases",
    "Identifiability",
    "check_identifiability",
    "blended_bases",
    "parity_residuals",
    "residual_threshold",
]

#: Typical (1-sigma) size of the INS error state during the flight, used to weigh the
#: state directions when the numerical left null space is taken (our choice: tilt
#: 0.3 mrad, heading 3 mrad, velocity 1 m/s, position 100 m, clock 1 km).
TYPICAL_STATE_STD = np.array(
    [3e-4, 3e-4, 3e-3, 1.0, 1.0, 1.0, 100.0 / 6.36e6, 100.0 / 4.95e6, 100.0, 1000.0]
)
#: How far ``V^T V`` of a basis :func:`align_bases` takes may be from the identity: the
#: SVD's bases are orthonormal to about 1e-15; a zero or scaled basis is far off.
ORTHONORMAL_TOL = 1e-6


# --------------------------------------------------------------- parity space


def stacked_matrices(A, C, s, B=None):
    """Time-redundant measurement matrices ``H_0`` and ``H_w`` over ``s + 1`` samples.

    ``Y(k) = H_0 x(k - s) + H_w W(k)`` with ``W = [w(k-s); ...; w(k)]`` (paper eqs.
    15-17): block row ``i`` of ``H_0`` is ``C A^i``; block ``(i, j)`` of ``H_w`` is
    ``C A^{i-1-j} B`` for ``j < i`` and zero otherwise.

    Parameters
    ----------
    A : array_like, shape (n, n)
        Discrete transition.
    C : array_like, shape (m, n) or (n,)
        Measurement rows (one row: a single sensor).
    s : int
        Window length minus one, in [0, 200].
    B : array_like, shape (n, r), optional
        Disturbance input; ``None`` gives an empty ``H_w``.

    Returns
    -------
    H0 : ndarray, shape ((s+1) m, n)
    Hw : ndarray, shape ((s+1) m, (s+1) r)

    Examples
    --------
    >>> H0, Hw = stacked_matrices([[1.0, 1.0], [0.0, 1.0]], [1.0, 0.0], 2, B=[[0.0], [1.0]])
    >>> H0.tolist(), Hw.tolist()
    ([[1.0, 0.0], [1.0, 1.0], [1.0, 2.0]], [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    """
    A = check_finite_array("A", A)
    if A.ndim != 2 or A.shape[0] != A.shape[1] or A.size == 0:
        raise ValueError(f"A must be a square matrix of shape (n, n), n >= 1, got shape {A.shape}")
    n = A.shape[0]
    C = np.atleast_2d(check_finite_array("C", C))
    if C.ndim != 2 or C.shape[1] != n:
        raise ValueError(f"C must have shape (m, {n}), got {C.shape}")
    s = check_int("s", s, 0, 200)
    m = C.shape[0]
    rows = [C]
    for _ in range(s):
        rows.append(rows[-1] @ A)  # C A^i, eq. (16)
    H0 = np.vstack(rows)
    if B is None:
        return H0, np.zeros((H0.shape[0], 0))
    B = check_finite_array("B", B)
    if B.ndim != 2 or B.shape[0] != n:
        raise ValueError(f"B must have shape ({n}, r), got {B.shape}")
    r = B.shape[1]
    markov = [rows[i] @ B for i in range(s)]  # C A^i B
    Hw = np.zeros(((s + 1) * m, (s + 1) * r))
    for i in range(1, s + 1):
        for j in range(i):
            Hw[i * m:(i + 1) * m, j * r:(j + 1) * r] = markov[i - 1 - j]  # eq. (17)
    return H0, Hw


def parity_basis(A, C, s, *, B=None, state_std=None, tol=None):
    """Orthonormal basis of the left null space of ``H* = [H_0 D, H_w]`` (paper eqs. 19, 22).

    The columns ``v`` satisfy ``v^T H_0 x ~ 0`` and ``v^T H_w W ~ 0``: the residual
    ``v^T Z`` does not depend on the state at the start of the window nor on the
    disturbance inside it.

    Parameters
    ----------
    A : array_like, shape (n, n)
        Discrete transition.
    C : array_like, shape (m, n) or (n,)
        Measurement rows; one row gives the single-sensor (fully decoupled) parity space.
    s : int
        Window length minus one.
    B : array_like, shape (n, r), optional
        Disturbance input for unit-variance noise (``LocalModel.B``); ``None`` ignores
        the disturbance.
    state_std : array_like, shape (n,), optional
        Typical size of each state, weighting the columns of ``H_0`` so that ``tol`` is
        in the units of the measurement (default: ones).
    tol : float, optional
        Singular values of ``H*`` above ``tol`` span the directions to decouple. ``None``
        is numerical exactness (``max(shape) eps sigma_max``): the paper's left null
        space. A value in metres, such as ``0.3 sigma``, keeps the directions in which a
        typical state or noise contributes less than ``tol`` to the window.

    Returns
    -------
    ndarray, shape ((s+1) m, q)
        Orthonormal columns; ``q = 0`` when the null space is empty (constraint 1 fails).

    Examples
    --------
    >>> A = [[1.0, 1.0], [0.0, 1.0]]          # position and velocity, dt = 1
    >>> V = parity_basis(A, [1.0, 0.0], 3)     # annihilates constants and lines
    >>> V.shape, bool(np.allclose(V.T @ [1.0, 1.0, 1.0, 1.0], 0.0))
    ((4, 2), True)
    """
    H0, Hw = stacked_matrices(A, C, s, B)
    if state_std is not None:
        d = check_finite_array("state_std", state_std, shape=(H0.shape[1],))
        if d.ndim != 1 or np.any(d < 0):
            raise ValueError("state_std must be a 1-D array of values >= 0")
        H0 = H0 * d
    Hs = np.hstack([H0, Hw])
    U, S, _ = np.linalg.svd(Hs, full_matrices=True)
    if tol is None:
        tol = max(Hs.shape) * np.finfo(float).eps * (S[0] if S.size else 0.0)
    else:
        tol = check_real("tol", tol, 0.0)
    rank = int(np.sum(S > tol))
    return U[:, rank:]  # v^T [H0 Hw] = 0, eqs. (19), (22)


def align_bases(bases, ref=None):
    """Rotate parity bases onto a common orientation (orthogonal Procrustes).

    Left null spaces from different local models are returned in arbitrary
    orientations, so their residuals cannot be blended as they are. Each basis ``V``
    is replaced by ``V Q`` with the orthogonal ``Q`` that brings it closest to the
    reference (``Q = U W^T`` from the SVD ``V^T V_ref = U S W^T``).

    Parameters
    ----------
    bases : sequence of array_like, each shape (p, q)
        Orthonormal bases of equal shape (``V^T V = I`` to :data:`ORTHONORMAL_TOL`).
    ref : int, optional
        Index of the reference basis (default: the middle one).

    Returns
    -------
    list of ndarray, each shape (p, q)

    Examples
    --------
    >>> V = np.eye(3)[:, :2]
    >>> out = align_bases([V, -V])
    >>> bool(np.allclose(out[0], out[1]))
    True
    """
    if isinstance(bases, np.ndarray) and bases.ndim == 3:  # a stack (N, p, q) is N bases
        bases = list(bases)
    bases = check_arrays("bases", bases, ndim=2)
    for i, b in enumerate(bases[1:], 1):  # one null-space dimension: bases[0] sets the shape
        check_shape(f"bases[{i}]", b, bases[0].shape, "the shape of bases[0]")
    for i, b in enumerate(bases):  # a zero or scaled basis has no rotation onto another
        err = float(np.abs(b.T @ b - np.eye(b.shape[1])).max(initial=0.0))  # q = 0: none
        if err > ORTHONORMAL_TOL:
            raise ValueError(f"bases[{i}] must have orthonormal columns (V^T V = I to "
                             f"{ORTHONORMAL_TOL:g}), off by {err:.3g}: a parity_basis() result")
    ref = len(bases) // 2 if ref is None else check_int("ref", ref, 0, len(bases) - 1)
    out = []
    for b in bases:
        u, _, wt = np.linalg.svd(b.T @ bases[ref])
        out.append(b @ (u @ wt))
    return out


@dataclass(frozen=True)
class Identifiability:
    """The paper's two constraints on window length and parity vectors.

    Attributes
    ----------
    null_dim : int
        Dimension ``q`` of the parity space. Constraint 1: ``q >= 1``, i.e.
        ``s + 1 > rank(H*)``.
    sensitivity : float
        Smallest singular value of the stacked ``V^T M`` relative to the largest of the
        stacked ``M``. Constraint 2: the fault signature is seen by the residual.
    condition_1, condition_2 : bool
        Whether the constraints hold.
    """

    null_dim: int
    sensitivity: float
    condition_1: bool
    condition_2: bool

    @property
    def ok(self):
        """Both constraints hold: the fault parameters can be estimated."""
        return self.condition_1 and self.condition_2


def check_identifiability(V, M, rtol=1e-6):
    """Check the identifiability constraints for parity basis ``V`` and fault signature ``M``.

    Parameters
    ----------
    V : array_like, shape (p, q)
        Parity basis (:func:`parity_basis`); ``q`` may be 0.
    M : array_like, shape (p, k) or (K, p, k)
        Fault signature in one window, or in each of ``K`` windows (the fault
        parameters must be seen over the set of windows).
    rtol : float
        Smallest relative sensitivity accepted, in (0, 1).

    Returns
    -------
    Identifiability

    Examples
    --------
    >>> V = parity_basis([[1.0, 1.0], [0.0, 1.0]], [1.0, 0.0], 3)
    >>> check_identifiability(V, np.ones((4, 1))).ok            # a constant: invisible
    False
    >>> check_identifiability(V, [[0.0], [0.0], [1.0], [1.0]]).ok  # a step in the window
    True
    """
    V = check_finite_array("V", V)
    if V.ndim != 2:
        raise ValueError(f"V must have shape (p, q), got {V.shape}")
    M = check_finite_array("M", M)
    given = M.shape
    if M.ndim == 2:
        M = M[None]
    if M.ndim != 3 or M.shape[1] != V.shape[0] or 0 in M.shape:
        raise ValueError(f"M must have shape ({V.shape[0]}, k) or (K, {V.shape[0]}, k), k >= 1 "
                         f"fault parameters, got {given}")
    rtol = check_real("rtol", rtol, 0.0, 1.0, lo_open=True, hi_open=True)
    q = V.shape[1]
    scale = np.linalg.norm(M.reshape(-1, M.shape[2]), 2)
    if q == 0 or scale == 0.0:
        return Identifiability(q, 0.0, q >= 1, False)
    G = np.einsum("pq,Kpk->Kqk", V, M).reshape(-1, M.shape[2])
    sens = float(np.linalg.svd(G, compute_uv=False)[-1] / scale) if G.shape[0] >= G.shape[1] else 0.0
    return Identifiability(q, sens, True, sens > rtol)


# ------------------------------------------------------------------ residuals


def blended_bases(weights, bases):
    """Membership-weighted parity bases ``W(k) = sum_l mu_l(k) V_l`` (paper eq. 25).

    Parameters
    ----------
    weights : array_like, shape (n, N)
        Memberships of each sample (:func:`~.fuzzy.memberships`): each >= 0, each row
        adding up to 1 (to 1e-9).
    bases : array_like, shape (N, m, p, q)
        Aligned parity bases of each local model and sensor.

    Returns
    -------
    ndarray, shape (n, m, p, q)

    Examples
    --------
    >>> b = np.stack([np.ones((1, 2, 1)), 3 * np.ones((1, 2, 1))])
    >>> blended_bases([[0.5, 0.5]], b)[0, 0, :, 0].tolist()
    [2.0, 2.0]
    """
    w = check_finite_array("weights", weights)
    if w.ndim != 2:
        raise ValueError(f"weights must have shape (n, N), got shape {w.shape}")
    # normalised memberships (eq. 13): other weights scaled the basis (its residuals, their
    # threshold) or flipped it without a word
    sums = w.sum(axis=1)
    if np.any(w < 0.0) or np.any(np.abs(sums - 1.0) > 1e-9):
        k = int(np.argmax(np.any(w < 0.0, axis=1) | (np.abs(sums - 1.0) > 1e-9)))
        raise ValueError(f"weights[{k}] must be memberships (each >= 0, adding up to 1), got "
                         f"{w[k].tolist()!r:.80}")
    b = check_shape("bases", bases, (w.shape[1], None, None, None), f"N = {w.shape[1]} columns of weights")
    return np.einsum("kl,ljpq->kjpq", w, b)


def parity_residuals(z, W):
    """Global parity residuals ``r_j(k) = W_j(k)^T Z_j(k)`` over sliding windows (eqs. 21, 25).

    Parameters
    ----------
    z : array_like, shape (n, m)
        Measurements ``rho - rho_I`` of each sensor, m.
    W : array_like, shape (n, m, s+1, q)
        Blended parity bases at each window end (:func:`blended_bases`).

    Returns
    -------
    ndarray, shape (n - s, m, q)
        Residual of the window ending at sample ``s + i`` in row ``i``, m.

    Examples
    --------
    >>> V = parity_basis([[1.0, 1.0], [0.0, 1.0]], [1.0, 0.0], 3)
    >>> W = np.broadcast_to(V, (6, 1, 4, 2))
    >>> z = np.array([0.0, 1.0, 2.0, 3.0, 4.0, 15.0])[:, None]   # a line, then a jump
    >>> np.linalg.norm(parity_residuals(z, W), axis=2).round(6).ravel().tolist()[:2]
    [0.0, 0.0]
    """
    z = check_finite_array("z", z)
    if z.ndim != 2:
        raise ValueError(f"z must have shape (n, m), got shape {z.shape}")
    W = check_shape("W", W, (*z.shape, None, None), "its samples and sensors: the shape of z")
    s = W.shape[2] - 1
    if s >= len(z):
        raise ValueError(f"the window (s + 1 = {s + 1}) must be shorter than z ({len(z)} samples)")
    win = np.lib.stride_tricks.sliding_window_view(z, s + 1, axis=0)  # (n-s, m, s+1)
    return np.einsum("kjpq,kjp->kjq", W[s:], win)


def residual_threshold(sigma, q, p_fa=1e-6):
    """Threshold ``r_t`` on ``||r_j||`` for a false-alarm probability per test (eq. 26).

    Under no fault ``r_j = V^T eps_j`` with ``V`` orthonormal, so
    ``||r_j||^2 / sigma^2 ~ chi^2_q``; ``r_t = sigma sqrt(chi2_q^{-1}(1 - p_fa))``. (The
    paper sets ``r_t`` "from experimental data and the system's reliability".)

    Parameters
    ----------
    sigma : float
        Pseudorange noise, m, in (0, 1e6].
    q : int
        Parity-space dimension, in [1, 1000].
    p_fa : float
        False-alarm probability per window and sensor, in (0, 0.5).

    Returns
    -------
    float
        Threshold, m.

    Examples
    --------
    >>> round(residual_threshold(1.0, 1, p_fa=0.05), 3)
    1.96
    """
    sigma = check_real("sigma", sigma, 0.0, 1e6, lo_open=True)
    q = check_int("q", q, 1, 1000)
    p_fa = check_real("p_fa", p_fa, 0.0, 0.5, lo_open=True, hi_open=True)
    return sigma * math.sqrt(chi2_isf(p_fa, q))
