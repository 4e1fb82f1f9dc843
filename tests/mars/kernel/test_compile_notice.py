"""The filter kernel's first-use notice: one line on a cold cache, nothing once compiled."""

import io

from xnavlab.mars.kernel import compile_notice
from xnavlab.mars.navigation import scenarios


def test_no_notice_when_the_kernel_is_compiled_or_cached():
    scenarios.run(scenarios.MarsScenario(days=0.01))
    assert compile_notice.is_compiled()
    stream = io.StringIO()
    assert compile_notice.announce_compile(stream) is False and stream.getvalue() == ""


def test_one_line_once_per_process_on_a_cold_cache(monkeypatch):
    monkeypatch.setattr(compile_notice, "is_compiled", lambda: False)
    monkeypatch.setattr(compile_notice, "_ANNOUNCED", False)
    stream = io.StringIO()
    assert compile_notice.announce_compile(stream) is True
    assert compile_notice.announce_compile(stream) is False
    lines = stream.getvalue().splitlines()
    assert len(lines) == 1 and "compiling the filter kernel, once" in lines[0]
