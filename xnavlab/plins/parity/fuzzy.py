"""The T-S fuzzy model of the PL/INS error system (paper eqs. 12-14).

Local linear models ``(A_l, B_l, C_l)`` of the pseudolite/INS error system
(:mod:`xnavlab.plins.ins`, :mod:`xnavlab.plins.pseudolites`) at operating points
``l = 1..N`` of the premise ``rho = [latitude, north velocity, north accelerometer
output]`` (:data:`PREMISES`), blended with normalised products of triangular memberships
``mu_l(rho)`` (Takagi & Sugeno 1985). The paper's Fig. 1 (the points and sets) was lost;
our choices are stated in :func:`operating_points` and :func:`memberships`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from xnavlab.core.validate import check_finite_array, check_int, check_real, check_shape
from xnavlab.plins import ins as _ins
from xnavlab.plins import pseudolites as _pl
from xnavlab.plins._checks import check_angle, check_sites

__all__ = [
    "PREMISES",
    "premises",
    "operating_points",
    "triangular",
    "partition_memberships",
    "memberships",
    "LocalModel",
    "local_models",
]

#: Premise variables of the T-S model: latitude (deg), north velocity (m/s), north
#: accelerometer output (specific force, m/s^2).
PREMISES = ("lat_deg", "v_n", "f_n")


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
    # A side narrower than its distances to x (a subnormal width) has a slope beyond the floats:
    # its quotient is +-inf, which the clip below makes the exact limit 1 or 0 (a shoulder).
    if center > left:
        rise = x - left
        with np.errstate(over="ignore"):
            mu = np.minimum(mu, rise / (center - left))
    if right > center:
        fall = right - x
        with np.errstate(over="ignore"):
            mu = np.minimum(mu, fall / (right - center))
    return np.clip(mu, 0.0, 1.0)


def partition_memberships(x, centers):
    """Memberships of ``x`` in the triangular partition with peaks at ``centers``.

    Each fuzzy set has its feet at the neighbouring centres; the two end sets are
    shoulders, so the memberships of any ``x`` add up to 1 (a Ruspini partition).

    Parameters
    ----------
    x : array_like, shape (n,)
        Premise values, n >= 1.
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
    if x.ndim != 1 or x.size == 0:  # a row of premises was numpy's broadcast error
        raise ValueError(f"x must have shape (n,) with n >= 1 (one premise value a sample), got "
                         f"shape {x.shape}")
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
        Premise values ``[lat_deg, v_n, f_n]``, n >= 1.
    points : array_like, shape (N, 3)
        Operating points, N >= 1.

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
    if rho.ndim != 2 or len(rho) < 1:  # a stack of premises was numpy's broadcast error
        raise ValueError(f"rho must have shape (n, 3) with n >= 1 (one premise a sample), got "
                         f"shape {rho.shape}")
    points = _check_points(points)  # no point was refused as the inner partition's centers
    w = np.ones((len(rho), len(points)))
    for i in range(3):
        centers = np.unique(points[:, i])
        mu = partition_memberships(rho[:, i], centers)
        w *= mu[:, np.searchsorted(centers, points[:, i])]
    total = w.sum(axis=1)
    if np.any(total <= 0):
        raise ValueError("rho has a premise outside every fuzzy set of the operating points")
    return w / total[:, None]


def _check_points(points):
    """Operating points as an (N, 3) array, N >= 1 (one T-S rule each), else one ValueError."""
    points = check_finite_array("points", points, shape=(3,))
    if points.ndim != 2 or len(points) < 1:
        raise ValueError(f"points must have shape (N, 3) with N >= 1 (one operating point a "
                         f"rule), got shape {points.shape}")
    return points


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
        Operating points ``[lat_deg, v_n, f_n]``, N >= 1.
    lon : float
        Longitude, rad, in [-2 pi, 2 pi].
    h : float
        Height, m, in [-1e4, 1e5] (as :func:`xnavlab.plins.ins.error_matrix`).
    sites : array_like, shape (m, 3)
        Pseudolite positions, ECEF, m; m >= 1, at least 1 m apart.
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
    points = _check_points(points)  # none was an empty list of models
    sites = check_sites(sites)  # checked up front (no site: models without pseudolites)
    for l, lat_deg in enumerate(points[:, 0]):  # degrees here: error_matrix names its lat in rad
        if abs(lat_deg) > 89.0:
            raise ValueError(f"points[{l}] must have a latitude in [-89, 89] deg (the ENU error "
                             f"model is singular at the poles), got {lat_deg:g}")
    lon = check_angle("lon", lon, "lon")  # checked here: measurement_matrix would name r for a list
    h = check_real("h", h, -1e4, 1e5)  # as the error model's (xnavlab.plins.ins.error_matrix)
    q = _ins.imu_noise_psd() if q is None else check_shape("q", q, (7,))
    dt = check_real("dt", dt, 0.0, 86400.0, lo_open=True)  # as discretize's
    G = _ins.noise_matrix()
    out = []
    for l, (lat_deg, v_n, f_n) in enumerate(points):
        lat = math.radians(lat_deg)
        v = np.array([0.0, v_n, 0.0])
        w = 2.0 * _ins.omega_ie(lat) + _ins.omega_en(lat, h, v)
        f = np.array([0.0, f_n, _ins.normal_gravity(lat, h)]) + np.cross(w, v)
        F = _ins.error_matrix(lat, h, v, f)
        growth = np.abs(F).sum(axis=1).max() * dt  # discretize's bound, named as the point's
        if growth > 50.0:
            raise ValueError(f"points[{l}] must give an error model with ||F||_inf dt <= 50 "
                             f"(discretize's bound), got {growth:.6g} at dt = {dt:g} s: a smaller "
                             f"v_n or f_n, or a shorter dt")
        A, Qd = _ins.discretize(F, G, q, dt)
        vals, vecs = np.linalg.eigh(Qd)
        B = vecs * np.sqrt(np.clip(vals, 0.0, None))  # B B^T = Q_d
        C = _pl.measurement_matrix(lat, lon, h, sites)
        out.append(LocalModel(np.array([lat_deg, v_n, f_n]), A, B, C))
    return out
