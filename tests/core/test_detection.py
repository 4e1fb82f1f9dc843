"""Wavelet and chi-square fault detection: Mallat vs PyWavelets, detectors on synthetic faults."""

import math

import numpy as np
import pytest
import pywt
from hypothesis import given
from hypothesis import strategies as st

from xnavlab.core import detection as D
from xnavlab.core.faults import Fault, inject

WAVELETS = ("haar", "db2", "db3", "db4", "sym4")
SIGMA = 5000.0          # m, UV range noise of the paper
DT = 3.0                # s, UV sampling of the paper


def _range_like(t):
    """A UV range-like truth: 4190 km mean, 380 km orbital swing, 2.3 h period (m)."""
    return 4.19e6 - 3.8e5 * np.cos(2.0 * np.pi * t / 8280.0)


@pytest.fixture(scope="module")
def sigma_uv():
    t = DT * np.arange(20000)
    det = D.WaveletDetector()
    det.train(_range_like(t) + np.random.default_rng(1).normal(0.0, SIGMA, t.size))
    return det.sigma


# ---------------------------------------------------------------------------- Mallat vs pywt

@given(n=st.integers(2, 300), wavelet=st.sampled_from(WAVELETS), mode=st.sampled_from(D.MALLAT_MODES),
       seed=st.integers(0, 2**16))
def test_mallat_dwt_idwt_match_pywavelets(n, wavelet, mode, seed):
    x = np.random.default_rng(seed).normal(0.0, 1.0, n)
    a, d = D.mallat_dwt(x, wavelet, mode)
    ra, rd = pywt.dwt(x, wavelet, mode)
    assert a.shape == ra.shape and d.shape == rd.shape
    assert np.max(np.abs(a - ra)) <= 1e-12 and np.max(np.abs(d - rd)) <= 1e-12
    if mode != "periodization" and len(a) < pywt.Wavelet(wavelet).dec_len // 2:
        return
    y = D.mallat_idwt(a, d, wavelet, mode)
    ry = pywt.idwt(a, d, wavelet, mode)
    assert y.shape == ry.shape and np.max(np.abs(y - ry)) <= 1e-12


@given(n=st.integers(16, 2000), wavelet=st.sampled_from(WAVELETS), mode=st.sampled_from(D.MALLAT_MODES),
       data=st.data())
def test_mallat_wavedec_waverec_match_pywavelets_and_reconstruct(n, wavelet, mode, data):
    top = D.max_level(n, wavelet)
    assert top == pywt.dwt_max_level(n, pywt.Wavelet(wavelet).dec_len)
    if top < 1:
        return
    level = data.draw(st.integers(1, top))
    x = np.random.default_rng(n).normal(0.0, 1.0, n)
    ours = D.mallat_wavedec(x, wavelet, level, mode)
    ref = pywt.wavedec(x, wavelet, mode=mode, level=level)
    assert len(ours) == len(ref) == level + 1
    for c, r in zip(ours, ref, strict=True):
        assert c.shape == r.shape and np.max(np.abs(c - r)) <= 1e-12
    back = D.mallat_waverec(ours, wavelet, mode)
    assert np.max(np.abs(back - pywt.waverec(ref, wavelet, mode=mode))) <= 1e-12
    assert np.max(np.abs(back[:n] - x)) <= 1e-10     # perfect reconstruction (filters to ~1e-13)


def test_mallat_filters_are_the_orthonormal_qmf_pair():
    h, g = D.mallat_filters("db3")
    F = len(h)
    assert np.isclose(h @ h, 1.0) and np.isclose(h.sum(), math.sqrt(2.0)) and abs(g.sum()) < 1e-12
    assert np.allclose(g, (-1.0) ** np.arange(F) * h[::-1])             # g_m = (-1)^m h_{F-1-m}
    for shift in (2, 4):
        assert abs(h[shift:] @ h[:-shift]) < 1e-12                      # orthogonal to even shifts


@given(n=st.integers(200, 700), level=st.integers(1, 5), seed=st.integers(0, 1000))
def test_detail_signals_sum_to_signal_minus_approximation(n, level, seed):
    x = np.random.default_rng(seed).normal(0.0, SIGMA, n) + 1e6
    details, approx = D.detail_signals(x, level=level)
    assert details.shape == (level, n) and approx.shape == (n,)
    assert np.max(np.abs(details.sum(axis=0) - (x - approx))) <= 1e-9 * np.abs(x).max()


def test_detail_signals_of_a_step_are_local():
    x = np.r_[np.zeros(512), np.ones(512)]
    details, _ = D.detail_signals(x)
    far = np.r_[np.arange(0, 300), np.arange(724, 1024)]
    assert np.abs(details[:, far]).max() < 1e-10                        # vanishing moments
    assert np.abs(details[:, 490:535]).max() > 0.1


# ---------------------------------------------------------------------------- causal details

def test_causal_filters_unit_norm_and_vanishing_moments():
    for j, g in enumerate(D.causal_filters("db3", 5), start=1):
        assert len(g) == (2**j - 1) * 5 + 1
        assert np.isclose(g @ g, 1.0)
        m = np.arange(len(g)) / len(g)
        for p in range(3):                                              # db3: 3 vanishing moments
            assert abs(np.sum(m**p * g)) < 1e-12


def test_causal_details_are_pywt_swt_delayed():
    """Our causal details equal the stationary wavelet transform, delayed by 3 (2^j - 1) samples."""
    x = np.random.default_rng(0).normal(size=512)
    ours = D.causal_details(x)
    swt = pywt.swt(x, "db3", level=5, trim_approx=False)
    for j in range(1, 6):
        ref = np.roll(swt[5 - j][1], 3 * (2**j - 1))
        assert np.max(np.abs(ours[j - 1, 200:] - ref[200:])) < 1e-12


# ---------------------------------------------------------------------------- thresholds

def test_threshold_and_false_alarm_probability_are_inverse():
    for pfa in (1e-2, 1e-5, 1e-8):
        k = D.threshold_multiplier(pfa, 6)
        assert math.isclose(D.false_alarm_probability(k, 6), pfa, rel_tol=1e-9)


def test_mad_sigma_of_db3_details_of_white_noise_is_sigma():
    x = np.random.default_rng(2).normal(0.0, SIGMA, 50000)
    sig = D.mad_sigma(D.causal_details(x)[:, 200:])
    assert np.allclose(sig / SIGMA, 1.0, atol=0.03)


@pytest.mark.parametrize("pfa,var_window", [(1e-2, 32), (1e-3, 32), (1e-3, 0)])
def test_false_alarm_rate_on_fault_free_noise_near_design(pfa, var_window):
    """Known sigma: the measured rate is 0.85-1.0 of the design (the union bound is nearly tight)."""
    t = DT * np.arange(300000)
    x = np.random.default_rng(7).normal(0.0, SIGMA, t.size)
    res = D.wavelet_detect(t, x, sigma=np.full(5, SIGMA), pfa=pfa, var_window=var_window)
    assert 0.75 * pfa <= res.false_alarm_rate <= 1.15 * pfa


def test_no_false_alarm_at_default_pfa_on_range_like_series(sigma_uv):
    t = DT * np.arange(100000)
    x = _range_like(t) + np.random.default_rng(3).normal(0.0, SIGMA, t.size)
    res = D.wavelet_detect(t, x, sigma=sigma_uv)
    assert res.false_alarm_rate <= 5e-5 and len(res.events) <= 2      # design 1e-5: one expected


# ---------------------------------------------------------------------------- detection

# kind, magnitude, max onset delay (samples) -- UV range-like series, 5000 m noise, 3 s.
CASES = [
    ("step", 10 * SIGMA, 20),       # 50 km: measured median 4, max 12 samples
    ("step", 20 * SIGMA, 1),        # 100 km: at the onset
    ("spike", 15 * SIGMA, 1),       # 75 km outlier
    ("ramp", 1000.0, 80),           # 1 km/s (0.6 sigma per sample): the kink seen at level 5
    ("stuck", 0.0, 80),             # frozen output: variance test (64-sample span)
    ("noise", 4 * SIGMA, 40),       # extra 20 km noise
]


@pytest.mark.parametrize("kind,magnitude,max_delay", CASES, ids=[f"{c[0]}-{c[1]:g}" for c in CASES])
def test_detects_fault_at_onset_within_delay(sigma_uv, kind, magnitude, max_delay):
    t = DT * np.arange(16000)
    delays = []
    for seed in range(10):
        onset = 24000.0 + 7 * DT * seed
        x = _range_like(t) + np.random.default_rng(100 + seed).normal(0.0, SIGMA, t.size)
        x = inject(t, x, [Fault("uv", kind, magnitude, onset, 3000.0)], "uv", rng=seed)
        res = D.wavelet_detect(t, x, sigma=sigma_uv)
        assert not res.alarm[t < onset].any(), "false alarm before the onset"
        delays.append((res.first_onset_after(onset) - onset) / DT)
    assert max(delays) <= max_delay, delays


def test_step_gives_onset_and_end_events(sigma_uv):
    """A wavelet detector sees changes: a 3000-s step is two events, at its onset and its end."""
    t = DT * np.arange(16000)
    x = _range_like(t) + np.random.default_rng(5).normal(0.0, SIGMA, t.size)
    x = inject(t, x, [Fault("uv", "step", 20 * SIGMA, 24000.0, 3000.0)], "uv")
    res = D.wavelet_detect(t, x, sigma=sigma_uv)
    assert [e.onset for e in res.events] == [24000.0, 27000.0]
    for ev in res.events:
        assert ev.onset <= ev.end < ev.onset + 160 * DT
        assert ev.cleared == ev.end + res.data["holdoff"] * DT
        assert set(ev.as_dict("uv", "wavelet")) == {"sensor", "detected_onset", "detected_end", "detector"}
    assert res.faulty[(t >= 24000.0) & (t < res.events[0].cleared)].all()


def test_small_step_is_missed_ramp_seen_only_at_its_end(sigma_uv):
    """What the detector cannot see: a 1-sigma step, and a slow ramp's kink (only its end jump)."""
    t = DT * np.arange(16000)
    x0 = _range_like(t) + np.random.default_rng(6).normal(0.0, SIGMA, t.size)
    res = D.wavelet_detect(t, inject(t, x0, [Fault("uv", "step", SIGMA, 24000.0, 3000.0)], "uv"),
                           sigma=sigma_uv)
    assert not res.events
    res = D.wavelet_detect(t, inject(t, x0, [Fault("uv", "ramp", 10.0, 24000.0, 3000.0)], "uv"),
                           sigma=sigma_uv)
    assert len(res.events) == 1 and 27000.0 <= res.events[0].onset <= 27000.0 + 40 * DT


def test_online_detector_equals_batch(sigma_uv):
    t = DT * np.arange(3000)
    x = _range_like(t) + np.random.default_rng(8).normal(0.0, SIGMA, t.size)
    x = inject(t, x, [Fault("uv", "step", 12 * SIGMA, 3000.0, 600.0),
                      Fault("uv", "noise", 3 * SIGMA, 6000.0, 300.0)], "uv", rng=1)
    batch = D.wavelet_detect(t, x, sigma=sigma_uv)
    det = D.WaveletDetector(sigma=sigma_uv)
    flags = []
    for ti, xi in zip(t, x, strict=True):
        flags.append(det.update(ti, xi))
        if ti == 900.0:
            assert np.allclose(det.details(), batch.data["details"][:, 300], rtol=1e-9, atol=1e-6)
    assert np.array_equal(np.array(flags), batch.faulty)
    _same_events(det.all_events(), batch.events)
    assert len(batch.events) == 2     # step (onset and end merged: 200 samples < hold-off), noise


def _same_events(a, b):
    key = [(e.onset, e.end, e.cleared, e.test) for e in a]
    assert key == [(e.onset, e.end, e.cleared, e.test) for e in b]
    assert np.allclose([e.peak for e in a], [e.peak for e in b], rtol=1e-9)


def test_trained_on_the_series_itself_is_robust():
    t = DT * np.arange(20000)
    x = _range_like(t) + np.random.default_rng(9).normal(0.0, SIGMA, t.size)
    x = inject(t, x, [Fault("uv", "step", 10 * SIGMA, 30000.0, 3000.0)], "uv")
    res = D.wavelet_detect(t, x)                                      # sigma by MAD on x itself
    assert np.allclose(res.data["sigma"] / SIGMA, 1.0, atol=0.06)
    assert res.first_onset_after(30000.0) - 30000.0 <= 20 * DT


def test_event_tracker_matches_events_from_alarms():
    rng = np.random.default_rng(10)
    alarm = rng.random(2000) < 0.02
    ratio = np.where(alarm, 1.0 + rng.random(2000), 0.5)
    t = np.arange(2000.0)
    events, faulty = D.events_from_alarms(t, alarm, ratio, 30)
    tr = D.EventTracker(30)
    flags = [tr.update(ti, a, r) for ti, a, r in zip(t, alarm, ratio, strict=True)]
    assert np.array_equal(flags, faulty)
    assert [(e.onset, e.end, e.cleared, e.peak) for e in tr.all_events()] == \
           [(e.onset, e.end, e.cleared, e.peak) for e in events]


def test_sensor_detector_splits_pfa_and_names_the_component():
    t = DT * np.arange(100000)
    z = np.random.default_rng(14).normal(0.0, 1.0, (t.size, 3))
    res = D.wavelet_detect_sensor(t, z, pfa=1e-2, sigma=np.ones((3, 5)))
    assert 0.75e-2 <= res.false_alarm_rate <= 1.15e-2                 # per sensor sample
    z = inject(t[:8000], z[:8000], [Fault("cns", "step", 20.0, 12000.0, 600.0, component=1)], "cns")
    res = D.wavelet_detect_sensor(t[:8000], z, train=3000)
    assert [e.onset for e in res.events] == [12000.0]
    assert res.events[0].test.startswith("component 1, ")
    assert set(res.data["component"][res.alarm]) == {1}


@given(st.lists(st.integers(1, 5999), min_size=1, max_size=12), st.integers(0, 2**32 - 1))
def test_block_by_block_is_the_batch_to_the_bit(cuts, seed):
    """BlockWavelet(Sensor): any cutting into blocks gives the batch's bits, and the onsets it
    hands out block by block are the batch's event onsets."""
    rng = np.random.default_rng(seed)
    t = DT * np.arange(6000)
    z = rng.normal(0.0, 1.0, (t.size, 2)) + 3e3                   # an offset: the origin matters
    z[3000 + int(rng.integers(0, 2000)):, int(rng.integers(0, 2))] += 6.0
    whole = D.wavelet_detect_sensor(t, z, train=1000, pfa=1e-3)
    one = D.wavelet_detect(t, z[:, 0], train=1000, pfa=1e-3)
    b, b0 = D.BlockWaveletSensor(t, z, train=1000, pfa=1e-3), D.BlockWavelet(t, z[:, 0], train=1000,
                                                                             pfa=1e-3)
    onsets, onsets0 = [], []
    for c in sorted(set(cuts)) + [t.size]:
        onsets += b.new_onsets(c).tolist()
        onsets0 += b0.new_onsets(c).tolist()
    for blocks, batch, ons in ((b, whole, onsets), (b0, one, onsets0)):
        res = blocks.detection()
        assert np.array_equal(res.ratio, batch.ratio) and np.array_equal(res.alarm, batch.alarm)
        assert ons == [int(np.searchsorted(t, e.onset)) for e in batch.events]
        assert [(e.onset, e.end, e.test) for e in res.events] == \
               [(e.onset, e.end, e.test) for e in batch.events]
    with pytest.raises(ValueError, match="stop"):
        b0.advance(-1)


# ---------------------------------------------------------------------------- singularities

def test_lipschitz_exponents_of_step_ramp_spike():
    n = np.arange(-1024, 1024)
    s = 2.0 ** np.arange(1, 7)
    signals = {0.0: np.where(n >= 0, 1.0, 0.0), 1.0: np.maximum(n, 0.0), -1.0: (n == 0) * 1.0}
    for alpha, x in signals.items():
        assert abs(D.lipschitz_exponent(D.cwt(x, s, "gaus1"), s, 1024) - alpha) < 0.1


def test_modulus_maxima_locate_the_step_at_every_scale():
    x = np.r_[np.zeros(256), np.ones(256)]
    w = D.cwt(x, [2.0, 4.0, 8.0, 16.0], "gaus1")
    mm = D.modulus_maxima(w, threshold=0.1)[:, 64:448]                # away from the ends
    for row in mm:
        assert np.flatnonzero(row).tolist() == [256 - 64] or np.flatnonzero(row).tolist() == [255 - 64]


# ---------------------------------------------------------------------------- chi-square

def _innovations(n, m, seed):
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(m, m))
    S = A @ A.T + m * np.eye(m)
    nu = rng.multivariate_normal(np.zeros(m), S, n)
    return nu, S


@pytest.mark.parametrize("window", [1, 5])
def test_chi2_false_alarm_rate_near_alpha(window):
    nu, S = _innovations(200000, 3, 11)
    res = D.chi2_detect(np.arange(nu.shape[0]) * DT, nu, S, alpha=1e-2, window=window)
    assert res.data["dof"] == 3 * window
    assert 0.85e-2 <= res.false_alarm_rate <= 1.15e-2


def test_chi2_detects_bias_and_online_equals_batch():
    nu, S = _innovations(3000, 3, 12)
    t = np.arange(3000) * DT
    nu = inject(t, nu, [Fault("uv", "step", 10.0 * math.sqrt(S[0, 0]), 3000.0, 300.0, component=0)], "uv")
    S_n = np.broadcast_to(S, (3000, 3, 3))
    res = D.chi2_detect(t, nu, S_n, window=3, holdoff=5)
    assert res.first_onset_after(3000.0) == 3000.0
    big = [e for e in res.events if e.onset >= 3000.0]
    assert big[0].end >= 3000.0 + 300.0 - 2 * DT
    det = D.Chi2Detector(3, window=3, holdoff=5)
    flags = [det.update(ti, v, S) for ti, v in zip(t, nu, strict=True)]
    assert np.array_equal(flags, res.faulty)
    _same_events(det.all_events(), res.events)


def test_chi2_statistic_is_the_normalised_innovation_squared():
    nu, S = _innovations(50, 2, 13)
    stat, dof = D.chi2_statistic(nu, S)
    assert dof == 2 and np.allclose(stat, np.einsum("ni,ij,nj->n", nu, np.linalg.inv(S), nu))
    stat1, _ = D.chi2_statistic(nu[:, 0], np.full(50, S[0, 0]))
    assert np.allclose(stat1, nu[:, 0] ** 2 / S[0, 0])


# ---------------------------------------------------------------------------- bad input

@pytest.mark.parametrize("call,name", [
    (lambda: D.mallat_dwt(np.ones(16), mode="wrap"), "mode"),
    (lambda: D.mallat_dwt(np.ones(16), wavelet="db99"), "wavelet"),
    (lambda: D.mallat_dwt(np.ones(16), wavelet="bior1.3"), "wavelet"),
    (lambda: D.mallat_dwt([1.0, np.nan]), "c"),
    (lambda: D.mallat_wavedec(np.ones(64), level=5), "level"),
    (lambda: D.mallat_wavedec(np.ones(64), level=0), "level"),
    (lambda: D.detail_signals(np.ones((3, 64))), "x"),
    (lambda: D.WaveletDetector(level=0), "level"),
    (lambda: D.WaveletDetector(pfa=1.5), "pfa"),
    (lambda: D.WaveletDetector(var_window=-1), "var_window"),
    (lambda: D.WaveletDetector(holdoff=0), "holdoff"),
    (lambda: D.WaveletDetector(sigma=[1.0, 2.0]), "sigma"),
    (lambda: D.WaveletDetector(sigma=[1.0, 1.0, 1.0, 1.0, -1.0]), "sigma"),
    (lambda: D.WaveletDetector().train(np.ones(100)), "x"),
    (lambda: D.WaveletDetector(sigma=np.ones(5)).update(0.0, math.inf), "x"),
    (lambda: D.wavelet_detect(np.arange(10.0), np.ones(11)), "t"),
    (lambda: D.threshold_multiplier(0.0), "pfa"),
    (lambda: D.wavelet_detect_sensor(np.arange(10.0), np.ones((11, 2))), "z"),
    (lambda: D.wavelet_detect_sensor(np.arange(500.0), np.ones((500, 2)), sigma=np.ones(5)), "sigma"),
    (lambda: D.wavelet_detect_sensor(np.arange(500.0), np.ones((500, 2)), train=np.ones((400, 3))), "train"),
    (lambda: D.chi2_threshold(0.01, 0), "dof"),
    (lambda: D.chi2_statistic(np.ones((5, 2)), np.eye(2), window=0), "window"),
    (lambda: D.chi2_statistic(np.ones((5, 2)), np.eye(3)), "S"),
    (lambda: D.chi2_statistic(np.ones((5, 2)), -np.eye(2)), "S"),
    (lambda: D.Chi2Detector(m=2, alpha=0.0), "alpha"),
    (lambda: D.Chi2Detector(m=2).update(0.0, [1.0], np.eye(2)), "nu"),
    (lambda: D.cwt(np.ones(32), [0.0, 2.0]), "scales"),
    (lambda: D.cwt(np.ones(32), [2.0], wavelet="db3"), "wavelet"),
    (lambda: D.modulus_maxima(np.ones(8), threshold=-1.0), "threshold"),
    (lambda: D.lipschitz_exponent(np.ones((2, 8)), [1.0, 2.0], index=9), "index"),
])
def test_bad_input_raises_value_error_naming_the_parameter(call, name):
    with pytest.raises(ValueError, match=rf"\b{name}\b"):
        call()


def test_reproduction_mallat_vs_pywavelets_passes():
    from xnavlab import reproduce

    reproduce.run("mallat-vs-pywavelets").assert_passed()


def test_plot_fault_detection_reports_delay_and_is_pure():
    import matplotlib.pyplot as plt
    from matplotlib.figure import Figure

    t = DT * np.arange(8000)
    clean = _range_like(t) + np.random.default_rng(7).normal(0.0, SIGMA, t.size)
    step = Fault("uv", "step", 10 * SIGMA, onset=12_000.0, duration=3000.0)
    before = plt.get_fignums()
    fig = D.plot_fault_detection(t, clean, [step], train=3000, zoom_h=(3.0, 4.0), title="10 sigma")
    assert isinstance(fig, Figure) and plt.get_fignums() == before  # not left in pyplot
    res = D.wavelet_detect(t, inject(t, clean, [step], "uv"), train=3000)
    delay = res.first_onset_after(step.onset) - step.onset
    assert fig.get_suptitle() == (f"10 sigma, k = {res.data['k']:.2f}: onset detected after "
                                  f"{delay:.0f} s, 0 false-alarm samples before it")
    ax1, ax2 = fig.axes
    assert ax1.get_xlim() == (3.0, 4.0) and ax2.get_ylabel() == "ratio"
    np.testing.assert_allclose(ax2.lines[0].get_ydata(), np.maximum(res.ratio, 1e-3))
    # a step far below the threshold is missed, and said so
    small = Fault("uv", "step", 0.5 * SIGMA, onset=12_000.0, duration=3000.0)
    assert "onset missed" in D.plot_fault_detection(t, clean, [small], train=3000).get_suptitle()


@pytest.mark.parametrize(("kwargs", "name"), [
    ({"zoom_h": (2.0, 1.0)}, "zoom_h"),
    ({"zoom_h": 3.0}, "zoom_h"),
    ({"scale": 0.0}, "scale"),
    ({"faults": ["step"]}, "faults"),
])
def test_plot_detection_bad_input(kwargs, name):
    t = DT * np.arange(600)
    x = np.random.default_rng(0).normal(0.0, SIGMA, t.size)
    res = D.wavelet_detect(t, x)
    with pytest.raises(ValueError, match=rf"\b{name}\b"):
        D.plot_detection(res, x, **kwargs)
    with pytest.raises(ValueError, match=r"\bx\b"):
        D.plot_detection(res, x[:-1])
    with pytest.raises(ValueError, match=r"\bresult\b"):
        D.plot_detection(None, x)


def test_event_tracker_snapshot_restore_and_close():
    from xnavlab.core.detection import EventTracker

    tr = EventTracker(holdoff=3)
    tr.update(0.0, True, 2.0, "a")
    snap = tr.snapshot()
    for i in range(1, 6):
        tr.update(float(i), i == 2, 3.0, "b")
    after = [(e.onset, e.end, e.cleared) for e in tr.events]
    tr.restore(snap)
    assert tr.faulty and tr.events == []
    for i in range(1, 6):
        tr.update(float(i), i == 2, 3.0, "b")
    assert [(e.onset, e.end, e.cleared) for e in tr.events] == after == [(0.0, 2.0, 5.0)]
    tr.update(9.0, True, 2.0, "c")
    tr.close(9.5)
    assert not tr.faulty and tr.events[-1].cleared == 9.5
    tr.close()                                   # nothing open: no-op
    assert len(tr.events) == 2


def test_wavelet_detect_refuses_a_time_axis_that_is_not_increasing():
    from xnavlab.core.detection.batch import wavelet_detect

    t = 3.0 * np.arange(2000.0)
    x = np.random.default_rng(0).standard_normal(t.size)
    with pytest.raises(ValueError, match=r"t must be strictly increasing .* t\[1\] = 5994 follows"):
        wavelet_detect(t[::-1].copy(), x, sigma=1.0)
    t[500] = t[499]
    with pytest.raises(ValueError, match=r"t must be strictly increasing .*t\[500\]"):
        wavelet_detect(t, x, sigma=1.0)
