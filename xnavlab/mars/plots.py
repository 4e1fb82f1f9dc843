"""Figures of the Mars system behind the chapters' sliders (chapters 5, 6 and 8).

Each function is pure in its arguments (the scenario is seeded) and returns a
:class:`matplotlib.figure.Figure` that is not registered with pyplot, so a chapter can call it
from :func:`xnavlab.core.widgets.explore` and also leave a static figure for the HTML book.

Examples
--------
>>> fig = plot_subsystem("uv", 1.0, 30, days=0.02)
>>> len(fig.axes)
1
"""

from __future__ import annotations

import math

import numpy as np

from xnavlab.core.constants import DAY
from xnavlab.core.faults import Fault
from xnavlab.core.validate import check_choice, check_real
from xnavlab.mars import fault_tolerance, scenarios

__all__ = ["plot_subsystem", "plot_sharing", "plot_fault_response"]


def plot_subsystem(subsystem="uv", noise_scale=1.0, interval_s=3, days=0.25):
    """One subsystem alone: its position error and the filter's 3-sigma bound.

    Runs :func:`~xnavlab.mars.scenarios.run` with the single ``subsystem``, its noise parameters multiplied by
    ``noise_scale`` and its measurement interval set to ``interval_s`` (XNAV: at least
    30 s). A pure function of its arguments (the scenario is seeded), for chapter 5's
    slider.

    Parameters
    ----------
    subsystem : {"xnav", "uv", "cns"}
    noise_scale : float
        Factor on the paper's noise (> 0): UV range and direction, CNS star and horizon
        sensors, or the four XNAV ranging accuracies (109, 344, 1866, 325 m).
    interval_s : float
        Measurement interval, s (> 0).
    days : float
        Span, days (default six hours).

    Returns
    -------
    matplotlib.figure.Figure
        One log-scale axes; not registered with pyplot.

    Examples
    --------
    >>> fig = plot_subsystem("cns", 2.0, 30, days=0.02)
    >>> fig.axes[0].get_title()
    'cns: noise x 2, every 30 s'
    """
    from matplotlib.figure import Figure

    check_choice("subsystem", subsystem, scenarios.SUBSYSTEMS)
    noise_scale = check_real("noise_scale", noise_scale, 0.0, lo_open=True)
    interval_s = check_real("interval_s", interval_s, 0.0, lo_open=True)
    kw = {"days": days, "subsystems": (subsystem,), "record_dt": 30.0}
    if subsystem == "uv":
        kw.update(sigma_range_m=5000.0 * noise_scale, sigma_dir_deg=0.1 * noise_scale,
                  dt_uv=interval_s)
    elif subsystem == "cns":
        kw.update(sigma_horizon_deg=0.05 * noise_scale, sigma_star_arcsec=3.0 * noise_scale,
                  dt_cns=interval_s)
    else:
        kw.update(xnav_sigma_m=tuple(np.array([109.0, 344.0, 1866.0, 325.0]) * noise_scale),
                  dt_xnav=max(interval_s, 30.0))
    res = scenarios.run(**kw)
    hours = res.t_days * 24
    fig = Figure(figsize=(7, 3), layout="constrained")
    ax = fig.add_subplot()
    ax.fill_between(hours, 0, 3 * res.sigma_position(), color="C0", alpha=0.15, label="3 sigma")
    ax.plot(hours, res.position_error(), color="C0", label="|position error|")
    ax.set(xlabel="time (h)", ylabel="m", yscale="log", ylim=(10, 3e4),
           title=f"{subsystem}: noise x {noise_scale:.2g}, every {kw['dt_' + subsystem]:g} s")
    ax.legend(fontsize=8)
    return fig


def plot_sharing(beta_xnav=1 / 3, mode="reset", days=0.5):
    """The fused filter with a chosen information share for the XNAV local.

    Runs :func:`~xnavlab.mars.scenarios.run` (60-s records) with sharing factors ``(beta_xnav, rest, rest)``,
    ``rest = (1 - beta_xnav) / 2`` for UV and CNS, in the given federated ``mode``. A pure
    function of its arguments (the scenario is seeded), for chapter 6's slider.

    Parameters
    ----------
    beta_xnav : float
        Share of the XNAV local, 0 < beta_xnav < 1.
    mode : {"reset", "no-reset"}
    days : float
        Span, days (default half a day; the title gives the RMS error after its midpoint).

    Returns
    -------
    matplotlib.figure.Figure
        One log-scale axes: the position error and the filter's 1-sigma; not registered
        with pyplot.

    Examples
    --------
    >>> fig = plot_sharing(0.8, "no-reset", days=0.02)
    >>> fig.axes[0].get_title()[:36]
    'no-reset, beta = (0.80, 0.10, 0.10):'
    """
    from matplotlib.figure import Figure

    beta_xnav = check_real("beta_xnav", beta_xnav, 0.0, 1.0, lo_open=True, hi_open=True)
    check_choice("mode", mode, scenarios.MODES)
    rest = (1.0 - beta_xnav) / 2
    res = scenarios.run(days=days, record_dt=60.0, mode=mode, beta=(beta_xnav, rest, rest))
    settle = days / 2
    hours = res.t_days * 24
    fig = Figure(figsize=(7, 3), layout="constrained")
    ax = fig.add_subplot()
    ax.semilogy(hours, res.position_error(), label="|position error|")
    ax.semilogy(hours, res.sigma_position(), "--", label="1-sigma")
    ax.set(xlabel="time (h)", ylabel="m", ylim=(10, 2e4),
           title=f"{mode}, beta = ({beta_xnav:.2f}, {rest:.2f}, {rest:.2f}): "
                 f"{res.metrics(settle)['position_error_m']:.0f} m after {settle * 24:g} h")
    ax.legend(fontsize=8)
    return fig


def plot_fault_response(size_sigma=5.0, sensor="uv", kind="step", duration=4000.0, days=1.0,
                        seed=0):
    """One fault in a short Mars run under every detector: fused position error.

    The fault (``size_sigma`` noise standard deviations of
    :func:`~xnavlab.mars.fault_tolerance.sensor_sigma`, per second of ``duration`` for a ramp
    so that it reaches ``size_sigma`` at its end; on the UV range, on every CNS angle or on
    every pulsar) starts at 60 % of the run; the wavelet detectors
    train on the first 40 %. A pure function of its arguments (the chapter's slider).

    Parameters
    ----------
    size_sigma : float
        Fault size in noise standard deviations, in (0, 1000].
    sensor : {"uv", "cns", "xnav"}
    kind : {"step", "ramp", "spike"}
    duration : float
        Fault duration, s, in (0, 0.3 days].
    days : float
        Run length, days, in [0.5, 5].
    seed : int
        Noise seed.

    Returns
    -------
    matplotlib.figure.Figure
    """
    size_sigma = check_real("size_sigma", size_sigma, 0.0, 1000.0, lo_open=True)
    check_choice("kind", kind, ("step", "ramp", "spike"))
    days = check_real("days", days, 0.5, 5.0)
    duration = check_real("duration", duration, 0.0, 0.3 * days * DAY, lo_open=True)
    sig = fault_tolerance.sensor_sigma(sensor)
    onset = round(0.6 * days * DAY, 0) + 1.0
    mag = size_sigma * sig / (duration if kind == "ramp" else 1.0)
    comp = 0 if sensor == "uv" else None
    fault = Fault(sensor, kind, mag, onset, duration, comp)
    inp = scenarios.prepare(days=days, seed=seed)
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.5, 3.4), layout="constrained")
    ax = fig.add_subplot()
    settle = 0.4 * days
    text = []
    for det in fault_tolerance.DETECTORS:
        r = fault_tolerance.run_fault_tolerant(faults=[fault], detector=det, inputs=inp, train_days=settle)
        rms = r.run.metrics(settle)["position_error_m"]
        ax.semilogy(r.run.t_days * 24, r.run.position_error(), lw=0.7, label=f"{det}: {rms:.0f} m")
        d = r.delays()[0]["delay"]
        if det != "none":
            text.append(f"{det} delay {d:.0f} s" if math.isfinite(d) else f"{det} missed")
            band = fault_tolerance.DETECTORS.index(det) - 1          # one band of isolation per detector
            for iv in r.isolation_intervals():
                back = iv["back"] if iv["back"] is not None else days * DAY
                ax.axvspan(iv["out"] / 3600, back / 3600, ymin=0.05 * band,
                           ymax=0.05 * (band + 1), color=f"C{band + 1}", alpha=0.8)
    ax.axvspan(onset / 3600, (onset + duration) / 3600, color="0.85", zorder=0)
    ax.set(xlim=(settle * 24, days * 24), ylim=(5, 2e4), xlabel="time (h)",
           ylabel="|position error| (m)",
           title=f"{sensor} {kind} of {size_sigma:g} sigma: " + ", ".join(text))
    ax.legend(fontsize=8, loc="upper left", title="detector: RMS after 40 %", title_fontsize=8)
    return fig
