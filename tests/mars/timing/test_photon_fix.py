"""A held-out fix along the line to J0030+0451 from the Fermi photons shipped with PINT.

The photons' phases are PINT's (cached on disk by :mod:`xnavlab.mars.timing.pint_bridge`); the
displaced phases are checked against PINT's own with the geocentre moved.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from xnavlab.core.constants import C
from xnavlab.mars.timing import photon_fix

INJECTED_KM = (0.0, 10.0, 100.0, 500.0)


@pytest.fixture(scope="module")
def photons():
    return photon_fix.fermi_photons()


@pytest.fixture(scope="module")
def reference(photons):
    return photon_fix.build_reference(photons)


@pytest.fixture(scope="module")
def witness(photons):
    """Along 500 km, across 500 km, along one cycle c P, and PINT's phases after each move."""
    return photon_fix.pint_witness(photons)


@pytest.fixture(scope="module")
def offsets(witness):
    return witness[0]


@pytest.fixture(scope="module")
def pint_phases(witness):
    return witness[1]


def wrapped(x):
    return (x + 0.5) % 1.0 - 0.5


def test_photons_and_geometry_line_up(photons):
    assert photons.size == 6973
    assert np.allclose(np.linalg.norm(photons.direction, axis=1), 1.0, atol=1e-12)
    # the geocentre is about 1 au from the SSB; the photons span years
    r_au = np.linalg.norm(photons.r_geo_ssb, axis=1) / 1.495978707e11
    assert r_au.min() > 0.97 and r_au.max() < 1.03
    assert np.ptp(photons.t) > 6 * 365.25 * 86400.0
    assert abs(photon_fix.cycle_length(photons) / 1e3 - 1458.6) < 0.1   # c P, km


def test_displaced_phases_agree_with_pint(photons, offsets, pint_phases):
    for k, dr in enumerate(offsets):
        ours = photon_fix.displaced_phases(photons, dr)
        diff = wrapped(pint_phases[k] - ours)
        # the remainder is the solar Shapiro delay, which sees a move across the line
        assert np.abs(diff).max() < 1e-6, k     # cycles: 5 ns, 1.5 m
    along = wrapped(pint_phases[0] - photons.phases)
    assert abs(np.median(along) - 500e3 / photon_fix.cycle_length(photons)) < 1e-6


def test_across_and_whole_cycle_moves_leave_pint_phases_alone(photons, pint_phases):
    assert np.abs(wrapped(pint_phases[1] - photons.phases)).max() < 1e-6
    assert np.abs(wrapped(pint_phases[2] - photons.phases)).max() < 1e-6


def test_reference_uses_no_navigation_photon(photons, reference):
    nav = ~reference.in_reference
    assert 0.4 < nav.mean() < 0.6
    assert not np.any(photons.month[nav] % 2 == 0)       # navigation: the odd months
    scrambled = photons.phases.copy()
    scrambled[nav] = np.random.default_rng(0).random(nav.sum())
    other = photon_fix.build_reference(photon_fix.Photons(
        scrambled, photons.weights, photons.t, photons.direction, photons.r_geo_ssb,
        photons.spin_frequency, photons.components))
    assert np.array_equal(other.theta, reference.theta)
    assert np.array_equal(other.coeffs, reference.coeffs)


def test_reference_finds_the_timing_models_drift(reference):
    # chapter 1 saw the catalogue model's phases drift; the correction is about half a nHz
    df, sigma = reference.theta[1], np.sqrt(reference.cov[1, 1])
    assert 0.3e-9 < df < 0.9e-9 and df > 10 * sigma


@pytest.mark.parametrize("injected_km", INJECTED_KM)
def test_held_out_fix_recovers_offsets_along_the_line(photons, reference, injected_km):
    f = photon_fix.fix(photons, photon_fix.offset_vector(photons, along_m=injected_km * 1e3), reference)
    assert f.truth_along_m == pytest.approx(injected_km * 1e3, abs=1e-6)
    assert abs(f.along_m - injected_km * 1e3) < 2.0 * f.sigma_m
    assert 300.0 < f.sigma_m < 3000.0                     # m: a km-level fix from 3.5 years


def test_fix_from_pints_own_displaced_phases(photons, reference, offsets, pint_phases):
    ours = photon_fix.fix(photons, offsets[0], reference)
    pints = photon_fix.fix(photons, offsets[0], reference, phases=pint_phases[0])
    assert abs(pints.along_m - ours.along_m) < 1.0        # m
    assert abs(pints.along_m - 500e3) < 2.0 * pints.sigma_m


def test_offset_across_the_line_leaves_the_fix_unchanged(photons, reference, offsets, pint_phases):
    zero = photon_fix.fix(photons, np.zeros(3), reference)
    across = photon_fix.fix(photons, offsets[1], reference)
    assert across.truth_along_m == pytest.approx(0.0, abs=1e-6)
    assert abs(across.along_m - zero.along_m) < 0.01 * zero.sigma_m
    pints = photon_fix.fix(photons, offsets[1], reference, phases=pint_phases[1])
    assert abs(pints.along_m - zero.along_m) < 0.01 * zero.sigma_m


def test_cycle_ambiguity(photons, reference, offsets, pint_phases):
    cycle = photon_fix.cycle_length(photons)
    zero = photon_fix.fix(photons, np.zeros(3), reference)
    one = photon_fix.fix(photons, offsets[2], reference)
    assert abs(one.along_m - zero.along_m) < 1.0          # m: c P is invisible
    assert one.wrapped_truth_m == pytest.approx(0.0, abs=1e-3)
    pints = photon_fix.fix(photons, offsets[2], reference, phases=pint_phases[2])
    assert abs(pints.along_m - zero.along_m) < 1.0
    # past half a cycle the fix wraps to the other side
    beyond = photon_fix.fix(photons, photon_fix.offset_vector(photons, along_m=0.5 * cycle + 50e3),
                            reference)
    assert beyond.along_m < 0.0
    assert abs(beyond.along_m - (50e3 - 0.5 * cycle)) < 2.0 * beyond.sigma_m


def test_error_bar_has_its_three_parts(photons, reference):
    f = photon_fix.fix(photons, np.zeros(3), reference)
    parts = np.array([f.sigma_photons_m, f.sigma_template_m, f.sigma_timing_m])
    assert f.sigma_m == pytest.approx(np.sqrt(np.sum(parts**2)))
    # equal halves of the data: the template is about as noisy as the navigation photons
    assert 0.8 < f.sigma_template_m / f.sigma_photons_m < 1.25
    assert f.sigma_timing_m < 0.1 * f.sigma_m


def test_likelihood_scan_peaks_at_the_fix(photons, reference):
    nav = photons.subset(~reference.in_reference)
    d, sigma = photon_fix.estimate_offset(nav, reference)
    offsets, scan = photon_fix.likelihood_scan(nav, reference, bins=2048)
    peak = offsets[np.argmax(scan)]
    cycle = photon_fix.cycle_length(nav)
    assert abs((peak - d + 0.5 * cycle) % cycle - 0.5 * cycle) < 2 * cycle / 2048
    exact = photon_fix.log_likelihood(nav, reference, [d, d + 3 * sigma])
    assert exact[0] > exact[1]                             # a maximum
    assert exact[0] - exact[1] == pytest.approx(4.5, rel=0.35)   # -2 dL = (3 sigma)^2 / sigma^2


def test_template_density_is_a_density(reference):
    f = photon_fix.template_density(reference.coeffs)
    assert np.mean(f) == pytest.approx(1.0, abs=1e-12)
    index = np.array([1638, 9830])                          # phases 0.1 and 0.6 of the table
    direct = photon_fix.template_density(reference.coeffs, index / f.size)
    assert np.allclose(direct, f[index], atol=1e-9)


def test_split_months():
    n = 24
    fake = photon_fix.Photons(np.zeros(n), np.ones(n), np.arange(n) * photon_fix.MONTH / 2,
                              np.tile([1.0, 0.0, 0.0], (n, 1)), np.zeros((n, 3)), np.ones(n),
                              np.zeros((3, 3)))
    assert photon_fix.split_months(fake).tolist() == [True, True, False, False] * 6
    a, b = photon_fix.split_months(fake, 3), photon_fix.split_months(fake, 3)
    assert np.array_equal(a, b)
    assert np.array_equal(fake.subset(np.arange(4, 8)).month, [2, 2, 3, 3])  # months of the parent


def test_bad_input_raises(photons):
    with pytest.raises(ValueError, match="bandwidth"):
        photon_fix.build_reference(photons, bandwidth=0.5)
    with pytest.raises(ValueError, match="in_reference"):
        photon_fix.build_reference(photons, in_reference=np.zeros(photons.size, bool))
    with pytest.raises(ValueError, match="offset_m"):
        photon_fix.displaced_phases(photons, [1.0, 2.0])
    with pytest.raises(ValueError, match="along_m"):
        photon_fix.offset_vector(photons, along_m=float("nan"))


@settings(max_examples=40, deadline=None)
@given(a=st.floats(-3e6, 3e6), b=st.floats(-3e6, 3e6), phase=st.floats(0.0, 0.999))
def test_displacements_add(a, b, phase):
    n = np.array([[0.6, 0.0, 0.8]])
    fake = photon_fix.Photons(np.array([phase]), np.ones(1), np.zeros(1), n, np.zeros((1, 3)),
                              np.array([205.53]), np.zeros((3, 3)))
    once = photon_fix.displaced_phases(fake, (a + b) * n[0])
    moved = photon_fix.Photons(photon_fix.displaced_phases(fake, a * n[0]), *[
        getattr(fake, k) for k in ("weights", "t", "direction", "r_geo_ssb", "spin_frequency",
                                   "components")])
    twice = photon_fix.displaced_phases(moved, b * n[0])
    assert abs(wrapped(once[0] - twice[0])) < 1e-9
    assert abs(wrapped(once[0] - phase - 205.53 * (a + b) / C)) < 1e-9


def _fake(n=4):
    return photon_fix.Photons(np.zeros(n), np.ones(n), np.arange(n) * photon_fix.MONTH,
                              np.tile([1.0, 0.0, 0.0], (n, 1)), np.zeros((n, 3)), np.full(n, 200.0),
                              np.zeros((3, 3)))


@pytest.mark.parametrize("bad", [True, -0.0, [], np.array(1.0)])
def test_photons_and_reference_are_refused_by_name_when_of_another_kind(bad):
    """Issue 35 (review 35h): a number or a list was an AttributeError from inside."""
    for call in (lambda: photon_fix.cycle_length(bad), lambda: photon_fix.offset_vector(bad, 1.0),
                 lambda: photon_fix.displaced_phases(bad, np.zeros(3)),
                 lambda: photon_fix.split_months(bad), lambda: photon_fix.build_reference(bad),
                 lambda: photon_fix.fix(bad, np.zeros(3), None)):
        with pytest.raises(ValueError, match=r"^photons must be a Photons \(from fermi_photons\(\)\)"):
            call()
    for call in (lambda: photon_fix.log_likelihood(_fake(), bad, [0.0]),
                 lambda: photon_fix.likelihood_scan(_fake(), bad),
                 lambda: photon_fix.estimate_offset(_fake(), bad),
                 lambda: photon_fix.fix(_fake(), np.zeros(3), bad)):
        with pytest.raises(ValueError, match=r"^reference must be a Reference \(from build_reference\(\)\)"):
            call()


@pytest.mark.parametrize("bad", [True, [], [0.5, True], np.zeros((1, 1)), [0.5, "a"]])
def test_template_coefficients_must_be_numbers(bad):
    """Issue 35 (review 35h): a bool was taken as the coefficient 1, an empty list as none."""
    with pytest.raises(ValueError, match=r"^coeffs must be a non-empty 1-D array of \(complex\) numbers"):
        photon_fix.template_density(bad, [0.0])
    assert photon_fix.template_density([0.5 + 0.0j], [0.0]).tolist() == [2.0]


def test_phases_are_one_per_photon_and_a_reference_is_of_these_photons(photons, reference):
    """Issue 35 (review 35h): phases=[] was numpy's broadcast error, a bool a phase of 1."""
    nav = photons.subset(~reference.in_reference)
    with pytest.raises(ValueError, match=r"^phases must be an array of finite numbers, got True"):
        photon_fix.estimate_offset(nav, reference, True)
    for bad in ([], np.zeros(3)):
        with pytest.raises(ValueError, match=rf"^phases must have shape \({nav.size},\) \(one phase per"):
            photon_fix.estimate_offset(nav, reference, bad)
    with pytest.raises(ValueError, match=rf"^reference must be built from these {nav.size} photons"):
        photon_fix.fix(nav, np.zeros(3), reference)


def test_template_density_refuses_masked_coefficients():
    """Review 35m (5) 1: the masked coefficients were used (its own complex check, not the
    shared array check); an array with no masked entry is its data."""
    phases = np.array([0.0, 0.25, 0.5])
    with pytest.raises(ValueError, match=r"^coeffs has masked entries"):
        photon_fix.template_density(np.ma.masked_array([0.5, 0.1], mask=[True, False]), phases)
    with pytest.raises(ValueError, match=r"^coeffs must be a non-empty 1-D array of \(complex\) "
                                         r"numbers, got \[0.5, masked\]"):
        photon_fix.template_density([0.5, np.ma.masked], phases)
    with pytest.raises(ValueError, match=r"^phases has masked entries: 1 of 3, the first phases\[1\]"):
        photon_fix.template_density([0.5], np.ma.masked_array(phases, mask=[False, True, False]))
    assert np.array_equal(photon_fix.template_density(np.ma.masked_array([0.5]), phases),
                          photon_fix.template_density([0.5], phases))
