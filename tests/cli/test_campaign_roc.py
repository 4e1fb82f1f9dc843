"""``python -m xnavlab campaign roc``: the curve files, the JSON summary, resuming, bad input."""

import json

import pytest

from xnavlab.cli import main
from xnavlab.mars.studies import roc

GRID = ('detector = "chi2"\nthresholds = [1e-7, 1e-3]\ndays = 0.5\n\n'
        '[[faults]]\nfault_class = "step"\nsensor = "uv"\nsize = 8.0\n')


@pytest.fixture
def grid_file(tmp_path):
    path = tmp_path / "grid.toml"
    path.write_text(GRID)
    return path


def test_roc_writes_the_curve_and_resumes(tmp_path, grid_file, capsys):
    out = str(tmp_path / "camp")
    argv = ["campaign", "roc", "--grid", str(grid_file), "--runs", "2", "--seed", "3",
            "--workers", "1", "--out", out]
    assert main([*argv, "--quiet"]) == 0
    printed = capsys.readouterr()
    assert "threshold" in printed.out and "Wilson" in printed.out and printed.err == ""
    data = json.loads((tmp_path / "camp" / "roc.json").read_text())
    assert [r["threshold"] for r in data["curve"]] == [1e-7, 1e-3]
    assert all(r["trials"] == 2 and r["pd"] == 1.0 for r in data["curve"])
    csv_lines = (tmp_path / "camp" / "roc.csv").read_text().splitlines()
    assert csv_lines[0].split(",") == list(roc.CURVE_COLUMNS) and len(csv_lines) == 3
    assert main([*argv, "--json"]) == 0
    again = json.loads(capsys.readouterr().out)
    assert (again["reused"], again["computed"], again["failed"]) == (2, 0, 0)
    assert again["curve"] == data["curve"] and again["grid"] == data["grid"]
    assert (tmp_path / "camp" / "summary.json").exists()
    _the_pandas_recipe_of_the_roc_docs_reads_the_runs(tmp_path / "camp", data["curve"])


def _the_pandas_recipe_of_the_roc_docs_reads_the_runs(directory, curve):
    # xnavlab.mars.studies.roc's module docstring, as a reader would paste it: one row a (run, threshold)
    import pandas as pd

    from xnavlab.core.campaign import load_runs

    df = load_runs(directory).explode("metrics.per_threshold", ignore_index=True)
    long = pd.concat([df.drop(columns="metrics.per_threshold"),
                      pd.json_normalize(df["metrics.per_threshold"].tolist())], axis=1)
    pd_by = long.groupby(["parameters.fault_class", "threshold"])["detected"].mean()
    assert len(long) == 2 * 2 and list(pd_by.index.get_level_values("threshold")) == [1e-7, 1e-3]
    assert list(pd_by) == [r["pd"] for r in curve]


def _write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return str(path)


@pytest.mark.parametrize("name, text, extra, words", [
    ("g.toml", GRID.replace("1e-3", "2.0"), [], "thresholds[1] (alpha) must be a real number"),
    ("g.toml", GRID.replace('"chi2"', '"cusum"'), [], "detector must be one of"),
    ("g.toml", GRID.replace("0.5", "9"), [], "days must be a real number in [0.5, 5]"),
    ("g.toml", GRID.replace("8.0", "-1"), [], "faults[0].size must be a real number"),
    ("g.toml", GRID.replace('"uv"', '"gps"'), [], "faults[0].sensor must be one of"),
    ("g.toml", GRID + "onset = 5\n", [], "faults[0]: unknown key 'onset'"),
    ("g.toml", GRID.split("[[faults]]")[0], [], "missing key 'faults'"),
    ("g.toml", "thresholds = [", [], "is not valid TOML"),
    ("g.json", "{}", [], "missing key 'thresholds'"),
    ("g.txt", GRID, [], "must end in .toml or .json"),
    ("g.toml", GRID, ["--days", "1"], "takes its run length from the grid file's days"),
    ("g.toml", GRID, ["--runs", "0"], "--runs must be an integer in [1, 10000000]"),
])
def test_bad_roc_input_is_one_line_exit_2(tmp_path, capsys, name, text, extra, words):
    path = _write(tmp_path, name, text)
    runs = [] if "--runs" in extra else ["--runs", "2"]   # an option is given once
    argv = ["campaign", "roc", "--grid", path, *runs, "--out", str(tmp_path / "o"), *extra]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert words in err and err.count("\n") == 1, err
    assert not (tmp_path / "o" / "runs.jsonl").exists()


def test_missing_grid_file_is_one_line_exit_2(tmp_path, capsys):
    assert main(["campaign", "roc", "--grid", str(tmp_path / "none.toml"), "--runs", "1",
                 "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "cannot be read" in err and err.count("\n") == 1


def test_grid_is_refused_for_other_campaigns(tmp_path, grid_file, capsys):
    assert main(["campaign", "detectors", "--grid", str(grid_file), "--runs", "1",
                 "--out", str(tmp_path / "o")]) == 2
    assert "--grid is an option of campaign roc only" in capsys.readouterr().err


def test_unknown_campaign_lists_roc(tmp_path, capsys):
    assert main(["campaign", "rocs", "--runs", "1", "--out", str(tmp_path / "o")]) == 2
    assert "roc" in capsys.readouterr().err
