"""The cost of the guarded filter steps: ``check=True`` (the default) against ``check=False``.

Run: ``.venv/bin/python benchmarks/bench_guarded.py [--calls N]``. Times the core steps of
:mod:`xnavlab.core.filters` (EKF and UKF predict and update) and
:func:`xnavlab.core.federated.fuse` on the Mars run's sizes (state of 6, a measurement of 4 as
XNAV's four pulsars, three locals fused), each the best of 5 repeats of ``N`` calls (default
2000), and prints the time per call with and without the checks, their ratio and the checks'
cost per call. The compiled Mars loop (:mod:`xnavlab.mars.kernel.kernels`) does not call these steps,
so its speed does not depend on them; the guard matters for code that calls the steps in a
Python loop.
"""

import argparse

import numpy as np
from _timing import Record, best_of

from xnavlab.core import federated, filters

N, M = 6, 4            # state (position, velocity) and measurement sizes


def problem(seed=0):
    """A well-conditioned random problem of the Mars sizes (one seed)."""
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(N, N))
    P = A @ A.T + N * np.eye(N)
    F = np.eye(N) + 0.01 * rng.normal(size=(N, N))
    H = rng.normal(size=(M, N))
    return {"x": rng.normal(size=N), "P": P, "F": F, "Q": 1e-3 * np.eye(N), "H": H,
            "R": 0.5 * np.eye(M), "z": rng.normal(size=M)}


def steps(p):
    """Step name -> function of ``check`` calling that step once."""
    x, P, F, Q, H, R, z = (p[k] for k in ("x", "P", "F", "Q", "H", "R", "z"))
    Ps = [P, 2.0 * P, 3.0 * P]
    xs = [x, x + 0.1, x - 0.1]
    return {
        "ekf_predict": lambda c: filters.ekf_predict(x, P, F @ x, F, Q, check=c),
        "ekf_update": lambda c: filters.ekf_update(x, P, z, H @ x, H, R, check=c),
        "ukf_predict": lambda c: filters.ukf_predict(x, P, lambda s: s @ F.T, Q, check=c),
        "ukf_update": lambda c: filters.ukf_update(x, P, z, lambda s: s @ H.T, R, check=c),
        "fuse (3 locals)": lambda c: federated.fuse(xs, Ps, check=c),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--calls", type=int, default=2000)
    args = ap.parse_args()
    rec = Record("guarded", "The filters' input checks: cost per call",
                 f"Each step with its checks on and off, {args.calls} calls, best of 5, "
                 "microseconds per call.")
    rows = []
    for name, step in steps(problem()).items():
        step(True), step(False)                          # warm caches, check they run
        per = {}
        for check in (True, False):
            wall = best_of(lambda s=step, c=check: [s(c) for _ in range(args.calls)], repeat=5)
            per[check] = wall / args.calls * 1e6         # microseconds per call
        rows.append([name, f"{per[True]:.1f}", f"{per[False]:.1f}",
                     f"{per[True] / per[False]:.2f}", f"{per[True] - per[False]:.1f}"])
    rec.table(["step", "check=True us", "check=False us", "ratio", "checks us"], rows)
    rec.write()


if __name__ == "__main__":
    main()
