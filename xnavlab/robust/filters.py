"""Four navigation filters against planetary-ephemeris error (Li et al. 2017).

The measurement the filters see is the XNAV range with the planet position taken from
the filter's ephemeris removed, ``y = z - N r_E_hat = N r + N dr_E + v`` (m), so the
ephemeris error appears as the bias ``B = N dr_E`` (paper eq. (17)). All four filters
share the unscented prediction of the planet-centred two-body + J2 dynamics
(:func:`predict`, the scaled unscented transform of :mod:`xnavlab.core.filters`).
:func:`run_filter` runs one filter over one scenario; :func:`run_filters` steps many runs at
once (the seeds of a study), each giving the numbers of its own run to the last bit.

UKF
    The baseline: ignores the bias.
ASUKF (Wang et al. 2013)
    State augmented with the bias, ``[r, v, b]`` with ``b`` a random walk, and
    ``y = N r + b + v`` (:func:`asukf_update`).
TDUKF (Wang et al. 2014)
    Time-differenced measurements ``y_k - y_{k-1} = N (r_k - r_{k-1}) + v_k - v_{k-1}``:
    a slowly varying bias cancels. A clone of the previous state is carried so that the
    difference is linear in the state (:func:`tdukf_predict`, :func:`tdukf_update`). The
    paper's competitor (default) takes the differenced noise as white with covariance
    ``2 R``; it is in fact an MA(1) sequence (consecutive differences share ``v_{k-1}``).
    ``td_carry_noise=True`` carries the previous noise in the state and handles that
    correlation exactly: that filter is then equivalent to a constant-bias ASUKF (the bias
    is eliminated exactly once and never re-estimated), a different filter from the one
    the paper ran, kept to explain why the paper's TDUKF pays for differencing.
RKF (the paper's method, eqs. (8)-(26) lost; re-derived)
    Kalman form with the unknown bias: ``e+ = (I - K H) e- - K B - K v``. For any
    ``eps > 0``, ``(a + b)(a + b)^T <= (1 + 1/eps) a a^T + (1 + eps) b b^T``, so with
    ``Sigma- >= P-``::

        P+ <= Sigma+(K) = (1 + 1/eps) (I - K H) Sigma- (I - K H)^T + K [R + (1 + eps) B B^T] K^T

    Setting ``d tr Sigma+ / dK = 0`` gives the bound-minimising gain and bound::

        K = Sigma- H^T [H Sigma- H^T + (R + (1 + eps) B B^T) / (1 + 1/eps)]^-1
        Sigma+ = (1 + 1/eps) (I - K H) Sigma-

    ``eps`` (paper: 1000 Earth, 100 Mars) enters twice: it weights the bias outer product
    in the gain (the measurement combination along ``B`` is de-weighted by about
    ``1 + eps``) and inflates the bound by ``1 + 1/eps`` per update.

    The bias is unknown; the paper bounds it from the measurement residuals
    ("the lower bound of the systematic bias is determined from the measurement
    residuals"). Default ``rkf_bias="residual"``: with ``m_k`` the exponentially weighted
    mean of the innovations ``nu_k = y_k - N r_k-`` (weight ``lam``), whose noise part has
    covariance ``lam / (2 - lam) S`` for white innovations of covariance
    ``S = H Sigma- H^T + R``, ``E[m m^T] = B B^T + lam / (2 - lam) S``, so
    ``B B^T >= [m m^T - lam / (2 - lam) S]_+`` (positive part; zero "otherwise",
    :func:`rkf_bias_bound`); the bound from the innovations up to epoch ``k`` sets the
    gain of epoch ``k + 1``. ``rkf_bias="oracle"`` uses the true bias ``B = N dr_E``
    (teaching only: a filter that knew it would subtract it). ``H Sigma- H^T`` and
    ``Sigma- H^T`` come from the unscented transform (paper: the UKF replaces eqs. (8)
    and (13)); for this linear measurement they equal the closed forms (:func:`rkf_update`).
    That is a lower bound, so ``Sigma`` is no bound: :mod:`xnavlab.robust.coverage` measures
    it and adds ``rkf_bias="prior"``, ``B B^T <= d_max^2 N N^T`` from ``|dr_E| <= d_max``.

Units: m, m/s, s. Frames: planet-centred J2000 for ``r, v``; measurement space for ``b``.

Examples
--------
>>> sc = simulate("earth", n_steps=20, rng=0)
>>> res = run_filter("rkf", sc, rng=0)
>>> res.x.shape, res.error.shape
((20, 6), (20,))
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field

import numpy as np

from xnavlab.core import validate
from xnavlab.core.filters import ukf_weights
from xnavlab.core.validate import check_choice, check_finite_array, check_int, check_real, make_rng
from xnavlab.robust import ephemeris_error as ee
from xnavlab.robust._batch import first, mv, sigma_points, sym, tr, unscented
from xnavlab.robust._checks import (
    check_epoch,
    check_n_dyn,
    check_position,
    check_runs,
    check_state,
    check_update,
)
from xnavlab.robust._propagation import propagate_unchecked

__all__ = [
    "FILTERS",
    "ERRORS",
    "EPSILON",
    "EPS_RANGE",
    "Scenario",
    "FilterRun",
    "simulate",
    "predict",
    "ukf_update",
    "asukf_update",
    "tdukf_predict",
    "tdukf_update",
    "rkf_gain",
    "rkf_bias_bound",
    "rkf_update",
    "RKF_BIAS",
    "SETTINGS",
    "run_filter",
    "run_filters",
]

#: Ephemeris-error models accepted by :func:`simulate`.
ERRORS = ("de405", "de405-drift", "constant", "slow", "growing", "none")
#: Filter names accepted by :func:`run_filter`.
FILTERS = ("ukf", "asukf", "tdukf", "rkf")
#: The paper's epsilon: 1000 for the Earth orbit, 100 for Mars.
EPSILON = {"earth": 1000.0, "mars": 100.0}
#: The range of epsilon every function here takes. Below 1e-6 the bound's factor ``1 + 1/eps``
#: passes 1e6 per update; above 1e15 ``(1 + eps) B B^T`` leaves float64's range for the
#: largest bias a scenario takes (1e8 m). Inside it a run can still lose P's definiteness or
#: the solve's precision (measured on chapter 10's Mars run: below about 1e-4 or, with a 1e8 m
#: error, above about 3e4): the run then stops naming eps (the paper takes eps > 1).
EPS_RANGE = (1e-6, 1e15)


@dataclass
class Scenario:
    """A simulated navigation run.

    Attributes
    ----------
    body : str
        ``"earth"`` or ``"mars"``.
    t : ndarray, shape (n,)
        Measurement epochs, s TDB past J2000 (one per ``dt``).
    dt : float
        Step, s.
    x_true : ndarray, shape (n, 6)
        True planet-centred states, m and m/s.
    y : ndarray, shape (n, k)
        Reduced measurements ``z - N r_E_hat = N r + N dr_E + v``, m.
    n : ndarray, shape (k, 3)
        Pulsar directions.
    R : ndarray, shape (k, k)
        Measurement-noise covariance, m^2.
    dr_e : ndarray, shape (n, 3)
        Ephemeris error ``r_E - r_E_hat`` used, m.
    """

    body: str
    t: np.ndarray
    dt: float
    x_true: np.ndarray
    y: np.ndarray
    n: np.ndarray
    R: np.ndarray
    dr_e: np.ndarray


@dataclass
class FilterRun:
    """Output of :func:`run_filter`.

    Attributes
    ----------
    name : str
    x : ndarray, shape (n, 6)
        Estimated states after each update.
    P : ndarray, shape (n, 6, 6)
        Their covariance (for the RKF, the bound ``Sigma``).
    error : ndarray, shape (n,)
        Position error ``|r_hat - r|``, m.
    extra : dict
        Filter-specific series (``"bias"`` for ASUKF, ``"bias_bound"`` for RKF).
    """

    name: str
    x: np.ndarray
    P: np.ndarray
    error: np.ndarray
    extra: dict = field(default_factory=dict)


def simulate(body="earth", n_steps=1200, dt=500.0, error="de405", size=0.0, pulsar_names=None,
             sigma_m=None, t0=ee.EPOCH_1997, elements=None, direction=None, growth_time=None,
             profile="linear", rng=None):
    """Simulate truth and measurements for one scenario.

    Parameters
    ----------
    body : {"earth", "mars"}
    n_steps : int
        Number of measurement epochs (``t = t0 + dt * [1..n_steps]``).
    dt : float
        Observation interval, s (paper: 500).
    error : {"de405", "de405-drift", "constant", "slow", "growing", "none"}
        Ephemeris error: DE421 - DE405 (the paper's, as it evolves over the run), its
        change since ``t0`` (:func:`xnavlab.robust.ephemeris_error.ephemeris_drift`: starts
        at zero), an injected constant, slowly varying or growing error of ``size``
        metres (:func:`xnavlab.robust.ephemeris_error.injected_error`), or none.
    size : float
        Size of the injected error, m (for ``"growing"``: reached at ``growth_time``); another
        ``error`` refuses any but 0.
    pulsar_names : sequence of str, optional
        Pulsars (default :data:`xnavlab.robust.ephemeris_error.PULSARS`).
    sigma_m : sequence of float, optional
        Their ranging noise, m (default :data:`xnavlab.robust.ephemeris_error.SIGMA_M`; needed
        when other pulsars are chosen: defaults to their ranging accuracy then).
    t0 : float
        Epoch of the initial state, s TDB past J2000, within the years DE421 and DE405 both
        cover (1900-2199; with ``error="de405"`` or ``"de405-drift"`` the run's end too).
    elements : tuple, optional
        Orbital elements replacing the default orbit (see :func:`xnavlab.robust.ephemeris_error.orbit`:
        the perigee ``a (1 - e)`` at or above the planet's radius).
    direction : array_like of shape (3,) or "de405", optional
        Direction of an injected error (ICRF); ``"de405"``: that of the real DE421 - DE405
        error at ``t0``. Default ``(1, 1, 1) / sqrt(3)``; an ``error`` not injected refuses it.
    growth_time : float, optional
        ``"growing"`` only: time after ``t0`` at which the error reaches ``size``, s, in
        [1, 1e12]. Default: the run's length ``n_steps * dt`` (with the default lengths of
        :func:`~xnavlab.robust.comparison.compare_filters`, the end of the paper's RMSE window).
        A shorter one lets the error grow on past ``size`` (it is not held there); a run in
        which it would exceed 1e8 m (the range of ``size``) is refused, naming growth_time
        (:func:`xnavlab.robust.ephemeris_error.injected_error`).
    profile : {"linear", "quadratic", "sqrt"} or callable
        ``"growing"`` only (another error refuses any but ``"linear"``): time profile
        (:func:`xnavlab.robust.ephemeris_error.growth_profile`).
    rng : numpy.random.Generator or int, optional

    Returns
    -------
    Scenario

    Examples
    --------
    >>> sc = simulate("mars", n_steps=5, error="constant", size=100.0, rng=1)
    >>> sc.y.shape, round(float(np.linalg.norm(sc.dr_e[0])), 6)
    ((5, 3), 100.0)
    >>> g = simulate("mars", n_steps=4, error="growing", size=400.0, rng=1)
    >>> np.round(np.linalg.norm(g.dr_e, axis=1), 6).tolist()
    [100.0, 200.0, 300.0, 400.0]
    """
    check_choice("body", body, tuple(ee.PLANETS))
    n_steps = check_int("n_steps", n_steps, 1, 10**6)
    dt = check_real("dt", dt, 1.0, 1e5)
    check_choice("error", error, ERRORS)
    size = check_real("size", size, 0.0, 1e8)
    ee.growth_profile(np.array([0.0, 1.0]), profile)  # names the profile's choices (or a bad callable)
    if error != "growing" and (growth_time is not None or not _same(profile, "linear")):
        shaped = "growth_time" if growth_time is not None else "profile"
        raise ValueError(f"{shaped} shapes a growing error only (error='growing'), got error = {error!r}; "
                         f"leave {shaped} out")
    if error not in ("constant", "slow", "growing") and (size != 0.0 or direction is not None):
        shaped = "size" if size != 0.0 else "direction"  # the real error has its own: unused
        raise ValueError(f"{shaped} shapes an injected error (error='constant', 'slow' or "
                         f"'growing'), got error = {error!r}; leave {shaped} out")
    growth_time = check_real("growth_time", n_steps * dt if growth_time is None else growth_time, 1.0,
                             1e12)  # as ephemeris_error.injected_error's (n_steps dt <= 1e11)
    rng = make_rng(rng)
    from xnavlab.mars.timing import pulsars

    names = ee.PULSARS if pulsar_names is None else pulsars.check_names(pulsar_names, "pulsar_names")
    if sigma_m is None:
        if names == ee.PULSARS:
            sigma_m = ee.SIGMA_M
        else:
            sigma_m = [pulsars.ranging_accuracy(nm) for nm in names]
    sigma = check_finite_array("sigma_m", sigma_m)
    if sigma.shape != (len(names),) or np.any(sigma <= 0):
        raise ValueError(f"sigma_m must hold {len(names)} positive values, got {sigma_m!r}")
    n = ee.directions(names)
    orb = ee.orbit(body, t0, elements)
    if error in ("de405", "de405-drift"):  # the run's epochs in the ephemerides, by the user's names
        check_epoch("t0", orb.t0, n_steps * dt, "n_steps", "n_steps * dt")
    if direction is None:
        direction = np.ones(3)
    elif isinstance(direction, str):
        check_choice("direction", direction, ("de405",))
        direction = ee.ephemeris_error(body, orb.t0)
    t = orb.t0 + dt * np.arange(1, n_steps + 1)
    x = _truth(body, tuple(float(v) for v in orb.state0), n_steps, dt).copy()
    if error == "de405":
        dr = ee.ephemeris_error(body, t)
    elif error == "de405-drift":
        dr = ee.ephemeris_drift(body, t, orb.t0)
    elif error == "none":
        dr = np.zeros((n_steps, 3))
    else:
        grow = error == "growing"  # injected_error refuses the growth settings for another kind
        dr = ee.injected_error(t, size, error, direction, t0=0.0 if error == "constant" else orb.t0,
                               growth_time=growth_time if grow else None,
                               profile=profile if grow else "linear")
    v = rng.normal(size=(n_steps, len(names))) * sigma
    y = (x[:, :3] + dr) @ n.T + v  # y = z - N r_E_hat = N (r + dr_E) + v, paper eqs. (1)-(3)
    return Scenario(body, t, dt, x, y, n, np.diag(sigma**2), dr)


@functools.lru_cache(maxsize=16)
def _truth(body, state0, n_steps, dt):
    """True states after each of ``n_steps`` steps from ``state0`` (kept: a study's seeds share them)."""
    x = np.empty((n_steps, 6))
    s = np.asarray(state0)
    for k in range(n_steps):
        s = propagate_unchecked(s, dt, ee.PLANETS[body], substep=10.0)
        x[k] = s
    x.flags.writeable = False
    return x


@functools.lru_cache(maxsize=32)
def _weights(m):
    Wm, Wc, lam = ukf_weights(m)
    Wm.flags.writeable = False
    Wc.flags.writeable = False
    return Wm, Wc, lam


# The steps below work on a batch of runs: x (r, m), P (r, m, m), y (r, k) (xnavlab.robust._batch);
# the public step functions are one run of them (r = 1), run_filters all the seeds of a study at once.
def _predict(x, P, dt, body, Q, n_dyn=6):
    Wm, Wc, lam = _weights(x.shape[-1])
    X = sigma_points(x, P, lam)
    Y = X.copy()
    # x_k|k-1 = f(x_k-1), per sigma point
    Y[..., :n_dyn] = propagate_unchecked(X[..., :n_dyn], dt, ee.PLANETS[body])
    return unscented(Y, Wm, Wc, Q)


def predict(x, P, dt, body, Q, n_dyn=6):
    """Unscented time update of ``[r, v, extra...]``: ``r, v`` through the dynamics, the rest held.

    Parameters
    ----------
    x : array_like, shape (m,)
        State; its first ``n_dyn = 6`` components are ``[r, v]`` (m, m/s), any further
        components (a bias) are constant over the step.
    P : array_like, shape (m, m)
        Covariance.
    dt : float
        Step, s.
    body : {"earth", "mars"}
    Q : array_like, shape (m, m)
        Process noise over the step.
    n_dyn : int
        Number of leading components the dynamics propagate: 6 (``[r, v]``), the only value.

    Returns
    -------
    x : ndarray, shape (m,)
    P : ndarray, shape (m, m)

    Examples
    --------
    >>> o = ee.orbit("earth")
    >>> x, P = predict(o.state0, np.eye(6), 500.0, "earth", np.zeros((6, 6)))
    >>> bool(np.allclose(x, ee.propagate(o.state0, 500.0), atol=1e-3))
    True
    """
    n_dyn = check_n_dyn(n_dyn)  # refused before it slices x
    x, P = check_state(x, P, n_dyn)
    Q = validate.check_covariance("Q", validate.check_shape("Q", Q, P.shape, "m = size of x"))
    check_choice("body", body, tuple(ee.PLANETS))
    dt = check_real("dt", dt, -1e6, 1e6)
    check_position("x[:3]", x[:3], ee.PLANETS[body][2], body)  # the planet's field outside it only
    return first(_predict(x[None], P[None], dt, body, Q, n_dyn))


def _measure(x, P, H):
    """Linear measurement: mean ``H x``, ``H P H^T`` and ``P H^T``.

    For a linear ``h`` the unscented transform returns exactly these (the sigma points
    reproduce the mean and covariance), so they are computed in closed form.
    """
    PHt = P @ H.T
    return mv(H, x), sym(H @ PHt), PHt


def _update_linear(x, P, y, R, H):
    z_pred, Pzz, Pxz = _measure(x, P, H)
    S = Pzz + R  # S = H P H^T + R
    K = tr(np.linalg.solve(S, tr(Pxz)))  # K = Pxz S^-1
    nu = y - z_pred
    return x + mv(K, nu), sym(P - K @ S @ tr(K)), nu  # P+ = P- - K S K^T


def ukf_update(x, P, y, R, n):
    """UKF measurement update with ``h(x) = N r`` (the bias is ignored).

    Parameters
    ----------
    x : array_like, shape (6,)
        Predicted ``[r, v]``.
    P : array_like, shape (6, 6)
    y : array_like, shape (k,)
        Reduced measurement ``z - N r_E_hat``, m.
    R : array_like, shape (k, k)
    n : array_like, shape (k, 3)
        Pulsar directions.

    Returns
    -------
    x : ndarray, shape (6,)
    P : ndarray, shape (6, 6)
    nu : ndarray, shape (k,)
        Innovation.

    Examples
    --------
    >>> x, P, nu = ukf_update(np.zeros(6), np.eye(6), np.ones(3), np.eye(3), np.eye(3))
    >>> np.round(x[:3], 6).tolist()
    [0.5, 0.5, 0.5]
    """
    x, P, y, R, n = check_update(x, P, y, R, n, lambda k: (6, "6 entries [r, v]"))
    H = np.zeros((n.shape[0], 6))
    H[:, :3] = n  # h(x) = N r
    return first(_update_linear(x[None], P[None], y[None], R, H))


def asukf_update(x, P, y, R, n):
    """ASUKF update: state ``[r, v, b]``, ``h(x) = N r + b`` (Wang et al. 2013).

    Parameters
    ----------
    x : array_like, shape (6 + k,)
    P : array_like, shape (6 + k, 6 + k)
    y, R, n : as in :func:`ukf_update`

    Returns
    -------
    x, P, nu

    Examples
    --------
    >>> x, P, nu = asukf_update(np.zeros(9), np.eye(9), np.ones(3), np.eye(3), np.eye(3))
    >>> np.round(x[6:], 6).tolist()
    [0.333333, 0.333333, 0.333333]
    """
    x, P, y, R, n = check_update(x, P, y, R, n, lambda k: (6 + k, f"6 + {k} entries (state and bias)"))
    return first(_update_linear(x[None], P[None], y[None], R, _asukf_h(n)))


def _asukf_h(n):
    k = n.shape[0]
    H = np.zeros((k, 6 + k))
    H[:, :3] = n
    H[:, 6:] = np.eye(k)  # y = N r + b + v
    return H


def tdukf_predict(x, P, dt, body, Q):
    """TDUKF time update: ``[x_k (, v_k)] -> [x_k+1, x_k (clone) (, v_k)]``.

    The clone ``x_k`` is what the differenced measurement of :func:`tdukf_update` needs;
    the returned covariance is symmetric and singular by construction (the clone and
    ``x_k+1`` are tied by the dynamics up to the process noise).

    Parameters
    ----------
    x : array_like, shape (6,) or (6 + k,)
        Posterior ``[r, v]`` and, for the exact form, the posterior of the last
        measurement noise ``v_k``.
    P : array_like, shape matching ``x``
    dt : float
    body : {"earth", "mars"}
    Q : array_like, shape (6, 6)
        Process noise of ``[r, v]`` over the step.

    Returns
    -------
    x : ndarray, shape (12,) or (12 + k,)
    P : ndarray, matching

    Examples
    --------
    >>> o = ee.orbit("mars")
    >>> x, P = tdukf_predict(np.r_[o.state0, 0, 0, 0], np.eye(9), 500.0, "mars", np.eye(6))
    >>> x.shape, bool(np.allclose(x[6:12], o.state0))
    ((15,), True)
    """
    x, P = check_state(x, P)
    Q = validate.check_covariance("Q", validate.check_shape("Q", Q, (6, 6), "the covariance of [r, v]"))
    check_choice("body", body, tuple(ee.PLANETS))
    dt = check_real("dt", dt, -1e6, 1e6)
    check_position("x[:3]", x[:3], ee.PLANETS[body][2], body)  # the planet's field outside it only
    return first(_tdukf_predict(x[None], P[None], dt, body, Q))


def _tdukf_predict(x, P, dt, body, Q):
    m = x.shape[-1]
    Wm, Wc, lam = _weights(m)
    X = sigma_points(x, P, lam)
    fx = propagate_unchecked(X[..., :6], dt, ee.PLANETS[body])
    Y = np.concatenate([fx, X[..., :6], X[..., 6:]], axis=-1)  # [f(x_k), x_k, v_k]
    noise = np.zeros(Q.shape[:-2] + (m + 6, m + 6))
    noise[..., :6, :6] = Q
    return unscented(Y, Wm, Wc, noise)  # P- = sum Wc (Y - x-)(Y - x-)^T + Q


def tdukf_update(x, P, dy, R, n, carry_noise=False):
    """TDUKF update with the differenced measurement ``dy = y_k+1 - y_k``.

    ``dy = N r_k+1 - N r_k + (v_k+1 - v_k)`` is linear in ``[x_k+1, x_k]`` (the state and
    its clone from :func:`tdukf_predict`) plus the differenced noise.

    ``carry_noise=False`` (default; the paper's competitor, Wang et al. 2014): the state
    is ``[x_k+1, x_k]``, ``H = [N 0, -N 0]``, and the differenced noise is taken as white
    with covariance ``2 R``, ``cov(v_k+1 - v_k) = 2 R``. It is not white: consecutive
    differences share ``v_k`` (covariance ``-R``), which this form ignores, and that is
    the noise increase the paper holds against the TDUKF.

    ``carry_noise=True`` (exact, for teaching): the previous noise ``v_k`` is carried in
    the state and ``v_k+1 ~ N(0, R)`` appended, ``H = [N 0, -N 0, -I, I]`` over
    ``[x_k+1, x_k, v_k, v_k+1]`` with no further noise, and the result is marginalised to
    ``[x_k+1, v_k+1]``. Carrying the noise this exactly makes the filter a constant-bias
    estimator in disguise: it is equivalent to an ASUKF whose bias never changes, so it is
    not the competitor the paper ran.

    Either way the process noise of the step is correlated with ``dy`` through the joint
    covariance of ``x_k+1`` and its clone ``x_k``.

    Covariances stay symmetric and positive semi-definite: the update uses the Joseph
    form ``P+ = (I - K H) P (I - K H)^T + K R_d K^T`` (``R_d = 2 R``, or 0 in the exact
    form where the noise is in the state), a sum of congruences of PSD matrices, which is
    PSD for any gain, and the result is symmetrised. The clone block makes ``P`` singular
    by construction (``x_k+1`` and ``x_k`` are tied by the dynamics), so its smallest
    eigenvalue is zero up to rounding; a test must check PSD within a tolerance relative
    to the scale, not the sign of that eigenvalue.

    Parameters
    ----------
    x : array_like, shape (12,) or (12 + k,)
        Output of :func:`tdukf_predict` (``12 + k`` entries when ``carry_noise`` is True).
    P : array_like, shape matching ``x``
    dy : array_like, shape (k,)
    R, n : as in :func:`ukf_update`
    carry_noise : bool
        Treat the differenced noise as white with ``2 R`` (False) or carry the previous
        measurement noise in the state (True, exact).

    Returns
    -------
    x : ndarray, shape (6,) or (6 + k,)
    P : ndarray, shape (6, 6) or (6 + k, 6 + k)
    nu : ndarray, shape (k,)

    Examples
    --------
    >>> x, P, nu = tdukf_update(np.zeros(12), np.eye(12), np.zeros(3), np.eye(3), np.eye(3))
    >>> x.shape, P.shape
    ((6,), (6, 6))
    >>> tdukf_update(np.zeros(15), np.eye(15), np.zeros(3), np.eye(3), np.eye(3), True)[0].shape
    (9,)
    """
    carry_noise = validate.check_bool("carry_noise", carry_noise)
    def size(k):
        return 12 + k * carry_noise, f"12{f' + {k}' * carry_noise} entries when carry_noise is {carry_noise}"

    x, P, dy, R, n = check_update(x, P, dy, R, n, size, "dy")
    return first(_tdukf_update(x[None], P[None], dy[None], R, n, carry_noise))


def _tdukf_update(x, P, dy, R, n, carry_noise):
    k = n.shape[0]
    if not carry_noise:
        H = np.zeros((k, 12))
        H[:, :3] = n
        H[:, 6:9] = -n  # dy = N r_k+1 - N r_k + (v_k+1 - v_k)
        xo, Po, nu = _joseph_update(x, P, dy, H, 2.0 * R)  # white: cov(v_k+1 - v_k) = 2 R
        return xo[:, :6], Po[:, :6, :6], nu
    r, m = x.shape
    xa = np.concatenate([x, np.zeros((r, k))], axis=1)
    Pa = np.zeros((r, m + k, m + k))
    Pa[:, :m, :m] = P
    Pa[:, m:, m:] = R  # v_k+1 ~ N(0, R)
    H = np.zeros((k, m + k))
    H[:, :3] = n
    H[:, 6:9] = -n
    H[:, 12:12 + k] = -np.eye(k)
    H[:, 12 + k:] = np.eye(k)  # dy = N r_k+1 - N r_k - v_k + v_k+1
    xa, Pa, nu = _joseph_update(xa, Pa, dy, H, np.zeros((k, k)))
    keep = np.r_[0:6, 12 + k: 12 + 2 * k]
    return xa[:, keep], Pa[:, keep][:, :, keep], nu


def _joseph_update(x, P, y, H, Rd):
    """Kalman update in Joseph form; symmetric and PSD for any gain."""
    PHt = P @ H.T
    S = sym(H @ PHt + Rd)  # S = H P H^T + R_d
    K = tr(np.linalg.solve(S, tr(PHt)))  # K = P H^T S^-1
    nu = y - mv(H, x)
    A = np.eye(P.shape[-1]) - K @ H
    return x + mv(K, nu), sym(A @ P @ tr(A) + K @ Rd @ tr(K)), nu  # P+ = (I-KH) P (I-KH)^T + K R_d K^T


def rkf_gain(Pxz, Pzz, R, BB, eps):
    """Bound-minimising RKF gain ``K = Sigma H^T [H Sigma H^T + (R + (1+eps) B B^T)/(1+1/eps)]^-1``.

    Parameters
    ----------
    Pxz : array_like, shape (n, k)
        ``Sigma- H^T``.
    Pzz : array_like, shape (k, k)
        ``H Sigma- H^T``.
    R : array_like, shape (k, k)
    BB : array_like, shape (k, k)
        Bound on the bias outer product ``B B^T`` (positive semi-definite).
    eps : float
        The scalar of the matrix inequality, in :data:`EPS_RANGE` (paper: ``eps > 1``).

    Returns
    -------
    ndarray, shape (n, k)

    Examples
    --------
    >>> K = rkf_gain(np.eye(1), np.eye(1), np.eye(1), np.zeros((1, 1)), 1e12)
    >>> round(float(K[0, 0]), 6)   # eps -> inf, B = 0: the Kalman gain 1 / (1 + 1)
    0.5
    """
    eps = check_real("eps", eps, *EPS_RANGE)
    Pxz = check_finite_array("Pxz", Pxz)
    if Pxz.ndim != 2 or Pxz.size == 0:
        raise ValueError(f"Pxz must be a non-empty 2-D array (n, k), got shape {Pxz.shape}")
    k = Pxz.shape[1]
    Pzz = validate.check_shape("Pzz", Pzz, (k, k), "k = columns of Pxz")
    R = validate.check_covariance("R", R, k)
    BB = validate.check_covariance("BB", BB, k)  # a bound on B B^T: a negative one shrank W
    W = (R + (1.0 + eps) * BB) / (1.0 + 1.0 / eps)  # (R + (1+eps) B B^T) / (1 + 1/eps)
    return tr(_solve_gain(sym(Pzz + W), tr(Pxz), eps))  # K = Sigma H^T [H Sigma H^T + W]^-1


def _solve_gain(S, PxzT, eps):
    """``S^-1 Pxz^T``, or a ValueError naming eps when ``S`` is singular to float64."""
    try:
        return np.linalg.solve(S, PxzT)
    except np.linalg.LinAlgError:
        raise ValueError(f"eps = {eps:g} makes H Sigma H^T + (R + (1+eps) B B^T)/(1 + 1/eps) "
                         f"singular to float64 (the bias term swamps R): take a smaller eps") from None


def rkf_bias_bound(m, S, lam):
    """Lower bound on ``B B^T`` from the mean innovation: ``[m m^T - lam/(2-lam) S]_+``.

    Parameters
    ----------
    m : array_like, shape (k,)
        Exponentially weighted mean of the innovations (weight ``lam``).
    S : array_like, shape (k, k)
        Innovation covariance without the bias, ``H Sigma H^T + R``.
    lam : float
        Weight in (0, 1].

    Returns
    -------
    ndarray, shape (k, k)
        Positive semi-definite (negative eigenvalues set to zero, "otherwise 0").

    Examples
    --------
    >>> rkf_bias_bound(np.zeros(2), np.eye(2), 0.1).tolist()
    [[0.0, 0.0], [0.0, 0.0]]
    """
    m = validate.check_vector("m", m)
    S = validate.check_shape("S", S, (None, None))
    m = validate.check_shape("m", m, (S.shape[0],), "k = rows of S")
    S = validate.check_shape("S", S, (m.size, m.size), "k = size of m")
    lam = check_real("lam", lam, 0.0, 1.0, lo_open=True)
    return _bias_bound(m, S, lam)


def _bias_bound(m, S, lam):
    c = np.asarray(lam / (2.0 - lam))[..., None, None]  # one lam, or one per run
    A = sym(m[..., :, None] * m[..., None, :] - c * S)  # m m^T - lam/(2-lam) S
    w, V = np.linalg.eigh(A)
    return sym((V * np.clip(w, 0.0, None)[..., None, :]) @ tr(V))  # its positive part


def rkf_update(x, P, y, R, n, BB, eps):
    """RKF measurement update (re-derived paper eqs. (9), (17)-(26); see the module docstring).

    Parameters
    ----------
    x : array_like, shape (6,)
        Predicted ``[r, v]``.
    P : array_like, shape (6, 6)
        Predicted bound ``Sigma-``.
    y, R, n : as in :func:`ukf_update`
    BB : array_like, shape (k, k)
        Bound on the bias outer product ``B B^T`` (from :func:`rkf_bias_bound` or from an
        a priori ephemeris-error model ``B = N dr_E``).
    eps : float
        The inequality's scalar, in :data:`EPS_RANGE` (paper: 1000 Earth, 100 Mars).

    Returns
    -------
    x : ndarray, shape (6,)
    P : ndarray, shape (6, 6)
        ``Sigma+ = (1 + 1/eps) (I - K H) Sigma-`` (symmetrised).
    nu : ndarray, shape (k,)
        Innovation.

    Examples
    --------
    >>> x, P, nu = rkf_update(np.zeros(6), np.eye(6), np.ones(3), np.eye(3), np.eye(3),
    ...                       np.zeros((3, 3)), 1000.0)
    >>> bool(np.all(np.linalg.eigvalsh(P) > 0))
    True
    """
    x, P, y, R, n = check_update(x, P, y, R, n, lambda k: (6, "6 entries [r, v]"))
    k = n.shape[0]
    BB = validate.check_covariance("BB", BB, k)  # a bound on B B^T, as rkf_gain's
    eps = check_real("eps", eps, *EPS_RANGE)
    H = np.zeros((k, 6))
    H[:, :3] = n
    return first(_rkf_update(x[None], P[None], y[None], R, H, BB, eps))


def _rkf_update(x, P, y, R, H, BB, eps):
    z_pred, Pzz, Pxz = _measure(x, P, H)
    nu = y - z_pred
    W = (R + (1.0 + eps) * BB) / (1.0 + 1.0 / eps)  # (R + (1+eps) B B^T) / (1 + 1/eps)
    K = tr(_solve_gain(sym(Pzz + W), tr(Pxz), eps))  # K = Sigma H^T [H Sigma H^T + W]^-1
    # Sigma+ = (1 + 1/eps) (Sigma- - K H Sigma-); with the UT, H Sigma- = Pxz^T
    Sig = (1.0 + 1.0 / eps) * (P - K @ tr(Pxz))
    return x + mv(K, nu), sym(Sig), nu


#: Where the RKF's bound on ``B B^T`` comes from (:func:`run_filter`).
RKF_BIAS = ("residual", "oracle", "prior")


#: run_filter setting -> (the filters that use it, its default); set apart from its default
#: for another filter it is refused.
SETTINGS = {"eps": (("rkf",), None), "lam": (("rkf",), 0.02), "rkf_bias": (("rkf",), "residual"),
             "oracle_error": (("rkf",), None), "bias_max": (("rkf",), None),
             "td_carry_noise": (("tdukf",), False), "q_b": (("asukf",), 1.0),
             "sigma_b0": (("asukf",), 3000.0)}


def _per_run(label, value, r, hi, lo_open=False, lo=0.0):
    """A setting given once or once per run -> (r,) floats in [lo, hi] (or (lo, hi]), each checked."""
    given = np.atleast_1d(np.asarray(value, dtype=object))
    vals = [check_real(label, v, lo, hi, lo_open=lo_open) for v in given]
    if len(vals) not in (1, r):
        raise ValueError(f"{label} must be one value or one per scenario ({r}), got {len(vals)}")
    return np.array(vals * (r // len(vals)))


def _diag(v):
    """Diagonal matrices of the rows of ``v`` (r, m) -> (r, m, m)."""
    return np.eye(v.shape[-1]) * v[:, None, :]


def _same(value, default):
    """``value == default`` for a scalar setting (an array or other type is not the default)."""
    try:
        return type(value) is not bool and type(default) is not bool and value == default \
            or value is default
    except (TypeError, ValueError):
        return False


def run_filter(name, scenario, eps=None, sigma_r0=1000.0, sigma_v0=1.0, q_r=0.0, q_v=1e-4,
               q_b=1.0, sigma_b0=3000.0, rkf_bias="residual", oracle_error=None, lam=0.02,
               td_carry_noise=False, rng=None, bias_max=None):
    """Run one filter over a scenario from a random initial error.

    Parameters
    ----------
    name : {"ukf", "asukf", "tdukf", "rkf"}
    scenario : Scenario
    eps : float, optional
        RKF scalar, in :data:`EPS_RANGE` (default :data:`EPSILON` of the body).
    sigma_r0, sigma_v0 : float
        Initial position (m, in [1e-3, 1e8]) and velocity (m/s, in [1e-6, 1e5]) error,
        1 sigma per axis; the initial error is drawn from this distribution and ``P0`` is
        its covariance.
    q_r, q_v : float
        Process noise per step, 1 sigma per axis, m and m/s.
    q_b : float
        ASUKF bias random-walk step, m per step (1 sigma).
    sigma_b0 : float
        ASUKF initial bias uncertainty, m, in [1e-3, 1e8].
    rkf_bias : {"residual", "oracle", "prior"}
        Where the RKF's bound on ``B B^T`` comes from. ``"residual"`` (default, the
        paper's, re-derived): the lower bound of :func:`rkf_bias_bound` from the running
        mean of the innovations up to the previous epoch (each epoch's innovation updates
        the mean after its update; the bound then sets the next gain). ``"oracle"``
        (teaching only): ``B = N dr`` with ``dr`` the true ephemeris error of the epoch
        (or ``oracle_error``); a filter that knew ``dr`` should subtract it, so this only
        shows what a perfect bound would give. ``"prior"``: an upper bound that holds
        whenever ``|dr_E| <= bias_max``, ``B B^T <= bias_max^2 N N^T``.
    oracle_error : array_like, shape (3,) or (n, 3), optional
        ``dr`` for ``rkf_bias="oracle"``, m (default: the scenario's true error).
    lam : float
        Weight of the running innovation mean of the residual bound, in (0, 1]
        (``lam = 1``: the current residual only).
    td_carry_noise : bool
        TDUKF: False (default) treats the differenced noise as white with ``2 R`` (the
        paper's competitor); True carries the previous noise exactly (:func:`tdukf_update`).
    rng : numpy.random.Generator or int, optional
        Draws the initial error.
    bias_max : float or array_like, shape (n,), optional
        ``rkf_bias="prior"``: bound on the ephemeris error ``|dr_E|`` (each epoch), m.

    Returns
    -------
    FilterRun

    Examples
    --------
    >>> sc = simulate("earth", n_steps=10, rng=0)
    >>> [run_filter(f, sc).x.shape for f in FILTERS]
    [(10, 6), (10, 6), (10, 6), (10, 6)]
    >>> run_filter("ukf", sc, lam=0.5)
    Traceback (most recent call last):
    ...
    ValueError: lam is a setting of the rkf filter, not used by ukf, got lam = 0.5; leave it out
    """
    settings = {k: v for k, v in locals().items() if k not in ("name", "scenario", "rng")}
    validate.check_instance("scenario", scenario, Scenario, "a Scenario from simulate()")
    make_rng(rng)  # refused under its own name (run_filters names rngs[0])
    return run_filters(name, [scenario], [rng], **settings)[0]


def run_filters(name, scenarios, rngs=None, eps=None, sigma_r0=1000.0, sigma_v0=1.0, q_r=0.0, q_v=1e-4,
                q_b=1.0, sigma_b0=3000.0, rkf_bias="residual", oracle_error=None, lam=0.02,
                td_carry_noise=False, bias_max=None):
    """Run one filter over several scenarios at once (a batch: one step of every run per step).

    Each run is :func:`run_filter` of its scenario and its ``rng``, to the last bit (each run's
    products are its own); stepping the runs together makes one array operation of what were
    as many small ones, which is what cost the time.

    Parameters
    ----------
    name : {"ukf", "asukf", "tdukf", "rkf"}
    scenarios : sequence of Scenario
        Draws of one :func:`simulate` setting (the same body, epochs, pulsars and noise
        covariance; the measurements, truth and ephemeris error may differ).
    rngs : sequence of (numpy.random.Generator or int), optional
        One per scenario: draws its initial error. A Generator listed more than once is
        drawn from in order, as :func:`run_filter` called run after run with it would.
    sigma_r0, sigma_v0, q_r, q_v, q_b, sigma_b0, lam : float or sequence of float
        As for :func:`run_filter`: one value for every run, or one per scenario (a study of
        the settings runs as one batch too).
    eps, rkf_bias, oracle_error, td_carry_noise, bias_max
        As for :func:`run_filter`, the same for every run.

    Returns
    -------
    list of FilterRun
        One per scenario, in their order.

    Examples
    --------
    >>> scs = [simulate("mars", n_steps=10, rng=s) for s in (0, 1)]
    >>> runs = run_filters("rkf", scs, (5, 6))
    >>> bool(np.allclose(runs[1].x, run_filter("rkf", scs[1], rng=6).x, rtol=1e-12, atol=1e-6))
    True
    >>> two = run_filters("rkf", scs, (5, 6), lam=(0.02, 0.5))
    >>> bool(np.allclose(two[1].x, run_filter("rkf", scs[1], rng=6, lam=0.5).x, rtol=1e-12, atol=1e-6))
    True
    """
    check_choice("name", name, FILTERS)
    given = {key: value for key, value in locals().items() if key in SETTINGS}
    for key, value in given.items():  # a setting of another filter: refused, not ignored
        users, default = SETTINGS[key]
        if name not in users and (value is not default if default is None
                                  else not _same(value, default)):
            raise ValueError(f"{key} is a setting of the {'/'.join(users)} filter, not used by "
                             f"{name}, got {key} = {value!r:.60}; leave it out")
    scenarios, rngs = check_runs(scenarios, rngs, Scenario)
    sc = scenarios[0]
    if any(s.body != sc.body or s.dt != sc.dt or not np.array_equal(s.t, sc.t)
           or not np.array_equal(s.n, sc.n) or not np.array_equal(s.R, sc.R) for s in scenarios):
        raise ValueError("scenarios must share the body, dt, epochs, pulsars and R (draws of one setting)")
    r, N = len(scenarios), sc.t.size
    eps = EPSILON[sc.body] if eps is None else check_real("eps", eps, *EPS_RANGE)
    # Initial sigmas from 1 mm and 1 um/s: their squares (P0) stay far from underflow, which
    # left a P0 of 5e-324**2 = 0 that no Cholesky factor takes.
    sigma_r0 = _per_run("sigma_r0", sigma_r0, r, 1e8, lo=1e-3)
    sigma_v0 = _per_run("sigma_v0", sigma_v0, r, 1e5, lo=1e-6)
    q_r, q_v, q_b = _per_run("q_r", q_r, r, 1e6), _per_run("q_v", q_v, r, 1e3), _per_run("q_b", q_b, r, 1e6)
    sigma_b0 = _per_run("sigma_b0", sigma_b0, r, 1e8, lo=1e-3)  # as sigma_r0
    check_choice("rkf_bias", rkf_bias, RKF_BIAS)
    td_carry_noise = validate.check_bool("td_carry_noise", td_carry_noise)
    for key, value, mode in (("oracle_error", oracle_error, "oracle"), ("bias_max", bias_max, "prior")):
        if value is not None and rkf_bias != mode:  # given, and unused by this bias rule
            raise ValueError(f"{key} goes with rkf_bias={mode!r}, got rkf_bias={rkf_bias!r}; "
                             f"leave {key} out")
    lam = _per_run("lam", lam, r, 1.0, lo_open=True)
    if oracle_error is None:
        oracle = np.stack([s.dr_e for s in scenarios])
    else:
        oracle_error = check_finite_array("oracle_error", oracle_error)
        if oracle_error.shape not in ((3,), (N, 3)):
            raise ValueError(f"oracle_error must have shape (3,) or ({N}, 3), got {oracle_error.shape}")
        oracle = np.broadcast_to(oracle_error, (r, N, 3))
    if rkf_bias == "prior":
        bias_max = check_finite_array("bias_max", bias_max)
        if bias_max.shape not in ((), (N,)) or np.any(bias_max < 0):
            raise ValueError(f"bias_max must be >= 0 m, a scalar or one per epoch ({N},)")
        bias_max = np.broadcast_to(bias_max, (N,))
    body, dt, n, R = sc.body, sc.dt, sc.n, sc.R
    k = n.shape[0]
    sd0 = np.column_stack([sigma_r0] * 3 + [sigma_v0] * 3)  # (r, 6)
    draws = [make_rng(g, f"rngs[{j}]").normal(size=6) for j, g in enumerate(rngs)]
    x = np.array([ee.propagate(s.x_true[0], -dt, body, substep=10.0) + d * sd
                  for s, d, sd in zip(scenarios, draws, sd0, strict=True)])  # x0 = true x0 + initial error
    P = _diag(sd0**2)
    Q = _diag(np.column_stack([np.maximum(q_r, 1e-6) ** 2] * 3 + [np.maximum(q_v, 1e-9) ** 2] * 3))
    y = np.stack([s.y for s in scenarios], axis=1)  # (N, r, k)
    xs, Ps = np.empty((N, r, 6)), np.empty((N, r, 6, 6))
    extra = {}
    if name == "asukf":
        x = np.concatenate([x, np.zeros((r, k))], axis=1)
        P = _diag(np.column_stack([sd0**2] + [sigma_b0**2] * k))
        Qa = np.zeros((r, 6 + k, 6 + k))
        Qa[:, :6, :6] = Q
        Qa[:, 6:, 6:] = np.eye(k) * (q_b**2)[:, None, None]  # b_k+1 = b_k + w_b
        extra["bias"] = np.empty((N, r, k))
    elif name == "tdukf":
        kv = k if td_carry_noise else 0
        x = np.concatenate([x, np.zeros((r, kv))], axis=1)
        P = np.zeros((r, 6 + kv, 6 + kv))
        P[:, :6, :6] = _diag(sd0**2)
        P[:, 6:, 6:] = R[:kv, :kv]  # the noise of the first measurement
    elif name == "rkf":
        m = np.zeros((r, k))
        BB = np.zeros((r, k, k))  # no residual seen yet: B B^T >= 0
        extra["bias_bound"] = np.empty((N, r))
    H = np.zeros((k, 6))
    H[:, :3] = n
    Ha = _asukf_h(n)
    for i in range(N):
        if name == "ukf":
            x, P = _predict(x, P, dt, body, Q)
            x, P, _ = _update_linear(x, P, y[i], R, H)
        elif name == "asukf":
            x, P = _predict(x, P, dt, body, Qa)
            x, P, _ = _update_linear(x, P, y[i], R, Ha)
            extra["bias"][i] = x[:, 6:]
        elif name == "tdukf":
            x, P = _tdukf_predict(x, P, dt, body, Q)
            if i == 0:  # no previous measurement: keep [x_1, v_1] with v_1 ~ N(0, R)
                x = np.concatenate([x[:, :6], np.zeros((r, kv))], axis=1)
                P0, P = P, np.zeros((r, 6 + kv, 6 + kv))
                P[:, :6, :6], P[:, 6:, 6:] = P0[:, :6, :6], R[:kv, :kv]
            else:
                x, P, _ = _tdukf_update(x, P, y[i] - y[i - 1], R, n, td_carry_noise)
        else:
            try:
                x, P = _predict(x, P, dt, body, Q)
            except ValueError:  # the bound lost its definiteness in float64 (see EPS_RANGE)
                raise ValueError(f"eps = {eps:g}: the RKF's bound lost its definiteness at step "
                                 f"{i} (float64 cannot carry it at this eps; the paper takes "
                                 f"eps > 1, chapter 10 runs 1 to 1e4)") from None
            if rkf_bias == "oracle":
                b = mv(n, oracle[:, i])  # B = N dr_E (paper eq. (17)), the true bias
                BB = b[:, :, None] * b[:, None, :]
            elif rkf_bias == "prior":  # B B^T = N dr dr^T N^T <= |dr|^2 N N^T <= d_max^2 N N^T
                BB = np.broadcast_to(bias_max[i] ** 2 * (n @ n.T), (r, k, k))
            S = sym(H @ P @ H.T) + R  # innovation covariance without the bias
            extra["bias_bound"][i] = np.sqrt(np.trace(BB, axis1=1, axis2=2))
            x, P, nu = _rkf_update(x, P, y[i], R, H, BB, eps)
            if rkf_bias == "residual":  # paper eqs. (23)-(26), re-derived: bound for the next epoch
                m = (1.0 - lam[:, None]) * m + lam[:, None] * nu  # m_k = (1 - lam) m_k-1 + lam nu_k
                BB = _bias_bound(m, S, lam)  # B B^T >= [m m^T - lam/(2-lam) S]_+
        xs[i], Ps[i] = x[:, :6], P[:, :6, :6]
    err = np.linalg.norm(xs[..., :3] - np.stack([s.x_true[:, :3] for s in scenarios], axis=1), axis=2)
    return [FilterRun(name, xs[:, j].copy(), Ps[:, j].copy(), err[:, j].copy(),
                      {key: v[:, j].copy() for key, v in extra.items()}) for j in range(r)]
