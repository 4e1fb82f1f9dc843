"""The named containers of the compiled filter's arguments (:func:`xnavlab.mars.kernels.run_epochs`).

The kernel takes its arrays and settings in six named tuples instead of 54 positional
arguments: :class:`FilterState` (the estimates, updated in place), :class:`Propagation` (the
time update's model), :class:`Plan` (epochs, subsystems, modes), :class:`Sensors` (measurements
and noise), :class:`Records` (the outputs) and :class:`WatchState` (the combined detector's
state, :class:`xnavlab.mars.watch.Watch`). The arrays inside are shared, not copied: what the
kernel writes into them is seen by the caller.

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
(:func:`xnavlab.mars.compile_notice.announce_compile` stops asking once it knows). A call of
:func:`xnavlab.mars.scenarios.run_kernel` over no epoch then costs 33 us (58 us with the 54
positional arguments and that question asked each time; load 3), which matters to the
chi-square detector's 8675 calls in the 30-day run.

A change of a container's fields must come with a change of :mod:`xnavlab.mars.kernels`
(its ``_LAYOUT`` check fails at import until then): numba keys its on-disk cache by that
file's source and the fields' types, not their names, so a reordering here alone would load
machine code that reads the wrong fields.

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

__all__ = ["FilterState", "Propagation", "Plan", "Sensors", "Records", "WatchState", "layout"]


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
        The third-body table (:class:`~xnavlab.mars.dynamics.ThirdBodyTable`): its first
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
        Subsystem codes (:data:`~xnavlab.mars.kernels.KIND_XNAV`, ``KIND_UV``, ``KIND_CNS``).
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
    """What :func:`~xnavlab.mars.kernels.run_epochs` writes per epoch (in place).

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
    """The combined detector's state (:class:`xnavlab.mars.watch.Watch`), read and written.

    Attributes
    ----------
    wf : ndarray, shape (ns, 10)
        Float parameters, columns ``WF_*`` of :mod:`xnavlab.mars.kernels`.
    wi : ndarray of int64, shape (ns, 15)
        Integer state, columns ``WI_*`` of :mod:`xnavlab.mars.kernels` (``wi[i, WI_ON]``:
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


def layout():
    """Every container's name and fields, in order: what the compiled kernels read.

    Returns
    -------
    tuple of str
        ``"Name(field field ...)"`` per container.
    """
    return tuple(f"{c.__name__}({' '.join(c._fields)})" for c in
                 (FilterState, Propagation, Plan, Sensors, Records, WatchState))
