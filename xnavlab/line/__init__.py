"""XNAV on a line: the book's on-ramp (chapter 0), one or two pulsars and a Kalman filter.

A spacecraft moves on the line towards a pulsar (or in the plane of two pulsars); photons
folded over a window give a TOA, the TOA times ``c`` gives the range along the line of sight,
and a constant-velocity Kalman filter (:mod:`xnavlab.core.filters`) tracks the spacecraft.

=====================  ===================================================================
module                 what it models
=====================  ===================================================================
``measure``            one folded window of photons turned into a range, and its sigma
``track``              the constant-velocity model, the filter fed by folded TOAs, and
                       the figure behind chapter 0's slider
=====================  ===================================================================

It imports the core and the book's pulsar catalogue and photon model,
:mod:`xnavlab.mars.timing.pulsars` (the same pulsars, photons and TOA estimator as chapter 1).
"""

__all__: list[str] = []
