"""``python -m xnavlab run SCENARIO``: the scenarios, e.g. ``run mars --days 30``.

:data:`RUNNERS` is the table of scenarios: name -> (configure, execute, help).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from xnavlab.cli import Parser, UsageError
from xnavlab.core.federated import MODES
from xnavlab.core.validate import check_choice, check_int, check_real

__all__ = ["HELP", "FAULT_HELP", "RUNNERS", "configure", "execute", "configure_mars", "execute_mars",
           "out_dir"]

#: One-line help of the command (``python -m xnavlab --help``).
HELP = "run a scenario"


def _days(text):
    try:
        value = float(text)
    except ValueError:
        raise ValueError(f"days must be a real number in (0, 365], got {text!r}") from None
    return check_real("days", value, 0.0, 365.0, lo_open=True)


def _seed(text):
    try:
        value = int(text)
    except ValueError:
        raise ValueError(f"seed must be an integer in [0, 2^63 - 1], got {text!r}") from None
    return check_int("seed", value, 0, 2**63 - 1)


#: The fault-spec grammar, listed by ``run mars --help``.
FAULT_HELP = """\
fault spec: SENSOR[.COMPONENT]:KIND:MAGNITUDE@ONSET+DURATION, comma-separated; times in s
since the start, DURATION may be inf; no COMPONENT means every component of the sensor.
  sensor  components                              magnitude unit (a ramp: per second)
  xnav    B0531, B1937, B1957, B1821 (or 0-3;     s (delay); 1e-5 s = 3 km
          full names such as B1937+21 also work)
  uv      range, ux, uy, uz (or 0-3)              m (range); 1 (unit-vector components)
  cns     angle0, angle1, angle2 (or 0-2)         rad (starlight angle)
  kinds   step (+magnitude), ramp (+magnitude * (t - onset)), spike (one sample),
          stuck (output frozen; magnitude ignored), noise (extra noise of that sigma)
UV and CNS faults must start after the wavelets' training span (the first day, or half
the run when shorter) with the wavelet and combined detectors; every onset must lie in
the run. 'paper' is the paper's 16-fault schedule (needs --days 27.84 or more).
example: --faults uv.range:step:25000@200000+3000,xnav.B1937+21:ramp:2e-9@300000+5000
"""


def out_dir(path):
    """``--out``: ``None``, or a directory that exists or can be made; else ValueError."""
    if path is None:
        return None
    out = Path(path)
    if out.exists() and not out.is_dir():
        raise ValueError(f"out must be a directory (for mars_run.npz and mars_summary.json), "
                         f"but {str(out)!r} is a file")
    return out


def configure_mars(parser):
    """Options of ``run mars``."""
    parser.formatter_class = argparse.RawDescriptionHelpFormatter
    parser.epilog = FAULT_HELP
    parser.add_argument("--days", default="30", help="simulated days (default 30)")
    parser.add_argument("--seed", default="0", help="noise seed (default 0)")
    parser.add_argument("--mode", default="reset", help="federated mode: reset or no-reset")
    parser.add_argument("--backend", default="numba", help="numba (default) or numpy")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument("--out", metavar="DIR", help="write mars_run.npz and mars_summary.json")
    parser.add_argument("--faults", metavar="SPEC",
                        help="SENSOR[.COMPONENT]:KIND:MAGNITUDE@ONSET+DURATION[,...] or 'paper' "
                             "(see 'fault spec' below)")
    parser.add_argument("--detector", default=None,
                        help="none, wavelet, chi2 or combined (default combined with --faults, "
                             "else none)")


def execute_mars(args):
    """Run ``run mars``; returns the exit code."""
    days = _days(args.days)
    seed = _seed(args.seed)
    mode = check_choice("mode", args.mode, MODES)
    backend = check_choice("backend", args.backend, ("numba", "numpy"))
    from xnavlab.mars.scenarios import MarsScenario, run  # imported here: the parser stays light

    t_start = time.perf_counter()
    sc = MarsScenario(days=days, seed=seed, mode=mode)
    detector = args.detector or ("combined" if args.faults else "none")
    if args.faults or detector != "none":
        from xnavlab.mars import fault_tolerance  # only a fault-tolerant run needs it

        check_choice("detector", detector, fault_tolerance.DETECTORS)
        if backend != "numba":
            raise ValueError("--faults and --detector run with --backend numba only")
        out_dir(args.out)
        if args.faults:
            fault_tolerance.parse_faults(args.faults, sc)  # a bad spec is named before any run
        # the spec as given: run_fault_tolerant parses it and refuses a fault it cannot use
        ft = fault_tolerance.run_fault_tolerant(sc, args.faults or [], detector)
        res = ft  # its save_npz adds the isolation mask and the detector series
        summary = ft.summary()
    else:
        out_dir(args.out)
        res = run(sc, backend=backend, progress=sys.stderr.isatty())  # a bar for a terminal
        summary = res.summary()  # the API's own default settling (one source of defaults)
    summary["filter_time_s"] = summary.pop("run_time_s")
    summary["run_time_s"] = time.perf_counter() - t_start
    if args.out:
        out = out_dir(args.out)
        out.mkdir(parents=True, exist_ok=True)
        res.save_npz(out / "mars_run.npz")
        (out / "mars_summary.json").write_text(json.dumps(summary, indent=2))
    if args.json:
        print(json.dumps(summary))
    else:
        width = max(len(k) for k in summary)
        for key, val in summary.items():
            if isinstance(val, list):
                print(f"{key:{width}s}  {len(val)}")
                for item in val:
                    print(" " * (width + 2) + "  " + json.dumps(item))
                continue
            print(f"{key:{width}s}  {val:.6g}" if isinstance(val, float) else
                  f"{key:{width}s}  {val}")
    return 0


#: Scenario name -> (configure(parser), execute(args) -> exit code, help).
RUNNERS = {
    "mars": (configure_mars, execute_mars, "the main paper's 30-day federated Mars navigation run"),
}


def configure(parser):
    """Add one sub-command per scenario of :data:`RUNNERS`."""
    scen = parser.add_subparsers(dest="scenario", parser_class=Parser)
    for name, (conf, _, help_) in sorted(RUNNERS.items()):
        conf(scen.add_parser(name, help=help_))


def execute(args):
    """Run the chosen scenario."""
    if not args.scenario:
        raise UsageError("run needs a scenario: " + ", ".join(sorted(RUNNERS)))
    return RUNNERS[args.scenario][1](args)
