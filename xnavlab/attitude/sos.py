"""The single-observer scheme (SOS, the paper's): residuals of one EKF plus the gyro parity.

``r_i = |b_i_hat - b_i_ref|`` for the orthogonal gyros (paper eq. (35)) from the one
filter's drift estimates (:mod:`xnavlab.attitude.ekf`), and the hardware-parity residual
of the skewed gyro ``r4 = |w_g4 - h4^T w_g1 - p_ref|`` (eqs. (36)-(37), reconstructed from
the paper's count of 3 multiplications, 4 additions and 1 absolute value). The references
are learned on board from a fault-free calibration window; thresholds are ``n_sigma``
times each residual's predicted standard deviation (:mod:`xnavlab.attitude.simulation`).
The fault table and decision rule (paper Tables 1-2, reconstructed) are
:data:`xnavlab.attitude.diagnosis.SOS_TABLE` and :func:`xnavlab.attitude.diagnosis.sos_decide`.

Rates in rad/s.
"""

from __future__ import annotations

import numpy as np

from xnavlab.attitude.sensors import SKEW_AXIS, gyro_matrix
from xnavlab.core.validate import check_finite_array

__all__ = [
    "gyro_parity",
    "sos_residuals",
]


def gyro_parity(omega_g, skew_axis=SKEW_AXIS):
    """Hardware parity of the gyro assembly ``p = w_g4 - h4^T w_g1``, rad/s.

    Free of the body rate (``[-h4^T 1] H = 0``), so ``p = b4 - h4^T b1 + noise +
    f4 - h4^T f1``: it moves for a fault on any gyro and never for the star tracker
    (paper eq. (36), reconstructed).

    Parameters
    ----------
    omega_g : array_like, shape (..., 4)
        Gyro-assembly output, rad/s.
    skew_axis : array_like, shape (3,)

    Returns
    -------
    ndarray, shape (...)

    Examples
    --------
    >>> H = gyro_matrix()
    >>> abs(float(gyro_parity(H @ np.array([0.1, -0.2, 0.3])))) < 1e-15
    True
    """
    wg = check_finite_array("omega_g", omega_g, shape=(4,))
    h4 = gyro_matrix(skew_axis)[3]
    return wg[..., 3] - wg[..., :3] @ h4  # 3 multiplications, 3 additions


def sos_residuals(drift_hat, omega_g, drift_ref, parity_ref, skew_axis=SKEW_AXIS):
    """SOS residuals ``r1..r4`` (paper eqs. (35)-(37), reconstructed), rad/s.

    ``r_i = |b_i_hat - b_i_ref|`` (i = 1, 2, 3) from the one filter's drift estimates, and
    ``r4 = |w_g4 - h4^T w_g1 - p_ref|``: 3 multiplications, 4 additions, 1 absolute value,
    the paper's operation count. With ``drift_ref = 0`` the first three are the paper's
    literal ``|b_i_hat|``.

    Parameters
    ----------
    drift_hat : array_like, shape (..., 3)
        Drift estimates of the orthogonal gyros, rad/s.
    omega_g : array_like, shape (..., 4)
        Gyro outputs, rad/s.
    drift_ref : array_like, shape (..., 3)
        Fault-free drift references, rad/s.
    parity_ref : float or array_like, shape (...)
        Fault-free parity ``b4 - h4^T b1``, rad/s.
    skew_axis : array_like, shape (3,)

    Returns
    -------
    ndarray, shape (..., 4)

    Examples
    --------
    >>> r = sos_residuals([1.0, 2.0, 3.0], [0.0, 0.0, 0.0, 1.0], [1.0, 1.0, 1.0], 0.0)
    >>> r.tolist()
    [0.0, 1.0, 2.0, 1.0]
    """
    b = check_finite_array("drift_hat", drift_hat, shape=(3,))
    ref = check_finite_array("drift_ref", drift_ref, shape=(3,))
    pref = check_finite_array("parity_ref", parity_ref)
    p = gyro_parity(omega_g, skew_axis)
    lead = b.shape[:-1]  # the runs' axes "...": each later argument's must agree with those before
    for name, shape in (("omega_g", p.shape), ("drift_ref", ref.shape[:-1]), ("parity_ref", pref.shape)):
        try:
            both = np.broadcast_shapes(lead, shape)
        except ValueError:
            both = None
        if both != lead and (name == "parity_ref" or both is None):
            raise ValueError(f"{name} must have leading axes (...) that broadcast to those of the "
                             f"arguments before it, {lead}, got {shape}")
        lead = both
    r13 = np.abs(b - ref)  # paper eq. (35)
    r4 = np.abs(p - pref)  # paper eq. (37)
    return np.concatenate([np.broadcast_to(r13, lead + (3,)), np.broadcast_to(r4, lead)[..., None]], axis=-1)
