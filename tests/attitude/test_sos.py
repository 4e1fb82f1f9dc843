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


@pytest.mark.parametrize("parity_ref", [[], [1.0], np.zeros(2)])
def test_sos_residuals_names_a_parity_reference_of_other_runs(parity_ref):
    """Issue 35: parity_ref=[] was numpy's concatenate message."""
    with pytest.raises(ValueError, match=r"^parity_ref must have leading axes \(\.\.\.\) that broadcast to "
                                         r"those of the arguments before it, \(\), got \("):
        att.sos_residuals([1.0, 2.0, 3.0], [0.0, 0.0, 0.0, 1.0], [1.0, 1.0, 1.0], parity_ref)


def test_sos_residuals_names_omega_g_of_other_runs_and_broadcasts_shared_ones():
    with pytest.raises(ValueError, match=r"^omega_g must have leading axes \(\.\.\.\) that broadcast"):
        att.sos_residuals(np.ones((2, 3)), np.zeros((3, 4)), np.zeros(3), 0.0)
    r = att.sos_residuals(np.ones(3), np.zeros((2, 4)), np.zeros(3), 0.0)
    assert r.tolist() == [[1.0, 1.0, 1.0, 0.0]] * 2
