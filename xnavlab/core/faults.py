"""Sensor fault injection: step, ramp, spike, stuck output and noise increase.

A :class:`Fault` says which sensor and which measurement component fails, how,
how much, from when and for how long. :func:`inject` applies a schedule of faults
to a measurement time series; :func:`parse_spec` reads the command-line form
``SENSOR[.COMPONENT]:KIND:MAGNITUDE@ONSET+DURATION``.

Magnitudes are in the measurement's SI unit (seconds for XNAV delays, metres for
ranges, radians for angles, rad/s for gyro rates); a ramp's magnitude is its rate
per second; a noise fault's magnitude is the standard deviation of the extra noise.

Kinds
-----
step
    ``+ magnitude`` while active.
ramp
    ``+ magnitude * (t - onset)`` while active (a drift).
spike
    ``+ magnitude`` on the first sample at or after the onset only (an outlier);
    the duration is ignored.
stuck
    the output freezes at the last fault-free sample before the onset.
noise
    ``+ N(0, magnitude^2)`` while active.

What a fault refuses
--------------------
A fault that would be injected as nothing is refused with a ``ValueError`` naming the
parameter and its range, because a run with it would score a fault that never acted as
missed: a zero ``magnitude`` (step, ramp, spike; a noise sigma must be > 0; a stuck
output's magnitude is ignored), a zero or negative ``duration`` (every kind but the spike,
whose duration is ignored; ``math.inf`` is a permanent fault), and a ``magnitude``,
``onset`` or finite ``duration`` that is NaN or infinite, and a fault larger than
:data:`MAX_SIZE` (1e15 in the measurement's SI unit: a ``magnitude``, or what a ramp reaches
on the samples it acts on, :func:`inject`). Whether a fault falls inside a
run and acts on at least one sample is the run's check
(:func:`xnavlab.mars.faults.schedules.check_schedule` for the Mars run).

A schedule (:func:`check_faults`) is a sequence of :class:`Fault`: one Fault alone, a spec
string or anything else is refused by name, and so is a fault listed twice (it would be
injected twice, doubling its size, and scored as two faults), and so are two faults acting on
one component of one sensor at one time (the same fault written two ways, ``uv.range`` and
``uv`` for every component, or overlapping windows: compared as parsed faults, a window
``[onset, end)``, a spike's the instant ``onset``).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from numbers import Real

import numpy as np

from xnavlab.core.validate import (
    check_choice,
    check_finite_array,
    check_increasing,
    check_int,
    check_text,
    make_rng,
)

__all__ = ["KINDS", "MAX_SIZE", "Fault", "check_faults", "inject", "fault_mask", "parse_spec", "format_spec"]

#: The fault kinds :class:`Fault` accepts.
KINDS = ("step", "ramp", "spike", "stuck", "noise")

#: The largest size of a fault, in the measurement's SI unit: its ``magnitude`` (a ramp's rate
#: per second, a noise sigma) and what a ramp reaches while it acts. Far above any physical
#: fault in the package's units (1e15 m is 6700 au; 1e15 s of XNAV delay 30 million years;
#: an angle or a unit-vector component is meaningless beyond a few units), and far below
#: where the arithmetic fails (a ramp of 1e308 per s overflows; an undetected Mars fault of
#: 1e22 m still runs, one of 1e30 leaves the filter's covariance indefinite).
MAX_SIZE = 1e15


@dataclass(frozen=True)
class Fault:
    """One fault on one sensor.

    Parameters
    ----------
    sensor : str
        Sensor name, e.g. ``"uv"``, ``"xnav"``, ``"cns"``, ``"gyro"``, ``"pseudorange"``.
    kind : {"step", "ramp", "spike", "stuck", "noise"}
        Fault kind (see module docstring).
    magnitude : float
        Size in the measurement's SI unit (per second for a ramp); 0 for a stuck fault (the
        output freezes at its last fault-free value).
    onset : float
        Start time, s.
    duration : float
        Length, s; ``math.inf`` for a permanent fault.
    component : int or None
        Index of the faulty measurement component; ``None`` means every component.

    Examples
    --------
    >>> f = Fault("uv", "step", 5000.0, onset=10.0, duration=5.0, component=0)
    >>> f.active(np.array([9.0, 10.0, 14.9, 15.0])).tolist()
    [False, True, True, False]
    """

    sensor: str
    kind: str
    magnitude: float
    onset: float
    duration: float = math.inf
    component: int | None = None

    def __post_init__(self):
        if not isinstance(self.sensor, str) or not self.sensor:
            raise ValueError(f"sensor must be a non-empty string, got {self.sensor!r}")
        self._store("sensor", str(self.sensor))   # np.str_: a plain str
        self._store("kind", str(check_choice("kind", self.kind, KINDS)))
        self._store("magnitude", _check_finite("magnitude", self.magnitude,
                                               "the measurement's SI unit"))
        if abs(self.magnitude) > MAX_SIZE:
            raise ValueError(f"magnitude of a {self.kind} fault must be at most {MAX_SIZE:g} in size "
                             f"(the measurement's SI unit{', per s' if self.kind == 'ramp' else ''}; "
                             f"beyond any physical fault), got {self.magnitude!r}")
        if self.kind == "noise" and not self.magnitude > 0.0:
            raise ValueError(f"magnitude of a noise fault (the extra noise's standard deviation) "
                             f"must be a real number in (0, inf), got {self.magnitude!r}")
        if self.kind == "stuck" and self.magnitude != 0.0:  # every input used or refused
            raise ValueError(f"magnitude of a stuck fault must be 0 (the output freezes at its "
                             f"last fault-free value: a size would go unused), got "
                             f"{self.magnitude!r}")
        if self.kind not in ("noise", "stuck") and self.magnitude == 0.0:
            raise ValueError(f"magnitude of a {self.kind} fault must be a nonzero finite real "
                             f"number, in (-inf, 0) or (0, inf), got {self.magnitude!r} (a "
                             "zero-size fault injects nothing)")
        self._store("onset", _check_finite("onset", self.onset, "s"))
        d = self.duration
        real = isinstance(d, Real) and not isinstance(d, bool)
        if self.kind == "spike":         # one sample: the duration is ignored
            if not (real and d >= 0.0):
                raise ValueError(f"duration of a spike fault (ignored) must be a real number in "
                                 f"[0, inf], s, got {d!r}")
        elif not (real and 0.0 < d <= math.inf):
            why = " (a fault of zero or negative length injects nothing)" if real and d <= 0 else ""
            raise ValueError(f"duration of a {self.kind} fault must be a real number in "
                             f"(0, inf], s, got {d!r}{why}")
        if self.component is not None:
            self._store("component", check_int("component", self.component, 0))
        try:
            self._store("duration", float(d))
        except OverflowError:   # 10**400 s: a permanent fault
            self._store("duration", math.inf)

    def _store(self, field, value):
        """Keep the checked Python number (``float``, ``int``), not the user's numpy scalar: an
        np.float16 or np.int8 would compute in its own dtype later (``onset + duration``)."""
        object.__setattr__(self, field, value)

    @property
    def end(self):
        """End time, s (``onset + duration``)."""
        return self.onset + self.duration

    def active(self, t):
        """Boolean mask of the samples ``t`` (s) at which the fault acts."""
        t = check_finite_array("t", t)
        if self.kind == "spike":
            mask = np.zeros(t.shape, dtype=bool)
            idx = np.flatnonzero(t >= self.onset)
            if idx.size:
                mask[idx[0]] = True
            return mask
        return (t >= self.onset) & (t < self.end)


def _check_finite(name, value, unit):
    """``float(value)``, or one ValueError naming ``name`` (an integer beyond any float too)."""
    try:
        x = float(value) if isinstance(value, Real) and not isinstance(value, bool) else math.nan
    except OverflowError:   # 10**400
        x = math.inf
    if not math.isfinite(x):
        raise ValueError(f"{name} must be a finite real number, {unit}, got {value!r}")
    return x


def check_faults(name, faults, components=None):
    """``faults`` as a list of :class:`Fault`, or one ``ValueError`` naming ``name``.

    Parameters
    ----------
    name : str
        The parameter's name, for the message.
    faults : sequence of Fault
        A schedule; no fault may be listed twice (it would be injected twice and scored as
        two faults).
    components : dict of str to sequence of str, optional
        Component names per sensor (a non-empty list or tuple of str each), to name a repeated
        fault in the spec form; when given, it must name every fault's sensor and component.

    Returns
    -------
    list of Fault

    Examples
    --------
    >>> f = Fault("uv", "step", 5.0, 1.0, 2.0, 0)
    >>> len(check_faults("faults", (f,)))
    1
    >>> check_faults("faults", [f, f], {"uv": ["range"]})
    Traceback (most recent call last):
    ...
    ValueError: faults lists uv.range:step:5@1+2 twice (items 0 and 1): a fault is injected and scored once
    """
    name = check_text("name", name)
    want = f"{name} must be a sequence of Fault"
    if isinstance(faults, Fault):
        raise ValueError(f"{want}, got one Fault: give [fault]")
    if isinstance(faults, str | bytes):
        raise ValueError(f"{want}, got the string {faults!r:.80}: read a fault spec with "
                         "parse_spec (xnavlab.mars.faults.schedules.parse_faults for the Mars run)")
    if isinstance(faults, dict) or not hasattr(faults, "__iter__") or \
            isinstance(faults, np.ndarray) and faults.ndim == 0:   # a 0-d array has no items
        raise ValueError(f"{want}, got {type(faults).__name__} {faults!r:.80}")
    items = list(faults)
    for i, f in enumerate(items):
        if not isinstance(f, Fault):
            hint = " (a spec: read it with parse_spec)" if isinstance(f, str) else ""
            raise ValueError(f"{name}[{i}] must be a Fault, got {f!r:.80}{hint}")
    if components is not None:   # a table is checked whole: one the faults are not in is no use
        _check_components(components, items, name)
    seen = {}
    for i, f in enumerate(items):
        if f in seen:
            named = components is not None and f.sensor in components
            raise ValueError(f"{name} lists {_item(f, components if named else None)} twice "
                             f"(items {seen[f]} and {i}): a fault is injected and scored once")
        seen[f] = i
    _check_overlaps(name, items, components)
    return items


def _overlap(a, b):
    """Whether faults ``a`` and ``b`` of one kind act on one component of one sensor at one
    time: a component of ``None`` is every component; a window is ``[onset, end)``, a spike's
    the instant ``onset`` (it acts on the first sample from then on). Faults of different kinds
    on one component combine (a ramp beside a step is the affine fault ``a t + b`` of the
    pseudolite chapter) and are not an overlap."""
    if a.kind != b.kind or a.sensor != b.sensor or None not in (a.component, b.component) and \
            a.component != b.component:
        return False
    if a.kind == "spike" and b.kind == "spike":
        return a.onset == b.onset
    if a.kind == "spike":
        return b.onset <= a.onset < b.end
    if b.kind == "spike":
        return a.onset <= b.onset < a.end
    return a.onset < b.end and b.onset < a.end


def _check_overlaps(name, items, components):
    """One ValueError naming two faults of one kind that act on one component at one time (the
    same fault written two ways, ``uv.range`` and ``uv.0``, or ``uv`` beside ``uv.range``, or two
    overlapping windows): injected, they add up; scored, they are two faults for one event.
    Faults of different kinds on one component combine (:func:`_overlap`). The earliest such
    pair in time is named (:func:`_first_overlap`)."""
    pair = _first_overlap(items)
    if pair is None:
        return
    i, j = sorted(pair)
    named = components if components is not None and items[i].sensor in components else None
    raise ValueError(
        f"{name} items {i} ({_item(items[i], named)}) and {j} ({_item(items[j], named)}) act on "
        f"the same component at the same time: a sensor component takes one fault at a time "
        f"(give their sum as one fault, or windows apart)")


def _reach(f):
    """Where fault ``f`` stops acting, s: its ``end``; a spike's its ``onset`` (one instant)."""
    return f.onset if f.kind == "spike" else f.end


def _first_overlap(items):
    """Indices ``(earlier, later)`` of a pair of ``items`` that overlap (:func:`_overlap`), the
    later one starting first of all such pairs, or None; O(n log n).

    One sweep in order of onset (then reach): among the earlier faults a fault can overlap
    (same sensor and kind, its component or every component), the one reaching furthest
    overlaps it if any does, so each fault is compared with at most two: the furthest of its
    own component and the furthest of ``None`` (every component), or, for a fault on every
    component, the furthest of any component. A window ``[onset, end)`` that is empty in
    floating point (``end == onset``) sorts before the windows from that onset, which keeps
    the sweep exact (it meets no fault starting with it).
    """
    order = sorted(range(len(items)), key=lambda i: (items[i].onset, _reach(items[i]), i))
    furthest = {}   # (sensor, kind, component) -> index; component "any": every one seen
    for j in order:
        f = items[j]
        group = (f.sensor, f.kind)
        keys = [(*group, "any")] if f.component is None else \
            [(*group, f.component), (*group, None)]
        for key in keys:
            i = furthest.get(key)
            if i is not None and _overlap(items[i], f):
                return i, j
        for key in ((*group, f.component), (*group, "any")):
            i = furthest.get(key)
            if i is None or _reach(f) > _reach(items[i]):
                furthest[key] = j
    return None


def fault_mask(t, faults, sensor):
    """Samples of ``t`` at which any fault of ``sensor`` acts.

    Examples
    --------
    >>> fault_mask([0.0, 1.0, 2.0], [Fault("uv", "step", 1.0, 1.0, 1.0)], "uv").tolist()
    [False, True, False]
    """
    t = check_finite_array("t", t)
    faults = check_faults("faults", faults)
    sensor = check_text("sensor", sensor)
    mask = np.zeros(t.shape, dtype=bool)
    for f in faults:
        if f.sensor == sensor:
            mask |= f.active(t)
    return mask


def inject(t, z, faults, sensor, rng=None):
    """Return a copy of measurements ``z`` with the faults of ``sensor`` applied.

    Parameters
    ----------
    t : array_like, shape (n,)
        Sample times, s, strictly increasing.
    z : array_like, shape (n,) or (n, m)
        Fault-free measurements of ``sensor`` (one row per sample, one column per component).
    faults : sequence of Fault
        The schedule; faults of other sensors are ignored. Faults are applied in
        order, so a ``stuck`` fault freezes whatever earlier faults produced.
    sensor : str
        Which sensor ``z`` belongs to.
    rng : numpy.random.Generator or int, optional
        Source of the extra noise of ``noise`` faults.

    Returns
    -------
    ndarray, same shape as ``z``

    Examples
    --------
    >>> t = np.arange(5.0)
    >>> inject(t, np.zeros(5), [Fault("uv", "ramp", 2.0, onset=2.0)], "uv").tolist()
    [0.0, 0.0, 0.0, 2.0, 4.0]
    """
    t = check_finite_array("t", t)
    z = check_finite_array("z", z).copy()
    if t.ndim != 1:
        raise ValueError(f"t must be a 1-D array of sample times, got shape {t.shape}")
    # lengths that disagree: the shorter is named (a series cut short is the likelier slip)
    if z.ndim == 0 or z.shape[0] < t.shape[0]:
        raise ValueError(f"z must have shape (n,) or (n, m) with n = len(t) = {t.size}, got shape {z.shape}")
    if z.shape[0] > t.shape[0]:
        raise ValueError(f"t must hold one time per row of z ({z.shape[0]}), got {t.size}")
    if z.ndim > 2:  # the components of a sample are one axis (a fault's component indexes it)
        raise ValueError(f"z must have shape (n,) or (n, m) with n = len(t) = {t.size}, got "
                         f"shape {z.shape}")
    check_increasing("t", t)  # a stuck fault holds the value before its onset, in time order
    faults = check_faults("faults", faults)
    sensor = check_text("sensor", sensor)
    rng = make_rng(rng)
    out = z.reshape(len(t), int(np.prod(z.shape[1:]))).copy()  # no sample: nothing to inject
    for i, f in enumerate(faults):
        if f.sensor != sensor:
            continue
        cols = _columns(f, out.shape[1], i)
        mask = f.active(t)
        if not mask.any():
            continue
        if f.kind in ("step", "spike"):
            out[np.ix_(mask, cols)] += f.magnitude
        elif f.kind == "ramp":
            reach = abs(f.magnitude) * float(t[mask].max() - f.onset)
            if reach > MAX_SIZE:
                raise ValueError(f"faults[{i}]: a ramp of {f.magnitude:g} per s from "
                                 f"{f.onset:g} s reaches {reach:.3g} by t = {t[mask].max():g} s, "
                                 f"beyond MAX_SIZE = {MAX_SIZE:g} (the measurement's SI unit)")
            out[np.ix_(mask, cols)] += f.magnitude * (t[mask] - f.onset)[:, None]
        elif f.kind == "noise":
            out[np.ix_(mask, cols)] += rng.normal(0.0, f.magnitude, (mask.sum(), len(cols)))
        else:  # stuck
            before = np.flatnonzero(t < f.onset)
            frozen = out[before[-1], cols] if before.size else out[np.flatnonzero(mask)[0], cols]
            out[np.ix_(mask, cols)] = frozen
    return out.reshape(z.shape)


def _columns(fault, m, i):
    if fault.component is None:
        return np.arange(m)
    if fault.component >= m:
        raise ValueError(f"faults[{i}]: component must be in [0, {m - 1}] for sensor "
                         f"{fault.sensor!r} (the columns of z), got {fault.component}")
    return np.array([fault.component])


# ONSET and DURATION are split at the first '+' that is not an exponent sign (1e+06).
_SPEC = re.compile(
    r"^(?P<sensor>[A-Za-z_][\w-]*)(?:\.(?P<comp>[\w-]+))?:(?P<kind>\w+):(?P<mag>[^@]+)"
    r"@(?P<onset>(?:[^+]|(?<=[eE])\+)+)\+(?P<dur>.+)$"
)


# A number as a spec writes it: plain decimal text (what float() reads, without 1_0, blanks)
_NUMBER = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?|[+-]?(inf|infinity|nan)", re.I | re.A)


def parse_spec(spec, components):
    """Parse ``SENSOR[.COMPONENT]:KIND:MAGNITUDE@ONSET+DURATION[,...]`` into faults.

    Parameters
    ----------
    spec : str
        Comma-separated fault items. COMPONENT is a name or an index; none means
        every component. DURATION may be ``inf``.
    components : dict of str to sequence of str
        For each known sensor, the names of its measurement components in order.

    Returns
    -------
    list of Fault

    Raises
    ------
    ValueError
        Leading with ``spec`` and naming the bad item and what is wrong with it (or with
        ``components``: an empty table, or one that is not a dict of name lists).

    Examples
    --------
    >>> comps = {"uv": ["range", "ux", "uy", "uz"], "xnav": ["0", "1", "2", "3"]}
    >>> f, = parse_spec("uv.range:step:5000@700000+3000", comps)
    >>> (f.sensor, f.component, f.kind, f.magnitude, f.onset, f.duration)
    ('uv', 0, 'step', 5000.0, 700000.0, 3000.0)
    """
    if not isinstance(spec, str) or not spec.strip():
        raise ValueError(f"spec must be a non-empty string of fault items "
                         f"SENSOR[.COMPONENT]:KIND:MAGNITUDE@ONSET+DURATION, got {spec!r:.80}")
    _check_components(components)
    faults = []
    for item in spec.split(","):
        item = item.strip()
        m = _SPEC.match(item)
        if not m:
            raise ValueError(
                f"spec: bad fault item {item!r}: expected SENSOR[.COMPONENT]:KIND:MAGNITUDE@ONSET+DURATION"
            )
        faults.append(_fault_from_match(item, m, components))
    return check_faults("spec", faults, components)


def _check_components(components, faults=(), name="faults"):
    """Component names per sensor: a non-empty dict of str to a non-empty list or tuple of str,
    naming every sensor of ``faults`` and holding each one's component, else one ValueError
    naming ``components`` (or the fault, ``name[i]``, it has no names for: a table the faults
    are not in would be ignored)."""
    want = "components must be a dict of sensor name to its component names (a list of str)"
    if not isinstance(components, dict):
        raise ValueError(f"{want}, got {type(components).__name__} {components!r:.80}")
    if not components:
        raise ValueError(f"{want}, got an empty dict (no sensor is known)")
    for k, v in components.items():
        if not isinstance(k, str) or not k:
            raise ValueError(f"{want}, got the key {k!r:.80}")
        if not isinstance(v, list | tuple) or not v or \
                not all(isinstance(c, str) and c for c in v):
            raise ValueError(f"components[{k!r}] must be a non-empty list of component names "
                             f"(str), got {v!r:.80}")
    for i, f in enumerate(faults):
        if f.sensor not in components:
            raise ValueError(f"{name}[{i}]: sensor {f.sensor!r} has no component names in components "
                             f"(known: {', '.join(sorted(components))})")
        n = len(components[f.sensor])
        if f.component is not None and f.component >= n:
            raise ValueError(f"{name}[{i}]: component must be in [0, {n - 1}] for sensor {f.sensor!r} "
                             f"(components[{f.sensor!r}]: {', '.join(components[f.sensor])}), got "
                             f"{f.component}")


def _fault_from_match(item, m, components):
    sensor = m["sensor"]
    if sensor not in components:
        known = ", ".join(sorted(components))
        raise ValueError(f"spec: bad fault item {item!r}: unknown sensor {sensor!r} (known: {known})")
    names = list(components[sensor])
    comp = m["comp"]
    index = None
    if comp is not None:
        if comp in names:
            index = names.index(comp)
        elif comp.isdigit() and int(comp) < len(names):
            index = int(comp)
        else:
            raise ValueError(
                f"spec: bad fault item {item!r}: component {comp!r} of {sensor} must be one of "
                f"{', '.join(names)} or an index in [0, {len(names) - 1}]"
            )
    if m["kind"] not in KINDS:
        raise ValueError(f"spec: bad fault item {item!r}: kind must be one of {', '.join(KINDS)}")
    values = {}
    for key in ("mag", "onset", "dur"):
        if not _NUMBER.fullmatch(m[key]):  # float() would also read 1_0 as 10, as no flag does
            raise ValueError(f"spec: bad fault item {item!r}: {m[key]!r} is not a number (plain "
                             f"decimals: 25000, 1e-5, inf)")
        values[key] = float(m[key])
    try:
        return Fault(sensor, m["kind"], values["mag"], values["onset"], values["dur"], index)
    except ValueError as exc:
        raise ValueError(f"spec: bad fault item {item!r}: {exc}") from None


def format_spec(faults, components):
    """Inverse of :func:`parse_spec` (component names where known): parsed back, the text gives
    the same faults, every number to the last bit (``%g`` where that is exact, else ``repr``).

    Examples
    --------
    >>> format_spec([Fault("uv", "step", 5.0, 1.0, 2.0, 0)], {"uv": ["range"]})
    'uv.range:step:5@1+2'
    """
    faults = check_faults("faults", faults)
    if not faults:   # "" would not parse back: parse_spec refuses an empty spec
        raise ValueError("faults must hold at least one Fault (an empty schedule has no spec)")
    _check_components(components, faults, "faults")  # each fault's sensor and component named
    return ",".join(_item(f, components) for f in faults)


def _number(x):
    """A number as a spec writes it: ``%g`` when that reads back exactly, else the shortest text
    that does (``repr``), so that :func:`parse_spec` gives the same fault back."""
    text = f"{x:g}"
    return text if float(text) == x else repr(float(x))


def _item(f, components):
    """One fault in the spec form; its component by name (``components``) or index (None)."""
    if f.component is None:
        comp = ""
    elif components is None:
        comp = f".{f.component}"
    else:
        comp = "." + list(components[f.sensor])[f.component]
    return (f"{f.sensor}{comp}:{f.kind}:{_number(f.magnitude)}@{_number(f.onset)}"
            f"+{_number(f.duration)}")
