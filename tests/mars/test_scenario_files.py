"""Scenario files: dump and read back, every field group reaches the run, flags override."""

import json

import pytest

from xnavlab.cli import main
from xnavlab.mars import scenario_files as sfm
from xnavlab.mars import scenarios


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
])
def test_a_bad_field_is_one_line_naming_it(tmp_path, capsys, text, words):
    code, err = _run(capsys, tmp_path, text)
    assert code == 2 and len(err.splitlines()) == 1 and words in err, err


def test_a_missing_file_is_one_line(capsys):
    assert main(["run", "mars", "--scenario", "/nonexistent/s.toml"]) == 2
    assert "cannot be read" in capsys.readouterr().err
