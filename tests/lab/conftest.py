"""The JupyterLab test runs only under ``make lab-test`` (``XNAVLAB_LAB_TEST=1``).

The normal ``pytest ... xnavlab tests book`` run ignores this directory: it needs Chromium
and starts a JupyterLab server. Under ``make lab-test`` the fixtures below give every test
one JupyterLab server (serving copies of the chapters from a temporary directory, so nothing
the lab does touches ``book/``) and one headless Chromium showing it; both are stopped at the
end of the session, also when a test failed. Without Chromium every test here SKIPs with the
reason printed (``-ra``).
"""

import os
import shutil
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

if not os.environ.get("XNAVLAB_LAB_TEST"):
    collect_ignore_glob = ["*.py"]
else:
    sys.path.insert(0, str(ROOT / "tools"))
    import lab_driver  # noqa: E402  (tools/lab_driver.py)

#: The chapters, each tested on its own.
CHAPTERS = sorted(p.name for p in (ROOT / "book").glob("[0-9][0-9]_*.ipynb"))
SHOTS = Path(os.environ.get("XNAVLAB_LAB_SCREENSHOTS", ROOT / "_build" / "lab-screenshots"))
_REPORTS = []


@pytest.fixture(scope="session")
def lab_root(tmp_path_factory):
    """The server's root: a copy of every chapter (throwaway notebooks are written here too)."""
    root = tmp_path_factory.mktemp("lab-root")
    for name in CHAPTERS:
        shutil.copy2(ROOT / "book" / name, root / name)
    return root


@pytest.fixture(scope="session")
def lab_server(lab_root):
    """One JupyterLab server on 127.0.0.1 for the session; stopped and its port freed after."""
    if lab_driver.chromium.find_chromium() is None:
        pytest.skip("chromium is not installed and could not be installed "
                    "(apt-get install chromium as root); JupyterLab test skipped")
    server = lab_driver.LabServer(lab_root)
    try:
        yield server
    finally:
        server.cleanup()  # raises (an error at teardown) if the port stays in use


@pytest.fixture(scope="session")
def lab(lab_server):
    """Headless Chromium with JupyterLab loaded (the ipywidgets extension must be active)."""
    with lab_driver.LabBrowser(lab_server) as browser:
        yield browser


@pytest.fixture
def lab_report(record_property):
    """Records a :class:`lab_driver.NotebookReport`'s summary line for the summary at the end.

    The line travels as a user property of the test's report, so that it reaches the summary
    also when pytest-xdist runs the chapters on several workers (``make lab-test`` does).
    """
    return lambda rep: record_property("lab_summary", rep.summary())


def pytest_runtest_logreport(report):
    if report.when == "call":
        _REPORTS.extend(v for k, v in report.user_properties if k == "lab_summary")


def pytest_terminal_summary(terminalreporter):
    if not _REPORTS:
        return
    lines = sorted(_REPORTS)
    terminalreporter.section("JupyterLab: run times and redraw times (input to new figure)")
    for line in lines:
        terminalreporter.write_line(line)
    SHOTS.mkdir(parents=True, exist_ok=True)
    (SHOTS / "redraw-times.txt").write_text("\n".join(lines) + "\n")
