"""The Mars system's campaign registry (xnavlab.mars.studies.campaigns): the named campaigns, their
parameters per run, their allowed lengths and the detector cells. The physics of the consistency
campaign (NEES, NIS against their bands) is tested in tests/mars/navigation/test_consistency.py."""

import pytest

from xnavlab.mars.studies import campaigns as mc
from xnavlab.mars.studies import trials


def test_detector_cells_cover_every_class_sensor_and_size_once():
    cells = mc.detector_cells()
    assert len(cells) == len(set(cells)) == sum(
        len(trials.SIZES[f]) for f in trials.FAULT_CLASSES) * len(trials.SENSORS)
    assert mc.detector_cells(("step",), ("uv",)) == [("step", "uv", i)
                                                      for i in range(len(trials.SIZES["step"]))]
    with pytest.raises(ValueError, match="fault_class"):
        mc.detector_cells(("wobble",))
    with pytest.raises(ValueError, match="sensor"):
        mc.detector_cells(sensors=("gps",))


def test_detectors_campaign_cycles_through_the_cells():
    c = mc.campaign("detectors", days=2.0)
    cells = mc.detector_cells()
    for i in (0, 7, len(cells), len(cells) + 7):
        f, s, k = cells[i % len(cells)]
        assert c.params(i) == {"fault_class": f, "sensor": s, "size_index": k, "days": 2.0}
    assert c.manifest["detectors"] == list(trials.DETECTORS)


def test_consistency_campaign_passes_its_days_to_every_run():
    c = mc.campaign("consistency", days=0.5)
    assert c.params(0) == c.params(99) == {"days": 0.5}
    assert c.manifest["nees_bins"] == mc.NEES_BINS


@pytest.mark.parametrize(("name", "days"), [("consistency", 0.0), ("consistency", 31.0),
                                            ("detectors", 0.25), ("detectors", 6.0)])
def test_a_campaign_refuses_days_outside_its_range(name, days):
    with pytest.raises(ValueError, match="^days"):
        mc.campaign(name, days=days)


def test_an_unknown_campaign_is_refused_by_name():
    with pytest.raises(ValueError, match=r"^name must be one of 'consistency', 'detectors', got 'every"):
        mc.campaign("everything")
    assert set(mc.CAMPAIGNS) == set(mc.DAYS)


def test_summarise_detectors_skips_failed_runs():
    failed = {"status": "error", "parameters": {}, "metrics": {}}
    assert mc.summarise_detectors([failed]) == []


def test_a_consistency_campaign_too_short_for_its_nees_bins_is_refused_before_any_run():
    # issue 35: 1e-5 days failed inside every run (a record_dt below its range, or an empty bin)
    for make in (lambda: mc.campaign("consistency", days=1e-5),
                 lambda: mc.consistency_run(seed=0, days=1e-4)):
        with pytest.raises(ValueError, match=r"^days must be at least 0.000417 for the "
                                             r"consistency campaign: each of its 12 NEES bins"):
            make()


def test_a_scenario_sets_every_field_but_those_the_consistency_campaign_sets():
    from xnavlab.mars.navigation import scenarios

    sc = scenarios.MarsScenario(sigma_range_m=100.0, mode="no-reset")
    camp = mc.campaign("consistency", days=0.02, scenario=sc)
    assert camp.params(0)["fields"] == {"sigma_range_m": 100.0, "mode": "no-reset"}
    for bad in ({"seed": 3}, {"record_dt": 10.0}):
        with pytest.raises(ValueError, match=f"scenario.{next(iter(bad))} is not used"):
            mc.campaign("consistency", days=0.02, scenario=scenarios.MarsScenario(**bad))
    with pytest.raises(ValueError, match="'seed' is not a field consistency_run takes"):
        mc.consistency_run(seed=0, days=0.02, fields={"seed": 1})


@pytest.mark.parametrize(("kw", "words"), [
    ({"fault_classes": ("step", "wobble")}, "fault_classes[1] must be one of"),
    ({"sensors": ("uv", "gps")}, "sensors[1] must be one of"),
    ({"sensors": "uv"}, "sensors must be a list of sensors, got the string 'uv'"),  # was 'u'
    ({"fault_classes": ("step", "step")}, "fault_classes lists step twice (items 0 and 1)"),
])
def test_detector_cells_name_each_item_under_its_list(kw, words):  # review 35d D11's class
    with pytest.raises(ValueError) as exc:
        mc.detector_cells(**kw)
    assert str(exc.value).startswith(words), str(exc.value)


@pytest.mark.parametrize("bad", ["abc", None, [{"metrics": {}}]])
def test_summaries_refuse_what_is_no_list_of_records(bad):  # review 35d D37's class: TypeError
    for call in (mc.summarise_consistency, mc.summarise_detectors):
        with pytest.raises(ValueError, match=r"^runs(\[0\])? must be a (list of )?campaign record"):
            call(bad)


def test_consistency_run_refuses_a_string_for_its_subsystems():
    """Review 35e: subsystems="uv" was split into 'u', 'v' ("subsystems[0] ... got 'u'")."""
    with pytest.raises(ValueError, match=r"^subsystems must be a list of subsystems, got the string 'uv'"):
        mc.consistency_run(seed=1, days=0.05, subsystems="uv")


def test_a_campaign_name_or_a_record_list_is_refused_by_name():
    """Issue 35 (review 35h): the name was refused as 'campaign' (no parameter), and a 0-d
    array of runs was numpy's 'iteration over a 0-d array'."""
    import numpy as np

    with pytest.raises(ValueError, match=r"^name must be one of 'consistency', 'detectors', got True$"):
        mc.campaign(True)
    for fn in (mc.summarise_consistency, mc.summarise_detectors):
        with pytest.raises(ValueError, match=r"^runs must be a list of campaign records \(dicts\), got arr"):
            fn(np.array(1.0))


@pytest.mark.parametrize(("kw", "words"), [
    ({"scenario": {"a": 1}}, r"^scenario must be a MarsScenario, got dict"),
    ({"backend": "x"}, r"^backend must be one of 'numba', 'numpy', got 'x'"),
    ({"local_filter": "x"}, r"^local_filter must be one of 'ekf', 'ukf'"),
    ({"local_filter": "ukf"}, r"^local_filter='ukf' runs with backend='numpy' only"),
])
def test_campaign_refuses_a_setting_every_run_would_refuse(kw, words):
    """Review 35j (1) 17, (5) 17: a dict scenario was an AttributeError; backend 'x' and the UKF
    with numba built a campaign whose every run failed."""
    with pytest.raises(ValueError, match=words):
        mc.campaign("consistency", days=0.02, **kw)
    assert mc.campaign("consistency", days=0.02, backend="numpy", local_filter="ukf").name


@pytest.mark.parametrize(("detectors", "words"), [
    ((), r"^detectors must name at least one detector, got an empty list"),
    (("chi2", "chi2"), r"^detectors lists chi2 twice"),
    (("cusum",), r"^detectors\[0\] must be one of"),
])
def test_detectors_run_refuses_no_detector(detectors, words):
    """Review 35j (5) 35: detectors=() returned {}."""
    with pytest.raises(ValueError, match=words):
        mc.detectors_run("step", "uv", 0, seed=0, detectors=detectors)


def test_a_short_consistency_run_records_no_closer_than_its_measurements():
    """Review 35j follow-up: under 0.00167 days the campaign's record_dt (span / 48) fell below
    the 3-s measurements, which MarsScenario now refuses, naming a record_dt the user never set."""
    from xnavlab.mars.studies import campaigns

    r = campaigns.consistency_run(seed=0, days=0.001, subsystems=("uv", "cns"))
    assert len(r["nees_bins"]) == campaigns.NEES_BINS


def test_summaries_refuse_metrics_they_cannot_use():
    """Review 35k (6) 1: a record's metrics without nees_bins (or with text in it) gave a
    KeyError / numpy TypeError; now one line naming runs[i] and the key, and the campaign's
    check_metrics says the same of a stored record."""
    good = mc.consistency_run(seed=1, days=0.02)
    runs = [{"status": "ok", "metrics": good}, {"status": "ok", "metrics": {"a": 1}}]
    with pytest.raises(ValueError, match=r"^runs\[1\]\['metrics'\].*nees_bins is missing"):
        mc.summarise_consistency(runs)
    bad = {**good, "nees_bins": ["x"] + good["nees_bins"][1:]}
    with pytest.raises(ValueError, match=r"nees_bins\[0\] is 'x', not a finite number"):
        mc.summarise_consistency([{"status": "ok", "metrics": bad}])
    camp = mc.campaign("consistency", days=0.02)
    assert camp.check_metrics(good) is None and "nees_bins" in camp.check_metrics(bad)
    with pytest.raises(ValueError, match=r"^runs\[0\]\['metrics'\] is not a detectors_run"):
        mc.summarise_detectors([{"status": "ok", "parameters": {}, "metrics": {"x": {}}}])


def _runs(change):
    good = mc.consistency_run(seed=1, days=0.02)
    out = []
    for _ in range(2):
        m = {k: (dict(v) if isinstance(v, dict) else list(v) if isinstance(v, list) else v)
             for k, v in good.items()}
        change(m)
        out.append({"status": "ok", "metrics": m})
    return out


@pytest.mark.parametrize(("change", "words"), [
    (lambda m: m.__setitem__("nees_bins", [-5.0] * 12), "nees_bins[0] is -5.0, not a number in [0"),
    (lambda m: m.__setitem__("nees_bins", [1e308] * 12), "nees_bins[0] is 1e+308"),
    (lambda m: m.__setitem__("position_error_m", 1e308), "position_error_m is 1e+308"),
    (lambda m: m.__setitem__("position_error_m", -1.0), "position_error_m is -1.0"),
    (lambda m: m.__setitem__("bin_days", [-1.0] * 12), "bin_days[0] is -1.0"),
    (lambda m: m["nis_sum"].__setitem__("uv", 1e308), "nis_sum.uv is 1e+308"),
    (lambda m: m["nis_dof"].__setitem__("xnav", 0), "nis_dof.xnav is 0, not an integer in [1"),
    (lambda m: (m["nis_count"].__setitem__("uv", 0), m["nis_sum"].__setitem__("uv", 5.0)),
     "nis_sum.uv is 5.0 of nis_count.uv = 0 updates"),
])
def test_summarise_consistency_refuses_values_out_of_range(change, words):
    """Review 35l (1) 2, (3) 1, (5) 2: negative or huge values gave messages naming value or
    dof, an overflow warning, a negative RMS, bins at -1 day, or dropped the NIS uv row; now
    one line naming runs[i]['metrics'] and the key, and the campaign's store check refuses
    the same record (its run is computed again)."""
    runs = _runs(change)
    with pytest.raises(ValueError) as info:
        mc.summarise_consistency(runs)
    assert str(info.value).startswith("runs[0]['metrics'] is not a consistency_run result: "
                                      + words)
    assert words in mc.campaign("consistency", days=0.02).check_metrics(runs[0]["metrics"])


def test_consistency_check_metrics_compares_the_manifest():
    """Review 35l (5) 2: bins of another run length or a dof of 1e6 were summarised."""
    camp = mc.campaign("consistency", days=0.02)
    good = _runs(lambda m: None)[0]["metrics"]
    assert camp.check_metrics(good) is None
    assert "bin_days[0]" in mc.campaign("consistency", days=0.04).check_metrics(good)
    bad = _runs(lambda m: m["nis_dof"].__setitem__("xnav", 10**6))[0]["metrics"]
    assert "not the campaign's" in camp.check_metrics(bad)


def test_detectors_check_metrics_refuses_out_of_range_records():
    """Review 35l (1) 1, (6) 1, (6) 4: armed_days 0 or -1 passed the store's check."""
    camp = mc.campaign("detectors", days=1.0)
    rec = dict(size=3.0, detected=True, delay_s=1.0, late=False, false_alarms=0,
               armed_days=0.6, fused_rms_ratio=1.0, time_out_s=300.0)
    assert camp.check_metrics({"chi2": rec}) is None
    assert "chi2.armed_days is 0.0" in camp.check_metrics({"chi2": dict(rec, armed_days=0.0)})
    assert "chi2.size is -3.0" in camp.check_metrics({"chi2": dict(rec, size=-3.0)})
    assert "size 7.5 is none" in camp.check_metrics({"chi2": dict(rec, size=7.5)})
    run = {"status": "ok", "parameters": {"fault_class": "step", "sensor": "uv", "size_index": 1},
           "metrics": {"chi2": rec}}
    with pytest.raises(ValueError, match=r"^runs\[0\]\['metrics'\]\['chi2'\]\['size'\] must be"):
        mc.summarise_detectors([run])


def test_summarise_consistency_checks_the_runs_against_a_scenario_given():
    """Issue 35: called directly, the summary compared nis_dof only run with run; with the
    scenario it also compares it (and the bins' times) with the scenario's."""
    from xnavlab.mars.navigation.scenarios import MarsScenario
    from xnavlab.mars.timing.pulsars import PAPER_PULSARS

    runs = [{"status": "ok", "metrics": mc.consistency_run(seed=s, days=0.02)} for s in (1, 2)]
    rows = mc.summarise_consistency(runs, scenario=MarsScenario(days=0.02))
    assert rows == mc.summarise_consistency(runs)
    with pytest.raises(ValueError, match=r"^runs\[0\]\['metrics'\] is not a consistency_run "
                                         r"result: nis_dof is \{'xnav': 4, .*not the campaign's "
                                         r"\{'xnav': 3"):
        mc.summarise_consistency(runs, scenario=MarsScenario(days=0.02,
                                                             pulsars=PAPER_PULSARS[:3]))
    with pytest.raises(ValueError, match=r"^runs\[0\]\['metrics'\] is not a consistency_run "
                                         r"result: bin_days\[0\] is "):
        mc.summarise_consistency(runs, scenario=MarsScenario(days=0.04))
    with pytest.raises(ValueError, match=r"^scenario must be a MarsScenario \(the runs' set-up\), "
                                         r"got 'x'"):
        mc.summarise_consistency(runs, scenario="x")


@pytest.mark.parametrize(("parameters", "words"), [
    ({"fault_class": "bogus", "sensor": 3, "size_index": -7},
     "['fault_class'] must be one of 'step'"),
    ({"fault_class": "step", "sensor": 3, "size_index": 0}, "['sensor'] must be one of 'uv'"),
    ({"fault_class": "step", "sensor": "uv", "size_index": -7},
     "['size_index'] must be an integer in [0, 2], got -7"),
    ({"fault_class": "step", "sensor": "uv", "size_index": True}, "['size_index'] must be"),
])
def test_summarise_detectors_refuses_parameters_of_no_cell(parameters, words):
    """Review 35m (5) 7, pattern H: a run with fault_class "bogus", sensor 3 and size_index
    -7 became a table row for the cell (bogus, 3, -7); its parameters are a cell's or refused."""
    rec = dict(size=3.0, detected=True, delay_s=1.0, late=False, false_alarms=0,
               armed_days=0.6, fused_rms_ratio=1.0, time_out_s=300.0)
    run = {"status": "ok", "parameters": parameters, "metrics": {"chi2": rec}}
    with pytest.raises(ValueError) as err:
        mc.summarise_detectors([run])
    assert str(err.value).startswith("runs[0]['parameters']" + words)
    run["parameters"] = {"fault_class": "step", "sensor": "uv", "size_index": 0}
    assert [r["fault_class"] for r in mc.summarise_detectors([run])] == ["step"]
