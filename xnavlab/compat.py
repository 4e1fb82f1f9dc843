"""Old flat module names (release 0.1) as aliases of the new ones, with a DeprecationWarning.

``import xnavlab.toa`` (or ``from xnavlab import toa``) returns the module
:mod:`xnavlab.mars.toa` itself, not a copy, and warns once per name. The aliases are
kept for one release.

Examples
--------
>>> import warnings
>>> with warnings.catch_warnings(record=True) as caught:
...     warnings.simplefilter("always")
...     from xnavlab import toa
>>> toa.__name__, caught[0].category.__name__
('xnavlab.mars.toa', 'DeprecationWarning')
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import sys
import warnings

__all__ = ["RENAMED", "install"]

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
    "xnavlab.pulsars": "xnavlab.mars.pulsars",
    "xnavlab.toa": "xnavlab.mars.toa",
    "xnavlab.dynamics": "xnavlab.mars.dynamics",
    "xnavlab.sensors": "xnavlab.mars.sensors",
    "xnavlab.stars": "xnavlab.mars.stars",
    "xnavlab.scenarios": "xnavlab.mars.scenarios",
    "xnavlab.fault_tolerance": "xnavlab.mars.fault_tolerance",
    "xnavlab._kernels": "xnavlab.mars.kernels",
    "xnavlab.ephemeris_error": "xnavlab.robust.ephemeris_error",
    "xnavlab.ins": "xnavlab.plins.ins",
    "xnavlab.pseudolites": "xnavlab.plins.pseudolites",
    "xnavlab.parity": "xnavlab.plins.parity",
}


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
