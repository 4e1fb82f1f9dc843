"""The fuzzy-parity chapter's figure: residual norms with the threshold, identified faults.
"""

from __future__ import annotations

import numpy as np

from xnavlab.core.faults import MAX_SIZE, Fault
from xnavlab.core.validate import check_int, check_real, shown
from xnavlab.plins.parity.diagnosis import FLIGHT_S, Diagnosis, diagnose_flight
from xnavlab.plins.pseudolites import SENSOR

__all__ = [
    "plot_diagnosis",
    "plot_step_diagnosis",
]


def plot_diagnosis(diag, axes=None):
    """Plot the residual norms with the threshold, and the identified fault parameters.

    Parameters
    ----------
    diag : ~xnavlab.plins.parity.diagnosis.Diagnosis
        From :func:`~.diagnosis.diagnose_flight`.
    axes : sequence of 2 matplotlib Axes, optional
        Where to draw: two 2-D rectilinear Axes of one figure
        (:func:`xnavlab.core.plotting.check_axes`); a new figure when omitted.

    Returns
    -------
    matplotlib.figure.Figure
        Left, the residual norms and the threshold (log scale, m), their legend below the axes;
        right, the identified parameters with the injected faults dotted.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from xnavlab.plins.parity.diagnosis import diagnose_flight
    >>> fig = plot_diagnosis(diagnose_flight(duration=40.0))
    >>> len(fig.axes)
    2
    """
    if not isinstance(diag, Diagnosis):
        raise ValueError(f"diag must be a Diagnosis, got {type(diag).__name__}")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FuncFormatter, LogLocator

    from xnavlab.core.plotting import check_axes

    if axes is None:
        fig, axes = plt.subplots(1, 2, figsize=(10, 3.6), constrained_layout=True)
    elif not (isinstance(axes, list | tuple | np.ndarray) and len(axes) == 2
              and np.asarray(axes, dtype=object).ndim == 1):
        raise ValueError(f"axes must be a pair of matplotlib Axes (left, right), got {shown(axes)}")
    else:  # each 2-D, of one figure (a polar or removed Axes was matplotlib's error)
        fig = check_axes("axes[0]", axes[0])[0]
        check_axes("axes[1]", axes[1], fig)
    ax0, ax1 = axes
    for j in range(diag.statistic.shape[1]):
        ax0.semilogy(diag.t_res, np.maximum(diag.statistic[:, j], 1e-3), label=f"PR{j + 1}")
    ax0.axhline(diag.threshold, color="k", ls="--", lw=1, label="$r_t$")
    ax0.yaxis.set_major_locator(LogLocator(base=10.0, subs=(1.0, 2.0, 5.0), numticks=15))
    ax0.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    ax0.yaxis.set_minor_formatter(FuncFormatter(lambda v, _: ""))
    ax0.set_xlabel("time (s)")
    ax0.set_ylabel(r"$\|r_j\|$ (m)")
    # below the axes, in one row: the residuals fill the panel (a fault's peak sits anywhere)
    ax0.legend(fontsize=8, ncol=5, loc="upper center", bbox_to_anchor=(0.5, -0.2), frameon=False)
    for j, idn in diag.identification.items():
        for i, name in enumerate(idn.names):
            ax1.plot(idn.t, idn.theta[:, i], label=f"PR{j + 1} {name}")
    for j in range(diag.fault.shape[1]):
        if np.any(diag.fault[:, j]):
            ax1.plot(diag.t, diag.fault[:, j], color="0.5", lw=0.8, ls=":")
    ax1.set_xlabel("time (s)")
    ax1.set_ylabel("estimate (m, m/s)")
    if diag.identification:
        ax1.legend(fontsize=8)
    return fig


def plot_step_diagnosis(step_m=30.0, s=11, threshold_m=14.0, *, component=0, onset_s=50.0):
    """Diagnose the flight with one pseudorange step and plot it: the chapter's slider.

    Runs :func:`~.diagnosis.diagnose_flight` with a step of ``step_m`` on pseudorange
    ``component`` from ``onset_s`` on, the window ``s`` and the threshold ``threshold_m``, and
    draws :func:`plot_diagnosis` in a new figure (not registered with pyplot, so a live
    slider may draw it in a second thread), titled with the step and the first alarm of the
    faulty pseudorange. A pure function of its arguments.

    Parameters
    ----------
    step_m : float
        Step size, m, nonzero, ``|step_m| <= 1e15`` (:data:`xnavlab.core.faults.MAX_SIZE`).
    s : int
        Window length minus one (samples); :func:`~.diagnosis.diagnose_flight` checks it.
    threshold_m : float
        Threshold ``r_t`` of the residual norms, m (> 0).
    component : int
        The faulty pseudorange, 0-based (0..3).
    onset_s : float
        Onset of the step, s, in [0, FLIGHT_S] (the flight of :func:`~.diagnosis.diagnose_flight`).

    Returns
    -------
    matplotlib.figure.Figure
        As :func:`plot_diagnosis`; the left panel's title says
        ``"<step> m step on PR<k>: alarm at <t> s"`` or ``"...: no alarm"``. It carries an
        in-place update (:func:`xnavlab.core.plotting.in_place`) that a live slider calls.

    Examples
    --------
    >>> fig = plot_step_diagnosis(step_m=300.0, threshold_m=14.0)
    >>> fig.axes[0].get_title()
    '300 m step on PR1: alarm at 50 s'
    """
    from matplotlib.figure import Figure

    from xnavlab.core.plotting import in_place

    def diagnose(step_m, s, threshold_m, component, onset_s):
        # a nonzero step within Fault's size bound, inside diagnose_flight's 200-s flight
        step_m = check_real("step_m", step_m, -MAX_SIZE, MAX_SIZE)
        if step_m == 0.0:
            raise ValueError("step_m must be nonzero (a step of 0 m is no fault), got 0")
        threshold_m = check_real("threshold_m", threshold_m, 0.0, lo_open=True)
        component = check_int("component", component, 0, 3)
        onset_s = check_real("onset_s", onset_s, 0.0, FLIGHT_S)
        d = diagnose_flight([Fault(SENSOR, "step", step_m, onset_s, component=component)],
                            s=s, threshold=threshold_m)
        alarm = d.detection[component]
        return d, (f"{step_m:g} m step on PR{component + 1}: "
                   + (f"alarm at {alarm:g} s" if alarm is not None else "no alarm"))

    d, title = diagnose(step_m, s, threshold_m, component, onset_s)
    fig = Figure(figsize=(10, 3.6), layout="constrained")
    ax0, ax1 = fig.subplots(1, 2)
    plot_diagnosis(d, axes=(ax0, ax1))
    ax0.set_title(title)
    m = d.statistic.shape[1]
    built = d.fault.shape

    def update(step_m=30.0, s=11, threshold_m=14.0, *, component=0, onset_s=50.0):
        d, title = diagnose(step_m, s, threshold_m, component, onset_s)
        if d.fault.shape != built:
            return False  # another flight: a new figure
        # left: the residual norms and the threshold (the artists plot_diagnosis drew)
        for j, line in enumerate(ax0.lines[:m]):
            line.set_data(d.t_res, np.maximum(d.statistic[:, j], 1e-3))
        ax0.lines[m].set_ydata([d.threshold, d.threshold])
        ax0.set_title(title)
        # right: drawn again as plot_diagnosis draws it (its colours, its order)
        for line in list(ax1.lines):
            line.remove()
        if ax1.get_legend() is not None:
            ax1.get_legend().remove()
        k = 0
        for j, idn in d.identification.items():
            for i, name in enumerate(idn.names):
                ax1.plot(idn.t, idn.theta[:, i], color=f"C{k % 10}", label=f"PR{j + 1} {name}")
                k += 1
        for j in range(d.fault.shape[1]):
            if np.any(d.fault[:, j]):
                ax1.plot(d.t, d.fault[:, j], color="0.5", lw=0.8, ls=":")
        if d.identification:
            ax1.legend(fontsize=8)
        for ax in (ax0, ax1):
            ax.relim()
            ax.autoscale_view()
        return None

    return in_place(fig, update)
