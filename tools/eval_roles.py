"""Convert a chapter's prose to roles that JupyterLab and the book both render.

A chapter opened in JupyterLab (with ``jupyterlab-myst``, which ``make setup`` installs) shows
its markdown as MyST. Some roles only the book's build understands and JupyterLab shows as raw
text; this tool rewrites them, mechanically, into forms both render (measured in JupyterLab
4.6 with jupyterlab-myst 2.7 and in the book's build):

* ``{glue:text}`ch07_sigma_m:g``` becomes ``{eval}`glued["ch07_sigma_m:g"]```;
* ``{py:func}`~xnavlab.core.filters.ekf_update``` becomes
  ``[`ekf_update`](#xnavlab.core.filters.ekf_update)``, and
  ``{py:func}`track.run_line <xnavlab.line.track.run_line>``` becomes
  ``[`track.run_line`](#xnavlab.line.track.run_line)`` (any ``{py:...}`` role);
* ``{doc}`chapter 7 <07_wavelets>``` becomes ``[chapter 7](07_wavelets.ipynb)``;
* in the code, ``from myst_nb import glue`` becomes ``from xnavlab.core.prose import glue, glued``.

``{eval}`` is evaluated in the chapter's kernel by both (:mod:`xnavlab.core.prose`); a Markdown
link to ``#a.python.name`` is a cross-reference to the API page in the book (myst-parser) and
code text in JupyterLab; a link to a chapter's file opens the chapter in both. The glue calls
stay as they are (``glue("name", value, display=False)``), now recording into the kernel's
table ``glued``. Jupyter's metadata ``user_expressions`` (jupyterlab-myst's copy of evaluated
values, saved by JupyterLab into a markdown cell) is removed: a chapter is committed
without outputs.

Roles both already render stay: ``{eq}``, ``{numref}``/``{ref}`` to labels of the same
notebook, ``{cite}`` (JupyterLab shows the key), ``{math}``, and the directives
(admonitions, ``{exercise}``, ``{solution-start}``/``{solution-end}``).

Usage, from the repository root::

    .venv/bin/python tools/eval_roles.py book/07_wavelets.ipynb   # convert in place
    .venv/bin/python tools/eval_roles.py                          # every chapter
    .venv/bin/python tools/eval_roles.py --check [book/NN_<name>.ipynb ...]

``--check`` changes nothing and exits 1 when a chapter is not converted or is not
consistent: a role the conversion rewrites, a ``from myst_nb import glue``, an ``{eval}``
that the book would not evaluate (:data:`xnavlab.core.prose.EVAL_NAME`), a ``glued[...]``
name no ``glue(...)`` call of the chapter makes, ``{eval}`` roles without the import of
``glued``, a code cell that assigns ``glued``, a ``{doc}`` without a text, a chapter link to
no file, saved ``user_expressions``. Exit status: 0 fine, 1 a problem, 2 a bad argument.
"""

from __future__ import annotations

import re
import sys

import nbformat
from chapter_files import chosen, notebook_parser

from xnavlab.core.prose import EVAL_NAME, eval_expressions

IMPORT_OLD = "from myst_nb import glue"
IMPORT_NEW = "from xnavlab.core.prose import glue, glued  # noqa: F401 (glued: read by the {eval} roles)"

_GLUE_TEXT = re.compile(r"\{glue:text\}`([^`\n]+)`")
_GLUE_OTHER = re.compile(r"\{glue(?::(?!text\})[\w-]*)?\}`[^`\n]*`")
_PY_ROLE = re.compile(r"\{py:(?:func|meth|class|mod|data|attr|obj|exc|const)\}`([^`\n]+)`")
_DOC_ROLE = re.compile(r"\{doc\}`([^`\n]+)`")
_TITLED = re.compile(r"^(.*?)\s*<([^<>]+)>$", re.S)
_IMPORT = re.compile(r"^from myst_nb import glue[ \t]*$", re.M)
_MYST_NB_IMPORT = re.compile(r"^\s*(?:from myst_nb\b|import myst_nb\b)", re.M)
_ASSIGNS_GLUED = re.compile(r"(?<![\w.])glued\s*(?:=[^=]|,[^\n]*=[^=])|\bfor\s+glued\b|"
                            r"\bas\s+glued\b|\bdef\s+glued\b")
# names a chapter's code may glue: every identifier-like string literal (glue("name", ...), or a
# dict of names handed to glue in a loop) and every f-string with a field (glue(f"ch02_{k}_m", ...))
_NAME_LITERAL = re.compile(r"(?<![\w])[\"']([A-Za-z_]\w*)[\"']")
_NAME_FSTRING = re.compile(r"(?<![\w])f[\"']([A-Za-z_][^\"'\n]*\{[^\"'\n]*)[\"']")
_NAME_PREFIX = re.compile(r"(?<![\w])[\"']([A-Za-z_]\w*)[\"']\s*\+")  # "ch10_range_" + name
_GLUED_NAME = re.compile(r'^glued\["([A-Za-z_]\w*)')


def _glue_to_eval(m):
    key = m.group(1).strip()
    if "::" in key:  # a value glued on another page: no kernel holds it
        return m.group()
    return f'{{eval}}`glued["{key}"]`'


def _py_to_link(m):
    target = m.group(1).strip()
    titled = _TITLED.match(target)
    if titled:
        text, target = titled.group(1).strip(), titled.group(2).strip()
    else:
        target = target.lstrip("~")
        text = target.rsplit(".", 1)[-1] if m.group(1).strip().startswith("~") else target
    text = text.lstrip("~")
    return f"[`{text}`](#{target.lstrip('.')})"


def _doc_to_link(m, folder):
    titled = _TITLED.match(m.group(1).strip())
    if not titled:
        return m.group()  # no text: JupyterLab would show the file name (--check says so)
    text, target = titled.group(1).strip(), titled.group(2).strip()
    for suffix in (".ipynb", ".md"):
        if (folder / f"{target}{suffix}").is_file():
            return f"[{text}]({target}{suffix})"
    return m.group()  # no such page: left for the build to report


def convert_markdown(text, folder):
    """``text`` with its roles rewritten; returns (text, counts by kind)."""
    counts = {}

    def count(kind, pattern, repl, source):
        new, n = pattern.subn(repl, source)
        counts[kind] = n - len(pattern.findall(new))  # those left as they were do not count
        return new

    text = count("glue:text", _GLUE_TEXT, _glue_to_eval, text)
    text = count("py", _PY_ROLE, _py_to_link, text)
    text = count("doc", _DOC_ROLE, lambda m: _doc_to_link(m, folder), text)
    return text, counts


def convert(path):
    """Convert one notebook in place; returns the counts of what changed (empty: nothing)."""
    nb = nbformat.read(path, as_version=4)
    counts = {}
    for cell in nb.cells:
        if cell.cell_type == "markdown":
            new, c = convert_markdown(cell.source, path.parent)
            for k, v in c.items():
                counts[k] = counts.get(k, 0) + v
            cell.source = new
            if cell.metadata.pop("user_expressions", None) is not None:
                counts["user_expressions"] = counts.get("user_expressions", 0) + 1
        elif cell.cell_type == "code":
            new, n = _IMPORT.subn(IMPORT_NEW, cell.source)
            if n:
                counts["import"] = counts.get("import", 0) + n
                cell.source = new
    counts = {k: v for k, v in counts.items() if v}
    if counts:
        nbformat.write(nb, path)
    return counts


def check(path, notes=None):
    """The problems of one notebook (an empty list: converted and consistent).

    ``notes``, a list, receives what may be fine: a ``glued["name"]`` whose name the code
    never spells out (it may be built at run time; the book's execution and the JupyterLab
    test evaluate every role).
    """
    notes = [] if notes is None else notes
    nb = nbformat.read(path, as_version=4)
    problems = []
    code = "\n".join(c.source for c in nb.cells if c.cell_type == "code")
    literal = set(_NAME_LITERAL.findall(code))
    patterns = [re.compile("^" + re.sub(r"\\\{[^}]*\\\}", r"\\w+", re.escape(f)) + "$")
                for f in _NAME_FSTRING.findall(code)]
    patterns += [re.compile(re.escape(p) + r"\w+$") for p in _NAME_PREFIX.findall(code)]
    n_eval = 0
    for i, cell in enumerate(nb.cells):
        where = f"{path.name}: cell {i}"
        if cell.cell_type == "code":
            if _MYST_NB_IMPORT.search(cell.source):
                problems.append(f"{where}: imports myst_nb (use `{IMPORT_NEW}`)")
            if _ASSIGNS_GLUED.search(cell.source):
                problems.append(f"{where}: assigns the name `glued` (the prose's table of "
                                "glued values: rename the variable)")
            continue
        if cell.cell_type != "markdown":
            continue
        src = cell.source
        if "user_expressions" in cell.metadata:
            problems.append(f"{where}: holds JupyterLab's saved user_expressions (values: "
                            "committed without outputs; run the tool to remove them)")
        for m in _GLUE_TEXT.finditer(src):
            problems.append(f"{where}: {m.group()} (write {_glue_to_eval(m)})")
        for m in _GLUE_OTHER.finditer(src):
            problems.append(f"{where}: {m.group()}: JupyterLab cannot show it (glue the value "
                            "and write {eval}`glued[\"name:spec\"]`)")
        for m in _PY_ROLE.finditer(src):
            problems.append(f"{where}: {m.group()} shows as raw text in JupyterLab "
                            f"(write {_py_to_link(m)})")
        for m in _DOC_ROLE.finditer(src):
            new = _doc_to_link(m, path.parent)
            problems.append(f"{where}: {m.group()} is a broken link in JupyterLab ("
                            + (f"write {new})" if new != m.group() else
                               "write [text](NN_chapter.ipynb), a link to the chapter's file)"))
        for target in re.findall(r"\]\(([^)#\s]+\.(?:ipynb|md))(?:#[^)]*)?\)", src):
            if "://" not in target and not (path.parent / target).is_file():
                problems.append(f"{where}: a link to {target}, which is not a file of book/")
        for expr in eval_expressions(src):
            n_eval += 1
            if not re.match(EVAL_NAME, expr):
                problems.append(f"{where}: {{eval}}`{expr}` is not evaluated by the book (only "
                                'glued["name"] and glued["name:spec"])')
                continue
            name = _GLUED_NAME.match(expr).group(1)
            if name not in literal and not any(p.match(name) for p in patterns):
                notes.append(f"{where}: {{eval}}`{expr}`: the chapter's code never names "
                                f"{name!r} (a typo? glue(\"{name}\", value))")
    if n_eval and not re.search(r"^from xnavlab\.core\.prose import [^\n]*\bglued\b", code, re.M):
        problems.append(f"{path.name}: {n_eval} {{eval}} roles but no "
                        f"`{IMPORT_NEW}` in its code")
    return problems


def main(argv=None):
    ap = notebook_parser(__doc__.splitlines()[0],
                         "chapters to convert or check (default: every book/NN_*.ipynb)")
    ap.add_argument("--check", action="store_true",
                    help="change nothing; exit 1 when a chapter is not converted")
    args = ap.parse_args(argv)
    paths = chosen("eval_roles", args.notebooks)
    if paths is None:
        return 2
    if args.check:
        notes = []
        problems = [p for path in paths for p in check(path, notes)]
        for p in problems:
            print(p)
        for n in notes:
            print(f"note: {n}")
        print(f"eval_roles: {len(problems)} problem(s) in {len(paths)} chapter(s)"
              if problems else f"eval_roles: {len(paths)} chapter(s) converted")
        return 1 if problems else 0
    for path in paths:
        counts = convert(path)
        said = ", ".join(f"{v} {k}" for k, v in sorted(counts.items())) or "nothing to convert"
        print(f"eval_roles: {path.name}: {said}")
        notes = []
        for p in check(path, notes):
            print(f"  left: {p}")
        for n in notes:
            print(f"  note: {n}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
