"""The PL/INS fault diagnosis as a whole (chapter 12): its reproductions pass and write their
figures. Each module of xnavlab.plins.parity has its own test module."""

import pytest

from xnavlab import reproduce


@pytest.mark.parametrize("rid", ["plins-step", "plins-ramp"])
def test_reproductions_pass(rid):
    assert rid in reproduce.ids()
    result = reproduce.run(rid)
    result.assert_ok()
    assert result.note and reproduce.get(rid).chapter == "12_fuzzy_parity"


def test_reproduction_figures(tmp_path):
    # both judge single runs with check_event, which needs >= 32 of them
    res = reproduce.run("plins-step", out=tmp_path, n_runs=32)
    res2 = reproduce.run("plins-ramp", out=tmp_path)
    names = sorted(p.name for p in tmp_path.glob("*.png"))
    assert names == ["plins-fig2.png", "plins-fig3.png", "plins-fig4.png"]
    assert len(res.figures) == 2 and len(res2.figures) == 1
