"""Does the RKF's ``Sigma`` bound the error? Coverage, error ratio and NEES over seeds.

The RKF (:mod:`xnavlab.robust.filters`) propagates a matrix ``Sigma`` that is an upper bound
on the error's second moment, ``E[e e^T] <= Sigma``, **if** the matrix ``B B^T`` it is given
is an upper bound on the bias outer product (chapter 10, inequality (53)). Three statistics
test that property on simulated runs, over the epochs after the first fifth:

coverage
    fraction of epochs with ``|e_r| <= 3 sqrt(tr Sigma_rr)``. For a bound that holds,
    Chebyshev's inequality gives ``P(|e_r| > k sqrt(tr Sigma_rr)) <= E|e_r|^2 / (k^2 tr
    Sigma_rr) <= 1 / k^2`` at each epoch, whatever the error's distribution: the expected
    coverage is at least :data:`CHEBYSHEV_LEVEL` (8/9 for ``k = 3``).
ratio
    ``|e_r| / sqrt(tr Sigma_rr)``; its median is below about 1 for a bound.
NEES
    ``e_r^T Sigma_rr^-1 e_r``; ``E[NEES] = tr(Sigma_rr^-1 E[e_r e_r^T]) <= 3`` for a bound.

Two sources of ``B B^T`` are compared (:func:`coverage_over_seeds`):

``rkf_bias="residual"`` (the paper's, re-derived; the reproduction's default)
    ``[m m^T - lam/(2-lam) S]_+`` from the running mean ``m`` of the innovations. It is a
    *lower* bound, and only on the part of the bias the innovations still show: once the
    state has absorbed part of the bias, ``E[nu] = H E[e-] + B`` is no longer ``B``. The
    property is lost, and this module measures by how much.
``rkf_bias="prior"`` (added here)
    ``B B^T = N dr_E dr_E^T N^T <= d_max^2 N N^T`` from a prior bound ``|dr_E| <= d_max`` on
    the ephemeris error (for the real error, its size from the DE421 - DE405 difference,
    :func:`prior_bias_max`). An upper bound whenever the prior holds, so ``Sigma`` bounds
    the error; the price is that the three measurements are de-weighted along every
    direction the bias may take.

Residuals alone cannot give an upper bound: the part of the bias the state has absorbed
leaves no trace in the innovations. A bound that holds must come from outside the data.

Units: m. Frames: planet-centred J2000.

Examples
--------
>>> out = coverage_over_seeds("rkf", seeds=(0,), n_steps=60, rkf_bias="prior")
>>> out["coverage"] >= CHEBYSHEV_LEVEL
True
"""

from __future__ import annotations

import inspect

import numpy as np

from xnavlab.core.validate import (
    check_choice,
    check_definite,
    check_instance,
    check_int,
    check_items,
    check_real,
    check_seeds,
)
from xnavlab.robust import ephemeris_error as ee
from xnavlab.robust import filters
from xnavlab.robust._checks import check_run_of

__all__ = [
    "K_SIGMA",
    "CHEBYSHEV_LEVEL",
    "SKIP",
    "bound_coverage",
    "prior_bias_max",
    "coverage_over_seeds",
    "BOUND_SOURCES",
    "compare_bounds",
]

#: The ellipse's size in sigmas: ``|e_r| <= K_SIGMA sqrt(tr Sigma_rr)``.
K_SIGMA = 3.0
#: Coverage a bound that holds guarantees in expectation at ``K_SIGMA = 3`` (Chebyshev, 1 - 1/k^2).
CHEBYSHEV_LEVEL = 1.0 - 1.0 / K_SIGMA**2
#: Fraction of the run left out at the start (the initial transient).
SKIP = 0.2


def bound_coverage(run, scenario, k=K_SIGMA, skip=SKIP):
    """Coverage, error ratio and NEES of one run's position covariance (or bound).

    Parameters
    ----------
    run : xnavlab.robust.filters.FilterRun
        Its ``P`` is the filter's covariance (for the RKF, the bound ``Sigma``).
    scenario : xnavlab.robust.filters.Scenario
        The truth the run is scored against.
    k : float
        Size of the ellipse, sigmas, at least 1e-3 (a subnormal k divided the level
        ``1 - 1/k^2`` by zero).
    skip : float
        Fraction of the epochs left out at the start, in [0, 1).

    Returns
    -------
    dict
        ``coverage`` (fraction of the kept epochs with ``|e_r| <= k sqrt(tr Sigma_rr)``),
        ``median_ratio`` (median of ``|e_r| / sqrt(tr Sigma_rr)``), ``nees`` (mean of
        ``e_r^T Sigma_rr^-1 e_r``; 3 for a consistent filter, at most 3 for a bound),
        ``rmse_m``, ``median_sigma_m`` (median ``sqrt(tr Sigma_rr)``), and the kept
        epochs' series ``ratio`` (n,) and ``nees_k`` (n,).

    Examples
    --------
    >>> sc = filters.simulate("mars", n_steps=40, error="none", rng=0)
    >>> c = bound_coverage(filters.run_filter("ukf", sc, rng=0), sc)
    >>> 0.0 <= c["coverage"] <= 1.0, c["ratio"].shape
    (True, (32,))
    """
    check_instance("run", run, filters.FilterRun, "a FilterRun from run_filter()")
    check_instance("scenario", scenario, filters.Scenario, "the Scenario the run ran on")
    check_run_of(run, scenario)  # its epochs and its truth
    k = check_real("k", k, 1e-3)
    skip = check_real("skip", skip, 0.0, 1.0, hi_open=True)
    first = int(skip * scenario.t.size)
    e = run.x[first:, :3] - scenario.x_true[first:, :3]
    P = check_definite("run.P", run.P[first:, :3, :3])  # NEES inverts it: not indefinite, singular
    sig = np.sqrt(np.trace(P, axis1=1, axis2=2))  # sqrt(tr Sigma_rr)
    dist = np.linalg.norm(e, axis=1)
    ratio = dist / sig
    nees = np.einsum("ni,ni->n", e, np.linalg.solve(P, e[..., None])[..., 0])  # e^T Sigma^-1 e
    return {"coverage": float(np.mean(ratio <= k)), "median_ratio": float(np.median(ratio)),
            "nees": float(np.mean(nees)), "rmse_m": float(np.sqrt(np.mean(dist**2))),
            "median_sigma_m": float(np.median(sig)), "ratio": ratio, "nees_k": nees}


def prior_bias_max(body="mars", t0=ee.EPOCH_1997, span=500 * 500.0, margin=1.0):
    """A prior bound on the ephemeris error from the DE421 - DE405 difference, m.

    ``d_max = margin * max |dr_E|`` over ``[t0, t0 + span]``: the size of the real error
    the paper's truth (DE421) and filter (DE405) differ by. A mission would take it from
    the ephemeris' published uncertainty; the difference of two ephemerides is the
    customary proxy.

    Parameters
    ----------
    body : {"earth", "mars"}
    t0 : float
        Start, s TDB past J2000 (default 1997-01-01).
    span : float
        Length, s (default: the paper's Mars run, 500 steps of 500 s).
    margin : float
        Factor ``>= 1`` applied to the maximum.

    Returns
    -------
    float

    Examples
    --------
    >>> 1000.0 < prior_bias_max("mars") < 1500.0
    True
    """
    margin = check_real("margin", margin, 1.0, 100.0)
    return margin * ee.error_summary(body, t0, span)["max_m"]


def coverage_over_seeds(name="rkf", seeds=(0, 1, 2, 3), body="mars", error="growing", size=None,
                        n_steps=500, rkf_bias="residual", bias_max=None, k=K_SIGMA, skip=SKIP,
                        **filter_kwargs):
    """:func:`bound_coverage` over seeds: does the filter's ``P`` (the RKF's ``Sigma``) bound its error?

    Each seed draws one scenario (:func:`xnavlab.robust.filters.simulate`) and the initial
    error (``rng=seed``); the statistics pool the kept epochs of all seeds.

    Parameters
    ----------
    name : {"ukf", "asukf", "tdukf", "rkf"}
    seeds : sequence of int
    body, error, size, n_steps : optional
        The scenario (default: the paper's Mars case, an error growing from 0 to 50 km over
        500 steps of 500 s along (1, 1, 1)/sqrt(3)); ``size`` defaults to 5e4 m for an
        injected error and is refused with another (the real error has its own size).
    rkf_bias : {"residual", "oracle", "prior"}
        Source of the RKF's ``B B^T`` (:func:`xnavlab.robust.filters.run_filter`).
    bias_max : float or array_like, shape (n_steps,), optional
        ``rkf_bias="prior"``: the bound on ``|dr_E|``, m (refused with another filter or
        bias rule, which would not use it). Default: the largest true ``|dr_E|`` of the run
        (the error's known size: ``size`` for an injected error).
    k, skip
        As in :func:`bound_coverage`.
    **filter_kwargs
        Passed to :func:`xnavlab.robust.filters.run_filter` (``eps``, ``lam``, ...).

    Returns
    -------
    dict
        Pooled ``coverage``, ``median_ratio``, ``nees``, ``rmse_m``, ``median_sigma_m``;
        ``per_seed`` (list of :func:`bound_coverage` dicts without the series); ``level``
        (:data:`CHEBYSHEV_LEVEL` for ``k = 3``, ``1 - 1/k^2``).

    Examples
    --------
    >>> out = coverage_over_seeds(seeds=(0,), n_steps=60)
    >>> sorted(out)[:3]
    ['coverage', 'level', 'median_ratio']
    """
    check_choice("name", name, filters.FILTERS)
    check_choice("rkf_bias", rkf_bias, filters.RKF_BIAS)
    _check_keywords(filter_kwargs, _RUN_SETTINGS, "run_filter setting")
    seeds = check_seeds("seeds", seeds)
    n_steps = check_int("n_steps", n_steps, 2, 10**6)
    k = check_real("k", k, 1e-3)  # 1 - 1/k^2: 5e-324 divided by 0; k * k is inf, k**2 overflowed
    if size is None:
        size = 5e4 if error in ("constant", "slow", "growing") else 0.0
    if bias_max is not None and not (name == "rkf" and rkf_bias == "prior"):
        raise ValueError(f"bias_max goes with name='rkf' and rkf_bias='prior', got name={name!r}, "
                         f"rkf_bias={rkf_bias!r}; leave bias_max out")
    per, ratios, nees, sq, sig = [], [], [], [], []
    for seed in seeds:
        sc = filters.simulate(body, n_steps=n_steps, error=error, size=size, rng=seed)
        kw = dict(filter_kwargs)
        if name == "rkf":
            kw["rkf_bias"] = rkf_bias
            if rkf_bias == "prior":  # the error's known size: |dr_E| <= d_max
                kw["bias_max"] = np.linalg.norm(sc.dr_e, axis=1).max() if bias_max is None else bias_max
        c = bound_coverage(filters.run_filter(name, sc, rng=seed, **kw), sc, k, skip)
        ratios.append(c.pop("ratio"))
        nees.append(c.pop("nees_k"))
        sq.append(c["rmse_m"] ** 2)
        sig.append(c["median_sigma_m"])
        per.append(c)
    ratio = np.concatenate(ratios)
    return {"coverage": float(np.mean(ratio <= k)), "median_ratio": float(np.median(ratio)),
            "nees": float(np.mean(np.concatenate(nees))), "rmse_m": float(np.sqrt(np.mean(sq))),
            "median_sigma_m": float(np.median(sig)), "per_seed": per, "level": 1.0 - 1.0 / (k * k)}


#: The settings of run_filter that coverage_over_seeds passes on (it sets the scenario, the seed
#: and the RKF's bias rule itself).
_RUN_SETTINGS = set(inspect.signature(filters.run_filter).parameters) - {"name", "scenario", "rng",
                                                                        "rkf_bias", "bias_max"}


def _check_keywords(kwargs, valid, what):
    """Each keyword of ``kwargs`` one of ``valid``, else a ValueError naming it (a misspelt one
    was a TypeError from inside run_filter)."""
    for key, value in kwargs.items():
        if key not in valid:
            raise ValueError(f"{key}={value!r:.60} is not a {what} (they are {', '.join(sorted(valid))})")


#: The RKF's sources of ``B B^T`` compared by :func:`compare_bounds`, and the UKF for reference.
BOUND_SOURCES = ("residual", "prior", "oracle", "ukf")


def compare_bounds(seeds=(0, 1, 2, 3), sources=BOUND_SOURCES, **scenario):
    """:func:`coverage_over_seeds` for each source of ``B B^T`` (and the UKF), one row each.

    Parameters
    ----------
    seeds : sequence of int
    sources : sequence of str
        Any of :data:`BOUND_SOURCES` (``"ukf"``: the UKF's own covariance).
    **scenario
        ``body``, ``error``, ``size``, ``n_steps``, ``bias_max``, ``eps``, ... as in
        :func:`coverage_over_seeds`.

    Returns
    -------
    list of dict
        ``source``, ``coverage``, ``median_ratio``, ``nees``, ``rmse_m``,
        ``median_sigma_m``, ``is_bound`` (coverage at least the Chebyshev level and mean NEES
        at most 3).

    Examples
    --------
    >>> rows = compare_bounds((0,), ("residual", "prior"), n_steps=60)
    >>> [r["source"] for r in rows]
    ['residual', 'prior']
    """
    rows = []
    _check_keywords(scenario, _RUN_SETTINGS | set(inspect.signature(coverage_over_seeds).parameters)
                    - {"name", "seeds", "rkf_bias", "filter_kwargs"}, "setting of coverage_over_seeds")
    sources = check_items("sources", sources, "source",
                          lambda label, s: check_choice(label, s, BOUND_SOURCES))
    for src in sources:
        if src == "ukf":
            kw = {k: v for k, v in scenario.items() if k not in ("bias_max", "eps", "lam")}
            out = coverage_over_seeds("ukf", seeds, **kw)
        else:  # bias_max is the prior row's (refused by another bias rule)
            kw = {k: v for k, v in scenario.items() if k != "bias_max" or src == "prior"}
            out = coverage_over_seeds("rkf", seeds, rkf_bias=src, **kw)
        rows.append({"source": src, **{k: out[k] for k in ("coverage", "median_ratio", "nees",
                                                            "rmse_m", "median_sigma_m")},
                     "is_bound": out["coverage"] >= out["level"] and out["nees"] <= 3.0})
    return rows
