"""The ROC campaign (xnavlab.mars.studies.roc): the grid's validation, one run, the curve's statistics."""

import json

import matplotlib.pyplot as plt
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

from xnavlab.core.campaign import run_campaign
from xnavlab.mars.studies import roc

FAULT = {"fault_class": "step", "sensor": "uv", "size": 8.0}
GRID = {"detector": "chi2", "thresholds": [1e-3, 1e-7], "days": 0.5, "faults": [FAULT]}


def test_check_grid_sorts_thresholds_and_fills_defaults():
    g = roc.check_grid({"thresholds": [3, 0.1], "faults": [FAULT]})
    assert g["detector"] == "combined" and g["threshold_name"] == "rate_per_day"
    assert g["thresholds"] == [0.1, 3.0] and g["days"] == 0.5
    assert roc.check_grid(g) == g                      # idempotent (the manifest re-checks it)


@pytest.mark.parametrize("change, words", [
    ({"detector": "cusum"}, "detector must be one of"),
    ({"thresholds": []}, "thresholds must be a list of 1 to 20"),
    ({"thresholds": 0.1}, "thresholds must be a list"),
    ({"thresholds": [1e-3, 1.0]}, "thresholds[1] (alpha) must be a real number in (0, 1)"),
    ({"thresholds": [1e-3, "x"]}, "thresholds[1] (alpha)"),
    ({"thresholds": [1e-3, 1e-3]}, "thresholds must be distinct"),
    ({"detector": "combined", "thresholds": [200.0]},
     "thresholds[0] (rate_per_day) must be a real number in [0.001, 100]"),
    ({"detector": "combined", "thresholds": [5e-324]},
     "thresholds[0] (rate_per_day) must be a real number in [0.001, 100], got 5e-324"),
    ({"threshold_name": "banana"}, "threshold_name 'banana' does not match detector"),
    ({"days": 0.1}, "days must be a real number in [0.5, 5]"),
    ({"faults": []}, "faults must be a list of 1 to 50"),
    ({"faults": ["step"]}, "faults[0] must be a table"),
    ({"faults": [{**FAULT, "onset": 3}]}, "faults[0]: unknown key 'onset'"),
    ({"faults": [{"fault_class": "step", "sensor": "uv"}]}, "faults[0]: missing key 'size'"),
    ({"faults": [{**FAULT, "fault_class": "jump"}]}, "faults[0].fault_class must be one of"),
    ({"faults": [{**FAULT, "sensor": "gps"}]}, "faults[0].sensor must be one of"),
    ({"faults": [{**FAULT, "size": -1.0}]}, "faults[0].size must be a real number in (0, 100000]"),
    ({"faults": [FAULT, {"fault_class": "noise", "sensor": "uv", "size": 1.0}]},
     "faults[1].size must be a real number in (1, 100000]"),
    ({"pfa": 0.1}, "grid: unknown key 'pfa'"),
])
def test_bad_grid_field_is_one_line_naming_it(change, words):
    with pytest.raises(ValueError) as err:
        roc.check_grid({**GRID, **change})
    msg = str(err.value)
    assert words in msg and "\n" not in msg


def test_missing_grid_keys_are_named():
    with pytest.raises(ValueError, match="missing key 'faults'"):
        roc.check_grid({"thresholds": [1.0]})


def test_load_grid_reads_toml_and_json_alike(tmp_path):
    (tmp_path / "g.toml").write_text(
        'detector = "chi2"\nthresholds = [1e-3, 1e-7]\ndays = 0.5\n\n'
        '[[faults]]\nfault_class = "step"\nsensor = "uv"\nsize = 8.0\n')
    (tmp_path / "g.json").write_text(json.dumps(GRID))
    assert roc.load_grid(tmp_path / "g.toml") == roc.load_grid(tmp_path / "g.json")


@pytest.mark.parametrize("name, text, words", [
    ("g.yaml", "", "must end in .toml or .json"),
    ("g.toml", "thresholds = [", "is not valid TOML"),
    ("g.json", "{", "is not valid JSON"),
    ("g.json", json.dumps({**GRID, "days": 9}), "days must be a real number in [0.5, 5]"),
])
def test_load_grid_bad_file_is_one_line(tmp_path, name, text, words):
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(ValueError) as err:
        roc.load_grid(path)
    assert words in str(err.value) and "\n" not in str(err.value)


def test_load_grid_missing_file(tmp_path):
    with pytest.raises(ValueError, match="cannot be read"):
        roc.load_grid(tmp_path / "none.toml")


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 500))
def test_poisson_interval_is_garwoods_exact_limits(k):
    """At the limits the Poisson tail probabilities are 2.5 % each (0 events: lower limit 0)."""
    lo, hi = roc.poisson_interval(k)
    assert lo <= k <= hi
    assert stats.poisson.cdf(k, hi) == pytest.approx(0.025, rel=1e-6)
    if k:
        assert stats.poisson.sf(k - 1, lo) == pytest.approx(0.025, rel=1e-6)
    else:
        assert lo == 0.0


def test_roc_run_same_seed_same_record_and_a_large_step_is_found():
    camp = roc.campaign(GRID)
    a = roc.roc_run(**camp.params(0), seed=11)
    assert a == roc.roc_run(**camp.params(0), seed=11)
    assert [r["threshold"] for r in a["per_threshold"]] == [1e-7, 1e-3]
    assert all(r["detected"] for r in a["per_threshold"])       # an 8-sigma range step
    assert a["armed_days"] == pytest.approx(0.3)
    assert 0.55 * 43200 <= a["onset_s"] <= 0.70 * 43200 + 3


def _record(fc, detected, false_alarms, status="ok"):
    per = [{"threshold": t, "detected": d, "delay_s": 10.0 if d else None,
            "out_at_onset": False, "late": not d, "false_alarms": f}
           for t, d, f in zip((0.1, 1.0), detected, false_alarms, strict=True)]
    return {"status": status, "parameters": {"fault_class": fc, "sensor": "uv", "size": 3.0},
            "metrics": {"onset_s": 1.0, "armed_days": 0.5, "per_threshold": per}}


def test_roc_curve_pools_runs_per_threshold_with_intervals():
    runs = [_record("step", (False, True), (0, 2)), _record("ramp", (True, True), (1, 3)),
            _record("step", (True, True), (0, 0), status="failed")]
    c0, c1 = roc.roc_curve(runs)
    assert (c0["threshold"], c0["trials"], c0["detected"], c0["pd"]) == (0.1, 2, 1, 0.5)
    assert (c0["late"], c1["late"]) == (1, 0)                  # counted apart, not in pd
    assert c1["false_alarms"] == 5 and c1["armed_days"] == 1.0
    assert c1["false_alarms_per_day"] == 5.0
    for row in (c0, c1):
        assert row["pd_lo"] <= row["pd"] <= row["pd_hi"]
        lo, hi = roc.poisson_interval(row["false_alarms"])
        assert row["false_alarms_per_day_hi"] == pytest.approx(hi / row["armed_days"])
        assert row["false_alarms_per_day_lo"] == pytest.approx(lo / row["armed_days"])
    by = roc.roc_curve(runs, by_fault=True)
    assert [(r["fault_class"], r["threshold"], r["pd"]) for r in by] == [
        ("ramp", 0.1, 1.0), ("ramp", 1.0, 1.0), ("step", 0.1, 0.0), ("step", 1.0, 1.0)]
    assert roc.curve_csv(roc.roc_curve(runs)).splitlines()[0] == ",".join(roc.CURVE_COLUMNS)


def test_campaign_resumes_and_writes_the_curve(tmp_path):
    grid = {**GRID, "faults": [FAULT, {"fault_class": "spike", "sensor": "cns", "size": 12.0}]}
    first = run_campaign(roc.campaign(grid), 2, seed=4, out=tmp_path, engine="serial")
    again = run_campaign(roc.campaign(grid), 2, seed=4, out=tmp_path, engine="serial")
    assert (first.computed, again.reused, again.computed) == (2, 2, 0)
    assert again.runs() == first.runs()
    data = roc.write_curve(tmp_path, grid, again.runs(), 4)
    assert json.loads((tmp_path / "roc.json").read_text()) == data
    assert len((tmp_path / "roc.csv").read_text().splitlines()) == 3       # header + 2
    assert [r["trials"] for r in data["curve"]] == [2, 2]
    with pytest.raises(ValueError, match="another"):
        run_campaign(roc.campaign({**grid, "thresholds": [1e-5]}), 2, seed=4, out=tmp_path,
                     engine="serial")


def test_shipped_curves_are_consistent():
    data = roc.load_curves()
    assert set(data["curves"]) == {"combined", "chi2"}
    for det, cur in data["curves"].items():
        grid = roc.check_grid(cur["grid"])
        assert grid["detector"] == det
        assert [r["threshold"] for r in cur["curve"]] == grid["thresholds"]
        for r in cur["curve"]:
            assert r["pd_lo"] <= r["pd"] <= r["pd_hi"]
            assert r["detected"] + r["late"] <= r["trials"]
            assert (r["false_alarms_per_day_lo"] <= r["false_alarms_per_day"]
                    <= r["false_alarms_per_day_hi"])
            assert r["trials"] == cur["runs"]


@pytest.mark.parametrize(("detector", "threshold"), [("combined", 1.0), ("chi2", 1e-5)])
def test_shipped_curve_runs_recompute(detector, threshold):
    """The stored first run of each curve (the grid's first fault), at one threshold,
    recomputed from its seed by the code here: the same decisions (detected, late, out at
    onset, false alarms), the delay to 30 s."""
    chk = roc.load_curves()["curves"][detector]["checks"][0]
    fresh, = roc.roc_run(**{**chk["parameters"], "thresholds": [threshold]},
                         seed=chk["seed"])["per_threshold"]
    old = next(r for r in chk["metrics"]["per_threshold"] if r["threshold"] == threshold)
    for key in ("detected", "late", "out_at_onset", "false_alarms"):
        assert fresh[key] == old[key], (key, old, fresh)
    if old["detected"]:
        assert abs(fresh["delay_s"] - old["delay_s"]) <= 30.0


def test_plot_roc_draws_one_curve_per_detector():
    data = roc.load_curves()
    fig = roc.plot_roc({d: c["curve"] for d, c in data["curves"].items()})
    ax = fig.axes[0]
    assert [t.get_text() for t in ax.get_legend().get_texts()] == list(data["curves"])
    assert ax.get_xscale() == "symlog"
    plt.close(fig)


def test_corrupt_shipped_curves_are_refused_with_the_row(tmp_path):
    data = roc.load_curves()
    data["curves"]["chi2"]["curve"][1]["pd"] = float("nan")    # json.dumps writes NaN
    path = tmp_path / "curves.json"
    path.write_text(json.dumps(data))
    with pytest.raises(ValueError, match=r"curves.json', chi2: row 1 has NaN in pd"):
        roc.load_curves(path)
    path.write_text('{"curves": []}')
    with pytest.raises(ValueError, match="must hold a table 'curves'"):
        roc.load_curves(path)


def _grid_record(index, detector="combined", days=0.5):
    rec = _record("step", (True, False), (0, 1))
    rec["index"] = index
    rec["parameters"].update(detector=detector, days=days, thresholds=[0.1, 1.0])
    return rec


@pytest.mark.parametrize(("runs", "words"), [
    ([], "runs must hold at least one run record, got an empty list"),
    ({"status": "ok"}, "runs must be a list of run records"),
    ("abc", "runs must be a list of run records"),
    ([_grid_record(0), _grid_record(0)], "runs lists run index 0 twice (runs[0] and runs[1])"),
    ([_grid_record(0), {**_grid_record(1), "parameters": {
        k: v for k, v in _grid_record(1)["parameters"].items() if k != "detector"}}],
     "runs[1] is a run of another grid"),
    # review 35m pattern H: chi2's alpha is in (0, 1): no grid of chi2 holds 1.0
    ([_grid_record(0, detector="chi2")],
     "runs[0]['parameters']['thresholds'][1] must be a real number in (0, 1), got 1.0"),
    ([_grid_record(0), _grid_record(1, days=2.0)], "runs[1] is a run of another grid"),
    ([{**_grid_record(0), "metrics": {"per_threshold": []}}], "runs[0]['metrics']['armed_days'] is "
                                                              "missing"),
    ([{**_grid_record(0), "metrics": {"armed_days": 0.0, "per_threshold": []}}],
     "runs[0]['metrics']['armed_days'] is 0.0, not a number in (0, 1e+100]"),
    ([{**_grid_record(0), "metrics": {"armed_days": 0.5, "per_threshold": [
        {"threshold": 0.1, "detected": True, "late": False, "delay_s": 1.0, "false_alarms": -3}]}}],
     "runs[0]['metrics']['per_threshold'][0]['false_alarms'] is -3, not an integer in [0, "
     "1e+09]"),
])
def test_roc_curve_refuses_runs_it_cannot_pool(runs, words):
    # review 35d D26: these gave [], TypeError, KeyError, ZeroDivisionError, a negative rate,
    # a pooled curve of two grids, or a message naming poisson_interval's k
    with pytest.raises(ValueError) as info:
        roc.roc_curve(runs)
    assert words in str(info.value)


def test_a_grid_fault_twice_is_refused_and_a_json_key_twice_too(tmp_path):  # review 35d D6/D7
    fault = {"fault_class": "step", "sensor": "uv", "size": 3.0}
    with pytest.raises(ValueError, match=r"faults lists \('step', 'uv', 3.0\) twice"):
        roc.check_grid({"thresholds": [1.0], "faults": [fault, dict(fault)]})
    path = tmp_path / "grid.json"
    path.write_text('{"detector": "chi2", "thresholds": [0.001], "faults": [{"fault_class": '
                    '"step", "sensor": "uv", "size": 3.0}], "detector": "combined"}')
    with pytest.raises(ValueError, match="gives the key 'detector' twice"):
        roc.load_grid(path)


def test_write_curve_makes_its_folder(tmp_path):  # review 35d D27: a FileNotFoundError
    out = tmp_path / "a" / "b"
    roc.write_curve(out, {"thresholds": [0.1, 1.0], "faults": [
        {"fault_class": "step", "sensor": "uv", "size": 3.0}]}, [_grid_record(0)], 0)
    assert (out / "roc.json").is_file() and (out / "roc.csv").is_file()


@pytest.mark.parametrize("bad", [{}, 5])
def test_loaders_refuse_a_path_that_is_no_path(bad):  # review 35d D37's class: TypeError
    with pytest.raises(ValueError, match=r"^grid file must be a path"):
        roc.load_grid(bad)
    with pytest.raises(ValueError, match=r"^ROC curves must be a path"):
        roc.load_curves(bad)


@pytest.mark.parametrize("bad", ["abc", None, [3]])
def test_curve_csv_refuses_what_is_no_list_of_rows(bad):  # review 35d D37's class: AttributeError
    with pytest.raises(ValueError, match=r"^rows(\[0\])? must be a (list of )?curve row"):
        roc.curve_csv(bad)


def test_roc_run_refuses_a_seed_above_the_records_range():
    """Review 35e: 2^63 was taken (check_int without its upper end)."""
    with pytest.raises(ValueError, match=r"^seed must be an integer in \[0, 9223372036854775807\]"):
        roc.roc_run("step", "uv", 2.0, "combined", [1.0], seed=2**63)


def test_plot_roc_and_curve_csv_refuse_what_is_no_curve_by_name():
    """Issue 35 (review 35h): a bool or a list for ``curves`` was an AttributeError ('items'),
    and a 0-d array of rows numpy's 'iteration over a 0-d array'."""
    import numpy as np

    with pytest.raises(ValueError, match=r"^curves must be a dict of label -> roc_curve rows, got bool"):
        roc.plot_roc(True)
    with pytest.raises(ValueError, match=r"^curves must hold at least one labelled curve$"):
        roc.plot_roc({})
    with pytest.raises(ValueError, match=r"^curves\['chi2'\]\[0\] must be a roc_curve row"):
        roc.plot_roc({"chi2": [{"pd": 0.5}]})
    with pytest.raises(ValueError, match=r"^rows must be a list of curve rows \(dicts\), got array\(1\.\)$"):
        roc.curve_csv(np.array(1.0))


def test_poisson_interval_refuses_a_count_beyond_its_law_by_name():
    """Issue 35: k = 1e30 was refused as dof (the chi-square's degrees of freedom, 2k + 2)."""
    with pytest.raises(ValueError, match=r"^k must be an integer in \[0, 499999999999\], got 10{30}$"):
        roc.poisson_interval(10**30)
    assert roc.poisson_interval(499_999_999_999)[1] > 4.99e11


@pytest.mark.parametrize(("rows", "words"), [
    ([{"a": 1}], r"^rows\[0\] must be a curve row \(a dict with threshold, trials"),
    ([], r"^rows must hold at least one curve row, got an empty list"),
    ([dict.fromkeys(roc.CURVE_COLUMNS, 1), {**dict.fromkeys(roc.CURVE_COLUMNS, 1), "x": 2}],
     r"^rows\[1\] must have the columns of rows\[0\]"),
])
def test_curve_csv_refuses_rows_that_are_no_curve(rows, words):
    """Review 35j (5) 37: rows without the curve's columns were written ('a\\n1\\n'), no row as ''."""
    with pytest.raises(ValueError, match=words):
        roc.curve_csv(rows)


@pytest.mark.parametrize(("args", "words"), [
    (("step", "xnav", 3.0, "combined", []), r"^thresholds must name at least one value of rate_per_day"),
    (("step", "xnav", 3.0, "chi2", [1e-3, 1e-3]), r"^thresholds lists 0.001 twice"),
    (("step", "xnav", 3.0, "chi2", [2.0]), r"^thresholds\[0\] \(alpha\) must be a real number in \(0, 1\)"),
    (("stpe", "xnav", 3.0, "chi2", [0.1]), r"^fault_class must be one of"),
    (("noise", "xnav", 0.5, "chi2", [0.1]), r"^size of a noise fault must be a ratio > 1"),
])
def test_roc_run_refuses_before_any_run(args, words, monkeypatch):
    """Review 35j (5) 36: no threshold ran a half-day simulation for nothing."""
    from xnavlab.mars.navigation import scenarios

    monkeypatch.setattr(scenarios, "prepare", lambda *a, **k: pytest.fail("the run started"))
    with pytest.raises(ValueError, match=words):
        roc.roc_run(*args, seed=0)


def test_write_curve_refuses_a_seed_that_is_no_integer(tmp_path):
    """Review 35j, class of (5): int(seed) took 1.5 as 1 and 'x' as Python's 'invalid literal'."""
    for seed in (1.5, "x"):
        with pytest.raises(ValueError, match=r"^seed must be an integer"):
            roc.write_curve(tmp_path, roc.DEFAULT_GRID, [], seed)


@pytest.mark.parametrize("ax", [1.0, "x", True])
def test_plot_roc_refuses_an_ax_that_is_no_axes(ax):
    """Review 35k (1) 24: a non-Axes ax gave AttributeError 'no attribute figure'."""
    with pytest.raises(ValueError, match="^ax must be a 2-D rectilinear matplotlib Axes"):
        roc.plot_roc({"a": [dict.fromkeys(("threshold", "pd", "pd_lo", "pd_hi",
                                           "false_alarms_per_day", "false_alarms_per_day_lo",
                                           "false_alarms_per_day_hi"), 0.5)]}, ax=ax)


def test_roc_refuses_an_empty_or_foreign_per_threshold():
    """Review 35l (5) 3, (6) 4: per_threshold [] gave an empty curve and a threshold not of
    the grid a row of its own; the store's check took both."""
    camp = roc.campaign(roc.DEFAULT_GRID)
    thr = camp.params(0)["thresholds"]
    row = {"detected": True, "late": False, "false_alarms": 0, "delay_s": 1.0}
    good = {"armed_days": 0.3, "per_threshold": [dict(row, threshold=t) for t in thr]}
    assert camp.check_metrics(good) is None
    assert "is empty" in camp.check_metrics({**good, "per_threshold": []})
    other = {**good, "per_threshold": [dict(row, threshold=0.5)] + good["per_threshold"][1:]}
    assert "not the grid's" in camp.check_metrics(other)
    assert "delay_s is -50.0" in camp.check_metrics(
        {**good, "per_threshold": [dict(row, threshold=t, delay_s=-50.0) for t in thr]})


ROW = {"threshold": 1.0, "pd": 0.5, "pd_lo": 0.3, "pd_hi": 0.7, "false_alarms_per_day": 2.0,
       "false_alarms_per_day_lo": 1.0, "false_alarms_per_day_hi": 3.5}


@pytest.mark.parametrize("projection, word", [("3d", "'3d' Axes"), ("polar", "'polar' Axes")])
def test_plot_roc_refuses_an_axes_of_another_projection(projection, word):
    """Review 35m (1) 3: a 3-D Axes was Axes3D.errorbar's TypeError, a polar one
    'The xscale cannot be set on a polar plot'."""
    from matplotlib.figure import Figure

    ax = Figure().add_subplot(projection=projection)
    with pytest.raises(ValueError, match=rf"^ax must be a 2-D rectilinear matplotlib Axes, got a {word}"):
        roc.plot_roc({"chi2": [ROW]}, ax=ax)
    assert not ax.lines and not ax.collections  # refused before anything was drawn


def test_plot_roc_refuses_an_axes_removed_from_its_figure_and_draws_on_a_subfigure():
    """Review 35m (1) 3: an Axes removed from its figure was "'NoneType' object has no
    attribute 'tight_layout'"; a subfigure's Axes gives its root figure."""
    from matplotlib.figure import Figure

    fig = Figure()
    ax = fig.subplots()
    ax.remove()
    with pytest.raises(ValueError, match=r"^ax must be a 2-D rectilinear matplotlib Axes of a figure"):
        roc.plot_roc({"chi2": [ROW]}, ax=ax)
    for bad in ("ax", 1.0, fig):
        with pytest.raises(ValueError, match=r"^ax must be a 2-D rectilinear matplotlib Axes, got"):
            roc.plot_roc({"chi2": [ROW]}, ax=bad)
    root = Figure()
    assert roc.plot_roc({"chi2": [ROW]}, ax=root.subfigures(1, 2)[0].subplots()) is root
    ax = Figure().subplots()
    assert roc.plot_roc({"chi2": [ROW]}, ax=ax) is ax.figure


@pytest.mark.parametrize("change, message", [
    ({"pd_lo": 0.9}, r"^curves\['chi2'\]\[0\]\['pd_lo'\] must be at most pd \(0.5\), got 0.9"),
    ({"pd_hi": 0.4}, r"^curves\['chi2'\]\[0\]\['pd_hi'\] must be at least pd \(0.5\), got 0.4"),
    ({"false_alarms_per_day_lo": 2.5},
     r"^curves\['chi2'\]\[0\]\['false_alarms_per_day_lo'\] must be at most false_alarms_per_day"),
    ({"false_alarms_per_day_hi": 1.5},
     r"^curves\['chi2'\]\[0\]\['false_alarms_per_day_hi'\] must be at least false_alarms_per_day"),
])
def test_plot_roc_names_an_interval_that_misses_its_value(change, message):
    """Review 35m (2) 2: pd_lo 0.9 > pd 0.5 was matplotlib's "'yerr' must not contain negative
    values"."""
    with pytest.raises(ValueError, match=message):
        roc.plot_roc({"chi2": [dict(ROW, **change)]})


@pytest.mark.parametrize("change, message", [
    ({"pd": 1.5, "pd_hi": 1.6}, r"^curves\['chi2'\]\[0\]\['pd'\] must be a real number in \[0, 1\], got 1.5"),
    ({"threshold": float("nan")},
     r"^curves\['chi2'\]\[0\]\['threshold'\] must be a real number in \(0, inf\)"),
    ({"threshold": 0.0}, r"^curves\['chi2'\]\[0\]\['threshold'\] must be a real number in \(0, inf\)"),
    ({"pd_lo": -0.1}, r"^curves\['chi2'\]\[0\]\['pd_lo'\] must be a real number in \[0, 1\]"),
    ({"false_alarms_per_day": float("inf")},
     r"^curves\['chi2'\]\[0\]\['false_alarms_per_day'\] must be"),
    ({"pd": "0.5"}, r"^curves\['chi2'\]\[0\]\['pd'\] must be a real number"),
])
def test_plot_roc_refuses_a_meaningless_row(change, message):
    """Review 35m (5) 4: pd 1.5 (with pd_hi 1.6) and threshold NaN were drawn."""
    with pytest.raises(ValueError, match=message):
        roc.plot_roc({"chi2": [dict(ROW, **change)]})


@pytest.mark.parametrize("k, n", [(0, 3), (10, 10), (0, 6), (25, 25)])
def test_plot_roc_draws_a_wilson_interval_rounded_past_its_end(k, n):
    """Review 35m (2) 2: roc_curve's Wilson ends at pd 0 or 1 round past it (pd_lo 6e-17 at
    pd 0, pd_hi 1 - 1e-16 at pd 1): such a row of a real campaign was matplotlib's 'yerr' error."""
    from xnavlab.core.montecarlo import wilson_interval

    lo, hi = wilson_interval(k, n)
    fig = roc.plot_roc({"chi2": [dict(ROW, pd=k / n, pd_lo=lo, pd_hi=hi)]})
    assert len(fig.axes) == 1
    plt.close(fig)


@pytest.mark.parametrize(("change", "words"), [
    ({"fault_class": "bogus"}, "['fault_class'] must be one of 'step'"),
    ({"sensor": 3}, "['sensor'] must be one of 'uv'"),
    ({"size": -1.0}, "['size'] must be a real number in (0, 100000], got -1.0"),
    ({"detector": "x"}, "['detector'] must be one of 'combined'"),
    ({"days": 0.1}, "['days'] must be a real number in [0.5, 5]"),
    ({"thresholds": 3}, "['thresholds'] must be a list"),
])
def test_roc_curve_refuses_parameters_of_no_grid_fault(change, words):
    """Review 35m pattern H: roc_curve read a run's fault class, sensor and size without a
    check; a run of fault class "bogus" became a by-fault row of its own."""
    rec = _record("step", (True, False), (0, 1))
    rec["parameters"].update(change)
    with pytest.raises(ValueError) as err:
        roc.roc_curve([rec], by_fault=True)
    assert str(err.value).startswith("runs[0]['parameters']" + words)
    with pytest.raises(ValueError, match=r"^runs\[0\]\['parameters'\] must be a table"):
        roc.roc_curve([dict(rec, parameters=3)])
