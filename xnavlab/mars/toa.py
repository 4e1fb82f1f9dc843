"""The time-transfer (TOA) equation of X-ray pulsar navigation and its gradient.

A pulse reaches the spacecraft earlier than the solar-system barycentre (SSB) by

.. math::

   \\Delta t = \\frac{n \\cdot R}{c}
   + \\frac{(n \\cdot R)^2 - |R|^2}{2 c D_0}
   + \\frac{2 \\mu_\\odot}{c^3} \\ln\\left| \\frac{n \\cdot R + |R|}{n \\cdot b + |b|} + 1 \\right|

(paper eq. (1); Sheikh et al. 2006), with ``R = r_M + r`` the spacecraft position
relative to the SSB (``r`` planet-centred, ``r_M`` the planet relative to the SSB),
``n`` the unit vector to the pulsar, ``D0`` its distance and ``b`` the SSB position
relative to the Sun. The three terms are the Roemer delay (geometry), the parallax
(curvature of the wavefront) and the Shapiro delay (the Sun's gravity), each
available on its own.

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
from xnavlab.core.constants import GM_SUN, C
from xnavlab.core.validate import check_choice, check_finite_array, check_int, check_real
from xnavlab.mars import pulsars

__all__ = [
    "roemer",
    "parallax",
    "shapiro",
    "delay",
    "gradient",
    "terms",
    "delays_at",
    "pdop",
    "gradient_fd",
    "plot_orbit_terms",
]


def _args(r_ssb, n):
    r_ssb = check_finite_array("r_ssb", r_ssb, shape=(3,))
    n = check_finite_array("n", n, shape=(3,))
    if n.ndim != 2:
        raise ValueError(f"n must have shape (k, 3), got {n.shape}")
    if np.any(np.abs(np.linalg.norm(n, axis=-1) - 1.0) > 1e-9):
        raise ValueError("n must hold unit vectors (|n| = 1 within 1e-9)")
    return r_ssb, n


def _distance(distance, k):
    d = check_finite_array("distance", distance)
    d = np.broadcast_to(d, (k,)) if d.ndim == 0 else d
    if d.shape != (k,) or np.any(d <= 0):
        raise ValueError(f"distance must be positive with shape ({k},), got {np.shape(distance)}")
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

    Always <= 0: the wavefront is a sphere centred on the pulsar, not a plane.

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
    return -check_finite_array("r_sun_ssb", r_sun_ssb, shape=(3,))


def shapiro(r_ssb, n, r_sun_ssb):
    """Shapiro delay ``2 mu/c^3 ln|(n.R + |R|)/(n.b + |b|) + 1|``, s; shape (..., k).

    Parameters
    ----------
    r_ssb : array_like, shape (..., 3)
        Spacecraft position relative to the SSB, m.
    n : array_like, shape (k, 3)
        Unit vectors to the pulsars.
    r_sun_ssb : array_like, shape (..., 3)
        Sun position relative to the SSB, m (so ``b = -r_sun_ssb``).

    Examples
    --------
    >>> s = shapiro(np.array([2.2e11, 0, 0]), np.array([[0.0, 1.0, 0.0]]), np.zeros(3) + 1e8)
    >>> bool(0 < s[0] < 1e-4)
    True
    """
    r_ssb, n = _args(r_ssb, n)
    b = _b(r_sun_ssb)
    u = r_ssb @ n.T + np.linalg.norm(r_ssb, axis=-1)[..., None]
    w = b @ n.T + np.linalg.norm(b, axis=-1)[..., None]
    return 2.0 * GM_SUN / C**3 * np.log(np.abs(u / w + 1.0))  # paper eq. (1), third term


def delay(r_ssb, n, distance, r_sun_ssb):
    """Time-transfer delay, paper eq. (1): Roemer + parallax + Shapiro, s; shape (..., k).

    Examples
    --------
    >>> nvec, dist = pulsars.directions()
    >>> delay(np.array([2.0e11, 1e10, 0.0]), nvec, dist, np.zeros(3) + 1e8).shape
    (4,)
    """
    return roemer(r_ssb, n) + parallax(r_ssb, n, distance) + shapiro(r_ssb, n, r_sun_ssb)


def gradient(r_ssb, n, distance, r_sun_ssb):
    """Gradient of :func:`delay` with respect to the spacecraft position, s/m.

    Because ``R = r_M + r``, the gradient with respect to the planet-centred ``r`` is
    the same; these are the position columns of the rows of ``H1`` (paper eq. (4)):

    - Roemer: ``n / c``
    - parallax: ``((n . R) n - R) / (c D0)``
    - Shapiro: ``2 mu/c^3 (n + R/|R|) / (n.R + |R| + n.b + |b|)``

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
    r_ssb, n = _args(r_ssb, n)
    d = _distance(distance, n.shape[0])
    b = _b(r_sun_ssb)
    R = r_ssb[..., None, :]
    nr = (r_ssb @ n.T)[..., None]
    rn = np.linalg.norm(r_ssb, axis=-1)[..., None, None]
    u = nr + rn
    w = (b @ n.T)[..., None] + np.linalg.norm(b, axis=-1)[..., None, None]
    g_roemer = n / C
    g_parallax = (nr * n - R) / (C * d[:, None])
    g_shapiro = 2.0 * GM_SUN / C**3 * (n + R / rn) / (u + w)
    return g_roemer + g_parallax + g_shapiro


def terms(r_ssb, n, distance, r_sun_ssb):
    """The three terms of eq. (1) separately: dict with ``roemer``, ``parallax``, ``shapiro``.

    Examples
    --------
    >>> nvec, dist = pulsars.directions()
    >>> sorted(terms(np.array([2e11, 0, 0]), nvec, dist, np.ones(3) * 1e8))
    ['parallax', 'roemer', 'shapiro']
    """
    return {
        "roemer": roemer(r_ssb, n),
        "parallax": parallax(r_ssb, n, distance),
        "shapiro": shapiro(r_ssb, n, r_sun_ssb),
    }


def delays_at(r, t, pulsar_names=pulsars.PAPER_PULSARS, center="mars", ephem="de421"):
    """Eq. (1) delays for a spacecraft at ``r`` about ``center`` at epochs ``t``.

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

    Returns
    -------
    ndarray, shape (k,) or (n, k)
        Delays, s.

    Examples
    --------
    >>> delays_at([-3.4e6, -1.3e6, -2.6e6], 5.0e8).shape
    (4,)
    """
    n, d = pulsars.directions(pulsar_names)
    r = check_finite_array("r", r, shape=(3,))
    r_c = ephemeris.position(center, t, ephem)
    r_sun = ephemeris.position("sun", t, ephem)
    return delay(r + r_c, n, d, r_sun)


def pdop(n, sigma=None):
    """Geometry of a pulsar set: position dilution of precision and snapshot position error.

    With unit vectors ``n`` (rows) and ranging noise ``sigma`` (m), a single snapshot of
    range-like measurements ``c dt = n . r`` determines the position with covariance
    ``(N^T W N)^-1``, ``W = diag(sigma^-2)``. ``PDOP = sqrt(tr (N^T N)^-1)``.

    Parameters
    ----------
    n : array_like, shape (k, 3)
        Unit vectors to ``k >= 3`` pulsars.
    sigma : array_like, shape (k,), optional
        Ranging accuracies, m.

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
    n = check_finite_array("n", n, shape=(3,))
    if n.ndim != 2 or n.shape[0] < 3:
        raise ValueError(f"n must have shape (k, 3) with k >= 3, got {n.shape}")
    gram = n.T @ n
    if np.linalg.cond(gram) > 1e12:
        raise ValueError("n must span three dimensions (the pulsar directions are coplanar)")
    value = float(np.sqrt(np.trace(np.linalg.inv(gram))))
    if sigma is None:
        return value
    sigma = check_finite_array("sigma", sigma)
    if sigma.shape != (n.shape[0],) or np.any(sigma <= 0):
        raise ValueError(f"sigma must be positive with shape ({n.shape[0]},), got {sigma.shape}")
    w = sigma**-2.0
    return value, float(np.sqrt(np.trace(np.linalg.inv(n.T @ (w[:, None] * n)))))


def gradient_fd(r_ssb, n, distance, r_sun_ssb, step=1.0e3, which=("roemer", "parallax", "shapiro")):
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
        Finite-difference step, m (> 0).
    which : sequence of {"roemer", "parallax", "shapiro"}
        The terms to differentiate (default all three, the whole delay).

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
    r_ssb = check_finite_array("r_ssb", r_ssb, shape=(3,))
    step = check_real("step", step, 0.0, lo_open=True)
    which = tuple(which)
    if not which:
        raise ValueError("which must name at least one of roemer, parallax, shapiro")
    for name in which:
        check_choice("which", name, ("roemer", "parallax", "shapiro"))

    def f(point):
        t = terms(point, n, distance, r_sun_ssb)
        return sum(t[name] for name in which)

    cols = [(f(r_ssb + step * e) - f(r_ssb - step * e)) / (2.0 * step) for e in np.eye(3)]
    return np.column_stack(cols)


def plot_orbit_terms(pulsar="B0531+21", day=0):
    """The orbit-dependent part of each delay term over one day of the paper's 30-day orbit.

    Spacecraft minus Mars centre, ``c (term(R_M + r) - term(R_M))``, for one pulsar, on
    the 60-s grid of the 30-day truth (:func:`xnavlab.mars.dynamics.truth` from
    ``MARS_T0``, cached on disk). A pure function of its arguments, for chapter 2's slider.

    Parameters
    ----------
    pulsar : str
        One of :data:`xnavlab.mars.pulsars.PAPER_PULSARS`.
    day : int
        Day of the 30, 0 to 29.

    Returns
    -------
    matplotlib.figure.Figure
        Three axes: Roemer (km), parallax (cm), Shapiro (cm); not registered with pyplot.

    Examples
    --------
    >>> fig = plot_orbit_terms("B1937+21", 3)
    >>> [ax.get_xlabel() for ax in fig.axes]
    ['hours into day 3', 'hours into day 3', 'hours into day 3']
    """
    from matplotlib.figure import Figure

    from xnavlab.mars import dynamics

    check_choice("pulsar", pulsar, pulsars.PAPER_PULSARS)
    day = check_int("day", day, 0, 29)
    t = dynamics.MARS_T0 + np.arange(0.0, 30 * 86400.0 + 1.0, 60.0)  # the chapter's grid
    i = slice(day * 1440, (day + 1) * 1440 + 1)  # one day of 60-s samples
    x = dynamics.truth(t)[i]
    t = t[i]
    r_mars = ephemeris.position("mars", t)
    r_sun = ephemeris.position("sun", t)
    n_p, d_p = pulsars.directions([pulsar])
    at_sc = terms(r_mars + x[:, :3], n_p, d_p, r_sun)
    at_mars = terms(r_mars, n_p, d_p, r_sun)
    hours = (t - t[0]) / 3600.0
    fig = Figure(figsize=(12, 3.4), layout="constrained")
    axes = fig.subplots(1, 3)
    units = {"roemer": (1e-3, "km"), "parallax": (1e2, "cm"), "shapiro": (1e2, "cm")}
    for ax, (key, (scale, unit)) in zip(axes, units.items(), strict=True):
        ax.plot(hours, C * (at_sc[key] - at_mars[key])[:, 0] * scale)
        ax.set(title=f"{key} $\\times c$, spacecraft - Mars ({unit})",
               xlabel=f"hours into day {day}")
    fig.suptitle(pulsar)
    return fig
