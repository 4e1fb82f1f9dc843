"""Scenario files: every setting of a Mars run in one TOML file, with units and ranges.

``python -m xnavlab scenario --dump`` writes :func:`dump` (the defaults, each key with its
unit, range and meaning in a comment); ``python -m xnavlab run mars --scenario FILE``
reads it with :func:`load` (flags given on the command line override the file). The
Python API takes the same settings: ``load(path)`` returns a :class:`ScenarioFile`
whose ``scenario`` is the :class:`~xnavlab.mars.navigation.scenarios.MarsScenario` and whose
``run`` and ``detector`` hold the run's and the detector's settings, with the same
defaults as :func:`~xnavlab.mars.navigation.scenarios.run` and
:func:`~xnavlab.mars.faults.fault_tolerance.run_fault_tolerant`.

A key left out takes its default; an unknown section or key, or a value out of its
range, is one ``ValueError`` naming ``[section] key`` and what is allowed. So is a key that
the other settings make inert, when it is set to other than its default: a subsystem's key
while ``[run] subsystems`` leaves that subsystem out, ``[xnav] noise``, ``area_m2`` or
``background`` beside ``[xnav] sigma_m`` (:mod:`xnavlab.mars.navigation.unused_inputs`), a
``[detector]`` key the run's detector does not use (:func:`check_detector`: ``pfa`` with
``name = "none"``, ``arm_s`` in a plain run), and a force model's SRP key (``area_m2``,
``mass_kg``, ``reflectivity``) with ``srp = false``
(:class:`~xnavlab.mars.models.force_models.ForceModel`). A key at its default is the same run
as the key left out, and :func:`dump` writes every key, so those are accepted.

The set-up (``[run] setup``): ``"paper"`` (the default,
:class:`~xnavlab.mars.navigation.scenarios.MarsScenario`:
truth and filter share the paper's force model, as in the book's reproductions) or ``"study"``
(:meth:`~xnavlab.mars.navigation.scenarios.MarsScenario.study`: a rich truth, the paper's filter, ``q_acc``
derived from their difference); the keys of the file then depart from that set-up's defaults.
``[truth_model]`` and ``[filter_model]`` name the two force models
(:class:`xnavlab.mars.models.force_models.ForceModel`); ``[filter] q_acc = "derived"`` computes the
process noise from them (:func:`xnavlab.mars.models.model_noise.derived_q_acc`). ``[xnav] pulsars``
takes catalogue names, ``.par`` paths (relative to the file's folder) and inline tables
(:mod:`xnavlab.mars.timing.pulsar_specs`).

Examples
--------
>>> text = dump()
>>> sf = loads(text)
>>> sf.scenario == scenarios.MarsScenario(), sf.run["backend"], sf.detector["name"]
(True, 'numba', None)
>>> loads('[uv]\\nsigma_range_m = 2500.0').scenario.sigma_range_m
2500.0
>>> loads('[uv]\\nsigma_range = 1')
Traceback (most recent call last):
...
ValueError: scenario file: [uv] has no key 'sigma_range' (keys: dt_s, sigma_range_m, sigma_dir_deg, \
range_model, limb)
"""

from __future__ import annotations

import dataclasses
import json
import re
from dataclasses import dataclass, field

from xnavlab.core.userfiles import as_path, parse_toml, read_text
from xnavlab.core.validate import check_choice, check_instance, check_real, check_text, shown
from xnavlab.mars.models import force_models, model_noise
from xnavlab.mars.navigation import scenarios
from xnavlab.mars.timing import pulsar_specs

__all__ = ["SECTIONS", "SETUPS", "RUN_DEFAULTS", "DETECTOR_DEFAULTS", "UNITS", "ScenarioFile",
           "DETECTOR_USES", "dump", "load", "loads", "with_overrides", "detector_name",
           "check_detector", "check_fault_backend", "scenario_json"]

#: The set-ups a file's defaults come from (``[run] setup``).
SETUPS = ("paper", "study")

#: Settings of the run that are not fields of MarsScenario (``None``: the API's own default).
RUN_DEFAULTS = {"setup": "paper", "backend": "numba", "local_filter": "ekf", "settle_days": None}

#: Settings of the fault-tolerant run (``name = None``: :func:`detector_name`, the combined
#: detector when there are faults, else none: a plain run).
DETECTOR_DEFAULTS = {"name": None, "faults": "", "pfa": 1e-5, "alpha": 1e-5,
                     "rate_per_day": 1.0, "train_days": None, "arm_s": 600.0,
                     "adaptive": True}

#: ``[detector]`` key -> the detectors that use it; one set (not at its default) for another
#: detector is refused (:func:`check_detector`).
DETECTOR_USES = {"pfa": ("wavelet",), "alpha": ("chi2",), "rate_per_day": ("combined",),
                 "train_days": ("wavelet", "combined"), "arm_s": ("combined",),
                 "adaptive": ("combined",)}

_BODIES = ", ".join(force_models.PLANETS)
_MODEL_KEYS = {
    "gravity_degree": "Mars gravity field MRO95A (Konopliv et al. 2011) to this degree and "
                      "order: 0 (point mass) or 2-8",
    "third_bodies": f"point masses from the ephemeris, any of {_BODIES}",
    "srp": "solar radiation pressure (cannonball, Mars's cylindrical shadow), true/false",
    "area_m2": "SRP cross-section, m^2, (0, 1000]",
    "mass_kg": "spacecraft mass for SRP, kg, [1e-3, 1e5]",
    "reflectivity": "SRP coefficient C_R, [1, 2]",
}

# (section, key) -> (where: "scenario" field name, "run" or "detector" key; comment)
_KEYS = {
    ("run", "setup"): ("run:setup", "the set-up the defaults come from: \"paper\" (truth and "
                                    "filter share the paper's force model) or \"study\" "
                                    "(MarsScenario.study(): rich truth, the paper's filter)"),
    ("run", "days"): ("days", "simulated span, days, (0, 365]"),
    ("run", "seed"): ("seed", "seed of every noise draw, integer >= 0"),
    ("run", "mode"): ("mode", "federated mode: \"reset\" or \"no-reset\""),
    ("run", "subsystems"): ("subsystems", "any of \"xnav\", \"uv\", \"cns\""),
    ("run", "beta"): ("beta", "information-sharing factors, one a subsystem, in [1e-3, 1], "
                              "normalised to sum 1 (only their ratios count); omit for equal "
                              "shares"),
    ("run", "record_dt"): ("record_dt", "spacing of the recorded estimates, s, [0.1, 86400]"),
    ("run", "max_step"): ("max_step", "longest filter integration sub-step, s, [0.01, 3600]"),
    ("run", "backend"): ("run:backend", "\"numba\" (compiled) or \"numpy\" (the readable loop)"),
    ("run", "local_filter"): ("run:local_filter", "\"ekf\" or \"ukf\" (the UKF needs backend "
                                                  "\"numpy\")"),
    ("run", "settle_days"): ("run:settle_days", "start of the RMS window, days; omit for "
                                                "min(1, days / 2)"),
    ("orbit", "t0"): ("t0", "start epoch, s TDB past J2000"),
    ("orbit", "state0"): ("state0", "true initial state, Mars-centred J2000, m and m/s"),
    ("orbit", "truth_ephem"): ("truth_ephem", "ephemeris of the truth: \"de421\" or \"de405\""),
    ("orbit", "filter_ephem"): ("filter_ephem", "ephemeris of the filter: \"de421\" or "
                                                "\"de405\""),
    **{("truth_model", k): (f"truth_model.{k}", c) for k, c in _MODEL_KEYS.items()},
    **{("filter_model", k): (f"filter_model.{k}", c + (" (the compiled filter: 0 only)"
                                                     if k == "gravity_degree" else
                                                     " (the compiled filter: false only)"
                                                     if k == "srp" else ""))
       for k, c in _MODEL_KEYS.items()},
    ("filter", "q_acc"): ("q_acc", "process noise, white-acceleration PSD, m^2/s^3, [0, 1], or "
                                   "\"derived\" (from the truth and filter models)"),
    ("filter", "pos_err0_m"): ("pos_err0_m", "initial position error and 1-sigma per axis, m"),
    ("filter", "vel_err0_mps"): ("vel_err0_mps", "initial velocity error and 1-sigma per axis, "
                                                 "m/s"),
    ("filter", "init_error"): ("init_error", "\"fixed\" (the paper's) or \"random\" (N(0, P0))"),
    ("xnav", "pulsars"): ("pulsars", "catalogue names, .par paths (from this file's folder) "
                                     "or tables {par = ..., flux_ph_cm2_s = ..., "
                                     "pulsed_fraction = ..., width_s = ..., distance_m = ...}"),
    ("xnav", "dt_s"): ("dt_xnav", "measurement interval and integration time, s, [0.1, 86400]"),
    ("xnav", "sigma_m"): ("xnav_sigma_m", "ranging accuracy per pulsar, m; omit to compute it "
                                          "from area_m2, dt_s and background"),
    ("xnav", "noise"): ("xnav_noise", "how sigma_m is computed when omitted: \"paper\" (the "
                                      "paper's formula) or \"crlb\" (the Cramer-Rao bound)"),
    ("xnav", "area_m2"): ("area_m2", "detector area, m^2, (0, 100]"),
    ("xnav", "background"): ("background", "X-ray background, ph/cm^2/s, [0, 10]"),
    ("uv", "dt_s"): ("dt_uv", "measurement interval, s, [0.1, 86400]"),
    ("uv", "sigma_range_m"): ("sigma_range_m", "range noise, m"),
    ("uv", "sigma_dir_deg"): ("sigma_dir_deg", "direction noise per axis, deg"),
    ("uv", "range_model"): ("uv_range_model", "\"constant\" (the paper's) or \"radius\" (from "
                                              "the apparent radius, orbit-mean sigma_range_m)"),
    ("uv", "limb"): ("limb", "limb of the UV and horizon sensors: \"sphere\" (the paper's) or "
                             "\"oblate\" (Mars's ellipsoid fitted by a sphere)"),
    ("cns", "dt_s"): ("dt_cns", "measurement interval, s, [0.1, 86400]"),
    ("cns", "sigma_star_arcsec"): ("sigma_star_arcsec", "star-sensor noise, arcsec"),
    ("cns", "sigma_horizon_deg"): ("sigma_horizon_deg", "horizon-sensor noise, deg"),
    ("cns", "horizon_tau_s"): ("horizon_tau_s", "correlation time of the horizon errors, s; 0 "
                                                "for white (the paper's)"),
    ("cns", "stars"): ("stars", "the CNS stars by name, one or more (none twice); omit for the "
                                "three the catalogue picks"),
    ("detector", "name"): ("detector:name", "\"none\", \"wavelet\", \"chi2\" or \"combined\"; "
                                            "omit for combined with faults, else none"),
    ("detector", "faults"): ("detector:faults", "fault spec (run mars --help) or \"paper\"; "
                                                "\"\" for none"),
    ("detector", "pfa"): ("detector:pfa", "wavelet false-alarm probability per sample, (0, 1)"),
    ("detector", "alpha"): ("detector:alpha", "chi-square false-alarm probability per "
                                              "measurement, (0, 1)"),
    ("detector", "rate_per_day"): ("detector:rate_per_day", "combined: design false alarms per "
                                                            "subsystem per day, [1e-3, 100]"),
    ("detector", "train_days"): ("detector:train_days", "UV/CNS wavelet training span, days; "
                                                        "omit for min(1, days / 2)"),
    ("detector", "arm_s"): ("detector:arm_s", "combined: seconds before the innovation tests "
                                              "start, [0, span)"),
    ("detector", "adaptive"): ("detector:adaptive", "combined: adaptive noise scale, true/false"),
}

#: The sections of a scenario file, in the order :func:`dump` writes them.
SECTIONS = ("run", "orbit", "truth_model", "filter_model", "filter", "xnav", "uv", "cns",
            "detector")

#: Unit of each MarsScenario field (``scenario --check`` prints them beside the values).
UNITS = {"days": "day", "dt_xnav": "s", "dt_uv": "s", "dt_cns": "s", "pulsars": "-",
         "xnav_sigma_m": "m", "area_m2": "m^2", "background": "ph/cm^2/s", "sigma_range_m": "m",
         "sigma_dir_deg": "deg", "sigma_star_arcsec": "arcsec", "sigma_horizon_deg": "deg",
         "stars": "-", "pos_err0_m": "m", "vel_err0_mps": "m/s", "init_error": "-",
         "q_acc": "m^2/s^3", "max_step": "s", "truth_ephem": "-", "filter_ephem": "-",
         "truth_model": "gravity_degree: -, third_bodies: -, srp: -, area_m2: m^2, "
                        "mass_kg: kg, reflectivity: -",
         "filter_model": "gravity_degree: -, third_bodies: -, srp: -, area_m2: m^2, "
                         "mass_kg: kg, reflectivity: -",
         "subsystems": "-", "beta": "-", "mode": "-", "record_dt": "s", "seed": "-",
         "t0": "s TDB past J2000", "state0": "m, m/s (Mars-centred J2000)"}


@dataclass(frozen=True)
class ScenarioFile:
    """A read scenario file.

    Attributes
    ----------
    scenario : MarsScenario
        The scenario.
    run : dict
        ``setup``, ``backend``, ``local_filter``, ``settle_days`` (``None``: the default).
    detector : dict
        ``name``, ``faults``, ``pfa``, ``alpha``, ``rate_per_day``, ``train_days``, ``arm_s``,
        ``adaptive``.
    """

    scenario: scenarios.MarsScenario
    run: dict = field(default_factory=lambda: dict(RUN_DEFAULTS))
    detector: dict = field(default_factory=lambda: dict(DETECTOR_DEFAULTS))


def _toml(value):
    if isinstance(value, force_models.ForceModel):
        raise TypeError("a force model is written key by key")  # pragma: no cover
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, int | float):
        return repr(float(value)) if isinstance(value, float) else str(value)
    return "[" + ", ".join(_toml(v) for v in value) + "]"


def dump(scenario=None, run=None, detector=None):
    """The scenario file of ``scenario`` (default the paper's), one key a line with its unit.

    Keys whose value is ``None`` (computed) are written commented out with their meaning.
    Every other key is written, at its value, even where another setting makes it inert
    (``area_m2`` with ``srp = false``, ``pfa`` without a detector): :func:`loads` accepts a key
    at its default with any other settings and refuses an inert one only when it is changed.

    Returns
    -------
    str
        TOML text; :func:`loads` of it gives the same settings back.
    """
    sc = scenario if scenario is not None else scenarios.MarsScenario()
    values = {"run": {**RUN_DEFAULTS, "setup": "paper" if sc.paper_setup else "study",
                      **(run or {})},
              "detector": {**DETECTOR_DEFAULTS, **(detector or {})}}
    lines = ["# xnavlab Mars scenario: python -m xnavlab run mars --scenario THIS_FILE",
             "# Every key is optional (left out: the default below). Units and ranges in the "
             "comments.", ""]
    for section in SECTIONS:
        lines.append(f"[{section}]")
        for (sec, key), (where, comment) in _KEYS.items():
            if sec != section:
                continue
            if ":" in where:
                part, name = where.split(":")
                value = values[part][name]
            elif "." in where:
                part, name = where.split(".")
                value = getattr(getattr(sc, part), name)
            else:
                value = getattr(sc, where)
            if value is None:
                lines.append(f"# {key} = ...  # {comment}")
            elif where == "pulsars":
                items = ", ".join(pulsar_specs.to_toml(p) for p in value)
                lines.append(f"{key} = [{items}]  # {comment}")
            else:
                lines.append(f"{key} = {_toml(value)}  # {comment}")
        lines.append("")
    return "\n".join(lines)


def loads(text, base=None):
    """Read scenario-file text; returns a :class:`ScenarioFile` (see the module docstring).

    ``base``: the folder relative ``.par`` paths are read from (:func:`load` passes the
    file's own folder; default the working directory).
    """
    data = parse_toml(text, "scenario file")
    fields, run, detector = {}, dict(RUN_DEFAULTS), dict(DETECTOR_DEFAULTS)
    models = {"truth_model": {}, "filter_model": {}}
    for section, table in data.items():
        if not isinstance(table, dict):
            raise ValueError(_not_a_section(section, table))
        if section not in SECTIONS:
            raise ValueError(f"scenario file: unknown section [{section}] "
                             f"(sections: {', '.join(SECTIONS)})")
        for key, value in table.items():
            if (section, key) not in _KEYS:
                known = ", ".join(k for s, k in _KEYS if s == section)
                raise ValueError(f"scenario file: [{section}] has no key {key!r} (keys: {known})")
            where = _KEYS[(section, key)][0]
            if ":" in where:
                part, name = where.split(":")
                (run if part == "run" else detector)[name] = value
            elif "." in where:
                models[section][key] = value
            elif where == "pulsars":
                fields[where] = _pulsars(value, base)
            else:
                fields[where] = tuple(value) if isinstance(value, list) else value
    check_choice("[run] setup", run["setup"], SETUPS)
    for section, given in models.items():
        if given:
            start = (force_models.STUDY if section == "truth_model" and run["setup"] == "study"
                     else force_models.PAPER)
            try:
                fields[section] = force_models.ForceModel(**{**start.as_dict(), **given})
            except (TypeError, ValueError) as exc:
                raise ValueError(f"scenario file: [{section}] {exc}") from None
    derived = fields.get("q_acc") == "derived"
    if derived:
        del fields["q_acc"]
    try:
        if run["setup"] == "study":
            sc = scenarios.MarsScenario.study(**fields)
        else:
            sc = scenarios.MarsScenario(**fields)
            if derived:
                sc = dataclasses.replace(sc, q_acc=model_noise.derived_q_acc(
                    sc.truth_model, sc.filter_model, state0=sc.state0, t0=sc.t0,
                    truth_ephem=sc.truth_ephem, filter_ephem=sc.filter_ephem))
    except (TypeError, ValueError) as exc:
        raise ValueError(f"scenario file: {_where(exc)}") from None
    _check_run(run, sc)
    _check_detector(detector, sc)
    check_fault_backend(run, detector)
    return ScenarioFile(sc, run, detector)


def _not_a_section(name, value):
    """The message for a top-level entry that is no table: ``[[run]]`` (an array of tables) or
    a key outside any section (``days = 3``, said with the section that has it)."""
    if isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
        if name not in SECTIONS:
            return (f"scenario file: unknown section [[{name}]] (sections, one table each: "
                    f"{', '.join(SECTIONS)})")
        return f"scenario file: [[{name}]] is an array of tables; write [{name}] (one table)"
    if name in SECTIONS:
        return f"scenario file: {name} is a section: write [{name}] and its keys under it"
    home = [s for s, k in _KEYS if k == name]
    where = (f"put it under {' or '.join(f'[{s}]' for s in home)}" if home else
             f"no section has it (sections: {', '.join(SECTIONS)})")
    return f"scenario file: the key {name!r} is outside any section: {where}"


def _pulsars(value, base):
    """``[xnav] pulsars``: checked here so that a message names the key."""
    try:
        return pulsar_specs.check_list(value, base)
    except ValueError as exc:
        raise ValueError(f"scenario file: [xnav] {exc}") from None


def _where(exc):
    """A MarsScenario error in the file's words: the field it names (``dt_xnav``,
    ``xnav_sigma_m[1]``) replaced by the file's ``[section] key`` (``[xnav] dt_s``,
    ``[xnav] sigma_m[1]``), wherever the message uses it."""
    text = str(exc)
    name = text.split(" ")[0].split("[")[0]
    for (section, key), (where, _) in _KEYS.items():
        # the field the message is about (its first word), and any other field with an
        # internal name it mentions (xnav_sigma_m; a plain word such as days or subsystems
        # only where the message gives its value: "subsystems = ['uv']")
        if where == name:
            text = f"[{section}] {key}" + text[len(name):]
        elif ":" not in where and "." not in where:
            after = r"\b" if "_" in where else r"(?= = )"
            text = re.sub(rf"(?<![\w\[])({re.escape(where)}){after}", f"[{section}] {key}", text)
    return text


def _check_run(run, sc):
    check_choice("[run] setup", run["setup"], SETUPS)
    check_choice("[run] backend", run["backend"], ("numba", "numpy"))
    check_choice("[run] local_filter", run["local_filter"], ("ekf", "ukf"))
    if run["local_filter"] == "ukf" and run["backend"] != "numpy":
        raise ValueError("scenario file: [run] local_filter = \"ukf\" needs backend = \"numpy\"")
    if run["settle_days"] is not None:
        run["settle_days"] = check_real("[run] settle_days", run["settle_days"], 0.0, sc.days,
                                        hi_open=True)


def _check_detector(det, sc):
    from xnavlab.mars.faults.fault_tolerance import DETECTORS, parse_faults
    from xnavlab.mars.faults.schedules import RATE_PER_DAY_RANGE

    if det["name"] is not None:
        check_choice("[detector] name", det["name"], DETECTORS)
    if not isinstance(det["faults"], str):
        raise ValueError(f"[detector] faults must be a fault spec string, got {det['faults']!r}")
    if det["faults"]:  # a bad spec (" " too) is named by --check, not first by the run
        try:
            parse_faults(det["faults"], sc)
        except ValueError as exc:  # parse_faults' own name, spec, is the key here
            text = re.sub(r"^spec(\[\d+\])?: ", r"\1: ", str(exc))
            text = re.sub(r"^(spec|faults)(?=[ \[])", "", text)
            raise ValueError(f"[detector] faults{text if text[:1] in ':[ ' else ': ' + text}") \
                from None
    for key in ("pfa", "alpha"):
        det[key] = check_real(f"[detector] {key}", det[key], 0.0, 1.0, lo_open=True,
                              hi_open=True)
    det["rate_per_day"] = check_real("[detector] rate_per_day", det["rate_per_day"],
                                     *RATE_PER_DAY_RANGE)
    if det["train_days"] is not None:
        det["train_days"] = check_real("[detector] train_days", det["train_days"], 0.0, sc.days,
                                       lo_open=True, hi_open=True)
    det["arm_s"] = check_real("[detector] arm_s", det["arm_s"], 0.0, 1e8)
    if not isinstance(det["adaptive"], bool):
        raise ValueError(f"[detector] adaptive must be true or false, got {det['adaptive']!r}")
    check_detector(det)  # a key the run's detector does not use: refused, with or without faults
    if detector_name(det) == "combined" and not det["arm_s"] < sc.span:  # names the run's days
        raise ValueError(f"[detector] arm_s ({det['arm_s']:g} s, when the combined detector's "
                         f"tests start) must be shorter than the run: [run] days = {sc.days:g} "
                         f"is {sc.span:g} s")


def load(path):
    """Read the scenario file at ``path`` (:func:`loads`); a missing file is a ValueError."""
    path = as_path(path, "scenario file")  # a dict or None: one line, not Path's TypeError
    text = read_text(path, "scenario file")
    try:
        return loads(text, base=path.resolve().parent)
    except ValueError as exc:  # the file's name in the one line
        msg = str(exc).removeprefix("scenario file: ").removeprefix("scenario file ")
        raise ValueError(f"scenario file {str(path)!r}: {msg}") from None


def detector_name(detector):
    """The detector of a run: ``detector["name"]``, or when it is ``None`` (left out) the
    combined detector with faults and none without (a plain run) -- the default both of
    ``run mars`` and of :func:`xnavlab.mars.faults.fault_tolerance.run_fault_tolerant`.

    Examples
    --------
    >>> detector_name({"name": None, "faults": "paper"}), detector_name({"name": None, "faults": ""})
    ('combined', 'none')
    """
    check_instance("detector", detector, dict, "a [detector] table (a dict with 'name' and "
                   "'faults')")
    for key in ("name", "faults"):
        if key not in detector:
            raise ValueError(f"detector must hold {key!r} (a [detector] table: "
                             f"{', '.join(DETECTOR_DEFAULTS)})")
    if detector["name"] is not None:
        return check_text("detector['name']", detector["name"])
    faults = detector["faults"]
    if not isinstance(faults, str):
        raise ValueError(f"detector['faults'] must be a fault spec (text, '' for none), got "
                         f"{shown(faults)}")
    return "combined" if faults else "none"


def check_detector(detector):
    """Refuse a ``[detector]`` key set (not at its default, :data:`DETECTOR_DEFAULTS`) that the
    run's detector (:func:`detector_name`) does not use (:data:`DETECTOR_USES`).

    A key at its default is the same run as the key left out (``scenario --dump`` writes every
    key), so it is accepted with any detector. ``run mars`` checks again after ``--faults``
    and ``--detector`` have replaced the file's.

    Examples
    --------
    >>> check_detector({**DETECTOR_DEFAULTS, "name": "wavelet", "pfa": 0.01})
    >>> check_detector({**DETECTOR_DEFAULTS, "name": "none", "pfa": 0.01})
    Traceback (most recent call last):
    ...
    ValueError: [detector] pfa is set but the run's detector is none ([detector] name = "none"): \
only the wavelet detector uses it; leave it out or name that detector
    """
    name = detector_name(detector)
    missing = [k for k in DETECTOR_USES if k not in detector]
    if missing:
        raise ValueError(f"detector must hold every [detector] key, {missing[0]!r} is missing "
                         f"(the keys: {', '.join(DETECTOR_DEFAULTS)})")
    if name != "none" and not any(name in users for users in DETECTOR_USES.values()):
        return  # an unknown detector is named by its own check
    for key, users in DETECTOR_USES.items():
        if name in users or detector[key] == DETECTOR_DEFAULTS[key]:
            continue
        why = (f'[detector] name = "{name}"' if detector["name"] is not None else
               "no [detector] name and no faults: a plain run" if name == "none" else
               "no [detector] name and faults: the combined detector")
        which = " or ".join(users)
        raise ValueError(f"[detector] {key} is set but the run's detector is {name} ({why}): "
                         f"only the {which} detector{'s use' if len(users) > 1 else ' uses'} it; "
                         f"leave it out or name {'one of them' if len(users) > 1 else 'that detector'}")


def check_fault_backend(run, detector):
    """Refuse faults or a detector with another backend or local filter than the compiled EKF.

    The fault-tolerant loop (:func:`xnavlab.mars.faults.fault_tolerance.run_fault_tolerant`) is the
    compiled kernel's, with EKF locals: ``scenario --check`` refuses in the file's words what
    ``run mars`` could not run.

    Examples
    --------
    >>> check_fault_backend({"backend": "numpy", "local_filter": "ekf"},
    ...                     {**DETECTOR_DEFAULTS, "faults": "uv.range:step:1e3@1000+10"})
    Traceback (most recent call last):
    ...
    ValueError: [detector] faults (a fault-tolerant run) runs with [run] backend = "numba" and \
local_filter = "ekf" only, got backend = "numpy"
    """
    name = detector_name(detector)
    if name == "none" and not str(detector["faults"]).strip():
        return
    bad = [f'{k} = "{run[k]}"' for k, ok in (("backend", "numba"), ("local_filter", "ekf"))
           if run[k] != ok]
    if bad:
        why = "[detector] faults" if str(detector["faults"]).strip() else \
            f'[detector] name = "{name}"'
        raise ValueError(f"{why} (a fault-tolerant run) runs with [run] backend = \"numba\" and "
                         f"local_filter = \"ekf\" only, got {' and '.join(bad)}")


def scenario_json(scenario):
    """The fields of a :class:`~xnavlab.mars.navigation.scenarios.MarsScenario` as JSON-ready values
    (force models as dicts, pulsars as :func:`xnavlab.mars.timing.pulsar_specs.to_json`). None is
    the default scenario; anything else that is no MarsScenario is one ValueError.

    Examples
    --------
    >>> d = scenario_json(scenarios.MarsScenario())
    >>> d["truth_model"]["gravity_degree"], d["pulsars"][0]
    (0, 'B0531+21')
    """
    scenario = scenarios.check_scenario("scenario", scenario)  # not dataclasses' TypeError
    out = {}
    for f in dataclasses.fields(scenario):
        v = getattr(scenario, f.name)
        if isinstance(v, force_models.ForceModel):
            v = v.as_dict()
        elif f.name == "pulsars":
            v = [pulsar_specs.to_json(p) for p in v]
        elif isinstance(v, tuple):
            v = list(v)
        out[f.name] = v
    return out


def with_overrides(sf, **fields):
    """A :class:`ScenarioFile` with scenario fields replaced (the command line's overrides).

    The run's and the detector's settings are checked again against the new scenario, with
    the ranges ``scenario --check`` gives (``[run] settle_days`` in ``[0, days)``), the
    overrides named: ``--days 0.03`` with ``settle_days = 0.04`` in the file is refused as
    ``[run] settle_days must be a real number in [0, 0.03), got 0.04 (with days = 0.03)``.
    """
    fields = {k: v for k, v in fields.items() if v is not None}
    given = ", ".join(f"{k} = {v:g}" if isinstance(v, float) else f"{k} = {v}"
                      for k, v in fields.items())
    try:  # a field the overrides make bad (t0 past the ephemeris with more days): the file's words
        out = dataclasses.replace(sf, scenario=dataclasses.replace(sf.scenario, **fields))
    except ValueError as exc:
        raise ValueError(f"{_where(exc)} (with {given})") from None
    if fields:
        run, det = dict(out.run), dict(out.detector)
        try:
            _check_run(run, out.scenario)
            _check_detector(det, out.scenario)
        except ValueError as exc:
            raise ValueError(f"{exc} (with {given})") from None
    return out
