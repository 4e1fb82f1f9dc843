"""Force models of the truth and of the filter: Mars's gravity field, the Sun and planets, sunlight.

The main paper (Fan et al. 2016) flies its orbit, truth and filter alike, under a Mars
point mass with the Sun and Jupiter (:mod:`xnavlab.mars.models.dynamics`): a filter tested against
its own model. A :class:`ForceModel` names the terms of one model so that a scenario can give
the truth a richer one than its filter (:class:`xnavlab.mars.navigation.scenarios.MarsScenario`, fields
``truth_model`` and ``filter_model``):

Mars's gravity field
    The JPL field MRO95A (Konopliv et al. 2011, Icarus 211, 401-428; the PDS product
    JGMRO_095A), fully normalised coefficients to degree and order 8 shipped in
    ``xnavlab/data/mars_gravity_mro95a.csv``, reference radius 3396.0 km, summed to
    ``gravity_degree`` (0: the point mass alone; 2: J2, C22, S22 and C21, S21; up to 8) by the
    recursion of Montenbruck and Gill (2000, sec. 3.2.4) in the Mars-fixed frame of the field:
    ``r_IN = Rz(-N) Rx(-J) Rz(-PSI) Rx(-I) Rz(-PHI) r_BF`` with the field's own orientation
    angles (``N``, ``J``, ``PSI``, ``I``, ``PHI`` of the MRO95A label: :data:`MARS_ORIENTATION`;
    nutations and the seasonal spin terms, below 0.5 arcsec, are left out).
The Sun and planets
    Point masses with the indirect term, positions from the ephemeris and GMs from the same
    ephemeris's header (:func:`planet_gm`; the Sun and Jupiter take the package's constants, as
    the paper's model does).
Solar radiation pressure
    A cannonball (Montenbruck and Gill 2000, eq. 3.75):
    ``a = P0 C_R (A / m) (AU / |r - s|)^2 (r - s) / |r - s|`` away from the Sun at ``s``, with
    ``P0 = 1367 W m^-2 / c = 4.56e-6 N m^-2`` and no force in Mars's cylindrical shadow. The
    study's orbiter (:data:`STUDY`): ``A = 10 m^2``, ``m = 1000 kg``, ``C_R = 1.3``. ``A / m =
    0.01 m^2/kg`` is the size of Mars Express (11.4 m^2 of solar arrays, 1120 kg at launch) and
    of Mars Reconnaissance Orbiter (20 m^2 of arrays, 2180 kg at launch); ``C_R = 1.3`` lies in
    the 1-2 range of real spacecraft (Montenbruck and Gill 2000, sec. 3.4.1), an array that
    absorbs most of the light. At Mars (1.4-1.7 au) that is 2-3e-8 m/s^2.

The compiled filter (:mod:`xnavlab.mars.kernel.kernels`) integrates a Mars point mass and third bodies
only, so a filter model has ``gravity_degree = 0`` and no SRP; its third bodies may be any of
:data:`PLANETS` (the kernel takes them as a table).

The process noise a filter needs for what its model leaves out is derived in
:mod:`xnavlab.mars.models.model_noise`.

Examples
--------
>>> STUDY.gravity_degree, PAPER.is_paper, STUDY.is_paper
(8, True, False)
>>> a = acceleration(dynamics.MARS_T0, dynamics.MARS_STATE0[:3], ForceModel(gravity_degree=2))
>>> bool(1e-3 < np.linalg.norm(a - dynamics.point_mass(dynamics.MARS_STATE0[:3])) < 1e-2)
True
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass
from importlib import resources

import numba
import numpy as np

from xnavlab.core import ephemeris
from xnavlab.core.constants import AU, DAY, GM_JUPITER, GM_MARS, GM_SUN, R_MARS, C
from xnavlab.core.diskcache import entry_path, load_array, store
from xnavlab.core.userfiles import csv_rows
from xnavlab.core.validate import (
    check_bool,
    check_choice,
    check_instance,
    check_int,
    check_real,
    check_shape,
    check_vector,
)
from xnavlab.mars.models import _checks, dynamics

__all__ = [
    "GRAVITY_SOURCE",
    "GRAVITY_RADIUS",
    "MAX_DEGREE",
    "MARS_ORIENTATION",
    "PLANETS",
    "SOLAR_PRESSURE_1AU",
    "ForceModel",
    "PAPER",
    "STUDY",
    "MODELS",
    "model",
    "check_models",
    "gravity_coefficients",
    "planet_gm",
    "mars_fixed_matrix",
    "harmonic_acceleration",
    "srp_acceleration",
    "acceleration",
    "Tables",
    "third_body_table",
    "accelerations",
    "propagate",
    "truth",
]

#: The Mars gravity field shipped: its name and reference.
GRAVITY_SOURCE = ("MRO95A (Konopliv et al. 2011, Icarus 211, 401-428; JPL PDS product "
                  "JGMRO_095A)")
#: Reference radius of MRO95A, m.
GRAVITY_RADIUS = 3_396_000.0
#: Highest degree (and order) shipped in ``xnavlab/data/mars_gravity_mro95a.csv``.
MAX_DEGREE = 8
#: Orientation of MRO95A's Mars-fixed frame (its label), degrees and degrees per day past J2000:
#: ``r_IN = Rz(-N) Rx(-J) Rz(-PSI) Rx(-I) Rz(-PHI) r_BF``.
MARS_ORIENTATION = {"N": 3.37919183, "J": 24.67682669, "PSI0": 81.9683745250,
                    "PSI_RATE": -0.000005775, "I": 25.1893973568, "PHI0": 133.38463,
                    "PHI_RATE": 350.891985307}
#: The third bodies a model may take (``"earthmoon"``: the Earth-Moon barycentre).
PLANETS = ("sun", "mercury", "venus", "earthmoon", "jupiter", "saturn")
#: Solar radiation pressure at 1 au, N/m^2: solar flux 1367 W/m^2 over c (Montenbruck and
#: Gill 2000, sec. 3.4.1).
SOLAR_PRESSURE_1AU = 1367.0 / C

# the ephemeris header's GM of each body (au^3/day^2), the Sun and Jupiter excepted
_HEADER = {"mercury": "GM1", "venus": "GM2", "earthmoon": "GMB", "saturn": "GM6"}


_SRP_FIELDS = ("area_m2", "mass_kg", "reflectivity")
_MIN_MASS_KG = 1e-3  # 1 g: a subnormal mass made A/m infinite (review 35k)


@dataclass(frozen=True)
class ForceModel:
    """The terms of one force model about Mars (module notes).

    Parameters
    ----------
    gravity_degree : int
        Degree and order of Mars's field (MRO95A), 0 (point mass) or 2 to
        :data:`MAX_DEGREE`.
    third_bodies : tuple of str
        Point-mass perturbers, any of :data:`PLANETS`, each at most once.
    srp : bool
        Solar radiation pressure (cannonball, Mars's cylindrical shadow).
    area_m2, mass_kg, reflectivity : float
        SRP cross-section, m^2, in (0, 1000]; mass, kg, in [1e-3, 1e5]; radiation-pressure
        coefficient C_R, in [1, 2]. With ``srp`` false they are unused, so each must stay at
        its default (a setting away from it is refused, not dropped).

    Examples
    --------
    >>> ForceModel(gravity_degree=1)
    Traceback (most recent call last):
    ...
    ValueError: gravity_degree must be 0 (point mass) or an integer in [2, 8], got 1
    >>> ForceModel(third_bodies=("sun", "pluto"))
    Traceback (most recent call last):
    ...
    ValueError: third_bodies must be distinct names from ('sun', 'mercury', 'venus', \
'earthmoon', 'jupiter', 'saturn'), got ('sun', 'pluto')
    >>> ForceModel(mass_kg=500.0)
    Traceback (most recent call last):
    ...
    ValueError: mass_kg = 500 is unused: srp is false (no solar radiation pressure); set srp \
true, or leave mass_kg at its default 1000
    """

    gravity_degree: int = 0
    third_bodies: tuple = ("sun", "jupiter")
    srp: bool = False
    area_m2: float = 10.0
    mass_kg: float = 1000.0
    reflectivity: float = 1.3

    def __post_init__(self):
        deg = self.gravity_degree
        if isinstance(deg, bool) or not isinstance(deg, int | np.integer) or not (
                deg == 0 or 2 <= deg <= MAX_DEGREE):
            raise ValueError(f"gravity_degree must be 0 (point mass) or an integer in "
                             f"[2, {MAX_DEGREE}], got {deg!r}")
        object.__setattr__(self, "gravity_degree", int(deg))
        bodies = self.third_bodies
        if isinstance(bodies, str) or not isinstance(bodies, tuple | list):
            raise ValueError(f"third_bodies must be a list of names from {PLANETS}, "
                             f"got {bodies!r}")
        bodies = tuple(bodies)
        if len(set(bodies)) != len(bodies) or any(b not in PLANETS for b in bodies):
            raise ValueError(f"third_bodies must be distinct names from {PLANETS}, got {bodies!r}")
        object.__setattr__(self, "third_bodies", bodies)
        if not isinstance(self.srp, bool | np.bool_):
            raise ValueError(f"srp must be true or false, got {self.srp!r}")
        object.__setattr__(self, "srp", bool(self.srp))
        object.__setattr__(self, "area_m2",
                           check_real("area_m2", self.area_m2, 0.0, 1000.0, lo_open=True))
        object.__setattr__(self, "mass_kg",
                           check_real("mass_kg", self.mass_kg, _MIN_MASS_KG, 1e5))
        object.__setattr__(self, "reflectivity",
                           check_real("reflectivity", self.reflectivity, 1.0, 2.0))
        if not self.srp:  # SRP settings away from their defaults would go unused
            for f in (f for f in dataclasses.fields(self) if f.name in _SRP_FIELDS):
                if getattr(self, f.name) != f.default:
                    raise ValueError(f"{f.name} = {getattr(self, f.name):g} is unused: srp is "
                                     f"false (no solar radiation pressure); set srp true, or "
                                     f"leave {f.name} at its default {f.default:g}")

    @property
    def is_paper(self):
        """Whether this is the main paper's model (point mass, the Sun and Jupiter, no SRP)."""
        return (self.gravity_degree == 0 and not self.srp
                and sorted(self.third_bodies) == ["jupiter", "sun"])

    @property
    def compiled_filter_ok(self):
        """Whether the compiled filter can integrate it (no harmonics, no SRP)."""
        return self.gravity_degree == 0 and not self.srp

    def describe(self):
        """One line naming every term, e.g. ``'Mars point mass + Sun, Jupiter'``.

        Examples
        --------
        >>> STUDY.describe()
        'Mars MRO95A 8x8 + Sun, Venus, Earth-Moon, Jupiter, Saturn + SRP (A 10 m^2, m 1000 kg, C_R 1.3)'
        """
        names = {"earthmoon": "Earth-Moon"}
        grav = ("Mars point mass" if self.gravity_degree == 0
                else f"Mars MRO95A {self.gravity_degree}x{self.gravity_degree}")
        parts = [grav]
        if self.third_bodies:
            parts.append(", ".join(names.get(b, b.capitalize()) for b in self.third_bodies))
        if self.srp:
            parts.append(f"SRP (A {self.area_m2:g} m^2, m {self.mass_kg:g} kg, "
                         f"C_R {self.reflectivity:g})")
        return " + ".join(parts)

    def as_dict(self):
        """The fields as a JSON-ready dict (a list for ``third_bodies``)."""
        return {"gravity_degree": self.gravity_degree, "third_bodies": list(self.third_bodies),
                "srp": self.srp, "area_m2": self.area_m2, "mass_kg": self.mass_kg,
                "reflectivity": self.reflectivity}


#: The main paper's model (Fan et al. 2016, section 4.1): the filter's, and the truth's in
#: the reproductions.
PAPER = ForceModel()
#: The studies' truth: MRO95A 8x8, the Sun, Venus, the Earth-Moon barycentre, Jupiter and
#: Saturn, and SRP on a 10 m^2, 1000 kg orbiter with C_R 1.3.
STUDY = ForceModel(gravity_degree=MAX_DEGREE,
                   third_bodies=("sun", "venus", "earthmoon", "jupiter", "saturn"), srp=True)
#: Named models (:func:`model`).
MODELS = {"paper": PAPER, "study": STUDY}


def check_models(truth_model, filter_model):
    """``(truth, filter)`` as :class:`ForceModel`; the filter's must suit the compiled filter.

    Examples
    --------
    >>> check_models("study", "paper")[0] is STUDY
    True
    >>> try:
    ...     check_models("paper", "study")
    ... except ValueError as exc:
    ...     print(str(exc)[:46])
    filter_model must be a point mass with third b
    """
    out = [model(truth_model, "truth_model"), model(filter_model, "filter_model")]
    if not out[1].compiled_filter_ok:
        raise ValueError(f"filter_model must be a point mass with third bodies (gravity_degree "
                         f"0, srp false: the compiled filter integrates no more), got "
                         f"{out[1].describe()}")
    return tuple(out)


def model(spec, name="spec"):
    """A :class:`ForceModel` from a name of :data:`MODELS`, a dict of its fields, or itself.

    Parameters
    ----------
    spec : ForceModel, str or dict
        The model, a name of :data:`MODELS` or a table of :class:`ForceModel` fields.
    name : str
        The caller's parameter, for the messages (``"truth_model"``): a refusal leads with it.

    Examples
    --------
    >>> model("paper") is PAPER, model({"gravity_degree": 2}).gravity_degree
    (True, 2)
    >>> model("rich")
    Traceback (most recent call last):
    ...
    ValueError: spec must be one of 'paper', 'study' or a table of ForceModel fields, got 'rich'
    """
    if isinstance(spec, ForceModel):
        return spec
    if isinstance(spec, str) and spec in MODELS:
        return MODELS[spec]
    if isinstance(spec, dict):
        known = ("gravity_degree", "third_bodies", "srp", "area_m2", "mass_kg", "reflectivity")
        bad = sorted(set(spec) - set(known))
        if bad:
            raise ValueError(f"{name} has no field {bad[0]!r} (fields: {', '.join(known)})")
        try:
            return ForceModel(**spec)
        except ValueError as exc:  # a field's refusal, under the parameter the user typed
            raise ValueError(f"{name}: {exc}") from None
    raise ValueError(f"{name} must be one of 'paper', 'study' or a table of ForceModel "
                     f"fields, got {spec!r}")


@functools.cache
def gravity_coefficients():
    """MRO95A's unnormalised coefficients to :data:`MAX_DEGREE`: ``(C, S)``, each (9, 9).

    ``C[n, m] = N_nm Cbar[n, m]`` with ``N_nm = sqrt((2 - delta_m0)(2n + 1)(n - m)!/(n + m)!)``
    (Montenbruck and Gill 2000, eq. 3.13); degrees 0 and 1 are zero (the point mass is
    summed apart).

    Examples
    --------
    >>> Cu, Su = gravity_coefficients()
    >>> round(-Cu[2, 0] * 1e3, 5)   # J2 of MRO95A, unnormalised
    1.95661
    """
    text = resources.files("xnavlab").joinpath("data/mars_gravity_mro95a.csv").read_text("utf-8")
    where = "data/mars_gravity_mro95a.csv"
    rows = csv_rows(text, where, ("n", "m", "C", "S"))
    Cu = np.zeros((MAX_DEGREE + 1, MAX_DEGREE + 1))
    Su = np.zeros_like(Cu)
    seen = set()
    for row in rows:
        n, m, c, s = int(row["n"]), int(row["m"]), row["C"], row["S"]
        if not (0 <= m <= n <= MAX_DEGREE) or (n, m) in seen:
            raise ValueError(f"{where}: degree {n}, order {m} is out of range or listed twice")
        seen.add((n, m))
        norm = math.sqrt((2 - (m == 0)) * (2 * n + 1) * math.factorial(n - m)
                         / math.factorial(n + m))  # M&G eq. (3.13)
        Cu[n, m], Su[n, m] = norm * float(c), norm * float(s)
    if len(seen) != (MAX_DEGREE + 1) * (MAX_DEGREE + 2) // 2 - 3:  # every (n, m), n >= 2
        raise ValueError(f"{where}: {len(seen)} coefficients, not every degree 2 to "
                         f"{MAX_DEGREE} and order")
    Cu.setflags(write=False)
    Su.setflags(write=False)
    return Cu, Su


@functools.cache
def planet_gm(body, ephem="de421"):
    """GM of a third body, m^3/s^2: the Sun's and Jupiter's constants, else the ephemeris header's.

    Examples
    --------
    >>> round(planet_gm("saturn") / 1e16, 4)
    3.7941
    """
    check_choice("body", body, PLANETS)
    check_choice("ephem", ephem, ephemeris.EPHEMERIDES)
    if body == "sun":
        return GM_SUN
    if body == "jupiter":
        return GM_JUPITER
    import importlib

    from jplephem.ephem import Ephemeris

    eph = Ephemeris(importlib.import_module(ephem))
    au = eph.AU * 1e3  # the header's au, km -> m
    return float(getattr(eph, _HEADER[body])) * au**3 / DAY**2  # au^3/day^2 -> m^3/s^2


def _rx(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, s], [0.0, -s, c]])


def _rz(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])


def _orientation_args():
    o = {k: math.radians(v) for k, v in MARS_ORIENTATION.items()}
    fixed = _rx(o["J"]) @ _rz(o["N"])   # the constant part, EME2000 -> Mars mean orbit
    return fixed, _rx(o["I"]), o["PSI0"], o["PSI_RATE"], o["PHI0"], o["PHI_RATE"]


def mars_fixed_matrix(t):
    """Rotation from J2000 axes to MRO95A's Mars-fixed axes at ``t`` (s TDB past J2000), (3, 3).

    ``r_BF = Rz(PHI) Rx(I) Rz(PSI) Rx(J) Rz(N) r_IN`` with ``Rz(a) = [[c, s, 0], [-s, c, 0],
    [0, 0, 1]]`` (the inverse of the label's ``r_IN = Rz(-N) ... Rz(-PHI) r_BF``).

    Examples
    --------
    >>> M = mars_fixed_matrix(0.0)
    >>> pole = M.T @ [0.0, 0.0, 1.0]          # Mars's north pole in J2000 axes
    >>> bool(np.degrees(np.arccos(pole @ dynamics.MARS_POLE)) < 0.01)   # IAU: within 0.01 deg
    True
    """
    t = _checks.epoch("t", t)
    fixed, rxi, psi0, psi1, phi0, phi1 = _orientation_args()
    d = t / DAY
    return _rz(phi0 + phi1 * d) @ rxi @ _rz(psi0 + psi1 * d) @ fixed


@numba.njit(cache=True)
def _harmonics(rb, nmax, Cu, Su, gm, radius):  # pragma: no cover - compiled
    """Acceleration of degrees 2..nmax in the body-fixed frame (M&G eqs. 3.29-3.33)."""
    x, y, z = rb[0], rb[1], rb[2]
    r2 = x * x + y * y + z * z
    rho = radius * radius / r2
    x0, y0, z0 = radius * x / r2, radius * y / r2, radius * z / r2
    N = nmax + 2
    V = np.zeros((N + 1, N + 1))
    W = np.zeros((N + 1, N + 1))
    V[0, 0] = radius / math.sqrt(r2)
    V[1, 0] = z0 * V[0, 0]
    for n in range(2, N + 1):  # zonal terms, M&G eq. (3.30)
        V[n, 0] = ((2 * n - 1) * z0 * V[n - 1, 0] - (n - 1) * rho * V[n - 2, 0]) / n
    for m in range(1, N + 1):  # tesseral and sectorial terms, M&G eqs. (3.29), (3.30)
        V[m, m] = (2 * m - 1) * (x0 * V[m - 1, m - 1] - y0 * W[m - 1, m - 1])
        W[m, m] = (2 * m - 1) * (x0 * W[m - 1, m - 1] + y0 * V[m - 1, m - 1])
        if m + 1 <= N:
            V[m + 1, m] = (2 * m + 1) * z0 * V[m, m]
            W[m + 1, m] = (2 * m + 1) * z0 * W[m, m]
        for n in range(m + 2, N + 1):
            V[n, m] = ((2 * n - 1) * z0 * V[n - 1, m] - (n + m - 1) * rho * V[n - 2, m]) / (n - m)
            W[n, m] = ((2 * n - 1) * z0 * W[n - 1, m] - (n + m - 1) * rho * W[n - 2, m]) / (n - m)
    ax = ay = az = 0.0
    for n in range(2, nmax + 1):  # M&G eq. (3.33)
        for m in range(0, n + 1):
            c, s = Cu[n, m], Su[n, m]
            if m == 0:
                ax -= c * V[n + 1, 1]
                ay -= c * W[n + 1, 1]
            else:
                f = (n - m + 2) * (n - m + 1)  # (n-m+2)! / (n-m)!
                ax += 0.5 * ((-c * V[n + 1, m + 1] - s * W[n + 1, m + 1])
                             + f * (c * V[n + 1, m - 1] + s * W[n + 1, m - 1]))
                ay += 0.5 * ((-c * W[n + 1, m + 1] + s * V[n + 1, m + 1])
                             + f * (-c * W[n + 1, m - 1] + s * V[n + 1, m - 1]))
            az += (n - m + 1) * (-c * V[n + 1, m] - s * W[n + 1, m])
    k = gm / (radius * radius)
    out = np.empty(3)
    out[0], out[1], out[2] = k * ax, k * ay, k * az
    return out


_R_SUN = 6.957e8  # m, the nominal solar radius (IAU 2015 Resolution B3)


def _outside_mars(name, r):
    """Positions (3,) or (n, 3), m, each outside Mars, where the gravity models hold (the
    harmonic series diverges inside its reference sphere; at the centre the field is singular)."""
    rn = np.linalg.norm(r, axis=-1).reshape(-1)
    if not np.all(rn > R_MARS):
        i = int(np.argmin(rn > R_MARS))
        label = name if r.ndim == 1 else f"{name}[{i}]"
        raise ValueError(f"{label} must lie outside Mars (|r| > {R_MARS:g} m), where the gravity "
                         f"models hold, got |r| = {rn[i]:.6g} m")
    return r


def harmonic_acceleration(t, r, degree=MAX_DEGREE):
    """Acceleration of MRO95A's degrees 2 to ``degree`` at ``r`` (J2000, Mars-centred), m/s^2.

    The point mass is not included (:func:`xnavlab.mars.models.dynamics.point_mass`).

    Parameters
    ----------
    t : float
        Epoch, s TDB past J2000 (Mars's rotation).
    r : array_like, shape (3,)
        Position, m, J2000 axes; outside Mars (``|r| > R_MARS``), else refused.
    degree : int
        2 to :data:`MAX_DEGREE`.

    Returns
    -------
    ndarray, shape (3,)

    Examples
    --------
    >>> r = dynamics.MARS_STATE0[:3]
    >>> a, j2 = harmonic_acceleration(dynamics.MARS_T0, r, 2), dynamics.j2_acceleration(r)
    >>> round(float(np.linalg.norm(a - j2) / np.linalg.norm(j2)), 2)   # C22, S22: 9 % beside J2
    0.09
    """
    degree = check_int("degree", degree, 2, MAX_DEGREE)
    r = _outside_mars("r", check_vector("r", r, 3))
    M = mars_fixed_matrix(t)
    Cu, Su = gravity_coefficients()
    return M.T @ _harmonics(M @ r, degree, Cu, Su, GM_MARS, GRAVITY_RADIUS)


def srp_acceleration(r, s, area_m2=10.0, mass_kg=1000.0, reflectivity=1.3):
    """Cannonball solar radiation pressure with Mars's cylindrical shadow, m/s^2, shape (3,).

    ``a = P0 C_R (A/m) (AU/|d|)^2 d/|d|`` with ``d = r - s`` (Montenbruck and Gill 2000,
    eq. 3.75); zero when ``r . s < 0`` and ``|r - (r . u) u| < R_MARS`` (``u = s / |s|``).

    Parameters
    ----------
    r : array_like, shape (3,)
        Spacecraft, Mars-centred, m; outside the Sun (``|r - s|`` above its radius, 695,700
        km), else refused.
    s : array_like, shape (3,)
        Sun, Mars-centred, m; ``|s|`` above the Sun's radius (the Sun does not hold Mars).
    area_m2, mass_kg, reflectivity : float
        Cross-section in (0, 1000] m^2, mass in [1e-3, 1e5] kg and C_R in [1, 2], as
        :class:`ForceModel` (an area of 0 or a mass below 1 g, whose ``A/m`` overflows, is
        refused, not a zero or an infinity).

    Examples
    --------
    >>> s = np.array([1.5 * AU, 0.0, 0.0])
    >>> a = srp_acceleration(np.array([4e6, 0.0, 0.0]), s)
    >>> round(-a[0] * 1e8, 3)     # 2.6e-8 m/s^2 towards -x, away from the Sun
    2.635
    >>> srp_acceleration(np.array([-4e6, 0.0, 0.0]), s).tolist()   # in Mars's shadow
    [0.0, 0.0, 0.0]
    """
    r, s = check_vector("r", r, 3), check_vector("s", s, 3)
    for label, d in (("|s|", s), ("|r - s|", r - s)):  # _srp divides by both
        if not float(np.linalg.norm(d)) > _R_SUN:
            raise ValueError(f"{label} must exceed the Sun's radius ({_R_SUN:g} m): r is the "
                             f"spacecraft and s the Sun, both Mars-centred; got "
                             f"{float(np.linalg.norm(d)):.6g} m")
    area = check_real("area_m2", area_m2, 0.0, 1000.0, lo_open=True)
    mass = check_real("mass_kg", mass_kg, _MIN_MASS_KG, 1e5)  # 5e-324: -inf (review 35k)
    cr = check_real("reflectivity", reflectivity, 1.0, 2.0)
    return _srp(r, s, SOLAR_PRESSURE_1AU * cr * area / mass, R_MARS)


@numba.njit(cache=True)
def _srp(r, s, k, r_shadow):  # pragma: no cover - compiled
    out = np.zeros(3)
    sn = math.sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2])
    proj = (r[0] * s[0] + r[1] * s[1] + r[2] * s[2]) / sn
    if proj < 0.0:
        perp2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2] - proj * proj
        if perp2 < r_shadow * r_shadow:
            return out  # in Mars's cylindrical shadow
    d0, d1, d2 = r[0] - s[0], r[1] - s[1], r[2] - s[2]
    dn = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    f = k * (AU / dn) ** 2 / dn  # a = P0 C_R (A/m) (AU/|d|)^2 d/|d|
    out[0], out[1], out[2] = f * d0, f * d1, f * d2
    return out


class Tables:
    """Everything a model's compiled right-hand side needs over a span, built once.

    Parameters
    ----------
    force_model : ForceModel
    t_start, t_end : float
        Span, s TDB past J2000.
    ephem : {"de421", "de405"}

    Attributes
    ----------
    table : ThirdBodyTable or None
        The third bodies (:class:`xnavlab.mars.models.dynamics.ThirdBodyTable`) with the model's GMs;
        when the model has SRP the Sun is in it (with GM 0 if the model has no Sun).
    args : tuple
        The arguments of the compiled right-hand side after ``(t, x)``.
    """

    def __init__(self, force_model, t_start, t_end, ephem="de421"):
        t_start = _checks.epoch("t_start", t_start)  # float32 refused (it resolves 32 s)
        t_end = _checks.epoch("t_end", t_end, t_start)
        fm = model(force_model, "force_model")
        bodies = list(fm.third_bodies)
        if fm.srp and "sun" not in bodies:
            bodies.append("sun")
        gm = np.array([planet_gm(b, ephem) if b in fm.third_bodies else 0.0 for b in bodies])
        if bodies:
            self.table = _table(float(t_start), float(t_end), tuple(bodies), ephem)
            pos, vel, step, t0 = self.table.pos, self.table.vel, self.table.step, self.table.t_start
        else:
            self.table = None
            pos = vel = np.zeros((2, 0, 3))
            step, t0 = 3600.0, float(t_start)
        sun = bodies.index("sun") if fm.srp else -1
        k_srp = SOLAR_PRESSURE_1AU * fm.reflectivity * fm.area_m2 / fm.mass_kg if fm.srp else 0.0
        Cu, Su = gravity_coefficients()
        fixed, rxi, psi0, psi1, phi0, phi1 = _orientation_args()
        self.model, self.ephem, self.t_start, self.t_end = fm, ephem, t_start, t_end
        self.args = (GM_MARS, t0, step, pos, vel, gm, fm.gravity_degree, Cu, Su, GRAVITY_RADIUS,
                     fixed, rxi, np.array([psi0, psi1 / DAY, phi0, phi1 / DAY]), sun, k_srp,
                     R_MARS)


def _table(t_start, t_end, bodies, ephem):
    """A ThirdBodyTable of any :data:`PLANETS`, with their GMs (:func:`planet_gm`)."""
    return dynamics.ThirdBodyTable(t_start, t_end, bodies, "mars", ephem,
                                   gm=tuple(planet_gm(b, ephem) for b in bodies))


def third_body_table(force_model, t_start, t_end, ephem="de421"):
    """The filter's third bodies over a span: a :class:`~xnavlab.mars.models.dynamics.ThirdBodyTable`.

    The Sun and Jupiter alone give the table the paper's filter always had (their GMs from
    :data:`xnavlab.mars.models.dynamics.GM_BODIES`); other planets take :func:`planet_gm`. Harmonics
    and SRP are not in a table (the compiled filter has neither).

    Examples
    --------
    >>> tab = third_body_table("paper", dynamics.MARS_T0, dynamics.MARS_T0 + 3600.0)
    >>> tab.bodies
    ('sun', 'jupiter')
    """
    fm = model(force_model, "force_model")
    if set(fm.third_bodies) <= set(dynamics.GM_BODIES):
        return dynamics.ThirdBodyTable(t_start, t_end, fm.third_bodies, "mars", ephem)
    return _table(t_start, t_end, fm.third_bodies, ephem)


@numba.njit(cache=True)
def _rz3(a):  # pragma: no cover - compiled
    c, s = math.cos(a), math.sin(a)
    out = np.zeros((3, 3))
    out[0, 0], out[0, 1], out[1, 0], out[1, 1], out[2, 2] = c, s, -s, c, 1.0
    return out


@numba.njit(cache=True)
def _mul3(a, b):  # pragma: no cover - compiled
    out = np.zeros((3, 3))
    for i in range(3):
        for j in range(3):
            out[i, j] = a[i, 0] * b[0, j] + a[i, 1] * b[1, j] + a[i, 2] * b[2, j]
    return out


@numba.njit(cache=True)
def _accel(t, r, gm, t_start, step, pos, vel, gms, nmax, Cu, Su, radius, fixed, rxi, angles,
           sun, k_srp, r_shadow):  # pragma: no cover - compiled
    """The model's acceleration at (t, r): point mass, third bodies, harmonics, SRP."""
    r0, r1, r2 = r[0], r[1], r[2]
    rn2 = r0 * r0 + r1 * r1 + r2 * r2
    rn = math.sqrt(rn2)
    k = -gm / (rn2 * rn)  # a = -mu r / |r|^3
    a = np.empty(3)
    a[0], a[1], a[2] = k * r0, k * r1, k * r2
    nb = gms.shape[0]
    sun_pos = np.zeros(3)
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
            if b == sun:
                sun_pos[:] = sv
            if gms[b] == 0.0:
                continue
            d0, d1, d2 = sv[0] - r0, sv[1] - r1, sv[2] - r2
            dn = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
            sn = math.sqrt(sv[0] * sv[0] + sv[1] * sv[1] + sv[2] * sv[2])
            kd, ks = gms[b] / dn**3, gms[b] / sn**3
            # a_k = mu_k [ (s - r)/|s - r|^3 - s/|s|^3 ]
            a[0] += kd * d0 - ks * sv[0]
            a[1] += kd * d1 - ks * sv[1]
            a[2] += kd * d2 - ks * sv[2]
    if nmax >= 2:
        psi = angles[0] + angles[1] * t  # the field's orientation angles at t
        phi = angles[2] + angles[3] * t
        M = _mul3(_rz3(phi), _mul3(rxi, _mul3(_rz3(psi), fixed)))
        rb = np.empty(3)  # r_BF = Rz(PHI) Rx(I) Rz(PSI) Rx(J) Rz(N) r_IN
        for i in range(3):
            rb[i] = M[i, 0] * r0 + M[i, 1] * r1 + M[i, 2] * r2
        ab = _harmonics(rb, nmax, Cu, Su, gm, radius)
        for i in range(3):  # back to J2000 axes: a_IN = M^T a_BF
            a[i] += M[0, i] * ab[0] + M[1, i] * ab[1] + M[2, i] * ab[2]
    if sun >= 0:
        a += _srp(r, sun_pos, k_srp, r_shadow)
    return a


@numba.njit(cache=True)
def _rhs(t, x, gm, t_start, step, pos, vel, gms, nmax, Cu, Su, radius, fixed, rxi, angles,
         sun, k_srp, r_shadow):  # pragma: no cover - compiled
    out = np.empty(6)
    out[:3] = x[3:]
    out[3:] = _accel(t, x[:3], gm, t_start, step, pos, vel, gms, nmax, Cu, Su, radius, fixed,
                     rxi, angles, sun, k_srp, r_shadow)
    return out


@numba.njit(cache=True)
def _accel_many(t, r, gm, t_start, step, pos, vel, gms, nmax, Cu, Su, radius, fixed, rxi, angles,
                sun, k_srp, r_shadow):  # pragma: no cover - compiled
    out = np.empty((t.shape[0], 3))
    for j in range(t.shape[0]):
        out[j] = _accel(t[j], r[j], gm, t_start, step, pos, vel, gms, nmax, Cu, Su, radius,
                        fixed, rxi, angles, sun, k_srp, r_shadow)
    return out


def acceleration(t, r, force_model=PAPER, ephem="de421"):
    """Total acceleration of a model at one epoch, m/s^2, shape (3,).

    Parameters
    ----------
    t : float
        Epoch, s TDB past J2000 (float64: a float32 one is refused), inside ``ephem``'s
        coverage when the model has third bodies or SRP.
    r : array_like, shape (3,)
        Mars-centred position, J2000 axes, m; outside Mars (``|r| > R_MARS``), else refused.
    force_model : ForceModel or str
        The model (:func:`model`).
    ephem : {"de421", "de405"}

    Examples
    --------
    >>> t, r = dynamics.MARS_T0, dynamics.MARS_STATE0[:3]
    >>> tab = dynamics.ThirdBodyTable(t, t + 3600.0)
    >>> bool(np.allclose(acceleration(t, r), dynamics.acceleration(t, r, tab), rtol=1e-12))
    True
    """
    t = _checks.epoch("t", t)  # float32 refused (it resolves 32 s), as accelerations' t
    r = _outside_mars("r", check_vector("r", r, 3))
    fm = model(force_model, "force_model")
    if fm.third_bodies or fm.srp:  # the table's t_start was named (review 35l (3) 4)
        _checks.covered("t", t, ephem)
    return accelerations(np.array([t]), r.reshape(1, 3), force_model, ephem)[0]


def accelerations(t, r, force_model=PAPER, ephem="de421", tables=None):
    """A model's acceleration at many epochs and positions, m/s^2, shape (n, 3).

    Parameters
    ----------
    t : array_like, shape (n,)
        Epochs, s TDB past J2000, each inside ``ephem``'s coverage when the model has third
        bodies or SRP.
    r : array_like, shape (n, 3)
        Mars-centred positions, m, each outside Mars (``|r| > R_MARS``), else refused.
    force_model : ForceModel or str
    ephem : {"de421", "de405"}
    tables : Tables, optional
        Reuse a tabulation of ``force_model`` and ``ephem`` covering ``t`` (another is refused).

    Examples
    --------
    >>> t = dynamics.MARS_T0 + np.array([0.0, 60.0])
    >>> accelerations(t, np.tile(dynamics.MARS_STATE0[:3], (2, 1)), "study").shape
    (2, 3)
    """
    t = _checks.epochs("t", t)
    r = check_shape("r", r, (t.size, 3), "n = length of t")
    _outside_mars("r", r)
    fm = model(force_model, "force_model")
    if tables is None:
        if fm.third_bodies or fm.srp:  # t, not the table's t_start or t_end (review 35l (3) 4)
            _checks.covered("t", t, ephem)
        tables = Tables(fm, float(t.min()), float(t.max()), ephem)
    else:  # review 35k: AttributeError 'args'; a table of another model was used silently
        check_instance("tables", tables, Tables, "a Tables of force_model over t (or None)")
        if tables.model != fm or tables.ephem != ephem or not (
                tables.t_start <= t.min() and t.max() <= tables.t_end):
            raise ValueError(f"tables must tabulate force_model ({fm.describe()}) from {ephem} "
                             f"over t, got {tables.model.describe()} from {tables.ephem} over "
                             f"[{tables.t_start:.9g}, {tables.t_end:.9g}] s")
    return _accel_many(t, np.ascontiguousarray(r), *tables.args)


def propagate(t_eval, state0=dynamics.MARS_STATE0, t0=dynamics.MARS_T0, force_model=STUDY,
              ephem="de421", rtol=1e-13, atol=1e-9):
    """Integrate a model with ``solve_ivp`` (DOP853), as :func:`xnavlab.mars.models.dynamics.propagate`.

    Parameters
    ----------
    t_eval : array_like, shape (n,)
        Output epochs, s TDB past J2000, increasing, all ``>= t0``, up to 731 days past it
        (float64: as :func:`xnavlab.mars.models.dynamics.propagate`).
    state0 : array_like, shape (6,)
        State at ``t0``, m and m/s.
    t0 : float
        Inside ``ephem``'s coverage.
    force_model : ForceModel or str
    ephem : {"de421", "de405"}
    rtol, atol : float
        Integrator tolerances (the defaults of :func:`xnavlab.mars.models.dynamics.propagate`).

    Returns
    -------
    ndarray, shape (n, 6)

    Examples
    --------
    >>> x = propagate(dynamics.MARS_T0 + np.array([0.0, 60.0]), force_model="paper")
    >>> bool(np.allclose(x, dynamics.propagate(dynamics.MARS_T0 + np.array([0.0, 60.0])),
    ...                  rtol=0, atol=1e-6))
    True
    """
    fm = model(force_model, "force_model")
    t_eval = _checks.epochs("t_eval", t_eval)
    state0 = dynamics.check_state0(state0)  # above Mars, slower than a craft bound to the Sun
    t0 = _checks.epoch("t0", t0)
    rtol = check_real("rtol", rtol, 2.3e-14, 1e-3)
    atol = check_real("atol", atol, 1e-12, 1e3, lo_open=True)
    t_end = float(t_eval[-1])
    _checks.span(t0, t_end, ephem)  # as dynamics.propagate (review 35k)
    if np.any(np.diff(t_eval) < 0) or t_eval[0] < t0:
        raise ValueError("t_eval must be a non-empty increasing 1-D array with t_eval[0] >= t0")
    if t_end == t0:
        return np.tile(state0, (t_eval.size, 1))
    args = Tables(fm, t0, t_end, ephem).args

    def rhs(t, x):
        return _rhs(t, x, *args)

    from scipy.integrate import solve_ivp  # imported here: only a cache miss needs it

    sol = solve_ivp(rhs, (t0, t_end), state0, method="DOP853", dense_output=True,
                    rtol=rtol, atol=atol, events=dynamics.IMPACT_EVENTS)
    dynamics.check_impact(sol, t0, t_end)
    return sol.sol(t_eval).T


def truth(t_eval, state0=dynamics.MARS_STATE0, t0=dynamics.MARS_T0, force_model=PAPER,
          ephem="de421", cache=True):
    """The truth trajectory of a model, cached on disk like :func:`xnavlab.mars.models.dynamics.truth`.

    The paper's model (and any model of the Sun and Jupiter alone, with or without J2 as
    the degree-2 zonal term is not what :func:`~xnavlab.mars.models.dynamics.truth` has) goes to
    :func:`xnavlab.mars.models.dynamics.truth`, so the paper's runs keep their numbers bit for bit;
    any other model is integrated by :func:`propagate` and stored under a key of every field,
    the ephemeris's GMs and the code that computes it (this module, its coefficients and all
    it imports: :func:`xnavlab.core.diskcache.entry_path`).

    Returns
    -------
    ndarray, shape (n, 6)

    Examples
    --------
    >>> t = dynamics.MARS_T0 + np.array([0.0, 3.0])
    >>> bool(np.array_equal(truth(t, cache=False), dynamics.truth(t, cache=False)))
    True
    """
    cache = check_bool("cache", cache)
    fm = model(force_model, "force_model")
    t_eval, t0 = _checks.epochs("t_eval", t_eval), _checks.epoch("t0", t0)
    state0 = dynamics.check_state0(state0)
    check_choice("ephem", ephem, ephemeris.EPHEMERIDES)
    if fm.gravity_degree == 0 and not fm.srp and set(fm.third_bodies) <= {"sun", "jupiter"}:
        bodies = tuple(b for b in ("sun", "jupiter") if b in fm.third_bodies)
        return dynamics.truth(t_eval, state0, t0, bodies, False, ephem, cache=cache)
    if not cache:
        return propagate(t_eval, state0, t0, fm, ephem)
    gms = tuple(planet_gm(b, ephem) for b in fm.third_bodies)
    path = entry_path("truth-model", (float(t0), tuple(sorted(fm.as_dict().items())), ephem, gms),
                      (t_eval, state0), (__name__,), suffix=".npy")
    x = load_array(path, (t_eval.size, 6))
    if x is not None:
        return x
    x = propagate(t_eval, state0, t0, fm, ephem)
    store(path, lambda f: np.save(f, x))
    return x
