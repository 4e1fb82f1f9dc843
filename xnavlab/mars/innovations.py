"""Innovations of the Mars subsystems against the master: propagation, whitening, a wavelet.

The fault-tolerant loop (:mod:`xnavlab.mars.fault_tolerance`) watches XNAV, and with the
combined detector every subsystem, on its innovations ``nu = z - h(x)`` against the master
filter's state at a recent record, propagated to the measurement. This module holds the pieces
of that computation that do not depend on the loop's bookkeeping:

- :func:`two_body_taylor` and :func:`kepler_rk4`: the short propagation of the master
  (second-order Taylor over a few seconds; point-mass RK4 over the 60 s between records);
- :func:`whiten_optical` and :func:`whiten_xnav`: the UV, CNS and XNAV innovations divided by
  (the Cholesky factor of) their predicted covariance ``S = H P H^T + R``, compiled with numba;
- :class:`XnavInnovationWavelet`: the causal db3 detector of the whitened XNAV innovations
  and :func:`unit_sigma`, the per-level noise of the causal details of unit white noise.

Examples
--------
>>> import numpy as np
>>> w = np.array([4.0e6, 0.0, 0.0, 0.0, 3.0e3, 0.0])
>>> kepler_rk4(w, 60.0, 4.2828e13)
>>> bool(abs(np.linalg.norm(w[:3]) - 4.0e6) < 2.0e3)
True
>>> unit_sigma(3).round(3)
array([1., 1., 1.])
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from xnavlab.core.constants import GM_MARS, GM_SUN, C
from xnavlab.core.detection import EventTracker, causal_filters, threshold_multiplier

__all__ = ["unit_sigma", "two_body_taylor", "kepler_rk4", "propagate_positions", "whiten_optical",
           "whiten_optical_at", "whiten_xnav", "XnavInnovationWavelet"]


def unit_sigma(level, wavelet="db3"):
    """Per-level std of the causal details of unit white noise: the filters' 2-norms."""
    return np.array([np.sqrt(np.sum(np.square(g))) for g in causal_filters(wavelet, level)])


def two_body_taylor(x, dt):
    """Propagate Mars-centred states (..., 6) by a few seconds (Taylor, point mass; mm at 6 s)."""
    r, v = x[..., :3], x[..., 3:]
    rn = np.linalg.norm(r, axis=-1, keepdims=True)
    a = -GM_MARS * r / rn**3
    return np.concatenate([r + v * dt + 0.5 * a * dt * dt, v + a * dt], axis=-1)


@njit(cache=True)
def kepler_rk4(w, dt, gm):
    """Propagate the Mars-centred state w (6,) by dt s in place: point mass, classical RK4 in
    steps of at most 30 s (over the 60 s between records: 0.1 m; the Sun's and Jupiter's
    tides add 0.2 mm)."""
    m = max(1, int(math.ceil(abs(dt) / 30.0)))
    h = dt / m
    k = np.empty((4, 6))
    y = np.empty(6)
    for _ in range(m):
        for s in range(4):
            c = (0.0, 0.5, 0.5, 1.0)[s]
            for i in range(6):
                y[i] = w[i] + (c * h * k[s - 1, i] if s > 0 else 0.0)
            rn = math.sqrt(y[0] ** 2 + y[1] ** 2 + y[2] ** 2)
            a = -gm / rn**3                                  # r'' = -GM r / |r|^3
            for i in range(3):
                k[s, i] = y[3 + i]
                k[s, 3 + i] = a * y[i]
        for i in range(6):
            w[i] += h / 6.0 * (k[0, i] + 2.0 * k[1, i] + 2.0 * k[2, i] + k[3, i])


@njit(cache=True)
def propagate_positions(x, dt, gm, R):
    """Positions (N, 3) of the Mars-centred states ``x`` (N, 6) after ``dt`` (N,) s, in place in
    ``R`` (:func:`kepler_rk4`; the UV and CNS innovations of one epoch share them)."""
    w = np.empty(6)
    for n in range(x.shape[0]):
        for i in range(6):
            w[i] = x[n, i]
        kepler_rk4(w, dt[n], gm)
        for i in range(3):
            R[n, i] = w[i]


@njit(cache=True)
def whiten_optical(kind, x, P, dt, z, stars, sig_a, sig_b, gm, y):
    """Whitened UV (kind 0) or CNS (kind 1) innovations, in place in ``y`` (N, m).

    ``x`` (N, 6) and ``P`` (N, 6, 6) are the master at the latest record at or before epoch
    k - 2, propagated here by ``dt`` (N,) s (:func:`kepler_rk4`). UV: ``sig_a`` range noise (m),
    ``sig_b`` direction noise (rad); components range and the two tangent axes of the
    direction (:func:`xnavlab.mars.sensors.tangent_basis`), each ``nu / sqrt(g P g^T + sigma^2)``.
    CNS: ``sig_a`` star, ``sig_b`` horizon noise (rad); ``y = L^-1 nu`` with
    ``L L^T = H P H^T + sigma_s^2 I + sigma_h^2 A A^T``.
    """
    R = np.empty((x.shape[0], 3))
    propagate_positions(x, dt, gm, R)
    whiten_optical_at(kind, R, P, z, stars, sig_a, sig_b, y)


@njit(cache=True)
def whiten_optical_at(kind, R, P, z, stars, sig_a, sig_b, y):
    """:func:`whiten_optical` from the propagated positions ``R`` (N, 3) (:func:`propagate_positions`)."""
    N = R.shape[0]
    k = stars.shape[0]
    r = np.empty(3)
    u = np.empty(3)
    A = np.empty((k, 3))
    S = np.empty((k, k))
    L = np.zeros((k, k))
    nu = np.empty(k)
    g = np.empty(3)
    for n in range(N):
        for i in range(3):
            r[i] = R[n, i]
        rn = math.sqrt(r[0] ** 2 + r[1] ** 2 + r[2] ** 2)
        for i in range(3):
            u[i] = -r[i] / rn
        if kind == 0:
            # range: g = r/|r| = -u; S = g P g^T + sigma_r^2
            s = 0.0
            for i in range(3):
                for j in range(3):
                    s += u[i] * P[n, i, j] * u[j]
            y[n, 0] = (z[n, 0] - rn) / math.sqrt(s + sig_a * sig_a)
            # tangent basis e1 = normalise(z x u) (x x u near the poles), e2 = u x e1
            if abs(u[2]) > 1.0 - 1e-12:
                e1 = (0.0, -u[2], u[1])
            else:
                e1 = (-u[1], u[0], 0.0)
            m1 = math.sqrt(e1[0] ** 2 + e1[1] ** 2 + e1[2] ** 2)
            e1 = (e1[0] / m1, e1[1] / m1, e1[2] / m1)
            e2 = (u[1] * e1[2] - u[2] * e1[1], u[2] * e1[0] - u[0] * e1[2],
                  u[0] * e1[1] - u[1] * e1[0])
            for c_, e in ((1, e1), (2, e2)):
                d = 0.0
                for i in range(3):
                    d += (z[n, 1 + i] - u[i]) * e[i]
                    g[i] = -e[i] / rn                     # d(e . u)/dr = -e^T (I - u u^T)/|r|
                s = 0.0
                for i in range(3):
                    for j in range(3):
                        s += g[i] * P[n, i, j] * g[j]
                y[n, c_] = d / math.sqrt(s + sig_b * sig_b)
        else:
            for j in range(k):
                us = u[0] * stars[j, 0] + u[1] * stars[j, 1] + u[2] * stars[j, 2]
                cx = u[1] * stars[j, 2] - u[2] * stars[j, 1]
                cy = u[2] * stars[j, 0] - u[0] * stars[j, 2]
                cz = u[0] * stars[j, 1] - u[1] * stars[j, 0]
                nu[j] = z[n, j] - math.atan2(math.sqrt(cx * cx + cy * cy + cz * cz), us)  # eq. (6)
                an = 0.0
                for i in range(3):
                    A[j, i] = stars[j, i] - us * u[i]
                    an += A[j, i] ** 2
                an = math.sqrt(an)
                for i in range(3):
                    A[j, i] /= an
            for a in range(k):
                for b in range(a + 1):
                    s = sig_b * sig_b * (A[a, 0] * A[b, 0] + A[a, 1] * A[b, 1] + A[a, 2] * A[b, 2])
                    if a == b:
                        s += sig_a * sig_a
                    for i in range(3):
                        for j in range(3):
                            s += A[a, i] * P[n, i, j] * A[b, j] / (rn * rn)   # H P H^T
                    S[a, b] = s
            # Cholesky S = L L^T and forward substitution y = L^-1 nu
            for a in range(k):
                for b in range(a + 1):
                    s = S[a, b]
                    for c_ in range(b):
                        s -= L[a, c_] * L[b, c_]
                    L[a, b] = math.sqrt(s) if a == b else s / L[b, b]
            for a in range(k):
                s = nu[a]
                for c_ in range(a):
                    s -= L[a, c_] * y[n, c_]
                y[n, a] = s / L[a, a]


_SHAPIRO = 2.0 * GM_SUN / C**3


@njit(cache=True)
def whiten_xnav(x, dt, P, z, r_mars, r_sun, n, distance, sigma, gm, y):
    """Whitened XNAV innovations ``y = L^-1 (z - h(x))`` (N, k), in place in ``y``.

    ``x`` (N, 6) and ``P`` (N, 6, 6) are the master at the latest record at or before epoch
    k - 2, propagated here by ``dt`` (N,) s (second-order Taylor, :func:`two_body_taylor`).
    ``z`` (N, k) measured delays, s; ``r_mars``, ``r_sun`` (N, 3) the filter ephemeris' Mars and
    Sun relative to the SSB, m; pulsar directions ``n`` (k, 3), ``distance`` (k,) m and noise
    ``sigma`` (k,) s. ``h`` is paper eq. (1) (Roemer + parallax + Shapiro, as
    :func:`xnavlab.mars.toa.delay`); ``L L^T = H P H^T + diag(sigma^2)`` with ``H ~ n^T / c``
    (the other terms of eq. (4) are 1e-4 of it).
    """
    N, k = z.shape
    S = np.empty((k, k))
    L = np.zeros((k, k))
    nu = np.empty(k)
    for q in range(N):
        rn = math.sqrt(x[q, 0] ** 2 + x[q, 1] ** 2 + x[q, 2] ** 2)
        h = dt[q]
        R = np.empty(3)
        for i in range(3):
            a = -gm * x[q, i] / rn**3
            R[i] = r_mars[q, i] + (x[q, i] + x[q, 3 + i] * h + 0.5 * a * h * h)   # Taylor
        Rn = math.sqrt(R[0] ** 2 + R[1] ** 2 + R[2] ** 2)
        b0, b1, b2 = -r_sun[q, 0], -r_sun[q, 1], -r_sun[q, 2]
        bn = math.sqrt(b0 * b0 + b1 * b1 + b2 * b2)
        for i in range(k):
            nr = n[i, 0] * R[0] + n[i, 1] * R[1] + n[i, 2] * R[2]
            nb = n[i, 0] * b0 + n[i, 1] * b1 + n[i, 2] * b2
            zp = (nr / C + (nr * nr - Rn * Rn) / (2.0 * C * distance[i])
                  + _SHAPIRO * math.log(abs((nr + Rn) / (nb + bn) + 1.0)))   # paper eq. (1)
            nu[i] = z[q, i] - zp
        for a_ in range(k):                           # S = H P H^T + R, H = n^T / c
            for b_ in range(a_ + 1):
                s = 0.0
                for i in range(3):
                    for j in range(3):
                        s += n[a_, i] * P[q, i, j] * n[b_, j]
                s /= C * C
                if a_ == b_:
                    s += sigma[a_] ** 2
                S[a_, b_] = s
        for a_ in range(k):                           # S = L L^T, y = L^-1 nu
            for b_ in range(a_ + 1):
                s = S[a_, b_]
                for c_ in range(b_):
                    s -= L[a_, c_] * L[b_, c_]
                L[a_, b_] = math.sqrt(s) if a_ == b_ else s / L[b_, b_]
        for a_ in range(k):
            s = nu[a_]
            for c_ in range(a_):
                s -= L[a_, c_] * y[q, c_]
            y[q, a_] = s / L[a_, a_]


class XnavInnovationWavelet:
    """Causal db3 detector of the XNAV innovations, all pulsars at once (one event tracker).

    The inputs are innovations divided by their predicted standard deviations, unit white
    noise when healthy, so level ``j``'s noise is the 2-norm of its filter and no training is
    needed; a sample alarms when any pulsar's ``|d_j| > k sigma_j`` with
    ``k = threshold_multiplier(pfa / m, level)`` (no variance test at 500 s a sample).
    """

    def __init__(self, m, level, pfa, holdoff):
        filters = causal_filters("db3", level)
        self.window = len(filters[-1])
        self.G = np.zeros((level, self.window))
        for i, g in enumerate(filters):
            self.G[i, :len(g)] = g
        self.sigma = unit_sigma(level)[:, None]
        self.k = threshold_multiplier(pfa / m, level)
        self.buf = np.zeros((self.window, m))          # newest first
        self.count = 0
        self.tracker = EventTracker(holdoff)
        self.new_onset = False

    def update(self, t, nu):
        self.buf[1:] = self.buf[:-1]
        self.buf[0] = nu
        self.count += 1
        was = self.tracker.faulty
        self.new_onset = False
        if self.count < self.window:
            return False
        ratio = np.abs(self.G @ self.buf) / (self.k * self.sigma)      # (level, m)
        i, p = np.unravel_index(int(np.argmax(ratio)), ratio.shape)
        r = float(ratio[i, p])
        flag = self.tracker.update(t, r > 1.0, r, f"pulsar {p}, level {i + 1}")
        self.new_onset = flag and not was
        return flag

    def snapshot(self):
        return self.buf.copy(), self.count, self.new_onset, self.tracker.snapshot()

    def restore(self, state):
        buf, self.count, self.new_onset, tr = state
        self.buf[...] = buf
        self.tracker.restore(tr)

    def clear(self):
        """Forget the window (zeros, which every detail filter maps to zero) and close the
        open event: armed at once (used at re-admission)."""
        self.buf[...] = 0.0
        self.count = self.window
        self.tracker.close()
