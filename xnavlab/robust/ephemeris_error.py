"""Planetary-ephemeris error and its effect on XNAV (Li et al. 2017).

An orbiter's XNAV measurement is the projection of its barycentric position on the
pulsar direction (paper eqs. (1)-(2))::

    c dt_i = n_i . (r + r_E)

with ``r`` the spacecraft position relative to the planet and ``r_E`` the planet's
position relative to the solar-system barycentre (SSB). The filter only knows the
planet's position from an ephemeris, ``r_E_hat``; the ephemeris error (paper eq. (3))

    dr_E = r_E - r_E_hat

therefore enters the measurement as the bias ``B_i = n_i . dr_E``. Following the paper,
the truth uses DE421 and the filter DE405; an injected constant or slowly drifting
offset of a chosen size can replace the DE405 error (:func:`injected_error`).

This module holds the model: the error itself (:func:`ephemeris_error`,
:func:`error_summary`), pulsar directions (:func:`pulsar_direction`), the measurement
(:func:`xnav_range`, :data:`SIGMA_M`), the planet-centred two-body + J2 dynamics
(:func:`acceleration`, :func:`propagate`) and the two scenario orbits
(:func:`orbit`). The filters are in :mod:`xnavlab.robust`.

Conventions
-----------
Measurements are in metres (``c dt``), so ``R = diag(109^2, 325^2, 340^2)`` m^2.
Pulsar directions use the standard ICRF component order
``[cos d cos a, cos d sin a, sin d]``. The paper prints
``[cos d sin a, cos d cos a, sin d]``, which swaps x and y: that vector is the mirror
image of the true direction in the plane x = y, not a rotation, so it cannot be a
different but equivalent frame convention; it is a typo (the standard order follows
from x towards the equinox, alpha = 0, and y towards alpha = 90 deg). The paper's
order can still be asked for with ``order="paper"``.

Epoch: the paper gives Table 1 "within 1997"; we use 1997-01-01 00:00 TDB
(:data:`EPOCH_1997`) for the error table and for the navigation runs.

Examples
--------
>>> dr = ephemeris_error("earth", EPOCH_1997)
>>> bool(500.0 < np.linalg.norm(dr) < 5000.0)   # DE421 - DE405, metres
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from xnavlab.core import ephemeris
from xnavlab.core.constants import (
    DAY,
    GM_EARTH,
    GM_MARS,
    J2_EARTH,
    J2_EARTH_RADIUS,
    J2_MARS,
    J2_MARS_RADIUS,
    R_EARTH,  # noqa: F401 - used by the doctest of acceleration
)
from xnavlab.core.validate import check_choice, check_finite_array, check_int, check_items, check_real, shown
from xnavlab.mars.models.dynamics import MARS_POLE, MARS_STATE0, MAX_GM, R_MAX, R_MIN
from xnavlab.mars.timing import pulsars
from xnavlab.robust._checks import check_directions, check_epoch, check_position
from xnavlab.robust._propagation import derivatives, propagate_unchecked

__all__ = [
    "EPOCH_1997",
    "YEAR",
    "PULSARS",
    "SIGMA_M",
    "EARTH_POLE",
    "PLANETS",
    "Orbit",
    "EARTH_ELEMENTS",
    "ephemeris_error",
    "error_summary",
    "PROFILES",
    "MAX_ERROR",
    "growth_profile",
    "injected_error",
    "ephemeris_drift",
    "pulsar_direction",
    "directions",
    "xnav_range",
    "acceleration",
    "MAX_SUBSTEPS",
    "propagate",
    "elements_to_state",
    "orbit",
]

#: 1997-01-01 00:00 TDB (JD 2450449.5), s past J2000: the paper's Table 1 year.
EPOCH_1997 = -94_651_200.0
#: Julian year, s.
YEAR = 365.25 * DAY
#: The three pulsars whose ranging accuracies match the paper's R (109, 325, 340 m):
#: B0531+21 (109 m), B1821-24 (326 m) and B1937+21 (345 m) at 500 s, 1 m^2, 0.005 ph/cm^2/s.
PULSARS = ("B0531+21", "B1821-24", "B1937+21")
#: The paper's measurement noise (1 sigma), m: ``R = diag(109^2, 325^2, 340^2)``.
SIGMA_M = (109.0, 325.0, 340.0)
#: Earth's pole for J2 (the J2000 z axis; precession is neglected).
EARTH_POLE = np.array([0.0, 0.0, 1.0])
#: Planet constants: GM (m^3/s^2), J2, the J2's reference radius (m), pole (ICRF unit vector).
PLANETS = {
    "earth": (GM_EARTH, J2_EARTH, J2_EARTH_RADIUS, EARTH_POLE),
    "mars": (GM_MARS, J2_MARS, J2_MARS_RADIUS, MARS_POLE),
}


def ephemeris_error(body, t, truth="de421", model="de405"):
    """Ephemeris error ``dr_E = r_E(truth) - r_E(model)`` of a planet, m (paper eq. (3)).

    Parameters
    ----------
    body : {"earth", "mars"}
        Planet (Mars is the Mars-system barycentre, see :mod:`xnavlab.core.ephemeris`).
    t : float or array_like, shape (n,)
        Epochs, s TDB past J2000.
    truth, model : {"de421", "de405"}
        The ephemeris taken as truth and the one the filter uses.

    Returns
    -------
    ndarray, shape (3,) or (n, 3)
        SSB-relative position difference, ICRF axes, m.

    Examples
    --------
    >>> ephemeris_error("mars", [EPOCH_1997, EPOCH_1997 + 3600.0]).shape
    (2, 3)
    """
    check_choice("body", body, tuple(PLANETS))
    check_choice("truth", truth, ephemeris.EPHEMERIDES)  # by the user's names, not the ephemeris'
    check_choice("model", model, ephemeris.EPHEMERIDES)
    return ephemeris.position(body, t, truth) - ephemeris.position(body, t, model)


def error_summary(body, t0=EPOCH_1997, span=DAY, n=97):
    """Mean, maximum and end-minus-start norm of the DE421 - DE405 error over a span.

    The idea of the paper's Table 1 (values lost): the mean error over 24 h and over
    one year.

    Parameters
    ----------
    body : {"earth", "mars"}
    t0 : float
        Start, s TDB past J2000 (default 1997-01-01), within the years DE421 and DE405 both
        cover (1900-2199).
    span : float
        Length, s (positive, at most 10 years; ``t0 + span`` within the ephemerides too).
    n : int
        Number of samples (at least 2).

    Returns
    -------
    dict
        ``mean_m``, ``max_m``, ``change_m`` (``|dr(t0+span)| - |dr(t0)|``), ``t`` (n,)
        and ``norm`` (n,) in m.

    Examples
    --------
    >>> s = error_summary("earth")
    >>> bool(s["max_m"] >= s["mean_m"] > 0)
    True
    """
    check_choice("body", body, tuple(PLANETS))
    span = check_real("span", span, 0.0, 10 * YEAR, lo_open=True)
    t0 = check_epoch("t0", t0, span, "span")  # named as given, not as the ephemeris' t
    n = check_int("n", n, 2, 10**6)
    t = t0 + np.linspace(0.0, span, n)
    norm = np.linalg.norm(ephemeris_error(body, t), axis=1)
    return {"mean_m": float(norm.mean()), "max_m": float(norm.max()),
            "change_m": float(norm[-1] - norm[0]), "t": t, "norm": norm}


#: Time profiles of the growing injected error (:func:`growth_profile`), ``f(0) = 0``, ``f(1) = 1``.
PROFILES = ("linear", "quadratic", "sqrt")


def growth_profile(s, profile="linear"):
    """Fraction of its final size a growing error has reached, ``f(s)`` for ``s >= 0``.

    Parameters
    ----------
    s : float or array_like
        Time since the error started, as a fraction of the time at which it reaches its
        full size (``s = 1``); negative values give 0 (the error has not started).
    profile : {"linear", "quadratic", "sqrt"} or callable
        ``s``, ``s^2`` or ``sqrt(s)``; a callable ``f`` must be vectorised with
        ``f(0) = 0`` and ``f(1) = 1`` (checked) and finite values.

    Returns
    -------
    ndarray, same shape as ``s``

    Examples
    --------
    >>> growth_profile([0.0, 0.25, 1.0], "sqrt").tolist()
    [0.0, 0.5, 1.0]
    """
    s = np.clip(check_finite_array("s", s), 0.0, None)
    if callable(profile):
        ends = np.asarray(profile(np.array([0.0, 1.0])), dtype=float)
        if ends.shape != (2,) or not np.allclose(ends, [0.0, 1.0], rtol=0.0, atol=1e-9):
            raise ValueError("profile must be a vectorised callable with f(0) = 0 and f(1) = 1")
        out = np.asarray(profile(s), dtype=float)
        if out.shape != s.shape or not np.all(np.isfinite(out)):
            raise ValueError("profile must return finite values of the shape of its argument")
        return out
    check_choice("profile", profile, PROFILES)
    if profile == "linear":
        return s
    return s * s if profile == "quadratic" else np.sqrt(s)


def injected_error(t, size, kind="constant", direction=(1.0, 1.0, 1.0), t0=0.0, period=YEAR,
                   growth_time=None, profile="linear"):
    """A synthetic ephemeris error of a chosen size, m (Figs. 4 and 8, and the growing error).

    Parameters
    ----------
    t : float or array_like, shape (n,)
        Epochs, s TDB past J2000 (float64: a float32 array, which rounds 5e8 s to 32 s, is
        refused).
    size : float
        Magnitude, m, in [0, 1e8] (an ephemeris error of 100,000 km; as
        :func:`~xnavlab.robust.filters.simulate`).
    kind : {"constant", "slow", "growing"}
        ``"constant"``: ``size * u``; ``"slow"``: ``size * u * (1 + 0.2 sin(2 pi (t - t0) / period))``,
        a slowly varying error of the DE405-DE421 kind (about 20 % over a year);
        ``"growing"``: ``size * u * f((t - t0) / growth_time)``, zero at ``t0`` and ``size``
        at ``t0 + growth_time`` (the paper's error that "keeps increasing with time";
        ``f`` is :func:`growth_profile`). Past ``t0 + growth_time`` it keeps growing (it is
        not held at ``size``), so ``size`` is its size at ``t0 + growth_time``, not its
        largest; an error that would exceed :data:`MAX_ERROR` (1e8 m, the range of ``size``)
        at some epoch ``t`` is refused, naming growth_time (the chapter's runs take
        ``growth_time`` = the run's span, where the error ends at ``size``).
    direction : array_like, shape (3,)
        Direction ``u`` (normalised here; must be non-zero).
    t0 : float
        For ``"growing"`` and ``"slow"``: reference epoch (start of the growth, phase of the
        slow variation), s TDB past J2000, within the years DE421 and DE405 both cover
        (1900-2199); ``"constant"`` refuses any but the default.
    period : float
        For ``"slow"``: period of the slow variation, s, at least 1; another kind refuses
        any but the default (a year).
    growth_time : float, optional
        For ``"growing"``: time after ``t0`` at which the error reaches ``size``, s, in
        [1, 1e12] (required), and long enough that the error stays within :data:`MAX_ERROR`
        over the epochs ``t``.
    profile : str or callable
        For ``"growing"``: the time profile ``f`` (see :func:`growth_profile`).

    Returns
    -------
    ndarray, shape (3,) or (n, 3)

    Examples
    --------
    >>> round(float(np.linalg.norm(injected_error(0.0, 100.0))), 9)
    100.0
    >>> g = injected_error([0.0, 50.0, 100.0], 10.0, "growing", (0, 0, 1), growth_time=100.0)
    >>> g[:, 2].tolist()
    [0.0, 5.0, 10.0]
    """
    size = check_real("size", size, 0.0, 1e8)  # as filters.simulate's
    check_choice("kind", kind, ("constant", "slow", "growing"))
    if kind != "growing":  # settings this kind would not use (as filters.simulate refuses them)
        for name, value, default in (("growth_time", growth_time, None), ("profile", profile, "linear")):
            if value is not default and not (isinstance(value, str) and value == default):
                raise ValueError(f"{name} shapes a growing error only (kind='growing'), got kind = "
                                 f"{kind!r}; leave {name} out")
    for name, value, default, kinds in (("t0", t0, 0.0, ("growing", "slow")), ("period", period, YEAR,
                                                                             ("slow",))):
        if kind not in kinds and not _is_number(value, default):  # unused by this kind: refused
            raise ValueError(f"{name} shapes a {' or '.join(kinds)} error only (kind={kinds[0]!r}"
                             f"{'' if len(kinds) == 1 else f' or {kinds[1]!r}'}), got kind = "
                             f"{kind!r}; leave {name} out")
    u = check_finite_array("direction", direction, shape=(3,))
    norm = float(np.linalg.norm(u))
    if norm == 0.0:
        raise ValueError("direction must be a non-zero 3-vector")
    period = check_real("period", period, 1.0)  # from a second: 5e-324 overflowed (t - t0) / period
    t0, given = check_epoch("t0", t0), t0  # 1e300 put every t before the onset (zero throughout)
    ephemeris.check_resolution("t0", given, abs(t0))  # a float32 t0 rounded by 32 s
    t = ephemeris.check_epochs("t", t)  # float32, datetime64 or a Quantity refused (review 35 Q1, Q2)
    scale = np.full(t.shape, size)
    if kind == "slow":
        scale = size * (1.0 + 0.2 * np.sin(2.0 * math.pi * (t - t0) / period))
    elif kind == "growing":
        if growth_time is None:
            raise ValueError("growth_time must be given (s > 0) for a growing error")
        # from a second (a faster growth is a step; 1e-300 overflowed (t - t0) / growth_time)
        growth_time = check_real("growth_time", growth_time, 1.0, 1e12)
        scale = size * growth_profile((t - t0) / growth_time, profile)  # |dr_E(t)| = size f(s)
        _check_growth(scale, t - t0, size, growth_time, profile)
    return scale[..., None] * (u / norm)


#: The largest injected error, m: the bound of ``size`` (an ephemeris error of 100,000 km), which a
#: growing error must keep to over its run too (a small ``growth_time`` made 1e20 m).
MAX_ERROR = 1e8


def _check_growth(scale, since, size, growth_time, profile):
    """Refuse a growing error whose norm ``scale = size f((t - t0) / growth_time)`` exceeds
    :data:`MAX_ERROR` at some epoch (``since = t - t0``), naming growth_time, size and the span."""
    scale = np.abs(scale)  # a callable profile may go negative
    if scale.size == 0 or float(np.max(scale)) <= MAX_ERROR * (1.0 + 1e-9):  # rounding of s = 1
        return
    k = int(np.argmax(scale))
    span, ratio = float(np.max(since)), MAX_ERROR / size
    need = {"linear": span / ratio, "quadratic": span / math.sqrt(ratio), "sqrt": span / ratio**2}
    hint = (f"; growth_time >= {need[profile]:.6g} s keeps it" if isinstance(profile, str) else "")
    raise ValueError(f"growth_time must keep the growing error within {MAX_ERROR:g} m (the size range) "
                     f"over the run's span t - t0 <= {span:.6g} s: with size = {size:g} m, growth_time = "
                     f"{growth_time:g} s it reaches {float(scale.flat[k]):.6g} m at t - t0 = "
                     f"{float(since.flat[k]):.6g} s{hint}")


def _is_number(value, default):
    """Whether ``value`` is the real number ``default`` (a setting left at its default)."""
    return (not isinstance(value, bool) and isinstance(value, int | float | np.integer | np.floating)
            and value == default)


def ephemeris_drift(body, t, t_ref, truth="de421", model="de405"):
    """The real ephemeris error's change since ``t_ref``: ``dr_E(t) - dr_E(t_ref)``, m.

    The DE421 - DE405 difference as it evolves, with its value at ``t_ref`` removed (what
    a filter whose ephemeris was corrected at ``t_ref`` would meet): zero at ``t_ref``
    and growing by metres per day (see :func:`error_summary`).

    Parameters
    ----------
    body : {"earth", "mars"}
    t : float or array_like, shape (n,)
        Epochs, s TDB past J2000.
    t_ref : float
        Reference epoch, s TDB past J2000.
    truth, model : {"de421", "de405"}

    Returns
    -------
    ndarray, shape (3,) or (n, 3)

    Examples
    --------
    >>> float(np.linalg.norm(ephemeris_drift("earth", EPOCH_1997, EPOCH_1997)))
    0.0
    """
    t_ref, given = check_epoch("t_ref", t_ref), t_ref
    ephemeris.check_resolution("t_ref", given, abs(t_ref))  # a float32 t_ref rounded by 32 s
    return ephemeris_error(body, t, truth, model) - ephemeris_error(body, t_ref, truth, model)


def pulsar_direction(ra_deg, dec_deg, order="standard"):
    """Unit vector to a pulsar from J2000 right ascension and declination.

    Parameters
    ----------
    ra_deg, dec_deg : float
        Right ascension and declination, degrees.
    order : {"standard", "paper"}
        ``"standard"``: ``[cos d cos a, cos d sin a, sin d]`` (ICRF, used throughout);
        ``"paper"``: the paper's printed ``[cos d sin a, cos d cos a, sin d]`` (x and y
        swapped, a mirror image; kept only to show the difference).

    Returns
    -------
    ndarray, shape (3,)

    Examples
    --------
    >>> np.round(pulsar_direction(90.0, 0.0), 12).tolist()
    [0.0, 1.0, 0.0]
    >>> np.round(pulsar_direction(90.0, 0.0, order="paper"), 12).tolist()
    [1.0, 0.0, 0.0]
    """
    a = math.radians(check_real("ra_deg", ra_deg, 0.0, 360.0))
    d = math.radians(check_real("dec_deg", dec_deg, -90.0, 90.0))
    check_choice("order", order, ("standard", "paper"))
    if order == "paper":
        return np.array([math.cos(d) * math.sin(a), math.cos(d) * math.cos(a), math.sin(d)])
    return np.array([math.cos(d) * math.cos(a), math.cos(d) * math.sin(a), math.sin(d)])


def directions(names=PULSARS, order="standard"):
    """Pulsar directions as rows, shape (k, 3): the matrix ``N`` of ``z = N (r + r_E)``.

    Examples
    --------
    >>> directions().shape
    (3, 3)
    """
    names = check_items("names", names, "pulsar")
    rows = []
    for name in names:
        p = pulsars.get(name)
        rows.append(pulsar_direction(p.ra_deg, p.dec_deg, order))
    return np.array(rows)


def xnav_range(r, r_planet, n):
    """XNAV measurement in metres, ``c dt_i = n_i . (r + r_E)`` (paper eqs. (1)-(2)).

    Parameters
    ----------
    r : array_like, shape (..., 3)
        Spacecraft position relative to the planet, m.
    r_planet : array_like, shape (..., 3)
        Planet position relative to the SSB, m (broadcast against ``r``).
    n : array_like, shape (k, 3)
        Pulsar directions (unit rows, to 1e-6: a row of norm k would scale its range by k).

    Returns
    -------
    ndarray, shape (..., k)
        Ranges ``c dt``, m.

    Examples
    --------
    >>> xnav_range([1.0, 2.0, 3.0], np.zeros(3), np.eye(3)).tolist()
    [1.0, 2.0, 3.0]
    """
    r = check_finite_array("r", r, shape=(3,))
    r_planet = check_finite_array("r_planet", r_planet, shape=(3,))
    n = check_directions("n", n)  # (k, 3), one pulsar a row
    return (r + r_planet) @ n.T  # paper eq. (1): c dt = n . (r + r_E)


def acceleration(r, body="earth"):
    """Two-body + J2 acceleration in the planet-centred J2000 frame, m/s^2 (paper eq. (5)).

    ``a = -mu r / |r|^3 - 3/2 J2 mu R^2 / |r|^5 [(1 - 5 z^2/|r|^2) r + 2 z p]``, ``z = r . p``,
    with ``R`` the reference radius of the J2 (:data:`PLANETS`).

    Parameters
    ----------
    r : array_like, shape (3,) or (k, 3)
        Position, m, between the planet's radius (:data:`PLANETS`) and 1e15 m from its centre
        (the model is the planet's field outside it).
    body : {"earth", "mars"}

    Examples
    --------
    >>> a = acceleration([R_EARTH, 0.0, 0.0])
    >>> bool(9.8 < -a[0] < 9.85)
    True
    """
    check_choice("body", body, tuple(PLANETS))
    gm, j2, radius, pole = PLANETS[body]
    r = check_position("r", r, radius, body)  # the planet's field outside it only
    X = np.zeros(r.shape[:-1] + (6,))
    X[..., :3] = r
    return derivatives(np.atleast_2d(X), gm, j2, radius, pole)[:, 3:].reshape(r.shape)


#: The most RK4 steps :func:`propagate` takes over one ``dt`` (``ceil(|dt| / substep)``): a
#: second or so per state, far more than any accuracy needs (the default takes 25 over 500 s).
MAX_SUBSTEPS = 10**7


def propagate(x, dt, body="earth", substep=20.0):
    """Propagate states over ``dt`` with fixed-step RK4 of the two-body + J2 model.

    Parameters
    ----------
    x : array_like, shape (6,) or (k, 6)
        States ``[r, v]``, m and m/s (rows are propagated together, e.g. sigma points);
        ``r`` outside the planet (as :func:`acceleration`'s).
    dt : float
        Time step, s (may be negative, ``|dt| <= 1e6``).
    body : {"earth", "mars"}
    substep : float
        Largest RK4 step, s, in (0, 1e5]; ``dt`` is split into ``ceil(|dt| / substep)`` equal
        steps, at most :data:`MAX_SUBSTEPS` (``substep >= |dt| / 1e7``). 20 s keeps the error
        over one orbit (12 h Earth, 2.3 h Mars) below 0.1 m.

    Returns
    -------
    ndarray, same shape as ``x``

    Examples
    --------
    >>> x0 = orbit("earth").state0
    >>> x1 = propagate(propagate(x0, 500.0), -500.0)
    >>> bool(np.allclose(x1, x0, atol=1e-6))
    True
    """
    check_choice("body", body, tuple(PLANETS))
    x = check_finite_array("x", x, shape=(6,))
    dt = check_real("dt", dt, -1e6, 1e6)
    substep = check_real("substep", substep, 0.0, 1e5, lo_open=True)
    if abs(dt) / substep > MAX_SUBSTEPS:  # 5e-324 overflowed the count (and 1e-9 ran for hours)
        raise ValueError(f"substep must be at least |dt| / {MAX_SUBSTEPS:.0e} = "
                         f"{abs(dt) / MAX_SUBSTEPS:.6g} s (at most {MAX_SUBSTEPS:.0e} RK4 steps over "
                         f"dt = {dt:g} s), got {substep:g}")
    check_position("x[:3]", x[..., :3], PLANETS[body][2], body)  # the planet's field outside it only
    return propagate_unchecked(x, dt, PLANETS[body], substep)


def elements_to_state(a, e, i_deg, raan_deg, argp_deg, nu_deg, gm, radius=None):
    """Cartesian state from Keplerian elements, m and m/s.

    Parameters
    ----------
    a : float
        Semi-major axis, m, in [R_MIN, R_MAX] (:data:`xnavlab.mars.models.dynamics.R_MIN`, 1 m:
        a subnormal axis gave a state of subnormal position and overflowing speed), and with
        the whole orbit outside the central body and within R_MAX of its centre: the perigee
        ``a (1 - e)`` at least ``radius``, the apogee ``a (1 + e)`` at most R_MAX (the
        distances :func:`propagate` and :func:`acceleration` accept).
    e : float
        Eccentricity, ``0 <= e < 1``.
    i_deg, raan_deg, argp_deg, nu_deg : float
        Inclination, right ascension of the ascending node, argument of periapsis and
        true anomaly, degrees, in [-360, 360] (in the frame of the planet-centred J2000 axes).
    gm : float
        Gravitational parameter, m^3/s^2.
    radius : float, optional
        Radius of the central body, m, in [R_MIN, R_MAX]: the perigee's lower bound. Default:
        that of the planet of :data:`PLANETS` whose GM is ``gm`` (the reference radius of its
        J2, as :func:`propagate` bounds ``|r|``); required for another ``gm`` (refused
        without it, naming gm).

    Returns
    -------
    ndarray, shape (6,)

    Examples
    --------
    >>> x = elements_to_state(7e6, 0.0, 0.0, 0.0, 0.0, 0.0, GM_EARTH)
    >>> round(float(x[4]), 3) == round(math.sqrt(GM_EARTH / 7e6), 3)
    True
    """
    return _state_of((a, e, i_deg, raan_deg, argp_deg, nu_deg), gm,
                     ("a", "e", "i_deg", "raan_deg", "argp_deg", "nu_deg"), radius=radius)


def _state_of(elements, gm, names, body=None, radius=None):
    """:func:`elements_to_state` of the six ``elements``, each checked under its ``names`` entry,
    the orbit between the radius of the planet ``body`` (default: the planet of ``gm``; or
    ``radius``, given) and R_MAX."""
    a = check_real(names[0], elements[0], R_MIN, R_MAX)  # the distances a state may have (dynamics.R_MIN)
    e = check_real(names[1], elements[1], 0.0, 1.0, hi_open=True)
    gm = check_real("gm", gm, 0.0, MAX_GM, lo_open=True)
    i, raan, argp, nu = (math.radians(check_real(n, v, -360.0, 360.0)) for n, v in
                         zip(names[2:], elements[2:], strict=True))
    if radius is not None:
        radius, body = check_real("radius", radius, R_MIN, R_MAX), "the central body"
    else:
        body = body or next((b for b, planet in PLANETS.items() if planet[0] == gm), None)
        if body is None:
            raise ValueError(f"gm must be earth's or mars' ({PLANETS['earth'][0]:g} or "
                             f"{PLANETS['mars'][0]:g} m^3/s^2) unless radius (the central body's "
                             f"radius, m) is given, got {gm:g}")
        radius = PLANETS[body][2]
    if a * (1.0 - e) < radius:  # the orbit through the planet: its field is the one outside it only
        raise ValueError(f"{names[0]} must put the perigee {names[0]} (1 - {names[1]}) at or above the "
                         f"radius of {body} ({radius:g} m): {names[0]} >= {radius / (1.0 - e):.6g} m with "
                         f"{names[1]} = {e:g}, got {a:g}")
    if a * (1.0 + e) > R_MAX:  # as propagate's bound on |r|
        raise ValueError(f"{names[0]} must keep the apogee {names[0]} (1 + {names[1]}) within {R_MAX:g} m "
                         f"of the centre: {names[0]} <= {R_MAX / (1.0 + e):.6g} m with {names[1]} = {e:g}, "
                         f"got {a:g}")
    p = a * (1.0 - e * e)
    rn = p / (1.0 + e * math.cos(nu))
    r_pf = np.array([rn * math.cos(nu), rn * math.sin(nu), 0.0])
    v_pf = math.sqrt(gm / p) * np.array([-math.sin(nu), e + math.cos(nu), 0.0])
    cO, sO, ci, si, cw, sw = (math.cos(raan), math.sin(raan), math.cos(i), math.sin(i),
                              math.cos(argp), math.sin(argp))
    rot = np.array([
        [cO * cw - sO * sw * ci, -cO * sw - sO * cw * ci, sO * si],
        [sO * cw + cO * sw * ci, -sO * sw + cO * cw * ci, -cO * si],
        [sw * si, cw * si, ci],
    ])
    return np.concatenate([rot @ r_pf, rot @ v_pf])


@dataclass(frozen=True)
class Orbit:
    """A navigation scenario: planet, initial state and epoch.

    Attributes
    ----------
    body : str
        ``"earth"`` or ``"mars"``.
    state0 : ndarray, shape (6,)
        Initial planet-centred J2000 state, m and m/s.
    t0 : float
        Initial epoch, s TDB past J2000.
    name : str
        Label.
    source : str
        Where the elements come from.
    """

    body: str
    state0: np.ndarray
    t0: float
    name: str
    source: str


#: Elements of the Earth orbit (a m, e, i, RAAN, argp, nu in degrees).
EARTH_ELEMENTS = (26_560e3, 0.01, 63.0, 0.0, 0.0, 0.0)


def orbit(body="earth", t0=EPOCH_1997, elements=None):
    """The scenario orbit of the paper for ``body`` (elements adjustable).

    Earth: "OPS_5111" of Wang et al. (2014). OPS 5111 is the military designation of
    NAVSTAR 1, the first GPS Block I satellite; its elements were not recoverable from
    the sources at hand, so we use representative Block I elements: a = 26,560 km,
    e = 0.01, i = 63 deg (period 11.97 h). Mars: the orbit of Wei et al. (2013) could
    not be recovered either; we use the Mars orbit of the main paper
    (:data:`xnavlab.mars.models.dynamics.MARS_STATE0`: a = 4196 km, e = 0.09, i = 75 deg,
    period 2.29 h) so that the book has one Mars orbit.

    Parameters
    ----------
    body : {"earth", "mars"}
    t0 : float
        Epoch, s TDB past J2000, within the years DE421 and DE405 both cover (1900-2199).
    elements : sequence of 6 floats, optional
        ``(a_m, e, i_deg, raan_deg, argp_deg, nu_deg)`` replacing the default orbit, each in
        :func:`elements_to_state`'s range (named ``elements[i]``): the perigee
        ``a (1 - e)`` at or above the planet's radius (:data:`PLANETS`).

    Returns
    -------
    Orbit

    Examples
    --------
    >>> o = orbit("earth")
    >>> round(float(np.linalg.norm(o.state0[:3])) / 1e3)
    26294
    """
    check_choice("body", body, tuple(PLANETS))
    t0 = check_epoch("t0", t0)
    gm = PLANETS[body][0]
    if elements is not None:
        el = check_finite_array("elements", elements, finite=False)
        if el.shape != (6,):
            raise ValueError(f"elements must be (a_m, e, i_deg, raan_deg, argp_deg, nu_deg), 6 numbers, "
                             f"got {shown(elements)}")
        return Orbit(body, _state_of(el, gm, [f"elements[{i}]" for i in range(6)], body), t0,
                     f"{body} (user elements)", "user")
    if body == "earth":
        return Orbit(body, elements_to_state(*EARTH_ELEMENTS, gm), t0, "OPS_5111 (representative)",
                     "representative GPS Block I elements (OPS 5111 = NAVSTAR 1)")
    return Orbit(body, MARS_STATE0.copy(), t0, "Mars orbiter",
                 "Fan et al. 2016 initial state (xnavlab.mars.models.dynamics.MARS_STATE0)")
