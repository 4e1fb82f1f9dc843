"""The light per-sample input check that the attitude system's on-board loops share.

Plumbing of :mod:`xnavlab.attitude` (imported by :mod:`xnavlab.attitude.ekf` and
:mod:`xnavlab.attitude.monitors` only); not part of the public API.
"""

from __future__ import annotations

import numpy as np

__all__ = ["check_sample"]


def check_sample(name, value, n):
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
    arr = np.asarray(value)
    if arr.dtype.kind not in "fiu":  # complex (never cut to its real part), text, flags
        raise ValueError(f"{name} must be {n} finite real numbers, got {value!r}")
    arr = arr.astype(float, copy=False)
    if arr.shape != (n,) or not np.isfinite(arr).all():
        raise ValueError(f"{name} must be {n} finite numbers, got {value!r}")
    return arr
