"""The PL/INS diagnosis figure (xnavlab.plins.parity.plots)."""

import pytest

from xnavlab.core.faults import Fault
from xnavlab.plins import parity as P
from xnavlab.plins import pseudolites as pl


def test_plot_diagnosis_draws_two_panels_and_checks_its_input():
    fig = P.plot_diagnosis(P.diagnose_flight([Fault(pl.SENSOR, "step", 50.0, 50.0, component=0)]))
    assert len(fig.axes) == 2
    with pytest.raises(ValueError, match="diag"):
        P.plot_diagnosis(None)


def test_plot_diagnosis_keeps_its_legend_off_the_residuals():
    """The residuals' legend sits below the axes (a fault's peak may be anywhere in the panel)."""
    fig = P.plot_diagnosis(P.diagnose_flight([Fault(pl.SENSOR, "step", 12.0, 50.0, component=0)]))
    fig.canvas.draw()
    ax = fig.axes[0]
    legend = ax.get_legend().get_window_extent()
    assert legend.y1 <= ax.get_window_extent().y0          # wholly below the axes
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["PR1", "PR2", "PR3", "PR4", "$r_t$"]
