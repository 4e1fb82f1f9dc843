"""Orbit dynamics about Mars in the Mars-centred J2000 frame, the truth propagator and the STM.

The model of the main paper (Fan et al. 2016, section 4.1): Mars point-mass gravity
plus the third-body perturbations of the Sun and Jupiter, from the JPL ephemeris;
Mars's J2 is optional. For a third body at ``s`` (relative to Mars) the perturbing
acceleration includes the indirect term (the body also accelerates Mars):

.. math::

   a_k = \\mu_k \\left( \\frac{s - r}{|s - r|^3} - \\frac{s}{|s|^3} \\right)

Ephemeris look-ups are tabulated once per run (:class:`ThirdBodyTable`: positions
and velocities every hour, cubic Hermite interpolation, error below a centimetre),
so the integrator never calls jplephem in its inner loop.

State vectors are ``[x, y, z, vx, vy, vz]`` in m and m/s; time is s TDB past J2000.

Examples
--------
>>> bool(np.linalg.norm(MARS_STATE0[:3]) > 4.5e6)
True
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import NamedTuple

import numba
import numpy as np

from xnavlab.core import ephemeris
from xnavlab.core.constants import AU, GM_JUPITER, GM_MARS, GM_SUN, J2_MARS, J2_MARS_RADIUS, R_MARS
from xnavlab.core.diskcache import entry_path, load_array, store
from xnavlab.core.validate import (
    check_bool,
    check_choice,
    check_finite_array,
    check_instance,
    check_int,
    check_items,
    check_real,
    check_vector,
)
from xnavlab.mars.models import _checks

#: The longest propagation, days past ``t0`` (:func:`propagate`, :func:`truth`): about four
#: minutes of integration; a longer span is refused up front.
MAX_SPAN_DAYS = _checks.MAX_SPAN_DAYS

__all__ = [
    "MARS_T0",
    "MARS_STATE0",
    "MARS_POLE",
    "GM_BODIES",
    "MAX_GM",
    "R_MIN",
    "R_MAX",
    "MAX_BODY_RADIUS",
    "MAX_SPAN_DAYS",
    "ThirdBodyTable",
    "point_mass",
    "third_body",
    "j2_acceleration",
    "acceleration",
    "IMPACT_EVENTS",
    "check_impact",
    "V_INF_MAX",
    "R_HILL",
    "check_state0",
    "propagate",
    "truth",
    "chapter_times",
    "chapter_truths",
    "gravity_gradient",
    "transition_matrix",
    "OrbitalElements",
    "orbital_elements",
    "model_difference",
    "plot_model_difference",
]

#: Scenario epoch: 2016-01-01 00:00 TDB, s past J2000 (the paper gives none; we chose
#: the start of its publication year).
MARS_T0 = 504_878_400.0
#: The paper's initial state (section 4.1), Mars-centred J2000, m and m/s.
MARS_STATE0 = np.array([
    -3437565.6220408, -1322042.9896803, -2631212.18533248,
    1953.976776814, -253.7102283189, -2198.7761971543,
])
#: Mars north pole in ICRF (IAU WGCCRE 2015: alpha0 = 317.68143 deg, delta0 = 52.88650 deg at J2000).
MARS_POLE = np.array([
    math.cos(math.radians(52.88650)) * math.cos(math.radians(317.68143)),
    math.cos(math.radians(52.88650)) * math.sin(math.radians(317.68143)),
    math.sin(math.radians(52.88650)),
])
#: GM of the third bodies that can be switched on, m^3/s^2.
GM_BODIES = {"sun": GM_SUN, "jupiter": GM_JUPITER}
#: The largest central GM the force model takes, m^3/s^2: about 7.5 solar masses, above any
#: body a spacecraft orbits (10 x GM_SUN would still be a star; 1e308 overflowed ``gm * r``).
MAX_GM = 1e21
#: Distances from the centre a position may have, m: from 1 m (the point-mass field is
#: singular at the centre; its gradient's ``1/|r|^5`` overflows below about 1e-57 m) to 1e15 m
#: (6,700 au, past every planet; ``|r|^3`` overflows above 1e102 m).
R_MIN, R_MAX = 1.0, 1e15
#: The largest reference radius of a body, m: above the Sun's 6.96e8 m.
MAX_BODY_RADIUS = 1e9


@dataclass
class ThirdBodyTable:
    """Third-body positions relative to the centre body, tabulated for fast interpolation.

    Parameters
    ----------
    t_start, t_end : float
        Span to cover, s TDB past J2000, ``t_start <= t_end``, both inside the ephemeris's
        :func:`~xnavlab.core.ephemeris.coverage` with two steps to spare at the end.
    bodies : sequence of str
        Third bodies (keys of :data:`GM_BODIES`).
    center : str
        Centre body.
    ephem : {"de421", "de405"}
    step : float
        Knot spacing, s (default one hour).
    gm : sequence of float, optional
        GM of each body, m^3/s^2; then ``bodies`` may be any of
        :data:`xnavlab.core.ephemeris.BODIES` (:mod:`xnavlab.mars.models.force_models` tabulates the
        planets so). Default: :data:`GM_BODIES`.

    Examples
    --------
    >>> tab = ThirdBodyTable(MARS_T0, MARS_T0 + 86400.0)
    >>> tab.positions(MARS_T0 + 1800.0).shape
    (2, 3)
    """

    t_start: float
    t_end: float
    bodies: tuple = ("sun", "jupiter")
    center: str = "mars"
    ephem: str = "de421"
    step: float = 3600.0
    gm: tuple | None = None

    def __post_init__(self):
        self.step = check_real("step", self.step, 1.0, 86400.0)
        check_choice("center", self.center, ephemeris.BODIES)  # not ephemeris's 'body' (35k)
        lo, hi = ephemeris.coverage(self.ephem)
        # the knots run two steps past t_end; every one must lie inside the ephemeris
        self.t_start = _checks.epoch("t_start", self.t_start, lo, hi - 2.0 * self.step)
        self.t_end = _checks.epoch("t_end", self.t_end, self.t_start, hi - 2.0 * self.step)
        known = tuple(GM_BODIES) if self.gm is None else tuple(
            b for b in ephemeris.BODIES if b != self.center)
        self.bodies = check_items("bodies", self.bodies, "perturber", min_len=0,
                                  each=lambda label, b: check_choice(label, b, known))
        if self.gm is None:
            gm = [GM_BODIES[b] for b in self.bodies]
        else:
            gm = check_finite_array("gm", self.gm).reshape(-1)
            if gm.shape != (len(self.bodies),) or np.any(gm < 0):
                raise ValueError(f"gm must hold {len(self.bodies)} values >= 0, m^3/s^2, one a body")
        n = max(2, int(math.ceil((self.t_end - self.t_start) / self.step)) + 2)
        self.knots = self.t_start + self.step * np.arange(n)
        rc, vc = ephemeris.state(self.center, self.knots, self.ephem)
        pos, vel = [], []
        for b in self.bodies:
            rb, vb = ephemeris.state(b, self.knots, self.ephem)
            pos.append(rb - rc)
            vel.append(vb - vc)
        #: shape (n_knots, n_bodies, 3)
        self.pos = np.stack(pos, axis=1) if pos else np.zeros((n, 0, 3))
        self.vel = np.stack(vel, axis=1) if vel else np.zeros((n, 0, 3))
        self.gm = np.array(gm, dtype=float)

    def positions(self, t):
        """Positions of the third bodies relative to the centre at scalar ``t``, shape (k, 3), m."""
        if isinstance(t, bool) or not isinstance(t, float | int | np.floating | np.integer) \
                or not (self.t_start <= t <= self.knots[-1]):
            raise ValueError(
                f"t must lie in [{self.t_start:.9g}, {self.knots[-1]:.9g}] s, the table's span; got {t!r}"
            )
        x = (t - self.t_start) / self.step
        i = min(int(x), len(self.knots) - 2)
        s = x - i
        h = self.step
        # cubic Hermite basis
        s2, s3 = s * s, s * s * s
        h00, h10 = 2 * s3 - 3 * s2 + 1, s3 - 2 * s2 + s
        h01, h11 = -2 * s3 + 3 * s2, s3 - s2
        return (h00 * self.pos[i] + h10 * h * self.vel[i]
                + h01 * self.pos[i + 1] + h11 * h * self.vel[i + 1])


def _position(name, r, one=False):
    """A finite position (..., 3), or (3,) with ``one``, m, between R_MIN and R_MAX from the
    centre (the field is singular at the centre, and its powers of |r| overflow float64 near
    it and far out)."""
    r = check_vector(name, r, 3) if one else check_finite_array(name, r, shape=(3,))
    with np.errstate(over="ignore"):  # a norm beyond float64 (inf) is refused below
        rn = np.linalg.norm(r, axis=-1)
    if np.any(rn < R_MIN) or np.any(rn > R_MAX):
        bad = float(np.ravel(rn)[np.argmax(np.ravel((rn < R_MIN) | (rn > R_MAX)))])
        raise ValueError(f"{name} must lie between {R_MIN:g} m and {R_MAX:g} m of the centre "
                         f"(the field is singular at it), got |{name}| = {bad:g} m")
    return r


def _third_bodies(third_bodies):
    """The perturbers as a tuple: a list of names of :data:`GM_BODIES`, none twice (a string
    is not split into letters; a body listed twice would pull twice)."""
    return check_items("third_bodies", third_bodies, "perturber", min_len=0,
                       each=lambda label, b: check_choice(label, b, tuple(GM_BODIES)))


def _pole(pole):
    """A unit vector (3,): a pole of another length would scale the J2 term, not orient it."""
    pole = check_finite_array("pole", pole, shape=(3,))
    if pole.ndim != 1 or not abs(float(np.linalg.norm(pole)) - 1.0) <= 1e-9:
        raise ValueError(f"pole must be a unit vector (shape (3,), norm 1), got norm "
                         f"{float(np.linalg.norm(pole)):.6g}")
    return pole


def point_mass(r, gm=GM_MARS):
    """Central gravity ``-mu r / |r|^3``, m/s^2; ``r`` shape (..., 3).

    Examples
    --------
    >>> a = point_mass(np.array([R_MARS, 0.0, 0.0]))
    >>> round(-a[0], 3)   # surface gravity of Mars, m/s^2
    3.713
    """
    r = _position("r", r)
    gm = check_real("gm", gm, 0.0, MAX_GM)
    rn = np.linalg.norm(r, axis=-1, keepdims=True)
    return -gm * r / rn**3


def third_body(r, s, gm):
    """Third-body perturbation with the indirect term, m/s^2.

    Parameters
    ----------
    r : array_like, shape (3,)
        Spacecraft position relative to the centre, m.
    s : array_like, shape (k, 3)
        Third-body positions relative to the centre, m: none at the centre or at ``r``
        (refused: the pull is singular there).
    gm : array_like, shape (k,)
        Their GM, m^3/s^2.

    Examples
    --------
    >>> third_body(np.zeros(3), np.array([[1e11, 0, 0]]), np.array([GM_SUN])).tolist()
    [0.0, 0.0, 0.0]
    """
    r = check_vector("r", r, 3)  # one position: a (1, 3) one broadcast (review 35k)
    s = _position("s", s).reshape(-1, 3)
    gm = check_finite_array("gm", gm).reshape(-1)
    if gm.size != s.shape[0]:
        raise ValueError(f"gm must hold one GM per body of s ({s.shape[0]}), got {gm.size}")
    d = s - r
    dn3 = np.linalg.norm(d, axis=-1) ** 3
    if not np.all(dn3 > 0.0):  # a body at the spacecraft (or 1e-103 m from it): singular
        k = int(np.argmin(dn3 > 0.0))
        raise ValueError(f"s[{k}] must differ from r: a body at the spacecraft's position pulls "
                         f"without bound (|s - r| = {np.linalg.norm(d[k]):.3g} m)")
    sn3 = np.linalg.norm(s, axis=-1) ** 3
    # a_k = mu_k [ (s - r)/|s - r|^3 - s/|s|^3 ]
    return np.sum(gm[:, None] * (d / dn3[:, None] - s / sn3[:, None]), axis=0)


def j2_acceleration(r, j2=J2_MARS, radius=J2_MARS_RADIUS, gm=GM_MARS, pole=MARS_POLE):
    """Oblateness (J2) acceleration about a pole, m/s^2; ``r`` shape (3,).

    ``a = -3/2 J2 mu R^2 / r^5 [ (1 - 5 z^2/r^2) r + 2 z p ]`` with ``z = r . p`` and ``R``
    the reference radius the J2 was determined with (MGS95J: 3396.0 km,
    :data:`xnavlab.core.constants.J2_MARS_RADIUS`, not the IAU radius ``R_MARS``). ``r`` inside
    the reference sphere (``|r| < radius``, inside the body, where the series diverges) is
    refused.

    Examples
    --------
    >>> a = j2_acceleration(np.array([0.0, 0.0, 4e6]), pole=np.array([0.0, 0.0, 1.0]))
    >>> bool(a[2] > 0)   # over the pole J2 weakens gravity
    True
    """
    r = _position("r", r, one=True)  # (1, 3): numpy's matmul message (review 35k)
    pole = _pole(pole)
    j2 = check_real("j2", j2, -1.0, 1.0)  # |J2| of every planet is below 0.02
    radius = check_real("radius", radius, 1.0, MAX_BODY_RADIUS)  # as R_MIN
    gm = check_real("gm", gm, 0.0, MAX_GM)
    rn2 = float(r @ r)
    if not math.sqrt(rn2) >= radius:  # review 35j: 1e24 m/s^2 at 1 m from the centre
        raise ValueError(f"r must lie outside the body, on or above the J2 reference sphere "
                         f"(|r| >= radius = {radius:g} m; the series diverges inside), got "
                         f"|r| = {math.sqrt(rn2):.6g} m")
    z = float(r @ pole)
    k = -1.5 * j2 * gm * radius**2 / rn2**2.5
    return k * ((1.0 - 5.0 * z * z / rn2) * r + 2.0 * z * pole)


def acceleration(t, r, table=None, j2=False):
    """Total acceleration of the paper's model at ``t``, m/s^2, shape (3,).

    Parameters
    ----------
    t : float
        Epoch, s TDB past J2000.
    r : array_like, shape (3,)
        Mars-centred position, m.
    table : ThirdBodyTable, optional
        Third bodies; ``None`` means Mars point mass only.
    j2 : bool
        Include Mars's J2.

    Examples
    --------
    >>> a = acceleration(MARS_T0, MARS_STATE0[:3])
    >>> bool(2.0 < np.linalg.norm(a) < 2.2)
    True
    """
    t = check_real("t", t)
    r = _position("r", r, one=True)
    if table is not None:
        check_instance("table", table, ThirdBodyTable, "a ThirdBodyTable or None")
    j2 = check_bool("j2", j2)
    a = point_mass(r)
    if table is not None and table.bodies:
        a = a + third_body(r, table.positions(t), table.gm)
    if j2:
        a = a + j2_acceleration(r)
    return a


def _surface(t, x):
    """The impact event of a propagation: |r|^2 - R_MARS^2, zero at Mars's surface."""
    return x[0] * x[0] + x[1] * x[1] + x[2] * x[2] - R_MARS * R_MARS


_surface.terminal = True
_surface.direction = -1
#: The events ``solve_ivp`` watches in every propagation of this package: the orbit reaching
#: Mars's surface (a terminal event, crossing inwards), read by :func:`check_impact`.
IMPACT_EVENTS = (_surface,)


def check_impact(sol, t0, t_end):
    """Refuse, in one line, a propagation that fell into Mars or that the integrator lost.

    Parameters
    ----------
    sol : scipy.integrate OdeResult
        The result of ``solve_ivp(..., events=IMPACT_EVENTS)``.
    t0, t_end : float
        The propagation's start and end, s (TDB seconds, as ``solve_ivp`` was given them).

    Raises
    ------
    ValueError
        Naming ``state0`` and the time of impact after ``t0``, when the orbit reached Mars's
        surface (radius ``R_MARS``, 3,396.19 km) before ``t_end``.

    Examples
    --------
    >>> from scipy.integrate import solve_ivp
    >>> fall = solve_ivp(lambda t, x: [x[3], x[4], x[5], 0.0, 0.0, 0.0], (0.0, 10.0),
    ...                  [R_MARS + 5.0, 0.0, 0.0, -1.0, 0.0, 0.0], events=IMPACT_EVENTS)
    >>> check_impact(fall, 0.0, 10.0)
    Traceback (most recent call last):
    ...
    ValueError: state0: the orbit reaches Mars's surface (|r| = 3.39619e+06 m) at t0 + 5 s, ...
    """
    if sol.status == 1:
        t_hit = float(sol.t_events[0][0])
        raise ValueError(f"state0: the orbit reaches Mars's surface (|r| = {R_MARS:g} m) at t0 + "
                         f"{t_hit - t0:.6g} s, before the end of the propagation (t0 + "
                         f"{t_end - t0:.6g} s): give a state0 whose orbit stays above Mars")
    if not sol.success:  # pragma: no cover
        raise RuntimeError(f"propagation failed: {sol.message}")


#: Speed relative to Mars far from it, m/s, above which no craft bound to the Sun passes Mars:
#: the Sun's escape speed at Mars's perihelion (1.381 au, 35.8 km/s) plus Mars's speed there
#: (26.5 km/s) is 62.3 km/s, rounded up. :func:`check_state0` adds Mars's pull.
V_INF_MAX = 65.0e3

#: Mars's Hill radius at its perihelion, m: ``a (GM_MARS / (3 GM_SUN))^(1/3)`` with
#: a = 1.381 au (Hill 1878; Murray & Dermott 1999, eq. 3.75), 9.8e5 km. Farther out the Sun,
#: not Mars, holds a craft, so a Mars-centred state there is no Mars orbit: :func:`check_state0`
#: refuses it.
R_HILL = 1.381 * AU * (GM_MARS / (3.0 * GM_SUN)) ** (1.0 / 3.0)


def check_state0(state0, name="state0"):
    """A Mars-centred state checked for physics: finite, above Mars, inside its Hill sphere,
    slower than any craft bound to the Sun.

    Parameters
    ----------
    state0 : array_like, shape (6,)
        Position and velocity, Mars-centred J2000, m and m/s.
    name : str
        The parameter's name in messages.

    Returns
    -------
    ndarray, shape (6,)

    Raises
    ------
    ValueError
        For a state not finite, complex or of another shape, a position inside Mars (``|r| <= R_MARS``)
        or outside its Hill sphere (``|r| >= R_HILL``), or a
        speed of ``sqrt(V_INF_MAX**2 + 2 GM_MARS / |r|)`` or more (65.2 km/s at the surface:
        :data:`V_INF_MAX` plus the speed gained falling from far away to ``|r|``), each
        naming ``name``, its range and the value.

    Examples
    --------
    >>> check_state0(MARS_STATE0).shape
    (6,)
    >>> check_state0([4e6, 0.0, 0.0, 9e8, 0.0, 0.0])
    Traceback (most recent call last):
    ...
    ValueError: state0 speed must be below 65164.5 m/s at |r| = 4e+06 m (no craft bound to ...
    """
    x = check_vector(name, state0, 6)  # not check_finite_array: its shape is a trailing one
    r, v = math.hypot(*x[:3]), math.hypot(*x[3:])  # hypot: no overflow for a huge component
    if not r > R_MARS:
        raise ValueError(f"{name} position must lie outside Mars (|r| > {R_MARS:g} m), got "
                         f"|r| = {r:.6g} m")
    if not r < R_HILL:
        raise ValueError(f"{name} position must lie inside Mars's Hill sphere (|r| < {R_HILL:.4g} m; "
                         f"farther out the Sun, not Mars, holds the craft), got |r| = {r:.6g} m")
    v_max = math.sqrt(V_INF_MAX**2 + 2.0 * GM_MARS / r)  # eq: vis-viva, v^2 = v_inf^2 + 2 mu / r
    if not v < v_max:
        raise ValueError(f"{name} speed must be below {v_max:.6g} m/s at |r| = {r:.6g} m (no "
                         f"craft bound to the Sun passes Mars faster), got {v:.6g} m/s")
    return x


def _check_table(table, third_bodies, ephem, t0, t_end):
    """A :func:`propagate` table: a ThirdBodyTable of the run's bodies, ephemeris and span."""
    check_instance("table", table, ThirdBodyTable, "a ThirdBodyTable (or None)")
    if table.center != "mars" or set(table.bodies) != set(third_bodies) or table.ephem != ephem:
        raise ValueError(f"table tabulates {list(table.bodies)} about {table.center} from "
                         f"{table.ephem}, but the run asks third_bodies = {list(third_bodies)} "
                         f"about mars from ephem = {ephem!r}: the table's would be used; pass a "
                         f"table of those (or none)")
    if not table.t_start <= t0 <= t_end <= table.t_end:
        raise ValueError(f"table must cover the run, t0 = {t0:.9g} s to t_eval[-1] = {t_end:.9g} s, "
                         f"got [{table.t_start:.9g}, {table.t_end:.9g}] s")


def propagate(t_eval, state0=MARS_STATE0, t0=MARS_T0, third_bodies=("sun", "jupiter"),
              j2=False, ephem="de421", rtol=1e-13, atol=1e-9, table=None):
    """Truth trajectory: integrate the model with ``solve_ivp`` (DOP853).

    Parameters
    ----------
    t_eval : array_like, shape (n,)
        Output epochs, s TDB past J2000, increasing, all ``>= t0``, ``t_eval[-1] - t0`` at
        most 731 days (about 4 minutes of integration); an epoch dtype resolving them worse
        than 1 ms (float32 resolves 32 s at 5e8 s) is refused, as for ``t0``.
    state0 : array_like, shape (6,)
        State at ``t0``, m and m/s (default: the paper's); refused by :func:`check_state0`
        inside Mars or faster than any craft bound to the Sun.
    t0 : float
        Initial epoch (default :data:`MARS_T0`); with third bodies inside ``ephem``'s coverage.
    third_bodies : sequence of str
        Any of ``"sun"``, ``"jupiter"``.
    j2 : bool
        Include Mars's J2.
    ephem : {"de421", "de405"}
    rtol, atol : float
        Integrator tolerances. With the defaults a 30-day run ends within 0.1 m of a
        run with tighter tolerances (rtol 3e-14; see the tests).
    table : ThirdBodyTable, optional
        Reuse a tabulation: Mars-centred, of the ``third_bodies`` (any order) from ``ephem``,
        covering ``t0`` to ``t_eval[-1]`` (another table is refused: its bodies would replace
        ``third_bodies`` without a word); its GM values are used.

    Returns
    -------
    ndarray, shape (n, 6)

    Examples
    --------
    >>> x = propagate(MARS_T0 + np.array([0.0, 60.0]))
    >>> bool(np.allclose(x[0], MARS_STATE0))
    True
    """
    t_eval = _checks.epochs("t_eval", t_eval)
    state0 = check_state0(state0)
    t0 = _checks.epoch("t0", t0)
    rtol = check_real("rtol", rtol, 2.3e-14, 1e-3)
    atol = check_real("atol", atol, 1e-12, 1e3, lo_open=True)
    third_bodies = _third_bodies(third_bodies)
    j2 = check_bool("j2", j2)
    check_choice("ephem", ephem, ephemeris.EPHEMERIDES)
    _checks.span(t0, float(t_eval[-1]), ephem if table is None and third_bodies else None)
    if np.any(np.diff(t_eval) < 0) or t_eval[0] < t0:
        raise ValueError("t_eval must be a non-empty increasing 1-D array with t_eval[0] >= t0")
    if table is not None:
        _check_table(table, third_bodies, ephem, t0, float(t_eval[-1]))
    elif third_bodies:
        table = ThirdBodyTable(t0, float(t_eval[-1]), tuple(third_bodies), "mars", ephem)

    if table is None:
        tab_args = (t0, 3600.0, np.zeros((2, 0, 3)), np.zeros((2, 0, 3)), np.zeros(0))
    else:
        tab_args = (table.t_start, table.step, table.pos, table.vel, table.gm)
    j2_args = (J2_MARS if j2 else 0.0, J2_MARS_RADIUS, MARS_POLE)

    def rhs(t, x):
        return _rhs(t, x, GM_MARS, *tab_args, *j2_args)

    t_end = float(t_eval[-1])
    if t_end == t0:
        return np.tile(state0, (t_eval.size, 1))
    from scipy.integrate import solve_ivp  # imported here: only a cache miss needs it

    sol = solve_ivp(rhs, (t0, t_end), state0, method="DOP853", dense_output=True,
                    rtol=rtol, atol=atol, events=IMPACT_EVENTS)
    check_impact(sol, t0, t_end)
    return sol.sol(t_eval).T


def truth(t_eval, state0=MARS_STATE0, t0=MARS_T0, third_bodies=("sun", "jupiter"), j2=False,
          ephem="de421", cache=True):
    """:func:`propagate` with the default tolerances, cached on disk.

    The first call for a given set of arguments integrates and stores the result under
    ``$XNAVLAB_CACHE`` (default ``~/.cache/xnavlab``); later calls, from any process,
    load it. The key covers every argument and the code that computes it (this module and all
    it imports, :func:`xnavlab.core.diskcache.entry_path`), so a changed model is never served
    from a stale file.

    Returns
    -------
    ndarray, shape (n, 6)

    Examples
    --------
    >>> truth(MARS_T0 + np.array([0.0, 3.0]), cache=False).shape
    (2, 6)
    """
    t_eval, t0 = _checks.epochs("t_eval", t_eval), _checks.epoch("t0", t0)
    state0 = check_state0(state0)
    bodies = _third_bodies(third_bodies)
    j2, cache = check_bool("j2", j2), check_bool("cache", cache)
    if not cache:
        return propagate(t_eval, state0, t0, bodies, j2, ephem)
    path = entry_path("truth", (float(t0), bodies, bool(j2), ephem), (t_eval, state0),
                      (__name__,), suffix=".npy")
    x = load_array(path, (t_eval.size, 6))
    if x is not None:
        return x
    x = propagate(t_eval, state0, t0, bodies, j2, ephem)
    store(path, lambda f: np.save(f, x))  # a read-only home still gets the result
    return x


@numba.njit(cache=True)
def _rhs(t, x, gm, t_start, step, pos, vel, gms, j2, radius, pole):  # pragma: no cover
    """Compiled right-hand side: the same model as :func:`acceleration` (tests compare them)."""
    out = np.empty(6)
    r0, r1, r2 = x[0], x[1], x[2]
    rn2 = r0 * r0 + r1 * r1 + r2 * r2
    rn = math.sqrt(rn2)
    k = -gm / (rn2 * rn)  # a = -mu r / |r|^3
    a0, a1, a2 = k * r0, k * r1, k * r2
    nb = gms.shape[0]
    if nb > 0:
        u = (t - t_start) / step
        i = min(int(u), pos.shape[0] - 2)
        s = u - i
        s2 = s * s
        s3 = s2 * s
        h00, h10 = 2 * s3 - 3 * s2 + 1, (s3 - 2 * s2 + s) * step
        h01, h11 = -2 * s3 + 3 * s2, (s3 - s2) * step
        for b in range(nb):
            sv = np.empty(3)
            for c in range(3):
                sv[c] = (h00 * pos[i, b, c] + h10 * vel[i, b, c]
                         + h01 * pos[i + 1, b, c] + h11 * vel[i + 1, b, c])
            d0, d1, d2 = sv[0] - r0, sv[1] - r1, sv[2] - r2
            dn = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
            sn = math.sqrt(sv[0] * sv[0] + sv[1] * sv[1] + sv[2] * sv[2])
            kd, ks = gms[b] / dn**3, gms[b] / sn**3
            # a_k = mu_k [ (s - r)/|s - r|^3 - s/|s|^3 ]
            a0 += kd * d0 - ks * sv[0]
            a1 += kd * d1 - ks * sv[1]
            a2 += kd * d2 - ks * sv[2]
    if j2 != 0.0:
        z = r0 * pole[0] + r1 * pole[1] + r2 * pole[2]
        kj = -1.5 * j2 * gm * radius * radius / (rn2 * rn2 * rn)
        f = 1.0 - 5.0 * z * z / rn2
        a0 += kj * (f * r0 + 2.0 * z * pole[0])
        a1 += kj * (f * r1 + 2.0 * z * pole[1])
        a2 += kj * (f * r2 + 2.0 * z * pole[2])
    out[0], out[1], out[2] = x[3], x[4], x[5]
    out[3], out[4], out[5] = a0, a1, a2
    return out


def gravity_gradient(r, gm=GM_MARS):
    """Point-mass gravity gradient ``d a / d r = mu (3 r r^T / |r|^5 - I / |r|^3)``, shape (3, 3).

    Examples
    --------
    >>> G = gravity_gradient(np.array([4e6, 0.0, 0.0]))
    >>> bool(G[0, 0] > 0 and G[1, 1] < 0)
    True
    """
    r = _position("r", r)
    if r.shape != (3,):
        raise ValueError(f"r must have shape (3,), got {r.shape}")
    gm = check_real("gm", gm, 0.0, MAX_GM)
    rn = np.linalg.norm(r)
    return gm * (3.0 * np.outer(r, r) / rn**5 - np.eye(3) / rn**3)


def transition_matrix(r, dt, gm=GM_MARS):
    """State-transition matrix over a step: the series of ``exp(F dt)`` to fourth order.

    ``F = [[0, I], [G, 0]]`` with ``G`` the point-mass gravity gradient at ``r``, held
    constant over the step; the third bodies' gradients (below 1e-13 s^-2 near Mars)
    are neglected. The truncation error is about ``|G|^2 dt^5 / 120``.

    Parameters
    ----------
    r : array_like, shape (3,)
        Position at the start of the step, m.
    dt : float
        Step, s, in [-1e6, 1e6]: beyond 12 days (several orbits) a fourth-order series is no
        transition matrix, and near 1e77 s its ``dt^4`` overflows.

    Returns
    -------
    ndarray, shape (6, 6)

    Examples
    --------
    >>> Phi = transition_matrix(MARS_STATE0[:3], 3.0)
    >>> Phi.shape, round(float(Phi[0, 3]), 4)
    ((6, 6), 3.0)
    """
    G = gravity_gradient(r, gm)
    dt = check_real("dt", dt, -1e6, 1e6)
    G2 = G @ G
    I3 = np.eye(3)
    # Phi = I + F dt + (F dt)^2/2 + (F dt)^3/6 + (F dt)^4/24, with F^2 = diag(G, G):
    diag = I3 + G * dt**2 / 2 + G2 * dt**4 / 24
    return np.block([[diag, I3 * dt + G * dt**3 / 6],
                     [G * dt + G2 * dt**3 / 6, diag]])


class OrbitalElements(NamedTuple):
    """Osculating two-body elements of a state (see :func:`orbital_elements`)."""

    a: float  #: semi-major axis, m
    e: float  #: eccentricity
    inclination: float  #: to the J2000 equator, rad
    inclination_pole: float  #: to the plane normal to ``pole``, rad
    period: float  #: s
    r_periapsis: float  #: m
    r_apoapsis: float  #: m
    energy: float  #: specific orbital energy, J/kg


def orbital_elements(state, gm=GM_MARS, pole=MARS_POLE):
    """Osculating elements of a Cartesian state about a point mass.

    ``a = 1 / (2/r - v^2/mu)`` (vis-viva), ``e = |((v^2 - mu/r) r - (r.v) v) / mu|``,
    ``T = 2 pi sqrt(a^3/mu)``, inclination from the angular momentum ``h = r x v``.

    Parameters
    ----------
    state : array_like, shape (6,)
        Position (m) and velocity (m/s), centre-relative.
    gm : float
        Centre's GM, m^3/s^2 (default Mars), in (0, MAX_GM].
    pole : array_like, shape (3,)
        Unit vector of the centre's spin axis, for ``inclination_pole``.

    Returns
    -------
    OrbitalElements

    Raises
    ------
    ValueError
        For an unbound (parabolic or hyperbolic) state.

    Examples
    --------
    >>> el = orbital_elements(MARS_STATE0)
    >>> round(el.a / 1e3), round(el.e, 3), round(el.period / 3600, 2)
    (4196, 0.09, 2.29)
    """
    state = check_vector("state", state, 6)  # (1, 6): numpy's cross message (review 35k)
    gm = check_real("gm", gm, 0.0, MAX_GM, lo_open=True)
    pole = _pole(pole)
    r, v = state[:3], state[3:]
    if not np.linalg.norm(np.cross(r, v)) > 0.0:  # the centre, or a radial fall: no plane
        raise ValueError("state must have a position off the centre and a velocity not along "
                         "it (an orbit has a plane), got angular momentum 0")
    rn, vn = float(np.linalg.norm(r)), float(np.linalg.norm(v))
    energy = 0.5 * vn**2 - gm / rn
    if energy >= 0.0:
        raise ValueError(f"state must be a bound orbit (energy < 0), got energy {energy:.6g} J/kg")
    a = 1.0 / (2.0 / rn - vn**2 / gm)  # vis-viva
    e = float(np.linalg.norm(((vn**2 - gm / rn) * r - (r @ v) * v) / gm))
    h = np.cross(r, v)
    hhat = h / np.linalg.norm(h)
    return OrbitalElements(
        a=a,
        e=e,
        inclination=float(np.arccos(np.clip(hhat[2], -1.0, 1.0))),
        inclination_pole=float(np.arccos(np.clip(hhat @ np.asarray(pole, float), -1.0, 1.0))),
        period=2.0 * math.pi * math.sqrt(a**3 / gm),
        r_periapsis=a * (1.0 - e),
        r_apoapsis=a * (1.0 + e),
        energy=energy,
    )


def chapter_times():
    """The chapters' epochs: the paper's 30 days from :data:`MARS_T0` every 60 s.

    The grid on which chapters 2 and 3 and chapter 3's slider (:func:`plot_model_difference`)
    ask for :func:`truth`, whose disk cache is keyed by the epochs: ``python -m xnavlab
    warmup`` fills it for every force model of the slider.

    Returns
    -------
    ndarray, shape (43201,)
        Seconds TDB past J2000.

    Examples
    --------
    >>> t = chapter_times()
    >>> t.size, float(t[1] - t[0]), float(t[-1] - t[0]) / 86400.0
    (43201, 60.0, 30.0)
    """
    return MARS_T0 + np.arange(0.0, 30 * 86400.0 + 1.0, 60.0)


def chapter_truths():
    """Fill :func:`truth`'s disk cache for every force model chapter 3's slider offers.

    The eight models of :func:`plot_model_difference` (the Sun, Jupiter and J2 each on or off,
    the paper's model among them) on :func:`chapter_times`; ``python -m xnavlab warmup``
    calls it, so no chapter integrates them on a reader's first run (about 60 s in all).

    Examples
    --------
    >>> chapter_truths()  # doctest: +SKIP
    >>> d = model_difference(chapter_times(), ("sun",))  # doctest: +SKIP
    """
    t = chapter_times()
    for sun, jupiter, j2 in itertools.product((True, False), (True, False), (False, True)):
        truth(t, third_bodies=_bodies(sun, jupiter), j2=j2)


def _bodies(sun, jupiter):
    """The third bodies of a force model with the Sun and Jupiter on or off."""
    return tuple(b for b, on in (("sun", sun), ("jupiter", jupiter)) if on)


def model_difference(t_eval, third_bodies=("sun", "jupiter"), j2=False):
    """Position difference of a force-model variant from the paper's model, split by direction.

    Both orbits start from :data:`MARS_STATE0` at :data:`MARS_T0` (:func:`truth`, cached).
    The difference ``r_variant - r_paper`` is projected on the unit vectors of the paper's
    orbit: radial ``r/|r|``, cross-track ``(r x v)/|r x v|`` and along-track
    ``cross x radial``.

    Parameters
    ----------
    t_eval : array_like, shape (n,)
        Epochs, s past J2000 (TDB).
    third_bodies : sequence of {"sun", "jupiter"}
        Third bodies of the variant.
    j2 : bool
        Whether the variant includes Mars's J2.

    Returns
    -------
    dict
        ``"norm"``, ``"radial"``, ``"along"``, ``"cross"``: arrays of shape (n,), m.

    Examples
    --------
    >>> t = MARS_T0 + np.array([0.0, 600.0])
    >>> d = model_difference(t, third_bodies=("sun", "jupiter"))
    >>> float(d["norm"].max())
    0.0
    """
    ref = truth(t_eval)
    other = truth(t_eval, third_bodies=third_bodies, j2=j2)
    diff = other[:, :3] - ref[:, :3]
    radial = ref[:, :3] / np.linalg.norm(ref[:, :3], axis=1, keepdims=True)
    cross = np.cross(ref[:, :3], ref[:, 3:])
    cross /= np.linalg.norm(cross, axis=1, keepdims=True)
    along = np.cross(cross, radial)
    return {"norm": np.linalg.norm(diff, axis=1), "radial": np.sum(diff * radial, axis=1),
            "along": np.sum(diff * along, axis=1), "cross": np.sum(diff * cross, axis=1)}


def plot_model_difference(sun=True, jupiter=True, j2=False, days_shown=30):
    """Plot :func:`model_difference` over the first ``days_shown`` days of the 30-day orbit.

    The 30-day, 60-s grid of the chapters (cached truths). A pure function of its
    arguments, for chapter 3's slider.

    Parameters
    ----------
    sun, jupiter, j2 : bool
        Perturbations of the variant (the paper's model is Sun and Jupiter, no J2).
    days_shown : int
        Days to show, 1 to 30.

    Returns
    -------
    matplotlib.figure.Figure
        Two axes: the norm of the difference and its radial, along- and cross-track
        components (m); not registered with pyplot. It carries an in-place update
        (:func:`xnavlab.core.plotting.in_place`) that a live slider calls.

    Examples
    --------
    >>> fig = plot_model_difference(sun=False, days_shown=2)
    >>> fig.axes[0].lines[0].get_xdata()[-1]
    2.0
    """
    from matplotlib.figure import Figure

    from xnavlab.core.plotting import in_place

    # the layout every frame shares; update() sets the curves, limits and title
    fig = Figure(figsize=(11, 3.4), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2)
    norm, = ax1.plot([0.0, 1.0], [0.0, 0.0], lw=0.5)
    ax1.set(xlabel="days", ylabel="m", title="|r - r_paper|")
    parts = {key: ax2.plot([0.0, 1.0], [0.0, 0.0], lw=0.4, label=name)[0]
             for key, name in (("radial", "radial"), ("along", "along-track"),
                               ("cross", "cross-track"))}
    ax2.set(xlabel="days", ylabel="m", title="r - r_paper, components")
    ax2.legend(fontsize=8)
    title = fig.suptitle("")

    def update(sun=True, jupiter=True, j2=False, days_shown=30):
        sun, jupiter = check_bool("sun", sun), check_bool("jupiter", jupiter)
        j2 = check_bool("j2", j2)
        days_shown = check_int("days_shown", days_shown, 1, 30)
        bodies = _bodies(sun, jupiter)
        t = chapter_times()  # the chapters' grid (cached truths)
        shown = slice(0, days_shown * 1440 + 1)
        d = {k: v[shown] for k, v in model_difference(t, bodies, j2).items()}
        days = (t[shown] - t[0]) / 86400.0
        norm.set_data(days, d["norm"])
        for key, line in parts.items():
            line.set_data(days, d[key])
        for ax in (ax1, ax2):
            ax.relim()
            ax.autoscale_view()
        label = " + ".join(["Mars"] + [b.capitalize() for b in bodies] + (["J2"] if j2 else []))
        title.set_text(f"{label}: max difference {d['norm'].max():.4g} m")
        return None

    update(sun, jupiter, j2, days_shown)
    return in_place(fig, update)
