"""The detector study of chapter 9: the Monte Carlo table, and CUSUM against a windowed chi-square.

Run: ``.venv/bin/python benchmarks/bench_detectors.py`` (prints; about 10 min on 2 cores) or
``.venv/bin/python benchmarks/bench_detectors.py --write`` (also rewrites the shipped table
``xnavlab/data/detector_table.json`` that chapter 9 loads and ``tests/mars/studies/test_trials.py`` checks
against freshly computed cells). ``--trials N`` sets the trials per cell (default 20).

1. Sequential test chosen by measurement: on unit white innovations with a drift reaching
   5 sigma in 6000 s (3 s a sample, UV/CNS; 500 s a sample, XNAV), the detection delay of the
   mean CUSUM of :class:`xnavlab.core.detection.CombinedDesign` against a windowed chi-square
   of the NIS (windows of 100 and 4 samples) at the same false-alarm rate (the CUSUM share of
   the budget, 0.5 a day).
2. The table: :func:`xnavlab.mars.studies.trials.detector_trials` (the three detectors on one seed)
   for every fault class, size and sensor, one-day runs, aggregated by
   :func:`~xnavlab.mars.studies.trials.detector_table`; cells where the combined detector is worse than
   the better of the other two beyond Monte Carlo error are listed
   (:func:`~xnavlab.mars.studies.trials.marked_cells`).
3. The XNAV cells at the edge of what the detector must find (a drift reaching 5 sigma in 6000 s, a
   noise increase to 3 and 4 times nominal for 3000 s, one sample per 500 s), with many trials
   of the combined detector (``--edge-trials``, default 96): the fraction found within 4000 s
   of the onset with its Wilson interval, against :func:`xnavlab.mars.studies.trials.detection_limit`,
   the Neyman-Pearson bound of any detector at the design false-alarm rate; and, on one
   component at 500 s, the CUSUM against the drift-matched GLR (:func:`glr_comparison`).
"""

import argparse
import json
import math
import time

import numpy as np
from scipy import stats

from xnavlab.core import montecarlo
from xnavlab.core.detection import CombinedDesign, InnovationMonitor, drift_glr
from xnavlab.mars.studies import trials


def _cusum_delay(y, design):
    mon = InnovationMonitor(design, adaptive=False)
    i = mon.process(np.arange(y.shape[0], dtype=float), y)
    return i


def _window_delay(y, w, thr):
    q = np.convolve(y[:, 0] ** 2, np.ones(w))[:y.shape[0]]
    hit = np.flatnonzero(q > thr)
    return int(hit[0]) if hit.size else -1


def _drift_series(rng, n0, n_f):
    """Unit white noise (1 component) with a drift reaching 5 sigma over ``n_f`` samples from
    sample ``n0``; returned from 10 samples before the onset."""
    y = rng.normal(size=(n0 + 3 * n_f, 1))
    y[n0:n0 + n_f, 0] += 5.0 * np.arange(n_f) / n_f
    return y[n0 - 10:]


def _delay_s(i, dt):
    """Delay after the onset (sample 10) of an alarm at sample i, s; inf for none or a false alarm."""
    return (i - 10) * dt if i >= 10 else np.inf


def sequential_comparison(n_trials=200, seed=0):
    """Median delays (s) of the mean CUSUM and a windowed chi-square on a 5-sigma/6000-s drift."""
    rng = np.random.default_rng(seed)
    out = []
    for dt, w, k in ((3.0, 100, 0.25), (500.0, 4, 0.5)):
        n_day = 86400.0 / dt
        shares = {"wavelet": 0.1, "chi2": 0.2, "cusum": 0.5, "variance": 0.2}
        design = CombinedDesign(n_day, 1, 1.0, shares, k_mean=k)
        # the windowed chi-square at the CUSUM share: 0.5 alarm samples a day (its alarm events,
        # which cluster, are fewer: this favours the CUSUM by at most a few per cent in delay)
        thr = stats.chi2.isf(0.5 / n_day, w)
        n0 = int(2000 / (dt / 3.0)) if dt == 3.0 else 60
        n_f = int(6000 / dt)
        dc, dw = [], []
        for _ in range(n_trials):
            y = _drift_series(rng, n0, n_f)
            dc.append(_delay_s(_cusum_delay(y, design), dt))
            dw.append(_delay_s(_window_delay(y, w, thr), dt))
        out.append({"dt_s": dt, "window": w, "cusum_median_delay_s": float(np.median(dc)),
                    "window_chi2_median_delay_s": float(np.median(dw))})
    return out


def _events(T, h, window):
    """Alarm events of a statistic: exceedances with no exceedance in the ``window`` before."""
    above = np.flatnonzero(T > h)
    return above[np.r_[True, np.diff(above) > window]] if above.size else above


def glr_threshold(rate_per_day, samples_per_day, window=16, n=2_000_000, seed=1):
    """GLR threshold with ``rate_per_day`` alarm events on unit white noise (bisection)."""
    T = drift_glr(np.random.default_rng(seed).normal(size=n), window)
    want = rate_per_day * n / samples_per_day
    lo, hi = 1.0, 60.0
    for _ in range(40):
        h = 0.5 * (lo + hi)
        lo, hi = (h, hi) if _events(T, h, window).size > want else (lo, h)
    return 0.5 * (lo + hi)


def glr_comparison(n_trials=400, seed=0, window=16, within_s=4000.0):
    """XNAV (500 s a sample): CUSUM against the drift GLR at the CUSUM's share of the budget
    (0.5 alarms a day), on a drift reaching 5 sigma in 6000 s: median delay and the fraction
    found within ``within_s`` of the onset."""
    dt = 500.0
    n_day = 86400.0 / dt
    design = CombinedDesign(n_day, 1, 1.0, {"wavelet": 0.1, "chi2": 0.2, "cusum": 0.5, "variance": 0.2},
                            k_mean=0.5)
    h = glr_threshold(0.5, n_day, window)
    rng = np.random.default_rng(seed)
    n0, n_f = 60, int(6000 / dt)
    dc, dg = [], []
    for _ in range(n_trials):
        y = _drift_series(rng, n0, n_f)
        dc.append(_delay_s(_cusum_delay(y, design), dt))
        hit = np.flatnonzero(drift_glr(y[:, 0], window) > h)
        dg.append(_delay_s(int(hit[0]) if hit.size else -1, dt))
    dc, dg = np.array(dc), np.array(dg)
    return {"h_glr": h, "window": window, "cusum_median_s": float(np.median(dc)),
            "glr_median_s": float(np.median(dg)), "cusum_within": float(np.mean(dc <= within_s)),
            "glr_within": float(np.mean(dg <= within_s)), "trials": n_trials}


def run_table(n_trials=20, seed=0, days=1.0, max_workers=2):
    params = table_params(n_trials, days)
    res = montecarlo.run_tasks(trials.detector_trials, params, seed=seed,
                               max_workers=max_workers, chunksize=4)
    records = [r for group in res for r in group]
    return records, trials.detector_table(records)


#: Tasks re-run by tests/mars/studies/test_trials.py (their records are stored with the table).
CHECK_CELLS = (("step", "uv", 1), ("ramp", "cns", 1), ("noise", "xnav", 2))


def table_params(n_trials, days=1.0):
    """The table's task list, in order (task i gets ``montecarlo.seeds(seed, n)[i]``)."""
    return [dict(fault_class=fc, sensor=s, size_index=i, days=days)
            for fc in trials.FAULT_CLASSES for s in trials.SENSORS for i in range(3)
            for _ in range(n_trials)]


def table_checks(n_trials, seed, days=1.0):
    """The records of the first trial of each of :data:`CHECK_CELLS`, recomputed."""
    params = table_params(n_trials, days)
    task_seeds = montecarlo.seeds(seed, len(params))
    out = []
    for fc, s, i in CHECK_CELLS:
        k = next(j for j, p in enumerate(params) if (p["fault_class"], p["sensor"],
                                                     p["size_index"]) == (fc, s, i))
        out.append({"task": k, "params": params[k], "seed": int(task_seeds[k]),
                    "records": trials.detector_trials(**params[k], seed=int(task_seeds[k]))})
    return out


#: (fault class, size index) of the XNAV cells at the edge of the acceptance.
EDGE_CELLS = (("ramp", 1), ("noise", 1), ("noise", 2))


def edge_cells(n_trials=96, seed=12345, window_s=4000.0):
    """Combined detector on :data:`EDGE_CELLS` (XNAV): found within ``window_s`` against the limit."""
    out = []
    for fc, i in EDGE_CELLS:
        params = [dict(fault_class=fc, sensor="xnav", size_index=i, detector="combined", days=1.0)]
        recs = montecarlo.run_tasks(trials.detector_trial, params * n_trials, seed=seed, max_workers=2)
        d = np.array([r["delay_s"] if r["detected"] else np.inf for r in recs])
        k = int(np.sum(d <= window_s))
        lo, hi = montecarlo.wilson_interval(k, n_trials)
        size = trials.SIZES[fc][i]
        out.append({"fault_class": fc, "size": size, "found": k / n_trials, "found_lo": lo,
                    "found_hi": hi, "p95_s": float(np.sort(d)[math.ceil(0.95 * d.size) - 1]),
                    "limit": trials.detection_limit(fc, "xnav", size, window_s)})
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--trials", type=int, default=20)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--write", action="store_true")
    ap.add_argument("--edge-trials", type=int, default=96)
    args = ap.parse_args()
    if args.edge_trials > 0:
        for row in edge_cells(args.edge_trials):
            print(f"XNAV {row['fault_class']} {row['size']:g}, combined, {args.edge_trials} trials: found "
                  f"within 4000 s {row['found']:.3f} [{row['found_lo']:.3f}, {row['found_hi']:.3f}], "
                  f"p95 delay {row['p95_s']:.0f} s; limit of any detector {row['limit']:.3f}")
    for row in sequential_comparison():
        print(f"drift 5 sigma / 6000 s at {row['dt_s']:g} s: CUSUM {row['cusum_median_delay_s']:.0f} s,"
              f" windowed chi-square ({row['window']} samples) "
              f"{row['window_chi2_median_delay_s']:.0f} s (median delays)")
    g = glr_comparison()
    print(f"drift 5 sigma / 6000 s at 500 s, {g['trials']} trials, 0.5 alarms a day each: CUSUM median "
          f"{g['cusum_median_s']:.0f} s, {g['cusum_within']:.3f} within 4000 s; drift GLR (window "
          f"{g['window']}, h {g['h_glr']:.1f}) median {g['glr_median_s']:.0f} s, {g['glr_within']:.3f}")
    t0 = time.perf_counter()
    records, rows = run_table(args.trials, args.seed)
    wall = time.perf_counter() - t0
    marked = trials.marked_cells(rows)
    print(f"{len(records)} one-day runs in {wall:.0f} s; {len(marked)} marked cells")
    for m in marked:
        print("  marked:", m)
    for r in rows:
        if r["detector"] == "combined":
            print(f"  {r['fault_class']:5s} {r['sensor']:4s} {r['size']:6g}: Pd {r['pd']:.2f} "
                  f"median {r['delay_median_s']} s, p95 {r['delay_p95_s']} s, "
                  f"FA/day {r['false_alarms_per_day']:.2f}, RMS ratio {r['rms_ratio']:.2f}")
    if args.write:
        data = {"command": "python benchmarks/bench_detectors.py --write --trials "
                           f"{args.trials} --seed {args.seed}",
                "trials": args.trials, "seed": args.seed, "days": 1.0,
                "rows": rows, "marked": marked,
                "checks": table_checks(args.trials, args.seed)}
        trials.TABLE_PATH.write_text(json.dumps(data, indent=1))
        print("wrote", trials.TABLE_PATH)


if __name__ == "__main__":
    main()
