"""Checks that the timing modules share: the spin drift a photon simulation can invert, the
exposure a fold divides by.

Plumbing of :mod:`xnavlab.mars.timing` (imported by :mod:`xnavlab.mars.timing.pulsars`); not
part of the public API.
"""

from __future__ import annotations

import numpy as np

__all__ = ["MAX_DRIFT", "check_spin_drift", "check_exposure"]

#: The largest relative change of the spin frequency, ``|fdot| tau / f``, over the photons'
#: times ``tau`` that :func:`xnavlab.mars.timing.pulsars.simulate_photons` accepts. It inverts
#: ``Phi(tau) = f tau + fdot tau^2 / 2`` by two Newton steps from ``tau = Phi / f``, whose
#: error is about ``drift^7 tau / 128``: below 1e-16 ``tau`` (float64's spacing) at 1 %, while
#: at 10 % it is 1e-9 ``tau`` (a millisecond over 1e6 s), and near 100 % the frequency
#: ``f + fdot tau`` reaches zero and the Newton step divides by it. Every catalogued pulsar
#: drifts by under 1e-5 over the longest observation (the Crab: 1.3e-11 per second).
MAX_DRIFT = 0.01


def check_spin_drift(name, f, fdot, t_obs, shift):
    """Refuse a spin that drifts by more than :data:`MAX_DRIFT` over the photons of a simulation.

    The photons' times from the phase model's epoch reach ``|shift| + t_obs`` and a few
    periods more (the spare cycles drawn at each end).

    Parameters
    ----------
    name : str
        The pulsar's name, for the message.
    f, fdot : float
        Spin frequency (Hz, positive) and its derivative (Hz/s).
    t_obs, shift : float
        Observation time and the pulse train's offset, s.

    Raises
    ------
    ValueError
        Naming ``pulsar`` when its spin-down alone drifts too far within ``t_obs``, else
        ``shift`` (the offset that carries the photons that far from the epoch).

    Examples
    --------
    >>> check_spin_drift("B0531+21", 29.946923, -3.77535e-10, 1e6, 0.0)
    >>> check_spin_drift("X", 1e-4, -1.0, 10.0, 0.0)   # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: pulsar X must change its spin frequency by under 1% over the photons' times, ...
    """
    spare = 3.0 / f  # the spare cycles each side and the profile's tails
    if abs(fdot) * (t_obs + spare) > MAX_DRIFT * f:
        raise ValueError(f"pulsar {name} must change its spin frequency by under {MAX_DRIFT:.0%} over "
                         f"the photons' times, got fdot = {fdot:g} Hz/s against f = {f:g} Hz over "
                         f"{t_obs + spare:.3g} s (t_obs = {t_obs:g} s and 3 periods)")
    reach = abs(shift) + t_obs + spare
    if abs(fdot) * reach > MAX_DRIFT * f:
        limit = MAX_DRIFT * f / abs(fdot) - t_obs - spare
        raise ValueError(f"shift must be within {limit:.3g} s of 0, where pulsar {name}'s spin "
                         f"frequency (fdot = {fdot:g} Hz/s, f = {f:g} Hz) has drifted by "
                         f"{MAX_DRIFT:.0%}, got {shift:g}")


def check_exposure(exposure, span, given, period):
    """``exposure`` (each phase bin's, cycles) if every bin has some, else one ValueError.

    A span shorter than a pulse cycle leaves some bins unswept: their exposure is zero and
    :func:`xnavlab.mars.timing.pulsars.fold` would divide their counts by it (inf and NaN, with
    numpy's warnings). Named ``span`` when the caller gave it (``given``), else ``t`` (whose
    first and last photons made it).

    Examples
    --------
    >>> check_exposure(np.ones(4), (0.0, 1.0), True, 0.5).tolist()
    [1.0, 1.0, 1.0, 1.0]
    >>> check_exposure(np.array([1.0, 0.0]), (0.0, 0.2), True, 0.5)
    Traceback (most recent call last):
    ...
    ValueError: span must sweep every phase bin (a whole pulse cycle, 0.5 s, does), got 0.2 s
    """
    if np.all(exposure > 0.0):
        return exposure
    length = float(span[1] - span[0])
    if given:
        raise ValueError(f"span must sweep every phase bin (a whole pulse cycle, {period:.6g} s, does), "
                         f"got {length:.6g} s")
    raise ValueError(f"t must span every phase bin (a whole pulse cycle, {period:.6g} s, does) for its "
                     f"exposure, got photons over {length:.6g} s: give span, or exposure=False")
