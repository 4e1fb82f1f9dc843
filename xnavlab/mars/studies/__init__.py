"""Monte Carlo studies on the run: detector trials, ROC curves, campaigns (chapters 9, 13).

Many runs of :mod:`xnavlab.mars.navigation` and :mod:`xnavlab.mars.faults`, with seeds,
summarised: the detectors' trials, their ROC curves and heat maps, the campaigns of
``python -m xnavlab campaign``.

=====================  ===================================================================
module                 what it models
=====================  ===================================================================
``trials``             Monte Carlo trials of the detectors on the Mars run (chapter 9)
``roc``                a detector's threshold swept over a fault grid: Pd against false
                       alarms per day (``campaign roc``, chapter 9)
``campaigns``          the Mars campaigns of ``python -m xnavlab campaign`` (chapter 13)
``detector_maps``      the detector table as heat maps and false-alarm strips (chapter 9)
``_metrics``           plumbing (not public API): the campaigns' check of a stored run's
                       metrics (``Campaign.check_metrics``)
=====================  ===================================================================

The modules are imported by name (``from xnavlab.mars.studies import trials``);
importing the subpackage imports none of them.
"""

__all__: list[str] = []
