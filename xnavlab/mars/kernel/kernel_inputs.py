"""The named containers of the compiled filter's arguments (:func:`xnavlab.mars.kernel.kernels.run_epochs`).

The kernel takes its arrays and settings in six named tuples instead of 54 positional
arguments: :class:`FilterState` (the estimates, updated in place), :class:`Propagation` (the
time update's model), :class:`Plan` (epochs, subsystems, modes), :class:`Sensors` (measurements
and noise), :class:`Records` (the outputs) and :class:`WatchState` (the combined detector's
state, :class:`xnavlab.mars.faults.watch.Watch`, its columns :data:`WF_KMEAN` ... and :data:`WI_ON`
...). The arrays inside are shared, not copied: what the kernel writes into them is seen by
the caller. Inside, the kernel keeps its working arrays in five more, which
:func:`~xnavlab.mars.kernel.kernels.run_epochs` allocates once per call and every helper reads by
field name: :class:`PredictScratch`, :class:`Measurement`, :class:`UpdateScratch`,
:class:`FusionScratch` and :class:`WatchScratch`.

Why named tuples
----------------
numba passes a named tuple by value, as the flat list of its members, and resolves a field by
name at compile time: reading one costs what reading an argument costs, with no reference
count (the helpers are compiled without numba's runtime, ``_nrt=False``), and the kernels'
machine code is the same as with positional arguments (their outputs are identical bit for
bit). numba's ``structref`` and ``jitclass`` are heap objects behind a pointer: each field read
is a load through it plus an atomic reference-count update. Measured on a toy (a container of
8 arrays and 4 scalars; a loop calling a helper that reads 6 of its fields, 2e6 calls; one
process per variant, 2 shared cores at load 9-14): positional arguments compiled in 1.7-1.8 s
and ran at 1.3-1.7 ns per call, the named tuple 1.6-1.9 s and 1.3-1.5 ns, ``structref`` 2.1-3.8
s and 6.7-8.7 ns, ``jitclass`` 6.9-8.4 s and 4.3-6.2 ns. The price of a named tuple is at the
Python boundary: the dispatcher types a tuple's members in Python, and hashing the signature of
such types is slow, so nothing may ask for ``run_epochs.signatures`` at every call
(:func:`xnavlab.mars.kernel.compile_notice.announce_compile` stops asking once it knows). A call of
:func:`xnavlab.mars.navigation.scenarios.run_kernel` over no epoch then costs 33 us (58 us with the 54
positional arguments and that question asked each time; load 3), which matters to the
chi-square detector's 8675 calls in the 30-day run.

numba keys its on-disk cache by the fields' types, not their names: a reordering here alone
would load machine code that reads the wrong fields, were the kernels' cache not keyed by this
file's source too (:mod:`xnavlab.mars.kernel.kernel_compile`).

Examples
--------
>>> import numpy as np
>>> st = FilterState(np.zeros((3, 6)), np.tile(np.eye(6), (3, 1, 1)), np.full(3, 1 / 3),
...                  np.zeros(6), np.eye(6))
>>> st.Ps.shape, layout()[0]
((3, 6, 6), 'FilterState(xs Ps shares xm Pm)')
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["FilterState", "Propagation", "Plan", "Sensors", "Records", "WatchState", "layout",
           "PredictScratch", "Measurement", "UpdateScratch", "FusionScratch", "WatchScratch",
           "WF_KMEAN", "WF_KVAR", "WF_CHI2", "WF_HMEAN", "WF_HVAR", "WF_TARM", "WF_PRIOR",
           "WF_MAD", "WF_RTHR", "WF_ZQ", "WI_ON", "WI_M", "WI_W", "WI_NRING", "WI_POS",
           "WI_NFED", "WI_NEXT", "WI_XCOUNT", "WI_EVERY", "WI_ADAPT", "WI_OUT", "WI_NOUT",
           "WI_LAST", "WI_RWIN", "WI_CHECK"]

# The columns of WatchState.wf (ns, 10), the detector's float parameters
WF_KMEAN = 0   #: Column of ``WatchState.wf``: the mean CUSUMs' reference k.
WF_KVAR = 1    #: Column of ``WatchState.wf``: the variance CUSUM's reference k_v.
WF_CHI2 = 2    #: Column of ``WatchState.wf``: the chi-square threshold.
WF_HMEAN = 3   #: Column of ``WatchState.wf``: the mean CUSUMs' threshold.
WF_HVAR = 4    #: Column of ``WatchState.wf``: the variance CUSUM's threshold.
WF_TARM = 5    #: Column of ``WatchState.wf``: the arming time, s TDB past J2000.
WF_PRIOR = 6   #: Column of ``WatchState.wf``: the adaptive scale's prior weight n0.
WF_MAD = 7     #: Column of ``WatchState.wf``: the MAD factor (0.6745).
WF_RTHR = 8    #: Column of ``WatchState.wf``: the re-admission test's NIS-sum threshold.
WF_ZQ = 9      #: Column of ``WatchState.wf``: the re-admission test's normal quantile.
# The columns of WatchState.wi (ns, 15), the detector's integer state
WI_ON = 0      #: Column of ``WatchState.wi``: the subsystem is watched (1) or not (0).
WI_M = 1       #: Column of ``WatchState.wi``: its measurement's components m.
WI_W = 2       #: Column of ``WatchState.wi``: the MAD window's length.
WI_NRING = 3   #: Column of ``WatchState.wi``: the window's fill.
WI_POS = 4     #: Column of ``WatchState.wi``: the window's next row.
WI_NFED = 5    #: Column of ``WatchState.wi``: samples fed.
WI_NEXT = 6    #: Column of ``WatchState.wi``: samples fed at the next scale update.
WI_XCOUNT = 7  #: Column of ``WatchState.wi``: samples in the XNAV wavelet's window.
WI_EVERY = 8   #: Column of ``WatchState.wi``: the scale's update period, samples.
WI_ADAPT = 9   #: Column of ``WatchState.wi``: the scale is adaptive (1) or fixed (0).
WI_OUT = 10    #: Column of ``WatchState.wi``: the subsystem is switched out (1).
WI_NOUT = 11   #: Column of ``WatchState.wi``: its measurements since it was switched out.
WI_LAST = 12   #: Column of ``WatchState.wi``: its last measurement's row.
WI_RWIN = 13   #: Column of ``WatchState.wi``: the re-admission test's window, samples.
WI_CHECK = 14  #: Column of ``WatchState.wi``: the re-admission grid's period, epochs.


class FilterState(NamedTuple):
    """The federated filter's estimates, updated in place by the kernel.

    Attributes
    ----------
    xs : ndarray, shape (ns, 6)
        Local estimates ``[r, v]`` (m, m/s), Mars-centred J2000.
    Ps : ndarray, shape (ns, 6, 6)
        Their covariances (m^2, m^2/s, m^2/s^2).
    shares : ndarray, shape (ns,)
        The information share each local carries (reset mode; sums to 1 over the connected).
    xm : ndarray, shape (6,)
        The master (fused) estimate.
    Pm : ndarray, shape (6, 6)
        Its covariance.
    """

    xs: np.ndarray
    Ps: np.ndarray
    shares: np.ndarray
    xm: np.ndarray
    Pm: np.ndarray


class Propagation(NamedTuple):
    """The time update's model: process noise, sub-step and the forces.

    Attributes
    ----------
    q : float
        Process-noise acceleration power spectral density, m^2/s^3.
    max_step : float
        Longest RK4 sub-step, s.
    gm_mars : float
        Mars' gravitational parameter, m^3/s^2.
    tb_t0, tb_step : float
        The third-body table (:class:`~xnavlab.mars.models.dynamics.ThirdBodyTable`): its first
        knot (s TDB past J2000) and its knot spacing (s).
    tb_pos, tb_vel : ndarray, shape (nk, nb, 3)
        The nb third bodies' positions (m) and velocities (m/s) relative to Mars at the knots.
    tb_gm : ndarray, shape (nb,)
        Their gravitational parameters, m^3/s^2.
    """

    q: float
    max_step: float
    gm_mars: float
    tb_t0: float
    tb_step: float
    tb_pos: np.ndarray
    tb_vel: np.ndarray
    tb_gm: np.ndarray


class Plan(NamedTuple):
    """The epochs and the subsystems: when each measures, whether it is connected.

    Attributes
    ----------
    times : ndarray, shape (n,)
        Epochs, s TDB past J2000.
    kinds : ndarray of int64, shape (ns,)
        Subsystem codes (:data:`~xnavlab.mars.kernel.kernels.KIND_XNAV`, ``KIND_UV``, ``KIND_CNS``).
    meas_idx : ndarray of int64, shape (n, ns)
        Row of each epoch's measurement in the subsystem's series, or -1.
    active : ndarray of bool, shape (n, ns)
        Connected subsystems per epoch (an alarm clears the next epoch's entry).
    beta : ndarray, shape (ns,)
        Information-sharing factors (sum 1).
    reset : bool
        Reset mode (else no-reset).
    gate : ndarray, shape (ns,)
        NIS thresholds of the innovation gate (inf: none).
    """

    times: np.ndarray
    kinds: np.ndarray
    meas_idx: np.ndarray
    active: np.ndarray
    beta: np.ndarray
    reset: bool
    gate: np.ndarray


class Sensors(NamedTuple):
    """The measurements and sensor parameters of the three subsystems.

    Attributes
    ----------
    z_x : ndarray, shape (m_x, p)
        XNAV pulse delays, s (paper eq. (1)).
    rm_x, rs_x : ndarray, shape (m_x, 3)
        The filter ephemeris' Mars and Sun at each XNAV epoch, m from the barycentre.
    n_x : ndarray, shape (p, 3)
        Pulsar unit directions.
    d_x, sig_x : ndarray, shape (p,)
        Pulsar distances (m) and delay noise (s).
    z_u : ndarray, shape (m_u, 4)
        UV range (m) and unit direction to Mars (paper eq. (5)).
    sig_r, sig_u : float
        UV range noise (m) and per-axis direction noise (rad).
    z_c : ndarray, shape (m_c, k)
        CNS star-to-Mars angles, rad (paper eq. (6)).
    stars_c : ndarray, shape (k, 3)
        Star unit directions.
    sig_s, sig_h : float
        CNS star and horizon noise, rad.
    """

    z_x: np.ndarray
    rm_x: np.ndarray
    rs_x: np.ndarray
    n_x: np.ndarray
    d_x: np.ndarray
    sig_x: np.ndarray
    z_u: np.ndarray
    sig_r: float
    sig_u: float
    z_c: np.ndarray
    stars_c: np.ndarray
    sig_s: float
    sig_h: float


class Records(NamedTuple):
    """What :func:`~xnavlab.mars.kernel.kernels.run_epochs` writes per epoch (in place).

    Attributes
    ----------
    pos : ndarray of int64, shape (n,)
        Record row of each epoch, or -1 (not recorded).
    x, P : ndarray, shape (nr, 6), (nr, 6, 6)
        The master's estimate and covariance at the recorded epochs (m, m/s).
    xl, Pl : ndarray, shape (nr, ns, 6)
        The locals' estimates and covariance diagonals there.
    nis, flags : ndarray, shape (n, ns)
        Every epoch's NIS and flag (0 no measurement, 1 updated, 2 rejected by the gate,
        3 isolated); ``flags`` int8.
    """

    pos: np.ndarray
    x: np.ndarray
    P: np.ndarray
    xl: np.ndarray
    Pl: np.ndarray
    nis: np.ndarray
    flags: np.ndarray


class WatchState(NamedTuple):
    """The combined detector's state (:class:`xnavlab.mars.faults.watch.Watch`), read and written.

    Attributes
    ----------
    wf : ndarray, shape (ns, 10)
        Float parameters, columns :data:`WF_KMEAN` to :data:`WF_ZQ`.
    wi : ndarray of int64, shape (ns, 15)
        Integer state, columns :data:`WI_ON` to :data:`WI_CHECK` (``wi[i, WI_ON]``:
        subsystem i is watched).
    wS : ndarray, shape (ns, 12)
        CUSUMs: ``S+`` of the m components, then ``S-``, then ``V`` (3 m columns used).
    wsc : ndarray, shape (ns, 4)
        Adaptive scale per component.
    ring : ndarray, shape (ns, 4, W)
        The scale's window of healthy whitened innovations.
    ys_x, ys_u, ys_c : ndarray, shape (m_*, m)
        Whitened innovation of every XNAV, UV, CNS measurement (unitless).
    xbuf : ndarray, shape (nw, 4)
        The XNAV innovation wavelet's window, newest first.
    xG : ndarray, shape (levels, nw)
        Its detail filters (no rows: no wavelet).
    xthr : ndarray, shape (levels,)
        Its thresholds.
    alarm : ndarray, shape (ns, 4)
        The last alarm per subsystem: part and ratio, wavelet code and ratio (-1: none).
    """

    wf: np.ndarray
    wi: np.ndarray
    wS: np.ndarray
    wsc: np.ndarray
    ring: np.ndarray
    ys_x: np.ndarray
    ys_u: np.ndarray
    ys_c: np.ndarray
    xbuf: np.ndarray
    xG: np.ndarray
    xthr: np.ndarray
    alarm: np.ndarray


class PredictScratch(NamedTuple):
    """The time update's working arrays (:func:`xnavlab.mars.kernel.kernel_propagation.predict`).

    Attributes
    ----------
    Phi, Ph, T : ndarray, shape (6, 6)
        The transition matrix, one sub-step's, and a product.
    xc : ndarray, shape (6,)
        The state at a sub-step's start.
    s0, i0, s1, i1, s2, i2 : ndarray, shape (nb, 3)
        The third bodies' positions (m) and indirect accelerations (m/s^2) at t, t + h/2 and
        t + h of an RK4 step.
    """

    Phi: np.ndarray
    Ph: np.ndarray
    T: np.ndarray
    xc: np.ndarray
    s0: np.ndarray
    i0: np.ndarray
    s1: np.ndarray
    i1: np.ndarray
    s2: np.ndarray
    i2: np.ndarray


class Measurement(NamedTuple):
    """One measurement at a predicted state (:func:`xnavlab.mars.kernel.kernel_measurements.measure`),
    of size m <= mm (the first m rows are used).

    Attributes
    ----------
    nu : ndarray, shape (mm,)
        The innovation ``z - h(x)`` (s, m or rad, as the sensor measures).
    H : ndarray, shape (mm, 6)
        The Jacobian's position columns in ``H[:, :3]``; ``H[:, 3:]`` is scratch (the
        velocity columns are zero for all three sensors).
    R : ndarray, shape (mm, mm)
        The measurement noise covariance.
    A : ndarray, shape (mm, 3)
        Scratch of the CNS noise (the unit tangents of the star-to-Mars angles).
    """

    nu: np.ndarray
    H: np.ndarray
    R: np.ndarray
    A: np.ndarray


class UpdateScratch(NamedTuple):
    """The measurement updates' working arrays (:mod:`xnavlab.mars.kernel.kernel_measurements`).

    Attributes
    ----------
    PHt : ndarray, shape (6, mm)
        ``P H^T``.
    S, L : ndarray, shape (mm, mm)
        The innovation covariance (lower triangle) and its Cholesky factor.
    y : ndarray, shape (mm,)
        A vector (a whitened innovation, a row of the gain).
    K, W : ndarray, shape (6, mm)
        The gain and ``K R - T H^T``.
    T : ndarray, shape (6, 6)
        ``(I - K H) P``.
    """

    PHt: np.ndarray
    S: np.ndarray
    L: np.ndarray
    y: np.ndarray
    K: np.ndarray
    W: np.ndarray
    T: np.ndarray


class FusionScratch(NamedTuple):
    """The master's prediction, the information the locals gained and the fusions' working
    arrays (:mod:`xnavlab.mars.kernel.kernel_fusion`).

    Attributes
    ----------
    d : ndarray, shape (6,)
        Jacobi scaling ``1 / sqrt(P_ii)`` of the first fused estimate.
    Y, Ci, Cf : ndarray, shape (6, 6)
        Sum of the scaled information matrices; a scaled covariance and its inverse.
    yv : ndarray, shape (6,)
        Sum of the scaled information vectors.
    xp, Pp : ndarray, shape (6,), (6, 6)
        The master's prediction (m, m/s).
    J, G : ndarray, shape (3, 3)
        The gained information ``sum H^T R^-1 H`` (lower triangle) and ``J (I + P J)^-1``.
    bv : ndarray, shape (3,)
        ``sum H^T R^-1 nu``.
    use : ndarray of bool, shape (ns,)
        The locals fused at this epoch.
    inv_sh : ndarray, shape (ns,)
        ``1 / share`` of each local.
    """

    d: np.ndarray
    Y: np.ndarray
    yv: np.ndarray
    Ci: np.ndarray
    Cf: np.ndarray
    xp: np.ndarray
    Pp: np.ndarray
    J: np.ndarray
    bv: np.ndarray
    G: np.ndarray
    use: np.ndarray
    inv_sh: np.ndarray


class WatchScratch(NamedTuple):
    """The combined detector's working arrays (:mod:`xnavlab.mars.kernel.kernel_watch`).

    Attributes
    ----------
    alarmed : ndarray of bool, shape (ns,)
        The subsystems that alarmed at this epoch.
    zw : ndarray, shape (mm,)
        A whitened innovation over its adaptive scale.
    med : ndarray, shape (W,)
        The medians' working copy of a window.
    cnt : ndarray of int64, shape (8192,)
        The radix selection's histogram.
    """

    alarmed: np.ndarray
    zw: np.ndarray
    med: np.ndarray
    cnt: np.ndarray


def layout():
    """Every container's name and fields, in order: what the compiled kernels read.

    Returns
    -------
    tuple of str
        ``"Name(field field ...)"`` per container.
    """
    return tuple(f"{c.__name__}({' '.join(c._fields)})" for c in
                 (FilterState, Propagation, Plan, Sensors, Records, WatchState))
