"""xnavlab.core.widgets: the live widget and the kernel-free HTML scrubber."""

import base64
import io
import json
import re
from decimal import Decimal
from fractions import Fraction

import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.figure import Figure

from xnavlab.core import widgets
from xnavlab.core._ahead import distance
from xnavlab.core._frames import FRAME_CACHE_ENV, DiskFrames
from xnavlab.core.widgets import explore

CALLS = []


@pytest.fixture(autouse=True)
def no_worker_unless_asked(monkeypatch):
    """Tests that fake a kernel would get the ahead worker by default: off unless a test
    asks for it with ``explore(..., ahead=True)`` (its calls are then counted in CALLS).
    The frames on disk are off too, unless a test turns them on (with its own cache)."""
    monkeypatch.setenv(widgets.AHEAD_ENV, "0")
    monkeypatch.setenv(FRAME_CACHE_ENV, "0")


def wave(omega=1.0, phase=0.0, style="-", title=""):
    CALLS.append((omega, phase, style))
    fig = Figure(figsize=(3, 2))
    t = np.linspace(0.0, 10.0, 100)
    ax = fig.add_subplot()
    ax.plot(t, np.sin(omega * t + phase), style)
    ax.set_title(title)
    return fig


def pyplot_wave(omega=1.0):
    fig, ax = plt.subplots(figsize=(3, 2))
    ax.plot([0, 1], [0, omega])
    return fig


def scrubber_data(html):
    m = re.search(r'<script type="application/json" class="xnav-scrubber-data">(.*?)</script>',
                  html, re.S)
    return json.loads(m.group(1))


def test_frames_cover_grid_and_start_at_initial():
    ex = explore(wave, omega=np.linspace(1.0, 2.0, 21), phase=0.5, max_frames=5)
    assert ex.frame_values == [1.0, 1.25, 1.5, 1.75, 2.0]
    assert ex.initial == {"omega": 1.5}
    assert ex.fixed == {"phase": 0.5}
    html = ex.html()
    data = scrubber_data(html)
    assert len(data["frames"]) == 5
    assert data["labels"][2] == "omega = 1.5"
    assert 'value="2"' in html and "<output>omega = 1.5</output>" in html
    # every frame is a real PNG and the <img> opens on the initial one
    for uri in data["frames"]:
        assert base64.b64decode(uri.split(",", 1)[1])[:8] == b"\x89PNG\r\n\x1a\n"
    assert f'src="{data["frames"][2]}"' in html


def test_explicit_initial_is_a_frame_and_others_held():
    CALLS.clear()
    ex = explore(wave, omega=[1, 2, 3, 4, 5, 6, 7], phase=[0.0, 1.0], main="omega",
                 initial={"omega": 2, "phase": 1.0}, max_frames=3)
    assert 2 in ex.frame_values and len(ex.frame_values) == 3
    ex.frames()
    assert {c[1] for c in CALLS} == {1.0}  # the other grid is held at its initial value
    assert sorted(c[0] for c in CALLS) == sorted(ex.frame_values)
    ex.frames()  # cached
    assert len(CALLS) == 3


def test_frames_close_their_figures():
    before = plt.get_fignums()
    explore(pyplot_wave, omega=[1.0, 2.0, 3.0]).frames()
    assert plt.get_fignums() == before


def test_plain_scalars_passed_to_plot():
    ex = explore(wave, omega=np.array([1, 2]), style="--")
    assert all(type(v) is int for v in ex.frame_values)
    CALLS.clear()
    ex.frames()
    assert CALLS[0][2] == "--"


def test_html_is_safe_to_embed():
    ex = explore(wave, title=["a", "</script>"], max_frames=2)
    html = ex.html()
    assert html.count("</script>") == 1  # only the data block's own end tag
    assert scrubber_data(html)["labels"][1] == "title = </script>"


def test_mimebundle_outside_kernel_is_html_only():
    bundle = explore(wave, omega=[1.0, 2.0])._repr_mimebundle_()
    assert set(bundle) == {"text/plain", "text/html"}
    assert bundle["text/plain"].startswith("Explorer(wave, main='omega', 2 frames")


def test_mimebundle_in_kernel_adds_widget(monkeypatch):
    monkeypatch.setattr(widgets, "_in_kernel", lambda: True)
    ex = explore(wave, omega=[1.0, 2.0, 3.0], style=["-", ":"])
    bundle = ex._repr_mimebundle_()
    assert widgets._MIME_WIDGET in bundle and "text/html" in bundle
    w = ex.widget()
    assert w is ex.widget()
    sliders = {c.description: c for c in w.children[:-1]}
    assert sliders["omega"].continuous_update is False
    assert sliders["omega"].value == 2.0 and sliders["style"].value == "-"
    w.close()


def test_kernel_outside_the_book_draws_one_figure(monkeypatch):
    # a reader's kernel (or nbval's): the HTML part is the widget's opening figure, drawn once
    monkeypatch.setattr(widgets, "_in_kernel", lambda: True)
    monkeypatch.delenv(widgets.FRAMES_ENV, raising=False)
    CALLS.clear()
    ex = explore(wave, omega=np.linspace(0.5, 3.0, 11), max_frames=6)
    bundle = ex._repr_mimebundle_()
    page = bundle["text/html"]
    assert widgets._MIME_WIDGET in bundle
    assert "xnav-scrubber" not in page and page.count("<img") == 1
    assert ex._frames is None and CALLS == [(ex.initial["omega"], 0.0, "-")]
    png = base64.b64decode(re.search(r'base64,([^"]+)"', page).group(1))
    assert png == ex._last_png and png.startswith(b"\x89PNG")
    ex.widget().close()


def test_kernel_building_the_book_draws_the_frames(monkeypatch):
    monkeypatch.setattr(widgets, "_in_kernel", lambda: True)
    monkeypatch.setenv(widgets.FRAMES_ENV, "1")
    ex = explore(wave, omega=np.linspace(0.5, 3.0, 11), max_frames=6)
    bundle = ex._repr_mimebundle_()
    assert len(scrubber_data(bundle["text/html"])["frames"]) == 6
    # no live widget: the HTML book cannot drive one, and its opening figure would be one
    # more output of the cell where nbval executes the page for the book
    assert widgets._MIME_WIDGET not in bundle and ex._widget is None


def test_kernel_still_html_names_an_opening_error(monkeypatch):
    monkeypatch.setattr(widgets, "_in_kernel", lambda: True)
    monkeypatch.delenv(widgets.FRAMES_ENV, raising=False)

    def broken(a=1.0):
        raise ValueError("a must be in [0, 1], got 1.5")

    ex = explore(broken, a=[1.0, 2.0])
    page = ex._repr_mimebundle_()["text/html"]
    assert 'class="xnav-error"' in page and "a must be in [0, 1]" in page
    ex.widget().close()


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"phase": 0.0}, "at least one parameter grid"),
        ({"omega": []}, "omega is an empty grid"),
        ({"omega": [1.0], "main": "phase"}, "main must be one of"),
        ({"omega": [1.0, 2.0], "initial": {"omega": 1.5}}, r"initial\['omega'\] must be one of"),
        ({"omega": [1.0], "initial": {"nope": 1}}, r"initial\['nope'\] is not a grid parameter"),
        ({"omega": [1.0], "max_frames": 1}, "max_frames"),
        ({"omega": [1.0], "dpi": 1000}, "dpi"),
    ],
)
def test_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        explore(wave, **kwargs)


def test_plot_must_return_figure():
    with pytest.raises(ValueError, match="plot must return a matplotlib Figure"):
        explore(lambda omega: None, omega=[1.0]).frames()
    with pytest.raises(ValueError, match="plot must be a function"):
        explore(3, omega=[1.0])


def test_widget_marks_its_parts_for_the_browser_test(monkeypatch):
    """Stable CSS classes: the lab test (tests/lab/) finds the main slider and the figure."""
    ex = explore(wave, omega=[1.0, 2.0, 3.0], style=["-", ":"], main="omega")
    w = ex.widget()
    assert "xnav-explore" in w._dom_classes
    controls = [c for c in w.children if "xnav-control" in c._dom_classes]
    assert [c.description for c in controls] == ["omega", "style"]
    assert [c.description for c in w.children if "xnav-main" in c._dom_classes] == ["omega"]
    assert w.children[-2] is ex.status and "xnav-status" in ex.status._dom_classes
    assert w.children[-1] is w.out and "xnav-output" in w.out._dom_classes
    w.close()


def test_widget_says_computing_while_it_redraws():
    seen = []

    def slow(omega=1.0):
        seen.append(ex.status.value)  # what the browser shows during the call
        return wave(omega)

    ex = explore(slow, omega=[1.0, 2.0, 3.0])
    w = ex.widget()  # draws once at the initial value
    controls = [c for c in w.children if "xnav-control" in c._dom_classes]
    controls[0].value = 3.0  # the reader moves the slider: one more redraw
    assert len(seen) == 2
    for value in seen:
        assert widgets.BUSY in value and 'class="xnav-busy"' in value
        assert "0.3s" in value  # shown only once the redraw takes longer than 0.3 s
    assert ex.status.value == ""  # cleared when done
    assert ex.last_error is None
    w.close()


def test_widget_shows_one_line_when_plot_raises(capsys, caplog):
    def fragile(omega=1.0):
        if omega == 3.0:
            raise ValueError("omega must be in [1, 2], got 3.0\nsecond line of detail")
        return wave(omega)

    ex = explore(fragile, omega=[1.0, 2.0, 3.0])
    w = ex.widget()
    controls = [c for c in w.children if "xnav-control" in c._dom_classes]
    capsys.readouterr()
    controls[0].value = 3.0  # raises inside the callback: the widget must not
    out = capsys.readouterr().out
    assert ex.last_error == "error: ValueError: omega must be in [1, 2], got 3.0"
    assert ex.last_error in out and "Traceback" not in out and "second line" not in out
    assert ex.status.value == ""  # not stuck on "computing…"
    assert not [r for r in caplog.records if "Exception in interact callback" in r.message]
    controls[0].value = 2.0  # and the next value draws again
    assert ex.last_error is None
    w.close()


def test_widget_shows_one_line_when_plot_returns_no_figure():
    ex = explore(lambda omega=1.0: None if omega > 1.5 else wave(omega), omega=[1.0, 2.0])
    w = ex.widget()
    [c for c in w.children if "xnav-control" in c._dom_classes][0].value = 2.0
    assert ex.last_error.startswith("error: ValueError: plot must return a matplotlib Figure")
    w.close()


@pytest.mark.parametrize(
    ("exc", "line"),
    [
        (ValueError("bad size"), "error: ValueError: bad size"),
        (KeyError("sensor"), "error: KeyError: 'sensor'"),
        (RuntimeError("  \n  first\nsecond"), "error: RuntimeError: first"),
        (ZeroDivisionError(), "error: ZeroDivisionError"),
    ],
)
def test_error_line(exc, line):
    assert widgets.error_line(exc) == line


def test_error_line_is_short():
    line = widgets.error_line(ValueError("x" * 1000))
    assert len(line) == 300 and line.endswith("\u2026")


def test_live_png_has_the_pixels_of_the_default_png():
    """The live widget's fast zlib level changes the bytes, never the image."""
    from PIL import Image

    fig = Figure(figsize=(3, 2), dpi=60)
    fig.add_subplot().plot(np.arange(50.0) ** 0.5, label="sqrt")
    default = io.BytesIO()
    fig.savefig(default, format="png")
    fast = widgets.live_png(fig)
    assert fast[:8] == b"\x89PNG\r\n\x1a\n"
    a = np.asarray(Image.open(io.BytesIO(fast)))
    b = np.asarray(Image.open(io.BytesIO(default.getvalue())))
    assert a.shape == b.shape and np.array_equal(a, b)


def test_widget_shows_a_position_drawn_before_without_calling_plot_again(capsys):
    """plot is pure: back at a seen position, the kept PNG is shown, not a new draw."""
    calls = []

    def counted(omega=1.0):
        calls.append(omega)
        return wave(omega)

    ex = explore(counted, omega=[1.0, 2.0, 3.0])
    w = ex.widget()                       # draws the opening position, 2.0
    slider = [c for c in w.children if "xnav-control" in c._dom_classes][0]
    slider.value = 3.0
    slider.value = 2.0                    # seen: no call
    slider.value = 3.0                    # seen: no call
    assert calls == [2.0, 3.0]
    assert ex.status.value == "" and ex.last_error is None
    w.close()


def titled(title="a", suptitle=None, panels=1):
    """A constrained-layout figure whose title, like a slider's, changes from frame to frame."""
    fig = Figure(figsize=(4, 2.5), layout="constrained")
    for ax in np.atleast_1d(fig.subplots(1, panels)):
        ax.plot([0.0, 1.0], [0.0, 1e3])
        ax.set(title=title, ylabel="y")
    if suptitle is not None:
        fig.suptitle(suptitle)
    return fig


#: Axes positions are figure fractions computed by the layout engine or copied through a Bbox
#: (x1 = x0 + width, width = x1 - x0): equal positions may differ in the last digit, with the
#: Python and matplotlib versions. 1e-9 of a figure is far below a pixel (6e-7 px at 640 px).
BOX_TOL = 1e-9


def assert_same_box(a, b):
    """Two axes positions (bounds, or a text's xy) equal to far below a pixel."""
    np.testing.assert_allclose(a, b, rtol=0, atol=BOX_TOL)


def png_pixels(png):
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(png)))


def test_steady_layout_gives_the_pixels_of_the_figures_own_layout():
    """Kept from an identical figure, the layout draws the same image as the engine's."""
    steady = widgets.SteadyLayout()
    assert steady.prepare(titled(suptitle="s", panels=2)) == "laid out"
    fig = titled(suptitle="s", panels=2)
    kept = widgets.live_png(fig, steady)
    from matplotlib.layout_engine import PlaceHolderLayoutEngine

    assert isinstance(fig.get_layout_engine(), PlaceHolderLayoutEngine)  # one draw, no engine
    assert np.array_equal(png_pixels(kept), png_pixels(widgets.live_png(
        titled(suptitle="s", panels=2))))


def test_steady_layout_keeps_the_axes_and_suptitle_where_the_first_frame_put_them():
    steady = widgets.SteadyLayout()
    first = titled("a", suptitle="first")
    steady.prepare(first)
    later = titled("a title long enough to move a constrained layout", suptitle="later, longer")
    assert steady.prepare(later) == "kept layout"
    assert_same_box(later.axes[0].get_position().bounds, first.axes[0].get_position().bounds)
    assert_same_box(later.axes[0].get_position(original=True).bounds,
                    first.axes[0].get_position(original=True).bounds)
    assert later.get_suptitle() == "later, longer"
    assert_same_box(later._suptitle.get_position(), first._suptitle.get_position())


def test_steady_layout_lays_out_afresh_a_figure_with_other_axes():
    steady = widgets.SteadyLayout()
    steady.prepare(titled(panels=1))
    two = titled(panels=2)
    assert steady.prepare(two) == "laid out"
    assert steady.prepare(titled(panels=2)) == "kept layout"
    assert steady.prepare(titled(panels=1)) == "laid out"
    bigger = Figure(figsize=(5, 2.5), layout="constrained")
    bigger.add_subplot()
    assert steady.prepare(bigger) == "laid out"


def test_steady_layout_leaves_fixed_margins_alone():
    fig = wave()
    before = fig.axes[0].get_position().bounds
    assert widgets.SteadyLayout().prepare(fig) == "fixed"
    assert fig.axes[0].get_position().bounds == before


def test_scrubber_frames_take_the_opening_frames_layout():
    """The opening frame is drawn first and the others keep its axes positions."""
    drawn = []

    def plot(n=1):
        fig = titled("x" * n)
        drawn.append((n, fig))
        return fig

    ex = explore(plot, n=[1, 30, 60], initial={"n": 30})
    ex.frames()
    assert [n for n, _ in drawn] == [30, 1, 60]
    opening = drawn[0][1].axes[0].get_position().bounds
    for _, fig in drawn[1:]:
        assert_same_box(fig.axes[0].get_position().bounds, opening)


def test_frames_drawn_on_a_shared_renderer_carry_nothing_of_the_frame_before():
    """Frames of one size share an Agg renderer (its text metrics): each image is its own."""
    steady = widgets.SteadyLayout()
    widgets.live_png(titled("first frame, with a long title", panels=2), steady)
    for title in ("b", "first frame, with a long title"):
        fig = titled(title, panels=2)
        shared = widgets.live_png(fig, steady)
        own = widgets.live_png(titled(title, panels=2))
        if steady.last == "kept layout" and title == "b":
            continue  # kept positions differ from b's own layout: compared below
        assert np.array_equal(png_pixels(shared), png_pixels(own)), title
    blank = Figure(figsize=(4, 2.5), layout="constrained")
    assert np.array_equal(png_pixels(widgets.live_png(blank, widgets.SteadyLayout())),
                          png_pixels(widgets.live_png(Figure(figsize=(4, 2.5)))))


def test_a_slider_whose_layout_keeps_changing_lays_out_every_frame():
    """Each larger y label needs more room than the kept layout gives: a misfit each time."""
    def labelled(size):
        fig = Figure(figsize=(4, 2.5), layout="constrained")
        fig.add_subplot().set_ylabel("y", fontsize=size)
        return fig

    steady = widgets.SteadyLayout()
    steady.png(labelled(10))
    assert steady.last == "laid out"
    steady.png(labelled(10))
    assert steady.last == "kept layout"
    for k, size in enumerate([40, 80][: widgets.MAX_MISFITS], start=1):
        steady.png(labelled(size))
        assert (steady.last, steady.misfits) == ("laid out again", k)
    steady.png(labelled(10))
    assert steady.last == "laid out"


def test_the_shared_renderer_keeps_no_figure_alive():
    import gc
    import weakref

    steady = widgets.SteadyLayout()
    fig = titled("kept alive?")
    widgets.live_png(fig, steady)
    ref = weakref.ref(fig)
    del fig
    gc.collect()
    assert ref() is None


# -- frames computed ahead -------------------------------------------------------------------
def counted_titled(calls):
    def plot(n=1, style="a"):
        calls.append((n, style))
        return titled("x" * n + style)
    return plot


def test_the_worker_draws_every_position_and_a_move_onto_one_is_a_lookup():
    calls = []
    ex = explore(counted_titled(calls), n=[1, 2, 3, 4], style=["a", "b"], ahead=True,
                 initial={"n": 2, "style": "a"})
    w = ex.widget()
    assert ex._worker.idle(timeout=120)  # nothing left to draw: the thread has ended
    assert sorted(calls) == sorted({(n, s) for n in [1, 2, 3, 4] for s in "ab"})
    drawn = len(calls)
    slider, menu = [c for c in w.children if "xnav-control" in c._dom_classes]
    slider.value = 4
    menu.value = "b"
    assert len(calls) == drawn and ex.last_error is None  # no call: served from the cache
    w.close()


def test_the_worker_draws_the_positions_one_control_away_first_nearest_first():
    calls = []
    ex = explore(counted_titled(calls), n=[1, 2, 3, 4, 5], style=["a", "b", "c"], ahead=True,
                 initial={"n": 3, "style": "b"})
    w = ex.widget()
    assert ex._worker.idle(timeout=120)
    order = [(n - 1, "abc".index(s)) for n, s in calls[1:]]  # after the opening frame
    keys = [distance((2, 1), p) for p in order]
    assert keys == sorted(keys)
    assert keys[:4] == [(1, 1)] * 4 and keys[4:6] == [(1, 2)] * 2
    w.close()


def test_closing_the_widget_stops_the_worker():
    calls = []
    ex = explore(counted_titled(calls), n=list(range(1, 60)), ahead=True)
    w = ex.widget()
    w.close()
    assert ex._worker.stopped and ex._worker.idle(timeout=60)
    n = len(calls)
    assert n < 59  # stopped long before the end (at most its current frame after close)


def test_frames_drawn_ahead_are_the_frames_drawn_at_a_move():
    seen = {}
    for ahead in (False, True):
        ex = explore(titled, title=["a", "a longer title", "b"], ahead=ahead)
        w = ex.widget()
        if ahead:
            assert ex._worker.idle(timeout=120)
        control = [c for c in w.children if "xnav-control" in c._dom_classes][0]
        for title in ("b", "a"):
            control.value = title
            seen.setdefault(title, []).append(ex._last_png)
        w.close()
    for title, (moved, ahead) in seen.items():
        assert np.array_equal(png_pixels(moved), png_pixels(ahead)), title


def test_the_worker_leaves_the_scrubber_as_it_was(monkeypatch):
    monkeypatch.setattr(widgets, "_in_kernel", lambda: True)
    monkeypatch.setenv(widgets.FRAMES_ENV, "1")
    pages = []
    for ahead in (False, True):
        ex = explore(titled, title=["a", "a longer title", "b", "c"], ahead=ahead)
        ex.widget()
        if ahead:
            assert ex._worker.idle(timeout=120) and ex._worker.computed == 3
        pages.append(ex._repr_mimebundle_()["text/html"])
        ex.close()
    assert pages[0] == pages[1]


def test_the_worker_is_off_by_default_outside_a_kernel_and_for_pyplot_figures():
    ex = explore(wave, omega=[1.0, 2.0])
    ex.widget()
    assert ex._worker is None and not widgets.ahead_default()
    ex.close()
    ex = explore(pyplot_wave, omega=[1.0, 2.0, 3.0], ahead=True)
    ex.widget()
    assert ex._worker is None  # pyplot's state is not safe in a second thread
    ex.close()


# -- figures updated in place ----------------------------------------------------------------
def in_place_sliders():
    """Every slider whose plotting function has an in-place update, as its chapter calls it
    (each control's grid cut to a few values; shorter runs where a fixed argument allows)."""
    from xnavlab import attitude as att
    from xnavlab.core import detection, montecarlo
    from xnavlab.line import track
    from xnavlab.mars.models import dynamics, sensors
    from xnavlab.mars.navigation import plots
    from xnavlab.mars.timing import photon_plots, toa
    from xnavlab.mars.timing.pulsars import PAPER_RANGING_M
    from xnavlab.plins import parity
    from xnavlab.robust import plots as rplots

    return [
        pytest.param(track.plot_tracking, dict(exposure_s=[10.0, 20.0, 1000.0],
                                               accel_sigma=[0.0, 0.03]), id="plot_tracking"),
        pytest.param(photon_plots.plot_ranging_accuracy,
                     dict(area_m2=[0.01, 1.0, 10.0], t_obs=[10.0, 500.0, 1e5],
                          background_ph_cm2_s=[0.0, 0.005, 0.05], reference=PAPER_RANGING_M),
                     id="plot_ranging_accuracy"),
        pytest.param(photon_plots.plot_fix, dict(offset_km=[0.0, 100.0, 1458.6, 2000.0]),
                     id="plot_fix"),
        pytest.param(plots.plot_shapiro_angle, dict(angle_deg=[0.1, 1.0, 90.0]),
                     id="plot_shapiro_angle"),
        pytest.param(plots.plot_subsystem, dict(noise_scale=[0.1, 1.0, 10.0],
                                                subsystem=["uv", "cns", "xnav"],
                                                interval_s=[3, 30, 60], days=0.05),
                     id="plot_subsystem"),
        pytest.param(plots.plot_sharing, dict(beta_xnav=[0.05, 1 / 3, 0.9],
                                              mode=["reset", "no-reset"], days=0.05),
                     id="plot_sharing"),
        pytest.param(plots.plot_fault_response, dict(size_sigma=[1.0, 5.0, 20.0],
                                                     sensor=["uv", "cns", "xnav"],
                                                     kind=["step", "ramp", "spike"], days=0.5),
                     id="plot_fault_response"),
        pytest.param(detection.plot_combined_parts,
                     dict(drift_sigma_per_hour=[0.5, 2.0, 64.0], noise_ratio=[1.0, 3.0],
                          step_sigma=[0.0, 4.0]), id="plot_combined_parts"),
        pytest.param(montecarlo.plot_pd, dict(kind=["step", "ramp", "spike", "noise"],
                                              noise_scale=[1.0, 1.3], trials=2),
                     id="plot_pd"),
        pytest.param(rplots.plot_filter_comparison,
                     dict(size=[100.0, 5000.0], eps=[10.0, 100.0],
                          pulsar_set=list(rplots.PULSAR_SETS)), id="plot_filter_comparison"),
        pytest.param(att.plot_fault_case,
                     dict(size=[0.1, 10.0, 100.0], location=list(att.LOCATIONS),
                          kind=["step", "ramp"], n_sigma=[2.0, 5.0, 10.0]),
                     id="plot_fault_case"),
        pytest.param(parity.plot_step_diagnosis,
                     dict(step_m=[5.0, 30.0, 300.0], s=[4, 11, 29], threshold_m=[5.0, 14.0, 40.0]),
                     id="plot_step_diagnosis"),
        pytest.param(montecarlo.plot_pd_error, dict(runs=[10, 300, 3000], pd=[0.5, 0.99]),
                     id="plot_pd_error"),
        pytest.param(toa.plot_orbit_terms, dict(day=[0, 13, 29], pulsar=["B0531+21", "B1937+21"],
                                                shapiro=list(toa.SHAPIRO_FORMS)),
                     id="plot_orbit_terms"),
        pytest.param(detection.plot_step_detector, dict(size_sigma=[1.0, 6.0, 20.0], levels=[1, 5],
                                                        log10_pfa=[-8, -5, -1]),
                     id="plot_step_detector"),
        pytest.param(dynamics.plot_model_difference,
                     dict(days_shown=[1, 7, 30], sun=[True, False], jupiter=[True, False],
                          j2=[False, True]), id="plot_model_difference"),
        pytest.param(sensors.plot_optical_geometry,
                     dict(sigma_dir_deg=[0.01, 0.1, 1.0], sigma_horizon_deg=[0.005, 0.05, 0.3],
                          vmag_max=[0.5, 1.0, 2.0]), id="plot_optical_geometry"),
    ]


@pytest.mark.parametrize(("plot", "params"), in_place_sliders())
def test_a_frame_updated_in_place_has_the_pixels_of_the_frame_drawn_from_nothing(plot, params):
    """Exactly (no tolerance): both frames run the plotting function's one update code, in the
    slider's one kept layout, on the same Agg renderer."""
    from xnavlab.core.plotting import updater

    calls = []

    def counted(**values):
        calls.append(values)
        return plot(**values)

    ex = explore(counted, ahead=False, **params)
    w = ex.widget()
    assert updater(ex._live["fig"]) is not None  # the widget keeps the figure to update it
    controls = [c for c in w.children if "xnav-control" in c._dom_classes]
    for control in controls:
        for value in (control.options[0][1], control.options[-1][1]):
            ex._cache.frames.clear()  # drawn, not looked up
            control.value = value
            assert ex.last_error is None and len(calls) == 1  # updated, plot not called
            values = {c.description: c.value for c in controls}
            fresh = widgets.live_png(ex.figure(**values), ex.layout)
            calls.pop()
            assert np.array_equal(png_pixels(ex._last_png), png_pixels(fresh)), values
    w.close()


def updatable(calls):
    """A constrained figure whose update refuses n > 2 (a new figure) and raises at n = 0."""
    from xnavlab.core.plotting import in_place

    def plot(n=1):
        calls.append(n)
        fig = titled()
        line = fig.axes[0].lines[0]

        def update(n=1):
            if n == 0:
                raise ValueError("n must be in [1, 3], got 0")
            if n > 2:
                return False
            line.set_ydata([0.0, 1e3 * n])
            fig.axes[0].set_title(str(n))

        update(n)
        return in_place(fig, update)
    return plot


def test_the_widget_updates_a_figure_in_place_and_falls_back_to_a_new_one():
    calls = []
    ex = explore(updatable(calls), n=[0, 1, 2, 3], initial={"n": 1}, ahead=False)
    w = ex.widget()
    slider = [c for c in w.children if "xnav-control" in c._dom_classes][0]
    slider.value = 2
    assert calls == [1] and ex.layout.last == "kept layout"  # updated, drawn in the kept layout
    slider.value = 3
    assert calls == [1, 3]  # update returned False: a new figure
    slider.value = 0
    assert ex.last_error == "error: ValueError: n must be in [1, 3], got 0"
    assert ex._live["fig"] is None  # a failed update: the next move starts from nothing
    ex._cache.frames.clear()
    slider.value = 2
    assert calls == [1, 3, 2] and ex.last_error is None
    w.close()


def test_in_a_kernel_the_worker_waits_for_the_cells_and_a_second_after(monkeypatch):
    """A "Run All" (or nbval) never runs beside it: it computes once the kernel is idle."""
    import time

    import IPython

    from xnavlab.core import _ahead

    hooks = {}

    class Events:
        def register(self, name, callback):
            hooks[name] = callback

    class Shell:
        events = Events()

    monkeypatch.setattr(_ahead, "_GATE", _ahead._Gate())
    monkeypatch.setattr(IPython, "get_ipython", lambda: Shell())
    calls = []
    ex = explore(counted_titled(calls), n=[1, 2, 3], ahead=True)
    ex.widget()  # built in the explore cell, which is still running
    time.sleep(0.3)
    assert calls == [(2, "a")] and set(hooks) == {"pre_run_cell", "post_run_cell"}
    hooks["post_run_cell"]()
    t0 = time.monotonic()
    assert ex._worker.idle(timeout=120) and sorted(n for n, _ in calls) == [1, 2, 3]
    assert time.monotonic() - t0 >= _ahead.IDLE_S * 0.9
    ex.close()


# -- frames kept on disk ---------------------------------------------------------------------
def test_a_reopened_slider_looks_its_frames_up_on_disk_and_they_are_the_frames_drawn_fresh(
        monkeypatch, tmp_path):
    """A move drawn in one widget is written to disk; the same slider opened again (a new
    Explorer: a re-run chapter) finds it there (its figure is not updated) with the pixels of
    the frame drawn from nothing."""
    import functools

    from xnavlab.core import montecarlo

    monkeypatch.setenv("XNAVLAB_CACHE", str(tmp_path))
    monkeypatch.setenv(FRAME_CACHE_ENV, "1")
    plot = functools.wraps(montecarlo.plot_pd_error)(lambda **v: montecarlo.plot_pd_error(**v))
    grids = dict(runs=[10, 100, 1000], pd=[0.5, 0.9], campaigns=100)
    first = explore(plot, ahead=False, **grids)
    w = first.widget()
    [runs, _] = [c for c in w.children if "xnav-control" in c._dom_classes]
    runs.value = 10
    drawn = first._last_png
    w.close()
    frames = list((tmp_path / "frames").glob("*.png"))
    assert len(frames) == 1  # the move's frame (the opening frame lays the layout out: not kept)
    again = explore(plot, ahead=False, **grids)
    w = again.widget()
    [runs, _] = [c for c in w.children if "xnav-control" in c._dom_classes]
    runs.value = 10
    assert again._last_png == drawn  # looked up:
    assert again._live["fig"].axes[0].get_title() == "100 campaigns of N = 100 runs"  # not drawn
    fresh = widgets.live_png(again.figure(runs=10), again.layout)
    assert np.array_equal(png_pixels(again._last_png), png_pixels(fresh))
    monkeypatch.setenv(FRAME_CACHE_ENV, "0")  # off: drawn again, the same frame
    again._cache.frames.clear()
    runs.value = 100
    runs.value = 10
    assert again._live["fig"].axes[0].get_title() == "100 campaigns of N = 10 runs"
    assert again._last_png == drawn
    w.close()


def test_a_slider_with_fixed_margins_keeps_its_frames_on_disk_too(monkeypatch, tmp_path):
    """A figure without a layout engine is drawn as it is: its frames are keyed as "fixed"."""
    monkeypatch.setenv("XNAVLAB_CACHE", str(tmp_path))
    monkeypatch.setenv(FRAME_CACHE_ENV, "1")
    calls = []

    def plot(n=1):
        calls.append(n)
        fig = Figure(figsize=(3, 2))
        fig.add_subplot().plot([0.0, 1.0], [0.0, n])
        return fig
    # keyed as the package's (its code: that module's)
    plot.__module__, plot.__qualname__ = "xnavlab.core.plotting", "fixed_demo"
    pngs = []
    for _ in range(2):  # a first session, then the slider opened again
        ex = explore(plot, n=[1, 2, 3], initial={"n": 1}, ahead=False)
        w = ex.widget()
        assert ex.layout.state() == "fixed"
        [slider] = [c for c in w.children if "xnav-control" in c._dom_classes]
        slider.value = 3
        pngs.append(ex._last_png)
        w.close()
    assert calls == [1, 3, 1] and pngs[0] == pngs[1]  # the second move: read from disk


def test_a_frame_the_kept_layout_does_not_fit_is_drawn_again_and_the_frames_after_it_are_not(
        monkeypatch, tmp_path):
    """Laid out anew, it changes the kept layout: a reopened slider draws it again (and lays
    its layout out as the first session did), then finds the frames drawn after it on disk."""
    monkeypatch.setenv("XNAVLAB_CACHE", str(tmp_path))
    monkeypatch.setenv(FRAME_CACHE_ENV, "1")
    calls = []

    def plot(size=10, title="a"):
        calls.append((size, title))
        fig = Figure(figsize=(4, 2.5), layout="constrained")
        ax = fig.add_subplot()
        ax.set_ylabel("y", fontsize=size)
        ax.set_title(title)
        return fig
    plot.__module__, plot.__qualname__ = "xnavlab.core.plotting", "labelled_demo"
    pngs = []
    for _ in range(2):
        ex = explore(plot, size=[10, 40], title=["a", "b"], initial={"size": 10, "title": "a"},
                     ahead=False)
        w = ex.widget()
        size, title = [c for c in w.children if "xnav-control" in c._dom_classes]
        size.value = 40
        assert ex.layout.last == "laid out again"  # drawn (and laid out) in both sessions
        title.value = "b"
        pngs.append((ex._last_png, ex.layout.last))
        w.close()
    assert calls == [(10, "a"), (40, "a"), (40, "b"), (10, "a"), (40, "a")]  # b: from disk
    assert pngs[0][0] == pngs[1][0] and pngs[0][1] == "kept layout"


def test_the_key_of_a_frame_on_disk_changes_with_the_code_and_the_arguments(tmp_path,
                                                                          monkeypatch):
    """An edit of the plotting function's module, or of a module it imports, gives a new key;
    an edit elsewhere in the package does not; so do other arguments and another layout."""
    from xnavlab.core.diskcache import code_digest

    monkeypatch.setenv("XNAVLAB_CACHE", str(tmp_path / "cache"))
    monkeypatch.setenv(FRAME_CACHE_ENV, "1")
    root = tmp_path / "xnavlab"
    root.mkdir()
    (root / "__init__.py").write_text("")
    (root / "demo.py").write_text("from xnavlab import helper\n\ndef plot(n=1):\n    pass\n")
    (root / "helper.py").write_text("K = 1\n")
    (root / "other.py").write_text("J = 1\n")

    def plot(n=1):
        pass
    plot.__module__, plot.__qualname__ = "xnavlab.demo", "plot"

    def key(kwargs=None, state="kept"):
        code_digest.cache_clear()  # one process sees one code; this test edits it
        return DiskFrames(plot, root).path({"n": 1, "s": "a"} if kwargs is None else kwargs,
                                           state)

    base = key()
    assert base is not None and base == key() and base.parent == tmp_path / "cache" / "frames"
    (root / "other.py").write_text("J = 2\n")
    assert key() == base  # not imported by the plotting function's module
    (root / "helper.py").write_text("K = 2\n")
    helper_edit = key()
    assert helper_edit != base
    (root / "demo.py").write_text("from xnavlab import helper\n\ndef plot(n=1):\n    1\n")
    assert key() not in (base, helper_edit)
    assert len({key(), key({"n": 2, "s": "a"}), key({"n": 1.0, "s": "a"}), key(state="other"),
                key({"n": np.int64(2), "s": "a"})}) == 4  # np.int64(2) is the key of 2
    assert key({"n": 1, "s": object()}) is None  # no exact key: not kept on disk
    assert key(state=None) is None  # no kept layout yet
    monkeypatch.setenv(FRAME_CACHE_ENV, "0")
    assert key() is None
    monkeypatch.setenv(FRAME_CACHE_ENV, "1")
    assert DiskFrames(lambda n=1: None).path({"n": 1}, "kept") is None  # not the package's


def test_frames_written_at_once_by_many_threads_are_read_back_whole(tmp_path):
    """Each writer writes a temporary file of its own and renames it: a reader sees one
    writer's whole frame, never a mixture, and no temporary file is left."""
    import threading

    path = tmp_path / "frames" / "f.png"
    pngs = [b"\x89PNG\r\n\x1a\n" + bytes([k]) * (50_000 + 1000 * k) + b"IEND\xaeB`\x82"
            for k in range(8)]
    seen = []

    def write(png):
        for _ in range(20):
            assert DiskFrames.store(path, png)
            seen.append(DiskFrames.load(path))

    threads = [threading.Thread(target=write, args=(png,)) for png in pngs]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert all(png in pngs for png in seen) and DiskFrames.load(path) in pngs
    assert [p.name for p in path.parent.iterdir()] == ["f.png"]
    path.write_bytes(pngs[0][:-3])  # cut short (not by a store): drawn again, not served
    assert DiskFrames.load(path) is None


def test_explore_keeps_max_frames_and_dpi_as_checked():
    """Review 35m pattern M: check_int's value was dropped, the raw np.uint8 / np.int64 went on
    to the Explorer (np.uint8 arithmetic wraps at 256)."""
    ex = explore(wave, omega=np.linspace(1.0, 2.0, 21), max_frames=np.uint8(5), dpi=np.int64(80))
    assert type(ex.dpi) is int and ex.frame_values == [1.0, 1.25, 1.5, 1.75, 2.0]


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"initial": [1.0]}, r"^initial must be a dict \{grid name: opening value\}, got list"),
        ({"initial": "om"}, r"^initial must be a dict .*got str 'om'"),
        ({"initial": 0}, r"^initial must be a dict"),  # not taken as "no initial"
        ({"initial": {"phase": 0.0}}, r"^initial\['phase'\] is not a grid parameter"),
        ({"initial": {"omega": np.array([1.0, 2.0])}}, r"^initial\['omega'\] must be one of"),
        ({"initial": {"omega": 1j}}, r"^initial\['omega'\] must be one of"),
        ({"initial": {"omega": True}}, r"^initial\['omega'\] must be one of"),  # not 1.0
        ({"omegaa": [1.0, 2.0]}, r"^omegaa is not a keyword of explore or of wave.*did you mean "
                                 "omega"),
        ({"ahead": "no"}, r"^ahead must be True or False, got 'no'"),
        ({"ahead": 0.5}, r"^ahead must be True or False"),
        ({"omega": np.array([[1.0, 2.0], [3.0, 4.0]])}, r"^omega must be a grid .*shape \(2, 2\)"),
        ({"omega": np.array(2.0)}, r"^omega must be a grid .*shape \(\)"),
        ({"phase": (x for x in [1.0])}, r"^phase must be a grid .*got generator"),
        ({"omega": [1.0, np.nan]}, r"^omega\[1\] is NaN"),
        ({"omega": [1.0, 2.0, 1.0 + 1e-12]}, r"^omega\[2\] is omega\[0\] again"),
        ({"main": ["omega"]}, r"^main must be the name of a grid parameter \(str\), got list"),
        ({"main": np.array(["omega", "x"])}, r"^main must be the name of a grid parameter"),
    ],
)
def test_explore_refuses_each_keyword_of_the_wrong_kind_by_its_name(kwargs, match):
    """Review 35o 1.1, 1.2, 2.1, 5.3, 5.4 and pattern T: a list or str for initial went to
    dict() (a raw TypeError, or Python's bare "dictionary update sequence"); a misspelt grid
    name was taken and raised in plot at the first frame; ahead="no" or 0.5 turned the worker
    on (bool()); a 2-D grid was flattened; a generator was used up by the first frame; a NaN
    or repeated grid value made a position no initial could name; a 2-value array for main
    or an initial value raised numpy's "truth value ... is ambiguous"."""
    kwargs = {"omega": [1.0, 2.0], **kwargs}
    with pytest.raises(ValueError, match=match):
        explore(wave, **kwargs)


def test_explore_refuses_a_plot_missing_a_parameter_it_needs_and_takes_bool_grids():
    """Review 35o pattern T: plot's required parameter left out raised plot's TypeError at the
    first frame, not at explore."""
    def needs(omega, phase=0.0):
        return wave(omega, phase)

    with pytest.raises(ValueError, match=r"^plot needs omega: give each a grid or a value"):
        explore(needs, phase=[0.0, 1.0])
    ex = explore(wave, omega=[1.0, 2.0], style=["-", ":"], ahead=np.True_,
                 initial={"omega": np.float64(2.0), "style": ":"})
    assert ex.ahead is True and ex.initial == {"omega": 2.0, "style": ":"}
    flags = explore(lambda on=True: wave(1.0 + on), on=[True, False], initial={"on": False})
    assert flags.initial == {"on": False}
    with pytest.raises(ValueError, match=r"^initial\['on'\] must be one of"):
        explore(lambda on=True: wave(), on=[True, False], initial={"on": 0})
    with pytest.raises(ValueError, match=r"^phasee is not a keyword of figure or of wave"):
        ex.figure(phasee=1.0)


def test_frame_helpers_refuse_what_is_not_a_figure_or_a_setting():
    """Review 35o pattern T: live_png(None), SteadyLayout().png(fig, dpi="x") or
    compress_level=20, error_line("x") gave AttributeError, TypeError, OSError or a line for
    a non-exception."""
    with pytest.raises(ValueError, match=r"^fig must be a matplotlib Figure, got NoneType"):
        widgets.live_png(None)
    with pytest.raises(ValueError, match=r"^layout must be a SteadyLayout"):
        widgets.live_png(Figure(), layout=3)
    with pytest.raises(ValueError, match=r"^dpi must be"):
        widgets.SteadyLayout().png(Figure(), dpi="x")
    with pytest.raises(ValueError, match=r"^compress_level must be an integer in \[0, 9\]"):
        widgets.SteadyLayout().png(Figure(), compress_level=20)
    with pytest.raises(ValueError, match=r"^fig must be a matplotlib Figure, got str"):
        widgets.SteadyLayout().prepare("fig")
    with pytest.raises(ValueError, match=r"^exc must be an exception, got str"):
        widgets.error_line("x")


def test_a_grid_is_checked_in_linear_time(monkeypatch):
    """Review 35 Q11: each value was compared with every earlier one (np.isclose a pair):
    about 20 s for a 1,000-value slider and 30 min for 10,000, before any frame. Now the
    real values are sorted and each compared with its neighbour."""
    from xnavlab.core import _grids

    calls = []
    close = _grids._close
    monkeypatch.setattr(_grids, "_close", lambda a, b: calls.append(1) or close(a, b))
    ex = explore(wave, omega=np.linspace(0.5, 3.0, 2000))
    assert len(ex.grids["omega"]) == 2000 and len(calls) < 3 * 2000  # not 2000**2 / 2
    with pytest.raises(ValueError, match=r"^omega\[1999\] is omega\[3\] again \(0.5038\): each "
                                         r"grid value must be one position$"):
        explore(wave, omega=[*np.linspace(0.5, 3.0, 1999), 0.5 + 2.5 / 1998 * 3 * (1 + 1e-12)])


@pytest.mark.parametrize(("grid", "match"), [
    ([Decimal("NaN"), Decimal("NaN")], r"^omega\[0\] is NaN: each grid value must be one position$"),
    ([complex("nan")], r"^omega\[0\] is NaN"),
    ([1.0, Decimal("sNaN")], r"^omega\[1\] is NaN"),
    ([1.0, 1 + 0j], r"^omega\[1\] is omega\[0\] again \(\(1\+0j\)\)"),
    ([2, 1.0, 2.0], r"^omega\[2\] is omega\[0\] again \(2\)"),
    ([np.array([1.0, 2.0]), np.array([1, 2])], r"^omega\[1\] is omega\[0\] again"),
    (["a", "b", "a"], r"^omega\[2\] is omega\[0\] again \(a\)"),
])
def test_a_grid_value_unequal_to_itself_or_given_twice_is_refused(grid, match):
    """Review 35 Q21: a Decimal or complex NaN passed the float-only NaN check, then the
    opening value failed under the name 'value', which the user never typed."""
    with pytest.raises(ValueError, match=match):
        explore(wave, omega=grid)


def test_a_numeric_grid_is_put_in_order_and_any_other_keeps_its_order():
    """Review 35 Q6: a slider over [3, 1, 2] moved 3 -> 1 -> 2."""
    ex = explore(wave, omega=[3.0, 1.0, 2.0], style=[":", "-", "--"], phase=[True, False])
    assert ex.frame_values == [1.0, 2.0, 3.0] and ex.grids["omega"] == [1.0, 2.0, 3.0]
    assert ex.grids["style"] == [":", "-", "--"] and ex.grids["phase"] == [True, False]
    assert explore(wave, omega=[2, Fraction(1, 2), 1.5]).grids["omega"] == [Fraction(1, 2), 1.5, 2]
    assert explore(wave, omega=[1.0, "auto", 0.5]).grids["omega"] == [1.0, "auto", 0.5]


def test_the_explorer_names_its_grid_when_the_opening_value_is_not_in_it():
    """Review 35 Q21: Explorer.__init__ looked the opening value up under the name 'value'."""
    with pytest.raises(ValueError, match=r"^omega must be one of its grid values \['1', '2'\], "
                                         r"got 3.0$"):
        widgets.Explorer(wave, {"omega": [1.0, 2.0]}, {}, "omega", {"omega": 3.0}, 4, 80)
