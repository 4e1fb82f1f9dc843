"""How good is the fix from real photons: its error bar against exposure, and checked.

Three questions about :func:`xnavlab.mars.timing.photon_fix.fix`:

- :func:`exposure_scaling`: how does its error bar shrink with the number of photons (months
  of data)? Measured (the scatter of fixes from disjoint sets of months) and stated (the
  photon statistics, eq. ch01-photon-sigma), beside
- :func:`snr_range_sigma`: chapter 1's signal-to-noise formula (eq. ch1-snr) for the same
  counts;
- :func:`split_pulls`: is the stated error bar honest? Fixes over random splits of the
  months into reference and navigation photons, divided by their stated sigmas.

Units: m, counts of photons, months of :data:`xnavlab.mars.timing.photon_fix.MONTH`.

Examples
--------
>>> from xnavlab.mars.timing.photon_fix import Photons
>>> comps = np.array([[0.18, 0.05, 0.29], [0.61, 0.0174, 0.15], [0.43, 0.36, 0.56]])
>>> fake = Photons(*(np.zeros(1),) * 3, np.zeros((1, 3)), np.zeros((1, 3)), np.array([205.53]), comps)
>>> round(snr_range_sigma(4000.0, 2800.0, fake) / snr_range_sigma(1000.0, 700.0, fake), 6)
0.5
"""

from __future__ import annotations

import math

import numpy as np

from xnavlab.core.constants import KPC, C
from xnavlab.core.validate import check_instance, check_int, check_items, check_real, check_seeds
from xnavlab.mars.timing import pulsars
from xnavlab.mars.timing.photon_fix import (
    Photons,
    Reference,
    build_reference,
    estimate_offset,
    fix,
    split_months,
)

_PHOTONS = "a Photons (from fermi_photons())"

__all__ = ["exposure_scaling", "snr_range_sigma", "split_pulls"]


def snr_range_sigma(n_photons, weight_sum, photons):
    """Chapter 1's signal-to-noise formula (eq. ch1-snr) for a set of Fermi photons, as a range, m.

    As chapter 1 does for its yearly sets: the narrowest component of the shipped template is
    the pulse (width ``W`` its FWHM, its share of the pulsar's photons the pulsed fraction),
    every other photon is background, and :func:`xnavlab.mars.timing.pulsars.toa_sigma` gives
    ``sigma_TOA = W / (2 SNR)``; the range is ``c sigma_TOA``. It depends on the counts only.

    Parameters
    ----------
    n_photons : float
        Photons in the set, in [0.01, 1e11]: the photons beyond ``weight_sum`` are the background
        of an equivalent pulsar over 1e6 s on 1 m^2, which must stay at most 10 ph/cm^2/s.
    weight_sum : float
        Their weights' sum (photons from the pulsar), in [0.01, n_photons]: the equivalent
        pulsar's flux, ``weight_sum`` per 1e6 s on 1 m^2, is at least 1e-8 ph/m^2/s, the
        lower end of :class:`~xnavlab.mars.timing.pulsars.Pulsar`'s (a hundredth of a pulsed
        photon times nothing).
    photons : Photons
        For the template components and the period.

    Returns
    -------
    float
        m.

    Examples
    --------
    >>> comps = np.array([[0.18, 0.05, 0.29], [0.61, 0.0174, 0.15], [0.43, 0.36, 0.56]])
    >>> from xnavlab.mars.timing.photon_fix import Photons
    >>> fake = Photons(*(np.zeros(1),) * 3, np.zeros((1, 3)), np.zeros((1, 3)),
    ...                np.array([205.53]), comps)
    >>> round(snr_range_sigma(1000.0, 700.0, fake))   # m
    1327
    """
    n_photons = check_real("n_photons", n_photons, 0.01, 1e11)
    weight_sum = check_real("weight_sum", weight_sum, 0.01, n_photons)
    photons = check_instance("photons", photons, Photons, _PHOTONS)
    period = 1.0 / float(np.mean(photons.spin_frequency))
    comp = photons.components[np.argmin(photons.components[:, 1])]  # (phase, FWHM, amplitude)
    t_unit = 1.0e6  # s: the formula depends on the counts only
    equivalent = pulsars.Pulsar(name="J0030+0451", ra_deg=0.0, dec_deg=0.0, distance=KPC,
                                period=period, fdot=0.0, flux=weight_sum / t_unit,
                                pulsed_fraction=float(comp[2]), width=float(comp[1]) * period)
    background = (n_photons - weight_sum) / t_unit / 1.0e4  # ph/cm^2/s on 1 m^2
    return C * pulsars.toa_sigma(equivalent, area_m2=1.0, t_obs=t_unit,  # eq. (ch1-snr)
                                 background_ph_cm2_s=background)


def exposure_scaling(photons, reference, months=(1, 2, 3, 4, 6, 8), min_sets=4):
    """The fix's error bar against exposure: measured, stated and from the formula.

    The navigation months (those not in the reference) are cut into sets of ``m``
    consecutive navigation months for each ``m`` of ``months``; every set gives a fix at
    zero offset (:func:`~xnavlab.mars.timing.photon_fix.estimate_offset`). All sets share the reference,
    so their scatter
    about their mean measures the photon noise alone.

    Parameters
    ----------
    photons : Photons
    reference : Reference
    months : sequence of int
        Set lengths, in navigation months (each at least 1).
    min_sets : int
        Lengths that give fewer sets are left out (at least 2).

    Returns
    -------
    dict of ndarray, one entry per kept length
        ``months``; ``n_sets``; ``n_photons`` and ``weight_sum`` (mean per set);
        ``measured_m`` (the sets' standard deviation about their mean, m) and
        ``measured_unc`` (its relative uncertainty, ``1 / sqrt(2 (n_sets - 1))``);
        ``stated_m`` (root mean square of the sets' eq. ch01-photon-sigma, m);
        ``formula_m`` (root mean square of :func:`snr_range_sigma` over the sets, m);
        and ``estimates_m``, an object array of each length's fixes (m).

    Examples
    --------
    >>> from xnavlab.mars.timing.photon_fix import fermi_photons              # doctest: +SKIP
    >>> photons = fermi_photons(); ref = build_reference(photons)    # doctest: +SKIP
    >>> out = exposure_scaling(photons, ref, months=(2, 6))           # doctest: +SKIP
    >>> out["n_sets"].tolist()                                        # doctest: +SKIP
    [21, 7]
    """
    photons = check_instance("photons", photons, Photons, _PHOTONS)
    reference = check_instance("reference", reference, Reference, "a Reference (from build_reference())")
    if reference.in_reference.shape != (photons.size,):  # built from other photons
        raise ValueError(f"reference must be built from these {photons.size} photons, got one from "
                         f"{reference.in_reference.size}")
    min_sets = check_int("min_sets", min_sets, 2, 10**6)
    nav = photons.subset(~reference.in_reference)
    nav_months = np.unique(nav.month)
    rows = []
    for m in check_items("months", months, "set length",  # months[i], a repeat refused
                         lambda label, m: check_int(label, m, 1, nav_months.size)):
        m = int(m)
        n_sets = nav_months.size // m
        if n_sets < min_sets:
            continue
        est, stated, formula, counts, wsum = [], [], [], [], []
        for k in range(n_sets):
            sel = np.isin(nav.month, nav_months[k * m:(k + 1) * m])
            part = nav.subset(sel)
            d, s = estimate_offset(part, reference)
            est.append(d)
            stated.append(s)
            counts.append(part.size)
            wsum.append(part.weights.sum())
            formula.append(snr_range_sigma(part.size, part.weights.sum(), photons))
        est = np.array(est)
        rows.append((m, n_sets, np.mean(counts), np.mean(wsum), np.std(est, ddof=1),
                     1.0 / math.sqrt(2.0 * (n_sets - 1)), math.sqrt(np.mean(np.square(stated))),
                     math.sqrt(np.mean(np.square(formula))), est))
    keys = ("months", "n_sets", "n_photons", "weight_sum", "measured_m", "measured_unc", "stated_m",
            "formula_m")
    out = {key: np.array([r[i] for r in rows]) for i, key in enumerate(keys)}
    out["estimates_m"] = np.empty(len(rows), dtype=object)
    for i, r in enumerate(rows):
        out["estimates_m"][i] = r[-1]
    return out


def split_pulls(photons, seeds=range(16), bandwidth=0.004):
    """Is the stated error bar honest? Zero-offset fixes over random splits of the months.

    Each seed splits the months at random (:func:`~xnavlab.mars.timing.photon_fix.split_months`), builds a
    reference from
    one half and fixes the position, not displaced, from the other. Over many splits the
    fixes divided by their stated standard deviations (the pulls) should have a standard
    deviation of 1.

    Parameters
    ----------
    photons : Photons
    seeds : iterable of int
        One split per seed (at least 3).
    bandwidth : float
        As :func:`~xnavlab.mars.timing.photon_fix.build_reference`.

    Returns
    -------
    dict of ndarray
        ``along_m``, ``sigma_m`` and ``sigma_photons_m`` (the navigation photons' part) of
        each split's fix (m), and ``pulls``, ``along_m / sigma_m``.

    Examples
    --------
    >>> from xnavlab.mars.timing.photon_fix import fermi_photons    # doctest: +SKIP
    >>> out = split_pulls(fermi_photons(), seeds=range(4))   # doctest: +SKIP
    >>> out["pulls"].shape                                   # doctest: +SKIP
    (4,)
    """
    photons = check_instance("photons", photons, Photons, _PHOTONS)
    seeds = check_seeds("seeds", seeds, min_len=3)  # a repeat would count one split twice
    rows = []
    for seed in seeds:
        ref = build_reference(photons, split_months(photons, seed), bandwidth=bandwidth)
        f = fix(photons, np.zeros(3), ref)
        rows.append((f.along_m, f.sigma_m, f.sigma_photons_m))
    along, sigma, photons_only = np.array(rows).T
    return {"along_m": along, "sigma_m": sigma, "sigma_photons_m": photons_only, "pulls": along / sigma}
