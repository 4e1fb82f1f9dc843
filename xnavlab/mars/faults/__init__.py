"""Fault detection, isolation and re-admission on the federated run (chapters 8-9).

The fault schedules, the wavelet, chi-square and combined detectors on the run, the
detector's state in the compiled loop and the XNAV innovations it watches.

=====================  ===================================================================
module                 what it models
=====================  ===================================================================
``fault_tolerance``    fault schedules, detection, isolation, re-admission (chapters 8-9)
``schedules``          fault schedules checked against a run, and a run's faults scored
``watch``              the combined detector's state in the compiled loop, its alarms
``innovations``        XNAV innovations against the master, the XNAV innovation wavelet
``_checks``            plumbing (not public API): the run's options a detector or run does
                       not use, refused
=====================  ===================================================================

The modules are imported by name (``from xnavlab.mars.faults import fault_tolerance``);
importing the subpackage imports none of them.
"""

__all__: list[str] = []
