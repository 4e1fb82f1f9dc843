"""Fault injection and the command-line fault spec."""

import math
import re

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from xnavlab.core.faults import (
    KINDS,
    MAX_SIZE,
    Fault,
    check_faults,
    fault_mask,
    format_spec,
    inject,
    parse_spec,
)

COMPS = {"uv": ["range", "ux", "uy", "uz"], "xnav": ["0", "1", "2", "3"], "cns": ["0", "1", "2"]}
T = np.arange(0.0, 20.0)


def test_step_ramp_spike_noise_stuck():
    z = np.column_stack([np.arange(20.0), np.zeros(20)])
    out = inject(T, z, [Fault("s", "step", 5.0, 5.0, 3.0, component=1)], "s")
    assert out[:, 1].tolist() == [0] * 5 + [5] * 3 + [0] * 12
    np.testing.assert_array_equal(out[:, 0], z[:, 0])
    out = inject(T, z, [Fault("s", "ramp", 2.0, 10.0, component=1)], "s")
    assert out[12, 1] == 4.0 and out[9, 1] == 0.0
    out = inject(T, z, [Fault("s", "spike", 9.0, 4.5, 100.0)], "s")
    assert np.flatnonzero(out[:, 1]).tolist() == [5]
    out = inject(T, z, [Fault("s", "stuck", 0.0, 10.0, 5.0, component=0)], "s")
    assert out[10:15, 0].tolist() == [9.0] * 5 and out[15, 0] == 15.0
    out = inject(T, z, [Fault("s", "noise", 1.0, 10.0)], "s", rng=1)
    assert np.all(out[:10] == z[:10]) and np.all(out[10:] != z[10:])


def test_other_sensors_untouched_and_input_not_modified():
    z = np.zeros(20)
    out = inject(T, z, [Fault("uv", "step", 1.0, 0.0)], "cns")
    np.testing.assert_array_equal(out, z)
    inject(T, z, [Fault("cns", "step", 1.0, 0.0)], "cns")
    assert not z.any()


def test_noise_is_seeded():
    f = [Fault("s", "noise", 1.0, 0.0)]
    np.testing.assert_array_equal(inject(T, np.zeros(20), f, "s", 3), inject(T, np.zeros(20), f, "s", 3))


def test_mask():
    faults = [Fault("uv", "step", 1.0, 2.0, 2.0), Fault("uv", "step", 1.0, 10.0, 1.0)]
    assert np.flatnonzero(fault_mask(T, faults, "uv")).tolist() == [2, 3, 10]


@pytest.mark.parametrize("kwargs, match", [
    ({"kind": "wobble"}, "kind must be one of"),
    ({"magnitude": math.nan}, r"^magnitude must be a finite real number"),
    ({"magnitude": math.inf}, r"^magnitude must be a finite real number"),
    ({"magnitude": -math.inf}, r"^magnitude must be a finite real number"),
    ({"onset": math.nan}, r"^onset must be a finite real number, s"),
    ({"onset": math.inf}, r"^onset must be a finite real number, s"),
    ({"duration": -1.0}, r"^duration of a step fault must be a real number in \(0, inf\]"),
    ({"duration": -math.inf}, r"^duration of a step fault must be a real number in \(0, inf\]"),
    ({"duration": math.nan}, r"^duration of a step fault must be a real number in \(0, inf\]"),
    ({"component": -1}, "component"),
    ({"kind": "noise", "magnitude": -1.0}, r"^magnitude of a noise fault .* in \(0, inf\)"),
    ({"kind": "spike", "duration": -1.0}, r"^duration of a spike fault \(ignored\)"),
])
def test_bad_fault(kwargs, match):
    args = {"sensor": "uv", "kind": "step", "magnitude": 1.0, "onset": 0.0} | kwargs
    with pytest.raises(ValueError, match=match):
        Fault(**args)


@pytest.mark.parametrize("kind", ["step", "ramp", "spike", "noise"])
def test_a_zero_size_fault_is_refused_naming_the_magnitude(kind):
    """A zero-size fault would be injected as nothing and then scored as missed."""
    with pytest.raises(ValueError, match=r"^magnitude of a \w+ fault") as err:
        Fault("uv", kind, 0.0, 100.0, 50.0)
    assert "(0, inf)" in str(err.value)


@pytest.mark.parametrize("kind", ["step", "ramp", "stuck", "noise"])
@pytest.mark.parametrize("duration", [0.0, -5.0])
def test_a_zero_or_negative_length_fault_is_refused_naming_the_duration(kind, duration):
    with pytest.raises(ValueError, match=r"^duration of a \w+ fault must be a real number in "
                                         r"\(0, inf\], s, got .* injects nothing\)$"):
        Fault("uv", kind, 0.0 if kind == "stuck" else 1.0, 100.0, duration)


def test_what_a_kind_ignores_may_be_zero():
    """A spike's duration and a stuck output's magnitude are ignored: zero is accepted."""
    assert Fault("uv", "spike", 5.0, 10.0, 0.0).duration == 0.0
    assert Fault("uv", "stuck", 0.0, 10.0, 5.0).magnitude == 0.0
    assert Fault("uv", "step", -2.0, 10.0, math.inf).end == math.inf      # permanent, negative


def test_a_stuck_fault_refuses_a_magnitude_it_would_not_use():
    """Review 35m (6) 5's class: Fault('uv', 'stuck', 5.0, ...) froze the output and dropped
    the 5 without a word (the CLI's grammar refuses it; the class now does too)."""
    with pytest.raises(ValueError, match=r"^magnitude of a stuck fault must be 0 \(the output "
                                         r"freezes at its last fault-free value: a size would "
                                         r"go unused\), got 5.0$"):
        Fault("uv", "stuck", 5.0, 10.0, 5.0)


def test_component_out_of_range():
    with pytest.raises(ValueError, match=r"component must be in \[0, 1\]"):
        inject(T, np.zeros((20, 2)), [Fault("s", "step", 1.0, 0.0, component=3)], "s")


def test_parse_spec_examples():
    faults = parse_spec("uv.range:step:5000@700000+3000,xnav.1:ramp:2e-9@500000+5000,cns:spike:1e-3@5+inf",
                        COMPS)
    assert faults[0] == Fault("uv", "step", 5000.0, 700000.0, 3000.0, 0)
    assert faults[1] == Fault("xnav", "ramp", 2e-9, 500000.0, 5000.0, 1)
    assert faults[2].component is None and faults[2].duration == math.inf


@pytest.mark.parametrize("spec, match", [
    ("uv.range:step:5000@700000", "expected SENSOR"),
    ("gps:step:1@0+1", "unknown sensor 'gps'"),
    ("uv.alt:step:1@0+1", "component 'alt' of uv"),
    ("uv:jump:1@0+1", "kind must be one of"),
    ("uv:step:big@0+1", "'big' is not a number"),
    ("uv:step:1_0@0+1", r"'1_0' is not a number \(plain decimals"),   # as --days 1_0
    ("uv:step:1@0x10+1", "'0x10' is not a number"),
    ("uv:step:1@10+1_000", "'1_000' is not a number"),
    ("uv:step:1@0+-5", "duration"),
    ("uv:step:0@3600+3000", r"^spec: bad fault item .*: magnitude of a step fault must be a nonzero"),
    ("uv:step:25000@3600+0", r"^spec: bad fault item .*: duration of a step fault must be a real "
                             r"number in \(0, inf\], s, got 0\.0"),
    ("uv:ramp:nan@3600+10", "magnitude must be a finite real number"),
    ("uv:step:inf@3600+10", "magnitude must be a finite real number"),
    ("uv:step:1@nan+10", "onset must be a finite real number"),
    ("uv:step:1@3600+nan", "duration of a step fault"),
    ("", "non-empty"),
])
def test_parse_spec_errors_name_the_bad_part(spec, match):
    with pytest.raises(ValueError, match=match):
        parse_spec(spec, COMPS)


@given(
    st.sampled_from(sorted(COMPS)), st.sampled_from(KINDS),
    st.floats(1e-12, 1e6), st.floats(0, 3e6), st.floats(1e-3, 1e5),
)
def test_format_parse_round_trip(sensor, kind, mag, onset, dur):
    mag = 0.0 if kind == "stuck" else mag  # a stuck output's size is 0 (it is not used)
    f = Fault(sensor, kind, float(f"{mag:g}"), float(f"{onset:g}"), float(f"{dur:g}"), 0)
    assert parse_spec(format_spec([f], COMPS), COMPS) == [f]


FINITE = st.floats(allow_nan=False, allow_infinity=False)


@given(st.sampled_from(sorted(COMPS)), st.sampled_from(KINDS),
       st.floats(0.0, MAX_SIZE, exclude_min=True),
       st.booleans(), FINITE, st.one_of(st.floats(1e-300, 1e300), st.just(math.inf)),
       st.one_of(st.none(), st.integers(0, 1)))
def test_a_saved_spec_reads_back_as_the_same_faults_to_the_last_bit(sensor, kind, mag, neg, onset,
                                                                    dur, comp):
    """format_spec wrote %g (1234.5678 became 1234.57): a re-run from a saved spec injected
    another fault. Every float now comes back bit for bit; %g text where it was exact."""
    mag = 0.0 if kind == "stuck" else mag  # a stuck output's size is 0 (it is not used)
    f = Fault(sensor, kind, -mag if neg and kind != "noise" else mag, onset, dur, comp)
    other = "uv" if sensor == "cns" else "cns"  # a second item, on another sensor
    text = format_spec([f, Fault(other, "step", 1.0, onset, 1.0, 2)], COMPS)
    back = parse_spec(text, COMPS)
    assert back[0] == f and all(isinstance(v, float) for v in (back[0].magnitude, back[0].onset))
    assert format_spec(back, COMPS) == text


def test_format_spec_keeps_the_g_text_where_it_is_exact():
    f = Fault("uv", "step", 1234.5678, 12345.67, 10.123456, 0)
    assert format_spec([f], COMPS) == "uv.range:step:1234.5678@12345.67+10.123456"
    assert format_spec([Fault("uv", "step", 5e3, 7e5, 3e3, 0)], COMPS) == "uv.range:step:5000@700000+3000"


def test_a_fault_listed_twice_is_refused_with_both_items():
    """Injected twice it doubled its size; scored twice it counted one event as two faults."""
    with pytest.raises(ValueError, match=r"^spec lists uv.range:step:1000@1000\+10 twice "
                                         r"\(items 0 and 2\)"):
        parse_spec("uv.range:step:1e3@1000+10,uv:step:1e3@1000+10,uv.0:step:1e3@1000+10", COMPS)
    f = Fault("uv", "step", 1.0, 1.0, 1.0)
    for call in (lambda: inject(T, np.zeros(20), [f, f], "uv"),
                 lambda: fault_mask(T, [f, f], "uv"), lambda: format_spec([f, f], COMPS)):
        with pytest.raises(ValueError, match=r"^faults lists uv:step:1@1\+1 twice \(items 0 and 1\)"):
            call()


@pytest.mark.parametrize("faults, match", [
    (Fault("uv", "step", 1.0, 1.0, 1.0), r"^faults must be a sequence of Fault, got one Fault"),
    ("uv:step:1@1+1", r"^faults must be a sequence of Fault, got the string .*parse_spec"),
    (["uv:step:1@1+1"], r"^faults\[0\] must be a Fault, got 'uv:step:1@1\+1' \(a spec"),
    (5, r"^faults must be a sequence of Fault, got int 5"),
    ({"uv": 1}, r"^faults must be a sequence of Fault, got dict"),
])
def test_a_schedule_that_is_not_a_list_of_faults_is_refused_by_name(faults, match):
    for call in (lambda: check_faults("faults", faults), lambda: inject(T, np.zeros(20), faults, "uv"),
                 lambda: fault_mask(T, faults, "uv"), lambda: format_spec(faults, COMPS)):
        with pytest.raises(ValueError, match=match):
            call()


def test_format_spec_names_a_component_or_sensor_it_has_no_name_for():
    with pytest.raises(ValueError, match=r"^faults\[0\]: component must be in \[0, 3\] for "
                                         r"sensor 'uv' \(components\['uv'\]: .*\), got 99"):
        format_spec([Fault("uv", "step", 1.0, 10.0, 5.0, 99)], COMPS)
    with pytest.raises(ValueError, match=r"^faults\[0\]: sensor 'gps' has no component names"):
        format_spec([Fault("gps", "step", 1.0, 10.0, 5.0)], COMPS)
    for bad in ("uv", ["uv"], {"uv": "range"}):
        with pytest.raises(ValueError, match=r"^components(\[.uv.\])? must be a (dict of sensor "
                                             r"name|non-empty list)"):
            parse_spec("uv:step:1@1+1", bad)


def test_an_empty_series_takes_a_schedule_and_stays_empty():
    out = inject(np.zeros(0), np.zeros((0, 3)), [Fault("uv", "step", 1.0, 1.0, 1.0)], "uv")
    assert out.shape == (0, 3)


def test_sample_times_and_measurements_are_checked_before_injection():
    f = Fault("uv", "step", 1.0, 1.0, 1.0)
    with pytest.raises(ValueError, match="^z must hold real numbers"):
        inject(np.arange(3.0), np.zeros(3) + 1j, [f], "uv")
    with pytest.raises(ValueError, match="^t must contain only finite"):
        fault_mask([0.0, np.nan], [f], "uv")
    with pytest.raises(ValueError, match="^t must hold real numbers"):
        f.active([1j])


@pytest.mark.parametrize("spec, items", [
    ("uv.range:step:1e3@1000+10,uv:step:1e3@1000+10", "0 (uv.range:step:1000@1000+10) and 1 "
                                                      "(uv:step:1000@1000+10)"),
    ("uv.range:step:1e3@1000+100,uv.range:step:2e3@1050+100", "0 (uv.range:step:1000@1000+100) "
                                                              "and 1 (uv.range:step:2000@1050+100)"),
    ("xnav.1:spike:1@9+0,uv:spike:1@5+0,xnav:spike:1@9+0", "0 (xnav.1:spike:1@9+0) and 2 "
                                                           "(xnav:spike:1@9+0)")])
def test_two_faults_on_one_component_at_one_time_are_refused_naming_both(spec, items):
    """uv.range and uv (every component) at one time were injected twice, one alarm scored as
    two detections; the parsed faults of one kind are compared, not the strings (a ramp beside
    a step, the affine fault a t + b, combines: below)."""
    with pytest.raises(ValueError, match=re.escape(f"spec items {items} act on the same "
                                                   "component at the same time")):
        parse_spec(spec, COMPS)
    ok = "uv.range:step:1e3@1000+10,uv.ux:step:1e3@1000+10,uv.range:step:1e3@1010+10"
    assert len(parse_spec(ok, COMPS)) == 3  # another component, or the next window: fine


def test_faults_of_different_kinds_on_one_component_combine():
    """The pseudolite chapter's ramp counted from its onset: a step of b and a ramp of a."""
    faults = parse_spec("uv.range:ramp:10@30+100,uv.range:step:-300@30+100", COMPS)
    assert [f.kind for f in faults] == ["ramp", "step"]


@pytest.mark.parametrize("kind", ["step", "ramp", "spike", "noise"])
def test_a_fault_beyond_max_size_is_refused_naming_its_magnitude(kind):
    """Review 35b N7: a ramp of 1e308 per s overflowed into 'x must contain only finite numbers'
    after a numpy overflow warning; every kind is bounded by MAX_SIZE."""
    with pytest.raises(ValueError, match=rf"^magnitude of a {kind} fault must be at most 1e\+15"):
        Fault("uv", kind, -1e308 if kind != "noise" else 1e308, 0.0, 10.0)
    assert Fault("uv", kind, MAX_SIZE, 0.0, 10.0).magnitude == MAX_SIZE
    with pytest.raises(ValueError, match=r"^spec: bad fault item 'uv.range:ramp:1e308@1000\+10': magnitude"):
        parse_spec("uv.range:ramp:1e308@1000+10", COMPS)


def test_a_ramp_that_grows_beyond_max_size_is_refused_by_inject_naming_it():
    t = np.array([0.0, 10.0, 2e3])
    ok = Fault("uv", "ramp", 1e12, 0.0)
    assert np.isfinite(inject(t[:2], np.zeros(2), [ok], "uv")).all()
    with pytest.raises(ValueError, match=r"^faults\[1\]: a ramp of 1e\+12 per s from 0 s reaches "
                                         r"2e\+15 by t = 2000 s, beyond MAX_SIZE = 1e\+15"):
        inject(t, np.zeros(3), [Fault("cns", "step", 1.0, 0.0), ok], "uv")


@pytest.mark.parametrize(("call", "match"), [
    (lambda: check_faults(True, []), r"^name must be"),
    (lambda: check_faults("faults", np.array(1.0)), r"^faults must be a sequence of Fault, got ndarray"),
    (lambda: fault_mask([0.0], np.array(1.0), "uv"), r"^faults must be a sequence of Fault"),
    (lambda: fault_mask([0.0], [], True), r"^sensor must be"),
    (lambda: inject(np.arange(5.0), -0.0, [], "uv"), r"^z must have shape .* = len\(t\) = 5"),
    (lambda: inject(np.arange(5.0), [1.0], [], "uv"), r"^z must have shape"),
    (lambda: inject([1.0], np.zeros(5), [], "uv"), r"^t must hold one time per row of z \(5\), got 1"),
    (lambda: inject(np.arange(5.0), np.zeros(5), [], []), r"^sensor must be"),
    (lambda: format_spec([], {"uv": ["range"]}), r"^faults must hold at least one Fault"),
])
def test_an_edge_input_is_refused_naming_it(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_inject_refuses_times_going_back_and_z_of_three_dimensions():
    """Review 35j (5) 24: inject took decreasing times (documented increasing) and a z of
    shape (5, 2, 2) (documented (n,) or (n, m))."""
    ramp = [Fault("uv", "ramp", 1.0, 2.0)]
    with pytest.raises(ValueError, match=r"^t must be strictly increasing .*t\[1\] = 3 after t\[0\] = 4"):
        inject(np.arange(5.0)[::-1], np.zeros(5), ramp, "uv")
    with pytest.raises(ValueError, match=r"^z must have shape \(n,\) or \(n, m\) with n = len\(t\) = 5, "
                                         r"got shape \(5, 2, 2\)"):
        inject(np.arange(5.0), np.zeros((5, 2, 2)), [Fault("uv", "step", 1.0, 2.0)], "uv")
    with pytest.raises(ValueError, match=r"^faults\[1\]: component must be in \[0, 1\] for sensor "
                                         r"'uv' \(the columns of z\), got 2"):
        inject(np.arange(5.0), np.zeros((5, 2)), [Fault("cns", "step", 1.0, 2.0),
                                                  Fault("uv", "step", 1.0, 2.0, component=2)], "uv")


def test_a_fault_stores_the_checked_python_numbers():
    """Review 35k (1) 1 and (5) 2: a Fault kept the user's numpy scalar (np.float16, np.int8);
    its end time onset + duration then overflowed float16 (a RuntimeWarning)."""
    f = Fault(np.str_("uv"), "step", np.float16(5000.0), np.int8(100), np.float16(5.0),
              np.int8(0))
    assert [type(v) for v in (f.sensor, f.magnitude, f.onset, f.duration, f.component)] == \
        [str, float, float, float, int]
    assert (f.magnitude, f.onset, f.end, f.component) == (5000.0, 100.0, 105.0, 0)
    assert Fault("uv", "step", 1.0, 0.0, 10**400).duration == math.inf   # permanent
    with pytest.raises(ValueError, match=r"^magnitude must be a finite real number"):
        Fault("uv", "step", 10**400, 0.0, 1.0)


@pytest.mark.parametrize(("components", "match"), [
    (-1, r"^components must be a dict of sensor name .*, got int -1"),
    (math.nan, r"^components must be a dict"),
    ("x", r"^components must be a dict"),
    (True, r"^components must be a dict"),
    ([], r"^components must be a dict"),
    ({}, r"^components must be a dict .*got an empty dict"),
    ({"uv": []}, r"^components\['uv'\] must be a non-empty list of component names"),
    ({"cns": ["a"]}, r"^faults\[0\]: sensor 'uv' has no component names in components \(known: cns\)"),
    ({"uv": ["range"], "cns": ["a"]}, r"^faults\[0\]: component must be in \[0, 0\] for sensor 'uv' "
                                      r"\(components\['uv'\]: range\), got 2"),
])
def test_check_faults_checks_its_components(components, match):
    """Review 35k (5) 1: check_faults never checked components (-1, NaN, 'x', a table without
    the faults' sensor were accepted)."""
    with pytest.raises(ValueError, match=match):
        check_faults("faults", [Fault("uv", "step", 5.0, 1.0, 2.0, 2)], components)


def test_parse_spec_leads_with_spec_and_refuses_an_empty_components_table():
    """Review 35k (3) 16 and (5) 11: parse_spec's messages began 'bad fault item', never naming
    spec; an empty components table was accepted and then blamed on the spec ('unknown sensor
    'uv' (known: )')."""
    with pytest.raises(ValueError, match=r"^spec: bad fault item 'x': expected SENSOR"):
        parse_spec("x", {"uv": ["range"]})
    for bad in (None, "", " ", 5):
        with pytest.raises(ValueError, match=r"^spec must be a non-empty string of fault items"):
            parse_spec(bad, {"uv": ["range"]})
    with pytest.raises(ValueError, match=r"^components must be a dict .*got an empty dict"):
        parse_spec("uv.range:step:5@1+2", {})


def _acts_with(a, b):
    """Every-pair reading of an overlap: one kind, one sensor, one component (None: every one),
    and one instant (two spikes) or windows [onset, end) that meet."""
    if a.kind != b.kind or a.sensor != b.sensor or \
            None not in (a.component, b.component) and a.component != b.component:
        return False
    if a.kind == "spike":
        return a.onset == b.onset
    return a.onset < b.end and b.onset < a.end


ONE_FAULT = st.builds(
    lambda sensor, kind, comp, onset, dur: Fault(sensor, kind, 1.0, onset, dur, comp),
    st.sampled_from(["uv", "cns"]), st.sampled_from(["step", "ramp", "spike"]),
    st.one_of(st.none(), st.integers(0, 2)),
    st.sampled_from([0.0, 1.0, 2.0, 3.0, 4.5, 1e17, 1e17 + 16.0]),
    st.sampled_from([1e-300, 0.5, 1.0, 2.0, 5.0, math.inf]))


@given(st.lists(ONE_FAULT, max_size=12))
def test_the_overlap_check_refuses_exactly_what_a_check_of_every_pair_refuses(faults):
    """Review 35 R12: the check compared every pair (quadratic); it now sweeps the faults once
    in time order. It refuses a schedule exactly when some pair overlaps (windows empty in
    floating point, 1e17 + 1e-300, included), and the two items it names do overlap."""
    faults = list(dict.fromkeys(faults))   # a fault listed twice has its own refusal
    pairs = {(i, j) for j in range(len(faults)) for i in range(j) if _acts_with(faults[i], faults[j])}
    if not pairs:
        assert check_faults("faults", faults) == faults
        return
    with pytest.raises(ValueError, match=r"act on the same component at the same time") as info:
        check_faults("faults", faults)
    named = re.match(r"^faults items (\d+) \(.*\) and (\d+) \(", str(info.value))
    assert (int(named[1]), int(named[2])) in pairs


class _CountedFault(Fault):
    """A Fault that counts the reads of its end time (each comparison of two windows reads it)."""

    reads = 0

    @property
    def end(self):
        type(self).reads += 1
        return self.onset + self.duration


def test_the_overlap_check_compares_each_fault_with_a_few_others_not_with_all():
    """Review 35 R12: 2,000 faults in one Mars run took 25 s (8,000 over 2 min), about 13 checks
    of all n (n - 1) / 2 pairs; a sweep reads each fault's end a few times (not n times)."""
    n = 2000
    faults = [_CountedFault("uv", "step", 1.0, 10.0 * i + 5.0 * (i % 2), 5.0, None if i % 2 else 0)
              for i in range(n)]
    _CountedFault.reads = 0
    assert len(check_faults("faults", faults)) == n
    assert _CountedFault.reads <= 10 * n   # every pair: about n ** 2 = 4e6 reads
    late = _CountedFault("uv", "step", 2.0, 10.0 * 1500 + 2.0, 1.0, 0)   # inside item 1500
    with pytest.raises(ValueError, match=r"^faults items 1500 \(uv.range:step:1@15000\+5\) and "
                                         r"2000 \(uv.range:step:2@15002\+1\) act on the same "
                                         r"component at the same time"):
        check_faults("faults", faults + [late], {"uv": ["range"]})
