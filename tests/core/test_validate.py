"""Argument checks: messages name the parameter and the allowed range."""

import functools
import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from xnavlab.core.validate import (
    check_bool,
    check_choice,
    check_covariance,
    check_definite,
    check_evenly_spaced,
    check_finite_array,
    check_int,
    check_items,
    check_keywords,
    check_real,
    check_records,
    check_seed,
    check_seeds,
    make_rng,
    seed_after,
)


def test_check_real():
    assert check_real("x", 1, 0, 2) == 1.0
    for bad in (math.nan, math.inf, "1", None, True, -0.1):
        with pytest.raises(ValueError, match=r"x must be a real number in \[0, 2\]"):
            check_real("x", bad, 0, 2)
    with pytest.raises(ValueError, match=r"\(0, inf\)"):
        check_real("x", 0.0, 0.0, lo_open=True, hi_open=True)


def test_check_int():
    assert check_int("n", np.int64(3), 1, 5) == 3
    for bad in (2.5, "3", True, 0, 6):
        with pytest.raises(ValueError, match=r"n must be an integer in \[1, 5\]"):
            check_int("n", bad, 1, 5)


def test_check_finite_array():
    assert check_finite_array("r", [[1, 2, 3]], shape=(3,)).shape == (1, 3)
    with pytest.raises(ValueError, match="finite"):
        check_finite_array("r", [1, np.nan, 3])
    with pytest.raises(ValueError, match=r"trailing shape \(\.\.\., 3\)"):
        check_finite_array("r", [1, 2], shape=(3,))
    with pytest.raises(ValueError, match="array of finite numbers"):
        check_finite_array("r", ["a", "b"])


def test_check_choice():
    with pytest.raises(ValueError, match="kind must be one of 'a', 'b'"):
        check_choice("kind", "c", ("a", "b"))


def test_make_rng():
    g = np.random.default_rng(5)
    assert make_rng(g) is g
    assert make_rng(None).integers(1 << 30) == make_rng(0).integers(1 << 30)
    with pytest.raises(ValueError, match="^rng must be a numpy Generator or an integer seed"):
        make_rng(-1)
    with pytest.raises(ValueError, match="seed"):
        make_rng("x")


# ---- issue 35: every input used or refused --------------------------------------------------

def test_a_range_is_the_real_one_never_minus_inf_to_inf():
    with pytest.raises(ValueError, match=r"^x must be a finite real number, got nan$"):
        check_real("x", math.nan)
    with pytest.raises(ValueError, match=r"^x must be a real number in \[0, inf\), got -1$"):
        check_real("x", -1, 0.0)
    with pytest.raises(ValueError, match=r"^n must be an integer in \[1, inf\), got 0$"):
        check_int("n", 0, 1)
    with pytest.raises(ValueError, match=r"in \[0, 9223372036854775807\], got -1$"):
        check_int("seed", -1, 0, 2**63 - 1)                 # exact, not 9.22337e+18
    with pytest.raises(ValueError, match=r"got 2.5$"):         # a numpy scalar shown plainly
        check_int("n", np.float64(2.5), 0, 5)


@pytest.mark.parametrize("bad", [[1.0, 2.0 + 1e-9j], np.array([1.0 + 1j]), [np.complex128(1)]])
def test_complex_numbers_are_refused_not_cut_to_their_real_part(bad):
    with pytest.raises(ValueError, match="^z must hold real numbers, got complex values"):
        check_finite_array("z", bad)
    with pytest.raises(ValueError, match="^z must be a finite real number"):
        check_real("z", complex(1, 1))


@pytest.mark.parametrize("bad", ["3.0", ["1", "2"], [True, False], [None], [[1.0], [2.0, 3.0]]])
def test_text_flags_and_ragged_lists_are_not_numbers(bad):
    with pytest.raises(ValueError, match="^r must be an array of finite numbers"):
        check_finite_array("r", bad)


def test_finite_false_lets_nan_through_but_not_complex():
    assert np.isnan(check_finite_array("x", [np.nan, 1.0], finite=False)[0])
    with pytest.raises(ValueError, match="complex"):
        check_finite_array("x", [1j], finite=False)


@pytest.mark.parametrize(("matrix", "words"), [
    ([[1.0, 2.0], [2.0, 1.0]], r"^S must be positive definite, but it is indefinite \(smallest"),
    ([[1.0, 1.0], [1.0, 1.0]], r"^S must be positive definite, but it is singular"),
    (np.diag([1.0, 0.0]), r"^S must be positive definite, but it is singular"),
    (np.diag([1.0, -1e-30]), r"^S must be positive definite, but it is indefinite"),
    ([[1.0, 0.5], [0.0, 1.0]], r"^S must be symmetric"),
    ([[1.0, 0.0, 0.0]], r"^S must be a square matrix"),
    ([[1.0, np.nan], [np.nan, 1.0]], r"^S must contain only finite numbers"),
])
def test_check_definite_names_the_matrix_and_what_is_wrong(matrix, words):
    with pytest.raises(ValueError, match=words) as err:
        check_definite("S", matrix)
    assert "\n" not in str(err.value)


def test_check_definite_takes_mixed_units_and_names_the_bad_matrix_of_a_stack():
    P = np.diag([1e12, 1e12, 1e12, 1e-6, 1e-6, 1e-6])       # m^2 beside m^2/s^2
    P[0, 3] = P[3, 0] = 0.999 * math.sqrt(1e12 * 1e-6)       # strongly correlated, not singular
    assert check_definite("P", P, 6).shape == (6, 6)
    stack = np.stack([np.eye(2)] * 3)
    stack[2] = [[1.0, 2.0], [2.0, 1.0]]
    with pytest.raises(ValueError, match=r"^P\[2\] must be positive definite, but it is indefinite"):
        check_definite("P", stack)


def test_check_items_refuses_strings_empty_lists_and_repeats():
    assert check_items("stars", ("Vega", "Sirius"), "star") == ("Vega", "Sirius")
    cases = [("Vega", r"^stars must be a list of stars, got the string 'Vega' \(write \[\"Vega\"\]\)$"),
             ((), r"^stars must name at least one star, got an empty list$"),
             (["Vega", "Deneb", "Vega"], r"^stars lists Vega twice \(items 0 and 2\)$"),
             (3.0, r"^stars must be a list of stars, got 3.0$"),
             ({"Vega": 1}, r"^stars must be a list of stars"),
             ([["Vega"]], r"^stars\[0\] must be a star"),
             # a set has no order: its items' order would follow the hash seed (review 35i)
             ({"Vega", "Deneb"}, r"^stars must be a list of stars in order \(a set has none"),
             (frozenset({"Vega"}), r"^stars must be a list of stars in order")]
    for value, words in cases:
        with pytest.raises(ValueError, match=words):
            check_items("stars", value, "star")
    with pytest.raises(ValueError, match=r"^stars\[1\] must be one of 'Vega'"):
        check_items("stars", ["Vega", "x"], "star", lambda lab, s: check_choice(lab, s, ("Vega",)))


def test_make_rng_names_the_callers_parameter():
    with pytest.raises(ValueError, match=r"^seed must be a numpy Generator or an integer seed .* got 1j$"):
        make_rng(1j, "seed")


def test_an_integer_beyond_every_float_is_refused_in_one_short_line():
    # 10**400 raised OverflowError from float() (a traceback from `scenario --check`)
    with pytest.raises(ValueError, match=r"^days must be a real number in \(0, 365\], got 1000+\.\.\.$"):
        check_real("days", 10**400, 0.0, 365.0, lo_open=True)


def test_a_nan_bound_or_tolerance_is_refused_not_a_pass():
    """Review 35 D.18: check_real('a', 1.0, nan, 2) returned 1.0 (x < nan is False)."""
    with pytest.raises(ValueError, match=r"^the range of a must have real bounds, got lo=nan"):
        check_real("a", 1.0, math.nan, 2)
    with pytest.raises(ValueError, match=r"^the range of n must have real bounds"):
        check_int("n", 1, 0, math.nan)
    from xnavlab.core.validate import check_covariance

    for bad in (math.nan, -1.0):
        with pytest.raises(ValueError, match=r"^rtol must be a real number in \[0, inf\)"):
            check_covariance("P", np.eye(2), rtol=bad)
        with pytest.raises(ValueError, match=r"^rtol must be a real number in \[0, inf\)"):
            check_definite("P", np.eye(2), rtol=bad)


def test_crossed_bounds_are_refused_not_reported_as_a_range():
    """Review 35b N17: check_real('a', 1.0, 2.0, 0.0) accepted, then said 'in [2, 0]'."""
    with pytest.raises(ValueError, match=r"^the range of a must have lo <= hi, got lo=2 > hi=0"):
        check_real("a", 1.0, 2.0, 0.0)
    with pytest.raises(ValueError, match=r"^the range of n must have lo <= hi"):
        check_int("n", 1, 3, 1)
    assert check_real("a", 1.0, 1.0, 1.0) == 1.0  # a one-point range is a range


@pytest.mark.parametrize("bad", ["no", "False", "", 0, 1, 1.0, None, [True], np.array([True])])
def test_check_bool_takes_only_real_bools(bad):
    """Review 35b N19: a truthy string ('no') was read as True."""
    with pytest.raises(ValueError, match=r"^flag must be True or False, got "):
        check_bool("flag", bad)
    assert check_bool("flag", True) is True and check_bool("flag", np.False_) is False


@pytest.mark.parametrize(("value", "words"), [
    ("abc", "rows must be a list of records (dicts), got 'abc'"),
    ({"pd": 1}, "rows must be a list of records (dicts), got {'pd': 1}"),
    (None, "rows must be a list of records (dicts), got None"),
    ([{"pd": 1}, 3], "rows[1] must be a record (a dict with pd), got 3"),
    ([{"size": 1}], "rows[0] must be a record (a dict with pd), got {'size': 1}"),
])
def test_check_records_refuses_what_is_no_list_of_records(value, words):
    with pytest.raises(ValueError) as exc:
        check_records("rows", value, ("pd",))
    assert str(exc.value) == words


def test_check_records_takes_any_list_of_dicts_and_the_empty_one():
    assert check_records("rows", ({"pd": 1},), ("pd",)) == [{"pd": 1}]
    assert check_records("rows", [], ("pd",)) == []


def test_check_seeds_gives_distinct_int_seeds_or_names_the_one_at_fault():
    assert check_seeds("seeds", np.arange(3)) == (0, 1, 2)
    assert all(type(s) is int for s in check_seeds("seeds", np.arange(2)))
    for bad, message in (([], r"^seeds must name at least one seed, got an empty list$"),
                         ("12", r"^seeds must be a list of seeds, got the string '12'"),
                         ([0, 0], r"^seeds lists 0 twice \(items 0 and 1\)$"),
                         ([0, -1], r"^seeds\[1\] must be an integer in \[0, 9223372036854775807\]"),
                         ([2**63], r"^seeds\[0\] must be an integer in"),
                         ([1.0], r"^seeds\[0\] must be an integer"),
                         ([True], r"^seeds\[0\] must be an integer")):
        with pytest.raises(ValueError, match=message):
            check_seeds("seeds", bad)
    assert check_seeds("s", [5], min_len=1) == (5,)


def test_check_seed_and_seed_after_stay_in_the_range_every_record_stores():
    """Review 35e: a seed above 2^63 - 1 passed several checks, and a derived seed + 1 of the
    last seed was refused under the name rng."""
    assert check_seed("seed", np.int64(5)) == 5
    for bad in (-1, 2**63, 1.0, True, "3"):
        with pytest.raises(ValueError, match=r"^seed must be an integer in \[0, 9223372036854775807\]"):
            check_seed("seed", bad)
    assert seed_after(0) == 1 and seed_after(2**63 - 1) == 0 and seed_after(2**63 - 2, 2) == 0
    with pytest.raises(ValueError, match=r"^seed must be an integer in"):
        seed_after(2**63)


@pytest.mark.parametrize("value", [[1.0, True], (0.0, [2.0, np.True_]), [[True, 0.0], [0.0, 1.0]]])
def test_a_bool_among_numbers_is_refused_not_read_as_one(value):
    # review 35g: [..., true] in a scenario file's state0 became 1.0 m/s without a word
    with pytest.raises(ValueError, match=r"^x must be an array of finite numbers, got "):
        check_finite_array("x", value)


@given(arrays(np.float64, (3, 3), elements=st.floats(-1.7e308, 1.7e308)))
def test_check_covariance_judges_any_finite_matrix_without_a_warning(m):
    """Entries near 1e308 made arr + arr.T overflow (a RuntimeWarning, then an eigenvalue of
    inf): the check now works on the matrix scaled by a power of two."""
    for definite in (False, True):
        try:
            out = check_covariance("P", m, definite=definite)
        except ValueError as exc:
            assert str(exc).startswith("P must be"), exc
        else:
            assert out is not None and np.all(np.isfinite(out))


def test_check_covariance_scales_exactly():
    """The scaling is by a power of two: the verdicts of a matrix and of it times 2^k agree."""
    m = np.diag([2.0, 0.0])  # singular exactly (no rounding-level eigenvalue): not definite
    for k in (-900, 0, 900):
        check_covariance("P", np.ldexp(m, k))
        with pytest.raises(ValueError, match="^P must be positive definite"):
            check_covariance("P", np.ldexp(m, k), definite=True)
    with pytest.raises(ValueError, match=r"^P must be positive semi-definite, got smallest "
                                         r"eigenvalue -1e\+308"):
        check_covariance("P", -1e308 * np.eye(3))


def test_check_evenly_spaced_names_the_step_that_deviates_most():
    """Review 35j (5) 20: the shared check for evenly spaced times (combined_detect)."""
    t = 3.0 * np.arange(10)
    assert check_evenly_spaced("t", t, 0.01) is t
    assert check_evenly_spaced("t", t[:1], 0.01).size == 1        # one sample: no step
    t2 = t.copy()
    t2[4] += 0.6
    t2[7] += 0.3
    with pytest.raises(ValueError, match=r"^t must be evenly spaced \(each step within 0.01 of the "
                                         r"median step, 3 s\), got t\[4\] - t\[3\] = 3.6 s \(0.2 off\)"):
        check_evenly_spaced("t", t2, 0.01)
    assert check_evenly_spaced("t", t2, 0.25) is t2
    with pytest.raises(ValueError, match=r"^rtol must be"):
        check_evenly_spaced("t", t, -1.0)


def test_check_keywords_names_a_keyword_passed_on():
    """Review 35j (1) 2-4, 10-11: the shared check of keywords passed on to another function."""
    def target(t, x, *, level=5, pfa=1e-5):
        return level

    def open_target(**kw):
        return kw

    assert check_keywords("f", None, target) == {}
    assert check_keywords("f", {"level": 3}, target) == {"level": 3}
    assert check_keywords("f", {"whatever": 3}, open_target) == {"whatever": 3}
    assert check_keywords("f", {"whatever": 3}, max) == {"whatever": 3}   # no signature to read
    with pytest.raises(ValueError, match=r"^whatever is not a keyword of f or of len, .* of len are none$"):
        check_keywords("f", {"whatever": 3}, len)                   # positional only
    with pytest.raises(ValueError, match=r"^levle is not a keyword of f or of target, which f passes "
                                         r"its other keywords on to: those of target are t, x, level, pfa "
                                         r"\(did you mean level\?\)"):
        check_keywords("f", {"levle": 3}, target)
    with pytest.raises(ValueError, match=r"^f_kw\['zz'\] is not a keyword of target \(f passes f_kw "
                                         r"on to it\): the valid ones are level, pfa$"):
        check_keywords("f", {"zz": 3}, target, name="f_kw",
                       set_here={"t": "its t", "x": "its x"})
    with pytest.raises(ValueError, match=r"^f_kw\['pfa'\] is set by f \(from the design\): leave it out"):
        check_keywords("f", {"pfa": 3}, target, name="f_kw", set_here={"pfa": "from the design"})
    with pytest.raises(ValueError, match=r"^lvl is not a keyword f takes: the valid ones are a, b$"):
        check_keywords("f", {"lvl": 1}, ("a", "b"))
    for bad in ([("level", 3)], {3: 1}, "level=3"):
        with pytest.raises(ValueError, match=r"^f_kw must be a dict of keyword arguments"):
            check_keywords("f", bad, target, name="f_kw")


# -------------------------------------------------------------------- review 35m (5) 1, (2) 1


@given(st.integers(1, 4), st.integers(1, 5), st.data())
def test_a_masked_entry_is_refused_naming_the_argument_and_the_first_one(rows, cols, data):
    """Review 35m (5) 1: np.asarray dropped the mask, so the masked values were used as data."""
    mask = data.draw(arrays(np.bool_, (rows, cols)).filter(np.any))
    first = ", ".join(str(int(i)) for i in np.unravel_index(np.argmax(mask), mask.shape))
    value = np.ma.masked_array(np.ones((rows, cols)), mask=mask)
    with pytest.raises(ValueError, match=rf"^P has masked entries: {mask.sum()} of {mask.size}, "
                                         rf"the first P\[{first}\] \(no number to use"):
        check_finite_array("P", value)


@pytest.mark.parametrize("value", [[np.ma.masked_array([1.0, 2.0], mask=[True, False]), [3.0, 4.0]],
                                   [1.0, np.ma.masked], (True, np.ma.masked), [[0.0], [np.ma.masked]]])
def test_a_masked_entry_inside_a_list_is_refused_without_numpys_warning(value):
    """Review 35m (5) 1: a list of masked arrays lost its masks in np.asarray; np.ma.masked in a
    list was converted to NaN with a UserWarning (an error under the tests' filterwarnings)."""
    with pytest.raises(ValueError, match=r"^x has masked entries \(no number to use"):
        check_finite_array("x", value)


def test_the_masked_constant_is_named_without_an_empty_index():
    """Review 35n: check_finite_array("x", np.ma.masked) named its entry x[]."""
    with pytest.raises(ValueError, match=r"^x is masked \(no number to use\)$"):
        check_finite_array("x", np.ma.masked)


def test_an_unmasked_masked_array_and_a_matrix_are_used_as_their_data():
    """Review 35m pattern N: a numpy.ma array with no masked entry is its data; np.matrix its
    2-D array (a plain ndarray, so that ``*`` stays elementwise)."""
    m = np.arange(6.0).reshape(2, 3)
    with pytest.warns(PendingDeprecationWarning):  # numpy's own, at the user's np.asmatrix
        matrix = np.asmatrix(m)
    for value in (np.ma.masked_array(m), np.ma.masked_array(m, mask=np.zeros(m.shape, bool)),
                  matrix, [np.ma.masked_array(m[0]), m[1]]):
        out = check_finite_array("x", value)
        assert type(out) is np.ndarray and np.array_equal(out, m)


def test_a_read_only_array_is_copied_and_a_writable_float64_one_is_not():
    """Review 35m (2) 1: a read-only array reached PyWavelets ("buffer source array is read-only")
    and the numba kernels (a new compilation); the common path still makes no copy."""
    x = np.arange(6.0).reshape(2, 3)
    assert check_finite_array("x", x) is x
    assert np.shares_memory(check_finite_array("x", x[:, ::2]), x)  # strided: a view, as it is
    ro = x.copy()
    ro.setflags(write=False)
    out = check_finite_array("x", ro)
    assert out.flags.writeable and out.flags.c_contiguous and np.array_equal(out, x)
    big = check_finite_array("x", x.astype(">f8"))
    assert big.dtype == np.float64 and big.dtype.isnative and np.array_equal(big, x)


def _carriers(v):
    """The kinds of the same float array a caller may hold (review 35m mode c), by name."""
    ro = v.copy()
    ro.setflags(write=False)
    out = {"unmasked np.ma": np.ma.masked_array(v.copy()), "read-only": ro,
           "big-endian": v.astype(">f8"), "strided": np.repeat(v, 2, axis=-1)[..., ::2]}
    if v.ndim == 2:
        with pytest.warns(PendingDeprecationWarning):
            out["np.matrix"] = np.asmatrix(v)
    return out


@functools.cache
def _public_calls():
    """(label, function, {argument: array}, other keywords, result -> array, numba kernel or None)."""
    from xnavlab.attitude import _bank_kernel, simulation
    from xnavlab.core import filters, quaternions
    from xnavlab.core.detection import chisquare, mallat
    from xnavlab.mars.models import dynamics, force_models
    from xnavlab.mars.timing import photon_fix

    def same(r):
        return np.asarray(r, dtype=float)

    nu = np.random.default_rng(5).normal(0.0, 5000.0, 200)
    cfg = simulation.SimConfig(duration=50.0)
    _, wg, qs = simulation.simulate_sensors(cfg)
    return [
        ("nees", filters.nees, {"err": np.array([1.0, 2.0]), "P": np.diag([1.0, 4.0])}, {}, same, None),
        ("nis", filters.nis, {"nu": np.array([3.0, 1.0]), "S": np.array([[9.0, 1.0], [1.0, 4.0]])},
         {}, same, None),
        ("chi2_detect", chisquare.chi2_detect,
         {"t": 3.0 * np.arange(200), "nu": nu, "S": np.full(200, 5000.0**2)}, {},
         lambda d: np.r_[d.ratio, d.alarm], None),
        ("quat_to_rotvec", quaternions.quat_to_rotvec,
         {"q": quaternions.quat_from_rotvec([0.1, -0.2, 0.3])}, {}, same, None),
        ("quat_product", quaternions.quat_product,
         {"p": np.array([0.0, 0.0, 0.6, 0.8]), "q": np.array([[0.6, 0.0, 0.0, 0.8]] * 2)}, {}, same, None),
        ("detail_signals", mallat.detail_signals,
         {"x": np.random.default_rng(2).normal(size=200)}, {}, lambda r: np.vstack([r[0], r[1]]), None),
        ("acceleration", lambda r: force_models.acceleration(dynamics.MARS_T0, r),
         {"r": dynamics.MARS_STATE0[:3].copy()}, {}, same, force_models._accel_many),
        ("diagnose_batch", lambda omega_g, q_meas: simulation.diagnose_batch(omega_g, q_meas, cfg),
         {"omega_g": wg[None], "q_meas": qs[None]}, {}, lambda r: r["sos_r"], _bank_kernel._bank),
        ("template_density", photon_fix.template_density,
         {"coeffs": np.array([0.5, 0.1]), "phases": np.array([0.0, 0.25, 0.5])}, {}, same, None),
    ]


LABELS = ("nees", "nis", "chi2_detect", "quat_to_rotvec", "quat_product", "detail_signals",
          "acceleration", "diagnose_batch", "template_density")


@pytest.mark.parametrize("case", LABELS)
def test_masked_and_read_only_arrays_are_refused_or_give_the_same_result(case):
    """Review 35m (5) 1, (2) 1, pattern N: across modules, a masked entry is refused naming the
    argument; the unmasked, read-only, big-endian, strided and matrix kinds of the same array
    give the same result (to rounding), and a read-only one compiles no new numba specialization (it ran
    past 6 s in acceleration and diagnose_batch)."""
    label, fn, args, kw, key, kernel = _public_calls()[LABELS.index(case)]
    assert label == case
    base = key(fn(**args, **kw))
    n_compiled = len(kernel.signatures) if kernel is not None else 0
    for name, v in args.items():
        masked = np.ma.masked_array(v.copy())
        masked[np.unravel_index(v.size - 1, v.shape)] = np.ma.masked
        with pytest.raises(ValueError, match=rf"^{name} has masked entries"):
            fn(**{**args, name: masked}, **kw)
        for kind, carrier in _carriers(v).items():
            got = key(fn(**{**args, name: carrier}, **kw))
            # to rounding: a strided array may take another BLAS/einsum path (diagnose_batch)
            scale = float(np.abs(base).max())
            assert np.allclose(got, base, rtol=0.0, atol=1e-12 * scale), f"{label}({name}=<{kind}>)"
    if kernel is not None:
        assert len(kernel.signatures) == n_compiled, f"{label}: a new specialization compiled"


# Review 35 Q1, Q9, Q18: dates, durations and quantities; every item of an object array; one line.

@pytest.mark.parametrize(("value", "got"), [
    (np.array(["2020-01-01T00:00:00"], dtype="datetime64[s]"),
     r"datetime64\[s\] values: a date is no number"),
    (np.datetime64("2020-01-01"), r"datetime64\[D\] values: a date is no number"),
    (np.array([0, 1000], dtype="timedelta64[ms]"),
     r"timedelta64\[ms\] values: convert them \(t / np.timedelta64\(1, 's'\) gives seconds\)"),
])
def test_check_finite_array_refuses_dates_and_durations(value, got):
    """A datetime64 array was read as seconds since 1970 (2020 as the year 2050 past J2000), a
    timedelta64[ms] one as seconds: refused, naming the unit the parameter documents."""
    with pytest.raises(ValueError, match=rf"^t must be plain numbers in s TDB past J2000, got {got}"):
        check_finite_array("t", value, unit="s TDB past J2000")
    with pytest.raises(ValueError, match=r"^t must be plain numbers in the SI unit its function documents"):
        check_finite_array("t", value)


def test_check_finite_array_refuses_pandas_dates():
    """A pandas datetime Series (nanoseconds since 1970) and a time-zone aware one (Timestamps)."""
    pd = pytest.importorskip("pandas")
    naive = pd.Series(pd.to_datetime(["2020-01-01", "2020-01-02"]))
    with pytest.raises(ValueError, match=r"^t must be plain numbers .*, got datetime64\[(ns|us)\] values"):
        check_finite_array("t", naive)
    with pytest.raises(ValueError, match=r"^t must be plain numbers .*, got date values: a date is no "
                                         r"number"):
        check_finite_array("t", naive.dt.tz_localize("UTC"))


def test_check_finite_array_refuses_quantities():
    """An astropy Quantity was taken as its number in its own unit (90 deg as 90 rad, 1 day as
    1 s); as an array, in a list or in an object array, it is refused with its unit named."""
    u = pytest.importorskip("astropy.units")
    want = r"^phi must be plain numbers in the SI unit its function documents, got a Quantity in deg: " \
           r"its unit is not read; convert it \(phi.si.value gives SI numbers\)$"
    for value in (np.array([90.0, 0.0, 0.0]) * u.deg, [90.0 * u.deg, 0.0 * u.deg],
                  np.array([1.0, 90.0 * u.deg], dtype=object)):
        with pytest.raises(ValueError, match=want):
            check_finite_array("phi", value)
    with pytest.raises(ValueError, match=r"got a dimensionless Quantity: its unit is not read"):
        check_finite_array("x", [1.0 * u.one, 2.0 * u.one])
    with pytest.raises(ValueError, match=r"^t must be a finite real number, got datetime.timedelta"):
        check_real("t", np.timedelta64(5, "s"))  # an integer to numpy: float() failed on it
    with pytest.raises(ValueError, match=r"^n must be an integer, got datetime.timedelta"):
        check_int("n", np.timedelta64(5, "s"))


def test_check_finite_array_scans_every_item_of_an_object_array():
    """Review 35 Q9: a bool past the 10,000th item of an object array was read as 1.0."""
    for odd in (True, np.True_):
        with pytest.raises(ValueError, match=r"^x must be an array of finite numbers, got array\(\[0.5"):
            check_finite_array("x", np.array([0.5] * 10_001 + [odd], dtype=object))
    with pytest.raises(ValueError, match=r"^x must hold real numbers, got complex values"):
        check_finite_array("x", np.array([0.5] * 10_001 + [1j], dtype=object))
    with pytest.raises(ValueError, match=r"^x must be an array of finite numbers, got an object array"):
        check_finite_array("x", np.array([0.5, 10**400], dtype=object))
    ok = check_finite_array("x", np.array([0.5] * 10_001 + [1], dtype=object))
    assert ok.dtype == np.float64 and ok[-1] == 1.0


def test_messages_are_one_line():
    """Review 35 Q18: a SeedSequence's repr and a 2-D array's spanned several lines."""
    from xnavlab.core.validate import shown

    seq = np.random.SeedSequence(0)
    with pytest.raises(ValueError, match=r"^seed must be an integer in \[0, 9223372036854775807\], got "
                                         r"SeedSequence\( entropy=0, \): pass an int seed$"):
        check_seed("seed", seq)
    with pytest.raises(ValueError, match=r"got SeedSequence\( entropy=0, \): pass an int seed \(or a "
                                         r"Generator: np.random.default_rng\(seq\)\)$"):
        make_rng(seq, "seed")
    assert shown(np.ones((3, 4), dtype=bool)) == "a bool array of shape (3, 4)"
    assert shown(np.zeros(579, np.float32)) == "a float32 array of shape (579,)"
    assert shown(np.zeros(40, np.int64)) == "an int64 array of shape (40,)"
    assert shown(np.array([1.0, 2.0])) == "array([1., 2.])"  # a short array keeps its repr
    assert shown("a  b\n") == "'a  b\\n'"  # text: its repr, spaces kept
    with pytest.raises(ValueError) as err:
        check_finite_array("q", np.ones((3, 4), dtype=bool))
    assert str(err.value) == "q must be an array of finite numbers, got a bool array of shape (3, 4)"


def test_review35_r16_a_decimal_is_refused_saying_why():
    """Review 35 R16: Decimal("0.02") was refused as "not a real number"; it is refused (a
    Decimal mixes with no float, and callers may keep the raw value), saying so."""
    from decimal import Decimal
    from fractions import Fraction

    with pytest.raises(ValueError, match=r"^days must be a real number in \(0, 365\], got "
                       r"Decimal\('0\.02'\): a Decimal is not taken \(pass float\(value\)\)$"):
        check_real("days", Decimal("0.02"), 0.0, 365.0, lo_open=True)
    with pytest.raises(ValueError, match=r"^x must be a finite real number, got Decimal\('NaN'\): "
                       r"a Decimal is not taken \(pass float\(value\)\)$"):
        check_real("x", Decimal("NaN"))
    with pytest.raises(ValueError, match=r"^n must be an integer in \[1, inf\), got Decimal\('5'\): "
                       r"a Decimal is not taken \(pass int\(value\)\)$"):
        check_int("n", Decimal("5"), 1)
    assert check_real("days", Fraction(1, 50), 0.0, 365.0) == 0.02      # a Fraction is taken
    with pytest.raises(ValueError, match=r"^days must be a real number in \[0, 365\], got "
                       r"'0\.02'$"):                                      # no note for text
        check_real("days", "0.02", 0.0, 365.0)
