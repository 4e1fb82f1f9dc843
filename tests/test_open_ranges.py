"""Every range open at the top is open for a reason (issue 35: numeric ranges with their real range).

A ``check_real``/``check_int`` call with a lower end and no upper end says to the user that
any larger value is used. :data:`OPEN` lists every such call in the package (module and the
name the call reports), each with the reason that is true: the value enters a formula that
stays finite and meaningful for every finite input, or another check bounds it under the same
name. A new one-sided range fails :func:`test_every_open_range_has_a_reason` until it gets an
upper end or a reason here; :func:`test_the_register_has_no_stale_entry` keeps the list honest.

:data:`UPPER_ENDS` holds the upper ends the audit of the one-sided ranges added (each was
found taking 1e308 or 10**30 into an overflow, a traceback, an error naming another
parameter, or a result no one can use), each refused under the user's own name.
"""

import ast
import functools
import math
import re
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]

#: "module:label" (the label as the call writes it) -> why no upper end is needed.
OPEN = {
    # times and windows: a larger value only moves the event past the data (the answer then
    # is "no event", which the result says)
    "xnavlab.attitude.motion:\"wobble_period\"": "the wobble's period: sin(2 pi t / T) -> 0 as T grows",
    "xnavlab.attitude.simulation:\"wobble_period\"": "SimConfig's copy of truth_rate's "
                                                  "wobble_period: sin(2 pi t / T) -> 0 as T grows",
    "xnavlab.attitude.montecarlo:\"onset\"": "with the caller's config the next check bounds it "
                                           "to [t_cal[1], duration), naming onset",
    "xnavlab.mars.navigation.plots:\"settle_days\"": "the next check bounds it by every case's "
                                                  "last record time, naming settle_days",
    "xnavlab.mars.navigation.unused_inputs:\"settle_days\"": "a run note's text: printed only",
    "xnavlab.mars.navigation.unused_inputs:\"record_dt\"": "a run note's text: printed only",
    "xnavlab.mars.navigation.unused_inputs:\"n\"": "a count of records: compared with 2 only",
    "xnavlab.mars.navigation.unused_inputs:f\"counts[{s!r}]\"": "a count of measurements: "
                                                              "compared with 0 only",
    "xnavlab.mars.studies.trials:\"rate_per_day\"": "the next check bounds it by the day's "
                                                   "samples over the window's, naming rate_per_day "
                                                   "(a window of no sample: 0 whatever the rate)",
    "xnavlab.attitude.simulation:\"qdiff_window_s\"": "bounded by t_cal in the next check",
    "xnavlab.attitude.sensors:\"onset\"": "a fault is made before its run: the run refuses an "
                                         "onset at or past its end, naming faults[i]",
    "xnavlab.core.detection.plots:\"period_s\"": "the orbit's period in a cosine: any T > 0 is finite",
    "xnavlab.core.detection.singularity:\"dt\"": "a scale factor of the wavelet's time axis",
    "xnavlab.mars.faults.schedules:f\"dt[{sensor!r}]\"": "open at both ends: a sensor's sampling interval",
    "xnavlab.mars.studies.trials:\"window_s\"": "a probability's window: the result stays in [0, 1]",
    "xnavlab.mars.timing.fold_toa:\"duration\"": "a tag's offset inside the span: arithmetic only",
    "xnavlab.mars.models.optics:\"dt\"": "exp(-dt / tau) -> 0: every positive spacing is meaningful",
    "xnavlab.mars.models.time_update:\"dt\"": "dt / max_step <= 1e6 sub-steps is checked next",
    "xnavlab.mars.navigation.plots:\"bin_days\"": "a bin wider than the run is one bin",
    "xnavlab.robust.comparison:\"t_from\"": "a window over the run; an empty one is refused",
    "xnavlab.robust.comparison:\"t_to\"": "a window over the run; an empty one is refused",
    "xnavlab.robust.ephemeris_error:\"period\"": "the slow error's period in a sine",
    "xnavlab.core.quaternions:\"dt\"": "the angle |w| dt is bounded by MAX_ANGLE in the same call",
    "xnavlab.mars.navigation._run_checks:\"MarsRun.wall_time\"": "a measured run time: reported only",
    "xnavlab.mars.faults._checks:\"FaultTolerantRun.wall_time\"": "a measured run time: "
                                                                   "reported only",
    # indices and counts that are clipped by slice semantics or counted, not allocated
    "xnavlab.core.detection.batch:\"stop\"": "slice semantics: a stop past the data computes "
                                             "to its end (documented in advance)",
    "xnavlab.core.detection.batch:\"lo\"": "slice semantics over the samples computed",
    "xnavlab.core.detection.batch:\"hi\"": "slice semantics over the samples computed",
    "xnavlab.core.detection.combined:\"max_rows\"": "at most the ring's rows are copied",
    "xnavlab.core.detection.combined:\"holdoff\"": "bounded to 1e9 by EventTracker under the same name",
    "xnavlab.core.detection.limits:\"n\"": "window_false_alarm: F n / N, clipped to a probability",
    "xnavlab.core.detection.mallat:\"n\"": "log2 of a length: no allocation",
    "xnavlab.core.detection.online:\"n_tests\"": "a probability's exponent: stays in [0, 1]",
    "xnavlab.core.montecarlo:\"n\"": "a count in the Wilson interval: stays in [0, 1]",
    "xnavlab.core.faults:\"component\"": "checked against the sensor's components by check_faults",
    # statistics: thresholds, degrees of freedom, multipliers
    "xnavlab.core.detection.chisquare:\"dof\"": "chi-square quantile: finite for every dof",
    "xnavlab.core.filters:n": "a statistic against its band: a comparison only",
    "xnavlab.mars.navigation.plots:n": "the band's ends: a comparison and a line drawn",
    "xnavlab.core.detection.online:\"k\"": "a threshold multiplier: the probability -> 0",
    "xnavlab.core.detection.singularity:\"threshold\"": "a comparison: a high one finds no maxima",
    "xnavlab.core.detection.limits:\"rate_per_day\"": "F n / N, clipped to a probability",
    "xnavlab.core.detection.limits:\"samples_per_day\"": "F n / N, clipped to a probability",
    "xnavlab.core.detection.plots:\"scale\"": "the axis unit's divisor (1000 for km)",
    "xnavlab.core.federated:\"gate\"": "a NIS gate: inf (the default) means no gate",
    "xnavlab.plins.parity.diagnosis:\"threshold\"": "a comparison: a high one raises no alarm",
    "xnavlab.plins.parity.plots:\"threshold_m\"": "a comparison: a high one raises no alarm",
    "xnavlab.plins.parity.diagnosis:\"tol\"": "a null-space tolerance: a large one leaves no "
                                             "parity space, which is refused",
    "xnavlab.plins.parity.space:\"tol\"": "a singular-value tolerance: a comparison only",
    "xnavlab.plins.parity.identification:\"R\"": "a scalar noise variance: the gain -> 0, finite",
    "xnavlab.plins.parity.identification:\"Q\"": "a scalar random-walk variance: finite",
    "xnavlab.plins.parity.fuzzy:\"center\"": "ordered after left: a membership in [0, 1]",
    "xnavlab.plins.parity.fuzzy:\"right\"": "ordered after center: a membership in [0, 1]",
    "xnavlab.robust.comparison:lab": "an RMSE in a table",
    "xnavlab.robust.coverage:\"k\"": "a k-sigma multiplier: the coverage stays in [0, 1]",
    "xnavlab.reproduce:\"elapsed_s\"": "seconds stated under the headline: text only",
    "xnavlab.verdicts:name": "a row's tolerance (rel, tol, slack): its size is the claim's own; "
                             "finite is checked, an infinite one could not fail",
}


@functools.cache
def _open_calls():
    """"module:label" of every check_real/check_int call with a lower end and no upper end."""
    found = []
    for path in sorted((ROOT / "xnavlab").rglob("*.py")):
        src = path.read_text()
        module = ".".join(path.relative_to(ROOT).with_suffix("").parts)
        for node in ast.walk(ast.parse(src)):
            if not (isinstance(node, ast.Call) and node.args):
                continue
            f = node.func
            name = f.id if isinstance(f, ast.Name) else getattr(f, "attr", None)
            if name not in ("check_real", "check_int"):
                continue
            keys = {k.arg for k in node.keywords}
            starred = any(isinstance(a, ast.Starred) for a in node.args)
            lo = len(node.args) >= 3 or "lo" in keys
            hi = len(node.args) >= 4 or "hi" in keys or starred
            if lo and not hi:
                found.append(f"{module}:{ast.get_source_segment(src, node.args[0])}")
    return tuple(found)


def test_every_open_range_has_a_reason():
    missing = sorted(set(_open_calls()) - {k for k, why in OPEN.items() if why})
    assert not missing, f"one-sided ranges without an upper end or a reason in OPEN: {missing}"


def test_the_register_has_no_stale_entry():
    stale = sorted({k for k, why in OPEN.items() if why} - set(_open_calls()))
    assert not stale, f"OPEN lists ranges the package no longer has: {stale}"


def _mars():
    from xnavlab.mars.models import dynamics, optics, sensors, stars, time_update

    r = np.array([4e6, 0.0, 0.0])
    return [
        (lambda: dynamics.point_mass(r, gm=1e308), "gm"),
        (lambda: dynamics.gravity_gradient(r, gm=1e308), "gm"),
        (lambda: dynamics.orbital_elements(np.array([4e6, 0, 0, 0, 3e3, 0]), gm=1e308), "gm"),
        (lambda: dynamics.j2_acceleration(r, j2=1e308), "j2"),
        (lambda: dynamics.j2_acceleration(r, radius=1e308), "radius"),
        (lambda: dynamics.point_mass(np.array([1e200, 0.0, 0.0])), "r"),
        (lambda: dynamics.gravity_gradient(np.array([1e-59, 0.0, 0.0])), "r"),
        (lambda: dynamics.ThirdBodyTable(dynamics.MARS_T0, 1e308), "t_end"),
        (lambda: optics.apparent_radius(np.array([4e6]), radius=1e308), "radius"),
        (lambda: optics.range_from_radius(0.5, radius=1e308), "radius"),
        (lambda: optics.limb_fit(r, a=1e308), "a"),
        (lambda: optics.limb_fit(r, c=1e308), "c"),
        (lambda: optics.limb_bias(r, r_fit=1e308), "r_fit"),
        (lambda: optics.sigma_alpha_for(1e308), "sigma_range_m"),
        (lambda: optics.UVInstrument(1e308, 1e-3), "sigma_range"),
        (lambda: optics.UVInstrument(5e3, 1e308), "sigma_dir"),
        (lambda: sensors.UVSensor(sigma_range=1e308), "sigma_range"),
        (lambda: stars.starlight_geometry(np.array([1e10, 0, 0]), ("Polaris",), radius=1e308), "radius"),
        (lambda: time_update.Propagation(dynamics.MARS_T0, 1e308, None, 10.0), "dt / max_step"),
        (lambda: time_update.Propagation(dynamics.MARS_T0, 10.0, None, 1e308), "max_step"),
    ]


def _mars_runs():
    from xnavlab.mars.faults import fault_tolerance as ft
    from xnavlab.mars.faults import schedules
    from xnavlab.mars.navigation import scenarios
    from xnavlab.mars.timing import photon_plots, timing_bound

    sc = scenarios.MarsScenario(days=0.05)
    return [
        (lambda: ft.run_fault_tolerant(sc, check_every=10**30), "check_every"),
        (lambda: ft.run_fault_tolerant(sc, xnav_holdoff=10**30), "xnav_holdoff"),
        (lambda: ft.run_fault_tolerant(sc, readmit_samples={"uv": 10**30}), "readmit_samples['uv']"),
        (lambda: ft.run_fault_tolerant(sc, arm_s=1e308), "arm_s"),
        (lambda: schedules.check_schedule((), sc, train_days=1e308), "train_days"),
        (lambda: scenarios.default_settle_days(1e308), "days"),
        (lambda: photon_plots.plot_ambiguity(np.ones(2), np.ones(2), 1e308), "cycle_m"),
        (lambda: timing_bound.expected_fold(32, 0.1, 1e308, 1.0), "pulsed"),
        (lambda: timing_bound.expected_fold(32, 0.1, 1.0, 1e308), "unpulsed"),
    ]


def _core():
    from xnavlab.core import montecarlo
    from xnavlab.core.detection import chisquare, combined, limits
    from xnavlab.core.detection import plots as dplots
    from xnavlab.reproductions import ch07_wavelets

    design = combined.CombinedDesign(172.8, 3)
    return [
        (lambda: chisquare.Chi2Detector(3, window=10**30), "window"),
        (lambda: chisquare.Chi2Detector(10**30), "m"),
        (lambda: chisquare.chi2_statistic(np.ones((2, 1)), np.eye(1), window=10**30), "window"),
        (lambda: limits.noise_pd_limit([3.0], 10**30, 0.01), "n"),
        (lambda: combined.InnovationMonitor(design, prior_samples=10**30), "prior_samples"),
        (lambda: combined.InnovationMonitor(design, scale_samples=10**30), "scale_samples"),
        (lambda: combined.InnovationMonitor(design, scale_every=10**30), "scale_every"),
        (lambda: dplots.plot_step_detector(mean_m=1e308), "mean_m"),
        (lambda: dplots.plot_step_detector(swing_m=1e308), "swing_m"),
        (lambda: montecarlo.detection_table(("step",), (1e308,), trials=1), "sizes[0]"),
        (lambda: ch07_wavelets.mallat_vs_pywavelets(n=10**30), "n"),
    ]


def _others():
    from xnavlab.attitude import diagnosis, montecarlo
    from xnavlab.attitude import plots as aplots
    from xnavlab.plins import pseudolites
    from xnavlab.plins.parity import diagnosis as pdiag
    from xnavlab.plins.parity import plots as pplots
    from xnavlab.robust import ephemeris_error, filters
    from xnavlab.robust import plots as rplots

    t = np.arange(10.0)
    return [
        (lambda: montecarlo.isolation_monte_carlo(1, locations=("gyro_x",), kinds=("step",),
                                                  sizes=(1e308,)), "sizes[0]"),
        (lambda: montecarlo.isolation_monte_carlo(1, locations=("gyro_x",), kinds=("step",),
                                                  sizes=(1.0,), onset=1e308), "onset"),
        (lambda: aplots.plot_fault_case(size=1e308), "size"),
        (lambda: diagnosis.diagnose(t, np.zeros((10, 4)), np.ones(4), confirm_s=1e308), "confirm_s"),
        (lambda: pdiag.diagnose_flight(sigma=1e308), "sigma"),
        (lambda: pdiag.diagnose_flight(leak_tol=1e308), "leak_tol"),
        (lambda: pdiag.compare_detectors("step", [10.0], sensor=10**30, n_runs=1), "sensor"),
        (lambda: pplots.plot_step_diagnosis(step_m=1e308), "step_m"),
        (lambda: pplots.plot_step_diagnosis(step_m=0.0), "step_m"),
        (lambda: pplots.plot_step_diagnosis(onset_s=1e308), "onset_s"),
        (lambda: pseudolites.geodetic_jacobian(0.0, 0.0, 1e308), "h"),
        (lambda: ephemeris_error.injected_error(t, 1e308), "size"),
        (lambda: ephemeris_error.injected_error(t, 1.0, "growing", growth_time=1e-300), "growth_time"),
        (lambda: ephemeris_error.elements_to_state(1e308, 0.1, 0, 0, 0, 0, 3.98e14), "a"),
        (lambda: ephemeris_error.elements_to_state(7e6, 0.1, 0, 0, 0, 0, 1e308), "gm"),
        (lambda: filters.rkf_gain(np.eye(1), np.eye(1), np.eye(1), np.zeros((1, 1)), 1e308), "eps"),
        (lambda: filters.rkf_gain(np.eye(1), np.eye(1), np.eye(1), np.zeros((1, 1)), 1e-300), "eps"),
        (lambda: rplots.filter_comparison(100.0, 1e308, "all four"), "eps"),
        (lambda: rplots.filter_comparison(1e308, 100.0, "all four"), "size"),
    ]


def _cases():
    return [pytest.param(i, group, id=f"{group}-{i}")
            for group, n in (("mars", 20), ("mars_runs", 9), ("core", 11), ("others", 19))
            for i in range(n)]


GROUPS = {"mars": _mars, "mars_runs": _mars_runs, "core": _core, "others": _others}


def test_the_case_counts_match():
    assert {g: len(f()) for g, f in GROUPS.items()} == {"mars": 20, "mars_runs": 9, "core": 11,
                                                         "others": 19}


@pytest.mark.parametrize(("i", "group"), _cases())
def test_an_upper_end_is_refused_by_its_own_name(i, group):
    call, name = GROUPS[group]()[i]
    with pytest.raises(ValueError, match=rf"^{re.escape(name)} must"):
        call()


@pytest.mark.parametrize("eps", [1e-6, 1e5])
def test_an_rkf_run_that_float64_cannot_carry_stops_naming_eps(eps):
    """Inside EPS_RANGE a run can still lose P's definiteness (small eps) or the solve's
    precision (large eps with a 1e8 m error); it stops naming eps, not P or a LinAlgError."""
    from xnavlab.robust import filters

    sc = filters.simulate("mars", n_steps=500, error="growing", size=1e8, rng=0)  # chapter 10's length
    with pytest.raises(ValueError, match=rf"^eps = {eps:g}"):
        filters.run_filter("rkf", sc, rng=1, eps=eps)


def test_the_paper_eps_still_runs_at_the_largest_error():
    from xnavlab.robust import filters

    sc = filters.simulate("mars", n_steps=40, error="growing", size=1e8, rng=0)
    run = filters.run_filter("rkf", sc, rng=1, eps=100.0)
    assert math.isfinite(float(run.error.max()))
