"""The ephemeris-error system as a whole (chapter 10): its reproductions run and their checks hold,
the Earth ranking is judged pair by pair, and the memory sweep pairs its seeds. Each module's own tests are
in the test module of its name."""

import numpy as np
import pytest

from xnavlab import reproduce
from xnavlab import robust as rb
from xnavlab.reproductions import ch10_ephemeris_error as ch10


@pytest.mark.parametrize("rid", ["ukf-vs-ephemeris-error", "rkf-mars", "rkf-sweep", "rkf-residual-memory"])
def test_reproductions_pass(rid):
    reproduce.run(rid).assert_ok()


def test_rkf_earth_judges_the_papers_ranking_pair_by_pair():
    """With the registered 32 seeds: the ranking's verdict follows its three adjacent pairs."""
    res = reproduce.run("rkf-earth")
    res.assert_ok()
    pairs = [res.check(f"{a} better than {b} (paired RMSE difference)")
             for a, b in (("RKF", "TDUKF"), ("TDUKF", "ASUKF"), ("ASUKF", "UKF"))]
    ranking = res.check("ranking of the mean RMSE, best first")
    verdicts = {c.verdict for c in pairs}
    expect = ("REPRODUCED" if verdicts == {"REPRODUCED"} else
              "NOT REPRODUCED" if "NOT REPRODUCED" in verdicts else "UNDECIDED")
    assert ranking.verdict == expect


def test_rkf_memory_sweep_checks_its_input_and_pairs_the_seeds():
    out = ch10.rkf_memory_sweep((0.05,), seeds=(3,), body="mars", size=2000.0)
    assert np.isinf(out["se"][0])                          # one seed: no standard error
    runs = rb.compare_filters("mars", ("tdukf", "rkf"), error="growing", size=2000.0, seeds=(3,), lam=0.05)
    assert out["diff"][0] == pytest.approx(runs["rmse"]["rkf"] - runs["rmse"]["tdukf"], rel=1e-12)
    for bad in ((1.5,), (0.0,), ()):
        with pytest.raises(ValueError, match="lams"):
            ch10.rkf_memory_sweep(bad, seeds=(0,), body="mars", size=10.0)
