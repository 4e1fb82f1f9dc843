"""Argument checks of the ephemeris-error filters' step functions and batch runner.

Plumbing of :mod:`xnavlab.robust.filters` (kept apart so that the filters' module holds the
filters): each check names the argument at fault first, the later arguments' shapes checked
against the earlier ones (:func:`xnavlab.core.validate.check_shape`). Not part of the public
API.
"""

from __future__ import annotations

import numpy as np

from xnavlab.core.validate import check_shape, check_vector, shown

__all__ = ["check_state", "check_update", "check_runs"]


def check_state(x, P, n_dyn=6):
    """``x`` as a 1-D state of at least ``n_dyn`` entries and ``P`` its (m, m) covariance."""
    x = check_vector("x", x)
    if x.size < n_dyn:
        raise ValueError(f"x must hold at least {n_dyn} entries [r, v, ...], got {x.size}")
    return x, check_shape("P", P, (x.size, x.size), "m = size of x")


def check_update(x, P, y, R, n, size, yname="y"):
    """The arguments of a measurement update: ``x`` (m,), ``P`` (m, m), ``y`` (k,), ``R``
    (k, k), ``n`` (k, 3), each checked on its own, then the sizes against the pulsars of
    ``n`` (``n`` is named when ``y`` and ``R`` agree on another k), then ``x`` against
    ``size(k) -> (m, what x must have)`` and ``P`` against ``x``."""
    x = check_vector("x", x)
    P = check_shape("P", P, (None, None))
    y = check_vector(yname, y)
    if y.size == 0:
        raise ValueError(f"{yname} must hold at least one measurement, got an empty array")
    R = check_shape("R", R, (None, None))
    n = check_shape("n", n, (None, 3))
    if y.size == R.shape[0] == R.shape[1] != n.shape[0]:
        check_shape("n", n, (y.size, 3), f"k = size of {yname} and R")
    k = n.shape[0]
    y = check_shape(yname, y, (k,), "k = rows of n")
    R = check_shape("R", R, (k, k), "k = rows of n")
    m, what = size(k)
    if x.size != m:
        raise ValueError(f"x must have {what}, got {x.size}")
    return x, check_shape("P", P, (m, m), "m = size of x"), y, R, n


def check_runs(scenarios, rngs, kind):
    """``scenarios`` as a non-empty list of ``kind`` (a Scenario) and ``rngs`` as one entry per
    scenario (``None``: a list of Nones), each refusal naming the argument."""
    if not isinstance(scenarios, list | tuple):
        raise ValueError(f"scenarios must be a list of Scenarios from simulate(), got {shown(scenarios)}")
    if not scenarios:
        raise ValueError("scenarios must hold at least one Scenario from simulate(), got an empty list")
    for i, s in enumerate(scenarios):
        if not isinstance(s, kind):
            raise ValueError(f"scenarios[{i}] must be a Scenario from simulate(), got {shown(s)}")
    if rngs is None:
        return list(scenarios), [None] * len(scenarios)
    if not isinstance(rngs, list | tuple | range) and not (isinstance(rngs, np.ndarray) and rngs.ndim == 1):
        raise ValueError(f"rngs must be a list of Generators or seeds, one per scenario, got {shown(rngs)}")
    if len(rngs) != len(scenarios):
        raise ValueError(f"rngs must hold one entry per scenario ({len(scenarios)}), got {len(rngs)}")
    return list(scenarios), list(rngs)
