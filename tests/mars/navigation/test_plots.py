"""The chapter figures of xnavlab.mars.navigation.plots (more in test_scenarios and test_fault_tolerance)."""

import io
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
    # review 35p P2, P13: the same number of records at other epochs (a longer run recorded
    # half as often; another t0) compared sigmas of other instants; another system's result
    for other in (scenarios.run(days=0.04, record_dt=120.0),
                  scenarios.run(days=0.02, t0=run.scenario.t0 + 86400.0)):
        with pytest.raises(ValueError, match=r"^runs must share their epochs: 'b' has 30 records "
                                             r"from 50\d{7} to"):
            mars_plots.plot_runs({"a": run, "b": other})
    from xnavlab.attitude import simulate
    with pytest.raises(ValueError, match=r"^runs\['b'\] must be a MarsRun \(t_days, "
                                         r"position_error\(\), sigma_position\(\)\), got AttitudeRun"):
        mars_plots.plot_runs({"a": run, "b": simulate(duration=50.0)})


@pytest.mark.parametrize(("call", "match"), [
    (lambda: mars_plots.plot_subsystem("cns", 1e308, 30, days=0.02),
     r"noise_scale must be a real number in \[0.01, 100\]"),
    (lambda: mars_plots.plot_subsystem("cns", 2.0, 10**30, days=0.02),
     r"interval_s must be a real number in \[0.1, 86400\]"),
    (lambda: mars_plots.plot_details(np.arange(10.0), np.zeros(10), np.zeros((1, 10)), stride=10**30),
     r"stride must be an integer in \[1, 10\]"),
])
def test_huge_plot_settings_are_refused(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_an_edge_value_of_a_figure_argument_is_refused_by_name():
    """Issue 35 (review 35h): a bool, a number or a 0-d array where a dict or a list belongs
    was a TypeError or an AttributeError inside matplotlib, and a subnormal noise scale or
    share was refused under the scenario's name (sigma_horizon_deg, beta[0])."""
    from xnavlab.core.faults import Fault

    t = np.linspace(0.0, 2.0, 50)
    curves = {"run": (t, 30.0 + t)}
    cases = [
        (lambda: mars_plots.plot_subsystem("uv", 5e-324, 30, days=0.02),
         r"^noise_scale must be a real number in \[0.01, 100\], got 5e-324$"),
        (lambda: mars_plots.plot_subsystem("uv", 1.0, 5e-324, days=0.02),
         r"^interval_s must be a real number in \[0.1, 86400\], got 5e-324$"),
        (lambda: mars_plots.plot_sharing(5e-324, days=0.02),
         r"^beta_xnav must be a real number in \[0.001, 0.998\], got 5e-324$"),
        (lambda: mars_plots.plot_runs(True), r"^runs must be a dict of label -> MarsRun"),
        (lambda: mars_plots.plot_runs({}), r"^runs must hold at least one labelled run"),
        (lambda: mars_plots.plot_error_curves([1.0]), r"^curves must be a dict of label"),
        (lambda: mars_plots.plot_error_curves(curves, True), r"^faults must be a list of Faults, got True"),
        (lambda: mars_plots.plot_error_curves(curves, [1.0]), r"^faults\[0\] must be a Fault, got 1.0"),
        (lambda: mars_plots.plot_error_curves(curves, isolations=[1.0]),
         r"^isolations\[0\] must be a sensor isolation \(a dict with sensor, out, back\)"),
        (lambda: mars_plots.plot_details(-0.0, t, np.vstack([t, t])),
         r"^t_days must be a 1-D array of at least one sample time, got shape \(\)$"),
        (lambda: mars_plots.plot_details(t, t, np.vstack([t, t]), True),
         r"^onsets_days must be a list of onsets, days, got True$"),
        (lambda: mars_plots.plot_details(t, t, np.vstack([t, t]), [1.0, True, 0.0]),
         r"^onsets_days must be an array of finite numbers"),
        (lambda: mars_plots.detector_table_markdown(np.array(1.0)), r"^table must be a dict with 'rows'"),
        (lambda: mars_plots.plot_consistency(True, (4.0, 8.0)), r"^cases must be a dict of label"),
        (lambda: mars_plots.plot_consistency({"a": (t, t)}, -0.0), r"^band must be a list of two numbers"),
        (lambda: mars_plots.plot_consistency({"a": (t, t)}, []), r"^band must be a pair \(lo, hi\), got"),
        (lambda: mars_plots.plot_consistency({"a": (t, t)}, [1.0, True]),
         r"^band\[1\] must be a real number in \[0, inf\), got True"),
    ]
    for call, message in cases:
        with pytest.raises(ValueError, match=message):
            call()
    fig = mars_plots.plot_runs({"a": _FakeRun()}, band_days=(0.1, 0.2))
    assert len(fig.axes) == 2
    with pytest.raises(ValueError, match=r"^band_days must be a 1-D array \(shape \(2,\)\), got"):
        mars_plots.plot_runs({"a": _FakeRun()}, band_days=[1.0])
    assert mars_plots.plot_error_curves(curves, [Fault("uv", "step", 1.0, 86400.0, 3000.0)]).axes


class _FakeRun:
    """A run's plotted part: times, days, and positive errors and sigmas, m."""

    t_days = np.linspace(0.0, 1.0, 5)

    def position_error(self):
        return np.full(5, 10.0)

    def sigma_position(self):
        return np.full(5, 20.0)


def test_plot_subsystem_runs_an_interval_longer_than_its_30_s_records():
    """Review 35j: MarsScenario now refuses a record_dt below the run's epochs; the slider
    records every epoch when they are sparser than 30 s (the same records as before)."""
    for sub, interval in (("xnav", 500.0), ("uv", 45.0)):
        fig = mars_plots.plot_subsystem(sub, 1.0, interval, days=0.05)
        assert len(fig.axes[0].lines[0].get_xdata()) > 2


def _cases():
    t = np.linspace(0.0, 2.0, 97)
    return {"a": (t, np.full(t.size, 6.0))}


@pytest.mark.parametrize("kw, name", [
    ({"dof": None}, "dof"), ({"dof": 2.5}, "dof"), ({"dof": True}, "dof"), ({"dof": -1}, "dof"),
    ({"dof": "3"}, "dof"),
    ({"settle_days": None}, "settle_days"), ({"settle_days": "1.0"}, "settle_days"),
    ({"settle_days": np.nan}, "settle_days"), ({"settle_days": 1e300}, "settle_days"),
    ({"bin_days": 5e-324}, "bin_days"),
    ({"ylim": 1.0}, "ylim"), ({"ylim": True}, "ylim"), ({"ylim": np.nan}, "ylim"),
    ({"ylim": "x"}, "ylim"), ({"ylim": []}, "ylim"), ({"ylim": {}}, "ylim"),
    ({"ylim": (10.0, 1.0)}, "ylim"), ({"ylim": (0.0, 1.0)}, r"ylim\[0\]"),
])
def test_plot_consistency_checks_its_defaulted_parameters(kw, name):
    """Review 35k (1) 4-5, (2) 8, (3) 19, (5) 7: dof, settle_days, bin_days and ylim (left at
    their defaults by the examples) reached matplotlib or judge_series unchecked."""
    with pytest.raises(ValueError, match=f"^{name} must"):
        mars_plots.plot_consistency(_cases(), (4.0, 8.0), **kw)


@pytest.mark.parametrize("cases, name", [
    ({"a": 1.0}, r"cases\['a'\]"), ({"a": ([0.0, 1.0], [1.0])}, r"cases\['a'\]\[1\]"),
    ({"a": ([-1.0, 1.0], [1.0, 1.0])}, r"cases\['a'\]\[0\]"),
])
def test_plot_consistency_checks_each_case(cases, name):
    """Review 35k pattern A: the cases' pairs were unpacked and divided unchecked."""
    with pytest.raises(ValueError, match=f"^{name}"):
        mars_plots.plot_consistency(cases, (4.0, 8.0))


def test_plot_details_refuses_no_detail_rows():
    """Review 35k (1) 6: details of shape (0, N) gave TypeError 'Axes' not subscriptable."""
    t = np.linspace(0.0, 1.0, 400)
    with pytest.raises(ValueError, match="^details must hold at least one detail signal"):
        mars_plots.plot_details(t, np.sin(t), np.zeros((0, t.size)), [t[100]], stride=4)


def test_consistency_plot_of_a_diverged_case_and_its_ylim_range():
    """Review 35k: NEES or a band end near 1e300 overflowed matplotlib's log autoscale (a
    RuntimeWarning); ylim = (1, 1e308) overflowed its ticks. The axis now ends at YLIM_RANGE's
    edge, and a ylim outside the range is refused naming ylim[i]."""
    t = np.linspace(0.0, 2.0, 2881)
    cases = {"diverged": (t, np.full(t.size, 1e300)), "good": (t, np.full(t.size, 6.0))}
    fig = mars_plots.plot_consistency(cases, (4.0, 8.0))
    fig.savefig(io.BytesIO(), format="png")
    assert fig.axes[0].get_ylim() == (4.0, mars_plots.YLIM_RANGE[1])
    with pytest.raises(ValueError, match=r"ylim\[1\] must be a real number in \[1e-200, 1e\+200\]"):
        mars_plots.plot_consistency(cases, (4.0, 8.0), ylim=(1.0, 1e308))


@pytest.mark.parametrize("band", [(8.0, 4.0), (0.0, 0.0), (5.0, 5.0)])
def test_plot_consistency_names_band_when_it_is_no_range(band):
    """Review 35m (3) 1, (5) 4: band=(8, 4) was refused as judge_series' "hi must be at least
    lo", and band=(0, 0) (a band no record falls in) was drawn."""
    t = np.linspace(0.0, 2.0, 97)
    with pytest.raises(ValueError, match=r"^band must be \(lo, hi\) with lo < hi, got "):
        mars_plots.plot_consistency({"a": (t, np.full(t.size, 6.0))}, band)


def test_plot_consistency_names_the_case_of_a_negative_nees():
    """Review 35m (3) 1: a negative NEES was named judge_series' values[0] (and counted in the
    judged span only), not the case's entry."""
    t = np.linspace(0.0, 2.0, 97)
    nees = np.full(t.size, 6.0)
    nees[3] = -1.0  # before settle_days: judge_series never saw it
    with pytest.raises(ValueError,
                       match=r"^cases\['b'\]\[1\]\[3\] must be a NEES value in \[0, inf\), got -1"):
        mars_plots.plot_consistency({"a": (t, np.full(t.size, 6.0)), "b": (t, nees)}, (4.0, 8.0))


def test_plot_sharing_titles_a_fraction_of_days_as_its_float():
    """Review 35m (1) 2, pattern M: days=Fraction(1, 50) passed the run's check_real, then the
    title formatted the raw Fraction ('unsupported format string passed to Fraction')."""
    from fractions import Fraction

    fig = mars_plots.plot_sharing(0.8, "no-reset", days=Fraction(1, 50))
    ref = mars_plots.plot_sharing(0.8, "no-reset", days=0.02)
    assert fig.axes[0].get_title() == ref.axes[0].get_title()


@pytest.mark.parametrize("times", [np.arange(400)[::-1] * 3.0 / 86400.0, np.zeros(400),
                                   np.arange(400) * 3.0 / 86400.0 - 1.0])
def test_plot_details_refuses_times_that_do_not_increase(times):
    """Review 35 Q6: reversed times, every sample at one instant and negative times were
    drawn; plot_error_curves and plot_consistency refused them."""
    x = np.random.default_rng(0).normal(0.0, 5000.0, 400)
    with pytest.raises(ValueError, match=r"^t_days must hold increasing sample times >= 0 "
                                         r"\(days since the start\)$"):
        mars_plots.plot_details(times, x, np.vstack([x, x]), stride=4)
    assert len(mars_plots.plot_details(np.arange(400) * 3.0 / 86400.0, x, np.vstack([x, x]),
                                       stride=4).axes) == 3
