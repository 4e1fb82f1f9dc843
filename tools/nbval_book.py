"""A pytest plugin: nbval's run of the chapters, kept for the book when ``make test`` asks.

``make test`` executes every chapter with nbval and then builds the book, which must execute
every chapter too. With ``XNAVLAB_NBVAL_BOOK=DIR`` set (``make test`` sets it), the root
``conftest.py`` loads this plugin: the chapters run under nbval exactly as
``tools/book_execute.py`` runs them for the book, and each passed chapter is kept in ``DIR``
(``book_execute.write_executed``); the book's build takes it from there
(``book_execute.py --executed DIR``) instead of executing it a second time (about 200 s of a
2-core machine's CI, measured 2026-11-29). Without the variable (``pytest book``,
``make notebooks``) the plugin is not loaded: nbval runs the chapters as a reader's kernel
does and nothing is kept.

What "as the book runs them" means here:

* the kernel starts with ``XNAVLAB_SCRUBBER_FRAMES=1`` and without ``MPLBACKEND`` (pytest's
  ``Agg``): each slider draws its scrubber frames and figures are inline PNGs, as in the book
  (:data:`xnavlab.core.widgets.FRAMES_ENV`);
* before each code cell, the ``{eval}`` expressions of the markdown cells before it are
  evaluated in the kernel (one silent request with ``user_expressions``), and all of them again
  after the last cell, with ``book_execute.ProseValues``'s checks: a page fails here as it
  would in ``book_execute``.

A chapter is kept only when every one of its cells passed. The live widget of
:func:`xnavlab.core.widgets.explore` is not built in such a kernel, so no output of a cell is
a widget's (nbval, unlike nbclient, does not tell a widget's output from the cell's); the
JupyterLab test (``make lab-test``) runs every chapter as a reader does, live widgets and all.
"""

import copy
import os
import time

import book_execute  # tools/book_execute.py, beside this file (on sys.path: see conftest.py)
import nbformat
import pytest
from nbval.plugin import IPyNbCell

from xnavlab.core.prose import eval_expressions
from xnavlab.core.widgets import FRAMES_ENV

#: The environment variable naming the directory where executed chapters are kept.
KEEP_ENV = "XNAVLAB_NBVAL_BOOK"
KEEP = os.environ.get(KEEP_ENV)

#: Seconds to wait for the kernel's reply to one request of expressions.
EVAL_TIMEOUT_S = 120.0


class _Page:
    """One chapter's run under nbval: its outputs and prose values so far."""

    def __init__(self, nb):
        self.nb = copy.deepcopy(nb)
        self.code = [i for i, cell in enumerate(nb.cells) if cell.cell_type == "code"]
        self.prose = book_execute.ProseValues()
        self.next = 0          # the first cell not handled yet
        self.failed = False
        self.start = time.perf_counter()


_PAGES = {}


@pytest.hookimpl(wrapper=True)
def pytest_runtest_setup(item):
    if not (isinstance(item, IPyNbCell) and item.parent.kernel is None):
        return (yield)
    # nbval starts the page's kernel in this setup: with the book's environment
    with pytest.MonkeyPatch.context() as env:
        env.setenv(FRAMES_ENV, "1")
        env.delenv("MPLBACKEND", raising=False)
        result = yield
    _PAGES[item.parent.nodeid] = _Page(item.parent.nb)
    return result


def _evaluate(item, expressions, where):
    """The kernel's values of ``expressions`` (``book_execute.eval_results``)."""
    keys = book_execute.eval_request(expressions, where)
    kernel = item.parent.kernel
    msg_id = kernel.kc.execute("", silent=True, store_history=False, user_expressions=keys)
    while True:  # nbval's own replies are all read: only this one can come
        msg = kernel.get_message(stream="shell", timeout=EVAL_TIMEOUT_S)
        if msg["parent_header"].get("msg_id") == msg_id:
            return book_execute.eval_results(keys, msg["content"], where)


def _prose_until(item, page, stop):
    """Evaluate the markdown cells from ``page.next`` up to cell ``stop`` (excluded)."""
    for index in range(page.next, stop):
        cell = page.nb.cells[index]
        if cell.cell_type == "markdown" and (exprs := eval_expressions(cell.source)):
            page.prose.shown(_evaluate(item, exprs, f"markdown cell {index}"), index)
    page.next = max(page.next, stop)


@pytest.hookimpl(wrapper=True)
def pytest_runtest_call(item):
    page = _PAGES.get(item.parent.nodeid) if isinstance(item, IPyNbCell) else None
    if page is None or page.failed:
        return (yield)
    index = page.code[item.cell_num]
    try:
        _prose_until(item, page, index)
        result = yield
    except pytest.skip.Exception:  # an nbval-skip cell: no outputs, as the book's skip-execution
        _done(item, page, index, [])
        raise
    except BaseException:
        page.failed = True
        raise
    _done(item, page, index, item.test_outputs or [])
    return result


def _done(item, page, index, outputs):
    """Keep a passed cell's outputs; after the last code cell, finish the page."""
    page.nb.cells[index].outputs = [nbformat.from_dict(o) for o in outputs]
    page.next = index + 1
    if item.cell_num == len(page.code) - 1:
        _finish(item, page)


def _finish(item, page):
    """After the last code cell: the prose after it, the final check, the page kept."""
    _prose_until(item, page, len(page.nb.cells))
    if page.prose.evaluated:
        page.prose.check_final(_evaluate(item, list(page.prose.evaluated),
                                         "after the last cell"))
    book_execute.write_executed(KEEP, item.parent.path, page.nb, page.prose.evaluated,
                                time.perf_counter() - page.start)
    del _PAGES[item.parent.nodeid]
