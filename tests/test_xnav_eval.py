"""book/_ext/xnav_eval.py: myst-nb's {eval} role reads what tools/book_execute.py evaluated.

The build's side of the chapters' ``{eval}`glued["name:spec"]``` numbers: the extension's
``eval_variable`` returns the value stored with the page's record in the execution cache, and
refuses, loudly, an expression that the book does not evaluate or that was never evaluated
(the role then renders a warning, which fails the ``-W`` build, never an empty number).
"""

import sys
from pathlib import Path
from types import SimpleNamespace

import nbformat
import pytest
from jupyter_cache import get_cache
from jupyter_cache.base import CacheBundleIn
from myst_nb.core.execute.base import EvalNameError

from xnavlab.core.prose import BOOK_CACHE_KEY, EVAL_NAME

EXT = Path(__file__).resolve().parents[1] / "book" / "_ext"


@pytest.fixture
def ext(monkeypatch):
    monkeypatch.syspath_prepend(str(EXT))
    import xnav_eval

    yield xnav_eval
    sys.modules.pop("xnav_eval", None)


def _page(code="x = 1"):
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(code),
                                         nbformat.v4.new_markdown_cell('{eval}`glued["a:.1f"]`')])
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                 "language": "python"}
    return nb


def _client(cache_path, nb):
    config = SimpleNamespace(eval_name_regex=EVAL_NAME, execution_cache_path=str(cache_path))
    return SimpleNamespace(nb_config=config, notebook=nb)


def _cache(path, nb, data):
    cache = get_cache(str(path))
    try:
        cache.cache_notebook_bundle(CacheBundleIn(nb, str(path / "one.ipynb"), data=data),
                                    check_validity=False, overwrite=True)
    finally:
        cache.db.dispose()


def test_the_role_gets_the_value_evaluated_with_the_cached_page(ext, tmp_path):
    nb = _page()
    _cache(tmp_path, nb, {BOOK_CACHE_KEY: {'glued["a:.1f"]': {"data": {"text/plain": "4.2"},
                                                               "metadata": {}}}})
    (out,) = ext.eval_variable(_client(tmp_path, nb), 'glued["a:.1f"]')
    assert out.output_type == "execute_result" and out.data == {"text/plain": "4.2"}
    out.metadata["strip_text_quotes"] = True   # what myst-nb's role does to it ...
    (again,) = ext.eval_variable(_client(tmp_path, nb), 'glued["a:.1f"]')
    assert again.metadata == {}               # ... leaves the stored value as it was


def test_an_expression_never_evaluated_is_an_error_that_says_what_to_run(ext, tmp_path):
    nb = _page()
    _cache(tmp_path, nb, {"execution_seconds": 1.0})     # cached by jupyter-book itself
    with pytest.raises(ext.MissingEvaluation, match="run `python tools/book_execute.py`"):
        ext.eval_variable(_client(tmp_path, nb), 'glued["a:.1f"]')
    with pytest.raises(ext.MissingEvaluation):                # a page not in the cache at all
        ext.eval_variable(_client(tmp_path / "empty", _page("y = 2")), 'glued["a:.1f"]')


def test_only_entries_of_the_glued_table_are_evaluated(ext, tmp_path):
    with pytest.raises(EvalNameError):
        ext.eval_variable(_client(tmp_path, _page()), "__import__('os').getcwd()")


def test_the_extension_installs_itself_into_myst_nb(ext):
    from myst_nb.core.execute.cache import NotebookClientCache

    calls = []
    app = SimpleNamespace(connect=lambda event, fn: calls.append((event, fn)))
    saved = NotebookClientCache.eval_variable
    try:
        assert ext.setup(app)["parallel_read_safe"]
        assert NotebookClientCache.eval_variable is ext.eval_variable
    finally:
        NotebookClientCache.eval_variable = saved
    config = SimpleNamespace(nb_eval_name_regex=r"^[a-zA-Z_][a-zA-Z0-9_]*$")
    (event, fn), = calls
    fn(None, config)
    assert event == "config-inited" and config.nb_eval_name_regex == EVAL_NAME
