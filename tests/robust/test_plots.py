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


def test_filter_comparison_gives_compare_filters_numbers_and_keeps_them():
    """The slider's cached runs equal one compare_filters call, also after an eps move."""
    import numpy as np

    from xnavlab.robust import filters
    from xnavlab.robust import plots as rplots

    key = "B0531+21, B1821-24, B1957+20"
    rplots.filter_comparison(700.0, 30.0, key)           # RKF at another eps, kept first
    out = rplots.filter_comparison(700.0, 300.0, key)
    ref = filters.compare_filters("mars", error="growing", size=700.0, eps=300.0,
                                  pulsar_names=rplots.PULSAR_SETS[key], seeds=(0,))
    assert out["rmse"] == ref["rmse"]
    assert np.array_equal(out["tau"], ref["tau"])
    for f in filters.FILTERS:
        assert np.array_equal(out["error"][f], ref["error"][f])
    again = rplots.filter_comparison(700.0, 300.0, key)
    assert again["error"]["rkf"] is out["error"]["rkf"]   # the kept run, not a new one
    with pytest.raises(ValueError, match="eps"):
        rplots.filter_comparison(700.0, 0.0, key)
