"""The parameter grids of :func:`xnavlab.core.widgets.explore`: checked, ordered, looked up.

Plumbing of the sliders (:mod:`xnavlab.core.widgets`), not meant for readers. A grid is a
list, tuple, range or 1-D array of values, each one position of a control:

- :func:`grid_values` checks a grid in time linear in its length (up to the sort of its
  numbers): not empty, no value unequal to itself (a NaN of any type), no value twice (equal,
  or two real numbers within a relative 1e-9). A grid of real numbers (no bool) is put in
  increasing order, so that its slider moves one way; any other grid keeps the order given.
- :func:`grid_index` finds a value's position by the same equality.
- :func:`grid_label` is the text a control or a frame shows for a value.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from numbers import Real

import numpy as np

__all__ = ["RTOL", "is_grid", "grid_values", "grid_index", "grid_label"]

#: Two real grid values closer than this, relative to the larger, are one position.
RTOL = 1e-9


def is_grid(value):
    """Whether ``value`` is given as a grid (a list, tuple, range, array or iterator).

    Examples
    --------
    >>> is_grid([1.0, 2.0]), is_grid(1.0)
    (True, False)
    """
    return isinstance(value, list | tuple | range | np.ndarray | Iterator)


def _real(v):
    """A real number that is not a bool (the values a grid orders)."""
    if type(v) is float or type(v) is int:  # the usual case, without the ABC's slow check
        return True
    return isinstance(v, Real) and not isinstance(v, bool | np.bool_)


def _close(a, b):
    """``a == b``, or two finite reals within a relative :data:`RTOL` of the larger."""
    if a == b:
        return True
    try:
        a, b = float(a), float(b)
    except (OverflowError, TypeError, ValueError):  # an int beyond float: only ==
        return False
    return math.isfinite(a) and math.isfinite(b) and abs(a - b) <= RTOL * max(abs(a), abs(b))


def _unequal_to_itself(v):
    """A NaN of any type (float, complex, Decimal); a signalling one raises on comparison."""
    if isinstance(v, np.ndarray):
        return False
    try:
        unequal = v != v
    except ArithmeticError:  # Decimal("sNaN")
        return True
    return isinstance(unequal, bool | np.bool_) and bool(unequal)


def _repeat(values):
    """``(j, i)``, the first value ``i`` that repeats an earlier value ``j``, or ``None``."""
    pairs = []
    seen, loose = {}, []  # hashable values by (is a bool, value); the unhashable ones
    for i, v in enumerate(values):
        try:
            j = seen.setdefault((isinstance(v, bool | np.bool_), v), i)
        except TypeError:  # unhashable (an array, a list): compared with the few others
            j = grid_index([values[k] for k in loose], v, None)
            j = i if j is None else loose[j]
            loose.append(i)
        if j != i:
            pairs.append((i, j))
            break
    reals = sorted((i for i, v in enumerate(values) if _real(v)), key=lambda i: values[i])
    pairs += [(max(a, b), min(a, b)) for a, b in zip(reals, reals[1:], strict=False)
              if _close(values[a], values[b])]
    return None if not pairs else min(pairs)[::-1]


def grid_values(name, value):
    """The grid ``name`` as a list of plain values: 1-D, not empty, no NaN, no value twice.

    Parameters
    ----------
    name : str
        The parameter, for the messages.
    value : list, tuple, range or 1-D numpy.ndarray
        Its values; numpy scalars become plain Python ones (what the plotting function gets).

    Returns
    -------
    list
        The values; real numbers (a grid of nothing else) in increasing order.

    Raises
    ------
    ValueError
        Not a grid, an empty one, a value unequal to itself (``name[i] is NaN``), or a value
        given twice (``name[i] is name[j] again``), naming ``name``.

    Examples
    --------
    >>> grid_values("omega", [3.0, 1.0, 2.0]), grid_values("kind", ["step", "ramp"])
    ([1.0, 2.0, 3.0], ['step', 'ramp'])
    >>> grid_values("omega", [1.0, 2.0, 1.0 + 1e-12])
    Traceback (most recent call last):
    ...
    ValueError: omega[2] is omega[0] again (1): each grid value must be one position
    """
    if isinstance(value, Iterator) or isinstance(value, np.ndarray) and value.ndim != 1:
        got = f"shape {value.shape}" if isinstance(value, np.ndarray) else type(value).__name__
        raise ValueError(f"{name} must be a grid (a list, tuple, range or 1-D array) or one value "
                         f"passed through, got {got} (write a list, or use functools.partial)")
    values = [v.item() if isinstance(v, np.generic) else v for v in value]  # plot gets plain ones
    if not values:
        raise ValueError(f"{name} is an empty grid; give at least one value")
    for i, v in enumerate(values):
        if _unequal_to_itself(v):
            raise ValueError(f"{name}[{i}] is NaN: each grid value must be one position")
    pair = _repeat(values)
    if pair is not None:
        j, i = pair
        raise ValueError(f"{name}[{i}] is {name}[{j}] again ({grid_label(values[i])}): each grid "
                         f"value must be one position")
    return sorted(values) if all(_real(v) for v in values) else values


def grid_label(value):
    """The text shown for a grid value: a float to 4 significant digits, else its ``str``.

    Examples
    --------
    >>> grid_label(2.0 / 3.0), grid_label("step")
    ('0.6667', 'step')
    """
    if isinstance(value, float | np.floating):
        return f"{float(value):.4g}"
    if isinstance(value, np.generic):
        return str(value.item())
    return str(value)


def grid_index(grid, value, name="value"):
    """Index of ``value`` in ``grid`` (real numbers within a relative :data:`RTOL`, a bool
    only as a bool, arrays entry by entry); ``name`` None: None if absent.

    Raises
    ------
    ValueError
        ``value`` not in ``grid`` (``name`` given), naming ``name`` and the grid's values.

    Examples
    --------
    >>> grid_index([1.0, 2.0], 2.0 + 1e-12), grid_index([1.0, 2.0], 3.0, None)
    (1, None)
    """
    flag, real, array = isinstance(value, bool | np.bool_), _real(value), isinstance(value, np.ndarray)
    for i, g in enumerate(grid):
        if array or isinstance(g, np.ndarray):
            if np.array_equal(g, value):
                return i
        elif isinstance(g, bool | np.bool_) == flag and (
                g == value or real and _real(g) and _close(g, value)):
            return i
    if name is not None:
        raise ValueError(f"{name} must be one of its grid values "
                         f"{[grid_label(g) for g in grid]}, got {value!r}")
    return None
