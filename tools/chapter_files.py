"""The chapter notebooks the book tools walk, and the command line they share.

``tools/eval_roles.py`` and ``tools/hidden_names.py`` each take notebooks on the command line
(every ``book/NN_*.ipynb`` when none is given) and refuse, in one line, a path that is not a
notebook. Both take that from here.

Examples
--------
>>> all(p.suffix == ".ipynb" for p in chapters())
True
>>> chosen("tool", [Path("README.md")]) is None    # "tool: not a notebook: README.md" on stderr
True
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

__all__ = ["ROOT", "chapters", "notebook_parser", "chosen"]

ROOT = Path(__file__).resolve().parent.parent


def chapters():
    """Every chapter notebook, ``book/NN_*.ipynb``, in order."""
    return sorted((ROOT / "book").glob("[0-9][0-9]_*.ipynb"))


def notebook_parser(description, help_text):
    """An argument parser whose positional arguments are notebooks (any number)."""
    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("notebooks", nargs="*", type=Path, help=help_text)
    return ap


def chosen(prog, notebooks):
    """The notebooks given (every chapter when none is), or None after one line on stderr.

    A path that is not an existing ``.ipynb`` file is named in that line; the caller then
    exits with status 2.
    """
    paths = list(notebooks) or chapters()
    missing = [p for p in paths if not p.is_file() or p.suffix != ".ipynb"]
    if missing:
        print(f"{prog}: not a notebook: {', '.join(map(str, missing))}", file=sys.stderr)
        return None
    return paths
