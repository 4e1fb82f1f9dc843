"""The four schematics show the model's own numbers (xnavlab.mars.navigation.schematics)."""

import inspect
import math

import numpy as np
import pytest
from matplotlib.figure import Figure
from scipy.stats import chi2

from xnavlab.core import ephemeris
from xnavlab.core.constants import R_MARS
from xnavlab.mars.faults import fault_tolerance
from xnavlab.mars.models import dynamics, sensors, stars
from xnavlab.mars.navigation import scenarios, schematics
from xnavlab.mars.timing import pulsars, toa


def text_of(fig):
    return " ".join(schematics.figure_texts(fig))


def test_xnav_geometry_writes_the_three_delay_terms_of_the_model():
    fig = schematics.plot_xnav_geometry("B1937+21")
    assert isinstance(fig, Figure)
    p = pulsars.get("B1937+21")
    R = ephemeris.position("mars", dynamics.MARS_T0) + dynamics.MARS_STATE0[:3]
    terms = toa.terms(R, p.direction[None], np.array([p.distance]),
                      ephemeris.position("sun", dynamics.MARS_T0))
    text = text_of(fig)
    assert f"= {terms['roemer'][0]:.1f} s" in text
    assert f"= {terms['parallax'][0] * 1e6:.2f} µs" in text
    assert f"= {terms['shapiro'][0] * 1e6:.1f} µs" in text
    ax = fig.axes[0]
    assert "(au)" in ax.get_xlabel() and "(au)" in ax.get_ylabel()


def test_xnav_geometry_draws_the_spacecraft_at_its_roemer_coordinate():
    """The horizontal axis is along n: the spacecraft's x is n . R in au."""
    fig = schematics.plot_xnav_geometry("B1937+21")
    p = pulsars.get("B1937+21")
    R = ephemeris.position("mars", dynamics.MARS_T0) + dynamics.MARS_STATE0[:3]
    mars_dot = [ln for ln in fig.axes[0].lines if ln.get_marker() == "o"][0]
    assert mars_dot.get_xdata()[0] == pytest.approx(p.direction @ R / 1.495978707e11, abs=1e-3)


def test_optical_geometry_angles_are_the_sensor_models():
    fig = schematics.plot_optical_geometry()
    star = stars.pick_three(t=dynamics.MARS_T0)[0]
    z = sensors.cns_h(dynamics.MARS_STATE0, stars.direction(star, dynamics.MARS_T0)[None])[0]
    rho = math.degrees(math.asin(R_MARS / np.linalg.norm(dynamics.MARS_STATE0[:3])))
    text = text_of(fig)
    assert f"= {math.degrees(z):.1f}°" in text
    assert f"= {rho:.1f}°" in text
    assert star in text
    assert fig.axes[0].get_xlabel() == "$10^3$ km"


def test_optical_geometry_takes_another_star():
    assert "Sirius" in text_of(schematics.plot_optical_geometry("Sirius"))


def test_federated_filter_shows_the_scenario_shares_and_mode():
    text = text_of(schematics.plot_federated_filter())
    assert text.count("= 0.333") == 3 and "reset mode" in text and "every 500 s" in text
    sc = scenarios.MarsScenario(beta=(0.5, 0.25, 0.25), mode="no-reset")
    text = text_of(schematics.plot_federated_filter(sc))
    assert "= 0.5" in text and text.count("= 0.25") == 2
    assert "no-reset mode" in text and "restarts" not in text


def test_the_rejoining_windows_are_run_fault_tolerant_defaults():
    """The drawing's windows are the run's defaults (since review 35j the run takes them from
    :func:`xnavlab.mars.faults._checks.readmit_windows`, no longer a ``win = {...}`` literal)."""
    from xnavlab.mars.faults import _checks

    assert "_checks.readmit_windows(" in inspect.getsource(fault_tolerance.run_fault_tolerant)
    assert schematics.READMIT_WINDOWS == _checks.readmit_windows(None, "chi2", scenarios.SUBSYSTEMS)


def test_isolate_rejoin_writes_window_and_threshold_of_each_subsystem():
    text = text_of(schematics.plot_isolate_rejoin("cns"))
    alpha = inspect.signature(fault_tolerance.run_fault_tolerant).parameters["readmit_alpha"].default
    for name, m in (("XNAV", 4), ("UV", 3), ("CNS", 3)):
        w = schematics.READMIT_WINDOWS[name.lower()]
        assert f"{name}: W = {w}, m = {m}, threshold {chi2.isf(alpha, w * m):.1f}" in text
    assert "(CNS: W = 100, m = 3)" in text and "time update only" in text


def test_isolate_rejoin_rejects_an_unknown_subsystem():
    with pytest.raises(ValueError, match="subsystem"):
        schematics.plot_isolate_rejoin("gps")
