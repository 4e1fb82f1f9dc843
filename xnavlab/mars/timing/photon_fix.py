"""A one-dimensional position fix from real photons: the geocentre along the line to J0030+0451.

The Fermi-LAT photons of PSR J0030+0451 that ship with PINT (:mod:`xnavlab.mars.timing.pint_bridge`)
are time-tagged and referred to the geocentre, whose position PINT takes from DE421. Treat the
geocentre as the spacecraft: if the position assumed for it is off by ``dr`` (m, ICRF axes),
every photon's Roemer delay ``n . R / c`` (chapter 2's sign: the arrival time at the SSB minus
the arrival time at the spacecraft) is off by ``n . dr / c``, and its pulse phase by

    ``dphi_i = f_i n_i . dr / c``                         (cycles; eq. ch01-photon-dphi)

with ``n_i`` the unit vector to the pulsar and ``f_i`` its spin frequency at photon ``i``
(both PINT's). The fold slides by that much against a template, and the slide, measured by
maximum likelihood, estimates ``n . dr``: a fix along the line to the pulsar. An offset
across the line moves nothing; one of ``c P`` (about 1,459 km) moves the fold by exactly one
cycle and is invisible too (the cycle ambiguity).

The steps, each a function:

1. :func:`fermi_photons`: the photons, their weights, and PINT's geometry (:class:`Photons`).
2. :func:`split_months`: alternate months make the **reference** part and the **navigation**
   part, so the fix never uses the photons its template came from.
3. :func:`build_reference` (reference part only): the timing model's corrections (spin
   frequency and pulsar direction, which the shipped catalogue model gets slightly wrong,
   chapter 1's timing equation) and a smoothed template of the pulse (a kernel estimate of the
   weighted fold), with the covariance of the corrections (:class:`Reference`).
4. :func:`estimate_offset` (navigation part): the offset that maximises the photons'
   likelihood (eq. ch01-photon-like) and its photon noise (eq. ch01-photon-sigma);
   :func:`fix` adds the reference's uncertainty (eq. ch01-photon-total).
5. :mod:`xnavlab.mars.timing.photon_error`: the error bar against exposure, beside chapter 1's
   formula, and checked over random splits.

Units: metres, seconds, cycles (phases), Hz; vectors in ICRF axes; times in s TDB past J2000.
PINT runs only when the disk cache of :mod:`xnavlab.mars.timing.pint_bridge` is empty. The figures
are in :mod:`xnavlab.mars.timing.photon_plots`.

Examples
--------
>>> round(MONTH / DAY, 4)
30.4375
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from xnavlab.core.constants import DAY, C
from xnavlab.core.validate import (
    check_finite_array,
    check_instance,
    check_int,
    check_real,
    check_shape,
    make_rng,
    shown,
)
from xnavlab.mars.timing import pint_bridge

__all__ = [
    "MONTH",
    "Photons",
    "Reference",
    "Fix",
    "fermi_photons",
    "cycle_length",
    "offset_vector",
    "displaced_phases",
    "pint_witness",
    "split_months",
    "template_density",
    "build_reference",
    "estimate_offset",
    "log_likelihood",
    "likelihood_scan",
    "fix",
]

#: One month, s (a twelfth of a Julian year): the unit the photons are split and counted in.
MONTH = 365.25 * DAY / 12.0

_TABLE = 1 << 14  # points of the template tables over one cycle (6e-5 cycle, 0.3 us apart)
_WEIGHT_GRID = np.linspace(0.0, 1.0, 101)  # weights at which the Fisher information is tabulated
_FLOOR = 0.01  # the template density is kept above this (per cycle; its mean is 1)


def _photons(photons, name="photons"):
    """``photons`` if it is a :class:`Photons`, else one ValueError naming it."""
    return check_instance(name, photons, Photons, "a Photons (from fermi_photons())")


def _reference(reference):
    """``reference`` if it is a :class:`Reference`, else one ValueError naming it."""
    return check_instance("reference", reference, Reference, "a Reference (from build_reference())")


def _phases(photons, phases):
    """``phases`` (None, or one finite phase per photon) checked under the user's name."""
    if phases is None:
        return None
    return check_shape("phases", phases, (photons.size,), "one phase per photon")


@dataclass(frozen=True, eq=False)
class Photons:
    """The Fermi-LAT photons of PSR J0030+0451 with the geometry PINT gave them.

    Attributes
    ----------
    phases : ndarray, shape (n,)
        PINT's pulse phases with the photons at the geocentre, cycles in [0, 1).
    weights : ndarray, shape (n,)
        Probability that each photon comes from the pulsar, in (0.4, 1].
    t : ndarray, shape (n,)
        Photon epochs, s TDB past J2000.
    direction : ndarray, shape (n, 3)
        Unit vector from the SSB to the pulsar at each photon, ICRF.
    r_geo_ssb : ndarray, shape (n, 3)
        The geocentre relative to the SSB at each photon, ICRF axes, m.
    spin_frequency : ndarray, shape (n,)
        The timing model's spin frequency at each photon, Hz.
    components : ndarray, shape (c, 3)
        The shipped three-Gaussian template (rows: phase, FWHM in cycles, amplitude), used
        only by the signal-to-noise formula (:func:`~xnavlab.mars.timing.photon_error.snr_range_sigma`).
    t_first : float, optional
        Start of month 0, s TDB past J2000 (default the first photon); a subset keeps its
        parent's, so months are counted alike.
    """

    phases: np.ndarray
    weights: np.ndarray
    t: np.ndarray
    direction: np.ndarray
    r_geo_ssb: np.ndarray
    spin_frequency: np.ndarray
    components: np.ndarray
    t_first: float | None = None

    @property
    def size(self):
        """Number of photons."""
        return int(self.phases.size)

    @property
    def mean_direction(self):
        """The photons' mean pulsar direction, a unit vector, ICRF, shape (3,)."""
        n = self.direction.mean(axis=0)
        return n / np.linalg.norm(n)

    @property
    def month(self):
        """Month of each photon since the first one (0, 1, ...), int, shape (n,)."""
        return np.floor((self.t - self.start) / MONTH).astype(int)

    @property
    def start(self):
        """Start of month 0, s TDB past J2000."""
        return float(self.t.min()) if self.t_first is None else float(self.t_first)

    def subset(self, mask):
        """The photons selected by a boolean mask (or index array), as a new :class:`Photons`."""
        return Photons(self.phases[mask], self.weights[mask], self.t[mask], self.direction[mask],
                       self.r_geo_ssb[mask], self.spin_frequency[mask], self.components, self.start)

@dataclass(frozen=True, eq=False)
class Reference:
    """What the reference photons provide: timing-model corrections and a template.

    Attributes
    ----------
    coeffs : ndarray, shape (K,), complex
        Fourier coefficients ``a_k`` (k = 1..K) of the template density
        ``f(phi) = 1 + 2 Re sum_k a_k exp(2 pi i k phi)`` (per cycle, mean 1).
    theta : ndarray, shape (4,)
        Corrections to the timing model: phase offset (cycles), spin frequency (Hz), and the
        pulsar direction's error east and north on the sky (rad); see :meth:`correction`.
    cov : ndarray, shape (4, 4)
        Their covariance, from the reference photons' Fisher information.
    t_ref : float
        Reference epoch of the spin-frequency term, s TDB past J2000.
    east, north : ndarray, shape (3,)
        Unit vectors on the sky at the pulsar, ICRF (the directions of the direction error).
    in_reference : ndarray of bool, shape (n,)
        Which photons built it.
    bandwidth : float
        The template's smoothing (Gaussian kernel sigma), cycles.
    """

    coeffs: np.ndarray
    theta: np.ndarray
    cov: np.ndarray
    t_ref: float
    east: np.ndarray
    north: np.ndarray
    in_reference: np.ndarray
    bandwidth: float

    def regressors(self, photons):
        """Phase change per unit of each correction, shape (n, 4): ``[1, t - t_ref, f e.R/c, f u.R/c]``."""
        fr = photons.spin_frequency[:, None] * photons.r_geo_ssb / C
        return np.column_stack([np.ones(photons.size), photons.t - self.t_ref,
                                fr @ self.east, fr @ self.north])

    def correction(self, photons):
        """The phase correction of each photon, cycles, shape (n,) (chapter 1's timing equation)."""
        return self.regressors(photons) @ self.theta  # phi0 + df (t - t_ref) + f dn . R / c

    def corrected(self, photons, phases=None):
        """``phases`` (default the photons' own) minus :meth:`correction`, cycles in [0, 1)."""
        phases = photons.phases if phases is None else phases
        return (phases - self.correction(photons)) % 1.0


@dataclass(frozen=True)
class Fix:
    """A fix along the line to the pulsar (:func:`fix`).

    Attributes
    ----------
    along_m : float
        Estimated offset of the assumed position along the mean pulsar direction, m,
        in [-cP/2, cP/2).
    sigma_m : float
        Its standard deviation, m: the three parts below together (eq. ch01-photon-total).
    sigma_photons_m : float
        The navigation photons' part, m (eq. ch01-photon-sigma).
    sigma_template_m : float
        The template's part, m: the reference photons' noise.
    sigma_timing_m : float
        The timing corrections' part, m (their spin frequency and direction).
    truth_along_m : float
        The injected offset's component along the mean direction, m (not wrapped).
    cycle_m : float
        The cycle length ``c P``, m.
    n_photons : int
        Navigation photons used.
    weight_sum : float
        Their weights' sum (the expected number from the pulsar).
    """

    along_m: float
    sigma_m: float
    sigma_photons_m: float
    sigma_template_m: float
    sigma_timing_m: float
    truth_along_m: float
    cycle_m: float
    n_photons: int
    weight_sum: float

    @property
    def wrapped_truth_m(self):
        """The injected offset as one pulsar sees it: wrapped into [-cP/2, cP/2), m."""
        return (self.truth_along_m + 0.5 * self.cycle_m) % self.cycle_m - 0.5 * self.cycle_m

    @property
    def error_m(self):
        """Estimate minus the wrapped truth, m."""
        return self.along_m - self.wrapped_truth_m


# ------------------------------------------------------------------ photons and geometry


def fermi_photons():
    """The Fermi-LAT photons of PSR J0030+0451 shipped with PINT, with PINT's geometry.

    Phases and weights from :func:`xnavlab.mars.timing.pint_bridge.fermi_photon_phases`, geometry
    from :func:`xnavlab.mars.timing.pint_bridge.fermi_photon_geometry` (both cached on disk; PINT
    runs only when the cache is empty).

    Returns
    -------
    Photons

    Examples
    --------
    >>> photons = fermi_photons()   # doctest: +SKIP
    >>> photons.size, round(cycle_length(photons) / 1e3)   # doctest: +SKIP
    (6973, 1459)
    """
    phases, weights, meta = pint_bridge.fermi_photon_phases()
    geo = pint_bridge.fermi_photon_geometry()
    return Photons(phases, weights, geo["t"], geo["direction"], geo["r_geo_ssb"],
                   geo["spin_frequency"], meta["template"])


def cycle_length(photons):
    """The cycle ambiguity ``c P = c / f``, m: an offset along the line that one pulsar cannot see.

    Examples
    --------
    >>> fake = Photons(*(np.zeros(1),) * 3, np.zeros((1, 3)), np.zeros((1, 3)),
    ...                np.array([205.530699]), np.zeros((3, 3)))
    >>> round(cycle_length(fake) / 1e3, 1)   # km, J0030+0451 (P = 4.87 ms)
    1458.6
    """
    return C / float(np.mean(_photons(photons).spin_frequency))


def offset_vector(photons, along_m=0.0, across_m=0.0):
    """An offset of the assumed position: ``along_m`` along the pulsar, ``across_m`` across it.

    Parameters
    ----------
    photons : Photons
    along_m, across_m : float
        Components, m: along the mean pulsar direction, and along the sky's east at the
        pulsar (perpendicular to it).

    Returns
    -------
    ndarray, shape (3,)
        The offset, ICRF axes, m.

    Examples
    --------
    >>> fake = Photons(*(np.zeros(1),) * 3, np.array([[0.0, 0.6, 0.8]]), np.zeros((1, 3)),
    ...                np.ones(1), np.zeros((3, 3)))
    >>> offset_vector(fake, along_m=10.0, across_m=5.0).round(3).tolist()
    [-5.0, 6.0, 8.0]
    """
    photons = _photons(photons)
    along_m = check_real("along_m", along_m)
    across_m = check_real("across_m", across_m)
    n = photons.mean_direction
    east, _ = _sky_axes(n)
    return along_m * n + across_m * east


def _sky_axes(n):
    """East and north unit vectors on the sky at direction ``n`` (ICRF)."""
    east = np.cross([0.0, 0.0, 1.0], n)
    east /= np.linalg.norm(east)
    return east, np.cross(n, east)


def displaced_phases(photons, offset_m):
    """The photons' phases had their position been assumed ``offset_m`` away, cycles in [0, 1).

    Moving the assumed position by ``dr`` changes each photon's Roemer delay by
    ``n_i . dr / c`` and so its phase by ``f_i n_i . dr / c`` (eq. ch01-photon-dphi), with
    PINT's own direction ``n_i`` and spin frequency ``f_i`` at that photon. Agrees with
    PINT's phases for a geocentre moved by 500 km to 1e-6 cycle
    (:func:`xnavlab.mars.timing.pint_bridge.fermi_displaced_phases`; the remainder is the solar
    Shapiro delay, which this leaves out).

    Parameters
    ----------
    photons : Photons
    offset_m : array_like, shape (3,)
        The offset of the assumed position, ICRF axes, m.

    Returns
    -------
    ndarray, shape (n,)

    Examples
    --------
    >>> fake = Photons(np.array([0.25]), np.ones(1), np.zeros(1), np.array([[1.0, 0, 0]]),
    ...                np.zeros((1, 3)), np.array([200.0]), np.zeros((3, 3)))
    >>> displaced_phases(fake, [C / 800.0, 5e5, 0.0]).tolist()   # a quarter cycle along x
    [0.5]
    """
    photons = _photons(photons)
    dr = check_finite_array("offset_m", offset_m, shape=(3,))
    if dr.ndim != 1:
        raise ValueError(f"offset_m must have shape (3,), got {dr.shape}")
    shift = photons.spin_frequency * (photons.direction @ dr) / C  # eq. (ch01-photon-dphi)
    return (photons.phases + shift) % 1.0


def pint_witness(photons, distance_m=500e3):
    """PINT's own phases for three moves of the geocentre, to hold :func:`displaced_phases` against.

    The moves: ``distance_m`` along the line, ``distance_m`` across it, and one cycle
    ``c P`` along it (:func:`offset_vector`), given to
    :func:`xnavlab.mars.timing.pint_bridge.fermi_displaced_phases` (cached on disk; PINT reads the
    photons when the cache is empty).

    Returns
    -------
    offsets_m : ndarray, shape (3, 3)
        The moves, ICRF axes, m.
    phases : ndarray, shape (3, n)
        PINT's phases of the photons after each move, cycles.

    Examples
    --------
    >>> photons = fermi_photons()                          # doctest: +SKIP
    >>> offsets, phases = pint_witness(photons)            # doctest: +SKIP
    >>> bool(np.abs((phases[1] - photons.phases + 0.5) % 1 - 0.5).max() < 1e-6)  # doctest: +SKIP
    True
    """
    photons = _photons(photons)
    distance_m = check_real("distance_m", distance_m, 0.0, 1e9)
    offsets = np.array([offset_vector(photons, along_m=distance_m),
                        offset_vector(photons, across_m=distance_m),
                        offset_vector(photons, along_m=cycle_length(photons))])
    return offsets, pint_bridge.fermi_displaced_phases(offsets)


def split_months(photons, seed=None):
    """Which photons make the reference: alternate months, or a random half of the months.

    Parameters
    ----------
    photons : Photons
    seed : int or numpy.random.Generator, optional
        Without it, the even months (0, 2, 4, ...) make the reference and the odd ones are
        for navigation; with it, each month goes to the reference with probability 1/2.

    Returns
    -------
    ndarray of bool, shape (n,)
        True for a reference photon.

    Examples
    --------
    >>> fake = Photons(*(np.zeros(4),) * 2, np.arange(4) * MONTH, np.zeros((4, 3)),
    ...                np.zeros((4, 3)), np.ones(4), np.zeros((3, 3)))
    >>> split_months(fake).tolist()
    [True, False, True, False]
    """
    month = _photons(photons).month
    if seed is None:
        return month % 2 == 0
    rng = make_rng(seed)
    return (rng.random(month.max() + 1) < 0.5)[month]


# ------------------------------------------------------------------ the template


def _fourier(phases, weights, harmonics):
    """``sum_j w_j exp(-2 pi i k phi_j)`` for k = 1..harmonics, by powers (no large exp)."""
    z = np.exp(-2j * np.pi * phases)
    out = np.empty(harmonics, dtype=complex)
    p = weights.astype(complex)
    for k in range(harmonics):
        p = p * z
        out[k] = p.sum()
    return out


def template_density(coeffs, phases=None, derivative=0):
    """The template density ``f`` (or its derivative) from Fourier coefficients.

    ``f(phi) = 1 + 2 Re sum_k a_k exp(2 pi i k phi)``, per cycle; its integral over a cycle
    is 1.

    Parameters
    ----------
    coeffs : array_like, shape (K,), complex
        ``a_1 .. a_K``.
    phases : array_like, optional
        Where to evaluate it (cycles); default a table of 16384 equally spaced phases.
    derivative : int
        0, 1 or 2: the density, or its first or second derivative (per cycle^2, ^3).

    Returns
    -------
    ndarray

    Examples
    --------
    >>> f = template_density(np.array([0.5]), np.array([0.0, 0.25, 0.5]))
    >>> f.round(12).tolist()   # 1 + cos(2 pi phi)
    [2.0, 1.0, 0.0]
    """
    coeffs = _coeffs(coeffs)
    derivative = check_int("derivative", derivative, 0, 2)
    k = np.arange(1, coeffs.size + 1)
    spec = coeffs * (2j * np.pi * k) ** derivative
    if phases is None:
        full = np.zeros(_TABLE // 2 + 1, dtype=complex)
        full[1:coeffs.size + 1] = spec
        return np.fft.irfft(full, _TABLE) * _TABLE + (1.0 if derivative == 0 else 0.0)
    x = check_finite_array("phases", phases)
    series = 2.0 * np.real(np.exp(2j * np.pi * np.multiply.outer(x, k)) @ spec)
    return series + (1.0 if derivative == 0 else 0.0)


def _coeffs(coeffs):
    """``coeffs`` as a non-empty 1-D complex array of finite numbers, else one ValueError."""
    if np.ma.is_masked(coeffs):  # np.asarray would use the masked values (review 35m (5) 1)
        raise ValueError("coeffs has masked entries (no number to use: fill or drop them)")
    raw = np.asarray(coeffs, dtype=object) if isinstance(coeffs, list | tuple) else np.asarray(coeffs)
    if raw.dtype.kind == "O":  # a list: each item a real or complex number, no bool
        ok = raw.ndim == 1 and all(isinstance(v, complex | float | int | np.number)
                                   and not isinstance(v, bool | np.bool_) for v in raw)
    else:
        ok = raw.ndim == 1 and raw.dtype.kind in "iufc"
    if not ok or raw.size == 0:
        raise ValueError(f"coeffs must be a non-empty 1-D array of (complex) numbers, got {shown(coeffs)}")
    out = raw.astype(complex)
    if not np.all(np.isfinite(out)):
        raise ValueError("coeffs must contain only finite numbers (no NaN or inf)")
    return out


def _template_coeffs(phases, weights, bandwidth):
    """Kernel estimate of the pulse profile from weighted phases: its Fourier coefficients.

    ``a_k = g_k sum_j w_j exp(-2 pi i k phi_j) / sum_j w_j^2``: unbiased for a photon mixture
    ``w f + (1 - w)``, smoothed by a wrapped Gaussian kernel ``g_k = exp(-2 pi^2 k^2 b^2)``.
    """
    harmonics = int(math.ceil(math.sqrt(10.0) / (math.pi * bandwidth)))  # g_K < e^-20
    harmonics = min(harmonics, _TABLE // 4)
    k = np.arange(1, harmonics + 1)
    kernel = np.exp(-2.0 * (np.pi * k * bandwidth) ** 2)
    return _fourier(phases, weights, harmonics) / np.sum(weights**2) * kernel


class _Tables:
    """The template and its derivatives tabulated over a cycle, and the Fisher information per weight."""

    def __init__(self, coeffs):
        self.f = np.clip(template_density(coeffs), _FLOOR, None)
        self.d1 = template_density(coeffs, derivative=1)
        self.d2 = template_density(coeffs, derivative=2)
        w = _WEIGHT_GRID[:, None]
        # J(w) = int w^2 f'^2 / (w f + 1 - w) dphi: expected information per photon, cycles^-2
        self.info = np.mean(w**2 * self.d1**2 / (w * self.f + 1.0 - w), axis=1)

    def at(self, table, x):
        u = (np.asarray(x) % 1.0) * _TABLE  # linear interpolation, periodic
        i = np.minimum(u.astype(int), _TABLE - 1)
        frac = u - i
        return table[i] * (1.0 - frac) + table[(i + 1) % _TABLE] * frac

    def photon_info(self, weights):
        return np.interp(weights, _WEIGHT_GRID, self.info)

    def score(self, x, weights):
        """d log L_i / d s_i for photons at template phases ``x`` (s_i their shift), per cycle."""
        q = weights * self.at(self.f, x) + 1.0 - weights
        return -weights * self.at(self.d1, x) / q


@functools.lru_cache(maxsize=8)
def _tables_cached(key):
    return _Tables(np.frombuffer(key, dtype=complex))


def _tables(coeffs):
    return _tables_cached(np.ascontiguousarray(coeffs, dtype=complex).tobytes())


# ------------------------------------------------------------------ the reference


def _z2_frequency(phases, weights, dt, span, harmonics=12):
    """Spin-frequency correction (Hz) maximising the weighted Z^2 power of ``phases - df dt``."""
    z = np.exp(-2j * np.pi * phases)

    def power(dfs):
        out = np.empty(len(dfs))
        for m, df in enumerate(dfs):
            u = z * np.exp(2j * np.pi * df * dt)
            p, s = weights.astype(complex), 0.0
            for _ in range(harmonics):
                p = p * u
                s += abs(p.sum()) ** 2
            out[m] = s
        return out

    grid = np.linspace(-3.0, 3.0, 241) / span  # +-3 cycles over the span
    best = grid[np.argmax(power(grid))]
    for step in (0.025, 0.025 / 8, 0.025 / 64):
        fine = best + step / span * np.arange(-8, 9)
        best = fine[np.argmax(power(fine))]
    return float(best)


def build_reference(photons, in_reference=None, bandwidth=0.004, iterations=4):
    """Timing-model corrections and a template, from the reference photons only.

    The shipped timing model of J0030+0451 is slightly off (chapter 1 saw its phases drift),
    and a fix needs a template. Both come from the reference photons:

    1. a spin-frequency correction that maximises the weighted Z^2 power of the phases
       (12 harmonics), which sharpens the fold;
    2. then, ``iterations`` times: a template from the corrected phases (weighted kernel
       estimate, Gaussian kernel of ``bandwidth`` cycles) and a maximum-likelihood fit of
       the four corrections of chapter 1's timing equation by Fisher scoring: a phase offset,
       the spin frequency, and the pulsar direction's error east and north (seen as an
       annual term, the error times the geocentre's distance from the SSB);
    3. the template rebuilt once more and the covariance of the corrections from their
       Fisher information.

    Parameters
    ----------
    photons : Photons
        All photons (undisplaced: the reference is measured at the true geocentre).
    in_reference : array_like of bool, shape (n,), optional
        The reference photons; default :func:`split_months` (even months).
    bandwidth : float
        Kernel sigma, cycles (0.0005 to 0.05); the narrowest peak of J0030+0451 has a
        sigma of about 0.0074.
    iterations : int
        Template-and-fit rounds (1 to 20).

    Returns
    -------
    Reference

    Examples
    --------
    >>> ref = build_reference(fermi_photons())   # doctest: +SKIP
    >>> round(ref.theta[1] * 1e9, 2)             # spin-frequency correction, nHz  # doctest: +SKIP
    0.57
    """
    photons = _photons(photons)
    bandwidth = check_real("bandwidth", bandwidth, 0.0005, 0.05)
    iterations = check_int("iterations", iterations, 1, 20)
    mask = split_months(photons) if in_reference is None else np.asarray(in_reference, dtype=bool)
    if mask.shape != (photons.size,) or mask.sum() < 100:
        raise ValueError(f"in_reference must be a boolean mask of shape ({photons.size},) selecting "
                         f"at least 100 photons, got shape {mask.shape}")
    ref_photons = photons.subset(mask)
    w = ref_photons.weights
    t_ref = float(np.average(ref_photons.t, weights=w))
    span = float(np.ptp(photons.t))
    east, north = _sky_axes(photons.mean_direction)
    theta = np.zeros(4)
    theta[1] = _z2_frequency(ref_photons.phases, w, ref_photons.t - t_ref, span)
    ref = Reference(np.zeros(1, complex), theta, np.zeros((4, 4)), t_ref, east, north, mask, bandwidth)
    x_all = ref.regressors(ref_photons)
    scale = np.abs(x_all).max(axis=0)  # columns scaled to order 1 for the linear algebra
    x = x_all / scale
    for _ in range(iterations):
        coeffs = _template_coeffs(ref.corrected(ref_photons), w, bandwidth)
        tables = _tables(coeffs)
        beta = np.zeros(4)  # corrections to theta (scaled) against this template
        info_w = tables.photon_info(w)
        fisher = (x * info_w[:, None]).T @ x
        for _ in range(20):  # Fisher scoring: beta += I^-1 U
            resid = ref.corrected(ref_photons) - x @ beta
            step = np.linalg.solve(fisher, x.T @ tables.score(resid, w))
            beta += step
            if np.max(np.abs(step * np.sqrt(np.diag(fisher)))) < 1e-6:
                break
        theta = ref.theta + beta / scale
        ref = Reference(coeffs, theta, np.zeros((4, 4)), t_ref, east, north, mask, bandwidth)
    coeffs = _template_coeffs(ref.corrected(ref_photons), w, bandwidth)
    fisher = (x * _tables(coeffs).photon_info(w)[:, None]).T @ x
    cov = np.linalg.inv(fisher) / np.outer(scale, scale)
    return Reference(coeffs, theta, cov, t_ref, east, north, mask, bandwidth)


# ------------------------------------------------------------------ the fix


def log_likelihood(photons, reference, offsets_m, phases=None):
    """The photons' log-likelihood against the template, as a function of the offset along the line.

    ``L(d) = sum_i log(w_i f(phi_i - f_i d / c) + 1 - w_i)`` (eq. ch01-photon-like), with
    ``phi_i`` the corrected phases (:meth:`Reference.corrected`).

    Parameters
    ----------
    photons : Photons
    reference : Reference
    offsets_m : array_like, shape (m,)
        Offsets ``d`` along the line, m.
    phases : array_like, shape (n,), optional
        The photons' phases (default their own), e.g. :func:`displaced_phases`.

    Returns
    -------
    ndarray, shape (m,)

    Examples
    --------
    >>> photons = fermi_photons(); ref = build_reference(photons)       # doctest: +SKIP
    >>> nav = photons.subset(~ref.in_reference)                          # doctest: +SKIP
    >>> L = log_likelihood(nav, ref, [0.0, cycle_length(nav)])           # doctest: +SKIP
    >>> bool(abs(L[1] - L[0]) < 1e-3)                                    # doctest: +SKIP
    True
    """
    photons, reference = _photons(photons), _reference(reference)
    d = check_finite_array("offsets_m", offsets_m)
    phases = _phases(photons, phases)
    tables = _tables(reference.coeffs)
    phi = reference.corrected(photons, phases)
    w = photons.weights
    out = np.empty(d.shape)
    for m, dm in np.ndenumerate(d):
        q = w * tables.at(tables.f, phi - photons.spin_frequency * dm / C) + 1.0 - w
        out[m] = np.sum(np.log(q))  # eq. (ch01-photon-like)
    return out


def likelihood_scan(photons, reference, phases=None, bins=1024):
    """The log-likelihood (eq. ch01-photon-like) over one cycle of offsets, by FFT.

    The photons are binned in phase (``bins`` bins) and in weight (ten groups, each at its
    mean weight), and each group's histogram is correlated with ``log(w f + 1 - w)``: an
    approximation of :func:`log_likelihood` good to a bin, for finding the peak and drawing.

    Parameters
    ----------
    photons : Photons
    reference : Reference
    phases : array_like, shape (n,), optional
        The photons' phases (default their own).
    bins : int
        Offsets per cycle (64 to 65536).

    Returns
    -------
    offsets_m : ndarray, shape (bins,)
        Offsets along the line, ``k c P / bins``, m (one cycle from 0).
    log_like : ndarray, shape (bins,)

    Examples
    --------
    >>> photons = fermi_photons(); ref = build_reference(photons)     # doctest: +SKIP
    >>> d, L = likelihood_scan(photons.subset(~ref.in_reference), ref)  # doctest: +SKIP
    >>> d.shape, L.shape                                              # doctest: +SKIP
    ((1024,), (1024,))
    """
    photons, reference = _photons(photons), _reference(reference)
    phases = _phases(photons, phases)
    bins = check_int("bins", bins, 64, 65536)
    tables = _tables(reference.coeffs)
    phi = reference.corrected(photons, phases)
    w = photons.weights
    index = np.minimum((phi * bins).astype(int), bins - 1)
    f_binned = tables.at(tables.f, (np.arange(bins) + 0.5) / bins)
    groups = np.minimum((w * 10).astype(int), 9)
    out = np.zeros(bins)
    for g in np.unique(groups):
        sel = groups == g
        hist = np.bincount(index[sel], minlength=bins)
        wg = float(w[sel].mean())
        logq = np.log(wg * f_binned + 1.0 - wg)  # eq. (ch01-photon-like), binned
        out += np.fft.irfft(np.fft.rfft(hist) * np.conj(np.fft.rfft(logq)), bins)
    return np.arange(bins) / bins * cycle_length(photons), out


def estimate_offset(photons, reference, phases=None):
    """Maximum-likelihood offset along the line from navigation photons, and its photon noise.

    A scan of the likelihood over one cycle (:func:`likelihood_scan`) finds the peak; Fisher
    scoring on the exact likelihood (eq. ch01-photon-like) refines it. The standard
    deviation is the sandwich (robust) form
    ``sqrt(sum_i U_i^2) / |sum_i dU_i/dd|`` of the photons' scores ``U_i`` at the estimate
    (eq. ch01-photon-sigma): it stays right when the template is itself noisy, where the
    Fisher information computed from that template would not (with a kernel narrower
    than the pulse, the noise of the template looks like information).

    Parameters
    ----------
    photons : Photons
        The navigation photons.
    reference : Reference
    phases : array_like, shape (n,), optional
        Their phases (default their own), e.g. :func:`displaced_phases`.

    Returns
    -------
    along_m : float
        The offset, m, in [-cP/2, cP/2) (``P`` at the photons' mean spin frequency).
    sigma_m : float
        Its standard deviation from these photons alone, m.

    Examples
    --------
    >>> photons = fermi_photons(); ref = build_reference(photons)   # doctest: +SKIP
    >>> nav = photons.subset(~ref.in_reference)                      # doctest: +SKIP
    >>> d, s = estimate_offset(nav, ref, displaced_phases(nav, offset_vector(nav, 1e5)))  # doctest: +SKIP
    >>> abs(d - 1e5) < 2 * s                                         # doctest: +SKIP
    True
    """
    photons, reference = _photons(photons), _reference(reference)
    phases = _phases(photons, phases)
    tables = _tables(reference.coeffs)
    phi = reference.corrected(photons, phases)
    w = photons.weights
    cycle = cycle_length(photons)
    offsets, scan = likelihood_scan(photons, reference, phases)
    d = float(offsets[np.argmax(scan)])  # m
    gain = photons.spin_frequency / C  # cycles per metre, per photon
    expected = float(np.sum(tables.photon_info(w) * gain**2))  # Fisher information, m^-2
    for _ in range(30):  # Fisher scoring on the exact likelihood
        step = float(np.sum(tables.score(phi - gain * d, w) * gain)) / expected
        d += step
        if abs(step) < 1e-4:
            break
    x = phi - gain * d
    q = w * tables.at(tables.f, x) + 1.0 - w
    score = -w * tables.at(tables.d1, x) / q * gain  # dL_i/dd, m^-1
    curvature = float(np.sum((w * tables.at(tables.d2, x) / q - (w * tables.at(tables.d1, x) / q) ** 2)
                             * gain**2))  # d2L/dd2, m^-2
    if not curvature < 0.0:  # not a maximum of the exact likelihood: the expected curvature
        curvature = -expected
    sigma = math.sqrt(float(np.sum(score**2))) / abs(curvature)  # eq. (ch01-photon-sigma)
    d = (d + 0.5 * cycle) % cycle - 0.5 * cycle
    return float(d), sigma


def fix(photons, offset_m, reference, phases=None):
    """A held-out fix: the offset along the line from the navigation photons, with the truth.

    The navigation photons (those not in ``reference.in_reference``) are phased as if the
    position were ``offset_m`` away (:func:`displaced_phases`, or the given ``phases``), and
    :func:`estimate_offset` measures the offset back. Its variance has three parts
    (eq. ch01-photon-total): the navigation photons' own; the template's, which is a
    measurement too, made of the reference photons, taken as that of a fix from them
    (the photons' variance times the ratio of the two sets' Fisher information); and the
    timing corrections', ``x^T Cov x`` without the phase offset, ``x`` the navigation
    photons' information-weighted mean regressor (:meth:`Reference.regressors`).

    Parameters
    ----------
    photons : Photons
        All photons (the reference ones are left out here).
    offset_m : array_like, shape (3,)
        The error of the assumed position, ICRF axes, m (:func:`offset_vector`).
    reference : Reference
    phases : array_like, shape (n,), optional
        Phases of all photons to use instead of :func:`displaced_phases` (e.g. PINT's own
        with the geocentre moved, :func:`xnavlab.mars.timing.pint_bridge.fermi_displaced_phases`).

    Returns
    -------
    Fix

    Examples
    --------
    >>> photons = fermi_photons(); ref = build_reference(photons)   # doctest: +SKIP
    >>> f = fix(photons, offset_vector(photons, along_m=0.0), ref)   # doctest: +SKIP
    >>> abs(f.along_m) < 2 * f.sigma_m                               # doctest: +SKIP
    True
    """
    photons = _photons(photons)
    dr = check_finite_array("offset_m", offset_m, shape=(3,))
    if dr.ndim != 1:
        raise ValueError(f"offset_m must have shape (3,), got {dr.shape}")
    reference = _reference(reference)
    if reference.in_reference.shape != (photons.size,):  # built from other photons
        raise ValueError(f"reference must be built from these {photons.size} photons, got one from "
                         f"{reference.in_reference.size}")
    nav = ~reference.in_reference
    photons_nav = photons.subset(nav)
    if phases is None:
        nav_phases = displaced_phases(photons_nav, dr)
    else:
        nav_phases = _phases(photons, phases)[nav] % 1.0
    along, sigma_nav = estimate_offset(photons_nav, reference, nav_phases)
    tables = _tables(reference.coeffs)
    info_nav = tables.photon_info(photons_nav.weights)
    info_ref = tables.photon_info(photons.weights[reference.in_reference])
    sigma_template = sigma_nav * math.sqrt(info_nav.sum() / info_ref.sum())
    xbar = info_nav @ reference.regressors(photons_nav) / info_nav.sum()  # cycles per unit
    xbar[0] = 0.0  # the phase offset is the template's: counted above
    cycle = cycle_length(photons_nav)
    sigma_timing = math.sqrt(max(float(xbar @ reference.cov @ xbar), 0.0)) * cycle  # cycles -> m
    sigma = math.sqrt(sigma_nav**2 + sigma_template**2 + sigma_timing**2)  # eq. (ch01-photon-total)
    return Fix(along, sigma, sigma_nav, sigma_template, sigma_timing,
               float(photons.mean_direction @ dr), cycle, photons_nav.size,
               float(photons_nav.weights.sum()))
