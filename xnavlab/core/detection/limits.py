"""What no detector can beat: Neyman-Pearson limits on the detection probability of a fault.

A detector that watches a subsystem continuously at a design false-alarm rate ``F`` per day
cannot find every fault: a fault that is small, or short, leaves too little evidence in the
samples it touches. This module computes an *upper bound* on the probability that *any*
detector with that false-alarm rate alarms within the first ``n`` samples of a fault, so that
a Monte Carlo cell of chapter 9 can be compared with what is possible, not only with the other
detectors.

The bound gives the detector everything it could wish for: it knows the onset, the fault's
shape and size, and the noise model; it only has to decide, from the ``n`` samples after the
onset, between "no fault" and "this fault". By the Neyman-Pearson lemma the likelihood-ratio
test is then the most powerful test of its size. Its size: a detector whose alarms come at
``F`` per day over ``N`` samples a day alarms in a given window of ``n`` samples, without a
fault, with probability about ``F n / N`` (:func:`window_false_alarm`); a detector that did
better on every window would have a lower rate. Everything a real detector lacks (the onset,
the shape) only lowers its probability, and so does the filter absorbing part of a slow fault
into its state; the bound is therefore optimistic, and a measured probability below it is
not by itself a defect, while a requirement above it cannot be met by any detector.

Two fault classes have closed or cheap forms, for whitened innovations ``z_c[i]`` (unit
variance, independent) of ``m`` components:

``mean`` (a step or a drift, :func:`mean_shift_pd_limit`)
    ``z_c[i] ~ N(mu_c[i], 1)``: the test statistic ``sum mu z`` is normal, and
    ``Pd = Phi(||mu|| - Phi^-1(1 - alpha))``.
``variance`` (a noise increase, :func:`noise_pd_limit`)
    ``z_c[i] ~ N(0, r_c^2)``: the likelihood ratio is ``sum_c w_c sum_i z_c[i]^2`` with
    ``w_c = 1 - r_c^-2``, a weighted sum of chi-squares, whose quantiles are computed by
    Monte Carlo (a seeded :class:`numpy.random.Generator`).
"""

from __future__ import annotations

import numpy as np

from xnavlab.core.distributions import norm_cdf, norm_isf
from xnavlab.core.validate import check_finite_array, check_int, check_real, make_rng, shown

__all__ = ["MAX_SAMPLES", "window_false_alarm", "mean_shift_pd_limit", "ramp_means", "noise_pd_limit"]

#: The most samples or draws an array of these limits holds: 10**7 float64 rows are 80 MB a
#: component, past any detector window (a year of 3 s samples) and any useful precision.
MAX_SAMPLES = 10**7


def window_false_alarm(rate_per_day, samples_per_day, n):
    """Probability that a detector with ``rate_per_day`` alarms in a given window of ``n`` samples.

    ``alpha = min(1, F n / N)`` (alarms spread over the day).

    Parameters
    ----------
    rate_per_day : float
        Design false alarms per day ``F``, > 0.
    samples_per_day : float
        Samples per day ``N``, > 0.
    n : int
        Window length, samples, >= 1.

    Returns
    -------
    float

    Examples
    --------
    >>> round(window_false_alarm(1.0, 172.8, 6), 4)    # XNAV, 6 samples of 500 s
    0.0347
    """
    F = check_real("rate_per_day", rate_per_day, 0.0, lo_open=True)
    N = check_real("samples_per_day", samples_per_day, 0.0, lo_open=True)
    n = check_int("n", n, 1)
    return min(1.0, F * n / N)


def _alpha(alpha):
    return check_real("alpha", alpha, 0.0, 1.0, lo_open=True, hi_open=True)


def mean_shift_pd_limit(mu, alpha):
    """Best detection probability of a known mean shift ``mu`` in unit white noise.

    Parameters
    ----------
    mu : array_like
        Means of the whitened samples under the fault (any shape: samples x components), in
        noise standard deviations.
    alpha : float
        False-alarm probability of the test, in (0, 1).

    Returns
    -------
    float
        ``Phi(||mu|| - Phi^-1(1 - alpha))`` (Neyman-Pearson).

    Examples
    --------
    >>> round(mean_shift_pd_limit([3.0], 0.05), 3)       # one sample of a 3-sigma step
    0.912
    """
    mu = check_finite_array("mu", mu)
    if mu.size == 0:   # no sample under the fault: no test, not a "Pd" of alpha
        raise ValueError(f"mu must hold at least one mean, got shape {mu.shape}")
    alpha = _alpha(alpha)
    d = float(np.sqrt(np.sum(np.square(mu))))
    return norm_cdf(d - norm_isf(alpha))  # Pd = Phi(||mu|| - z_(1-alpha))


def ramp_means(slopes, n, phase=1.0):
    """Means of ``n`` samples after a drift's onset: ``mu_c[i] = slope_c (i - 1 + phase)``.

    Parameters
    ----------
    slopes : array_like, shape (m,)
        Drift of each component, noise standard deviations per sample.
    n : int
        Samples, in [1, MAX_SAMPLES].
    phase : float
        Time of the first sample after the onset, in sample intervals, in (0, 1]; 1 (the
        default, the latest first sample) gives the largest means.

    Returns
    -------
    ndarray, shape (n, m)

    Examples
    --------
    >>> ramp_means([0.5], 3).ravel().tolist()
    [0.5, 1.0, 1.5]
    """
    slopes = np.atleast_1d(check_finite_array("slopes", slopes))
    if slopes.ndim != 1 or slopes.size == 0:
        raise ValueError(f"slopes must be a 1-D array of at least one component's drift, got "
                         f"shape {slopes.shape}")
    n = check_int("n", n, 1, MAX_SAMPLES)
    phase = check_real("phase", phase, 0.0, 1.0, lo_open=True)
    i = np.arange(n, dtype=float)[:, None]
    return slopes[None, :] * (i + phase)


def noise_pd_limit(ratios, n, alpha, *, draws=200_000, rng=0):
    """Best detection probability of a known noise increase from ``n`` samples.

    Parameters
    ----------
    ratios : array_like, shape (m,)
        Faulty over nominal standard deviation of each component, >= 1 (1: unaffected).
    n : int
        Samples the fault lasts (or that the detector may use), in [1, MAX_SAMPLES].
    alpha : float
        False-alarm probability of the test, in (0, 1).
    draws : int
        Monte Carlo draws for the quantile and the probability (default 200,000: about
        +-0.001), in [1000, MAX_SAMPLES].
    rng : int or numpy.random.Generator
        Seed or generator of the draws.

    Returns
    -------
    float
        Probability that the likelihood-ratio statistic ``sum_c w_c chi2_n,c`` with
        ``w_c = 1 - r_c^-2`` exceeds its ``1 - alpha`` quantile under the fault.

    Examples
    --------
    >>> p = noise_pd_limit([3.0], 6, 0.0347)             # 3x the noise for 6 samples
    >>> round(p, 2)
    0.96
    """
    r = np.atleast_1d(check_finite_array("ratios", ratios))
    if r.ndim != 1 or r.size == 0 or np.any(r < 1.0):   # no component: no test, not a "Pd" of alpha
        raise ValueError(f"ratios must be a 1-D array of at least one value >= 1, got {shown(r)}")
    n = check_int("n", n, 1, MAX_SAMPLES)
    alpha = _alpha(alpha)
    draws = check_int("draws", draws, 1000, MAX_SAMPLES)
    g = make_rng(rng)
    w = 1.0 - 1.0 / np.square(r)                        # log LR = sum_c w_c / 2 sum_i z^2 + const
    if not np.any(w > 0.0):
        return float(alpha)
    q0 = g.chisquare(n, size=(draws, r.size)) @ w       # no fault: z ~ N(0, 1)
    thr = np.quantile(q0, 1.0 - alpha)
    q1 = (g.chisquare(n, size=(draws, r.size)) * np.square(r)) @ w   # fault: z ~ N(0, r^2)
    return float(np.mean(q1 > thr))
