"""What an array of numbers may not hold: the item kinds that
:func:`xnavlab.core.validate.check_finite_array` refuses rather than converts.

A bool among numbers (``np.asarray`` makes it 1.0), text, complex numbers (a cast drops the
imaginary part), masked entries, dates and durations (``datetime64``/``timedelta64``, which
``astype(float)`` turns into counts of their own tick since 1970) and quantities that carry a
unit (astropy's ``Quantity``, read as its number in its own unit: 90 deg as 90 rad, a day as
1 s). Every item of an object array and of a (nested) list is looked at, not a sample.

Plumbing of :mod:`xnavlab.core.validate` (which words the refusals); not part of the public API.
"""

from __future__ import annotations

import datetime
import re
import warnings
from decimal import Decimal

import numpy as np

__all__ = ["as_array", "odd_item", "item_kinds", "carries_unit", "unit_refusal", "one_line",
           "decimal_note"]

#: Item types whose kind is read item by item in an object array (a container's or an int's
#: kind depends on its content or size); any other type by its first item.
_BY_ITEM = (np.ndarray, list, tuple, int)


def carries_unit(value):
    """Whether ``value`` is a quantity with a unit (astropy's ``.unit``; pint's ``.units`` and
    ``.magnitude``), whose number alone is in that unit, not in the SI unit a function documents.

    Examples
    --------
    >>> carries_unit(np.ones(3)), carries_unit(3.0)
    (False, False)
    """
    if isinstance(value, datetime.date | datetime.timedelta) or \
            getattr(getattr(value, "dtype", None), "kind", "") in ("M", "m"):
        return False  # pandas' dates and durations: their .unit is their tick (a date, refused too)
    return hasattr(value, "unit") or hasattr(value, "units") and hasattr(value, "magnitude")


def as_array(value):
    """``np.asarray(value)``, or None for a quantity with a unit (its array would drop the unit)
    or a value that is no array (a ragged list).

    Examples
    --------
    >>> as_array([1.0, 2.0]).dtype, as_array([[1.0], [2.0, 3.0]]) is None
    (dtype('float64'), True)
    """
    if carries_unit(value):
        return None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", np.exceptions.VisibleDeprecationWarning)
            return np.asarray(value)
    except (TypeError, ValueError):
        return None


def odd_item(value):
    """``"masked"`` if a (nested) list or tuple holds a masked entry, else ``"unit"`` if a
    quantity with a unit, else ``"bool"`` if a bool, else None.

    Examples
    --------
    >>> odd_item([1.0, [2.0, True]]), odd_item([1.0, 2.0]) is None
    ('bool', True)
    """
    odd = set()
    for v in value:
        if isinstance(v, list | tuple):
            odd.add(odd_item(v))
        elif isinstance(v, bool | np.bool_):
            odd.add("bool")
        elif isinstance(v, np.ma.MaskedArray) and np.ma.is_masked(v):
            odd.add("masked")
        elif carries_unit(v):
            odd.add("unit")
    return next((k for k in ("masked", "unit", "bool") if k in odd), None)


def item_kinds(raw):
    """The dtype kinds (``"f"``, ``"b"``, ``"M"``...) of ``raw``'s items: its dtype's kind, or
    for an object array every item's (``"unit"`` for a quantity with a unit).

    Examples
    --------
    >>> sorted(item_kinds(np.array([0.5] * 10_001 + [True], dtype=object)))
    ['b', 'f']
    """
    if raw.dtype.kind != "O":
        return {raw.dtype.kind}
    flat = raw.ravel()
    kinds = set()
    for kind in set(map(type, flat)):
        items = [v for v in flat if type(v) is kind] if kind in _BY_ITEM else \
            [next(v for v in flat if type(v) is kind)]
        kinds.update(map(_kind, items))
    return kinds


def _kind(item):
    """One item's dtype kind, ``"unit"`` for a quantity with a unit (``"O"``: no array of numbers)."""
    if carries_unit(item):
        return "unit"
    if isinstance(item, datetime.date | datetime.timedelta):  # pandas' Timestamp and Timedelta too
        return "m" if isinstance(item, datetime.timedelta) else "M"
    try:
        return np.asarray(item).dtype.kind
    except (TypeError, ValueError):  # a ragged list inside the array
        return "O"


def unit_refusal(name, value, raw, unit=None):
    """The one-line refusal of dates, durations or a quantity with a unit where plain numbers
    in ``unit`` belong (``None`` when ``value``, as the array ``raw``, is none of them).

    Parameters
    ----------
    name : str
        The parameter, for the message.
    value : object
        What the user gave (a quantity, or a list holding one).
    raw : ndarray or None
        ``value`` as an array (None when it did not convert).
    unit : str, optional
        The unit the parameter documents (``"s TDB past J2000"``); by default "the SI unit its
        function documents".

    Examples
    --------
    >>> print(unit_refusal("t", None, np.array([1, 2], dtype="timedelta64[ms]"), "s"))  # doctest: +ELLIPSIS
    t must be plain numbers in s, got timedelta64[ms] values: convert them (t / np.timedelta64(1, 's') ...
    """
    want = f"{name} must be plain numbers in {unit or 'the SI unit its function documents'}"
    if (item := _with_unit(value)) is not None:
        got = str(getattr(item, "unit", getattr(item, "units", "")))
        what = f"a {type(item).__name__} in {got}" if got else f"a dimensionless {type(item).__name__}"
        return f"{want}, got {what}: its unit is not read; convert it ({name}.si.value gives SI numbers)"
    kinds = item_kinds(raw) if raw is not None else set()
    got = raw.dtype if raw is not None and raw.dtype.kind in "Mm" else None
    if "M" in kinds:
        return (f"{want}, got {got or 'date'} values: a date is no number; convert it (to s TDB "
                f"past J2000: xnavlab.core.ephemeris.t_from_jd(astropy.time.Time({name}).tdb.jd))")
    if "m" in kinds:
        return (f"{want}, got {got or 'duration'} values: convert them ({name} / "
                f"np.timedelta64(1, 's') gives seconds)")
    return None


def _with_unit(value):
    """``value`` if it carries a unit, else the first item of a (nested) list or an object
    array that does, else None."""
    if carries_unit(value):
        return value
    if isinstance(value, np.ndarray) and value.dtype.kind == "O":
        value = value.ravel().tolist()
    if isinstance(value, list | tuple):
        return next((w for v in value if (w := _with_unit(v)) is not None), None)
    return None


def one_line(text):
    """``text`` with each line break and the indentation around it made one space (a repr of a
    SeedSequence or of a 2-D array spans lines; a message is one line).

    Examples
    --------
    >>> one_line("SeedSequence(\\n    entropy=0,\\n)")
    'SeedSequence( entropy=0, )'
    """
    return re.sub(r"\s*\n\s*", " ", text)


def decimal_note(value, cast):
    """Why a ``Decimal`` is refused where a number is wanted, else ``""``: the end of the
    refusal's line (review 35 R16: "must be a real number, got Decimal('0.02')" was untrue).

    A Decimal is not a ``numbers.Real`` and mixes with no float (``Decimal * float`` is a
    TypeError), and the checks' callers may keep the value they checked: it is refused, not
    converted (a ``Fraction`` is a ``numbers.Real`` and works with floats).

    Examples
    --------
    >>> decimal_note(Decimal("0.02"), "float")
    ': a Decimal is not taken (pass float(value))'
    >>> decimal_note("0.02", "float")
    ''
    """
    return f": a Decimal is not taken (pass {cast}(value))" if isinstance(value, Decimal) else ""
