"""The package's disk cache: where it lives, and arrays stored there atomically.

Results that are expensive and unchanged between processes (a 30-day truth trajectory,
PINT's delays, the headline campaign) are kept under ``$XNAVLAB_CACHE`` (default
``~/.cache/xnavlab``), each file named by a hash of everything that determines it, so that
a changed input or model is never served from a stale file. A write goes to a temporary
file first and is renamed into place, so a reader never sees half a file, and two processes
computing the same entry at once both succeed. A home that cannot be written still gets
its result, uncached.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import os
import zipfile
from pathlib import Path

import numpy as np

__all__ = ["cache_dir", "cached_arrays", "source_digest", "store"]


def cache_dir():
    """The cache's root: ``$XNAVLAB_CACHE``, or ``~/.cache/xnavlab`` when it is unset or empty.

    Returns
    -------
    pathlib.Path
        Not created here.

    Examples
    --------
    >>> import os
    >>> os.environ["XNAVLAB_CACHE"] = "/tmp/xnav-cache"
    >>> str(cache_dir())
    '/tmp/xnav-cache'
    >>> del os.environ["XNAVLAB_CACHE"]
    >>> cache_dir() == Path.home() / ".cache" / "xnavlab"
    True
    """
    return Path(os.environ.get("XNAVLAB_CACHE") or Path.home() / ".cache" / "xnavlab")


def cached_arrays(path, compute):
    """The dict of arrays stored at ``path`` (an ``.npz``), else ``compute()`` stored there.

    Parameters
    ----------
    path : pathlib.Path
        The entry, ending in ``.npz``, its name a hash of the inputs (the caller's key).
    compute : callable
        ``compute() -> dict of str to array_like``, called only when ``path`` is missing or
        unreadable.

    Returns
    -------
    dict of str to ndarray

    Examples
    --------
    >>> import tempfile
    >>> calls = []
    >>> def compute():
    ...     calls.append(1)
    ...     return {"x": np.arange(3.0)}
    >>> entry = Path(tempfile.mkdtemp()) / "demo.npz"
    >>> cached_arrays(entry, compute)["x"].tolist(), cached_arrays(entry, compute)["x"].tolist()
    ([0.0, 1.0, 2.0], [0.0, 1.0, 2.0])
    >>> len(calls)
    1
    """
    path = Path(path)
    if path.exists():
        try:
            with open(path, "rb") as f, np.load(f) as data:
                return {key: data[key] for key in data.files}
        except (OSError, ValueError, EOFError, zipfile.BadZipFile):  # unreadable: computed again
            pass
    result = compute()
    store(path, lambda f: np.savez(f, **result))
    return {key: np.asarray(value) for key, value in result.items()}


def store(path, write):
    """Write a cache entry atomically: ``write(f)`` into a temporary file beside ``path``
    (opened ``"wb"``), then renamed to ``path``.

    Parameters
    ----------
    path : pathlib.Path
        The entry.
    write : callable
        ``write(f)`` writes the entry's bytes to the open file ``f``.

    Returns
    -------
    bool
        True when stored; False where the cache cannot be written (a read-only home): the
        caller keeps its result, uncached, and no temporary file is left.

    Examples
    --------
    >>> import tempfile
    >>> entry = Path(tempfile.mkdtemp()) / "demo.bin"
    >>> store(entry, lambda f: f.write(b"42")), entry.read_bytes()
    (True, b'42')
    """
    path = Path(path)
    tmp = path.with_suffix(f".{os.getpid()}.tmp{path.suffix}")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with open(tmp, "wb") as f:
            write(f)
        os.replace(tmp, path)
    except OSError:
        with contextlib.suppress(OSError):
            tmp.unlink(missing_ok=True)
        return False
    return True


@functools.lru_cache(maxsize=8)
def source_digest(root, skip=()):
    """A hash of every file of a package tree: an entry keyed by it is served only for the
    same code and data.

    Every file below ``root`` (sources and shipped data, ``__pycache__`` passed over), its
    path and its bytes, in sorted order. Computed once per process and argument.

    Parameters
    ----------
    root : str or pathlib.Path
        The package's directory.
    skip : tuple of str
        Directory names whose files are left out (e.g. ``("reproductions",)``).

    Returns
    -------
    str
        16 hexadecimal digits.

    Examples
    --------
    >>> import tempfile
    >>> d = Path(tempfile.mkdtemp())
    >>> _ = (d / "a.py").write_text("x = 1")
    >>> first = source_digest(d)
    >>> len(first), source_digest(d) == first
    (16, True)
    """
    root = Path(root)
    h = hashlib.sha256()
    for path in sorted(root.rglob("*")):
        parts = path.relative_to(root).parts
        if not path.is_file() or "__pycache__" in parts or set(parts[:-1]) & set(skip):
            continue
        h.update(str(path.relative_to(root)).encode())
        h.update(path.read_bytes())
    return h.hexdigest()[:16]
