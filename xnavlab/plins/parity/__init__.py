"""Fuzzy parity equations for pseudolite/INS fault diagnosis (Jin et al. 2011, chapter 12).

A reconstruction of Jin, Song, Qiu & Wang (Jin et al. 2011), whose equations were lost in
extraction; the standard forms used are those of Chow & Willsky (1984) for parity
relations over a data window, Gertler (1998) for structured ("fully decoupled")
residuals, Song & Zhang (2002, 2003) for the parity-plus-Kalman-filter fault
identification the paper builds on, and Takagi & Sugeno (1985) for the fuzzy model.

=====================  ===================================================================
module                 what it models
=====================  ===================================================================
``fuzzy``              the T-S fuzzy model: premises, operating points, triangular
                       memberships, local linear models (eqs. 12-14)
``space``              the fully decoupled parity space: ``H_0``, ``H_w``, parity bases,
                       the identifiability constraints, blended global residuals and
                       their threshold (eqs. 15-22, 25-26)
``identification``     fault models, onset search, the random-walk Kalman filter that
                       identifies the fault parameters (eqs. 23-24, 27-28)
``diagnosis``          the whole flight (:func:`~.diagnosis.diagnose_flight`), the chi-square
                       comparison detector, detection rates by fault size
``plots``              the chapter's figure
=====================  ===================================================================

A module imports only those above it in this table (and :mod:`xnavlab.core`,
:mod:`xnavlab.plins.ins`, :mod:`xnavlab.plins.pseudolites`). The names listed in
``__all__`` below are re-exported here: ``from xnavlab.plins import parity`` then
``parity.diagnose_flight(...)``. ``diagnosis.flight_design`` (the cached T-S parity
design of a flight) is public in its own module only.

Two findings shape the implementation (the chapter explains both): the parity space is
the *numerical* left null space (see ``space``), and a fault constant inside the
window is not identifiable, so faults are identified from the windows that straddle
their onset (see ``identification``).
"""

from xnavlab.plins.parity.diagnosis import (
    Chi2Monitor,
    Diagnosis,
    chi2_monitor,
    compare_detectors,
    diagnose_flight,
    first_alarm,
)
from xnavlab.plins.parity.fuzzy import (
    PREMISES,
    LocalModel,
    local_models,
    memberships,
    operating_points,
    partition_memberships,
    premises,
    triangular,
)
from xnavlab.plins.parity.identification import (
    MODELS,
    FaultIdentifier,
    Identification,
    estimate_onset,
    fault_signature,
    identify_fault,
    kf_identify,
    rw_predict,
    rw_update,
)
from xnavlab.plins.parity.plots import plot_diagnosis, plot_step_diagnosis
from xnavlab.plins.parity.space import (
    TYPICAL_STATE_STD,
    Identifiability,
    align_bases,
    blended_bases,
    check_identifiability,
    parity_basis,
    parity_residuals,
    residual_threshold,
    stacked_matrices,
)

__all__ = [
    # fuzzy
    "PREMISES",
    "premises",
    "operating_points",
    "triangular",
    "partition_memberships",
    "memberships",
    "LocalModel",
    "local_models",
    # space
    "TYPICAL_STATE_STD",
    "stacked_matrices",
    "parity_basis",
    "align_bases",
    "Identifiability",
    "check_identifiability",
    "blended_bases",
    "parity_residuals",
    "residual_threshold",
    # identification
    "MODELS",
    "fault_signature",
    "estimate_onset",
    "rw_predict",
    "rw_update",
    "FaultIdentifier",
    "kf_identify",
    "Identification",
    "identify_fault",
    # diagnosis
    "first_alarm",
    "Chi2Monitor",
    "chi2_monitor",
    "Diagnosis",
    "diagnose_flight",
    "compare_detectors",
    # plots
    "plot_diagnosis",
    "plot_step_diagnosis",
]
