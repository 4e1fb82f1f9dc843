"""Why a stored run's metrics are not a campaign's (the campaigns' ``check_metrics``).

A spec maps each key the summary reads to its kind: ``"real"`` (a finite number, not a
bool), ``"real?"`` (that or null: a non-finite value is stored as null), ``"count"`` (an
integer >= 0), ``"bool"``, ``("list", n, kind)`` (a list of ``n`` items, ``None`` any
length), ``("map", kind)`` (a table of items of that kind) or a nested spec (a dict).
"""

from __future__ import annotations

import math

__all__ = ["why_not"]


def _why_item(value, kind, where):
    if isinstance(kind, dict):
        return why_not(value, kind, where)
    if isinstance(kind, tuple) and kind[0] == "list":
        if not isinstance(value, list):
            return f"{where} is not a list"
        if kind[1] is not None and len(value) != kind[1]:
            return f"{where} holds {len(value)} items, not {kind[1]}"
        for i, v in enumerate(value):
            why = _why_item(v, kind[2], f"{where}[{i}]")
            if why:
                return why
        return None
    if isinstance(kind, tuple) and kind[0] == "map":
        if not isinstance(value, dict):
            return f"{where} is not a table"
        for k, v in value.items():
            why = _why_item(v, kind[1], f"{where}.{k}")
            if why:
                return why
        return None
    if kind == "bool":
        return None if isinstance(value, bool) else f"{where} is {value!r}, not true or false"
    if kind == "count":
        ok = isinstance(value, int) and not isinstance(value, bool) and value >= 0
        return None if ok else f"{where} is {value!r}, not an integer >= 0"
    if kind == "real?" and value is None:
        return None
    ok = (isinstance(value, int | float) and not isinstance(value, bool)
          and math.isfinite(value))
    return None if ok else f"{where} is {value!r}, not a finite number"


def why_not(metrics, spec, where=""):
    """Why ``metrics`` does not hold ``spec`` (the first key at fault, dotted), else None."""
    if not isinstance(metrics, dict):
        return f"{where or 'metrics'} is not a table"
    for key, kind in spec.items():
        place = f"{where}.{key}" if where else key
        if key not in metrics:
            return f"{place} is missing"
        why = _why_item(metrics[key], kind, place)
        if why:
            return why
    return None
