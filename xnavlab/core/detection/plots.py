"""Figures of the detection chapters: the slider's function and its static figures.
"""

from __future__ import annotations

import math

import numpy as np

from xnavlab.core.detection.batch import wavelet_detect
from xnavlab.core.detection.online import Detection
from xnavlab.core.faults import Fault, inject
from xnavlab.core.validate import check_finite_array, check_real

__all__ = [
    "plot_detection",
    "plot_fault_detection",
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
        Divisor of ``x`` for display (default 1e3: m to km), > 0.

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
    scale = check_real("scale", scale, 0.0, lo_open=True)
    zoom = _check_zoom(zoom_h)
    faults = list(faults)
    for f in faults:
        if not isinstance(f, Fault):
            raise ValueError(f"faults must hold Fault objects, got {type(f).__name__}")
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
        Keyword arguments of :func:`~.batch.wavelet_detect` (``level``, ``pfa``, ``train``, ...).

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
    return plot_detection(res, x, [f for f in faults if f.sensor == sensor],
                          title=f"{title}, {summary}" if title else summary, zoom_h=zoom_h)
