"""``python -m xnavlab``: see :mod:`xnavlab.cli`."""

import sys

from .cli import main

sys.exit(main())
