"""``campaign consistency --scenario FILE``: a campaign with a pulsar from a timing model and a
truth model apart from the filter's, its records carrying both; refused with other campaigns."""

import json

import pytest

from xnavlab.cli import main
from xnavlab.mars.navigation import scenarios
from xnavlab.mars.studies import campaigns
from xnavlab.mars.timing import pint_bridge


def test_a_consistency_campaign_takes_a_scenario_files_pulsars_and_models(tmp_path, capsys):
    par = pint_bridge.examples_path("J1614-2230_NANOGrav_12yv3.wb.gls.par")
    (tmp_path / "s.toml").write_text(
        "[filter]\nq_acc = 1e-5\n[truth_model]\ngravity_degree = 2\n[xnav]\n"
        f"pulsars = [\"B0531+21\", {{par = \"{par}\", flux_ph_cm2_s = 1e-4, "
        "pulsed_fraction = 0.5, width_s = 1e-4}]\n")
    argv = ["campaign", "consistency", "--runs", "2", "--days", "0.02", "--workers", "1",
            "--out", str(tmp_path / "c"), "--scenario", str(tmp_path / "s.toml"), "--json"]
    assert main(argv) == 0
    out = json.loads(capsys.readouterr().out)
    p = out["runs"][0]["parameters"]
    assert p["pulsars"][1]["name"] == "J1614-2230" and p["truth_model"]["gravity_degree"] == 2
    assert p["q_acc"] == 1e-5 and out["runs"][1]["metrics"]["nis_dof"]["xnav"] == 2
    assert main(argv) == 0  # run again: both runs reused, the same records
    again = json.loads(capsys.readouterr().out)
    assert again["reused"] == 2 and again["runs"] == out["runs"]


def test_a_scenario_goes_with_the_consistency_campaign_only():
    with pytest.raises(ValueError, match="scenario goes with campaign consistency"):
        campaigns.campaign("detectors", days=1.0, scenario=scenarios.MarsScenario())


def _campaign(tmp_path, text, *extra, out="o"):
    (tmp_path / "f.toml").write_text(text)
    return main(["campaign", "consistency", "--runs", "1", "--workers", "1", "--json",
                 "--out", str(tmp_path / out), "--scenario", str(tmp_path / "f.toml"), *extra])


@pytest.mark.parametrize("text, key", [
    ("[run]\nrecord_dt = 86400", "[run] record_dt"),
    ("[run]\nsettle_days = 0.001", "[run] settle_days"),
    ("[detector]\nfaults = \"uv.range:step:1e3@1000+10\"", "[detector] faults"),
    ("[detector]\nname = \"chi2\"", "[detector] name")])
def test_a_key_the_consistency_campaign_does_not_use_is_refused(tmp_path, capsys, text, key):
    assert _campaign(tmp_path, text, "--days", "0.01") == 2
    err = capsys.readouterr().err
    assert f"{key} is not used by campaign consistency" in err and len(err.splitlines()) == 1


def test_the_consistency_campaign_uses_the_files_other_settings(tmp_path, capsys):
    text = "[run]\ndays = 0.01\nseed = 7\n[uv]\nsigma_range_m = 100.0"
    assert _campaign(tmp_path, text) == 0  # the file's days and seed
    out = json.loads(capsys.readouterr().out)
    p = out["runs"][0]["parameters"]
    assert p["fields"] == {"sigma_range_m": 100.0} and p["days"] == 0.01
    assert _campaign(tmp_path, "[uv]\nsigma_range_m = 100.0", "--days", "0.01", "--seed", "7",
                     out="p") == 0  # the same run from the flags
    again = json.loads(capsys.readouterr().out)
    assert again["runs"][0]["metrics"] == out["runs"][0]["metrics"]
    assert _campaign(tmp_path, "", "--days", "0.01", out="q") == 0  # the paper's UV noise
    paper = json.loads(capsys.readouterr().out)
    assert paper["runs"][0]["metrics"] != out["runs"][0]["metrics"]
