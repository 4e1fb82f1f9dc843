"""The combined detector inside the compiled filter loop: its state arrays and its alarms.

:func:`xnavlab.mars.kernels.run_epochs` whitens every measurement of a watched subsystem
against the master's one-step prediction (``y = L^-1 nu``, ``L L^T = H P H^T + R``) and feeds
the innovation parts of the combined detector (:class:`xnavlab.core.detection.InnovationMonitor`:
per-sample chi-square, mean and variance CUSUMs with an adaptive scale) and, for XNAV, its
innovation wavelet (:class:`xnavlab.mars.innovations.XnavInnovationWavelet`) *before* the
measurement is used: an alarm leaves that measurement out and switches the subsystem out from
the next epoch. No chunk is run ahead and rolled back. The kernel stops after an epoch with an
alarm (the loop then plans isolation and re-admission) or when a subsystem's noise scale is due
(its median is taken here, in numpy, on the same grid of samples as the monitor's).

:class:`Watch` holds the arrays the kernel reads and writes, turns its stops into events, and
re-arms a subsystem at re-admission.

Examples
--------
>>> from xnavlab.core.detection import CombinedDesign, InnovationMonitor
>>> mon = {"uv": InnovationMonitor(CombinedDesign(28800.0, 3))}
>>> w = Watch(("uv",), mon, None, {"uv": 10}, t_arm=0.0)
>>> len(w.arrays()), w.ys["uv"].shape
(12, (10, 3))
"""

from __future__ import annotations

import math

import numpy as np

from xnavlab.core.detection import Event
from xnavlab.mars import kernels

__all__ = ["Watch"]


class Watch:
    """State of the combined detector for :func:`xnavlab.mars.kernels.run_epochs`.

    Parameters
    ----------
    subsystems : sequence of str
        The run's subsystems, in the kernel's order.
    monitors : dict
        ``{subsystem: InnovationMonitor}`` of the watched subsystems (their designs, scale
        windows and grids are used; their scale is kept up to date here).
    xdet : XnavInnovationWavelet or None
        The XNAV innovation wavelet (its filters, thresholds and window).
    n_meas : dict
        Measurements per subsystem (rows of the scaled-innovation outputs).
    t_arm : float
        Time (s, the run's time scale) before which no innovation is tested.
    """

    def __init__(self, subsystems, monitors, xdet, n_meas, t_arm):
        self.subs = tuple(subsystems)
        self.monitors = dict(monitors)
        self.xdet = xdet
        ns = len(self.subs)
        w_max = max([m.scale_samples for m in self.monitors.values()] + [1])
        self.wf = np.zeros((ns, 6))
        self.wi = np.zeros((ns, 8), dtype=np.int64)
        self.wS = np.zeros((ns, 12))
        self.wsc = np.ones((ns, 4))
        self.ring = np.zeros((ns, 4, w_max))      # components contiguous: fast medians
        # scaled innovations per measurement (every measurement of a watched subsystem)
        self.ys = {s: np.zeros((1, 4)) for s in ("xnav", "uv", "cns")}
        for s, mon in self.monitors.items():
            i = self.subs.index(s)
            d = mon.design
            self.ys[s] = np.full((n_meas[s], d.m), np.nan)
            self.wf[i] = (d.k_mean, d.k_var, d.chi2_threshold, d.h_mean, d.h_var, t_arm)
            nxt = mon.next_scale_update() if mon.adaptive else np.iinfo(np.int64).max
            self.wi[i, :kernels.WI_XCOUNT] = (1, d.m, mon.scale_samples, 0, 0, 0, nxt)
            self.wsc[i, :d.m] = mon.scale
        if xdet is not None:
            self.xG, self.xthr = xdet.G, (xdet.k * xdet.sigma[:, 0]).copy()
            self.xbuf = np.zeros((xdet.window, 4))
        else:
            self.xG, self.xthr, self.xbuf = np.zeros((0, 1)), np.zeros(0), np.zeros((1, 4))
        self.alarm = np.full((ns, 4), -1.0)
        self._events = {s: [] for s in self.subs}     # [onset, end, cleared, peak, test]

    def arrays(self):
        """The kernel's watch arguments, in :func:`~xnavlab.mars.kernels.run_epochs` order."""
        return (self.wf, self.wi, self.wS, self.wsc, self.ring, self.ys["xnav"], self.ys["uv"],
                self.ys["cns"], self.xbuf, self.xG, self.xthr, self.alarm)

    # -- between kernel calls
    def after_stop(self, t):
        """Handle a kernel stop at time ``t`` (s): record the alarms, recompute the scales that
        are due. Returns the subsystems that alarmed (to be switched out)."""
        hit = []
        for i, s in enumerate(self.subs):
            part, ratio, code, wratio = self.alarm[i]
            if part >= 0:
                self._open(s, t, ratio, self.monitors[s].part_names[int(part)])
            if code >= 0:
                m = self.wi[i, kernels.WI_M]
                self._open(s, t, wratio, f"wavelet pulsar {int(code) % m}, level {int(code) // m + 1}")
            if part >= 0 or code >= 0:
                hit.append(s)
            mon = self.monitors.get(s)
            if mon is not None and self.wi[i, kernels.WI_NFED] >= self.wi[i, kernels.WI_NEXT]:
                self._rescale(i, mon)
        self.alarm[...] = -1.0
        return hit

    def _rescale(self, i, mon):
        m, n = self.wi[i, kernels.WI_M], self.wi[i, kernels.WI_NRING]
        mon.scale = mon.scale_from(self.ring[i, :m, :n].T)
        self.wsc[i, :m] = mon.scale
        self.wi[i, kernels.WI_NEXT] = mon.next_scale_update(int(self.wi[i, kernels.WI_NEXT]))

    def _open(self, s, t, ratio, test):
        self._events[s].append([t, t, math.inf, float(ratio), test])

    def readmit(self, s):
        """Subsystem ``s`` rejoins: fresh CUSUMs, an empty XNAV wavelet window (zeros, which
        every detail filter maps to zero: armed at once), its open events closed."""
        i = self.subs.index(s)
        self.wS[i] = 0.0
        if s == "xnav" and self.xdet is not None:
            self.xbuf[...] = 0.0
            self.wi[i, kernels.WI_XCOUNT] = self.xG.shape[1]
        for e in self._events[s]:
            if math.isinf(e[2]):
                e[2] = e[1]                    # cleared at its last alarm (EventTracker.close)

    def events(self, s):
        """The detector's events of subsystem ``s`` (absolute times; ``cleared = inf`` while
        it is still out)."""
        return [Event(float(a), float(b), float(c), p, tst) for a, b, c, p, tst in self._events[s]]
