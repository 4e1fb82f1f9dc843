"""Small helpers shared by the benchmark scripts (not a test): timing, statistics, tables.

A script records what it measured with :class:`Record`: its tables go to
``benchmarks/results/<name>.json`` with the date, the machine, the CPU reference and the load
before and after the run, and ``benchmarks/report.py`` renders every such file into
``benchmarks/README.md``.
"""

import datetime
import json
import os
import platform
import shlex
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent  # the repository
RESULTS = ROOT / "benchmarks" / "results"  # one JSON file per benchmark, rendered by report.py


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


def machine():
    """The machine a benchmark runs on: CPU model, cores, system, Python, numpy and its BLAS."""
    cpu = platform.processor() or platform.machine()
    try:
        for text in Path("/proc/cpuinfo").read_text().splitlines():
            if text.startswith("model name"):
                cpu = text.split(":", 1)[1].strip()
                break
    except OSError:  # pragma: no cover - not on every platform
        pass
    out = {"cpu": cpu, "cores": os.cpu_count(), "system": f"{platform.system()} {platform.machine()}",
           "python": platform.python_version()}
    try:
        import numpy as np
        out["numpy"] = np.__version__
        blas = np.show_config(mode="dicts")["Build Dependencies"]["blas"]
        out["blas"] = f"{blas.get('name', '?')} {blas.get('version', '')}".strip()
    except Exception:  # noqa: BLE001 - numpy missing or too old to say: the line omits it
        pass
    return out


def _state():
    """The CPU reference (ms) and the 1-minute load average, now."""
    try:
        load = round(os.getloadavg()[0], 2)
    except OSError:  # pragma: no cover - not on every platform
        load = None
    return round(cpu_ms(), 1), load


class Record:
    """What one benchmark run measured, written to ``benchmarks/results/<name>.json``.

    Created at the start of the run (it takes the date, the CPU reference and the load
    then); :meth:`table` and :meth:`line` print as before and keep the rows; :meth:`write`
    takes the CPU reference and the load again and writes the file. Cells are kept as the
    strings printed, so the page shows exactly what the run printed.
    """

    def __init__(self, name, title, about=""):
        self.name, self.title, self.about = name, title, about
        self.script = Path(sys.argv[0]).name
        self.command = " ".join(["python", f"benchmarks/{self.script}",
                                 *map(shlex.quote, sys.argv[1:])])
        self.date = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d")
        self.cpu_before, self.load_before = _state()
        self.tables, self.notes = [], []
        print(machine_line(), flush=True)

    def table(self, header, rows, title="", stream=sys.stdout):
        """Print ``rows`` under ``header`` (as :func:`table`) and keep them under ``title``."""
        table(header, rows, stream=stream)
        self.tables.append({"title": title, "columns": [str(c) for c in header],
                            "rows": [[str(c) for c in r] for r in rows]})

    def line(self, what, measured, target="", result=""):
        """Print one measured quantity and keep it as a row of the run's first table."""
        print(f"{what:52s}: {measured}" + (f"   (target {target}) {result}" if target else ""),
              flush=True)
        if not self.tables or self.tables[0].get("lines") is None:
            self.tables.insert(0, {"title": "", "columns": ["what", "measured", "target",
                                                            "verdict"], "rows": [], "lines": True})
        self.tables[0]["rows"].append([str(what), str(measured), str(target), str(result)])

    def note(self, text):
        """Keep a sentence shown under the tables (a caveat the run found)."""
        print(text)
        self.notes.append(str(text))

    def data(self):
        """The record as the JSON-ready dict :meth:`write` writes."""
        cpu_after, load_after = _state()
        tables = [{k: v for k, v in t.items() if k != "lines"} for t in self.tables]
        return {"name": self.name, "title": self.title, "about": self.about,
                "script": self.script, "command": self.command, "date": self.date,
                "machine": machine(), "cpu_reference_ms": [self.cpu_before, cpu_after],
                "load_1min": [self.load_before, load_after], "tables": tables,
                "notes": self.notes}

    def write(self, path=None):
        """Write the record to ``path`` (default ``benchmarks/results/<name>.json``)."""
        data = self.data()
        print(machine_line())
        path = Path(path) if path else RESULTS / f"{self.name}.json"
        path.parent.mkdir(parents=True, exist_ok=True)
        write_json(path, data)
        return path
