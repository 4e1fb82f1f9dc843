"""Fault schedules of the Mars run (xnavlab.mars.schedules): the components a spec may name, the
paper's schedule, the command line's spec, the check that refuses a fault a run cannot use, and
the matching of detections to faults."""

import math

import pytest

from xnavlab.core.detection import Event
from xnavlab.core.faults import Fault
from xnavlab.mars import scenarios
from xnavlab.mars import schedules as s


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
    xnav = [Fault("xnav", "step", 1e-5, 3600.0, 100.0)]          # XNAV does not train
    assert s.check_schedule(xnav, sc, detector="wavelet")


def test_check_schedule_refuses_a_fault_before_the_filter_settles_for_the_combined_detector():
    sc = scenarios.MarsScenario(days=1)
    with pytest.raises(ValueError, match="before the filter has settled"):
        s.check_schedule([Fault("uv", "step", 1.0, s.EARLIEST_ONSET_S - 1.0, 10.0)], sc)
    assert s.check_schedule([Fault("uv", "step", 1.0, s.EARLIEST_ONSET_S, 10.0)], sc)


def test_fault_detection_delays_count_a_detection_until_the_window_after_the_end():
    f = Fault("uv", "ramp", 1.0, onset=100.0, duration=50.0)

    def delay(onset, window=None):
        events = {"uv": [Event(onset, onset + 1.0, onset + 2.0, 2.0, "level 1")]}
        return s.fault_detection_delays([f], events, window)[0]["delay"]

    assert delay(130.0) == 30.0
    assert delay(50.0) == math.inf                                    # before the onset
    assert delay(150.0 + s.MATCH_WINDOW["uv"] - 1.0) == s.MATCH_WINDOW["uv"] + 49.0
    assert delay(150.0 + s.MATCH_WINDOW["uv"]) == math.inf
    assert delay(160.0, window=5.0) == math.inf and delay(154.0, window=5.0) == 54.0
    assert delay(154.0, window={"uv": 5.0}) == 54.0
    assert s.fault_detection_delays([f], {})[0]["detected_onset"] == math.inf
    with pytest.raises(ValueError, match="^window"):
        delay(130.0, window=-1.0)
