"""Figures of the detection chapters: the slider's function and its static figures.
"""

from __future__ import annotations

import functools
import math
from numbers import Real

import numpy as np

from xnavlab.core.detection.batch import series_lengths, wavelet_detect
from xnavlab.core.detection.online import Detection
from xnavlab.core.faults import Fault, check_faults, inject
from xnavlab.core.validate import (
    check_finite_array,
    check_int,
    check_keywords,
    check_real,
    check_seed,
    check_text,
    shown,
)

__all__ = [
    "plot_detection",
    "plot_fault_detection",
    "plot_step_detector",
]

# --------------------------------------------------------------------------------------------
# Figures (the chapter's slider and its static figures)
# --------------------------------------------------------------------------------------------

def _check_zoom(zoom_h):
    if zoom_h is None:
        return None
    try:
        lo, hi = (float(v) for v in zoom_h)
    except (TypeError, ValueError):
        raise ValueError(f"zoom_h must be a pair (start, end) of hours, got {zoom_h!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise ValueError(f"zoom_h must be finite with start < end, got {zoom_h!r}")
    return lo, hi


#: The largest value :func:`plot_detection` plots (``x / scale``): matplotlib's limits overflow
#: near 1e308.
_PLOT_MAX = 1e300


def plot_detection(result, x, faults=(), *, title="", zoom_h=None, ylabel="range (km)",
                   scale=1e3):
    """Plot a series and what a detector flags: the series, then ratio to threshold and flags.

    Parameters
    ----------
    result : Detection
        From :func:`~.batch.wavelet_detect` or :func:`~.chisquare.chi2_detect`; its ``t`` is the time axis.
    x : array_like, shape (N,)
        The series the detector saw (plotted divided by ``scale``).
    faults : sequence of Fault, optional
        Drawn as grey bands from onset to end.
    title : str, optional
    zoom_h : (float, float), optional
        Time window shown, hours; the whole series when omitted.
    ylabel : str, optional
        Label of the series' axis.
    scale : float, optional
        Divisor of ``x`` for display (default 1e3: m to km), > 0 and at least
        ``max |x| / 1e300`` (what is plotted stays finite).

    Returns
    -------
    matplotlib.figure.Figure
        Two panels sharing the time axis (hours); not registered with pyplot.

    Examples
    --------
    >>> t = 3.0 * np.arange(4000)
    >>> x = np.random.default_rng(0).normal(0.0, 5000.0, t.size)
    >>> fig = plot_detection(wavelet_detect(t, x), x, title="noise only")
    >>> len(fig.axes), fig.axes[1].get_ylabel()
    (2, 'ratio')
    """
    if not isinstance(result, Detection):
        raise ValueError(f"result must be a Detection, got {type(result).__name__}")
    t = np.asarray(result.t, dtype=float)
    x = check_finite_array("x", x)
    if x.shape != t.shape:
        raise ValueError(f"x must have the shape of result.t {t.shape}, got {x.shape}")
    faults = check_faults("faults", faults)
    title = check_text("title", title)
    zoom = _check_zoom(zoom_h)
    ylabel = check_text("ylabel", ylabel)
    scale = check_real("scale", scale, 0.0, lo_open=True)
    top = float(np.abs(x).max(initial=0.0))
    if top > _PLOT_MAX * scale:   # x / scale would overflow, or the figure's limits would
        raise ValueError(f"scale must be at least max |x| / {_PLOT_MAX:g} = {top / _PLOT_MAX:.3g} "
                         f"(x / scale is plotted; max |x| = {top:.3g}), got {shown(scale)}")
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10, 4.6), layout="constrained")
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    th = t / 3600.0
    ax1.plot(th, x / scale, lw=0.3)
    ax1.set_ylabel(ylabel)
    ax2.semilogy(th, np.maximum(result.ratio, 1e-3), lw=0.3, label="max test statistic / threshold")
    ax2.axhline(1.0, color="k", lw=0.8)
    ax2.fill_between(th, 1e-3, 1e3, where=result.faulty, color="C3", alpha=0.2, label="flagged")
    ax2.set(ylim=(1e-2, 50), xlabel="t (h)", ylabel="ratio")
    for ax in (ax1, ax2):
        for f in faults:
            ax.axvspan(f.onset / 3600.0, min(f.end, t[-1]) / 3600.0, color="0.8", zorder=0)
        if zoom:
            ax.set_xlim(*zoom)
    ax2.legend(fontsize=8, loc="upper left")
    if title:
        fig.suptitle(title)
    return fig


def plot_fault_detection(t, clean, faults, *, sensor="uv", title="", zoom_h=None, **detect):
    """Inject faults into a fault-free series, run :func:`~.batch.wavelet_detect` and plot the result.

    The figure's title adds what happened at the first fault of ``sensor``: the detection
    delay at its onset (or "onset missed") and the number of false-alarm samples before it.
    A pure function of its arguments: the chapter's slider calls it.

    Parameters
    ----------
    t : array_like, shape (N,)
        Sample times, s.
    clean : array_like, shape (N,)
        Fault-free measurements, m.
    faults : sequence of Fault
        Injected with :func:`xnavlab.core.faults.inject`; faults of other sensors are ignored.
    sensor : str, optional
        The sensor ``clean`` belongs to (default ``"uv"``).
    title : str, optional
        Prefix of the figure's title.
    zoom_h : (float, float), optional
        Time window shown, hours.
    **detect
        Keyword arguments of :func:`~.batch.wavelet_detect` (``level``, ``pfa``, ``train``, ...);
        another keyword is refused, naming it.

    Returns
    -------
    matplotlib.figure.Figure
        As :func:`plot_detection`.

    Examples
    --------
    >>> t = 3.0 * np.arange(6000)
    >>> clean = np.random.default_rng(1).normal(0.0, 5000.0, t.size)
    >>> step = Fault("uv", "step", 50000.0, onset=9000.0, duration=3000.0)
    >>> fig = plot_fault_detection(t, clean, [step], train=2000, title="10 sigma")
    >>> fig.get_suptitle().split(":")[0]
    '10 sigma, k = 4.79'
    """
    t = check_finite_array("t", t)
    clean = check_finite_array("clean", clean)   # named here, not as inject's z
    if clean.ndim != 1:
        raise ValueError(f"clean must be a 1-D fault-free series, got shape {clean.shape}")
    series_lengths(t, "clean", clean.size)
    faults = check_faults("faults", faults)
    sensor = check_text("sensor", sensor)
    title = check_text("title", title)
    detect = check_keywords("plot_fault_detection", detect, wavelet_detect, set_here={
        "t": "its t", "x": "its clean, the faults injected"})
    res, x, title = _fault_detection(t, clean, faults, sensor, title, detect)
    return plot_detection(res, x, [f for f in faults if f.sensor == sensor], title=title,
                          zoom_h=zoom_h)


def _fault_detection(t, clean, faults, sensor, title, detect):
    """``(result, x, title)`` of :func:`plot_fault_detection`: the detector run on the
    series with the faults injected, and the figure's title."""
    t = check_finite_array("t", t)
    x = inject(t, clean, faults, sensor)
    res = wavelet_detect(t, x, **detect)
    onsets = [f.onset for f in faults if f.sensor == sensor]
    if onsets:
        onset = min(onsets)
        delay = res.first_onset_after(onset) - onset
        found = f"onset detected after {delay:.0f} s" if math.isfinite(delay) else "onset missed"
        false = int(res.alarm[t < onset].sum())
        summary = f"k = {res.data['k']:.2f}: {found}, {false} false-alarm samples before it"
    else:
        summary = f"k = {res.data['k']:.2f}: no fault, {int(res.alarm.sum())} false-alarm samples"
    return res, x, f"{title}, {summary}" if title else summary


@functools.lru_cache(maxsize=4)
def _range_series(n, dt_s, mean_m, swing_m, period_s, sigma_m, seed):
    """``(t, clean)``: the range-like series of :func:`plot_step_detector` (kept read-only)."""
    t = dt_s * np.arange(n)
    truth = mean_m - swing_m * np.cos(2.0 * np.pi * t / period_s)
    clean = truth + np.random.default_rng(seed).normal(0.0, sigma_m, n)
    t.flags.writeable = clean.flags.writeable = False
    return t, clean


#: The shortest orbital period :func:`plot_step_detector` takes, s (a microsecond: its phase
#: ``2 pi t / period_s`` stays finite over the longest run, and a period below the sampling
#: interval is aliased noise anyway).
_PERIOD_MIN_S = 1e-6


def _check_duration(duration_s):
    """The step's length, s, in (0, inf] (``inf``: to the end of the run), named as the
    slider's ``duration_s`` rather than the Fault's ``duration``."""
    if isinstance(duration_s, Real | np.floating) and not isinstance(duration_s, bool) \
            and duration_s == math.inf:
        return math.inf
    try:
        return check_real("duration_s", duration_s, 0.0, math.inf, lo_open=True)  # inf: above
    except ValueError:
        raise ValueError(f"duration_s must be a real number in (0, inf] (s; inf: to the end of "
                         f"the run), got {shown(duration_s)}") from None


def plot_step_detector(size_sigma=6.0, levels=5, log10_pfa=-5, *, sigma_m=5000.0, dt_s=3.0,
                       n=12_000, mean_m=4.19e6, swing_m=3.8e5, period_s=8280.0, seed=5,
                       onset_s=18_000.0, duration_s=3000.0, train=3000, zoom_h=(4.5, 6.5)):
    """A step fault in a noisy orbital range series, and what the wavelet detector flags.

    The series is a range to a planet's centre along an elliptical orbit,
    ``mean_m - swing_m cos(2 pi t / period_s)``, plus white noise of ``sigma_m``, sampled every
    ``dt_s`` (``n`` samples, noise seeded by ``seed``; made once per set of these values).
    A step of ``size_sigma`` noise standard deviations starts at ``onset_s`` and lasts
    ``duration_s``; :func:`plot_fault_detection` runs
    :func:`~.batch.wavelet_detect` with ``levels`` decomposition levels, the false-alarm
    probability ``10 ** log10_pfa`` and ``train`` training samples, and plots the result.
    The wavelet chapter's slider calls it (a pure function of its arguments).

    Parameters
    ----------
    size_sigma : float
        Step size in noise standard deviations (dimensionless), in [-1e6, 1e6] (a million
        sigma: every step the slider shows is detected long before).
    levels : int
        Decomposition levels of the detector, 1..12.
    log10_pfa : float
        Base-10 logarithm of the per-sample false-alarm probability, in [-12, 0).
    sigma_m, dt_s : float
        Noise standard deviation, m, in (0, 1e9] (a million km, so the step stays under
        :data:`~xnavlab.core.faults.MAX_SIZE`), and sample interval, s, in [1e-6, 86400].
    n : int
        Number of samples, in [2 * ``train``, 10**7] (80 MB a series, made once per setting).
    mean_m, swing_m, period_s : float
        Mean range (m) in [0, 1e12] and its orbital swing (m) in [0, ``mean_m``] (a range is
        never negative), and the orbit's period, s, from 1e-6 (a microsecond) on.
    seed : int
        Seed of the noise, in [0, 2**63 - 1].
    onset_s, duration_s : float
        Start of the step, s, in [0, (``n`` - 1) ``dt_s``] (it acts on at least one sample
        of the run), and its length, s, in (0, inf] (``inf``: to the end of the run).
    train : int
        Fault-free training samples of the detector's threshold, in [1, 5e6].
    zoom_h : (float, float), optional
        Time window shown, hours (``None``: the whole series).

    Returns
    -------
    matplotlib.figure.Figure
        As :func:`plot_detection`, titled with the step size, the levels and what the
        detector did (:func:`plot_fault_detection`); not registered with pyplot.

    Examples
    --------
    >>> fig = plot_step_detector(size_sigma=10.0, levels=2, n=6000, onset_s=9000.0,
    ...                          train=2000, zoom_h=None)
    >>> title = fig.get_suptitle()
    >>> title.split(",")[:2], "onset detected after" in title
    (['10 sigma step', ' 2 levels'], True)
    """
    from xnavlab.core.plotting import in_place

    def run(size_sigma, levels, log10_pfa, sigma_m, dt_s, n, mean_m, swing_m, period_s, seed,
            onset_s, duration_s, train):
        size_sigma = check_real("size_sigma", size_sigma, -1e6, 1e6)
        if size_sigma == 0.0:   # named here, not as the Fault's magnitude
            raise ValueError("size_sigma must be a nonzero step size in [-1e6, 1e6] (a zero-size "
                             f"fault is no fault), got {size_sigma:g}")
        levels = check_int("levels", levels, 1, 12)
        log10_pfa = check_real("log10_pfa", log10_pfa, -12.0, 0.0, hi_open=True)
        sigma_m = check_real("sigma_m", sigma_m, 0.0, 1e9, lo_open=True)
        dt_s = check_real("dt_s", dt_s, 1e-6, 86400.0)   # from a microsecond, as period_s
        period_s = check_real("period_s", period_s, _PERIOD_MIN_S)  # 2 pi t / period_s: finite
        train = check_int("train", train, 1, 5 * 10**6)
        n = check_int("n", n, 2 * train, 10**7)
        # a range within 1e12 m (7 au): at 1e308 the noise vanished in the rounding; never < 0
        mean_m = check_real("mean_m", mean_m, 0.0, 1e12)
        swing_m = check_real("swing_m", swing_m, 0.0, 1e12)
        if swing_m > mean_m:
            raise ValueError(f"swing_m must be at most mean_m = {mean_m:g} (the range "
                             f"mean_m - swing_m cos(...) stays >= 0), got {swing_m:g}")
        seed = check_seed("seed", seed)
        # the step acts on at least one sample of the run [0, (n - 1) dt_s], from its start
        onset_s = check_real("onset_s", onset_s)
        if not 0.0 <= onset_s <= (n - 1) * dt_s:
            raise ValueError(f"onset_s must lie in the run, [0, (n - 1) dt_s] = [0, "
                             f"{(n - 1) * dt_s:g}] s (n = {n}, dt_s = {dt_s:g}), got {onset_s:g}")
        duration_s = _check_duration(duration_s)
        t, clean = _range_series(n, dt_s, mean_m, swing_m, period_s, sigma_m, seed)
        fault = Fault("uv", "step", size_sigma * sigma_m, onset=onset_s, duration=duration_s)
        return (*_fault_detection(t, clean, [fault], "uv",
                                  f"{size_sigma:g} sigma step, {levels} levels",
                                  {"level": levels, "pfa": 10.0 ** log10_pfa, "train": train}),
                fault)

    built = (n, dt_s, onset_s, duration_s, zoom_h)
    res, x, title, fault = run(size_sigma, levels, log10_pfa, sigma_m, dt_s, n, mean_m, swing_m,
                               period_s, seed, onset_s, duration_s, train)
    fig = plot_detection(res, x, [fault], title=title, zoom_h=zoom_h)
    ax1, ax2 = fig.axes

    def update(size_sigma=6.0, levels=5, log10_pfa=-5, *, sigma_m=5000.0, dt_s=3.0, n=12_000,
               mean_m=4.19e6, swing_m=3.8e5, period_s=8280.0, seed=5, onset_s=18_000.0,
               duration_s=3000.0, train=3000, zoom_h=(4.5, 6.5)):
        if (n, dt_s, onset_s, duration_s, zoom_h) != built:
            return False  # another time axis or fault window: a new figure
        res, x, title, _ = run(size_sigma, levels, log10_pfa, sigma_m, dt_s, n, mean_m, swing_m,
                               period_s, seed, onset_s, duration_s, train)
        # the artists plot_detection drew: the series, the ratio, the flagged band
        ax1.lines[0].set_ydata(x / 1e3)
        ax2.lines[0].set_ydata(np.maximum(res.ratio, 1e-3))
        band = ax2.collections[0]
        band.remove()
        th = np.asarray(res.t, dtype=float) / 3600.0
        ax2.fill_between(th, 1e-3, 1e3, where=res.faulty, color="C3", alpha=0.2,
                         label="flagged")
        ax1.relim()
        ax1.autoscale_view()
        fig.suptitle(title)
        return None

    return in_place(fig, update)
