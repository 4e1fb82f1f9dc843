"""Sliders that survive the HTML book: a live widget in Jupyter, a kernel-free scrubber offline.

A chapter's slider calls a pure plotting function. In Jupyter, :func:`explore` shows it as a
live ``ipywidgets.interactive`` (``continuous_update=False``: the figure is redrawn when the
slider is released). The rendered HTML book has no kernel to redraw anything, so the same
call also carries a *scrubber*: the figure precomputed over a small grid of the main
parameter, embedded as PNG frames with an HTML range input that swaps them (a few lines of
inline JavaScript, no library, no network). The display bundle holds both; Jupyter shows the
widget, the book shows the scrubber (``_config.yml`` ranks ``text/html`` above the widget
view for the HTML builders).

Usage in a chapter cell::

    from xnavlab.core.widgets import explore

    def plot_delay(sigma_m=100.0, days=10.0):   # pure: values in, Figure out
        ...
        return fig

    explore(plot_delay, sigma_m=np.linspace(50, 500, 10), days=[1, 10, 30])

The first keyword given a grid (``sigma_m``) is the scrubber's parameter unless ``main``
names another; the others are held at their ``initial`` value in the scrubber (the live
widget gets a slider or menu for every grid). A keyword given a scalar is passed through
unchanged, with no control.

Only the built book shows the scrubber's frames (up to ``max_frames`` figures): a kernel
draws them when :data:`FRAMES_ENV` (``XNAVLAB_SCRUBBER_FRAMES``) is ``1`` (``make book``,
``make test``'s nbval run, ``tools/nbval_book.py``), and shows the scrubber alone (no live
widget: nothing could drive it). In any other kernel (a reader's JupyterLab) the HTML part
of the display is one static image, the live widget's opening figure, drawn once for both:
"Run All" costs one figure per slider, not thirteen. Outside a kernel,
:meth:`Explorer.html` always draws the frames.

The live widget never leaves the reader without feedback: while a redraw runs, its status
line says ``computing…`` (shown only once the redraw has taken 0.3 s, so quick redraws do
not flicker), and an exception raised by the plotting function replaces the figure with one
readable line, ``error: ValueError: ...``, instead of a traceback. The parts carry stable
CSS classes for the JupyterLab browser test (``tests/lab/``): ``xnav-explore`` (the whole
widget), ``xnav-control`` (every control; ``xnav-main`` marks the control of ``main``),
``xnav-status`` (the status line) and ``xnav-output`` (the figure), with ``xnav-error`` on an
error line.

Three things make a move quick. **Frames computed ahead:** once the opening frame is drawn, a
background thread draws the live widget's other positions (one control away first, nearest
steps first, among equals onward along the control moved last) and keeps their PNGs (the
:data:`LIVE_MEMO_FRAMES` nearest): a move onto one is a lookup, a move elsewhere draws at once,
a move onto the position being drawn waits for it. The thread never draws the reader's figure,
waits while a foreground frame or a cell runs, stops with the widget and is a daemon;
``explore(..., ahead=False)`` or :data:`AHEAD_ENV` turns it off (:func:`ahead_default`; the
plumbing, and what it relies on in matplotlib's thread safety: ``xnavlab/core/_ahead.py``).
**Frames kept on disk:** every frame drawn in the kept layout is also written under
``$XNAVLAB_CACHE/frames/``, keyed by the plotting function's code (its module and all the
package modules it imports), its arguments, the kept layout and matplotlib's settings and
version: a slider opened again (the chapter re-run, another kernel) looks its frames up
there, and an edit of the code draws them again (``xnavlab/core/_frames.py``; the environment
variable ``XNAVLAB_FRAME_CACHE=0`` turns it off). **Figures updated in place:** a plotting
function may return its figure with an update (:func:`xnavlab.core.plotting.in_place`); the
live widget then keeps that figure and, at a move, updates its artists and draws it again
(a test holds each such frame to the pixels of the frame drawn from nothing). None of these
changes the HTML scrubber, whose frames are drawn from nothing as before.
"""

from __future__ import annotations

import base64
import functools
import html as _html
import inspect
import io
import json
import weakref
from collections.abc import Callable
from numbers import Number

import numpy as np

from xnavlab.core import validate
from xnavlab.core._ahead import RENDER_LOCK, AheadWorker, Failed, FrameCache, foreground
from xnavlab.core._frames import DiskFrames, check_png_args
from xnavlab.core._grids import grid_index, grid_label, grid_values, is_grid
from xnavlab.core._render import recording_canvas_class
from xnavlab.core.diskcache import env_switch
from xnavlab.core.plotting import updater

__all__ = ["explore", "Explorer", "SteadyLayout", "error_line", "live_png", "ahead_default",
           "BUSY", "LIVE_MEMO_FRAMES", "FRAMES_ENV", "AHEAD_ENV", "MAX_MISFITS"]

_MIME_WIDGET = "application/vnd.jupyter.widget-view+json"

#: Positions whose PNG the live widget keeps (drawn at a move or ahead), to show them again
#: without a redraw: those nearest the current position.
LIVE_MEMO_FRAMES = 128

#: The environment variable that makes a kernel draw the HTML scrubber's frames (``"1"``):
#: set where a page is executed for the HTML book.
FRAMES_ENV = "XNAVLAB_SCRUBBER_FRAMES"

#: The environment variable that switches the frames computed ahead off (``"0"``) in every
#: live widget of a kernel, whatever :func:`explore`'s ``ahead`` default.
AHEAD_ENV = "XNAVLAB_AHEAD"

#: Text of the live widget's status line while a redraw runs.
BUSY = "computing\u2026"
# the status line while busy: hidden for the first 0.3 s (a CSS animation delay), so that only
# redraws slower than that show it
_BUSY_HTML = (
    "<style>@keyframes xnav-appear{from{visibility:hidden}to{visibility:visible}}</style>"
    '<span class="xnav-busy" style="animation:xnav-appear 0s linear 0.3s both;'
    f'font-style:italic;opacity:0.75">&#8987; {BUSY}</span>'
)
_ERROR_MAX_CHARS = 300
# swap the frame on input; self-contained so that several scrubbers can share a page
_ONINPUT = (
    "var d=this.closest('.xnav-scrubber');"
    "var j=d._xnav||(d._xnav=JSON.parse(d.querySelector('.xnav-scrubber-data').textContent));"
    "d.querySelector('img').src=j.frames[this.value];"
    "d.querySelector('output').textContent=j.labels[this.value];"
)


class Explorer:
    """A plotting function with parameter grids, shown live in Jupyter and as a scrubber in HTML.

    Build it with :func:`explore`. Displaying it (as a cell's last value) gives Jupyter a
    live ``ipywidgets`` widget and the HTML book a precomputed scrubber.

    Attributes
    ----------
    plot : callable
        ``plot(**values) -> matplotlib.figure.Figure``.
    grids : dict of str to list
        The parameters that get a control, each with its values.
    fixed : dict
        Parameters passed through unchanged.
    main : str
        The parameter the scrubber moves through.
    initial : dict
        The value of every grid parameter when the widget or scrubber opens.
    frame_values : list
        The values of ``main`` at which the scrubber's frames are drawn.
    status : ipywidgets.HTML or None
        The live widget's status line (``None`` until :meth:`widget` is built): holds
        :data:`BUSY` while the plotting function runs, empty otherwise.
    last_error : str or None
        The :func:`error_line` of the last failed redraw of the live widget; ``None`` after
        a successful one.
    layout : SteadyLayout
        The axes layout of the opening figure, shared by the live widget's redraws and the
        scrubber's frames (the axes stay put from frame to frame).
    ahead : bool or None
        Whether the live widget computes the other positions in the background once it has
        drawn its opening frame (``None``: when :func:`ahead_default` says so, checked when
        the widget is built).
    """

    def __init__(self, plot, grids, fixed, main, initial, max_frames, dpi, ahead=None):
        self.plot = plot
        self.grids = grids
        self.fixed = fixed
        self.main = main
        self.initial = initial
        self.dpi = dpi
        grid = grids[main]
        idx = sorted(set(np.round(np.linspace(0, len(grid) - 1, min(max_frames, len(grid))))
                         .astype(int).tolist()))
        k0 = grid_index(grid, initial[main], main)
        if k0 not in idx:  # the scrubber opens on the initial value: swap in for the nearest
            idx[int(np.argmin([abs(i - k0) for i in idx]))] = k0
            idx.sort()
        self.frame_values = [grid[i] for i in idx]
        self._start = self.frame_values.index(grid[k0])
        self._frames = None
        self._widget = None
        # the live widget's frames by position (PNG bytes, or the error line of one that
        # raised), drawn at a move or ahead by the worker
        self._cache = FrameCache([len(g) for g in grids.values()], LIVE_MEMO_FRAMES)
        self.ahead = ahead
        self._worker = None  # the AheadWorker, once the widget is built (ahead on)
        self._disk = DiskFrames(plot)  # its frames drawn in the kept layout, on disk
        self._live = {"fig": None}  # the foreground's figure kept for in-place updates
        self._behind = {"fig": None}  # the worker's own
        self._last_png = None  # the live widget's latest figure (its opening one at first)
        self._pyplot = False  # plot's last new figure was registered with pyplot
        self.status = None
        self.last_error = None
        self.layout = SteadyLayout()

    def __repr__(self):
        name = getattr(self.plot, "__name__", "plot")
        return (f"Explorer({name}, main={self.main!r}, {len(self.frame_values)} frames, "
                f"controls={list(self.grids)})")

    # -- the kernel-free scrubber ---------------------------------------------------------
    def figure(self, **values):
        """Call ``plot`` with the initial values updated by ``values``; return the Figure."""
        values = validate.check_keywords("figure", values, self.plot)
        kwargs = {**self.fixed, **self.initial, **values}
        fig = self.plot(**kwargs)
        from matplotlib.figure import Figure

        if not isinstance(fig, Figure):
            raise ValueError(
                f"plot must return a matplotlib Figure, got {type(fig).__name__} "
                f"for {kwargs!r}"
            )
        return fig

    def frames(self):
        """PNG bytes of the figure at each of ``frame_values`` (computed once).

        The opening frame is drawn first; the others take its layout (attribute ``layout``, a
        :class:`SteadyLayout`).
        """
        if self._frames is None:
            import matplotlib.pyplot as plt

            out = [b""] * len(self.frame_values)
            # the opening frame first: its layout is the one the others keep
            order = [self._start] + [k for k in range(len(out)) if k != self._start]
            for k in order:
                fig = self.figure(**{self.main: self.frame_values[k]})
                with RENDER_LOCK:  # a live widget's worker may be drawing
                    out[k] = self.layout.png(fig, dpi=self.dpi)
                plt.close(fig)
            self._frames = out
        return self._frames

    def html(self):
        """The scrubber: an ``<img>`` and a range input over the precomputed frames."""
        uris = ["data:image/png;base64," + base64.b64encode(b).decode("ascii")
                for b in self.frames()]
        labels = [f"{self.main} = {grid_label(v)}" for v in self.frame_values]
        data = json.dumps({"frames": uris, "labels": labels}).replace("</", "<\\/")
        k = self._start
        name = _html.escape(self.main)
        alt = _html.escape(f"{getattr(self.plot, '__name__', 'figure')} at {labels[k]}")
        return (
            '<div class="xnav-scrubber" style="max-width:100%;margin:0.5em 0">'
            f'<img src="{uris[k]}" alt="{alt}" style="max-width:100%;height:auto;display:block">'
            '<div style="display:flex;align-items:center;gap:0.8em;flex-wrap:wrap">'
            f'<input type="range" min="0" max="{len(uris) - 1}" step="1" value="{k}" '
            f'aria-label="{name}" style="flex:1 1 12em;max-width:28em" '
            f'oninput="{_html.escape(_ONINPUT)}">'
            f"<output>{_html.escape(labels[k])}</output>"
            '<span style="opacity:0.6;font-size:smaller">(precomputed frames; run the '
            "notebook for the live slider)</span></div>"
            f'<script type="application/json" class="xnav-scrubber-data">{data}</script>'
            "</div>"
        )

    # -- the live widget ------------------------------------------------------------------
    def widget(self):
        """The live ``ipywidgets.interactive`` (built once), ``continuous_update=False``.

        Below the controls sits the status line (attribute ``status``, ``computing…`` during a
        redraw), then the figure. ``plot`` being pure, a position drawn before (or ahead, see
        the module) is shown again from its kept PNG (the :data:`LIVE_MEMO_FRAMES` positions
        nearest the current one), without calling it; a figure with an in-place update
        (:func:`xnavlab.core.plotting.in_place`) is updated rather than built again.
        An exception raised by ``plot`` (or ``plot`` not returning a
        Figure) shows :func:`error_line` in place of the figure and is kept in
        attribute ``last_error``; the widget stays usable.
        """
        if self._widget is None:
            import html

            import ipywidgets as w
            from IPython.display import Image, display

            controls = {name: _control(w, name, grid, self.initial[name])
                        for name, grid in self.grids.items()}
            # every parameter name in full (the default label width cuts them at ~8 letters)
            label_em = max(len(name) for name in self.grids) * 0.6 + 1.0
            for name, control in controls.items():
                control.style.description_width = f"{label_em:.1f}em"
                control.layout.width = f"calc({label_em:.1f}em + 20em)"
                control.add_class("xnav-control")
                if name == self.main:
                    control.add_class("xnav-main")
            fixed = {name: w.fixed(v) for name, v in self.fixed.items()}
            status = w.HTML(value="")
            status.add_class("xnav-status")
            self.status = status

            def show(**values):
                pos = self._position(values)
                entry = self._cache.get(pos)  # drawn before, or ahead (waits if in flight)
                if entry is None:
                    status.value = _BUSY_HTML  # sent to the browser at once (iopub thread)
                    try:
                        with foreground():  # the worker starts nothing new meanwhile
                            entry = self._draw(values, self._live)
                    finally:
                        status.value = ""
                    self._cache.put(pos, entry)
                self._cache.move(pos)
                if self._worker is not None:
                    self._worker.kick()  # the positions near this one, next
                if isinstance(entry, Failed):  # one line for the reader, not a traceback wall
                    self.last_error = entry.line
                    display({"text/plain": entry.line,
                             "text/html": '<pre class="xnav-error" style="color:#b00020;'
                                          f'white-space:pre-wrap">{html.escape(entry.line)}'
                                          "</pre>"}, raw=True)
                    return
                self.last_error = None
                self._last_png = entry
                display(Image(data=entry, format="png"))

            widget = _interactive_class(w)(show, **controls, **fixed)
            widget.on_close = self._stop
            widget.add_class("xnav-explore")
            widget.out.add_class("xnav-output")
            widget.children = (*widget.children[:-1], status, widget.out)
            self._disk.warm()  # the key's code hashed before the first move
            if self._use_ahead():
                self._worker = AheadWorker(self._cache, self._ahead_frame)
                self._worker.kick()  # after the opening frame (drawn by the line above)
            self._widget = widget
        return self._widget

    def close(self):
        """Close the live widget: its worker stops after its current frame, figures go."""
        if self._widget is not None:
            self._widget.close()  # calls _stop
        self._stop()

    def _stop(self):
        if self._worker is not None:
            self._worker.stop()
        self._live["fig"] = self._behind["fig"] = None

    # -- frames of the live widget ----------------------------------------------------------
    def _position(self, values):
        """The grid indices of a widget position (its controls' values)."""
        return tuple(grid_index(grid, values[name], name) for name, grid in self.grids.items())

    def _draw(self, values, holder, turn=None):
        """The live widget's frame at ``values``: PNG bytes, or :class:`Failed` if ``plot``
        raised. ``holder["fig"]`` is the figure kept for in-place updates (the reader's, or
        the worker's own); ``turn()`` is waited for before the Agg draw."""
        fig = holder["fig"]
        kwargs = {**self.fixed, **self.initial, **values}
        with RENDER_LOCK:
            state = self.layout.state()
        path = self._disk.path(kwargs, state)  # drawn before, in this layout, by this code
        png = self._disk.load(path)
        if png is not None:
            return png
        try:
            update = updater(fig) if fig is not None else None
            if update is None or update(**kwargs) is False:  # a new figure, from nothing
                fig = holder["fig"] = None
                fig = self.figure(**values)
                self._pyplot = fig.canvas.manager is not None  # (the render drops the manager)
                if updater(fig) is not None and not self._pyplot:
                    holder["fig"] = fig  # updated in place from now on
        except Exception as exc:
            holder["fig"] = None  # an update may have stopped half-way: start again
            return Failed(error_line(exc))
        if turn is not None:
            turn()
        # one PNG at the figure's own size and dpi (display(fig) would draw it twice for a
        # tight bounding box: up to a third of a redraw), in the opening figure's layout
        with RENDER_LOCK:
            kept = self.layout.state() == state  # the layout the key names (none: not kept)
            png = live_png(fig, self.layout)
            kept = kept and self.layout.state() == state  # and left as it was (see _frames)
        if kept:
            self._disk.store(path, png)
        if self._pyplot:
            import matplotlib.pyplot as plt

            plt.close(fig)  # shown once, not again by the inline backend
        return png

    def _ahead_frame(self, pos):
        """The worker's frame at grid indices ``pos`` (its own figure, never the reader's;
        drawn once no frame of the reader's is being drawn)."""
        values = {name: grid[i] for (name, grid), i in zip(self.grids.items(), pos, strict=True)}
        return self._draw(values, self._behind, turn=AheadWorker.render_turn)

    def _use_ahead(self):
        """Whether the worker runs: ``ahead`` if given, else :func:`ahead_default`; never
        for figures registered with pyplot (not safe in a second thread)."""
        on = ahead_default() if self.ahead is None else bool(self.ahead)
        return on and self._last_png is not None and not self._pyplot

    def still_html(self):
        """The HTML of a kernel that is not building the book: the live widget's opening
        figure as one static image (drawn once, for the widget and this), no frames.

        What a saved notebook shows where the widget cannot be (a viewer without a kernel).
        """
        self.widget()  # built once: its construction draws the opening figure
        png = self._last_png
        if png is None:  # the opening figure raised: the widget shows the error line
            return f'<pre class="xnav-error">{_html.escape(self.last_error or "")}</pre>'
        alt = _html.escape(f"{getattr(self.plot, '__name__', 'figure')} at the opening values")
        return (f'<img src="data:image/png;base64,{base64.b64encode(png).decode("ascii")}" '
                f'alt="{alt}" style="max-width:100%;height:auto">')

    def _repr_mimebundle_(self, include=None, exclude=None):
        if not _in_kernel():
            return {"text/plain": repr(self), "text/html": self.html()}
        if env_switch(FRAMES_ENV, False):  # executed for the HTML book: the scrubber only
            return {"text/plain": repr(self), "text/html": self.html()}
        view = self.widget()._repr_mimebundle_()
        bundle = {"text/plain": repr(self), "text/html": self.still_html()}
        bundle.update({k: v for k, v in view.items() if k == _MIME_WIDGET})
        return bundle


class SteadyLayout:
    """One slider's axes layout: worked out at its first frame, reused by the later ones.

    A figure with a layout engine (``layout="constrained"``) works its layout out at every
    render: a draw that renders nothing, then the real one, and the first is about a third of
    the render (0.13 of 0.45 s for chapter 1's figure, 0.45 of 1.6 s for chapter 2's on the
    project's machine). A slider's frames come from one pure function and have the same axes,
    so the layout of the first frame is kept: a later frame with the same figure size and the
    same kinds of axes gets the kept axes positions (and the kept positions of its
    ``suptitle``, ``supxlabel`` and ``supylabel``) and no layout engine, hence one draw. Its
    axes also stay where they were while the slider moves, which makes two frames easier to
    compare.

    The kept layout is checked on what was drawn: a frame in which a text (a tick label, a
    title) sticks out of the figure or runs into another axes' frame, where the first frame's
    own layout had none, is laid out again by its own engine and drawn again, and its layout
    is kept from then on (after :data:`MAX_MISFITS` such frames, the slider's frames are all
    laid out by their own engine). So is a frame whose figure or axes differ. A figure without a
    layout engine (fixed margins) is drawn as it is. Every frame is drawn on an Agg renderer
    shared by the frames of its size, which keeps the text metrics it has measured.

    Examples
    --------
    >>> from matplotlib.figure import Figure
    >>> steady = SteadyLayout()
    >>> def frame(title):
    ...     fig = Figure(figsize=(3, 2), layout="constrained")
    ...     fig.add_subplot().set_title(title)
    ...     return fig
    >>> first, later = frame("a"), frame("a longer title")
    >>> png = steady.png(first)
    >>> steady.last
    'laid out'
    >>> png = steady.png(later)
    >>> steady.last
    'kept layout'
    >>> later.axes[0].get_position().bounds == first.axes[0].get_position().bounds
    True
    >>> png = steady.png(frame("a title far too long for the kept layout of 3 inches"))
    >>> steady.last
    'laid out again'

    """

    def __init__(self):
        self._shape = None
        self._boxes = None
        self._texts = None
        self._engine = None  # the layout engine of the figure prepared last
        self._engines = weakref.WeakKeyDictionary()  # of every figure prepared, still alive
        self._trusted = True  # the laid-out frame drew clear (see png): its layout may be kept
        #: Frames the kept layout did not fit; at :data:`MAX_MISFITS` no layout is kept.
        self.misfits = 0
        #: How the last frame was laid out: ``'laid out'``, ``'kept layout'``, ``'laid out
        #: again'`` (the kept layout did not fit it) or ``'fixed'`` (no layout engine).
        self.last = None

    def prepare(self, fig):
        """Lay ``fig`` out for one draw; return how (``'laid out'``, ``'kept layout'``, ``'fixed'``).

        ``'laid out'``: its own layout engine ran (without rendering) and the result is kept;
        ``'kept layout'``: the kept positions were applied (a figure of the same shape as the
        kept one, whose first frame drew clear), unchecked (:meth:`png` checks);
        ``'fixed'``: the figure has no layout engine. After the first two the figure's layout
        engine is off, so a ``savefig`` draws it once.
        """
        from matplotlib.layout_engine import PlaceHolderLayoutEngine

        check_png_args(fig)
        engine = fig.get_layout_engine()
        if engine is None or isinstance(engine, PlaceHolderLayoutEngine):
            engine = self._engines.get(fig)  # a figure prepared before, updated in place
            if engine is None:
                return "fixed"
        shape = _figure_shape(fig)
        if shape == self._shape and self._trusted:
            for ax, (original, active) in zip(fig.axes, self._boxes, strict=True):
                in_layout = ax.get_in_layout()  # set_position takes the axes out of layout
                ax.set_position(original, which="original")
                ax.set_position(active, which="active")
                ax.set_in_layout(in_layout)  # (a frame the kept layout misfits is laid out)
            for name, xy in self._texts.items():
                getattr(fig, name).set_position(xy)
            how = "kept layout"
        else:
            if fig in self._engines:  # laid out before (a kept layout, or updated in place):
                _subplot_positions(fig)  # its engine starts where a new figure's starts
            fig.set_layout_engine(engine)
            fig.draw_without_rendering()  # the engine lays the figure out
            self._shape = shape
            self._boxes = [(ax.get_position(original=True).frozen(),
                            ax.get_position(original=False).frozen()) for ax in fig.axes]
            self._texts = {name: getattr(fig, name).get_position() for name in _SUP_TEXTS
                           if getattr(fig, name, None) is not None}
            how = "laid out"
        self._engine = engine  # for a frame the kept layout does not fit
        self._engines[fig] = engine
        fig.set_layout_engine("none")
        return how

    def state(self):
        """The kept layout a later frame is drawn in, as text (``"fixed"`` while every frame had
        fixed margins; ``None`` before the first frame and once no layout is kept): part of the
        key of a frame kept on disk."""
        if self._shape is None or not self._trusted:
            return "fixed" if self._shape is None and self.last == "fixed" else None
        boxes = [b.bounds for pair in self._boxes for b in pair]
        return repr((self._shape, boxes, sorted(self._texts.items())))

    def png(self, fig, dpi=None, compress_level=6):
        """PNG bytes of ``fig`` (at ``dpi``, default its own), laid out by :meth:`prepare`.

        A kept layout whose drawn texts stick out of the figure or into another axes (see the
        class) is replaced: the frame is laid out by its own engine and drawn again.
        """
        check_png_args(fig, dpi, compress_level)
        how = self.prepare(fig)
        if how == "fixed":  # drawn as it is (on the shared renderer)
            png = _png_checked(fig, dpi, compress_level, check=False)[0]
        else:
            png, clear = _png_checked(fig, dpi, compress_level)
            if how == "laid out":  # a first frame that does not draw clear: no layout is kept
                self._trusted = clear
            elif not clear:  # the kept layout does not fit this frame
                fig.set_layout_engine(self._engine)
                self._shape = None
                self.prepare(fig)
                png, clear = _png_checked(fig, dpi, compress_level)
                self.misfits += 1  # a slider whose layouts keep changing lays out every frame
                self._trusted = clear and self.misfits < MAX_MISFITS
                how = "laid out again"
        self.last = how
        return png


_SUP_TEXTS = ("_suptitle", "_supxlabel", "_supylabel")


def _subplot_positions(fig):
    """Put every subplot of ``fig`` back where its gridspec puts it before any layout.

    A layout engine's result depends on the positions it starts from (the constrained layout
    measures the tick labels of the axes as they are), so a figure laid out again must start
    where a figure made from nothing starts to come out the same.
    """
    for ax in fig.axes:
        spec = ax.get_subplotspec()
        if spec is not None:
            in_layout = ax.get_in_layout()  # set_position takes the axes out of layout
            ax.set_position(spec.get_position(fig), which="both")
            ax.set_in_layout(in_layout)

#: Frames a kept layout may fail to fit before a slider lays out every frame by its own
#: engine: a figure whose labels change size from frame to frame would otherwise pay a
#: second draw at every misfit.
MAX_MISFITS = 2


def _figure_shape(fig):
    """What must match for a kept layout to fit: size, dpi, and each axes' kind and locator."""
    return (tuple(fig.get_size_inches().round(6)), fig.dpi,
            tuple((type(ax).__name__, ax.get_subplotspec() is not None,
                   ax.get_axes_locator() is None) for ax in fig.axes),
            tuple(getattr(fig, name, None) is not None for name in _SUP_TEXTS))


def _png_checked(fig, dpi, compress_level, check=True):
    """``(png, clear)``: one Agg draw of ``fig``; ``clear`` when no drawn text (unclipped)
    sticks out of the figure by more than a pixel or overlaps the frame of an axes it does
    not belong to (axes sharing a frame, like twins, count as one). ``check=False``: not
    looked at (``clear`` is ``None``)."""
    canvas = recording_canvas_class()(fig)
    buf = io.BytesIO()
    if _one_draw(fig, dpi):
        # what savefig does, less its first, non-rendering draw (the layout engine is off
        # here): a third less time for the live widget's frames
        from matplotlib.image import imsave

        canvas.draw()
        imsave(buf, canvas.buffer_rgba(), format="png", origin="upper", dpi=fig.dpi,
               pil_kwargs={"compress_level": compress_level})
    else:
        fig.savefig(buf, format="png", dpi=dpi, pil_kwargs={"compress_level": compress_level})
    if not check:
        canvas.renderer.texts = []
        return buf.getvalue(), None
    renderer = canvas.renderer  # the one that drew, at the saved dpi
    texts, renderer.texts = renderer.texts, []  # the shared renderer keeps no figure alive
    from matplotlib.transforms import Bbox

    width, height = renderer.width, renderer.height
    inside = Bbox([[-1 / width, -1 / height], [1 + 1 / width, 1 + 1 / height]])
    frames = [ax.get_position().frozen() for ax in fig.axes]  # figure fractions
    for text in texts:
        if text.get_clip_on() and text.get_clip_box() is not None:
            continue
        px = text.get_window_extent(renderer, dpi=renderer.dpi)
        box = Bbox([[px.x0 / width, px.y0 / height], [px.x1 / width, px.y1 / height]])
        if not (inside.contains(box.x0, box.y0) and inside.contains(box.x1, box.y1)):
            return buf.getvalue(), False
        own = text.axes.get_position().bounds if text.axes is not None else None
        if any(frame.bounds != own and box.overlaps(frame) for frame in frames):
            return buf.getvalue(), False
    return buf.getvalue(), True


def _one_draw(fig, dpi):
    """Whether one canvas draw gives savefig's pixels for ``fig`` at ``dpi``: its own dpi, an
    inert layout engine, and the default savefig settings (no colours, box or dpi of their
    own)."""
    import matplotlib as mpl
    from matplotlib.layout_engine import PlaceHolderLayoutEngine

    engine = fig.get_layout_engine()
    rc = mpl.rcParams
    return ((dpi is None or dpi == fig.dpi) and rc["savefig.dpi"] == "figure"
            and (engine is None or isinstance(engine, PlaceHolderLayoutEngine))
            and rc["savefig.facecolor"] == "auto" and rc["savefig.edgecolor"] == "auto"
            and not rc["savefig.transparent"] and rc["savefig.bbox"] is None)


def live_png(fig, layout=None):
    """The live widget's rendering of a figure: PNG bytes at its own size and dpi, fast zlib.

    One Agg draw (no tight bounding box, which would draw twice) and zlib level 1 instead of
    matplotlib's default 6: the same pixels (PNG is lossless), a few per cent more bytes, and
    about 0.05 s less per redraw of a large figure. The HTML scrubber's frames keep the default
    compression, since they are stored in the page.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        Any figure (an Agg canvas is attached when it has none).
    layout : SteadyLayout, optional
        The slider's kept layout (drawn by :meth:`SteadyLayout.png`); by default the figure's
        own layout engine runs.

    Returns
    -------
    bytes
        The PNG file.

    Examples
    --------
    >>> from matplotlib.figure import Figure
    >>> fig = Figure(figsize=(2, 1), dpi=50)
    >>> png = live_png(fig)
    >>> png[:8] == b"\\x89PNG\\r\\n\\x1a\\n"
    True
    """
    check_png_args(fig, layout=layout, layout_class=SteadyLayout)
    if layout is not None:
        return layout.png(fig, compress_level=1)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", pil_kwargs={"compress_level": 1})
    return buf.getvalue()


def error_line(exc):
    """One readable line for an exception raised while drawing: ``error: <Type>: <message>``.

    Parameters
    ----------
    exc : BaseException
        The exception.

    Returns
    -------
    str
        ``"error: "``, the exception's class name and the first line of its message, at
        most 300 characters (longer messages end in ``…``).

    Examples
    --------
    >>> error_line(ValueError("size must be in [1, 100], got 500\\nmore detail"))
    'error: ValueError: size must be in [1, 100], got 500'
    >>> error_line(ZeroDivisionError())
    'error: ZeroDivisionError'
    """
    validate.check_instance("exc", exc, BaseException, "an exception")
    lines = str(exc).strip().splitlines()
    text = f"error: {type(exc).__name__}" + (f": {lines[0].strip()}" if lines else "")
    if len(text) > _ERROR_MAX_CHARS:
        text = text[:_ERROR_MAX_CHARS - 1] + "\u2026"
    return text


def explore(plot: Callable, *, main=None, initial=None, max_frames=12, dpi=80, ahead=None,
            **params):
    """Explore a pure plotting function over parameter grids, live in Jupyter and in HTML.

    Parameters
    ----------
    plot : callable
        ``plot(**values) -> matplotlib.figure.Figure``; pure (same values, same figure).
        Prefer ``matplotlib.figure.Figure()`` over ``pyplot`` inside it; figures are closed
        after use either way.
    main : str, optional
        The parameter the HTML scrubber moves through; default the first grid parameter.
    initial : dict, optional
        ``{grid name: opening value}`` (one of the grid's values); default the
        middle of the scrubber's frames for ``main`` and the middle value of other grids.
    max_frames : int, optional
        At most this many frames in the scrubber (2 to 60), spread evenly over the grid of
        ``main`` and always including its initial value. Default 12.
    dpi : int, optional
        Resolution of the frames (30 to 300). Default 80.
    ahead : bool, optional
        Whether the live widget computes its other positions in the background after its
        opening frame (see the module); default :func:`ahead_default` (on in a reader's
        kernel). The HTML scrubber is the same either way.
    **params
        ``name=grid`` (a list, tuple, range or 1-D array of values, each once and no NaN: a
        control; a grid of real numbers is put in increasing order, any other keeps the order
        given) or ``name=value`` (passed unchanged; not a generator), each a keyword ``plot``
        takes, and every one it needs. At least one grid is required.

    Returns
    -------
    Explorer
        Display it (the last expression of a cell): a live widget in Jupyter, the
        scrubber (:meth:`Explorer.html`) in the HTML book.

    Raises
    ------
    ValueError
        An argument of the wrong kind or out of range (named), a keyword ``plot`` does not
        take or needs, or ``plot`` not returning a Figure.

    Examples
    --------
    >>> import numpy as np
    >>> from matplotlib.figure import Figure
    >>> def wave(omega=1.0, phase=0.0):
    ...     fig = Figure(figsize=(4, 2))
    ...     t = np.linspace(0.0, 10.0, 200)
    ...     fig.add_subplot().plot(t, np.sin(omega * t + phase))
    ...     return fig
    >>> ex = explore(wave, omega=np.linspace(0.5, 3.0, 11), phase=0.0, max_frames=6)
    >>> ex.main, len(ex.frame_values), ex.initial
    ('omega', 6, {'omega': 1.5})
    >>> page = ex.html()
    >>> page.count('type="range"'), len(ex.frames())
    (1, 6)
    >>> explore(wave, phase=0.0)
    Traceback (most recent call last):
    ...
    ValueError: explore needs at least one parameter grid (name=[values...]), got only phase
    """
    max_frames = validate.check_int("max_frames", max_frames, 2, 60)  # an int: np.uint8 wraps
    dpi = validate.check_int("dpi", dpi, 30, 300)
    ahead = None if ahead is None else validate.check_bool("ahead", ahead)  # "no" is not True
    validate.check_callable("plot", plot, "a function plot(**values) -> Figure")
    validate.check_keywords("explore", params, plot)  # a misspelt name now, not at a frame
    try:  # every parameter plot needs is given (a builtin has no signature: its own check)
        need = [p.name for p in inspect.signature(plot).parameters.values() if p.default is p.empty
                and p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY) and p.name not in params]
    except (TypeError, ValueError):
        need = []
    if need:
        raise ValueError(f"plot needs {', '.join(need)}: give each a grid or a value (name=...)")
    grids = {name: grid_values(name, value) for name, value in params.items() if is_grid(value)}
    fixed = {name: value for name, value in params.items() if name not in grids}
    if not grids:
        raise ValueError("explore needs at least one parameter grid (name=[values...]), got "
                         + (f"only {', '.join(fixed)}" if fixed else "no parameters"))
    if main is not None:
        validate.check_instance("main", main, str, "the name of a grid parameter (str)")
    main = validate.check_choice("main", next(iter(grids)) if main is None else main, tuple(grids))
    initial = {} if initial is None else validate.check_instance(
        "initial", initial, dict, "a dict {grid name: opening value}")
    for name in initial:
        if not isinstance(name, str) or name not in grids:
            raise ValueError(f"initial[{name!r}] is not a grid parameter: the grids are "
                             + ", ".join(grids))
    start = {}
    for name, grid in grids.items():
        if name in initial:
            start[name] = grid[grid_index(grid, initial[name], f"initial[{name!r}]")]
        elif name == main:
            n = min(max_frames, len(grid))
            idx = sorted(set(np.round(np.linspace(0, len(grid) - 1, n)).astype(int).tolist()))
            start[name] = grid[idx[(len(idx) - 1) // 2]]
        else:
            start[name] = grid[(len(grid) - 1) // 2]
    return Explorer(plot, grids, fixed, main, start, max_frames, dpi, ahead)


def ahead_default():
    """Whether a live widget computes its frames ahead when :func:`explore` is not told.

    On inside a Jupyter kernel, except where a page is executed for the HTML book
    (:data:`FRAMES_ENV` is ``"1"``: nobody moves a slider there) and where
    :data:`AHEAD_ENV` is ``"0"``; off outside a kernel (scripts, tests). In a kernel the
    worker waits for the kernel to be idle a second after a cell, so a "Run All" (and
    nbval, whose cells follow each other at once) runs without it.

    Examples
    --------
    >>> ahead_default()  # not in a kernel
    False
    """
    return (_in_kernel() and not env_switch(FRAMES_ENV, False)
            and env_switch(AHEAD_ENV, True))


@functools.cache
def _interactive_class(w):
    """``ipywidgets.interactive`` whose ``close`` also stops its slider's worker."""

    class Interactive(w.interactive):
        on_close = None  # set to the Explorer's _stop

        def close(self):
            if self.on_close is not None:
                self.on_close()
            super().close()

    return Interactive


def _control(w, name, grid, value):
    """A slider over a numeric grid, a menu over anything else; ``continuous_update=False``."""
    numeric = all(isinstance(g, Number) and not isinstance(g, bool) for g in grid)
    labels = [grid_label(g) for g in grid]
    if len(set(labels)) < len(labels):  # 4 significant digits were not enough
        labels = [repr(g) for g in grid]
    if numeric and len(grid) > 1:
        options = list(zip(labels, grid, strict=True))
        return w.SelectionSlider(options=options, value=value, description=name,
                                 continuous_update=False)
    return w.Dropdown(options=list(zip(labels, grid, strict=True)), value=value, description=name)


def _in_kernel():
    """True inside a running IPython kernel (Jupyter, or the book's build)."""
    try:
        from IPython import get_ipython
    except ImportError:  # pragma: no cover
        return False
    ip = get_ipython()
    return ip is not None and getattr(ip, "kernel", None) is not None
