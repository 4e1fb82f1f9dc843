"""Sphinx extension: myst-nb's ``{eval}`` role on pages executed into the execution cache.

The chapters show their numbers with ``{eval}`glued["ch07_sigma_m:g"]``` (the convention of
:mod:`xnavlab.core.prose`), a role JupyterLab evaluates in the reader's kernel
(``jupyterlab-myst``). myst-nb 1.4 can evaluate it only in its ``inline`` execution mode: in
``cache`` mode, the book's, ``NotebookClientCache.eval_variable`` raises
``NotImplementedError`` and the role renders nothing but a warning.

``tools/book_execute.py`` (``make book`` runs it before ``jupyter-book build``) evaluates every
``{eval}`` expression of a page in its kernel, at the place of the markdown cell that shows
it, and stores the results with the executed page in the cache (the record's data, key
:data:`xnavlab.core.prose.BOOK_CACHE_KEY`). This extension gives ``NotebookClientCache`` an
``eval_variable`` that returns them, as ``execute_result`` outputs, so that myst-nb's own role
renders them (their ``text/plain``, as ``{glue:text}`` rendered a glued value). It also sets
``nb_eval_name_regex`` to :data:`xnavlab.core.prose.EVAL_NAME`: only ``glued["name"]`` and
``glued["name:spec"]`` are evaluated.

A value that is not there (the page was executed by ``jupyter-book build`` itself, not by
``tools/book_execute.py``) is an error, not an empty number: myst-nb turns it into a warning,
which fails the book's ``-W`` build.

Registered in ``_config.yml`` under ``sphinx.local_extensions``.
"""

from __future__ import annotations

import re

import nbformat
from jupyter_cache import get_cache
from myst_nb.core.execute.base import EvalNameError
from myst_nb.core.execute.cache import NotebookClientCache

from xnavlab.core.prose import BOOK_CACHE_KEY, EVAL_NAME


class MissingEvaluation(RuntimeError):
    """An ``{eval}`` expression whose value the page's cached execution does not hold."""


def cached_evaluations(cache_path, notebook):
    """The evaluated expressions stored with ``notebook``'s record in the cache at ``cache_path``.

    Returns a dict expression -> ``{"data": ..., "metadata": ...}``, empty when the notebook
    is not in the cache or was cached without them.
    """
    cache = get_cache(str(cache_path))
    try:
        record = cache.match_cache_notebook(notebook)
    except KeyError:
        return {}
    finally:
        cache.db.dispose()  # close jupyter_cache's sqlite connections
    return dict((record.data or {}).get(BOOK_CACHE_KEY) or {})


def eval_variable(self, name):
    """``NotebookClientCache.eval_variable``: the value ``tools/book_execute.py`` evaluated.

    Raises ``EvalNameError`` for an expression outside ``nb_eval_name_regex`` and
    :class:`MissingEvaluation` for one the cached execution did not evaluate.
    """
    if not re.match(self.nb_config.eval_name_regex, name):
        raise EvalNameError(name)
    values = getattr(self, "_xnav_evaluations", None)
    if values is None:  # read once per page
        path = self.nb_config.execution_cache_path or ".jupyter_cache"
        values = self._xnav_evaluations = cached_evaluations(path, self.notebook)
    if name not in values:
        raise MissingEvaluation(
            f"{name} was not evaluated when the page was executed: run "
            "`python tools/book_execute.py` before `jupyter-book build` (make book does)")
    result = values[name]
    return [nbformat.v4.new_output("execute_result", data=dict(result.get("data", {})),
                                   metadata=dict(result.get("metadata", {})))]


def _config_inited(app, config):
    config.nb_eval_name_regex = EVAL_NAME


def setup(app):
    NotebookClientCache.eval_variable = eval_variable
    app.connect("config-inited", _config_inited)
    return {"version": "1.0", "parallel_read_safe": True, "parallel_write_safe": True}
