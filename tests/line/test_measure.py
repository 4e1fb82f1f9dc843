"""One folded window turned into a range (xnavlab.line.measure)."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from xnavlab.core.constants import AU, C
from xnavlab.line import measure
from xnavlab.mars.timing import pulsars


@pytest.mark.parametrize("name", ["B0531+21", "B1937+21"])
def test_nbins_gives_a_power_of_two_with_a_dozen_bins_per_pulse_width(name):
    n = measure.nbins_for(name)
    assert n & (n - 1) == 0
    assert 12 <= n * pulsars.get(name).duty_cycle < 24


def test_wavelength_is_c_times_the_period():
    assert measure.wavelength("B1937+21") == pytest.approx(C * 0.00156)


def test_fold_range_is_unbiased_with_the_stated_sigma():
    rng = np.random.default_rng(5)
    x = 1.5 * AU
    err = np.array([measure.fold_range(x, x, exposure=10.0, rng=rng) - x for _ in range(300)])
    sigma = measure.range_sigma("B0531+21", 10.0)
    assert abs(err.mean()) < 4 * sigma / math.sqrt(err.size)
    assert 0.85 < err.std() / sigma < 1.15


@settings(max_examples=25, deadline=None)
@given(offset=st.floats(-0.45, 0.45), cycles=st.integers(-1000, 1000))
def test_the_cycle_nearest_the_prediction_is_chosen(offset, cycles):
    """A prediction off by less than half a wavelength gives the true cycle."""
    lam = measure.wavelength("B0531+21")
    x = 2.0e11 + cycles * lam
    z = measure.fold_range(x, x + offset * lam, exposure=100.0, rng=1)
    assert abs(z - x) < 6 * measure.range_sigma("B0531+21", 100.0)


def test_a_prediction_off_by_one_wavelength_gives_the_wrong_cycle():
    lam = measure.wavelength("B0531+21")
    z = measure.fold_range(2.0e11, 2.0e11 + lam, exposure=100.0, rng=1)
    assert z - 2.0e11 == pytest.approx(lam, abs=2e3)


def test_range_sigma_falls_as_one_over_root_exposure():
    ratio = measure.range_sigma("B0531+21", 10.0) / measure.range_sigma("B0531+21", 1000.0)
    assert ratio == pytest.approx(10.0, rel=1e-9)
    assert measure.range_sigma("B0531+21", 10.0, area_m2=4.0) == pytest.approx(
        measure.range_sigma("B0531+21", 40.0), rel=1e-9)


@pytest.mark.parametrize("kwargs, name", [({"exposure": 0.0}, "exposure"), ({"x": math.nan}, "x"),
                                          ({"x_ref": math.inf}, "x_ref")])
def test_bad_input_names_the_parameter(kwargs, name):
    args = {"x": 1.0e11, "x_ref": 1.0e11, **kwargs}
    with pytest.raises(ValueError, match=name):
        measure.fold_range(**args)
    with pytest.raises(ValueError, match="exposure"):
        measure.range_sigma("B0531+21", -1.0)


@pytest.mark.parametrize("call, match", [
    (lambda: measure.range_sigma(exposure=1e-300), r"^exposure must be a real number in \[0.001, 100000\]"),
    (lambda: measure.fold_range(1e3, 1e3, exposure=5e-324, rng=1), r"^exposure must be a real"),
    (lambda: measure.fold_range(1e22, 1e22, rng=1), r"^x must be a real number in \[-1e\+15, 1e\+15\]"),
    (lambda: measure.fold_range(1e3, -1e20, rng=1), r"^x_ref must be a real number in \[-1e\+15"),
])
def test_issue35_exposure_and_distance_have_physical_ranges(call, match):
    # Review 35f findings 15 and 26: a tiny exposure divided by zero; a distance past 1e20 m
    # lost the ranging noise in the float spacing.
    with pytest.raises(ValueError, match=match):
        call()
