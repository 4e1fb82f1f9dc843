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


def test_plot_step_diagnosis_is_plot_diagnosis_of_the_step_with_its_alarm_in_the_title():
    """The slider's function: one step on a pseudorange, the flight diagnosed, not in pyplot."""
    import matplotlib.pyplot as plt
    import numpy as np

    before = plt.get_fignums()
    fig = P.plot_step_diagnosis(step_m=30.0, s=11, threshold_m=14.0, component=1)
    assert plt.get_fignums() == before  # a Figure of its own: the live slider's worker may draw it
    d = P.diagnose_flight([Fault(pl.SENSOR, "step", 30.0, 50.0, component=1)], s=11,
                          threshold=14.0)
    ref = P.plot_diagnosis(d)
    assert fig.axes[0].get_title() == f"30 m step on PR2: alarm at {d.detection[1]:g} s"
    for a, b in zip(fig.axes, ref.axes, strict=True):
        for la, lb in zip(a.lines, b.lines, strict=True):
            np.testing.assert_array_equal(la.get_ydata(), lb.get_ydata())
    plt.close(ref)
    assert P.plot_step_diagnosis(step_m=5.0, threshold_m=40.0).axes[0].get_title() == (
        "5 m step on PR1: no alarm")


@pytest.mark.parametrize(("kwargs", "name"), [
    ({"threshold_m": 0.0}, "threshold_m"),
    ({"component": 4}, "component"),
    ({"s": 1}, "s"),
])
def test_plot_step_diagnosis_bad_input(kwargs, name):
    with pytest.raises(ValueError, match=name):
        P.plot_step_diagnosis(**kwargs)


def test_plot_diagnosis_names_axes_that_are_no_pair_of_axes():
    """Issue 35 (review 35i): axes="ax" was an AttributeError, [ax] 'not enough values to
    unpack'."""
    from matplotlib.figure import Figure

    d = P.diagnose_flight(duration=40.0)
    ax = Figure().subplots()
    for axes in ("ax", [ax], True, Figure().subplots(2, 2)):
        with pytest.raises(ValueError, match=r"^axes must be a pair of matplotlib Axes"):
            P.plot_diagnosis(d, axes=axes)
    with pytest.raises(ValueError, match=r"^axes\[1\] must be a 2-D rectilinear matplotlib Axes, got str"):
        P.plot_diagnosis(d, axes=(ax, "ax"))  # review 35m: the item at fault named
    fig = Figure()
    assert P.plot_diagnosis(d, axes=fig.subplots(1, 2)) is fig


def test_plot_diagnosis_refuses_a_polar_removed_or_foreign_axes():
    """Review 35m (1) 3, the rule of every plot's axes: a polar Axes was matplotlib's
    NotImplementedError (no log scale), a removed one an AttributeError, two figures' pair
    returned one of them."""
    from matplotlib.figure import Figure

    d = P.diagnose_flight(duration=40.0)
    fig = Figure()
    left = fig.add_subplot(1, 2, 1)
    polar = fig.add_subplot(1, 2, 2, projection="polar")
    with pytest.raises(ValueError,
                       match=r"^axes\[1\] must be a 2-D rectilinear matplotlib Axes, got a 'polar'"):
        P.plot_diagnosis(d, axes=[left, polar])
    with pytest.raises(ValueError, match=r"^axes\[1\] must be an Axes of the same figure"):
        P.plot_diagnosis(d, axes=[left, Figure().subplots()])
    gone = fig.add_subplot(2, 2, 4)
    gone.remove()
    with pytest.raises(ValueError, match=r"^axes\[1\] must be a 2-D rectilinear matplotlib Axes of a figure"):
        P.plot_diagnosis(d, axes=[left, gone])
    assert not left.lines  # refused before anything was drawn
