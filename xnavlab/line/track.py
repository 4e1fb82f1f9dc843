"""A constant-velocity Kalman filter fed by folded pulsar TOAs, on a line or in a plane.

The state is ``[r, v]`` with ``r`` (d,) the position relative to the SSB (d = 1 on the line
to one pulsar, d = 2 in the plane of two) and ``v`` its velocity; an unknown acceleration,
white with spectral density ``accel_sigma**2``, drives it. Each epoch every pulsar gives one
range ``n_i . r`` (:func:`xnavlab.line.measure.fold_range`); the steps are the core's
(:func:`xnavlab.core.filters.ekf_predict`, :func:`~xnavlab.core.filters.ekf_update`), which
for this linear model are the Kalman filter itself. :func:`run_line` flies chapter 0's
spacecraft on the line to the Crab and :func:`plot_tracking` draws it for the chapter's slider
(with an in-place update, :func:`xnavlab.core.plotting.in_place`).

Units: m, s. Arrays: ``truth`` (n + 1, 2 d), directions (m, d) unit vectors.

Examples
--------
>>> truth = simulate(np.array([2.0e11, 2.0e4]), dt=10.0, n=50)
>>> run = track(truth, 10.0, x0=truth[0] + [300.0, 1.0], P0=np.diag([1e6, 4.0]))
>>> bool(abs(run.x[-1, 0] - truth[-1, 0]) < 3 * np.sqrt(run.P[-1, 0, 0]))
True
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from xnavlab.core.constants import AU
from xnavlab.core.filters import ekf_predict, ekf_update
from xnavlab.core.plotting import in_place
from xnavlab.core.validate import (
    check_covariance,
    check_finite_array,
    check_int,
    check_real,
    check_seed,
    make_rng,
    seed_after,
)
from xnavlab.line.measure import fold_range, range_sigma
from xnavlab.mars.timing import pulsars

__all__ = ["X0", "V0", "MAX_TOAS", "SECONDS_PER_TOA", "cv_model", "simulate", "Track", "track",
           "snapshot_covariance", "run_line", "plot_tracking"]

#: Chapter 0's spacecraft: its distance from the SSB along ``n`` at the start, m (1.5 au) ...
X0 = 1.5 * AU
#: ... and its planned speed towards the pulsar, m/s.
V0 = 2.0e4

#: Wall time of one TOA of :func:`track` (a fold and a filter step), s: 2.0-2.2 ms measured
#: on a 2-core machine (2026-11-29; 1e4 TOAs of run_line in 22 s).
SECONDS_PER_TOA = 2.1e-3
#: The most TOAs (steps times pulsars) :func:`track` and :func:`run_line` take: 2e5, about 7
#: minutes at :data:`SECONDS_PER_TOA` (review 35p P10: 1e6 TOAs, span_s = 1e5 s of 0.1 s
#: exposures, took about 37 minutes without a word). Chapter 0 takes at most 200 (2,000 s of
#: 10 s), the default span at the shortest exposure 20,000 (2,000 s of 0.1 s, 42 s).
MAX_TOAS = 200_000


def _check_toas(count, name, what, most):
    """``count`` TOAs at most :data:`MAX_TOAS`, else one ValueError leading with ``name``, with
    the estimated time and the most the caller may ask (``most``, text)."""
    if count > MAX_TOAS:
        raise ValueError(f"{name} must keep at most {MAX_TOAS} TOAs (about "
                         f"{MAX_TOAS * SECONDS_PER_TOA / 60:.0f} minutes at "
                         f"{SECONDS_PER_TOA * 1e3:g} ms a TOA), got {what} = {count} TOAs, about "
                         f"{count * SECONDS_PER_TOA / 60:.0f} minutes ({most})")


#: How far from 1 the norm of a direction may be: a range is ``n . r`` with ``|r|`` up to
#: 1e15 m (1.5 au is 2.2e11 m), so a norm off by ``e`` moves it by ``e |r|``. 1e-12 keeps that
#: below a metre at 1.5 au (the Crab's 10-s range sigma is 821 m) and passes any vector
#: normalised in floating point (off by a few 1e-16); a 3-digit (0.707, 0.707) is 1.5e-4 off,
#: 3e7 m at 1.5 au. A direction off by more is refused, not rescaled: its scale is the user's
#: error to see, not ours to guess.
_UNIT_TOL = 1e-12


def _check_directions(N):
    """Each row of ``N`` (m, d) a unit vector to ``_UNIT_TOL``, else one ValueError naming
    ``directions[i]`` (a zero row observes nothing; a non-unit one scales its ranges)."""
    norms = np.linalg.norm(N, axis=1)
    for i, norm in enumerate(norms):
        if norm == 0.0:
            raise ValueError(f"directions[{i}] must be a unit vector to a pulsar, got a zero "
                             f"vector (no line of sight)")
        if abs(norm - 1.0) > _UNIT_TOL:
            raise ValueError(f"directions[{i}] must be a unit vector to a pulsar (norm 1 to "
                             f"{_UNIT_TOL:g}: a range n . r scales with it), got norm {norm:.12g}")
    return N


def cv_model(dt, accel_sigma=0.0, dim=1):
    """Transition ``F`` and process noise ``Q`` of a constant-velocity model, (2 dim, 2 dim).

    ``F = [[I, dt I], [0, I]]``, ``Q = q [[dt^3/3 I, dt^2/2 I], [dt^2/2 I, dt I]]`` with
    ``q = accel_sigma**2`` (m^2/s^3): white acceleration integrated over the step.

    Examples
    --------
    >>> F, Q = cv_model(10.0, 1e-3)
    >>> F.tolist(), round(float(Q[1, 1]), 9)
    ([[1.0, 10.0], [0.0, 1.0]], 1e-05)
    """
    dt = check_real("dt", dt, 0.0, 1e7, lo_open=True)
    q = check_real("accel_sigma", accel_sigma, 0.0, 1.0) ** 2
    eye = np.eye(check_int("dim", dim, 1, 3))
    F = np.block([[eye, dt * eye], [0 * eye, eye]])
    Q = q * np.block([[dt**3 / 3 * eye, dt**2 / 2 * eye], [dt**2 / 2 * eye, dt * eye]])
    return F, Q


def simulate(state0, dt, n, accel_sigma=0.0, rng=None):
    """True states ``x_k = F x_{k-1} + w_k``, ``w_k ~ N(0, Q)``, shape (n + 1, 2 d).

    Parameters
    ----------
    state0 : array_like
        Initial position and velocity, shape (2 d,), d in {1, 2, 3}.
    dt, accel_sigma
        As :func:`cv_model`.
    n : int
        Number of steps, in [1, 1e6].
    rng : numpy.random.Generator or int, optional
        The noise's generator. With ``accel_sigma = 0`` the truth is noise-free and ``rng``
        does not change it: accepted, not refused, so that a caller sweeping
        ``accel_sigma`` down to 0 (chapter 0's slider, :func:`run_line`) keeps one call.

    Examples
    --------
    >>> simulate(np.array([0.0, 5.0]), 2.0, 3)[:, 0].tolist()
    [0.0, 10.0, 20.0, 30.0]
    """
    state0 = check_finite_array("state0", state0)
    if state0.ndim != 1 or state0.size not in (2, 4, 6):
        raise ValueError(f"state0 must be a position and a velocity in 1, 2 or 3 dimensions, "
                         f"shape (2,), (4,) or (6,), got shape {state0.shape}")
    F, Q = cv_model(dt, accel_sigma, state0.size // 2)
    w = make_rng(rng).multivariate_normal(np.zeros(state0.size), Q, check_int("n", n, 1, 10**6))
    out = [state0]
    for wk in w:
        out.append(F @ out[-1] + wk)  # x_k = F x_{k-1} + w_k
    return np.array(out)


class Track(NamedTuple):
    """A filter run: estimates ``x`` (n + 1, 2 d), covariances ``P`` (n + 1, 2 d, 2 d), ranges
    ``z`` (n, m), m, and the normalised innovations squared ``nis`` (n,)."""

    x: np.ndarray
    P: np.ndarray
    z: np.ndarray
    nis: np.ndarray


def track(truth, exposure, x0, P0, pulsar_names=("B0531+21",), directions=((1.0,),),
          accel_sigma=0.0, rng=None, area_m2=1.0):
    """Run the constant-velocity Kalman filter on ranges from folded photons.

    Parameters
    ----------
    truth : array_like
        True states at ``t_k = k exposure`` (:func:`simulate`), shape (n + 1, 2 d), n >= 1,
        with ``n`` times the pulsars at most :data:`MAX_TOAS` (2e5 TOAs, about 7 minutes).
    exposure : float
        Window of each TOA and step of the filter, s, in [1e-3, 1e5] (as
        :func:`~xnavlab.line.measure.range_sigma`).
    x0, P0 : array_like
        The filter's initial estimate and covariance, shapes (2 d,) and (2 d, 2 d).
    pulsar_names : sequence of str
        One pulsar per line of sight (default the Crab alone).
    directions : array_like
        Unit vectors to the pulsars in the line (d = 1) or the plane (d = 2), shape (m, d),
        each of norm 1 to 1e-12 (a zero or non-unit row is refused, not rescaled).
    accel_sigma : float
        The filter's (and truth's) white acceleration, m/s^1.5.
    rng, area_m2
        As :func:`~xnavlab.line.measure.fold_range`.

    Returns
    -------
    Track
    """
    truth = check_finite_array("truth", truth)
    pulsar_names = pulsars.check_names(pulsar_names, "pulsar_names")
    N = check_finite_array("directions", directions)
    if N.ndim != 2:
        raise ValueError(f"directions must hold one row a pulsar, got shape {N.shape}")
    d = N.shape[1]
    if truth.ndim != 2 or truth.shape[1] != 2 * d or N.shape[0] != len(pulsar_names):
        raise ValueError(f"truth must be (n + 1, {2 * d}) and directions one row a pulsar, "
                         f"got {truth.shape} and {N.shape} for {len(pulsar_names)} pulsars")
    if len(truth) < 2:  # no step: a track of no measurement
        raise ValueError(f"truth must hold at least 2 rows (t = 0 and one exposure), got {len(truth)}")
    _check_directions(N)
    m = len(pulsar_names)
    pl = "pulsar" if m == 1 else "pulsars"
    _check_toas((len(truth) - 1) * m, "truth", f"{len(truth) - 1} steps x {m} {pl}",
                f"at most {MAX_TOAS // m + 1} rows with {m} {pl}")
    rng = make_rng(rng)
    exposure = check_real("exposure", exposure, 1e-3, 1e5)  # range_sigma's range
    F, Q = cv_model(exposure, accel_sigma, d)
    H = np.hstack([N, np.zeros_like(N)])  # z_i = n_i . r
    R = np.diag([range_sigma(p, exposure, area_m2) ** 2 for p in pulsar_names])
    x = check_finite_array("x0", x0, (2 * d,))
    P = check_covariance("P0", P0, 2 * d)
    xs, Ps, zs, nis = [x], [P], [], []
    for k in range(1, len(truth)):
        x, P = ekf_predict(x, P, F @ x, F, Q, check=k == 1)  # x- = F x, P- = F P F^T + Q
        z = np.array([fold_range(n @ truth[k, :d], n @ x[:d], p, exposure, rng, area_m2)
                      for p, n in zip(pulsar_names, N, strict=True)])
        x, P, _, _, s = ekf_update(x, P, z, lambda s: H @ s, H, R, check=k == 1)  # K = P- H^T S^-1
        xs.append(x)
        Ps.append(P)
        zs.append(z)
        nis.append(s)
    return Track(np.array(xs), np.array(Ps), np.array(zs), np.array(nis))


def snapshot_covariance(directions, sigmas):
    """Position covariance from one range per pulsar, ``(H^T R^-1 H)^-1``, shape (d, d), m^2.

    ``directions``: shape (n, d), one unit vector a pulsar (norm 1 to 1e-12: a zero row is
    refused, not dropped, and a non-unit one refused, not read as a scaled range), spanning
    the d-dimensional space (two pulsars along one line leave a direction unobserved: a
    ValueError, not a singular inverse); ``sigmas``: shape (n,), their range sigmas, m, each in [1e-3, 1e15].

    Examples
    --------
    >>> snapshot_covariance([[1.0, 0.0], [0.0, 1.0]], [3.0, 4.0]).tolist()
    [[9.0, 0.0], [0.0, 16.0]]
    >>> snapshot_covariance([[1.0, 0.0], [1.0, 0.0]], [1.0, 1.0])
    Traceback (most recent call last):
    ...
    ValueError: directions must span the plane (2 dimensions), got rank 1: a direction no pulsar \
observes has no finite covariance
    """
    H = check_finite_array("directions", directions)
    if H.ndim != 2 or H.shape[0] < 1 or H.shape[1] < 1:
        raise ValueError(f"directions must have shape (n, d), n, d >= 1, got shape {H.shape}")
    _check_directions(H)
    sigmas = check_finite_array("sigmas", sigmas, shape=(H.shape[0],))
    # From 1 mm (no X-ray TOA ranges better; 5e-324 made 1 / sigma^2 infinite) to 1e15 m.
    if sigmas.ndim != 1 or not np.all((sigmas >= 1e-3) & (sigmas <= 1e15)):
        raise ValueError(f"sigmas must be real numbers in [1e-3, 1e15], m, one a direction (shape "
                         f"({H.shape[0]},)), got {sigmas.tolist()!r:.80}")
    d = H.shape[1]
    rank = int(np.linalg.matrix_rank(H))
    if rank < d:
        space = {1: "the line", 2: "the plane", 3: "space"}.get(d, f"R^{d}")
        raise ValueError(f"directions must span {space} ({d} dimensions), got rank {rank}: a "
                         f"direction no pulsar observes has no finite covariance")
    w = 1.0 / sigmas**2
    return np.linalg.inv(H.T @ (w[:, None] * H))  # (H^T R^-1 H)^-1


def run_line(exposure_s=10.0, accel_sigma=0.0, span_s=2000.0, dv=1.0, seed=0):
    """Chapter 0's spacecraft on the line to the Crab, and the filter that tracks it.

    The spacecraft starts :data:`X0` from the SSB at :data:`V0` plus ``dv`` towards the
    Crab; the filter starts 2 km off at :data:`V0` (sigmas 3 km and 2 m/s) and takes one
    TOA every ``exposure_s`` over ``span_s``.

    Parameters
    ----------
    exposure_s : float
        Window of each TOA, s, in [0.1, 1e4].
    accel_sigma : float
        As :func:`cv_model`.
    span_s : float
        Length of the run, s, in [exposure_s, 1e5]: a whole number of exposures (to 1e-9 of
        one), ``span_s / exposure_s`` TOAs. A span between two whole numbers is refused with
        the nearest valid ones (it was cut to the nearest, the truth ending elsewhere than
        asked); every span and exposure of chapter 0's slider divide. At most
        :data:`MAX_TOAS` TOAs: a TOA takes about 2.1 ms on two cores, so the cap, 2e5, keeps a
        run under about 7 minutes (1e5 s of 0.1 s exposures, 1e6 TOAs, took 37); chapter 0,
        the tests and the benchmarks take at most 20,000 (the default span at 0.1 s).
    dv : float
        Velocity offset towards the Crab, m/s, in [-1e5, 1e5].
    seed : int

    Returns
    -------
    truth : ndarray
        True states, shape (n + 1, 2): position (m) and velocity (m/s).
    run : Track
        The filter's run.

    Examples
    --------
    >>> truth, run = run_line(exposure_s=500.0)
    >>> truth.shape, run.z.shape
    ((5, 2), (4, 1))
    """
    exposure_s = check_real("exposure_s", exposure_s, 0.1, 1e4)
    span_s = check_real("span_s", span_s, 1.0, 1e5)
    if span_s < exposure_s:
        raise ValueError(f"span_s must be at least exposure_s ({exposure_s:g} s) and at most "
                         f"1e5 s, got {span_s:g}: a run holds at least one TOA")
    ratio = span_s / exposure_s
    _check_toas(math.floor(ratio + 1e-9), "span_s / exposure_s",
                f"span_s = {span_s:g} s / exposure_s = {exposure_s:g} s",
                f"at most {MAX_TOAS * exposure_s:.6g} s at this exposure")
    n = round(ratio)  # whole TOAs only: a fraction of one was cut without a word
    if abs(ratio - n) > 1e-9:
        lo, hi = math.floor(ratio), math.ceil(ratio)
        raise ValueError(f"span_s must be a whole number of exposures exposure_s = {exposure_s:g} "
                         f"s, got {span_s:g} s ({ratio:.6g} TOAs): the nearest are "
                         f"{lo * exposure_s:g} and {hi * exposure_s:g} s")
    dv = check_real("dv", dv, -1e5, 1e5)
    seed = check_seed("seed", seed)
    truth = simulate(np.array([X0, V0 + dv]), exposure_s, n, accel_sigma, seed)
    run = track(truth, exposure_s, np.array([X0 + 2e3, V0]), np.diag([3e3**2, 2.0**2]),
                accel_sigma=accel_sigma, rng=seed_after(seed))
    return truth, run


def plot_tracking(exposure_s=10.0, accel_sigma=0.0, span_s=2000.0, dv=1.0, seed=0):
    """Chapter 0's slider: the errors of :func:`run_line`'s filter over time; a Figure.

    Top: each TOA's range error and the filter's position error with its 1-sigma band;
    bottom: the velocity error and its band.

    Examples
    --------
    >>> fig = plot_tracking(exposure_s=50.0)
    >>> [ax.get_ylabel() for ax in fig.axes]
    ['position error (m)', 'velocity error (m/s)']
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7, 4.2), layout="constrained")
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    toas, = ax1.plot([], [], ".", color="0.6", ms=3, label="one TOA's range")
    bands, lines = [], []
    for ax in (ax1, ax2):
        bands.append(ax.fill_between([0.0, 1.0], -1.0, 1.0, color="C0", alpha=0.2,
                                     label="filter's 1 sigma"))
        lines.append(ax.plot([], [], color="C0", label="filter")[0])
    ax1.set(ylabel="position error (m)")
    ax2.set(xlabel="time (s)", ylabel="velocity error (m/s)")
    ax1.legend(fontsize=8, loc="lower left", bbox_to_anchor=(0.0, 1.0), ncols=3, frameon=False)

    def update(exposure_s=10.0, accel_sigma=0.0, span_s=2000.0, dv=1.0, seed=0):
        truth, run = run_line(exposure_s, accel_sigma, span_s, dv, seed)
        exposure_s = float(exposure_s)  # run_line checked it: a Fraction or numpy scalar, a float
        n = len(truth) - 1
        t, err = exposure_s * np.arange(n + 1), run.x - truth
        sd = np.sqrt(run.P[:, [0, 1], [0, 1]])
        toas.set_data(t[1:], run.z[:, 0] - truth[1:, 0])
        for i, (band, line) in enumerate(zip(bands, lines, strict=True)):
            band.set_data(t, -sd[:, i], sd[:, i])
            line.set_data(t, err[:, i])
        for ax in (ax1, ax2):
            ax.relim()
        top = 4 * sd[n // 10:, 0].max()
        ax1.set_ylim(-top, top)
        ax2.autoscale_view()
        ax1.autoscale_view(scaley=False)
        fig.suptitle(f"exposure {exposure_s:g} s: {n} TOAs, final 1 sigma {sd[-1, 0]:.0f} m",
                     x=0.99, ha="right", fontsize=10)

    update(exposure_s, accel_sigma, span_s, dv, seed)
    return in_place(fig, update)
