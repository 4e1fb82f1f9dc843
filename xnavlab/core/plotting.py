"""Figures outside pyplot, for reproductions, chapters and the CLI.

A bare :class:`matplotlib.figure.Figure` needs no backend, so writing a figure never
switches the backend of a running notebook kernel and leaves no open pyplot figure.
"""

from __future__ import annotations

__all__ = ["figure"]


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
