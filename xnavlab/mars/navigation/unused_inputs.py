"""Inputs a Mars run would leave unused or empty: refused, or warned about, in one line.

A setting that another setting makes inert is refused by :func:`check_fields` (called by
:class:`~xnavlab.mars.navigation.scenarios.MarsScenario` itself): a field of :data:`SUBSYSTEM_FIELDS`
set for a subsystem that is not in ``subsystems`` (``xnav_sigma_m`` without ``"xnav"``,
``stars`` without ``"cns"``), a field of :data:`NOISE_FIELDS` beside ``xnav_sigma_m``,
which gives the ranging noise they would compute, ``beta`` for a run of one subsystem (only
the factors' ratios count) and a ``record_dt`` below the run's epochs (:func:`check_record_dt`).

"Set" means *different from the field's default* (the dataclass default, which is also the
value a scenario file's left-out key takes). A value equal to the default is the same run as
leaving it out, so nothing the user asked for is dropped; and a file written by
``scenario --dump`` (every key at its default) still loads when its ``subsystems`` is edited.
The price: a key typed at its default value for a subsystem that does not run is accepted.

Inputs that leave part of the run empty are warned about with
:class:`~xnavlab.core.userfiles.InputWarning` (the command line prints it as one line, also under
``--quiet``): :func:`warn_unmeasured`, a subsystem in ``subsystems`` that gets no
measurement in the whole run; :func:`warn_few_records`, an RMS taken over fewer than 2 records;
:func:`warn_slow_loop`, a run of the readable numpy loop estimated to take longer than
:data:`SLOW_RUN_S` (review 35p P8: ``--days 365 --backend numpy`` ran for about a day without a word).

Examples
--------
>>> from xnavlab.mars.navigation.scenarios import MarsScenario
>>> MarsScenario(subsystems=("uv",), stars=("Sirius", "Vega", "Canopus"))
Traceback (most recent call last):
...
ValueError: stars is set but subsystems = ['uv'] runs no cns: leave it out or add 'cns'
"""

from __future__ import annotations

import dataclasses
import warnings

from xnavlab.core.userfiles import InputWarning
from xnavlab.core.validate import check_instance, check_int, check_real, shown

__all__ = ["SUBSYSTEM_FIELDS", "NOISE_FIELDS", "NOISE_SETTINGS", "check_fields", "check_record_dt",
           "warn_unmeasured", "warn_few_records", "NUMPY_S_PER_EPOCH", "SLOW_RUN_S", "warn_slow_loop",
           "divergence_advice"]

#: Seconds an epoch of the readable numpy loop takes, by local filter, on a 2-core machine,
#: taken low: measured 2026-11-29, 7.5 ms with the EKF and 91 ms with the UKF on a quiet machine
#: (579 epochs), 8.4 and 111 ms beside other work (1,447): the estimate of
#: :func:`warn_slow_loop`, which so warns a little late rather than early.
NUMPY_S_PER_EPOCH = {"ekf": 6e-3, "ukf": 8e-2}

#: A numpy-loop run estimated to take longer than this, s, is warned about before it starts.
SLOW_RUN_S = 600.0

#: Subsystem -> the MarsScenario fields only it uses (``limb`` shapes both the UV sensor and
#: the CNS horizon sensor, so it is used while either runs).
SUBSYSTEM_FIELDS = {
    "xnav": ("dt_xnav", "pulsars", "xnav_sigma_m", "xnav_noise", "area_m2", "background"),
    "uv": ("dt_uv", "sigma_range_m", "sigma_dir_deg", "uv_range_model", "limb"),
    "cns": ("dt_cns", "sigma_star_arcsec", "sigma_horizon_deg", "horizon_tau_s", "stars",
            "limb"),
}

#: The fields that compute the XNAV ranging noise; unused when ``xnav_sigma_m`` gives it.
NOISE_FIELDS = ("xnav_noise", "area_m2", "background")


def _defaults(obj):
    out = {}
    for f in dataclasses.fields(obj):
        if f.default is not dataclasses.MISSING:
            out[f.name] = f.default
        elif f.default_factory is not dataclasses.MISSING:
            out[f.name] = f.default_factory()
    return out


def check_fields(scenario):
    """Refuse a field of ``scenario`` that is set (not at its default) but unused.

    Parameters
    ----------
    scenario : MarsScenario
        Checked after its own fields are (values normalised: pulsar and star names).

    Raises
    ------
    ValueError
        One line naming the field and the setting that makes it inert (``subsystems`` or
        ``xnav_sigma_m``), and what to do.

    Examples
    --------
    >>> from xnavlab.mars.navigation.scenarios import MarsScenario
    >>> MarsScenario(subsystems=("uv",), xnav_sigma_m=(1.0,) * 4)
    Traceback (most recent call last):
    ...
    ValueError: xnav_sigma_m is set but subsystems = ['uv'] runs no xnav: leave it out or add 'xnav'
    >>> MarsScenario(subsystems=("uv",), dt_xnav=500.0).subsystems   # the default: no change
    ('uv',)
    """
    default = _defaults(scenario)
    on = scenario.subsystems
    for f in dataclasses.fields(scenario):
        owners = [s for s, names in SUBSYSTEM_FIELDS.items() if f.name in names]
        if not owners or any(s in on for s in owners) or getattr(scenario, f.name) == \
                default[f.name]:
            continue
        runs = f"no {owners[0]}" if len(owners) == 1 else f"neither {' nor '.join(owners)}"
        add = f"'{owners[0]}'" if len(owners) == 1 else "one of them"
        raise ValueError(f"{f.name} is set but subsystems = {list(on)!r} runs {runs}: leave it "
                         f"out or add {add}")
    if scenario.beta is not None and len(on) == 1:  # review 35j: only ratios of beta count
        raise ValueError(f"beta is set but subsystems = {list(on)!r} runs one local filter, which "
                         f"holds the whole information share (beta = 1): leave it out")
    check_record_dt(scenario, default["record_dt"])
    if scenario.xnav_sigma_m is None:
        return
    for name in NOISE_FIELDS:
        value = getattr(scenario, name)
        if value != default[name]:
            raise ValueError(f"{name} = {value!r} is unused: xnav_sigma_m gives the ranging "
                             f"noise it would compute; give one of them")


def check_record_dt(scenario, default):
    """Refuse a ``record_dt`` set (not at its ``default``) below the shortest measurement interval
    of the run's subsystems: the run records at most every epoch, so a shorter spacing was
    raised to the epochs' without a word (review 35j). The default (60 s) records every epoch
    of a run whose epochs are sparser (XNAV alone, every 500 s).

    Examples
    --------
    >>> from xnavlab.mars.navigation.scenarios import MarsScenario
    >>> MarsScenario(days=0.02, subsystems=("uv",), record_dt=1.0)
    Traceback (most recent call last):
    ...
    ValueError: record_dt must be at least 3 s (dt_uv, the shortest measurement interval of \
subsystems = ['uv']: the run records at most one estimate an epoch), got 1: use record_dt = 3
    """
    dt, name = min((getattr(scenario, f"dt_{s}"), f"dt_{s}") for s in scenario.subsystems)
    if scenario.record_dt != default and scenario.record_dt < dt:
        raise ValueError(f"record_dt must be at least {dt:g} s ({name}, the shortest measurement "
                         f"interval of subsystems = {list(scenario.subsystems)!r}: the run records "
                         f"at most one estimate an epoch), got {scenario.record_dt:g}: use "
                         f"record_dt = {dt:g}")


def warn_unmeasured(scenario, counts):
    """Warn (:class:`~xnavlab.core.userfiles.InputWarning`) for each subsystem that gets no
    measurement in the run.

    Parameters
    ----------
    scenario : MarsScenario
    counts : dict
        Subsystem -> number of its measurements in the run.

    Examples
    --------
    >>> import warnings
    >>> from xnavlab.mars.navigation.scenarios import MarsScenario
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     warn_unmeasured(MarsScenario(days=0.005), {"xnav": 0, "uv": 144, "cns": 144})
    >>> print(w[0].message)
    xnav gets no measurement in 0.005 days (its first comes at 500 s): run longer or drop it \
from subsystems
    """
    scenario = _scenario(scenario)
    check_instance("counts", counts, dict, "a dict of subsystem -> number of measurements")
    for s in scenario.subsystems:
        if s not in counts:
            raise ValueError(f"counts must hold every subsystem of the scenario "
                             f"({', '.join(scenario.subsystems)}), {s!r} is missing")
        if check_int(f"counts[{s!r}]", counts[s], 0) == 0:
            dt = getattr(scenario, f"dt_{s}")
            warnings.warn(f"{s} gets no measurement in {scenario.days:g} days (its first comes "
                          f"at {dt:g} s): run longer or drop it from subsystems", InputWarning,
                          stacklevel=3)


def warn_few_records(n, settle_days, record_dt):
    """Warn (:class:`~xnavlab.core.userfiles.InputWarning`) when the error RMS of a run is taken
    over fewer than 2 records (``n``): it is then one sample, not a statistic.

    Parameters
    ----------
    n : int
        Records in the RMS window.
    settle_days, record_dt : float
        Start of the window, days, and the spacing of the records, s (named in the message).

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     warn_few_records(1, 0.025, 86400.0)
    >>> print(w[0].message)
    position_error_m and velocity_error_mps are the RMS of 1 record (from settle_days = 0.025 \
with record_dt = 86400 s): lower record_dt or settle_days, or run longer
    """
    n = check_int("n", n, 0)
    settle_days = check_real("settle_days", settle_days, 0.0)
    record_dt = check_real("record_dt", record_dt, 0.0, lo_open=True)
    if n < 2:
        warnings.warn(f"position_error_m and velocity_error_mps are the RMS of {n} record"
                      f"{'' if n == 1 else 's'} (from settle_days = {settle_days:g} with "
                      f"record_dt = {record_dt:g} s): lower record_dt or settle_days, or run "
                      f"longer", InputWarning, stacklevel=3)


#: The settings that set a noise or an uncertainty, named when the filter cannot carry them.
NOISE_SETTINGS = ("sigma_range_m", "sigma_dir_deg", "sigma_star_arcsec", "sigma_horizon_deg",
                  "xnav_sigma_m", "area_m2", "background", "pos_err0_m", "vel_err0_mps", "q_acc",
                  "pulsars")


def warn_slow_loop(n, local_filter):
    """Warn (:class:`~xnavlab.core.userfiles.InputWarning`, before the run) when ``n`` epochs of
    the numpy loop with ``local_filter`` (``"ekf"``, ``"ukf"``) are estimated to take longer than
    :data:`SLOW_RUN_S`; the compiled kernel gives the EKF's estimates in seconds.

    Examples
    --------
    >>> warn_slow_loop(1000, "ekf")    # about 6 s: no warning
    """
    n = check_int("n", n, 0, 10**9)  # a run's epochs (30 days of 3-s epochs: 864,000)
    est = n * NUMPY_S_PER_EPOCH[local_filter]
    if est > SLOW_RUN_S:
        instead = ("the compiled kernel (backend numba, the default) gives the same estimates in "
                   "seconds" if local_filter == "ekf" else "the UKF runs on numpy only: fewer days "
                   "run sooner")
        took = f"{est / 60.0:.0f} min" if est < 5400.0 else f"{est / 3600.0:.1f} h"
        warnings.warn(f"backend numpy, the readable loop, takes about "
                      f"{NUMPY_S_PER_EPOCH[local_filter] * 1e3:g} ms an epoch with the "
                      f"{local_filter.upper()} on 2 cores: these {n:,} epochs take about {took}; "
                      f"{instead}", InputWarning, stacklevel=3)


def _scenario(scenario):
    """``scenario`` checked as a MarsScenario, under its own name."""
    if type(scenario).__name__ != "MarsScenario" or not dataclasses.is_dataclass(scenario):
        raise ValueError(f"scenario must be a MarsScenario, got {type(scenario).__name__} "
                         f"{shown(scenario)}")  # (scenarios imports this module: no isinstance)
    return scenario


def divergence_advice(scenario):
    """What to change when the compiled filter cannot carry a scenario: the noise settings
    moved from their defaults, by name (review 35f: the message named only pos_err0_m, a
    setting the user had not given), else the smallest noise setting.

    Examples
    --------
    >>> from xnavlab.mars.navigation.scenarios import MarsScenario
    >>> divergence_advice(MarsScenario(sigma_range_m=1.0))
    'the noise settings away from their defaults: sigma_range_m = 1.0 (default 5000.0) (move them back)'
    >>> divergence_advice(MarsScenario())
    'raise the smallest noise setting'
    """
    scenario = _scenario(scenario)
    defaults = _defaults(scenario)
    moved = [f"{name} = {getattr(scenario, name)!r:.60} (default {defaults[name]!r:.40})"
             for name in NOISE_SETTINGS if getattr(scenario, name) != defaults[name]]
    if not moved:
        return "raise the smallest noise setting"
    return "the noise settings away from their defaults: " + "; ".join(moved) + " (move them back)"
