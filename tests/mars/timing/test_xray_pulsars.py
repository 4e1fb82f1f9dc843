"""The X-ray table: its rows, the paper's four equal to the catalogue's, names and aliases."""

import pytest

from xnavlab.mars.timing import pulsars, xray_pulsars


def test_the_papers_four_rows_are_the_catalogues_values():
    for name in pulsars.PAPER_PULSARS:
        row, p = xray_pulsars.lookup(name), pulsars.get(name)
        assert row["flux_ph_cm2_s"] * 1e4 == pytest.approx(p.flux, rel=1e-12)
        assert (row["pulsed_fraction"], row["width_s"], row["period_s"]) == (
            p.pulsed_fraction, p.width, p.period)


def test_every_row_is_a_physical_pulsar():
    for row in xray_pulsars.table().values():
        assert 0 < row["width_s"] <= 0.5 * row["period_s"], row["name"]
        assert 0 < row["pulsed_fraction"] <= 1 and 0 < row["flux_ph_cm2_s"] < 10
        assert row["source"] == xray_pulsars.SOURCE


@pytest.mark.parametrize(("name", "found"), [
    ("J0437-4715", "J0437-4715"), ("PSR J0030+0451", "J0030+0451"), ("j1939+2134", "B1937+21"),
    ("J1824-2452A", "B1821-24"), ("J1614-2230", None), ("", None),
])
def test_lookup_by_name_alias_and_prefix(name, found):
    row = xray_pulsars.lookup(name)
    assert (row["name"] if row else None) == found


def test_names_lists_the_first_names():
    assert "J0437-4715" in xray_pulsars.names() and len(xray_pulsars.names()) == 10


@pytest.mark.parametrize("bad", [True, [], None, 1.0])
def test_lookup_takes_a_name_only(bad):
    """Issue 35 (review 35h): True was looked up as the name 'TRUE' (and found nothing)."""
    with pytest.raises(ValueError, match=r"^name must be text \(a str\)"):
        xray_pulsars.lookup(bad)


def test_the_table_and_its_rows_are_read_only():
    """Review 35 R4: table() (cached) and lookup() gave back the dicts every later from_par
    read, so editing a row changed the flux of every later pulsar from a .par."""
    row = xray_pulsars.lookup("B1937+21")
    for target in (row, xray_pulsars.table()["B1937+21"]):
        with pytest.raises(TypeError, match="does not support item assignment"):
            target["flux_ph_cm2_s"] = 1e3
    with pytest.raises(TypeError, match="does not support item assignment"):
        xray_pulsars.table()["B1937+21"] = {}
    copy = dict(row)
    copy["flux_ph_cm2_s"] = 1e3  # a copy is the caller's
    assert xray_pulsars.lookup("B1937+21")["flux_ph_cm2_s"] == 4.99e-5
