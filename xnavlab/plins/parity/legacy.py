r"""Fault diagnosis of a PL/INS system with T-S fuzzy, fully decoupled parity equations.

A reconstruction of Jin, Song, Qiu & Wang (2011), whose equations were lost in
extraction; the standard forms used are those of Chow & Willsky (1984) for parity
relations over a data window, Gertler (1998) for structured ("fully decoupled")
residuals, Song & Zhang (2002, 2003) for the parity-plus-Kalman-filter fault
identification the paper builds on, and Takagi & Sugeno (1985) for the fuzzy model.

The pieces, with the paper's equation numbers where the surviving text cites them:

1. **T-S fuzzy model** (eqs. 12-14). Local linear models ``(A_l, B_l, C_l)`` of the
   PL/INS error system (:mod:`xnavlab.plins.ins`, :mod:`xnavlab.plins.pseudolites`) at operating
   points ``l = 1..N`` of the premise ``rho = [latitude, north velocity, north
   accelerometer output]``, blended with normalised products of triangular
   memberships ``mu_l(rho)``.
2. **Time-redundant measurement** of sensor ``j`` over the ``s + 1`` latest samples
   (eqs. 15-17, 20): ``Y_j(k) = H_0 x(k - s) + H_w W(k) + eps_j(k)`` with
   ``H_0 = [c_j; c_j A; ...; c_j A^s]`` and ``H_w`` the block-Toeplitz matrix of the
   Markov parameters ``c_j A^i B``.
3. **Fully decoupled parity vectors** (eqs. 18-22): the columns of ``V_j`` span the
   left null space of ``H* = [H_0 H_w]``, so ``r_j = V_j^T Z_j`` is decoupled from the
   state and the disturbance and, being built from sensor ``j`` alone, sensitive to
   that sensor only.
4. **Global residual** (eq. 25): ``r_j(k) = sum_l mu_l(k) r_lj(k)``; a fault of sensor
   ``j`` is declared when ``||r_j(k)|| > r_t`` (eq. 26).
5. **Fault identification** (eqs. 23-24, 27-28): with the fault of sensor ``j`` in the
   window written ``M_j(k) theta_j``, ``r_j(k) = V_j^T M_j(k) theta_j + V_j^T eps_j``; the
   parameters ``theta_j`` are a random walk estimated by a Kalman filter.

Two findings shape this implementation (the chapter explains both):

* *Exact* decoupling from the IMU noise leaves no parity space for a single
  pseudorange (every new sample brings new noise into the window), and an exact left
  null space of ``H_0`` annihilates polynomials of high degree, which costs most of the
  fault sensitivity. We therefore take the **numerical** left null space: the
  directions in which a typical (1-sigma) state or noise sample contributes less than
  ``tol`` metres to the window (``tol = 0.3 sigma`` by default). The paper's exact
  version is ``tol=None``.
* A fault that is **constant inside the window** (the paper's eq. 23, ``M = 1``) is
  *not* identifiable: ``1`` lies in the range of ``H_0`` because the pseudolite
  equivalent error (the receiver clock) enters every sample of every pseudorange
  alike, so ``V^T 1 = 0`` for every parity vector (constraint 2 fails for every
  window length). What the residual sees is the fault's *change* inside the window;
  we identify the fault from the windows that straddle its onset, with the onset
  located by a likelihood-ratio search (:func:`estimate_onset`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.stats import chi2 as _chi2

from xnavlab.core import faults as _faults
from xnavlab.core.validate import check_choice, check_finite_array, check_int, check_real, make_rng
from xnavlab.plins import ins as _ins
from xnavlab.plins import pseudolites as _pl

__all__ = [
    "PREMISES",
    "MODELS",
    "TYPICAL_STATE_STD",
    "premises",
    "operating_points",
    "triangular",
    "partition_memberships",
    "memberships",
    "LocalModel",
    "local_models",
    "stacked_matrices",
    "parity_basis",
    "align_bases",
    "Identifiability",
    "check_identifiability",
    "fault_signature",
    "blended_bases",
    "parity_residuals",
    "residual_threshold",
    "first_alarm",
    "estimate_onset",
    "rw_predict",
    "rw_update",
    "FaultIdentifier",
    "kf_identify",
    "Identification",
    "identify_fault",
    "Chi2Monitor",
    "chi2_monitor",
    "Diagnosis",
    "diagnose_flight",
    "compare_detectors",
    "plot_diagnosis",
]

#: Premise variables of the T-S model: latitude (deg), north velocity (m/s), north
#: accelerometer output (specific force, m/s^2).
PREMISES = ("lat_deg", "v_n", "f_n")

#: Fault models for identification: ``"bias"`` is constant inside the window (paper
#: eq. 23), ``"step"`` a step at an onset, ``"ramp"`` ``f = a t + b`` from an onset.
MODELS = ("bias", "step", "ramp")

#: Typical (1-sigma) size of the INS error state during the flight, used to weigh the
#: state directions when the numerical left null space is taken (our choice: tilt
#: 0.3 mrad, heading 3 mrad, velocity 1 m/s, position 100 m, clock 1 km).
TYPICAL_STATE_STD = np.array(
    [3e-4, 3e-4, 3e-3, 1.0, 1.0, 1.0, 100.0 / 6.36e6, 100.0 / 4.95e6, 100.0, 1000.0]
)


# --------------------------------------------------------------------------- T-S model
def premises(traj):
    """Premise variables ``[lat_deg, v_n, f_n]`` along a flight.

    Parameters
    ----------
    traj : xnavlab.plins.ins.Trajectory

    Returns
    -------
    ndarray, shape (n, 3)
        Latitude (deg), north velocity (m/s), north specific force (m/s^2).

    Examples
    --------
    >>> premises(_ins.paper_trajectory())[0].round(3).tolist()
    [39.0, 100.0, 0.5]
    """
    if not isinstance(traj, _ins.Trajectory):
        raise ValueError(f"traj must be a Trajectory, got {type(traj).__name__}")
    return np.column_stack([traj.lat_deg, traj.v_enu[:, 1], traj.f_enu[:, 1]])


def operating_points(traj, n_points=3):
    """Operating points of the T-S model: the premise at evenly spaced times of the flight.

    The paper (Fig. 1, lost) does not give its points; we take ``n_points`` samples of
    the flight at equal time spacing, start and end included.

    Parameters
    ----------
    traj : xnavlab.plins.ins.Trajectory
    n_points : int
        Number of rules ``N``, in [1, 50].

    Returns
    -------
    ndarray, shape (N, 3)
        ``[lat_deg, v_n, f_n]`` of each operating point.

    Examples
    --------
    >>> operating_points(_ins.paper_trajectory())[:, 1].tolist()
    [100.0, 150.0, 200.0]
    """
    n_points = check_int("n_points", n_points, 1, 50)
    rho = premises(traj)
    idx = np.round(np.linspace(0, len(rho) - 1, n_points)).astype(int)
    return rho[idx]


def triangular(x, left, center, right):
    """Triangular membership function with feet ``left``, ``right`` and peak ``center``.

    ``left == center`` (or ``center == right``) gives a shoulder: membership 1 on that
    side of the peak.

    Parameters
    ----------
    x : float or array_like
        Premise value.
    left, center, right : float
        ``left <= center <= right``.

    Returns
    -------
    ndarray
        Membership in [0, 1], same shape as ``x``.

    Examples
    --------
    >>> triangular([0.0, 0.5, 1.0, 1.5, 2.0], 0.0, 1.0, 2.0).tolist()
    [0.0, 0.5, 1.0, 0.5, 0.0]
    >>> triangular([-5.0, 1.5], 1.0, 1.0, 2.0).tolist()
    [1.0, 0.5]
    """
    x = check_finite_array("x", x)
    left = check_real("left", left)
    center = check_real("center", center, left)
    right = check_real("right", right, center)
    mu = np.ones_like(x)
    if center > left:
        mu = np.minimum(mu, (x - left) / (center - left))
    if right > center:
        mu = np.minimum(mu, (right - x) / (right - center))
    return np.clip(mu, 0.0, 1.0)


def partition_memberships(x, centers):
    """Memberships of ``x`` in the triangular partition with peaks at ``centers``.

    Each fuzzy set has its feet at the neighbouring centres; the two end sets are
    shoulders, so the memberships of any ``x`` add up to 1 (a Ruspini partition).

    Parameters
    ----------
    x : array_like, shape (n,)
        Premise values.
    centers : array_like, shape (m,)
        Strictly increasing peaks.

    Returns
    -------
    ndarray, shape (n, m)

    Examples
    --------
    >>> partition_memberships([0.0, 0.25, 3.0], [0.0, 1.0, 2.0]).tolist()
    [[1.0, 0.0, 0.0], [0.75, 0.25, 0.0], [0.0, 0.0, 1.0]]
    """
    x = np.atleast_1d(check_finite_array("x", x))
    c = np.atleast_1d(check_finite_array("centers", centers))
    if c.ndim != 1 or len(c) < 1 or np.any(np.diff(c) <= 0):
        raise ValueError("centers must be a non-empty, strictly increasing 1-D array")
    out = np.empty((len(x), len(c)))
    for i in range(len(c)):
        left = c[i - 1] if i > 0 else c[i]
        right = c[i + 1] if i < len(c) - 1 else c[i]
        out[:, i] = triangular(x, left, c[i], right)
    return out


def memberships(rho, points):
    """Normalised firing strengths ``mu_l`` of the T-S rules (paper eq. 13).

    Rule ``l`` fires with the product of the memberships of each premise variable in
    the set peaked at the rule's operating point (:func:`partition_memberships` over the
    distinct values of that variable); the strengths are normalised to add up to 1. A
    variable that has one value at every operating point (the north accelerometer
    output of the paper's constant-acceleration flight) has a single set and
    membership 1.

    Parameters
    ----------
    rho : array_like, shape (n, 3)
        Premise values ``[lat_deg, v_n, f_n]``.
    points : array_like, shape (N, 3)
        Operating points.

    Returns
    -------
    ndarray, shape (n, N)

    Raises
    ------
    ValueError
        If a premise falls outside every rule (all strengths zero).

    Examples
    --------
    >>> pts = np.array([[39.0, 100.0, 0.5], [39.2, 200.0, 0.5]])
    >>> memberships([[39.1, 150.0, 0.5]], pts).tolist()
    [[0.5, 0.5]]
    """
    rho = check_finite_array("rho", rho, shape=(3,))
    points = check_finite_array("points", points, shape=(3,))
    rho = np.atleast_2d(rho)
    if points.ndim != 2:
        raise ValueError(f"points must have shape (N, 3), got {points.shape}")
    w = np.ones((len(rho), len(points)))
    for i in range(3):
        centers = np.unique(points[:, i])
        mu = partition_memberships(rho[:, i], centers)
        w *= mu[:, np.searchsorted(centers, points[:, i])]
    total = w.sum(axis=1)
    if np.any(total <= 0):
        raise ValueError("rho has a premise outside every fuzzy set of the operating points")
    return w / total[:, None]


@dataclass(frozen=True)
class LocalModel:
    """A local linear PL/INS model ``x+ = A x + B w``, ``z = C x`` (paper eq. 12).

    Attributes
    ----------
    point : ndarray, shape (3,)
        Operating point ``[lat_deg, v_n, f_n]``.
    A : ndarray, shape (10, 10)
        Discrete state transition over one sample.
    B : ndarray, shape (10, 10)
        Noise input for unit-variance ``w`` (``B B^T = Q_d``).
    C : ndarray, shape (m, 10)
        Measurement matrix ``[0, E T, K]`` at the operating point.
    """

    point: np.ndarray
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray


def local_models(points, lon, h, sites, dt, q=None):
    """Local linear models at the operating points (paper eqs. 6-12).

    The velocity is ``[0, v_n, 0]`` and the specific force ``[0, f_n, 0] + (2 omega_ie +
    omega_en) x v - g^n`` (the north component of the Coriolis term vanishes for a
    northbound flight).

    Parameters
    ----------
    points : array_like, shape (N, 3)
        Operating points ``[lat_deg, v_n, f_n]``.
    lon : float
        Longitude, rad.
    h : float
        Height, m.
    sites : array_like, shape (m, 3)
        Pseudolite positions, ECEF, m.
    dt : float
        Sample interval, s.
    q : array_like, shape (7,), optional
        Noise PSDs (default :func:`xnavlab.plins.ins.imu_noise_psd()`).

    Returns
    -------
    list of LocalModel

    Examples
    --------
    >>> tr = _ins.paper_trajectory()
    >>> ms = local_models(operating_points(tr), tr.lon[0], tr.h[0], _pl.sites_ecef(), tr.dt)
    >>> len(ms), ms[0].A.shape, ms[0].C.shape
    (3, (10, 10), (4, 10))
    """
    points = check_finite_array("points", points, shape=(3,))
    if points.ndim != 2:
        raise ValueError(f"points must have shape (N, 3), got {points.shape}")
    q = _ins.imu_noise_psd() if q is None else check_finite_array("q", q, shape=(7,))
    G = _ins.noise_matrix()
    out = []
    for lat_deg, v_n, f_n in points:
        lat = math.radians(lat_deg)
        v = np.array([0.0, v_n, 0.0])
        w = 2.0 * _ins.omega_ie(lat) + _ins.omega_en(lat, h, v)
        f = np.array([0.0, f_n, _ins.normal_gravity(lat, h)]) + np.cross(w, v)
        A, Qd = _ins.discretize(_ins.error_matrix(lat, h, v, f), G, q, dt)
        vals, vecs = np.linalg.eigh(Qd)
        B = vecs * np.sqrt(np.clip(vals, 0.0, None))  # B B^T = Q_d
        C = _pl.measurement_matrix(lat, lon, h, sites)
        out.append(LocalModel(np.array([lat_deg, v_n, f_n]), A, B, C))
    return out


# ---------------------------------------------------------------------- parity space
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
    n = A.shape[0]
    if A.shape != (n, n):
        raise ValueError(f"A must be square, got shape {A.shape}")
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
        Orthonormal bases of equal shape.
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
    bases = [check_finite_array("bases", b) for b in bases]
    if not bases:
        raise ValueError("bases must not be empty")
    shape = bases[0].shape
    if any(b.shape != shape or b.ndim != 2 for b in bases):
        raise ValueError("bases must all have the same 2-D shape (the same null-space dimension)")
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
    if M.ndim == 2:
        M = M[None]
    if M.ndim != 3 or M.shape[1] != V.shape[0]:
        raise ValueError(f"M must have shape ({V.shape[0]}, k) or (K, {V.shape[0]}, k)")
    rtol = check_real("rtol", rtol, 0.0, 1.0, lo_open=True, hi_open=True)
    q = V.shape[1]
    scale = np.linalg.norm(M.reshape(-1, M.shape[2]), 2)
    if q == 0 or scale == 0.0:
        return Identifiability(q, 0.0, q >= 1, False)
    G = np.einsum("pq,Kpk->Kqk", V, M).reshape(-1, M.shape[2])
    sens = float(np.linalg.svd(G, compute_uv=False)[-1] / scale) if G.shape[0] >= G.shape[1] else 0.0
    return Identifiability(q, sens, True, sens > rtol)


def fault_signature(t_window, model, onset=0.0, time_origin="absolute"):
    """Fault signature ``M`` in a window: the fault is ``M @ theta`` (paper eq. 23).

    Built with :func:`xnavlab.core.faults.inject` (unit faults on zeros), so it has the
    same semantics as the injected faults: active for ``t >= onset``.

    Parameters
    ----------
    t_window : array_like, shape (p,)
        Sample times of the window, s.
    model : {"bias", "step", "ramp"}
        ``"bias"``: ``theta = [f]``, constant in the whole window (paper eq. 23, the
        onset is ignored). ``"step"``: ``theta = [f]`` from ``onset``. ``"ramp"``:
        ``theta = [a, b]``, ``f = a t + b`` from ``onset``.
    onset : float
        Fault onset, s.
    time_origin : {"absolute", "onset"}
        For ``"ramp"``: ``t`` in ``a t + b`` is the flight time (``"absolute"``) or the
        time since the onset (``"onset"``).

    Returns
    -------
    ndarray, shape (p, 1) or (p, 2)

    Examples
    --------
    >>> fault_signature([1.0, 2.0, 3.0], "step", onset=2.0)[:, 0].tolist()
    [0.0, 1.0, 1.0]
    >>> fault_signature([1.0, 2.0, 3.0], "ramp", onset=2.0).tolist()
    [[0.0, 0.0], [2.0, 1.0], [3.0, 1.0]]
    """
    t = check_finite_array("t_window", t_window)
    if t.ndim != 1:
        raise ValueError(f"t_window must have shape (p,), got {t.shape}")
    check_choice("model", model, MODELS)
    onset = check_real("onset", onset)
    check_choice("time_origin", time_origin, ("absolute", "onset"))
    if model == "bias":
        return np.ones((len(t), 1))
    zero = np.zeros(len(t))
    step = _faults.inject(t, zero, [_faults.Fault("unit", "step", 1.0, onset)], "unit")
    if model == "step":
        return step[:, None]
    ramp = _faults.inject(t, zero, [_faults.Fault("unit", "ramp", 1.0, onset)], "unit")
    if time_origin == "absolute":
        ramp = ramp + onset * step  # a t = a (t - onset) + a onset
    return np.column_stack([ramp, step])  # f = a t + b, the paper's ramp model


# ------------------------------------------------------------------------- residuals
def blended_bases(weights, bases):
    """Membership-weighted parity bases ``W(k) = sum_l mu_l(k) V_l`` (paper eq. 25).

    Parameters
    ----------
    weights : array_like, shape (n, N)
        Memberships of each sample (:func:`memberships`).
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
    b = check_finite_array("bases", bases)
    if w.ndim != 2 or b.ndim != 4 or w.shape[1] != b.shape[0]:
        raise ValueError("weights must have shape (n, N) and bases (N, m, p, q)")
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
    W = check_finite_array("W", W)
    if z.ndim != 2 or W.ndim != 4 or W.shape[:2] != z.shape:
        raise ValueError("z must have shape (n, m) and W shape (n, m, s+1, q)")
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
        Pseudorange noise, m, > 0.
    q : int
        Parity-space dimension, >= 1.
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
    sigma = check_real("sigma", sigma, 0.0, lo_open=True)
    q = check_int("q", q, 1)
    p_fa = check_real("p_fa", p_fa, 0.0, 0.5, lo_open=True, hi_open=True)
    return sigma * math.sqrt(_chi2.isf(p_fa, q))


def first_alarm(t, statistic, threshold, after=-math.inf):
    """Time of the first sample at or after ``after`` whose statistic exceeds the threshold.

    Parameters
    ----------
    t : array_like, shape (n,)
        Times, s.
    statistic : array_like, shape (n,)
        Test statistic.
    threshold : float
        Threshold.
    after : float
        Ignore alarms before this time, s.

    Returns
    -------
    float or None
        Alarm time, s; ``None`` if there is none.

    Examples
    --------
    >>> first_alarm([0.0, 1.0, 2.0], [0.1, 5.0, 5.0], 1.0)
    1.0
    >>> first_alarm([0.0, 1.0], [0.1, 0.2], 1.0) is None
    True
    """
    t = check_finite_array("t", t)
    st = check_finite_array("statistic", statistic)
    if t.shape != st.shape or t.ndim != 1:
        raise ValueError("t and statistic must have the same shape (n,)")
    threshold = check_real("threshold", threshold)
    idx = np.flatnonzero((st > threshold) & (t >= after))
    return float(t[idx[0]]) if idx.size else None


def estimate_onset(t, z_j, W_j, k_alarm, model="step", time_origin="absolute"):
    """Locate a fault onset by a generalised likelihood-ratio search.

    Every sample time of the window that raised the alarm is a candidate onset; for
    each, the fault parameters are fitted by least squares to the residuals of the
    windows that can contain it (``k_alarm - s`` to ``k_alarm + s``), and the candidate
    explaining the most residual energy wins.

    Parameters
    ----------
    t : array_like, shape (n,)
        Sample times, s.
    z_j : array_like, shape (n,)
        Measurements of sensor ``j``, m.
    W_j : array_like, shape (n, s+1, q)
        Blended parity bases of sensor ``j`` at each window end.
    k_alarm : int
        Index (into ``t``) of the last sample of the first alarmed window, >= s.
    model : {"step", "ramp"}
        Fault model (:func:`fault_signature`).
    time_origin : {"absolute", "onset"}
        For ``"ramp"``, see :func:`fault_signature`.

    Returns
    -------
    float
        Estimated onset, s (one of the sample times).

    Examples
    --------
    >>> V = parity_basis([[1.0, 1.0], [0.0, 1.0]], [1.0, 0.0], 3)
    >>> t = np.arange(12.0); z = np.where(t >= 6.0, 50.0, 0.0)
    >>> estimate_onset(t, z, np.broadcast_to(V, (12, 4, 2)), 6)
    6.0
    """
    t = check_finite_array("t", t)
    z_j = check_finite_array("z_j", z_j)
    W_j = check_finite_array("W_j", W_j)
    if t.ndim != 1 or z_j.shape != t.shape or W_j.ndim != 3 or W_j.shape[0] != len(t):
        raise ValueError("t and z_j must have shape (n,) and W_j shape (n, s+1, q)")
    check_choice("model", model, ("step", "ramp"))
    s = W_j.shape[1] - 1
    n = len(t)
    k_alarm = check_int("k_alarm", k_alarm, s, n - 1)
    ks = np.arange(max(s, k_alarm - s), min(n - 1, k_alarm + s) + 1)
    r = np.concatenate([W_j[k].T @ z_j[k - s:k + 1] for k in ks])
    best, best_score = None, -math.inf
    for tc in t[k_alarm - s:k_alarm + 1]:
        M = fault_signature(t, model, tc, time_origin)  # a function of time: slice windows
        G = np.vstack([W_j[k].T @ M[k - s:k + 1] for k in ks])
        theta, *_ = np.linalg.lstsq(G, r, rcond=None)
        score = float(np.sum((G @ theta) ** 2))
        if score > best_score + 1e-12:
            best, best_score = float(tc), score
    return best


# ------------------------------------------------------------------ identification KF
def rw_predict(theta, P, Q):
    """Kalman prediction for random-walk fault parameters (paper eq. 28).

    ``theta(k+1) = theta(k) + zeta(k)``, ``zeta ~ N(0, Q)``.

    Parameters
    ----------
    theta : array_like, shape (p,)
    P : array_like, shape (p, p)
    Q : array_like, shape (p, p)

    Returns
    -------
    theta, P : ndarray

    Examples
    --------
    >>> rw_predict([1.0], [[2.0]], [[0.5]])[1].tolist()
    [[2.5]]
    """
    theta = check_finite_array("theta", theta)
    P = check_finite_array("P", P)
    Q = check_finite_array("Q", Q)
    if P.shape != (len(theta), len(theta)) or Q.shape != P.shape:
        raise ValueError("P and Q must have shape (p, p) with p = len(theta)")
    return theta.copy(), P + Q  # P = P + Q, eq. (28)


def rw_update(theta, P, r, G, R):
    """Kalman update of the fault parameters from a parity residual (paper eq. 27).

    ``r = G theta + eta``, ``eta ~ N(0, R)``; Joseph-form covariance.

    Parameters
    ----------
    theta : array_like, shape (p,)
    P : array_like, shape (p, p)
    r : array_like, shape (q,)
        Residual, m.
    G : array_like, shape (q, p)
        Regressor ``V^T M``.
    R : array_like, shape (q, q)
        Residual noise covariance, m^2.

    Returns
    -------
    theta, P : ndarray

    Examples
    --------
    >>> th, P = rw_update([0.0], [[1.0]], [2.0], [[1.0]], [[1.0]])
    >>> th.tolist(), P.tolist()
    ([1.0], [[0.5]])
    """
    theta = check_finite_array("theta", theta)
    P = check_finite_array("P", P)
    r = check_finite_array("r", r)
    G = check_finite_array("G", G)
    R = check_finite_array("R", R)
    p, q = len(theta), len(r)
    if P.shape != (p, p) or G.shape != (q, p) or R.shape != (q, q):
        raise ValueError("shapes must be theta (p,), P (p, p), r (q,), G (q, p), R (q, q)")
    return _rw_update(theta, P, r, G, R)


def _rw_update(theta, P, r, G, R):
    S = G @ P @ G.T + R
    K = np.linalg.solve(S, G @ P).T  # K = P G^T S^-1
    theta = theta + K @ (r - G @ theta)  # eq. (27)
    IKG = np.eye(len(theta)) - K @ G
    P = IKG @ P @ IKG.T + K @ R @ K.T  # Joseph form
    return theta, 0.5 * (P + P.T)


class FaultIdentifier:
    """Thin stateful wrapper of :func:`rw_predict` and :func:`rw_update`.

    Parameters
    ----------
    theta0 : array_like, shape (p,)
        Initial parameters.
    P0 : array_like, shape (p, p)
        Initial covariance.
    Q : array_like, shape (p, p)
        Random-walk covariance per step.

    Examples
    --------
    >>> kf = FaultIdentifier([0.0], [[100.0]], [[0.0]])
    >>> for _ in range(50):
    ...     kf.step([3.0], [[1.0]], [[1.0]])
    >>> round(float(kf.theta[0]), 1)
    3.0
    """

    def __init__(self, theta0, P0, Q):
        self.theta = check_finite_array("theta0", theta0).astype(float)
        self.P = check_finite_array("P0", P0).astype(float)
        self.Q = check_finite_array("Q", Q).astype(float)
        p = len(self.theta)
        if self.P.shape != (p, p) or self.Q.shape != (p, p):
            raise ValueError("P0 and Q must have shape (p, p) with p = len(theta0)")

    def step(self, r, G, R):
        """Predict then update with residual ``r`` and regressor ``G``."""
        self.theta, self.P = rw_predict(self.theta, self.P, self.Q)
        self.theta, self.P = rw_update(self.theta, self.P, r, G, R)


def kf_identify(r, G, R, Q, theta0=None, P0=None):
    """Run the random-walk Kalman filter over a sequence of residuals (eqs. 27-28).

    Parameters
    ----------
    r : array_like, shape (K, q)
        Residuals, m.
    G : array_like, shape (K, q, p)
        Regressors.
    R : float or array_like, shape (q, q)
        Residual noise covariance (a float is ``R I``), m^2.
    Q : float or array_like, shape (p, p)
        Random-walk covariance per step (a float is ``Q I``).
    theta0 : array_like, shape (p,), optional
        Initial parameters (default zeros).
    P0 : array_like, shape (p, p), optional
        Initial covariance (default ``1e8 I``: uninformative).

    Returns
    -------
    theta : ndarray, shape (K, p)
        Estimate after each residual.
    P : ndarray, shape (K, p, p)
        Its covariance.

    Examples
    --------
    >>> th, P = kf_identify(np.full((20, 1), 4.0), np.ones((20, 1, 1)), 1.0, 0.0)
    >>> round(float(th[-1, 0]), 3), bool(P[-1, 0, 0] < 0.06)
    (4.0, True)
    """
    r = check_finite_array("r", r)
    G = check_finite_array("G", G)
    if r.ndim != 2 or G.ndim != 3 or G.shape[:2] != r.shape:
        raise ValueError("r must have shape (K, q) and G shape (K, q, p)")
    K, q = r.shape
    p = G.shape[2]
    if np.ndim(R) == 0:
        R = check_real("R", R, 0.0, lo_open=True) * np.eye(q)
    else:
        R = check_finite_array("R", R, shape=(q, q))
    if np.ndim(Q) == 0:
        Q = check_real("Q", Q, 0.0) * np.eye(p)
    else:
        Q = check_finite_array("Q", Q, shape=(p, p))
    theta = np.zeros(p) if theta0 is None else check_finite_array("theta0", theta0, shape=(p,))
    P = 1e8 * np.eye(p) if P0 is None else check_finite_array("P0", P0, shape=(p, p))
    ths = np.empty((K, p))
    Ps = np.empty((K, p, p))
    for k in range(K):
        P = P + Q  # eq. (28)
        theta, P = _rw_update(theta, P, r[k], G[k], R)
        ths[k], Ps[k] = theta, P
    return ths, Ps


@dataclass(frozen=True)
class Identification:
    """Fault parameters of one sensor identified by the random-walk Kalman filter.

    Attributes
    ----------
    sensor : int
        Pseudolite index (0-based).
    model : str
        Fault model (:data:`MODELS`).
    names : tuple of str
        Parameter names (``("f",)`` or ``("a", "b")``).
    onset : float
        Onset used, s.
    t : ndarray, shape (K,)
        End time of each window used, s.
    theta : ndarray, shape (K, p)
        Estimate after each window (m; m/s for a slope).
    P : ndarray, shape (K, p, p)
        Covariance of the estimate.
    """

    sensor: int
    model: str
    names: tuple
    onset: float
    t: np.ndarray
    theta: np.ndarray
    P: np.ndarray

    @property
    def final(self):
        """The settled estimate (after the last window), shape (p,)."""
        return self.theta[-1]

    @property
    def std(self):
        """1-sigma of the settled estimate according to the filter, shape (p,)."""
        return np.sqrt(np.diag(self.P[-1]))


def identify_fault(t, z_j, W_j, onset, model="step", sigma=_pl.DEFAULT_SIGMA,
                   time_origin="absolute", q_rw=1e-6, sensor=0):
    """Identify the parameters of a fault of one sensor from its parity residuals.

    Runs :func:`kf_identify` over every window that ends at or after the onset, with
    regressor ``G_k = W_k^T M_k`` (:func:`fault_signature`) and residual noise
    ``sigma^2 I``. The windows after the onset has left them carry no information
    (``G_k = 0`` up to leakage: the estimate is held, "settled").

    Parameters
    ----------
    t : array_like, shape (n,)
        Sample times, s.
    z_j : array_like, shape (n,)
        Measurements of the sensor, m.
    W_j : array_like, shape (n, s+1, q)
        Blended parity bases of the sensor.
    onset : float
        Fault onset, s (e.g. from :func:`estimate_onset`).
    model : {"bias", "step", "ramp"}
        Fault model.
    sigma : float
        Pseudorange noise, m, > 0.
    time_origin : {"absolute", "onset"}
        For ``"ramp"`` (:func:`fault_signature`).
    q_rw : float
        Random-walk variance per step of each parameter (eq. 28), >= 0.
    sensor : int
        Sensor index, recorded in the result.

    Returns
    -------
    Identification

    Examples
    --------
    >>> V = parity_basis([[1.0, 1.0], [0.0, 1.0]], [1.0, 0.0], 3)
    >>> t = np.arange(30.0); z = np.where(t >= 10.0, 50.0, 0.0)
    >>> idn = identify_fault(t, z, np.broadcast_to(V, (30, 4, 2)), 10.0, sigma=1.0)
    >>> round(float(idn.final[0]), 3)
    50.0
    """
    t = check_finite_array("t", t)
    z_j = check_finite_array("z_j", z_j)
    W_j = check_finite_array("W_j", W_j)
    if t.ndim != 1 or z_j.shape != t.shape or W_j.ndim != 3 or W_j.shape[0] != len(t):
        raise ValueError("t and z_j must have shape (n,) and W_j shape (n, s+1, q)")
    onset = check_real("onset", onset)
    check_choice("model", model, MODELS)
    sigma = check_real("sigma", sigma, 0.0, lo_open=True)
    q_rw = check_real("q_rw", q_rw, 0.0)
    s = W_j.shape[1] - 1
    ks = np.arange(s, len(t))
    if model != "bias":
        ks = ks[t[ks] >= onset]
    if ks.size == 0:
        raise ValueError(f"onset must be at or before the last sample ({t[-1]:g} s), got {onset:g}")
    win = np.lib.stride_tricks.sliding_window_view(z_j, s + 1)[ks - s]  # (K, s+1)
    r = np.einsum("kpq,kp->kq", W_j[ks], win)  # eq. (24)
    M = fault_signature(t, model, onset, time_origin)  # (n, p), a function of time
    Mw = np.lib.stride_tricks.sliding_window_view(M, s + 1, axis=0)[ks - s]  # (K, p, s+1)
    G = np.einsum("kiq,kpi->kqp", W_j[ks], Mw)
    p = G.shape[2]
    theta, P = kf_identify(r, G, sigma**2, q_rw, P0=1e8 * np.eye(p))
    names = ("a", "b") if model == "ramp" else ("f",)
    return Identification(sensor, model, names, onset, t[ks], theta, P)


# --------------------------------------------------------- chi-square comparison
@dataclass(frozen=True)
class Chi2Monitor:
    """Residual chi-square test of a PL/INS Kalman filter (Brumback & Srinath 1987).

    Attributes
    ----------
    t : ndarray, shape (n,)
        Time, s.
    statistic : ndarray, shape (n,)
        ``nu^T S^{-1} nu`` of the innovation ``nu`` with covariance ``S``.
    threshold : float
        ``chi2_m^{-1}(1 - p_fa)``.
    x : ndarray, shape (n, 10)
        Filtered error state.
    """

    t: np.ndarray
    statistic: np.ndarray
    threshold: float
    x: np.ndarray

    def first_alarm(self, after=-math.inf):
        """Time of the first alarm at or after ``after``, s, or ``None``."""
        return first_alarm(self.t, self.statistic, self.threshold, after)


def chi2_monitor(data, transitions, sites=None, x0_std=None, p_fa=1e-6):
    """Kalman filter of the PL/INS error state with a residual chi-square test.

    The comparison detector of "Beyond the paper": a 10-state linear Kalman filter on
    ``z = rho - rho_I`` with ``H`` linearised at the INS position, and the normalised
    innovation squared ``nu^T S^-1 nu ~ chi^2_m`` tested every sample. It detects but
    does not isolate, and after a fault it adapts (no exclusion).

    Parameters
    ----------
    data : xnavlab.plins.pseudolites.PseudorangeData
        Simulated measurements.
    transitions : tuple of ndarray
        ``(A, Qd)`` of the flight (:func:`xnavlab.plins.ins.error_transitions`).
    sites : array_like, shape (m, 3), optional
        Pseudolite positions, ECEF (default :func:`xnavlab.plins.pseudolites.sites_ecef()`).
    x0_std : array_like, shape (10,), optional
        Initial 1-sigma (default :data:`xnavlab.plins.ins.DEFAULT_INITIAL_STD`).
    p_fa : float
        False-alarm probability per sample, in (0, 0.5).

    Returns
    -------
    Chi2Monitor

    Examples
    --------
    >>> tr = _ins.paper_trajectory(duration=30.0)
    >>> tx = _ins.error_transitions(tr)
    >>> d = _pl.simulate_pseudoranges(tr, _ins.simulate_errors(tr, rng=0, transitions=tx))
    >>> mon = chi2_monitor(d, tx)
    >>> mon.first_alarm() is None
    True
    """
    if not isinstance(data, _pl.PseudorangeData):
        raise ValueError(f"data must be a PseudorangeData, got {type(data).__name__}")
    A, Qd = transitions
    n, m = data.z.shape
    if np.shape(A) != (n - 1, 10, 10) or np.shape(Qd) != (n - 1, 10, 10):
        raise ValueError(f"transitions must be two arrays of shape ({n - 1}, 10, 10)")
    sites = _pl.sites_ecef() if sites is None else check_finite_array("sites", sites, shape=(3,))
    x0_std = _ins.DEFAULT_INITIAL_STD if x0_std is None else \
        check_finite_array("x0_std", x0_std, shape=(10,))
    p_fa = check_real("p_fa", p_fa, 0.0, 0.5, lo_open=True, hi_open=True)
    thr = float(_chi2.isf(p_fa, m))
    R = max(data.sigma, 1e-3) ** 2 * np.eye(m)
    lat, lon, h = _pl.ecef_to_geodetic(data.r_ins)
    x = np.zeros(10)
    P = np.diag(x0_std**2)
    stat = np.empty(n)
    xs = np.empty((n, 10))
    for k in range(n):
        if k > 0:
            x = A[k - 1] @ x  # x = A x
            P = A[k - 1] @ P @ A[k - 1].T + Qd[k - 1]  # P = A P A^T + Q
        H = _pl.measurement_matrix(lat[k], lon[k], h[k], sites)
        nu = data.z[k] - H @ x
        S = H @ P @ H.T + R
        stat[k] = nu @ np.linalg.solve(S, nu)  # chi-square statistic
        K = np.linalg.solve(S, H @ P).T
        x = x + K @ nu
        IKH = np.eye(10) - K @ H
        P = IKH @ P @ IKH.T + K @ R @ K.T
        xs[k] = x
    return Chi2Monitor(data.t.copy(), stat, thr, xs)


# ------------------------------------------------------------------ the whole flight
@dataclass
class Diagnosis:
    """Everything :func:`diagnose_flight` computed, for plots and checks.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Sample times, s.
    z : ndarray, shape (n, m)
        Measurements ``rho - rho_I``, m.
    fault : ndarray, shape (n, m)
        Injected faults, m.
    t_res : ndarray, shape (n - s,)
        Window end times, s.
    residual : ndarray, shape (n - s, m, q)
        Global parity residuals, m.
    statistic : ndarray, shape (n - s, m)
        ``||r_j||``, m.
    threshold : float
        ``r_t``, m.
    detection : list of (float or None)
        First alarm time of each sensor, s.
    onset : list of (float or None)
        Estimated onset of each alarmed sensor, s.
    identification : dict of int to Identification
        Identified faults of the alarmed sensors.
    s : int
        Window length minus one.
    null_dim : int
        Parity-space dimension ``q``.
    sigma : float
        Pseudorange noise, m.
    weights : ndarray, shape (n, N)
        Memberships of the operating points.
    points : ndarray, shape (N, 3)
        Operating points.
    chi2 : Chi2Monitor or None
        The comparison detector (when requested).
    """

    t: np.ndarray
    z: np.ndarray
    fault: np.ndarray
    t_res: np.ndarray
    residual: np.ndarray
    statistic: np.ndarray
    threshold: float
    detection: list
    onset: list
    identification: dict
    s: int
    null_dim: int
    sigma: float
    weights: np.ndarray
    points: np.ndarray
    chi2: Chi2Monitor | None = None


_FLIGHT_CACHE: dict = {}


def _flight(dt, duration):
    key = (dt, duration)
    if key not in _FLIGHT_CACHE:
        traj = _ins.paper_trajectory(dt=dt, duration=duration)
        _FLIGHT_CACHE.clear()
        _FLIGHT_CACHE[key] = (traj, _ins.error_transitions(traj))
    return _FLIGHT_CACHE[key]


_DESIGN_CACHE: dict = {}


def _design(traj, sites, s, tol, n_points):
    """T-S parity design of a flight: operating points, memberships, blended bases."""
    key = (len(traj), traj.dt, float(traj.lat[-1]), sites.tobytes(), s, tol, n_points)
    if key in _DESIGN_CACHE:
        return _DESIGN_CACHE[key]
    points = operating_points(traj, n_points)
    models = local_models(points, traj.lon[0], traj.h[0], sites, traj.dt)
    bases = []
    for j in range(len(sites)):
        Vj = [parity_basis(lm.A, lm.C[j], s, B=lm.B, state_std=TYPICAL_STATE_STD, tol=tol)
              for lm in models]
        dims = {v.shape[1] for v in Vj}
        if len(dims) != 1:
            raise ValueError(f"the local parity spaces of sensor {j} differ in dimension "
                             f"{sorted(dims)}; change leak_tol or n_points")
        bases.append(align_bases(Vj))
    q = bases[0][0].shape[1]
    if q == 0 or any(b[0].shape[1] != q for b in bases):
        raise ValueError(f"s = {s} leaves no common parity space (constraint 1); increase s")
    stacked = np.stack([np.stack([bases[j][l] for j in range(len(sites))])
                        for l in range(len(models))])
    weights = memberships(premises(traj), points)
    W = blended_bases(weights, stacked)  # (n, m, s+1, q)
    if len(_DESIGN_CACHE) > 16:
        _DESIGN_CACHE.clear()
    _DESIGN_CACHE[key] = (points, weights, W, q)
    return _DESIGN_CACHE[key]


def diagnose_flight(faults=(), *, model="step", s=11, threshold=None, sigma=_pl.DEFAULT_SIGMA,
                    p_fa=1e-6, leak_tol=0.3, n_points=3, time_origin="absolute", seed=0,
                    dt=1.0, duration=200.0, sites_deg=None, q_rw=1e-6, with_chi2=False):
    """Simulate the paper's flight with pseudorange faults and diagnose it.

    A pure function of its arguments (seeded): the chapter's slider calls it.

    Steps: trajectory and true INS errors (:mod:`xnavlab.plins.ins`); pseudoranges with
    ``faults`` injected (:mod:`xnavlab.plins.pseudolites`); T-S local models at ``n_points``
    operating points; single-sensor parity bases (numerical left null space with
    ``tol = leak_tol * sigma``), aligned and blended with the memberships; global
    residuals, threshold and alarms; onset search and Kalman identification for each
    alarmed sensor; optionally the chi-square comparison detector.

    Parameters
    ----------
    faults : sequence of xnavlab.core.faults.Fault
        Faults of sensor ``"pseudorange"`` (component = pseudolite index).
    model : {"step", "ramp"}
        Fault model used to identify alarmed sensors.
    s : int
        Window length minus one, in [2, 60] (paper: 11).
    threshold : float, optional
        ``r_t`` in metres (default :func:`residual_threshold` at ``p_fa``).
    sigma : float
        Pseudorange noise, m, > 0 (default 2 m, see :mod:`xnavlab.plins.pseudolites`).
    p_fa : float
        False-alarm probability per window and sensor for the default threshold.
    leak_tol : float
        Largest contribution of a typical state or noise left in the residual, in
        units of ``sigma``, > 0 (sets the numerical left null space).
    n_points : int
        Number of T-S operating points.
    time_origin : {"absolute", "onset"}
        Reading of ``t`` in a ramp ``a t + b`` (:func:`fault_signature`).
    seed : int or numpy.random.Generator
        Seed of INS errors and pseudorange noise.
    dt, duration : float
        Sample interval and flight time, s.
    sites_deg : array_like, shape (m, 3), optional
        Pseudolite sites ``[lat_deg, lon_deg, h]`` (default
        :data:`xnavlab.plins.pseudolites.DEFAULT_SITES_DEG`).
    q_rw : float
        Random-walk variance of the fault parameters per step.
    with_chi2 : bool
        Also run the chi-square comparison detector (:func:`chi2_monitor`).

    Returns
    -------
    Diagnosis

    Examples
    --------
    >>> from xnavlab.core.faults import Fault
    >>> d = diagnose_flight([Fault("pseudorange", "step", 300.0, 50.0, component=0)])
    >>> d.detection[0], d.detection[1], round(float(d.identification[0].final[0]))
    (50.0, None, 300)
    """
    check_choice("model", model, ("step", "ramp"))
    s = check_int("s", s, 2, 60)
    sigma = check_real("sigma", sigma, 0.0, lo_open=True)
    leak_tol = check_real("leak_tol", leak_tol, 0.0, lo_open=True)
    check_choice("time_origin", time_origin, ("absolute", "onset"))
    dt = check_real("dt", dt, 0.0, 10.0, lo_open=True)
    duration = check_real("duration", duration, 0.0, 1e4, lo_open=True)
    if duration / dt < s + 2:
        raise ValueError(f"duration must cover more than s + 2 = {s + 2} samples")
    faults = list(faults)
    for f in faults:
        if not isinstance(f, _faults.Fault):
            raise ValueError(f"faults must hold xnavlab.core.faults.Fault objects, got {f!r}")
    rng = make_rng(seed)
    traj, trans = _flight(dt, duration)
    sites = _pl.sites_ecef(sites_deg)
    x_err = _ins.simulate_errors(traj, rng=rng, transitions=trans)
    data = _pl.simulate_pseudoranges(traj, x_err, sites, sigma=sigma, faults=faults, rng=rng)
    m = data.z.shape[1]
    tol = leak_tol * sigma
    points, weights, W, q = _design(traj, sites, s, tol, n_points)
    r = parity_residuals(data.z, W)
    stat = np.linalg.norm(r, axis=2)
    thr = residual_threshold(sigma, q, p_fa) if threshold is None else \
        check_real("threshold", threshold, 0.0, lo_open=True)
    t_res = traj.t[s:]
    detection, onsets, ident = [], [], {}
    for j in range(m):
        ta = first_alarm(t_res, stat[:, j], thr)
        detection.append(ta)
        if ta is None:
            onsets.append(None)
            continue
        k_alarm = int(np.flatnonzero(traj.t == ta)[0])
        onset = estimate_onset(traj.t, data.z[:, j], W[:, j], k_alarm, model, time_origin)
        onsets.append(onset)
        ident[j] = identify_fault(traj.t, data.z[:, j], W[:, j], onset, model, sigma,
                                  time_origin, q_rw, sensor=j)
    chi = chi2_monitor(data, trans, sites, p_fa=p_fa) if with_chi2 else None
    return Diagnosis(
        t=traj.t.copy(), z=data.z, fault=data.fault, t_res=t_res, residual=r, statistic=stat,
        threshold=thr, detection=detection, onset=onsets, identification=ident, s=s,
        null_dim=q, sigma=sigma, weights=weights, points=points, chi2=chi,
    )


def compare_detectors(kind, sizes, *, onset=None, sensor=0, n_runs=5, seed=0, **kwargs):
    """Detection rate and delay of the parity test and the chi-square test, by fault size.

    For each size a fault of ``kind`` is put on pseudorange ``sensor`` and the flight of
    :func:`diagnose_flight` is simulated ``n_runs`` times (seeds ``seed, seed+1, ...``).

    Parameters
    ----------
    kind : {"step", "ramp"}
        Fault kind (a ramp starts from zero at the onset).
    sizes : sequence of float
        Step sizes (m) or ramp slopes (m/s).
    onset : float, optional
        Onset, s (default 50 s for a step, 30 s for a ramp, as in the paper).
    sensor : int
        Faulty pseudorange, 0-based.
    n_runs : int
        Runs per size, in [1, 1000].
    seed : int
        First seed.
    **kwargs
        Passed to :func:`diagnose_flight` (``sigma``, ``s``, ``threshold``, ``p_fa``...).

    Returns
    -------
    list of dict
        One row per size: ``size``, ``parity_rate`` and ``chi2_rate`` (fraction of runs
        with an alarm at or after the onset), ``parity_delay`` and ``chi2_delay`` (median
        delay of those alarms, s, or ``None``), ``isolated`` (fraction of runs in which
        the parity test alarmed on the faulty sensor only; the chi-square test cannot
        isolate).

    Examples
    --------
    >>> row, = compare_detectors("step", [100.0], n_runs=1)
    >>> row["parity_delay"], row["chi2_delay"], row["isolated"]
    (0.0, 0.0, 1.0)
    """
    check_choice("kind", kind, ("step", "ramp"))
    sizes = np.atleast_1d(check_finite_array("sizes", sizes))
    onset = (50.0 if kind == "step" else 30.0) if onset is None else check_real("onset", onset)
    sensor = check_int("sensor", sensor, 0)
    n_runs = check_int("n_runs", n_runs, 1, 1000)
    seed = check_int("seed", seed, 0)
    rows = []
    for size in sizes:
        fault = _faults.Fault(_pl.SENSOR, kind, float(size), onset, component=sensor)
        pd, cd, iso = [], [], 0
        for i in range(n_runs):
            d = diagnose_flight([fault], seed=seed + i, with_chi2=True, **kwargs)
            if sensor >= len(d.detection):
                raise ValueError(f"sensor must be in [0, {len(d.detection) - 1}], got {sensor}")
            ta = first_alarm(d.t_res, d.statistic[:, sensor], d.threshold, after=onset)
            tc = d.chi2.first_alarm(after=onset)
            if ta is not None:
                pd.append(ta - onset)
                others = [first_alarm(d.t_res, d.statistic[:, j], d.threshold)
                          for j in range(len(d.detection)) if j != sensor]
                iso += all(o is None for o in others)
            if tc is not None:
                cd.append(tc - onset)
        rows.append({
            "size": float(size),
            "parity_rate": len(pd) / n_runs,
            "parity_delay": float(np.median(pd)) if pd else None,
            "chi2_rate": len(cd) / n_runs,
            "chi2_delay": float(np.median(cd)) if cd else None,
            "isolated": iso / n_runs,
        })
    return rows


def plot_diagnosis(diag, axes=None):
    """Plot the residual norms with the threshold, and the identified fault parameters.

    Parameters
    ----------
    diag : Diagnosis
        From :func:`diagnose_flight`.
    axes : sequence of 2 matplotlib Axes, optional
        Where to draw (a new figure when omitted).

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> fig = plot_diagnosis(diagnose_flight(duration=40.0))
    >>> len(fig.axes)
    2
    """
    if not isinstance(diag, Diagnosis):
        raise ValueError(f"diag must be a Diagnosis, got {type(diag).__name__}")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FuncFormatter, LogLocator

    if axes is None:
        fig, axes = plt.subplots(1, 2, figsize=(10, 3.6), constrained_layout=True)
    else:
        fig = axes[0].figure
    ax0, ax1 = axes
    for j in range(diag.statistic.shape[1]):
        ax0.semilogy(diag.t_res, np.maximum(diag.statistic[:, j], 1e-3), label=f"PR{j + 1}")
    ax0.axhline(diag.threshold, color="k", ls="--", lw=1, label="$r_t$")
    ax0.yaxis.set_major_locator(LogLocator(base=10.0, subs=(1.0, 2.0, 5.0), numticks=15))
    ax0.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    ax0.yaxis.set_minor_formatter(FuncFormatter(lambda v, _: ""))
    ax0.set_xlabel("time (s)")
    ax0.set_ylabel(r"$\|r_j\|$ (m)")
    ax0.legend(fontsize=8, ncol=2)
    for j, idn in diag.identification.items():
        for i, name in enumerate(idn.names):
            ax1.plot(idn.t, idn.theta[:, i], label=f"PR{j + 1} {name}")
    for j in range(diag.fault.shape[1]):
        if np.any(diag.fault[:, j]):
            ax1.plot(diag.t, diag.fault[:, j], color="0.5", lw=0.8, ls=":")
    ax1.set_xlabel("time (s)")
    ax1.set_ylabel("estimate (m, m/s)")
    if diag.identification:
        ax1.legend(fontsize=8)
    return fig
