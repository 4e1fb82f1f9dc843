"""Matched vs mismatched: the three cases, their set-ups, the table's columns and its cache."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from xnavlab.mars.models import force_models
from xnavlab.mars.navigation import model_mismatch, scenarios


def test_the_cases_and_their_setups():
    m = model_mismatch.case_scenario("matched", days=1.0, seed=3)
    d = model_mismatch.case_scenario("mismatched, derived q", days=1.0)
    p = model_mismatch.case_scenario("mismatched, default q", days=1.0)
    assert m.paper_setup and m.init_error == "random" and m.seed == 3
    assert d.truth_model == force_models.STUDY and d.filter_model == force_models.PAPER
    assert d.q_acc > 1e-6 and p.q_acc == scenarios.DEFAULT_Q_ACC and not p.paper_setup
    with pytest.raises(ValueError, match="case must be one of"):
        model_mismatch.case_scenario("both")


def test_a_short_table_has_every_column_and_reads_back_from_its_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("XNAVLAB_CACHE", str(tmp_path))
    rows = model_mismatch.mismatch_table(days=0.05, seeds=(0, 1))
    assert [r["case"] for r in rows] == list(model_mismatch.CASES)
    for r in rows:
        assert set(model_mismatch.TABLE_COLUMNS) <= set(r) and r["seeds"] == 2
        assert r["nees_lo"] < r["nees_hi"] and 0.0 <= r["nees_inside"] <= 1.0
    assert rows[0]["paper_setup"] and not rows[1]["paper_setup"]
    assert rows[2]["position_error_m"] > rows[1]["position_error_m"]  # no q for the difference
    assert list(tmp_path.glob("mismatch-runs-*.json"))
    assert model_mismatch.mismatch_table(days=0.05, seeds=(0, 1)) == rows


@pytest.mark.parametrize(("kw", "words"), [
    ({"seeds": ()}, "seeds must name at least one seed, got an empty list"),
    ({"seeds": (1, 1)}, "seeds lists 1 twice (items 0 and 1)"),
    ({"seeds": 3}, "seeds must be a list"),
    ({"seeds": [0, -1]}, "seeds[1] must be an integer in [0, 9223372036854775807], got -1"),  # D11
    ({"seeds": [0.5]}, "seeds[0] must be an integer in"),
    ({"days": 0.0}, "days must be a real number in (0, 365]"),
    ({"days": 1.0, "settle_days": 1.0}, "settle_days must be a real number in [0, 1)"),
])
def test_bad_arguments_are_refused(kw, words):
    with pytest.raises(ValueError) as exc:
        model_mismatch.mismatch_runs(cache=False, **kw)
    assert words in str(exc.value)


def test_the_setup_note_says_which_set_up_a_run_has():
    assert model_mismatch.setup_note(scenarios.MarsScenario()).startswith("Paper set-up:")
    note = model_mismatch.setup_note(model_mismatch.case_scenario("mismatched, derived q", 1.0))
    assert note.startswith("Study set-up: the truth flies Mars MRO95A 8x8") and "q_acc 0.00513" in note


def test_each_local_filter_s_nis_is_judged_from_the_same_cached_runs(tmp_path, monkeypatch):
    monkeypatch.setenv("XNAVLAB_CACHE", str(tmp_path))
    rows = model_mismatch.subsystem_nis(days=0.05, seeds=(0, 1))
    assert [(r["case"], r["subsystem"]) for r in rows] == [
        (c, s) for c in model_mismatch.CASES for s in ("xnav", "uv", "cns")]
    for r in rows:
        assert r["updates"] > 0 and r["nis_lo"] < r["dof"] < r["nis_hi"]
        assert r["nis_ratio"] == pytest.approx(r["nis"] / r["dof"])
        assert r["nis_verdict"] in ("inside", "conservative", "optimistic")
    assert {r["dof"] for r in rows if r["subsystem"] != "xnav"} == {3}
    ratio = {(r["case"], r["subsystem"]): r["nis_ratio"] for r in rows}
    for s in ("xnav", "uv", "cns"):          # the unallowed-for force model: every local sees it
        assert ratio["mismatched, default q", s] > ratio["matched", s]
    assert rows[6]["subsystem"] == "xnav" and rows[6]["nis_verdict"] == "optimistic"
    assert len(list(tmp_path.glob("mismatch-runs-*.json"))) == 1      # the table's runs
    assert model_mismatch.subsystem_nis(days=0.05, seeds=(0, 1)) == rows

def test_q_sweep_a_filter_without_process_noise_claims_more_than_it_has():
    out = model_mismatch.q_sweep((0.0, 1e-9), days=0.3, cache=False)
    (rms0, sigma0, _), (rms9, sigma9, _) = out["rms_sigma_nees"]
    assert out["q"].tolist() == [0.0, 1e-9]
    assert sigma0 < sigma9                 # more process noise, a larger claimed sigma
    assert np.all(np.isfinite(out["rms_sigma_nees"])) and rms0 > 0 and rms9 > 0


@pytest.mark.parametrize("bad", [dict(q_values=()), dict(q_values=(-1e-11,)),
                                 dict(q_values=((1e-11,),)), dict(days=0.0)])
def test_q_sweep_checks_its_arguments(bad):
    with pytest.raises(ValueError, match="q_values|days"):
        model_mismatch.q_sweep(**bad, cache=False)



@pytest.mark.parametrize("call", [
    lambda: model_mismatch.mismatch_runs(days=0.01, seeds=[0], cache="no"),
    lambda: model_mismatch.mismatch_table(days=0.01, seeds=[0], cache=1),
    lambda: model_mismatch.subsystem_nis(days=0.01, seeds=[0], cache="no"),
    lambda: model_mismatch.q_sweep(q_values=[0.0], days=0.01, cache="no"),
])
def test_cache_must_be_a_bool(call):  # review 35d D9
    with pytest.raises(ValueError, match="cache must be True or False"):
        call()


@pytest.mark.parametrize(("kw", "words"), [
    ({"q_values": [0.0, 0.0]}, "q_values lists 0.0 twice (items 0 and 1)"),  # review 35d D10
    ({"q_values": [1e-11, 0.0, 1e-11]}, "q_values lists 1e-11 twice (items 0 and 2)"),
    ({"days": 400.0}, "days must be a real number in (0, 365], got 400.0"),  # was (0, inf)
])
def test_q_sweep_refuses_a_repeated_psd_and_names_the_real_range_of_days(kw, words):
    with pytest.raises(ValueError) as exc:
        model_mismatch.q_sweep(**{"q_values": [0.0], "days": 0.01, **kw}, cache=False)
    assert str(exc.value) == words


@given(st.lists(st.integers(-2**64, 2**64), min_size=1, max_size=4))
def test_seeds_are_refused_under_their_own_name_with_the_scenario_range(seeds):
    bad = [i for i, s in enumerate(seeds) if not 0 <= s <= 2**63 - 1]
    again = [i for i, s in enumerate(seeds) if s in seeds[:i]]
    if not bad and not again:
        return  # a good list: running it is the other tests' business
    with pytest.raises(ValueError) as exc:
        model_mismatch.mismatch_runs(days=0.01, seeds=seeds, cache=False)
    words = str(exc.value)
    if bad and (not again or bad[0] < again[0]):  # items are checked in order
        assert words == (f"seeds[{bad[0]}] must be an integer in [0, 9223372036854775807], "
                         f"got {seeds[bad[0]]}")
    else:
        assert words.startswith(f"seeds lists {seeds[again[0]]} twice (items ")


@pytest.mark.parametrize("bad", [{}, None, "paper", force_models.PAPER])
def test_setup_note_refuses_what_is_not_a_scenario(bad):  # review 35d D12: AttributeError
    with pytest.raises(ValueError) as exc:
        model_mismatch.setup_note(bad)
    assert str(exc.value).startswith("scenario must be a MarsScenario, got ")
    assert len(str(exc.value).splitlines()) == 1
