"""Inputs a Mars run would leave unused (refused) or empty (warned about): review 35 B.6, B.8."""

import dataclasses

import pytest

from xnavlab.core.userfiles import InputWarning
from xnavlab.mars.navigation import scenarios, unused_inputs

#: A valid value other than the default, for every field only one subsystem uses.
CHANGED = {"dt_xnav": 600.0, "pulsars": ("B1937+21", "B0531+21", "B1957+20"),
           "xnav_sigma_m": (1.0, 2.0, 3.0, 4.0), "xnav_noise": "crlb", "area_m2": 2.0,
           "background": 0.01, "dt_uv": 6.0, "sigma_range_m": 1000.0, "sigma_dir_deg": 0.2,
           "uv_range_model": "radius", "limb": "oblate", "dt_cns": 6.0,
           "sigma_star_arcsec": 1.0, "sigma_horizon_deg": 0.1, "horizon_tau_s": 100.0,
           "stars": ("Sirius", "Vega", "Canopus")}


def test_the_map_names_fields_of_the_scenario_and_every_one_has_a_changed_value():
    names = {f.name for f in dataclasses.fields(scenarios.MarsScenario)}
    listed = {n for fields in unused_inputs.SUBSYSTEM_FIELDS.values() for n in fields}
    assert listed <= names and set(unused_inputs.NOISE_FIELDS) <= listed
    assert listed == set(CHANGED)
    assert set(unused_inputs.SUBSYSTEM_FIELDS) == set(scenarios.SUBSYSTEMS)


@pytest.mark.parametrize("name", sorted(CHANGED))
def test_a_field_set_for_a_subsystem_that_does_not_run_is_refused_in_one_line(name):
    owners = [s for s, f in unused_inputs.SUBSYSTEM_FIELDS.items() if name in f]
    others = tuple(s for s in scenarios.SUBSYSTEMS if s not in owners)
    with pytest.raises(ValueError) as info:
        scenarios.MarsScenario(subsystems=others, **{name: CHANGED[name]})
    msg = str(info.value)
    assert msg.startswith(f"{name} is set but subsystems = {list(others)!r} runs ")
    assert all(s in msg for s in owners) and len(msg.splitlines()) == 1
    # used when its subsystem runs; accepted at its default without it (the same run)
    kw = {name: CHANGED[name]}
    if name in ("xnav_noise", "area_m2", "background"):
        kw["xnav_sigma_m"] = None
    assert getattr(scenarios.MarsScenario(subsystems=(owners[0],), **kw), name) is not None
    default = getattr(scenarios.MarsScenario(), name)
    assert scenarios.MarsScenario(subsystems=others, **{name: default}).subsystems == others


@pytest.mark.parametrize("name, value", [("xnav_noise", "crlb"), ("area_m2", 2.0),
                                         ("background", 0.01)])
def test_what_computes_the_ranging_noise_is_refused_beside_given_sigmas(name, value):
    with pytest.raises(ValueError, match=rf"^{name} = {value!r} is unused: xnav_sigma_m gives "
                                         r"the ranging noise it would compute; give one of them$"):
        scenarios.MarsScenario(xnav_sigma_m=(1.0, 2.0, 3.0, 4.0), **{name: value})


def test_a_subsystem_that_gets_no_measurement_is_warned_about_with_the_fix():
    with pytest.warns(InputWarning, match=r"^xnav gets no measurement in 0.005 days \(its first "
                                          r"comes at 500 s\): run longer or drop it from "
                                          r"subsystems$") as rec:
        inp = scenarios.prepare(days=0.005)
    assert len(rec) == 1 and inp.t_meas["xnav"].size == 0 and inp.t_meas["uv"].size == 144
    with pytest.warns(InputWarning, match=r"^cns gets no measurement in 0.05 days \(its first "
                                          r"comes at 86400 s\)"):
        scenarios.prepare(days=0.05, subsystems=("uv", "cns"), dt_cns=86400.0)


def test_an_rms_of_one_record_is_warned_about_and_two_are_not():
    res = scenarios.run(days=0.05, subsystems=("uv",), record_dt=86400.0)
    with pytest.warns(InputWarning, match=r"^position_error_m and velocity_error_mps are the RMS "
                                          r"of 1 record \(from settle_days = 0.025 with "
                                          r"record_dt = 86400 s\): lower record_dt or "
                                          r"settle_days, or run longer$"):
        m = res.metrics()
    assert m["position_error_m"] == m["final_position_error_m"]
    res.metrics(settle_days=0.0)            # the first and the last record: no warning


def test_beta_for_one_subsystem_is_refused():
    """Review 35j (5) 10: beta=(0.5,) with one subsystem was kept, though only ratios count."""
    for beta in ((0.5,), (1.0,), (0.5, 0.5)):
        with pytest.raises(ValueError, match=r"^beta is set but subsystems = \['uv'\] runs one "
                                             r"local filter, which holds the whole information "
                                             r"share \(beta = 1\): leave it out$"):
            scenarios.MarsScenario(days=0.02, subsystems=("uv",), beta=beta)


def test_a_record_dt_below_the_runs_epochs_is_refused_with_the_nearest_valid_value():
    """Review 35j (5) 12: record_dt = 1 s on a 3-s grid recorded every 3 s without a word."""
    with pytest.raises(ValueError, match=r"^record_dt must be at least 3 s \(dt_uv, the shortest "
                                         r"measurement interval of subsystems = \['uv'\]: the run "
                                         r"records at most one estimate an epoch\), got 1: use "
                                         r"record_dt = 3$"):
        scenarios.MarsScenario(days=0.02, subsystems=("uv",), record_dt=1.0)
    with pytest.raises(ValueError, match=r"^record_dt must be at least 500 s \(dt_xnav, .*, got "
                                         r"300: use record_dt = 500$"):
        scenarios.MarsScenario(days=0.1, subsystems=("xnav",), record_dt=300.0)
    # the default (60 s) records every epoch of XNAV alone; the shortest interval is valid
    assert scenarios.MarsScenario(days=0.1, subsystems=("xnav",)).record_dt == 60.0
    assert scenarios.MarsScenario(days=0.02, subsystems=("uv",), record_dt=3.0).record_dt == 3.0


@pytest.mark.parametrize("call, name", [
    (lambda: unused_inputs.warn_unmeasured(1.0, {"xnav": 1}), "scenario"),
    (lambda: unused_inputs.warn_unmeasured(scenarios.MarsScenario(), None), "counts"),
    (lambda: unused_inputs.warn_unmeasured(scenarios.MarsScenario(), {"xnav": 1}), "counts"),
    (lambda: unused_inputs.warn_unmeasured(scenarios.MarsScenario(), {"xnav": "1", "uv": 1, "cns": 1}),
     r"counts\['xnav'\]"),
    (lambda: unused_inputs.warn_few_records(None, 0.025, 86400.0), "n"),
    (lambda: unused_inputs.warn_few_records(1, "x", 86400.0), "settle_days"),
    (lambda: unused_inputs.warn_few_records(1, 0.0, 0.0), "record_dt"),
    (lambda: unused_inputs.divergence_advice("x"), "scenario"),
])
def test_the_helpers_name_their_parameters(call, name):
    """Review 35k (1) 25: the run notes' helpers raised AttributeError or TypeError."""
    with pytest.raises(ValueError, match=f"^{name} must"):
        call()


def test_a_long_run_of_the_numpy_loop_is_announced_with_its_estimate(monkeypatch):
    """Review 35p P8: ``run mars --days 365 --backend numpy`` ran for about a day without a
    word. The estimate (epochs x the measured seconds an epoch) is warned about before the run
    when past SLOW_RUN_S; here the threshold is lowered so that a short run crosses it."""
    import warnings

    inputs = scenarios.prepare(days=0.01)
    with warnings.catch_warnings():  # at the real threshold: nothing said
        warnings.simplefilter("error")
        scenarios.run(inputs=inputs, backend="numpy")
    monkeypatch.setattr(unused_inputs, "SLOW_RUN_S", 1.0)
    with pytest.warns(InputWarning, match=r"^backend numpy, the readable loop, takes about 6 ms an "
                                          r"epoch with the EKF on 2 cores: these \d+ epochs take "
                                          r"about \d+ min; the compiled kernel \(backend numba"):
        scenarios.run(inputs=inputs, backend="numpy")
    with warnings.catch_warnings():  # the compiled kernel: nothing said
        warnings.simplefilter("error")
        scenarios.run(inputs=inputs)
