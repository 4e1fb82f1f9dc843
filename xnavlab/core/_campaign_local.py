"""The local engines of :func:`xnavlab.core.campaign.run_campaign` (``"serial"`` and
``"local"``): plumbing, not public API. ``execute`` and ``describe`` are the campaign module's
(passed: no import cycle)."""

from __future__ import annotations

import multiprocessing
import os
import signal
import sys
import threading
import time
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool

__all__ = ["Serial", "Pool"]


class Serial:
    window = 1

    def __init__(self, execute):
        self._execute = execute
        self._done = {}
        self._n = 0

    def submit(self, trial, seed, params):
        self._n += 1
        self._done[self._n] = ("ok", self._execute(trial, seed, params))
        return self._n

    def wait(self, handles):
        return [(h, self._done.pop(h)) for h in handles]

    def close(self):
        pass


def _die_with(parent_pid):
    """Pool worker initializer: end this worker when the campaign process that started it ends.

    However the parent ends (SIGINT, SIGTERM, SIGKILL), its workers must not outlive it:
    they would keep computing for nobody and, before the store's descriptor was kept from
    them, held its lock. On Linux the kernel sends SIGKILL at the parent's death
    (``prctl(PR_SET_PDEATHSIG)``); everywhere a daemon thread checks every 0.2 s that the
    parent is still the same process and exits otherwise.
    """
    if sys.platform.startswith("linux"):
        try:
            import ctypes

            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(1, int(signal.SIGKILL), 0, 0, 0)  # PR_SET_PDEATHSIG = 1
        except (OSError, AttributeError):  # pragma: no cover - the watchdog still runs
            pass
    if os.getppid() != parent_pid:  # the parent died before the prctl took effect
        os._exit(1)

    def watch():
        while True:
            time.sleep(0.2)
            if os.getppid() != parent_pid:
                os._exit(1)

    threading.Thread(target=watch, name="xnavlab-parent-watch", daemon=True).start()


class Pool:
    """A local process pool that is rebuilt when a worker dies (BrokenProcessPool).

    Workers are started with ``spawn`` (they inherit no open file, so never the store's
    lock) and end with the campaign process (:func:`_die_with`).
    """

    def __init__(self, workers, execute, describe):
        self._execute, self._describe = execute, describe
        self.workers = workers
        self.window = 2 * workers
        self.pool = self._new()

    def _new(self):
        return ProcessPoolExecutor(max_workers=self.workers,
                                   mp_context=multiprocessing.get_context("spawn"),
                                   initializer=_die_with, initargs=(os.getpid(),))

    def submit(self, trial, seed, params):
        try:
            return self.pool.submit(self._execute, trial, seed, params)
        except BrokenProcessPool:
            self.pool.shutdown(wait=False, cancel_futures=True)
            self.pool = self._new()
            return self.pool.submit(self._execute, trial, seed, params)

    def wait(self, handles):
        done, _ = wait(handles, return_when=FIRST_COMPLETED)
        out = []
        for f in done:
            exc = f.exception()
            if exc is None:
                out.append((f, ("ok", f.result())))
            elif isinstance(exc, BrokenProcessPool):
                out.append((f, ("lost", "WorkerDied: the worker process running this run "
                                        "died (BrokenProcessPool)")))
            else:
                out.append((f, ("error", self._describe(exc))))
        return out

    def close(self):
        self.pool.shutdown(wait=True, cancel_futures=True)
