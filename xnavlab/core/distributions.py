"""Tail probabilities and quantiles of the normal, chi-square and Student t laws, no ``scipy.stats``.

The detectors' thresholds need a handful of these numbers (a chi-square gate for a false-alarm
rate, a normal quantile for a Bonferroni split). ``scipy.stats`` would give them too, but
importing it costs about a second, which every chapter, every ``python -m xnavlab`` call and
every worker of a campaign paid before the first line of its own work. Each function here
calls the ``scipy.special`` routine that ``scipy.stats`` itself calls for the same law
(scipy's ``norm_gen``, ``chi2_gen`` and ``t_gen``), so the numbers are the same;
``tests/core/test_distributions.py`` holds them against ``scipy.stats``.

Probabilities are plain numbers in (0, 1); ``dof`` is the law's degrees of freedom, in
[1, 1e12] (see :data:`DOF_RANGE`).
"""

from __future__ import annotations

import numpy as np

from xnavlab.core.validate import check_finite_array, check_real

__all__ = [
    "DOF_RANGE", "T_Q_MIN",
    "norm_cdf", "norm_sf", "norm_ppf", "norm_isf", "chi2_cdf", "chi2_ppf", "chi2_isf", "t_ppf",
]


def _special():
    # imported on first use: scipy.special takes 0.25 s to import, which a process that imports
    # the detectors but computes no quantile (a fault-free `run mars`) need not pay
    from scipy import special

    return special


#: The degrees of freedom these functions take. 1: a chi-square or t law here counts
#: independent terms (the m components of a NIS, the n - 1 of a mean over n runs), at least
#: one; below it ``t_ppf`` has no finite tail (``dof = 5e-324`` gave NaN and inf). 1e12: more
#: terms than any campaign sums, where both laws equal their normal limit to double precision.
DOF_RANGE = (1.0, 1e12)

#: The smallest tail probability :func:`t_ppf` takes: scipy's ``stdtrit`` returns inf (not the
#: huge finite quantile) below about 1e-250 for dof near 2 and 3, and ``t_ppf(5e-324, 31)`` was
#: inf; 1e-200 is answered finitely for every dof in :data:`DOF_RANGE` and is far beyond any
#: confidence level.
T_Q_MIN = 1e-200


def _prob(name, p):
    return check_real(name, p, 0.0, 1.0, lo_open=True, hi_open=True)


def _dof(dof):
    return check_real("dof", dof, *DOF_RANGE)


def norm_cdf(x):
    """``P(X <= x)`` for ``X ~ N(0, 1)``.

    Examples
    --------
    >>> round(norm_cdf(1.959963984540054), 6)
    0.975
    """
    return float(_special().ndtr(check_real("x", x)))   # Phi(x)


def norm_sf(x):
    """``P(X > x)`` for ``X ~ N(0, 1)``, accurate far in the tail (no ``1 - Phi(x)``).

    Examples
    --------
    >>> f"{norm_sf(6.0):.3e}"
    '9.866e-10'
    """
    return float(_special().ndtr(-check_real("x", x)))   # 1 - Phi(x) = Phi(-x)


def norm_ppf(q):
    """The ``q`` quantile of ``N(0, 1)``: ``x`` with ``P(X <= x) = q``, ``0 < q < 1``.

    Examples
    --------
    >>> round(norm_ppf(0.75), 6)   # the MAD's scale for a normal law
    0.67449
    """
    return float(_special().ndtri(_prob("q", q)))   # Phi^-1(q)


def norm_isf(p):
    """The upper ``p`` point of ``N(0, 1)``: ``x`` with ``P(X > x) = p``, ``0 < p < 1``.

    Examples
    --------
    >>> round(norm_isf(0.025), 4)
    1.96
    """
    return float(-_special().ndtri(_prob("p", p)))   # Phi^-1(1 - p) = -Phi^-1(p)


def chi2_cdf(x, dof):
    """``P(X <= x)`` for ``X ~ chi2(dof)``, elementwise; 0 for ``x <= 0``.

    Parameters
    ----------
    x : float or array_like
        Where to evaluate (any shape), real numbers in [-inf, inf] (``inf`` gives 1); NaN is
        refused, as :func:`norm_cdf` refuses it (a NaN probability would pass any test
        against it silently).
    dof : float
        Degrees of freedom, in [1, 1e12] (:data:`DOF_RANGE`).

    Returns
    -------
    ndarray, shape of ``x``

    Examples
    --------
    >>> chi2_cdf([-1.0, 0.0, 7.814727903251178], 3).round(6)
    array([0.  , 0.  , 0.95])
    """
    # P(chi2_k <= x) = P(k/2, x/2), the regularised lower incomplete gamma function; it is 0 at
    # x = 0, so x <= 0 is clipped there
    x = check_finite_array("x", x, finite=False)
    if np.any(np.isnan(x)):
        raise ValueError("x must hold real numbers in [-inf, inf], got NaN")
    x = np.maximum(x, 0.0)
    return np.asarray(_special().chdtr(_dof(dof), x))


def chi2_ppf(q, dof):
    """The ``q`` quantile of ``chi2(dof)``: ``x`` with ``P(X <= x) = q``, ``0 < q < 1``.

    Examples
    --------
    >>> round(chi2_ppf(0.025, 2), 6)   # the lower end of a Garwood interval for 0 events
    0.050636
    """
    return float(2.0 * _special().gammaincinv(_dof(dof) / 2.0, _prob("q", q)))   # P(k/2, x/2) = q


def chi2_isf(p, dof):
    """The upper ``p`` point of ``chi2(dof)``: ``x`` with ``P(X > x) = p``, ``0 < p < 1``.

    The gate of a chi-square (NIS) test with false-alarm rate ``p`` per test.

    Examples
    --------
    >>> round(chi2_isf(0.05, 3), 4)
    7.8147
    """
    return float(_special().chdtri(_dof(dof), _prob("p", p)))   # Q(k/2, x/2) = p


def t_ppf(q, dof):
    """The ``q`` quantile of Student's t law with ``dof`` degrees of freedom.

    ``q`` is in ``[1e-200, 1)`` (:data:`T_Q_MIN`: below it scipy's inverse answers inf) and
    ``dof`` in [1, 1e12] (:data:`DOF_RANGE`).

    Examples
    --------
    >>> round(t_ppf(0.975, 31), 4)   # the 95 % interval of a mean over 32 runs
    2.0395
    """
    q = check_real("q", q, T_Q_MIN, 1.0, hi_open=True)
    return float(_special().stdtrit(_dof(dof), q))   # F_t^-1(q)
