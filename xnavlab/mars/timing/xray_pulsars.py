"""The X-ray side of navigation pulsars: a small table of flux, pulsed fraction and pulse width.

A radio timing model (a ``.par`` file) gives a pulsar's position, distance and spin, but not
what an X-ray detector sees: the photon flux, the fraction of it that is pulsed and the pulse
width. ``xnavlab/data/xray_pulsars.csv`` holds them for ten pulsars from Sheikh et al. (2006,
Table 1; the file's header says how each row was read); :func:`xnavlab.mars.timing.pulsars.from_par`
takes them from here and refuses a pulsar that is neither here nor given them, naming what is
missing. Units as the literature's: flux in ph/cm^2/s (2-10 keV), width (FWHM) in s.

Examples
--------
>>> row = lookup("J0437-4715")
>>> row["flux_ph_cm2_s"], row["pulsed_fraction"], row["width_s"]
(6.65e-05, 0.275, 0.00029)
>>> lookup("J1939+2134")["name"]        # B1937+21 by its J2000 name
'B1937+21'
>>> lookup("J1614-2230") is None
True
"""

from __future__ import annotations

import functools
from importlib import resources
from types import MappingProxyType

from xnavlab.core.userfiles import csv_rows
from xnavlab.core.validate import check_text

__all__ = ["SOURCE", "TABLE_FILE", "FIELDS", "table", "lookup", "names"]

#: Where the values come from.
SOURCE = "Sheikh et al. 2006, Table 1 (xnavlab/data/xray_pulsars.csv)"
#: The table, relative to the package.
TABLE_FILE = "data/xray_pulsars.csv"
#: The X-ray fields a timing model lacks, in the units of the table.
FIELDS = ("flux_ph_cm2_s", "pulsed_fraction", "width_s")


@functools.cache
def table():
    """Every row, keyed by name: ``name``, ``aliases`` (tuple), ``period_s``, ``width_s``,
    ``flux_ph_cm2_s``, ``pulsed_fraction``, ``source``.

    Read once: the table and its rows are read-only mappings (``types.MappingProxyType``), so
    that no caller's edit reaches every later :func:`xnavlab.mars.timing.pulsars.from_par`;
    ``dict(row)`` gives an editable copy.

    Examples
    --------
    >>> len(table()), table()["B0531+21"]["aliases"]
    (10, ('J0534+2200',))
    >>> table()["B0531+21"]["flux_ph_cm2_s"] = 1.0
    Traceback (most recent call last):
    ...
    TypeError: 'mappingproxy' object does not support item assignment
    """
    text = resources.files("xnavlab").joinpath(TABLE_FILE).read_text("utf-8")
    rows = {}
    for cells in csv_rows(text, TABLE_FILE, ("period_s", "width_s", "flux_ph_cm2_s",
                                             "pulsed_fraction")):
        if cells["name"] in rows:
            raise ValueError(f"{TABLE_FILE}: pulsar {cells['name']} is listed twice")
        rows[cells["name"]] = MappingProxyType({
            "name": cells["name"], "aliases": tuple(cells["aliases"].split()),
            "period_s": cells["period_s"], "width_s": cells["width_s"],
            "flux_ph_cm2_s": cells["flux_ph_cm2_s"],
            "pulsed_fraction": cells["pulsed_fraction"], "source": SOURCE,
        })
    return MappingProxyType(rows)


@functools.cache
def _index():
    out = {}
    for name, row in table().items():
        for key in (name, *row["aliases"]):
            out[_norm(key)] = row
    return out


def _norm(name):
    name = str(name).strip().upper()
    return name[3:].strip() if name.startswith("PSR") else name


def lookup(name):
    """The table's row for a pulsar named ``name`` (or an alias; a ``PSR`` prefix is ignored),
    else ``None``: a read-only mapping (:func:`table`).

    Examples
    --------
    >>> lookup("PSR B1821-24")["width_s"]
    5.5e-05
    """
    return _index().get(_norm(check_text("name", name)))  # a bool or a list is no name


def names():
    """The table's pulsars, by their first name.

    Examples
    --------
    >>> names()[:2]
    ['B0531+21', 'B1937+21']
    """
    return list(table())
