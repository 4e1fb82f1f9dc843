"""Every chapter, opened in JupyterLab in headless Chromium and used as a reader uses it.

Run by ``make lab-test`` (after ``make test``'s static browser test). For each
``book/NN_*.ipynb`` the test opens the chapter in JupyterLab, runs all cells ("Run All
Cells"), waits for the kernel to go idle and fails on any error output; it reads every
rendered markdown cell and fails on raw role text, a role or directive jupyterlab-myst does not
understand, an ``{eval}`` that failed or was not evaluated and an unresolved reference (a
``{cite}`` key and a reference to a code cell's figure are reported as JupyterLab's limits,
``lab_driver.LAB_LIMITS``), and saves a screenshot of the prose's first numbers
(``NN_x-prose.png``); then it finds the
chapter's first live ``xnavlab.core.widgets.explore`` widget, moves its main slider to two
other values (a mouse click on the track, a key press) and a dropdown where there is one, and
fails unless the figure changed each time (it waits on the new image and the status line, up
to ``lab_driver.REDRAW_TIMEOUT_S``, never on a fixed sleep). The redraw time (from the input
event to the new figure painted) is measured and reported, not judged: a loaded 2-core
machine is slow, and speed is the benchmarks' business (``XNAVLAB_LAB_MAX_REDRAW_S`` sets a
budget for a quiet machine). A failure names the chapter, the control and what the page
showed. A screenshot of the widget after the moves goes to
``_build/lab-screenshots/`` (override with ``XNAVLAB_LAB_SCREENSHOTS``); the run and redraw
times are printed at the end and written to ``redraw-times.txt`` there.
"""

import pytest

from .conftest import CHAPTERS, SHOTS, lab_driver


def test_every_chapter_is_here():
    assert len(CHAPTERS) >= 12, CHAPTERS


@pytest.mark.parametrize("chapter", CHAPTERS)
def test_chapter(chapter, lab, lab_server, lab_report):
    rep = lab_driver.check_notebook(lab, chapter, SHOTS / chapter.replace(".ipynb", ".png"))
    lab_report(rep)
    problems = "\n".join(f"  - {p}" for p in rep.problems)
    assert not rep.problems, f"{rep.summary()}\n{problems}"
    moves = sum(r.control == rep.redraws[0].control for r in rep.redraws)
    assert moves == 2, (f"{chapter}: the main slider {rep.redraws[0].control!r} was moved "
                        f"{moves} times, not 2\n{rep.summary()}")
    assert lab_server.kernels() == [], f"{chapter}: the chapter's kernel is still running"
