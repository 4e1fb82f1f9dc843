"""Sphinx extension for the API reference (``book/api/``): module constants as written.

napoleon reads the first line of a data or attribute docstring as ``type: description``
(the Google "inline attribute" convention), so ``#: Julian date of J2000 (12:00 TDB).`` would
render with "Julian date of J2000 (12" as its type. xnavlab's constants are documented in
prose (``#:`` comments), so their docstrings are restored after napoleon has run; functions,
classes and modules still go through napoleon (numpydoc sections).

A package re-exports the names of its modules (``xnavlab.core.detection.Event`` is
``xnavlab.core.detection.online.Event``); the reference documents each name once, in its
module, so a reference written with the package path is resolved to that module. A name the
package does not export still fails the nitpicky build.
"""

import importlib

_saved = {}


def _save(app, what, name, obj, options, lines):
    if what in ("data", "attribute"):
        _saved[(what, name)] = list(lines)


def _restore(app, what, name, obj, options, lines):
    if (what, name) in _saved:
        lines[:] = _saved.pop((what, name))


def _reexported(app, env, node, contnode):
    """Resolve ``xnavlab.PKG.NAME`` to ``MODULE.NAME`` when PKG re-exports MODULE's NAME."""
    if node.get("refdomain") != "py":
        return None
    modname, _, attr = node.get("reftarget", "").lstrip("~.").rpartition(".")
    if not modname.startswith("xnavlab."):
        return None
    try:
        module = importlib.import_module(modname)
    except ImportError:
        return None
    home = getattr(getattr(module, attr, None), "__module__", None)
    if attr not in getattr(module, "__all__", ()) or not home or home == modname:
        return None
    return env.get_domain("py").resolve_xref(env, node["refdoc"], app.builder, node["reftype"],
                                             f"{home}.{attr}", node, contnode)


def setup(app):
    app.setup_extension("sphinx.ext.napoleon")
    app.connect("autodoc-process-docstring", _save, priority=100)  # before napoleon (500)
    app.connect("autodoc-process-docstring", _restore, priority=900)  # after it
    app.connect("missing-reference", _reexported)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
