"""The dedicated-observer scheme (DOS, the paper's ref. [21]): a bank of four EKFs.

Filter ``j`` is fed by the three gyros other than gyro ``j`` (:data:`DOS_GROUPS`), reading
the body rate as ``T_j w_g[group_j]`` (:func:`dos_rate_matrices`); its residual is the
distance of its equivalent drift estimate from a fault-free reference
(:func:`dos_residuals`). A fault of gyro ``j`` moves every residual but ``j``'s, a
star-tracker fault moves all four (:data:`xnavlab.attitude.diagnosis.DOS_TABLE`,
:func:`xnavlab.attitude.diagnosis.dos_decide`). The bank itself runs in
:mod:`xnavlab.attitude.simulation` (batched) and :class:`xnavlab.attitude.monitors.DOSMonitor`
(one sample at a time).

Rates in rad/s.
"""

from __future__ import annotations

import numpy as np

from xnavlab.attitude.sensors import SKEW_AXIS, gyro_matrix
from xnavlab.core.validate import check_finite_array

__all__ = [
    "DOS_GROUPS",
    "dos_rate_matrices",
    "dos_residuals",
]

#: DOS gyro groups: filter ``j`` uses the three gyros other than gyro ``j``.
DOS_GROUPS = ((1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2))


def dos_rate_matrices(skew_axis=SKEW_AXIS):
    """Rate reconstruction of each DOS filter: ``T_j = H[group_j]^-1``, shape (4, 3, 3).

    Filter ``j`` reads the body rate as ``T_j w_g[group_j]`` from the three gyros of
    :data:`DOS_GROUPS` ``[j]`` (all but gyro ``j``); its drift states are
    ``T_j b[group_j]``.

    Examples
    --------
    >>> np.allclose(dos_rate_matrices()[3], np.eye(3))
    True
    """
    H = gyro_matrix(skew_axis)
    return np.stack([np.linalg.inv(H[list(g)]) for g in DOS_GROUPS])


def dos_residuals(drift_hat, drift_ref):
    """DOS residuals: ``R_j = |d_j_hat - d_j_ref|`` (Euclidean norm), rad/s.

    Parameters
    ----------
    drift_hat : array_like, shape (..., 4, 3)
        Equivalent body-frame drift estimates of the four filters, rad/s.
    drift_ref : array_like, shape (..., 4, 3)
        Their fault-free references, rad/s.

    Returns
    -------
    ndarray, shape (..., 4)

    Examples
    --------
    >>> dos_residuals(np.ones((4, 3)), np.zeros((4, 3))).round(3).tolist()
    [1.732, 1.732, 1.732, 1.732]
    """
    d = check_finite_array("drift_hat", drift_hat, shape=(4, 3))
    ref = check_finite_array("drift_ref", drift_ref, shape=(4, 3))
    return np.linalg.norm(d - ref, axis=-1)
