"""Fault schedules of the Mars run (xnavlab.mars.faults.schedules): the components a spec may name, the
paper's schedule, the command line's spec, the check that refuses a fault a run cannot use, and
the scoring rule (detected while the fault acts or out at its onset, late after its end, false
alarms what no fault explains)."""

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from xnavlab.core.detection import Event
from xnavlab.core.faults import Fault
from xnavlab.mars.faults import schedules as s
from xnavlab.mars.navigation import scenarios


def test_components_follow_the_scenario_subsystems():
    comps = s.components(scenarios.MarsScenario(subsystems=("uv", "cns")))
    assert set(comps) == {"uv", "cns"}
    assert comps["cns"] == ("angle0", "angle1", "angle2")
    assert s.components()["xnav"] == ("B0531", "B1937", "B1957", "B1821")


def test_paper_schedule_has_every_paper_onset_once_and_scales_with_the_noise():
    sc = scenarios.MarsScenario(sigma_range_m=2000.0)
    faults = s.paper_schedule(uv_step_sigma=3.0, scenario=sc)
    for sensor, onsets in s.PAPER_ONSETS.items():
        assert sorted(f.onset for f in faults if f.sensor == sensor) == sorted(onsets)
    assert [f.onset for f in faults] == sorted(f.onset for f in faults)
    assert {f.magnitude for f in faults if f.sensor == "uv"} == {6000.0}
    cns = {f.magnitude for f in faults if f.sensor == "cns"}
    assert len(cns) == 1 and cns.pop() == pytest.approx(8.0 * math.radians(sc.sigma_horizon_deg))
    ramps = [f for f in faults if f.kind == "ramp"]
    assert ramps and all(f.sensor == "xnav" and f.component == 1 for f in ramps)


@pytest.mark.parametrize(("kw", "name"), [({"uv_duration": 0.0}, "uv_duration"),
                                          ({"cns_step_sigma": -1.0}, "cns_step_sigma"),
                                          ({"xnav_ramp": 1.0}, "xnav_ramp")])
def test_paper_schedule_names_a_bad_argument(kw, name):
    with pytest.raises(ValueError, match=f"^{name}"):
        s.paper_schedule(**kw)


def test_parse_faults_reads_a_pulsar_by_its_full_name():
    by_full, = s.parse_faults("xnav.B1937+21:step:1e-5@5e5+5000")
    by_short, = s.parse_faults("xnav.B1937:step:1e-5@5e5+5000")
    assert by_full == by_short and by_full.component == 1 and by_full.duration == 5000.0
    assert len(s.parse_faults(" paper ")) == len(s.paper_schedule())


def test_check_schedule_takes_a_fault_inside_the_run_and_returns_the_list():
    sc = scenarios.MarsScenario(days=2)
    fs = (Fault("uv", "step", 1.0, 1000.0, 10.0, component=0),)
    assert s.check_schedule(fs, sc) == list(fs)
    assert s.check_schedule([Fault("uv", "step", 1.0, 1.5 * 86400.0, 1e9)], sc)  # may end after


def test_check_schedule_refuses_a_fault_after_the_run_and_says_how_long_to_run():
    sc = scenarios.MarsScenario(days=1)
    with pytest.raises(ValueError, match=r"outside this run .* run at least --days 1\.22"):
        s.check_schedule([Fault("uv", "step", 1.0, 100000.0, 10.0, component=0)], sc)


def test_check_schedule_refuses_a_wavelet_fault_in_the_training_span():
    sc = scenarios.MarsScenario(days=3)
    early = [Fault("cns", "step", 1e-3, 3600.0, 100.0)]
    with pytest.raises(ValueError, match="on which the cns wavelet detector trains"):
        s.check_schedule(early, sc, detector="wavelet", train_days=1.0)
    assert s.check_schedule(early, sc, detector="combined")
    xnav = [Fault("xnav", "step", 1e-5, 3600.0, 1000.0)]         # XNAV does not train
    assert s.check_schedule(xnav, sc, detector="wavelet")


def test_check_schedule_refuses_a_fault_before_the_filter_settles_for_the_combined_detector():
    sc = scenarios.MarsScenario(days=1)
    with pytest.raises(ValueError, match="before the filter has settled"):
        s.check_schedule([Fault("uv", "step", 1.0, s.EARLIEST_ONSET_S - 1.0, 10.0)], sc)
    assert s.check_schedule([Fault("uv", "step", 1.0, s.EARLIEST_ONSET_S, 10.0)], sc)


def test_check_schedule_refuses_a_negative_onset_without_a_nonsense_fix():
    sc = scenarios.MarsScenario(days=1)
    with pytest.raises(ValueError, match=r"starts at -100 s, before the run's start: an onset "
                                         r"is s since the start, in \[0, 86400\)$"):
        s.check_schedule([Fault("uv", "step", 1.0, -100.0, 10.0)], sc)
    with pytest.raises(ValueError, match=r"outside this run .*: move its onset into the run$"):
        s.check_schedule([Fault("uv", "step", 1.0, 1e9, 10.0)], sc)     # no --days > 365


def test_check_schedule_refuses_a_fault_that_acts_on_no_sample():
    """A 300-s XNAV step between two samples 500 s apart would be injected as nothing."""
    sc = scenarios.MarsScenario(days=1)
    with pytest.raises(ValueError, match=r"acts on no sample: it lasts 300 s between two xnav "
                                         r"samples \(one every 500 s\): make it last at least 500 s"):
        s.check_schedule([Fault("xnav", "step", 1e-5, 61100.0, 300.0)], sc)
    assert s.check_schedule([Fault("xnav", "step", 1e-5, 61000.0, 300.0)], sc)   # on a sample
    assert s.check_schedule([Fault("xnav", "spike", 1e-5, 61100.0, 0.0)], sc)    # its next one
    with pytest.raises(ValueError, match="comes after the last xnav sample before the run.s end"):
        s.check_schedule([Fault("xnav", "spike", 1e-5, 86300.0, 0.0)], sc)


def test_paper_schedule_refuses_a_zero_xnav_fault():
    with pytest.raises(ValueError, match=r"^xnav_step_s must be a nonzero real number"):
        s.paper_schedule(xnav_step_s=0.0)
    with pytest.raises(ValueError, match=r"^xnav_ramp must be a nonzero real number"):
        s.paper_schedule(xnav_ramp=0.0)


# ------------------------------------------------------------------ the scoring rule


def _ev(*onsets):
    return [Event(t, t, t + 10.0, 2.0, "test") for t in onsets]


STEP = Fault("xnav", "step", 3e-6, onset=61000.0, duration=8000.0)     # acts on [61000, 69000)


def test_an_alarm_after_the_end_is_late_not_a_detection():
    """The issue's case: a step of 8000 s flagged 500 s after its end."""
    res = s.score_faults([STEP], {"xnav": _ev(69500.0)})
    f, = res["faults"]
    assert (f["status"], f["detected"], f["delay_s"], f["late_s"]) == ("late", False, None, 500.0)
    assert res["alarms"] == [{"sensor": "xnav", "onset": 69500.0, "match": "late", "fault": 0}]
    d, = s.fault_detection_delays([STEP], {"xnav": _ev(69500.0)})
    assert d["delay"] == math.inf and d["status"] == "late"
    # the fault acts on [onset, end): an alarm at the end itself is raised on a clean sample
    assert s.score_faults([STEP], {"xnav": _ev(69000.0)})["faults"][0]["status"] == "late"
    assert s.score_faults([STEP], {"xnav": _ev(68999.0)})["faults"][0]["delay_s"] == 7999.0


def test_an_alarm_open_at_the_onset_over_the_whole_fault_is_a_detection_at_delay_0():
    out = [{"sensor": "xnav", "out": 60000.0, "back": 69000.0}]         # back at the end
    f, = s.score_faults([STEP], {"xnav": _ev(60000.0)}, out)["faults"]
    assert (f["status"], f["delay_s"], f["out_at_onset"], f["detected_onset"]) == \
        ("detected", 0.0, True, 61000.0)
    still = [{"sensor": "xnav", "out": 60000.0, "back": None}]           # out to the run's end
    assert s.score_faults([STEP], {}, still)["faults"][0]["out_at_onset"]
    # out at the onset but back in before the end: the rest of the fault reached the filter
    early_back = [{"sensor": "xnav", "out": 60000.0, "back": 65000.0}]
    f, = s.score_faults([STEP], {}, early_back)["faults"]
    assert (f["status"], f["out_at_onset"]) == ("missed", False)
    f, = s.score_faults([STEP], {"xnav": _ev(66000.0)}, early_back)["faults"]
    assert (f["status"], f["delay_s"], f["out_at_onset"]) == ("detected", 5000.0, False)
    # out from the onset epoch itself is the fault's own alarm, not "out at onset"
    own = [{"sensor": "xnav", "out": 61000.0, "back": None}]
    f, = s.score_faults([STEP], {"xnav": _ev(61000.0)}, own)["faults"]
    assert (f["delay_s"], f["out_at_onset"]) == (0.0, False)
    # another subsystem out does not cover the fault
    assert s.score_faults([STEP], {}, [{"sensor": "uv", "out": 0.0, "back": None}])[
        "faults"][0]["status"] == "missed"


def test_every_alarm_is_matched_once_and_false_alarms_are_what_no_fault_explains():
    ramp = Fault("uv", "ramp", 1.0, onset=1000.0, duration=500.0)          # nothing finds it
    events = {"xnav": _ev(100.0, 61500.0, 62000.0, 69400.0, 69000.0 + s.LATE_WINDOW_S["xnav"]),
              "uv": _ev(1600.0, 1700.0), "cns": _ev(61500.0)}
    res = s.score_faults([STEP, ramp], events)
    assert [f["status"] for f in res["faults"]] == ["detected", "late"]
    assert res["faults"][0]["delay_s"] == 500.0 and res["faults"][1]["late_s"] == 100.0
    match = [(a["sensor"], a["onset"], a["match"], a["fault"]) for a in res["alarms"]]
    assert match == [
        ("xnav", 100.0, "false alarm", None),          # before the onset
        ("uv", 1600.0, "late", 1),                     # the ramp's first alarm after its end
        ("uv", 1700.0, "after end", 1),                # a second one: neither late nor false
        ("xnav", 61500.0, "detection", 0),
        ("cns", 61500.0, "false alarm", None),         # another sensor: a false alarm
        ("xnav", 62000.0, "during fault", 0),
        ("xnav", 69400.0, "after end", 0),             # the detected step's end alarm
        ("xnav", 87000.0, "false alarm", None),        # beyond the late window
    ]


def test_a_spike_is_detected_only_on_its_own_sample():
    spike = Fault("xnav", "spike", 1e-5, onset=61001.0, duration=0.0)    # acts at 61500 s
    dt = s.sample_intervals()
    assert s.scoring_span(spike, dt) == (61001.0, 61750.0)
    assert s.score_faults([spike], {"xnav": _ev(61500.0)}, dt=dt)["faults"][0]["delay_s"] == 499.0
    late, = s.score_faults([spike], {"xnav": _ev(62000.0)}, dt=dt)["faults"]
    assert (late["status"], late["late_s"]) == ("late", 250.0)
    with pytest.raises(ValueError, match="^dt must give the sampling interval of sensor 'xnav'"):
        s.score_faults([spike], {})


def test_a_fault_that_outlasts_the_run_is_scored_to_its_end():
    forever = Fault("uv", "step", 1.0, onset=1000.0)
    f, = s.score_faults([forever], {"uv": _ev(5000.0)}, span=8000.0)["faults"]
    assert (f["end"], f["delay_s"]) == (8000.0, 4000.0)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(0.0, 2e5), max_size=12), st.floats(1.0, 2e4), st.floats(1.0, 1e5))
def test_scoring_is_a_partition(alarms, onset, duration):
    """Each fault gets one status; each alarm one match; the false alarms are exactly the
    alarms outside [onset, end + LATE_WINDOW_S) of every fault of their sensor."""
    f = Fault("uv", "step", 1.0, onset, duration)
    res = s.score_faults([f], {"uv": _ev(*alarms)})
    r, = res["faults"]
    assert r["status"] in s.STATUSES and r["detected"] == (r["status"] == "detected")
    assert [a["match"] in s.MATCHES for a in res["alarms"]] == [True] * len(alarms)
    false = [a["onset"] for a in res["alarms"] if a["match"] == "false alarm"]
    assert sorted(false) == sorted(t for t in alarms
                                   if not onset <= t < onset + duration + s.LATE_WINDOW_S["uv"])
    assert sum(a["match"] == "detection" for a in res["alarms"]) == int(r["detected"])
    assert sum(a["match"] == "late" for a in res["alarms"]) == int(r["status"] == "late")


def test_trial_outcome_takes_a_run_of_one_fault():
    from types import SimpleNamespace

    with pytest.raises(ValueError, match="^ft must hold exactly one fault, got 2"):
        s.trial_outcome(SimpleNamespace(faults=[STEP, STEP]))
    with pytest.raises(ValueError, match="^armed_from_s must be a real number in"):
        s.trial_outcome(SimpleNamespace(faults=[STEP]), armed_from_s=-1.0)


@pytest.mark.parametrize("span", [math.nan, 1j, 0.0, "1"])
def test_a_runs_span_that_is_not_a_positive_number_is_refused(span):
    with pytest.raises(ValueError, match=r"^span must be a real number in \(0, inf\]"):
        s.scoring_span(Fault("uv", "step", 1.0, 100.0, 50.0), span=span)
    with pytest.raises(ValueError, match="^span must"):
        s.score_faults([], {}, span=span)


def test_a_fault_listed_twice_is_refused_with_both_items():
    """Review 35 B.3: one event scored as two faults (faults: 2, detected: 2)."""
    sc = scenarios.MarsScenario(days=0.2)
    f = Fault("uv", "step", 1e3, 1000.0, 10.0, 0)
    with pytest.raises(ValueError, match=r"^faults lists uv.range:step:1000@1000\+10 twice "
                                         r"\(items 0 and 1\)"):
        s.check_schedule([f, f], sc)
    with pytest.raises(ValueError, match=r"twice \(items 0 and 1\)"):
        s.parse_faults("uv.range:step:1e3@1000+10,uv.range:step:1e3@1000+10", sc)
    with pytest.raises(ValueError, match=r"^faults lists .* twice"):
        s.score_faults([f, f], {})


@pytest.mark.parametrize("call, match", [
    (lambda sc: s.check_schedule(Fault("uv", "step", 1.0, 1000.0, 10.0), sc),
     r"^faults must be a sequence of Fault, got one Fault"),
    (lambda sc: s.check_schedule(["uv.range:step:1@1000+10"], sc), r"^faults\[0\] must be a Fault"),
    (lambda sc: s.check_schedule([], {"days": 1}), r"^scenario must be a MarsScenario, got dict"),
    (lambda sc: s.check_schedule([], None), r"^scenario must be a MarsScenario"),
    (lambda sc: s.components({"days": 1}), r"^scenario must be a MarsScenario, got dict"),
    (lambda sc: s.parse_faults("paper", "days=1"), r"^scenario must be a MarsScenario, got str"),
    (lambda sc: s.score_faults([Fault("uv", "step", 1.0, 1000.0, 10.0)], {"uv": [1001.0]}),
     r"^events\['uv'\]\[0\] must be a detection Event"),
    (lambda sc: s.score_faults([], [1001.0]), r"^events must be a dict of sensor"),
    (lambda sc: s.score_faults([], {"uv": 1001.0}), r"^events\['uv'\] must be a list"),
    (lambda sc: s.score_faults([], {}, [("uv", 1.0, None)]), r"^isolations\[0\] must be a dict"),
    (lambda sc: s.score_faults("uv:step:1@1+1", {}), r"^faults must be a sequence of Fault, got the"),
])
def test_a_wrong_type_is_one_value_error_naming_the_parameter(call, match):
    """Review 35 E.20, E.22, E.26: AttributeError and TypeError from deep inside before."""
    with pytest.raises(ValueError, match=match):
        call(scenarios.MarsScenario(days=0.2))


def test_a_fault_on_the_samples_at_the_runs_end_only_is_refused():
    """The UV sample at the end (2592 s of a 0.03-day run) existed, so the check took a fault
    at 2591 s; the score cuts a fault at the end, [2591, 2592), and always read it missed."""
    sc = scenarios.MarsScenario(days=0.03)
    for spec in ("uv.range:step:1e3@2591+10", "uv.range:spike:1e3@2590+0"):
        with pytest.raises(ValueError, match=r"acts on no sample: it comes after the last uv "
                                             r"sample before the run's end \(2589 s"):
            s.check_schedule(s.parse_faults(spec, sc), sc)
    f, = s.check_schedule(s.parse_faults("uv.range:step:1e3@2589+10", sc), sc)
    assert s.scoring_span(f, span=sc.span) == (2589.0, 2592.0)  # holds the 2589-s sample


def test_a_ramp_that_would_grow_beyond_max_size_in_the_run_is_refused_before_it():
    """Review 35b N7: the size a ramp reaches by the run's end (or its own end) is bounded, with
    the largest rate this run takes; one that ends early may be steeper."""
    sc = scenarios.MarsScenario(days=0.03)
    with pytest.raises(ValueError, match=r"^faults: uv.range:ramp:1e\+12@1000\+inf reaches 1\.59e\+15 "
                                         r"by 2592 s, beyond 1e\+15 .*a rate of at most 6\.28e\+11 "
                                         r"per s over this run$"):
        s.check_schedule(s.parse_faults("uv.range:ramp:1e12@1000+inf", sc), sc)
    assert len(s.check_schedule(s.parse_faults("uv.range:ramp:1e12@1000+900", sc), sc)) == 1


@pytest.mark.parametrize(("kw", "words"), [
    ({"detector": "Combined"}, "detector must be one of 'none', 'wavelet', 'chi2', 'combined'"),
    ({"train_days": -1.0}, "train_days must be a real number in (0, 0.05)"),  # the run's days
    ({"train_days": math.nan}, "train_days must be a real number in (0, 0.05)"),
    ({"paper": "no"}, "paper must be True or False"),
])
def test_check_schedule_checks_its_own_arguments(kw, words):  # review 35d D34: accepted
    sc = scenarios.MarsScenario(days=0.05)
    with pytest.raises(ValueError) as info:
        s.check_schedule([Fault("uv", "step", 1.0, 1000.0, 10.0, component=0)], sc, **kw)
    assert words in str(info.value)


@pytest.mark.parametrize(("kw", "words"), [
    ({"dt": 0}, "dt must be a dict of sensor -> sampling interval, s, got 0"),  # review 35d D35
    ({"dt": {"uv": math.nan}}, "dt['uv'] must be a real number in (0, inf), got nan"),
    ({"dt": {"uv": 0.0}}, "dt['uv'] must be a real number in (0, inf), got 0.0"),
    ({"dt": {"xnav": -1.0}}, "dt['xnav'] must be a real number in (0, inf), got -1.0"),
    ({"span": 10.0}, "span must end after the fault's onset (100 s): a fault that starts at or "
                     "after the run's end is not in it, got 10"),  # was the window (100, 10)
    ({"span": 100.0}, "span must end after the fault's onset (100 s)"),
])
def test_scoring_span_checks_dt_whenever_given_and_refuses_an_inverted_window(kw, words):
    with pytest.raises(ValueError) as exc:
        s.scoring_span(Fault("uv", "step", 1.0, 100.0, 50.0), **kw)
    assert str(exc.value).startswith(words), str(exc.value)
    if "span" in kw:  # score_faults scores through it: the fault after the end is refused too
        with pytest.raises(ValueError, match="^span must end after the fault's onset"):
            s.score_faults([Fault("uv", "step", 1.0, 100.0, 50.0)], {}, **kw)


@pytest.mark.parametrize("bad", [None, "uv.range:step:1@100+50", {"sensor": "uv"}])
def test_scoring_span_refuses_what_is_no_fault(bad):  # review 35d D37's class
    with pytest.raises(ValueError, match=r"^fault must be a Fault, got "):
        s.scoring_span(bad)


def test_an_event_with_a_non_finite_onset_is_refused():
    with pytest.raises(ValueError, match=r"^events\['uv'\]\[0\] must be a detection Event"):
        s.score_faults([], {"uv": [Event(math.nan, 1.0, 2.0, 1.0, "x")]})


@given(st.floats(0.0, 1e6), st.floats(1.0, 1e5), st.floats(1e-3, 2e6))
def test_a_scoring_window_is_never_inverted(onset, duration, span):
    f = Fault("uv", "step", 1.0, onset, duration)
    if span > onset:
        lo, hi = s.scoring_span(f, span=span)
        assert lo == onset < hi <= span
    else:
        with pytest.raises(ValueError, match="^span must end after the fault's onset"):
            s.scoring_span(f, span=span)


@pytest.mark.parametrize(("events", "words"), [
    ("abc", "events must be a list of detection Events (xnavlab.core.detection.Event), got 'abc'"),
    ({"uv": []}, "events must be a list of detection Events"),
    (5, "events must be a list of detection Events"),
    ([("uv", math.nan)], "events[0] must be a detection Event (xnavlab.core.detection.Event) with "
                         "finite onset and end and a real peak, got ('uv', nan)"),
    ([Event(1.0, 2.0, 3.0, 1.0, "a"), Event(math.nan, 1.0, 2.0, 1.0, "a")], "events[1] must be"),
    ([Event(1.0, 2.0, math.nan, 1.0, "a")], "events[0] must be"),
    # review 35e: the peak went unchecked (merge_events compares it: '1' was a TypeError, NaN
    # lost every comparison), and a bool passed for a time
    ([Event(1.0, 2.0, 3.0, "1", "a")], "events[0] must be"),
    ([Event(1.0, 2.0, 3.0, math.nan, "a")], "events[0] must be"),
    ([Event(True, 2.0, 3.0, 1.0, "a")], "events[0] must be"),
])
def test_check_event_list_refuses_what_is_no_list_of_events(events, words):
    with pytest.raises(ValueError) as exc:
        s.check_event_list("events", events)
    assert str(exc.value).startswith(words), str(exc.value)


def test_check_event_list_takes_an_event_still_flagging_at_the_end():
    e = Event(1.0, 2.0, math.inf, 1.0, "a")
    assert s.check_event_list("events", (e,)) == [e]


@pytest.mark.parametrize("bad", [{}, "abc", None])
def test_score_and_trial_outcome_refuse_what_is_no_run(bad):  # review 35d D37's class
    for call in (lambda: s.score(bad), lambda: s.trial_outcome(bad)):
        with pytest.raises(ValueError, match=r"^ft must be a FaultTolerantRun \(the result of "
                                             r"run_fault_tolerant\), got "):
            call()


def test_an_edge_value_of_a_fault_list_or_an_event_list_is_refused_by_name():
    """Issue 35 (review 35h): ``check_armed`` took a bool for every argument (``faults=True``
    a TypeError), and a 0-d array for a list was numpy's 'iteration over a 0-d array'."""
    import numpy as np

    sc = scenarios.MarsScenario(days=0.05)
    faults = s.parse_faults("uv.range:step:25000@1000+100", sc)
    with pytest.raises(ValueError, match=r"^faults must be a sequence of Fault, got bool True"):
        s.check_armed(True, 600.0, sc)
    with pytest.raises(ValueError, match=r"^faults\[0\] must be a Fault, got 1\.0$"):
        s.check_armed([1.0], 600.0, sc)
    with pytest.raises(ValueError, match=r"^faults must be a sequence of Fault, got array\(1\.\)$"):
        s.check_armed(np.array(1.0), 600.0, sc)
    with pytest.raises(ValueError, match=r"^arm_s must be a real number in \[0, 3.1536e\+07\], got True"):
        s.check_armed(faults, True, sc)
    with pytest.raises(ValueError, match=r"^scenario must be a MarsScenario, got list \[\]"):
        s.check_armed(faults, 600.0, [])
    with pytest.raises(ValueError, match=r"^faults must be a sequence of Fault, got array\(1\.\)$"):
        s.score_faults(np.array(1.0), {})
    with pytest.raises(ValueError, match=r"^isolations must be a list of dicts"):
        s.score_faults([], {}, np.array(1.0))
    with pytest.raises(ValueError, match=r"^events must be a list of detection Events"):
        s.check_event_list("events", np.array(1.0))
    with pytest.raises(ValueError, match=r"^name must be text \(a str\), got True"):
        s.check_event_list(True, [])
    assert s.check_event_list("events", []) == []  # no alarm: a valid list


@pytest.mark.parametrize(("faults", "kw", "words"), [
    ([Fault("xnav", "step", 1e-5, 1000.0, 100.0, 0)], {},
     r"^faults\[0\]: sensor 'xnav' is not in this run \(its subsystems: uv, cns\)"),
    ([Fault("uv", "step", 1.0, 1000.0, 10.0, 0), Fault("gps", "step", 1.0, 1000.0, 100.0)], {},
     r"^faults\[1\]: sensor 'gps' is not in this run"),
    ([Fault("uv", "step", 1.0, 1000.0, 100.0, 9)], {},
     r"^faults\[0\]: component must be in \[0, 3\] for sensor 'uv' \(range, ux, uy, uz\), got 9"),
    ([Fault("uv", "step", 1.0, 1000.0, 100.0, 9)] * 2, {},   # before the repeat (an IndexError)
     r"^faults\[0\]: component must be in \[0, 3\]"),
    ([Fault("uv", "step", 1.0, 1000.0, 100.0, 0)], {"train_days": 1.0},
     r"^train_days must be a real number in \(0, 0.05\), got 1.0"),
])
def test_check_schedule_is_the_runs_check(faults, kw, words):
    """Review 35j (5) 14: a fault on a subsystem the run lacks, an unknown sensor, a component out
    of range and a training span longer than the run were returned as fine."""
    sc = scenarios.MarsScenario(days=0.05, subsystems=("uv", "cns"))
    with pytest.raises(ValueError, match=words):
        s.check_schedule(faults, sc, **kw)


def test_check_schedule_names_days_when_the_default_training_span_is_too_short():
    """Review 35j (3) 7: the left-out train_days was named; the run's days is at fault. The
    suggestion is rounded up (0.0247 was itself too short), and a fault's own problem comes first."""
    with pytest.raises(ValueError, match=r"^days = 0.02 is too short for the combined detector: "
                                         r".* run at least 0.0248 days, or give train_days >= 0.0124"):
        s.check_schedule([], scenarios.MarsScenario(days=0.02))
    assert s.check_schedule([], scenarios.MarsScenario(days=0.0248)) == []
    with pytest.raises(ValueError, match=r"^faults: .* outside this run"):
        s.check_schedule([Fault("uv", "step", 1.0, 1e6, 10.0, 0)], scenarios.MarsScenario(days=0.02))
    with pytest.raises(ValueError, match=r"^train_days = 0.01 days gives the uv wavelet detector 287"):
        s.check_schedule([], scenarios.MarsScenario(days=0.05), "wavelet", 0.01)
    # chi2 and none train nothing: the short default span is no matter, a given one is ignored
    assert s.check_schedule([], scenarios.MarsScenario(days=0.02), "chi2") == []
    assert s.check_schedule([], scenarios.MarsScenario(days=0.05), "none", 0.01) == []


@pytest.mark.parametrize(("events", "isolations", "words"), [
    ({"gps": []}, (), r"^events\['gps'\]: 'gps' is not a sensor"),
    ({"uv": []}, [{"sensor": "uv", "out": 1200.0, "back": 1100.0}],
     r"^isolations\[0\]\['back'\] must come after its out \(1200 s\)"),
    ({"uv": []}, [{"sensor": "uv", "out": 1200.0, "back": 1200.0}], r"^isolations\[0\]\['back'\]"),
    ({"uv": []}, [{"sensor": "gps", "out": 1200.0, "back": None}], r"^isolations\[0\]\['sensor'\]"),
    ({"uv": []}, [{"sensor": "uv", "out": math.nan, "back": None}], r"^isolations\[0\]\['out'\]"),
])
def test_score_faults_refuses_what_it_would_not_score(events, isolations, words):
    """Review 35j (5) 15: the events of an unknown sensor were ignored; an isolation back before
    it went out was taken."""
    fs = [Fault("uv", "step", 25000.0, 1000.0, 100.0, 0)]
    with pytest.raises(ValueError, match=words):
        s.score_faults(fs, events, isolations, span=4320.0)
    assert s.score_faults(fs, {"uv": []}, [{"sensor": "uv", "out": 900.0, "back": None}],
                          span=4320.0)["faults"][0]["out_at_onset"]


def test_check_event_list_refuses_an_event_out_of_order():
    """Review 35j (5) 16: merge_events took an Event ending before its onset."""
    from xnavlab.core.detection import Event

    for ev in (Event(5.0, 2.0, 6.0, 1.0, "a"), Event(1.0, 2.0, 1.5, 1.0, "a")):
        with pytest.raises(ValueError, match=r"^events\[0\] must have onset <= end <= cleared"):
            s.check_event_list("events", [ev])


def test_parse_faults_leads_with_spec():
    """Review 35k (3) 16: parse_faults('x') said "bad fault item 'x': ..." without naming spec;
    a spec that is no string (or blank) is refused naming 'paper' too."""
    with pytest.raises(ValueError, match=r"^spec: bad fault item 'x': expected SENSOR"):
        s.parse_faults("x")
    for bad in (None, "", "  ", 5, ["paper"]):
        with pytest.raises(ValueError, match=r"^spec must be 'paper' or a fault spec SENSOR"):
            s.parse_faults(bad)


_IN_RANGE = " must be a real number in \\[0.001, 1000\\]"


@pytest.mark.parametrize("kw, lead", [
    (dict(cns_step_sigma=5e-324), "cns_step_sigma" + _IN_RANGE),
    (dict(uv_step_sigma=1e-4), "uv_step_sigma" + _IN_RANGE),
    (dict(scenario=scenarios.MarsScenario(sigma_horizon_deg=5e-324)),
     "scenario.sigma_horizon_deg \\(5e-324\\) times cns_step_sigma")])
def test_paper_schedule_refuses_a_step_size_under_its_own_name(kw, lead):
    """Review 35l (3) 3: cns_step_sigma=5e-324 underflowed to a zero step, refused as the Fault's
    "magnitude of a step fault", and the stated range (0, 1000] was not the real one."""
    with pytest.raises(ValueError, match=f"^{lead}"):
        s.paper_schedule(**kw)
    assert len(s.paper_schedule(uv_step_sigma=s.MIN_STEP_SIGMA, cns_step_sigma=s.MIN_STEP_SIGMA)) == 16


@pytest.mark.parametrize(("spec", "words"), [
    ("uv.range:stuck:5@20000+3000", "magnitude of a stuck fault must be 0 (the output freezes at "
                                    "its last fault-free value: a size would go unused), got 5.0"),
    ("uv.range:spike:5@20000+3000", "a spike fault's DURATION must be 0 (it acts on one sample: a "
                                    "duration would go unused), got 3000"),
    ("uv.range:spike:5@20000+inf", "a spike fault's DURATION must be 0"),
])
def test_a_number_a_fault_kind_does_not_use_is_refused(spec, words):
    """Review 35m (6) 5: run mars --help said 'stuck (magnitude ignored)' and 'Refused: a zero
    MAGNITUDE', and any stuck magnitude or spike duration ran unused: each number is used or
    refused (0 is the one value of an unused number)."""
    sc = scenarios.MarsScenario(days=0.5)
    with pytest.raises(ValueError) as info:
        s.parse_faults(spec, sc)
    assert str(info.value).startswith(f"spec: bad fault item {spec!r}: {words}")
    for ok in ("uv.range:stuck:0@20000+3000", "uv.range:spike:5@20000+0"):
        assert len(s.parse_faults(ok, sc)) == 1
