"""The spacecraft's true attitude motion (the paper gives none; our choice, stated here).

An Earth-pointing spacecraft in a 100-minute circular orbit turns at the orbital rate about
the negative body y axis (pitch rate -0.06 deg/s), and its attitude control adds a slow
three-axis wobble (:func:`truth_rate`). :func:`truth_motion` holds the rate over each
sample (10 Hz by default) and propagates the quaternion with the exact discrete kinematics
of paper eq. (12), so the filter's model is exact for the truth apart from sensor errors.

Quaternions are reference-to-body, scalar last (:mod:`xnavlab.core.quaternions`); rates in
rad/s, times in s; a name says otherwise (``omega_orbit_deg_s``).
"""

from __future__ import annotations

import math

import numpy as np

from xnavlab.attitude._checks import MAX_SAMPLES, check_quaternion
from xnavlab.core.quaternions import kinematics_matrix, quat_from_rotvec, quat_normalize
from xnavlab.core.validate import check_finite_array, check_int, check_real

__all__ = [
    "DEFAULT_Q0",
    "truth_rate",
    "truth_motion",
]

#: Our choice of initial attitude: rotation vector (0.3, -0.5, 0.8) rad.
DEFAULT_Q0 = quat_from_rotvec([0.3, -0.5, 0.8])


def truth_rate(t, *, omega_orbit_deg_s=0.06, wobble_deg_s=0.01, wobble_period=300.0):
    """Body angular rate of our truth motion (the paper does not give one), rad/s.

    An Earth-pointing spacecraft in a ~100-minute circular orbit turns at the orbital
    rate about the negative body y axis; the attitude control adds a slow three-axis
    wobble: ``w(t) = [a s(t), -w_o + a s(t + P/3), a s(t + 2P/3)]`` with
    ``s(t) = sin(2 pi t / P)``.

    Parameters
    ----------
    t : array_like, shape (n,)
        Time, s.
    omega_orbit_deg_s : float
        Orbital (pitch) rate ``w_o``, deg/s, >= 0. Default 0.06 (a 100-min orbit).
    wobble_deg_s : float
        Wobble amplitude ``a``, deg/s, >= 0.
    wobble_period : float
        Wobble period ``P``, s, >= 1e-3 (a subnormal one overflowed ``t / P``).

    Returns
    -------
    ndarray, shape (n, 3)

    Examples
    --------
    >>> np.round(np.degrees(truth_rate([0.0])), 4)
    array([[ 0.    , -0.0513, -0.0087]])
    """
    t = check_finite_array("t", t)
    wo = math.radians(check_real("omega_orbit_deg_s", omega_orbit_deg_s, 0.0, 10.0))
    a = math.radians(check_real("wobble_deg_s", wobble_deg_s, 0.0, 10.0))
    period = check_real("wobble_period", wobble_period, 1e-3)
    ph = 2.0 * math.pi * t[..., None] / period + np.array([0.0, 2.0, 4.0]) * math.pi / 3.0
    w = a * np.sin(ph)
    w[..., 1] -= wo
    return w


def truth_motion(n, dt, *, q0=DEFAULT_Q0, **motion):
    """Sample times, held body rates and true attitude of :func:`truth_rate`.

    The rate ``w[k] = truth_rate(t_k + dt/2)`` is held over ``[t_k, t_k + dt]`` and the
    attitude propagated with the exact discrete kinematics (paper eq. (12)), so the
    filter's model is exact for the truth apart from the sensor errors.

    Parameters
    ----------
    n : int
        Number of samples, in [2, 1.6e6] (a loop step each: the most a
        :class:`~xnavlab.attitude.simulation.SimConfig` allows, about 2 GB of a run).
    dt : float
        Sample interval, s, in (0, 10].
    q0 : array_like, shape (4,)
        Attitude at t = 0 (reference-to-body, scalar last); normalised.
    **motion
        Passed to :func:`truth_rate` (``omega_orbit_deg_s``, ``wobble_deg_s``,
        ``wobble_period``; another keyword is refused).

    Returns
    -------
    t : ndarray, shape (n,)
    w : ndarray, shape (n, 3)
        Body rate held over each sample interval, rad/s.
    q : ndarray, shape (n, 4)

    Examples
    --------
    >>> t, w, q = truth_motion(11, 0.1)
    >>> t[-1], bool(np.allclose(np.linalg.norm(q, axis=1), 1.0))
    (1.0, True)
    """
    n = check_int("n", n, 2, MAX_SAMPLES)
    dt = check_real("dt", dt, 0.0, 10.0, lo_open=True)
    q = quat_normalize(check_quaternion("q0", q0, unit=False))  # documented: normalised; zero refused
    if q.ndim != 1:  # a stack of quaternions was numpy's broadcast error
        raise ValueError(f"q0 must have shape (4,) (one quaternion), got shape {q.shape}")
    valid = ("omega_orbit_deg_s", "wobble_deg_s", "wobble_period")  # truth_rate's settings
    for key, value in motion.items():
        if key not in valid:  # a misspelt or repeated keyword was a TypeError from truth_rate
            raise ValueError(f"{key}={value!r:.60} is not a setting of truth_rate "
                             f"(they are {', '.join(valid)})")
    t = np.arange(n) * dt
    w = truth_rate(t + 0.5 * dt, **motion)
    phi = kinematics_matrix(w, dt)  # paper eq. (12) for every interval
    out = np.empty((n, 4))
    out[0] = q
    for k in range(n - 1):
        out[k + 1] = phi[k] @ out[k]
    return t, w, out
