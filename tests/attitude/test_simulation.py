"""The attitude simulation (xnavlab.attitude.simulation): configuration checks and fault-free runs."""

import math

import numpy as np
import pytest

from xnavlab import attitude as att
from xnavlab.core.faults import Fault

DPH = att.DEG_PER_H


@pytest.fixture(scope="module")
def nominal():
    return att.simulate()


@pytest.mark.parametrize(
    ("changes", "name"),
    [
        ({"n_sigma": 0.0}, "n_sigma"),
        ({"dt": -0.1}, "dt"),
        ({"t_cal": (40.0, 20.0)}, "t_cal"),
        ({"t_cal": (20.0, 200.0)}, "t_cal"),
        ({"qdiff_window_s": 45.0}, "qdiff_window_s"),
        ({"persist": 0}, "persist"),
        ({"dos": 1}, "dos"),
        ({"drifts_deg_per_h": (1.0, 2.0)}, "drifts_deg_per_h"),
        ({"skew_axis": (1.0, 0.0, 0.0)}, "skew_axis"),
        ({"star_noise_deg": 0.0}, "star_noise_deg"),
        ({"duration": 0.1}, "duration"),
    ],
)
def test_config_validation(changes, name):
    with pytest.raises(ValueError, match=f"^{name}"):
        att.SimConfig(**changes)


def test_simulate_fault_free(nominal):
    run = nominal
    assert run.truth == "none" and run.onset == math.inf
    assert (run.sos.verdict, run.dos.verdict, run.qd.verdict) == ("none", "none", "none")
    assert run.t.shape == (1001,) and run.sos_r.shape == (1001, 4)
    assert np.all(run.sos_r[run.armed] < run.sos_J)
    assert np.degrees(np.abs(run.att_err[200:]).max()) < 0.005
    np.testing.assert_allclose(run.refs["drift"] / DPH, att.PAPER_DRIFTS_DEG_PER_H[:3], atol=3)
    assert set(run.refs) == {"drift", "parity", "qdiff", "dos"}


def test_simulate_arguments():
    with pytest.raises(ValueError, match="unknown SimConfig setting"):
        att.simulate(colour="red")
    with pytest.raises(ValueError, match="^faults"):
        att.simulate(["gyro_x"])
    with pytest.raises(ValueError, match="^config"):
        att.simulate(config={"dt": 0.1})
    run = att.simulate(Fault("gyro", "noise", 1e-3, 45.0), duration=60.0, dos=False)
    assert run.truth == "unknown" and run.dos is None
