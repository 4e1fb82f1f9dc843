"""Render the benchmarks' results into ``benchmarks/README.md`` (``make benchmarks-page``).

Every ``benchmarks/results/<name>.json`` (written by a benchmark through ``_timing.Record``,
or transcribed from an earlier run's printed output, which the file then says) becomes one
section of the page, between the lines ``<!-- begin generated: <name> -->`` and
``<!-- end generated: <name> -->``: a heading, one line with the date, the command, the
machine, the CPU reference and the load (the lower and the higher of their values before and
after the run), then the tables. The rest of the page is written
by hand. A result without its marked section, or a marked section without its result, is an
error: the markers are placed by hand where the result belongs in the page's story.

Run: ``.venv/bin/python benchmarks/report.py`` (rewrites the page) or ``--check`` (exit 1 if
the page is not the rendering of the results, changing nothing).
"""

import argparse
import json
import re
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"
PAGE = HERE / "README.md"

SECTION = re.compile(r"(<!-- begin generated: ([\w-]+) -->\n)(.*?)(<!-- end generated: \2 -->)",
                     re.DOTALL)


def _span(pair, unit=""):
    """``"a-b unit"`` from a ``[before, after]`` pair (one number when they agree)."""
    vals = [v for v in pair if v is not None]
    if not vals:
        return "not recorded"
    lo, hi = min(vals), max(vals)
    text = f"{lo:g}" if lo == hi else f"{lo:g}-{hi:g}"
    return f"{text}{unit}"


def machine_text(m):
    """One phrase naming the machine of a result (the fields it has)."""
    parts = [m.get("cpu"), f"{m['cores']} cores" if m.get("cores") else None, m.get("system"),
             f"Python {m['python']}" if m.get("python") else None]
    if m.get("numpy"):
        parts.append(f"numpy {m['numpy']}" + (f" ({m['blas']})" if m.get("blas") else ""))
    return ", ".join(p for p in parts if p) or "not recorded"


def dated_line(data):
    """The section's one line: when, how, on what, at which CPU reference and load."""
    how = [f"by `{data['command']}`"] if data.get("command") else []
    if data.get("source"):
        how.append(f"transcribed from {data['source']}")
    return (f"Measured {data['date']} {', '.join(how)}; machine: "
            f"{machine_text(data.get('machine', {}))}; CPU reference `sum(range(10**6))` "
            f"{_span(data.get('cpu_reference_ms', []), ' ms')}, load (1 min) "
            f"{_span(data.get('load_1min', []))}.")


def _cell(text):
    return str(text).replace("|", "\\|").replace("\n", " ")


def markdown_table(columns, rows):
    """A markdown table; a column empty in every row is left out."""
    keep = [i for i in range(len(columns)) if any(str(r[i]).strip() for r in rows)] or \
        list(range(len(columns)))
    out = ["| " + " | ".join(_cell(columns[i]) for i in keep) + " |",
           "|" + "---|" * len(keep)]
    out += ["| " + " | ".join(_cell(r[i]) for i in keep) + " |" for r in rows]
    return out


def render(data):
    """The markdown of one result (without its markers)."""
    lines = [f"### {data['title']}", ""]
    if data.get("about"):
        lines += [data["about"], ""]
    lines.append(dated_line(data))
    for t in data["tables"]:
        lines.append("")
        if t.get("title"):
            lines += [f"**{t['title']}**", ""]
        lines += markdown_table(t["columns"], t["rows"])
    for note in data.get("notes", []):
        lines += ["", note]
    return "\n".join(lines) + "\n"


def load_results(folder=RESULTS):
    """Every result in ``folder``, by name (the file's stem)."""
    out = {}
    for path in sorted(Path(folder).glob("*.json")):
        data = json.loads(path.read_text())
        if data.get("name", path.stem) != path.stem:
            raise ValueError(f"{path}: name {data.get('name')!r} is not the file's stem")
        out[path.stem] = data
    return out


def rendered(page_text, results):
    """``page_text`` with every marked section replaced by the rendering of its result."""
    marked = [m.group(2) for m in SECTION.finditer(page_text)]
    missing = sorted(set(results) - set(marked))
    unknown = sorted(set(marked) - set(results))
    twice = sorted({n for n in marked if marked.count(n) > 1})
    problems = ([f"results without a marked section in the page: {', '.join(missing)}"] * bool(missing)
                + [f"marked sections without a result: {', '.join(unknown)}"] * bool(unknown)
                + [f"sections marked twice: {', '.join(twice)}"] * bool(twice))
    if problems:
        raise ValueError("; ".join(problems))
    return SECTION.sub(lambda m: m.group(1) + render(results[m.group(2)]) + m.group(4), page_text)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true",
                        help="exit 1 if the page is not the rendering of the results")
    args = parser.parse_args(argv)
    text = PAGE.read_text()
    new = rendered(text, load_results())
    if args.check:
        if new != text:
            print(f"{PAGE.relative_to(HERE.parent)} is not the rendering of benchmarks/results/: "
                  "run `make benchmarks-page`", file=sys.stderr)
            return 1
        return 0
    if new != text:
        PAGE.write_text(new)
        print(f"rewrote {PAGE.relative_to(HERE.parent)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
