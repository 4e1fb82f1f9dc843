"""Attitude-sensor fault diagnosis (chapter 11): models, EKF, SOS, DOS, ref. [22], reproductions."""

import math

import matplotlib.pyplot as plt
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from xnavlab import attitude as att
from xnavlab import reproduce
from xnavlab.core import quaternions as qt
from xnavlab.core.faults import Fault

DPH = att.DEG_PER_H


@pytest.fixture(scope="module")
def nominal():
    return att.simulate()


@st.composite
def unit_quat(draw):
    v = np.array(draw(st.lists(st.floats(-1, 1), min_size=4, max_size=4)))
    if np.linalg.norm(v) < 1e-3:
        v = qt.IDENTITY.copy()
    return v / np.linalg.norm(v)


small_rate = st.lists(st.floats(-0.05, 0.05), min_size=3, max_size=3).map(np.array)


# ----------------------------------------------------------------------------- models


def test_gyro_matrix():
    H = att.gyro_matrix()
    assert H.shape == (4, 3)
    np.testing.assert_allclose(H[:3], np.eye(3))
    np.testing.assert_allclose(H[3], np.ones(3) / math.sqrt(3))
    np.testing.assert_allclose(att.gyro_matrix([2.0, 2.0, 2.0]), H)


@pytest.mark.parametrize("axis", [[1.0, 0.0, 1.0], [0.0, 0.0, 0.0], [1.0, 1.0], [np.nan, 1, 1]])
def test_gyro_matrix_rejects_bad_axes(axis):
    with pytest.raises(ValueError, match="^skew_axis"):
        att.gyro_matrix(axis)


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


def test_gyro_measurements_model_and_faults():
    t, w, _ = att.truth_motion(100, 0.1)
    clean = att.gyro_measurements(t, w, noise_deg_per_h=0.0)
    b = np.array(att.PAPER_DRIFTS_DEG_PER_H) * DPH
    np.testing.assert_allclose(clean, w @ att.gyro_matrix().T + b)
    f = att.make_fault("gyro_y", "step", 1e-3, onset=5.0)
    faulty = att.gyro_measurements(t, w, noise_deg_per_h=0.0, faults=[f])
    diff = faulty - clean
    np.testing.assert_allclose(diff[t >= 5.0, 1], 1e-3)
    assert np.all(diff[t < 5.0] == 0) and np.all(diff[:, [0, 2, 3]] == 0)
    noisy = att.gyro_measurements(t, w, rng=3)
    assert np.std(noisy - clean) / DPH == pytest.approx(0.05, rel=0.15)
    with pytest.raises(ValueError, match="^w must"):
        att.gyro_measurements(t, w[:, :2])
    with pytest.raises(ValueError, match="^noise_deg_per_h"):
        att.gyro_measurements(t, w, noise_deg_per_h=-1.0)


def test_star_tracker_measurements():
    t, _, q = att.truth_motion(2000, 0.1)
    qs = att.star_tracker_measurements(t, q, rng=1)
    np.testing.assert_allclose(np.linalg.norm(qs, axis=1), 1.0, atol=1e-12)
    err = qt.attitude_error(qs, q)
    # q_s = q (x) q_v: the error is the body-frame noise rotated by A(q); per axis sigma
    sigma = np.degrees(np.sqrt(np.mean(np.sum(err**2, axis=1)) / 3))
    assert sigma == pytest.approx(att.PAPER_STAR_NOISE_DEG, rel=0.05)
    f = att.make_fault("star_tracker", "step", 1e-3, onset=100.0)
    qf = att.star_tracker_measurements(t, q, noise_deg=1e-9, faults=[f])
    assert np.abs(qf[t < 100] - q[t < 100]).max() < 1e-9
    assert np.abs(qf[t >= 100] - q[t >= 100]).max() > 5e-4
    with pytest.raises(ValueError, match="^q must"):
        att.star_tracker_measurements(t, q[:, :3])
    with pytest.raises(ValueError, match="^noise_deg"):
        att.star_tracker_measurements(t, q, noise_deg=np.inf)


def test_make_fault():
    for i, loc in enumerate(att.LOCATIONS[:4]):
        f = att.make_fault(loc, "step", 1.0)
        assert (f.sensor, f.component, f.onset) == ("gyro", i, 50.0)
    f = att.make_fault("star_tracker", "ramp", 1e-5, onset=3.0, duration=4.0)
    assert (f.sensor, f.component, f.end) == ("star_tracker", 0, 7.0)
    with pytest.raises(ValueError, match="^location"):
        att.make_fault("gyro_w", "step", 1.0)
    with pytest.raises(ValueError, match="^kind"):
        att.make_fault("gyro_x", "jump", 1.0)


# ----------------------------------------------------------------------------- the EKF


def _random_state(q, b, scale):
    x = np.concatenate([q, b])
    rng = np.random.default_rng(int(1e6 * abs(scale)) % 1000)
    L = rng.normal(size=(7, 7)) * scale
    return x, L @ L.T + 1e-12 * np.eye(7)


@given(unit_quat(), small_rate, small_rate, unit_quat(), st.floats(1e-5, 1e-2))
def test_ekf_keeps_P_symmetric_positive_definite(q, b, w, qm, scale):
    x, P = _random_state(q, b * 1e-2, scale)
    x1, P1 = att.ekf_predict(x, P, w, 0.1, 1e-12, 1e-14)
    x2, P2, nu = att.ekf_update(x1, P1, qm, 1e-10)
    for M in (P1, P2):
        np.testing.assert_allclose(M, M.T, atol=1e-15)
        assert np.linalg.eigvalsh(M).min() > -1e-12 * np.abs(M).max()
    assert np.trace(P2) <= np.trace(P1) + 1e-18
    assert np.linalg.norm(x2[:4]) == pytest.approx(1.0, abs=1e-12)
    assert nu.shape == (4,)


@given(unit_quat(), small_rate, small_rate)
def test_ekf_jacobian_matches_finite_differences(q, b, w):
    """With P = I and no noise, P(k+1|k) = F F^T; compare with a central-difference F."""
    dt = 0.1
    x = np.concatenate([q, b])

    def f(xx):
        return np.concatenate([qt.quat_propagate(xx[:4], w - xx[4:], dt), xx[4:]])

    J = np.empty((7, 7))
    for i in range(7):
        e = np.zeros(7)
        e[i] = 1e-6
        J[:, i] = (f(x + e) - f(x - e)) / 2e-6
    _, P1 = att.ekf_predict(x, np.eye(7), w, dt, 0.0, 0.0)
    # F uses the first-order -dt/2 Xi(q) (paper eqs. (22)-(23)): error O(dt^2 |w - b|)
    np.testing.assert_allclose(P1, J @ J.T, atol=0.5 * dt**2 * np.linalg.norm(w - b) + 1e-8)


def test_ekf_update_is_sign_invariant():
    x, P = att.ekf_init(att.DEFAULT_Q0, attitude_sigma=1e-4, drift_sigma=1e-4)
    qm = qt.quat_product(qt.quat_from_rotvec([1e-4, 0, 0]), att.DEFAULT_Q0)
    a = att.ekf_update(x, P, qm, 1e-10)
    b = att.ekf_update(x, P, -qm, 1e-10)
    np.testing.assert_allclose(a[0], b[0])
    np.testing.assert_allclose(a[1], b[1])


def test_ekf_bad_inputs():
    x, P = att.ekf_init(att.DEFAULT_Q0, attitude_sigma=1e-4, drift_sigma=1e-4)
    with pytest.raises(ValueError, match="^dt "):
        att.ekf_predict(x, P, np.zeros(3), 0.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="^omega_g"):
        att.ekf_predict(x, P, np.zeros(4), 0.1, 0.0, 0.0)
    with pytest.raises(ValueError, match="^gyro_cov"):
        att.ekf_predict(x, P, np.zeros(3), 0.1, -1.0, 0.0)
    with pytest.raises(ValueError, match="^R "):
        att.ekf_update(x, P, att.DEFAULT_Q0, -np.eye(4))
    with pytest.raises(ValueError, match="^x "):
        att.ekf_update(np.zeros(7), P, att.DEFAULT_Q0, 1e-10)
    with pytest.raises(ValueError, match="^P "):
        att.ekf_update(x, P[:6, :6], att.DEFAULT_Q0, 1e-10)
    with pytest.raises(ValueError, match="^attitude_sigma"):
        att.ekf_init(att.DEFAULT_Q0, attitude_sigma=0.0, drift_sigma=1.0)
    with pytest.raises(ValueError, match="^drift_sigma"):
        att.ekf_init(att.DEFAULT_Q0, attitude_sigma=1.0, drift_sigma=-1.0)


def test_attitude_ekf_converges_to_the_drifts():
    t, w, q = att.truth_motion(301, 0.1)
    wg = att.gyro_measurements(t, w, rng=2)
    qs = att.star_tracker_measurements(t, q, rng=3)
    f = att.AttitudeEKF(qs[0], 0.1, 0.05 * DPH, math.radians(att.PAPER_STAR_NOISE_DEG),
                        DPH, 100 * DPH)
    f.update(qs[0])
    for k in range(1, len(t)):
        f.predict(wg[k - 1, :3])
        f.update(qs[k])
    np.testing.assert_allclose(f.drift / DPH, att.PAPER_DRIFTS_DEG_PER_H[:3], atol=4.0)
    assert np.degrees(np.linalg.norm(qt.attitude_error(f.q, q[-1]))) < 0.005
    with pytest.raises(ValueError, match="^omega_g"):
        f.predict([0.0, np.nan, 0.0])
    with pytest.raises(ValueError, match="^q_meas"):
        f.update([0.0, 0.0, 1.0])
    with pytest.raises(ValueError, match="^dt "):
        att.AttitudeEKF(qs[0], -0.1, 0.0, 1e-4, 0.0, 1e-4)


# ----------------------------------------------------------------------------- SOS, DOS


@given(small_rate)
def test_gyro_parity_is_blind_to_the_rate(w):
    assert abs(float(att.gyro_parity(att.gyro_matrix() @ w))) < 1e-15
    b = np.array(att.PAPER_DRIFTS_DEG_PER_H) * DPH
    p = att.gyro_parity(att.gyro_matrix() @ w + b)
    assert float(p) == pytest.approx(b[3] - att.SKEW_AXIS @ b[:3], abs=1e-15)


def test_sos_residuals():
    r = att.sos_residuals(np.ones((5, 3)), np.zeros((5, 4)), np.zeros((5, 3)), np.ones(5))
    np.testing.assert_allclose(r, np.ones((5, 4)))
    with pytest.raises(ValueError, match="^drift_hat"):
        att.sos_residuals(np.ones(4), np.zeros(4), np.zeros(3), 0.0)
    with pytest.raises(ValueError, match="^omega_g"):
        att.sos_residuals(np.ones(3), np.zeros(3), np.zeros(3), 0.0)


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


def test_dos_rate_matrices_invert_each_group():
    H = att.gyro_matrix()
    T = att.dos_rate_matrices()
    for j, g in enumerate(att.DOS_GROUPS):
        assert j not in g
        np.testing.assert_allclose(T[j] @ H[list(g)], np.eye(3), atol=1e-12)


def test_dos_residuals():
    d = np.zeros((4, 3))
    d[2] = [3.0, 4.0, 0.0]
    np.testing.assert_allclose(att.dos_residuals(d, np.zeros((4, 3))), [0, 0, 5.0, 0])
    with pytest.raises(ValueError, match="^drift_ref"):
        att.dos_residuals(d, np.zeros((3, 3)))


# ----------------------------------------------------------------------------- ref. [22]


def test_quaternion_rate_noise_matches_prediction():
    t, w, q = att.truth_motion(1001, 0.1, wobble_deg_s=0.0)
    qs = att.star_tracker_measurements(t, q, rng=5)
    wq = att.quaternion_rate(qs, 0.1, 10.0)
    assert wq.shape == (901, 3)
    M = 100
    sigma = math.radians(att.PAPER_STAR_NOISE_DEG) * math.sqrt(12 / (M * (M + 1) * (M + 2))) / 0.1
    assert np.std(wq - w[0]) == pytest.approx(sigma, rel=0.35)
    # sign flips of the measured quaternion do not matter
    flipped = qs.copy()
    flipped[::7] *= -1
    np.testing.assert_allclose(att.quaternion_rate(flipped, 0.1, 10.0), wq, atol=1e-15)
    with pytest.raises(ValueError, match="^window_s"):
        att.quaternion_rate(qs, 0.1, 0.1)
    with pytest.raises(ValueError, match="^q_meas"):
        att.quaternion_rate(qs[:50], 0.1, 10.0)


def test_qdiff_fault_estimates_and_decision():
    t, w, q = att.truth_motion(301, 0.1)
    f = att.qdiff_fault_estimates(w + [1e-4, 0, 0], q, 0.1, 5.0)
    assert f.shape == (251, 3)
    # the wobble's curvature over the 5 s window: ~3e-8 rad/s (0.006 deg/h)
    np.testing.assert_allclose(f, np.tile([1e-4, 0, 0], (251, 1)), atol=1e-7)
    assert att.qdiff_decide(np.array([False, False, False])) == "none"
    assert att.qdiff_decide(np.array([[False, True, False]])).tolist() == ["gyro_y"]
    with pytest.raises(ValueError, match="^omega_g"):
        att.qdiff_fault_estimates(w[:, :2], q, 0.1, 5.0)
    with pytest.raises(ValueError, match="same number of samples"):
        att.qdiff_fault_estimates(w[:-1], q, 0.1, 5.0)


# ----------------------------------------------------------------------------- detection


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
    d = att.diagnose(t, r, np.ones(4), t_arm=100.0)
    assert d.detect_time == math.inf and d.verdict == "none"
    batch = att.diagnose(t, np.stack([r, 0 * r]), np.ones((2, 4)), persist=2)
    assert batch.verdict.tolist() == ["gyro_x", "none"]
    with pytest.raises(ValueError, match="^residuals"):
        att.diagnose(t, r[:5], np.ones(4))
    with pytest.raises(ValueError, match="^thresholds"):
        att.diagnose(t, r, np.ones(3))
    with pytest.raises(ValueError, match="^persist"):
        att.diagnose(t, r, np.ones(4), persist=0)


# ----------------------------------------------------------------------------- simulation


@pytest.mark.parametrize(
    ("changes", "name"),
    [
        ({"n_sigma": 0.0}, "n_sigma"),
        ({"dt": -0.1}, "dt"),
        ({"t_cal": (40.0, 20.0)}, "t_cal"),
        ({"t_cal": (20.0, 200.0)}, "t_cal"),
        ({"qdiff_window_s": 45.0}, "qdiff_window_s"),
        ({"persist": 0}, "persist"),
        ({"dos": 1}, "dos"),
        ({"drifts_deg_per_h": (1.0, 2.0)}, "drifts_deg_per_h"),
        ({"skew_axis": (1.0, 0.0, 0.0)}, "skew_axis"),
        ({"star_noise_deg": 0.0}, "star_noise_deg"),
        ({"duration": 0.1}, "duration"),
    ],
)
def test_config_validation(changes, name):
    with pytest.raises(ValueError, match=f"^{name}"):
        att.SimConfig(**changes)


def test_simulate_fault_free(nominal):
    run = nominal
    assert run.truth == "none" and run.onset == math.inf
    assert (run.sos.verdict, run.dos.verdict, run.qd.verdict) == ("none", "none", "none")
    assert run.t.shape == (1001,) and run.sos_r.shape == (1001, 4)
    assert np.all(run.sos_r[run.armed] < run.sos_J)
    assert np.degrees(np.abs(run.att_err[200:]).max()) < 0.005
    np.testing.assert_allclose(run.refs["drift"] / DPH, att.PAPER_DRIFTS_DEG_PER_H[:3], atol=3)
    assert set(run.refs) == {"drift", "parity", "qdiff", "dos"}


def test_simulate_arguments():
    with pytest.raises(ValueError, match="unknown SimConfig setting"):
        att.simulate(colour="red")
    with pytest.raises(ValueError, match="^faults"):
        att.simulate(["gyro_x"])
    with pytest.raises(ValueError, match="^config"):
        att.simulate(config={"dt": 0.1})
    run = att.simulate(Fault("gyro", "noise", 1e-3, 45.0), duration=60.0, dos=False)
    assert run.truth == "unknown" and run.dos is None


def test_monitors_match_the_batch(nominal):
    run = nominal
    sos = att.SOSMonitor(run.q_meas[0], run.config, run.refs["drift"], run.refs["parity"])
    dos = att.DOSMonitor(run.q_meas[0], run.config, run.refs["dos"])
    for k in range(300):
        np.testing.assert_allclose(sos.step(run.omega_g[k], run.q_meas[k]), run.sos_r[k],
                                   rtol=1e-6, atol=1e-12)
        np.testing.assert_allclose(dos.step(run.omega_g[k], run.q_meas[k]), run.dos_r[k],
                                   rtol=1e-6, atol=1e-12)
    with pytest.raises(ValueError, match="^omega_g"):
        sos.step(np.zeros(3), run.q_meas[0])
    with pytest.raises(ValueError, match="^drift_ref"):
        att.DOSMonitor(run.q_meas[0], drift_ref=np.zeros(3))


def test_time_sos_dos_reports_both():
    r = att.time_sos_dos(n_steps=20, repeats=1)
    assert set(r) == {"sos_us", "dos_us", "ratio"}
    assert r["sos_us"] > 0 and r["dos_us"] > 0
    with pytest.raises(ValueError, match="^n_steps"):
        att.time_sos_dos(n_steps=1)


def test_isolation_monte_carlo_small():
    rows = att.isolation_monte_carlo(
        2, locations=["gyro_z", "star_tracker"], kinds=["step"], sizes=[1.0], rng=4
    )
    assert len(rows) == 6  # (none, gyro_z, star_tracker) x (SOS, DOS)
    by = {(r["location"], r["method"]): r for r in rows}
    assert by[("none", "SOS")]["false_alarm"] == 0.0 and by[("none", "SOS")]["correct"] == 1.0
    assert by[("gyro_z", "SOS")]["correct"] == 1.0 and by[("gyro_z", "DOS")]["correct"] == 1.0
    assert by[("gyro_z", "SOS")]["delay_s"] < by[("gyro_z", "DOS")]["delay_s"]
    table = att.isolation_table(rows)
    assert table.strip().count("\n") == 4 and "| gyro_z | step | 36 deg/h |" in table
    with pytest.raises(ValueError, match="^onset"):
        att.isolation_monte_carlo(1, onset=10.0)
    with pytest.raises(ValueError, match="^locations"):
        att.isolation_monte_carlo(1, locations=["sun_sensor"])
    with pytest.raises(ValueError, match="^sizes"):
        att.isolation_monte_carlo(1, sizes=[-1.0])


@pytest.mark.parametrize("method", ["sos", "dos", "qdiff"])
def test_plot_residuals(nominal, method):
    fig = att.plot_residuals(nominal, method)
    assert len(fig.axes) == (3 if method == "qdiff" else 4)
    plt.close(fig)


def test_plot_residuals_bad_input(nominal):
    with pytest.raises(ValueError, match="^method"):
        att.plot_residuals(nominal, "gos")
    with pytest.raises(ValueError, match="^run"):
        att.plot_residuals("run")


# ----------------------------------------------------------------------------- reproductions

ATTITUDE_IDS = [
    "attitude-xgyro-step",
    "attitude-skew-ramp",
    "attitude-star-tracker",
    "attitude-qdiff",
    "attitude-cost",
]


def test_all_attitude_reproductions_are_registered():
    assert set(ATTITUDE_IDS) <= set(reproduce.ids())
    for rid in ATTITUDE_IDS:
        rep = reproduce.get(rid)
        assert rep.chapter == "11_attitude_sos" and rep.title and rep.source


@pytest.mark.parametrize("rid", ATTITUDE_IDS)
def test_reproduction_passes(rid):
    res = reproduce.run(rid)
    res.assert_passed()
    assert res.note


def test_reproduction_writes_figures(tmp_path):
    res = reproduce.run("attitude-qdiff", out=tmp_path)
    assert res.figures and (tmp_path / "attitude-qdiff.png").exists()


def test_plot_fault_case_is_simulate_plus_plot_residuals():
    from matplotlib.figure import Figure

    before = plt.get_fignums()
    fig = att.plot_fault_case("gyro_y", "ramp", 10.0, n_sigma=4.0)
    assert isinstance(fig, Figure) and plt.get_fignums() == before  # not left in pyplot
    run = att.simulate(att.make_fault("gyro_y", "ramp", 10.0 * att.DEFAULT_MAGNITUDES[("gyro", "ramp")]),
                       n_sigma=4.0)
    assert len(fig.axes) == 8
    sos_axes, dos_axes = fig.axes[0::2], fig.axes[1::2]   # subplots(4, 2): row-major
    for i in range(4):
        np.testing.assert_allclose(sos_axes[i].lines[0].get_ydata(), run.sos_r[:, i] / DPH)
        np.testing.assert_allclose(dos_axes[i].lines[0].get_ydata(), run.dos_r[:, i] / DPH)
    assert sos_axes[0].get_title().startswith(f"SOS: verdict {run.sos.verdict}")
    st_fig = att.plot_fault_case("star_tracker", "step", 1.0)
    assert "truth star_tracker" in st_fig.axes[0].get_title()


@pytest.mark.parametrize(("kwargs", "name"), [
    ({"location": "gyro_w"}, "location"),
    ({"kind": "spike"}, "kind"),
    ({"size": 0.0}, "size"),
    ({"n_sigma": -1.0}, "n_sigma"),
])
def test_plot_fault_case_bad_input(kwargs, name):
    with pytest.raises(ValueError, match=rf"\b{name}\b"):
        att.plot_fault_case(**kwargs)
