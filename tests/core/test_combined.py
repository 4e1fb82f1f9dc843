"""The combined detector (xnavlab.core.detection.combined: wavelet, per-sample chi-square and
CUSUMs on the whitened innovations): the CUSUM design, the false-alarm budget, the adaptive noise
scale, streaming against batch, and the drift GLR."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

from xnavlab.core.detection import (
    PARTS,
    CombinedDesign,
    InnovationMonitor,
    combined_detect,
    cusum_arl,
    cusum_threshold,
    drift_glr,
    plot_combined_parts,
    variance_reference,
)


def test_cusum_arl_matches_the_literature_and_simulation():
    # Page's CUSUM, k = 0.5, h = 4: ARL0 = 336 (Siegmund's approximation; tabulated 336)
    assert abs(cusum_arl(4.0, 0.5) - 336.0) < 3.0
    h = cusum_threshold(300.0, 0.5)
    rng = np.random.default_rng(0)
    runs = []
    for _ in range(400):
        s, n = 0.0, 0
        for v in rng.normal(size=20000):
            n += 1
            s = max(0.0, s + v - 0.5)
            if s > h:
                break
        runs.append(n)
    se = np.std(runs) / math.sqrt(len(runs))
    assert abs(np.mean(runs) - 300.0) < 4 * se


def test_variance_cusum_threshold_hits_its_arl():
    k = variance_reference(2.0)
    h = cusum_threshold(500.0, k, dof=1)
    assert abs(cusum_arl(h, k, dof=1) / 500.0 - 1.0) < 1e-3


def test_design_budget_sums_to_the_design_rate():
    d = CombinedDesign(28800.0, 3, rate_per_day=2.0)
    rates = d.part_rates()
    assert set(rates) == set(PARTS)
    assert abs(sum(rates.values()) - 2.0) < 1e-9
    assert d.chi2_threshold == pytest.approx(stats.chi2.isf(d.alpha, 3))


@pytest.mark.parametrize("kw,name", [(dict(rate_per_day=0.0), "rate_per_day"),
                                     (dict(m=0), "m"),
                                     (dict(shares={"chi2": 1.0}), "shares"),
                                     (dict(k_mean=-1.0), "k_mean")])
def test_design_bad_input_names_the_parameter(kw, name):
    args = dict(samples_per_day=28800.0, m=2) | kw
    with pytest.raises(ValueError, match=name):
        CombinedDesign(**args)


def _count_alarms(y, design, adaptive=True):
    mon = InnovationMonitor(design, adaptive=adaptive)
    t = np.arange(y.shape[0], dtype=float)
    mon.process(t, y, stop=False)
    return len(mon.all_events())


def test_false_alarm_rate_of_the_innovation_parts_is_the_design():
    # 10 days of 3-s samples at 30 false alarms a day: 0.9 of the budget is the innovation
    # parts' (the wavelet holds 0.1), so 270 alarms are expected
    rng = np.random.default_rng(1)
    d = CombinedDesign(28800.0, 2, rate_per_day=30.0)
    n = _count_alarms(rng.normal(size=(288000, 2)), d)
    lo, hi = stats.poisson.ppf([0.001, 0.999], 270.0)
    assert lo <= n <= hi, n


def test_adaptive_scale_keeps_the_rate_when_the_noise_is_mismodelled():
    # true noise 1.3 times the model, 4 days at 30 alarms a day (108 expected from the
    # innovation parts): the model's scale alarms 20-70 times too often, the adaptive one
    # near the design after its first few hundred samples
    rng = np.random.default_rng(2)
    d = CombinedDesign(28800.0, 2, rate_per_day=30.0)
    y = 1.3 * rng.normal(size=(115200, 2))
    fixed = _count_alarms(y, d, adaptive=False)
    adaptive = _count_alarms(y, d, adaptive=True)
    assert fixed > 20 * 108
    assert adaptive < stats.poisson.ppf(0.999, 1.3 * 108), adaptive


@settings(max_examples=10, deadline=None)
@given(cuts=st.lists(st.integers(1, 5999), min_size=1, max_size=6, unique=True))
def test_streaming_in_chunks_equals_one_batch(cuts):
    rng = np.random.default_rng(3)
    y = rng.normal(size=(6000, 2))
    y[3000:, 1] += 0.004 * np.arange(3000)
    t = 3.0 * np.arange(6000)
    d = CombinedDesign(28800.0, 2, rate_per_day=5.0)
    kw = dict(scale_every=500, scale_samples=2000)
    one = InnovationMonitor(d, **kw)
    one.process(t, y, stop=False)
    many = InnovationMonitor(d, **kw)
    edges = [0, *sorted(cuts), 6000]
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        many.process(t[a:b], y[a:b], stop=False)
    assert [(e.onset, e.test) for e in one.all_events()] == [(e.onset, e.test) for e in many.all_events()]
    np.testing.assert_allclose(one.scale, many.scale, rtol=0, atol=0)


def test_snapshot_restore_replays_identically():
    rng = np.random.default_rng(4)
    y = rng.normal(size=(4000, 3))
    y[2500:, 0] += 3.0
    t = np.arange(4000.0)
    mon = InnovationMonitor(CombinedDesign(28800.0, 3), scale_every=300, scale_samples=1000)
    mon.process(t[:2000], y[:2000], stop=False)
    snap = mon.snapshot(max_rows=2000)
    a = mon.process(t[2000:], y[2000:])
    mon.restore(snap)
    b = mon.process(t[2000:], y[2000:])
    assert a == b and a >= 500
    small = mon.snapshot(max_rows=10)
    mon.process(t[:50] + 5000.0, y[:50] * 0.0, stop=False)   # times go on from the last fed
    with pytest.raises(ValueError, match="max_rows"):
        mon.restore(small)


def test_one_sample_update_equals_process():
    rng = np.random.default_rng(5)
    y = rng.normal(size=(1500, 1))
    y[1000:, 0] += 6.0
    d = CombinedDesign(28800.0, 1)
    a = InnovationMonitor(d)
    flags = [a.update(float(i), y[i]) for i in range(1500)]
    b = InnovationMonitor(d)
    assert b.process(np.arange(1500.0), y) == flags.index(True)


def test_drift_is_seen_by_the_cusum_long_before_the_wavelet():
    rng = np.random.default_rng(6)
    t = 3.0 * np.arange(12000)
    y = rng.normal(size=12000)
    y[6000:] += 5.0 * np.arange(6000) / 2000.0 * (np.arange(6000) < 2000) \
        + 5.0 * (np.arange(6000) >= 2000)
    res = combined_detect(t, y, train=4000)
    first = res.data["first"]
    onset = 18000.0
    assert first["cusum"] - onset < 1500.0
    assert first["cusum"] < first["wavelet"]
    assert res.events[0].onset == min(first.values())


def test_plot_combined_parts_is_a_figure_and_checks_input():
    fig = plot_combined_parts(drift_sigma_per_hour=3.0)
    assert "cusum" in fig.axes[0].get_title()
    with pytest.raises(ValueError, match="noise_ratio"):
        plot_combined_parts(noise_ratio=0.5)


def test_drift_glr_is_the_matched_statistic_and_checks_its_input():
    from xnavlab.core.detection import drift_glr

    rng = np.random.default_rng(2)
    y = rng.normal(size=300)
    T = drift_glr(y, window=10)
    np.testing.assert_allclose(drift_glr(-y, window=10), T)          # sign-free
    n, L = 200, 7                                                    # one window by hand
    c = np.arange(1.0, L + 1.0)
    assert T[n] >= (c @ y[n - L + 1:n + 1]) ** 2 / (c @ c) - 1e-12
    assert np.all(drift_glr(y, window=12) >= T - 1e-12)               # a longer window only adds
    for bad, name in ((dict(y=np.ones((3, 2))), "y"), (dict(window=0), "window")):
        with pytest.raises(ValueError, match=name):
            drift_glr(**({"y": y, "window": 5} | bad))


def test_the_monitor_refuses_complex_innovations_by_name():
    mon = InnovationMonitor(CombinedDesign(samples_per_day=28800.0, m=2))
    with pytest.raises(ValueError, match="^y must hold real numbers"):
        mon.process(np.arange(3.0), np.ones((3, 2)) * (1 + 1j))
    with pytest.raises(ValueError, match=r"^y must have shape \(n, 2\) with n = len\(t\) = 3"):
        mon.process(np.arange(3.0), np.ones((3, 3)))
    with pytest.raises(ValueError, match="^healthy must contain only finite"):
        mon.scale_from(np.full((4, 2), np.nan))


def _series(n=500):
    return 86.4 * np.arange(n), np.random.default_rng(0).normal(size=(n, 3))


def test_combined_detect_names_its_own_bad_inputs():
    # review 35d D30/D31: times out of order blamed samples_per_day (or divided by zero);
    # a rate beside a design went unused
    t, y = _series()
    with pytest.raises(ValueError, match=r"t must be strictly increasing .* t\[1\] = 43027.2 after"):
        combined_detect(t[::-1], y)
    with pytest.raises(ValueError, match=r"t must be strictly increasing .* t\[1\] = 0 after"):
        combined_detect(np.zeros(500), y)
    with pytest.raises(ValueError, match="rate_per_day = 5.0 is unused with a design"):
        combined_detect(t, y, design=CombinedDesign(1000.0, 3), rate_per_day=5.0)


def test_design_shares_and_monitor_flags_are_checked():  # review 35d D32/D33
    with pytest.raises(ValueError, match="shares must be a dict of part -> share"):
        CombinedDesign(100, 3, shares=(-1, 1, 1))
    with pytest.raises(ValueError, match="adaptive must be True or False, got 'no'"):
        InnovationMonitor(CombinedDesign(100, 3), adaptive="no")



@pytest.mark.parametrize("m", [1, 3])
def test_the_recorded_ratios_are_the_array_forms_bit_for_bit(m, monkeypatch):
    """process(record=...) runs the compiled segment (_scan_rows); with the array form
    (_segment) in its place the run gives the same bits: ratios, first alarm, CUSUMs, scale."""
    from xnavlab.core.detection import combined

    rng = np.random.default_rng(7)
    t = 3.0 * np.arange(6000)
    y = rng.normal(0.0, 1.0, (6000, m))
    y[3000:] += (8.0 * (t[3000:] - t[3000]) / 3600.0)[:, None]  # a drift: alarms at most samples
    design = combined.CombinedDesign(86400.0 / 3.0, m, 1.0)

    def run(stop):
        mon, rec = combined.InnovationMonitor(design), {}
        first = mon.process(t, y, stop=stop, record=rec)
        return first, rec["ratio"].tobytes(), mon.S.tobytes(), mon.scale.tobytes()

    compiled = [run(stop) for stop in (False, True)]

    def array_form(self, y, rows):
        ratio, S = self._segment(y)
        rows[:] = ratio
        rmax = ratio.max(axis=1)
        hit = np.flatnonzero(rmax > 1.0)
        a = int(hit[0]) if hit.size else -1
        return a, rmax, (ratio[a] if hit.size else None), S[-1]

    monkeypatch.setattr(combined.InnovationMonitor, "_scan_rows", array_form)
    assert [run(stop) for stop in (False, True)] == compiled
    assert compiled[0][0] == compiled[1][0] >= 3000


@pytest.mark.parametrize(("n", "rate"), [(172.8, 5e-324), (172.8, 1e-9), (1e8, 1e-3)])
def test_a_design_rate_too_low_for_the_cusum_is_refused_naming_rate_per_day(n, rate):
    # review 35f #8: 5e-324 was refused as "p must be ... got 0.0", 1e-9 as "arl must be ..."
    with pytest.raises(ValueError, match=rf"^rate_per_day = {rate!r} .* too low for .* raise "
                                         r"rate_per_day$"):
        CombinedDesign(n, 3, rate)


@pytest.mark.parametrize(("call", "match"), [
    (lambda: cusum_threshold(1e5, 5e-324), r"^k must be a real number in \[0.01, 100\]"),
    (lambda: drift_glr([]), r"^y must be a 1-D array of at least one sample"),
    (lambda: combined_detect(-0.0, np.zeros(500)), r"^t must be a 1-D array of sample times"),
    (lambda: combined_detect(np.arange(300.0), np.zeros(300)), r"^t must hold at least 400 samples"),
    (lambda: combined_detect(3.0 * np.arange(500), np.zeros(500), train=-0.0), r"^train must be"),
])
def test_an_edge_input_is_refused_naming_it(call, match):
    with pytest.raises(ValueError, match=match):
        call()


@pytest.mark.parametrize(("args", "message"), [
    ((2.0, 2.0), r"^arl must be at least 44 samples for k = 2 "),
    ((2.0, 100.0), r"^k = 100 is too high: this CUSUM runs more than 1e\+13 samples"),
    ((10.0, 8.0), r"^k = 8 is too high"),
])
def test_cusum_threshold_refuses_a_design_the_chain_cannot_reach(args, message):
    # k = 2 alarms on noise every 44 samples at the earliest (h -> 0): arl = 2 used to halve h
    # down to 0 for minutes and fail naming h; k = 100 made the chain singular
    with pytest.raises(ValueError, match=message):
        cusum_threshold(*args)


def test_cusum_threshold_designs_the_longest_arl_and_cusum_arl_refuses_past_its_digits():
    # arl = 1e12 with k = 0.25 met negative chain ARLs while bracketing (math domain error)
    h = cusum_threshold(1e12, 0.25)
    assert 45.0 < h < 55.0
    assert cusum_arl(h, 0.25) == pytest.approx(1e12, rel=1e-3)
    with pytest.raises(ValueError, match=r"^h = 100 is too high for k = 0.25: the run length passes"):
        cusum_arl(100.0, 0.25)


def _noise(n=3000, m=1, seed=0):
    return 3.0 * np.arange(n), np.random.default_rng(seed).normal(size=(n, m))


def test_combined_detect_refuses_a_design_that_is_no_combined_design():
    """Review 35j (1) 1: design={'m': 1} raised AttributeError 'pfa_wavelet'."""
    t, y = _noise()
    with pytest.raises(ValueError, match=r"^design must be a CombinedDesign \(or None.*got dict"):
        combined_detect(t, y, design={"m": 1})


def test_combined_detect_names_wavelet_kw_set_by_it_or_misspelt():
    """Review 35j (1) 2-3: wavelet_kw={'pfa': ...} or {'train': ...} was "got multiple values"
    from wavelet_detect; a typo in it or in the monitor's keywords a TypeError naming an
    internal function."""
    t, y = _noise()
    with pytest.raises(ValueError, match=r"^wavelet_kw\['pfa'\] is set by combined_detect \(from "
                                         r"the design's pfa_wavelet\)"):
        combined_detect(t, y, wavelet_kw={"pfa": 1e-3})
    with pytest.raises(ValueError, match=r"^wavelet_kw\['train'\] is set by combined_detect"):
        combined_detect(t, y, wavelet_kw={"train": 500})
    with pytest.raises(ValueError, match=r"^wavelet_kw\['levle'\] is not a keyword of "
                                         r"wavelet_detect .*\(did you mean level\?\)"):
        combined_detect(t, y, wavelet_kw={"levle": 3})
    with pytest.raises(ValueError, match=r"^wavelet_kw must be a dict of keyword arguments"):
        combined_detect(t, y, wavelet_kw=[("level", 3)])
    with pytest.raises(ValueError, match=r"^adaptve is not a keyword combined_detect takes: .*"
                                         r"scale_samples.*\(did you mean adaptive\?\)"):
        combined_detect(t, y, adaptve=False)
    # the valid ones still pass
    res = combined_detect(t, y, train=1000, wavelet_kw={"level": 4}, scale_samples=3000)
    assert res.data["wavelet"].data["sigma"].size == 4


def test_combined_detect_refuses_uneven_times():
    """Review 35j (5) 20: sorted random times were accepted, though the design's samples a
    day and the wavelet assume one step."""
    t, y = _noise()
    tu = np.sort(np.random.default_rng(1).uniform(0.0, 9000.0, t.size))
    with pytest.raises(ValueError, match=r"^t must be evenly spaced \(each step within 0.01 of "
                                         r"the median step"):
        combined_detect(tu, y)
    gap = np.r_[t[:1500], t[1500:] + 3.0]          # one sample missing
    with pytest.raises(ValueError, match=r"got t\[1500\] - t\[1499\] = 6 s \(1 off\)"):
        combined_detect(gap, y)
    # rounding of large times is far inside the tolerance
    jitter = 5e8 + t + np.random.default_rng(2).uniform(-0.01, 0.01, t.size)
    combined_detect(jitter, y, train=1000)


def test_combined_detect_refuses_a_design_for_another_sampling_or_m():
    """Review 35j (5) 21: a design for 500-s sampling ran on 3-s data without a word."""
    t, y = _noise()
    with pytest.raises(ValueError, match=r"^design must be for the sampling of t, 28800 samples a "
                                         r"day \(one every 3 s\), got CombinedDesign\(samples_per_day"
                                         r"=172.8.*one every 500 s"):
        combined_detect(t, y, design=CombinedDesign(172.8, 1))
    with pytest.raises(ValueError, match=r"^design must have m = 1 \(the columns of y\)"):
        combined_detect(t, y, design=CombinedDesign(28800.0, 2))
    res = combined_detect(t, y, design=CombinedDesign(28800.0, 1), train=1000)
    assert res.data["design"].samples_per_day == 28800.0


def test_the_monitor_refuses_scale_settings_without_the_adaptive_scale():
    """Review 35j (5) 5: scale_samples, scale_every and prior_samples were accepted and unused
    with adaptive=False."""
    d = CombinedDesign(28800.0, 2)
    for key in ("scale_samples", "scale_every", "prior_samples"):
        with pytest.raises(ValueError, match=rf"^{key} = 100 is unused with adaptive=False"):
            InnovationMonitor(d, adaptive=False, **{key: 100})
    assert InnovationMonitor(d, adaptive=False).prior_samples == 500
    assert InnovationMonitor(d).prior_samples == 500
    with pytest.raises(ValueError, match=r"^design must be a CombinedDesign, got dict"):
        InnovationMonitor({"m": 2})


def test_the_monitor_refuses_time_going_back():
    """Review 35j (5) 22 (the class): the monitor took samples earlier than those fed before."""
    t, y = _noise(500, 2)
    mon = InnovationMonitor(CombinedDesign(28800.0, 2))
    mon.process(t, y, stop=False)
    with pytest.raises(ValueError, match=r"^t must increase from one call to the next .*t\[0\] = 0 "
                                         r"after the last sample fed, at 1497"):
        mon.process(t[:10], y[:10])
    with pytest.raises(ValueError, match=r"^t must be strictly increasing"):
        mon.process(t[10:][::-1] + 2000.0, y[10:])
    with pytest.raises(ValueError, match=r"^t must increase"):
        mon.update(1497.0, y[0])
    assert mon.update(1500.0, y[0]) in (True, False)


def test_the_monitor_restore_refuses_a_state_that_is_no_snapshot():
    """Review 35j (1), the class: a state that is no snapshot was a KeyError."""
    mon = InnovationMonitor(CombinedDesign(28800.0, 1))
    with pytest.raises(ValueError, match=r"^state must be a snapshot\(\) of this monitor"):
        mon.restore({"a": 1})
    mon.restore(mon.snapshot())


def test_review35_r15_a_series_with_no_noise_is_named_as_given():
    """Review 35 R15: combined_detect on a constant y named sigma, never given; it names
    y[:, 0] (or x when given), the training span and wavelet_kw's sigma."""
    t = np.arange(2000.0)
    tail = (r" has no noise over the training samples {}: the median \|detail coefficient\| is 0 "
            r"at levels 1, 2, 3, 4, 5 of 5, so no noise level can be estimated; give "
            r"wavelet_kw=\{{'sigma': \.\.\.\}} \(5 levels\) or a noisy series$")
    with pytest.raises(ValueError, match=r"^y\[:, 0\] \(x not given\)"
                       + tail.format(r"\[0, 2000\) \(train not given: the whole series\)")):
        combined_detect(t, np.zeros(2000))
    with pytest.raises(ValueError, match=r"^x" + tail.format(r"\[0, 1000\) \(train = 1000\)")):
        combined_detect(t, np.random.default_rng(0).normal(size=2000), x=np.ones(2000), train=1000)
