"""Figures of pulsar photons: the paper's ranging accuracy and the fix from real photons.

Pure functions that return a :class:`matplotlib.figure.Figure` (not registered with pyplot):
:func:`plot_ranging_accuracy` (chapter 1's slider: the accuracy formula's bars for a detector
area, an observation time and a background), and for the one-dimensional fix from real photons
(:mod:`xnavlab.mars.timing.photon_fix`) :func:`plot_fix` (the slider of the page "Navigating with
real photons": the fold and the likelihood for one injected offset), :func:`plot_recovery`
(recovered against injected offsets), :func:`plot_ambiguity` (the cycle ambiguity) and
:func:`plot_exposure` (the error bar against exposure). Distances in the figures are km, or m
where the axis says so. The two sliders' figures carry an in-place update
(:func:`xnavlab.core.plotting.in_place`): the live slider changes their artists instead of
building a new figure.

Examples
--------
>>> x = np.linspace(-3e6, 3e6, 7)
>>> len(plot_ambiguity(x, (x + 7.3e5) % 1.46e6 - 7.3e5, 1.46e6).axes)
1
"""

from __future__ import annotations

import functools

import numpy as np

from xnavlab.core.plotting import in_place
from xnavlab.core.validate import check_finite_array, check_instance, check_real, check_shape, shown
from xnavlab.mars.timing import pulsars
from xnavlab.mars.timing.photon_fix import (
    Fix,
    build_reference,
    cycle_length,
    displaced_phases,
    fermi_photons,
    fix,
    likelihood_scan,
    log_likelihood,
    offset_vector,
    template_density,
)

__all__ = ["plot_fix", "plot_recovery", "plot_ambiguity", "plot_exposure", "plot_ranging_accuracy"]


@functools.cache
def _default():
    """The shipped photons and the reference of the even months (for the slider)."""
    photons = fermi_photons()
    return photons, build_reference(photons)


def _fold_axes(ax, nbins=64):
    """The fold panel's artists; :func:`_fold_update` gives them a fix's data."""
    counts = ax.step((np.arange(nbins) + 0.5) / nbins, np.zeros(nbins), where="mid", color="0.45",
                     lw=0.9, label="navigation photons, weighted")[0]
    expected = ax.plot([], [], color="C1", lw=1.2, label="template at the fix")[0]
    ax.set(xlabel="phase at the assumed position (cycles)", ylabel="weighted photons per bin",
           xlim=(0.0, 1.0))
    return counts, expected


def _fold_update(ax, artists, photons, reference, phases, estimate_m):
    """The navigation photons' weighted fold against the template moved by the estimate."""
    counts_line, expected_line = artists
    nbins = len(counts_line.get_xdata())
    phi = reference.corrected(photons, phases)
    w = photons.weights
    counts = np.histogram(phi, nbins, (0.0, 1.0), weights=w)[0]
    x = np.linspace(0.0, 1.0, 513)
    shift = estimate_m / cycle_length(photons)  # cycles
    dens = template_density(reference.coeffs, x - shift)
    expected = (np.sum(w**2) * dens + np.sum(w * (1.0 - w))) / nbins  # weighted photons per bin
    counts_line.set_ydata(counts)
    expected_line.set_data(x, expected)
    ax.relim()
    ax.autoscale_view()


def plot_fix(offset_km=100.0, across_km=0.0):
    """The fix for one injected offset: the fold it sees, and the likelihood over offsets.

    A pure function of its arguments (the photons and the reference of the even months
    are read once and kept), for the page's slider.

    Parameters
    ----------
    offset_km : float
        Error of the assumed position along the line to the pulsar, km (-1e5 to 1e5).
    across_km : float
        Error across the line (east on the sky), km (-1e5 to 1e5).

    Returns
    -------
    matplotlib.figure.Figure
        Three axes: the navigation photons folded at the assumed position, with the template
        moved to the fix; the log-likelihood (eq. ch01-photon-like) against the offset over
        three cycles, its peaks ``c P`` apart; and the same near the fix, with its 2-sigma
        interval. Not registered with pyplot.

    Examples
    --------
    >>> fig = plot_fix(100.0)   # doctest: +SKIP
    >>> len(fig.axes)           # doctest: +SKIP
    3
    """
    from matplotlib.figure import Figure

    offset_km = check_real("offset_km", offset_km, -1e5, 1e5)  # the checked floats, as drawn below
    across_km = check_real("across_km", across_km, -1e5, 1e5)
    photons, ref = _default()
    nav = photons.subset(~ref.in_reference)
    fig = Figure(figsize=(11, 3.4), layout="constrained")
    ax1, ax2, ax3 = fig.subplots(1, 3, width_ratios=(1.0, 1.2, 0.8))
    fold = _fold_axes(ax1)
    ax1.legend(fontsize=7, loc="upper left")
    scan_line, = ax2.plot([], [], color="C0", lw=0.8)
    ax2.set(xlabel="offset along the line (km)", ylabel="log-likelihood - max")
    marks = []  # the truth, its aliases and the fix: their number changes with the offset
    near_line, = ax3.plot([], [], color="C0", lw=1.0)
    band = ax3.axvspan(0.0, 1.0, color="C1", alpha=0.15, label="fix, 2 sigma")
    truth_line = ax3.axvline(0.0, color="k", lw=0.8, label="injected (one cycle)")
    ax3.set(xlabel="offset along the line (km)", ylabel="log-likelihood - max")
    ax3.legend(fontsize=7, loc="lower center")

    def update(offset_km=100.0, across_km=0.0):
        offset_km = check_real("offset_km", offset_km, -1e5, 1e5)
        across_km = check_real("across_km", across_km, -1e5, 1e5)
        dr = offset_vector(photons, offset_km * 1e3, across_km * 1e3)
        f = fix(photons, dr, ref)
        phases = displaced_phases(nav, dr)
        cycle_km = f.cycle_m / 1e3
        offsets, scan = likelihood_scan(nav, ref, phases, bins=4096)
        near = f.along_m + np.linspace(-4.0, 4.0, 81) * f.sigma_m
        like = log_likelihood(nav, ref, near, phases)
        _fold_update(ax1, fold, nav, ref, phases, f.along_m)
        tiled = np.concatenate([offsets + k * f.cycle_m for k in (-2, -1, 0, 1)]) / 1e3
        scan_line.set_data(tiled, np.tile(scan - scan.max(), 4))
        while marks:
            marks.pop().remove()
        for k in range(-3, 4):  # the truth and its aliases, c P apart
            x = f.truth_along_m / 1e3 + k * cycle_km
            if abs(x) <= 1.5 * cycle_km:
                marks.append(ax2.axvline(x, color="k", lw=0.8, ls="-" if k == 0 else ":",
                                         label="injected" if k == 0 else None))
        marks.append(ax2.plot([], [], "k:", lw=0.8, label="injected + k c P")[0])
        marks.append(ax2.axvline(f.along_m / 1e3, color="C1", lw=1.2, ls="--", label="fix"))
        ax2.set_xlim(-1.5 * cycle_km, 1.5 * cycle_km)
        ax2.relim()
        ax2.autoscale_view()
        ax2.legend(fontsize=7, loc="lower left")  # its entries follow the marks drawn
        near_line.set_data(near / 1e3, like - like.max())
        band.set_x((f.along_m - 2 * f.sigma_m) / 1e3)
        band.set_width(4 * f.sigma_m / 1e3)
        truth_line.set_xdata([f.wrapped_truth_m / 1e3] * 2)
        ax3.relim()
        ax3.autoscale_view()
        fig.suptitle(f"injected {offset_km:,.0f} km along, {across_km:,.0f} km across: fix "
                     f"{f.along_m / 1e3:,.1f} ± {2 * f.sigma_m / 1e3:.1f} km (2 sigma)",
                     fontsize=10)

    update(offset_km, across_km)
    return in_place(fig, update)


def plot_recovery(injected_m, fixes, across=None):
    """Recovered offsets against injected ones, with 2-sigma bars.

    Parameters
    ----------
    injected_m : array_like, shape (k,)
        Injected offsets along the line, m.
    fixes : sequence of Fix
        The fixes, one per injected offset.
    across : tuple of (float, Fix), optional
        An offset across the line (m) and its fix, drawn last on the right.

    Returns
    -------
    matplotlib.figure.Figure
        Two axes: recovered against injected (km), and recovered minus injected (km) for
        each fix, each with its 2-sigma bar.

    Examples
    --------
    >>> from xnavlab.mars.timing.photon_fix import Fix
    >>> fx = Fix(1.0e4 + 300.0, 800.0, 600.0, 500.0, 20.0, 1.0e4, 1.4586e6, 3000, 2000.0)
    >>> fig = plot_recovery([1.0e4], [fx])
    >>> fig.axes[0].get_xlabel()
    'injected offset along the line (km)'
    """
    from matplotlib.figure import Figure

    inj = _offsets("injected_m", injected_m) / 1e3
    if not isinstance(fixes, list | tuple):
        raise ValueError(f"fixes must be a list of Fix (from fix()), got {shown(fixes)}")
    for i, f in enumerate(fixes):
        check_instance(f"fixes[{i}]", f, Fix, "a Fix (from fix())")
    if len(fixes) != inj.size:
        raise ValueError(f"fixes must hold one Fix per injected offset ({inj.size}), got {len(fixes)}")
    if across is not None:
        check_instance("across", across, tuple | list, "a pair (offset_m, Fix)")
        if len(across) != 2:
            raise ValueError(f"across must be a pair (offset_m, Fix), got {shown(across)}")
        check_real("across[0]", across[0])
        check_instance("across[1]", across[1], Fix, "a Fix (from fix())")
    rec = np.array([f.along_m for f in fixes]) / 1e3
    bar = np.array([2.0 * f.sigma_m for f in fixes]) / 1e3
    fig = Figure(figsize=(10, 3.4), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2)
    lim = 1.1 * max(np.abs(inj).max(), 1.0)
    ax1.plot([-0.1 * lim, lim], [-0.1 * lim, lim], color="0.6", lw=0.8, label="recovered = injected")
    ax1.errorbar(inj, rec, bar, fmt="o", color="C0", ms=4, capsize=3, label="held-out fix, 2 sigma")
    ax2.axhline(0.0, color="0.6", lw=0.8)
    pos = np.arange(inj.size)
    ax2.errorbar(pos, rec - inj, bar, fmt="o", color="C0", ms=4, capsize=3, label="along the line")
    labels = [f"{v:,.0f} along" for v in inj]
    if across is not None:
        dist, fx = across
        ax2.errorbar([inj.size], [fx.along_m / 1e3], [2.0 * fx.sigma_m / 1e3], fmt="s", color="C3",
                     ms=5, mfc="none", capsize=3, label="across the line (reads 0 along)")
        labels.append(f"{dist / 1e3:,.0f} across")
    ax2.set_xticks(range(len(labels)), labels)
    ax1.set(xlabel="injected offset along the line (km)", ylabel="recovered offset (km)")
    ax2.set(xlabel="injected offset (km)", ylabel="recovered - injected along (km)",
            xlim=(-0.5, len(labels) - 0.5))
    ax2.margins(y=0.4)
    ax1.legend(fontsize=8, loc="upper left")
    ax2.legend(fontsize=8, loc="upper center", ncols=2)
    return fig


def plot_ambiguity(injected_m, recovered_m, cycle_m):
    """The cycle ambiguity: the fix against the injected offset over several cycles.

    Parameters
    ----------
    injected_m, recovered_m : array_like, shape (k,)
        Injected offsets along the line (at least 2) and their fixes, m.
    cycle_m : float
        ``c P``, m, in [3e4, 1e12] (``P`` from 1e-4 s, the shortest period of a
        :class:`~xnavlab.mars.timing.pulsars.Pulsar`) and at least 1e-4 of the injected span
        (at most 10,000 whole-cycle lines are drawn).

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> x = np.linspace(-3e6, 3e6, 7)
    >>> fig = plot_ambiguity(x, (x + 7.3e5) % 1.46e6 - 7.3e5, 1.46e6)
    >>> fig.axes[0].get_ylabel()
    'fix (km)'
    """
    from matplotlib.figure import Figure

    inj = _offsets("injected_m", injected_m) / 1e3
    if inj.size < 2:  # one offset draws no curve across the cycles
        raise ValueError(f"injected_m must hold at least 2 offsets, got {inj.size}")
    rec = check_shape("recovered_m", recovered_m, inj.shape, "one fix per injected offset") / 1e3
    # c times a period of 1e-4 s (5e-324 looped for ever) to 3,300 s, past every pulsar's (1e308
    # overflowed the plot's transform)
    cycle_km = check_real("cycle_m", cycle_m, 3e4, 1e12) / 1e3
    span = float(np.ptp(inj))
    if span / cycle_km > 1e4:
        raise ValueError(f"cycle_m must be at least 1e-4 of the injected span ({span * 1e3:.6g} m): "
                         f"at most 10,000 whole-cycle lines are drawn, got {cycle_km * 1e3:.6g}")
    fig = Figure(figsize=(7, 3.4), layout="constrained")
    ax = fig.add_subplot()
    ax.plot(inj, inj, color="0.7", lw=0.8, label="injected")
    ax.plot(inj, rec, ".", color="C0", ms=4, label="fix")
    for k in range(int(np.floor(inj.min() / cycle_km)), int(np.ceil(inj.max() / cycle_km)) + 1):
        ax.axvline(k * cycle_km, color="C3", lw=0.7, ls=":",
                   label="whole cycles, k c P" if k == 1 else None)
    ax.axhspan(-cycle_km / 2, cycle_km / 2, color="C0", alpha=0.07, label="what one pulsar can see")
    ax.set(xlabel="injected offset along the line (km)", ylabel="fix (km)")
    ax.legend(fontsize=8, loc="upper left")
    return fig


def plot_exposure(scaling, paper_m=None, total=None):
    """The fix's error bar against exposure: measured, stated and the formula.

    Parameters
    ----------
    scaling : dict
        From :func:`~xnavlab.mars.timing.photon_error.exposure_scaling`.
    paper_m : sequence of float, optional
        Ranging accuracies to shade as a band (m), e.g. the main paper's X-ray ones.
    total : tuple of (float, float, float), optional
        ``(n_photons, stated_m, formula_m)`` of the fix from all navigation photons.

    Returns
    -------
    matplotlib.figure.Figure
        Log-log axes: photons per set against the fix's standard deviation (m).

    Examples
    --------
    >>> s = {"n_photons": np.array([100.0, 400.0]), "measured_m": np.array([4e3, 2.1e3]),
    ...      "measured_unc": np.array([0.2, 0.3]), "stated_m": np.array([4e3, 2e3]),
    ...      "formula_m": np.array([5e3, 2.5e3]), "months": np.array([1, 4]),
    ...      "n_sets": np.array([40, 10])}
    >>> plot_exposure(s, paper_m=[109.0, 1866.0]).axes[0].get_yscale()
    'log'
    """
    from matplotlib.figure import Figure

    scaling = _scaling(scaling)
    if paper_m is not None:
        paper_m = _offsets("paper_m", paper_m)
    if total is not None:
        total = check_shape("total", total, (3,), "n_photons, stated_m, formula_m")
    n = scaling["n_photons"]
    fig = Figure(figsize=(7, 3.8), layout="constrained")
    ax = fig.add_subplot()
    meas = np.asarray(scaling["measured_m"])
    unc = np.asarray(scaling["measured_unc"]) * meas
    ax.errorbar(n, meas, unc, fmt="o", color="C0", ms=5, capsize=3,
                label="measured: scatter of the sets' fixes")
    ax.plot(n, scaling["stated_m"], "s", color="C1", mfc="none", ms=6,
            label="stated: photon statistics")
    n_line = np.geomspace(0.7 * n.min(), 1.4 * (total[0] if total is not None else n.max()), 50)
    k_formula = np.sqrt(np.mean(np.asarray(scaling["formula_m"]) ** 2 * n))  # sigma = k / sqrt(N)
    ax.plot(n_line, k_formula / np.sqrt(n_line), color="k", lw=1.0, ls="--",
            label="chapter 1's formula")
    if total is not None:
        ax.plot([total[0]], [total[1]], "D", color="C1", ms=6,
                label="stated, all navigation photons")
    if paper_m is not None:
        ax.axhspan(min(paper_m), max(paper_m), color="C2", alpha=0.15,
                   label="main paper: X-ray, 1 m$^2$, 500 s")
    ax.set(xscale="log", yscale="log", xlabel="photons per set",
           ylabel="fix standard deviation (m)")
    per_month = float(np.mean(n / np.asarray(scaling["months"], dtype=float)))  # photons a month
    top = ax.secondary_xaxis("top", functions=(lambda x: x / per_month, lambda m: m * per_month))
    top.set_xlabel("months of photons")
    ax.legend(fontsize=8, loc="lower left")
    return fig


_SCALING = ("n_photons", "measured_m", "measured_unc", "stated_m", "formula_m", "months")


def _offsets(name, value):
    """``value`` as a non-empty 1-D finite array, else one ValueError naming ``name``."""
    arr = check_finite_array(name, value)
    if arr.ndim != 1 or arr.size == 0:
        raise ValueError(f"{name} must be a non-empty 1-D array, got shape {arr.shape}")
    return arr


def _scaling(scaling):
    """The entries of :func:`~xnavlab.mars.timing.photon_error.exposure_scaling` that
    :func:`plot_exposure` draws, as 1-D arrays of one length, else one ValueError."""
    if not isinstance(scaling, dict) or any(k not in scaling for k in _SCALING):
        raise ValueError(f"scaling must be the dict of exposure_scaling() (with {', '.join(_SCALING)}), "
                         f"got {shown(scaling)}")
    out = {k: _offsets(f"scaling[{k!r}]", scaling[k]) for k in _SCALING}
    for k in _SCALING[1:]:
        check_shape(f"scaling[{k!r}]", out[k], out["n_photons"].shape, "one per set length")
    return out


def _check_reference(reference, names):
    """The marks of :func:`plot_ranging_accuracy`, one per name, m; else one ValueError naming
    ``reference`` or its entry (a float was a TypeError, a missing name a KeyError, an empty
    dict or an unknown name dropped in silence)."""
    if not isinstance(reference, dict) or not reference:
        raise ValueError(f"reference must be a non-empty dict of pulsar name -> ranging accuracy (m), "
                         f"got {shown(reference)}")
    for key in reference:
        if key not in names:
            raise ValueError(f"reference[{key!r}] marks no bar: the bars are {', '.join(names)}")
    missing = [n for n in names if n not in reference]
    if missing:
        raise ValueError(f"reference must hold a value for every bar, got none for {', '.join(missing)}")
    return [check_real(f"reference[{n!r}]", reference[n], 1e-3, 1e13) for n in names]


def plot_ranging_accuracy(area_m2=1.0, t_obs=500.0, background_ph_cm2_s=0.005, reference=None,
                          pulsar_names=pulsars.PAPER_PULSARS):
    """Bar chart of the ranging accuracies of a pulsar set
    (:func:`xnavlab.mars.timing.pulsars.ranging_accuracy`).

    A pure function of its arguments, for the chapter's slider.

    Parameters
    ----------
    area_m2, t_obs, background_ph_cm2_s : float
        As :func:`xnavlab.mars.timing.pulsars.ranging_accuracy` (m^2, s, ph/cm^2/s).
    reference : dict of str to float, optional
        Values to mark on the bars (m, each in [1e-3, 1e13]), e.g. the paper's at 1 m^2 and
        500 s: one for each pulsar of ``pulsar_names`` (keyed as written there), no other.
    pulsar_names : sequence of str
        The pulsars, one bar each (default the paper's four).

    Returns
    -------
    matplotlib.figure.Figure
        One log-scale axes; not registered with pyplot.

    Examples
    --------
    >>> fig = plot_ranging_accuracy(t_obs=2000.0)
    >>> [round(b.get_height()) for b in fig.axes[0].patches]
    [54, 172, 934, 163]
    """
    from matplotlib.figure import Figure

    from xnavlab.core.plotting import sparse_log_minors

    names = list(pulsars.check_names(pulsar_names, "pulsar_names"))
    if reference is not None:
        marks = _check_reference(reference, names)
    built = (reference, pulsar_names)
    fig = Figure(figsize=(6, 3.2), layout="constrained")
    ax = fig.add_subplot()
    bars = ax.bar(names, [1.0] * len(names), color="C0", label="xnavlab")
    if reference:
        ax.plot(names, marks, "k_", ms=30, mew=2,
                label="paper (1 m$^2$, 500 s)")
    ax.set(yscale="log", ylim=(1, 1e5), ylabel="ranging accuracy (m)")
    ax.legend(fontsize=8)
    sparse_log_minors(ax)

    def update(area_m2=1.0, t_obs=500.0, background_ph_cm2_s=0.005, reference=None,
               pulsar_names=pulsars.PAPER_PULSARS):
        if (reference, pulsar_names) != built:
            return False  # other bars or marks: a new figure
        ours = [pulsars.ranging_accuracy(n, area_m2, t_obs, background_ph_cm2_s) for n in names]
        # checked there: a Fraction or numpy scalar, a float
        area_m2, t_obs, background_ph_cm2_s = map(float, (area_m2, t_obs, background_ph_cm2_s))
        for bar, height in zip(bars, ours, strict=True):
            bar.set_height(height)
        ax.set_title(f"A = {area_m2:.3g} m$^2$, t = {t_obs:.4g} s, "
                     f"B = {background_ph_cm2_s:.3g} ph/cm$^2$/s")

    update(area_m2, t_obs, background_ph_cm2_s, reference, pulsar_names)
    return in_place(fig, update)
