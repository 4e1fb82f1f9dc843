"""The attitude chapter's figures: a run's residuals against their thresholds, SOS beside DOS.

:func:`plot_residuals` draws one method's residuals of an
:class:`xnavlab.attitude.simulation.AttitudeRun`; :func:`plot_fault_case` simulates one
fault and draws SOS and DOS side by side (a pure function of its arguments: the chapter's
slider calls it). Residuals are shown in deg/h.
"""

from __future__ import annotations

import math

import numpy as np

from xnavlab.attitude.sensors import DEFAULT_MAGNITUDES, DEG_PER_H, LOCATIONS, MAX_FACTOR, make_fault
from xnavlab.attitude.simulation import AttitudeRun, simulate
from xnavlab.core.validate import check_choice, check_real, check_text, shown

__all__ = [
    "LOCATION_NAMES",
    "location_name",
    "plot_residuals",
    "plot_fault_case",
]

#: Plain words for the fault locations and the diagnoses' verdicts
#: (:data:`xnavlab.attitude.diagnosis.VERDICTS`), for titles and printed output.
LOCATION_NAMES = {"none": "none", "gyro_x": "x gyro", "gyro_y": "y gyro", "gyro_z": "z gyro",
                  "gyro_skew": "skewed gyro", "star_tracker": "star tracker", "unknown": "unknown"}


def location_name(name):
    """A location or verdict in plain words (:data:`LOCATION_NAMES`; others: ``_`` as a space).

    Examples
    --------
    >>> location_name("gyro_skew"), location_name("star_tracker"), location_name("a_b")
    ('skewed gyro', 'star tracker', 'a b')
    """
    name = check_text("name", name)  # a verdict is text (a bool or a list was spelled out as one)
    return LOCATION_NAMES.get(name, name.replace("_", " "))


def plot_residuals(run, method="sos", axes=None):
    """Plot a run's residuals against their thresholds (deg/h), one panel per residual.

    Parameters
    ----------
    run : AttitudeRun
    method : {"sos", "dos", "qdiff"}
    axes : sequence of matplotlib Axes, optional
        Four axes (three for ``"qdiff"``), no more: 2-D rectilinear Axes of one figure
        (:func:`xnavlab.core.plotting.check_axes`); a new figure when omitted.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import matplotlib; matplotlib.use("Agg")
    >>> fig = plot_residuals(simulate(duration=50.0))
    >>> len(fig.axes)
    4
    """
    import matplotlib.pyplot as plt

    t, r, J, d, names = _residual_parts(run, method)
    m = r.shape[1]
    if axes is None:
        fig, axes = plt.subplots(m, 1, sharex=True, figsize=(7, 1.5 * m + 1), squeeze=False)
        axes = axes[:, 0]
    else:  # a string or a short list was an AttributeError or IndexError from inside
        from xnavlab.core.plotting import check_axes

        if isinstance(axes, str | bytes | dict) or not hasattr(axes, "__len__") or len(axes) != m \
                or np.asarray(axes, dtype=object).ndim != 1:
            raise ValueError(f"axes must be a sequence of {m} matplotlib Axes (one per residual of "
                             f"{method!r}), got {shown(axes)}")
        fig = check_axes("axes[0]", axes[0])[0]  # each 2-D, of one figure
        for i in range(1, m):
            check_axes(f"axes[{i}]", axes[i], fig)
    _residual_axes(axes[:m], run, method)(run)
    axes[m - 1].set_xlabel("t (s)")
    return fig


def _residual_parts(run, method):
    """``(t, r, J, d, names)`` of one method's residuals (checked)."""
    check_choice("method", method, ("sos", "dos", "qdiff"))
    if not isinstance(run, AttitudeRun):
        raise ValueError(f"run must be an AttitudeRun, got {type(run).__name__}")
    if method == "dos" and run.dos is None:
        raise ValueError("method='dos' needs a run simulated with dos=True")
    if method == "sos":
        t, r, J, d = run.t, run.sos_r, run.sos_J, run.sos
        names = ["$r_1$ (x)", "$r_2$ (y)", "$r_3$ (z)", "$r_4$ (parity)"]
    elif method == "dos":
        t, r, J, d = run.t, run.dos_r, run.dos_J, run.dos
        names = [f"$R_{j + 1}$ (no {g})" for j, g in enumerate(("x", "y", "z", "skew"))]
    else:
        t, r, J, d = run.t_qd, np.abs(run.qd_f), run.qd_J, run.qd
        names = ["$|f_x|$", "$|f_y|$", "$|f_z|$"]
    return t, r, J, d, names


def _run_timing(run, method):
    """What the residual panels of ``run`` share with another run's: times, calibration, onset."""
    t = _residual_parts(run, method)[0]
    return t, run.config.t_cal[1], run.onset


def _residual_axes(axes, run, method):
    """Draw the parts of the residual panels that ``run``'s timing fixes; return
    ``set_run(run)``, which draws a run of that timing (``False``, changing nothing, for a
    run of another timing)."""
    t, t_cal_end, onset = _run_timing(run, method)
    names = _residual_parts(run, method)[4]
    curves, limits = [], []
    for i, ax in enumerate(axes):
        curves.append(ax.plot(t, np.zeros(t.size), lw=0.8)[0])
        limits.append(ax.axhline(0.0, color="C3", ls="--", lw=0.8))
        ax.axvspan(t[0], t_cal_end, color="0.9", lw=0)
        if math.isfinite(onset):
            ax.axvline(onset, color="k", ls=":", lw=0.8)
        ax.set_ylabel(names[i] + "\n deg/h", fontsize=8)
    title = axes[0].set_title("", fontsize=9)

    def set_run(run):
        t_new, cal_new, onset_new = _run_timing(run, method)
        if not (np.array_equal(t_new, t) and cal_new == t_cal_end
                and (onset_new == onset or not (math.isfinite(onset) or math.isfinite(onset_new)))):
            return False
        _, r, J, d, _ = _residual_parts(run, method)
        for i, ax in enumerate(axes):
            curves[i].set_ydata(r[:, i] / DEG_PER_H)
            limits[i].set_ydata([J[i] / DEG_PER_H] * 2)
            top = max(4.0 * J[i], float(np.max(r[t >= t_cal_end, i], initial=0.0)) * 1.1)
            ax.set_ylim(0.0, top / DEG_PER_H)
        det = float(d.detect_time)
        if not math.isfinite(det):
            when = "no detection"
        elif math.isfinite(run.onset):
            when = f"detected {det - run.onset:+.1f} s after onset"
        else:
            when = f"detected at {det:.1f} s"
        title.set_text(f"{method.upper()}: verdict {location_name(d.verdict)} ({when}); "
                       f"truth {location_name(run.truth)}")
        return None

    return set_run


def plot_fault_case(location="gyro_x", kind="ramp", size=10.0, n_sigma=5.0, *, rng=None):
    """Simulate one fault and plot its SOS and DOS residuals side by side.

    A pure function of its arguments (the sensor noise is seeded): the chapter's slider
    calls it.

    Parameters
    ----------
    location : {"gyro_x", "gyro_y", "gyro_z", "gyro_skew", "star_tracker"}
    kind : {"step", "ramp"}
    size : float
        Multiple of the reference size :data:`~.sensors.DEFAULT_MAGNITUDES` of ``(sensor, kind)``,
        in [1e-6, MAX_FACTOR].
    n_sigma : float
        Threshold multiplier of :func:`~.simulation.simulate`, in [0.01, 30] (as
        :class:`~.simulation.SimConfig`'s).
    rng : numpy.random.Generator or int, optional
        Seed of the sensor noise (default 0, as :func:`~.simulation.simulate`).

    Returns
    -------
    matplotlib.figure.Figure
        Four rows (the residuals), SOS left and DOS right, as :func:`plot_residuals`; not
        registered with pyplot. It carries an in-place update
        (:func:`xnavlab.core.plotting.in_place`) that a live slider calls.

    Examples
    --------
    >>> fig = plot_fault_case("gyro_x", "step", 1.0)
    >>> len(fig.axes), fig.axes[0].get_title()[:23]
    (8, 'SOS: verdict x gyro (de')
    """
    run = _fault_run(location, kind, size, n_sigma, rng)
    from matplotlib.figure import Figure

    from xnavlab.core.plotting import in_place

    # fixed margins, not the constrained layout: half the drawing time of these eight panels
    # (0.16 s of 0.32 s), which the chapter's live slider pays at every redraw
    fig = Figure(figsize=(12, 6.5))
    fig.subplots_adjust(left=0.07, right=0.99, bottom=0.08, top=0.95, wspace=0.2, hspace=0.22)
    axes = fig.subplots(4, 2, sharex=True)
    panels = [_residual_axes(axes[:, k], run, method) for k, method in enumerate(("sos", "dos"))]
    axes[3, 0].set_xlabel("t (s)")
    axes[3, 1].set_xlabel("t (s)")

    def update(location="gyro_x", kind="ramp", size=10.0, n_sigma=5.0, *, rng=None):
        run = _fault_run(location, kind, size, n_sigma, rng)
        if panels[0](run) is False:  # other times or onset (SOS and DOS share them)
            return False  # a new figure
        panels[1](run)
        return None

    update(location, kind, size, n_sigma, rng=rng)
    return in_place(fig, update)


def _fault_run(location, kind, size, n_sigma, rng):
    """The run of :func:`plot_fault_case` (checked arguments)."""
    check_choice("location", location, LOCATIONS)
    check_choice("kind", kind, ("step", "ramp"))
    # From a millionth of the reference fault (far below the noise; a subnormal multiple made
    # the magnitude 0, a zero-size fault) to MAX_FACTOR.
    size = check_real("size", size, 1e-6, MAX_FACTOR)
    sensor = "star_tracker" if location == "star_tracker" else "gyro"
    return simulate(make_fault(location, kind, size * DEFAULT_MAGNITUDES[(sensor, kind)]),
                    n_sigma=n_sigma, rng=rng)
