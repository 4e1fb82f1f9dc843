"""``campaign consistency --scenario FILE``: a campaign with a pulsar from a timing model and a
truth model apart from the filter's, its records carrying both; refused with other campaigns."""

import json

import pytest

from xnavlab.cli import main
from xnavlab.mars import campaigns, pint_bridge, scenarios


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
