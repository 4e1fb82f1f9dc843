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
