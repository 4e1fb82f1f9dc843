"""The filter kernel's first-use notice: one line on a cold cache, nothing once compiled."""

import io
import json
import os
import subprocess
import sys

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


def test_numba_disable_jit_runs_the_kernel_as_python_and_says_so(tmp_path):
    """Review 35q Q17: NUMBA_DISABLE_JIT=1 (numba's debugging switch) broke every Mars command,
    reproduce --list included, with a 45-line AttributeError at import."""
    env = {**os.environ, "NUMBA_DISABLE_JIT": "1", "XNAVLAB_CACHE": str(tmp_path)}
    listed = subprocess.run([sys.executable, "-m", "xnavlab", "reproduce", "--list"], env=env,
                            capture_output=True, text=True, timeout=120)
    assert listed.returncode == 0 and "mars-nofault" in listed.stdout, listed.stderr
    ran = subprocess.run([sys.executable, "-m", "xnavlab", "run", "mars", "--days", "0.01",
                          "--json"], env=env, capture_output=True, text=True, timeout=300)
    assert ran.returncode == 0, ran.stderr
    assert json.loads(ran.stdout)["position_error_m"] > 0.0
    assert ran.stderr.splitlines() == [
        "xnavlab: NUMBA_DISABLE_JIT is set: the filter kernel runs as plain Python, about 3,000 "
        "times slower (some 20 minutes for the paper's 30 days)"]
