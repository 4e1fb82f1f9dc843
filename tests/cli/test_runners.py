"""``python -m xnavlab run`` (xnavlab.cli.runners): the scenario table, the --out check, a short
Mars run with its files, and the one-line errors for bad flags."""

import errno
import json
import os

import pytest

from xnavlab.cli import main, runners
from xnavlab.mars.navigation import scenarios


def test_out_dir_accepts_none_or_a_directory_and_refuses_a_file(tmp_path):
    assert runners.out_dir(None) is None
    assert runners.out_dir(tmp_path / "new") == tmp_path / "new"
    (tmp_path / "f").write_text("")
    with pytest.raises(ValueError, match="^--out must be a directory"):
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


@pytest.mark.parametrize(("spec", "words"), [
    ("uv.range:step:0@3600+3000", "magnitude of a step fault must be a nonzero finite real number"),
    ("uv.range:step:25000@3600+0", "duration of a step fault must be a real number in (0, inf]"),
    ("uv.range:ramp:25000@3600+-60", "duration of a ramp fault must be a real number in (0, inf]"),
    ("uv.range:noise:0@3600+3000", "magnitude of a noise fault"),
    ("uv.range:step:nan@3600+3000", "magnitude must be a finite real number"),
    ("uv.range:step:inf@3600+3000", "magnitude must be a finite real number"),
    ("uv.range:step:25000@nan+3000", "onset must be a finite real number"),
    ("uv.range:step:25000@-100+3000", "before the run's start"),
    ("uv.range:step:25000@1e9+3000", "outside this run"),
    ("xnav.0:step:1e-5@3100+300", "acts on no sample"),
])
def test_a_fault_that_would_inject_nothing_exits_2_with_one_line(spec, words, capsys):
    """A zero-size, zero-length or non-finite fault, or one outside the run, is refused before
    any score is given (it would be injected as nothing and scored as missed)."""
    assert main(["run", "mars", "--days", "0.1", "--json", "--faults", spec]) == 2
    cap = capsys.readouterr()
    err = cap.err.strip()
    assert words in err and len(err.splitlines()) == 1 and cap.out == ""


def test_help_states_the_refusals_and_the_scoring_rule(capsys):
    from xnavlab.mars.faults import schedules

    with pytest.raises(SystemExit):
        main(["run", "mars", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    for words in ("a zero, NaN or infinite MAGNITUDE", "a DURATION <= 0", "acts on no sample",
                  "raised while it acts, [onset, end)", "from before the onset to the end (delay 0)",
                  f"up to {schedules.LATE_WINDOW_S['uv']:.0f} s after the end "
                  f"(XNAV {schedules.LATE_WINDOW_S['xnav']:.0f} s)", '"late", never detected',
                  "no fault explains is a false alarm (a late one is not)"):
        assert words in text, words
    assert schedules.LATE_WINDOW_S["uv"] == schedules.LATE_WINDOW_S["cns"]


def test_an_alarm_after_the_fault_ended_is_scored_late_in_the_json(capsys):
    """The issue's run: the 8000-s XNAV step is flagged 500 s after its end: LATE, no delay."""
    assert main(["run", "mars", "--days", "2", "--seed", "53", "--json", "--faults",
                 "xnav.2:step:3e-6@61000+8000"]) == 0
    score = json.loads(capsys.readouterr().out)["score"]
    f, = score["faults"]
    assert (f["status"], f["detected"], f["delay_s"], f["late_s"]) == ("late", False, None, 500.0)
    late = [d for d in score["detections"] if d["match"] == "late"]
    assert len(late) == 1 and late[0]["detected_onset"] == 69500.0 and not late[0]["false_alarm"]
    assert score["counts"]["xnav"]["late"] == 1 and score["counts"]["xnav"]["detected"] == 0


def test_an_out_that_cannot_be_written_is_refused_before_the_run(tmp_path, monkeypatch, capsys):
    # issue 35: --out under a file, or in /proc, ended in a traceback after the run (result lost)
    from xnavlab.mars.navigation import scenarios

    monkeypatch.setattr(scenarios, "run", lambda *a, **k: pytest.fail("the run started"))
    (tmp_path / "f").write_text("")
    for out, words in ((tmp_path / "f" / "x", "a part of its folder is a file"),
                       ("", "--out must name a folder, got ''")):
        assert main(["run", "mars", "--days=0.01", f"--out={out}"]) == 2
        err = capsys.readouterr().err.strip()
        assert words in err and len(err.splitlines()) == 1
    assert runners.out_dir(tmp_path / "new" / "deeper").is_dir()      # made before the run


@pytest.mark.parametrize(("flags", "words"), [
    (["--days", "1e-5"], "--days must span at least one measurement interval"),  # was settle_days
    (["--days", "1_0"], "--days must be a real number in (0, 365], got '1_0'"),    # was 10 days
    (["--scenario="], "scenario file must name a file, got ''"),                 # was the defaults
    (["--days", "0.01", "--detector", "wavelet"],   # was train_days (review 35j (3) 7)
     "--days 0.01 is too short for the wavelet detector: its uv wavelet trains on the first "
     "min(1, days / 2) = 0.005 days (143 samples) and needs 356: run at least --days 0.0248"),
])
def test_a_flag_is_refused_in_the_users_own_words(flags, words, capsys):
    assert main(["run", "mars", *flags]) == 2
    err = capsys.readouterr().err.strip()
    assert words in err and len(err.splitlines()) == 1


@pytest.mark.parametrize("spec", ["", "  "])
def test_an_empty_faults_flag_is_refused(capsys, spec):
    """--faults "$SPEC" with an empty variable was a plain run without a word."""
    assert main(["run", "mars", "--days", "0.02", "--faults", spec]) == 2
    err = capsys.readouterr().err
    assert "--faults is empty" in err and len(err.splitlines()) == 1


def test_a_run_too_short_for_the_training_names_where_its_days_came_from(tmp_path, capsys, monkeypatch):
    """Review 35j (3) 7: the run's days, from --days or a scenario file's [run] days, is named
    (train_days is no option of the command line); a file's own train_days under its name."""
    monkeypatch.setattr(scenarios, "run", lambda *a, **k: pytest.fail("the run started"))
    short = tmp_path / "short.toml"
    short.write_text("[run]\ndays = 0.02\n")
    train = tmp_path / "train.toml"
    train.write_text('[run]\ndays = 0.05\n[detector]\nname = "combined"\ntrain_days = 0.01\n')
    spec = "uv.range:step:25000@1000+100"
    for argv, words in (
            (["--scenario", str(short), "--faults", spec],
             f"scenario file {str(short)!r}: [run] days = 0.02 is too short for the combined "
             f"detector"),
            (["--scenario", str(short), "--days", "0.021", "--faults", spec], "--days 0.021 is too short"),
            (["--scenario", str(train), "--faults", spec],
             f"scenario file {str(train)!r}: [detector] train_days = 0.01 days gives the uv wavelet "
             f"detector 287 samples")):
        assert main(["run", "mars", *argv]) == 2
        err = capsys.readouterr().err.strip()
        assert words in err and len(err.splitlines()) == 1, err


def test_mars_summary_json_is_checked_before_the_run(tmp_path, capsys):
    """Review 35k (6) 5: a folder where mars_summary.json goes was refused after the run."""
    (tmp_path / "o" / "mars_summary.json").mkdir(parents=True)
    with pytest.raises(ValueError, match="mars_summary.json.*is a folder"):
        runners.out_dir(tmp_path / "o")
    assert main(["run", "mars", "--days", "15", "--quiet", "--out", str(tmp_path / "o")]) == 2
    assert "mars_summary.json" in capsys.readouterr().err


@pytest.mark.parametrize("days", ["1e-5", "5e-324"])
def test_a_run_too_short_names_the_days_flag(days, capsys):
    """Review 35k (6) 7: --days too short was named as the scenario file's [run] days."""
    assert main(["run", "mars", "--days", days]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("xnavlab: error: --days must span") and "[run]" not in err


_FAULT_CLAIMS = [  # (words of FAULT_HELP's "Refused:" part, flags, words of the one-line refusal)
    ("a zero, NaN or infinite MAGNITUDE", ["--faults", "uv.range:step:0@20000+3000"],
     "--faults: bad fault item 'uv.range:step:0@20000+3000': magnitude of a step fault must be"),
    ("a zero, NaN or infinite MAGNITUDE", ["--faults", "uv.range:step:nan@20000+3000"],
     "--faults: bad fault item 'uv.range:step:nan@20000+3000': magnitude must be a finite"),
    ("a zero, NaN or infinite MAGNITUDE", ["--faults", "uv.range:ramp:inf@20000+3000"],
     "--faults: bad fault item 'uv.range:ramp:inf@20000+3000': magnitude must be a finite"),
    ("a noise sigma must be > 0", ["--faults", "uv.range:noise:-1@20000+3000"],
     "magnitude of a noise fault (the extra noise's standard deviation) must be"),
    ("a stuck fault's, a number it would not use, must be 0", ["--faults", "uv.range:stuck:5@20000+3000"],
     "--faults: bad fault item 'uv.range:stuck:5@20000+3000': magnitude of a stuck fault must be 0"),
    ("a DURATION <= 0 or NaN", ["--faults", "uv.range:step:1@20000+0"],
     "duration of a step fault must be a real number in (0, inf], s, got 0.0"),
    ("a DURATION <= 0 or NaN", ["--faults", "uv.range:step:1@20000+nan"],
     "duration of a step fault must be a real number in (0, inf], s, got nan"),
    ("(a spike's must be 0)", ["--faults", "uv.range:spike:1@20000+3000"],
     "a spike fault's DURATION must be 0"),
    ("a fault whose onset lies outside the run", ["--faults", "uv.range:step:1@43200+3000"],
     "--faults: uv.range:step:1@43200+3000 starts at 43200 s, outside this run"),
    ("a fault whose onset lies outside the run", ["--faults", "uv.range:step:1@-5+3000"],
     "--faults: uv.range:step:1@-5+3000 starts at -5 s, before the run's start"),
    ("acts on no sample of its sensor (XNAV: one every 500 s)", ["--faults", "xnav:step:1e-5@20001+10"],
     "--faults: xnav:step:1e-05@20001+10 acts on no sample"),
    ("with the wavelet detector a UV or CNS fault that starts inside the wavelets' training span",
     ["--detector", "wavelet", "--faults", "uv.range:step:25000@2000+3000"],
     "--faults: uv.range:step:25000@2000+3000 starts at 2000 s, inside the 21600-s span on which "
     "the uv wavelet detector trains (it must be fault-free); move its onset to 21600 s or later, "
     "or use --detector combined"),
    ("with the combined detector a fault that starts before 600 s",
     ["--faults", "uv.range:step:25000@599+3000"],
     "--faults: uv.range:step:25000@599+3000 starts at 599 s, before the filter has settled"),
    ("'paper' is the paper's 16-fault schedule (refused for a run that ends by its last onset, "
     "2400000 s: --days 27.77 or less", ["--days", "27.77", "--faults", "paper"],
     "--faults: the paper's schedule has onsets up to 2400000 s (27.78 days); run at least "
     "--days 27.84"),
    ("--days below 0.0248 with the wavelet or combined detector) is refused",
     ["--days", "0.0247", "--detector", "wavelet"], "--days 0.0247 is too short for the wavelet "
                                                     "detector"),
]


@pytest.mark.parametrize(("claim", "flags", "words"), _FAULT_CLAIMS)
def test_every_refusal_run_mars_help_states_holds(claim, flags, words, capsys, monkeypatch):
    """Review 35m (6) 5: the help said "Refused: a zero ... MAGNITUDE" and "stuck (... magnitude
    ignored)", and a stuck fault of magnitude 0 or 5 ran; every "Refused:" statement is now
    checked by a refusal, in one line leading with the flag (review 35m (6) 1: "spec:" and
    "faults:", parse_faults' and check_schedule's parameters, led before)."""
    from xnavlab.mars.faults import fault_tolerance

    monkeypatch.setattr(fault_tolerance, "run_fault_tolerant", lambda *a, **k: pytest.fail("ran"))
    monkeypatch.setattr(scenarios, "run", lambda *a, **k: pytest.fail("the run started"))
    assert claim in " ".join(runners.FAULT_HELP.split())
    argv = flags if "--days" in flags else ["--days", "0.5", *flags]
    assert main(["run", "mars", "--quiet", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("xnavlab: error: ") and words in err and len(err.splitlines()) == 1, err
    assert " spec" not in err and "error: faults" not in err


def test_a_fault_backend_conflict_in_a_file_is_refused_by_check(tmp_path, capsys):
    """FAULT_HELP: "a scenario file with faults or a detector and another backend or local_filter
    is refused by --check"."""
    assert "is refused by --check" in " ".join(runners.FAULT_HELP.split())
    path = tmp_path / "s.toml"
    path.write_text('[run]\nbackend = "numpy"\n[detector]\nfaults = "uv.range:step:1@700+300"\n')
    assert main(["scenario", "--check", str(path)]) == 2
    assert '[detector] faults (a fault-tolerant run) runs with [run] backend = "numba"' in \
        capsys.readouterr().err


def test_a_files_faults_and_arm_s_are_named_as_its_keys(tmp_path, capsys, monkeypatch):
    """Review 35m (6) 1, pattern Q: run_fault_tolerant's check of arm_s said "faults: ... (arm_s =
    5000 s) ... lower arm_s", its parameters, for a file's [detector] faults and arm_s."""
    from xnavlab.mars.faults import fault_tolerance

    monkeypatch.setattr(fault_tolerance, "run_fault_tolerant", lambda *a, **k: pytest.fail("ran"))
    path = tmp_path / "s.toml"
    path.write_text('[run]\ndays = 0.5\n[detector]\nfaults = "uv.range:step:25000@700+300"\n'
                    'arm_s = 5000.0\n')
    for flags, head in (([], "[detector] faults"), (["--faults", "uv.range:step:25000@800+100"],
                                                    "--faults")):
        assert main(["run", "mars", "--scenario", str(path), "--quiet", *flags]) == 2
        err = capsys.readouterr().err.strip()
        assert err.startswith(f"xnavlab: error: scenario file {str(path)!r}: {head}: uv.range:step:"), err
        assert "([detector] arm_s = 5000 s)" in err and err.endswith(
            "move it after [detector] arm_s or lower [detector] arm_s")


def test_a_full_out_leaves_no_file_cut_short(tmp_path, monkeypatch, capsys):
    """Review 35 Q16: one clear line, but a truncated 65,536-byte mars_run.npz was left."""
    import numpy as np

    def half_then_full(path, **arrays):
        with open(path, "wb") as fh:
            fh.write(b"PK\x03\x04" + b"\0" * 100)
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(np, "savez_compressed", half_then_full)
    assert main(["run", "mars", "--days", "0.01", "--quiet", "--out", str(tmp_path)]) == 2
    assert capsys.readouterr().err == (f"xnavlab: error: --out '{tmp_path}': mars_run.npz cannot "
                                       f"be written (No space left on device)\n")
    assert list(tmp_path.iterdir()) == []


def test_a_non_finite_summary_value_is_null_in_strict_json(tmp_path, monkeypatch, capsys):
    """Review 35 Q7: the run's JSON was dumped with NaN allowed (not JSON)."""
    real = scenarios.MarsRun.summary
    monkeypatch.setattr(scenarios.MarsRun, "summary",
                        lambda self, *a: {**real(self, *a), "position_error_m": float("nan")})
    assert main(["run", "mars", "--days", "0.01", "--json", "--out", str(tmp_path)]) == 0
    strict = {"parse_constant": lambda c: pytest.fail(f"{c} in the JSON")}
    assert json.loads(capsys.readouterr().out, **strict)["position_error_m"] is None
    saved = json.loads((tmp_path / "mars_summary.json").read_text(), **strict)
    assert saved["position_error_m"] is None
