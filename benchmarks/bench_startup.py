"""What a reader waits for at the command line: first compile, warm start, the 30-day Mars run.

Run: ``.venv/bin/python benchmarks/bench_startup.py [--runs 3] [--numba-cache-dir DIR]
[--json FILE]``. Every measurement is a subprocess of this interpreter, so each one pays for
the interpreter's start and the imports as a reader's command does. Prints, with the load
average before and after (the machine may be shared: the numbers are what it gave then):

(a) cold compile: ``python -m xnavlab warmup`` with ``NUMBA_CACHE_DIR`` pointing at an empty
    directory, so numba compiles every kernel the book and the command line use (the package's
    own cache beside its sources is neither read nor written). The truth cache
    (``XNAVLAB_CACHE``, default ``~/.cache/xnavlab``) is left as it is, so the 30-day truth is
    normally loaded, not computed: the first step's time says which. Per warmup step, the time
    it prints, and the whole process's wall time. Target: 15 s or less on 2 cores.
(b) warm: the same command again, with the cache (a) filled: what a rerun costs.
(c) ``python -m xnavlab run mars --days 30 --json`` with that warm cache, ``--runs`` times
    (default 3): the best wall time including the process start, against the 1-s target, and
    its parts from the JSON it prints (before the run: interpreter, imports and parser; the
    inputs; the filter), beside the bare interpreter (``python -c pass``) and
    ``python -m xnavlab --version``, best of ``--runs`` each.
(d) ``python -X importtime``: the 10 slowest imports by cumulative time (and by their own
    time) of ``import xnavlab.mars.navigation.scenarios`` and of the command line's path
    (``python -m xnavlab run mars --days 30 --json``), each one process.

``--numba-cache-dir DIR`` compiles into ``DIR`` (which must be empty or absent, so that (a)
is cold) and keeps it afterwards, e.g. to run the other benchmarks against it; by default a
temporary directory is used and removed.
"""

import argparse
import json
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _timing import ROOT, Record, child_env, machine_line, table, verdict, write_json

PY = sys.executable
TARGET_COMPILE_S = 15.0
TARGET_RUN_S = 1.0
RUN_MARS = ["-m", "xnavlab", "run", "mars", "--days", "30", "--json"]
_STEP = re.compile(r"^warmup: (?P<label>.+): (?P<s>[0-9.]+) s$")


def timed(args, env, check=True):
    """Run ``python args...``; return (wall time, stdout, stderr)."""
    t0 = time.perf_counter()
    proc = subprocess.run([PY, *args], capture_output=True, text=True, env=env, cwd=ROOT)
    wall = time.perf_counter() - t0
    if check and proc.returncode != 0:
        raise SystemExit(f"python {' '.join(args)} failed ({proc.returncode}):\n{proc.stderr}")
    return wall, proc.stdout, proc.stderr


def warmup(env):
    """One ``python -m xnavlab warmup``: wall time, the steps it printed, its other stderr lines.

    Each step: its label, the time the command printed for it and the wall time since the
    process started at which its line arrived.
    """
    t0 = time.perf_counter()
    proc = subprocess.Popen([PY, "-m", "xnavlab", "warmup"], stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True, env=env, cwd=ROOT)
    steps, other = [], []
    for line in proc.stderr:
        line = line.rstrip("\n")
        m = _STEP.match(line)
        if m:
            steps.append({"label": m["label"], "printed_s": float(m["s"]),
                          "at_wall_s": time.perf_counter() - t0})
        elif line.strip():
            other.append(line)
    code = proc.wait()
    wall = time.perf_counter() - t0
    if code != 0:
        raise SystemExit("python -m xnavlab warmup failed:\n" + "\n".join(other))
    return {"wall_s": wall, "steps": steps, "other_stderr": other}


def importtime(args, env, top=10):
    """The ``top`` imports by cumulative and by self time of ``python -X importtime args``."""
    _, _, err = timed(["-X", "importtime", *args], env)
    rows = []
    for line in err.splitlines():
        if not line.startswith("import time:") or "imported package" in line:
            continue
        self_us, cum_us, name = line[len("import time:"):].split("|", 2)
        depth = (len(name) - len(name.lstrip(" "))) // 2
        rows.append({"module": name.strip(), "self_s": int(self_us) * 1e-6,
                     "cumulative_s": int(cum_us) * 1e-6, "depth": depth})
    total = sum(r["self_s"] for r in rows)
    by_cum = sorted(rows, key=lambda r: -r["cumulative_s"])[:top]
    by_self = sorted(rows, key=lambda r: -r["self_s"])[:top]
    return {"command": "python -X importtime " + " ".join(args), "total_s": total,
            "modules": len(rows), "top_cumulative": by_cum, "top_self": by_self}


def print_warmup(name, w, rec):
    print(f"\n({name}) python -m xnavlab warmup: {w['wall_s']:.1f} s wall")
    rows = []
    for s in w["steps"]:
        rows.append([s["label"], f"{s['printed_s']:.1f}", f"{s['at_wall_s']:.1f}"])
    rows.append(["whole process (interpreter, imports, steps)", "", f"{w['wall_s']:.1f}"])
    rec.table(["step", "printed s", "line at wall s"], rows,
              f"({name}) `python -m xnavlab warmup`: {w['wall_s']:.1f} s wall")
    for line in w["other_stderr"]:
        print(f"  stderr: {line}")


def print_imports(imp, rec):
    print(f"\n{imp['command']}: {imp['modules']} modules, {imp['total_s']:.2f} s of imports "
          "(sum of self times; one process)")
    rows = [[r["module"], r["depth"], f"{r['cumulative_s']:.3f}", f"{r['self_s']:.3f}"]
            for r in imp["top_cumulative"]]
    rec.table(["top 10 by cumulative", "depth", "cumul. s", "self s"], rows,
              f"`{imp['command']}`: {imp['modules']} modules, {imp['total_s']:.2f} s of imports")
    rows = [[r["module"], r["depth"], f"{r['self_s']:.3f}", f"{r['cumulative_s']:.3f}"]
            for r in imp["top_self"]]
    table(["top 10 by own time", "depth", "self s", "cumul. s"], rows)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3, help="processes per timed command")
    parser.add_argument("--numba-cache-dir", metavar="DIR",
                        help="compile into DIR (empty or absent) and keep it")
    parser.add_argument("--json", metavar="FILE", help="also write the results as JSON")
    args = parser.parse_args()

    if args.numba_cache_dir:
        cache = Path(args.numba_cache_dir)
        if cache.exists() and any(cache.iterdir()):
            raise SystemExit(f"--numba-cache-dir {cache} is not empty: (a) would not be cold")
        cache.mkdir(parents=True, exist_ok=True)
        keep = True
    else:
        cache = Path(tempfile.mkdtemp(prefix="xnavlab-numba-cold-"))
        keep = False
    rec = Record("startup", "What a reader waits for at the command line",
                 "`python -m xnavlab warmup` into an empty numba cache (a: the first compile; "
                 f"target {TARGET_COMPILE_S:.0f} s) and again with it filled (b); the 30-day "
                 f"run with that cache, best of {args.runs} processes (c; target "
                 f"{TARGET_RUN_S:.0f} s wall); the slowest imports (d). The truth cache is "
                 "left as it is, so the 30-day truth is normally loaded, not computed.")
    env = child_env(cache)
    truth = env.get("XNAVLAB_CACHE", "~/.cache/xnavlab (default)")
    out = {"machine_before": machine_line(), "numba_cache_dir": str(cache),
           "xnavlab_cache": truth}
    print(f"machine: {out['machine_before']}")
    print(f"NUMBA_CACHE_DIR={cache} (empty at the start, {'kept' if keep else 'removed'} at "
          f"the end); truth cache XNAVLAB_CACHE={truth}, kept as it is")
    try:
        out["cold"] = warmup(env)
        print_warmup("a: cold numba cache", out["cold"], rec)
        print(f"target <= {TARGET_COMPILE_S:.0f} s: "
              f"{verdict(out['cold']['wall_s'] <= TARGET_COMPILE_S)}")
        out["warm"] = warmup(env)
        print_warmup("b: warm, the same cache again", out["warm"], rec)

        bare = min(timed(["-c", "pass"], env)[0] for _ in range(args.runs))
        version = min(timed(["-m", "xnavlab", "--version"], env)[0] for _ in range(args.runs))
        scen = min(timed(["-c", "import xnavlab.mars.navigation.scenarios"], env)[0]
                   for _ in range(args.runs))
        runs = []
        for _ in range(args.runs):
            wall, stdout, _ = timed(RUN_MARS, env)
            summary = json.loads(stdout)
            runs.append({"wall_s": wall, "run_time_s": summary["run_time_s"],
                         "filter_time_s": summary["filter_time_s"]})
        best = min(runs, key=lambda r: r["wall_s"])
        out["run_mars_30"] = {"runs": runs, "best": best, "python_c_pass_s": bare,
                              "version_s": version, "import_scenarios_s": scen}
        print(f"\n(c) python {' '.join(RUN_MARS)}, best of {args.runs} (warm numba cache)")
        rows = [
            ["python -c pass (interpreter alone)", f"{bare:.2f}"],
            ["python -m xnavlab --version", f"{version:.2f}"],
            ["python -c 'import xnavlab.mars.navigation.scenarios'", f"{scen:.2f}"],
            ["run mars --days 30: whole process", f"{best['wall_s']:.2f}"],
            ["  before the run (interpreter, imports, parser)",
             f"{best['wall_s'] - best['run_time_s']:.2f}"],
            ["  inputs (truth, measurements) and output",
             f"{best['run_time_s'] - best['filter_time_s']:.2f}"],
            ["  filter (as the JSON reports it)", f"{best['filter_time_s']:.2f}"],
        ]
        rec.table(["what", "best s"], rows, f"(c) `python {' '.join(RUN_MARS)}`, best of "
                  f"{args.runs}, warm numba cache; all runs: "
                  + ", ".join(f"{r['wall_s']:.2f}" for r in runs) + " s; target "
                  f"{TARGET_RUN_S:.0f} s: {'met' if best['wall_s'] <= TARGET_RUN_S else 'missed'}")
        print(f"target <= {TARGET_RUN_S:.0f} s wall: {verdict(best['wall_s'] <= TARGET_RUN_S)}")

        print("\n(d) imports")
        out["imports"] = [importtime(["-c", "import xnavlab.mars.navigation.scenarios"], env),
                          importtime(RUN_MARS, env)]
        for imp in out["imports"]:
            print_imports(imp, rec)
    finally:
        if not keep:
            shutil.rmtree(cache, ignore_errors=True)
    out["machine_after"] = machine_line()
    print(f"\nmachine: {out['machine_after']}")
    write_json(args.json, out)
    rec.note(f"(a) against its target of {TARGET_COMPILE_S:.0f} s: "
             f"{'met' if out['cold']['wall_s'] <= TARGET_COMPILE_S else 'missed'}.")
    rec.write()


if __name__ == "__main__":
    main()
