"""Old module names as aliases of the new ones, with a DeprecationWarning.

``import xnavlab.toa`` (or ``from xnavlab import toa``) returns the module
:mod:`xnavlab.mars.timing.toa` itself, not a copy, and warns once per name. The same holds
for the Mars system's flat names from before its subpackages (issue 37):
``xnavlab.mars.<module>`` is ``xnavlab.mars.<subpackage>.<module>``
(:data:`MARS_SUBPACKAGES`). The aliases are kept for one release.

Examples
--------
>>> import warnings
>>> with warnings.catch_warnings(record=True) as caught:
...     warnings.simplefilter("always")
...     from xnavlab import toa
>>> toa.__name__, caught[0].category.__name__
('xnavlab.mars.timing.toa', 'DeprecationWarning')
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import sys
import warnings

__all__ = ["MARS_SUBPACKAGES", "RENAMED", "install"]

#: Old module name -> new module name.
RENAMED = {
    "xnavlab.constants": "xnavlab.core.constants",
    "xnavlab._validate": "xnavlab.core.validate",
    "xnavlab.ephemeris": "xnavlab.core.ephemeris",
    "xnavlab.quaternions": "xnavlab.core.quaternions",
    "xnavlab.filters": "xnavlab.core.filters",
    "xnavlab.federated": "xnavlab.core.federated",
    "xnavlab.faults": "xnavlab.core.faults",
    "xnavlab.montecarlo": "xnavlab.core.montecarlo",
    "xnavlab.widgets": "xnavlab.core.widgets",
    "xnavlab.detection": "xnavlab.core.detection",
    "xnavlab.pulsars": "xnavlab.mars.timing.pulsars",
    "xnavlab.toa": "xnavlab.mars.timing.toa",
    "xnavlab.dynamics": "xnavlab.mars.models.dynamics",
    "xnavlab.sensors": "xnavlab.mars.models.sensors",
    "xnavlab.stars": "xnavlab.mars.models.stars",
    "xnavlab.scenarios": "xnavlab.mars.navigation.scenarios",
    "xnavlab.fault_tolerance": "xnavlab.mars.faults.fault_tolerance",
    "xnavlab._kernels": "xnavlab.mars.kernel.kernels",
    "xnavlab.ephemeris_error": "xnavlab.robust.ephemeris_error",
    "xnavlab.ins": "xnavlab.plins.ins",
    "xnavlab.pseudolites": "xnavlab.plins.pseudolites",
    "xnavlab.parity": "xnavlab.plins.parity",
}

#: The Mars system's subpackages and their modules, in the order of the flow (photons, a
#: position, a study); each module's old flat name ``xnavlab.mars.<module>`` is in
#: :data:`RENAMED` as an alias of ``xnavlab.mars.<subpackage>.<module>``.
MARS_SUBPACKAGES = {
    "timing": ("pulsars", "xray_pulsars", "pulsar_specs", "timing_bound", "toa", "fold_toa",
               "timing_terms", "pint_bridge", "photon_fix", "photon_error", "photon_plots"),
    "models": ("dynamics", "force_models", "model_noise", "time_update", "stars", "sensors",
               "optics", "series"),
    "kernel": ("kernels", "kernel_inputs", "kernel_compile", "kernel_linalg",
               "kernel_propagation", "kernel_measurements", "kernel_fusion", "kernel_watch",
               "compile_notice"),
    "navigation": ("scenarios", "scenario_files", "unused_inputs", "consistency",
                   "linearisation", "model_mismatch", "headline", "plots", "schematics"),
    "faults": ("fault_tolerance", "schedules", "watch", "innovations"),
    "studies": ("trials", "roc", "campaigns", "detector_maps"),
}
RENAMED.update({f"xnavlab.mars.{module}": f"xnavlab.mars.{sub}.{module}"
                for sub, modules in MARS_SUBPACKAGES.items() for module in modules})


class _AliasLoader(importlib.abc.Loader):
    def __init__(self, new):
        self.new = new

    def create_module(self, spec):
        warnings.warn(f"{spec.name} is deprecated; import {self.new}", DeprecationWarning,
                      stacklevel=2)
        module = importlib.import_module(self.new)
        self.spec = module.__spec__
        return module

    def exec_module(self, module):
        """Nothing to run: the module is the new one; give it back its own spec."""
        module.__spec__ = self.spec  # the import system set the alias's spec on it


class _AliasFinder(importlib.abc.MetaPathFinder):
    def find_spec(self, fullname, path=None, target=None):
        new = RENAMED.get(fullname)
        if new is None:
            return None
        return importlib.machinery.ModuleSpec(fullname, _AliasLoader(new))


def install():
    """Put the alias finder on ``sys.meta_path`` (once; :mod:`xnavlab` does it on import)."""
    if not any(isinstance(f, _AliasFinder) for f in sys.meta_path):
        sys.meta_path.append(_AliasFinder())
