"""Argument checks shared by every module.

Every public function validates its inputs with these helpers, so a bad value
raises one :class:`ValueError` that names the parameter and the allowed range
instead of propagating a NaN, clipping silently or failing deep in a traceback.
"""

from __future__ import annotations

import math
from numbers import Integral, Real

import numpy as np

from xnavlab.core._array_kinds import as_array, decimal_note, item_kinds, odd_item, one_line, unit_refusal

__all__ = [
    "shown",
    "check_real",
    "check_int",
    "check_bool",
    "check_finite_array",
    "check_choice",
    "check_vector",
    "check_shape",
    "check_increasing",
    "check_evenly_spaced",
    "off_unit",
    "check_arrays",
    "check_callable",
    "check_instance",
    "check_keywords",
    "check_text",
    "check_symmetric",
    "check_covariance",
    "check_definite",
    "check_items",
    "check_records",
    "check_seeds",
    "check_seed",
    "seed_after",
    "make_rng",
    "SEED_MAX",
]

#: The largest seed a run takes: seeds are stored as int64 in the records and caches.
SEED_MAX = 2**63 - 1


def check_real(name, value, lo=-math.inf, hi=math.inf, *, lo_open=False, hi_open=False):
    """Return ``float(value)`` if it is a finite real number in the range, else raise.

    Parameters
    ----------
    name : str
        Parameter name used in the error message.
    value : object
        Value to check.
    lo, hi : float
        Bounds of the allowed range.
    lo_open, hi_open : bool
        Whether the bound itself is excluded.

    Examples
    --------
    >>> check_real("sigma_deg", 0.1, 0.0, 10.0, lo_open=True)
    0.1
    >>> check_real("sigma_deg", -1, 0.0, 10.0, lo_open=True)
    Traceback (most recent call last):
    ...
    ValueError: sigma_deg must be a real number in (0, 10], got -1
    >>> check_real("t0", complex(1, 2))
    Traceback (most recent call last):
    ...
    ValueError: t0 must be a finite real number, got (1+2j)

    An infinite bound is written open (``[0, inf)``: every finite number from 0) and no
    bounds at all as "a finite real number", never ``[-inf, inf]``. A ``Decimal`` is refused,
    saying so (it mixes with no float; a ``Fraction`` is taken).
    """
    _check_bounds(name, lo, hi)
    want = f"a {'finite ' if lo == -math.inf and hi == math.inf else ''}real number" \
        + _range(lo, hi, lo_open, hi_open)
    if isinstance(value, bool | np.timedelta64) or not isinstance(value, Real | np.floating | np.integer):
        raise ValueError(f"{name} must be {want}, got {shown(value)}{decimal_note(value, 'float')}")
    try:
        x = float(value)
    except OverflowError:  # an integer beyond any float (10**400): out of every range
        x = math.inf
    bad = (
        not math.isfinite(x)
        or (x < lo or (lo_open and x == lo))
        or (x > hi or (hi_open and x == hi))
    )
    if bad:
        raise ValueError(f"{name} must be {want}, got {shown(value)}")
    return x


def check_int(name, value, lo=-math.inf, hi=math.inf):
    """Return ``int(value)`` if it is an integer in ``[lo, hi]``, else raise.

    Examples
    --------
    >>> check_int("levels", 5, 1, 10)
    5
    >>> check_int("window", 0, 1)
    Traceback (most recent call last):
    ...
    ValueError: window must be an integer in [1, inf), got 0
    """
    _check_bounds(name, lo, hi)
    want = "an integer" + _range(lo, hi, False, False, exact=True)
    if isinstance(value, bool | np.timedelta64) or not isinstance(value, Integral | np.integer):
        # (a timedelta64 is an integer to numpy)
        raise ValueError(f"{name} must be {want}, got {shown(value)}{decimal_note(value, 'int')}")
    if value < lo or value > hi:
        raise ValueError(f"{name} must be {want}, got {shown(value)}")
    return int(value)


def check_finite_array(name, value, shape=None, dtype=float, finite=True, *, unit=None):
    """Return ``value`` as a finite float array, checking its trailing shape.

    Complex numbers (whose imaginary part a cast would drop), text, booleans, masked entries,
    dates and durations (datetime64, timedelta64) and quantities with a unit (astropy's
    ``Quantity``, whose number is in its own unit) are refused, not converted, wherever they
    sit (every item of an object array is looked at); a ``numpy.ma`` array with no masked entry
    is used as its data, a matrix as its 2-D array. A read-only array is copied once (PyWavelets
    and the compiled kernels need a writable one); a writable float64 array is returned as it is.
    ``finite=False`` lets NaN and inf through (an elementwise function that maps NaN to NaN, as
    scipy's do).

    Parameters
    ----------
    name : str
        Parameter name used in the error message.
    value : array_like
        Value to check.
    shape : tuple of int or None, optional
        Required trailing shape (``None`` entries match any size).
    unit : str, optional
        The unit the parameter documents, for the refusal of dates or a quantity.

    Examples
    --------
    >>> check_finite_array("r", [1.0, 2.0, 3.0], shape=(3,)).shape
    (3,)
    >>> check_finite_array("z", [1.0, 2.0 + 1e-3j])
    Traceback (most recent call last):
    ...
    ValueError: z must hold real numbers, got complex values (an imaginary part is not dropped)
    >>> check_finite_array("state0", [1.0, True])
    Traceback (most recent call last):
    ...
    ValueError: state0 must be an array of finite numbers, got [1.0, True]
    >>> check_finite_array("P", np.ma.masked_array([1.0, 4.0], mask=[True, False]))
    Traceback (most recent call last):
    ...
    ValueError: P has masked entries: 1 of 2, the first P[0] (no number to use: fill or drop them)
    """
    if isinstance(value, np.ma.MaskedArray):  # np.asarray used the masked values (review 35m)
        if (mask := np.ma.getmaskarray(value)).any():
            at = ", ".join(str(int(i)) for i in np.unravel_index(np.argmax(mask), mask.shape))
            raise ValueError(f"{name} has masked entries: {int(mask.sum())} of {mask.size}, the "
                             f"first {name}[{at}] (no number to use: fill or drop them)"
                             if at else f"{name} is masked (no number to use)")
        value = value.data
    if (odd := odd_item(value) if isinstance(value, list | tuple) else None) == "masked":
        raise ValueError(f"{name} has masked entries (no number to use: fill or drop them)")
    raw = as_array(value)
    kinds = item_kinds(raw) if raw is not None else set()
    if odd == "unit" or raw is None or kinds & {"M", "m", "unit"}:  # review 35 Q1: 2020 read as 2050
        raise ValueError(unit_refusal(name, value, raw, unit)
                         or f"{name} must be an array of finite numbers, got {shown(value)}")
    if "c" in kinds:
        raise ValueError(f"{name} must hold real numbers, got complex values (an imaginary part "
                         f"is not dropped)")
    if kinds & set("USbO") or odd:
        # a True among floats: np.asarray made it 1.0 without a word (review 35g)
        raise ValueError(f"{name} must be an array of finite numbers, got {shown(value)}")
    try:
        arr = raw.astype(dtype, copy=False)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be an array of finite numbers, got {shown(value)}") from None
    if shape is not None:
        tail = arr.shape[arr.ndim - len(shape):] if arr.ndim >= len(shape) else None
        ok = tail is not None and all(s is None or s == t for s, t in zip(shape, tail, strict=True))
        if not ok:
            want = "(..., " + ", ".join("n" if s is None else str(s) for s in shape) + ")"
            raise ValueError(f"{name} must have trailing shape {want}, got shape {arr.shape}")
    if finite and not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must contain only finite numbers (no NaN or inf)")
    return arr if arr.flags.writeable else arr.copy()  # pywt: "buffer source array is read-only"


def check_bool(name, value):
    """Return ``bool(value)`` if it is ``True`` or ``False`` (a Python or numpy bool), else raise.

    A string is not read as a truth value (``"no"`` is a non-empty string, so Python's
    ``bool("no")`` is True), nor is a number (``0``/``1`` may be a count or an index typed in
    the wrong place): only a real bool says yes or no.

    Examples
    --------
    >>> check_bool("cache", np.True_)
    True
    >>> check_bool("cache", "no")
    Traceback (most recent call last):
    ...
    ValueError: cache must be True or False, got 'no'
    """
    if not isinstance(value, bool | np.bool_):
        raise ValueError(f"{name} must be True or False, got {shown(value)}")
    return bool(value)


def check_choice(name, value, choices):
    """Return ``value`` if it is one of ``choices``, else raise listing them.

    Examples
    --------
    >>> check_choice("kind", "step", ("step", "ramp"))
    'step'
    """
    if value not in choices:
        allowed = ", ".join(repr(c) for c in choices)
        raise ValueError(f"{name} must be one of {allowed}, got {value!r}")
    return value


def check_vector(name, value, n=None):
    """Return ``value`` as a finite 1-D float array (of length ``n`` when given), else raise.

    Examples
    --------
    >>> check_vector("x0", [1.0, 2.0], 2).tolist()
    [1.0, 2.0]
    >>> check_vector("x0", [[1.0], [2.0]])
    Traceback (most recent call last):
    ...
    ValueError: x0 must be a 1-D array (shape (n,)), got shape (2, 1)
    """
    arr = check_finite_array(name, value)
    want = "(n,)" if n is None else f"({n},)"
    if arr.ndim != 1 or (n is not None and arr.shape[0] != n):
        raise ValueError(f"{name} must be a 1-D array (shape {want}), got shape {arr.shape}")
    return arr


def check_shape(name, value, shape, why=""):
    """Return ``value`` as a finite float array of exactly ``shape``, else one ValueError that
    leads with ``name`` (the argument at fault) and says what fixed the shape.

    A cross-check of several arguments (``r`` must match the rows of ``H``) names the argument
    whose shape disagrees with the ones checked before it, so the user reads first what to
    change.

    Parameters
    ----------
    name : str
        Parameter name used in the error message.
    value : array_like
        Value to check.
    shape : tuple of int or None
        The shape (``None`` entries match any size).
    why : str, optional
        What fixed the sizes, for the message (``"m = rows of H"``).

    Examples
    --------
    >>> check_shape("r", [1.0, 2.0], (2,), "m = rows of H").shape
    (2,)
    >>> check_shape("r", [], (2,), "m = rows of H")
    Traceback (most recent call last):
    ...
    ValueError: r must have shape (2,) (m = rows of H), got shape (0,)
    """
    arr = check_finite_array(name, value)
    if arr.ndim != len(shape) or any(s not in (None, t) for s, t in zip(shape, arr.shape, strict=False)):
        want = str(tuple("n" if s is None else s for s in shape)).replace("'", "")
        reason = f" ({why})" if why else ""
        raise ValueError(f"{name} must have shape {want}{reason}, got shape {arr.shape}")
    return arr


def check_increasing(name, value):
    """Return ``value`` (a 1-D array, already checked) if it strictly increases, else one
    ValueError naming the first sample that does not (sample times read in order: an onset,
    a window or a step taken from them would be wrong).

    Examples
    --------
    >>> check_increasing("t", np.array([0.0, 1.0, 3.0])).tolist()
    [0.0, 1.0, 3.0]
    >>> check_increasing("t", np.array([0.0, 2.0, 1.0]))
    Traceback (most recent call last):
    ...
    ValueError: t must be strictly increasing (sample times, s), got t[2] = 1 after t[1] = 2
    """
    step = np.diff(value)
    if not np.all(step > 0.0):
        k = int(np.argmax(~(step > 0.0))) + 1
        raise ValueError(f"{name} must be strictly increasing (sample times, s), got "
                         f"{name}[{k}] = {_fmt(value[k])} after {name}[{k - 1}] = {_fmt(value[k - 1])}")
    return value


def check_evenly_spaced(name, value, rtol):
    """Return ``value`` (a strictly increasing 1-D array, already checked) if every step is
    within ``rtol`` of the median step, else one ValueError naming the step that deviates most
    (a sampling rate taken from the median step, or a filter that assumes one step, would be
    wrong for the others).

    Examples
    --------
    >>> check_evenly_spaced("t", 3.0 * np.arange(4), 0.01).tolist()
    [0.0, 3.0, 6.0, 9.0]
    >>> check_evenly_spaced("t", np.array([0.0, 3.0, 6.0, 10.0, 13.0]), 0.01)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: t must be evenly spaced (each step within 0.01 of the median step, 3 s), ...
    >>> float(check_evenly_spaced("t", np.array([0.0, 3.0, 6.0, 10.0, 13.0]), 0.5)[-1])
    13.0
    """
    _check_rtol(rtol)
    step = np.diff(value)
    if step.size:
        dt = float(np.median(step))
        off = np.abs(step - dt) / dt
        k = int(np.argmax(off))
        if off[k] > rtol:
            raise ValueError(f"{name} must be evenly spaced (each step within {rtol:g} of the "
                             f"median step, {dt:.6g} s), got {name}[{k + 1}] - {name}[{k}] = "
                             f"{float(step[k]):.6g} s ({float(off[k]):.3g} off)")
    return value


def off_unit(vectors, tol):
    """``(i, norms)``: the flat index ``i`` of the first vector (along the last axis) whose norm
    is more than ``tol`` from 1 (None if every one is a unit vector), and the norms.

    The shared test of the unit-vector checks (a zero or a scaled direction is refused, not
    rescaled); each caller words its own refusal. A norm past the float range counts as off.

    Examples
    --------
    >>> i, norms = off_unit(np.array([[1.0, 0.0], [0.0, 2.0]]), 1e-6)
    >>> i, norms.tolist()
    (1, [1.0, 2.0])
    >>> off_unit(np.eye(3), 1e-6)[0] is None
    True
    """
    with np.errstate(over="ignore"):  # a norm beyond float64 is no unit vector: off
        norms = np.linalg.norm(vectors, axis=-1)
    bad = np.ravel(~(np.abs(norms - 1.0) <= tol))
    return (int(np.argmax(bad)) if bad.any() else None), norms


def check_arrays(name, value, ndim=None, min_len=1):
    """Return ``value`` as a list of finite float arrays (a list or tuple of them, or a stack
    ``(N, ...)`` of them, at least ``min_len``), each checked under ``name[i]``, else one
    ValueError.

    Examples
    --------
    >>> [a.shape for a in check_arrays("xs", [[1.0, 2.0], [3.0, 4.0]], ndim=1)]
    [(2,), (2,)]
    >>> check_arrays("xs", True)
    Traceback (most recent call last):
    ...
    ValueError: xs must be a list of arrays, got True
    """
    if isinstance(value, np.ndarray) and value.ndim >= 1 and value.dtype.kind in "fiu":
        value = list(value)  # a stack (N, ...): one array per row
    if not isinstance(value, list | tuple):
        raise ValueError(f"{name} must be a list of arrays, got {shown(value)}")
    if len(value) < min_len:
        raise ValueError(f"{name} must hold at least {min_len} array{'s' * (min_len != 1)}, got {len(value)}")
    out = [check_finite_array(f"{name}[{i}]", v) for i, v in enumerate(value)]
    for i, arr in enumerate(out):
        if ndim is not None and arr.ndim != ndim:
            raise ValueError(f"{name}[{i}] must be a {ndim}-D array, got shape {arr.shape}")
    return out


def check_callable(name, value, what="a function"):
    """Return ``value`` if it can be called, else one ValueError naming ``name``.

    Examples
    --------
    >>> check_callable("h", abs) is abs
    True
    >>> check_callable("h", True, "a function h(x) -> z")
    Traceback (most recent call last):
    ...
    ValueError: h must be a function h(x) -> z, got True
    """
    if not callable(value):
        raise ValueError(f"{name} must be {what}, got {shown(value)}")
    return value


def check_instance(name, value, kinds, what, bool_ok=False):
    """Return ``value`` if it is an instance of ``kinds``, else one ValueError naming ``name``
    (a bool is refused unless ``bool_ok``: ``True`` is an ``int`` to Python, not to a user).

    Examples
    --------
    >>> check_instance("window", (0.0, 1.0), tuple | list, "a pair (t_from, t_to)")
    (0.0, 1.0)
    >>> check_instance("scenario", 1.0, dict, "a scenario")
    Traceback (most recent call last):
    ...
    ValueError: scenario must be a scenario, got float 1.0
    """
    if not isinstance(value, kinds) or isinstance(value, bool) and not bool_ok:
        raise ValueError(f"{name} must be {what}, got {type(value).__name__} {shown(value)}")
    return value


def check_keywords(caller, given, target, *, name=None, set_here=None):
    """Return ``given`` (keywords ``caller`` passes on to ``target``) as a dict if each is one
    ``target`` takes and ``caller`` does not set itself, else one ValueError naming it.

    A misspelt keyword passed on unchecked surfaces as a TypeError of an internal function
    (or, when the caller sets it too, as "got multiple values"); here it is named as the user
    wrote it, with the valid names and the nearest one.

    Parameters
    ----------
    caller : str
        The function the user called, for the message.
    given : dict or None
        The keywords (``**kw``, or a ``*_kw`` dict; None is no keywords).
    target : callable or iterable of str
        What takes them: its signature's keyword parameters (a ``**`` parameter takes any),
        or the valid names.
    name : str, optional
        The ``*_kw`` parameter that holds them (its entries are then named ``name['key']``);
        None for ``**kw`` (each named by itself).
    set_here : dict of str to str, optional
        Keywords ``caller`` sets itself -> where the value comes from.

    Examples
    --------
    >>> def target(a, b=1, *, level=5):
    ...     pass
    >>> check_keywords("f", {"level": 3}, target)
    {'level': 3}
    >>> check_keywords("f", {"levle": 3}, ["a", "level"])
    Traceback (most recent call last):
    ...
    ValueError: levle is not a keyword f takes: the valid ones are a, level (did you mean level?)
    >>> check_keywords("f", {"levle": 3}, target)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: levle is not a keyword of f or of target, ...: those of target are a, b, level (did ...
    >>> check_keywords("f", {"a": 3}, target, name="f_kw", set_here={"a": "from its x"})
    Traceback (most recent call last):
    ...
    ValueError: f_kw['a'] is set by f (from its x): leave it out
    >>> check_keywords("f", {"c": 3}, target, name="f_kw", set_here={"a": "from its x"})
    Traceback (most recent call last):
    ...
    ValueError: f_kw['c'] is not a keyword of target (f passes f_kw on to it): the valid ones are b, level
    """
    import difflib
    import inspect

    set_here = dict(set_here or {})
    if given is None:
        given = {}
    if not isinstance(given, dict) or not all(isinstance(k, str) for k in given):
        what = name if name is not None else "the keywords"
        raise ValueError(f"{what} must be a dict of keyword arguments (names as str), got "
                         f"{shown(given)}")
    if callable(target):
        try:
            params = inspect.signature(target).parameters.values()
        except (TypeError, ValueError):  # no signature to read (a builtin): the target's own check
            return dict(given)
        if any(p.kind is p.VAR_KEYWORD for p in params):
            valid = None
        else:
            valid = [p.name for p in params if p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)
                     and p.name != "self"]
    else:
        valid = list(target)
    for key in given:
        label = key if name is None else f"{name}[{key!r}]"
        if key in set_here:
            raise ValueError(f"{label} is set by {caller} ({set_here[key]}): leave it out")
        if valid is not None and key not in valid:
            ok = [v for v in valid if v not in set_here]
            near = difflib.get_close_matches(key, ok, n=1)
            hint = f" (did you mean {near[0]}?)" if near else ""
            to = getattr(target, "__qualname__", None) if callable(target) else None
            if to is not None and "<" in to:  # a local function: its own name
                to = target.__name__
            if to is None:
                what = f"a keyword {caller} takes{'' if name is None else ' in ' + name}: the " \
                       f"valid ones are"
            elif name is None:
                what = f"a keyword of {caller} or of {to}, which {caller} passes its other " \
                       f"keywords on to: those of {to} are"
            else:
                what = f"a keyword of {to} ({caller} passes {name} on to it): the valid ones are"
            raise ValueError(f"{label} is not {what} {', '.join(ok) or 'none'}{hint}")
    return dict(given)


def check_text(name, value, none_ok=False):
    """Return ``value`` if it is a string (or None when ``none_ok``), else one ValueError.

    Examples
    --------
    >>> check_text("title", "Figure 1")
    'Figure 1'
    >>> check_text("title", True)
    Traceback (most recent call last):
    ...
    ValueError: title must be text (a str), got True
    """
    if not (isinstance(value, str) or none_ok and value is None):
        raise ValueError(f"{name} must be text (a str{' or None' if none_ok else ''}), got {shown(value)}")
    return value


def _unit_scaled(arr):
    """``(arr 2^-e, e)``: ``arr`` scaled by a power of two (exact) to a largest entry in
    [0.5, 1) (``e = 0`` for zeros), so that sums of entries near 1e308 stay finite."""
    scale = float(np.max(np.abs(arr))) if arr.size else 0.0
    e = int(np.frexp(scale)[1]) if scale > 0.0 else 0
    return np.ldexp(arr, -e), e


def check_symmetric(name, value, rtol=1e-8):
    """Return ``value`` (a finite square array, already checked) if it is symmetric to ``rtol``
    of its largest entry (a matrix that went through floating-point products is symmetric only
    to rounding), else one ValueError naming it.

    Examples
    --------
    >>> check_symmetric("P", np.array([[2.0, 1.0], [1.0, 3.0]])).shape
    (2, 2)
    >>> check_symmetric("P", np.array([[1.0, 0.5], [0.0, 1.0]]))
    Traceback (most recent call last):
    ...
    ValueError: P must be symmetric (to 1e-08 of its largest entry)
    """
    _check_rtol(rtol)
    unit, _ = _unit_scaled(value)
    if np.max(np.abs(unit - unit.T), initial=0.0) > rtol * float(np.max(np.abs(unit), initial=0.0)):
        raise ValueError(f"{name} must be symmetric (to {rtol:g} of its largest entry)")
    return value


def check_covariance(name, value, n=None, *, definite=False, rtol=1e-8):
    """Return ``value`` as a finite, symmetric, positive (semi-)definite (n, n) array, else raise.

    Symmetry is tested to ``rtol`` of the largest entry (a covariance that went through
    floating-point products is symmetric only to rounding); definiteness by the smallest
    eigenvalue, which must be above ``-rtol`` times the largest (semi-definite) or
    above zero (``definite=True``: a measurement-noise covariance, which is inverted).

    Parameters
    ----------
    name : str
        Parameter name used in the error message.
    value : array_like, shape (n, n)
        The matrix.
    n : int, optional
        Required size.
    definite : bool
        Require positive definite (else semi-definite).

    Examples
    --------
    >>> check_covariance("P", np.eye(2), 2).shape
    (2, 2)
    >>> check_covariance("P", -np.eye(2))
    Traceback (most recent call last):
    ...
    ValueError: P must be positive semi-definite, got smallest eigenvalue -1
    """
    _check_rtol(rtol)
    arr = check_finite_array(name, value)
    size = arr.shape[0] if arr.ndim == 2 else None
    want = "(n, n)" if n is None else f"({n}, {n})"
    if arr.ndim != 2 or arr.shape[1] != size or (n is not None and size != n):
        raise ValueError(f"{name} must be a square matrix of shape {want}, got shape {arr.shape}")
    check_symmetric(name, arr, rtol)
    unit, e = _unit_scaled(arr)  # the eigenvalues of arr times 2^-e, to the last bit
    low_unit = float(np.linalg.eigvalsh(0.5 * (unit + unit.T))[0]) if size else 0.0
    try:
        low = math.ldexp(low_unit, e)  # arr's own smallest eigenvalue, for the message
    except OverflowError:  # past 1.8e308 in size
        low = math.copysign(math.inf, low_unit)
    if definite and not low_unit > 0.0:
        raise ValueError(f"{name} must be positive definite, got smallest eigenvalue {low:.3g}")
    if low_unit < -rtol * float(np.max(np.abs(unit), initial=0.0)):
        raise ValueError(f"{name} must be positive semi-definite, got smallest eigenvalue {low:.3g}")
    return arr


def check_definite(name, value, n=None, *, rtol=1e-8):
    """Return ``value`` as finite, symmetric, positive definite, invertible matrices, else raise.

    The check of a matrix a statistic inverts (a NEES, NIS or chi-square test): one ValueError
    that names the matrix and what is wrong with it (not square, not symmetric, indefinite or
    singular), never a raw ``LinAlgError`` or a negative statistic. Vectorised over leading
    axes: a stack ``(..., n, n)`` names its first bad matrix by index. Definiteness is judged
    on the correlation matrix (the matrix scaled by its diagonal), so mixed units (m^2 beside
    m^2/s^2) do not look singular: a correlation eigenvalue at or below ``100 n eps`` is
    singular.

    Parameters
    ----------
    name : str
        Parameter name used in the error message.
    value : array_like, shape (..., n, n)
    n : int, optional
        Required size.
    rtol : float
        Symmetry tolerance, relative to each matrix's largest entry.

    Examples
    --------
    >>> check_definite("S", [[4.0, 0.0], [0.0, 1e-6]]).shape
    (2, 2)
    >>> check_definite("S", [[1.0, 2.0], [2.0, 1.0]])
    Traceback (most recent call last):
    ...
    ValueError: S must be positive definite, but it is indefinite (smallest eigenvalue -1)
    >>> check_definite("P", np.stack([np.eye(2), np.diag([2.0, 0.0])]))
    Traceback (most recent call last):
    ...
    ValueError: P[1] must be positive definite, but it is singular (smallest eigenvalue 0, largest 2)
    """
    _check_rtol(rtol)
    arr = check_finite_array(name, value)
    want = "(..., n, n)" if n is None else f"(..., {n}, {n})"
    if arr.ndim < 2 or arr.shape[-1] != arr.shape[-2] or (n is not None and arr.shape[-1] != n):
        raise ValueError(f"{name} must be a square matrix of shape {want}, got shape {arr.shape}")
    m = arr.shape[-1]
    if arr.size == 0:
        return arr
    flat = arr.reshape(-1, m, m)

    def label(k):
        where = np.unravel_index(k, arr.shape[:-2])
        return name if arr.ndim == 2 else f"{name}[{', '.join(str(int(i)) for i in where)}]"

    scale = np.max(np.abs(flat), axis=(1, 2))
    asym = np.max(np.abs(flat - flat.transpose(0, 2, 1)), axis=(1, 2)) > rtol * scale
    if asym.any():
        raise ValueError(f"{label(int(np.argmax(asym)))} must be symmetric (to {rtol:g} of its "
                         f"largest entry)")
    d = np.diagonal(flat, axis1=1, axis2=2)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = 1.0 / np.sqrt(np.where(d > 0.0, d, 1.0))
        corr = 0.5 * (flat + flat.transpose(0, 2, 1)) * s[:, :, None] * s[:, None, :]
    low = np.where(np.all(d > 0.0, axis=1), np.linalg.eigvalsh(corr)[:, 0], -1.0)
    low = np.where(np.any(d == 0.0, axis=1) & np.all(d >= 0.0, axis=1), 0.0, low)
    bad = low <= 100.0 * m * np.finfo(float).eps
    if bad.any():
        k = int(np.argmax(bad))
        eig = np.linalg.eigvalsh(0.5 * (flat[k] + flat[k].T))
        what = ("indefinite" if low[k] < -100.0 * m * np.finfo(float).eps else "singular")
        more = f", largest {float(eig[-1]):.3g}" if what == "singular" else ""
        raise ValueError(f"{label(k)} must be positive definite, but it is {what} (smallest "
                         f"eigenvalue {float(eig[0]):.3g}{more})")
    return arr


def check_items(name, value, what="item", each=None, min_len=1):
    """Return ``value`` as a tuple of items: a list (not a string, a table or a number), with
    at least ``min_len`` items and none twice, else one ValueError naming ``name``.

    A list of pulsars, stars or subsystems: a string where the list belongs is refused (not
    split into its letters), an empty list is refused, and an item given twice (which would
    count its information twice) is named with both positions.

    Parameters
    ----------
    name : str
        Parameter name used in the error message.
    value : object
        The list (any iterable but a string, bytes or a mapping).
    what : str
        What one item is, for the messages (``"pulsar"``).
    each : callable, optional
        ``each(label, item) -> key``: checks one item (``label`` is ``name[i]``, for its
        message) and returns the key that identifies it (two equal keys are a repeat); by
        default the item is its own key.
    min_len : int
        Fewest items.

    Examples
    --------
    >>> check_items("subsystems", ["uv", "cns"], "subsystem")
    ('uv', 'cns')
    >>> check_items("pulsars", "B1937+21", "pulsar")
    Traceback (most recent call last):
    ...
    ValueError: pulsars must be a list of pulsars, got the string 'B1937+21' (write ["B1937+21"])
    >>> check_items("stars", ["Vega", "Sirius", "Vega"], "star")
    Traceback (most recent call last):
    ...
    ValueError: stars lists Vega twice (items 0 and 2)
    >>> check_items("stars", {"Vega"}, "star")
    Traceback (most recent call last):
    ...
    ValueError: stars must be a list of stars in order (a set has none: write a list), got {'Vega'}
    """
    if isinstance(value, str | bytes):
        text = value.decode(errors="replace") if isinstance(value, bytes) else value
        raise ValueError(f"{name} must be a list of {what}s, got the string {text!r} "
                         f"(write [\"{text}\"])")
    if isinstance(value, set | frozenset):  # no order: the items' order would follow the hash seed
        raise ValueError(f"{name} must be a list of {what}s in order (a set has none: write a "
                         f"list), got {shown(value)}")
    flat = not isinstance(value, np.ndarray) or value.ndim == 1
    if isinstance(value, dict) or not hasattr(value, "__iter__") or not flat:
        raise ValueError(f"{name} must be a list of {what}s, got {shown(value)}")
    items = tuple(value)
    if len(items) < min_len:
        got = "an empty list" if not items else f"{len(items)}"
        least = f"one {what}" if min_len == 1 else f"{min_len} {what}s"
        raise ValueError(f"{name} must name at least {least}, got {got}")
    seen = {}
    for i, item in enumerate(items):
        key = each(f"{name}[{i}]", item) if each is not None else item
        try:
            first = seen.setdefault(key, i)
        except TypeError:  # an unhashable item (a list inside the list)
            raise ValueError(f"{name}[{i}] must be a {what}, got {shown(item)}") from None
        if first != i:
            raise ValueError(f"{name} lists {key} twice (items {first} and {i})")
    return items


def check_records(name, value, keys=(), what="record"):
    """``value`` as a list of dicts (records, rows) that each hold ``keys``, else one ValueError
    naming ``name`` (a string, a dict or a number is no list) or ``name[i]`` and what it lacks.

    An empty list is returned as is (what it means is the caller's).

    Examples
    --------
    >>> check_records("rows", ({"pd": 0.5},), ("pd",))
    [{'pd': 0.5}]
    >>> check_records("rows", [{"pd": 0.5}, {"size": 2}], ("pd",), "detector row")
    Traceback (most recent call last):
    ...
    ValueError: rows[1] must be a detector row (a dict with pd), got {'size': 2}
    >>> check_records("rows", np.array(1.0))
    Traceback (most recent call last):
    ...
    ValueError: rows must be a list of records (dicts), got array(1.)
    """
    no_list = isinstance(value, np.ndarray) and value.ndim != 1  # a 0-d array: iterable to hasattr
    if isinstance(value, str | bytes | dict) or not hasattr(value, "__iter__") or no_list:
        raise ValueError(f"{name} must be a list of {what}s (dicts), got {shown(value)}")
    value = list(value)
    for i, row in enumerate(value):
        if not isinstance(row, dict) or any(k not in row for k in keys):
            with_keys = f" with {', '.join(keys)}" if keys else ""
            raise ValueError(f"{name}[{i}] must be a {what} (a dict{with_keys}), got {shown(row)}")
    return value


def check_seeds(name, value, min_len=1):
    """Return ``value`` as a tuple of distinct integer seeds in ``[0, SEED_MAX]``, else one
    ValueError naming ``name`` (or ``name[i]`` for the item at fault).

    A seed given twice would count one run twice in a Monte Carlo mean; a string, an empty
    list or a float seed is refused (:func:`check_items`, :func:`check_int`).

    Examples
    --------
    >>> check_seeds("seeds", range(3))
    (0, 1, 2)
    >>> check_seeds("seeds", [0, 1.5])
    Traceback (most recent call last):
    ...
    ValueError: seeds[1] must be an integer in [0, 9223372036854775807], got 1.5
    """
    return tuple(int(s) for s in check_items(name, value, "seed", check_seed, min_len))


def check_seed(name, value):
    """Return ``value`` as an integer seed in ``[0, SEED_MAX]``, else one ValueError naming
    ``name`` (a seed above the range cannot be stored in a record or a cache, nor passed on).

    Examples
    --------
    >>> check_seed("seed", 7)
    7
    >>> check_seed("seed", 2**63)
    Traceback (most recent call last):
    ...
    ValueError: seed must be an integer in [0, 9223372036854775807], got 9223372036854775808
    """
    if isinstance(value, np.random.SeedSequence | np.random.BitGenerator | np.random.Generator):
        raise ValueError(f"{name} must be an integer in [0, {SEED_MAX}], got {shown(value)}: pass an int "
                         f"seed")
    return check_int(name, value, 0, SEED_MAX)


def seed_after(seed, k=1):
    """The seed ``k`` places after ``seed``, wrapping past :data:`SEED_MAX` to 0.

    The seed of a second stream derived from a checked seed (a fault injection beside a
    run's noise): ``seed + k`` for every seed but the last ``k`` of the range, which would
    otherwise be refused under a name the caller never gave.

    Examples
    --------
    >>> seed_after(3), seed_after(SEED_MAX)
    (4, 0)
    """
    return (check_seed("seed", seed) + check_int("k", k, 0, SEED_MAX)) % (SEED_MAX + 1)


def make_rng(seed=None, name="rng"):
    """Return a :class:`numpy.random.Generator` from a seed or an existing generator.

    ``None`` gives seed 0, so that every result in the book is reproducible unless a
    caller asks otherwise by passing a Generator. ``name``: the caller's parameter, for the
    message that refuses anything else.

    Examples
    --------
    >>> bool(make_rng(1).integers(10) == make_rng(1).integers(10))
    True
    """
    if isinstance(seed, np.random.Generator):
        return seed
    if seed is None:
        seed = 0
    if isinstance(seed, bool) or not isinstance(seed, Integral | np.integer) or not 0 <= seed <= SEED_MAX:
        how = ": pass an int seed (or a Generator: np.random.default_rng(seq))" \
            if isinstance(seed, np.random.SeedSequence | np.random.BitGenerator) else ""
        raise ValueError(f"{name} must be a numpy Generator or an integer seed in "
                         f"[0, {SEED_MAX}], got {shown(seed)}{how}")
    return np.random.default_rng(int(seed))


def _check_bounds(name, lo, hi):
    """The range of a check: NaN bounds would let every value through (``x < nan`` is False),
    and crossed bounds (``lo > hi``) would refuse every value with a range such as ``[2, 0]``."""
    if lo != lo or hi != hi:  # NaN (a comparison, cheap: the checks run in every call)
        raise ValueError(f"the range of {name} must have real bounds, got lo={lo!r}, hi={hi!r}")
    if lo > hi:
        raise ValueError(f"the range of {name} must have lo <= hi, got lo={_fmt(lo)} > "
                         f"hi={_fmt(hi)} (an empty range)")


def _check_rtol(rtol):
    if not rtol >= 0.0:  # NaN or negative: a tolerance that passes or fails everything
        raise ValueError(f"rtol must be a real number in [0, inf), got {rtol!r}")


def _fmt(x):
    if x == math.inf:
        return "inf"
    if x == -math.inf:
        return "-inf"
    return f"{x:g}"


def _range(lo, hi, lo_open, hi_open, exact=False):
    """`` in [lo, hi]`` with an infinite bound written open; empty when both are infinite.
    ``exact``: integer bounds in full (2^63 - 1 is not 9.22337e+18)."""
    if lo == -math.inf and hi == math.inf:
        return ""
    fmt = (lambda x: str(int(x)) if math.isfinite(x) else _fmt(x)) if exact else _fmt
    left = "(" if lo_open or lo == -math.inf else "["
    right = ")" if hi_open or hi == math.inf else "]"
    return f" in {left}{fmt(lo)}, {fmt(hi)}{right}"


def shown(value):
    """``repr`` of a value for a message, on one line, numpy scalars as plain numbers, cut at 80
    characters; an array whose repr is longer by its dtype and shape.

    Examples
    --------
    >>> shown(np.float64(2.5)), shown("x" * 100)[-4:], shown(np.ones((3, 40), np.float32))
    ('2.5', 'x...', 'a float32 array of shape (3, 40)')
    """
    if isinstance(value, np.generic):
        value = value.item()
    text = one_line(repr(value))  # a SeedSequence's or a 2-D array's repr spans lines (review 35 Q18)
    if len(text) > 80 and isinstance(value, np.ndarray):
        return f"{'an' if value.dtype.name[0] in 'aeiou' else 'a'} {value.dtype} array of shape {value.shape}"
    return text if len(text) <= 80 else text[:77] + "..."
