"""The package's disk cache: where it lives, and arrays stored there atomically.

Results that are expensive and unchanged between processes (a 30-day truth trajectory,
PINT's delays, the headline campaign) are kept under ``$XNAVLAB_CACHE`` (default
``~/.cache/xnavlab``), each file named by a hash of everything that determines it, so that
a changed input or model is never served from a stale file. The code is part of that hash:
:func:`code_digest` hashes the source of the module that computes an entry and of every
module of the package it imports, directly or not, with the shipped data; an edit anywhere in
that code computes the entry again, an edit elsewhere in the package does not. A write goes to
a temporary file first and is renamed into place, so a reader never sees half a file; a second
process asking for an entry another is computing waits for it and reads it (:func:`exclusive`),
instead of computing it twice. A home that cannot be written still gets its result, uncached;
a cache on a full disk too, with one warning (:func:`store`).
"""

from __future__ import annotations

import contextlib
import errno
import functools
import hashlib
import os
import tempfile
import threading
import warnings
import zipfile
from pathlib import Path

import numpy as np

from xnavlab.core.userfiles import InputWarning

__all__ = ["cache_dir", "check_cache", "cached_arrays", "code_digest", "entry_path", "env_switch",
           "exclusive", "load_array", "source_digest", "store"]


def env_switch(name, default):
    """The on/off setting of the environment variable ``name``: ``"1"`` on, ``"0"`` off, unset
    or empty ``default``; any other value is refused in one line naming the variable (a
    ``false`` or ``off`` read as "not 0" would leave the switch on without a word).

    Examples
    --------
    >>> import os
    >>> os.environ["XNAVLAB_DEMO"] = "0"
    >>> env_switch("XNAVLAB_DEMO", True)
    False
    >>> os.environ["XNAVLAB_DEMO"] = "off"
    >>> env_switch("XNAVLAB_DEMO", True)
    Traceback (most recent call last):
    ...
    ValueError: XNAVLAB_DEMO must be 0 (off) or 1 (on), or unset (on); got 'off'
    >>> del os.environ["XNAVLAB_DEMO"]
    """
    value = os.environ.get(name, "")
    if value not in ("", "0", "1"):
        raise ValueError(f"{name} must be 0 (off) or 1 (on), or unset ({'on' if default else 'off'}); "
                         f"got {value!r}")
    return bool(default) if value == "" else value == "1"


@functools.lru_cache(maxsize=8)
def _usable(folder):
    """None when ``folder`` is (or can be made) a folder this process can write, else why not."""
    if Path(folder).exists() and not Path(folder).is_dir():
        return "a file, not a folder"
    try:
        Path(folder).mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as exc:
        return exc.strerror or type(exc).__name__
    return None


def cache_dir():
    """The cache's root: ``$XNAVLAB_CACHE``, or ``~/.cache/xnavlab`` when it is unset or empty.

    ``$XNAVLAB_CACHE`` set is checked at first use (created if missing): a file, or a folder
    that cannot be written, is refused in one line naming the variable, instead of every result
    computed uncached without a word. A leading ``~`` is expanded (a quoted value, an ``.env``
    file, a kernel's ``env`` or a Docker ``ENV`` leave it as typed); a value with leading or
    trailing blanks, or a relative path (another folder from each working directory: the
    book's kernels run in ``book/``) is refused. The default, a home that cannot be written,
    still gets its results, uncached.

    Returns
    -------
    pathlib.Path
        Created when ``$XNAVLAB_CACHE`` names it; the default is not created here.

    Examples
    --------
    >>> import os
    >>> os.environ["XNAVLAB_CACHE"] = "/tmp/xnav-cache"
    >>> str(cache_dir())
    '/tmp/xnav-cache'
    >>> os.environ["XNAVLAB_CACHE"] = "cache"
    >>> cache_dir()  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: XNAVLAB_CACHE must name a folder this process can write, by its full path ...
    >>> del os.environ["XNAVLAB_CACHE"]
    >>> cache_dir() == Path.home() / ".cache" / "xnavlab"
    True
    """
    given = os.environ.get("XNAVLAB_CACHE")
    if not given:
        return Path.home() / ".cache" / "xnavlab"
    folder = os.path.expanduser(given)
    if given != given.strip():
        why = "leading or trailing blanks"
    elif not os.path.isabs(folder):
        why = "a relative path: another folder from each working directory"
    else:
        why = _usable(folder)
    if why is not None:
        raise ValueError(f"XNAVLAB_CACHE must name a folder this process can write, by its full "
                         f"path (or be unset: ~/.cache/xnavlab); got {given!r} ({why})")
    return Path(folder)


def check_cache():
    """Refuse an unusable ``$XNAVLAB_CACHE`` now, in one line naming it (:func:`cache_dir`'s
    check), before work whose every step would read the cache: a campaign's runs. Nothing is
    stored or returned.

    Examples
    --------
    >>> check_cache()   # unset, or a folder this process can write: nothing to say
    """
    cache_dir()


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
    with exclusive(path):  # a second process asking for it waits, then reads it
        if path.exists():
            try:
                with open(path, "rb") as f, np.load(f) as data:
                    return {key: data[key] for key in data.files}
            except (OSError, ValueError, EOFError, zipfile.BadZipFile):  # unreadable: computed again
                pass
        result = compute()
        store(path, lambda f: np.savez(f, **result))
    return {key: np.asarray(value) for key, value in result.items()}


@contextlib.contextmanager
def exclusive(path):
    """Hold the entry ``path`` for this process: another process asking for it waits here.

    Two processes that need the same expensive entry at once (``pytest -n 2``, the book's two
    kernels, a test beside a chapter) would both compute it; with this lock the second waits
    for the first and then reads what it stored. An advisory lock (``fcntl.flock``) on the
    file ``path`` + ``.lock`` beside the entry, released when the block ends, also on an
    exception. Where the cache cannot be written (a read-only home) or the platform has no
    advisory locks, nothing is held and each process computes on its own, as without the lock.

    Parameters
    ----------
    path : str or pathlib.Path
        The entry (it need not exist yet).

    Examples
    --------
    >>> import tempfile
    >>> entry = Path(tempfile.mkdtemp()) / "demo.npz"
    >>> with exclusive(entry):
    ...     entry.with_name("demo.npz.lock").exists()
    True
    """
    path = Path(path)
    try:
        import fcntl
    except ImportError:  # pragma: no cover - no advisory locks (Windows): compute side by side
        yield
        return
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fh = open(path.with_name(path.name + ".lock"), "a", encoding="utf-8")  # noqa: SIM115
    except OSError:  # a cache that cannot be written: nothing to share, nothing to wait for
        yield
        return
    with fh:
        fcntl.flock(fh.fileno(), fcntl.LOCK_EX)  # blocks; released when the file closes
        yield


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
        True when stored; False where the cache cannot be written (a read-only home, a full
        disk): the caller keeps its result, uncached, and no temporary file is left. A full
        disk (or quota) is said once a process, in an
        :class:`~xnavlab.core.userfiles.InputWarning` naming the folder. An exception of
        ``write`` is raised again, also without a temporary file left.

    Examples
    --------
    >>> import tempfile
    >>> entry = Path(tempfile.mkdtemp()) / "demo.bin"
    >>> store(entry, lambda f: f.write(b"42")), entry.read_bytes()
    (True, b'42')
    """
    path = Path(path)
    # one temporary name per process and thread: two writers of one entry never share it
    tmp = path.with_suffix(f".{os.getpid()}.{threading.get_ident()}.tmp")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with open(tmp, "wb") as f:
            write(f)
        os.replace(tmp, path)
    except OSError as exc:
        full = _disk_full(exc, path.parent)  # before the partial file is removed
        with contextlib.suppress(OSError):
            tmp.unlink(missing_ok=True)
        if full:
            _say_full(path.parent, exc)
        return False
    except BaseException:  # a writer that fails (or Ctrl-C) leaves no temporary file either
        with contextlib.suppress(OSError):
            tmp.unlink(missing_ok=True)
        raise
    return True


def _disk_full(exc, folder):
    """Whether ``exc`` (a failed store) is a full disk or quota: its errno, or, for a writer
    that drops it (``numpy.save``: "N requested and M written"), no block left in ``folder``."""
    if exc.errno in (errno.ENOSPC, errno.EDQUOT):
        return True
    try:
        return exc.errno is None and os.statvfs(folder).f_bavail == 0
    except (OSError, AttributeError):  # pragma: no cover - no statvfs (Windows)
        return False


def _say_full(folder, exc):
    """One warning a process that the cache's disk is full (each store would fail alike)."""
    if _FULL:
        return
    _FULL.append(folder)
    given = os.environ.get("XNAVLAB_CACHE")
    name = (f"XNAVLAB_CACHE {given!r}" if given else
            f"the cache {str(cache_dir())!r} (XNAVLAB_CACHE unset)")
    why = (exc.strerror or "no space left on device").lower()
    warnings.warn(f"{name}: {why}; results are not kept (each is computed again when next "
                  f"used)", InputWarning, stacklevel=3)


#: The folder of the first store that found its disk full (:func:`_say_full`), if any.
_FULL: list = []


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


def _module_file(root, name):
    """The source file of module ``name`` (``xnavlab.mars.timing.toa``) under the package's ``root``, or
    None."""
    parts = name.split(".")[1:]
    base = root.joinpath(*parts) if parts else root
    for candidate in (base.with_suffix(".py"), base / "__init__.py"):
        if candidate.is_file():
            return candidate
    return None


def _imported(name, path, package):
    """Every module name of ``package`` that the source at ``path`` imports (at any depth of
    the file: module level and inside functions), with the packages above each."""
    import ast

    is_pkg = path.name == "__init__.py"
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = name if is_pkg else name.rpartition(".")[0]
                for _ in range(node.level - 1):
                    anchor = anchor.rpartition(".")[0]
                base = f"{anchor}.{base}" if base else anchor
            targets = [base] + [f"{base}.{a.name}" for a in node.names]
        else:
            continue
        for target in targets:
            if target == package or target.startswith(package + "."):
                parts = target.split(".")
                found.update(".".join(parts[:k]) for k in range(1, len(parts) + 1))
    return found


@functools.lru_cache(maxsize=64)
def code_digest(modules, root=None):
    """A hash of the code that computes a cache entry: ``modules``, everything they import.

    The source of each module named in ``modules`` and of every module of the package it
    imports, directly or through others, at module level or inside a function (found by reading
    the source, so an import made only on a call counts too), with the packages above each and
    the package's shipped data (``data/``). An entry keyed by it is computed again when any of
    that code changes, and only then. Computed once per process and argument.

    Parameters
    ----------
    modules : tuple of str
        Dotted module names of the package (``("xnavlab.mars.navigation.headline",)``).
    root : str or pathlib.Path, optional
        The package's directory (default: this package's, ``xnavlab/``).

    Returns
    -------
    str
        16 hexadecimal digits.

    Examples
    --------
    >>> a = code_digest(("xnavlab.core.constants",))
    >>> len(a), a == code_digest(("xnavlab.core.constants",))
    (16, True)
    >>> a == code_digest(("xnavlab.core.diskcache",))
    False
    """
    if isinstance(modules, str):
        raise ValueError("modules must be a tuple of module names, not one string")
    root = Path(root) if root is not None else Path(__file__).resolve().parents[1]
    package = root.name
    seen, todo = {}, list(modules)
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        inside = name == package or name.startswith(package + ".")
        path = _module_file(root, name) if inside else None
        seen[name] = path
        if path is not None:
            todo.extend(_imported(name, path, package) - set(seen))
    if not any(path is not None for name, path in seen.items() if name in modules):
        raise ValueError(f"modules must name modules of {package}; got {modules!r}")
    h = hashlib.sha256()
    for name in sorted(n for n, p in seen.items() if p is not None):
        h.update(name.encode())
        h.update(seen[name].read_bytes())
    data = root / "data"
    for path in sorted(data.rglob("*")) if data.is_dir() else ():
        if path.is_file() and "__pycache__" not in path.parts:
            h.update(str(path.relative_to(root)).encode())
            h.update(path.read_bytes())
    return h.hexdigest()[:16]


def entry_path(prefix, parts=(), arrays=(), modules=(), versions=(), suffix=".npz"):
    """The cache entry for one result: ``$XNAVLAB_CACHE/<prefix>-<key><suffix>``.

    The one place a cache key is made. The key covers everything that determines the result:
    the arguments (``parts``, by their ``repr``; ``arrays``, by their bytes and dtype), the code
    that computes it (:func:`code_digest` of ``modules``: the module and all it imports) and the
    versions of the other distributions it calls (``versions``, e.g. ``("pint-pulsar",)``).

    Parameters
    ----------
    prefix : str
        What the entry holds (``"truth"``, ``"pint-witness"``).
    parts : tuple
        Arguments with an exact ``repr`` (numbers, strings, tuples of them).
    arrays : sequence of array_like
        Array arguments.
    modules : tuple of str
        The modules of the package that compute the entry (at least one).
    versions : tuple of str
        Distributions whose version is part of the key.
    suffix : str
        The file's suffix.

    Returns
    -------
    pathlib.Path
        Not created here.

    Examples
    --------
    >>> a = entry_path("demo", (1, "x"), [np.arange(3.0)], ("xnavlab.core.constants",))
    >>> a.name.startswith("demo-") and a.suffix == ".npz"
    True
    >>> a == entry_path("demo", (2, "x"), [np.arange(3.0)], ("xnavlab.core.constants",))
    False
    """
    import importlib.metadata

    if not modules:
        raise ValueError("modules must name the modules that compute the entry (its code is "
                         "part of the key)")
    h = hashlib.sha256(repr((prefix, tuple(parts))).encode())
    for a in arrays:
        a = np.ascontiguousarray(a)
        h.update(a.dtype.str.encode() + repr(a.shape).encode())
        h.update(a.tobytes())
    h.update(code_digest(tuple(modules)).encode())
    for dist in versions:
        try:
            h.update(f"{dist}={importlib.metadata.version(dist)}".encode())
        except importlib.metadata.PackageNotFoundError:
            h.update(f"{dist}=none".encode())
    return cache_dir() / f"{prefix}-{h.hexdigest()[:24]}{suffix}"


def load_array(path, shape):
    """The array stored at ``path`` (``.npy``) when it exists, is readable and has ``shape``, else None.

    Examples
    --------
    >>> import tempfile
    >>> entry = Path(tempfile.mkdtemp()) / "demo.npy"
    >>> load_array(entry, (3,)) is None
    True
    >>> store(entry, lambda f: np.save(f, np.arange(3.0)))
    True
    >>> load_array(entry, (3,)).tolist(), load_array(entry, (4,))
    ([0.0, 1.0, 2.0], None)
    """
    path = Path(path)
    if not path.exists():
        return None
    try:
        x = np.load(path)
    except (OSError, ValueError):
        return None
    return x if x.shape == tuple(shape) else None
