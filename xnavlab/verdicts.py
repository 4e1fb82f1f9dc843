"""The verdicts of the reproductions: one vocabulary, and the rows that judge a paper's claims.

A reproduction (:mod:`xnavlab.reproduce`) returns rows (:class:`Check`), each the paper's value
beside ours, the tolerance with its reason, and a verdict. This module holds the vocabulary and
the constructors of the rows; :mod:`xnavlab.reproduce` holds the registry, the results and
their tables, and re-exports these names (``reproduce.check_rel`` is this ``check_rel``).

Claims and checks
-----------------
One vocabulary (:data:`VERDICTS`) is used by every table that shows a reproduction: a
chapter's last cell and its summary box, the command line, its JSON and the dashboard. A row
is either a *claim* of the paper, judged against our numbers, or a *check* of ours, which is
never counted as a reproduction.

``REPRODUCED``
    The paper's claim holds within a stated tolerance, whose reason is written beside it. For
    a number the paper reports from one run, the tolerance is our own spread: the paper's
    number must fall inside the 95 % range of at least 32 of our single runs
    (:func:`check_draw`).
``NOT REPRODUCED``
    Our numbers contradict the claim; the row says by how much.
``UNDECIDED``
    The claim is inside our noise (an ordering whose paired difference is not resolved by our
    runs, :func:`check_order`); the row says about how many runs would decide it.
``CHECK``
    Not a claim of the paper: a sanity or consistency check of ours that holds, or an extra
    measurement shown beside the paper's (where the paper gives no number).
``CHECK FAILED``
    A check of ours that does not hold: a defect, which fails the tests.

A claim decided by a parameter the paper lost
---------------------------------------------
Some of the papers' numbers are set by a parameter the paper does not give (a fault's size
or rate, a threshold, the direction of an error, a filter's tuning), which we had to choose.
Where we ran the lost parameter's plausible values, one rule applies, whatever its effect
against our noise (:func:`check_lost`): the claim is judged over those values, one lost
setting varied at a time (each setting's range is our single-run range shifted by that
setting's measured effect), and

* REPRODUCED when the paper's number lies inside our range at every plausible value: the
  tolerance spans the lost parameter, and says so;
* UNDECIDED when some plausible value reaches it and others do not, or when no plausible value
  reaches it but it lies outside what they reach by no more than the lost parameter's own
  spread (the largest minus the smallest of its shifts of our range, our noise not included:
  a value we did not run, or a lost parameter we could not vary, such as an orbit, may move it
  that far): the reading names the lost parameter, what our values reach, and what would
  decide it (the paper's value of that parameter);
* NOT REPRODUCED only when no plausible value reaches it, by more than that spread.

The row's tolerance says, from the numbers, whether the lost parameter moves ours further than
our noise (its spread against the width of our own range) or less; the rule is the same either
way. An outcome the paper shows from one run (yes or no, :func:`check_event`) is judged over a
lost parameter's values by the same rule (:func:`check_event_lost`): REPRODUCED when it is an
ordinary draw at every value, UNDECIDED at some, NOT REPRODUCED at none (the margin is the
spread of our share over the values).

One claim, several rows
-----------------------
A claim of the paper may take several rows (one figure's curves, one table's pulsars, a ranking
and the paired orders it is made of). Rows marked as parts of one claim (:func:`part_of`, the
row's ``claim``) are counted once: the claim is REPRODUCED when every part is, NOT REPRODUCED
when a part is, else UNDECIDED. Counts of "paper claims" (:func:`~xnavlab.reproduce.headline`)
count claims, not rows.

A reproduction's headline (:attr:`~xnavlab.reproduce.Result.verdict`, :data:`HEADLINES`) follows its claims:
``REPRODUCED`` (every claim), ``PARTLY REPRODUCED`` (some claims reproduced, others not or
undecided), ``NOT REPRODUCED`` (claims, none reproduced, at least one refuted), ``UNDECIDED``
(every claim undecided), ``CHECK`` (no claim of the paper: only checks), or ``ERROR`` (it
raised or a check failed). A reproduction that names its main claim
(:attr:`~xnavlab.reproduce.Result.main`) follows it first: when the main claim is not
reproduced, the headline is that claim's verdict (NOT REPRODUCED or UNDECIDED), whatever its
lesser claims say. A result is :attr:`~xnavlab.reproduce.Result.ok` when it has no error and
every check holds: that, and the verdicts recorded in ``tests/test_verdicts.py``, is what the
tests assert; a claim that is not reproduced is an honest result, not a failure.
:func:`~xnavlab.reproduce.headline` is the one sentence that counts the claims and the checks,
printed by ``python -m xnavlab reproduce --all`` and shown by the dashboard.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from xnavlab.core.validate import check_bool, check_finite_array, check_real, check_text

__all__ = [
    "REPRODUCED", "NOT_REPRODUCED", "UNDECIDED", "CHECK", "CHECK_FAILED", "PARTLY_REPRODUCED",
    "ERROR", "CLAIM_VERDICTS", "VERDICTS", "HEADLINES", "MIN_RUNS", "BRIEF_ASIDE", "Check",
    "check_rel", "check_abs", "check_range", "check_true", "check_draw", "check_order",
    "check_sanity", "check_measure", "check_lost", "check_event", "check_event_lost", "part_of",
    "combine", "show",
]


#: The paper's claim holds within a stated, justified tolerance.
REPRODUCED = "REPRODUCED"
#: Our numbers contradict the paper's claim (the row says by how much).
NOT_REPRODUCED = "NOT REPRODUCED"
#: The claim is inside our noise (the row says how many runs would decide it).
UNDECIDED = "UNDECIDED"
#: A check of ours (sanity, consistency, an extra measurement) that holds; not a claim.
CHECK = "CHECK"
#: A check of ours that does not hold: a defect (fails the tests).
CHECK_FAILED = "CHECK FAILED"
#: The verdicts of a claim of the paper.
CLAIM_VERDICTS = (REPRODUCED, NOT_REPRODUCED, UNDECIDED)
#: The one verdict vocabulary of every row of every reproduction table, in this order.
VERDICTS = (*CLAIM_VERDICTS, CHECK, CHECK_FAILED)
#: Headline of a reproduction with some claims reproduced and others not, or undecided.
PARTLY_REPRODUCED = "PARTLY REPRODUCED"
#: Headline of a reproduction that raised, or whose check failed.
ERROR = "ERROR"
#: A reproduction's headline verdict (:attr:`~xnavlab.reproduce.Result.verdict`), in this order.
HEADLINES = (REPRODUCED, PARTLY_REPRODUCED, NOT_REPRODUCED, UNDECIDED, CHECK, ERROR)
#: The fewest of our single runs a paper's single-run number is judged against.
MIN_RUNS = 32
#: The longest aside in parentheses a closing box keeps (:meth:`Check.brief`), characters:
#: longer ones (lists of settings, the reasons for a reading) stay in the table below the box.
BRIEF_ASIDE = 80


@dataclass(frozen=True)
class Check:
    """One row: a quantity, the paper's value, ours, the tolerance with its reason, the verdict.

    Attributes
    ----------
    name : str
        The quantity, with its unit.
    paper : object
        The paper's value (a number, or words where the paper gives words).
    ours : object
        Our value. A NaN or infinity in either (a number, an array's entry) is refused.
    tolerance : str
        The criterion and the reason for it ("within 5 %: the paper prints three digits").
    verdict : str
        One of :data:`VERDICTS`.
    reading : str
        What the numbers say beyond the verdict: where the paper's number falls among our runs,
        by how much ours differs, or how many runs would decide an undecided claim.
    claim : str
        The paper's claim this row is a part of, when one claim takes several rows
        (:func:`part_of`); empty: the row is a claim (or a check) of its own.
    """

    name: str
    paper: Any
    ours: Any
    tolerance: str
    verdict: str
    reading: str = ""
    claim: str = ""

    def __post_init__(self):
        _words("name", self.name)
        _shown("paper", self.paper), _shown("ours", self.ours)
        for label in ("tolerance", "reading", "claim"):
            check_text(label, getattr(self, label))
        if self.verdict not in VERDICTS:
            raise ValueError(f"verdict must be one of {', '.join(VERDICTS)}; got {self.verdict!r}")

    @property
    def claimed(self):
        """Whether the row is a claim of the paper (not a check of ours)."""
        return self.verdict in CLAIM_VERDICTS

    @property
    def ok(self):
        """False only for a check of ours that does not hold (`CHECK_FAILED`)."""
        return self.verdict != CHECK_FAILED

    def sentence(self):
        """The row in one plain sentence, for a chapter's prose (glued, never typed).

        Examples
        --------
        >>> c = check_rel("B0531+21 (m)", 109.0, 111.0, 0.05, why="three digits")
        >>> print(c.sentence())  # doctest: +NORMALIZE_WHITESPACE
        B0531+21 (m): the paper 109, ours 111: REPRODUCED (within 5 % of the paper:
        three digits; ours is 1.8 % above the paper).
        """
        if self.claimed:
            text = f"{self.name}: the paper {show(self.paper)}, ours {show(self.ours)}: {self.verdict}"
        else:
            text = f"{self.name}: ours {show(self.ours)}: {self.verdict}"
        detail = "; ".join(s for s in (self.tolerance, self.reading) if s)
        return f"{text} ({detail})." if detail else f"{text}."

    def brief(self):
        """The row's reason in a line or two, for a chapter's closing box.

        Three parts of the row's own words, each at most once: the criterion (the tolerance
        before its reason: "within 1 % of the paper"), the reading's first clause (where the
        paper's number falls among our runs, or by how much ours misses it), and what would
        decide an undecided row (the clause that ends "would decide it"); an aside in parentheses
        longer than :data:`BRIEF_ASIDE` characters is left out. The table of the reproduction
        and the dashboard keep the whole tolerance and reading.

        Examples
        --------
        >>> c = check_rel("B0531+21 (m)", 109.0, 111.0, 0.05, why="three digits")
        >>> c.brief()
        'within 5 % of the paper; ours is 1.8 % above the paper'
        """
        criterion = _clauses(self.tolerance, ": ")[0] if self.tolerance else ""
        first = _clauses(self.reading, "; ")[0] if self.reading else ""
        decide = ""
        for text in (self.reading, self.tolerance):
            ends = [c for c in _clauses(text, "; ") if c.rstrip(". ").endswith("would decide it")]
            if ends:
                decide = _clauses(ends[-1], ": ")[-1].rstrip(". ")
                break
        parts = []
        for part in (criterion, first.rstrip(". "), decide):
            if part and not any(part in p for p in parts):
                parts.append(part)
        return "; ".join(_without_long_asides(p) for p in parts)


def _without_long_asides(text, limit=None):
    """``text`` without its parenthesised asides (outermost) longer than ``limit`` characters."""
    limit = BRIEF_ASIDE if limit is None else limit
    out, depth, start = [], 0, 0
    for i, ch in enumerate(text):
        if ch == "(":
            if depth == 0:
                start = i
            depth += 1
        elif ch == ")" and depth:
            depth -= 1
            if depth == 0 and i - start - 1 > limit:
                out.append((start, i + 1))
    for a, b in reversed(out):
        text = text[:a].rstrip() + text[b:]
    return text


def _clauses(text, sep):
    """``text`` split at ``sep`` outside parentheses and brackets ("a (b; c); d" -> two)."""
    out, depth, start, i = [], 0, 0, 0
    while i < len(text):
        ch = text[i]
        depth += (ch in "([") - (ch in ")]")
        if depth == 0 and text.startswith(sep, i):
            out.append(text[start:i])
            start = i = i + len(sep)
            continue
        i += 1
    out.append(text[start:])
    return [c.strip() for c in out if c.strip()]


def _claim(name, paper, ours, holds, tolerance, reading):
    """A claim row: `REPRODUCED` when ``holds``, else `NOT_REPRODUCED`."""
    return Check(name, paper, ours, tolerance, REPRODUCED if holds else NOT_REPRODUCED, reading)


def _why(criterion, why):
    if not (isinstance(why, str) and why.strip()):
        raise ValueError("why must say, in words, the reason for the tolerance")
    return f"{criterion}: {why.strip()}"


def _real(name, value, finite=False, lo=-math.inf):
    """``float(value)``, a bool or text refused; NaN and infinities kept unless ``finite`` (a
    paper's value, ours, a bound; ``lo=0``: a tolerance, where an infinite one cannot fail)."""
    try:
        if isinstance(value, bool | np.bool_ | str | bytes | np.ma.MaskedArray) or getattr(value, "ndim", 0):
            raise TypeError
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number; got {value!r}") from None
    return check_real(name, x, lo) if finite or lo > -math.inf else x


def _finite(name, value):
    return _real(name, value, True)


def _tolerance(name, value):
    return _real(name, value, True, 0.0)


def _shown(name, value):
    """``value``, a row's shown value (words, a number, or an array, list, tuple or dict of
    them), refused when a number in it is NaN or infinite: a row's JSON has neither."""
    items = value
    if isinstance(value, np.ndarray):
        arr = np.asarray(value)
        items = arr[~np.isfinite(arr)][:1].tolist() if arr.dtype.kind in "fc" else list(arr.flat)
    elif isinstance(value, dict):
        items = list(value.values())
    if isinstance(items, list | tuple):
        for item in items:
            _shown(name, item)
    elif isinstance(value, float | complex | np.inexact) and not np.isfinite(value):
        raise ValueError(f"{name} must hold finite numbers only (a row's JSON has no NaN or "
                         f"infinity); got {value}")
    return value


def _hits(name, value):
    """Per-run outcomes as a flat bool array (a "no" or a 0.5 counted as a hit); masked refused."""
    arr = np.asarray(value).ravel()
    if arr.dtype != bool or np.ma.is_masked(value):
        raise ValueError(f"{name} must hold one bool a run (did the outcome happen), none masked; "
                         f"got {'masked entries' if np.ma.is_masked(value) else arr.dtype}")
    return arr


def _words(name, value):
    """``value``, words (a non-empty str: a row's name, the paper's outcome), else refused."""
    if not (isinstance(value, str) and value.strip()):
        raise ValueError(f"{name} must be words (a non-empty str); got {value!r}")
    return value


def _relative(ours, paper):
    if not (math.isfinite(ours) and paper != 0):
        return ""
    d = 100.0 * (ours - paper) / abs(paper)
    if not d:
        return "ours equals the paper"
    return f"ours is {abs(d):.2g} % {'above' if d > 0 else 'below'} the paper"


def check_rel(name, paper, ours, rel, why):
    """A claim that holds when ``|ours - paper| <= rel * |paper|``.

    Parameters
    ----------
    name : str
        The quantity, with its unit.
    paper, ours : float
        The paper's value and ours, finite.
    rel : float
        The relative tolerance (0.05 is 5 %), finite and >= 0.
    why : str
        The reason for that tolerance (the paper's printed digits, a lost parameter, a named
        physical difference). Required: a tolerance without a reason is not a check.

    Examples
    --------
    >>> check_rel("B0531+21 (m)", 109.0, 111.0, 0.05, why="three printed digits").verdict
    'REPRODUCED'
    >>> check_rel("B0531+21 (m)", 109.0, 131.0, 0.05, why="three printed digits").reading
    'ours is 20 % above the paper'
    """
    paper, ours, rel = _finite("paper", paper), _finite("ours", ours), _tolerance("rel", rel)
    ok = abs(ours - paper) <= rel * abs(paper)
    return _claim(name, paper, ours, ok, _why(f"within {100 * rel:g} % of the paper", why),
                  _relative(ours, paper))


def check_abs(name, paper, ours, tol, unit="", why=""):
    """A claim that holds when ``|ours - paper| <= tol`` (all finite, ``tol >= 0``).

    Examples
    --------
    >>> check_abs("improvement (%)", 67.4, 60.0, 10.0, "pp", why="one run").verdict
    'REPRODUCED'
    """
    paper, ours, tol = _finite("paper", paper), _finite("ours", ours), _tolerance("tol", tol)
    unit = check_text("unit", unit)
    ok = abs(ours - paper) <= tol
    reading = f"ours is {abs(ours - paper):.3g} {unit} {'above' if ours > paper else 'below'} the paper" \
        if math.isfinite(ours) and ours != paper else ""
    return _claim(name, paper, ours, ok, _why(f"within {tol:g} {unit}".rstrip(), why),
                  " ".join(reading.split()))


def check_range(name, paper, ours, lo, hi, why):
    """A claim that holds when ``lo <= ours <= hi`` (all finite); ``why`` says why those bounds.

    Examples
    --------
    >>> check_range("mean error (m)", "lost", 1487.0, 100.0, 1e4, why="DE405-class").verdict
    'REPRODUCED'
    """
    if not isinstance(paper, str):   # words ("lost", "about 5e4") or a number
        paper = _finite("paper", paper)
    ours, lo, hi = _finite("ours", ours), _finite("lo", lo), _finite("hi", hi)
    if hi < lo:
        raise ValueError(f"hi must be at least lo = {lo:g}; got {hi:g}")
    ok = lo <= ours <= hi
    return _claim(name, paper, ours, ok, _why(f"between {lo:g} and {hi:g}", why),
                  "" if ok else _outside(ours, lo, hi))


def _outside(ours, lo, hi):
    """How far ``ours`` lies outside ``[lo, hi]``, in words."""
    bound, side = (lo, "below") if ours < lo else (hi, "above")
    gap = abs(ours - bound)
    if bound != 0 and ours != 0 and (ours / bound > 0):
        ratio = max(abs(ours / bound), abs(bound / ours))
        if ratio >= 1.5:
            return f"ours is {ratio:.2g} times {side} the {'lower' if side == 'below' else 'upper'} bound"
    return f"ours is {gap:.3g} {side} the {'lower' if side == 'below' else 'upper'} bound"


def check_true(name, paper, ours, condition, why, reading=""):
    """A qualitative claim (e.g. "isolated as the x gyro"): reproduced when ``condition`` holds.

    ``reading`` says what the numbers show beyond the verdict; when the claim fails and none is
    given, the row says that ours does not meet the condition. A NaN or infinity in ``paper``
    or ``ours`` is refused (a row's JSON has neither).

    Examples
    --------
    >>> check_true("isolated", "x gyro", "x gyro", True, why="the same sensor").verdict
    'REPRODUCED'
    >>> check_true("isolated", "x gyro", "y gyro", False, why="the same sensor").reading
    'ours (y gyro) does not meet it'
    """
    if not (isinstance(why, str) and why.strip()):
        raise ValueError("why must say, in words, what the condition checks")
    condition, reading = check_bool("condition", condition), check_text("reading", reading)
    if not condition and not reading:
        reading = f"ours ({show(ours)}) does not meet it"
    return _claim(name, paper, ours, bool(condition), why.strip(), reading)


#: How a :func:`check_draw` row's tolerance begins (:func:`check_lost` reads it: its ranges are
#: then our single runs' 95 % ranges, not one number per value).
_DRAWN = "inside the 95 % range of our "


def _ordinal(p):
    n = int(round(p))
    suffix = "th" if 10 <= n % 100 <= 20 else {1: "st", 2: "nd", 3: "rd"}.get(n % 10, "th")
    return f"{n}{suffix}"


def check_draw(name, paper, runs, why="", slack=0.0, unit=""):
    """A number the paper reports from one run, judged as one draw from our single runs.

    Our ``runs`` (at least :data:`MIN_RUNS`, one per seed) give the 95 % range of a single
    run (its 2.5th to 97.5th percentiles). The claim is reproduced when the paper's number
    falls inside that range, widened by ``slack`` on either side when a reason for more is
    written in ``why`` (the paper's printed digits, a lost parameter, a named physical
    difference). The reading gives the paper's percentile among our runs.

    Parameters
    ----------
    name : str
        The quantity, with its unit.
    paper : float
        The paper's single-run number, finite.
    runs : array_like, shape (n,)
        Our single runs, one per seed; ``n >= MIN_RUNS``, all finite.
    why : str, optional
        The reason for a ``slack`` (required when ``slack > 0``).
    slack : float, optional
        Added to both ends of our range, in the quantity's unit: finite, >= 0.
    unit : str, optional
        The quantity's unit, for the reading.

    Examples
    --------
    >>> runs = np.linspace(26.0, 30.0, 40)
    >>> c = check_draw("fused position error (m)", 28.835, runs)
    >>> c.verdict, c.reading
    ('REPRODUCED', "the paper's number is at the 70th percentile of our 40 runs")
    >>> check_draw("fused position error (m)", 36.587, runs).verdict
    'NOT REPRODUCED'
    """
    paper, why, unit = _finite("paper", paper), check_text("why", why), check_text("unit", unit)
    runs = check_finite_array("runs", runs).ravel()  # finite, no masked run
    if runs.size < MIN_RUNS:
        raise ValueError(f"runs must hold at least {MIN_RUNS} single runs; got {runs.size}")
    slack = _tolerance("slack", slack)
    lo, hi = np.percentile(runs, [2.5, 97.5])
    criterion = f"{_DRAWN}{runs.size} single runs"
    if slack > 0:
        criterion = _why(f"{criterion}, widened by {slack:g} {unit}".rstrip(), why)
    elif why:
        criterion = f"{criterion}: {why.strip()}"
    pct = 100.0 * (np.sum(runs < paper) + 0.5 * np.sum(runs == paper)) / runs.size
    med = float(np.median(runs))
    if paper < runs.min():
        where = f"the paper's number is below all of our {runs.size} runs"
    elif paper > runs.max():
        where = f"the paper's number is above all of our {runs.size} runs"
    else:
        where = f"the paper's number is at the {_ordinal(pct)} percentile of our {runs.size} runs"
    inside = lo - slack <= paper <= hi + slack
    if not inside and med != 0:
        where += f"; {_relative(paper, med).replace('ours is', 'it is').replace('the paper', 'our median')}"
    ours = f"median {med:.4g} [{lo:.4g}, {hi:.4g}]"
    return _claim(name, paper, ours, inside, criterion, where)


def check_order(name, claim, differences, unit="", why=""):
    """A claimed ordering ("A better than B"), judged on paired differences over seeds.

    ``differences`` are ``A - B`` per seed (e.g. RMSE of A minus RMSE of B: negative where A
    is better, as claimed). With the mean difference and its 95 % interval (1.96 standard
    errors): `REPRODUCED` when the interval lies below zero, `NOT_REPRODUCED` when it lies
    above, `UNDECIDED` otherwise, with the number of runs that would decide it if the mean and
    spread stayed as measured.

    Parameters
    ----------
    name : str
        The ordering, e.g. ``"RKF better than TDUKF (paired RMSE difference, m)"``.
    claim : str
        The paper's claim in words (``"RKF < TDUKF"``).
    differences : array_like, shape (n,)
        Paired differences, A minus B, one per seed; ``n >= 2``, all finite.
    unit : str, optional
        Their unit.
    why : str, optional
        Anything beyond the statistics the reader needs (a named difference of set-up).

    Examples
    --------
    >>> check_order("A better than B (m)", "A < B", [-3.0, -2.0, -4.0, -3.0]).verdict
    'REPRODUCED'
    >>> c = check_order("A better than B (m)", "A < B", [-3.0, 2.0, -4.0, 3.0])
    >>> c.verdict, c.reading
    ('UNDECIDED', 'the 95 % interval holds zero; about 190 runs would decide it (we have 4)')
    """
    claim, unit, why = _words("claim", claim), check_text("unit", unit), check_text("why", why)
    d = check_finite_array("differences", differences, finite=False).ravel()
    if d.size < 2 or not np.all(np.isfinite(d)):
        raise ValueError("differences must hold at least 2 finite paired differences")
    mean, se = float(d.mean()), float(d.std(ddof=1) / math.sqrt(d.size))
    lo, hi = mean - 1.96 * se, mean + 1.96 * se
    ours = f"{mean:+.3g} [{lo:+.3g}, {hi:+.3g}] {unit}".rstrip()
    criterion = f"95 % interval of the mean paired difference over {d.size} seeds below zero"
    if why:
        criterion += f": {why.strip()}"
    if hi < 0:
        return Check(name, claim, ours, criterion, REPRODUCED, "")
    if lo > 0:
        return Check(name, claim, ours, criterion, NOT_REPRODUCED,
                     "the opposite order holds: the interval lies above zero")
    if mean == 0:
        reading = "the 95 % interval holds zero and the mean difference is zero"
    else:
        need = math.ceil((1.96 * float(d.std(ddof=1)) / abs(mean)) ** 2)
        reading = (f"the 95 % interval holds zero; about {need} runs would decide it "
                   f"(we have {d.size})")
    return Check(name, claim, ours, criterion, UNDECIDED, reading)


def check_sanity(name, expected, ours, condition, what):
    """A check of ours (not a claim of the paper): `CHECK` when ``condition`` holds.

    Use it for sanity and consistency checks (an orbit stays bound, a covariance stays
    positive definite, our implementation matches a witness). ``expected`` says what we
    expect; ``what`` says the criterion. A check that does not hold is `CHECK_FAILED`, a
    defect that fails the tests. A NaN or infinity in ``expected`` or ``ours`` is refused.

    Examples
    --------
    >>> check_sanity("min altitude (km)", "above the surface", 420.4, True, "> 0").verdict
    'CHECK'
    """
    if not (isinstance(what, str) and what.strip()):
        raise ValueError("what must say, in words, the criterion of the check")
    ok = check_bool("condition", condition)
    _shown("expected", expected)
    return Check(name, expected, ours, what.strip(), CHECK if ok else CHECK_FAILED, "")


def check_measure(name, ours, what, paper="not given"):
    """An extra measurement shown beside the paper's (`CHECK`): nothing is decided by it.

    Use it where the paper gives no number (``paper="not given"``) or gives one for another
    set-up; ``what`` says what the number is and why it is shown. A NaN or infinity in
    ``ours`` or ``paper`` (an array's entry too) is refused: a measurement to show is a number.

    Examples
    --------
    >>> check_measure("false alarms in 30 days", 4, "design pfa 1e-5 per sample").verdict
    'CHECK'
    """
    if not (isinstance(what, str) and what.strip()):
        raise ValueError("what must say, in words, what the measurement shows")
    return check_sanity(name, _shown("paper", paper), _shown("ours", ours), True, what)


def combine(verdicts):
    """The verdict of one claim from the verdicts of its rows (:func:`part_of`).

    Examples
    --------
    >>> combine(["REPRODUCED", "UNDECIDED"]), combine(["REPRODUCED", "NOT REPRODUCED"])
    ('UNDECIDED', 'NOT REPRODUCED')
    """
    try:
        found = set(verdicts)
    except TypeError:  # not a list
        raise ValueError(f"verdicts must be a list of claim verdicts; got {verdicts!r}") from None
    if not found or not found <= set(CLAIM_VERDICTS):
        raise ValueError(f"verdicts must be claim verdicts ({', '.join(CLAIM_VERDICTS)}); "
                         f"got {sorted(found)}")
    if found == {REPRODUCED}:
        return REPRODUCED
    return NOT_REPRODUCED if NOT_REPRODUCED in found else UNDECIDED


def part_of(claim, *rows):
    """The claim rows ``rows`` marked as parts of one claim of the paper, counted once.

    Use it where one claim takes several rows: one figure's curves, one table's entries, a
    ranking and the paired orders it is made of. Checks of ours among ``rows`` are returned
    unchanged.

    Examples
    --------
    >>> a = check_rel("PR1 (s)", 50.0, 50.0, 0.01, why="one sample")
    >>> b = check_rel("PR2 (s)", 50.0, 60.0, 0.01, why="one sample")
    >>> [r.claim for r in part_of("steps detected at the onset", a, b)]
    ['steps detected at the onset', 'steps detected at the onset']
    """
    if not (isinstance(claim, str) and claim.strip()):
        raise ValueError("claim must say, in words, the paper's claim the rows are parts of")
    for i, r in enumerate(rows):
        if not isinstance(r, Check):
            raise ValueError(f"rows[{i}] must be a Check (a row of check_rel, check_draw, ...); "
                             f"got {type(r).__name__} {r!r}")
    return [replace(r, claim=claim.strip()) if r.claimed else r for r in rows]


def check_lost(row, lost, reach, decides, unit="", held=""):
    """Judge again a claim whose number a parameter the paper lost decides (the module's rule).

    ``row`` is the claim as judged at our choice of the lost parameter (its name, the paper's
    number and ours are kept). ``reach`` gives, for each plausible value of the lost parameter
    that we ran (one lost setting varied at a time), the range our number takes there: the
    95 % range of our single runs, shifted by that setting's measured effect.

    * REPRODUCED: the paper's number is inside the range of every plausible value.
    * UNDECIDED: it is inside some and not others, inside the span of all of them (between
      two values run, the number moves with the parameter), or outside that span by no more
      than the lost parameter's own spread (the largest minus the smallest of its shifts of
      our range, our noise not included: a value we did not run, or a lost parameter we could
      not vary, may move it that far).
    * NOT REPRODUCED: outside the span by more than that spread.

    The tolerance says whether the lost parameter moves our number further than our noise (its
    spread against the width of our own range, the label naming our choice) or less. A row
    judged among our single runs (:func:`check_draw`) keeps its reading first: where the paper's
    number falls among them at our choice (its percentile).

    Parameters
    ----------
    row : Check
        The claim, judged at our choice (e.g. by :func:`check_draw`).
    lost : str
        The lost parameter(s), in words ("the ramp rate of the paper's eq. (39)").
    reach : dict of str -> (float, float)
        Plausible value (a label, e.g. ``"rate 0.15 deg/h/s"``) -> our number's range there.
        At least two values; exactly one label, our own choice, starts with ``"ours"``.
    decides : str
        What would decide the claim ("the paper's ramp rate").
    unit : str, optional
        The number's unit, for the reading.
    held : str, optional
        Another lost parameter held at our choice, with the written reason it is not varied
        (another of the paper's numbers places it, or it moves ours less than our noise);
        shown in the tolerance.

    Examples
    --------
    >>> runs = np.linspace(3.5, 4.5, 40)
    >>> row = check_draw("delay (s)", 2.5, runs)
    >>> c = check_lost(row, "ramp rate", {"ours, 0.1": (3.5, 4.5), "0.15": (2.3, 3.1)},
    ...                "the paper's ramp rate", unit="s")
    >>> c.verdict
    'UNDECIDED'
    >>> c.tolerance.split(":")[0]  # doctest: +NORMALIZE_WHITESPACE
    'the paper lost the ramp rate, which moves our number further than our noise
     (1.3 s, against our range of 1 s)'
    >>> check_lost(row, "ramp rate", {"ours": (3.9, 4.3), "0.09": (4.0, 4.4)},
    ...            "the paper's ramp rate").verdict
    'NOT REPRODUCED'
    """
    if not isinstance(row, Check) or not row.claimed:
        raise ValueError("row must be a claim row (a Check with a claim verdict)")
    for label, text, what in (("lost", lost, "the lost parameter"),
                              ("decides", decides, "what would decide the claim")):
        if not (isinstance(text, str) and text.strip()):
            raise ValueError(f"{label} must say, in words, {what}")
    paper, unit = _real("paper", row.paper), check_text("unit", unit)
    if not isinstance(reach, dict) or len(reach) < 2:
        raise ValueError("reach must map at least two plausible values (labels) to our (lo, hi) there")
    spans = {}
    for label, pair in reach.items():
        lo, hi = (_real("reach", v) for v in pair)
        spans[str(label)] = (min(lo, hi), max(lo, hi))
    ours = [k for k in spans if k.lower().startswith("ours")]
    if len(ours) != 1:
        raise ValueError("reach must name our own choice: exactly one label starting with 'ours'; "
                         f"got {list(spans)}")
    lo = min(v[0] for v in spans.values())
    hi = max(v[1] for v in spans.values())
    # the lost parameter's own spread: its shifts of our range (the centres'), our noise not in it
    centres = [0.5 * (a + b) for a, b in spans.values()]
    spread = max(centres) - min(centres)
    noise = spans[ours[0]][1] - spans[ours[0]][0]
    inside = [k for k, (a, b) in spans.items() if a <= paper <= b]
    u = f" {unit}" if unit else ""
    span = f"ours spans {lo:.4g}-{hi:.4g}{u} over {len(spans)} plausible values ({'; '.join(spans)})"
    drawn = row.tolerance.startswith(_DRAWN)   # the ranges are our single runs' 95 % ranges
    moves = (f"by {spread:.3g}{u} (" + ("our single runs all give the same number: a range of zero "
                                        "width at each)" if drawn else
                                        "our number is one value at each, its noise not in the ranges)")
             if noise == 0 and all(a == b for a, b in spans.values()) else
             f"further than our noise ({spread:.3g}{u}, against our range of {noise:.3g}{u})"
             if spread > noise else
             f"less than our noise ({spread:.3g}{u}, against our range of {noise:.3g}{u})")
    tolerance = (f"the paper lost the {lost.strip()}, which moves our number {moves}: judged over "
                 "its plausible values, one varied at a time")
    if isinstance(held, str) and held.strip():
        tolerance += f" ({held.strip()})"
    elif held:
        raise ValueError(f"held must be words (what is held and why); got {held!r}")
    # a single-run number keeps where it falls among our runs at our choice (its percentile)
    first = f"at our choice, {row.reading}; " if drawn and row.reading else ""
    if len(inside) == len(spans):
        return replace(row, tolerance=tolerance + ": inside our range at every one",
                       verdict=REPRODUCED, reading=f"{first}{span}; the paper's number is inside each")
    gap = lo - paper if paper < lo else paper - hi if paper > hi else 0.0
    if inside or gap <= spread:
        where = (f"reached at {'; '.join(inside)}" if inside else
                 "inside their span" if gap == 0.0 else
                 f"{gap:.3g}{u} {'below' if paper < lo else 'above'} their span, no plausible value "
                 f"reaching it, but less than the {spread:.3g}{u} the lost parameter itself moves it")
        return replace(row, tolerance=tolerance, verdict=UNDECIDED,
                       reading=f"{first}the lost {lost.strip()} decides it: {span}; the paper's "
                               f"{paper:g}{u} is {where}; {decides.strip()} would decide it")
    side = "below" if paper < lo else "above"
    return replace(row, tolerance=tolerance, verdict=NOT_REPRODUCED,
                   reading=f"{first}no plausible value reaches it: {span}; the paper's {paper:g}{u} is "
                           f"{gap:.3g}{u} {side} them, more than the {spread:.3g}{u} the lost "
                           "parameter itself moves it")


def check_event(name, paper, hits, why):
    """An outcome the paper reports from one run (it happened), judged as one draw from ours.

    ``paper`` names the outcome in words; ``hits`` says, per single run of ours, whether it
    happened (at least :data:`MIN_RUNS` runs). As for a number (:func:`check_draw`), the
    paper's single run is an ordinary draw when it falls inside the 95 % range of our single
    runs, that is when at least 2.5 % of ours show the outcome: REPRODUCED; else NOT
    REPRODUCED. How often ours show it (the reliability) is in the reading: that is our
    measurement, not the paper's claim.

    With at most 40 runs one run that shows it is already 2.5 % (1 of 40), so the claim fails
    only when none does; a run that shows it but too rarely (a rare draw) needs more runs, at
    least 41 (1 of 41 is 2.4 %). That is the two-sided 95 % range of :func:`check_draw` applied
    to a yes/no outcome, not a looser rule.

    Examples
    --------
    >>> c = check_event("identified within 5 %", "identified", [True] * 26 + [False] * 14,
    ...                 why="5 % read as 'on them'")
    >>> c.verdict, c.reading
    ('REPRODUCED', "26 of our 40 single runs (65 %) do what the paper's one run did: an ordinary draw")
    >>> check_event("identified within 5 %", "identified", [False] * 40, why="w").verdict
    'NOT REPRODUCED'
    >>> rare = check_event("identified within 5 %", "identified", [True] + [False] * 49, why="w")
    >>> rare.verdict, rare.reading.split(": ")[-1]
    ('NOT REPRODUCED', "the paper's run would be a rare draw among ours")
    """
    if not (isinstance(why, str) and why.strip()):
        raise ValueError("why must say, in words, what counts as the outcome")
    paper = _words("paper", paper)
    hits = _hits("hits", hits)
    if hits.size < MIN_RUNS:
        raise ValueError(f"hits must hold at least {MIN_RUNS} single runs; got {hits.size}")
    k, n = int(hits.sum()), hits.size
    share = k / n
    ok = share >= 0.025
    reading = (f"{k} of our {n} single runs ({100 * share:.0f} %) do what the paper's one run did: "
               + ("an ordinary draw" if ok else "the paper's run would be a rare draw among ours"
                  if k else "none does"))
    return _claim(name, paper, f"{k} of {n} runs", ok,
                  f"the paper's single run as one draw: at least 2.5 % of our {n} single runs "
                  f"show it ({why.strip()})", reading)


def check_event_lost(name, paper, hits, why, lost, decides, held=""):
    """An outcome of the paper's one run, judged over the values of a parameter it lost.

    :func:`check_lost`'s rule (the module's) for a yes/no outcome (:func:`check_event`):
    ``hits`` gives, for each plausible value of the lost parameter that we ran, whether the
    outcome happened in each of our single runs there, and each value is judged by
    :func:`check_event` (an ordinary draw when at least 2.5 % of our runs show it).

    * REPRODUCED: an ordinary draw at every plausible value.
    * UNDECIDED: at some and not at others; or at none, but short of 2.5 % by no more than
      the lost parameter's own spread (the largest minus the smallest of our shares over its
      values: a value we did not run may move the share that far).
    * NOT REPRODUCED: at none, short of 2.5 % by more than that spread (with 40 runs or
      fewer: no run shows it at any value).

    Parameters
    ----------
    name : str
        The outcome, as the row names it.
    paper : str
        The paper's outcome, in words ("detected").
    hits : dict of str -> array_like of bool, shape (n,)
        Plausible value (a label, e.g. ``"ours, 2 m"``) -> per single run of ours there,
        whether the outcome happened (``n >= MIN_RUNS``). At least two values; exactly one
        label, our own choice, starts with ``"ours"``.
    why : str
        What counts as the outcome (as for :func:`check_event`).
    lost : str
        The lost parameter, in words ("reading of its noise").
    decides : str
        What would decide the claim ("the paper's pseudorange noise").
    held : str, optional
        Another lost parameter held at our choice, with the written reason it is not varied;
        shown in the tolerance.

    Returns
    -------
    Check
        The claim row: the paper's outcome, our counts at each value (``"k of n runs at
        <value>"``, our own choice first), the tolerance and the verdict.

    Examples
    --------
    >>> hits = {"ours, 2 m": [True] * 40, "10 m": [False] * 40}
    >>> c = check_event_lost("detected within 5 s", "detected", hits, why="within 5 s",
    ...                      lost="noise", decides="the paper's noise")
    >>> c.verdict, c.ours
    ('UNDECIDED', '40 of 40 runs at 2 m; 0 of 40 runs at 10 m')
    >>> check_event_lost("detected within 5 s", "detected", {"ours": [True] * 40, "b": [True] * 40},
    ...                  why="within 5 s", lost="noise", decides="x").verdict
    'REPRODUCED'
    >>> check_event_lost("detected within 5 s", "detected", {"ours": [False] * 40, "b": [False] * 40},
    ...                  why="within 5 s", lost="noise", decides="x").verdict
    'NOT REPRODUCED'
    """
    for label, text, what in (("lost", lost, "the lost parameter"),
                              ("decides", decides, "what would decide the claim")):
        if not (isinstance(text, str) and text.strip()):
            raise ValueError(f"{label} must say, in words, {what}")
    if not isinstance(held, str):
        raise ValueError(f"held must be words (what is held and why); got {held!r}")
    if not isinstance(hits, dict) or len(hits) < 2:
        raise ValueError("hits must map at least two plausible values (labels) to our runs there")
    runs = {str(k): _hits(f"hits[{k!r}]", h) for k, h in hits.items()}
    ours = [k for k in runs if k.lower().startswith("ours")]
    if len(ours) != 1:
        raise ValueError("hits must name our own choice: exactly one label starting with 'ours'; "
                         f"got {list(runs)}")
    runs = {ours[0]: runs[ours[0]], **runs}            # our own choice first
    rows = {k: check_event(name, paper, h, why=why) for k, h in runs.items()}
    shares = [float(h.mean()) for h in runs.values()]

    def at(label):
        return (label[4:].lstrip(", ") or "ours") if label.lower().startswith("ours") else label

    counts = "; ".join(f"{r.ours} at {at(k)}" for k, r in rows.items())
    tolerance = (f"{rows[ours[0]].tolerance}; the paper lost the {lost.strip()}: judged at each "
                 f"of its plausible values ({'; '.join(rows)})")
    if held.strip():
        tolerance += f" ({held.strip()})"
    shown = [k for k, r in rows.items() if r.verdict == REPRODUCED]
    first = rows[ours[0]]
    if len(shown) == len(rows):
        return replace(first, ours=counts, tolerance=tolerance,
                       reading=f"an ordinary draw at every plausible value ({counts})")
    # the lost parameter's own spread: its shifts of our share (check_lost's margin)
    spread = max(shares) - min(shares)
    gap = 0.025 - max(shares)
    if shown or gap <= spread:
        where = (f"an ordinary draw at {'; '.join(shown)}, not at "
                 f"{'; '.join(k for k in rows if k not in shown)}" if shown else
                 f"an ordinary draw at none, but {100 * gap:.2g} % short of 2.5 %, less than the "
                 f"{100 * spread:.2g} % the lost parameter itself moves the share")
        return replace(first, ours=counts, tolerance=tolerance, verdict=UNDECIDED,
                       reading=f"the lost {lost.strip()} decides it: {where} ({counts}); "
                               f"{decides.strip()} would decide it")
    return replace(first, ours=counts, tolerance=tolerance, verdict=NOT_REPRODUCED,
                   reading=f"not an ordinary draw at any plausible value ({counts})")


def show(x):
    """A value as a table shows it: a float to four significant digits, anything else as text.

    Examples
    --------
    >>> show(28.8351), show("RKF < TDUKF")
    ('28.84', 'RKF < TDUKF')
    """
    if isinstance(x, float):
        return f"{x:.4g}"
    return str(x)
