"""Argument checks of the ephemeris-error filters' step functions and batch runner.

Plumbing of :mod:`xnavlab.robust.filters` (kept apart so that the filters' module holds the
filters): each check names the argument at fault first, the later arguments' shapes checked
against the earlier ones (:func:`xnavlab.core.validate.check_shape`). Not part of the public
API.
"""

from __future__ import annotations

from numbers import Integral

import numpy as np

from xnavlab.core import dates, ephemeris
from xnavlab.core.validate import (
    check_covariance,
    check_finite_array,
    check_real,
    check_shape,
    check_vector,
    shown,
)
from xnavlab.mars.models.dynamics import R_MAX

__all__ = ["check_state", "check_update", "check_runs", "check_position", "check_directions",
           "check_run_of", "check_epoch", "check_n_dyn", "UNIT_TOL"]

#: How far from 1 the norm of a pulsar direction may be. A direction is a unit vector: a row
#: of norm k would scale the range ``n . r`` by k, so a non-unit one is refused rather than
#: silently rescaled (that would hide a wrong input); 1e-6 leaves room for directions typed
#: to 7 digits or computed in float32.
UNIT_TOL = 1e-6


def check_position(name, r, radius, body):
    """Positions ``r`` (..., 3), m, between the planet's radius and R_MAX from its centre: the
    two-body + J2 field is the planet's field outside it only (and singular at the centre)."""
    r = check_finite_array(name, r, shape=(3,))
    with np.errstate(over="ignore"):  # a norm beyond float64 (inf) is refused below
        rn = np.linalg.norm(r, axis=-1)
    bad = (rn < radius) | (rn > R_MAX)
    if np.any(bad):
        worst = float(np.ravel(rn)[np.argmax(np.ravel(bad))])
        raise ValueError(f"{name} must lie between the radius of {body} ({radius:g} m) and "
                         f"{R_MAX:g} m from its centre, got |{name}| = {worst:g} m")
    return r


def check_epoch(name, t0, span=0.0, span_name=None, span_expr=None):
    """``t0`` (s TDB past J2000) as a float whose span ``[t0, t0 + span]`` both ephemerides
    (DE421 and DE405) cover, else one ValueError leading with ``name`` (``span_name`` when
    ``t0`` lies inside and only the span's end, ``name + span_expr``, outside): the user's own
    parameter, never the ephemeris' ``t``."""
    lo = max(ephemeris.coverage(e)[0] for e in ephemeris.EPHEMERIDES)
    hi = min(ephemeris.coverage(e)[1] for e in ephemeris.EPHEMERIDES)
    want = f"in {dates.epoch_range(lo, hi)} (the years DE421 and DE405 both cover)"
    try:
        t0 = check_real(name, t0, lo, hi)
    except ValueError:
        raise ValueError(f"{name} must be an epoch {want}, got {shown(t0)}") from None
    if t0 + span > hi:
        raise ValueError(f"{span_name} must end the run within the ephemerides: {name} + "
                         f"{span_expr or span_name} at most {dates.epoch_text(hi)} s TDB past J2000 "
                         f"({hi - t0:.9g} s after {name} = {dates.epoch_text(t0)}), got "
                         f"{dates.epoch_text(t0 + span)}")
    return t0


def check_n_dyn(n_dyn):
    """``n_dyn`` as 6: the step propagates the six components ``[r, v]`` of the state."""
    if isinstance(n_dyn, bool) or not isinstance(n_dyn, Integral | np.integer) or n_dyn != 6:
        raise ValueError(f"n_dyn must be 6 (the dynamics propagate the six components [r, v] of x; "
                         f"further components are held), got {shown(n_dyn)}")
    return 6


def check_directions(name, n):
    """Pulsar directions ``n`` (k, 3) as unit rows (to :data:`UNIT_TOL`), a zero row refused."""
    n = check_finite_array(name, n)
    if n.ndim != 2 or n.shape[1] != 3:  # said as the docstrings say it: k pulsars, not "(n, 3)"
        raise ValueError(f"{name} must have shape (k, 3), one pulsar a row, got shape {n.shape}")
    norms = np.linalg.norm(n, axis=1)
    if np.any(norms == 0.0):
        i = int(np.argmax(norms == 0.0))
        raise ValueError(f"{name} must hold unit directions, got a zero row {name}[{i}]")
    off = np.abs(norms - 1.0)
    if np.any(off > UNIT_TOL):
        i = int(np.argmax(off))
        raise ValueError(f"{name} must hold unit directions (norm 1 to {UNIT_TOL:g}), got "
                         f"|{name}[{i}]| = {norms[i]:.6g}")
    return n


def check_state(x, P, n_dyn=6):
    """``x`` as a 1-D state of at least ``n_dyn`` entries and ``P`` its (m, m) covariance,
    symmetric positive definite (its sigma points take its Cholesky factor)."""
    x = check_vector("x", x)
    if x.size < n_dyn:
        raise ValueError(f"x must hold at least {n_dyn} entries [r, v, ...], got {x.size}")
    P = check_shape("P", P, (x.size, x.size), "m = size of x")
    return x, check_covariance("P", P, x.size, definite=True)


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
    n = check_directions("n", n)
    if y.size == R.shape[0] == R.shape[1] != n.shape[0]:
        check_shape("n", n, (y.size, 3), f"k = size of {yname} and R")
    k = n.shape[0]
    y = check_shape(yname, y, (k,), "k = rows of n")
    R = check_shape("R", R, (k, k), "k = rows of n")
    m, what = size(k)
    if x.size != m:
        raise ValueError(f"x must have {what}, got {x.size}")
    P = check_covariance("P", check_shape("P", P, (m, m), "m = size of x"), m)
    return x, P, y, check_covariance("R", R, k, definite=True), n  # R definite: S inverted


def check_run_of(run, scenario):
    """``scenario`` as the one ``run`` ran on: its epochs, and its truth, against which the run
    recorded its errors ``|r_hat - r|`` (a run records no seed: two seeds of one body share the
    truth, and the run's errors, hence its scores, are the same against either)."""
    if run.x.shape[0] != scenario.t.size:
        raise ValueError(f"scenario must be the one the run ran on: it has {scenario.t.size} epochs, "
                         f"the run {run.x.shape[0]}")
    err = np.linalg.norm(run.x[:, :3] - scenario.x_true[:, :3], axis=1)
    if not np.allclose(err, run.error, rtol=1e-9, atol=1e-6):
        raise ValueError("scenario must be the one the run ran on: the run's errors |r_hat - r| "
                         "were not measured against this scenario's truth x_true")


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
