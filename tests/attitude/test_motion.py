"""The true attitude motion (xnavlab.attitude.motion): the body rate and its exact quaternion kinematics."""


import numpy as np
import pytest

from xnavlab import attitude as att
from xnavlab.core import quaternions as qt


def test_truth_rate():
    t = np.linspace(0.0, 300.0, 3001)
    w = att.truth_rate(t)
    assert w.shape == (3001, 3)
    assert np.degrees(w[:, 1].mean()) == pytest.approx(-0.06, abs=1e-3)
    assert np.degrees(np.abs(w[:, 0]).max()) == pytest.approx(0.01, rel=1e-3)
    with pytest.raises(ValueError, match="^wobble_period"):
        att.truth_rate(t, wobble_period=0.0)
    with pytest.raises(ValueError, match="^omega_orbit_deg_s"):
        att.truth_rate(t, omega_orbit_deg_s=-1.0)


def test_truth_motion_uses_exact_kinematics():
    t, w, q = att.truth_motion(50, 0.1)
    assert t.shape == (50,) and w.shape == (50, 3) and q.shape == (50, 4)
    np.testing.assert_allclose(q[1], qt.quat_propagate(q[0], w[0], 0.1))
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(w[3], att.truth_rate([0.35])[0])
    with pytest.raises(ValueError, match="^n "):
        att.truth_motion(1, 0.1)
    with pytest.raises(ValueError, match="^dt "):
        att.truth_motion(10, 0.0)


def test_truth_motion_refuses_more_samples_than_a_run_takes():
    with pytest.raises(ValueError, match=r"n must be an integer in \[2, 1600000\]"):
        att.truth_motion(10**30, 0.1)


def test_truth_motion_review_35i_refusals():
    """A zero q0 named q0; a misspelt or repeated keyword named with the valid ones."""
    with pytest.raises(ValueError, match=r"^q0 must have a non-zero norm"):
        att.truth_motion(11, 0.1, q0=np.zeros(4))
    with pytest.raises(ValueError, match=r"^wobble_deg_=0.0 is not a setting of truth_rate \(they are"):
        att.truth_motion(11, 0.1, wobble_deg_=0.0)
    with pytest.raises(ValueError, match=r"^t=5.0 is not a setting of truth_rate"):
        att.truth_motion(11, 0.1, t=5.0)


def test_truth_motion_takes_one_initial_quaternion_and_a_real_period():
    """Review 35k (patterns D, E): q0 of shape (2, 4) was numpy's broadcast error; a subnormal
    wobble_period overflowed t / P (RuntimeWarning)."""
    with pytest.raises(ValueError, match=r"^q0 must have shape \(4,\) \(one quaternion\)"):
        att.truth_motion(3, 0.1, q0=np.tile(att.DEFAULT_Q0, (2, 1)))
    with pytest.raises(ValueError, match=r"^wobble_period must be a real number in \[0.001, inf\)"):
        att.truth_rate([0.0, 1.0], wobble_period=5e-324)
