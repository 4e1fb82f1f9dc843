"""Jin et al. 2011: pseudolite/INS integrated navigation and T-S fuzzy parity equations.

=====================  ===================================================================
module                 what it models
=====================  ===================================================================
``ins``                the 10-state ENU INS error model and the paper's flight
``pseudolites``        WGS-84 pseudolite geometry and the measurement matrix
``parity``             fuzzy parity-space fault detection and identification (a package)
=====================  ===================================================================

It imports the core only (chapter 12).
"""

__all__: list[str] = []
