"""xnavlab.robust.sensitivity: the UKF's error against a constant ephemeris error, by direction."""

import math

import numpy as np
import pytest

from xnavlab.robust import sensitivity


def _slopes(A, base, size, dirs):
    # RMSE(u)^2 = size^2 u^T A u + base^2, the quadratic form steepest_direction fits
    return {k: (np.sqrt(size ** 2 * v @ A @ v + base ** 2) - base) / size for k, v in dirs.items()}


def _dirs():
    rows = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 0], [1, 0, 1], [0, 1, 1.0]])
    return {str(i): v / np.linalg.norm(v) for i, v in enumerate(rows)}


def test_the_steepest_direction_of_a_known_form_is_its_top_eigenvector():
    rng = np.random.default_rng(3)
    Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    A = Q @ np.diag([0.1, 0.7, 2.0]) @ Q.T
    u, top = sensitivity.steepest_direction(_slopes(A, 40.0, 1e3, _dirs()), _dirs(), 40.0, 1e3)
    assert abs(abs(u @ Q[:, 2]) - 1.0) < 1e-9
    assert top == pytest.approx((np.sqrt(1e6 * 2.0 + 1600.0) - 40.0) / 1e3, rel=1e-9)


def test_fewer_than_six_directions_are_refused():
    dirs = dict(list(_dirs().items())[:5])
    with pytest.raises(ValueError, match="at least 6"):
        sensitivity.steepest_direction(_slopes(np.eye(3), 40.0, 1e3, dirs), dirs, 40.0, 1e3)


def test_the_named_directions_are_unit_vectors():
    d = sensitivity.sensitivity_directions("mars")
    assert {"orbit normal", "DE421-DE405", "(1,1,1)"} <= set(d)
    assert all(abs(np.linalg.norm(v) - 1.0) < 1e-12 for v in d.values())


def test_the_earth_error_is_the_real_ephemeris_difference():
    assert 1.0e3 < sensitivity.earth_error_size() < 2.0e3


@pytest.mark.parametrize(("change", "words"), [
    ({"base": "1"}, r"^base must be a real number in \[0, 1e\+12\], got '1'$"),
    ({"base": None}, r"^base must be a real number"),
    ({"base": 1 + 1j}, r"^base must be a real number"),
    ({"size": 0.0}, r"^size must be a real number in \[0.001, 1e\+12\], got 0.0$"),
    ({"size": math.inf}, r"^size must be a real number in \[0.001, 1e\+12\], got inf$"),
    ({"slopes": [1.0] * 6}, r"^slopes must be a dict of direction name -> value, got \[1.0"),
    ({"slopes": {**{k: 0.5 for k in _dirs()}, "x": 0.5}}, r"^slopes\['x'\] has no direction"),
    ({"slopes": {**{k: 0.5 for k in _dirs()}, "0": math.nan}}, r"^slopes\['0'\] must be a real"),
    ({"slopes": {**{k: 0.5 for k in _dirs()}, "0": -1.0}},
     r"^slopes\['0'\] must be a real number in \[-0.04, 1e\+06\], got -1.0$"),
    ({"directions": {**_dirs(), "0": [2.0, 0.0, 0.0]}},
     r"^directions\['0'\] must be a unit vector, got norm 2$"),
    ({"directions": {**_dirs(), "0": [1.0, 0.0]}}, r"^directions\['0'\] must be a 1-D array"),
    ({"directions": {str(i): [np.cos(a), np.sin(a), 0.0] for i, a in enumerate(np.linspace(0, 3, 6))}},
     r"^directions must determine the quadratic form"),
])
def test_steepest_direction_refuses_what_would_give_a_wrong_direction(change, words):
    """Review 35e: base '1' or None was a TypeError, size 0 or inf a NaN direction, a slope
    without its direction was dropped, a non-unit or coplanar set fitted a wrong form."""
    args = {"slopes": {k: 0.5 for k in _dirs()}, "directions": _dirs(), "base": 40.0, "size": 1e3}
    args.update(change)
    with pytest.raises(ValueError, match=words):
        sensitivity.steepest_direction(**args)


def test_sensitivity_names_sizes_and_directions():
    """Issue 35: a bool among the sizes was taken as 1 m, a list of directions was an
    AttributeError, a subnormal size a failed eigendecomposition."""
    for bad, words in ((True, "^sizes must be an array of finite numbers"),
                       ([1.0, True], "^sizes must be an array of finite numbers"),
                       ([1.0, 2e8], r"^sizes\[1\] must be a real number in \[0, 1e\+08\]")):
        with pytest.raises(ValueError, match=words):
            sensitivity.ukf_sensitivity(bad)
    for bad in ([], {}, True):
        with pytest.raises(ValueError, match="^directions must be a non-empty dict"):
            sensitivity.ukf_sensitivity_by_direction(bad)
    with pytest.raises(ValueError, match=r"^directions\['z'\] must be a 1-D array"):
        sensitivity.ukf_sensitivity_by_direction({"z": [0.0, 1.0]})
    with pytest.raises(ValueError, match=r"^size must be a real number in \[0.001"):
        sensitivity.steepest_direction({k: 0.5 for k in _dirs()}, _dirs(), 40.0, 5e-324)


@pytest.mark.parametrize("size", [0.0, 5e-324, None, "1.0", True, 1e9])
def test_review_35k_1_12_sensitivity_size(size):
    """Review 35k (1) 12: size 0 was a ZeroDivisionError, None or text a TypeError, True taken as 1."""
    with pytest.raises(ValueError, match=r"^size must be a real number in \[0.001, 1e\+08\]"):
        sensitivity.ukf_sensitivity_by_direction({"z": [0.0, 0.0, 1.0]}, body="mars", size=size)


@pytest.mark.parametrize("t0", [math.nan, None, 1e300])
def test_review_35k_3_4_earth_error_size_t0(t0):
    """Review 35k (3) 4: t0 was refused as the ephemeris' ``t``."""
    with pytest.raises(ValueError, match=r"^t0 must be an epoch in \["):
        sensitivity.earth_error_size(t0=t0)


@pytest.mark.parametrize("sizes, words", [
    ((4.0, 4.0), r"^sizes lists 4.0 twice \(items 0 and 1\)$"),
    ([0.0, 250.0, 0.0], r"^sizes lists 0.0 twice \(items 0 and 2\)$"),
    ((), r"^sizes must name at least one size, got an empty list$"),
    ([1.0, -1.0, 1.0], r"^sizes\[1\] must be a real number in \[0, 1e\+08\]"),  # each range first
])
def test_review_35_q10_ukf_sensitivity_refuses_a_repeated_size_and_an_empty_list(sizes, words):
    """Review 35 Q10: a repeated size was run and returned twice, an empty list returned two
    empty arrays without a word (detection_table and its siblings refuse both)."""
    with pytest.raises(ValueError, match=words):
        sensitivity.ukf_sensitivity(sizes)
