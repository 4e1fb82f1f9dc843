"""The combined detector: wavelet singularities + per-sample chi-square + CUSUM on innovations.

Each detector of chapter 9 wins a different class of faults: the wavelet (paper, chapter 7)
sees *changes* (steps, outliers, a stuck or noisier output) and calibrates itself from the
data; the innovation chi-square test sees *levels*, but only one sample at a time, and trusts
the noise model. Neither sees a slow drift early. The combined detector runs, per subsystem,

``wavelet``
    :func:`~xnavlab.core.detection.batch.wavelet_detect` (raw series or innovations);
``chi2``
    the per-sample test ``q_n = sum_c (y_c[n] / s_c)^2 > chi2.isf(alpha, m)`` on the whitened
    innovations ``y = L^-1 nu`` (``L L^T = S``), the chi-square test of chapter 9;
``cusum``
    two one-sided CUSUMs per component on the signed innovation (a mean shift or a drift of
    either sign), ``S+ = max(0, S+ + y_c/s_c - k)``, ``S- = max(0, S- - y_c/s_c - k)``
    (Page 1954), alarm when ``S > h``;
``variance``
    one CUSUM per component on the squared innovation, ``V = max(0, V + (y_c/s_c)^2 - k_v)``
    (a noise increase), ``k_v = 2 ln(lambda) / (1 - lambda^-2)`` the log-likelihood-ratio
    reference for a noise standard deviation ``lambda`` times the model's (2 by default).

A sample alarms when any part does; a subsystem whose detector alarms is isolated.

Sequential test: CUSUM, chosen by measurement
    At the same false-alarm rate, the CUSUM on the signed innovation finds drifts and small
    steps sooner than a windowed chi-square of the NIS (``benchmarks/bench_detectors.py``
    prints both; for a drift reaching 5 sigma in 6000 s at 3 s the CUSUM alarms after about
    570 s (median), the windowed chi-square of 100 samples after about 1070 s; at 500 s a
    sample, against a window of 4, both after 3000 s, a tie). Two reasons: the CUSUM uses the
    sign (a bias adds ``delta`` to the statistic per sample, a chi-square window only
    ``delta^2``), and it has no window length to tune: it is Lorden-optimal for a shift of
    ``2 k`` and accumulates for as long as the evidence grows. A GLR over drift onsets and
    slopes (:func:`drift_glr`) is the drift-matched test; at 500 s a sample the benchmark
    measures it against the CUSUM at the same false-alarm rate on the 5-sigma/6000-s drift: it
    finds about as many within 4000 s, a sample earlier in the median, at a cost growing with
    its window; the CUSUM, one addition per sample, is kept.
False-alarm budget
    The design rate ``F`` (false alarms per subsystem per day, default 1) is split into shares
    (:data:`SHARES`: wavelet 0.1, chi-square 0.2, CUSUM 0.5, variance 0.2). With ``N`` samples
    a day and ``m`` components: ``alpha = 0.2 F / N``; each of the ``2 m`` mean CUSUMs gets an
    in-control average run length ``ARL = 2 m N / (0.5 F)`` samples, each variance CUSUM
    ``m N / (0.2 F)``; ``h`` follows from the ARL by the Brook-Evans Markov chain
    (:func:`cusum_arl`); the wavelet's per-sample probability is ``0.1 F / N``. The union bound
    makes ``F`` an upper bound; it is nearly tight, since the parts rarely fire on one noise
    sample together and the wavelet's share is small (its alarm samples come in clusters, so it
    realises less than its share).
Robustness to a mis-modelled noise level
    Each component is divided by an adaptive scale ``s_c``: the MAD of the last
    ``scale_samples`` innovations fed while healthy, ``median|y_c| / 0.6745``, shrunk toward the
    model's 1 with the weight of ``prior_samples`` samples,
    ``s_c^2 = (n0 + n MAD^2) / (n0 + n)``. It is recomputed after 100, 200, 400, ... samples
    fed and then every ``scale_every`` (a fixed grid of samples fed, so that streaming and batch
    give the same decisions). A noise
    30 % above the model is learnt within hours at 3 s (the MAD ignores the few faulty samples
    of a fault not yet detected) and the false-alarm rate stays near design, as the wavelet's
    (trained by MAD) does.
"""

from __future__ import annotations

import functools
import inspect
import math

import numpy as np

from xnavlab.core.detection._cusum_scan import scan_segment
from xnavlab.core.detection._tracked import TrackedDetector
from xnavlab.core.detection.batch import series_lengths, wavelet_detect
from xnavlab.core.detection.limits import MAX_SAMPLES
from xnavlab.core.detection.online import (
    MAD_SCALE,
    Detection,
    EventTracker,
    events_from_alarms,
)
from xnavlab.core.distributions import chi2_cdf, chi2_isf
from xnavlab.core.validate import (
    check_bool,
    check_choice,
    check_evenly_spaced,
    check_finite_array,
    check_increasing,
    check_int,
    check_keywords,
    check_real,
    check_seed,
    check_shape,
    shown,
)

__all__ = [
    "SHARES",
    "PARTS",
    "EVEN_RTOL",
    "variance_reference",
    "ARL_MAX",
    "H_MIN",
    "cusum_arl",
    "cusum_threshold",
    "CombinedDesign",
    "InnovationMonitor",
    "combined_detect",
    "drift_glr",
    "plot_combined_parts",
]

#: Shares of the false-alarm budget: wavelet, per-sample chi-square, mean CUSUM, variance CUSUM.
SHARES = {"wavelet": 0.1, "chi2": 0.2, "cusum": 0.5, "variance": 0.2}

#: The parts of the combined detector, in the order of :data:`SHARES`.
PARTS = tuple(SHARES)

#: How far a step of :func:`combined_detect`'s ``t`` may be from the median step (relative),
#: and a given design's ``samples_per_day`` from the sampling of ``t``: 1 %, far beyond the
#: rounding of times such as ``t0 + 3.0 * np.arange(n)``, far below a missing sample (100 %).
EVEN_RTOL = 0.01


def variance_reference(lam=2.0):
    """Reference ``k_v`` of a CUSUM on ``y^2`` for a noise ``lam`` times the model's.

    The log-likelihood ratio of ``N(0, lam^2)`` against ``N(0, 1)`` per sample is
    ``(y^2 / 2)(1 - lam^-2) - ln(lam)``, proportional to ``y^2 - k_v`` with
    ``k_v = 2 ln(lam) / (1 - lam^-2)``.

    Examples
    --------
    >>> round(variance_reference(2.0), 3)
    1.848
    """
    lam = check_real("lam", lam, 1.0, 100.0, lo_open=True)
    return 2.0 * math.log(lam) / (1.0 - lam**-2)


def _chi2_1_cdf(x):
    from scipy import special

    return special.erf(np.sqrt(np.maximum(x, 0.0) / 2.0))   # chi2(1): P(y^2 <= x) = erf(sqrt(x/2))


#: The longest run length :func:`cusum_arl` answers: ``I - R`` has a condition number of about
#: the ARL, so at 1e13 samples its solve keeps about three digits; at 1e16 it returned negative
#: run lengths (h = 100, k = 0.25). :func:`cusum_threshold` designs up to 1e12.
ARL_MAX = 1e13
#: The smallest threshold :func:`cusum_threshold` brackets down to (noise sigmas).
H_MIN = 1e-6


def _check_k_alarms(k, dof):
    """The run length as h -> 0, refusing a k whose CUSUM passes ARL_MAX even there."""
    shortest = _arl(H_MIN, float(k), dof, 300)
    if not 0.0 < shortest <= ARL_MAX:
        raise ValueError(f"k = {k:g} is too high: this CUSUM runs more than {ARL_MAX:g} samples "
                         f"on noise even as h -> 0 (lower k)")
    return shortest


@functools.lru_cache(maxsize=256)
def _arl(h, k, dof, cells):
    # Brook & Evans (1972): the CUSUM as a Markov chain on [0, h] (cell midpoints plus the atom
    # at 0); ARL from the start state = first entry of (I - R)^-1 1.
    w = h / cells
    mids = np.r_[0.0, (np.arange(cells) + 0.5) * w]                  # state 0: S = 0
    upper = (np.arange(cells) + 1.0) * w                             # upper cell edges
    from scipy import special  # imported here: only an ARL needs it

    if dof == 0:
        cdf = special.ndtr                                           # increments y - k
    elif dof == 1:
        cdf = _chi2_1_cdf                                            # increments y^2 - k
    else:
        cdf = functools.partial(chi2_cdf, dof=dof)
    # P(S' = 0 | s) = P(X <= k - s); P(S' in cell j | s) = P(k - s + lo_j < X <= k - s + hi_j)
    F = cdf(k - mids[:, None] + np.r_[0.0, upper][None, :])          # (cells + 1, cells + 1)
    R = np.empty((cells + 1, cells + 1))
    R[:, 0] = F[:, 0]
    R[:, 1:] = np.diff(F, axis=1)
    try:
        arl = np.linalg.solve(np.eye(cells + 1) - R, np.ones(cells + 1))
    except np.linalg.LinAlgError:  # the chain never leaves [0, h]: no alarm on noise, ever
        return math.inf
    return float(arl[0])


def cusum_arl(h, k, dof=0, cells=300):
    """In-control average run length (samples) of a one-sided CUSUM, by the Brook-Evans chain.

    ``S_n = max(0, S_{n-1} + X_n - k)``, alarm when ``S_n > h``, with ``X = y`` (``dof = 0``,
    ``y ~ N(0, 1)``: the mean CUSUM) or ``X = y^2 ~ chi2(dof)`` (the variance CUSUM, ``dof = 1``).

    Parameters
    ----------
    h : float
        Threshold, > 0.
    k : float
        Reference value (> 0 for the mean CUSUM, > dof for the variance CUSUM).
    dof : int
        0 for Gaussian increments, else the chi-square degrees of freedom.
    cells : int
        Discretisation of ``[0, h]`` (300 gives 3 significant digits).

    Examples
    --------
    >>> round(cusum_arl(4.0, 0.5))   # Siegmund's approximation gives 336
    335
    """
    h = check_real("h", h, 0.0, 1e4, lo_open=True)
    k = check_real("k", k, 0.0, 100.0, lo_open=True)
    dof = check_int("dof", dof, 0, 100)
    cells = check_int("cells", cells, 20, 5000)
    if dof and k <= dof:
        raise ValueError(f"k must exceed dof = {dof} for a variance CUSUM, got {k}")
    arl = _arl(float(h), float(k), dof, cells)
    if not 0.0 < arl <= ARL_MAX:
        _check_k_alarms(k, dof)
        raise ValueError(f"h = {h:g} is too high for k = {k:g}: the run length passes "
                         f"{ARL_MAX:g} samples, beyond what the chain resolves (lower h or k)")
    return arl


def cusum_threshold(arl, k, dof=0):
    """Threshold ``h`` whose in-control ARL (:func:`cusum_arl`) is ``arl`` samples.

    ``arl`` in [2, 1e12]; the reference value ``k`` in [0.01, 100] (noise sigmas: below 0.01
    the longest ARLs need an ``h`` beyond :func:`cusum_arl`'s range).

    Examples
    --------
    >>> h = cusum_threshold(1e5, 0.25)
    >>> round(h, 2), round(cusum_arl(h, 0.25) / 1e5, 3)
    (17.71, 1.0)
    """
    arl = check_real("arl", arl, 2.0, 1e12)
    # from 0.01 (a drift to find of 0.02 sigma): a smaller k needs an h beyond cusum_arl's 1e4
    # for the longest ARLs (k = 0.001: h = 10880 at 1e12), and k = 5e-324 made h inf
    k = check_real("k", k, 0.01, 100.0)
    dof = check_int("dof", dof, 0, 100)
    if dof and k <= dof:
        raise ValueError(f"k must exceed dof = {dof} for a variance CUSUM, got {k}")

    def f(h):
        run = _arl(h, k, dof, 300)
        # past ARL_MAX the chain loses its digits: the ARL grows with h, so that h is above
        return math.log(run) - math.log(arl) if 0.0 < run <= ARL_MAX else 1.0

    # log ARL is nearly linear in h for large h (ARL ~ exp(2 k h), Siegmund 1985): bracket
    # from Siegmund's approximation and solve by Brent's method (a few chain solutions)
    kk = k - dof if dof else k
    h0 = max(0.5, math.log(max(2.0 * kk * kk * arl, 2.0)) / (2.0 * kk) - 1.166) if dof == 0 \
        else max(0.5, math.log(arl) / 0.5)
    lo, hi = 0.5 * h0, 1.5 * h0
    while f(lo) > 0:
        lo *= 0.5
        if lo < H_MIN:  # even h -> 0 runs longer than asked: this k alarms on noise no sooner
            shortest = _check_k_alarms(k, dof)
            raise ValueError(f"arl must be at least {shortest:.3g} samples for k = {k:g} (the "
                             f"run length of this CUSUM as h -> 0), got {arl:g}")
    while f(hi) < 0:
        hi *= 1.5
    from scipy import optimize  # imported here: only a threshold design needs it

    return float(optimize.brentq(f, lo, hi, xtol=1e-4))


class CombinedDesign:
    """The combined detector's thresholds for one subsystem, from its false-alarm budget.

    Parameters
    ----------
    samples_per_day : float
        Measurements of the subsystem per day (28800 at 3 s, 172.8 at 500 s).
    m : int
        Components of the whitened innovation.
    rate_per_day : float
        Design false alarms of the subsystem per day ``F`` (all parts together), in (0, 100].
    shares : dict, optional
        Share of each part (:data:`SHARES`); they must sum to 1.
    k_mean : float
        Reference of the mean CUSUMs (sigma), half the shift it is tuned for; default 0.25.
    lam_var : float
        Noise ratio the variance CUSUM is tuned for (default 2).

    Attributes
    ----------
    alpha : float
        Per-sample false-alarm probability of the chi-square part.
    chi2_threshold : float
        ``chi2.isf(alpha, m)``.
    h_mean, h_var : float
        CUSUM thresholds.
    pfa_wavelet : float
        Per-sample false-alarm probability of the wavelet part.

    Examples
    --------
    >>> d = CombinedDesign(28800.0, 3)
    >>> f"{d.alpha:.2e}", round(d.h_mean, 1), round(d.h_var, 1)
    ('6.94e-06', 20.2, 27.7)
    >>> {k: round(v, 2) for k, v in d.part_rates().items()}
    {'wavelet': 0.1, 'chi2': 0.2, 'cusum': 0.5, 'variance': 0.2}
    """

    def __init__(self, samples_per_day, m, rate_per_day=1.0, shares=None, k_mean=0.25,
                 lam_var=2.0):
        self.samples_per_day = check_real("samples_per_day", samples_per_day, 1.0, 1e8)
        self.m = check_int("m", m, 1, 100)
        self.rate_per_day = check_real("rate_per_day", rate_per_day, 0.0, 100.0, lo_open=True)
        if shares is not None and not isinstance(shares, dict):
            raise ValueError(f"shares must be a dict of part -> share (parts {PARTS}), got "
                             f"{shown(shares)}")
        shares = dict(SHARES if shares is None else shares)
        for key, v in shares.items():
            check_choice("shares key", key, PARTS)
            check_real(f"shares[{key!r}]", v, 0.0, 1.0, lo_open=True)
        if abs(sum(shares.values()) - 1.0) > 1e-9 or set(shares) != set(PARTS):
            raise ValueError(f"shares must give each of {PARTS} a share, summing to 1, got {shares}")
        self.shares = shares
        self.k_mean = check_real("k_mean", k_mean, 0.01, 5.0)
        self.lam_var = check_real("lam_var", lam_var, 1.0, 100.0, lo_open=True)
        self.k_var = variance_reference(self.lam_var)
        n, F = self.samples_per_day, self.rate_per_day
        for part, parts in (("cusum", 2 * self.m), ("variance", self.m)):  # their ARL, as below
            rate = shares[part] * F
            arl = parts * n / rate if rate > 0.0 else math.inf
            if not arl <= 1e12:  # cusum_threshold's range, reported as the caller's settings
                raise ValueError(f"rate_per_day = {F!r} (shares[{part!r}] = {shares[part]:g}) is "
                                 f"too low for {n:g} samples a day and m = {self.m}: the {part} "
                                 f"test's average run length would be {arl:.3g} samples, above "
                                 f"1e12; raise rate_per_day")
        self.alpha = shares["chi2"] * F / n
        if self.alpha >= 0.5:
            raise ValueError(f"rate_per_day {F} is too high for {n} samples a day")
        self.chi2_threshold = chi2_isf(self.alpha, self.m)
        self.arl_mean = 2 * self.m * n / (shares["cusum"] * F)
        self.arl_var = self.m * n / (shares["variance"] * F)
        self.h_mean = cusum_threshold(self.arl_mean, self.k_mean)
        self.h_var = cusum_threshold(self.arl_var, self.k_var, dof=1)
        self.pfa_wavelet = shares["wavelet"] * F / n

    def part_rates(self):
        """Design false alarms per day of each part (their sum is ``rate_per_day``)."""
        n = self.samples_per_day
        return {"wavelet": self.pfa_wavelet * n, "chi2": self.alpha * n,
                "cusum": 2 * self.m * n / self.arl_mean, "variance": self.m * n / self.arl_var}

    def __repr__(self):
        return (f"CombinedDesign(samples_per_day={self.samples_per_day:g}, m={self.m}, "
                f"rate_per_day={self.rate_per_day:g})")


class InnovationMonitor(TrackedDetector):
    """Per-sample chi-square, mean CUSUMs and variance CUSUMs on whitened innovations, with an
    adaptive noise scale (the innovation parts of the combined detector, module notes).

    Feed it chunks of whitened innovations ``y`` (N, m) with :meth:`process`; it stops at the
    first alarm (the caller isolates the subsystem), resets its CUSUMs and returns the index.
    :meth:`update` is the one-sample form; both give the same decisions.

    Parameters
    ----------
    design : CombinedDesign
    adaptive : bool
        Divide by the adaptive scale (default) or trust the model (``s_c = 1``; then
        ``scale_samples``, ``scale_every`` and ``prior_samples`` are unused, and refused).
    scale_samples : int, optional
        Innovations in the MAD window (default one day of samples, at least 2000), in
        [10, MAX_SAMPLES].
    scale_every : int, optional
        Samples between scale updates (default half a day, at least 20), in [1, MAX_SAMPLES].
    prior_samples : int, optional
        Weight of the model's scale 1 (default 500 samples), in [0, MAX_SAMPLES].
    holdoff : int
        Alarm-free samples before an event closes (default 1).

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> mon = InnovationMonitor(CombinedDesign(28800.0, 2))
    >>> y = rng.normal(0.0, 1.0, (3000, 2))
    >>> y[2000:, 0] += 0.002 * np.arange(1000)          # a drift from sample 2000
    >>> i = mon.process(3.0 * np.arange(3000), y)
    >>> 2000 < i < 2400, mon.events[0].test if mon.events else mon.all_events()[0].test
    (True, 'cusum+ 0')
    """

    def __init__(self, design, *, adaptive=True, scale_samples=None, scale_every=None,
                 prior_samples=None, holdoff=1):
        if not isinstance(design, CombinedDesign):
            raise ValueError(f"design must be a CombinedDesign, got {type(design).__name__} "
                             f"{shown(design)}")
        self.design = design
        self.m = design.m
        n_day = design.samples_per_day
        self.adaptive = check_bool("adaptive", adaptive)
        if not self.adaptive:  # they set the adaptive scale only
            for key, value in (("scale_samples", scale_samples), ("scale_every", scale_every),
                               ("prior_samples", prior_samples)):
                if value is not None:
                    raise ValueError(f"{key} = {shown(value)} is unused with adaptive=False (it "
                                     f"sets the adaptive noise scale): leave it out")
        prior_samples = 500 if prior_samples is None else prior_samples
        self.scale_samples = check_int("scale_samples", max(2000, round(n_day))
                                       if scale_samples is None else scale_samples, 10, MAX_SAMPLES)
        self.scale_every = check_int("scale_every", max(20, round(n_day / 2))
                                     if scale_every is None else scale_every, 1, MAX_SAMPLES)
        self.prior_samples = check_int("prior_samples", prior_samples, 0, MAX_SAMPLES)
        self._tracker = EventTracker(holdoff)
        self.part_names = (["chi2"] + [f"cusum+ {c}" for c in range(self.m)]
                       + [f"cusum- {c}" for c in range(self.m)]
                       + [f"variance {c}" for c in range(self.m)])
        self.scale = np.ones(self.m)
        self._ring = np.zeros((self.scale_samples, self.m))
        self._n_ring = 0          # samples stored (up to scale_samples)
        self._pos = 0             # next ring row
        self._n_fed = 0           # healthy samples fed (the scale grid)
        self._next_update = self.next_scale_update()
        self._t_last = -math.inf  # the latest sample time fed (times must increase)
        self.reset_statistics()

    def reset_statistics(self):
        """Zero the CUSUMs (after an alarm or a re-admission); keeps the scale."""
        self.S = np.zeros(3 * self.m)      # [S+ (m), S- (m), V (m)]

    def readmitted(self):
        """The watched subsystem rejoins after an isolation: fresh CUSUMs, the open event closed
        (a later alarm is a new event)."""
        self.reset_statistics()
        self._tracker.close()

    def snapshot(self, max_rows=None):
        """A copy of the state, for :meth:`restore` (a rolled-back chunk).

        ``max_rows``: at most this many samples will be fed before the restore (only the ring
        rows they can overwrite are copied); default the whole ring."""
        W = self.scale_samples
        n = W if max_rows is None else min(W, check_int("max_rows", max_rows, 1))
        idx = (self._pos + np.arange(n)) % W
        tr = self._tracker
        return {"S": self.S.copy(), "scale": self.scale.copy(), "idx": idx,
                "rows": self._ring[idx].copy(), "n_ring": self._n_ring, "pos": self._pos,
                "n_fed": self._n_fed, "next": self._next_update, "tracker": tr.snapshot(),
                "t_last": self._t_last}

    def restore(self, state):
        """Return to a :meth:`snapshot` (at most its ``max_rows`` samples fed since)."""
        keys = {"S", "scale", "idx", "rows", "n_ring", "pos", "n_fed", "next", "tracker", "t_last"}
        if not isinstance(state, dict) or set(state) != keys:
            raise ValueError(f"state must be a snapshot() of this monitor, got {shown(state)}")
        if self._n_fed - state["n_fed"] > state["idx"].size:
            raise ValueError("restore: more samples were fed since the snapshot than its max_rows")
        self.S = state["S"].copy()
        self.scale = state["scale"].copy()
        self._ring[state["idx"]] = state["rows"]
        self._n_ring, self._pos, self._n_fed = state["n_ring"], state["pos"], state["n_fed"]
        self._next_update = state["next"]
        self._t_last = state["t_last"]
        self._tracker.restore(state["tracker"])

    @property
    def thresholds(self):
        """Alarm thresholds per statistic: chi-square, 2m mean CUSUMs, m variance CUSUMs, shape (1 + 3m,)."""
        d = self.design
        return np.r_[d.chi2_threshold, np.full(2 * self.m, d.h_mean), np.full(self.m, d.h_var)]

    def scale_from(self, healthy):
        """The adaptive scale (m,) from the healthy innovations ``healthy`` (n, m) of the MAD
        window: ``s^2 = (n0 + n MAD^2) / (n0 + n)``, ``MAD = median|y| / 0.6745``."""
        healthy = check_finite_array("healthy", healthy)
        if healthy.ndim != 2 or healthy.shape[1] != self.m:
            raise ValueError(f"healthy must have shape (n, {self.m}), got shape {healthy.shape}")
        n, n0 = healthy.shape[0], self.prior_samples
        if not self.adaptive or n == 0:
            return self.scale.copy()
        # one component at a time (a contiguous copy each: twice as fast as axis=0)
        mad = np.array([np.median(np.abs(col)) for col in healthy.T]) / MAD_SCALE
        return np.sqrt((n0 + n * mad**2) / (n0 + n))   # s^2 = (n0 + n MAD^2) / (n0 + n)

    def next_scale_update(self, n=None):
        """Samples fed at which the scale is next recomputed after the one at ``n`` (default:
        the first): 100, 200, 400, ... then every ``scale_every``."""
        if n is None:
            return min(100, self.scale_every)
        return min(2 * n, n + self.scale_every)

    def _update_scale(self):
        self.scale = self.scale_from(self._ring[:self._n_ring])

    def _store(self, y):
        n = y.shape[0]
        if n >= self.scale_samples:
            y = y[-self.scale_samples:]
            n = y.shape[0]
        idx = (self._pos + np.arange(n)) % self.scale_samples
        self._ring[idx] = y
        self._pos = (self._pos + n) % self.scale_samples
        self._n_ring = min(self.scale_samples, self._n_ring + n)

    def _segment(self, y):
        """Statistics of a segment at one scale, from the current CUSUM state.

        Returns the (N, 1 + 3m) statistics / thresholds ratio matrix and the final states per
        prefix (the caller cuts at the first alarm)."""
        m, d = self.m, self.design
        z = y / self.scale
        q = np.sum(z * z, axis=1)                                   # chapter 9 eq. (ch9-chi2)
        X = np.concatenate([z - d.k_mean, -z - d.k_mean, z * z - d.k_var], axis=1)
        D = np.cumsum(X, axis=0)
        # Lindley: S_n = max(S_0 + D_n, max_j (D_n - D_j)) = D_n - min(-S_0, min_{j<=n} D_j)
        S = D - np.minimum(-self.S, np.minimum.accumulate(D, axis=0))
        ratio = np.empty((y.shape[0], 1 + 3 * m))
        ratio[:, 0] = q / d.chi2_threshold
        ratio[:, 1:1 + 2 * m] = S[:, :2 * m] / d.h_mean
        ratio[:, 1 + 2 * m:] = S[:, 2 * m:] / d.h_var
        return ratio, S

    def _scan(self, y):
        """:func:`~xnavlab.core.detection._cusum_scan.scan_segment` of a segment up to its
        first alarm: (alarm index or -1, rmax up to it, its ratios, final S)."""
        d, n = self.design, y.shape[0]
        rmax, row, S_end = np.empty(n), np.empty((1, 1 + 3 * self.m)), np.empty(3 * self.m)
        a = scan_segment(np.ascontiguousarray(y), self.scale, self.S, d.k_mean, d.k_var,
                         d.chi2_threshold, d.h_mean, d.h_var, row, rmax, S_end, True)
        return a, rmax[:a + 1] if a >= 0 else rmax, row[0], S_end

    def _scan_rows(self, y, rows):
        """:func:`~xnavlab.core.detection._cusum_scan.scan_segment` of a whole segment, its
        ratios written into ``rows``: (alarm index or -1, rmax, the alarm's ratios or None,
        final S)."""
        d, n = self.design, y.shape[0]
        rmax, S_end = np.empty(n), np.empty(3 * self.m)
        a = scan_segment(np.ascontiguousarray(y), self.scale, self.S, d.k_mean, d.k_var,
                         d.chi2_threshold, d.h_mean, d.h_var, rows, rmax, S_end, False)
        return a, rmax, (rows[a] if a >= 0 else None), S_end

    def process(self, t, y, *, stop=True, record=None):
        """Feed whitened innovations ``y`` (N, m) at times ``t`` (N,) s, in order.

        ``t`` must increase, from the last sample fed before (an earlier time is refused; a
        :meth:`restore` returns to the snapshot's last time).

        Parameters
        ----------
        stop : bool
            Stop after the first alarm (default) and return its index; else run to the end
            (resetting the CUSUMs at every alarm) and return the first alarm's index.
        record : dict, optional
            If given, filled with ``ratio`` (N, 1 + 3m): every statistic over its threshold.

        Returns
        -------
        int
            Index of the first alarm in this chunk, or -1.
        """
        t = check_finite_array("t", t)
        y = check_finite_array("y", y)
        if t.ndim != 1:
            raise ValueError(f"t must be a 1-D array of sample times, got shape {t.shape}")
        m = self.m
        if y.shape != (t.size, m) and not (m == 1 and y.shape == (t.size,)):
            raise ValueError(f"y must have shape (n, {m}) with n = len(t) = {t.size} and m = "
                             f"the design's m, got shape {y.shape}")
        check_increasing("t", t)
        if t.size and not t[0] > self._t_last:
            raise ValueError(f"t must increase from one call to the next (sample times, s), got "
                             f"t[0] = {t[0]:g} after the last sample fed, at {self._t_last:g}")
        y = y.reshape(t.size, self.m)
        first = -1
        i = 0
        n = t.size
        ratios = np.zeros((n, 1 + 3 * self.m)) if record is not None else None
        seg = 2048            # segment length: short after an alarm (cheap restarts), doubling
        while i < n:
            j = min(n, i + max(1, self._next_update - self._n_fed), i + seg)
            if ratios is None:
                a_rel, rmax, hit_row, S_end = self._scan(y[i:j])
            else:  # every sample's ratios: the compiled form of _segment (the same bits)
                a_rel, rmax, hit_row, S_end = self._scan_rows(y[i:j], ratios[i:j])
            if a_rel >= 0:
                a = i + a_rel
                seg = slice(i, a)          # the healthy samples before the alarm
                self._feed_healthy(t[seg], y[seg], rmax[:a_rel])
                p = int(np.argmax(hit_row))
                self._tracker.update(float(t[a]), True, float(hit_row[p]), self.part_names[p])
                self.reset_statistics()
                if first < 0:
                    first = a
                if stop:
                    break
                i = a + 1
                seg = 32
                continue
            seg = min(2048, 2 * seg)
            self.S = S_end.copy()
            self._feed_healthy(t[i:j], y[i:j], rmax)
            i = j
        if n:  # the last sample fed (stop: the first alarm's; the rest was not fed)
            self._t_last = float(t[first if stop and first >= 0 else n - 1])
        if record is not None:
            record["ratio"] = ratios
        return first

    def _feed_healthy(self, t, y, rmax):
        if t.size == 0:
            return
        if self._tracker.faulty:
            for tt, r in zip(t, rmax, strict=True):
                self._tracker.update(float(tt), False, float(r))
                if not self._tracker.faulty:
                    break
        self._n_fed += t.size
        self._store(y)
        if self._n_fed >= self._next_update:
            self._update_scale()
            self._next_update = self.next_scale_update(self._next_update)

    def update(self, t, y):
        """Feed one whitened innovation ``y`` (m,); return whether it alarms."""
        y = check_shape("y", y, (self.m,), f"one whitened innovation a measurement, m = {self.m}")
        return self.process(np.array([check_real("t", t)]), y[None, :]) == 0


def drift_glr(y, window=16):
    """Generalised likelihood-ratio statistic of a linear drift that started in the last ``window`` samples.

    For unit white innovations ``y`` and a drift ``a j`` on the ``j``-th sample after an onset
    ``L`` samples back (slope ``a`` unknown), twice the log-likelihood ratio maximised over ``a``
    is ``(sum_j j y[n - L + j])^2 / sum_j j^2`` (``j = 1..L``); the statistic is its maximum over
    ``L = 1..window`` (Basseville and Nikiforov 1993, section 2.4). It is the test a drift-only
    detector would use; ``benchmarks/bench_detectors.py`` compares it with the CUSUM at the same
    false-alarm rate.

    Parameters
    ----------
    y : array_like, shape (N,)
        Whitened innovations of one component.
    window : int
        Longest drift considered, samples, in [1, 10000].

    Returns
    -------
    ndarray, shape (N,)
        The statistic at each sample (a window reaching before the first sample is skipped).

    Examples
    --------
    >>> y = np.r_[np.zeros(20), 0.5 * np.arange(1, 9)]
    >>> T = drift_glr(y, window=8)
    >>> bool(T[:20].max() == 0.0), round(float(T[-1]), 2)   # 0.5^2 * sum_j j^2 = 51
    (True, 51.0)
    """
    y = check_finite_array("y", y)
    if y.ndim != 1 or y.size == 0:
        raise ValueError(f"y must be a 1-D array of at least one sample, got shape {y.shape}")
    window = check_int("window", window, 1, 10_000)
    n = y.size
    T = np.zeros(n)
    for L in range(1, min(window, n) + 1):
        c = np.arange(1.0, L + 1.0)
        s = np.convolve(y, c[::-1])[:n]       # s_n = sum_j j y[n - L + j]
        s[:L - 1] = 0.0
        np.maximum(T, s * s / np.dot(c, c), out=T)   # (sum j y)^2 / sum j^2
    return T


def combined_detect(t, y, *, x=None, design=None, rate_per_day=1.0, adaptive=True,
                    wavelet_kw=None, train=None, holdoff=None, **monitor_kw):
    """Batch combined detector over whole series (the teaching form; no navigation loop).

    Parameters
    ----------
    t : array_like, shape (N,)
        Sample times, s, increasing and evenly spaced: each step within :data:`EVEN_RTOL` of
        the median step ``dt`` (a gap, a missing sample, is refused).
    y : array_like, shape (N, m) or (N,)
        Whitened innovations (unit white noise when healthy under the model).
    x : array_like, shape (N,), optional
        The raw series the wavelet watches (default: ``y[:, 0]``).
    design : CombinedDesign, optional
        Default from ``rate_per_day`` and the sampling of ``t``; a design given must be for
        that sampling (its ``samples_per_day`` within :data:`EVEN_RTOL` of ``86400 / dt``) and
        for the ``m`` columns of ``y``.
    adaptive : bool
        Adaptive noise scale of the innovation parts.
    wavelet_kw : dict, optional
        Passed to :func:`~.batch.wavelet_detect` (``level``, ``var_window``, ``sigma``...);
        not ``pfa`` (the design's) nor ``train`` (this function's own).
    train : int, optional
        Wavelet training samples at the start (default: the series itself).
    holdoff : int, optional
        Hold-off grouping the combined alarms into events (default the wavelet's).
    **monitor_kw
        Passed to :class:`InnovationMonitor` (``scale_samples``, ``scale_every``,
        ``prior_samples``); another keyword is refused, naming it.

    Returns
    -------
    Detection
        Combined alarms and events; ``data["first"]`` maps each part to its first alarm time
        (s, ``inf`` if none), ``data["parts"]`` to its alarm mask, ``data["ratio"]`` to its
        largest statistic / threshold per sample, and ``data["design"]``.

    Examples
    --------
    >>> rng = np.random.default_rng(2)
    >>> t = 3.0 * np.arange(6000)
    >>> y = rng.normal(0.0, 1.0, 6000)
    >>> y[3000:] += 5.0                                   # a 5-sigma step
    >>> res = combined_detect(t, y, train=2000)
    >>> res.events[0].onset - 9000.0 < 30.0, sorted(k for k, v in res.data["first"].items() if v < 9100)
    (True, ['chi2', 'variance', 'wavelet'])
    """
    t = check_finite_array("t", t)
    y = check_finite_array("y", y)
    if y.ndim == 1:
        y = y[:, None]
    if y.ndim != 2:
        raise ValueError(f"y must have shape (N, m) or (N,), got {y.shape}")
    series_lengths(t, "y", y.shape[0])
    if t.size < 400:
        raise ValueError(f"t must hold at least 400 samples (and y as many), got {t.size}")
    check_increasing("t", t)  # else a sampling rate from the median step, misnamed
    check_evenly_spaced("t", t, EVEN_RTOL)  # the design's rate and the wavelet assume one step
    dt = float(np.median(np.diff(t)))
    if design is None:
        design = CombinedDesign(86400.0 / dt, y.shape[1], rate_per_day)
    else:
        _check_design(design, dt, y.shape[1])
        if rate_per_day != 1.0:  # a rate beside a design would go unused
            raise ValueError(f"rate_per_day = {shown(rate_per_day)} is unused with a design (its "
                             f"own rate is {design.rate_per_day:g}): give one of them")
    given_x = x is not None
    x = y[:, 0] if x is None else check_shape("x", x, (t.size,), "one measurement a time of t")
    wkw = check_keywords("combined_detect", wavelet_kw, wavelet_detect, name="wavelet_kw",
                         set_here={"t": "its t", "x": "its x (default y[:, 0])",
                                   "pfa": "from the design's pfa_wavelet",
                                   "train": "its own train"})
    # the rest goes to InnovationMonitor, whose design, adaptive and holdoff are taken above
    own = [k for k in inspect.signature(combined_detect).parameters if k not in ("t", "y", "monitor_kw")]
    monitor_kw = check_keywords("combined_detect", monitor_kw,
                                own + ["scale_samples", "scale_every", "prior_samples"])
    wav = _wavelet_part(t, x, given_x, design.pfa_wavelet, train, wkw)
    mon = InnovationMonitor(design, adaptive=adaptive, **monitor_kw)
    rec = {}
    mon.process(t, y, stop=False, record=rec)
    r = rec["ratio"]
    m = design.m
    ratio = {"wavelet": np.where(wav.armed, wav.ratio, 0.0), "chi2": r[:, 0],
             "cusum": r[:, 1:1 + 2 * m].max(axis=1), "variance": r[:, 1 + 2 * m:].max(axis=1)}
    parts = {k: v > 1.0 for k, v in ratio.items()}
    parts["wavelet"] = wav.alarm
    alarm = np.any(list(parts.values()), axis=0)
    stacked = np.array([ratio[p] for p in PARTS])
    which = np.argmax(stacked, axis=0)
    best = stacked[which, np.arange(t.size)]
    hold = wav.data["holdoff"] if holdoff is None else check_int("holdoff", holdoff, 1)
    events, faulty = events_from_alarms(t, alarm, best, hold, np.asarray(PARTS)[which])
    first = {p: float(t[np.argmax(a)]) if a.any() else math.inf for p, a in parts.items()}
    return Detection(t, best, alarm, faulty, wav.armed, events,
                     data={"first": first, "parts": parts, "ratio": ratio, "design": design,
                           "wavelet": wav, "scale": mon.scale.copy()})


def _wavelet_part(t, x, given_x, pfa, train, wkw):
    """:func:`xnavlab.core.detection.batch.wavelet_detect` of ``x``; a series with no noise to
    train on is refused naming it as :func:`combined_detect` was given it (``y[:, 0]`` when
    ``x`` was not given) and ``wavelet_kw``'s sigma."""
    try:
        return wavelet_detect(t, x, pfa=pfa, train=train, **wkw)
    except ValueError as e:
        reword = getattr(e, "reword", None)   # batch's no-noise refusal, in its caller's words
        if reword is None:
            raise
        series = ("x" if given_x else "y[:, 0] (x not given)") if e.series == "x" else "train"
        raise ValueError(reword(series, f"wavelet_kw={{'sigma': ...}} ({e.level} levels)")) from None


def _check_design(design, dt, m):
    """``design`` (given to :func:`combined_detect`) as a CombinedDesign for samples ``dt`` s
    apart (within :data:`EVEN_RTOL`) and ``m`` components, else one ValueError naming it."""
    if not isinstance(design, CombinedDesign):
        raise ValueError(f"design must be a CombinedDesign (or None: one from rate_per_day and "
                         f"the sampling of t), got {type(design).__name__} {shown(design)}")
    rate = 86400.0 / dt
    if abs(design.samples_per_day - rate) > EVEN_RTOL * rate:
        raise ValueError(f"design must be for the sampling of t, {rate:.6g} samples a day (one "
                         f"every {dt:.6g} s), got {design!r}, {design.samples_per_day:.6g} a day "
                         f"(one every {86400.0 / design.samples_per_day:.6g} s): its thresholds "
                         f"would give another false-alarm rate")
    if design.m != m:
        raise ValueError(f"design must have m = {m} (the columns of y), got {design!r}")


def plot_combined_parts(drift_sigma_per_hour=3.0, step_sigma=0.0, noise_ratio=1.0,
                        model_noise=1.0, seed=0):
    """When each part of the combined detector fires: one drift (and optional step) in unit
    white noise at 3 s (a UV range or CNS angle innovation), 12 h, fault from hour 4.

    A pure function of its arguments (the chapter's slider).

    Parameters
    ----------
    drift_sigma_per_hour : float
        Drift rate, noise sigmas per hour, in [0, 100].
    step_sigma : float
        A step added at the fault onset, sigma, in [0, 100].
    noise_ratio : float
        Noise standard deviation after the onset over before, in [1, 10].
    model_noise : float
        True noise over the model's (a mis-modelled noise level), in [0.5, 3].
    seed : int
        Noise seed.

    Returns
    -------
    matplotlib.figure.Figure
        Top, the innovations; bottom, each part's statistic over its threshold, its first
        alarm after the onset dashed. It carries an in-place update
        (:func:`xnavlab.core.plotting.in_place`): a live slider sets its data and texts.

    Examples
    --------
    >>> fig = plot_combined_parts(drift_sigma_per_hour=8.0)
    >>> fig.axes[0].get_title().split(":")[0]
    'drift 8 sigma/h, step 0, noise x1'
    """
    from matplotlib.figure import Figure

    from xnavlab.core.plotting import in_place

    n = 14400
    t = 3.0 * np.arange(n)
    t0 = 14400.0
    on = t >= t0
    h = t / 3600.0
    colours = {"wavelet": "C0", "chi2": "C1", "cusum": "C2", "variance": "C3"}
    # the layout every frame shares; update() sets the data, the alarm lines and the title
    fig = Figure(figsize=(8.5, 4.2), layout="constrained")
    ax, bx = fig.subplots(2, 1, sharex=True, height_ratios=(1, 1.3))
    series, = ax.plot(h, np.zeros(n), lw=0.3, color="0.4")
    ax.axvline(t0 / 3600.0, color="k", lw=0.8, ls=":")
    ax.set(ylabel="innovation (sigma)")
    curves, firsts = {}, {}
    for p in PARTS:
        curves[p], = bx.semilogy(h, np.ones(n), lw=0.7, color=colours[p], label=p)
        # the part's first alarm after the onset (hidden when it has none)
        firsts[p] = bx.axvline(t0 / 3600.0, color=colours[p], lw=1.0, ls="--", visible=False)
    bx.axhline(1.0, color="k", lw=0.8)
    bx.axvline(t0 / 3600.0, color="k", lw=0.8, ls=":")
    bx.set(ylim=(1e-2, 1e2), xlabel="time (h)", ylabel="statistic / threshold")
    bx.legend(fontsize=8, ncol=4, loc="upper left")
    title = ax.set_title("", fontsize=9)

    def update(drift_sigma_per_hour=3.0, step_sigma=0.0, noise_ratio=1.0, model_noise=1.0,
               seed=0):
        drift = check_real("drift_sigma_per_hour", drift_sigma_per_hour, 0.0, 100.0)
        step = check_real("step_sigma", step_sigma, 0.0, 100.0)
        ratio = check_real("noise_ratio", noise_ratio, 1.0, 10.0)
        noise = check_real("model_noise", model_noise, 0.5, 3.0)
        rng = np.random.default_rng(check_seed("seed", seed))
        y = rng.normal(0.0, noise, n)
        y[on] = y[on] * ratio + step + drift * (t[on] - t0) / 3600.0
        res = combined_detect(t, y, train=4000)
        series.set_ydata(y)
        text = []
        for p in PARTS:
            curves[p].set_ydata(np.maximum(res.data["ratio"][p], 1e-3))
            f = min((tt for tt in t[res.data["parts"][p]] if tt >= t0), default=math.inf)
            firsts[p].set_visible(math.isfinite(f))
            if math.isfinite(f):
                firsts[p].set_xdata([f / 3600.0, f / 3600.0])
                text.append(f"{p} {f - t0:.0f} s")
            else:
                firsts[p].set_xdata([t0 / 3600.0, t0 / 3600.0])
                text.append(f"{p} -")
        for a in (ax, bx):
            a.relim()
            a.autoscale_view()
        title.set_text(f"drift {drift:g} sigma/h, step {step:g}, noise x{ratio:g}: first alarm "
                       "after onset: " + ", ".join(text))

    update(drift_sigma_per_hour, step_sigma, noise_ratio, model_noise, seed)
    return in_place(fig, update)
