"""Fault identification (xnavlab.plins.parity.identification): fault signatures, the onset
estimate, and the random-walk Kalman filter of the fault's parameters."""


import numpy as np
import pytest

from xnavlab.core.faults import Fault
from xnavlab.plins import ins
from xnavlab.plins import parity as P
from xnavlab.plins import pseudolites as pl

from ._paper_design import TRAJ, W_DESIGN


def test_fault_signature():
    t = np.array([28.0, 29.0, 30.0, 31.0])
    np.testing.assert_allclose(P.fault_signature(t, "bias"), np.ones((4, 1)))
    np.testing.assert_allclose(P.fault_signature(t, "step", 30.0)[:, 0], [0, 0, 1, 1])
    ramp = P.fault_signature(t, "ramp", 30.0) @ [10.0, -300.0]  # the paper's ramp, absolute t
    np.testing.assert_allclose(ramp, [0.0, 0.0, 0.0, 10.0])
    ramp = P.fault_signature(t, "ramp", 30.0, "onset") @ [10.0, -300.0]
    np.testing.assert_allclose(ramp, [0.0, 0.0, -300.0, -290.0])
    with pytest.raises(ValueError, match="model"):
        P.fault_signature(t, "drift")
    with pytest.raises(ValueError, match="time_origin"):
        P.fault_signature(t, "ramp", 30.0, "relative")
    with pytest.raises(ValueError, match="t_window"):
        P.fault_signature(np.ones((2, 2)), "step")


# ------------------------------------------------------------------------- residuals
def test_estimate_onset_and_identification_without_noise():
    t = TRAJ.t
    x = ins.simulate_errors(TRAJ, rng=7)
    ramp = Fault(pl.SENSOR, "ramp", 10.0, 30.0, component=0)
    step = Fault(pl.SENSOR, "step", -120.0, 70.0, component=1)
    d = pl.simulate_pseudoranges(TRAJ, x, sigma=0.0, faults=[ramp, step])
    assert P.estimate_onset(t, d.z[:, 1], W_DESIGN[:, 1], 70, "step") == 70.0
    idn = P.identify_fault(t, d.z[:, 1], W_DESIGN[:, 1], 70.0, "step", sigma=0.1, sensor=1)
    assert idn.final[0] == pytest.approx(-120.0, abs=0.5)
    assert idn.names == ("f",) and idn.t[0] == 70.0 and idn.std[0] > 0
    idn = P.identify_fault(t, d.z[:, 0], W_DESIGN[:, 0], 30.0, "ramp", sigma=0.1)
    np.testing.assert_allclose(idn.final, [10.0, -300.0], rtol=0.01)
    with pytest.raises(ValueError, match="onset"):
        P.identify_fault(t, d.z[:, 0], W_DESIGN[:, 0], 500.0, "step")
    with pytest.raises(ValueError, match="k_alarm"):
        P.estimate_onset(t, d.z[:, 0], W_DESIGN[:, 0], 3, "step")
    with pytest.raises(ValueError, match="model"):
        P.estimate_onset(t, d.z[:, 0], W_DESIGN[:, 0], 40, "bias")


# ------------------------------------------------------------------ identification KF
def test_random_walk_kalman_filter():
    th, Pm = P.rw_predict([1.0, 2.0], np.eye(2), 0.5 * np.eye(2))
    np.testing.assert_allclose(Pm, 1.5 * np.eye(2))
    th, Pm = P.rw_update([0.0], [[1.0]], [4.0, 4.0], [[1.0], [1.0]], np.eye(2))
    assert th[0] == pytest.approx(8.0 / 3.0) and Pm[0, 0] == pytest.approx(1.0 / 3.0)
    kf = P.FaultIdentifier([0.0, 0.0], 1e6 * np.eye(2), np.zeros((2, 2)))
    rng = np.random.default_rng(1)
    for k in range(200):
        G = np.array([[1.0, float(k)]])
        kf.step(G @ [3.0, 0.5] + 0.01 * rng.normal(size=1), G, [[1e-4]])
    np.testing.assert_allclose(kf.theta, [3.0, 0.5], atol=1e-2)
    ths, Ps = P.kf_identify(np.ones((5, 2)), np.ones((5, 2, 1)), np.eye(2), [[0.0]])
    assert ths.shape == (5, 1) and Ps.shape == (5, 1, 1)
    with pytest.raises(ValueError, match="P"):
        P.rw_predict([0.0], np.eye(2), np.eye(2))
    with pytest.raises(ValueError, match=r"^G must have shape \(1, 1\) \(q = len\(r\), p = len\(theta\)\)"):
        P.rw_update([0.0], [[1.0]], [1.0], [[1.0, 2.0]], [[1.0]])
    with pytest.raises(ValueError, match="R"):
        P.kf_identify(np.ones((5, 1)), np.ones((5, 1, 1)), -1.0, 0.0)
    with pytest.raises(ValueError, match="G"):
        P.kf_identify(np.ones((5, 1)), np.ones((4, 1, 1)), 1.0, 0.0)
    with pytest.raises(ValueError, match="P0"):
        P.FaultIdentifier([0.0], np.eye(2), [[0.0]])


def test_the_random_walk_filter_refuses_an_indefinite_R_or_Q():
    """rw_update with R = -1 returned an indefinite P; rw_predict with Q = -I returned P = 0."""
    with pytest.raises(ValueError, match="R must be positive semi-definite, got smallest eigenvalue -1"):
        P.rw_update(np.zeros(2), np.eye(2), np.zeros(1), np.ones((1, 2)), -np.eye(1))
    with pytest.raises(ValueError, match="Q must be positive semi-definite, got smallest eigenvalue -1"):
        P.rw_predict(np.zeros(2), np.eye(2), -np.eye(2))
    with pytest.raises(ValueError, match="Q must be positive semi-definite"):
        P.kf_identify(np.ones((3, 1)), np.ones((3, 1, 1)), 1.0, -np.eye(1))
    assert P.rw_predict(np.zeros(2), np.eye(2), np.zeros((2, 2)))[1].tolist() == np.eye(2).tolist()


def test_identify_fault_refuses_a_noise_beyond_its_range():
    """Review 35e: sigma=1e308 was 'OverflowError: (34, 'Numerical result out of range')'."""
    V = P.parity_basis([[1.0, 1.0], [0.0, 1.0]], [1.0, 0.0], 3)
    t = np.arange(30.0)
    z = np.where(t >= 10.0, 50.0, 0.0)
    W = np.broadcast_to(V, (30, 4, 2))
    with pytest.raises(ValueError, match=r"^sigma must be a real number in \[1e-06, 1e\+06\], got 1e\+308$"):
        P.identify_fault(t, z, W, 10.0, sigma=1e308)
    with pytest.raises(ValueError, match=r"^q_rw must be a real number in \[0, 1e\+06\]"):
        P.identify_fault(t, z, W, 10.0, q_rw=1e308)


def test_the_kalman_filter_names_the_argument_whose_shape_disagrees():
    """Issue 35 (review 35h): theta=-0.0 was 'len() of unsized object', and a bad P, Q, r, G or R
    was refused as 'shapes must be theta (p,), P (p, p), ...' or under P's name."""
    cases = [
        (lambda: P.rw_predict(-0.0, [[2.0]], [[0.5]]), r"^theta must be a 1-D array"),
        (lambda: P.rw_predict([], [[2.0]], [[0.5]]), r"^theta must hold at least one parameter"),
        (lambda: P.rw_predict([1.0], [[2.0]], -0.0), r"^Q must have shape \(1, 1\) \(p = len\(theta\)\)"),
        (lambda: P.rw_update(-0.0, [[1.0]], [2.0], [[1.0]], [[1.0]]), r"^theta must be a 1-D array"),
        (lambda: P.rw_update([0.0], -0.0, [2.0], [[1.0]], [[1.0]]), r"^P must have shape \(1, 1\)"),
        (lambda: P.rw_update([0.0], [[1.0]], [], [[1.0]], [[1.0]]), r"^r must hold at least one residual"),
        (lambda: P.rw_update([0.0], [[1.0]], [2.0], -0.0, [[1.0]]), r"^G must have shape \(1, 1\)"),
        (lambda: P.rw_update([0.0], [[1.0]], [2.0], [[1.0]], -0.0), r"^R must have shape \(1, 1\) \(q = len"),
        (lambda: P.FaultIdentifier(-0.0, [[100.0]], [[0.0]]), r"^theta0 must be a 1-D array"),
        (lambda: P.FaultIdentifier([0.0], [[100.0]], -0.0), r"^Q must have shape \(1, 1\) \(p = len\(theta0"),
        (lambda: P.kf_identify(np.ones((20, 1)), -0.0, 1.0, 0.0), r"^G must have shape \(20, 1, n\)"),
    ]
    for call, words in cases:
        with pytest.raises(ValueError, match=words):
            call()


def test_the_onset_search_and_identification_name_the_series_at_fault():
    """Issue 35 (review 35h): a 0-d z_j or W_j was refused as 't and z_j must have shape (n,)
    ...', and sigma=5e-324 squared to a residual variance of 0, refused under the name R."""
    V = P.parity_basis([[1.0, 1.0], [0.0, 1.0]], [1.0, 0.0], 3)
    t = np.arange(12.0)
    z = np.where(t >= 6.0, 50.0, 0.0)
    W = np.broadcast_to(V, (12, 4, 2))
    for call in (P.estimate_onset, lambda *a: P.identify_fault(*a[:3], 6.0)):
        with pytest.raises(ValueError, match=r"^z_j must be a 1-D array"):
            call(t, -0.0, W, 6)
        with pytest.raises(ValueError, match=r"^W_j must have shape \(12, n, n\)"):
            call(t, z, -0.0, 6)
        with pytest.raises(ValueError, match=r"^t must hold one time per sample of z_j \(n = 12\), got 1$"):
            call([1.0], z, W, 6)
        with pytest.raises(ValueError, match=r"^z_j must have shape \(12,\) \(n = len\(t\)\), got shape"):
            call(t, [1.0], W, 6)
    with pytest.raises(ValueError, match=r"^sigma must be a real number in \[1e-06, 1e\+06\], got 5e-324$"):
        P.identify_fault(t, z, W, 6.0, sigma=5e-324)


def test_the_random_walk_filter_checks_its_covariances():
    """Issue 35 (review 35i): rw_predict returned an indefinite or non-symmetric P as given,
    rw_update updated an indefinite P, FaultIdentifier took P0 = -100, and kf_identify with
    P0 = -1 raised numpy's 'Singular matrix'."""
    cases = [
        (lambda: P.rw_predict([1.0, 0.0], [[2.0, 0.0], [0.0, -1.0]], np.zeros((2, 2))),
         r"^P must be positive semi-definite, got smallest eigenvalue -1$"),
        (lambda: P.rw_predict([1.0, 0.0], [[2.0, 0.5], [0.0, 1.0]], np.zeros((2, 2))),
         r"^P must be symmetric"),
        (lambda: P.rw_update([0.0, 0.0], [[1.0, 0.0], [0.0, -1.0]], [2.0], [[1.0, 1.0]], [[1.0]]),
         r"^P must be positive semi-definite"),
        (lambda: P.FaultIdentifier([0.0], [[-100.0]], [[0.0]]), r"^P0 must be positive semi-definite"),
        (lambda: P.FaultIdentifier([0.0], [[100.0]], [[-1.0]]), r"^Q must be positive semi-definite"),
        (lambda: P.kf_identify(np.full((20, 1), 4.0), np.ones((20, 1, 1)), 1.0, 0.0, P0=[[-1.0]]),
         r"^P0 must be positive semi-definite, got smallest eigenvalue -1$"),
        (lambda: P.kf_identify(np.full((20, 1), 4.0), np.ones((20, 1, 1)), 1.0, 0.0, P0=[1.0]),
         r"^P0 must have shape \(1, 1\) \(p = columns of G\)"),
        (lambda: P.kf_identify(np.full((3, 1), 4.0), np.ones((3, 1, 1)), [[0.0]], 0.0, P0=[[0.0]]),
         r"^R must be positive definite along the residual directions"),
    ]
    for call, words in cases:
        with pytest.raises(ValueError, match=words):
            call()
    th, Pk = P.kf_identify(np.full((20, 1), 4.0), np.ones((20, 1, 1)), 1.0, 0.0, P0=[[1e8]])
    assert round(float(th[-1, 0]), 3) == 4.0


def test_onset_search_identification_and_first_alarm_need_increasing_times():
    """Issue 35 (review 35i): times reversed or repeated were read as given (an onset of 6 s
    from reversed times, 0 s from repeated ones); sensor=-1, 7.0 were stored as given."""
    V = P.parity_basis([[1.0, 1.0], [0.0, 1.0]], [1.0, 0.0], 3)
    t = np.arange(30.0)
    z = np.where(t >= 10.0, 50.0, 0.0)
    W = np.broadcast_to(V, (30, 4, 2))
    for times, words in ((t[::-1].copy(), r"t\[1\] = 28 after t\[0\] = 29"),
                         (np.zeros(30), r"t\[1\] = 0 after t\[0\] = 0")):
        with pytest.raises(ValueError, match=r"^t must be strictly increasing \(sample times, s\), "
                                             r"got " + words):
            P.estimate_onset(times, z, W, 10)
        with pytest.raises(ValueError, match=r"^t must be strictly increasing"):
            P.identify_fault(times, z, W, 10.0, sigma=1.0)
    for sensor in (-1, 1000, 1.0, True):
        with pytest.raises(ValueError, match=r"^sensor must be an integer in \[0, 999\]"):
            P.identify_fault(t, z, W, 10.0, sigma=1.0, sensor=sensor)
    assert P.identify_fault(t, z, W, 10.0, sigma=1.0, sensor=np.int64(3)).sensor == 3


def test_fault_signature_refuses_times_out_of_order():
    """Review 35i: a window's times decreasing were accepted (a window is samples in order)."""
    with pytest.raises(ValueError, match=r"^t_window must be strictly increasing"):
        P.fault_signature([3.0, 2.0, 1.0], "step", onset=2.0)
