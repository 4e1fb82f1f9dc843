"""The notation page says one thing, and the chapters say the same.

* Its tables do not break: every row has as many cells as its header (a ``|`` inside a cell must
  be escaped, or written ``\\lvert``/``\\lVert`` in math).
* Every symbol its symbol tables define (the math of the first column, normalised) is written
  in at least one chapter (the markdown of ``book/*.ipynb``, or a ``book/*.md`` page).
* The time-transfer delay has one sign: chapter 2's. Every display equation of the book whose
  left-hand side is the delay ``\\Delta t`` (or ``c\\,\\Delta t``) gives its Roemer term, the
  pulsar direction ``n`` dotted with the position, the sign chapter 2 gives it; and prose that
  defines the delay as "the arrival time at A minus the arrival time at B" names the SSB and the
  spacecraft in the order that sign implies.

The files are read when the tests run (other pages change in parallel; nothing is cached).
"""

import json
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BOOK = ROOT / "book"
NOTATION = BOOK / "notation.md"
CHAPTER2 = BOOK / "02_time_transfer.ipynb"
CHAPTER10 = BOOK / "10_ephemeris_error.ipynb"
SKIP_PAGES = {"notation.md", "bibliography.md"}


# ------------------------------------------------------------------------------------------
# reading pages


def prose(path):
    """The markdown of a page: a notebook's markdown cells, or a ``.md`` page (whose code cells
    `_without_code` drops)."""
    text = path.read_text(encoding="utf-8")
    if path.suffix == ".ipynb":
        cells = json.loads(text)["cells"]
        return "\n\n".join("".join(c["source"]) for c in cells if c["cell_type"] == "markdown")
    return text


def chapter_pages():
    """Every page whose math can use a symbol: the chapters and the other ``book/*.md`` pages."""
    pages = sorted(BOOK.glob("[0-9][0-9]_*.ipynb"))
    pages += sorted(p for p in BOOK.glob("*.md") if p.name not in SKIP_PAGES)
    return pages


_FENCE = re.compile(r"^[ \t]*(`{3,}|~{3,}|:{3,})[ \t]*(\{([^}]*)\})?")
_CODE_DIRECTIVES = {"code-cell", "code-block", "code", "sourcecode", "literalinclude", "raw",
                    "eval-rst"}


def _without_code(text):
    """``text`` without code blocks, code spans and directive header lines (a directive's
    body, e.g. an exercise's, stays: it is prose)."""
    kept, stack = [], []  # stack of (fence char, fence length, body is code)
    for line in text.split("\n"):
        stripped = line.strip()
        if stack and stripped and set(stripped) == {stack[-1][0]} and len(stripped) >= stack[-1][1]:
            stack.pop()
            continue
        if stack and stack[-1][2]:
            continue
        m = _FENCE.match(line)
        if m:
            directive = m.group(3)
            stack.append((m.group(1)[0], len(m.group(1)),
                          directive is None and m.group(1)[0] != ":" or directive in _CODE_DIRECTIVES))
            continue
        if re.match(r"^[ \t]*:[\w-]+:", line) and stack:  # a directive's option line
            continue
        kept.append(line)
    return re.sub(r"(?<!`)(`+)(?!`).+?(?<!`)\1(?!`)", "", "\n".join(kept))


def math_spans(text, display_only=False):
    """The math of a markdown text: ``$$...$$`` blocks, then (unless ``display_only``) ``$...$``."""
    text = _without_code(text).replace(r"\$", "")
    display = re.findall(r"\$\$(.*?)\$\$", text, flags=re.S)
    if display_only:
        return display
    rest = re.sub(r"\$\$.*?\$\$", " ", text, flags=re.S)
    return display + re.findall(r"\$([^$\n]+(?:\n[^$\n]+)*?)\$", rest)


# ------------------------------------------------------------------------------------------
# normalised LaTeX tokens


_DROP = {r"\,", r"\;", r"\:", r"\!", r"\ ", r"\quad", r"\qquad", r"\left", r"\right", r"\big",
         r"\Big", r"\bigl", r"\bigr", r"\Bigl", r"\Bigr", r"\displaystyle", r"\textstyle", "~"}
_SAME = {r"\bm": r"\boldsymbol", r"\lvert": "|", r"\rvert": "|", r"\vert": "|", r"\lVert": r"\|",
         r"\rVert": r"\|", r"\Vert": r"\|", r"\top": "T", r"\intercal": "T", r"\dfrac": r"\frac",
         r"\tfrac": r"\frac", r"\to": r"\rightarrow", r"\le": r"\leq", r"\ge": r"\geq"}
_TEXT = {r"\mathrm", r"\text", r"\textrm", r"\operatorname", r"\mathsf", r"\rm"}
_TOKEN = re.compile(r"\\[A-Za-z]+|\\.|[A-Za-z0-9]|[^\sA-Za-z0-9]")


def tokens(latex, braces=False):
    """Normalised tokens of a LaTeX math source.

    Spacing and sizing commands go, synonyms become one spelling (``\\bm`` is ``\\boldsymbol``,
    ``\\lvert`` is ``|``, ``\\top`` is ``T``), a text command and its argument become one token
    (``\\mathrm{SSB}``), and braces go unless ``braces`` (so ``\\mathbf{r}_{M}`` and
    ``\\mathbf r_M`` are the same symbol). Fonts stay: ``\\mathbf r`` is not ``r``.

    >>> tokens(r"\\hat{\\mathbf{x}}_f") == tokens(r"\\hat{\\mathbf x}_{f}")
    True
    >>> tokens(r"\\sigma_\\mathrm{TOA}")
    ['\\\\sigma', '_', '\\\\mathrm{TOA}']
    """
    raw = _TOKEN.findall(latex)
    out = []
    i = 0
    while i < len(raw):
        tok = _SAME.get(raw[i], raw[i])
        i += 1
        if tok in _DROP:
            continue
        if tok in _TEXT:
            if i < len(raw) and raw[i] == "{":  # the argument up to the matching brace
                depth, j = 0, i
                while j < len(raw):
                    depth += {"{": 1, "}": -1}.get(raw[j], 0)
                    if depth == 0:
                        break
                    j += 1
                arg, i = "".join(raw[i + 1 : j]), j + 1
            else:
                arg, i = (raw[i] if i < len(raw) else ""), i + 1
            out.append("T" if tok == r"\mathsf" and arg == "T" else f"{tok}{{{arg}}}")
            continue
        if tok in "{}" and not braces:
            continue
        out.append(tok)
    return out


def contains(hay, needle):
    """Whether the token list ``needle`` occurs contiguously in ``hay``."""
    n = len(needle)
    return n > 0 and any(hay[k : k + n] == needle for k in range(len(hay) - n + 1))


def split_top(toks, separators):
    """Split braced tokens at the separators that stand outside every group.

    Returns a list of ``(separator before the part or None, part)``.
    """
    parts, depth, sep, cur = [], 0, None, []
    for tok in toks:
        if tok in "{([":
            depth += 1
        elif tok in "})]":
            depth -= 1
        if depth == 0 and tok in separators:
            parts.append((sep, cur))
            sep, cur = tok, []
        else:
            cur.append(tok)
    parts.append((sep, cur))
    return parts


# ------------------------------------------------------------------------------------------
# the notation page's tables


def _cells(row):
    row = row.strip()
    inner = row[1:-1] if row.endswith("|") and not row.endswith(r"\|") else row[1:]
    return [c.strip() for c in re.split(r"(?<!\\)\|", inner)]


def tables(text):
    """Every markdown table of a page: a list of rows, each a list of cell texts."""
    out, block = [], []
    for line in _without_code(text).splitlines() + [""]:
        if line.lstrip().startswith("|"):
            block.append(line)
        elif block:
            out.append([_cells(r) for r in block if not re.fullmatch(r"\s*\|?[\s:|-]+\|?\s*", r)])
            block = []
    return out


def notation_symbols():
    """``(source, tokens)`` of every symbol in the first column of the notation page's symbol
    tables (those whose header's first cell is "symbol"); a cell may hold several ``$...$``, and
    one ``$...$`` several symbols separated by top-level commas."""
    symbols = []
    for table in tables(NOTATION.read_text(encoding="utf-8")):
        if table[0][0].lower() != "symbol":
            continue
        for row in table[1:]:
            for span in math_spans(row[0]):
                for _, part in split_top(tokens(span, braces=True), {","}):
                    toks = [t for t in part if t not in "{}"]
                    if toks:
                        symbols.append((span.strip(), toks))
    return symbols


def test_notation_tables_do_not_break():
    broken = []
    for table in tables(NOTATION.read_text(encoding="utf-8")):
        width = len(table[0])
        broken += [" | ".join(row) for row in table[1:] if len(row) != width]
    assert not broken, f"rows whose cell count differs from the header (an unescaped |?): {broken}"


def test_notation_page_has_symbol_tables():
    assert len(notation_symbols()) >= 20


def test_every_notation_symbol_is_used_in_a_chapter():
    used = [tokens(m) for page in chapter_pages() for m in math_spans(prose(page))]
    unused = sorted({src for src, toks in notation_symbols()
                     if not any(contains(hay, toks) for hay in used)})
    assert not unused, (f"symbols of book/notation.md that no chapter writes (fix the page or the "
                        f"chapter): {unused}")


# ------------------------------------------------------------------------------------------
# the sign of the time-transfer delay


_DELAY = tokens(r"\Delta t")
_WRAPPERS = {r"\mathbf", r"\boldsymbol", r"\hat", "{", "(", "[", r"\frac"}


def _roemer_sign(equation):
    """Sign of the Roemer term of a delay equation, or None when ``equation`` is not one.

    A delay equation: its left-hand side (before the first top-level ``=``) holds ``\\Delta t``;
    its Roemer term: the first top-level additive term after that ``=`` that holds the pulsar
    direction ``n`` dotted with something (``\\cdot`` or a transpose), and neither the distance
    ``D`` of the parallax term nor the logarithm or ``\\mu`` of the Shapiro term.
    """
    toks = tokens(equation, braces=True)
    sides = split_top(toks, {"=", r"\approx"})
    if len(sides) < 2:
        return None
    lhs = sides[0][1]
    if not contains([t for t in lhs if t not in "{}"], _DELAY):
        return None
    sign = -1 if "-" in lhs[: lhs.index(r"\Delta")] else 1
    for _, rhs in sides[1:]:  # "= t_SSB - t_SC = n.R/c + ...": the first side with the term
        for op, term in split_top(rhs, {"+", "-"}):
            if "n" not in term or not ({r"\cdot", "T"} & set(term)):
                continue
            if {"D", r"\ln", r"\mu"} & set(term):
                continue
            k = term.index("n")
            while k > 0 and term[k - 1] in _WRAPPERS:
                k -= 1
            inner = -1 if k > 0 and term[k - 1] == "-" else 1
            return sign * inner * (-1 if op == "-" else 1)
    return None


def delay_signs(path):
    """Signs of the Roemer terms of the delay equations of one page."""
    signs = [_roemer_sign(eq) for eq in math_spans(prose(path), display_only=True)]
    return [s for s in signs if s is not None]


def chapter2_sign():
    signs = delay_signs(CHAPTER2)
    assert signs, "chapter 2 has no delay equation with a Roemer term the test can read"
    assert len(set(signs)) == 1, f"chapter 2 gives the Roemer term both signs: {signs}"
    return signs[0]


@pytest.mark.parametrize("equation, sign", [
    (r"\Delta t = \frac{\mathbf n\cdot\mathbf R}{c} + \frac{(\mathbf n\cdot\mathbf R)^2}{2cD_0}", 1),
    (r"c\,\Delta t_i = n_i^T (r + r_E) + v_i", 1),
    (r"\Delta t = -\frac{\mathbf n\cdot\mathbf R}{c} + \ldots", -1),
    (r"\Delta t = \frac{-\mathbf n\cdot\mathbf R}{c}", -1),
    (r"c\,\Delta t_i = v_i - n_i^{\mathsf T}(r + r_E)", -1),
    (r"\Delta t = t_\mathrm{SSB} - t_\mathrm{SC} = \underbrace{\frac{\mathbf n\cdot\mathbf R}{c}}"
     r"_{\text{Roemer}} + \frac{2\mu_\odot}{c^3}\ln\left|\mathbf n\cdot\mathbf b\right|", 1),
    (r"\Phi(t) = \Phi(t_0) + f\,(t - t_0)", None),
    (r"\boldsymbol\Phi \approx e^{\mathbf F\Delta t}", None),
])
def test_roemer_sign_reader(equation, sign):
    assert _roemer_sign(equation) == sign


def test_chapter2_has_one_delay_sign():
    assert chapter2_sign() in (1, -1)


@pytest.mark.parametrize("path", [CHAPTER10, NOTATION], ids=lambda p: p.name)
def test_delay_equation_has_chapter2_sign(path):
    signs = delay_signs(path)
    assert signs, f"{path.name}: no delay equation found (the delay on the left, n . r on the right)"
    reference = chapter2_sign()
    assert set(signs) == {reference}, (
        f"{path.name}: the Roemer term of the delay has sign {signs}, chapter 2's is {reference}")


def test_every_delay_equation_has_chapter2_sign():
    reference = chapter2_sign()
    wrong = {p.name: s for p in chapter_pages() + [NOTATION]
             if (s := delay_signs(p)) and set(s) != {reference}}
    assert not wrong, f"pages whose delay equation has the other sign than chapter 2's: {wrong}"


_PLACE = r"(SSB|barycent\w*|spacecraft)"
_DIFFERENCE = re.compile(_PLACE + r"[^.;:$]{0,80}?\bminus\b[^.;:$]{0,80}?" + _PLACE, re.I)


def definitions_in(text):
    """``(first place, second place, text)`` of each "... at A minus ... at B" of a markdown text
    in a sentence about arrival times or the delay (A, B: the SSB or the spacecraft)."""
    text = re.sub(r"\$[^$]*\$", " ", _without_code(text))
    out = []
    for sentence in re.split(r"(?<=[.!?])\s+", text):
        if not re.search(r"arriv|delay|TOA|time transfer", sentence, re.I):
            continue
        for m in _DIFFERENCE.finditer(sentence):
            first, second = ("spacecraft" if g.lower() == "spacecraft" else "ssb" for g in m.groups())
            if first != second:
                out.append((first, second, " ".join(m.group(0).split())))
    return out


def delay_definitions(path):
    """`definitions_in` the prose of one page."""
    return definitions_in(prose(path))


def test_delay_definition_reader():
    page = ("The measurement is the pulse's time of arrival at the spacecraft minus its time of "
            "arrival at the SSB. The delay is the arrival time at the SSB minus the arrival time "
            "at the spacecraft. Unrelated: the spacecraft minus the Mars centre, arrival.")
    assert [d[:2] for d in definitions_in(page)] == [("spacecraft", "ssb"), ("ssb", "spacecraft")]


def test_delay_is_defined_in_words_with_chapter2_order():
    # chapter 2's sign: a positive Roemer term n.R/c means the pulse reaches the spacecraft
    # (displaced towards the pulsar) first, so the delay is t_SSB - t_SC: "SSB minus spacecraft"
    expected = ("ssb", "spacecraft") if chapter2_sign() > 0 else ("spacecraft", "ssb")
    wrong = {p.name: [d[2] for d in found]
             for p in chapter_pages() + [NOTATION]
             if (found := [d for d in delay_definitions(p) if d[:2] != expected])}
    assert not wrong, (f"prose that defines the delay in the other order than chapter 2's sign "
                       f"({expected[0]} minus {expected[1]}): {wrong}")


def test_notation_defines_the_delay_in_words():
    assert delay_definitions(NOTATION), "the notation page should say what the delay is a difference of"
