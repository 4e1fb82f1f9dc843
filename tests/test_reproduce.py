"""The registry: every registered reproduction runs and its checks hold; results serialise; IDs
are unique; one verdict vocabulary, claims and checks apart; tables no cell can break."""

import errno
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


def test_xnav_ranging_rows_and_json():
    res = reproduce.run("xnav-ranging")
    res.assert_ok()
    payload = json.loads(res.to_json())
    assert payload["ok"] is True and payload["id"] == "xnav-ranging"
    assert payload["verdict"] == res.verdict in reproduce.HEADLINES
    kinds = {row["name"]: row["kind"] for row in payload["rows"]}
    assert kinds["B0531+21 ranging (m)"] == "claim"
    assert "<td>B0531+21 ranging (m)</td>" in res._repr_html_()


def test_a_failed_check_of_ours_is_an_error_a_refuted_claim_is_not():
    refuted = reproduce.Result("demo", [reproduce.check_rel("x", 1.0, 2.0, 0.1, why="w")])
    assert refuted.ok and refuted.verdict == "NOT REPRODUCED"
    refuted.assert_ok()
    broken = reproduce.Result("demo", [reproduce.check_sanity("y", "> 0", -1.0, False, "positive")])
    assert not broken.ok and broken.verdict == "ERROR"
    with pytest.raises(AssertionError, match="demo: ERROR"):
        broken.assert_ok()
    assert reproduce.Result("empty", []).verdict == "CHECK"


def test_double_registration_is_refused():
    reproduce.ids()
    with pytest.raises(ValueError, match="registered twice"):
        reproduce.register("xnav-ranging", title="t", source="s", chapter="c")(lambda out=None: None)


def test_run_writes_figures(tmp_path):
    res = reproduce.run("xnav-ranging", out=tmp_path / "figs")
    assert res.figures and all((tmp_path / "figs").glob("*.png"))


def test_checks_are_shown_but_never_counted_as_reproductions():
    rows = [reproduce.check_rel("x", 1.0, 1.0, 0.1, why="w"),
            reproduce.check_measure("rank", "b", "shown", paper="a")]
    res = reproduce.Result("demo", rows)
    assert res.verdict == "REPRODUCED" and "CHECK" in res.table()
    assert [r["kind"] for r in res.to_dict()["rows"]] == ["claim", "check"]
    assert reproduce.Result("info", rows[1:]).verdict == "CHECK"


@pytest.mark.parametrize("rid", ["toa-terms", "mars-orbit"])
def test_part_one_sanity_reproductions_are_checks(rid):
    res = reproduce.run(rid)
    res.assert_ok()
    assert res.verdict == "CHECK" and not res.claims


def test_package_never_switches_the_matplotlib_backend():
    # a notebook kernel's inline backend must survive reproduce.run(..., out=...)
    from pathlib import Path

    root = Path(reproduce.__file__).parent
    offenders = [p.name for p in root.rglob("*.py")
                 if "matplotlib.use(" in "".join(l for l in p.read_text().splitlines(True)
                                                if not l.lstrip().startswith(">>>"))]
    assert not offenders, offenders


# every registered reproduction is run once, its checks and its claims' recorded verdicts
# judged together: tests/test_verdicts.py (one run, not one here and one there)


@pytest.mark.parametrize(("rid", "kw", "message"), [
    ("mars-sensors", {"n": 1999}, r"n must be an integer in \[2000, 1000000\]"),
    ("mars-sensors", {"seed": -1}, r"seed must be an integer in \[0, 9223372036854775807\]"),
    ("mallat-vs-pywavelets", {"seed": 2**63}, r"seed must be a numpy Generator or an integer"),
])
def test_a_reproductions_seed_and_size_are_refused_by_their_own_names(rid, kw, message):
    """Never as ``rng``, a name the caller never gave (review 35e)."""
    with pytest.raises(ValueError, match=message):
        reproduce.run(rid, fresh=True, **kw)


def test_fewer_sensor_draws_widen_the_tolerance_by_their_own_scatter():
    """2 % at the default 40,000 draws; five sample-sigma scatters, 5/sqrt(2 n), below 31,250."""
    assert reproduce.run("mars-sensors").check("UV range (m)").tolerance.startswith("within 2 %")
    res = reproduce.run("mars-sensors", n=2000, seed=3)
    res.assert_ok()
    assert res.check("UV range (m)").tolerance.startswith("within 7.9 %")


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
        reproduce.check_abs(NASTY, 1.0, 1.5, 1.0, unit="m|s", why="a | reason"),
        reproduce.check_measure("rank | order", "ASUKF\n| best", "not | claimed\n<b>", paper="<RKF>"),
        reproduce.check_true("flag", "x|y", "x|y", False, why="same | text"),
        reproduce.check_order("a | b", "a < b", [-1.0, 1.5, -2.0, 1.0]),
    ], note="a note with | and <script>alert(1)</script>\nover lines")


def test_verdict_vocabulary_is_defined_once():
    assert reproduce.VERDICTS == ("REPRODUCED", "NOT REPRODUCED", "UNDECIDED", "CHECK", "CHECK FAILED")
    assert reproduce.HEADLINES == ("REPRODUCED", "PARTLY REPRODUCED", "NOT REPRODUCED",
                                   "UNDECIDED", "CHECK", "ERROR")
    res = _nasty_result()
    assert [c.verdict for c in res.checks] == ["REPRODUCED", "CHECK", "NOT REPRODUCED", "UNDECIDED"]
    assert res.verdict == "PARTLY REPRODUCED" and res.ok
    undecided = reproduce.Result("u", res.checks[3:])
    assert undecided.verdict == "UNDECIDED"
    refuted = reproduce.Result("n", res.checks[2:])
    assert refuted.verdict == "NOT REPRODUCED"
    with pytest.raises(ValueError, match="verdict must be one of"):
        reproduce.Check("x", 1, 1, "t", "PASS")
    raised = reproduce.Result("raised", res.checks, error="ValueError: boom")
    assert raised.verdict == "ERROR"


def test_run_or_fail_turns_an_exception_into_an_error():
    res = reproduce.run_or_fail("no-such-reproduction")
    assert res.verdict == "ERROR" and res.error.startswith("ValueError: unknown reproduction id")
    assert res.to_dict()["error"] == res.error


def test_headline_counts_claims_and_checks_apart():
    ok = reproduce.Result("a", [reproduce.check_rel("x", 1.0, 1.0, 0.1, why="w"),
                                reproduce.check_measure("y", 2, "why"),
                                reproduce.check_measure("z", 2, "why")])
    assert reproduce.headline([ok]) == ("1 of 1 paper claim reproduced (0 not reproduced, "
                                        "0 undecided); 2 of 2 checks hold")
    text = reproduce.headline([ok, _nasty_result(), reproduce.run_or_fail("no-such")])
    assert text == ("2 of 4 paper claims reproduced (1 not reproduced, 1 undecided); "
                    "3 of 4 checks hold; ERROR: no-such")
    n = reproduce.counts([ok, _nasty_result()])
    assert n["claims"] == 4 and n["checks"] == 3 and n["errors"] == []
    assert n["headlines"]["PARTLY REPRODUCED"] == 1 and n["headlines"]["REPRODUCED"] == 1


def test_a_sentence_and_the_summary_box_come_from_the_rows():
    res = _nasty_result()
    assert res.sentence("flag").startswith("flag: the paper x|y, ours x|y: NOT REPRODUCED (")
    with pytest.raises(ValueError, match="has no row 'nope'"):
        res.sentence("nope")
    box = reproduce.summary_box([res])
    assert "<script>" not in box and "admonition" in box
    assert box.count("<li>") == len(res.claims) + 1      # one per claim, one for the checks
    assert "1 check of ours holds (not claims of the paper)" in box


def test_result_html_has_one_cell_per_column_and_escapes_everything():
    res = _nasty_result()
    page = res._repr_html_()
    assert "<script>" not in page and "<i>" not in page and "<b>" not in page
    assert "&lt;script&gt;" in page
    (table,) = _tables(page)
    header, *rows = table
    assert header == ["quantity", "paper", "ours", "tolerance", "verdict", "reading"]
    assert len(rows) == len(res.checks)
    assert all(len(r) == len(header) for r in rows)
    assert rows[0][0] == NASTY  # the text survives, escaped, in its own cell
    assert [r[-2] for r in rows] == [c.verdict for c in res.checks]
    assert set(r[-2] for r in rows) <= set(reproduce.VERDICTS)
    assert not hasattr(res, "_repr_markdown_")  # text/html is the one rendering


def test_report_html_is_safe_and_says_what_the_cli_says():
    results = [_nasty_result(), reproduce.Result("ok", [reproduce.check_rel("x", 1.0, 1.0, 0.1, why="w")])]
    page = reproduce.report_html(results, elapsed_s=12.3)
    assert "<script>" not in page
    assert reproduce.headline(results) in page
    count, summary, checks = _tables(page)
    assert count[0] == list(reproduce.COUNT_HEADER)
    assert count[1][1:4] == ["2", "1", "1"] and count[3][4:] == ["1", "0"]
    assert count[1][0] == "claims of the papers" and count[2][1:4] == ["2", "1", "1"]  # rows
    assert summary[0] == list(reproduce.SUMMARY_HEADER)
    assert checks[0] == list(reproduce.CHECK_HEADER)
    for table in (summary, checks):
        assert all(len(r) == len(table[0]) for r in table)
    assert [r[1] for r in summary[1:]] == [r.verdict for r in results]
    assert [r[-2] for r in checks[1:]] == [c.verdict for r in results for c in r.checks]
    plain = reproduce.results_table(results).splitlines()
    assert plain[0].split()[-2:] == ["verdict", "reading"]
    assert all(f"  {c.verdict}" in line for line, c in
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
        return reproduce.Result("test-dummy", [reproduce.check_rel("x", 1.0, 1.0, 0.1, why="w")],
                                data={"a": np.arange(3.0) + seed})

    def forget():  # what a new process would not have: the session's results
        for key in [k for k in reproduce._CACHE if k[0].startswith("test-")]:
            del reproduce._CACHE[key]

    reproduce.register("test-dummy", title="t", source="s", chapter="c")(func)
    yield calls, forget
    forget()
    for rid in [i for i in reproduce._REGISTRY if i.startswith("test-")]:
        reproduce._REGISTRY.pop(rid)


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
    monkeypatch.setattr(reproduce, "code_digest", lambda *a, **k: "another version")
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


# -- review 35: the session cache ------------------------------------------------------------

def test_the_session_cache_gives_each_call_its_own_copy(dummy):
    """Review 35 R5: run gave back the session cache's own Result, so a cell that edited it
    (cleared its rows, changed its data) changed every later run of the ID in the kernel."""
    calls, _ = dummy
    first = reproduce.run("test-dummy")
    first.checks.clear()
    first.note = "edited"
    first.data["a"][0] = 99.0
    first.data["b"] = 1
    again = reproduce.run("test-dummy")
    assert again is not first and calls == [0]  # read from the session, not computed again
    assert len(again.checks) == 1 and again.verdict == "REPRODUCED" and again.note == ""
    assert again.data.keys() == {"a"} and again.data["a"][0] == 0.0
    again.checks.clear()
    assert len(reproduce.run_or_fail("test-dummy").checks) == 1 and calls == [0]


def test_true_1_and_1_0_are_three_session_keys(dummy):
    """Review 35 R6: the session key matched keywords by ==, so seed=True or 1.0 (refused in a
    fresh process) was handed seed 1's result: each is now computed, and so checked."""
    calls, _ = dummy
    for seed in (1, True, 1.0, np.int64(1), 1, True):
        reproduce.run("test-dummy", seed=seed)
    assert calls == [1, True, 1.0, 1] and [type(c) for c in calls] == [int, bool, float, np.int64]
    first = reproduce.run("mallat-vs-pywavelets", n=500, seed=1)
    for kw, match in [({"seed": True}, "^seed must be .* got True$"),
                      ({"seed": 1.0}, "^seed must be .* got 1.0$"),
                      ({"n": 500.0, "seed": 1}, "^n must be an integer in .* got 500.0$")]:
        with pytest.raises(ValueError, match=match):
            reproduce.run("mallat-vs-pywavelets", **{"n": 500, **kw})
    assert reproduce.run("mallat-vs-pywavelets", n=500, seed=1).checks == first.checks


def test_a_list_or_array_keyword_is_the_equal_tuple(dummy, tmp_path):
    """Review 35 R13: a list or array keyword (seeds=[0, 1]) raised "TypeError: unhashable
    type" when keyed; it is passed as the equal tuple, with its result and disk-cache entry."""
    calls, forget = dummy

    def func(out=None, seeds=(0, 1)):
        calls.append(seeds)
        return reproduce.Result("test-seeds", [reproduce.check_measure("n", len(seeds), "n")])

    reproduce.register("test-seeds", title="t", source="s", chapter="c")(func)
    assert reproduce.run("test-seeds", seeds=[0, 1]).checks[0].ours == 2
    assert reproduce.run("test-seeds", seeds=np.array([0, 1])).checks[0].ours == 2  # session
    forget()
    assert reproduce.run("test-seeds", seeds=(0, 1)).from_cache  # the list's disk entry
    assert calls == [(0, 1)] and type(calls[0][0]) is int
    assert len(list((tmp_path / "reproductions").glob("test-seeds-*.pickle"))) == 1
    assert not reproduce.run_or_fail("test-seeds", seeds=[[0], 1]).error  # nested: (0,)
    reproduce.run("test-seeds", seeds={0: 1})  # no key (a dict): computed each time
    reproduce.run("test-seeds", seeds={0: 1})
    assert calls == [(0, 1), ((0,), 1), {0: 1}, {0: 1}]


# -- review 35m: the public calls' arguments ------------------------------------------------

def test_run_refuses_a_keyword_its_reproduction_does_not_take(dummy):
    """Review 35m (1) 1: run(id, bogus=1) raised the reproduction function's TypeError (and
    run_or_fail turned it into "ERROR: TypeError"); now one ValueError naming the keyword, the
    reproduction's ID and the keywords it takes."""
    with pytest.raises(ValueError, match=r"^bogus is not a keyword the reproduction 'test-dummy' "
                                         r"takes: the valid ones are seed"):
        reproduce.run("test-dummy", bogus=1)
    assert reproduce.run_or_fail("test-dummy", bogus=1).error.startswith("ValueError: bogus is")


def test_run_refuses_an_out_that_is_not_a_folder(dummy, tmp_path):
    """Review 35m (1) 1: out=123 raised pathlib's TypeError, out=<a file> FileExistsError."""
    afile = tmp_path / "afile"
    afile.write_text("x")
    with pytest.raises(ValueError, match=r"^out must be a folder \(a str or os.PathLike\); got 123"):
        reproduce.run("test-dummy", out=123)
    with pytest.raises(ValueError, match=r"^out '.*afile' is a file, not a folder"):
        reproduce.run("test-dummy", out=afile)
    (tmp_path / "dang").symlink_to(tmp_path / "nothing")  # review 35n 6: "cannot be created: File exists"
    with pytest.raises(ValueError, match=r"^out '.*dang' is a symbolic link to '.*nothing', which "
                                         r"does not exist"):
        reproduce.run("test-dummy", out=tmp_path / "dang")
    assert reproduce.run("test-dummy", out=tmp_path / "new").id == "test-dummy"  # created


def test_run_refuses_a_fresh_that_is_not_a_bool(dummy):
    """Review 35m (5) 3: fresh="no" was taken as true (computed again)."""
    with pytest.raises(ValueError, match="^fresh must be True or False, got 'no'"):
        reproduce.run("test-dummy", fresh="no")


@pytest.mark.parametrize("value", ["false", "no", "off", " 0", "2"])
def test_the_cache_switch_refuses_what_is_not_0_or_1(dummy, monkeypatch, value):
    """Review 35m (5) 5: XNAVLAB_REPRODUCE_CACHE=false/no/off left the cache on without a word
    (only "0" turned it off); now refused in one line naming the variable, also by run_or_fail
    (raised once, not as every reproduction's ERROR)."""
    monkeypatch.setenv(reproduce.CACHE_ENV, value)
    with pytest.raises(ValueError, match="^XNAVLAB_REPRODUCE_CACHE must be 0 .off. or 1 .on."):
        reproduce.run("test-dummy")
    with pytest.raises(ValueError, match="^XNAVLAB_REPRODUCE_CACHE"):
        reproduce.run_or_fail("test-dummy")


def test_an_unusable_cache_folder_is_refused(dummy, monkeypatch, tmp_path):
    """Review 35m (7) 2: XNAVLAB_CACHE naming a file computed every result uncached without a
    word; now refused naming the variable (the default home's silent fallback stays)."""
    afile = tmp_path / "afile"
    afile.write_text("x")
    for bad in (str(afile), str(afile / "sub")):
        monkeypatch.setenv("XNAVLAB_CACHE", bad)
        with pytest.raises(ValueError, match="^XNAVLAB_CACHE must name a folder this process can write"):
            reproduce.run("test-dummy")


@pytest.mark.parametrize(("call", "match"), [
    (lambda: reproduce.counts([1, 2]), r"^results\[0\] must be a Result .*got int 1"),
    (lambda: reproduce.results_table(["x"]), r"^results\[0\] must be a Result .*got str 'x'"),
    (lambda: reproduce.headline([]), "^results must hold at least one Result"),
    (lambda: reproduce.summary_box(True), "^results must be a list of Result"),
    (lambda: reproduce.report_html([reproduce.run_or_fail("no-such-id")], elapsed_s="x"),
     "^elapsed_s must be"),
    (lambda: reproduce.summary_box([reproduce.run_or_fail("no-such-id")], title=3), "^title must be"),
    (lambda: reproduce.get(5), r"^id must be a reproduction ID \(a str"),
    (lambda: reproduce.run_or_fail(None), r"^id must be a reproduction ID"),
])
def test_the_tables_and_the_registry_refuse_what_is_not_theirs(call, match):
    """Review 35m (1) 1: counts([1, 2]) and results_table(["x"]) raised AttributeError."""
    with pytest.raises(ValueError, match=match):
        call()


def test_save_figure_refuses_a_missing_folder(tmp_path):
    """Review 35m (1) 1: save_figure into a missing folder raised matplotlib's FileNotFoundError."""
    fig, _ = reproduce.figure()
    with pytest.raises(ValueError, match="^out must be an existing folder; '/nonexistent/dir' does not"):
        reproduce.save_figure(fig, "/nonexistent/dir", "x")
    with pytest.raises(ValueError, match="^fig must be a matplotlib Figure"):
        reproduce.save_figure(None, tmp_path, "x")
    with pytest.raises(ValueError, match="^name must be a file name"):
        reproduce.save_figure(fig, tmp_path, "a/b")
    assert reproduce.save_figure(fig, tmp_path, "x").endswith("x.png")


def test_a_results_json_is_strict():
    """Review 35 Q7: Result.to_json wrote NaN (json.dumps' default allow_nan), not JSON; a row
    now refuses NaN, and the dump refuses one that got past it."""
    row = reproduce.check_measure("x", np.array([1.0, 2.0]), "what")
    assert json.loads(reproduce.Result("demo", [row]).to_json())["rows"][0]["ours"] == [1.0, 2.0]
    res = reproduce.Result("demo", [row], note="n")
    res.figures.append(float("nan"))  # not a row's value: caught by the dump
    with pytest.raises(ValueError, match="Out of range float values are not JSON compliant"):
        res.to_json()


def _no_space(*args, **kwargs):
    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


def test_a_figure_on_a_full_disk_is_one_line_and_leaves_no_file(monkeypatch, tmp_path):
    """Review 35 Q16: a figure cut short by a full disk stayed as a PNG that looks complete,
    and each reproduction with a figure became an ERROR row ("OSError ... must not raise")."""
    import matplotlib.figure

    fig, _ = reproduce.figure()
    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", _no_space)
    with pytest.raises(reproduce.OutputError,
                       match=rf"^out '{tmp_path}': x.png cannot be written \(No space left on "
                             rf"device\)$"):
        reproduce.save_figure(fig, tmp_path, "x")
    assert list(tmp_path.iterdir()) == []


def test_run_or_fail_raises_a_full_out_instead_of_an_error_row(dummy, monkeypatch, tmp_path):
    """Review 35 Q16: the caller's folder failed, not the reproduction: raised, not an ERROR row
    (a figure written by savefig itself as well as by save_figure); another OSError, or one
    without out, is still the reproduction's ERROR."""
    def full(out=None, seed=0):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    reproduce._REGISTRY["test-dummy"] = reproduce.Reproduction("test-dummy", "t", "s", "c", full)
    with pytest.raises(reproduce.OutputError, match=r"^out '.*' cannot be written \(No space"):
        reproduce.run_or_fail("test-dummy", out=tmp_path / "o")
    assert reproduce.run_or_fail("test-dummy").verdict == reproduce.ERROR


def test_save_figure_takes_the_dpi_and_a_figure_laid_out_already(tmp_path):
    """The reproductions that saved at 90 dpi with savefig (a cut-short PNG on a full disk) go
    through save_figure too; its dpi and layout are checked by name."""
    fig, _ = reproduce.figure(figsize=(2.0, 1.0))
    path = reproduce.save_figure(fig, tmp_path, "x", dpi=90, layout=False)
    from matplotlib.image import imread
    assert imread(path).shape[:2] == (90, 180)
    with pytest.raises(ValueError, match=r"^dpi must be a real number in \[30, 300\], got 1000"):
        reproduce.save_figure(fig, tmp_path, "x", dpi=1000)
    with pytest.raises(ValueError, match=r"^layout must be True or False"):
        reproduce.save_figure(fig, tmp_path, "x", layout="no")
