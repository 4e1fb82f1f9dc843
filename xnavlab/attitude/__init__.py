"""Li, Niu et al. 2019: attitude-sensor fault diagnosis with one Kalman filter (SOS vs DOS).

Li, Niu, Shao & Shen (Li, Niu et al. 2019) diagnose single faults of a gyro assembly (three
orthogonal gyros and one skewed gyro) and a star tracker with *one* extended Kalman filter
(the simplified observer scheme, SOS), where the earlier dedicated-observer scheme (DOS,
their ref. [21]) ran four. Most of the paper's equations were lost from our copy; the
modules rebuild them in the standard forms of Lefferts, Markley & Shuster (1982) and
Crassidis & Junkins (2012, ch. 7), keep the paper's equation numbers in the comments and
state every choice made where the paper is silent (chapter 11). The package imports the
core only.

=====================  ===================================================================
module                 what it models
=====================  ===================================================================
``motion``             the true attitude motion: orbital pitch rate plus a control wobble
``sensors``            gyro assembly ``w_g = H w + b + v_g + f_g`` (3+1, skewed), star
                       tracker ``q_s = q (x) q_v + f_q``, fault locations and sizes
``ekf``                the 7-state additive-quaternion EKF ``[q; b]``: pure steps and
                       :class:`~.ekf.AttitudeEKF`
``sos``                SOS residuals: drift estimates and the skewed-gyro hardware parity
``dos``                the DOS bank: gyro groups, rate matrices, residuals
``differentiation``    quaternion differentiation (ref. [22]): star-tracker rate vs gyros
``diagnosis``          fault tables, the decision rules of SOS, DOS and ref. [22], and the
                       shared threshold logic (:func:`~.diagnosis.diagnose`)
``simulation``         :class:`~.simulation.SimConfig`, :func:`~.simulation.simulate` (one run)
                       and the batched building blocks
``monitors``           SOS and DOS on board, one sample at a time, and their timing
``montecarlo``         isolation statistics over fault location, kind and size; per-seed outcomes
``plots``              the chapter's figures
=====================  ===================================================================

A module imports only those above it in this table (and :mod:`xnavlab.core`). The names
listed in ``__all__`` below are re-exported here: ``from xnavlab import attitude as att``
then ``att.simulate(...)``. A few building blocks are public in their own module only:
``simulation.make_config``, ``simulation.simulate_sensors`` and
``simulation.diagnose_batch``. The plumbing the modules share (the per-sample input check,
the EKF steps without checks, the filter bank compiled by numba for the simulations) lives in
the private modules ``_checks``, ``_ekf_steps`` and ``_bank_kernel``.

Units are SI inside (rad, rad/s, s); names say otherwise (``drifts_deg_per_h``).
"""

from xnavlab.attitude.diagnosis import (
    DOS_TABLE,
    SOS_TABLE,
    VERDICTS,
    Diagnosis,
    diagnose,
    dos_decide,
    qdiff_decide,
    sos_decide,
)
from xnavlab.attitude.differentiation import qdiff_fault_estimates, quaternion_rate
from xnavlab.attitude.dos import DOS_GROUPS, dos_rate_matrices, dos_residuals
from xnavlab.attitude.ekf import MAX_RATE, AttitudeEKF, ekf_init, ekf_predict, ekf_update
from xnavlab.attitude.monitors import DOSMonitor, SOSMonitor, time_sos_dos
from xnavlab.attitude.montecarlo import isolation_monte_carlo, isolation_table, seeded_outcomes
from xnavlab.attitude.motion import DEFAULT_Q0, truth_motion, truth_rate
from xnavlab.attitude.plots import LOCATION_NAMES, location_name, plot_fault_case, plot_residuals
from xnavlab.attitude.sensors import (
    DEFAULT_MAGNITUDES,
    DEG_PER_H,
    LOCATIONS,
    MAX_DEG_PER_H,
    PAPER_DRIFTS_DEG_PER_H,
    PAPER_GYRO_NOISE_DEG_PER_H,
    PAPER_STAR_NOISE_DEG,
    SKEW_AXIS,
    gyro_matrix,
    gyro_measurements,
    make_fault,
    star_tracker_measurements,
)
from xnavlab.attitude.simulation import AttitudeRun, SimConfig, simulate
from xnavlab.attitude.sos import gyro_parity, sos_residuals

__all__ = [
    # motion
    "DEFAULT_Q0",
    "truth_rate",
    "truth_motion",
    # sensors
    "DEG_PER_H",
    "MAX_DEG_PER_H",
    "PAPER_DRIFTS_DEG_PER_H",
    "PAPER_GYRO_NOISE_DEG_PER_H",
    "PAPER_STAR_NOISE_DEG",
    "SKEW_AXIS",
    "LOCATIONS",
    "DEFAULT_MAGNITUDES",
    "gyro_matrix",
    "gyro_measurements",
    "star_tracker_measurements",
    "make_fault",
    # ekf
    "MAX_RATE",
    "ekf_init",
    "ekf_predict",
    "ekf_update",
    "AttitudeEKF",
    # sos
    "gyro_parity",
    "sos_residuals",
    # dos
    "DOS_GROUPS",
    "dos_rate_matrices",
    "dos_residuals",
    # differentiation
    "quaternion_rate",
    "qdiff_fault_estimates",
    # diagnosis
    "VERDICTS",
    "SOS_TABLE",
    "DOS_TABLE",
    "sos_decide",
    "dos_decide",
    "qdiff_decide",
    "Diagnosis",
    "diagnose",
    # simulation
    "SimConfig",
    "AttitudeRun",
    "simulate",
    # monitors
    "SOSMonitor",
    "DOSMonitor",
    "time_sos_dos",
    # montecarlo
    "isolation_monte_carlo",
    "isolation_table",
    "seeded_outcomes",
    # plots
    "LOCATION_NAMES",
    "location_name",
    "plot_residuals",
    "plot_fault_case",
]
