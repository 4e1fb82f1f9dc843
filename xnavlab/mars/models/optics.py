"""The optical sensors as instruments make them: apparent-radius range, oblate limb, correlated horizon.

The main paper's UV sensor and horizon sensor (:mod:`xnavlab.mars.models.sensors`) are idealised:
the UV range has a constant 5 km noise, the limb is that of a sphere centred on Mars's
centre, and every 3-s sample has independent (white) errors. This module models what an
instrument measures, as options beside those defaults (the reproductions keep the paper's):

Range from the apparent radius (``uv_range_model="radius"``)
    An optical sensor measures Mars's apparent angular radius ``alpha`` and infers the range
    ``rho = R / sin(alpha)``; an error ``sigma_alpha`` in ``alpha`` gives
    ``sigma_rho = |d rho / d alpha| sigma_alpha = rho cot(alpha) sigma_alpha``
    (:func:`radius_range_sigma`), which varies about 2x over the paper's orbit
    (3,817-4,575 km from the centre). ``sigma_alpha`` is chosen so that the time-mean of
    ``sigma_rho`` over one orbit is the paper's 5 km (:func:`sigma_alpha_for`: 0.0926 deg; then
    3.2 km at 3,817 km, 6.7 km at 4,575 km).
The oblate limb (``limb="oblate"``)
    Mars is an ellipsoid of revolution, equatorial radius :data:`R_EQUATOR`, polar
    :data:`R_POLAR` (flattening about 1/170). Seen from ``r``, its limb is an elliptic cone
    (:func:`limb_fit`); a sensor that fits a circle to it (the cone's axis as the centre, the
    mean angular distance of the limb from the axis as the radius) and a sphere of radius
    :data:`R_MEAN` to that circle reports a range and a centre direction with a bias that
    depends on the range and on the latitude under the spacecraft (:func:`limb_bias`).
Correlated horizon errors (``horizon_tau_s > 0``)
    The horizon sensor's error is a first-order Gauss-Markov process per tangent axis,
    ``g_k = phi g_k-1 + sqrt(1 - phi^2) w_k`` with ``phi = exp(-dt / tau)`` and the same
    steady-state sigma (0.05 deg), instead of white noise (:func:`gauss_markov`).
    Infrared horizon sensors' dominant errors follow the radiance of the atmosphere's
    limb under the line of sight, and change sign and size with the spacecraft's position
    around the orbit (about 0.03-0.06 deg on a polar Earth orbit, a 1980 NASA study of
    horizon-sensor systematic errors; Alex and Shrivastava 1989 correct them as functions
    of orbital position), so they are correlated over a fraction of an orbit.
    :data:`HORIZON_TAU_S` (1000 s, an eighth of the paper's 8,252-s orbit) is this
    module's choice; :func:`gauss_markov` takes any ``tau``.

The filter is not told: it keeps its white-noise ``R`` (constant 5 km range noise, 0.05 deg
horizon), which is exactly the mismatch a real mission meets. :func:`uv_series_model` and
:func:`cns_series_model` give :func:`xnavlab.mars.navigation.scenarios.prepare` the measurement
generator of a scenario (the paper's compiled one when every option is the paper's).

Units: m, rad (``_deg`` names: deg), s. Frames: Mars-centred J2000/ICRF.

Examples
--------
>>> rho = np.array([3.817e6, 4.575e6])
>>> np.round(radius_range_sigma(rho, sigma_alpha_for(5000.0)) / 1e3, 1).tolist()
[3.2, 6.7]
"""

from __future__ import annotations

import math

import numpy as np

from xnavlab.core.constants import GM_MARS, R_MARS
from xnavlab.core.validate import check_choice, check_finite_array, check_int, check_real, off_unit, shown
from xnavlab.mars.models import series
from xnavlab.mars.models.dynamics import MARS_POLE, MARS_STATE0, MAX_BODY_RADIUS, check_state0
from xnavlab.mars.models.sensors import perturb_direction

__all__ = [
    "R_EQUATOR",
    "R_POLAR",
    "R_MEAN",
    "MIN_ALPHA",
    "RANGE_MODELS",
    "LIMBS",
    "HORIZON_TAU_S",
    "UNIT_TOL",
    "apparent_radius",
    "range_from_radius",
    "radius_range_sigma",
    "orbit_ranges",
    "sigma_alpha_for",
    "limb_fit",
    "limb_bias",
    "gauss_markov",
    "is_paper",
    "UVInstrument",
    "CNSInstrument",
    "uv_series_model",
    "cns_series_model",
]

#: Mars's equatorial radius, m (IAU 2015, Archinal et al. 2018; :data:`xnavlab.core.constants.R_MARS`).
R_EQUATOR = R_MARS
#: Mars's polar radius, m (IAU 2015, Archinal et al. 2018): flattening (a - c)/a = 1/170.
R_POLAR = 3_376_200.0
#: Radius of the sphere of Mars's volume, ``(a^2 c)^(1/3)``, m: the sphere a limb sensor fits.
R_MEAN = (R_EQUATOR**2 * R_POLAR) ** (1.0 / 3.0)
#: UV range models: the paper's constant noise, or the range from the apparent radius.
RANGE_MODELS = ("constant", "radius")
#: Limb models: the paper's sphere of radius R_MARS, or the oblate ellipsoid fitted by a sphere.
LIMBS = ("sphere", "oblate")
#: Correlation time of the horizon sensor's errors chosen here, s (an eighth of the orbit).
HORIZON_TAU_S = 1000.0


def apparent_radius(rho, radius=R_MARS):
    """Apparent angular radius of a sphere, ``alpha = arcsin(R / rho)``, rad.

    Parameters
    ----------
    rho : float or array_like
        Distance from the centre, m (``> radius``).
    radius : float
        Sphere radius, m, in [1, MAX_BODY_RADIUS] (from 1 m, as :func:`limb_fit`'s radii).

    Examples
    --------
    >>> round(float(np.degrees(apparent_radius(2.0 * R_MARS))), 9)
    30.0
    """
    rho = check_finite_array("rho", rho)
    radius = check_real("radius", radius, 1.0, MAX_BODY_RADIUS)  # 5e-324: 0 rad (35k)
    if np.any(rho <= radius):
        raise ValueError("rho must exceed the radius (the sensor is outside the planet)")
    return np.arcsin(radius / rho)  # sin(alpha) = R / rho


#: The smallest apparent radius, rad: 1 nrad (Mars from 20,000 AU), below what any limb sensor
#: resolves; ``R / sin(alpha)`` overflows near 1e-300. Ranges are at most ``radius / MIN_ALPHA``.
MIN_ALPHA = 1e-9


def range_from_radius(alpha, radius=R_MARS):
    """Range from the apparent angular radius, ``rho = R / sin(alpha)``, m.

    Parameters
    ----------
    alpha : float or array_like
        Apparent radius, rad, in [MIN_ALPHA, pi/2) (1e-9 rad: no limb sensor resolves less).
    radius : float
        Sphere radius, m, in [1, MAX_BODY_RADIUS] (from 1 m, as :func:`limb_fit`'s radii).

    Examples
    --------
    >>> round(float(range_from_radius(np.radians(30.0)) / R_MARS), 12)
    2.0
    """
    alpha = check_finite_array("alpha", alpha)
    if np.any((alpha < MIN_ALPHA) | (alpha >= math.pi / 2)):
        bad = float(alpha[(alpha < MIN_ALPHA) | (alpha >= math.pi / 2)][0])
        raise ValueError(f"alpha must be in [{MIN_ALPHA:g}, pi/2) rad, got {bad:g}")
    radius = check_real("radius", radius, 1.0, MAX_BODY_RADIUS)  # 5e-324: 0 rad (35k)
    return radius / np.sin(alpha)  # rho = R / sin(alpha)


def radius_range_sigma(rho, sigma_alpha, radius=R_MARS):
    """Range noise of the apparent-radius measurement, ``rho cot(alpha) sigma_alpha``, m.

    First order: ``d rho / d alpha = -R cos(alpha) / sin^2(alpha) = -rho cot(alpha)``.

    Parameters
    ----------
    rho : float or array_like
        Range, m, in (radius, radius / MIN_ALPHA] (beyond, an apparent radius under 1 nrad).
    sigma_alpha : float
        Noise of the apparent radius, rad, in [0, pi].
    radius : float
        Sphere radius, m, in [1, MAX_BODY_RADIUS] (from 1 m, as :func:`limb_fit`'s radii).

    Examples
    --------
    >>> round(float(radius_range_sigma(2.0 * R_MARS, 1e-3) / R_MARS), 6)   # 2 R cot 30 deg 1e-3
    0.003464
    """
    sigma_alpha = check_real("sigma_alpha", sigma_alpha, 0.0, math.pi)
    rho = _check_ranges("rho", rho, radius)
    alpha = apparent_radius(rho, radius)
    return rho / np.tan(alpha) * sigma_alpha  # sigma_rho = rho cot(alpha) sigma_alpha


def _check_ranges(name, rho, radius):
    """``rho`` as a finite array of ranges in ``(radius, radius / MIN_ALPHA]``, else one
    ValueError naming ``name``."""
    rho = check_finite_array(name, rho)
    radius = check_real("radius", radius, 1.0, MAX_BODY_RADIUS)  # 5e-324: 0 rad (35k)
    if np.any((rho <= radius) | (rho > radius / MIN_ALPHA)):
        bad = float(rho[(rho <= radius) | (rho > radius / MIN_ALPHA)][0])
        raise ValueError(f"{name} must be in (radius, radius / MIN_ALPHA] = ({radius:g}, "
                         f"{radius / MIN_ALPHA:g}] m (outside the planet, where it subtends at "
                         f"least 1 nrad), got {bad:g}")
    return rho


def orbit_ranges(state0=MARS_STATE0, n=3600):
    """Distances from Mars's centre over one Keplerian orbit, sampled uniformly in time, m.

    Parameters
    ----------
    state0 : array_like, shape (6,)
        An osculating state, m and m/s (default: the paper's initial state), as
        :func:`xnavlab.mars.models.dynamics.check_state0` takes it (above Mars, in its Hill
        sphere) and on an elliptic orbit.
    n : int
        Samples (uniform in mean anomaly).

    Returns
    -------
    ndarray, shape (n,)

    Examples
    --------
    >>> r = orbit_ranges()
    >>> round(float(r.min()) / 1e3), round(float(r.max()) / 1e3)
    (3817, 4575)
    """
    s = check_state0(state0)  # one state above Mars (review 35k: (1, 6), the centre: 1/0)
    n = check_int("n", n, 8, 10**7)
    r, v = s[:3], s[3:]
    a = 1.0 / (2.0 / np.linalg.norm(r) - v @ v / GM_MARS)  # vis-viva
    e = np.linalg.norm(np.cross(v, np.cross(r, v)) / GM_MARS - r / np.linalg.norm(r))
    if not 0.0 <= e < 1.0:
        raise ValueError(f"state0 must be on an elliptic orbit, got e = {e:.3f}")
    M = 2.0 * math.pi * (np.arange(n) + 0.5) / n
    E = M.copy()
    for _ in range(30):  # Kepler: E - e sin E = M (Newton)
        E -= (E - e * np.sin(E) - M) / (1.0 - e * np.cos(E))
    return a * (1.0 - e * np.cos(E))  # r = a (1 - e cos E)


def sigma_alpha_for(sigma_range_m=5000.0, ranges=None, radius=R_MARS):
    """The apparent-radius noise whose range noise averages ``sigma_range_m`` over an orbit, rad.

    ``sigma_alpha = sigma_range / mean(rho cot(alpha))`` over ``ranges`` (default
    :func:`orbit_ranges` of the paper's orbit: 0.0926 deg for 5 km).

    Parameters
    ----------
    sigma_range_m : float
        Mean range noise, m, in (0, 1e7].
    ranges : array_like, shape (n,), optional
        At least one range, m, each in (radius, radius / MIN_ALPHA].
    radius : float
        Sphere radius, m, in [1, MAX_BODY_RADIUS] (from 1 m, as :func:`limb_fit`'s radii).

    Examples
    --------
    >>> round(float(np.degrees(sigma_alpha_for(5000.0))), 4)
    0.0926
    """
    sigma_range_m = check_real("sigma_range_m", sigma_range_m, 0.0, 1e7, lo_open=True)  # as sensors
    rho = orbit_ranges() if ranges is None else _check_ranges("ranges", ranges, radius)
    if rho.ndim != 1 or rho.size == 0:  # the mean of no range is NaN
        raise ValueError(f"ranges must be a 1-D array of at least one range, got shape {rho.shape}")
    return sigma_range_m / float(np.mean(radius_range_sigma(rho, 1.0, radius)))


#: How far from 1 the norm of a unit vector (a pole, a star direction) may be, as the sensors'.
UNIT_TOL = 1e-6


def _unit_pole(pole, name="pole"):
    """``pole`` (3,) if its norm is within :data:`UNIT_TOL` of 1, made exactly unit (a change
    below 1e-6: the numbers of a unit pole stay), else one ValueError (review 35j: a zero or a
    scaled pole was rescaled, or divided by zero)."""
    p = check_finite_array(name, pole)
    norm = float(np.linalg.norm(p)) if p.shape == (3,) else 0.0
    if p.shape != (3,) or not abs(norm - 1.0) <= UNIT_TOL:
        got = f"shape {p.shape}" if p.shape != (3,) else f"norm {norm:.6g}"
        raise ValueError(f"{name} must be a unit vector, shape (3,), norm within {UNIT_TOL:g} of "
                         f"1 (not rescaled), got {got}")
    return p / norm


def _star_dirs(star_dirs):
    """``star_dirs`` (k, 3), k >= 1, unit rows, none twice (within 1e-9 rad), else one ValueError."""
    s = check_finite_array("star_dirs", star_dirs)
    if s.ndim != 2 or s.shape[1] != 3 or s.shape[0] == 0:
        raise ValueError(f"star_dirs must have shape (k, 3), one unit vector a star, k >= 1, got "
                         f"shape {s.shape}")
    i, norm = off_unit(s, UNIT_TOL)
    if i is not None:
        raise ValueError(f"star_dirs[{i}] must be a unit vector (norm within {UNIT_TOL:g} of 1, "
                         f"not rescaled), got norm {norm[i]:.6g}")
    sine = np.linalg.norm(np.cross(s[:, None, :], s[None, :, :]), axis=-1)
    close = np.triu((sine < 1e-9) & (s @ s.T > 0.0), 1)  # a star twice: its angle counted twice
    if close.any():
        i, j = (int(v) for v in np.argwhere(close)[0])
        raise ValueError(f"star_dirs lists one direction twice (rows {i} and {j})")
    return s


def _check_pole_used(pole, limb):
    """The instruments' pole: a unit vector, and unused (refused unless the default) with the
    sphere, which has none."""
    p = _unit_pole(pole)
    if limb == "sphere" and not np.array_equal(np.asarray(pole, dtype=float), MARS_POLE):
        raise ValueError("pole is unused with limb = 'sphere' (a sphere has no pole): leave it "
                         "out or take limb = 'oblate'")
    return p


def limb_fit(r, pole=MARS_POLE, a=R_EQUATOR, c=R_POLAR, n_azimuth=36):
    """The circle a limb sensor fits to the limb of an ellipsoid of revolution.

    Seen from ``r`` the limb of ``x^T A x = 1``, ``A = I / a^2 + (1/c^2 - 1/a^2) p p^T``,
    is the cone of directions ``d`` with ``d^T M d = 0``,
    ``M = (A r)(A r)^T - (r^T A r - 1) A`` (a line from ``r`` touching the surface). ``M``
    has one positive eigenvalue ``l0`` (its eigenvector is the cone's axis) and two negative
    ones ``l1, l2``; at azimuth ``phi`` about the axis the limb is at
    ``tan^2(theta) = l0 / -(l1 cos^2 phi + l2 sin^2 phi)``. The fitted centre is the axis and
    the fitted angular radius the mean of ``theta`` over ``n_azimuth`` equally spaced
    azimuths (the least-squares circle about the axis of limb points uniform in azimuth).

    Parameters
    ----------
    r : array_like, shape (..., 3)
        Spacecraft positions, Mars-centred, m (outside the ellipsoid).
    pole : array_like, shape (3,)
        Unit vector of the symmetry axis (norm within 1e-6 of 1; a zero or scaled one is
        refused, not rescaled).
    a, c : float
        Equatorial and polar radii, m, each in [1, MAX_BODY_RADIUS].
    n_azimuth : int
        Limb samples.

    Returns
    -------
    alpha : ndarray, shape (...,)
        Fitted angular radius, rad.
    u : ndarray, shape (..., 3)
        Fitted centre direction (unit, toward Mars).

    Examples
    --------
    >>> al, u = limb_fit(np.array([0.0, 0.0, 2.0 * R_MARS]), pole=(0, 0, 1), a=R_MARS, c=R_MARS)
    >>> round(float(np.degrees(al)), 9), (u + 0.0).tolist()
    (30.0, [0.0, 0.0, -1.0])
    """
    r = check_finite_array("r", r, shape=(3,))
    p = _unit_pole(pole)
    # radii from 1 m (as dynamics.R_MIN: below it 1/a^2 of a subnormal overflowed) to a star's
    a = check_real("a", a, 1.0, MAX_BODY_RADIUS)
    c = check_real("c", c, 1.0, MAX_BODY_RADIUS)
    n_azimuth = check_int("n_azimuth", n_azimuth, 4, 100000)
    A = np.eye(3) / a**2 + (1.0 / c**2 - 1.0 / a**2) * np.outer(p, p)
    Ar = r @ A
    q = np.einsum("...i,...i->...", r, Ar)
    if np.any(q <= 1.0):
        raise ValueError("r must be outside the ellipsoid")
    M = Ar[..., :, None] * Ar[..., None, :] - (q - 1.0)[..., None, None] * A  # tangent cone
    w, V = np.linalg.eigh(M)  # ascending: l1 <= l2 < 0 < l0
    l1, l2, l0 = w[..., 0:1], w[..., 1:2], w[..., 2:3]
    u = V[..., :, 2]
    u = u * np.where(np.einsum("...i,...i->...", u, r) > 0.0, -1.0, 1.0)[..., None]
    phi = 2.0 * math.pi * np.arange(n_azimuth) / n_azimuth
    theta = np.arctan(np.sqrt(l0 / -(l1 * np.cos(phi) ** 2 + l2 * np.sin(phi) ** 2)))
    return theta.mean(axis=-1), u


def limb_bias(r, pole=MARS_POLE, r_fit=R_MEAN):
    """Range and direction bias of a sphere fitted to Mars's oblate limb, as a function of geometry.

    The sensor fits a circle to the limb (:func:`limb_fit`) and a sphere of radius ``r_fit``
    to that circle: range ``r_fit / sin(alpha_fit)``, centre the circle's.

    Parameters
    ----------
    r : array_like, shape (..., 3)
        Spacecraft positions, Mars-centred, m.
    pole : array_like, shape (3,)
        Mars's pole (default :data:`xnavlab.mars.models.dynamics.MARS_POLE`), a unit vector
        (norm within 1e-6 of 1).
    r_fit : float
        Radius of the sensor's sphere, m (default :data:`R_MEAN`), in [1, MAX_BODY_RADIUS].

    Returns
    -------
    dict
        ``range_m`` (...,): fitted minus true range; ``direction_rad`` (...,): angle between
        the fitted and the true centre direction; ``latitude_deg`` (...,): latitude of the
        spacecraft over Mars's equator.

    Examples
    --------
    >>> b = limb_bias(np.array([[4.2e6, 0, 0], [0, 0, 4.2e6]]), pole=(0, 0, 1))
    >>> np.round(b["range_m"] / 1e3, 1).tolist(), np.round(b["direction_rad"], 9).tolist()
    ([-4.0, 7.8], [0.0, 0.0])
    """
    r = check_finite_array("r", r, shape=(3,))
    r_fit = check_real("r_fit", r_fit, 1.0, MAX_BODY_RADIUS)
    p = _unit_pole(pole)
    alpha, u = limb_fit(r, p)
    rho = np.linalg.norm(r, axis=-1)
    cosd = np.clip(-np.einsum("...i,...i->...", u, r) / rho, -1.0, 1.0)
    return {"range_m": r_fit / np.sin(alpha) - rho, "direction_rad": np.arccos(cosd),
            "latitude_deg": np.degrees(np.arcsin(np.clip(r @ p / rho, -1.0, 1.0)))}


def gauss_markov(w, phi, g0=None):
    """First-order Gauss-Markov sequence from white draws: ``g_k = phi g_k-1 + sqrt(1 - phi^2) w_k``.

    With ``w`` standard normal and ``g0`` (the value before the first sample) drawn from the
    steady state N(0, 1), or ``g0 = None`` (the first sample is ``w_0``, itself steady
    state), ``g`` is stationary with unit variance and autocorrelation ``phi^|lag|``;
    ``phi = exp(-dt / tau)`` for samples ``dt`` apart and correlation time ``tau``.

    Parameters
    ----------
    w : array_like, shape (n, ...)
        White standard normal draws, time along axis 0.
    phi : float
        Lag-one correlation in [0, 1).
    g0 : array_like, shape (...), optional
        Value before ``w[0]``; carries a sequence over chunks.

    Returns
    -------
    ndarray, shape (n, ...)

    Examples
    --------
    >>> gauss_markov(np.array([1.0, 0.0, 0.0]), 0.5).tolist()
    [1.0, 0.5, 0.25]
    """
    from scipy.signal import lfilter  # here: scipy.signal imports scipy.stats (slow)

    w = check_finite_array("w", w)
    if w.ndim == 0:
        raise ValueError(f"w must be an array with time along axis 0, got a scalar {w.item()!r}")
    phi = check_real("phi", phi, 0.0, 1.0, hi_open=True)
    if w.shape[0] == 0:
        return w.copy()
    b = math.sqrt(1.0 - phi * phi)
    if g0 is None:  # start in the steady state: g_0 = w_0
        g = np.empty_like(w)
        g[0] = w[0]
        if w.shape[0] > 1:
            g[1:] = lfilter([b], [1.0, -phi], w[1:], axis=0, zi=(phi * w[0])[None])[0]
        return g
    g0 = check_finite_array("g0", g0)
    try:
        g0 = np.broadcast_to(g0, w.shape[1:])
    except ValueError:  # review 35j: numpy's remapped-shapes message
        raise ValueError(f"g0 must have shape {w.shape[1:]} (w's shape past axis 0), or one "
                         f"that broadcasts to it, got shape {g0.shape}") from None
    return lfilter([b], [1.0, -phi], w, axis=0, zi=(phi * g0)[None])[0]  # g_k = phi g_k-1 + b w_k


def is_paper(scenario):
    """Whether a scenario's optical sensors are the paper's idealised ones (every option off).

    Examples
    --------
    >>> from xnavlab.mars.navigation.scenarios import MarsScenario
    >>> is_paper(MarsScenario()), is_paper(MarsScenario(limb="oblate"))
    (True, False)
    """
    _check_fields("scenario", scenario, "MarsScenario", ("uv_range_model", "limb", "horizon_tau_s"))
    return (scenario.uv_range_model == "constant" and scenario.limb == "sphere"
            and scenario.horizon_tau_s == 0.0)


def _check_fields(name, value, kind, fields):
    """Refuse, in one line naming ``name``, a value without the fields of ``kind``."""
    if not all(hasattr(value, f) for f in fields):
        raise ValueError(f"{name} must be a {kind} (fields {', '.join(fields)}), got {shown(value)}")


def _centre(states, limb, pole):
    """Fitted range and centre direction of the truth ``states`` (n, 6): ``(rho, u)``."""
    r = states[:, :3]
    rho = np.linalg.norm(r, axis=1)
    if limb == "sphere":
        return rho, -r / rho[:, None], np.arcsin(R_MARS / rho)
    alpha, u = limb_fit(r, pole)
    return R_MEAN / np.sin(alpha), u, alpha


class UVInstrument:
    """UV measurements ``[range, u]`` with the instrument options (a generator for ``prepare``).

    Called as ``sim(states, noise, out)`` on consecutive chunks (the draws of the paper's
    model: ``noise`` (n, 3), range then the two tangent axes). Range: ``"constant"``, the
    fitted range plus ``sigma_range w``; ``"radius"``, ``r_fit / sin(alpha_fit + sigma_alpha
    w)`` with ``sigma_alpha`` from :func:`sigma_alpha_for` (orbit-mean noise
    ``sigma_range``). Direction: the fitted centre turned by
    :func:`~xnavlab.mars.models.sensors.perturb_direction`.

    Parameters
    ----------
    sigma_range, sigma_dir : float
        Range noise (orbit mean), m, in (0, 1e7]; direction noise per axis, rad, in (0, pi].
    range_model : {"constant", "radius"}
    limb : {"sphere", "oblate"}
    pole : array_like, shape (3,)
        Mars's pole, a unit vector (norm within 1e-6 of 1), for the oblate limb; with the
        sphere one other than the default is refused (unused).

    Examples
    --------
    >>> sim = UVInstrument(5000.0, 1e-3, "radius", "oblate")
    >>> z = sim(np.array([[4.2e6, 0, 0, 0, 3e3, 0]]), np.zeros((1, 3)), np.empty((1, 4)))
    >>> round(float(z[0, 0] - 4.2e6) / 1e3, 1)   # the oblate limb's bias at this geometry, km
    -1.6
    """

    def __init__(self, sigma_range, sigma_dir, range_model="constant", limb="sphere",
                 pole=MARS_POLE):
        # the ranges of sensors.uv_measurement's: 1e4 km, and a half turn
        self.sigma_range = check_real("sigma_range", sigma_range, 0.0, 1e7, lo_open=True)
        self.sigma_dir = check_real("sigma_dir", sigma_dir, 0.0, math.pi, lo_open=True)
        self.range_model = check_choice("range_model", range_model, RANGE_MODELS)
        self.limb = check_choice("limb", limb, LIMBS)
        self.pole = _check_pole_used(pole, self.limb)
        radius = R_MARS if limb == "sphere" else R_MEAN
        self.radius = radius
        self.sigma_alpha = sigma_alpha_for(self.sigma_range, radius=radius)

    def __call__(self, states, noise, out):
        rho, u, alpha = _centre(states, self.limb, self.pole)
        if self.range_model == "constant":
            out[:, 0] = rho + self.sigma_range * noise[:, 0]
        else:  # rho = R / sin(alpha + sigma_alpha w), the apparent radius measured
            out[:, 0] = self.radius / np.sin(alpha + self.sigma_alpha * noise[:, 0])
        out[:, 1:] = perturb_direction(u, self.sigma_dir, noise[:, 1:3])
        return out


class CNSInstrument:
    """Starlight angles with the horizon options (a generator for ``prepare``).

    Called as ``sim(states, noise, out)`` on consecutive chunks of epochs ``dt`` apart
    (``noise`` (n, 2 + 2k): the horizon's two tangent axes, then the stars'). The horizon
    draws become a Gauss-Markov sequence of correlation time ``tau_s`` (carried over chunks;
    ``tau_s = 0``: white) and turn the fitted centre direction (``limb``); the angles are
    then those of :func:`xnavlab.mars.models.series.simulate_cns`.

    Parameters
    ----------
    star_dirs : ndarray, shape (k, 3)
        Star directions, k >= 1 unit vectors (norm within 1e-6 of 1), none twice.
    sigma_star, sigma_horizon : float
        Per-axis noise, rad, in (0, pi].
    dt : float
        Spacing of the epochs, s.
    tau_s : float
        Correlation time of the horizon errors, s (0: white).
    limb : {"sphere", "oblate"}
    pole : array_like, shape (3,)
        As :class:`UVInstrument`'s.

    Examples
    --------
    >>> sim = CNSInstrument(np.array([[0.0, 1.0, 0.0]]), 1e-5, 1e-3, 3.0, tau_s=1000.0)
    >>> sim(np.array([[4e6, 0.0, 0, 0, 0, 0]]), np.zeros((1, 4)), np.empty((1, 1))).shape
    (1, 1)
    """

    def __init__(self, star_dirs, sigma_star, sigma_horizon, dt, tau_s=0.0, limb="sphere",
                 pole=MARS_POLE):
        self.star_dirs = _star_dirs(star_dirs)
        # the ranges of sensors.cns_measurement's: a half turn
        self.sigma_star = check_real("sigma_star", sigma_star, 0.0, math.pi, lo_open=True)
        self.sigma_horizon = check_real("sigma_horizon", sigma_horizon, 0.0, math.pi, lo_open=True)
        dt = check_real("dt", dt, 0.0, lo_open=True)
        self.tau_s = check_real("tau_s", tau_s, 0.0, 1e8)
        self.phi = math.exp(-dt / self.tau_s) if self.tau_s > 0.0 else 0.0  # phi = exp(-dt / tau)
        self.limb = check_choice("limb", limb, LIMBS)
        self.pole = _check_pole_used(pole, self.limb)
        self.carry = None  # the last horizon draw of the previous chunk

    def __call__(self, states, noise, out):
        noise = np.array(noise, dtype=float)
        if self.tau_s > 0.0 and noise.shape[0]:
            noise[:, 0:2] = gauss_markov(noise[:, 0:2], self.phi, self.carry)
            self.carry = noise[-1, 0:2].copy()
        _, u, _ = _centre(states, self.limb, self.pole)
        pseudo = np.zeros_like(states)
        pseudo[:, :3] = -u  # the angles depend on r only through u = -r/|r|
        return series.simulate_cns(pseudo, noise, self.star_dirs, self.sigma_star,
                                   self.sigma_horizon, out)


def uv_series_model(scenario, uv):
    """The UV series' ``(simulate, params)`` for ``prepare``: the compiled model or :class:`UVInstrument`.

    Examples
    --------
    >>> from xnavlab.mars.navigation.scenarios import MarsScenario
    >>> sc = MarsScenario()
    >>> uv_series_model(sc, sc.sensors()["uv"])[0] is series.simulate_uv
    True
    """
    _check_fields("scenario", scenario, "MarsScenario", ("uv_range_model", "limb"))
    _check_fields("uv", uv, "UVSensor", ("sigma_range", "sigma_dir"))
    if scenario.uv_range_model == "constant" and scenario.limb == "sphere":
        return series.simulate_uv, (uv.sigma_range, uv.sigma_dir)
    return UVInstrument(uv.sigma_range, uv.sigma_dir, scenario.uv_range_model, scenario.limb), ()


def cns_series_model(scenario, cns):
    """The CNS series' ``(simulate, params)`` for ``prepare``: the compiled model or :class:`CNSInstrument`.

    Examples
    --------
    >>> from xnavlab.mars.navigation.scenarios import MarsScenario
    >>> sc = MarsScenario(horizon_tau_s=1000.0)
    >>> type(cns_series_model(sc, sc.sensors()["cns"])[0]).__name__
    'CNSInstrument'
    """
    _check_fields("scenario", scenario, "MarsScenario", ("limb", "horizon_tau_s", "dt_cns"))
    _check_fields("cns", cns, "CNSSensor", ("star_dirs", "sigma_star", "sigma_horizon"))
    if scenario.limb == "sphere" and scenario.horizon_tau_s == 0.0:
        return series.simulate_cns, (cns.star_dirs, cns.sigma_star, cns.sigma_horizon)
    return CNSInstrument(cns.star_dirs, cns.sigma_star, cns.sigma_horizon, scenario.dt_cns,
                         scenario.horizon_tau_s, scenario.limb), ()
