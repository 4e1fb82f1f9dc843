"""The isolation Monte Carlo of the attitude system (xnavlab.attitude.montecarlo)."""


import pytest

from xnavlab import attitude as att


def test_isolation_monte_carlo_small():
    rows = att.isolation_monte_carlo(
        2, locations=["gyro_z", "star_tracker"], kinds=["step"], sizes=[1.0], rng=4
    )
    assert len(rows) == 6  # (none, gyro_z, star_tracker) x (SOS, DOS)
    by = {(r["location"], r["method"]): r for r in rows}
    assert by[("none", "SOS")]["false_alarm"] == 0.0 and by[("none", "SOS")]["correct"] == 1.0
    assert by[("gyro_z", "SOS")]["correct"] == 1.0 and by[("gyro_z", "DOS")]["correct"] == 1.0
    assert by[("gyro_z", "SOS")]["delay_s"] < by[("gyro_z", "DOS")]["delay_s"]
    table = att.isolation_table(rows)
    assert table.strip().count("\n") == 4 and "| gyro_z | step | 36 deg/h |" in table
    with pytest.raises(ValueError, match="^onset"):
        att.isolation_monte_carlo(1, onset=10.0)
    with pytest.raises(ValueError, match="^locations"):
        att.isolation_monte_carlo(1, locations=["sun_sensor"])
    with pytest.raises(ValueError, match="^sizes"):
        att.isolation_monte_carlo(1, sizes=[-1.0])


@pytest.mark.parametrize(("kw", "words"), [
    ({"locations": []}, r"^locations must name at least one location, got an empty list"),
    ({"kinds": []}, r"^kinds must name at least one kind"),
    ({"sizes": []}, r"^sizes must name at least one size"),
    ({"locations": ["gyro_x", "gyro_x"]}, r"^locations lists gyro_x twice \(items 0 and 1\)"),
    ({"locations": "gyro_x"}, r"^locations must be a list of locations, got the string"),
    ({"sizes": [1.0, -2.0]}, r"^sizes\[1\] must be a real number in \(0, 1000\]"),
])
def test_an_empty_or_repeated_list_is_refused_not_a_table_without_its_rows(kw, words):
    """Review 35b N23's class: an empty list left only the fault-free rows, without a word."""
    with pytest.raises(ValueError, match=words):
        att.isolation_monte_carlo(1, **kw)


def test_seeded_outcomes_run_k_is_simulate_with_seed_k():
    """Each run of the batch is the single run of its seed (the chapter plots seed 0)."""
    fault = att.make_fault("gyro_skew", "ramp", 0.1 * att.DEG_PER_H)
    out = att.seeded_outcomes(fault, [3, 0], duration=60.0)
    for k, seed in enumerate((3, 0)):
        run = att.simulate(fault, rng=seed, duration=60.0)
        assert out["sos_verdict"][k] == run.sos.verdict == "gyro_skew"
        assert out["qd_verdict"][k] == run.qd.verdict
        assert out["dos_verdict"][k] == run.dos.verdict
        assert out["sos_delay_s"][k] == pytest.approx(run.sos.detect_time - run.onset)
        after = run.t >= run.onset
        assert out["crossed"][k].tolist() == run.sos.flags[after].any(axis=0).tolist()
        assert out["false_alarm"][k] == run.sos.flags[~after].any()
    assert out["seeds"].tolist() == [3, 0] and out["onset"] == 50.0
    assert out["first_flag_s"][:, :3].tolist() == [[float("inf")] * 3] * 2   # r4 alone crosses
    assert 0.0 < out["first_flag_s"][0, 3] <= out["sos_delay_s"][0]


@pytest.mark.parametrize(("args", "words"), [
    ((), r"^faults must hold at least one fault"),
    ((att.make_fault("gyro_x", "step", 1e-4),), None),
])
def test_seeded_outcomes_refuses_no_fault_and_bad_seeds(args, words):
    if words is not None:
        with pytest.raises(ValueError, match=words):
            att.seeded_outcomes(list(args), [0])
        return
    with pytest.raises(ValueError, match=r"^seeds must name at least one seed"):
        att.seeded_outcomes(args[0], [])
    with pytest.raises(ValueError, match=r"^seeds lists 1 twice"):
        att.seeded_outcomes(args[0], [1, 1])


def test_isolation_monte_carlo_refuses_a_count_that_would_not_end():
    """Review 35e: n_runs=10**30 ran without end."""
    with pytest.raises(ValueError, match=r"^n_runs must be an integer in \[1, 1000000\]"):
        att.isolation_monte_carlo(10**30, locations=["gyro_x"], kinds=["step"], sizes=[1.0])


@pytest.mark.parametrize(("rows", "match"), [
    (True, r"^rows must be a list of isolation_monte_carlo's rows"),
    (-0.0, r"^rows must be a list of isolation_monte_carlo's rows"),
    ([1.0], r"^rows\[0\] must be a row \(a dict with location, kind"),
    ([{"location": "gyro_x"}], r"^rows\[0\] must be a row \(a dict with location, kind"),
])
def test_isolation_table_names_rows(rows, match):
    """Issue 35: a bool or a list of numbers was a TypeError."""
    import numpy as np

    with pytest.raises(ValueError, match=match):
        att.isolation_table(rows)
    with pytest.raises(ValueError, match=r"^rows must be a list"):
        att.isolation_table(np.array(1.0))


def test_seeded_outcomes_names_a_0d_array_of_faults():
    import numpy as np

    with pytest.raises(ValueError, match=r"^faults must be a Fault or a sequence of Fault, got array\(1"):
        att.seeded_outcomes(np.array(1.0), [0])
    with pytest.raises(ValueError, match=r"^faults must be a Fault or a sequence of Fault"):
        att.simulate(np.array(1.0))


def test_isolation_monte_carlo_refuses_a_set():
    with pytest.raises(ValueError, match=r"^sizes must be a list \(ordered"):
        att.isolation_monte_carlo(1, locations=["gyro_x"], kinds=["step"], sizes={10.0, 1.0})


@pytest.mark.parametrize(("onset", "words"), [
    (5e-324, r"^onset must be a real number in \[40, 159960\], got 5e-324"),
    (None, r"^onset must be a real number in \[40, 159960\]"),
    (159970.0, r"^onset must be a real number in \[40, 159960\]"),
    (45.05, r"^onset = 45\.05 s makes the default config's duration onset \+ 30 s, which SimConfig "
            r"refuses: duration must be a whole number of steps"),
])
def test_the_onset_of_the_default_config_is_refused_under_its_own_name(onset, words):
    """Review 35k (3) 14: onset=5e-324 was refused as 't_cal must satisfy 0 <= t_cal[0] <
    t_cal[1] <= duration', a field of the default config the user never gave."""
    with pytest.raises(ValueError, match=words):
        att.isolation_monte_carlo(1, locations=["gyro_x"], kinds=["step"], sizes=[1.0], onset=onset)


def test_a_batch_past_about_nine_minutes_is_refused_with_the_most_runs_that_fit():
    """Review 35p P6: isolation_monte_carlo(10**4) built one batch of 310,000 runs (~250 GB)
    and seeded_outcomes one of all its seeds; a batch past 4e7 run-samples is refused up front,
    naming n_runs (seeds) with the estimate and the largest count that fits."""
    with pytest.raises(ValueError, match=r"^n_runs must keep the batch at most 4e\+07 run-samples "
                       r"\(about 9 minutes at 13 us each\), got n_runs = 10000: 10000 runs x 31 "
                       r"cases \(30 and the fault-free\) x 801 samples = 2\.48e\+08, about 54 "
                       r"minutes \(at most 1610 runs with these cases and config\)$"):
        att.isolation_monte_carlo(10**4)
    with pytest.raises(ValueError, match=r"^n_runs must keep .* \(not one run fits: fewer "
                       r"locations, kinds or sizes, or a shorter config\.duration"):
        att.isolation_monte_carlo(1, onset=159960.0)
    fault = att.make_fault("gyro_x", "step", 36 * att.DEG_PER_H)
    with pytest.raises(ValueError, match=r"^seeds must keep the batch at most 4e\+07 run-samples "
                       r".*got 50000 seeds x 1001 samples = 5e\+07, about 11 minutes \(at most "
                       r"39960 seeds of this duration and dt\)$"):
        att.seeded_outcomes(fault, range(50000))


def test_a_batch_in_chunks_equals_one_batch_bit_for_bit(monkeypatch):
    """Review 35p P6: the runs are diagnosed a chunk at a time (memory bounded); chunks of one
    or two runs give the outcomes of one batch exactly."""
    import numpy as np

    from xnavlab.attitude import _checks

    fault = att.make_fault("gyro_x", "step", 36 * att.DEG_PER_H)
    whole = att.seeded_outcomes(fault, range(5), duration=60.0)
    rows = att.isolation_monte_carlo(3, locations=["gyro_x", "star_tracker"], rng=5)
    for chunk in (601, 2 * 601, 2 * 801):
        monkeypatch.setattr(_checks, "CHUNK_SAMPLES", chunk)
        part = att.seeded_outcomes(fault, range(5), duration=60.0)
        for key, value in whole.items():
            assert np.array_equal(part[key], value) and np.asarray(part[key]).dtype == np.asarray(value).dtype
        assert att.isolation_monte_carlo(3, locations=["gyro_x", "star_tracker"], rng=5) == rows
