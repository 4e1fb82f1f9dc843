"""The records of a campaign store (``runs.jsonl``): what a record is, and reading them.

One line of the store is one run's record, a JSON object with at least :data:`PUBLIC_KEYS`.
A line that is not one (torn by a kill, edited by hand) is reported by its line number and
its run computed again (:mod:`xnavlab.core.campaign`), never dropped in silence.
"""

from __future__ import annotations

import json
import warnings

from xnavlab.core.userfiles import InputWarning

__all__ = ["PUBLIC_KEYS", "json_or_none", "why_not_a_record", "parse_records", "report_bad_lines"]

#: Keys of a record that make up a run's result (the rest is bookkeeping).
PUBLIC_KEYS = ("index", "seed", "parameters", "metrics", "status", "error")


def json_or_none(text):
    """The JSON value of ``text``, or None when it is not JSON (a line torn by a kill).

    Examples
    --------
    >>> json_or_none('{"a": 1}'), json_or_none('{"a"')
    ({'a': 1}, None)
    """
    try:
        return json.loads(text)
    except json.JSONDecodeError:
        return None


def why_not_a_record(rec):
    """Why a parsed line is not a campaign record (None when it is one).

    Examples
    --------
    >>> why_not_a_record([1, 2])
    'not a JSON object'
    """
    if rec is None:
        return "not JSON"
    if not isinstance(rec, dict):
        return "not a JSON object"
    missing = [k for k in PUBLIC_KEYS if k not in rec]
    if missing:
        return "no " + ", ".join(missing)
    if isinstance(rec["index"], bool) or not isinstance(rec["index"], int) or rec["index"] < 0:
        return f"index {rec['index']!r} is not an integer >= 0"
    if isinstance(rec["seed"], bool) or not isinstance(rec["seed"], int):
        return f"seed {rec['seed']!r} is not an integer"
    if rec["status"] not in ("ok", "failed"):
        return f"status {rec['status']!r} is neither 'ok' nor 'failed'"
    for key in ("parameters", "metrics"):
        if rec[key] is not None and not isinstance(rec[key], dict):
            return f"{key} is not a table"
    return None


def parse_records(lines, first=0):
    """The campaign records among the lines of ``runs.jsonl``, and the lines that are not.

    Parameters
    ----------
    lines : list of str
        The file's lines (blank ones are skipped).
    first : int
        Lines before ``lines[0]`` in the file (for the line numbers).

    Returns
    -------
    records : list of dict
    bad : list of (int, str)
        ``(line number, why)`` of every line that is not a record: not JSON (a line torn by a
        kill), not an object, a key missing, or a key of the wrong kind.

    Examples
    --------
    >>> rec = '{"index": 0, "seed": 1, "parameters": {}, "metrics": {}, "status": "ok", "error": null}'
    >>> recs, bad = parse_records([rec, '{"index": 1', rec.replace("ok", "done")])
    >>> len(recs), bad
    (1, [(2, 'not JSON'), (3, "status 'done' is neither 'ok' nor 'failed'")])
    """
    records, bad = [], []
    for n, line in enumerate(lines, first + 1):
        if not line.strip():
            continue
        rec = json_or_none(line)
        why = why_not_a_record(rec)
        if why is None:
            records.append(rec)
        else:
            bad.append((n, why))
    return records, bad


def report_bad_lines(bad, path, then):
    """One warning naming the file and each line that is not a record (the first ten)."""
    shown = "; ".join(f"line {n} ({why})" for n, why in bad[:10])
    more = f"; and {len(bad) - 10} more" if len(bad) > 10 else ""
    warnings.warn(f"{path}: {len(bad)} line{'s' if len(bad) > 1 else ''} not read as campaign "
                  f"records, {then}: {shown}{more}", InputWarning, stacklevel=3)
