"""Execute the book's notebooks into myst-nb's execution cache, several at a time.

``make book`` runs ``jupyter-book build`` in myst-nb's ``cache`` mode. Left alone, the build
executes the chapters one after another: on a two-core machine one core waits while the
other runs a chapter. This script runs first and executes every page of ``_toc.yml`` that is
a notebook (``.ipynb``, or MyST Markdown with notebook top-matter) and is not in the cache
yet, ``--jobs`` at a time, exactly as myst-nb would (the same reader, the same
``jupyter_cache`` executor, the page's directory as working directory, the ``execute:``
timeout of ``_config.yml`` or the page's own ``mystnb.execution_timeout``, errors not
allowed) and stores each executed notebook in the cache, where the build then finds it
("Using cached notebook") instead of executing it again. Nothing is executed twice and
nothing is skipped: a page whose code cells match the cache is not run, every other is.

The kernels run with ``XNAVLAB_SCRUBBER_FRAMES=1`` (:data:`xnavlab.core.widgets.FRAMES_ENV`):
a page executed for the HTML book draws its sliders' scrubber frames, which a reader's kernel
does not.

A markdown cell's ``{eval}`` roles (``{eval}`glued["ch07_sigma_m:g"]```: the chapters' numbers,
:mod:`xnavlab.core.prose`) are evaluated in the page's kernel at that cell's place, between the
code cells before and after it, as JupyterLab does when a reader runs the cells in order (one
``execute_request`` with the expressions as ``user_expressions``). The results are stored with
the executed page, in its cache record's data (:data:`xnavlab.core.prose.BOOK_CACHE_KEY`), where
``book/_ext/xnav_eval.py`` gives them to myst-nb's ``{eval}`` role. A page fails on an expression
that the book does not evaluate (:data:`xnavlab.core.prose.EVAL_NAME`), that raises, or whose
value changes after the prose showed it (every expression is evaluated again after the last
cell: JupyterLab's "Run All Cells" may evaluate the prose late). A page that is in the cache
but lacks the value of one of its expressions (its prose changed, not its code) is executed
again.

Each page's line names its slowest cell (nbclient's timing), so a page that takes long says
where. A page that fails stops the script with its traceback and exit code 1 (the build would stop
on it too, later). ``tools/book_cache.py`` must run before it, so that a cache made with an
older package is dropped first.

Pages executed by ``make test``'s nbval run (``tools/nbval_book.py``, the same execution: scrubber
frames drawn, the ``{eval}`` values evaluated in place by :class:`ProseValues`) are taken from
``--executed DIR`` (:func:`import_executed`) instead of being executed a second time.

Usage: ``python tools/book_execute.py [--jobs N] [--executed DIR]`` from the repository root.
"""

import argparse
import concurrent.futures
import contextlib
import json
import os
import re
import sys
import time
import traceback
from datetime import datetime
from pathlib import Path

import nbformat
import yaml
from jupyter_cache import get_cache
from jupyter_cache.base import CacheBundleIn
from jupyter_cache.executors.utils import ExecutionResult
from jupyter_cache.utils import Timer
from myst_nb.core.read import (
    is_myst_markdown_notebook,
    read_myst_markdown_notebook,
    standard_nb_read,
)
from nbclient import NotebookClient
from nbclient.exceptions import CellExecutionError, CellTimeoutError
from nbclient.util import ensure_async

from xnavlab.core.prose import BOOK_CACHE_KEY, EVAL_NAME, eval_expressions
from xnavlab.core.widgets import FRAMES_ENV

ROOT = Path(__file__).resolve().parents[1]
CACHE = ROOT / "_build" / ".jupyter_cache"
#: Each page's last execution time here (seconds), for the order of the next run.
TIMES = ROOT / "_build" / ".book-execute-times.json"


@contextlib.contextmanager
def open_cache(path=None):
    """myst-nb's execution cache at ``path`` (default :data:`CACHE`), its database closed on exit.

    ``jupyter_cache`` opens its database (a SQLAlchemy engine, a pool of sqlite connections) on
    first use and never closes it: left to the garbage collector, each pooled connection is a
    ``ResourceWarning: unclosed database`` on Python 3.13, an error under the tests'
    ``filterwarnings = error``. Disposing of the engine closes them.
    """
    cache = get_cache(str(path or CACHE))
    try:
        yield cache
    finally:
        cache.db.dispose()


def toc_files(toc):
    """Every ``file:`` of a ``_toc.yml`` tree, in reading order."""
    if isinstance(toc, dict):
        found = [toc["file"]] if "file" in toc else []
        for key in ("root",):
            if key in toc:
                found.append(toc[key])
        for value in toc.values():
            if isinstance(value, (list, dict)):
                found += toc_files(value)
        return found
    if isinstance(toc, list):
        return [f for item in toc for f in toc_files(item)]
    return []


def read_page(path):
    """The page as myst-nb reads it, or None when it is not a notebook."""
    text = path.read_text(encoding="utf-8")
    if path.suffix == ".ipynb":
        return standard_nb_read(text)
    if is_myst_markdown_notebook(text):
        return read_myst_markdown_notebook(text, add_source_map=True, path=str(path))
    return None


def notebook_pages(root=None):
    """Paths of the pages of ``_toc.yml`` that are notebooks."""
    root = root or ROOT
    toc = yaml.safe_load((root / "_toc.yml").read_text(encoding="utf-8"))
    pages = []
    for name in dict.fromkeys(toc_files(toc)):
        for suffix in (".ipynb", ".md"):
            path = root / f"{name}{suffix}"
            if path.exists() and read_page(path) is not None:
                pages.append(path)
                break
    return pages


def default_timeout(root=None):
    """The ``execute: timeout`` of ``_config.yml`` (seconds per cell)."""
    root = root or ROOT
    config = yaml.safe_load((root / "_config.yml").read_text(encoding="utf-8"))
    return int(config.get("execute", {}).get("timeout", 30))


def longest_first(pages):
    """The pages, slowest first by their last run here (so two jobs end together), else
    Markdown notebooks (the dashboard) first, then in reading order."""
    try:
        last = json.loads(TIMES.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        last = {}
    return sorted(pages, key=lambda p: (-float(last.get(p.name, 0.0)), p.suffix != ".md"))


def _stamp(value):
    """An nbclient timing stamp (ISO 8601 text or datetime) as seconds since the epoch."""
    if isinstance(value, str):
        value = datetime.fromisoformat(value.replace("Z", "+00:00"))
    return value.timestamp()


def cell_times(nb, remove=False):
    """Each executed code cell's time, from the timing nbclient records (``record_timing``).

    Returns a list of dicts, in page order: ``index`` (of the cell in ``nb.cells``),
    ``first_line`` (its first line of code, at most 60 characters), ``start`` and ``stop``
    (seconds since the epoch: ``iopub.execute_input`` to ``shell.execute_reply``) and
    ``seconds``. ``remove=True`` also removes the timing (``metadata.execution``) from every
    cell, so that a page stored afterwards holds what myst-nb's own execution would store.
    """
    times = []
    for index, cell in enumerate(nb.cells):
        meta = cell.get("metadata", {})
        timing = (meta.pop("execution", None) if remove else meta.get("execution")) or {}
        if cell.cell_type != "code" or "iopub.execute_input" not in timing:
            continue
        start = _stamp(timing["iopub.execute_input"])
        stop = _stamp(timing.get("shell.execute_reply", timing["iopub.execute_input"]))
        first = next((ln for ln in cell.source.splitlines()
                      if ln.strip() and not ln.startswith(("#", "%"))), "")
        times.append({"index": index, "first_line": first[:60], "start": start, "stop": stop,
                      "seconds": stop - start})
    return times


def slowest_cell(nb):
    """The code cell that took longest, from nbclient's timing: (index, seconds, first line).

    The timing is removed from every cell (:func:`cell_times` with ``remove=True``).
    ``(None, 0.0, "")`` when no cell has a timing.
    """
    best = (None, 0.0, "")
    for t in cell_times(nb, remove=True):
        if t["seconds"] >= best[1]:
            best = (t["index"], t["seconds"], t["first_line"][:50])
    return best


def page_expressions(nb):
    """Every ``{eval}`` expression of the page's markdown cells, in order, each once."""
    return list(dict.fromkeys(e for cell in nb.cells if cell.cell_type == "markdown"
                              for e in eval_expressions(cell.source)))


def _eval_error(where, expr, why):
    """A failed ``{eval}`` as nbclient reports a failed cell (the page fails the same way)."""
    msg = f"{where}: {{eval}}`{expr}` {why}"
    return CellExecutionError(msg, "EvalError", msg)


def eval_request(expressions, where):
    """The ``user_expressions`` of one request for ``expressions``: key -> expression.

    Raises (as a failed cell) on an expression the book does not evaluate
    (:data:`xnavlab.core.prose.EVAL_NAME`).
    """
    for expr in expressions:
        if not re.match(EVAL_NAME, expr):
            raise _eval_error(where, expr, "is not an entry of the glued table: the book "
                              'evaluates only glued["name"] and glued["name:spec"] '
                              "(xnavlab.core.prose)")
    return {str(i): expr for i, expr in enumerate(expressions)}


def eval_results(keys, content, where):
    """expression -> result (``{"data": ..., "metadata": ...}``) from the kernel's reply
    ``content`` to the request :func:`eval_request` made; raises (as a failed cell) on a reply
    that is not ``ok`` or an expression that raised."""
    if content.get("status") != "ok":
        raise _eval_error(where, next(iter(keys.values())), f"was not evaluated: {content!r:.300}")
    results = {}
    for key, expr in keys.items():
        res = content.get("user_expressions", {}).get(key, {})
        if res.get("status") != "ok":
            raise _eval_error(where, expr, f"raised {res.get('ename')}: {res.get('evalue')}")
        results[expr] = {"data": res.get("data", {}), "metadata": res.get("metadata", {})}
    return results


class ProseValues:
    """The ``{eval}`` values one page shows, each kept at the first markdown cell showing it.

    ``evaluated`` maps each expression to its result, the value :data:`BOOK_CACHE_KEY` keeps
    with the executed page. Used by :class:`EvalNotebookClient` and by ``tools/nbval_book.py``
    (``make test``'s nbval run of the chapters, which stores them for the book).
    """

    def __init__(self):
        self.evaluated = {}
        self._shown_at = {}

    def shown(self, results, cell_index):
        """Record ``results`` shown by markdown cell ``cell_index``; raises where an
        expression shown before had another value (a name glued twice)."""
        for expr, res in results.items():
            if expr in self.evaluated and self.evaluated[expr] != res:
                raise _eval_error(f"markdown cell {cell_index}", expr, (
                    f"shows {res['data'].get('text/plain')!r} here but "
                    f"{self.evaluated[expr]['data'].get('text/plain')!r} in cell "
                    f"{self._shown_at[expr]}: glue each name once"))
            self.evaluated.setdefault(expr, res)
            self._shown_at.setdefault(expr, cell_index)

    def check_final(self, final):
        """Raise where a value after the last cell (``final``) differs from the one shown:
        JupyterLab's "Run All Cells" may evaluate the prose late."""
        for expr, res in final.items():
            if res != self.evaluated[expr]:
                raise _eval_error(f"markdown cell {self._shown_at[expr]}", expr, (
                    f"shows {self.evaluated[expr]['data'].get('text/plain')!r}, but the "
                    f"value is {res['data'].get('text/plain')!r} after the last cell: a "
                    "reader's JupyterLab may show either; glue each name once"))


class EvalNotebookClient(NotebookClient):
    """nbclient's client, also evaluating each markdown cell's ``{eval}`` expressions in place.

    ``evaluated`` maps each expression to its result (``{"data": ..., "metadata": ...}``, the
    ``user_expressions`` reply of the kernel), the value at the first cell that shows it.
    """

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.prose = ProseValues()

    @property
    def evaluated(self):
        return self.prose.evaluated

    async def _evaluate(self, expressions, where):
        """The kernel's ``user_expressions`` reply for ``expressions``: expression -> result."""
        keys = eval_request(expressions, where)
        msg_id = await ensure_async(self.kc.execute(
            "", silent=True, store_history=False, user_expressions=keys))
        reply = await self.async_wait_for_reply(msg_id)
        return eval_results(keys, (reply or {}).get("content", {}), where)

    async def async_execute_cell(self, cell, cell_index, execution_count=None,
                                 store_history=True):
        if cell.cell_type == "markdown" and (exprs := eval_expressions(cell.source)):
            self.prose.shown(await self._evaluate(exprs, f"markdown cell {cell_index}"),
                             cell_index)
        cell = await super().async_execute_cell(cell, cell_index, execution_count, store_history)
        if cell_index == len(self.nb.cells) - 1 and self.evaluated:
            self.prose.check_final(await self._evaluate(list(self.evaluated),
                                                        "after the last cell"))
        return cell


def execute_notebook(nb, cwd, timeout, allow_errors=False, record_timing=True):
    """Execute ``nb`` in place, as jupyter_cache's ``single_nb_execution`` does, and evaluate
    its ``{eval}`` expressions (:class:`EvalNotebookClient`).

    Returns (``jupyter_cache``'s ``ExecutionResult``, the evaluated expressions).
    """
    if "execution" in nb.metadata:  # jupyter_cache's meta_override
        timeout = nb.metadata.execution.get("timeout", timeout)
        allow_errors = nb.metadata.execution.get("allow_errors", allow_errors)
    client = EvalNotebookClient(nb, timeout=timeout, allow_errors=allow_errors,
                                record_timing=record_timing,
                                resources={"metadata": {"path": cwd}})
    error = exc_string = None
    timer = Timer()
    with timer:
        try:
            client.execute()
        except (CellExecutionError, CellTimeoutError) as err:
            error = err
            exc_string = "".join(traceback.format_exc())
    return ExecutionResult(nb, cwd, timer.last_split, error, exc_string), client.evaluated


def execute(path, timeout):
    """Execute one page in its directory.

    Returns (path, notebook JSON or None, seconds, error, slowest cell, evaluated
    expressions): the slowest cell as :func:`slowest_cell` gives it, so that a page that takes
    long says where.
    """
    # (a worker process of its own) the page is executed for the HTML book: its kernel's
    # sliders draw the scrubber's frames
    os.environ[FRAMES_ENV] = "1"
    nb = read_page(path)
    timeout = int(nb.metadata.get("mystnb", {}).get("execution_timeout", timeout))
    result, evaluated = execute_notebook(nb, str(path.parent), timeout)
    slowest = slowest_cell(nb)
    if result.err is not None:
        return path, None, result.time, result.exc_string, slowest, {}
    return path, nbformat.writes(nb), result.time, None, slowest, evaluated


def store_page(cache, path, nb, seconds, evaluated):
    """Store the executed page ``nb`` of ``path`` in the execution cache, with its time and
    its ``{eval}`` values (:data:`BOOK_CACHE_KEY`), where the build finds it."""
    cache.cache_notebook_bundle(
        CacheBundleIn(nb, str(path), data={"execution_seconds": seconds,
                                           BOOK_CACHE_KEY: evaluated}),
        check_validity=False, overwrite=True)


def code_sources(nb):
    """The page's code cells' sources, in order: what decides whether an execution is its."""
    return [cell.source for cell in nb.cells if cell.cell_type == "code"]


def write_executed(directory, page, nb, evaluated, seconds):
    """Keep a page executed elsewhere for :func:`import_executed`: ``directory/<stem>.json``.

    ``make test``'s nbval run of the chapters (``tools/nbval_book.py``) executes each chapter
    as the book does (scrubber frames drawn, ``{eval}`` values evaluated in place by
    :class:`ProseValues`) and keeps it here, so that the book's build does not execute it a
    second time. ``page`` is the page's path; ``nb`` the executed notebook.
    """
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    record = {"page": str(Path(page).resolve()), "notebook": nbformat.writes(nb),
              "evaluated": evaluated, "seconds": round(float(seconds), 1)}
    path = directory / f"{Path(page).stem}.json"
    tmp = path.with_suffix(".json.tmp")
    tmp.write_text(json.dumps(record), encoding="utf-8")
    tmp.replace(path)
    return path


def import_executed(cache, directory, pages):
    """Store in ``cache`` every page of ``pages`` that :func:`write_executed` kept in
    ``directory`` and whose code cells are the page's own now; returns their paths.

    A kept execution of another version of the page (its code changed since) is left out
    and said so: the page is then executed here.
    """
    done = []
    wanted = {p.resolve(): p for p in pages}
    for path in sorted(Path(directory).glob("*.json")):
        record = json.loads(path.read_text(encoding="utf-8"))
        page = wanted.get(Path(record["page"]))
        if page is None:
            continue
        nb = nbformat.reads(record["notebook"], as_version=4)
        if code_sources(nb) != code_sources(read_page(page)):
            print(f"book_execute: {page.relative_to(ROOT)}: the execution kept in {path} is "
                  "of another version of its code: executed here", flush=True)
            continue
        store_page(cache, page, nb, record["seconds"], record["evaluated"])
        print(f"book_execute: {page.relative_to(ROOT)} executed by nbval in "
              f"{record['seconds']:.1f} s, stored", flush=True)
        done.append(page)
    return done


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                        help="pages executed at once (default: the number of CPUs)")
    parser.add_argument("--executed", type=Path, default=None,
                        help="a directory of pages executed by make test's nbval run "
                             "(tools/nbval_book.py): stored, not executed again")
    parser.add_argument("pages", nargs="*", type=Path,
                        help="only these pages (default: every notebook page of _toc.yml)")
    args = parser.parse_args(argv)
    if args.jobs < 1:
        print(f"book_execute: --jobs must be at least 1, got {args.jobs}", file=sys.stderr)
        return 2
    if args.executed is not None and not args.executed.is_dir():
        print(f"book_execute: --executed {args.executed}: no such directory", file=sys.stderr)
        return 2
    with open_cache() as cache:
        return _run(args, cache)


def _run(args, cache):
    """The body of :func:`main`, with the execution cache open."""
    todo = []
    pages = [p.resolve() for p in args.pages] if args.pages else notebook_pages()
    if args.executed is not None:
        import_executed(cache, args.executed, pages)
    for path in longest_first(pages):
        nb = read_page(path)
        try:
            record = cache.match_cache_notebook(nb)
        except KeyError:
            todo.append(path)
            continue
        if set(page_expressions(nb)) - set((record.data or {}).get(BOOK_CACHE_KEY, {})):
            todo.append(path)  # its prose shows an expression its cached run did not evaluate
    if not todo:
        print("book_execute: every page is in the execution cache")
        return 0
    timeout = default_timeout()
    try:
        times = json.loads(TIMES.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        times = {}
    start = time.perf_counter()
    print(f"book_execute: {len(todo)} pages, {args.jobs} at a time", flush=True)
    with concurrent.futures.ProcessPoolExecutor(args.jobs) as pool:
        futures = [pool.submit(execute, path, timeout) for path in todo]
        for future in concurrent.futures.as_completed(futures):
            path, text, seconds, error, (index, cell_s, line), evaluated = future.result()
            name = path.relative_to(ROOT)
            where = f" (slowest: cell {index}, {cell_s:.1f} s, `{line}`)" if index is not None else ""
            if error is not None:
                print(f"book_execute: {name} failed after {seconds:.1f} s{where}\n{error}",
                      file=sys.stderr, flush=True)
                for other in futures:
                    other.cancel()
                return 1
            store_page(cache, path, nb=nbformat.reads(text, as_version=4), seconds=seconds,
                       evaluated=evaluated)
            times[path.name] = round(seconds, 1)
            print(f"book_execute: {name} {seconds:.1f} s{where}", flush=True)
    TIMES.write_text(json.dumps(times, indent=1, sort_keys=True), encoding="utf-8")
    print(f"book_execute: done in {time.perf_counter() - start:.1f} s wall", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
