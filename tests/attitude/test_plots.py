"""The attitude figures (xnavlab.attitude.plots): residual plots and the fault-case figure."""


import dataclasses

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


@pytest.mark.parametrize(("change", "words"), [
    (lambda run: {"sos_r": run.sos_r[:10]},
     r"^AttitudeRun\.sos_r must have shape \(501, 4\) \(n = config\.n = 501 samples\), got shape \(10, 4\)$"),
    (lambda run: {"sos": None},
     r"^AttitudeRun\.sos must be the run's Diagnosis, flags of shape \(501, 4\), got NoneType$"),
    (lambda run: {"sos_r": run.sos_r * float("nan")},
     r"^AttitudeRun\.sos_r must contain only finite numbers \(no NaN or inf\)$"),
    (lambda run: {"dos": None},
     r"^AttitudeRun\.dos must be the run's Diagnosis, flags of shape \(501, 4\) \(config\.dos is True\)"),
    (lambda run: {"sos_J": run.sos_J[:2]}, r"^AttitudeRun\.sos_J must have shape \(4,\)"),
    (lambda run: {"armed": run.armed.astype(float)}, r"^AttitudeRun\.armed must be a boolean array"),
    (lambda run: {"onset": float("nan")}, r"^AttitudeRun\.onset must be a time, s, or inf"),
    (lambda run: {"qd_f": run.qd_f[:5]}, r"^AttitudeRun\.qd_f must have shape \(\d+, 3\)"),
    (lambda run: {"sos": dataclasses.replace(run.sos, flags=run.sos.flags[:10])},
     r"^AttitudeRun\.sos must be the run's Diagnosis, flags of shape \(501, 4\), got flags of "
     r"shape \(10, 4\)$"),
    (lambda run: {"sos": dataclasses.replace(run.sos, detect_time=float("nan"))},
     r"^Diagnosis\.detect_time must be a time, s, or inf \(none\), shape \(\)"),
    (lambda run: {"sos": dataclasses.replace(run.sos, verdict=3)},
     r"^Diagnosis\.verdict must be a str \(a verdict of the decision rule\), got 3$"),
])
def test_an_edited_run_is_refused_naming_its_field(change, words):
    """Review 35p P11: plot_residuals on an AttitudeRun edited with dataclasses.replace gave
    numpy's IndexError (sos_r cut), an AttributeError (sos=None) or an empty figure (NaN);
    the run (and its Diagnosis) checks its fields when made, naming AttitudeRun.<field>."""
    run = att.simulate(duration=50.0)
    with pytest.raises(ValueError, match=words):
        att.plot_residuals(dataclasses.replace(run, **change(run)))


def test_a_run_and_its_diagnosis_are_frozen():
    """Review 35p P11: checked when made, so not assignable after (an assigned field would
    skip the check)."""
    run = att.simulate(duration=50.0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        run.sos_r = run.sos_r[:10]
    with pytest.raises(dataclasses.FrozenInstanceError):
        run.sos.verdict = "gyro_x"
