"""Sphinx extension: the book's Sphinx build may read its pages on several processes.

``make book`` builds with ``tools/book_build.py --jobs N`` (Sphinx's parallel build). Sphinx
reads in parallel only when every extension declares itself safe for it; two of Jupyter
Book 1's own declare nothing, so Sphinx warns ("does not declare if it is safe for parallel
reading") and reads serially, and ``-W`` makes the warning an error. Their sources were read
(the versions in :data:`JUDGED`):

* ``sphinx-multitoc-numbering`` 0.1.3: its ``setup`` replaces
  ``TocTreeCollector.assign_section_numbers``, which Sphinx calls in the main process on the
  merged environment once every page is read (``env-get-updated``), never in a reading
  process.
* ``sphinx-jupyterbook-latex`` 1.0.0: while a page is read, two transforms add attributes and
  hidden nodes to that page's own doctree (nothing kept in the environment); everything else
  it does acts only for the LaTeX builder.

Both are therefore safe for parallel reading, and this extension says so for them once every
extension is loaded (``config-inited``). A version other than the one judged is left alone:
Sphinx then warns as before, and the build fails until it is judged again.

Registered in ``_config.yml`` under ``sphinx.local_extensions``.
"""

from __future__ import annotations

import sys

#: Extension (module name) -> the version whose source was read and judged safe.
JUDGED = {"sphinx_multitoc_numbering": "0.1.3", "sphinx_jupyterbook_latex": "1.0.0"}


def _config_inited(app, config):
    for name, version in JUDGED.items():
        ext = app.extensions.get(name)
        module = sys.modules.get(name)
        if (ext is not None and getattr(module, "__version__", None) == version
                and ext.parallel_read_safe is None):
            ext.parallel_read_safe = True


def setup(app):
    app.connect("config-inited", _config_inited)
    return {"version": "1.0", "parallel_read_safe": True, "parallel_write_safe": True}
