"""The compiled filter's small linear algebra: a 6 x 6 product, Cholesky and its solves.

The filter's matrices are at most 6 x 6 (a state of position and velocity; at most four
measurement components per subsystem in the paper's set-up), so plain loops beat any call
into LAPACK. The Cholesky factor keeps the *reciprocals* of its diagonal, so that the solves
multiply instead of dividing. All are inlined into their callers
(:data:`~xnavlab.mars.kernel.kernel_compile.INLINE`); called from Python each compiles on its own.

Examples
--------
>>> import numpy as np
>>> A = np.array([[4.0, 2.0], [2.0, 3.0]])
>>> L = np.zeros((2, 2))
>>> b = np.array([2.0, 1.0])
>>> ok = cholesky(A, 2, L)
>>> forward(L, 2, b)
>>> backward(L, 2, b)       # b = A^-1 b
>>> bool(ok), np.allclose(A @ b, [2.0, 1.0])
(True, True)
"""

from __future__ import annotations

import math

from xnavlab.mars.kernel.kernel_compile import INLINE, jit

__all__ = ["matmul6", "cholesky", "forward", "backward", "inverse_from_cholesky"]


@jit(**INLINE)
def matmul6(A, B, out):
    """``out = A B`` for 6 x 6 matrices.

    Parameters
    ----------
    A, B : ndarray, shape (6, 6)
    out : ndarray, shape (6, 6)
        Written; must alias neither.
    """
    for i in range(6):
        for j in range(6):
            acc = 0.0
            for m in range(6):
                acc += A[i, m] * B[m, j]
            out[i, j] = acc


@jit(**INLINE)
def cholesky(A, n, L):
    """Lower Cholesky factor ``L L^T = A`` of the lower triangle of ``A[:n, :n]``.

    Parameters
    ----------
    A : ndarray, shape (>= n, >= n)
        Symmetric; only its lower triangle is read.
    n : int
        The size.
    L : ndarray, shape (>= n, >= n)
        Written: the factor's strict lower triangle, and on the diagonal the *reciprocals*
        ``1 / L_ii``. May be ``A`` itself (in place).

    Returns
    -------
    bool
        False if ``A`` is not positive definite (then ``L`` is not a factor).
    """
    ok = True
    for j in range(n):
        s = A[j, j]
        for k in range(j):
            s -= L[j, k] * L[j, k]
        if not s > 0.0:
            ok = False
            s = 1.0
        r = 1.0 / math.sqrt(s)
        L[j, j] = r
        for i in range(j + 1, n):
            s = A[i, j]
            for k in range(j):
                s -= L[i, k] * L[j, k]
            L[i, j] = s * r
    return ok


@jit(**INLINE)
def forward(L, n, b):
    """``b = L^-1 b`` in place (forward substitution).

    Parameters
    ----------
    L : ndarray, shape (>= n, >= n)
        A factor from :func:`cholesky`.
    n : int
        The size.
    b : ndarray, shape (>= n,)
        Overwritten in its first n entries.
    """
    for i in range(n):
        s = b[i]
        for k in range(i):
            s -= L[i, k] * b[k]
        b[i] = s * L[i, i]


@jit(**INLINE)
def backward(L, n, b):
    """``b = L^-T b`` in place (back substitution; after :func:`forward`, ``b = A^-1 b``).

    Parameters
    ----------
    L : ndarray, shape (>= n, >= n)
        A factor from :func:`cholesky`.
    n : int
        The size.
    b : ndarray, shape (>= n,)
        Overwritten in its first n entries.
    """
    for i in range(n - 1, -1, -1):
        s = b[i]
        for k in range(i + 1, n):
            s -= L[k, i] * b[k]
        b[i] = s * L[i, i]


@jit(**INLINE)
def inverse_from_cholesky(L, out):
    """``out = (L L^T)^-1`` for a 6 x 6 factor, ``A^-1 = L^-T L^-1``.

    Parameters
    ----------
    L : ndarray, shape (6, 6)
        A factor from :func:`cholesky`; overwritten by ``L^-1`` (its lower triangle).
    out : ndarray, shape (6, 6)
        Its lower triangle is written.
    """
    for j in range(6):
        for i in range(j + 1, 6):
            s = 0.0
            for k in range(j, i):
                s -= L[i, k] * L[k, j]
            L[i, j] = s * L[i, i]
    # A^-1 = L^-T L^-1
    for a in range(6):
        for b in range(a + 1):
            s = 0.0
            for k in range(a, 6):
                s += L[k, a] * L[k, b]
            out[a, b] = s
