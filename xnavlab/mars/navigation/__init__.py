"""The federated run: a position and its accuracy (the paper's 30-day scenario).

The scenario, its settings and files, the federated run and what it is checked against:
consistency, linearisation, model mismatch, the headline accuracies, and the run's figures
(chapters 5-6).

=====================  ===================================================================
module                 what it models
=====================  ===================================================================
``scenarios``          the paper's 30-day scenario and the federated run (chapters 5-6)
``scenario_files``     every scenario setting in a TOML file, with units (``run mars
                       --scenario``, ``python -m xnavlab scenario --dump``)
``unused_inputs``      scenario settings another setting makes unused, runs left empty
``consistency``        run-averaged NEES and NIS against chi-square (chapters 5, 13)
``linearisation``      the EKF against the UKF on one UV run: what linearising costs (ch. 5)
``model_mismatch``     matched vs mismatched truth and filter: accuracy and NEES
                       (chapters 3, 5, 6)
``headline``           the headline accuracies as means over noise seeds, with intervals
``plots``              the figures behind the sliders of chapters 5, 6 and 8
``schematics``         drawings of the XNAV geometry, the UV and starlight angles, the
                       federated filter and the isolate/rejoin rule (chapters 2, 4, 6, 8)
``_run_checks``        plumbing (not public API): the checks of a run's inputs object,
                       overrides, ``active`` flags and ``gate``, used by ``scenarios``
=====================  ===================================================================

The modules are imported by name (``from xnavlab.mars.navigation import scenarios``);
importing the subpackage imports none of them.
"""

__all__: list[str] = []
