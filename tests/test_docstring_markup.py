"""Docstrings that Sphinx reads as reStructuredText: no markup error the book build would fail on.

The book is built with ``-W`` (a warning fails it), at the end of ``make test``; two of its
failures came from docstrings: ``|w| dt`` outside backquotes (read as an undefined
substitution) and a table whose first column had become narrower than a module path moved
into a subpackage ("Malformed table"). Parsing every docstring of the package with docutils
finds both classes in seconds, before the book is built.
"""

import importlib
import inspect
import pkgutil
import re

import docutils.core
import docutils.nodes
import pytest
from sphinx.ext.napoleon import Config
from sphinx.ext.napoleon.docstring import NumpyDocstring

import xnavlab

#: docutils messages that Sphinx turns into a failing warning, whatever the docstring style
#: (numpydoc's section headings and fields are not errors of this kind).
FATAL = ("Undefined substitution referenced", "Malformed table", "Inline literal start-string",
         "Inline interpreted text or phrase reference start-string",
         "Field list ends without a blank line")


def _modules():
    for info in pkgutil.walk_packages(xnavlab.__path__, "xnavlab."):
        if info.name.endswith("__main__"):
            continue
        yield info.name


def _docstrings(module):
    yield module.__name__, module.__doc__
    for name in getattr(module, "__all__", ()):
        obj = getattr(module, name, None)
        # a decorated function (functools.lru_cache) is no inspect.isfunction: callable() is
        # what autodoc documents (wavelet-details' detail_runs failed the book build unseen)
        if inspect.isclass(obj) or callable(obj):
            yield f"{module.__name__}.{name}", obj.__doc__
        if inspect.isclass(obj):
            for attr, member in vars(obj).items():
                if inspect.isfunction(member) and not attr.startswith("_"):
                    yield f"{module.__name__}.{name}.{attr}", member.__doc__


#: The book's napoleon settings (_config.yml) that change the reStructuredText it makes.
NAPOLEON = Config(napoleon_google_docstring=False, napoleon_numpy_docstring=True,
                  napoleon_use_rtype=False, napoleon_custom_sections=[["Attributes", "params_style"]])


def _errors(text):
    """The fatal messages of ``text`` as Sphinx reads it: napoleon's rendering, then docutils."""
    settings = {"report_level": 5, "halt_level": 5, "warning_stream": False}
    rst = str(NumpyDocstring(inspect.cleandoc(text), NAPOLEON))
    tree = docutils.core.publish_doctree(rst, settings_overrides=settings)
    # parse-time messages sit in the tree; the transforms' (substitutions) in transform_messages
    messages = [*tree.findall(docutils.nodes.system_message), *tree.transform_messages]
    return [m.astext().splitlines()[0] for m in messages
            if any(f in m.astext() for f in FATAL)]


@pytest.mark.parametrize("modname", sorted(_modules()))
def test_docstrings_have_no_fatal_markup(modname):
    module = importlib.import_module(modname)
    found = [(where, err) for where, doc in _docstrings(module) if doc
             for err in _errors(doc)]
    assert not found, found


def test_the_check_finds_both_classes_it_was_written_for():
    assert _errors("the angle |w| dt at most one")
    table = "==  ==\na   b\nlong_name  c\n==  ==\n"
    assert _errors(table)
    assert not _errors("the angle ``|w| dt`` at most one")
    # inside a numpydoc section, as napoleon renders it for Sphinx
    assert _errors("Sum.\n\nReturns\n-------\ndict\n    the largest |D_j| of each run\n")


def test_decorated_functions_are_read_too():
    from xnavlab.reproductions import ch08_wavelet_details as m

    assert "xnavlab.reproductions.ch08_wavelet_details.detail_runs" in dict(_docstrings(m))


@pytest.mark.parametrize("modname", sorted(_modules()))
def test_a_bare_data_reference_names_a_documented_constant(modname):
    # ``:data:`DOF_RANGE``` in a docstring resolves only if autodoc documents the name, that is,
    # if it is in the module's __all__: a constant left out failed the book build (-W, "py:data
    # reference target not found") after every test had passed
    module = importlib.import_module(modname)
    public = set(getattr(module, "__all__", ()))
    own = [(where, doc) for where, doc in _docstrings(module)  # a re-export: in its own module
           if where == modname or getattr(getattr(module, where.split(".")[len(modname.split("."))], None),
                                          "__module__", modname) == modname]
    found = [(where, ref) for where, doc in own if doc
             for ref in re.findall(r":data:`~?([A-Za-z_]\w*)`", doc) if ref not in public]
    assert not found, f"not in {modname}.__all__: {found}"


#: numpydoc sections whose unindented lines napoleon reads as ``name : type`` entries.
ENTRY_SECTIONS = ("Parameters", "Other Parameters", "Attributes")
ENTRY = re.compile(r"[*\w][\w*]*(, [*\w][\w*]*)*( : \S.*)?")


def _stray_lines(doc):
    """Unindented lines of an entry section that are not ``name[, name] : type``.

    napoleon renders such a line as one more parameter (a sentence inside Parameters became a
    parameter of type 'with' and failed the book build, -W, after every test had passed).
    """
    lines = inspect.cleandoc(doc).splitlines()
    heading = [i for i in range(len(lines) - 1)
               if lines[i + 1].strip() and set(lines[i + 1].strip()) == {"-"}]
    stray = []
    for start, end in zip(heading, [*heading[1:], len(lines)][:len(heading)], strict=True):
        if lines[start].strip() not in ENTRY_SECTIONS:
            continue
        stray += [line for line in lines[start + 2:end]
                  if line and not line[0].isspace() and not ENTRY.fullmatch(line)]
    return stray


@pytest.mark.parametrize("modname", sorted(_modules()))
def test_entry_sections_hold_only_entries(modname):
    module = importlib.import_module(modname)
    found = [(where, line) for where, doc in _docstrings(module) if doc
             for line in _stray_lines(doc)]
    assert not found, f"move each sentence into an entry or a Notes section: {found}"


def test_the_entry_check_finds_a_sentence_inside_parameters():
    doc = "Sum.\n\nParameters\n----------\nx, y : float\n    Terms.\n\nA sentence: with.\n"
    assert _stray_lines(doc) == ["A sentence: with."]
    assert _stray_lines(doc.replace("x, y : float", "z, h :")) == ["z, h :", "A sentence: with."]
    notes = doc.replace("A sentence", "Notes\n-----\nA sentence")
    assert not _stray_lines(notes)


def _ignored_class_patterns():
    """The book's ``nitpick_ignore_regex`` entries for ``py:class`` (read from _config.yml)."""
    import pathlib

    import yaml

    config = yaml.safe_load((pathlib.Path(__file__).parents[1] / "_config.yml").read_text())
    return [re.compile(rx) for role, rx in config["sphinx"]["config"]["nitpick_ignore_regex"]
            if role == "py:class"]


def _documented_classes():
    """Every class (and exception) an xnavlab module's ``__all__`` documents, by full name."""
    names = set()
    for modname in _modules():
        module = importlib.import_module(modname)
        for name in getattr(module, "__all__", ()):
            obj = getattr(module, name, None)
            if inspect.isclass(obj):
                names |= {f"{modname}.{name}", f"{obj.__module__}.{obj.__qualname__}"}
    return names


def _unresolved_types(doc, ignored, classes):
    """The pieces of ``doc``'s type fields that the book's nitpicky build (``-n``) cannot
    resolve: Sphinx splits each ``:type x: ...`` napoleon writes at its delimiters
    (PyXrefMixin's, below) and looks each piece up as a class, by the end of its name; a
    built-in or typing name, or one the config ignores, is no reference."""
    import builtins
    import typing

    from sphinx.domains.python._object import PyXrefMixin

    delimiters = PyXrefMixin._delimiters_re
    rst = str(NumpyDocstring(inspect.cleandoc(doc), NAPOLEON))
    found = []
    for spec in re.findall(r"^\s*:(?:type|vartype) [^:]*: (.*)$", rst, re.M):
        for piece in filter(None, delimiters.split(spec)):
            if delimiters.match(piece):
                continue
            piece = piece.lstrip("~.")
            if (piece == "None"
                    or inspect.isclass(getattr(builtins, piece, None))
                    or piece.removeprefix("typing.") in typing.__all__
                    or any(rx.fullmatch(piece) for rx in ignored)
                    or any(c == piece or c.endswith(f".{piece}") for c in classes)):
                continue
            found.append(piece)
    return found


@pytest.fixture(scope="module")
def type_lookup():
    return _ignored_class_patterns(), _documented_classes()


@pytest.mark.parametrize("modname", sorted(m for m in _modules() if "._" not in m))
def test_every_type_in_a_docstring_resolves_in_the_book(modname, type_lookup):
    """A type the nitpicky build cannot resolve (``os.PathLike`` before the standard library's
    ``os`` joined the ignored packages) failed the book build after every test had passed.
    The API reference documents the public modules (a private one's docstrings are not read)."""
    module = importlib.import_module(modname)
    found = [(where, piece) for where, doc in _docstrings(module) if doc
             for piece in _unresolved_types(doc, *type_lookup)]
    assert not found, f"no class of that name in the API reference or _config.yml: {found}"


def test_the_type_check_finds_a_type_the_book_cannot_resolve(type_lookup):
    doc = "Sum.\n\nParameters\n----------\nx : {}, optional\n    Terms.\n"
    assert _unresolved_types(doc.format("os.PathLike"), *type_lookup) == []  # ignored: os
    assert _unresolved_types(doc.format("shutil.Foo"), *type_lookup) == ["shutil.Foo"]
    assert _unresolved_types(doc.format("MarsScenario or None"), *type_lookup) == []
    assert _unresolved_types(doc.format("MarsScenaro"), *type_lookup) == ["MarsScenaro"]
    assert _unresolved_types(doc.format("array_like, shape (n, 3)"), *type_lookup) == []


@pytest.mark.parametrize("modname", sorted(m for m in _modules() if "._" not in m))
def test_a_reference_to_another_package_shows_its_package(modname):
    """``:class:`~matplotlib.figure.Figure``` renders as a bare "Figure", which the page check
    (tools/check_book.py) cannot tell from an unresolved xnavlab name: the CI failed on it."""
    import importlib.util

    module = importlib.import_module(modname)
    found = [(where, ref) for where, doc in _docstrings(module) if doc
             for ref in re.findall(r":\w+:`~((?!xnavlab\.|\.)[\w.]+)`", doc)
             if importlib.util.find_spec(ref.split(".")[0]) is not None]  # another package's
    assert not found, f"write the full name (no ~) of another package's object: {found}"


#: The roles the book's nitpicky build checks without an exception: only ``py:class`` has
#: ignored patterns (_config.yml), so any other role must name an object the book documents.
CHECKED_ROLES = ("func", "meth", "data", "attr", "mod", "exc", "obj", "const")


def _foreign_roles(doc):
    """The ``:func:`` ... references of ``doc`` whose target is another package's object (its
    first part an importable package other than xnavlab; ``MarsRun.metrics`` resolves in its
    module)."""
    import importlib.util

    refs = re.findall(rf":(?:py:)?(?:{'|'.join(CHECKED_ROLES)}):`~?([\w.]+)(?:\(\))?`", doc)
    return [r for r in refs if "." in r and r.split(".")[0] not in ("", "xnavlab")
            and importlib.util.find_spec(r.split(".")[0]) is not None]


@pytest.mark.parametrize("modname", sorted(m for m in _modules() if "._" not in m))
def test_an_explicit_role_names_an_object_of_the_book(modname):
    """``:func:`dataclasses.replace``` is a warning of the nitpicky build (offline, the standard
    library's objects do not resolve; only py:class has ignored patterns): the fresh-clone CI's
    book build failed on two docstrings of the attitude results after every test had passed.
    Another package's function is written as a literal, ````dataclasses.replace````."""
    module = importlib.import_module(modname)
    found = [(where, ref) for where, doc in _docstrings(module) if doc
             for ref in _foreign_roles(doc)]
    assert not found, f"write another package's object as a ``literal``: {found}"


def test_the_role_check_finds_a_foreign_function():
    assert _foreign_roles("made with :func:`dataclasses.replace` or :meth:`MarsRun.check`") == \
        ["dataclasses.replace"]
    assert _foreign_roles(":func:`~xnavlab.reproduce.run`, :data:`MAX_SAMPLES`, :func:`run`") == []
