"""The constant-velocity filter fed by folded TOAs (xnavlab.line.track)."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad_vec

from xnavlab.line import track


@pytest.mark.parametrize("dim", [1, 2])
def test_cv_model_q_is_the_integrated_white_acceleration(dim):
    dt, a = 7.0, 0.02
    F, Q = track.cv_model(dt, a, dim)
    G = np.vstack([np.zeros((dim, dim)), np.eye(dim)])

    def integrand(s):
        Phi = track.cv_model(s, 0.0, dim)[0] if s > 0 else np.eye(2 * dim)
        return Phi @ G @ G.T @ Phi.T * a**2

    assert np.allclose(Q, quad_vec(integrand, 0.0, dt)[0], rtol=1e-10, atol=0)
    assert np.allclose(F[:dim, dim:], dt * np.eye(dim))


def test_cv_model_rejects_a_bad_step():
    with pytest.raises(ValueError, match="dt"):
        track.cv_model(0.0)
    with pytest.raises(ValueError, match="dim"):
        track.cv_model(1.0, dim=4)


def test_simulate_without_noise_moves_at_constant_velocity():
    truth = track.simulate(np.array([1.0, 2.0, 3.0, -4.0]), 5.0, 10)
    assert truth.shape == (11, 4)
    assert np.allclose(truth[-1], [1.0 + 150.0, 2.0 - 200.0, 3.0, -4.0])


def test_simulate_with_noise_has_the_model_spread_of_velocity():
    truth = np.array([track.simulate(np.zeros(2), 10.0, 100, 0.01, rng=s)[-1] for s in range(300)])
    assert np.std(truth[:, 1]) == pytest.approx(0.01 * math.sqrt(1000.0), rel=0.15)


def test_the_filter_is_consistent():
    """NEES and NIS averaged over runs stay near their dimensions (2 and 1)."""
    nees, nis = [], []
    for seed in range(12):
        truth = track.simulate(np.array([2.0e11, 2.0e4]), 20.0, 60, rng=seed)
        run = track.track(truth, 20.0, truth[0] + [300.0, 1.0], np.diag([1e6, 4.0]), rng=seed + 50)
        e = run.x[-1] - truth[-1]
        nees.append(e @ np.linalg.solve(run.P[-1], e))
        nis.extend(run.nis)
    assert 1.0 < np.mean(nees) < 3.5
    assert 0.8 < np.mean(nis) < 1.2
    assert run.z.shape == (60, 1) and run.P.shape == (61, 2, 2)


def test_one_pulsar_leaves_the_other_axis_unobserved_two_bound_it():
    truth = track.simulate(np.array([2.0e11, 0.0, 2.0e4, 0.0]), 20.0, 40)
    P0 = np.diag([1e8, 1e8, 1.0, 1.0])
    pair = ("B0531+21", "B1937+21")
    n2 = np.array([[1.0, 0.0], [math.cos(2.2), math.sin(2.2)]])
    one = track.track(truth, 20.0, truth[0], P0, pair[:1], n2[:1], rng=1)
    two = track.track(truth, 20.0, truth[0], P0, pair, n2, rng=1)
    assert one.P[-1, 1, 1] > one.P[0, 1, 1]  # across the line of sight: grows
    assert two.P[-1, 1, 1] < 1e-2 * two.P[0, 1, 1]
    assert one.P[-1, 0, 0] < 1e-3 * one.P[0, 0, 0]


def test_track_rejects_mismatched_shapes():
    with pytest.raises(ValueError, match="directions"):
        track.track(np.zeros((3, 2)), 10.0, np.zeros(2), np.eye(2), ("B0531+21", "B1937+21"))
    with pytest.raises(ValueError, match="P0"):
        track.track(np.zeros((3, 2)), 10.0, np.zeros(2), -np.eye(2))


@settings(max_examples=30, deadline=None)
@given(theta=st.floats(0.05, math.pi - 0.05), sigma=st.floats(1.0, 1e4))
def test_snapshot_axes_of_two_equal_pulsars(theta, sigma):
    """Semi-axes sigma / sqrt(1 -+ cos theta) for two pulsars theta apart."""
    P = track.snapshot_covariance([[1.0, 0.0], [math.cos(theta), math.sin(theta)]], [sigma] * 2)
    axes = np.sqrt(np.linalg.eigvalsh(P))
    expect = sorted(sigma / math.sqrt(1.0 + s * abs(math.cos(theta))) for s in (1, -1))
    assert np.allclose(axes, expect, rtol=1e-9)


def test_run_line_flies_the_chapter_spacecraft():
    truth, run = track.run_line(exposure_s=100.0, span_s=1000.0, dv=2.0)
    assert truth[0].tolist() == [track.X0, track.V0 + 2.0]
    assert run.x[0].tolist() == [track.X0 + 2e3, track.V0]
    assert truth.shape == (11, 2) and run.nis.shape == (10,)
    with pytest.raises(ValueError, match="exposure_s"):
        track.run_line(exposure_s=0.0)


def test_plot_tracking_labels_its_axes_and_states_the_final_sigma():
    fig = track.plot_tracking(exposure_s=100.0, span_s=1000.0)
    ax1, ax2 = fig.axes
    assert ax1.get_ylabel() == "position error (m)" and ax2.get_xlabel() == "time (s)"
    assert "10 TOAs" in fig.get_suptitle()


def test_track_names_its_own_exposure_and_pulsars():
    with pytest.raises(ValueError, match="^exposure must be a real number"):
        track.track(np.zeros((2, 2)), 10.0 + 1j, np.zeros(2), np.eye(2))
    with pytest.raises(ValueError, match="^dv must be a real number"):
        track.run_line(dv=float("nan"))


@pytest.mark.parametrize("directions, sigmas, match", [
    (((1.0, 0.0), (1.0, 0.0)), (1.0, 1.0), r"directions must span the plane \(2 dimensions\), got rank 1"),
    (((1.0, 0.0), (0.0, 1.0)), (1.0, 0.0), r"sigmas must be real numbers in \[1e-3, 1e15\]"),
    (((1.0, 0.0), (0.0, 1.0)), (1.0,), r"sigmas must"),
    ((1.0, 0.0), (1.0,), r"directions must have shape \(n, d\)")])
def test_snapshot_covariance_refuses_directions_that_do_not_span_and_bad_sigmas(directions, sigmas,
                                                                               match):
    """Two pulsars in one direction gave a raw LinAlgError (Singular matrix)."""
    with pytest.raises(ValueError, match=match):
        track.snapshot_covariance(directions, sigmas)


def test_run_line_names_its_seed_and_takes_the_last_one():
    """Review 35e: seed -1 was refused as 'rng', and the last seed failed on its seed + 1."""
    with pytest.raises(ValueError, match=r"^seed must be an integer in \[0, 9223372036854775807\]"):
        track.run_line(seed=-1)
    truth, run = track.run_line(exposure_s=500.0, seed=2**63 - 1)
    assert np.all(np.isfinite(run.x))


def test_issue35_simulate_names_a_state0_of_odd_size():
    # Review 35f finding 24: numpy's "mean and cov must have same length" named no parameter.
    with pytest.raises(ValueError, match=r"^state0 must be a position and a velocity"):
        track.simulate(np.zeros(3), 1.0, 3, rng=0)


@pytest.mark.parametrize("exposure_s, span_s", [(100.0, 50.0), (10000.0, 1.0)])
def test_issue35_run_line_refuses_a_span_shorter_than_one_toa(exposure_s, span_s):
    # Review 35f finding 25: the span was silently stretched to one exposure.
    with pytest.raises(ValueError, match=r"^span_s must be at least exposure_s"):
        track.run_line(exposure_s=exposure_s, span_s=span_s)


def test_issue35_snapshot_covariance_sigmas_from_a_millimetre():
    # Review 35f finding 27: 1 / 5e-324**2 overflowed to inf.
    with pytest.raises(ValueError, match=r"^sigmas must be real numbers in \[1e-3, 1e15\]"):
        track.snapshot_covariance(((1.0, 0.0), (0.0, 1.0)), (5e-324, 1.0))


@pytest.mark.parametrize("directions, words", [
    (((0.0,),), r"^directions\[0\] must be a unit vector to a pulsar, got a zero vector"),
    (((3.0,),), r"^directions\[0\] must be a unit vector to a pulsar \(norm 1 to 1e-12: a range "
                r"n \. r scales with it\), got norm 3$"),
    (((1.0 + 1e-9,),), r"^directions\[0\] must be a unit vector .* got norm 1.000000001$"),
])
def test_issue35_track_refuses_a_zero_or_non_unit_direction(directions, words):
    """Review 35i: directions=((0.0,),) ran a filter that observed nothing, ((3.0,),) one whose
    ranges were three times the truth's."""
    truth = track.simulate(np.array([0.0, 5.0]), 500.0, 4)
    with pytest.raises(ValueError, match=words):
        track.track(truth, 500.0, np.array([0.0, 5.0]), np.diag([1e6, 1.0]), directions=directions,
                    rng=0)
    run = track.track(truth, 500.0, np.array([0.0, 5.0]), np.diag([1e6, 1.0]),
                      directions=((np.cos(0.0),),), rng=0)
    assert run.x.shape == (5, 2)


@pytest.mark.parametrize("directions, sigmas, words", [
    ([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], [3.0, 4.0, 5.0],
     r"^directions\[0\] must be a unit vector to a pulsar, got a zero vector"),
    ([[2.0, 0.0], [0.0, 1.0]], [3.0, 4.0], r"^directions\[0\] must be a unit vector .* got norm 2$"),
    ([[0.707, 0.707], [0.0, 1.0]], [3.0, 4.0], r"^directions\[0\] must be a unit vector"),
])
def test_issue35_snapshot_covariance_refuses_a_zero_or_non_unit_direction(directions, sigmas, words):
    """Review 35i: a zero row was dropped without a word and [[2, 0], [0, 1]] gave a variance
    of 9 / 4 instead of 9."""
    with pytest.raises(ValueError, match=words):
        track.snapshot_covariance(directions, sigmas)
    c = np.cos(np.radians(30.0))
    assert track.snapshot_covariance([[c, 0.5], [-0.5, c]], [1.0, 1.0]) == pytest.approx(np.eye(2))


@pytest.mark.parametrize("exposure_s, span_s, words", [
    (500.0, 1700.0, r"^span_s must be a whole number of exposures exposure_s = 500 s, got 1700 s "
                    r"\(3.4 TOAs\): the nearest are 1500 and 2000 s$"),
    (30.0, 2000.0, r"^span_s must be a whole number of exposures exposure_s = 30 s, got 2000 s"),
])
def test_issue35_run_line_refuses_a_span_between_two_whole_exposures(exposure_s, span_s, words):
    """Review 35i: exposure_s=500, span_s=1700 ran 3 TOAs, its truth ending at 1500 s."""
    with pytest.raises(ValueError, match=words):
        track.run_line(exposure_s=exposure_s, span_s=span_s)
    for exposure in (10.0, 20.0, 50.0, 100.0, 200.0, 500.0, 1000.0):  # chapter 0's slider
        assert track.run_line(exposure_s=exposure, span_s=2000.0)[1].z.shape == (2000.0 / exposure, 1)


def test_issue35_simulate_takes_an_rng_without_noise_and_ignores_it_as_documented():
    """Review 35i: rng is unused with accel_sigma = 0; accepted (a sweep down to 0 keeps one
    call), documented, and the truth is then the same for every seed."""
    base = track.simulate(np.array([0.0, 5.0]), 2.0, 3)
    for rng in (1, np.random.default_rng(7)):
        np.testing.assert_array_equal(track.simulate(np.array([0.0, 5.0]), 2.0, 3, rng=rng), base)
    with pytest.raises(ValueError, match=r"^rng must be"):
        track.simulate(np.array([0.0, 5.0]), 2.0, 3, rng=1.5)


def test_track_refuses_a_truth_of_one_row():
    """Review 35i: one row of truth gave a Track of no measurement (z of shape (0,))."""
    with pytest.raises(ValueError, match=r"^truth must hold at least 2 rows"):
        track.track(np.zeros((1, 2)), 10.0, np.zeros(2), np.eye(2) * 1e6, rng=0)


def test_plot_tracking_takes_a_fraction_as_its_float():
    """Review 35m (1) 2, pattern M: exposure_s=Fraction(50) passed run_line's check, then the
    plot went on with the raw Fraction (matplotlib's "ufunc 'isfinite' not supported")."""
    from fractions import Fraction

    fig = track.plot_tracking(exposure_s=Fraction(50))
    ref = track.plot_tracking(exposure_s=50.0)
    assert fig.get_suptitle() == ref.get_suptitle()
    np.testing.assert_array_equal(fig.axes[0].lines[0].get_xdata(), ref.axes[0].lines[0].get_xdata())


def test_a_run_of_more_than_max_toas_is_refused_with_the_estimate():
    """Review 35p P10: run_line(exposure_s=0.1, span_s=1e5) took 1e6 TOAs, about 37 minutes,
    without a word; past MAX_TOAS (2e5, about 7 minutes) it is refused naming span_s and
    exposure_s, and track() likewise names truth."""
    with pytest.raises(ValueError, match=r"^span_s / exposure_s must keep at most 200000 TOAs "
                       r"\(about 7 minutes at 2\.1 ms a TOA\), got span_s = 100000 s / exposure_s = "
                       r"0\.1 s = 1000000 TOAs, about 35 minutes \(at most 20000 s at this "
                       r"exposure\)$"):
        track.run_line(exposure_s=0.1, span_s=1e5)
    with pytest.raises(ValueError, match=r"^span_s / exposure_s must keep at most 200000 TOAs"):
        track.plot_tracking(exposure_s=0.2, span_s=5e4)
    with pytest.raises(ValueError, match=r"^truth must keep at most 200000 TOAs .* got 100001 steps "
                       r"x 2 pulsars = 200002 TOAs, about 7 minutes \(at most 100001 rows with 2 "
                       r"pulsars\)$"):
        track.track(np.zeros((100002, 4)), 1.0, np.zeros(4), np.eye(4),
                    pulsar_names=("B0531+21", "B1937+21"), directions=((1.0, 0.0), (0.0, 1.0)))
