"""xnavlab.mars.kernel.kernel_linalg: the compiled filter's Cholesky, solves and products against numpy."""

import numpy as np

from xnavlab.core.validate import make_rng
from xnavlab.mars.kernel import kernel_linalg as kl


def _spd(n, seed):
    a = make_rng(seed).normal(size=(n, n))
    return a @ a.T + n * np.eye(n)


def test_cholesky_and_its_solves_invert_the_matrix():
    for n, seed in ((3, 0), (4, 1), (6, 2)):
        A = _spd(n, seed)
        L = np.zeros((n, n))
        assert kl.cholesky(A, n, L)
        ref = np.linalg.cholesky(A)
        assert np.allclose(np.tril(L, -1), np.tril(ref, -1), rtol=1e-12)
        assert np.allclose(np.diag(L), 1.0 / np.diag(ref), rtol=1e-12)   # reciprocals
        b = make_rng(seed).normal(size=n)
        y = b.copy()
        kl.forward(L, n, y)
        kl.backward(L, n, y)
        assert np.allclose(y, np.linalg.solve(A, b), rtol=1e-10)


def test_cholesky_refuses_a_matrix_that_is_not_positive_definite():
    A = np.array([[1.0, 2.0], [2.0, 1.0]])
    assert not kl.cholesky(A, 2, np.zeros((2, 2)))


def test_the_inverse_and_the_product_of_6_x_6_matrices():
    A = _spd(6, 3)
    L, out = np.zeros((6, 6)), np.zeros((6, 6))
    kl.cholesky(A, 6, L)
    kl.inverse_from_cholesky(L, out)
    assert np.allclose(np.tril(out), np.tril(np.linalg.inv(A)), rtol=1e-10, atol=1e-14)
    B = _spd(6, 4)
    prod = np.zeros((6, 6))
    kl.matmul6(A, B, prod)
    assert np.allclose(prod, A @ B, rtol=1e-14)
