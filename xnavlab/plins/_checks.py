"""The input checks that the PL/INS modules share: pseudolite sites (ECEF, distinct, at least one),
and geodetic angles (radians, bounded).

Plumbing of :mod:`xnavlab.plins`; not part of the public API.
"""

from __future__ import annotations

import math

import numpy as np

from xnavlab.core.validate import check_finite_array, check_real, shown

__all__ = ["check_sites", "distinct_sites", "LAT_MAX", "LON_MAX", "check_angle", "check_angles"]

#: The largest latitude, rad (the pole).
LAT_MAX = math.pi / 2
#: The largest longitude, rad, either way: one turn (east or west, or 0 to 360 deg), so that a
#: value in degrees (116 for Beijing) or a meaningless 1e300 is refused, not taken as radians.
LON_MAX = 2 * math.pi
_ANGLES = {"lat": ("a latitude", "latitudes", LAT_MAX), "lon": ("a longitude", "longitudes", LON_MAX)}


def _degrees_hint(value, bound):
    """A hint when ``value`` (out of ``bound``, rad) reads as an angle in degrees."""
    return " (degrees? use np.radians)" if bound < abs(value) <= 360.0 else ""


def check_angle(name, value, kind):
    """A latitude (``kind="lat"``, [-pi/2, pi/2]) or longitude (``"lon"``, [-2 pi, 2 pi]) in
    radians as a float, else one ValueError naming ``name``, the range in radians and the value
    (with a hint when it reads as degrees)."""
    one, _, bound = _ANGLES[kind]
    try:
        return check_real(name, value, -bound, bound)
    except ValueError:
        number = isinstance(value, int | float | np.integer | np.floating) and not isinstance(value, bool)
        hint = _degrees_hint(float(value), bound) if number and math.isfinite(value) else ""
        raise ValueError(f"{name} must be {one} in radians in [{-bound:g}, {bound:g}], got "
                         f"{shown(value)}{hint}") from None


def check_angles(name, value, kind):
    """:func:`check_angle` of an array (finite, any shape): the first entry out of range named."""
    one, many, bound = _ANGLES[kind]
    arr = check_finite_array(name, value)
    bad = np.abs(arr) > bound
    if np.any(bad):
        at = np.unravel_index(int(np.argmax(bad)), arr.shape)
        v = float(arr[at])
        where = f"{name}[{', '.join(str(int(i)) for i in at)}] = " if arr.ndim else ""
        raise ValueError(f"{name} must {'hold ' + many if arr.ndim else 'be ' + one} in radians in "
                         f"[{-bound:g}, {bound:g}], got {where}{v!r}{_degrees_hint(v, bound)}")
    return arr


def check_sites(sites, name="sites"):
    """Pseudolite sites as an (m, 3) ECEF array, m >= 1, at least 1 m apart, else one ValueError
    leading with ``name`` (no site was an empty (0, 10) measurement matrix or an IndexError)."""
    sites = check_finite_array(name, sites, shape=(3,))
    if sites.ndim != 2 or len(sites) < 1:
        raise ValueError(f"{name} must have shape (m, 3) with m >= 1 (one row a pseudolite), got "
                         f"shape {sites.shape}")
    return distinct_sites(name, sites)


def distinct_sites(name, ecef):
    """ECEF sites at least 1 m apart (two antennas cannot share a place), or ValueError."""
    gap = np.linalg.norm(ecef[:, None, :] - ecef[None, :, :], axis=-1)
    i, j = np.triu_indices(len(ecef), k=1)
    close = np.flatnonzero(gap[i, j] < 1.0)
    if close.size:
        k = close[0]
        raise ValueError(f"{name} must be distinct sites at least 1 m apart, got sites {i[k]} "
                         f"and {j[k]} {gap[i[k], j[k]]:.3g} m apart")
    return ecef
