"""The photon fix's error bar: against exposure, against chapter 1's formula, over random splits."""

import math

import numpy as np
import pytest

from xnavlab.mars.timing import photon_error, photon_fix


@pytest.fixture(scope="module")
def photons():
    return photon_fix.fermi_photons()


@pytest.fixture(scope="module")
def reference(photons):
    return photon_fix.build_reference(photons)


def test_formula_falls_as_one_over_root_n(photons):
    one = photon_error.snr_range_sigma(1000.0, 700.0, photons)
    assert photon_error.snr_range_sigma(4000.0, 2800.0, photons) == pytest.approx(one / 2, rel=1e-12)
    # more of the photons from the pulsar: a smaller sigma
    assert photon_error.snr_range_sigma(1000.0, 900.0, photons) < one
    with pytest.raises(ValueError, match="weight_sum"):
        photon_error.snr_range_sigma(100.0, 200.0, photons)


def test_exposure_scaling_sets_and_ratios(photons, reference):
    out = photon_error.exposure_scaling(photons, reference, months=(2, 6, 40))
    assert out["months"].tolist() == [2, 6]                   # 40 months make one set: left out
    assert out["n_sets"].tolist() == [21, 7]
    assert np.all(np.diff(out["n_photons"]) > 0) and np.all(np.diff(out["stated_m"]) < 0)
    # the stated sigma falls as one over the square root of the photons, like the formula
    slope = np.diff(np.log(out["stated_m"])) / np.diff(np.log(out["n_photons"]))
    assert abs(slope[0] + 0.5) < 0.15
    ratio = out["stated_m"] / out["formula_m"]
    assert np.all((ratio > 0.6) & (ratio < 1.2))
    # measured scatter and stated sigma agree within the scatter's own uncertainty (x 3)
    rel = out["measured_m"] / out["stated_m"] - 1.0
    assert np.all(np.abs(rel) < 3 * out["measured_unc"])
    assert len(out["estimates_m"][0]) == 21


def test_split_pulls_shapes(photons):
    out = photon_error.split_pulls(photons, seeds=range(3))
    assert out["pulls"].shape == (3,)
    assert np.allclose(out["pulls"], out["along_m"] / out["sigma_m"])
    assert np.all(out["sigma_photons_m"] < out["sigma_m"])
    assert np.all(np.abs(out["pulls"]) < 5.0)
    with pytest.raises(ValueError, match="seeds"):
        photon_error.split_pulls(photons, seeds=[1])


@pytest.mark.parametrize(("months", "words"), [
    ((2, 0), "months[1] must be an integer in [1, "),
    ((2, 2), "months lists 2 twice (items 0 and 1)"),
    (6, "months must be a list of set lengths, got 6"),
])
def test_exposure_scaling_names_each_length_under_its_list(photons, reference, months, words):
    # review 35d D11's class: the message said months for one item; a repeat ran twice
    with pytest.raises(ValueError) as exc:
        photon_error.exposure_scaling(photons, reference, months=months)
    assert str(exc.value).startswith(words), str(exc.value)


def test_snr_range_sigma_refuses_more_photons_than_its_background_allows():
    comps = np.array([[0.18, 0.05, 0.29], [0.61, 0.0174, 0.15], [0.43, 0.36, 0.56]])
    fake = photon_fix.Photons(*(np.zeros(1),) * 3, np.zeros((1, 3)), np.zeros((1, 3)),
                              np.array([205.53]), comps)
    with pytest.raises(ValueError, match=r"^n_photons must be a real number in \[0\.01, 1e\+11\]"):
        photon_error.snr_range_sigma(1e308, 700.0, fake)
    # issue 35, review 35f 14's class: weight_sum 5e-324 was a Pulsar flux the toa_sigma
    # divides by (now refused by its own name, not as a Pulsar's flux)
    with pytest.raises(ValueError, match=r"^weight_sum must be a real number in \[0\.01, 1000\]"):
        photon_error.snr_range_sigma(1000.0, 5e-324, fake)
    assert math.isfinite(photon_error.snr_range_sigma(0.01, 0.01, fake))


@pytest.mark.parametrize("bad", [True, -0.0, [], np.array(1.0)])
def test_photons_reference_and_seeds_are_named_when_of_another_kind(photons, reference, bad):
    """Issue 35 (review 35h): a number or a list was an AttributeError or a TypeError."""
    with pytest.raises(ValueError, match=r"^photons must be a Photons"):
        photon_error.exposure_scaling(bad, reference)
    with pytest.raises(ValueError, match=r"^reference must be a Reference"):
        photon_error.exposure_scaling(photons, bad)
    with pytest.raises(ValueError, match=r"^photons must be a Photons"):
        photon_error.snr_range_sigma(1000.0, 700.0, bad)
    with pytest.raises(ValueError, match=r"^photons must be a Photons"):
        photon_error.split_pulls(bad)
    with pytest.raises(ValueError, match=r"^seeds"):
        photon_error.split_pulls(photons, seeds=bad)
    with pytest.raises(ValueError, match=r"^seeds\[1\] must be an integer"):
        photon_error.split_pulls(photons, seeds=[1, True, 0])
