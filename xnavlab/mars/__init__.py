"""The main paper's system: autonomous Mars navigation with XNAV, a UV sensor and a CNS.

Fan et al. 2016, the main paper: three subsystems, each with its own EKF, fused by a
federated filter; wavelet fault detection, isolation and reconfiguration.

Its modules sit in six subpackages, in the order of the flow from photons to a position to
a study (each subpackage's page has the table of its modules):

================================  =========================================================
subpackage                        what it holds
================================  =========================================================
:mod:`~xnavlab.mars.timing`       photons to a time of arrival: pulsars, photons, the TOA and
                                  its accuracy (chapters 0-2)
:mod:`~xnavlab.mars.models`       the orbit's and the sensors' models: dynamics, forces,
                                  process noise, stars, XNAV/UV/CNS measurements (chapters 3-5)
:mod:`~xnavlab.mars.kernel`       the compiled (numba) filter loop, one step per module
:mod:`~xnavlab.mars.navigation`   the federated run: a position and its accuracy, the
                                  scenario and its files, the run's figures (chapters 5-6)
:mod:`~xnavlab.mars.faults`       detection, isolation and re-admission on the run (chapters 8-9)
:mod:`~xnavlab.mars.studies`      Monte Carlo studies on the run: trials, ROC, detector maps,
                                  campaigns (chapters 9, 13)
================================  =========================================================

timing -> models -> kernel -> navigation -> faults -> studies: a module imports from its own
subpackage and those before it, with these exceptions: ``timing``'s ``toa``, ``fold_toa`` and
``timing_terms`` use ``models.dynamics`` (the orbit a TOA is computed along), ``timing_terms``
runs a ``navigation`` scenario (the clock's effect on the run), and ``navigation``'s
``headline``, ``plots``, ``schematics`` and ``scenario_files`` use ``faults.fault_tolerance``
(the fault runs they show, its detectors' names). No import cycle (``tests/test_layers.py``).
The flat names the modules had before (``xnavlab.mars.<module>``) still import, with a
``DeprecationWarning`` (:data:`xnavlab.compat.RENAMED`).

It imports the core (:mod:`xnavlab.core`) and no other system.
"""

__all__: list[str] = []
