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
