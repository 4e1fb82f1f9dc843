"""Scenario files: dump and read back, every field group reaches the run, flags override."""

import json

import pytest

from xnavlab.cli import main
from xnavlab.mars.navigation import scenario_files as sfm
from xnavlab.mars.navigation import scenarios


def _run(capsys, tmp_path, text, *flags):
    path = tmp_path / "s.toml"
    path.write_text(text)
    code = main(["run", "mars", "--scenario", str(path), "--json", *flags])
    out = capsys.readouterr()
    return code, (json.loads(out.out) if code == 0 else out.err.strip())


def test_dump_reads_back_as_the_defaults_and_a_changed_scenario_round_trips():
    sf = sfm.loads(sfm.dump())
    assert sf.scenario == scenarios.MarsScenario()
    assert sf.run == sfm.RUN_DEFAULTS and sf.detector == sfm.DETECTOR_DEFAULTS
    sc = scenarios.MarsScenario(days=2.5, dt_uv=6.0, sigma_range_m=2500.0, q_acc=2e-11,
                                subsystems=("xnav", "uv"), beta=(0.3, 0.7),
                                xnav_sigma_m=(100.0, 300.0, 1800.0, 300.0))
    det = {"name": "chi2", "faults": "uv.range:step:25000@100000+3000", "alpha": 1e-4}
    back = sfm.loads(sfm.dump(sc, detector=det))
    assert back.scenario == sc and back.detector == {**sfm.DETECTOR_DEFAULTS, **det}


def test_the_cli_dump_round_trips(tmp_path, capsys):
    out = tmp_path / "d.toml"
    assert main(["scenario", "--dump", "--out", str(out)]) == 0
    assert sfm.load(out).scenario == scenarios.MarsScenario()
    assert main(["scenario", "--check", str(out)]) == 0
    assert json.loads(capsys.readouterr().out)["scenario"]["days"] == 30.0


def test_each_field_group_of_the_file_reaches_the_run(tmp_path, capsys):
    base = "[run]\ndays = 0.1\n"
    code, ref = _run(capsys, tmp_path, base)
    assert code == 0 and ref["days"] == 0.1 and ref["seed"] == 0
    code, res = _run(capsys, tmp_path, "[run]\ndays = 0.1\nseed = 4\nsubsystems = [\"xnav\", \"uv\"]\n")
    assert res["seed"] == 4 and "updates_cns" not in res and res["updates_uv"] > 0
    code, res = _run(capsys, tmp_path, base + "[uv]\ndt_s = 6.0\n[cns]\ndt_s = 9.0\n")
    assert abs(res["updates_uv"] - ref["updates_uv"] / 2) <= 2
    assert abs(res["updates_cns"] - ref["updates_cns"] / 3) <= 2
    code, res = _run(capsys, tmp_path, base + "[xnav]\ndt_s = 250.0\n")
    assert res["updates_xnav"] >= 2 * ref["updates_xnav"] - 2
    code, res = _run(capsys, tmp_path, base + "[filter]\npos_err0_m = 500.0\nq_acc = 1e-10\n")
    assert res["position_error_m"] != ref["position_error_m"]
    code, res = _run(capsys, tmp_path, base + "[orbit]\nfilter_ephem = \"de405\"\n")
    assert res["position_error_m"] != ref["position_error_m"]
    code, res = _run(capsys, tmp_path, base + "[run]\nsettle_days = 0.08\n".replace("[run]\n", ""))
    assert res["settle_days"] == 0.08
    code, res = _run(capsys, tmp_path, "[run]\ndays = 1.2\n[detector]\nname = \"chi2\"\n"
                     "faults = \"uv.range:step:25000@60000+3000\"\n")
    assert code == 0 and res["detector"] == "chi2" and res["score"]["counts"]["uv"]["faults"] == 1


def test_flags_override_the_file(tmp_path, capsys):
    code, res = _run(capsys, tmp_path, "[run]\ndays = 0.1\nseed = 4\n", "--seed", "2",
                     "--days", "0.05")
    assert code == 0 and res["seed"] == 2 and res["days"] == 0.05


@pytest.mark.parametrize("text,words", [
    ("[uv]\nsigma_range_m = -1.0\n", "[uv] sigma_range_m"),
    ("[uv]\nsigma_range = 1.0\n", "[uv] has no key 'sigma_range'"),
    ("[gps]\nx = 1\n", "unknown section [gps]"),
    ("[run]\ndays = 0.1\nlocal_filter = \"ukf\"\n", "needs backend = \"numpy\""),
    ("[detector]\nname = \"kalman\"\n", "[detector] name"),
    ("[run\n", "not valid TOML"),
    ("[run]\nsetup = \"rich\"\n", "[run] setup must be one of"),
    ("[truth_model]\ngravity_degree = 1\n", "[truth_model] gravity_degree must be 0"),
    ("[truth_model]\nthird_bodies = [\"pluto\"]\n", "[truth_model] third_bodies must be"),
    ("[truth_model]\nj2 = true\n", "[truth_model] has no key 'j2'"),
    ("[filter_model]\nsrp = true\n", "filter_model must be a point mass with third bodies"),
    ("[filter]\nq_acc = \"large\"\n", "q_acc must be a real number"),
    ("[xnav]\npulsars = []\n", "[xnav] pulsars must name at least one pulsar"),
    ("[xnav]\npulsars = \"B0531+21\"\n", "[xnav] pulsars must be a list of pulsars, got the string"),
    ("[xnav]\npulsars = [\"B0531+21\", \"B0531+21\"]\n", "lists B0531+21 twice"),
    ("[xnav]\npulsars = [\"B\"]\n", "unknown pulsar 'B'"),
    ("[xnav]\npulsars = [\"b1937+21\"]\n", "the catalogue names it 'B1937+21'"),  # review 35d D4
    ("[orbit]\nstate0 = [4e6, 0, 0, 9e8, 0, 0]\n", "[orbit] state0 speed must be below 65164.5 m/s"),
])
def test_a_bad_field_is_one_line_naming_it(tmp_path, capsys, text, words):
    code, err = _run(capsys, tmp_path, text)
    assert code == 2 and len(err.splitlines()) == 1 and words in err, err


def test_a_missing_file_is_one_line(capsys):
    assert main(["run", "mars", "--scenario", "/nonexistent/s.toml"]) == 2
    assert "cannot be read" in capsys.readouterr().err


def test_a_non_utf8_file_is_one_line_naming_it(tmp_path, capsys):
    path = tmp_path / "latin.toml"
    path.write_bytes("[uv]\n# r\xe9sum\xe9\nsigma_range_m = 1.0\n".encode("latin-1"))
    assert main(["run", "mars", "--scenario", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert "is not UTF-8 text" in err and str(path) in err and len(err.splitlines()) == 1


def test_a_study_scenario_round_trips_and_the_setup_marks_it():
    sc = scenarios.MarsScenario.study(days=1.0)
    text = sfm.dump(sc)
    assert 'setup = "study"' in text and "gravity_degree = 8" in text
    assert sfm.loads(text).scenario == sc
    assert sfm.loads('[run]\nsetup = "study"\ndays = 1.0\n').scenario == sc
    paper = sfm.loads("")
    assert paper.scenario.paper_setup and paper.run["setup"] == "paper"


def test_q_acc_derived_from_the_models():
    sf = sfm.loads('[truth_model]\nsrp = true\n[filter]\nq_acc = "derived"\n')
    assert sf.scenario.truth_model.srp and 0.0 < sf.scenario.q_acc < 1e-12  # SRP alone
    same = sfm.loads('[filter]\nq_acc = "derived"\n').scenario
    assert same.q_acc == 0.0  # truth and filter alike: nothing to stand for


def test_a_truth_model_apart_runs_from_the_cli_and_python_with_identical_numbers(tmp_path, capsys):
    text = ("[run]\ndays = 0.05\nseed = 2\n[truth_model]\ngravity_degree = 4\nsrp = true\n"
            "third_bodies = [\"sun\", \"jupiter\", \"saturn\"]\n[filter]\nq_acc = 1e-5\n")
    code, cli = _run(capsys, tmp_path, text)
    assert code == 0 and cli["setup"] == "study" and "MRO95A 4x4" in cli["truth_model"]
    sf = sfm.load(tmp_path / "s.toml")
    assert not sf.scenario.paper_setup and sf.scenario.filter_model.is_paper
    py = scenarios.run(sf.scenario).summary()
    for key in ("position_error_m", "velocity_error_mps", "final_position_error_m",
                "updates_xnav", "updates_uv", "updates_cns"):
        assert cli[key] == py[key], key
    matched = scenarios.run(sf.scenario, truth_model="paper").summary()
    assert matched["position_error_m"] != py["position_error_m"]


def test_a_timing_model_pulsar_in_a_file_runs_dumps_checks_and_takes_faults(tmp_path, capsys):
    from xnavlab.mars.timing import pint_bridge

    src = pint_bridge.examples_path("J1614-2230_NANOGrav_12yv3.wb.gls.par")
    (tmp_path / "m.par").write_text(src.read_text())
    text = ("[run]\ndays = 0.05\n[xnav]\npulsars = [\"B0531+21\", \"B1937+21\", {par = \"m.par\", "
            "flux_ph_cm2_s = 1e-4, pulsed_fraction = 0.5, width_s = 1e-4}]\n")
    code, res = _run(capsys, tmp_path, text, "--faults", "xnav.J1614:step:1e-5@1500+2000")
    assert code == 0 and res["detector"] == "combined" and res["updates_xnav"] > 0
    assert [(f["component"], f["spec"]) for f in res["faults"]] == [
        (2, "xnav.J1614:step:1e-05@1500+2000")]
    sf = sfm.load(tmp_path / "s.toml")
    assert sfm.loads(sfm.dump(sf.scenario)).scenario == sf.scenario
    assert main(["scenario", "--check", str(tmp_path / "s.toml")]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["scenario"]["pulsars"][2]["name"] == "J1614-2230"
    assert out["units"]["q_acc"] == "m^2/s^3" and "kg" in out["units"]["truth_model"]
    bare = "[run]\ndays = 0.05\n[xnav]\npulsars = [\"m.par\"]\n"
    code, err = _run(capsys, tmp_path, bare)
    assert code == 2 and "J1614-2230" in err and "flux_ph_cm2_s, pulsed_fraction, width_s" in err


# ---- issue 35: every field of the file, given anything, is used or refused in one line ----------

from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

#: TOML values of every kind: numbers of any size (nan, inf), booleans, text, lists, tables
_SCALAR = st.one_of(st.integers(-10**6, 10**6).map(str), st.booleans().map(lambda b: str(b).lower()),
                    st.floats(allow_nan=True, allow_infinity=True).map(
                        lambda x: "nan" if x != x else ("inf" if x == float("inf") else
                                                        "-inf" if x == float("-inf") else repr(x))),
                    st.text("abcxyz.+-_ 0123456789", max_size=8).map(lambda s: '"' + s + '"'),
                    st.sampled_from(['"paper"', '"none"', '"B1937+21"', '"Vega"', '"uv"', '"de405"']))
_VALUE = st.one_of(_SCALAR, st.lists(_SCALAR, max_size=4).map(lambda xs: "[" + ", ".join(xs) + "]"),
                   _SCALAR.map(lambda v: "{ x = " + v + " }"))
@settings(max_examples=200)   # every field a few times (one example is ~25 ms)
@given(st.sampled_from(sorted(sfm._KEYS)), _VALUE)
def test_any_value_of_any_field_is_used_or_refused_in_one_line_naming_the_field(field, value):
    section, key = field
    try:
        sf = sfm.loads(f"[{section}]\n{key} = {value}\n")
    except ValueError as exc:
        msg = str(exc)
        assert "\n" not in msg and key in msg, msg
    else:   # used: the file written back reads the same settings
        assert sfm.loads(sfm.dump(sf.scenario, sf.run, sf.detector)).scenario == sf.scenario


@pytest.mark.parametrize("field", sorted(sfm._KEYS))
def test_a_table_where_a_value_belongs_is_refused_for_every_field(field):
    section, key = field
    with pytest.raises(ValueError, match=key):
        sfm.loads(f"[{section}]\n{key} = {{ x = 1 }}\n")


def test_a_bad_fault_spec_is_refused_by_check_not_first_by_the_run():
    with pytest.raises(ValueError, match=r"^(scenario file: )?\[detector\] faults: "
                                         r"bad fault item 'abc'"):
        sfm.loads('[detector]\nfaults = "abc"\n')


@pytest.mark.parametrize(("faults", "words"), [
    ("abc", "[detector] faults: bad fault item 'abc': expected"),
    ("uv.range:step:1@700+300,uv.range:step:1@700+300", "[detector] faults lists "
                                                        "uv.range:step:1@700+300 twice"),
    (" ", "[detector] faults must be 'paper' or a fault spec"),  # was a run with faults " "
    ("uv.range:stuck:3@700+300", "[detector] faults: bad fault item 'uv.range:stuck:3@700+300': "
                                 "magnitude of a stuck fault must be 0"),
])
def test_a_fault_spec_is_named_as_the_files_key(faults, words):
    """Review 35m (6) 1, pattern Q: '[detector] faults: spec: bad fault item' named parse_faults'
    parameter inside the key's message; a blank spec ran as the combined detector's run."""
    with pytest.raises(ValueError) as info:
        sfm.loads(f'[detector]\nfaults = "{faults}"\n')
    assert str(info.value).removeprefix("scenario file: ").startswith(words), str(info.value)
    assert "spec" not in str(info.value).replace("fault spec", "")


@pytest.mark.parametrize(("text", "words"), [
    ("[[run]]\ndays = 1\n", "[[run]] is an array of tables; write [run] (one table)"),
    ("days = 3\n", "the key 'days' is outside any section: put it under [run]"),
    ("dt_s = 3\n", "the key 'dt_s' is outside any section: put it under [xnav] or [uv] or [cns]"),
    ("run = 3\n", "run is a section: write [run] and its keys under it"),
    ("bogus = 1\n", "the key 'bogus' is outside any section: no section has it (sections: run,"),
    ("[[gps]]\nx = 1\n", "unknown section [[gps]] (sections, one table each: run,"),
])
def test_the_files_structure_is_named_as_written(text, words):
    """Review 35m (3) 3: [[run]] was "unknown section [run] (sections: run, ...)" and a key
    outside any section "unknown section [days]"."""
    with pytest.raises(ValueError) as info:
        sfm.loads(text)
    assert str(info.value).startswith(f"scenario file: {words}"), str(info.value)


def test_a_par_without_f0_names_the_pulsar_entry_and_the_file(tmp_path, capsys):
    """Review 35m (3) 2: "[xnav] path: its F0 (Hz) must be a real number ..., got 0.0"."""
    (tmp_path / "nof0.par").write_text("PSR J0000+00\nRAJ 1:00:00\nDECJ 1:00:00\n")
    path = tmp_path / "s.toml"
    path.write_text('[xnav]\npulsars = ["B0531+21", "nof0.par"]\n')
    assert main(["scenario", "--check", str(path)]) == 2
    assert capsys.readouterr().err.strip() == (
        f"xnavlab: error: scenario file {str(path)!r}: [xnav] pulsars[1]: "
        f"{str(tmp_path / 'nof0.par')!r} is not a pulsar timing model: it has no F0 line (the "
        f"spin frequency, Hz, in every timing model)")


def test_a_short_plain_run_is_not_refused_for_the_combined_detectors_arming_time():
    # issue 35: a 0.005-day file without faults was refused: "[detector] arm_s ... [0, 432)"
    assert sfm.loads("[run]\ndays = 0.005\n").scenario.days == 0.005
    with pytest.raises(ValueError, match=r"arm_s \(600 s, .*\) must be shorter than the run: "
                                         r"\[run\] days = 0.005 is 432 s"):
        sfm.loads('[run]\ndays = 0.005\n[detector]\nfaults = "uv.range:step:1e5@100+10"\n')


@pytest.mark.parametrize("text, words", [
    ("[xnav]\ndt_s = -1\n", "[xnav] dt_s must be a real number in [0.1, 86400], got -1"),
    ('[xnav]\nnoise = "x"\n', "[xnav] noise must be one of 'paper', 'crlb', got 'x'"),
    ('[uv]\nrange_model = "q"\n', "[uv] range_model must be one of"),
    ('[xnav]\npulsars = ["B1937+21"]\nsigma_m = [1.0, 2.0]\n',
     "[xnav] sigma_m must hold 1 value, one a pulsar, got 2"),
    ("[xnav]\nsigma_m = [1.0, 2.0, -3, 4]\n", "[xnav] sigma_m[2] must be a real number"),
    ('[run]\nsubsystems = ["uv", "cns"]\nbeta = [0.5, 0.5, 0.5]\n', "[run] beta must hold 2 "
                                                                     "factors, one a subsystem, got 3"),
    # review 35j: one subsystem takes no beta (only the factors' ratios count)
    ('[run]\nsubsystems = ["uv"]\nbeta = [0.5, 0.5]\n', "[run] beta is set but [run] subsystems "
                                                         "= ['uv'] runs one local filter"),
    ('[run]\nsubsystems = ["uv"]\nrecord_dt = 1.0\n', "[run] record_dt must be at least 3 s "
                                                       "([uv] dt_s, the shortest measurement"),
])
def test_a_bad_value_is_named_by_the_file_s_key_not_the_field(text, words):
    """Review 35 F.27: '[xnav] dt_s: dt_xnav must be ...' and 'must hold 1 values'."""
    with pytest.raises(ValueError) as info:
        sfm.loads(text)
    assert str(info.value) == f"scenario file: {words}" or words in str(info.value)
    assert "dt_xnav" not in str(info.value) and "xnav_" not in str(info.value)


def test_days_on_the_command_line_rechecks_the_file_s_settings_with_its_name(tmp_path, capsys):
    """Review 35 F.27: --days 0.03 with settle_days = 0.04 in a file blamed settle_days
    without the file and with another range than scenario --check."""
    path = tmp_path / "s.toml"
    path.write_text("[run]\nsettle_days = 0.04\n")
    assert main(["run", "mars", "--scenario", str(path), "--days", "0.03"]) == 2
    err = capsys.readouterr().err.strip()
    assert err == (f"xnavlab: error: scenario file {str(path)!r}: [run] settle_days must be a "
                   f"real number in [0, 0.03), got 0.04 (with --days 0.03)")
    path2 = tmp_path / "s2.toml"
    path2.write_text("[run]\ndays = 0.03\nsettle_days = 0.04\n")
    assert main(["scenario", "--check", str(path2)]) == 2
    assert "[run] settle_days must be a real number in [0, 0.03), got 0.04" in capsys.readouterr().err


@pytest.mark.parametrize("text, flags, words", [
    ('[run]\ndays = 30\n[detector]\nname = "combined"\narm_s = 200000\n', ["--days", "1"],
     "[detector] arm_s (200000 s, when the combined detector's tests start) must be shorter "
     "than the run: --days 1 is 86400 s"),
    ("[run]\ndays = 30\nsettle_days = 5\n", ["--days", "1e0"],
     "[run] settle_days must be a real number in [0, 1), got 5.0 (with --days 1e0)"),
    ('[run]\ndays = 30\n[detector]\nname = "wavelet"\ntrain_days = 10\n', ["--days", "1"],
     "[detector] train_days must be a real number in (0, 1), got 10.0 (with --days 1)"),
    ("[run]\nsettle_days = 0.5\n", ["--days", "0.1", "--seed", "3"],
     "[run] settle_days must be a real number in [0, 0.1), got 0.5 (with --days 0.1, --seed 3)"),
])
def test_the_flags_a_file_s_setting_clashes_with_are_named_as_typed(tmp_path, capsys, text,
                                                                     flags, words):
    """Review 35l (6) 8: a message that leads with another key said "[run] days = 1 ... (with
    days = 1)" for the flag --days 1, a days the file does not hold."""
    path = tmp_path / "s.toml"
    path.write_text(text)
    assert main(["run", "mars", "--scenario", str(path), *flags, "--quiet"]) == 2
    assert capsys.readouterr().err.strip() == (f"xnavlab: error: scenario file {str(path)!r}: "
                                               f"{words}")


@pytest.mark.parametrize("content, words", [
    (b"\xff\xfeRAJ 1\n", "is not UTF-8 text (byte 0xff at position 0)"),
    (b"PSR J0000\nRAJ foo\nDECJ 1\nF0 1\nPEPOCH 55000\n", "PINT cannot read the timing model"),
])
def test_a_par_file_that_cannot_be_read_is_named(tmp_path, content, words):
    """Review 35 F.27: a raw codec error, or astropy's, without the .par's name."""
    (tmp_path / "p.par").write_bytes(content)
    (tmp_path / "s.toml").write_text('[xnav]\npulsars = ["p.par"]\n')
    with pytest.raises(ValueError) as info:
        sfm.load(tmp_path / "s.toml")
    assert words in str(info.value) and str(tmp_path / "p.par") in str(info.value)
    assert len(str(info.value).splitlines()) == 1


# ---- review 35 B.6: a key the other settings make inert is refused, not accepted and unused ----


@pytest.mark.parametrize("text, words", [
    ('[run]\nsubsystems = ["uv"]\n[xnav]\nsigma_m = [1.0, 1.0, 1.0, 1.0]\n',
     "[xnav] sigma_m is set but [run] subsystems = ['uv'] runs no xnav: leave it out or add 'xnav'"),
    ('[run]\nsubsystems = ["uv"]\n[xnav]\ndt_s = 100.0\n',
     "[xnav] dt_s is set but [run] subsystems = ['uv'] runs no xnav"),
    ('[run]\nsubsystems = ["uv"]\n[xnav]\npulsars = ["B1937+21"]\n',
     "[xnav] pulsars is set but [run] subsystems = ['uv'] runs no xnav"),
    ('[run]\nsubsystems = ["xnav", "uv"]\n[cns]\nstars = ["Sirius", "Vega", "Canopus"]\n',
     "[cns] stars is set but [run] subsystems = ['xnav', 'uv'] runs no cns"),
    ('[run]\nsubsystems = ["xnav", "cns"]\n[uv]\nsigma_range_m = 100.0\n',
     "[uv] sigma_range_m is set but [run] subsystems = ['xnav', 'cns'] runs no uv"),
    ('[run]\nsubsystems = ["xnav"]\n[uv]\nlimb = "oblate"\n',
     "[uv] limb is set but [run] subsystems = ['xnav'] runs neither uv nor cns: leave it out or "
     "add one of them"),
    ('[xnav]\nsigma_m = [1.0, 1.0, 1.0, 1.0]\narea_m2 = 2.0\n',
     "[xnav] area_m2 = 2.0 is unused: [xnav] sigma_m gives the ranging noise it would compute"),
    ('[detector]\nname = "none"\npfa = 0.5\n',
     "[detector] pfa is set but the run's detector is none ([detector] name = \"none\"): only "
     "the wavelet detector uses it; leave it out or name that detector"),
    ('[detector]\nname = "wavelet"\nalpha = 0.5\n',
     "[detector] alpha is set but the run's detector is wavelet"),
    ('[detector]\nfaults = "uv.range:step:1e3@1000+10"\npfa = 0.5\n',
     "[detector] pfa is set but the run's detector is combined (no [detector] name and faults: "
     "the combined detector)"),
    ('[run]\ndays = 0.2\n[detector]\narm_s = 20000\n',
     "[detector] arm_s is set but the run's detector is none (no [detector] name and no faults: "
     "a plain run): only the combined detector uses it"),
    ('[run]\ndays = 0.2\n[detector]\narm_s = 20000\nfaults = "uv.range:step:1e3@1000+10"\n',
     "[detector] arm_s (20000 s, when the combined detector's tests start) must be shorter than "
     "the run"),
    ('[detector]\nname = "chi2"\ntrain_days = 0.5\n',
     "[detector] train_days is set but the run's detector is chi2 ([detector] name = \"chi2\"): "
     "only the wavelet or combined detectors use it; leave it out or name one of them"),
    ('[truth_model]\nsrp = false\narea_m2 = 50.0\n',
     "[truth_model] area_m2 = 50 is unused: srp is false (no solar radiation pressure)"),
    ('[filter_model]\nreflectivity = 2.0\n',
     "[filter_model] reflectivity = 2 is unused: srp is false"),
])
def test_a_key_made_inert_by_another_setting_is_refused_naming_both(text, words):
    with pytest.raises(ValueError) as info:
        sfm.loads(text)
    msg = str(info.value)
    assert words in msg and len(msg.splitlines()) == 1, msg


@pytest.mark.parametrize("text", [
    '[run]\nsubsystems = ["uv"]\n[xnav]\ndt_s = 500.0\nnoise = "paper"\n',   # at their defaults
    '[detector]\nname = "none"\npfa = 1e-5\narm_s = 600.0\n',
    '[detector]\nname = "wavelet"\npfa = 0.01\ntrain_days = 0.5\n',
    '[detector]\nname = "combined"\narm_s = 100.0\nrate_per_day = 2.0\nadaptive = false\n',
    '[truth_model]\nsrp = false\narea_m2 = 10.0\n',                # the dump writes every key
])
def test_a_key_at_its_default_or_used_by_the_run_is_accepted(text):
    sf = sfm.loads(text)
    assert sfm.loads(sfm.dump(sf.scenario, sf.run, sf.detector)).scenario == sf.scenario


def test_a_dump_with_subsystems_edited_still_loads():
    text = sfm.dump().replace('subsystems = ["xnav", "uv", "cns"]', 'subsystems = ["uv"]')
    assert 'subsystems = ["uv"]' in text and sfm.loads(text).scenario.subsystems == ("uv",)


def test_the_detector_flags_recheck_the_file_s_detector_keys(tmp_path, capsys):
    path = tmp_path / "s.toml"
    path.write_text('[run]\ndays = 0.05\n[detector]\nname = "wavelet"\npfa = 0.01\n')
    assert main(["scenario", "--check", str(path)]) == 0
    capsys.readouterr()
    assert main(["run", "mars", "--scenario", str(path), "--detector", "chi2"]) == 2
    err = capsys.readouterr().err.strip()
    assert err == (f"xnavlab: error: scenario file {str(path)!r}: [detector] pfa is set but the "
                   f"run's detector is chi2 ([detector] name = \"chi2\"): only the wavelet "
                   f"detector uses it; leave it out or name that detector (with --detector chi2)")


# ---- review 35b: what run refuses, --check refuses, in the file's words ----

@pytest.mark.parametrize("text, words", [
    ('[run]\nlocal_filter = "ukf"\nbackend = "numpy"\n[detector]\n'
     'faults = "uv.range:step:1e3@1000+10"\n',
     '[detector] faults (a fault-tolerant run) runs with [run] backend = "numba" and '
     'local_filter = "ekf" only, got backend = "numpy" and local_filter = "ukf"'),
    ('[run]\nbackend = "numpy"\n[detector]\nname = "wavelet"\n',
     '[detector] name = "wavelet" (a fault-tolerant run) runs with'),
    ("[orbit]\nt0 = -1e12\n", "[orbit] t0 must be in [-3158136000 (1899-12-04T00:00:00 TDB), "
                              "6311476800 (2200-01-02T00:00:00 TDB)] s TDB past J2000 (the run, t0 "
                              "to t0 + days, in DE421), got -1000000000000.0"),
    ('[run]\ndays = 30\n[orbit]\nt0 = 6.313e9\nfilter_ephem = "de405"\n', "in DE405 and DE421"),
])
def test_check_refuses_what_run_would_refuse(tmp_path, capsys, text, words):
    """Review 35b N5/N6: faults with the numpy backend or the UKF, and t0 outside DE421, passed
    scenario --check; run then blamed flags never given or an internal 't'."""
    path = tmp_path / "s.toml"
    path.write_text(text)
    assert main(["scenario", "--check", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert words in err and str(path) in err and len(err.splitlines()) == 1, err
    sfm.loads("[run]\nbackend = \"numpy\"\n")  # no faults, no detector: a plain numpy run


def test_flags_that_move_the_run_past_the_ephemeris_name_the_file_s_key(tmp_path, capsys):
    path = tmp_path / "s.toml"
    path.write_text("[run]\ndays = 0.01\n[orbit]\nt0 = 6.3e9\n")
    assert main(["run", "mars", "--scenario", str(path), "--days", "365"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"xnavlab: error: scenario file {str(path)!r}: [orbit] t0 must be in "
                          "[-3158136000 (1899-12-04T00:00:00 TDB), 6282532800 (2199-02-01T00:00:00 "
                          "TDB)]") and err.endswith("(with --days 365)"), err


def test_a_flag_that_makes_the_run_fault_tolerant_names_the_file_s_backend(tmp_path, capsys):
    path = tmp_path / "s.toml"
    path.write_text('[run]\nbackend = "numpy"\n')
    assert main(["run", "mars", "--scenario", str(path), "--faults", "uv.range:step:1e3@1000+10"]) == 2
    assert capsys.readouterr().err.strip() == (
        'xnavlab: error: --faults: a fault-tolerant run needs backend numba and the EKF, got '
        '[run] backend = "numpy" in the scenario file')


def test_a_file_with_a_byte_order_mark_is_read(tmp_path):
    """Review 35b N21: 'is not valid TOML: Invalid statement (at line 1, column 1)'."""
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf[uv]\nsigma_range_m = 2500.0\n")
    assert sfm.load(path).scenario.sigma_range_m == 2500.0


@pytest.mark.parametrize("bad", [{}, "abc", 3])
def test_scenario_json_refuses_what_is_no_scenario(bad):  # review 35d D37's class: TypeError
    with pytest.raises(ValueError, match=r"^scenario must be a MarsScenario, got "):
        sfm.scenario_json(bad)


def test_the_dump_says_how_many_stars_a_file_takes():
    """Review 35e: the dump said 'the three stars' while one star (one angle) is taken."""
    assert sfm.loads("[cns]\nstars = [\"Vega\"]\n").scenario.stars == ("Vega",)
    line = next(ln for ln in sfm.dump().splitlines() if ln.startswith("# stars"))
    assert "one or more (none twice)" in line and "the three stars" not in line


def test_load_refuses_a_path_that_is_no_path():
    """Review 35j (class of (1) 18): load({}) raised Path's TypeError."""
    with pytest.raises(ValueError, match=r"^scenario file must be a path \(a str or pathlib.Path\), "
                                         r"got dict \{\}$"):
        sfm.load({})
    with pytest.raises(ValueError, match=r"^scenario file must name a file, got ''$"):
        sfm.load("")


@pytest.mark.parametrize("call, name", [
    (lambda: sfm.detector_name(None), "detector"),
    (lambda: sfm.detector_name({}), "detector"),
    (lambda: sfm.detector_name({"name": None, "faults": None}), r"detector\['faults'\]"),
    (lambda: sfm.detector_name({"name": 1, "faults": ""}), r"detector\['name'\]"),
    (lambda: sfm.check_detector({}), "detector"),
    (lambda: sfm.check_detector({"name": "wavelet", "faults": ""}), "detector"),
])
def test_detector_helpers_name_their_parameter(call, name):
    """Review 35k (1) 25: detector_name(None) and check_detector({}) raised TypeError/KeyError."""
    with pytest.raises(ValueError, match=f"^{name} must"):
        call()
