"""The input checks that the attitude system's modules share: the light per-sample check of
the on-board loops, quaternions (non-zero, unit), batches of covariances, and the memory and
time budget of a run or a batch of runs (:data:`BYTES_PER_SAMPLE`, :data:`MAX_SAMPLES`,
:data:`MAX_RUN_SAMPLES`).

Plumbing of :mod:`xnavlab.attitude`; not part of the public API.
"""

from __future__ import annotations

import math

import numpy as np

from xnavlab.core.quaternions import UNIT_TOL
from xnavlab.core.validate import check_covariance, check_finite_array

__all__ = ["check_sample", "check_quaternion", "check_covariances", "BYTES_PER_SAMPLE",
           "MAX_SAMPLES", "MAX_RUN_SAMPLES", "SECONDS_PER_RUN_SAMPLE", "CHUNK_SAMPLES"]

#: Peak memory of a run a sample, bytes, with DOS (truth, sensors, the four filters'
#: estimates and drift covariances, residuals, flags): measured 1,113-1,178 bytes (peak
#: RSS over the import, 2026-11-29) for one run of 2e4 and 1e5 samples and batches of
#: 160,000-480,000 run-samples.
BYTES_PER_SAMPLE = 1200
#: The most samples one run holds: 1.6e6 samples take about 2 GB (the project's budget, as
#: ``xnavlab.mars.timing._checks.MAX_PHOTONS``); 1e7 samples (duration 1e6 s at 0.1 s) asked
#: for about 12 GB. At 0.1 s this is 44 hours of flight, about 21 s to simulate.
MAX_SAMPLES = 1_600_000
#: Wall time of a batch a run-sample (runs times samples a run), s: 7.6-15 us measured on a
#: 2-core machine (2026-11-29), taken as 13 us.
SECONDS_PER_RUN_SAMPLE = 13e-6
#: The most run-samples a batch (:func:`xnavlab.attitude.isolation_monte_carlo`,
#: :func:`xnavlab.attitude.seeded_outcomes`) takes: 4e7, about 9 minutes at
#: :data:`SECONDS_PER_RUN_SAMPLE` (the 10,000 runs of 100 s a reproduction may ask take 1e7,
#: about 2 minutes). A batch is diagnosed in chunks of :data:`CHUNK_SAMPLES`, so its memory
#: does not grow with it.
MAX_RUN_SAMPLES = 40_000_000
#: Run-samples diagnosed at once in a batch: about 0.5 GB at :data:`BYTES_PER_SAMPLE`.
CHUNK_SAMPLES = 400_000


def check_quaternion(name, q, unit=True):
    """Quaternions ``q`` (..., 4), finite, none zero (named ``name``, as the user typed it), and
    with ``unit`` of norm 1 to :data:`xnavlab.core.quaternions.UNIT_TOL`: an attitude is a unit
    quaternion, and a scaled one is refused rather than rescaled in silence (the additive EKF,
    the differentiation and the sensors would carry the scale into their results)."""
    q = check_finite_array(name, q, shape=(4,))
    norm = np.linalg.norm(q, axis=-1)
    if np.any(norm == 0.0):
        raise ValueError(f"{name} must have a non-zero norm, got a zero quaternion")
    if unit and np.any(np.abs(norm - 1.0) > UNIT_TOL):
        worst = float(np.ravel(norm)[int(np.argmax(np.ravel(np.abs(norm - 1.0))))])
        raise ValueError(f"{name} must be a unit quaternion (norm 1 to {UNIT_TOL:g}), got norm {worst:.6g}")
    return q


def check_covariances(name, value, n, definite=False, rtol=1e-8):
    """``value`` as (..., n, n) symmetric positive (semi-)definite matrices
    (:func:`xnavlab.core.validate.check_covariance`, one matrix or a batch)."""
    arr = check_finite_array(name, value, shape=(n, n))
    if arr.ndim == 2:
        return check_covariance(name, arr, n, definite=definite, rtol=rtol)
    if arr.ndim < 2:
        raise ValueError(f"{name} must have shape (..., {n}, {n}), got shape {arr.shape}")
    scale = np.max(np.abs(arr), axis=(-2, -1))
    if np.any(np.max(np.abs(arr - np.swapaxes(arr, -1, -2)), axis=(-2, -1)) > rtol * scale):
        raise ValueError(f"{name} must be symmetric (to {rtol:g} of its largest entry)")
    low = np.linalg.eigvalsh(0.5 * (arr + np.swapaxes(arr, -1, -2)))[..., 0]
    if definite and not np.all(low > 0.0):
        raise ValueError(f"{name} must be positive definite, got smallest eigenvalue "
                         f"{float(np.min(low)):.3g}")
    if np.any(low < -rtol * scale):
        raise ValueError(f"{name} must be positive semi-definite, got smallest eigenvalue "
                         f"{float(np.min(low)):.3g}")
    return arr


def check_sample(name, value, n, unit=False):
    """One sensor sample as ``n`` finite floats: the light check of the on-board loops.

    Cheaper than :func:`xnavlab.core.validate.check_finite_array` (one shape test, one
    finiteness test), because :class:`xnavlab.attitude.ekf.AttitudeEKF` and the monitors of
    :mod:`xnavlab.attitude.monitors` call it at every sample.

    Parameters
    ----------
    name : str
        Name of the argument, for the error message.
    value : array_like, shape (n,)
        One sample: gyro rates (rad/s) or a star-tracker quaternion.
    n : int
        Expected length.
    unit : bool
        A quaternion measurement: its norm must be 1 to :data:`xnavlab.core.quaternions.UNIT_TOL`
        (one norm per call; a zero or scaled one is refused, not rescaled, as
        :func:`check_quaternion`).

    Returns
    -------
    ndarray, shape (n,)

    Raises
    ------
    ValueError
        If ``value`` is not ``n`` finite numbers.

    Examples
    --------
    >>> check_sample("omega_g", [0.0, 0.1, 0.2], 3).shape
    (3,)
    """
    if isinstance(value, np.ma.MaskedArray) and np.ma.is_masked(value):  # review 35m (5) 1
        raise ValueError(f"{name} has masked entries (no number to use: fill or drop them)")
    arr = np.asarray(value)
    if arr.dtype.kind not in "fiu":  # complex (never cut to its real part), text, flags
        raise ValueError(f"{name} must be {n} finite real numbers, got {value!r}")
    arr = arr.astype(float, copy=False)
    if arr.shape != (n,) or not np.isfinite(arr).all():
        raise ValueError(f"{name} must be {n} finite numbers, got {value!r}")
    if unit:
        norm = math.sqrt(float(arr @ arr))
        if norm == 0.0:
            raise ValueError(f"{name} must have a non-zero norm, got a zero quaternion")
        if abs(norm - 1.0) > UNIT_TOL:
            raise ValueError(f"{name} must be a unit quaternion (norm 1 to {UNIT_TOL:g}), got "
                             f"norm {norm:.6g}")
    return arr
