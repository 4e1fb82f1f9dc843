"""Headline accuracies as Monte Carlo means: intervals, the cache, the refusals."""

import numpy as np
import pytest

from xnavlab.mars import headline


def test_mean_interval_is_the_student_t_interval_of_the_mean():
    v = np.random.default_rng(0).normal(10.0, 2.0, 32)
    r = headline.mean_interval(v)
    assert r["lo"] < r["mean"] < r["hi"] and r["n"] == 32
    assert r["hi"] - r["lo"] == pytest.approx(2 * 2.0395 * v.std(ddof=1) / np.sqrt(32), rel=1e-3)
    with pytest.raises(ValueError, match="at least two finite numbers"):
        headline.mean_interval([1.0])


def test_headline_runs_are_stored_and_reused(tmp_path, monkeypatch):
    monkeypatch.setenv("XNAVLAB_CACHE", str(tmp_path))
    a = headline.headline_numbers(n_seeds=3, days=0.2, faults=False, workers=1)
    b = headline.headline_numbers(n_seeds=3, days=0.2, faults=False, workers=1)
    assert a["quantities"] == b["quantities"] and a["directory"] == b["directory"]
    assert a["directory"].startswith(str(tmp_path))
    q = a["quantities"]
    assert set(q) >= {"fused_position_m", "fused_velocity_mps", "local_position_m.xnav",
                      "local_position_m.uv", "local_position_m.cns"}
    assert q["fused_position_m"]["lo"] <= q["fused_position_m"]["mean"] <= q["fused_position_m"]["hi"]


def test_faults_need_the_papers_thirty_days():
    with pytest.raises(ValueError, match="faults needs days = 30"):
        headline.headline_numbers(n_seeds=2, days=5.0, faults=True, cache=False)
