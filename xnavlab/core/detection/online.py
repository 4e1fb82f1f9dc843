"""Fault detection: Mallat's fast wavelet transform, wavelet singularity detectors, chi-square tests.

The main paper (Fan et al. 2016, section 2) detects sensor faults as *singularities* of the
measurement series: local modulus maxima of the wavelet detail coefficients, db3, five levels.
The package (:mod:`xnavlab.core.detection`) holds

- :func:`~.mallat.mallat_dwt`, :func:`~.mallat.mallat_idwt`, :func:`~.mallat.mallat_wavedec`,
  :func:`~.mallat.mallat_waverec`: Mallat's fast decomposition and reconstruction, paper
  eqs. (9)-(10), written out in numpy for the book and tested against PyWavelets to 1e-12;
- :func:`~.mallat.detail_signals`: the db3 5-level detail signals reconstructed to full
  length (what the paper's Fig. 5 shows), via PyWavelets;
- :func:`causal_filters`, :func:`causal_details`: the undecimated (a trous, dyadic) detail
  coefficients as causal FIR filters, the sliding window of the online detector;
- :class:`WaveletDetector` (online, one sample at a time) and :func:`~.batch.wavelet_detect`
  (batch over a whole series, identical decisions), with thresholds from robust MAD noise
  estimates;
- :func:`~.singularity.modulus_maxima`, :func:`~.singularity.lipschitz_exponent`,
  :func:`~.singularity.cwt`: singularities across scales (paper eqs. (7)-(8)) for the chapter;
- :class:`~.chisquare.Chi2Detector`, :func:`~.chisquare.chi2_detect`: the baseline innovation
  chi-square test with the same onset/end reporting (:class:`Event`).

Design decisions
----------------
Sliding window and boundary.
    The detector's detail coefficient of level ``j`` at sample ``n`` is the undecimated
    (dyadic, Mallat & Hwang 1992) wavelet coefficient computed by a causal FIR filter
    ``d_j[n] = sum_m g_j[m] x[n - m]`` whose length ``(2^j - 1)(F - 1) + 1`` (156 samples for
    db3, level 5) *is* the sliding window. The window holds exactly the filter's support, so
    no boundary extension is needed once it is full: the newest sample is never mirrored or
    wrapped, and online and batch give the same numbers. Before the window is full the past is
    extended with the first sample (a constant, which every detail filter maps to zero) and
    the detector is not armed. Undecimated rather than decimated coefficients make the
    response to a fault independent of where it falls on the dyadic grid, and cost one
    dot product per level per sample.
Thresholds and the false-alarm rate.
    Per level the noise is ``sigma_j = median(|d_j|) / 0.6745`` (Donoho & Johnstone 1994) on a
    fault-free training series. A sample alarms when any ``|d_j| > k sigma_j`` or when the
    variance test on level 1 fails (below). ``pfa`` is the design probability that a
    fault-free sample alarms; it is split equally over the ``J`` level tests and the variance
    test (Bonferroni), so ``k = Phi^-1(1 - pfa / (2 (J + 1)))``: ``k = 4.79`` for db3, five
    levels and the default ``pfa = 1e-5`` (8.6 false samples expected in 30 days at 3 s; the
    undecimated coefficients are correlated, so they come in clusters, about 1.6 samples an
    event (:func:`alarm_clusters`): about 6 isolations of one hold-off a month, cheap next to a
    missed fault). The union bound
    makes the realised rate at most ``pfa`` for Gaussian white noise; it is nearly tight (the
    measured rate is 0.8-1.0 ``pfa`` with known ``sigma_j``).
Variance test.
    A stuck (frozen) output or a noise increase is no singularity of the signal. The level-1
    coefficients of white noise at even lags are independent (orthonormal filters), so
    ``Q = sum_{i<w} (d_1[n - 2i] / sigma_1)^2`` is chi-square with ``w`` degrees of freedom; a
    sample alarms when ``Q`` falls outside the central ``1 - pfa/(J+1)`` interval.
Hold-off and clearing.
    An event opens at the first alarm (the *detected onset*). It stays open while alarms
    continue; it closes once ``holdoff`` samples in a row are free of alarms (default: the
    longest filter, or the variance window's span if longer, so that one singularity gives one
    event). The last alarm is the *detected end*; the detector clears ``holdoff`` samples
    later. A wavelet detector sees *changes*: a step or ramp longer than the hold-off shows as
    two events, one at its onset and one at its end, with the detector clear in between.

What it sees (db3, 5 levels, default ``pfa``; noise ``sigma`` per sample, white)
    A step of size ``A`` peaks at ``A * step_gain`` = 0.47 A (level 1) ... 1.61 A (level 5):
    sure to cross from about 3 sigma, found at the onset within 12 samples from 10 sigma and at
    the first sample from 20 sigma. A ramp's kink peaks at ``16.8 * rate * dt`` at level 5:
    only ramps faster than about ``0.29 sigma`` per sample show at their onset; slower drifts
    show only at their end (if they end in a jump). An outlier is caught from about 6 sigma.
    A stuck output or a noise increase is caught by the variance test (within about 60 samples
    for a stuck output, 12 for extra noise of 4 sigma).

Use in a navigation scenario
    The detector needs only the raw measurements, not the filter's state, so a scenario can run
    :func:`~.batch.wavelet_detect` once per sensor component over the whole series (0.06-0.1 s for 30
    days at 3 s, compiled: the a trous cascade and the tests in one pass) and hand
    ``Detection.faulty`` to the filter loop; :class:`WaveletDetector` gives the same flags one
    sample at a time (about 30 us per sample in numpy).
"""


from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field

import numpy as np
from numba import njit

from xnavlab.core.detection._tracked import TrackedDetector
from xnavlab.core.detection._wavelets import orthogonal_wavelet
from xnavlab.core.distributions import chi2_isf, chi2_ppf, norm_isf, norm_sf
from xnavlab.core.faults import MAX_SIZE
from xnavlab.core.validate import (
    check_finite_array,
    check_increasing,
    check_int,
    check_real,
    check_text,
    shown,
)

__all__ = [
    "MAD_SCALE",
    "Event",
    "Detection",
    "causal_filters",
    "causal_details",
    "step_gain",
    "mad_sigma",
    "threshold_multiplier",
    "false_alarm_probability",
    "events_from_alarms",
    "alarm_clusters",
    "signal_threshold_ratio",
    "EventTracker",
    "WaveletDetector",
]

#: ``median(|N(0, 1)|) = Phi^-1(0.75)``: the MAD of Gaussian noise is ``0.6745 sigma`` (Donoho &
#: Johnstone 1994); written out (``tests/core/test_online.py`` holds it against
#: :func:`~xnavlab.core.distributions.norm_ppf`) so that importing the detectors needs no scipy.
MAD_SCALE = 0.6744897501960817


# --------------------------------------------------------------------------------------------
# Causal undecimated details: the online detector's sliding window
# --------------------------------------------------------------------------------------------

def causal_filters(wavelet="db3", level=5):
    """Causal FIR filters ``g_j`` of the undecimated (a trous) detail coefficients, j = 1..level.

    ``g_1`` is ``dec_hi``; level ``j`` convolves the lowpass ``dec_lo`` upsampled by
    ``1, 2, ..., 2^(j-2)`` with ``dec_hi`` upsampled by ``2^(j-1)`` (Mallat's algorithm without
    the decimation). Each has unit norm and ``3`` vanishing moments for db3; the length of
    ``g_j`` is ``(2^j - 1)(F - 1) + 1``.

    Returns
    -------
    list of ndarray
        ``[g_1, ..., g_level]``.

    Examples
    --------
    >>> [len(g) for g in causal_filters("db3", 5)]
    [6, 16, 36, 76, 156]
    >>> bool(np.isclose(np.sum(causal_filters()[4] ** 2), 1.0))
    True
    """
    w = orthogonal_wavelet(wavelet)
    level = check_int("level", level, 1, 12)
    lo = np.array(w.dec_lo)
    hi = np.array(w.dec_hi)
    approx = np.array([1.0])
    out = []
    for j in range(level):
        step = 2 ** j
        hi_up = np.zeros((len(hi) - 1) * step + 1)
        hi_up[::step] = hi
        lo_up = np.zeros((len(lo) - 1) * step + 1)
        lo_up[::step] = lo
        out.append(np.convolve(approx, hi_up))
        approx = np.convolve(approx, lo_up)
    return out


def _filter_matrix(filters):
    L = len(filters[-1])
    G = np.zeros((len(filters), L))
    for j, g in enumerate(filters):
        G[j, :len(g)] = g                    # G[j, m] multiplies x[n - m]
    return G


def causal_details(x, wavelet="db3", level=5, origin=None):
    """Undecimated detail coefficients ``d_j[n] = sum_m g_j[m] x[n - m]`` of a whole series.

    Causal: ``d_j[n]`` uses samples up to ``n`` only. Samples before the start are taken equal
    to ``origin`` (every ``g_j`` sums to zero, so a constant past contributes nothing); the
    first ``len(g_level) - 1`` values are therefore warm-up values.

    Parameters
    ----------
    x : array_like, shape (N,)
        Measurement series.
    wavelet : str
        Default ``"db3"``.
    level : int
        Number of levels (default 5).
    origin : float, optional
        Subtracted before filtering (default ``x[0]``); a block of a longer series passes that
        series' first sample, and its details after the warm-up are then the same bits as the
        whole series'.

    Returns
    -------
    ndarray, shape (level, N)
        Row ``j - 1`` holds level ``j``, in the unit of ``x``.

    Examples
    --------
    >>> d = causal_details(np.r_[np.zeros(200), np.ones(200)])
    >>> d.shape, float(np.abs(d[:, :200]).max())
    ((5, 400), 0.0)
    """
    x = check_finite_array("x", x)
    if x.ndim != 1 or x.size < 1:
        raise ValueError(f"x must be a non-empty 1-D array, got shape {x.shape}")
    causal_filters(wavelet, level)                      # checks wavelet and level
    w = orthogonal_wavelet(wavelet)
    out = np.empty((level, x.size))
    _atrous(x - (x[0] if origin is None else check_real("origin", origin)), np.array(w.dec_lo),
            np.array(w.dec_hi), out)
    return out


@njit(cache=True, nogil=True)
def _atrous(y, lo, hi, out):
    """The a trous cascade of :func:`causal_details` in place in ``out`` (level, N):
    ``d_j = hi_(2^j) * a_j``, ``a_(j+1) = lo_(2^j) * a_j``, ``a_0 = y`` (``*_s``: the filter
    upsampled by ``s``, zero before the start), ``F`` taps a level instead of the equivalent
    filters' ``(2^j - 1)(F - 1) + 1``."""
    n = y.size
    f = lo.size
    a = y.copy()
    b = np.empty(n)
    for j in range(out.shape[0]):
        step = 1 << j
        for i in range(n):
            d = 0.0
            s = 0.0
            for m in range(f):
                k = i - m * step
                if k < 0:
                    break
                d += hi[m] * a[k]          # d_j[n] = sum_m hi[m] a_j[n - m 2^j]
                s += lo[m] * a[k]          # a_(j+1)[n] = sum_m lo[m] a_j[n - m 2^j]
            out[j, i] = d
            b[i] = s
        a, b = b, a


def step_gain(wavelet="db3", level=5):
    """Largest response of each level's detail to a unit step: ``max_n |sum_{m<=n} g_j[m]|``.

    A step of size ``A`` gives a detail of at most ``A * step_gain`` at level ``j``; with noise
    ``sigma`` per sample and threshold ``k sigma`` it is certain to cross at the peak when
    ``A > k sigma / step_gain`` (about ``2^(j/2)`` growth: the step is Lipschitz 0).

    Returns
    -------
    ndarray, shape (level,)

    Examples
    --------
    >>> np.round(step_gain("db3", 5), 2).tolist()
    [0.47, 0.55, 0.81, 1.13, 1.61]
    """
    return np.array([np.abs(np.cumsum(g)).max() for g in causal_filters(wavelet, level)])


# --------------------------------------------------------------------------------------------
# Thresholds
# --------------------------------------------------------------------------------------------

def mad_sigma(d, axis=-1):
    """Robust noise level ``median(|d|) / 0.6745`` (Donoho & Johnstone 1994), per row by default.

    Parameters
    ----------
    d : array_like
        Detail coefficients, shape (level, N) for one estimate per level (at least 1-D, at
        least one coefficient along ``axis``: the median of nothing is no noise level).
    axis : int
        Axis along which to take the median, in ``[-d.ndim, d.ndim - 1]``.

    Examples
    --------
    >>> d = np.random.default_rng(3).normal(0.0, 5000.0, (2, 100000))
    >>> np.round(mad_sigma(d) / 5000.0, 2).tolist()
    [1.0, 1.0]
    """
    d = check_finite_array("d", d)
    if d.ndim == 0:
        raise ValueError("d must be an array of detail coefficients (shape (N,) or (level, N)), "
                         "got a scalar")
    axis = check_int("axis", axis, -d.ndim, d.ndim - 1)
    if d.shape[axis] == 0:
        raise ValueError(f"d must hold at least one coefficient along axis {axis}, got shape {d.shape}")
    return np.median(np.abs(d), axis=axis) / MAD_SCALE


def threshold_multiplier(pfa, n_tests=6):
    """Multiplier ``k`` of the two-sided Gaussian tests so that ``n_tests`` of them alarm with
    total probability at most ``pfa`` per sample: ``k = Phi^-1(1 - pfa / (2 n_tests))``.

    ``pfa`` is in [1e-15, 1): below 1e-15 (one false sample in 30 million years at 1 Hz) no
    design asks for, and 5e-324 underflowed ``pfa / (2 n_tests)`` to 0.

    Examples
    --------
    >>> round(threshold_multiplier(1e-5, 6), 2)
    4.79
    """
    pfa = check_real("pfa", pfa, 1e-15, 1.0, hi_open=True)
    n_tests = check_int("n_tests", n_tests, 1)
    return norm_isf(pfa / (2 * n_tests))


def false_alarm_probability(k, n_tests=6):
    """Union bound on the per-sample false-alarm probability: ``n_tests * 2 (1 - Phi(k))``.

    Examples
    --------
    >>> f"{false_alarm_probability(threshold_multiplier(1e-4, 6), 6):.1e}"
    '1.0e-04'
    """
    k = check_real("k", k, 0.0, lo_open=True)
    n_tests = check_int("n_tests", n_tests, 1)
    return float(min(1.0, n_tests * 2.0 * norm_sf(k)))


# --------------------------------------------------------------------------------------------
# Events: onset, end, hold-off
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Event:
    """One detected fault interval.

    Attributes
    ----------
    onset : float
        Time of the first alarm, s: the detected onset.
    end : float
        Time of the last alarm, s: the detected end of the fault.
    cleared : float
        Time the detector cleared (``holdoff`` samples after ``end``), s; ``inf`` when the
        detector was still flagging at the end of the data.
    peak : float
        Largest ratio of a test statistic to its threshold during the event (> 1).
    test : str
        The test that reached ``peak``: ``"level 1"`` .. ``"level J"``, ``"variance"`` or
        ``"chi2"``.
    """

    onset: float
    end: float
    cleared: float
    peak: float
    test: str

    def as_dict(self, sensor, detector):
        """The scenario's JSON form: ``sensor``, ``detected_onset``, ``detected_end``, ``detector``.

        Examples
        --------
        >>> Event(10.0, 12.0, 20.0, 3.0, "level 2").as_dict("uv", "wavelet")["detected_end"]
        12.0
        """
        sensor = check_text("sensor", sensor)
        detector = check_text("detector", detector)
        return {"sensor": sensor, "detected_onset": self.onset, "detected_end": self.end,
                "detector": detector}


@dataclass
class Detection:
    """Result of a batch detector over a whole series.

    Attributes
    ----------
    t : ndarray, shape (N,)
        Sample times, s.
    ratio : ndarray, shape (N,)
        Largest test statistic divided by its threshold; an armed sample alarms when > 1.
    alarm : ndarray of bool, shape (N,)
        Armed samples whose ``ratio`` exceeds 1.
    faulty : ndarray of bool, shape (N,)
        Detector state after each sample (from an event's onset until it clears).
    armed : ndarray of bool, shape (N,)
        Samples at which the detector decides (window full, trained).
    events : list of Event
    data : dict
        Detector-specific arrays (``details``, ``z``, ``variance``; ``statistic``).
    """

    t: np.ndarray
    ratio: np.ndarray
    alarm: np.ndarray
    faulty: np.ndarray
    armed: np.ndarray
    events: list
    data: dict = field(default_factory=dict, repr=False)

    @property
    def false_alarm_rate(self):
        """Fraction of armed samples that alarm (meaningful on fault-free data)."""
        return float(self.alarm[self.armed].mean()) if self.armed.any() else math.nan

    def first_onset_after(self, t0):
        """Detected onset of the first event starting at or after ``t0`` (s); inf if none.

        Examples
        --------
        >>> ev = Event(5.0, 6.0, 9.0, 2.0, "chi2")
        >>> Detection(np.zeros(0), *[np.zeros(0)] * 4, [ev]).first_onset_after(4.0)
        5.0
        """
        if isinstance(t0, bool) or not isinstance(t0, int | float | np.integer | np.floating) \
                or math.isnan(t0):
            raise ValueError(f"t0 must be a real number (s; -inf for any), got {t0!r}")
        for ev in self.events:
            if ev.onset >= t0:
                return ev.onset
        return math.inf


def _check_holdoff(holdoff):
    return check_int("holdoff", holdoff, 1, 10**9)  # samples; an int64 beyond overflows


def events_from_alarms(t, alarm, ratio, holdoff, tests=None):
    """Group alarms into events with a hold-off (pure batch form of :class:`EventTracker`).

    Two alarms ``holdoff`` samples apart or closer belong to one event; an event clears
    ``holdoff`` samples after its last alarm.

    Parameters
    ----------
    t : array_like, shape (N,)
        Sample times, s, strictly increasing.
    alarm : array_like of bool, shape (N,)
    ratio : array_like, shape (N,)
        Statistic / threshold per sample (for ``Event.peak``).
    holdoff : int
        Samples without alarm after which the detector clears.
    tests : sequence of str, shape (N,), optional
        Name of the test with the largest ratio at each sample.

    Returns
    -------
    events : list of Event
    faulty : ndarray of bool, shape (N,)

    Examples
    --------
    >>> a = np.array([0, 1, 0, 1, 0, 0, 0, 1, 0, 0], bool)
    >>> ev, faulty = events_from_alarms(np.arange(10.0), a, a * 2.0, holdoff=2)
    >>> [(e.onset, e.end, e.cleared) for e in ev], faulty.astype(int).tolist()
    ([(1.0, 3.0, 5.0), (7.0, 7.0, 9.0)], [0, 1, 1, 1, 1, 0, 0, 1, 1, 0])
    """
    t = check_finite_array("t", t)
    if t.ndim != 1:
        raise ValueError(f"t must be a 1-D array of sample times, got shape {t.shape}")
    alarm = _flags("alarm", alarm, None, "one per sample")
    ratio = check_finite_array("ratio", ratio, finite=False)
    if np.isnan(ratio).any():
        raise ValueError("ratio must not contain NaN")
    if ratio.ndim != 1:
        raise ValueError(f"ratio must be a 1-D array (one per sample), got shape {ratio.shape}")
    _one_length(t=t.size, alarm=alarm.size, ratio=ratio.size)
    check_increasing("t", t)  # else an event would end before its onset
    holdoff = _check_holdoff(holdoff)
    n = t.size
    if tests is not None:
        if isinstance(tests, str | bytes) or not hasattr(tests, "__getitem__") or \
                not hasattr(tests, "__len__"):
            raise ValueError(f"tests must be a sequence of test names (one per sample), got "
                             f"{shown(tests)}")
        if len(tests) != n:
            raise ValueError(f"tests must have length {n} (one name per sample, as t), got "
                             f"{len(tests)}")
    faulty = np.zeros(n, dtype=bool)
    idx = np.flatnonzero(alarm)
    if idx.size == 0:
        return [], faulty
    breaks = np.flatnonzero(np.diff(idx) > holdoff)
    starts = np.r_[idx[0], idx[breaks + 1]]
    ends = np.r_[idx[breaks], idx[-1]]
    events = []
    for s, e in zip(starts, ends, strict=True):
        c = e + holdoff
        faulty[s:min(c, n)] = True
        seg = slice(s, e + 1)
        p = s + int(np.argmax(ratio[seg]))
        events.append(Event(float(t[s]), float(t[e]), float(t[c]) if c < n else math.inf,
                            float(ratio[p]), str(tests[p]) if tests is not None else ""))
    return events, faulty


def _one_length(**sizes):
    """One ValueError naming the series whose length differs from the others' (which agree),
    or the last one when no two agree."""
    if len(set(sizes.values())) > 1:
        rest = {k: [v for j, v in sizes.items() if j != k] for k in sizes}
        odd = next((k for k in sizes if len(set(rest[k])) == 1), list(sizes)[-1])
        others = " and ".join(k for k in sizes if k != odd)
        raise ValueError(f"{odd} must have length {rest[odd][0]} (as {others}), got {sizes[odd]}")


def _flags(name, value, n, why):
    """``value`` as a 1-D array of flags (bools, or numbers 0 and 1; of length ``n`` unless
    None), else one ValueError naming ``name``: a list mixing bools and numbers is refused."""
    if np.ma.is_masked(value):  # np.asarray would use the masked flags (review 35m (5) 1)
        raise ValueError(f"{name} has masked entries (no flag to use: fill or drop them)")
    arr = np.asarray(value)
    ok = arr.dtype.kind == "b" or (arr.dtype.kind in "iuf" and np.all((arr == 0) | (arr == 1)))
    mixed = isinstance(value, list | tuple) and len({isinstance(v, bool | np.bool_) for v in value}) > 1
    if not ok or mixed or arr.ndim != 1 or n is not None and arr.size != n:
        size = "" if n is None else f" of length {n}"
        raise ValueError(f"alarm must be a 1-D array of flags (true/false, {why}){size}, got "
                         f"{shown(value)}".replace("alarm", name, 1))
    return arr.astype(bool)


def alarm_clusters(alarm, gap=1):
    """Clusters of alarms: flagged samples at most ``gap`` samples apart belong to one cluster.

    Undecimated detail coefficients are correlated over the filter's support, so one noise
    excursion past the threshold flags several samples in a row: the number of false *events*
    (isolations) is the number of clusters, not of flagged samples. ``gap = 1`` counts runs of
    consecutive flags; ``gap = len(causal_filters(wavelet, level)[-1])`` (156 for db3, five
    levels) joins flags closer than the longest filter's support (the detector's default
    hold-off: its events, :func:`events_from_alarms`).

    Parameters
    ----------
    alarm : array_like of bool, shape (N,)
    gap : int
        Largest index difference inside a cluster, ``>= 1``.

    Returns
    -------
    first, last, size : ndarray of int, shape (n_clusters,)
        First and last flagged index of each cluster and its number of flagged samples.

    Examples
    --------
    >>> a = np.array([0, 1, 1, 0, 1, 0, 0, 0, 1, 1], bool)
    >>> [c.tolist() for c in alarm_clusters(a)]
    [[1, 4, 8], [2, 4, 9], [2, 1, 2]]
    >>> [c.tolist() for c in alarm_clusters(a, gap=2)]
    [[1, 8], [4, 9], [3, 2]]
    """
    alarm = _flags("alarm", alarm, None, "one per sample")
    if alarm.size == 0:
        raise ValueError("alarm must hold at least one flag, got an empty array")
    gap = check_int("gap", gap, 1, 10**9)
    idx = np.flatnonzero(alarm)
    if idx.size == 0:
        return np.zeros(0, int), np.zeros(0, int), np.zeros(0, int)
    breaks = np.flatnonzero(np.diff(idx) > gap)  # a new cluster after a longer gap
    first = np.r_[idx[0], idx[breaks + 1]]
    last = np.r_[idx[breaks], idx[-1]]
    size = np.diff(np.r_[0, breaks + 1, idx.size])
    return first, last, size


def signal_threshold_ratio(x, sigma, wavelet="db3", level=5, pfa=1e-5, n_tests=None):
    """How close a noise-free signal's own details come to the thresholds, per level.

    ``max_n |d_j[n]| / (k sigma_j)`` over the series after the longest filter's warm-up, with
    ``d_j`` the causal undecimated details of the clean signal (:func:`causal_details`) and
    ``k`` :func:`threshold_multiplier`. A ratio well below 1 means the signal leaves that
    level's decisions to the noise; a ratio near 1 means the signal alone nearly alarms, and
    together with the noise it raises the false-alarm rate above the design.

    Parameters
    ----------
    x : array_like, shape (N,)
        The noise-free signal (e.g. a measurement model along the true trajectory).
    sigma : float or array_like, shape (level,)
        Per-level noise of the detector (white noise of sigma per sample: sigma at every
        level, the filters having unit norm; or a trained MAD estimate), each in
        [1e-100, MAX_SIZE] (:data:`xnavlab.core.faults.MAX_SIZE`, the measurement's SI unit:
        beyond any physical noise, and ``k sigma`` overflows near 1e308; below 1e-100 the
        ratio overflows).
    wavelet, level : as in :func:`causal_details`
    pfa : float
        Design false-alarm probability per sample.
    n_tests : int, optional
        Tests ``pfa`` is split over (default ``level + 1``, the detector's).

    Returns
    -------
    ndarray, shape (level,)

    Examples
    --------
    >>> t = np.arange(20000.0)
    >>> r = signal_threshold_ratio(1e4 * np.sin(2 * np.pi * t / 2750.0), 1.0)
    >>> bool(r[0] < 1e-3 < r[4] < 1.0)
    True
    """
    level = check_int("level", level, 1, 12)
    sigma = check_finite_array("sigma", sigma)
    # from 1e-100: x / (k sigma) overflowed for a subnormal sigma (a noise of 1e-100 in any SI
    # unit is far below any sensor's)
    if sigma.shape not in ((), (level,)) or np.any(sigma < 1e-100) or np.any(sigma > MAX_SIZE):
        raise ValueError(f"sigma must be in [1e-100, {MAX_SIZE:g}], a scalar or one per level ({level},)")
    sigma = np.broadcast_to(sigma, (level,))
    n_tests = level + 1 if n_tests is None else n_tests
    k = threshold_multiplier(pfa, n_tests)
    warm = len(causal_filters(wavelet, level)[-1]) - 1
    d = causal_details(x, wavelet, level)[:, warm:]
    if d.shape[1] == 0:
        raise ValueError(f"x must be longer than the longest filter ({warm + 1} samples)")
    return np.abs(d).max(axis=1) / (k * sigma)


class EventTracker:
    """Online form of :func:`events_from_alarms`: feed one sample's alarm at a time.

    Parameters
    ----------
    holdoff : int
        Samples without alarm after which the detector clears.

    Examples
    --------
    >>> tr = EventTracker(holdoff=2)
    >>> [tr.update(float(i), a, 2.0 * a) for i, a in enumerate([0, 1, 0, 1, 0, 0, 0])]
    [False, True, True, True, True, False, False]
    >>> tr.events[0].onset, tr.events[0].end, tr.events[0].cleared
    (1.0, 3.0, 5.0)
    """

    def __init__(self, holdoff):
        self.holdoff = _check_holdoff(holdoff)
        self.events = []
        self.faulty = False
        self._open = None          # [onset, end, peak, test]
        self._quiet = 0
        self._t_last = -math.inf   # the latest time fed: times must not go back

    def _not_back(self, t, what):
        if t < self._t_last:  # an event would end (or clear) before its onset
            raise ValueError(f"t must not go back from one {what} to the next (sample times, "
                             f"s), got t = {t:g} after t = {self._t_last:g}")

    def update(self, t, alarm, ratio=0.0, test=""):
        """Advance one sample (``t`` not before the last one fed); return whether the detector
        flags the sensor after it."""
        t = check_real("t", t)
        self._not_back(t, "update")
        if isinstance(ratio, complex) or ratio != ratio:  # complex or NaN
            raise ValueError(f"ratio must be a real number, got {ratio!r}")
        if alarm is not True and alarm is not False and not (
                isinstance(alarm, int | float | np.bool_ | np.integer | np.floating)
                and alarm in (0, 1)):
            raise ValueError(f"alarm must be true or false, got {alarm!r}")
        self._t_last = t
        if alarm:
            if self._open is None:
                self._open = [t, t, ratio, test]
            else:
                self._open[1] = t
                if ratio > self._open[2]:
                    self._open[2:] = [ratio, test]
            self._quiet = 0
            self.faulty = True
        elif self._open is not None:
            self._quiet += 1
            if self._quiet >= self.holdoff:
                onset, end, peak, tst = self._open
                self.events.append(Event(float(onset), float(end), float(t), float(peak), tst))
                self._open = None
                self.faulty = False
        return self.faulty

    def snapshot(self):
        """The tracker's state, for :meth:`restore`."""
        return (list(self.events), None if self._open is None else list(self._open),
                self._quiet, self.faulty, self._t_last)

    def restore(self, state):
        """Return to a :meth:`snapshot`.

        Examples
        --------
        >>> tr = EventTracker(holdoff=2)
        >>> s = tr.snapshot(); tr.update(0.0, True, 2.0); tr.restore(s); tr.faulty
        True
        False
        """
        if not isinstance(state, tuple) or len(state) != 5:
            raise ValueError(f"state must be a snapshot() of this tracker, got {shown(state)}")
        events, open_, self._quiet, self.faulty, self._t_last = state
        self.events = list(events)
        self._open = None if open_ is None else list(open_)

    def close(self, t=None):
        """Close the open event now (``cleared = t``, not before the last time fed; default its
        last alarm), e.g. when the watched sensor is re-admitted after an isolation; no-op when
        none is open.

        Examples
        --------
        >>> tr = EventTracker(holdoff=5)
        >>> tr.update(1.0, True, 2.0), tr.close(4.0), tr.faulty, tr.events[0].cleared
        (True, None, False, 4.0)
        """
        if t is not None:
            t = check_real("t", t)
            self._not_back(t, "update or close")
        if self._open is None:
            return
        onset, end, peak, tst = self._open
        self.events.append(Event(float(onset), float(end), float(end if t is None else t),
                                 float(peak), tst))
        self._open = None
        self._quiet = 0
        self.faulty = False

    def all_events(self):
        """Closed events plus the open one (``cleared = inf``)."""
        if self._open is None:
            return list(self.events)
        onset, end, peak, tst = self._open
        return self.events + [Event(float(onset), float(end), math.inf, float(peak), tst)]


# --------------------------------------------------------------------------------------------
# The wavelet detector
# --------------------------------------------------------------------------------------------

class WaveletDetector(TrackedDetector):
    """Online causal wavelet singularity detector for one measurement component.

    Each new sample enters a window of the last ``len(g_J)`` samples (156 for db3, level 5);
    the window gives one undecimated detail coefficient per level (:func:`causal_filters`).
    A sample alarms when any ``|d_j| > k sigma_j`` or the level-1 variance test fails; alarms
    are grouped into :class:`Event` s with a hold-off (see the module notes).

    Parameters
    ----------
    wavelet : str
        Default ``"db3"`` (the paper's).
    level : int
        Number of levels ``J``, default 5 (the paper's).
    sigma : array_like, shape (level,), optional
        Noise level of each level's detail, in the measurement unit. If omitted, call
        :meth:`train` with a fault-free series before the detector arms.
    pfa : float
        Design false-alarm probability per sample, default 1e-5 (union bound over the ``J``
        level tests and the variance test).
    var_window : int
        Number of independent level-1 coefficients in the variance test (0 switches it off);
        default 32 (a span of 64 samples).
    holdoff : int, optional
        Alarm-free samples before the detector clears; default the window length or the
        variance span, whichever is longer.

    Attributes
    ----------
    k : float
        Threshold multiplier from ``pfa``.
    thresholds : ndarray, shape (level,)
        ``k sigma_j`` in the measurement unit.
    events : list of Event
        Closed events so far (``all_events()`` adds the open one).

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> det = WaveletDetector()
    >>> det.train(rng.normal(0.0, 5000.0, 20000))
    >>> flags = [det.update(3.0 * i, x) for i, x in enumerate(rng.normal(0.0, 5000.0, 400))]
    >>> any(flags)
    False
    >>> flags = [det.update(1200.0 + 3.0 * i, 50000.0 + x) for i, x in enumerate(rng.normal(0.0, 5000.0, 10))]
    >>> det.faulty, det.all_events()[0].onset
    (True, 1203.0)
    """

    def __init__(self, wavelet="db3", level=5, *, sigma=None, pfa=1e-5, var_window=32, holdoff=None):
        self.wavelet = orthogonal_wavelet(wavelet).name
        self.level = check_int("level", level, 1, 12)
        self.pfa = check_real("pfa", pfa, 0.0, 1.0, lo_open=True, hi_open=True)
        self.var_window = check_int("var_window", var_window, 0, 100000)
        self.filters = causal_filters(self.wavelet, self.level)
        self.window = len(self.filters[-1])
        self._G = _filter_matrix(self.filters)
        n_tests = self.level + (1 if self.var_window else 0)
        self.k = threshold_multiplier(self.pfa, n_tests)
        p_each = self.pfa / n_tests
        self.var_bounds = (
            (chi2_ppf(p_each / 2, self.var_window), chi2_isf(p_each / 2, self.var_window))
            if self.var_window else None
        )
        default_hold = max(self.window, 2 * self.var_window)
        self.holdoff = _check_holdoff(default_hold if holdoff is None else holdoff)
        self.sigma = None
        if sigma is not None:
            self._set_sigma(sigma)
        self.reset()

    def _set_sigma(self, sigma):
        sigma = check_finite_array("sigma", sigma)
        if sigma.shape != (self.level,):  # "trailing shape (..., 2)" read as a stack (review 35p P14)
            raise ValueError(f"sigma must have shape ({self.level},), one noise level a wavelet "
                             f"level (level = {self.level}), got shape {sigma.shape}")
        if np.any(sigma <= 0):
            raise ValueError(f"sigma must be {self.level} positive numbers, got {sigma!r}")
        self.sigma = sigma.copy()

    @property
    def thresholds(self):
        return None if self.sigma is None else self.k * self.sigma

    def train(self, x):
        """Set ``sigma_j`` from a fault-free series by the MAD of each level's details.

        Parameters
        ----------
        x : array_like, shape (N,)
            Fault-free measurements, ``N >= window + 200`` (several thousand samples give
            ``sigma_5`` to a few per cent: level-5 coefficients are correlated over the window).
        """
        x = check_finite_array("x", x)
        if x.ndim != 1 or x.size < self.window + 200:
            raise ValueError(f"x must be a 1-D training series of at least {self.window + 200} "
                             f"samples, got shape {x.shape}")
        sigma = mad_sigma(causal_details(x, self.wavelet, self.level)[:, self.window - 1:])
        if np.any(sigma <= 0.0):   # a MAD of 0 (a constant x) was refused as sigma, never given
            levels = ", ".join(str(j + 1) for j in np.flatnonzero(sigma <= 0.0))
            raise ValueError(f"x has no noise over its {x.size} samples: the median |detail "
                             f"coefficient| is 0 at level(s) {levels} of {self.level}, so no "
                             f"noise level can be estimated; give sigma ({self.level} levels) "
                             f"or a noisy series")
        self._set_sigma(sigma)

    def reset(self):
        """Forget the data seen (keeps ``sigma``)."""
        self._buf = np.zeros(self.window)        # newest first: _buf[m] = x[n - m] - x0
        self._x0 = None
        self._count = 0
        self._z1 = deque(maxlen=max(1, 2 * self.var_window - 1))
        self._tracker = EventTracker(self.holdoff)
        self._t_last = -math.inf

    def details(self):
        """Current detail coefficients ``d_j[n]``, shape (level,), measurement unit."""
        return self._G @ self._buf

    def update(self, t, x):
        """Feed one measurement ``x`` taken at time ``t`` (s, after the last one fed); return
        whether the sensor is flagged.

        Before :meth:`train` (or ``sigma``) and until the window is full, it returns False.
        """
        x = check_real("x", x)
        self._advance_time(check_real("t", t))
        if self._x0 is None:
            self._x0 = x
        self._buf[1:] = self._buf[:-1]
        self._buf[0] = x - self._x0
        self._count += 1
        d = self._G @ self._buf                                   # d_j[n] = sum_m g_j[m] x[n-m]
        if self.sigma is None:
            return False
        z = d / self.sigma
        ratios = np.abs(z) / self.k
        names = [f"level {j + 1}" for j in range(self.level)]
        if self.var_window:
            self._z1.append(z[0])
            if len(self._z1) == self._z1.maxlen:
                q = float(np.sum(np.square(list(self._z1)[::-2])))   # Q = sum_i z_1[n - 2i]^2
                ratios = np.append(ratios, _var_ratio(q, *self.var_bounds))
                names.append("variance")
        if self._count < self.window:
            return False
        i = int(np.argmax(ratios))
        return self._tracker.update(t, bool(ratios[i] > 1.0), float(ratios[i]), names[i])


def _var_ratio(q, lo, hi):
    """Variance-test ratio: > 1 outside ``[lo, hi]`` (chi-square bounds of ``Q``)."""
    return np.maximum(q / hi, lo / np.maximum(q, 1e-300))
