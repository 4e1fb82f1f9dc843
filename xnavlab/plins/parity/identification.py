"""Fault identification: fault models, onset search and the random-walk Kalman filter.

With the fault of sensor ``j`` in the window written ``M_j(k) theta_j``
(:func:`fault_signature`, paper eq. 23), ``r_j(k) = V_j^T M_j(k) theta_j + V_j^T eps_j``
(eq. 24); the parameters ``theta_j`` are a random walk (eq. 28) estimated by a Kalman
filter (eq. 27: :func:`rw_predict`, :func:`rw_update`, :class:`FaultIdentifier`,
:func:`kf_identify`), as in Song & Zhang (2002, 2003). :func:`identify_fault` runs it over
the windows of one sensor.

A fault that is **constant inside the window** (the paper's eq. 23, ``M = 1``) is *not*
identifiable: ``1`` lies in the range of ``H_0`` because the pseudolite equivalent error
(the receiver clock) enters every sample of every pseudorange alike, so ``V^T 1 = 0`` for
every parity vector (constraint 2 fails for every window length). What the residual sees
is the fault's *change* inside the window; we identify the fault from the windows that
straddle its onset, with the onset located by a likelihood-ratio search
(:func:`estimate_onset`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from xnavlab.core import faults as _faults
from xnavlab.core.validate import (
    check_choice,
    check_covariance,
    check_finite_array,
    check_increasing,
    check_int,
    check_real,
    check_shape,
    check_vector,
    shown,
)
from xnavlab.plins import pseudolites as _pl

__all__ = [
    "MODELS",
    "SIGMA_MIN",
    "fault_signature",
    "estimate_onset",
    "rw_predict",
    "rw_update",
    "FaultIdentifier",
    "kf_identify",
    "Identification",
    "identify_fault",
]

#: Fault models for identification: ``"bias"`` is constant inside the window (paper
#: eq. 23), ``"step"`` a step at an onset, ``"ramp"`` ``f = a t + b`` from an onset.
MODELS = ("bias", "step", "ramp")

#: Smallest pseudorange noise taken, m: a micrometre is far below any code or carrier ranging
#: noise, and its square (the residual variance) stays a normal float (a subnormal ``sigma``
#: squares to 0, a singular residual covariance).
SIGMA_MIN = 1e-6


def _nonempty(name, value, what):
    """``value`` as a finite 1-D array of at least one entry, else one ValueError naming it."""
    arr = check_vector(name, value)
    if arr.size == 0:
        raise ValueError(f"{name} must hold at least one {what}, got an empty array")
    return arr


def _series(t, z_j, W_j):
    """``t`` (n,), ``z_j`` (n,) and ``W_j`` (n, s+1, q), each named when it disagrees with the
    ones checked before it."""
    t = _nonempty("t", t, "sample time")
    check_increasing("t", t)  # the windows and the onset search read t in order
    z_j = check_vector("z_j", z_j)
    if len(z_j) > len(t):  # two well-formed series: the shorter one is named (cut short)
        raise ValueError(f"t must hold one time per sample of z_j (n = {len(z_j)}), got {len(t)}")
    z_j = check_shape("z_j", z_j, (len(t),), "n = len(t)")
    W_j = check_shape("W_j", W_j, (len(t), None, None), "n = len(t) window ends")
    return t, z_j, W_j


def fault_signature(t_window, model, onset=0.0, time_origin="absolute"):
    """Fault signature ``M`` in a window: the fault is ``M @ theta`` (paper eq. 23).

    Built with :func:`xnavlab.core.faults.inject` (unit faults on zeros), so it has the
    same semantics as the injected faults: active for ``t >= onset``.

    Parameters
    ----------
    t_window : array_like, shape (p,)
        Sample times of the window, s, strictly increasing.
    model : {"bias", "step", "ramp"}
        ``"bias"``: ``theta = [f]``, constant in the whole window (paper eq. 23, the
        onset is ignored). ``"step"``: ``theta = [f]`` from ``onset``. ``"ramp"``:
        ``theta = [a, b]``, ``f = a t + b`` from ``onset``.
    onset : float
        Fault onset, s.
    time_origin : {"absolute", "onset"}
        For ``"ramp"``: ``t`` in ``a t + b`` is the flight time (``"absolute"``) or the
        time since the onset (``"onset"``).

    Returns
    -------
    ndarray, shape (p, 1) or (p, 2)

    Examples
    --------
    >>> fault_signature([1.0, 2.0, 3.0], "step", onset=2.0)[:, 0].tolist()
    [0.0, 1.0, 1.0]
    >>> fault_signature([1.0, 2.0, 3.0], "ramp", onset=2.0).tolist()
    [[0.0, 0.0], [2.0, 1.0], [3.0, 1.0]]
    """
    t = check_finite_array("t_window", t_window)
    if t.ndim != 1:
        raise ValueError(f"t_window must have shape (p,), got {t.shape}")
    check_increasing("t_window", t)  # a window's samples in time order
    check_choice("model", model, MODELS)
    onset = check_real("onset", onset)
    check_choice("time_origin", time_origin, ("absolute", "onset"))
    if model == "bias":
        return np.ones((len(t), 1))
    zero = np.zeros(len(t))
    step = _faults.inject(t, zero, [_faults.Fault("unit", "step", 1.0, onset)], "unit")
    if model == "step":
        return step[:, None]
    ramp = _faults.inject(t, zero, [_faults.Fault("unit", "ramp", 1.0, onset)], "unit")
    if time_origin == "absolute":
        ramp = ramp + onset * step  # a t = a (t - onset) + a onset
    return np.column_stack([ramp, step])  # f = a t + b, the paper's ramp model


def estimate_onset(t, z_j, W_j, k_alarm, model="step", time_origin="absolute"):
    """Locate a fault onset by a generalised likelihood-ratio search.

    Every sample time of the window that raised the alarm is a candidate onset; for
    each, the fault parameters are fitted by least squares to the residuals of the
    windows that can contain it (``k_alarm - s`` to ``k_alarm + s``), and the candidate
    explaining the most residual energy wins.

    Parameters
    ----------
    t : array_like, shape (n,)
        Sample times, s.
    z_j : array_like, shape (n,)
        Measurements of sensor ``j``, m.
    W_j : array_like, shape (n, s+1, q)
        Blended parity bases of sensor ``j`` at each window end.
    k_alarm : int
        Index (into ``t``) of the last sample of the first alarmed window, >= s.
    model : {"step", "ramp"}
        Fault model (:func:`fault_signature`).
    time_origin : {"absolute", "onset"}
        For ``"ramp"``, see :func:`fault_signature`.

    Returns
    -------
    float
        Estimated onset, s (one of the sample times).

    Examples
    --------
    >>> from xnavlab.plins.parity.space import parity_basis
    >>> V = parity_basis([[1.0, 1.0], [0.0, 1.0]], [1.0, 0.0], 3)
    >>> t = np.arange(12.0); z = np.where(t >= 6.0, 50.0, 0.0)
    >>> estimate_onset(t, z, np.broadcast_to(V, (12, 4, 2)), 6)
    6.0
    """
    t, z_j, W_j = _series(t, z_j, W_j)
    check_choice("model", model, ("step", "ramp"))
    s = W_j.shape[1] - 1
    n = len(t)
    k_alarm = check_int("k_alarm", k_alarm, s, n - 1)
    ks = np.arange(max(s, k_alarm - s), min(n - 1, k_alarm + s) + 1)
    r = np.concatenate([W_j[k].T @ z_j[k - s:k + 1] for k in ks])
    best, best_score = None, -math.inf
    for tc in t[k_alarm - s:k_alarm + 1]:
        M = fault_signature(t, model, tc, time_origin)  # a function of time: slice windows
        G = np.vstack([W_j[k].T @ M[k - s:k + 1] for k in ks])
        theta, *_ = np.linalg.lstsq(G, r, rcond=None)
        score = float(np.sum((G @ theta) ** 2))
        if score > best_score + 1e-12:
            best, best_score = float(tc), score
    return best


# ---------------------------------------------------------- identification KF


def rw_predict(theta, P, Q):
    """Kalman prediction for random-walk fault parameters (paper eq. 28).

    ``theta(k+1) = theta(k) + zeta(k)``, ``zeta ~ N(0, Q)``.

    Parameters
    ----------
    theta : array_like, shape (p,)
    P : array_like, shape (p, p)
    Q : array_like, shape (p, p)

    Returns
    -------
    theta, P : ndarray

    Examples
    --------
    >>> rw_predict([1.0], [[2.0]], [[0.5]])[1].tolist()
    [[2.5]]
    """
    theta = _nonempty("theta", theta, "parameter")
    p = len(theta)
    P = check_shape("P", P, (p, p), "p = len(theta)")
    check_covariance("P", P, p)  # an indefinite or non-symmetric P came back as one
    Q = check_shape("Q", Q, (p, p), "p = len(theta)")
    check_covariance("Q", Q, p)  # a negative Q would shrink P below its truth
    return theta.copy(), P + Q  # P = P + Q, eq. (28)


def rw_update(theta, P, r, G, R):
    """Kalman update of the fault parameters from a parity residual (paper eq. 27).

    ``r = G theta + eta``, ``eta ~ N(0, R)``; Joseph-form covariance.

    Parameters
    ----------
    theta : array_like, shape (p,)
    P : array_like, shape (p, p)
    r : array_like, shape (q,)
        Residual, m.
    G : array_like, shape (q, p)
        Regressor ``V^T M``.
    R : array_like, shape (q, q)
        Residual noise covariance, m^2.

    Returns
    -------
    theta, P : ndarray

    Examples
    --------
    >>> th, P = rw_update([0.0], [[1.0]], [2.0], [[1.0]], [[1.0]])
    >>> th.tolist(), P.tolist()
    ([1.0], [[0.5]])
    """
    theta = _nonempty("theta", theta, "parameter")
    p = len(theta)
    P = check_shape("P", P, (p, p), "p = len(theta)")
    check_covariance("P", P, p)  # an indefinite P gave an indefinite updated P
    r = _nonempty("r", r, "residual")
    q = len(r)
    G = check_shape("G", G, (q, p), "q = len(r), p = len(theta)")
    R = check_shape("R", R, (q, q), "q = len(r)")
    check_covariance("R", R, q)  # an indefinite R gave an indefinite "covariance" P
    return _rw_update(theta, P, r, G, R)


def _rw_update(theta, P, r, G, R):
    S = G @ P @ G.T + R
    try:
        K = np.linalg.solve(S, G @ P).T  # K = P G^T S^-1
    except np.linalg.LinAlgError:  # R and P both singular along one residual direction
        raise ValueError("R must be positive definite along the residual directions G P G^T "
                         "leaves uncertain: S = G P G^T + R is singular") from None
    theta = theta + K @ (r - G @ theta)  # eq. (27)
    IKG = np.eye(len(theta)) - K @ G
    P = IKG @ P @ IKG.T + K @ R @ K.T  # Joseph form
    return theta, 0.5 * (P + P.T)


class FaultIdentifier:
    """Thin stateful wrapper of :func:`rw_predict` and :func:`rw_update`.

    Parameters
    ----------
    theta0 : array_like, shape (p,)
        Initial parameters.
    P0 : array_like, shape (p, p)
        Initial covariance.
    Q : array_like, shape (p, p)
        Random-walk covariance per step.

    Examples
    --------
    >>> kf = FaultIdentifier([0.0], [[100.0]], [[0.0]])
    >>> for _ in range(50):
    ...     kf.step([3.0], [[1.0]], [[1.0]])
    >>> round(float(kf.theta[0]), 1)
    3.0
    """

    def __init__(self, theta0, P0, Q):
        self.theta = _nonempty("theta0", theta0, "parameter").astype(float)
        p = len(self.theta)
        self.P = check_covariance("P0", check_shape("P0", P0, (p, p), "p = len(theta0)"),
                                  p).astype(float)
        self.Q = check_covariance("Q", check_shape("Q", Q, (p, p), "p = len(theta0)"),
                                  p).astype(float)

    def step(self, r, G, R):
        """Predict then update with residual ``r`` and regressor ``G``."""
        self.theta, self.P = rw_predict(self.theta, self.P, self.Q)
        self.theta, self.P = rw_update(self.theta, self.P, r, G, R)


def kf_identify(r, G, R, Q, theta0=None, P0=None):
    """Run the random-walk Kalman filter over a sequence of residuals (eqs. 27-28).

    Parameters
    ----------
    r : array_like, shape (K, q)
        Residuals, m.
    G : array_like, shape (K, q, p)
        Regressors.
    R : float or array_like, shape (q, q)
        Residual noise covariance (a float is ``R I``), m^2.
    Q : float or array_like, shape (p, p)
        Random-walk covariance per step (a float is ``Q I``).
    theta0 : array_like, shape (p,), optional
        Initial parameters (default zeros).
    P0 : array_like, shape (p, p), optional
        Initial covariance (default ``1e8 I``: uninformative).

    Returns
    -------
    theta : ndarray, shape (K, p)
        Estimate after each residual.
    P : ndarray, shape (K, p, p)
        Its covariance.

    Examples
    --------
    >>> th, P = kf_identify(np.full((20, 1), 4.0), np.ones((20, 1, 1)), 1.0, 0.0)
    >>> round(float(th[-1, 0]), 3), bool(P[-1, 0, 0] < 0.06)
    (4.0, True)
    """
    r = check_finite_array("r", r)
    if r.ndim != 2:
        raise ValueError(f"r must have shape (K, q), got shape {r.shape}")
    G = check_shape("G", G, (*r.shape, None), "K windows of q residuals: the shape of r")
    K, q = r.shape
    p = G.shape[2]
    if np.ndim(R) == 0:
        R = check_real("R", R, 0.0, lo_open=True) * np.eye(q)
    else:
        R = check_covariance("R", check_shape("R", R, (q, q), "q = columns of r"), q)
    if np.ndim(Q) == 0:
        Q = check_real("Q", Q, 0.0) * np.eye(p)
    else:
        Q = check_covariance("Q", check_shape("Q", Q, (p, p), "p = columns of G"), p)
    theta = np.zeros(p) if theta0 is None else check_shape("theta0", theta0, (p,), "p = columns of G")
    P = 1e8 * np.eye(p) if P0 is None else \
        check_covariance("P0", check_shape("P0", P0, (p, p), "p = columns of G"), p)
    ths = np.empty((K, p))
    Ps = np.empty((K, p, p))
    for k in range(K):
        P = P + Q  # eq. (28)
        theta, P = _rw_update(theta, P, r[k], G[k], R)
        ths[k], Ps[k] = theta, P
    return ths, Ps


@dataclass(frozen=True)
class Identification:
    """Fault parameters of one sensor identified by the random-walk Kalman filter.

    Attributes
    ----------
    sensor : int
        Pseudolite index (0-based).
    model : str
        Fault model (:data:`MODELS`).
    names : tuple of str
        Parameter names (``("f",)`` or ``("a", "b")``).
    onset : float
        Onset used, s.
    t : ndarray, shape (K,)
        End time of each window used, s.
    theta : ndarray, shape (K, p)
        Estimate after each window (m; m/s for a slope).
    P : ndarray, shape (K, p, p)
        Covariance of the estimate.
    """

    sensor: int
    model: str
    names: tuple
    onset: float
    t: np.ndarray
    theta: np.ndarray
    P: np.ndarray

    def __post_init__(self):
        """Check the fields (an edited copy, ``dataclasses.replace``, is checked again), each
        refusal naming ``Identification.<field>``; a few array checks, negligible beside the
        filter that made them."""
        n = "Identification."
        check_int(n + "sensor", self.sensor, 0, 999)
        check_choice(n + "model", self.model, MODELS)
        check_real(n + "onset", self.onset)
        t = _nonempty(n + "t", self.t, "window end")
        check_increasing(n + "t", t)
        want = ("a", "b") if self.model == "ramp" else ("f",)
        if not isinstance(self.names, tuple) or self.names != want:
            raise ValueError(f"{n}names must be {want} (the parameters of model {self.model!r}), got "
                             f"{shown(self.names)}")
        p = len(want)
        theta = check_shape(n + "theta", self.theta, (t.size, p), f"K = len(t) windows, p = {p} parameters")
        P = check_shape(n + "P", self.P, (t.size, p, p), "K = len(t) windows, p parameters")
        for field, value in (("t", t), ("theta", theta), ("P", P)):
            object.__setattr__(self, field, value)

    @property
    def final(self):
        """The settled estimate (after the last window), shape (p,)."""
        return self.theta[-1]

    @property
    def std(self):
        """1-sigma of the settled estimate according to the filter, shape (p,)."""
        return np.sqrt(np.diag(self.P[-1]))


def identify_fault(t, z_j, W_j, onset, model="step", sigma=_pl.DEFAULT_SIGMA,
                   time_origin="absolute", q_rw=1e-6, sensor=0):
    """Identify the parameters of a fault of one sensor from its parity residuals.

    Runs :func:`kf_identify` over every window that ends at or after the onset, with
    regressor ``G_k = W_k^T M_k`` (:func:`fault_signature`) and residual noise
    ``sigma^2 I``. The windows after the onset has left them carry no information
    (``G_k = 0`` up to leakage: the estimate is held, "settled").

    Parameters
    ----------
    t : array_like, shape (n,)
        Sample times, s.
    z_j : array_like, shape (n,)
        Measurements of the sensor, m.
    W_j : array_like, shape (n, s+1, q)
        Blended parity bases of the sensor.
    onset : float
        Fault onset, s (e.g. from :func:`estimate_onset`).
    model : {"bias", "step", "ramp"}
        Fault model.
    sigma : float
        Pseudorange noise, m, in [1e-6, 1e6] (:data:`SIGMA_MIN`).
    time_origin : {"absolute", "onset"}
        For ``"ramp"`` (:func:`fault_signature`).
    q_rw : float
        Random-walk variance per step of each parameter (eq. 28), in [0, 1e6].
    sensor : int
        Sensor (pseudolite) index, 0-based, in [0, 999], recorded in the result (this
        function sees one sensor's series: the flight's count is the caller's to check).

    Returns
    -------
    Identification

    Examples
    --------
    >>> from xnavlab.plins.parity.space import parity_basis
    >>> V = parity_basis([[1.0, 1.0], [0.0, 1.0]], [1.0, 0.0], 3)
    >>> t = np.arange(30.0); z = np.where(t >= 10.0, 50.0, 0.0)
    >>> idn = identify_fault(t, z, np.broadcast_to(V, (30, 4, 2)), 10.0, sigma=1.0)
    >>> round(float(idn.final[0]), 3)
    50.0
    """
    t, z_j, W_j = _series(t, z_j, W_j)
    onset = check_real("onset", onset)
    check_choice("model", model, MODELS)
    sigma = check_real("sigma", sigma, SIGMA_MIN, 1e6)  # sigma^2 a normal float (SIGMA_MIN)
    q_rw = check_real("q_rw", q_rw, 0.0, 1e6)
    # an index, not a float or a negative; a thousand pseudolites is far beyond any flight's
    sensor = check_int("sensor", sensor, 0, 999)
    s = W_j.shape[1] - 1
    ks = np.arange(s, len(t))
    if model != "bias":
        ks = ks[t[ks] >= onset]
    if ks.size == 0:
        raise ValueError(f"onset must be at or before the last sample ({t[-1]:g} s), got {onset:g}")
    win = np.lib.stride_tricks.sliding_window_view(z_j, s + 1)[ks - s]  # (K, s+1)
    r = np.einsum("kpq,kp->kq", W_j[ks], win)  # eq. (24)
    M = fault_signature(t, model, onset, time_origin)  # (n, p), a function of time
    Mw = np.lib.stride_tricks.sliding_window_view(M, s + 1, axis=0)[ks - s]  # (K, p, s+1)
    G = np.einsum("kiq,kpi->kqp", W_j[ks], Mw)
    p = G.shape[2]
    theta, P = kf_identify(r, G, sigma**2, q_rw, P0=1e8 * np.eye(p))
    names = ("a", "b") if model == "ramp" else ("f",)
    return Identification(sensor, model, names, onset, t[ks], theta, P)
