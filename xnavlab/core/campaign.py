"""Monte Carlo campaigns at scale: local processes or a Dask cluster, resumable, loss-free.

A *campaign* runs one trial function many times. Run ``i`` calls
``trial(seed=s_i, **params(i))`` where ``s_i`` is the ``i``-th child of
``numpy.random.SeedSequence(seed)`` (:func:`xnavlab.core.montecarlo.seeds`) and ``params(i)``
depends on the run index only. Neither depends on the engine, the number of workers, the
worker a run landed on or the order in which runs completed, so a campaign gives the same
records on a laptop and on a cluster.

Engines (:data:`ENGINES`)
    ``"serial"``
        in this process, one run after the other (notebooks, doctests, debugging);
    ``"local"``
        a local ``concurrent.futures.ProcessPoolExecutor`` (the default; no Dask needed);
    ``"dask"``
        an existing Dask cluster, given by its scheduler address
        (``distributed.Client(address, timeout=timeout)``);
    ``"local-cluster"``
        a ``distributed.LocalCluster`` of worker processes started (and stopped) here.

    Dask is imported only by the two Dask engines.

Store (:class:`Store`)
    With ``out=DIR`` every attempt of a run is appended to ``DIR/runs.jsonl`` as one JSON
    line and flushed as soon as it completes (records only, so any JSON-lines reader and
    :func:`load_runs` take it directly); ``DIR/campaign.json`` holds the header, the
    campaign's manifest (name, seed, trial, parameters). Running the same campaign into the
    same DIR again reuses every finished run and computes only the missing ones (and those
    whose every attempt failed); a DIR whose header names another campaign is refused with a
    ``ValueError``. The number of runs is not part of the manifest: run ``i``'s seed and
    parameters do not depend on it, so a campaign of 100 runs can be extended to 1,000 in
    the same DIR. A line that is not a record (a last line torn by a process killed while
    writing, a line edited by hand) is reported in one warning naming the file and the line,
    and its run computed again (a torn last line is cut off); a record a full disk cuts short is
    cut off and ends the campaign in one ValueError naming the file. Every refusal (another
    campaign's DIR, a store in use, a malformed scheduler address, an unreachable scheduler)
    comes before the store's files are made. The manifest does not cover the code: after
    changing a trial's code, start a new DIR.

Failures
    A run that raises, returns something that is not a JSON-ready dict, or whose worker
    dies is recorded with ``status = "failed"`` and its error, retried ``retries`` times
    (default once), and never stops the campaign. When a local worker process dies, every
    run in flight on the pool is lost with it; those runs are rerun one at a time, and only a
    death while a run was alone on the pool counts as that run's failure (a Dask scheduler
    does the same bookkeeping itself and reports ``KilledWorker``).

Records
    One dict a run: ``index``, ``seed``, ``parameters``, ``metrics`` (the trial's dict,
    normalised to JSON: tuples become lists, numpy scalars plain numbers, and non-finite
    floats ``None``, since JSON has no inf or NaN), ``status`` (``"ok"`` or ``"failed"``),
    ``error`` (``None`` or ``"Type: message"``); the store also keeps ``attempt``,
    ``elapsed_s`` (time in the trial) and ``worker`` (host:pid), which are not part of a
    run's result (:func:`public_record` drops them).

Examples
--------
>>> from xnavlab.core.montecarlo import signal_trial
>>> camp = Campaign("spikes", signal_trial, lambda i: {"kind": "spike", "size_sigma": 9.0})
>>> res = run_campaign(camp, 3, seed=1, engine="serial")
>>> [r["index"] for r in res.runs()], res.computed, res.failed
([0, 1, 2], 3, 0)
>>> res.runs()[0]["metrics"]["chi2"]["detected"]
True
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import socket
import sys
import time
import warnings
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from xnavlab.core._campaign_local import Pool, Serial
from xnavlab.core.campaign_records import (
    PUBLIC_KEYS,
    given_warnings,
    json_or_none,
    parse_records,
    report_bad_lines,
    report_disagreements,
    warn_again,
    why_not_a_record,
)
from xnavlab.core.diskcache import check_cache
from xnavlab.core.montecarlo import seeds as spawn_seeds
from xnavlab.core.userfiles import InputWarning, as_path, path_kind, read_text, write_whole
from xnavlab.core.validate import check_bool, check_choice, check_int, check_real, check_seed, shown

__all__ = ["ENGINES", "STORE_FILE", "HEADER_FILE", "SUMMARY_FILE", "OWNER_FILE", "FORMAT",
           "SCHEDULER_SCHEMES", "Campaign", "CampaignResult", "Store", "json_ready", "differences",
           "execute", "public_record", "run_campaign", "check_scheduler", "load_runs"]

#: Where a campaign can run.
ENGINES = ("serial", "local", "dask", "local-cluster")
#: The store's file name inside the campaign directory.
STORE_FILE = "runs.jsonl"
#: The store's header file (the campaign's name, manifest, seed, format).
HEADER_FILE = "campaign.json"
#: The summary the command line writes beside the runs.
SUMMARY_FILE = "summary.json"
#: The file naming the process that holds the store (for the "in use" message).
OWNER_FILE = "owner.pid"
#: Format tag of the store's header.
FORMAT = "xnavlab-campaign/2"
#: The first format: the header was the first line of ``runs.jsonl`` (read and converted).
LEGACY_FORMAT = "xnavlab-campaign/1"


@dataclass(frozen=True)
class Campaign:
    """What a campaign runs: a trial, the parameters of run ``i``, and its identity.

    Parameters
    ----------
    name : str
        Campaign name (part of the manifest).
    trial : callable
        ``trial(seed=int, **params) -> dict`` (JSON-ready); a module-level function, so that
        it pickles to worker processes and Dask workers (which need xnavlab installed).
    params : callable
        ``params(index) -> dict``: the keyword arguments of run ``index``, a function of the
        index alone.
    manifest : dict
        Every setting that changes the results besides the seed (e.g. ``days``); with the
        name, the trial's import path and the seed it identifies the campaign in a store.
    summarise : callable, optional
        ``summarise(runs) -> list of dict``: the aggregated table of the run records
        (:func:`public_record`), for reports.
    check_metrics : callable, optional
        ``check_metrics(metrics) -> None or str``: why a stored ``ok`` record's metrics are
        not this campaign's (reported by file and line, and its run computed again).
    """

    name: str
    trial: Callable
    params: Callable
    manifest: dict = field(default_factory=dict)
    summarise: Callable | None = None
    check_metrics: Callable | None = None

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name:
            raise ValueError(f"name must be a non-empty string, got {self.name!r}")
        if not callable(self.trial) or not callable(self.params):
            raise ValueError("trial and params must be callable")
        if not isinstance(self.manifest, dict):
            raise ValueError(f"manifest must be a dict, got {type(self.manifest).__name__}")
        for name in ("summarise", "check_metrics"):
            if getattr(self, name) is not None and not callable(getattr(self, name)):
                raise ValueError(f"{name} must be a function of the records or None, got "
                                 f"{type(getattr(self, name)).__name__}")

    def header(self, seed):
        """The store's header for ``seed``: format, campaign name, trial, seed, parameters."""
        trial = f"{getattr(self.trial, '__module__', '?')}:{getattr(self.trial, '__qualname__', '?')}"
        return json_ready({"format": FORMAT, "campaign": self.name, "trial": trial,
                         "seed": int(seed), "parameters": self.manifest})


def json_ready(value):
    """``value`` as plain JSON types: dicts (str keys), lists, str, int, float, bool, None.

    Strict, unlike :func:`xnavlab.reproduce.jsonable` (a lenient ``json.dumps`` fallback): a
    campaign record must read back as it was written.

    Tuples and arrays become lists, numpy scalars Python numbers, non-finite floats ``None``.

    Raises
    ------
    ValueError
        For a value of any other type (named in the message).

    Examples
    --------
    >>> json_ready({"a": (1, np.float64(2.5)), "b": float("inf"), "c": np.arange(2)})
    {'a': [1, 2.5], 'b': None, 'c': [0, 1]}
    """
    if value is None or isinstance(value, bool | str):
        return value
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, bool | int):
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {str(k): json_ready(v) for k, v in value.items()}
    if isinstance(value, list | tuple | np.ndarray):
        return [json_ready(v) for v in (value.tolist() if isinstance(value, np.ndarray) else value)]
    raise ValueError(f"metrics must hold JSON-ready values, got {type(value).__name__}")


def differences(stored, asked, prefix=""):
    """The keys in which two tables differ, nested keys dotted, each with both values (cut to
    80 characters): a refusal names what differs instead of printing both tables.

    Examples
    --------
    >>> differences({"seed": 1, "parameters": {"days": 1.0, "mode": "reset"}},
    ...             {"seed": 1, "parameters": {"days": 2.0, "mode": "reset"}})
    'parameters.days 1.0 (asked 2.0)'
    """
    out, none = [], object()
    for k in sorted(set(stored) | set(asked), key=str):
        a, b = stored.get(k, none), asked.get(k, none)
        if a == b:
            continue
        if isinstance(a, dict) and isinstance(b, dict):
            out.append(differences(a, b, f"{prefix}{k}."))
        else:
            a, b = ("missing" if v is none else shown(v) for v in (a, b))
            out.append(f"{prefix}{k} {a} (asked {b})")
    return "; ".join(out)


def execute(trial, seed, params):
    """Run one trial where it lands (worker side) and package its outcome.

    Returns
    -------
    dict
        ``metrics`` (the result as JSON text, or ``None``), ``error`` (``None`` or
        ``"Type: message"``), ``elapsed_s`` (s in the trial), ``worker`` (host:pid),
        ``warnings`` (:func:`~xnavlab.core.campaign_records.given_warnings`: given again
        where the campaign runs, so a worker's warning reaches the command line's printer).
        Exceptions of the trial are caught here, so an unpicklable exception cannot break
        the transfer back.

    Examples
    --------
    >>> out = execute(lambda seed, x: {"y": x + seed}, 1, {"x": 2})
    >>> out["metrics"], out["error"]
    ('{"y": 3}', None)
    """
    t0 = time.perf_counter()
    metrics, error = None, None
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            result = trial(seed=seed, **params)
            if not isinstance(result, dict):
                raise ValueError(f"trial must return a dict, got {type(result).__name__}")
            metrics = json.dumps(json_ready(result), allow_nan=False)
        except Exception as exc:  # noqa: BLE001 - any failure of a run is recorded, not raised
            error = _describe(exc)
    return {"metrics": metrics, "error": error, "elapsed_s": time.perf_counter() - t0,
            "worker": f"{socket.gethostname()}:{os.getpid()}", "warnings": given_warnings(caught)}


def _describe(exc):
    text = " ".join(str(exc).split())
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def public_record(record):
    """A run's result: the record's ``index``, ``seed``, ``parameters``, ``metrics``,
    ``status`` and ``error`` (no timing, worker or attempt).

    Examples
    --------
    >>> public_record({"index": 0, "seed": 5, "parameters": {}, "metrics": {"a": 1},
    ...                "status": "ok", "error": None, "elapsed_s": 0.1, "attempt": 1})
    {'index': 0, 'seed': 5, 'parameters': {}, 'metrics': {'a': 1}, 'status': 'ok', 'error': None}
    """
    return {k: record[k] for k in PUBLIC_KEYS}


# ---------------------------------------------------------------------------------- store


def _check_files(directory):
    """A folder, a pipe or a dangling link in place of the store's files: one line naming it."""
    if path_kind(directory, "out") != "folder":
        return
    for name in (STORE_FILE, HEADER_FILE):
        path = directory / name
        kind = path_kind(path, f"out {str(directory)!r}: {name}")
        what = {"folder": "a folder", "other": "a pipe, socket or device"}.get(kind)
        if kind == "missing" and os.path.islink(path):
            what = f"a symbolic link to {os.readlink(path)!r}, which does not exist"
        if what is not None:
            raise ValueError(f"out {str(directory)!r}: {name} {str(path)!r} is {what}, not a "
                             f"file of a campaign store; remove it, or choose another --out")


def _try_lock(fh, directory, release=False):
    """Lock the store's file ``fh`` (released at once with ``release``); another running
    campaign holding it is one ValueError naming its process (the pid in ``owner.pid``)."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - no advisory locks on this platform
        return
    try:
        fcntl.flock(fh.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        try:
            who = (directory / OWNER_FILE).read_text().split()[0]
        except (OSError, IndexError, UnicodeDecodeError):
            who = "unknown"
        raise ValueError(f"out {directory} is in use by another running campaign (process "
                         f"{who})") from None
    # the lock is the kernel's: it ends with the process that holds it, so a dead owner's
    # store is taken over at once; the pid is only for the message above
    if release:
        fcntl.flock(fh.fileno(), fcntl.LOCK_UN)


def _decode(read, directory):
    """The lines ``read()`` gives of ``runs.jsonl``; not UTF-8 is one ValueError."""
    try:
        return read().split("\n")
    except UnicodeDecodeError as exc:
        raise ValueError(f"out {str(directory)!r}: {STORE_FILE} is not UTF-8 text (byte "
                         f"{exc.start}), not an xnavlab campaign store; choose another --out") from None


def _scan(directory, lines, header, check):
    """What the store's ``lines`` hold for ``header``, read only (:class:`Store` writes what it
    says): ``read`` (the record lines), ``lines`` (them without a torn last line),
    ``legacy``, ``torn_header`` (empty or torn campaign.json, no record), ``torn`` ((line,
    why) of a torn last line, or None), ``records``, ``bad``, ``numbers``."""
    head_path = directory / HEADER_FILE
    first = json_or_none(lines[0]) if lines[0].strip() else None
    legacy = isinstance(first, dict) and first.get("format") == LEGACY_FORMAT
    torn_header = False
    if path_kind(head_path, HEADER_FILE) != "missing":
        head = json_or_none(read_text(head_path, "campaign header"))
        if head is None:  # empty or torn: the records cannot be matched to this campaign
            if any(line.strip() for line in lines):
                raise ValueError(f"out {str(directory)!r}: {HEADER_FILE} is empty or not JSON "
                                 f"(torn), so the records in {STORE_FILE} cannot be matched "
                                 f"to this campaign; restore it, or choose another --out")
            torn_header = True
    elif legacy:
        head = {**first, "format": FORMAT}
    elif lines == [""]:
        head = None
    else:
        raise ValueError(f"out {directory / STORE_FILE} is not an xnavlab campaign store; "
                         f"choose another --out")
    if head is not None and (not isinstance(head, dict) or head.get("format") != FORMAT):
        raise ValueError(f"out {directory} is not an xnavlab campaign store; choose another "
                         f"--out")
    if head is not None and head != header:
        raise ValueError(f"out {directory} holds another campaign's records: "
                         f"{differences(head, header)}; choose another --out")
    skipped = int(legacy)
    read = (lines[1:] or [""]) if legacy else lines
    torn, kept = None, read
    why = why_not_a_record(json_or_none(read[-1])) if read[-1] != "" else None
    if why is not None:  # the last line torn by a kill: its run is computed again
        torn = (skipped + len(read), f"{why}; the last line, torn by an interrupted write: "
                                     f"cut off")
        kept = read[:-1] + [""]
    records, bad, numbers = parse_records(kept, skipped, numbers=True, check=check)
    return {"read": read, "lines": kept, "legacy": legacy, "torn_header": torn_header,
            "torn": torn, "records": records, "bad": bad, "numbers": numbers}


def _final(records):
    """The record that counts for each index: its ``ok`` one, else its last failed one."""
    out = {}
    for rec in records:
        i = rec["index"]
        if i not in out or out[i]["status"] != "ok":
            out[i] = rec
    return out


class Store:
    """A campaign's files: ``DIR/campaign.json`` (the header) and ``DIR/runs.jsonl`` (records).

    ``runs.jsonl`` holds one record per line and nothing else, so any JSON-lines reader
    takes it directly (``pandas.read_json(path, lines=True)``, or :func:`load_runs`); it is
    appended to and locked while a campaign runs. ``campaign.json`` is the header: the
    campaign's name, manifest, seed and format. A store of the first format (header as the
    first line of ``runs.jsonl``) is converted when it is opened. A line that is not a record
    is reported in one warning naming the file and line, and its run computed again; a torn
    last line (a process killed while writing) is also cut off, so no broken line stays in the
    middle of the file. :meth:`read` reads a store without making or changing a file.

    Parameters
    ----------
    directory : str or Path
        Campaign directory (created if missing).
    header : dict
        The campaign's header (:meth:`Campaign.header`). A new store starts with it; an
        existing one must hold the same header.
    check : callable, optional
        The campaign's ``check_metrics``.

    Raises
    ------
    ValueError
        If the store holds another campaign, is not a campaign store, has records but a
        header that cannot be read (empty or torn ``campaign.json``), is in use by another
        process, a folder, a pipe or a dangling link stands in place of one of its files, or
        one of them cannot be written (a full disk).
    """

    def __init__(self, directory, header, check=None):
        directory = as_path(directory, "directory", "folder")  # None, a dict or "": one line
        self.path = directory / STORE_FILE
        self.header_path = directory / HEADER_FILE
        self.header = header
        _check_files(directory)
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise ValueError(f"out {str(directory)!r} cannot be made a folder ({exc.strerror})") from None
        try:
            # newline="": the lines as stored (a CRLF file's torn line is cut at its own byte)
            self._fh = open(self.path, "a+", encoding="utf-8", newline="")  # noqa: SIM115
        except OSError as exc:
            raise ValueError(f"out {str(directory)!r}: {STORE_FILE} {str(self.path)!r} cannot be "
                             f"opened for appending ({exc.strerror})") from None
        self._locked = False
        try:
            _try_lock(self._fh, directory)
            self._locked = True
            (directory / OWNER_FILE).write_text(f"{os.getpid()} {socket.gethostname()}\n")
            self._fh.seek(0)
            scan = _scan(directory, _decode(self._fh.read, directory), header, check)
            lines = scan["lines"]
            if scan["torn_header"]:
                warnings.warn(f"{self.header_path}: empty or not JSON (torn) and no record "
                              f"stored; written again", InputWarning, stacklevel=3)
                self._write_header()
            if scan["legacy"]:  # the first format: move the header line to its own file
                self._fh.seek(0)
                self._fh.truncate()
                self._fh.write("\n".join(scan["read"]))
                self._fh.flush()
            if not self.header_path.exists():
                self._write_header()
            if scan["torn"] is not None:  # cut off, so that no broken line stays in the file
                self._fh.truncate(len("\n".join(lines).encode("utf-8")))
                self._fh.seek(0, os.SEEK_END)
                self._fh.flush()
            elif scan["read"][-1] != "":
                self._fh.write("\n")  # a whole record that lost only its newline
                self._fh.flush()
            bad = scan["bad"] + ([scan["torn"]] if scan["torn"] is not None else [])
            if bad:
                report_bad_lines(bad, self.path, "their runs are computed again")
            report_disagreements(scan["records"], scan["numbers"], self.path)
            self._records = scan["records"]
        except OSError as exc:  # a full disk: one line naming the file
            self.close()
            raise ValueError(f"out {str(directory)!r}: the campaign store cannot be written "
                             f"({exc.strerror or exc})") from None
        except BaseException:
            self.close()
            raise

    @staticmethod
    def read(directory, header, check=None):
        """The record that counts for each index (:meth:`final`) of the store in ``directory``,
        read without making, locking or changing any file, and without a warning (opening it
        gives them): the refusals of opening it, before a command makes its other checks.

        Returns
        -------
        dict
            Index -> record; empty for a missing folder or store.
        """
        directory = as_path(directory, "directory", "folder")
        if path_kind(directory, "out") != "folder":
            return {}  # missing (made by the open), or a file (refused by it)
        _check_files(directory)
        path = directory / STORE_FILE
        lines = [""]
        if path_kind(path, STORE_FILE) == "file":
            try:
                with open(path, encoding="utf-8", newline="") as fh:
                    _try_lock(fh, directory, release=True)
                    lines = _decode(fh.read, directory)
            except OSError as exc:
                raise ValueError(f"out {str(directory)!r}: {STORE_FILE} {str(path)!r} cannot be "
                                 f"read ({exc.strerror})") from None
        return _final(_scan(directory, lines, header, check)["records"])

    def _write_header(self):
        """The header, written whole or not at all (a kill mid-write leaves no torn file)."""
        text = json.dumps(self.header, indent=1, allow_nan=False) + "\n"
        write_whole(self.header_path, lambda tmp: tmp.write_text(text))

    def _write(self, obj):
        """One line appended whole, or the file left as it was before it: a failed write (a
        full disk) is cut off again and is one ValueError naming the file."""
        # appended unbuffered: nothing is left in a buffer to flush (and fail) at close
        fd, data = self._fh.fileno(), (json.dumps(obj, allow_nan=False) + "\n").encode("utf-8")
        size = os.fstat(fd).st_size
        try:
            while data:
                data = data[os.write(fd, data):]
            os.fsync(fd)
        except OSError as exc:
            with contextlib.suppress(OSError):
                os.ftruncate(fd, size)
            raise ValueError(f"out {str(self.path.parent)!r}: {STORE_FILE} cannot be written ("
                             f"{exc.strerror}); its runs are kept: run the same command again "
                             f"with room to complete the campaign") from None

    @property
    def records(self):
        """Every record read or appended, in file order (several attempts of a run possible)."""
        return list(self._records)

    def final(self):
        """The record that counts for each index: its ``ok`` one, else its last failed one.

        Returns
        -------
        dict
            Index -> record.
        """
        return _final(self._records)

    def append(self, record):
        """Append one record and flush it to disk (a full disk: ValueError, the file as it was)."""
        self._write(record)
        self._records.append(record)

    def close(self):
        """Release the lock (and ``owner.pid``) and close the file."""
        if self._locked:  # removed while locked: a process taking the store over writes its own
            with contextlib.suppress(OSError):
                (self.path.parent / OWNER_FILE).unlink(missing_ok=True)
        with contextlib.suppress(OSError):  # an earlier write's failure: already reported
            self._fh.close()


# -------------------------------------------------------------------------------- engines


#: Schemes of a Dask scheduler's address (:func:`check_scheduler`).
SCHEDULER_SCHEMES = ("tcp", "tls", "ws", "wss")


def check_scheduler(name, address):
    """``address`` if it is a Dask scheduler's address, ``[SCHEME://]HOST:PORT`` (a scheme of
    :data:`SCHEDULER_SCHEMES`, tcp when left out; an IPv6 host in brackets; a port in [1,
    65535]); else one ValueError leading with ``name`` that calls it malformed (not
    unreachable: this is checked before any connection).

    Examples
    --------
    >>> check_scheduler("scheduler", "tcp://10.0.0.5:8786")
    'tcp://10.0.0.5:8786'
    >>> check_scheduler("--scheduler", "tcp://host")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: --scheduler 'tcp://host' is a malformed scheduler address: no port; give ...
    """
    if not isinstance(address, str) or not address.strip():
        raise ValueError(f"{name} must be a scheduler address, [SCHEME://]HOST:PORT (e.g. "
                         f"tcp://HOST:8786), got {shown(address)}")
    scheme, sep, rest = address.partition("://")
    scheme, rest = (scheme, rest) if sep else ("tcp", address)
    host, _, port = rest.rpartition(":")
    why = None
    if scheme not in SCHEDULER_SCHEMES:
        why = f"unknown scheme {scheme!r} ({', '.join(SCHEDULER_SCHEMES)})"
    elif not (port.isascii() and port.isdigit() and 1 <= int(port) <= 65535):
        why = f"the port {port!r} is not an integer in [1, 65535]" if host else "no port"
    elif host.strip("[]") == "" or any(c.isspace() or c in "/?#@" for c in host):
        why = f"the host {host!r} is not a host name or IP address"
    elif ":" in host and not (host.startswith("[") and host.endswith("]")):
        why = f"the IPv6 host {host!r} goes in brackets ([::1]:8786)"
    if why is not None:
        raise ValueError(f"{name} {address!r} is a malformed scheduler address: {why}; give "
                         f"[SCHEME://]HOST:PORT, e.g. tcp://HOST:8786")
    return address


#: run_campaign's defaults, which an engine that would not use workers or a timeout accepts.
_WORKERS = 2
_TIMEOUT_S = 5.0


def _check_unused(engine, workers, timeout):
    """``workers`` and ``timeout`` given to an engine that would not use them: one ValueError
    (``"serial"`` runs in this process, one worker; a Dask scheduler's cluster has its own
    workers; only a Dask cluster is waited for)."""
    if (engine == "serial" and workers not in (1, _WORKERS)) or (engine == "dask" and workers != _WORKERS):
        raise ValueError(f"workers sets the processes of engine 'local' or 'local-cluster', got "
                         f"workers={workers} with engine {engine!r}; leave workers out")
    if engine in ("serial", "local") and timeout != _TIMEOUT_S:
        raise ValueError(f"timeout is the wait for a Dask cluster (engine 'dask' or "
                         f"'local-cluster'), got timeout={timeout:g} with engine {engine!r}; "
                         f"leave timeout out")


def _engine(engine, workers, scheduler, timeout):
    if engine == "serial":
        return Serial(execute)
    if engine == "local":
        return Pool(workers, execute, _describe)
    from xnavlab.core._campaign_dask import DaskEngine  # Dask only for the Dask engines

    return DaskEngine(scheduler if engine == "dask" else None, workers, timeout, execute)


# ------------------------------------------------------------------------------- campaign


@dataclass
class CampaignResult:
    """The outcome of :func:`run_campaign`.

    Attributes
    ----------
    header : dict
        The campaign's manifest (:meth:`Campaign.header`).
    records : list of dict
        One record per run ``0 .. runs-1``, in index order (the record that counts).
    computed, reused, failed : int
        Runs computed now, runs taken from the store, runs whose every attempt failed.
    attempts : int
        Attempts made now (computed plus retries).
    wall_s : float
        Wall time, s.
    summary : list of dict or None
        The campaign's aggregated table (``Campaign.summarise``) of the runs.
    """

    header: dict
    records: list
    computed: int
    reused: int
    failed: int
    attempts: int
    wall_s: float
    summary: list | None = None

    def runs(self):
        """The run records without bookkeeping (:func:`public_record`), in index order."""
        return [public_record(r) for r in self.records]

    def to_dict(self):
        """One JSON-ready dict: ``campaign`` (the header), ``runs``, ``summary`` and counts."""
        return {"campaign": self.header, "runs": self.runs(), "summary": self.summary,
                "computed": self.computed, "reused": self.reused, "failed": self.failed,
                "wall_s": self.wall_s}

    def to_json(self):
        """:meth:`to_dict` as strict JSON text (``json.dumps``; no NaN or infinity)."""
        return json.dumps(self.to_dict(), allow_nan=False)


def _record(index, seed, params, outcome, attempt):
    kind, payload = outcome
    if kind == "ok":
        warn_again(payload.get("warnings", ()))
    rec = {"index": index, "seed": seed, "parameters": params, "metrics": None, "status": "failed",
           "error": None, "attempt": attempt, "elapsed_s": None, "worker": None}
    if kind == "ok":
        rec.update(elapsed_s=payload["elapsed_s"], worker=payload["worker"])
        if payload["error"] is None:
            rec.update(metrics=json.loads(payload["metrics"]), status="ok")
        else:
            rec["error"] = payload["error"]
    else:
        rec["error"] = payload
    return rec


def run_campaign(campaign, runs, *, seed=0, out=None, engine="local", workers=_WORKERS, scheduler=None,
                 timeout=_TIMEOUT_S, retries=1, progress=False, retry_failed=True):
    """Run (or complete) a campaign of ``runs`` runs on an engine, storing each run as it ends.

    Parameters
    ----------
    campaign : Campaign
    runs : int
        Number of runs, 1 to 10^7 (indices ``0 .. runs-1``).
    seed : int
        The one seed, in [0, 2^63 - 1]; run ``i`` gets ``seeds(seed, runs)[i]``.
    out : str or Path, optional
        Campaign directory (:class:`Store`); without it nothing is stored or reused.
    engine : {"serial", "local", "dask", "local-cluster"}
        Where the runs execute (see the module's docstring).
    workers : int
        Processes of ``"local"`` and ``"local-cluster"``, 1 to 256 (``"serial"`` takes 1 or
        the default, ``"dask"`` the default only: they would not use another).
    scheduler : str, optional
        Scheduler address of ``"dask"``, e.g. ``"tcp://10.0.0.5:8786"``.
    timeout : float
        Seconds to connect to the scheduler and to wait for its first worker, in (0, 3600]
        (``"dask"`` and ``"local-cluster"`` only: another engine takes the default only).
    retries : int
        Extra attempts of a failed run, 0 to 10.
    progress : bool
        A tqdm bar on stderr: runs done, failed, rate.
    retry_failed : bool
        Recompute runs whose every stored attempt failed (default); ``False`` reuses them.

    Returns
    -------
    CampaignResult

    Raises
    ------
    ValueError
        Bad arguments, a store of another campaign, an unreachable scheduler.
    """
    if not isinstance(campaign, Campaign):
        raise ValueError(f"campaign must be a Campaign, got {type(campaign).__name__}")
    runs = check_int("runs", runs, 1, 10**7)
    seed = check_seed("seed", seed)
    check_choice("engine", engine, ENGINES)
    workers = check_int("workers", workers, 1, 256)
    timeout = check_real("timeout", timeout, 0.0, 3600.0, lo_open=True)
    retries = check_int("retries", retries, 0, 10)
    progress, retry_failed = check_bool("progress", progress), check_bool("retry_failed", retry_failed)
    if engine == "dask" and not scheduler:
        raise ValueError("engine 'dask' needs a scheduler address, e.g. tcp://HOST:8786")
    if engine != "dask" and scheduler:
        raise ValueError(f"a scheduler address needs engine 'dask', got engine {engine!r}")
    if engine == "dask":
        check_scheduler("scheduler", scheduler)  # malformed, not unreachable: before connecting
    _check_unused(engine, workers, timeout)
    if engine != "dask":  # runs here read the cache: an unusable $XNAVLAB_CACHE refused now
        check_cache()
    header = campaign.header(seed)
    run_seeds = spawn_seeds(seed, runs)
    params = [campaign.params(i) for i in range(runs)]
    if not all(isinstance(p, dict) for p in params):
        raise ValueError("campaign.params(index) must return a dict of keyword arguments")
    params = [json_ready(p) for p in params]

    def reusable(stored):  # the stored runs that count; one of another campaign: refused
        final = {}
        for i, rec in stored.items():
            if i >= runs:
                continue
            was = {"seed": rec["seed"], "parameters": rec["parameters"]}
            asked = {"seed": run_seeds[i], "parameters": params[i]}
            if was != asked:
                raise ValueError(f"out {out}: stored run {i} is another campaign's: "
                                 f"{differences(was, asked)}; choose another --out")
            if rec["status"] == "ok" or not retry_failed:
                final[i] = rec
        return final

    final = {}
    if out is not None:  # every refusal before the engine connects and the store's files exist
        as_path(out, "out", "folder")  # a dict or "" (the current folder): one line
        final = reusable(Store.read(out, header, campaign.check_metrics))
    t0 = time.perf_counter()
    eng = _engine(engine, workers, scheduler, timeout) if len(final) < runs else None
    store = None
    try:
        if out is not None:
            store = Store(out, header, campaign.check_metrics)
            final = reusable(store.final())  # again, locked: another process may have written
        reused = len(final)
        todo = [i for i in range(runs) if i not in final]
        computed, attempts = 0, 0
        if todo:
            eng = eng or _engine(engine, workers, scheduler, timeout)
            computed, attempts = _drive(campaign, todo, run_seeds, params, final, store, eng,
                                        retries, progress, runs, reused)
    finally:
        if eng is not None:
            eng.close()
        if store is not None:
            store.close()
    records = [final[i] for i in range(runs)]
    failed = sum(r["status"] != "ok" for r in records)
    result = CampaignResult(header, records, computed, reused, failed, attempts, time.perf_counter() - t0)
    if campaign.summarise is not None:
        result.summary = json_ready(campaign.summarise(result.runs()))
    return result


def _drive(campaign, todo, run_seeds, params, final, store, eng, retries, progress, runs,
           reused):
    """Submit, collect, store and retry until every run in ``todo`` has a final record."""
    from tqdm import tqdm

    bar = tqdm(total=runs, initial=reused, desc=campaign.name, unit="run", file=sys.stderr,
               disable=not progress, mininterval=0.5, dynamic_ncols=True)
    queue = deque((i, 1) for i in todo)
    # runs that were in flight when a local worker died, with others: which one killed it is
    # unknown, so each is rerun alone, and only a death while alone counts as its failure
    solo, running = deque(), {}
    n_failed = sum(r["status"] != "ok" for r in final.values())
    computed = attempts = 0
    try:
        while queue or solo or running:
            if solo:
                if not running:
                    i, attempt = solo.popleft()
                    running[eng.submit(campaign.trial, run_seeds[i], params[i])] = (i, attempt, True)
            else:
                while queue and len(running) < eng.window:
                    i, attempt = queue.popleft()
                    running[eng.submit(campaign.trial, run_seeds[i], params[i])] = (
                        i, attempt, eng.window == 1)
            for handle, outcome in eng.wait(list(running)):
                i, attempt, alone = running.pop(handle)
                lost = outcome[0] == "lost" and not alone
                if lost:
                    outcome = ("error", outcome[1] + ", with other runs in flight: rerun "
                                                    "alone, not counted as an attempt")
                rec = _record(i, run_seeds[i], params[i], outcome, attempt)
                attempts += 1
                if store is not None:
                    store.append(rec)
                if lost:
                    solo.append((i, attempt))
                    continue
                if rec["status"] != "ok" and attempt <= retries:
                    (solo if outcome[0] == "lost" else queue).appendleft((i, attempt + 1))
                    continue
                final[i] = rec
                computed += 1
                n_failed += rec["status"] != "ok"
                bar.set_postfix(failed=n_failed, refresh=False)
                bar.update(1)
    finally:
        bar.close()
    return computed, attempts


def load_runs(directory, final=True):
    """A campaign directory's runs as a ``pandas.DataFrame``, one row per record.

    Columns: ``index``, ``seed``, ``status``, ``error``, then every parameter as
    ``parameters.NAME`` and every scalar metric as ``metrics.NAME`` (lists and nested
    values stay Python objects in their cell). The header (``campaign.json``) is in
    ``df.attrs["campaign"]``. Pandas is needed only here.

    Parameters
    ----------
    directory : str or Path
        A directory written by :func:`run_campaign` (or ``python -m xnavlab campaign``).
    final : bool
        Only the record that counts for each index (its ``ok`` one, else its last
        attempt), sorted by index (default); ``False`` keeps every attempt in file order.

    Examples
    --------
    >>> import tempfile
    >>> from xnavlab.core.montecarlo import signal_trial
    >>> camp = Campaign("s", signal_trial, lambda i: {"kind": "spike", "size_sigma": 9.0})
    >>> with tempfile.TemporaryDirectory() as d:
    ...     _ = run_campaign(camp, 3, out=d, engine="serial")
    ...     df = load_runs(d)
    >>> list(df["index"]), df.attrs["campaign"]["campaign"]
    ([0, 1, 2], 's')
    """
    try:
        import pandas as pd
    except ImportError:
        raise ValueError("load_runs needs pandas (pip install pandas)") from None
    directory = as_path(directory, "campaign folder", "folder")  # a dict, None or "": one line
    path, head = directory / STORE_FILE, directory / HEADER_FILE
    if path_kind(path, "campaign store") == "missing":
        raise ValueError(f"directory {str(directory)!r} holds no campaign ({STORE_FILE} missing)")
    lines = read_text(path, "campaign store").split("\n")
    first = json_or_none(lines[0]) if lines[0].strip() else None
    has_head = path_kind(head, "campaign header") != "missing"
    header = json_or_none(read_text(head, "campaign header")) if has_head else None
    if has_head and not isinstance(header, dict):
        warnings.warn(f"{head}: not a campaign header (not a JSON object); "
                      f"df.attrs['campaign'] is None", InputWarning, stacklevel=2)
        header = None
    skipped = 0
    if isinstance(first, dict) and first.get("format") == LEGACY_FORMAT:
        header, lines, skipped = first, lines[1:], 1
    final = check_bool("final", final)
    recs, bad, numbers = parse_records(lines, skipped, numbers=True)
    report_disagreements(recs, numbers, path)
    if bad:
        torn = lines[-1] != "" and bad[-1][0] == len(lines) + skipped
        report_bad_lines(bad, path, "left out of the table" + (
            " (the last one torn by an interrupted write: run the campaign again to compute "
            "its run)" if torn else ""))
    if final:
        best = _final(recs)
        recs = [best[i] for i in sorted(best)]
    rows = [{"index": r["index"], "seed": r["seed"], "status": r["status"], "error": r["error"],
             **{f"parameters.{k}": v for k, v in (r["parameters"] or {}).items()},
             **{f"metrics.{k}": v for k, v in (r["metrics"] or {}).items()}} for r in recs]
    df = pd.DataFrame(rows, columns=None if rows else ["index", "seed", "status", "error"])
    df.attrs["campaign"] = header
    return df
