"""Checks of a Mars run's options: the inputs object, the overrides, the ``active`` flags and
the NIS ``gate`` (review 35j: a dict, a list, floats or a scalar gave Python's or numpy's
message, or were cast without a word).

Plumbing of :mod:`xnavlab.mars.navigation` (imported by
:mod:`xnavlab.mars.navigation.scenarios`); not part of the public API.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from xnavlab.core.validate import check_finite_array, check_instance, check_shape, check_text, shown

__all__ = ["check_scenario", "check_names", "check_object", "check_extra", "check_active",
           "check_gate", "check_beta"]


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
    if none of its names is one of the run's own arrays ``taken``, else one ValueError."""
    clash = [k for k in extra if k in taken]
    if clash:
        raise ValueError(f"extra[{clash[0]!r}] takes a name the npz already uses (taken: "
                         f"{', '.join(taken)}): give the array another name")
    return extra


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
