"""``python -m xnavlab``: see :mod:`xnavlab.cli` (``python -m xnavlab --version`` prints the version)."""

import sys

from xnavlab.cli import main

sys.exit(main())
