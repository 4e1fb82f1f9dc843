"""What the main paper's time-transfer equation leaves out: every term, in seconds and metres.

Chapter 2's eq. (1) (:mod:`xnavlab.mars.timing.toa`) keeps the Roemer, parallax and the Sun's
Shapiro delay in the paper's approximate form. A timing code such as PINT (Luo et al.
2021) or Tempo2 (Edwards, Hobbs & Manchester 2006) also has

- the Sun's Shapiro delay in its exact form (Backer & Hellings 1986, eq. 4.6, gamma = 1),
  ``Delta = 2 mu/c^3 ln[(n.x + |x|)/(n.b + |b|)]`` with ``x`` the spacecraft and ``b`` the
  SSB seen from the Sun (:func:`xnavlab.mars.timing.toa.shapiro`); the paper's form
  (:func:`xnavlab.mars.timing.toa.shapiro_paper`) puts ``|R| + |b|`` where ``|x|`` belongs, which
  matters when the pulsar is seen close to the Sun (:func:`shapiro_by_angle`);
- the planets' Shapiro delays, the same formula with each planet's ``GM`` and position
  (:func:`planet_shapiro`);
- the time scale: a clock on board keeps its proper time, not TDB
  (:func:`xnavlab.mars.timing.toa.proper_time_terms`): a mean rate, a Mars-year term and the
  orbit-periodic term ``-V_Mars . r / c^2``.

Every term is returned as what it adds to ``Delta t = t_SSB - t_SC`` (chapter 2's sign):
the truth is the paper's model plus the term. A clock that runs ahead of TDB by ``tau -
TDB`` reads the arrival later, so it adds ``-(tau - TDB)``. :func:`orbit_terms` and
:func:`mars_year_terms` tabulate them; :func:`position_bias` projects a term through the
measurement geometry and :func:`xnav_run_with_term` runs the navigation filter with the term
in the truth only (the filter keeps the paper's model). :func:`pint_witness` sets our
numbers beside PINT's (:mod:`xnavlab.mars.timing.pint_bridge`), cached on disk.

Examples
--------
>>> out = shapiro_by_angle([1.0, 90.0])
>>> bool(abs(out["error"][0]) > abs(out["error"][1]))   # the paper's form is worst near the Sun
True
"""

from __future__ import annotations

import numpy as np

from xnavlab.core import ephemeris
from xnavlab.core.constants import DAY, GM_SUN, R_MARS, C
from xnavlab.core.diskcache import cached_arrays, entry_path
from xnavlab.core.validate import check_choice, check_finite_array, check_items, check_real, shown
from xnavlab.mars.models import dynamics
from xnavlab.mars.navigation import scenarios
from xnavlab.mars.timing import _checks, pulsars, toa
from xnavlab.mars.timing._checks import check_broadcast, check_outside

__all__ = [
    "PLANET_BODIES",
    "TERMS",
    "MARS_YEAR_DAYS",
    "RUNAWAY_M",
    "sun_angle_deg",
    "directions_from_sun",
    "shapiro_by_angle",
    "planet_shapiro",
    "clock_terms",
    "orbit_terms",
    "mars_year_terms",
    "closest_approach",
    "position_bias",
    "xnav_run_with_term",
    "navigation_effect",
    "pint_witness",
    "summary_rows",
    "plot_terms",
]

#: The bodies :func:`planet_shapiro` sums by default (those of :data:`xnavlab.mars.timing.toa.GM_DE421`
#: besides the Sun and the Moon; Jupiter and Saturn are their systems).
PLANET_BODIES = ("venus", "earth", "mars", "jupiter", "saturn")

#: The omitted terms :func:`orbit_terms` returns, each an addition to ``Delta t``, s.
TERMS = ("shapiro_exact_minus_paper", "planets", "clock", "clock_rate", "clock_mars_year",
         "clock_orbit")

#: An RMS position error beyond this (1000 km) is a filter that ran away, m: the worst term
#: the XNAV filter survives (the Mars-year clock term) leaves 6.1 km after 30 days.
RUNAWAY_M = 1e6

#: Mars's sidereal year, days (687 days; the span of :func:`mars_year_terms`).
MARS_YEAR_DAYS = 686.98


def sun_angle_deg(r_ssb, n, r_sun_ssb):
    """Angle between each pulsar and the Sun as seen from ``r_ssb``, degrees; shape (..., k).

    Parameters
    ----------
    r_ssb : array_like, shape (..., 3)
        Observer relative to the SSB, m, within 1e15 m (as :mod:`~xnavlab.mars.timing.toa`'s).
    n : array_like, shape (k, 3)
        Unit vectors to the pulsars (norm 1 within 1e-9).
    r_sun_ssb : array_like, shape (..., 3)
        Sun relative to the SSB, m, coordinates within 1e15 m, at least 1 m from ``r_ssb`` (the angle
        from the Sun's centre has no direction there).

    Examples
    --------
    >>> sun_angle_deg(np.array([1e11, 0, 0]), np.array([[-1.0, 0, 0], [0, 1.0, 0]]), np.zeros(3))
    array([ 0., 90.])
    """
    toa.roemer(r_ssb, n)  # validates r_ssb (norm <= 1e15 m) and n (unit vectors), by name
    r_ssb, n = np.asarray(r_ssb, dtype=float), np.asarray(n, dtype=float)
    r_sun = check_finite_array("r_sun_ssb", r_sun_ssb, shape=(3,))
    check_broadcast("r_sun_ssb", r_sun, "r_ssb", r_ssb, "one Sun position per observer position")
    if np.any(np.abs(r_sun) > 1e15):  # as r_ssb: their difference's norm stays finite
        raise ValueError(f"r_sun_ssb must have coordinates within 1e15 m of the SSB, got "
                         f"{float(np.abs(r_sun).max()):.6g} m")
    to_sun = r_sun - r_ssb
    dist = np.linalg.norm(to_sun, axis=-1)[..., None]
    if np.any(dist < 1.0):
        raise ValueError(f"r_sun_ssb must be at least 1 m from r_ssb (the Sun's direction is "
                         f"undefined at its centre), got {float(dist.min()):.6g} m")
    u = to_sun / dist
    return np.degrees(np.arccos(np.clip(u @ n.T, -1.0, 1.0)))


def directions_from_sun(angle_deg, t=None, ephem="de421"):
    """Unit vectors ``angle_deg`` from the Sun as seen from Mars's centre, shape (m, 3).

    In the plane of the Sun's direction and Mars's velocity (where a pulsar near the
    ecliptic passes behind the Sun), on the side Mars moves towards; the construction of
    :func:`xnavlab.mars.navigation.plots.plot_shapiro_angle`.

    Parameters
    ----------
    angle_deg : float or array_like, shape (m,)
        Angles, degrees, in (0, 180].
    t : float, optional
        Epoch, s TDB past J2000; default :data:`xnavlab.mars.models.dynamics.MARS_T0`.
    ephem : {"de421", "de405"}
        Ephemeris of Mars and the Sun.

    Examples
    --------
    >>> n = directions_from_sun([2.0, 30.0])
    >>> r_m, r_s = ephemeris.position("mars", dynamics.MARS_T0), ephemeris.position("sun", dynamics.MARS_T0)
    >>> sun_angle_deg(r_m, n, r_s).round(6)
    array([ 2., 30.])
    """
    theta = np.atleast_1d(check_finite_array("angle_deg", angle_deg))
    if theta.ndim != 1 or np.any((theta <= 0.0) | (theta > 180.0)):
        raise ValueError("angle_deg must hold angles in (0, 180] degrees")
    t = dynamics.MARS_T0 if t is None else _checks.check_epoch("t", t)
    r_mars, v_mars = (np.asarray(a, dtype=float).reshape(3) for a in ephemeris.state("mars", t, ephem))
    u = ephemeris.position("sun", t, ephem).reshape(3) - r_mars
    u /= np.linalg.norm(u)  # Mars -> Sun
    e = v_mars - (v_mars @ u) * u
    e /= np.linalg.norm(e)
    th = np.radians(theta)
    return np.cos(th)[:, None] * u + np.sin(th)[:, None] * e


def shapiro_by_angle(angle_deg, t=None, ephem="de421"):
    """The Sun's Shapiro delay at Mars's centre, exact and paper form, by Sun-pulsar angle.

    Parameters
    ----------
    angle_deg : float or array_like, shape (m,)
        Sun-pulsar angles seen from Mars, degrees, in (0, 180] (:func:`directions_from_sun`).
    t : float, optional
        Epoch, s TDB past J2000; default :data:`xnavlab.mars.models.dynamics.MARS_T0`.
    ephem : {"de421", "de405"}
        Ephemeris.

    Returns
    -------
    dict of ndarray, shape (m,)
        ``exact`` (:func:`xnavlab.mars.timing.toa.shapiro`), ``paper``
        (:func:`xnavlab.mars.timing.toa.shapiro_paper`) and ``error`` = paper - exact, s.

    Examples
    --------
    >>> out = shapiro_by_angle(0.5)
    >>> bool(abs(out["error"][0]) > 1e-6)   # microseconds, near the Sun
    True
    """
    t = dynamics.MARS_T0 if t is None else _checks.check_epoch("t", t)
    n = directions_from_sun(angle_deg, t, ephem)
    r_mars = ephemeris.position("mars", t, ephem).reshape(3)
    r_sun = ephemeris.position("sun", t, ephem).reshape(3)
    exact = toa.shapiro(r_mars, n, r_sun)  # Backer & Hellings eq. 4.6
    paper = toa.shapiro_paper(r_mars, n, r_sun)  # paper eq. (1), third term
    return {"exact": exact, "paper": paper, "error": paper - exact}


def planet_shapiro(r_ssb, t, n, bodies=PLANET_BODIES, reference="ssb", ephem="de421"):
    """The planets' Shapiro delays at ``r_ssb``, exact form, with chapter 2's sign, s.

    For each body ``p`` (``GM_p`` from :data:`xnavlab.mars.timing.toa.GM_DE421`), with ``x`` the
    observer and ``b`` the SSB seen from the body,

    ``Delta_p = 2 GM_p/c^3 ln[(n.x + |x|)/(n.b + |b|)]``  (Backer & Hellings 1986, eq. 4.6)

    referred to the SSB like :func:`xnavlab.mars.timing.toa.shapiro`; with ``reference="au"`` the
    denominator is 1 au instead, PINT's and Tempo2's convention (their ``PLANET_SHAPIRO``);
    ``reference="both"`` returns the two, one ephemeris look-up per body.

    Parameters
    ----------
    r_ssb : array_like, shape (m, 3) or (3,)
        Observer relative to the SSB, m, outside each of ``bodies`` (its polar radius).
    t : float or array_like, shape (m,)
        Epochs, s TDB past J2000.
    n : array_like, shape (k, 3)
        Unit vectors to the pulsars.
    bodies : sequence of str
        Bodies of :data:`xnavlab.mars.timing.toa.GM_DE421` other than the Sun, at least one,
        none twice (a repeat would count its delay twice in ``total``).
    reference : {"ssb", "au", "both"}
        What the delay is referred to.
    ephem : {"de421", "de405"}
        Ephemeris of the bodies.

    Returns
    -------
    dict of ndarray, shape (m, k) (or (k,))
        One entry per body and their sum ``total``, s; with ``reference="both"`` also the
        same referred to 1 au under the names ``<body>_au`` and ``total_au``.

    Examples
    --------
    >>> n, _ = pulsars.directions()
    >>> r = ephemeris.position("mars", dynamics.MARS_T0) + np.array([3.0e6, 1.0e6, -2.0e6])
    >>> out = planet_shapiro(r, dynamics.MARS_T0, n)
    >>> sorted(out)
    ['earth', 'jupiter', 'mars', 'saturn', 'total', 'venus']
    >>> bool(np.abs(out["total"]).max() < 1e-7)     # nanoseconds
    True
    """
    check_choice("reference", reference, ("ssb", "au", "both"))
    r = check_finite_array("r_ssb", r_ssb, shape=(3,))
    if r.ndim > 2:
        raise ValueError(f"r_ssb must have shape (3,) or (m, 3), got {r.shape}")
    n = check_finite_array("n", n, shape=(3,))
    t = _checks.check_epochs("t", t)
    if t.size == 0:  # no epoch: the bodies' positions are no (3,) vector
        raise ValueError("t must hold at least one epoch, got an empty array")
    rows = r.shape[0] if r.ndim == 2 else 1
    if t.ndim > 1 or (t.ndim == 1 and t.size != rows):  # as pint_bridge.planet_shapiro
        raise ValueError(f"t must be a scalar or have shape ({rows},) (one epoch per row of r_ssb), "
                         f"got shape {t.shape}")
    allowed = tuple(b for b in toa.GM_DE421 if b != "sun")
    bodies = check_items("bodies", bodies, "body name", lambda label, b: check_choice(label, b, allowed))
    ssb, au = {}, {}
    for body in bodies:
        r_p = ephemeris.position(body, t, ephem)
        r_p = r_p.reshape(3) if r.ndim == 1 else r_p  # t a scalar: one position for every row
        check_outside("r_ssb", np.linalg.norm(r - r_p, axis=-1), body)  # toa.shapiro named the Sun
        ratio = toa.GM_DE421[body] / GM_SUN  # toa.shapiro is 2 GM_sun/c^3 ln[...]
        # the body in place of the Sun: 2 GM_p/c^3 ln[(n.x + |x|)/(n.b + |b|)]
        ssb[body] = ratio * toa.shapiro(r, n, r_p)
        if reference != "ssb":  # ln[(n.x + |x|)/1 au]
            au[body] = ssb[body] - ratio * toa.shapiro_offset_to_pint(n, r_p)
    ssb["total"] = sum(ssb.values())
    if reference == "ssb":
        return ssb
    au["total"] = sum(au.values())
    if reference == "au":
        return au
    return {**ssb, **{f"{key}_au": value for key, value in au.items()}}


def clock_terms(t, x, ephem="de421"):
    """A clock on board against TDB, split in parts, each as it adds to ``Delta t``, s; shape (m,).

    From :func:`xnavlab.mars.timing.toa.proper_time_terms` (synchronised at ``t[0]``): ``clock``
    is ``-(tau - TDB)``, the whole offset; ``clock_orbit`` its orbit-periodic part,
    ``+V_Mars . r / c^2`` (the sign flip of ``orbit_term``); ``clock_rate`` the straight
    line fitted to the rest, ``-rate (t - t[0])`` plus a constant; ``clock_mars_year`` what
    is left: over a run much shorter than the Mars year, the curvature of the slowly
    changing rate along Mars's orbit.

    Parameters
    ----------
    t : array_like, shape (m,)
        Epochs, s TDB past J2000, increasing; steps much shorter than the orbit (float64: a
        float32 array resolves 32 s and is refused).
    x : array_like, shape (m, 6)
        Spacecraft states relative to Mars, m and m/s.
    ephem : {"de421", "de405"}
        Ephemeris.

    Returns
    -------
    dict of ndarray
        ``clock``, ``clock_rate``, ``clock_mars_year``, ``clock_orbit`` (s, shape (m,),
        summing to ``clock``) and ``rate`` (the mean of ``d(tau - TDB)/dTDB``, float).

    Examples
    --------
    >>> t = dynamics.MARS_T0 + np.arange(0.0, 86400.0 + 1.0, 60.0)
    >>> out = clock_terms(t, dynamics.truth(t))
    >>> round(out["rate"] * 1e9, 1), bool(np.allclose(out["clock"], out["clock_rate"]
    ...     + out["clock_mars_year"] + out["clock_orbit"], atol=1e-15))
    (6.7, True)
    """
    t = _checks.check_epochs("t", t)
    pt = toa.proper_time_terms(t, x, center="mars", ephem=ephem)
    clock = -pt["tau_minus_tdb"]  # a clock ahead of TDB reads the arrival late
    orbit = -pt["orbit_term"]  # +V_Mars . r / c^2
    smooth = clock - orbit
    fit = np.polyfit(t - t[0], smooth, 1)
    linear = np.polyval(fit, t - t[0])
    return {"clock": clock, "clock_rate": linear, "clock_mars_year": smooth - linear,
            "clock_orbit": orbit, "rate": float(-fit[0])}  # rate: mean d(tau - TDB)/dTDB


def orbit_terms(t, x, pulsar_names=pulsars.PAPER_PULSARS, ephem="de421"):
    """Every omitted term (:data:`TERMS`) along an orbit around Mars, each as it adds to ``Delta t``.

    Parameters
    ----------
    t : array_like, shape (m,)
        Epochs, s TDB past J2000, increasing (steps much shorter than the orbit), float64 (a
        float32 array resolves 32 s and is refused).
    x : array_like, shape (m, 6)
        Spacecraft states relative to Mars, J2000, m and m/s.
    pulsar_names : sequence of str
        The pulsars.
    ephem : {"de421", "de405"}
        Ephemeris.

    Returns
    -------
    dict of ndarray, shape (m, k)
        The terms of :data:`TERMS`, s (the clock terms, the same for every pulsar, repeated
        on the last axis); ``planets_au`` (the planets referred to 1 au, PINT's convention),
        ``sun_angle_deg`` (m, k) and ``rate`` (float).

    Examples
    --------
    >>> t = dynamics.MARS_T0 + np.arange(0.0, 86400.0 + 1.0, 600.0)
    >>> out = orbit_terms(t, dynamics.truth(t))
    >>> out["planets"].shape, bool(np.abs(out["shapiro_exact_minus_paper"]).max() < 1e-8)
    ((145, 4), True)
    """
    t = _epochs("t", t)
    x = check_finite_array("x", x, shape=(6,))
    if x.ndim != 2:
        raise ValueError(f"x must have shape (m, 6), one state per epoch, got {x.shape}")
    if t.size != x.shape[0]:  # x is a well-formed series: the epochs are the ones to match it
        raise ValueError(f"t must hold one epoch per row of x ({x.shape[0]}), got {t.size}")
    n, _ = pulsars.directions(pulsars.check_names(pulsar_names, "pulsar_names"))
    r = ephemeris.position("mars", t, ephem).reshape(-1, 3) + x[:, :3]
    r_sun = ephemeris.position("sun", t, ephem).reshape(-1, 3)
    clock = clock_terms(t, x, ephem)  # first: it names x inside Mars (planet_shapiro, r_ssb)
    planets = planet_shapiro(r, t, n, ephem=ephem, reference="both")
    out = {"shapiro_exact_minus_paper": toa.shapiro(r, n, r_sun) - toa.shapiro_paper(r, n, r_sun),
           "planets": planets["total"], "planets_au": planets["total_au"],
           "sun_angle_deg": sun_angle_deg(r, n, r_sun)}
    for key in ("clock", "clock_rate", "clock_mars_year", "clock_orbit"):
        out[key] = np.repeat(clock[key][:, None], n.shape[0], axis=1)
    out["rate"] = clock["rate"]
    return out


def mars_year_terms(t0=None, step_days=1.0, pulsar_names=pulsars.PAPER_PULSARS, ephem="de421",
                    orbit_radius_m=None):
    """The omitted terms at Mars's centre over one Mars year (:data:`MARS_YEAR_DAYS`).

    Parameters
    ----------
    t0 : float, optional
        Start, s TDB past J2000; default :data:`xnavlab.mars.models.dynamics.MARS_T0`.
    step_days : float
        Step, days (0.01 to 30).
    pulsar_names : sequence of str
        The pulsars.
    ephem : {"de421", "de405"}
        Ephemeris.
    orbit_radius_m : float, optional
        Radius for the bound of the orbit-periodic clock term, m, in [R_Mars, 1e10] (an orbit
        outside Mars, :data:`xnavlab.core.constants.R_MARS`); default the largest radius of
        the paper's orbit in its first day.

    Returns
    -------
    dict
        ``t`` (m,) s; ``shapiro_exact_minus_paper``, ``planets`` (:data:`PLANET_BODIES`
        but Mars, whose own delay at its centre is infinite), ``planets_au`` (the same
        referred to 1 au), ``sun_angle_deg`` (m, k);
        ``clock`` (m,): ``-(tau - TDB)`` of a clock riding with Mars; ``clock_mars_year``
        (m,): ``clock`` less its straight-line fit; ``rate`` (float): the mean rate of the
        clock; ``clock_orbit_bound`` (m,): ``|V_Mars| r / c^2``, the amplitude of the
        orbit-periodic term.

    Examples
    --------
    >>> out = mars_year_terms(step_days=10.0)
    >>> out["planets"].shape, bool(np.ptp(out["clock_mars_year"]) > 1e-3)    # milliseconds
    ((69, 4), True)
    """
    t0 = dynamics.MARS_T0 if t0 is None else _checks.check_epoch("t0", t0)
    step = check_real("step_days", step_days, 0.01, 30.0)
    if orbit_radius_m is None:
        day = dynamics.MARS_T0 + np.arange(0.0, DAY + 1.0, 600.0)
        orbit_radius_m = float(np.linalg.norm(dynamics.truth(day)[:, :3], axis=1).max())
    orbit_radius_m = check_real("orbit_radius_m", orbit_radius_m, R_MARS, 1e10)  # an orbit outside Mars
    t = t0 + np.arange(0.0, MARS_YEAR_DAYS * DAY, step * DAY)
    n, _ = pulsars.directions(pulsars.check_names(pulsar_names, "pulsar_names"))
    r_mars, v_mars = ephemeris.state("mars", t, ephem)
    r_sun = ephemeris.position("sun", t, ephem)
    clock = -toa.proper_time_terms(t, center="mars", ephem=ephem)["tau_minus_tdb"]
    fit = np.polyval(np.polyfit(t - t0, clock, 1), t - t0)
    planets = planet_shapiro(r_mars, t, n, bodies=tuple(b for b in PLANET_BODIES if b != "mars"),
                             ephem=ephem, reference="both")
    return {"t": t,
            "shapiro_exact_minus_paper": toa.shapiro(r_mars, n, r_sun) - toa.shapiro_paper(r_mars, n, r_sun),
            "planets": planets["total"], "planets_au": planets["total_au"],
            "sun_angle_deg": sun_angle_deg(r_mars, n, r_sun),
            "clock": clock, "clock_mars_year": clock - fit,
            "rate": float(-np.polyfit(t - t0, clock, 1)[0]),
            "clock_orbit_bound": np.linalg.norm(v_mars, axis=1) * orbit_radius_m / C**2}


def closest_approach(pulsar="B0531+21", t_start=None, years=1.0, step_days=0.5, ephem="de421"):
    """When a pulsar passes closest to the Sun as seen from Mars, and the paper form's error there.

    Parameters
    ----------
    pulsar : str
        A pulsar of :data:`xnavlab.mars.timing.pulsars.CATALOGUE`.
    t_start : float, optional
        Start of the search, s TDB past J2000; default :data:`xnavlab.mars.models.dynamics.MARS_T0`.
    years : float
        Length of the search in Mars years (0.1 to 25).
    step_days : float
        Search step, days (0.01 to 10); the minimum is refined on a 0.01-day grid around it.
    ephem : {"de421", "de405"}
        Ephemeris.

    Returns
    -------
    dict
        ``t`` (s TDB past J2000), ``angle_deg``, and at Mars's centre then ``exact``,
        ``paper`` and ``error`` = paper - exact (s, floats).

    Examples
    --------
    >>> out = closest_approach("B0531+21")
    >>> bool(out["angle_deg"] < 3.0 and abs(out["error"]) > 1e-6)
    True
    """
    t_start = dynamics.MARS_T0 if t_start is None else _checks.check_epoch("t_start", t_start)
    years = check_real("years", years, 0.1, 25.0)
    step = check_real("step_days", step_days, 0.01, 10.0)
    n, _ = pulsars.directions([pulsar])

    def angles(t):
        return sun_angle_deg(ephemeris.position("mars", t, ephem), n,
                             ephemeris.position("sun", t, ephem))[:, 0]

    t = t_start + np.arange(0.0, years * MARS_YEAR_DAYS * DAY, step * DAY)
    t_min = t[np.argmin(angles(t))]
    fine = t_min + np.arange(-step, step + 0.005, 0.01) * DAY
    a = angles(fine)
    i = int(np.argmin(a))
    r_m, r_s = ephemeris.position("mars", fine[i], ephem), ephemeris.position("sun", fine[i], ephem)
    exact = float(toa.shapiro(r_m, n, r_s)[0])
    paper = float(toa.shapiro_paper(r_m, n, r_s)[0])
    return {"t": float(fine[i]), "angle_deg": float(a[i]), "exact": exact, "paper": paper,
            "error": paper - exact}


def position_bias(delta, n, sigma):
    """The position offset a per-pulsar delay bias makes in a weighted least-squares fix, m.

    A snapshot of range measurements ``c Delta t_i = n_i . r`` with weights
    ``W = diag(sigma_i^-2)`` moves by ``dr = (N^T W N)^-1 N^T W c delta`` when each delay
    carries an unmodelled ``delta_i`` (the rows of ``N`` are the ``n_i``).

    Parameters
    ----------
    delta : array_like, shape (..., k)
        Delay biases, s, each in [-1e6, 1e6].
    n : array_like, shape (k, 3)
        Unit vectors to ``k >= 3`` pulsars.
    sigma : array_like, shape (k,)
        Ranging accuracies, m, each in [1e-3, 1e13] (:func:`xnavlab.mars.timing.toa.pdop`'s;
        required: the weights).

    Returns
    -------
    ndarray, shape (..., 3)
        Position offsets, m.

    Examples
    --------
    >>> position_bias(np.full(3, 1.0 / C), np.eye(3), np.ones(3))
    array([1., 1., 1.])
    """
    delta = check_finite_array("delta", delta)
    n = check_finite_array("n", n, shape=(3,))
    if sigma is None:  # pdop's "no weights"; here the weights of the fix (None was an IndexError)
        raise ValueError("sigma must be the pulsars' ranging accuracies, m, shape (k,) (the fix's "
                         "weights), got None")
    toa.pdop(n, sigma)  # validates the geometry (k >= 3, not coplanar) and sigma (1 mm to 1e13 m)
    if delta.shape[-1:] != (n.shape[0],):
        raise ValueError(f"delta must have shape (..., {n.shape[0]}), one per pulsar, got {delta.shape}")
    if np.any(np.abs(delta) > 1e6):  # c delta stays finite; 11 days is no delay bias
        raise ValueError(f"delta must be in [-1e6, 1e6] s, got {float(np.abs(delta).max()):.6g}")
    w = np.asarray(sigma, dtype=float) ** -2.0  # W = diag(sigma^-2)
    gain = np.linalg.solve(n.T @ (w[:, None] * n), n.T * w)  # (N^T W N)^-1 N^T W
    return (C * delta) @ gain.T


def xnav_run_with_term(term="clock_orbit", days=30.0, subsystems=("xnav",), seed=0, scale=1.0):
    """A navigation run whose truth has an omitted term that the filter's model does not.

    :func:`xnavlab.mars.navigation.scenarios.prepare` draws the XNAV delays from the paper's eq. (1);
    the term (:func:`orbit_terms` at the true states, times ``scale``) is added to them,
    and :func:`xnavlab.mars.navigation.scenarios.run` (the compiled filter, which keeps the paper's
    model) navigates. ``term=None`` is the run without it (the same noise draws).

    Parameters
    ----------
    term : str or None
        One of :data:`TERMS`, or None.
    days : float
        Span, days (0 to 365).
    subsystems : tuple of str
        Subsystems of the run; must include ``"xnav"``.
    seed : int
        Seed of the scenario's noise.
    scale : float
        Factor on the term (1 for the physical size); only with a term (with ``term=None``
        anything but 1 is refused: there is no term to scale).

    Returns
    -------
    xnavlab.mars.navigation.scenarios.MarsRun

    Raises
    ------
    RuntimeError
        When the filter breaks down (a covariance loses positive definiteness), as it
        does under a bias thousands of times its noise.

    Examples
    --------
    >>> run = xnav_run_with_term("planets", days=0.5)
    >>> bool(run.metrics()["position_error_m"] > 0)
    True
    """
    if term is not None:
        check_choice("term", term, TERMS)
    scale = check_real("scale", scale)
    if term is None and scale != 1.0:
        raise ValueError(f"scale is used only with a term: term=None runs without one, so scale = "
                         f"{scale:g} would be ignored (give a term, or leave scale at 1)")
    inp, terms = _inputs_and_terms(days, subsystems, seed)
    if term is not None:
        inp.z["xnav"] = inp.z["xnav"] + scale * terms[term]  # truth = paper eq. (1) + term
    return scenarios.run(inputs=inp)


def _inputs_and_terms(days, subsystems, seed):
    """The run's inputs and :func:`orbit_terms` at its XNAV epochs and true states."""
    subsystems = check_items("subsystems", subsystems, "subsystem")  # "uv" is no list of letters
    if "xnav" not in subsystems:
        raise ValueError(f"subsystems must include 'xnav', got {subsystems!r}")
    inp = scenarios.prepare(days=days, subsystems=subsystems, seed=seed)
    rows = inp.meas_idx[:, inp.scenario.subsystems.index("xnav")] >= 0
    terms = orbit_terms(inp.times[rows], inp.truth[rows], inp.scenario.pulsars,
                        inp.scenario.truth_ephem)
    return inp, terms


def navigation_effect(terms=TERMS, days=30.0, subsystems=("xnav",), seed=0):
    """The navigation error with each omitted term in the truth only, against the run without.

    One :func:`xnavlab.mars.navigation.scenarios.prepare` (the same noise draws for every run), then
    one run of the compiled filter per term, as :func:`xnav_run_with_term`.

    Parameters
    ----------
    terms : sequence of str
        Terms of :data:`TERMS`.
    days, subsystems, seed
        As :func:`xnav_run_with_term`.

    Returns
    -------
    dict
        ``None`` (the run without a term) and each term: a dict with
        ``position_error_m`` (RMS after settling), ``position_error_max_m`` and
        ``settle_days`` (:meth:`xnavlab.mars.navigation.scenarios.MarsRun.metrics`), or, when the
        filter broke down, ``failed`` (why). A breakdown is either a covariance that lost
        positive definiteness (the run raised) or an estimate that ran away (RMS position
        error beyond :data:`RUNAWAY_M`, its metrics kept beside ``failed``): which of the
        two a marginal run meets can depend on the CPU's BLAS kernels, so both are one
        outcome here.

    Examples
    --------
    >>> out = navigation_effect(("planets",), days=0.5)
    >>> sorted(out, key=str), bool(out["planets"]["position_error_m"] > 0)
    ([None, 'planets'], True)
    """
    terms = check_items("terms", terms, "term", lambda label, t: check_choice(label, t, TERMS))
    inp, table = _inputs_and_terms(days, subsystems, seed)
    z0 = inp.z["xnav"]
    out = {}
    for term in (None, *terms):
        inp.z["xnav"] = z0 if term is None else z0 + table[term]  # truth = paper eq. (1) + term
        try:
            m = scenarios.run(inputs=inp).metrics()
        except RuntimeError as exc:  # the filter broke down
            out[term] = {"failed": str(exc)}
            continue
        out[term] = {k: m[k] for k in ("position_error_m", "position_error_max_m", "settle_days")}
        if m["position_error_m"] > RUNAWAY_M:  # broke down too, the covariance still valid
            out[term]["failed"] = (f"the estimate ran away: RMS position error "
                                   f"{m['position_error_m']:.3g} m, beyond {RUNAWAY_M:.0e} m")
    inp.z["xnav"] = z0
    return out


def _cache_path(kind, arrays):
    return entry_path("pint-witness", (kind,), [np.asarray(a, dtype=float) for a in arrays],
                      (__name__,), versions=("pint-pulsar",))


def pint_witness(r_ssb, t, n, distance):
    """Our delays against PINT's at spacecraft positions ``r_ssb``: every term PINT models.

    Calls :func:`xnavlab.mars.timing.pint_bridge.pint_delays` (with the planets) and subtracts
    PINT's numbers from ours, each turned to PINT's reference: the Sun's exact Shapiro
    delay less :func:`xnavlab.mars.timing.toa.shapiro_offset_to_pint`, the planets'
    (:func:`planet_shapiro`) with ``reference="au"``. PINT's import takes about ten
    seconds, so the result is cached on disk under ``$XNAVLAB_CACHE`` (default
    ``~/.cache/xnavlab``), keyed by the inputs and PINT's version.

    Parameters
    ----------
    r_ssb : array_like, shape (m, 3)
        Spacecraft positions relative to the SSB, m (no component exactly 0).
    t : array_like, shape (m,)
        Epochs, s TDB past J2000.
    n : array_like, shape (k, 3)
        Unit vectors to the pulsars.
    distance : array_like, shape (k,)
        Pulsar distances, m.

    Returns
    -------
    dict of ndarray, shape (m, k)
        ``roemer``, ``parallax``, ``shapiro`` (the Sun, exact form), ``shapiro_paper``
        (the paper's form), ``jupiter``, ``saturn``, ``venus``: ours minus PINT's, s;
        ``pint_uranus_neptune``: PINT's Uranus and Neptune (which our ephemeris lacks), s;
        ``pint_planets``: PINT's five planets, s; both referred to 1 au.

    Examples
    --------
    >>> n, d = pulsars.directions()
    >>> out = pint_witness(np.array([[2.0e11, 1.0e11, 3.0e10]]), [5.0e8], n, d)  # doctest: +SKIP
    >>> bool(np.abs(out["shapiro"]).max() < 1e-11)  # doctest: +SKIP
    True
    """
    r = np.atleast_2d(check_finite_array("r_ssb", r_ssb, shape=(3,)))
    t = np.atleast_1d(_checks.check_epochs("t", t))
    n = check_finite_array("n", n, shape=(3,))
    d = check_finite_array("distance", distance)
    return cached_arrays(_cache_path("terms", (r, t, n, d)), lambda: _witness(r, t, n, d))


def _witness(r, t, n, d):
    """:func:`pint_witness`'s arrays, computed (PINT's import and its delays)."""
    from xnavlab.mars.timing import pint_bridge

    pint = pint_bridge.pint_delays(r, t, n, d, planets=True)
    r_sun = ephemeris.position("sun", t).reshape(-1, 3)
    offset = toa.shapiro_offset_to_pint(n, r_sun)
    ours = planet_shapiro(r, t, n, bodies=("jupiter", "saturn", "venus"), reference="au")
    out = {"roemer": toa.roemer(r, n) - pint["roemer"],
           "parallax": toa.parallax(r, n, d) - pint["parallax"],
           "shapiro": toa.shapiro(r, n, r_sun) - offset - pint["shapiro"],
           "shapiro_paper": toa.shapiro_paper(r, n, r_sun) - offset - pint["shapiro"],
           "pint_uranus_neptune": pint["shapiro_uranus"] + pint["shapiro_neptune"],
           "pint_planets": sum(pint[f"shapiro_{p}"] for p in pint_bridge.PLANETS)}
    for p in ("jupiter", "saturn", "venus"):
        out[p] = ours[p] - pint[f"shapiro_{p}"]
    return out


_LABELS = {
    "shapiro_exact_minus_paper": "Sun's Shapiro: exact minus the paper's form",
    "planets": "planets' Shapiro (Venus, Earth, Mars, Jupiter, Saturn)",
    "clock": "clock: tau - TDB, whole",
    "clock_rate": "clock: mean rate",
    "clock_mars_year": "clock: Mars-year term",
    "clock_orbit": "clock: orbit term V_Mars . r / c^2",
}


_ORBIT_KEYS = (*TERMS, "planets_au")
_YEAR_KEYS = ("t", "shapiro_exact_minus_paper", "planets", "planets_au", "clock", "clock_mars_year",
              "clock_orbit_bound")


def _epochs(name, value):
    """``value`` as a non-empty 1-D array of finite epochs, else one ValueError naming ``name``."""
    t = _checks.check_epochs(name, value)  # float32: 32 s at 5e8 s (review 35l (5) 5)
    if t.ndim != 1 or t.size == 0:
        raise ValueError(f"{name} must be a non-empty 1-D array of epochs, got shape {t.shape}")
    return t


def _terms(name, value, keys, what):
    """``value`` if it is a dict holding ``keys`` (what :func:`orbit_terms` or
    :func:`mars_year_terms` returns), else one ValueError naming ``name``."""
    if not isinstance(value, dict) or any(k not in value for k in keys):
        raise ValueError(f"{name} must be the dict of {what} (with {', '.join(keys)}), got {shown(value)}")
    return value


def _year_term(year, term):
    """The Mars-year counterpart of an orbit term, s, shape (m, k) or (m,)."""
    if term == "clock_rate":
        return year["clock"] - year["clock_mars_year"]
    if term == "clock_orbit":
        return year["clock_orbit_bound"]
    return year[term]


def _nav(nav):
    """``nav`` if it is :func:`navigation_effect`'s dict, else one ValueError naming the entry."""
    if not isinstance(nav, dict):
        raise ValueError(f"nav must be the dict of navigation_effect(), got {shown(nav)}")
    for key, value in nav.items():
        if key is not None and key not in TERMS:  # a term that no row shows
            raise ValueError(f"nav[{key!r}] is no term: nav's keys are None and terms of TERMS "
                             f"({', '.join(TERMS)})")
        if not isinstance(value, dict) or not ({"failed", "position_error_m"} & set(value)):
            raise ValueError(f"nav[{key!r}] must be a dict with position_error_m or failed (as "
                             f"navigation_effect() gives), got {shown(value)}")
        if "failed" not in value:
            check_real(f"nav[{key!r}]['position_error_m']", value["position_error_m"])
    return nav


def summary_rows(orbit, year, n, sigma, witness=None, nav=None):
    """One row per omitted term (:data:`TERMS`): sizes, ours against PINT, effect on navigation.

    Parameters
    ----------
    orbit : dict
        :func:`orbit_terms` along the orbit.
    year : dict
        :func:`mars_year_terms`.
    n : array_like, shape (k, 3)
        Unit vectors to the pulsars.
    sigma : array_like, shape (k,)
        Ranging accuracies of the pulsars, m (for :func:`position_bias`).
    witness : dict, optional
        :func:`pint_witness` (with ``shapiro``, ``jupiter``, ``saturn``, ``venus``); without it
        the column says ``-``.
    nav : dict, optional
        :func:`navigation_effect` (keys ``None`` and terms of :data:`TERMS`); without it, or for
        a term it lacks, the column says ``-``.

    Returns
    -------
    header : list of str
    rows : list of list
        Floats (s, m) or text, for :func:`xnavlab.core.plotting.html_table`.

    Examples
    --------
    >>> t = dynamics.MARS_T0 + np.arange(0.0, 86400.0 + 1.0, 600.0)
    >>> n, _ = pulsars.directions()
    >>> header, rows = summary_rows(orbit_terms(t, dynamics.truth(t)), mars_year_terms(step_days=10.0),
    ...                             n, [109.0, 344.0, 1866.0, 325.0])
    >>> len(header), len(rows), rows[0][0]
    (8, 6, "Sun's Shapiro: exact minus the paper's form")
    """
    orbit = _terms("orbit", orbit, TERMS, "orbit_terms()")
    year = _terms("year", year, _YEAR_KEYS, "mars_year_terms()")
    pint_col = {"shapiro_exact_minus_paper": "shapiro", "planets": ("jupiter", "saturn", "venus")}
    if witness is not None:
        witness = _terms("witness", witness, ("shapiro", "jupiter", "saturn", "venus"), "pint_witness()")
    nav = {} if nav is None else _nav(nav)
    header = ["term", "orbit, 30 days: max (s)", "(m)", "Mars year: max (s)", "(m)",
              "ours minus PINT: max (s)", "snapshot position bias, orbit (m)",
              "XNAV filter RMS position error (m)"]
    rows = []
    for term in TERMS:
        on_orbit = float(np.abs(orbit[term]).max())
        in_year = float(np.abs(_year_term(year, term)).max())
        bias = float(np.linalg.norm(position_bias(orbit[term], n, sigma), axis=-1).max())
        if witness is None:
            theirs = "-"
        elif term in pint_col:
            keys = pint_col[term] if isinstance(pint_col[term], tuple) else (pint_col[term],)
            theirs = float(max(np.abs(check_finite_array(f"witness[{key!r}]", witness[key])).max()
                               for key in keys))
        else:
            theirs = "not in PINT (it takes TDB epochs)"
        if term not in nav:
            effect = "-"
        elif "failed" in nav[term]:
            effect = "the filter breaks down"
        else:
            effect = float(nav[term]["position_error_m"])
        rows.append([_LABELS[term], on_orbit, C * on_orbit, in_year, C * in_year, theirs, bias, effect])
    return header, rows


def plot_terms(t, orbit, year, witness_t=None, witness=None):
    """Every omitted term in metres (``c`` times its largest value over the pulsars), log scale.

    Left: around the paper's orbit; right: over a Mars year at Mars's centre (the orbit
    clock term as its amplitude), both counted in days from ``t[0]`` (so ``year`` should
    start there). PINT's numbers, where given, are markers: the paper's
    Shapiro form against PINT's exact one and PINT's five planets (referred to 1 au,
    beside ours referred to 1 au, dashed).

    Parameters
    ----------
    t : array_like, shape (m,)
        Epochs of ``orbit``, s TDB past J2000.
    orbit, year : dict
        :func:`orbit_terms` and :func:`mars_year_terms`.
    witness_t : array_like, shape (k,), optional
        Epochs of ``witness`` (:func:`pint_witness`); given with ``witness`` only.
    witness : dict, optional
        :func:`pint_witness` at ``witness_t`` (with ``shapiro_paper`` and ``pint_planets``).

    Returns
    -------
    matplotlib.figure.Figure
        Two axes; not registered with pyplot.

    Examples
    --------
    >>> t = dynamics.MARS_T0 + np.arange(0.0, 86400.0 + 1.0, 600.0)
    >>> fig = plot_terms(t, orbit_terms(t, dynamics.truth(t)), mars_year_terms(step_days=10.0))
    >>> [ax.get_yscale() for ax in fig.axes]
    ['log', 'log']
    """
    from matplotlib.figure import Figure

    t = _epochs("t", t)
    orbit = _terms("orbit", orbit, _ORBIT_KEYS, "orbit_terms()")
    year = _terms("year", year, _YEAR_KEYS, "mars_year_terms()")
    rows = {np.shape(orbit[k])[0] if np.ndim(orbit[k]) else 0 for k in _ORBIT_KEYS}
    if len(rows) != 1:
        raise ValueError(f"orbit must hold every term at the same epochs (orbit_terms()), got "
                         f"{sorted(rows)} rows")
    if rows != {t.size}:  # orbit is the run's series: its epochs are the ones to match it
        raise ValueError(f"t must hold one epoch per row of orbit's terms ({rows.pop()}), got {t.size}")
    fig = Figure(figsize=(12, 5.2), layout="constrained")
    axes = fig.subplots(1, 2, sharey=True)
    panels = ((axes[0], (t - t[0]) / DAY, orbit, "days of the paper's run (around the orbit)"),
              (axes[1], (year["t"] - year["t"][0]) / DAY, year, "days of a Mars year (at Mars's centre)"))
    for ax, days, data, xlabel in panels:
        for i, term in enumerate(TERMS):
            value = data[term] if data is orbit else _year_term(year, term)
            size = np.abs(value).max(axis=-1) if np.ndim(value) == 2 else np.abs(value)
            ax.plot(days, C * np.maximum(size, 1e-30), color=f"C{i}", label=_LABELS[term])
        ax.plot(days, C * np.abs(data["planets_au"]).max(axis=-1), "--", color="C1",
                label="planets' Shapiro referred to 1 au (PINT's convention)")
        ax.set(yscale="log", xlabel=xlabel, ylim=(1e-2, 1e9))
    if witness is None and witness_t is not None:
        raise ValueError("witness_t is used only with witness (the epochs of pint_witness()), "
                         "got witness_t without witness")
    if witness is not None:
        witness = _terms("witness", witness, ("shapiro_paper", "pint_planets"), "pint_witness()")
        if witness_t is None:
            raise ValueError("witness_t must be given with witness (the epochs of pint_witness())")
        wt = (check_finite_array("witness_t", witness_t) - t[0]) / DAY
        for ax, span in ((axes[0], (t[-1] - t[0]) / DAY), (axes[1], (year["t"][-1] - t[0]) / DAY)):
            inside = (wt >= -1e-9) & (wt <= span + 1e-9)
            ax.plot(wt[inside], C * np.abs(witness["shapiro_paper"][inside]).max(axis=-1), "kx",
                    label="PINT: paper's form minus PINT's Shapiro")
            ax.plot(wt[inside], C * np.abs(witness["pint_planets"][inside]).max(axis=-1), "k+",
                    label="PINT: its five planets")
    axes[0].set_ylabel("largest over the pulsars, times c (m)")
    handles, labels = axes[1].get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=8, ncol=3, loc="outside lower center")
    return fig
