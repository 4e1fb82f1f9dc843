"""Headline accuracies as Monte Carlo means: intervals, the cache, the refusals."""

import numpy as np
import pytest

from xnavlab.mars.navigation import headline


def test_mean_interval_is_the_student_t_interval_of_the_mean():
    v = np.random.default_rng(0).normal(10.0, 2.0, 32)
    r = headline.mean_interval(v)
    assert r["lo"] < r["mean"] < r["hi"] and r["n"] == 32
    assert r["hi"] - r["lo"] == pytest.approx(2 * 2.0395 * v.std(ddof=1) / np.sqrt(32), rel=1e-3)
    with pytest.raises(ValueError, match="at least two numbers"):
        headline.mean_interval([1.0])


@pytest.mark.parametrize(("bad", "message"), [
    (np.array([1 + 1j, 2, 3]), "^values must hold real numbers, got complex values"),
    ([1.0, np.nan, 3.0], r"^values must contain only finite numbers \(no NaN or inf\)"),
    (["a", "b"], "^values must be an array of finite numbers"),
    ([[1.0, 2.0], [3.0, 4.0]], r"^values must be a 1-D array \(shape \(n,\)\), got shape \(2, 2\)"),
])
def test_mean_interval_names_what_is_wrong_with_values(bad, message):
    """Review 35b N13: an imaginary part dropped, 'got 3' for a NaN, numpy's own messages."""
    with pytest.raises(ValueError, match=message):
        headline.mean_interval(bad)


@pytest.mark.parametrize("flag", ["faults", "cache", "progress", "shipped"])
def test_a_flag_is_a_real_bool_not_a_truthy_string(flag):
    """Review 35b N19: headline_run(faults="no") ran with faults."""
    with pytest.raises(ValueError, match=f"^{flag} must be True or False, got 'no'"):
        headline.headline_numbers(n_seeds=2, days=0.01, **{"faults": False, flag: "no"})
    with pytest.raises(ValueError, match="^faults must be True or False, got 'no'"):
        headline.headline_run(seed=0, days=0.01, faults="no")


def test_headline_runs_are_stored_and_reused(tmp_path, monkeypatch):
    monkeypatch.setenv("XNAVLAB_CACHE", str(tmp_path))
    a = headline.headline_numbers(n_seeds=3, days=0.2, faults=False, workers=1)
    b = headline.headline_numbers(n_seeds=3, days=0.2, faults=False, workers=1)
    assert a["quantities"] == b["quantities"] and a["directory"] == b["directory"]
    assert a["directory"].startswith(str(tmp_path))
    q = a["quantities"]
    assert set(q) >= {"fused_position_m", "fused_velocity_mps", "local_position_m.xnav",
                      "local_position_m.uv", "local_position_m.cns"}
    assert q["fused_position_m"]["lo"] <= q["fused_position_m"]["mean"] <= q["fused_position_m"]["hi"]



def test_two_processes_asking_at_once_share_one_stored_campaign(tmp_path):
    """A test and a chapter run side by side (pytest -n 2) both get the numbers: the second
    waits for the first instead of meeting the store's lock, then reads the same runs."""
    import json
    import os
    import subprocess
    import sys

    code = ("import json; from xnavlab.mars.navigation import headline; "
            "h = headline.headline_numbers(n_seeds=3, days=0.2, faults=False, workers=1); "
            "print(json.dumps(h['quantities']['fused_position_m']))")
    env = {**os.environ, "XNAVLAB_CACHE": str(tmp_path)}
    procs = [subprocess.Popen([sys.executable, "-c", code], env=env, text=True,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE) for _ in range(2)]
    outs = [p.communicate(timeout=600) for p in procs]
    assert [p.returncode for p in procs] == [0, 0], [err for _, err in outs]
    first, second = (json.loads(out) for out, _ in outs)
    assert first == second and first["n"] == 3

def test_faults_need_the_papers_thirty_days():
    with pytest.raises(ValueError, match="faults needs days = 30"):
        headline.headline_numbers(n_seeds=2, days=5.0, faults=True, cache=False)


#: README row label -> (quantity, decimals as printed)
README_ROWS = {
    "fused position error, fault-free (m)": ("fused_position_m", 2),
    "fused velocity error, fault-free (m/s)": ("fused_velocity_mps", 4),
    "fused position error, the paper's faults, combined detector (m)": ("faulty_position_m", 2),
    "fused velocity error, the paper's faults, combined detector (m/s)": ("faulty_velocity_mps", 4),
    "faulty over fault-free position error, same seed": ("fault_ratio", 3),
    "fused position error, the paper's faults, the paper's wavelet detector (m)":
        ("wavelet_position_m", 2),
}


def test_the_readme_states_the_campaigns_numbers():
    """The README's headline table is the 32-seed campaign's (computed once, then cached)."""
    from pathlib import Path

    text = (Path(__file__).resolve().parents[3] / "README.md").read_text()
    h = headline.headline_numbers()
    for label, (key, dec) in README_ROWS.items():
        row = next((ln for ln in text.splitlines() if ln.startswith(f"| {label} |")), None)
        assert row is not None, f"README has no row {label!r}"
        q = h["quantities"][key]
        cell = row.split("|")[2]                   # "mean [lo, hi]" as printed
        printed = [float(v) for v in cell.replace("[", " ").replace("]", " ").replace(",", " ").split()]
        for value, stated in zip((q["mean"], q["lo"], q["hi"]), printed, strict=True):
            # one unit of the last printed digit: the rounding of a value near a half-unit
            # may differ between CPUs' BLAS kernels, nothing more
            assert abs(value - stated) <= 10.0 ** -dec, (label, key, value, row)
    assert f"{h['n_seeds']} noise seeds" in text


def test_the_default_campaign_is_read_from_the_shipped_runs():
    h = headline.headline_numbers()
    assert h["source"] == "shipped" and h["n_seeds"] == headline.SHIPPED["n_seeds"]
    assert h["directory"] is None
    runs = headline.load_shipped()["runs"]
    assert h["runs"]["fused_position_m"] == [r["metrics"]["fused_position_m"] for r in runs]


#: Relative agreement of a recomputed run with the shipped one: far above the last digits an
#: OpenBLAS kernel family or a compiler moves (1e-12 here), far below any change of the model.
RECOMPUTE_RTOL = 1e-6


def test_the_shipped_runs_recompute_from_their_seeds():
    """The first shipped run, computed again from its seed by the code here: every metric to
    RECOMPUTE_RTOL. A change that moves it fails here until bench_headline.py --write."""
    first = headline.load_shipped()["runs"][0]
    fresh = headline.headline_run(seed=first["seed"], days=headline.SHIPPED["days"],
                                  faults=headline.SHIPPED["faults"])
    assert sorted(fresh) == sorted(first["metrics"])
    for key, value in first["metrics"].items():
        assert fresh[key] == pytest.approx(value, rel=RECOMPUTE_RTOL, abs=1e-12), key


@pytest.mark.parametrize(("edit", "message"), [
    (lambda d: d.update(campaign={**d["campaign"], "seed": 1}), "must hold the campaign"),
    (lambda d: d["runs"].pop(3), "must hold runs 0 to 31 in order"),
    (lambda d: d["runs"][2]["metrics"].update(fused_position_m=None), "run 2 must hold"),
])
def test_a_broken_shipped_table_is_one_line_naming_it(tmp_path, edit, message):
    import json

    data = json.loads(headline.RUNS_PATH.read_text())
    edit(data)
    path = tmp_path / "headline_runs.json"
    path.write_text(json.dumps(data))
    with pytest.raises(ValueError, match=message):
        headline.load_shipped(path)


def test_numbers_of_names_the_quantity_that_is_not_numbers():
    with pytest.raises(ValueError, match=r"^runs' b: values must contain only finite numbers"):
        headline.numbers_of([{"a": 1.0, "b": np.nan}, {"a": 2.0, "b": 1.0}])


@pytest.mark.parametrize(("runs", "words"), [
    ("abc", r"^runs must be a list of metrics records \(dicts\), got 'abc'$"),
    ([], r"^runs must hold the metrics of at least two runs, got an empty list$"),
    ([{"a": 1.0, "b": 2.0}, {"a": 3.0}],
     r"^runs\[1\] must hold the quantities of runs\[0\], but 'b' is in runs\[0\] only$"),
    ([{"a": 1.0}, {"a": 3.0, "c": 1.0}],
     r"^runs\[1\] must hold the quantities of runs\[0\], but 'c' is in runs\[1\] only$"),
])
def test_numbers_of_refuses_runs_that_are_no_list_of_like_records(runs, words):
    """Review 35e: a string was a TypeError, a quantity missing from a later run a KeyError,
    and a quantity only a later run had was dropped in silence."""
    with pytest.raises(ValueError, match=words):
        headline.numbers_of(runs)


def test_headline_records_takes_its_folder_as_a_str(tmp_path):
    """Review 35j (1) 18: out='/tmp/x' raised AttributeError 'str' object has no attribute
    'parent' (only a Path worked)."""
    out = str(tmp_path / "hl")
    runs = headline.headline_records(n_seeds=2, days=0.02, faults=False, out=out, workers=1)
    assert [r["index"] for r in runs] == [0, 1] and (tmp_path / "hl").is_dir()
    with pytest.raises(ValueError, match=r"^out must be a path \(a str or pathlib.Path\), got dict"):
        headline.headline_records(n_seeds=2, days=0.02, faults=False, out={})


def test_headline_records_refuses_the_fault_schedule_on_a_short_run():
    """Review 35j: every run failed (the paper's faults need 30 days): an empty list."""
    with pytest.raises(ValueError, match=r"^faults needs days = 30 \(the paper's schedule runs "
                                         r"to 27.84 days\), got 0.02$"):
        headline.headline_records(n_seeds=2, days=0.02)
    with pytest.raises(ValueError, match=r"^path must be a path \(a str or pathlib.Path\), got dict"):
        headline.load_shipped({})


def test_load_shipped_names_its_path():
    """Review 35k (tests/test_default_inputs.py): a path of the wrong kind was refused without
    naming the parameter."""
    with pytest.raises(ValueError, match=r"^path, the headline runs 'x' must end in \.json"):
        headline.load_shipped("x")
