"""The single-observer scheme's residuals (xnavlab.attitude.sos): the gyro parity and the SOS residuals."""


import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from xnavlab import attitude as att

DPH = att.DEG_PER_H


small_rate = st.lists(st.floats(-0.05, 0.05), min_size=3, max_size=3).map(np.array)


@given(small_rate)
def test_gyro_parity_is_blind_to_the_rate(w):
    assert abs(float(att.gyro_parity(att.gyro_matrix() @ w))) < 1e-15
    b = np.array(att.PAPER_DRIFTS_DEG_PER_H) * DPH
    p = att.gyro_parity(att.gyro_matrix() @ w + b)
    assert float(p) == pytest.approx(b[3] - att.SKEW_AXIS @ b[:3], abs=1e-15)


def test_sos_residuals():
    r = att.sos_residuals(np.ones((5, 3)), np.zeros((5, 4)), np.zeros((5, 3)), np.ones(5))
    np.testing.assert_allclose(r, np.ones((5, 4)))
    with pytest.raises(ValueError, match="^drift_hat"):
        att.sos_residuals(np.ones(4), np.zeros(4), np.zeros(3), 0.0)
    with pytest.raises(ValueError, match="^omega_g"):
        att.sos_residuals(np.ones(3), np.zeros(3), np.zeros(3), 0.0)
