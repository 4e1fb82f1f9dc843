"""Progress bars of the slow paths on the command line: shown on a terminal, never with --quiet."""

import json
import sys

from xnavlab.cli import main

GRID = ('detector = "chi2"\nthresholds = [1e-5]\ndays = 0.5\n\n'
        '[[faults]]\nfault_class = "spike"\nsensor = "cns"\nsize = 12.0\n')


def test_run_mars_numpy_bar_on_a_terminal_and_nothing_with_quiet(monkeypatch, capsys):
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    argv = ["run", "mars", "--days", "0.005", "--backend", "numpy"]
    assert main(argv) == 0
    assert "mars (numpy, ekf)" in capsys.readouterr().err
    assert main([*argv, "--quiet"]) == 0
    quiet = capsys.readouterr()
    assert quiet.err == "" and "position_error_m" in quiet.out
    assert main([*argv, "--json"]) == 0
    out = capsys.readouterr()
    assert out.err == "" and json.loads(out.out)["backend"] == "numpy"


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
