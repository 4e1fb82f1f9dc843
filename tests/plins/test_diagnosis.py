"""The PL/INS diagnosis (xnavlab.plins.parity.diagnosis): the chi-square monitor, the diagnosis of
a flight with and without a fault, and the comparison of the two detectors."""


import numpy as np
import pytest
from scipy.stats import chi2

from xnavlab.core.faults import Fault
from xnavlab.plins import ins
from xnavlab.plins import parity as P
from xnavlab.plins import pseudolites as pl

TRAJ = ins.paper_trajectory()


# ------------------------------------------------------------------------ the flight
def test_first_alarm_is_the_first_crossing_after_the_arming_time():
    assert P.first_alarm([0.0, 1.0, 2.0], [5.0, 0.0, 5.0], 1.0, after=0.5) == 2.0
    with pytest.raises(ValueError, match="statistic"):
        P.first_alarm([0.0, 1.0], [1.0], 1.0)


def test_chi2_monitor():
    A, Qd = ins.error_transitions(TRAJ)
    x = ins.simulate_errors(TRAJ, rng=0, transitions=(A, Qd))
    clean = pl.simulate_pseudoranges(TRAJ, x, rng=1)
    mon = P.chi2_monitor(clean, (A, Qd))
    assert mon.first_alarm() is None and mon.threshold == pytest.approx(chi2.isf(1e-6, 4))
    assert np.mean(mon.statistic[20:]) == pytest.approx(4.0, rel=0.25)  # chi^2_4 on average
    bad = pl.simulate_pseudoranges(
        TRAJ, x, rng=1, faults=[Fault(pl.SENSOR, "step", 100.0, 80.0, component=2)])
    assert P.chi2_monitor(bad, (A, Qd)).first_alarm() == 80.0
    with pytest.raises(ValueError, match="data"):
        P.chi2_monitor(x, (A, Qd))
    with pytest.raises(ValueError, match="transitions"):
        P.chi2_monitor(clean, (A[:5], Qd[:5]))


def test_diagnose_flight_fault_free_and_faulty():
    d = P.diagnose_flight(seed=3)
    assert d.detection == [None] * 4 and d.identification == {}
    assert d.null_dim == 10 and d.s == 11 and d.statistic.shape == (190, 4)
    faults = [Fault(pl.SENSOR, "step", -80.0, 120.0, component=3)]
    d = P.diagnose_flight(faults, seed=3, with_chi2=True, s=8, threshold=20.0)
    assert d.detection == [None, None, None, 120.0] and d.threshold == 20.0
    # a shorter window identifies a step less well: about 3 m (1 sigma) for s = 8
    assert d.identification[3].final[0] == pytest.approx(-80.0, abs=10.0)
    assert d.chi2.first_alarm() == 120.0


def test_diagnose_flight_bad_input():
    for kw, name in (({"s": 1}, "s"), ({"sigma": 0.0}, "sigma"), ({"model": "bias"}, "model"),
                     ({"leak_tol": 0.0}, "leak_tol"), ({"threshold": -1.0}, "threshold"),
                     ({"duration": 5.0}, "duration"), ({"time_origin": "t"}, "time_origin")):
        with pytest.raises(ValueError, match=name):
            P.diagnose_flight(**kw)
    with pytest.raises(ValueError, match="faults"):
        P.diagnose_flight(["pseudorange:step:100@50+inf"])


def test_compare_detectors_sees_a_slow_drift_by_the_filter_only_and_checks_its_input():
    rows = P.compare_detectors("ramp", [1.0], n_runs=1)
    assert rows[0]["parity_rate"] == 0.0 and rows[0]["parity_delay"] is None
    assert rows[0]["chi2_rate"] == 1.0  # the filter's memory catches the slow drift
    with pytest.raises(ValueError, match="kind"):
        P.compare_detectors("spike", [1.0])
    with pytest.raises(ValueError, match="n_runs"):
        P.compare_detectors("step", [1.0], n_runs=0)
    with pytest.raises(ValueError, match="sensor"):
        P.compare_detectors("step", [100.0], n_runs=1, sensor=9)


def test_every_window_of_chapter_12s_slider_is_a_valid_design():
    """The chapter's slider offers s = 4..29; each gives a flight design. At s = 30 one sensor's
    local parity spaces differ in dimension (28 against 29) and the design is refused with one
    line, which is why the slider stops at 29."""
    from xnavlab.plins import ins, pseudolites
    from xnavlab.plins.parity import diagnosis

    traj, sites = ins.paper_trajectory(), pseudolites.sites_ecef()
    tol = 0.3 * pseudolites.DEFAULT_SIGMA
    for s in range(4, 30):
        diagnosis.flight_design(traj, sites, s, tol)
    with pytest.raises(ValueError, match=r"^tol = 0.6 m leaves local parity spaces of sensor \d that "
                                         r"differ in dimension \[28, 29\]; change tol or n_points$"):
        diagnosis.flight_design(traj, sites, 30, tol)


def test_first_alarm_refuses_a_nan_or_complex_arming_time():
    for after in (float("nan"), 1j, "0"):
        with pytest.raises(ValueError, match="^after must be a real number"):
            P.first_alarm([0.0, 1.0], [5.0, 5.0], 1.0, after=after)


@pytest.mark.parametrize(("sizes", "kwargs", "words"), [
    ([], {}, r"^sizes must be a list of at least one fault size \(shape \(n,\), n >= 1\), got "
             r"shape \(0,\)"),
    ([[1.0, 2.0]], {}, r"^sizes must be a list of at least one fault size"),
    ([100.0, 0.0], {}, r"^sizes\[1\] must be a nonzero fault size"),
    ([100.0], {"with_chi2": False}, r"^compare_detectors got with_chi2=False: set by "
                                    r"compare_detectors itself"),
    ([100.0], {"sigmaa": 1.0}, r"^compare_detectors got sigmaa=1.0: not a setting of "
                               r"diagnose_flight \(it passes on .*sigma"),
])
def test_compare_detectors_refuses_an_empty_table_and_settings_it_would_not_use(sizes, kwargs,
                                                                               words):
    """Review 35b N23: an empty list of sizes returned [] (a table with no rows)."""
    with pytest.raises(ValueError, match=words):
        P.compare_detectors("step", sizes, n_runs=1, **kwargs)


def test_diagnose_flight_with_chi2_is_a_real_bool():
    with pytest.raises(ValueError, match="^with_chi2 must be True or False, got 'no'"):
        P.diagnose_flight([], with_chi2="no")


def test_compare_detectors_takes_a_first_seed_whose_runs_stay_in_range():
    """Review 35e: seed 2^63 - 1 with two runs failed in its second run with the seed + 1
    it was never given; the range now says how far the first seed may go."""
    with pytest.raises(ValueError, match=r"^seed must be an integer in \[0, 9223372036854775806\], "
                                         r"got 9223372036854775807$"):
        P.compare_detectors("step", [1.0], n_runs=2, seed=2**63 - 1)


def test_first_alarm_names_the_series_cut_short():
    """Issue 35 (review 35h): a 0-d statistic was refused as 't and statistic must have the same
    shape (n,)', leading with t."""
    with pytest.raises(ValueError, match=r"^statistic must be a 1-D array"):
        P.first_alarm([0.0, 1.0, 2.0], -0.0, 1.0)
    with pytest.raises(ValueError, match=r"^t must hold one time per sample of statistic \(n = 3\), got 1$"):
        P.first_alarm([1.0], [0.1, 5.0, 5.0], 1.0)


@pytest.mark.parametrize("transitions", [True, -0.0, [], [1.0, True, 0.0], np.array(1.0)])
def test_chi2_monitor_names_transitions_that_are_no_pair(transitions):
    """Issue 35 (review 35h): transitions=True was 'cannot unpack non-iterable bool object', []
    'not enough values to unpack'."""
    tr = ins.paper_trajectory(duration=5.0)
    d = pl.simulate_pseudoranges(tr, ins.simulate_errors(tr, rng=0))
    with pytest.raises(ValueError, match=r"^transitions must be a pair \(A, Qd\) from error_transitions"):
        P.chi2_monitor(d, transitions)


@pytest.mark.parametrize("faults", [True, -0.0, np.array(1.0), [1.0]])
def test_diagnose_flight_names_faults_that_are_no_list_of_faults(faults):
    """Issue 35 (review 35h): faults=True was "TypeError: 'bool' object is not iterable"."""
    with pytest.raises(ValueError, match=r"^faults(\[0\])? must be a"):
        P.diagnose_flight(faults)


def test_flight_design_leads_with_the_tolerance_that_leaves_no_parity_space():
    """Issue 35 (review 35h): tol=0 was refused as 's = 11 leaves no common parity space'."""
    tr = ins.paper_trajectory(duration=40.0)
    with pytest.raises(ValueError, match=r"^tol = 0 m leaves no common parity space with s = 11 "
                                         r"\(constraint 1\); increase tol or s$"):
        P.diagnosis.flight_design(tr, pl.sites_ecef(), 11, 0.0)


def test_diagnose_flight_names_leak_tol_not_the_tol_it_makes_of_it():
    """Review 35i: diagnose_flight(leak_tol=1e-300) was refused naming flight_design's tol."""
    with pytest.raises(ValueError, match=r"^leak_tol = 1e-300 \(tol = leak_tol x sigma = 2e-300 m\) "
                                         r"leaves no common parity space with s = 11 \(constraint 1\); "
                                         r"increase leak_tol or s$"):
        P.diagnose_flight(leak_tol=1e-300)


def test_first_alarm_refuses_times_out_of_order_and_a_negative_threshold():
    """Issue 35 (review 35i): t = [2, 1, 0] gave an alarm at 1 s, repeated times at 0 s, and a
    threshold of -1 an alarm at the first sample."""
    with pytest.raises(ValueError, match=r"^t must be strictly increasing \(sample times, s\), got "
                                         r"t\[1\] = 1 after t\[0\] = 2$"):
        P.first_alarm([2.0, 1.0, 0.0], [0.1, 5.0, 5.0], 1.0)
    with pytest.raises(ValueError, match=r"^t must be strictly increasing"):
        P.first_alarm([0.0, 0.0, 0.0], [0.1, 5.0, 5.0], 1.0)
    with pytest.raises(ValueError, match=r"^threshold must be a real number in \[0, inf\), got -1.0$"):
        P.first_alarm([0.0, 1.0, 2.0], [0.1, 5.0, 5.0], -1.0)
    assert P.first_alarm([0.0, 1.0, 2.0], [0.0, 5.0, 5.0], 0.0) == 1.0


def test_chi2_monitor_checks_each_qd_and_a_negative_initial_sigma():
    """Issue 35 (review 35i): a swapped (Qd, A) pair and x0_std = -1 were accepted."""
    tr = ins.paper_trajectory(duration=10.0)
    A, Qd = ins.error_transitions(tr)
    d = pl.simulate_pseudoranges(tr, ins.simulate_errors(tr, rng=0, transitions=(A, Qd)))
    with pytest.raises(ValueError, match=r"^transitions\[1\]\[0\] must be symmetric"):
        P.chi2_monitor(d, (Qd, A))
    bad = Qd.copy()
    bad[3, 0, 0] = -1.0
    with pytest.raises(ValueError, match=r"^transitions\[1\]\[3\] must be positive semi-definite"):
        P.chi2_monitor(d, (A, bad))
    with pytest.raises(ValueError, match=r"^x0_std must be >= 0 \(1-sigma initial errors\), got -1$"):
        P.chi2_monitor(d, (A, Qd), x0_std=-np.ones(10))
    with pytest.raises(ValueError, match=r"^x0_std must have shape \(10,\)"):
        P.chi2_monitor(d, (A, Qd), x0_std=np.ones((1, 10)))


def test_diagnose_flight_refuses_p_fa_it_would_ignore_and_a_step_its_design_cannot_take():
    """Issue 35 (review 35i): p_fa beside a threshold was ignored; dt=3, duration=40 was
    refused as 'the local parity spaces ... change leak_tol or n_points', duration=40.5 cut to
    40 s."""
    with pytest.raises(ValueError, match=r"^p_fa must be omitted when threshold is given without "
                                         r"with_chi2"):
        P.diagnose_flight(threshold=14.0, p_fa=1e-3, duration=40.0)
    d = P.diagnose_flight(threshold=14.0, p_fa=1e-3, duration=40.0, with_chi2=True)
    assert d.threshold == 14.0 and d.chi2.threshold == pytest.approx(chi2.isf(1e-3, 4))
    with pytest.raises(ValueError, match=r"^p_fa must be a real number in \(0, 0.5\)"):
        P.diagnose_flight(p_fa=0.7, duration=40.0)
    with pytest.raises(ValueError, match=r"^dt must be a real number in \[0.001, 3\], got 4.0$"):
        P.diagnose_flight(dt=4.0, duration=200.0)
    with pytest.raises(ValueError, match=r"^duration must be a whole number of steps dt = 1 s, got "
                                         r"40.5 s \(40.5 steps\): the nearest are 40 and 41 s$"):
        P.diagnose_flight(duration=40.5)
    with pytest.raises(ValueError, match=r"^duration must be a whole number of steps dt = 3 s"):
        P.diagnose_flight(dt=3.0, duration=40.0)
    assert P.diagnose_flight(duration=40.0).threshold == P.diagnose_flight(duration=40.0, p_fa=1e-6).threshold


def test_compare_detectors_refuses_a_size_given_twice():
    """Review 35i (borderline): sizes=[100, 100] ran the same runs twice, one row repeated."""
    with pytest.raises(ValueError, match=r"^sizes lists 100 twice \(items 0 and 1\)$"):
        P.compare_detectors("step", [100.0, 100.0], n_runs=1)


def test_flight_design_refuses_no_site_and_compare_detectors_names_the_onset():
    """Review 35k (1) 23: flight_design(tr, sites[:0], ...) was an IndexError; compare_detectors'
    onset=-1 was refused as 'faults[0] (...) starts outside this flight' (a list never given)."""
    with pytest.raises(ValueError, match=r"^sites must have shape \(m, 3\) with m >= 1"):
        P.diagnosis.flight_design(ins.paper_trajectory(), pl.sites_ecef()[:0], 11, 0.6)
    for onset in (-1.0, 1e300, "1.0"):
        with pytest.raises(ValueError, match=r"^onset must be a real number in \[0, 200\]"):
            P.compare_detectors("step", [100.0], n_runs=1, onset=onset)
    with pytest.raises(ValueError, match=r"^onset must be a real number in \[0, 30\], got 50"):
        P.compare_detectors("step", [100.0], n_runs=1, duration=30.0)


def _fresh_design(traj, sites, s=11, tol=0.6):
    """The blended bases of ``traj`` built from the public steps, not from the design cache."""
    points = P.operating_points(traj)
    models = P.local_models(points, traj.lon[0], traj.h[0], sites, traj.dt)
    V = [P.align_bases([P.parity_basis(lm.A, lm.C[j], s, B=lm.B, state_std=P.TYPICAL_STATE_STD,
                                       tol=tol) for lm in models]) for j in range(len(sites))]
    stacked = np.stack([np.stack([V[j][k] for j in range(len(sites))]) for k in range(len(models))])
    return P.blended_bases(P.memberships(P.premises(traj), points), stacked)


def test_the_cached_design_and_a_diagnosis_hand_out_read_only_arrays():
    """Review 35 R2: flight_design's arrays were the cache's own, writeable: W[:] = 0 made a
    later diagnose_flight miss a 100 m step; Diagnosis.points and .weights were those arrays."""
    fault = [Fault(pl.SENSOR, "step", 100.0, 50.0, component=0)]
    before = P.diagnose_flight(fault)
    *arrays, _ = P.diagnosis.flight_design(TRAJ, pl.sites_ecef(), 11, 0.6)
    for arr in [*arrays, before.points, before.weights]:
        assert not arr.flags.writeable
        with pytest.raises(ValueError, match="read-only"):
            arr[...] = 0.0
    before.t_res[:] = 0.0   # the result's own times: the cached flight's stay as they were
    after = P.diagnose_flight(fault)
    assert after.detection == [50.0, None, None, None] == before.detection
    np.testing.assert_array_equal(after.t_res, TRAJ.t[11:])
    np.testing.assert_array_equal(after.statistic, before.statistic)


def test_two_flights_that_differ_in_longitude_or_height_get_their_own_design():
    """Review 35 R3: the cache key held the flight's length, step and last latitude only: a
    flight at another longitude (or height) got the first flight's design."""
    sites = pl.sites_ecef()
    first = P.diagnosis.flight_design(ins.paper_trajectory(duration=40.0), sites, 11, 0.6)
    for other in (ins.paper_trajectory(duration=40.0, lon0_deg=-60.0),
                  ins.paper_trajectory(duration=40.0, h=5_000.0)):
        design = P.diagnosis.flight_design(other, sites, 11, 0.6)
        assert design is not first
        np.testing.assert_array_equal(design[2], _fresh_design(other, sites))
    again = P.diagnosis.flight_design(ins.paper_trajectory(duration=40.0), sites, 11, 0.6)
    np.testing.assert_array_equal(again[2], first[2])   # an equal flight: an equal design
