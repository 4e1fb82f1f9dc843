"""``python -m xnavlab run`` (xnavlab.cli.runners): the scenario table, the --out check, a short
Mars run with its files, and the one-line errors for bad flags."""

import json

import pytest

from xnavlab.cli import main, runners


def test_out_dir_accepts_none_or_a_directory_and_refuses_a_file(tmp_path):
    assert runners.out_dir(None) is None
    assert runners.out_dir(tmp_path / "new") == tmp_path / "new"
    (tmp_path / "f").write_text("")
    with pytest.raises(ValueError, match="^out must be a directory"):
        runners.out_dir(tmp_path / "f")


def test_every_runner_has_configure_execute_and_help():
    for name, (configure, execute, help_) in runners.RUNNERS.items():
        assert callable(configure) and callable(execute) and help_, name


@pytest.mark.parametrize(("flags", "name"), [
    (["--days", "0"], "days"), (["--days", "two"], "days"), (["--seed", "-1"], "seed"),
    (["--seed", "1.5"], "seed"), (["--mode", "sometimes"], "mode"), (["--backend", "gpu"], "backend"),
    (["--detector", "chi2", "--backend", "numpy", "--days", "0.01"], "backend numba"),
])
def test_a_bad_flag_exits_2_naming_it(flags, name, capsys):
    assert main(["run", "mars", *flags]) == 2
    err = capsys.readouterr().err.strip()
    assert name in err and len(err.splitlines()) == 1


def test_run_without_a_scenario_is_a_usage_error(capsys):
    assert main(["run"]) == 2
    assert "run needs a scenario: mars" in capsys.readouterr().err


def test_a_short_numpy_run_prints_json_and_writes_its_files(tmp_path, capsys):
    assert main(["run", "mars", "--days", "0.01", "--backend", "numpy", "--json",
                 "--out", str(tmp_path)]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["run_time_s"] >= summary["filter_time_s"] > 0.0
    assert json.loads((tmp_path / "mars_summary.json").read_text()) == summary
    assert (tmp_path / "mars_run.npz").stat().st_size > 0
