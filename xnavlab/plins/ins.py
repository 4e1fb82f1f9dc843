r"""Inertial navigation in the local-level ENU frame: the 9-state error model plus one pseudolite state.

The navigation frame is East-North-Up (ENU) at the vehicle; position is geodetic
(latitude ``L``, longitude ``lambda``, height ``h`` on WGS-84). The error state of a
pseudolite/INS (PL/INS) integration is, in this order,

====  =========================  ======
idx   state                      unit
====  =========================  ======
0-2   attitude errors phi_E,N,U  rad
3-5   velocity errors dv_E,N,U   m/s
6     latitude error dL          rad
7     longitude error dlambda    rad
8     height error dh            m
9     pseudolite equivalent      m
      error drho (receiver
      clock offset in range
      units, common to all PLs)
====  =========================  ======

The first nine rows are the classic phi-angle (psi/phi) INS error equations in ENU
(Titterton & Weston 2004, ch. 12; Savage 2000; in the Chinese literature Yuan, Yu &
Chen 1993, the source paper's ref. [6]). Jin et al. (2011) lost these equations in
extraction; they are reconstructed here in their standard form:

.. math::

    \dot\phi = -\omega_{in}^n\times\phi + \delta\omega_{in}^n - \epsilon^n  \quad (1a)

    \delta\dot v = f^n\times\phi - (2\omega_{ie}^n+\omega_{en}^n)\times\delta v
        + v\times(2\delta\omega_{ie}^n+\delta\omega_{en}^n) + \delta g^n + \nabla^n  \quad (1b)

    \delta\dot L = \frac{\delta v_N}{R_M+h} - \frac{v_N\,\delta h}{(R_M+h)^2}, \;
    \delta\dot\lambda = \frac{\sec L\,\delta v_E}{R_N+h} + \dots, \;
    \delta\dot h = \delta v_U  \quad (1c)

    \delta\dot\rho = 0 \quad (F_P = 0, \text{paper eq. 1})  \quad (1d)

The standard simplification is kept: the derivatives of the radii of curvature with
latitude are neglected (relative size about 1 %). Both gravity gradients are kept: the
vertical one ``dg/dh = -2 g / (R_0 + h)`` and the latitude derivative of Somigliana's
formula (tiny, but it makes ``F`` the exact Jacobian of :func:`nav_rates` up to the
radii terms, which the tests check against finite differences). Sensor errors
are white noise (the 9-state model has no bias states): gyro angle random walk and
accelerometer velocity random walk, rotated into ENU (isotropic, so the rotation does
not change the covariance).

All angles are radians inside; names carrying degrees say so (``lat_deg``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.linalg import expm

from xnavlab.core.validate import (
    check_covariance,
    check_finite_array,
    check_increasing,
    check_real,
    check_shape,
    check_vector,
    make_rng,
    shown,
)
from xnavlab.plins._checks import check_angle, check_angles

__all__ = [
    "WGS84_A",
    "WGS84_F",
    "WGS84_E2",
    "OMEGA_IE",
    "STATE_NAMES",
    "N_STATES",
    "earth_radii",
    "normal_gravity",
    "omega_ie",
    "omega_en",
    "nav_rates",
    "error_matrix",
    "noise_matrix",
    "imu_noise_psd",
    "G_MAX",
    "Q_MAX",
    "discretize",
    "Trajectory",
    "paper_trajectory",
    "DEFAULT_INITIAL_STD",
    "error_transitions",
    "simulate_errors",
]

#: WGS-84 semi-major axis, m.
WGS84_A = 6_378_137.0
#: WGS-84 flattening.
WGS84_F = 1.0 / 298.257_223_563
#: WGS-84 first eccentricity squared.
WGS84_E2 = WGS84_F * (2.0 - WGS84_F)
#: Earth rotation rate (WGS-84), rad/s.
OMEGA_IE = 7.292_115e-5

#: Names of the 10 error states, in order (see the module docstring).
STATE_NAMES = (
    "phi_E", "phi_N", "phi_U", "dv_E", "dv_N", "dv_U", "dlat", "dlon", "dh", "drho",
)
#: Number of error states (``len(STATE_NAMES)``).
N_STATES = 10

#: Largest entry of a noise input matrix ``G`` (:func:`discretize`), in magnitude: a gain from
#: a noise to a state is a unit conversion (an Earth radius is 6.4e6 m), far below; with
#: :data:`Q_MAX` it keeps ``G q G^T`` below 1e150, so that ``Q_d`` (grown at most ``e^150``
#: by ``||F||_inf dt <= 50``) stays far inside the float range.
G_MAX = 1e25
#: Largest entry of a noise power spectral density ``q`` (:func:`discretize`), any SI unit:
#: far beyond any sensor's (see :data:`G_MAX`).
Q_MAX = 1e100

_G_EQ = 9.780_325_335_9  # WGS-84 normal gravity at the equator, m/s^2
_K_SOMIGLIANA = 0.001_931_852_652_41


def _skew(v):
    """Cross-product matrix: ``_skew(a) @ b == np.cross(a, b)``."""
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def earth_radii(lat):
    """Meridian and prime-vertical radii of curvature of WGS-84.

    Parameters
    ----------
    lat : float or array_like
        Geodetic latitude, rad, in [-pi/2, pi/2].

    Returns
    -------
    r_m, r_n : float or ndarray
        Meridian radius ``R_M = a (1 - e^2) / (1 - e^2 sin^2 L)^{3/2}`` and prime-vertical
        radius ``R_N = a / (1 - e^2 sin^2 L)^{1/2}``, m.

    Examples
    --------
    >>> r_m, r_n = earth_radii(0.0)
    >>> round(r_n), round(r_m)
    (6378137, 6335439)
    """
    lat = check_angles("lat", lat, "lat")
    w = 1.0 - WGS84_E2 * np.sin(lat) ** 2
    r_m = WGS84_A * (1.0 - WGS84_E2) / w**1.5  # R_M
    r_n = WGS84_A / np.sqrt(w)  # R_N
    if r_m.ndim == 0:
        return float(r_m), float(r_n)
    return r_m, r_n


def normal_gravity(lat, h):
    """Magnitude of WGS-84 normal gravity at latitude ``lat`` and height ``h``.

    Somigliana's formula at the ellipsoid, reduced to height with the inverse-square
    law ``g(h) = g_0(L) (R_0 / (R_0 + h))^2``, ``R_0 = sqrt(R_M R_N)`` (Titterton &
    Weston 2004, eq. 3.91).

    Parameters
    ----------
    lat : float
        Geodetic latitude, rad.
    h : float
        Height above the ellipsoid, m, in [-1e4, 1e5].

    Returns
    -------
    float
        Gravity, m/s^2 (positive; the vector is ``[0, 0, -g]`` in ENU).

    Examples
    --------
    >>> round(normal_gravity(math.radians(39.0), 0.0), 4)
    9.8008
    """
    lat = check_angle("lat", lat, "lat")
    h = check_real("h", h, -1e4, 1e5)
    s2 = math.sin(lat) ** 2
    g0 = _G_EQ * (1.0 + _K_SOMIGLIANA * s2) / math.sqrt(1.0 - WGS84_E2 * s2)  # Somigliana
    r_m, r_n = earth_radii(lat)
    r0 = math.sqrt(r_m * r_n)
    return g0 * (r0 / (r0 + h)) ** 2


def _dg_dlat(lat, h):
    """Latitude derivative of :func:`normal_gravity` (radii held fixed), m/s^2/rad."""
    s_l, c_l = math.sin(lat), math.cos(lat)
    w = 1.0 - WGS84_E2 * s_l**2
    dg0 = _G_EQ * (2.0 * _K_SOMIGLIANA * s_l * c_l / math.sqrt(w)
                   + (1.0 + _K_SOMIGLIANA * s_l**2) * WGS84_E2 * s_l * c_l / w**1.5)
    r_m, r_n = earth_radii(lat)
    r0 = math.sqrt(r_m * r_n)
    return dg0 * (r0 / (r0 + h)) ** 2


def _check_state(lat, h, v_enu):
    lat = check_real("lat", lat, -math.radians(89.0), math.radians(89.0))
    h = check_real("h", h, -1e4, 1e5)
    v = check_shape("v_enu", v_enu, (3,))
    return lat, h, v


def omega_ie(lat):
    """Earth rate in the ENU frame, ``omega_ie^n = [0, Omega cos L, Omega sin L]``, rad/s.

    Examples
    --------
    >>> omega_ie(0.0).tolist() == [0.0, OMEGA_IE, 0.0]
    True
    """
    lat = check_angle("lat", lat, "lat")
    return np.array([0.0, OMEGA_IE * math.cos(lat), OMEGA_IE * math.sin(lat)])


def omega_en(lat, h, v_enu):
    """Transport rate of the ENU frame, rad/s.

    ``omega_en^n = [-v_N/(R_M+h), v_E/(R_N+h), v_E tan L/(R_N+h)]``.

    Parameters
    ----------
    lat : float
        Latitude, rad, within 89 deg of the equator (ENU is singular at the poles).
    h : float
        Height, m.
    v_enu : array_like, shape (3,)
        Velocity over the Earth in ENU, m/s.

    Examples
    --------
    >>> w = omega_en(0.0, 0.0, [0.0, 100.0, 0.0])
    >>> bool(w[0] < 0 and w[1] == 0 and w[2] == 0)
    True
    """
    lat, h, v = _check_state(lat, h, v_enu)
    r_m, r_n = earth_radii(lat)
    return np.array([-v[1] / (r_m + h), v[0] / (r_n + h), v[0] * math.tan(lat) / (r_n + h)])


def nav_rates(lat, lon, h, v_enu, f_enu):
    """Right-hand side of the nonlinear local-level navigation equations.

    ``L' = v_N/(R_M+h)``, ``lambda' = v_E/((R_N+h) cos L)``, ``h' = v_U`` and
    ``v' = f^n - (2 omega_ie^n + omega_en^n) x v + g^n`` (Titterton & Weston 2004,
    eqs. 3.71 and 3.72). The error matrix :func:`error_matrix` linearises these.

    Parameters
    ----------
    lat, lon : float
        Geodetic latitude in [-pi/2, pi/2] and longitude in [-2 pi, 2 pi], rad.
    h : float
        Height, m.
    v_enu : array_like, shape (3,)
        Velocity, m/s, ENU.
    f_enu : array_like, shape (3,)
        Specific force, m/s^2, ENU.

    Returns
    -------
    ndarray, shape (6,)
        ``[L', lambda', h', v_E', v_N', v_U']`` in rad/s, rad/s, m/s, m/s^2.

    Examples
    --------
    >>> g = normal_gravity(0.7, 0.0)
    >>> abs(nav_rates(0.7, 2.0, 0.0, [0, 0, 0], [0, 0, g])[5]) < 1e-12
    True
    """
    check_angle("lon", lon, "lon")
    lat, h, v = _check_state(lat, h, v_enu)
    f = check_shape("f_enu", f_enu, (3,))  # a (1, 3) row broadcast into numpy's message
    r_m, r_n = earth_radii(lat)
    p_dot = np.array([v[1] / (r_m + h), v[0] / ((r_n + h) * math.cos(lat)), v[2]])
    g_n = np.array([0.0, 0.0, -normal_gravity(lat, h)])
    v_dot = f - np.cross(2.0 * omega_ie(lat) + omega_en(lat, h, v), v) + g_n
    return np.concatenate([p_dot, v_dot])


def error_matrix(lat, h, v_enu, f_enu):
    """The 10x10 continuous-time PL/INS error matrix ``F = blkdiag(F_I, F_P)``.

    Parameters
    ----------
    lat : float
        Latitude of the operating point, rad.
    h : float
        Height, m.
    v_enu : array_like, shape (3,)
        Velocity, m/s, ENU.
    f_enu : array_like, shape (3,)
        Specific force, m/s^2, ENU.

    Returns
    -------
    ndarray, shape (10, 10)
        ``dx/dt = F x + G w`` for the state of the module docstring; ``F_P = 0``.

    Examples
    --------
    >>> F = error_matrix(math.radians(39.0), 1e4, [0.0, 150.0, 0.0], [0.0, 0.5, 9.8])
    >>> F.shape, float(F[8, 5]), float(F[9].sum())
    ((10, 10), 1.0, 0.0)
    """
    lat, h, v = _check_state(lat, h, v_enu)
    f = check_shape("f_enu", f_enu, (3,))  # a (1, 3) row raised an IndexError in _skew
    s_l, c_l, t_l = math.sin(lat), math.cos(lat), math.tan(lat)
    r_m, r_n = earth_radii(lat)
    rmh, rnh = r_m + h, r_n + h
    v_e, v_n, _ = v
    w_ie = omega_ie(lat)
    w_en = omega_en(lat, h, v)
    # d(omega_en)/d(dv) and d(omega_in)/d(dp), dp = [dL, dlambda, dh]
    m_wv = np.array([[0.0, -1.0 / rmh, 0.0], [1.0 / rnh, 0.0, 0.0], [t_l / rnh, 0.0, 0.0]])
    m_iep = np.array([[0.0, 0.0, 0.0], [-OMEGA_IE * s_l, 0.0, 0.0], [OMEGA_IE * c_l, 0.0, 0.0]])
    m_enp = np.array([
        [0.0, 0.0, v_n / rmh**2],
        [0.0, 0.0, -v_e / rnh**2],
        [v_e / (c_l**2 * rnh), 0.0, -v_e * t_l / rnh**2],
    ])
    m_wp = m_iep + m_enp  # d(omega_in)/d(dp)
    m_pv = np.array([[0.0, 1.0 / rmh, 0.0], [1.0 / (c_l * rnh), 0.0, 0.0], [0.0, 0.0, 1.0]])
    m_pp = np.array([
        [0.0, 0.0, -v_n / rmh**2],
        [v_e * t_l / (c_l * rnh), 0.0, -v_e / (c_l * rnh**2)],
        [0.0, 0.0, 0.0],
    ])
    F = np.zeros((N_STATES, N_STATES))
    F[0:3, 0:3] = -_skew(w_ie + w_en)  # eq. (1a): -omega_in x phi
    F[0:3, 3:6] = m_wv  # eq. (1a): delta omega_in from dv
    F[0:3, 6:9] = m_wp  # eq. (1a): delta omega_in from dp
    F[3:6, 0:3] = _skew(f)  # eq. (1b): f^n x phi
    F[3:6, 3:6] = -_skew(2.0 * w_ie + w_en) + _skew(v) @ m_wv  # eq. (1b)
    F[3:6, 6:9] = _skew(v) @ (2.0 * m_iep + m_enp)  # eq. (1b): v x (2 d omega_ie + d omega_en)
    F[5, 6] -= _dg_dlat(lat, h)  # eq. (1b): delta g_U = -dg/dL dL
    F[5, 8] += 2.0 * normal_gravity(lat, h) / (math.sqrt(r_m * r_n) + h)  # eq. (1b): -dg/dh
    F[6:9, 3:6] = m_pv  # eq. (1c)
    F[6:9, 6:9] = m_pp  # eq. (1c)
    # F[9, :] = 0: eq. (1d), F_P = 0
    return F


def noise_matrix():
    """Noise input matrix ``G`` (10x7) for ``w = [gyro(3), accel(3), pseudolite(1)]``.

    Gyro noise enters the attitude errors with a minus sign (eq. 1a, ``-epsilon^n``),
    accelerometer noise the velocity errors (eq. 1b, ``+nabla^n``), and the seventh
    input drives the pseudolite equivalent error as a random walk.

    Returns
    -------
    ndarray, shape (10, 7)

    Examples
    --------
    >>> G = noise_matrix()
    >>> G.shape, float(G[0, 0]), float(G[3, 3]), float(G[9, 6])
    ((10, 7), -1.0, 1.0, 1.0)
    """
    G = np.zeros((N_STATES, 7))
    G[0:3, 0:3] = -np.eye(3)
    G[3:6, 3:6] = np.eye(3)
    G[9, 6] = 1.0
    return G


def imu_noise_psd(gyro_arw_deg_rth=0.1, accel_vrw_mps_rth=0.1, pl_rw_m_rts=0.0):
    """Power spectral densities of ``w`` (diagonal of ``q``, SI) from data-sheet units.

    The default is a tactical-grade IMU (the paper is silent): gyro angle random walk
    0.1 deg/sqrt(h), accelerometer velocity random walk 0.1 (m/s)/sqrt(h), and a
    constant pseudolite equivalent error (``F_P = 0`` and no noise, paper eq. 1).

    Parameters
    ----------
    gyro_arw_deg_rth : float
        Gyro angle random walk, deg/sqrt(h), in [0, 1e4].
    accel_vrw_mps_rth : float
        Accelerometer velocity random walk, (m/s)/sqrt(h), in [0, 1e4].
    pl_rw_m_rts : float
        Random walk of the pseudolite equivalent error, m/sqrt(s), in [0, 1e4].

    Returns
    -------
    ndarray, shape (7,)
        PSDs in rad^2/s, (m/s)^2/s and m^2/s.

    Examples
    --------
    >>> q = imu_noise_psd(gyro_arw_deg_rth=60.0, accel_vrw_mps_rth=60.0)
    >>> bool(np.isclose(q[0], math.radians(1.0) ** 2)), float(q[3])
    (True, 1.0)
    """
    arw = math.radians(check_real("gyro_arw_deg_rth", gyro_arw_deg_rth, 0.0, 1e4)) / 60.0  # rad/sqrt(s)
    vrw = check_real("accel_vrw_mps_rth", accel_vrw_mps_rth, 0.0, 1e4) / 60.0  # (m/s)/sqrt(s)
    plw = check_real("pl_rw_m_rts", pl_rw_m_rts, 0.0, 1e4)
    return np.array([arw**2] * 3 + [vrw**2] * 3 + [plw**2])


def discretize(F, G, q, dt):
    """Exact zero-order discretisation ``A = exp(F dt)`` and ``Q_d`` (Van Loan 1978).

    Parameters
    ----------
    F : array_like, shape (n, n)
        Continuous system matrix, 1/s, with ``||F||_inf dt <= 50`` (its largest row sum of
        ``|F|``; a growth of ``e^50`` in one step is far beyond any INS).
    G : array_like, shape (n, m)
        Noise input matrix, entries at most :data:`G_MAX` in magnitude.
    q : array_like, shape (m,) or (m, m)
        Noise power spectral density (diagonal entries at least 0, or a full symmetric
        positive semi-definite matrix), entries at most :data:`Q_MAX`.
    dt : float
        Step, s, in (0, 86400] (an INS step is milliseconds to a second; a day is far beyond,
        and near 1e308 s the matrix exponential overflows).

    Returns
    -------
    A : ndarray, shape (n, n)
        State transition matrix, ``x_{k+1} = A x_k + w_k``.
    Qd : ndarray, shape (n, n)
        Covariance of ``w_k``: ``int_0^dt e^{F s} G q G^T e^{F^T s} ds``.

    Examples
    --------
    >>> A, Qd = discretize([[0.0, 1.0], [0.0, 0.0]], [[0.0], [1.0]], [1.0], 2.0)
    >>> A.tolist(), np.round(Qd, 6).tolist()
    ([[1.0, 2.0], [0.0, 1.0]], [[2.666667, 2.0], [2.0, 2.0]])
    """
    F = check_finite_array("F", F)
    if F.ndim != 2 or F.shape[0] != F.shape[1] or F.size == 0:
        raise ValueError(f"F must be a square matrix of shape (n, n), n >= 1, got shape {F.shape}")
    n = F.shape[0]
    G = check_finite_array("G", G)
    if G.ndim != 2 or G.shape[0] != n:
        raise ValueError(f"G must have shape ({n}, m) (n = {n} rows of F), got shape {G.shape}")
    if np.abs(G).max(initial=0.0) > G_MAX:  # G q G^T below 1e150: Q_d stays far inside the floats
        raise ValueError(f"G must have entries of at most {G_MAX:g} in magnitude (a noise input "
                         f"gain: unit conversions are far smaller), got {np.abs(G).max():.3g}")
    q = check_finite_array("q", q)
    m = G.shape[1]
    if q.ndim not in (1, 2) or q.shape not in ((m,), (m, m)):
        raise ValueError(f"q must have shape ({m},) or ({m}, {m}) (m = {m} columns of G), "
                         f"got shape {q.shape}")
    if np.abs(q).max(initial=0.0) > Q_MAX:  # with G_MAX: G q G^T below 1e150 (see G_MAX)
        raise ValueError(f"q must have entries of at most {Q_MAX:g} (a noise power spectral "
                         f"density far beyond any sensor's), got {np.abs(q).max():.3g}")
    q = np.diag(q) if q.ndim == 1 else q
    q = check_covariance("q", q, m)  # a spectral density: symmetric, positive semi-definite
    dt = check_real("dt", dt, 0.0, 86400.0, lo_open=True)
    growth = np.abs(F).sum(axis=1).max() * dt  # ||F||_inf dt bounds log ||e^{F dt}||
    if growth > 50.0:  # e^50 ~ 5e21 in one step, far beyond any INS; near 700 e^{F dt} overflows
        raise ValueError(f"F must have row sums of |F| at most 50 / dt = {50.0 / dt:.6g} 1/s "
                         f"(||F||_inf dt <= 50), got {growth / dt:.6g}")
    # Van Loan: expm([[-F, G q G^T], [0, F^T]] dt) = [[., A^-1 Qd], [0, A^T]]
    big = np.zeros((2 * n, 2 * n))
    big[:n, :n] = -F
    big[:n, n:] = G @ q @ G.T
    big[n:, n:] = F.T
    e = expm(big * dt)
    A = e[n:, n:].T
    Qd = A @ e[:n, n:]
    return A, 0.5 * (Qd + Qd.T)


@dataclass(frozen=True)
class Trajectory:
    """A sampled flight: time, geodetic position, ENU velocity and specific force.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Time since the start of the flight, s.
    lat, lon : ndarray, shape (n,)
        Geodetic latitude in [-pi/2, pi/2] and longitude in [-2 pi, 2 pi], rad.
    h : ndarray, shape (n,)
        Height above the WGS-84 ellipsoid, m.
    v_enu : ndarray, shape (n, 3)
        Velocity over the Earth, m/s, ENU.
    f_enu : ndarray, shape (n, 3)
        Specific force (what the accelerometers measure), m/s^2, ENU.

    Notes
    -----
    Every field is checked when the flight is built, naming the field: finite numbers, at
    least two samples, ``t`` strictly increasing at one step (:attr:`dt`, the step of
    :func:`error_transitions`), every other field one row per time, ``lat`` in
    [-pi/2, pi/2] and ``lon`` in [-2 pi, 2 pi] (radians: a flight in degrees is refused).

    Examples
    --------
    >>> Trajectory([0.0, 1.0], [0.7, 0.7], [2.0, 2.0], [0.0, 0.0], np.zeros((2, 3)),
    ...            np.zeros((2, 3))).dt
    1.0
    >>> Trajectory([1.0, 0.0], [0.7, 0.7], [2.0, 2.0], [0.0, 0.0], np.zeros((2, 3)),
    ...            np.zeros((2, 3)))
    Traceback (most recent call last):
    ...
    ValueError: t must be strictly increasing (sample times, s), got t[1] = 0 after t[0] = 1
    """

    t: np.ndarray
    lat: np.ndarray
    lon: np.ndarray
    h: np.ndarray
    v_enu: np.ndarray
    f_enu: np.ndarray

    def __post_init__(self):
        t = check_vector("t", self.t)
        if len(t) < 2:
            raise ValueError(f"t must hold at least two samples (a flight has a step dt), got "
                             f"{len(t)}")
        step = np.diff(check_increasing("t", t))
        # one step: error_transitions discretises every sample with dt = t[1] - t[0]
        if np.max(np.abs(step - step[0])) > 1e-9 * max(step[0], np.max(np.abs(t))):
            raise ValueError(f"t must be evenly spaced (error_transitions steps by dt = t[1] - "
                             f"t[0] = {step[0]:g} s), got steps from {step.min():g} to "
                             f"{step.max():g} s")
        why = f"n = {len(t)} samples of t"
        checked = {"t": t}
        for name in ("lat", "lon", "h"):
            checked[name] = check_shape(name, getattr(self, name), (len(t),), why)
        for name in ("lat", "lon"):  # radians, bounded: a flight typed in degrees is refused here
            check_angles(name, checked[name], name)
        for name in ("v_enu", "f_enu"):
            checked[name] = check_shape(name, getattr(self, name), (len(t), 3), why)
        for name, value in checked.items():  # frozen: stored as the checked float arrays
            object.__setattr__(self, name, value)

    @property
    def dt(self):
        """Sample interval, s."""
        return float(self.t[1] - self.t[0])

    @property
    def lat_deg(self):
        """Latitude, deg."""
        return np.degrees(self.lat)

    def __len__(self):
        return len(self.t)


def _whole_steps(name, span, step_name, step):
    """``span / step``, a whole number (at least 1, to 1e-9 of a step), else one ValueError
    naming ``name`` with the nearest valid spans: a span between two whole steps was cut to
    the nearest (10.5 s at 1-s steps ended at 10 s, 10 s at 3-s steps at 9 s) without a word."""
    ratio = span / step
    if ratio > 1e6:  # a million samples: the flight's Python loops and arrays stay tractable
        raise ValueError(f"{name} must hold at most 1e6 steps {step_name} = {step:g} s, got "
                         f"{span:g} s ({ratio:.6g} steps)")
    n = round(ratio)
    if n < 1 or abs(ratio - n) > 1e-9:
        lo, hi = max(math.floor(ratio), 1), max(math.ceil(ratio), 1)
        near = f"{lo * step:g} s" if lo == hi else f"{lo * step:g} and {hi * step:g} s"
        raise ValueError(f"{name} must be a whole number of steps {step_name} = {step:g} s, got "
                         f"{span:g} s ({ratio:.6g} steps): the nearest {'is' if lo == hi else 'are'} "
                         f"{near}")
    return int(n)


def paper_trajectory(dt=1.0, duration=200.0, lat0_deg=39.0, lon0_deg=116.0, h=10_000.0,
                     v0=100.0, v1=200.0):
    """The flight of Jin et al. (2011): north along a meridian, accelerating.

    Constant north acceleration ``(v1 - v0) / duration`` (the paper gives only the
    speeds; uniform acceleration is our choice), constant longitude and height.
    Latitude is integrated exactly: ``dL/dt = v_N / (R_M(L) + h)`` (trapezoidal
    sub-steps). The specific force is ``f^n = v' + (2 omega_ie + omega_en) x v - g^n``.

    Parameters
    ----------
    dt : float
        Sample interval, s, in [1e-3, 10] (a millisecond: an INS's fastest output).
    duration : float
        Flight time, s, in (0, 1e5]: at most 1e6 steps, a whole number of steps ``dt`` (to 1e-9 of a step; a
        duration between two whole steps is refused with its nearest valid values, not cut
        short to the step below).
    lat0_deg, lon0_deg : float
        Start position, deg.
    h : float
        Flight height, m.
    v0, v1 : float
        North speed at the start and at the end, m/s, > 0.

    Returns
    -------
    Trajectory

    Examples
    --------
    >>> tr = paper_trajectory()
    >>> len(tr), float(tr.v_enu[-1, 1]), round(float(tr.lat_deg[-1]), 3)
    (201, 200.0, 39.27)
    """
    dt = check_real("dt", dt, 1e-3, 10.0)  # 1 ms: an INS's fastest rate (5e-324 made inf steps)
    duration = check_real("duration", duration, 0.0, 1e5, lo_open=True)
    lat0 = math.radians(check_real("lat0_deg", lat0_deg, -80.0, 80.0))
    lon0 = math.radians(check_real("lon0_deg", lon0_deg, -180.0, 360.0))
    h = check_real("h", h, -1e3, 1e5)
    v0 = check_real("v0", v0, 0.0, 1e4, lo_open=True)
    v1 = check_real("v1", v1, 0.0, 1e4, lo_open=True)
    n = _whole_steps("duration", duration, "dt", dt) + 1
    t = np.arange(n) * dt
    acc = (v1 - v0) / duration
    v_n = v0 + acc * t
    lat = np.empty(n)
    lat[0] = lat0
    sub = 10
    for k in range(n - 1):  # dL/dt = v_N / (R_M + h), trapezoidal sub-steps
        L = lat[k]
        for i in range(sub):
            ta = t[k] + i * dt / sub
            tb = ta + dt / sub
            ra = earth_radii(L)[0] + h
            lb = L + (v0 + acc * ta) / ra * dt / sub
            rb = earth_radii(lb)[0] + h
            L = L + 0.5 * ((v0 + acc * ta) / ra + (v0 + acc * tb) / rb) * dt / sub
        lat[k + 1] = L
    v_enu = np.column_stack([np.zeros(n), v_n, np.zeros(n)])
    f_enu = np.empty((n, 3))
    for k in range(n):
        w = 2.0 * omega_ie(lat[k]) + omega_en(lat[k], h, v_enu[k])
        g_n = np.array([0.0, 0.0, -normal_gravity(lat[k], h)])
        f_enu[k] = np.array([0.0, acc, 0.0]) + np.cross(w, v_enu[k]) - g_n  # f = v' + w x v - g
    return Trajectory(t, lat, np.full(n, lon0), np.full(n, h), v_enu, f_enu)


#: Default 1-sigma initial INS errors (our choice; the paper is silent): tilt 0.3 mrad
#: (about 1 arcmin), heading 3 mrad, velocity 0.1 m/s, horizontal and vertical
#: position 10 m, pseudolite equivalent (receiver clock) error 100 m.
DEFAULT_INITIAL_STD = np.array(
    [3e-4, 3e-4, 3e-3, 0.1, 0.1, 0.1, 10.0 / 6.36e6, 10.0 / 4.95e6, 10.0, 100.0]
)


def simulate_errors(traj, x0_std=None, q=None, rng=None, transitions=None):
    """Propagate the true INS error state along a trajectory.

    The truth uses the error matrix at every sample (``A_k = exp(F(t_k) dt)``, exact
    Van Loan noise), not the fuzzy local models, so the T-S model used by the
    diagnosis is an approximation of it, as in the paper.

    Parameters
    ----------
    traj : Trajectory
        The flight.
    x0_std : array_like, shape (10,), optional
        1-sigma initial errors (default :data:`DEFAULT_INITIAL_STD`).
    q : array_like, shape (7,), optional
        Noise PSDs (default :func:`imu_noise_psd()`).
    rng : numpy.random.Generator or int, optional
        Seed (``None`` is seed 0).
    transitions : tuple of ndarray, optional
        ``(A, Qd)`` from :func:`error_transitions` (computed when omitted; pass them to
        reuse them across Monte Carlo runs), each ``Qd[k]`` a covariance (symmetric,
        positive semi-definite). They hold the noise already: giving ``q`` as well is
        refused (it would be ignored).

    Returns
    -------
    ndarray, shape (n, 10)
        Error state at every sample, units of :data:`STATE_NAMES`.

    Examples
    --------
    >>> x = simulate_errors(paper_trajectory(duration=10.0), rng=1)
    >>> x.shape, bool(np.all(x[:, 9] == x[0, 9]))
    ((11, 10), True)
    """
    if not isinstance(traj, Trajectory):
        raise ValueError(f"traj must be a Trajectory, got {type(traj).__name__}")
    x0_std = DEFAULT_INITIAL_STD if x0_std is None else x0_std
    x0_std = check_shape("x0_std", x0_std, (N_STATES,))
    if np.any(x0_std < 0):
        raise ValueError("x0_std must be >= 0")
    rng = make_rng(rng)
    n = len(traj)
    if transitions is None:
        A, Qd = error_transitions(traj, q)
    else:
        if q is not None:  # the transitions' Qd already holds a noise: q would be ignored
            raise ValueError("q must be omitted when transitions are given (their Qd holds the "
                             "noise: error_transitions(traj, q))")
        A, Qd = _check_transitions(transitions, n)
    x = np.empty((n, N_STATES))
    x[0] = x0_std * rng.standard_normal(N_STATES)
    for k in range(n - 1):
        x[k + 1] = A[k] @ x[k] + _sample(Qd[k], rng)  # x_{k+1} = A_k x_k + w_k
    return x


def error_transitions(traj, q=None):
    """Discrete error transitions ``A_k`` and noise covariances ``Q_k`` along a flight.

    ``A_k = exp(F(t_k) dt)`` with :func:`error_matrix` at sample ``k`` and ``Q_k`` from
    :func:`discretize` (Van Loan), for ``x_{k+1} = A_k x_k + w_k``.

    Parameters
    ----------
    traj : Trajectory
        The flight.
    q : array_like, shape (7,), optional
        Noise PSDs (default :func:`imu_noise_psd()`).

    Returns
    -------
    A, Qd : ndarray, shape (n - 1, 10, 10)

    Examples
    --------
    >>> A, Qd = error_transitions(paper_trajectory(duration=3.0))
    >>> A.shape, bool(np.allclose(A[:, 9, 9], 1.0))
    ((3, 10, 10), True)
    """
    if not isinstance(traj, Trajectory):
        raise ValueError(f"traj must be a Trajectory, got {type(traj).__name__}")
    q = imu_noise_psd() if q is None else check_shape("q", q, (7,))
    G = noise_matrix()
    n = len(traj)
    if not traj.dt <= 86400.0:  # discretize's range, named here as the flight's step
        raise ValueError(f"traj must have a step t[1] - t[0] of at most 86400 s (a day), got "
                         f"{traj.dt:g} s")
    A = np.empty((n - 1, N_STATES, N_STATES))
    Qd = np.empty_like(A)
    for k in range(n - 1):
        F = error_matrix(traj.lat[k], traj.h[k], traj.v_enu[k], traj.f_enu[k])
        growth = np.abs(F).sum(axis=1).max() * traj.dt  # discretize's bound, named as the flight's
        if growth > 50.0:
            raise ValueError(f"traj must have a step dt of at most {50.0 * traj.dt / growth:.3g} s "
                             f"at sample {k} (||F||_inf dt <= 50 for its error model), got "
                             f"{traj.dt:g} s")
        A[k], Qd[k] = discretize(F, G, q, traj.dt)
    return A, Qd


def _check_transitions(transitions, n):
    """``(A, Qd)`` of a flight of ``n`` samples: two arrays of shape (n - 1, 10, 10), else one
    ValueError naming ``transitions`` (a number, a bool or a list of three is no pair)."""
    if not isinstance(transitions, list | tuple) or len(transitions) != 2:
        raise ValueError(f"transitions must be a pair (A, Qd) from error_transitions, got "
                         f"{shown(transitions)}")
    why = f"n - 1 = {n - 1} steps of the flight"
    A, Qd = (check_shape(f"transitions[{i}]", a, (n - 1, N_STATES, N_STATES), why)
             for i, a in enumerate(transitions))
    k = _first_non_covariance(Qd)  # an indefinite Qd[k], or a swapped (Qd, A) pair
    if k is not None:
        check_covariance(f"transitions[1][{k}]", Qd[k], N_STATES)  # raises, naming Qd[k]
    return A, Qd


def _first_non_covariance(stack):
    """Index of the first matrix of ``stack`` (k, n, n) that :func:`check_covariance` refuses
    (its own tests, vectorised: one eigvalsh call for a flight), else None."""
    if not len(stack):
        return None
    scale = np.abs(stack).max(axis=(1, 2))
    asym = np.abs(stack - stack.transpose(0, 2, 1)).max(axis=(1, 2)) > 1e-8 * scale
    low = np.linalg.eigvalsh(0.5 * (stack + stack.transpose(0, 2, 1)))[:, 0]
    bad = asym | (low < -1e-8 * scale)
    return int(np.argmax(bad)) if bad.any() else None


def _sample(cov, rng):
    """One draw of N(0, cov) for a PSD (possibly singular) covariance."""
    vals, vecs = np.linalg.eigh(cov)
    vals = np.clip(vals, 0.0, None)
    return vecs @ (np.sqrt(vals) * rng.standard_normal(len(vals)))
