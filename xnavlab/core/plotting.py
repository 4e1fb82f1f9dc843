"""Figures outside pyplot, and tables, for reproductions, chapters and the CLI.

A bare :class:`matplotlib.figure.Figure` needs no backend, so writing a figure never
switches the backend of a running notebook kernel and leaves no open pyplot figure.

Tables are built so that no cell's content can break them: :func:`markdown_table` escapes
``|`` and newlines, :func:`html_table` escapes every cell (``<``, ``&``, ``|`` are text).
Prefer :func:`html_table` for a table whose cells may hold ``|`` inside math (a norm, an
absolute value): in a Markdown table the escaped ``\\|`` reaches the math as ``\\|``.
"""

from __future__ import annotations

import html
import math
from collections.abc import Mapping

import numpy as np

from xnavlab.core.validate import check_int, check_keywords, check_real, shown

__all__ = ["figure", "check_figsize", "MAX_PIXELS", "check_axes", "sparse_log_minors",
           "LOG_MINOR_SUBS", "markdown_table", "html_table", "SafeHTML", "format_cell", "in_place",
           "updater", "UPDATE_ATTR"]

#: Where :func:`sparse_log_minors` puts the minor ticks of a log axis: at 2 and 5 of each decade.
LOG_MINOR_SUBS = (2.0, 5.0)

#: The most pixels a figure may be drawn with (width x height at its dpi): 50 million, a
#: 200 MB RGBA buffer (a figure of (150, 150) inches at 100 dpi would be 225 million, 0.9 GB).
MAX_PIXELS = 50_000_000


def check_figsize(figsize, dpi, name="figsize"):
    """Return ``(width, height)``, inches, if the figure they make at ``dpi`` has at least one
    pixel a side and at most :data:`MAX_PIXELS` pixels, else one ValueError naming ``name``.

    Parameters
    ----------
    figsize : sequence of two float
        Width and height, inches, each > 0.
    dpi : float
        Dots per inch the figure is drawn at (> 0).
    name : str
        The parameter, for the messages.

    Returns
    -------
    (float, float)

    Examples
    --------
    >>> check_figsize((6, 3.5), 100)
    (6.0, 3.5)
    >>> check_figsize((150, 150), 100)
    Traceback (most recent call last):
    ...
    ValueError: figsize must make 1 to 50,000,000 pixels at 100 dpi (width x height x dpi^2, \
at least one pixel a side), got (150, 150) inches: 225,000,000 pixels
    """
    if isinstance(figsize, str | bytes | dict) or not hasattr(figsize, "__len__") or \
            len(figsize) != 2:
        raise ValueError(f"{name} must be a pair (width, height) of inches, got {shown(figsize)}")
    width = check_real(f"{name}[0]", figsize[0], 0.0, math.inf, lo_open=True)
    height = check_real(f"{name}[1]", figsize[1], 0.0, math.inf, lo_open=True)
    dpi = check_real("dpi", dpi, 0.0, math.inf, lo_open=True)
    pixels = width * dpi * height * dpi
    if min(width, height) * dpi < 1.0 or not pixels <= MAX_PIXELS:
        raise ValueError(f"{name} must make 1 to {MAX_PIXELS:,} pixels at {dpi:g} dpi (width x "
                         f"height x dpi^2, at least one pixel a side), got ({width:g}, "
                         f"{height:g}) inches: {pixels:,.0f} pixels")
    return width, height


def figure(*args, figsize=(6.0, 3.5), **kwargs):
    """A figure for a reproduction's PNG: like ``pyplot.subplots`` but outside pyplot.

    ``args`` and ``kwargs`` are ``Figure.subplots``' (``nrows``, ``ncols``, ``sharex``, ...);
    another keyword is refused, naming it. ``figsize`` is (width, height), inches, making at
    most :data:`~xnavlab.core.plotting.MAX_PIXELS` pixels at matplotlib's ``figure.dpi``
    (:func:`~xnavlab.core.plotting.check_figsize`).

    A bare :class:`matplotlib.figure.Figure` needs no backend, so writing figures never
    switches the backend of a running notebook kernel and leaves no open pyplot figure.

    Returns
    -------
    (Figure, Axes or array of Axes)

    Examples
    --------
    >>> fig, ax = figure()
    >>> type(fig).__name__
    'Figure'
    """
    import matplotlib as mpl
    from matplotlib.figure import Figure

    kwargs = check_keywords("figure", kwargs, Figure.subplots)  # named here, not by matplotlib
    fig = Figure(figsize=check_figsize(figsize, mpl.rcParams["figure.dpi"]))
    return fig, fig.subplots(*args, **kwargs)


def check_axes(name, ax, figure=None):
    """Return ``(fig, ax)`` if ``ax`` is a 2-D rectilinear matplotlib Axes that belongs to a
    figure, else one ValueError naming ``name``: the rule of every plotting function's ``ax``
    or ``axes`` item.

    A 3-D, polar or other projection's Axes, or an Axes removed from its figure, is refused
    before anything is drawn (they were matplotlib's TypeError, NotImplementedError or
    AttributeError half-way through a plot). ``fig`` is the Axes' root
    ``matplotlib.figure.Figure`` (a subfigure's Axes: the figure holding it), the
    figure the plotting function returns.

    Parameters
    ----------
    name : str
        The user's parameter (``"ax"``, ``"axes[1]"``), leading the message.
    ax : object
        The value to check.
    figure : matplotlib.figure.Figure, optional
        The root figure ``ax`` must belong to (that of the other Axes of the same plot).

    Returns
    -------
    (Figure, Axes)

    Examples
    --------
    >>> fig, ax = figure()
    >>> check_axes("ax", ax) == (fig, ax)
    True
    >>> check_axes("ax", fig.add_subplot(projection="polar"))
    Traceback (most recent call last):
    ...
    ValueError: ax must be a 2-D rectilinear matplotlib Axes, got a 'polar' Axes
    """
    from matplotlib.axes import Axes

    want = "a 2-D rectilinear matplotlib Axes"
    if not isinstance(ax, Axes):
        raise ValueError(f"{name} must be {want}, got {type(ax).__name__} {shown(ax)}")
    if ax.name != "rectilinear":
        raise ValueError(f"{name} must be {want}, got a {ax.name!r} Axes")
    owner = ax.figure
    if owner is None or not (ax in owner.axes or any(ax in a.child_axes for a in owner.axes)):
        raise ValueError(f"{name} must be {want} of a figure, got an Axes removed from its "
                         f"figure")
    root = owner.figure  # a Figure's is itself, a SubFigure's the Figure that holds it
    if figure is not None and root is not figure:
        raise ValueError(f"{name} must be an Axes of the same figure as the others, got one of "
                         f"another figure")
    return root, ax


#: The attribute of a figure that holds its in-place update (:func:`in_place`).
UPDATE_ATTR = "xnav_update"


def in_place(fig, update):
    """Give ``fig`` an in-place update, the way a slider shows other values without a new figure.

    ``update(**values)`` takes the keyword arguments of the plotting function that built
    ``fig`` and changes ``fig`` (its artists' data, texts, limits; artists may be replaced)
    into what that function draws for ``values``: the same pixels in the same layout. It
    checks its values before it changes anything (a ``ValueError`` leaves the figure as it
    was) and returns ``None``, or ``False`` when these values need a new figure.
    :func:`xnavlab.core.widgets.explore` updates a figure that has one instead of calling the
    function again. Write the plotting function as ``build`` (the parts every frame shares),
    then ``update(**values)``, then ``return in_place(fig, update)``: a frame drawn from
    nothing and a frame updated in place then run the same code.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    update : callable
        ``update(**values) -> None | False``.

    Returns
    -------
    matplotlib.figure.Figure
        ``fig``, with attribute :data:`UPDATE_ATTR` set to ``update``.

    Examples
    --------
    >>> fig, ax = figure()
    >>> line, = ax.plot([0.0, 1.0], [0.0, 1.0])
    >>> def update(slope=1.0):
    ...     line.set_ydata([0.0, slope])
    >>> fig = in_place(fig, update)
    >>> updater(fig)(slope=2.0)
    >>> [float(y) for y in line.get_ydata()]
    [0.0, 2.0]
    """
    setattr(fig, UPDATE_ATTR, update)
    return fig


def updater(fig):
    """The in-place update :func:`in_place` gave ``fig``, or ``None``.

    Examples
    --------
    >>> fig, ax = figure()
    >>> updater(fig) is None
    True
    """
    return getattr(fig, UPDATE_ATTR, None)


def sparse_log_minors(*axes):
    """Minor ticks at 2 and 5 of each decade on every log-scaled axis of ``axes``.

    Matplotlib puts them at 2, 3, ..., 9 by default: eight marks a decade, each a tick of
    five artists that every new figure makes and draws. A slider's figure with log axes over
    several decades renders in about half the time with two a decade (chapter 2's Shapiro
    figure: 1.1 s a frame with eight, 0.6 s with two), and each decade still shows its 2
    and 5. Child axes (a ``secondary_yaxis``) are included; call it after they are made.

    Parameters
    ----------
    *axes : matplotlib.axes.Axes
        Axes whose log-scaled x and y axes get the sparse minor ticks (others are left); each
        a 2-D rectilinear Axes of a figure (:func:`check_axes`), else one ValueError naming
        ``axes[i]``.

    Examples
    --------
    >>> fig, ax = figure()
    >>> _ = ax.set(xscale="log", xlim=(1.0, 1e3))
    >>> sparse_log_minors(ax)
    >>> [float(v) for v in ax.xaxis.get_minorticklocs() if 1.0 < v < 1e3]
    [2.0, 5.0, 20.0, 50.0, 200.0, 500.0]
    """
    from matplotlib.ticker import LogLocator

    for i, ax in enumerate(axes):
        check_axes(f"axes[{i}]", ax)
        for part in (ax, *ax.child_axes):
            for axis in (part.xaxis, part.yaxis):
                if axis.get_scale() in ("log", "functionlog"):
                    axis.set_minor_locator(LogLocator(subs=LOG_MINOR_SUBS))


def format_cell(v, digits=4):
    """The text of one table cell: ``None`` as ``-``, floats to ``digits`` significant digits.

    Parameters
    ----------
    v : object
        The value.
    digits : int
        Significant digits of floats, 1..17.

    Returns
    -------
    str

    Examples
    --------
    >>> format_cell(2.0 / 3.0, 3), format_cell(None), format_cell("a|b")
    ('0.667', '-', 'a|b')
    """
    digits = check_int("digits", digits, 1, 17)
    if v is None:
        return "-"
    return f"{v:.{digits}g}" if isinstance(v, float) else str(v)


def _check_rows(rows, cols):
    for i, r in enumerate(rows):
        if isinstance(r, Mapping):
            missing = [c for c in cols if c not in r]
            if missing:
                raise ValueError(f"rows: every row must hold the columns {list(cols)}; "
                                 f"missing {missing}")
        elif len(r) != len(cols):
            raise ValueError(f"rows: every row must have {len(cols)} cells (one per column); "
                             f"got {len(r)}")
        for c, v in zip(cols, _cells(r, cols), strict=True):
            # a table the reader sees shows no "nan": a missing value is None, printed "-"
            if isinstance(v, (float, np.floating)) and not math.isfinite(v):
                raise ValueError(f"rows[{i}][{c!r}] is {v}: a table cell must be finite "
                                 "(give None for a missing value, shown as -)")


def _cells(row, cols):
    return [row[c] for c in cols] if isinstance(row, Mapping) else list(row)


def _md_escape(text):
    # a "|" would end the cell and a newline the row: escape the one, flatten the other
    return " ".join(text.replace("\\|", "|").replace("|", "\\|").split())


def markdown_table(rows, cols, digits=4):
    """Rows as a Markdown table (a chapter displays it with ``IPython.display.Markdown``).

    Every cell (header too) is escaped so that its content cannot split the table: ``|``
    becomes ``\\|`` and newlines become spaces. Inside math a bar is better written
    ``\\lvert x \\rvert``; or use :func:`html_table`.

    Parameters
    ----------
    rows : sequence of dict or of sequence
        One dict per row holding every name of ``cols``, or one sequence of
        ``len(cols)`` cells per row.
    cols : sequence of str
        Column names, in order (also the header).
    digits : int
        Significant digits of floats, 1..17; ``None`` prints as ``-``. A NaN or infinite
        cell is refused (``ValueError`` naming its row and column).

    Returns
    -------
    str

    Examples
    --------
    >>> print(markdown_table([{"a": 1, "b": 0.123456}, {"a": "x|y", "b": None}], ["a", "b"], 3))
    | a | b |
    |---|---|
    | 1 | 0.123 |
    | x\\|y | - |
    <BLANKLINE>
    """
    digits = check_int("digits", digits, 1, 17)
    _check_rows(rows, cols)
    head = "| " + " | ".join(_md_escape(str(c)) for c in cols) + " |\n|" + "---|" * len(cols) + "\n"
    return head + "".join(
        "| " + " | ".join(_md_escape(format_cell(v, digits)) for v in _cells(r, cols)) + " |\n"
        for r in rows
    )


class SafeHTML(str):
    """HTML text that a notebook displays as HTML (``_repr_html_``); it is still a ``str``."""

    def _repr_html_(self):
        return str(self)


def html_table(header, rows, digits=4, css_class="table xnav-table"):
    """Rows as an HTML table in which every cell is escaped text.

    No content can break the table: ``<``, ``>``, ``&`` and quotes are escaped, a ``|`` is
    plain text, and every row has exactly one ``<td>`` per column.

    Parameters
    ----------
    header : sequence of str
        Column names, in order.
    rows : sequence of dict or of sequence
        One dict per row holding every name of ``header``, or one sequence of
        ``len(header)`` cells per row.
    digits : int
        Significant digits of floats, 1..17; ``None`` prints as ``-``.
    css_class : str
        Class of the ``<table>`` element (``table``: styled like the book's other tables).
        The table sits in a ``<div>`` that scrolls sideways when the page is too narrow.

    Returns
    -------
    SafeHTML
        A ``str`` that a notebook displays as the table.

    Examples
    --------
    >>> print(html_table(["a", "b"], [[1, "x|<y>"]]))
    <div class="pst-scrollable-table-container"><table class="table xnav-table">
    <thead><tr><th>a</th><th>b</th></tr></thead>
    <tbody>
    <tr><td>1</td><td>x|&lt;y&gt;</td></tr>
    </tbody>
    </table></div>
    """
    digits = check_int("digits", digits, 1, 17)
    _check_rows(rows, header)

    def td(tag, v):
        text = html.escape(format_cell(v, digits) if tag == "td" else str(v))
        return f"<{tag}>{text}</{tag}>"

    lines = ['<div class="pst-scrollable-table-container">'
             f'<table class="{html.escape(css_class)}">',
             "<thead><tr>" + "".join(td("th", c) for c in header) + "</tr></thead>", "<tbody>"]
    lines += ["<tr>" + "".join(td("td", v) for v in _cells(r, header)) + "</tr>" for r in rows]
    lines += ["</tbody>", "</table></div>"]
    return SafeHTML("\n".join(lines))
