"""Companion paper 003: attitude-sensor fault diagnosis with one Kalman filter (SOS vs DOS).

Gyro assembly (3+1, skewed), star tracker, the 7-state EKF, the single-observer scheme's
residuals and decision table, the dedicated-observer bank, quaternion differentiation,
Monte Carlo and the chapter's figures (chapter 11). It imports the core only.
Every public name of the submodules is re-exported here: ``from xnavlab import attitude``.
"""

from xnavlab.attitude.legacy import *  # noqa: F403
from xnavlab.attitude.legacy import __all__ as _legacy_all

__all__ = [*_legacy_all]
