"""One folded window of photons turned into a range along the line of sight.

A spacecraft at distance ``x`` from the SSB along the unit vector ``n`` to a pulsar receives
each pulse ``x / c`` before the SSB does (chapter 2's sign: the delay
``Delta t = t_SSB - t_SC = n . R / c = x / c``). Folding the photons of one window gives the
pulse profile displaced by ``-Delta t`` modulo the period ``P``; the cross-correlation with
the template (:func:`xnavlab.mars.timing.pulsars.estimate_phase_shift`) measures that displacement,
so a window measures ``x`` modulo the pulse "wavelength" ``c P``. The cycle is taken from a
prediction ``x_ref`` (the filter's), which must be known to better than ``c P / 2``.

The folded counts are drawn bin by bin (:func:`xnavlab.mars.timing.pulsars.simulate_folded`: Poisson
counts per phase bin, the distribution of a folded Poisson photon stream), with the delay held
at its value in the middle of the window: folding with the predicted motion removes the rest.

Units: m, s. Pulsars by name from :data:`xnavlab.mars.timing.pulsars.CATALOGUE`.

Examples
--------
>>> x = 2.0e11                       # m from the SSB along n
>>> z = fold_range(x, x + 3.0e6, "B0531+21", exposure=10.0, rng=1)
>>> bool(abs(z - x) < 5 * range_sigma("B0531+21", 10.0))
True
"""

from __future__ import annotations

import functools
import math

from xnavlab.core.constants import C
from xnavlab.core.validate import check_real, make_rng
from xnavlab.mars.timing import pulsars

__all__ = ["nbins_for", "wavelength", "fold_range", "range_sigma"]


def nbins_for(pulsar):
    """Phase bins of the fold: the power of two giving at least 12 bins per pulse width.

    Examples
    --------
    >>> nbins_for("B0531+21"), nbins_for("B1937+21")
    (256, 1024)
    """
    return 2 ** math.ceil(math.log2(12.0 / pulsars.get(pulsar).duty_cycle))


def wavelength(pulsar):
    """The range one pulse period spans, ``c P``, m: a fold measures ``x`` modulo it.

    Examples
    --------
    >>> round(wavelength("B0531+21") / 1e3)   # km
    10043
    """
    return C * pulsars.get(pulsar).period


def fold_range(x, x_ref, pulsar="B0531+21", exposure=10.0, rng=None, area_m2=1.0):
    """Range along ``n`` measured by folding one window of photons, m.

    Parameters
    ----------
    x : float
        True distance of the spacecraft from the SSB along ``n`` (mid-window), m, in
        [-1e15, 1e15].
    x_ref : float
        Predicted distance, m, in [-1e15, 1e15]; the cycle nearest it is chosen (error
        below ``c P / 2``).
    pulsar : str or xnavlab.mars.timing.pulsars.Pulsar
        Default the Crab, B0531+21.
    exposure : float
        Window length, s, in [1e-3, 1e5].
    rng : numpy.random.Generator or int, optional
    area_m2 : float
        Detector area, m^2 (background 0.005 ph/cm^2/s, as chapter 1).

    Returns
    -------
    float
        ``c Delta t`` on the cycle nearest ``x_ref``, m.
    """
    p = pulsars.get(pulsar)
    x, x_ref = _check_distance("x", x), _check_distance("x_ref", x_ref)
    exposure = _check_exposure(exposure)
    nbins = nbins_for(p)
    shift = (-x / C) % p.period  # the pulse reaches the spacecraft x / c early
    counts = pulsars.simulate_folded(p, exposure, area_m2, nbins=nbins, rng=make_rng(rng), shift=shift)
    rho = -pulsars.estimate_phase_shift(counts, _template(nbins, p.duty_cycle)) * C * p.period
    lam = wavelength(p)
    return rho + lam * round((x_ref - rho) / lam)  # x = c Delta t + k c P, k nearest x_ref


def _check_distance(name, x):
    # |x| <= 1e15 m (about 6,700 au): the float spacing there, 0.125 m, stays far below the
    # ranging noise (821 m for the Crab in 10 s); at 1e20 m it is 16 km and swamps it.
    return check_real(name, x, -1e15, 1e15)


def _check_exposure(exposure):
    # At least 1 ms, a fraction of the fastest period: shorter windows fold no photon and
    # a tiny one (1e-300 s) divides by zero in the TOA sigma.
    return check_real("exposure", exposure, 1e-3, 1e5)


@functools.lru_cache(maxsize=8)
def _template(nbins, duty):
    return pulsars.binned_template(nbins, duty)


def range_sigma(pulsar="B0531+21", exposure=10.0, area_m2=1.0):
    """Standard deviation of :func:`fold_range`, m: ``c`` times the estimator's TOA sigma.

    The first-order sigma of the cross-correlation estimator on the fold's bins
    (:func:`xnavlab.mars.timing.pulsars.xcorr_toa_sigma`, chapter 1); it falls as
    ``exposure ** -0.5``.

    Parameters
    ----------
    pulsar, area_m2
        As :func:`fold_range`.
    exposure : float
        Window length, s, in [1e-3, 1e5].

    Examples
    --------
    >>> round(range_sigma("B0531+21", 10.0))
    821
    """
    exposure = _check_exposure(exposure)
    return C * pulsars.xcorr_toa_sigma(pulsar, area_m2, exposure, nbins=nbins_for(pulsar))
