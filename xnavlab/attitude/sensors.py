"""The attitude sensors: a gyro assembly (3 orthogonal + 1 skewed) and a star tracker.

Models (Li, Niu et al. 2019; equations lost from our copy, rebuilt in the standard forms
of Crassidis & Junkins 2012, ch. 7, with the paper's numbers in the comments):

Gyros
    ``w_g = H w + b + v_g + f_g`` (paper eq. (2)) with ``H = [I3; h4^T]`` and the skewed
    gyro on the equal-angle axis ``h4 = [1, 1, 1]/sqrt(3)`` (:data:`SKEW_AXIS`, paper
    eq. (3) lost). Drifts and noise at the paper's values (section 4).
Star tracker
    ``q_s = q (x) q_v + f_q`` (paper eq. (17) with ``q_f = 1``), renormalised, as a star
    tracker reports unit quaternions.
Faults
    A single fault sits on one of :data:`LOCATIONS`; :func:`make_fault` builds it as a
    :class:`xnavlab.core.faults.Fault`, and :data:`DEFAULT_MAGNITUDES` are our reference
    sizes (the paper's eqs. (38)-(40) were lost).

Units are SI inside (rad, rad/s, s); names say otherwise (``drifts_deg_per_h``).
"""

from __future__ import annotations

import math

import numpy as np

from xnavlab.attitude._checks import check_quaternion
from xnavlab.core.faults import KINDS, Fault, check_faults, inject
from xnavlab.core.quaternions import quat_from_rotvec, quat_normalize, quat_product
from xnavlab.core.validate import (
    check_choice,
    check_finite_array,
    check_increasing,
    check_real,
    check_vector,
    make_rng,
)

__all__ = [
    "DEG_PER_H",
    "MAX_DEG_PER_H",
    "PAPER_DRIFTS_DEG_PER_H",
    "PAPER_GYRO_NOISE_DEG_PER_H",
    "PAPER_STAR_NOISE_DEG",
    "SKEW_AXIS",
    "LOCATIONS",
    "DEFAULT_MAGNITUDES",
    "MAX_FACTOR",
    "gyro_matrix",
    "gyro_measurements",
    "star_tracker_measurements",
    "make_fault",
]

#: rad/s in one deg/h.
DEG_PER_H = math.pi / 180.0 / 3600.0

#: The largest gyro drift, noise or drift uncertainty a setting takes, deg/h (about 28 deg/s,
#: far beyond any gyro; a larger one would overflow the squares of the filters' covariances).
MAX_DEG_PER_H = 1e5

#: Constant drifts of gyros x, y, z and the skewed gyro, deg/h (paper section 4).
PAPER_DRIFTS_DEG_PER_H = (50.0, 40.0, -50.0, 45.0)

#: Gyro measurement noise, 1 sigma per sample, deg/h (paper section 4).
PAPER_GYRO_NOISE_DEG_PER_H = 0.05

#: Star-tracker noise, 1 sigma per axis, deg (paper section 4).
PAPER_STAR_NOISE_DEG = 0.00333

#: Our choice of skewed-gyro axis (paper eq. (3) lost): equal angles with x, y, z.
SKEW_AXIS = np.full(3, 1.0 / math.sqrt(3.0))

#: Where a single fault can be: the four gyros and the star tracker.
LOCATIONS = ("gyro_x", "gyro_y", "gyro_z", "gyro_skew", "star_tracker")

#: Our reference fault sizes (paper eqs. (38)-(40) lost), SI: a gyro step of 36 deg/h
#: (0.01 deg/s), a gyro ramp of 0.1 deg/h per second, a star-tracker step of 2e-4 and a
#: star-tracker ramp of 5e-5 per second on the quaternion component q1.
DEFAULT_MAGNITUDES = {
    ("gyro", "step"): 36.0 * DEG_PER_H,
    ("gyro", "ramp"): 0.1 * DEG_PER_H,
    ("star_tracker", "step"): 2e-4,
    ("star_tracker", "ramp"): 5e-5,
}
#: The largest multiple of :data:`DEFAULT_MAGNITUDES` a study takes: a thousand times the
#: paper's faults (a 36,000 deg/h gyro step, a 0.2 rad star-tracker step) is past any sensor's
#: failure; at 1e308 the magnitude left every range under another name.
MAX_FACTOR = 1000.0


# -------------------------------------------------------------- gyro assembly


def gyro_matrix(skew_axis=SKEW_AXIS):
    """Measurement matrix ``H = [I3; h4^T]`` of three orthogonal gyros and a skewed one.

    Paper eqs. (2)-(3) (eq. (3) lost): gyro ``i`` measures the body rate along its
    input axis, the rows of ``H``.

    Parameters
    ----------
    skew_axis : array_like, shape (3,)
        Input axis of the skewed gyro in the body frame; normalised here. All three
        components must be non-zero, so that any three of the four gyros span 3-D
        (needed by the DOS bank). Default: equal angles, ``[1, 1, 1]/sqrt(3)``.

    Returns
    -------
    ndarray, shape (4, 3)

    Examples
    --------
    >>> np.round(gyro_matrix()[3], 4)
    array([0.5774, 0.5774, 0.5774])
    """
    h4 = check_finite_array("skew_axis", skew_axis, shape=(3,))
    if h4.ndim != 1:
        raise ValueError(f"skew_axis must have shape (3,), got {h4.shape}")
    n = np.linalg.norm(h4)
    if n == 0.0 or np.min(np.abs(h4)) < 1e-3 * n:
        raise ValueError(
            "skew_axis must have three non-zero components (each >= 1e-3 of its norm), "
            f"got {h4.tolist()}"
        )
    return np.vstack([np.eye(3), h4 / n])


def gyro_measurements(
    t,
    w,
    *,
    drifts_deg_per_h=PAPER_DRIFTS_DEG_PER_H,
    noise_deg_per_h=PAPER_GYRO_NOISE_DEG_PER_H,
    skew_axis=SKEW_AXIS,
    faults=(),
    rng=None,
):
    """Gyro-assembly outputs ``w_g = H w + b + v_g + f_g`` (paper eq. (2)), rad/s.

    Parameters
    ----------
    t : array_like, shape (n,)
        Sample times, s.
    w : array_like, shape (n, 3)
        True body rate, rad/s.
    drifts_deg_per_h : array_like, shape (4,)
        Constant drifts ``b`` of gyros x, y, z and skew, deg/h.
    noise_deg_per_h : float
        White noise ``v_g``, 1 sigma per sample, deg/h, >= 0.
    skew_axis : array_like, shape (3,)
        See :func:`gyro_matrix`.
    faults : sequence of Fault
        Faults of sensor ``"gyro"`` (components 0-3: x, y, z, skew) are injected with
        :func:`xnavlab.core.faults.inject`; magnitudes in rad/s (rad/s^2 for ramps).
    rng : numpy.random.Generator or int, optional
        Source of the noise ``v_g`` (default seed 0). A ``"noise"`` fault draws its extra noise
        from a child stream spawned from it (``numpy.random.Generator.spawn``, which
        draws nothing from it), so ``v_g`` depends on the seed alone.

    Returns
    -------
    ndarray, shape (n, 4)

    Examples
    --------
    >>> t = np.arange(3.0)
    >>> wg = gyro_measurements(t, np.zeros((3, 3)), noise_deg_per_h=0.0)
    >>> np.round(wg[0] / DEG_PER_H, 6)
    array([ 50.,  40., -50.,  45.])
    """
    t = check_vector("t", t)  # each on its own first: a 0-d t was refused under w's name
    w = check_finite_array("w", w, shape=(3,))
    if w.ndim != 2:
        raise ValueError(f"w must have shape (n, 3), one rate per sample, got {w.shape}")
    if t.size != w.shape[0]:  # w is a well-formed series: the times are the ones to match it
        raise ValueError(f"t must hold one time per row of w ({w.shape[0]}), got {t.size}")
    check_increasing("t", t)  # a fault's onset and duration are read against t
    b = check_finite_array("drifts_deg_per_h", drifts_deg_per_h, shape=(4,)) * DEG_PER_H
    sigma = check_real("noise_deg_per_h", noise_deg_per_h, 0.0, MAX_DEG_PER_H) * DEG_PER_H
    H = gyro_matrix(skew_axis)
    faults = _own_faults(faults, "gyro", "gyro_measurements")
    rng = make_rng(rng)
    z = w @ H.T + b + rng.normal(0.0, 1.0, (t.size, 4)) * sigma  # paper eq. (2)
    return inject(t, z, faults, "gyro", rng=_fault_stream(rng, faults))  # + f_g


def _fault_stream(rng, faults):
    """The generator of the faults' own draws: a child of ``rng``, or ``rng`` if no fault draws.

    Only a ``"noise"`` fault draws (its extra noise). Its child comes from
    ``numpy.random.Generator.spawn``, which takes no draw from ``rng``: the sensor noise is
    the same with or without the fault, and the fault's noise independent of it (as the Mars
    runs' ``seed_after`` stream, which a Generator has no seed for). ``rng``'s seed sequence
    counts its children, so the runs of a batch drawn from one generator get one each.
    """
    if not any(f.kind == "noise" for f in faults):
        return rng  # nothing to draw: rng's seed sequence left as it was
    try:
        return rng.spawn(1)[0]
    except TypeError:  # a bit generator seeded without a seed sequence (legacy seeding)
        raise ValueError("rng must be a seed or a numpy Generator that can spawn a child stream "
                         "(numpy.random.default_rng(seed)) when a fault is of kind 'noise'") from None


def _own_faults(faults, sensor, func):
    """``faults`` as a list of Faults of ``sensor``: another sensor's fault was dropped in silence."""
    faults = check_faults("faults", faults)
    for i, f in enumerate(faults):
        if f.sensor != sensor:
            raise ValueError(f"faults[{i}] is a fault of the {f.sensor!r} sensor: {func} injects the "
                             f"{sensor!r} faults only (give each its sensor's function)")
    return faults


# --------------------------------------------------------------- star tracker


def star_tracker_measurements(t, q, *, noise_deg=PAPER_STAR_NOISE_DEG, faults=(), rng=None):
    """Star-tracker quaternions ``q_s = q (x) q_v + f_q``, renormalised (paper eq. (17)).

    ``q_v`` is the quaternion of a small rotation with independent N(0, sigma^2) angles
    about the three axes; the paper's fault rotation ``q_f`` is left at identity and
    faults enter through the additive ``f_q``, injected with :func:`xnavlab.core.faults.inject`
    (sensor ``"star_tracker"``, components 0-3: q1..q4, dimensionless; a ramp's
    magnitude is per second). The output is renormalised, as a star tracker reports
    unit quaternions.

    Parameters
    ----------
    t : array_like, shape (n,)
        Sample times, s.
    q : array_like, shape (n, 4)
        True attitude, scalar last.
    noise_deg : float
        Noise per axis, 1 sigma, deg, >= 0.
    faults : sequence of Fault
    rng : numpy.random.Generator or int, optional
        Source of the noise ``q_v`` (default seed 0). A ``"noise"`` fault draws its extra noise
        from a child stream spawned from it, as :func:`gyro_measurements`'s.

    Returns
    -------
    ndarray, shape (n, 4)

    Examples
    --------
    >>> from xnavlab.attitude.motion import DEFAULT_Q0
    >>> q = np.tile(DEFAULT_Q0, (2, 1))
    >>> bool(np.allclose(star_tracker_measurements([0.0, 1.0], q, noise_deg=0.0), q))
    True
    """
    t = check_vector("t", t)  # each on its own first: a 0-d t was refused under q's name
    q = check_quaternion("q", q)  # the true attitude: a zero or scaled one refused
    if q.ndim != 2:
        raise ValueError(f"q must have shape (n, 4), one quaternion per sample, got {q.shape}")
    if t.size != q.shape[0]:  # q is a well-formed series: the times are the ones to match it
        raise ValueError(f"t must hold one time per row of q ({q.shape[0]}), got {t.size}")
    check_increasing("t", t)  # a fault's onset and duration are read against t
    sigma = math.radians(check_real("noise_deg", noise_deg, 0.0, 180.0))
    faults = _own_faults(faults, "star_tracker", "star_tracker_measurements")
    rng = make_rng(rng)
    qv = quat_from_rotvec(rng.normal(0.0, 1.0, (t.size, 3)) * sigma)
    qs = quat_product(q, qv)  # paper eq. (17), q_f = identity
    qs = inject(t, qs, faults, "star_tracker", rng=_fault_stream(rng, faults))  # + f_q
    return quat_normalize(qs)


# --------------------------------------------------------- faults and samples


def make_fault(location, kind, magnitude, onset=50.0, duration=math.inf):
    """A :class:`xnavlab.core.faults.Fault` on one of the attitude sensors.

    Parameters
    ----------
    location : {"gyro_x", "gyro_y", "gyro_z", "gyro_skew", "star_tracker"}
        A star-tracker fault acts on the quaternion component q1.
    kind : {"step", "ramp", "spike", "stuck", "noise"}
    magnitude : float
        SI: rad/s for a gyro step (rad/s^2 for a ramp); dimensionless quaternion units
        for the star tracker (per second for a ramp).
    onset : float
        Start, s since the start of the run, in [0, inf) (a run refuses one at or past its end).
    duration : float
        Length, s (``math.inf``: permanent).

    Examples
    --------
    >>> f = make_fault("gyro_skew", "ramp", 0.1 * DEG_PER_H)
    >>> (f.sensor, f.component, f.kind)
    ('gyro', 3, 'ramp')
    """
    check_choice("location", location, LOCATIONS)
    check_choice("kind", kind, KINDS)
    check_real("onset", onset, 0.0)  # s since the start: the attitude runs begin at t = 0
    if location == "star_tracker":
        return Fault("star_tracker", kind, magnitude, onset, duration, 0)
    return Fault("gyro", kind, magnitude, onset, duration, LOCATIONS.index(location))


