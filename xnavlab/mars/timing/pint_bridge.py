"""PINT, the radio pulsar-timing package, as a witness: offline, with the DE421 of skyfield-data.

PINT (Luo et al. 2021) is what the field uses to time pulsars. This module runs it without
a network and hands its numbers back as plain numpy arrays, so the book can set our
time-transfer terms (:mod:`xnavlab.mars.timing.toa`) beside PINT's and fold real photons:

- :func:`offline` makes astropy and PINT work offline (no download is ever attempted)
  and loads DE421 from the ``skyfield-data`` package; every other function calls it first.
- :func:`pint_delays`: PINT's Roemer, parallax and solar Shapiro delays (and the
  planets') for a spacecraft at given SSB positions and epochs, through PINT's
  ``spacecraft`` observatory (the Tempo2 ``-telx -tely -telz`` flags);
  :func:`planet_shapiro` the planets' part alone.
- :func:`fermi_photon_phases`: the Fermi-LAT photons of PSR J0030+0451 shipped with PINT,
  their phases under the shipped timing model and their weights;
  :func:`fermi_template` the three-Gaussian template shipped beside them.
- :func:`fermi_photon_geometry`: where PINT put the geocentre and the pulsar for each of
  those photons; :func:`fermi_displaced_phases` their phases with the geocentre moved
  (the witness of :mod:`xnavlab.mars.timing.photon_fix`).
- :func:`nanograv_residuals`: the NANOGrav 9-year residuals of PSR B1855+09.
- :func:`timing_parameters`: position, parallax and spin of any ``.par`` file, the
  numbers behind :func:`xnavlab.mars.timing.pulsars.from_par`.

PINT is imported inside the functions: ``import xnavlab`` stays fast and works without it.

Signs and references
--------------------
PINT's delays are added to the emission time to give the arrival time; ours
(:mod:`xnavlab.mars.timing.toa`) are the time by which the pulse reaches the spacecraft *before*
the SSB. Every delay returned here is PINT's with its sign flipped, so that ``roemer`` and
``parallax`` compare with :func:`xnavlab.mars.timing.toa.roemer` and
:func:`xnavlab.mars.timing.toa.parallax` directly. PINT's Shapiro delays are referred to a
distance of 1 au (``-2 GM/c^3 ln[(r - r cos theta) / 1 au]``); ours to the SSB's own
Shapiro delay: :func:`xnavlab.mars.timing.toa.shapiro_offset_to_pint` converts.

Offline switches (PINT 1.1.8, astropy 6-8)
------------------------------------------
``astropy.utils.data.conf.allow_internet = False`` and
``astropy.utils.iers.conf.auto_download = False`` (astropy then uses the IERS-B table
and the leap seconds it ships); the solar-system ephemeris is loaded from a local file
(``pint.solar_system_ephemerides.load_kernel("de421", path=...)``, which PINT keeps for
every later call); TOAs are read with ``include_bipm=False`` (no BIPM clock file). PINT
has no switch for the observatory and GPS clock files, which it fetches from the
global repository: :func:`nanograv_residuals` turns them off for Arecibo while it runs
(the observatory keeps the ``-to`` time offsets written in the ``.tim`` file). Two
astropy warnings are filtered, by name, inside these functions only: ``IERSStaleWarning``
("leap-second file is expired") and the ``AstropyWarning`` "leap-second auto-update
failed", which an offline machine would raise once the shipped leap-second table ages.

Examples
--------
>>> ephemeris_path().name
'de421.bsp'
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import importlib.metadata
import importlib.resources
import os
import sys
import warnings
from pathlib import Path

import numpy as np

from xnavlab.core import dates, ephemeris
from xnavlab.core.constants import DAY, KPC
from xnavlab.core.diskcache import cached_arrays, entry_path
from xnavlab.core.validate import check_bool, check_choice, check_finite_array, check_int, shown
from xnavlab.mars.timing import _checks

__all__ = [
    "EPHEMERIS",
    "PLANETS",
    "ephemeris_path",
    "examples_path",
    "offline",
    "pint_delays",
    "planet_shapiro",
    "fermi_photon_phases",
    "fermi_template",
    "fermi_photon_geometry",
    "fermi_displaced_phases",
    "nanograv_residuals",
    "timing_parameters",
]

#: The solar-system ephemeris PINT is given (the same DE421 as :mod:`xnavlab.core.ephemeris`).
EPHEMERIS = "de421"
#: The planets whose Shapiro delay PINT models (``PLANET_SHAPIRO``), in PINT's order.
PLANETS = ("jupiter", "saturn", "venus", "uranus", "neptune")

_MJD_J2000 = 51544.5  # MJD of J2000 (JD 2451545.0)
_FERMI_EVENTS = "J0030+0451_P8_15.0deg_239557517_458611204_ft1weights_GEO_wt.gt.0.4.fits"
_FERMI_PAR = "PSRJ0030+0451_psrcat.par"
_FERMI_TEMPLATE = "templateJ0030.3gauss"
_NANOGRAV_PAR = "B1855+09_NANOGrav_9yv1.gls.par"
_NANOGRAV_TIM = "B1855+09_NANOGrav_9yv1.tim"


def ephemeris_path():
    """Path of the DE421 SPK kernel shipped in the ``skyfield-data`` package.

    Raises
    ------
    FileNotFoundError
        If ``skyfield-data`` is missing or ships no ``de421.bsp``.

    Examples
    --------
    >>> ephemeris_path().parent.name
    'data'
    """
    try:
        root = importlib.resources.files("skyfield_data")
    except ModuleNotFoundError as exc:
        raise FileNotFoundError("the skyfield-data package (which ships de421.bsp) is not installed") from exc
    path = Path(str(root)) / "data" / f"{EPHEMERIS}.bsp"
    if not path.is_file():
        raise FileNotFoundError(f"skyfield-data ships no {path.name} (looked for {path})")
    return path


def examples_path(name):
    """Path of a file in PINT's ``pint/data/examples`` (the ``.par``, ``.tim`` and photon files).

    Found without importing PINT (which takes seconds). A ``name`` that is no non-empty string,
    holds a folder, or is no file PINT ships is one ValueError (listing the files it ships);
    PINT not installed, a FileNotFoundError.

    Parameters
    ----------
    name : str
        A file name in ``pint/data/examples``, such as ``"B1855+09_NANOGrav_9yv1.gls.par"``
        (no folder: a path that climbs out of the examples is refused).

    Examples
    --------
    >>> examples_path("B1855+09_NANOGrav_9yv1.tim").name
    'B1855+09_NANOGrav_9yv1.tim'
    """
    import importlib.util

    if not isinstance(name, str) or not name.strip():  # (a dict gave Path's TypeError)
        raise ValueError(f"name must be a file name in PINT's examples, got {name!r:.80}")
    spec = importlib.util.find_spec("pint")
    if spec is None or not spec.submodule_search_locations:
        raise FileNotFoundError("PINT (the pint-pulsar package) is not installed")
    folder = Path(spec.submodule_search_locations[0]) / "data" / "examples"
    # The name looked up among the files, never opened as given: a name the OS refuses (300
    # characters, a NUL) was an OSError or ValueError from the file system
    shipped = sorted(p.name for p in folder.iterdir() if p.is_file()) if folder.is_dir() else []
    if name not in shipped:
        import difflib

        near = difflib.get_close_matches(name, shipped, n=1)
        hint = f" (nearest: {near[0]!r})" if near else ""
        raise ValueError(f"name must be an example file PINT {importlib.metadata.version('pint-pulsar')} "
                         f"ships, got {name[:80]!r}{'...' if len(name) > 80 else ''}{hint}; the "
                         f"{len(shipped)} files in {folder}: {', '.join(shipped)}")
    return folder / name


_OFFLINE = {}


def offline(log_level="WARNING"):
    """Make astropy and PINT work offline and load DE421 from ``skyfield-data``; idempotent.

    Sets ``astropy.utils.data.conf.allow_internet = False`` (any download raises at once
    instead of waiting on a network) and ``astropy.utils.iers.conf.auto_download = False``
    (the IERS-B table shipped with astropy serves UT1 and polar motion), then loads the
    DE421 kernel from :func:`ephemeris_path` into PINT, which keeps it for every later
    request of ``"de421"``.

    Parameters
    ----------
    log_level : str or None
        Level of PINT's log messages (loguru) written to ``sys.stderr``
        (``"WARNING"`` keeps INFO chatter out of notebooks); ``None`` leaves PINT's
        logging as it is. Python warnings are not redirected.

    Returns
    -------
    pathlib.Path
        The DE421 kernel loaded.

    Examples
    --------
    >>> offline().name
    'de421.bsp'
    """
    if log_level is not None:
        check_choice("log_level", log_level, ("TRACE", "DEBUG", "INFO", "SUCCESS", "WARNING",
                                              "ERROR", "CRITICAL"))
    import astropy.utils.data
    import astropy.utils.iers

    astropy.utils.data.conf.allow_internet = False
    astropy.utils.iers.conf.auto_download = False
    path = ephemeris_path()
    with _quiet():
        import pint.logging
        import pint.solar_system_ephemerides as sse

        if log_level is not None and _OFFLINE.get("log_level") != log_level:
            # a sink that looks sys.stderr up at each message (pytest and Jupyter swap it)
            pint.logging.setup(level=log_level, sink=lambda message: sys.stderr.write(message),
                               usecolors=False, capturewarnings=False)
            _OFFLINE["log_level"] = log_level
        sse.load_kernel(EPHEMERIS, path=str(path))
    return path


@contextlib.contextmanager
def _quiet():
    """The two astropy warnings an ageing leap-second table raises offline, filtered by name."""
    from astropy.utils.exceptions import AstropyWarning
    from astropy.utils.iers import IERSStaleWarning

    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="leap-second file is expired", category=IERSStaleWarning)
        warnings.filterwarnings("ignore", message="leap-second auto-update failed", category=AstropyWarning)
        yield


# ------------------------------------------------------------------ delays for a spacecraft


def _epochs(t, m):
    """(day, fraction) MJD TDB pairs of epochs ``t`` (s TDB past J2000), without losing ns."""
    t = np.broadcast_to(t, (m,)).astype(float)
    day = np.floor(t / DAY)
    frac = (t - day * DAY) / DAY + 0.5  # J2000 is MJD 51544.5
    return _MJD_J2000 - 0.5 + day, frac


def _spacecraft_toas(r_ssb, t, planets):
    """PINT TOAs at the spacecraft positions ``r_ssb`` (m, SSB) and epochs ``t`` (s TDB)."""
    from astropy.time import Time
    from pint.solar_system_ephemerides import objPosVel_wrt_SSB
    from pint.toa import get_TOAs_array

    mjd1, mjd2 = _epochs(t, r_ssb.shape[0])
    tdb = Time(mjd1, mjd2, format="mjd", scale="tdb")
    earth_km = objPosVel_wrt_SSB("earth", tdb, EPHEMERIS).pos.to_value("km").T
    geo_km = r_ssb / 1e3 - earth_km  # the spacecraft from the geocentre, km (-telx, -tely, -telz)
    flags = [{"telx": repr(float(x)), "tely": repr(float(y)), "telz": repr(float(z)),
              "vx": "0.0", "vy": "0.0", "vz": "0.0"} for x, y, z in geo_km]
    return get_TOAs_array((mjd1, mjd2), obs="spacecraft", scale="tdb", include_bipm=False,
                          planets=planets, ephem=EPHEMERIS, flags=flags)


_PAR = """PSR XNAVLAB
RAJ 00:00:00.0
DECJ 00:00:00.0
F0 100.0
PEPOCH 55000
POSEPOCH 55000
PX 0.0
EPHEM DE421
UNITS TDB
PLANET_SHAPIRO N
"""


def _direction_model():
    import io

    from pint.models import get_model

    return get_model(io.StringIO(_PAR))


def pint_delays(r_sc_ssb, t, n, distance=None, planets=False):
    """PINT's delays for a spacecraft at SSB positions ``r_sc_ssb`` and epochs ``t``.

    The positions go to PINT's ``spacecraft`` observatory as geocentric offsets (km) from
    PINT's own DE421 Earth; PINT adds them back to that Earth, so it evaluates its delays
    at the positions given (to rounding, returned as ``r_ssb``). One timing model per
    pulsar: the direction ``n`` (RAJ/DECJ, no proper motion) and the parallax
    ``PX = 1 / distance``.

    Parameters
    ----------
    r_sc_ssb : array_like, shape (3,) or (m, 3)
        Spacecraft positions relative to the SSB, ICRF axes, m.
    t : float or array_like, shape (m,)
        Epochs, s TDB past J2000.
    n : array_like, shape (k, 3)
        Unit vectors to the pulsars, ICRF.
    distance : array_like, shape (k,), optional
        Pulsar distances, m; without them there is no ``parallax`` (PINT's PX = 0).
    planets : bool
        Also return the planets' Shapiro delays (PINT's ``PLANET_SHAPIRO``).

    Returns
    -------
    dict of ndarray
        With our sign (the time by which the pulse reaches the spacecraft before the
        SSB), s, shape (m, k) (or (k,) for a single position):

        - ``roemer``: PINT's geometric delay with ``PX = 0``, to compare with
          :func:`xnavlab.mars.timing.toa.roemer`;
        - ``parallax``: PINT's geometric delay with the parallax minus the one without
          (only with ``distance``), to compare with :func:`xnavlab.mars.timing.toa.parallax`;
        - ``shapiro``: PINT's solar Shapiro delay, referred to 1 au (see
          :func:`xnavlab.mars.timing.toa.shapiro_offset_to_pint`);
        - ``shapiro_<planet>`` for each of :data:`PLANETS` (with ``planets``),
          referred to 1 au like the Sun's;

        and the geometry PINT used, m, shape (m, 3) (or (3,)): ``r_ssb`` (the spacecraft)
        and ``r_sun_ssb`` (the Sun), both relative to the SSB.

    Examples
    --------
    >>> from xnavlab.mars.timing import pulsars
    >>> n, d = pulsars.directions()
    >>> r = np.array([2.0e11, 1.0e11, 3.0e10])
    >>> out = pint_delays(r, 5.0e8, n, d)
    >>> out["roemer"].shape, sorted(out)
    ((4,), ['parallax', 'r_ssb', 'r_sun_ssb', 'roemer', 'shapiro'])
    >>> bool(np.abs(out["roemer"] - n @ r / 299792458.0).max() < 1e-11)   # n . R / c
    True
    """
    planets = check_bool("planets", planets)
    r = check_finite_array("r_sc_ssb", r_sc_ssb, shape=(3,))
    single = r.ndim == 1
    r = np.atleast_2d(r)
    if r.ndim != 2:
        raise ValueError(f"r_sc_ssb must have shape (3,) or (m, 3), got {r.shape}")
    if np.any(r == 0.0):
        # PINT takes a position with any zero component for the barycentre (no geometric delay)
        raise ValueError("r_sc_ssb must have no component exactly 0 (PINT reads such a position as "
                         "the barycentre)")
    t = _checks.check_epochs("t", t)
    if t.ndim > 1 or (t.ndim == 1 and t.size != r.shape[0]):
        raise ValueError(f"t must be a scalar or have shape ({r.shape[0]},), got {t.shape}")
    lo, hi = ephemeris.coverage(EPHEMERIS)
    if t.size and (t.min() < lo or t.max() > hi):  # PINT's words name no parameter
        raise ValueError(f"t must lie in {dates.epoch_range(lo, hi)}, the coverage of "
                         f"{EPHEMERIS.upper()} (PINT's ephemeris here); got "
                         f"[{dates.epoch_text(t.min())}, {dates.epoch_text(t.max())}]")
    n = check_finite_array("n", n, shape=(3,))
    if n.ndim != 2:
        raise ValueError(f"n must hold unit vectors with shape (k, 3), got shape {n.shape}")
    norms = np.linalg.norm(n, axis=1)
    if np.any(np.abs(norms - 1.0) > 1e-9):
        k = int(np.argmax(np.abs(norms - 1.0)))
        raise ValueError(f"n must hold unit vectors, but n[{k}] has norm {norms[k]:.6g}")
    if distance is not None:
        distance = check_finite_array("distance", distance)
        if distance.shape != (n.shape[0],) or np.any(distance <= 0):
            raise ValueError(f"distance must be positive with shape ({n.shape[0]},), got {distance.shape}")
    planets = bool(planets)
    offline()
    import astropy.units as u
    import pint

    with _quiet():
        toas = _spacecraft_toas(r, t, planets)
        model = _direction_model()
        astrometry = model.components["AstrometryEquatorial"]
        shapiro = model.components["SolarSystemShapiro"]
        tbl = toas.table
        out = {key: np.empty((r.shape[0], n.shape[0]))
               for key in ("roemer", "shapiro") + (("parallax",) if distance is not None else ())
               + tuple(f"shapiro_{p}" for p in PLANETS if planets)}
        tdb = np.asarray(tbl["tdbld"], dtype=float)
        for k, nk in enumerate(n):
            model.RAJ.quantity = np.arctan2(nk[1], nk[0]) % (2 * np.pi) * u.rad
            model.DECJ.quantity = np.arcsin(np.clip(nk[2], -1.0, 1.0)) * u.rad
            model.PX.value = 0.0
            geometric = astrometry.solar_system_geometric_delay(toas).to_value(u.s)
            out["roemer"][:, k] = -geometric  # PINT: -n.R/c; ours: +n.R/c
            if distance is not None:
                model.PX.value = KPC / distance[k]  # mas: PX (mas) = 1 / D (kpc)
                with_px = astrometry.solar_system_geometric_delay(toas).to_value(u.s)
                out["parallax"][:, k] = -(with_px - geometric)
            psr_dir = astrometry.ssb_to_psb_xyz_ICRS(epoch=tdb)
            out["shapiro"][:, k] = -shapiro.ss_obj_shapiro_delay(tbl["obs_sun_pos"], psr_dir, pint.Tsun.value)
            for p in PLANETS if planets else ():
                mass = getattr(pint, f"T{p}").value  # GM/c^3, s
                out[f"shapiro_{p}"][:, k] = -shapiro.ss_obj_shapiro_delay(tbl[f"obs_{p}_pos"], psr_dir, mass)
        r_used = tbl["ssb_obs_pos"].quantity.to_value(u.m)
        out["r_ssb"] = r_used
        out["r_sun_ssb"] = r_used + tbl["obs_sun_pos"].quantity.to_value(u.m)
    if single:
        out = {key: value[0] for key, value in out.items()}
    return out


def planet_shapiro(r_sc_ssb, t, n):
    """The planets' Shapiro delays for a spacecraft, from PINT (:func:`pint_delays`).

    Parameters
    ----------
    r_sc_ssb : array_like, shape (3,) or (m, 3)
        Spacecraft positions relative to the SSB, m.
    t : float or array_like, shape (m,)
        Epochs, s TDB past J2000.
    n : array_like, shape (k, 3)
        Unit vectors to the pulsars.

    Returns
    -------
    dict of ndarray
        One entry per planet of :data:`PLANETS` and their sum ``total``, s, shape (m, k)
        (or (k,)): with our sign and PINT's reference (each planet's
        ``2 GM/c^3 ln[(|x| + n.x) / 1 au]``, ``x`` the spacecraft from the planet).

    Examples
    --------
    >>> from xnavlab.mars.timing import pulsars
    >>> n, _ = pulsars.directions()
    >>> sorted(planet_shapiro([2.0e11, 1.0e11, 3.0e10], 5.0e8, n))
    ['jupiter', 'neptune', 'saturn', 'total', 'uranus', 'venus']
    """
    out = pint_delays(r_sc_ssb, t, n, planets=True)
    planets = {p: out[f"shapiro_{p}"] for p in PLANETS}
    planets["total"] = sum(planets.values())
    return planets


# ------------------------------------------------------------------ shipped data sets


def _cache_file(kind, sources):
    """Path of a disk cache entry: keyed by the shipped files (names and sizes), this module's
    code and PINT's version (:func:`xnavlab.core.diskcache.entry_path`)."""
    files = tuple((path.name, path.stat().st_size) for path in sources)
    return entry_path(f"pint-{kind}", files, (), (__name__,), versions=("pint-pulsar",))


def _cached(kind, sources, compute):
    """``compute()`` (a dict of arrays; run offline, PINT's warnings filtered), stored on disk."""
    def offline_compute():
        offline()
        with _quiet():
            return compute()

    return cached_arrays(_cache_file(kind, sources), offline_compute)


def _read_gauss_template(path):
    """The ``phasN``/``fwhmN``/``amplN`` lines of a pygaussfit template: (c, 3) array."""
    values = {}
    for line in path.read_text().splitlines():
        parts = line.split("=")
        if len(parts) == 2 and parts[0].strip()[:4] in ("phas", "fwhm", "ampl"):
            key = parts[0].strip()
            values[key] = float(parts[1].split("+/-")[0])
    count = sum(1 for key in values if key.startswith("phas"))
    return np.array([[values[f"{name}{i}"] for name in ("phas", "fwhm", "ampl")]
                     for i in range(1, count + 1)])


def _fermi():
    from astropy import units as u
    from pint.fermi_toas import get_Fermi_TOAs
    from pint.models import get_model

    events = examples_path(_FERMI_EVENTS)
    model = get_model(str(examples_path(_FERMI_PAR)))
    with open(events, "rb") as fh:  # PINT leaves the file it opens itself open
        toas = get_Fermi_TOAs(fh, weightcolumn="PSRJ0030+0451", include_bipm=False,
                              ephem=EPHEMERIS, planets=False)
    phase = model.phase(toas, abs_phase=False)
    return {
        "phases": np.asarray(phase.frac.to_value(u.dimensionless_unscaled), dtype=float) % 1.0,
        "weights": np.asarray(toas.get_flag_value("weight", as_type=float)[0], dtype=float),
        "mjd_tt": np.asarray(toas.get_mjds().to_value(u.d), dtype=float),
        "f0": np.array(model.F0.value, dtype=float),
    }


@functools.cache
def _fermi_cached():
    sources = [examples_path(name) for name in (_FERMI_EVENTS, _FERMI_PAR)]
    return _cached("fermi-j0030", sources, _fermi)


def fermi_photon_phases():
    """Phases and weights of the Fermi-LAT photons of PSR J0030+0451 shipped with PINT.

    The photons (``J0030+0451_P8_15.0deg_..._GEO_wt.gt.0.4.fits``: geocentred event times,
    TT, each with the probability that it comes from the pulsar, all above 0.4) are read
    with ``pint.fermi_toas.get_Fermi_TOAs`` (DE421, no BIPM correction) and phased with
    the shipped ATNF model ``PSRJ0030+0451_psrcat.par``: ``model.phase(toas,
    abs_phase=False)`` takes each photon from the geocentre to the SSB (Roemer, Einstein
    and solar Shapiro delays) and through the spin-down. Cached in memory and on disk
    (``$XNAVLAB_CACHE``); the first call takes about ten seconds.

    Returns
    -------
    phases : ndarray, shape (n,)
        Pulse phases, cycles in [0, 1).
    weights : ndarray, shape (n,)
        Photon weights, in (0.4, 1].
    meta : dict
        ``mjd_tt`` (n,) photon MJDs (TT, geocentre), ``f0`` the spin frequency (Hz),
        ``template`` (3, 3) the shipped three-Gaussian template (rows: phase in cycles,
        FWHM in cycles, amplitude; see :func:`fermi_template`), ``events`` and ``par``
        the file names.

    Examples
    --------
    >>> phases, weights, meta = fermi_photon_phases()  # doctest: +SKIP
    >>> phases.shape == weights.shape, meta["template"].shape  # doctest: +SKIP
    (True, (3, 3))
    """
    data = _fermi_cached()
    meta = {"mjd_tt": data["mjd_tt"].copy(), "f0": float(data["f0"]),
            "template": _read_gauss_template(examples_path(_FERMI_TEMPLATE)),
            "events": _FERMI_EVENTS, "par": _FERMI_PAR}
    return data["phases"].copy(), data["weights"].copy(), meta


def fermi_template(nbins=None, phases=None):
    """The three-Gaussian template of J0030+0451 shipped with PINT (``templateJ0030.3gauss``).

    A sum of wrapped Gaussians, ``sum_i a_i N(phi; phi_i, FWHM_i)``, whose amplitudes add
    up to 1: a density per cycle whose integral over a cycle is 1 (the photons' phases of
    :func:`fermi_photon_phases` follow ``w * template + (1 - w)`` for a photon of weight
    ``w``).

    Parameters
    ----------
    nbins : int, optional
        Return the fraction of the template in each of ``nbins`` equal phase bins (exact
        integrals; sums to 1), the form :func:`xnavlab.mars.timing.pulsars.estimate_phase_shift`
        takes.
    phases : array_like, optional
        Instead, evaluate the density (per cycle) at these phases.

    Returns
    -------
    ndarray, shape (nbins,) or the shape of ``phases``

    Examples
    --------
    >>> round(float(fermi_template(nbins=64).sum()), 12)
    1.0
    >>> int(fermi_template(nbins=64).argmax())   # the narrow peak near phase 0.61
    38
    """
    from scipy.special import erf

    if (nbins is None) == (phases is None):
        raise ValueError("give exactly one of nbins and phases")
    comps = _read_gauss_template(examples_path(_FERMI_TEMPLATE))
    sigma = comps[:, 1] / (2.0 * np.sqrt(2.0 * np.log(2.0)))  # FWHM -> sigma, cycles
    shifts = np.arange(-3, 4)  # wrap: the widest component has sigma 0.15 cycle
    if phases is not None:
        x = check_finite_array("phases", phases)
        d = x[..., None, None] - comps[:, 0][:, None] + shifts  # (..., c, wraps)
        g = np.exp(-0.5 * (d / sigma[:, None]) ** 2) / (sigma[:, None] * np.sqrt(2.0 * np.pi))
        return np.sum(comps[:, 2] * g.sum(axis=-1), axis=-1)
    nbins = check_int("nbins", nbins, 8, 2**20)
    edges = np.linspace(0.0, 1.0, nbins + 1)
    z = (edges[:, None, None] - comps[:, 0][:, None] + shifts) / (sigma[:, None] * np.sqrt(2.0))
    cdf = 0.5 * erf(z).sum(axis=-1)  # (nbins + 1, c): wrapped CDF up to a constant
    per_bin = np.diff(cdf, axis=0) @ comps[:, 2]
    return per_bin / per_bin.sum()


@functools.cache
def _fermi_toas():
    """PINT's TOAs of the Fermi photons and the shipped model, read once per process (~17 s)."""
    from pint.fermi_toas import get_Fermi_TOAs
    from pint.models import get_model

    offline()
    with _quiet():
        model = get_model(str(examples_path(_FERMI_PAR)))
        with open(examples_path(_FERMI_EVENTS), "rb") as fh:
            toas = get_Fermi_TOAs(fh, weightcolumn="PSRJ0030+0451", include_bipm=False,
                                  ephem=EPHEMERIS, planets=False)
    return toas, model


def _fermi_geometry():
    from astropy import units as u

    toas, model = _fermi_toas()
    tbl = toas.table
    tdb = np.asarray(tbl["tdbld"], dtype=float)  # MJD TDB
    n = model.components["AstrometryEquatorial"].ssb_to_psb_xyz_ICRS(epoch=tdb)
    spin = model.F0.value + model.F1.value * (tdb - float(model.PEPOCH.value)) * DAY
    return {
        "r_geo_ssb": np.asarray(tbl["ssb_obs_pos"].quantity.to_value(u.m), dtype=float),
        "direction": np.asarray(n, dtype=float),
        "spin_frequency": np.asarray(spin, dtype=float),
        "t": (tdb - _MJD_J2000) * DAY,
    }


@functools.cache
def _fermi_geometry_cached():
    sources = [examples_path(name) for name in (_FERMI_EVENTS, _FERMI_PAR)]
    return _cached("fermi-j0030-geometry", sources, _fermi_geometry)


def fermi_photon_geometry():
    """Where PINT put the geocentre and the pulsar for each Fermi photon of J0030+0451.

    The same photons, in the same order, as :func:`fermi_photon_phases` (read the same
    way, DE421, no BIPM correction). Cached in memory and on disk (``$XNAVLAB_CACHE``);
    the first call reads the photons with PINT (about twenty seconds).

    Returns
    -------
    dict of ndarray
        - ``r_geo_ssb`` (n, 3): the geocentre relative to the SSB at each photon, ICRF
          axes, m (PINT's ``ssb_obs_pos``: the photon times are referred to the geocentre);
        - ``direction`` (n, 3): the unit vector from the SSB to the pulsar at each photon,
          ICRF (PINT's ``ssb_to_psb_xyz_ICRS``, proper motion applied);
        - ``spin_frequency`` (n,): the model's spin frequency at each photon,
          ``F0 + F1 (t - PEPOCH)``, Hz;
        - ``t`` (n,): the photon epochs, s TDB past J2000.

    Examples
    --------
    >>> geo = fermi_photon_geometry()  # doctest: +SKIP
    >>> geo["direction"].shape == geo["r_geo_ssb"].shape  # doctest: +SKIP
    True
    """
    return {key: value.copy() for key, value in _fermi_geometry_cached().items()}


def fermi_displaced_phases(offsets_m):
    """PINT's phases of the Fermi photons of J0030+0451 with the geocentre moved.

    For each offset ``dr``, every photon's observatory position (PINT's ``ssb_obs_pos``,
    the geocentre) is moved by ``dr`` and its position relative to the Sun
    (``obs_sun_pos``) by ``-dr``; PINT's ``model.phase`` then phases the photons as
    :func:`fermi_photon_phases` does, so the difference is PINT's own answer to "what if
    the photons had been recorded ``dr`` away from the geocentre" (its Roemer and solar
    Shapiro delays both see the move). Cached on disk per set of offsets.

    Parameters
    ----------
    offsets_m : array_like, shape (k, 3)
        Offsets of the assumed geocentre, ICRF axes, m.

    Returns
    -------
    ndarray, shape (k, n)
        Pulse phases, cycles in [0, 1), the photons in the order of
        :func:`fermi_photon_phases`.

    Examples
    --------
    >>> phases = fermi_displaced_phases([[0.0, 0.0, 0.0]])  # doctest: +SKIP
    >>> bool(np.allclose(phases[0], fermi_photon_phases()[0]))  # doctest: +SKIP
    True
    """
    offsets = check_finite_array("offsets_m", offsets_m, shape=(3,))
    if offsets.ndim != 2:
        raise ValueError(f"offsets_m must have shape (k, 3), got {offsets.shape}")

    def compute():
        from astropy import units as u

        toas, model = _fermi_toas()
        tbl = toas.table
        saved = tbl["ssb_obs_pos"].quantity.copy(), tbl["obs_sun_pos"].quantity.copy()
        out = np.empty((offsets.shape[0], len(tbl)))
        try:
            for k, dr in enumerate(offsets):
                tbl["ssb_obs_pos"] = saved[0] + dr * u.m
                tbl["obs_sun_pos"] = saved[1] - dr * u.m
                phase = model.phase(toas, abs_phase=False)
                out[k] = np.asarray(phase.frac.to_value(u.dimensionless_unscaled), dtype=float) % 1.0
        finally:
            tbl["ssb_obs_pos"], tbl["obs_sun_pos"] = saved
        return {"phases": out}

    key = hashlib.sha256(np.ascontiguousarray(offsets).tobytes()).hexdigest()[:16]
    sources = [examples_path(name) for name in (_FERMI_EVENTS, _FERMI_PAR)]
    return _cached(f"fermi-j0030-displaced-{key}", sources, compute)["phases"].copy()


@contextlib.contextmanager
def _without_clock_files(site_name):
    """No observatory or GPS clock files for one site while inside (``-to`` offsets stay)."""
    from pint.observatory import get_observatory

    site = get_observatory(site_name)
    saved = (site.clock_files, site._clock, site.apply_gps2utc)
    site.clock_files, site._clock, site.apply_gps2utc = [], [], False
    try:
        yield
    finally:
        site.clock_files, site._clock, site.apply_gps2utc = saved


def _nanograv():
    from astropy import units as u
    from pint.models import get_model
    from pint.residuals import Residuals
    from pint.toa import get_TOAs

    model = get_model(str(examples_path(_NANOGRAV_PAR)))
    with _without_clock_files("arecibo"):
        toas = get_TOAs(str(examples_path(_NANOGRAV_TIM)), model=model, include_bipm=False,
                        ephem=EPHEMERIS, planets=False)
        res = Residuals(toas, model)
        resid = res.time_resids.to_value(u.s)
        error = res.get_data_error(scaled=True).to_value(u.s)
    return {"t_mjd": np.asarray(toas.get_mjds().to_value(u.d), dtype=float),
            "residual_s": np.asarray(resid, dtype=float), "error_s": np.asarray(error, dtype=float)}


@functools.cache
def _nanograv_cached():
    sources = [examples_path(name) for name in (_NANOGRAV_PAR, _NANOGRAV_TIM)]
    return _cached("nanograv-b1855", sources, _nanograv)


def nanograv_residuals():
    """Timing residuals of PSR B1855+09 from the NANOGrav 9-year data shipped with PINT.

    The 4005 Arecibo TOAs of ``B1855+09_NANOGrav_9yv1.tim`` against the published timing
    model ``B1855+09_NANOGrav_9yv1.gls.par`` (no re-fit), from ``pint.residuals.Residuals``:
    the pulse phase of each TOA to the nearest pulse, times the period, weighted mean
    removed. Offline means without clock files: the residuals lack the Arecibo observatory
    clock, GPS-to-UTC and TT(BIPM) corrections (the ``-to`` offsets of the ``.tim`` file
    are applied); these are slow and mostly absorbed by the fitted spin and DMX
    parameters, but their remainder is part of what is left. The model's red noise and
    ECORR are not subtracted. Cached in memory and on disk; the first call takes about
    ten seconds.

    Returns
    -------
    t_mjd : ndarray, shape (4005,)
        TOA epochs, MJD (UTC at the observatory, as in the ``.tim`` file).
    residual_s : ndarray, shape (4005,)
        Residuals, s.
    error_s : ndarray, shape (4005,)
        TOA uncertainties scaled by the model's EFAC and EQUAD, s.

    Examples
    --------
    >>> t_mjd, residual_s, error_s = nanograv_residuals()  # doctest: +SKIP
    >>> t_mjd.shape  # doctest: +SKIP
    (4005,)
    """
    data = _nanograv_cached()
    return data["t_mjd"].copy(), data["residual_s"].copy(), data["error_s"].copy()


def timing_parameters(path):
    """Position, parallax and spin of a pulsar from a PINT timing model (a ``.par`` file).

    The position is PINT's ICRS position at the model's position epoch (``POSEPOCH``, or
    ``PEPOCH`` without one; proper motion is not applied): equatorial models give their
    ``RAJ``/``DECJ``, ecliptic ones (``ELONG``/``ELAT`` or ``LAMBDA``/``BETA``) are turned
    to ICRS by PINT with the model's obliquity (``ECL``).

    Parameters
    ----------
    path : str or pathlib.Path
        The ``.par`` file.

    Returns
    -------
    dict
        ``name`` (str), ``ra_deg`` and ``dec_deg`` (ICRS, degrees), ``px_mas`` (parallax,
        mas; ``None`` when the model has none or it is not positive), ``f0`` (Hz), ``f1``
        (Hz/s, 0 without ``F1``), ``pepoch_mjd`` and ``posepoch_mjd`` (MJD TDB, ``None``
        when absent) and ``frame`` (``"equatorial"`` or ``"ecliptic"``).

    Examples
    --------
    >>> par = timing_parameters(examples_path("B1855+09_NANOGrav_9yv1.gls.par"))
    >>> par["name"], par["frame"], round(par["f0"], 6), par["px_mas"]
    ('B1855+09', 'ecliptic', 186.494081, 0.2929)
    """
    if not isinstance(path, str | os.PathLike):
        raise ValueError(f"path must name an existing .par file (a str or Path), got {shown(path)}")
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"path must name an existing .par file, got {str(path)!r}")
    offline()
    import astropy.units as u
    from pint.models import get_model

    try:
        with _quiet():
            model = get_model(str(path))
            icrs = model.coords_as_ICRS()
    except UnicodeDecodeError as exc:  # the file named, as every file's error
        raise ValueError(f"path: the timing model {str(path)!r} is not UTF-8 text (byte "
                         f"{exc.object[exc.start]:#04x} at position {exc.start})") from None
    except Exception as exc:  # astropy's or PINT's own errors on a malformed model: one line
        why = (str(exc).strip().splitlines() or [""])[0]
        kind = "" if isinstance(exc, ValueError) else f"{type(exc).__name__}: "
        raise ValueError(f"path: PINT cannot read the timing model {str(path)!r} ({kind}{why})") \
            from None
    frame = "equatorial" if "AstrometryEquatorial" in model.components else "ecliptic"

    def mjd(name):
        par = getattr(model, name, None)
        return None if par is None or par.value is None else float(par.value)

    px = getattr(model, "PX", None)
    px = None if px is None or px.value is None or not float(px.value) > 0 else float(px.value)
    f1 = getattr(model, "F1", None)
    return {
        "name": str(model.PSR.value),
        "ra_deg": float(icrs.ra.to_value(u.deg)),
        "dec_deg": float(icrs.dec.to_value(u.deg)),
        "px_mas": px,
        "f0": float(model.F0.value),
        "f1": 0.0 if f1 is None or f1.value is None else float(f1.value),
        "pepoch_mjd": mjd("PEPOCH"),
        "posepoch_mjd": mjd("POSEPOCH"),
        "frame": frame,
    }
