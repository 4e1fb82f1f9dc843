"""Tests for xnavlab.core.campaign_records: what a line of a campaign store must be."""

import json

import pytest

from xnavlab.core import campaign_records as cr
from xnavlab.core.userfiles import InputWarning

RECORD = {"index": 0, "seed": 7, "parameters": {}, "metrics": {"rmse": 1.0}, "status": "ok",
          "error": None}


def test_a_whole_record_is_read_and_every_other_line_named_by_its_number():
    good = json.dumps(RECORD)
    lines = [good, "", '{"index": 1', "[1, 2]", json.dumps({**RECORD, "index": -1}),
             json.dumps({k: v for k, v in RECORD.items() if k != "seed"}),
             json.dumps({**RECORD, "metrics": [1]})]
    records, bad = cr.parse_records(lines, first=1)
    assert records == [RECORD]
    assert [n for n, _ in bad] == [4, 5, 6, 7, 8]          # line numbers count the first line
    assert [why for _, why in bad] == ["not JSON", "not a JSON object",
                                       "index -1 is not an integer >= 0", "no seed",
                                       "metrics is not a table"]


@pytest.mark.parametrize(("change", "why"), [
    ({"index": True}, "index True is not an integer >= 0"),
    ({"seed": 1.5}, "seed 1.5 is not an integer"),
    ({"status": "done"}, "status 'done' is neither 'ok' nor 'failed'"),
    ({"parameters": None}, None),
])
def test_why_not_a_record(change, why):
    assert cr.why_not_a_record({**RECORD, **change}) == why


def test_bad_lines_are_one_warning_naming_the_file_and_the_first_ten():
    bad = [(n, "not JSON") for n in range(1, 13)]
    with pytest.warns(InputWarning, match=r"^runs.jsonl: 12 lines not read .* again: line 1 "
                                          r"\(not JSON\).*line 10 \(not JSON\); and 2 more$"):
        cr.report_bad_lines(bad, "runs.jsonl", "their runs are computed again")


def test_two_ok_records_of_one_run_that_disagree_are_one_warning_with_their_lines():
    """Review 35b N16: a failed attempt before an ok one, or an exact repeat, is no conflict."""
    failed = {**RECORD, "status": "failed", "metrics": None, "error": "boom"}
    other = {**RECORD, "seed": 8, "metrics": {"rmse": 2.0}}
    records, _, numbers = cr.parse_records([json.dumps(r) for r in (failed, RECORD, RECORD, other)],
                                           numbers=True)
    assert numbers == [1, 2, 3, 4]
    with pytest.warns(InputWarning, match=r"^f: run 0 has two 'ok' records that disagree \(lines "
                                          r"2 and 4 differ in seed, metrics\); the first counts$"):
        cr.report_disagreements(records, numbers, "f")
    cr.report_disagreements(records[:3], numbers[:3], "f")  # no warning (filterwarnings=error)


def test_a_record_whose_seed_no_run_can_draw_from_is_no_record():
    """Review 35e: seed -1 and 2^70 were read as records (and shown in load_runs's table)."""
    lines = [json.dumps({**RECORD, "seed": s}) for s in (-1, 2**70, 0, 2**63 - 1)]
    records, bad = cr.parse_records(lines)
    assert [r["seed"] for r in records] == [0, 2**63 - 1]
    assert bad == [(1, "seed -1 is not in [0, 9223372036854775807]"),
                   (2, f"seed {2**70} is not in [0, 9223372036854775807]")]


@pytest.mark.parametrize(("change", "why"), [
    ({"error": "boom"}, "status 'ok' with an error 'boom'"),
    ({"metrics": None}, "status 'ok' without metrics"),
    ({"status": "failed", "error": "boom"}, "status 'failed' with metrics"),
    ({"status": "failed", "metrics": None}, "status 'failed' without its error"),
    ({"status": "failed", "metrics": None, "error": 3}, "error 3 is neither null nor a text"),
])
def test_a_record_whose_status_error_and_metrics_disagree_is_no_record(change, why):
    """Review 35m (5) 6: "status": "ok" with "error": "boom" was reused without a word; a
    campaign writes an ok run with metrics and no error, a failed one the other way round."""
    assert cr.why_not_a_record({**RECORD, **change}) == why
    assert cr.why_not_a_record({**RECORD, "status": "failed", "metrics": None,
                                "error": "RuntimeError: boom"}) is None
