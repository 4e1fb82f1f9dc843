"""From residuals to a verdict: fault tables, decision rules and the threshold logic.

The fault tables say which residuals each single fault drives over its threshold:
:data:`SOS_TABLE` (paper Table 1, reconstructed) and the structured-residual table of the
DOS bank, :data:`DOS_TABLE`. The decision rules turn the set of crossed residuals into a
verdict, one of :data:`VERDICTS`: :func:`sos_decide` (paper Table 2, reconstructed),
:func:`dos_decide` and :func:`qdiff_decide` (ref. [22]). :func:`diagnose` is the threshold
logic the three methods share (persistence, arming, confirmation window) and returns a
:class:`Diagnosis`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from xnavlab.attitude.sensors import LOCATIONS
from xnavlab.core.validate import (
    check_callable,
    check_finite_array,
    check_increasing,
    check_int,
    check_real,
    check_vector,
)

__all__ = [
    "VERDICTS",
    "SOS_TABLE",
    "DOS_TABLE",
    "sos_decide",
    "dos_decide",
    "qdiff_decide",
    "Diagnosis",
    "diagnose",
]

#: Every verdict of :func:`sos_decide` and :func:`dos_decide`.
VERDICTS = ("none",) + LOCATIONS + ("unknown",)

#: Paper Table 1 (reconstructed) for SOS: which residuals (r1, r2, r3, r4) each fault
#: drives over its threshold. ``None``: may cross; a star-tracker fault moves at least
#: one of r1-r3 and never the gyro parity r4.
SOS_TABLE = {
    "gyro_x": (True, False, False, True),
    "gyro_y": (False, True, False, True),
    "gyro_z": (False, False, True, True),
    "gyro_skew": (False, False, False, True),
    "star_tracker": (None, None, None, False),
}

#: DOS structured-residual table: residuals (R1..R4) that each fault moves.
DOS_TABLE = {
    "gyro_x": (False, True, True, True),
    "gyro_y": (True, False, True, True),
    "gyro_z": (True, True, False, True),
    "gyro_skew": (True, True, True, False),
    "star_tracker": (True, True, True, True),
}


# ------------------------------------------------------------- decision rules


def sos_decide(crossed):
    """SOS decision rule (paper Table 2, reconstructed) from the crossed residuals.

    ===================  ================================
    r4 crossed, and      diagnosis
    ===================  ================================
    none of r1-r3        ``"gyro_skew"``
    exactly r_i          ``"gyro_x"``, ``"gyro_y"``, ``"gyro_z"``
    two or more          ``"unknown"`` (not a single fault)
    ===================  ================================

    r4 not crossed: ``"star_tracker"`` if any of r1-r3 crossed, else ``"none"``.

    Parameters
    ----------
    crossed : array_like of bool, shape (..., 4)
        Which of r1..r4 exceeded their thresholds.

    Returns
    -------
    str or ndarray of str, shape (...)

    Examples
    --------
    >>> sos_decide([True, False, False, True]), sos_decide([False, True, True, False])
    ('gyro_x', 'star_tracker')
    """
    c = _bool_flags("crossed", crossed, 4)
    n13 = c[..., :3].sum(-1)
    which = np.array(["gyro_x", "gyro_y", "gyro_z"])[np.argmax(c[..., :3], axis=-1)]
    r4 = c[..., 3]
    out = np.select(
        [r4 & (n13 == 0), r4 & (n13 == 1), r4, n13 > 0],
        ["gyro_skew", which, "unknown", "star_tracker"],
        "none",
    )
    return out.item() if out.ndim == 0 else out


def dos_decide(crossed):
    """DOS decision rule (structured residuals, :data:`DOS_TABLE`).

    All four residuals crossed: ``"star_tracker"``; exactly three: the gyro excluded
    from the one quiet filter; one or two: ``"unknown"``; none: ``"none"``.

    Parameters
    ----------
    crossed : array_like of bool, shape (..., 4)

    Returns
    -------
    str or ndarray of str, shape (...)

    Examples
    --------
    >>> dos_decide([False, True, True, True]), dos_decide([True, True, True, True])
    ('gyro_x', 'star_tracker')
    """
    c = _bool_flags("crossed", crossed, 4)
    n = c.sum(-1)
    quiet = np.array(LOCATIONS[:4])[np.argmin(c, axis=-1)]
    out = np.select([n == 4, n == 3, n > 0], ["star_tracker", quiet, "unknown"], "none")
    return out.item() if out.ndim == 0 else out


def qdiff_decide(crossed):
    """Verdict of the quaternion-differentiation method: the gyros whose estimate crossed.

    Parameters
    ----------
    crossed : array_like of bool, shape (..., 3)

    Returns
    -------
    str or ndarray of str: ``"none"`` or the blamed gyros joined by ``"+"``.

    Examples
    --------
    >>> qdiff_decide([True, False, True])
    'gyro_x+gyro_z'
    """
    c = _bool_flags("crossed", crossed, 3)
    names = np.array(["gyro_x", "gyro_y", "gyro_z"])
    flat = c.reshape(-1, 3)
    out = np.array(["+".join(names[row]) or "none" for row in flat], dtype=object)
    out = out.reshape(c.shape[:-1])
    return out.item() if out.ndim == 0 else out


def _bool_flags(name, flags, n):
    if np.ma.is_masked(flags):  # np.asarray would use the masked flags (review 35m (5) 1)
        raise ValueError(f"{name} has masked entries (no flag to use: fill or drop them)")
    try:
        arr = np.asarray(flags)
    except (TypeError, ValueError):
        arr = None
    if arr is None or arr.dtype != bool or arr.shape[-1:] != (n,):
        raise ValueError(f"{name} must be a boolean array of shape (..., {n})")
    return arr


# ------------------------------------------------------------ threshold logic


@dataclass(frozen=True, eq=False)
class Diagnosis:
    """Output of :func:`diagnose` (leading batch shape ``...``).

    Its fields are checked when it is made (a copy edited with ``dataclasses.replace``
    too): one ValueError naming ``Diagnosis.<field>`` (review 35p P11: a cut or missing field
    reached the plots as numpy's IndexError).

    Attributes
    ----------
    flags : ndarray of bool, shape (..., n, m)
        Residual over its threshold for ``persist`` consecutive armed samples.
    detect_time : ndarray, shape (...)
        First flagged sample time, s; ``inf`` when nothing was detected.
    crossed : ndarray of bool, shape (..., m)
        Residuals flagged within ``confirm_s`` of the detection.
    verdict : str or ndarray of str, shape (...)
        The decision rule applied to ``crossed``.

    Examples
    --------
    >>> d = diagnose(np.arange(5.0), np.ones((5, 4)), np.zeros(4), persist=1)
    >>> float(d.detect_time), d.verdict, d.flags.shape
    (0.0, 'unknown', (5, 4))
    """

    flags: np.ndarray
    detect_time: np.ndarray
    crossed: np.ndarray
    verdict: object

    def __post_init__(self):
        flags = _field_bools("flags", self.flags, "(..., n, m)")
        if flags.ndim < 2:
            raise ValueError(f"Diagnosis.flags must have shape (..., n, m), got shape {flags.shape}")
        lead, m = flags.shape[:-2], flags.shape[-1]
        object.__setattr__(self, "flags", flags)
        crossed = _field_bools("crossed", self.crossed, str(lead + (m,)))
        if crossed.shape != lead + (m,):
            raise ValueError(f"Diagnosis.crossed must have shape {lead + (m,)} (one flag a residual "
                             f"of flags {flags.shape}), got shape {crossed.shape}")
        object.__setattr__(self, "crossed", crossed)
        det = self.detect_time
        try:
            arr = np.asarray(det, dtype=float)
        except (TypeError, ValueError):
            arr = None
        if (arr is None or isinstance(det, bool | str | bytes) or arr.shape != lead
                or np.isnan(arr).any() or (arr == -math.inf).any()):
            raise ValueError(f"Diagnosis.detect_time must be a time, s, or inf (none), shape {lead} "
                             f"(of flags {flags.shape}), got {det!r:.80}")
        object.__setattr__(self, "detect_time", np.float64(arr) if lead == () else arr)
        verdict = self.verdict
        if lead == ():
            ok = isinstance(verdict, str)
        else:
            v = np.asarray(verdict) if isinstance(verdict, np.ndarray) else None
            ok = v is not None and v.shape == lead and all(isinstance(x, str) for x in v.flat)
        if not ok:
            want = "a str" if lead == () else f"an array of str of shape {lead}"
            raise ValueError(f"Diagnosis.verdict must be {want} (a verdict of the decision rule), "
                             f"got {verdict!r:.80}")


def _field_bools(name, value, shape):
    """A Diagnosis field of flags as a boolean array, else one ValueError naming it."""
    arr = value if isinstance(value, np.ndarray) else None
    if arr is None or arr.dtype != bool:
        raise ValueError(f"Diagnosis.{name} must be a boolean array of shape {shape}, got "
                         f"{value!r:.80}")
    return arr


def _broadcasts_to(shape, target):
    try:
        return np.broadcast_shapes(shape, target) == target
    except ValueError:
        return False


def diagnose(t, residuals, thresholds, *, t_arm=0.0, persist=3, confirm_s=5.0, decide=sos_decide):
    """Threshold logic shared by SOS, DOS and ref. [22].

    A residual is *flagged* at a sample once it has exceeded its threshold for
    ``persist`` consecutive samples at or after ``t_arm``. The first flag is the
    detection; the residuals flagged within ``confirm_s`` seconds after it are the
    *crossed* set, which ``decide`` turns into a verdict (so a residual that lags the
    first one, as a drift estimate lags the gyro parity, still counts).

    Parameters
    ----------
    t : array_like, shape (n,)
        Sample times, s, strictly increasing.
    residuals : array_like, shape (..., n, m)
    thresholds : array_like, shape (..., m)
        Its leading axes broadcast to the residuals' ``...`` (one verdict a run).
    t_arm : float
        No flag before this time, s, at most ``t[-1]`` (a later one would flag nothing).
    persist : int
        Consecutive samples over the threshold needed, >= 1.
    confirm_s : float
        Isolation window after the detection, s, in [0, 86400] (as :class:`~.simulation.SimConfig`'s).
    decide : callable
        ``crossed (..., m) -> verdict`` (:func:`sos_decide`, :func:`dos_decide`,
        :func:`qdiff_decide`).

    Returns
    -------
    Diagnosis

    Examples
    --------
    >>> t = np.arange(10.0); r = np.zeros((10, 4)); r[5:, [0, 3]] = 2.0
    >>> d = diagnose(t, r, np.ones(4), persist=2, confirm_s=1.0)
    >>> float(d.detect_time), d.verdict
    (6.0, 'gyro_x')
    """
    t = check_vector("t", t)
    if t.size == 0:
        raise ValueError("t must hold at least one sample time, got an empty array")
    r = check_finite_array("residuals", residuals)
    if r.ndim < 2:
        raise ValueError(f"residuals must have shape (..., n, m), got {r.shape}")
    if r.shape[-2] != t.size:  # both well formed: the times are the ones to match the series
        raise ValueError(f"t must hold one time per sample of the residuals (n = {r.shape[-2]}), "
                         f"got {t.size}")
    check_increasing("t", t)  # the detection time is the first flag's
    J = check_finite_array("thresholds", thresholds, shape=(r.shape[-1],))
    lead = r.shape[:-2]
    if not _broadcasts_to(J.shape[:-1], lead):  # else the verdict would gain axes
        raise ValueError(f"thresholds must have shape (..., {r.shape[-1]}) whose leading axes "
                         f"broadcast to the residuals' {lead}, got {J.shape}")
    if np.any(J < 0.0):  # the residuals are absolute values: a negative threshold flags every sample
        raise ValueError(f"thresholds must be >= 0 (the residuals are absolute values), got "
                         f"{float(np.min(J)):g}")
    # an arming time after the last sample flags nothing: detect_time inf, as a healthy run's
    t_arm = check_real("t_arm", t_arm, hi=float(t[-1]))
    persist = check_int("persist", persist, 1, t.size)
    confirm_s = check_real("confirm_s", confirm_s, 0.0, 86400.0)  # as SimConfig's
    check_callable("decide", decide, "a verdict function such as sos_decide")
    over = (r > J[..., None, :]) & (t >= t_arm)[:, None]
    c = np.cumsum(over, axis=-2)
    lagged = np.concatenate([np.zeros_like(c[..., :persist, :]), c[..., :-persist, :]], -2)
    flags = (c - lagged) >= persist
    anyf = flags.any(-1)
    det = np.where(anyf.any(-1), np.argmax(anyf, axis=-1), -1)
    detect_time = np.where(det >= 0, t[np.maximum(det, 0)], math.inf)
    in_win = (t >= detect_time[..., None]) & (t <= detect_time[..., None] + confirm_s)
    crossed = (flags & in_win[..., None]).any(-2)
    return Diagnosis(flags, detect_time, crossed, decide(crossed))
