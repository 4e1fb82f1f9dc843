"""Li et al. 2017: navigation robust to planetary-ephemeris error.

=======================  =================================================================
module                   what it models
=======================  =================================================================
``ephemeris_error``      the DE421 - DE405 ephemeris error, orbits about Earth or Mars, the
                         XNAV measurements that see the error (chapter 10)
``filters``              UKF, ASUKF, TDUKF and the robust Kalman filter (RKF)
``comparison``           the filters compared over seeds (mean RMSE, improvement over the UKF)
``sensitivity``          the UKF's error against a constant ephemeris error, by its size and
                         direction (Fig. 4)
``coverage``             whether the RKF's ``Sigma`` bounds its error: coverage of the
                         3-sigma ellipse, NEES, over seeds; the prior bound on ``B B^T``
``plots``                the figure behind chapter 10's slider, and its table of the RKF's
                         bound over seeds (stored on disk)
=======================  =================================================================

The public names of ``filters`` and ``comparison`` are re-exported here (``from xnavlab import robust``).
This system uses two pieces of the Mars system, because the book's story needs them: the
pulsar catalogue (:mod:`xnavlab.mars.timing.pulsars`: the same four pulsars are observed) and the
Mars initial state and pole (:mod:`xnavlab.mars.models.dynamics`: the Mars case flies the main
paper's orbit).
"""

from xnavlab.robust.comparison import *  # noqa: F403
from xnavlab.robust.comparison import __all__ as _comparison_all
from xnavlab.robust.filters import *  # noqa: F403
from xnavlab.robust.filters import __all__ as _filters_all

__all__ = [*_filters_all, *_comparison_all]
