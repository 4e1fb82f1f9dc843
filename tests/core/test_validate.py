"""Argument checks: messages name the parameter and the allowed range."""

import math

import numpy as np
import pytest

from xnavlab.core.validate import check_choice, check_finite_array, check_int, check_real, make_rng


def test_check_real():
    assert check_real("x", 1, 0, 2) == 1.0
    for bad in (math.nan, math.inf, "1", None, True, -0.1):
        with pytest.raises(ValueError, match=r"x must be a real number in \[0, 2\]"):
            check_real("x", bad, 0, 2)
    with pytest.raises(ValueError, match=r"\(0, inf\)"):
        check_real("x", 0.0, 0.0, lo_open=True, hi_open=True)


def test_check_int():
    assert check_int("n", np.int64(3), 1, 5) == 3
    for bad in (2.5, "3", True, 0, 6):
        with pytest.raises(ValueError, match=r"n must be an integer in \[1, 5\]"):
            check_int("n", bad, 1, 5)


def test_check_finite_array():
    assert check_finite_array("r", [[1, 2, 3]], shape=(3,)).shape == (1, 3)
    with pytest.raises(ValueError, match="finite"):
        check_finite_array("r", [1, np.nan, 3])
    with pytest.raises(ValueError, match=r"trailing shape \(\.\.\., 3\)"):
        check_finite_array("r", [1, 2], shape=(3,))
    with pytest.raises(ValueError, match="array of finite numbers"):
        check_finite_array("r", ["a", "b"])


def test_check_choice():
    with pytest.raises(ValueError, match="kind must be one of 'a', 'b'"):
        check_choice("kind", "c", ("a", "b"))


def test_make_rng():
    g = np.random.default_rng(5)
    assert make_rng(g) is g
    assert make_rng(None).integers(1 << 30) == make_rng(0).integers(1 << 30)
    with pytest.raises(ValueError, match="seed must be an integer"):
        make_rng(-1)
    with pytest.raises(ValueError, match="seed"):
        make_rng("x")
