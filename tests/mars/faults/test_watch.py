"""xnavlab.mars.faults.watch: the combined detector's state between kernel calls (alarms to events,
isolation, re-admission). The kernel side is exercised by every fault-tolerant run
(tests/mars/faults/test_fault_tolerance.py); here the bookkeeping is driven by hand."""

import math

import numpy as np

from xnavlab.core.detection import CombinedDesign, InnovationMonitor
from xnavlab.mars.faults.watch import Watch
from xnavlab.mars.kernel import kernel_inputs, kernels

READMIT = ({"uv": 100, "cns": 100}, {"uv": 350.0, "cns": 350.0}, {"uv": 3.3, "cns": 3.3}, 100)


def _watch():
    mon = {s: InnovationMonitor(CombinedDesign(28800.0, 3)) for s in ("uv", "cns")}
    return Watch(("xnav", "uv", "cns"), mon, None, {"uv": 10, "cns": 7}, 600.0, READMIT)


def test_the_kernels_argument_shares_the_watchs_arrays():
    w = _watch()
    ws = w.arrays()
    assert isinstance(ws, kernel_inputs.WatchState)
    assert ws.ys_u.shape == (10, 3) and ws.ys_c.shape == (7, 3)
    assert np.all(np.isnan(ws.ys_u))                       # no innovation taken yet
    ws.alarm[1, 0] = 0.0
    assert w.alarm[1, 0] == 0.0                            # the same array, not a copy
    assert w.wi[1, kernels.WI_ON] == 1 and w.wi[0, kernels.WI_ON] == 0   # xnav unwatched here


def test_an_alarm_becomes_an_open_event_and_is_cleared_by_readmission():
    w = _watch()
    w.alarm[1] = [0.0, 7.5, -1.0, -1.0]                    # uv: part 0 alarmed, ratio 7.5
    assert w.after_stop(1000.0) == ["uv"]
    assert np.all(w.alarm == -1.0)                         # consumed
    (ev,) = w.events("uv")
    assert ev.onset == 1000.0 and math.isinf(ev.cleared) and ev.peak == 7.5
    w.set_out(np.array([False, True, False]))
    assert w.wi[1, kernels.WI_OUT] == 1 and w.wi[1, kernels.WI_NOUT] == 0
    w.readmit("uv")
    assert w.wi[1, kernels.WI_OUT] == 0 and np.all(w.wS[1] == 0.0)
    (ev,) = w.events("uv")
    assert ev.cleared == ev.end == 1000.0                  # closed at its last alarm
    assert w.events("cns") == [] and w.after_stop(2000.0) == []


def test_the_scale_starts_at_the_monitors_and_is_read_as_a_copy():
    w = _watch()
    assert np.array_equal(w.scale("uv"), w.monitors["uv"].scale)
    w.wsc[1, 0] = 2.0                                      # as the kernel adapts it
    got = w.scale("uv")
    assert got[0] == 2.0 and got.shape == (3,)
    got[0] = 5.0
    assert w.wsc[1, 0] == 2.0                              # the caller's copy only
