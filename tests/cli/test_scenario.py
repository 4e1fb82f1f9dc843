"""``python -m xnavlab scenario`` (xnavlab.cli.scenario): --dump writes the defaults, --check reads
a file back to the same settings, and bad command lines exit 2 with one line."""

import json

import pytest

from xnavlab.cli import main
from xnavlab.mars.navigation import scenario_files


def test_dump_to_stdout_is_the_default_scenario_file(capsys):
    assert main(["scenario", "--dump"]) == 0
    assert capsys.readouterr().out == scenario_files.dump()


def test_dump_to_a_file_then_check_gives_the_default_settings(tmp_path, capsys):
    path = tmp_path / "mars.toml"
    assert main(["scenario", "--dump", "--out", str(path)]) == 0
    assert path.read_text(encoding="utf-8") == scenario_files.dump()
    capsys.readouterr()
    assert main(["scenario", "--check", str(path)]) == 0
    got = json.loads(capsys.readouterr().out)
    default = scenario_files.loads("")
    assert got["run"] == json.loads(json.dumps(default.run))
    assert got["detector"] == json.loads(json.dumps(default.detector))
    assert got["scenario"]["days"] == default.scenario.days


@pytest.mark.parametrize(("argv", "words"), [
    (["scenario"], "needs --dump or --check"),
    (["scenario", "--check", "x.toml", "--out", "y.toml"], "--out goes with --dump"),
    (["scenario", "--dump", "--check", "x.toml"], "not allowed with argument"),
])
def test_bad_command_lines_exit_2_with_one_line(argv, words, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert words in err and len(err.splitlines()) == 1


def test_dump_refuses_a_directory_as_out(tmp_path, capsys):
    assert main(["scenario", "--dump", "--out", str(tmp_path)]) == 2
    assert "is a folder, not a file" in capsys.readouterr().err


def test_dump_makes_a_missing_folder_and_refuses_what_it_cannot_write(tmp_path, capsys):
    # issue 35: a missing folder ended in a traceback
    assert main(["scenario", "--dump", "--out", str(tmp_path / "new" / "s.toml")]) == 0
    assert (tmp_path / "new" / "s.toml").read_text(encoding="utf-8") == scenario_files.dump()
    (tmp_path / "f").write_text("")
    for argv, words in ((["--out", str(tmp_path / "f" / "s.toml")], "a part of its folder is a file"),
                        (["--out="], "--out must name a file"), (["--setup="], "--setup must be one of")):
        assert main(["scenario", "--dump", *argv]) == 2
        err = capsys.readouterr().err.strip()
        assert words in err and len(err.splitlines()) == 1


@pytest.mark.parametrize("name", ["d.json", "d", "d.toml.bak", "new/d.txt"])
def test_dump_refuses_an_out_that_is_no_toml_file(name, tmp_path, capsys):
    """Review 35j (6) 1: d.json got TOML without a word (and its folder was made first)."""
    assert main(["scenario", "--dump", "--out", str(tmp_path / name)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("xnavlab: error: --out must name a .toml file") and len(err.splitlines()) == 1
    assert not (tmp_path / name).exists() and not (tmp_path / "new").exists()
    assert main(["scenario", "--dump", "--out", str(tmp_path / "D.TOML")]) == 0


def test_every_out_of_the_command_line_makes_its_missing_folders_as_its_help_says(tmp_path):
    """Review 35j (6) 1: scenario --dump made a missing folder, as run mars, campaign and
    reproduce do; each --help now says so."""
    from xnavlab.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    for names in (("scenario",), ("run", "mars"), ("campaign",), ("reproduce",)):
        p = sub.choices[names[0]]
        if len(names) > 1:
            p = next(a for a in p._actions if a.dest == "scenario").choices[names[1]]
        text = " ".join(p.format_help().split())
        assert "made if missing" in text or "missing folders are made" in text, names
    assert main(["scenario", "--dump", "--out", str(tmp_path / "a" / "b" / "s.toml")]) == 0
    assert (tmp_path / "a" / "b" / "s.toml").is_file()


def test_a_dump_on_a_full_disk_leaves_no_file_cut_short(tmp_path, monkeypatch, capsys):
    """Review 35 Q16, by class: one line, but the .toml file cut short was left."""
    import errno
    import os
    import pathlib

    def half_then_full(path, text, *args, **kwargs):
        with open(path, "w", encoding="utf-8") as fh:
            fh.write(text[: len(text) // 2])
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(pathlib.Path, "write_text", half_then_full)
    out = tmp_path / "s.toml"
    assert main(["scenario", "--dump", "--out", str(out)]) == 2
    assert capsys.readouterr().err == (f"xnavlab: error: --out '{out}' cannot be written (No "
                                       f"space left on device)\n")
    assert list(tmp_path.iterdir()) == []
