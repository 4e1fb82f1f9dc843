"""List the numbers typed into the book's prose (they should be glued from a computation).

A number in a chapter's markdown that comes from a computation must be glued
(``glue("ch05_fused_rms_m", rms)`` in the code, ``{eval}`glued["ch05_fused_rms_m:.1f"]``` in the
prose: :mod:`xnavlab.core.prose`; a chapter not yet converted by ``tools/eval_roles.py`` still
has ``{glue:text}`ch05_fused_rms_m:.1f```), never typed: a typed number goes stale when the code
changes. This tool reads the markdown cells of ``book/NN_*.ipynb`` and the prose of the
``book/*.md`` pages (not ``bibliography.md``, not the API pages, not code cells or outputs) and
prints every number that is neither glued nor allow-listed, one line per hit::

    book/05_ekf_ukf.ipynb:cell 8: 7.9 ... s direction is worth 7.9 km per epoch. The

``cell N`` is ``nb["cells"][N]`` (counted from 0, code cells included); in a ``.md`` page the
line number is given instead.

Not a hit:

* anything inside math (``$...$``, ``$$...$$``, ``\\(...\\)``, ``\\begin{..}...\\end{..}``, the
  ``{math}`` role), code spans and code fences (and ``{code-cell}``/``{math}``/... directives),
  MyST roles with their targets (``{eval}``, ``{eq}``, ``{ref}``, ``{numref}``, ``{doc}``,
  ``{cite}``, ``{glue:text}``...), directive header and option lines (`````{exercise}``, ``:label: ...``),
  link targets and URLs, HTML tags and comments, substitutions, front matter, list markers;
* digits inside identifiers and names (``B1937+21``, ``J0030+0451``, ``db3``, ``3D``, ``DE421``,
  ``x1``, ``ch05-ex1``, ``SO(3)``, a DOI);
* structural numbers after chapter, section, eq., eqs., equation, fig., figure, table, exercise,
  part, step, level, appendix (their plurals and lists: "chapters 1-3", "sections 0 and 3");
* four-digit years 1900-2099 and ISO dates (``2000-01-01 12:00``), when no unit follows;
* integers 0-10 standing alone (counts and definitions), i.e. with no unit, ``%`` or ``x`` after.

Everything else (decimals, percentages, numbers with units, integers above 10) is a hit unless
``tools/typed_numbers_allow.txt`` lists it: one entry a line,
``<book path or *> | <number exactly as printed here> | <reason>`` (``#`` starts a comment);
an entry allows that number everywhere on that page. An entry without a reason is refused.
The number ``all`` exempts one whole page (for a page whose every number is a source paper's
own statement, such as the Sources page; never ``*``).

Usage (from the repository root)::

    .venv/bin/python tools/typed_numbers.py                      # every page
    .venv/bin/python tools/typed_numbers.py book/05_ekf_ukf.ipynb  # some pages
    .venv/bin/python tools/typed_numbers.py --allow other_allow.txt PATHS...

Exit status: 0 no hit, 1 some hit, 2 a bad argument or a bad allow-list entry.

Examples
--------
>>> [h.number for h in scan_text("The error is 28.8 m after 3 days, $x = 4.5$, `y = 12`.")]
['28.8', '3']
>>> [h.number for h in scan_text("See chapter 12, B1937+21 and {glue:text}`ch05_x:.1f` in 2016.")]
[]
>>> [h.number for h in scan_text('The error is {eval}`glued["ch05_rms_m:.1f"]` m after 12 days.')]
['12']
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BOOK = ROOT / "book"
ALLOW = ROOT / "tools" / "typed_numbers_allow.txt"
#: ``book/*.md`` pages that are not prose of the book
SKIP_PAGES = {"bibliography.md"}

#: directives whose body is code or math (masked); any other directive's body is prose
CODE_DIRECTIVES = {
    "code-cell", "code-block", "code", "sourcecode", "math", "literalinclude", "raw",
    "glue:math", "bibliography", "eval-rst", "eval-md", "mermaid", "graphviz", "csv-table",
}

_UNIT_WORDS = [
    # time
    "s", "sec", "secs", "ms", "µs", "μs", "ns", "min", "mins", "h", "hr", "hrs", "d",
    "second", "seconds", "minute", "minutes", "hour", "hours", "day", "days", "week", "weeks",
    "month", "months", "yr", "yrs", "year", "years", "millisecond", "milliseconds",
    "microsecond", "microseconds", "nanosecond", "nanoseconds",
    # length, speed, acceleration
    "m", "km", "cm", "mm", "µm", "μm", "nm", "au", "AU", "pc", "kpc", "ly", "m/s", "km/s",
    "mm/s", "cm/s", "m/s2", "m/s²", "metre", "metres", "meter", "meters", "kilometre",
    "kilometres", "kilometer", "kilometers", "millimetre", "millimetres", "centimetre",
    "centimetres", "km/h",
    # angles
    "deg", "degree", "degrees", "°", "arcsec", "arcmin", "mas", "µas", "μas", "rad", "mrad",
    "µrad", "μrad", "radian", "radians", "arcsecond", "arcseconds", "arcminute", "arcminutes",
    "milliarcsecond", "milliarcseconds", "deg/h", "°/h", "rad/s",
    # frequency, other
    "Hz", "kHz", "MHz", "GHz", "mHz", "dB", "ppm", "ppb", "kg", "keV", "MeV", "eV", "W",
    "kW", "ph/s", "counts/s", "cm2", "cm²", "m2", "m²", "km2", "km²", "percent", "%", "‰",
]
#: multipliers count as a unit only when attached: "2x", "3×" (but "a 3 x 3 matrix")
_ATTACHED_ONLY = ["x", "×"]
# longest first, so "km/s" wins over "km"; a unit ends at a non-letter
_UNIT = "|".join(re.escape(u) for u in sorted(set(_UNIT_WORDS), key=len, reverse=True))
_UNIT_AFTER_SPACE = re.compile(
    r"[ \t\u00a0\u202f\u2009]?-?(?:" + _UNIT + r")(?:\^-?[0-9]|[²³])?(?![A-Za-z0-9µμ])"
)
# attached directly (no space): "5km", "20%", "2x", "500-s", "30-day"
_UNIT_ATTACHED = re.compile(
    r"-?(?:" + _UNIT + "|" + "|".join(_ATTACHED_ONLY) + r")(?:\^-?[0-9]|[²³])?(?![A-Za-z0-9µμ])"
)
_NOT_A_UNIT_AFTER = re.compile(r"\s*(?:degrees?\s+of\s+freedom|sigma\b|σ)", re.I)
_ORDINAL = re.compile(r"(?:st|nd|rd|th)(?![A-Za-z])")

_STRUCT_WORDS = (
    r"chapters?|ch\.|sections?|sec\.|secs\.|§|eqs?\.|equations?|figs?\.|figures?|tables?|tab\."
    r"|exercises?|ex\.|parts?|steps?|levels?|appendix|appendices|pages?|pp?\.|items?|lines?"
    r"|columns?|rows?|cells?|refs?\.|references?"
)
_STRUCT_BEFORE = re.compile(
    r"(?:^|[^\w])(?:" + _STRUCT_WORDS + r")\s*"
    r"(?:\(?[0-9][0-9.]*[a-z]?\)?\s*(?:,|and|or|to|-|–|—|&|\s)\s*)*\(?\s*$",
    re.I,
)

_NUMBER = re.compile(
    r"(?<![0-9.,])(?:[0-9]{1,3}(?:[ \u00a0\u202f\u2009][0-9]{3})+(?![0-9])"
    r"|[0-9]+(?:[.,][0-9]+)*(?:[eE][-+−]?[0-9]+)?)"
)
_IDENT = re.compile(
    r"[A-Za-z_µμ][0-9#]|[0-9#][A-Za-z_]|[A-Za-z][(:/+][0-9#]|[0-9#][:/+_][A-Za-z]"
)


@dataclass(frozen=True)
class Hit:
    """One typed number: its text as written, its offset in the scanned text, its context."""

    number: str
    offset: int
    context: str


@dataclass(frozen=True)
class Allow:
    """One allow-list entry: a page (or ``*``) and a number exactly as printed."""

    page: str
    number: str
    reason: str
    line: int


class BadAllowList(ValueError):
    """The allow-list has an entry the tool refuses (no reason, wrong shape)."""


# --------------------------------------------------------------------------------------------
# masking: every character that is not prose becomes a space (newlines kept, offsets kept)


def _blank(chars: list[str], start: int, end: int) -> None:
    for i in range(start, end):
        if chars[i] != "\n":
            chars[i] = " "


def _mask_regex(text: str, pattern: re.Pattern[str], group: int = 0) -> str:
    chars = list(text)
    for m in pattern.finditer(text):
        _blank(chars, m.start(group), m.end(group))
    return "".join(chars)


_FENCE_OPEN = re.compile(r"^[ \t]*(`{3,}|~{3,}|:{3,})[ \t]*(\{([^}\s]*)\})?(.*)$")
_OPTION = re.compile(r"^[ \t]*:[\w-]+:")
_LABEL_LINE = re.compile(r"^[ \t]*\([\w:.-]+\)=[ \t]*$")
_CELL_BREAK = re.compile(r"^\+\+\+")


def _mask_blocks(text: str) -> str:
    """Mask front matter, code fences, directive headers and options, label lines."""
    lines = text.split("\n")
    out: list[str] = []
    stack: list[tuple[str, int, bool]] = []  # (fence char, length, body is code)
    options = False  # just after a directive header: option lines follow
    yaml_block = False
    i = 0
    if lines and lines[0].strip() == "---":  # front matter
        for j in range(1, len(lines)):
            if lines[j].strip() == "---":
                out.extend(" " * len(x) for x in lines[: j + 1])
                i = j + 1
                break
    while i < len(lines):
        line = lines[i]
        i += 1
        blank = " " * len(line)
        in_code = bool(stack) and stack[-1][2]
        stripped = line.strip()
        if stack and stripped and set(stripped) == {stack[-1][0]} and len(stripped) >= stack[-1][1]:
            stack.pop()
            out.append(blank)
            options = yaml_block = False
            continue
        if in_code:
            out.append(blank)
            continue
        if options:
            if yaml_block:
                yaml_block = stripped != "---"
                out.append(blank)
                continue
            if stripped == "---":
                yaml_block = True
                out.append(blank)
                continue
            if _OPTION.match(line):
                out.append(blank)
                continue
            options = False
        m = _FENCE_OPEN.match(line)
        if m:
            fence, directive, name = m.group(1), m.group(2), (m.group(3) or "")
            if fence[0] == "`" and "`" in (m.group(4) or ""):
                out.append(line)  # an inline code span, not a fence
                continue
            code = (directive is None and fence[0] != ":") or name in CODE_DIRECTIVES
            stack.append((fence[0], len(fence), code))
            options = not code
            out.append(blank)
            continue
        if _LABEL_LINE.match(line) or _CELL_BREAK.match(line):
            out.append(blank)
            continue
        out.append(line)
    return "\n".join(out)


_INLINE_PATTERNS = [
    re.compile(r"<!--.*?-->", re.S),  # HTML comments
    re.compile(r"\{[\w:.-]+\}(`+)(?:(?!\n[ \t]*\n).)+?\1", re.S),  # roles with their targets
    re.compile(r"(?<!`)(`+)(?!`)(?:(?!\n[ \t]*\n).)+?(?<!`)\1(?!`)", re.S),  # code spans
    re.compile(r"\\\$"),  # an escaped dollar is not math
    re.compile(r"\$\$.*?\$\$(?:[ \t]*\([\w:.-]+\))?", re.S),  # display math and its label
    re.compile(r"\$(?:(?!\n[ \t]*\n)[^$])+?\$", re.S),  # inline math
    re.compile(r"\\\(.*?\\\)|\\\[.*?\\\]", re.S),
    re.compile(r"\\begin\{([A-Za-z*]+)\}.*?\\end\{\1\}", re.S),
    re.compile(r"^[ \t]*\[[^\]\n]+\]:[ \t]*\S.*$", re.M),  # link reference definitions
    re.compile(r"\[\^[^\]\n]+\]"),  # footnote references
    re.compile(r"\]\([^)\s]*(?:[ \t]+\"[^\"]*\")?\)"),  # link targets
    re.compile(r"<(?:https?|ftp|mailto):[^>\s]+>"),  # autolinks
    re.compile(r"(?:https?|ftp)://\S+"),  # bare URLs
    re.compile(r"</?[A-Za-z][^>\n]*>|<![^>]*>"),  # HTML tags
    re.compile(r"\{\{.*?\}\}", re.S),  # substitutions
    re.compile(r"\b(?:19|20)[0-9]{2}-[01][0-9]-[0-3][0-9](?:[T ][0-9]{2}:[0-9]{2}(?::[0-9]{2}"
               r"(?:\.[0-9]+)?)?)?"),  # ISO dates and times
    re.compile(r"^[ \t]*(?:[-*+][ \t]+)?[0-9]+[.)](?=[ \t])", re.M),  # ordered-list markers
    re.compile(r"^[ \t]*#+[ \t]+[0-9]+(?:\.[0-9]+)*\.?(?=[ \t])", re.M),  # "# 12. Title"
    re.compile(r"(?<![\w.])\([0-9]+\)(?![\w])"),  # "(6)": an equation number
    re.compile(r"(?<![\w.])\[[0-9]+(?:[-–,][ \t]*[0-9]+)*\]"),  # "[21]": a reference number
    re.compile(r"\b[0-9]+\([0-9]+\)(?::[ \t]*[0-9]+(?:[-–][0-9]+)?)?"),  # "38(1): 26-33"
    re.compile(r"[*]"),  # emphasis markers
]


def mask(text: str) -> str:
    """Return ``text`` with everything that is not prose replaced by spaces.

    Parameters
    ----------
    text : str
        Markdown (MyST) source of one cell or one page.

    Returns
    -------
    str
        The same length as ``text``, with newlines in place, so an offset into it is an
        offset into ``text``.
    """
    masked = _mask_blocks(text)
    for pattern in _INLINE_PATTERNS:
        masked = _mask_regex(masked, pattern)
    return masked


# --------------------------------------------------------------------------------------------
# classifying a number


def _word_bounds(text: str, start: int, end: int) -> tuple[int, int]:
    a, b = start, end
    while a > 0 and not text[a - 1].isspace():
        a -= 1
    while b < len(text) and not text[b].isspace():
        b += 1
    return a, b


def _unit_after(text: str, end: int) -> tuple[bool, int]:
    """Whether a unit follows the number ending at ``end`` (and where the unit ends)."""
    if _NOT_A_UNIT_AFTER.match(text, end):
        return False, end
    m = _UNIT_ATTACHED.match(text, end) or _UNIT_AFTER_SPACE.match(text, end)
    if m:
        return True, m.end()
    return False, end


def _is_hit(text: str, start: int, end: int) -> bool:
    token = text[start:end]
    has_unit, unit_end = _unit_after(text, end)
    after = unit_end
    if not has_unit:
        m = _ORDINAL.match(text, end)
        if m:
            return False  # an ordinal is a position ("95th percentile", "the 3rd day")
    a, b = _word_bounds(text, start, max(after, end))
    word = text[a:start] + "#" + text[after:b] if after <= b else text[a:start] + "#"
    if _IDENT.search(word):
        return False  # digits inside a name or identifier
    if text[a:start].endswith(("-", "+")) and re.search(r"[A-Za-z]", text[a:start]):
        return False  # second part of a name: J0030+0451, ch05-ex1
    if has_unit:
        return True
    plain = token.replace(",", "")
    if _STRUCT_BEFORE.search(text[max(0, start - 80):start]):
        return False
    if plain.isdigit():
        value = int(plain)
        if len(plain) == 4 and 1900 <= value <= 2099:
            return False
        if value <= 10:
            return False
    return True


def scan_text(text: str) -> list[Hit]:
    """Every typed number of one markdown cell or page.

    Parameters
    ----------
    text : str
        MyST markdown source.

    Returns
    -------
    list of Hit
        In order of appearance; ``offset`` indexes ``text``.
    """
    masked = mask(text)
    hits = []
    for m in _NUMBER.finditer(masked):
        if _is_hit(masked, m.start(), m.end()):
            lo, hi = max(0, m.start() - 20), min(len(text), m.end() + 20)
            context = " ".join(text[lo:hi].split())
            number = re.sub(r"[\u00a0\u202f\u2009]", " ", m.group())
            hits.append(Hit(number, m.start(), context))
    return hits


# --------------------------------------------------------------------------------------------
# pages, the allow-list, the command line


def default_paths() -> list[Path]:
    """The chapters ``book/NN_*.ipynb`` and the prose pages ``book/*.md`` (sorted)."""
    chapters = sorted(BOOK.glob("[0-9][0-9]_*.ipynb"))
    pages = sorted(p for p in BOOK.glob("*.md") if p.name not in SKIP_PAGES)
    return chapters + pages


def display_path(path: Path) -> str:
    """The path as printed and as written in the allow-list (relative to the repository)."""
    path = path.resolve()
    try:
        return path.relative_to(ROOT).as_posix()
    except ValueError:
        return path.as_posix()


def scan_file(path: Path) -> list[tuple[str, Hit]]:
    """Hits of one page as ``(where, hit)``: ``where`` is ``cell N`` or ``line N``."""
    out = []
    if path.suffix == ".ipynb":
        nb = json.loads(path.read_text(encoding="utf-8"))
        for i, cell in enumerate(nb.get("cells", [])):
            if cell.get("cell_type") != "markdown":
                continue
            src = cell.get("source", "")
            src = "".join(src) if isinstance(src, list) else src
            out.extend((f"cell {i}", h) for h in scan_text(src))
    else:
        text = path.read_text(encoding="utf-8")
        for h in scan_text(text):
            out.append((f"line {text.count(chr(10), 0, h.offset) + 1}", h))
    return out


def load_allow(path: Path) -> list[Allow]:
    """Read the allow-list; raise `BadAllowList` on an entry without a reason or a bad line."""
    entries = []
    if not path.exists():
        return entries
    for n, raw in enumerate(path.read_text(encoding="utf-8").splitlines(), start=1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        parts = [p.strip() for p in line.split("|", 2)]
        if len(parts) != 3 or not parts[0] or not parts[1]:
            raise BadAllowList(f"{path}:{n}: expected '<book path or *> | <number> | <reason>',"
                               f" got {raw!r}")
        if not parts[2]:
            raise BadAllowList(f"{path}:{n}: the entry for {parts[1]!r} on {parts[0]} has no"
                               " reason (a reason is mandatory)")
        if parts[1] == "all" and parts[0] == "*":
            raise BadAllowList(f"{path}:{n}: 'all' exempts one page, not every page")
        if parts[1] != "all" and not _NUMBER.fullmatch(parts[1]):
            raise BadAllowList(f"{path}:{n}: {parts[1]!r} is not a number as this tool prints it")
        entries.append(Allow(parts[0], parts[1], parts[2], n))
    return entries


def main(argv: list[str] | None = None) -> int:
    """Command line: print the hits, return the exit status (0, 1 or 2)."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("paths", nargs="*", help="book pages (.ipynb or .md); default: all")
    parser.add_argument("--allow", type=Path, default=ALLOW, help="allow-list file")
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:
        return 2 if exc.code else 0
    try:
        allow = load_allow(args.allow)
    except BadAllowList as exc:
        print(f"typed_numbers: {exc}", file=sys.stderr)
        return 2
    paths = [Path(p) for p in args.paths] or default_paths()
    for p in paths:
        if not p.is_file() or p.suffix not in (".ipynb", ".md"):
            print(f"typed_numbers: {p}: not a book page (.ipynb or .md file)", file=sys.stderr)
            return 2
    allowed = {(a.page, a.number) for a in allow}
    used: set[tuple[str, str]] = set()
    n_hits = 0
    for p in paths:
        shown = display_path(p)
        try:
            hits = scan_file(p)
        except (json.JSONDecodeError, UnicodeDecodeError) as exc:
            print(f"typed_numbers: {p}: cannot read ({exc})", file=sys.stderr)
            return 2
        for where, hit in hits:
            key = next((k for k in ((shown, hit.number), ("*", hit.number), (shown, "all"))
                        if k in allowed), None)
            if key is not None:
                used.add(key)
                continue
            n_hits += 1
            print(f"{shown}:{where}: {hit.number} ... {hit.context}")
    scanned = {display_path(p) for p in paths}
    for a in allow:
        if a.page in scanned and (a.page, a.number) not in used:
            print(f"typed_numbers: note: {args.allow.name}:{a.line}: {a.number!r} is not typed on"
                  f" {a.page} any more (entry can go)", file=sys.stderr)
    if n_hits:
        print(f"typed_numbers: {n_hits} typed number(s) in {len(paths)} page(s): glue them"
              f" (xnavlab.core.prose.glue + {{eval}}`glued[\"name:spec\"]`) or allow-list a"
              f" paper constant in"
              f" {display_path(args.allow)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
