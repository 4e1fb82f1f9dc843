"""The environment that environment.txt builds: what it must hold, and what it must not.

A package pulled in by another one's extra can cost every reader's kernel seconds: jsonschema
4.25 added rfc3987-syntax to the ``format-nongpl`` extra Jupyter installs, and importing it builds
three Earley parsers (3 s) in every process that loads nbformat's validator, which is every
chapter's first ``glue``. environment.txt holds jsonschema below 4.25 and ``make setup``
removes the package from an environment made before; this test keeps it that way.
"""

import importlib.util
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_no_rfc3987_syntax_in_the_environment():
    assert importlib.util.find_spec("rfc3987_syntax") is None, (
        "rfc3987-syntax is installed: every chapter's first glue pays 3 s for its parsers; "
        "run `make setup` (it removes it) or `pip uninstall rfc3987-syntax`")


def test_environment_txt_keeps_jsonschema_below_the_release_that_pulls_it_in():
    lines = (ROOT / "environment.txt").read_text().splitlines()
    pins = [line for line in lines if re.match(r"jsonschema\b", line)]
    assert pins and "<4.25" in pins[0]
