"""Every page of the built book, opened in headless Chromium with the network off.

Run by ``make browser-test`` (which builds the book first if it is missing or stale and
installs Debian's chromium when absent). For each HTML page of ``_build/html`` (override with
``XNAVLAB_HTML_DIR``), served from 127.0.0.1, the test fails on:

- a JavaScript error (an uncaught exception, ``console.error``, a browser log error);
- a request that leaves the machine (everything must be served by the build; the optional
  ipywidgets CDN scripts are the only exception) or a local file that fails to load;
- TeX left unrendered (``$$``, ``\\begin{``, ``\\(`` ... visible in the text; a math element
  without MathJax output) or a MathJax error;
- an ``<img>`` that did not load;
- an error cell (a traceback in an output);
- a kernel-free scrubber (``xnavlab.core.widgets``) that does not move.

The API reference (``book/api/``) is among the pages and is checked like the chapters
(``test_api_reference_was_built`` fails if one of its pages is missing from the build).
A full-page screenshot of every page under ``book/`` is saved in ``_build/screenshots/``
(override with ``XNAVLAB_SCREENSHOTS``).
"""

import os
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))

import chromium  # noqa: E402  (tools/chromium.py)

HTML = Path(os.environ.get("XNAVLAB_HTML_DIR", ROOT / "_build" / "html"))
SHOTS = Path(os.environ.get("XNAVLAB_SCREENSHOTS", ROOT / "_build" / "screenshots"))
PAGES = chromium.pages(HTML) if HTML.is_dir() else []

pytestmark = pytest.mark.skipif(not os.environ.get("XNAVLAB_BROWSER_TEST"),
                                reason="set XNAVLAB_BROWSER_TEST=1 (make browser-test)")


@pytest.fixture(scope="module")
def site():
    if not (HTML / "index.html").is_file():
        pytest.fail(f"no built book at {HTML}: run `make book` (make browser-test does)")
    with chromium.serve(HTML) as base:
        yield base


@pytest.fixture(scope="module")
def browser():
    if chromium.find_chromium() is None:
        pytest.skip("chromium is not installed and could not be installed "
                    "(apt-get install chromium as root); browser test skipped")
    with chromium.Browser() as b:
        yield b


def test_book_was_built():
    assert PAGES, f"no HTML pages under {HTML}: run `make book`"
    assert any(p.startswith("book/") for p in PAGES), f"no chapter pages under {HTML}/book"


def test_api_reference_was_built():
    """Every page of the API reference (book/api/*.md) is built, so test_page opens it."""
    api = [f"book/api/{p.stem}.html" for p in sorted((ROOT / "book" / "api").glob("*.md"))]
    assert api, "no API reference pages under book/api/"
    missing = [p for p in api if p not in PAGES]
    assert not missing, f"API reference pages not built under {HTML}: {missing}"


@pytest.mark.parametrize("page", PAGES)
def test_page(page, site, browser):
    shot = SHOTS / chromium.screenshot_name(page) if page.startswith("book/") else None
    report = chromium.check_page(browser, site + page, shot)
    problems = "\n".join(f"  - {p}" for p in report["problems"])
    assert not report["problems"], f"{page}:\n{problems}"
