"""Compiled (numba) draws of the UV and CNS measurement series of the Mars run.

:func:`simulate_uv` and :func:`simulate_cns` draw the 30-day series of
:func:`xnavlab.mars.navigation.scenarios.prepare` from pre-drawn standard normal noise, with the models of
:meth:`xnavlab.mars.models.sensors.UVSensor.simulate` and
:meth:`~xnavlab.mars.models.sensors.CNSSensor.simulate`
(equal to rounding, tested), without the numpy temporaries. Separate from
:mod:`xnavlab.mars.kernel.kernels` (the filter's compilation unit), which never calls them.
"""

from __future__ import annotations

import math

from numba import njit

__all__ = ["simulate_uv", "simulate_cns"]



@njit(cache=True, inline="always", _nrt=False)
def _perturb(u0, u1, u2, sigma, w1, w2):
    """:func:`xnavlab.mars.models.sensors.perturb_direction` for one unit vector (same operations)."""
    polar = abs(u2) > 1.0 - 1e-12
    # e1 = z x u = (-uy, ux, 0), or x x u = (0, -uz, uy) near the poles, normalised
    a0 = 0.0 if polar else -u1
    a1 = -u2 if polar else u0
    a2 = u1 if polar else 0.0
    n = math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
    e10, e11, e12 = a0 / n, a1 / n, a2 / n
    e20 = u1 * e12 - u2 * e11  # e2 = u x e1
    e21 = u2 * e10 - u0 * e12
    e22 = u0 * e11 - u1 * e10
    wn = math.sqrt(w1 * w1 + w2 * w2)
    ang = sigma * wn
    f = math.sin(ang) / (wn if wn > 0.0 else 1.0)
    c = math.cos(ang)
    # u' = cos|d| u + sin|d| d/|d|, d/|d| = (w1 e1 + w2 e2)/|w|
    return (c * u0 + f * (w1 * e10 + w2 * e20), c * u1 + f * (w1 * e11 + w2 * e21),
            c * u2 + f * (w1 * e12 + w2 * e22))


@njit(cache=True)
def simulate_uv(states, noise, sigma_range, sigma_dir, out):
    """Noisy UV measurements ``[range, u]`` (paper eq. (5)), compiled.

    The same model and operations as :meth:`xnavlab.mars.models.sensors.UVSensor.simulate`
    (range plus white noise; the unit vector turned by
    :func:`xnavlab.mars.models.sensors.perturb_direction`),
    compiled; equal to it to rounding (the sine and cosine may differ in the last bit).

    Parameters
    ----------
    states : ndarray, shape (n, 6)
        True states, Mars-centred J2000, m and m/s.
    noise : ndarray, shape (n, 3)
        Standard normal draws: range, then the two tangent axes.
    sigma_range, sigma_dir : float
        Range noise, m, and per-axis direction noise, rad.
    out : ndarray, shape (n, 4)
        Filled with the measurements.

    Returns
    -------
    ndarray, shape (n, 4)
        ``out``.

    Examples
    --------
    >>> x = np.array([[3e6, 0.0, 4e6, 0, 0, 0]])
    >>> z = simulate_uv(x, np.zeros((1, 3)), 5000.0, 1e-3, np.empty((1, 4)))
    >>> z.tolist()
    [[5000000.0, -0.6, 0.0, -0.8]]
    """
    for k in range(states.shape[0]):
        r0, r1, r2 = states[k, 0], states[k, 1], states[k, 2]
        rn = math.sqrt(r0 * r0 + r1 * r1 + r2 * r2)  # paper eq. (5)
        out[k, 0] = rn + sigma_range * noise[k, 0]
        out[k, 1], out[k, 2], out[k, 3] = _perturb(-r0 / rn, -r1 / rn, -r2 / rn, sigma_dir,
                                                   noise[k, 1], noise[k, 2])
    return out


@njit(cache=True)
def simulate_cns(states, noise, star_dirs, sigma_star, sigma_horizon, out):
    """Noisy starlight angles (paper eq. (6)), rad, compiled.

    The Mars direction is turned once per epoch (horizon sensor, ``noise[:, 0:2]``) and
    each star direction separately (star sensor, ``noise[:, 2 + 2j:4 + 2j]``), with the
    operations of :meth:`xnavlab.mars.models.sensors.CNSSensor.simulate`; equal to it to rounding.

    Parameters
    ----------
    states : ndarray, shape (n, 6)
        True states, m and m/s.
    noise : ndarray, shape (n, 2 + 2k)
        Standard normal draws.
    star_dirs : ndarray, shape (k, 3)
        Unit vectors to the stars.
    sigma_star, sigma_horizon : float
        Star-sensor and horizon-sensor noise per axis, rad.
    out : ndarray, shape (n, k)
        Filled with the angles.

    Returns
    -------
    ndarray, shape (n, k)
        ``out``.

    Examples
    --------
    >>> a = simulate_cns(np.array([[4e6, 0.0, 0, 0, 0, 0]]), np.zeros((1, 4)),
    ...                  np.array([[0.0, 1.0, 0.0]]), 1e-5, 1e-3, np.empty((1, 1)))
    >>> round(float(np.degrees(a[0, 0])), 9)
    90.0
    """
    for e in range(states.shape[0]):
        r0, r1, r2 = states[e, 0], states[e, 1], states[e, 2]
        rn = math.sqrt(r0 * r0 + r1 * r1 + r2 * r2)
        m0, m1, m2 = _perturb(-r0 / rn, -r1 / rn, -r2 / rn, sigma_horizon,
                              noise[e, 0], noise[e, 1])
        for j in range(star_dirs.shape[0]):
            s0, s1, s2 = _perturb(star_dirs[j, 0], star_dirs[j, 1], star_dirs[j, 2], sigma_star,
                                  noise[e, 2 + 2 * j], noise[e, 3 + 2 * j])
            c0 = m1 * s2 - m2 * s1
            c1 = m2 * s0 - m0 * s2
            c2 = m0 * s1 - m1 * s0
            # the angle between the Mars centre and the star, paper eq. (6)
            out[e, j] = math.atan2(math.sqrt(c0 * c0 + c1 * c1 + c2 * c2),
                                   m0 * s0 + m1 * s1 + m2 * s2)
    return out
