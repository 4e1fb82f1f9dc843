"""Checks that the timing modules share: a pulsar's fields, the spin drift a photon simulation
can invert, an observation's span, the exposure a fold divides by, two positions that broadcast,
a position outside a body, photon times a dtype can place in a phase bin, a .par file's text
(and its key, and a copy PINT can read).

Plumbing of :mod:`xnavlab.mars.timing` (imported by :mod:`xnavlab.mars.timing.pulsars`); not
part of the public API.
"""

from __future__ import annotations

import codecs
import contextlib
import hashlib
import os
import tempfile
from pathlib import Path

import numpy as np

from xnavlab.core import ephemeris
from xnavlab.core.ephemeris import check_epoch, check_epochs
from xnavlab.core.validate import check_finite_array, check_real, shown

__all__ = ["EPOCH_RESOLUTION", "check_epochs", "check_epoch",
           "MAX_DRIFT", "MAX_PHOTONS", "RADII", "check_pulsar_fields", "check_spin_drift", "check_span",
           "check_exposure", "check_broadcast", "check_outside", "check_photons",
           "check_times_dtype", "PHASE_RESOLUTION", "check_phase_dtype", "check_par_text",
           "PAR_NAMES", "par_digest", "readable_par"]

#: :data:`xnavlab.core.ephemeris.EPOCH_RESOLUTION` (1 ms), the one rule of the epochs' dtype
#: (a float32 epoch near 5e8 s moved clock_terms' clock term by 1.2e-7 s, 36 m).
EPOCH_RESOLUTION = ephemeris.EPOCH_RESOLUTION

#: The most photons a simulation of arrival times expects, ``(lambda_s + lambda_b) t_obs``
#: (the rates of :func:`xnavlab.mars.timing.pulsars.photon_rates`, which grow with the area):
#: a simulation holds about 40 bytes a photon at its peak, so 5e7 photons take about 2 GB
#: and half a minute (the Crab at 1 m^2 over 3,200 s; the millisecond pulsars over 11 days).
#: t_obs = 1e6 s of the Crab asked for 80 GiB at once.
MAX_PHOTONS = 5e7

#: The largest relative change of the spin frequency, ``|fdot| tau / f``, over the photons'
#: times ``tau`` that :func:`xnavlab.mars.timing.pulsars.simulate_photons` accepts. It inverts
#: ``Phi(tau) = f tau + fdot tau^2 / 2`` by two Newton steps from ``tau = Phi / f``, whose
#: error is about ``drift^7 tau / 128``: below 1e-16 ``tau`` (float64's spacing) at 1 %, while
#: at 10 % it is 1e-9 ``tau`` (a millisecond over 1e6 s), and near 100 % the frequency
#: ``f + fdot tau`` reaches zero and the Newton step divides by it. Every catalogued pulsar
#: drifts by under 1e-5 over the longest observation (the Crab: 1.3e-11 per second).
MAX_DRIFT = 0.01

#: Polar radii of the bodies of :data:`xnavlab.mars.timing.toa.GM_DE421`, m (IAU WGCCRE 2015,
#: Archinal et al. 2018: the smallest semi-axis, so that a clock on the surface at any latitude
#: passes; the Moon's and Venus's mean radius, the Sun's IAU 2015 B3 nominal one): a clock or an
#: observer nearer the centre is inside the body, where ``GM / |R - R_i|`` is no potential and
#: the body's Shapiro delay no delay (at the centre, a division by 0 or the log of 0).
RADII = {"sun": 6.957e8, "mercury": 2.43826e6, "venus": 6.0518e6, "earth": 6.3567519e6,
         "moon": 1.7374e6, "mars": 3.3762e6, "jupiter": 6.6854e7, "saturn": 5.4364e7}


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


def check_pulsar_fields(p, ranges, min_duty):
    """Refuse a :class:`xnavlab.mars.timing.pulsars.Pulsar` field out of its kind or range, by name.

    ``ranges`` maps each numeric field to its closed range; the width is within ``[min_duty P,
    0.5 P]``; the name is non-empty text (the key of every list of names), and ``sources``
    a dict from field names to text.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> p = SimpleNamespace(name="", period=1.0, width=0.1, sources={})
    >>> check_pulsar_fields(p, {"period": (1e-4, 1e4)}, 1e-4)
    Traceback (most recent call last):
    ...
    ValueError: Pulsar name must be a non-empty name (text, e.g. 'B0531+21'), got ''
    """
    if not isinstance(p.name, str) or not p.name.strip():
        raise ValueError(f"Pulsar name must be a non-empty name (text, e.g. 'B0531+21'), got {shown(p.name)}")
    for key, (lo, hi) in ranges.items():
        check_real(f"Pulsar {key}", getattr(p, key), lo, hi)
    check_real("Pulsar width", p.width, min_duty * p.period, 0.5 * p.period)
    fields = (*ranges, "width")
    if not isinstance(p.sources, dict):
        raise ValueError(f"Pulsar sources must be a dict {{field: where its value comes from}}, "
                         f"got {shown(p.sources)}")
    for key, value in p.sources.items():
        if key not in fields or not isinstance(value, str):
            raise ValueError(f"Pulsar sources must map fields ({', '.join(fields)}) to text, got "
                             f"{key!r}: {shown(value)}")


def check_photons(name, rates, t_obs):
    """``rates`` (``lambda_s, lambda_b``, ph/s) back when their photons over ``t_obs`` s expect at
    most :data:`MAX_PHOTONS`, else one ValueError leading with ``name`` (the argument the caller
    took that sets the count), before any array is drawn.

    Examples
    --------
    >>> check_photons("t_obs", (1e4, 5e3), 1e6)   # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: t_obs must keep the expected photons at most 5e+07 (about 2 GB), got 1.5e+10: ...
    """
    rate = float(rates[0] + rates[1])
    total = rate * t_obs
    if total > MAX_PHOTONS:
        raise ValueError(f"{name} must keep the expected photons at most {MAX_PHOTONS:.0e} (about 2 GB), "
                         f"got {total:.3g}: {rate:.4g} photons/s over {t_obs:.6g} s (at this area and "
                         f"background, at most {MAX_PHOTONS / rate:.4g} s; or a smaller area_m2)")
    return rates


def check_span(span):
    """``span`` as a float array ``(t_start, t_stop)`` with ``t_stop > t_start``, else one ValueError.

    Examples
    --------
    >>> check_span((10.0, 0.0))
    Traceback (most recent call last):
    ...
    ValueError: span must be (t_start, t_stop) with t_stop > t_start, got [10.0, 0.0]
    """
    span = check_finite_array("span", span)
    if span.shape != (2,) or not span[1] > span[0]:
        raise ValueError(f"span must be (t_start, t_stop) with t_stop > t_start, got {span.tolist()}")
    return span


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


def check_broadcast(name, value, other_name, other, why):
    """Refuse ``value`` (an array, shape (..., 3)) whose shape does not broadcast with ``other``'s.

    One ValueError leading with ``name`` (the later argument, checked against the earlier
    ``other_name``), in place of numpy's "operands could not be broadcast together".

    Examples
    --------
    >>> check_broadcast("r_sun_ssb", np.zeros(3), "r_ssb", np.zeros((5, 3)), "one per row")
    >>> check_broadcast("r_sun_ssb", np.zeros((3, 3)), "r_ssb", np.zeros((5, 3)), "one per row")
    Traceback (most recent call last):
    ...
    ValueError: r_sun_ssb must have shape (3,) or r_ssb's shape (5, 3) (one per row), got shape (3, 3)
    """
    try:
        np.broadcast_shapes(np.shape(value), np.shape(other))
    except ValueError:
        raise ValueError(f"{name} must have shape (3,) or {other_name}'s shape {np.shape(other)} ({why}), "
                         f"got shape {np.shape(value)}") from None


def check_outside(name, dist, body):
    """Refuse a distance from ``body``'s centre (m; a scalar or one per row of ``name``) within
    its polar radius (:data:`RADII`), naming ``name`` and the first row inside.

    Examples
    --------
    >>> check_outside("x", np.array([4e6, 3e6]), "mars")   # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: x must lie outside mars (at least its polar radius, 3376.2 km, from its centre), ...
    """
    dist = np.asarray(dist, dtype=float)
    inside = dist < RADII[body]
    if np.any(inside):
        i = int(np.argmax(inside.ravel()))
        where = f"{name}[{i}]" if dist.ndim else name
        raise ValueError(f"{name} must lie outside {body} (at least its polar radius, {RADII[body] / 1e3:g} "
                         f"km, from its centre), got {where} at {float(dist.ravel()[i]) / 1e3:.6g} km")


def check_times_dtype(name, value, p, nbins):
    """Refuse times ``value`` (s, already checked finite) of a float dtype narrower than
    float64 that cannot place a photon to a tenth of one of ``nbins`` phase bins of ``p``:
    refused, not converted (the values given are already rounded; float32 resolves 1 ms at
    1e4 s, a tenth of a bin of B1937+21's 1.56 ms in 256 bins is 0.6 us)."""
    dtype = np.asarray(value).dtype
    if dtype.kind != "f" or dtype.itemsize >= 8:
        return
    largest = float(np.abs(np.asarray(value, dtype=float)).max(initial=0.0))
    res = float(np.spacing(dtype.type(largest)))
    tenth = 0.1 * p.period / nbins  # s: a tenth of a phase bin
    if not res <= tenth:
        raise ValueError(f"{name} must resolve its times to a tenth of a phase bin ({tenth:.3g} s, "
                         f"{nbins} bins of {p.name}'s {p.period:.4g} s period): as {dtype} it "
                         f"resolves {res:.3g} s at {largest:.6g} s; pass float64 times")


#: The finest a pulse phase's times must resolve, cycles (:func:`check_phase_dtype`): a thousandth
#: of a cycle is 34 us for the Crab and 1.6 us for B1937+21 (float32 resolves 32 s at 5e8 s).
PHASE_RESOLUTION = 1e-3


def check_phase_dtype(f, named):
    """Refuse times (s, already checked finite: ``named`` maps each parameter to its value) of a
    float dtype narrower than float64 that cannot resolve a phase of spin frequency ``f`` (Hz)
    to :data:`PHASE_RESOLUTION` cycles, nor epochs to :data:`EPOCH_RESOLUTION`: refused, not
    converted (the values given are already rounded), naming the first at fault.

    Examples
    --------
    >>> check_phase_dtype(29.6, {"t": np.float32([10.0]), "t0": 0.0})
    >>> check_phase_dtype(29.6, {"t": np.float32([5e8])})  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: t must resolve its times to 3.38e-05 s (0.001 of a cycle at f = 29.6 Hz, at most 0.001 s): ...
    """
    tol = min(EPOCH_RESOLUTION, PHASE_RESOLUTION / f)
    for name, value in named.items():
        dtype = np.asarray(value).dtype
        if dtype.kind != "f" or dtype.itemsize >= 8:
            continue
        largest = float(np.abs(np.asarray(value, dtype=float)).max(initial=0.0))
        res = float(np.spacing(dtype.type(largest)))
        if not res <= tol:
            raise ValueError(f"{name} must resolve its times to {tol:.3g} s ({PHASE_RESOLUTION:g} of a "
                             f"cycle at f = {f:g} Hz, at most {EPOCH_RESOLUTION:g} s): as {dtype} it "
                             f"resolves {res:.3g} s at {largest:.6g} s; pass float64 times")


#: The keywords that name the pulsar in a timing model (PINT's ``PSR`` and its aliases).
PAR_NAMES = ("PSR", "PSRJ", "PSRB")


def check_par_text(path):
    """A file that is no timing model (binary, empty, without F0 or PSR) refused in our words,
    naming it; PINT would say "Model must have one and only one spindown component", take 0 Hz,
    or name the pulsar "None". Returns the file's bytes (``None`` for no file: PINT's reader
    names it)."""
    if not isinstance(path, str | os.PathLike) or not Path(path).is_file():
        return None  # timing_parameters names it
    try:
        data = Path(path).read_bytes()
    except OSError as exc:
        raise ValueError(f"path: the timing model {str(path)!r} cannot be read ({exc.strerror})") from None
    head = f"path: {str(path)!r} is not a pulsar timing model"
    if b"\0" in data:
        raise ValueError(f"{head}: it holds binary data (byte 0x00 at position {data.index(0)}), "
                         f"not the text of a .par file")
    try:
        text = data.decode("utf-8").removeprefix("\ufeff")  # a byte-order mark: readable_par
    except UnicodeDecodeError as exc:
        raise ValueError(f"path: the timing model {str(path)!r} is not UTF-8 text (byte "
                         f"{data[exc.start]:#04x} at position {exc.start})") from None
    lines = [ln.split() for ln in text.splitlines()
             if ln.split() and not ln.lstrip().startswith(("#", "C "))]
    if not lines:
        raise ValueError(f"{head}: it is empty (a .par file gives one parameter a line: PSR, "
                         f"RAJ and DECJ or ELONG and ELAT, F0, ...)")
    f0 = [ln for ln in lines if ln[0].upper() == "F0"]
    if not f0:
        raise ValueError(f"{head}: it has no F0 line (the spin frequency, Hz, in every timing model)")
    try:  # PINT: an AttributeError of its own for "F0" alone, its long double's words for "F0 abc"
        float(f0[0][1].upper().replace("D", "E"))  # a Fortran exponent (1.2D-3) is a number too
    except (IndexError, ValueError):
        raise ValueError(f"{head}: its F0 line holds no number (the spin frequency, Hz), got "
                         f"{' '.join(f0[0])!r}") from None
    if not any(ln[0].upper() in PAR_NAMES and len(ln) > 1 for ln in lines):  # PINT: "None"
        raise ValueError(f"{head}: it has no PSR line with the pulsar's name (e.g. PSR B1937+21; "
                         f"PSRJ or PSRB too)")
    return data


def par_digest(name, path):
    """The SHA-256 of a ``.par`` file's bytes (hex), which keys the pulsar read from it, else
    one ValueError naming the pulsar ``name`` as given.

    Its bytes, not its modification time: ``cp -p``, ``rsync -t``, ``tar x``, ``unzip`` and
    ``shutil.copy2`` keep a file's time, so another model can replace it unseen.

    Examples
    --------
    >>> par_digest("x.par", "/no/such/x.par")
    Traceback (most recent call last):
    ...
    ValueError: pulsar 'x.par': no such timing model (.par) file
    """
    try:
        return hashlib.sha256(Path(path).read_bytes()).hexdigest()
    except FileNotFoundError:
        raise ValueError(f"pulsar {name!r}: no such timing model (.par) file") from None
    except OSError as exc:  # a folder, a file without read permission
        raise ValueError(f"pulsar {name!r}: the timing model cannot be read ({exc.strerror})") from None


@contextlib.contextmanager
def readable_par(path):
    """``path``, checked by :func:`check_par_text`, for PINT to read: as it is, or, when it
    starts with a UTF-8 byte-order mark, a copy without the mark (in a temporary folder while
    the ``with`` block runs). PINT reads the mark into the first keyword (``'\\ufeffPSR'``),
    drops that line with a warning and names the pulsar "None". A ValueError raised in the block
    names ``path``, never the copy.

    Examples
    --------
    >>> folder = Path(tempfile.mkdtemp())
    >>> (folder / "m.par").write_bytes(codecs.BOM_UTF8 + b"PSR B1937+21\\nF0 641.9\\n")
    25
    >>> with readable_par(folder / "m.par") as copy:
    ...     copy.read_bytes()[:12], copy == folder / "m.par"
    (b'PSR B1937+21', False)
    >>> import shutil; shutil.rmtree(folder)
    """
    data = check_par_text(path)
    if data is None or not data.startswith(codecs.BOM_UTF8):
        yield path
        return
    with tempfile.TemporaryDirectory() as folder:
        copy = Path(folder) / Path(path).name
        copy.write_bytes(data[len(codecs.BOM_UTF8):])
        try:
            yield copy
        except ValueError as exc:  # PINT's reader named the copy
            raise ValueError(str(exc).replace(str(copy), str(path))) from None
