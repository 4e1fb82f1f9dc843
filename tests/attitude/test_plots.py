"""The attitude figures (xnavlab.attitude.plots): residual plots and the fault-case figure."""


import matplotlib.pyplot as plt
import numpy as np
import pytest

from xnavlab import attitude as att

DPH = att.DEG_PER_H


@pytest.fixture(scope="module")
def nominal():
    return att.simulate()


@pytest.mark.parametrize("method", ["sos", "dos", "qdiff"])
def test_plot_residuals(nominal, method):
    fig = att.plot_residuals(nominal, method)
    assert len(fig.axes) == (3 if method == "qdiff" else 4)
    plt.close(fig)


def test_plot_residuals_bad_input(nominal):
    with pytest.raises(ValueError, match="^method"):
        att.plot_residuals(nominal, "gos")
    with pytest.raises(ValueError, match="^run"):
        att.plot_residuals("run")


def test_plot_fault_case_is_simulate_plus_plot_residuals():
    from matplotlib.figure import Figure

    before = plt.get_fignums()
    fig = att.plot_fault_case("gyro_y", "ramp", 10.0, n_sigma=4.0)
    assert isinstance(fig, Figure) and plt.get_fignums() == before  # not left in pyplot
    run = att.simulate(att.make_fault("gyro_y", "ramp", 10.0 * att.DEFAULT_MAGNITUDES[("gyro", "ramp")]),
                       n_sigma=4.0)
    assert len(fig.axes) == 8
    sos_axes, dos_axes = fig.axes[0::2], fig.axes[1::2]   # subplots(4, 2): row-major
    for i in range(4):
        np.testing.assert_allclose(sos_axes[i].lines[0].get_ydata(), run.sos_r[:, i] / DPH)
        np.testing.assert_allclose(dos_axes[i].lines[0].get_ydata(), run.dos_r[:, i] / DPH)
    assert sos_axes[0].get_title().startswith(f"SOS: verdict {att.location_name(run.sos.verdict)}")
    st_fig = att.plot_fault_case("star_tracker", "step", 1.0)
    assert "truth star tracker" in st_fig.axes[0].get_title()


@pytest.mark.parametrize(("kwargs", "name"), [
    ({"location": "gyro_w"}, "location"),
    ({"kind": "spike"}, "kind"),
    ({"size": 0.0}, "size"),
    ({"n_sigma": -1.0}, "n_sigma"),
])
def test_plot_fault_case_bad_input(kwargs, name):
    with pytest.raises(ValueError, match=rf"\b{name}\b"):
        att.plot_fault_case(**kwargs)


def test_location_name_gives_plain_words_for_every_verdict():
    from xnavlab.attitude.diagnosis import VERDICTS

    names = [att.location_name(v) for v in VERDICTS]
    assert all("_" not in n for n in names) and len(set(names)) == len(VERDICTS)
    assert att.location_name("gyro_x") == "x gyro" and att.location_name("new_thing") == "new thing"


def test_location_name_takes_text_only():
    """Issue 35: True was spelled 'True', a list its repr."""
    for bad in (True, [], 1.0):
        with pytest.raises(ValueError, match=r"^name must be text \(a str\)"):
            att.location_name(bad)


def test_plot_fault_case_takes_a_multiple_from_a_millionth():
    """Issue 35: a subnormal multiple made a zero-size fault, refused under make_fault's name."""
    with pytest.raises(ValueError, match=r"^size must be a real number in \[1e-06, 1000\], got 5e-324$"):
        att.plot_fault_case("gyro_x", "step", 5e-324)


def test_plot_residuals_refuses_axes_of_the_wrong_kind_or_count():
    run = att.simulate(duration=50.0, rng=0)
    fig, ax = plt.subplots()
    try:
        for axes in ([ax], "ax"):
            with pytest.raises(ValueError, match=r"^axes must be a sequence of 4 matplotlib Axes"):
                att.plot_residuals(run, axes=axes)
    finally:
        plt.close(fig)


@pytest.mark.parametrize("n_sigma", [5e-324, 100.0, None, "1.0", True])
def test_plot_fault_case_names_n_sigma_not_the_tail_probability(n_sigma):
    """Review 35k (3) 13: n_sigma=5e-324 was refused as 'p must be a real number in (0, 1),
    got 1.0' (the thresholds' tail probability, an inner name)."""
    with pytest.raises(ValueError, match=r"^n_sigma must be a real number in \[0.01, 30\]"):
        att.plot_fault_case("gyro_x", "step", 1.0, n_sigma=n_sigma)


def test_plot_residuals_refuses_extra_3d_or_foreign_axes():
    """Review 35m (1) 3, the rule of every plot's axes: a 3-D or polar Axes was matplotlib's
    error mid-plot, a fifth Axes was ignored without a word, Axes of two figures returned
    the first's."""
    from matplotlib.figure import Figure

    run = att.simulate(duration=50.0, rng=0)
    fig = Figure()
    four = list(fig.subplots(4, 1))
    with pytest.raises(ValueError, match=r"^axes must be a sequence of 4 matplotlib Axes"):
        att.plot_residuals(run, axes=four + [fig.add_subplot(5, 1, 5)])
    with pytest.raises(ValueError, match=r"^axes\[2\] must be a 2-D rectilinear matplotlib Axes, got a '3d'"):
        att.plot_residuals(run, axes=four[:2] + [Figure().add_subplot(projection="3d")] + four[3:])
    with pytest.raises(ValueError, match=r"^axes\[3\] must be an Axes of the same figure"):
        att.plot_residuals(run, axes=four[:3] + [Figure().subplots()])
    assert not any(a.lines for a in four)  # refused before anything was drawn
    assert att.plot_residuals(run, axes=four) is fig
