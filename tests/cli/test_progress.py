"""Progress bars of the slow paths on the command line: shown on a terminal, never with --quiet."""

import json
import sys

from xnavlab.cli import main

GRID = ('detector = "chi2"\nthresholds = [1e-5]\ndays = 0.5\n\n'
        '[[faults]]\nfault_class = "spike"\nsensor = "cns"\nsize = 12.0\n')


def test_run_mars_numpy_bar_on_a_terminal_and_nothing_with_quiet(monkeypatch, capsys):
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    argv = ["run", "mars", "--days", "0.01", "--backend", "numpy"]  # every subsystem measures
    assert main(argv) == 0
    assert "mars (numpy, ekf)" in capsys.readouterr().err
    assert main([*argv, "--quiet"]) == 0
    quiet = capsys.readouterr()
    assert quiet.err == "" and "position_error_m" in quiet.out
    assert main([*argv, "--json"]) == 0
    out = capsys.readouterr()
    assert out.err == "" and json.loads(out.out)["backend"] == "numpy"


def test_a_warning_about_the_input_is_printed_once_also_with_quiet(tmp_path, capsys):
    """--quiet silences progress, not warnings about the user's input (review 35 B.8)."""
    assert main(["run", "mars", "--days", "0.005", "--quiet"]) == 0
    err = capsys.readouterr().err
    assert err == ("xnavlab: warning: xnav gets no measurement in 0.005 days (its first comes at "
                   "500 s): run longer or drop it from subsystems\n")
    path = tmp_path / "s.toml"
    path.write_text("[run]\nrecord_dt = 86400.0\n")
    assert main(["run", "mars", "--scenario", str(path), "--days", "0.05", "--json", "--faults",
                 "uv.range:step:1e5@1000+10"]) == 0
    out = capsys.readouterr()       # the summary and the score both take the RMS: warned once
    assert out.err.splitlines() == [
        "xnavlab: warning: position_error_m and velocity_error_mps are the RMS of 1 record (from "
        "settle_days = 0.025 with record_dt = 86400 s): lower record_dt or settle_days, or run "
        "longer"]
    assert json.loads(out.out)["updates_uv"] > 0


def test_campaign_bar_and_nothing_with_quiet_or_json(tmp_path, capsys):
    grid = tmp_path / "grid.toml"
    grid.write_text(GRID)
    base = ["campaign", "roc", "--grid", str(grid), "--workers", "1", "--out", str(tmp_path / "c")]
    assert main([*base, "--runs", "1", "--quiet"]) == 0
    assert capsys.readouterr().err == ""
    assert main([*base, "--runs", "2"]) == 0                  # one more run: the bar shows it
    assert "2/2" in capsys.readouterr().err
    assert main([*base, "--runs", "3", "--json"]) == 0
    out = capsys.readouterr()
    assert out.err == "" and json.loads(out.out)["computed"] == 1


def test_reproduce_all_bar_and_nothing_with_quiet_or_json(monkeypatch, capsys):
    from xnavlab import reproduce

    monkeypatch.setattr(reproduce, "ids", lambda: ["mars-orbit"])
    assert main(["reproduce", "--all"]) == 0
    assert "reproductions: 100%" in capsys.readouterr().err
    assert main(["reproduce", "--all", "--quiet"]) == 0
    assert capsys.readouterr().err == ""
    assert main(["reproduce", "--all", "--json"]) == 0
    out = capsys.readouterr()
    assert out.err.strip() == reproduce.headline([reproduce.run("mars-orbit")])
    assert json.loads(out.out)[0]["id"] == "mars-orbit"
