"""Epochs written for people: seconds TDB past J2000 in full, with their calendar date.

The package's epochs are seconds of TDB past J2000 (2000-01-01 12:00:00 TDB), near 5e8 for
the paper's 2016 and up to 6.3e9 at the end of DE421. A message that writes such an epoch at
six digits (``6.31407e+09``) can show a value and the bound it broke as the same number: the
refusals of epochs outside an ephemeris write them with :func:`epoch_text` instead, every
digit of the whole seconds (and the decimals the value has, to 1 ms) and the date.

TT and TDB differ by under 2 ms and neither has leap seconds, so the calendar date is the
uniform count of days from J2000 (no leap-second table is involved).
"""

import datetime as _dt
import math

import numpy as np

from xnavlab.core.validate import check_real

__all__ = ["DATED", "J2000_DATE", "epoch_date", "epoch_range", "epoch_text"]

#: The origin of the package's epochs, 2000-01-01 12:00:00 TDB.
J2000_DATE = _dt.datetime(2000, 1, 1, 12)
#: The epochs a calendar date can be written for (the years 1 to 9999), s TDB past J2000.
DATED = tuple((d - J2000_DATE).total_seconds() for d in (_dt.datetime.min, _dt.datetime(9999, 12, 31)))


def epoch_date(t):
    """Calendar date of an epoch ``t`` (s TDB past J2000), ISO text to the second, TDB.

    Parameters
    ----------
    t : float
        Epoch, s TDB past J2000, in :data:`DATED` (the years 1 to 9999).

    Returns
    -------
    str
        ``YYYY-MM-DDTHH:MM:SS`` (TDB).

    Examples
    --------
    >>> epoch_date(0.0), epoch_date(504878400.0)
    ('2000-01-01T12:00:00', '2016-01-01T00:00:00')
    """
    t = check_real("t", t, *DATED)
    return (J2000_DATE + _dt.timedelta(seconds=round(t))).isoformat()


def epoch_text(t, name="t"):
    """An epoch for a message: every digit of its seconds (to 1 ms) and its date.

    Parameters
    ----------
    t : float
        Epoch, s TDB past J2000 (a NaN or an infinity is written as Python writes it).
    name : str
        The parameter named when ``t`` is no real number.

    Returns
    -------
    str
        ``"<seconds> (<date> TDB)"``; the seconds without an exponent, their decimals only as
        far as the value has them (at most 3); a value that is no finite epoch of years 1 to
        9999 as Python writes it.

    Examples
    --------
    >>> epoch_text(6314068800.0)
    '6314068800 (2200-02-01T00:00:00 TDB)'
    >>> epoch_text(6314067927.36)
    '6314067927.36 (2200-01-31T23:45:27 TDB)'
    """
    if isinstance(t, float | np.floating) and not math.isfinite(t):
        return repr(float(t))
    t = check_real(name, t) + 0.0  # -0.0 written as 0
    if not DATED[0] <= t <= DATED[1]:
        return repr(t)
    date = epoch_date(t)
    seconds = f"{t:.3f}".rstrip("0").rstrip(".")
    return f"{seconds} ({date} TDB)"


def epoch_range(lo, hi):
    """A range of epochs for a message: ``"[<lo>, <hi>] s TDB past J2000"``, each end as
    :func:`epoch_text` writes it.

    Examples
    --------
    >>> epoch_range(0.0, 86400.5)
    '[0 (2000-01-01T12:00:00 TDB), 86400.5 (2000-01-02T12:00:00 TDB)] s TDB past J2000'
    """
    return f"[{epoch_text(lo, 'lo')}, {epoch_text(hi, 'hi')}] s TDB past J2000"
