"""The federated Kalman filter of Carlson (1990): local filters, information sharing, fusion.

Each navigation subsystem runs its own local filter on its own sensor. The master
filter fuses the local estimates in information form,

.. math::

   P_f^{-1} = \\sum_{i \\in A} P_i^{-1}, \\qquad
   \\hat x_f = P_f \\sum_{i \\in A} P_i^{-1} \\hat x_i ,

over the set ``A`` of connected (healthy) locals. The common process noise and the
common prior would make the locals' errors correlated; Carlson's information-sharing
principle removes the correlation by giving local ``i`` only the share ``beta_i`` of
the information (``sum beta_i = 1``): its prior covariance is ``P / beta_i`` and its
process noise ``Q / beta_i``. Two modes:

``"reset"`` (fusion-reset)
    after each fusion every local restarts from the master's estimate with covariance
    ``P_f / beta_i``. With fusion at every epoch this is exactly the centralised EKF
    for a linear system, and the most accurate mode.
``"no-reset"``
    the locals run independently from ``P0 / beta_i`` with ``Q / beta_i`` and the
    master only fuses; the fused covariance is an upper bound (conservative), and a
    fault in one subsystem cannot leak into the others through the resets.

Switching out and back in (fault isolation, paper section 3): a switched-out local
does time updates only and is left out of the fusion. In reset mode the shares are
renormalised over the connected locals, ``beta_i / sum_{j in A} beta_j``, so no
information is lost; a switched-out local is kept at the master's estimate with the
full covariance ``P_f`` (it carries no share), and when it is switched back in the
master is re-split among the new set before its next measurement update, so no
information is counted twice. In no-reset mode a switched-out local simply
free-wheels on its dynamics and rejoins the fusion with its grown covariance.

The master holds no sensor (``beta_m = 0``); when every local is switched out it
propagates its last estimate (time update only).

Fusion is computed on Jacobi-scaled covariances (each divided by the standard
deviations of the first connected local) and on deviations from that local's
estimate, which keeps the 6x6 inversions well conditioned when position (m) and
velocity (m/s) variances differ by many orders of magnitude.

Examples
--------
Two unbiased estimates of a scalar with variances 1 and 3:

>>> x, P = fuse([np.array([0.0]), np.array([4.0])], [np.eye(1), 3 * np.eye(1)])
>>> float(x[0]), float(P[0, 0])
(1.0, 0.75)
"""

from __future__ import annotations

import math

import numpy as np

from xnavlab.core.filters import EKF, UKF, Update, ekf_update, symmetrize, ukf_update
from xnavlab.core.validate import (
    check_arrays,
    check_bool,
    check_choice,
    check_covariance,
    check_finite_array,
    check_int,
    check_items,
    check_real,
    check_vector,
)

__all__ = ["MODES", "MAX_LOCAL", "fuse", "share_factors", "FederatedFilter"]

#: The most local filters a federated filter takes: one per sensor subsystem, and each holds a
#: copy of the state and its covariance, so a count beyond a thousand is no navigation system
#: (and 10**30 would ask numpy for an array it cannot size).
MAX_LOCAL = 1000

#: Federated-filter modes.
MODES = ("reset", "no-reset")


def fuse(xs, Ps, use=None, check=True):
    """Information-form fusion of local estimates.

    Parameters
    ----------
    xs : sequence of array_like, each shape (n,)
        Local estimates.
    Ps : sequence of array_like, each shape (n, n)
        Their covariances.
    use : sequence of bool, optional
        Which locals to fuse (default all).
    check : bool
        Check that every estimate is finite of shape (n,) and every covariance finite,
        symmetric and positive definite of shape (n, n) (``False`` in checked loops).

    Returns
    -------
    x : ndarray, shape (n,)
        ``P_f sum P_i^-1 x_i``.
    P : ndarray, shape (n, n)
        ``(sum P_i^-1)^-1``.

    Raises
    ------
    ValueError
        If no local is used (this function has no master estimate to fall back on; a
        :class:`FederatedFilter` with every local switched out coasts on its master instead),
        or (``check=True``) an estimate or covariance is not valid.

    Examples
    --------
    >>> x, P = fuse([np.zeros(2), np.ones(2)], [np.eye(2), np.eye(2)], use=[False, True])
    >>> x.tolist(), P.tolist()
    ([1.0, 1.0], [[1.0, 0.0], [0.0, 1.0]])
    """
    if check_bool("check", check):  # before any cast: a complex entry is refused, not cut
        xs = check_arrays("xs", xs, ndim=1)
        Ps = check_arrays("Ps", Ps, ndim=2)
    xs = [np.asarray(x, dtype=float) for x in xs]
    Ps = [np.asarray(P, dtype=float) for P in Ps]
    if len(Ps) != len(xs):
        raise ValueError(f"Ps must hold one covariance per estimate ({len(xs)}), got {len(Ps)}")
    if use is not None:
        use = _flags("use", use, len(xs), "one per estimate")
    if check and xs:
        n = check_vector("xs[0]", xs[0]).size
        for i, (x, P) in enumerate(zip(xs, Ps, strict=True)):
            check_vector(f"xs[{i}]", x, n)
            check_covariance(f"Ps[{i}]", P, n, definite=True)
    use = [True] * len(xs) if use is None else [bool(u) for u in use]
    idx = [i for i, u in enumerate(use) if u]
    if not idx:
        raise ValueError("use must select at least one local estimate to fuse")
    ref = idx[0]
    d = np.sqrt(np.diag(Ps[ref]))
    Y = np.zeros_like(Ps[ref])
    y = np.zeros_like(xs[ref])
    for i in idx:
        Yi = np.linalg.inv(Ps[i] / np.outer(d, d))  # scaled P_i^-1
        Y += symmetrize(Yi)
        y += Yi @ ((xs[i] - xs[ref]) / d)  # sum P_i^-1 (x_i - x_ref)
    Cf = symmetrize(np.linalg.inv(Y))  # P_f = (sum P_i^-1)^-1
    return xs[ref] + d * (Cf @ y), Cf * np.outer(d, d)  # x_f = P_f sum P_i^-1 x_i


def share_factors(beta, active):
    """Information shares of the locals: ``beta_i / sum_{j active} beta_j``; 1 if switched out.

    Parameters
    ----------
    beta : array_like, shape (N,)
        Information-sharing factors, positive finite numbers (only their ratios count).
    active : array_like of bool, shape (N,)
        Connected locals.

    Examples
    --------
    >>> share_factors([0.5, 0.25, 0.25], [True, False, True]).tolist()
    [0.6666666666666666, 1.0, 0.3333333333333333]
    """
    beta = check_vector("beta", beta)
    if beta.size == 0:
        raise ValueError("beta must hold at least one information-sharing factor, got an empty array")
    if np.any(beta <= 0.0):
        raise ValueError(f"beta must hold positive information-sharing factors, got {beta.tolist()}")
    active = _flags("active", active, beta.size, "one per factor of beta")
    if not active.any():
        return np.ones_like(beta)
    # shares are ratios: the active betas scaled to at most 1 sum without overflow (1e308s)
    b = beta[active] / beta[active].max()
    out = np.ones_like(beta)
    out[active] = b / b.sum()  # beta_i / sum_{j active} beta_j
    return out


def _flags(name, value, n, why):
    """``value`` as ``n`` booleans (True/False or 1/0, not a mixture), else one ValueError."""
    if np.ma.is_masked(value):  # np.asarray would use the masked flags (review 35m (5) 1)
        raise ValueError(f"{name} has masked entries (no flag to use: fill or drop them)")
    arr = np.asarray(value)
    ok = arr.dtype.kind == "b" or (arr.dtype.kind in "iuf" and np.all((arr == 0) | (arr == 1)))
    mixed = isinstance(value, list | tuple) and len({isinstance(v, bool | np.bool_) for v in value}) > 1
    if not ok or mixed or arr.ndim != 1 or arr.size != n:
        raise ValueError(f"{name} must hold {n} flags (true/false, {why}), got {value!r:.80}")
    return arr.astype(bool)


def _name(label, value):
    if not isinstance(value, str) or not value:
        raise ValueError(f"{label} must be a non-empty string, got {value!r:.80}")
    return value


class FederatedFilter:
    """Carlson's federated filter with switchable locals.

    Parameters
    ----------
    x0 : array_like, shape (n,)
        Initial estimate (common to all locals).
    P0 : array_like, shape (n, n)
        Its covariance.
    n_local : int
        Number of local filters (subsystems), in [1, MAX_LOCAL].
    beta : array_like, shape (n_local,), optional
        Information-sharing factors (normalised to sum 1; default equal).
    mode : {"reset", "no-reset"}
        See the module docstring.
    kind : {"ekf", "ukf"}
        Local filter type.
    names : sequence of str, optional
        Names of the subsystems (for messages): ``n_local`` non-empty strings, none twice.

    Attributes
    ----------
    locals : list of EKF or UKF
        The local filters.
    x, P : ndarray
        The master (fused) estimate.
    active : ndarray of bool
        Which locals are connected.
    shares : ndarray
        Information share each local currently carries.

    Examples
    --------
    A scalar random walk seen by two sensors; the second is switched out:

    >>> ff = FederatedFilter([0.0], [[100.0]], n_local=2)
    >>> _ = ff.predict(lambda s: s, np.eye(1), [[1.0]])
    >>> _ = ff.update(0, [1.0], lambda s: s, np.eye(1), [[1.0]])
    >>> _ = ff.update(1, [1.2], lambda s: s, np.eye(1), [[1.0]])
    >>> x, P = ff.fuse()
    >>> round(float(x[0]), 4), round(float(P[0, 0]), 4)
    (1.0946, 0.4975)
    >>> ff.switch_out(1)
    >>> ff.shares.tolist()
    [1.0, 1.0]
    """

    def __init__(self, x0, P0, n_local=3, beta=None, mode="reset", kind="ekf", names=None):
        self.mode = check_choice("mode", mode, MODES)
        self.kind = check_choice("kind", kind, ("ekf", "ukf"))
        x0 = check_vector("x0", x0)
        if x0.size == 0:
            raise ValueError("x0 must hold at least one state component, got shape (0,)")
        P0 = symmetrize(check_covariance("P0", P0, x0.size, definite=True))
        n_local = check_int("n_local", n_local, 1, MAX_LOCAL)
        if beta is None:
            beta = np.full(n_local, 1.0 / n_local)
        beta = check_finite_array("beta", beta).reshape(-1)
        if beta.shape != (n_local,) or np.any(beta <= 0):
            raise ValueError(f"beta must hold {n_local} positive information-sharing factors")
        self.beta = beta / beta.sum()
        if names is None:
            names = tuple(str(i) for i in range(n_local))
        # a list (not a string split into letters), no name twice, one a local filter
        names = check_items("names", names, "name", lambda label, v: _name(label, v))
        if len(names) != n_local:
            raise ValueError(f"names must hold {n_local} names, one for each local filter "
                             f"(n_local), got {len(names)}")
        self.names = names
        self.active = np.ones(n_local, dtype=bool)
        self.shares = share_factors(self.beta, self.active)
        cls = EKF if self.kind == "ekf" else UKF
        self.locals = [cls(x0, P0 / s) for s in self.shares]  # P_i = P0 / beta_i
        self.x, self.P = x0.astype(float).copy(), P0

    # ---------------------------------------------------------------- time update
    def predict(self, f, F, Q):
        """Time update of every local (process noise ``Q / share_i``) and of the master.

        ``F`` is ignored by UKF locals. Returns ``self``.
        """
        Q = check_covariance("Q", Q, self.x.size)
        for lf, s in zip(self.locals, self.shares, strict=True):
            if self.kind == "ekf":
                lf.predict(f, F, Q / s)  # Q_i = Q / beta_i
            else:
                lf.predict(f, Q / s)
        master = EKF(self.x, self.P).predict(f, F, Q)
        self.x, self.P = master.x, master.P
        return self

    # --------------------------------------------------------- measurement update
    def update(self, i, z, h, H, R, gate=math.inf, residual=None):
        """Measurement update of local ``i``; a switched-out local only evaluates its innovation.

        Parameters
        ----------
        i : int
            Local index.
        z, h, H, R : array_like, callable, ndarray, ndarray
            As :func:`xnavlab.core.filters.ekf_update` (``H`` unused by UKF locals).
        gate : float
            NIS threshold: an innovation with a larger NIS is rejected (time update only).
        residual : callable, optional
            ``residual(z, h(x))``, as :func:`xnavlab.core.filters.ekf_update` (angles that wrap).

        Returns
        -------
        Update
            Innovation statistics; ``x``/``P`` are the local's estimate afterwards.
        """
        if gate != math.inf:
            gate = check_real("gate", gate, 0.0)
        i = check_int("i", i, 0, len(self.locals) - 1)
        lf = self.locals[i]
        if self.kind == "ekf":
            up = ekf_update(lf.x, lf.P, z, h, H, R, residual)
        else:
            up = ukf_update(lf.x, lf.P, z, h, R, lf.alpha, lf.beta, lf.kappa, residual)
        if z is not None and self.active[i] and up.nis <= gate:
            lf.x, lf.P = up.x, up.P
        lf.last = up
        return Update(lf.x, lf.P, up.innovation, up.S, up.nis)

    # ------------------------------------------------------------------- fusion
    def fuse(self, next_active=None):
        """Fuse the connected locals into the master; in reset mode, reset the locals.

        Parameters
        ----------
        next_active : array_like of bool, optional
            Connection state for the next epoch (applied before the reset, so a local
            switched back in receives its share of the master).

        Returns
        -------
        x, P : ndarray
            The master estimate.
        """
        if self.active.any():
            self.x, self.P = fuse([lf.x for lf in self.locals], [lf.P for lf in self.locals],
                                  self.active)
        if next_active is not None:
            self.set_active(next_active)
        elif self.mode == "reset":
            self._reset()
        return self.x, self.P

    def _reset(self):
        self.shares = share_factors(self.beta, self.active)
        for lf, s in zip(self.locals, self.shares, strict=True):
            lf.x, lf.P = self.x.copy(), self.P / s  # P_i = P_f / beta_i

    # ------------------------------------------------------------ reconfiguration
    def switch_out(self, i):
        """Disconnect local ``i`` (time updates only, left out of the fusion).

        Call between epochs (after :meth:`fuse`). In reset mode the master is re-split
        among the remaining locals.
        """
        self._set(i, False)

    def switch_in(self, i):
        """Reconnect local ``i``. Call between epochs (after :meth:`fuse`)."""
        self._set(i, True)

    def set_active(self, active):
        """Set which locals are connected (array of bool); call between epochs.

        In reset mode the master is re-split among the connected locals. Every local may be
        switched out (a fault-tolerant run that isolates every subsystem): the master then
        coasts on its own time updates, and :meth:`fuse` returns it unchanged, by design
        (the module docstring), unlike the function :func:`fuse`, which has no master and
        refuses ``use`` with no local.
        """
        self.active = _flags("active", active, len(self.locals), "one per local filter")
        if self.mode == "reset":
            self._reset()

    def _set(self, i, flag):
        i = check_int("i", i, 0, len(self.locals) - 1)
        active = self.active.copy()
        active[i] = flag
        self.set_active(active)

    def __repr__(self):
        state = ", ".join(f"{n}:{'on' if a else 'off'}" for n, a in zip(self.names, self.active,
                                                                       strict=True))
        return f"FederatedFilter(mode={self.mode!r}, {state})"
