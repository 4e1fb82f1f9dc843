"""Process noise from the model difference: the unmodelled acceleration, its size and time
scale, q = sigma_a^2 T, and the studies' fields."""

import math

import numpy as np
import pytest

from xnavlab.mars.models import dynamics
from xnavlab.mars.models import force_models as fm
from xnavlab.mars.models import model_noise as mn
from xnavlab.mars.navigation.scenarios import MarsScenario


def test_the_unmodelled_acceleration_and_the_derived_q():
    t = dynamics.MARS_T0 + np.arange(0.0, 3601.0, 60.0)
    x = fm.truth(t, force_model="study")
    da = mn.unmodelled_acceleration(t, x, "study", "paper")
    assert 1e-3 < np.sqrt(np.mean(np.sum(da**2, axis=1))) < 1e-2  # J2 dominates: mm/s^2
    assert not mn.unmodelled_acceleration(t, x, "paper", "paper").any()
    srp_only = fm.ForceModel(srp=True)
    d2 = mn.unmodelled_acceleration(t, x, srp_only, "paper")
    assert 0.0 < np.linalg.norm(d2, axis=1).max() < 1e-7
    q = mn.derived_q_acc(days=0.1, dt=60.0)
    st_ = mn.unmodelled_statistics(days=0.1, dt=60.0)
    assert q == pytest.approx(st_["sigma_axis_mps2"] ** 2 * st_["correlation_time_s"])
    assert 0.0 < st_["correlation_time_s"] < 3 * 3600  # under an orbit and a half
    assert mn.derived_q_acc(horizon=3.0, days=0.1, dt=60.0) == pytest.approx(
        st_["sigma_axis_mps2"] ** 2 * 3.0)
    with pytest.raises(ValueError, match="beyond the filter's range"):
        mn.derived_q_acc(horizon=1e6, days=0.1, dt=60.0)
    with pytest.raises(ValueError, match="horizon"):
        mn.derived_q_acc(horizon="orbit", days=0.1, dt=60.0)


def test_shapes_are_checked():
    with pytest.raises(ValueError, match="states must have shape"):
        mn.unmodelled_acceleration([dynamics.MARS_T0], np.zeros((1, 4)))


def test_study_fields_fill_only_what_is_not_given():
    f = mn.study_fields(lambda kw: MarsScenario(**kw), {"days": 1.0})
    assert f["truth_model"] == fm.STUDY and f["filter_model"] == fm.PAPER
    assert f["q_acc"] == pytest.approx(mn.derived_q_acc(), rel=1e-12)
    g = mn.study_fields(lambda kw: MarsScenario(**kw), {"truth_model": "paper"})
    assert g["q_acc"] == 0.0
    sc = MarsScenario.study(days=1.0)
    assert not sc.paper_setup and sc.q_acc == f["q_acc"]


def test_an_edge_value_is_refused_under_its_own_name():
    """Issue 35 (review 35h): a bool model was refused as 'force model', a scalar ``t`` as
    ``states``, and ``study_fields`` took any ``make`` and failed on ``fields``' type."""
    t = dynamics.MARS_T0 + np.array([0.0, 600.0])
    x = dynamics.truth(t, cache=False)
    with pytest.raises(ValueError, match=r"^t must be a 1-D array of at least one epoch, got shape \(\)"):
        mn.unmodelled_acceleration(-0.0, x, "paper", "paper")
    with pytest.raises(ValueError, match=r"^truth_model must be one of 'paper', 'study'"):
        mn.unmodelled_acceleration(t, x, True, "paper")
    with pytest.raises(ValueError, match=r"^filter_model must be one of 'paper', 'study'"):
        mn.unmodelled_statistics("paper", True, days=0.05)
    with pytest.raises(ValueError, match=r"^truth_model must be one of"):
        mn.derived_q_acc(True, "paper", days=0.05)
    with pytest.raises(ValueError, match=r"^make must be a function make\(fields\) -> MarsScenario"):
        mn.study_fields(True, {"q_acc": 1e-6})
    with pytest.raises(ValueError, match=r"^fields must be a dict of MarsScenario fields, got list \[\]"):
        mn.study_fields(lambda kw: MarsScenario(**kw), [])


def test_a_step_longer_than_the_span_or_a_misspelt_orbit_setting_is_refused():
    """Review 35j (1) 21: dt > days gave one sample and 0/0 (a RuntimeWarning); a typo in
    derived_q_acc's **orbit raised unmodelled_statistics' TypeError."""
    with pytest.raises(ValueError, match=r"^days must span at least one sampling step dt = 3600 s "
                                         r"\(two samples or more for a correlation time\), got "
                                         r"0.01 \(864 s\)$"):
        mn.unmodelled_statistics(days=0.01, dt=3600.0)
    with pytest.raises(ValueError, match=r"^derived_q_acc got sttae0=1: not an orbit setting "
                                         r"\(they are state0, t0, truth_ephem, filter_ephem, dt\)$"):
        mn.derived_q_acc("paper", "paper", days=0.05, sttae0=1)
    assert mn.unmodelled_statistics("paper", "paper", days=0.01, dt=864.0)["rms_mps2"] == 0.0


def test_the_orbit_settings_are_refused_under_the_users_names():
    """Review 35k (1) 17, (3) 2: t0=None was a TypeError and '1.0' a UFuncTypeError; t0=nan
    was refused as 't_eval', 1e300 as 't_start', and truth_ephem='' as 'ephem'."""
    for bad in (None, "1.0", math.nan, 1e300, True):
        with pytest.raises(ValueError, match=r"^t0 must be an epoch in \[-3158136000 \(1899-12-04"
                                             r"T00:00:00 TDB\), 6314\d+ \(2200-01-31T\S+ TDB\)\] "
                                             r"s TDB past J2000, got "):
            mn.unmodelled_statistics("paper", "paper", days=0.05, t0=bad)
    for name in ("truth_ephem", "filter_ephem"):
        with pytest.raises(ValueError, match=rf"^{name} must be one of 'de421', 'de405', got ''$"):
            mn.unmodelled_statistics("paper", "paper", days=0.05, **{name: ""})
        t = dynamics.MARS_T0 + np.array([0.0, 600.0])
        with pytest.raises(ValueError, match=rf"^{name} must be one of 'de421', 'de405', got 3$"):
            mn.unmodelled_acceleration(t, np.tile(dynamics.MARS_STATE0, (2, 1)), "paper", "paper",
                                       **{name: 3})
