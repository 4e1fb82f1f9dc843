"""Numbers in a chapter's prose: glued by the code, evaluated by the markdown (``{eval}``).

A chapter never types a number it computed. Its code glues the value under a name, and its
markdown shows it with MyST's ``{eval}`` role on the table :data:`glued`, with a format
specification after a colon::

    # a code cell
    from xnavlab.core.prose import glue, glued
    glue("ch07_sigma_m", float(SIGMA), display=False)

    <!-- the next markdown cell -->
    with {eval}`glued["ch07_sigma_m:g"]` m of white noise

Both readers of the chapter evaluate the role in the chapter's own kernel: JupyterLab with
``jupyterlab-myst`` (``make setup`` installs it) when the reader runs the markdown cell, and the
HTML book when ``tools/book_execute.py`` executes the chapter (it evaluates each markdown cell's
``{eval}`` expressions at that cell's place and stores the results with the executed notebook
in myst-nb's cache, where ``book/_ext/xnav_eval.py`` gives them to myst-nb's ``{eval}`` role).
The entry shows ``format(value, spec)`` as plain text, exactly as myst-nb's
``{glue:text}`name:spec``` did; without a spec, ``str(value)``.

Rules that keep the two readers in agreement:

* a name is glued once (or again with the same value): JupyterLab's "Run All Cells" may
  evaluate a markdown cell after later code cells ran, so the prose must not depend on when
  it is evaluated (``tools/book_execute.py`` fails on a value that changes after the prose that
  shows it);
* only ``glued["name"]`` and ``glued["name:spec"]`` are evaluated by the book
  (``nb_eval_name_regex`` in ``_config.yml``): the prose holds no other code.

This module is the kernel side: :func:`glue` records a value in the table :data:`glued` (a
:class:`Glued`), whose entries are :class:`Text`, a string shown without quotes. It also holds
what the tools share about the role (:data:`EVAL_ROLE`, :data:`EVAL_NAME`,
:func:`eval_expressions`, :data:`BOOK_CACHE_KEY`).
"""

from __future__ import annotations

import math
import numbers
import re
from collections.abc import Mapping

from xnavlab.core.validate import check_bool

__all__ = [
    "Text",
    "Glued",
    "glued",
    "glue",
    "format_value",
    "EVAL_ROLE",
    "EVAL_NAME",
    "eval_expressions",
    "BOOK_CACHE_KEY",
]

#: An ``{eval}`` role in MyST markdown (single backticks); group 1 is the expression.
EVAL_ROLE = re.compile(r"\{eval\}`([^`\n]+)`")
#: The expressions the book evaluates: an entry of :data:`glued`, ``glued["name"]`` or
#: ``glued["name:spec"]`` (``nb_eval_name_regex`` of ``_config.yml`` is this pattern).
#:
#: :meta hide-value:
EVAL_NAME = r'^glued\["[A-Za-z_][A-Za-z0-9_]*(:[^"\\]*)?"\]$'
#: Where ``tools/book_execute.py`` keeps a page's evaluated expressions: this key of the data of
#: the page's record in myst-nb's execution cache (``book/_ext/xnav_eval.py`` reads it).
BOOK_CACHE_KEY = "xnavlab_eval"
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
# Code in markdown that is shown, not evaluated: fenced blocks that are not directives
# (```python ..., not ```{exercise}) and inline code spans.
_FENCE = re.compile(r"^([ \t]*)(`{3,}|~{3,})(?!\{)[^\n]*\n.*?^\1\2[ \t]*$", re.M | re.S)
_FENCE_LINE = re.compile(r"^[ \t]*(?:`{3,}|~{3,}).*$", re.M)  # a directive's own fence lines
_TICKS = re.compile(r"`+")
_ROLE_HEAD = re.compile(r"\{[\w:.+-]+\}$")


class Text(str):
    """Text that shows as itself: its ``repr`` has no quotes.

    An ``{eval}`` role shows the ``text/plain`` representation of its value, which for a
    ``str`` is its ``repr`` (quoted, with backslashes doubled). A :class:`Text` is shown as
    written, in JupyterLab, in myst-nb and in a code cell's output.

    Examples
    --------
    >>> Text("5,000")
    5,000
    >>> Text("5,000") == "5,000"
    True
    """

    __slots__ = ()

    def __repr__(self):
        return str.__str__(self)


def format_value(value, spec=""):
    """``value`` as the prose shows it: ``format(value, spec)``, or ``str(value)`` without a spec.

    The rule of myst-nb's ``{glue:text}`` role: a spec ending in ``e``, ``E``, ``f``,
    ``F``, ``g``, ``G``, ``n`` or ``%`` formats ``float(value)``, one ending in ``b``, ``c``,
    ``d``, ``o``, ``x`` or ``X`` formats ``int(value)``, one ending in ``s`` formats
    ``str(value)``. A NumPy scalar is formatted as the Python number it holds.

    Refused, so that no wrong number reaches the reader: a non-finite number (NaN or an
    infinity, shown as ``nan``/``inf``, with any spec) and a number that is not a whole one
    with an integer spec (``int()`` would truncate 1.5 to ``1``).

    Parameters
    ----------
    value : object
        The glued value.
    spec : str
        A format specification (Python's mini-language), e.g. ``".1f"``, ``",d"``, ``".0%"``.

    Returns
    -------
    Text
        The formatted value.

    Raises
    ------
    ValueError
        When the spec does not apply to the value, the value is not finite, or an integer
        spec would truncate it (``spec`` and the value are named).

    Examples
    --------
    >>> format_value(4190.0, ".0f"), format_value(156, ""), format_value(0.25, ".0%")
    (4190, 156, 25%)
    >>> format_value("REPRODUCED")
    REPRODUCED
    >>> format_value(1.5, "d")
    Traceback (most recent call last):
    ...
    ValueError: spec 'd' would truncate the value 1.5 to 1 (use a float spec such as '.0f', or round it first)
    """
    if not isinstance(spec, str):
        raise ValueError(f"spec must be a format specification string, got {spec!r}")
    if hasattr(value, "item") and getattr(value, "shape", None) == ():
        value = value.item()  # a NumPy scalar: the Python number it holds
    if isinstance(value, numbers.Number) and not isinstance(value, numbers.Integral) and not (
            math.isfinite(abs(value))):  # NaN and the infinities, real or complex
        raise ValueError(f"the non-finite value {value!r} would reach the prose (spec {spec!r}): "
                         f"glue a finite number, or text that says why there is none")
    if spec == "":
        return Text(str(value))
    kind = spec[-1]
    if kind in "bcdoxX" and isinstance(value, numbers.Real) and int(value) != value:
        raise ValueError(f"spec {spec!r} would truncate the value {value!r} to {int(value)} "
                         f"(use a float spec such as '.0f', or round it first)")
    try:
        if kind == "s":
            value = str(value)
        elif kind in "bcdoxX":
            value = int(value)
        elif kind in "eEfFgGn%":
            value = float(value)
        return Text(format(value, spec))
    except (TypeError, ValueError) as exc:
        raise ValueError(f"spec {spec!r} does not format the value {value!r}: {exc}") from None


class Glued(Mapping):
    """A chapter's glued values, read by the prose as ``glued["name:spec"]``.

    :meth:`glue` records a value; an entry ``"name"`` or ``"name:spec"`` is the value as
    :func:`format_value` shows it, a :class:`Text`. Iterating gives the names glued so far.

    Examples
    --------
    >>> table = Glued()
    >>> table.glue("ch07_sigma_m", 5000.0)
    >>> table["ch07_sigma_m:g"], table["ch07_sigma_m:,.0f"], table["ch07_sigma_m"]
    (5000, 5,000, 5000.0)
    >>> table.value("ch07_sigma_m")
    5000.0
    >>> table["ch07_typo"]
    Traceback (most recent call last):
    ...
    KeyError: "nothing glued as 'ch07_typo' (1 names glued: ch07_sigma_m)"
    """

    def __init__(self):
        self._values = {}

    def glue(self, name, value, display=False):
        """Record ``value`` as ``name`` (the call of myst-nb's ``glue``, for the prose's ``{eval}``).

        Parameters
        ----------
        name : str
            A Python identifier, by convention ``chNN_what_unit``.
        value : object
            The value; the prose formats it (a float, an int, a string ...).
        display : bool
            Also show the value as the cell's output (IPython's ``display``); True or False.

        Notes
        -----
        A non-finite number may be glued (a chapter's code may keep one), but no entry shows
        it: ``glued["name:spec"]`` refuses it, naming the entry (:func:`format_value`).
        """
        if not isinstance(name, str) or not _NAME.fullmatch(name):
            raise ValueError(f"name must be an identifier such as 'ch07_sigma_m', got {name!r}")
        display = check_bool("display", display)
        self._values[name] = value
        if display:
            from IPython.display import display as show

            show(value)

    def value(self, name):
        """The value glued as ``name`` (unformatted)."""
        return self._values[self._name(name)]

    def _name(self, name):
        if name not in self._values:
            known = ", ".join(sorted(self._values)[:8]) + (", ..." if len(self._values) > 8 else "")
            raise KeyError(f"nothing glued as {name!r} ({len(self._values)} names glued: {known})")
        return name

    def __getitem__(self, key):
        if not isinstance(key, str):
            raise KeyError(f"an entry is 'name' or 'name:spec', got {key!r}")
        name, _, spec = key.partition(":")
        value = self._values[self._name(name)]
        try:
            return format_value(value, spec)
        except ValueError as exc:  # named by the entry the prose asked for
            raise ValueError(f"glued[{key!r}]: {exc}") from None

    def __iter__(self):
        return iter(self._values)

    def __len__(self):
        return len(self._values)

    def __repr__(self):
        return f"<Glued: {len(self._values)} values>"


#: The kernel's table: what :func:`glue` records and the chapters' ``{eval}`` roles read.
glued = Glued()
#: ``glue(name, value, display=False)``: record a value in :data:`glued` (:meth:`Glued.glue`).
glue = glued.glue


def eval_expressions(markdown):
    """The ``{eval}`` expressions of a markdown cell, in order, each once.

    Roles inside code (a fenced block that is not a directive, an inline code span) are
    left out; roles inside directives (an exercise, an admonition, a table cell) count.

    Examples
    --------
    >>> eval_expressions('A {eval}`glued["a:.1f"]`, `{eval}` and {eval}`glued["a:.1f"]`.')
    ['glued["a:.1f"]']

    ``markdown`` must be a ``str`` (a cell's source joined); anything else is one ValueError.
    """
    if not isinstance(markdown, str):
        raise ValueError(f"markdown must be a str (a markdown cell's source), got "
                         f"{type(markdown).__name__}")
    text = _FENCE_LINE.sub("", _FENCE.sub("", markdown))
    found, pos = [], 0
    while (m := _TICKS.search(text, pos)) is not None:
        # a run of backticks opens a role's content ({name}`...`) or a code span; either
        # ends at the next run of the same length (CommonMark), or is literal text
        close = re.compile(rf"(?<!`){m.group()}(?!`)").search(text, m.end())
        if close is None:
            pos = m.end()
            continue
        head = _ROLE_HEAD.search(text, 0, m.start())
        if head is not None and head.group() == "{eval}":
            found.append(text[m.end():close.start()].strip())
        pos = close.end()
    return list(dict.fromkeys(found))
