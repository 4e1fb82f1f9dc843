"""Frames computed ahead for :mod:`xnavlab.core.widgets`: a slider's frame cache and its worker.

Plumbing of the live widget (:class:`xnavlab.core.widgets.Explorer`), not meant for readers.
After the opening frame, a background thread draws the slider's other positions, nearest
first, into a :class:`FrameCache`; a move onto a position it has drawn is a lookup.

Threads and matplotlib. Matplotlib is not thread-safe as a whole, but its documentation
("Working with threads" in the FAQ) allows separate figures in separate threads with a
non-interactive backend such as Agg, serialised by the user where they share state. Here:

- every thread draws only its own :class:`~matplotlib.figure.Figure` objects (the worker
  builds its own, never touches the foreground's; no pyplot state: a slider whose figures
  are registered with pyplot gets no worker);
- every Agg draw holds :data:`RENDER_LOCK`, since the widgets share their Agg renderers and
  the slider's kept layout between frames (fonts are per thread in matplotlib's font cache,
  keyed by the thread's id; text metrics are cached per renderer);
- the worker computes only while no foreground frame is being drawn (:func:`foreground`), no
  notebook cell runs and the kernel has been idle :data:`IDLE_S` seconds (so a "Run All", or
  nbval's back-to-back cells, never run beside it), and only for the slider that was moved
  or opened last (:meth:`AheadWorker.kick`); one such worker computes at a time.

The worker is a daemon thread (it never keeps a kernel alive) that ends when its slider has
nothing left to draw, when another slider becomes the active one, or when
:meth:`AheadWorker.stop` is called (the widget closed); a move starts it again.
"""

from __future__ import annotations

import itertools
import threading
import time
from contextlib import contextmanager

__all__ = ["RENDER_LOCK", "IDLE_S", "MAX_POSITIONS", "Failed", "FrameCache", "AheadWorker",
           "foreground", "distance"]

#: Held by every Agg draw of a slider frame (shared renderers, kept layouts).
RENDER_LOCK = threading.RLock()

#: Seconds the kernel must have been idle after a cell before a worker computes.
IDLE_S = 1.0

#: Sliders with more positions than this are computed ahead only one control away.
MAX_POSITIONS = 4096


class Failed:
    """A position whose frame raised: the widget's one error line for it."""

    def __init__(self, line):
        self.line = line


def distance(a, b):
    """How far position ``b`` is from ``a`` (tuples of grid indices): (controls moved, steps).

    A reader moves one control at a time, so every position one control away comes first,
    the nearest steps first.

    Examples
    --------
    >>> distance((0, 1, 2), (0, 3, 2)), distance((0, 1, 2), (1, 2, 2))
    ((1, 2), (2, 2))
    """
    moved = [abs(x - y) for x, y in zip(a, b, strict=True) if x != y]
    return len(moved), sum(moved)


class _Gate:
    """When a worker may compute: shared by every slider of the process."""

    def __init__(self):
        self.cond = threading.Condition()
        self.busy = 0  # foreground frames being drawn
        self.cell_running = False
        self.idle_since = -float("inf")
        self.active = None  # the worker of the slider moved or opened last
        self.watching = False

    def watch_cells(self):
        """Follow IPython's cells (once): a worker waits while one runs and IDLE_S after."""
        if self.watching:
            return
        try:
            from IPython import get_ipython
        except ImportError:  # pragma: no cover
            return
        ip = get_ipython()
        if ip is None:
            return
        self.watching = True
        with self.cond:  # called from a cell (the explore call's): it is running now
            self.cell_running = True

        def pre(*_):
            with self.cond:
                self.cell_running = True

        def post(*_):
            with self.cond:
                self.cell_running = False
                self.idle_since = time.monotonic()
                self.cond.notify_all()

        ip.events.register("pre_run_cell", pre)
        ip.events.register("post_run_cell", post)

    def wait_turn(self, worker):
        """Block until ``worker`` may start a frame; ``False`` when it must end instead."""
        with self.cond:
            while True:
                if worker.stopped or self.active is not worker:
                    return False
                wait = IDLE_S - (time.monotonic() - self.idle_since)
                if not self.busy and not self.cell_running and wait <= 0:
                    return True
                self.cond.wait(timeout=max(wait, 0.05) if not self.cell_running else None)

    def wait_no_foreground(self):
        """Block while a foreground frame is being drawn (the worker's render waits for it)."""
        with self.cond:
            while self.busy:
                self.cond.wait()


_GATE = _Gate()
_TURN = threading.Lock()  # one worker computes at a time


@contextmanager
def foreground():
    """Mark a frame the reader waits for: workers start nothing new until it is drawn."""
    with _GATE.cond:
        _GATE.busy += 1
    try:
        yield
    finally:
        with _GATE.cond:
            _GATE.busy -= 1
            _GATE.cond.notify_all()


class FrameCache:
    """One slider's finished frames by position (a tuple of grid indices), nearest kept.

    Entries are PNG bytes or :class:`Failed`. At most ``capacity`` are kept: the one farthest
    (:func:`distance`) from ``current`` goes first.
    """

    def __init__(self, sizes, capacity):
        self.sizes = tuple(sizes)
        self.capacity = capacity
        self.frames = {}
        self.current = None
        self.heading = None  # (control, moved up) of the last move of one control
        self.in_flight = None  # the position the worker is drawing
        self.cond = threading.Condition()

    def get(self, pos, wait=True):
        """The frame at ``pos`` (``None`` if absent); waits for it if the worker is drawing it."""
        with self.cond:
            while wait and self.in_flight == pos:
                self.cond.wait()
            return self.frames.get(pos)

    def put(self, pos, entry):
        with self.cond:
            self.frames[pos] = entry
            while len(self.frames) > self.capacity:
                far = max((p for p in self.frames if p != self.current),
                          key=lambda p: distance(self.current or p, p))
                del self.frames[far]
            self.cond.notify_all()

    def move(self, pos):
        """The reader is at ``pos`` now (after a move of one control, its direction kept)."""
        with self.cond:
            if self.current is not None and pos != self.current:
                moved = [k for k, (a, b) in enumerate(zip(self.current, pos, strict=True))
                         if a != b]
                k = moved[0]
                self.heading = (k, pos[k] > self.current[k]) if len(moved) == 1 else None
            self.current = pos

    def order(self, pos):
        """Sort key of a position to draw: :func:`distance` from ``current``, then (among
        equals) the control moved last before others, in the direction it moved: a reader
        sweeping a slider goes on."""
        here = self.current
        near = distance(here, pos)
        if self.heading is None or near[0] != 1:
            return (*near, 1, 1)
        k, up = self.heading
        return (*near, pos[k] == here[k], (pos[k] > here[k]) != up)

    def positions(self):
        """Every position of the grids (or those one control away from ``current`` when
        there are more than :data:`MAX_POSITIONS`)."""
        total = 1
        for n in self.sizes:
            total *= n
        if total <= MAX_POSITIONS:
            return itertools.product(*(range(n) for n in self.sizes))
        return ((*self.current[:k], i, *self.current[k + 1:])
                for k, n in enumerate(self.sizes) for i in range(n))

    def claim_next(self):
        """The nearest position not yet drawn, now in flight; ``None`` when none is worth it
        (all drawn, or the cache full of nearer frames)."""
        with self.cond:
            if self.current is None:
                return None
            here = self.current
            todo = [p for p in self.positions() if p not in self.frames]
            if not todo:
                return None
            pos = min(todo, key=self.order)
            if len(self.frames) >= self.capacity:
                farthest = max(distance(here, p) for p in self.frames)
                if distance(here, pos) >= farthest:
                    return None
            self.in_flight = pos
            return pos

    def release(self, pos, entry):
        """Store the worker's frame for ``pos`` (``None``: dropped) and wake who waits for it."""
        with self.cond:
            if entry is not None:
                self.put(pos, entry)
            self.in_flight = None
            self.cond.notify_all()


class AheadWorker:
    """The background thread that fills a :class:`FrameCache` with ``compute(pos)``'s frames.

    ``compute(pos)`` returns an entry (PNG bytes or :class:`Failed`); it calls
    :meth:`render_turn` before its Agg draw and draws under :data:`RENDER_LOCK`.
    """

    def __init__(self, cache, compute):
        self.cache = cache
        self.compute = compute
        self.stopped = False
        self.computed = 0  # frames drawn ahead (for tests and benchmarks)
        self._thread = None

    def kick(self):
        """Make this the active worker and (re)start its thread; from the foreground."""
        _GATE.watch_cells()
        with _GATE.cond:
            if self.stopped:
                return
            _GATE.active = self
            _GATE.cond.notify_all()
        if self._thread is None or not self._thread.is_alive():
            self._thread = threading.Thread(target=self._run, name="xnavlab-ahead", daemon=True)
            self._thread.start()

    def stop(self, timeout=None):
        """End the thread after its current frame (waits up to ``timeout`` s for it)."""
        with _GATE.cond:
            self.stopped = True
            if _GATE.active is self:
                _GATE.active = None
            _GATE.cond.notify_all()
        if self._thread is not None and timeout is not None:
            self._thread.join(timeout)

    def idle(self, timeout=None):
        """Wait until the thread has ended (nothing left, or stopped); ``True`` if it has."""
        if self._thread is not None:
            self._thread.join(timeout)
        return self._thread is None or not self._thread.is_alive()

    @staticmethod
    def render_turn():
        """Wait until no foreground frame is being drawn (called by ``compute``)."""
        _GATE.wait_no_foreground()

    def _run(self):
        while _GATE.wait_turn(self):
            with _TURN:
                pos = self.cache.claim_next()
                if pos is None:
                    return
                entry = None
                try:
                    entry = self.compute(pos)
                    self.computed += 1
                finally:
                    self.cache.release(pos, None if self.stopped else entry)
