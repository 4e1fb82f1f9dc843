"""Fault-tolerant federated navigation: schedule, detection, isolation, rejoining, JSON."""

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy import stats

from xnavlab.core.detection import Event
from xnavlab.core.faults import Fault
from xnavlab.mars.faults import fault_tolerance as ft
from xnavlab.mars.navigation import plots as mars_plots
from xnavlab.mars.navigation import scenarios

DAYS = 1.0
TRAIN = 0.4          # days of fault-free training of the UV/CNS wavelet detectors
# onsets the paper does not use, one per sensor and kind
HAND = [
    Fault("uv", "step", 30000.0, onset=45123.0, duration=4000.0, component=0),
    Fault("xnav", "step", 1.0e-5, onset=61234.0, duration=3000.0),
    Fault("cns", "step", math.radians(0.4), onset=74321.0, duration=3000.0),
]


@pytest.fixture(scope="module")
def inputs():
    return scenarios.prepare(days=DAYS)


@pytest.fixture(scope="module")
def runs(inputs):
    return {d: ft.run_fault_tolerant(faults=HAND, detector=d, inputs=inputs, train_days=TRAIN)
            for d in ft.DETECTORS}


@pytest.fixture(scope="module")
def clean(inputs):
    return scenarios.run(inputs=inputs)


def test_paper_schedule_uses_the_paper_onsets():
    fs = ft.paper_schedule()
    for s, onsets in ft.PAPER_ONSETS.items():
        assert sorted(f.onset for f in fs if f.sensor == s) == sorted(onsets)
    assert all(f.duration == 5000.0 for f in fs)
    uv = [f for f in fs if f.sensor == "uv"]
    assert all(f.component == 0 and f.magnitude == 25000.0 for f in uv)


@pytest.mark.parametrize("kw", [dict(uv_step_sigma=0.0), dict(cns_duration=2e5),
                                dict(xnav_ramp=1.0)])
def test_paper_schedule_rejects_bad_arguments(kw):
    name = next(iter(kw))
    with pytest.raises(ValueError, match=name):
        ft.paper_schedule(**kw)


def test_parse_faults_paper_and_spec():
    assert len(ft.parse_faults("paper")) == 16
    f, = ft.parse_faults("xnav.B1937:ramp:2e-9@500000+5000")
    assert (f.sensor, f.component, f.kind) == ("xnav", 1, "ramp")
    with pytest.raises(ValueError, match="bad fault item 'cns.angle7"):
        ft.parse_faults("cns.angle7:step:1@1+1")


def test_no_detector_lets_faults_in(runs, clean):
    bad = runs["none"].run.metrics(0.3)["position_error_max_m"]
    ok = clean.metrics(0.3)["position_error_max_m"]
    assert bad > 5 * ok
    assert runs["none"].detections == [] and not runs["none"].isolated.any()


@pytest.mark.parametrize("detector", ["wavelet", "chi2", "combined"])
def test_hand_made_schedule_is_detected_and_isolated(runs, clean, detector):
    r = runs[detector]
    intervals = r.isolation_intervals()
    for f, d in zip(HAND, r.delays(), strict=True):
        # detected, or already out (an earlier false alarm) and kept out through the fault
        kept_out = any(iv["sensor"] == f.sensor and iv["out"] <= f.onset
                       and (iv["back"] is None or iv["back"] >= f.end) for iv in intervals)
        assert d["delay"] < 600.0 or kept_out, d
    for f in HAND:
        hit = [iv for iv in intervals if iv["sensor"] == f.sensor
               and iv["out"] <= f.onset + 600.0 and iv["back"] is not None
               and iv["back"] >= f.end]
        assert hit, (f, intervals)
    # every subsystem is back at the end, and the fused error stays near the fault-free one
    assert not r.isolated[-1].any()
    m, m0 = r.run.metrics(0.3), clean.metrics(0.3)
    assert m["position_error_m"] < 1.5 * m0["position_error_m"]
    assert m["position_error_max_m"] < 3 * m0["position_error_max_m"]


def test_isolated_subsystem_does_time_updates_only(runs):
    r = runs["wavelet"]
    flags, iso = r.run.flags, r.isolated
    assert np.all(flags[iso & (flags > 0)] == 3)          # switched out, never updated
    assert np.all(flags[~iso & (flags > 0)] == 1)         # no gate in wavelet mode


def test_fault_free_wavelet_run_matches_the_plain_run(inputs, clean):
    r = ft.run_fault_tolerant(faults=[], detector="wavelet", inputs=inputs, train_days=TRAIN)
    if not r.isolated.any():
        # the same filter: equal to rounding, whose size depends on the BLAS kernels
        # (1.0e-6 m, 1.4e-11 relative, on OpenBLAS's Sandybridge family): 1e-9 relative
        np.testing.assert_allclose(r.run.x, clean.x, rtol=1e-9, atol=1e-6)
    assert r.isolated.mean() < 0.01


def test_summary_lists_faults_and_detections(runs):
    s = runs["wavelet"].summary(0.3)
    assert len(s["faults"]) == 3 and s["faults"][0]["spec"].startswith("uv.range:step")
    assert s["detections"] and set(s["detections"][0]) == {"sensor", "detected_onset",
                                                          "detected_end", "detector"}
    assert {"position_error_m", "velocity_error_mps", "detector", "isolations"} <= set(s)


def test_fault_inside_the_training_span_is_refused(inputs):
    with pytest.raises(ValueError, match="starts at 100 s, inside the .* wavelet detector trains"):
        ft.run_fault_tolerant(faults=[Fault("uv", "step", 1e4, 100.0, 100.0)], inputs=inputs,
                              detector="wavelet", train_days=TRAIN)


@pytest.mark.parametrize("kw,name", [(dict(detector="kalman"), "detector"),
                                     (dict(pfa=0.0), "pfa"), (dict(check_every=0), "check_every"),
                                     (dict(readmit_samples={"uv": 0}), "readmit_samples"),
                                     (dict(readmit_samples=0), "^readmit_samples must be a dict"),
                                     (dict(readmit_samples=[("uv", 4)]), "^readmit_samples must")])
def test_bad_arguments_name_the_parameter(inputs, kw, name):
    with pytest.raises(ValueError, match=name):
        ft.run_fault_tolerant(faults=[], inputs=inputs, train_days=TRAIN, **kw)


def test_inject_inputs_takes_a_list_of_faults_and_names_anything_else(inputs):
    with pytest.raises(ValueError, match=r"^faults must be a sequence of Fault, got the string"):
        ft.inject_inputs(inputs, "uv.range:step:1e3@1000+10")
    with pytest.raises(ValueError, match=r"^faults must be a sequence of Fault, got one Fault"):
        ft.inject_inputs(inputs, Fault("uv", "step", 1e3, 1000.0, 10.0))


def test_unknown_sensor_in_faults_is_refused():
    inp = scenarios.prepare(days=0.05, subsystems=("uv", "cns"))
    with pytest.raises(ValueError, match="xnav"):
        ft.run_fault_tolerant(faults=[Fault("xnav", "step", 1e-5, 10.0, 10.0)], inputs=inp,
                              detector="none")


def test_naive_rejoining_lets_the_biased_stretch_in(inputs):
    f = Fault("uv", "step", 30000.0, onset=52000.0, duration=4000.0, component=0)
    kw = dict(faults=[f], detector="wavelet", inputs=inputs, train_days=TRAIN)
    rule = ft.run_fault_tolerant(**kw).isolation_intervals()
    naive = ft.run_fault_tolerant(readmit="clear", **kw).isolation_intervals()
    assert len(rule) == 1 and rule[0]["back"] > f.end            # out through the whole step
    assert len(naive) == 2 and naive[0]["back"] < f.end          # back in while still biased
    with pytest.raises(ValueError, match="readmit"):
        ft.run_fault_tolerant(readmit="clear", **{**kw, "detector": "chi2"})


def test_a_cns_onset_detected_right_after_an_xnav_epoch_stays_out_while_flagged(inputs):
    # the paper's onsets are multiples of the 500-s XNAV interval: a CNS step detected at its
    # first sample after such an onset lands on the epoch right after an XNAV measurement
    # (where the wavelet loop may not open a chunk); it must leave the fusion there and stay
    # out while its detector flags, as at any other epoch (it was back in 3 s after)
    sc = inputs.scenario
    f = Fault("cns", "step", math.radians(0.4), onset=76500.0, duration=3000.0)
    r = ft.run_fault_tolerant(faults=[f], detector="wavelet", inputs=inputs, train_days=TRAIN)
    t = r.run.times - r.run.times[0]
    first = r.events["cns"][0].onset
    assert f.onset % sc.dt_xnav == 0.0 and first == f.onset + sc.dt_cns      # the case
    i = sc.subsystems.index("cns")
    det = r.detection_data["cns"]
    flagged = np.searchsorted(t, det["t"][det["faulty"]])
    assert flagged.size and r.isolated[flagged, i].all()   # out whenever its detector flags
    (iv,) = r.isolation_intervals()
    assert iv["sensor"] == "cns" and iv["out"] == first and iv["back"] > f.end


def test_plot_fault_response_is_a_figure():
    fig = mars_plots.plot_fault_response(8.0, "uv", days=0.5)
    assert "uv step of 8 sigma" in fig.axes[0].get_title()
    with pytest.raises(ValueError, match="size_sigma"):
        mars_plots.plot_fault_response(0.0)


def test_speculative_chunks_equal_deciding_at_every_xnav_epoch(inputs, monkeypatch):
    kw = dict(faults=HAND, detector="wavelet", inputs=inputs, train_days=TRAIN)
    ref = ft.run_fault_tolerant(**kw)
    monkeypatch.setattr(ft._Loop, "HORIZON", 40)        # shorter than the 167-epoch XNAV gap
    short = ft.run_fault_tolerant(**kw)
    assert np.array_equal(short.isolated, ref.isolated)
    np.testing.assert_allclose(short.run.x, ref.run.x, rtol=1e-12, atol=0)
    assert short.detections == ref.detections


# ---------------------------------- the combined detector: delays and accuracy on random faults


def _random_schedule(rng, days, sc):
    """3 faults sized like the paper's at random onsets, sensors and kinds, far apart."""
    faults = []
    t = 0.5 * days * 86400.0
    for _ in range(3):
        t += float(rng.uniform(3000.0, 9000.0))
        sensor = str(rng.choice(["uv", "cns", "xnav"]))
        kind = str(rng.choice(["step", "ramp", "noise", "stuck"]))
        sig = ft.sensor_sigma(sensor, sc)
        comp = 0 if sensor == "uv" and kind != "stuck" else None
        onset = round(t / 3.0) * 3.0 + 1.0
        if kind == "step":
            f = Fault(sensor, "step", float(rng.uniform(5.0, 8.0)) * sig, onset,
                      float(rng.uniform(1500.0, 5000.0)), comp)
        elif kind == "ramp":            # reaches 5 sigma within 3000-6000 s, lasts that long
            T = float(rng.uniform(3000.0, 6000.0))
            f = Fault(sensor, "ramp", 5.0 * sig / T, onset, T, comp)
        elif kind == "noise":
            r = float(rng.uniform(3.0, 4.0))
            f = Fault(sensor, "noise", sig * math.sqrt(r * r - 1.0), onset,
                      float(rng.uniform(3000.0, 5000.0)), comp)
        else:
            f = Fault(sensor, "stuck", 0.0, onset, float(rng.uniform(1500.0, 5000.0)), None)
        faults.append(f)
        t = f.end + 20000.0        # faults far apart: each is judged on its own
    return faults


@pytest.mark.parametrize("seed", [11, 12, 13, 14])
def test_combined_acceptance_on_random_schedules(seed):
    """The combined detector finds steps and stuck outputs within 1500 s, drifts and noise within
    4000 s, and keeps the fused RMS at most 1.5 times the fault-free run of the same seed."""
    rng = np.random.default_rng(seed)
    days = 2.0
    inp = scenarios.prepare(days=days, seed=seed)
    faults = _random_schedule(rng, days, inp.scenario)
    r = ft.run_fault_tolerant(faults=faults, detector="combined", inputs=inp, train_days=0.5,
                              rng=rng)
    for f, d in zip(faults, r.delays(), strict=True):
        limit = 1500.0 if f.kind in ("step", "stuck") else 4000.0
        assert d["delay"] <= limit, (f, d)
    ref = scenarios.run(inputs=inp).metrics(0.5)["position_error_m"]
    assert r.run.metrics(0.5)["position_error_m"] <= 1.5 * ref


def _early_fault(rng, sc):
    """A step (5-8 sigma), a drift (5 sigma in 3000-6000 s) or a stuck output, on any
    subsystem, starting between 600 s and the end of the first day's training span."""
    sensor = str(rng.choice(["uv", "cns", "xnav"]))
    kind = str(rng.choice(["step", "ramp", "stuck"]))
    sig = ft.sensor_sigma(sensor, sc)
    comp = 0 if sensor == "uv" and kind != "stuck" else None
    onset = float(rng.uniform(600.0, 40000.0))
    if kind == "step":
        return Fault(sensor, "step", float(rng.uniform(5.0, 8.0)) * sig, onset, 4000.0, comp)
    if kind == "ramp":
        T = float(rng.uniform(3000.0, 6000.0))
        return Fault(sensor, "ramp", 5.0 * sig / T, onset, T, comp)
    return Fault(sensor, "stuck", 0.0, onset, 4000.0, None)


@pytest.mark.parametrize("seed", [21, 22, 23, 24])
def test_faults_from_600_s_are_found_while_the_wavelets_train(seed):
    """Faults in the first hours, inside the wavelets' training span, are found by the
    innovation tests as fast as later ones (steps and stuck outputs within 1500 s, drifts
    within 4000 s, or their subsystem already out of the fusion at the onset), and the fused
    RMS stays within 1.5 times the fault-free run of the same seed."""
    rng = np.random.default_rng(seed)
    inp = scenarios.prepare(days=1.0, seed=seed)
    ref = scenarios.run(inputs=inp).metrics()["position_error_m"]
    for _ in range(3):
        f = _early_fault(rng, inp.scenario)
        r = ft.run_fault_tolerant(faults=[f], detector="combined", inputs=inp, rng=rng)
        sc = r.score()["faults"][0]
        limit = 1500.0 if f.kind in ("step", "stuck") else 4000.0
        assert sc["out_at_onset"] or (sc["detected"] and sc["delay_s"] <= limit), (f, sc)
        assert r.run.metrics()["position_error_m"] <= 1.5 * ref, f


def test_a_fault_before_the_filter_settles_is_refused_and_the_training_is_robust(inputs):
    with pytest.raises(ValueError, match="before the filter has settled"):
        ft.run_fault_tolerant(faults=[Fault("uv", "step", 3e4, 300.0, 1000.0, 0)],
                              detector="combined", inputs=inputs, train_days=TRAIN)
    # a step inside the training span moves the wavelet's MAD noise levels by little
    from xnavlab.core.detection import WaveletDetector

    x = inputs.z["uv"][:, 0]
    n = int(TRAIN * 86400.0 / inputs.scenario.dt_uv)
    clean, faulty = WaveletDetector(), WaveletDetector()
    clean.train(x[:n])
    bad = x[:n].copy()
    bad[n // 3:n // 3 + 1500] += 6.0 * inputs.scenario.sigma_range_m
    faulty.train(bad)
    assert np.allclose(faulty.sigma, clean.sigma, rtol=0.1)


def test_combined_fault_free_false_alarms_within_the_design(inputs):
    # one fault-free day at 1 false alarm per subsystem per day: 3 expected (30 days: the
    # benchmark, 81 measured against 90 designed); a stated loose bound for one day
    r = ft.run_fault_tolerant(faults=[], detector="combined", inputs=inputs, train_days=TRAIN)
    n = len(r.isolation_intervals())
    assert n <= stats.poisson.ppf(0.999, 3.0)
    assert r.isolated.mean() < 0.02


def test_combined_readmits_xnav_soon_after_its_fault_ends(inputs):
    f = Fault("xnav", "step", 1.0e-5, onset=50001.0, duration=3000.0)
    back = {}
    for det in ("wavelet", "combined"):
        r = ft.run_fault_tolerant(faults=[f], detector=det, inputs=inputs, train_days=TRAIN)
        ivs = [iv for iv in r.isolation_intervals() if iv["sensor"] == "xnav"
               and iv["out"] <= f.end and iv["back"] is not None and iv["back"] >= f.end]
        assert ivs, (det, r.isolation_intervals())
        back[det] = ivs[0]["back"] - f.end
    # combined: 4 clean XNAV samples (2000 s) plus the grid; the wavelet waits for its window
    assert back["combined"] <= 2500.0
    assert back["wavelet"] > 3 * back["combined"]


def test_combined_result_does_not_depend_on_the_kernel_calls(inputs, monkeypatch):
    # the detector runs inside the kernel, which stops where a decision is taken: cutting
    # the run into short calls changes nothing, to the bit
    faults = HAND + [Fault("cns", "ramp", math.radians(0.25) / 6000.0, onset=35001.0,
                           duration=6000.0)]
    kw = dict(faults=faults, detector="combined", inputs=inputs, train_days=TRAIN)
    ref = ft.run_fault_tolerant(**kw)
    monkeypatch.setattr(ft._Loop, "HORIZON_COMBINED", 97)
    short = ft.run_fault_tolerant(**kw)
    assert np.array_equal(short.isolated, ref.isolated)
    assert np.array_equal(short.run.x, ref.run.x)
    assert short.detections == ref.detections


@pytest.mark.parametrize("sensor", ["uv", "cns", "xnav"])
def test_compiled_monitor_alarms_where_the_reference_monitor_does(inputs, sensor):
    """The kernel's innovation parts against :class:`InnovationMonitor` fed with the kernel's
    own whitened innovations, segment by segment between re-admissions (adaptive scale, a
    high design rate for many alarms; XNAV's innovation wavelet and the raw UV/CNS wavelets
    are the other isolations, after which the monitor simply restarts)."""
    from xnavlab.core.detection import InnovationMonitor

    r = ft.run_fault_tolerant(faults=[], detector="combined", inputs=inputs, train_days=TRAIN,
                              rate_per_day=40.0, arm_s=600.0)
    data = r.detection_data[sensor]
    i = inputs.scenario.subsystems.index(sensor)
    t = data["t"]
    y = data["innovations"]
    iso = r.isolated[np.searchsorted(inputs.times, inputs.t_meas[sensor]), i]
    kernel_alarms = sorted(e.onset for e in data["innovation_events"]
                           if not e.test.startswith("wavelet"))
    alarmed = [e.onset for e in data["innovation_events"]]
    mon = InnovationMonitor(data["design"])
    ref_alarms, start = [], int(np.searchsorted(t, 600.0))
    backs = [iv["back"] for iv in r.isolation_intervals() if iv["sensor"] == sensor]
    outs = [iv["out"] for iv in r.isolation_intervals() if iv["sensor"] == sensor]
    for out, back in zip(outs + [math.inf], backs + [None], strict=True):
        stop = int(np.searchsorted(t, out, side="right"))     # the segment up to the isolation
        seg = np.arange(start, stop)
        seg = seg[~iso[seg] | np.isin(t[seg], alarmed)]   # the alarming sample was judged
        a = mon.process(t[seg], y[seg])
        if a >= 0:
            ref_alarms.append(float(t[seg[a]]))
        if back is None:
            break
        mon.readmitted()
        start = stop
    assert len(kernel_alarms) >= 3
    assert ref_alarms == kernel_alarms
    np.testing.assert_array_equal(mon.scale, data["scale"])


@given(st.lists(st.floats(-1e300, 1e300), min_size=1, max_size=300)
       | st.lists(st.sampled_from([0.0, -1.0, 1.0, 2.5, -2.5]), min_size=1, max_size=300))
def test_kernel_median_is_numpys(values):
    """The adaptive scale's median inside the kernel (a radix selection) is numpy's, exactly."""
    from xnavlab.mars.kernel import kernel_watch

    x = np.array(values)
    med, cnt = np.empty(x.size), np.empty(8192, dtype=np.int64)
    assert kernel_watch._median_abs(x, x.size, med, cnt) == np.median(np.abs(x))


def test_run_mars_cli_defaults_to_combined_with_faults(capsys):
    import argparse
    import json

    from xnavlab.cli import runners

    parser = argparse.ArgumentParser()
    runners.configure_mars(parser)
    args = parser.parse_args(["--days", "0.3", "--json", "--faults",
                              "uv.range:step:30000@15001+1500"])
    assert runners.execute_mars(args) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["detector"] == "combined"
    assert out["detections"] and out["detections"][0]["detected_onset"] - 15001.0 < 60.0


# ------------------------------------------------------------------ scored fault runs


@pytest.mark.parametrize("detector", ["wavelet", "chi2", "combined"])
def test_score_matches_every_detection_or_calls_it_a_false_alarm(runs, detector):
    run = runs[detector]
    sc = run.score()
    assert len(sc["faults"]) == len(HAND)
    assert len(sc["detections"]) == len(run.detections)
    for d in sc["detections"]:
        assert d["false_alarm"] == (d["fault"] is None) == (d["match"] == "false alarm")
    for f, delay in zip(sc["faults"], run.delays(), strict=True):
        assert f["detected"] == np.isfinite(delay["delay"]) == (f["status"] == "detected")
        assert (f["delay_s"] is None) == (not f["detected"])
        assert (f["late_s"] is None) == (f["status"] != "late")
        assert f["out_after_end_s"] is None or f["out_after_end_s"] >= 0.0
    for s, c in sc["counts"].items():
        assert c["detected"] + c["late"] + c["missed"] == c["faults"] == sum(f.sensor == s
                                                                          for f in HAND)
        assert c["false_alarms"] <= c["alarms"]
    err = sc["fused_error"]
    assert err["inside_faults_m"] > 0.0 and err["outside_faults_m"] > 0.0
    assert run.summary()["score"]["counts"] == sc["counts"]


def test_the_steps_are_scored_detected_with_their_delay_or_already_out(runs):
    """A step is found within 1500 s, unless its subsystem was out of the fusion at its onset
    (here a false alarm of XNAV's variance part at 60000 s keeps XNAV out over its step)."""
    sc = runs["combined"].score()
    steps = [f for f in sc["faults"] if f["kind"] == "step"]
    assert steps and all(f["out_at_onset"] or (f["detected"] and 0.0 <= f["delay_s"] <= 1500.0)
                         for f in steps)
    assert sum(f["detected"] for f in steps) >= 2


def test_save_npz_keeps_the_isolation_mask_and_the_detector_series(runs, tmp_path):
    run = runs["combined"]
    run.save_npz(tmp_path / "r.npz")
    with np.load(tmp_path / "r.npz") as z:
        np.testing.assert_array_equal(z["isolated"], run.isolated)
        assert str(z["detector"]) == "combined" and "uv.range:step" in str(z["faults"])
        assert any(k.startswith("det_uv_") for k in z.files)


def test_plot_fault_response_with_kept_inputs_draws_what_fresh_inputs_draw():
    """The slider keeps the fault-free inputs between moves; each curve is a fresh run's."""
    mars_plots.plot_fault_response(3.0, "uv", "step", days=0.5)      # keeps the inputs
    ax = mars_plots.plot_fault_response(8.0, "cns", "ramp", days=0.5).axes[0]
    kept = [line.get_ydata() for line in ax.get_lines()]
    onset, duration = round(0.6 * 0.5 * 86400.0) + 1.0, 4000.0
    fault = Fault("cns", "ramp", 8.0 * ft.sensor_sigma("cns") / duration, onset, duration, None)
    inputs = scenarios.prepare(days=0.5, seed=0)
    assert len(kept) == len(ft.DETECTORS)
    for det, curve in zip(ft.DETECTORS, kept, strict=True):
        r = ft.run_fault_tolerant(faults=[fault], detector=det, inputs=inputs, train_days=0.2)
        assert np.array_equal(curve, r.run.position_error())


@pytest.mark.parametrize(("days", "kw", "words"), [
    (0.03, {"arm_s": 3000.0}, r"^arm_s \(3000 s: .*\) must be shorter than the run, days = "
                              r"0.03 \(2592 s\)"),
    (0.01, {}, r"^days = 0.01 is too short for the combined detector: its uv wavelet trains on "
               r".* 0.005 days \(143 samples\) .* run at least 0.0248 days"),  # review 35j (3) 7
    (0.05, {"train_days": 0.01}, r"^train_days = 0.01 days .* give train_days >= 0.0124"),
])
def test_a_run_too_short_for_the_detector_names_days_not_an_internal_setting(days, kw, words):
    # issue 35: these named arm_s's range [0, 432) and "train_days must give at least 356 ..."
    # for settings the user never gave
    with pytest.raises(ValueError, match=words):
        ft.run_fault_tolerant(scenarios.MarsScenario(days=days), [], "combined", **kw)


def test_adaptive_must_be_a_bool():  # review 35d D36
    with pytest.raises(ValueError, match="adaptive must be True or False, got .no."):
        ft.run_fault_tolerant(scenarios.MarsScenario(days=0.02), adaptive="no")


@pytest.mark.parametrize(("detector", "kw", "words"), [
    ("chi2", {"pfa": 0.5}, "pfa = 0.5 is unused with detector 'chi2': only the wavelet detector"),
    ("wavelet", {"alpha": 0.5}, "alpha = 0.5 is unused with detector 'wavelet'"),
    ("chi2", {"arm_s": 100.0}, "arm_s = 100.0 is unused with detector 'chi2'"),
    ("chi2", {"adaptive": False}, "adaptive = False is unused with detector 'chi2'"),
    ("none", {"rate_per_day": 5.0}, "rate_per_day = 5.0 is unused with detector 'none'"),
])
def test_a_setting_of_another_detector_is_refused(detector, kw, words):
    # review 35d D36: these ran without a word (a scenario file refuses them)
    with pytest.raises(ValueError) as info:
        ft.run_fault_tolerant(scenarios.MarsScenario(days=0.02), [], detector, **kw)
    assert words in str(info.value)


@pytest.mark.parametrize(("events", "words"), [
    ("abc", "events must be a list of detection Events"),  # review 35d D37: AttributeError
    ([("uv", math.nan)], "events[0] must be a detection Event"),
    (None, "events must be a list of detection Events"),
    ([Event(1.0, 2.0, 5.0, None, "a")], "events[0] must be a detection Event"),  # review 35e
    ([Event(1.0, 2.0, 5.0, math.nan, "a")], "events[0] must be a detection Event"),
])
def test_merge_events_refuses_what_is_no_list_of_events(events, words):
    with pytest.raises(ValueError) as exc:
        ft.merge_events(events)
    assert str(exc.value).startswith(words) and len(str(exc.value).splitlines()) == 1


@pytest.mark.parametrize("bad", [None, {}, "inputs"])
def test_inject_inputs_refuses_what_is_no_inputs(bad):  # review 35d D37: AttributeError
    with pytest.raises(ValueError, match=r"^inputs must be an Inputs from scenarios.prepare\(\), "
                                         r"got "):
        ft.inject_inputs(bad, [Fault("uv", "step", 1e3, 1000.0, 10.0)])


def test_the_last_seed_runs_with_a_detector():
    """Review 35e: run mars --seed 9223372036854775807 --detector chi2 stopped on 'rng must be
    ... got 9223372036854775808' (the fault noise's seed + 1): it wraps to 0 now."""
    res = ft.run_fault_tolerant(None, [], "chi2", days=0.05, seed=2**63 - 1)
    assert res.run.scenario.seed == 2**63 - 1


def test_the_run_length_advice_for_arm_s_exceeds_the_run():
    # review 35f #9: "run at least days = 0.05" for a run of 0.05 days (a rounding)
    with pytest.raises(ValueError, match=r"run at least days = 0.0501 or lower arm_s"):
        ft.run_fault_tolerant(scenarios.MarsScenario(days=0.05), [], "combined", arm_s=4320.0)


def test_a_fault_over_before_the_detector_arms_is_refused_not_scored_missed():
    # review 35f #10: it ran and was scored "missed", though no test could see it
    sc = scenarios.MarsScenario(days=0.05)
    fault = Fault("uv", "step", 25000.0, 1000.0, 100.0, 0)
    with pytest.raises(ValueError, match=r"^faults: uv.range:step:25000@1000\+100 ends at 1100 s, "
                                         r"before the combined detector's tests arm \(arm_s = "
                                         r"2000 s\)"):
        ft.run_fault_tolerant(sc, [fault], "combined", arm_s=2000.0)


def test_a_design_rate_below_its_range_is_refused_by_name():
    # review 35f #8: 5e-324 was refused as "p must be a real number in (0, 1), got 0.0"
    from xnavlab.mars.navigation import scenario_files

    with pytest.raises(ValueError, match=r"^rate_per_day must be a real number in \[0.001, 100\]"):
        ft.run_fault_tolerant(scenarios.MarsScenario(days=0.05), [], "combined", rate_per_day=5e-324)
    text = scenario_files.dump()
    assert "rate_per_day = 1.0" in text
    for bad in (5e-324, 2e2):  # the scenario file's range is the same
        with pytest.raises(ValueError, match=r"rate_per_day must be a real number in \[0.001, 100\]"):
            scenario_files.loads(text.replace("rate_per_day = 1.0", f"rate_per_day = {bad!r}"))


def test_merge_events_refuses_a_0d_array_by_name():
    """Issue 35 (review 35h): numpy's 'iteration over a 0-d array' became a ValueError."""
    with pytest.raises(ValueError, match=r"^events must be a list of detection Events"):
        ft.merge_events(np.array(1.0))
    assert ft.merge_events([]) == []  # no alarm, nothing merged


@pytest.mark.parametrize(("call", "words"), [
    (lambda: ft.run_fault_tolerant(None, [], inputs={"a": 1}),
     r"^inputs must be an Inputs from scenarios.prepare\(\), got dict"),
    (lambda: ft.sensor_sigma("uv", "x"), r"^scenario must be a MarsScenario, got str 'x'"),
    (lambda: ft.sensor_sigma("uv", {"days": 1}), r"^scenario must be a MarsScenario, got dict"),
])
def test_an_object_parameter_of_the_wrong_kind_is_named(call, words):
    """Review 35j (1) 14-15: an AttributeError ('dict' object has no attribute 'scenario')."""
    with pytest.raises(ValueError, match=words):
        call()


def test_a_fault_with_a_bad_component_is_named_as_an_item_of_faults():
    """Review 35j (3) 6: 'component must be in [0, 3] ...' named no parameter of the call."""
    sc = scenarios.MarsScenario(days=0.05, subsystems=("uv", "cns"))
    with pytest.raises(ValueError, match=r"^faults\[0\]: component must be in \[0, 3\] for "
                                         r"sensor 'uv'"):
        ft.run_fault_tolerant(sc, [Fault("uv", "step", 1.0, 2000.0, 100.0, 9)], detector="chi2")
    with pytest.raises(ValueError, match=r"^faults\[0\]: sensor 'xnav' is not in this run"):
        ft.run_fault_tolerant(sc, [Fault("xnav", "step", 1e-5, 2000.0, 1000.0)], detector="chi2")


@pytest.fixture(scope="module")
def uv_cns_inputs():
    return scenarios.prepare(scenarios.MarsScenario(days=0.05, subsystems=("uv", "cns")))


@pytest.mark.parametrize(("detector", "kw", "words"), [
    ("chi2", {"xnav_level": 4}, r"^xnav_level = 4 is unused: the run has no xnav subsystem"),
    ("wavelet", {"xnav_holdoff": 5}, r"^xnav_holdoff = 5 is unused: the run has no xnav"),
    ("none", {"readmit_samples": {"uv": 5}}, r"^readmit_samples is unused with detector 'none'"),
    ("none", {"readmit_alpha": 0.05},
     r"^readmit_alpha = 0.05 is unused with detector 'none': only the wavelet, chi2 and combined"),
    ("none", {"check_every": 3}, r"^check_every = 3 is unused with detector 'none'"),
    ("chi2", {"readmit_samples": {"xnav": 5}},
     r"^readmit_samples\['xnav'\] is unused: the run has no xnav subsystem"),
])
def test_an_option_the_run_does_not_use_is_refused(detector, kw, words, uv_cns_inputs):
    """Review 35j (5) 2-4: xnav_level/xnav_holdoff without XNAV, the rejoining settings with no
    detector and a readmit window of a subsystem the run lacks were accepted and dropped."""
    with pytest.raises(ValueError, match=words):
        ft.run_fault_tolerant(faults=[], detector=detector, inputs=uv_cns_inputs, **kw)


def test_xnav_settings_with_a_detector_without_the_xnav_wavelet_are_refused():
    """Review 35j (5) 2: chi2 has no XNAV innovation wavelet; its defaults are taken."""
    with pytest.raises(ValueError, match=r"^xnav_level = 4 is unused: detector 'chi2' has no XNAV"):
        ft.run_fault_tolerant(scenarios.MarsScenario(days=0.05), [], "chi2", xnav_level=4)


def test_the_defaults_of_the_rejoining_settings_are_taken_with_every_detector():
    """Review 35j (5) 1-4: a refusal only for a value the user gave, never for a default (the
    command line and the scenario files pass none of these); train_days is documented as
    ignored by chi2 and none (one call serves every detector, as the trials and the book do)."""
    import inspect

    defaults = {k: v.default for k, v in inspect.signature(ft.run_fault_tolerant).parameters.items()}
    for key in ("readmit_alpha", "check_every", "xnav_level", "xnav_holdoff"):
        ft._checks.check_settings("none", {key: defaults[key]}, ("uv",))
    sc = scenarios.MarsScenario(days=0.05, subsystems=("uv", "cns"))
    r = ft.run_fault_tolerant(sc, [], "chi2", train_days=0.02, readmit_alpha=0.01, check_every=100)
    assert r.detector == "chi2"


def test_merge_events_refuses_an_event_ending_before_its_onset():
    """Review 35j (5) 16: Event(5, 2, 1, ...) was returned as it was."""
    with pytest.raises(ValueError, match=r"^events\[0\] must have onset <= end <= cleared"):
        ft.merge_events([Event(5.0, 2.0, 1.0, 1.0, "a")])


@pytest.mark.parametrize("kw, name", [(dict(readmit_alpha=0.5), "readmit_alpha"),
                                      (dict(readmit_samples={"uv": 2}), "readmit_samples")])
def test_readmit_clear_refuses_the_window_tests_settings(kw, name):
    """Review 35l (5) 6: readmit='clear' never asks the NIS window test, yet readmit_alpha and
    readmit_samples given with it were taken and dropped (same 65.644 m)."""
    with pytest.raises(ValueError, match=f"^{name} is unused with readmit='clear'"):
        ft.run_fault_tolerant(scenarios.MarsScenario(days=0.2), (), "wavelet", readmit="clear", **kw)
    with pytest.raises(ValueError, match="^inputs must be"):  # the defaults pass this check
        ft.run_fault_tolerant(None, (), "wavelet", readmit="clear", inputs="x")


@pytest.mark.parametrize("spec, words", [
    ("uv.range:step:5@", r"^faults: bad fault item 'uv.range:step:5@'"),
    (" ", r"^faults is empty \(' '\): pass \[\] \(or leave it out\) for no faults"),  # 35o C1
    ("uv.range:stuck:5@1000+10", r"^faults: bad fault item .*: magnitude of a stuck fault must be 0"),
])
def test_a_fault_spec_string_is_refused_under_faults(inputs, spec, words):
    """Review 35m (6) 1's class: run_fault_tolerant(faults="...") said "spec: ...", the name of
    parse_faults' parameter."""
    with pytest.raises(ValueError, match=words):
        ft.run_fault_tolerant(faults=spec, inputs=inputs, detector="wavelet", train_days=TRAIN)


def test_edited_inputs_and_an_empty_fault_spec_are_refused_by_name(inputs):
    """Review 35o (1) 3-4, (5) 1, C1: an Inputs edited by hand reached the compiled kernel (a cut
    z read past its end, a NaN x0 blamed on pos_err0_m); faults='' was refused as a bad spec
    while the CLI's --faults '' says to leave it out."""
    import dataclasses

    cut = dataclasses.replace(inputs, z={**inputs.z, "uv": inputs.z["uv"][:10]})
    for call in (lambda: ft.run_fault_tolerant(faults=HAND[:1], detector="none", inputs=cut),
                 lambda: ft.inject_inputs(cut, HAND[:1])):
        with pytest.raises(ValueError, match=r"^inputs\.z\['uv'\] has 10 rows; inputs\.meas_idx"):
            call()
    nan_x0 = dataclasses.replace(inputs, x0=np.full(6, np.nan))
    with pytest.raises(ValueError, match=r"^inputs\.x0 must contain only finite numbers"):
        ft.run_fault_tolerant(faults=HAND[:1], detector="chi2", inputs=nan_x0)
    for empty in ("", "  "):
        with pytest.raises(ValueError, match=r"^faults is empty \(.*\): pass \[\] \(or leave it "
                                             r"out\) for no faults, 'paper', or a fault spec"):
            ft.run_fault_tolerant(faults=empty, detector="none", inputs=inputs)


@pytest.mark.parametrize(("field", "value", "words"), [
    ("faults", "uv", r"^FaultTolerantRun\.faults must be a sequence of Fault, got the string 'uv'"),
    ("detector", "wavlet", r"^FaultTolerantRun\.detector must be one of 'none', 'wavelet'"),
    ("events", {"gps": []}, r"^FaultTolerantRun\.events must be a dict keyed by the run's "
                            r"subsystems \['xnav', 'uv', 'cns'\]"),
    ("events", {"uv": [1.0]}, r"^FaultTolerantRun\.events\['uv'\] must be a list of Event"),
    ("isolated", "cut", r"^FaultTolerantRun\.isolated must be a bool array of shape \(\d+, 3\)"),
    ("run", None, r"^FaultTolerantRun\.run must be a MarsRun, got NoneType None"),
    ("wall_time", float("nan"), r"^FaultTolerantRun\.wall_time must be a real number"),
])
def test_an_edited_result_is_checked_by_field(runs, field, value, words):
    """Review 35o C3: a FaultTolerantRun (or its MarsRun) edited with dataclasses.replace kept a
    string for faults and raised an AttributeError in summary(); both results are frozen and
    check their fields when made, naming the field."""
    import dataclasses

    res = runs["wavelet"]
    if value == "cut":
        value = res.isolated[:-1]
    with pytest.raises(ValueError, match=words):
        dataclasses.replace(res, **{field: value})
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.faults = []
    assert dataclasses.replace(res).summary()["faults"] == res.summary()["faults"]


@pytest.mark.parametrize(("field", "cut", "words"), [
    ("x", lambda a: a[:-1], r"^MarsRun\.x must have shape \(\d+, 6\), got shape"),
    ("P", lambda a: a * np.nan, r"^MarsRun\.P must contain only finite numbers, got MarsRun\.P\[0, 0, 0\]"),
    ("flags", lambda a: a + 4, r"^MarsRun\.flags must hold 0 \(no measurement\), 1"),
    ("t", lambda a: a[::-1].copy(), r"^MarsRun\.t must increase"),
    ("nis", lambda a: a[:, :2], r"^MarsRun\.nis must have shape"),
    ("backend", lambda a: "gpu", r"^MarsRun\.backend must be one of 'numba', 'numpy'"),
    ("scenario", lambda sc: dataclasses.replace(sc, days=5.0),  # summary() blamed settle_days
     r"^MarsRun\.scenario must be the scenario the run ran: its days = 5 and t0 = "),
])
def test_an_edited_mars_run_is_checked_by_field(clean, field, cut, words):
    with pytest.raises(ValueError, match=words):
        dataclasses.replace(clean, **{field: cut(getattr(clean, field))})
    ok = dataclasses.replace(clean, nis=np.full_like(clean.nis, np.nan))  # NaN: no measurement
    assert ok.metrics() == clean.metrics()
