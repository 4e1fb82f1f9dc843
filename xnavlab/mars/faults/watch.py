"""The combined detector inside the compiled filter loop: its state arrays and its alarms.

:func:`xnavlab.mars.kernel.kernels.run_epochs` whitens every measurement of a watched subsystem
against the master's one-step prediction (``y = L^-1 nu``, ``L L^T = H P H^T + R``) and feeds
the innovation parts of the combined detector (:class:`xnavlab.core.detection.InnovationMonitor`:
per-sample chi-square, mean and variance CUSUMs with an adaptive scale, recomputed on the
monitor's grid of samples fed) and, for XNAV, its innovation wavelet
(:class:`xnavlab.mars.faults.innovations.XnavInnovationWavelet`) *before* the measurement is used: an
alarm leaves that measurement out and switches the subsystem out from the next epoch. No chunk
is run ahead and rolled back. The kernel returns after an epoch with an alarm (the loop then
records the event) and, on the re-admission grid, when an isolated subsystem's last
innovations pass the re-admission test (the loop then decides).

:class:`Watch` holds the arrays the kernel reads and writes, turns its alarms into events and
keeps the loop's isolations and re-admissions in step with the kernel.

Examples
--------
>>> from xnavlab.core.detection import CombinedDesign, InnovationMonitor
>>> mon = {"uv": InnovationMonitor(CombinedDesign(28800.0, 3))}
>>> w = Watch(("uv",), mon, None, {"uv": 10}, 0.0, ({"uv": 100}, {"uv": 350.0}, {"uv": 3.3}, 100))
>>> len(w.arrays()), w.ys["uv"].shape
(12, (10, 3))
"""

from __future__ import annotations

import math

import numpy as np

from xnavlab.core.detection import MAD_SCALE, Event
from xnavlab.mars.kernel import kernel_inputs, kernels

__all__ = ["Watch"]


class Watch:
    """State of the combined detector for :func:`xnavlab.mars.kernel.kernels.run_epochs`.

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
        Measurements per subsystem (rows of the innovation outputs ``ys``).
    t_arm : float
        Time (s, the run's time scale) before which no innovation is tested.
    readmit : tuple
        ``(window, threshold, zq, check_every)``: per subsystem, the re-admission test's window
        (samples), NIS-sum threshold and the normal quantile of its bias test; the period of
        its grid (epochs).
    """

    def __init__(self, subsystems, monitors, xdet, n_meas, t_arm, readmit):
        self.subs = tuple(subsystems)
        self.monitors = dict(monitors)
        self.xdet = xdet
        ns = len(self.subs)
        w_max = max([m.scale_samples for m in self.monitors.values()] + [1])
        win, thr, zq, check = readmit
        self.wf = np.zeros((ns, 10))
        self.wi = np.zeros((ns, 15), dtype=np.int64)
        self.wS = np.zeros((ns, 12))
        self.wsc = np.ones((ns, 4))
        self.ring = np.zeros((ns, 4, w_max))      # components contiguous (the medians)
        # the whitened innovations of every measurement of a watched subsystem (unit white
        # noise when healthy under the model; NaN where none was taken)
        self.ys = {s: np.zeros((1, 4)) for s in ("xnav", "uv", "cns")}
        K = kernels
        for s, mon in self.monitors.items():
            i = self.subs.index(s)
            d = mon.design
            self.ys[s] = np.full((n_meas[s], d.m), np.nan)
            self.wf[i, :K.WF_ZQ + 1] = (d.k_mean, d.k_var, d.chi2_threshold, d.h_mean, d.h_var,
                                        t_arm, mon.prior_samples, MAD_SCALE, thr[s], zq[s])
            for col, v in ((K.WI_ON, 1), (K.WI_M, d.m), (K.WI_W, mon.scale_samples),
                           (K.WI_NEXT, mon.next_scale_update()), (K.WI_EVERY, mon.scale_every),
                           (K.WI_ADAPT, int(mon.adaptive)), (K.WI_RWIN, win[s]),
                           (K.WI_CHECK, check)):
                self.wi[i, col] = v
            self.wsc[i, :d.m] = mon.scale
        if xdet is not None:
            self.xG, self.xthr = xdet.G, (xdet.k * xdet.sigma[:, 0]).copy()
            self.xbuf = np.zeros((xdet.window, 4))
        else:
            self.xG, self.xthr, self.xbuf = np.zeros((0, 1)), np.zeros(0), np.zeros((1, 4))
        self.alarm = np.full((ns, 4), -1.0)
        self._events = {s: [] for s in self.subs}     # [onset, end, cleared, peak, test]

    def arrays(self):
        """The kernel's watch argument: a :class:`~xnavlab.mars.kernel.kernel_inputs.WatchState` of
        this object's arrays (shared, not copied)."""
        return kernel_inputs.WatchState(self.wf, self.wi, self.wS, self.wsc, self.ring,
                                        self.ys["xnav"], self.ys["uv"], self.ys["cns"], self.xbuf,
                                        self.xG, self.xthr, self.alarm)

    def scale(self, s):
        """The adaptive scale (m,) of subsystem ``s`` now."""
        i = self.subs.index(s)
        return self.wsc[i, :self.wi[i, kernels.WI_M]].copy()

    # -- between kernel calls
    def after_stop(self, t):
        """Record the alarms of a kernel stop at time ``t`` (s). Returns the subsystems that
        alarmed (to be switched out)."""
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
        self.alarm[...] = -1.0
        return hit

    def _open(self, s, t, ratio, test):
        self._events[s].append([t, t, math.inf, float(ratio), test])

    def set_out(self, out):
        """Tell the kernel which subsystems are out (``out`` (ns,) bool): a newly isolated one
        starts counting its measurements for the re-admission test."""
        for i, s in enumerate(self.subs):
            if s in self.monitors and bool(out[i]) != bool(self.wi[i, kernels.WI_OUT]):
                self.wi[i, kernels.WI_OUT] = int(out[i])
                self.wi[i, kernels.WI_NOUT] = 0

    def readmit(self, s):
        """Subsystem ``s`` rejoins: fresh CUSUMs, an empty XNAV wavelet window (zeros, which
        every detail filter maps to zero: armed at once), its open events closed."""
        i = self.subs.index(s)
        self.wS[i] = 0.0
        self.wi[i, kernels.WI_OUT] = self.wi[i, kernels.WI_NOUT] = 0
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
