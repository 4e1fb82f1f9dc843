"""The headline accuracies as Monte Carlo means with 95 % intervals, not single seeds.

A reviewer asks what a number is worth: the fused position error of one 30-day run with one
noise seed is one draw. :func:`headline_numbers` runs the paper's 30-day scenario over
``n_seeds`` noise seeds (default 32), fault-free and with the paper's fault schedule under the
combined detector, through the campaign machinery (:mod:`xnavlab.core.campaign`), and
returns for each quantity the mean over the seeds, its 95 % interval (Student t) and the
spread. The default campaign (32 seeds of 30 days from seed 2016, :data:`SHIPPED`) is
shipped with the package (:data:`RUNS_PATH`, written by ``python benchmarks/bench_headline.py
--write``: four minutes on two cores) and read, not computed; ``tests/mars/navigation/test_headline.py``
recomputes its first runs from their seeds, so a change of the code that moves them fails
there until the table is written again. Any other campaign is stored in a resumable campaign
directory under the truth cache (``$XNAVLAB_CACHE/campaigns``), keyed by the code, and
computed once.

Quantities (metres and metres per second, RMS after day 1, as the paper's figures):
``fused_position_m``, ``fused_velocity_mps`` of the fault-free run (the paper: 28.835 m,
0.02149 m/s, one run), the same of the faulty run with detection and isolation
(``faulty_position_m``, ``faulty_velocity_mps``; the paper: 36.587 m, 0.02293 m/s), the
local filters' position errors of the fault-free run (``local_position_m.xnav``, ``.uv``,
``.cns``) and the faulty-to-clean ratio of the fused position error per seed
(``fault_ratio``). With faults, each seed also runs the paper's own set-up of Figs. 3 and 4,
whose numbers the paper reports from one run: its schedule with no detector
(``ekf_max_position_m``, beside the fault-free ``clean_max_position_m``) and with the wavelet
detector (``wavelet_position_m``, ``wavelet_velocity_mps``, ``wavelet_ratio`` to the fault-free
run, ``wavelet_detected_fraction`` of the faults, ``wavelet_connected_at_end``).

Examples
--------
>>> h = headline_numbers(n_seeds=2, days=0.2, faults=False, cache=False, workers=1)
>>> sorted(h["quantities"])[:2], h["n_seeds"]
(['fused_position_m', 'fused_velocity_mps'], 2)
"""

from __future__ import annotations

import contextlib
import math
from importlib import resources
from pathlib import Path

import numpy as np

from xnavlab.core.campaign import Campaign, run_campaign
from xnavlab.core.diskcache import cache_dir, code_digest, exclusive
from xnavlab.core.distributions import t_ppf
from xnavlab.core.userfiles import as_path, load_table
from xnavlab.core.validate import check_bool, check_int, check_real, check_records, check_seed, check_vector

__all__ = ["PAPER", "SHIPPED", "RUNS_PATH", "headline_run", "headline_numbers",
           "headline_records", "load_shipped", "mean_interval", "numbers_of"]

#: The paper's single-run values (Fan et al. 2016, section 4.2, Figs. 2 and 4).
PAPER = {"fused_position_m": 28.835, "fused_velocity_mps": 0.02149,
         "faulty_position_m": 36.587, "faulty_velocity_mps": 0.02293}

#: The campaign shipped in :data:`RUNS_PATH`: :func:`headline_numbers`' defaults (also
#: :func:`headline_records`' arguments).
SHIPPED = {"n_seeds": 32, "days": 30.0, "faults": True, "seed": 2016}

#: The shipped runs of :data:`SHIPPED` (``python benchmarks/bench_headline.py --write``).
RUNS_PATH = Path(str(resources.files("xnavlab").joinpath("data/headline_runs.json")))


def headline_run(*, seed, days=30.0, faults=True):
    """One seed of the headline campaign: the fault-free run and, if ``faults``, the faulty one.

    Parameters
    ----------
    seed : int
        Noise seed of the scenario (the faulty run draws its extra noise from it too).
    days : float
        Run length, days, in (0, 30]; the RMS is taken after ``min(1, days / 2)`` days.
    faults : bool
        Also run the paper's fault schedule (needs the 30 days) under the combined detector.

    Returns
    -------
    dict
        JSON-ready metrics (see the module docstring).
    """
    from xnavlab.mars.faults import fault_tolerance
    from xnavlab.mars.navigation import scenarios

    days = check_real("days", days, 0.0, 30.0, lo_open=True)
    seed = check_seed("seed", seed)
    faults = check_bool("faults", faults)
    sc = scenarios.MarsScenario(days=days, seed=seed % 2**31)
    inputs = scenarios.prepare(sc)
    clean = scenarios.run(inputs=inputs)
    m = clean.metrics()
    after = clean.t_days >= m["settle_days"]
    out = {"fused_position_m": m["position_error_m"], "fused_velocity_mps": m["velocity_error_mps"]}
    for i, s in enumerate(sc.subsystems):
        err = np.linalg.norm(clean.x_local[after, i, :3] - clean.truth[after, :3], axis=1)
        out[f"local_position_m.{s}"] = float(np.sqrt(np.mean(err**2)))
    if faults:
        ft = fault_tolerance.run_fault_tolerant(faults="paper", detector="combined", inputs=inputs)
        fm = ft.run.metrics()
        out.update(faulty_position_m=fm["position_error_m"],
                   faulty_velocity_mps=fm["velocity_error_mps"],
                   fault_ratio=fm["position_error_m"] / m["position_error_m"])
        out.update(_paper_detectors(inputs, m))
    return out


def _paper_detectors(inputs, clean):
    """The paper's Figs. 3 and 4 for one seed: its schedule with no detector and with the wavelet.

    The paper reports each from one run; these are the single runs the reproductions judge its
    numbers against (``mars-faults-ekf``, ``mars-faults-wavelet``).
    """
    from xnavlab.mars.faults import fault_tolerance

    none = fault_tolerance.run_fault_tolerant(faults="paper", detector="none", inputs=inputs)
    wav = fault_tolerance.run_fault_tolerant(faults="paper", detector="wavelet", inputs=inputs)
    wm = wav.run.metrics()
    found = sum(math.isfinite(d["delay"]) for d in wav.delays())
    return {"ekf_max_position_m": none.run.metrics()["position_error_max_m"],
            "clean_max_position_m": clean["position_error_max_m"],
            "wavelet_position_m": wm["position_error_m"],
            "wavelet_velocity_mps": wm["velocity_error_mps"],
            "wavelet_ratio": wm["position_error_m"] / clean["position_error_m"],
            "wavelet_detected_fraction": found / len(wav.faults),
            "wavelet_connected_at_end": float(not wav.isolated[-1].any())}


def mean_interval(values, level=0.95):
    """Mean, ``level`` interval of the mean (Student t) and standard deviation of ``values``.

    ``values``: a 1-D array of at least two finite real numbers (a NaN, a complex number, text
    or a table is refused by name, not cast).

    Examples
    --------
    >>> r = mean_interval([1.0, 2.0, 3.0])
    >>> r["mean"], round(r["lo"], 3), round(r["hi"], 3)
    (2.0, -0.484, 4.484)
    >>> mean_interval([1.0])
    Traceback (most recent call last):
    ...
    ValueError: values must hold at least two numbers (shape (n,), n >= 2), got 1
    """
    v = check_vector("values", values)
    if v.size < 2:
        raise ValueError(f"values must hold at least two numbers (shape (n,), n >= 2), got "
                         f"{v.size}")
    level = check_real("level", level, 0.0, 1.0, lo_open=True, hi_open=True)
    sd = float(v.std(ddof=1))
    half = t_ppf(0.5 + level / 2, v.size - 1) * sd / math.sqrt(v.size)
    mean = float(v.mean())
    return {"mean": mean, "lo": mean - half, "hi": mean + half, "sd": sd, "n": int(v.size)}


def _code_key():
    """A hash of the code that computes the campaign (this module and everything it imports,
    :func:`~xnavlab.core.diskcache.code_digest`): a stored campaign is reused only for it."""
    return code_digest((__name__,))


def load_shipped(path=None):
    """The shipped runs: ``{"campaign": SHIPPED, "runs": [{"index", "seed", "metrics"}],
    "command": str, ...}``, one per seed in index order; a file that is not such a table (a
    missing run, a run without its metrics, another campaign) is one ValueError.

    Examples
    --------
    >>> data = load_shipped()
    >>> len(data["runs"]) == SHIPPED["n_seeds"], sorted(data["runs"][0])
    (True, ['index', 'metrics', 'seed'])
    """
    path = RUNS_PATH if path is None else as_path(path, "path")  # a dict: one line
    data = load_table(path, "path, the headline runs", (".json",))  # the user's name first
    what = f"path, the headline runs {str(path)!r},"
    if data.get("campaign") != SHIPPED:
        raise ValueError(f"{what} must hold the campaign {SHIPPED}, got {data.get('campaign')}")
    runs = data.get("runs")
    if not isinstance(runs, list) or [r.get("index") if isinstance(r, dict) else None
                                      for r in runs] != list(range(SHIPPED["n_seeds"])):
        raise ValueError(f"{what} must hold runs 0 to {SHIPPED['n_seeds'] - 1} in order")
    for r in runs:
        m = r.get("metrics")
        if (not isinstance(m, dict) or not m or not isinstance(r.get("seed"), int)
                or not all(isinstance(v, (int, float)) and math.isfinite(v) for v in m.values())):
            raise ValueError(f"{what} run {r['index']} must hold its seed and finite metrics")
    return data


def _check_days(days, faults):
    days = check_real("days", days, 0.0, 30.0, lo_open=True)
    if faults and days < 30.0:
        raise ValueError(f"faults needs days = 30 (the paper's schedule runs to 27.84 days), "
                         f"got {days:g}")
    return days


def headline_numbers(n_seeds=32, days=30.0, faults=True, seed=2016, cache=True, workers=2,
                     progress=False, shipped=True):
    """The headline accuracies over ``n_seeds`` noise seeds, with 95 % intervals.

    Parameters
    ----------
    n_seeds : int
        Number of seeds, 2 to 10000 (default 32).
    days : float
        Run length, days (30: the paper's); ``faults`` needs 30.
    faults : bool
        Include the paper's fault schedule under the combined detector.
    seed : int
        The campaign's seed (run ``i``'s noise seed is drawn from it by index).
    cache : bool
        Store the runs under ``$XNAVLAB_CACHE/campaigns`` (default ``~/.cache/xnavlab``) and
        reuse them; the directory's name holds a hash of the package's code.
    workers : int
        Local worker processes.
    progress : bool
        A progress bar on stderr.
    shipped : bool
        Read the shipped runs (:func:`load_shipped`) when the campaign is :data:`SHIPPED`
        (default); False computes it (``bench_headline.py --write`` does).

    Returns
    -------
    dict
        ``quantities``: name -> :func:`mean_interval` dict (``mean``, ``lo``, ``hi``, ``sd``,
        ``n``); ``runs``: name -> the single runs' values, one per seed (the paper's
        single-run numbers are judged against these); ``paper``: :data:`PAPER`; ``n_seeds``,
        ``days``, ``seed``; ``directory`` (the store, or None); ``source``: ``"shipped"`` or
        ``"computed"``.
    """
    n_seeds = check_int("n_seeds", n_seeds, 2, 10_000)
    faults, cache, progress, shipped = (check_bool(n, v) for n, v in (
        ("faults", faults), ("cache", cache), ("progress", progress), ("shipped", shipped)))
    days = _check_days(days, faults)
    if shipped and {"n_seeds": n_seeds, "days": days, "faults": bool(faults),
                    "seed": seed} == SHIPPED:
        return _numbers([r["metrics"] for r in load_shipped()["runs"]], days, seed, None,
                        "shipped")
    out = None
    if cache:
        out = (cache_dir() / "campaigns"
               / f"headline-{_code_key()}-{days:g}d-{int(faults)}-{seed}")
    records = headline_records(n_seeds, days, faults, seed, out=out, workers=workers,
                               progress=progress)
    runs = [r["metrics"] for r in records]
    if len(runs) < 2:
        raise ValueError(f"only {len(runs)} of {n_seeds} headline runs succeeded")
    return _numbers(runs, days, seed, None if out is None else str(out), "computed")


def headline_records(n_seeds=32, days=30.0, faults=True, seed=2016, out=None, workers=2,
                     progress=False):
    """The campaign's successful runs, computed (or resumed from the store ``out``).

    Parameters are :func:`headline_numbers`'; ``out`` is the campaign's directory, a str or
    an os.PathLike (None: in memory).

    Returns
    -------
    list of dict
        ``{"index", "seed", "metrics"}`` per successful run, in index order: the records
        :data:`RUNS_PATH` ships.
    """
    faults, progress = check_bool("faults", faults), check_bool("progress", progress)
    days = _check_days(days, faults)  # else every run failed: an empty list (review 35j)
    out = None if out is None else as_path(out, "out", "folder")  # a str too (review 35j)
    camp = Campaign("headline", headline_run, lambda i: {"days": days, "faults": bool(faults)},
                    manifest={"days": days, "faults": bool(faults), "code": _code_key()})
    with contextlib.nullcontext() if out is None else exclusive(out):
        res = run_campaign(camp, n_seeds, seed=seed, out=out, engine="local" if workers > 1
                           else "serial", workers=workers, progress=progress)
    return [{"index": r["index"], "seed": r["seed"], "metrics": r["metrics"]}
            for r in sorted(res.runs(), key=lambda r: r["index"]) if r["status"] == "ok"]


def numbers_of(runs):
    """Each quantity's :func:`mean_interval` over the runs' metrics (a list of dicts); a
    quantity that is not two finite numbers or more is named in the message, and so is a run
    whose quantities differ from the first run's (a missing one was a KeyError, an extra one
    dropped in silence)."""
    runs = check_records("runs", runs, what="metrics record")
    if not runs:
        raise ValueError("runs must hold the metrics of at least two runs, got an empty list")
    for i, r in enumerate(runs):
        if set(r) != set(runs[0]):
            odd = sorted(set(r) ^ set(runs[0]))
            raise ValueError(f"runs[{i}] must hold the quantities of runs[0], but {odd[0]!r} is in "
                             f"{'runs[0]' if odd[0] in runs[0] else f'runs[{i}]'} only")
    out = {}
    for k in sorted(runs[0]):
        try:
            out[k] = mean_interval([r[k] for r in runs])
        except ValueError as exc:
            raise ValueError(f"runs' {k}: {exc}") from None
    return out


def _numbers(runs, days, seed, directory, source):
    """:func:`headline_numbers`' dictionary from the runs' metrics."""
    names = sorted(runs[0])
    return {"quantities": numbers_of(runs),
            "runs": {k: [r[k] for r in runs] for k in names},
            "paper": dict(PAPER), "n_seeds": len(runs), "days": days, "seed": seed,
            "directory": directory, "source": source}
