"""``python -m xnavlab``: see :mod:`xnavlab.cli`."""

import sys

from xnavlab.cli import main

sys.exit(main())
