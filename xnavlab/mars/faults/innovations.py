"""Innovations of the Mars subsystems against the master: a short propagation, an XNAV wavelet.

The fault-tolerant loop (:mod:`xnavlab.mars.faults.fault_tolerance`) watches XNAV on its innovations
``nu = z - h(x)`` against the master's state. This module holds the pieces of that computation
that do not depend on the loop's bookkeeping:

- :func:`two_body_taylor`: the short propagation of a recorded master state to an XNAV
  measurement (second-order Taylor over a few seconds), for the ``"wavelet"`` detector;
- :class:`XnavInnovationWavelet`: the causal db3 detector of the whitened XNAV innovations
  and :func:`unit_sigma`, the per-level noise of the causal details of unit white noise.

The ``"combined"`` detector whitens every subsystem's innovation inside the compiled filter
(:func:`xnavlab.mars.kernel.kernels.run_epochs`, :mod:`xnavlab.mars.faults.watch`); its XNAV wavelet uses
this class's filters and thresholds.

Examples
--------
>>> import numpy as np
>>> x = two_body_taylor(np.array([4.0e6, 0.0, 0.0, 0.0, 3.0e3, 0.0]), 6.0)
>>> bool(abs(x[1] - 1.8e4) < 1e-6)
True
>>> unit_sigma(3).round(3)
array([1., 1., 1.])
"""

from __future__ import annotations

import numpy as np

from xnavlab.core.constants import GM_MARS
from xnavlab.core.detection import EventTracker, causal_filters, threshold_multiplier
from xnavlab.core.validate import check_finite_array

__all__ = ["unit_sigma", "two_body_taylor", "XnavInnovationWavelet"]


def unit_sigma(level, wavelet="db3"):
    """Per-level std of the causal details of unit white noise: the filters' 2-norms."""
    return np.array([np.sqrt(np.sum(np.square(g))) for g in causal_filters(wavelet, level)])


def two_body_taylor(x, dt):
    """Propagate Mars-centred states (..., 6) by a few seconds (Taylor, point mass; mm at 6 s)."""
    x, dt = check_finite_array("x", x, shape=(6,)), check_finite_array("dt", dt)
    r, v = x[..., :3], x[..., 3:]
    rn = np.linalg.norm(r, axis=-1, keepdims=True)
    a = -GM_MARS * r / rn**3
    return np.concatenate([r + v * dt + 0.5 * a * dt * dt, v + a * dt], axis=-1)


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

    def clear(self):
        """Forget the window (zeros, which every detail filter maps to zero) and close the
        open event: armed at once (used at re-admission)."""
        self.buf[...] = 0.0
        self.count = self.window
        self.tracker.close()
