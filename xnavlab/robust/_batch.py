"""Batched linear algebra of the ephemeris-error filters: a stack of runs stepped at once.

Plumbing of :mod:`xnavlab.robust.filters`: states ``x`` (r, m) and covariances ``P`` (r, m, m),
one row per run. Every product is taken run by run (a matrix times each run's vector or
matrix), so a run's numbers are the same to the last bit whatever else is in its batch, and
the same as the single-run arithmetic of :mod:`xnavlab.core.filters`. Not part of the
public API.
"""

from __future__ import annotations

import numpy as np

__all__ = ["tr", "sym", "mv", "first", "sigma_points", "unscented"]


def tr(a):
    """The transpose of each matrix of a stack (the last two axes swapped)."""
    return np.swapaxes(a, -1, -2)


def sym(P):
    """``(P + P^T) / 2`` of each matrix of a stack."""
    return 0.5 * (P + tr(P))


def mv(A, v):
    """``A v`` for each run: A (r, p, q) or (p, q), v (r, q) -> (r, p); each run's product is
    the one of its own (a run's numbers do not depend on the others in its batch)."""
    return (A @ v[..., None])[..., 0]


def first(arrays):
    """The first run of each array: a batch of one back to one run."""
    return tuple(a[0] for a in arrays)


def sigma_points(x, P, lam):
    """``x, x +/- columns of chol((m + lam) P)`` per run (:func:`xnavlab.core.filters.sigma_points`)."""
    try:
        L = np.linalg.cholesky((x.shape[-1] + lam) * sym(P))
    except np.linalg.LinAlgError:
        raise ValueError("P must be positive definite (its Cholesky factor failed)") from None
    c = x[:, None, :]
    return np.concatenate([c, c + tr(L), c - tr(L)], axis=1)  # (r, 2m + 1, m)


def unscented(Y, Wm, Wc, noise):
    """Mean and covariance of sigma points Y (r, 2m + 1, q) per run (deviations from the centre)."""
    mean = Y[:, 0] + Wm @ (Y - Y[:, :1])
    D = Y - mean[:, None, :]
    return mean, sym(tr(Wc[:, None] * D) @ D + noise)  # P- = sum Wc (Y - x-)(Y - x-)^T + Q
