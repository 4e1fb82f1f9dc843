"""A small bright-star table (Hipparcos) and a rule that picks three well-spread stars.

The table ``xnavlab/data/bright_stars.csv`` holds 38 bright stars (the Nautical
Almanac's navigational stars with V <= 2.0, plus Polaris) with their values from the
Hipparcos main catalogue (ESA 1997, ESA SP-1200; CDS I/239 ``hip_main``): ICRS
right ascension and declination at the catalogue epoch J1991.25, proper motions
(``pmRA`` is mu_alpha cos delta), parallax and V magnitude. The main paper used the
Tycho-2 catalogue; for the three bright stars a star sensor tracks, Hipparcos gives
the same directions to better than 0.1 arcsec.

Directions are ICRF unit vectors, propagated from J1991.25 to the requested epoch
with the proper motions by the unit-vector method (no radial velocity). Stellar
parallax seen from Mars (at most 1.2 arcsec, Rigil Kentaurus) and aberration (about
20 arcsec for a Mars orbiter) are not applied: the truth and the filter use the same
catalogue directions, as in the paper.

Examples
--------
>>> s = direction("Sirius", 0.0)     # J2000.0
>>> ra, dec = radec(s)
>>> round(ra, 6), round(dec, 6)
(101.287155, -16.716116)
"""

from __future__ import annotations

import functools
import itertools
import math
from dataclasses import dataclass
from importlib import resources

import numpy as np

from xnavlab.core.userfiles import csv_rows
from xnavlab.core.validate import check_finite_array, check_items, check_real, check_vector, off_unit

__all__ = [
    "HIPPARCOS_EPOCH",
    "Star",
    "catalogue",
    "names",
    "get",
    "direction",
    "directions",
    "radec",
    "spread",
    "pick_three",
    "starlight_geometry",
]

#: Hipparcos catalogue epoch J1991.25 in s TDB past J2000 (-8.75 Julian years).
HIPPARCOS_EPOCH = -8.75 * 365.25 * 86400.0
_MAS = math.pi / (180.0 * 3600.0e3)
_YEAR = 365.25 * 86400.0


@dataclass(frozen=True)
class Star:
    """One catalogue star (Hipparcos values at J1991.25).

    Attributes
    ----------
    hip : int
        Hipparcos number.
    name, designation : str
        Proper name and Bayer designation.
    ra_deg, dec_deg : float
        ICRS position at J1991.25, deg.
    pm_ra_cosdec_mas_yr, pm_dec_mas_yr : float
        Proper motion, mas/yr (the first already multiplied by cos dec).
    parallax_mas : float
        Parallax, mas.
    vmag : float
        V magnitude.
    """

    hip: int
    name: str
    designation: str
    ra_deg: float
    dec_deg: float
    pm_ra_cosdec_mas_yr: float
    pm_dec_mas_yr: float
    parallax_mas: float
    vmag: float


@functools.cache
def catalogue():
    """All stars of the shipped table, brightest first.

    Returns
    -------
    tuple of Star

    Examples
    --------
    >>> cat = catalogue()
    >>> len(cat), cat[0].name
    (38, 'Sirius')
    """
    text = resources.files("xnavlab").joinpath("data/bright_stars.csv").read_text("utf-8")
    rows = csv_rows(text, "data/bright_stars.csv", ("hip", "ra_deg", "dec_deg",
                                                    "pm_ra_cosdec_mas_yr", "pm_dec_mas_yr",
                                                    "parallax_mas", "vmag"))
    stars = [
        Star(int(r["hip"]), r["name"], r["designation"], r["ra_deg"], r["dec_deg"],
             r["pm_ra_cosdec_mas_yr"], r["pm_dec_mas_yr"], r["parallax_mas"], r["vmag"])
        for r in rows
    ]
    return tuple(sorted(stars, key=lambda s: s.vmag))


def names():
    """Names of the stars in the table, brightest first.

    Examples
    --------
    >>> names()[:3]
    ('Sirius', 'Canopus', 'Arcturus')
    """
    return tuple(s.name for s in catalogue())


def get(star):
    """A :class:`Star` by name (case-insensitive) or Hipparcos number.

    Examples
    --------
    >>> get("vega").hip, get(32349).name
    (91262, 'Sirius')
    """
    if isinstance(star, Star):
        return star
    for s in catalogue():
        if (isinstance(star, str) and s.name.lower() == star.lower()) or (
            not isinstance(star, str | bool) and star == s.hip
        ):
            return s
    raise ValueError(f"unknown star {star!r}; known stars: {', '.join(names())}")


def _star_name(label, star):
    """The name of the star ``star`` (:func:`get`), refused under ``label`` (``stars[1]``)."""
    try:
        return get(star).name
    except ValueError as exc:
        raise ValueError(f"{label}: {exc}") from None


def direction(star, t=0.0):
    """ICRF unit vector to ``star`` at epoch ``t`` (s TDB past J2000), shape (3,).

    The Hipparcos position is moved along its proper motion,
    ``u(t) = normalise(u0 + (t - t_H) (mu_a* p + mu_d q))`` with ``p``, ``q`` the unit
    vectors of increasing right ascension and declination at J1991.25.

    Examples
    --------
    >>> u = direction("Polaris")
    >>> bool(u[2] > 0.9998)
    True
    """
    s = get(star)
    t = check_real("t", t, -1e11, 1e11)
    a, d = math.radians(s.ra_deg), math.radians(s.dec_deg)
    u0 = np.array([math.cos(d) * math.cos(a), math.cos(d) * math.sin(a), math.sin(d)])
    p = np.array([-math.sin(a), math.cos(a), 0.0])
    q = np.array([-math.sin(d) * math.cos(a), -math.sin(d) * math.sin(a), math.cos(d)])
    years = (t - HIPPARCOS_EPOCH) / _YEAR
    u = u0 + years * _MAS * (s.pm_ra_cosdec_mas_yr * p + s.pm_dec_mas_yr * q)
    return u / np.linalg.norm(u)


def directions(stars, t=0.0):
    """Unit vectors to several stars, shape (k, 3).

    ``stars`` is a list (a string is not split into its letters, None is no list), each star
    once (``"Vega"`` and ``"vega"`` are the same star): else one ValueError naming ``stars``.

    Examples
    --------
    >>> directions(["Sirius", "Vega", "Canopus"]).shape
    (3, 3)
    """
    stars = check_items("stars", stars, "star", each=lambda label, s: get(s).name)
    return np.array([direction(s, t) for s in stars])


def radec(u):
    """Right ascension and declination (deg) of a unit vector, RA in [0, 360); a zero vector
    is refused.

    Examples
    --------
    >>> radec(np.array([0.0, 1.0, 0.0]))
    (90.0, 0.0)
    """
    u = check_vector("u", u, 3)  # one vector: (1, 3) was an IndexError (review 35k)
    if not np.linalg.norm(u) > 0.0:  # (a NaN declination and a warning before)
        raise ValueError("u must be a direction (a non-zero vector), got (0, 0, 0)")
    ra = math.degrees(math.atan2(u[1], u[0])) % 360.0
    dec = math.degrees(math.asin(max(-1.0, min(1.0, u[2] / np.linalg.norm(u)))))
    return ra, dec


def spread(s):
    """How well three directions span space: ``|det [s1 s2 s3]|`` (1 when orthogonal).

    Parameters
    ----------
    s : array_like, shape (3, 3)
        Unit vectors, one a row, each of norm within 1e-6 of 1 (a scaled one is refused: its
        determinant would scale with it).

    Examples
    --------
    >>> spread(np.eye(3))
    1.0
    """
    s = check_finite_array("s", s, shape=(3, 3))
    if s.ndim != 2:
        raise ValueError(f"s must have shape (3, 3), three unit vectors one a row, got shape {s.shape}")
    i, norm = off_unit(s, 1e-6)
    if i is not None:  # review 35j: 2 I gave 8
        raise ValueError(f"s[{i}] must be a unit vector (norm within 1e-6 of 1), got norm {norm[i]:.6g}")
    return float(abs(np.linalg.det(s)))


def pick_three(vmag_max=1.0, t=0.0, avoid=None, avoid_deg=0.0, candidates=None):
    """The rule for the CNS stars: the three brightest-enough stars that are most spread.

    Among the stars with ``V <= vmag_max`` (and farther than ``avoid_deg`` from every
    direction in ``avoid``, e.g. the Sun), return the triple that maximises
    :func:`spread`, the volume spanned by the three unit vectors. Well-spread stars
    keep the three starlight angles from all nearing 0 or 180 deg (where eq. (6) loses
    its sensitivity) at once, not each of them: on the paper's orbit Acrux comes within
    15 deg of the Mars direction and is behind Mars's disc for about a quarter of each
    orbit (:func:`starlight_geometry`). Ties go to the brighter triple.

    Parameters
    ----------
    vmag_max : float
        Faintest magnitude allowed (bright stars are the ones a star sensor
        identifies most reliably).
    t : float
        Epoch, s TDB past J2000.
    avoid : array_like, shape (k, 3), optional
        Directions to keep away from (any length but zero: the Sun's position will do).
    avoid_deg : float
        Exclusion half-angle around each ``avoid`` direction, deg, in [0, 180]; positive
        with ``avoid`` and 0 without it (either alone would exclude nothing: refused).
    candidates : sequence of str, optional
        Restrict the choice to these stars, at least three, none twice.

    Returns
    -------
    tuple of str
        Three star names, brightest first.

    Raises
    ------
    ValueError
        Fewer than three stars left by ``vmag_max`` (and ``avoid``), naming it.

    Examples
    --------
    >>> pick_three()
    ('Arcturus', 'Procyon', 'Acrux')
    """
    vmag_max = check_real("vmag_max", vmag_max, -2.0, 10.0)
    avoid_deg = check_real("avoid_deg", avoid_deg, 0.0, 180.0)
    t = check_real("t", t, -1e11, 1e11)
    names = None if candidates is None else tuple(  # a repeat was dropped (review 35j)
        check_items("candidates", candidates, "star", _star_name, min_len=3))
    if (avoid is None) != (avoid_deg == 0.0):
        raise ValueError("avoid_deg is unused without avoid (the directions it is measured from)"
                         if avoid is None else "avoid is unused with avoid_deg = 0 (an exclusion "
                         "of no angle): give avoid_deg > 0")
    if avoid is not None:
        avoid = check_finite_array("avoid", avoid, shape=(3,)).reshape(-1, 3)
        if avoid.size == 0:  # review 35k: numpy's 'axis 1 is out of bounds'
            raise ValueError("avoid must hold at least one direction (shape (3,) or (k, 3)), "
                             "got none")
        norm = np.linalg.norm(avoid, axis=1)
        if not np.all(norm > 0.0):  # 0/0 (review 35j)
            raise ValueError(f"avoid[{int(np.argmin(norm > 0.0))}] must be a direction (a "
                             f"non-zero vector), got (0, 0, 0)")
        avoid = tuple(map(tuple, avoid.tolist()))
    return _pick_three(vmag_max, t, avoid, avoid_deg, names)


@functools.lru_cache(maxsize=64)
def _pick_three(vmag_max, t, avoid, avoid_deg, names):
    """:func:`pick_three` on checked, hashable arguments, kept: every Mars scenario's CNS
    sensor asks for the same triple (455 triples weighed: 12-14 ms of a one-day run)."""
    pool = [get(s) for s in names] if names is not None else list(catalogue())
    pool = [s for s in pool if s.vmag <= vmag_max]
    of = "candidates" if names is not None else "the catalogue's stars"
    if len(pool) < 3:  # review 35j: the message named no parameter
        raise ValueError(f"vmag_max = {vmag_max:g} leaves {len(pool)} of {of} bright enough, "
                         f"pick_three needs 3: raise vmag_max"
                         + (" or give more candidates" if names is not None else ""))
    if avoid is not None:
        av = np.array(avoid)
        av = av / np.linalg.norm(av, axis=1, keepdims=True)
        cos_lim = math.cos(math.radians(avoid_deg))
        pool = [s for s in pool if np.all(av @ direction(s, t) < cos_lim)]
        if len(pool) < 3:
            raise ValueError(f"avoid_deg = {avoid_deg:g} leaves {len(pool)} of {of} with V <= "
                             f"{vmag_max:g} outside it, pick_three needs 3: lower avoid_deg or "
                             f"raise vmag_max")
    pool.sort(key=lambda s: s.vmag)
    u = {s.name: direction(s, t) for s in pool}
    best, best_val = None, -1.0
    for trio in itertools.combinations(pool, 3):
        val = spread(np.array([u[s.name] for s in trio]))
        if val > best_val + 1e-12:
            best, best_val = trio, val
    return tuple(s.name for s in best)


def starlight_geometry(r, star_names=None, t=0.0, radius=None):
    """Each star's starlight angle range and the fraction of the time it is hidden behind Mars.

    The starlight angle of star ``j`` is ``arccos(-r . s_j / |r|)`` (paper eq. (6)); the star
    is behind Mars's disc (occulted, no measurement) when that angle is below the disc's
    apparent radius ``arcsin(R / |r|)``.

    Parameters
    ----------
    r : array_like, shape (n, 3)
        Spacecraft positions (at least one), Mars-centred J2000, m, sampled uniformly in time (e.g. the
        truth of :func:`xnavlab.mars.navigation.scenarios.prepare`).
    star_names : sequence of str, optional
        Default :func:`pick_three`.
    t : float
        Epoch of the star directions, s TDB past J2000.
    radius : float, optional
        Mars's radius, m (default :data:`xnavlab.core.constants.R_MARS`, equatorial), in [1, 1e9].

    Returns
    -------
    dict
        ``{name: {"min_deg", "max_deg", "occulted_fraction"}}``.

    Examples
    --------
    >>> ang = np.linspace(0.0, 2 * np.pi, 360, endpoint=False)
    >>> r = 4.2e6 * np.c_[np.cos(ang), np.sin(ang), np.zeros(360)]
    >>> g = starlight_geometry(r, ("Polaris",))["Polaris"]
    >>> round(g["min_deg"]), round(g["max_deg"]), g["occulted_fraction"]
    (89, 91, 0.0)
    """
    from xnavlab.core.constants import R_MARS
    from xnavlab.mars.models.dynamics import MAX_BODY_RADIUS

    r = check_finite_array("r", r, shape=(3,))
    if r.ndim > 2 or r.size == 0:  # review 35k: no position was numpy's 'zero-size array'
        raise ValueError(f"r must have shape (n, 3) with n >= 1 (positions, one a row), got "
                         f"shape {r.shape}")
    r = r.reshape(-1, 3)
    radius = R_MARS if radius is None else check_real("radius", radius, 1.0, MAX_BODY_RADIUS)
    rho = np.linalg.norm(r, axis=1)
    if np.any(rho <= radius):
        raise ValueError("r must lie outside Mars (|r| > radius)")
    names = pick_three(t=t) if star_names is None else tuple(
        get(s).name for s in check_items("star_names", star_names, "star", _star_name))
    disc = np.arcsin(radius / rho)  # apparent radius of the disc
    out = {}
    for name in names:
        ang = np.arccos(np.clip(-(r @ direction(name, t)) / rho, -1.0, 1.0))  # paper eq. (6)
        out[name] = {"min_deg": float(np.degrees(ang.min())), "max_deg": float(np.degrees(ang.max())),
                     "occulted_fraction": float(np.mean(ang < disc))}
    return out
