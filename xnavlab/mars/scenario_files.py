"""Scenario files: every setting of a Mars run in one TOML file, with units and ranges.

``python -m xnavlab scenario --dump`` writes :func:`dump` (the defaults, each key with its
unit, range and meaning in a comment); ``python -m xnavlab run mars --scenario FILE``
reads it with :func:`load` (flags given on the command line override the file). The
Python API takes the same settings: ``load(path)`` returns a :class:`ScenarioFile`
whose ``scenario`` is the :class:`~xnavlab.mars.scenarios.MarsScenario` and whose
``run`` and ``detector`` hold the run's and the detector's settings, with the same
defaults as :func:`~xnavlab.mars.scenarios.run` and
:func:`~xnavlab.mars.fault_tolerance.run_fault_tolerant`.

A key left out takes its default; an unknown section or key, or a value out of its
range, is one ``ValueError`` naming ``[section] key`` and what is allowed.

Examples
--------
>>> text = dump()
>>> sf = loads(text)
>>> sf.scenario == scenarios.MarsScenario(), sf.run["backend"], sf.detector["name"]
(True, 'numba', 'none')
>>> loads('[uv]\\nsigma_range_m = 2500.0').scenario.sigma_range_m
2500.0
>>> loads('[uv]\\nsigma_range = 1')
Traceback (most recent call last):
...
ValueError: scenario file: [uv] has no key 'sigma_range' (keys: dt_s, sigma_range_m, sigma_dir_deg)
"""

from __future__ import annotations

import dataclasses
import json
from dataclasses import dataclass, field
from pathlib import Path

from xnavlab.core.validate import check_choice, check_real
from xnavlab.mars import scenarios

__all__ = ["SECTIONS", "RUN_DEFAULTS", "DETECTOR_DEFAULTS", "ScenarioFile", "dump", "load", "loads",
           "with_overrides"]

#: Settings of the run that are not fields of MarsScenario (``None``: the API's own default).
RUN_DEFAULTS = {"backend": "numba", "local_filter": "ekf", "settle_days": None}

#: Settings of the fault-tolerant run (``name = "none"``: no detector, no faults).
DETECTOR_DEFAULTS = {"name": "none", "faults": "", "pfa": 1e-5, "alpha": 1e-5,
                     "rate_per_day": 1.0, "train_days": None, "arm_s": 600.0,
                     "adaptive": True}

# (section, key) -> (where: "scenario" field name, "run" or "detector" key; comment)
_KEYS = {
    ("run", "days"): ("days", "simulated span, days, (0, 365]"),
    ("run", "seed"): ("seed", "seed of every noise draw, integer >= 0"),
    ("run", "mode"): ("mode", "federated mode: \"reset\" or \"no-reset\""),
    ("run", "subsystems"): ("subsystems", "any of \"xnav\", \"uv\", \"cns\""),
    ("run", "beta"): ("beta", "information-sharing factors, one a subsystem, in (0, 1]; "
                              "omit for equal shares"),
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
    ("filter", "q_acc"): ("q_acc", "process noise, white-acceleration PSD, m^2/s^3, [0, 1]"),
    ("filter", "pos_err0_m"): ("pos_err0_m", "initial position error and 1-sigma per axis, m"),
    ("filter", "vel_err0_mps"): ("vel_err0_mps", "initial velocity error and 1-sigma per axis, "
                                                 "m/s"),
    ("filter", "init_error"): ("init_error", "\"fixed\" (the paper's) or \"random\" (N(0, P0))"),
    ("xnav", "pulsars"): ("pulsars", "the pulsars, by catalogue name"),
    ("xnav", "dt_s"): ("dt_xnav", "measurement interval and integration time, s, [0.1, 86400]"),
    ("xnav", "sigma_m"): ("xnav_sigma_m", "ranging accuracy per pulsar, m; omit to compute it "
                                          "from area_m2, dt_s and background"),
    ("xnav", "area_m2"): ("area_m2", "detector area, m^2, (0, 100]"),
    ("xnav", "background"): ("background", "X-ray background, ph/cm^2/s, [0, 10]"),
    ("uv", "dt_s"): ("dt_uv", "measurement interval, s, [0.1, 86400]"),
    ("uv", "sigma_range_m"): ("sigma_range_m", "range noise, m"),
    ("uv", "sigma_dir_deg"): ("sigma_dir_deg", "direction noise per axis, deg"),
    ("cns", "dt_s"): ("dt_cns", "measurement interval, s, [0.1, 86400]"),
    ("cns", "sigma_star_arcsec"): ("sigma_star_arcsec", "star-sensor noise, arcsec"),
    ("cns", "sigma_horizon_deg"): ("sigma_horizon_deg", "horizon-sensor noise, deg"),
    ("cns", "stars"): ("stars", "the three stars, by name; omit to pick them from the catalogue"),
    ("detector", "name"): ("detector:name", "\"none\", \"wavelet\", \"chi2\" or \"combined\""),
    ("detector", "faults"): ("detector:faults", "fault spec (run mars --help) or \"paper\"; "
                                                "\"\" for none"),
    ("detector", "pfa"): ("detector:pfa", "wavelet false-alarm probability per sample, (0, 1)"),
    ("detector", "alpha"): ("detector:alpha", "chi-square false-alarm probability per "
                                              "measurement, (0, 1)"),
    ("detector", "rate_per_day"): ("detector:rate_per_day", "combined: design false alarms per "
                                                            "subsystem per day, (0, 100]"),
    ("detector", "train_days"): ("detector:train_days", "UV/CNS wavelet training span, days; "
                                                        "omit for min(1, days / 2)"),
    ("detector", "arm_s"): ("detector:arm_s", "combined: seconds before the innovation tests "
                                              "start, [0, span)"),
    ("detector", "adaptive"): ("detector:adaptive", "combined: adaptive noise scale, true/false"),
}

#: The sections of a scenario file, in the order :func:`dump` writes them.
SECTIONS = ("run", "orbit", "filter", "xnav", "uv", "cns", "detector")


@dataclass(frozen=True)
class ScenarioFile:
    """A read scenario file.

    Attributes
    ----------
    scenario : MarsScenario
        The scenario.
    run : dict
        ``backend``, ``local_filter``, ``settle_days`` (``None``: the default).
    detector : dict
        ``name``, ``faults``, ``pfa``, ``alpha``, ``rate_per_day``, ``train_days``, ``arm_s``,
        ``adaptive``.
    """

    scenario: scenarios.MarsScenario
    run: dict = field(default_factory=lambda: dict(RUN_DEFAULTS))
    detector: dict = field(default_factory=lambda: dict(DETECTOR_DEFAULTS))


def _toml(value):
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

    Returns
    -------
    str
        TOML text; :func:`loads` of it gives the same settings back.
    """
    sc = scenario if scenario is not None else scenarios.MarsScenario()
    values = {"run": {**RUN_DEFAULTS, **(run or {})},
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
            else:
                value = getattr(sc, where)
            if value is None:
                lines.append(f"# {key} = ...  # {comment}")
            else:
                lines.append(f"{key} = {_toml(value)}  # {comment}")
        lines.append("")
    return "\n".join(lines)


def _parse_toml(text):
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10
        try:
            import tomli as tomllib
        except ModuleNotFoundError:
            raise ValueError("scenario files need Python 3.11+ or the package tomli") from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"scenario file: not valid TOML ({exc})") from None


def loads(text):
    """Read scenario-file text; returns a :class:`ScenarioFile` (see the module docstring)."""
    data = _parse_toml(text)
    fields, run, detector = {}, dict(RUN_DEFAULTS), dict(DETECTOR_DEFAULTS)
    for section, table in data.items():
        if section not in SECTIONS or not isinstance(table, dict):
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
            else:
                fields[where] = tuple(value) if isinstance(value, list) else value
    try:
        sc = scenarios.MarsScenario(**fields)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"scenario file: {_where(exc)}{exc}") from None
    _check_run(run, sc)
    _check_detector(detector, sc)
    return ScenarioFile(sc, run, detector)


def _where(exc):
    """``[section] key: `` of the field a MarsScenario error names, if one does."""
    name = str(exc).split(" ")[0]
    for (section, key), (where, _) in _KEYS.items():
        if where == name:
            return f"[{section}] {key}: "
    return ""


def _check_run(run, sc):
    check_choice("[run] backend", run["backend"], ("numba", "numpy"))
    check_choice("[run] local_filter", run["local_filter"], ("ekf", "ukf"))
    if run["local_filter"] == "ukf" and run["backend"] != "numpy":
        raise ValueError("scenario file: [run] local_filter = \"ukf\" needs backend = \"numpy\"")
    if run["settle_days"] is not None:
        run["settle_days"] = check_real("[run] settle_days", run["settle_days"], 0.0, sc.days,
                                        hi_open=True)


def _check_detector(det, sc):
    from xnavlab.mars.fault_tolerance import DETECTORS

    check_choice("[detector] name", det["name"], DETECTORS)
    if not isinstance(det["faults"], str):
        raise ValueError(f"[detector] faults must be a fault spec string, got {det['faults']!r}")
    for key in ("pfa", "alpha"):
        det[key] = check_real(f"[detector] {key}", det[key], 0.0, 1.0, lo_open=True,
                              hi_open=True)
    det["rate_per_day"] = check_real("[detector] rate_per_day", det["rate_per_day"], 0.0, 100.0,
                                     lo_open=True)
    if det["train_days"] is not None:
        det["train_days"] = check_real("[detector] train_days", det["train_days"], 0.0, sc.days,
                                       lo_open=True, hi_open=True)
    det["arm_s"] = check_real("[detector] arm_s", det["arm_s"], 0.0, sc.span, hi_open=True)
    if not isinstance(det["adaptive"], bool):
        raise ValueError(f"[detector] adaptive must be true or false, got {det['adaptive']!r}")


def load(path):
    """Read the scenario file at ``path`` (:func:`loads`); a missing file is a ValueError."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise ValueError(f"scenario file {str(path)!r} cannot be read ({exc.strerror})") from None
    return loads(text)


def with_overrides(sf, **fields):
    """A :class:`ScenarioFile` with scenario fields replaced (the command line's overrides)."""
    fields = {k: v for k, v in fields.items() if v is not None}
    return dataclasses.replace(sf, scenario=dataclasses.replace(sf.scenario, **fields))
