"""Epochs written for messages: full digits and their TDB calendar date."""

import math

import pytest

from xnavlab.core import dates, ephemeris


@pytest.mark.parametrize("t, text", [
    (0.0, "0 (2000-01-01T12:00:00 TDB)"),
    (-0.0, "0 (2000-01-01T12:00:00 TDB)"),
    (86400.5, "86400.5 (2000-01-02T12:00:00 TDB)"),
    (6314067927.361, "6314067927.361 (2200-01-31T23:45:27 TDB)"),
    (math.nan, "nan"),
    (math.inf, "inf"),
    (1e300, "1e+300"),  # beyond the year 9999: no date
])
def test_epoch_text_writes_every_digit_and_the_date(t, text):
    assert dates.epoch_text(t) == text


def test_a_bound_and_a_value_one_second_apart_read_apart():
    """Review 35q Q19: at six digits both read 6.31407e+09."""
    hi = ephemeris.coverage("de421")[1]
    assert dates.epoch_text(hi - 1.0) != dates.epoch_text(hi)
    assert dates.epoch_range(0.0, hi).endswith("(2200-02-01T00:00:00 TDB)] s TDB past J2000")


def test_the_dates_of_the_ephemerides_coverage_are_their_documented_years():
    assert dates.epoch_date(ephemeris.coverage("de421")[0]).startswith("1899-12-04")
    assert dates.epoch_date(ephemeris.coverage("de421")[1]).startswith("2200-02-01")
