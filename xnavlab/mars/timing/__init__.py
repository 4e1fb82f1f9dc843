"""Photons to a time of arrival: the pulsars, their photons, the TOA and its accuracy.

The first step of the flow: from the pulsars' photons to a time of arrival at the
spacecraft and its accuracy (chapters 0-2).

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
``timing_terms``       what the paper's TOA equation leaves out: exact vs paper Shapiro,
                       the planets' Shapiro, the on-board clock against TDB (chapter 2)
``pint_bridge``        PINT offline as a witness: its delays for a spacecraft, shipped
                       Fermi photons and NANOGrav residuals (chapters 1-2)
``photon_fix``         a held-out fix along the line to J0030+0451 from PINT's Fermi
                       photons: the geocentre as the spacecraft (chapter 1, real photons)
``photon_error``       that fix's error bar against exposure and chapter 1's formula,
                       checked over random splits of the months
``photon_plots``       chapter 1's ranging-accuracy bars; the figures of the fix: slider,
                       recovery, cycle ambiguity, exposure
``_checks``            plumbing (not public API): the spin drift a photon simulation can
                       invert, shared by the modules above
=====================  ===================================================================

The modules are imported by name (``from xnavlab.mars.timing import pulsars``);
importing the subpackage imports none of them.
"""

__all__: list[str] = []
