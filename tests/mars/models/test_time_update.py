"""The filters' time update (xnavlab.mars.models.time_update): RK4 against the truth propagator, the
transition matrix against finite differences, the process noise's structure, one memoised step."""

import numpy as np
import pytest

from xnavlab.mars.models import dynamics, time_update


@pytest.fixture(scope="module")
def table():
    return dynamics.ThirdBodyTable(dynamics.MARS_T0, dynamics.MARS_T0 + 2000.0)


def test_propagation_follows_the_truth_and_its_transition_matrix_the_finite_differences(table):
    x0, t0 = dynamics.MARS_STATE0, dynamics.MARS_T0
    x1, Phi = time_update.filter_propagate(x0, t0, 500.0, table)
    truth = dynamics.propagate([t0 + 500.0])[0]
    assert np.abs(x1 - truth)[:3].max() < 1e-3
    h = np.array([1.0, 1.0, 1.0, 1e-3, 1e-3, 1e-3])           # m, m/s
    numeric = np.column_stack([
        (time_update.filter_propagate(x0 + h[i] * e, t0, 500.0, table)[0]
         - time_update.filter_propagate(x0 - h[i] * e, t0, 500.0, table)[0]) / (2 * h[i])
        for i, e in enumerate(np.eye(6))])
    # point-mass gradient held over each 10-s sub-step: 1e-4 of the largest entry (505 s)
    assert np.abs(Phi - numeric).max() < 1e-3 * np.abs(numeric).max()


def test_process_noise_is_the_white_acceleration_form():
    Q = time_update.process_noise(10.0, 2.0)
    assert np.allclose(Q, Q.T) and np.all(np.linalg.eigvalsh(Q) >= 0.0)
    assert Q[0, 0] == pytest.approx(2.0 * 1000.0 / 3.0) and Q[0, 3] == pytest.approx(100.0)
    assert Q[3, 3] == pytest.approx(20.0) and Q[0, 1] == 0.0


def test_one_memoised_step_integrates_once(table, monkeypatch):
    calls = []
    real = time_update.filter_propagate
    monkeypatch.setattr(time_update, "filter_propagate",
                        lambda *a, **k: calls.append(1) or real(*a, **k))
    prop = time_update.Propagation(dynamics.MARS_T0, 60.0, table, 10.0)
    x = dynamics.MARS_STATE0
    prop.f(x), prop.F(x), prop.f(x)
    assert len(calls) == 1


def test_the_time_update_refuses_complex_and_nan_by_name():
    tab = dynamics.ThirdBodyTable(dynamics.MARS_T0, dynamics.MARS_T0 + 600.0)
    x = dynamics.MARS_STATE0.astype(complex)
    with pytest.raises(ValueError, match="^x must hold real numbers"):
        time_update.filter_propagate(x, dynamics.MARS_T0, 60.0, tab)
    with pytest.raises(ValueError, match="^max_step must be a real number"):
        time_update.filter_propagate(dynamics.MARS_STATE0, dynamics.MARS_T0, 60.0, tab, np.nan)
    with pytest.raises(ValueError, match="^q must be a real number"):
        time_update.process_noise(1.0, 1j)
    with pytest.raises(ValueError, match="^dt must be a real number"):
        time_update.Propagation(dynamics.MARS_T0, np.nan, tab, 10.0)


def test_a_step_or_noise_beyond_its_range_is_refused_not_an_overflow_or_an_endless_loop():
    """Review 35e: filter_step(dt=1e308) and process_noise(1e308, q) overflowed to inf, and
    filter_propagate(dt=1e308) or max_step=1e-300 looped without end."""
    tab = dynamics.ThirdBodyTable(dynamics.MARS_T0, dynamics.MARS_T0 + 600.0)
    x0, t0 = dynamics.MARS_STATE0, dynamics.MARS_T0
    with pytest.raises(ValueError, match=r"^dt must be a real number in \[-86400, 86400\], got 1e\+308$"):
        time_update.filter_step(x0, t0, 1e308, tab)
    with pytest.raises(ValueError, match=r"^dt must be a real number in \[0, 1e\+06\], got 1e\+308$"):
        time_update.process_noise(1e308, 1.0)
    with pytest.raises(ValueError, match=r"^q must be a real number in \[0, 1e\+06\], got 1e\+308$"):
        time_update.process_noise(1.0, 1e308)
    with pytest.raises(ValueError, match=r"^dt / max_step must be at most 1e6 sub-steps, got dt = 1e\+308 s"):
        time_update.filter_propagate(x0, t0, 1e308, tab)
    with pytest.raises(ValueError, match=r"^dt / max_step must be at most 1e6 sub-steps"):
        time_update.filter_propagate(x0, t0, 1e5, tab, max_step=0.01)
    with pytest.raises(ValueError, match=r"^max_step must be a real number in \[0.01, 86400\], got 1e-300$"):
        time_update.filter_propagate(x0, t0, 500.0, tab, max_step=1e-300)
    with pytest.raises(ValueError, match=r"^max_step must be a real number in \[0.01, 86400\]"):
        time_update.filter_propagate(x0, t0, 500.0, tab, max_step=1e308)


def test_a_table_that_is_no_third_body_table_is_refused_by_name():
    """Issue 35 (review 35h): a bool or a list for ``table`` was an AttributeError inside
    the RK4 step ('bool' object has no attribute 'bodies')."""
    x0, t0 = dynamics.MARS_STATE0, dynamics.MARS_T0
    for fn in (lambda: time_update.filter_step(x0, t0, 3.0, True),
               lambda: time_update.filter_propagate(x0, t0, 3.0, -0.0),
               lambda: time_update.Propagation(t0, 60.0, [], 10.0)):
        with pytest.raises(ValueError, match=r"^table must be a ThirdBodyTable or None, got"):
            fn()
    tab = dynamics.ThirdBodyTable(t0, t0 + 600.0)
    with pytest.raises(ValueError, match=r"^max_step must be a real number in \[0.01, 86400\], got 5e-324$"):
        time_update.Propagation(t0, 60.0, tab, 5e-324)
    point_mass = dynamics.acceleration(t0, x0[:3])  # no table: Mars's point mass alone
    k1 = time_update.filter_step(x0, t0, 1e-3, None)
    assert np.allclose((k1 - x0)[3:] / 1e-3, point_mass, rtol=1e-6)


def test_a_step_out_of_the_tables_span_names_dt():
    """Review 35j (3) 2: a negative dt from the table's start blamed t, with a value inside
    the step the user never gave."""
    tab = dynamics.ThirdBodyTable(dynamics.MARS_T0, dynamics.MARS_T0 + 1e4)
    x0, t0 = dynamics.MARS_STATE0, dynamics.MARS_T0
    with pytest.raises(ValueError, match=r"^dt = -10 s takes the step to t \+ dt = 504878390 s, "
                                         r"outside the table's span \[504878400, 504892800\] s: "
                                         r"dt must be in \[0, 14400\] from this t$"):
        time_update.filter_step(x0, t0, -10.0, tab)
    with pytest.raises(ValueError, match=r"^dt = 100000 s takes the step to"):
        time_update.filter_propagate(x0, t0, 1e5, tab)
    with pytest.raises(ValueError, match=r"^t must lie in \[504878400, 504892800\] s, the table's "
                                         r"span, got 504878395$"):
        time_update.Propagation(t0 - 5.0, 10.0, tab, 10.0)
    assert np.isfinite(time_update.filter_step(x0, t0 + 10.0, -10.0, tab)).all()  # backward


def test_one_state_is_refused_as_x_not_as_an_inner_r():
    """Review 35k (3) 7: a (1, 6) x was refused as 'r must have trailing shape (..., 3)', and
    a state at the centre as dynamics.acceleration's r."""
    tab = dynamics.ThirdBodyTable(dynamics.MARS_T0, dynamics.MARS_T0 + 600.0)
    for call in (time_update.filter_step, time_update.filter_propagate):
        with pytest.raises(ValueError, match=r"^x must be a 1-D array \(shape \(6,\)\), got "
                                             r"shape \(1, 6\)$"):
            call(dynamics.MARS_STATE0[None], dynamics.MARS_T0, 3.0, tab)
    with pytest.raises(ValueError, match=r"^x position must lie between 1 m and 1e\+15 m of "
                                         r"Mars's centre, got \|r\| = 0 m$"):
        time_update.filter_step(np.zeros(6), dynamics.MARS_T0, 3.0, tab)
