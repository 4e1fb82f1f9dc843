"""What a reader waits for at a slider: every ``explore`` frame of every chapter, timed.

Run: ``.venv/bin/python benchmarks/bench_sliders.py [--chapters 08 09] [--main-only]
[--revisit] [--think S] [--ipympl] [--json FILE] [--result FILE]``.

For each chapter ``book/NN_*.ipynb`` the code cells up to its last ``explore(`` call are
executed in this process (magic lines dropped, output silenced, Agg backend), with
:func:`xnavlab.core.widgets.explore` wrapped so that every :class:`~xnavlab.core.widgets.Explorer`
the chapter builds is kept; the time of those cells is printed as "set-up" (it is part of the
chapter's run-all, not of a slider frame). The positions are every one a reader reaches by
moving one control from the opening position (every value of every control's grid, the others
at their opening values; ``--main-only``: the scrubber's main control only), the opening one
first. Three ways of drawing them are timed:

- **from nothing**: each frame drawn for the first time in this process as the live widget
  drew it before figures were updated in place: the chapter's pure plotting function
  (:meth:`Explorer.figure <xnavlab.core.widgets.Explorer.figure>`), then its render
  (:func:`xnavlab.core.widgets.live_png` with the slider's kept
  :class:`~xnavlab.core.widgets.SteadyLayout`); function and render are reported apart;
- **in place**: the live widget itself (``ahead=False``), its controls set one at a time along
  a walk through the positions in that order (a position that differs from the last in two
  controls is two moves); each move timed from setting the control until the widget has shown
  the frame: an in-place update where the plotting function offers one
  (:func:`xnavlab.core.plotting.in_place`), a new figure where not, the kept PNG of a
  position seen before. Its frames are also written to disk (a reader's first session), into
  a frames directory of this run's own (``xnavlab/core/_frames.py``), empty at the start;
- **reopened**: the same walk in a new widget of the same slider (``ahead=False``: a chapter
  run again), whose moves find their frames on disk: a file read;
- **ahead**: the same walk with the frames computed ahead (``ahead=True``), the reader
  pausing ``--think`` seconds (default 2) after the opening frame and after every move (the
  worker runs meanwhile, in this process, as in a kernel). A move is counted as it is
  experienced: a move onto a frame the worker has finished is the lookup and display it takes
  (milliseconds, a "hit"); onto the frame in flight, the wait for it; elsewhere, the frame
  drawn at once while the worker may still be finishing its own (both share the GIL). Every
  move counts, hits included, in the median and the worst.

The targets (issue 38) are in CPU references, which carry from one machine to another: the
median move at most 10 references and the worst at most 20, the reference being
``sum(range(10**6))``'s time (:func:`_timing.cpu_ms`), measured before and after each slider
(the mean is used; the machine may be shared). The verdict is the ahead walk's. The load
average is printed with every number and stored in the JSON. ``--ipympl`` also times, for the
sliders with an in-place update, what ipympl's canvas does at a move in the kernel (its Agg
draw, then the PNG of the difference it sends), against the widget's PNG frame (skipped when
ipympl is not importable; it is not in ``environment.txt``).

The summary table is recorded with :class:`_timing.Record` in ``benchmarks/results/sliders.json``
(``--result`` writes it elsewhere, e.g. for a run of a few chapters), which
``benchmarks/report.py`` renders into ``benchmarks/README.md``; ``--json`` also writes every
frame's time.
"""

import argparse
import contextlib
import io
import json
import os
import re
import shutil
import statistics
import time
from pathlib import Path

os.environ.setdefault("MPLBACKEND", "Agg")

from _timing import (  # noqa: E402
    Record,
    chapters,
    cpu_ms,
    loadavg,
    machine_line,
    verdict,
    write_json,
)

#: Issue 38's targets, in CPU references (:func:`_timing.cpu_ms`).
TARGET_MEDIAN_REF = 10
TARGET_WORST_REF = 20
THINK_S = 2.0
_MAGIC = re.compile(r"^\s*[%!]")
ABOUT = (
    "Per slider, every position one control away from the opening one, walked one control at "
    "a time (seconds per move, median / worst). \"fn\" and \"render\": a frame drawn from "
    "nothing, its function and its render; \"nothing\": their sum; \"in place\": the live "
    "widget with `ahead=False` (each move timed from setting the control to the frame shown; "
    "its frames written to disk as in a reader's first session); \"reopened\": the same walk "
    "in a new widget of the same slider, its frames read from disk; \"ahead\": the widget "
    "with the frames computed ahead and a reader who pauses before each move, every move "
    "counted as experienced (\"hits\": moves onto a frame waiting in memory). \"refs\": "
    "seconds over the slider's CPU reference (the mean of its value before and after the "
    "slider). The verdict is the ahead walk's, against issue 38's targets in CPU references "
    f"(median {TARGET_MEDIAN_REF}, worst {TARGET_WORST_REF}).")


def explore_cells(nb):
    """Source of the code cells up to the last one that calls ``explore(``."""
    code = [c["source"] if isinstance(c["source"], str) else "".join(c["source"])
            for c in nb["cells"] if c["cell_type"] == "code"]
    calls = [i for i, s in enumerate(code)
             if re.search(r"(?<![\w.])explore\(", s) and "def explore" not in s]
    return code[: calls[-1] + 1] if calls else []


def explorers_of(path):
    """Execute a chapter's cells up to its last slider; its Explorers and the set-up time, s."""
    import matplotlib.pyplot as plt

    import xnavlab.core.widgets as widgets

    found, original = [], widgets.explore

    def recording(*args, **kwargs):
        ex = original(*args, **kwargs)
        # the same call again, with the frames computed ahead on or off
        ex.remake = lambda ahead: original(*args, **{**kwargs, "ahead": ahead})
        found.append(ex)
        return ex

    cells = explore_cells(json.loads(path.read_text()))
    namespace = {"__name__": "__main__"}
    cwd = os.getcwd()
    widgets.explore = recording
    t0 = time.perf_counter()
    try:
        os.chdir(path.parent)
        for src in cells:
            src = "\n".join("" if _MAGIC.match(ln) else ln for ln in src.splitlines())
            with contextlib.redirect_stdout(io.StringIO()):
                exec(compile(src, str(path), "exec"), namespace)  # noqa: S102
            plt.close("all")
    finally:
        widgets.explore = original
        os.chdir(cwd)
    return found, time.perf_counter() - t0


def frames_of(ex, main_only):
    """Every position one control away from the opening one, the opening position first."""
    out = [dict(ex.initial)]
    names = [ex.main] if main_only else list(ex.grids)
    for name in names:
        for value in ex.grids[name]:
            values = {**ex.initial, name: value}
            if values not in out:
                out.append(values)
    return out


def time_frame(ex, values):
    """(function s, render s, process CPU s, error line or None, layout) of one frame.

    Drawn as the live widget draws it; ``layout`` says how the frame was laid out
    (:attr:`SteadyLayout.last <xnavlab.core.widgets.SteadyLayout.last>`, ``None`` before it
    existed).

    A plotting function that raises is timed up to its exception (the live widget then shows
    :func:`~xnavlab.core.widgets.error_line` in place of the figure, with nothing to render).
    """
    import matplotlib.pyplot as plt

    from xnavlab.core.widgets import error_line

    c0, t0 = time.process_time(), time.perf_counter()
    try:
        fig = ex.figure(**values)
    except Exception as exc:  # the widget shows one error line instead: no render
        return time.perf_counter() - t0, 0.0, time.process_time() - c0, error_line(exc), None
    t1 = time.perf_counter()
    layout = getattr(ex, "layout", None)
    render_png(fig, layout)
    t2 = time.perf_counter()
    cpu = time.process_time() - c0
    plt.close(fig)
    return t1 - t0, t2 - t1, cpu, None, getattr(layout, "last", None)


def render_png(fig, layout=None):
    """The live widget's rendering of ``fig`` (PNG bytes), with its slider's kept ``layout``."""
    import xnavlab.core.widgets as widgets

    if layout is not None:
        return widgets.live_png(fig, layout)
    if hasattr(widgets, "live_png"):
        return widgets.live_png(fig)
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    return buf.getvalue()


def bench_explorer(ex, main_only, revisit):
    """Times of every frame of one slider drawn from nothing, with their summary."""
    frames = frames_of(ex, main_only)
    rows = []
    for values in frames:
        f, r, cpu, err, how = time_frame(ex, values)
        rows.append({"values": {k: repr(v) for k, v in values.items()}, "function_s": f,
                     "render_s": r, "total_s": f + r, "cpu_s": cpu, "error": err,
                     "layout": how})
    res = {"function": getattr(ex.plot, "__qualname__", repr(ex.plot)),
           "frames": rows, "n_frames": len(rows),
           "errors": [{"values": row["values"], "error": row["error"]}
                      for row in rows if row["error"]]}
    for part in ("function", "render", "total"):
        vals = [row[f"{part}_s"] for row in rows]
        res[f"{part}_median_s"], res[f"{part}_worst_s"] = statistics.median(vals), max(vals)
    # the opening frame is drawn when the chapter's cell runs, not at a move of a control
    res["opening_s"] = rows[0]["total_s"]
    res["move_worst_s"] = max((row["total_s"] for row in rows[1:]), default=0.0)
    res["cpu_median_s"] = statistics.median(row["cpu_s"] for row in rows)
    res["layouts"] = {how: sum(row["layout"] == how for row in rows)
                      for how in sorted({str(row["layout"]) for row in rows if row["layout"]})}
    if revisit:
        again = [sum(time_frame(ex, values)[:2]) for values in frames]
        res["revisit_median_s"] = statistics.median(again)
    return res


def walk(ex, main_only, ahead, think_s, disk=False):
    """The live widget moved along :func:`frames_of`'s positions, one control at a time.

    Returns the opening time and one row per move: the wall time from setting the control to
    the frame shown, and whether the frame was waiting in the widget's cache (drawn ahead,
    or seen before) or, with ``disk``, on disk (the frames directory of this run).
    """
    from xnavlab.core._frames import FRAME_CACHE_ENV
    from xnavlab.core.plotting import updater

    os.environ[FRAME_CACHE_ENV] = "1" if disk else "0"
    positions = frames_of(ex, main_only)
    live = ex.remake(ahead)
    on_disk = {"n": 0}
    load = live._disk.load

    def counted_load(path):
        png = load(path)
        on_disk["n"] += png is not None
        return png
    live._disk.load = counted_load
    with contextlib.redirect_stdout(io.StringIO()):  # the widget's display, outside a kernel
        t0 = time.perf_counter()
        w = live.widget()
        opening = time.perf_counter() - t0
        live._disk.path({}, "")  # the key's code hashed (in the background) before a reader moves
        controls = {c.description: c for c in w.children if "xnav-control" in c._dom_classes}
        moves = []
        try:
            for values in positions[1:]:
                for name, value in values.items():
                    control = controls[name]
                    if control.value == value:
                        continue
                    time.sleep(think_s)  # the reader looks at the frame; the worker works
                    cached = live._cache.get(live._position({**{n: c.value for n, c in
                                                                controls.items()},
                                                             name: value}), wait=False)
                    found = on_disk["n"]
                    t0 = time.perf_counter()
                    control.value = value
                    moves.append({"values": {n: repr(c.value) for n, c in controls.items()},
                                  "s": time.perf_counter() - t0,
                                  "hit": cached is not None or on_disk["n"] > found,
                                  "error": live.last_error})
        finally:
            in_place = updater(live._live["fig"]) is not None
            computed = live._worker.computed if live._worker is not None else 0
            live.close()
            if live._worker is not None:
                live._worker.idle(timeout=120)  # its last frame done before the next reference
    return {"opening_s": opening, "moves": moves, "in_place": in_place,
            "computed_ahead": computed}


def summary(moves):
    """(median s, worst s, hits) of a walk's moves."""
    times = [m["s"] for m in moves] or [0.0]
    return statistics.median(times), max(times), sum(m["hit"] for m in moves)


def ipympl_rows(ex, n=8):
    """(PNG frame s, ipympl draw and diff s, their kB) at ``n`` moves of the main control, or
    ``None`` without an in-place update or without ipympl."""
    from xnavlab.core.plotting import updater
    from xnavlab.core.widgets import SteadyLayout, live_png

    try:
        from ipympl.backend_nbagg import Canvas, FigureManager
    except ImportError:
        return None
    fig, other = ex.figure(), ex.figure()
    if updater(fig) is None:
        return None
    layout = SteadyLayout()
    live_png(fig, layout)
    canvas = Canvas(other)
    FigureManager(canvas, 1)
    canvas.syncing_data_url = False  # as after the front-end's 'initialized'
    sent = []
    canvas.send_binary = lambda data: sent.append(len(data))  # what goes to the browser
    canvas.draw()
    other.set_layout_engine("none")  # laid out once, as SteadyLayout does for the PNG frames
    ours, theirs, kb_ours, kb_theirs = [], [], [], []
    for value in ex.grids[ex.main][:n]:
        kwargs = {**ex.fixed, **ex.initial, ex.main: value}
        updater(fig)(**kwargs)
        t0 = time.perf_counter()
        png = live_png(fig, layout)
        t1 = time.perf_counter()
        updater(other)(**kwargs)
        t2 = time.perf_counter()
        canvas.draw()  # ipympl: the Agg draw, then the difference image as PNG
        t3 = time.perf_counter()
        ours.append(t1 - t0)
        theirs.append(t3 - t2)
        kb_ours.append(len(png) * 4 / 3 / 1e3)  # base64 in the widget's display message
        kb_theirs.append(sent[-1] / 1e3)  # binary in ipympl's comm message
    return tuple(statistics.median(v) for v in (ours, theirs, kb_ours, kb_theirs))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--chapters", nargs="+", metavar="NN", help="only these chapters")
    parser.add_argument("--main-only", action="store_true",
                        help="only the frames of each slider's main control")
    parser.add_argument("--revisit", action="store_true",
                        help="draw every frame from nothing a second time, report that median")
    parser.add_argument("--think", type=float, default=THINK_S, metavar="S",
                        help=f"the reader's pause before each move, s (default {THINK_S})")
    parser.add_argument("--ipympl", action="store_true",
                        help="also time ipympl's draw at a move (sliders updated in place)")
    parser.add_argument("--json", metavar="FILE", help="also write the results as JSON")
    parser.add_argument("--result", metavar="FILE",
                        help="where the recorded summary goes (default "
                             "benchmarks/results/sliders.json)")
    args = parser.parse_args()

    import tempfile

    import xnavlab.core._frames as frames

    frames_dir = Path(tempfile.mkdtemp(prefix="bench-sliders-"))  # this run's frames on disk
    frames.cache_dir = lambda: frames_dir
    rec = Record("sliders", "Sliders: a move, in CPU references (issue 38)", ABOUT)

    before = machine_line()
    print(f"machine: {before}")
    print(f"target: a move's median <= {TARGET_MEDIAN_REF} CPU references, worst <= "
          f"{TARGET_WORST_REF}, with frames computed ahead (reader's pause {args.think:g} s)\n")
    results, rows, extra = [], [], []
    for path in chapters(args.chapters):
        load0 = loadavg()
        explorers, setup = explorers_of(path)
        for ex in explorers:
            ref0 = cpu_ms()
            res = bench_explorer(ex, args.main_only, args.revisit)
            res["in_place"] = walk(ex, args.main_only, False, 0.0, disk=True)
            res["reopened"] = walk(ex, args.main_only, False, 0.0, disk=True)
            res["ahead"] = walk(ex, args.main_only, True, args.think)
            ref_ms = (ref0 + cpu_ms()) / 2
            med, worst, hits = summary(res["ahead"]["moves"])
            in_med, in_worst, in_hits = summary(res["in_place"]["moves"])
            re_med, re_worst, re_hits = summary(res["reopened"]["moves"])
            res.update(chapter=path.name, setup_s=setup, load_before=load0,
                       load_after=loadavg(), cpu_reference_ms=ref_ms, think_s=args.think,
                       median_ref=med / ref_ms * 1e3, worst_ref=worst / ref_ms * 1e3,
                       in_place_median_ref=in_med / ref_ms * 1e3,
                       in_place_worst_ref=in_worst / ref_ms * 1e3)
            res["ok"] = (res["median_ref"] <= TARGET_MEDIAN_REF
                         and res["worst_ref"] <= TARGET_WORST_REF)
            if args.ipympl:
                res["ipympl"] = ipympl_rows(ex)
            results.append(res)
            n_moves = len(res["ahead"]["moves"])
            print(f"{path.name}: {res['function']}, {res['n_frames']} positions, "
                  f"set-up {setup:.1f} s, CPU reference {ref_ms:.0f} ms; from nothing median "
                  f"{res['total_median_s']:.3f} s (function {res['function_median_s']:.3f}, "
                  f"render {res['render_median_s']:.3f}), worst move {res['move_worst_s']:.3f} s;"
                  f" in place {in_med:.3f} / {in_worst:.3f} s; reopened {re_med:.3f} / "
                  f"{re_worst:.3f} s ({re_hits} from disk); ahead {med:.3f} / {worst:.3f} s, "
                  f"{hits} of {n_moves} moves from the cache (load {load0} -> "
                  f"{res['load_after']})"
                  + (f"; {len(res['errors'])} frames raised, e.g. {res['errors'][0]['error']}"
                     if res["errors"] else ""), flush=True)
            rows.append([path.name[:2], res["function"], n_moves,
                         "yes" if res["in_place"]["in_place"] else "no", f"{ref_ms:.0f}",
                         f"{res['function_median_s']:.3f}", f"{res['render_median_s']:.3f}",
                         f"{res['total_median_s']:.3f} / {res['move_worst_s']:.3f}",
                         f"{in_med:.3f} / {in_worst:.3f}",
                         f"{res['in_place_median_ref']:.1f} / {res['in_place_worst_ref']:.1f}",
                         f"{med:.3f} / {worst:.3f}",
                         f"{hits}/{n_moves}",
                         f"{re_med:.3f} / {re_worst:.3f}", f"{re_hits}/{n_moves}",
                         f"{res['median_ref']:.1f} / {res['worst_ref']:.1f}"]
                        + ([f"{res['revisit_median_s']:.3f}"] if args.revisit else [])
                        + [verdict(res["ok"]), res["load_after"].split(",")[0]])
            if res.get("ipympl"):
                extra.append([path.name[:2], res["function"]]
                             + [f"{v:.3f}" for v in res["ipympl"][:2]]
                             + [f"{v:.0f}" for v in res["ipympl"][2:]])
        if not explorers:
            print(f"{path.name}: no explore call")
        write_json(args.json, {"machine_before": before, "machine_now": machine_line(),
                               "target_median_ref": TARGET_MEDIAN_REF,
                               "target_worst_ref": TARGET_WORST_REF, "sliders": results})
    print()
    rec.table(["ch", "function", "moves", "in place", "ref ms", "fn med", "render med",
               "nothing med/worst", "in place med/worst", "in place refs", "ahead med/worst",
               "hits", "reopened med/worst", "from disk", "ahead refs med/worst"]
              + (["revisit med"] if args.revisit else []) + ["verdict", "load 1m"], rows)
    if extra:
        print()
        rec.table(["ch", "function", "PNG frame s", "ipympl draw s", "PNG kB", "ipympl kB"],
                  extra, "ipympl's draw at a move against the widget's PNG frame")
    after = machine_line()
    print(f"\nseconds per move (median / worst); refs = seconds / CPU reference; the verdict is "
          f"the ahead walk's\nmachine: {after}")
    write_json(args.json, {"machine_before": before, "machine_after": after,
                           "target_median_ref": TARGET_MEDIAN_REF,
                           "target_worst_ref": TARGET_WORST_REF, "sliders": results})
    errors = sum(len(r["errors"]) for r in results)
    if errors:
        rec.note(f"{errors} frames raised in their plotting function (shown as an error line "
                 "by the widget; listed in the `--json` file).")
    rec.write(args.result)
    shutil.rmtree(frames_dir, ignore_errors=True)


if __name__ == "__main__":
    main()
