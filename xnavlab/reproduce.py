"""The registry of reproductions: every paper number the book claims, computed in one place.

A *reproduction* is a function registered under an ID (``"xnav-ranging"``,
``"mars-nofault"``, ...) that recomputes one figure or table of a source paper and
returns a :class:`Result` holding the paper's values, ours, the tolerance and the
verdict. The chapters' last cells, ``tests/`` and the command line
(``python -m xnavlab reproduce ID``) all call :func:`run`, so a number is computed
by exactly one piece of code.

Reproductions live in the modules of :mod:`xnavlab.reproductions`; each module is
imported on first use of the registry, so adding a file there is all it takes to
register new IDs.
"""

from __future__ import annotations

import importlib
import json
import math
import pkgutil
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from xnavlab.core.plotting import figure

__all__ = [
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
    "results_table",
    "figure",
    "save_figure",
    "jsonable",
]


@dataclass(frozen=True)
class Check:
    """One comparison: a quantity, the paper's value, ours, the tolerance, the verdict.

    ``claimed=False`` marks a row we show but do not claim to reproduce (see
    :func:`check_info`); it does not count towards the verdict.
    """

    name: str
    paper: Any
    ours: Any
    tolerance: str
    passed: bool
    claimed: bool = True

    @property
    def verdict(self):
        """``"PASS"``, ``"FAIL"``, or ``"NOT CLAIMED"`` for an informational row."""
        if not self.claimed:
            return "NOT CLAIMED"
        return "PASS" if self.passed else "FAIL"


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
    """

    id: str
    checks: list[Check]
    note: str = ""
    data: dict[str, Any] = field(default_factory=dict, repr=False)
    figures: list[str] = field(default_factory=list)

    @property
    def passed(self):
        claimed = [c for c in self.checks if c.claimed]
        return bool(claimed) and all(c.passed for c in claimed)

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
        """The JSON form: ``id``, ``paper``, ``ours``, ``tolerance``, ``pass``, ``note``."""
        return {
            "id": self.id,
            "paper": self.paper,
            "ours": self.ours,
            "tolerance": self.tolerance,
            "pass": self.passed,
            "checks": {c.name: c.verdict for c in self.checks},
            "note": self.note,
            "figures": self.figures,
        }

    def to_json(self):
        return json.dumps(self.to_dict(), default=jsonable)

    def table(self):
        """A plain-text table: quantity, paper, ours, tolerance, verdict."""
        return results_table([self])

    def _repr_markdown_(self):
        lines = [
            f"**{self.id}**: {'PASS' if self.passed else 'FAIL'}",
            "",
            "| quantity | paper | ours | tolerance | pass |",
            "|---|---|---|---|---|",
        ]
        for c in self.checks:
            lines.append(
                f"| {c.name} | {_show(c.paper)} | {_show(c.ours)} | {c.tolerance} | "
                f"{c.verdict.lower()} |"
            )
        if self.note:
            lines += ["", self.note]
        return "\n".join(lines)

    def assert_passed(self):
        """Raise ``AssertionError`` listing every failed check."""
        if not self.passed:
            raise AssertionError(f"{self.id} failed:\n" + results_table([self]))


@dataclass(frozen=True)
class Reproduction:
    """A registered reproduction: its ID, what it reproduces, and the function that runs it."""

    id: str
    title: str
    source: str
    chapter: str
    func: Callable[..., Result]


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


def register(id, *, title, source, chapter):
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
    """

    def deco(func):
        if id in _REGISTRY and _REGISTRY[id].func is not func:
            raise ValueError(f"reproduction {id!r} is registered twice")
        _REGISTRY[id] = Reproduction(id, title, source, chapter, func)
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


def run(id, out=None, **kwargs):
    """Run the reproduction ``id`` and return its :class:`Result`.

    Results without ``out`` are cached for the session, so a chapter that plots a
    reproduction's data and then asserts its numbers computes it once.

    Parameters
    ----------
    id : str
        A registered ID (see :func:`ids`).
    out : str or Path, optional
        Directory for the figures; created if missing. ``None`` writes none.
    **kwargs
        Passed to the reproduction (for example ``seed``).
    """
    rep = get(id)
    key = (id, tuple(sorted(kwargs.items())))
    if out is None and key in _CACHE:
        return _CACHE[key]
    if out is not None:
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
    result = rep.func(out=out, **kwargs)
    if out is None:
        _CACHE[key] = result
    return result


def results_table(results):
    """Plain-text table of the checks of several results."""
    rows = [("id", "quantity", "paper", "ours", "tolerance", "pass")]
    for res in results:
        for c in res.checks:
            rows.append(
                (res.id, c.name, _show(c.paper), _show(c.ours), c.tolerance, c.verdict)
            )
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    return "\n".join("  ".join(s.ljust(w) for s, w in zip(r, widths, strict=True)) for r in rows)


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
