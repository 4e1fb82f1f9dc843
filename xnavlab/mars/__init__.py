"""The main paper's system: autonomous Mars navigation with XNAV, a UV sensor and a CNS.

Fan et al. 2016, the main paper: three subsystems, each with its own EKF, fused by a
federated filter; wavelet fault detection, isolation and reconfiguration.

=====================  ===================================================================
module                 what it models
=====================  ===================================================================
``pulsars``            pulsar catalogue, timing model, photons, TOA accuracy (chapter 1)
``xray_pulsars``       the X-ray side of navigation pulsars: flux, pulsed fraction, width
``pulsar_specs``       a scenario's pulsars by name, timing model (``.par``) or table
``timing_bound``       the Poisson Cramer-Rao bound of the TOA, the maximum-likelihood TOA
                       that reaches it, XNAV noise at the bound (chapter 1)
``toa``                the time-transfer (TOA) equation and its gradient (chapter 2)
``fold_toa``           the TOA of a fold: photons time-transferred along the a-priori orbit,
                       the time tag, the instantaneous model's error (chapter 2)
``pint_bridge``        PINT offline as a witness: its delays for a spacecraft, shipped
                       Fermi photons and NANOGrav residuals (chapters 1-2)
``photon_fix``         a held-out fix along the line to J0030+0451 from PINT's Fermi
                       photons: the geocentre as the spacecraft (chapter 1, real photons)
``photon_error``       that fix's error bar against exposure and chapter 1's formula,
                       checked over random splits of the months
``photon_plots``       chapter 1's ranging-accuracy bars; the figures of the fix: slider,
                       recovery, cycle ambiguity, exposure
``timing_terms``       what the paper's TOA equation leaves out: exact vs paper Shapiro,
                       the planets' Shapiro, the on-board clock against TDB (chapter 2)
``dynamics``           Mars-orbit dynamics, truth propagator, transition matrix (chapter 3)
``force_models``       the truth's and the filter's force models apart: Mars's field
                       (MRO95A), the Sun and planets, SRP; q_acc from their difference
``model_noise``        the process noise a filter needs for what its model leaves out
``stars``              the bright-star table and the CNS star choice (chapter 4)
``sensors``            XNAV, UV and CNS measurement models (chapters 4-5)
``optics``             the optical sensors as instruments: range from the apparent radius,
                       Mars's oblate limb, correlated horizon errors (chapters 4-6)
``scenarios``          the paper's 30-day scenario and the federated run (chapters 5-6)
``unused_inputs``      scenario settings another setting makes unused, runs left empty
``consistency``        run-averaged NEES and NIS against chi-square (chapters 5, 13)
``linearisation``      the EKF against the UKF on one UV run: what linearising costs (ch. 5)
``time_update``        the filters' time update: RK4 with the paper's force model, the
                       transition matrix, the process noise (chapter 5)
``scenario_files``     every scenario setting in a TOML file, with units (``run mars
                       --scenario``, ``python -m xnavlab scenario --dump``)
``model_mismatch``     matched vs mismatched truth and filter: accuracy and NEES
                       (chapters 3, 5, 6)
``headline``           the headline accuracies as means over noise seeds, with intervals
``kernels``            the compiled (numba) filter loop behind ``scenarios.run``, with the
                       combined detector inside it
``kernel_inputs``      the kernel's arguments in six named containers, with units
``compile_notice``     the one-line notice before the kernel's first compile
``series``             the compiled draws of the UV and CNS measurement series
``fault_tolerance``    fault schedules, detection, isolation, re-admission (chapters 8-9)
``schedules``          fault schedules checked against a run, and a run's faults scored
``watch``              the combined detector's state in the compiled loop, its alarms
``innovations``        XNAV innovations against the master, the XNAV innovation wavelet
``plots``              the figures behind the sliders of chapters 5, 6 and 8
``schematics``         drawings of the XNAV geometry, the UV and starlight angles, the
                       federated filter and the isolate/rejoin rule (chapters 2, 4, 6, 8)
``trials``             Monte Carlo trials of the detectors on the Mars run (chapter 9)
``roc``                a detector's threshold swept over a fault grid: Pd against false
                       alarms per day (``campaign roc``, chapter 9)
``detector_maps``      the detector table as heat maps and false-alarm strips (chapter 9)
``campaigns``          the Mars campaigns of ``python -m xnavlab campaign`` (chapter 13)
=====================  ===================================================================

It imports the core (:mod:`xnavlab.core`) and no other system.
"""

__all__: list[str] = []
