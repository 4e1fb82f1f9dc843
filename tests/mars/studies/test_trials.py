"""The detector trials of the Mars system (xnavlab.mars.studies.trials): the shipped Monte Carlo table is
complete and self-consistent, its stored cells recompute from their seeds, and the Neyman-Pearson
limit of a cell bounds what any detector can find."""

import pytest

from xnavlab.mars.navigation import scenarios
from xnavlab.mars.studies import trials


@pytest.fixture(scope="module")
def table():
    return trials.load_detector_table()


def test_table_is_complete_and_self_consistent(table):
    rows = table["rows"]
    keys = {(r["fault_class"], r["sensor"], r["size_index"], r["detector"]) for r in rows}
    assert len(keys) == len(trials.FAULT_CLASSES) * len(trials.SENSORS) * 3 * len(trials.DETECTORS)
    for r in rows:
        assert r["trials"] == table["trials"]
        assert r["pd_lo"] <= r["pd"] <= r["pd_hi"]
        assert r["false_alarms_per_day_lo"] <= r["false_alarms_per_day"] <= r["false_alarms_per_day_hi"]
    assert trials.marked_cells(rows) == table["marked"]


def _same_decisions(old, new):
    """Detected, late, out at onset and the false-alarm count exactly; a delay to 30 s and an
    RMS ratio to 5 % (rounding differs between BLAS kernels: no test decides on it)."""
    for key in ("detected", "late", "out_at_onset"):
        assert new[key] == old[key], (key, old, new)
    if old["detected"]:
        assert abs(new["delay_s"] - old["delay_s"]) <= 30.0
    if "false_alarms" in old:
        assert new["false_alarms"] == old["false_alarms"]


def test_table_cells_recompute(table):
    # the stored first trial of a few cells, recomputed from its seed by the code here
    for chk in table["checks"][:2]:
        fresh = trials.detector_trials(**chk["params"], seed=chk["seed"])
        for old, new in zip(chk["records"], fresh, strict=True):
            assert new["detector"] == old["detector"]
            _same_decisions(old, new)
            assert new["fused_rms_ratio"] == pytest.approx(old["fused_rms_ratio"], rel=0.05)
            row = next(r for r in table["rows"] if (r["fault_class"], r["sensor"],
                                                    r["size_index"], r["detector"])
                       == (new["fault_class"], new["sensor"], new["size_index"], new["detector"]))
            assert row["pd_hi"] > 0.0 if new["detected"] else row["pd_lo"] < 1.0
            assert row["late"] >= int(new["late"])


def test_table_counts_late_apart_from_detected(table):
    """A late trial is never a detection: per cell, detected plus late is at most the trials,
    and the late column is there for every cell."""
    for r in table["rows"]:
        assert 0 <= r["late"] <= r["trials"] and r["late_fraction"] == r["late"] / r["trials"]
        assert round(r["pd"] * r["trials"]) + r["late"] <= r["trials"]


def test_early_fault_table_recomputes():
    early = trials.load_early_faults()
    chk = early["checks"]
    onset = trials.EARLY_ONSETS_S[0]
    fresh = trials.early_fault_trial(seed=chk["seed"], onsets=(onset,))
    stored = [r for r in chk["records"] if r["onset_s"] == onset]
    assert [r["sensor"] for r in fresh] == [r["sensor"] for r in stored] == list(trials.SENSORS)
    for old, new in zip(stored, fresh, strict=True):
        _same_decisions(old, new)
        assert new["rms_ratio"] == pytest.approx(old["rms_ratio"], rel=0.05)
    for row in early["rows"]:
        assert row["found"] + row["late"] <= row["trials"] and row["out_at_onset"] <= row["found"]


def test_detection_limit_of_the_xnav_edge_cells():
    """A 3x XNAV noise lasting 3000 s (6 samples of 500 s) cannot be found every time by
    any detector at the design rate; a drift reaching 5 sigma in 6000 s can, within 4000 s."""
    assert trials.detection_limit("noise", "xnav", 3.0) < 0.99
    assert trials.detection_limit("ramp", "xnav", 5.0) > 0.999
    assert trials.detection_limit("ramp", "xnav", 5.0, window_s=400.0) == 0.0   # no sample yet
    assert trials.detection_limit("step", "uv", 3.0) > 0.999
    with pytest.raises(ValueError, match="sensor"):
        trials.detection_limit("noise", "cns", 3.0)
    with pytest.raises(ValueError, match="fault_class"):
        trials.detection_limit("stuck", "xnav", 600.0)


def test_shipped_noise_cells_stay_below_the_limit():
    """A noise fault leaves no evidence after it ends: no detector finds it more often than the
    limit over its duration (to within the Wilson interval of the shipped table)."""
    rows = trials.load_detector_table()["rows"]
    for r in rows:
        if r["fault_class"] == "noise" and r["sensor"] == "xnav":
            lim = trials.detection_limit("noise", "xnav", r["size"], trials.DURATIONS["noise"])
            assert r["pd_lo"] <= lim + 1e-9, r


@pytest.mark.parametrize(("text", "words"), [
    ("{", "is not valid JSON"),
    ('{"rows": []}', "must hold a non-empty list of rows"),
    ('{"rows": [{"sensor": "uv"}]}', "row 0 has no fault_class"),
])
def test_a_corrupt_detector_table_is_refused_with_its_file_and_row(tmp_path, text, words):
    path = tmp_path / "table.json"
    path.write_text(text)
    with pytest.raises(ValueError, match=words) as err:
        trials.load_detector_table(path)
    assert "table.json" in str(err.value)
    with pytest.raises(ValueError, match="table.json"):
        trials.load_early_faults(path)


@pytest.mark.parametrize("bad", [{}, 5])
def test_table_loaders_refuse_a_path_that_is_no_path(bad):  # review 35d D37's class: TypeError
    with pytest.raises(ValueError, match=r"^detector table must be a path"):
        trials.load_detector_table(bad)
    with pytest.raises(ValueError, match=r"^early-fault table must be a path"):
        trials.load_early_faults(bad)


@pytest.mark.parametrize("bad", ["abc", None, [{"sensor": "uv"}]])
def test_tables_refuse_what_is_no_list_of_rows(bad):  # review 35d D37's class: TypeError
    with pytest.raises(ValueError, match=r"^records(\[0\])? must be a (list of )?trial record"):
        trials.detector_table(bad)
    with pytest.raises(ValueError, match=r"^rows(\[0\])? must be a (list of )?detector_table row"):
        trials.marked_cells(bad)


@pytest.mark.parametrize("seed", [1.5, -1, "3", None])
def test_early_fault_trial_refuses_a_seed_that_is_no_integer_in_range(seed):
    # review 35d D24's class: int() truncated 1.5 to 1 and wrapped -1 silently
    with pytest.raises(ValueError, match=r"^seed must be an integer in \[0, 9223372036854775807\]"):
        trials.early_fault_trial(seed=seed)


@pytest.mark.parametrize("trial", [lambda s: trials.mars_trial(seed=s),
                                   lambda s: trials.detector_trial("step", "uv", 0, "combined",
                                                                   seed=s)])
def test_mars_and_detector_trials_refuse_a_seed_above_the_records_range(trial):
    """Review 35e: 2^63 was taken (check_int without its upper end), no record can store it."""
    with pytest.raises(ValueError, match=r"^seed must be an integer in \[0, 9223372036854775807\], "
                                         r"got 9223372036854775808$"):
        trial(2**63)


def test_a_0d_array_of_records_is_refused_by_name():
    """Issue 35 (review 35h): numpy's 'iteration over a 0-d array' became a ValueError."""
    import numpy as np

    with pytest.raises(ValueError, match=r"^records must be a list of trial records \(dicts\), got array"):
        trials.detector_table(np.array(1.0))
    with pytest.raises(ValueError, match=r"^rows must be a list of detector_table rows \(dicts\), got arr"):
        trials.marked_cells(np.array(1.0))
    assert trials.detector_table([]) == [] and trials.marked_cells([]) == []


@pytest.mark.parametrize(("call", "words"), [
    (lambda: trials.fault_for("step", "uv", 5.0, 1000.0, scenario="x"),
     r"^scenario must be a MarsScenario, got str 'x'"),
    (lambda: trials.fault_for("step", "uv", 5.0, -1000.0), r"^onset must be a real number in \[0, "),
    (lambda: trials.fault_for("step", "uv", 5.0, 1e12),
     r"^onset must be a real number in \[0, 3.1536e\+07\)"),
    (lambda: trials.fault_for("step", "uv", 5.0, 5000.0, scenarios.MarsScenario(days=0.05)),
     r"^onset must be a real number in \[0, 4320\)"),
    (lambda: trials.detection_limit("step", "uv", 3.0, scenario={"days": 1}),
     r"^scenario must be a MarsScenario, got dict"),
    (lambda: trials.early_fault_trial(seed=0, onsets=()), r"^onsets must name at least one onset"),
    (lambda: trials.early_fault_trial(seed=0, onsets=(100.0,)),
     r"^onsets\[0\] must be a real number in \[600, 86400\)"),
    (lambda: trials.early_fault_trial(seed=0, size_sigma=0.0),
     r"^size_sigma must be a real number in \(0, 1000\]"),
    (lambda: trials.early_fault_trial(seed=0, duration=-1.0),
     r"^duration must be a real number in \(0, 86400\]"),
    (lambda: trials.mars_trial(5.0, days=0.5, duration=1e6),
     r"^duration must be a real number in \(0, 8640\]"),
    (lambda: trials.mars_trial(0.0, days=0.5), r"^size_sigma must be a real number in \(0, 1000\]"),
])
def test_a_trial_refuses_what_it_would_not_run(call, words, monkeypatch):
    """Review 35j (1) 16, (5) 18, 34, 38: a string scenario was an AttributeError; an onset before
    the start or 1e12 s, no onset at all, a fault longer than the run were taken."""
    monkeypatch.setattr(scenarios, "prepare", lambda *a, **k: pytest.fail("the run started"))
    with pytest.raises(ValueError, match=words):
        call()


@pytest.mark.parametrize("rate", [5e-324, 1e300, None, "1.0", True])
def test_detection_limit_names_rate_per_day(rate):
    """Review 35k (3) 18: a subnormal or huge rate_per_day was refused as alpha."""
    with pytest.raises(ValueError, match="^rate_per_day must be"):
        trials.detection_limit("step", "uv", 3.0, rate_per_day=rate)


_REC = dict(fault_class="step", sensor="uv", size_index=0, size=3.0, detector="chi2",
            detected=True, delay_s=1.0, late=False, false_alarms=0, armed_days=0.6,
            fused_rms_ratio=1.0, time_out_s=300.0)


@pytest.mark.parametrize(("change", "words"), [
    ({"armed_days": 0.0}, "records[0]['armed_days'] is 0.0, not a number in (0, 1e+100]"),
    ({"armed_days": -1.0}, "records[0]['armed_days'] is -1.0"),
    ({"armed_days": float("nan")}, "records[0]['armed_days'] is nan, not a finite number"),
    ({"detected": "no"}, "records[0]['detected'] is 'no', not true or false"),
    ({"false_alarms": 2.5}, "records[0]['false_alarms'] is 2.5, not an integer in [0, 1e+09]"),
    ({"false_alarms": -1}, "records[0]['false_alarms'] is -1"),
    ({"delay_s": -5.0}, "records[0]['delay_s'] is -5.0, not a number in [0, 1e+100]"),
    ({"fused_rms_ratio": float("inf")}, "records[0]['fused_rms_ratio'] is inf"),
    ({"fused_rms_ratio": 1e308}, "records[0]['fused_rms_ratio'] is 1e+308"),
])
def test_detector_table_refuses_values_out_of_range(change, words):
    """Review 35l (1) 1, (1) 2, (3) 2, (5) 1: armed_days 0 gave ZeroDivisionError, 1e308 an
    overflow warning, false_alarms -1 a message naming dof, and -1 days, "no", 2.5 false
    alarms, a negative delay or an infinite ratio numbers; now one line naming records[i]."""
    with pytest.raises(ValueError) as info:
        trials.detector_table([dict(_REC, **change)] * 2)
    assert str(info.value).startswith(words)


def test_detector_table_refuses_two_sizes_in_a_cell():
    """Review 35l (5) 1: a cell's size was its first record's, whatever the others said."""
    with pytest.raises(ValueError, match=r"^records\[1\]\['size'\] must be that of its cell"):
        trials.detector_table([_REC, dict(_REC, size=5.0)])


@pytest.mark.parametrize(("change", "words"), [
    ({"fault_class": "bogus"}, "records[0]['fault_class'] must be one of 'step'"),
    ({"sensor": 3}, "records[0]['sensor'] must be one of 'uv'"),
    ({"size_index": -7}, "records[0]['size_index'] must be an integer in [0, 2], got -7"),
    ({"detector": "none"}, "records[0]['detector'] must be one of 'wavelet'"),
    ({"size": 5.0}, "records[0]['size'] must be its cell's size SIZES['step'][0] = 3.0, got 5.0"),
])
def test_detector_table_refuses_a_record_of_no_cell(change, words):
    """Review 35m pattern H: the values were checked but not the cell keys; a record of fault
    class "bogus", sensor 3 or size_index -7 became a table row of its own."""
    with pytest.raises(ValueError) as err:
        trials.detector_table([dict(_REC, **change)])
    assert str(err.value).startswith(words)
