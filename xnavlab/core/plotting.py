"""Figures outside pyplot, and Markdown tables, for reproductions, chapters and the CLI.

A bare :class:`matplotlib.figure.Figure` needs no backend, so writing a figure never
switches the backend of a running notebook kernel and leaves no open pyplot figure.
"""

from __future__ import annotations

from xnavlab.core.validate import check_int

__all__ = ["figure", "markdown_table"]


def figure(*args, figsize=(6.0, 3.5), **kwargs):
    """A figure for a reproduction's PNG: like ``pyplot.subplots`` but outside pyplot.

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
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize)
    return fig, fig.subplots(*args, **kwargs)


def markdown_table(rows, cols, digits=4):
    """Rows of dicts as a Markdown table (a chapter displays it with ``IPython.display.Markdown``).

    Parameters
    ----------
    rows : sequence of dict
        One dict per row; each must hold every name of ``cols``.
    cols : sequence of str
        Column names, in order (also the header).
    digits : int
        Significant digits of floats, 1..17; ``None`` prints as ``-``.

    Returns
    -------
    str

    Examples
    --------
    >>> print(markdown_table([{"a": 1, "b": 0.123456}, {"a": 2, "b": None}], ["a", "b"], 3))
    | a | b |
    |---|---|
    | 1 | 0.123 |
    | 2 | - |
    <BLANKLINE>
    """
    digits = check_int("digits", digits, 1, 17)

    def cell(v):
        if v is None:
            return "-"
        return f"{v:.{digits}g}" if isinstance(v, float) else str(v)

    head = "| " + " | ".join(cols) + " |\n|" + "---|" * len(cols) + "\n"
    for r in rows:
        missing = [c for c in cols if c not in r]
        if missing:
            raise ValueError(f"rows: every row must hold the columns {list(cols)}; missing {missing}")
    return head + "".join("| " + " | ".join(cell(r[c]) for c in cols) + " |\n" for r in rows)
