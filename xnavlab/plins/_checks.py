"""The input checks that the PL/INS modules share: pseudolite sites (ECEF, distinct, at least one).

Plumbing of :mod:`xnavlab.plins`; not part of the public API.
"""

from __future__ import annotations

import numpy as np

from xnavlab.core.validate import check_finite_array

__all__ = ["check_sites", "distinct_sites"]


def check_sites(sites, name="sites"):
    """Pseudolite sites as an (m, 3) ECEF array, m >= 1, at least 1 m apart, else one ValueError
    leading with ``name`` (no site was an empty (0, 10) measurement matrix or an IndexError)."""
    sites = check_finite_array(name, sites, shape=(3,))
    if sites.ndim != 2 or len(sites) < 1:
        raise ValueError(f"{name} must have shape (m, 3) with m >= 1 (one row a pseudolite), got "
                         f"shape {sites.shape}")
    return distinct_sites(name, sites)


def distinct_sites(name, ecef):
    """ECEF sites at least 1 m apart (two antennas cannot share a place), or ValueError."""
    gap = np.linalg.norm(ecef[:, None, :] - ecef[None, :, :], axis=-1)
    i, j = np.triu_indices(len(ecef), k=1)
    close = np.flatnonzero(gap[i, j] < 1.0)
    if close.size:
        k = close[0]
        raise ValueError(f"{name} must be distinct sites at least 1 m apart, got sites {i[k]} "
                         f"and {j[k]} {gap[i[k], j[k]]:.3g} m apart")
    return ecef
