"""The shared core: what every system of the book uses, and nothing paper-specific.

========================  =================================================================
module                    what it models
========================  =================================================================
``constants``             physical constants, each with its source
``validate``              argument checks (``ValueError`` naming the parameter and range), RNGs
``distributions``         normal, chi-square and t quantiles for thresholds (no ``scipy.stats``)
``ephemeris``             Sun and planet states from the JPL ephemerides DE421/DE405
``quaternions``           scalar-last quaternion algebra and kinematics
``filters``               EKF and UKF as pure step functions plus thin classes; NEES/NIS
``federated``             Carlson's federated filter (information sharing, reset/no-reset)
``faults``                sensor fault injection (step, ramp, spike, stuck, noise)
``detection``             wavelet singularity detection and chi-square tests (a package)
``montecarlo``            Monte Carlo over any ``concurrent.futures.Executor``, seeds per run
``campaign``              resumable Monte Carlo campaigns (local pool or Dask), one store
``diskcache``             the on-disk cache's root, its atomic entries keyed by the code
``userfiles``             a user's input files read or refused with one line; outputs checked
``plotting``              figures outside pyplot, for reproductions and chapters
``widgets``               ``explore``: a live slider in Jupyter, a scrubber in the HTML book
``prose``                 a chapter's glued numbers, shown by its prose's ``{eval}`` roles
========================  =================================================================

Nothing here imports :mod:`xnavlab.mars`, :mod:`xnavlab.robust`, :mod:`xnavlab.attitude`,
:mod:`xnavlab.plins`, the reproductions or the CLI (``tests/test_layers.py`` checks it).
Submodules are imported on demand: ``from xnavlab.core import filters``.
"""

__all__: list[str] = []
