"""Keep myst-nb's execution cache honest: drop it when the package or the environment changed.

``make book`` executes chapters in myst-nb's ``cache`` mode: a chapter re-executes only when
its code cells (or kernel) changed. A chapter's outputs also depend on ``xnavlab`` and on the
installed packages, which the notebook's hash cannot see, so this script keeps a SHA-256 of
every file under ``xnavlab/`` plus ``environment.txt`` and ``pyproject.toml`` beside the cache
and deletes the cache when it differs: after a change to the package every chapter runs again
(conservative, and simple to reason about); after a change to one chapter, only that one.

Deleting the execution cache alone is not enough: Sphinx keeps its own environment
(``_build/.doctrees``) and re-reads only the documents whose *source* changed, so a chapter
whose notebook did not change would keep its old outputs. The environment and the executed
copies (``_build/jupyter_execute``) go with the cache.

Usage: ``python tools/book_cache.py [--clear]`` from the repository root.
"""

import hashlib
import shutil
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CACHE = ROOT / "_build" / ".jupyter_cache"
#: What must go with the execution cache so that every chapter is read (and executed) again.
DEPENDENT = (ROOT / "_build" / ".doctrees", ROOT / "_build" / "jupyter_execute")
STAMP = ROOT / "_build" / ".jupyter_cache.xnavlab-sha256"


def package_hash():
    """SHA-256 over the package sources and the environment files, in a fixed order."""
    h = hashlib.sha256()
    files = sorted(p for p in (ROOT / "xnavlab").rglob("*")
                   if p.is_file() and "__pycache__" not in p.parts)
    for path in [*files, ROOT / "environment.txt", ROOT / "pyproject.toml"]:
        h.update(str(path.relative_to(ROOT)).encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def main(argv):
    digest = package_hash()
    old = STAMP.read_text().strip() if STAMP.exists() else None
    if "--clear" in argv or old != digest:
        if CACHE.exists():
            why = "asked to" if "--clear" in argv else "xnavlab/ or the environment changed"
            print(f"book cache: cleared ({why}); every chapter executes", file=sys.stderr)
            shutil.rmtree(CACHE)
        for path in DEPENDENT:
            shutil.rmtree(path, ignore_errors=True)
        STAMP.parent.mkdir(parents=True, exist_ok=True)
        STAMP.write_text(digest + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
