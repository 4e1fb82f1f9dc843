"""T-S fuzzy fully decoupled parity equations and fault identification (xnavlab.plins.parity)."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.stats import chi2

from xnavlab import reproduce
from xnavlab.core.faults import Fault
from xnavlab.plins import ins
from xnavlab.plins import parity as P
from xnavlab.plins import pseudolites as pl

finite = dict(allow_nan=False, allow_infinity=False)
TRAJ = ins.paper_trajectory()
SITES = pl.sites_ecef()
MODELS = P.local_models(P.operating_points(TRAJ), TRAJ.lon[0], TRAJ.h[0], SITES, TRAJ.dt)


# ------------------------------------------------------------------ T-S fuzzy model
def test_premises_and_operating_points():
    rho = P.premises(TRAJ)
    assert rho.shape == (201, 3)
    pts = P.operating_points(TRAJ, 5)
    assert pts.shape == (5, 3)
    np.testing.assert_allclose(pts[:, 1], [100.0, 125.0, 150.0, 175.0, 200.0])
    np.testing.assert_allclose(pts[:, 2], 0.5)
    with pytest.raises(ValueError, match="n_points"):
        P.operating_points(TRAJ, 0)
    with pytest.raises(ValueError, match="traj"):
        P.premises([1, 2, 3])


def test_triangular():
    np.testing.assert_allclose(P.triangular([-1.0, 0.0, 3.0, 4.0], 0.0, 2.0, 4.0),
                               [0.0, 0.0, 0.5, 0.0])
    np.testing.assert_allclose(P.triangular([5.0, 1.0], 0.0, 1.0, 1.0), [1.0, 1.0])  # shoulder
    with pytest.raises(ValueError, match="center"):
        P.triangular(0.0, 1.0, 0.0, 2.0)
    with pytest.raises(ValueError, match="right"):
        P.triangular(0.0, 0.0, 1.0, 0.5)
    with pytest.raises(ValueError, match="x"):
        P.triangular(math.nan, 0.0, 1.0, 2.0)


@given(
    x=st.lists(st.floats(-10.0, 10.0, **finite), min_size=1, max_size=20),
    gaps=st.lists(st.floats(0.1, 3.0, **finite), min_size=0, max_size=5),
)
def test_partition_of_unity(x, gaps):
    centers = np.cumsum([-1.0, *gaps])
    mu = P.partition_memberships(x, centers)
    assert mu.shape == (len(x), len(centers))
    np.testing.assert_allclose(mu.sum(axis=1), 1.0)
    assert np.all((mu >= 0.0) & (mu <= 1.0))


def test_memberships():
    pts = P.operating_points(TRAJ)
    w = P.memberships(P.premises(TRAJ), pts)
    assert w.shape == (201, 3)
    np.testing.assert_allclose(w.sum(axis=1), 1.0)
    np.testing.assert_allclose(w[[0, 100, 200]], np.eye(3), atol=1e-12)
    assert np.all(w[1:100, 2] == 0.0) and np.all(w[101:, 0] == 0.0)
    with pytest.raises(ValueError, match="centers"):
        P.partition_memberships([0.0], [1.0, 0.0])
    with pytest.raises(ValueError, match="rho"):
        # a premise no rule covers: north acceleration 5 m/s^2 with sets at 0 and 1
        P.memberships([[39.0, 100.0, 5.0]], [[39.0, 100.0, 0.0], [39.2, 200.0, 1.0]])
    with pytest.raises(ValueError, match="points"):
        P.memberships([[39.0, 100.0, 0.5]], [39.0, 100.0, 0.5])


def test_local_models():
    assert len(MODELS) == 3
    lm = MODELS[0]
    np.testing.assert_allclose(lm.point, [39.0, 100.0, 0.5], atol=1e-9)
    F = ins.error_matrix(TRAJ.lat[0], TRAJ.h[0], TRAJ.v_enu[0], TRAJ.f_enu[0])
    A, Qd = ins.discretize(F, ins.noise_matrix(), ins.imu_noise_psd(), 1.0)
    np.testing.assert_allclose(lm.A, A, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(lm.B @ lm.B.T, Qd, rtol=1e-6, atol=1e-18)
    np.testing.assert_allclose(
        lm.C, pl.measurement_matrix(TRAJ.lat[0], TRAJ.lon[0], TRAJ.h[0], SITES))
    with pytest.raises(ValueError, match="points"):
        P.local_models([1.0, 2.0, 3.0], 0.0, 0.0, SITES, 1.0)


# ---------------------------------------------------------------------- parity space
small_systems = st.integers(0, 10_000).map(lambda seed: np.random.default_rng(seed))


@given(rng=small_systems, s=st.integers(1, 6))
def test_stacked_matrices_reproduce_a_simulation(rng, s):
    n, m, r = 3, 2, 2
    A = rng.normal(size=(n, n)) / 2
    C = rng.normal(size=(m, n))
    B = rng.normal(size=(n, r))
    x0 = rng.normal(size=n)
    w = rng.normal(size=(s + 1, r))
    x, ys = x0, []
    for k in range(s + 1):
        ys.append(C @ x)
        x = A @ x + B @ w[k]
    H0, Hw = P.stacked_matrices(A, C, s, B)
    np.testing.assert_allclose(H0 @ x0 + Hw @ w.ravel(), np.concatenate(ys), atol=1e-10)


@given(rng=small_systems, s=st.integers(4, 12))
def test_parity_vectors_are_orthogonal_to_the_state_observation_matrix(rng, s):
    n = 4
    A = np.eye(n) + rng.normal(size=(n, n)) / 5
    c = rng.normal(size=n)
    H0, _ = P.stacked_matrices(A, c, s)
    V = P.parity_basis(A, c, s)
    assert V.shape[1] == s + 1 - np.linalg.matrix_rank(H0)
    np.testing.assert_allclose(V.T @ V, np.eye(V.shape[1]), atol=1e-12)
    assert np.linalg.norm(V.T @ H0) <= 1e-9 * np.linalg.norm(H0)


@given(s=st.integers(5, 20), j=st.integers(0, 3))
def test_pl_ins_parity_space(s, j):
    lm = MODELS[1]
    H0, Hw = P.stacked_matrices(lm.A, lm.C[j], s, lm.B)
    # exact decoupling from the IMU noise leaves nothing for one pseudorange (constraint 1)
    assert P.parity_basis(lm.A, lm.C[j], s, B=lm.B).shape == (s + 1, 0)
    # the numerical left null space: state and noise leak less than tol metres
    V = P.parity_basis(lm.A, lm.C[j], s, B=lm.B, state_std=P.TYPICAL_STATE_STD, tol=0.6)
    assert V.shape[1] == s - 1  # constants and lines (clock, position, velocity) removed
    leak = np.linalg.svd(V.T @ np.hstack([H0 * P.TYPICAL_STATE_STD, Hw]), compute_uv=False)
    assert leak[0] <= 0.6


def test_parity_basis_bad_input():
    lm = MODELS[0]
    with pytest.raises(ValueError, match="s"):
        P.parity_basis(lm.A, lm.C[0], -1)
    with pytest.raises(ValueError, match="state_std"):
        P.parity_basis(lm.A, lm.C[0], 11, state_std=np.ones(3))
    with pytest.raises(ValueError, match="tol"):
        P.parity_basis(lm.A, lm.C[0], 11, tol=-1.0)
    with pytest.raises(ValueError, match="C"):
        P.stacked_matrices(lm.A, np.ones(3), 2)
    with pytest.raises(ValueError, match="A"):
        P.stacked_matrices(np.ones((2, 3)), np.ones(3), 2)
    with pytest.raises(ValueError, match="B"):
        P.stacked_matrices(lm.A, lm.C[0], 2, B=np.ones((3, 2)))


def test_align_bases():
    rng = np.random.default_rng(0)
    V, _ = np.linalg.qr(rng.normal(size=(6, 3)))
    R, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    a, b = P.align_bases([V @ R, V], ref=1)
    np.testing.assert_allclose(a, b, atol=1e-12)
    with pytest.raises(ValueError, match="bases"):
        P.align_bases([V, V[:, :2]])
    with pytest.raises(ValueError, match="bases"):
        P.align_bases([])
    with pytest.raises(ValueError, match="ref"):
        P.align_bases([V], ref=3)


@given(s=st.integers(5, 20))
def test_a_constant_fault_is_not_identifiable(s):
    """The paper's eq. 23 (same fault in the whole window) fails constraint 2: the clock."""
    lm = MODELS[2]
    V = P.parity_basis(lm.A, lm.C[0], s, B=lm.B, state_std=P.TYPICAL_STATE_STD, tol=0.6)
    tw = np.arange(s + 1.0)
    assert not P.check_identifiability(V, P.fault_signature(tw, "bias")).ok
    step = P.fault_signature(tw, "step", onset=tw[s // 2])
    assert P.check_identifiability(V, step).ok
    transit = np.stack([P.fault_signature(tw + k, "ramp", onset=s, time_origin="absolute")
                        for k in range(1, s + 1)])
    assert P.check_identifiability(V, transit).ok


def test_check_identifiability_edge_cases():
    rep = P.check_identifiability(np.zeros((4, 0)), np.ones((4, 1)))
    assert rep.null_dim == 0 and not rep.condition_1 and not rep.ok
    with pytest.raises(ValueError, match="M"):
        P.check_identifiability(np.eye(4)[:, :2], np.ones((3, 1)))
    with pytest.raises(ValueError, match="V"):
        P.check_identifiability(np.ones(4), np.ones((4, 1)))
    with pytest.raises(ValueError, match="rtol"):
        P.check_identifiability(np.eye(4)[:, :2], np.ones((4, 1)), rtol=0.0)


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
def _design(s=11, tol=0.6):
    V = [P.align_bases([P.parity_basis(m.A, m.C[j], s, B=m.B, state_std=P.TYPICAL_STATE_STD,
                                       tol=tol) for m in MODELS]) for j in range(4)]
    stacked = np.stack([np.stack([V[j][lm] for j in range(4)]) for lm in range(3)])
    return P.blended_bases(P.memberships(P.premises(TRAJ), P.operating_points(TRAJ)), stacked)


W_DESIGN = _design()


def test_blended_residuals_ignore_the_ins_errors():
    x = ins.simulate_errors(TRAJ, rng=4)
    d = pl.simulate_pseudoranges(TRAJ, x, sigma=0.0)
    r = P.parity_residuals(d.z, W_DESIGN)
    assert r.shape == (190, 4, 10)
    assert np.abs(d.z).max() > 50.0  # the INS errors are there ...
    # ... and decoupled: what is left (the line of sight turning inside the window, which
    # the time-invariant local models do not describe) stays below half the noise
    assert np.linalg.norm(r, axis=2).max() < 0.5 * pl.DEFAULT_SIGMA
    with pytest.raises(ValueError, match="W"):
        P.parity_residuals(d.z, W_DESIGN[:, :3])
    with pytest.raises(ValueError, match="window"):
        P.parity_residuals(d.z[:5], W_DESIGN[:5])
    with pytest.raises(ValueError, match="weights"):
        P.blended_bases(np.ones((3, 2)), np.ones((3, 1, 2, 2)))


def test_residual_threshold_and_first_alarm():
    assert P.residual_threshold(2.0, 10, 1e-6) == pytest.approx(2.0 * math.sqrt(chi2.isf(1e-6, 10)))
    for kw, name in (({"q": 0}, "q"), ({"p_fa": 0.7}, "p_fa"), ({"sigma": 0.0}, "sigma")):
        args = {"sigma": 1.0, "q": 3, "p_fa": 1e-3, **kw}
        with pytest.raises(ValueError, match=name):
            P.residual_threshold(**args)
    assert P.first_alarm([0.0, 1.0, 2.0], [5.0, 0.0, 5.0], 1.0, after=0.5) == 2.0
    with pytest.raises(ValueError, match="statistic"):
        P.first_alarm([0.0, 1.0], [1.0], 1.0)


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
    with pytest.raises(ValueError, match="shapes"):
        P.rw_update([0.0], [[1.0]], [1.0], [[1.0, 2.0]], [[1.0]])
    with pytest.raises(ValueError, match="R"):
        P.kf_identify(np.ones((5, 1)), np.ones((5, 1, 1)), -1.0, 0.0)
    with pytest.raises(ValueError, match="G"):
        P.kf_identify(np.ones((5, 1)), np.ones((4, 1, 1)), 1.0, 0.0)
    with pytest.raises(ValueError, match="P0"):
        P.FaultIdentifier([0.0], np.eye(2), [[0.0]])


# ------------------------------------------------------------------------ the flight
def test_chi2_monitor():
    A, Qd = ins.error_transitions(TRAJ)
    x = ins.simulate_errors(TRAJ, rng=0, transitions=(A, Qd))
    clean = pl.simulate_pseudoranges(TRAJ, x, rng=1)
    mon = P.chi2_monitor(clean, (A, Qd))
    assert mon.first_alarm() is None and mon.threshold == pytest.approx(chi2.isf(1e-6, 4))
    assert np.mean(mon.statistic[20:]) == pytest.approx(4.0, rel=0.25)  # chi^2_4 on average
    bad = pl.simulate_pseudoranges(
        TRAJ, x, rng=1, faults=[Fault(pl.SENSOR, "step", 100.0, 80.0, component=2)])
    assert P.chi2_monitor(bad, (A, Qd)).first_alarm() == 80.0
    with pytest.raises(ValueError, match="data"):
        P.chi2_monitor(x, (A, Qd))
    with pytest.raises(ValueError, match="transitions"):
        P.chi2_monitor(clean, (A[:5], Qd[:5]))


def test_diagnose_flight_fault_free_and_faulty():
    d = P.diagnose_flight(seed=3)
    assert d.detection == [None] * 4 and d.identification == {}
    assert d.null_dim == 10 and d.s == 11 and d.statistic.shape == (190, 4)
    faults = [Fault(pl.SENSOR, "step", -80.0, 120.0, component=3)]
    d = P.diagnose_flight(faults, seed=3, with_chi2=True, s=8, threshold=20.0)
    assert d.detection == [None, None, None, 120.0] and d.threshold == 20.0
    # a shorter window identifies a step less well: about 3 m (1 sigma) for s = 8
    assert d.identification[3].final[0] == pytest.approx(-80.0, abs=10.0)
    assert d.chi2.first_alarm() == 120.0


def test_diagnose_flight_bad_input():
    for kw, name in (({"s": 1}, "s"), ({"sigma": 0.0}, "sigma"), ({"model": "bias"}, "model"),
                     ({"leak_tol": 0.0}, "leak_tol"), ({"threshold": -1.0}, "threshold"),
                     ({"duration": 5.0}, "duration"), ({"time_origin": "t"}, "time_origin")):
        with pytest.raises(ValueError, match=name):
            P.diagnose_flight(**kw)
    with pytest.raises(ValueError, match="faults"):
        P.diagnose_flight(["pseudorange:step:100@50+inf"])


def test_compare_detectors_and_plot():
    rows = P.compare_detectors("ramp", [1.0], n_runs=1)
    assert rows[0]["parity_rate"] == 0.0 and rows[0]["parity_delay"] is None
    assert rows[0]["chi2_rate"] == 1.0  # the filter's memory catches the slow drift
    with pytest.raises(ValueError, match="kind"):
        P.compare_detectors("spike", [1.0])
    with pytest.raises(ValueError, match="n_runs"):
        P.compare_detectors("step", [1.0], n_runs=0)
    with pytest.raises(ValueError, match="sensor"):
        P.compare_detectors("step", [100.0], n_runs=1, sensor=9)
    fig = P.plot_diagnosis(P.diagnose_flight([Fault(pl.SENSOR, "step", 50.0, 50.0, component=0)]))
    assert len(fig.axes) == 2
    with pytest.raises(ValueError, match="diag"):
        P.plot_diagnosis(None)


# ------------------------------------------------------------------- reproductions
@pytest.mark.parametrize("rid", ["plins-step", "plins-ramp"])
def test_reproductions_pass(rid):
    assert rid in reproduce.ids()
    result = reproduce.run(rid)
    result.assert_passed()
    assert result.note and reproduce.get(rid).chapter == "12_fuzzy_parity"


def test_reproduction_figures(tmp_path):
    res = reproduce.run("plins-step", out=tmp_path, n_runs=2)
    res2 = reproduce.run("plins-ramp", out=tmp_path, n_runs=2)
    names = sorted(p.name for p in tmp_path.glob("*.png"))
    assert names == ["plins-fig2.png", "plins-fig3.png", "plins-fig4.png"]
    assert len(res.figures) == 2 and len(res2.figures) == 1
