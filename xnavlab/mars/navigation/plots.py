"""Figures of the Mars system behind the chapters' sliders (chapters 5, 6 and 8), the paper's
Figs. 3-5 layouts and the detector table of chapter 9.

Each function is pure in its arguments (the scenario is seeded). The figure functions return a
:class:`matplotlib.figure.Figure` that is not registered with pyplot, so a chapter can call one
from :func:`xnavlab.core.widgets.explore` and also leave a static figure for the HTML book;
:func:`detector_table_markdown` returns Markdown text. The sliders' figures
(:func:`plot_subsystem`, :func:`plot_sharing`, :func:`plot_fault_response`,
:func:`plot_shapiro_angle`) carry an in-place update (:func:`xnavlab.core.plotting.in_place`):
the live slider changes their artists instead of building a new figure.

Examples
--------
>>> fig = plot_subsystem("uv", 1.0, 30, days=0.02)
>>> len(fig.axes)
1
"""

from __future__ import annotations

import functools
import math

import numpy as np

from xnavlab.core.constants import DAY
from xnavlab.core.faults import Fault, check_faults
from xnavlab.core.plotting import in_place, sparse_log_minors
from xnavlab.core.validate import (
    check_choice,
    check_finite_array,
    check_instance,
    check_int,
    check_real,
    check_records,
    check_shape,
    check_vector,
    shown,
)
from xnavlab.mars.faults import fault_tolerance
from xnavlab.mars.navigation import scenarios

__all__ = ["plot_subsystem", "plot_sharing", "plot_runs", "plot_fault_response", "plot_error_curves",
           "plot_details", "detector_table_markdown", "plot_shapiro_angle", "plot_consistency",
           "YLIM_RANGE"]


def plot_subsystem(subsystem="uv", noise_scale=1.0, interval_s=3, days=0.25):
    """One subsystem alone: its position error and the filter's 3-sigma bound.

    Runs :func:`~xnavlab.mars.navigation.scenarios.run` with the single ``subsystem``, its noise
    parameters multiplied by
    ``noise_scale`` and its measurement interval set to ``interval_s`` (XNAV: at least
    30 s). A pure function of its arguments (the scenario is seeded), for chapter 5's
    slider.

    Parameters
    ----------
    subsystem : {"xnav", "uv", "cns"}
    noise_scale : float
        Factor on the paper's noise, in [0.01, 100]: UV range and direction, CNS star and
        horizon sensors, or the four XNAV ranging accuracies (109, 344, 1866, 325 m); a
        hundred times the paper's noise is no sensor (and the scenario refuses a star
        sensor's above 3600 arcsec).
    interval_s : float
        Measurement interval, s, in [0.1, 86400] (the scenario's intervals: at most a day).
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

    fig = Figure(figsize=(7, 3), layout="constrained")
    ax = fig.add_subplot()
    band = ax.fill_between([0.0, 1.0], 0, [1.0, 1.0], color="C0", alpha=0.15,
                           label="the filter's 3 sigma")
    line, = ax.plot([], [], color="C0", label="|position error|")
    ax.set(xlabel="time (h)", ylabel="|position error| (m)", yscale="log", ylim=(10, 3e4))
    fig.legend(fontsize=8, ncol=2, loc="outside lower center")  # off the shaded band

    def update(subsystem="uv", noise_scale=1.0, interval_s=3, days=0.25):
        check_choice("subsystem", subsystem, scenarios.SUBSYSTEMS)
        # a hundredth to a hundred times the paper's noise (a subnormal scale was a noise of 0,
        # refused under the scenario's name)
        noise_scale = check_real("noise_scale", noise_scale, 0.01, 100.0)
        # the scenario's measurement intervals: 0.1 s to a day
        interval_s = check_real("interval_s", interval_s, 0.1, 86400.0)
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
        # every epoch when they are sparser than 30 s (the same records: a shorter record_dt
        # is refused since review 35j)
        kw["record_dt"] = max(30.0, kw.get(f"dt_{subsystem}", 30.0))
        res = scenarios.run(**kw)
        hours = res.t_days * 24
        band.set_data(hours, 0, 3 * res.sigma_position())
        line.set_data(hours, res.position_error())
        ax.relim()
        ax.autoscale_view()
        ax.set_title(f"{subsystem}: noise x {noise_scale:.2g}, every {kw['dt_' + subsystem]:g} s")

    update(subsystem, noise_scale, interval_s, days)
    return in_place(fig, update)


def plot_sharing(beta_xnav=1 / 3, mode="reset", days=0.5):
    """The fused filter with a chosen information share for the XNAV local.

    Runs :func:`~xnavlab.mars.navigation.scenarios.run` (60-s records) with sharing factors ``(beta_xnav,
    rest, rest)``,
    ``rest = (1 - beta_xnav) / 2`` for UV and CNS, in the given federated ``mode``. A pure
    function of its arguments (the scenario is seeded), for chapter 6's slider.

    Parameters
    ----------
    beta_xnav : float
        Share of the XNAV local, in [0.001, 0.998] (each share at least 0.001, as
        :class:`~xnavlab.mars.navigation.scenarios.MarsScenario`'s ``beta``).
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

    fig = Figure(figsize=(7, 3), layout="constrained")
    ax = fig.add_subplot()
    error, = ax.semilogy([], [], label="|position error|")
    sigma, = ax.semilogy([], [], "--", label="the filter's 1 sigma")
    ax.set(xlabel="time (h)", ylabel="position (m)", ylim=(10, 2e4))
    fig.legend(fontsize=8, ncol=2, loc="outside lower center")  # off the curves

    def update(beta_xnav=1 / 3, mode="reset", days=0.5):
        # every share at least 1e-3, as the scenario's beta: rest = (1 - beta_xnav) / 2 too
        beta_xnav = check_real("beta_xnav", beta_xnav, 1e-3, 0.998)
        check_choice("mode", mode, scenarios.MODES)
        rest = (1.0 - beta_xnav) / 2
        res = scenarios.run(days=days, record_dt=60.0, mode=mode, beta=(beta_xnav, rest, rest))
        days = float(days)  # run checked it: a Fraction or numpy scalar, a float
        settle = days / 2
        hours = res.t_days * 24
        error.set_data(hours, res.position_error())
        sigma.set_data(hours, res.sigma_position())
        ax.relim()
        ax.autoscale_view()
        ax.set_title(f"{mode}, beta = ({beta_xnav:.2f}, {rest:.2f}, {rest:.2f}): "
                     f"{res.metrics(settle)['position_error_m']:.0f} m after {settle * 24:g} h")

    update(beta_xnav, mode, days)
    return in_place(fig, update)


def plot_runs(runs, band_days=None):
    """The fused position error of several Mars runs, and their filters' 1 sigma against the first's.

    Chapter 6 compares the federated modes and a subsystem switched out with it: the top
    panel holds each run's fused position error (log scale), the bottom one the uncertainty
    each filter claims, ``100 (sigma / sigma_first - 1)`` per cent above the first run's, so
    that a change of the covariance by a few per cent can be told from the noise of one run.

    Parameters
    ----------
    runs : dict of str to xnavlab.mars.navigation.scenarios.MarsRun
        Label to run (anything with ``t_days``, ``position_error()`` and ``sigma_position()``,
        each shape (N,), days and m); all recorded at the same epochs (a MarsRun's ``t``, s
        TDB; else ``t_days``), else a ValueError. The first is the reference of the bottom panel.
    band_days : tuple of float, optional
        ``(start, end)``, days: a span to shade grey on both panels (e.g. a subsystem out).

    Returns
    -------
    matplotlib.figure.Figure
        Two axes sharing the time axis (the top one log scale), one legend below them; not
        registered with pyplot.

    Examples
    --------
    >>> run = scenarios.run(days=0.02)
    >>> fig = plot_runs({"reset": run}, band_days=(0.005, 0.01))
    >>> [ax.get_ylabel() for ax in fig.axes]
    ['|position error| (m)', "filter's 1 sigma above reset's (%)"]
    """
    from matplotlib.figure import Figure

    check_instance("runs", runs, dict, "a dict of label -> MarsRun")
    if not runs:
        raise ValueError("runs must hold at least one labelled run")
    if band_days is not None:
        band_days = check_vector("band_days", band_days, 2)
    fig = Figure(figsize=(8.0, 4.6), layout="constrained")
    top, bottom = fig.subplots(2, 1, sharex=True)
    for label, run in runs.items():  # review 35p P13: an AttitudeRun was an AttributeError
        if not all(hasattr(run, a) for a in ("t_days", "position_error", "sigma_position")):
            raise ValueError(f"runs[{label!r}] must be a MarsRun (t_days, position_error(), "
                             f"sigma_position()), got {type(run).__name__}")
    first = next(iter(runs))
    reference = runs[first].sigma_position()
    epochs = getattr(runs[first], "t", runs[first].t_days)
    for k, (label, run) in enumerate(runs.items()):
        sigma = run.sigma_position()
        mine = getattr(run, "t", run.t_days)
        if sigma.shape != reference.shape or not np.array_equal(mine, epochs):  # review 35p P2
            raise ValueError(f"runs must share their epochs: {label!r} has {sigma.size} records "
                             f"from {mine[0]:.9g} to {mine[-1]:.9g}, {first!r} {reference.size} "
                             f"from {epochs[0]:.9g} to {epochs[-1]:.9g}")
        top.semilogy(run.t_days, run.position_error(), lw=0.5, color=f"C{k}", label=label)
        bottom.plot(run.t_days, 100.0 * (sigma / reference - 1.0), lw=1.0, color=f"C{k}")
    for ax in (top, bottom):
        if band_days is not None:
            ax.axvspan(*band_days, color="0.9", zorder=0)
    top.set(ylabel="|position error| (m)")
    bottom.set(xlabel="time (days)", ylabel=f"filter's 1 sigma above {first}'s (%)")
    fig.legend(fontsize=8, ncol=len(runs), loc="outside lower center")  # off the curves
    return fig


def plot_fault_response(size_sigma=5.0, sensor="uv", kind="step", duration=4000.0, days=1.0,
                        seed=0):
    """One fault in a short Mars run under every detector: fused position error.

    The fault (``size_sigma`` noise standard deviations of
    :func:`~xnavlab.mars.faults.fault_tolerance.sensor_sigma`, per second of ``duration`` for a ramp
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
    from matplotlib.figure import Figure

    # fixed margins, not the constrained layout: the live slider redraws this at every move
    fig = Figure(figsize=(8.5, 3.4))
    fig.subplots_adjust(left=0.08, right=0.99, bottom=0.14, top=0.91)
    ax = fig.add_subplot()
    lines = [ax.semilogy([], [], lw=0.7, label=det)[0] for det in fault_tolerance.DETECTORS]
    ax.set(ylim=(5, 2e4), xlabel="time (h)", ylabel="|position error| (m)")
    legend = ax.legend(fontsize=8, loc="upper left", title="detector: RMS after 40 %",
                       title_fontsize=8)
    spans = []  # the isolation bands and the fault's span, drawn again at each update

    def update(size_sigma=5.0, sensor="uv", kind="step", duration=4000.0, days=1.0, seed=0):
        size_sigma = check_real("size_sigma", size_sigma, 0.0, 1000.0, lo_open=True)
        check_choice("kind", kind, ("step", "ramp", "spike"))
        days = check_real("days", days, 0.5, 5.0)
        duration = check_real("duration", duration, 0.0, 0.3 * days * DAY, lo_open=True)
        sig = fault_tolerance.sensor_sigma(sensor)
        onset = round(0.6 * days * DAY, 0) + 1.0
        mag = size_sigma * sig / (duration if kind == "ramp" else 1.0)
        comp = 0 if sensor == "uv" else None
        fault = Fault(sensor, kind, mag, onset, duration, comp)
        inp = _fault_free_inputs(float(days), int(seed))   # the same for every slider position
        settle = 0.4 * days
        runs = [fault_tolerance.run_fault_tolerant(faults=[fault], detector=det, inputs=inp,
                                                   train_days=settle)
                for det in fault_tolerance.DETECTORS]
        while spans:
            spans.pop().remove()
        text = []
        for det, r, line, label in zip(fault_tolerance.DETECTORS, runs, lines, legend.texts,
                                       strict=True):
            rms = r.run.metrics(settle)["position_error_m"]
            line.set_data(r.run.t_days * 24, r.run.position_error())
            line.set_label(f"{det}: {rms:.0f} m")
            label.set_text(line.get_label())
            d = r.delays()[0]
            if det != "none":      # the scoring rule: schedules.score_faults
                text.append(f"{det} delay {d['delay']:.0f} s" if d["status"] == "detected" else
                            f"{det} late" if d["status"] == "late" else f"{det} missed")
                band = fault_tolerance.DETECTORS.index(det) - 1  # one band of isolation per detector
                for iv in r.isolation_intervals():
                    back = iv["back"] if iv["back"] is not None else days * DAY
                    spans.append(ax.axvspan(iv["out"] / 3600, back / 3600, ymin=0.05 * band,
                                            ymax=0.05 * (band + 1), color=f"C{band + 1}",
                                            alpha=0.8))
        spans.append(ax.axvspan(onset / 3600, (onset + duration) / 3600, color="0.85", zorder=0))
        ax.set(xlim=(settle * 24, days * 24),
               title=f"{sensor} {kind} of {size_sigma:g} sigma: " + ", ".join(text))

    update(size_sigma, sensor, kind, duration, days, seed)
    return in_place(fig, update)


@functools.lru_cache(maxsize=4)
def _fault_free_inputs(days, seed):
    """``scenarios.prepare(days=days, seed=seed)``, kept: the slider's runs only read it."""
    return scenarios.prepare(days=days, seed=seed)


def plot_error_curves(curves, faults=(), *, title="", isolations=()):
    """Fused position error curves (log scale), the faults as grey bands, isolations as ticks.

    The layout of the paper's Figs. 3 and 4 (chapter 8): each curve is a run's fused position
    error against time; each fault is a grey band from its onset to its end; each isolation
    interval of a subsystem is a coloured tick along the bottom (green XNAV, red UV, purple CNS).

    Parameters
    ----------
    curves : dict of str to (array_like, array_like)
        Label to ``(t_days, error_m)``: time, days, and the position error norm, m (> 0 for
        the log scale), of one run, both shape (N,).
    faults : sequence of Fault
        Fault onsets and durations, s since the start of the run.
    title : str
        Axes title.
    isolations : sequence of dict
        ``sensor``, ``out`` and ``back`` (s since the start; ``back`` ``None`` while still out),
        as from :meth:`xnavlab.mars.faults.fault_tolerance.FaultTolerantRun.isolation_intervals`.

    Returns
    -------
    matplotlib.figure.Figure
        One axes; not registered with pyplot.

    Examples
    --------
    >>> t = np.linspace(0.0, 2.0, 50)
    >>> fig = plot_error_curves({"run": (t, 30.0 + t)}, [Fault("uv", "step", 1.0, 86400.0, 3000.0)],
    ...                         isolations=[{"sensor": "uv", "out": 86400.0, "back": None}])
    >>> fig.axes[0].get_yscale(), len(fig.axes[0].get_lines())
    ('log', 1)
    """
    from matplotlib.figure import Figure

    series = _pairs("curves", curves, "t_days, error_m")
    faults = check_faults("faults", _sequence("faults", faults, "Faults"))
    isolations = check_records("isolations", _sequence("isolations", isolations, "dicts"),
                               ("sensor", "out", "back"), "sensor isolation")
    fig = Figure(figsize=(9.0, 3.6), layout="constrained")
    ax = fig.add_subplot()
    for label, td, e in series:
        ax.semilogy(td, e, lw=0.6, label=label)
    for f in faults:
        ax.axvspan(f.onset / DAY, f.end / DAY, color="0.75", zorder=0)
    colors = {"xnav": "C2", "uv": "C3", "cns": "C4"}
    for iv in isolations:
        back = iv["back"] if iv["back"] is not None else math.inf
        ax.axvspan(iv["out"] / DAY, min(back, 1e9) / DAY, ymax=0.04,
                   color=colors.get(iv["sensor"], "k"))
    ax.set(xlabel="time (days)", ylabel="|position error| (m)", title=title)
    ax.legend(fontsize=8, loc="upper right")
    return fig


def plot_details(t_days, x, details, onsets_days=(), *, stride=20, title=""):
    """The paper's Fig. 5 layout: a series and its detail signals D1..DJ, fault onsets dashed.

    Parameters
    ----------
    t_days : array_like, shape (N,)
        Sample times, days since the start: >= 0 and increasing.
    x : array_like, shape (N,)
        The series, m (plotted in km).
    details : array_like, shape (J, N), J >= 1
        Its detail signals, m, from :func:`xnavlab.core.detection.detail_signals
        <xnavlab.core.detection.mallat.detail_signals>`.
    onsets_days : sequence of float
        Fault onsets, days (dashed lines).
    stride : int
        Plot every ``stride``-th sample of the series and the largest ``|D_j|`` over each
        block of ``stride`` samples (keeps a month of 3-s samples drawable), from 1 to the
        series' length (a longer stride draws no sample).
    title : str
        Title of the top panel.

    Returns
    -------
    matplotlib.figure.Figure
        J + 1 panels sharing the time axis; not registered with pyplot.

    Examples
    --------
    >>> t = np.arange(400) * 3.0 / 86400.0
    >>> x = np.random.default_rng(0).normal(0.0, 5000.0, 400)
    >>> fig = plot_details(t, x, np.vstack([x, x]), [t[200]], stride=4)
    >>> len(fig.axes), fig.axes[2].get_ylabel()
    (3, 'D2 (km)')
    """
    from matplotlib.figure import Figure

    t_days = check_finite_array("t_days", t_days)
    if t_days.ndim != 1 or t_days.size == 0:
        raise ValueError(f"t_days must be a 1-D array of at least one sample time, got shape "
                         f"{t_days.shape}")
    if t_days[0] < 0.0 or np.any(np.diff(t_days) <= 0.0):  # each sample its own instant
        raise ValueError("t_days must hold increasing sample times >= 0 (days since the start)")
    x = check_shape("x", x, t_days.shape, "N = length of t_days")
    details = check_shape("details", details, (None, t_days.size), "N = length of t_days")
    if not details.shape[0]:  # no detail row: nothing below the series
        raise ValueError(f"details must hold at least one detail signal (J >= 1 rows), got "
                         f"shape {details.shape}")
    onsets_days = check_finite_array("onsets_days", _sequence("onsets_days", onsets_days,
                                                              "onsets, days"))
    if onsets_days.ndim != 1:
        raise ValueError(f"onsets_days must be a list of onsets, days, got shape {onsets_days.shape}")
    stride = check_int("stride", stride, 1, max(1, t_days.size))
    J = details.shape[0]
    fig = Figure(figsize=(9.0, 1.3 * (J + 1) + 0.6), layout="constrained")
    axes = fig.subplots(J + 1, 1, sharex=True)
    n = (t_days.size // stride) * stride
    td = t_days[:n:stride]
    axes[0].plot(td, x[:n:stride] / 1e3, lw=0.4)
    axes[0].set_ylabel("range (km)", fontsize=8)
    for j in range(J):
        d = details[j, :n].reshape(-1, stride)
        peak = d[np.arange(d.shape[0]), np.argmax(np.abs(d), axis=1)]   # signed extreme per block
        axes[j + 1].plot(td, peak / 1e3, lw=0.4)
        axes[j + 1].set_ylabel(f"D{j + 1} (km)", fontsize=8)
    for ax in axes:
        for o in onsets_days:
            ax.axvline(o, color="C3", ls="--", lw=0.6)
    axes[-1].set_xlabel("time (days)")
    if title:
        axes[0].set_title(title)
    return fig


def detector_table_markdown(table, digits=2):
    """The detectors' Monte Carlo table in the navigation loop, as a Markdown table.

    One row per fault class, sensor and size (in the order of ``table["rows"]``); one column
    per detector holding ``Pd / median delay / p95 delay / false alarms per day / RMS ratio``
    (delays in s, ``-`` where no trial detected the fault). A size the table lists as
    marked (the combined detector worse than the better of the other two beyond Monte Carlo
    error) is flagged **(marked)**.

    Parameters
    ----------
    table : dict
        ``rows`` (one dict per class, sensor, size and detector, as from
        :func:`xnavlab.mars.studies.trials.detector_table`) and ``marked`` (dicts with
        ``fault_class``, ``sensor``, ``size_index``), as
        :func:`xnavlab.mars.studies.trials.load_detector_table` returns.
    digits : int
        Decimals of Pd and of the RMS ratio, 0..6 (false alarms per day get one fewer, at
        least one).

    Returns
    -------
    str
        Markdown (display it with ``IPython.display.Markdown``).

    Examples
    --------
    >>> rows = [dict(fault_class="step", sensor="uv", size_index=0, size=3.0, detector=d,
    ...              pd=1.0, delay_median_s=12.0, delay_p95_s=None, false_alarms_per_day=0.5,
    ...              rms_ratio=1.014) for d in ("chi2", "combined")]
    >>> md = detector_table_markdown({"rows": rows, "marked": []})
    >>> len(md.splitlines()), "| 1.00 / 12 / - / 0.5 / 1.01 |" in md
    (3, True)
    """
    from xnavlab.core.plotting import markdown_table
    from xnavlab.core.validate import check_int

    check_instance("table", table, dict, "a dict with 'rows' and 'marked' "
                   "(xnavlab.mars.studies.trials.load_detector_table)")
    digits = check_int("digits", digits, 0, 6)
    try:
        rows, marked = table["rows"], table["marked"]
    except (TypeError, KeyError):
        raise ValueError("table must be a dict with 'rows' and 'marked' "
                         "(xnavlab.mars.studies.trials.load_detector_table)") from None
    fa_digits = max(1, digits - 1)

    def delay(v):
        return "-" if v is None else f"{v:.0f}"

    def summary(r):
        return (f"{r['pd']:.{digits}f} / {delay(r['delay_median_s'])} / {delay(r['delay_p95_s'])} / "
                f"{r['false_alarms_per_day']:.{fa_digits}f} / {r['rms_ratio']:.{digits}f}")

    flagged = {(m["fault_class"], m["sensor"], m["size_index"]) for m in marked}
    cells, detectors = {}, []
    for r in rows:
        key = (r["fault_class"], r["sensor"], r["size_index"])
        cells.setdefault(key, {"size": r["size"]})[r["detector"]] = summary(r)
        if r["detector"] not in detectors:
            detectors.append(r["detector"])
    cols = ["class", "sensor", "size"] + [f"{d}: Pd / med / p95 / FA/d / RMS" for d in detectors]
    out = []
    for (fc, sensor, i), c in cells.items():
        flag = " **(marked)**" if (fc, sensor, i) in flagged else ""
        out.append(dict(zip(cols, [fc, sensor, f"{c['size']:g}{flag}"]
                            + [c.get(d, "-") for d in detectors], strict=True)))
    return markdown_table(out, cols)


#: Nominal solar radius, m (IAU 2015 Resolution B3): where a line of sight starts to cross the Sun.
_R_SUN = 6.957e8


def plot_shapiro_angle(angle_deg=2.0, t=None):
    """The Sun's Shapiro delay seen from Mars: exact form against the paper's, by Sun-pulsar angle.

    At the epoch ``t`` a pulsar is placed ``angle_deg`` from the Sun as seen from the
    centre of Mars, in the plane of the Sun's direction and Mars's velocity (the plane in
    which a pulsar near the ecliptic passes behind the Sun). The left panel draws the
    exact delay (:func:`xnavlab.mars.timing.toa.shapiro`) and the paper's eq. (1) form
    (:func:`xnavlab.mars.timing.toa.shapiro_paper`) against the angle, the right panel their
    difference in microseconds and metres (``c`` times it) beside the TOA noise of the
    paper's four pulsars (:func:`xnavlab.mars.timing.pulsars.toa_sigma`, 500 s, 1 m^2); a marker
    shows ``angle_deg``. Angles inside the Sun's disc are shaded. A pure function of its
    arguments, for chapter 2's slider.

    Parameters
    ----------
    angle_deg : float
        Angle between the Sun and the pulsar as seen from Mars, degrees, in (0, 180].
    t : float, optional
        Epoch, s TDB past J2000; default :data:`xnavlab.mars.models.dynamics.MARS_T0`.

    Returns
    -------
    matplotlib.figure.Figure
        Two axes; not registered with pyplot.

    Examples
    --------
    >>> fig = plot_shapiro_angle(1.0)
    >>> len(fig.axes) >= 2, fig.axes[1].get_title().startswith("1 deg from the Sun")
    (True, True)
    """
    from matplotlib.figure import Figure

    from xnavlab.core import ephemeris
    from xnavlab.core.constants import C
    from xnavlab.mars.models import dynamics
    from xnavlab.mars.timing import pulsars, toa

    angle_deg = check_real("angle_deg", angle_deg, 0.0, 180.0, lo_open=True)
    t0 = dynamics.MARS_T0 if t is None else check_real("t", t)
    r_mars, v_mars = (np.asarray(a, dtype=float).reshape(3) for a in ephemeris.state("mars", t0))
    r_sun = np.asarray(ephemeris.position("sun", t0), dtype=float).reshape(3)
    to_sun = r_sun - r_mars
    dist = np.linalg.norm(to_sun)
    u = to_sun / dist                                  # Mars -> Sun
    e = v_mars - (v_mars @ u) * u
    e /= np.linalg.norm(e)                             # in the plane of u and Mars's velocity

    def directions(theta_deg):
        th = np.radians(np.atleast_1d(theta_deg))
        return np.cos(th)[:, None] * u + np.sin(th)[:, None] * e

    base = np.geomspace(0.05, 180.0, 400)
    disc_deg = math.degrees(math.asin(_R_SUN / dist))  # the Sun's angular radius from Mars

    fig = Figure(figsize=(10, 3.4), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2)
    marks = []
    for ax in (ax1, ax2):
        ax.axvspan(base[0], disc_deg, color="0.85", lw=0)
        marks.append(ax.axvline(1.0, color="k", lw=0.8, ls=":"))
        ax.set(xscale="log", xlabel="Sun-pulsar angle seen from Mars (deg)", xlim=(base[0], 180.0))
    exact_line, = ax1.plot([], [], label="exact (toa.shapiro)")
    paper_line, = ax1.plot([], [], "--", label="paper eq. (1) (toa.shapiro_paper)")
    pair, = ax1.plot([], [], "ko", ms=4)
    ax1.set(ylabel="Shapiro delay (us)")
    ax1.set_title("the Sun's Shapiro delay, referred to the SSB", fontsize=10)
    ax1.legend(fontsize=8)
    diff_line, = ax2.loglog([], [], color="C3", label="|paper - exact|")
    for k, name in enumerate(pulsars.PAPER_PULSARS):
        ax2.axhline(pulsars.toa_sigma(name) * 1e6, color=f"C{k}", lw=0.8, ls="--",
                    label=f"TOA noise {name}")
    dot, = ax2.plot([], [], "ko", ms=5)
    ax2.set(ylabel="us", ylim=(1e-4, 1e3))
    sec = ax2.secondary_yaxis("right", functions=(lambda us: us * 1e-6 * C, lambda m: m / C * 1e6))
    sec.set_ylabel("m")
    ax2.legend(fontsize=7, loc="lower left")
    sparse_log_minors(ax1, ax2)  # three log axes over 4-7 decades: half the render

    def update(angle_deg=2.0, t=None):
        angle_deg = check_real("angle_deg", angle_deg, 0.0, 180.0, lo_open=True)
        if (dynamics.MARS_T0 if t is None else check_real("t", t)) != t0:
            return False  # another epoch: another geometry, a new figure
        grid = np.unique(np.concatenate([base, [angle_deg]]))
        exact = toa.shapiro(r_mars, directions(grid), r_sun) * 1e6         # us
        paper = toa.shapiro_paper(r_mars, directions(grid), r_sun) * 1e6
        diff = np.abs(paper - exact)
        at = float(np.interp(angle_deg, grid, diff))
        ex_at, pa_at = (float(np.interp(angle_deg, grid, v)) for v in (exact, paper))
        for mark in marks:
            mark.set_xdata([angle_deg, angle_deg])
        exact_line.set_data(grid, exact)
        paper_line.set_data(grid, paper)
        pair.set_data([angle_deg] * 2, [ex_at, pa_at])
        diff_line.set_data(grid, diff)
        dot.set_data([angle_deg], [at])
        ax1.relim()
        ax1.autoscale_view()
        at_m = C * at * 1e-6
        ax2.set_title(f"{angle_deg:g} deg from the Sun: paper - exact = {at:.3g} us = "
                      + (f"{at_m:,.0f}" if at_m >= 100 else f"{at_m:.2g}") + " m", fontsize=10)

    update(angle_deg, t)
    return in_place(fig, update)


def _sequence(name, value, what):
    """``value`` as a list (a tuple, a list or a 1-D array), else one ValueError naming ``name``
    (a number, a string, a dict or a 0-d array is no list)."""
    if isinstance(value, str | bytes | dict) or not hasattr(value, "__iter__") or (
            isinstance(value, np.ndarray) and value.ndim != 1):
        raise ValueError(f"{name} must be a list of {what}, got {shown(value)}")
    return list(value)


def _pairs(name, value, what):
    """``{label: (t_days, y)}`` checked: a dict of at least one pair of 1-D arrays (finite
    times) of one length (at least one record), times >= 0 and non-decreasing; else one ValueError naming
    ``name['label']``. Returns ``[(label, t, y)]``."""
    check_instance(name, value, dict, f"a dict of label -> ({what})")
    if not value:
        raise ValueError(f"{name} must hold at least one ({what}) pair")
    out = []
    for label, pair in value.items():
        where = f"{name}[{label!r}]"
        if isinstance(pair, str | bytes | dict) or not hasattr(pair, "__len__") or len(pair) != 2:
            raise ValueError(f"{where} must be a pair ({what}), got {shown(pair)}")
        t = check_finite_array(f"{where}[0]", pair[0])
        y = check_finite_array(f"{where}[1]", pair[1], finite=False)  # a diverged case: inf
        if t.ndim != 1 or not t.size:
            raise ValueError(f"{where}[0] must be a 1-D array of at least one time, got shape "
                             f"{t.shape}")
        check_shape(f"{where}[1]", y, t.shape, f"one value a time of {where}[0]")
        if t[0] < 0.0 or np.any(np.diff(t) < 0.0):
            raise ValueError(f"{where}[0] must hold non-decreasing times >= 0 (days since the "
                             f"start)")
        out.append((label, t, y))
    return out


#: Most bins of :func:`plot_consistency`'s top panel (last time / bin_days).
_MAX_BINS = 10**6
#: The range of :func:`plot_consistency`'s ``ylim`` values: matplotlib's log-axis ticks
#: overflow for wider limits (1e-250 to 1e250 already did).
YLIM_RANGE = (1e-200, 1e200)


#: Line colours of the cases of :func:`plot_consistency` (green and red mark the band's shares).
_CASE_COLORS = ("C0", "k", "C1", "C4", "C5", "C6", "C8", "C9")


def plot_consistency(cases, band, dof=6, settle_days=1.0, bin_days=1.0 / 24.0, ylim=None):
    """Run-averaged NEES of several cases over time, and the share of records in their band.

    Top: the NEES averaged over ``bin_days`` bins (log scale), with the 95 % band of one record
    and the mean ``dof`` of a consistent filter. Bottom: for each case, the shares of the
    records after ``settle_days`` below, inside and above the band
    (:func:`xnavlab.core.filters.judge_series`, whose verdict labels the bar). For chapter 5's
    instruments and force-model cases.

    Parameters
    ----------
    cases : dict
        ``{label: (t_days, nees)}``: record times, days since the start, shape (n,), and the
        run-averaged NEES at each (>= 0), shape (n,).
    band : tuple of float
        ``(lo, hi)``, ``0 <= lo < hi``: the 95 % band of one record's average
        (:func:`xnavlab.core.filters.chi2_bounds`).
    dof : int
        Degrees of freedom (6: position and velocity), 1 to 1000.
    settle_days : float
        Start of the judged span, days, >= 0 and at most every case's last record time.
    bin_days : float
        Width of the averaging bins of the top panel, days (default one hour); at most
        10^6 bins up to the last record (5e-324 is refused, not divided by).
    ylim : tuple of float, optional
        Limits ``(lo, hi)``, lo < hi, each in :data:`YLIM_RANGE`, of the top panel's (log)
        NEES axis (a diverging case may leave it; its bar still shows it).

    Returns
    -------
    matplotlib.figure.Figure
        Two axes; not registered with pyplot.

    Examples
    --------
    >>> t = np.linspace(0.0, 2.0, 2881)
    >>> fig = plot_consistency({"a": (t, np.full(t.size, 6.0)), "b": (t, np.full(t.size, 1e3))},
    ...                        (4.0, 8.0))
    >>> [label.get_text() for label in fig.axes[1].get_yticklabels()]
    ['a: inside', 'b: optimistic']
    """
    from matplotlib.figure import Figure

    from xnavlab.core.filters import judge_series

    series = _pairs("cases", cases, "t_days, nees")
    band = _sequence("band", band, "two numbers (lo, hi)")
    if len(band) != 2:
        raise ValueError(f"band must be a pair (lo, hi), got {shown(band)}")
    lo, hi = (check_real(n, v, 0.0) for n, v in zip(("band[0]", "band[1]"), band, strict=True))
    if lo >= hi:  # judge_series named its own lo and hi; (0, 0) holds no record
        raise ValueError(f"band must be (lo, hi) with lo < hi, got {shown(tuple(band))}")
    for label, _, nees in series:  # judge_series named its values[i], of the judged span
        if np.any(nees < 0.0):
            i = int(np.argmax(nees < 0.0))
            raise ValueError(f"cases[{label!r}][1][{i}] must be a NEES value in [0, inf), got "
                             f"{nees[i]:g}")
    dof = check_int("dof", dof, 1, 1000)
    settle_days = check_real("settle_days", settle_days, 0.0)
    for label, t, _ in series:
        if t[-1] < settle_days:
            raise ValueError(f"settle_days must be at most the last record time of every case, "
                             f"{t[-1]:g} days for cases[{label!r}], got {settle_days:g}")
    bin_days = check_real("bin_days", bin_days, 0.0, lo_open=True)
    last = float(max(t[-1] for _, t, _ in series))
    if last > _MAX_BINS * bin_days:  # (not last / bin_days: 5e-324 overflows)
        raise ValueError(f"bin_days must be at least {last / _MAX_BINS:.3g} (at most "
                         f"{_MAX_BINS:.0e} bins up to day {last:g}), got {bin_days:g}")
    if ylim is not None:
        ylim = _sequence("ylim", ylim, "two numbers (lo, hi)")
        if len(ylim) != 2:
            raise ValueError(f"ylim must be a pair (lo, hi), got {shown(ylim)}")
        # matplotlib's log-axis ticks overflow (a RuntimeWarning) for limits past about 1e250
        ylim = [check_real(f"ylim[{i}]", v, YLIM_RANGE[0], YLIM_RANGE[1]) for i, v in enumerate(ylim)]
        if ylim[0] >= ylim[1]:
            raise ValueError(f"ylim must be (lo, hi) with lo < hi, got {shown(tuple(ylim))}")
    fig = Figure(figsize=(8, 5.6), layout="constrained")
    top, bars = fig.subplots(2, 1, height_ratios=(2, 1))
    binned = []
    for _, t, nees in series:
        b = np.floor(t / bin_days).astype(int)
        n = np.bincount(b)
        have = n > 0
        binned.append((((np.arange(n.size) + 0.5) * bin_days)[have],
                       (np.bincount(b, nees) / np.maximum(n, 1))[have]))
    drawn = [v for v in [lo, hi, dof, *(v for _, m in binned for v in (m.min(), m.max()))]
             if 0.0 < v < math.inf]
    if ylim is None and (min(drawn) < YLIM_RANGE[0] or max(drawn) > YLIM_RANGE[1]):
        # a diverged case (NEES 1e300): matplotlib's log autoscale would overflow; the axis
        # ends at the range's edge and the case's bar still shows where it went
        ylim = (max(min(drawn), YLIM_RANGE[0]), min(max(drawn), YLIM_RANGE[1]))
    top.set_yscale("log")
    if ylim is not None:  # before the curves: no autoscale of them first
        top.set_ylim(*ylim)
    names = []
    for k, ((label, t, nees), (x, mean)) in enumerate(zip(series, binned, strict=True)):
        top.plot(x, mean, color=_CASE_COLORS[k % len(_CASE_COLORS)], lw=0.8, label=label)
        j = judge_series(nees[t >= settle_days], lo, hi)
        left = 0.0
        for share, color, word in ((j["below"], "0.6", "below"), (j["inside"], "C2", "inside"),
                                   (j["above"], "C3", "above")):
            bars.barh(k, share, left=left, color=color, label=word if k == 0 else None)
            left += share
        names.append(f"{label}: {j['verdict']}")
    top.axhspan(lo, hi, color="C2", alpha=0.25, label="95 % band of one record")
    top.axhline(dof, color="k", ls="--", lw=0.8, label=f"{dof}: a consistent filter's mean")
    top.set(xlabel="time (days)", ylabel="NEES, hourly mean" if bin_days == 1.0 / 24.0
            else "NEES, binned mean")
    fig.legend(*top.get_legend_handles_labels(), fontsize=7, ncol=3, loc="outside upper center")
    bars.set_yticks(range(len(names)), names, fontsize=8)
    bars.invert_yaxis()
    bars.set(xlim=(0.0, 1.0), xlabel=f"share of the records after day {settle_days:g} "
             "below, inside and above the band")
    bars.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return fig

