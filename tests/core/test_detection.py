"""The detection package as a whole (xnavlab.core.detection): every public function and detector
rejects bad input with a ValueError naming the parameter, and the Mallat-vs-PyWavelets reproduction
passes. Each module's own tests are in the test module of its name."""

import math

import numpy as np
import pytest

from xnavlab.core import detection as D


@pytest.mark.parametrize("call,name", [
    (lambda: D.mallat_dwt(np.ones(16), mode="wrap"), "mode"),
    (lambda: D.mallat_dwt(np.ones(16), wavelet="db99"), "wavelet"),
    (lambda: D.mallat_dwt(np.ones(16), wavelet="bior1.3"), "wavelet"),
    (lambda: D.mallat_dwt([1.0, np.nan]), "c"),
    (lambda: D.mallat_wavedec(np.ones(64), level=5), "level"),
    (lambda: D.mallat_wavedec(np.ones(64), level=0), "level"),
    (lambda: D.detail_signals(np.ones((3, 64))), "x"),
    (lambda: D.WaveletDetector(level=0), "level"),
    (lambda: D.WaveletDetector(pfa=1.5), "pfa"),
    (lambda: D.WaveletDetector(var_window=-1), "var_window"),
    (lambda: D.WaveletDetector(holdoff=0), "holdoff"),
    (lambda: D.WaveletDetector(sigma=[1.0, 2.0]), "sigma"),
    (lambda: D.WaveletDetector(sigma=[1.0, 1.0, 1.0, 1.0, -1.0]), "sigma"),
    (lambda: D.WaveletDetector().train(np.ones(100)), "x"),
    (lambda: D.WaveletDetector(sigma=np.ones(5)).update(0.0, math.inf), "x"),
    (lambda: D.wavelet_detect(np.arange(10.0), np.ones(11)), "t"),
    (lambda: D.threshold_multiplier(0.0), "pfa"),
    (lambda: D.wavelet_detect_sensor(np.arange(10.0), np.ones((11, 2))), "z"),
    (lambda: D.wavelet_detect_sensor(np.arange(500.0), np.ones((500, 2)), sigma=np.ones(5)), "sigma"),
    (lambda: D.wavelet_detect_sensor(np.arange(500.0), np.ones((500, 2)), train=np.ones((400, 3))), "train"),
    (lambda: D.chi2_threshold(0.01, 0), "dof"),
    (lambda: D.chi2_statistic(np.ones((5, 2)), np.eye(2), window=0), "window"),
    (lambda: D.chi2_statistic(np.ones((5, 2)), np.eye(3)), "S"),
    (lambda: D.chi2_statistic(np.ones((5, 2)), -np.eye(2)), "S"),
    (lambda: D.Chi2Detector(m=2, alpha=0.0), "alpha"),
    (lambda: D.Chi2Detector(m=2).update(0.0, [1.0], np.eye(2)), "nu"),
    (lambda: D.cwt(np.ones(32), [0.0, 2.0]), "scales"),
    (lambda: D.cwt(np.ones(32), [2.0], wavelet="db3"), "wavelet"),
    (lambda: D.modulus_maxima(np.ones(8), threshold=-1.0), "threshold"),
    (lambda: D.lipschitz_exponent(np.ones((2, 8)), [1.0, 2.0], index=9), "index"),
])
def test_bad_input_raises_value_error_naming_the_parameter(call, name):
    with pytest.raises(ValueError, match=rf"\b{name}\b"):
        call()
