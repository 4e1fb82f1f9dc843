"""How the compiled filter (:mod:`xnavlab.mars.kernel.kernels`) is compiled and cached.

Every function of the kernel modules (:data:`SOURCES`) is compiled by numba with
``cache=True``: the first call in a fresh environment compiles (a minute or two; ``python -m
xnavlab warmup`` does it at set-up) and stores the machine code in ``__pycache__``; later
processes load it in a fraction of a second.

The cache's key
---------------
numba keys a function's cache by the source of the file that defines it, not by the functions
it calls, which it compiles into its own code: split over several modules, a change of a
helper would leave its callers' cached code stale. :func:`jit` therefore stamps every kernel's
cache with :func:`sources_digest`, the hash of all the kernel modules' sources (and of the
constants and containers they read): a change of any byte of them recompiles every kernel, as
a change of the single file did before the split. The containers' field names are covered too
(numba keys the cache by the fields' types, not their names).

Options
-------
The helpers are compiled with ``_nrt=False`` (:data:`HELPER`; numba's switch for functions
that allocate nothing): otherwise numba may wrap each call that passes arrays in atomic
reference-count updates, which cost more than the arithmetic of these 6 x 6 steps; the small
ones are inlined into their callers (:data:`INLINE`), so that constant sizes propagate. No
fast-math, not even FMA contraction: with ``fastmath={"contract"}`` a process that compiled
the kernels and one that loaded them from numba's cache gave different last digits (30-day
RMS 26.412803132646456 m against 26.41280310716354 m); without it both give the same bits
(26.412803121293372 m) at the same cost (1.23 s against 1.24 s).

Examples
--------
>>> len(sources_digest()), SOURCES[0]
(64, 'core/constants.py')
"""

from __future__ import annotations

import hashlib
from pathlib import Path

from numba import njit
from numba.core.caching import FunctionCache

__all__ = ["HELPER", "INLINE", "SOURCES", "sources_digest", "SourcesCache", "jit"]

#: compile options of the helpers (no allocation inside; no fast-math: see above)
HELPER = {"cache": True, "_nrt": False}
#: small helpers inlined into their caller (so that constant sizes propagate)
INLINE = {"cache": True, "_nrt": False, "inline": "always"}

#: The files the kernels' machine code depends on, relative to the ``xnavlab`` package: the
#: constants and containers they read and every module that compiles with :func:`jit`.
SOURCES = ("core/constants.py", "mars/kernel/kernel_inputs.py", "mars/kernel/kernel_compile.py",
           "mars/kernel/kernel_linalg.py", "mars/kernel/kernel_propagation.py",
           "mars/kernel/kernel_measurements.py", "mars/kernel/kernel_fusion.py",
           "mars/kernel/kernel_watch.py",
           "mars/kernel/kernels.py")

_PACKAGE = Path(__file__).resolve().parents[2]


def sources_digest(root=None):
    """SHA-256 (hex) of the kernel's sources, :data:`SOURCES` in order, name and bytes.

    Parameters
    ----------
    root : path-like, optional
        The ``xnavlab`` package directory to read (default: this one).

    Returns
    -------
    str
        64 hex digits.
    """
    root = Path(root) if root is not None else _PACKAGE
    h = hashlib.sha256()
    for rel in SOURCES:
        data = (root / rel).read_bytes()
        h.update(f"{rel}\0{len(data)}\0".encode())
        h.update(data)
    return h.hexdigest()


_DIGEST = sources_digest()


class SourcesCache(FunctionCache):
    """numba's on-disk cache of one function, valid only for the kernel sources it was written
    for: its index is stamped with :func:`sources_digest` instead of the defining file's hash
    (an index of another stamp is ignored and rewritten, as numba does for a changed file).

    Parameters
    ----------
    py_func : callable
        The Python function the dispatcher compiles.
    """

    def __init__(self, py_func):
        super().__init__(py_func)
        # numba checks this stamp when it loads the index (IndexDataCacheFile._load_index)
        self._cache_file._source_stamp = ("xnavlab kernel sources", _DIGEST)


def jit(**options):
    """``numba.njit(**options)``; with ``cache=True``, cached by :class:`SourcesCache`.

    Parameters
    ----------
    **options
        numba's options (:data:`HELPER`, :data:`INLINE` or those of an entry point).

    Returns
    -------
    callable
        The decorator.
    """

    def wrap(py_func):
        dispatcher = njit(**options)(py_func)
        if options.get("cache") and hasattr(dispatcher, "py_func"):  # NUMBA_DISABLE_JIT: none
            dispatcher._cache = SourcesCache(dispatcher.py_func)
        return dispatcher

    return wrap
