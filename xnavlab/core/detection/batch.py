"""The batch wavelet detector: a whole series at once, or block by block in time.

:func:`wavelet_detect` runs the online detector's tests (:class:`~.online.WaveletDetector`)
over a whole series with compiled loops: the a trous details (:func:`~.online.causal_details`)
and every level's test and the variance test in one pass; :func:`wavelet_detect_sensor` ORs
the components of a sensor. :class:`BlockWavelet` and :class:`BlockWaveletSensor` compute the
same thing in time blocks (:meth:`~BlockWavelet.advance`), the same bits as one batch: each
block restarts the filters a warm-up before it (the details' span, 155 samples for db3 at five
levels, plus the variance window's), from the series' first sample. A navigation loop can so
take the onsets of the first days and start filtering while the rest is computed in another
thread (:mod:`xnavlab.mars.faults.fault_tolerance`).
"""

from __future__ import annotations

from concurrent.futures import Executor

import numpy as np
from numba import njit

from xnavlab.core.detection.online import (
    Detection,
    WaveletDetector,
    causal_details,
    causal_filters,
    events_from_alarms,
    mad_sigma,
)
from xnavlab.core.validate import (
    check_finite_array,
    check_increasing,
    check_int,
    check_keywords,
    check_real,
    shown,
)

__all__ = ["wavelet_detect", "wavelet_detect_sensor", "BlockWavelet", "BlockWaveletSensor"]


@njit(cache=True, nogil=True)
def _batch_ratios(d, sigma, k, w, lo, hi, which, q, ratio):
    """The tests of :func:`wavelet_detect` in one pass, in place: the levels' ``|d_j /
    sigma_j| / k`` and (window ``w > 0``) the variance test on ``Q[n] = sum_(i<w) z_1[n - 2i]^2``
    (``q``, from sample ``2w - 2``); ``ratio`` their maximum, ``which`` its test's index."""
    level, n = d.shape
    z1sq = np.empty(n if w > 0 else 0)
    for i in range(z1sq.size):
        z1sq[i] = (d[0, i] / sigma[0]) ** 2
    for i in range(n):
        r = -1.0
        for j in range(level):
            v = abs(d[j, i] / sigma[j]) / k
            if v > r:
                r = v
                which[i] = j
        if w > 0:
            v = 0.0
            if i >= 2 * w - 2:
                s = 0.0
                for m in range(w):                    # Q[n] = sum_i z_1[n - 2i]^2
                    s += z1sq[i - 2 * m]
                q[i] = s
                v = max(s / hi, lo / max(s, 1e-300))  # > 1 outside [lo, hi]
            if v > r:
                r = v
                which[i] = level
        ratio[i] = r


def wavelet_detect(t, x, *, wavelet="db3", level=5, sigma=None, train=None, pfa=1e-5,
                   var_window=32, holdoff=None):
    """Batch wavelet detector over a whole series; the same decisions as :class:`~.online.WaveletDetector`.

    Parameters
    ----------
    t : array_like, shape (N,)
        Sample times, s, increasing.
    x : array_like, shape (N,)
        Measurements of one component (any unit).
    wavelet, level, pfa, var_window, holdoff
        As in :class:`~.online.WaveletDetector`.
    sigma : array_like, shape (level,), optional
        Per-level noise; if omitted it is trained by MAD on ``train``.
    train : array_like or int, optional
        A fault-free training series, or an int ``n``: train on ``x[:n]`` (which must then be
        fault-free; the detector arms only after it). Default: ``x`` itself, robust as long
        as faults cover a small fraction of it (the median ignores them).

    Returns
    -------
    Detection
        With ``data["details"]`` (level, N), ``data["sigma"]`` (level,) (``details /
        sigma[:, None]`` is the normalised detail), ``data["k"]`` and ``data["variance"]``
        (the Q statistic).

    Examples
    --------
    >>> from xnavlab.core.faults import Fault, inject
    >>> rng = np.random.default_rng(4)
    >>> t = 3.0 * np.arange(20000)
    >>> x = inject(t, rng.normal(0.0, 5000.0, t.size), [Fault("uv", "step", 50000.0, 30000.0, 3000.0)], "uv")
    >>> res = wavelet_detect(t, x)
    >>> [(e.onset, e.end) for e in res.events]
    [(30012.0, 30366.0), (33003.0, 33291.0)]
    """
    b = BlockWavelet(t, x, wavelet=wavelet, level=level, sigma=sigma, train=train, pfa=pfa,
                     var_window=var_window, holdoff=holdoff)
    b.advance(b.n)
    return b.detection()


def wavelet_detect_sensor(t, z, *, pfa=1e-5, train=None, sigma=None, executor=None, **kwargs):
    """Batch wavelet detection of a multi-component sensor: one detector per component, OR-ed.

    Each of the ``m`` components gets its own :func:`wavelet_detect` with ``pfa / m``, so the
    sensor as a whole keeps the design false-alarm probability ``pfa`` per sample; a sample
    alarms when any component alarms, and the combined alarms are grouped into events with the
    same hold-off.

    Parameters
    ----------
    t : array_like, shape (N,)
        Sample times, s.
    z : array_like, shape (N, m) or (N,)
        The sensor's measurements, one column per component.
    pfa : float
        Design false-alarm probability per sensor sample.
    train : int or array_like of shape (N_train, m), optional
        As in :func:`wavelet_detect`, per column for an array.
    sigma : array_like, shape (m, level), optional
        Per-component, per-level noise.
    executor : concurrent.futures.Executor, optional
        Runs the components' detectors (a thread pool: their compiled parts release the
        GIL); the result is the same.
    **kwargs
        ``wavelet``, ``level``, ``var_window``, ``holdoff`` as in :func:`wavelet_detect`
        (another keyword is refused, naming it).

    Returns
    -------
    Detection
        Combined; ``data["components"]`` holds the per-component results and
        ``data["component"]`` (N,) the component with the largest ratio (-1 where none).

    Examples
    --------
    >>> from xnavlab.core.faults import Fault, inject
    >>> t = 3.0 * np.arange(6000)
    >>> z = np.random.default_rng(0).normal(0.0, 1.0, (6000, 3))
    >>> z = inject(t, z, [Fault("cns", "spike", 12.0, onset=9000.0, component=2)], "cns")
    >>> res = wavelet_detect_sensor(t, z)
    >>> [(e.onset, e.test) for e in res.events]
    [(9000.0, 'component 2, level 1')]
    """
    kwargs = _sensor_kwargs("wavelet_detect_sensor", kwargs)
    b = BlockWaveletSensor(t, z, pfa=pfa, train=train, sigma=sigma, executor=executor, **kwargs)
    b.advance(b.n)
    return b.detection()


#: The keywords :func:`wavelet_detect_sensor` passes on to each component's detector.
_SENSOR_KW = ("wavelet", "level", "var_window", "holdoff")


def _sensor_kwargs(caller, kwargs):
    """``kwargs`` for each component's :class:`BlockWavelet`, else one ValueError naming the
    keyword (an internal class was named in a TypeError)."""
    return check_keywords(caller, kwargs, _SENSOR_KW + ("t", "z", "pfa", "train", "sigma",
                                                          "executor"))


def _check_executor(executor):
    if executor is not None and not isinstance(executor, Executor) and \
            not callable(getattr(executor, "map", None)):
        raise ValueError(f"executor must be a concurrent.futures.Executor (or None: the "
                         f"components in turn), got {type(executor).__name__} {shown(executor)}")
    return executor


def series_lengths(t, name, n):
    """Check ``t`` as a 1-D array of sample times and its length against the ``n`` samples of
    the series ``name``; when the lengths disagree the shorter is named (a series cut short
    is the likelier slip), in one ValueError.

    Examples
    --------
    >>> series_lengths(np.arange(3.0), "x", 2)
    Traceback (most recent call last):
    ...
    ValueError: x must have N = len(t) = 3 samples, got 2
    """
    if t.ndim != 1:
        raise ValueError(f"t must be a 1-D array of sample times, got shape {t.shape}")
    if n < t.size:
        raise ValueError(f"{name} must have N = len(t) = {t.size} samples, got {n}")
    if n > t.size:
        raise ValueError(f"t must hold one time per sample of {name} ({n}), got {t.size}")


class BlockWavelet:
    """:func:`wavelet_detect` of one series, computed block by block in time.

    Parameters are those of :func:`wavelet_detect`. :meth:`advance` computes the tests up to a
    sample; :meth:`new_onsets` also returns the event onsets found there; :meth:`detection`
    gives :func:`wavelet_detect`'s result once the whole series is done.

    Examples
    --------
    >>> rng = np.random.default_rng(4)
    >>> t = 3.0 * np.arange(20000)
    >>> x = rng.normal(0.0, 5000.0, t.size)
    >>> x[10000:11000] += 50000.0
    >>> b = BlockWavelet(t, x, train=5000)
    >>> b.new_onsets(9000).tolist(), b.new_onsets(20000).tolist()
    ([], [10004, 11001])
    >>> bool(np.array_equal(b.detection().ratio, wavelet_detect(t, x, train=5000).ratio))
    True
    """

    def __init__(self, t, x, *, wavelet="db3", level=5, sigma=None, train=None, pfa=1e-5,
                 var_window=32, holdoff=None):
        self.t = t = check_finite_array("t", t)
        self.x = x = check_finite_array("x", x)
        if x.ndim != 1:
            raise ValueError(f"x must be a 1-D series of measurements, got shape {x.shape}")
        series_lengths(t, "x", x.size)
        check_increasing("t", t)
        self.det = det = WaveletDetector(wavelet, level, sigma=sigma, pfa=pfa,
                                         var_window=var_window, holdoff=holdoff)
        self.n = n = x.size
        start = 0
        if det.sigma is None:
            if train is None:
                if n < det.window + 200:
                    raise ValueError(f"x must be a 1-D training series of at least "
                                     f"{det.window + 200} samples (train and sigma not given), "
                                     f"got shape {x.shape}")
                _train(det, x, "x", f"[0, {n}) (train not given: the whole series)")
            elif isinstance(train, int | np.integer) and not isinstance(train, bool):
                start = check_int("train", train, det.window + 200, n)
                _train(det, x[:start], "x", f"[0, {start}) (train = {start})")
            else:
                train = check_finite_array("train", train)
                if train.ndim != 1 or train.size < det.window + 200:   # named here, not as det.train's x
                    raise ValueError(f"train must be a 1-D fault-free series of at least "
                                     f"{det.window + 200} samples (or an int), got shape {train.shape}")
                _train(det, train, "train", f"[0, {train.size}) (the whole series)")
        self.d = np.empty((det.level, n))
        self.ratio = np.empty(n)
        self.which = np.zeros(n, dtype=np.int8)
        self.q = np.full(n, np.nan)
        self.armed = np.zeros(n, dtype=bool)
        self.armed[max(det.window - 1, start):] = True
        self.warm = len(causal_filters(det.wavelet, det.level)[-1]) - 1 + 2 * det.var_window
        self.holdoff = det.holdoff
        self.done = 0              # samples computed
        self._last_alarm = None    # the latest alarm's index (events across blocks)

    def advance(self, stop):
        """Compute the tests of samples ``[done, stop)``."""
        stop = min(check_int("stop", stop, 0), self.n)
        if stop <= self.done:
            return
        det, a = self.det, max(0, self.done - self.warm)
        d = causal_details(self.x[a:stop], det.wavelet, det.level, origin=self.x[0])
        m = stop - a
        ratio, which, q = np.empty(m), np.zeros(m, dtype=np.int8), np.full(m, np.nan)
        lo, hi = det.var_bounds if det.var_window else (0.0, 0.0)
        _batch_ratios(d, np.asarray(det.sigma, dtype=float), det.k, det.var_window, lo, hi,
                      which, q, ratio)
        k = self.done - a
        self.d[:, self.done:stop] = d[:, k:]
        self.ratio[self.done:stop], self.which[self.done:stop] = ratio[k:], which[k:]
        self.q[self.done:stop] = q[k:]
        self.done = stop

    def alarm(self, lo=0, hi=None):
        """Alarms of samples ``[lo, hi)`` (computed ones)."""
        lo = check_int("lo", lo, 0)
        hi = self.done if hi is None else min(check_int("hi", hi, lo), self.done)
        return self.armed[lo:hi] & (self.ratio[lo:hi] > 1.0)

    def new_onsets(self, stop):
        """:meth:`advance` to ``stop`` and return the onsets (sample indices) of the events
        that start in the new samples (as :func:`~.online.events_from_alarms` groups them)."""
        lo = self.done
        self.advance(stop)
        idx = lo + np.flatnonzero(self.alarm(lo))
        prev = np.r_[-np.inf if self._last_alarm is None else self._last_alarm, idx[:-1]]
        if idx.size:
            self._last_alarm = int(idx[-1])
        return idx[idx - prev > self.holdoff]   # a gap beyond the hold-off starts an event

    def detection(self):
        """The :func:`wavelet_detect` result (the whole series must be done)."""
        if self.done < self.n:
            raise ValueError(f"detection: only {self.done} of {self.n} samples are computed")
        det = self.det
        names = [f"level {j + 1}" for j in range(det.level)]
        if det.var_window:
            names.append("variance")
        alarm = self.alarm()
        tests = _TestNames(names, self.which)  # the deciding test at each sample (lazily)
        events, faulty = events_from_alarms(self.t, alarm, self.ratio, det.holdoff, tests)
        return Detection(self.t, self.ratio, alarm, faulty, self.armed, events,
                         data={"details": self.d, "sigma": det.sigma, "k": det.k,
                               "variance": self.q, "thresholds": det.thresholds,
                               "holdoff": det.holdoff, "tests": tests})


def _train(det, series, name, span):
    """Set ``det.sigma`` by the MAD of each level's details of ``series`` (as
    :meth:`xnavlab.core.detection.online.WaveletDetector.train`), else :class:`_NoNoise` naming
    ``name`` (``"x"`` or ``"train"``) and the training samples ``span``."""
    sigma = mad_sigma(causal_details(series, det.wavelet, det.level)[:, det.window - 1:])
    if np.any(sigma <= 0.0):   # a MAD of 0 was refused as sigma, never given (review 35 R15)
        raise _NoNoise(name, span, np.flatnonzero(sigma <= 0.0) + 1, det.level)
    det.sigma = sigma


class _NoNoise(ValueError):
    """A training series with no noise at some level (the median of its ``|d_j|`` is 0).

    ``series`` is ``"x"`` or ``"train"``; :meth:`reword` gives the message in a caller's
    words (a sensor's column, :func:`xnavlab.core.detection.combined.combined_detect`'s
    default ``y[:, 0]``)."""

    def __init__(self, series, span, levels, level):
        self.series, self.span, self.levels, self.level = series, span, levels, level
        super().__init__(self.reword(series))

    def reword(self, series, sigma=None):
        """The message naming ``series`` and, to give instead, ``sigma`` (default ``sigma``
        of ``level`` levels)."""
        levels = ("level " if len(self.levels) == 1 else "levels ") + ", ".join(map(str, self.levels))
        sigma = f"sigma ({self.level} levels)" if sigma is None else sigma
        return (f"{series} has no noise over the training samples {self.span}: the median "
                f"|detail coefficient| is 0 at {levels} of {self.level}, so no noise level "
                f"can be estimated; give {sigma} or a noisy series")


class BlockWaveletSensor(BlockWavelet):
    """:func:`wavelet_detect_sensor` computed block by block in time: one :class:`BlockWavelet`
    per component with ``pfa / m``, their alarms OR-ed.

    Parameters are those of :func:`wavelet_detect_sensor` (``executor`` runs the components
    of each :meth:`advance`). :meth:`~BlockWavelet.new_onsets` is the single series', on the
    OR-ed alarms.
    """

    def __init__(self, t, z, *, pfa=1e-5, train=None, sigma=None, executor=None, **kwargs):
        kwargs = _sensor_kwargs(type(self).__name__, kwargs)
        executor = _check_executor(executor)
        t = check_finite_array("t", t)
        z = check_finite_array("z", z)
        if z.ndim == 1:
            z = z[:, None]
        if z.ndim != 2:
            raise ValueError(f"z must have shape (N, m) or (N,), got {z.shape}")
        series_lengths(t, "z", z.shape[0])
        m = z.shape[1]
        pfa = check_real("pfa", pfa, 0.0, 1.0, lo_open=True, hi_open=True)
        if sigma is not None:
            sigma = check_finite_array("sigma", sigma)
            if sigma.ndim != 2 or sigma.shape[0] != m:
                raise ValueError(f"sigma must have shape (m, level) with m = {m}, got {sigma.shape}")
        if train is not None and not isinstance(train, int | np.integer):
            train = check_finite_array("train", train)
            if train.ndim == 1:
                train = train[:, None]
            if train.ndim != 2 or train.shape[1] != m:
                raise ValueError(f"train must have shape (N_train, {m}), got {train.shape}")

        def one(i):
            tr = train if train is None or isinstance(train, int | np.integer) else train[:, i]
            try:
                return BlockWavelet(t, z[:, i], pfa=pfa / m, train=tr,
                                    sigma=None if sigma is None else sigma[i], **kwargs)
            except _NoNoise as e:   # named as the user gave it: a column of z or of train
                raise ValueError(e.reword(f"{'z' if e.series == 'x' else 'train'}[:, {i}]",
                                          f"sigma (shape ({m}, {e.level}))")) from None

        self.executor = executor
        self.parts = self._map(one, range(m))
        self.t, self.n, self.done, self._last_alarm = t, t.size, 0, None
        self.holdoff = self.parts[0].det.holdoff

    def _map(self, f, items):
        return list(map(f, items) if self.executor is None else self.executor.map(f, items))

    def advance(self, stop):
        self._map(lambda p: p.advance(stop), self.parts)
        self.done = min(p.done for p in self.parts)

    def alarm(self, lo=0, hi=None):
        return np.any([p.alarm(lo, hi) for p in self.parts], axis=0)

    def detection(self):
        """The :func:`wavelet_detect_sensor` result (the whole series must be done)."""
        parts = self._map(lambda p: p.detection(), self.parts)
        t = self.t
        ratios = np.array([p.ratio for p in parts])
        which = np.argmax(ratios, axis=0)
        ratio = ratios[which, np.arange(t.size)]
        alarm = np.any([p.alarm for p in parts], axis=0)
        armed = np.all([p.armed for p in parts], axis=0)
        names = _ComponentTests(parts, which)
        events, faulty = events_from_alarms(t, alarm, ratio, self.holdoff, names)
        return Detection(t, ratio, alarm, faulty, armed, events,
                         data={"components": parts, "component": np.where(alarm, which, -1),
                               "holdoff": self.holdoff})


class _TestNames:
    """``names[n]``: the test with the largest ratio at sample ``n`` (lazy, no N-long array)."""

    def __init__(self, names, which):
        self.names, self.which = names, which

    def __len__(self):
        return len(self.which)

    def __getitem__(self, n):
        return self.names[int(self.which[n])]


class _ComponentTests:
    """``names[n]``: which component and test has the largest ratio at sample ``n`` (lazy)."""

    def __init__(self, parts, which):
        self.parts, self.which = parts, which

    def __len__(self):
        return len(self.which)

    def __getitem__(self, n):
        i = int(self.which[n])
        return f"component {i}, {self.parts[i].data['tests'][n]}"


