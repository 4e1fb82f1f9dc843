"""Singularities across scales: modulus maxima, Lipschitz exponents, the CWT (paper eqs. (7)-(8)).
"""

from __future__ import annotations

import math

import numpy as np
import pywt

from xnavlab.core.validate import check_choice, check_finite_array, check_int, check_real, check_shape, shown

__all__ = [
    "modulus_maxima",
    "lipschitz_exponent",
    "cwt",
]

# --------------------------------------------------------------------------------------------
# Singularities across scales (chapter): modulus maxima, Lipschitz exponents, CWT
# --------------------------------------------------------------------------------------------

def modulus_maxima(w, threshold=0.0):
    """Local maxima of ``|w|`` along the last axis (the time axis), per scale.

    Parameters
    ----------
    w : array_like, shape (n_scales, N) or (N,)
        Wavelet coefficients (CWT or undecimated details).
    threshold : float
        Only maxima with ``|w| > threshold`` count.

    Returns
    -------
    ndarray of bool, same shape as ``w``
        True where ``|w[n]| >= |w[n-1]|``, ``|w[n]| > |w[n+1]|`` and ``|w[n]| > threshold``.

    Examples
    --------
    >>> modulus_maxima([0.0, 1.0, -3.0, 0.5, 0.0, 2.0, 0.0]).astype(int).tolist()
    [0, 0, 1, 0, 0, 1, 0]
    """
    w = check_finite_array("w", w)
    if w.ndim == 0 or w.shape[-1] == 0:
        raise ValueError(f"w must have shape (N,) or (n_scales, N) with N >= 1, got shape {w.shape}")
    threshold = check_real("threshold", threshold, 0.0)
    a = np.abs(w)
    left = np.concatenate([np.full(a.shape[:-1] + (1,), np.inf), a[..., :-1]], axis=-1)
    right = np.concatenate([a[..., 1:], np.full(a.shape[:-1] + (1,), -np.inf)], axis=-1)
    left[..., 0] = -np.inf
    return (a >= left) & (a > right) & (a > threshold)


def lipschitz_exponent(w, scales, index, cone=None):
    """Lipschitz (Hoelder) exponent at sample ``index`` from the decay of the maxima across scales.

    For an L2-normalised wavelet with enough vanishing moments, the maximum of ``|W(s, u)|``
    in the cone ``|u - index| <= C s`` behaves as ``A s^(alpha + 1/2)`` (Mallat & Hwang 1992);
    ``alpha`` is the slope of ``log2 max|W|`` against ``log2 s``, minus 1/2. A step has
    ``alpha = 0``, a ramp's kink ``1``, a Dirac spike ``-1``.

    Parameters
    ----------
    w : array_like, shape (n_scales, N)
        Coefficients at the given scales (e.g. centred undecimated details, or :func:`cwt`).
    scales : array_like, shape (n_scales,)
        Scales in samples (``2^j`` for dyadic details), positive, at least two distinct.
    index : int
        Sample of the singularity.
    cone : array_like, shape (n_scales,), optional
        Half-width of the search window per scale, samples, > 0; default ``3 * scales``.

    Returns
    -------
    float

    Raises
    ------
    ValueError
        When the maximum of ``|w|`` in the cone at some scale is 0 or below 1e-12 of the
        largest ``|w|`` (a constant signal, no singularity there): its logarithm is no decay.

    Examples
    --------
    >>> n = np.arange(-512, 512)
    >>> s = 2.0 ** np.arange(1, 6)
    >>> w = cwt(np.where(n >= 0, 1.0, 0.0), s, "gaus1")
    >>> abs(round(lipschitz_exponent(w, s, 512), 1))
    0.0
    """
    w = check_finite_array("w", w)
    if w.ndim != 2 or w.shape[0] < 2 or w.shape[1] < 1:
        raise ValueError(f"w must have shape (n_scales, N) with n_scales >= 2 and N >= 1, got "
                         f"shape {w.shape}")
    scales = _scales(scales, w.shape[0])
    if np.unique(scales).size < 2:  # the slope over log2(scale) needs two distinct scales
        raise ValueError(f"scales must hold at least two distinct scales (the exponent is a "
                         f"slope over log2(scale)), got {shown(scales.tolist())}")
    index = check_int("index", index, 0, w.shape[1] - 1)
    cone = 3.0 * scales if cone is None else check_shape("cone", cone, (w.shape[0],),
                                                          "one half-width a scale of w")
    if np.any(cone <= 0.0):  # a negative half-width leaves no sample to search
        raise ValueError(f"cone must be positive half-widths (samples), one per scale, got "
                         f"{float(cone.min()):g}")
    half = [int(math.ceil(c)) for c in cone]
    peaks = np.array([np.abs(row[max(0, index - h):index + h + 1]).max()
                      for row, h in zip(w, half, strict=True)])
    _check_peaks(peaks, scales, index, float(np.abs(w).max()))
    slope = np.polyfit(np.log2(scales), np.log2(peaks), 1)[0]
    return float(slope - 0.5)


#: The smallest cone maximum :func:`lipschitz_exponent` fits, relative to the largest ``|w|``
#: (below it the maxima are rounding, and their log an exponent of nothing).
_PEAK_FLOOR = 1e-12


def _check_peaks(peaks, scales, index, top):
    """ValueError naming ``w``, the scales and ``index`` when a cone maximum is 0 or below
    ``_PEAK_FLOOR`` times ``top`` (the largest ``|w|``): its log2 was floored at 1e-300."""
    low = peaks <= _PEAK_FLOOR * top
    if not low.any():
        return
    at = ("scale " if low.sum() == 1 else "scales ") + ", ".join(f"{a:g}" for a in scales[low])
    what = "0" if not peaks[low].any() else \
        f"at most {peaks[low].max():.3g}, below {_PEAK_FLOOR:g} of its largest |w| ({top:.3g}),"
    raise ValueError(f"w is {what} in its cone at {at}: no singularity at index {index} "
                     f"(the exponent is the slope of log2 of the cone's maximum over log2(scale))")


def _scales(scales, n=None):
    """Scales as a 1-D array of positive numbers (``n`` of them when given), else ValueError."""
    scales = check_finite_array("scales", scales)
    if scales.ndim != 1 or scales.size == 0 or n is not None and scales.size != n:
        want = "at least one" if n is None else f"{n} (one per row of w)"
        raise ValueError(f"scales must be a 1-D array of {want} positive scales, got shape {scales.shape}")
    if np.any(scales <= 0):
        raise ValueError(f"scales must be positive, got {scales.min():g}")
    return scales


#: The longest wavelet :func:`cwt` samples at one scale (``scale * support`` samples, 80 MB).
_KERNEL_MAX = 1e7


def cwt(x, scales, wavelet="gaus1", dt=1.0):
    """Continuous wavelet transform, paper eqs. (7)-(8), via ``pywt.cwt``.

    ``S(a, b) = a^(-1/2) integral s(t) psi((t - b)/a) dt`` sampled at ``b = n dt`` (PyWavelets
    computes it by convolution with the integrated wavelet, so the normalisation is eq. (8)'s
    ``a^(-1/2)`` with ``a`` in samples). ``"gaus1"`` (first derivative of a Gaussian) gives
    maxima at edges, the choice of Mallat & Hwang (1992); ``"mexh"`` at peaks.

    Parameters
    ----------
    x : array_like, shape (N,)
        Signal sampled every ``dt``.
    scales : array_like, shape (n_scales,)
        Scales ``a`` in samples, in [1 / support, 1e7 / support] with the wavelet's support
        (10 for ``"gaus1"``: [0.1, 1e6]).
    wavelet : str
        A PyWavelets continuous wavelet, real-valued (``"gaus1"``, ``"mexh"``, ``"morl"``, ...).
    dt : float
        Sampling interval, s, > 0 (only scales the frequencies PyWavelets reports, which are
        not returned: unused here).

    Returns
    -------
    ndarray, shape (n_scales, N)

    Examples
    --------
    >>> cwt(np.r_[np.zeros(64), np.ones(64)], [2.0, 4.0]).shape
    (2, 128)
    """
    x = check_finite_array("x", x)
    if x.ndim != 1 or x.size == 0:
        raise ValueError(f"x must be a 1-D signal of at least one sample, got shape {x.shape}")
    scales = _scales(scales)
    check_choice("wavelet", wavelet, [w for w in pywt.wavelist(kind="continuous")
                                      if not w.startswith(("cgau", "cmor", "shan", "fbsp"))])
    # the wavelet at a scale spans scale * support samples (pywt): at least 2 (one difference),
    # at most 1e7 (80 MB, as the other series here)
    c = pywt.ContinuousWavelet(wavelet)
    support = c.upper_bound - c.lower_bound
    lo, hi = 1.0 / support, _KERNEL_MAX / support
    if not np.all((scales >= lo) & (scales <= hi)):
        bad = scales[(scales < lo) | (scales > hi)][0]
        raise ValueError(f"scales must lie in [{lo:g}, {hi:g}] samples for the {wavelet!r} "
                         f"wavelet (its support, {support:g}, times a scale: at least 1 sample "
                         f"step, at most {_KERNEL_MAX:g} samples), got {bad:g}")
    check_real("dt", dt, 0.0, lo_open=True)
    # dt scales only the frequencies pywt reports, which are not returned: it is not passed on
    # (pywt's 1 / (scale dt) overflowed for a subnormal dt)
    coefs, _ = pywt.cwt(x, scales, wavelet)
    return np.asarray(coefs)


