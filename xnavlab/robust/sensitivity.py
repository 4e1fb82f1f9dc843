"""The UKF's sensitivity to a constant ephemeris error (Li et al. 2017, Fig. 4), by direction.

A constant error of the planet's ephemeris shifts the pulsar-direction measurements the same
way at every step; the UKF, which does not model it, turns it into a position error. These
functions measure that error against the error's size (:func:`ukf_sensitivity`) and its
direction (:func:`ukf_sensitivity_by_direction`, the named directions of
:func:`sensitivity_directions`), and find the steepest direction over the whole sphere from a
few measured ones (:func:`steepest_direction`). Chapter 10's ``ukf-vs-ephemeris-error``
reproduction is built on them.

Examples
--------
>>> round(earth_error_size() / 1e3, 1)   # the real DE421 - DE405 Earth error at 1997-01-01, km
1.5
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from xnavlab.core.validate import check_items, check_real, check_vector, shown
from xnavlab.robust import ephemeris_error as ee
from xnavlab.robust._checks import check_epoch
from xnavlab.robust.comparison import compare_filters

__all__ = ["ukf_sensitivity", "sensitivity_directions", "ukf_sensitivity_by_direction",
           "steepest_direction", "earth_error_size"]


def ukf_sensitivity(sizes=(0.0, 250.0, 500.0, 750.0, 1000.0), body="earth", seeds=(0,), direction=None):
    """UKF RMSE against an injected constant ephemeris error (Fig. 4).

    Parameters
    ----------
    sizes : sequence of float
        Error sizes, m, each in [0, 1e8]; at least one, none twice (a repeat would be run and
        returned twice).
    body : {"earth", "mars"}
    seeds : sequence of int
    direction : array_like, shape (3,), optional
        Direction of the error (default ``(1, 1, 1) / sqrt(3)``).

    Returns
    -------
    sizes : ndarray, shape (m,)
    rmse : ndarray, shape (m,)
        Mean RMSE over the seeds over the paper's window, m.

    Examples
    --------
    >>> sizes, r = ukf_sensitivity((0.0, 1000.0))
    >>> bool(r[1] - r[0] > 500.0)
    True
    """
    sizes = check_vector("sizes", sizes)  # simulate's range of an injected error, m, each:
    check_items("sizes", sizes, "size", lambda label, s: check_real(label, s, 0.0, 1e8))
    out = [compare_filters(body, ("ukf",), error="constant", size=float(s), seeds=seeds,
                           direction=direction)["rmse"]["ukf"] for s in sizes]
    return sizes, np.array(out)


def sensitivity_directions(body="earth"):
    """Named directions of an ephemeris error for :func:`ukf_sensitivity_by_direction`.

    The three pulsar directions, the orbit normal at the start, the real DE421 - DE405
    error at 1997-01-01, and ``(1, 1, 1) / sqrt(3)`` (the injected error's default).

    Returns
    -------
    dict
        Name -> unit vector, shape (3,), ICRF.

    Examples
    --------
    >>> sorted(sensitivity_directions())[:2]
    ['(1,1,1)', 'B0531+21']
    """
    d = {name: n for name, n in zip(ee.PULSARS, ee.directions(), strict=True)}
    s0 = ee.orbit(body).state0
    h = np.cross(s0[:3], s0[3:])
    d["orbit normal"] = h / np.linalg.norm(h)
    dr = ee.ephemeris_error(body, ee.EPOCH_1997)
    d["DE421-DE405"] = dr / np.linalg.norm(dr)
    d["(1,1,1)"] = np.ones(3) / np.sqrt(3.0)
    return d


def ukf_sensitivity_by_direction(directions=None, size=1000.0, body="earth", seeds=(0,)):
    """UKF error per metre of constant ephemeris error, for each error direction.

    The slope ``(RMSE(size) - RMSE(0)) / size`` over the paper's window, with the same
    seeds for both runs.

    Parameters
    ----------
    directions : dict of name -> array_like (3,), optional
        Default :func:`sensitivity_directions`.
    size : float
        Error size, m, in [1e-3, 1e8] (from a millimetre, as :func:`steepest_direction`'s: the
        slope divides by it; to simulate's largest injected error).
    body : {"earth", "mars"}
    seeds : sequence of int

    Returns
    -------
    dict
        Name -> slope, m per m.

    Examples
    --------
    >>> s = ukf_sensitivity_by_direction({"z": [0.0, 0.0, 1.0]}, body="mars")
    >>> list(s)
    ['z']
    """
    size = check_real("size", size, 1e-3, 1e8)  # checked before the runs (0 divided the slope)
    if directions is None:
        directions = sensitivity_directions(body)
    elif not isinstance(directions, Mapping) or not directions:
        raise ValueError(f"directions must be a non-empty dict of name -> direction (3,), "
                         f"got {shown(directions)}")
    else:  # each named as the user gave it (simulate names its one direction)
        directions = {k: u if isinstance(u, str) else check_vector(f"directions[{k!r}]", u, 3)
                      for k, u in directions.items()}
    base = compare_filters(body, ("ukf",), error="none", seeds=seeds)["rmse"]["ukf"]
    out = {}
    for name, u in directions.items():
        r = compare_filters(body, ("ukf",), error="constant", size=size, seeds=seeds,
                                   direction=u)["rmse"]["ukf"]
        out[name] = (r - base) / size  # Fig. 4's slope along this direction
    return out


def steepest_direction(slopes, directions, base, size):
    """The error direction of the steepest UKF slope, from the slopes along known directions.

    With a constant error ``size * u``, the UKF error is a linear response to it plus the
    noise, so its mean square is a quadratic form in ``u``:
    ``RMSE(u)^2 = size^2 u^T A u + base^2`` (``base`` the RMSE without the error). Six
    directions or more determine ``A`` (least squares); its largest eigenvalue gives the
    steepest direction over the whole sphere and its predicted slope.

    Parameters
    ----------
    slopes : dict of name -> float
        Measured slope along each direction, m per m (:func:`ukf_sensitivity_by_direction`).
    directions : dict of name -> array_like (3,)
        The unit vectors (at least six of the names in ``slopes``, not all in one plane).
    base : float
        UKF RMSE without an ephemeris error, m.
    size : float
        The error size the slopes were measured at, m, in [1e-3, 1e12].

    Returns
    -------
    u : ndarray, shape (3,)
        Unit vector of the steepest direction.
    slope : float
        Its predicted slope, m per m.

    Examples
    --------
    >>> A = np.diag([0.25, 1.0, 2.25])
    >>> dirs = {str(i): v / np.linalg.norm(v) for i, v in enumerate(np.array(
    ...     [[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 0], [1, 0, 1], [0, 1, 1.0]]))}
    >>> sl = {k: (np.sqrt(1e6 * v @ A @ v + 50.0 ** 2) - 50.0) / 1e3 for k, v in dirs.items()}
    >>> u, top = steepest_direction(sl, dirs, 50.0, 1e3)
    >>> np.round(np.abs(u), 3).tolist(), round(top, 2)
    ([0.0, 0.0, 1.0], 1.45)
    """
    U, rr, base, size = _slope_inputs(slopes, directions, base, size)
    rows = np.column_stack([U[:, 0] ** 2, U[:, 1] ** 2, U[:, 2] ** 2,
                            2 * U[:, 0] * U[:, 1], 2 * U[:, 0] * U[:, 2], 2 * U[:, 1] * U[:, 2]])
    if np.linalg.matrix_rank(rows) < 6:  # lstsq would return one of many forms in silence
        raise ValueError("directions must determine the quadratic form: these lie on one cone "
                         "or plane (give six or more in general position)")
    a = np.linalg.lstsq(rows, (rr ** 2 - base ** 2) / size ** 2, rcond=None)[0]
    A = np.array([[a[0], a[3], a[4]], [a[3], a[1], a[5]], [a[4], a[5], a[2]]])
    w, V = np.linalg.eigh(A)
    top = max(float(w[-1]), 0.0)
    return V[:, -1], float((np.sqrt(size ** 2 * top + base ** 2) - base) / size)


def _slope_inputs(slopes, directions, base, size):
    """:func:`steepest_direction`'s inputs checked: the unit vectors, the RMSEs along them,
    ``base`` and ``size``; one ValueError naming the input at fault."""
    for name, value in (("slopes", slopes), ("directions", directions)):
        if not isinstance(value, Mapping):
            raise ValueError(f"{name} must be a dict of direction name -> value, got {shown(value)}")
    for k in slopes:  # a slope without its direction would be dropped in silence
        if k not in directions:
            raise ValueError(f"slopes[{k!r}] has no direction: directions gives "
                             f"{', '.join(map(repr, directions))}")
    if len(slopes) < 6:
        raise ValueError(f"slopes must cover at least 6 of the directions; got {len(slopes)}")
    base = check_real("base", base, 0.0, 1e12)
    # From 1 mm (far below any ranging noise; size**2 of a subnormal size was 0, the fit's
    # right-hand side inf) to 1e12 m.
    size = check_real("size", size, 1e-3, 1e12)
    U = np.array([check_vector(f"directions[{k!r}]", directions[k], 3) for k in slopes])
    for k, u in zip(slopes, U, strict=True):
        if abs(float(np.linalg.norm(u)) - 1.0) > 1e-6:
            raise ValueError(f"directions[{k!r}] must be a unit vector, got norm "
                             f"{float(np.linalg.norm(u)):.6g}")
    rr = np.array([base + check_real(f"slopes[{k!r}]", slopes[k], -base / size, 1e6) * size
                   for k in slopes])  # an RMSE >= 0 along each direction
    return U, rr, base, size


def earth_error_size(t0=ee.EPOCH_1997):
    """Size of the real DE421 - DE405 Earth error at ``t0``, m (the Earth runs' final size).

    Parameters
    ----------
    t0 : float
        Epoch, s TDB past J2000, within the years DE421 and DE405 both cover (1900-2199).

    Examples
    --------
    >>> round(earth_error_size())
    1492
    """
    t0 = check_epoch("t0", t0)  # named as given, not as the ephemeris' t
    return float(np.linalg.norm(ee.ephemeris_error("earth", t0)))
