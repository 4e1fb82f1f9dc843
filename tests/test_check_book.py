"""tools/check_book.py: small planted pages, one per kind of problem, are each rejected; a clean
page (tables, math with bars, code, a glued number, an exercise with a collapsed executed
solution, a figure) is accepted."""

import importlib.util
import json
import sys
from pathlib import Path

import pytest

TOOL = Path(__file__).resolve().parents[1] / "tools" / "check_book.py"


@pytest.fixture(scope="module")
def cb():
    spec = importlib.util.spec_from_file_location("check_book", TOOL)
    mod = importlib.util.module_from_spec(spec)
    sys.modules["check_book"] = mod  # dataclasses look their module up there
    try:
        spec.loader.exec_module(mod)
        yield mod
    finally:
        sys.modules.pop("check_book", None)


def _page(body):
    return ("<!DOCTYPE html><html><head><title>t | book</title></head><body>"
            "<nav>a | nav bar</nav><article class=\"bd-article\"><section>"
            f"{body}</section></article></body></html>")


TABLE = ("<table class=\"table\"><thead><tr><th>quantity</th><th>paper</th><th>verdict</th></tr>"
         "</thead><tbody>{rows}</tbody></table>")
CELL = ("<div class=\"cell docutils container\"><div class=\"cell_input docutils container\">"
        "<pre>x = 1</pre></div><div class=\"cell_output docutils container\">{out}</div></div>")
EXERCISE = ("<div class=\"exercise admonition\" id=\"ch05-ex1\"><p class=\"admonition-title\">"
            "<span class=\"caption-number\">Exercise 1 </span></p><p>How much?</p></div>")
SOLUTION = ("<div class=\"solution {cls} admonition\" id=\"ch05-solution-1\">"
            "<p class=\"admonition-title\">Solution to<a class=\"reference internal\" "
            "href=\"#ch05-ex1\"> Exercise 1</a></p><section>{body}</section></div>")
EXECUTED = CELL.format(out="<div class=\"output stream\"><pre>3.5</pre></div>")

CLEAN = _page(
    "<h1>Chapter<a class=\"headerlink\" href=\"#c\">#</a></h1>"
    "<div class=\"math notranslate nohighlight\" id=\"equation-ch5-x\">\\[\\|x\\| = |y|\\]</div>"
    "<p>See <a class=\"reference internal\" href=\"#equation-ch5-x\">(1)</a> and "
    "<span class=\"math notranslate nohighlight\">\\(|a|\\)</span>, code <code>a | b</code>; "
    "the value is <span class=\"pasted-text\">26.4</span> m.</p>"
    "<pre>shell | pipe $ HOME</pre>"
    + TABLE.format(rows="<tr><td>x</td><td>1</td><td>REPRODUCED</td></tr>"
                        "<tr><td>y</td><td>2</td><td><strong>NOT REPRODUCED</strong></td></tr>"
                        "<tr><td>z</td><td>2</td><td>CHECK</td></tr>"
                        "<tr><td colspan=\"2\">both</td><td>PARTLY REPRODUCED</td></tr>")
    + "<table><tr><th rowspan=\"2\">a</th><th>b</th></tr><tr><td>c</td></tr></table>"
    + CELL.format(out="<img src=\"fig.png\" alt=\"a figure\">")
    + CELL.format(out="<div class=\"output text_html\">"
                      "<p>html output with MathJax source \\(|x|\\)</p></div>")
    + EXERCISE + SOLUTION.format(cls="dropdown", body=EXECUTED)
    + "<p>Unlinked on purpose: <code class=\"xref py py-class docutils literal\">numpy.ndarray</code>"
    " and <code class=\"xref py py-exc docutils literal\">ValueError</code>.</p>"
    + CELL.format(out="<div class=\"output text_html\"><p class=\"xnav-result\">id: UNDECIDED</p>"
                      "<table class=\"table xnav-table\"><tr><th>quantity</th><th>verdict</th>"
                      "</tr><tr><td>max |x| (m)</td><td>UNDECIDED</td></tr></table>"
                      "<p class=\"xnav-note\">|r_1| stays below its threshold</p></div>")
)

BROKEN = {
    "cells": TABLE.format(rows="<tr><td>x</td><td>1</td><td>CHECK</td><td>extra</td></tr>"),
    "verdict": TABLE.format(rows="<tr><td>x</td><td>1</td><td>PASS</td></tr>"),
    "verdict 'fail'": "<table><tr><th>id</th><th>pass</th></tr><tr><td>a</td><td>fail</td></tr></table>",
    "literal '|'": "<p>| quantity | paper | broke</p>",
    "literal '$'": "<p>the error $\\sigma is large</p>",
    "'??'": "<p>see figure ??</p>",
    "raw role": "<p>see {eq}`ch9-wavelet` above</p>",
    "shows its label": "<p>as in eq. (ch9-wavelet) above</p>",
    "unresolved reference": "<p>see <code class=\"xref eq docutils literal\">ch9-x</code></p>",
    "unresolved reference 'MarsRun.save_npz()'": ("<p><code class=\"xref py py-meth docutils\">"
                                                  "MarsRun.save_npz()</code></p>"),
    "unresolved reference 'xnavlab.mars.nothing'": ("<p><code class=\"xref py py-mod docutils\">"
                                                    "xnavlab.mars.nothing</code></p>"),
    "shown unformatted": "<p>error <span class=\"pasted-text\">np.float64(2.0)</span> m</p>",
    "[missing reference]": "<p>Solution to [missing reference]</p>",
    "glue key not found": "<p>glue key not found: ch05_x</p>",
    "{glue:text}": "<p>the error is {glue:text}`ch05_x:.1f` m</p>",
    "image file missing": "<p><img src=\"_images/nothere.png\" alt=\"x\"></p>",
    "empty cell output": CELL.format(out="  "),
    "empty output": CELL.format(out="<div class=\"output text_plain\"><pre>1</pre></div>"
                                    "<div class=\"output text_html\"></div>"),
    "exercise without a solution": EXERCISE,
    "not collapsed": EXERCISE + SOLUTION.format(cls="", body=EXECUTED),
    "no executed code cell": EXERCISE + SOLUTION.format(cls="dropdown", body="<p>prose</p>"),
    "prose 'Solution' admonition": ("<div class=\"dropdown admonition\"><p class=\"admonition-"
                                    "title\">Solution</p><p>words</p></div>"),
}


def _book(tmp_path, pages):
    html = tmp_path / "html"
    (html / "book").mkdir(parents=True)
    (html / "book" / "fig.png").write_bytes(b"\x89PNG")
    (html / "_static").mkdir()
    (html / "_static" / "junk.html").write_text("<p>| ?? $ not content</p>")
    (html / "genindex.html").write_text(_page("<p>| generated</p>"))
    for name, text in pages.items():
        (html / "book" / name).write_text(text)
    return html


def test_clean_page_is_accepted(cb, tmp_path, capsys):
    html = _book(tmp_path, {"clean.html": CLEAN})
    assert cb.main(["--html", str(html)]) == 0
    assert capsys.readouterr().out == ""


@pytest.mark.parametrize("kind", sorted(BROKEN))
def test_each_broken_page_is_rejected(cb, tmp_path, capsys, kind):
    html = _book(tmp_path, {"clean.html": CLEAN, "broken.html": _page(BROKEN[kind])})
    assert cb.main(["--html", str(html)]) == 1
    lines = capsys.readouterr().out.strip().splitlines()
    assert lines and all(line.startswith("book/broken.html: ") for line in lines), lines
    assert any(kind in line for line in lines), lines


CHAPTER_BROKEN = {
    "template leak 'nan'": CELL.format(out="<div class=\"output stream\"><pre>mean a = nan m/s</pre></div>"),
    "template leak 'inf'": "<p>detected after inf s</p>",
    "template leak 'm(s)'": "<p>the alarm(s) of the detector</p>",
    "holds 'glue('": CELL.replace("x = 1", "glue(\"ch05_x\", 1.0, display=False)").format(out="1"),
    "holds 'assert'": CELL.replace("x = 1", "y = 2\nassert y > 1").format(out="1"),
}


@pytest.mark.parametrize("kind", sorted(CHAPTER_BROKEN))
def test_a_chapter_page_with_a_leak_or_bookkeeping_in_sight_is_rejected(cb, tmp_path, capsys, kind):
    html = _book(tmp_path, {"05_x.html": _page(CHAPTER_BROKEN[kind])})
    assert cb.main(["--html", str(html)]) == 1
    assert kind in capsys.readouterr().out


def test_leaks_and_bookkeeping_are_looked_for_on_chapters_only(cb, tmp_path, capsys):
    html = _book(tmp_path, {"api.html": _page("".join(CHAPTER_BROKEN.values()))})
    assert cb.main(["--html", str(html)]) == 0
    clean = _page("<p>nanoseconds, infinite, a (1) list and inf-norm words</p>"
                  + CELL.replace("x = 1", "inside = nan_count(x)  # the glue_ideas").format(out="1"))
    html = _book(tmp_path / "b", {"05_x.html": clean})
    assert cb.main(["--html", str(html)]) == 0, capsys.readouterr().out


def test_glue_that_rendered_as_nothing(cb, tmp_path, capsys):
    nb = {"cells": [{"cell_type": "markdown", "metadata": {}, "source":
                     "Error {glue:text}`ch05_a:.1f` m and {glue:text}`ch05_b:.1f` m."}],
          "metadata": {}, "nbformat": 4, "nbformat_minor": 5}
    html = _book(tmp_path, {"05_x.html": _page("<p>Error <span class=\"pasted-text\">1.5</span>"
                                               " m and  m.</p>")})
    (html / "_sources" / "book").mkdir(parents=True)
    (html / "_sources" / "book" / "05_x.ipynb").write_text(json.dumps(nb))
    assert cb.main(["--html", str(html)]) == 1
    assert "1 of 2 {glue:text} roles rendered as nothing" in capsys.readouterr().out


def test_eval_that_rendered_as_nothing_or_raw(cb, tmp_path, capsys):
    # myst-nb renders an {eval} role as <span class="output text_plain">; a code cell's own
    # text output (class output text_plain too, inside cell_output) does not count for it
    nb = {"cells": [{"cell_type": "markdown", "metadata": {}, "source":
                     'Error {eval}`glued["ch05_a:.1f"]` m and {eval}`glued["ch05_b:.1f"]` m.'}],
          "metadata": {}, "nbformat": 4, "nbformat_minor": 5}
    html = _book(tmp_path, {"05_x.html": _page(
        '<p>Error <span class="output text_plain">1.5</span> m and  m.</p>'
        '<div class="cell_output"><span class="output text_plain">2.5</span></div>'
        '<p>raw {eval}`glued["ch05_c"]`</p>')})
    (html / "_sources" / "book").mkdir(parents=True)
    (html / "_sources" / "book" / "05_x.ipynb").write_text(json.dumps(nb))
    assert cb.main(["--html", str(html)]) == 1
    out = capsys.readouterr().out
    assert "1 of 2 {eval} roles rendered as nothing" in out and "raw role {eval}" in out


def test_verdict_vocabulary_is_the_registrys(cb):
    from xnavlab.reproduce import HEADLINES, VERDICTS

    assert cb.VERDICTS == VERDICTS and cb.HEADLINES == HEADLINES


def test_bad_arguments_exit_2(cb, tmp_path, capsys):
    assert cb.main(["--html", str(tmp_path / "missing")]) == 2
    assert cb.main(["--html", str(tmp_path)]) == 2  # no page
    assert cb.main(["--bogus"]) == 2
    capsys.readouterr()


def test_an_absolute_value_in_text_is_not_a_broken_table(cb):
    # '|S|', '|position error|' and '|dr_E|' are notation; '| a | b |' is a table that did not render
    assert not cb._ABS.sub(" ", "The largest |S| in the cone |b| <= 3a").count("|")
    assert not cb._ABS.sub(" ", "max |position error|, faults; |dr_E|").count("|")
    assert "|" in cb._ABS.sub(" ", "| a | b |")


def test_pages_read_at_once_give_the_problems_of_pages_read_one_by_one(cb, tmp_path, capsys):
    html = _book(tmp_path, {"clean.html": CLEAN,
                            **{f"broken-{i}.html": _page(BROKEN[k])
                               for i, k in enumerate(sorted(BROKEN)[:4])}})
    outs = []
    for jobs in ("1", "2"):
        assert cb.main(["--html", str(html), "--jobs", jobs]) == 1
        outs.append(capsys.readouterr().out)
    assert outs[0] == outs[1] and outs[0].count("book/broken-") >= 4
    assert cb.main(["--html", str(html), "--jobs", "0"]) == 2
    assert "--jobs must be at least 1, got 0" in capsys.readouterr().err
