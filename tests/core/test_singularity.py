"""Singularity analysis (xnavlab.core.detection.singularity): Lipschitz exponents and modulus maxima."""


import numpy as np

from xnavlab.core import detection as D


def test_lipschitz_exponents_of_step_ramp_spike():
    n = np.arange(-1024, 1024)
    s = 2.0 ** np.arange(1, 7)
    signals = {0.0: np.where(n >= 0, 1.0, 0.0), 1.0: np.maximum(n, 0.0), -1.0: (n == 0) * 1.0}
    for alpha, x in signals.items():
        assert abs(D.lipschitz_exponent(D.cwt(x, s, "gaus1"), s, 1024) - alpha) < 0.1


def test_modulus_maxima_locate_the_step_at_every_scale():
    x = np.r_[np.zeros(256), np.ones(256)]
    w = D.cwt(x, [2.0, 4.0, 8.0, 16.0], "gaus1")
    mm = D.modulus_maxima(w, threshold=0.1)[:, 64:448]                # away from the ends
    for row in mm:
        assert np.flatnonzero(row).tolist() == [256 - 64] or np.flatnonzero(row).tolist() == [255 - 64]
