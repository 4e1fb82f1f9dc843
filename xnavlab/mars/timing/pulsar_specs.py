"""A scenario's pulsars: by catalogue name, by timing model, or by a table of their properties.

:class:`xnavlab.mars.navigation.scenarios.MarsScenario` takes ``pulsars`` as a list whose items are any of

a catalogue name
    ``"B0531+21"`` (:data:`xnavlab.mars.timing.pulsars.CATALOGUE`: the main paper's four).
a timing model
    the path of a ``.par`` file (:func:`xnavlab.mars.timing.pulsars.get`): position, distance and
    spin from the model, the X-ray properties from the table of
    :mod:`xnavlab.mars.timing.xray_pulsars`; a pulsar not in that table is refused, naming what is
    missing.
a table (a dict; in a scenario file an inline table)
    ``{par = "J1614.par", flux_ph_cm2_s = 1e-5, pulsed_fraction = 0.5, width_s = 1e-4,
    distance_m = 2e19}``: a timing model with the X-ray properties (and, for a model without a
    parallax, the distance) given, each overriding the table's; or every field of a
    :class:`~xnavlab.mars.timing.pulsars.Pulsar` without a timing model: ``{name, ra_deg, dec_deg,
    distance_m, period_s, fdot_hz_s, flux_ph_cm2_s, pulsed_fraction, width_s}``, in the ranges
    of :class:`~xnavlab.mars.timing.pulsars.Pulsar` and
    :func:`~xnavlab.mars.timing.pulsars.from_par`: ``distance_m`` in [1 pc, 1 Mpc],
    ``period_s`` in [1e-4, 100], ``fdot_hz_s`` in [-1, 1], ``flux_ph_cm2_s`` in [1e-12, 1e3],
    ``pulsed_fraction`` in [1e-6, 1], ``width_s`` in [1e-4, 0.5] times the period.
a :class:`~xnavlab.mars.timing.pulsars.Pulsar`
    from Python.

:func:`check_list` normalises a list (a table becomes its Pulsar, a path an absolute path) and
refuses, one line each: a string where a list belongs, an empty list, an item of another type,
an unknown name and a pulsar listed twice (by name or by direction). :func:`to_json` and
:func:`to_toml` write an item back so that it reads the same; :func:`fault_names` gives each
pulsar's name in the fault grammar (``xnav.B1937``, ``xnav.J0030``).

Examples
--------
>>> check_list(["B0531+21", "B1937+21"])
('B0531+21', 'B1937+21')
>>> check_list("B0531+21")
Traceback (most recent call last):
...
ValueError: pulsars must be a list of pulsars, got the string 'B0531+21' (write ["B0531+21"])
>>> check_list(["B0531+21", "B0531+21"])
Traceback (most recent call last):
...
ValueError: pulsars lists B0531+21 twice (items 0 and 1)
>>> fault_names(["B0531+21", "B1937+21"])
('B0531', 'B1937')
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from xnavlab.core.constants import KPC
from xnavlab.core.validate import check_real, shown
from xnavlab.mars.timing import pulsars

__all__ = ["PAR_KEYS", "ENTRY_KEYS", "resolve", "check_list", "names", "fault_names", "to_json",
           "to_toml"]

#: Keys of a table that names a timing model (``par`` required, the others optional).
PAR_KEYS = ("par", "flux_ph_cm2_s", "pulsed_fraction", "width_s", "distance_m")
#: Keys of a table that gives a pulsar without a timing model (all required).
ENTRY_KEYS = ("name", "ra_deg", "dec_deg", "distance_m", "period_s", "fdot_hz_s", "flux_ph_cm2_s",
              "pulsed_fraction", "width_s")
_PER_CM2 = 1.0e4  # ph/cm^2/s -> ph/m^2/s


def _from_table(spec, base):
    keys = set(spec)
    if "par" in keys:
        bad = sorted(keys - set(PAR_KEYS))
        if bad:
            raise ValueError(f"a pulsar table with a par has no key {bad[0]!r} "
                             f"(keys: {', '.join(PAR_KEYS)})")
        if not isinstance(spec["par"], str | Path) or not str(spec["par"]).strip():
            raise ValueError(f"par must be the path of a .par file (a string), "
                             f"got {shown(spec['par'])}")  # a number is no file name
        path = Path(spec["par"]).expanduser()
        if base is not None and not path.is_absolute():
            path = Path(base) / path
        if not path.is_file():
            raise ValueError(f"par names no timing model (.par) file: {str(path)!r}")
        return pulsars.from_par(path, distance=spec.get("distance_m"),
                                flux_ph_cm2_s=spec.get("flux_ph_cm2_s"),
                                pulsed_fraction=spec.get("pulsed_fraction"),
                                width_s=spec.get("width_s"))
    missing = [k for k in ENTRY_KEYS if k not in keys]
    bad = sorted(keys - set(ENTRY_KEYS))
    if bad:
        raise ValueError(f"a pulsar table has no key {bad[0]!r} (a timing model: par, "
                         f"{', '.join(PAR_KEYS[1:])}; or every one of {', '.join(ENTRY_KEYS)})")
    if missing:
        raise ValueError(f"a pulsar table without a par needs {', '.join(missing)} "
                         f"(or give par = its timing model)")
    name = spec["name"]
    if not isinstance(name, str) or not name.strip():
        raise ValueError(f"name must be a non-empty string, got {name!r}")
    period = check_real("period_s", spec["period_s"], 1e-4, 100.0)
    src = "scenario table"
    return pulsars.Pulsar(
        name=name.strip(), ra_deg=check_real("ra_deg", spec["ra_deg"], 0.0, 360.0, hi_open=True),
        dec_deg=check_real("dec_deg", spec["dec_deg"], -90.0, 90.0),
        distance=check_real("distance_m", spec["distance_m"], KPC / 1e3, 1e3 * KPC),
        period=period, fdot=check_real("fdot_hz_s", spec["fdot_hz_s"], -1.0, 1.0),
        flux=check_real("flux_ph_cm2_s", spec["flux_ph_cm2_s"], 1e-12, 1e3) * _PER_CM2,
        pulsed_fraction=check_real("pulsed_fraction", spec["pulsed_fraction"], 1e-6, 1.0),
        width=check_real("width_s", spec["width_s"], 1e-4 * period, 0.5 * period),
        sources=dict.fromkeys(("ra_deg", "dec_deg", "distance", "period", "fdot", "flux",
                               "pulsed_fraction", "width"), src))


def resolve(spec, base=None):
    """The :class:`~xnavlab.mars.timing.pulsars.Pulsar` of one item (module notes).

    Parameters
    ----------
    spec : str, dict or Pulsar
    base : str or os.PathLike, optional
        Folder a relative ``.par`` path is read from (a scenario file's own folder); ignored
        for an item without one (a catalogue name, a Pulsar, a table without ``par``), as for
        the items of a scenario file's list. Anything but a non-empty path or None is refused.

    Examples
    --------
    >>> resolve("B1957+20").name
    'B1957+20'
    >>> resolve({"name": "X", "ra_deg": 10.0, "dec_deg": 5.0, "distance_m": 3e19,
    ...          "period_s": 0.005, "fdot_hz_s": 0.0, "flux_ph_cm2_s": 1e-5,
    ...          "pulsed_fraction": 0.5, "width_s": 5e-4}).duty_cycle
    0.1
    """
    base = _check_base(base)
    if isinstance(spec, pulsars.Pulsar):
        return spec
    if isinstance(spec, dict):
        return _from_table(spec, base)
    if isinstance(spec, str):
        if base is not None and spec.strip().lower().endswith(".par"):
            path = Path(spec).expanduser()
            spec = str(path if path.is_absolute() else Path(base) / path)
        return pulsars.get(spec)
    raise ValueError(f"a pulsar must be a catalogue name, the path of a .par file or a table, "
                     f"got {spec!r}")


def _check_base(base):
    """``base`` as None or a non-empty path (str or os.PathLike), else one ValueError naming it
    (nan, -1, [] or True were accepted unchecked where no ``.par`` path used them)."""
    if base is None:
        return None
    if not isinstance(base, str | os.PathLike) or not str(os.fspath(base)).strip():
        raise ValueError(f"base must be a folder (a non-empty str or os.PathLike) or None, got {shown(base)}")
    return base


def _normal(spec, base):
    """The item as the scenario keeps it: a name, an absolute .par path, or a Pulsar."""
    if isinstance(spec, dict):
        return _from_table(spec, base)
    if isinstance(spec, str) and spec.strip().lower().endswith(".par"):
        path = Path(spec.strip()).expanduser()
        if base is not None and not path.is_absolute():
            path = Path(base) / path
        return str(path.resolve())
    return spec


#: from_par's parameters -> the keys of a pulsar table that give them.
_TABLE_KEY = {"distance": "distance_m", **{k: k for k in (*PAR_KEYS, *ENTRY_KEYS)}}


def _item_words(text, item, spec):
    """A message about one item in the list's words: ``pulsars[0]: ...``, a table's key as
    ``pulsars[0]['width_s'] ...``, never from_par's ``path`` or ``distance``."""
    text = text.removeprefix("path: ")
    first = text.split(" ")[0]
    if isinstance(spec, dict) and first in _TABLE_KEY:
        return f"{item}[{_TABLE_KEY[first]!r}]{text[len(first):]}"
    return f"{item}: {text}"


def check_list(specs, base=None, name="pulsars"):
    """A checked, normalised tuple of pulsar items (module notes); one ``ValueError`` a fault.

    Parameters
    ----------
    specs : sequence
        The items.
    base : str or os.PathLike, optional
        Folder of relative ``.par`` paths (ignored by the items without one; anything but a
        non-empty path or None is refused).
    name : str
        The parameter's name in messages.

    Returns
    -------
    tuple
        Catalogue names and absolute ``.par`` paths as strings, tables as Pulsars.
    """
    base = _check_base(base)
    if isinstance(specs, str):
        raise ValueError(f"{name} must be a list of pulsars, got the string {specs!r} "
                         f"(write [\"{specs}\"])")
    if isinstance(specs, dict | pulsars.Pulsar) or not hasattr(specs, "__iter__"):
        raise ValueError(f"{name} must be a list of pulsars, got {specs!r}")
    specs = list(specs)
    if not specs:
        raise ValueError(f"{name} must name at least one pulsar, got an empty list")
    out, seen = [], {}
    for i, spec in enumerate(specs):
        if not isinstance(spec, str | dict | pulsars.Pulsar):
            raise ValueError(f"{name}[{i}] must be a catalogue name, the path of a .par file or "
                             f"a table, got {spec!r}")
        try:
            norm = _normal(spec, base)
            p = resolve(norm)
        except ValueError as exc:
            raise ValueError(_item_words(str(exc), f"{name}[{i}]", spec)) from None
        key = p.name
        n = p.direction
        for j, (other, d) in seen.items():
            if other == key or float(np.dot(n, d)) > math.cos(1e-6):
                raise ValueError(f"{name} lists {key} twice (items {j} and {i})")
        seen[i] = (key, n)
        out.append(norm)
    return tuple(out)


def names(specs):
    """The pulsars' names, in order; ``specs`` checked as :func:`check_list` does (None, a
    string or a repeat is one ValueError).

    Examples
    --------
    >>> names(["B0531+21"])
    ('B0531+21',)
    """
    return tuple(resolve(s).name for s in check_list(specs))


def fault_names(specs):
    """Each pulsar's component name in the fault grammar: its name up to a ``+`` or ``-``
    (``B1937``, ``J0030``), or the whole name where two would be the same.

    Examples
    --------
    >>> fault_names(["B1937+21", "B1957+20"])
    ('B1937', 'B1957')
    """
    full = names(specs)
    short = tuple(n.split("+")[0].split("-")[0] for n in full)
    return tuple(f if short.count(s) > 1 else s for s, f in zip(short, full, strict=True))


def _per_cm2(flux):
    """``flux`` (ph/m^2/s) in ph/cm^2/s, the float that gives ``flux`` back times 1e4."""
    y = flux / _PER_CM2
    for c in (y, np.nextafter(y, np.inf), np.nextafter(y, -np.inf)):
        if float(c) * _PER_CM2 == flux:
            return float(c)
    return y  # pragma: no cover - no neighbour maps back (not met)


def to_json(spec):
    """A JSON-ready form of an item: the string itself, or the table of a Pulsar
    (:data:`ENTRY_KEYS`).

    Examples
    --------
    >>> to_json("B0531+21")
    'B0531+21'
    >>> sorted(to_json(pulsars.get("B1937+21")))[:3]
    ['dec_deg', 'distance_m', 'fdot_hz_s']
    """
    if isinstance(spec, str):
        return spec
    p = resolve(spec)
    return {"name": p.name, "ra_deg": p.ra_deg, "dec_deg": p.dec_deg, "distance_m": p.distance,
            "period_s": p.period, "fdot_hz_s": p.fdot, "flux_ph_cm2_s": _per_cm2(p.flux),
            "pulsed_fraction": p.pulsed_fraction, "width_s": p.width}


def to_toml(spec):
    """An item as TOML: a quoted string, or an inline table that :func:`resolve` reads back.

    Examples
    --------
    >>> to_toml("B0531+21")
    '"B0531+21"'
    """
    import json

    value = to_json(spec)
    if isinstance(value, str):
        return json.dumps(value)
    return "{" + ", ".join(f"{k} = {json.dumps(v) if isinstance(v, str) else repr(float(v))}"
                           for k, v in value.items()) + "}"
