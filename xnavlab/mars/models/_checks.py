"""Plumbing (not public API): the checks the models' epochs and spans share.

Epochs are seconds TDB past J2000, near 5e8 s for the paper's run: a float32 array there
resolves 32 s (and float16 none at all), so such epochs are refused, not converted (the
values given are already rounded: a float64 copy of them would keep the wrong times).
"""

from __future__ import annotations

import numpy as np

from xnavlab.core import dates, ephemeris
from xnavlab.core.constants import DAY
from xnavlab.core.validate import check_choice

__all__ = ["EPOCH_RESOLUTION", "MAX_SPAN_DAYS", "epoch", "epochs", "span", "covered"]

#: :data:`xnavlab.core.ephemeris.EPOCH_RESOLUTION` (1 ms), the one rule of the epochs' dtype.
EPOCH_RESOLUTION = ephemeris.EPOCH_RESOLUTION
#: The longest propagation span, days: two years (more than a Mars year, 687 days). The
#: integrator takes about 0.3 s a day at its default tolerances, so this is about 4 minutes;
#: a span of years (t0 = 0 with epochs in 2016: 16 years) is refused, not run for an hour.
MAX_SPAN_DAYS = 731.0
#: The knots of a third-body table run two steps (of 3600 s) past its end.
_TABLE_MARGIN = 2.0 * 3600.0


def epoch(name, value, lo=-np.inf, hi=np.inf):
    """A scalar epoch, s TDB past J2000, as a float (:func:`xnavlab.core.ephemeris.check_epoch`:
    a float32 one resolving it refused; finite bounds written in full with their dates)."""
    return ephemeris.check_epoch(name, value, lo, hi)


def epochs(name, value):
    """A non-empty 1-D array of epochs as float64 (:func:`xnavlab.core.ephemeris.check_epochs`:
    dates, quantities and a float dtype that cannot resolve them refused: module notes)."""
    t = ephemeris.check_epochs(name, value)
    if t.ndim != 1 or t.size == 0:
        raise ValueError(f"{name} must be a 1-D array of at least one epoch, got shape {t.shape}")
    return t


def span(t0, t_end, ephem=None, name="t_eval"):
    """Refuse a propagation from ``t0`` to ``t_end`` (``name[-1]``) longer than
    :data:`MAX_SPAN_DAYS` or, with ``ephem``, outside its coverage (the table's knots)."""
    if t_end - t0 > MAX_SPAN_DAYS * DAY:
        raise ValueError(f"{name}[-1] - t0 must be at most {MAX_SPAN_DAYS:g} days (the longest "
                         f"propagation), got {(t_end - t0) / DAY:.6g} days (t0 = {t0:.9g} s, "
                         f"{name}[-1] = {t_end:.9g} s)")
    if ephem is not None:
        check_choice("ephem", ephem, ephemeris.EPHEMERIDES)
        lo, hi = ephemeris.coverage(ephem)
        hi -= _TABLE_MARGIN
        if not lo <= t0 <= hi:
            raise ValueError(f"t0 must be in {dates.epoch_range(lo, hi)} (the coverage of {ephem}), "
                             f"got {dates.epoch_text(t0)}")
        if not t_end <= hi:
            raise ValueError(f"{name}[-1] must be at most {dates.epoch_text(hi)} s TDB past J2000 "
                             f"(the coverage of {ephem}), got {dates.epoch_text(t_end)}")


def covered(name, t, ephem):
    """Refuse epochs ``t`` (a float or an array, the user's ``name``) outside ``ephem``'s
    coverage less a third-body table's knots past its end, naming ``name`` (``name[i]``), not
    the table's ``t_start`` or ``t_end``."""
    check_choice("ephem", ephem, ephemeris.EPHEMERIDES)
    lo, hi = ephemeris.coverage(ephem)
    hi -= _TABLE_MARGIN
    arr = np.asarray(t, dtype=float).reshape(-1)
    bad = np.flatnonzero((arr < lo) | (arr > hi))
    if bad.size:
        label = name if np.ndim(t) == 0 else f"{name}[{bad[0]}]"
        raise ValueError(f"{label} must be in {dates.epoch_range(lo, hi)} (the coverage of {ephem}, "
                         f"which tabulates the third bodies), got {dates.epoch_text(arr[bad[0]])}")
