"""``python -m xnavlab warmup`` (xnavlab.cli.warmup): the steps run in order, each reported on one
line with its time, and the command exits 0. The steps themselves (the numba compiles) are
replaced by stand-ins: they are what the chapters and the Mars tests run anyway."""

import io

from xnavlab.cli import main, warmup


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


def test_the_command_runs_warm_and_exits_0(monkeypatch):
    called = []
    monkeypatch.setattr(warmup, "warm", lambda: called.append(True) or {})
    assert main(["warmup"]) == 0 and called == [True]
