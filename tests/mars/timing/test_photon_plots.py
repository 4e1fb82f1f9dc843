"""Figures of the photon fix: each a pure function returning an unregistered Figure."""

import matplotlib.pyplot as plt
import numpy as np
import pytest

from xnavlab.mars.timing import photon_plots, pulsars
from xnavlab.mars.timing.photon_fix import Fix


def test_plot_fix_draws_the_fold_and_the_likelihood():
    before = plt.get_fignums()
    fig = photon_plots.plot_fix(100.0)
    assert len(fig.axes) == 3 and plt.get_fignums() == before
    assert fig.get_suptitle().startswith("injected 100 km along")
    assert fig.axes[1].get_xlabel() == "offset along the line (km)"


def test_plot_recovery_with_an_across_point():
    fx = Fix(1.0e4 + 300.0, 800.0, 600.0, 500.0, 20.0, 1.0e4, 1.4586e6, 3000, 2000.0)
    zero = Fix(250.0, 800.0, 600.0, 500.0, 20.0, 0.0, 1.4586e6, 3000, 2000.0)
    fig = photon_plots.plot_recovery([0.0, 1.0e4], [zero, fx], across=(5e5, zero))
    labels = [t.get_text() for t in fig.axes[1].get_xticklabels()]
    assert labels == ["0 along", "10 along", "500 across"]
    with pytest.raises(ValueError, match=r"^fixes must hold one Fix per injected offset \(1\), got 2"):
        photon_plots.plot_recovery([0.0], [zero, fx])


def test_plot_ambiguity_and_exposure():
    x = np.linspace(-3e6, 3e6, 13)
    fig = photon_plots.plot_ambiguity(x, (x + 7.3e5) % 1.46e6 - 7.3e5, 1.46e6)
    assert fig.axes[0].get_xlabel() == "injected offset along the line (km)"
    s = {"n_photons": np.array([100.0, 400.0]), "measured_m": np.array([4e3, 2.1e3]),
         "measured_unc": np.array([0.2, 0.3]), "stated_m": np.array([4e3, 2e3]),
         "formula_m": np.array([5e3, 2.5e3]), "months": np.array([1, 4]), "n_sets": np.array([40, 10])}
    fig = photon_plots.plot_exposure(s, paper_m=[109.0, 1866.0], total=(3000.0, 700.0, 900.0))
    assert fig.axes[0].get_yscale() == "log" and fig.axes[0].get_ylabel() == "fix standard deviation (m)"


def test_plot_ranging_accuracy_bars_and_reference():
    ref = {"B0531+21": 109.0, "B1937+21": 344.0, "B1957+20": 1866.0, "B1821-24": 325.0}
    fig = photon_plots.plot_ranging_accuracy(area_m2=0.5, reference=ref)
    ax = fig.axes[0]
    heights = [b.get_height() for b in ax.patches]
    assert heights == pytest.approx(
        [pulsars.ranging_accuracy(n, area_m2=0.5) for n in pulsars.PAPER_PULSARS])
    assert list(ax.lines[0].get_ydata()) == list(ref.values())
    assert "A = 0.5 m$^2$" in ax.get_title()
    assert not photon_plots.plot_ranging_accuracy(pulsar_names=["B0531+21"]).axes[0].lines


@pytest.mark.parametrize(("args", "words"), [
    ((np.linspace(-3e6, 3e6, 7), np.zeros(7), 5e-324),
     r"^cycle_m must be a real number in \[30000, 1e\+12\]"),
    ((np.linspace(-3e6, 3e6, 7), np.zeros(7), 1e-300), r"^cycle_m must be a real number in \[30000, "),
    ((np.array([-1e12, 1e12]), np.zeros(2), 3e4), r"^cycle_m must be at least 1e-4 of the injected span"),
    ((np.array([]), np.array([]), 1.46e6), r"^injected_m must be a non-empty 1-D array"),
    ((np.zeros(3), np.zeros(2), 1.46e6),
     r"^recovered_m must have shape \(3,\) \(one fix per injected offset\), got shape \(2,\)"),
    ((np.zeros(1), np.zeros(1), 1.46e6), r"^injected_m must hold at least 2 offsets, got 1"),
])
def test_plot_ambiguity_draws_a_bounded_number_of_cycles(args, words):
    """Issue 35, review 35f 16's class: cycle_m = 1e-300 looped over 1e306 cycle lines."""
    with pytest.raises(ValueError, match=words):
        photon_plots.plot_ambiguity(*args)


@pytest.mark.parametrize("bad", [True, -0.0, [1.0], np.array(1.0)])
def test_fixes_and_scaling_are_refused_by_name(bad):
    """Issue 35 (review 35h): a number or a list of numbers was a TypeError from inside."""
    with pytest.raises(ValueError, match=r"^fixes(\[0\])? must be a (list of )?Fix"):
        photon_plots.plot_recovery([1.0e4], bad)
    with pytest.raises(ValueError, match=r"^scaling must be the dict of exposure_scaling\(\)"):
        photon_plots.plot_exposure(bad)


@pytest.mark.parametrize(("paper_m", "words"), [
    (True, r"^paper_m must be an array of finite numbers, got True"),
    ([], r"^paper_m must be a non-empty 1-D array, got shape \(0,\)"),
    ([1.0, True], r"^paper_m must be an array of finite numbers"),
])
def test_plot_exposure_names_paper_m(paper_m, words):
    s = {"n_photons": [100.0, 400.0], "measured_m": [4e3, 2.1e3], "measured_unc": [0.2, 0.3],
         "stated_m": [4e3, 2e3], "formula_m": [5e3, 2.5e3], "months": [1, 4]}
    with pytest.raises(ValueError, match=words):
        photon_plots.plot_exposure(s, paper_m=paper_m)
    with pytest.raises(ValueError, match=r"^scaling\['months'\] must have shape \(2,\)"):
        photon_plots.plot_exposure({**s, "months": [1]})


@pytest.mark.parametrize("reference, message", [
    (1.0, r"^reference must be a non-empty dict of pulsar name -> ranging accuracy"),
    ([], r"^reference must be a non-empty dict"),
    ({}, r"^reference must be a non-empty dict"),
    ({"B0531+21": 109.0}, r"^reference must hold a value for every bar, got none for B1937\+21"),
    ({**pulsars.PAPER_RANGING_M, "X": 1.0}, r"^reference\['X'\] marks no bar"),
    ({**pulsars.PAPER_RANGING_M, "B0531+21": None}, r"^reference\['B0531\+21'\] must be a real number"),
])
def test_review_35k_1_20_ranging_reference(reference, message):
    """Review 35k (1) 20: reference=1.0 was a TypeError ('not subscriptable'), [] and {} were
    accepted (nothing marked), a missing name a KeyError."""
    with pytest.raises(ValueError, match=message):
        photon_plots.plot_ranging_accuracy(t_obs=2000.0, reference=reference)


@pytest.mark.parametrize("name", ["area_m2", "t_obs", "background_ph_cm2_s"])
def test_plot_ranging_accuracy_titles_a_fraction_as_its_float(name):
    """Review 35m (1) 2, pattern M: t_obs=Fraction(...) passed ranging_accuracy's check, then the
    title formatted the raw Fraction ('unsupported format string passed to Fraction')."""
    from fractions import Fraction

    value = {"area_m2": 1.0, "t_obs": 500.0, "background_ph_cm2_s": 0.005}[name]
    fig = photon_plots.plot_ranging_accuracy(**{name: Fraction(value)})
    ref = photon_plots.plot_ranging_accuracy(**{name: value})
    assert fig.axes[0].get_title() == ref.axes[0].get_title()
    plt.close("all")
