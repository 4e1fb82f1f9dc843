"""The Cramer-Rao bound of a pulsar TOA, the maximum-likelihood TOA that reaches it, XNAV noise at the bound.

A detector sees a pulsar as a Poisson process of rate

.. math::

   \\lambda(t) = \\lambda_b + \\lambda_s\\, h\\big(\\Phi(t - \\tau)\\big)

(``lambda_s`` pulsed and ``lambda_b`` unpulsed photons per second,
:func:`~xnavlab.mars.timing.pulsars.photon_rates`;
``h`` the pulse profile, a density per cycle, :func:`~xnavlab.mars.timing.pulsars.profile`: a wrapped
Gaussian whose FWHM is the catalogue's pulse width; ``Phi`` the phase model; ``tau`` the TOA
offset). The Fisher information of ``tau`` in an exposure ``T`` is ``int_0^T lambda'(t)^2 /
lambda(t) dt`` (Golshan & Sheikh 2007; Emadzadeh & Speyer 2010), and no unbiased TOA
estimator does better than

.. math::

   \\sigma_{TOA}^2 \\ge \\Big[T f^2 \\int_0^1
   \\frac{\\lambda_s^2\\, h'(\\phi)^2}{\\lambda_b + \\lambda_s h(\\phi)}\\, d\\phi\\Big]^{-1}

(:func:`toa_crlb`; ``f`` the spin frequency, the integral over one cycle). The main paper's
ranging accuracies (Fan et al. 2016: 109, 344, 1866, 325 m for 500 s and 1 m^2) come from the
signal-to-noise heuristic of Sheikh et al. (2006) (:func:`~xnavlab.mars.timing.pulsars.ranging_accuracy`),
which counts the background inside one pulse width only; with the same rates and profile the
bound is 99, 454, 2637 and 381 m: three of the four quoted accuracies are below it.

:func:`ml_phase_shift` is the maximum-likelihood TOA of a folded profile with the rates known
(the global maximum of the binned Poisson log-likelihood on the bin grid, by FFT, refined by
safeguarded Newton steps on the exact bin integrals of the profile). The package's other
estimator, :func:`~xnavlab.mars.timing.pulsars.estimate_phase_shift`, is the cross-correlation
(FFTFIT) one: maximum likelihood only when the background dominates (the MSPs), 18 % above the
bound for the Crab. :func:`monte_carlo_ml_toa` measures the ML estimator on simulated photons
and :func:`accuracy_table` puts formula, bound and both Monte Carlos side by side for the
chapter. For a symmetric profile the bound with the rates unknown equals the bound with them
known (the derivatives of ``lambda`` in ``tau`` and in the rates are orthogonal), so the known
rates cost nothing in generality.

:func:`xnav_noise_sigma` gives the XNAV delay noise of the Mars scenario for each choice of
:data:`XNAV_NOISE` (``MarsScenario(xnav_noise="crlb")``).

Units: times in s, rates in photons/s, areas in m^2, the background in ph/cm^2/s (as
:mod:`xnavlab.mars.timing.pulsars`), phases in cycles.

Examples
--------
>>> round(ranging_crlb("B1937+21"))          # m, 500 s, 1 m^2: the formula gives 345
454
"""

from __future__ import annotations

import json
import math

import numpy as np

from xnavlab.core.constants import C
from xnavlab.core.diskcache import entry_path, store
from xnavlab.core.distributions import chi2_ppf
from xnavlab.core.validate import (
    check_bool,
    check_choice,
    check_finite_array,
    check_int,
    check_real,
    check_records,
    check_shape,
    make_rng,
    shown,
)
from xnavlab.mars.timing import pulsars
from xnavlab.mars.timing._checks import check_photons

__all__ = [
    "MAX_COUNTS",
    "XNAV_NOISE",
    "profile_derivative",
    "fisher_information",
    "toa_crlb",
    "ranging_crlb",
    "default_nbins",
    "expected_fold",
    "ml_phase_shift",
    "monte_carlo_ml_toa",
    "accuracy_table",
    "ACCURACY_COLUMNS",
    "accuracy_html",
    "plot_accuracy",
    "xnav_noise_sigma",
]

#: The XNAV noise models of the Mars scenario: ``"paper"`` the Sheikh et al. (2006) formula
#: (the main paper's 109, 344, 1866, 325 m), ``"crlb"`` the Poisson Cramer-Rao bound.
XNAV_NOISE = ("paper", "crlb")

#: The most expected photons in a fold: 1e15 photons/s (the rate bound of
#: :func:`fisher_information`) over 1e9 s, thirty years; near 1e308 the likelihood overflows.
MAX_COUNTS = 1e24

_FWHM = 2.0 * math.sqrt(2.0 * math.log(2.0))
_WRAPS = np.arange(-3, 4)  # images of the wrapped Gaussian (sigma <= 0.5 / 2.355 cycles)


def _sigma(duty):
    return check_real("duty", duty, 1e-4, 0.5) / _FWHM  # pulsars.profile's (and Pulsar's) range


def profile_derivative(ph, duty):
    """Derivative ``h'(phi)`` of :func:`~xnavlab.mars.timing.pulsars.profile`, per cycle^2.

    Parameters
    ----------
    ph : float or array_like
        Phase, cycles.
    duty : float
        Pulse FWHM over period, in [1e-4, 0.5] (as :func:`~xnavlab.mars.timing.pulsars.profile`).

    Returns
    -------
    ndarray
        ``dh/dphi`` at ``ph`` (the profile is a density per cycle).

    Examples
    --------
    >>> d = 0.05
    >>> fd = (pulsars.profile(0.010001, d) - pulsars.profile(0.009999, d)) / 2e-6
    >>> bool(abs(profile_derivative(0.01, d) / fd - 1) < 1e-6)
    True
    """
    sig = _sigma(duty)
    x = check_finite_array("ph", ph)
    x = x - np.round(x)
    u = (x[..., None] + _WRAPS) / sig
    g = np.exp(-0.5 * u * u) / (sig * math.sqrt(2.0 * math.pi))
    return np.sum(-u / sig * g, axis=-1)  # d/dphi of the wrapped Gaussian


def _grid(duty):
    return int(2 ** math.ceil(math.log2(max(4096.0, 400.0 / duty))))


#: How far from 1 the mean of :func:`fisher_information`'s ``h`` may be (relative): the package's
#: profile on :func:`toa_crlb`'s grid is 1 within 2.3e-16; a grid too coarse for the pulse misses
#: its peak or lands on it, and its mean is off by far more (0.47 for a 1 % pulse in 64 samples).
_MEAN_TOL = 1e-6


def fisher_information(pulsed, unpulsed, frequency, h, dh):
    """Fisher information of the TOA per second of exposure, 1/s^2 per s.

    ``J = f^2 mean_phi[ (lambda_s h')^2 / (lambda_b + lambda_s h) ]`` over samples of one
    cycle (uniform grid, so the mean is the periodic trapezoid rule: spectrally accurate
    for a smooth profile), or, for a binned profile, the sum over the bins.

    Parameters
    ----------
    pulsed, unpulsed : float
        ``lambda_s`` in [1e-20, 1e15] and ``lambda_b`` in [0, 1e15], photons/s.
    frequency : float
        Spin frequency f, Hz.
    h, dh : array_like, shape (m,)
        The profile (density per cycle, >= 0, mean 1 within 1e-6: refused otherwise, not
        rescaled, since ``dh`` would need the same factor) and its derivative (per cycle^2,
        0 where the rate is 0) at ``m`` equally spaced phases of one cycle, ``m >= 8``
        (:func:`toa_crlb`'s fewest bins; :func:`toa_crlb` scales its ``template`` itself).

    Returns
    -------
    float
        ``J``; the bound over an exposure T is ``1 / sqrt(T J)``, s.

    Examples
    --------
    >>> x = np.arange(4096) / 4096
    >>> h, dh = pulsars.profile(x, 0.1), profile_derivative(x, 0.1)
    >>> j = fisher_information(1.0, 0.0, 1.0, h, dh)   # no background: f^2 int h'^2 / h
    >>> round(j * (0.1 / 2.3548200450309493) ** 2, 6)  # = 1/sigma^2 for a Gaussian
    1.0
    """
    # a rate above 1e15 photons/s (a million times the Crab's on a square metre) or a spin
    # above 1e4 Hz (the fastest pulsar known spins at 716 Hz) is no pulsar; beyond, J overflows.
    # A pulsed rate below 1e-20 photons/s is below the least of photon_rates (1 mm^2, 1e-12
    # ph/cm^2/s, a pulsed fraction of 1e-6; a subnormal one made lambda_s h zero where h' is not)
    ls = check_real("pulsed", pulsed, 1e-20, 1e15)
    lb = check_real("unpulsed", unpulsed, 0.0, 1e15)
    f = check_real("frequency", frequency, 0.0, 1e4, lo_open=True)
    h = check_finite_array("h", h)
    if h.ndim != 1 or h.size < 8:  # toa_crlb's fewest bins: fewer cannot draw a pulse
        raise ValueError(f"h must be a 1-D array, the profile at m >= 8 phases, got shape {h.shape}")
    dh = check_shape("dh", dh, h.shape, "one per sample of h")
    if np.any(h < 0.0):  # a density: lambda_b + lambda_s h < 0 is no rate
        i = int(np.argmin(h))
        raise ValueError(f"h must be a profile, >= 0 (a density per cycle), got h[{i}] = {float(h[i]):g}")
    mean = float(np.mean(h))
    if abs(mean - 1.0) > _MEAN_TOL:  # lambda_s h carries lambda_s photons/s only at mean 1
        raise ValueError(f"h must have mean 1 over the cycle (within {_MEAN_TOL:g}: lambda_s h then "
                         f"carries pulsed = lambda_s photons/s), got mean {mean:.6g}: divide h and dh "
                         f"by it, or sample a narrow pulse more finely")
    lam = lb + ls * h
    if np.any((lam == 0.0) & (dh != 0.0)):  # h' of a profile is 0 where it is 0
        i = int(np.argmax((lam == 0.0) & (dh != 0.0)))
        raise ValueError(f"dh must be 0 wherever the rate lambda_b + lambda_s h is 0 (h[{i}] = 0 with "
                         f"unpulsed = 0), got dh[{i}] = {float(dh[i]):g}")
    with np.errstate(over="ignore"):
        ratio = np.divide((ls * dh) ** 2, lam, out=np.zeros_like(lam), where=lam > 0.0)  # 0 where h = 0
        j = f * f * float(np.mean(ratio))  # J = f^2 int lambda'^2 / lambda dphi
    if not np.isfinite(j):
        raise ValueError(f"h and dh must be a profile and its derivative of finite information; "
                         f"got |dh| up to {float(np.max(np.abs(dh))):.3g} per cycle^2, whose "
                         f"information overflows")
    return j


def toa_crlb(pulsar, area_m2=1.0, t_obs=500.0, background_ph_cm2_s=0.005, nbins=None,
             template=None):
    """Poisson Cramer-Rao bound of the TOA (1 sigma, s) of one pulsar.

    ``sigma_TOA^2 >= 1 / (T f^2 int_0^1 (lambda_s h')^2 / (lambda_b + lambda_s h) dphi)``
    (Golshan & Sheikh 2007; Emadzadeh & Speyer 2010): the information ``int_0^T
    lambda'(t)^2 / lambda(t) dt`` of the arrival times of a Poisson process whose rate
    ``lambda(t) = lambda_b + lambda_s h(Phi(t - tau))`` is shifted by the TOA ``tau``. The
    rates are those of :func:`~xnavlab.mars.timing.pulsars.photon_rates` (pulsed ``A F p_f``,
    unpulsed ``A (B + F (1 - p_f))``).

    Parameters
    ----------
    pulsar : str or Pulsar
        Supplies the flux, pulsed fraction, period and (unless ``template``) the width.
    area_m2 : float
        Effective area, m^2, in [1e-6, 1e3].
    t_obs : float
        Exposure T, s, in [1e-6, 1e7] (the ranges of :func:`~xnavlab.mars.timing.pulsars.toa_sigma`).
    background_ph_cm2_s : float
        Diffuse background, ph/cm^2/s, in [0, 10].
    nbins : int, optional
        Bound of a folded profile of ``nbins`` phase bins (the counts per bin are
        sufficient statistics of a binned estimator): ``J = f^2 sum_i mu_i'^2 / mu_i`` with
        ``mu_i`` the expected rate in bin i. By default the photons' own (unbinned) bound.
    template : array_like, shape (m,), optional
        Another pulse profile, sampled at ``m`` equally spaced phases of one cycle (scaled
        to mean 1 here; derivative by FFT). By default the package's model,
        :func:`~xnavlab.mars.timing.pulsars.profile`, a Gaussian of the catalogue width.

    Returns
    -------
    float
        The lower bound on the TOA standard deviation, s.

    Examples
    --------
    >>> round(toa_crlb("B0531+21") * 1e9)       # ns, 500 s, 1 m^2
    329
    >>> round(toa_crlb("B0531+21", nbins=1024) / toa_crlb("B0531+21"), 4)   # 40 bins a FWHM
    1.0001
    """
    p = pulsars.get(pulsar)
    t_obs = check_real("t_obs", t_obs, 1e-6, 1e7)  # as pulsars.toa_sigma's: 1 us times nothing
    ls, lb = pulsars.photon_rates(p, area_m2, background_ph_cm2_s)
    if template is not None:
        if nbins is not None:
            raise ValueError("give nbins or template, not both")
        h = check_finite_array("template", template)
        if h.ndim != 1 or h.size < 8 or np.any(h < 0) or not h.sum() > 0:
            raise ValueError("template must be a 1-D profile of at least 8 non-negative samples")
        h = h / h.mean()
        k = np.fft.fftfreq(h.size, 1.0 / h.size)
        dh = np.fft.ifft(2j * np.pi * k * np.fft.fft(h)).real  # h' by FFT, per cycle^2
        j = fisher_information(ls, lb, p.frequency, h, dh)
        if not j > 0.0:
            raise ValueError("template must vary over the cycle: a flat profile carries no "
                             "timing information (the bound would be infinite)")
    elif nbins is None:
        x = np.arange(_grid(p.duty_cycle)) / _grid(p.duty_cycle)
        j = fisher_information(ls, lb, p.frequency, pulsars.profile(x, p.duty_cycle),
                               profile_derivative(x, p.duty_cycle))
    else:
        nbins = check_int("nbins", nbins, 8, 2**20)
        mu, dmu, _ = _bins(nbins, p.duty_cycle, 1.0, lb / ls, 0.0)
        j = p.frequency**2 * ls * float(np.sum(dmu**2 / mu))  # J = f^2 sum mu_i'^2 / mu_i
    return 1.0 / math.sqrt(t_obs * j)  # sigma_TOA >= 1 / sqrt(T J)


def ranging_crlb(pulsar, area_m2=1.0, t_obs=500.0, background_ph_cm2_s=0.005):
    """The bound of :func:`toa_crlb` as a range, ``c sigma_TOA``, m.

    Examples
    --------
    >>> [round(ranging_crlb(n)) for n in pulsars.PAPER_PULSARS]
    [99, 454, 2637, 381]
    """
    return C * toa_crlb(pulsar, area_m2, t_obs, background_ph_cm2_s)


def default_nbins(pulsar):
    """Phase bins of the Monte Carlo folds: 10 a pulse width (FWHM), at least 256.

    Binning then costs at most 0.7 % of the bound (:func:`toa_crlb` with ``nbins``).

    Examples
    --------
    >>> default_nbins("B0531+21"), default_nbins("B1937+21")
    (256, 743)
    >>> round(toa_crlb("B1937+21", nbins=743) / toa_crlb("B1937+21"), 4)
    1.0032
    """
    p = pulsars.get(pulsar)
    return max(256, math.ceil(10.0 / p.duty_cycle))


def _images(sig):
    """Images ``k`` of the wrapped Gaussian that reach a phase within half a cycle (10 sigma)."""
    k = math.floor(0.5 + 10.0 * sig)
    return np.arange(-k, k + 1)


def _bins(nbins, duty, pulsed, unpulsed, shift):
    """Expected counts per bin and their first two derivatives in the shift (per cycle).

    ``shift`` is a float or an array (...,); the results have shape (..., nbins). Each bin's
    edges are moved by the whole number of cycles nearest its centre, so that the few images
    of :func:`_images` hold all of the wrapped profile there.
    """
    from scipy.special import ndtr  # imported here: scipy.special is slow to import

    sig = duty / _FWHM
    lo = np.arange(nbins) / nbins - np.asarray(shift, dtype=float)[..., None]
    lo = lo - np.round(lo + 0.5 / nbins)  # bin [lo, lo + 1/N], centre within half a cycle of 0
    near = np.abs(lo + 0.5 / nbins) < 12.0 * sig + 1.0 / nbins  # elsewhere h < 1e-31 h(0)
    u = (lo[near][:, None] + _images(sig)) / sig  # lower edges of the images, in sigmas
    v = u + 1.0 / (nbins * sig)  # upper edges
    gu, gv = np.exp(-0.5 * u * u), np.exp(-0.5 * v * v)
    norm = pulsed / (sig * math.sqrt(2.0 * math.pi))
    mu = np.full(lo.shape, unpulsed / nbins)
    dmu, d2mu = np.zeros(lo.shape), np.zeros(lo.shape)
    mu[near] += pulsed * np.sum(ndtr(v) - ndtr(u), axis=1)  # lambda_b T/N + lambda_s T int_bin h
    dmu[near] = norm * np.sum(gu - gv, axis=1)  # d mu_i / d shift = lambda_s T (h(lo) - h(hi))
    d2mu[near] = norm / sig * np.sum(u * gu - v * gv, axis=1)  # = lambda_s T (h'(hi) - h'(lo))
    return mu, dmu, d2mu


def expected_fold(nbins, duty, pulsed, unpulsed, shift=0.0):
    """Expected counts of a fold: ``unpulsed / nbins + pulsed * int_bin h(phi - shift) dphi``.

    The profile's bin integrals are exact (the Gaussian's CDF), not sampled.

    Parameters
    ----------
    nbins : int
        Phase bins; bin i covers ``[i / nbins, (i + 1) / nbins)``.
    duty : float
        Pulse FWHM over period, in [1e-4, 0.5].
    pulsed, unpulsed : float
        Expected pulsed and unpulsed photons in the fold, ``lambda_s T`` and ``lambda_b T``,
        each in [0, MAX_COUNTS].
    shift : float
        Pulse arrival offset, cycles (late positive).

    Returns
    -------
    ndarray, shape (nbins,)
        Expected counts; they sum to ``pulsed + unpulsed``.

    Examples
    --------
    >>> mu = expected_fold(64, 0.1, 1000.0, 640.0, shift=0.25)
    >>> round(float(mu.sum()), 6), int(np.argmax(mu))     # the peak moves to bin 16
    (1640.0, 15)
    """
    nbins = check_int("nbins", nbins, 8, 2**20)
    pulsed = check_real("pulsed", pulsed, 0.0, MAX_COUNTS)  # the checked floats (np.float16 overflowed)
    unpulsed = check_real("unpulsed", unpulsed, 0.0, MAX_COUNTS)
    return _bins(nbins, _sigma(duty) * _FWHM, pulsed, unpulsed, check_real("shift", shift))[0]


def _loglik(counts, mu):
    return np.sum(counts * np.log(mu), axis=-1)  # sum n_i log mu_i (sum mu_i does not depend on tau)


def ml_phase_shift(counts, duty, pulsed, unpulsed, search=0.5, max_iter=30):
    """Maximum-likelihood pulse offset of a fold (or of many), cycles, with the rates known.

    Maximises the binned Poisson log-likelihood ``l(tau) = sum_i n_i log mu_i(tau) - mu_i(tau)``
    with ``mu_i(tau)`` of :func:`expected_fold` (``sum_i mu_i`` does not depend on ``tau``):
    first on the grid of whole-bin shifts within ``search`` of zero, where ``l`` is the
    circular cross-correlation of the counts with ``log mu(0)`` (one FFT), then by Newton steps
    on the exact bin integrals (Fisher scoring where ``l'' >= 0``), at most a bin each and,
    above a thousandth of a bin, halved until ``l`` increases. With bins much narrower than
    the pulse this is the photons' own ML estimate (:func:`toa_crlb` with ``nbins`` gives the
    binned bound).

    Parameters
    ----------
    counts : array_like, shape (nbins,) or (m, nbins)
        Folded counts, one fold a row (exposure-corrected counts, non-integer, are accepted).
    duty : float
        Pulse FWHM over period, in [1e-4, 0.5].
    pulsed, unpulsed : float
        Expected pulsed and unpulsed photons in a fold (``lambda_s T``, ``lambda_b T``), in
        [1e-6, MAX_COUNTS]: a fold expecting under a millionth of a photon of either has
        no phase to estimate, and its likelihood's ratios overflow.
    search : float
        Half-width of the window of offsets searched, cycles, in [0, 0.5] (0.5: the whole
        cycle, the unrestricted ML): the a-priori knowledge of the offset. The refinement
        may leave the window by at most a bin (a fold whose likelihood peaks farther out
        gives the window's edge plus a bin).
    max_iter : int
        Most Newton steps.

    Returns
    -------
    float or ndarray, shape (m,)
        The offset, cycles, in [-0.5, 0.5): positive means the pulses arrive late (the
        convention of :func:`~xnavlab.mars.timing.pulsars.estimate_phase_shift`).

    Examples
    --------
    >>> mu = expected_fold(256, 0.05, 2e4, 1e5, shift=0.1234)
    >>> round(ml_phase_shift(mu, 0.05, 2e4, 1e5), 6)         # noise-free counts
    0.1234
    """
    n = check_finite_array("counts", counts)
    if n.ndim not in (1, 2) or n.shape[-1] < 8 or np.any(n < 0):
        raise ValueError("counts must be a fold of at least 8 non-negative bins, or a 2-D "
                         "array of folds (one a row)")
    pulsed = check_real("pulsed", pulsed, 1e-6, MAX_COUNTS)  # 1e-300 divided by zero
    unpulsed = check_real("unpulsed", unpulsed, 1e-6, MAX_COUNTS)  # 1e-300 overflowed (d1 / m)^2
    search = check_real("search", search, 0.0, 0.5)
    max_iter = check_int("max_iter", max_iter, 1, 1000)
    duty = _sigma(duty) * _FWHM
    n2 = n.reshape(-1, n.shape[-1])
    if not np.all(n2.sum(axis=1) > 0.0):
        k = int(np.argmin(n2.sum(axis=1) > 0.0))
        raise ValueError(f"counts{'' if n.ndim == 1 else f'[{k}]'} must hold at least one "
                         f"photon: an empty fold has no phase")
    nb = n2.shape[1]
    log_mu0 = np.log(_bins(nb, duty, pulsed, unpulsed, 0.0)[0])
    grid = np.fft.irfft(np.fft.rfft(n2) * np.conj(np.fft.rfft(log_mu0)), nb)  # l(j / N)
    shifts = (np.arange(nb) / nb + 0.5) % 1.0 - 0.5
    grid[:, np.abs(shifts) > search] = -np.inf  # outside the a-priori window
    tau = shifts[np.argmax(grid, axis=1)]
    mu, dmu, d2mu = _bins(nb, duty, pulsed, unpulsed, tau)
    ll = _loglik(n2, mu)
    live = np.arange(n2.shape[0])  # folds still iterating
    for _ in range(max_iter):
        x, m, d1, d2 = n2[live], mu[live], dmu[live], d2mu[live]
        g = np.sum(x * d1 / m, axis=1)  # l'(tau)
        curv = np.sum(x * (d2 / m - (d1 / m) ** 2), axis=1)  # l''(tau)
        info = np.sum(d1**2 / m, axis=1)  # expected information
        info = np.where(info > 0.0, info, math.inf)  # 0 for a pulse inside one bin: no step
        step = np.where(curv < 0, -g / np.where(curv < 0, curv, -1.0), g / info)
        step = np.clip(step, -1.0 / nb, 1.0 / nb)  # at most a bin a step
        if search < 0.5:  # and never farther than a bin out of the a-priori window
            edge = search + 1.0 / nb
            step = np.clip(step, -edge - tau[live], edge - tau[live])
        todo = np.arange(live.size)  # halve the steps that lower l
        while todo.size:
            i = live[todo]
            new = _bins(nb, duty, pulsed, unpulsed, tau[i] + step[todo])
            ll_new = _loglik(n2[i], new[0])
            # a step below a thousandth of a bin changes l by less than its rounding: take it
            ok = (ll_new >= ll[i]) | (np.abs(step[todo]) < 1e-3 / nb)
            j = i[ok]
            tau[j] += step[todo[ok]]
            mu[j], dmu[j], d2mu[j], ll[j] = new[0][ok], new[1][ok], new[2][ok], ll_new[ok]
            step[todo[~ok]] *= 0.5
            todo = todo[~ok]
        live = live[np.abs(step) >= 1e-10]  # cycles: 0.2 ps for the fastest pulsar
        if not live.size:
            break
    out = (tau + 0.5) % 1.0 - 0.5
    return float(out[0]) if n.ndim == 1 else out


def monte_carlo_ml_toa(pulsar, n_trials=400, area_m2=1.0, t_obs=500.0,
                       background_ph_cm2_s=0.005, nbins=None, rng=None, photons=False,
                       search=0.05):
    """Monte Carlo of the maximum-likelihood TOA (:func:`ml_phase_shift`): errors, s.

    Each trial draws a true offset uniform within a tenth of a period, a fold of the photon
    process with that offset, estimates the offset and records estimate minus truth. The fold
    is drawn directly as independent Poisson counts per bin with the means of
    :func:`expected_fold` (the counts of a Poisson process in disjoint phase bins, exactly the
    distribution of the folded photons over whole cycles) or, with ``photons``,
    from the photons themselves (:func:`~xnavlab.mars.timing.pulsars.simulate_photons`, folded with
    :func:`~xnavlab.mars.timing.pulsars.fold` over ``(0, t_obs)``; 15 million photons a trial for
    the Crab, so meant for the millisecond pulsars).

    Parameters
    ----------
    pulsar : str or Pulsar
    n_trials : int
        Trials, 2 to 1e6.
    area_m2, t_obs, background_ph_cm2_s : float
        As :func:`toa_crlb` (m^2, s, ph/cm^2/s).
    nbins : int, optional
        Phase bins (default :func:`default_nbins`: 10 a pulse width or more).
    rng : numpy.random.Generator or int, optional
    photons : bool
        Simulate photon arrival times and fold them (slow) instead of drawing the fold; each
        trial's photons at most 5e7 expected (as
        :func:`~xnavlab.mars.timing.pulsars.simulate_photons`: ``t_obs`` refused beyond).
    search : float
        Half-width of the estimator's search window, cycles (:func:`ml_phase_shift`). The
        default, the true offsets' own range, makes it the maximum a posteriori estimate
        under their uniform prior (as a navigation filter searches near its predicted
        TOA); 0.5 searches the whole cycle, where at low signal-to-noise a noise peak
        elsewhere sometimes wins (B1957+20: about one fold in 300 at 500 s, 1 m^2).

    Returns
    -------
    ndarray, shape (n_trials,)
        TOA errors, s.

    Examples
    --------
    >>> err = monte_carlo_ml_toa("B1821-24", n_trials=50, rng=0)
    >>> bool(0.7 < np.std(err) / toa_crlb("B1821-24") < 1.3)
    True
    """
    photons = check_bool("photons", photons)
    p = pulsars.get(pulsar)
    n_trials = check_int("n_trials", n_trials, 2, 10**6)
    t_obs = check_real("t_obs", t_obs, 1e-6, 1e7)  # as toa_crlb's
    nbins = default_nbins(p) if nbins is None else check_int("nbins", nbins, 8, 2**20)
    rng = make_rng(rng)
    ls, lb = pulsars.photon_rates(p, area_m2, background_ph_cm2_s)
    if min(ls, lb) * t_obs < 1e-6:  # ml_phase_shift's lower end, refused here by the caller's name
        raise ValueError(f"t_obs must be long enough to expect 1e-6 pulsed and unpulsed photons a "
                         f"fold, got {ls * t_obs:.3g} and {lb * t_obs:.3g} in {t_obs:g} s")
    if photons:  # each trial's arrival times: bounded before the first is drawn (1e6 s asked 7.8 TiB)
        check_photons("t_obs", (ls, lb), t_obs)
    if photons and t_obs < p.period:  # part of a cycle leaves phase bins unswept (pulsars.fold)
        raise ValueError(f"t_obs must last a whole pulse cycle of {p.name} ({p.period:.6g} s) to fold "
                         f"photons, got {t_obs:g} s")
    truth = rng.uniform(-0.05, 0.05, n_trials)  # cycles
    if photons:
        counts = np.empty((n_trials, nbins))
        for i in range(n_trials):
            t = pulsars.simulate_photons(p, t_obs, area_m2, background_ph_cm2_s, rng,
                                         truth[i] * p.period)
            # no photon: an empty fold, refused below by t_obs (fold refuses an empty t)
            counts[i] = pulsars.fold(t, p, nbins, span=(0.0, t_obs)) if t.size else 0.0
    else:
        counts = rng.poisson(_bins(nbins, p.duty_cycle, ls * t_obs, lb * t_obs, truth)[0])
    empty = ~(counts.sum(axis=1) > 0)  # no phase (refused below as 'counts', not given here)
    if np.any(empty):
        raise ValueError(f"t_obs must be long enough for every trial's fold to hold a photon: "
                         f"trial {int(np.argmax(empty))} drew none in {t_obs:g} s")
    est = ml_phase_shift(counts, p.duty_cycle, ls * t_obs, lb * t_obs, search)
    return (est - truth) * p.period


#: Keys of :func:`accuracy_table`'s rows and the column titles of :func:`accuracy_html`.
ACCURACY_COLUMNS = {
    "pulsar": "pulsar",
    "paper_m": "paper (m)",
    "formula_m": "formula (m)",
    "crlb_m": "Cramer-Rao bound (m)",
    "ml_m": "ML Monte Carlo (m)",
    "ml_lo_m": "95 % from (m)",
    "ml_hi_m": "95 % to (m)",
    "ml_beyond_4": "ML beyond 4 bounds",
    "xcorr_m": "cross-correlation Monte Carlo (m)",
    "formula_over_crlb": "formula / bound",
    "ml_over_crlb": "ML / bound",
}


def accuracy_table(pulsar_names=pulsars.PAPER_PULSARS, n_trials=2000, rng=0, area_m2=1.0,
                   t_obs=500.0, background_ph_cm2_s=0.005, xcorr_trials=300, cache=False):
    """Ranging accuracy per pulsar: the paper, its formula, the bound and two Monte Carlos.

    For each pulsar (1 sigma, m): the main paper's quoted value
    (:data:`~xnavlab.mars.timing.pulsars.PAPER_RANGING_M`, ``None`` for another pulsar), the Sheikh
    et al. (2006) formula the paper used (:func:`~xnavlab.mars.timing.pulsars.ranging_accuracy`),
    the Poisson Cramer-Rao bound
    (:func:`ranging_crlb`), the standard deviation of the maximum-likelihood TOA over
    ``n_trials`` simulated folds (:func:`monte_carlo_ml_toa`) with its 95 % interval (chi-square,
    ``n_trials - 1`` degrees of freedom) and the fraction of its errors beyond four bounds,
    and that of the package's cross-correlation estimator
    (:func:`~xnavlab.mars.timing.pulsars.monte_carlo_toa`, ``xcorr_trials`` folds).

    Measured (``n_trials=50000``): the ML scatter is 0.996, 1.027, 1.071 and 0.996 times
    the bound for B0531+21, B1937+21, B1957+20, B1821-24; B1957+20, the faintest, is in the
    threshold regime (0.17 % of its folds beyond four bounds). With the default 2000 trials
    a ratio is known to about +-3 % (B1957+20's tail: +-4 %).

    Parameters
    ----------
    pulsar_names : sequence of str or Pulsar
        Catalogue names, ``.par`` paths or Pulsars
        (:func:`~xnavlab.mars.timing.pulsars.check_names`).
    n_trials : int
        Monte Carlo trials of the ML estimator per pulsar.
    rng : numpy.random.Generator or int
        One generator draws every trial, pulsar after pulsar (ML, then cross-correlation).
    area_m2, t_obs, background_ph_cm2_s : float
        As :func:`toa_crlb`.
    xcorr_trials : int
        Trials of the cross-correlation estimator (slower: one fold at a time); 0 skips
        it (``xcorr_m`` is then ``None``).
    cache : bool
        Read the rows from the disk cache, or compute and store them there (keyed by the
        arguments, each pulsar by all its parameters, and the code,
        :func:`xnavlab.core.diskcache.entry_path`); ``rng`` must then be an int. The default
        table takes about 10-20 s to compute.

    Returns
    -------
    list of dict
        One row per pulsar, keys :data:`ACCURACY_COLUMNS`.

    Examples
    --------
    >>> rows = accuracy_table(["B1821-24"], n_trials=40, xcorr_trials=0)
    >>> rows[0]["paper_m"], round(rows[0]["formula_m"]), round(rows[0]["crlb_m"])
    (325.0, 326, 381)
    """
    cache = check_bool("cache", cache)
    n_trials = check_int("n_trials", n_trials, 2, 10**6)
    xcorr_trials = check_int("xcorr_trials", xcorr_trials, 0, 10**6)
    if xcorr_trials == 1:
        raise ValueError("xcorr_trials must be 0 (skip) or at least 2")
    pulsar_names = pulsars.check_names(pulsar_names, "pulsar_names")
    if cache:
        if isinstance(rng, bool) or not isinstance(rng, int | np.integer):
            raise ValueError(f"rng must be an int seed when cache=True (a key), got {rng!r}")
        ps = tuple(pulsars.get(n) for n in pulsar_names)  # keyed and computed as given, not by name
        parts = (tuple(map(repr, ps)), n_trials, int(rng), float(area_m2), float(t_obs),
                 float(background_ph_cm2_s), xcorr_trials)
        path = entry_path("accuracy-table", parts, modules=(__name__,), suffix=".json")
        try:
            return json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):  # missing or unreadable: computed and stored
            rows = accuracy_table(ps, n_trials, int(rng), area_m2, t_obs,
                                  background_ph_cm2_s, xcorr_trials)
            store(path, lambda f: f.write(json.dumps(rows).encode()))
            return rows
    rng = make_rng(rng)
    lo = math.sqrt(chi2_ppf(0.025, n_trials - 1) / (n_trials - 1))
    hi = math.sqrt(chi2_ppf(0.975, n_trials - 1) / (n_trials - 1))
    rows = []
    for name in pulsar_names:
        p = pulsars.get(name)
        args = (area_m2, t_obs, background_ph_cm2_s)
        formula = pulsars.ranging_accuracy(p, *args)
        bound = ranging_crlb(p, *args)
        err = C * monte_carlo_ml_toa(p, n_trials, *args, rng=rng)
        ml = float(np.std(err, ddof=1))
        xc = None
        if xcorr_trials:
            xc = C * float(np.std(pulsars.monte_carlo_toa(p, xcorr_trials, *args, rng=rng), ddof=1))
        rows.append({"pulsar": p.name, "paper_m": pulsars.PAPER_RANGING_M.get(p.name),
                     "formula_m": formula, "crlb_m": bound, "ml_m": ml,
                     "ml_lo_m": ml / hi, "ml_hi_m": ml / lo,
                     "ml_beyond_4": float(np.mean(np.abs(err) > 4.0 * bound)), "xcorr_m": xc,
                     "formula_over_crlb": formula / bound, "ml_over_crlb": ml / bound})
    return rows


def accuracy_html(rows, digits=4):
    """:func:`accuracy_table`'s rows as the book's HTML table (every cell escaped).

    ``rows`` must be a list of :func:`accuracy_table` rows; anything else is one ValueError
    naming ``rows`` or ``rows[i]``.

    Examples
    --------
    >>> rows = accuracy_table(["B0531+21"], n_trials=10, xcorr_trials=0)
    >>> "Cramer-Rao bound (m)" in accuracy_html(rows)
    True
    """
    from xnavlab.core.plotting import html_table

    rows = _rows(rows)
    return html_table(list(ACCURACY_COLUMNS.values()),
                      [[r[k] for k in ACCURACY_COLUMNS] for r in rows], digits=digits)


def _rows(rows, keys=tuple(ACCURACY_COLUMNS)):
    """``rows`` as a non-empty list of :func:`accuracy_table` rows holding ``keys``, else one
    ValueError naming it."""
    if not isinstance(rows, list | tuple):  # a 0-d array or a number is no list of rows
        raise ValueError(f"rows must be a list of accuracy_table rows, got {shown(rows)}")
    rows = check_records("rows", rows, keys, "accuracy_table row")
    if not rows:
        raise ValueError("rows must hold at least one pulsar's row, got an empty list")
    return rows


def plot_accuracy(rows):
    """:func:`accuracy_table`'s rows as a figure: each accuracy over the bound, per pulsar.

    One marker per estimate of a pulsar's ranging accuracy, divided by its Cramer-Rao bound
    (the line at 1): the paper's value, the Sheikh et al. (2006) formula, the
    maximum-likelihood Monte Carlo with its 95 % interval and, where the rows have it, the
    cross-correlation Monte Carlo. A value below the line is an accuracy no unbiased TOA
    reaches.

    Parameters
    ----------
    rows : list of dict
        :func:`accuracy_table`'s rows.

    Returns
    -------
    matplotlib.figure.Figure
        Not registered with pyplot.

    Examples
    --------
    >>> fig = plot_accuracy(accuracy_table(["B1821-24"], n_trials=20, xcorr_trials=0))
    >>> fig.axes[0].get_ylabel()
    'ranging accuracy / Cramer-Rao bound'
    """
    from matplotlib.figure import Figure

    rows = _rows(rows, ("pulsar", "paper_m", "formula_m", "crlb_m", "ml_m", "ml_lo_m", "ml_hi_m",
                        "xcorr_m"))  # what the figure draws
    fig = Figure(figsize=(7.0, 3.4), layout="constrained")
    ax = fig.subplots()
    x = np.arange(len(rows))
    bound = np.array([r["crlb_m"] for r in rows])
    ax.axhline(1.0, color="k", lw=1.0, label="Cramer-Rao bound")
    ax.bar(x - 0.2, [r["formula_m"] for r in rows] / bound, 0.3, color="C0", alpha=0.6,
           label="formula (Sheikh et al. 2006)")
    paper = [(i, r["paper_m"] / r["crlb_m"]) for i, r in enumerate(rows) if r["paper_m"]]
    if paper:
        ax.plot([i - 0.2 for i, _ in paper], [v for _, v in paper], "kx", ms=8, mew=2,
                label="the paper's value")
    ml = np.array([r["ml_m"] for r in rows]) / bound
    err = np.array([[r["ml_m"] - r["ml_lo_m"], r["ml_hi_m"] - r["ml_m"]] for r in rows]).T
    ax.errorbar(x + 0.15, ml, err / bound, fmt="o", color="C3", capsize=3,
                label="maximum likelihood, Monte Carlo (95 %)")
    xc = [(i, r["xcorr_m"] / r["crlb_m"]) for i, r in enumerate(rows) if r["xcorr_m"]]
    if xc:
        ax.plot([i + 0.3 for i, _ in xc], [v for _, v in xc], "s", color="C2", ms=5,
                label="cross-correlation, Monte Carlo")
    ax.set_xticks(x, [r["pulsar"] for r in rows])
    ax.set(ylabel="ranging accuracy / Cramer-Rao bound", xlim=(-0.6, len(rows) - 0.4))
    top = max(1.25, float(np.max(ml)) + 0.1)
    ax.set_ylim(0.0, top * 1.45)
    ax.legend(fontsize=8, loc="upper center", ncols=2)
    return fig


def xnav_noise_sigma(kind="paper", pulsar_names=pulsars.PAPER_PULSARS, area_m2=1.0,
                     t_obs=500.0, background=0.005, efficiency=1.0):
    """XNAV delay noise per pulsar, s, for a noise model of :data:`XNAV_NOISE`.

    ``"paper"``: the ranging accuracy of Sheikh et al. (2006) over c (the main paper's set-up,
    :func:`xnavlab.mars.models.sensors.xnav_sigma`); ``"crlb"``: the Poisson Cramer-Rao bound
    :func:`toa_crlb`, divided by ``efficiency`` (1: an estimator that reaches the bound, as
    the ML one does at these rates; 0.8: a TOA variance 1.25 times the bound's).

    Parameters
    ----------
    kind : {"paper", "crlb"}
    pulsar_names : sequence of str
    area_m2 : float
        Effective area, m^2, in [1e-6, 1e3].
    t_obs : float
        Integration time, s, in [1e-6, 1e7].
    background : float
        Diffuse background, ph/cm^2/s, in [0, 10].
    efficiency : float
        Statistical efficiency of the TOA estimator, (0, 1]; ``"crlb"`` only.

    Returns
    -------
    ndarray, shape (k,)
        1-sigma delay noise, s.

    Examples
    --------
    >>> np.round(xnav_noise_sigma("crlb") * C).astype(int).tolist()
    [99, 454, 2637, 381]
    """
    check_choice("kind", kind, XNAV_NOISE)
    eff = check_real("efficiency", efficiency, 0.0, 1.0, lo_open=True)
    background = check_real("background", background, 0.0, 10.0)  # named here, not as pulsars'
    names = list(pulsars.check_names(pulsar_names, "pulsar_names"))
    if kind == "paper":
        if eff != 1.0:
            raise ValueError("efficiency applies to kind='crlb' only")
        return np.array([pulsars.toa_sigma(p, area_m2, t_obs, background) for p in names])
    return np.array([toa_crlb(p, area_m2, t_obs, background) for p in names]) / math.sqrt(eff)
