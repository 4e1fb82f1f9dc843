"""The combined detector inside the compiled filter's loop.

For the subsystems it watches, :func:`xnavlab.mars.kernel.kernels.run_epochs` whitens each
measurement's innovation against the master's one-step prediction (:func:`whiten`) and
feeds the combined detector's innovation parts (chi-square, mean and variance CUSUMs;
XNAV's innovation wavelet: :func:`watch`) before the update; an alarm leaves the
measurement out and switches the subsystem out from the next epoch, and the call returns
after that epoch, as it does on the re-admission grid when an isolated subsystem's last
innovations are quiet (:func:`quiet`). :mod:`xnavlab.mars.faults.watch` holds the state (its
columns: :data:`~xnavlab.mars.kernel.kernel_inputs.WF_KMEAN` ...); the adaptive scale is
recomputed here, its medians by selection. Unwatched runs pay one test per measurement.
The readable versions: :class:`xnavlab.core.detection.InnovationMonitor` and
:class:`xnavlab.mars.faults.innovations.XnavInnovationWavelet`.

Examples
--------
>>> import numpy as np
>>> med, cnt = np.empty(5), np.empty(8192, dtype=np.int64)
>>> float(_median_abs(np.array([3.0, -1.0, 2.0, -5.0]), 4, med, cnt))   # (2 + 3) / 2
2.5
"""

from __future__ import annotations

import math

import numpy as np

from xnavlab.mars.kernel import kernel_inputs as ki
from xnavlab.mars.kernel.kernel_compile import HELPER, INLINE, jit
from xnavlab.mars.kernel.kernel_linalg import cholesky, forward
from xnavlab.mars.kernel.kernel_measurements import KIND_CNS, KIND_UV, KIND_XNAV, innovation_cov

__all__ = ["whiten", "watch", "quiet"]


@jit(**INLINE)
def _whiten_uv(x, P, jm, se, y):
    """UV measurement ``jm``'s innovation at the state ``x`` (6,) with covariance ``P``,
    whitened per component into ``y``: the range and the direction's two tangent axes, each
    ``nu / sqrt(g P g^T + sigma^2)`` (the unit vector's radial part carries no information)."""
    z, sig_r, sig_u = se.z_u, se.sig_r, se.sig_u
    rn = math.sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2])
    u0, u1, u2 = -x[0] / rn, -x[1] / rn, -x[2] / rn
    p00, p01, p02, p11, p12, p22 = P[0, 0], P[0, 1], P[0, 2], P[1, 1], P[1, 2], P[2, 2]
    s = (u0 * (p00 * u0 + p01 * u1 + p02 * u2) + u1 * (p01 * u0 + p11 * u1 + p12 * u2)
         + u2 * (p02 * u0 + p12 * u1 + p22 * u2))                   # u^T P u
    y[0] = (z[jm, 0] - rn) / math.sqrt(s + sig_r * sig_r)          # range, g = -u
    if abs(u2) > 1.0 - 1e-12:                     # tangent basis e1 = z x u (x x u at a pole)
        e1 = (0.0, -u2, u1)
    else:
        e1 = (-u1, u0, 0.0)
    m1 = math.sqrt(e1[0] ** 2 + e1[1] ** 2 + e1[2] ** 2)
    e1 = (e1[0] / m1, e1[1] / m1, e1[2] / m1)
    e2 = (u1 * e1[2] - u2 * e1[1], u2 * e1[0] - u0 * e1[2], u0 * e1[1] - u1 * e1[0])
    for c in range(2):
        e = e1 if c == 0 else e2
        d = (z[jm, 1] - u0) * e[0] + (z[jm, 2] - u1) * e[1] + (z[jm, 3] - u2) * e[2]
        s = (e[0] * (p00 * e[0] + p01 * e[1] + p02 * e[2]) + e[1] * (p01 * e[0] + p11 * e[1]
             + p12 * e[2]) + e[2] * (p02 * e[0] + p12 * e[1] + p22 * e[2]))   # e^T P e
        y[1 + c] = d / math.sqrt(s / (rn * rn) + sig_u * sig_u)    # g = -e / |r|


@jit(**INLINE)
def _whiten_at(P, me, m, up):
    """``up.y = L^-1 nu`` with ``L L^T = H P H^T + R`` (``me``'s nu, H, R); False if S is
    not positive definite."""
    innovation_cov(P, 1.0, me, m, up)                         # S = H P H^T + R
    ok = cholesky(up.S, m, up.L)
    y, nu = up.y, me.nu
    for i in range(m):
        y[i] = nu[i]
    forward(up.L, m, y)
    return ok


@jit(**INLINE)
def whiten(kind, jm, me, m, fu, se, up):
    """One measurement's innovation against the master's prediction, whitened.

    Parameters
    ----------
    kind, jm : int
        The subsystem's code (:data:`~xnavlab.mars.kernel.kernel_measurements.KIND_XNAV`, ...) and
        the measurement's row in its series.
    me : xnavlab.mars.kernel.kernel_inputs.Measurement
        Its innovation, Jacobian and R at the master's prediction, size m.
    m : int
    fu : xnavlab.mars.kernel.kernel_inputs.FusionScratch
        The master's prediction ``xp``, ``Pp``.
    se : xnavlab.mars.kernel.kernel_inputs.Sensors
    up : xnavlab.mars.kernel.kernel_inputs.UpdateScratch
        ``y`` written: ``L^-1 nu`` with ``L L^T = H P H^T + R`` (UV: the range and the
        direction's two tangent axes, each over its own sigma).

    Returns
    -------
    int
        The whitened innovation's size (UV: 3).
    """
    if kind == KIND_UV:
        _whiten_uv(fu.xp, fu.Pp, jm, se, up.y)
        return 3
    _whiten_at(fu.Pp, me, m, up)
    return m


@jit(**INLINE)
def _ys(kind, ws):
    """The innovation output (whitened, unscaled) of a subsystem kind (``ws`` a
    :class:`~xnavlab.mars.kernel.kernel_inputs.WatchState`)."""
    if kind == KIND_UV:
        return ws.ys_u
    if kind == KIND_CNS:
        return ws.ys_c
    return ws.ys_x


@jit(**INLINE)
def watch(kind, i, jm, connected, m, y, ws, wt):
    """Feed one whitened innovation to the combined detector's parts; True on an alarm.

    Parameters
    ----------
    kind, i, jm : int
        The subsystem's code and index, the measurement's row.
    connected : bool
        Judged only if connected (and armed); else only recorded.
    m : int
    y : ndarray, shape (>= m,)
        The innovation from :func:`whiten`.
    ws : xnavlab.mars.kernel.kernel_inputs.WatchState
        The detector's state, updated; ``alarm[i]`` says which part alarmed.
    wt : xnavlab.mars.kernel.kernel_inputs.WatchScratch

    Returns
    -------
    bool
    """
    wi = ws.wi
    wi[i, ki.WI_LAST] = jm
    if wi[i, ki.WI_OUT]:
        wi[i, ki.WI_NOUT] += 1
    hit = _watch_monitor(i, jm, m, connected, y, _ys(kind, ws), ws, wt)
    if connected and kind == KIND_XNAV and ws.xG.shape[0] > 0:
        hit = _watch_wavelet(i, wt.zw, m, ws) or hit
    return hit


@jit(**INLINE)
def _watch_monitor(i, jm, m, connected, y, ys, ws, wt):
    """The innovation parts of the combined detector on one whitened innovation ``y`` (m,)
    of subsystem ``i`` (:class:`xnavlab.core.detection.InnovationMonitor`, one sample), its
    state in ``ws`` (:class:`~xnavlab.mars.kernel.kernel_inputs.WatchState`).

    Writes ``y`` to ``ys[jm]`` and ``z = y / s`` (the adaptive scale) to ``wt.zw``; if
    ``connected`` (and armed): the chi-square ``q = sum z^2``, the CUSUMs
    ``S+ = max(0, S+ + z - k)``, ``S- = max(0, S- - z - k)``, ``V = max(0, V + z^2 - k_v)``;
    on an alarm the CUSUMs restart, ``alarm[i]`` gets the part and its ratio and True is
    returned; a healthy sample goes into the scale's window, and the scale is recomputed on
    the monitor's grid of samples fed (``_rescale``)."""
    wf, wi, wS, wsc, ring, alarm = ws.wf, ws.wi, ws.wS, ws.wsc, ws.ring, ws.alarm
    z = wt.zw
    q = 0.0
    for c in range(m):
        ys[jm, c] = y[c]
        z[c] = y[c] / wsc[i, c]
        q += z[c] * z[c]                                       # chapter 9 eq. (ch9-chi2)
    if not connected:
        return False
    km, kv = wf[i, ki.WF_KMEAN], wf[i, ki.WF_KVAR]
    hm, hv = wf[i, ki.WF_HMEAN], wf[i, ki.WF_HVAR]
    over = q > wf[i, ki.WF_CHI2]
    for c in range(m):
        a = max(0.0, wS[i, c] + z[c] - km)                    # S+ = max(0, S+ + z - k)
        b = max(0.0, wS[i, m + c] - z[c] - km)                # S- = max(0, S- - z - k)
        v = max(0.0, wS[i, 2 * m + c] + z[c] * z[c] - kv)     # V = max(0, V + z^2 - k_v)
        wS[i, c], wS[i, m + c], wS[i, 2 * m + c] = a, b, v
        over = over or a > hm or b > hm or v > hv
    best = 0.0
    if over:                  # (statistic / threshold > 1 needs statistic > threshold)
        best = q / wf[i, ki.WF_CHI2]
        part = 0
        for j in range(3 * m):
            r = wS[i, j] / (hm if j < 2 * m else hv)
            if r > best:
                best = r
                part = 1 + j
    if best > 1.0:
        for j in range(3 * m):
            wS[i, j] = 0.0
        alarm[i, 0] = part
        alarm[i, 1] = best
        return True
    W = wi[i, ki.WI_W]                                            # a healthy sample: the window
    pos = wi[i, ki.WI_POS]
    for c in range(m):
        ring[i, c, pos] = y[c]
    wi[i, ki.WI_POS] = (pos + 1) % W
    wi[i, ki.WI_NRING] = min(W, wi[i, ki.WI_NRING] + 1)
    wi[i, ki.WI_NFED] += 1
    if wi[i, ki.WI_NFED] >= wi[i, ki.WI_NEXT]:
        if wi[i, ki.WI_ADAPT]:
            _rescale(i, m, ws, wt)
        nxt = wi[i, ki.WI_NEXT]                 # 100, 200, 400, ... then every scale_every
        wi[i, ki.WI_NEXT] = min(2 * nxt, nxt + wi[i, ki.WI_EVERY])
    return False


@jit(**HELPER)
def _rescale(i, m, ws, wt):
    """The adaptive scale ``ws.wsc[i]`` from the MAD window ``ws.ring[i]``, as
    :meth:`xnavlab.core.detection.InnovationMonitor.scale_from`:
    ``s^2 = (n0 + n MAD^2) / (n0 + n)``, ``MAD = median|y| / 0.6745`` (scratch ``wt.med``,
    ``wt.cnt``)."""
    wf, wi, ring, wsc, med, cnt = ws.wf, ws.wi, ws.ring, ws.wsc, wt.med, wt.cnt
    n = wi[i, ki.WI_NRING]
    n0 = wf[i, ki.WF_PRIOR]
    for c in range(m):
        mad = _median_abs(ring[i, c], n, med, cnt) / wf[i, ki.WF_MAD]
        wsc[i, c] = math.sqrt((n0 + n * (mad * mad)) / (n0 + n))


@jit(**HELPER)
def _median_abs(x, n, med, cnt):
    """``median(|x[:n]|)`` exactly as numpy takes it (the mean of the two middle values for even
    ``n``), by :func:`_radix_select` (scratch ``med`` (>= n,), ``cnt`` (8192,) int64)."""
    for r in range(n):
        med[r] = abs(x[r])
    k = n // 2
    v = _radix_select(med, n, k, cnt)
    if n % 2 == 0:
        below, lo = 0, 0.0
        for r in range(n):          # (branch-free: the comparisons are coin flips)
            a = abs(x[r])
            lt = a < v
            below += lt
            lo = max(lo, a * lt)
        v = ((lo if below >= k else v) + v) / 2.0
    return v


@jit(**HELPER)
def _radix_select(f, n, k, cnt):
    """The k-th smallest (0-based) of the nonnegative ``f[:n]``, destroying ``f``: histograms of
    the bit patterns (whose order is the values' order), 12 then 13 bits at a time, keep the
    bucket holding the k-th, until at most 32 are left (few branches, so few mispredictions:
    half a quickselect's time on a day of innovations)."""
    u = f.view(np.uint64)
    shift, width = 52, 12
    while True:
        mask = (1 << width) - 1
        sh, mk = np.uint64(shift), np.uint64(mask)
        for b in range(mask + 1):
            cnt[b] = 0
        for r in range(n):
            cnt[np.int64((u[r] >> sh) & mk)] += 1
        b = 0
        while cnt[b] <= k:
            k -= cnt[b]
            b += 1
        w = 0
        for r in range(n):          # compaction without a branch
            e = u[r]
            u[w] = e
            w += np.int64((e >> sh) & mk) == b
        n = w
        if n <= 32 or shift == 0:      # (at shift 0 the bucket holds one value, repeated)
            break
        width = min(13, shift)
        shift -= width
    for r in range(1, n):              # insertion sort of the last bucket
        v, j = f[r], r - 1
        while j >= 0 and f[j] > v:
            f[j + 1] = f[j]
            j -= 1
        f[j + 1] = v
    return f[k]


@jit(**HELPER)
def quiet(kind, i, ws):
    """Whether subsystem ``i``, switched out, may rejoin.

    A superset of the loop's own test, which decides: its last ``W`` scaled innovations since
    the isolation give a NIS sum below the threshold and no component sum beyond
    ``zq sqrt(W)``.

    Parameters
    ----------
    kind, i : int
        The subsystem's code and index.
    ws : xnavlab.mars.kernel.kernel_inputs.WatchState

    Returns
    -------
    bool
    """
    ys = _ys(kind, ws)
    wf, wi, wsc = ws.wf, ws.wi, ws.wsc
    w = wi[i, ki.WI_RWIN]
    if wi[i, ki.WI_NOUT] < w:
        return False
    m = wi[i, ki.WI_M]
    last = wi[i, ki.WI_LAST]
    tot = 0.0
    for c in range(m):
        sc = 0.0
        for r in range(last - w + 1, last + 1):
            z = ys[r, c] / wsc[i, c]
            tot += z * z
            sc += z
        if abs(sc) > wf[i, ki.WF_ZQ] * math.sqrt(w) * (1.0 + 1e-9):
            return False
    return tot < wf[i, ki.WF_RTHR] * (1.0 + 1e-9)


@jit(**HELPER)
def _watch_wavelet(i, z, m, ws):
    """The XNAV innovation wavelet on one scaled innovation ``z`` (m,) (newest first in
    ``ws.xbuf``; :class:`xnavlab.mars.faults.innovations.XnavInnovationWavelet`): True when a level's
    ``|d_j| > k sigma_j`` for some pulsar; ``ws.alarm[i, 2:]`` get ``level * m + pulsar`` and
    the ratio."""
    wi, xbuf, xG, xthr, alarm = ws.wi, ws.xbuf, ws.xG, ws.xthr, ws.alarm
    nw = xG.shape[1]
    for r in range(nw - 1, 0, -1):
        for c in range(m):
            xbuf[r, c] = xbuf[r - 1, c]
    for c in range(m):
        xbuf[0, c] = z[c]
    wi[i, ki.WI_XCOUNT] += 1
    if wi[i, ki.WI_XCOUNT] < nw:
        return False
    best = -1.0
    code = 0
    for lv in range(xG.shape[0]):
        for c in range(m):
            d = 0.0
            for r in range(nw):
                d += xG[lv, r] * xbuf[r, c]                    # d_j = sum_r g_j[r] z[n - r]
            ratio = abs(d) / xthr[lv]
            if ratio > best:
                best = ratio
                code = lv * m + c
    if best > 1.0:
        alarm[i, 2] = code
        alarm[i, 3] = best
        return True
    return False
