"""The registry of reproductions: every paper number the book claims, computed in one place.

A *reproduction* is a function registered under an ID (``"xnav-ranging"``,
``"mars-nofault"``, ...) that recomputes one figure or table of a source paper and
returns a :class:`Result` holding the paper's values, ours, the tolerance and the
verdict. The chapters' last cells, ``tests/`` and the command line
(``python -m xnavlab reproduce ID``) all call :func:`run`, so a number is computed
by exactly one piece of code.

A reproduction's result is kept on disk, under ``$XNAVLAB_CACHE/reproductions`` (default
``~/.cache/xnavlab``), keyed by the ID, its arguments, every file of the package (code and
shipped data), the numeric libraries' versions and ``OPENBLAS_CORETYPE``: the same code on the
same machine gives the same numbers (the seeds are fixed), so a chapter, a test and the
dashboard that ask for the same reproduction compute it once between them. Each ID keeps one
entry per set of arguments and BLAS kernel family (a chapter's shortened run beside the full
one, a ``make portability`` run beside the default kernels); the first entry stored for a new
version of the code removes the ID's entries for the old one. Computed afresh: a run with
``out``, with ``fresh=True`` or with an argument that is not a plain number, string or tuple
of them, a reproduction registered with ``cache=False`` (a measured timing), and every run
under ``XNAVLAB_REPRODUCE_CACHE=0``.

Reproductions live in the modules of :mod:`xnavlab.reproductions`; each module is
imported on first use of the registry, so adding a file there is all it takes to
register new IDs.

One verdict vocabulary (:data:`VERDICTS`) is used by every table that shows a
reproduction: a chapter's last cell, the command line, its JSON and the dashboard.

``PASS``
    A claimed number within its stated tolerance.
``NOT CLAIMED``
    A number measured and shown beside the paper's, with the reason it is not claimed
    (:func:`check_info`); it never decides a verdict.
``FAIL``
    A claimed number out of its tolerance. It fails the tests.

A row's verdict is its :class:`Check`'s; a :class:`Result`'s verdict is ``FAIL`` when any
claimed check fails, when it has no claimed check, or when the reproduction raised
(:func:`run_or_fail`), and ``PASS`` otherwise. :func:`headline` is the one sentence that
counts them, printed by ``python -m xnavlab reproduce --all`` and shown by the dashboard.
"""

from __future__ import annotations

import hashlib
import html
import importlib
import importlib.metadata
import json
import math
import os
import pickle
import pkgutil
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from xnavlab.core.diskcache import cache_dir, source_digest, store
from xnavlab.core.plotting import SafeHTML, figure, html_table

__all__ = [
    "PASS",
    "NOT_CLAIMED",
    "FAIL",
    "VERDICTS",
    "Check",
    "Reproduction",
    "Result",
    "register",
    "ids",
    "get",
    "run",
    "check_rel",
    "check_abs",
    "check_range",
    "check_true",
    "check_info",
    "run_or_fail",
    "CACHE_ENV",
    "counts",
    "headline",
    "results_table",
    "summary_rows",
    "check_rows",
    "report_html",
    "SUMMARY_HEADER",
    "CHECK_HEADER",
    "figure",
    "save_figure",
    "jsonable",
]


#: A claimed number within its stated tolerance.
PASS = "PASS"
#: Measured and shown, with the reason it is not claimed; never decides a verdict.
NOT_CLAIMED = "NOT CLAIMED"
#: A claimed number out of its tolerance (fails the tests).
FAIL = "FAIL"
#: The one verdict vocabulary of every reproduction table, in this order.
VERDICTS = (PASS, NOT_CLAIMED, FAIL)


@dataclass(frozen=True)
class Check:
    """One comparison: a quantity, the paper's value, ours, the tolerance, the verdict.

    ``claimed=False`` marks a row we show but do not claim to reproduce (see
    :func:`check_info`); it does not count towards the verdict. For such a row,
    ``tolerance`` holds the reason it is not claimed.
    """

    name: str
    paper: Any
    ours: Any
    tolerance: str
    passed: bool
    claimed: bool = True

    @property
    def verdict(self):
        """`PASS`, `FAIL`, or `NOT_CLAIMED` for an informational row (see `VERDICTS`)."""
        if not self.claimed:
            return NOT_CLAIMED
        return PASS if self.passed else FAIL


def check_rel(name, paper, ours, rel):
    """Pass when ``|ours - paper| <= rel * |paper|``.

    Examples
    --------
    >>> check_rel("B0531+21", 109.0, 111.0, 0.05).passed
    True
    """
    ok = math.isfinite(ours) and abs(ours - paper) <= rel * abs(paper)
    return Check(name, paper, float(ours), f"within {rel:.0%} of the paper", bool(ok))


def check_abs(name, paper, ours, tol, unit=""):
    """Pass when ``|ours - paper| <= tol``.

    Examples
    --------
    >>> check_abs("improvement", 67.4, 60.0, 10.0, "pp").passed
    True
    """
    ok = math.isfinite(ours) and abs(ours - paper) <= tol
    return Check(name, paper, float(ours), f"within {tol:g} {unit}".rstrip(), bool(ok))


def check_range(name, paper, ours, lo, hi, tolerance):
    """Pass when ``lo <= ours <= hi``; ``tolerance`` says in words why those bounds.

    Examples
    --------
    >>> check_range("position_error_m", 28.8, 40.0, 14.4, 57.7, "factor of 2").passed
    True
    """
    ok = math.isfinite(ours) and lo <= ours <= hi
    return Check(name, paper, float(ours), tolerance, bool(ok))


def check_true(name, paper, ours, condition, tolerance):
    """A qualitative check (e.g. "isolated as the x gyro"): pass when ``condition`` holds.

    Examples
    --------
    >>> check_true("isolated", "x gyro", "x gyro", True, "same sensor").passed
    True
    """
    return Check(name, paper, ours, tolerance, bool(condition))


def check_info(name, paper, ours, why):
    """A row shown beside the paper's value that we do not claim to reproduce.

    Use it where ours differs from the paper for a stated reason (``why``), so the
    difference is visible in every table and in the dashboard instead of hidden.

    Examples
    --------
    >>> c = check_info("ranking", "RKF best", "ASUKF best", "not reproduced: see note")
    >>> c.verdict
    'NOT CLAIMED'
    """
    return Check(name, paper, ours, why, passed=False, claimed=False)


@dataclass
class Result:
    """What a reproduction returns.

    Attributes
    ----------
    id : str
        The reproduction ID.
    checks : list of Check
        The asserted comparisons; the reproduction passes when all pass.
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
    """

    id: str
    checks: list[Check]
    note: str = ""
    data: dict[str, Any] = field(default_factory=dict, repr=False)
    figures: list[str] = field(default_factory=list)
    error: str = ""
    #: True when this result was read from the disk cache (computed earlier by the same code)
    from_cache: bool = field(default=False, compare=False)

    @property
    def verdict(self):
        """`FAIL` if a claimed check fails, none is claimed or it raised; else `PASS`.

        Examples
        --------
        >>> Result("demo", [check_rel("x", 1.0, 1.02, 0.05)]).verdict
        'PASS'
        >>> Result("demo", [check_info("y", "a", "b", "see note")]).verdict
        'FAIL'
        """
        claimed = [c for c in self.checks if c.claimed]
        ok = bool(claimed) and all(c.passed for c in claimed) and not self.error
        return PASS if ok else FAIL

    @property
    def passed(self):
        """Whether the verdict is `PASS`."""
        return self.verdict == PASS

    def counts(self):
        """Rows by verdict: ``{"PASS": n, "NOT CLAIMED": n, "FAIL": n}`` (every key present).

        Examples
        --------
        >>> rows = [check_rel("x", 1.0, 1.0, 0.1), check_info("y", "a", "b", "see note")]
        >>> Result("demo", rows).counts()
        {'PASS': 1, 'NOT CLAIMED': 1, 'FAIL': 0}
        """
        out = dict.fromkeys(VERDICTS, 0)
        for c in self.checks:
            out[c.verdict] += 1
        return out

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

        Keys: ``id``, ``verdict`` (`PASS` or `FAIL`), ``pass`` (the same as a bool),
        ``checks`` (each quantity's verdict), ``counts`` (rows by verdict), ``paper``,
        ``ours``, ``tolerance`` (by quantity), ``note``, ``figures``, ``error``.
        """
        return {
            "id": self.id,
            "verdict": self.verdict,
            "paper": self.paper,
            "ours": self.ours,
            "tolerance": self.tolerance,
            "pass": self.passed,
            "checks": {c.name: c.verdict for c in self.checks},
            "counts": self.counts(),
            "note": self.note,
            "figures": self.figures,
            "error": self.error,
        }

    def to_json(self):
        return json.dumps(self.to_dict(), default=jsonable)

    def table(self):
        """A plain-text table: id, quantity, paper, ours, tolerance, verdict."""
        return results_table([self])

    def html(self):
        """The result as safe HTML: its verdict, a table of its checks, its note.

        Every cell and the note are escaped text (a ``|``, ``<`` or newline in a value
        cannot break the table); the table has the columns :data:`CHECK_HEADER` without
        the reproduction's ID.

        Examples
        --------
        >>> page = Result("demo", [check_abs("a|b", 1.0, 1.5, 1.0)], note="x < y").html()
        >>> page.count("<td>"), "a|b" in page, "x &lt; y" in page
        (5, True, True)
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

    def assert_passed(self):
        """Raise ``AssertionError`` listing every check when the verdict is `FAIL`."""
        if not self.passed:
            raise AssertionError(f"{self.id}: {FAIL}\n" + results_table([self])
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


def save_figure(fig, out, name):
    """Lay out ``fig`` and write it as ``out / (name + ".png")`` at 100 dpi; return the path.

    Examples
    --------
    >>> import tempfile
    >>> fig, ax = figure()
    >>> with tempfile.TemporaryDirectory() as d:
    ...     save_figure(fig, d, "x").endswith("x.png")
    True
    """
    fig.tight_layout()
    path = Path(out) / f"{name}.png"
    fig.savefig(path, dpi=100)
    return str(path)


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
    _load_all()
    if id not in _REGISTRY:
        known = ", ".join(sorted(_REGISTRY))
        raise ValueError(f"unknown reproduction id {id!r}; known ids: {known}")
    return _REGISTRY[id]


_CACHE: dict[tuple, Result] = {}

#: Set to ``"0"`` to compute every reproduction afresh instead of reading the disk cache.
CACHE_ENV = "XNAVLAB_REPRODUCE_CACHE"
#: The distributions whose version is part of a cached result's key (the numbers depend on them).
_DEPENDS = ("numpy", "scipy", "numba", "PyWavelets", "jplephem", "de421", "de405", "pint-pulsar")
_PACKAGE = Path(__file__).resolve().parent


def _plain(value):
    """Whether ``value`` has a ``repr`` that names it exactly (an argument a key may hold)."""
    if isinstance(value, tuple):
        return all(_plain(v) for v in value)
    return value is None or type(value) in (bool, int, float, str)


def _disk_path(id, kwargs):
    """``<id>-<family>-<code>.pickle``: the family is the arguments and the BLAS kernels (each
    keeps its entry), the code is the package's files and the numeric libraries' versions."""
    family = repr((id, sorted(kwargs.items()), os.environ.get("OPENBLAS_CORETYPE", "")))
    h = hashlib.sha256(repr((2, id, source_digest(_PACKAGE))).encode())
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


def run(id, out=None, fresh=False, **kwargs):
    """Run the reproduction ``id`` and return its :class:`Result`.

    Results without ``out`` are cached for the session, so a chapter that plots a
    reproduction's data and then asserts its numbers computes it once; they are also kept on
    disk for the same code and arguments (see the module docs), so the chapters, the tests
    and the dashboard compute each once between them.

    Parameters
    ----------
    id : str
        A registered ID (see :func:`ids`).
    out : str or Path, optional
        Directory for the figures; created if missing. ``None`` writes none.
    fresh : bool, optional
        Compute it even when a result is cached (in this session or on disk), and store the
        new one.
    **kwargs
        Passed to the reproduction (for example ``seed``).
    """
    rep = get(id)
    key = (id, tuple(sorted(kwargs.items())))
    if out is None and key in _CACHE and not fresh:
        return _CACHE[key]
    on_disk = (out is None and rep.cache and all(_plain(v) for v in kwargs.values())
               and os.environ.get(CACHE_ENV, "1") != "0")
    path = _disk_path(id, kwargs) if on_disk else None
    result = None if (path is None or fresh) else _from_disk(path)
    if result is None:
        if out is not None:
            out = Path(out)
            out.mkdir(parents=True, exist_ok=True)
        result = rep.func(out=out, **kwargs)
        if path is not None:
            _to_disk(id, path, result)
    if out is None:
        _CACHE[key] = result
    return result


def run_or_fail(id, out=None, **kwargs):
    """Like :func:`run`, but an exception becomes a `FAIL` result instead of propagating.

    The command line's ``--all`` and the dashboard run every reproduction through this
    function, so a reproduction that raises is counted and shown the same way in both:
    one claimed check "ran without error" that fails, and ``error`` set.

    Examples
    --------
    >>> res = run_or_fail("no-such-id")
    >>> res.verdict, res.error.startswith("ValueError")
    ('FAIL', True)
    """
    try:
        return run(id, out=out, **kwargs)
    except Exception as exc:  # noqa: BLE001 - reported as the FAIL of that reproduction
        error = " ".join(f"{type(exc).__name__}: {exc}".split())
        check = Check("ran without error", "runs", error, "must not raise", False)
        return Result(id, [check], note="the reproduction raised an exception", error=error)


def counts(results):
    """Reproductions and rows by verdict, the numbers of :func:`headline`.

    Returns
    -------
    dict
        ``reproductions`` (how many), ``pass`` (how many with verdict `PASS`), ``fail``
        (the IDs with verdict `FAIL`, in order) and ``rows`` (every check row by verdict,
        as :meth:`Result.counts`).

    Examples
    --------
    >>> ok = Result("a", [check_rel("x", 1.0, 1.0, 0.1), check_info("y", 1, 2, "why")])
    >>> counts([ok, Result("b", [])])["fail"]
    ['b']
    """
    rows = dict.fromkeys(VERDICTS, 0)
    for res in results:
        for verdict, n in res.counts().items():
            rows[verdict] += n
    return {"reproductions": len(results), "pass": sum(r.passed for r in results),
            "fail": [r.id for r in results if not r.passed], "rows": rows}


def headline(results):
    """The one sentence that counts the verdicts (the CLI's ``--all`` and the dashboard).

    Examples
    --------
    >>> ok = Result("a", [check_rel("x", 1.0, 1.0, 0.1), check_info("y", 1, 2, "why")])
    >>> headline([ok, Result("b", [])])
    '1 of 2 reproductions pass (1 row not claimed); FAIL: b'
    """
    n = counts(results)
    k = n["rows"][NOT_CLAIMED]
    text = (f"{n['pass']} of {n['reproductions']} reproductions pass"
            f" ({k} row{'' if k == 1 else 's'} not claimed)")
    return text + (f"; {FAIL}: {', '.join(n['fail'])}" if n["fail"] else "")


#: Columns of :func:`summary_rows`: one row per reproduction.
SUMMARY_HEADER = ("reproduction", "verdict", "claimed checks passing", "not claimed",
                  "chapter", "what")
#: Columns of :func:`check_rows`: one row per check.
CHECK_HEADER = ("reproduction", "quantity", "paper", "ours", "tolerance", "verdict")


def summary_rows(results):
    """One row per result (columns :data:`SUMMARY_HEADER`), for :func:`~xnavlab.core.plotting.html_table`."""
    rows = []
    for res in results:
        n = res.counts()
        try:
            rep = get(res.id)
            chapter, title = rep.chapter, rep.title
        except ValueError:
            chapter, title = "", ""
        claimed = n[PASS] + n[FAIL]
        rows.append((res.id, res.verdict, f"{n[PASS]} of {claimed}", n[NOT_CLAIMED], chapter,
                     title))
    return rows


def check_rows(results):
    """One row per check (columns :data:`CHECK_HEADER`), values formatted for a table."""
    return [(res.id, c.name, _show(c.paper), _show(c.ours), c.tolerance, c.verdict)
            for res in results for c in res.checks]


def report_html(results, elapsed_s=None):
    """Every result on one page (the dashboard): the headline, a summary table, every check.

    Built only from :func:`headline`, :func:`summary_rows`, :func:`check_rows` and
    :func:`~xnavlab.core.plotting.html_table`, the same words and counts as the command line;
    every cell and note is escaped text. The notes (the choices behind each reproduction)
    follow in a collapsed ``<details>`` block.

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
    >>> page = report_html([Result("a", [check_rel("x|y", 1.0, 1.0, 0.1)], note="a < b")])
    >>> "1 of 1 reproductions pass (0 rows not claimed)" in page, "x|y" in page
    (True, True)
    """
    reused = sum(r.from_cache for r in results)
    when = "" if elapsed_s is None else f" (computed when the book was built, in {elapsed_s:.0f} s)"
    if elapsed_s is not None and reused:
        when = (f" (when the book was built, in {elapsed_s:.0f} s: {len(results) - reused} "
                f"computed, {reused} read from the reproduction cache, computed earlier by the "
                "same code on this machine)")
    parts = [f'<p class="xnav-headline"><strong>{html.escape(headline(results))}</strong>'
             f"{html.escape(when)}.</p>",
             html_table(SUMMARY_HEADER, summary_rows(results)),
             "<p><strong>Every check</strong></p>",
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


def results_table(results):
    """Plain-text table of the checks of several results (columns :data:`CHECK_HEADER`)."""
    rows = [CHECK_HEADER] + [tuple(" ".join(str(v).split()) for v in row)
                             for row in check_rows(results)]
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    return "\n".join("  ".join(s.ljust(w) for s, w in zip(r, widths, strict=True)).rstrip()
                     for r in rows)


def _show(x):
    if isinstance(x, float):
        return f"{x:.4g}"
    return str(x)


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
