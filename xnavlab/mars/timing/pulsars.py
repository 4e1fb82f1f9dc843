"""X-ray pulsars as clocks: catalogue, timing model, photons, folding and TOA accuracy.

The catalogue holds the four pulsars of the main paper (Fan et al. 2016) with the
X-ray parameters of Sheikh et al. (2006, Table 1): period, pulse width (FWHM),
photon flux (2-10 keV) and pulsed fraction. Positions (J2000) and spin-down rates are
rounded ATNF Pulsar Catalogue values (Manchester et al. 2005); distances are the
rounded ATNF/Sheikh values. Each value's source is in :attr:`Pulsar.sources`.

Units: flux in photons per m^2 per s (the literature's ph/cm^2/s times 1e4);
times in s; distances in m; angles in rad (``ra_deg``/``dec_deg`` say degrees).

Examples
--------
>>> crab = get("B0531+21")
>>> round(ranging_accuracy(crab), 0)   # m, 500 s, 1 m^2, background 0.005 ph/cm^2/s
109.0
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from xnavlab.core import validate
from xnavlab.core.constants import KPC, C
from xnavlab.core.validate import check_bool, check_finite_array, check_int, check_items, check_real, make_rng
from xnavlab.mars.timing import _checks, xray_pulsars
from xnavlab.mars.timing._checks import check_exposure, check_pulsar_fields, check_span, check_spin_drift

__all__ = [
    "Pulsar", "MAX_DISTANCE", "MAX_SPAN", "CATALOGUE", "PAPER_PULSARS", "PAPER_RANGING_M", "get",
    "from_par", "names", "check_names", "directions", "phase", "profile", "binned_template",
    "photon_rates", "simulate_photons", "phase_exposure", "fold", "simulate_folded",
    "estimate_phase_shift", "toa_sigma", "ranging_accuracy", "monte_carlo_toa", "xcorr_toa_sigma",
]

#: The farthest pulsar distance, m: 1 Mpc, the Local Group (the Galaxy is 30 kpc across, the
#: Magellanic Clouds' pulsars 50-60 kpc away); the delays' 1 / D terms overflow near 1e308 m.
MAX_DISTANCE = 1e3 * KPC
#: The longest time from a timing model's epoch, s (about 32,000 years, far beyond any
#: model's validity); the powers of eq. (2) overflow near 1e308 s.
MAX_SPAN = 1e12
_PC = KPC / 1e3
# Each property's range (flux in ph/m^2/s), where its formulas stay finite: no neutron star is
# within 1 pc (the nearest are ~100 pc away); none spins above 10 kHz (it would break up), and
# 1e4 s is about the slowest (accreting) X-ray pulsars' period; a flux below 1e-12 ph/cm^2/s (below every
# catalogued X-ray pulsar's) or a pulsed fraction below 1e-6 times nothing in any exposure; a
# pulse narrower than 1e-4 of the period would need over 2^21 phase samples (xcorr_toa_sigma);
# a spin-down beyond 1 Hz/s (the fastest known is ~1e-9) would overflow the phase of eq. (2).
_RANGES = {"ra_deg": (0, 360), "dec_deg": (-90, 90), "distance": (_PC, MAX_DISTANCE),
           "period": (1e-4, 1e4), "fdot": (-1, 1), "flux": (1e-8, 1e7), "pulsed_fraction": (1e-6, 1)}
_MIN_DUTY = 1e-4  # the narrowest pulse width over period (above)

_SHEIKH = "Sheikh et al. 2006, Table 1"
_ATNF = "ATNF Pulsar Catalogue (Manchester et al. 2005), rounded"
_PER_CM2 = 1.0e4  # ph/cm^2/s -> ph/m^2/s


@dataclass(frozen=True)
class Pulsar:
    """One X-ray pulsar.

    Attributes
    ----------
    name : str
        B1950 name, e.g. ``"B0531+21"``.
    ra_deg, dec_deg : float
        J2000 right ascension and declination, degrees.
    distance : float
        Distance, m, in [1 pc, MAX_DISTANCE].
    period : float
        Spin period P, s, in [1e-4, 1e4].
    fdot : float
        Spin-frequency derivative, Hz/s, in [-1, 1].
    flux : float
        Photon flux 2-10 keV, ph/m^2/s, in [1e-8, 1e7] (1e-12 to 1e3 ph/cm^2/s).
    pulsed_fraction : float
        Fraction of the flux that is pulsed, in [1e-6, 1].
    width : float
        Pulse width (FWHM), s, in [1e-4 P, 0.5 P].
    sources : dict
        Where each value comes from: a property's name (``"period"``, ...) to text.
    """

    name: str
    ra_deg: float
    dec_deg: float
    distance: float
    period: float
    fdot: float
    flux: float
    pulsed_fraction: float
    width: float
    sources: dict = field(default_factory=dict, compare=False, repr=False)

    def __post_init__(self):  # a complex, NaN or out-of-range field is refused, by name
        check_pulsar_fields(self, _RANGES, _MIN_DUTY)  # dataclasses.replace runs this too

    @property
    def direction(self):
        """Unit vector to the pulsar, ICRF/J2000, shape (3,): ``[cos d cos a, cos d sin a, sin d]``."""
        a, d = math.radians(self.ra_deg), math.radians(self.dec_deg)
        return np.array([math.cos(d) * math.cos(a), math.cos(d) * math.sin(a), math.sin(d)])

    @property
    def frequency(self):
        """Spin frequency f = 1/P, Hz."""
        return 1.0 / self.period

    @property
    def duty_cycle(self):
        """Pulse width over period, W/P (at least 1e-4: W = 1e-4 P can divide to 1 ulp below)."""
        return max(self.width / self.period, _MIN_DUTY)


def _pulsar(name, ra_hms, dec_dms, dist_kpc, period, fdot, flux_cm2, pf, width):
    h, m, s = ra_hms
    sign = -1.0 if dec_dms[0] < 0 or str(dec_dms[0]).startswith("-") else 1.0
    d, dm, ds = (abs(x) for x in dec_dms)
    sources = {**dict.fromkeys(("ra_deg", "dec_deg", "distance", "fdot"), _ATNF),
               **dict.fromkeys(("period", "flux", "pulsed_fraction", "width"), _SHEIKH)}
    return Pulsar(name=name, ra_deg=15.0 * (h + m / 60.0 + s / 3600.0),
                  dec_deg=sign * (d + dm / 60.0 + ds / 3600.0), distance=dist_kpc * KPC,
                  period=period, fdot=fdot, flux=flux_cm2 * _PER_CM2, pulsed_fraction=pf,
                  width=width, sources=sources)


#: The pulsar catalogue, keyed by name.
CATALOGUE = {
    p.name: p
    for p in (
        _pulsar("B0531+21", (5, 34, 31.97), (22, 0, 52.1), 2.0, 0.0335, -3.775e-10,
                1.54, 0.70, 1.67e-3),
        _pulsar("B1937+21", (19, 39, 38.56), (21, 34, 59.1), 3.6, 0.00156, -4.33e-14,
                4.99e-5, 0.86, 2.1e-5),
        _pulsar("B1957+20", (19, 59, 36.77), (20, 48, 15.1), 2.5, 0.0016, -6.5e-15,
                8.31e-5, 0.60, 8.0e-5),
        _pulsar("B1821-24", (18, 24, 32.01), (-24, 52, 10.8), 5.5, 0.00305, -1.74e-13,
                1.93e-4, 0.98, 5.5e-5),
    )
}

#: The main paper's pulsar set, in its order.
PAPER_PULSARS = ("B0531+21", "B1937+21", "B1957+20", "B1821-24")

#: The main paper's ranging accuracy of each pulsar, m (Fan et al. 2016, section 4.1: 500 s,
#: 1 m^2, background 0.005 ph/cm^2/s); :func:`ranging_accuracy` computes ours.
PAPER_RANGING_M = {"B0531+21": 109.0, "B1937+21": 344.0, "B1957+20": 1866.0, "B1821-24": 325.0}


def names():
    """Names of the catalogued pulsars.

    Examples
    --------
    >>> names()
    ['B0531+21', 'B1937+21', 'B1957+20', 'B1821-24']
    """
    return list(CATALOGUE)


def get(name):
    """Return the :class:`Pulsar` called ``name`` (a Pulsar passes through).

    ``name`` is a catalogue name or the path of a timing model (a ``.par`` file, read by
    :func:`from_par` with its X-ray properties from :mod:`xnavlab.mars.timing.xray_pulsars`; read
    once per file and content).

    Raises
    ------
    ValueError
        For an unknown name, listing the known ones, what is no string or Pulsar, or a
        ``.par`` that :func:`from_par` refuses. A catalogue pulsar spelt another way
        (another case, spaces, a ``PSR`` prefix or its J2000 alias) is refused naming the
        catalogue's spelling, not taken: the name is an identifier in records, caches,
        dumps and the fault grammar, which all use the one spelling.

    Examples
    --------
    >>> get("B1937+21").period
    0.00156
    >>> get("b1937+21")
    Traceback (most recent call last):
    ...
    ValueError: unknown pulsar 'b1937+21': the catalogue names it 'B1937+21' (write that)
    """
    if isinstance(name, Pulsar):
        return name
    if not isinstance(name, str):  # an array or a list is no name (it raised unhashable type)
        raise ValueError(f"a pulsar must be a catalogue name, the path of a timing model (.par) "
                         f"or a Pulsar, got {validate.shown(name)}")
    if isinstance(name, str) and name.strip().lower().endswith(".par"):
        path = Path(name).expanduser()  # keyed by its bytes: cp -p keeps the mtime, not the model
        return _par_pulsar(str(path.resolve()), _checks.par_digest(name, path))
    if name not in CATALOGUE:
        row = xray_pulsars.lookup(name) if isinstance(name, str) else None
        if row is not None and row["name"] in CATALOGUE:  # another case, a space or an alias
            raise ValueError(f"unknown pulsar {name!r}: the catalogue names it "
                             f"{row['name']!r} (write that)")
        hint = (f" ({name} is in the X-ray table but needs its timing model: give the path of "
                f"its .par file)" if row is not None else "")
        raise ValueError(f"unknown pulsar {name!r}{hint}; known pulsars: {', '.join(CATALOGUE)}, "
                         f"or the path of a timing model (.par)")
    return CATALOGUE[name]


@functools.lru_cache(maxsize=64)
def _par_pulsar(path, digest):
    """:func:`from_par` of a file, kept per path and SHA-256 of its bytes."""
    return from_par(path)


_FROM_PAR = "argument of pulsars.from_par"


def from_par(path, distance=None, flux_ph_cm2_s=None, pulsed_fraction=None, duty_cycle=None,
             width_s=None):
    """A :class:`Pulsar` from a radio timing model (a ``.par`` file), read by PINT.

    So that any catalogued pulsar can be navigated with: the direction (ICRS at the
    model's position epoch, :func:`xnavlab.mars.timing.pint_bridge.timing_parameters`), the
    distance ``1 / PX`` and the spin ``F0``, ``F1`` come from the model. The X-ray
    fields, which no timing model holds, are arguments or, left out, the X-ray table's
    (:mod:`xnavlab.mars.timing.xray_pulsars`, by the model's pulsar name); a field in neither is
    refused, never filled in. :attr:`Pulsar.sources` says where each value came from.
    PINT is imported here only (offline, :func:`xnavlab.mars.timing.pint_bridge.offline`).

    Parameters
    ----------
    path : str or pathlib.Path
        The ``.par`` file: UTF-8 text (a leading byte-order mark is skipped) with ``F0`` and the
        pulsar's name (``PSR``, ``PSRJ`` or ``PSRB``), else refused.
    distance : float, optional
        Distance, m, in [1 pc, MAX_DISTANCE]; by default ``1 / PX`` (kpc per mas; PX in
        [0.001, 1000] mas). A model without a positive ``PX`` needs it.
    flux_ph_cm2_s : float, optional
        X-ray photon flux (2-10 keV), ph/cm^2/s, in [1e-12, 1e3].
    pulsed_fraction : float, optional
        Pulsed fraction, in [1e-6, 1].
    duty_cycle : float, optional
        Pulse width (FWHM) over period, in [1e-4, 0.5] (the ranges of :class:`Pulsar`).
    width_s : float, optional
        Pulse width (FWHM), s, in [1e-4 P, 0.5 P] (instead of ``duty_cycle``); ``duty_cycle``
        and ``width_s`` default to the table's width. The model's F0 must be in [1e-4, 1e4] Hz.

    Returns
    -------
    Pulsar

    Raises
    ------
    ValueError
        Without ``distance`` when the model has no positive parallax; for an X-ray field
        neither given nor in the table (one line naming each one missing); or for a bad
        argument.

    Examples
    --------
    >>> from xnavlab.mars.timing import pint_bridge
    >>> p = from_par(pint_bridge.examples_path("B1855+09_NANOGrav_9yv1.gls.par"),
    ...              flux_ph_cm2_s=1e-5, pulsed_fraction=0.5, duty_cycle=0.1)
    >>> p.name, round(p.distance / KPC, 3), round(p.frequency, 6)
    ('B1855+09', 3.414, 186.494081)
    """
    from xnavlab.mars.timing import pint_bridge

    if duty_cycle is not None and width_s is not None:
        raise ValueError("give duty_cycle or width_s, not both (the same pulse width)")
    if duty_cycle is not None:  # checked before it scales the period (a str would repeat)
        duty_cycle = check_real("duty_cycle", duty_cycle, _MIN_DUTY, 0.5)
    with _checks.readable_par(path) as readable:  # checked; without a byte-order mark
        try:  # its ValueErrors lead with path and name the file (PINT's and astropy's too)
            par = pint_bridge.timing_parameters(readable)
        except (TypeError, AttributeError, ArithmeticError) as exc:  # a value PINT left unset
            why = (str(exc).strip().splitlines() or [""])[0]
            raise ValueError(f"path: PINT cannot read the timing model {str(path)!r} "
                             f"({type(exc).__name__}: {why})") from None
    model = f"path: the timing model {str(path)!r}"
    period = 1.0 / check_real(f"{model}: its F0 (Hz)", par["f0"], 1e-4, 1e4)
    row = xray_pulsars.lookup(par["name"])
    given = {"flux_ph_cm2_s": flux_ph_cm2_s, "pulsed_fraction": pulsed_fraction,
             "width_s": width_s if duty_cycle is None else duty_cycle * period}
    missing = [k for k, v in given.items() if v is None and row is None]
    if missing:
        raise ValueError(f"pulsar {par['name']} (timing model {Path(path).name}) has no "
                         f"{', '.join(missing)}: a timing model holds none and the X-ray table "
                         f"({xray_pulsars.SOURCE}) has no row for it; give them (arguments "
                         f"of from_par; in a scenario file the keys of a pulsar table "
                         f"{{par = ..., {' = ..., '.join(missing)} = ...}})")
    src = {k: _FROM_PAR if v is not None else row["source"] for k, v in given.items()}
    vals = {k: row[k] if v is None else v for k, v in given.items()}
    flux = check_real("flux_ph_cm2_s", vals["flux_ph_cm2_s"], 1e-12, 1e3)
    pf = check_real("pulsed_fraction", vals["pulsed_fraction"], 1e-6, 1.0)
    width = check_real("width_s", vals["width_s"], _MIN_DUTY * period, 0.5 * period)  # duty_cycle's too
    sources = dict.fromkeys(("ra_deg", "dec_deg", "period", "fdot"), f"timing model {par['name']}")
    if distance is None:
        if par["px_mas"] is None:
            raise ValueError(f"distance must be given (m, 1 pc to 1 Mpc): the timing model of {par['name']} "
                             "has no positive parallax PX (in a scenario file: the key distance_m "
                             "of a pulsar table {par = ..., distance_m = ...})")
        distance = KPC / check_real(f"{model}: its PX (mas)", par["px_mas"], 1e-3, 1e3)
        sources["distance"] = f"timing model {par['name']} (1 / PX)"
    else:
        distance = check_real("distance", distance, _PC, MAX_DISTANCE)
        sources["distance"] = "argument of pulsars.from_par"
    sources.update({"flux": src["flux_ph_cm2_s"], "pulsed_fraction": src["pulsed_fraction"],
                    "width": src["width_s"]})
    return Pulsar(name=par["name"], ra_deg=par["ra_deg"], dec_deg=par["dec_deg"], distance=distance,
                  period=period, fdot=par["f1"], flux=flux * _PER_CM2, pulsed_fraction=pf,
                  width=width, sources=sources)


def check_names(pulsars, name="pulsars"):
    """A list of pulsars (names, ``.par`` paths or Pulsars) as a tuple, or one ValueError.

    Refused, naming ``name``: a string where the list belongs, an empty list, an item that is
    not a pulsar, an unknown one, and a pulsar given twice (by name or by sky position: its
    information would count twice).

    Examples
    --------
    >>> check_names(["B1937+21", "B0531+21"])
    ('B1937+21', 'B0531+21')
    >>> check_names(["B1937+21", "B1937+21"], "pulsar_names")
    Traceback (most recent call last):
    ...
    ValueError: pulsar_names lists B1937+21 twice (items 0 and 1)
    """
    seen = []

    def each(label, item):
        if not isinstance(item, str | Pulsar):
            raise ValueError(f"{label} must be a pulsar name, a .par path or a Pulsar, got {item!r}")
        p = get(item)
        same = [q.name for q in seen if float(np.dot(p.direction, q.direction)) > math.cos(1e-6)]
        seen.append(p)
        return same[0] if same else p.name

    return check_items(name, pulsars, "pulsar", each)


def directions(pulsars=PAPER_PULSARS):
    """Unit vectors to several pulsars, shape (k, 3), and their distances, shape (k,), m.

    Examples
    --------
    >>> n, d = directions()
    >>> n.shape, d.shape
    ((4, 3), (4,))
    """
    ps = [get(p) for p in check_names(pulsars)]
    return np.array([p.direction for p in ps]), np.array([p.distance for p in ps])


def phase(t, freqs, t0=0.0, phase0=0.0):
    """Pulse phase, paper eq. (2): Phi(t) = Phi0 + sum_n f^(n-1) (t - t0)^n / n!.

    Parameters
    ----------
    t : float or array_like
        Times, s, within MAX_SPAN of ``t0``; float32 times or ``t0`` that round the phase by over
        ``_checks.PHASE_RESOLUTION`` (a thousandth of a cycle) or 1 ms are refused.
    freqs : sequence of float
        ``[f, fdot, fddot, ...]``: frequency (Hz, > 0) and its derivatives (Hz/s^n); refused
        when the phase they give overflows float64 at some ``t``.
    t0 : float
        Reference epoch, s.
    phase0 : float
        Phase at ``t0``, cycles.

    Returns
    -------
    ndarray
        Phase in cycles (not wrapped).

    Examples
    --------
    >>> float(phase(2.0, [10.0, 0.5]))   # 10*2 + 0.5*2**2/2
    21.0
    """
    given, t = t, check_finite_array("t", t)
    freqs = check_finite_array("freqs", freqs)
    if freqs.ndim != 1 or freqs.size == 0:
        raise ValueError("freqs must be a non-empty sequence [f, fdot, ...]")
    if not freqs[0] > 0.0:  # a spin frequency; a negative one ran the phase backwards
        raise ValueError(f"freqs[0] must be the spin frequency f, > 0 Hz, got {float(freqs[0]):g}")
    dt = t - check_real("t0", t0)
    _checks.check_phase_dtype(float(freqs[0]), {"t": given, "t0": t0})  # float32: 32 s at 5e8 s
    if np.any(np.abs(dt) > MAX_SPAN):
        raise ValueError(f"t must be within MAX_SPAN = {MAX_SPAN:g} s of t0 (the timing model's epoch)")
    out = np.full(dt.shape, check_real("phase0", phase0))
    term = np.ones_like(dt)
    with np.errstate(over="ignore", invalid="ignore"):  # a phase beyond float64: refused below
        for n, fn in enumerate(freqs, start=1):
            term = term * (dt / n)  # (t - t0)^n / n!
            out = out + fn * term if fn else out  # paper eq. (2)
    if not np.all(np.isfinite(out)):
        raise ValueError("freqs must give a phase within float64's range at every t (|Phi| < 1.8e308)")
    return out


def profile(ph, duty):
    """Normalised pulse profile: a wrapped Gaussian of FWHM ``duty`` cycles (in [1e-4, 0.5],
    the duty cycles of :class:`Pulsar`), peak at phase 0.

    ``int_0^1 profile(phi) dphi = 1``, so a rate ``lambda_s * profile(phi)`` carries
    ``lambda_s`` pulsed photons per second on average.

    Examples
    --------
    >>> x = np.linspace(0, 1, 2001)[:-1]
    >>> round(float(profile(x, 0.05).mean()), 6)
    1.0
    """
    duty = check_real("duty", duty, _MIN_DUTY, 0.5)
    sig = duty / (2.0 * math.sqrt(2.0 * math.log(2.0)))
    ph = check_finite_array("ph", ph)
    x = ph - np.round(ph)  # in [-0.5, 0.5]
    out = np.zeros_like(x)
    for k in (-2, -1, 0, 1, 2):
        out += np.exp(-0.5 * ((x + k) / sig) ** 2)
    return out / (sig * math.sqrt(2.0 * math.pi))


def binned_template(nbins, duty):
    """Expected fraction of pulsed photons in each of ``nbins`` phase bins (``duty`` as
    :func:`profile`'s), sums to 1.

    Bin ``i`` covers phases ``[i/nbins, (i+1)/nbins)``; the integral is taken with
    Simpson's rule on 8 sub-intervals per bin.

    Examples
    --------
    >>> round(float(binned_template(64, 0.1).sum()), 9)
    1.0
    """
    nbins = check_int("nbins", nbins, 8, 2**20)
    sub = 8
    x = np.linspace(0.0, 1.0, nbins * sub + 1)
    y = profile(x, duty)
    w = np.ones(sub + 1)
    w[1:-1:2], w[2:-1:2] = 4.0, 2.0
    y = y[:-1].reshape(nbins, sub)
    ends = np.append(y[1:, 0], y[0, 0])
    vals = np.column_stack([y, ends]) @ w / (3.0 * sub * nbins)
    return vals / vals.sum()


def photon_rates(pulsar, area_m2=1.0, background_ph_cm2_s=0.005):
    """Pulsed and unpulsed photon rates at the detector, ph/s.

    The unpulsed rate is the background plus the pulsar's unpulsed flux:
    ``lambda_b = A (B + F (1 - p_f))``; the pulsed rate is ``lambda_s = A F p_f``.

    Examples
    --------
    >>> ls, lb = photon_rates("B1821-24")
    >>> round(ls, 4), round(lb, 3)
    (1.8914, 50.039)
    """
    p = get(pulsar)
    area = check_real("area_m2", area_m2, 1e-6, 1e3)  # 1 mm^2 at least: finite TOA sigmas
    bg = check_real("background_ph_cm2_s", background_ph_cm2_s, 0.0, 10.0) * _PER_CM2
    pulsed = area * p.flux * p.pulsed_fraction
    unpulsed = area * (bg + p.flux * (1.0 - p.pulsed_fraction))
    return pulsed, unpulsed


def simulate_photons(pulsar, t_obs, area_m2=1.0, background_ph_cm2_s=0.005, rng=None,
                     shift=0.0):
    """Photon arrival times of a non-homogeneous Poisson process over ``[0, t_obs)``.

    The rate is ``lambda_b + lambda_s * profile(Phi(t - shift))`` with the phase model
    ``Phi(t) = f t + fdot t^2 / 2``: pulsed photons are drawn in phase (a Poisson
    number, a uniform cycle, a phase from the profile) and mapped to time by inverting
    Phi; unpulsed photons are uniform in time.

    Parameters
    ----------
    pulsar : str or Pulsar
    t_obs : float
        Observation time, s, in (0, 1e6], over which the photon rates expect at most 5e7
        photons (about 2 GB: the Crab at 1 m^2 over 3,200 s; ``_checks.MAX_PHOTONS``).
    area_m2, background_ph_cm2_s : float
        Detector effective area, m^2, in [1e-6, 1e3]; diffuse background, ph/cm^2/s, in [0, 10].
    rng : numpy.random.Generator or int, optional
    shift : float
        True TOA offset of the pulse train, s (what an estimator should recover).

    Returns
    -------
    ndarray, shape (n,)
        Sorted arrival times, s.

    Examples
    --------
    >>> t = simulate_photons("B1821-24", 10.0, rng=1)
    >>> bool(300 < t.size < 800), bool(t.min() >= 0.0 and t.max() < 10.0)
    (True, True)
    """
    p = get(pulsar)
    t_obs = check_real("t_obs", t_obs, 0.0, 1e6, lo_open=True)
    shift = check_real("shift", shift)
    rng = make_rng(rng)
    lam_s, lam_b = _checks.check_photons("t_obs", photon_rates(p, area_m2, background_ph_cm2_s), t_obs)
    f, fdot = p.frequency, p.fdot
    check_spin_drift(p.name, f, fdot, t_obs, shift)  # else f + fdot tau nears 0 below (MAX_DRIFT)
    sig = p.duty_cycle / (2.0 * math.sqrt(2.0 * math.log(2.0)))
    # Draw over whole cycles -1 .. n_cyc (one spare each side, since the shift and the
    # profile's tails move photons across the ends), at lambda_s / f photons per cycle,
    # then keep those inside [0, t_obs): the kept count is Poisson(lambda_s t_obs).
    first, last = -1 + math.floor(-shift * f), math.ceil(f * t_obs - shift * f) + 1
    n_cyc = last - first + 1
    n_s = rng.poisson(lam_s / f * n_cyc)
    ph = rng.integers(first, last + 1, n_s) + rng.normal(0.0, sig, n_s)
    # invert Phi(tau) = f tau + fdot tau^2 / 2 for tau (two Newton steps from tau = ph/f)
    tau = ph / f
    for _ in range(2):
        tau -= (f * tau + 0.5 * fdot * tau**2 - ph) / (f + fdot * tau)
    t_s = tau + shift
    t_s = t_s[(t_s >= 0.0) & (t_s < t_obs)]
    t_b = rng.uniform(0.0, t_obs, rng.poisson(lam_b * t_obs))
    return np.sort(np.concatenate([t_s, t_b]))


def _binned_phase(name, t, p, nbins, t0):
    """``Phi(t)`` of ``p`` (cycles), refused (naming ``name``) beyond ``0.1 2^52 / nbins`` cycles,
    where float64's spacing, ``|Phi| 2^-52``, exceeds a tenth of a bin: which bin is noise."""
    t = check_finite_array(name, t)
    start = check_real("t0", t0)
    _checks.check_times_dtype("t0", t0, p, nbins)  # a float32 t0 rounds every phase
    if np.any(np.abs(t - start) > MAX_SPAN):  # phase() refuses it: no bin either
        t = np.full(t.shape, math.inf)
    ph = phase(t, [p.frequency, p.fdot], t0=t0) if np.all(np.isfinite(t)) else t
    limit = 0.1 * 2.0**52 / nbins  # eq: cycles at which float64's spacing is 0.1 / nbins
    worst = float(np.max(np.abs(ph), initial=0.0)) if np.all(np.isfinite(ph)) else math.inf
    if not worst <= limit:
        raise ValueError(f"{name} must lie within about {limit / p.frequency:.3g} s of t0 "
                         f"(phases below {limit:.3g} cycles, which float64 places to a tenth of "
                         f"one of {nbins} bins), got phases up to {worst:.3g} cycles")
    return ph


def phase_exposure(span, pulsar, nbins=256, t0=0.0):
    """Exposure of each phase bin over an observation, cycles; shape (nbins,).

    Bin ``i`` covers phases ``[i/nbins, (i+1)/nbins)`` of every cycle; its exposure is the
    length of phase, summed over the cycles, that the span ``[t_start, t_stop]`` sweeps
    through it, with the phase model ``Phi`` of :func:`phase` (``[f, fdot]``). Over a
    whole number of cycles every bin has the same exposure, ``(Phi(t_stop) -
    Phi(t_start)) / nbins``; otherwise the bins the last partial cycle crosses have one
    ``1/nbins`` more.

    Parameters
    ----------
    span : (float, float)
        Start and end of the observation, s (end after start).
    pulsar : str or Pulsar
        Supplies the phase model ``[f, fdot]``.
    nbins : int
        Number of phase bins.
    t0 : float
        Epoch at which the phase is zero, s. The span's phases must stay below
        ``0.1 2^52 / nbins`` cycles (float64 then places them to a tenth of a bin); beyond,
        refused.

    Returns
    -------
    ndarray, shape (nbins,)
        Phase exposure, cycles; sums to ``Phi(t_stop) - Phi(t_start)``.

    Examples
    --------
    >>> crab = get("B0531+21")
    >>> e = phase_exposure((0.0, 2.5 * crab.period), crab, nbins=8)
    >>> (e * 8).round(6).tolist()   # two whole cycles, and half a cycle more in bins 0-3
    [3.0, 3.0, 3.0, 3.0, 2.0, 2.0, 2.0, 2.0]
    """
    p = get(pulsar)
    nbins = check_int("nbins", nbins, 8, 2**20)
    given, span = span, check_span(span)
    _checks.check_times_dtype("span", given, p, nbins)
    ends = _binned_phase("span", span, p, nbins, t0)
    lo = np.arange(nbins) / nbins

    def swept(ph):  # phase swept through each bin from phase 0 up to ph (cycles)
        whole = math.floor(ph)
        return whole / nbins + np.clip(ph - whole - lo, 0.0, 1.0 / nbins)

    return swept(float(ends[1])) - swept(float(ends[0]))


def fold(t, pulsar, nbins=256, t0=0.0, span=None, exposure=True):
    """Epoch folding: photons per phase bin, ``Phi(t) mod 1``, corrected for exposure.

    Unless the observation spans a whole number of pulse cycles, some phase bins are
    observed for one cycle more than the others (:func:`phase_exposure`) and collect more
    background; uncorrected, that extra background pulls a TOA estimate toward them (for
    the Crab over 10 s, 298.5 cycles, by about +1 us, several sigma). With ``exposure``
    (the default) each bin's count is divided by its exposure relative to the mean
    exposure, so every bin estimates the counts of a mean bin and the total stays about
    the number of photons (stingray's ``fold_events(..., expocorr=True)`` does the same,
    normalised to the largest exposure instead).

    Parameters
    ----------
    t : array_like, shape (n,)
        Photon arrival times, s.
    pulsar : str or Pulsar
        Supplies the phase model ``[f, fdot]``.
    nbins : int
        Number of phase bins.
    t0 : float
        Epoch at which the phase is zero, s. Photons whose phase exceeds ``0.1 2^52 / nbins``
        cycles (about 3e9 s from ``t0`` for B1937+21, 642 Hz, in 256 bins) are refused:
        float64 no longer tells their bin.
    span : (float, float), optional
        Start and end of the observation, s (end after start), which must hold every photon
        (for :func:`simulate_photons`, ``(0, t_obs)``). By default the first and last photon:
        for bright sources nearly the same, for faint ones short by the waits for the
        first and last photon. Only with ``exposure`` (with ``exposure=False``, refused).
    exposure : bool
        Divide by the relative exposure (default). ``False`` gives the raw counts
        (integers), exact only over a whole number of cycles.

    Returns
    -------
    ndarray, shape (nbins,)
        Exposure-corrected counts (float), or raw counts (int) with ``exposure=False``.

    Examples
    --------
    >>> fold([0.0, 0.25, 0.5], "B0531+21", nbins=8, exposure=False).sum()
    3
    >>> crab = get("B0531+21")
    >>> t = np.arange(1 / 16, 2.5, 1 / 8) * crab.period    # a photon per bin, 2.5 cycles
    >>> fold(t, crab, nbins=8, exposure=False).tolist()
    [3, 3, 3, 3, 2, 2, 2, 2]
    >>> fold(t, crab, nbins=8, span=(0.0, 2.5 * crab.period)).round(6).tolist()
    [2.5, 2.5, 2.5, 2.5, 2.5, 2.5, 2.5, 2.5]
    """
    exposure = check_bool("exposure", exposure)
    if span is not None and not exposure:  # the raw counts need no span: it would be ignored
        raise ValueError("span is used only with exposure=True (for the correction): leave it out")
    p = get(pulsar)
    nbins = check_int("nbins", nbins, 8, 2**20)
    given, t = t, check_finite_array("t", t)
    if t.ndim != 1 or t.size == 0:
        raise ValueError(f"t must be a non-empty 1-D array of photon times, got shape {t.shape}")
    _checks.check_times_dtype("t", given, p, nbins)
    ph = _binned_phase("t", t, p, nbins, t0) % 1.0  # a bin float64 can tell (else refused)
    idx = np.minimum((ph * nbins).astype(np.int64), nbins - 1)
    counts = np.bincount(idx, minlength=nbins)
    if not exposure:
        return counts
    given = span is not None
    if span is None:
        if t.size < 2 or not t.max() > t.min():
            raise ValueError("t must hold photons at two or more times to infer the span; give span")
        span = (float(t.min()), float(t.max()))
    span = check_span(span)  # before t: a reversed span blamed t
    if t.min() < span[0] or t.max() > span[1]:
        raise ValueError(f"t must lie within span = {span.tolist()}, got photons in "
                         f"[{float(t.min())!r}, {float(t.max())!r}]")
    e = check_exposure(phase_exposure(span, p, nbins, t0), span, given, p.period)  # no bin unswept
    return counts * (e.mean() / e)


def simulate_folded(pulsar, t_obs, area_m2=1.0, background_ph_cm2_s=0.005, nbins=256,
                    rng=None, shift=0.0):
    """Folded profile drawn directly: Poisson counts per phase bin.

    The counts in disjoint phase bins of a Poisson process are independent Poisson
    variables; this draws them with means ``lambda_b t_obs / nbins + lambda_s t_obs T_i``
    (``T_i`` the :func:`binned_template` shifted by ``shift``), fast enough for Monte Carlo
    runs with millions of photons. When ``f t_obs`` is a whole number of cycles this is
    the distribution of ``fold(simulate_photons(p, t_obs, ..., shift=shift), p,
    span=(0, t_obs))``. Otherwise the folded photons see the last partial cycle in some
    bins only; :func:`fold` divides that exposure out, which gives the same means, and
    variances that differ from these by at most the partial cycle's share, ``1 / (f
    t_obs)`` relative (without the correction the means would differ: see :func:`fold`).
    The spin-down is not drawn here: folding with the pulsar's ``[f, fdot]`` removes it.

    Returns
    -------
    ndarray of int, shape (nbins,)

    Examples
    --------
    >>> simulate_folded("B0531+21", 1.0, nbins=64, rng=0).shape
    (64,)
    """
    p = get(pulsar)
    t_obs = check_real("t_obs", t_obs, 0.0, 1e7, lo_open=True)
    shift = check_real("shift", shift)
    rng = make_rng(rng)
    lam_s, lam_b = photon_rates(p, area_m2, background_ph_cm2_s)
    template = _shifted_template(nbins, p.duty_cycle, shift * p.frequency)
    mean = lam_b * t_obs / nbins + lam_s * t_obs * template
    return rng.poisson(mean)


def _shifted_template(nbins, duty, shift_cycles):
    base = binned_template(nbins, duty)
    k = np.fft.rfftfreq(nbins, 1.0 / nbins)
    spec = np.fft.rfft(base) * np.exp(-2j * np.pi * k * shift_cycles)
    out = np.fft.irfft(spec, nbins)
    return np.clip(out, 0.0, None) / np.clip(out, 0.0, None).sum()


def estimate_phase_shift(counts, template):
    """TOA estimate: the phase shift maximising the cross-correlation with the template.

    The circular cross-correlation ``C(tau) = sum_k X_k conj(T_k) exp(2 pi i k tau)``
    is evaluated on a fine grid by FFT to find the peak, then refined by Newton's
    method on ``C'(tau) = 0`` using the Fourier series (Taylor 1992, "FFTFIT").

    Parameters
    ----------
    counts : array_like, shape (nbins,)
        Folded profile: photon counts, >= 0, ``nbins >= 2``, not all equal.
    template : array_like, shape (nbins,)
        Noise-free profile, >= 0, not flat; bin 0 starts at the timing model's phase 0 (the
        shift's origin), which need not be the pulse's peak (PINT's Fermi template peaks at 0.6).

    Returns
    -------
    float
        Shift in cycles, in [-0.5, 0.5), against ``template``: positive means the pulses arrive late.

    Examples
    --------
    >>> tpl = binned_template(128, 0.05)
    >>> round(estimate_phase_shift(np.roll(tpl, 16), tpl), 6)
    0.125
    """
    x = check_finite_array("counts", counts)
    if x.ndim != 1 or x.size < 2:
        raise ValueError(f"counts must be a 1-D fold of at least 2 phase bins, got shape {x.shape}")
    tpl = validate.check_shape("template", template, x.shape, "one bin per bin of counts")
    for name, v, what in (("counts", x, "photon counts"), ("template", tpl, "a pulse profile")):
        if np.any(v < 0.0):  # a negative template (an inverted pulse) measured the wrong peak
            raise ValueError(f"{name} must be {what}, >= 0, got {float(v.min()):g} in "
                             f"bin {int(np.argmin(v))}")
        if np.ptp(v) == 0.0:  # a flat profile has no phase: 0.0 was returned as if measured
            raise ValueError(f"{name} must hold a pulse (bins not all equal), got every bin "
                             f"{float(v[0]):g}: no phase shift can be estimated")
    n = x.size
    cross = np.fft.rfft(x - x.mean()) * np.conj(np.fft.rfft(tpl - tpl.mean()))
    k = np.arange(cross.size)
    fine = np.fft.irfft(cross, 8 * n)
    tau = np.argmax(fine) / (8 * n)
    for _ in range(6):  # Newton on dC/dtau = 0
        e = cross * np.exp(2j * np.pi * k * tau)
        d1 = np.sum((2j * np.pi * k) * e).real
        d2 = np.sum(-((2 * np.pi * k) ** 2) * e).real
        if d2 >= 0:
            break
        tau -= d1 / d2
    return float((tau + 0.5) % 1.0 - 0.5)


def toa_sigma(pulsar, area_m2=1.0, t_obs=500.0, background_ph_cm2_s=0.005):
    """TOA accuracy (1 sigma, s) from the signal-to-noise ratio, Sheikh et al. (2006).

    ``SNR = F A p_f t / sqrt([B + F (1 - p_f)] A t d + F A p_f t)``, ``d = W / P``,
    and ``sigma_TOA = W / (2 SNR)`` (Sheikh et al. 2006, eqs. (34)-(35)). The parameters and
    their ranges are :func:`xcorr_toa_sigma`'s.

    Examples
    --------
    >>> round(toa_sigma("B1937+21") * 1e6, 3)   # microseconds
    1.149
    """
    p = get(pulsar)
    t_obs = check_real("t_obs", t_obs, 1e-6, 1e7)  # 1 us at least: finite TOA sigmas
    lam_s, lam_b = photon_rates(p, area_m2, background_ph_cm2_s)
    signal = lam_s * t_obs
    noise = math.sqrt(lam_b * t_obs * p.duty_cycle + signal)
    return p.width / (2.0 * signal / noise)


def ranging_accuracy(pulsar, area_m2=1.0, t_obs=500.0, background_ph_cm2_s=0.005):
    """Ranging accuracy ``c * sigma_TOA``, m (see :func:`toa_sigma`).

    Examples
    --------
    >>> [round(ranging_accuracy(n)) for n in PAPER_PULSARS]
    [109, 345, 1868, 326]
    """
    return C * toa_sigma(pulsar, area_m2, t_obs, background_ph_cm2_s)


def monte_carlo_toa(pulsar, n_trials=200, area_m2=1.0, t_obs=500.0, background_ph_cm2_s=0.005,
                    nbins=None, rng=None):
    """Monte Carlo of the photon-level TOA estimator: errors of ``n_trials`` estimates, s.

    Each trial draws a folded profile with a random true offset (uniform within a
    tenth of a period), estimates the offset with :func:`estimate_phase_shift` and
    records estimate minus truth.

    Parameters
    ----------
    nbins : int, optional
        Phase bins; by default enough for 40 bins per pulse width (at least 256).

    Returns
    -------
    ndarray, shape (n_trials,)
        TOA errors, s.

    Examples
    --------
    >>> err = monte_carlo_toa("B0531+21", n_trials=20, rng=0)
    >>> bool(np.std(err) < 1e-6)
    True
    """
    p = get(pulsar)
    n_trials = check_int("n_trials", n_trials, 2, 10**6)
    rng = make_rng(rng)
    if nbins is None:
        nbins = int(2 ** math.ceil(math.log2(max(256.0, 40.0 / p.duty_cycle))))
    template = binned_template(nbins, p.duty_cycle)
    errors = np.empty(n_trials)
    for i in range(n_trials):
        truth = rng.uniform(-0.05, 0.05) * p.period
        counts = simulate_folded(p, t_obs, area_m2, background_ph_cm2_s, nbins, rng, truth)
        if np.ptp(counts) == 0:  # no pulse to estimate (refused as 'counts' below, not given here)
            raise ValueError(f"t_obs must be long enough to fold a pulse in every trial: trial {i} "
                             f"drew {int(counts.sum())} photons, {int(counts[0])} in each of {nbins} bins")
        est = estimate_phase_shift(counts, template) * p.period
        errors[i] = est - truth
    return errors


def xcorr_toa_sigma(pulsar, area_m2=1.0, t_obs=500.0, background_ph_cm2_s=0.005, nbins=None):
    """TOA accuracy (1 sigma, s) of the cross-correlation estimator, to first order.

    :func:`estimate_phase_shift` solves ``C'(tau) = 0``; expanding it to first order in
    the Poisson noise of the folded counts gives, for a template ``h`` (normalised,
    ``int h = 1``) with ``N_s = lambda_s t`` pulsed and ``N_b = lambda_b t`` unpulsed
    photons,

    ``sigma_tau^2 = (N_b int h'^2 + N_s int h'^2 h) / (N_s^2 (int h'^2)^2)``  (cycles^2)

    and ``sigma_TOA = P sigma_tau``. Unlike :func:`toa_sigma` (Sheikh et al. 2006), which
    counts background only inside the pulse width, this counts the background the
    template's tails integrate too: for a Gaussian template the ratio to :func:`toa_sigma`
    is 1.05 when the pulsed photons dominate and 1.47 when the background does.

    Parameters
    ----------
    pulsar : str or Pulsar
    area_m2 : float
        Detector effective area, m^2, in [1e-6, 1e3] (a smaller one times nothing).
    t_obs : float
        Integration time, s, in [1e-6, 1e7] (a shorter one times nothing).
    background_ph_cm2_s : float
        Diffuse X-ray background, ph/cm^2/s, in [0, 10].
    nbins : int, optional
        Phase bins of the folded profile (the integrals become means over the bins of
        :func:`binned_template`, derivative by FFT); by default the continuous profile.

    Returns
    -------
    float
        sigma_TOA, s.

    Examples
    --------
    >>> round(xcorr_toa_sigma("B0531+21") / toa_sigma("B0531+21"), 2)   # signal dominated
    1.06
    >>> round(xcorr_toa_sigma("B1957+20") / toa_sigma("B1957+20"), 2)   # mostly background
    1.41
    """
    p = get(pulsar)
    t_obs = check_real("t_obs", t_obs, 1e-6, 1e7)  # 1 us at least: finite TOA sigmas
    lam_s, lam_b = photon_rates(p, area_m2, background_ph_cm2_s)
    if nbins is None:  # the continuous profile, sampled finely enough to integrate exactly
        m = int(2 ** math.ceil(math.log2(max(4096.0, 200.0 / p.duty_cycle))))
        h = profile(np.arange(m) / m, p.duty_cycle)
    else:
        m = check_int("nbins", nbins, 8, 2**20)
        h = binned_template(m, p.duty_cycle) * m  # density per cycle at the bins
    k = np.fft.fftfreq(m, 1.0 / m)
    dh = np.fft.ifft(2j * np.pi * k * np.fft.fft(h)).real  # h'(phi), per cycle^2
    i1 = float(np.mean(dh**2))  # int h'^2 dphi
    i2 = float(np.mean(dh**2 * h))  # int h'^2 h dphi
    n_s, n_b = lam_s * t_obs, lam_b * t_obs
    var = (n_b * i1 + n_s * i2) / (n_s**2 * i1**2)  # eq. (ch1-xcorr-var), cycles^2
    return p.period * math.sqrt(var)
