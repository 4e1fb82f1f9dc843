"""``python -m xnavlab run SCENARIO``: the scenarios, e.g. ``run mars --days 30``.

:data:`RUNNERS` is the table of scenarios: name -> (configure, execute, help).
"""

from __future__ import annotations

import argparse
import json
import re
import sys
import time
from pathlib import Path

from xnavlab.cli import Parser, UsageError, number
from xnavlab.core.federated import MODES
from xnavlab.core.userfiles import output_path, path_kind, write_whole
from xnavlab.core.validate import SEED_MAX, check_choice

__all__ = ["HELP", "FAULT_HELP", "RUNNERS", "configure", "execute", "configure_mars", "execute_mars",
           "out_dir"]

#: One-line help of the command (``python -m xnavlab --help``).
HELP = "run a scenario"


def _days(text):
    return number("--days", text, float, 0.0, 365.0, lo_open=True)


def _seed(text):
    return number("--seed", text, int, 0, SEED_MAX)


#: The fault-spec grammar, listed by ``run mars --help``.
FAULT_HELP = """\
fault spec: SENSOR[.COMPONENT]:KIND:MAGNITUDE@ONSET+DURATION, comma-separated; times in s
since the start, DURATION may be inf; no COMPONENT means every component of the sensor.
  sensor  components                              magnitude unit (a ramp: per second)
  xnav    B0531, B1937, B1957, B1821 (or 0-3;     s (delay); 1e-5 s = 3 km
          full names such as B1937+21 also work)
  uv      range, ux, uy, uz (or 0-3)              m (range); 1 (unit-vector components)
  cns     angle0, angle1, angle2 (or 0-2)         rad (starlight angle)
  kinds   step (+magnitude), ramp (+magnitude * (t - onset)), spike (one sample: DURATION
          0), stuck (output frozen: MAGNITUDE 0), noise (extra noise of that sigma)
Refused: a zero, NaN or infinite MAGNITUDE (a noise sigma must be > 0; a stuck fault's, a
number it would not use, must be 0); a DURATION <= 0 or NaN (a spike's must be 0); a fault
whose onset lies outside the run, or that acts on no sample of its sensor
(XNAV: one every 500 s); with the wavelet detector a UV or CNS
fault that starts inside the wavelets' training span (the first day, or half the run when
shorter); with the combined detector a fault that starts before 600 s (its innovation
tests watch while the wavelets train, so a UV or CNS fault inside the training span is
taken). 'paper' is the paper's 16-fault schedule (refused for a run that ends by its last
onset, 2400000 s: --days 27.77 or less; --days 27.84 lets its last faults act). A run too
short for the UV/CNS wavelets' training (356 samples in its first min(1, days / 2) days:
--days below 0.0248 with the wavelet or combined detector) is refused, after the faults'
own checks, naming --days.
Score (the summary's "score"): a fault is detected when an alarm on its sensor is raised
while it acts, [onset, end), or when that sensor was out of the fusion from before the
onset to the end (delay 0); an alarm up to 2000 s after the end (XNAV 18000 s) makes it
"late", never detected; an alarm that no fault explains is a false alarm (a late one is not).
A pulsar from a scenario file's timing model is named the same way (xnav.J0030 or its
index). --faults and --detector run with backend numba and the EKF only (a scenario file
with faults or a detector and another backend or local_filter is refused by --check).
example: --faults uv.range:step:25000@200000+3000,xnav.B1937+21:ramp:2e-9@300000+5000
"""


def out_dir(path):
    """``--out``: ``None``, or a directory that exists or is made now (before the run, so that
    no result is computed and then lost) and can be written; else ValueError."""
    if path is None:
        return None
    out = Path(path)
    if str(path).strip() and path_kind(out, "--out") not in ("missing", "folder"):
        raise ValueError(f"--out must be a directory (for mars_run.npz and mars_summary.json), "
                         f"but {str(out)!r} is a file")
    out = output_path(path, "--out", folder=True)
    for name in ("mars_run.npz", "mars_summary.json"):  # both checked before the run
        output_path(out / name, f"--out {str(path)!r}: {name}")
    return out


def configure_mars(parser):
    """Options of ``run mars``."""
    parser.formatter_class = argparse.RawDescriptionHelpFormatter
    parser.epilog = FAULT_HELP
    parser.add_argument("--scenario", metavar="FILE", dest="scenario_file",
                        help="a scenario file (TOML; python -m xnavlab scenario --dump writes "
                             "the defaults); the flags below override it")
    parser.add_argument("--days", default=None, help="simulated days (default 30)")
    parser.add_argument("--seed", default=None, help="noise seed (default 0)")
    parser.add_argument("--mode", default=None,
                        help="federated mode: reset (default) or no-reset")
    parser.add_argument("--backend", default=None, help="numba (default) or numpy")
    parser.add_argument("--json", action="store_true",
                        help="print one JSON object (no progress bar)")
    parser.add_argument("--quiet", action="store_true",
                        help="no progress bar (a terminal gets one on the numpy backend and "
                             "the UKF, the slow paths)")
    parser.add_argument("--out", metavar="DIR",
                        help="write mars_run.npz and mars_summary.json into DIR (made if missing, "
                             "with its parent folders)")
    parser.add_argument("--faults", metavar="SPEC",
                        help="SENSOR[.COMPONENT]:KIND:MAGNITUDE@ONSET+DURATION[,...] or 'paper' "
                             "(see 'fault spec' below)")
    parser.add_argument("--detector", default=None,
                        help="none, wavelet, chi2 or combined (default combined with faults, "
                             "else none: a plain run)")


def _as_typed(text, flags):
    """A message of :func:`~xnavlab.mars.navigation.scenario_files.with_overrides` in the
    words the user typed: the run's field an override replaced (``[run] days = 1``) and the
    closing ``(with days = 1, seed = 3)`` name the flags (``--days 1``); a flag the message
    already names is not repeated.

    ``flags`` maps a field to (its value as the scenario holds it or None, the flag's text).
    """
    given = re.search(r" \(with ([^()]*)\)$", text)
    body = text[:given.start()] if given else text
    tail = []
    for field, (value, typed) in flags.items():
        if value is None:
            continue
        shown = f"{value:g}" if isinstance(value, float) else f"{value}"
        flag = f"--{field} {typed}"
        body = body.replace(f"[run] {field} = {shown}", flag)  # the flag's value, not the file's
        if body.startswith(f"[run] {field} "):
            body = f"--{field} {body.removeprefix(f'[run] {field} ')}"
        if f"--{field}" not in body:
            tail.append(flag)
    return f"{body} (with {', '.join(tail)})" if tail else body


def _settings(args):
    """The scenario file (or the defaults) with the flags given on the command line applied."""
    from xnavlab.mars.navigation import scenario_files  # imported here: the parser stays light

    sf = (scenario_files.load(args.scenario_file) if args.scenario_file is not None
          else scenario_files.loads(""))
    days = None if args.days is None else _days(args.days)
    seed = None if args.seed is None else _seed(args.seed)
    mode = None if args.mode is None else check_choice("--mode", args.mode, MODES)
    try:  # the file's settings checked again against the flags, the file named
        sf = scenario_files.with_overrides(sf, days=days, seed=seed, mode=mode)
    except ValueError as exc:
        text = _as_typed(str(exc), {"days": (days, args.days), "seed": (seed, args.seed),
                                    "mode": (mode, args.mode)})
        if args.scenario_file is None:
            raise ValueError(text) from None
        raise ValueError(f"scenario file {args.scenario_file!r}: {text}") from None
    run, det = dict(sf.run), dict(sf.detector)
    if args.backend is not None:
        run["backend"] = check_choice("--backend", args.backend, ("numba", "numpy"))
    if args.faults is not None:
        if not args.faults.strip():  # an empty shell variable: "--faults $SPEC"
            raise UsageError("--faults is empty: give a fault spec or 'paper', or leave the "
                             "flag out for a fault-free run")
        det["faults"] = args.faults
    if args.detector is not None:
        det["name"] = args.detector
    flags = [f"{flag} {value}" for flag, value in (("--faults", args.faults),
                                                  ("--detector", args.detector)) if value is not None]
    if flags and args.scenario_file is not None:  # the file's detector keys for the new detector
        try:
            scenario_files.check_detector(det)
        except ValueError as exc:
            raise ValueError(f"scenario file {args.scenario_file!r}: {exc} (with "
                             f"{', '.join(flags)})") from None
    det["name"] = scenario_files.detector_name(det)  # combined with faults, else none
    return sf.scenario, run, det


def _check_fault_backend(args, opts, det):
    """Faults or a detector need the compiled EKF: refused in the words of what the user gave
    (a scenario file alone is refused when it is read; here one side came from a flag)."""
    bad = [f"--backend {args.backend}" if args.backend is not None else
           f'[run] backend = "{opts["backend"]}" in the scenario file'] \
        if opts["backend"] != "numba" else []
    if opts["local_filter"] != "ekf":
        bad.append(f'[run] local_filter = "{opts["local_filter"]}" in the scenario file')
    if bad:
        why = [f for f in ("--faults", "--detector") if getattr(args, f[2:]) is not None] \
            or [f"[detector] {'faults' if det['faults'] else 'name'} in the scenario file"]
        raise ValueError(f"{' and '.join(why)}: a fault-tolerant run needs backend numba and the "
                         f"EKF, got {' and '.join(bad)}")


def _fault_words(text, args):
    """A message of the fault checks (:func:`~xnavlab.mars.faults.schedules.parse_faults`,
    ``check_schedule``, ``check_armed``) in the user's words: their parameters ``spec`` and
    ``faults`` are ``--faults`` (or the scenario file's ``[detector] faults``), ``arm_s`` and
    ``train_days`` the file's ``[detector]`` keys, ``detector combined`` the flag."""
    source = "--faults" if args.faults is not None else "[detector] faults"
    text = re.sub(r"^(spec|faults)(?=[:\[ ])", source, text)
    text = re.sub(r"(?<!\] )\b(arm_s|train_days)\b", r"[detector] \1", text)
    text = text.replace("use detector combined", "use --detector combined")
    if args.scenario_file is not None and (args.faults is None or "[detector]" in text):
        return f"scenario file {args.scenario_file!r}: {text}"
    return text


def _check_schedule(args, sc, det):
    """The run's check of its faults and training span
    (:func:`xnavlab.mars.faults.schedules.check_schedule`) before any run: a fault's own problem
    first (its onset outside the run says how many days it needs), then a run too short for the
    wavelets' training, named as the user set the run's length (``--days``, or the scenario
    file's ``[run] days``), and a file's ``[detector] train_days`` under the file's name."""
    from xnavlab.mars.faults import schedules

    spec = det["faults"]
    try:
        faults = schedules.parse_faults(spec, sc) if spec else []
        faults = schedules.check_schedule(faults, sc, det["name"], det["train_days"],
                                          paper=spec.strip() == "paper")
        if det["name"] == "combined":  # run_fault_tolerant's check, in the user's words here
            schedules.check_armed(faults, det["arm_s"], sc)
    except schedules.RunTooShort as exc:   # train_days left out, min(1, days / 2): the length
        days, why = f"{exc.days:g}", exc.why
        need, train = f"{exc.need_days:g}", f"{exc.need_train_days:g}"
        if args.days is None and args.scenario_file is not None:
            raise ValueError(f"scenario file {args.scenario_file!r}: [run] days = {days} "
                             f"{why}: make it at least {need}, or set [detector] train_days "
                             f">= {train}") from None
        raise ValueError(f"--days {args.days if args.days is not None else days} {why}: run "
                         f"at least --days {need} (or set [detector] train_days >= {train} "
                         f"in a --scenario file)") from None
    except ValueError as exc:
        raise ValueError(_fault_words(str(exc), args)) from None


def execute_mars(args):
    """Run ``run mars``; returns the exit code."""
    sc, opts, det = _settings(args)
    from xnavlab.mars.navigation.scenarios import run  # imported here: the parser stays light

    t_start = time.perf_counter()
    detector, faults = det["name"], det["faults"]
    if faults or detector != "none":
        from xnavlab.mars.faults import fault_tolerance  # only a fault-tolerant run needs it

        check_choice("--detector", detector, fault_tolerance.DETECTORS)
        _check_fault_backend(args, opts, det)
        out_dir(args.out)
        _check_schedule(args, sc, det)  # a bad spec, then a fault the run cannot use, then days
        # the spec as given: run_fault_tolerant parses it and refuses a fault it cannot use
        ft = fault_tolerance.run_fault_tolerant(
            sc, faults or [], detector, pfa=det["pfa"], alpha=det["alpha"],
            train_days=det["train_days"], rate_per_day=det["rate_per_day"],
            adaptive=det["adaptive"], arm_s=det["arm_s"])
        res = ft  # its save_npz adds the isolation mask and the detector series
        summary = ft.summary(opts["settle_days"])
    else:
        out_dir(args.out)
        res = run(sc, backend=opts["backend"], local_filter=opts["local_filter"],
                  progress=sys.stderr.isatty() and not (args.json or args.quiet))
        summary = res.summary(opts["settle_days"])  # the API's own default settling
    summary["setup"] = "paper" if sc.paper_setup else "study"
    summary["truth_model"] = sc.truth_model.describe()
    summary["filter_model"] = sc.filter_model.describe()
    summary["q_acc"] = sc.q_acc
    summary["filter_time_s"] = summary.pop("run_time_s")
    summary["run_time_s"] = time.perf_counter() - t_start
    if args.out is not None:
        _write_out(args.out, res, summary)
    if args.json:
        from xnavlab.core.campaign import json_ready  # NaN as null: JSON has no NaN

        print(json.dumps(json_ready(summary), allow_nan=False))
    else:
        width = max(len(k) for k in summary)
        for key, val in summary.items():
            if isinstance(val, list | dict):
                items = val if isinstance(val, list) else [val]
                print(f"{key:{width}s}  {len(val)}")
                for item in items:
                    print(" " * (width + 2) + "  " + json.dumps(item))
                continue
            print(f"{key:{width}s}  {val:.6g}" if isinstance(val, float) else
                  f"{key:{width}s}  {val}")
    return 0


def _write_out(given, res, summary):
    """``mars_run.npz`` and ``mars_summary.json`` into ``--out``, each whole or not at all (a
    full disk leaves no file cut short); a write that fails is one line naming the file."""
    from xnavlab.core.campaign import json_ready

    out = out_dir(given)
    text = json.dumps(json_ready(summary), indent=2, allow_nan=False)  # NaN as null
    for name, write in (("mars_run.npz", res.save_npz),
                        ("mars_summary.json", lambda tmp: tmp.write_text(text))):
        try:
            write_whole(out / name, write)
        except OSError as exc:
            raise ValueError(f"--out {str(given)!r}: {name} cannot be written "
                             f"({exc.strerror or exc})") from None


#: Scenario name -> (configure(parser), execute(args) -> exit code, help).
RUNNERS = {
    "mars": (configure_mars, execute_mars,
             "the main paper's (Fan et al. 2016) 30-day federated Mars navigation run"),
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
