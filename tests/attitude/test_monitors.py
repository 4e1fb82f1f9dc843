"""The step-by-step SOS and DOS monitors (xnavlab.attitude.monitors): they match the batch
diagnosis, and their timing report gives both."""


import numpy as np
import pytest

from xnavlab import attitude as att


@pytest.fixture(scope="module")
def nominal():
    return att.simulate()


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


def test_time_sos_dos_refuses_counts_that_would_not_end():
    """Review 35e: repeats=10**30 ran without end."""
    with pytest.raises(ValueError, match=r"^repeats must be an integer in \[1, 10000\]"):
        att.time_sos_dos(n_steps=20, repeats=10**30)
    with pytest.raises(ValueError, match=r"^n_steps must be an integer in \[10, 100000\]"):
        att.time_sos_dos(n_steps=10**30)


@pytest.mark.parametrize("monitor", [att.SOSMonitor, att.DOSMonitor])
@pytest.mark.parametrize("q, words", [
    (np.zeros(4), "q_meas must have a non-zero norm"),
    (1.5 * np.asarray(att.DEFAULT_Q0), "q_meas must be a unit quaternion")])
def test_monitor_step_refuses_a_zero_or_scaled_measurement_before_any_filter_moves(monitor, q, words):
    """Review 35l (5) 4: att.SOSMonitor/att.DOSMonitor.step(w, np.zeros(4)) was taken."""
    m = monitor(att.DEFAULT_Q0)
    m.step(att.gyro_matrix() @ np.zeros(3), att.DEFAULT_Q0)
    xs = [f.x.copy() for f in m.filters]
    with pytest.raises(ValueError, match=f"^{words}"):
        m.step(att.gyro_matrix() @ np.zeros(3), q)
    assert all(np.array_equal(x, f.x) for x, f in zip(xs, m.filters, strict=True))


def test_a_masked_sample_is_refused_a_read_only_one_used(nominal):
    """Review 35m (5) 1: the monitors' per-sample check used a masked entry as data."""
    run = nominal
    sos = att.SOSMonitor(run.q_meas[0], run.config, run.refs["drift"], run.refs["parity"])
    twin = att.SOSMonitor(run.q_meas[0], run.config, run.refs["drift"], run.refs["parity"])
    wg = np.ma.masked_array(run.omega_g[0].copy())
    wg[2] = np.ma.masked
    with pytest.raises(ValueError, match=r"^omega_g has masked entries \(no number to use"):
        sos.step(wg, run.q_meas[0])
    ro = run.q_meas[0].copy()
    ro.setflags(write=False)
    np.testing.assert_array_equal(sos.step(np.ma.masked_array(run.omega_g[0]), ro),
                                  twin.step(run.omega_g[0], run.q_meas[0]))


def test_time_sos_dos_refuses_a_timing_of_hours():
    """Review 35p (same class as P6/P7): n_steps=1e5 with repeats=1e4 was allowed, about 29
    days at 2.5 ms a sample; n_steps x repeats is at most 2e5 (about 8 minutes)."""
    with pytest.raises(ValueError, match=r"^n_steps x repeats must be at most 200000 timed samples "
                       r"\(about 8 minutes at 2\.5 ms a sample of SOS and DOS\), got n_steps = "
                       r"100000 x repeats = 10000 = 1e\+09, about 694 hours \(at most 2 repeats "
                       r"of 100000 steps\)$"):
        att.time_sos_dos(n_steps=10**5, repeats=10**4)
