"""Small helpers shared by the benchmark scripts (not a test): timing, statistics, tables."""

import json
import os
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent  # the repository


def best_of(func, repeat=5):
    """Best wall time of ``repeat`` calls of ``func()``, s."""
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        func()
        best = min(best, time.perf_counter() - t0)
    return best


def loadavg():
    """The 1-, 5- and 15-minute load averages as one string (``"n/a"`` where unknown)."""
    try:
        return ", ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:  # pragma: no cover - not on every platform
        return "n/a"


def machine_line():
    """One line naming the CPU count, the load average and the CPU's speed (:func:`cpu_ms`).

    Printed before and after a run, so that numbers from different days can be compared: the
    project's machine is a shared virtual machine whose speed changes from day to day.
    """
    return (f"{os.cpu_count()} CPUs, load average {loadavg()} (1, 5, 15 min), "
            f"CPU reference {cpu_ms():.1f} ms")


def cpu_ms():
    """The CPU's speed for pure Python: ``sum(range(10**6))``, best of 5, milliseconds.

    Lower is faster. Matplotlib's rendering and the package's Python loops scale with it.
    """
    best = float("inf")
    for _ in range(5):
        t0 = time.perf_counter()
        sum(range(10**6))
        best = min(best, time.perf_counter() - t0)
    return best * 1e3


def median_max(values):
    """``(median, largest)`` of a non-empty sequence of numbers."""
    values = list(values)
    return statistics.median(values), max(values)


def child_env(numba_cache_dir=None, **extra):
    """The environment of a benchmark's subprocess: this one, with numba's cache redirected.

    ``numba_cache_dir`` sets ``NUMBA_CACHE_DIR`` (numba then reads and writes compiled
    kernels there, never beside the package's sources); ``None`` keeps the environment's.
    ``extra`` adds variables; a value ``None`` removes one.
    """
    env = dict(os.environ)
    if numba_cache_dir is not None:
        env["NUMBA_CACHE_DIR"] = str(numba_cache_dir)
    for key, value in extra.items():
        if value is None:
            env.pop(key, None)
        else:
            env[key] = str(value)
    return env


def table(header, rows, stream=sys.stdout):
    """Print ``rows`` (lists of cells, any type) under ``header`` as aligned text columns."""
    cells = [[str(c) for c in header]] + [[str(c) for c in row] for row in rows]
    widths = [max(len(r[i]) for r in cells) for i in range(len(header))]

    def line(r):
        return "  ".join(c.ljust(w) if i == 0 else c.rjust(w)
                         for i, (c, w) in enumerate(zip(r, widths, strict=True)))

    print(line(cells[0]), file=stream)
    print("  ".join("-" * w for w in widths), file=stream)
    for r in cells[1:]:
        print(line(r), file=stream)


def verdict(ok):
    """``"OK"`` or ``"MISS"``."""
    return "OK" if ok else "MISS"


def write_json(path, data):
    """Write ``data`` as indented JSON to ``path`` (``None``: do nothing)."""
    if path:
        Path(path).write_text(json.dumps(data, indent=2) + "\n")
        print(f"wrote {path}")


def chapters(selected=None):
    """The chapter notebooks ``book/NN_*.ipynb`` in order, or those whose ``NN`` is selected."""
    paths = sorted((ROOT / "book").glob("[0-9][0-9]_*.ipynb"))
    if selected:
        want = {f"{int(s):02d}" for s in selected}
        missing = want - {p.name[:2] for p in paths}
        if missing:
            raise SystemExit(f"no chapter numbered {', '.join(sorted(missing))} in book/")
        paths = [p for p in paths if p.name[:2] in want]
    return paths
