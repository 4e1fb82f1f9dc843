"""The registry: every registered reproduction passes; results serialise; IDs are unique;
one verdict vocabulary; tables no cell can break."""

import json
import os
from html.parser import HTMLParser

import numpy as np
import pytest

from xnavlab import reproduce


def test_registry_lists_the_part_one_id():
    assert "xnav-ranging" in reproduce.ids()
    rep = reproduce.get("xnav-ranging")
    assert rep.source and rep.title and rep.chapter


def test_unknown_id():
    with pytest.raises(ValueError, match="unknown reproduction id 'nope'; known ids:"):
        reproduce.get("nope")


def test_xnav_ranging_within_five_percent():
    res = reproduce.run("xnav-ranging")
    res.assert_passed()
    for name, paper in res.paper.items():
        assert abs(res.ours[name] - paper) <= 0.05 * paper
    payload = json.loads(res.to_json())
    assert payload["pass"] is True and payload["id"] == "xnav-ranging"
    assert payload["verdict"] == "PASS"
    assert "<td>B0531+21</td>" in res._repr_html_()


def test_failed_checks_are_reported():
    res = reproduce.Result("demo", [reproduce.check_rel("x", 1.0, 2.0, 0.1)])
    assert not res.passed
    with pytest.raises(AssertionError, match="demo: FAIL"):
        res.assert_passed()
    assert not reproduce.Result("empty", []).passed


def test_check_helpers():
    assert reproduce.check_abs("a", 10.0, 12.0, 3.0).passed
    assert not reproduce.check_range("b", 1.0, float("nan"), 0.0, 2.0, "range").passed
    assert reproduce.check_true("c", "x", "x", True, "same").passed


def test_double_registration_is_refused():
    reproduce.ids()
    with pytest.raises(ValueError, match="registered twice"):
        reproduce.register("xnav-ranging", title="t", source="s", chapter="c")(lambda out=None: None)


def test_run_writes_figures(tmp_path):
    res = reproduce.run("xnav-ranging", out=tmp_path / "figs")
    assert res.figures and all((tmp_path / "figs").glob("*.png"))


def test_unclaimed_rows_are_shown_but_do_not_decide():
    rows = [reproduce.check_rel("x", 1.0, 1.0, 0.1), reproduce.check_info("rank", "a", "b", "see note")]
    res = reproduce.Result("demo", rows)
    assert res.passed
    assert "NOT CLAIMED" in res.table()
    assert res.to_dict()["checks"] == {"x": "PASS", "rank": "NOT CLAIMED"}
    only_info = reproduce.Result("info", rows[1:])
    assert not only_info.passed


@pytest.mark.parametrize("rid", ["toa-terms", "mars-orbit"])
def test_part_one_sanity_reproductions(rid):
    reproduce.run(rid).assert_passed()


def test_package_never_switches_the_matplotlib_backend():
    # a notebook kernel's inline backend must survive reproduce.run(..., out=...)
    from pathlib import Path

    root = Path(reproduce.__file__).parent
    offenders = [p.name for p in root.rglob("*.py")
                 if "matplotlib.use(" in "".join(l for l in p.read_text().splitlines(True)
                                                if not l.lstrip().startswith(">>>"))]
    assert not offenders, offenders


@pytest.mark.parametrize("rid", reproduce.ids())
def test_every_registered_reproduction_passes(rid):
    """Every number the book claims is asserted here too (paper, ours, tolerance in the table)."""
    res = reproduce.run(rid)
    res.assert_passed()
    claimed = [c for c in res.checks if c.claimed]
    assert claimed and all(c.tolerance for c in claimed)
    assert res.note, f"{rid}: say how ours was obtained and where it differs"


# ------------------------------------------------------------------------------------------
# one verdict vocabulary, safe tables


class _Rows(HTMLParser):
    """The tables of an HTML fragment as lists of rows of cell texts (th and td)."""

    def __init__(self):
        super().__init__()
        self.tables, self._cell = [], None

    def handle_starttag(self, tag, attrs):
        if tag == "table":
            self.tables.append([])
        elif tag == "tr":
            self.tables[-1].append([])
        elif tag in ("td", "th"):
            self._cell = []

    def handle_endtag(self, tag):
        if tag in ("td", "th"):
            self.tables[-1][-1].append("".join(self._cell))
            self._cell = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell.append(data)


def _tables(fragment):
    parser = _Rows()
    parser.feed(fragment)
    parser.close()
    return parser.tables


NASTY = "a | b <i>x</i> & c\nnext | line"


def _nasty_result():
    return reproduce.Result("nasty", [
        reproduce.check_abs(NASTY, 1.0, 1.5, 1.0, unit="m|s"),
        reproduce.check_info("rank | order", "<RKF>", "ASUKF\n| best", "not | claimed\n<b>"),
        reproduce.check_true("flag", "x|y", "x|y", False, "same | text"),
    ], note="a note with | and <script>alert(1)</script>\nover lines")


def test_verdict_vocabulary_is_defined_once():
    assert reproduce.VERDICTS == ("PASS", "NOT CLAIMED", "FAIL")
    res = _nasty_result()
    assert [c.verdict for c in res.checks] == ["PASS", "NOT CLAIMED", "FAIL"]
    assert res.verdict == "FAIL" and not res.passed
    assert res.counts() == {"PASS": 1, "NOT CLAIMED": 1, "FAIL": 1}
    assert reproduce.Result("none", []).verdict == "FAIL"
    info_only = reproduce.Result("info", [reproduce.check_info("x", 1, 2, "why")])
    assert info_only.verdict == "FAIL"
    ok = reproduce.Result("ok", [reproduce.check_rel("x", 1.0, 1.0, 0.1)])
    assert ok.verdict == "PASS"
    raised = reproduce.Result("raised", ok.checks, error="ValueError: boom")
    assert raised.verdict == "FAIL"


def test_run_or_fail_turns_an_exception_into_fail():
    res = reproduce.run_or_fail("no-such-reproduction")
    assert res.verdict == "FAIL" and res.error.startswith("ValueError: unknown reproduction id")
    assert res.to_dict()["error"] == res.error


def test_headline_counts():
    ok = reproduce.Result("a", [reproduce.check_rel("x", 1.0, 1.0, 0.1),
                                reproduce.check_info("y", 1, 2, "why"),
                                reproduce.check_info("z", 1, 2, "why")])
    assert reproduce.headline([ok]) == "1 of 1 reproductions pass (2 rows not claimed)"
    text = reproduce.headline([ok, _nasty_result(), reproduce.run_or_fail("no-such")])
    assert text == "1 of 3 reproductions pass (3 rows not claimed); FAIL: nasty, no-such"
    n = reproduce.counts([ok, _nasty_result()])
    assert n["rows"] == {"PASS": 2, "NOT CLAIMED": 3, "FAIL": 1} and n["fail"] == ["nasty"]


def test_result_html_has_one_cell_per_column_and_escapes_everything():
    res = _nasty_result()
    page = res._repr_html_()
    assert "<script>" not in page and "<i>" not in page and "<b>" not in page
    assert "&lt;script&gt;" in page
    (table,) = _tables(page)
    header, *rows = table
    assert header == ["quantity", "paper", "ours", "tolerance", "verdict"]
    assert len(rows) == len(res.checks)
    assert all(len(r) == len(header) for r in rows)
    assert rows[0][0] == NASTY  # the text survives, escaped, in its own cell
    assert [r[-1] for r in rows] == [c.verdict for c in res.checks]
    assert set(r[-1] for r in rows) <= set(reproduce.VERDICTS)
    assert not hasattr(res, "_repr_markdown_")  # text/html is the one rendering


def test_report_html_is_safe_and_says_what_the_cli_says():
    results = [_nasty_result(), reproduce.Result("ok", [reproduce.check_rel("x", 1.0, 1.0, 0.1)])]
    page = reproduce.report_html(results, elapsed_s=12.3)
    assert "<script>" not in page
    assert reproduce.headline(results) in page
    summary, checks = _tables(page)
    assert summary[0] == list(reproduce.SUMMARY_HEADER)
    assert checks[0] == list(reproduce.CHECK_HEADER)
    for table in (summary, checks):
        assert all(len(r) == len(table[0]) for r in table)
    assert [r[1] for r in summary[1:]] == [r.verdict for r in results]
    assert [r[-1] for r in checks[1:]] == [c.verdict for r in results for c in r.checks]
    plain = reproduce.results_table(results).splitlines()
    assert plain[0].split()[-1] == "verdict"
    assert all(line.rstrip().endswith(c.verdict) for line, c in
               zip(plain[1:], [c for r in results for c in r.checks], strict=True))
    assert len(plain) == 1 + sum(len(r.checks) for r in results)  # newlines flattened


# -- the disk cache -------------------------------------------------------------------------

@pytest.fixture
def dummy(monkeypatch, tmp_path):
    """A registered reproduction that counts its calls, with an empty disk cache."""
    monkeypatch.setenv("XNAVLAB_CACHE", str(tmp_path))
    monkeypatch.delenv(reproduce.CACHE_ENV, raising=False)
    calls = []

    def func(out=None, seed=0):
        calls.append(seed)
        return reproduce.Result("test-dummy", [reproduce.check_rel("x", 1.0, 1.0, 0.1)],
                                data={"a": np.arange(3.0) + seed})

    def forget():  # what a new process would not have: the session's results
        for key in [k for k in reproduce._CACHE if k[0].startswith("test-")]:
            del reproduce._CACHE[key]

    reproduce.register("test-dummy", title="t", source="s", chapter="c")(func)
    yield calls, forget
    forget()
    reproduce._REGISTRY.pop("test-dummy", None)
    reproduce._REGISTRY.pop("test-timing", None)


def test_a_result_is_computed_once_for_the_same_code(dummy, tmp_path):
    calls, forget = dummy
    first = reproduce.run("test-dummy")
    forget()
    again = reproduce.run("test-dummy")
    assert calls == [0] and again.from_cache and not first.from_cache
    assert again.checks == first.checks and np.array_equal(again.data["a"], first.data["a"])
    assert len(list((tmp_path / "reproductions").glob("test-dummy-*.pickle"))) == 1
    page = reproduce.report_html([again], elapsed_s=1.0)
    assert "0 computed, 1 read from the reproduction cache" in page


def test_fresh_odd_arguments_or_the_switch_compute_again(dummy, monkeypatch):
    calls, forget = dummy
    reproduce.run("test-dummy")
    assert not reproduce.run("test-dummy", fresh=True).from_cache
    forget()
    assert not reproduce.run("test-dummy", seed=np.int64(3)).from_cache  # not a plain number:
    forget()
    assert not reproduce.run("test-dummy", seed=np.int64(3)).from_cache  # computed, not stored
    forget()
    monkeypatch.setenv(reproduce.CACHE_ENV, "0")
    assert not reproduce.run("test-dummy").from_cache
    assert calls == [0, 0, 3, 3, 0]


def test_each_set_of_arguments_and_blas_family_keeps_its_entry(dummy, monkeypatch, tmp_path):
    # a chapter's shortened run, the full run and a `make portability` run side by side
    calls, forget = dummy
    reproduce.run("test-dummy")
    reproduce.run("test-dummy", seed=2)
    forget()   # (a process reads OPENBLAS_CORETYPE once: another one is another process)
    base = os.environ.get("OPENBLAS_CORETYPE")      # (make portability sets it)
    monkeypatch.setenv("OPENBLAS_CORETYPE", "Prescott" if base != "Prescott" else "Haswell")
    reproduce.run("test-dummy")
    forget()
    if base is None:
        monkeypatch.delenv("OPENBLAS_CORETYPE")
    else:
        monkeypatch.setenv("OPENBLAS_CORETYPE", base)
    again = [reproduce.run("test-dummy", seed=2), reproduce.run("test-dummy")]
    assert calls == [0, 2, 0] and all(r.from_cache for r in again)
    assert again[0].data["a"][0] == 2.0
    assert len(list((tmp_path / "reproductions").glob("test-dummy-*.pickle"))) == 3


def test_other_code_or_an_unreadable_entry_computes_again(dummy, monkeypatch, tmp_path):
    calls, forget = dummy
    reproduce.run("test-dummy")
    reproduce.run("test-dummy", seed=2)
    forget()
    legacy = tmp_path / "reproductions" / f"test-dummy-{'0' * 24}.pickle"  # an entry named
    legacy.write_bytes(b"")                                               # before the families
    for entry in (tmp_path / "reproductions").glob("*.pickle"):
        entry.write_bytes(b"not a pickle")
    assert not reproduce.run("test-dummy").from_cache
    forget()
    monkeypatch.setattr(reproduce, "source_digest", lambda *a, **k: "another version")
    assert not reproduce.run("test-dummy").from_cache
    assert calls == [0, 2, 0, 0]
    # the other code's results, of every family, are gone
    assert len(list((tmp_path / "reproductions").glob("test-dummy-*.pickle"))) == 1


def test_a_timing_is_never_read_from_disk(dummy, tmp_path):
    calls, forget = dummy
    func = reproduce.get("test-dummy").func
    reproduce.register("test-timing", title="t", source="s", chapter="c", cache=False)(func)
    reproduce.run("test-timing")
    forget()
    assert not reproduce.run("test-timing").from_cache and calls == [0, 0]
    assert not list((tmp_path / "reproductions").glob("test-timing-*"))
    assert reproduce.get("attitude-cost").cache is False
