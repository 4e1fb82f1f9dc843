"""The browser test runs only under ``make browser-test`` (``XNAVLAB_BROWSER_TEST=1``).

The normal ``pytest ... xnavlab tests book`` run (``make test``, ``make unit``) ignores this
directory: it needs a built book and Chromium.
"""

import os

if not os.environ.get("XNAVLAB_BROWSER_TEST"):
    collect_ignore_glob = ["*.py"]
