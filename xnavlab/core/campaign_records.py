"""The records of a campaign store (``runs.jsonl``): what a record is, and reading them.

One line of the store is one run's record, a JSON object with at least :data:`PUBLIC_KEYS`
(an ``ok`` run with its metrics and a null ``error``, a ``failed`` one with its error text and
null metrics). A line that is not one (torn by a kill, edited by hand) is never dropped in
silence: a campaign reports it in one warning naming the file and the line and computes its
run again (:class:`xnavlab.core.campaign.Store`; a torn last line is also cut off), and
:func:`xnavlab.core.campaign.load_runs` reports it and leaves it out of its table.
"""

from __future__ import annotations

import json
import math
import sys
import warnings

from xnavlab.core.userfiles import InputWarning
from xnavlab.core.validate import SEED_MAX, shown

__all__ = ["PUBLIC_KEYS", "json_or_none", "non_finite", "why_not_a_record", "parse_records",
           "report_bad_lines", "report_disagreements", "given_warnings", "warn_again"]

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


def non_finite(value, where=""):
    """The dotted place of the first NaN or infinity in a parsed JSON value, else None.

    Python's ``json`` reads ``NaN`` and ``Infinity``; a campaign writes neither (non-finite
    metrics are stored as ``null``), so a record holding one was not written by a campaign.

    Examples
    --------
    >>> non_finite({"metrics": {"nees_bins": [1.0, float("nan")]}})
    'metrics.nees_bins[1]'
    """
    if isinstance(value, float) and not math.isfinite(value):
        return where or "value"
    if isinstance(value, dict):
        items = ((f"{where}.{k}" if where else str(k), v) for k, v in value.items())
    elif isinstance(value, list):
        items = ((f"{where}[{i}]", v) for i, v in enumerate(value))
    else:
        return None
    for place, v in items:
        found = non_finite(v, place)
        if found is not None:
            return found
    return None


def why_not_a_record(rec, check=None):
    """Why a parsed line is not a campaign record (None when it is one).

    ``check`` (optional): the campaign's ``check_metrics(metrics) -> None or why``, applied
    to the metrics of an ``ok`` record (a record whose metrics its summary cannot use is not
    a record of that campaign).

    Examples
    --------
    >>> why_not_a_record([1, 2])
    'not a JSON object'
    >>> why_not_a_record({"index": 0, "seed": 1, "parameters": {}, "metrics": {"a": float("inf")},
    ...                   "status": "ok", "error": None})
    'metrics.a is not a finite number (a campaign writes none)'
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
    if not 0 <= rec["seed"] <= SEED_MAX:  # no run draws from a seed out of range
        return f"seed {rec['seed']} is not in [0, {SEED_MAX}]"
    if rec["status"] not in ("ok", "failed"):
        return f"status {rec['status']!r} is neither 'ok' nor 'failed'"
    for key in ("parameters", "metrics"):
        if rec[key] is not None and not isinstance(rec[key], dict):
            return f"{key} is not a table"
    # a campaign writes an ok run with its metrics and a null error, a failed one the other
    # way round: a record with both (or neither) is no run's result
    if rec["error"] is not None and not isinstance(rec["error"], str):
        return f"error {shown(rec['error'])} is neither null nor a text"
    if rec["status"] == "ok" and (rec["error"] is not None or rec["metrics"] is None):
        return ("status 'ok' with an error " + shown(rec["error"]) if rec["error"] is not None
                else "status 'ok' without metrics")
    if rec["status"] == "failed" and (not rec["error"] or rec["metrics"] is not None):
        return ("status 'failed' with metrics" if rec["metrics"] is not None
                else "status 'failed' without its error")
    bad = non_finite({k: rec[k] for k in PUBLIC_KEYS})
    if bad is not None:
        return f"{bad} is not a finite number (a campaign writes none)"
    if check is not None and rec["status"] == "ok":
        why = check(rec["metrics"])
        if why is not None:
            return f"metrics: {why}"
    return None


def parse_records(lines, first=0, numbers=False, check=None):
    """The campaign records among the lines of ``runs.jsonl``, and the lines that are not.

    Parameters
    ----------
    lines : list of str
        The file's lines (blank ones are skipped).
    first : int
        Lines before ``lines[0]`` in the file (for the line numbers).
    numbers : bool
        Also return the line number of each record (for :func:`report_disagreements`).
    check : callable, optional
        The campaign's metrics check (:func:`why_not_a_record`).

    Returns
    -------
    records : list of dict
    bad : list of (int, str)
        ``(line number, why)`` of every line that is not a record: not JSON (a line torn by a
        kill), not an object, a key missing, a key of the wrong kind, a NaN or infinity, or
        metrics that ``check`` refuses.
    lines : list of int
        With ``numbers=True`` only: the line number of each record.

    Examples
    --------
    >>> rec = '{"index": 0, "seed": 1, "parameters": {}, "metrics": {}, "status": "ok", "error": null}'
    >>> recs, bad = parse_records([rec, '{"index": 1', rec.replace("ok", "done")])
    >>> len(recs), bad
    (1, [(2, 'not JSON'), (3, "status 'done' is neither 'ok' nor 'failed'")])
    """
    records, bad, where = [], [], []
    for n, line in enumerate(lines, first + 1):
        if not line.strip():
            continue
        rec = json_or_none(line)
        why = why_not_a_record(rec, check)
        if why is None:
            records.append(rec)
            where.append(n)
        else:
            bad.append((n, why))
    return (records, bad, where) if numbers else (records, bad)


def report_bad_lines(bad, path, then):
    """One warning naming the file and each line that is not a record (the first ten)."""
    shown = "; ".join(f"line {n} ({why})" for n, why in bad[:10])
    more = f"; and {len(bad) - 10} more" if len(bad) > 10 else ""
    warnings.warn(f"{path}: {len(bad)} line{'s' if len(bad) > 1 else ''} not read as campaign "
                  f"records, {then}: {shown}{more}", InputWarning, stacklevel=3)


def report_disagreements(records, numbers, path):
    """One warning naming every run with two ``ok`` records that disagree, by line number.

    A store holds one ``ok`` record per run (a run that succeeded is not run again), so two
    are a store written twice or edited by hand; the first counts (as a resumed campaign and
    :func:`xnavlab.core.campaign.load_runs` take it), and the warning says which keys differ.
    Two equal ``ok`` records are one result and pass in silence.

    Parameters
    ----------
    records : list of dict
        The records in file order (:func:`parse_records`).
    numbers : list of int
        Their line numbers.
    path : str or Path
        The file, for the message.

    Examples
    --------
    >>> import warnings
    >>> ok = {"index": 0, "seed": 1, "parameters": {}, "metrics": {"a": 1.0}, "status": "ok",
    ...       "error": None}
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     report_disagreements([ok, {**ok, "metrics": {"a": 2.0}}], [1, 3], "runs.jsonl")
    >>> str(w[0].message)
    "runs.jsonl: run 0 has two 'ok' records that disagree (lines 1 and 3 differ in metrics); the first counts"
    """
    first, found = {}, []
    for rec, n in zip(records, numbers, strict=True):
        if rec["status"] != "ok":
            continue
        i = rec["index"]
        if i not in first:
            first[i] = (rec, n)
            continue
        keep, m = first[i]
        diff = [k for k in PUBLIC_KEYS if keep[k] != rec[k]]
        if diff:
            found.append(f"run {i} has two 'ok' records that disagree (lines {m} and {n} "
                         f"differ in {', '.join(diff)})")
    if found:
        more = f"; and {len(found) - 10} more" if len(found) > 10 else ""
        warnings.warn(f"{path}: {'; '.join(found[:10])}{more}; the first counts", InputWarning,
                      stacklevel=3)


def given_warnings(caught):
    """The warnings a run gave where it ran (``warnings.catch_warnings(record=True)``), as
    ``(category, text)`` pairs, each once, for :func:`warn_again` in the campaign's process (a
    category that cannot travel back, not importable by name, becomes UserWarning).

    Examples
    --------
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     warnings.warn("a", InputWarning); warnings.warn("a", InputWarning)
    >>> given_warnings(w)
    [(<class 'xnavlab.core.userfiles.InputWarning'>, 'a')]
    """
    out = []
    for w in caught:
        cat = w.category
        module = sys.modules.get(getattr(cat, "__module__", ""), None)
        item = (cat if getattr(module, cat.__qualname__, None) is cat else UserWarning,
                str(w.message))
        if item not in out:
            out.append(item)
    return out


def warn_again(items):
    """Give again each ``(category, text)`` of :func:`given_warnings` (in this process: its
    filters and the command line's one-line printer see a worker's warnings)."""
    for category, text in items:
        warnings.warn(text, category, stacklevel=2)
