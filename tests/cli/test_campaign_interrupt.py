"""Review 35 R11 and R14: a campaign interrupted by SIGINT, as a terminal's Ctrl-C sends it (to
the whole process group) or as ``timeout -s INT`` does (to the process, then to its group).

It printed its one line and then, about half the time, hung for good in the interpreter's exit
(a pool worker waiting on its queue, ``owner.pid`` left in the folder); or printed a worker's
traceback, or an atexit one with leaked-semaphore warnings. Now the workers ignore SIGINT, the
parent ends them without waiting on the pool's queues, and exits 130 with one line.
"""

import json
import os
import signal
import subprocess
import sys
import time

import psutil
import pytest

from xnavlab.core.campaign import OWNER_FILE, STORE_FILE

ENV = {**os.environ, "NUMBA_NUM_THREADS": "1"}


def _campaign(out, workers):
    return [sys.executable, "-m", "xnavlab", "campaign", "consistency", "--runs", "4",
            "--days", "0.3", "--seed", "3", "--workers", str(workers), "--out", str(out),
            "--quiet"]


def _sigint_default():
    """In the child: SIGINT as a terminal's shell leaves it. A test process may have it ignored
    (a job started in the background with &, some CI runners, pytest-xdist's workers), and a
    process that starts with SIGINT ignored keeps it so, as it should: nothing to interrupt."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _start_until_first_record(argv, out):
    """The campaign, started in a session of its own (its own process group, as a terminal
    makes), once its first record is stored (or after 120 s)."""
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=ENV, start_new_session=True, preexec_fn=_sigint_default)
    store = out / STORE_FILE
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and proc.poll() is None:
        if store.exists() and store.stat().st_size:
            break
        time.sleep(0.05)
    return proc


@pytest.mark.parametrize(("workers", "how"), [(1, "timeout"), (2, "group")])
def test_sigint_exits_130_with_one_line_and_the_same_command_completes(tmp_path, workers, how):
    out = tmp_path / "camp"
    argv = _campaign(out, workers)
    proc = _start_until_first_record(argv, out)
    try:
        assert proc.poll() is None, "the campaign ended before it was interrupted"
        children = psutil.Process(proc.pid).children(recursive=True)
        if how == "timeout":  # timeout -s INT: the process, then its group
            os.kill(proc.pid, signal.SIGINT)
        os.killpg(proc.pid, signal.SIGINT)  # a terminal's Ctrl-C: the whole group
        _, err = proc.communicate(timeout=60)  # it hung for good (R11); now within a second
        _, alive = psutil.wait_procs(children, timeout=20)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate(timeout=30)
    assert proc.returncode == 130, err
    assert err.splitlines() == [f"xnavlab: interrupted; the finished runs are in {out}; run "
                                f"the same command to complete the campaign"], err
    assert not alive, f"processes of the interrupted campaign still running: {alive}"
    assert not (out / OWNER_FILE).exists()
    done = subprocess.run([*argv, "--json"], capture_output=True, text=True, env=ENV,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    payload = json.loads(done.stdout)
    assert payload["failed"] == 0 and payload["reused"] >= 1
    assert [r["index"] for r in payload["runs"]] == [0, 1, 2, 3]


def test_a_finished_campaign_leaves_the_sigint_handler_as_it_was(tmp_path, capsys):
    """The campaign's own SIGINT handler (the first SIGINT interrupts, later ones are
    ignored) is only the campaign's: a command that was not interrupted restores Python's."""
    from xnavlab.cli import main

    argv = ["campaign", "consistency", "--runs", "1", "--days", "0.02", "--workers", "1",
            "--out", str(tmp_path / "c"), "--quiet"]
    before = signal.signal(signal.SIGINT, signal.default_int_handler)  # as in a terminal
    try:
        assert main(argv) == 0, capsys.readouterr().err
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    finally:
        signal.signal(signal.SIGINT, before)
