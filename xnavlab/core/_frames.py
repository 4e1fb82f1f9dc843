"""A slider's frames kept on disk for :mod:`xnavlab.core.widgets`, keyed by the code that draws them.

Plumbing of the live widget (:class:`xnavlab.core.widgets.Explorer`), not meant for readers.
A frame the live widget draws (at a move, or ahead) is also written under
``$XNAVLAB_CACHE/frames/`` (:func:`xnavlab.core.diskcache.cache_dir`), so that a slider
opened again (the chapter re-run, the kernel restarted) finds it there: a move onto it is a
file read. The key covers everything the frame's pixels depend on:

- the plotting function: its module and qualified name, and the source of that module and of
  every module of the package it imports, with the shipped data
  (:func:`xnavlab.core.diskcache.code_digest`: an edit there draws the frames again, an edit
  elsewhere does not);
- its arguments (the position and the fixed values, by an exact ``repr``; arrays by their
  bytes); a function that is not the package's (a notebook's own, a lambda) or an argument
  without an exact ``repr`` (an object, a generator) is not kept on disk;
- the slider's kept layout (:meth:`xnavlab.core.widgets.SteadyLayout.state`: the axes
  positions every later frame is drawn in), the figure's dpi and every other matplotlib
  setting (``rcParams``, the backend aside), and the versions of matplotlib, numpy and
  Pillow.

Only frames that leave the slider's layout as they found it are written: those drawn in the
kept layout (:meth:`~xnavlab.core.widgets.SteadyLayout.state`, which the key names) or with
fixed margins, each a pure function of its key. The opening frame lays the layout out and is
drawn at every opening; a frame the kept layout does not fit is laid out anew and changes the
kept layout for the frames after it, so it is drawn again in a slider opened again (found on
disk, it would leave the layout as it was, and the frames after it would miss their keys).
A write goes to a temporary file of its own process and thread and is renamed into place
(``os.replace``), so a reader never sees half a frame and concurrent writers of one frame both
succeed; a frame that cannot be read back whole is drawn again. The directory is kept under
:data:`FRAME_CACHE_BYTES`: past it, the frames used least recently go. :data:`FRAME_CACHE_ENV`
set to ``"0"`` turns the disk off (the in-memory frames remain).
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import os
import threading
from pathlib import Path

import numpy as np

from xnavlab.core.diskcache import cache_dir, code_digest, env_switch, store

__all__ = ["DiskFrames", "FRAME_CACHE_ENV", "FRAME_CACHE_BYTES", "FRAMES_SUBDIR", "prune",
           "check_png_args"]

#: The environment variable that turns the frames on disk off (``"0"``).
FRAME_CACHE_ENV = "XNAVLAB_FRAME_CACHE"

#: At most this many bytes of frames on disk; past it the least recently used go (to 80 %).
FRAME_CACHE_BYTES = 256 * 2**20

#: The frames' directory under :func:`xnavlab.core.diskcache.cache_dir`.
FRAMES_SUBDIR = "frames"

_PNG_HEAD = b"\x89PNG\r\n\x1a\n"
_PNG_TAIL = b"IEND\xaeB`\x82"
_PRUNE_EVERY = 32  # writes between two looks at the directory's size
_writes = {"n": 0}
_RC_SKIP = ("backend", "interactive", "toolbar", "webagg")  # no pixel depends on them


class _Unkeyable(Exception):
    """An argument without an exact key: the frame is not kept on disk."""


def _key_of(value, h):
    """Feed an exact description of ``value`` to the hash ``h`` (or raise :class:`_Unkeyable`)."""
    if isinstance(value, np.generic):
        value = value.item()
    if value is None or isinstance(value, bool | int | float | complex | str | bytes):
        h.update(f"{type(value).__name__}:{value!r};".encode())
    elif isinstance(value, tuple | list):
        h.update(f"{type(value).__name__}[{len(value)}](".encode())
        for item in value:
            _key_of(item, h)
        h.update(b")")
    elif isinstance(value, np.ndarray) and value.dtype.kind in "biufcU":
        a = np.ascontiguousarray(value)
        h.update(f"array:{a.dtype.str}{a.shape};".encode())
        h.update(a.tobytes())
    else:
        raise _Unkeyable(type(value).__name__)


@functools.cache
def _versions():
    """The versions of the distributions that draw the frames, as text (once per process)."""
    import importlib.metadata

    out = []
    for dist in ("matplotlib", "numpy", "pillow"):
        try:
            out.append(f"{dist}={importlib.metadata.version(dist)}")
        except importlib.metadata.PackageNotFoundError:
            out.append(f"{dist}=none")
    return ",".join(out)


def _rc_text():
    """Every matplotlib setting a frame's pixels may depend on, as text."""
    import matplotlib as mpl

    return str([item for item in dict.items(mpl.rcParams) if not item[0].startswith(_RC_SKIP)])


class DiskFrames:
    """One plotting function's frames on disk (see the module).

    Parameters
    ----------
    plot : callable
        The slider's plotting function; kept on disk only if it is a module-level function
        of the package (or wraps one with :func:`functools.wraps`).
    root : pathlib.Path, optional
        The package's directory (default this package's): whose code is part of the key.

    Examples
    --------
    >>> import tempfile
    >>> from xnavlab.core.montecarlo import plot_pd_error
    >>> os.environ["XNAVLAB_CACHE"] = tempfile.mkdtemp()
    >>> disk = DiskFrames(plot_pd_error)
    >>> path = disk.path({"runs": 100, "pd": 0.9}, layout_state="kept axes")
    >>> path.parent.name, disk.load(path) is None
    ('frames', True)
    >>> disk.store(path, b"\\x89PNG\\r\\n\\x1a\\n...IEND\\xaeB`\\x82")
    True
    >>> disk.load(path)[:4], disk.path({"runs": 100, "pd": 0.9}, None)
    (b'\\x89PNG', None)
    >>> del os.environ["XNAVLAB_CACHE"]
    """

    def __init__(self, plot, root=None):
        self.plot = plot
        self.root = root
        self._static = None  # the key's part that one process never changes (lazily)
        self._lock = threading.Lock()

    def _static_key(self):
        """The function, its code and the versions: hashed once (``None``: not kept)."""
        with self._lock:
            if self._static is None:
                self._static = ""
                module = getattr(self.plot, "__module__", None) or ""
                name = getattr(self.plot, "__qualname__", "")
                package = Path(self.root).name if self.root is not None else "xnavlab"
                if module.startswith(package + ".") and name and "<" not in name:
                    try:
                        digest = code_digest((module,), self.root)
                    except (ValueError, OSError):  # not a module of the package's tree
                        return None
                    self._static = f"{module}:{name}:{digest}:{_versions()}"
            return self._static or None

    def warm(self):
        """Hash the code of the key now (a fraction of a second, once per process and
        module), so that the reader's first move does not; ``None``.

        In the calling thread, never a second one: hashing the code parses it with ``ast``,
        and CPython 3.11's AST constructor is not thread-safe (a parse beside the kernel's
        own, or beside a cell's, raised "SystemError: AST constructor recursion depth
        mismatch" in chapter 9 under nbval).
        """
        if env_switch(FRAME_CACHE_ENV, True) and self._static is None:
            self._static_key()

    def path(self, kwargs, layout_state):
        """The file of the frame drawn for ``kwargs`` in the kept layout ``layout_state``, or
        ``None`` when it is not kept on disk (no kept layout, the disk turned off, a function or
        an argument without an exact key)."""
        if layout_state is None or not env_switch(FRAME_CACHE_ENV, True):
            return None
        static = self._static_key()
        if static is None:
            return None
        h = hashlib.sha256(static.encode())
        try:
            for name in sorted(kwargs):
                h.update(f"{name}=".encode())
                _key_of(kwargs[name], h)
        except _Unkeyable:
            return None
        h.update(str(layout_state).encode())
        h.update(_rc_text().encode())
        name = getattr(self.plot, "__name__", "plot")
        return cache_dir() / FRAMES_SUBDIR / f"{name}-{h.hexdigest()[:32]}.png"

    @staticmethod
    def load(path):
        """The PNG bytes at ``path`` if it holds a whole PNG (its use time refreshed), else None."""
        if path is None:
            return None
        try:
            png = Path(path).read_bytes()
        except OSError:
            return None
        if not (png.startswith(_PNG_HEAD) and png.endswith(_PNG_TAIL)):
            return None
        with contextlib.suppress(OSError):
            os.utime(path)  # used now: the last to go when the directory is pruned
        return png

    @staticmethod
    def store(path, png):
        """Write ``png`` at ``path`` atomically; ``False`` where the cache cannot be written."""
        if path is None:
            return False
        path = Path(path)
        if not store(path, lambda f: f.write(png)):   # diskcache's atomic write
            return False
        _writes["n"] += 1
        if _writes["n"] % _PRUNE_EVERY == 0:
            prune(path.parent)
        return True


def check_png_args(fig, dpi=None, compress_level=6, layout=None, layout_class=None):
    """Check the arguments of a frame's PNG (:func:`xnavlab.core.widgets.live_png`,
    :meth:`xnavlab.core.widgets.SteadyLayout.png`): one ValueError naming the first one wrong.

    ``fig`` a matplotlib Figure, ``dpi`` None or a number in [1, 1000], ``compress_level`` an
    integer in [0, 9] and ``layout`` None or an instance of ``layout_class``; the figure's
    size at that dpi (default its savefig dpi) at most
    :data:`xnavlab.core.plotting.MAX_PIXELS` pixels (:func:`xnavlab.core.plotting.check_figsize`,
    naming ``figsize``).

    Examples
    --------
    >>> from matplotlib.figure import Figure
    >>> check_png_args(Figure(), dpi=80)
    >>> check_png_args(Figure(), compress_level=10)
    Traceback (most recent call last):
    ...
    ValueError: compress_level must be an integer in [0, 9], got 10
    """
    import matplotlib as mpl
    from matplotlib.figure import Figure

    from xnavlab.core import validate
    from xnavlab.core.plotting import check_figsize

    validate.check_instance("fig", fig, Figure, "a matplotlib Figure")
    if dpi is not None:
        validate.check_real("dpi", dpi, 1, 1000)
    validate.check_int("compress_level", compress_level, 0, 9)
    saved = mpl.rcParams["savefig.dpi"]  # what savefig draws at when dpi is None
    drawn = dpi if dpi is not None else fig.dpi if saved == "figure" else saved
    check_figsize(tuple(fig.get_size_inches()), drawn)
    if layout is not None:
        validate.check_instance("layout", layout, layout_class, "a SteadyLayout (or None)")


def prune(directory, max_bytes=None):
    """Remove the least recently used frames of ``directory`` until they take at most 80 % of
    ``max_bytes`` (default :data:`FRAME_CACHE_BYTES`), if they take more; return how many went.

    Examples
    --------
    >>> import tempfile
    >>> d = Path(tempfile.mkdtemp())
    >>> for k in range(4):
    ...     _ = (d / f"f{k}.png").write_bytes(b"x" * 100)
    ...     os.utime(d / f"f{k}.png", (k, k))
    >>> prune(d, max_bytes=300), sorted(p.name for p in d.iterdir())
    (2, ['f2.png', 'f3.png'])
    """
    max_bytes = FRAME_CACHE_BYTES if max_bytes is None else max_bytes
    files = []
    try:
        with os.scandir(directory) as entries:
            for entry in entries:
                with contextlib.suppress(OSError):
                    if entry.name.endswith(".png") and entry.is_file():
                        st = entry.stat()
                        files.append((st.st_mtime, st.st_size, entry.path))
    except OSError:
        return 0
    total = sum(size for _, size, _ in files)
    if total <= max_bytes:
        return 0
    gone = 0
    for _, size, name in sorted(files):
        if total <= 0.8 * max_bytes:
            break
        with contextlib.suppress(OSError):  # another process may have removed it
            os.unlink(name)
            gone += 1
        total -= size
    return gone
