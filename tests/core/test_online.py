"""The causal wavelet detector's parts (xnavlab.core.detection.online): causal filters and details,
the threshold and its false-alarm probability, the MAD noise estimate and the event tracker."""

import math

import numpy as np
import pytest
import pywt

from xnavlab.core import detection as D

SIGMA = 5000.0          # m, UV range noise of the paper


def test_causal_filters_unit_norm_and_vanishing_moments():
    for j, g in enumerate(D.causal_filters("db3", 5), start=1):
        assert len(g) == (2**j - 1) * 5 + 1
        assert np.isclose(g @ g, 1.0)
        m = np.arange(len(g)) / len(g)
        for p in range(3):                                              # db3: 3 vanishing moments
            assert abs(np.sum(m**p * g)) < 1e-12


def test_causal_details_are_pywt_swt_delayed():
    """Our causal details equal the stationary wavelet transform, delayed by 3 (2^j - 1) samples."""
    x = np.random.default_rng(0).normal(size=512)
    ours = D.causal_details(x)
    swt = pywt.swt(x, "db3", level=5, trim_approx=False)
    for j in range(1, 6):
        ref = np.roll(swt[5 - j][1], 3 * (2**j - 1))
        assert np.max(np.abs(ours[j - 1, 200:] - ref[200:])) < 1e-12


def test_threshold_and_false_alarm_probability_are_inverse():
    for pfa in (1e-2, 1e-5, 1e-8):
        k = D.threshold_multiplier(pfa, 6)
        assert math.isclose(D.false_alarm_probability(k, 6), pfa, rel_tol=1e-9)


def test_mad_sigma_of_db3_details_of_white_noise_is_sigma():
    x = np.random.default_rng(2).normal(0.0, SIGMA, 50000)
    sig = D.mad_sigma(D.causal_details(x)[:, 200:])
    assert np.allclose(sig / SIGMA, 1.0, atol=0.03)


def test_event_tracker_matches_events_from_alarms():
    rng = np.random.default_rng(10)
    alarm = rng.random(2000) < 0.02
    ratio = np.where(alarm, 1.0 + rng.random(2000), 0.5)
    t = np.arange(2000.0)
    events, faulty = D.events_from_alarms(t, alarm, ratio, 30)
    tr = D.EventTracker(30)
    flags = [tr.update(ti, a, r) for ti, a, r in zip(t, alarm, ratio, strict=True)]
    assert np.array_equal(flags, faulty)
    assert [(e.onset, e.end, e.cleared, e.peak) for e in tr.all_events()] == \
           [(e.onset, e.end, e.cleared, e.peak) for e in events]


def test_event_tracker_snapshot_restore_and_close():
    from xnavlab.core.detection import EventTracker

    tr = EventTracker(holdoff=3)
    tr.update(0.0, True, 2.0, "a")
    snap = tr.snapshot()
    for i in range(1, 6):
        tr.update(float(i), i == 2, 3.0, "b")
    after = [(e.onset, e.end, e.cleared) for e in tr.events]
    tr.restore(snap)
    assert tr.faulty and tr.events == []
    for i in range(1, 6):
        tr.update(float(i), i == 2, 3.0, "b")
    assert [(e.onset, e.end, e.cleared) for e in tr.events] == after == [(0.0, 2.0, 5.0)]
    tr.update(9.0, True, 2.0, "c")
    tr.close(9.5)
    assert not tr.faulty and tr.events[-1].cleared == 9.5
    tr.close()                                   # nothing open: no-op
    assert len(tr.events) == 2


def test_mad_scale_is_the_normal_quartile():
    from xnavlab.core.distributions import norm_ppf

    assert math.isclose(D.MAD_SCALE, norm_ppf(0.75), rel_tol=1e-15)


def test_alarm_clusters_runs_and_support():
    """Runs of consecutive flags (gap 1) and flags within the filter's support (the detector's
    events): the counts of isolations, not of flagged samples."""
    a = np.zeros(40, bool)
    a[[3, 4, 5, 9, 20, 21, 39]] = True
    first, last, size = D.alarm_clusters(a)
    assert first.tolist() == [3, 9, 20, 39] and last.tolist() == [5, 9, 21, 39]
    assert size.tolist() == [3, 1, 2, 1] and size.sum() == a.sum()
    assert len(D.alarm_clusters(a, gap=11)[0]) == 2
    assert all(len(c) == 0 for c in D.alarm_clusters(np.zeros(5, bool)))
    for bad in (0, 1.5):
        with pytest.raises(ValueError, match="gap"):
            D.alarm_clusters(a, gap=bad)


def test_false_alarms_of_white_noise_come_in_clusters():
    """White noise at pfa = 1e-3 (measured: 903 flagged samples in 30 days at 3 s, 655 runs, 477
    events; at the default 1e-5, 20 months: 9.7 samples and 6.05 events a month): the detector's
    events (flags within the 156-sample support) equal its hold-off events and are fewer than the
    flagged samples by a clear margin."""
    n = 300_000
    x = np.random.default_rng(5).normal(0.0, 1.0, n)
    res = D.wavelet_detect(3.0 * np.arange(n), x, sigma=np.full(5, 1.0), pfa=1e-3)
    support = len(D.causal_filters("db3", 5)[-1])
    runs = D.alarm_clusters(res.alarm)[0].size
    events = D.alarm_clusters(res.alarm, gap=support)[0].size
    assert events == len(res.events)
    assert res.alarm.sum() > 1.25 * runs and runs >= events


def test_signal_threshold_ratio():
    """A quadratic leaves every level at zero (three vanishing moments); a step reaches
    step_gain / k at each level; the ratio scales as 1 / sigma."""
    k = D.threshold_multiplier(1e-5, 6)
    t = np.arange(2000.0)
    np.testing.assert_allclose(D.signal_threshold_ratio(3.0 + 2.0 * t - 1e-3 * t**2, 1.0), 0.0,
                               atol=1e-9)
    step = (t >= 1000).astype(float)
    np.testing.assert_allclose(D.signal_threshold_ratio(step, 1.0), D.step_gain() / k, rtol=1e-12)
    np.testing.assert_allclose(D.signal_threshold_ratio(step, 2.0), D.step_gain() / (2 * k),
                               rtol=1e-12)
    for sigma in (0.0, np.ones(4)):
        with pytest.raises(ValueError, match="sigma"):
            D.signal_threshold_ratio(step, sigma)


def test_events_refuse_complex_or_nan_times_ratios_and_flags():
    tr = D.EventTracker(holdoff=2)
    for args, name in (((complex(1, 1), True, 2.0), "t"), ((1.0, True, math.nan), "ratio"),
                       ((1.0, math.nan, 2.0), "alarm"), ((1.0, 0.5, 2.0), "alarm")):
        with pytest.raises(ValueError, match=f"^{name} must"):
            tr.update(*args)
    with pytest.raises(ValueError, match="^t must hold real numbers"):
        D.events_from_alarms(np.arange(3.0) + 1j, np.zeros(3, bool), np.zeros(3), 1)
    with pytest.raises(ValueError, match="^ratio must not contain NaN"):
        D.events_from_alarms(np.arange(3.0), np.zeros(3, bool), [0.0, np.nan, 0.0], 1)
    with pytest.raises(ValueError, match="^t0 must be a real number"):
        D.Detection(np.zeros(0), *[np.zeros(0)] * 4, []).first_onset_after(math.nan)


def test_a_holdoff_beyond_its_range_is_refused_not_an_overflow():
    """Review 35e: holdoff=10**30 was 'OverflowError: Python int too large to convert to C long'."""
    a = np.zeros(10, bool)
    a[[2, 3]] = True
    with pytest.raises(ValueError, match=r"^holdoff must be an integer in \[1, 1000000000\]"):
        D.events_from_alarms(np.arange(10.0), a, a * 2.0, holdoff=10**30)


def test_signal_threshold_ratio_refuses_a_sigma_beyond_max_size():
    with pytest.raises(ValueError, match=r"sigma must be in \[1e-100, 1e\+15\]"):
        D.signal_threshold_ratio(np.sin(np.arange(2000.0)), 1e308)


@pytest.mark.parametrize(("call", "match"), [
    (lambda: D.mad_sigma(-0.0), r"^d must be an array of detail coefficients"),
    (lambda: D.mad_sigma([]), r"^d must hold at least one coefficient along axis -1"),
    (lambda: D.mad_sigma(np.ones(3), axis=1), r"^axis must be an integer in \[-1, 0\]"),
    (lambda: D.threshold_multiplier(5e-324), r"^pfa must be a real number in \[1e-15, 1\)"),
    (lambda: D.events_from_alarms(np.arange(3.0), True, np.ones(3), 2), r"^alarm must be a 1-D array"),
    (lambda: D.events_from_alarms(np.arange(3.0), [1, 0, 1], -0.0, 2), r"^ratio must be a 1-D array"),
    (lambda: D.events_from_alarms([1.0], [1, 0, 1], np.ones(3), 2), r"^t must have length 3 \(as alarm and"),
    (lambda: D.alarm_clusters([]), r"^alarm must hold at least one flag"),
    (lambda: D.alarm_clusters([1.0, True, 0.0]), r"^alarm must be a 1-D array of flags"),
    (lambda: D.signal_threshold_ratio(np.zeros(400), 5e-324), r"^sigma must be in \[1e-100, "),
    (lambda: D.Event(1.0, 2.0, 3.0, 2.0, "chi2").as_dict(True, "wavelet"), r"^sensor must be"),
    (lambda: D.Event(1.0, 2.0, 3.0, 2.0, "chi2").as_dict("uv", []), r"^detector must be"),
])
def test_an_edge_input_is_refused_naming_it(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_events_from_alarms_refuses_tests_of_another_length_and_times_going_back():
    """Review 35j (1) 6 and (5) 23: tests=['a'] for three samples was an IndexError; times
    going back gave an event ending before its onset."""
    t, a, r = np.arange(3.0), np.array([0, 1, 0], bool), np.array([0.0, 1.0, 0.0])
    with pytest.raises(ValueError, match=r"^tests must have length 3 \(one name per sample"):
        D.events_from_alarms(t, a, r, 1, tests=["a"])
    with pytest.raises(ValueError, match=r"^tests must be a sequence of test names"):
        D.events_from_alarms(t, a, r, 1, tests="abc")
    with pytest.raises(ValueError, match=r"^t must be strictly increasing .*t\[1\] = 1 after "
                                         r"t\[0\] = 2"):
        D.events_from_alarms(t[::-1], np.array([0, 1, 1], bool), np.array([0.0, 1.0, 1.0]), 1)
    assert D.events_from_alarms(t, a, r, 1, tests=["x", "y", "z"])[0][0].test == "y"


def test_online_detectors_refuse_time_going_back():
    """Review 35j (5) 22: Chi2Detector.update and WaveletDetector.update accepted time going
    back (an event then ended or cleared before its onset)."""
    det = D.Chi2Detector(1)
    det.update(5.0, [0.0], [[1.0]])
    with pytest.raises(ValueError, match=r"^t must increase from one update to the next .*got "
                                         r"t = 1 after t = 5"):
        det.update(1.0, [9.0], [[1.0]])
    with pytest.raises(ValueError, match=r"^t must increase"):
        det.update(5.0, [9.0], [[1.0]])
    det.update(6.0, [0.0], [[1.0]])
    w = D.WaveletDetector()
    w.update(3.0, 1.0)
    with pytest.raises(ValueError, match=r"^t must increase .*got t = 0 after t = 3"):
        w.update(0.0, 1.0)
    w.reset()                                     # forgets the data, and the times
    w.update(0.0, 1.0)
    tr = D.EventTracker(2)
    tr.update(4.0, True, 2.0)
    with pytest.raises(ValueError, match=r"^t must not go back .*got t = 3 after t = 4"):
        tr.update(3.0, False)
    with pytest.raises(ValueError, match=r"^t must not go back"):
        tr.close(3.0)
    snap = tr.snapshot()
    tr.update(9.0, False)
    tr.restore(snap)                              # back to t = 4: 5 is after it
    tr.update(5.0, False)


def test_restore_refuses_a_state_that_is_no_snapshot():
    """Review 35j (1), the class: a state that is no snapshot was Python's unpacking message."""
    with pytest.raises(ValueError, match=r"^state must be a snapshot\(\) of this tracker"):
        D.EventTracker(2).restore((1, 2))


def test_masked_alarm_flags_are_refused():
    """Review 35m (5) 1: np.asarray dropped the mask and the masked alarm was used."""
    alarm = np.ma.masked_array(np.zeros(5, bool), mask=[0, 0, 1, 0, 0])
    with pytest.raises(ValueError, match=r"^alarm has masked entries \(no flag to use"):
        D.events_from_alarms(np.arange(5.0), alarm, np.zeros(5), 1)
