r"""Pseudolites: WGS-84 geodesy, pseudoranges and the linearised PL/INS measurement.

A pseudolite (PL) is a ground transmitter of a GNSS-like ranging signal. The receiver
on the aircraft measures the pseudorange to PL ``k`` (Jin et al. 2011, eq. 2)

.. math::

    \rho_k = \lVert r - r_k \rVert + \delta\rho + \varepsilon_k + f_k ,

with ``r`` the antenna position in ECEF, ``delta rho`` the pseudolite equivalent error
(the receiver clock offset in range units, common to every PL: the tenth state of
:mod:`xnavlab.plins.ins`), white noise ``epsilon_k`` and a fault ``f_k``. The INS predicts
``rho_I,k = ||r_I - r_k||`` from its own position ``r_I = r + delta r`` (eq. 4). The
measurement of the PL/INS filter is the difference ``z = rho - rho_I`` (eq. 5), and its
linearisation about the operating point (eqs. 9-11) is

.. math::

    z = H x + \varepsilon + f, \qquad H = [\,0_{4\times 6}\;\; E\,T\;\; K\,],

where the rows of ``E`` are the unit vectors from the aircraft to the pseudolites
(ECEF), ``T = d r / d [L, lambda, h]`` converts the geodetic position error to ECEF
(eq. 10) and ``K = [1, 1, 1, 1]^T`` carries the common clock error. (The paper's
equations were lost in extraction; these are the standard forms, e.g. Misra & Enge
2011, ch. 6, and the geodesy of Hofmann-Wellenhof et al. 2008.)

Placement (our choice; the paper gives none): four pseudolites on the ground around
the 30 km leg flown north from 39 N, 116 E at 10 km, one under its middle and three
around it, seen 15-80 deg below the horizon; the geometry changes strongly along the
leg, which is what the fuzzy blending of local models is for (:data:`DEFAULT_SITES_DEG`).

Noise (our reading): the paper's "PL positioning accuracy 10 m" is read as the 1-sigma
accuracy of a pseudolite position fix. With the default sites the PDOP along the leg
is 3.3-9.2 (4.5 at the median), so the pseudorange noise is about
``10 m / 4.5 = 2.2 m``; we use ``sigma = 2 m`` (:data:`DEFAULT_SIGMA`), a typical
code-ranging noise. The other reading, 10 m per pseudorange, is ``sigma=10.0``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from xnavlab.core import faults as _faults
from xnavlab.core.validate import check_finite_array, check_real, make_rng, shown
from xnavlab.plins._checks import check_angle, check_angles, check_sites, distinct_sites
from xnavlab.plins.ins import N_STATES, WGS84_A, WGS84_E2, Trajectory, earth_radii

__all__ = [
    "DEFAULT_SITES_DEG",
    "DEFAULT_SIGMA",
    "MAX_HEIGHT",
    "SENSOR",
    "geodetic_to_ecef",
    "ecef_to_geodetic",
    "enu_matrix",
    "geodetic_jacobian",
    "sites_ecef",
    "pseudoranges",
    "los_matrix",
    "measurement_matrix",
    "pdop",
    "PseudorangeData",
    "simulate_pseudoranges",
]

#: Pseudolite sites ``[lat_deg, lon_deg, h]`` (h in m above WGS-84), our choice:
#: PL1 south-west of the start of the leg, PL2 east of its end, PL3 under its middle
#: (0.4 km east of the meridian, to separate height from clock), PL4 north-west
#: beyond its end. PDOP along the leg: 3.3 to 9.2.
DEFAULT_SITES_DEG = np.array([
    [39.00, 115.92, 50.0],
    [39.25, 116.10, 50.0],
    [39.13, 116.005, 50.0],
    [39.32, 115.90, 50.0],
])

#: Default 1-sigma pseudorange noise, m (see :func:`simulate_pseudoranges`).
DEFAULT_SIGMA = 2.0

#: The greatest height a point takes, m (a million km, beyond the Moon: a pseudolite's user is
#: near the ground, and far larger heights overflow the squares of the geometry).
MAX_HEIGHT = 1e9

#: Sensor name of the pseudoranges for :mod:`xnavlab.core.faults`.
SENSOR = "pseudorange"


def _geo_arrays(lat, lon, h):
    lat = check_angles("lat", lat, "lat")
    lon = check_angles("lon", lon, "lon")
    h = check_finite_array("h", h)
    if np.any(h <= -WGS84_A / 2) or np.any(h > MAX_HEIGHT):  # far out, squares overflow
        raise ValueError(f"h must be in ({-WGS84_A / 2:g}, {MAX_HEIGHT:g}] m")
    try:
        return np.broadcast_arrays(lat, lon, h)
    except ValueError:
        raise ValueError("lat, lon and h must broadcast to one shape") from None


def geodetic_to_ecef(lat, lon, h):
    """ECEF position of a geodetic point on WGS-84 (paper eq. 3).

    ``x = (R_N + h) cos L cos lambda``, ``y = (R_N + h) cos L sin lambda``,
    ``z = (R_N (1 - e^2) + h) sin L``.

    Parameters
    ----------
    lat, lon : float or array_like
        Geodetic latitude in [-pi/2, pi/2] and longitude in [-2 pi, 2 pi], rad (a value in
        degrees is refused: convert it with ``np.radians``).
    h : float or array_like
        Height above the ellipsoid, m, in (-a/2, :data:`MAX_HEIGHT`].

    Returns
    -------
    ndarray, shape (..., 3)
        ECEF position, m.

    Examples
    --------
    >>> geodetic_to_ecef(0.0, 0.0, 0.0).tolist()
    [6378137.0, 0.0, 0.0]
    """
    lat, lon, h = _geo_arrays(lat, lon, h)
    s_l = np.sin(lat)
    r_n = WGS84_A / np.sqrt(1.0 - WGS84_E2 * s_l**2)
    x = (r_n + h) * np.cos(lat) * np.cos(lon)  # eq. (3)
    y = (r_n + h) * np.cos(lat) * np.sin(lon)  # eq. (3)
    z = (r_n * (1.0 - WGS84_E2) + h) * s_l  # eq. (3)
    return np.stack([x, y, z], axis=-1)


def ecef_to_geodetic(r):
    """Geodetic latitude, longitude and height of an ECEF position (inverse of eq. 3).

    Fixed-point iteration on latitude with the height written as
    ``h = p cos L + z sin L - a sqrt(1 - e^2 sin^2 L)`` (valid at the poles too),
    iterated until the latitude changes by less than 1e-13 rad.

    Parameters
    ----------
    r : array_like, shape (..., 3)
        ECEF position, m, not within 1 km of the Earth's centre.

    Returns
    -------
    lat, lon, h : ndarray, shape (...)
        Latitude and longitude (rad, longitude in (-pi, pi]) and height (m).

    Examples
    --------
    >>> lat, lon, h = ecef_to_geodetic(geodetic_to_ecef(0.7, 2.0, 1e4))
    >>> round(float(lat), 12), round(float(lon), 12), round(float(h), 6)
    (0.7, 2.0, 10000.0)
    """
    r = check_finite_array("r", r, shape=(3,))
    x, y, z = r[..., 0], r[..., 1], r[..., 2]
    p = np.hypot(x, y)
    if np.any(np.hypot(p, z) < 1e3):
        raise ValueError("r must be at least 1 km from the Earth's centre")
    lon = np.arctan2(y, x)
    lat = np.arctan2(z, p * (1.0 - WGS84_E2))
    for _ in range(30):
        s_l = np.sin(lat)
        r_n = WGS84_A / np.sqrt(1.0 - WGS84_E2 * s_l**2)
        h = p * np.cos(lat) + z * s_l - WGS84_A * np.sqrt(1.0 - WGS84_E2 * s_l**2)
        new = np.arctan2(z, p * (1.0 - WGS84_E2 * r_n / (r_n + h)))
        done = np.max(np.abs(new - lat)) < 1e-13
        lat = new
        if done:
            break
    s_l = np.sin(lat)
    h = p * np.cos(lat) + z * s_l - WGS84_A * np.sqrt(1.0 - WGS84_E2 * s_l**2)
    return lat, lon, h


def enu_matrix(lat, lon):
    """Rotation from ECEF to the local ENU frame (rows: east, north, up in ECEF).

    Parameters
    ----------
    lat, lon : float
        Geodetic latitude in [-pi/2, pi/2] and longitude in [-2 pi, 2 pi], rad.

    Returns
    -------
    ndarray, shape (3, 3)
        ``C`` with ``v_enu = C @ v_ecef``.

    Examples
    --------
    >>> (enu_matrix(0.0, 0.0) + 0.0).tolist()
    [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]
    """
    lat = check_angle("lat", lat, "lat")
    lon = check_angle("lon", lon, "lon")
    s_l, c_l, s_o, c_o = math.sin(lat), math.cos(lat), math.sin(lon), math.cos(lon)
    return np.array([
        [-s_o, c_o, 0.0],
        [-s_l * c_o, -s_l * s_o, c_l],
        [c_l * c_o, c_l * s_o, s_l],
    ])


def geodetic_jacobian(lat, lon, h):
    """``T = d r_ecef / d [L, lambda, h]``, the geodetic-to-ECEF error transform (paper eq. 10).

    Columns: ``-(R_M + h) [sin L cos lambda, sin L sin lambda, -cos L]`` for latitude,
    ``(R_N + h) cos L [-sin lambda, cos lambda, 0]`` for longitude and the local up
    vector for height (exact derivatives of eq. 3).

    Parameters
    ----------
    lat, lon : float
        Geodetic latitude in [-pi/2, pi/2] and longitude in [-2 pi, 2 pi], rad.
    h : float
        Height, m, in (-a/2, :data:`MAX_HEIGHT`].

    Returns
    -------
    ndarray, shape (3, 3)
        m/rad in the first two columns, m/m in the third.

    Examples
    --------
    >>> T = geodetic_jacobian(0.0, 0.0, 0.0)
    >>> (np.round(T) + 0.0).tolist()
    [[0.0, 0.0, 1.0], [0.0, 6378137.0, 0.0], [6335439.0, 0.0, 0.0]]
    """
    lat = check_angle("lat", lat, "lat")
    lon = check_angle("lon", lon, "lon")
    h = check_real("h", h, -WGS84_A / 2, MAX_HEIGHT, lo_open=True)
    r_m, r_n = earth_radii(lat)
    s_l, c_l, s_o, c_o = math.sin(lat), math.cos(lat), math.sin(lon), math.cos(lon)
    return np.array([
        [-(r_m + h) * s_l * c_o, -(r_n + h) * c_l * s_o, c_l * c_o],
        [-(r_m + h) * s_l * s_o, (r_n + h) * c_l * c_o, c_l * s_o],
        [(r_m + h) * c_l, 0.0, s_l],
    ])


def sites_ecef(sites_deg=None):
    """ECEF positions of pseudolite sites given as ``[lat_deg, lon_deg, h]`` rows.

    Parameters
    ----------
    sites_deg : array_like, shape (m, 3), optional
        Sites (default :data:`DEFAULT_SITES_DEG`), latitudes in [-90, 90] deg, longitudes in
        [-360, 360] deg, distinct (at least 1 m apart).

    Returns
    -------
    ndarray, shape (m, 3)
        ECEF positions, m.

    Examples
    --------
    >>> sites_ecef().shape
    (4, 3)
    """
    sites = DEFAULT_SITES_DEG if sites_deg is None else sites_deg
    sites = check_finite_array("sites_deg", sites, shape=(3,))
    if sites.ndim != 2 or len(sites) < 1:
        raise ValueError(f"sites_deg must have shape (m, 3), got {sites.shape}")
    for col, what, bound in ((0, "latitudes", 90.0), (1, "longitudes", 360.0)):  # degrees here
        if np.any(bad := np.abs(sites[:, col]) > bound):
            i = int(np.argmax(bad))
            raise ValueError(f"sites_deg {what} must be in [{-bound:g}, {bound:g}] deg, got "
                             f"sites_deg[{i}, {col}] = {sites[i, col]:g}")
    ecef = geodetic_to_ecef(np.radians(sites[:, 0]), np.radians(sites[:, 1]), sites[:, 2])
    return distinct_sites("sites_deg", ecef)


def _point(lat, lon, h):
    """One receiver position: ``lat``, ``lon`` and ``h`` each a real number in its range, named."""
    lat = check_angle("lat", lat, "lat")
    lon = check_angle("lon", lon, "lon")
    h = check_real("h", h, -WGS84_A / 2, MAX_HEIGHT, lo_open=True)  # as geodetic_to_ecef's
    return lat, lon, h


def pseudoranges(r, sites):
    """Geometric ranges from positions ``r`` to the pseudolites (paper eq. 4).

    Parameters
    ----------
    r : array_like, shape (..., 3)
        Receiver positions, ECEF, m.
    sites : array_like, shape (m, 3)
        Pseudolite positions, ECEF, m; m >= 1, at least 1 m apart.

    Returns
    -------
    ndarray, shape (..., m)
        ``||r - r_k||``, m.

    Examples
    --------
    >>> pseudoranges([0.0, 0.0, 0.0], [[3.0, 4.0, 0.0], [0.0, 0.0, 2.0]]).tolist()
    [5.0, 2.0]
    """
    r = check_finite_array("r", r, shape=(3,))
    sites = check_sites(sites)
    return np.linalg.norm(r[..., None, :] - sites, axis=-1)  # eq. (4)


def los_matrix(r, sites):
    """``E``: rows are the unit vectors from the receiver to each pseudolite, ECEF.

    ``d rho_k / d r = -E_k`` (paper eq. 9), so ``rho_true - rho_I = E (r_I - r)`` to
    first order.

    Parameters
    ----------
    r : array_like, shape (3,)
        Receiver position, ECEF, m, not at a pseudolite.
    sites : array_like, shape (m, 3)
        Pseudolite positions, ECEF, m; m >= 1, at least 1 m apart.

    Returns
    -------
    ndarray, shape (m, 3)

    Examples
    --------
    >>> los_matrix([0.0, 0.0, 0.0], [[3.0, 4.0, 0.0]]).tolist()
    [[0.6, 0.8, 0.0]]
    """
    r = check_finite_array("r", r, shape=(3,))
    if r.ndim != 1:
        raise ValueError(f"r must have shape (3,), got {r.shape}")
    sites = check_sites(sites)
    d = sites - r
    rho = np.linalg.norm(d, axis=1)
    if np.any(rho < 1e-3):
        raise ValueError("r must not coincide with a pseudolite site")
    return d / rho[:, None]  # eq. (9)


def measurement_matrix(lat, lon, h, sites):
    """Linearised PL/INS measurement matrix ``H = [0_{m x 6}, E T, K]`` (paper eq. 11).

    Parameters
    ----------
    lat, lon : float
        Geodetic latitude (in [-pi/2, pi/2]) and longitude (in [-2 pi, 2 pi]) of the
        linearisation point, rad.
    h : float
        Height, m, in (-a/2, :data:`MAX_HEIGHT`].
    sites : array_like, shape (m, 3)
        Pseudolite positions, ECEF, m; m >= 1, at least 1 m apart.

    Returns
    -------
    ndarray, shape (m, 10)
        ``z = rho - rho_I = H x + noise`` for the state of :mod:`xnavlab.plins.ins`.

    Examples
    --------
    >>> H = measurement_matrix(0.68, 2.02, 1e4, sites_ecef())
    >>> H.shape, H[:, :6].any(), H[:, 9].tolist()
    ((4, 10), False, [1.0, 1.0, 1.0, 1.0])
    """
    lat, lon, h = _point(lat, lon, h)
    r = geodetic_to_ecef(lat, lon, h)
    E = los_matrix(r, sites)
    T = geodetic_jacobian(lat, lon, h)
    H = np.zeros((len(E), N_STATES))
    H[:, 6:9] = E @ T  # eq. (11): E T
    H[:, 9] = 1.0  # eq. (11): K, the common clock
    return H


def pdop(lat, lon, h, sites):
    """Position dilution of precision of a pseudolite-only fix (3-D position + clock).

    ``PDOP = sqrt(trace of the position block of (G^T G)^{-1})`` with ``G = [-E, 1]``.

    Parameters
    ----------
    lat, lon : float
        Receiver latitude (in [-pi/2, pi/2]) and longitude (in [-2 pi, 2 pi]), rad.
    h : float
        Receiver height, m, in (-a/2, :data:`MAX_HEIGHT`].
    sites : array_like, shape (m, 3), m >= 4
        Pseudolite positions, ECEF, m: distinct (at least 1 m apart) and around the
        receiver in 3-D (the geometry matrix's condition number at most 1e6).

    Returns
    -------
    float

    Examples
    --------
    >>> round(pdop(np.radians(39.13), np.radians(116.0), 1e4, sites_ecef()), 1)
    3.3
    """
    lat, lon, h = _point(lat, lon, h)
    r = geodetic_to_ecef(lat, lon, h)
    E = los_matrix(r, sites)
    if len(E) < 4:
        raise ValueError(f"sites must hold at least 4 pseudolites, got {len(E)}")
    G = np.column_stack([-E, np.ones(len(E))])
    if np.linalg.cond(G) > 1e6:  # PDOP ~ cond(G); 1e6 is no fix (sites on one line of sight)
        raise ValueError(f"sites must surround the receiver in 3-D (geometry [-E, 1] of rank 4 "
                         f"with condition number at most 1e6), got {np.linalg.cond(G):.3g}")
    cov = np.linalg.inv(G.T @ G)
    return float(math.sqrt(np.trace(cov[:3, :3])))  # PDOP = sqrt(tr (G^T G)^-1_pos)


@dataclass(frozen=True)
class PseudorangeData:
    """Simulated pseudoranges of a flight.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Time, s.
    rho_true : ndarray, shape (n, m)
        Geometric ranges from the true position, m.
    rho : ndarray, shape (n, m)
        Measured pseudoranges (clock, noise and faults included), m (eq. 2).
    rho_ins : ndarray, shape (n, m)
        Ranges predicted from the INS position, m (eq. 4).
    z : ndarray, shape (n, m)
        Measurement of the PL/INS system ``rho - rho_ins``, m (eq. 5).
    fault : ndarray, shape (n, m)
        The injected fault alone, m.
    sigma : float
        1-sigma pseudorange noise, m.
    r_ins : ndarray, shape (n, 3)
        INS-indicated position, ECEF, m (where a filter linearises ``H``).
    """

    t: np.ndarray
    rho_true: np.ndarray
    rho: np.ndarray
    rho_ins: np.ndarray
    z: np.ndarray
    fault: np.ndarray
    sigma: float
    r_ins: np.ndarray


def _check_flight_faults(faults, t):
    """The faults as a list, each one the flight uses (its sensor, an onset inside the flight,
    a sample it acts on), else one ValueError naming it: inject would drop it in silence."""
    if isinstance(faults, np.ndarray) and faults.ndim == 0:  # iterable to hasattr, not to list
        raise ValueError(f"faults must be a sequence of Fault, got {shown(faults)}")
    faults = _faults.check_faults("faults", faults)
    for i, f in enumerate(faults):
        where = f"faults[{i}] ({f.sensor} {f.kind} from {f.onset:g} s)"
        if f.sensor != SENSOR:
            raise ValueError(f"{where}: sensor must be {SENSOR!r} (the pseudoranges are the "
                             f"flight's only measurements), got {f.sensor!r}")
        if not t[0] <= f.onset <= t[-1]:
            raise ValueError(f"{where} starts outside this flight, [{t[0]:g}, {t[-1]:g}] s")
        if not f.active(t).any():
            raise ValueError(f"{where} acts on no sample: it lasts {f.duration:g} s between two "
                             f"samples")
    return faults


def simulate_pseudoranges(traj, x_err, sites=None, sigma=DEFAULT_SIGMA, faults=(), rng=None):
    """Measured and INS-predicted pseudoranges along a flight, with faults.

    The paper gives "PL positioning accuracy 10 m". We read it as the 1-sigma 3-D
    accuracy of a pseudolite fix, so the pseudorange noise is about ``10 m / PDOP``;
    with the default sites the median PDOP along the leg is 4.5, hence the
    default ``sigma = 2 m`` (module docstring). The other reading (10 m per
    pseudorange) is ``sigma=10.0``.

    Parameters
    ----------
    traj : xnavlab.plins.ins.Trajectory
        True flight.
    x_err : array_like, shape (n, 10)
        INS error state along the flight (:func:`xnavlab.plins.ins.simulate_errors`); the INS
        position is the true one plus ``x_err[:, 6:9]`` and ``x_err[:, 9]`` is the
        common clock offset in metres.
    sites : array_like, shape (m, 3), optional
        Pseudolite positions, ECEF, m (default :func:`sites_ecef()`).
    sigma : float
        1-sigma white pseudorange noise, m, in [0, 1e6].
    faults : sequence of xnavlab.core.faults.Fault
        Faults of sensor ``"pseudorange"`` (component = pseudolite index, 0-based),
        applied with :func:`xnavlab.core.faults.inject`; a fault of another sensor, one that
        starts outside the flight or acts on no sample is refused, naming it.
    rng : numpy.random.Generator or int, optional
        Seed of the noise (``None`` is seed 0).

    Returns
    -------
    PseudorangeData

    Examples
    --------
    >>> from xnavlab.plins import ins
    >>> from xnavlab.core.faults import Fault
    >>> tr = ins.paper_trajectory(duration=20.0)
    >>> x = ins.simulate_errors(tr, rng=0)
    >>> d = simulate_pseudoranges(tr, x, faults=[Fault("pseudorange", "step", 100.0, 10.0,
    ...                                                   component=1)])
    >>> d.z.shape, d.fault[9:11, 1].tolist()
    ((21, 4), [0.0, 100.0])
    """
    if not isinstance(traj, Trajectory):
        raise ValueError(f"traj must be a Trajectory, got {type(traj).__name__}")
    x_err = check_finite_array("x_err", x_err, shape=(N_STATES,))
    if x_err.shape != (len(traj), N_STATES):
        raise ValueError(f"x_err must have shape ({len(traj)}, {N_STATES}), got {x_err.shape}")
    sites = sites_ecef() if sites is None else check_sites(sites)
    sigma = check_real("sigma", sigma, 0.0, 1e6)  # as diagnose_flight's
    rng = make_rng(rng)
    r_true = geodetic_to_ecef(traj.lat, traj.lon, traj.h)
    r_ins = geodetic_to_ecef(traj.lat + x_err[:, 6], traj.lon + x_err[:, 7], traj.h + x_err[:, 8])
    rho_true = pseudoranges(r_true, sites)
    rho_ins = pseudoranges(r_ins, sites)
    noise = sigma * rng.standard_normal(rho_true.shape)
    clean = rho_true + x_err[:, 9:10] + noise  # eq. (2) without the fault
    rho = _faults.inject(traj.t, clean, _check_flight_faults(faults, traj.t), SENSOR, rng=rng)
    return PseudorangeData(
        t=traj.t.copy(), rho_true=rho_true, rho=rho, rho_ins=rho_ins,
        z=rho - rho_ins,  # eq. (5)
        fault=rho - clean, sigma=sigma, r_ins=r_ins,
    )
