"""The compiled scan of :class:`~xnavlab.core.detection.combined.InnovationMonitor`: chi-square,
mean CUSUMs and variance CUSUMs of a segment in one pass.

Plumbing of :mod:`xnavlab.core.detection.combined` (kept apart for that module's length); not
part of the public API.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["scan_segment"]


@njit(cache=True)
def scan_segment(y, scale, S0, k_mean, k_var, chi2_thr, h_mean, h_var, rows, rmax, S_end, stop):
    """Compiled form of :meth:`~xnavlab.core.detection.combined.InnovationMonitor._segment`.

    The same operations in the same order as the array form (so the same bits): ``z = y / s``,
    ``q = sum z^2``, running sums ``D`` of ``[z - k, -z - k, z^2 - k_v]``, their running minima
    ``M``, ``S = D - min(-S_0, M)`` (Lindley), every statistic over its threshold. ``rows`` is
    (N, 1 + 3m) to keep every sample's ratios, or (1, 1 + 3m) to keep only the latest (then,
    after an alarm with ``stop``, the alarm's). Fills ``rmax`` (N,) with each sample's largest
    ratio and ``S_end`` (3m,) with the CUSUMs of the last sample scanned. With ``stop`` the scan
    ends at the first sample whose largest ratio exceeds 1. Returns that sample's index or -1.
    """
    n, m = y.shape
    keep = rows.shape[0] == n
    D = np.zeros(3 * m)
    M = np.empty(3 * m)
    z = np.empty(m)
    first = -1
    for i in range(n):
        ri = i if keep else 0
        q = 0.0
        for c in range(m):
            z[c] = y[i, c] / scale[c]
            q += z[c] * z[c]                                   # chapter 9 eq. (ch9-chi2)
        for c in range(m):
            D[c] += z[c] - k_mean                              # S+ increments
            D[m + c] += -z[c] - k_mean                         # S- increments
            D[2 * m + c] += z[c] * z[c] - k_var                # variance increments
        best = q / chi2_thr
        rows[ri, 0] = best
        for j in range(3 * m):
            M[j] = D[j] if i == 0 else min(M[j], D[j])
            S = D[j] - min(-S0[j], M[j])                       # S_n = D_n - min(-S_0, min D_j)
            r = S / (h_mean if j < 2 * m else h_var)
            rows[ri, 1 + j] = r
            S_end[j] = S
            if r > best:
                best = r
        rmax[i] = best
        if first < 0 and best > 1.0:
            first = i
            if stop:
                return i
    return first
