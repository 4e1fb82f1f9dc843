"""Review 35p: an edited Diagnosis drawn (P4), angles without bounds (P5), a flight of a million
samples (P9), and the same classes nearby (Identification, Chi2Monitor, compare_detectors,
kf_identify's shapes)."""

import dataclasses
import math

import matplotlib
import numpy as np
import pytest

from xnavlab.core.faults import Fault
from xnavlab.plins import ins
from xnavlab.plins import parity as P
from xnavlab.plins import pseudolites as pl
from xnavlab.plins.parity import diagnosis, identification

matplotlib.use("Agg")


@pytest.fixture(scope="module")
def diag():
    return P.diagnose_flight([Fault("pseudorange", "step", 300.0, 20.0, component=0)], duration=40.0,
                             with_chi2=True)


@pytest.mark.parametrize("edit, words", [
    (dict(threshold="14"), r"^Diagnosis\.threshold must be a real number in \(0, inf\), got '14'$"),
    (dict(threshold=math.nan), r"^Diagnosis\.threshold must be a real number in \(0, inf\), got nan$"),
    (dict(threshold=-5.0), r"^Diagnosis\.threshold must be a real number in \(0, inf\), got -5\.0$"),
    (dict(statistic=np.zeros((5, 4))), r"^Diagnosis\.statistic must have shape \(30, 4\) \(n - s windows"),
    (dict(statistic=np.full((30, 4), np.nan)), r"^Diagnosis\.statistic must contain only finite numbers"),
    (dict(statistic=np.full((30, 4), -1.0)), r"^Diagnosis\.statistic must hold norms \(at least 0\)"),
    (dict(t_res=np.arange(30.0)), r"^Diagnosis\.t_res must be the window ends t\[s:\] \(s = 11\)$"),
    (dict(detection=[None]), r"^Diagnosis\.detection must be a list of one entry per pseudolite \(m = 4\)"),
    (dict(identification={0: 3}), r"^Diagnosis\.identification must map pseudolite indices in \[0, 3\]"),
    (dict(chi2="no"), r"^Diagnosis\.chi2 must be a Chi2Monitor or None, got 'no'$"),
])
def test_p4_an_edited_diagnosis_is_checked_again(diag, edit, words):
    with pytest.raises(ValueError, match=words):
        P.plot_diagnosis(dataclasses.replace(diag, **edit))


def test_p4_diagnosis_is_frozen_and_its_parts_checked(diag):
    with pytest.raises(dataclasses.FrozenInstanceError):
        diag.threshold = 1.0
    idn = diag.identification[0]
    with pytest.raises(ValueError, match=r"^Identification\.theta must have shape \(\d+, 1\) \(K = len\(t\) "
                                         r"windows, p = 1 parameters\), got shape \(3, 1\)$"):
        dataclasses.replace(idn, theta=idn.theta[:3])
    with pytest.raises(ValueError, match=r"^Identification\.names must be \('f',\) \(the parameters of model "
                                         r"'step'\), got \('a', 'b'\)$"):
        dataclasses.replace(idn, names=("a", "b"))
    with pytest.raises(ValueError, match=r"^Chi2Monitor\.threshold must be a real number in \(0, inf\)"):
        dataclasses.replace(diag.chi2, threshold=-1.0)
    with pytest.raises(ValueError, match=r"^Chi2Monitor\.statistic must have shape \(41,\) \(n = len\(t\)\)"):
        dataclasses.replace(diag.chi2, statistic=diag.chi2.statistic[:3])
    fig = P.plot_diagnosis(dataclasses.replace(diag, threshold=20.0))   # a valid edit is drawn
    assert fig.axes[0].lines[-1].get_ydata()[0] == 20.0
    matplotlib.pyplot.close(fig)


@pytest.mark.parametrize("call, words", [
    (lambda: pl.geodetic_to_ecef(0.5, 116.0, 0.0),
     r"^lon must be a longitude in radians in \[-6\.28319, 6\.28319\], got 116\.0 "
     r"\(degrees\? use np\.radians\)$"),
    (lambda: pl.geodetic_to_ecef(0.5, 1e300, 0.0),
     r"^lon must be a longitude in radians in \[-6\.28319, 6\.28319\], got 1e\+300$"),
    (lambda: pl.geodetic_to_ecef([0.5, 39.0], 2.0, 0.0),
     r"^lat must hold latitudes in radians in \[-1\.5708, 1\.5708\], got lat\[1\] = 39\.0 \(degrees\?"),
    (lambda: pl.enu_matrix(0.5, 1e20), r"^lon must be a longitude in radians in \[-6\.28319, 6\.28319\]"),
    (lambda: pl.geodetic_jacobian(0.5, 116.0, 0.0), r"^lon must be a longitude in radians"),
    (lambda: pl.pdop(0.68, 116.0, 1e4, pl.sites_ecef()), r"^lon must be a longitude in radians"),
    (lambda: ins.nav_rates(0.7, 116.0, 0.0, [0, 0, 0], [0, 0, 9.8]),
     r"^lon must be a longitude in radians"),
    (lambda: ins.normal_gravity(39.0, 0.0),
     r"^lat must be a latitude in radians in \[-1\.5708, 1\.5708\], got 39\.0"),
    (lambda: ins.Trajectory([0., 1.], [39., 39.], [2., 2.], [0., 0.], np.zeros((2, 3)), np.zeros((2, 3))),
     r"^lat must hold latitudes in radians in \[-1\.5708, 1\.5708\], got lat\[0\] = 39\.0 "
     r"\(degrees\? use np\.radians\)$"),
    (lambda: ins.Trajectory([0., 1.], [0.7, 0.7], [116., 116.], [0., 0.], np.zeros((2, 3)),
                            np.zeros((2, 3))),
     r"^lon must hold longitudes in radians in \[-6\.28319, 6\.28319\], got lon\[0\] = 116\.0"),
    (lambda: pl.sites_ecef([[39.0, 1e300, 0.0]]),
     r"^sites_deg longitudes must be in \[-360, 360\] deg, got sites_deg\[0, 1\] = 1e\+300$"),
])
def test_p5_angles_are_bounded_in_radians(call, words):
    with pytest.raises(ValueError, match=words):
        call()


def test_p5_angles_in_range_are_used():
    assert pl.geodetic_to_ecef(0.5, 2 * math.pi, 0.0).shape == (3,)
    assert pl.enu_matrix(-math.pi / 2, -2 * math.pi).shape == (3, 3)
    tr = ins.paper_trajectory(duration=5.0, lon0_deg=360.0)   # the largest longitude it takes
    assert tr.lon[0] == pytest.approx(2 * math.pi)


def test_p9_a_flight_of_too_many_samples_is_refused_up_front():
    with pytest.raises(ValueError, match=r"^duration must give at most 50000 samples \(duration / dt \+ 1; "
                                         r"about 5 min at the measured 6 ms a sample\), got "
                                         r"duration = 1000 s at dt = 0\.001 s: 1000001 samples "
                                         r"\(about 100 min\); at this dt, duration <= 49\.999 s$"):
        P.diagnose_flight(dt=1e-3, duration=1e3)
    with pytest.raises(ValueError, match=r"^duration must give at most 50000 samples .* dt = 0\.01 s"):
        P.diagnose_flight(dt=0.01, duration=1e4)
    with pytest.raises(ValueError, match=r"^n_runs must keep compare_detectors within about 10 min: 2 sizes "
                                         r"x 1000 runs of 10001 samples \(duration = 10000 s at dt = 1 s\)"):
        P.compare_detectors("step", [10.0, 20.0], n_runs=1000, duration=1e4)
    with pytest.raises(ValueError, match=r"^duration must give at most 50000 samples"):
        P.compare_detectors("step", [10.0], n_runs=1, dt=0.01, duration=1e3)
    assert diagnosis.MAX_SAMPLES * diagnosis.DESIGN_S_PER_SAMPLE <= diagnosis.MAX_SECONDS


def test_kf_identify_names_matrices_of_the_wrong_shape():
    r, G = np.zeros((5, 2)), np.zeros((5, 2, 1))
    with pytest.raises(ValueError,
                       match=r"^theta0 must have shape \(1,\) \(p = columns of G\), got shape \(3, 1\)$"):
        identification.kf_identify(r, G, np.eye(2), 1.0, theta0=np.zeros((3, 1)))
    with pytest.raises(ValueError,
                       match=r"^R must have shape \(2, 2\) \(q = columns of r\), got shape \(1, 2, 2\)$"):
        identification.kf_identify(r, G, np.eye(2)[None], 1.0)
    with pytest.raises(ValueError, match=r"^Q must have shape \(1, 1\) \(p = columns of G\)"):
        identification.kf_identify(r, G, np.eye(2), np.ones((1, 1, 1)))
