"""Mallat's fast wavelet transform, paper eqs. (9)-(10), and the detail signals of Fig. 5.

Written out in numpy for the book and tested against PyWavelets to 1e-12.
"""

from __future__ import annotations

import math

import numpy as np
import pywt

from xnavlab.core.detection._wavelets import orthogonal_wavelet
from xnavlab.core.validate import check_choice, check_finite_array, check_int

__all__ = [
    "MALLAT_MODES",
    "mallat_filters",
    "max_level",
    "mallat_dwt",
    "mallat_idwt",
    "mallat_wavedec",
    "mallat_waverec",
    "detail_signals",
]

#: Boundary modes of the plain Mallat implementation (PyWavelets' names).
MALLAT_MODES = ("periodization", "zero", "symmetric", "reflect", "constant", "periodic")
_NP_PAD = {"zero": "constant", "symmetric": "symmetric", "reflect": "reflect",
           "constant": "edge", "periodic": "wrap"}




# --------------------------------------------------------------------------------------------
# Mallat's fast algorithm, paper eqs. (9)-(10)
# --------------------------------------------------------------------------------------------

def mallat_filters(wavelet="db3"):
    """Scaling and wavelet coefficients ``h_m``, ``g_m`` (m = 0..F-1) of eqs. (9)-(10).

    ``h`` is PyWavelets' ``rec_lo`` (the time reverse of ``dec_lo``) and ``g`` its ``rec_hi``,
    ``g_m = (-1)^m h_{F-1-m}``; both have unit norm, ``sum h = sqrt(2)``, ``sum g = 0``.

    Parameters
    ----------
    wavelet : str
        An orthogonal PyWavelets wavelet name (``"db3"``: F = 6 coefficients).

    Returns
    -------
    h, g : ndarray, shape (F,)

    Examples
    --------
    >>> h, g = mallat_filters("db3")
    >>> len(h), round(float(h.sum()), 12) == round(2 ** 0.5, 12), abs(float(g.sum())) < 1e-12
    (6, True, True)
    """
    w = orthogonal_wavelet(wavelet)
    return np.array(w.rec_lo, dtype=float), np.array(w.rec_hi, dtype=float)


def max_level(n, wavelet="db3"):
    """Deepest useful decomposition level of ``n`` samples: ``floor(log2(n / (F - 1)))``.

    The same rule as ``pywt.dwt_max_level``: deeper levels' filters outgrow the signal.

    Examples
    --------
    >>> max_level(256, "db3"), max_level(1000, "db3")
    (5, 7)
    """
    n = check_int("n", n, 1)
    F = orthogonal_wavelet(wavelet).dec_len
    return max(0, int(math.floor(math.log2(n / (F - 1))))) if n >= F - 1 else 0


def mallat_dwt(c, wavelet="db3", mode="periodization"):
    """One level of Mallat's decomposition, paper eq. (9), in plain numpy.

    ``c_{j+1,k} = sum_m h_m c_{j, 2k+m+s}`` and ``d_{j+1,k} = sum_m g_m c_{j, 2k+m+s}``: the
    paper's ``sum_n h_{n-2k} c_{j,n}`` with ``n = 2k + m + s``. The offset ``s`` and the
    extension of ``c_j`` beyond its ends follow PyWavelets' ``mode`` so that the result equals
    ``pywt.dwt(c, wavelet, mode)``: ``"periodization"`` (``s = 1 - F/2``, indices modulo the
    length, an odd length first extended by its last sample; ``ceil(N/2)`` outputs) or one of
    the padding modes ``"zero"``, ``"symmetric"``, ``"reflect"``, ``"constant"``,
    ``"periodic"`` (``s = 2 - F``, ``floor((N + F - 1)/2)`` outputs; this is the index range
    ``n = 2k+2-M .. 2k+1`` that eq. (9) prints for ``d``, with ``M = F``).

    Parameters
    ----------
    c : array_like, shape (N,)
        Approximation coefficients of level ``j`` (the signal itself for ``j = 0``).
    wavelet : str
        Orthogonal wavelet, default ``"db3"``.
    mode : str
        Boundary mode, see above.

    Returns
    -------
    c_next, d_next : ndarray
        Approximation and detail coefficients of level ``j + 1``.

    Examples
    --------
    >>> x = np.arange(8.0)
    >>> a, d = mallat_dwt(x, "haar")
    >>> bool(np.allclose(a, np.array([1, 5, 9, 13]) / 2 ** 0.5)), bool(np.allclose(d, -2 ** -0.5))
    (True, True)
    """
    c = check_finite_array("c", c)
    if c.ndim != 1 or c.size < 1:
        raise ValueError(f"c must be a non-empty 1-D array, got shape {c.shape}")
    check_choice("mode", mode, MALLAT_MODES)
    h, g = mallat_filters(wavelet)
    F = len(h)
    m = np.arange(F)
    if mode == "periodization":
        x = np.append(c, c[-1]) if c.size % 2 else c
        N = x.size
        k = np.arange(N // 2)
        idx = (2 * k[:, None] + m[None, :] + 1 - F // 2) % N       # n = 2k + m + s, periodic
    else:
        x = np.pad(c, F - 1, mode=_NP_PAD[mode])                     # x[i + F - 1] = c_ext[i]
        k = np.arange((c.size + F - 1) // 2)
        idx = 2 * k[:, None] + m[None, :] + 1                        # n = 2k + m + 2 - F
    window = x[idx]                                                   # (K, F): c_{j,n}
    return window @ h, window @ g                                     # paper eq. (9)


def mallat_idwt(c, d, wavelet="db3", mode="periodization"):
    """One level of Mallat's reconstruction, paper eq. (10), in plain numpy.

    ``c_{j-1,n} = sum_k h_{n-2k} c_{j,k} + sum_k g_{n-2k} d_{j,k}`` (with the index offset of
    :func:`mallat_dwt`): every coefficient ``c_{j,k}`` spreads ``h_m c_{j,k}`` onto samples
    ``2k + m + s``. Equals ``pywt.idwt(c, d, wavelet, mode)``: ``2K`` samples for
    ``"periodization"``, ``2K - F + 2`` for the padding modes.

    Parameters
    ----------
    c, d : array_like, shape (K,)
        Approximation and detail coefficients of level ``j``.
    wavelet, mode : str
        As in :func:`mallat_dwt`.

    Returns
    -------
    ndarray
        Approximation coefficients of level ``j - 1``.

    Examples
    --------
    >>> x = np.random.default_rng(0).normal(size=16)
    >>> bool(np.allclose(mallat_idwt(*mallat_dwt(x)), x))
    True
    """
    c = check_finite_array("c", c)
    d = check_finite_array("d", d)
    if c.ndim != 1 or c.shape != d.shape or c.size < 1:
        raise ValueError(f"c and d must be non-empty 1-D arrays of one length, got {c.shape}, {d.shape}")
    check_choice("mode", mode, MALLAT_MODES)
    h, g = mallat_filters(wavelet)
    F = len(h)
    K = c.size
    k = np.arange(K)[:, None]
    m = np.arange(F)[None, :]
    contrib = c[:, None] * h[None, :] + d[:, None] * g[None, :]      # h_{n-2k} c_k + g_{n-2k} d_k
    if mode == "periodization":
        out = np.zeros(2 * K)
        np.add.at(out, (2 * k + m + 1 - F // 2) % (2 * K), contrib)   # paper eq. (10), periodic
        return out
    if 2 * K - F + 2 < 1:
        raise ValueError(f"c must have at least {F // 2} coefficients for mode {mode!r}, got {K}")
    full = np.zeros(2 * K + F - 2)
    np.add.at(full, 2 * k + m, contrib)                               # paper eq. (10)
    return full[F - 2:2 * K]


def _check_level(level, n, wavelet):
    """``level`` in [1, max_level(n)]; ``None`` is the paper's five levels, which ``x`` must
    be long enough for (an error then names ``x``, the input the caller gave)."""
    top = max_level(n, wavelet) if n >= 1 else 0   # an empty x: named here, not as max_level's n
    want = 5 if level is None and top >= 1 else 1
    if top < want:  # max_level: floor(log2(n / (F - 1))) >= want needs n >= (F - 1) 2^want
        need = (orthogonal_wavelet(wavelet).dec_len - 1) * 2**want
        levels = "the default 5 levels" if want == 5 else "one level"
        hint = f" (or pass level in [1, {top}])" if want == 5 else ""
        raise ValueError(f"x must hold at least {need} samples for {levels} of wavelet "
                         f"{wavelet!r}{hint}, got {n}")
    return 5 if level is None else check_int("level", level, 1, top)


def mallat_wavedec(x, wavelet="db3", level=None, mode="periodization"):
    """Multilevel decomposition by repeated :func:`mallat_dwt` (paper eq. (9), ``level`` times).

    Parameters
    ----------
    x : array_like, shape (N,)
        Signal.
    wavelet, mode : str
        As in :func:`mallat_dwt`.
    level : int, optional
        Number of levels, in [1, :func:`max_level` ``(N)``]; default (None) 5, for which
        ``N >= 32 (F - 1)`` (160 samples for db3).

    Returns
    -------
    list of ndarray
        ``[c_J, d_J, d_{J-1}, ..., d_1]``, the order of ``pywt.wavedec``.

    Examples
    --------
    >>> coeffs = mallat_wavedec(np.ones(64), "db3", 2)
    >>> [len(c) for c in coeffs]
    [16, 16, 32]
    """
    x = check_finite_array("x", x)
    if x.ndim != 1:
        raise ValueError(f"x must be a 1-D array, got shape {x.shape}")
    level = _check_level(level, x.size, wavelet)
    check_choice("mode", mode, MALLAT_MODES)
    details = []
    c = x
    for _ in range(level):
        c, d = mallat_dwt(c, wavelet, mode)
        details.append(d)
    return [c] + details[::-1]


def mallat_waverec(coeffs, wavelet="db3", mode="periodization"):
    """Multilevel reconstruction by repeated :func:`mallat_idwt` (paper eq. (10)).

    As ``pywt.waverec``, an approximation one sample longer than the next detail is trimmed.

    Parameters
    ----------
    coeffs : list of array_like
        ``[c_J, d_J, ..., d_1]`` as returned by :func:`mallat_wavedec`.

    Returns
    -------
    ndarray
        The signal (one sample longer than the original for an odd length).

    Examples
    --------
    >>> x = np.random.default_rng(1).normal(size=40)
    >>> bool(np.allclose(mallat_waverec(mallat_wavedec(x, "db3", 2, "symmetric"), "db3", "symmetric"), x))
    True
    """
    if not isinstance(coeffs, list | tuple) or len(coeffs) < 2:
        raise ValueError("coeffs must be a list [c_J, d_J, ..., d_1] of at least two arrays")
    c = check_finite_array("coeffs[0]", coeffs[0])
    for j, d in enumerate(coeffs[1:], start=1):
        d = check_finite_array(f"coeffs[{j}]", d)
        if c.size == d.size + 1:
            c = c[:-1]
        c = mallat_idwt(c, d, wavelet, mode)
    return c


# --------------------------------------------------------------------------------------------
# Detail signals (paper Fig. 5)
# --------------------------------------------------------------------------------------------

def detail_signals(x, wavelet="db3", level=None, mode="symmetric"):
    """Detail signals ``D_j`` of a ``level``-level decomposition, each reconstructed to full length.

    ``D_j`` is the reconstruction from the level-``j`` detail coefficients alone (all other
    coefficients zeroed), ``A_J`` from the level-``J`` approximation alone; by linearity
    ``x = A_J + sum_j D_j`` (perfect reconstruction). This is what the paper's Fig. 5 plots for
    the UV range measurement (db3, five levels). Uses PyWavelets.

    Parameters
    ----------
    x : array_like, shape (N,)
        Measurement series (any unit; the outputs carry it).
    wavelet : str
        Default ``"db3"`` as in the paper.
    level : int, optional
        Number of levels, in [1, :func:`max_level` ``(N)``]; default (None) 5 as in the paper,
        for which ``N >= 32 (F - 1)`` (160 samples for db3).
    mode : str
        PyWavelets boundary mode, default ``"symmetric"`` (no wrap-around between the ends).

    Returns
    -------
    details : ndarray, shape (level, N)
        ``details[j - 1]`` is ``D_j`` (row 0 the finest scale).
    approx : ndarray, shape (N,)
        ``A_J``.

    Examples
    --------
    >>> x = np.random.default_rng(2).normal(size=300)
    >>> D, A = detail_signals(x)
    >>> D.shape, bool(np.allclose(D.sum(axis=0) + A, x))
    ((5, 300), True)
    """
    x = check_finite_array("x", x)
    if x.ndim != 1:
        raise ValueError(f"x must be a 1-D array, got shape {x.shape}")
    w = orthogonal_wavelet(wavelet)
    level = _check_level(level, x.size, wavelet)
    check_choice("mode", mode, pywt.Modes.modes)
    coeffs = pywt.wavedec(x, w, mode=mode, level=level)
    zeros = [np.zeros_like(c) for c in coeffs]

    def only(i):
        parts = list(zeros)
        parts[i] = coeffs[i]
        return pywt.waverec(parts, w, mode=mode)[:x.size]

    details = np.array([only(level + 1 - j) for j in range(1, level + 1)])
    return details, only(0)


