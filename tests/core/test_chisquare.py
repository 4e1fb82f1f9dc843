"""The chi-square innovation detector (xnavlab.core.detection.chisquare): its false-alarm rate,
its detection of a bias online and in batch, and its statistic."""

import math

import numpy as np
import pytest

from xnavlab.core import detection as D
from xnavlab.core.faults import Fault, inject

DT = 3.0                # s, UV sampling of the paper


def _same_events(a, b):
    key = [(e.onset, e.end, e.cleared, e.test) for e in a]
    assert key == [(e.onset, e.end, e.cleared, e.test) for e in b]
    assert np.allclose([e.peak for e in a], [e.peak for e in b], rtol=1e-9)


def _innovations(n, m, seed):
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(m, m))
    S = A @ A.T + m * np.eye(m)
    nu = rng.multivariate_normal(np.zeros(m), S, n)
    return nu, S


@pytest.mark.parametrize("window", [1, 5])
def test_chi2_false_alarm_rate_near_alpha(window):
    nu, S = _innovations(200000, 3, 11)
    res = D.chi2_detect(np.arange(nu.shape[0]) * DT, nu, S, alpha=1e-2, window=window)
    assert res.data["dof"] == 3 * window
    assert 0.85e-2 <= res.false_alarm_rate <= 1.15e-2


def test_chi2_detects_bias_and_online_equals_batch():
    nu, S = _innovations(3000, 3, 12)
    t = np.arange(3000) * DT
    nu = inject(t, nu, [Fault("uv", "step", 10.0 * math.sqrt(S[0, 0]), 3000.0, 300.0, component=0)], "uv")
    S_n = np.broadcast_to(S, (3000, 3, 3))
    res = D.chi2_detect(t, nu, S_n, window=3, holdoff=5)
    assert res.first_onset_after(3000.0) == 3000.0
    big = [e for e in res.events if e.onset >= 3000.0]
    assert big[0].end >= 3000.0 + 300.0 - 2 * DT
    det = D.Chi2Detector(3, window=3, holdoff=5)
    flags = [det.update(ti, v, S) for ti, v in zip(t, nu, strict=True)]
    assert np.array_equal(flags, res.faulty)
    _same_events(det.all_events(), res.events)


def test_chi2_statistic_is_the_normalised_innovation_squared():
    nu, S = _innovations(50, 2, 13)
    stat, dof = D.chi2_statistic(nu, S)
    assert dof == 2 and np.allclose(stat, np.einsum("ni,ij,nj->n", nu, np.linalg.inv(S), nu))
    stat1, _ = D.chi2_statistic(nu[:, 0], np.full(50, S[0, 0]))
    assert np.allclose(stat1, nu[:, 0] ** 2 / S[0, 0])


@pytest.mark.parametrize(("S", "words"), [
    ([[1.0, 2.0], [2.0, 1.0]], "indefinite"), ([[1.0, 1.0], [1.0, 1.0]], "singular"),
])
def test_the_chi2_statistic_refuses_an_indefinite_or_singular_S_by_name(S, words):
    with pytest.raises(ValueError, match=rf"^S\[0\] must be positive definite, but it is {words}"):
        D.chi2_statistic(np.ones((3, 2)), S)


def test_the_online_test_refuses_a_complex_or_misshapen_S():
    det = D.Chi2Detector(m=1)
    with pytest.raises(ValueError, match="^S must hold real numbers"):
        det.update(0.0, [1.0], [[1.0 + 1j]])
    with pytest.raises(ValueError, match=r"^S must have shape \(1, 1\)"):
        det.update(0.0, [1.0], np.eye(2))


def test_issue35_chi2_statistic_refuses_a_window_longer_than_the_data():
    # Review 35f finding 23: no sum had the dof m * window returned.
    with pytest.raises(ValueError, match=r"^window must be an integer in \[1, 3\]"):
        D.chi2_statistic(np.ones((3, 2)), np.tile(np.eye(2), (3, 1, 1)), window=10)
    stat, dof = D.chi2_statistic(np.ones((3, 2)), np.tile(np.eye(2), (3, 1, 1)), window=3)
    assert stat.tolist() == [2.0, 4.0, 6.0] and dof == 6


@pytest.mark.parametrize("call", [
    lambda: D.chi2_statistic([], np.eye(2)),
    lambda: D.chi2_detect(np.arange(3.0), [], np.ones((3, 1, 1))),
])
def test_an_empty_nu_is_named_before_s(call):
    with pytest.raises(ValueError, match=r"^nu must hold at least one innovation"):
        call()


@pytest.mark.parametrize("call", [
    lambda: D.chi2_statistic([1.0], np.eye(2)),
    lambda: D.chi2_detect(np.arange(3.0), [1.0], np.ones(3)),
    lambda: D.chi2_detect(np.arange(3.0), [1.0], np.ones((3, 1, 1))),
])
def test_a_short_nu_is_named_against_a_well_formed_s(call):
    with pytest.raises(ValueError, match=r"^nu must have shape .* to match S of shape"):
        call()


def test_chi2_statistic_refuses_a_statistic_past_the_float_range():
    """Review 35j (1) 7: a subnormal S (1e-320) passes as definite and nu = 1e200 with
    S = 1e-200 is allowed: nu^T S^-1 nu overflowed with a RuntimeWarning."""
    for nu, S in ((np.ones(3), np.full(3, 1e-320)), (np.full(3, 1e200), np.full(3, 1e-200)),
                  (np.full((3, 2), 1e200), 1e-200 * np.eye(2))):
        with pytest.raises(ValueError, match=r"^nu is too large against S: nu\^T S\^-1 nu passes "
                                             r"the float range \(1.8e308\) at sample 0"):
            D.chi2_statistic(nu, S)
    with pytest.raises(ValueError, match=r"^nu is too large against S: the running sum"):
        D.chi2_statistic(np.full(3, 1e150), np.full(3, 1e-8))
    with pytest.raises(ValueError, match=r"^nu is too large against S"):
        D.Chi2Detector(1).update(0.0, [1.0], [[1e-320]])
    with pytest.raises(ValueError, match=r"^nu is too large against S"):
        D.chi2_detect(np.arange(3.0), np.ones(3), np.full(3, 1e-320))


def test_chi2_detect_refuses_times_going_back():
    """Review 35j (5) 22: reversed times gave an event cleared before its onset."""
    with pytest.raises(ValueError, match=r"^t must be strictly increasing"):
        D.chi2_detect(np.arange(3.0)[::-1], np.r_[1.0, 10.0, 1.0], np.ones(3))


def test_a_row_of_innovations_against_per_sample_variances_names_nu():
    """Review 35k pattern E: nu of shape (1, N) (one row) beside S of shape (N,) was refused
    naming S, whose shape was right."""
    with pytest.raises(ValueError, match=r"^nu must have shape \(1000,\) to match S of shape "
                                         r"\(1000,\) \(the variances of a scalar measurement\), "
                                         r"got shape \(1, 1000\)"):
        D.chi2_detect(3.0 * np.arange(1000), np.ones((1, 1000)), np.full(1000, 25.0))


def test_a_clash_of_nu_and_per_sample_variances_names_the_odd_one():
    """After review 35k: per-sample variances S (N,) beside a well-formed nu (n, m), m > 1, named
    nu; S is the odd one there. A row nu (1, N) beside S (N,) still names nu."""
    with pytest.raises(ValueError, match=r"^S must have shape \(m, m\) or \(N, m, m\) with m = 2"):
        D.chi2_statistic([[1.0, 0.0], [0.0, 2.0]], [1.0], window=2)
    with pytest.raises(ValueError, match=r"^nu must have shape \(3,\) to match S of shape \(3,\)"):
        D.chi2_statistic([[1.0, 2.0, 3.0]], [1.0, 1.0, 1.0])
