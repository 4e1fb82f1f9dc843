"""The orbit's and the sensors' models: the dynamics, the forces and the measurements.

What the truth and the filters know of the orbit and of the three sensors (chapters 3-5):
the dynamics and force models, the process noise, the star table and the XNAV, UV and CNS
measurement models.

=====================  ===================================================================
module                 what it models
=====================  ===================================================================
``dynamics``           Mars-orbit dynamics, truth propagator, transition matrix (chapter 3)
``force_models``       the truth's and the filter's force models apart: Mars's field
                       (MRO95A), the Sun and planets, SRP; q_acc from their difference
``model_noise``        the process noise a filter needs for what its model leaves out
``time_update``        the filters' time update: RK4 with the paper's force model, the
                       transition matrix, the process noise (chapter 5)
``stars``              the bright-star table and the CNS star choice (chapter 4)
``sensors``            XNAV, UV and CNS measurement models (chapters 4-5)
``optics``             the optical sensors as instruments: range from the apparent radius,
                       Mars's oblate limb, correlated horizon errors (chapters 4-6)
``series``             the compiled draws of the UV and CNS measurement series
``_checks``            plumbing (not public API): the epochs' dtype and the longest
                       propagation span the propagators share
=====================  ===================================================================

The modules are imported by name (``from xnavlab.mars.models import dynamics``);
importing the subpackage imports none of them.
"""

__all__: list[str] = []
