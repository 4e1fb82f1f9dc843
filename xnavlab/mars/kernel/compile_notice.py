"""The filter kernel's first compile, announced: one line instead of a silent pause.

:mod:`xnavlab.mars.kernel.kernels` is compiled by numba on its first call in a fresh environment
(about two minutes on two cores: 92-108 s measured; ``python -m xnavlab warmup`` does it at
set-up) and loaded
from numba's on-disk cache afterwards. :func:`announce_compile` prints one line when the
next call must compile; :func:`xnavlab.mars.navigation.scenarios.run_kernel` calls it. It lives
outside ``kernels.py`` because any edit of that file invalidates numba's cache of it.
"""

from __future__ import annotations

import sys

from xnavlab.mars.kernel import kernels

__all__ = ["is_compiled", "announce_compile"]

_ANNOUNCED = False


def is_compiled():
    """Whether :func:`~xnavlab.mars.kernel.kernels.run_epochs` is compiled here or in numba's cache.

    Reads numba's cache index beside ``kernels.py`` (an index written for another version of
    the source does not count). Any doubt (numba's internals changed) answers ``True``, so
    the worst case is a missing notice, never a wrong one.

    Examples
    --------
    >>> isinstance(is_compiled(), bool)
    True
    """
    if getattr(kernels.run_epochs, "signatures", True):  # compiled; or NUMBA_DISABLE_JIT: never
        return True
    try:
        return bool(kernels.run_epochs._cache._cache_file._load_index())
    except Exception:  # noqa: BLE001 - numba's private cache API: assume compiled
        return True


def announce_compile(stream=None):
    """Print one line when the next kernel call must compile (no cache yet); return whether.

    The first run in a fresh environment compiles the filter kernel for about two minutes on
    two cores (``python -m xnavlab warmup`` does it at set-up); this line says so instead of
    a silent pause. It prints at most once per process, and looks only until it has printed
    or found the kernel compiled.
    """
    global _ANNOUNCED
    if _ANNOUNCED:
        return False
    # once printed or once compiled, nothing more to say in this process: asked again at every
    # kernel call (8675 of them in a chi-square run), is_compiled would hash the signature of
    # named-tuple types each time (some 40 us)
    _ANNOUNCED = True
    if not hasattr(kernels.run_epochs, "signatures"):  # numba's NUMBA_DISABLE_JIT=1
        print("xnavlab: NUMBA_DISABLE_JIT is set: the filter kernel runs as plain Python, about "
              "3,000 times slower (some 20 minutes for the paper's 30 days)",
              file=stream or sys.stderr, flush=True)
        return True
    if is_compiled():
        return False
    print("xnavlab: compiling the filter kernel, once (about two minutes on two cores; later "
          "runs load it from numba's cache)", file=stream or sys.stderr, flush=True)
    return True
