"""The attitude sensors (xnavlab.attitude.sensors): the four-gyro matrix, gyro and star-tracker
measurement models with their faults, and the fault factory."""

import math

import numpy as np
import pytest

from xnavlab import attitude as att
from xnavlab.core import quaternions as qt

DPH = att.DEG_PER_H


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


def test_sensor_noise_beyond_its_range_is_refused():
    """Review 35e: the noise had no upper end (1e308 deg/h overflowed to inf samples)."""
    t = np.arange(3.0)
    with pytest.raises(ValueError, match=r"^noise_deg_per_h must be a real number in \[0, 100000\]"):
        att.gyro_measurements(t, np.zeros((3, 3)), noise_deg_per_h=1e308)
    with pytest.raises(ValueError, match=r"^noise_deg must be a real number in \[0, 180\]"):
        att.star_tracker_measurements(t, np.tile(att.DEFAULT_Q0, (3, 1)), noise_deg=1e308)


@pytest.mark.parametrize(("t", "match"), [
    (-0.0, r"^t must be a 1-D array \(shape \(n,\)\), got shape \(\)$"),
    ([1.0, True, 0.0], r"^t must be an array of finite numbers"),
    ([1.0], r"^t must hold one time per row of (w|q) \(3\), got 1$"),
    ([], r"^t must hold one time per row of (w|q) \(3\), got 0$"),
])
def test_the_sensors_name_t_when_the_times_do_not_match(t, match):
    """Issue 35: t was refused under w's or q's name (n = len(t))."""
    with pytest.raises(ValueError, match=match):
        att.gyro_measurements(t, np.zeros((3, 3)))
    with pytest.raises(ValueError, match=match):
        att.star_tracker_measurements(t, np.tile(att.DEFAULT_Q0, (3, 1)))
    with pytest.raises(ValueError, match=r"^w must have shape \(n, 3\), one rate per sample, got \(3,\)$"):
        att.gyro_measurements(np.arange(3.0), np.zeros(3))


def test_sensors_review_35i_refusals():
    """One Fault for a list, another sensor's fault, a zero true attitude."""
    t = np.arange(3.0)
    gyro, star = att.make_fault("gyro_x", "step", 1e-6), att.make_fault("star_tracker", "step", 1e-3)
    with pytest.raises(ValueError, match=r"^faults must be a sequence of Fault, got one Fault"):
        att.gyro_measurements(t, np.zeros((3, 3)), faults=gyro)
    with pytest.raises(ValueError, match=r"^faults\[1\] is a fault of the 'star_tracker' sensor"):
        att.gyro_measurements(t, np.zeros((3, 3)), faults=[gyro, star])
    q = np.tile(att.DEFAULT_Q0, (3, 1))
    with pytest.raises(ValueError, match=r"^faults\[0\] is a fault of the 'gyro' sensor"):
        att.star_tracker_measurements(t, q, faults=[gyro])
    with pytest.raises(ValueError, match=r"^q must have a non-zero norm"):
        att.star_tracker_measurements([0.0, 1.0], np.zeros((2, 4)), noise_deg=0.0)
    with pytest.raises(ValueError, match=r"^q must be a unit quaternion"):
        att.star_tracker_measurements(t, 2 * q, noise_deg=0.0)


def test_sensors_refuse_times_that_do_not_increase():
    """A fault's onset is read against t: decreasing or repeated times were accepted."""
    for t in (np.arange(3.0)[::-1].copy(), np.zeros(3)):
        with pytest.raises(ValueError, match=r"^t must be strictly increasing"):
            att.gyro_measurements(t, np.zeros((3, 3)), noise_deg_per_h=0.0)
        with pytest.raises(ValueError, match=r"^t must be strictly increasing"):
            att.star_tracker_measurements(t, np.tile(att.DEFAULT_Q0, (3, 1)), noise_deg=0.0)


def test_make_fault_refuses_an_onset_before_the_run():
    """Review 35i: a negative onset was accepted here and refused only by the run."""
    with pytest.raises(ValueError, match=r"^onset must be a real number in \[0, inf\)"):
        att.make_fault("gyro_x", "step", 1e-5, onset=-5.0)
    assert att.make_fault("gyro_x", "step", 1e-5, onset=0.0).onset == 0.0


def test_review_35_q4_a_noise_fault_draws_from_a_stream_of_its_own():
    """Review 35 Q4: a gyro noise fault drew from the sensor noise's generator, so the
    star-tracker noise of the whole run changed with it."""
    t, w, q = att.truth_motion(50, 0.1)
    gyro = att.make_fault("gyro_y", "noise", 1e-4, onset=2.0)
    star = att.make_fault("star_tracker", "noise", 1e-4, onset=2.0)
    g = np.random.default_rng(5)
    att.gyro_measurements(t, w, faults=[gyro], rng=g)
    after = att.star_tracker_measurements(t, q, rng=g)  # the gyro fault took no draw from g
    h = np.random.default_rng(5)
    att.gyro_measurements(t, w, rng=h)
    np.testing.assert_array_equal(after, att.star_tracker_measurements(t, q, rng=h))
    clean = att.star_tracker_measurements(t, q, rng=7)
    faulty = att.star_tracker_measurements(t, q, faults=[star], rng=7)
    np.testing.assert_array_equal(faulty[t < 2.0], clean[t < 2.0])
    assert np.abs(faulty - clean)[t >= 2.0].max() > 0.0  # the fault's own noise, after the onset
    np.testing.assert_array_equal(  # a Generator: the same run as its seed
        faulty, att.star_tracker_measurements(t, q, faults=[star], rng=np.random.default_rng(7)))


def test_review_35_q4_a_generator_that_cannot_spawn_is_refused_for_a_noise_fault():
    """Review 35 Q4: the fault's stream is a child of rng; a legacy-seeded generator has none."""
    t, w, _ = att.truth_motion(5, 0.1)
    bits = np.random.MT19937()
    bits._legacy_seeding(3)
    att.gyro_measurements(t, w, faults=[att.make_fault("gyro_x", "step", 1e-4, 0.1)],
                          rng=np.random.Generator(bits))  # nothing drawn: nothing spawned
    with pytest.raises(ValueError, match=r"^rng must be a seed or a numpy Generator that can "
                                         r"spawn a child stream \(numpy.random.default_rng\(seed\)\) "
                                         r"when a fault is of kind 'noise'$"):
        att.gyro_measurements(t, w, faults=[att.make_fault("gyro_x", "noise", 1e-4, 0.1)],
                              rng=np.random.Generator(bits))
