"""Compiled (numba) kernels of the federated Mars navigation run: the epoch loop.

The readable reference is the numpy loop of :mod:`xnavlab.mars.navigation.scenarios` (built from
:mod:`xnavlab.core.filters`, :mod:`xnavlab.mars.models.sensors`, :mod:`xnavlab.core.federated`
and :mod:`xnavlab.mars.models.dynamics`). :func:`run_epochs` computes the same estimates (the
tests compare them to 1e-9 relative) in about a microsecond per epoch of three EKFs and
the fusion (the measurement series are drawn by :mod:`xnavlab.mars.models.series`).

The modules of the kernel
-------------------------
One step of the filter per module, each read in one sitting:

==============================================  ===================================================
:mod:`xnavlab.mars.kernel.kernel_inputs`        the arguments and the scratch, as named tuples
:mod:`xnavlab.mars.kernel.kernel_compile`       how they are compiled and cached (no fast-math)
:mod:`xnavlab.mars.kernel.kernel_linalg`        Cholesky, its solves, a 6 x 6 product
:mod:`xnavlab.mars.kernel.kernel_propagation`   the time update (forces, RK4, Phi, Q)
:mod:`xnavlab.mars.kernel.kernel_measurements`  the sensors (paper eqs. (1)-(6)), the local updates
:mod:`xnavlab.mars.kernel.kernel_fusion`        the master's fusion, in two forms that agree
:mod:`xnavlab.mars.kernel.kernel_watch`         the combined detector inside the loop
this module                                     the loop: predict, measure, watch, update, fuse
==============================================  ===================================================

At every epoch :func:`run_epochs` predicts the master (and, in no-reset mode, each local),
takes each local's measurement (and, for a watched subsystem, feeds its innovation against
the master's prediction to the detector first), updates the locals (or, in reset mode, adds
up the information they gain) and fuses; it records the recorded epochs and, in reset mode,
shares the master among the locals connected at the next epoch. The arguments come in the
named tuples of :mod:`xnavlab.mars.kernel.kernel_inputs` (why named tuples: there), the working
arrays in five more that :func:`run_epochs` allocates once per call; every helper reads them
by field name (numba resolves a field at compile time) and takes a few of them.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np

from xnavlab.mars.kernel import kernel_inputs as ki
from xnavlab.mars.kernel import kernel_measurements as km
from xnavlab.mars.kernel.kernel_compile import HELPER, jit
from xnavlab.mars.kernel.kernel_fusion import fuse, fuse_information
from xnavlab.mars.kernel.kernel_measurements import measure, update, update_information
from xnavlab.mars.kernel.kernel_propagation import predict
from xnavlab.mars.kernel.kernel_watch import quiet, watch, whiten

__all__ = ["run_epochs", "FilterDivergence", "KIND_XNAV", "KIND_UV", "KIND_CNS"]

#: Subsystem code of the XNAV filter in the kernels' integer arrays.
KIND_XNAV = km.KIND_XNAV
#: Subsystem code of the UV-sensor filter.
KIND_UV = km.KIND_UV
#: Subsystem code of the CNS filter.
KIND_CNS = km.KIND_CNS

# The watch's columns, where xnavlab.mars.faults.watch reads them (their home: kernel_inputs).
(WF_ZQ, WI_ON, WI_M, WI_W, WI_NEXT, WI_EVERY, WI_ADAPT, WI_RWIN, WI_CHECK, WI_OUT, WI_NOUT,
 WI_XCOUNT) = (ki.WF_ZQ, ki.WI_ON, ki.WI_M, ki.WI_W, ki.WI_NEXT, ki.WI_EVERY, ki.WI_ADAPT,
               ki.WI_RWIN, ki.WI_CHECK, ki.WI_OUT, ki.WI_NOUT, ki.WI_XCOUNT)

# flags written per epoch and subsystem
NO_MEAS = 0
UPDATED = 1
REJECTED = 2  # innovation gate exceeded: time update only
ISOLATED = 3  # subsystem switched out: time update only

#: The loop's arguments and its scratch (:mod:`xnavlab.mars.kernel.kernel_inputs` holds their types).
_Args = namedtuple("_Args", "st pr pl se rec ws")
_Scratch = namedtuple("_Scratch", "sp me mw up fu wt")


class FilterDivergence(RuntimeError):
    """The compiled filter stopped: a covariance lost positive definiteness.

    :func:`run_epochs` returns -2; the scenario raises this with the settings to change.
    Settings that double precision cannot carry (a measurement noise many orders below the
    state's uncertainty) or a diverging filter; the command line reports it in one line.
    """


@jit(cache=True, nogil=True)
def run_epochs(k0, k1, st, pr, pl, se, rec, ws):
    """Run epochs ``k0 <= k < k1`` of the federated filter, updating the state in place.

    The containers are those of :mod:`xnavlab.mars.kernel.kernel_inputs` (their fields, shapes and
    units are documented there).

    Parameters
    ----------
    k0, k1 : int
        The epochs to run, ``0 <= k0 <= k1 <= n``.
    st : xnavlab.mars.kernel.kernel_inputs.FilterState
        The local and master estimates and the shares, updated in place.
    pr : xnavlab.mars.kernel.kernel_inputs.Propagation
        The time update's model (process noise, sub-step, Mars and the third-body table).
    pl : xnavlab.mars.kernel.kernel_inputs.Plan
        Epochs, subsystem codes, measurement rows, connections, sharing factors, mode and
        gates; ``pl.active[k + 1, i]`` is cleared when subsystem ``i`` alarms at epoch ``k``.
    se : xnavlab.mars.kernel.kernel_inputs.Sensors
        The measurements and noise of XNAV, UV and CNS.
    rec : xnavlab.mars.kernel.kernel_inputs.Records
        Written in place: the master's and the locals' estimates at the recorded epochs, every
        epoch's NIS and flag.
    ws : xnavlab.mars.kernel.kernel_inputs.WatchState
        The combined detector's state (:mod:`xnavlab.mars.faults.watch`), for the subsystems it
        watches (``ws.wi[i, WI_ON]``): each of their measurements is whitened against the
        master's prediction and fed to its parts before the update; an alarm leaves the
        measurement out and switches the subsystem out from the next epoch.

    Returns
    -------
    int
        -1 when the epochs ran to ``k1``; ``k`` when the run stopped after epoch ``k``
        because the combined detector alarmed there (``ws.alarm``) or an isolated subsystem
        may rejoin at epoch ``k + 1`` (a multiple of its check period); -2 on a numerical
        failure (a covariance lost positive definiteness).
    """
    ns = st.xs.shape[0]
    nb = pr.tb_pos.shape[1]
    mm = max(4, se.n_x.shape[0], se.stars_c.shape[0])
    e = np.empty     # (s*, i*: the third bodies' positions and indirect terms at t, t + h/2, t + h)
    sp = ki.PredictScratch(e((6, 6)), e((6, 6)), e((6, 6)), e(6),
                           e((nb, 3)), e((nb, 3)), e((nb, 3)), e((nb, 3)), e((nb, 3)), e((nb, 3)))
    A = e((mm, 3))                  # (the two measurement scratches share the CNS noise's)
    me = ki.Measurement(e(mm), np.zeros((mm, 6)), np.zeros((mm, mm)), A)  # at the local's state
    mw = ki.Measurement(e(mm), np.zeros((mm, 6)), np.zeros((mm, mm)), A)  # at the master's
    up = ki.UpdateScratch(e((6, mm)), e((mm, mm)), e((mm, mm)), e(mm), e((6, mm)), e((6, mm)),
                          e((6, 6)))
    fu = ki.FusionScratch(e(6), e((6, 6)), e(6), e((6, 6)), e((6, 6)),    # the fusion's
                          e(6), e((6, 6)),                                 # xp, Pp
                          np.zeros((3, 3)), np.zeros(3), e((3, 3)),        # J, bv, G
                          np.zeros(ns, dtype=np.bool_), e(ns))             # use, 1 / shares
    wt = ki.WatchScratch(np.zeros(ns, dtype=np.bool_), e(mm), e(ws.ring.shape[2]),
                         e(8192, dtype=np.int64))
    return _run(k0, k1, _Args(st, pr, pl, se, rec, ws), _Scratch(sp, me, mw, up, fu, wt))


@jit(**HELPER)
def _run(k0, k1, args, sc):
    """The epoch loop of :func:`run_epochs` (``args`` its arguments, an ``_Args``; ``sc`` the
    scratch allocated there, a ``_Scratch``)."""
    st, pr, pl, se, rec, ws = args.st, args.pr, args.pl, args.se, args.rec, args.ws
    sp, me, mw, up, fu, wt = sc.sp, sc.me, sc.mw, sc.up, sc.fu, sc.wt
    xs, Ps, shares, xm, Pm = st.xs, st.Ps, st.shares, st.xm, st.Pm
    times, kinds, active, reset, gate = pl.times, pl.kinds, pl.active, pl.reset, pl.gate
    wf, wi = ws.wf, ws.wi
    xp, Pp, use, inv_sh = fu.xp, fu.Pp, fu.use, fu.inv_sh
    ns = xs.shape[0]
    for i in range(ns):
        inv_sh[i] = 1.0 / shares[i]
    for k in range(k0, k1):
        stop = False
        if k > 0:
            tp = times[k - 1]
            dt = times[k] - tp
            # master time update (full Q): xp, Pp
            for a in range(6):
                xp[a] = xm[a]
                for b in range(6):
                    Pp[a, b] = Pm[a, b]
            predict(xp, Pp, tp, dt, 1.0, pr, sp)
            full = not reset or rec.pos[k] >= 0  # run the locals in full (else: information)
            if reset:
                # after a reset every local equals the master scaled by 1/share, and the time
                # update commutes with that scaling: P_i- = (Phi P_f Phi^T + Q) / share_i
                for i in range(ns):
                    for a in range(6):
                        xs[i, a] = xp[a]
                    if full:
                        for a in range(6):
                            for b in range(6):
                                Ps[i, a, b] = Pp[a, b] * inv_sh[i]
            else:
                for i in range(ns):
                    predict(xs[i], Ps[i], tp, dt, inv_sh[i], pr, sp)
            # measurement updates
            for a in range(3):
                fu.bv[a] = 0.0
                for b in range(3):
                    fu.J[a, b] = 0.0
            for i in range(ns):
                j = pl.meas_idx[k, i]
                if j < 0:
                    rec.flags[k, i] = NO_MEAS
                    continue
                act = active[k, i]
                m = measure(kinds[i], xs[i], j, se, me)
                wt.alarmed[i] = False
                if wi[i, ki.WI_ON] != 0:
                    wm = me         # (in reset mode the local's prediction is the master's)
                    if not reset:
                        wm = mw
                        measure(kinds[i], xp, j, se, mw)
                    armed = act and times[k] >= wf[i, ki.WF_TARM]    # connected and armed
                    mz = whiten(kinds[i], j, wm, m, fu, se, up)
                    if watch(kinds[i], i, j, armed, mz, up.y, ws, wt):
                        act = False     # an alarm: this measurement stays out, and so does i
                        wt.alarmed[i] = True
                        stop = True
                if full:
                    nis = update(st, i, me, m, gate[i], act, up)
                else:
                    nis = update_information(fu, i, me, m, gate[i], act, up)
                rec.nis[k, i] = nis
                if not act:
                    rec.flags[k, i] = ISOLATED
                elif nis > gate[i]:
                    rec.flags[k, i] = REJECTED
                elif math.isnan(nis):
                    return -2
                else:
                    rec.flags[k, i] = UPDATED
            # master fusion of the connected locals
            any_used = False
            ssum = 0.0
            for i in range(ns):
                use[i] = active[k, i]
                any_used = any_used or use[i]
                if use[i]:
                    ssum += shares[i]
            if not any_used:
                for a in range(6):
                    xm[a] = xp[a]
                    for b in range(6):
                        Pm[a, b] = Pp[a, b]
            elif full:
                if not fuse(st, fu):
                    return -2
            elif not fuse_information(st, fu, ssum):
                return -2
        if stop and k + 1 < times.shape[0]:
            for i in range(ns):
                if wt.alarmed[i]:
                    active[k + 1, i] = False     # switched out from the next epoch
        for i in range(ns):      # the re-admission grid: stop where the loop may readmit
            if wi[i, ki.WI_OUT] and (k + 1) % wi[i, ki.WI_CHECK] == 0 and \
                    quiet(kinds[i], i, ws):
                stop = True
        r = rec.pos[k]
        if r >= 0:
            for a in range(6):
                rec.x[r, a] = xm[a]
                for b in range(6):
                    rec.P[r, a, b] = Pm[a, b]
            for i in range(ns):
                for a in range(6):
                    rec.xl[r, i, a] = xs[i, a]
                    rec.Pl[r, i, a] = Ps[i, a, a]
        # reset: share the master among the locals connected at the next epoch (the locals
        # themselves are rebuilt from the master by the next time update; written at the end)
        if reset:
            kn = k + 1 if k + 1 < times.shape[0] else k
            tot = 0.0
            for i in range(ns):
                if active[kn, i]:
                    tot += pl.beta[i]
            for i in range(ns):
                shares[i] = pl.beta[i] / tot if active[kn, i] else 1.0
                inv_sh[i] = 1.0 / shares[i]
            if k == k1 - 1 or stop:
                for i in range(ns):
                    for a in range(6):
                        xs[i, a] = xm[a]
                        for b in range(6):
                            Ps[i, a, b] = Pm[a, b] * inv_sh[i]
        if stop:
            return k
    return -1
