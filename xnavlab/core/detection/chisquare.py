"""The baseline innovation chi-square test, with the wavelet detector's onset/end reporting.
"""

from __future__ import annotations

from collections import deque

import numpy as np

from xnavlab.core.detection._tracked import TrackedDetector
from xnavlab.core.detection.limits import MAX_SAMPLES
from xnavlab.core.detection.online import Detection, EventTracker, events_from_alarms
from xnavlab.core.distributions import chi2_isf
from xnavlab.core.validate import (
    check_definite,
    check_finite_array,
    check_increasing,
    check_int,
    check_real,
    check_shape,
)

__all__ = [
    "MAX_DIMENSION",
    "chi2_statistic",
    "chi2_threshold",
    "Chi2Detector",
    "chi2_detect",
]

#: The largest measurement dimension a test takes: no navigation sensor's measurement has more
#: than a thousand components (the chi-square's threshold and the (m, m) covariance both
#: stay cheap below it; 10**30 overflowed numpy's index type).
MAX_DIMENSION = 1000

# --------------------------------------------------------------------------------------------
# Baseline: innovation chi-square test
# --------------------------------------------------------------------------------------------

def chi2_threshold(alpha, dof):
    """``chi2.ppf(1 - alpha, dof)``: the test's threshold for false-alarm probability ``alpha``.

    Examples
    --------
    >>> round(chi2_threshold(0.05, 1), 3)
    3.841
    """
    alpha = check_real("alpha", alpha, 0.0, 1.0, lo_open=True, hi_open=True)
    dof = check_int("dof", dof, 1)
    return chi2_isf(alpha, dof)


def _nis(nu, S):
    nu = check_finite_array("nu", nu)
    if nu.ndim == 1:
        nu = nu[:, None]
    if nu.ndim != 2:
        raise ValueError(f"nu must have shape (N,) or (N, m), got {nu.shape}")
    if nu.size == 0:   # no innovation: no statistic (and S's shape would be judged by nothing)
        raise ValueError(f"nu must hold at least one innovation (N >= 1, m >= 1), got shape {nu.shape}")
    n, m = nu.shape
    S = check_finite_array("S", S)
    square = S.ndim in (2, 3) and S.shape[-1] == S.shape[-2] >= 1
    if square and (S.shape[-1] != m or S.ndim == 3 and S.shape[0] != n):   # a well-formed S: nu is odd
        want = f"(N, {S.shape[-1]})" if S.ndim == 2 else f"({S.shape[0]}, {S.shape[-1]})"
        raise ValueError(f"nu must have shape {want} to match S of shape {S.shape}, got shape {nu.shape}")
    if S.ndim == 1 and m == 1 and nu.shape[0] < S.size:   # lengths disagree: the shorter is named
        raise ValueError(f"nu must have shape ({S.size},) to match S of shape {S.shape}, got shape "
                         f"{nu.shape}")
    if S.ndim == 1 and m != 1 and n == 1 and m == S.size:   # nu a row (1, N) of scalar innovations
        raise ValueError(f"nu must have shape ({S.size},) to match S of shape {S.shape} (the "
                         f"variances of a scalar measurement), got shape {nu.shape}")
    if S.ndim == 1 and m != 1:   # per-sample variances serve a scalar measurement only
        raise ValueError(f"S must have shape (m, m) or (N, m, m) with m = {m}, N = {n} for nu of shape "
                         f"{nu.shape} (variances of shape (N,) only for a scalar measurement), got "
                         f"{S.shape}")
    if S.ndim == 1 and m == 1:
        S = S.reshape(-1, 1, 1)
    if S.shape == (m, m):
        S = np.broadcast_to(S, (n, m, m))
    if S.shape != (n, m, m):
        raise ValueError(f"S must have shape (m, m) or (N, m, m) with m = {m}, N = {n}, got {S.shape}")
    check_definite("S", S, m)  # one line naming S: not symmetric, indefinite or singular
    L = np.linalg.cholesky(S)
    with np.errstate(over="ignore", invalid="ignore"):  # judged below, by name
        y = np.linalg.solve(L, nu[..., None])[..., 0]
        q = np.sum(y * y, axis=-1)                                  # nu^T S^-1 nu
    if not np.all(np.isfinite(q)):  # a subnormal S (1e-320) passes as definite, or nu = 1e200
        i = int(np.argmax(~np.isfinite(q)))
        raise ValueError(_too_large(i, nu[i], S[i]))
    return q, m


def _too_large(i, nu, S):
    """The message refusing sample ``i`` whose statistic passes the float range."""
    return (f"nu is too large against S: nu^T S^-1 nu passes the float range (1.8e308) at "
            f"sample {i} (|nu| up to {float(np.max(np.abs(nu))):.3g}, S's variances down to "
            f"{float(np.min(np.diagonal(S))):.3g})")


def chi2_statistic(nu, S, window=1):
    """Normalised innovation squared ``nu^T S^-1 nu``, summed over a sliding window.

    Under no fault (a consistent filter) the sum over ``window`` samples is chi-square with
    ``m * window`` degrees of freedom (Willsky 1976; Basseville & Nikiforov 1993).

    Parameters
    ----------
    nu : array_like, shape (N, m) or (N,)
        Innovations ``z - h(x_pred)``, measurement unit.
    S : array_like, shape (N, m, m), (m, m) or (N,) for m = 1
        Innovation covariances ``H P H^T + R``.
    window : int
        Samples summed (1: the plain per-sample test), in [1, N] (and at most MAX_SAMPLES).

    Returns
    -------
    stat : ndarray, shape (N,)
        The windowed sum; the first ``window - 1`` values are partial sums.
    dof : int
        ``m * window``.

    Examples
    --------
    >>> stat, dof = chi2_statistic([[1.0, 0.0], [0.0, 2.0]], np.eye(2), window=2)
    >>> stat.tolist(), dof
    ([1.0, 5.0], 4)
    """
    window = check_int("window", window, 1, MAX_SAMPLES)
    q, m = _nis(nu, S)
    if window > q.size:  # no sum would span the window, so none has the dof returned
        raise ValueError(f"window must be an integer in [1, {q.size}] (the samples in nu), "
                         f"got {window}")
    with np.errstate(over="ignore"):
        c = np.cumsum(q)
    if not np.isfinite(c[-1]):  # each finite, their running sum past the float range
        raise ValueError(f"nu is too large against S: the running sum of nu^T S^-1 nu passes "
                         f"the float range (1.8e308) by sample "
                         f"{int(np.argmax(~np.isfinite(c)))}")
    stat = c.copy()
    stat[window:] = c[window:] - c[:-window]
    return stat, m * window


class Chi2Detector(TrackedDetector):
    """Online innovation chi-square detector for one subsystem (the baseline).

    Parameters
    ----------
    m : int
        Measurement dimension, in [1, MAX_DIMENSION].
    alpha : float
        False-alarm probability per decision, default 1e-5 (the wavelet detector's ``pfa``).
    window : int
        Innovations summed per decision (1 by default), in [1, MAX_SAMPLES].
    holdoff : int
        Alarm-free samples before the detector clears (default 1: clears at the first
        consistent innovation).

    Examples
    --------
    >>> det = Chi2Detector(m=1, alpha=1e-3)
    >>> [det.update(float(i), [v], [[1.0]]) for i, v in enumerate([0.5, -1.0, 8.0, 0.2])]
    [False, False, True, False]
    >>> det.events[0].onset, det.events[0].end
    (2.0, 2.0)
    """

    def __init__(self, m, alpha=1e-5, window=1, holdoff=1):
        self.m = check_int("m", m, 1, MAX_DIMENSION)
        self.alpha = check_real("alpha", alpha, 0.0, 1.0, lo_open=True, hi_open=True)
        self.window = check_int("window", window, 1, MAX_SAMPLES)
        self.threshold = chi2_threshold(self.alpha, self.m * self.window)
        self._tracker = EventTracker(holdoff)
        self._q = deque(maxlen=self.window)

    def update(self, t, nu, S):
        """Feed one innovation ``nu`` (m,) with covariance ``S`` (m, m) at time ``t`` (s, after
        the last one fed); return the flag."""
        t = check_real("t", t)
        nu = check_shape("nu", nu, (self.m,), f"one innovation a measurement, m = {self.m}")
        S = check_finite_array("S", S)
        if S.size != self.m * self.m:
            raise ValueError(f"S must have shape ({self.m}, {self.m}), got shape {S.shape}")
        q, _ = _nis(nu[None, :], S.reshape(1, self.m, self.m))
        self._advance_time(t)  # the sample is judged: its time is taken
        self._q.append(float(q[0]))
        if len(self._q) < self.window:
            return False
        total = sum(self._q)
        if total == float("inf"):  # each finite, their window sum past the float range
            self._q.pop()
            raise ValueError("nu is too large against S: the window's sum of nu^T S^-1 nu "
                             "passes the float range (1.8e308)")
        ratio = total / self.threshold
        return self._tracker.update(t, ratio > 1.0, ratio, "chi2")


def chi2_detect(t, nu, S, *, alpha=1e-5, window=1, holdoff=1):
    """Batch innovation chi-square detector; the same decisions as :class:`Chi2Detector`.

    Parameters
    ----------
    t : array_like, shape (N,)
        Sample times, s, strictly increasing.
    nu, S, window
        As in :func:`chi2_statistic`.
    alpha : float
        False-alarm probability per decision.
    holdoff : int
        As in :class:`Chi2Detector`.

    Returns
    -------
    Detection
        With ``data["statistic"]``, ``data["threshold"]`` and ``data["dof"]``.

    Examples
    --------
    >>> nu = np.random.default_rng(5).normal(0.0, 5000.0, 1000)
    >>> nu[600:650] += 40000.0
    >>> res = chi2_detect(3.0 * np.arange(1000), nu, np.full(1000, 5000.0 ** 2))
    >>> res.events[0].onset, res.events[0].end
    (1800.0, 1947.0)
    """
    t = check_finite_array("t", t)
    stat, dof = chi2_statistic(nu, S, window)
    if t.ndim != 1 or t.shape != stat.shape:
        raise ValueError(f"t must have shape ({stat.size},), got {t.shape}")
    check_increasing("t", t)  # else an event would end before its onset
    thr = chi2_threshold(alpha, dof)
    ratio = stat / thr
    armed = np.arange(t.size) >= window - 1
    alarm = armed & (ratio > 1.0)
    events, faulty = events_from_alarms(t, alarm, ratio, holdoff, ["chi2"] * t.size)
    return Detection(t, ratio, alarm, faulty, armed, events,
                     data={"statistic": stat, "threshold": thr, "dof": dof})


