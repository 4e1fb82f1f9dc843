"""Detection Monte Carlo: seeding, executors, statistics, ROC."""

import math
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from xnavlab.core import montecarlo as mc
from xnavlab.mars.studies import trials


def test_seeds_are_reproducible_and_distinct():
    a = mc.seeds(7, 50)
    assert a == mc.seeds(7, 50) and len(set(a)) == 50
    assert a[:10] == mc.seeds(7, 10)          # prefix-stable: SeedSequence.spawn
    assert a != mc.seeds(8, 50)


def test_results_do_not_depend_on_the_executor():
    params = [dict(kind="step", size_sigma=4.0), dict(kind="noise", size_sigma=2.0)] * 2
    serial = mc.run_tasks(mc.signal_trial, params, seed=3, max_workers=1)
    with ThreadPoolExecutor(2) as ex:
        threads = mc.run_tasks(mc.signal_trial, params, seed=3, executor=ex)
    procs = mc.run_tasks(mc.signal_trial, params, seed=3, max_workers=2)
    assert serial == threads == procs


def test_no_fault_gives_no_detection_and_design_false_alarms():
    res = mc.run_tasks(mc.signal_trial, [dict(kind="step", size_sigma=0.0, pfa=1e-3)] * 20,
                       seed=1, max_workers=1)
    for d in mc.DETECTORS:
        s = mc.summarise(res, d)
        assert s["far"] < 3e-3                       # near the design 1e-3 per sample
    assert mc.summarise(res, "chi2")["far"] > 2e-4


def test_large_faults_are_detected_quickly():
    rows = mc.detection_table(("step", "noise"), (10.0,), trials=5, max_workers=1)
    for r in rows:
        for d in mc.DETECTORS:
            assert r[f"{d}_pd"] == 1.0 and r[f"{d}_late"] == 0.0, r
            assert r[f"{d}_delay_s"] <= 60.0, r


def test_an_alarm_after_the_fault_is_late_not_a_detection():
    """A spike acts on its own sample: the chi-square test flags that sample, the causal
    wavelet a few samples later, after the spike has gone into the filter (late)."""
    spike = mc.detection_table(("spike",), (10.0,), trials=5, max_workers=1)[0]
    assert (spike["chi2_pd"], spike["chi2_late"], spike["chi2_delay_s"]) == (1.0, 0.0, 0.0)
    assert (spike["wavelet_pd"], spike["wavelet_late"]) == (0.0, 1.0)
    assert math.isinf(spike["wavelet_delay_s"])
    # a slow ramp: the wavelet sees only the jump back at its end (chapter 7)
    ramp = mc.signal_trial("ramp", 3.0, seed=2, duration=300)
    assert ramp["wavelet"]["late"] and not ramp["wavelet"]["detected"]
    assert ramp["chi2"]["detected"] and not ramp["chi2"]["late"]


def test_mismodelled_noise_hurts_chi2_not_the_trained_wavelet():
    rows = mc.detection_table(("step",), (0.0,), trials=20, noise_scale=1.3, max_workers=1)
    assert rows[0]["chi2_far"] > 30 * 1e-5
    assert rows[0]["wavelet_far"] < 10 * 1e-5


def test_roc_is_monotone_and_bounded():
    res = [mc.signal_trial("step", 3.0, seed=s) for s in range(10)]
    pf, pd, thr = mc.roc_curve(res, "wavelet")
    assert np.all(np.diff(pf) <= 0) and np.all(np.diff(pd) <= 0)
    assert pf.min() >= 0 and pd.max() <= 1 and thr.size == pf.size
    fig = mc.plot_roc({"wavelet": (pf, pd)})
    assert fig.axes[0].get_xlabel().startswith("false alarm")


def test_mars_trial_detects_the_uv_step():
    r = trials.mars_trial(6.0, "wavelet", seed=5, days=0.5)
    assert r["delay"] < 600.0 and r["isolations"] >= 1
    none = trials.mars_trial(6.0, "none", seed=5, days=0.5)
    assert math.isinf(none["delay"])
    assert none["max_position_error_m"] > r["max_position_error_m"]


@pytest.mark.parametrize("call,name", [
    (lambda: mc.signal_trial("drift", 1.0), "kind"),
    (lambda: mc.signal_trial("step", -1.0), "size_sigma"),
    (lambda: mc.signal_trial("step", 1.0, noise_scale=0.0), "noise_scale"),
    (lambda: mc.run_tasks(mc.signal_trial, [1, 2]), "params"),
    (lambda: mc.run_tasks(mc.signal_trial, [], max_workers=0), "max_workers"),
    (lambda: mc.seeds(-1, 2), "seed"),
])
def test_bad_input_names_the_parameter(call, name):
    with pytest.raises(ValueError, match=name):
        call()


def test_markdown_table_formats_and_checks_columns():
    from xnavlab.core.plotting import markdown_table

    text = markdown_table([{"a": 1, "b": 2.0 / 3.0}], ["a", "b"], digits=2)
    assert text.splitlines() == ["| a | b |", "|---|---|", "| 1 | 0.67 |"]
    with pytest.raises(ValueError, match="missing"):
        markdown_table([{"a": 1}], ["a", "b"])
    with pytest.raises(ValueError, match="digits"):
        markdown_table([], ["a"], digits=0)


@pytest.mark.parametrize(("kw", "words"), [
    (dict(sizes=(2.0, 2.0)), r"^sizes lists 2.0 twice"), (dict(sizes=(1j,)), r"^sizes\[0\] must"),
    (dict(sizes=4.0), "^sizes must be a list"), (dict(kinds="step"), "^kinds must be a list"),
])
def test_detection_table_refuses_bad_lists_before_any_trial(kw, words):
    with pytest.raises(ValueError, match=words):
        mc.detection_table(**kw, trials=1)


def test_signal_trial_refuses_a_seed_above_the_records_range():
    """Review 35e: 2^63 was taken (check_int without its upper end)."""
    with pytest.raises(ValueError, match=r"^seed must be an integer in \[0, 9223372036854775807\]"):
        mc.signal_trial("step", 3.0, seed=2**63)


def test_counts_beyond_their_range_are_refused_not_an_overflow_or_an_endless_run():
    """Review 35e: seeds(0, 10**30) was an OverflowError, detection_table(trials=10**30) ran
    without end, signal_trial(n=10**12) would allocate terabytes."""
    with pytest.raises(ValueError, match=r"^n must be an integer in \[0, 10000000\], got 10{30}$"):
        mc.seeds(0, 10**30)
    with pytest.raises(ValueError, match=r"^trials must be an integer in \[1, 1000000\]"):
        mc.detection_table(("step",), (10.0,), trials=10**30, max_workers=1)
    with pytest.raises(ValueError, match=r"^n must be an integer in \[2500, 10000000\], got 10{12}$"):
        mc.signal_trial("step", 3.0, n=10**12)
    with pytest.raises(ValueError, match=r"^duration must be an integer in \[1, 1000000\]"):
        mc.signal_trial("step", 3.0, duration=10**30)


@pytest.mark.parametrize("kind", mc.KINDS)
def test_plot_pd_draws_every_kind_of_the_chapter_and_a_delay_of_zero(kind):
    """Chapter 9's slider (10 trials): the chi-square flags a large spike at its own sample, a
    delay of 0 s, which the log axis could not show (a UserWarning, the point dropped); the
    symlog axis draws it at 0, no axis goes below 0 s, and a move to each kind draws too."""
    fig = mc.plot_pd(kind=kind, trials=10)
    ax = fig.axes[1]
    assert ax.get_yscale() == "symlog" and ax.get_ylim()[0] >= 0.0
    if kind == "spike":
        assert 0.0 in ax.lines[1].get_ydata()  # chi2's median delay at 8 sigma
    for other in mc.KINDS:
        assert fig.xnav_update(kind=other, trials=10) is None


def test_issue35_runs_for_halfwidth_from_a_millionth():
    # Review 35f finding 42: 1e-300 squared to 0 (ZeroDivisionError).
    with pytest.raises(ValueError, match=r"^halfwidth must be a real number in \[1e-06, 0.5\]"):
        mc.runs_for_halfwidth(0.5, 1e-300)


@pytest.mark.parametrize("thresholds, match", [
    ([float("nan")], r"^thresholds must"), (-5.0, r"^thresholds must be a sequence"),
    ([], r"^thresholds must be a sequence")])
def test_issue35_roc_curve_refuses_bad_thresholds_and_no_results(thresholds, match):
    # Review 35f finding 43: a NaN threshold was returned, a scalar raised IndexError, and no
    # results gave NaN with a RuntimeWarning.
    r = [mc.signal_trial("step", 4.0, seed=1)]
    with pytest.raises(ValueError, match=match):
        mc.roc_curve(r, "chi2", thresholds=thresholds)
    with pytest.raises(ValueError, match=r"^results must"):
        mc.roc_curve([], "chi2")


@pytest.mark.parametrize(("call", "match"), [
    (lambda: mc.run_tasks(mc.signal_trial, True), r"^params must be a list of keyword dicts"),
    (lambda: mc.run_tasks(mc.signal_trial, np.array(1.0)), r"^params must be a list"),
    (lambda: mc.run_tasks(mc.signal_trial, [1.0]), r"^params\[0\] must be a dict of keywords"),
    (lambda: mc.summarise(-0.0, "chi2"), r"^results must be a list of trials"),
    (lambda: mc.summarise([1.0], "chi2"), r"^results\[0\] must be a trial of signal_trial"),
    (lambda: mc.detection_table([1.0], (10.0,), trials=1), r"^kinds\[0\] must be one of 'step'"),
    (lambda: mc.plot_pd(sizes=True), r"^sizes must be a list of sizes"),
    (lambda: mc.plot_pd(sizes=[2.0, True]), r"^sizes\[1\] must be a real number"),
])
def test_an_edge_input_is_refused_naming_it(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_roc_curve_names_results_that_are_no_trials():
    """Review 35j (1) 9: roc_curve([{'a': 1}], 'wavelet') raised KeyError 'wavelet'
    (summarise checked this; roc_curve did not)."""
    for bad in ([{"a": 1}], [{"wavelet": 1}], [{"wavelet": {"peak_fault": 1.0}}]):
        with pytest.raises(ValueError, match=r"^results\[0\] must be a trial of signal_trial"):
            mc.roc_curve(bad, "wavelet")
    with pytest.raises(ValueError, match=r"^results\[0\] must be a trial of signal_trial"):
        mc.summarise([{"wavelet": {}}], "wavelet")
    with pytest.raises(ValueError, match=r"^results must hold at least one trial"):
        mc.roc_curve([], "wavelet")
    pf, pd, thr = mc.roc_curve([{"wavelet": {"peak_fault": 3.0, "peak_clean": 0.5}}], "wavelet",
                               [1.0])
    assert (pf.tolist(), pd.tolist()) == ([0.0], [1.0])


def test_detection_table_and_run_tasks_name_a_keyword_passed_on():
    """Review 35j (1) 10-11: a typo in detection_table's **trial_kw or in a task's params
    was a TypeError from inside signal_trial."""
    with pytest.raises(ValueError, match=r"^duraton is not a keyword of detection_table or of "
                                         r"signal_trial.*\(did you mean duration\?\)"):
        mc.detection_table(kinds=("step",), sizes=(2.0,), trials=1, max_workers=1, duraton=5)
    with pytest.raises(ValueError, match=r"^kind is set by detection_table \(from kinds\)"):
        mc.detection_table(kinds=("step",), sizes=(2.0,), trials=1, max_workers=1, kind="ramp")
    with pytest.raises(ValueError, match=r"^params\[0\]\['sise'\] is not a keyword of signal_trial "
                                         r"\(run_tasks passes params\[0\] on to it\)"):
        mc.run_tasks(mc.signal_trial, [{"kind": "step", "size_sigma": 3.0, "sise": 1}], max_workers=1)
    with pytest.raises(ValueError, match=r"^params\[1\]\['seed'\] is set by run_tasks"):
        mc.run_tasks(mc.signal_trial, [{"kind": "step", "size_sigma": 3.0}, {"seed": 1}], max_workers=1)
    with pytest.raises(ValueError, match=r"^params\[0\] does not fit signal_trial\(seed=\.\.\., "
                                         r"\*\*params\[0\]\): missing a required argument: "
                                         r"'size_sigma'"):
        mc.run_tasks(mc.signal_trial, [{"kind": "step"}], max_workers=1)
    # a function taking **kwargs takes any keyword
    assert mc.run_tasks(_echo, [{"anything": 1}], max_workers=1)[0]["anything"] == 1


def _echo(seed, **kw):
    return dict(kw, seed=seed)


def test_plot_roc_names_curves_that_are_no_dict_of_pairs():
    """Review 35j (1), the class (an object parameter not checked): a list of curves was an
    AttributeError, a label without a (pfa, pd) pair a TypeError."""
    for bad, msg in (([1, 2], r"^curves must be a dict of label -> \(pfa, pd\)"),
                     ({}, r"^curves must be a dict"),
                     ({"a": 1}, r"^curves\['a'\] must be a pair \(pfa, pd\), got 1"),
                     ({"a": ([0.0, 0.5], [1.0])}, r"^curves\['a'\] must be two equally long 1-D"),
                     ({"a": ([0.0, 2.0], [1.0, 1.0])}, r"probabilities in \[0, 1\]")):
        with pytest.raises(ValueError, match=msg):
            mc.plot_roc(bad)


def test_detection_table_and_plot_pd_take_noise_scale_as_checked():
    """Review 35m pattern M: noise_scale went on raw: a Fraction was stored in the rows and
    broke plot_pd's title ('unsupported format string passed to Fraction'); 0 was refused by
    each trial, not before the trials ran."""
    from fractions import Fraction

    rows = mc.detection_table(("step",), (8.0,), trials=1, noise_scale=Fraction(1), max_workers=1)
    assert type(rows[0]["noise_scale"]) is float
    fig = mc.plot_pd(trials=1, sizes=(8.0,), noise_scale=Fraction(1))
    assert "true/modelled noise 1," in fig.texts[0].get_text()
    with pytest.raises(ValueError, match=r"^noise_scale must be a real number in \(0, 100\]"):
        mc.detection_table(("step",), (8.0,), trials=1, noise_scale=0.0, max_workers=1)


def test_a_cell_of_detection_table_does_not_depend_on_the_other_cells():
    """Review 35 Q5: each trial was seeded by its position in the flattened (kind, size,
    trial) list, so adding a size or a kind redrew every later cell (step 3 sigma: wavelet
    Pd 0.50 with sizes (2, 3), 0.733 with (1, 2, 3)). Now trial j of (kind, size) is seeded
    from the cell: the same row whatever else the call holds, in whichever order, on any
    executor, and the first trials of a longer run are the shorter run's."""
    a = mc.detection_table(("step",), (2.0, 3.0), trials=4, max_workers=1)
    b = mc.detection_table(("step",), (1.0, 2.0, 3.0), trials=4, max_workers=1)
    with ThreadPoolExecutor(2) as ex:
        c = mc.detection_table(("noise", "step"), (3.0, 2.0), trials=4, executor=ex)
    assert b[1:] == a
    assert [r for r in c if r["kind"] == "step"] == a[::-1]
    assert mc.detection_table(("step",), (3,), trials=4, max_workers=2) == a[1:]  # 3 is 3.0
    seeds = mc.cell_seeds(0, "step", 3.0, 4)
    assert mc.cell_seeds(0, "step", 3.0, 2) == seeds[:2] and len(set(seeds)) == 4
    assert mc.cell_seeds(0, "step", -0.0, 1) == mc.cell_seeds(0, "step", 0.0, 1)
    assert len({mc.cell_seeds(0, k, s, 1)[0] for k in mc.KINDS for s in (1.0, 2.0)}) == 8
    assert mc.cell_seeds(1, "step", 3.0, 4) != seeds
    trial = mc.signal_trial("step", 3.0, seed=seeds[0])  # a row's trial, rerun by hand
    assert mc.summarise([trial], "chi2")["pd"] in (0.0, 1.0)
    with pytest.raises(ValueError, match=r"^kind must be one of 'step'"):
        mc.cell_seeds(0, "drift", 3.0, 1)
    with pytest.raises(ValueError, match=r"^trials must be an integer in \[0, 10000000\]"):
        mc.cell_seeds(0, "step", 3.0, -1)


def test_plot_pd_draws_sizes_in_increasing_order():
    """Review 35 Q6: sizes (8, 2, 4) were drawn in that order, a zig-zag."""
    fig = mc.plot_pd("step", 1.0, 1, 0, (8.0, 2.0, 4.0))
    assert fig.axes[0].lines[0].get_xdata().tolist() == [2.0, 4.0, 8.0]
    ordered = mc.plot_pd("step", 1.0, 1, 0, (2.0, 4.0, 8.0))
    for a, b in zip(fig.axes, ordered.axes, strict=True):
        for la, lb in zip(a.lines, b.lines, strict=True):
            assert list(la.get_ydata()) == list(lb.get_ydata())
    assert fig.xnav_update(kind="step", trials=1, sizes=(4.0, 8.0, 2.0)) is None  # same sizes
    assert fig.xnav_update(kind="step", trials=1, sizes=(4.0, 8.0)) is False


def test_roc_curve_and_plot_roc_order_their_points():
    """Review 35 Q6: roc_curve kept unsorted thresholds, and plot_roc drew its staircase
    (steps-post) over the points in the order given, a wrong staircase."""
    trials_ = [mc.signal_trial("step", 4.0, seed=s) for s in range(3)]
    pfa, pd, thr = mc.roc_curve(trials_, "wavelet", [3.0, 1.0, 2.0])
    ref = mc.roc_curve(trials_, "wavelet", [1.0, 2.0, 3.0])
    assert thr.tolist() == [1.0, 2.0, 3.0]
    assert pfa.tolist() == ref[0].tolist() and pd.tolist() == ref[1].tolist()
    fig = mc.plot_roc({"a": ([0.5, 0.1, 0.3], [0.9, 0.2, 0.6]), "b": ([0.2, 0.2, 0.0], [0.5, 0.1, 0.0])})
    lines = fig.axes[0].lines
    assert lines[0].get_xdata().tolist() == [0.1, 0.3, 0.5]
    assert lines[0].get_ydata().tolist() == [0.2, 0.6, 0.9]
    assert lines[1].get_xdata().tolist() == [0.0, 0.2, 0.2]
    assert lines[1].get_ydata().tolist() == [0.0, 0.1, 0.5]
