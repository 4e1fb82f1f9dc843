"""xnavlab.mars.kernel.kernel_propagation: the compiled time update against the readable one
(xnavlab.mars.models.time_update)."""

import numpy as np

from xnavlab.core.constants import GM_MARS
from xnavlab.mars.kernel import kernel_inputs as ki
from xnavlab.mars.kernel.kernel_propagation import predict
from xnavlab.mars.models import dynamics, time_update


def test_predict_is_the_readable_time_update():
    t0 = dynamics.MARS_T0
    tab = dynamics.ThirdBodyTable(t0, t0 + 2000.0)
    q, max_step, inv_scale = 1e-11, 10.0, 3.0
    pr = ki.Propagation(q, max_step, GM_MARS, tab.t_start, tab.step, tab.pos, tab.vel, tab.gm)
    nb = tab.pos.shape[1]
    sc = ki.PredictScratch(*[np.empty((6, 6)) for _ in range(3)], np.empty(6),
                           *[np.empty((nb, 3)) for _ in range(6)])
    P0 = np.diag([1e6, 2e6, 3e6, 1.0, 2.0, 3.0])
    P0[0, 4] = P0[4, 0] = 100.0
    for dt in (3.0, 25.0, 500.0):           # one sub-step, three, fifty
        x, P = dynamics.MARS_STATE0.copy(), P0.copy()
        predict(x, P, t0 + 100.0, dt, inv_scale, pr, sc)
        x_ref, Phi = time_update.filter_propagate(dynamics.MARS_STATE0, t0 + 100.0, dt, tab,
                                                  max_step=max_step)
        P_ref = Phi @ P0 @ Phi.T + time_update.process_noise(dt, q) * inv_scale
        assert np.allclose(x, x_ref, rtol=1e-12, atol=1e-9)
        assert np.allclose(P, P_ref, rtol=1e-9, atol=1e-12)
        assert np.array_equal(P, P.T)
