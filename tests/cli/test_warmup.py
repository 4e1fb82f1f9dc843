"""``python -m xnavlab warmup`` (xnavlab.cli.warmup): the steps run in order, each reported on one
line with its time, and the command exits 0. The steps themselves (the numba compiles) are
replaced by stand-ins: they are what the chapters and the Mars tests run anyway."""

import io
import subprocess
import sys
import time

import numpy as np
import pytest

from xnavlab.cli import main, warmup
from xnavlab.mars.models import dynamics
from xnavlab.mars.navigation import scenarios


def test_every_step_has_a_label_and_a_function():
    labels = [label for label, _ in warmup.STEPS]
    assert len(set(labels)) == len(labels) >= 3
    assert all(callable(func) for _, func in warmup.STEPS)


def test_warm_runs_the_steps_in_order_and_reports_each(monkeypatch):
    done = []
    monkeypatch.setattr(warmup, "STEPS", (("first", lambda: done.append(1)),
                                          ("second", lambda: done.append(2))))
    stream = io.StringIO()
    times = warmup.warm(stream)
    assert done == [1, 2] and list(times) == ["first", "second"]
    assert all(t >= 0.0 for t in times.values())
    lines = stream.getvalue().splitlines()
    assert [line.split(":")[1].strip() for line in lines] == ["first", "second"]
    assert all(line.startswith("warmup: ") and line.endswith(" s") for line in lines)


def test_the_command_runs_warm_and_exits_0(monkeypatch, capsys):
    called = []
    monkeypatch.setattr(warmup, "warm", lambda stream: called.append(stream.write("line\n")) or {})
    assert main(["warmup"]) == 0 and called == [5]
    assert capsys.readouterr().err == "line\n"  # its lines on the command's standard error


def _beside(monkeypatch, code):
    """Make warm start ``code`` in a second process as the kernel's compile."""
    started = []

    def start(stream):
        proc = subprocess.Popen([sys.executable, "-c", code])
        started.append(proc)
        return proc, time.perf_counter()

    monkeypatch.setattr(warmup, "_compile_beside", lambda: True)
    monkeypatch.setattr(warmup, "_start_kernel_compile", start)
    return started


def test_the_kernel_compiles_beside_the_steps_before_it(monkeypatch, tmp_path):
    """The steps before the kernel run while it compiles; those after wait for it."""
    flag = tmp_path / "compiled"
    started = _beside(monkeypatch, f"import time, pathlib; time.sleep(1.0); "
                                   f"pathlib.Path({str(flag)!r}).touch()")
    seen = {}
    monkeypatch.setattr(warmup, "STEPS", (
        ("before", lambda: seen.update(before=flag.exists())),
        (warmup.KERNEL_STEP, lambda: seen.update(ran_here=True)),
        ("after", lambda: seen.update(after=flag.exists()))))
    times = warmup.warm(io.StringIO())
    assert seen == {"before": False, "after": True}  # the kernel step ran in the child
    assert started[0].returncode == 0 and list(times) == ["before", warmup.KERNEL_STEP, "after"]
    assert times[warmup.KERNEL_STEP] >= 1.0  # timed from the child's start, not from its turn


def test_a_failed_compile_or_step_stops_the_warm_up(monkeypatch):
    _beside(monkeypatch, "raise SystemExit(3)")
    monkeypatch.setattr(warmup, "STEPS", ((warmup.KERNEL_STEP, lambda: None),))
    with pytest.raises(RuntimeError, match="exit code 3"):
        warmup.warm(io.StringIO())
    started = _beside(monkeypatch, "import time; time.sleep(60)")

    def fail():
        raise ValueError("a step before the kernel failed")

    monkeypatch.setattr(warmup, "STEPS", (("before", fail), (warmup.KERNEL_STEP, lambda: None)))
    with pytest.raises(ValueError, match="failed"):
        warmup.warm(io.StringIO())
    assert started[0].returncode is not None  # the compile was stopped, not left running


def test_the_steps_after_the_kernel_run_in_worker_processes(monkeypatch):
    """After the kernel, the steps share the cores: each in a pool worker, a line as it ends."""
    import os

    monkeypatch.setattr(warmup, "_compile_beside", lambda: False)
    monkeypatch.setattr(warmup, "STEPS", ((warmup.KERNEL_STEP, lambda: None),
                                          ("a", os.getpid), ("b", os.getpid)))
    stream = io.StringIO()
    times = warmup.warm(stream, workers=2)
    assert set(times) == {warmup.KERNEL_STEP, "a", "b"}
    assert sorted(line.split(":")[1].strip() for line in stream.getvalue().splitlines()) == [
        "a", "b", warmup.KERNEL_STEP]
    with pytest.raises(ValueError, match="workers must be"):
        warmup.warm(stream, workers=0)


def test_the_warm_up_truths_are_on_the_chapters_grid():
    t = dynamics.MARS_T0 + np.arange(0.0, scenarios.MarsScenario().span + 1.0, 60.0)  # ch. 2
    assert dynamics.chapter_times().tobytes() == t.tobytes()
