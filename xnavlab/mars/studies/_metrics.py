"""Why a stored run's metrics are not a campaign's (the campaigns' ``check_metrics``).

A spec maps each key the summary reads to its kind: ``"real"`` (a finite number, not a
bool, of magnitude at most :data:`CEILING`), ``"real>0"`` (in (0, CEILING]), ``"real>=0"``
(in [0, CEILING]), a kind ending in ``"?"`` (that or null: a non-finite value is stored as
null), ``"count"`` (an integer in [0, :data:`COUNT_MAX`]), ``"count>=1"`` (in [1,
COUNT_MAX]), ``"bool"``, ``("list", n, kind)`` (a list of ``n`` items, ``None`` any length,
``-1`` at least one), ``("map", kind)`` (a table of items of that kind) or a nested spec
(a dict).

The ceiling keeps the summaries' sums and squares (means, standard deviations over runs)
finite; the count bound keeps a sum of counts inside the Poisson interval's range.
"""

from __future__ import annotations

import math

__all__ = ["CEILING", "COUNT_MAX", "why_not", "refuse"]

#: Largest magnitude of a stored real metric (its square, summed over runs, stays finite).
CEILING = 1e100
#: Largest stored count (a sum over 500 runs stays inside poisson_interval's 5e11).
COUNT_MAX = 10**9

_REAL = {"real": (-CEILING, False), "real>0": (0.0, True), "real>=0": (0.0, False)}


def _place(where, key, brackets):
    if brackets:
        return f"{where}[{key!r}]" if where else repr(key)
    return f"{where}.{key}" if where else str(key)


def _why_item(value, kind, where, brackets=False):
    if isinstance(kind, dict):
        return why_not(value, kind, where, brackets)
    if isinstance(kind, tuple) and kind[0] == "list":
        if not isinstance(value, list):
            return f"{where} is not a list"
        if kind[1] == -1 and not value:
            return f"{where} is empty, not a list of at least one item"
        if kind[1] not in (None, -1) and len(value) != kind[1]:
            return f"{where} holds {len(value)} items, not {kind[1]}"
        for i, v in enumerate(value):
            why = _why_item(v, kind[2], f"{where}[{i}]", brackets)
            if why:
                return why
        return None
    if isinstance(kind, tuple) and kind[0] == "map":
        if not isinstance(value, dict):
            return f"{where} is not a table"
        for k, v in value.items():
            why = _why_item(v, kind[1], _place(where, k, brackets), brackets)
            if why:
                return why
        return None
    if kind == "bool":
        return None if isinstance(value, bool) else f"{where} is {value!r}, not true or false"
    if kind in ("count", "count>=1"):
        lo = 1 if kind == "count>=1" else 0
        ok = (isinstance(value, int) and not isinstance(value, bool)
              and lo <= value <= COUNT_MAX)
        return None if ok else f"{where} is {value!r}"[:200] + f", not an integer in [{lo}, {COUNT_MAX:.0e}]"
    if kind.endswith("?"):
        if value is None:
            return None
        kind = kind[:-1]
    lo, lo_open = _REAL[kind]
    ok = (isinstance(value, int | float) and not isinstance(value, bool)
          and math.isfinite(value) and (lo < value if lo_open else lo <= value)
          and value <= CEILING)
    if ok:
        return None
    if not (isinstance(value, int | float) and not isinstance(value, bool)
            and math.isfinite(value)):
        return f"{where} is {value!r}"[:200] + ", not a finite number"
    left = "(" if lo_open else "["
    return f"{where} is {value!r}"[:200] + f", not a number in {left}{lo:g}, {CEILING:g}]"


def why_not(metrics, spec, where="", brackets=False):
    """Why ``metrics`` does not hold ``spec`` (the first key at fault, dotted, or as
    ``where['key']`` with ``brackets``), else None."""
    if not isinstance(metrics, dict):
        return f"{where or 'metrics'} is not a table"
    for key, kind in spec.items():
        place = _place(where, key, brackets)
        if key not in metrics:
            return f"{place} is missing"
        why = _why_item(metrics[key], kind, place, brackets)
        if why:
            return why
    return None


def refuse(value, spec, where):
    """One ValueError for the first entry of ``value`` (named ``where['key']...``) that does
    not hold ``spec``; ``value`` itself when all do."""
    why = why_not(value, spec, where, brackets=True)
    if why is not None:
        raise ValueError(why)
    return value
