"""SOS and DOS on board, one sample at a time, and their measured cost.

:class:`SOSMonitor` runs one :class:`xnavlab.attitude.ekf.AttitudeEKF` and the four SOS
residuals; :class:`DOSMonitor` runs the four filters of the DOS bank. Fed the same samples
they give the numbers of :func:`xnavlab.attitude.simulation.simulate`. :func:`time_sos_dos`
measures their cost per sample in this process (the paper's remark 3: DOS costs about four
times SOS).

Rates in rad/s, times in s.
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

from xnavlab.attitude._checks import check_sample
from xnavlab.attitude.dos import DOS_GROUPS, dos_rate_matrices
from xnavlab.attitude.ekf import AttitudeEKF
from xnavlab.attitude.sensors import DEG_PER_H, gyro_matrix
from xnavlab.attitude.simulation import make_config, simulate_sensors
from xnavlab.core.validate import check_finite_array, check_int, check_real, make_rng

__all__ = [
    "SOSMonitor",
    "DOSMonitor",
    "time_sos_dos",
]


class SOSMonitor:
    """SOS on board, one sample at a time: one EKF plus the four residuals.

    Parameters
    ----------
    q0 : array_like, shape (4,)
        First star-tracker quaternion.
    config : SimConfig, optional
    drift_ref : array_like, shape (3,), optional
        Drift references, rad/s (default zeros: the paper's literal ``|b_hat|``).
    parity_ref : float
        Parity reference, rad/s.

    Examples
    --------
    >>> from xnavlab.attitude.motion import DEFAULT_Q0
    >>> m = SOSMonitor(DEFAULT_Q0)
    >>> m.step(gyro_matrix() @ np.zeros(3), DEFAULT_Q0).shape
    (4,)
    """

    n_filters = 1

    def __init__(self, q0, config=None, drift_ref=None, parity_ref=0.0):
        cfg = make_config(config)
        self.config = cfg
        self.filters = [self._make(q0, cfg, np.eye(3))]
        self.h4 = gyro_matrix(cfg.skew_axis)[3]
        self.drift_ref = np.zeros(3) if drift_ref is None else check_finite_array(
            "drift_ref", drift_ref, shape=(3,))
        self.parity_ref = check_real("parity_ref", parity_ref)
        self._first = True

    @staticmethod
    def _make(q0, cfg, T):
        TT = T @ T.T
        f = AttitudeEKF(
            q0, cfg.dt, cfg.gyro_noise_deg_per_h * DEG_PER_H,
            math.radians(cfg.star_noise_deg), cfg.drift_walk_deg_per_h_sqrt_s * DEG_PER_H,
            cfg.drift_sigma0_deg_per_h * DEG_PER_H,
        )
        f.gyro_cov = f.gyro_cov @ TT  # noise of T w_g: sigma^2 T T^T
        f.drift_cov = f.drift_cov @ TT
        f.P[4:, 4:] = f.P[4:, 4:] @ TT
        return f

    def step(self, omega_g, q_meas):
        """Process one gyro sample (4,) and star-tracker quaternion (4,), of norm 1 to
        :data:`xnavlab.core.quaternions.UNIT_TOL` (else refused before any filter moves);
        residuals (4,).

        The gyro sample of step ``k`` drives the prediction to ``k + 1``, as in
        :func:`~.simulation.simulate`.
        """
        wg = check_sample("omega_g", omega_g, 4)
        qm = check_sample("q_meas", q_meas, 4, unit=True)  # before the prediction moves x
        f = self.filters[0]
        if not self._first:
            f.predict(self._w_prev)
        f.update(qm)
        self._first = False
        self._w_prev = wg[:3]
        r = np.abs(f.drift - self.drift_ref)  # paper eq. (35)
        r4 = abs(wg[3] - self.h4 @ wg[:3] - self.parity_ref)  # paper eq. (37)
        return np.append(r, r4)


class DOSMonitor(SOSMonitor):
    """DOS on board: four EKFs, filter ``j`` fed by the gyros of :data:`~.dos.DOS_GROUPS` ``[j]``.

    Parameters
    ----------
    q0 : array_like, shape (4,)
    config : SimConfig, optional
    drift_ref : array_like, shape (4, 3), optional
        References of the four filters' drifts, rad/s (default zeros).

    Examples
    --------
    >>> from xnavlab.attitude.motion import DEFAULT_Q0
    >>> m = DOSMonitor(DEFAULT_Q0)
    >>> m.step(gyro_matrix() @ np.zeros(3), DEFAULT_Q0).shape
    (4,)
    """

    n_filters = 4

    def __init__(self, q0, config=None, drift_ref=None):
        cfg = make_config(config)
        self.config = cfg
        self.T = dos_rate_matrices(cfg.skew_axis)
        self.filters = [self._make(q0, cfg, T) for T in self.T]
        self.mix = np.zeros((4, 3, 4))  # w_tilde_j = T_j w_g[group_j] = mix_j w_g
        for j, g in enumerate(DOS_GROUPS):
            self.mix[j][:, list(g)] = self.T[j]
        self.drift_ref = np.zeros((4, 3)) if drift_ref is None else check_finite_array(
            "drift_ref", drift_ref, shape=(4, 3))
        self._first = True

    def step(self, omega_g, q_meas):
        """Process one sample; the four residuals ``|d_j_hat - d_j_ref|`` (4,), rad/s."""
        wg = check_sample("omega_g", omega_g, 4)
        qm = check_sample("q_meas", q_meas, 4, unit=True)  # before any filter moves
        r = np.empty(4)
        for j, (f, mix) in enumerate(zip(self.filters, self.mix, strict=True)):
            if not self._first:
                f.predict(mix @ self._w_prev)
            f.update(qm)
            r[j] = np.linalg.norm(f.drift - self.drift_ref[j])
        self._first = False
        self._w_prev = wg
        return r


#: Wall time of one timed sample of SOS and DOS together, s (2.5 ms measured, 2026-11-29).
_SECONDS_PER_STEP = 2.5e-3
#: The most samples :func:`time_sos_dos` times in all (``n_steps * repeats``): about 8 minutes.
_MAX_TIMED_STEPS = 200_000


def time_sos_dos(n_steps=500, repeats=3, config=None, rng=None):
    """Measured cost per sample of :class:`DOSMonitor` against :class:`SOSMonitor`.

    Both run on the same simulated data in this process; each is timed with
    :func:`!time.perf_counter` over ``n_steps`` samples, ``repeats`` times alternately,
    and the fastest repeat is kept (the least disturbed by the machine).

    Parameters
    ----------
    n_steps : int
        Samples per timing, in [10, 1e5].
    repeats : int
        Timings per scheme, in [1, 1e4], with ``n_steps * repeats`` at most 2e5: a sample of
        both monitors took about 2.5 ms on a 2-core machine (2026-11-29), so 2e5 take about 8
        minutes (1e5 steps of 1e4 repeats would take 29 days).
    config : SimConfig, optional
    rng : numpy.random.Generator or int, optional

    Returns
    -------
    dict
        ``sos_us`` and ``dos_us`` (microseconds per sample) and ``ratio`` (DOS/SOS).

    Examples
    --------
    >>> r = time_sos_dos(n_steps=20, repeats=1)
    >>> r["ratio"] > 1.0
    True
    """
    n_steps = check_int("n_steps", n_steps, 10, 10**5)  # n_steps dt within SimConfig's duration
    repeats = check_int("repeats", repeats, 1, 10**4)
    total = n_steps * repeats
    if total > _MAX_TIMED_STEPS:  # review 35p: 1e5 x 1e4 steps were allowed, about 29 days
        hours = total * _SECONDS_PER_STEP / 3600.0
        raise ValueError(f"n_steps x repeats must be at most {_MAX_TIMED_STEPS} timed samples (about "
                         f"{_MAX_TIMED_STEPS * _SECONDS_PER_STEP / 60:.0f} minutes at "
                         f"{_SECONDS_PER_STEP * 1e3:g} ms a sample of SOS and DOS), got n_steps = "
                         f"{n_steps} x repeats = {repeats} = {total:.3g}, about {hours:.3g} hours "
                         f"(at most {max(_MAX_TIMED_STEPS // n_steps, 1)} repeats of {n_steps} steps)")
    cfg = make_config(config)
    if cfg.n < n_steps:
        cfg = dataclasses.replace(cfg, duration=n_steps * cfg.dt)
    (_, _, _), wg, qs = simulate_sensors(cfg, (), make_rng(rng))
    best = {"sos": math.inf, "dos": math.inf}
    for _ in range(repeats):
        for name, cls in (("sos", SOSMonitor), ("dos", DOSMonitor)):
            mon = cls(qs[0], cfg)
            t0 = time.perf_counter()
            for k in range(n_steps):
                mon.step(wg[k], qs[k])
            best[name] = min(best[name], time.perf_counter() - t0)
    return {
        "sos_us": 1e6 * best["sos"] / n_steps,
        "dos_us": 1e6 * best["dos"] / n_steps,
        "ratio": best["dos"] / best["sos"],
    }
