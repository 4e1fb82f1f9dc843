"""Chapter 9's detector comparison as pictures: the shipped Monte Carlo table as heat maps.

The table (:func:`xnavlab.mars.studies.trials.load_detector_table`) holds, for every fault class, size
and sensor (a *cell*) and every detector, the probability of detection with its interval, the
trials flagged only after the fault's end (``late``), the delays, the false alarms per day and
the fused position RMS over the fault-free run of the same seed. Five numbers in 135 rows do not
read; these figures show one quantity at a time across all cells:

* :func:`cell_grid`: one quantity of one detector as a (cells, sensors) array, rows in the
  table's order (fault class, then size);
* :func:`plot_cell_maps`: one heat map per detector, a row per fault class and size, a column
  per sensor, each square annotated with its value (and its late trials for ``pd``);
* :func:`plot_false_alarms`: the false alarms per day of every cell, one strip per detector,
  against each detector's design rate;
* :func:`plot_signal_pd`: the white-noise trials of :func:`xnavlab.core.montecarlo.detection_table`
  (one panel per fault kind): the probability of detection and the share of late trials against
  the fault's size, per detector.

Examples
--------
>>> rows = [{"fault_class": "step", "sensor": s, "size": 3.0, "detector": "chi2", "pd": p,
...          "late": 0} for s, p in (("uv", 1.0), ("cns", 0.5), ("xnav", 0.25))]
>>> labels, values = cell_grid(rows, "pd", "chi2")
>>> labels, values.tolist()
(['step 3 σ'], [[1.0, 0.5, 0.25]])
"""

from __future__ import annotations

import numpy as np

from xnavlab.core.validate import (
    check_bool,
    check_choice,
    check_instance,
    check_items,
    check_real,
    check_records,
    shown,
)
from xnavlab.mars.studies.trials import FAULT_CLASSES

__all__ = ["SENSORS", "cell_label", "cell_grid", "plot_cell_maps", "plot_false_alarms",
           "plot_signal_pd"]

#: Columns of the maps, in the table's order.
SENSORS = ("uv", "cns", "xnav")
_SENSOR_NAMES = {"uv": "UV", "cns": "CNS", "xnav": "XNAV"}
_QUANTITIES = {
    "pd": ("probability of detection", 0.0, 1.0),
    "rms_ratio": ("fused RMS / fault-free", None, None),
    "false_alarms_per_day": ("false alarms per day", 0.0, None),
    "late_fraction": ("share flagged only after the end", 0.0, 1.0),
}


def cell_label(fault_class, size):
    """A cell's row label: the fault class and its size in the table's unit.

    Steps and spikes are in sigma of the sensor noise, ramps by the sigma reached at their
    end, noise faults by the total over the nominal noise, stuck outputs by their length.
    ``fault_class`` is one of :data:`xnavlab.mars.studies.trials.FAULT_CLASSES`.

    Examples
    --------
    >>> cell_label("ramp", 2.5), cell_label("noise", 3.0), cell_label("stuck", 600.0)
    ('ramp 2.5 σ', 'noise ×3', 'stuck 600 s')
    """
    check_choice("fault_class", fault_class, FAULT_CLASSES)  # 'stpe' was labelled 'stpe 3 σ'
    # a size in noise sigma or a stuck output's length, s: a year (3.2e7 s) at most
    size = check_real("size", size, 0.0, 1e8, lo_open=True)
    if fault_class == "noise":
        return f"noise ×{size:g}"
    if fault_class == "stuck":
        return f"stuck {size:g} s"
    return f"{fault_class} {size:g} σ"


def cell_grid(rows, key, detector):
    """One quantity of one detector over the table's cells.

    ``rows`` must be a list of detector-table rows; anything else is one ValueError naming
    ``rows`` or ``rows[i]``.

    Parameters
    ----------
    rows : sequence of dict
        The table's rows (``fault_class``, ``sensor``, ``size``, ``detector`` and ``key``).
    key : str
        The quantity, e.g. ``"pd"``, ``"rms_ratio"``, ``"false_alarms_per_day"``.
    detector : str
        Whose rows.

    Returns
    -------
    labels : list of str
        One per fault class and size (:func:`cell_label`), in the order the rows first give.
    values : ndarray, shape (len(labels), 3)
        Columns :data:`SENSORS`; NaN where the table has no value (e.g. no delay).
    """
    rows = check_records("rows", rows, ("fault_class", "size", "sensor", "detector"),
                         "detector_table row")
    mine = [r for r in rows if r["detector"] == detector]
    if not mine:
        raise ValueError(f"detector must be one of the table's detectors, got {detector!r}")
    keys = []
    for r in mine:
        k = (r["fault_class"], float(r["size"]))
        if k not in keys:
            keys.append(k)
    values = np.full((len(keys), len(SENSORS)), np.nan)
    for r in mine:
        v = r.get(key)
        if v is not None:
            values[keys.index((r["fault_class"], float(r["size"]))), SENSORS.index(r["sensor"])] = v
    return [cell_label(c, s) for c, s in keys], values


def plot_cell_maps(table, key="pd", detectors=("wavelet", "chi2", "combined"), *, log=False):
    """One heat map per detector: a row per fault class and size, a column per sensor.

    Parameters
    ----------
    table : dict
        The shipped table (:func:`xnavlab.mars.studies.trials.load_detector_table`): ``rows``.
    key : {"pd", "rms_ratio", "false_alarms_per_day", "late_fraction"}
        The quantity coloured and written in each square. With ``"pd"`` a square whose
        trials were flagged only after the fault's end also gives their number ("3 late").
    detectors : sequence of str
        One panel each, left to right.
    log : bool
        A logarithmic colour scale (for ``rms_ratio``, which spans 1 to tens).

    Returns
    -------
    matplotlib.figure.Figure
        Not registered with pyplot.

    Examples
    --------
    >>> rows = [{"fault_class": "step", "sensor": s, "size": 3.0, "detector": d, "pd": 0.5,
    ...          "late": 1} for s in SENSORS for d in ("wavelet", "chi2")]
    >>> fig = plot_cell_maps({"rows": rows}, detectors=("wavelet", "chi2"))
    >>> len(fig.axes)
    3
    """
    import matplotlib
    from matplotlib.colors import LogNorm, Normalize
    from matplotlib.figure import Figure

    rows = _table_rows(table, ("fault_class", "size", "sensor", "detector"))
    check_choice("key", key, tuple(_QUANTITIES))
    detectors = _detectors(detectors, rows)  # a string is no list
    log = check_bool("log", log)
    grids = {d: cell_grid(rows, key, d) for d in detectors}
    name, lo, hi = _QUANTITIES[key]
    allv = np.concatenate([g[1].ravel() for g in grids.values()])
    allv = allv[np.isfinite(allv)]
    lo = float(allv.min()) if lo is None else lo
    hi = float(allv.max()) if hi is None else hi
    norm = LogNorm(max(lo, 1e-3), max(hi, 1.001 * max(lo, 1e-3))) if log else Normalize(lo, hi)
    labels = next(iter(grids.values()))[0]
    fig = Figure(figsize=(3.1 * len(detectors) + 1.4, 0.33 * len(labels) + 1.3))
    axes = fig.subplots(1, len(detectors), sharey=True, squeeze=False)
    cmap = matplotlib.colormaps["viridis"]
    for ax, det in zip(axes[0], detectors, strict=True):
        _, v = grids[det]
        image = ax.imshow(np.ma.masked_invalid(v), cmap=cmap, norm=norm, aspect="auto")
        late = cell_grid(rows, "late", det)[1] if key == "pd" else None
        for i in range(v.shape[0]):
            for j in range(v.shape[1]):
                if not np.isfinite(v[i, j]):
                    ax.text(j, i, "-", ha="center", va="center", fontsize=7)
                    continue
                text = f"{v[i, j]:.2f}" if v[i, j] < 10 else f"{v[i, j]:.0f}"
                if late is not None and np.isfinite(late[i, j]) and late[i, j] > 0:
                    text += f"  ({late[i, j]:.0f} late)"
                light = norm(v[i, j]) < 0.55
                ax.text(j, i, text, ha="center", va="center", fontsize=6.5,
                        color="white" if light else "black")
        ax.set_xticks(range(len(SENSORS)), [_SENSOR_NAMES[s] for s in SENSORS])
        ax.set_title(det)
        for k in range(1, v.shape[0]):
            if labels[k].split()[0] != labels[k - 1].split()[0]:
                ax.axhline(k - 0.5, color="white", lw=1.5)
    axes[0, 0].set_yticks(range(len(labels)), labels)
    axes[0, 0].set_ylabel("fault class and size")
    fig.colorbar(image, ax=list(axes[0]), shrink=0.9, label=name)
    return fig


def plot_false_alarms(table, design, detectors=("wavelet", "chi2", "combined")):
    """The false alarms per day of every cell, one strip per detector, and its design rate.

    Parameters
    ----------
    table : dict
        The shipped table: ``rows`` with ``false_alarms_per_day`` (all subsystems together,
        per armed day of the one-day runs).
    design : dict of str to float
        Each detector's design rate, false alarms per day for the three subsystems together,
        drawn as a short line across its strip.
    detectors : sequence of str
        One strip each, left to right.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> rows = [{"detector": "chi2", "false_alarms_per_day": f} for f in (0.2, 0.6, 1.0)]
    >>> fig = plot_false_alarms({"rows": rows}, {"chi2": 0.58}, detectors=("chi2",))
    >>> fig.axes[0].get_ylabel()
    'false alarms per day (all subsystems)'
    """
    from matplotlib.figure import Figure

    rows = _table_rows(table, ("detector", "false_alarms_per_day"))
    check_instance("design", design, dict, "a dict of detector -> false alarms per day")
    for det, rate in design.items():  # at most one alarm a sample: 1e6 a day is 0.09 s samples
        check_real(f"design[{det!r}]", rate, 0.0, 1e6)
    detectors = _detectors(detectors, rows)
    rng = np.random.default_rng(0)              # the strips' horizontal jitter only
    n = table.get("trials")
    cell = f"a cell ({n} one-day runs)" if n else "a cell"
    fig = Figure(figsize=(6.4, 3.6))
    ax = fig.add_subplot()
    for i, det in enumerate(detectors):
        fa = np.array([r["false_alarms_per_day"] for r in rows if r["detector"] == det])
        ax.plot(i + rng.uniform(-0.18, 0.18, fa.size), fa, "o", ms=4, alpha=0.6, color=f"C{i}",
                label=cell if i == 0 else None)
        ax.plot([i - 0.3, i + 0.3], [np.mean(fa)] * 2, color="k", lw=2,
                label="mean over the cells" if i == 0 else None)
        if det in design:
            ax.plot([i - 0.3, i + 0.3], [design[det]] * 2, color="C3", lw=2, ls="--",
                    label="design rate" if i == 0 else None)
    ax.set_xticks(range(len(detectors)), list(detectors))
    ax.set_xlim(-0.6, len(detectors) - 0.4 + 1.1)
    ax.set_ylabel("false alarms per day (all subsystems)")
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    return fig


def plot_signal_pd(rows, detectors=("wavelet", "chi2")):
    """Probability of detection and share of late trials against the fault size, per kind.

    Parameters
    ----------
    rows : sequence of dict
        :func:`xnavlab.core.montecarlo.detection_table` rows: ``kind``, ``size_sigma`` and,
        per detector, ``{det}_pd`` and ``{det}_late``.
    detectors : sequence of str
        One colour each.

    Returns
    -------
    matplotlib.figure.Figure
        One panel per kind, in the rows' order: Pd solid with dots, the late share dashed.

    Examples
    --------
    >>> rows = [{"kind": "step", "size_sigma": s, "wavelet_pd": p, "wavelet_late": 0.0,
    ...          "chi2_pd": 1.0, "chi2_late": 0.0} for s, p in ((2.0, 0.1), (4.0, 0.9))]
    >>> fig = plot_signal_pd(rows)
    >>> [ax.get_title() for ax in fig.axes]
    ['step']
    """
    from matplotlib.figure import Figure

    rows = check_records("rows", rows, ("kind", "size_sigma"), "detection_table row")
    if not rows:
        raise ValueError("rows must hold at least one detection_table row, got an empty list")

    def has_columns(label, det):
        missing = [f"{det}_{c}" for c in ("pd", "late") if not all(f"{det}_{c}" in r for r in rows)]
        if missing:
            raise ValueError(f"{label} must be a detector whose columns the rows hold, got "
                             f"{shown(det)} (no {missing[0]} in every row)")
        return det

    detectors = check_items("detectors", detectors, "detector", has_columns)
    kinds = list(dict.fromkeys(r["kind"] for r in rows))
    fig = Figure(figsize=(2.6 * len(kinds) + 0.8, 3.2), layout="constrained")
    axes = fig.subplots(1, len(kinds), sharey=True, squeeze=False)[0]
    for ax, kind in zip(axes, kinds, strict=True):
        mine = sorted((r for r in rows if r["kind"] == kind), key=lambda r: r["size_sigma"])
        size = [r["size_sigma"] for r in mine]
        for i, det in enumerate(detectors):
            ax.plot(size, [r[f"{det}_pd"] for r in mine], "o-", color=f"C{i}",
                    label=f"{det}: detected")
            ax.plot(size, [r[f"{det}_late"] for r in mine], "x--", color=f"C{i}", alpha=0.7,
                    label=f"{det}: late")
        ax.set(title=kind, xscale="log", xlabel="fault size (noise sigma)", ylim=(-0.05, 1.05))
        ax.set_xticks(size, [f"{v:g}" for v in size])
        ax.minorticks_off()
    axes[0].set_ylabel("share of trials")
    fig.legend(*axes[0].get_legend_handles_labels(), loc="outside lower center",
               ncol=2 * len(detectors), fontsize=8)
    return fig


def _table_rows(table, keys):
    """The rows of a detector table (a dict with ``rows``), each holding ``keys``, else one
    ValueError naming ``table``."""
    if not isinstance(table, dict) or "rows" not in table:  # a list of rows was a TypeError
        raise ValueError(f"table must be a dict with the key 'rows' (a detector table), got "
                         f"{shown(table)}")
    rows = check_records("table['rows']", table["rows"], keys, "detector_table row")
    if not rows:
        raise ValueError("table['rows'] must hold at least one detector_table row, got an empty list")
    return rows


def _detectors(detectors, rows):
    """``detectors`` as a tuple of the table's detectors, each at most once, else one
    ValueError naming ``detectors`` or ``detectors[i]``."""
    known = tuple(dict.fromkeys(r["detector"] for r in rows))
    return check_items("detectors", detectors, "detector",
                       lambda label, d: check_choice(label, d, known))
