"""Sun and planet states from the JPL development ephemerides DE421 and DE405.

The ephemerides come from the ``de421`` and ``de405`` packages and are read with
``jplephem``'s legacy :class:`jplephem.ephem.Ephemeris` interface (those packages
ship the old per-series format, not SPK files). Positions are relative to the
solar-system barycentre (SSB), axes ICRF/J2000, in metres; velocities in m/s.

Time is seconds of TDB past J2000 (``t = 0`` is JD 2451545.0 TDB). The epoch is
passed to jplephem as the pair ``(2451545.0, t / 86400)`` so that a 30-day run at
3-s steps keeps sub-microsecond time resolution.

Bodies
------
``"sun"``, ``"mercury"``, ``"venus"``, ``"earth"``, ``"moon"``, ``"earthmoon"``,
``"mars"``, ``"jupiter"``, ``"saturn"``. ``"mars"`` and ``"jupiter"`` are the
system barycentres that the DE files tabulate; for Mars the offset from the planet's
centre caused by Phobos and Deimos is below 0.3 m and is ignored. ``"earth"`` is the
Earth-Moon barycentre minus ``moon / (1 + EMRAT)``; ``"moon"`` is the Moon's SSB
position.

Examples
--------
>>> r, v = state("mars", 0.0)
>>> r.shape, v.shape
((3,), (3,))
>>> bool(1.3 < np.linalg.norm(r) / 1.495978707e11 < 1.7)   # Mars at 1.38-1.67 au
True
"""

from __future__ import annotations

import functools

import numpy as np

from xnavlab.core import dates
from xnavlab.core.constants import DAY, J2000_JD
from xnavlab.core.validate import check_choice, check_finite_array, check_real, shown

__all__ = ["EPHEMERIDES", "BODIES", "EPOCH_RESOLUTION", "EPOCH_UNIT", "check_resolution", "check_epochs",
           "check_epoch", "state", "position", "coverage", "jd_from_t", "t_from_jd"]

#: Ephemerides that can be selected.
EPHEMERIDES = ("de421", "de405")
#: Bodies that can be asked for.
BODIES = ("sun", "mercury", "venus", "earth", "moon", "earthmoon", "mars", "jupiter", "saturn")
#: The coarsest resolution an epoch's dtype may have at the epoch's size, s (1 ms: a Mars
#: orbiter moves 3.5 m in it). float64 resolves 6e-8 s at 5e8 s; float32 32 s.
EPOCH_RESOLUTION = 1e-3
#: The epochs' unit, for the refusal of a date or a quantity with a unit where epochs belong.
EPOCH_UNIT = "s TDB past J2000"


def check_resolution(name, value, largest):
    """Refuse epochs ``value`` of a float dtype narrower than float64 that cannot resolve
    ``largest`` (s TDB past J2000, their largest magnitude) to :data:`EPOCH_RESOLUTION`.

    Refused, not converted: the values given are already rounded, so a float64 copy would
    keep the wrong times. The one rule of mars.models' and mars.timing's epoch checks.

    Examples
    --------
    >>> check_resolution("t", np.float32([5e8]), 5e8)
    Traceback (most recent call last):
    ...
    ValueError: t must resolve its epochs to 0.001 s: as float32 it resolves 32 s at 5e+08 s; ...
    """
    dtype = np.asarray(value).dtype
    if dtype.kind == "f" and dtype.itemsize < 8:
        res = float(np.spacing(dtype.type(largest)))
        if not res <= EPOCH_RESOLUTION:
            raise ValueError(f"{name} must resolve its epochs to {EPOCH_RESOLUTION:g} s: as "
                             f"{dtype} it resolves {res:.3g} s at {largest:.6g} s; pass float64 "
                             f"epochs")


def check_epochs(name, value):
    """Epochs ``value`` (s TDB past J2000, any shape) as a finite float64 array, else one
    ValueError naming ``name``: a date (datetime64) or a quantity with a unit is refused
    (:func:`xnavlab.core.validate.check_finite_array`), and so is a float dtype narrower than
    float64 that cannot resolve them to :data:`EPOCH_RESOLUTION` (:func:`check_resolution`).

    Examples
    --------
    >>> check_epochs("t", np.array(["2020-01-01"], dtype="datetime64[D]"))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: t must be plain numbers in s TDB past J2000, got datetime64[D] values: ...
    """
    t = check_finite_array(name, value, unit=EPOCH_UNIT)
    if t.size:
        check_resolution(name, value, float(np.abs(t).max()))
    return t


def check_epoch(name, value, lo=-np.inf, hi=np.inf):
    """One epoch (s TDB past J2000) as a float in ``[lo, hi]``
    (:func:`xnavlab.core.validate.check_real`; finite bounds written in full with their dates,
    :func:`xnavlab.core.dates.epoch_range`), a float32 one that cannot resolve it refused as
    :func:`check_epochs`.

    Examples
    --------
    >>> check_epoch("t0", np.float32(5e8))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: t0 must resolve its epochs to 0.001 s: as float32 it resolves 32 s at 5e+08 s; ...
    """
    try:
        t = check_real(name, value, lo, hi)
    except ValueError:
        if not np.isfinite(lo) or not np.isfinite(hi):
            raise
        raise ValueError(f"{name} must be an epoch in {dates.epoch_range(lo, hi)}, got "
                         f"{shown(value)}") from None
    check_resolution(name, value, abs(t))
    return t


_KM = 1.0e3
_KM_PER_DAY = 1.0e3 / DAY


@functools.cache
def _load(ephem):
    import importlib

    from jplephem.ephem import Ephemeris

    return Ephemeris(importlib.import_module(ephem))


def coverage(ephem="de421"):
    """First and last epoch covered by an ephemeris, s TDB past J2000.

    Examples
    --------
    >>> lo, hi = coverage("de421")
    >>> round(jd_from_t(lo), 1), round(jd_from_t(hi), 1)
    (2414992.5, 2524624.5)
    """
    check_choice("ephem", ephem, EPHEMERIDES)
    e = _load(ephem)
    return float((e.jalpha - J2000_JD) * DAY), float((e.jomega - J2000_JD) * DAY)


def jd_from_t(t):
    """Julian date (TDB) from seconds TDB past J2000.

    Examples
    --------
    >>> jd_from_t(86400.0)
    2451546.0
    """
    return J2000_JD + check_finite_array("t", t) / DAY


def t_from_jd(jd):
    """Seconds TDB past J2000 from a Julian date (TDB).

    Examples
    --------
    >>> t_from_jd(2457388.5)   # 2016-01-01 00:00 TDB
    504878400.0

    ``jd`` in [-1e15, 1e15] days (far beyond any ephemeris; the seconds stay finite).
    """
    jd = check_finite_array("jd", jd)
    if np.any(np.abs(jd) > 1e15):
        worst = jd.ravel()[np.argmax(np.abs(jd))]
        raise ValueError(f"jd must lie in [-1e+15, 1e+15] days, got {shown(worst)}")
    return (jd - J2000_JD) * DAY


def _raw(body, days, ephem):
    """Position (km) and velocity (km/day) of a tabulated series, shape (3, n)."""
    e = _load(ephem)
    return e.position_and_velocity(body, J2000_JD, days)


def _check(body, t, ephem):
    check_choice("body", body, BODIES)
    check_choice("ephem", ephem, EPHEMERIDES)
    t = check_epochs("t", t)  # float32 rounded 5e8 s to 32 s: 353 km of Mars (review 35 Q2)
    if t.ndim > 1:  # the states stack one row an epoch
        raise ValueError(f"t must be a number or a 1-D array of epochs (shape (n,)), got shape "
                         f"{t.shape}")
    lo, hi = coverage(ephem)
    if t.size and (t.min() < lo or t.max() > hi):
        raise ValueError(
            f"t must lie in {dates.epoch_range(lo, hi)}, the coverage of {ephem.upper()}; got "
            f"[{dates.epoch_text(t.min())}, {dates.epoch_text(t.max())}]"
        )
    return t


def state(body, t, ephem="de421"):
    """Position and velocity of ``body`` relative to the SSB, ICRF axes.

    Parameters
    ----------
    body : str
        One of :data:`BODIES`.
    t : float or array_like, shape (n,)
        Epochs, s TDB past J2000.
    ephem : {"de421", "de405"}
        Which ephemeris to read.

    Returns
    -------
    r : ndarray, shape (3,) or (n, 3)
        Position, m.
    v : ndarray, shape (3,) or (n, 3)
        Velocity, m/s.

    Raises
    ------
    ValueError
        If ``t`` lies outside the ephemeris's coverage, or the body or ephemeris
        is unknown.

    Examples
    --------
    >>> r, v = state("earth", [0.0, 86400.0])
    >>> r.shape
    (2, 3)
    >>> bool(29e3 < np.linalg.norm(v[0]) < 31e3)   # Earth's orbital speed, m/s
    True
    """
    t = _check(body, t, ephem)
    days = np.atleast_1d(t) / DAY
    if body == "earth":
        e = _load(ephem)
        r_emb, v_emb = _raw("earthmoon", days, ephem)
        r_moon, v_moon = _raw("moon", days, ephem)  # geocentric Moon
        r_km = r_emb - e.earth_share * r_moon
        v_kmd = v_emb - e.earth_share * v_moon
    elif body == "moon":
        e = _load(ephem)
        r_emb, v_emb = _raw("earthmoon", days, ephem)
        r_moon, v_moon = _raw("moon", days, ephem)
        r_km = r_emb + e.moon_share * r_moon
        v_kmd = v_emb + e.moon_share * v_moon
    else:
        r_km, v_kmd = _raw(body, days, ephem)
    r = (r_km * _KM).T
    v = (v_kmd * _KM_PER_DAY).T
    if t.ndim == 0:
        return r[0], v[0]
    return r, v


def position(body, t, ephem="de421"):
    """Position of ``body`` relative to the SSB, m; shape (3,) or (n, 3).

    Examples
    --------
    >>> position("sun", 0.0).shape
    (3,)
    """
    return state(body, t, ephem)[0]
