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
