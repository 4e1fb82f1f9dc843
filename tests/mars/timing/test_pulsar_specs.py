"""A scenario's pulsars: names, timing models (PINT's example .par files) and tables; the lists
refused (string, empty, wrong item, repeated); written back as they read."""

import json

import numpy as np
import pytest

from xnavlab.mars.navigation import scenarios
from xnavlab.mars.timing import pint_bridge, pulsar_specs, pulsars

J1614 = "J1614-2230_NANOGrav_12yv3.wb.gls.par"  # parallax, not in the X-ray table
J0030 = "PSRJ0030+0451_psrcat.par"             # in the table, no parallax
ENTRY = {"name": "X1", "ra_deg": 10.0, "dec_deg": 5.0, "distance_m": 3e19, "period_s": 0.005,
         "fdot_hz_s": 0.0, "flux_ph_cm2_s": 1e-5, "pulsed_fraction": 0.5, "width_s": 5e-4}


@pytest.fixture(scope="module")
def par():
    return {name: str(pint_bridge.examples_path(name)) for name in (J1614, J0030)}


def test_a_par_without_x_ray_properties_is_refused_naming_what_is_missing(par):
    with pytest.raises(ValueError) as exc:
        pulsar_specs.check_list(["B0531+21", par[J1614]])
    msg = str(exc.value)
    assert "J1614-2230" in msg and "has no flux_ph_cm2_s, pulsed_fraction, width_s" in msg
    assert len(msg.splitlines()) == 1


def test_a_par_with_the_missing_properties_given_is_a_pulsar(par):
    spec = {"par": par[J1614], "flux_ph_cm2_s": 1e-5, "pulsed_fraction": 0.5, "width_s": 1e-4}
    p = pulsar_specs.resolve(spec)
    assert p.name == "J1614-2230" and p.flux == pytest.approx(0.1) and p.width == 1e-4
    assert "argument" in p.sources["flux"] and "timing model" in p.sources["ra_deg"]


def test_a_tabled_par_takes_the_tables_x_ray_side(par):
    # review 35f #5: the message named "distance"; a scenario file's key is distance_m
    with pytest.raises(ValueError, match=r"distance must be given .* \(in a scenario file: the key "
                                         r"distance_m of a pulsar table"):
        pulsar_specs.resolve(par[J0030])          # this file's parallax is commented out
    p = pulsar_specs.resolve({"par": par[J0030], "distance_m": 1.0e19})
    assert (p.pulsed_fraction, p.width) == (0.10, 2.4e-4) and p.flux == pytest.approx(0.196)
    assert "Sheikh" in p.sources["flux"]


def test_relative_par_paths_read_from_the_base_folder(par, tmp_path):
    from pathlib import Path

    src = Path(par[J1614])
    (tmp_path / "m.par").write_text(src.read_text())
    got = pulsar_specs.check_list([{"par": "m.par", "flux_ph_cm2_s": 1e-5,
                                    "pulsed_fraction": 0.5, "width_s": 1e-4}], base=tmp_path)
    assert got[0].name == "J1614-2230"
    with pytest.raises(ValueError, match="no such timing model"):
        pulsar_specs.check_list(["nowhere.par"], base=tmp_path)


@pytest.mark.parametrize(("specs", "words"), [
    ("B0531+21", "must be a list of pulsars, got the string 'B0531+21'"),
    ([], "must name at least one pulsar, got an empty list"),
    (None, "must be a list of pulsars, got None"),
    ({"par": "x.par"}, "must be a list of pulsars"),
    ([3], "pulsars[0] must be a catalogue name, the path of a .par file or a table, got 3"),
    (["B0531+21", "B1937+21", "B0531+21"], "lists B0531+21 twice (items 0 and 2)"),
    (["B"], "unknown pulsar 'B'"),
    (["J0437-4715"], "is in the X-ray table but needs its timing model"),
    (["B0531+21", "b1937+21"], "unknown pulsar 'b1937+21': the catalogue names it 'B1937+21'"),
    ([{**ENTRY, "extra": 1}], "pulsar table has no key 'extra'"),
    ([{k: v for k, v in ENTRY.items() if k != "width_s"}], "needs width_s"),
    ([{**ENTRY, "dec_deg": 95.0}], "pulsars[0]['dec_deg'] must be a real number in [-90, 90]"),
    ([ENTRY, {**ENTRY, "name": "X2"}], "lists X2 twice (items 0 and 1)"),  # same direction
    # review 35e: a number or a list for par was read as the file name '5' or "['a.par']"
    ([{"par": 5}], "pulsars[0]['par'] must be the path of a .par file (a string), got 5"),
    ([{"par": ["a.par"]}], "pulsars[0]['par'] must be the path of a .par file (a string), got ['a.par']"),
    ([{"par": " "}], "pulsars[0]['par'] must be the path of a .par file (a string), got ' '"),
])
def test_bad_pulsar_lists_are_one_line_each(specs, words):
    with pytest.raises(ValueError) as exc:
        pulsar_specs.check_list(specs)
    assert words in str(exc.value) and len(str(exc.value).splitlines()) == 1


def test_items_write_back_as_they_read():
    p = pulsar_specs.resolve(ENTRY)
    for spec in ("B1957+20", p, pulsars.get("B1821-24")):
        back = pulsar_specs.resolve(json.loads(json.dumps(pulsar_specs.to_json(spec))))
        assert back == pulsar_specs.resolve(spec)
    assert pulsar_specs.to_toml(p).startswith('{name = "X1", ra_deg = 10.0')


def test_fault_names_stay_short_unless_they_collide():
    a = {**ENTRY, "name": "J1000+10"}
    b = {**ENTRY, "name": "J1000-20", "ra_deg": 50.0}
    assert pulsar_specs.fault_names(["B0531+21", a, b]) == ("B0531", "J1000+10", "J1000-20")
    assert pulsar_specs.names(["B0531+21", a]) == ("B0531+21", "J1000+10")


def test_a_scenario_with_a_timing_model_pulsar_runs(par):
    spec = {"par": par[J1614], "flux_ph_cm2_s": 1e-5, "pulsed_fraction": 0.5, "width_s": 1e-4}
    sc = scenarios.MarsScenario(days=0.02, pulsars=("B0531+21", spec))
    assert isinstance(sc.pulsars[1], pulsars.Pulsar)
    res = scenarios.run(sc)
    assert np.isfinite(res.metrics()["position_error_m"])
    assert res.nis.shape[1] == 3


def test_a_malformed_timing_model_is_one_line_naming_it(tmp_path):
    bad = tmp_path / "bad.par"
    bad.write_text("PSR J0000\nF0 1\nGARBAGE x\n")
    with pytest.raises(ValueError) as exc:
        pulsar_specs.check_list([str(bad)])
    assert "PINT cannot read the timing model" in str(exc.value) and str(bad) in str(exc.value)
    assert len(str(exc.value).splitlines()) == 1


@pytest.mark.parametrize("bad", [None, "B0531+21", ["B0531+21", "B0531+21"]])
def test_names_and_fault_names_check_their_list(bad):  # review 35d D37's class: TypeError
    for call in (pulsar_specs.names, pulsar_specs.fault_names):
        with pytest.raises(ValueError, match="^pulsars "):
            call(bad)


@pytest.mark.parametrize(("key", "value", "words"), [
    ("flux_ph_cm2_s", 5e-324, r"^flux_ph_cm2_s must be a real number in \[1e-12, 1000\]"),
    ("pulsed_fraction", 1e-300, r"^pulsed_fraction must be a real number in \[1e-06, 1\]"),
    ("distance_m", 1e-300, r"^distance_m must be a real number in \[3\.08\d*e\+16, "),
    ("width_s", 1e-300, r"^width_s must be a real number in \[5e-07, 0\.0025\]"),
    ("period_s", 5e-324, r"^period_s must be a real number in \[0\.0001, 100\]"),
])
def test_a_tables_ranges_are_the_pulsars(key, value, words):
    """Issue 35, review 35f 14/18's class: the table's ranges agree with Pulsar's, so a value
    Pulsar refuses is refused by the table's own key, not as a Pulsar field."""
    with pytest.raises(ValueError, match=words):
        pulsar_specs.resolve({**ENTRY, key: value})


@pytest.mark.parametrize("base", [float("nan"), -1, [], True, ""])
def test_review_35k_5_10_resolve_base(base):
    """Review 35k (5) 10: base (unused for a catalogue name) was accepted unchecked."""
    with pytest.raises(ValueError, match=r"^base must be a folder \(a non-empty str or os.PathLike\)"):
        pulsar_specs.resolve("B1957+20", base=base)
    with pytest.raises(ValueError, match=r"^base must be a folder"):
        pulsar_specs.check_list(["B1957+20"], base)


def test_review_35k_5_10_resolve_base_path():
    """Review 35k (5) 10: a folder as str or os.PathLike is taken (and ignored for a name)."""
    from pathlib import Path

    assert pulsar_specs.resolve("B1957+20", base=Path("/tmp")).name == "B1957+20"


def test_an_items_message_names_the_item_not_from_pars_parameters(tmp_path):
    """Review 35m (3) 2: a .par without F0 said "path: its F0 (Hz) must be ..., got 0.0" (from_par's
    parameter, no item, no file, 0.0 for a missing value); a table's key was named bare."""
    nof0 = tmp_path / "nof0.par"
    nof0.write_text("PSR J0000+00\nRAJ 1:00:00\nDECJ 1:00:00\n")
    with pytest.raises(ValueError) as info:
        pulsar_specs.check_list(["B0531+21", str(nof0)])
    assert str(info.value) == (f"pulsars[1]: {str(nof0)!r} is not a pulsar timing model: it has no "
                               f"F0 line (the spin frequency, Hz, in every timing model)")
    table = {"par": str(nof0), "distance_m": 3e19}
    with pytest.raises(ValueError, match=r"^stars\[0\]: '.*nof0\.par' is not a pulsar timing"):
        pulsar_specs.check_list([table], name="stars")
    with pytest.raises(ValueError, match=r"^pulsars\[0\]\['width_s'\] must be a real number"):
        pulsar_specs.check_list([{**ENTRY, "width_s": 1.0}])
