"""The base class of the online detectors: their events, read from an event tracker.

Plumbing of :mod:`xnavlab.core.detection`: :class:`~xnavlab.core.detection.online.WaveletDetector`,
:class:`~xnavlab.core.detection.chisquare.Chi2Detector` and
:class:`~xnavlab.core.detection.combined.InnovationMonitor` derive from it; not part of the
public API.
"""

from __future__ import annotations

__all__ = ["TrackedDetector"]


class TrackedDetector:
    """Base of the online detectors: event reporting from an
    :class:`~xnavlab.core.detection.online.EventTracker`.

    A subclass keeps its tracker in ``self._tracker``; this base exposes its events. Its
    one-sample ``update`` calls :meth:`_advance_time` (sample times strictly increase).
    """

    _t_last = float("-inf")   # the latest sample time fed (set per instance once fed)

    def _advance_time(self, t):
        """Refuse a sample time ``t`` (s, checked real) not after the last one fed (an event
        would end or clear before its onset); else record it."""
        if not t > self._t_last:
            raise ValueError(f"t must increase from one update to the next (sample times, s), "
                             f"got t = {t:g} after t = {self._t_last:g}")
        self._t_last = t

    @property
    def events(self):
        """Closed events, list of :class:`~xnavlab.core.detection.online.Event`."""
        return self._tracker.events

    @property
    def faulty(self):
        """Whether an event is open now."""
        return self._tracker.faulty

    def all_events(self):
        """Closed events plus the open one."""
        return self._tracker.all_events()
