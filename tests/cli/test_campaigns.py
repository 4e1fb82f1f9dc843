"""``python -m xnavlab campaign``: outputs checked before the runs (reviews 35k, 35m)."""

import pytest

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
    assert not (out / "runs.jsonl").exists()  # no run was computed, no store made


def test_roc_outputs_are_checked_before_the_runs(tmp_path, capsys):
    """Review 35k (6) 4: roc.json too (written after the runs)."""
    out = tmp_path / "r"
    (out / "roc.json").mkdir(parents=True)
    assert main(["campaign", "roc", "--runs", "1", "--quiet", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert "roc.json" in err and len(err.splitlines()) == 1


CONSISTENCY = ["campaign", "consistency", "--runs", "1", "--quiet"]


def test_a_refused_campaign_leaves_no_store_bound_to_its_settings(tmp_path, capsys):
    """Review 35m (7) 1: refused up front (summary.json a dangling link), it still left
    campaign.json, an empty runs.jsonl and owner.pid, and the corrected command was refused
    as "holds another campaign's records" though no run had been computed."""
    out = tmp_path / "s71"
    out.mkdir()
    (out / "summary.json").symlink_to(tmp_path / "none" / "x.json")
    assert main([*CONSISTENCY, "--days", "0.02", "--workers", "1", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("xnavlab: error: --out") and "summary.json" in err
    assert [p.name for p in out.iterdir()] == ["summary.json"]
    (out / "summary.json").unlink()
    assert main([*CONSISTENCY, "--days", "0.03", "--workers", "1", "--out", str(out)]) == 0
    assert "another campaign" not in capsys.readouterr().err


def test_an_unreachable_or_malformed_scheduler_names_the_flag_and_makes_nothing(tmp_path, capsys):
    """Review 35m (6) 3, (2) 3: "scheduler bogus://x unreachable within 1 s (ValueError:
    unknown address scheme ...)": the flag is --scheduler, and the address is malformed."""
    out = tmp_path / "s63"
    assert main([*CONSISTENCY, "--days", "0.02", "--out", str(out), "--scheduler", "bogus://x",
                 "--timeout", "1"]) == 2
    err = capsys.readouterr().err.strip()
    assert err == ("xnavlab: error: --scheduler 'bogus://x' is a malformed scheduler address: "
                   "unknown scheme 'bogus' (tcp, tls, ws, wss); give [SCHEME://]HOST:PORT, "
                   "e.g. tcp://HOST:8786")
    assert not out.exists()  # refused with the flags, before the folder is made
    assert main([*CONSISTENCY, "--days", "0.02", "--out", str(out), "--scheduler",
                 "tcp://127.0.0.1:1", "--timeout", "1"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("xnavlab: error: --scheduler tcp://127.0.0.1:1 unreachable within 1 s")
    assert len(err.splitlines()) == 1 and not list(out.iterdir())  # no store made


def test_a_store_file_that_is_a_folder_is_named_with_what_it_is(tmp_path, capsys):
    """Review 35m (7) 4: "--out must be a writable directory: [Errno 21] Is a directory:
    's74/runs.jsonl'": the folder is writable; runs.jsonl is the folder in the way."""
    out = tmp_path / "s74"
    (out / "runs.jsonl").mkdir(parents=True)
    assert main([*CONSISTENCY, "--days", "0.02", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert err == (f"xnavlab: error: --out {str(out)!r}: runs.jsonl {str(out / 'runs.jsonl')!r} "
                   f"is a folder, not a file of a campaign store; remove it, or choose another "
                   f"--out")


def test_an_unusable_cache_is_one_line_before_any_folder_or_run(tmp_path, monkeypatch, capsys):
    """Review 35n 3: with XNAVLAB_CACHE a file, every run of a campaign failed on it (rc 1, a
    store of failed records), while run mars, warmup and reproduce refused it in one line."""
    from xnavlab.core.campaign import run_campaign
    from xnavlab.mars.studies.campaigns import campaign

    (tmp_path / "afile").write_text("")
    monkeypatch.setenv("XNAVLAB_CACHE", str(tmp_path / "afile"))
    assert main(["campaign", "consistency", "--runs", "1", "--days", "0.02",
                 "--out", str(tmp_path / "o")]) == 2
    assert capsys.readouterr().err.strip().startswith("xnavlab: error: XNAVLAB_CACHE must name a "
                                                      "folder this process can write")
    with pytest.raises(ValueError, match=r"^XNAVLAB_CACHE must name a folder"):
        run_campaign(campaign("consistency", days=0.02), 1, out=tmp_path / "p")
    assert not (tmp_path / "o").exists() and not (tmp_path / "p").exists()
