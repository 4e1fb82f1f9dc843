"""The fuzzy-parity chapter's figure: residual norms with the threshold, identified faults.
"""

from __future__ import annotations

import numpy as np

from xnavlab.plins.parity.diagnosis import Diagnosis

__all__ = [
    "plot_diagnosis",
]


def plot_diagnosis(diag, axes=None):
    """Plot the residual norms with the threshold, and the identified fault parameters.

    Parameters
    ----------
    diag : ~xnavlab.plins.parity.diagnosis.Diagnosis
        From :func:`~.diagnosis.diagnose_flight`.
    axes : sequence of 2 matplotlib Axes, optional
        Where to draw (a new figure when omitted).

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

    if axes is None:
        fig, axes = plt.subplots(1, 2, figsize=(10, 3.6), constrained_layout=True)
    else:
        fig = axes[0].figure
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
