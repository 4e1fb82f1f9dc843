"""The command line: reproduce, list, bad input (one line, exit code 2)."""

import json
import subprocess
import sys

import pytest

from xnavlab import reproduce
from xnavlab.cli import main


def test_list(capsys):
    assert main(["reproduce", "--list"]) == 0
    assert "xnav-ranging" in capsys.readouterr().out


def test_reproduce_json(capsys):
    assert main(["reproduce", "xnav-ranging", "--json"]) == 0
    payload = json.loads(capsys.readouterr().out)
    assert payload["id"] == "xnav-ranging"
    assert payload["ok"] is True and payload["verdict"] in reproduce.HEADLINES
    assert set(payload) >= {"id", "verdict", "ok", "counts", "rows", "note", "figures", "error"}
    assert {row["verdict"] for row in payload["rows"]} <= set(reproduce.VERDICTS)
    assert {row["kind"] for row in payload["rows"]} == {"claim"}
    assert {row["name"] for row in payload["rows"]} >= {"B0531+21 ranging (m)", "B1821-24 ranging (m)"}


def test_reproduce_out_writes_figure(tmp_path, capsys):
    assert main(["reproduce", "xnav-ranging", "--out", str(tmp_path)]) == 0
    assert list(tmp_path.glob("*.png"))


@pytest.mark.parametrize(
    "argv",
    [["reproduce", "no-such-id"], ["reproduce", "--bogus"], ["frobnicate"], [], ["reproduce"]],
)
def test_bad_usage_is_one_line_exit_2(argv, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("xnavlab: error:")
    assert len(err.splitlines()) == 1


def test_module_entry_point():
    proc = subprocess.run(
        [sys.executable, "-m", "xnavlab", "reproduce", "nope"],
        capture_output=True, text=True, check=False,
    )
    assert proc.returncode == 2
    assert len(proc.stderr.strip().splitlines()) == 1
    assert "nope" in proc.stderr


def test_all_reports_a_raising_reproduction_as_failed(monkeypatch, capsys):
    from xnavlab import cli, reproduce

    monkeypatch.setattr(reproduce, "ids", lambda: ["xnav-ranging", "broken"])
    real_run = reproduce.run

    def fake_run(rid, out=None, **kw):
        if rid == "broken":
            raise ValueError("boom")
        return real_run(rid, out=out, **kw)

    monkeypatch.setattr(reproduce, "run", fake_run)
    assert cli.main(["reproduce", "--all"]) == 1
    out = capsys.readouterr().out
    assert "ValueError: boom" in out
    assert out.rstrip().endswith("; ERROR: broken")


def test_all_json_and_dashboard_say_the_same_words(monkeypatch, capsys):
    from xnavlab import cli, reproduce

    monkeypatch.setattr(reproduce, "ids", lambda: ["xnav-ranging", "broken"])
    real_run = reproduce.run

    def fake_run(rid, out=None, **kw):
        if rid == "broken":
            raise ValueError("boom | <b>")
        return real_run(rid, out=out, **kw)

    monkeypatch.setattr(reproduce, "run", fake_run)
    assert cli.main(["reproduce", "--all", "--json"]) == 1
    captured = capsys.readouterr()
    payload = json.loads(captured.out)
    results = [reproduce.run_or_fail(rid) for rid in reproduce.ids()]  # what the dashboard runs
    assert [p["verdict"] for p in payload] == [r.verdict for r in results]
    assert results[-1].verdict == "ERROR" and results[0].ok
    assert [[(row["name"], row["verdict"]) for row in p["rows"]] for p in payload] == \
        [[(c.name, c.verdict) for c in r.checks] for r in results]
    headline = reproduce.headline(results)
    assert captured.err.strip().endswith(headline)
    page = reproduce.report_html(results)
    assert headline in page and "boom | &lt;b&gt;" in page


def test_run_mars_faults_bad_spec_module_entry_point():
    proc = subprocess.run(
        [sys.executable, "-m", "xnavlab", "run", "mars", "--days", "0.01", "--faults",
         "uv.range:step:oops@1+2"],
        capture_output=True, text=True, check=False,
    )
    assert proc.returncode == 2
    assert len(proc.stderr.strip().splitlines()) == 1
    assert "oops" in proc.stderr
