"""xnavlab.core.distributions against scipy.stats, the witness; and what importing it spares.

The functions call the scipy.special routines scipy.stats calls for the same laws, so today
they agree bit for bit (checked when the module was written: every threshold of the package
came out unchanged). The tests allow 1e-12 relative, so that a scipy release that reorders
a formula inside scipy.stats does not fail them, while a wrong law or argument order would.
"""

import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy import stats

from xnavlab.core import distributions as dist

PROBS = st.floats(1e-12, 1.0 - 1e-12)
DOFS = st.floats(1.0, 500.0)   # DOF_RANGE starts at 1 (a law of at least one term)
X = st.floats(-40.0, 40.0)


def close(a, b):
    return np.allclose(a, b, rtol=1e-12, atol=0.0)


@given(X)
def test_normal_tails_equal_scipy(x):
    assert close(dist.norm_cdf(x), stats.norm.cdf(x))
    assert close(dist.norm_sf(x), stats.norm.sf(x))


@given(PROBS)
def test_normal_quantiles_equal_scipy(p):
    assert close(dist.norm_ppf(p), stats.norm.ppf(p))
    assert close(dist.norm_isf(p), stats.norm.isf(p))


@given(PROBS, DOFS)
def test_chi_square_quantiles_equal_scipy(p, dof):
    assert close(dist.chi2_ppf(p, dof), stats.chi2.ppf(p, dof))
    assert close(dist.chi2_isf(p, dof), stats.chi2.isf(p, dof))


@given(st.floats(0.3, 0.999999), st.integers(1, 400))
def test_student_quantile_equals_scipy(q, dof):
    assert close(dist.t_ppf(q, dof), stats.t.ppf(q, dof))


def test_chi_square_cdf_elementwise_like_scipy():
    x = np.array([[-3.0, 0.0, 1e-3], [2.5, 40.0, np.inf]])
    for dof in (1, 2, 7.5):
        ours = dist.chi2_cdf(x, dof)
        assert ours.shape == x.shape
        assert np.allclose(ours, stats.chi2(dof).cdf(x), rtol=1e-12, atol=0.0)
    assert dist.chi2_cdf(-1.0, 3) == 0.0


@pytest.mark.parametrize(("call", "name"), [
    (lambda: dist.norm_ppf(0.0), "q"),
    (lambda: dist.norm_isf(1.0), "p"),
    (lambda: dist.chi2_isf(0.05, 0), "dof"),
    (lambda: dist.chi2_ppf(float("nan"), 3), "q"),
    (lambda: dist.t_ppf(0.975, -1), "dof"),
    (lambda: dist.norm_cdf(float("inf")), "x"),
    (lambda: dist.chi2_cdf([1.0], "three"), "dof"),
    (lambda: dist.chi2_cdf(1.0, 5e-324), "dof"),     # was NaN: dof / 2 underflowed
    (lambda: dist.chi2_isf(0.05, 0.5), "dof"),       # DOF_RANGE starts at 1
    (lambda: dist.t_ppf(0.5, 5e-324), "dof"),
    (lambda: dist.t_ppf(5e-324, 31), "q"),           # was inf: below T_Q_MIN
    (lambda: dist.t_ppf(1e-201, 3), "q"),
])
def test_bad_input_named_with_its_range(call, name):
    # a range when there is one; an unbounded number is "a finite real number", never [-inf, inf]
    with pytest.raises(ValueError, match=rf"^{name} must be a (real number in|finite real number)"):
        call()


def imported_after(modules, watched):
    """Which of ``watched`` a fresh interpreter holds after importing ``modules``."""
    code = (f"import sys; import {', '.join(modules)}; "
            f"print(sorted(m for m in {tuple(watched)!r} if m in sys.modules))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120, check=True)
    return done.stdout.strip()


def test_the_detectors_and_chapters_modules_do_not_import_scipy_stats():
    # scipy.stats costs about a second to import; these modules are what a chapter, the CLI's
    # run and a campaign worker import (the distributions above replace it)
    modules = ("xnavlab.mars.navigation.plots", "xnavlab.mars.studies.trials", "xnavlab.mars.studies.roc",
               "xnavlab.core.detection", "xnavlab.core.montecarlo", "xnavlab.plins",
               "xnavlab.attitude", "xnavlab.robust", "xnavlab.mars.navigation.headline", "xnavlab.cli")
    assert imported_after(modules, ("scipy.stats", "scipy.optimize")) == "[]"


def test_the_mars_run_and_the_detectors_import_no_scipy_special():
    # scipy.special (0.25 s) is imported when a quantile is first asked for, not before: these
    # modules do not import it, beyond what PyWavelets (the wavelet detector's) loads itself.
    # PyWavelets 1.8, the last release for Python 3.10, imports scipy.fft and so scipy.special
    # when it is imported; 1.9 (Python 3.11 on) does not: "[]" there.
    modules = ("xnavlab.mars.navigation.scenarios", "xnavlab.core.detection",
               "xnavlab.mars.faults.fault_tolerance")
    pywavelets_own = imported_after(("pywt",), ("scipy.special",))
    assert imported_after(modules, ("scipy.special",)) == pywavelets_own


def test_chi2_cdf_refuses_nan_and_complex_as_norm_cdf_does():
    """Review 35 D.12: chi2_cdf(nan) returned nan where norm_cdf(nan) is refused."""
    for x in (np.nan, [1.0, np.nan]):
        with pytest.raises(ValueError, match=r"^x must hold real numbers in \[-inf, inf\], got NaN"):
            dist.chi2_cdf(x, 3)
    with pytest.raises(ValueError, match="^x must be a finite real number"):
        dist.norm_cdf(np.nan)
    with pytest.raises(ValueError, match="^x must hold real numbers"):
        dist.chi2_cdf([1.0 + 1j], 3)
