"""The wavelet check that the Mallat transform and the causal filters share.

Plumbing of :mod:`xnavlab.core.detection` (imported by its ``mallat`` and ``online`` modules
only); not part of the public API.
"""

from __future__ import annotations

import pywt

__all__ = ["orthogonal_wavelet"]


def orthogonal_wavelet(wavelet):
    """The :class:`pywt.Wavelet` for ``wavelet`` (a name or a Wavelet), checked to be orthogonal.

    Raises ``ValueError`` for an unknown name or a non-orthogonal wavelet (eqs. (9)-(10)
    need orthonormal ``h`` and ``g``).

    Examples
    --------
    >>> orthogonal_wavelet("db3").dec_len
    6
    """
    if isinstance(wavelet, pywt.Wavelet):
        w = wavelet
    else:
        if not isinstance(wavelet, str) or wavelet not in pywt.wavelist(kind="discrete"):
            raise ValueError(f"wavelet must be a discrete PyWavelets wavelet name such as 'db3', "
                             f"got {wavelet!r}")
        w = pywt.Wavelet(wavelet)
    if not w.orthogonal:
        raise ValueError(f"wavelet must be orthogonal (h and g of eqs. (9)-(10)), got {w.name!r}")
    return w
