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
    propagated states, same shape (any leading axes: the sigma points of several runs at
    once). The caller guarantees finite inputs (sigma points of a filter).
    """
    gm, j2, radius, pole = planet
    nsub = max(1, int(math.ceil(abs(dt) / substep)))
    X = np.ascontiguousarray(np.reshape(x, (-1, 6)), dtype=float)
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
    """``nsub`` classical Runge-Kutta steps of ``dt / nsub`` each, states ``X`` (k, 6).

    The states are held component by component (6, k), so that the loops over them run on
    vector instructions; each state's arithmetic is that of :func:`derivatives` in the same
    order, so the result does not depend on how many states are propagated together.
    """
    h = dt / nsub
    Y = np.ascontiguousarray(X.T)
    k1, k2, k3, k4 = np.empty_like(Y), np.empty_like(Y), np.empty_like(Y), np.empty_like(Y)
    T = np.empty_like(Y)
    for _ in range(nsub):
        _soa_derivatives(Y, k1, gm, j2, radius, pole)
        _axpy(Y, 0.5 * h, k1, T)
        _soa_derivatives(T, k2, gm, j2, radius, pole)
        _axpy(Y, 0.5 * h, k2, T)
        _soa_derivatives(T, k3, gm, j2, radius, pole)
        _axpy(Y, h, k3, T)
        _soa_derivatives(T, k4, gm, j2, radius, pole)
        w = h / 6.0
        for j in range(6):
            for k in range(Y.shape[1]):  # y + h/6 (k1 + 2 k2 + 2 k3 + k4)
                Y[j, k] = Y[j, k] + w * (k1[j, k] + 2.0 * k2[j, k] + 2.0 * k3[j, k] + k4[j, k])
    return np.ascontiguousarray(Y.T)


@numba.njit(cache=True)
def _axpy(Y, a, K, out):  # pragma: no cover - compiled
    """``out = Y + a K`` (the stages' arguments)."""
    for j in range(6):
        for k in range(Y.shape[1]):
            out[j, k] = Y[j, k] + a * K[j, k]


@numba.njit(cache=True)
def _soa_derivatives(X, out, gm, j2, radius, pole):  # pragma: no cover - compiled
    """:func:`derivatives` of states held by component, ``X`` and ``out`` (6, k)."""
    p0, p1, p2 = pole[0], pole[1], pole[2]
    x0, x1, x2 = X[0], X[1], X[2]
    o3, o4, o5 = out[3], out[4], out[5]
    out[0, :] = X[3]
    out[1, :] = X[4]
    out[2, :] = X[5]
    for k in range(X.shape[1]):
        r0, r1, r2 = x0[k], x1[k], x2[k]
        rn2 = r0 * r0 + r1 * r1 + r2 * r2
        rn = math.sqrt(rn2)
        c = -gm / (rn2 * rn)  # a = -mu r / |r|^3
        z = r0 * p0 + r1 * p1 + r2 * p2
        kj = -1.5 * j2 * gm * radius * radius / (rn2 * rn2 * rn)
        f = 1.0 - 5.0 * z * z / rn2  # J2: k [(1 - 5 z^2/r^2) r + 2 z p]
        o3[k] = c * r0 + kj * (f * r0 + 2.0 * z * p0)
        o4[k] = c * r1 + kj * (f * r1 + 2.0 * z * p1)
        o5[k] = c * r2 + kj * (f * r2 + 2.0 * z * p2)
