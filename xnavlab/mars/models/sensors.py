"""Measurement models of the three navigation subsystems: XNAV, UV sensor and CNS.

Each model gives the predicted measurement ``h(x)``, its Jacobian ``H = dh/dx``
(shape (m, 6), zero velocity columns) and the noise covariance ``R``; the pure
functions below are vectorised over leading axes of the state where that is cheap.
The sensor classes (:class:`XNAVSensor`, :class:`UVSensor`, :class:`CNSSensor`) hold
the noise levels and also simulate noisy measurements from a truth trajectory.

State ``x = [r, v]``: spacecraft position and velocity relative to Mars, J2000/ICRF
axes, m and m/s. Time: s TDB past J2000.

XNAV, paper eqs. (1), (3)-(4)
    ``z_i = dt_i`` (s), the time-transfer delay of pulsar ``i`` for the spacecraft at
    ``r_M + r`` (:func:`xnavlab.mars.timing.toa.delay`); ``H`` rows ``[d dt_i / d r, 0, 0, 0]``;
    ``R = diag(sigma_i^2)`` with ``sigma_i = ranging accuracy / c`` (500 s, 1 m^2,
    background 0.005 ph/cm^2/s: 109, 344, 1866 and 325 m for the paper's pulsars).
    The filter evaluates ``r_M`` with its own ephemeris, which may differ from the
    truth's.
UV sensor, paper eq. (5)
    ``z = [|r|, u]`` with ``u = -r/|r|`` the unit vector from the spacecraft to the
    Mars centre (4 components). Range noise 5000 m. Direction noise 0.1 deg, applied
    as a rotation of the true unit vector: the measured vector is the true one turned
    by a small angle about a random axis perpendicular to it, the two tangent
    components of the turn independent N(0, sigma^2) (so the total angular error is
    Rayleigh distributed, mean 1.25 sigma), and it stays a unit vector
    (:func:`perturb_direction`). The filter uses ``R = diag(sigma_r^2, sigma_u^2 I3)``:
    because ``u^T dH = 0``, the radial component of the residual carries no
    information and the 3x3 direction block acts exactly like the rank-2 tangent
    covariance ``sigma_u^2 (I - u u^T)``; the effective number of independent
    components (for NIS tests) is 3.
CNS, paper eq. (6)
    ``z_j = arccos(-r . s_j / |r|)``, the starlight angle between star ``j`` and the
    Mars centre, for three stars (:func:`xnavlab.mars.models.stars.pick_three`). The star sensor
    (3 arcsec) perturbs each star direction and the horizon sensor (0.05 deg) the
    Mars direction, both as rotations like the UV sensor's. Linearised, the angle
    errors are ``-a_j . du - b_j . ds_j`` with ``a_j`` the unit tangent at ``u``
    toward ``s_j``; the horizon error is common to the three angles, so
    ``R = sigma_s^2 I + sigma_h^2 A A^T`` (``A`` rows ``a_j``) is *not* diagonal.
    ``H`` rows are ``[a_j / |r|, 0, 0, 0]``: the CNS fixes the direction to Mars only.

Examples
--------
>>> x = np.array([4.0e6, 0.0, 0.0, 0.0, 3000.0, 0.0])
>>> uv_h(x).tolist()
[4000000.0, -1.0, -0.0, -0.0]
>>> uv_jacobian(x)[0].tolist()
[1.0, 0.0, 0.0, 0.0, 0.0, 0.0]
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from xnavlab.core import ephemeris
from xnavlab.core.constants import C
from xnavlab.core.validate import (
    check_choice,
    check_definite,
    check_finite_array,
    check_instance,
    check_items,
    check_real,
    check_vector,
    make_rng,
    off_unit,
    shown,
)
from xnavlab.mars.models import stars
from xnavlab.mars.timing import pulsars, toa

__all__ = [
    "tangent_basis",
    "perturb_direction",
    "xnav_sigma",
    "xnav_h",
    "xnav_jacobian",
    "uv_h",
    "uv_jacobian",
    "uv_R",
    "cns_h",
    "cns_jacobian",
    "cns_R",
    "position_dop",
    "optical_semi_axes",
    "plot_optical_geometry",
    "XNAVSensor",
    "UVSensor",
    "CNSSensor",
]

_ARCSEC = math.pi / (180.0 * 3600.0)
_UV_DIR = math.radians(0.1)  # paper: UV direction 0.1 deg
_HORIZON = math.radians(0.05)  # paper: horizon sensor 0.05 deg


#: A Mars-centred position's distance, m: from 1 m (the spacecraft is not at Mars's centre;
#: 1 / |r| overflows near 1e-308) to 1e13 m (67 au: no Mars navigation; |r|^2 overflows near 1e154).
_POSITION = (1.0, 1e13)
# The smallest noise a sensor takes (m, rad, deg or arcsec): its square, the variance, stays
# a normal float64 (review 35k: a subnormal sigma_dir_deg became 0 rad, refused as sigma_dir).
_SIGMA_MIN = 1e-100
_SIGMA_MIN_RAD = 1e-120  # in rad: below 1e-100 deg or arcsec made rad (never refused as rad)


def _state(x, one=False):
    """States (..., 6), or one (6,) with ``one`` (review 35k: (1, 6) reached matmul)."""
    x = check_vector("x", x, 6) if one else check_finite_array("x", x, shape=(6,))
    with np.errstate(over="ignore"):  # a norm beyond float64 is out of range: refused below
        rn = np.linalg.norm(x[..., :3], axis=-1)
    out = (rn < _POSITION[0]) | (rn > _POSITION[1])
    if np.any(out):
        raise ValueError(f"x must have a non-zero position, {_POSITION[0]:g} m to {_POSITION[1]:g} m "
                         f"from Mars's centre, got {float(rn[out].ravel()[0]):.6g} m")
    return x


# ------------------------------------------------------------------ direction noise


def _unit(name, u):
    """``u`` as finite unit vectors, shape (..., 3), each within 1e-6 of norm 1, else one
    ValueError naming ``name`` (a zero or a scaled direction gives meaningless angles)."""
    u = check_finite_array(name, u, shape=(3,))
    i, norm = off_unit(u, 1e-6)
    if i is not None:
        raise ValueError(f"{name} must hold unit vectors (norm within 1e-6 of 1), got one of "
                         f"norm {float(np.ravel(norm)[i]):.6g}")
    return u


def tangent_basis(u):
    """Two unit vectors completing ``u`` to a right-handed orthonormal basis.

    ``e1 = normalise(z x u)`` (``x x u`` when ``u`` is within 1e-6 of the z axis) and
    ``e2 = u x e1``.

    Parameters
    ----------
    u : array_like, shape (..., 3)
        Unit vectors (norm within 1e-6 of 1).

    Returns
    -------
    e1, e2 : ndarray, shape (..., 3)

    Examples
    --------
    >>> e1, e2 = tangent_basis(np.array([1.0, 0.0, 0.0]))
    >>> (e1 + 0.0).tolist(), (e2 + 0.0).tolist()
    ([0.0, 1.0, 0.0], [0.0, 0.0, 1.0])
    """
    u = _unit("u", u)
    ux, uy, uz = u[..., 0], u[..., 1], u[..., 2]
    polar = np.abs(uz) > 1.0 - 1e-12
    zero = np.zeros_like(ux)
    # e1 = z x u = (-uy, ux, 0), or x x u = (0, -uz, uy) near the poles, normalised
    a0 = np.where(polar, zero, -uy)
    a1 = np.where(polar, -uz, ux)
    a2 = np.where(polar, uy, zero)
    n = np.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
    e1 = np.stack([a0 / n, a1 / n, a2 / n], axis=-1)
    e2 = np.stack([uy * e1[..., 2] - uz * e1[..., 1], uz * e1[..., 0] - ux * e1[..., 2],
                   ux * e1[..., 1] - uy * e1[..., 0]], axis=-1)  # e2 = u x e1
    return e1, e2


def perturb_direction(u, sigma, w):
    """Turn unit vectors by small random angles: the direction-noise model.

    ``d = sigma (w1 e1 + w2 e2)`` in the tangent plane of ``u``
    (:func:`tangent_basis`), then ``u' = cos|d| u + sin|d| d/|d|`` (a rotation by
    ``|d|`` toward ``d``). Each tangent component of the error is N(0, sigma^2) when
    ``w`` is standard normal.

    Parameters
    ----------
    u : array_like, shape (..., 3)
        True unit vectors.
    sigma : float or array_like, shape (..., 1)
        Per-axis angular standard deviation, rad, >= 0: one, or one per direction.
    w : array_like, shape (..., 2)
        Standard normal draws.

    Returns
    -------
    ndarray, shape (..., 3)
        Unit vectors.

    Examples
    --------
    >>> v = perturb_direction(np.array([0.0, 0.0, 1.0]), 0.01, np.array([1.0, 0.0]))
    >>> round(float(np.degrees(np.arccos(v[2]))), 4), round(float(np.linalg.norm(v)), 12)
    (0.573, 1.0)
    """
    u = _unit("u", u)
    w = check_finite_array("w", w, shape=(2,))
    sigma = check_finite_array("sigma", sigma)
    if np.any(sigma < 0):
        raise ValueError("sigma must be >= 0, rad")
    one = w.shape[:-1] + (1,)  # one angle per direction
    try:
        fits = sigma.size > 0 and np.broadcast_shapes(sigma.shape, one) == one
    except ValueError:
        fits = False
    if not fits:
        raise ValueError(f"sigma must be one number, rad, or one per direction (shape {one}), "
                         f"got shape {sigma.shape}")
    e1, e2 = tangent_basis(u)
    w1, w2 = w[..., 0:1], w[..., 1:2]
    wn = np.sqrt(w1 * w1 + w2 * w2)
    ang = sigma * wn  # |d|, since e1 and e2 are orthonormal
    # u' = cos|d| u + sin|d| d/|d|, with d/|d| = (w1 e1 + w2 e2)/|w|
    f = np.sin(ang) / np.where(wn > 0.0, wn, 1.0)
    return np.cos(ang) * u + f * (w1 * e1 + w2 * e2)


# ---------------------------------------------------------------------------- XNAV


def xnav_sigma(pulsar_names=pulsars.PAPER_PULSARS, area_m2=1.0, t_obs=500.0,
               background=0.005):
    """Per-pulsar delay noise, s: ranging accuracy (Sheikh et al. 2006) divided by c.

    ``area_m2`` (m^2, in [1e-6, 1e3]), ``t_obs`` (s, in [1e-6, 1e7]) and ``background``
    (ph/cm^2/s, in [0, 10]) are those of :func:`xnavlab.mars.timing.pulsars.toa_sigma`.

    Examples
    --------
    >>> np.round(xnav_sigma() * C).astype(int).tolist()
    [109, 345, 1868, 326]
    """
    background = check_real("background", background, 0.0, 10.0)  # named here, not as pulsars'
    return np.array([pulsars.ranging_accuracy(p, area_m2, t_obs, background)
                     for p in pulsars.check_names(pulsar_names, "pulsar_names")]) / C


def xnav_h(x, r_mars_ssb, r_sun_ssb, n, distance):
    """Predicted XNAV delays, paper eqs. (1) and (3): shape (..., k), s.

    Parameters
    ----------
    x : array_like, shape (..., 6)
        Mars-centred state.
    r_mars_ssb : array_like, shape (..., 3)
        Mars relative to the SSB (from the filter's ephemeris), m.
    r_sun_ssb : array_like, shape (..., 3)
        Sun relative to the SSB, m.
    n : array_like, shape (k, 3)
        Pulsar unit vectors.
    distance : array_like, shape (k,)
        Pulsar distances, m.

    Examples
    --------
    >>> n, d = pulsars.directions()
    >>> z = xnav_h(np.r_[4e6, 0, 0, 0, 0, 0], [2e11, 0, 0], [1e8, 0, 0], n, d)
    >>> z.shape
    (4,)
    """
    x = _state(x)
    r_ssb = check_finite_array("r_mars_ssb", r_mars_ssb, shape=(3,)) + x[..., :3]
    return toa.delay(r_ssb, n, distance, r_sun_ssb, shapiro="paper")  # paper eq. (1)


def xnav_jacobian(x, r_mars_ssb, r_sun_ssb, n, distance):
    """XNAV Jacobian, paper eq. (4): rows ``[h_ix, h_iy, h_iz, 0, 0, 0]``, shape (k, 6), s/m.

    Examples
    --------
    >>> n, d = pulsars.directions()
    >>> H = xnav_jacobian(np.r_[4e6, 0, 0, 0, 0, 0], [2e11, 0, 0], [1e8, 0, 0], n, d)
    >>> H.shape, bool(np.allclose(H[:, :3] * C, n, atol=1e-6)), H[:, 3:].any()
    ((4, 6), True, False)
    """
    x = _state(x)
    r_ssb = check_finite_array("r_mars_ssb", r_mars_ssb, shape=(3,)) + x[..., :3]
    g = toa.gradient(r_ssb, n, distance, r_sun_ssb, shapiro="paper")  # paper eq. (4)
    H = np.zeros(g.shape[:-1] + (6,))
    H[..., :3] = g
    return H


# ------------------------------------------------------------------------- UV sensor


def uv_h(x):
    """UV sensor measurement, paper eq. (5): ``[|r|, -r/|r|]``, shape (..., 4).

    Examples
    --------
    >>> uv_h(np.array([0.0, 3e6, 4e6, 0, 0, 0])).tolist()
    [5000000.0, -0.0, -0.6, -0.8]
    """
    x = _state(x)
    r = x[..., :3]
    rn = np.linalg.norm(r, axis=-1, keepdims=True)
    return np.concatenate([rn, -r / rn], axis=-1)  # paper eq. (5)


def uv_jacobian(x):
    """Jacobian of :func:`uv_h`, shape (4, 6).

    ``d|r|/dr = r^T/|r|`` and ``d(-r/|r|)/dr = -(I - r r^T/|r|^2)/|r|``.

    Examples
    --------
    >>> H = uv_jacobian(np.array([2.0, 0, 0, 0, 0, 0]))
    >>> H[:, :3].tolist()
    [[1.0, 0.0, 0.0], [-0.0, -0.0, -0.0], [-0.0, -0.5, -0.0], [-0.0, -0.0, -0.5]]
    """
    x = _state(x, one=True)
    r = x[:3]
    rn = np.linalg.norm(r)
    e = r / rn
    H = np.zeros((4, 6))
    H[0, :3] = e
    H[1:, :3] = -(np.eye(3) - np.outer(e, e)) / rn
    return H


def uv_R(sigma_range=5000.0, sigma_dir=_UV_DIR):
    """UV noise covariance ``diag(sigma_range^2, sigma_dir^2 I3)``, shape (4, 4).

    ``sigma_range`` in m, in [1e-100, 1e7] (as :class:`UVSensor`'s); ``sigma_dir`` in
    [1e-120, pi] rad (below, a variance is no normal float).

    Examples
    --------
    >>> np.diag(uv_R(10.0, 0.5)).tolist()
    [100.0, 0.25, 0.25, 0.25]
    """
    sigma_range = check_real("sigma_range", sigma_range, _SIGMA_MIN, 1e7)
    sigma_dir = check_real("sigma_dir", sigma_dir, _SIGMA_MIN_RAD, math.pi)
    return np.diag([sigma_range**2, sigma_dir**2, sigma_dir**2, sigma_dir**2])


# ------------------------------------------------------------------------------ CNS


def _angles(u, s):
    """Angles between unit vectors ``u`` (..., 3) and rows of ``s`` (k, 3), robust near 0 and pi."""
    cross = np.linalg.norm(np.cross(u[..., None, :], s), axis=-1)
    return np.arctan2(cross, u @ s.T)


def cns_h(x, star_dirs):
    """Starlight angles, paper eq. (6): ``arccos(-r . s_j / |r|)``, shape (..., k), rad.

    Evaluated as ``atan2(|u x s|, u . s)`` with ``u = -r/|r|`` (same value, accurate
    near 0 and pi).

    Parameters
    ----------
    x : array_like, shape (..., 6)
        Mars-centred states, m and m/s, the position 1 m to 1e13 m from Mars's centre (as
        every function of this module taking ``x``).
    star_dirs : array_like, shape (k, 3)
        Unit vectors to the stars (norm within 1e-6 of 1; :func:`cns_jacobian` and
        :func:`cns_R` take the same).

    Examples
    --------
    >>> z = cns_h(np.array([1.0, 0, 0, 0, 0, 0]), np.eye(3))
    >>> np.round(np.degrees(z), 9).tolist()
    [180.0, 90.0, 90.0]
    """
    x = _state(x)
    s = _unit("star_dirs", star_dirs).reshape(-1, 3)
    r = x[..., :3]
    u = -r / np.linalg.norm(r, axis=-1, keepdims=True)
    return _angles(u, s)  # paper eq. (6)


def _cns_tangents(x, s):
    r = x[:3]
    rn = np.linalg.norm(r)
    u = -r / rn
    t = s - np.outer(s @ u, u)  # s_j - (u . s_j) u
    tn = np.linalg.norm(t, axis=1, keepdims=True)
    if np.any(tn < 1e-12):
        raise ValueError("a star lies along the Mars direction: its starlight angle has no gradient")
    return t / tn, rn


def cns_jacobian(x, star_dirs):
    """Jacobian of :func:`cns_h`: rows ``[a_j / |r|, 0, 0, 0]``, shape (k, 6), rad/m.

    ``a_j`` is the unit vector tangent at ``u = -r/|r|`` toward star ``j``.

    Examples
    --------
    >>> H = cns_jacobian(np.array([1e6, 0, 0, 0, 0, 0]), np.array([[0.0, 1.0, 0.0]]))
    >>> (H[0, :3] * 1e6).tolist()
    [0.0, 1.0, 0.0]
    """
    x = _state(x, one=True)
    s = _unit("star_dirs", star_dirs).reshape(-1, 3)
    a, rn = _cns_tangents(x, s)
    H = np.zeros((s.shape[0], 6))
    H[:, :3] = a / rn
    return H


def cns_R(x, star_dirs, sigma_star=3.0 * _ARCSEC, sigma_horizon=_HORIZON):
    """CNS noise covariance ``sigma_s^2 I + sigma_h^2 A A^T``, shape (k, k), rad^2.

    The horizon-sensor error of the Mars direction is shared by every starlight
    angle (``A`` rows: unit tangents at the Mars direction toward each star); the
    star-sensor errors are independent. ``x`` is one state (6,); ``sigma_star`` and
    ``sigma_horizon`` are in [1e-120, pi] rad.

    Examples
    --------
    >>> R = cns_R(np.array([1e6, 0, 0, 0, 0, 0]), np.array([[0.0, 1, 0], [0, 1, 0]]), 1.0, 2.0)
    >>> R.tolist()
    [[5.0, 4.0], [4.0, 5.0]]
    """
    x = _state(x, one=True)
    s = _unit("star_dirs", star_dirs).reshape(-1, 3)
    sigma_star = check_real("sigma_star", sigma_star, _SIGMA_MIN_RAD, math.pi)
    sigma_horizon = check_real("sigma_horizon", sigma_horizon, _SIGMA_MIN_RAD, math.pi)
    a, _ = _cns_tangents(x, s)
    return sigma_star**2 * np.eye(s.shape[0]) + sigma_horizon**2 * (a @ a.T)


# -------------------------------------------------------------------------- geometry


def position_dop(H, R):
    """Semi-axes of the one-epoch position error ellipsoid, m (inf where unobservable).

    From the position columns ``Hr = H[:, :3]``: the information ``Hr^T R^-1 Hr`` has
    eigenvalues ``l_k``; the semi-axes are ``1/sqrt(l_k)``, largest first. A rank-2
    information (a direction measurement alone) gives one infinite axis, and an ``H``
    without position columns three: an unobservable direction is a result, not an error.
    ``R`` (m, m) must be positive definite (ValueError naming it: an indefinite or singular
    ``R`` gave an infinite axis as if unobservable).

    Examples
    --------
    >>> position_dop(np.hstack([np.eye(3), np.zeros((3, 3))]), np.eye(3) * 4.0).tolist()
    [2.0, 2.0, 2.0]
    """
    H = np.atleast_2d(check_finite_array("H", H))
    if H.ndim != 2 or H.shape[1] < 3:
        raise ValueError(f"H must have shape (m, n) with n >= 3 (position first), got shape "
                         f"{H.shape}")
    R = check_definite("R", np.atleast_2d(check_finite_array("R", R)), H.shape[0])
    Hr = H[:, :3]
    with np.errstate(over="ignore", invalid="ignore"):  # an inverse beyond float64: refused below
        info = Hr.T @ np.linalg.solve(R, Hr)
    if not np.all(np.isfinite(info)):  # R = 5e-324 I was LinAlgError 'Eigenvalues did not converge'
        raise ValueError(f"R must have an inverse within float64 (smallest variance "
                         f"{float(np.diag(R).min()):.3g}: its information H^T R^-1 H overflows)")
    lam = np.linalg.eigvalsh(0.5 * (info + info.T))
    tol = lam.max() * 1e-10 if lam.max() > 0 else 0.0
    with np.errstate(divide="ignore"):
        axes = np.where(lam > tol, 1.0 / np.sqrt(np.maximum(lam, tol)), np.inf)
    return np.sort(axes)[::-1]


def optical_semi_axes(x, uv, cns):
    """One-epoch position error ellipsoids of the UV sensor, the CNS and both together.

    :func:`position_dop` of each sensor's Jacobian and noise at the state ``x``, and of the
    two stacked (independent noises: ``R = blockdiag(R_uv, R_cns)``).

    Parameters
    ----------
    x : array_like, shape (6,)
        Mars-centred state, m and m/s.
    uv : UVSensor
    cns : CNSSensor

    Returns
    -------
    dict
        ``"UV"``, ``"CNS"``, ``"UV + CNS"``: semi-axes, m, largest first (inf where
        unobservable), each of shape (3,).

    Examples
    --------
    >>> x = np.array([4.0e6, 0.0, 0.0, 0.0, 3000.0, 0.0])
    >>> ax = optical_semi_axes(x, UVSensor(), CNSSensor(("Sirius", "Canopus", "Vega")))
    >>> ax["UV"].round(-1).tolist(), bool(np.isinf(ax["CNS"][0]))
    ([6980.0, 6980.0, 5000.0], True)
    """
    x = _state(x, one=True)
    check_instance("uv", uv, UVSensor, "a UVSensor")
    check_instance("cns", cns, CNSSensor, "a CNSSensor")
    h_uv, r_uv = uv.jacobian(x), uv.R()
    h_c, r_c = cns.jacobian(x), cns.R(x)
    n_uv, n_c = r_uv.shape[0], r_c.shape[0]
    r_both = np.block([[r_uv, np.zeros((n_uv, n_c))], [np.zeros((n_c, n_uv)), r_c]])
    return {"UV": position_dop(h_uv, r_uv), "CNS": position_dop(h_c, r_c),
            "UV + CNS": position_dop(np.vstack([h_uv, h_c]), r_both)}


def plot_optical_geometry(sigma_dir_deg=0.1, sigma_horizon_deg=0.05, vmag_max=1.0):
    """Semi-axes of the one-epoch ellipsoids (:func:`optical_semi_axes`) along one revolution.

    The paper's orbit from ``MARS_T0`` (one 8252-s revolution of the cached truth, every
    240 s), the CNS stars picked by :func:`xnavlab.mars.models.stars.pick_three` with ``vmag_max``.
    A pure function of its arguments, for chapter 4's slider.

    Parameters
    ----------
    sigma_dir_deg : float
        UV direction noise, deg.
    sigma_horizon_deg : float
        Horizon-sensor noise, deg.
    vmag_max : float
        Magnitude limit of the star rule.

    Returns
    -------
    matplotlib.figure.Figure
        One log-scale axes: the largest finite and the smallest semi-axis (km) of the UV,
        CNS and combined ellipsoids; not registered with pyplot. It carries an in-place
        update (:func:`xnavlab.core.plotting.in_place`) that a live slider calls.

    Examples
    --------
    >>> fig = plot_optical_geometry()
    >>> len(fig.axes[0].lines), fig.axes[0].get_title()
    (6, 'stars Arcturus, Procyon, Acrux')
    """
    from matplotlib.figure import Figure
    from matplotlib.ticker import FuncFormatter

    from xnavlab.core.plotting import in_place, sparse_log_minors
    from xnavlab.mars.models import dynamics

    t0 = dynamics.MARS_T0
    t = t0 + np.arange(0.0, 8252.0 + 60.0, 60.0)  # one revolution (chapter 3), cached truth
    hours = (t[::4] - t0) / 3600.0
    # the layout every frame shares; update() sets the curves, limits and title
    fig = Figure(figsize=(8, 3.4), layout="constrained")
    ax = fig.add_subplot()
    curves = {}
    for k, color in (("UV", "C0"), ("CNS", "C1"), ("UV + CNS", "C2")):
        curves[k] = (ax.plot(hours, np.ones(hours.size), color=color,
                             label=f"{k}: largest finite axis")[0],
                     ax.plot(hours, np.ones(hours.size), color=color, ls=":",
                             label=f"{k}: smallest axis")[0])
    ax.set(xlabel="time (h)", ylabel="semi-axis (km)", yscale="log")
    sparse_log_minors(ax)  # 2 and 5 of each decade, labelled as plain numbers
    plain = FuncFormatter(lambda v, _: f"{v:g}")
    ax.yaxis.set_major_formatter(plain)
    ax.yaxis.set_minor_formatter(plain)
    fig.legend(fontsize=7, ncol=3, loc="outside lower center")  # off the curves

    def update(sigma_dir_deg=0.1, sigma_horizon_deg=0.05, vmag_max=1.0):
        names = stars.pick_three(vmag_max=vmag_max, t=t0)
        uv = UVSensor(sigma_dir_deg=sigma_dir_deg)
        cns = CNSSensor(names, sigma_horizon_deg=sigma_horizon_deg, epoch=t0)
        x = dynamics.truth(t)[::4]
        rows = [optical_semi_axes(xi, uv, cns) for xi in x]
        for k, (largest, smallest) in curves.items():
            a = np.array([r[k] for r in rows])
            finite = np.where(np.isfinite(a), a, np.nan)
            largest.set_ydata(finite[:, 0] / 1e3)
            smallest.set_ydata(finite[:, -1] / 1e3)
        ax.set_title(f"stars {', '.join(names)}")
        ax.relim()
        ax.autoscale_view()
        return None

    update(sigma_dir_deg, sigma_horizon_deg, vmag_max)
    return in_place(fig, update)


# --------------------------------------------------------------------------- classes


@dataclass
class XNAVSensor:
    """The XNAV subsystem's sensor: delays of a chosen pulsar set.

    Parameters
    ----------
    pulsar_names : tuple of str
        Pulsars (default: the paper's four).
    sigma : array_like, shape (k,), optional
        Delay noise, s; default from :func:`xnav_sigma` with ``area_m2``, ``t_obs``
        and ``background``.
    area_m2, t_obs, background : float
        Of :func:`xnav_sigma`; with ``sigma`` given they are unused, and one set away from
        its default (1 m^2, 500 s, 0.005 ph/cm^2/s) is refused.
    ephem : {"de421", "de405"}
        Ephemeris for Mars and the Sun in the predicted delays.

    Examples
    --------
    >>> xs = XNAVSensor()
    >>> xs.dim, xs.components[0]
    (4, 'B0531+21')
    """

    pulsar_names: tuple = pulsars.PAPER_PULSARS
    sigma: np.ndarray | None = None
    area_m2: float = 1.0
    t_obs: float = 500.0
    background: float = 0.005
    ephem: str = "de421"
    name: str = field(default="xnav", init=False)

    def __post_init__(self):
        self.pulsar_names = pulsars.check_names(self.pulsar_names, "pulsar_names")
        self.n, self.distance = pulsars.directions(self.pulsar_names)
        check_choice("ephem", self.ephem, ephemeris.EPHEMERIDES)  # not at the first h (review 35j)
        if self.sigma is not None:  # then the noise settings would be dropped (review 35j)
            for name, default in (("area_m2", 1.0), ("t_obs", 500.0), ("background", 0.005)):
                value = getattr(self, name)
                if not (isinstance(value, float | int) and not isinstance(value, bool)
                        and value == default):
                    raise ValueError(f"{name} = {shown(value)} is unused: sigma gives the delay "
                                     f"noise it would compute; give one of them")
        if self.sigma is None:
            self.sigma = xnav_sigma(self.pulsar_names, self.area_m2, self.t_obs, self.background)
        self.sigma = check_finite_array("sigma", self.sigma).reshape(-1)
        if self.sigma.shape != (len(self.pulsar_names),) or np.any(self.sigma <= 0):
            raise ValueError(f"sigma must hold {len(self.pulsar_names)} positive values, s")

    @property
    def dim(self):
        return len(self.pulsar_names)

    @property
    def components(self):
        return self.pulsar_names

    def bodies(self, t):
        """Mars and Sun SSB positions from this sensor's ephemeris at ``t``, each (..., 3)."""
        return ephemeris.position("mars", t, self.ephem), ephemeris.position("sun", t, self.ephem)

    def h(self, x, t):
        """Predicted delays (..., k), s."""
        rm, rs = self.bodies(t)
        return xnav_h(x, rm, rs, self.n, self.distance)

    def jacobian(self, x, t):
        """Jacobian (k, 6), s/m."""
        rm, rs = self.bodies(t)
        return xnav_jacobian(x, rm, rs, self.n, self.distance)

    def R(self, x=None):
        """Noise covariance ``diag(sigma^2)``, s^2."""
        return np.diag(self.sigma**2)

    def simulate(self, t, states, rng=None, noise=None):
        """Noisy delays for truth ``states`` (n, 6) at ``t`` (n,); shape (n, k), s.

        ``noise`` (n, k) standard normal draws may be passed instead of ``rng``.
        """
        states = check_finite_array("states", states, shape=(6,))
        z = self.h(states, t)
        if noise is None:
            noise = make_rng(rng).standard_normal(z.shape)
        return z + self.sigma * noise


@dataclass
class UVSensor:
    """The UV sensor (paper eq. (5)): range and unit vector to the Mars centre.

    Parameters
    ----------
    sigma_range : float
        Range noise, m (paper: 5000), in [1e-100, 1e7].
    sigma_dir_deg : float
        Per-axis direction noise, deg (paper: 0.1), in [1e-100, 90], applied by
        :func:`perturb_direction`.

    Examples
    --------
    >>> uv = UVSensor()
    >>> z = uv.simulate(np.array([[4e6, 0, 0, 0, 3e3, 0]]), rng=1)
    >>> z.shape, round(float(np.linalg.norm(z[0, 1:])), 12)
    ((1, 4), 1.0)
    """

    sigma_range: float = 5000.0
    sigma_dir_deg: float = 0.1
    name: str = field(default="uv", init=False)
    components: tuple = field(default=("range", "ux", "uy", "uz"), init=False)
    dim: int = field(default=4, init=False)

    def __post_init__(self):
        self.sigma_range = check_real("sigma_range", self.sigma_range, _SIGMA_MIN, 1e7)
        self.sigma_dir_deg = check_real("sigma_dir_deg", self.sigma_dir_deg, _SIGMA_MIN, 90.0)

    @property
    def sigma_dir(self):
        """Direction noise, rad."""
        return math.radians(self.sigma_dir_deg)

    def h(self, x, t=None):
        return uv_h(x)

    def jacobian(self, x, t=None):
        return uv_jacobian(x)

    def R(self, x=None):
        return uv_R(self.sigma_range, self.sigma_dir)

    def simulate(self, states, rng=None, noise=None):
        """Noisy ``[range, u]`` for truth ``states`` (n, 6); shape (n, 4).

        ``noise`` (n, 3) standard normal draws (range, two tangent axes) may be passed
        instead of ``rng``.
        """
        states = check_finite_array("states", states, shape=(6,))
        z = uv_h(states)
        if noise is None:
            noise = make_rng(rng).standard_normal(z.shape[:-1] + (3,))
        out = np.empty_like(z)
        out[..., 0] = z[..., 0] + self.sigma_range * noise[..., 0]
        out[..., 1:] = perturb_direction(z[..., 1:], self.sigma_dir, noise[..., 1:3])
        return out


@dataclass
class CNSSensor:
    """The CNS (paper eq. (6)): starlight angles between three stars and the Mars centre.

    Parameters
    ----------
    star_names : tuple of str, optional
        Stars; default :func:`xnavlab.mars.models.stars.pick_three`.
    sigma_star_arcsec : float
        Star-sensor noise per axis, arcsec (paper: 3), in [1e-100, 3600].
    sigma_horizon_deg : float
        Horizon-sensor noise per axis, deg (paper: 0.05), in [1e-100, 90].
    epoch : float
        Epoch for the star directions (proper motion), s TDB past J2000, in [-1e11, 1e11].

    Examples
    --------
    >>> cns = CNSSensor()
    >>> cns.star_names, cns.dim
    (('Arcturus', 'Procyon', 'Acrux'), 3)
    """

    star_names: tuple | None = None
    sigma_star_arcsec: float = 3.0
    sigma_horizon_deg: float = 0.05
    epoch: float = 0.0
    name: str = field(default="cns", init=False)

    def __post_init__(self):
        # review 35k: refused as pick_three's or directions' 't'
        self.epoch = check_real("epoch", self.epoch, -1e11, 1e11)
        if self.star_names is None:
            self.star_names = stars.pick_three(t=self.epoch)
        # a list of at least one star, none twice (its information would count twice), as
        # MarsScenario's stars
        self.star_names = check_items("star_names", self.star_names, "star",
                                      lambda _, s: stars.get(s).name)
        self.star_names = tuple(stars.get(s).name for s in self.star_names)
        self.sigma_star_arcsec = check_real("sigma_star_arcsec", self.sigma_star_arcsec,
                                            _SIGMA_MIN, 3600.0)
        self.sigma_horizon_deg = check_real("sigma_horizon_deg", self.sigma_horizon_deg,
                                            _SIGMA_MIN, 90.0)
        self.star_dirs = stars.directions(self.star_names, self.epoch)

    @property
    def dim(self):
        return len(self.star_names)

    @property
    def components(self):
        return self.star_names

    @property
    def sigma_star(self):
        return self.sigma_star_arcsec * _ARCSEC

    @property
    def sigma_horizon(self):
        return math.radians(self.sigma_horizon_deg)

    def h(self, x, t=None):
        return cns_h(x, self.star_dirs)

    def jacobian(self, x, t=None):
        return cns_jacobian(x, self.star_dirs)

    def R(self, x):
        return cns_R(x, self.star_dirs, self.sigma_star, self.sigma_horizon)

    def simulate(self, states, rng=None, noise=None):
        """Noisy starlight angles for truth ``states`` (n, 6); shape (n, k), rad.

        The Mars direction is perturbed once per epoch (horizon sensor) and each star
        direction separately (star sensor). ``noise`` (n, 2 + 2k) standard normal
        draws may be passed instead of ``rng``.
        """
        states = check_finite_array("states", states, shape=(6,))
        r = states[..., :3]
        u = -r / np.linalg.norm(r, axis=-1, keepdims=True)
        k = self.dim
        if noise is None:
            noise = make_rng(rng).standard_normal(u.shape[:-1] + (2 + 2 * k,))
        u_m = perturb_direction(u, self.sigma_horizon, noise[..., 0:2])
        out = np.empty(u.shape[:-1] + (k,))
        for j in range(k):
            s_m = perturb_direction(np.broadcast_to(self.star_dirs[j], u.shape),
                                    self.sigma_star, noise[..., 2 + 2 * j:4 + 2 * j])
            out[..., j] = np.arctan2(np.linalg.norm(np.cross(u_m, s_m), axis=-1),
                                     np.sum(u_m * s_m, axis=-1))
        return out
