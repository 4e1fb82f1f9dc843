"""Checks of a Mars run's options: the inputs object, the overrides, the ``active`` flags and
the NIS ``gate`` (review 35j: a dict, a list, floats or a scalar gave Python's or numpy's
message, or were cast without a word).

Plumbing of :mod:`xnavlab.mars.navigation` (imported by
:mod:`xnavlab.mars.navigation.scenarios`); not part of the public API.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from xnavlab.core.userfiles import as_path, output_path
from xnavlab.core.validate import (
    check_choice,
    check_finite_array,
    check_instance,
    check_real,
    check_shape,
    check_text,
    shown,
)

__all__ = ["RUN_BACKENDS", "check_scenario", "check_names", "check_object", "check_inputs",
           "check_run", "check_extra", "check_npz", "check_active", "check_gate", "check_beta"]

#: The labels ``run()`` gives a MarsRun's ``backend`` (the UKF runs on numpy only).
RUN_BACKENDS = ("numba", "numpy", "numpy-ukf")


def check_scenario(name, value, kind):
    """``value`` if it is a ``kind`` (MarsScenario), ``kind()`` for None, else one ValueError
    naming ``name`` (a dict of fields is not a scenario: ``kind(**fields)``)."""
    check_text("name", name)  # the caller's parameter, for the message
    if value is None:
        return kind()
    if not isinstance(value, kind):
        hint = f" (build one with {kind.__name__}(**fields))" if isinstance(value, dict) else ""
        raise ValueError(f"{name} must be a {kind.__name__}, got {type(value).__name__} "
                         f"{shown(value)}{hint}")
    return value


def check_names(name, value, names, owner):
    """``value`` if it is a mapping whose keys are all in ``names`` (the fields of ``owner``),
    else one ValueError naming ``name`` or the unknown keys and listing ``names``."""
    if not isinstance(value, Mapping):
        raise ValueError(f"{name} must be a dict of {owner} fields ({{name: value}}), got "
                         f"{type(value).__name__} {shown(value)}")
    unknown = sorted(repr(k) if not isinstance(k, str) else k for k in value if k not in names)
    if unknown:
        raise ValueError(f"unknown override {', '.join(unknown)}: not a field of {owner} "
                         f"(the fields: {', '.join(names)})")
    return value


def check_object(name, value, kind):
    """``value`` if it is a ``kind`` (:class:`~xnavlab.mars.navigation.scenarios.Inputs`), else one
    ValueError saying what to pass."""
    return check_instance(name, value, kind, f"an {kind.__name__} from prepare()")


def check_extra(extra, taken):
    """``extra`` (the named arrays of :meth:`~xnavlab.mars.navigation.scenarios.MarsRun.save_npz`)
    if each name is an identifier not among the run's own arrays ``taken`` and each value an
    array of numbers, bools or strings (what ``np.load`` reads back without pickle), else one
    ValueError naming ``extra['name']`` (review 35o 5.2: a dict or None was pickled, a name
    ``''`` or ``'a/b'`` written as ``.npy`` or a folder inside the npz)."""
    clash = [k for k in extra if k in taken]
    if clash:
        raise ValueError(f"extra[{clash[0]!r}] takes a name the npz already uses (taken: "
                         f"{', '.join(taken)}): give the array another name")
    for key, value in extra.items():
        if not key.isidentifier():
            raise ValueError(f"extra[{key!r}]: an array name must be an identifier (letters, "
                             f"digits, _; not a path or empty), got {key!r}")
        kind = np.asarray(value).dtype.kind if not isinstance(value, dict | set) else "O"
        if kind not in "biufcUS" or np.ma.isMaskedArray(value):
            raise ValueError(f"extra[{key!r}] must be an array of numbers, bools or strings "
                             f"(np.load reads nothing else without pickle), got "
                             f"{type(value).__name__} {shown(value)}: store a dict as JSON "
                             f"text, np.array(json.dumps(d))")
    return extra


def check_npz(path, extra, taken):
    """``path`` (a new ``.npz`` file, checked by :func:`~xnavlab.core.userfiles.output_path`,
    its folder made) once ``path``'s name and ``extra`` (:func:`check_extra`) are checked."""
    if not str(as_path(path, "path")).endswith(".npz"):
        raise ValueError(f"path must name a file ending in .npz, got {str(path)!r}")
    check_extra(extra, taken)
    return output_path(path, "path")


def check_active(active, n, subsystems):
    """``active`` as a C-contiguous bool array (n, ns): True/False flags or 1/0 numbers (as
    :mod:`xnavlab.core.federated` takes them), not 0.5 cast to True."""
    ns = len(subsystems)
    if active is None:
        return np.ones((n, ns), dtype=bool)
    if np.ma.is_masked(active):  # np.asarray would use the masked flags (review 35m (5) 1)
        raise ValueError("active has masked entries (no flag to use: fill or drop them)")
    try:
        arr = np.asarray(active)
    except (TypeError, ValueError):  # a ragged list
        arr = np.asarray(None)
    want = (f"active must hold True/False flags (or 1/0), shape ({n}, {ns}) (epochs x "
            f"subsystems {list(subsystems)})")
    if arr.dtype.kind not in "biuf":
        raise ValueError(f"{want}, got {type(active).__name__} {shown(active)}")
    if arr.shape != (n, ns):
        raise ValueError(f"{want}, got shape {arr.shape}")
    if arr.dtype.kind != "b":
        bad = ~((arr == 0) | (arr == 1))
        if bad.any():
            k, i = (int(v) for v in np.argwhere(bad)[0])
            raise ValueError(f"{want}, got active[{k}, {i}] = {shown(arr[k, i].item())} (a flag "
                             f"is not cast from another number)")
    return np.ascontiguousarray(arr, dtype=bool)


def check_gate(gate, subsystems):
    """``gate`` as ns NIS thresholds (non-negative, inf for none; one number is taken for a
    run of one subsystem), inf for all by default."""
    ns = len(subsystems)
    if gate is None:
        return np.full(ns, np.inf)
    want = (f"gate must hold one NIS threshold a subsystem, shape ({ns},) for subsystems "
            f"{list(subsystems)} (numbers, inf for no gate)")
    try:
        arr = check_finite_array("gate", gate, finite=False)
    except ValueError:
        raise ValueError(f"{want}, got {type(gate).__name__} {shown(gate)}") from None
    if arr.ndim == 0 and ns == 1:
        arr = arr.reshape(1)
    if arr.shape != (ns,):
        raise ValueError(f"{want}, got "
                         f"{'the number ' + shown(gate) if arr.ndim == 0 else f'shape {arr.shape}'}")
    bad = np.isnan(arr) | (arr < 0)
    if bad.any():
        i = int(np.argmax(bad))
        raise ValueError(f"gate[{i}] must be a non-negative NIS threshold (inf for no gate; "
                         f"subsystem {subsystems[i]}), got {shown(float(arr[i]))}")
    return arr.astype(float)


def check_beta(beta, subsystems):
    """``beta`` as ns positive information-sharing factors (of
    :func:`~xnavlab.mars.navigation.scenarios.run_options`; a local filter holds ``P0 / beta``)."""
    arr = check_shape("beta", beta, (len(subsystems),), f"one a subsystem of {list(subsystems)}")
    if not np.all(arr > 0.0):
        raise ValueError(f"beta must hold positive information-sharing factors, got {arr.tolist()}")
    return arr


def _finite(a):
    """Whether every entry of the float array ``a`` is finite: a finite sum says so (a NaN or
    inf carries into it) at a fifth of ``np.isfinite``'s cost; an overflow looks entry by entry."""
    with np.errstate(over="ignore", invalid="ignore"):
        return bool(np.isfinite(np.sum(a))) or bool(np.isfinite(a).all())


def _array(name, value, shape, kind="f", finite=True):
    """``value`` if it is a numpy array of ``kind`` (float64 or integer) and ``shape`` (None:
    any length), finite (unless not ``finite``: NaN marks "none"), else one ValueError naming
    ``name`` (nothing is copied or cast)."""
    want = "a float64" if kind == "f" else "an integer"
    ok = isinstance(value, np.ndarray) and (value.dtype == np.float64 if kind == "f"
                                            else value.dtype.kind in "iu")
    if not ok:
        got = f"a {value.dtype} array of shape {value.shape}" if isinstance(value, np.ndarray) \
            else f"{type(value).__name__} {shown(value)}"
        raise ValueError(f"{name} must be {want} array as prepare() makes it, got {got}")
    if value.ndim != len(shape) or any(w is not None and w != s
                                       for w, s in zip(shape, value.shape, strict=True)):
        want = ", ".join("m" if w is None else str(w) for w in shape)
        raise ValueError(f"{name} must have shape ({want}{',' if len(shape) == 1 else ''}), got "
                         f"shape {value.shape}")
    if finite and kind == "f" and value.size and not _finite(value):
        bad = tuple(int(i) for i in np.argwhere(~np.isfinite(value))[0])
        raise ValueError(f"{name} must contain only finite numbers, got {name}"
                         f"[{', '.join(map(str, bad))}] = {value[bad]}")
    return value


def check_inputs(name, inputs, kind, subsystems_all):
    """``inputs`` if it is a ``kind`` (:class:`~xnavlab.mars.navigation.scenarios.Inputs`) whose
    arrays agree with each other, else one ValueError naming ``inputs.<field>`` (review 35o S:
    an Inputs edited with ``dataclasses.replace`` gave an IndexError, ekf_update's names, or a
    compiled kernel reading past a shortened ``z``). Checked: ``times`` (n,) increasing,
    ``truth`` (n, 6), ``x0`` (6,), ``meas_idx`` (n, ns) in [-1, rows), the keys of ``z`` and
    ``t_meas`` the scenario's subsystems, each ``z[s]`` exactly the rows ``meas_idx`` uses and
    its sensor's columns, ``xnav_bodies`` one row per XNAV measurement, ``record`` increasing
    in [0, n); the float arrays finite. Nothing is copied or changed (about 1 % of a run).
    ``subsystems_all``: the names the sensors must hold (the compiled kernel reads all three).
    """
    check_object(name, inputs, kind)
    sc = inputs.scenario
    subs = tuple(sc.subsystems)
    ns = len(subs)
    times = _array(f"{name}.times", inputs.times, (None,))
    n = times.size
    if n < 1:
        raise ValueError(f"{name}.times must hold at least one epoch, got none")
    if n > 1 and not np.all(times[1:] > times[:-1]):
        k = int(np.argmax(~(np.diff(times) > 0))) + 1
        raise ValueError(f"{name}.times must increase, got times[{k}] = {times[k]!r} after "
                         f"times[{k - 1}] = {times[k - 1]!r}")
    _array(f"{name}.truth", inputs.truth, (n, 6))
    _array(f"{name}.x0", inputs.x0, (6,))
    idx = _array(f"{name}.meas_idx", inputs.meas_idx, (n, ns), "i")
    sens = inputs.sensors
    if not isinstance(sens, dict) or not all(s in sens for s in subsystems_all):
        raise ValueError(f"{name}.sensors must be the dict of sensors prepare() makes (keys "
                         f"{list(subsystems_all)}), got {shown(sens)}")
    for field in ("z", "t_meas"):
        d = getattr(inputs, field)
        if not isinstance(d, dict) or sorted(d) != sorted(subs):
            keys = sorted(map(str, d)) if isinstance(d, dict) else type(d).__name__
            raise ValueError(f"{name}.{field} must have one entry a subsystem of the scenario "
                             f"{list(subs)}, got {keys}")
    cols = {"xnav": sens["xnav"].dim, "uv": 4, "cns": sens["cns"].dim}
    for i, s in enumerate(subs):
        col = idx[:, i]
        if col.size and col.min() < -1:
            k = int(np.argmin(col))
            raise ValueError(f"{name}.meas_idx[{k}, {i}] must be -1 (no {s} measurement) or a row "
                             f"of {name}.z[{s!r}], got {int(col[k])}")
        rows = int(col.max()) + 1 if col.size else 0
        z = _array(f"{name}.z[{s!r}]", inputs.z[s], (None, cols[s]))
        if z.shape[0] != rows:
            raise ValueError(f"{name}.z[{s!r}] has {z.shape[0]} rows; {name}.meas_idx[:, {i}] uses "
                             f"{rows} (rows 0..{rows - 1}): one row a measurement")
        _array(f"{name}.t_meas[{s!r}]", inputs.t_meas[s], (rows,))
    m_x = inputs.z["xnav"].shape[0] if "xnav" in subs else None
    bodies = inputs.xnav_bodies
    if not isinstance(bodies, tuple) or len(bodies) != 2:
        raise ValueError(f"{name}.xnav_bodies must be a tuple (Mars, Sun positions), got "
                         f"{shown(bodies)}")
    for j in range(2):  # Mars, Sun positions at the XNAV epochs
        _array(f"{name}.xnav_bodies[{j}]", bodies[j], (m_x, 3))
    rec = _array(f"{name}.record", inputs.record, (None,), "i")
    if rec.size == 0:
        raise ValueError(f"{name}.record must hold at least one epoch index, got none")
    if rec.min() < 0 or rec.max() >= n:
        j = int(np.argmax((rec < 0) | (rec >= n)))
        raise ValueError(f"{name}.record must hold epoch indices in [0, {n - 1}] (n = {n} "
                         f"epochs), got {name}.record[{j}] = {int(rec[j])}")
    if rec.size > 1 and not np.all(np.diff(rec) > 0):
        j = int(np.argmax(~(np.diff(rec) > 0))) + 1
        raise ValueError(f"{name}.record must increase (each epoch once), got {name}.record[{j}] "
                         f"= {int(rec[j])} after {int(rec[j - 1])}")
    _check_layout(name, inputs)
    return inputs


def _check_layout(name, inputs):
    """Refuse an array the compiled kernel reads that is not C-contiguous (review 35q Q12): a
    strided view or a Fortran-ordered array is a new argument type for numba, which compiled
    another kernel for it (80 s, without the first-compile notice) instead of running in 0.2 s."""
    arrays = {"times": inputs.times, "truth": inputs.truth, "x0": inputs.x0,
              "meas_idx": inputs.meas_idx, "record": inputs.record,
              **{f"z[{s!r}]": z for s, z in inputs.z.items()},
              **{f"t_meas[{s!r}]": t for s, t in inputs.t_meas.items()},
              **{f"xnav_bodies[{j}]": b for j, b in enumerate(inputs.xnav_bodies)}}
    for label, arr in arrays.items():
        if not arr.flags.c_contiguous:
            raise ValueError(f"{name}.{label} must be a C-contiguous array as prepare() makes it "
                             f"(numba would compile another kernel for this layout, minutes), got a "
                             f"{'Fortran-ordered' if arr.flags.f_contiguous else 'strided'} array: "
                             f"pass np.ascontiguousarray({name}.{label})")


def check_run(run, scenario_kind):
    """``run`` (a :class:`~xnavlab.mars.navigation.scenarios.MarsRun`) if its fields agree with
    each other, else one ValueError naming ``MarsRun.<field>`` (review 35o C3: a run edited with
    ``dataclasses.replace`` failed later in ``metrics()`` or ``summary()`` with numpy's words).
    Checked: ``scenario`` a ``scenario_kind``; ``t`` (nr,) increasing; ``x``, ``truth`` (nr, 6),
    ``P`` (nr, 6, 6), ``x_local``, ``P_local_diag`` (nr, ns, 6), finite float64; ``times`` (n,)
    finite, from the scenario's ``t0`` to within one sample interval of its span (the
    scenario the run ran; review 35p P12), ``nis`` (n, ns) float64 (NaN where none), ``flags``
    (n, ns) integer in [0, 3];
    ``backend`` one of :data:`RUN_BACKENDS`; ``wall_time`` finite, >= 0 s. Nothing is copied."""
    if not isinstance(run.scenario, scenario_kind):
        raise ValueError(f"MarsRun.scenario must be a {scenario_kind.__name__}, got "
                         f"{type(run.scenario).__name__} {shown(run.scenario)}")
    ns = len(run.scenario.subsystems)
    t = _array("MarsRun.t", run.t, (None,))
    nr = t.size
    if nr < 1:
        raise ValueError("MarsRun.t must hold at least one recorded epoch, got none")
    if nr > 1 and not np.all(t[1:] > t[:-1]):
        raise ValueError("MarsRun.t must increase (the recorded epochs, s TDB past J2000)")
    for field, shape in (("x", (nr, 6)), ("truth", (nr, 6)), ("P", (nr, 6, 6)),
                         ("x_local", (nr, ns, 6)), ("P_local_diag", (nr, ns, 6))):
        _array(f"MarsRun.{field}", getattr(run, field), shape)
    times = _array("MarsRun.times", run.times, (None,))
    n, sc = times.size, run.scenario
    last = max(sc.dt_uv, sc.dt_cns, sc.dt_xnav)  # the last epoch: within one sample of the end
    if n < 1 or times[0] != sc.t0 or not sc.span - last <= times[-1] - sc.t0 <= sc.span + 1e-6:
        span = (times[-1] - times[0]) / 86400.0 if n else 0.0
        raise ValueError(f"MarsRun.scenario must be the scenario the run ran: its days = "
                         f"{sc.days:g} and t0 = {sc.t0:.9g} s, the run's epochs {span:g} days "
                         f"from {times[0] if n else float('nan'):.9g} s")
    _array("MarsRun.nis", run.nis, (n, ns), finite=False)
    flags = _array("MarsRun.flags", run.flags, (n, ns), "i")
    if flags.size and (flags.min() < 0 or flags.max() > 3):
        raise ValueError("MarsRun.flags must hold 0 (no measurement), 1 (updated), 2 (gated) or "
                         f"3 (switched out), got values in [{flags.min()}, {flags.max()}]")
    check_choice("MarsRun.backend", run.backend, RUN_BACKENDS)
    check_real("MarsRun.wall_time", run.wall_time, 0.0)
    return run
