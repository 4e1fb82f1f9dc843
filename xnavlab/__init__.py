"""xnavlab: models and filters for fault-tolerant autonomous spacecraft navigation.

The package behind the executable book, in layers (each imports only the layers above it
in this list; ``tests/test_layers.py`` checks it):

1. :mod:`xnavlab.core`: the shared core (constants, argument checks, JPL ephemerides,
   quaternions, EKF/UKF steps, the federated filter, fault injection, wavelet and
   chi-square detection, Monte Carlo, plotting, the book's slider widget);
2. one subpackage per system the book teaches:
   :mod:`xnavlab.mars` (Fan et al. 2016, the main paper: XNAV, UV and CNS navigation at
   Mars, federated fusion, fault tolerance), :mod:`xnavlab.robust` (Li et al. 2017:
   ephemeris error and the robust filters), :mod:`xnavlab.attitude` (Li, Niu et al. 2019:
   attitude-sensor fault diagnosis), :mod:`xnavlab.plins` (Jin et al. 2011:
   pseudolite/INS fuzzy parity equations);
3. :mod:`xnavlab.reproductions` (every paper number the book claims, one module per
   chapter) behind the registry :mod:`xnavlab.reproduce`;
4. :mod:`xnavlab.cli`: the command line, ``python -m xnavlab``.

Submodules are imported on demand: ``from xnavlab.mars.timing import toa``.

The four source papers go by their author and year everywhere (docstrings, the book, the
registry's ``source`` strings); the book's Sources page (``book/sources.md``) gives their
full references and says what each chapter reproduces from which.

:data:`__version__` is the one place the version is written: ``pyproject.toml`` reads it
(a dynamic version), ``python -m xnavlab --version`` prints it and the book's front page
shows it.

The flat module names of release 0.1 (``xnavlab.toa``, ``xnavlab.scenarios``, ...) still
import, with a ``DeprecationWarning`` naming the new path (:mod:`xnavlab.compat`); they
go in the next release.
"""

from xnavlab.compat import install as _install_compat

#: The package version (the only place it is written; see the module docstring).
__version__ = "0.2.0"

__all__ = ["__version__"]

_install_compat()
