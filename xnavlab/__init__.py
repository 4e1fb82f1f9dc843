"""xnavlab: models and filters for fault-tolerant autonomous spacecraft navigation.

The package behind the executable book, in layers (each imports only the layers above it
in this list; ``tests/test_layers.py`` checks it):

1. :mod:`xnavlab.core`: the shared core (constants, argument checks, JPL ephemerides,
   quaternions, EKF/UKF steps, the federated filter, fault injection, wavelet and
   chi-square detection, Monte Carlo, plotting, the book's slider widget);
2. one subpackage per system the book teaches:
   :mod:`xnavlab.mars` (the main paper: XNAV, UV and CNS navigation at Mars, federated
   fusion, fault tolerance), :mod:`xnavlab.robust` (paper 002: ephemeris error and the
   robust filters), :mod:`xnavlab.attitude` (paper 003: attitude-sensor fault diagnosis),
   :mod:`xnavlab.plins` (paper 004: pseudolite/INS fuzzy parity equations);
3. :mod:`xnavlab.reproductions` (every paper number the book claims, one module per
   chapter) behind the registry :mod:`xnavlab.reproduce`;
4. :mod:`xnavlab.cli`: the command line, ``python -m xnavlab``.

Submodules are imported on demand: ``from xnavlab.mars import toa``.

The flat module names of release 0.1 (``xnavlab.toa``, ``xnavlab.scenarios``, ...) still
import, with a ``DeprecationWarning`` naming the new path (:mod:`xnavlab.compat`); they
go in the next release.
"""

from xnavlab.compat import install as _install_compat

#: The package version.
__version__ = "0.2.0"

__all__ = ["__version__"]

_install_compat()
