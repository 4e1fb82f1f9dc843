"""The compiled orbit propagator of the ephemeris-error system: two-body + J2, RK4.

Plumbing of :mod:`xnavlab.robust`: :func:`xnavlab.robust.ephemeris_error.propagate` and
:func:`xnavlab.robust.ephemeris_error.acceleration` check their arguments and call these;
the filters of :mod:`xnavlab.robust.filters` call :func:`propagate_unchecked` on their sigma
points. Not part of the public API.
"""

from __future__ import annotations

import math

import numba
import numpy as np

__all__ = ["derivatives", "rk4", "propagate_unchecked"]


def propagate_unchecked(x, dt, planet, substep=20.0):
    """:func:`~xnavlab.robust.ephemeris_error.propagate` without the argument checks.

    ``x`` (..., 6) body-centred J2000 states (m, m/s), ``dt`` (s), ``planet`` the constants
    ``(gm, j2, radius, pole)`` of :data:`xnavlab.robust.ephemeris_error.PLANETS`; returns the
    propagated states, same shape. The caller guarantees finite inputs (sigma points of a
    filter).
    """
    gm, j2, radius, pole = planet
    nsub = max(1, int(math.ceil(abs(dt) / substep)))
    X = np.ascontiguousarray(np.atleast_2d(x), dtype=float)
    out = rk4(X, float(dt), nsub, gm, j2, radius, np.ascontiguousarray(pole, dtype=float))
    return out.reshape(np.shape(x))


@numba.njit(cache=True)
def derivatives(X, gm, j2, radius, pole):  # pragma: no cover - compiled
    """``dX/dt`` of states ``X`` (k, 6): two-body + J2 (paper eq. (5))."""
    out = np.empty_like(X)
    for k in range(X.shape[0]):
        r0, r1, r2 = X[k, 0], X[k, 1], X[k, 2]
        rn2 = r0 * r0 + r1 * r1 + r2 * r2
        rn = math.sqrt(rn2)
        c = -gm / (rn2 * rn)  # a = -mu r / |r|^3
        z = r0 * pole[0] + r1 * pole[1] + r2 * pole[2]
        kj = -1.5 * j2 * gm * radius * radius / (rn2 * rn2 * rn)
        f = 1.0 - 5.0 * z * z / rn2  # J2: k [(1 - 5 z^2/r^2) r + 2 z p]
        out[k, 0], out[k, 1], out[k, 2] = X[k, 3], X[k, 4], X[k, 5]
        out[k, 3] = c * r0 + kj * (f * r0 + 2.0 * z * pole[0])
        out[k, 4] = c * r1 + kj * (f * r1 + 2.0 * z * pole[1])
        out[k, 5] = c * r2 + kj * (f * r2 + 2.0 * z * pole[2])
    return out


@numba.njit(cache=True)
def rk4(X, dt, nsub, gm, j2, radius, pole):  # pragma: no cover - compiled
    """``nsub`` classical Runge-Kutta steps of ``dt / nsub`` each."""
    h = dt / nsub
    Y = X.copy()
    for _ in range(nsub):
        k1 = derivatives(Y, gm, j2, radius, pole)
        k2 = derivatives(Y + 0.5 * h * k1, gm, j2, radius, pole)
        k3 = derivatives(Y + 0.5 * h * k2, gm, j2, radius, pole)
        k4 = derivatives(Y + h * k3, gm, j2, radius, pole)
        Y = Y + (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
    return Y
