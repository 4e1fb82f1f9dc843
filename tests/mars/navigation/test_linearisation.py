"""The EKF and the UKF on the same UV measurements: shapes, agreement, the disk cache, refusals."""

import numpy as np
import pytest

from xnavlab.mars.navigation import linearisation


def test_both_filters_see_one_truth_and_agree_and_are_read_back_from_disk(tmp_path, monkeypatch):
    monkeypatch.setenv("XNAVLAB_CACHE", str(tmp_path))
    out = linearisation.ekf_and_ukf(days=0.001)
    n = out["hours"].size
    assert out["truth"].shape == out["ekf"].shape == out["ukf"].shape == (n, 6)
    assert out["hours"][0] == 0.0 and np.all(np.diff(out["hours"]) > 0)
    assert out["seconds"].shape == (2,) and np.all(out["seconds"] > 0)
    err = np.linalg.norm(out["ekf"][:, :3] - out["truth"][:, :3], axis=1)   # m
    gap = np.linalg.norm(out["ekf"][:, :3] - out["ukf"][:, :3], axis=1)     # m
    assert err[-1] < err[0] / 2                   # the UV updates pull both in
    assert np.all(gap <= 0.01 * err)              # ... to the same place
    assert len(list(tmp_path.glob("ekf-ukf-*.npz"))) == 1
    again = linearisation.ekf_and_ukf(days=0.001)
    assert all(np.array_equal(out[k], again[k]) for k in out)   # the stored wall times too


@pytest.mark.parametrize(("kw", "words"), [
    ({"days": 0.0}, "days"),
    ({"days": 31.0}, "days"),
    ({"record_dt": 0.0}, "record_dt"),
])
def test_bad_arguments_are_refused(kw, words):
    with pytest.raises(ValueError, match=words):
        linearisation.ekf_and_ukf(cache=False, **kw)


def test_cache_must_be_a_bool():  # review 35b N19 / 35d D8: "no" is a truthy string
    with pytest.raises(ValueError, match="cache must be True or False, got .no."):
        linearisation.ekf_and_ukf(days=0.01, cache="no")
