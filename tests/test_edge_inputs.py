"""Every input is used or refused (issue 35): edge values in the public examples.

Each doctest example of a public function or class (the examples ``tests/example_calls.py``
collects) is run again with one argument at a time, positional or keyword, replaced by each of
:func:`edge_values`: a bool, ``-0.0``, an empty list, a one-element list, a list mixing numbers
and a bool, a 0-d array and, for a positive number, zero, the subnormals just below and above
it, and for a number in (0, 1] also 1 and the double after 1. A changed call passes when

* it raises a ``ValueError`` that names the replaced parameter before any other parameter of
  the call (the user reads first the name of what they must change), or
* it returns a result whose numbers are finite, with no warning, and the value was one a user
  may mean: a bool or a list holding one is never a number (it must be refused), and an empty
  list is refused unless the callable maps each element of its input (:data:`EMPTY_OK`).

Anything else fails: a ``TypeError``, ``AttributeError`` or ``IndexError`` from inside (a
traceback to the user), numpy's own message, a warning, a NaN. A test collects the failures of
every edge value of one argument and reports them together. :data:`JOINT` lists the refusals
that rightly lead with another parameter (a joint condition whose other member is named first),
each with its reason.

Runtime (quiet machine, ``pytest -p no:randomly tests/test_edge_inputs.py``): see the closing
line of the module's run in ``benchmarks``-free terms: about a minute for some 1,100 arguments.
"""

import ast
import inspect

import numpy as np
import pytest
from example_calls import (
    evaluate,
    example_calls,
    finite,
    first_name,
    outcome,
    parameter_names,
    plumbing,
    public_doctests,
    state,
    unmodified,
)

#: ``test name:parameter`` -> why an empty list is a valid input: the result holds one entry per element
#: (an empty input, an empty result), or an empty list means something (no faults).
EMPTY_OK = {
    "xnavlab.robust.ephemeris_error.ephemeris_error:t": "one error vector per epoch",
    "xnavlab.robust.ephemeris_error.growth_profile:s": "one profile value per element of s",
    "xnavlab.robust.ephemeris_error.injected_error:t": "one error per epoch",
    "xnavlab.robust.ephemeris_error.ephemeris_drift:t": "one drift per epoch",
    "xnavlab.robust.sensitivity.ukf_sensitivity:sizes": "one RMSE per size",
    "xnavlab.attitude.motion.truth_rate:t": "one rate per time",
    "xnavlab.attitude.montecarlo.isolation_table:rows": "a table of no rows is its header (documented)",
    "xnavlab.attitude.simulation.simulate:faults": "faults=[] is a fault-free run (the default is ())",
    "xnavlab.plins.ins.earth_radii:lat": "one pair of radii per latitude",
    "xnavlab.plins.pseudolites.geodetic_to_ecef:lat": "one ECEF point per element, shape (0, 3)",
    "xnavlab.plins.pseudolites.geodetic_to_ecef:lon": "one ECEF point per element, shape (0, 3)",
    "xnavlab.plins.pseudolites.geodetic_to_ecef:h": "one ECEF point per element, shape (0, 3)",
    "xnavlab.plins.parity.fuzzy.triangular:x": "one membership per x",
    "xnavlab.plins.parity.fuzzy.partition_memberships:x": "one row of memberships per x",
    "xnavlab.plins.parity.identification.fault_signature:t_window": "one row of M per sample time",
    "xnavlab.plins.pseudolites.simulate_pseudoranges:faults": "faults=[] is a fault-free flight",
    "xnavlab.plins.parity.diagnosis.diagnose_flight:faults": "faults=[] is a fault-free flight",
    "xnavlab.mars.faults.fault_tolerance.merge_events:events": "no events: nothing to merge",
    "xnavlab.mars.faults.schedules.check_armed:faults": "no faults: nothing to arm for",
    "xnavlab.mars.faults.schedules.check_event_list:events": "a check item by item: no alarms",
    "xnavlab.mars.faults.schedules.fault_detection_delays:faults": "one delay per fault",
    "xnavlab.mars.faults.schedules.score_faults:faults": "one record per fault",
    "xnavlab.mars.faults.schedules.score_faults:isolations": "isolations=() is the default",
    "xnavlab.mars.models.dynamics.model_difference:third_bodies": "the point mass alone (the "
    "slider's Sun and Jupiter off)",
    "xnavlab.mars.models.optics.apparent_radius:rho": "one radius per range",
    "xnavlab.mars.models.optics.gauss_markov:w": "one output sample per input sample",
    "xnavlab.mars.models.optics.radius_range_sigma:rho": "one sigma per range",
    "xnavlab.mars.models.optics.range_from_radius:alpha": "one range per apparent radius",
    "xnavlab.mars.navigation.plots.plot_details:onsets_days": "one line per onset; default ()",
    "xnavlab.mars.navigation.plots.plot_error_curves:faults": "one band per fault; default ()",
    "xnavlab.mars.navigation.plots.plot_error_curves:isolations": "one line per isolation; default ()",
    "xnavlab.mars.studies.campaigns.summarise_consistency:runs": "no run that ended well: no row",
    "xnavlab.mars.studies.campaigns.summarise_detectors:runs": "no run: no row (its example)",
    "xnavlab.mars.studies.roc.curve_csv:rows": "one line per row: the header alone (its example)",
    "xnavlab.mars.studies.trials.detector_table:records": "one row per record",
    "xnavlab.mars.studies.trials.marked_cells:rows": "one row per row (its example)",
    "xnavlab.mars.timing.photon_fix.template_density:phases": "one density per phase",
    "xnavlab.mars.timing.photon_fix.log_likelihood:offsets_m": "one log-likelihood per offset",
    "xnavlab.mars.timing.pulsars.phase:t": "one phase per time",
    "xnavlab.mars.timing.pulsars.profile:ph": "one value per phase",
    "xnavlab.mars.timing.timing_bound.profile_derivative:ph": "one value per phase",
    "xnavlab.mars.timing.timing_terms.directions_from_sun:angle_deg": "one direction per angle",
    "xnavlab.mars.timing.timing_terms.shapiro_by_angle:angle_deg": "one delay per angle",
    "xnavlab.mars.timing.toa.delays_at:t": "one row per epoch, shape (0, 4)",
    "xnavlab.core.distributions.chi2_cdf:x": "one probability per x",
    "xnavlab.core.ephemeris.state:t": "one state per epoch",
    "xnavlab.core.ephemeris.position:t": "one position per epoch",
    "xnavlab.core.ephemeris.jd_from_t:t": "one date per epoch",
    "xnavlab.core.ephemeris.t_from_jd:jd": "one epoch per date",
    "xnavlab.core.faults.check_faults:faults": "no faults: the fault-free schedule",
    "xnavlab.core.faults.inject:faults": "no faults: z unchanged",
    "xnavlab.core.faults.fault_mask:faults": "no faults: an all-False mask",
    "xnavlab.core.faults.fault_mask:t": "one flag per epoch",
    "xnavlab.core.detection.plots.plot_fault_detection:faults": "no fault: the false-alarm case",
    "xnavlab.core.montecarlo.run_tasks:params": "one result per task",
}

#: ``test name:parameter`` -> why a refusal of an edge value of it names another parameter first.
JOINT = {
    "xnavlab.plins.parity.fuzzy.triangular:left": "left <= center <= right: center is checked "
    "against left, and either may be the wrong one",
    "xnavlab.plins.pseudolites.pdop:lat": "lat = 0 moves the receiver thousands of km from the "
    "sites: the geometry's condition belongs to receiver and sites together",
    "xnavlab.plins.pseudolites.pdop:lon": "as for lat",
    "xnavlab.core.federated.share_factors:beta": "a length clash of beta and active: active is "
    "checked against beta, and active=[1.0] leads with active",
    "xnavlab.mars.models.force_models.accelerations:t": "t and r disagree in length: either may "
    "be wrong; r is checked against t, checked first",
    "xnavlab.mars.models.model_noise.unmodelled_acceleration:t": "as accelerations: states is "
    "checked against t",
    "xnavlab.mars.navigation.plots.plot_details:t_days": "x is checked against t_days",
    "xnavlab.mars.navigation.scenarios.check_scenario:value": "a check helper: it leads with the "
    "name it is given, as the validate checks do",
}

#: ``test name:parameter`` -> why that argument is not tried.
SKIP = {
    "xnavlab.mars.navigation.linearisation.ekf_and_ukf:days": "days = 1 is a valid day-long EKF "
    "and UKF run (minutes, past LIMIT_S); the other values are tried by tests/mars/navigation",
    # a row's shown values: any object, shown as text (show); the reproductions pass numbers,
    # words, bools (ch08: "every subsystem connected", yes or no) and arrays (ch12's estimates)
    "xnavlab.verdicts.check_true:paper": "the paper's value as shown: any object (words, a number)",
    "xnavlab.verdicts.check_true:ours": "our value as shown: any object (a bool is a yes or no)",
    "xnavlab.verdicts.check_sanity:expected": "what we expect, as shown: any object",
    "xnavlab.verdicts.check_sanity:ours": "our value as shown: any object (a bool is a yes or no)",
    "xnavlab.verdicts.check_measure:ours": "our measurement as shown: any object (ch08 passes a "
    "bool, ch12 an array)",
    "xnavlab.verdicts.show:x": "any value, as a table shows it (show(True) is 'True')",
}

BOOLISH = ("True", "[1.0, True, 0.0]")


def edge_values(orig):
    """(label, value) pairs to put in place of the argument ``orig``."""
    out = []
    if not isinstance(orig, bool | np.bool_):
        out.append(("True", True))
    out += [
        ("-0.0", -0.0),
        ("[]", []),
        ("[1.0]", [1.0]),
        ("[1.0, True, 0.0]", [1.0, True, 0.0]),
        ("np.array(1.0)", np.array(1.0)),
    ]
    if isinstance(orig, int | float | np.integer | np.floating) and not isinstance(orig, bool | np.bool_):
        if orig > 0:
            out += [("0.0", 0.0), ("-5e-324", -5e-324), ("5e-324", 5e-324)]
            if orig <= 1:
                out += [("1.0", 1.0), ("nextafter(1, 2)", float(np.nextafter(1.0, 2.0)))]
    return out


def _slot_name(node, slot, globs):
    if isinstance(slot, str):
        return slot
    params = list(inspect.signature(evaluate(node.func, globs)).parameters.values())
    fixed = [p for p in params if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
    if slot < len(fixed):
        return fixed[slot].name
    star = [p for p in params if p.kind == p.VAR_POSITIONAL]
    return star[0].name if star else f"argument {slot}"


def _cases():
    out, seen = [], set()
    for test in public_doctests():
        for i, node in example_calls(test):
            lineno = (test.lineno or 0) + test.examples[i].lineno + 1
            slots = [j for j, a in enumerate(node.args) if not isinstance(a, ast.Starred)]
            slots += [k.arg for k in node.keywords if k.arg]
            for slot in slots:
                ident = f"{test.name}:{lineno}:{slot}"
                if ident not in seen:
                    seen.add(ident)
                    out.append(pytest.param(test, i, node, slot, id=ident))
    return out


CASES = _cases()


def _changed(node, slot):
    """A copy of the call whose argument at ``slot`` is the name ``EDGE``."""
    new = ast.parse(ast.unparse(node), mode="eval").body
    edge = ast.Name("EDGE", ast.Load())
    if isinstance(slot, int):
        new.args[slot] = edge
    else:
        next(k for k in new.keywords if k.arg == slot).value = edge
    return ast.fix_missing_locations(new)


def _judge(call, globs, label, value, base, name, names, key):
    """None if the call with ``EDGE = value`` is used or refused well, else what went wrong."""
    err, result = outcome(call, globs, value, base)
    if isinstance(err, ValueError):
        lead = first_name(str(err), names)
        if lead == name or key in JOINT:
            return None
        return f"{name}={label}: the ValueError leads with {lead!r}: {err}"
    if err is not None:
        return f"{name}={label}: {type(err).__name__}: {err}"
    if label in BOOLISH:
        return f"{name}={label}: a bool was taken as a number or a value"
    if label == "[]" and key not in EMPTY_OK:
        return f"{name}={label}: an empty list was accepted"
    if finite(base[1]) and not finite(result):
        return f"{name}={label}: a non-finite result"
    return None


def test_the_arguments_are_collected():
    names = {p.id.split(":")[0] for p in CASES}
    assert len(CASES) > 500
    assert "xnavlab.core.filters.ekf_update" in names


@pytest.mark.parametrize(("test", "i", "node", "slot"), CASES)
def test_an_edge_value_is_used_or_refused(test, i, node, slot):
    if plumbing(test):
        pytest.skip(plumbing(test))
    globs = state(test, i, node)
    key = f"{test.name}:{_slot_name(node, slot, globs)}"
    if key in SKIP:
        pytest.skip(SKIP[key])
    base = unmodified(test, i, node)
    if base is None:
        pytest.skip("the unmodified call raises (an example of a refusal)")
    orig = evaluate(
        node.args[slot] if isinstance(slot, int) else next(k.value for k in node.keywords if k.arg == slot),
        globs,
    )
    call = _changed(node, slot)
    name = _slot_name(node, slot, globs)
    names = parameter_names(node, globs)
    problems = [
        _judge(call, globs, label, value, base, name, names, key) for label, value in edge_values(orig)
    ]
    problems = [p for p in problems if p]
    assert not problems, f"{ast.unparse(node)}:\n" + "\n".join(p[:300] for p in problems)
