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
    ({"sizes": [1.0, -2.0]}, r"^sizes\[1\] must be a real number in \(0, inf\)"),
])
def test_an_empty_or_repeated_list_is_refused_not_a_table_without_its_rows(kw, words):
    """Review 35b N23's class: an empty list left only the fault-free rows, without a word."""
    with pytest.raises(ValueError, match=words):
        att.isolation_monte_carlo(1, **kw)
