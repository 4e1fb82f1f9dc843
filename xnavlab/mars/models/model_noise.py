"""Process noise from the model difference: what the filter's force model leaves out, as ``q_acc``.

A filter that integrates a poorer force model than the truth's
(:class:`xnavlab.mars.models.force_models.ForceModel`) stands for what it leaves out by white
acceleration noise of spectral density ``q`` (m^2/s^3). Along the truth orbit we take that
acceleration, ``da(t) = a_truth(t, r) - a_filter(t, r)`` (:func:`unmodelled_acceleration`), its
per-axis variance ``sigma_a^2 = mean |da|^2 / 3`` and its correlation time ``tau`` (the integral
of its normalised autocorrelation up to the first zero; :func:`unmodelled_statistics`), and the
guideline of Bar-Shalom, Li and Kirubarajan (2001, sec. 6.2.2) for the continuous white-noise
acceleration model: the velocity change over a time ``T`` is of the order ``sqrt(q T)``, here
``sigma_a T``, so

.. math:: q = \\sigma_a^2 \\, T

with ``T = tau``: over ``tau`` the unmodelled acceleration acts as a constant, beyond it as a
random walk whose white noise is ``sigma_a^2 tau`` (:func:`derived_q_acc`).
:func:`study_fields` gives :meth:`xnavlab.mars.navigation.scenarios.MarsScenario.study` its fields.

For the study's truth against the paper's filter on the paper's orbit (first day, 30-s samples)
this is an RMS of 5.1e-3 m/s^2 (Mars's J2 and C22 dominate; SRP is 2-3e-8), ``tau`` = 588 s and
``q`` = 5.1e-3 m^2/s^3, against the book's default 1e-11
(:data:`xnavlab.mars.navigation.scenarios.DEFAULT_Q_ACC`; the paper gives no process noise).

Examples
--------
>>> derived_q_acc("paper", "paper", days=0.05)
0.0
"""

from __future__ import annotations

import functools
import math

import numpy as np

from xnavlab.core import ephemeris
from xnavlab.core.constants import DAY
from xnavlab.core.validate import (
    check_callable,
    check_choice,
    check_finite_array,
    check_instance,
    check_real,
)
from xnavlab.mars.models import _checks, dynamics
from xnavlab.mars.models.force_models import PAPER, STUDY, accelerations, model, truth

__all__ = ["unmodelled_acceleration", "unmodelled_statistics", "derived_q_acc", "study_fields"]


def unmodelled_acceleration(t, states, truth_model=STUDY, filter_model=PAPER,
                            truth_ephem="de421", filter_ephem="de421"):
    """The acceleration the filter's model leaves out along an orbit, m/s^2, shape (n, 3).

    ``a_truth(t, r) - a_filter(t, r)`` at the positions of ``states`` (each model with its own
    ephemeris).

    Parameters
    ----------
    t : array_like, shape (n,)
        Epochs, s TDB past J2000.
    states : array_like, shape (n, 6) or (n, 3)
        Mars-centred positions (and velocities, unused), m.
    truth_model, filter_model : ForceModel or str
    truth_ephem, filter_ephem : {"de421", "de405"}

    Examples
    --------
    >>> t = dynamics.MARS_T0 + np.array([0.0, 600.0])
    >>> x = dynamics.truth(t, cache=False)
    >>> float(np.abs(unmodelled_acceleration(t, x, "paper", "paper")).max())
    0.0
    """
    t = _checks.epochs("t", t)
    _check_ephems(truth_ephem, filter_ephem)
    states = check_finite_array("states", states)
    if states.ndim != 2 or states.shape[1] not in (3, 6) or states.shape[0] != t.size:
        raise ValueError(f"states must have shape ({t.size}, 6) or ({t.size}, 3) (n = length "
                         f"of t), got {states.shape}")
    truth_model, filter_model = model(truth_model, "truth_model"), model(filter_model, "filter_model")
    r = states[:, :3]
    return (accelerations(t, r, truth_model, truth_ephem)
            - accelerations(t, r, filter_model, filter_ephem))


def _check_ephems(truth_ephem, filter_ephem):
    """Both ephemerides checked under their names; the span both cover, s TDB past J2000."""
    spans = [ephemeris.coverage(check_choice(name, e, ephemeris.EPHEMERIDES))
             for name, e in (("truth_ephem", truth_ephem), ("filter_ephem", filter_ephem))]
    return max(s[0] for s in spans), min(s[1] for s in spans)


def unmodelled_statistics(truth_model=STUDY, filter_model=PAPER, days=1.0, dt=30.0,
                          state0=dynamics.MARS_STATE0, t0=dynamics.MARS_T0, truth_ephem="de421",
                          filter_ephem="de421"):
    """Size and time scale of the unmodelled acceleration along the truth orbit.

    Parameters
    ----------
    truth_model, filter_model : ForceModel or str
    days : float
        Span sampled, days, in (0, 365] (the truth integrated with the truth model), at least
        one step ``dt`` (two samples or more).
    dt : float
        Sampling step, s, in [1, 3600].
    state0, t0, truth_ephem, filter_ephem
        The orbit and the ephemerides (:class:`~xnavlab.mars.navigation.scenarios.MarsScenario`);
        ``t0`` to ``t0 + days`` inside both ephemerides' coverage.

    Returns
    -------
    dict
        ``rms_mps2`` (RMS of ``|da|``), ``sigma_axis_mps2`` (``rms / sqrt(3)``, per axis),
        ``max_mps2``, ``correlation_time_s`` (``tau``: the integral of the normalised
        autocorrelation of ``da`` up to its first zero) and ``days``, ``dt_s``.

    Examples
    --------
    >>> st = unmodelled_statistics("paper", "paper", days=0.05)
    >>> st["rms_mps2"], st["correlation_time_s"]
    (0.0, 0.0)
    """
    truth_model, filter_model = model(truth_model, "truth_model"), model(filter_model, "filter_model")
    days = check_real("days", days, 0.0, 365.0, lo_open=True)
    dt = check_real("dt", dt, 1.0, 3600.0)
    if dt > days * DAY:  # one sample: no correlation (0/0, review 35j); as MarsScenario's days
        raise ValueError(f"days must span at least one sampling step dt = {dt:g} s (two samples "
                         f"or more for a correlation time), got {days:g} ({days * DAY:.6g} s)")
    lo, hi = _check_ephems(truth_ephem, filter_ephem)  # review 35k: 'ephem', 't_eval', 't_start'
    t0 = _checks.epoch("t0", t0, lo, hi - 7200.0 - days * DAY)  # the run inside both ephemerides
    t = t0 + np.arange(0.0, days * DAY + 1e-9, dt)
    x = truth(t, state0, t0, truth_model, truth_ephem)
    da = unmodelled_acceleration(t, x, truth_model, filter_model, truth_ephem, filter_ephem)
    rms = float(np.sqrt(np.mean(np.sum(da**2, axis=1))))
    tau = 0.0
    if rms > 0.0:
        dev = da - da.mean(axis=0)
        n = t.size
        spec = np.fft.rfft(dev, n=2 * n, axis=0)  # autocorrelation by FFT, summed over axes
        acf = np.fft.irfft(np.sum(np.abs(spec) ** 2, axis=1))[:n] / np.arange(n, 0, -1)
        rho = acf / acf[0]
        first = np.flatnonzero(rho <= 0.0)
        stop = int(first[0]) if first.size else n
        tau = float(np.trapezoid(rho[:stop], dx=dt)) if stop > 1 else 0.0
    return {"rms_mps2": rms, "sigma_axis_mps2": rms / math.sqrt(3.0),
            "max_mps2": float(np.linalg.norm(da, axis=1).max()), "correlation_time_s": tau,
            "days": days, "dt_s": dt}


def derived_q_acc(truth_model=STUDY, filter_model=PAPER, horizon="correlation", days=1.0,
                  **orbit):
    """The filter's white-acceleration PSD from the model difference, m^2/s^3.

    ``q = sigma_a^2 T`` (module notes: Bar-Shalom, Li and Kirubarajan 2001, sec. 6.2.2), with
    ``sigma_a`` the per-axis RMS of the unmodelled acceleration along the truth orbit
    (:func:`unmodelled_statistics`) and ``T``:

    ``"correlation"`` (default)
        the unmodelled acceleration's correlation time ``tau``: over ``tau`` it acts as a
        constant, so the velocity the filter misses grows as ``sigma_a t`` up to ``t = tau``
        and as a random walk beyond; ``q = sigma_a^2 tau`` is the white noise of that walk
        (one half of the zero-frequency density ``2 sigma_a^2 tau`` of an exponentially
        correlated process: the same order; the two-sided form overstates a periodic term).
    a number
        ``T`` in seconds, e.g. the filter's step (3 s), in (0, 1e6].

    Parameters
    ----------
    truth_model, filter_model : ForceModel or str
    horizon : "correlation" or float
    days : float
        Span of the orbit sampled (:func:`unmodelled_statistics`).
    **orbit
        ``state0``, ``t0``, ``truth_ephem``, ``filter_ephem``, ``dt``.

    Returns
    -------
    float
        ``q``, in [0, 1] (a larger one is refused: the models differ beyond what white noise
        can stand for).

    Examples
    --------
    >>> derived_q_acc("paper", "paper", days=0.05)
    0.0
    """
    takes = ("state0", "t0", "truth_ephem", "filter_ephem", "dt")  # unmodelled_statistics'
    for key in orbit:
        if key not in takes:  # review 35j: unmodelled_statistics' TypeError
            raise ValueError(f"derived_q_acc got {key}={orbit[key]!r:.60}: not an orbit setting "
                             f"(they are {', '.join(takes)})")
    st = unmodelled_statistics(truth_model, filter_model, days=days, **orbit)
    if isinstance(horizon, str):
        check_choice("horizon", horizon, ("correlation",))
        T = st["correlation_time_s"]
    else:
        T = check_real("horizon", horizon, 0.0, 1e6, lo_open=True)
    q = st["sigma_axis_mps2"] ** 2 * T  # q = sigma_a^2 T
    if q > 1.0:
        raise ValueError(f"the unmodelled acceleration ({st['rms_mps2']:.3g} m/s^2 RMS) needs "
                         f"q_acc {q:.3g} m^2/s^3, beyond the filter's range [0, 1]")
    return float(q)


@functools.lru_cache(maxsize=8)
def _derived(truth_model, filter_model, state0, t0, truth_ephem, filter_ephem):
    return derived_q_acc(truth_model, filter_model, state0=np.array(state0), t0=t0,
                         truth_ephem=truth_ephem, filter_ephem=filter_ephem)


def study_fields(make, fields):
    """The fields of the studies' set-up: ``truth_model`` :data:`~xnavlab.mars.models.force_models.STUDY`,
    ``filter_model`` the paper's and ``q_acc`` :func:`derived_q_acc` over the first day of the
    scenario's own orbit, each unless ``fields`` give it.

    Parameters
    ----------
    make : callable
        ``make(fields) -> MarsScenario`` (the class), for the scenario's orbit and ephemerides.
    fields : dict
        The caller's fields.

    Returns
    -------
    dict

    Examples
    --------
    >>> from xnavlab.mars.navigation.scenarios import MarsScenario
    >>> f = study_fields(lambda kw: MarsScenario(**kw), {"days": 1.0, "q_acc": 1e-6})
    >>> f["truth_model"].gravity_degree, f["q_acc"]
    (8, 1e-06)
    """
    check_callable("make", make, "a function make(fields) -> MarsScenario")
    check_instance("fields", fields, dict, "a dict of MarsScenario fields")
    fields = {"truth_model": STUDY, "filter_model": PAPER, **fields}
    if "q_acc" not in fields:
        probe = make({**fields, "q_acc": 0.0})
        fields["q_acc"] = _derived(probe.truth_model, probe.filter_model, probe.state0, probe.t0,
                                   probe.truth_ephem, probe.filter_ephem)
    return fields
