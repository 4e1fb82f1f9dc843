"""Singularity analysis (xnavlab.core.detection.singularity): Lipschitz exponents and modulus maxima."""


import numpy as np
import pytest

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


@pytest.mark.parametrize(("call", "match"), [
    (lambda: D.modulus_maxima(np.array(1.0)), r"^w must have shape \(N,\) or \(n_scales, N\) with N >= 1"),
    (lambda: D.modulus_maxima([]), r"^w must have shape"),
    (lambda: D.lipschitz_exponent(np.ones((3, 10)), -0.0, 5), r"^scales must be a 1-D array of 3 \(one per"),
    (lambda: D.lipschitz_exponent(np.ones((2, 10)), [1.0, -1.0], 5), r"^scales must be positive"),
    (lambda: D.cwt([], [2.0]), r"^x must be a 1-D signal of at least one sample"),
    (lambda: D.cwt(np.ones(8), []), r"^scales must be a 1-D array of at least one positive scale"),
])
def test_an_edge_input_is_refused_naming_it(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_lipschitz_exponent_refuses_equal_scales_and_a_cone_that_is_not_positive():
    """Review 35j (1) 8 and (2) 8: equal scales gave a RuntimeWarning (a slope over one
    abscissa); a negative cone numpy's "zero-size array to reduction operation"."""
    n = np.arange(-512, 512)
    s = 2.0 ** np.arange(1, 6)
    w = D.cwt(np.where(n >= 0, 1.0, 0.0), s)
    with pytest.raises(ValueError, match=r"^scales must hold at least two distinct scales"):
        D.lipschitz_exponent(w, np.ones(5), 512)
    for cone in (-np.ones(5), np.r_[1.0, 1.0, 0.0, 1.0, 1.0]):
        with pytest.raises(ValueError, match=r"^cone must be positive half-widths"):
            D.lipschitz_exponent(w, s, 512, cone=cone)
    assert abs(D.lipschitz_exponent(w, s, 512, cone=np.full(5, 0.5))) < 1.0


def test_cwt_bounds_its_scales_and_does_not_use_dt():
    """Review 35k (1) 4: dt=5e-324 passed '(0, inf)' and pywt's frequencies 1 / (scale dt)
    overflowed (a warning); dt scales only those frequencies, which cwt does not return. A
    scale below one sample step of the wavelet (pywt's 'Selected scale of 1e-300 too small',
    or a NaN warning at 5e-324) or beyond 1e7 samples of it (an allocation error) is refused
    naming scales."""
    x = np.r_[np.zeros(64), np.ones(64)]
    np.testing.assert_array_equal(D.cwt(x, [2.0, 4.0], dt=5e-324), D.cwt(x, [2.0, 4.0]))
    for bad in (5e-324, 1e-300, 0.09, 1e300):
        with pytest.raises(ValueError, match=r"^scales must lie in \[0.1, 1e\+06\] samples for "
                                             r"the 'gaus1' wavelet"):
            D.cwt(x, [2.0, bad])
    with pytest.raises(ValueError, match=r"^scales must lie in \[0.0625, 625000\]"):
        D.cwt(x, [0.05], "mexh")
    assert D.cwt(x, [0.1, 1e6]).shape == (2, 128)


def test_review35_r10_a_cone_with_no_coefficient_is_refused():
    """Review 35 R10: a cone maximum of 0 was floored at 1e-300 before log2, giving -0.5 for
    no signal and -299.6 for one empty scale; it is refused naming w, the scale and index."""
    s = np.array([1.0, 2, 4, 8])
    with pytest.raises(ValueError, match=r"^w is 0 in its cone at scales 1, 2, 4, 8: no "
                       r"singularity at index 100 \(the exponent is the slope of log2"):
        D.lipschitz_exponent(np.zeros((4, 200)), s, 100)
    w = np.zeros((4, 200))
    w[0, 95:105], w[1, 95:105], w[2, 95:105] = 1.0, 0.5, 0.25
    with pytest.raises(ValueError, match=r"^w is 0 in its cone at scale 8: no singularity at "
                       r"index 100 "):
        D.lipschitz_exponent(w, s, 100)
    w[3, 100] = 1e-14        # rounding, not a coefficient: below 1e-12 of the largest |w|
    with pytest.raises(ValueError, match=r"^w is at most 1e-14, below 1e-12 of its largest "
                       r"\|w\| \(1\), in its cone at scale 8: no singularity at index 100 "):
        D.lipschitz_exponent(w, s, 100)
    with pytest.raises(ValueError, match=r"^w is 0 in its cone at scales 1, 2, 4, 8: no "
                       r"singularity at index 1000 "):
        D.lipschitz_exponent(D.cwt(np.full(2000, 5.0), s), s, 1000)
    w[3, 100] = 0.125        # a real decay is still fitted: 2^(-j), alpha = -1.5
    assert D.lipschitz_exponent(w, s, 100) == pytest.approx(-1.5)
