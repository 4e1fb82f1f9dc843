"""benchmarks/report.py: the measurements page is the rendering of the committed results.

No timing is decided here: the tests read the JSON the benchmarks wrote and the page rendered
from it, and check that the two agree, that every result says when, how and on what machine it
was measured, and that the top-level README points at the page instead of quoting numbers.
"""

import ast
import importlib.util
import json
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
BENCH = ROOT / "benchmarks"

#: Scripts that write no result of this page, each with its reason.
NO_RESULT = {
    # studies that compute the shipped tables under xnavlab/data/ (their tests recompute cells)
    "bench_detectors.py": "computes xnavlab/data/detector_table.json",
    "bench_early_faults.py": "computes xnavlab/data/early_faults.json",
    "bench_headline.py": "computes xnavlab/data/headline_runs.json",
    "bench_roc.py": "computes xnavlab/data/roc_curves.json",
}


@pytest.fixture(scope="module")
def report():
    spec = importlib.util.spec_from_file_location("bench_report", BENCH / "report.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _result(name="demo", **extra):
    data = {"name": name, "title": "A demo", "about": "", "command": "python benchmarks/bench_demo.py",
            "date": "2026-11-28", "machine": {"cpu": "Some CPU", "cores": 2, "python": "3.11.7",
                                              "numpy": "2.4.6", "blas": "openblas 0.3"},
            "cpu_reference_ms": [40.0, 42.5], "load_1min": [1.2, 1.2],
            "tables": [{"title": "", "columns": ["what", "measured", "target"],
                        "rows": [["a | b", "1.0 s", ""], ["c", "2.0 s", ""]]}], "notes": ["A note."]}
    data.update(extra)
    return data


def test_the_page_is_the_rendering_of_the_committed_results(report):
    page = (BENCH / "README.md").read_text()
    assert report.rendered(page, report.load_results()) == page, (
        "benchmarks/README.md is not the rendering of benchmarks/results/: run `make benchmarks-page`")


def test_every_result_says_when_how_and_on_what_it_was_measured(report):
    results = report.load_results()
    assert {"startup", "mars", "chapters", "against"} <= set(results)
    for name, data in results.items():
        assert re.fullmatch(r"\d{4}-\d{2}-\d{2}", data["date"]), name
        assert data.get("command") or data.get("source"), name
        assert data["machine"].get("cores"), name
        if not data.get("source"):  # written by a benchmark: everything recorded
            assert {"cpu", "python", "numpy", "blas"} <= set(data["machine"]), name
            assert len(data["cpu_reference_ms"]) == 2 and len(data["load_1min"]) == 2, name
        assert data["tables"], name
        for t in data["tables"]:
            assert t["rows"], (name, t["title"])
            assert all(len(r) == len(t["columns"]) for r in t["rows"]), (name, t["title"])


def test_every_benchmark_script_records_its_result():
    for path in sorted(BENCH.glob("bench_*.py")):
        if path.name in NO_RESULT:
            continue
        calls = [n for n in ast.walk(ast.parse(path.read_text()))
                 if isinstance(n, ast.Call) and getattr(n.func, "id", None) == "Record"]
        assert calls, f"{path.name} writes no result (no _timing.Record)"
        name = calls[0].args[0].value
        assert (BENCH / "results" / f"{name}.json").exists(), f"{path.name}: no results/{name}.json"


def test_a_section_is_replaced_by_its_rendering_and_dated_once(report):
    page = "intro\n<!-- begin generated: demo -->\nold text\n<!-- end generated: demo -->\nafter\n"
    out = report.rendered(page, {"demo": _result()})
    assert out.startswith("intro\n<!-- begin generated: demo -->\n### A demo\n")
    assert out.endswith("<!-- end generated: demo -->\nafter\n")
    assert "old text" not in out
    assert out.count("Measured 2026-11-28") == 1
    assert "Some CPU, 2 cores, Python 3.11.7, numpy 2.4.6 (openblas 0.3)" in out
    assert "CPU reference `sum(range(10**6))` 40-42.5 ms, load (1 min) 1.2" in out
    assert "| a \\| b | 1.0 s |" in out  # the pipe escaped, the empty column left out
    assert "target" not in out
    assert report.rendered(out, {"demo": _result()}) == out


def test_a_transcribed_result_says_so(report):
    data = _result(source="its printed output", cpu_reference_ms=[], load_1min=[])
    line = report.dated_line(data)
    assert ", transcribed from its printed output;" in line
    assert "CPU reference `sum(range(10**6))` not recorded" in line


@pytest.mark.parametrize("page, results, words", [
    ("x\n", {"demo": None}, "without a marked section"),
    ("<!-- begin generated: gone -->\n<!-- end generated: gone -->\n", {}, "without a result"),
    ("<!-- begin generated: demo -->\n<!-- end generated: demo -->\n" * 2, {"demo": None}, "twice"),
])
def test_a_result_and_its_section_come_in_pairs(report, page, results, words):
    results = {k: _result(k) for k in results}
    with pytest.raises(ValueError, match=words):
        report.rendered(page, results)


def test_a_result_is_named_after_its_file(report, tmp_path):
    (tmp_path / "demo.json").write_text(json.dumps(_result("other")))
    with pytest.raises(ValueError, match="stem"):
        report.load_results(tmp_path)


def test_the_readme_points_at_the_page_and_quotes_no_measurement():
    readme = (ROOT / "README.md").read_text()
    assert "benchmarks/README.md" in readme
    for words in ("CPU reference", "load average", "load (1 min)"):
        assert words not in readme, f"README.md quotes a measurement ({words!r}): move it to the page"
