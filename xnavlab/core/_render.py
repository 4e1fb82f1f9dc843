"""The Agg renderers that the frames of :mod:`xnavlab.core.widgets` are drawn on.

Plumbing of the live widget and the scrubber (:func:`xnavlab.core.widgets.live_png`,
:class:`xnavlab.core.widgets.SteadyLayout`), not meant for readers: a canvas whose renderer is
shared by every frame of its size and records the texts it draws (what the kept layout is
checked on).
"""

from __future__ import annotations

import functools

__all__ = ["RENDERERS", "MAX_RENDERERS", "shared_renderer", "recording_canvas_class"]

# Agg renderers shared by the frames of every slider, by (width px, height px, dpi): matplotlib
# keeps the text metrics it measures (and its parsed math) per renderer, so a frame drawn on
# a renderer used before measures only its new texts (0.33 -> 0.28 s for chapter 1's figure).
# A renderer is cleared at each draw; frames are drawn one at a time (under the widgets' RENDER_LOCK).
RENDERERS = {}
MAX_RENDERERS = 4


def shared_renderer(cls, key):
    """The renderer of size ``key`` (made on first use; the least recently used dropped)."""
    renderer = RENDERERS.pop(key, None) or cls(*key)
    RENDERERS[key] = renderer  # most recently used last
    while len(RENDERERS) > MAX_RENDERERS:
        RENDERERS.pop(next(iter(RENDERERS)))
    return renderer


@functools.cache
def recording_canvas_class():
    """An Agg canvas whose renderer keeps every Text it draws (attribute ``texts``)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg, RendererAgg

    class TextRecorder(RendererAgg):
        def __init__(self, width, height, dpi):
            super().__init__(width, height, dpi)
            self.texts = []

        def clear(self):
            super().clear()
            self.texts = []

        def draw_text(self, gc, x, y, s, prop, angle, ismath=False, mtext=None):
            if mtext is not None:
                self.texts.append(mtext)
            return super().draw_text(gc, x, y, s, prop, angle, ismath=ismath, mtext=mtext)

    class RecordingCanvas(FigureCanvasAgg):
        def get_renderer(self):
            w, h = self.get_width_height(physical=True)
            key = w, h, self.figure.dpi
            if self._lastKey != key:
                self.renderer = shared_renderer(TextRecorder, key)
                self._lastKey = key
            return self.renderer

    return RecordingCanvas
