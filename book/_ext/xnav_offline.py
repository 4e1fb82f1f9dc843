"""Sphinx extension: a book that renders with no network.

* MathJax 3 is served from the build itself. The files come from the PyPI package
  ``django-static-mathjax`` (see ``environment.txt``); at the end of an HTML build the
  parts MathJax needs for TeX input and CommonHTML output (the ``tex-mml-chtml.js``
  bundle, its TeX extensions, fonts, menu and accessibility components) are copied to
  ``_build/html/_static/mathjax/es5/``. ``mathjax_path`` points there unless
  ``_config.yml`` sets another one. MathJax itself is never committed.
* The ipywidgets embed scripts (require.js and the html-manager from a CDN, added by
  myst-nb on pages that store widget state) are replaced by ``xnav-widgets-loader.js``,
  which fetches them only when the browser is online and ignores failures. A page
  therefore renders, without a JavaScript error, whether or not the CDN is reachable;
  the kernel-free scrubbers of :mod:`xnavlab.core.widgets` carry the interactivity offline.
* A script added twice to a page (sphinx-thebe's inline configuration) is kept once.

Registered in ``_config.yml`` under ``sphinx.local_extensions``.
"""

from __future__ import annotations

import filecmp
import importlib.util
import shutil
from pathlib import Path

from sphinx.errors import ExtensionError
from sphinx.util import logging

logger = logging.getLogger(__name__)

MATHJAX_PATH = "mathjax/es5/tex-mml-chtml.js"  # relative to _static
# what tex-mml-chtml.js may load at run time (autoloaded TeX packages, fonts, menu, a11y)
_MATHJAX_PARTS = ["tex-mml-chtml.js", "input", "output/chtml", "ui", "a11y", "sre", "adaptors"]
_STATIC = Path(__file__).parent / "static"
_SPHINX_DEFAULT_MATHJAX = "https://cdn.jsdelivr.net/npm/mathjax@3/es5/tex-mml-chtml.js"


def mathjax_source():
    """Directory ``.../mathjax/static/mathjax/es5`` of the installed django-static-mathjax."""
    spec = importlib.util.find_spec("mathjax")
    if spec is None or not spec.submodule_search_locations:
        raise ExtensionError(
            "xnav_offline: MathJax for the offline book comes from the PyPI package "
            "'django-static-mathjax'; install it (pip install -r environment.txt)"
        )
    es5 = Path(next(iter(spec.submodule_search_locations))) / "static" / "mathjax" / "es5"
    if not (es5 / "tex-mml-chtml.js").is_file():
        raise ExtensionError(f"xnav_offline: no tex-mml-chtml.js under {es5}")
    return es5


def _config_inited(app, config):
    if config.mathjax_path in ("", None, _SPHINX_DEFAULT_MATHJAX):
        config.mathjax_path = MATHJAX_PATH
    # myst-nb adds these to pages with widget state; a local loader makes them optional
    from myst_nb.core.config import ipywidgets_js_factory

    if config.nb_ipywidgets_js == ipywidgets_js_factory():
        config.nb_ipywidgets_js = {"xnav-widgets-loader.js": {}}
    config.html_static_path = [*config.html_static_path, str(_STATIC)]


def _copy_tree(src, dst):
    """Copy ``src`` to ``dst`` (file or directory), skipping files already identical."""
    if src.is_file():
        if not (dst.is_file() and filecmp.cmp(src, dst, shallow=True)):
            dst.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dst)
        return
    for f in src.rglob("*"):
        if f.is_file():
            _copy_tree(f, dst / f.relative_to(src))


def _build_finished(app, exception):
    if exception is not None or app.builder.format != "html":
        return
    if app.config.mathjax_path != MATHJAX_PATH:
        return
    es5 = mathjax_source()
    target = Path(app.outdir) / "_static" / "mathjax" / "es5"
    for part in _MATHJAX_PARTS:
        if (es5 / part).exists():
            _copy_tree(es5 / part, target / part)
    logger.info("xnav_offline: MathJax served from _static/mathjax (offline)")


def _dedupe_scripts(app, pagename, templatename, context, doctree):
    """Drop repeated identical <script> entries (sphinx-thebe adds its inline
    ``const THEBE_JS_URL = ...`` twice under Sphinx 7, once with filename ``None`` and
    once with ``''``: a SyntaxError in the browser)."""
    scripts = context.get("script_files")
    if not scripts:
        return
    seen, kept = set(), []
    for js in scripts:
        key = (getattr(js, "filename", js) or "",
               tuple(sorted((k, str(v)) for k, v in getattr(js, "attributes", {}).items())))
        if key not in seen:
            seen.add(key)
            kept.append(js)
    scripts[:] = kept


def _builder_inited(app):
    if app.builder.format == "html" and app.config.mathjax_path == MATHJAX_PATH:
        mathjax_source()  # fail early, with the fix, when the package is missing


def setup(app):
    app.connect("config-inited", _config_inited, priority=900)
    app.connect("build-finished", _build_finished)
    app.connect("builder-inited", _builder_inited)
    app.connect("html-page-context", _dedupe_scripts, priority=900)
    return {"version": "1.0", "parallel_read_safe": True, "parallel_write_safe": True}
