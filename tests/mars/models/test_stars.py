"""The bright-star table and the CNS star choice (xnavlab.mars.models.stars): the catalogue, look-up by
name or number, proper-motion propagation, RA/Dec round trip, the spread of three directions and
the rule that picks the three most spread stars."""

import itertools
import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from xnavlab.mars.models import stars

YEAR = 365.25 * 86400.0


def test_catalogue_is_sorted_brightest_first_with_unique_names_and_numbers():
    cat = stars.catalogue()
    assert len(cat) == len(stars.names()) >= 30
    assert [s.vmag for s in cat] == sorted(s.vmag for s in cat)
    assert len({s.name for s in cat}) == len(cat) and len({s.hip for s in cat}) == len(cat)
    assert all(0.0 <= s.ra_deg < 360.0 and -90.0 <= s.dec_deg <= 90.0 for s in cat)


def test_get_by_name_number_or_star_and_refuses_an_unknown_star():
    vega = stars.get("VEGA")
    assert stars.get(vega.hip) is not None and stars.get(vega.hip).name == "Vega"
    assert stars.get(vega) is vega
    with pytest.raises(ValueError, match="unknown star"):
        stars.get("Betelgeuse of Mars")
    with pytest.raises(ValueError, match="unknown star"):
        stars.get(True)   # a bool is not a Hipparcos number


def test_direction_at_the_catalogue_epoch_is_the_catalogue_position():
    for s in stars.catalogue()[:10]:
        ra, dec = stars.radec(stars.direction(s, stars.HIPPARCOS_EPOCH))
        assert ra == pytest.approx(s.ra_deg, abs=1e-9)
        assert dec == pytest.approx(s.dec_deg, abs=1e-9)


def test_direction_moves_by_the_proper_motion():
    """Over 100 years a star moves by its total proper motion times the time, to first order."""
    mas = math.pi / (180.0 * 3600.0e3)
    for name in ("Arcturus", "Rigil Kentaurus", "Sirius"):
        s = stars.get(name)
        u0 = stars.direction(s, stars.HIPPARCOS_EPOCH)
        u1 = stars.direction(s, stars.HIPPARCOS_EPOCH + 100 * YEAR)
        moved = math.acos(min(1.0, float(u0 @ u1)))
        mu = math.hypot(s.pm_ra_cosdec_mas_yr, s.pm_dec_mas_yr) * mas
        assert moved == pytest.approx(100 * mu, rel=1e-3)
        assert np.linalg.norm(u1) == pytest.approx(1.0, abs=1e-15)


def test_directions_stacks_one_row_per_star():
    d = stars.directions(["Sirius", "Vega"], 1e8)
    np.testing.assert_array_equal(d[1], stars.direction("Vega", 1e8))
    assert d.shape == (2, 3)


@given(st.floats(0.0, 359.999), st.floats(-89.9, 89.9))
def test_radec_inverts_the_unit_vector(ra, dec):
    a, d = math.radians(ra), math.radians(dec)
    u = np.array([math.cos(d) * math.cos(a), math.cos(d) * math.sin(a), math.sin(d)])
    got = stars.radec(u)
    assert got[1] == pytest.approx(dec, abs=1e-9)
    assert min(abs(got[0] - ra), 360.0 - abs(got[0] - ra)) < 1e-8


def test_spread_is_one_for_orthogonal_and_zero_for_coplanar_directions():
    assert stars.spread(np.eye(3)) == pytest.approx(1.0)
    coplanar = np.array([[1.0, 0, 0], [0, 1.0, 0], [math.sqrt(0.5), math.sqrt(0.5), 0]])
    assert stars.spread(coplanar) == pytest.approx(0.0, abs=1e-15)
    with pytest.raises(ValueError, match="^s"):
        stars.spread(np.eye(2))


def test_pick_three_maximises_the_spread_among_the_bright_stars():
    picked = stars.pick_three(vmag_max=1.0)
    pool = [s.name for s in stars.catalogue() if s.vmag <= 1.0]
    best = max(stars.spread(stars.directions(trio)) for trio in itertools.combinations(pool, 3))
    assert stars.spread(stars.directions(picked)) == pytest.approx(best, rel=1e-12)
    assert set(picked) <= set(pool)


def test_pick_three_keeps_away_from_the_avoided_direction_and_checks_its_input():
    sun = stars.direction("Arcturus")
    picked = stars.pick_three(avoid=sun, avoid_deg=30.0)
    assert "Arcturus" not in picked
    assert all(math.degrees(math.acos(float(stars.direction(n) @ sun))) > 30.0 for n in picked)
    assert stars.pick_three(candidates=["Vega", "Sirius", "Canopus"]) == ("Sirius", "Canopus", "Vega")
    with pytest.raises(ValueError, match=r"^candidates must name at least 3 stars, got 2$"):
        stars.pick_three(candidates=["Vega", "Sirius"])
    with pytest.raises(ValueError, match="vmag_max"):
        stars.pick_three(vmag_max=20.0)
    with pytest.raises(ValueError, match="avoid_deg"):
        stars.pick_three(avoid=sun, avoid_deg=-1.0)


def test_pick_three_is_kept_per_arguments_and_checks_them():
    """The triple is worked out once per set of arguments; an array and a list agree."""
    sun = np.array([[1.0, 0.2, 0.1]])
    first = stars.pick_three(avoid=sun, avoid_deg=30.0)
    assert stars.pick_three(avoid=sun.tolist(), avoid_deg=30.0) == first
    assert stars.pick_three(avoid=sun, avoid_deg=30.0) is first  # the kept tuple
    with pytest.raises(ValueError, match="t"):
        stars.pick_three(t=float("nan"))


@pytest.mark.parametrize(("value", "words"), [
    ("Sirius", "stars must be a list of stars, got the string 'Sirius'"),  # was split: 'S'
    (None, "stars must be a list of stars, got None"),
    (["Vega", "vega"], "stars lists Vega twice (items 0 and 1)"),
])
def test_directions_refuses_what_is_no_list_of_distinct_stars(value, words):
    with pytest.raises(ValueError) as exc:
        stars.directions(value)
    assert str(exc.value).startswith(words), str(exc.value)


def test_radec_refuses_the_zero_vector():  # review 35d D42's class: NaN and a warning
    with pytest.raises(ValueError, match=r"^u must be a direction \(a non-zero vector\)"):
        stars.radec(np.zeros(3))


def test_starlight_geometry_refuses_a_star_list_by_name():
    """Issue 35 (review 35h): ``star_names=True`` was a TypeError, ``[]`` gave an empty
    result, and an unknown star was refused without the parameter's name."""
    r = np.array([[4.2e6, 0.0, 0.0]])
    with pytest.raises(ValueError, match=r"^star_names must be a list of stars, got True$"):
        stars.starlight_geometry(r, True)
    with pytest.raises(ValueError, match=r"^star_names must name at least one star"):
        stars.starlight_geometry(r, [])
    with pytest.raises(ValueError, match=r"^star_names\[0\]: unknown star 1.0"):
        stars.starlight_geometry(r, [1.0])
    with pytest.raises(ValueError, match=r"^star_names must be a list of stars"):
        stars.starlight_geometry(r, np.array(1.0))
    assert list(stars.starlight_geometry(r, ["vega"])) == ["Vega"]


def test_pick_three_names_the_setting_that_leaves_too_few_stars():
    """Review 35j (3) 3: 'number of candidate stars must be an integer in [3, inf), got 2'
    named no parameter."""
    with pytest.raises(ValueError, match=r"^vmag_max = 0 leaves 2 of candidates bright enough, "
                                         r"pick_three needs 3: raise vmag_max or give more "
                                         r"candidates$"):
        stars.pick_three(vmag_max=0.0, candidates=["Sirius", "Vega", "Canopus", "Polaris"])
    with pytest.raises(ValueError, match=r"^avoid_deg = 179 leaves 0 of the catalogue's stars with "
                                         r"V <= 1 outside it, pick_three needs 3"):
        stars.pick_three(avoid=[1.0, 0.0, 0.0], avoid_deg=179.0)


def test_pick_three_refuses_avoid_or_avoid_deg_alone_a_zero_avoid_and_repeats():
    """Review 35j (5) 8, (5) 31: avoid_deg without avoid was unused; a repeated candidate was
    dropped; a zero avoid direction divided by zero."""
    with pytest.raises(ValueError, match=r"^avoid_deg is unused without avoid"):
        stars.pick_three(avoid_deg=10.0)
    with pytest.raises(ValueError, match=r"^avoid is unused with avoid_deg = 0"):
        stars.pick_three(avoid=[1.0, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"^avoid\[0\] must be a direction \(a non-zero vector\)"):
        stars.pick_three(avoid=[0.0, 0.0, 0.0], avoid_deg=5.0)
    with pytest.raises(ValueError, match=r"^candidates lists Sirius twice \(items 0 and 1\)$"):
        stars.pick_three(candidates=["Sirius", "Sirius", "Vega", "Canopus"])
    with pytest.raises(ValueError, match=r"^candidates\[2\]: unknown star 'Nope'"):
        stars.pick_three(candidates=["Sirius", "Vega", "Nope"])
    # a direction of any length (the Sun's position) is taken as its direction
    assert stars.pick_three(avoid=[1e11, 0.0, 0.0], avoid_deg=30.0) == \
        stars.pick_three(avoid=[1.0, 0.0, 0.0], avoid_deg=30.0)


def test_spread_refuses_vectors_that_are_not_unit():
    """Review 35j (5) 31: spread(2 I) returned 8."""
    with pytest.raises(ValueError, match=r"^s\[0\] must be a unit vector \(norm within 1e-6 of "
                                         r"1\), got norm 2$"):
        stars.spread(2 * np.eye(3))


def test_one_vector_or_no_position_is_refused_by_name():
    """Review 35k (1) 16, (2) 5: radec of a (1, 3) vector was an IndexError, and
    starlight_geometry of no position numpy's 'zero-size array' message."""
    with pytest.raises(ValueError, match=r"^u must be a 1-D array \(shape \(3,\)\), got shape "
                                         r"\(1, 3\)$"):
        stars.radec(np.array([[0.0, 0.0, 1.0]]))
    for r in (np.zeros((0, 3)), np.full((2, 2, 3), 4e6)):
        with pytest.raises(ValueError, match=r"^r must have shape \(n, 3\) with n >= 1"):
            stars.starlight_geometry(r, ("Polaris",))


def test_no_avoid_direction_or_a_subnormal_radius_is_refused():
    """Review 35k pattern A/D: avoid of shape (0, 3) was numpy's 'axis 1 is out of bounds';
    radius=5e-324 was taken (a disc of no size)."""
    with pytest.raises(ValueError, match=r"^avoid must hold at least one direction"):
        stars.pick_three(avoid=np.zeros((0, 3)), avoid_deg=10.0)
    with pytest.raises(ValueError, match=r"^radius must be a real number in \[1, 1e\+09\]"):
        stars.starlight_geometry(np.array([[4e6, 0.0, 0.0]]), ("Polaris",), radius=5e-324)
