"""The TOA of a fold: photon-level simulation against the fold's expected error and its model."""

import math

import numpy as np
import pytest

from xnavlab.core.constants import C
from xnavlab.mars.models import dynamics
from xnavlab.mars.timing import fold_toa as ft
from xnavlab.mars.timing import timing_bound

T0, X0 = dynamics.MARS_T0, dynamics.MARS_STATE0
#: A large a-priori error (5 km, 10 m/s on each axis), so that the end tag's error (km) stands
#: far above the noise of 20 folds.
BIG = (5000.0, 5000.0, 5000.0, 10.0, 10.0, 10.0)


@pytest.fixture(scope="module")
def big_window():
    return ft.fold_window("B1821-24", T0, X0, error=BIG, phase0=0.7)


def _photon_errors(window, n, **kw):
    return np.array([ft.fold_toa(window, ft.simulate_window_photons(window, rng=i), **kw).error
                     for i in range(n)])


def test_a_perfect_apriori_gives_the_true_delay_from_photons():
    w = ft.fold_window("B1821-24", T0 + 3000.0, dynamics.truth([T0 + 3000.0])[0], phase0=0.2)
    assert abs(w.delay_change()) > 10 * w.pulsar.period    # raw photons would show no pulse
    err = _photon_errors(w, 20, search=0.1)
    crlb = timing_bound.toa_crlb("B1821-24")
    assert abs(err.mean()) < 3.0 * crlb / math.sqrt(20)
    assert 0.5 < err.std() / crlb < 1.5    # 20 folds: +-3 sigma of the scatter's estimate
    e = ft.expected_error(w)
    assert abs(e.bias) * C < 1e-3 and e.coherence == pytest.approx(1.0, abs=1e-12)
    assert e.sigma == pytest.approx(timing_bound.toa_crlb("B1821-24", nbins=555), rel=1e-6)


@pytest.mark.parametrize("tag", ["mid", "end"])
def test_the_fold_toa_from_photons_matches_its_expected_error(big_window, tag):
    expected = ft.expected_error(big_window, "apriori", tag)
    err = _photon_errors(big_window, 20, tag=tag, search=0.1)
    assert abs(err.mean() - expected.bias) < 3.0 * expected.sigma / math.sqrt(20)
    if tag == "end":   # a-priori velocity error over half the window: km, far above the noise
        assert abs(expected.bias) > 20.0 * expected.sigma / math.sqrt(20)


def test_the_expected_error_is_the_first_order_bracket(big_window):
    # the fold's ML peak and the mean of e differ by ~2 m where e moves by 9 km in the window
    # (a 10 m/s error smears the pulse by half its width); against 3.4 km at the end tag
    for tag in ("start", "mid", "end", -100.0):
        bias = ft.expected_error(big_window, "apriori", tag).bias
        first = ft.first_order_error(big_window, "apriori", tag)
        assert abs(bias - first) * C < 3.0


def test_the_mid_tag_error_is_second_order_and_linear_in_the_apriori_error():
    errors = [np.array(ft.PAPER_ERROR0) * s for s in (1.0, 0.5)]
    mid = [ft.first_order_error(ft.fold_window("B1937+21", T0, X0, error=e)) for e in errors]
    end = [ft.first_order_error(ft.fold_window("B1937+21", T0, X0, error=e), tag="end")
           for e in errors]
    assert mid[1] == pytest.approx(mid[0] / 2.0, rel=1e-2)
    assert abs(mid[0]) < abs(end[0]) / 5.0
    # the mid tag's bracket is (n . delta_a) T^2 / 24c: the gravity gradient times ~8.7 km
    # gives a few mm/s^2 along the line of sight, some tens of metres
    assert 10.0 < abs(mid[0]) * C < 100.0


def test_without_per_photon_correction_the_pulse_is_lost():
    w = ft.fold_window("B1821-24", T0, X0, phase0=0.4)
    assert ft.expected_error(w, "constant").coherence < 0.05
    assert ft.expected_error(w, "constant").bias is None
    err = _photon_errors(w, 8, correction="constant")
    # photons folded with one delay: the estimates scatter over the period, not the bound
    assert err.std() > 50.0 * timing_bound.toa_crlb("B1821-24")


def test_holding_the_spacecraft_still_biases_the_crab_by_kilometres():
    # Mars's motion per photon but the spacecraft at its tag position: the Crab's pulse
    # survives (coherence ~1) but its peak moves to where the orbit's delay is stationary
    area = 0.05   # 390,000 photons a fold instead of 7.7 million: the bias stays, the test is fast
    w = ft.fold_window("B0531+21", T0, X0, error=ft.PAPER_ERROR0, phase0=0.3)
    e = ft.expected_error(w, "mars", "mid", area_m2=area)
    assert e.coherence > 0.95 and abs(e.bias) * C > 5000.0
    err = np.array([ft.fold_toa(w, ft.simulate_window_photons(w, area, rng=i), "mars",
                                area_m2=area).error for i in range(5)])
    assert abs(err.mean() - e.bias) < 3.0 * e.sigma / math.sqrt(5)


def test_the_survey_decides_the_instantaneous_model_with_a_mid_tag_is_adequate():
    settled = ft.window_survey(error=ft.SETTLED_ERROR, n_windows=3, spacing=2750.0)
    initial = ft.window_survey(error=ft.PAPER_ERROR0, n_windows=3, spacing=2750.0)
    for s, i in zip(settled, initial, strict=True):
        assert 20.0 < s["delay_change_ms"] < 45.0 and s["orbit_change_ms"] < 5.0
        assert s["apriori_mid_m"] < 1.0 and s["apriori_end_m"] < 10.0      # settled: < 1 m
        assert i["apriori_mid_m"] < i["crlb_m"] and i["apriori_end_m"] > 5.0 * i["apriori_mid_m"]
        assert i["constant_coherence"] < 0.05
        assert s["apriori_sigma_ratio"] < 1.01
    assert [r["mars_mid_m"] is None for r in settled] == [False, True, True, True]
    assert "coherence" in ft.survey_html(settled)


def test_tags_and_inputs_are_checked(big_window):
    assert ft.tag_offset("start", 500.0) == -250.0
    with pytest.raises(ValueError, match="tag must be one of"):
        ft.tag_offset("middle", 500.0)
    with pytest.raises(ValueError, match="tag must be a real number"):
        ft.tag_offset(300.0, 500.0)
    with pytest.raises(ValueError, match="u must hold photon offsets"):
        ft.fold_toa(big_window, np.array([0.0, 260.0]))
    with pytest.raises(ValueError, match="correction must be one of"):
        big_window.processing_delay("exact")
    with pytest.raises(ValueError, match="error must"):
        ft.fold_window("B1821-24", T0, X0, error=(1.0, 2.0))


def test_the_fold_shows_the_pulse_only_after_the_per_photon_time_transfer(big_window):
    u = ft.simulate_window_photons(big_window, rng=3)
    folds = {c: ft.fold_photons(big_window, u, c, nbins=128) for c in ft.CORRECTIONS}
    for counts in folds.values():
        assert counts.shape == (128,) and counts.sum() == pytest.approx(u.size, rel=0.01)
    contrast = {c: f.max() / np.median(f) for c, f in folds.items()}
    assert contrast["apriori"] > 2.0 and max(contrast["mars"], contrast["constant"]) < 1.5
    # fold_toa measures the pulse of the same fold
    r = ft.fold_toa(big_window, u, nbins=128)
    assert abs(r.offset / big_window.pulsar.period) < 0.05
    with pytest.raises(ValueError, match="u must hold photon offsets"):
        ft.fold_photons(big_window, np.array([0.0, 260.0]))


def test_the_survey_is_cached_by_its_arguments(monkeypatch, tmp_path):
    monkeypatch.setenv("XNAVLAB_CACHE", str(tmp_path))
    args = dict(pulsar_names=["B0531+21"], n_windows=1)
    first = ft.window_survey(**args, cache=True)
    assert first == ft.window_survey(**args)
    assert len(list(tmp_path.glob("fold-survey-*.json"))) == 1
    other = ft.window_survey(**args, error=ft.SETTLED_ERROR, cache=True)  # another key
    assert other != first and len(list(tmp_path.glob("fold-survey-*.json"))) == 2
    monkeypatch.setattr(ft, "expected_error", lambda *a, **k: None)  # would fail if called
    assert ft.window_survey(**args, cache=True) == first


def test_the_survey_figure_groups_the_tags_per_pulsar():
    rows = [{"pulsar": n, "crlb_m": 100.0 * k, "apriori_mid_m": 10.0 * k,
             "apriori_end_m": 50.0 * k} for k, n in enumerate(("B0531+21", "B1937+21"), 1)]
    fig = ft.plot_survey({"initial": rows, "settled": rows})
    ax = fig.axes[0]
    assert [t.get_text() for t in ax.get_xticklabels()] == ["B0531+21", "B1937+21"]
    labels = ax.get_legend_handles_labels()[1]
    assert labels == ["Cramer-Rao bound of one TOA", "initial, mid-window tag", "initial, end tag",
                      "settled, mid-window tag", "settled, end tag"]
    heights = sorted(p.get_height() for p in ax.patches)
    assert heights == sorted([10.0, 20.0, 50.0, 100.0] * 2)
    with pytest.raises(ValueError, match="same pulsars"):
        ft.plot_survey({"a": rows, "b": rows[:1]})
    with pytest.raises(ValueError, match="at least one survey"):
        ft.plot_survey({})


def test_window_survey_cache_must_be_a_bool():  # review 35d D15
    with pytest.raises(ValueError, match="cache must be True or False, got .no."):
        ft.window_survey(pulsar_names=["B1937+21"], n_windows=1, cache="no")


def test_fold_window_names_its_own_inputs():  # review 35d D13/D14: scipy's y0, the ephemeris' t
    s0 = dynamics.MARS_STATE0
    with pytest.raises(ValueError, match=r"state_true must be a 1-D array \(shape \(6,\)\)"):
        ft.fold_window("B1937+21", dynamics.MARS_T0, s0[None])
    with pytest.raises(ValueError, match=r"t_start must lie in \[.*\(the window in DE421\)"):
        ft.fold_window("B1937+21", -1e12, s0)


def test_fold_window_refuses_a_state_faster_than_any_craft_bound_to_the_sun():  # review 35d D5
    fast = np.array([4e6, 0.0, 0.0, 9e8, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"^state_true speed must be below 65164.5 m/s"):
        ft.fold_window("B1937+21", dynamics.MARS_T0, fast)


@pytest.mark.parametrize("bad", [{}, None, "abc", 3.0])
def test_every_function_of_a_window_refuses_what_is_no_window(bad):
    # review 35d D16: first_order_error({}) gave an AttributeError
    u = np.zeros(3)
    for call in (lambda: ft.first_order_error(bad), lambda: ft.expected_error(bad),
                 lambda: ft.simulate_window_photons(bad, rng=0), lambda: ft.fold_photons(bad, u),
                 lambda: ft.fold_toa(bad, u)):
        with pytest.raises(ValueError, match=r"^window must be a FoldWindow \(from fold_window\), "
                                             r"got "):
            call()


@pytest.mark.parametrize(("rows", "words"), [
    ("abc", "rows must be a list of window_survey rows (dicts), got 'abc'"),  # D16: TypeError
    ({"pulsar": "B0531+21"}, "rows must be a list of window_survey rows"),
    (5, "rows must be a list of window_survey rows (dicts), got 5"),
    ([{"pulsar": "B0531+21"}], "rows[0] must be a window_survey row (a dict with pulsar, crlb_m"),
    ([None], "rows[0] must be a window_survey row"),
])
def test_survey_html_refuses_what_is_no_list_of_rows(rows, words):
    with pytest.raises(ValueError) as exc:
        ft.survey_html(rows)
    assert str(exc.value).startswith(words) and len(str(exc.value).splitlines()) == 1


def test_an_a_priori_inside_mars_or_too_fast_names_the_users_inputs():  # review 35d D5's class
    with pytest.raises(ValueError, match=r"^state_true \+ error speed must be below"):
        ft.fold_window("B1937+21", dynamics.MARS_T0, dynamics.MARS_STATE0,
                       error=[0.0, 0.0, 0.0, 1e8, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"^state_true \+ error position must lie outside Mars"):
        ft.fold_window("B1937+21", dynamics.MARS_T0, dynamics.MARS_STATE0,
                       error=np.concatenate([-dynamics.MARS_STATE0[:3], np.zeros(3)]))


def test_plot_survey_checks_its_surveys_and_bound():
    """Review 35e: a list of surveys was a TypeError, bound='no' marked the bound."""
    rows = [{"pulsar": "B0531+21", "crlb_m": 98.7, "apriori_mid_m": 70.3, "apriori_end_m": 888.1}]
    with pytest.raises(ValueError, match=r"^surveys must be a dict of label -> survey rows"):
        ft.plot_survey([1, 2])
    with pytest.raises(ValueError, match=r"^bound must be True or False, got 'no'$"):
        ft.plot_survey({"x": rows}, bound="no")


@pytest.mark.parametrize("bad", [[], np.array(1.0), True])
def test_survey_html_names_rows(bad):
    """Issue 35 (review 35h): an empty list was an empty table, a 0-d array a TypeError."""
    with pytest.raises(ValueError, match=r"^rows must (be a list of window_survey rows|hold at least one)"):
        ft.survey_html(bad)


def test_a_fold_without_photons_is_refused_by_the_callers_names(big_window):
    """Review 35h: ml_phase_shift refused the rates as 'pulsed' and 'unpulsed'."""
    import dataclasses

    from xnavlab.mars.timing import pulsars

    dim = dataclasses.replace(pulsars.get("B1821-24"), flux=1e-8, pulsed_fraction=1e-6)
    window = ft.fold_window(dim, T0, X0, error=BIG)
    u = ft.simulate_window_photons(big_window, rng=0)
    with pytest.raises(ValueError, match=r"^area_m2 must collect at least 1e-6 pulsed photons of the "
                                         r"window's pulsar B1821-24 in its 500 s, got 5e-12"):
        ft.fold_toa(window, u)
    bare = dataclasses.replace(pulsars.get("B1821-24"), pulsed_fraction=1.0)
    with pytest.raises(ValueError, match=r"^background_ph_cm2_s must give at least 1e-6 unpulsed photons"):
        ft.fold_toa(ft.fold_window(bare, T0, X0, error=BIG), u, background_ph_cm2_s=0.0)


def test_a_window_shorter_than_a_cycle_is_not_folded(big_window):
    import dataclasses

    from xnavlab.mars.timing import pulsars

    slow = dataclasses.replace(pulsars.get("B1821-24"), period=1e4, width=100.0)
    window = ft.fold_window(slow, T0, X0, error=BIG)
    with pytest.raises(ValueError, match=r"^window must last a whole pulse cycle of B1821-24 \(10000 s\)"):
        ft.fold_photons(window, ft.simulate_window_photons(big_window, rng=0))


def test_fold_toa_gives_the_reason_for_too_few_photons_or_a_2d_u(big_window):
    """Review 35j (3) 4: one photon inside the window was refused as 'u must hold photon offsets
    within [-250, 250) s', the same message as a 2-D u."""
    u = ft.simulate_window_photons(big_window, rng=0)
    with pytest.raises(ValueError, match=r"^u must hold at least 2 photon offsets, got 1$"):
        ft.fold_toa(big_window, u[:1])
    with pytest.raises(ValueError, match=r"^u must be a 1-D array of photon offsets, shape \(n,\), got "
                                         r"shape \(2, 5\)"):
        ft.fold_toa(big_window, u[:10].reshape(2, 5))
    with pytest.raises(ValueError, match=r"^u must hold photon offsets within \[-250, 250\) s, got 260"):
        ft.fold_photons(big_window, np.array([0.0, 260.0]))


@pytest.mark.parametrize("kwargs, message", [
    ({"t0": None}, r"^t0 must be a finite real number, got None"),
    ({"t0": "1.0"}, r"^t0 must be a finite real number, got '1.0'"),
    ({"t0": math.nan}, r"^t0 must be a finite real number, got nan"),
    ({"t0": 1e300}, r"^t0 must lie in \[.*\] s TDB past J2000 \(its window in DE421\)"),
    ({"duration": 0.0}, r"^duration must be a real number in \[1, 86400\], got 0.0"),
    ({"duration": None}, r"^duration must be"),
    ({"area_m2": None}, r"^area_m2 must be a real number in \[1e-06, 1000\]"),
    ({"background_ph_cm2_s": "x"}, r"^background_ph_cm2_s must be"),
    ({"n_windows": 10**4, "spacing": 86400.0, "t0": 6.3e9}, r"^n_windows must keep the last window in DE421"),
    ({"error": [[0.0] * 6]}, r"^error must be a 1-D array \(shape \(6,\)\)"),
    ({"cache": True, "t0": None}, r"^t0 must be a finite real number"),
])
def test_review_35k_1_18_3_10_window_survey_names(kwargs, message):
    """Review 35k (1) 18, (3) 10: t0 of None or text was a TypeError, NaN refused as t_eval and
    1e300 as t_start; duration was refused as t_obs (the inner names); with cache=True float()
    met the raw values."""
    with pytest.raises(ValueError, match=message):
        ft.window_survey(["B0531+21"], **({"n_windows": 2} | kwargs))


def test_review_35k_1_22_window_photons_bounded():
    """Review 35k (1) 22: the photons of a window are bounded before they are drawn, by the
    caller's area_m2 (not simulate_photons' t_obs)."""
    w = ft.fold_window("B0531+21", dynamics.MARS_T0, dynamics.MARS_STATE0, duration=20.0)
    with pytest.raises(ValueError, match=r"^area_m2 must keep the expected photons at most 5e\+07"):
        ft.simulate_window_photons(w, area_m2=1e3, rng=0)


def test_a_survey_longer_than_the_longest_propagation_names_n_windows():
    """Review 35k (after the models' span bound): 800 daily windows were refused as the
    propagation's t_eval, a name the user never gave."""
    with pytest.raises(ValueError, match=r"^n_windows must keep the windows within 731 days"):
        ft.window_survey(["B0531+21"], n_windows=800, spacing=86400.0)
    assert dynamics.MAX_SPAN_DAYS == 731.0


@pytest.mark.parametrize("call, name", [
    (lambda: ft.fold_window("B0531+21", np.float32(dynamics.MARS_T0), dynamics.MARS_STATE0),
     "t_start"),
    (lambda: ft.window_survey(t0=np.float32(dynamics.MARS_T0), n_windows=1), "t0")])
def test_a_float32_window_epoch_is_refused_with_its_resolution(call, name):
    """A float32 epoch near 5e8 s resolves 32 s: the window's orbit started 32 s off in silence
    (the epochs' rule of :func:`xnavlab.core.ephemeris.check_resolution`)."""
    with pytest.raises(ValueError, match=f"^{name} must resolve its epochs to 0.001 s: as float32 "
                                         "it resolves 32 s"):
        call()


def test_the_cached_survey_of_a_custom_pulsar_is_its_own(monkeypatch, tmp_path):
    """Review 35 R8: with cache=True a Pulsar was keyed and computed by its name, so it got
    the catalogue pulsar's rows (a bound of 454.2 m for 19.5 m)."""
    import dataclasses

    from xnavlab.mars.timing import pulsars

    monkeypatch.setenv("XNAVLAB_CACHE", str(tmp_path))
    cat = pulsars.get("B1937+21")
    mine = dataclasses.replace(cat, ra_deg=10.0, dec_deg=-40.0, flux=cat.flux * 100)
    for ps in ([mine], ["B1937+21"]):
        computed = ft.window_survey(ps, n_windows=1)
        assert ft.window_survey(ps, n_windows=1, cache=True) == computed  # stored
        assert ft.window_survey(ps, n_windows=1, cache=True) == computed  # read back
    assert ft.window_survey([mine], n_windows=1, cache=True)[0]["crlb_m"] == pytest.approx(19.48, abs=0.01)
    assert ft.window_survey(["B1937+21"], n_windows=1, cache=True)[0]["crlb_m"] == pytest.approx(454.21,
                                                                                                abs=0.01)
    assert len(list(tmp_path.glob("fold-survey-*.json"))) == 2
