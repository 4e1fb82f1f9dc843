"""``python -m xnavlab campaign``: outputs checked before the runs (review 35k)."""

from xnavlab.cli import main


def test_summary_json_is_checked_before_the_runs(tmp_path, capsys):
    """Review 35k (6) 4: a folder where summary.json goes gave a traceback after every run."""
    out = tmp_path / "c"
    (out / "summary.json").mkdir(parents=True)
    assert main(["campaign", "consistency", "--runs", "1", "--days", "0.02", "--quiet",
                 "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("xnavlab: error: --out") and "summary.json" in err
    assert len(err.splitlines()) == 1
    assert not (out / "runs.jsonl").read_text()  # no run was computed


def test_roc_outputs_are_checked_before_the_runs(tmp_path, capsys):
    """Review 35k (6) 4: roc.json too (written after the runs)."""
    out = tmp_path / "r"
    (out / "roc.json").mkdir(parents=True)
    assert main(["campaign", "roc", "--runs", "1", "--quiet", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert "roc.json" in err and len(err.splitlines()) == 1
