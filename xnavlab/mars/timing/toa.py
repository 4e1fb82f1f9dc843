"""The time-transfer (TOA) equation of X-ray pulsar navigation and its gradient.

A pulse reaches the spacecraft earlier than the solar-system barycentre (SSB) by

.. math::

   \\Delta t = \\frac{n \\cdot R}{c}
   + \\frac{(n \\cdot R)^2 - |R|^2}{2 c D_0}
   + \\frac{2 \\mu_\\odot}{c^3} \\ln \\frac{n \\cdot x + |x|}{n \\cdot b + |b|}

with ``R`` the spacecraft position relative to the SSB (``R = r_M + r``: ``r``
planet-centred, ``r_M`` the planet relative to the SSB), ``n`` the unit vector to the
pulsar, ``D0`` its distance, ``x = R - r_sun`` the spacecraft seen from the Sun and
``b = -r_sun`` the SSB seen from the Sun. The three terms are the Roemer delay
(geometry), the parallax (curvature of the wavefront) and the Shapiro delay (the Sun's
gravity), each available on its own.

The Shapiro delay comes in two forms, chosen by the keyword ``shapiro`` of
:func:`delay`, :func:`gradient` and :func:`terms`:

- ``"exact"`` (the default, :func:`shapiro`): the logarithm above, the light-time
  through the Sun's field from the pulsar to the spacecraft minus the same to the SSB
  (Backer & Hellings 1986, eq. 4.6, with gamma = 1);
- ``"paper"`` (:func:`shapiro_paper`): the form of the main paper's eq. (1) (Fan et al.
  2016, after Sheikh et al. 2006), ``ln|(n.R + |R|)/(n.b + |b|) + 1|``, which puts the
  SSB-relative ``R`` where the Sun-relative ``x`` belongs. Seen from Mars (1990-2030,
  DE421) it differs from the exact form by up to 0.3 us for a pulsar 50 degrees or more
  from the Sun (0.9-5.1 ns for the paper's four pulsars over its 30 days), up to 26 us at
  2.3 degrees and 72 us at 0.22 degree. Everything that reproduces the paper (the Mars
  scenario, its compiled filter, the reproductions) uses it explicitly.

Both are referred to the SSB: zero for a spacecraft at the SSB. PINT and Tempo2 refer
theirs to 1 au instead; :func:`shapiro_offset_to_pint` is the difference.

The delays compare times on one scale, TDB. A clock on board keeps its proper time,
which drifts from TDB: :func:`proper_time_terms` gives the rate (about +5.5e-9 to
+6.6e-9 for a Mars orbiter: with Mars over its year, or on the paper's orbit), the Mars-year
term (22-23 ms peak to peak, by how the mean rate is fitted) and the orbit-periodic term
``-V_Mars . r / c^2`` (-718 to +656 ns on the paper's orbit). Chapter 2 measures each
(:mod:`xnavlab.mars.timing.timing_terms`).

Shapes broadcast: ``R`` has shape (..., 3), ``n`` shape (k, 3) and ``D0`` shape (k,);
results have shape (..., k) (delays, s) or (..., k, 3) (gradients, s/m).

Examples
--------
>>> n = np.array([[1.0, 0.0, 0.0]])
>>> float(roemer(np.array([299792458.0, 0.0, 0.0]), n)[0])
1.0
"""

from __future__ import annotations

import numpy as np

from xnavlab.core import ephemeris
from xnavlab.core.constants import AU, GM_SUN, C
from xnavlab.core.validate import (
    check_choice,
    check_finite_array,
    check_int,
    check_items,
    check_real,
    check_shape,
)
from xnavlab.mars.timing import _checks, pulsars
from xnavlab.mars.timing._checks import check_broadcast, check_outside

__all__ = [
    "roemer",
    "parallax",
    "shapiro",
    "shapiro_paper",
    "SHAPIRO_FORMS",
    "shapiro_offset_to_pint",
    "delay",
    "gradient",
    "terms",
    "delays_at",
    "L_B",
    "GM_DE421",
    "proper_time_terms",
    "pdop",
    "gradient_fd",
    "plot_orbit_terms",
]


#: The farthest spacecraft from the SSB, m (6,700 au, Voyager 1 is at 170); (n . R)^2 of the
#: parallax overflows near 1e154 m.
_MAX_R = 1e15
#: The Sun's (or, for timing_terms.planet_shapiro, a planet's) distance from the SSB, m: at
#: least 1 m (at 0 the Shapiro delay to the SSB is the log of 0), at most _MAX_R.
_SUN_SSB = (1.0, _MAX_R)


def _norm_in(name, v, lo, hi, why):
    """``v`` (..., 3) if every ``|v|`` is in ``[lo, hi]``, else one ValueError naming ``name``."""
    with np.errstate(over="ignore", under="ignore"):  # beyond float64: refused below
        vn = np.linalg.norm(v, axis=-1)
    out = (vn < lo) | (vn > hi)
    if np.any(out):
        raise ValueError(f"{name} must have a norm in [{lo:g}, {hi:g}] m ({why}), got "
                         f"{float(vn[out].ravel()[0]):.6g} m")
    return v


def _args(r_ssb, n):
    r_ssb = _norm_in("r_ssb", check_finite_array("r_ssb", r_ssb, shape=(3,)), 0.0, _MAX_R,
                     "a spacecraft within 6,700 au of the SSB")
    given, n = n, check_finite_array("n", n, shape=(3,))
    if n.ndim != 2:
        raise ValueError(f"n must have shape (k, 3), got {n.shape}")
    with np.errstate(over="ignore"):  # a norm beyond float64 is no unit vector: refused below
        norms = np.linalg.norm(n, axis=-1)
    if np.any(~(np.abs(norms - 1.0) <= 1e-9)):
        i = int(np.argmax(~(np.abs(norms - 1.0) <= 1e-9)))
        dtype, off = np.asarray(given).dtype, float(norms[i] - 1.0)
        if dtype.kind == "f" and dtype.itemsize < 8 and abs(off) <= 10.0 * np.finfo(dtype).eps:
            # float32 rounds each component by 6e-8: 13 km of n . R at 1.5 au (review 35 Q20)
            half = 0.5 * float(np.finfo(dtype).eps)  # relative rounding of a component
            raise ValueError(f"n must hold float64 unit vectors (|n| = 1 within 1e-9), got {dtype}, whose "
                             f"rounding ({half:.2g} a component; |n[{i}]| - 1 = {off:.2g}) moves n . R "
                             f"at 1.5 au by up to {half * 1.5 * AU / 1e3:.2g} km: pass float64 directions")
        raise ValueError(f"n must hold unit vectors (|n| = 1 within 1e-9), got |n[{i}]| = "
                         f"{float(norms[i]):.10g}")
    return r_ssb, n


def _distance(distance, k):
    d = check_finite_array("distance", distance)
    d = np.broadcast_to(d, (k,)) if d.ndim == 0 else d
    if d.shape != (k,):
        raise ValueError(f"distance must be a scalar or have shape ({k},), got shape {np.shape(distance)}")
    low = pulsars.MAX_DISTANCE * 1e-6  # 1 pc: no pulsar is nearer (1 / D overflowed at 5e-324)
    out = (d < low) | (d > pulsars.MAX_DISTANCE)
    if np.any(out):
        raise ValueError(f"distance must be in [{low:.3g}, {pulsars.MAX_DISTANCE:.3g}] m (1 pc to "
                         f"pulsars.MAX_DISTANCE), got {float(d[out][0]):.6g}")
    return d


def roemer(r_ssb, n):
    """Roemer delay ``n . R / c``, s; shape (..., k).

    Examples
    --------
    >>> roemer(np.zeros(3), np.eye(3)).tolist()
    [0.0, 0.0, 0.0]
    """
    r_ssb, n = _args(r_ssb, n)
    return r_ssb @ n.T / C  # paper eq. (1), first term


def parallax(r_ssb, n, distance):
    """Parallax delay ``[(n . R)^2 - |R|^2] / (2 c D0)``, s; shape (..., k).

    Always <= 0: the wavefront is a sphere centred on the pulsar, not a plane. ``distance``
    (m, a scalar or one per pulsar) is in [1 pc, :data:`~xnavlab.mars.timing.pulsars.MAX_DISTANCE`],
    as in every function here that takes it (no pulsar is nearer than 1 pc).

    Examples
    --------
    >>> float(parallax(np.array([0.0, 1e11, 0.0]), np.array([[1.0, 0, 0]]), 1e20)[0]) < 0
    True
    """
    r_ssb, n = _args(r_ssb, n)
    d = _distance(distance, n.shape[0])
    nr = r_ssb @ n.T
    rr = np.sum(r_ssb * r_ssb, axis=-1)[..., None]
    return (nr**2 - rr) / (2.0 * C * d)  # paper eq. (1), second term


def _b(r_sun_ssb):
    """SSB position relative to the Sun: b = -r_sun."""
    r_sun = check_finite_array("r_sun_ssb", r_sun_ssb, shape=(3,))
    return -_norm_in("r_sun_ssb", r_sun, *_SUN_SSB, "the Sun's centre is never on the SSB; "
                     "at 0 the delay to the SSB is the log of 0")


def _sun_x(r_ssb, b):
    """The spacecraft seen from the Sun, ``x = R - r_sun``, at least 1 m from its centre (at 0
    the delay is the log of 0; for a planet the spacecraft may orbit close)."""
    check_broadcast("r_sun_ssb", b, "r_ssb", r_ssb, "one Sun position per spacecraft position")
    x = r_ssb + b
    xn = np.linalg.norm(x, axis=-1)  # finite: |r_ssb|, |r_sun_ssb| <= 1e15 m
    if np.any(xn < 1.0):
        raise ValueError(f"r_ssb must be at least 1 m from the Sun's centre, |r_ssb - r_sun_ssb| >= "
                         f"1 m (the delay is the log of 0 there), got {float(xn[xn < 1.0].ravel()[0]):.6g} m")
    return x


#: The two forms of the Shapiro delay (the keyword ``shapiro`` of :func:`delay` and others).
SHAPIRO_FORMS = ("exact", "paper")

_T_SUN = 2.0 * GM_SUN / C**3  # 2 mu / c^3, s


def _log_arg(v, n):
    """``n . v + |v|`` for rows ``n``, shape (..., k), without cancellation.

    When ``n . v < 0`` the sum cancels (the direction ``n`` nearly opposite ``v``);
    there it is evaluated as ``|n x v|^2 / (|v| - n . v)``, the same number, from the
    cross product.
    """
    nv = v @ n.T
    vn = np.linalg.norm(v, axis=-1)[..., None]
    cross2 = np.sum(np.cross(v[..., None, :], n) ** 2, axis=-1)
    out = np.where(nv >= 0.0, nv + vn, cross2 / np.where(nv >= 0.0, 1.0, vn - nv))
    if np.any(out <= 0.0):
        raise ValueError("n: a pulsar lies exactly behind the Sun's centre as seen from the spacecraft "
                         "or the SSB (n . v = -|v|): the Shapiro delay is infinite there")
    return out


def shapiro(r_ssb, n, r_sun_ssb):
    """Shapiro delay, exact form: ``2 mu/c^3 ln[(n.x + |x|)/(n.b + |b|)]``, s; shape (..., k).

    ``x = r_ssb - r_sun_ssb`` is the spacecraft seen from the Sun and ``b = -r_sun_ssb``
    the SSB seen from the Sun: the Sun's Shapiro delay on the way to the spacecraft
    minus the same on the way to the SSB, with our sign (positive when the spacecraft
    is nearer the pulsar's side of the Sun, where the pulse arrives earlier). Both
    sums are evaluated without cancellation (see ``n . v + |v|`` in the module
    source), so a pulsar close behind the Sun keeps full precision.

    Parameters
    ----------
    r_ssb : array_like, shape (..., 3)
        Spacecraft position relative to the SSB, m.
    n : array_like, shape (k, 3)
        Unit vectors to the pulsars.
    r_sun_ssb : array_like, shape (..., 3)
        Sun position relative to the SSB, m (so ``b = -r_sun_ssb``).

    Raises
    ------
    ValueError
        If the line of sight passes exactly through the Sun's centre (infinite delay).

    Examples
    --------
    >>> s = shapiro(np.array([2.2e11, 0, 0]), np.array([[0.0, 1.0, 0.0]]), np.zeros(3) + 1e8)
    >>> bool(0 < s[0] < 1e-4)
    True
    """
    r_ssb, n = _args(r_ssb, n)
    b = _b(r_sun_ssb)
    x = _sun_x(r_ssb, b)  # spacecraft from the Sun: R - r_sun
    return _T_SUN * (np.log(_log_arg(x, n)) - np.log(_log_arg(b, n)))  # Backer & Hellings eq. 4.6


def shapiro_paper(r_ssb, n, r_sun_ssb):
    """Shapiro delay as the paper writes it: ``2 mu/c^3 ln|(n.R + |R|)/(n.b + |b|) + 1|``, s.

    Paper eq. (1), third term (Fan et al. 2016, after Sheikh et al. 2006), with ``R`` the
    spacecraft relative to the SSB (not to the Sun) and ``b = -r_sun_ssb``; shape (..., k).
    The Mars scenario and every reproduction of the paper use this form; :func:`shapiro`
    is the exact one.

    Parameters
    ----------
    r_ssb : array_like, shape (..., 3)
        Spacecraft position relative to the SSB, m.
    n : array_like, shape (k, 3)
        Unit vectors to the pulsars.
    r_sun_ssb : array_like, shape (..., 3)
        Sun position relative to the SSB, m.

    Examples
    --------
    >>> s = shapiro_paper(np.array([2.2e11, 0, 0]), np.array([[0.0, 1.0, 0.0]]), np.zeros(3) + 1e8)
    >>> bool(0 < s[0] < 1e-4)
    True
    """
    r_ssb, n = _args(r_ssb, n)
    b = _b(r_sun_ssb)
    _sun_x(r_ssb, b)
    u = r_ssb @ n.T + np.linalg.norm(r_ssb, axis=-1)[..., None]
    w = _log_arg(b, n)  # n.b + |b|, refused where 0 (the pulsar behind the Sun from the SSB)
    return _T_SUN * np.log(np.abs(u / w + 1.0))  # paper eq. (1), third term


def shapiro_offset_to_pint(n, r_sun_ssb):
    """Our exact Shapiro delay minus PINT's (and Tempo2's), s; shape (..., k).

    PINT refers the Sun's Shapiro delay to a distance of 1 au, ``-2 mu/c^3 ln[(|x| +
    n.x) / 1 au]`` (its sign: added to the emission time); we refer ours to the SSB's
    own delay. With PINT's value turned to our sign, ``shapiro(R, n, r_sun) -
    shapiro_offset_to_pint(n, r_sun)`` is PINT's number: the offset is
    ``2 mu/c^3 ln[1 au / (n.b + |b|)]``, which depends only on the pulsar and on where
    the Sun is relative to the SSB (about 5 ln-units, 50 us; it drifts by microseconds
    over Jupiter's 12-year period), not on the spacecraft.

    Parameters
    ----------
    n : array_like, shape (k, 3)
        Unit vectors to the pulsars.
    r_sun_ssb : array_like, shape (..., 3)
        Sun position relative to the SSB, m.

    Examples
    --------
    >>> (shapiro_offset_to_pint(np.eye(3), np.array([7e8, 1e8, 0.0])) * 1e6).round()  # us
    array([98., 54., 53.])
    """
    b = _b(r_sun_ssb)
    _, n = _args(np.zeros(3), n)
    return _T_SUN * (np.log(AU) - np.log(_log_arg(b, n)))


def _shapiro_form(form):
    check_choice("shapiro", form, SHAPIRO_FORMS)
    return shapiro if form == "exact" else shapiro_paper


def delay(r_ssb, n, distance, r_sun_ssb, shapiro="exact"):
    """Time-transfer delay: Roemer + parallax + Shapiro, s; shape (..., k).

    Parameters
    ----------
    r_ssb, n, distance, r_sun_ssb
        As :func:`roemer`, :func:`parallax` and :func:`shapiro`.
    shapiro : {"exact", "paper"}
        The Shapiro form: :func:`shapiro` or the paper's eq. (1) :func:`shapiro_paper`.

    Examples
    --------
    >>> nvec, dist = pulsars.directions()
    >>> delay(np.array([2.0e11, 1e10, 0.0]), nvec, dist, np.zeros(3) + 1e8).shape
    (4,)
    """
    form = _shapiro_form(shapiro)
    return roemer(r_ssb, n) + parallax(r_ssb, n, distance) + form(r_ssb, n, r_sun_ssb)


def gradient(r_ssb, n, distance, r_sun_ssb, shapiro="exact"):
    """Gradient of :func:`delay` with respect to the spacecraft position, s/m.

    Because ``R = r_M + r``, the gradient with respect to the planet-centred ``r`` is
    the same; these are the position columns of the rows of ``H1`` (paper eq. (4)):

    - Roemer: ``n / c``
    - parallax: ``((n . R) n - R) / (c D0)``
    - Shapiro, exact: ``2 mu/c^3 (n + x/|x|) / (n.x + |x|)``, ``x = R - r_sun``
    - Shapiro, paper: ``2 mu/c^3 (n + R/|R|) / (n.R + |R| + n.b + |b|)``

    Parameters
    ----------
    r_ssb, n, distance, r_sun_ssb
        As :func:`delay`.
    shapiro : {"exact", "paper"}
        The Shapiro form, as in :func:`delay`.

    Returns
    -------
    ndarray, shape (..., k, 3)

    Examples
    --------
    >>> nvec, dist = pulsars.directions()
    >>> g = gradient(np.array([2.0e11, 1e10, 0.0]), nvec, dist, np.zeros(3) + 1e8)
    >>> g.shape, bool(np.allclose(g * C, nvec, atol=1e-6))
    ((4, 3), True)
    """
    check_choice("shapiro", shapiro, SHAPIRO_FORMS)
    r_ssb, n = _args(r_ssb, n)
    d = _distance(distance, n.shape[0])
    b = _b(r_sun_ssb)
    R = r_ssb[..., None, :]
    nr = (r_ssb @ n.T)[..., None]
    rn = np.linalg.norm(r_ssb, axis=-1)[..., None, None]
    g_roemer = n / C
    g_parallax = (nr * n - R) / (C * d[:, None])
    x = _sun_x(r_ssb, b)
    if shapiro == "exact":
        xn = np.linalg.norm(x, axis=-1)[..., None, None]
        g_shapiro = _T_SUN * (n + x[..., None, :] / xn) / _log_arg(x, n)[..., None]
    else:
        if np.any(rn == 0.0):  # R / |R|: |R| has no gradient at the SSB
            raise ValueError("r_ssb must not be the SSB itself (0) for the paper's Shapiro form, "
                             "whose gradient holds R / |R|")
        u = nr + rn
        w = _log_arg(b, n)[..., None]  # n.b + |b| > 0
        g_shapiro = _T_SUN * (n + R / rn) / (u + w)  # d/dR of paper eq. (1), third term
    return g_roemer + g_parallax + g_shapiro


def terms(r_ssb, n, distance, r_sun_ssb, shapiro="exact"):
    """The three terms separately: dict with ``roemer``, ``parallax``, ``shapiro``.

    ``shapiro`` chooses the Shapiro form, as in :func:`delay`.

    Examples
    --------
    >>> nvec, dist = pulsars.directions()
    >>> sorted(terms(np.array([2e11, 0, 0]), nvec, dist, np.ones(3) * 1e8))
    ['parallax', 'roemer', 'shapiro']
    """
    form = _shapiro_form(shapiro)
    return {
        "roemer": roemer(r_ssb, n),
        "parallax": parallax(r_ssb, n, distance),
        "shapiro": form(r_ssb, n, r_sun_ssb),
    }


def delays_at(r, t, pulsar_names=pulsars.PAPER_PULSARS, center="mars", ephem="de421", shapiro="exact"):
    """Time-transfer delays (:func:`delay`) for a spacecraft at ``r`` about ``center`` at epochs ``t``.

    Parameters
    ----------
    r : array_like, shape (3,) or (n, 3)
        Spacecraft position relative to the centre body, J2000, m.
    t : float or array_like, shape (n,)
        Epochs, s TDB past J2000.
    pulsar_names : sequence of str
        Pulsars to use.
    center : str
        Centre body (``"mars"``, ``"earth"``, ...), see :data:`xnavlab.core.ephemeris.BODIES`.
    ephem : {"de421", "de405"}
        Ephemeris for the centre body and the Sun.
    shapiro : {"exact", "paper"}
        The Shapiro form, as in :func:`delay`.

    Returns
    -------
    ndarray, shape (k,) or (n, k)
        Delays, s.

    Examples
    --------
    >>> delays_at([-3.4e6, -1.3e6, -2.6e6], 5.0e8).shape
    (4,)
    """
    n, d = pulsars.directions(pulsars.check_names(pulsar_names, "pulsar_names"))
    r = check_finite_array("r", r, shape=(3,))
    if r.ndim > 2:
        raise ValueError(f"r must have shape (3,) or (n, 3), got {r.shape}")
    t = _checks.check_epochs("t", t)
    rows = r.shape[0] if r.ndim == 2 else None  # one fixed r serves any number of epochs
    if t.ndim > 1 or (t.ndim == 1 and rows is not None and t.size != rows):
        want = "(n,)" if rows is None else f"({rows},) (one epoch per row of r)"
        raise ValueError(f"t must be a scalar or have shape {want}, got shape {t.shape}")
    center = check_choice("center", center, ephemeris.BODIES)  # (was refused as the ephemeris's body)
    r_c = ephemeris.position(center, t, ephem)
    r_sun = ephemeris.position("sun", t, ephem)
    return delay(r + r_c, n, d, r_sun, shapiro=shapiro)


#: TDB rate against TCB: ``dTDB/dTCB = 1 - L_B`` (IAU 2006 Resolution B3).
L_B = 1.550519768e-8

#: GM of the bodies :func:`proper_time_terms` sums, m^3/s^2: the DE421 header values
#: (GMS, GM1, GM2, GMB with EMRAT = 81.3005690699153, GM4, GM5, GM6; au^3/day^2 times
#: (149597870.6996262 km)^3 / day^2). ``mars``, ``jupiter`` and ``saturn`` are systems.
GM_DE421 = {
    "sun": 1.3271244004094463e20,
    "mercury": 2.2032090000000113e13,
    "venus": 3.2485859200000125e14,
    "earth": 4.035032363095675e14 * 81.3005690699153 / 82.3005690699153,
    "moon": 4.035032363095675e14 / 82.3005690699153,
    "mars": 4.28283752140002e13,
    "jupiter": 1.2671276480000032e17,
    "saturn": 3.794058520000017e16,
}


def proper_time_terms(t, x=None, center="mars", ephem="de421"):
    """Proper time of a clock on board against TDB: rate, accumulated offset, orbit term.

    A clock at SSB position ``R`` moving at ``V`` in the potential ``U = sum GM_i /
    |R - R_i|`` keeps proper time ``tau`` with ``dtau/dTCB = 1 - (U + V^2/2)/c^2`` (the
    IAU 2000 metric to first post-Newtonian order), and ``dTDB/dTCB = 1 - L_B``, so

    ``d(tau - TDB)/dTDB = L_B - (U + V^2/2)/c^2``  (to order 1/c^2)

    which this integrates from ``t[0]`` (trapezoid rule; the step must follow the
    motion: days for the planet's year, a minute for an orbit around it). For a
    spacecraft at ``r`` about a body moving at ``V_c``, ``V^2`` holds the cross term ``2
    V_c . v``, whose integral, ``V_c . r``, is the orbit-periodic part: ``orbit_term =
    -V_c . r / c^2`` (its contribution to ``tau - TDB``, ``V_c`` treated as constant over
    an orbit).

    Parameters
    ----------
    t : array_like, shape (n,)
        Epochs, s TDB past J2000, increasing, n >= 2.
    x : array_like, shape (n, 6) or (6,), optional
        Spacecraft state relative to ``center`` (m, m/s), J2000 axes, outside every body
        (its polar radius: inside, ``GM / |R - R_i|`` is no potential). Without it the
        clock rides with the centre body and its own potential is left out.
    center : str
        Centre body, one of :data:`xnavlab.core.ephemeris.BODIES` except ``earthmoon``.
    ephem : {"de421", "de405"}
        Ephemeris of the bodies (``GM_DE421`` serves both).

    Returns
    -------
    dict of ndarray, shape (n,)
        ``rate``: ``d(tau - TDB)/dTDB`` (dimensionless, about +5.6e-9 at Mars);
        ``tau_minus_tdb``: its integral from ``t[0]``, s; ``orbit_term``: ``-V_c . r / c^2``,
        s (zeros without ``x``).

    Examples
    --------
    >>> t = np.arange(0.0, 687 * 86400.0, 86400.0)     # one Mars year, daily
    >>> out = proper_time_terms(t)
    >>> round(float(out["rate"].mean()) * 1e9, 1)      # the clock at Mars gains on TDB
    5.8
    """
    t = _checks.check_epochs("t", t)
    if t.ndim != 1 or t.size < 2 or np.any(np.diff(t) <= 0):
        raise ValueError(f"t must be 1-D, increasing, with at least 2 epochs, got shape {t.shape}")
    bodies = tuple(GM_DE421)
    check_choice("center", center, bodies)
    r_c, v_c = ephemeris.state(center, t, ephem)
    if x is None:
        r, v = r_c, v_c
        rel = np.zeros_like(r_c)
    else:
        x = check_finite_array("x", x, shape=(6,))
        if x.ndim > 1 and x.shape != (t.size, 6):
            raise ValueError(f"x must have shape (6,) or ({t.size}, 6) (one state per epoch of t), "
                             f"got shape {x.shape}")
        x = np.broadcast_to(x, (t.size, 6))
        r, v, rel = r_c + x[:, :3], v_c + x[:, 3:], x[:, :3]
    potential = np.zeros(t.size)
    for body in bodies:
        if body == center and x is None:
            continue  # riding with the body: its own potential is a constant left out
        d = np.linalg.norm(r - ephemeris.position(body, t, ephem), axis=1)
        check_outside("x", d, body)  # inside, GM / d is no potential (at the centre, 1 / 0)
        potential += GM_DE421[body] / d  # U = sum GM_i / |R - R_i|
    rate = L_B - (potential + 0.5 * np.sum(v * v, axis=1)) / C**2  # d(tau - TDB)/dTDB
    steps = 0.5 * (rate[1:] + rate[:-1]) * np.diff(t)  # trapezoid rule
    return {
        "rate": rate,
        "tau_minus_tdb": np.concatenate([[0.0], np.cumsum(steps)]),
        "orbit_term": -np.sum(v_c * rel, axis=1) / C**2,  # -V_c . r / c^2
    }


def pdop(n, sigma=None):
    """Geometry of a pulsar set: position dilution of precision and snapshot position error.

    With unit vectors ``n`` (rows) and ranging noise ``sigma`` (m), a single snapshot of
    range-like measurements ``c dt = n . r`` determines the position with covariance
    ``(N^T W N)^-1``, ``W = diag(sigma^-2)``. ``PDOP = sqrt(tr (N^T N)^-1)``.

    Parameters
    ----------
    n : array_like, shape (k, 3)
        Unit vectors to ``k >= 3`` pulsars (norm 1 within 1e-9).
    sigma : array_like, shape (k,), optional
        Ranging accuracies, m, each in [1e-3, 1e13] (1 mm, 3 ps, is far below any pulsar's
        timing; 1e13 m, 67 au, is no position fix).

    Returns
    -------
    float or (float, float)
        PDOP, and with ``sigma`` also the snapshot position error (m, 1 sigma RSS).

    Raises
    ------
    ValueError
        For fewer than three pulsars or a degenerate (coplanar) set.

    Examples
    --------
    >>> round(pdop(np.eye(3)), 3)
    1.732
    >>> pdop(np.eye(3), [1.0, 2.0, 2.0])[1]
    3.0
    """
    given, n = n, check_finite_array("n", n, shape=(3,))
    if n.ndim != 2 or n.shape[0] < 3:
        raise ValueError(f"n must have shape (k, 3) with k >= 3, got {n.shape}")
    _, n = _args(np.zeros(3), given)  # unit vectors (a scaled row overflowed the Gram matrix)
    gram = n.T @ n
    if np.linalg.cond(gram) > 1e12:
        raise ValueError("n must span three dimensions (the pulsar directions are coplanar)")
    value = float(np.sqrt(np.trace(np.linalg.inv(gram))))
    if sigma is None:
        return value
    sigma = check_finite_array("sigma", sigma)
    if sigma.shape != (n.shape[0],):
        raise ValueError(f"sigma must have shape ({n.shape[0]},), one per pulsar, got {sigma.shape}")
    if np.any((sigma < 1e-3) | (sigma > 1e13)):
        bad = sigma[(sigma < 1e-3) | (sigma > 1e13)][0]
        raise ValueError(f"sigma must be in [0.001, 1e+13] m, got {float(bad):.6g}")
    w = sigma**-2.0  # 1 mm to 1e13 m: the weights' inverse stays finite (5e-324 overflowed)
    return value, float(np.sqrt(np.trace(np.linalg.inv(n.T @ (w[:, None] * n)))))


def gradient_fd(r_ssb, n, distance, r_sun_ssb, step=1.0e3, which=("roemer", "parallax", "shapiro"),
                shapiro="exact"):
    """Central finite differences of (some of) the delay terms with respect to position.

    The check of :func:`gradient`: ``(f(R + step e_j) - f(R - step e_j)) / (2 step)`` for
    the three axes ``e_j``, with ``f`` the sum of the terms named in ``which``. The delay
    is ~300 s, so the step must be large enough for rounding (``300 s x 1e-16``) to stay
    small next to the gradient (``1/c`` s/m): the default 1 km gives about 1e-8.

    Parameters
    ----------
    r_ssb : array_like, shape (3,)
        Spacecraft position relative to the SSB, m.
    n : array_like, shape (k, 3)
        Unit vectors to the pulsars.
    distance : array_like, shape (k,)
        Pulsar distances, m.
    r_sun_ssb : array_like, shape (3,)
        Sun relative to the SSB, m.
    step : float
        Finite-difference step, m, in (0, 1e12] (7 au: a difference across more than the
        inner Solar System is no derivative, and near 1e308 m the squares overflow).
    which : sequence of {"roemer", "parallax", "shapiro"}
        The terms to differentiate (default all three, the whole delay).
    shapiro : {"exact", "paper"}
        The Shapiro form, as in :func:`delay`.

    Returns
    -------
    ndarray, shape (k, 3)
        s/m, rows comparable with :func:`gradient`.

    Examples
    --------
    >>> n = np.array([[0.6, 0.8, 0.0]])
    >>> (gradient_fd([1e11, 0.0, 0.0], n, [1e20], [1e9, 2e9, 0.0], which=("roemer",)) * C).round(9)
    array([[0.6, 0.8, 0. ]])
    """
    r_ssb = check_shape("r_ssb", r_ssb, (3,), "one position: the columns are its three axes")
    r_sun_ssb = check_shape("r_sun_ssb", r_sun_ssb, (3,), "the Sun at r_ssb's one epoch")
    step = check_real("step", step, 0.0, 1e12, lo_open=True)
    which = check_items("which", which, "term",
                        lambda label, name: check_choice(label, name, ("roemer", "parallax", "shapiro")))

    check_choice("shapiro", shapiro, SHAPIRO_FORMS)

    def f(point):
        t = terms(point, n, distance, r_sun_ssb, shapiro=shapiro)
        return sum(t[name] for name in which)

    cols = [(f(r_ssb + step * e) - f(r_ssb - step * e)) / (2.0 * step) for e in np.eye(3)]
    return np.column_stack(cols)


def plot_orbit_terms(pulsar="B0531+21", day=0, shapiro="exact"):
    """The orbit-dependent part of each delay term over one day of the paper's 30-day orbit.

    Spacecraft minus Mars centre, ``c (term(R_M + r) - term(R_M))``, for one pulsar, on
    the 60-s grid of the 30-day truth (:func:`xnavlab.mars.models.dynamics.truth` from
    ``MARS_T0``, cached on disk). A pure function of its arguments, for chapter 2's slider.

    Parameters
    ----------
    pulsar : str
        One of :data:`xnavlab.mars.timing.pulsars.PAPER_PULSARS`.
    day : int
        Day of the 30, 0 to 29.
    shapiro : {"exact", "paper"}
        The Shapiro form, as in :func:`delay`.

    Returns
    -------
    matplotlib.figure.Figure
        Three axes: Roemer (km), parallax (cm), Shapiro (cm); not registered with pyplot. It
        carries an in-place update (:func:`xnavlab.core.plotting.in_place`) that a live
        slider calls.

    Examples
    --------
    >>> fig = plot_orbit_terms("B1937+21", 3)
    >>> [ax.get_xlabel() for ax in fig.axes]
    ['hours into day 3', 'hours into day 3', 'hours into day 3']
    """
    from matplotlib.figure import Figure

    from xnavlab.core.plotting import in_place
    from xnavlab.mars.models import dynamics

    hours = np.arange(1441) / 60.0  # one day of 60-s samples, h
    # the layout every frame shares; update() sets the curves, limits and texts
    fig = Figure(figsize=(12, 3.4), layout="constrained")
    axes = fig.subplots(1, 3)
    units = {"roemer": (1e-3, "km"), "parallax": (1e2, "cm"), "shapiro": (1e2, "cm")}
    curves = {}
    for ax, (key, (_, unit)) in zip(axes, units.items(), strict=True):
        curves[key], = ax.plot(hours, np.zeros(hours.size))
        ax.set(title=f"{key} $\\times c$, spacecraft - Mars ({unit})")
    title = fig.suptitle("")

    def update(pulsar="B0531+21", day=0, shapiro="exact"):
        check_choice("pulsar", pulsar, pulsars.PAPER_PULSARS)
        day = check_int("day", day, 0, 29)
        check_choice("shapiro", shapiro, SHAPIRO_FORMS)
        t = dynamics.MARS_T0 + np.arange(0.0, 30 * 86400.0 + 1.0, 60.0)  # the chapter's grid
        i = slice(day * 1440, (day + 1) * 1440 + 1)  # one day of 60-s samples
        x = dynamics.truth(t)[i]
        t = t[i]
        r_mars = ephemeris.position("mars", t)
        r_sun = ephemeris.position("sun", t)
        n_p, d_p = pulsars.directions([pulsar])
        at_sc = terms(r_mars + x[:, :3], n_p, d_p, r_sun, shapiro=shapiro)
        at_mars = terms(r_mars, n_p, d_p, r_sun, shapiro=shapiro)
        for ax, (key, (scale, _)) in zip(axes, units.items(), strict=True):
            curves[key].set_ydata(C * (at_sc[key] - at_mars[key])[:, 0] * scale)
            ax.set_xlabel(f"hours into day {day}")
            ax.relim()
            ax.autoscale_view()
        title.set_text(pulsar)
        return None

    update(pulsar, day, shapiro)
    return in_place(fig, update)
