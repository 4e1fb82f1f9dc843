"""The test of the test: the JupyterLab checker fails on notebooks broken on purpose.

Each notebook is written at test time into the server's root and checked exactly as a chapter
is (``lab_driver.check_notebook``); each must be reported with the right problem. A widget
whose function raises only for the second value the slider reaches, a figure that never
changes and a cell that raises would all pass a test that only executes the notebook.
"""

import nbformat
import pytest

from .conftest import lab_driver

HEAD = """\
import numpy as np
from matplotlib.figure import Figure
from xnavlab.core.widgets import explore


def curve(a=1.0, kind="sin"):
    fig = Figure(figsize=(4, 2.5))
    x = np.linspace(0.0, 6.0, 200)
    fig.add_subplot().plot(x, (np.sin if kind == "sin" else np.cos)(a * x))
    return fig
"""

# the scrubber's two frames are a = 1 and a = 5 and the widget opens at a = 1: the checker's
# mouse click goes to a = 5 (fine), its key press one step back to a = 4, which raises
RAISES = HEAD + """

def fragile(a=1.0, kind="sin"):
    if a == 4.0:
        raise ValueError("a = 4 breaks this plot on purpose")
    return curve(a, kind)


explore(fragile, a=[1.0, 2.0, 3.0, 4.0, 5.0], kind=["sin", "cos"], max_frames=2)
"""

# the figure ignores the slider
STUCK = HEAD + """

def stuck(a=1.0):
    return curve(1.0)


explore(stuck, a=[1.0, 2.0, 3.0])
"""

# slow only at a = 2 (not a frame of the scrubber: frames a = 1 and 3, opens at a = 1): the
# checker's key press reaches it, after a quick click to a = 3
SLOW = HEAD + """
import time

import xnavlab.core.widgets

# every move computes: a position seen before would otherwise come from the widget's memo of
# drawn PNGs, and the budget's retry (the same change again) would time the memo
xnavlab.core.widgets.LIVE_MEMO_FRAMES = 0


def slow(a=1.0):
    if a == 2.0:
        time.sleep(6.0)
    return curve(a)


explore(slow, a=[1.0, 2.0, 3.0], max_frames=2)
"""

FAILS = HEAD + """
explore(curve, a=[1.0, 2.0, 3.0])
"""

# ahead=False: every move draws its frame, so the status line's "computing" is checked on each
# (with frames computed ahead a move onto a finished frame is a lookup and says nothing)
OK = HEAD + """
explore(curve, a=[1.0, 2.0, 3.0], kind=["sin", "cos"], ahead=False)
"""


def write(root, name, *cells):
    nb = nbformat.v4.new_notebook()
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                 "language": "python"}
    nb.cells = [nbformat.v4.new_code_cell(c) for c in cells]
    nbformat.write(nb, root / name)
    return name


def test_a_good_notebook_passes(lab, lab_server, lab_root):
    rep = lab_driver.check_notebook(lab, write(lab_root, "ok.ipynb", OK))
    assert not rep.problems, rep.problems
    assert [(r.how, r.before, r.after) for r in rep.redraws] == [
        ("mouse", "2", "3"), ("key Home", "3", "1"), ("menu ArrowDown Enter", "sin", "cos")]
    assert all(r.seconds is not None and r.error is None for r in rep.redraws)
    assert all(r.busy_set for r in rep.redraws)  # the status line said "computing"
    assert lab_server.kernels() == []  # the notebook's kernel was shut down


def test_fails_when_the_widget_raises_for_one_slider_value(lab, lab_root):
    rep = lab_driver.check_notebook(lab, write(lab_root, "raises.ipynb", RAISES))
    first, second = rep.redraws[:2]
    assert (first.before, first.after, first.error) == ("1", "5", None)  # the good value
    assert second.after == "4"
    # the widget shows one line, not a traceback, and the checker fails on it
    assert second.error == "error: ValueError: a = 4 breaks this plot on purpose"
    assert any("showed an error: error: ValueError: a = 4" in p for p in rep.problems), \
        rep.problems


def test_fails_when_the_figure_does_not_change(lab, lab_root):
    # 5 s of a settled page instead of the chapters' 15 (each move of a stuck figure waits it
    # out: 38 s of this test were those waits): a shorter wait can only report "did not
    # change" sooner, which is what this notebook must get
    rep = lab_driver.check_notebook(lab, write(lab_root, "stuck.ipynb", STUCK), settle_s=5.0)
    assert any("the figure did not change" in p for p in rep.problems), rep.problems


def test_a_speed_budget_when_one_is_set_and_the_computing_line(lab, lab_root):
    """By default redraw times are reported, not judged (a loaded machine is slow); with a
    budget set (``max_redraw_s``, a quiet machine) a redraw over it fails, after one retry.
    The budget (4 s) is far from the quick redraw and the slow one (6 s) on a loaded machine."""
    rep = lab_driver.check_notebook(lab, write(lab_root, "slow.ipynb", SLOW), max_redraw_s=4.0)
    quick, slow = rep.redraws[:2]
    assert (quick.after, quick.retry_seconds) == ("3", None)
    assert slow.after == "2" and slow.seconds > 5.0 and slow.retry_seconds > 5.0
    assert slow.busy_visible and not quick.busy_visible  # shown only after 0.3 s
    assert any("redraw took" in p for p in rep.problems), rep.problems


def write_prose(root, name, *cells):
    """A notebook of ``OK``'s widget and then ``cells``: ("code", source, metadata) or
    ("md", source)."""
    nb = nbformat.v4.new_notebook()
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                 "language": "python"}
    nb.cells = [nbformat.v4.new_code_cell("from xnavlab.core.prose import glue, glued\n\n"
                                          "glue('ch99_r_km', 4190.0)\n" + OK)]
    for kind, source, *meta in cells:
        new = nbformat.v4.new_code_cell if kind == "code" else nbformat.v4.new_markdown_cell
        nb.cells.append(new(source, metadata=meta[0] if meta else {}))
    nbformat.write(nb, root / name)
    return name


PROSE = [
    ("md", "# Prose\n\nA range of {eval}`glued[\"ch99_r_km:,.0f\"]` km, eq. {eq}`ch99-a`, "
           "{cite}`fan2016wavelet` and [chapter 7](07_wavelets.ipynb):\n\n"
           "$$\na = \\frac{b}{c}\n$$ (ch99-a)"),
    ("code", "import matplotlib.pyplot as plt\nplt.plot([0, 1]); plt.show()",
     {"mystnb": {"figure": {"caption": "A line.", "name": "fig-ch99-line"}}}),
    ("md", "As {numref}`fig-ch99-line` shows.\n\n```{admonition} Note\n"
           "In a box: {eval}`glued[\"ch99_r_km:.0f\"]` km.\n```"),
    ("md", "```{exercise}\n:label: ch99-ex1\n\nWhy {eval}`glued[\"ch99_r_km:.1f\"]`?\n```"),
    ("md", "```{solution-start} ch99-ex1\n:class: dropdown\n```"),
    ("code", "answer = 42"),
    ("md", "```{solution-end}\n```"),
]


def test_prose_that_reads_like_the_book_passes_and_shows_its_numbers(lab, lab_root, tmp_path):
    rep = lab_driver.check_notebook(lab, write_prose(lab_root, "prose.ipynb", *PROSE),
                                    screenshot=tmp_path / "prose.png")
    assert not rep.problems, rep.problems
    assert rep.expressions == 3 and rep.numbers == ["4,190", "4190", "4190.0"]
    # what JupyterLab cannot show as the book does is reported, not failed
    assert rep.lab_limits == ["1 citations", "1 figure references"]
    assert (tmp_path / "prose-prose.png").stat().st_size > 10_000


#: Prose that does not render in JupyterLab, each in its own markdown cell of one notebook, and
#: the problem the checker must report for it (one notebook, not one each: a notebook's check
#: costs a kernel, a run and the widget's moves, about 10 s of the JupyterLab test)
BAD_PROSE = [
    ("Raw {glue:text}`ch99_r_km:.1f` km", "unknown role {glue:text}`ch99_r_km:.1f`"),
    ("See {py:func}`~xnavlab.core.filters.ekf_update`", "unknown role {py:func}"),
    ('A typo: {eval}`glued["ch99_nope"]`', "expression failed: {eval}`glued[\"ch99_nope\"]`: "
                                           "KeyError"),
    ("As {numref}`fig-nowhere` shows", "unresolved reference 'fig-nowhere'"),
    ("```{glue:figure} ch99_fig\n```", "unknown directive {glue:figure}"),
]


def test_fails_on_prose_that_does_not_render(lab, lab_root):
    cells = [("md", markdown) for markdown, _ in BAD_PROSE]
    rep = lab_driver.check_notebook(lab, write_prose(lab_root, "bad_prose.ipynb", *cells))
    # each cell's own problem, at its own cell (cell 0 is the widget), and no other problem
    for i, (_, match) in enumerate(BAD_PROSE, 1):
        assert any(p.startswith(f"markdown cell {i}: ") and match in p for p in rep.problems), \
            (i, match, rep.problems)
    assert len(rep.problems) == len(BAD_PROSE), rep.problems
    assert rep.redraws, "the widget is still checked"


@pytest.mark.parametrize(
    ("cells", "match"),
    [
        ((FAILS, "1 / 0"), "raised ZeroDivisionError"),
        (("import xnavlab_no_such_module",), "raised ModuleNotFoundError"),
        (("print('no widget here')",), "no live explore widget"),
    ],
)
def test_fails_on_an_error_cell_or_a_missing_widget(lab, lab_root, cells, match):
    rep = lab_driver.check_notebook(lab, write(lab_root, "cell.ipynb", *cells))
    assert any(match in p for p in rep.problems), rep.problems
