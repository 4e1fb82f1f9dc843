"""The TOA of a fold: photons time-transferred along the a-priori orbit, a time tag, the filter's model.

An X-ray TOA is not taken at an instant. Over the main paper's 500-s window the spacecraft
moves about 1,500 km along its orbit and Mars about 12,000 km about the Sun, and the delay of
eq. (1) changes by up to 22-40 ms for the paper's four pulsars (the orbit's part: 1.5-3.7 ms;
13-15 periods of the millisecond pulsars, more than one of the Crab): folded as they arrive,
the photons would show no pulse. A TOA is made thus (:func:`fold_toa`, after Sheikh et al.
2006 and Emadzadeh & Speyer 2010):

1. each photon's arrival time ``t_i`` is time-transferred to the SSB with the delay at the
   a-priori position *at its own time*, ``s_i = t_i + Delta_t(r_hat(t_i))`` (eq. (1) along the
   orbit the filter predicts, ``correction="apriori"``);
2. the ``s_i`` are folded with the pulsar's phase model and the pulse offset ``tau_hat`` is
   measured (maximum likelihood, :func:`xnavlab.mars.timing.timing_bound.ml_phase_shift`; late
   positive);
3. the measurement is the delay at a stated time tag, ``z = Delta_t(r_hat(t_tag)) - tau_hat``.

With ``e(t) = Delta_t(r(t)) - Delta_t(r_hat(t))`` the a-priori error along the line of sight,
the fold measures its mean over the window, ``-tau_hat = e_bar`` (to first order), so

.. math::

   z = \\Delta t\\big(r(t_{tag})\\big) + \\big[\\bar e - e(t_{tag})\\big] + v .

**The filter's model** is ``z = h(x(t_tag)) + v``, ``h`` eq. (1) at the tag (the book's
instantaneous model), ``R`` the TOA variance (:mod:`xnavlab.mars.timing.timing_bound`), with the tag
at the window's mid-time: the linear part of ``e`` then cancels and the bracket is
``(n . delta_a) T^2 / (24 c)`` (``delta_a`` the a-priori acceleration error: the gravity
gradient times the position error). Tagged at an end it would be ``-+ (n . delta_v) T / (2c)``.
:func:`first_order_error` gives the bracket; :func:`expected_error` the error of the
noise-free fold itself; :func:`simulate_window_photons` and :func:`fold_toa` the photon-level
simulation and processing. A mid-window tag means the measurement is known half a window after
its tag; the book's runs process it at the tag (a simulation may).

Two cheaper processings are measured beside it (``correction``): ``"mars"`` time-transfers each
photon with Mars's ephemeris at its time but holds the spacecraft at its a-priori position at
the tag (the orbit's motion within the window ignored), and ``"constant"`` uses the delay at
the tag for every photon (the whole window treated as one instant).

:func:`window_survey` measures all of them over one orbit of the paper's scenario
(:data:`PAPER_ERROR0`, the paper's initial error, and :data:`SETTLED_ERROR`, its fused accuracy).

Times inside a window are offsets ``u`` from the window's mid-time (s), so that float64 keeps
them to 1e-13 s; delays are s (``Delta_t``, the pulse reaches the spacecraft earlier than the
SSB by it, chapter 2's sign). States are Mars-centred J2000, m and m/s.

Examples
--------
>>> w = fold_window("B1821-24", dynamics.MARS_T0, dynamics.MARS_STATE0)
>>> round(w.delay_change() * 1e3, 2)      # ms over the window, Mars's and the orbit's motion
38.12
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from xnavlab.core import dates, ephemeris
from xnavlab.core.constants import DAY, C
from xnavlab.core.diskcache import entry_path, store
from xnavlab.core.validate import (
    check_bool,
    check_choice,
    check_finite_array,
    check_int,
    check_real,
    check_vector,
    make_rng,
    shown,
)
from xnavlab.mars.models import dynamics
from xnavlab.mars.timing import pulsars, timing_bound, toa
from xnavlab.mars.timing._checks import check_epoch, check_photons

__all__ = [
    "CORRECTIONS",
    "TAGS",
    "PAPER_ERROR0",
    "SETTLED_ERROR",
    "FoldWindow",
    "fold_window",
    "tag_offset",
    "first_order_error",
    "FoldError",
    "expected_error",
    "simulate_window_photons",
    "fold_photons",
    "FoldTOA",
    "fold_toa",
    "window_survey",
    "SURVEY_COLUMNS",
    "survey_html",
    "plot_survey",
]

#: How each photon's time is carried to the SSB: along the a-priori orbit (``"apriori"``, the
#: right way), with Mars's motion only (``"mars"``: the spacecraft held at its tag position), or
#: with the tag's delay for every photon (``"constant"``).
CORRECTIONS = ("apriori", "mars", "constant")

#: Named time tags: the window's start, mid-time and end.
TAGS = ("start", "mid", "end")

#: The paper's initial error (Fan et al. 2016, section 4.1: 5 km and 1 m/s on each axis), as an
#: a-priori error ``r_hat - r``, ``v_hat - v`` (m, m/s).
PAPER_ERROR0 = (5000.0, 5000.0, 5000.0, 1.0, 1.0, 1.0)

#: The paper's fused accuracy after the filter settles (28.835 m and 0.02149 m/s, 3-D RMS) as an
#: equal error on each axis, m and m/s.
SETTLED_ERROR = tuple([28.835 / math.sqrt(3.0)] * 3 + [0.02149 / math.sqrt(3.0)] * 3)


def _spline(x, y):
    from scipy.interpolate import CubicSpline  # imported here: only a window needs it

    return CubicSpline(x, y, axis=0)


@dataclass(frozen=True, eq=False)
class FoldWindow:
    """One integration window of one pulsar: the true and a-priori orbits within it.

    Made by :func:`fold_window`. Grid arrays are sampled at offsets ``u`` (s) from the mid-time.

    Attributes
    ----------
    pulsar : Pulsar
    t_mid : float
        Mid-time, s TDB past J2000.
    duration : float
        Window length T, s.
    u : ndarray, shape (m,)
        Grid offsets from ``t_mid``, s, from ``-T/2`` to ``T/2``.
    r_true, r_apriori : ndarray, shape (m, 3)
        True and a-priori spacecraft positions, Mars-centred, m.
    r_mars, r_sun : ndarray, shape (m, 3)
        Mars and the Sun relative to the SSB (the ephemeris), m.
    d0 : float
        True delay at ``t_mid``, s.
    phase0 : float
        The pulsar's phase, cycles, at SSB time ``t_mid + d0`` (its timing model: known).
    """

    pulsar: pulsars.Pulsar
    t_mid: float
    duration: float
    u: np.ndarray
    r_true: np.ndarray
    r_apriori: np.ndarray
    r_mars: np.ndarray
    r_sun: np.ndarray
    d0: float
    phase0: float = 0.0
    _cache: dict = field(default_factory=dict, compare=False, repr=False)

    def delay(self, r):
        """Delay (eq. (1), the paper's Shapiro form) of positions ``r`` (m, 3) on the grid, s."""
        n, dist = pulsars.directions([self.pulsar])
        return toa.delay(self.r_mars + r, n, dist, self.r_sun, shapiro="paper")[:, 0]

    def true_delay(self):
        """``Delta_t(r(t)) - d0`` on the grid, s."""
        if "true" not in self._cache:
            self._cache["true"] = self.delay(self.r_true) - self.d0
        return self._cache["true"]

    def processing_delay(self, correction="apriori", tag="mid"):
        """The delay a processing puts on each photon, minus ``d0``, on the grid, s.

        ``"apriori"``: ``Delta_t(r_hat(t))``; ``"mars"``: ``Delta_t`` with Mars at ``t`` and the
        spacecraft at ``r_hat(t_tag)``; ``"constant"``: ``Delta_t(r_hat(t_tag))``.
        """
        check_choice("correction", correction, CORRECTIONS)
        u_tag = tag_offset(tag, self.duration)
        key = (correction, u_tag if correction != "apriori" else None)
        if key not in self._cache:
            if correction == "apriori":
                d = self.delay(self.r_apriori)
            else:
                r_tag = _spline(self.u, self.r_apriori)(u_tag)
                d = self.delay(np.broadcast_to(r_tag, self.r_apriori.shape))
                if correction == "constant":
                    d = np.full_like(d, float(_spline(self.u, d)(u_tag)))
            self._cache[key] = d - self.d0
        return self._cache[key]

    def error(self, correction="apriori", tag="mid"):
        """``eps(u) = Delta_t(r(t)) - (processing delay)`` on the grid, s (``e(t)`` for apriori)."""
        return self.true_delay() - self.processing_delay(correction, tag)

    def delay_change(self):
        """Change of the true delay over the window, s (end minus start)."""
        d = self.true_delay()
        return float(d[-1] - d[0])

    def orbit_delay_change(self):
        """The part of :meth:`delay_change` from the orbit about Mars, s.

        The true delay minus that of a spacecraft held at its mid-time position (Mars's
        motion), end minus start.
        """
        r_mid = _spline(self.u, self.r_true)(0.0)
        d = self.true_delay() - self.delay(np.broadcast_to(r_mid, self.r_true.shape))
        return float(d[-1] - d[0])


def fold_window(pulsar, t_start, state_true, error=None, duration=500.0, ephem="de421",
                step=1.0, phase0=0.0):
    """The window ``[t_start, t_start + duration]`` of one pulsar, with its true and a-priori orbits.

    Both orbits are integrated from ``t_start`` with the truth's force model
    (:func:`xnavlab.mars.models.dynamics.propagate`: Mars, the Sun and Jupiter): the truth from
    ``state_true``, the a-priori from ``state_true + error``, so the a-priori error within the
    window is that initial error carried by the dynamics.

    Parameters
    ----------
    pulsar : str or Pulsar
    t_start : float
        Window start, s TDB past J2000.
    state_true : array_like, shape (6,)
        True state at ``t_start``, Mars-centred J2000, m and m/s (above Mars and slower than
        any craft bound to the Sun: :func:`xnavlab.mars.models.dynamics.check_state0`).
    error : array_like, shape (6,), optional
        A-priori minus true state at ``t_start`` (default none: a perfect a-priori).
    duration : float
        Window length, s (the integration time; paper: 500).
    ephem : {"de421", "de405"}
        Ephemeris of Mars and the Sun.
    step : float
        Grid step, s (cubic splines in between: error below 1e-15 s at 1 s).
    phase0 : float
        The pulsar's phase at SSB time ``t_mid + d0``, cycles (see :class:`FoldWindow`).

    Returns
    -------
    FoldWindow

    Examples
    --------
    >>> w = fold_window("B0531+21", dynamics.MARS_T0, dynamics.MARS_STATE0, error=PAPER_ERROR0)
    >>> w.u[0], w.u[-1], round(float(np.abs(w.error()).max()) * C)     # s, s, m
    (-250.0, 250.0, 8175)
    """
    p = pulsars.get(pulsar)
    t_start = check_epoch("t_start", t_start)  # float32 refused (it resolves 32 s at 5e8 s)
    duration = check_real("duration", duration, 1.0, 86400.0)
    step = check_real("step", step, 0.01, 60.0)
    state_true = dynamics.check_state0(state_true, "state_true")  # above Mars, a physical speed
    err = np.zeros(6) if error is None else check_vector("error", error, 6)
    dynamics.check_state0(state_true + err, "state_true + error")  # the a-priori: named as given
    phase0 = check_real("phase0", phase0)
    lo, hi = ephemeris.coverage(ephem)
    if not (lo <= t_start and t_start + duration <= hi):  # else the ephemeris names its t
        raise ValueError(f"t_start must lie in {dates.epoch_range(lo, hi - duration)} (the window in "
                         f"{ephem.upper()}), got {dates.epoch_text(t_start)}")
    n = max(4, math.ceil(duration / step))
    rel = np.linspace(0.0, duration, n + 1)  # from t_start
    t = t_start + rel
    x_true = dynamics.propagate(t, state_true, t_start, ephem=ephem)
    x_ap = dynamics.propagate(t, state_true + err, t_start, ephem=ephem)
    r_mars = ephemeris.position("mars", t, ephem)
    r_sun = ephemeris.position("sun", t, ephem)
    u = rel - duration / 2.0
    mid = _spline(u, x_true[:, :3])(0.0)
    n_vec, dist = pulsars.directions([p])
    d0 = float(toa.delay(_spline(u, r_mars)(0.0) + mid, n_vec, dist, _spline(u, r_sun)(0.0),
                         shapiro="paper")[0])
    return FoldWindow(p, t_start + duration / 2.0, duration, u, x_true[:, :3], x_ap[:, :3],
                      r_mars, r_sun, d0, phase0)


def _check_window(window):
    """``window`` if it is a :class:`FoldWindow`, else one ValueError naming it."""
    if not isinstance(window, FoldWindow):
        raise ValueError(f"window must be a FoldWindow (from fold_window), got {shown(window)}")
    return window


def tag_offset(tag, duration):
    """Offset of a time tag from the window's mid-time, s: ``"start"``, ``"mid"``, ``"end"`` or s.

    Examples
    --------
    >>> tag_offset("end", 500.0), tag_offset(-100.0, 500.0)
    (250.0, -100.0)
    """
    duration = check_real("duration", duration, 0.0, lo_open=True)
    if isinstance(tag, str):
        check_choice("tag", tag, TAGS)
        return {"start": -0.5, "mid": 0.0, "end": 0.5}[tag] * duration
    return check_real("tag", tag, -duration / 2.0, duration / 2.0)


def first_order_error(window, correction="apriori", tag="mid"):
    """The measurement's error to first order: ``mean_u eps(u) - eps(u_tag)``, s.

    For ``"apriori"`` this is ``e_bar - e(t_tag)`` of the module notes: what the instantaneous
    model ``z = h(x(t_tag))`` leaves out. (The fold's own estimate weighs the window uniformly,
    as the photons arrive.) A ``window`` that is no :class:`FoldWindow` is refused (one
    ``ValueError``), here and in every function that takes one.

    Examples
    --------
    >>> w = fold_window("B1937+21", dynamics.MARS_T0, dynamics.MARS_STATE0, error=PAPER_ERROR0)
    >>> [round(first_order_error(w, tag=t) * C, 1) for t in TAGS]       # m
    [-116.4, -35.2, 257.1]
    """
    eps = _check_window(window).error(correction, tag)
    mean = float(np.sum((eps[1:] + eps[:-1]) / 2.0 * np.diff(window.u)) / window.duration)
    return mean - float(_spline(window.u, eps)(tag_offset(tag, window.duration)))


class FoldError(NamedTuple):
    """Error of the noise-free fold (:func:`expected_error`).

    Attributes
    ----------
    bias : float or None
        Measured minus true delay at the tag, s; ``None`` when the pulse is lost
        (``coherence < 0.5``: no TOA).
    coherence : float
        ``|mean_u exp(2 pi i f eps(u))|``: the fundamental harmonic of the folded pulse kept,
        1 for a perfect time transfer, near 0 for a pulse smeared over many periods.
    sigma : float or None
        Cramer-Rao bound of the TOA from the smeared fold, s (the binned bound of
        :func:`xnavlab.mars.timing.timing_bound.toa_crlb` when nothing smears).
    """

    bias: float | None
    coherence: float
    sigma: float | None


def expected_error(window, correction="apriori", tag="mid", area_m2=1.0,
                   background_ph_cm2_s=0.005, nbins=None):
    """Error of the noise-free fold of a window: bias, coherence and bound (:class:`FoldError`).

    A photon arriving at ``u`` is folded ``eps(u)`` early (:meth:`FoldWindow.error`), so the
    expected fold is the template convolved with the distribution of ``-f eps(u)`` over the
    window: its harmonics are the template's times ``mean_u exp(2 pi i k f eps(u))`` (the mean
    taken on a grid fine enough that ``f eps`` moves a fiftieth of a pulse width a step). The
    maximum-likelihood offset of that fold (:func:`xnavlab.mars.timing.timing_bound.ml_phase_shift`,
    the unsmeared template, as a processor would use) gives the bias, ``Delta_t(r_hat(t_tag))
    - tau_hat - Delta_t(r(t_tag))``; its Fisher information the bound.

    Parameters
    ----------
    window : FoldWindow
    correction : {"apriori", "mars", "constant"}
    tag : {"start", "mid", "end"} or float
    area_m2, background_ph_cm2_s : float
        As :func:`xnavlab.mars.timing.timing_bound.toa_crlb`.
    nbins : int, optional
        Phase bins (default :func:`xnavlab.mars.timing.timing_bound.default_nbins`).

    Returns
    -------
    FoldError

    Examples
    --------
    >>> w = fold_window("B1937+21", dynamics.MARS_T0, dynamics.MARS_STATE0, error=PAPER_ERROR0)
    >>> e = expected_error(w, tag="end")
    >>> round(e.bias * C, 1), round(e.coherence, 4)       # m: the first-order 257.1 m
    (257.2, 1.0)
    >>> expected_error(w, "constant").bias is None          # the pulse is smeared away
    True
    """
    p = _check_window(window).pulsar
    nbins = timing_bound.default_nbins(p) if nbins is None else check_int("nbins", nbins, 8, 2**20)
    ls, lb = pulsars.photon_rates(p, area_m2, background_ph_cm2_s)
    T, f = window.duration, p.frequency
    eps_fn = _spline(window.u, window.error(correction, tag))
    rate = float(np.max(np.abs(eps_fn(window.u, 1))))  # |d eps / du|
    du = min(1.0, 0.02 * p.duty_cycle / max(f * rate, 1e-30))
    m = max(16, math.ceil(T / du))
    sig = p.duty_cycle / (2.0 * math.sqrt(2.0 * math.log(2.0)))
    kmax = min(nbins // 2, math.ceil(1.0 / sig))  # beyond: template harmonics < 3e-9
    def harmonics(k):  # mean over u of exp(2 pi i k f eps(u)), in chunks of u
        out = np.zeros(k.size, dtype=complex)
        for lo in range(0, m, 20000):
            uu = -T / 2.0 + (np.arange(lo, min(m, lo + 20000)) + 0.5) * T / m
            out += np.exp(2j * np.pi * np.outer(f * eps_fn(uu), k)).sum(axis=0)
        return out / m

    coherence = float(abs(harmonics(np.array([1]))[0]))
    if coherence < 0.5:
        return FoldError(None, coherence, None)
    coh = harmonics(np.arange(kmax + 1))
    spec = np.zeros(nbins // 2 + 1, dtype=complex)
    spec[: kmax + 1] = np.fft.rfft(timing_bound.expected_fold(nbins, p.duty_cycle, 1.0, 0.0))[
        : kmax + 1] * coh
    mu = lb * T / nbins + ls * T * np.fft.irfft(spec, nbins)  # the smeared expected fold
    kk = np.arange(spec.size)
    dmu = ls * T * np.fft.irfft(spec * (-2j * np.pi * kk), nbins)  # d mu / d shift (cycles)
    sigma = 1.0 / (f * math.sqrt(float(np.sum(dmu**2 / mu))))  # 1 / sqrt(f^2 sum mu'^2 / mu)
    _fold_rates(p, T, area_m2, background_ph_cm2_s)  # a fold with a phase to measure
    tau = timing_bound.ml_phase_shift(mu, p.duty_cycle, ls * T, lb * T) * p.period
    u_tag = tag_offset(tag, T)
    bias = -float(eps_fn(u_tag)) - tau  # z - Delta_t(r(t_tag)) = -eps(t_tag) - tau_hat
    return FoldError(bias, coherence, sigma)


def _fold_rates(p, T, area_m2, background_ph_cm2_s):
    """The pulsed and unpulsed rates (:func:`~xnavlab.mars.timing.pulsars.photon_rates`), ph/s,
    with the photons a fold of ``T`` s expects of each refused below 1e-6 (the
    lower end of :func:`~xnavlab.mars.timing.timing_bound.ml_phase_shift`: no phase to
    estimate) under the caller's names, not as ``pulsed`` and ``unpulsed``."""
    ls, lb = pulsars.photon_rates(p, area_m2, background_ph_cm2_s)
    if not ls * T >= 1e-6:
        raise ValueError(f"area_m2 must collect at least 1e-6 pulsed photons of the window's pulsar "
                         f"{p.name} in its {T:g} s, got {ls * T:.3g} on {area_m2:g} m^2")
    if not lb * T >= 1e-6:
        raise ValueError(f"background_ph_cm2_s must give at least 1e-6 unpulsed photons in the "
                         f"window's {T:g} s, got {lb * T:.3g} (pulsar {p.name}, pulsed fraction "
                         f"{p.pulsed_fraction:g})")
    return ls, lb


def _ssb_offset(window, u):
    """``u + d(u)``: the SSB arrival time of a photon at ``u``, minus ``t_mid + d0``, s."""
    return u + _spline(window.u, window.true_delay())(u)


def simulate_window_photons(window, area_m2=1.0, background_ph_cm2_s=0.005, rng=None):
    """Photon arrival times at the spacecraft over a window, offsets from its mid-time, s.

    The pulsar's photons are a Poisson process in SSB time with the rate of
    :func:`xnavlab.mars.timing.pulsars.simulate_photons` (its phase model, ``phase0`` at SSB time
    ``t_mid + d0``); each is carried to the spacecraft on the *true* orbit by solving
    ``u + Delta_t(r(t_mid + u)) - d0 = s`` (fixed point: ``|d Delta_t / du| < 1e-4``), and those
    arriving within ``[-T/2, T/2)`` are kept. (The unpulsed photons are drawn in SSB time too:
    their rate at the spacecraft differs by ``d Delta_t / dt``, below 1e-4.)

    Parameters
    ----------
    window : FoldWindow
    area_m2, background_ph_cm2_s : float
        Effective area, m^2, in [1e-6, 1e3], and diffuse background, ph/cm^2/s, in [0, 10]:
        the window and its margins expect at most 5e7 photons
        (:func:`~xnavlab.mars.timing.pulsars.simulate_photons`' bound).
    rng : numpy.random.Generator or int, optional

    Returns
    -------
    ndarray, shape (n,)
        Sorted offsets from ``t_mid``, s.

    Examples
    --------
    >>> w = fold_window("B1821-24", dynamics.MARS_T0, dynamics.MARS_STATE0, duration=20.0)
    >>> u = simulate_window_photons(w, rng=0)
    >>> bool(900 < u.size < 1150), bool(u.min() >= -10.0 and u.max() < 10.0)
    (True, True)
    """
    p, T = _check_window(window).pulsar, window.duration
    d = window.true_delay()
    margin = float(np.max(np.abs(d))) + 1.0
    length = T + 2.0 * margin
    check_photons("area_m2", pulsars.photon_rates(p, area_m2, background_ph_cm2_s), length)  # by name
    shift = T / 2.0 + margin + window.phase0 * p.period  # phase zero at SSB offset phase0 P
    s = pulsars.simulate_photons(p, length, area_m2, background_ph_cm2_s, make_rng(rng),
                                 shift=shift) - (T / 2.0 + margin)
    spl = _spline(window.u, d)
    u = s.copy()
    for _ in range(4):  # u = s - d(u); the map's slope is below 1e-4, so 4 steps reach 1e-16 s
        u = s - spl(np.clip(u, window.u[0], window.u[-1]))
    return np.sort(u[(u >= -T / 2.0) & (u < T / 2.0)])


class FoldTOA(NamedTuple):
    """One processed fold (:func:`fold_toa`).

    Attributes
    ----------
    z : float
        Measured delay at the tag, minus ``d0``, s (``Delta_t(r_hat(t_tag)) - d0 - tau_hat``).
    t_tag : float
        The time tag, s TDB past J2000.
    offset : float
        The fold's pulse offset ``tau_hat``, s (late positive).
    error : float
        ``z`` minus the true delay at the tag, s, wrapped into a period.
    """

    z: float
    t_tag: float
    offset: float
    error: float


def fold_photons(window, u, correction="apriori", tag="mid", nbins=None):
    """Fold a window's photons after a processing's time transfer: counts per phase bin.

    Each photon is carried to the SSB with the processing delay of ``correction``
    (:meth:`FoldWindow.processing_delay`) and folded with the pulsar's phase model,
    exposure-corrected (:func:`xnavlab.mars.timing.pulsars.fold`); bin 0 starts at the phase the
    pulse has at SSB time ``t_mid + d0``, so a perfect time transfer puts the pulse at phase 0
    (the first bin, wrapping round to the last).

    Parameters
    ----------
    window : FoldWindow
    u : array_like, shape (n,)
        Photon arrival offsets from ``t_mid``, s, within ``[-T/2, T/2)``, at least 2.
    correction : {"apriori", "mars", "constant"}
    tag : {"start", "mid", "end"} or float
        The time tag (it matters to ``"mars"`` and ``"constant"`` only).
    nbins : int, optional
        Phase bins (default :func:`xnavlab.mars.timing.timing_bound.default_nbins`).

    Returns
    -------
    ndarray, shape (nbins,)
        Photons per bin (exposure-corrected).

    Examples
    --------
    >>> w = fold_window("B1821-24", dynamics.MARS_T0, dynamics.MARS_STATE0, error=PAPER_ERROR0)
    >>> u = simulate_window_photons(w, rng=1)
    >>> folds = [fold_photons(w, u, c, nbins=128) for c in CORRECTIONS]
    >>> [bool(f.max() > 2 * np.median(f)) for f in folds]      # the pulse stands out, or not
    [True, False, False]
    """
    p, T = _check_window(window).pulsar, window.duration
    if T < p.period:  # part of a cycle leaves phase bins unswept (pulsars.fold divides by their exposure)
        raise ValueError(f"window must last a whole pulse cycle of {p.name} ({p.period:.6g} s) to fold, "
                         f"got {T:g} s")
    u = check_finite_array("u", u)
    if u.ndim != 1:
        raise ValueError(f"u must be a 1-D array of photon offsets, shape (n,), got shape {u.shape}")
    if u.size < 2:  # one photon's fold has one filled bin: no pulse to place
        raise ValueError(f"u must hold at least 2 photon offsets, got {u.size}")
    if u.min() < -T / 2.0 or u.max() >= T / 2.0:
        bad = float(u.min()) if u.min() < -T / 2.0 else float(u.max())
        raise ValueError(f"u must hold photon offsets within [-{T / 2:g}, {T / 2:g}) s, got {bad:g}")
    nbins = timing_bound.default_nbins(p) if nbins is None else check_int("nbins", nbins, 8, 2**20)
    proc = _spline(window.u, window.processing_delay(correction, tag))
    x = u + proc(u) - window.phase0 * p.period  # SSB offset from the phase reference, s
    ends = np.array([-T / 2.0, T / 2.0])
    span = ends + proc(ends) - window.phase0 * p.period
    return pulsars.fold(x, p, nbins, span=(min(span[0], x.min()), max(span[1], x.max())))


def fold_toa(window, u, correction="apriori", tag="mid", area_m2=1.0,
             background_ph_cm2_s=0.005, nbins=None, search=0.5):
    """Process a window's photons into a delay measurement at a time tag (:class:`FoldTOA`).

    Each photon is carried to the SSB with the processing delay of ``correction``
    (:meth:`FoldWindow.processing_delay`: along the a-priori orbit by default), folded with the
    pulsar's phase model (exposure-corrected, :func:`xnavlab.mars.timing.pulsars.fold`), and the pulse
    offset measured by maximum likelihood (:func:`xnavlab.mars.timing.timing_bound.ml_phase_shift`,
    rates known); the measurement is ``Delta_t(r_hat(t_tag)) - tau_hat``.

    Parameters
    ----------
    window : FoldWindow
    u : array_like, shape (n,)
        Photon arrival offsets from ``t_mid``, s, within ``[-T/2, T/2)``, at least 2
        (:func:`simulate_window_photons`).
    correction : {"apriori", "mars", "constant"}
    tag : {"start", "mid", "end"} or float
        The time tag (mid-time: the model of the module notes).
    area_m2, background_ph_cm2_s : float
        The rates the estimator assumes.
    nbins : int, optional
        Phase bins (default :func:`xnavlab.mars.timing.timing_bound.default_nbins`).
    search : float
        Half-width of the offset search, cycles (:func:`~xnavlab.mars.timing.timing_bound.ml_phase_shift`).

    Returns
    -------
    FoldTOA

    Examples
    --------
    >>> w = fold_window("B1821-24", dynamics.MARS_T0, dynamics.MARS_STATE0, error=PAPER_ERROR0)
    >>> r = fold_toa(w, simulate_window_photons(w, rng=1))
    >>> bool(abs(r.error) < 4 * timing_bound.toa_crlb("B1821-24"))
    True
    """
    p, T = _check_window(window).pulsar, window.duration
    counts = fold_photons(window, u, correction, tag, nbins)
    proc = _spline(window.u, window.processing_delay(correction, tag))
    ls, lb = _fold_rates(p, T, area_m2, background_ph_cm2_s)
    tau = timing_bound.ml_phase_shift(counts, p.duty_cycle, ls * T, lb * T, search) * p.period
    u_tag = tag_offset(tag, T)
    z = float(proc(u_tag)) - tau
    err = z - float(_spline(window.u, window.true_delay())(u_tag))
    err = (err / p.period + 0.5) % 1.0 * p.period - 0.5 * p.period  # within a period
    return FoldTOA(z, window.t_mid + u_tag, tau, err)


#: Keys of :func:`window_survey`'s rows and the column titles of :func:`survey_html`.
SURVEY_COLUMNS = {
    "pulsar": "pulsar",
    "crlb_m": "Cramer-Rao bound (m)",
    "delay_change_ms": "delay change in the window (ms)",
    "orbit_change_ms": "of it, the orbit's (ms)",
    "apriori_mid_m": "a-priori, mid tag (m)",
    "apriori_end_m": "a-priori, end tag (m)",
    "apriori_sigma_ratio": "a-priori: bound / unsmeared",
    "mars_coherence": "Mars only: coherence",
    "mars_mid_m": "Mars only, mid tag (m)",
    "constant_coherence": "one delay: coherence",
}


def window_survey(pulsar_names=pulsars.PAPER_PULSARS, error=PAPER_ERROR0, n_windows=17,
                  spacing=500.0, duration=500.0, t0=dynamics.MARS_T0,
                  state0=dynamics.MARS_STATE0, area_m2=1.0, background_ph_cm2_s=0.005,
                  cache=False):
    """The fold's errors over the paper's orbit: the largest of each, per pulsar (noise-free).

    Windows start every ``spacing`` s from ``t0`` (default: 17 windows, one orbit of 8,252 s);
    the truth at each start comes from :func:`xnavlab.mars.models.dynamics.truth` and the a-priori
    is the truth plus ``error`` there (:func:`fold_window`). For each pulsar, the largest over
    the windows of: the delay change within the window and the orbit's part of it, ms; the
    bias of the a-priori-corrected fold with the mid-time and the end tags, m
    (:func:`expected_error`); the ratio of that fold's bound to the unsmeared one; and the
    coherence of the cheaper processings (the smallest) with the bias of the ``"mars"`` one
    at the mid tag (``None`` where a pulse is lost in some window).

    Measured over one orbit (17 windows, 500 s, 1 m^2; B0531+21, B1937+21, B1957+20,
    B1821-24): with the paper's initial error (5 km, 1 m/s per axis) the mid tag's error is at
    most 70, 57, 66, 62 m (bounds 99, 454, 2637, 381 m) and the end tag's 888, 418, 516, 763 m;
    with the settled error (the paper's fused 28.8 m, 0.021 m/s) 0.26, 0.22, 0.25, 0.23 m and
    6.3, 1.4, 1.9, 5.5 m. Holding the spacecraft still loses the three millisecond pulsars
    (coherence 0.01-0.07) and biases the Crab by up to 17.9 km; one delay for the window
    loses all four (coherence below 0.01). So the instantaneous model ``h(x(t_tag))`` with
    the tag at mid-window is adequate for the book's runs: its error stays below 0.3 % of the
    ranging noise once the filter has settled and below 0.71 of the Crab's bound at the start.

    Parameters
    ----------
    pulsar_names : sequence of str or Pulsar
        Catalogue names, ``.par`` paths or Pulsars
        (:func:`~xnavlab.mars.timing.pulsars.check_names`).
    error : array_like, shape (6,)
        A-priori minus true state at each window's start, m and m/s (:data:`PAPER_ERROR0`,
        :data:`SETTLED_ERROR`).
    n_windows : int
        1 to 10^4, the windows within DE421 and within
        :data:`~xnavlab.mars.models.dynamics.MAX_SPAN_DAYS` of ``t0``.
    spacing, duration : float
        Between window starts, in [1, 86400], and the window's length, in [1, 86400] (as
        :func:`fold_window`'s), s.
    t0 : float
        First window's start, s TDB past J2000 (the truth's epoch); every window within DE421.
    state0 : array_like, shape (6,)
        True state at ``t0`` (:func:`xnavlab.mars.models.dynamics.check_state0`; so is
        ``state0 + error``).
    area_m2, background_ph_cm2_s : float
        Effective area, m^2, in [1e-6, 1e3], and diffuse background, ph/cm^2/s, in [0, 10]
        (:func:`xnavlab.mars.timing.pulsars.photon_rates`).
    cache : bool
        Read the rows from the disk cache, or compute and store them there (keyed by the
        arguments, each pulsar by all its parameters, and the code,
        :func:`xnavlab.core.diskcache.entry_path`): the default survey takes about 10-15 s.

    Returns
    -------
    list of dict
        One row per pulsar, keys :data:`SURVEY_COLUMNS` (distances ``c`` times delays).

    Examples
    --------
    >>> rows = window_survey(["B0531+21"], n_windows=2)
    >>> round(rows[0]["apriori_mid_m"], 1), round(rows[0]["apriori_end_m"], 1)
    (46.6, 716.0)
    """
    cache = check_bool("cache", cache)
    n_windows = check_int("n_windows", n_windows, 1, 10**4)
    spacing = check_real("spacing", spacing, 1.0, 86400.0)
    err = check_vector("error", error, 6)
    # Each argument under its own name before the windows pass it on (as t_start, t_obs, ...)
    duration = check_real("duration", duration, 1.0, 86400.0)
    t0 = check_epoch("t0", t0)
    lo, hi = ephemeris.coverage("de421")
    if not lo <= t0 <= hi - duration:
        raise ValueError(f"t0 must lie in {dates.epoch_range(lo, hi - duration)} (its window in DE421), "
                         f"got {dates.epoch_text(t0)}")
    if t0 + spacing * (n_windows - 1) + duration > hi:
        raise ValueError(f"n_windows must keep the last window in DE421 (t0 + spacing (n_windows - 1) + "
                         f"duration <= {dates.epoch_text(hi)} s TDB past J2000), got {n_windows}")
    span = spacing * (n_windows - 1) + duration  # the truth is propagated over every window
    if span > dynamics.MAX_SPAN_DAYS * DAY:
        raise ValueError(f"n_windows must keep the windows within {dynamics.MAX_SPAN_DAYS:g} days of t0 "
                         f"(spacing (n_windows - 1) + duration, the longest propagation), got "
                         f"{n_windows} ({span / DAY:.6g} days)")
    state0 = dynamics.check_state0(state0)
    dynamics.check_state0(state0 + err, "state0 + error")  # the first window's a-priori
    area_m2 = check_real("area_m2", area_m2, 1e-6, 1e3)
    background_ph_cm2_s = check_real("background_ph_cm2_s", background_ph_cm2_s, 0.0, 10.0)
    pulsar_names = pulsars.check_names(pulsar_names, "pulsar_names")
    if cache:
        ps = tuple(pulsars.get(n) for n in pulsar_names)  # keyed and computed as given, not by name
        x0 = state0
        parts = (tuple(map(repr, ps)), n_windows, spacing, duration, t0, area_m2, background_ph_cm2_s)
        path = entry_path("fold-survey", parts, (err, x0), (__name__,), suffix=".json")
        try:
            return json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):  # missing or unreadable: computed and stored
            rows = window_survey(ps, err, n_windows, spacing, duration, t0, x0, area_m2,
                                 background_ph_cm2_s)
            store(path, lambda f: f.write(json.dumps(rows).encode()))
            return rows
    starts = t0 + spacing * np.arange(n_windows)
    states = dynamics.truth(starts, state0, t0)
    rows = []
    for name in pulsar_names:
        p = pulsars.get(name)
        acc = {k: [] for k in ("dc", "oc", "mid", "end", "ratio", "mcoh", "mmid", "ccoh")}
        bound = timing_bound.toa_crlb(p, area_m2, duration, background_ph_cm2_s,
                                      nbins=timing_bound.default_nbins(p))
        for t_start, x0 in zip(starts, states, strict=True):
            w = fold_window(p, t_start, x0, err, duration)
            args = (area_m2, background_ph_cm2_s)
            mid = expected_error(w, "apriori", "mid", *args)
            end = expected_error(w, "apriori", "end", *args)
            mars = expected_error(w, "mars", "mid", *args)
            const = expected_error(w, "constant", "mid", *args)
            acc["dc"].append(abs(w.delay_change()))
            acc["oc"].append(abs(w.orbit_delay_change()))
            acc["mid"].append(abs(mid.bias))
            acc["end"].append(abs(end.bias))
            acc["ratio"].append(mid.sigma / bound)
            acc["mcoh"].append(mars.coherence)
            acc["mmid"].append(None if mars.bias is None else abs(mars.bias))
            acc["ccoh"].append(const.coherence)
        rows.append({
            "pulsar": p.name, "crlb_m": C * timing_bound.toa_crlb(p, area_m2, duration,
                                                                  background_ph_cm2_s),
            "delay_change_ms": 1e3 * max(acc["dc"]), "orbit_change_ms": 1e3 * max(acc["oc"]),
            "apriori_mid_m": C * max(acc["mid"]), "apriori_end_m": C * max(acc["end"]),
            "apriori_sigma_ratio": max(acc["ratio"]), "mars_coherence": min(acc["mcoh"]),
            "mars_mid_m": None if None in acc["mmid"] else C * max(acc["mmid"]),
            "constant_coherence": min(acc["ccoh"]),
        })
    return rows


def survey_html(rows, digits=4):
    """:func:`window_survey`'s rows as the book's HTML table (every cell escaped).

    ``rows`` must be a list of dicts holding every key of :data:`SURVEY_COLUMNS`; a string, a
    dict or a row without a key is refused in one ``ValueError`` naming it.

    Examples
    --------
    >>> "coherence" in survey_html(window_survey(["B0531+21"], n_windows=1))
    True
    """
    from xnavlab.core.plotting import html_table

    if not isinstance(rows, list | tuple):  # a string, a dict, a number or a 0-d array
        raise ValueError(f"rows must be a list of window_survey rows (dicts), got {shown(rows)}")
    if not rows:
        raise ValueError("rows must hold at least one window_survey row, got an empty list")
    for i, r in enumerate(rows):
        missing = [k for k in SURVEY_COLUMNS if not isinstance(r, dict) or k not in r]
        if missing:
            raise ValueError(f"rows[{i}] must be a window_survey row (a dict with "
                             f"{', '.join(SURVEY_COLUMNS)}), got {shown(r)}")
    return html_table(list(SURVEY_COLUMNS.values()),
                      [[r[k] for k in SURVEY_COLUMNS] for r in rows], digits=digits)


def plot_survey(surveys, bound=True):
    """The instantaneous model's error per pulsar, mid-window and end tags: a Figure.

    Grouped bars (log scale), one group per pulsar: for each survey of :func:`window_survey`
    (labelled by the a-priori error it assumed) the largest error of the a-priori-corrected
    fold with the mid-window tag and with the end tag; a black tick marks each pulsar's
    Cramer-Rao bound (the noise of one TOA) when ``bound``.

    Parameters
    ----------
    surveys : dict of str to list of dict
        ``{label: window_survey(...) rows}``, the same pulsars in each, in order.
    bound : bool
        Mark each pulsar's bound.

    Returns
    -------
    matplotlib.figure.Figure
        Not registered with pyplot.

    Examples
    --------
    >>> rows = [{"pulsar": "B0531+21", "crlb_m": 98.7, "apriori_mid_m": 70.3,
    ...          "apriori_end_m": 888.1}]
    >>> fig = plot_survey({"the paper's initial error": rows})
    >>> fig.axes[0].get_ylabel()
    'largest error over the orbit (m)'
    """
    from matplotlib.figure import Figure

    if not isinstance(surveys, dict) or not surveys:  # a list was a TypeError
        raise ValueError(f"surveys must be a dict of label -> survey rows holding at least one "
                         f"survey, got {shown(surveys)}")
    bound = check_bool("bound", bound)
    labels = list(surveys)
    names = [r["pulsar"] for r in surveys[labels[0]]]
    if any([r["pulsar"] for r in surveys[k]] != names for k in labels):
        raise ValueError("surveys must hold the same pulsars, in the same order")
    fig = Figure(figsize=(8.0, 3.6), layout="constrained")
    ax = fig.subplots()
    x = np.arange(len(names))
    width = 0.8 / (2 * len(labels))
    for k, label in enumerate(labels):
        for j, (key, tag, hatch) in enumerate((("apriori_mid_m", "mid-window tag", ""),
                                               ("apriori_end_m", "end tag", "//"))):
            pos = x - 0.4 + width * (2 * k + j + 0.5)
            ax.bar(pos, [r[key] for r in surveys[label]], width, color=f"C{k}", hatch=hatch,
                   alpha=0.85 if j == 0 else 0.45, edgecolor=f"C{k}",
                   label=f"{label}, {tag}")
    if bound:
        ax.plot(x, [r["crlb_m"] for r in surveys[labels[0]]], "k_", ms=40, mew=2,
                label="Cramer-Rao bound of one TOA")
    ax.set_xticks(x, names)
    ax.set(yscale="log", ylabel="largest error over the orbit (m)")
    lo, hi = ax.get_ylim()
    ax.set_ylim(lo, hi * 300.0)  # room for the legend above the bars
    ax.legend(fontsize=8, loc="upper center", ncols=2)
    return fig
