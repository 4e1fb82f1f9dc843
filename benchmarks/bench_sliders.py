"""What a reader waits for at a slider: every ``explore`` frame of every chapter, timed.

Run: ``.venv/bin/python benchmarks/bench_sliders.py [--chapters 08 09] [--main-only]
[--revisit] [--json FILE]``.

For each chapter ``book/NN_*.ipynb`` the code cells up to its last ``explore(`` call are
executed in this process (magic lines dropped, output silenced, Agg backend), with
:func:`xnavlab.core.widgets.explore` wrapped so that every :class:`~xnavlab.core.widgets.Explorer`
the chapter builds is kept; the time of those cells is printed as "set-up" (it is part of the
chapter's run-all, not of a slider frame). Then every frame a reader can reach by moving one
control from the opening position (every value of every control's grid, the others at their
opening values; ``--main-only``: the scrubber's main control only) is drawn once, in the order
a reader would meet them (the opening frame first), and timed in two parts, as the live widget
draws it:

- the function: :meth:`Explorer.figure <xnavlab.core.widgets.Explorer.figure>`, i.e. the
  chapter's pure plotting function with those values;
- the render: the PNG the live widget sends to the browser, at the figure's own dpi (Agg):
  :func:`xnavlab.core.widgets.live_png` with the slider's
  :class:`~xnavlab.core.widgets.SteadyLayout` (the opening frame's layout, kept for the
  others; before it existed every frame ran its own layout, and before ``live_png`` existed
  the widget called ``fig.savefig(BytesIO, format="png")``: this script falls back to each).

A frame is drawn for the first time in this process (a cache inside a plotting function
helps only frames already seen; ``--revisit`` draws every frame a second time and reports
that median too). Per slider: the median and worst of function, render and the two
together, against the target (median 0.3 s or less, worst 0.5 s or less, function plus
render, on 2 cores). The worst is taken over the moves, the frames after the opening one:
the opening frame is drawn when the chapter's cell runs (it lays the figure out, see
:class:`~xnavlab.core.widgets.SteadyLayout`), and its time is reported on its own. The
machine may be shared: the load average is printed before and after
each chapter and stored with every number in the JSON.
"""

import argparse
import contextlib
import io
import json
import os
import re
import statistics
import time

os.environ.setdefault("MPLBACKEND", "Agg")

from _timing import chapters, loadavg, machine_line, table, verdict, write_json  # noqa: E402

TARGET_MEDIAN_S = 0.3
TARGET_WORST_S = 0.5
_MAGIC = re.compile(r"^\s*[%!]")


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
    """Times of every frame of one slider, with their summary against the target."""
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
    res["ok"] = (res["total_median_s"] <= TARGET_MEDIAN_S
                 and res["move_worst_s"] <= TARGET_WORST_S)
    return res


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--chapters", nargs="+", metavar="NN", help="only these chapters")
    parser.add_argument("--main-only", action="store_true",
                        help="only the frames of each slider's main control")
    parser.add_argument("--revisit", action="store_true",
                        help="draw every frame a second time and report that median too")
    parser.add_argument("--json", metavar="FILE", help="also write the results as JSON")
    args = parser.parse_args()

    before = machine_line()
    print(f"machine: {before}")
    print(f"target: function + render, median <= {TARGET_MEDIAN_S} s, "
          f"worst <= {TARGET_WORST_S} s\n")
    results, rows = [], []
    for path in chapters(args.chapters):
        load0 = loadavg()
        explorers, setup = explorers_of(path)
        for ex in explorers:
            res = bench_explorer(ex, args.main_only, args.revisit)
            res.update(chapter=path.name, setup_s=setup, load_before=load0,
                       load_after=loadavg())
            results.append(res)
            print(f"{path.name}: {res['function']}, {res['n_frames']} frames, "
                  f"set-up {setup:.1f} s; total median {res['total_median_s']:.3f} s, "
                  f"worst move {res['move_worst_s']:.3f} s, opening {res['opening_s']:.3f} s "
                  f"(load {load0} -> {res['load_after']})"
                  + (f"; layout {res['layouts']}" if res["layouts"] else "")
                  + (f"; {len(res['errors'])} frames raised, e.g. {res['errors'][0]['error']}"
                     if res["errors"] else ""), flush=True)
            rows.append([path.name[:2], res["function"], res["n_frames"],
                         f"{res['function_median_s']:.3f}", f"{res['function_worst_s']:.3f}",
                         f"{res['render_median_s']:.3f}", f"{res['render_worst_s']:.3f}",
                         f"{res['total_median_s']:.3f}", f"{res['move_worst_s']:.3f}",
                         f"{res['opening_s']:.3f}",
                         f"{res['cpu_median_s']:.3f}"]
                        + ([f"{res['revisit_median_s']:.3f}"] if args.revisit else [])
                        + [verdict(res["ok"]), res["load_after"].split(",")[0]])
        if not explorers:
            print(f"{path.name}: no explore call")
        write_json(args.json, {"machine_before": before, "machine_now": machine_line(),
                               "target_median_s": TARGET_MEDIAN_S,
                               "target_worst_s": TARGET_WORST_S, "sliders": results})
    print()
    table(["ch", "function", "frames", "fn med", "fn worst", "render med", "render worst",
           "total med", "move worst", "opening", "cpu med"]
          + (["revisit med"] if args.revisit else []) + ["verdict", "load 1m"], rows)
    after = machine_line()
    print(f"\nseconds per frame; cpu = process CPU time of function + render\nmachine: {after}")
    write_json(args.json, {"machine_before": before, "machine_after": after,
                           "target_median_s": TARGET_MEDIAN_S, "target_worst_s": TARGET_WORST_S,
                           "sliders": results})
    errors = sum(len(r["errors"]) for r in results)
    if errors:
        print(f"{errors} frames raised in their plotting function (shown as an error line by "
              "the widget; listed in the JSON)")


if __name__ == "__main__":
    main()
