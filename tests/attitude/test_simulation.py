"""The attitude simulation (xnavlab.attitude.simulation): configuration checks and fault-free runs."""

import math
import re

import numpy as np
import pytest

from xnavlab import attitude as att
from xnavlab.core.faults import Fault

DPH = att.DEG_PER_H


@pytest.fixture(scope="module")
def nominal():
    return att.simulate()


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
    with pytest.raises(ValueError, match=r"^colour=.red. is not a SimConfig setting \(they are duration, dt"):
        att.simulate(colour="red")
    with pytest.raises(ValueError, match="^faults"):
        att.simulate(["gyro_x"])
    with pytest.raises(ValueError, match="^config"):
        att.simulate(config={"dt": 0.1})
    run = att.simulate(Fault("gyro", "noise", 1e-3, 45.0), duration=60.0, dos=False)
    assert run.truth == "unknown" and run.dos is None


@pytest.mark.parametrize(("fault", "words"), [
    (att.make_fault("gyro_x", "step", 1.0, onset=1e9), r"faults\[0\] \(gyro step, component 0\) "
                                                       r"starts at 1e\+09 s, outside this run"),
    (Fault("gyro", "step", 1.0, -1.0, component=0), r"starts at -1 s, outside this run: an "
                                                        r"onset is s since the start, in \[0, 60\)"),
    (att.make_fault("gyro_y", "step", 1.0, onset=45.01, duration=0.05), "acts on no sample"),
    (Fault("uv", "step", 1.0, 45.0), r"sensor must be one of 'gyro', 'star_tracker'"),
    (att.make_fault("gyro_z", "step", 1e8), r"reaches 1e\+08 rad/s, .* at most 1e\+06 rad/s"),
    (att.make_fault("gyro_z", "ramp", 1e6), r"ramp, component 2\) reaches 1e\+07 rad/s"),
])
def test_a_fault_the_run_would_not_use_is_refused_naming_it(fault, words):
    """Review 35b N15: an onset outside the run was accepted and never acted; a gyro rate so
    large that a step turns by more than quaternions.MAX_ANGLE named only '|w| dt'."""
    with pytest.raises(ValueError, match=r"^faults\[0\] \(") as info:
        att.simulate([fault], duration=60.0, dos=False)
    assert re.search(words, str(info.value)), str(info.value)


def test_one_fault_alone_is_a_run_of_that_fault_and_a_list_is_checked_as_core_does():
    """Review 35b N26: simulate(fault) is this function's common call (chapter 11), kept;
    a sequence goes through core.faults.check_faults (a repeat, a string are refused)."""
    f = att.make_fault("gyro_x", "step", 1e-3, onset=45.0)
    assert att.simulation.check_faults_in_run(f, att.SimConfig()) == (f,)
    with pytest.raises(ValueError, match=r"^faults lists .* twice \(items 0 and 1\)"):
        att.simulate([f, f], duration=60.0)
    with pytest.raises(ValueError, match=r"^faults must be a sequence of Fault, got the string"):
        att.simulate("gyro_x:step:1@45+inf", duration=60.0)


@pytest.mark.parametrize(("change", "words"), [
    ({"duration": 1e308}, r"^duration must be a real number in \(0, 1e\+06\], got 1e\+308$"),
    ({"duration": 1e5, "dt": 1e-3}, r"^duration must keep a run at most 1600000 samples \(about 2 GB"),
    ({"gyro_noise_deg_per_h": 1e308}, r"^gyro_noise_deg_per_h must be a real number in \(0, 100000\]"),
    ({"drifts_deg_per_h": (1e308, 0.0, 0.0, 0.0)}, r"^drifts_deg_per_h must lie in \[-100000, 100000\]"),
    ({"drift_walk_deg_per_h_sqrt_s": 1e308}, r"^drift_walk_deg_per_h_sqrt_s must be a real number in"),
    ({"drift_sigma0_deg_per_h": 1e308}, r"^drift_sigma0_deg_per_h must be a real number in"),
    ({"n_sigma": 1e308}, r"^n_sigma must be a real number in \[0.01, 30\]"),
    ({"persist": 10**30}, r"^persist must be an integer in \[1, 1000000\]"),
    ({"confirm_s": 1e308}, r"^confirm_s must be a real number in \[0, 86400\]"),
])
def test_a_run_setting_beyond_its_range_is_refused_not_an_overflow(change, words):
    """Review 35e: duration=1e308 was 'OverflowError: cannot convert float infinity to integer'."""
    with pytest.raises(ValueError, match=words):
        att.SimConfig(**change)


# ------------------------------------------------------------ the compiled filter bank


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_compiled_bank_runs_the_books_ekf_steps(seed):
    """The numba bank the simulations run is ekf_predict and ekf_update, step for step, for
    every run and filter of a batch: to 1e-10 of each array's largest entry (the loops sum in
    another order than numpy's matrix products, and solve S by Cholesky rather than LU)."""
    from xnavlab.attitude._bank_kernel import filter_bank_compiled
    from xnavlab.attitude.ekf import ekf_init, ekf_predict, ekf_update
    from xnavlab.core.quaternions import quat_normalize, quat_propagate

    rng = np.random.default_rng(seed)
    B, F, n, dt = 2, 3, 60, 0.1
    w = rng.normal(0.0, 0.02, (B, n, F, 3)) + np.array([0.01, -0.02, 0.03])
    q = np.empty((B, n, 4))
    q[:, 0] = att.DEFAULT_Q0
    for k in range(1, n):
        q[:, k] = quat_propagate(q[:, k - 1], w[:, k - 1, 0], dt)
    q_meas = quat_normalize(q + rng.normal(0.0, 1e-4, q.shape))
    q_meas[:, ::7] *= -1.0  # the sign alignment of the update
    A = rng.normal(0.0, 1.0, (F, 3, 3))
    gyro_cov, drift_cov = 1e-8 * A @ np.swapaxes(A, 1, 2), 1e-12 * np.eye(3) * np.ones((F, 1, 1))
    R = 1e-8 * np.eye(4)
    x0, P0 = ekf_init(np.broadcast_to(q_meas[:, :1], (B, F, 4)), attitude_sigma=1e-3,
                      drift_sigma=1e-3)
    q_hat, d_hat, P_dd = filter_bank_compiled(x0, P0, w, q_meas, dt, gyro_cov, drift_cov, R)
    x, P = x0, P0
    for k in range(n):
        if k:
            x, P = ekf_predict(x, P, w[:, k - 1], dt, gyro_cov, drift_cov)
        x, P, _ = ekf_update(x, P, np.broadcast_to(q_meas[:, k, None], (B, F, 4)), R)
        for ours, book in ((q_hat[:, k], x[..., :4]), (d_hat[:, k], x[..., 4:]),
                           (P_dd[:, k], P[..., 4:, 4:])):
            assert np.max(np.abs(ours - book)) <= 1e-10 * np.max(np.abs(book)), k


def test_simulation_review_35i_refusals():
    """A duration that is no whole number of steps (the run ended past it); a misspelt setting."""
    with pytest.raises(ValueError, match=r"^duration must be a whole number of steps dt = 0.7 s, got 60 s "
                                         r"\(nearest 59.5 or 60.2 s\)"):
        att.SimConfig(duration=60.0, dt=0.7)
    with pytest.raises(ValueError, match=r"^duraton=60.0 is not a SimConfig setting"):
        att.simulate(duraton=60.0)
    assert att.simulate(duration=60.0, dt=0.5, rng=0).t[-1] == 60.0


def test_simconfig_names_a_misspelt_setting_and_keeps_its_signature():
    """SimConfig(duraton=...) was Python's TypeError; the shown signature stays the fields'."""
    import inspect
    import pickle

    with pytest.raises(ValueError, match=r"^duraton=60.0 is not a SimConfig setting \(they are duration, dt"):
        att.SimConfig(duraton=60.0)
    assert list(inspect.signature(att.SimConfig).parameters)[:2] == ["duration", "dt"]
    cfg = att.SimConfig(duration=60.0)
    assert pickle.loads(pickle.dumps(cfg)) == cfg


def test_simconfig_stores_the_checked_values_not_the_numpy_scalars():
    """Review 35k (1) 1: SimConfig(duration=np.float16(100.0)) kept the float16 and duration / dt
    overflowed (RuntimeWarning); every field is now stored as checked (float, int, tuples)."""
    cfg = att.SimConfig(duration=np.float16(100.0), dt=np.float64(0.1), persist=np.int8(3),
                        n_sigma=np.float16(4.0), t_cal=np.array([20.0, 40.0]),
                        q0=np.array(att.DEFAULT_Q0), drifts_deg_per_h=np.zeros(4, np.float32))
    assert type(cfg.duration) is float and cfg.duration == 100.0
    assert type(cfg.dt) is float and type(cfg.persist) is int and type(cfg.n_sigma) is float
    assert cfg.t_cal == (20.0, 40.0) and all(type(v) is float for v in cfg.q0 + cfg.drifts_deg_per_h)
    assert att.SimConfig() == att.SimConfig(q0=tuple(att.DEFAULT_Q0))  # the defaults unchanged


@pytest.mark.parametrize(("change", "words"), [
    ({"q0": []}, r"^q0 must have trailing shape \(\.\.\., 4\)"),
    ({"q0": None}, r"^q0 must be"),
    ({"q0": np.ones((2, 4))}, r"^q0 must have shape \(4,\) \(one quaternion\)"),
    ({"q0": [0.0] * 4}, r"^q0 must have a non-zero norm"),
    ({"omega_orbit_deg_s": None}, r"^omega_orbit_deg_s must be a real number in \[0, 10\]"),
    ({"wobble_deg_s": math.nan}, r"^wobble_deg_s must be a real number in \[0, 10\]"),
    ({"wobble_period": 5e-324}, r"^wobble_period must be a real number in \[0.001, inf\)"),
    ({"wobble_period": "1.0"}, r"^wobble_period must be a real number"),
    ({"n_sigma": 5e-324}, r"^n_sigma must be a real number in \[0.01, 30\]"),
    ({"n_sigma": 100.0}, r"^n_sigma must be a real number in \[0.01, 30\]"),
])
def test_simconfig_names_the_field_at_fault(change, words):
    """Review 35k (3) 11 and 13: SimConfig(q0=[]) was refused as 'q must have ...' (the inner
    helper's name), n_sigma=5e-324 (or 100, inside the stated (0, 100]) later as 'p must be
    ...' (the tail probability, 1 or 0); the truth-motion settings were not checked at all."""
    with pytest.raises(ValueError, match=words):
        att.SimConfig(**change)


def test_a_run_past_about_2_gb_is_refused_by_simconfig():
    """Review 35k (3) 12: simulate(duration=1e6, dt=0.1) passed SimConfig (1e7 steps) and was
    refused by truth_motion. Review 35p P7: 1e7 samples were then allowed, about 12-14 GB for
    one run; SimConfig refuses past 1.6e6 samples (about 2 GB), naming duration and dt with
    the estimate and the longest duration at that dt."""
    with pytest.raises(ValueError, match=r"^duration must keep a run at most 1600000 samples \(about "
                       r"2 GB at 1200 bytes a sample\), got duration = 1e\+06 s at dt = 0\.1 s: "
                       r"10000001 samples, about 12 GB \(at most 159999\.9 s at this dt\)$"):
        att.simulate(duration=1e6, dt=0.1)
    with pytest.raises(ValueError, match=r"^duration must keep .* at dt = 0.5 s: 2000001 samples"):
        att.SimConfig(duration=1e6, dt=0.5)
    assert att.SimConfig(duration=159999.9, dt=0.1).n == 1_600_000
    assert att.SimConfig(duration=1e6, dt=1.0).n == 1_000_001


@pytest.mark.parametrize(("truth", "words"), [
    (1.0, r"^truth must be a tuple \(t, w, q\) from truth_motion for config, got 1\.0"),
    ("x", r"^truth must be a tuple \(t, w, q\)"),
    ([], r"^truth must be a tuple \(t, w, q\)"),
    ({}, r"^truth must be a tuple \(t, w, q\)"),
    ((np.zeros(3),) * 3, r"^truth\[0\] must have shape \(601,\)"),
])
def test_simulate_sensors_checks_the_truth_it_is_given(truth, words):
    """Review 35k (1) 13, (2) 7: truth=1.0 was "TypeError: cannot unpack non-iterable float",
    truth='x' numpy's "not enough values to unpack (expected 3, got 1)"."""
    with pytest.raises(ValueError, match=words):
        att.simulation.simulate_sensors(att.SimConfig(duration=60.0), truth=truth)


def test_simulate_sensors_refuses_the_truth_of_another_config():
    """Review 35k (1) 13: a truth of another dt (the same number of samples) was used as given."""
    cfg = att.SimConfig(duration=60.0)
    with pytest.raises(ValueError, match=r"^truth\[0\] must be config's sample times k dt"):
        att.simulation.simulate_sensors(cfg, truth=att.truth_motion(cfg.n, 0.2))
    truth = att.truth_motion(cfg.n, cfg.dt)
    a = att.simulation.simulate_sensors(cfg, truth=truth)
    b = att.simulation.simulate_sensors(cfg)
    assert np.array_equal(a[1], b[1]) and np.array_equal(a[2], b[2])


@pytest.mark.parametrize("changes, words", [
    ({"duration": 20.0}, r"^duration must be at least 40 s with the default calibration window "
                         r"t_cal = \(20, 40\) s, got 20 s: lengthen it or give t_cal$"),
    ({"dt": 6.0, "duration": 60.0}, r"^dt must be at most 5 s with the default qdiff_window_s = "
                                    r"10 s \(two samples at least\), got 6 s"),
    ({"t_cal": (20.0, 25.0)}, r"^t_cal must leave an estimate for the default qdiff_window_s = "
                              r"10 s: .*got t_cal = \(20\.0, 25\.0\)"),
    ({"qdiff_window_s": 50.0}, r"^qdiff_window_s must leave an estimate inside t_cal: .*got "
                               r"w = 50\.0, t_cal = \(20\.0, 40\.0\)$"),
])
def test_a_default_setting_is_named_as_the_default_the_given_one_clashes_with(changes, words):
    """Review 35o (3) 1 (pattern U): make_config(duration=20) said 't_cal must satisfy ...
    got [20. 40.]', naming the default t_cal as if the user had typed it."""
    with pytest.raises(ValueError, match=words):
        att.simulation.make_config(**changes)



@pytest.mark.parametrize("location", ["gyro_x", "star_tracker"])
def test_review_35_q4_a_noise_fault_leaves_the_sensor_noise_of_its_seed(location):
    """Review 35 Q4: a gyro noise fault changed the star-tracker noise of the whole run, from
    t = 0, for the same seed; the fault's noise now comes from a stream of its own."""
    clean = att.simulate(duration=100.0, rng=0)
    fault = att.make_fault(location, "noise", 1e-4, onset=60.0)
    run = att.simulate(fault, duration=100.0, rng=0)
    before = run.t < 60.0
    np.testing.assert_array_equal(run.omega_g[before], clean.omega_g[before])
    np.testing.assert_array_equal(run.q_meas[before], clean.q_meas[before])
    other = "q_meas" if location == "gyro_x" else "omega_g"  # the other sensor: all of it
    np.testing.assert_array_equal(getattr(run, other), getattr(clean, other))
    again = att.simulate(fault, duration=100.0, rng=np.random.default_rng(0))
    np.testing.assert_array_equal(again.omega_g, run.omega_g)  # a Generator: its seed's run
    np.testing.assert_array_equal(again.q_meas, run.q_meas)
