"""The registry of reproductions: every paper claim the book judges, computed in one place.

A *reproduction* is a function registered under an ID (``"xnav-ranging"``,
``"mars-nofault"``, ...) that recomputes one figure or table of a source paper and returns a
:class:`Result`: a list of :class:`~xnavlab.verdicts.Check` rows, each the paper's value beside ours, the
tolerance with its reason, and a verdict. The chapters' last cells, ``tests/``, the dashboard
and the command line (``python -m xnavlab reproduce ID``) all call :func:`run`, so a number is
computed, and a verdict decided, by exactly one piece of code.

A reproduction's result is kept on disk, under ``$XNAVLAB_CACHE/reproductions`` (default
``~/.cache/xnavlab``), keyed by the ID, its arguments, the code that computes it (its module,
every module of the package that one imports, directly or not, and the shipped data:
:func:`~xnavlab.core.diskcache.code_digest`), the numeric libraries' versions and
``OPENBLAS_CORETYPE``: the same code on the
same machine gives the same numbers (the seeds are fixed), so a chapter, a test and the
dashboard that ask for the same reproduction compute it once between them. Each ID keeps one
entry per set of arguments and BLAS kernel family; the first entry stored for a new version of
the code removes the ID's entries for the old one. Computed afresh: a run with ``out``, with
``fresh=True`` or with an argument that is not a plain number, string or tuple of them, a
reproduction registered with ``cache=False`` (a measured timing), and every run under
``XNAVLAB_REPRODUCE_CACHE=0``.

Reproductions live in the modules of :mod:`xnavlab.reproductions`; each module is imported on
first use of the registry, so adding a file there is all it takes to register new IDs.

The verdicts
------------
Every row's verdict is one of :data:`~xnavlab.verdicts.VERDICTS` and every reproduction's
headline one of :data:`~xnavlab.verdicts.HEADLINES` (:mod:`xnavlab.verdicts` defines them and
the rows' constructors, re-exported here: ``reproduce.check_rel`` is
:func:`xnavlab.verdicts.check_rel`). A claim that is not reproduced is an honest result, not a
failure: :attr:`Result.ok` (no error, every check of ours holds) and the verdicts recorded in
``tests/test_verdicts.py`` are what the tests assert. :func:`headline` is the one sentence that
counts the claims and the checks, printed by ``python -m xnavlab reproduce --all`` and shown by
the dashboard.
"""

from __future__ import annotations

import contextlib
import copy
import errno
import hashlib
import html
import importlib
import importlib.metadata
import inspect
import json
import os
import pickle
import pkgutil
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from xnavlab.core.diskcache import cache_dir, code_digest, env_switch, exclusive, store
from xnavlab.core.plotting import SafeHTML, figure, html_table
from xnavlab.core.userfiles import output_path, write_whole
from xnavlab.core.validate import check_bool, check_keywords, check_real, check_text
from xnavlab.verdicts import (  # noqa: F401 - re-exported: reproduce.check_rel is verdicts.check_rel
    CHECK,
    CHECK_FAILED,
    CLAIM_VERDICTS,
    ERROR,
    HEADLINES,
    MIN_RUNS,
    NOT_REPRODUCED,
    PARTLY_REPRODUCED,
    REPRODUCED,
    UNDECIDED,
    VERDICTS,
    Check,
    check_abs,
    check_draw,
    check_event,
    check_event_lost,
    check_lost,
    check_measure,
    check_order,
    check_range,
    check_rel,
    check_sanity,
    check_true,
    combine,
    part_of,
    show,
)

__all__ = [
    "Reproduction",
    "Result",
    "register",
    "ids",
    "get",
    "run",
    "run_or_fail",
    "OutputError",
    "CACHE_ENV",
    "counts",
    "headline",
    "results_table",
    "summary_rows",
    "check_rows",
    "report_html",
    "summary_box",
    "SUMMARY_HEADER",
    "CHECK_HEADER",
    "COUNT_HEADER",
    "figure",
    "save_figure",
    "jsonable",
]


@dataclass
class Result:
    """What a reproduction returns.

    Attributes
    ----------
    id : str
        The reproduction ID.
    checks : list of Check
        Its rows: the paper's claims, judged, and our checks.
    note : str
        The honest account: choices made where the paper is silent, reasons for gaps.
    data : dict
        Arrays for the chapter's figures (not serialised).
    figures : list of str
        Paths of figures written when ``out`` was given.
    error : str
        ``"ExceptionType: message"`` when the reproduction raised (see :func:`run_or_fail`),
        else empty.
    from_cache : bool
        True when :func:`run` read it from the disk cache (computed earlier by the same
        code on this machine).
    main : str
        The paper's main claim (a row's name, or the ``claim`` its rows are parts of), which
        the headline follows first (:attr:`verdict`); empty when no claim is the main one.
    """

    id: str
    checks: list[Check]
    note: str = ""
    data: dict[str, Any] = field(default_factory=dict, repr=False)
    figures: list[str] = field(default_factory=list)
    error: str = ""
    #: True when this result was read from the disk cache (computed earlier by the same code)
    from_cache: bool = field(default=False, compare=False)
    main: str = ""

    @property
    def claims(self):
        """The rows that are claims of the paper."""
        return [c for c in self.checks if c.claimed]

    def claim_verdicts(self):
        """The paper's distinct claims and their verdicts, in order: ``{claim: verdict}``.

        A row is a claim of its own (keyed by its name) unless it is a part of a claim that
        takes several rows (:func:`~xnavlab.verdicts.part_of`), which is counted once with the
        verdict of its parts (:func:`~xnavlab.verdicts.combine`).

        Examples
        --------
        >>> a = check_rel("PR1 (s)", 50.0, 50.0, 0.01, why="one sample")
        >>> b = check_rel("PR2 (s)", 50.0, 60.0, 0.01, why="one sample")
        >>> Result("demo", part_of("steps detected at the onset", a, b)).claim_verdicts()
        {'steps detected at the onset': 'NOT REPRODUCED'}
        """
        parts = {}
        for c in self.claims:
            parts.setdefault(c.claim or c.name, []).append(c.verdict)
        return {k: combine(v) for k, v in parts.items()}

    @property
    def ok(self):
        """No error, and every check of ours holds (a refuted claim is not a defect)."""
        return not self.error and all(c.ok for c in self.checks)

    @property
    def verdict(self):
        """The headline (one of :data:`~xnavlab.verdicts.HEADLINES`), which follows the claims.

        Examples
        --------
        >>> yes = check_rel("x", 1.0, 1.02, 0.05, why="two digits")
        >>> no = check_rel("y", 1.0, 2.0, 0.05, why="two digits")
        >>> Result("demo", [yes]).verdict, Result("demo", [yes, no]).verdict
        ('REPRODUCED', 'PARTLY REPRODUCED')
        >>> Result("demo", [check_measure("z", 3, "shown")]).verdict
        'CHECK'
        >>> Result("demo", [yes, no], main="y").verdict  # the main claim fails
        'NOT REPRODUCED'
        """
        if not self.ok:
            return ERROR
        claims = self.claim_verdicts()
        found = set(claims.values())
        if not found:
            return CHECK
        if found == {REPRODUCED}:
            return REPRODUCED
        if self.main:
            if self.main not in claims:
                raise ValueError(f"{self.id}: main claim {self.main!r} is none of its claims: "
                                 + "; ".join(claims))
            if claims[self.main] != REPRODUCED:
                return claims[self.main]
        if REPRODUCED in found:
            return PARTLY_REPRODUCED
        return UNDECIDED if found == {UNDECIDED} else NOT_REPRODUCED

    def counts(self):
        """Rows by verdict: ``{"REPRODUCED": n, ..., "CHECK FAILED": n}`` (every key present).

        Examples
        --------
        >>> rows = [check_rel("x", 1.0, 1.0, 0.1, why="w"), check_measure("y", 2, "shown")]
        >>> Result("demo", rows).counts()["CHECK"]
        1
        """
        out = dict.fromkeys(VERDICTS, 0)
        for c in self.checks:
            out[c.verdict] += 1
        return out

    def claim_counts(self):
        """Distinct claims of the paper by verdict (:meth:`claim_verdicts`; every claim
        verdict a key).

        Examples
        --------
        >>> rows = part_of("one claim", check_rel("x", 1.0, 1.0, 0.1, why="w"),
        ...                check_rel("y", 1.0, 1.0, 0.1, why="w"))
        >>> Result("demo", rows).claim_counts()["REPRODUCED"]
        1
        """
        out = dict.fromkeys(CLAIM_VERDICTS, 0)
        for v in self.claim_verdicts().values():
            out[v] += 1
        return out

    def check(self, name):
        """The row named ``name`` (a ``ValueError`` lists the names when there is none)."""
        for c in self.checks:
            if c.name == name:
                return c
        names = "; ".join(c.name for c in self.checks)
        raise ValueError(f"{self.id} has no row {name!r}; its rows: {names}")

    def sentence(self, name):
        """The row ``name`` in one sentence (:meth:`xnavlab.verdicts.Check.sentence`), for a
        chapter to glue."""
        return self.check(name).sentence()

    @property
    def paper(self):
        return {c.name: c.paper for c in self.checks}

    @property
    def ours(self):
        return {c.name: c.ours for c in self.checks}

    @property
    def tolerance(self):
        return {c.name: c.tolerance for c in self.checks}

    def to_dict(self):
        """The JSON form.

        Keys: ``id``, ``verdict`` (the headline, one of :data:`~xnavlab.verdicts.HEADLINES`), ``ok`` (no error
        and every check holds), ``counts`` (rows by verdict), ``claims`` (the distinct claims
        of the paper and their verdicts, :meth:`claim_verdicts`), ``main`` (the main claim, or
        empty), ``rows`` (each row's ``name``, ``kind`` ("claim" or "check"), ``paper``,
        ``ours``, ``tolerance``, ``verdict``, ``reading`` and ``claim`` (the claim it is a
        part of)), ``note``, ``figures``, ``error``.
        """
        rows = [{"name": c.name, "kind": "claim" if c.claimed else "check", "paper": c.paper,
                 "ours": c.ours, "tolerance": c.tolerance, "verdict": c.verdict,
                 "reading": c.reading, "claim": c.claim or (c.name if c.claimed else "")}
                for c in self.checks]
        return {"id": self.id, "verdict": self.verdict, "ok": self.ok, "counts": self.counts(),
                "claims": self.claim_verdicts(), "main": self.main,
                "rows": rows, "note": self.note, "figures": self.figures, "error": self.error}

    def to_json(self):
        """:meth:`to_dict` as strict JSON (no NaN or infinity: a row refuses them)."""
        return json.dumps(self.to_dict(), default=jsonable, allow_nan=False)

    def table(self):
        """A plain-text table of the rows (columns :data:`CHECK_HEADER`)."""
        return results_table([self])

    def html(self):
        """The result as safe HTML: its headline, a table of its rows, its note.

        Every cell and the note are escaped text (a ``|``, ``<`` or newline in a value
        cannot break the table); the table has the columns :data:`CHECK_HEADER` without
        the reproduction's ID.

        Examples
        --------
        >>> row = check_abs("a|b", 1.0, 1.5, 1.0, why="x < y")
        >>> page = Result("demo", [row], note="x < y").html()
        >>> page.count("<td>"), "a|b" in page, "x &lt; y" in page
        (6, True, True)
        """
        head = (f'<p class="xnav-result"><strong>{html.escape(self.id)}</strong>: '
                f'<span class="xnav-verdict">{self.verdict}</span></p>')
        table = html_table(CHECK_HEADER[1:], [row[1:] for row in check_rows([self])])
        parts = [head, table]
        if self.error:
            parts.append(f'<p class="xnav-error">raised {html.escape(self.error)}</p>')
        if self.note:
            parts.append(f'<p class="xnav-note">{html.escape(self.note)}</p>')
        return SafeHTML("\n".join(parts))

    def _repr_html_(self):
        return self.html()

    def assert_ok(self):
        """Raise ``AssertionError`` listing every row when it raised or a check failed."""
        if not self.ok:
            raise AssertionError(f"{self.id}: {ERROR}\n" + results_table([self])
                                 + (f"\nraised {self.error}" if self.error else ""))


@dataclass(frozen=True)
class Reproduction:
    """A registered reproduction: its ID, what it reproduces, and the function that runs it."""

    id: str
    title: str
    source: str
    chapter: str
    func: Callable[..., Result]
    cache: bool = True


_REGISTRY: dict[str, Reproduction] = {}
_LOADED = False


class OutputError(ValueError):
    """A file under a reproduction's ``out`` that cannot be written (a full disk): the caller's
    folder, not the reproduction, so :func:`run_or_fail` raises it instead of an ERROR row."""


def save_figure(fig, out, name, *, dpi=100, layout=True):
    """Lay out ``fig`` (unless not ``layout``: a figure its plotting function laid out) and
    write it as ``out / (name + ".png")`` at ``dpi`` (30 to 300); return the path.

    Written whole or not at all (:func:`~xnavlab.core.userfiles.write_whole`); a write that
    fails (a full disk) is an :class:`OutputError` naming ``out`` and the file.

    Examples
    --------
    >>> import tempfile
    >>> fig, ax = figure()
    >>> with tempfile.TemporaryDirectory() as d:
    ...     save_figure(fig, d, "x").endswith("x.png")
    True
    """
    from matplotlib.figure import Figure

    if not isinstance(fig, Figure):
        raise ValueError(f"fig must be a matplotlib Figure (from figure()); got {type(fig).__name__}")
    out = _folder("out", out, create=False)
    if not (isinstance(name, str) and name.strip() and "/" not in name and "\\" not in name):
        raise ValueError(f"name must be a file name without its folder (a non-empty str); got {name!r}")
    dpi = check_real("dpi", dpi, 30.0, 300.0)
    if check_bool("layout", layout):
        fig.tight_layout()
    path = out / f"{name}.png"
    try:
        write_whole(path, lambda tmp: fig.savefig(tmp, dpi=dpi))
    except OSError as exc:
        raise OutputError(f"out {str(out)!r}: {path.name} cannot be written "
                          f"({exc.strerror or exc})") from None
    return str(path)


def _folder(name, value, create):
    """``value`` (a str or os.PathLike) as the Path of a folder: one that exists, or with
    ``create`` one made here; else one ValueError naming ``name``."""
    if not isinstance(value, str | os.PathLike) or not str(value).strip():
        raise ValueError(f"{name} must be a folder (a str or os.PathLike); got {value!r}")
    if create:  # made, writable: a file, a link to nothing or a file on the way named as such
        return output_path(value, name, folder=True)
    path = Path(value)
    if path.exists() and not path.is_dir():
        raise ValueError(f"{name} must be a folder; {str(value)!r} is a file")
    if not path.is_dir():
        raise ValueError(f"{name} must be an existing folder; {str(value)!r} does not exist")
    return path


def _results(results):
    """``results`` as a list of :class:`Result` (at least one), else one ValueError."""
    if isinstance(results, Result) or isinstance(results, str | bytes | dict) \
            or not hasattr(results, "__iter__") or getattr(results, "ndim", 1) == 0:
        raise ValueError("results must be a list of Result (from run or run_or_fail); got "
                         f"{type(results).__name__} {results!r:.80}")
    results = list(results)
    if not results:
        raise ValueError("results must hold at least one Result; got an empty list")
    for i, res in enumerate(results):
        if not isinstance(res, Result):
            raise ValueError(f"results[{i}] must be a Result (from run or run_or_fail); got "
                             f"{type(res).__name__} {res!r:.80}")
    return results


def register(id, *, title, source, chapter, cache=True):
    """Decorator registering ``func(out=None) -> Result`` under ``id``.

    Parameters
    ----------
    id : str
        Unique ID, lower case with hyphens (``"xnav-ranging"``).
    title : str
        One line: what is reproduced.
    source : str
        The paper and figure/table, e.g. ``"Fan et al. 2016, section 4.1"``.
    chapter : str
        The book chapter that shows it (notebook file name).
    cache : bool
        Keep its result on disk (see the module docs); ``False`` for a measurement that is
        not a function of the code alone (a timing).
    """

    def deco(func):
        if id in _REGISTRY and _REGISTRY[id].func is not func:
            raise ValueError(f"reproduction {id!r} is registered twice")
        _REGISTRY[id] = Reproduction(id, title, source, chapter, func, cache)
        return func

    return deco


def _load_all():
    global _LOADED
    if _LOADED:
        return
    # Plug-in discovery by package path: the registry does not import its reproductions
    # (they import it), so adding a module to xnavlab/reproductions/ registers its IDs.
    package = importlib.import_module("xnavlab.reproductions")
    for mod in pkgutil.iter_modules(package.__path__):
        importlib.import_module(f"{package.__name__}.{mod.name}")
    _LOADED = True


def ids():
    """Sorted list of registered reproduction IDs.

    Examples
    --------
    >>> "xnav-ranging" in ids()
    True
    """
    _load_all()
    return sorted(_REGISTRY)


def get(id):
    """Return the :class:`Reproduction` registered under ``id``."""
    if not isinstance(id, str):
        raise ValueError(f"id must be a reproduction ID (a str, see ids()); got {id!r}")
    _load_all()
    if id not in _REGISTRY:
        known = ", ".join(sorted(_REGISTRY))
        raise ValueError(f"unknown reproduction id {id!r}; known ids: {known}")
    return _REGISTRY[id]


_CACHE: dict[tuple, Result] = {}

#: Set to ``"0"`` to compute every reproduction afresh instead of reading the disk cache
#: (``"1"`` or unset: on; any other value is refused).
CACHE_ENV = "XNAVLAB_REPRODUCE_CACHE"


def _disk_on():
    """Whether results are kept on disk (:data:`CACHE_ENV`), its folder checked when on."""
    return env_switch(CACHE_ENV, True) and bool(cache_dir())
#: The distributions whose version is part of a cached result's key (the numbers depend on them).
_DEPENDS = ("numpy", "scipy", "numba", "PyWavelets", "jplephem", "de421", "de405", "pint-pulsar")


def _plain(value):
    """Whether ``value`` has a ``repr`` that names it exactly (an argument a key may hold)."""
    if isinstance(value, tuple):
        return all(_plain(v) for v in value)
    return value is None or type(value) in (bool, int, float, str)


def _items(value):
    """A list or array (also in a tuple) as the tuple of its items: the equal tuple's result."""
    if type(value) in (list, tuple):
        return tuple(_items(v) for v in value)
    if type(value).__name__ == "ndarray" and getattr(value, "ndim", 0) >= 1:
        return _items(value.tolist())  # its items as Python numbers, as a tuple would hold them
    return value


def _session_key(id, kwargs):
    """The session cache's key: each keyword by type and value (``True``, ``1`` and ``1.0`` are
    three keys); None for a value that cannot be a key (a dict: computed each time)."""
    def typed(v):
        if type(v) is tuple:
            return ("tuple", *map(typed, v))
        return f"{type(v).__name__}:{v!r}" if _plain(v) else (type(v), v)  # a Generator: itself

    key = (id, tuple((k, typed(v)) for k, v in sorted(kwargs.items())))
    try:
        hash(key)
    except TypeError:
        return None
    return key


def _disk_path(id, kwargs):
    """``<id>-<family>-<code>.pickle``: the family is the arguments and the BLAS kernels (each
    keeps its entry), the code is the package's files and the numeric libraries' versions."""
    family = repr((id, sorted(kwargs.items()), os.environ.get("OPENBLAS_CORETYPE", "")))
    code = code_digest((get(id).func.__module__, __name__))
    h = hashlib.sha256(repr((3, id, code)).encode())
    for dist in _DEPENDS:
        try:
            h.update(f"{dist}={importlib.metadata.version(dist)}".encode())
        except importlib.metadata.PackageNotFoundError:
            h.update(f"{dist}=none".encode())
    name = f"{id}-{hashlib.sha256(family.encode()).hexdigest()[:8]}-{h.hexdigest()[:24]}"
    return cache_dir() / "reproductions" / f"{name}.pickle"


def _from_disk(path):
    try:
        with open(path, "rb") as f:
            result = pickle.load(f)
    except Exception:  # noqa: BLE001 - missing or unreadable: computed again
        return None
    if not isinstance(result, Result):
        return None
    result.from_cache = True
    return result


def _to_disk(id, path, result):
    """Store ``result`` at ``path``; the ID's entries for other code, of every family, are
    removed (so the cache does not grow with every edit of the package)."""
    try:
        blob = pickle.dumps(result, protocol=pickle.HIGHEST_PROTOCOL)
    except (pickle.PicklingError, TypeError, AttributeError):  # kept in memory only
        return
    if not store(path, lambda f: f.write(blob)):
        return
    code = path.stem[-24:]
    for old in path.parent.glob(f"{id}-*.pickle"):
        # (another ID's entry never matches; nor does an entry named before the families,
        # "<id>-<code>", which is removed with the old code's)
        ours = re.fullmatch(re.escape(id) + r"(?:-[0-9a-f]{8})?-([0-9a-f]{24})", old.stem)
        if ours and ours.group(1) != code:
            old.unlink(missing_ok=True)
            old.with_name(old.name + ".lock").unlink(missing_ok=True)  # diskcache.exclusive's


def run(id, out=None, fresh=False, **kwargs):
    """Run the reproduction ``id`` and return its :class:`Result`.

    Results without ``out`` are cached for the session (each call gets its own copy), so a
    chapter that plots a reproduction's data and then asserts its numbers computes it once; they
    are also kept on disk for the same code and arguments (see the module docs), so the
    chapters, the tests and the dashboard compute each once between them.

    Parameters
    ----------
    id : str
        A registered ID (see :func:`ids`).
    out : str or os.PathLike, optional
        Folder for the figures; created if missing (a file there is refused). ``None`` writes none.
    fresh : bool, optional
        True or False (a string is refused): compute it even when a result is cached (in
        this session or on disk), and store the new one.
    **kwargs
        Passed to the reproduction (for example ``seed``): only the keywords its function
        takes (another is refused, naming them); a list or array is passed as a tuple.

    Examples
    --------
    >>> run("mallat-vs-pywavelets").verdict
    'CHECK'
    """
    rep = get(id)
    fresh = check_bool("fresh", fresh)
    takes = [p.name for p in inspect.signature(rep.func).parameters.values()
             if p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY) and p.name != "out"]
    kwargs = check_keywords(f"the reproduction {id!r}", kwargs, takes)
    kwargs = {k: _items(v) for k, v in kwargs.items()}  # a list keys as the equal tuple
    if out is not None:
        out = _folder("out", out, create=True)
    key = _session_key(id, kwargs) if out is None else None
    if key in _CACHE and not fresh:
        return copy.deepcopy(_CACHE[key])
    on_disk = (out is None and rep.cache and all(_plain(v) for v in kwargs.values())
               and _disk_on())
    path = _disk_path(id, kwargs) if on_disk else None
    # another process computing the same result (pytest -n 2, the book's kernels): wait, read
    with contextlib.nullcontext() if path is None else exclusive(path):
        result = None if (path is None or fresh) else _from_disk(path)
        if result is None:
            result = rep.func(out=out, **kwargs)
            if path is not None:
                _to_disk(id, path, result)
    if key is not None:  # a copy: a caller editing the result it was given changes no later call
        with contextlib.suppress(TypeError, copy.Error):  # one that cannot be copied: not kept
            _CACHE[key] = copy.deepcopy(result)
    return result


def run_or_fail(id, out=None, **kwargs):
    """Like :func:`run`, but an exception becomes an `ERROR` result instead of propagating.

    The command line's ``--all`` and the dashboard run every reproduction through this
    function, so a reproduction that raises is counted and shown the same way in both:
    one check "ran without error" that failed, and ``error`` set. A figure that cannot be
    written under ``out`` (an :class:`OutputError`, or a full disk's ``OSError``) is raised:
    the caller's folder failed, not the reproduction.

    Examples
    --------
    >>> res = run_or_fail("no-such-id")
    >>> res.verdict, res.error.startswith("ValueError")
    ('ERROR', True)
    """
    if not isinstance(id, str):  # the caller's slip, not the reproduction's: raised
        get(id)
    _disk_on()  # a bad cache setting is refused once, not as every reproduction's ERROR
    try:
        return run(id, out=out, **kwargs)
    except OutputError:
        raise
    except OSError as exc:  # a figure written by savefig itself into a full out
        if out is None or exc.errno not in (errno.ENOSPC, errno.EDQUOT):
            return _failed(id, exc)
        raise OutputError(f"out {str(out)!r} cannot be written ({exc.strerror})") from None
    except Exception as exc:  # noqa: BLE001 - reported as the ERROR of that reproduction
        return _failed(id, exc)


def _failed(id, exc):
    """The ERROR result of the reproduction ``id`` that raised ``exc``."""
    error = " ".join(f"{type(exc).__name__}: {exc}".split())
    check = Check("ran without error", "runs", error, "must not raise", CHECK_FAILED)
    return Result(id, [check], note="the reproduction raised an exception", error=error)


def counts(results):
    """The paper's claims and our checks by verdict, over several results (:func:`headline`).

    Returns
    -------
    dict
        ``reproductions`` (how many), ``headlines`` (reproductions by headline, every key of
        :data:`~xnavlab.verdicts.HEADLINES`), ``rows`` (every row by verdict, as :meth:`Result.counts`),
        ``claims`` (rows that are claims of the paper), ``checks`` (rows that are checks of
        ours), ``distinct`` (the paper's distinct claims by verdict, :meth:`Result.claim_counts`:
        a claim that takes several rows counts once), ``n_distinct`` (their number) and
        ``errors`` (the IDs whose headline is `ERROR`, in order).

    Examples
    --------
    >>> ok = Result("a", [check_rel("x", 1.0, 1.0, 0.1, why="w"), check_measure("y", 2, "shown")])
    >>> n = counts([ok, run_or_fail("no-such-id")])
    >>> n["claims"], n["checks"], n["errors"]
    (1, 2, ['no-such-id'])
    """
    results = _results(results)
    rows = dict.fromkeys(VERDICTS, 0)
    heads = dict.fromkeys(HEADLINES, 0)
    distinct = dict.fromkeys(CLAIM_VERDICTS, 0)
    for res in results:
        heads[res.verdict] += 1
        for verdict, n in res.counts().items():
            rows[verdict] += n
        for verdict, n in res.claim_counts().items():
            distinct[verdict] += n
    return {"reproductions": len(results), "headlines": heads, "rows": rows,
            "claims": sum(rows[v] for v in CLAIM_VERDICTS),
            "checks": rows[CHECK] + rows[CHECK_FAILED],
            "distinct": distinct, "n_distinct": sum(distinct.values()),
            "errors": [r.id for r in results if r.verdict == ERROR]}


def _plural(n, word):
    return f"{n} {word}" if n == 1 else f"{n} {word}s"


def headline(results):
    """The one sentence that counts the claims and the checks (the CLI's ``--all``, the dashboard).

    It counts the papers' distinct claims (a claim that takes several rows counts once,
    :meth:`Result.claim_verdicts`), then the rows that judge them when there are more.

    Examples
    --------
    >>> ok = Result("a", [check_rel("x", 1.0, 1.0, 0.1, why="w"), check_measure("y", 2, "shown")])
    >>> headline([ok])
    '1 of 1 paper claim reproduced (0 not reproduced, 0 undecided); 1 of 1 check holds'
    >>> two = Result("b", part_of("z", check_rel("z1", 1.0, 1.0, 0.1, why="w"),
    ...                           check_rel("z2", 1.0, 1.0, 0.1, why="w")))
    >>> headline([ok, two])
    '2 of 2 paper claims reproduced (0 not reproduced, 0 undecided; judged in 3 rows); 1 of 1 check holds'
    """
    n = counts(results)
    d = n["distinct"]
    rows = f"; judged in {n['claims']} rows" if n["claims"] != n["n_distinct"] else ""
    claims = (f"{d[REPRODUCED]} of {_plural(n['n_distinct'], 'paper claim')} reproduced "
              f"({d[NOT_REPRODUCED]} not reproduced, {d[UNDECIDED]} undecided{rows})")
    r = n["rows"]
    checks = f"{r[CHECK]} of {n['checks']} {'check holds' if n['checks'] == 1 else 'checks hold'}"
    text = f"{claims}; {checks}"
    return text + (f"; {ERROR}: {', '.join(n['errors'])}" if n["errors"] else "")


#: Columns of the dashboard's table of counts: how many rows of each verdict.
COUNT_HEADER = ("", *VERDICTS)
#: Columns of :func:`summary_rows`: one row per reproduction.
SUMMARY_HEADER = ("reproduction", "verdict", "claims reproduced", "not reproduced",
                  "undecided", "checks holding", "chapter", "what")
#: Columns of :func:`check_rows`: one row per check.
CHECK_HEADER = ("reproduction", "quantity", "paper", "ours", "tolerance", "verdict", "reading")


def summary_rows(results):
    """One row per result (columns :data:`SUMMARY_HEADER`), for :func:`~xnavlab.core.plotting.html_table`."""
    rows = []
    for res in _results(results):
        n = res.counts()
        try:
            rep = get(res.id)
            chapter, title = rep.chapter, rep.title
        except ValueError:
            chapter, title = "", ""
        k = res.claim_counts()
        rows.append((res.id, res.verdict, f"{k[REPRODUCED]} of {sum(k.values())}", k[NOT_REPRODUCED],
                     k[UNDECIDED], f"{n[CHECK]} of {n[CHECK] + n[CHECK_FAILED]}", chapter, title))
    return rows


def check_rows(results):
    """One row per check (columns :data:`CHECK_HEADER`), values formatted for a table."""
    return [(res.id, c.name, show(c.paper), show(c.ours), c.tolerance, c.verdict, c.reading)
            for res in _results(results) for c in res.checks]


def report_html(results, elapsed_s=None):
    """Every result on one page (the dashboard): the headline, the counts, a summary, every row.

    Built only from :func:`headline`, :func:`counts`, :func:`summary_rows`, :func:`check_rows`
    and :func:`~xnavlab.core.plotting.html_table`, the same words and counts as the command
    line; every cell and note is escaped text. The notes (the choices behind each
    reproduction) follow in a collapsed ``<details>`` block.

    Parameters
    ----------
    results : sequence of Result
        As returned by :func:`run_or_fail`, in the order to show.
    elapsed_s : float, optional
        Seconds it took to compute them, stated under the headline when given.

    Returns
    -------
    SafeHTML

    Examples
    --------
    >>> row = check_rel("x|y", 1.0, 1.0, 0.1, why="w")
    >>> page = report_html([Result("a", [row], note="a < b")])
    >>> "1 of 1 paper claim reproduced" in page, "x|y" in page
    (True, True)
    """
    results = _results(results)
    if elapsed_s is not None:
        elapsed_s = check_real("elapsed_s", elapsed_s, 0.0)
    reused = sum(r.from_cache for r in results)
    when = "" if elapsed_s is None else f" (computed when the book was built, in {elapsed_s:.0f} s)"
    if elapsed_s is not None and reused:
        when = (f" (when the book was built, in {elapsed_s:.0f} s: {len(results) - reused} "
                f"computed, {reused} read from the reproduction cache, computed earlier by the "
                "same code on this machine)")
    n = counts(results)
    claims = [n["distinct"][v] if v in CLAIM_VERDICTS else "" for v in VERDICTS]
    rows = [n["rows"][v] if v in CLAIM_VERDICTS else "" for v in VERDICTS]
    checks = [n["rows"][v] if v not in CLAIM_VERDICTS else "" for v in VERDICTS]
    parts = [f'<p class="xnav-headline"><strong>{html.escape(headline(results))}</strong>'
             f"{html.escape(when)}.</p>",
             html_table(COUNT_HEADER, [("claims of the papers", *claims),
                                       ("rows judging them (a claim may take several)", *rows),
                                       ("checks of ours (not reproductions)", *checks)]),
             "<p><strong>Every reproduction</strong></p>",
             html_table(SUMMARY_HEADER, summary_rows(results)),
             "<p><strong>Every row</strong></p>",
             html_table(CHECK_HEADER, check_rows(results))]
    notes = []
    for res in results:
        try:
            source = f" ({get(res.id).source})"
        except ValueError:
            source = ""
        text = " ".join(res.note.split())
        if res.error:
            text = f"raised {res.error}. {text}"
        notes.append(f"<li><strong>{html.escape(res.id)}</strong>{html.escape(source)}: "
                     f"{html.escape(text)}</li>")
    if notes:
        parts.append('<details class="xnav-notes"><summary>Sources, and the choices behind'
                     " each reproduction (their notes)</summary>\n<ul>\n" + "\n".join(notes)
                     + "\n</ul>\n</details>")
    return SafeHTML("\n".join(parts))


def summary_box(results, title="Reproducing the paper: the verdicts"):
    """A chapter's closing box: per claim, what the paper claimed, what we got, the verdict, why.

    HTML in the admonition style of the book's theme (it renders the same in the HTML book and
    in JupyterLab). Per reproduction its headline; per claim two or three lines: the claim and
    the paper's value, ours, the verdict and why in brief (:meth:`Check.brief
    <xnavlab.verdicts.Check.brief>`: the criterion, where the paper's number falls, what would
    decide it); the reproduction's table (its ``_repr_html_``, shown after the box) keeps the
    whole tolerance and reading. The checks of ours are counted in one line, never listed as
    reproductions.

    Parameters
    ----------
    results : sequence of Result
        The chapter's reproductions, in the order to show.
    title : str, optional
        The box's title.

    Returns
    -------
    SafeHTML

    Examples
    --------
    >>> res = Result("a", [check_rel("x (m)", 1.0, 1.02, 0.05, why="two digits"),
    ...                    check_sanity("y", "> 0", 1.0, True, "positive")])
    >>> box = summary_box([res])
    >>> "REPRODUCED" in box, "1 check of ours holds" in box
    (True, True)
    """
    results, title = _results(results), check_text("title", title)
    items = []
    for res in results:
        lines = []
        for c in res.claims:
            lines.append(
                f"<li><strong>{html.escape(c.name)}</strong>: the paper "
                f"{html.escape(show(c.paper))}, ours {html.escape(show(c.ours))}. "
                f'<span class="xnav-verdict">{c.verdict}</span>: {html.escape(c.brief())}.</li>')
        n = res.counts()
        held, total = n[CHECK], n[CHECK] + n[CHECK_FAILED]
        if total:
            word = "check of ours holds" if held == 1 else "checks of ours hold"
            lines.append(f"<li>{held} of {total} {word} (not claims of the paper).</li>")
        if res.error:
            lines.append(f"<li>raised {html.escape(res.error)}</li>")
        items.append(f"<p><strong>{html.escape(res.id)}</strong>: "
                     f'<span class="xnav-verdict">{res.verdict}</span></p>\n<ul>\n'
                     + "\n".join(lines) + "\n</ul>")
    return SafeHTML('<div class="admonition important xnav-summary">\n'
                    f'<p class="admonition-title">{html.escape(title)}</p>\n'
                    + "\n".join(items) + "\n</div>")


def results_table(results):
    """Plain-text table of the rows of several results (columns :data:`CHECK_HEADER`)."""
    rows = [CHECK_HEADER] + [tuple(" ".join(str(v).split()) for v in row)
                             for row in check_rows(results)]
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    return "\n".join("  ".join(s.ljust(w) for s, w in zip(r, widths, strict=True)).rstrip()
                     for r in rows)


def jsonable(x):
    """``json.dumps`` fallback: NumPy scalars and arrays as Python numbers and lists."""
    try:
        import numpy as np

        if isinstance(x, np.generic):
            return x.item()
        if isinstance(x, np.ndarray):
            return x.tolist()
    except ImportError:  # pragma: no cover
        pass
    return str(x)
