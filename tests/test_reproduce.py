"""The registry: every registered reproduction passes; results serialise; IDs are unique."""

import json

import pytest

from xnavlab import reproduce


def test_registry_lists_the_part_one_id():
    assert "xnav-ranging" in reproduce.ids()
    rep = reproduce.get("xnav-ranging")
    assert rep.source and rep.title and rep.chapter


def test_unknown_id():
    with pytest.raises(ValueError, match="unknown reproduction id 'nope'; known ids:"):
        reproduce.get("nope")


def test_xnav_ranging_within_five_percent():
    res = reproduce.run("xnav-ranging")
    res.assert_passed()
    for name, paper in res.paper.items():
        assert abs(res.ours[name] - paper) <= 0.05 * paper
    payload = json.loads(res.to_json())
    assert payload["pass"] is True and payload["id"] == "xnav-ranging"
    assert "| B0531+21 |" in res._repr_markdown_()


def test_failed_checks_are_reported():
    res = reproduce.Result("demo", [reproduce.check_rel("x", 1.0, 2.0, 0.1)])
    assert not res.passed
    with pytest.raises(AssertionError, match="demo failed"):
        res.assert_passed()
    assert not reproduce.Result("empty", []).passed


def test_check_helpers():
    assert reproduce.check_abs("a", 10.0, 12.0, 3.0).passed
    assert not reproduce.check_range("b", 1.0, float("nan"), 0.0, 2.0, "range").passed
    assert reproduce.check_true("c", "x", "x", True, "same").passed


def test_double_registration_is_refused():
    reproduce.ids()
    with pytest.raises(ValueError, match="registered twice"):
        reproduce.register("xnav-ranging", title="t", source="s", chapter="c")(lambda out=None: None)


def test_run_writes_figures(tmp_path):
    res = reproduce.run("xnav-ranging", out=tmp_path / "figs")
    assert res.figures and all((tmp_path / "figs").glob("*.png"))


def test_unclaimed_rows_are_shown_but_do_not_decide():
    rows = [reproduce.check_rel("x", 1.0, 1.0, 0.1), reproduce.check_info("rank", "a", "b", "see note")]
    res = reproduce.Result("demo", rows)
    assert res.passed
    assert "NOT CLAIMED" in res.table()
    assert res.to_dict()["checks"] == {"x": "PASS", "rank": "NOT CLAIMED"}
    only_info = reproduce.Result("info", rows[1:])
    assert not only_info.passed


@pytest.mark.parametrize("rid", ["toa-terms", "mars-orbit"])
def test_part_one_sanity_reproductions(rid):
    reproduce.run(rid).assert_passed()


def test_package_never_switches_the_matplotlib_backend():
    # a notebook kernel's inline backend must survive reproduce.run(..., out=...)
    from pathlib import Path

    root = Path(reproduce.__file__).parent
    offenders = [p.name for p in root.rglob("*.py")
                 if "matplotlib.use(" in "".join(l for l in p.read_text().splitlines(True)
                                                if not l.lstrip().startswith(">>>"))]
    assert not offenders, offenders


@pytest.mark.parametrize("rid", reproduce.ids())
def test_every_registered_reproduction_passes(rid):
    """Every number the book claims is asserted here too (paper, ours, tolerance in the table)."""
    res = reproduce.run(rid)
    res.assert_passed()
    claimed = [c for c in res.checks if c.claimed]
    assert claimed and all(c.tolerance for c in claimed)
    assert res.note, f"{rid}: say how ours was obtained and where it differs"
