"""Fault detection: Mallat's wavelet transform, the online wavelet singularity detector, chi-square tests.

The main paper (Fan et al. 2016, section 2) detects sensor faults as *singularities* of the
measurement series: local modulus maxima of the wavelet detail coefficients, db3, five levels.

=====================  ===================================================================
module                 what it holds
=====================  ===================================================================
``mallat``             Mallat's fast algorithm, paper eqs. (9)-(10); detail signals (Fig. 5)
``online``             causal undecimated details, MAD thresholds, events, the online
                       :class:`~.online.WaveletDetector`
``batch``              the batch :func:`~.batch.wavelet_detect`, whole or block by block
``singularity``        modulus maxima, Lipschitz exponents, the CWT (paper eqs. (7)-(8))
``chisquare``          the innovation chi-square baseline (:class:`~.chisquare.Chi2Detector`)
``combined``           the combined detector: wavelet + chi-square + CUSUMs on innovations
``limits``             Neyman-Pearson limits: the best detection probability of any detector
``plots``              the chapters' figures
=====================  ===================================================================

Every public name of these modules is re-exported here: ``from xnavlab.core import detection``.
The design decisions (sliding window, thresholds, hold-off) are in :mod:`.online`.
"""

from xnavlab.core.detection.batch import *  # noqa: F403
from xnavlab.core.detection.batch import __all__ as _batch_all
from xnavlab.core.detection.chisquare import *  # noqa: F403
from xnavlab.core.detection.chisquare import __all__ as _chisquare_all
from xnavlab.core.detection.combined import *  # noqa: F403
from xnavlab.core.detection.combined import __all__ as _combined_all
from xnavlab.core.detection.limits import *  # noqa: F403
from xnavlab.core.detection.limits import __all__ as _limits_all
from xnavlab.core.detection.mallat import *  # noqa: F403
from xnavlab.core.detection.mallat import __all__ as _mallat_all
from xnavlab.core.detection.online import *  # noqa: F403
from xnavlab.core.detection.online import __all__ as _online_all
from xnavlab.core.detection.plots import *  # noqa: F403
from xnavlab.core.detection.plots import __all__ as _plots_all
from xnavlab.core.detection.singularity import *  # noqa: F403
from xnavlab.core.detection.singularity import __all__ as _singularity_all

__all__ = [*_mallat_all, *_online_all, *_batch_all, *_singularity_all, *_chisquare_all, *_combined_all,
           *_limits_all, *_plots_all]
