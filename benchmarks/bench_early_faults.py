"""Faults in the first day: time to detection and fused error of a fault at 1 h, 6 h and 20 h.

Run: ``.venv/bin/python benchmarks/bench_early_faults.py [--seeds N] [--write]``. For each of
``N`` noise seeds (default 16), each sensor (UV, CNS, XNAV) and each onset of
:data:`xnavlab.mars.studies.trials.EARLY_ONSETS_S` (1 h, 6 h, 20 h), a one-day run with a 6-sigma
step of 4000 s under the combined detector (:func:`xnavlab.mars.studies.trials.early_fault_trial`);
the UV and CNS wavelets train on the first 12 hours, so at 1 h and 6 h only the innovation
tests watch. Prints, per sensor and onset, the fraction found (detected, scored by
:func:`xnavlab.mars.faults.schedules.score_faults`: an alarm while the fault acts, or its subsystem
already out of the fusion from before the onset to the end, after a false alarm: ``out``),
the faults whose first alarm came after their end (``late``, not found), the median and
largest detection delay of those found by an alarm and the largest ratio of the
fused RMS to the same seed's fault-free run (targets: delay <= 1500 s, ratio <= 1.5).
``--write`` stores the table in ``xnavlab/data/early_faults.json`` (chapter 9 shows it), with
the first seed's records (``checks``) for ``tests/mars/studies/test_trials.py`` to recompute.
Seeds run on a local process pool of two workers.
"""

import argparse
import json
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from xnavlab.mars.studies import trials


def _one(seed):
    return trials.early_fault_trial(seed=seed)


def early_table(runs):
    """Per sensor and onset: trials, found (detected), out at onset, late, delays, RMS ratio."""
    table = []
    for sensor in trials.SENSORS:
        for onset in trials.EARLY_ONSETS_S:
            cell = [r for r in runs if r["sensor"] == sensor and r["onset_s"] == onset]
            d = [r["delay_s"] for r in cell if r["detected"] and not r["out_at_onset"]]
            table.append({"sensor": sensor, "onset_s": onset, "trials": len(cell),
                          "found": sum(r["detected"] for r in cell),
                          "out_at_onset": sum(r["out_at_onset"] for r in cell),
                          "late": sum(r["late"] for r in cell),
                          "delay_median_s": float(np.median(d)) if d else None,
                          "delay_max_s": float(np.max(d)) if d else None,
                          "rms_ratio_max": float(max(r["rms_ratio"] for r in cell))})
    return table


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=16)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--write", action="store_true")
    args = parser.parse_args(argv)
    seeds = [int(s) for s in np.random.SeedSequence(args.seed).generate_state(args.seeds)]
    t0 = time.perf_counter()
    with ProcessPoolExecutor(2) as ex:
        per_seed = list(ex.map(_one, seeds))
    runs = [r for rows in per_seed for r in rows]
    wall = time.perf_counter() - t0
    table = early_table(runs)
    print(f"{'sensor':6s} {'onset':>7s} {'found':>7s} {'out':>4s} {'late':>4s} {'median':>8s} "
          f"{'max':>8s} {'RMS ratio':>9s}")
    for row in table:
        med = "-" if row["delay_median_s"] is None else f"{row['delay_median_s']:.0f} s"
        mx = "-" if row["delay_max_s"] is None else f"{row['delay_max_s']:.0f} s"
        print(f"{row['sensor']:6s} {row['onset_s'] / 3600:6.0f}h {row['found']:3d}/{row['trials']:<3d} "
              f"{row['out_at_onset']:4d} {row['late']:4d} {med:>8s} {mx:>8s} "
              f"{row['rms_ratio_max']:9.3f}")
    print(f"{len(runs)} one-day runs in {wall:.0f} s")
    if args.write:
        out = {"rows": table, "seeds": args.seeds, "seed": args.seed, "size_sigma": 6.0,
               "duration_s": 4000.0, "detector": "combined",
               "checks": {"seed": seeds[0], "records": per_seed[0]},
               "command": f"python benchmarks/bench_early_faults.py --seeds {args.seeds} "
                          f"--seed {args.seed} --write"}
        trials.EARLY_PATH.write_text(json.dumps(out, indent=1) + "\n")
        print(f"wrote {trials.EARLY_PATH}")


if __name__ == "__main__":
    main()
