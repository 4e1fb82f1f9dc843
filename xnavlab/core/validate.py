"""Argument checks shared by every module.

Every public function validates its inputs with these helpers, so a bad value
raises one :class:`ValueError` that names the parameter and the allowed range
instead of propagating a NaN, clipping silently or failing deep in a traceback.
"""

from __future__ import annotations

import math
from numbers import Integral, Real

import numpy as np

__all__ = [
    "check_real",
    "check_int",
    "check_finite_array",
    "check_choice",
    "check_vector",
    "check_covariance",
    "make_rng",
]


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
    """
    left = "(" if lo_open else "["
    right = ")" if hi_open else "]"
    rng = f"{left}{_fmt(lo)}, {_fmt(hi)}{right}"
    if isinstance(value, bool) or not isinstance(value, Real | np.floating | np.integer):
        raise ValueError(f"{name} must be a real number in {rng}, got {value!r}")
    x = float(value)
    bad = (
        not math.isfinite(x)
        or (x < lo or (lo_open and x == lo))
        or (x > hi or (hi_open and x == hi))
    )
    if bad:
        raise ValueError(f"{name} must be a real number in {rng}, got {value!r}")
    return x


def check_int(name, value, lo=-math.inf, hi=math.inf):
    """Return ``int(value)`` if it is an integer in ``[lo, hi]``, else raise.

    Examples
    --------
    >>> check_int("levels", 5, 1, 10)
    5
    """
    rng = f"[{_fmt(lo)}, {_fmt(hi)}]"
    if isinstance(value, bool) or not isinstance(value, Integral | np.integer):
        raise ValueError(f"{name} must be an integer in {rng}, got {value!r}")
    if value < lo or value > hi:
        raise ValueError(f"{name} must be an integer in {rng}, got {value!r}")
    return int(value)


def check_finite_array(name, value, shape=None, dtype=float):
    """Return ``value`` as a finite float array, checking its trailing shape.

    Parameters
    ----------
    name : str
        Parameter name used in the error message.
    value : array_like
        Value to check.
    shape : tuple of int or None, optional
        Required trailing shape (``None`` entries match any size).

    Examples
    --------
    >>> check_finite_array("r", [1.0, 2.0, 3.0], shape=(3,)).shape
    (3,)
    """
    try:
        arr = np.asarray(value, dtype=dtype)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be an array of finite numbers, got {value!r}") from None
    if shape is not None:
        tail = arr.shape[arr.ndim - len(shape):] if arr.ndim >= len(shape) else None
        ok = tail is not None and all(s is None or s == t for s, t in zip(shape, tail, strict=True))
        if not ok:
            want = "(..., " + ", ".join("n" if s is None else str(s) for s in shape) + ")"
            raise ValueError(f"{name} must have trailing shape {want}, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must contain only finite numbers (no NaN or inf)")
    return arr


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
    arr = check_finite_array(name, value)
    size = arr.shape[0] if arr.ndim == 2 else None
    want = "(n, n)" if n is None else f"({n}, {n})"
    if arr.ndim != 2 or arr.shape[1] != size or (n is not None and size != n):
        raise ValueError(f"{name} must be a square matrix of shape {want}, got shape {arr.shape}")
    scale = float(np.max(np.abs(arr))) if arr.size else 0.0
    if np.max(np.abs(arr - arr.T), initial=0.0) > rtol * scale:
        raise ValueError(f"{name} must be symmetric (to {rtol:g} of its largest entry)")
    low = float(np.linalg.eigvalsh(0.5 * (arr + arr.T))[0]) if size else 0.0
    if definite and not low > 0.0:
        raise ValueError(f"{name} must be positive definite, got smallest eigenvalue {low:.3g}")
    if low < -rtol * scale:
        raise ValueError(f"{name} must be positive semi-definite, got smallest eigenvalue {low:.3g}")
    return arr


def make_rng(seed=None):
    """Return a :class:`numpy.random.Generator` from a seed or an existing generator.

    ``None`` gives seed 0, so that every result in the book is reproducible unless a
    caller asks otherwise by passing a Generator.

    Examples
    --------
    >>> bool(make_rng(1).integers(10) == make_rng(1).integers(10))
    True
    """
    if isinstance(seed, np.random.Generator):
        return seed
    if seed is None:
        seed = 0
    seed = check_int("seed", seed, 0, 2**63 - 1)
    return np.random.default_rng(seed)


def _fmt(x):
    if x == math.inf:
        return "inf"
    if x == -math.inf:
        return "-inf"
    return f"{x:g}"
