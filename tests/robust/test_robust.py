"""The ephemeris-error system as a whole (chapter 10): its reproductions pass, the Earth case claims
only the orders it can decide, and the memory sweep pairs its seeds. Each module's own tests are
in the test module of its name."""

import numpy as np
import pytest

from xnavlab import reproduce
from xnavlab import robust as rb
from xnavlab.reproductions import ch10_ephemeris_error as ch10


@pytest.mark.parametrize("rid", ["ukf-vs-ephemeris-error", "rkf-mars", "rkf-sweep", "rkf-residual-memory"])
def test_reproductions_pass(rid):
    reproduce.run(rid).assert_passed()


def test_rkf_earth_claims_the_decided_orders_of_the_paper():
    """With the registered 32 seeds, RKF < ASUKF and TDUKF < ASUKF are claimed and pass; the order
    of the RKF and the TDUKF is shown, not claimed (our reconstruction cannot decide it)."""
    res = reproduce.run("rkf-earth")
    res.assert_passed()
    rows = {c.name: c for c in res.checks}
    for a, b in (("RKF", "ASUKF"), ("TDUKF", "ASUKF")):
        c = rows[f"{a} better than {b} (paired RMSE difference, m)"]
        assert c.claimed and c.passed, c
    assert not rows["RKF better than TDUKF (paired RMSE difference, m)"].claimed


def test_rkf_memory_sweep_checks_its_input_and_pairs_the_seeds():
    out = ch10.rkf_memory_sweep((0.05,), seeds=(3,), body="mars", size=2000.0)
    assert np.isinf(out["se"][0])                          # one seed: no standard error
    runs = rb.compare_filters("mars", ("tdukf", "rkf"), error="growing", size=2000.0, seeds=(3,), lam=0.05)
    assert out["diff"][0] == pytest.approx(runs["rmse"]["rkf"] - runs["rmse"]["tdukf"], rel=1e-12)
    for bad in ((1.5,), (0.0,), ()):
        with pytest.raises(ValueError, match="lams"):
            ch10.rkf_memory_sweep(bad, seeds=(0,), body="mars", size=10.0)
