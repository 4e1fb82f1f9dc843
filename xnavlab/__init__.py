"""xnavlab: models and filters for fault-tolerant autonomous spacecraft navigation.

The package behind the executable book. Modules are named for what they model:

- :mod:`xnavlab.constants`: physical constants with their sources
- :mod:`xnavlab.ephemeris`: Sun and planet states from JPL DE421/DE405
- :mod:`xnavlab.pulsars`: pulsar catalogue, timing model, photons, TOA accuracy
- :mod:`xnavlab.toa`: the time-transfer (TOA) equation and its gradient
- :mod:`xnavlab.dynamics`: Mars-orbit dynamics, truth propagator, state transition
- :mod:`xnavlab.reproduce`: the registry of paper reproductions (also the CLI)

Submodules are imported on demand: ``from xnavlab import toa``.
"""

__version__ = "0.1.0"

__all__ = ["__version__"]
