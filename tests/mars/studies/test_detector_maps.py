"""The heat maps and false-alarm strips of the detector table (xnavlab.mars.studies.detector_maps)."""

import matplotlib
import numpy as np
import pytest

from xnavlab.mars.studies import detector_maps as dm
from xnavlab.mars.studies import trials

matplotlib.use("Agg")


def _rows():
    rows = []
    for fc, sizes in (("step", (3.0, 5.0)), ("noise", (2.0,))):
        for size in sizes:
            for k, s in enumerate(dm.SENSORS):
                for d, base in (("wavelet", 0.1), ("combined", 0.5)):
                    rows.append({"fault_class": fc, "size": size, "sensor": s, "detector": d,
                                 "pd": base + 0.1 * k, "late": k, "rms_ratio": 1.0 + k,
                                 "false_alarms_per_day": base * 2})
    return rows


def test_cell_grid_places_each_row():
    labels, v = dm.cell_grid(_rows(), "pd", "combined")
    assert labels == ["step 3 σ", "step 5 σ", "noise ×2"]
    np.testing.assert_allclose(v, [[0.5, 0.6, 0.7]] * 3)
    _, late = dm.cell_grid(_rows(), "late", "wavelet")
    assert late[:, 2].tolist() == [2.0, 2.0, 2.0]


def test_cell_grid_missing_value_is_nan_and_unknown_detector_refused():
    rows = _rows()
    rows[0]["pd"] = None
    _, v = dm.cell_grid(rows, "pd", rows[0]["detector"])
    assert np.isnan(v[0, 0]) and np.isfinite(v[0, 1])
    with pytest.raises(ValueError, match="detector"):
        dm.cell_grid(rows, "pd", "oracle")


def test_shipped_table_fills_every_cell():
    table = trials.load_detector_table()
    n_cells = sum(len(v) for v in trials.SIZES.values())
    for det in trials.DETECTORS:
        labels, v = dm.cell_grid(table["rows"], "pd", det)
        assert len(labels) == n_cells and np.all(np.isfinite(v))


def test_maps_write_every_value_and_late_count():
    fig = dm.plot_cell_maps({"rows": _rows()}, detectors=("wavelet", "combined"))
    texts = [t.get_text() for t in fig.axes[0].texts]
    assert len(texts) == 9 and "0.30  (2 late)" in texts and "0.10" in texts
    assert [t.get_text() for t in fig.axes[0].get_yticklabels()] == ["step 3 σ", "step 5 σ",
                                                                    "noise ×2"]
    assert fig.axes[-1].get_ylabel() == "probability of detection"


def test_maps_log_scale_and_bad_key():
    fig = dm.plot_cell_maps({"rows": _rows()}, "rms_ratio", ("combined",), log=True)
    assert fig.axes[0].images[0].norm.__class__.__name__ == "LogNorm"
    with pytest.raises(ValueError, match="key"):
        dm.plot_cell_maps({"rows": _rows()}, "colour")


def test_false_alarm_strips_draw_design_and_mean():
    fig = dm.plot_false_alarms({"rows": _rows(), "trials": 16}, {"combined": 3.0},
                               detectors=("wavelet", "combined"))
    ax = fig.axes[0]
    ys = {tuple(line.get_ydata()) for line in ax.get_lines() if len(line.get_ydata()) == 2}
    assert (3.0, 3.0) in ys and (1.0, 1.0) in ys and (0.2, 0.2) in ys
    assert [t.get_text() for t in ax.get_legend().get_texts()][0] == "a cell (16 one-day runs)"


def test_signal_pd_one_panel_per_kind_with_late_dashed():
    rows = [{"kind": k, "size_sigma": s, "wavelet_pd": 0.5, "wavelet_late": 0.25,
             "chi2_pd": 1.0, "chi2_late": 0.0} for k in ("step", "ramp") for s in (2.0, 8.0)]
    fig = dm.plot_signal_pd(rows)
    assert [ax.get_title() for ax in fig.axes] == ["step", "ramp"]
    lines = fig.axes[1].get_lines()
    assert [tuple(ln.get_ydata()) for ln in lines] == [(0.5, 0.5), (0.25, 0.25), (1.0, 1.0),
                                                       (0.0, 0.0)]
    assert lines[1].get_linestyle() == "--"
    assert [t.get_text() for t in fig.legends[0].get_texts()][1] == "wavelet: late"


@pytest.mark.parametrize("bad", ["abc", None, [{"detector": "chi2"}]])
def test_cell_grid_refuses_what_is_no_list_of_rows(bad):  # review 35d D37's class: TypeError
    with pytest.raises(ValueError, match=r"^rows(\[0\])? must be a (list of )?detector_table row"):
        dm.cell_grid(bad, "pd", "chi2")


@pytest.mark.parametrize(("call", "words"), [
    (lambda rows: dm.plot_cell_maps(rows), r"^table must be a dict with the key 'rows'"),
    (lambda rows: dm.plot_cell_maps({"rows": rows}, detectors="wavelet"),
     r"^detectors must be a list of detectors, got the string 'wavelet'"),
    (lambda rows: dm.plot_cell_maps({"rows": rows}, detectors=("wavelet", "wavelet")),
     r"^detectors lists wavelet twice"),
    (lambda rows: dm.plot_cell_maps({"rows": rows}, detectors=("wavelet",), log="no"),
     r"^log must be True or False, got 'no'$"),
])
def test_plot_cell_maps_checks_its_table_detectors_and_log(call, words):
    """Review 35e: a list for table was a TypeError, 'wavelet' was split into 'w', a detector
    twice drew twice, log='no' drew a log scale."""
    rows = [{"fault_class": "step", "sensor": s, "size": 3.0, "detector": d, "pd": 0.5, "late": 1}
            for s in dm.SENSORS for d in ("wavelet", "chi2")]
    with pytest.raises(ValueError, match=words):
        call(rows)


def test_an_edge_value_of_a_label_table_or_detector_list_is_refused_by_name():
    """Issue 35 (review 35h): ``cell_label(True, ...)`` was a label, a bool table an
    AttributeError, an unknown detector refused as 'detector' (no parameter), and an empty
    list of rows matplotlib's 'Number of columns must be a positive integer'."""
    rows = [{"fault_class": "step", "sensor": s, "size": 3.0, "detector": d, "pd": 0.5,
             "false_alarms_per_day": 0.5, "late": 0} for s in dm.SENSORS for d in ("wavelet", "chi2")]
    table = {"rows": rows}
    cases = [
        (lambda: dm.cell_label(True, 3.0), r"^fault_class must be one of 'step', .*, got True$"),
        (lambda: dm.cell_label("step", True), r"^size must be a real number in \(0, 1e\+08\], got True$"),
        (lambda: dm.plot_cell_maps(table, detectors=[1.0]), r"^detectors\[0\] must be one of"),
        (lambda: dm.plot_false_alarms(True, {}), r"^table must be a dict with the key 'rows'"),
        (lambda: dm.plot_false_alarms({"rows": []}, {}), r"^table\['rows'\] must hold at least one"),
        (lambda: dm.plot_false_alarms(table, []), r"^design must be a dict of detector"),
        (lambda: dm.plot_false_alarms(table, {"chi2": True}), r"^design\['chi2'\] must be a real number"),
        (lambda: dm.plot_false_alarms(table, {}, detectors=[]), r"^detectors must name at least one"),
        (lambda: dm.plot_false_alarms(table, {}, detectors=-0.0), r"^detectors must be a list of detectors"),
        (lambda: dm.plot_signal_pd(True), r"^rows must be a list of detection_table rows"),
        (lambda: dm.plot_signal_pd([]), r"^rows must hold at least one detection_table row"),
        (lambda: dm.plot_signal_pd([1.0]), r"^rows\[0\] must be a detection_table row"),
        (lambda: dm.plot_signal_pd([{"kind": "step", "size_sigma": 2.0}], ["cusum"]),
         r"^detectors\[0\] must be a detector whose columns the rows hold, got 'cusum'"),
    ]
    for call, message in cases:
        with pytest.raises(ValueError, match=message):
            call()
    assert dm.plot_false_alarms(table, {"chi2": 0.5}, detectors=("chi2",)).axes


def test_cell_label_refuses_an_unknown_fault_class():
    """Review 35j (5) 39: cell_label('stpe', 3.0) was 'stpe 3 σ'."""
    with pytest.raises(ValueError, match=r"^fault_class must be one of 'step', 'ramp', 'spike', "
                                         r"'stuck', 'noise', got 'stpe'"):
        dm.cell_label("stpe", 3.0)
