"""Shared pytest set-up: non-interactive matplotlib and a deterministic hypothesis profile."""

import os

os.environ.setdefault("MPLBACKEND", "Agg")

from hypothesis import settings  # noqa: E402

settings.register_profile("xnavlab", deadline=None, max_examples=50, derandomize=True)
settings.load_profile("xnavlab")
