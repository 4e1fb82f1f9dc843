"""The ephemeris-error figures (xnavlab.robust.plots)."""


import pytest


def test_plot_filter_comparison_is_a_pure_figure_and_checks_its_input():
    from xnavlab.robust import plots as rplots

    fig = rplots.plot_filter_comparison(300.0, 100.0, "all four")
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert labels == ["UKF", "ASUKF", "TDUKF", "RKF"]
    with pytest.raises(ValueError, match="pulsar_set"):
        rplots.plot_filter_comparison(300.0, 100.0, "three of them")
    with pytest.raises(ValueError, match="size"):
        rplots.plot_filter_comparison(-1.0)
