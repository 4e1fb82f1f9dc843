"""The dedicated-observer scheme's residuals (xnavlab.attitude.dos)."""


import numpy as np
import pytest

from xnavlab import attitude as att


def test_dos_rate_matrices_invert_each_group():
    H = att.gyro_matrix()
    T = att.dos_rate_matrices()
    for j, g in enumerate(att.DOS_GROUPS):
        assert j not in g
        np.testing.assert_allclose(T[j] @ H[list(g)], np.eye(3), atol=1e-12)


def test_dos_residuals():
    d = np.zeros((4, 3))
    d[2] = [3.0, 4.0, 0.0]
    np.testing.assert_allclose(att.dos_residuals(d, np.zeros((4, 3))), [0, 0, 5.0, 0])
    with pytest.raises(ValueError, match="^drift_ref"):
        att.dos_residuals(d, np.zeros((3, 3)))
