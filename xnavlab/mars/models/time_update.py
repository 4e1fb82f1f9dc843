"""The filters' time update of the Mars scenario: the state propagated with the paper's force model.

Fan et al. 2016 give the filters' dynamics (Mars central gravity, the Sun and Jupiter as third
bodies, in the Mars-centred J2000 frame) but no process noise. Here: the RK4 propagation of the
state (:func:`filter_step`, :func:`filter_propagate`, which also returns the transition matrix
the EKF needs), the white-acceleration process noise (:func:`process_noise`), and
:class:`Propagation`, one memoised time update for the filters of
:mod:`xnavlab.mars.navigation.scenarios`. Chapter 5 shows one predict step with them.
"""

from __future__ import annotations

import math

import numpy as np

from xnavlab.core.validate import check_instance, check_real, check_vector
from xnavlab.mars.models import dynamics

__all__ = ["process_noise", "filter_step", "filter_propagate", "Propagation"]


def process_noise(dt, q):
    """White-acceleration process noise over ``dt``: ``q [[dt^3/3 I, dt^2/2 I], [dt^2/2 I, dt I]]``.

    ``dt`` in s and ``q`` in m^2/s^3, each in [0, 1e6] (beyond, ``dt^3`` and the products
    overflow).

    Examples
    --------
    >>> process_noise(2.0, 3.0)[[0, 0, 3], [0, 3, 3]].tolist()
    [8.0, 6.0, 6.0]
    """
    dt, q = check_real("dt", dt, 0.0, 1e6), check_real("q", q, 0.0, 1e6)
    Q = np.zeros((6, 6))
    I3 = np.eye(3)
    Q[:3, :3] = q * dt**3 / 3.0 * I3
    Q[:3, 3:] = Q[3:, :3] = q * dt**2 / 2.0 * I3
    Q[3:, 3:] = q * dt * I3
    return Q


def filter_step(x, t, dt, table):
    """The filters' state propagation: one classical RK4 step of the paper's force model.

    Parameters
    ----------
    x : ndarray, shape (6,)
        State at ``t``, its position 1 m to 1e15 m from Mars's centre.
    t, dt : float
        Epoch and step, s; ``dt`` in [-86400, 86400] (one day either way), ``t`` and ``t + dt``
        inside the table's span.
    table : ThirdBodyTable or None
        Third bodies (filter ephemeris); None: Mars's point mass alone.

    Examples
    --------
    >>> tab = dynamics.ThirdBodyTable(dynamics.MARS_T0, dynamics.MARS_T0 + 100.0)
    >>> x1 = filter_step(dynamics.MARS_STATE0, dynamics.MARS_T0, 3.0, tab)
    >>> truth = dynamics.propagate([dynamics.MARS_T0 + 3.0])[0]
    >>> bool(np.abs(x1 - truth)[:3].max() < 1e-6)
    True
    """
    x = check_vector("x", x, 6)  # one state: (1, 6) was refused as r (review 35k)
    if not dynamics.R_MIN <= math.hypot(*x[:3]) <= dynamics.R_MAX:  # not as acceleration's r
        raise ValueError(f"x position must lie between {dynamics.R_MIN:g} m and "
                         f"{dynamics.R_MAX:g} m of Mars's centre, got |r| = "
                         f"{math.hypot(*x[:3]):g} m")
    t, dt = check_real("t", t), check_real("dt", dt, -86400.0, 86400.0)
    _check_span(t, dt, _check_table(table))

    def f(tt, y):
        return np.concatenate([y[3:], dynamics.acceleration(tt, y[:3], table)])

    k1 = f(t, x)
    k2 = f(t + dt / 2, x + dt / 2 * k1)
    k3 = f(t + dt / 2, x + dt / 2 * k2)
    k4 = f(t + dt, x + dt * k3)
    return x + dt / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)


def filter_propagate(x, t, dt, table, max_step=10.0):
    """The filters' time update of the state: ``ceil(dt / max_step)`` RK4 sub-steps.

    Returns the propagated state and the transition matrix ``Phi_n ... Phi_1``
    (:func:`xnavlab.mars.models.dynamics.transition_matrix` at the start of each sub-step).
    ``max_step`` (s) is in [0.01, 86400], and at most 1e6 sub-steps are taken (a ``dt`` or a
    ``max_step`` that asks for more is refused, not run without end).

    Returns
    -------
    x : ndarray, shape (6,)
    Phi : ndarray, shape (6, 6)

    Examples
    --------
    >>> tab = dynamics.ThirdBodyTable(dynamics.MARS_T0, dynamics.MARS_T0 + 600.0)
    >>> x, Phi = filter_propagate(dynamics.MARS_STATE0, dynamics.MARS_T0, 500.0, tab)
    >>> truth = dynamics.propagate([dynamics.MARS_T0 + 500.0])[0]
    >>> bool(np.abs(x - truth)[:3].max() < 1e-3)
    True
    """
    x = check_vector("x", x, 6)
    t, dt, max_step = _check_steps(t, dt, table, max_step)
    n = max(1, math.ceil(dt / max_step - 1e-9))
    h = dt / n
    Phi = np.eye(6)
    for i in range(n):
        Phi = dynamics.transition_matrix(x[:3], h) @ Phi
        x = filter_step(x, t + i * h, h, table)
    return x, Phi


def _check_table(table):
    """The filter's third bodies: a ThirdBodyTable (its ``bodies`` may be empty) or None (Mars's
    point mass alone, as :func:`xnavlab.mars.models.dynamics.acceleration`)."""
    if table is not None:
        check_instance("table", table, dynamics.ThirdBodyTable, "a ThirdBodyTable or None")
    return table


def _check_span(t, dt, table):
    """The step from ``t`` to ``t + dt`` inside the table's span (review 35j: a step out of it
    was refused naming ``t`` and a value inside the step, not the user's ``dt``)."""
    if table is None:
        return
    lo, hi = table.t_start, float(table.knots[-1])
    if not lo <= t <= hi:
        raise ValueError(f"t must lie in [{lo:.9g}, {hi:.9g}] s, the table's span, got {t:.9g}")
    if not lo <= t + dt <= hi:
        raise ValueError(f"dt = {dt:g} s takes the step to t + dt = {t + dt:.9g} s, outside the "
                         f"table's span [{lo:.9g}, {hi:.9g}] s: dt must be in [{lo - t:.6g}, "
                         f"{hi - t:.6g}] from this t")


def _check_steps(t, dt, table, max_step):
    """(t, dt, max_step) checked, and the table: max_step in [0.01, 86400] s and at most 1e6
    sub-steps."""
    t, dt = check_real("t", t), check_real("dt", dt, 0.0)
    _check_table(table)
    # from 0.01 s (a scenario's shortest sub-step: RK4's truncation error is below its round-off
    # long before; a subnormal step asked for 1e300 sub-steps) to one day
    max_step = check_real("max_step", max_step, 0.01, 86400.0)
    if dt / max_step > 1e6:
        raise ValueError(f"dt / max_step must be at most 1e6 sub-steps, got dt = {dt:g} s and "
                         f"max_step = {max_step:g} s ({dt / max_step:.3g})")
    _check_span(t, dt, table)
    return t, dt, max_step


class Propagation:
    """One time update of the filters, memoised: ``f(x)`` and ``F(x)`` integrate once.

    Parameters
    ----------
    t, dt : float
        Epoch and step, s (``dt >= 0``).
    table : ThirdBodyTable or None
        Third bodies (filter ephemeris); None: Mars's point mass alone.
    max_step : float
        Largest RK4 sub-step, s, in [0.01, 86400]; ``dt / max_step`` at most 1e6 (as
        :func:`filter_propagate`, which it calls).

    Examples
    --------
    >>> tab = dynamics.ThirdBodyTable(dynamics.MARS_T0, dynamics.MARS_T0 + 600.0)
    >>> prop = Propagation(dynamics.MARS_T0, 60.0, tab, 10.0)
    >>> x1 = prop.f(dynamics.MARS_STATE0)
    >>> bool(np.array_equal(prop.F(dynamics.MARS_STATE0) @ np.eye(6), prop.F(dynamics.MARS_STATE0)))
    True
    """

    def __init__(self, t, dt, table, max_step):
        t, dt, max_step = _check_steps(t, dt, table, max_step)  # refused now, not at the first call
        self.args = (t, dt, table, max_step)
        self.key, self.val = None, None

    def _get(self, x):
        x = check_vector("x", x, 6)
        key = x.tobytes()
        if key != self.key:
            self.key, self.val = key, filter_propagate(x, *self.args)
        return self.val

    def f(self, x):
        return self._get(x)[0]

    def F(self, x):
        return self._get(x)[1]
