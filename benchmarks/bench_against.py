"""The Mars filter's speed against an earlier commit: did a refactor cost time?

Run: ``.venv/bin/python benchmarks/bench_against.py --base REV [--rounds 3]``.

The commit ``REV`` is checked out into a temporary git worktree beside this one and both trees
are imported in turn by the same interpreter (``PYTHONPATH`` pointing at the tree), each with
its own numba cache: the filter kernel is compiled first into that empty cache, and the
compile's CPU time is reported beside the runs'. Then, in alternating rounds (base,
this tree, base, ...) so that a change in the machine's load hits both alike, one process
per tree and round measures on the paper's 30-day inputs, by CPU time
(``time.process_time``, best of 3 within the round): the clean 30-day filter run and the
paper's fault schedule under each detector (combined, wavelet, chi-square). It prints, per
quantity, the best over the rounds for each tree and the ratio; a ratio within 1.05 is within
5 %. CPU time, not wall time: on a shared machine the wall time is mostly the load's.

The outputs are compared too: every run's fused estimate must be identical (``np.array_equal``)
between the two trees, else the script says which differs (a speed-up that changes numbers is
not a refactor).
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from _timing import ROOT, Record

RUNS = r"""
import hashlib, json, sys, time, warnings
warnings.simplefilter("ignore", DeprecationWarning)
import numpy as np
import importlib
def module(name):  # a tree before or after mars's subpackages (issue 37): its own path first
    # (a path the tree lacks must not be asked first: the editable install would answer it)
    for sub in ("", "navigation.", "faults."):
        try:
            return importlib.import_module("xnavlab.mars." + sub + name)
        except ImportError:
            pass
    raise ImportError(name)
scenarios, fault_tolerance = module("scenarios"), module("fault_tolerance")
inp = scenarios.prepare(days=30.0, seed=0)
def best(f, n=3):
    ts, out = [], None
    for _ in range(n):
        c0 = time.process_time(); out = f(); ts.append(time.process_time() - c0)
    return min(ts), out
def digest(a):
    return hashlib.sha256(np.ascontiguousarray(a).tobytes()).hexdigest()[:16]
res = {}
cpu, run = best(lambda: scenarios.run(inputs=inp))
res["clean 30 days"] = [cpu, digest(run.x)]
for det in ("combined", "wavelet", "chi2"):
    cpu, ft = best(lambda: fault_tolerance.run_fault_tolerant(faults="paper", detector=det,
                                                             inputs=inp))
    res[f"paper faults, {det}"] = [cpu, digest(ft.run.x)]
print(json.dumps(res))
"""

# the filter kernel's compile into an empty numba cache, by CPU time (the compile is one thread)
COMPILE = """
import json, time
from xnavlab.cli import warmup
c0 = time.process_time()
warmup.compile_kernel()
print(json.dumps(time.process_time() - c0))
"""


def run_in(tree, cache, code):
    """Run ``code`` with ``tree`` first on the path and its own numba cache; its stdout."""
    env = dict(os.environ, PYTHONPATH=str(tree), NUMBA_CACHE_DIR=str(cache), MPLBACKEND="Agg")
    proc = subprocess.run([sys.executable, "-c", code], cwd=tree, env=env, text=True,
                          capture_output=True, check=False)
    if proc.returncode:
        raise SystemExit(f"bench_against: {tree} failed:\n{proc.stderr[-2000:]}")
    return proc.stdout


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", required=True, help="the earlier commit to compare against")
    parser.add_argument("--rounds", type=int, default=3, help="alternating rounds (default 3)")
    args = parser.parse_args(argv)
    if args.rounds < 1:
        parser.error(f"--rounds must be at least 1, got {args.rounds}")
    rec = Record("against", f"The Mars filter against commit {args.base}",
                 f"CPU seconds, best over {args.rounds} alternating rounds, each tree with its own "
                 "numba cache; the outputs compared bit for bit.")
    with tempfile.TemporaryDirectory(prefix="xnav-bench-against-") as tmp:
        base = Path(tmp) / "base"
        subprocess.run(["git", "worktree", "add", "--detach", str(base), args.base], cwd=ROOT,
                       check=True, capture_output=True)
        try:
            trees = {"base": base, "this": ROOT}
            caches = {name: Path(tmp) / f"numba-{name}" for name in trees}
            compile_cpu = {}
            for name, tree in trees.items():
                print(f"compiling {name} ({tree}) ...", flush=True)
                compile_cpu[name] = json.loads(run_in(tree, caches[name], COMPILE))
            best = {}
            for r in range(args.rounds):
                print(f"round {r + 1}: load {os.getloadavg()[0]:.2f}", flush=True)
                for name, tree in trees.items():
                    for key, (cpu, dig) in json.loads(run_in(tree, caches[name], RUNS)).items():
                        old = best.setdefault(key, {}).get(name)
                        best[key][name] = (min(cpu, old[0]) if old else cpu, dig)
        finally:
            subprocess.run(["git", "worktree", "remove", "--force", str(base)], cwd=ROOT,
                           check=False, capture_output=True)
    rows = []
    for key, row in best.items():
        (b, db), (t, dt) = row["base"], row["this"]
        rows.append([key, f"{b:.3f}", f"{t:.3f}", f"{t / b:.3f}", "identical" if db == dt else "DIFFERENT"])
    b, t = compile_cpu["base"], compile_cpu["this"]
    rows.append(["kernel compile, once, into an empty cache", f"{b:.1f}", f"{t:.1f}", f"{t / b:.3f}", ""])
    print()
    rec.table(["run", "base (CPU s)", "this tree (CPU s)", "this / base", "outputs"], rows)
    rec.write()
    return 0


if __name__ == "__main__":
    sys.exit(main())
