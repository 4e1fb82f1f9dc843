"""The detector trials of the Mars system (xnavlab.mars.trials): the shipped Monte Carlo table is
complete and self-consistent, and its stored cells recompute from their seeds."""


import pytest

from xnavlab.mars import trials


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


def test_table_cells_recompute(table):
    # the stored first trial of a few cells, recomputed from its seed: same decisions
    for chk in table["checks"][:2]:
        fresh = trials.detector_trials(**chk["params"], seed=chk["seed"])
        for old, new in zip(chk["records"], fresh, strict=True):
            assert new["detector"] == old["detector"]
            assert new["detected"] == old["detected"]
            if old["detected"]:
                assert abs(new["delay_s"] - old["delay_s"]) <= 30.0
            assert new["fused_rms_ratio"] == pytest.approx(old["fused_rms_ratio"], rel=0.05)
            row = next(r for r in table["rows"] if (r["fault_class"], r["sensor"],
                                                    r["size_index"], r["detector"])
                       == (new["fault_class"], new["sensor"], new["size_index"], new["detector"]))
            assert row["pd_hi"] > 0.0 if new["detected"] else row["pd_lo"] < 1.0
