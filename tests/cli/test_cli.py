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
    claims = [row for row in payload["rows"] if row["kind"] == "claim"]
    checks = [row for row in payload["rows"] if row["kind"] == "check"]
    assert len(claims) + len(checks) == len(payload["rows"])
    assert {row["name"] for row in claims} >= {"B0531+21 ranging (m)", "B1821-24 ranging (m)"}
    # the four accuracies are parts of one claim of the paper (part_of), judged once
    assert {row["verdict"] for row in claims} <= set(reproduce.CLAIM_VERDICTS)
    assert {row["claim"] for row in claims} == set(payload["claims"]) and len(payload["claims"]) == 1
    # the Cramer-Rao rows are checks of ours: marked as checks, a part of no claim
    assert checks and {row["verdict"] for row in checks} <= {reproduce.CHECK, reproduce.CHECK_FAILED}
    assert all(row["claim"] == "" and "Cramer-Rao" in row["name"] for row in checks)
    assert payload["counts"][reproduce.CHECK] + payload["counts"][reproduce.CHECK_FAILED] == len(checks)


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


# ---- issue 35: the argument grammar, as properties (exit 2 and one line, never a traceback) ----

import math  # noqa: E402
import re  # noqa: E402

from hypothesis import assume, example, given  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from xnavlab.cli import number  # noqa: E402

#: Odd texts for a number flag: anything, numbers of every size, and the spellings Python's own
#: float() and int() take but a command line should not (underscores, hex, blanks, other digits).
ODD = st.one_of(
    st.text(max_size=12),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.integers(-10**30, 10**30).map(str),
    st.sampled_from(["1_0", "0x10", " 1", "1 ", "1e400", "-0", "1j", "\u0663", "", "nan", "-inf",
                     "+.5e-3", "1.", ".", "e3", "1e", "--1", "0.0", "1/2", "１"]),
)
_PLAIN = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?", re.A)


@given(ODD)
@example("1_0")
@example("1e400")
def test_a_real_number_flag_takes_plain_decimals_in_range_or_says_so_in_one_line(text):
    try:
        value = number("days", text, float, 0.0, 365.0, lo_open=True)
    except ValueError as exc:
        assert str(exc) == f"days must be a real number in (0, 365], got {text!r}"
    else:
        assert _PLAIN.fullmatch(text) and 0.0 < value <= 365.0 and value == float(text)


@given(ODD)
def test_an_integer_flag_takes_plain_integers_in_range_or_says_so_in_one_line(text):
    try:
        value = number("seed", text, int, 0, 2**63 - 1)
    except ValueError as exc:
        assert str(exc) == f"seed must be an integer in [0, 9223372036854775807], got {text!r}"
    else:
        assert re.fullmatch(r"[+-]?\d+", text, re.A) and 0 <= value < 2**63


def _valid(text, kind, lo, hi, lo_open=False):
    try:
        number("x", text, kind, lo, hi, lo_open=lo_open)
    except ValueError:
        return False
    return True


#: (argv before the flag, flag, its name in the message, is this text valid)
NUMBER_FLAGS = [
    (["run", "mars"], "--days", "days", lambda t: _valid(t, float, 0.0, 365.0, True)),
    (["run", "mars", "--days=0.01"], "--seed", "seed", lambda t: _valid(t, int, 0, 2**63 - 1)),
    (["campaign", "consistency"], "--runs", "runs", lambda t: _valid(t, int, 1, 10**7)),
    (["campaign", "consistency", "--runs=1"], "--days", "days",
     lambda t: _valid(t, float, 0.0, 30.0, True) and float(t) >= 0.000417),
    (["campaign", "detectors", "--runs=1"], "--days", "days", lambda t: _valid(t, float, 0.5, 5.0)),
    (["campaign", "consistency", "--runs=1"], "--seed", "seed", lambda t: _valid(t, int, 0, 2**63 - 1)),
    (["campaign", "consistency", "--runs=1"], "--workers", "workers", lambda t: False),  # see below
    (["campaign", "consistency", "--runs=1", "--local-cluster"], "--timeout", "timeout",
     lambda t: _valid(t, float, 0.0, 3600.0, True)),
]


@given(st.sampled_from(NUMBER_FLAGS), ODD)
def test_a_bad_number_on_the_command_line_exits_2_with_one_line_naming_it(tmp_path_factory, flag,
                                                                           text):
    before, option, name, valid = flag
    if option == "--workers":   # valid workers would start a campaign: keep the refused ones
        assume(not _valid(text, int, 1, 1))
        before = [*before, "--days=1e-9"] if _valid(text, int, 1, 256) else before
    assume(not valid(text))
    out = tmp_path_factory.getbasetemp() / "grammar"
    argv = [*before, f"{option}={text}"]
    if before[0] == "campaign":
        argv.append(f"--out={out}")
    import contextlib
    import io
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = main(argv)
    lines = err.getvalue().splitlines()
    assert code == 2 and len(lines) == 1 and lines[0].startswith("xnavlab: error: "), lines
    assert name in lines[0] or "days" in lines[0], lines


CHOICE_FLAGS = [(["run", "mars", "--days=0.01"], "--mode", ("reset", "no-reset")),
                (["run", "mars", "--days=0.01"], "--backend", ("numba", "numpy")),
                (["run", "mars", "--days=0.01"], "--detector", ("none",)),
                (["scenario", "--dump"], "--setup", ("paper", "study"))]


@given(st.sampled_from(CHOICE_FLAGS), st.text(max_size=10))
def test_an_unknown_choice_exits_2_with_one_line(flag, text):
    before, option, valid = flag
    assume(text not in valid)
    import contextlib
    import io
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = main([*before, f"{option}={text}"])
    lines = err.getvalue().splitlines()
    assert code == 2 and len(lines) == 1 and option.strip("-") in lines[0], lines


SPEC_PART = st.one_of(ODD, st.sampled_from(["uv", "xnav", "cns", "uv.range", "xnav.B1937",
                                            "cns.angle0", "step", "ramp", "spike", "stuck",
                                            "noise", "25000", "100", "inf", "0"]))


@given(st.lists(st.tuples(SPEC_PART, SPEC_PART, SPEC_PART, SPEC_PART, SPEC_PART), min_size=1,
                max_size=2), st.sampled_from([":@+", "::+", ":", ""]))
def test_a_fault_spec_is_used_or_refused_in_one_line_before_any_run(items, seps):
    from xnavlab.mars.faults import fault_tolerance
    from xnavlab.mars.navigation import scenarios

    a, b, c = (seps + ":@+")[:3]
    spec = ",".join(f"{s}{a}{k}:{m}{b}{o}{c}{d}" for s, k, m, o, d in items)
    assume(spec.strip())
    sc = scenarios.MarsScenario(days=0.05)
    try:   # a spec the run would take is not for this test (it would run)
        faults = fault_tolerance.parse_faults(spec, sc)
        fault_tolerance.check_schedule(faults, sc, "combined", scenarios.default_settle_days(0.05))
    except ValueError:
        pass
    else:
        assume(False)
    import contextlib
    import io
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = main(["run", "mars", "--days=0.05", f"--faults={spec}"])
    lines = err.getvalue().splitlines()
    assert code == 2 and len(lines) == 1 and lines[0].startswith("xnavlab: error: "), lines
    assert math.isfinite(len(lines))


def _options():
    """(subcommand argv, option, a value or None for a flag) of every option of every parser."""
    import argparse

    from xnavlab.cli import build_parser

    found = []

    def walk(parser, argv):
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction):
                for name, sub in action.choices.items():
                    walk(sub, [*argv, name])
            elif action.option_strings and action.dest != "help":
                found.append((argv, max(action.option_strings, key=len), action.nargs != 0))
    walk(build_parser(), [])
    return found


@pytest.mark.parametrize("argv,option,takes_value", _options())
def test_every_option_given_twice_is_refused_in_one_line(argv, option, takes_value, capsys):
    """argparse would keep the last of --faults A --faults B and drop A without a word."""
    twice = [option, "1", option, "2"] if takes_value else [option, option]
    assert main([*argv, *twice]) == 2
    lines = capsys.readouterr().err.splitlines()
    assert lines == [f"xnavlab: error: {option} given twice; give each option once"
                     + ("; join the fault specs with ','" if option == "--faults" else "")]


def test_the_walk_sees_every_command_and_the_faults_flag():
    options = _options()
    assert {a[0] for a, _, _ in options if a} >= {"reproduce", "run", "campaign", "scenario"}
    assert (["run", "mars"], "--faults", True) in options


@pytest.mark.parametrize("argv,words", [
    (["campaign", "consistency", "--runs", "1", "--timeout", "10"], "--timeout is the wait"),
    (["reproduce", "--list", "extra"], "--list takes no ID ('extra')"),
    (["reproduce", "--list", "--json", "--fresh"], "--list takes no --json, --fresh"),
    (["reproduce", "--list", "--quiet"], "--list takes no --quiet"),
    (["reproduce", "--all", "toa-terms"], "--all takes no ID"),
    (["reproduce", "xnav-ranging", "--quiet"], "--quiet goes with --all"),
])
def test_an_option_that_would_be_ignored_is_refused_in_one_line(argv, words, tmp_path, capsys):
    out = tmp_path / "out"
    assert main([*argv, "--out", str(out)] if argv[0] == "campaign" else argv) == 2
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) == 1 and words in lines[0], lines
    assert not out.exists()   # refused before any folder is made


def test_list_with_out_makes_no_folder(tmp_path, capsys):
    assert main(["reproduce", "--list", "--out", str(tmp_path / "x")]) == 2
    assert "--list takes no --out" in capsys.readouterr().err
    assert not (tmp_path / "x").exists()


@pytest.mark.parametrize("argv", [["--version"], ["--help"], ["reproduce", "--list"],
                                  ["scenario", "--dump"], ["run", "mars", "--help"]])
def test_a_standard_output_closed_early_ends_quietly(argv):
    """`reproduce --list | head -1` ended in a BrokenPipeError traceback (review 35 follow-up):
    the output closed before the command writes, and after its first line."""
    for lines in (0, 1):
        proc = subprocess.Popen([sys.executable, "-m", "xnavlab", *argv], stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE)
        if lines:
            assert proc.stdout.readline()
        proc.stdout.close()
        err = proc.stderr.read().decode()
        proc.stderr.close()
        assert proc.wait(timeout=120) in (0, 141) and err == "", err


@pytest.mark.parametrize(("argv", "line"), [
    (["run", "--days", "0.02"], "run needs its scenario before the options (choose from 'mars'): "
                                "write 'run mars --days 0.02'"),
    (["run", "--days", "0.02", "mars"], "run needs its scenario before the options (choose from "
                                        "'mars'): write 'run mars --days 0.02'"),
    (["run", "venus"], "run: unknown scenario 'venus' (choose from 'mars')"),  # review 35m (6) 2
])
def test_an_option_before_its_sub_command_says_the_order(argv, line, capsys):
    """Review 35b N24: 'run --days 0.02' said "argument scenario: invalid choice: '0.02'"."""
    assert main(argv) == 2
    assert capsys.readouterr().err.strip() == f"xnavlab: error: {line}"


def test_a_filter_the_kernel_cannot_carry_ends_in_one_line_not_a_traceback(tmp_path, capsys):
    # review 35d D44: the kernel's stop was a 26-line traceback
    path = tmp_path / "tiny.toml"
    path.write_text('[run]\nsubsystems = ["uv"]\n[uv]\nsigma_range_m = 1e-6\n'
                    'sigma_dir_deg = 1e-9\n')
    assert main(["run", "mars", "--scenario", str(path), "--days", "0.05", "--json"]) == 1
    err = capsys.readouterr().err
    assert err.startswith("xnavlab: error: the compiled filter stopped") and err.count("\n") == 1


@pytest.mark.parametrize("argv,line", [
    (["scenario", "--check", ""], "scenario file must name a file, got ''"),
    (["reproduce", ""], "unknown reproduction id ''"),
    (["reproduce", "--all", ""], "--all takes no ID (got '')"),
    (["reproduce", "--list", ""], "--list takes no ID ('')"),
    (["campaign", "roc", "--runs", "1", "--grid", ""], "grid file must name a file, got ''"),
    (["campaign", "consistency", "--runs", "1", "--scheduler", " "], "--scheduler is empty"),
    (["campaign", "consistency", "--runs", "1", "--workers", ""],
     "--workers must be an integer in [1, 256], got ''"),
])
def test_an_empty_value_is_a_value_not_a_flag_left_out(argv, line, tmp_path, capsys):
    """Review 35e: an empty shell variable ("--scheduler $ADDR") ran the campaign on local
    workers, --workers "" took 2, --check "" and an empty ID said the flag was missing, and
    --grid "" was named '.'."""
    out = tmp_path / "out"
    assert main([*argv, "--out", str(out)] if argv[0] == "campaign" else argv) == 2
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) == 1 and line in lines[0], lines
    assert not out.exists()  # refused before any folder is made


def test_a_folder_of_another_campaign_is_one_line_before_any_warning(tmp_path, capsys):
    """Review 35e: campaign detectors --runs 2 printed its cell warning first, then the refusal."""
    from xnavlab.core.campaign import Store
    from xnavlab.mars.studies.campaigns import campaign

    Store(tmp_path, campaign("consistency", days=0.05).header(0)).close()
    assert main(["campaign", "detectors", "--runs", "2", "--out", str(tmp_path)]) == 2
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) == 1 and "holds another campaign's records" in lines[0], lines


@pytest.mark.parametrize(("argv", "words"), [
    (["run", "mars", "--days", "-1e-3"], "--days must be a real number in (0, 365], got '-1e-3'"),
    (["run", "mars", "--days", "-inf"], "--days must be a real number in (0, 365], got '-inf'"),
    (["run", "mars", "--seed", "-1e2"], "--seed must be an integer in [0, "),
])
def test_a_negative_value_with_an_exponent_reaches_its_own_range(argv, words, capsys):
    # review 35f #13: argparse read -1e-3 as an option ("expected one argument")
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and words in err


@pytest.mark.parametrize(("flags", "words"), [
    (["consistency", "--runs", "1", "--days", "0"], "--days must be a real number in (0, 30], got '0'"),
    (["detectors", "--runs", "1", "--days", "99"], "--days must be a real number in [0.5, 5], got '99'"),
    (["consistency", "--runs", "0"], "--runs must be an integer in [1, 10000000], got '0'"),
    (["consistency", "--runs", "1", "--seed", "-1"], "--seed must be an integer in [0, "),
    (["consistency", "--runs", "1", "--workers", "0"], "--workers must be an integer in [1, 256]"),
    (["consistency", "--runs", "1", "--local-cluster", "--timeout", "0"],
     "--timeout must be a real number in (0, 3600], got '0'"),
])
def test_a_campaign_flag_is_named_with_its_dashes(flags, words, tmp_path, capsys):
    """Review 35l (6) 9: campaign --days 0 said "days must be ...", the API's name."""
    assert main(["campaign", *flags, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert err == f"xnavlab: error: {words}" or (len(err.splitlines()) == 1 and words in err), err


def test_a_refused_command_drops_library_warnings_but_a_run_shows_them(monkeypatch, capsys):
    # review 35f #4: PINT's notes on a timing model came before the error, three lines
    import warnings

    from xnavlab.cli import runners

    def noisy(args):
        warnings.warn("a library's note", UserWarning, stacklevel=1)
        raise ValueError("refused")

    def quiet(args):
        warnings.warn("a library's note", UserWarning, stacklevel=1)
        return 0

    configure, _, words = runners.RUNNERS["mars"]
    for execute, code, lines in ((noisy, 2, ["xnavlab: error: refused"]),
                                 (quiet, 0, ["xnavlab: warning: a library's note"])):
        monkeypatch.setitem(runners.RUNNERS, "mars", (configure, execute, words))
        with warnings.catch_warnings():  # as the command line runs: no "error" filter
            warnings.simplefilter("default")
            assert main(["run", "mars", "--days", "1"]) == code
        assert capsys.readouterr().err.strip().splitlines() == lines


@pytest.mark.parametrize(("argv", "line"), [
    (["--version", "run", "mars", "--days", "-1"],
     "--version is given alone (python -m xnavlab --version), got also 'run mars --days -1'"),
    (["--version", "warmup"], "--version is given alone (python -m xnavlab --version), got also "
                              "'warmup'"),
    (["bogus"], "python -m xnavlab: unknown command 'bogus' (choose from 'reproduce', 'run', "
                "'warmup', 'campaign', 'scenario')"),
    (["run", "attitude"], "run: unknown scenario 'attitude' (choose from 'mars')"),
    (["--versio"], "unrecognized arguments: --versio"),  # review 35n 5: argparse's abbreviation
    (["run", "mars", "--da", "0.01"], "unrecognized arguments: --da 0.01"),
])
def test_a_command_line_is_refused_in_the_words_it_shows(argv, line, capsys):
    """Review 35m (6) 4: '--version run mars --days -1' printed the version, rc 0, the rest
    unread; (6) 2: 'run attitude' said "argument scenario", argparse's internal name."""
    assert main(argv) == 2
    cap = capsys.readouterr()
    assert cap.err.strip() == f"xnavlab: error: {line}" and cap.out == ""
