"""Fault decisions (xnavlab.attitude.diagnosis): the SOS and DOS decision tables and the
persistence, arming and confirmation of a diagnosis."""

import math

import numpy as np
import pytest

from xnavlab import attitude as att


def _patterns(table):
    """Every boolean pattern a table row allows (None: either)."""
    for loc, row in table.items():
        options = [[True, False] if v is None else [v] for v in row]
        for a in options[0]:
            for b in options[1]:
                for c in options[2]:
                    for d in options[3]:
                        pat = (a, b, c, d)
                        if loc == "star_tracker" and not any(pat[:3]):
                            continue
                        yield loc, pat


def test_sos_decision_rule_inverts_the_table():
    for loc, pat in _patterns(att.SOS_TABLE):
        assert att.sos_decide(np.array(pat)) == loc
    assert att.sos_decide(np.zeros(4, bool)) == "none"
    assert att.sos_decide(np.array([True, True, False, True])) == "unknown"
    out = att.sos_decide(np.array([[True, False, False, True], [False, False, False, True]]))
    assert out.tolist() == ["gyro_x", "gyro_skew"]
    with pytest.raises(ValueError, match="^crossed"):
        att.sos_decide([1, 0, 0, 1])


def test_dos_decision_rule_inverts_the_table():
    for loc, pat in _patterns(att.DOS_TABLE):
        assert att.dos_decide(np.array(pat)) == loc
    assert att.dos_decide(np.zeros(4, bool)) == "none"
    assert att.dos_decide(np.array([True, True, False, False])) == "unknown"
    with pytest.raises(ValueError, match="^crossed"):
        att.dos_decide(np.ones(3, bool))


def test_diagnose_persistence_arming_and_confirmation():
    t = np.arange(20.0)
    r = np.zeros((20, 4))
    r[3, 0] = 5.0  # a one-sample outlier: filtered by persistence
    r[10:, 3] = 5.0  # r4 from 10 s
    r[13:, 0] = 5.0  # r1 from 13 s: within the 5 s window
    d = att.diagnose(t, r, np.ones(4), persist=2, confirm_s=5.0)
    assert float(d.detect_time) == 11.0 and d.verdict == "gyro_x"
    assert d.flags.shape == (20, 4) and not d.flags[3, 0]
    d = att.diagnose(t, r, np.ones(4), persist=2, confirm_s=1.0)
    assert d.verdict == "gyro_skew"
    d = att.diagnose(t, r, np.ones(4), t_arm=float(t[-1]))  # armed at the last sample only
    assert d.detect_time == math.inf and d.verdict == "none"
    batch = att.diagnose(t, np.stack([r, 0 * r]), np.ones((2, 4)), persist=2)
    assert batch.verdict.tolist() == ["gyro_x", "none"]
    with pytest.raises(ValueError, match=r"^t must hold one time per sample of the residuals \(n = 5\)"):
        att.diagnose(t, r[:5], np.ones(4))
    with pytest.raises(ValueError, match=r"^residuals must have shape \(\.\.\., n, m\), got \("):
        att.diagnose(t, r[:, 0], np.ones(4))
    with pytest.raises(ValueError, match="^thresholds"):
        att.diagnose(t, r, np.ones(3))
    with pytest.raises(ValueError, match="^persist"):
        att.diagnose(t, r, np.ones(4), persist=0)


@pytest.mark.parametrize("t, thresholds, match", [
    ([0, 2, 1, 3, 4.0], np.ones(4) * 0.5, r"^t must be strictly increasing"),
    (np.zeros(5), np.ones(4) * 0.5, r"^t must be strictly increasing"),
    (np.arange(5.0), np.ones((1, 4)) * 0.5, r"^thresholds must have shape \(\.\.\., 4\)")])
def test_issue35_diagnose_refuses_unordered_times_and_extra_threshold_axes(t, thresholds, match):
    # Review 35f finding 36: accepted, and 2-D thresholds gave an array verdict, not a str.
    with pytest.raises(ValueError, match=match):
        att.diagnose(np.asarray(t), np.ones((5, 4)), thresholds)


@pytest.mark.parametrize(("t", "match"), [
    (-0.0, r"^t must be a 1-D array \(shape \(n,\)\), got shape \(\)"),
    ([], r"^t must hold at least one sample time, got an empty array"),
    ([1.0, True], r"^t must be an array of finite numbers"),
    ([1.0], r"^t must hold one time per sample of the residuals \(n = 5\), got 1$"),
])
def test_diagnose_names_t_before_the_residuals(t, match):
    """Issue 35: a 0-d t was refused under residuals' name (n = len(t) = 1)."""
    with pytest.raises(ValueError, match=match):
        att.diagnose(t, np.ones((5, 4)), np.ones(4))


def test_diagnose_review_35i_refusals():
    """Negative thresholds (every sample flagged) and a decide that is no function."""
    t = np.arange(10.0)
    r = np.zeros((10, 4))
    r[5:, [0, 3]] = 2.0
    with pytest.raises(ValueError, match=r"^thresholds must be >= 0"):
        att.diagnose(t, r, -np.ones(4), persist=2, confirm_s=1.0)
    with pytest.raises(ValueError, match=r"^decide must be"):
        att.diagnose(t, r, np.ones(4), decide="sos")


def test_an_arming_time_after_the_last_sample_is_refused():
    """Review 35k (5) 8: t_arm=1e300 (past the run) was accepted and the diagnosis read as a
    healthy run's (detect_time inf)."""
    t = np.arange(10.0)
    r = np.zeros((10, 4))
    with pytest.raises(ValueError, match=r"^t_arm must be a real number in \(-inf, 9\], got 1e\+300"):
        att.diagnose(t, r, np.ones(4), persist=2, confirm_s=1.0, t_arm=1e300)
    assert math.isinf(float(att.diagnose(t, r, np.ones(4), persist=1, t_arm=9.0).detect_time))


def test_simconfig_arms_its_detectors_at_a_sample():
    """Review 35k (5) 8: SimConfig's t_cal[1] is diagnose's t_arm: it must not pass the last sample."""
    with pytest.raises(ValueError, match=r"^t_cal must satisfy .* <= duration \(the last sample, 50 s\)"):
        att.SimConfig(duration=50.0, t_cal=(20.0, 50.5))


def test_masked_crossed_flags_are_refused():
    """Review 35m (5) 1: np.asarray dropped the mask and the masked flag was used."""
    crossed = np.ma.masked_array([True, False, False, True], mask=[False, False, False, True])
    for decide in (att.sos_decide, att.dos_decide):
        with pytest.raises(ValueError, match=r"^crossed has masked entries \(no flag to use"):
            decide(crossed)
    assert att.sos_decide(np.ma.masked_array([True, False, False, True])) == "gyro_x"
