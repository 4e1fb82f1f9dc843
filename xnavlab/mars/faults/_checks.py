"""Checks of :func:`xnavlab.mars.faults.fault_tolerance.run_fault_tolerant`'s options: a setting
the run's detector or subsystems do not use is refused, not dropped (review 35j: ``xnav_level``
without XNAV, ``readmit_samples`` with no detector, ...).

Plumbing of :mod:`xnavlab.mars.faults`; not part of the public API.
"""

from __future__ import annotations

import math

import numpy as np

from xnavlab.core.detection import MAX_SAMPLES, Event
from xnavlab.core.faults import check_faults
from xnavlab.core.validate import check_choice, check_instance, check_int, check_real, shown
from xnavlab.mars.navigation.scenarios import SUBSYSTEMS

__all__ = ["DETECTOR_SETTINGS", "XNAV_SETTINGS", "READMIT_SAMPLES", "check_settings",
           "readmit_windows", "not_1d", "check_isolations", "check_result"]

#: Setting -> (the detectors that use it, its default): another detector with a setting away
#: from its default is refused (the scenario file's rule, ``DETECTOR_USES``). ``readmit_alpha``
#: and ``check_every`` belong to the rejoining test, which every detector but ``"none"`` runs.
DETECTOR_SETTINGS = {"pfa": (("wavelet",), 1e-5), "alpha": (("chi2",), 1e-5),
                     "rate_per_day": (("combined",), 1.0), "adaptive": (("combined",), True),
                     "arm_s": (("combined",), 600.0),
                     "readmit_alpha": (("wavelet", "chi2", "combined"), 0.01),
                     "check_every": (("wavelet", "chi2", "combined"), 100)}

#: Settings of the XNAV innovation wavelet (wavelet and combined detectors, a run with XNAV).
XNAV_SETTINGS = {"xnav_level": 3, "xnav_holdoff": 12}

#: NIS window of the rejoining test per subsystem, samples (``readmit_samples``' default).
READMIT_SAMPLES = {"uv": 100, "cns": 100, "xnav": 4}


def check_settings(detector, settings, subsystems=None):
    """Refuse a setting of ``settings`` (name -> value) away from its default that ``detector``
    does not use (:data:`DETECTOR_SETTINGS`), and, given the run's ``subsystems``, an XNAV
    setting (:data:`XNAV_SETTINGS`) of a run whose detector sees no XNAV innovations."""
    for key, value in settings.items():
        if key in XNAV_SETTINGS:
            if subsystems is None or value == XNAV_SETTINGS[key]:
                continue
            why = ("the run has no xnav subsystem" if "xnav" not in subsystems else
                   None if detector in ("wavelet", "combined") else
                   f"detector {detector!r} has no XNAV innovation wavelet")
            if why is not None:
                raise ValueError(f"{key} = {value!r} is unused: {why} (it sets the XNAV "
                                 f"innovation wavelet of the wavelet and combined detectors); "
                                 f"leave it at its default, {XNAV_SETTINGS[key]}")
            continue
        users, default = DETECTOR_SETTINGS[key]
        if value != default and detector not in users:
            who = users[0] if len(users) == 1 else f"{', '.join(users[:-1])} and {users[-1]}"
            name = "one of them" if len(users) > 1 else "that detector"
            raise ValueError(f"{key} = {value!r} is unused with detector {detector!r}: only the "
                             f"{who} detector{'s use' if len(users) > 1 else ' uses'} it; leave "
                             f"it at its default or name {name}")


def readmit_windows(readmit_samples, detector, subsystems):
    """The rejoining test's NIS window per subsystem: :data:`READMIT_SAMPLES` with
    ``readmit_samples`` (a dict, or None) over it, each key a subsystem of the run (else one
    ValueError naming it); given with detector ``"none"`` (nothing rejoins) it is refused."""
    win = dict(READMIT_SAMPLES)
    if readmit_samples is None:
        return win
    if not isinstance(readmit_samples, dict):
        raise ValueError(f"readmit_samples must be a dict of subsystem -> samples, e.g. "
                         f"{{'uv': 100}}, got {shown(readmit_samples)}")
    if detector == "none":
        raise ValueError("readmit_samples is unused with detector 'none': nothing is switched "
                         "out, so nothing rejoins; leave it out or name a detector")
    for k, v in readmit_samples.items():
        check_choice("readmit_samples key", k, SUBSYSTEMS)
        if k not in subsystems:
            raise ValueError(f"readmit_samples[{k!r}] is unused: the run has no {k} subsystem "
                             f"(its subsystems: {', '.join(subsystems)})")
        win[k] = check_int(f"readmit_samples[{k!r}]", v, 1, MAX_SAMPLES)
    return win


def not_1d(value):
    """Whether ``value`` is a numpy array that is no 1-D list (a 0-d array is not iterable)."""
    return isinstance(value, np.ndarray) and value.ndim != 1


def _time(v):
    """Whether ``v`` is a real, finite time >= 0 (not a bool)."""
    return isinstance(v, int | float | np.integer | np.floating) and not isinstance(v, bool) \
        and math.isfinite(v) and v >= 0


def check_isolations(isolations, sensors):
    """Isolation intervals: dicts with ``sensor`` (one of ``sensors``), ``out`` and ``back`` (s
    or None), else one ValueError naming ``isolations[i]``."""
    if isinstance(isolations, str | dict) or not hasattr(isolations, "__iter__") or not_1d(isolations):
        raise ValueError(f"isolations must be a list of dicts (sensor, out, back), got "
                         f"{shown(isolations)}")
    isolations = list(isolations)
    for i, iv in enumerate(isolations):
        if not isinstance(iv, dict) or not {"sensor", "out", "back"} <= set(iv):
            raise ValueError(f"isolations[{i}] must be a dict with keys sensor, out and back, "
                             f"got {shown(iv)}")
        if iv["sensor"] not in sensors:
            raise ValueError(f"isolations[{i}]['sensor'] must be one of "
                             f"{', '.join(map(repr, sensors))}, got {shown(iv['sensor'])}")
        for key in ("out", "back"):  # s since the start: a real time (back: None, still out)
            v = iv[key]
            if not (key == "back" and v is None or _time(v)):
                raise ValueError(f"isolations[{i}]['{key}'] must be a finite time >= 0, s since "
                                 f"the start{' (or None)' if key == 'back' else ''}, got {shown(v)}")
        if iv["back"] is not None and not iv["back"] > iv["out"]:
            raise ValueError(f"isolations[{i}]['back'] must come after its out ({iv['out']:g} s) "
                             f"or be None (still out at the end), got {iv['back']!r}")
    return isolations


def check_result(res, run_kind, detectors, components):
    """``res`` (a :class:`~xnavlab.mars.faults.fault_tolerance.FaultTolerantRun`) if its fields
    agree with its run, else one ValueError naming ``FaultTolerantRun.<field>`` (review 35o C3:
    ``dataclasses.replace(res, faults="uv")`` gave an AttributeError in ``summary()``).
    Checked: ``run`` a ``run_kind`` (itself checked when made); ``faults`` a sequence of Fault
    on the run's ``components(scenario)``; ``detector`` one of ``detectors``; ``events`` a dict of
    the run's subsystems to sequences of Event; ``isolated`` bool (n, ns) as the run's NIS;
    ``detection_data`` a dict of the run's subsystems; ``wall_time`` finite, >= 0 s."""
    run = check_instance("FaultTolerantRun.run", res.run, run_kind, f"a {run_kind.__name__}")
    subs = tuple(run.scenario.subsystems)
    check_faults("FaultTolerantRun.faults", res.faults, components(run.scenario))
    check_choice("FaultTolerantRun.detector", res.detector, detectors)
    for field in ("events", "detection_data"):
        d = getattr(res, field)
        if not isinstance(d, dict) or not set(d) <= set(subs):
            raise ValueError(f"FaultTolerantRun.{field} must be a dict keyed by the run's "
                             f"subsystems {list(subs)}, got {shown(d)}")
    for s, evs in res.events.items():
        if not isinstance(evs, list | tuple) or not all(isinstance(e, Event) for e in evs):
            raise ValueError(f"FaultTolerantRun.events[{s!r}] must be a list of Event, got "
                             f"{shown(evs)}")
    iso = res.isolated
    if not (isinstance(iso, np.ndarray) and iso.dtype == bool and iso.shape == run.nis.shape):
        raise ValueError(f"FaultTolerantRun.isolated must be a bool array of shape "
                         f"{run.nis.shape} (epochs, subsystems), got "
                         f"{type(iso).__name__} {getattr(iso, 'dtype', '')} "
                         f"{getattr(iso, 'shape', '')}")
    check_real("FaultTolerantRun.wall_time", res.wall_time, 0.0)
    return res
