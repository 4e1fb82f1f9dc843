"""``python -m xnavlab reproduce`` (xnavlab.cli.reproduce): the list, one reproduction, --all with
its JSON file, and the usage errors."""

import errno
import json
import os
import pathlib

import pytest

from xnavlab import reproduce
from xnavlab.cli import main
from xnavlab.cli import reproduce as cli_reproduce


def test_list_prints_one_line_per_registered_id(capsys):
    assert main(["reproduce", "--list"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert [line.split()[0] for line in lines] == reproduce.ids()


def test_one_reproduction_prints_its_table_and_verdict(capsys):
    assert main(["reproduce", "xnav-ranging"]) == 0
    verdict = reproduce.run("xnav-ranging").verdict
    assert capsys.readouterr().out.rstrip().endswith(f"xnav-ranging: {verdict}")


def test_all_with_out_writes_every_result_as_json(monkeypatch, tmp_path, capsys):
    monkeypatch.setattr(reproduce, "ids", lambda: ["xnav-ranging"])
    assert main(["reproduce", "--all", "--out", str(tmp_path)]) == 0
    saved = json.loads((tmp_path / "reproductions.json").read_text())
    assert [r["id"] for r in saved] == ["xnav-ranging"] and saved[0]["ok"] is True
    assert saved[0]["verdict"] == reproduce.run("xnav-ranging").verdict
    assert reproduce.headline([reproduce.run("xnav-ranging")]) in capsys.readouterr().out


def test_run_one_turns_an_exception_into_a_failed_result(monkeypatch):
    def boom(rid, out=None, **kw):
        raise RuntimeError("no data")

    monkeypatch.setattr(reproduce, "run", boom)
    result = cli_reproduce.run_one("xnav-ranging", None)
    assert result.verdict == "ERROR" and not result.ok


def test_list_and_all_together_is_a_usage_error(capsys):
    assert main(["reproduce", "--list", "--all"]) == 2
    assert "not allowed with argument" in capsys.readouterr().err


def test_out_with_a_figure_path_that_cannot_be_written_is_refused_before_the_run(
        monkeypatch, tmp_path, capsys):
    """Review 35l (6) 7: a folder (or a link to nothing) at a figure's name gave a traceback
    after the reproduction ran; now one line naming the figure, before any run."""
    monkeypatch.setattr(reproduce, "run", lambda *a, **k: (_ for _ in ()).throw(AssertionError))
    (tmp_path / "a" / "xnav-ranging.png").mkdir(parents=True)
    (tmp_path / "b").mkdir()
    (tmp_path / "b" / "xnav-ranging.png").symlink_to(tmp_path / "none" / "x.png")
    for sub, words in (("a", "is a folder, not a file"), ("b", "is a symbolic link")):
        for extra in ([], ["--all"]):
            ident = [] if extra else ["xnav-ranging"]
            assert main(["reproduce", *ident, *extra, "--out", str(tmp_path / sub)]) == 2
            err = capsys.readouterr().err
            assert "the figure xnav-ranging.png" in err and words in err


def _half_then_full(path, text, *args, **kwargs):
    """Path.write_text on a disk that fills up half way."""
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(text[: len(text) // 2])
    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


def test_a_full_out_is_one_line_naming_the_file_and_leaves_no_cut_file(monkeypatch, tmp_path,
                                                                       capsys):
    """Review 35 Q16: a raw OSError at reproductions.json (rc 1), a 4,096-byte file left; a
    figure that cannot be written was an ERROR row for every reproduction with one."""
    monkeypatch.setattr(reproduce, "ids", lambda: ["xnav-ranging"])
    monkeypatch.setattr(pathlib.Path, "write_text", _half_then_full)
    assert main(["reproduce", "--all", "--quiet", "--out", str(tmp_path)]) == 2
    captured = capsys.readouterr()
    assert captured.err == (f"xnavlab: error: --out '{tmp_path}': reproductions.json cannot be "
                            f"written (No space left on device)\n")
    assert "xnav-ranging" in captured.out  # the table was shown before
    assert [p.name for p in tmp_path.iterdir()] == ["xnav-ranging.png"]  # whole: savefig's

    def full(rid, out=None, **kw):
        raise reproduce.OutputError(f"out {str(out)!r}: {rid}.png cannot be written (No space "
                                    f"left on device)")

    monkeypatch.setattr(reproduce, "run", full)
    for extra in (["--all", "--quiet"], ["xnav-ranging"]):
        assert main(["reproduce", *extra, "--out", str(tmp_path)]) == 2
        assert capsys.readouterr().err == (f"xnavlab: error: --out '{tmp_path}': xnav-ranging.png "
                                           f"cannot be written (No space left on device)\n")


def test_the_json_of_all_is_strict(monkeypatch, capsys):
    """Review 35 Q7: the dump of --all --json allowed NaN."""
    monkeypatch.setattr(reproduce, "ids", lambda: ["xnav-ranging"])
    assert main(["reproduce", "--all", "--json"]) == 0
    json.loads(capsys.readouterr().out, parse_constant=lambda c: pytest.fail(f"{c} in the JSON"))
