"""Check the rendered book as a reader sees it: every HTML page of a built book.

Our tests check the notebooks; this checks the pages. It reads every page of a built book
(default ``_build/html``: the chapters, the dashboard, the notation page, the API pages, the
index) and prints one line per problem, ``page: what``:

* a table row whose cell count (with ``colspan`` and ``rowspan``) differs from its header's;
* a verdict cell (in a column headed "verdict" or "pass", in any table) whose text is not one
  of :data:`xnavlab.reproduce.VERDICTS` (a row's: REPRODUCED, NOT REPRODUCED, UNDECIDED, CHECK,
  CHECK FAILED) or :data:`xnavlab.reproduce.HEADLINES` (a reproduction's: those of a claim and
  PARTLY REPRODUCED, CHECK, ERROR);
* a template leak on a chapter or the dashboard, in prose or in an output: a ``nan`` or
  ``inf`` shown as a number, or a "(s)" plural;
* a visible code cell (its input shown on the page) that holds ``glue(`` or a bare ``assert``:
  bookkeeping belongs in cells whose input is removed (``remove-input``/``remove-cell``);
* a literal ``|`` in body text outside math, code and ``pre`` (a Markdown table broken by a bar
  in a cell leaves one; text that the registry rendered escaped, classes ``xnav-*``, cannot
  break and may hold one), and a literal ``$`` there (math that did not render);
* an unresolved reference: a sphinx ``xref`` that is not a link (a Python one only when it
  names an xnavlab object: other packages' names and builtins are left unlinked on purpose,
  as in the nitpick settings of ``_config.yml``), ``??``, a raw ``{eq}``/``{ref}``/``{doc}``...
  role, an "eq. (some-label)" showing the label instead of a number, ``[missing reference]``,
  a literal ``{glue:...}`` or ``{eval}``, myst-nb's "glue key not found", a ``{glue:text}`` or
  ``{eval}`` role of the page's source that rendered as nothing, and a glued value shown
  unformatted (``np.float64(...)``);
* an ``<img>`` whose file is missing;
* an empty output (a cell output area, or one output in it, with nothing in it);
* an exercise without a solution, a solution not collapsed (no ``dropdown`` class), a solution
  with no executed code cell, and an old prose "Solution" admonition.

Usage (from the repository root)::

    .venv/bin/python tools/check_book.py                  # _build/html
    .venv/bin/python tools/check_book.py --html /tmp/book/_build/html

Exit status: 0 no problem, 1 some problem, 2 a bad argument (no such directory, no page).
"""

from __future__ import annotations

import argparse
import builtins
import concurrent.futures
import importlib.util
import itertools
import os
import re
import sys
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import unquote, urlsplit

from bs4 import BeautifulSoup, Comment, Declaration, Doctype, NavigableString, ProcessingInstruction

try:
    from xnavlab.reproduce import HEADLINES, VERDICTS
except ImportError:  # pragma: no cover - the tool runs in the project's environment
    VERDICTS = ("REPRODUCED", "NOT REPRODUCED", "UNDECIDED", "CHECK", "CHECK FAILED")
    HEADLINES = ("REPRODUCED", "PARTLY REPRODUCED", "NOT REPRODUCED", "UNDECIDED", "CHECK", "ERROR")

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_HTML = ROOT / "_build" / "html"
#: directories and pages of a build that are not the book's content
SKIP_DIRS = {"_static", "_sources", "_images", "_panels_static", "_sphinx_design_static"}
SKIP_PAGES = {"genindex.html", "search.html", "py-modindex.html"}
#: headers of a verdict column
VERDICT_HEADERS = {"verdict", "verdicts", "pass", "passed", "pass?"}

_CODE_TAGS = {"pre", "code", "kbd", "samp", "tt", "script", "style", "textarea", "svg", "math",
              "mjx-container", "head", "title", "template", "noscript"}
_CODE_CLASSES = {"math", "highlight", "MathJax", "MathJax_Preview", "mjx-chtml", "xnav-verbatim"}
_MATH_SOURCE = re.compile(r"\\\(.*?\\\)|\\\[.*?\\\]|\$\$.*?\$\$", re.S)
_RAW_ROLE = re.compile(r"\{(?:eq|ref|numref|doc|cite(?::\w+)?|glue(?::\w*)?|eval|math|term|download"
                       r"|prf:ref|any|py:\w+|abbr)\}")
_EQ_LABEL = re.compile(r"\b(?:eqs?|equations?)\.?\s*\(([A-Za-z][\w.:]*[-_:][\w.:-]*)\)", re.I)
_GLUE_TEXT = re.compile(r"\{glue:text\}`[^`]+`")
_EVAL = re.compile(r"\{eval\}`[^`]+`")
#: what myst-nb renders a {glue:text} and an {eval} (a value's text/plain, inline) as
_PASTED = ".pasted-text, .pasted-inline, span.output.text_plain"
#: containers whose text was escaped by xnavlab (reproduce.Result.html, plotting.html_table)
_ESCAPED_CLASSES = {"xnav-table", "xnav-note", "xnav-notes", "xnav-result", "xnav-headline",
                    "xnav-error"}
_UNFORMATTED = re.compile(r"\b(?:np|numpy)\.\w+\(")
#: a number that is not one, or a plural left to the reader: a template that printed for a case
#: it was not written for
_LEAK = re.compile(r"(?<![\w.])(?:nan|NaN|-?inf|-?Infinity)(?![\w(-])|\w\(s\)")
#: a visible code line that is bookkeeping, not the idea
_BOOKKEEPING = re.compile(r"(?<![\w.])glue\(|^\s*assert\b", re.M)
#: pages that show chapters' prose and outputs (the API reference quotes code: not checked)
_CHAPTER_PAGE = re.compile(r"(?:^|/)(?:\d\d_[^/]*|dashboard)\.html$")
_VISIBLE = {"img", "svg", "table", "iframe", "object", "video", "canvas", "input", "embed",
            "mjx-container", "math"}


@dataclass(frozen=True)
class Problem:
    """One problem of one page."""

    page: str
    what: str

    def __str__(self):
        return f"{self.page}: {self.what}"


def _classes(tag):
    return set(tag.get("class") or ())


def _in_code(node):
    for parent in node.parents:
        if parent.name in _CODE_TAGS or _classes(parent) & _CODE_CLASSES:
            return True
    return False


def _escaped(node):
    return any(_classes(parent) & _ESCAPED_CLASSES for parent in node.parents)


def _foreign_python_name(text):
    """Whether an unlinked Python reference names a builtin or another package's object."""
    name = text.strip().rstrip("()").lstrip("~.")
    first = name.split(".")[0]
    if not first.isidentifier():
        return False
    if "." not in name and hasattr(builtins, name):
        return True
    if first == "xnavlab":
        return False
    try:
        return importlib.util.find_spec(first) is not None
    except (ImportError, ValueError):
        return False


#: |x| written in text (an absolute value, a norm: '|S|', '|position error|'), not a table's bar
_ABS = re.compile(r"\|[^|\s](?:[^|\n]{0,40}?[^|\s])?\|")


def _short(text, n=50):
    text = " ".join(text.split())
    return text if len(text) <= n else text[: n - 3] + "..."


def _content(soup):
    return soup.find("article") or soup.find("main") or soup.body or soup


# --------------------------------------------------------------------------------------------
# tables


def _own_rows(table):
    return [tr for tr in table.find_all("tr") if tr.find_parent("table") is table]


def _row_grid(rows):
    """Each row as its list of cells laid on the grid (rowspans carried down)."""
    carry: dict[int, int] = {}  # column -> rows still covered by a rowspan from above
    grid = []
    for tr in rows:
        cells = [c for c in tr.find_all(["td", "th"]) if c.find_parent("tr") is tr]
        placed, col = [], 0
        pending = dict(carry)
        carry = {k: v - 1 for k, v in carry.items() if v > 1}
        for cell in cells:
            while pending.get(col):
                placed.append(None)
                col += 1
            span = _int_attr(cell, "colspan")
            down = _int_attr(cell, "rowspan")
            for k in range(span):
                placed.append(cell)
                if down > 1:
                    carry[col + k] = down - 1
            col += span
        while pending.get(col):
            placed.append(None)
            col += 1
        grid.append(placed)
    return grid


def _int_attr(cell, name):
    try:
        return max(1, int(cell.get(name, 1)))
    except (TypeError, ValueError):
        return 1


def _check_tables(content, page):
    out = []
    for t_index, table in enumerate(content.find_all("table"), start=1):
        rows = _own_rows(table)
        if not rows:
            continue
        grid = _row_grid(rows)
        in_head = [tr.find_parent("thead") is not None for tr in rows]
        last_head = max((i for i, h in enumerate(in_head) if h), default=0)
        width = len(grid[0])
        caption = table.find("caption")
        name = f"table {t_index}" + (f" ({_short(caption.get_text(), 30)})" if caption else "")
        for r, row in enumerate(grid[1:], start=2):
            if len(row) != width:
                text = _short(" | ".join(c.get_text(" ", strip=True) for c in row if c), 60)
                out.append(Problem(page, f"{name} row {r}: {len(row)} cells where its header row"
                                         f" has {width} ({text})"))
        header = grid[last_head]
        verdict_cols = [i for i, c in enumerate(header) if c is not None
                        and c.get_text(" ", strip=True).lower() in VERDICT_HEADERS]
        for r, row in enumerate(grid[last_head + 1:], start=last_head + 2):
            for i in verdict_cols:
                if i >= len(row) or row[i] is None:
                    continue
                text = " ".join(row[i].get_text(" ", strip=True).split())
                if text not in VERDICTS and text not in HEADLINES:
                    allowed = ", ".join(dict.fromkeys(VERDICTS + HEADLINES))
                    out.append(Problem(page, f"{name} row {r}: verdict {text!r} is not one of"
                                             f" {allowed}"))
    return out


# --------------------------------------------------------------------------------------------
# text


def _text_nodes(content):
    skip = (Comment, Declaration, Doctype, ProcessingInstruction)
    for node in content.find_all(string=True):
        if isinstance(node, skip) or not isinstance(node, NavigableString):
            continue
        if _in_code(node):
            continue
        yield node


def _check_text(content, page):
    out = []
    seen = set()

    def add(what):
        if what not in seen:
            seen.add(what)
            out.append(Problem(page, what))

    for node in _text_nodes(content):
        text = _MATH_SOURCE.sub(" ", str(node))
        if "|" in _ABS.sub(" ", text) and not _escaped(node):
            add(f"literal '|' in text: {_short(text)!r}")
        if "$" in text:
            add(f"literal '$' in text (math that did not render?): {_short(text)!r}")
        if "??" in text:
            add(f"'??' in text (an unresolved reference?): {_short(text)!r}")
        m = _RAW_ROLE.search(text)
        if m:
            add(f"raw role {m.group()} in text: {_short(text)!r}")
        m = _EQ_LABEL.search(text)
        if m:
            add(f"equation reference shows its label {m.group(1)!r}: {_short(text)!r}")
        if "[missing reference]" in text.lower():
            add(f"[missing reference]: {_short(text)!r}")
        if "glue key" in text.lower() and "not found" in text.lower():
            add(f"glue key not found: {_short(text)!r}")
    for xref in content.select(".xref"):
        if xref.find_parent("a") is not None or xref.name == "a":
            continue
        if "py" in _classes(xref) and _foreign_python_name(xref.get_text()):
            continue
        add(f"unresolved reference {_short(xref.get_text(), 40)!r}"
            f" ({' '.join(sorted(_classes(xref) - {'docutils', 'literal', 'notranslate'}))})")
    for pasted in content.select(_PASTED):
        if _UNFORMATTED.search(pasted.get_text()):
            add(f"glued value shown unformatted: {_short(pasted.get_text(), 40)!r} (glue a Python"
                " float, not a NumPy scalar)")
    return out


def _check_glue(content, page, source):
    """``{glue:text}`` and ``{eval}`` roles of the page's source against the texts on the page."""
    if source is None or not source.is_file():
        return []
    text = source.read_text(encoding="utf-8", errors="replace")
    if source.suffix == ".ipynb":
        import json

        try:
            nb = json.loads(text)
        except json.JSONDecodeError:
            return []
        text = "\n".join("".join(c.get("source", "")) for c in nb.get("cells", [])
                         if c.get("cell_type") == "markdown")
    out = []
    expected = len(_GLUE_TEXT.findall(text))
    shown = len(content.select(".pasted-text"))
    if shown < expected:
        out.append(Problem(page, f"{expected - shown} of {expected} {{glue:text}} roles rendered as"
                                 " nothing (glue key not found, or a value myst-nb could not"
                                 " format: glue a Python float)"))
    expected = len(_EVAL.findall(text))
    shown = len([s for s in content.select("span.output.text_plain")
                 if s.find_parent(class_="cell_output") is None])
    if shown < expected:
        out.append(Problem(page, f"{expected - shown} of {expected} {{eval}} roles rendered as"
                                 " nothing (not evaluated by tools/book_execute.py?)"))
    return out


def _check_leaks(content, page):
    """Template leaks in a chapter's prose and outputs (not in its code's input)."""
    if not _CHAPTER_PAGE.search(page):
        return []
    out, seen = [], set()
    for node in content.find_all(string=True):
        if not isinstance(node, NavigableString) or isinstance(node, Comment):
            continue
        if node.find_parent(class_="cell_input") or node.find_parent(["script", "style"]):
            continue
        if _in_code(node) and not node.find_parent(class_="cell_output"):
            continue
        m = _LEAK.search(_MATH_SOURCE.sub(" ", str(node)))
        if m and (m.group(), _short(str(node))) not in seen:
            seen.add((m.group(), _short(str(node))))
            out.append(Problem(page, f"template leak {m.group()!r}: {_short(str(node))!r}"))
    return out


def _check_visible_code(content, page):
    """Visible code cells hold the idea; ``glue(`` and bare ``assert`` belong out of sight."""
    if not _CHAPTER_PAGE.search(page):
        return []
    out = []
    for n, cell in enumerate(content.select(".cell_input"), start=1):
        m = _BOOKKEEPING.search(cell.get_text())
        if m:
            out.append(Problem(page, f"visible code cell {n} holds {m.group().strip()!r}: move the "
                                     "bookkeeping into a cell tagged remove-input or remove-cell"))
    return out


# --------------------------------------------------------------------------------------------
# images, outputs, exercises


def _check_images(content, page_path, page):
    out = []
    for img in content.find_all("img"):
        src = img.get("src", "")
        parts = urlsplit(src)
        if not src or parts.scheme in ("data", "http", "https") or parts.netloc:
            if not src:
                out.append(Problem(page, "<img> without src"))
            continue
        target = (page_path.parent / unquote(parts.path)).resolve()
        if not target.is_file():
            out.append(Problem(page, f"image file missing: {src}"))
    return out


def _is_empty(tag):
    if tag.get_text(strip=True):
        return False
    return not any(tag.find(name) for name in _VISIBLE)


def _check_outputs(content, page):
    out = []
    for n, cell_output in enumerate(content.select(".cell_output"), start=1):
        if _is_empty(cell_output):
            out.append(Problem(page, f"empty cell output (output area {n}): nothing rendered"))
            continue
        for output in cell_output.select(".output"):
            if _is_empty(output):
                kind = " ".join(sorted(_classes(output) - {"output", "docutils", "container"}))
                out.append(Problem(page, f"empty output ({kind or 'unknown kind'}) in output"
                                         f" area {n}"))
    return out


def _check_exercises(content, page):
    out = []
    exercises = {ex.get("id"): ex for ex in content.select("div.exercise")}
    solved = set()
    for sol in content.select("div.solution"):
        title = sol.find(class_="admonition-title")
        link = title.find("a", href=True) if title else None
        target = urlsplit(link["href"]).fragment if link else ""
        name = _short(title.get_text(" ", strip=True) if title else sol.get("id", "?"), 40)
        if not target:
            out.append(Problem(page, f"solution {sol.get('id')!r} names no exercise ({name})"))
        solved.add(target)
        if "dropdown" not in _classes(sol):
            out.append(Problem(page, f"{name}: solution not collapsed (add :class: dropdown)"))
        if not sol.select(".cell"):
            out.append(Problem(page, f"{name}: solution has no executed code cell"))
    for ex_id, ex in exercises.items():
        if ex_id not in solved:
            title = ex.find(class_="admonition-title")
            name = _short(title.get_text(" ", strip=True), 30) if title else ex_id
            out.append(Problem(page, f"{name} ({ex_id}): exercise without a solution"))
    for adm in content.select("div.admonition"):
        if _classes(adm) & {"solution", "exercise"}:
            continue
        title = adm.find(class_="admonition-title")
        if title and title.get_text(" ", strip=True).lower().startswith("solution"):
            out.append(Problem(page, "a prose 'Solution' admonition: make it an executed"
                                     " sphinx-exercise solution"))
    return out


# --------------------------------------------------------------------------------------------


def pages(html_dir: Path) -> list[Path]:
    """The content pages of a built book (sorted): every ``.html`` but the generated ones."""
    found = []
    for p in sorted(html_dir.rglob("*.html")):
        rel = p.relative_to(html_dir)
        if rel.parts[0] in SKIP_DIRS or rel.name in SKIP_PAGES:
            continue
        found.append(p)
    return found


def check_page(path: Path, html_dir: Path) -> list[Problem]:
    """Every problem of one page."""
    page = path.relative_to(html_dir).as_posix()
    soup = BeautifulSoup(path.read_text(encoding="utf-8", errors="replace"), "html.parser")
    content = _content(soup)
    source = None
    stem = path.relative_to(html_dir).with_suffix("")
    for suffix in (".ipynb", ".md"):
        candidate = html_dir / "_sources" / (stem.as_posix() + suffix)
        if candidate.is_file():
            source = candidate
            break
    return (_check_tables(content, page) + _check_text(content, page)
            + _check_glue(content, page, source) + _check_images(content, path, page)
            + _check_outputs(content, page) + _check_exercises(content, page)
            + _check_leaks(content, page) + _check_visible_code(content, page))


def _check_pages(found: list[Path], html_dir: Path, jobs: int) -> list[list[Problem]]:
    """:func:`check_page` of every page, in order, ``jobs`` pages at once (parsing is most of
    the time: 33 s for the whole book on one core, measured 2026-11-29)."""
    if jobs == 1 or len(found) < 2:
        return [check_page(path, html_dir) for path in found]
    with concurrent.futures.ProcessPoolExecutor(min(jobs, len(found))) as pool:
        return list(pool.map(check_page, found, itertools.repeat(html_dir)))


def main(argv: list[str] | None = None) -> int:
    """Command line: print the problems, return the exit status (0, 1 or 2)."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--html", type=Path, default=DEFAULT_HTML,
                        help="the built book's HTML directory (default: _build/html)")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                        help="pages read at once (default: the number of CPUs)")
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:
        return 2 if exc.code else 0
    if args.jobs < 1:
        print(f"check_book: --jobs must be at least 1, got {args.jobs}", file=sys.stderr)
        return 2
    html_dir = args.html.resolve()
    if not html_dir.is_dir():
        print(f"check_book: {args.html}: no such directory (build the book first)", file=sys.stderr)
        return 2
    found = pages(html_dir)
    if not found:
        print(f"check_book: {args.html}: no HTML page", file=sys.stderr)
        return 2
    problems = [p for page in _check_pages(found, html_dir, args.jobs) for p in page]
    for p in problems:
        print(p)
    if problems:
        n_pages = len({p.page for p in problems})
        print(f"check_book: {len(problems)} problem(s) on {n_pages} of {len(found)} page(s)",
              file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
