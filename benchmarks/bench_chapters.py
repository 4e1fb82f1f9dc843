"""What "run all" costs: every chapter, and the dashboard page, executed in a fresh kernel.

Run: ``.venv/bin/python benchmarks/bench_chapters.py [--chapters 08 09] [--no-dashboard]
[--json FILE] [--numba-cache-dir DIR]``.

Each page is executed as a reader's "Restart and run all" executes it: with ``nbclient`` in a
new ``python3`` kernel of this environment, working directory ``book/``, ``MPLBACKEND`` unset
(the inline backend), ``XNAVLAB_SCRUBBER_FRAMES`` unset (a slider draws its opening figure,
not the HTML scrubber's frames that only the book's build draws), one page at a time. A chapter is
``book/NN_*.ipynb``; the dashboard, ``book/dashboard.md``, is a MyST Markdown notebook and is
read into a notebook with ``myst_nb``'s own reader (what the build uses; ``jupytext`` is not
needed). Per page: the kernel's start (to the first cell's start), the cells (first cell's start to
the last one's reply, from the timing nbclient records in each cell's metadata), the whole
run-all (the two together, what a reader waits for after "Restart and run all"), and the
three slowest cells with their first line (what dominates a miss).

From a warm environment: the numba kernels compiled and the 30-day truth cached
(``make setup`` runs ``python -m xnavlab warmup``; run it first, with the same
``NUMBA_CACHE_DIR`` when ``--numba-cache-dir DIR`` points the kernels at ``DIR``). A page's
own caches (e.g. a campaign store in a temporary directory) are whatever the page makes.

Targets: each chapter's run-all at most 10 s, the dashboard at most 30 s. The machine may be
shared: the load average is printed before and after every page.
"""

import argparse
import sys
import time
from pathlib import Path

from _timing import (
    ROOT,
    Record,
    chapters,
    child_env,
    loadavg,
    machine_line,
    write_json,
)

from xnavlab.core.widgets import FRAMES_ENV

sys.path.insert(0, str(ROOT / "tools"))
from book_execute import cell_times, read_page  # noqa: E402  (tools/book_execute.py)

TARGET_CHAPTER_S = 10.0
TARGET_DASHBOARD_S = 30.0
DASHBOARD = ROOT / "book" / "dashboard.md"


def run_page(path, numba_cache_dir, timeout):
    """Execute one page in a fresh kernel; kernel start, per-cell and total times, s.

    ``nbclient``'s own ``execute`` runs the page (kernel start, every cell, shut-down), as the
    book's build does; each cell's time is read from the timing it records in the cell's
    metadata (``iopub.execute_input`` to ``shell.execute_reply``). A page that raises stops
    there, and the error is reported with the time up to it.
    """
    from nbclient import NotebookClient
    from nbclient.exceptions import CellExecutionError, CellTimeoutError

    nb = read_page(path)
    # a reader's run-all: the inline backend, no scrubber frames (only the book's build draws them)
    env = child_env(numba_cache_dir, MPLBACKEND=None, **{FRAMES_ENV: None})
    client = NotebookClient(nb, timeout=timeout, kernel_name="python3", record_timing=True,
                            resources={"metadata": {"path": str(path.parent)}})
    error = None
    load = loadavg()
    t0 = time.time()
    try:
        client.execute(env=env)
    except (CellExecutionError, CellTimeoutError) as exc:
        error = str(exc).strip().splitlines()[-1][:200]
    t_end = time.time()
    cells = cell_times(nb)
    first_start = cells[0]["start"] if cells else t_end
    last_stop = cells[-1]["stop"] if cells else t_end
    return {"page": path.name, "kernel_start_s": first_start - t0,
            "cells_s": last_stop - first_start, "total_s": last_stop - t0,
            "teardown_s": t_end - last_stop, "cells": cells,
            "error": error, "load_before": load, "load_after": loadavg()}


def run_isolated(path, numba_cache_dir, timeout):
    """:func:`run_page` in a new process of its own (spawned), one per page.

    Several kernels started one after the other from one process sometimes left the second
    page waiting for a reply that never came (the kernel idle); a process per page, as the
    book's build runs one page per client, does not.
    """
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    with ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn")) as pool:
        return pool.submit(run_page, path, numba_cache_dir, timeout).result()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--chapters", nargs="+", metavar="NN", help="only these chapters")
    parser.add_argument("--no-dashboard", action="store_true", help="skip book/dashboard.md")
    parser.add_argument("--json", metavar="FILE", help="also write the results as JSON")
    parser.add_argument("--numba-cache-dir", metavar="DIR",
                        help="NUMBA_CACHE_DIR of the kernels (default: the environment's)")
    parser.add_argument("--timeout", type=float, default=1800.0, help="per cell, s")
    args = parser.parse_args()

    pages = [(p, TARGET_CHAPTER_S) for p in chapters(args.chapters)]
    if not args.no_dashboard and not args.chapters:
        pages.append((DASHBOARD, TARGET_DASHBOARD_S))
    before = machine_line()
    rec = Record("chapters", "Chapter run-all, fresh kernel",
                 "Each page executed with `nbclient` in a new kernel as a reader's \"Restart and run "
                 "all\" does, from a warm environment (the kernels compiled, the caches filled); "
                 f"targets: a chapter {TARGET_CHAPTER_S:.0f} s, the dashboard {TARGET_DASHBOARD_S:.0f} s.")
    results, rows = [], []
    for path, target in pages:
        res = run_isolated(Path(path), args.numba_cache_dir, args.timeout)
        res["target_s"] = target
        res["ok"] = res["error"] is None and res["total_s"] <= target
        results.append(res)
        slow = sorted(res["cells"], key=lambda c: -c["seconds"])[:3]
        res["slowest"] = slow
        print(f"{res['page']}: {res['total_s']:.1f} s (kernel {res['kernel_start_s']:.1f} s, "
              f"cells {res['cells_s']:.1f} s; load {res['load_before']} -> {res['load_after']})"
              + (f"  ERROR {res['error']}" if res["error"] else ""), flush=True)
        for c in slow:
            print(f"    cell {c['index']:3d}  {c['seconds']:6.1f} s  {c['first_line']}")
        rows.append([res["page"], f"{res['kernel_start_s']:.1f}", f"{res['cells_s']:.1f}",
                     f"{res['total_s']:.1f}", f"{target:.0f}",
                     "error" if res["error"] else ("met" if res["ok"] else "missed"),
                     f"{slow[0]['seconds']:.1f} s, cell {slow[0]['index']}: `{slow[0]['first_line']}`"
                     if slow else "", f"{res['load_before']} -> {res['load_after']}"])
    print()
    rec.table(["page", "kernel s", "cells s", "run-all s", "target s", "verdict", "slowest cell",
               "load"], rows)
    after = machine_line()
    print(f"\nmachine: {after}")
    write_json(args.json, {"machine_before": before, "machine_after": after, "pages": results})
    rec.write()


if __name__ == "__main__":
    main()
