"""The chapter figures of xnavlab.mars.navigation.plots (more in test_scenarios and test_fault_tolerance)."""

import re

import matplotlib
import numpy as np
import pytest

from xnavlab.mars.navigation import plots as mars_plots

matplotlib.use("Agg")


def test_fault_response_title_says_late_for_an_alarm_after_the_end():
    """A slow UV range drift: the wavelet flags only its end jump, which the scoring rule
    (schedules.score_faults) counts as late, never as a delay; the chi-square test sees it
    while it acts."""
    fig = mars_plots.plot_fault_response(5.0, "uv", "ramp", days=0.5)
    title = fig.axes[0].get_title()
    assert "wavelet late" in title
    assert re.search(r"chi2 delay \d+ s", title)


def test_the_sliders_figures_label_their_unit_and_keep_the_legend_off_the_axes():
    for fig in (mars_plots.plot_subsystem("uv", 1.0, 30, days=0.02),
                mars_plots.plot_sharing(0.5, "reset", days=0.02)):
        ax = fig.axes[0]
        assert ax.get_ylabel().endswith("(m)")
        assert ax.get_legend() is None and len(fig.legends) == 1


def test_plot_consistency_judges_each_case_after_the_settling_span():
    import numpy as np

    t = np.linspace(0.0, 3.0, 3 * 1440 + 1)
    nees = np.where(t < 1.0, 1e4, 6.0)                 # optimistic only while settling
    half = np.where(np.arange(t.size) % 2 == 0, 1.0, 6.0)   # half below the band
    fig = mars_plots.plot_consistency({"settles": (t, nees), "timid": (t, half)}, (4.0, 8.0))
    top, bars = fig.axes
    assert [x.get_text() for x in bars.get_yticklabels()] == ["settles: inside",
                                                              "timid: conservative"]
    widths = np.array([p.get_width() for p in bars.patches]).reshape(2, 3)  # below, in, above
    np.testing.assert_allclose(widths.sum(axis=1), 1.0)
    np.testing.assert_allclose(widths[:, 0], [0.0, 0.5], atol=1e-3)   # after day 1 only
    assert len(top.lines) == 3 and top.get_yscale() == "log"   # two cases and the mean 6


def test_plot_runs_draws_each_error_and_sigma_against_the_first_with_the_band_on_both():
    import numpy as np
    import pytest

    from xnavlab.mars.navigation import scenarios

    run = scenarios.run(days=0.02)
    fig = mars_plots.plot_runs({"a": run, "b": run}, band_days=(0.005, 0.01))
    top, bottom = fig.axes
    assert len(top.lines) == len(bottom.lines) == 2
    np.testing.assert_allclose(top.lines[0].get_ydata(), run.position_error())
    np.testing.assert_allclose(bottom.lines[1].get_ydata(), 0.0)     # b's sigma over a's
    assert len(top.patches) == len(bottom.patches) == 1            # the shaded span
    assert top.get_legend() is None and len(fig.legends) == 1
    assert bottom.get_xlabel() == "time (days)" and bottom.get_ylabel().endswith("a's (%)")
    with pytest.raises(ValueError, match="runs"):
        mars_plots.plot_runs({})
    with pytest.raises(ValueError, match="share their epochs"):
        mars_plots.plot_runs({"a": run, "short": scenarios.run(days=0.01)})


@pytest.mark.parametrize(("call", "match"), [
    (lambda: mars_plots.plot_subsystem("cns", 1e308, 30, days=0.02),
     r"noise_scale must be a real number in \(0, 100\]"),
    (lambda: mars_plots.plot_subsystem("cns", 2.0, 10**30, days=0.02),
     r"interval_s must be a real number in \(0, 86400\]"),
    (lambda: mars_plots.plot_details(np.arange(10.0), np.zeros(10), np.zeros((1, 10)), stride=10**30),
     r"stride must be an integer in \[1, 10\]"),
])
def test_huge_plot_settings_are_refused(call, match):
    with pytest.raises(ValueError, match=match):
        call()
