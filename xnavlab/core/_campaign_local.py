"""The local engines of :func:`xnavlab.core.campaign.run_campaign` (``"serial"`` and
``"local"``): plumbing, not public API. ``execute`` and ``describe`` are the campaign module's
(passed: no import cycle)."""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import signal
import sys
import threading
import time
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool

__all__ = ["Serial", "Pool"]

#: Seconds to wait for a worker to end after SIGTERM, then again after SIGKILL.
_END_S = 2.0


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
    """Pool worker initializer: ignore SIGINT, and end this worker when the campaign process
    that started it ends.

    A Ctrl-C reaches the terminal's whole process group, workers included: the parent
    decides (it ends its workers, :meth:`Pool.close`), so a worker ignores SIGINT (it started
    with SIGINT blocked, :func:`_sigint_held`, so none reached it before) and prints no
    traceback. However the parent ends (SIGINT, SIGTERM, SIGKILL), its workers must not
    outlive it: they would keep computing for nobody and, before the store's descriptor was
    kept from them, held its lock. On Linux the kernel sends SIGKILL at the parent's death
    (``prctl(PR_SET_PDEATHSIG)``); everywhere a daemon thread checks every 0.2 s that the
    parent is still the same process and exits otherwise.
    """
    _deaf_to_sigint()
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


def _deaf_to_sigint():
    """In a worker: SIGINT ignored (and unblocked: a SIGINT pending while it was blocked is
    dropped), and tqdm's lock a thread lock: a run's (disabled) progress bar would make it a
    multiprocessing semaphore, which a worker ended mid-run leaves registered ("leaked
    semaphore objects" warned at exit)."""
    from tqdm import tqdm

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
    tqdm.set_lock(threading.RLock())


def _in_main_thread():
    return threading.current_thread() is threading.main_thread()


@contextlib.contextmanager
def _sigint_held():
    """Context: a SIGINT waits until it ends (then raises KeyboardInterrupt as usual), and a
    process started within it starts with SIGINT blocked.

    Pool workers are started inside it: a Ctrl-C cannot reach one before its initializer
    ignores SIGINT (:func:`_die_with`), nor stop the parent between starting a worker and
    recording it. Only the main thread of a POSIX system holds it; elsewhere it does nothing.
    """
    handler = signal.getsignal(signal.SIGINT)
    if not (hasattr(signal, "pthread_sigmask") and _in_main_thread()) or handler is None:
        yield
        return
    caught = []
    signal.signal(signal.SIGINT, lambda signum, frame: caught.append(signum))
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)
        signal.signal(signal.SIGINT, handler)  # a SIGINT pending in the mask is caught first
        if caught:
            signal.raise_signal(signal.SIGINT)  # to the handler it was meant for


@contextlib.contextmanager
def _sigint_ignored():
    """Context: SIGINT ignored (main thread only), so that a second Ctrl-C, or ``timeout``'s
    SIGINT to the process and then to its group, cannot break off ending the pool."""
    handler = signal.getsignal(signal.SIGINT)
    if not _in_main_thread() or handler is None:
        yield
        return
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, handler)


class Pool:
    """A local process pool that is rebuilt when a worker dies (BrokenProcessPool).

    Workers are started with ``spawn`` (they inherit no open file, so never the store's
    lock), ignore SIGINT and end with the campaign process (:func:`_die_with`). Closed with
    runs in flight (an interrupt, an error), it ends at once: its workers are terminated,
    not waited for.
    """

    def __init__(self, workers, execute, describe):
        self._execute, self._describe = execute, describe
        self.workers = workers
        self.window = 2 * workers
        self.pool = self._new()
        self.processes = set()  # every worker started (multiprocessing.Process)
        self._open = 0  # runs submitted and not yet returned by wait (never under-counted)

    def _new(self):
        return ProcessPoolExecutor(max_workers=self.workers,
                                   mp_context=multiprocessing.get_context("spawn"),
                                   initializer=_die_with, initargs=(os.getpid(),))

    def submit(self, trial, seed, params):
        self._open += 1
        with _sigint_held():  # the workers this starts are recorded, and start deaf to SIGINT
            before = set(multiprocessing.active_children())
            try:
                return self.pool.submit(self._execute, trial, seed, params)
            except BrokenProcessPool:
                self.pool.shutdown(wait=False, cancel_futures=True)
                self.pool = self._new()
                return self.pool.submit(self._execute, trial, seed, params)
            finally:
                self.processes |= set(multiprocessing.active_children()) - before

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
        self._open -= len(out)
        return out

    def close(self):
        """End the pool: its idle workers exit; with runs in flight, or interrupted while
        they exit, every worker is terminated at once (:meth:`end`)."""
        if self._open:
            self.end()
            return
        try:
            self.pool.shutdown(wait=True)
        except BaseException:
            self.end()
            raise

    def end(self):
        """Cancel the pending runs and end the workers now, without waiting on the pool's
        queues: SIGTERM, then SIGKILL to a worker still there after ``_END_S`` seconds."""
        with _sigint_ignored():
            self.pool.shutdown(wait=False, cancel_futures=True)
            for p in self.processes:
                if p.exitcode is None:
                    p.terminate()
            for p in self.processes:
                p.join(_END_S)
                if p.exitcode is None:
                    p.kill()
                    p.join(_END_S)
