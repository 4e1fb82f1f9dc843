"""The headline campaign chapters 6 and 8 and the README quote: 32 seeds of the paper's 30 days.

Run: ``.venv/bin/python benchmarks/bench_headline.py`` (computes the campaign, prints each
quantity's mean and 95 % interval beside the shipped one, and the wall time) or
``.venv/bin/python benchmarks/bench_headline.py --write`` (also rewrites the shipped runs
``xnavlab/data/headline_runs.json`` that :func:`xnavlab.mars.navigation.headline.headline_numbers` reads).
``--store DIR`` keeps the campaign's runs there so that an interrupted run resumes.

Each seed runs the fault-free scenario, the paper's fault schedule under the combined detector,
with no detector and with the paper's wavelet detector: four 30-day runs. The campaign is
shipped because it takes minutes (four on two quiet cores), not a chapter's seconds;
``tests/mars/navigation/test_headline.py`` recomputes its first run from its seed, so a change of the code
that moves it fails there until this script writes the table again.
"""

import argparse
import datetime
import tempfile
import time
from pathlib import Path

from _timing import machine_line, table, write_json

from xnavlab.mars.navigation import headline


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true",
                    help="rewrite xnavlab/data/headline_runs.json")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--store", default=None, help="campaign directory (default: a temporary one)")
    args = ap.parse_args()
    print(machine_line())
    store = Path(args.store or tempfile.mkdtemp(prefix="xnavlab-headline-"))
    t0 = time.perf_counter()
    records = headline.headline_records(**headline.SHIPPED, out=store,
                                        workers=args.workers, progress=True)
    wall = time.perf_counter() - t0
    print(f"\n{len(records)} runs in {wall:.0f} s")
    fresh = headline.numbers_of([r["metrics"] for r in records])
    try:
        old = headline.headline_numbers()["quantities"]
    except ValueError as exc:  # no shipped table yet, or a broken one
        print(f"shipped table: {exc}")
        old = {}
    rows = []
    for name, q in fresh.items():
        was = old.get(name)
        rows.append([name, f"{q['mean']:.6g} [{q['lo']:.6g}, {q['hi']:.6g}]",
                     "-" if was is None else f"{was['mean']:.6g}"])
    table(["quantity", "mean [95 %]", "shipped mean"], rows)
    print(machine_line())
    if args.write:
        if len(records) != headline.SHIPPED["n_seeds"]:
            raise SystemExit(f"{headline.SHIPPED['n_seeds'] - len(records)} runs failed: "
                             f"not written")
        write_json(headline.RUNS_PATH, {
            "campaign": headline.SHIPPED,
            "command": "python benchmarks/bench_headline.py --write",
            "written": datetime.date.today().isoformat(),
            "wall_s": round(wall, 1),
            "runs": records})


if __name__ == "__main__":
    main()
