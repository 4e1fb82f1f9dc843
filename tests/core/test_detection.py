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


def test_review35p_p14_sigma_names_its_plain_shape_one_a_level():
    """Review 35p P14: sigma=0.0 at level 2 said "must have trailing shape (..., 2)"; the
    docstring says shape (level,): the message says so, one noise level a wavelet level."""
    for sigma, got in ((0.0, r"\(\)"), ([1.0, 2.0, 3.0], r"\(3,\)"), (np.ones((1, 2)), r"\(1, 2\)")):
        with pytest.raises(ValueError, match=r"^sigma must have shape \(2,\), one noise level a "
                           r"wavelet level \(level = 2\), got shape " + got + "$"):
            D.wavelet_detect(np.arange(300.0), np.zeros(300), level=2, sigma=sigma)


def test_review35p_p14_other_plain_shapes_are_named_plainly():
    """Review 35p P14's class in core/detection: nu, y, x and cone checked a trailing shape
    (a stack passed, a scalar read "trailing shape (..., m)"); each has a plain shape."""
    from xnavlab.core.detection.combined import CombinedDesign, InnovationMonitor
    from xnavlab.core.detection.singularity import lipschitz_exponent

    with pytest.raises(ValueError, match=r"^nu must have shape \(2,\) \(one innovation a "
                       r"measurement, m = 2\), got shape \(1, 2\)$"):
        D.Chi2Detector(2).update(0.0, np.zeros((1, 2)), np.eye(2))
    monitor = InnovationMonitor(CombinedDesign(28800.0, 2, rate_per_day=30.0))
    with pytest.raises(ValueError, match=r"^y must have shape \(2,\) \(one whitened innovation a "
                       r"measurement, m = 2\), got shape \(\)$"):
        monitor.update(0.0, 1.0)
    w = np.ones((3, 16))
    with pytest.raises(ValueError, match=r"^cone must have shape \(3,\) \(one half-width a scale "
                       r"of w\), got shape \(2, 3\)$"):
        lipschitz_exponent(w, [2.0, 4.0, 8.0], 5, cone=np.ones((2, 3)))
    t = np.arange(500.0)
    with pytest.raises(ValueError, match=r"^x must have shape \(500,\) \(one measurement a time "
                       r"of t\), got shape \(2, 500\)$"):
        D.combined_detect(t, np.zeros((500, 2)), x=np.zeros((2, 500)))
