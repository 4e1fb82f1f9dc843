"""tools/typed_numbers.py: a typed result in prose is flagged; glued, math, code, structural,
identifier and allow-listed numbers are not; an allow-list entry without a reason is refused.

The tests plant their own pages in a temporary directory: they do not depend on the state of
the book's chapters (the Makefile runs the tool on the real book).
"""

import importlib.util
import json
import sys
from pathlib import Path

import pytest

TOOL = Path(__file__).resolve().parents[1] / "tools" / "typed_numbers.py"


@pytest.fixture(scope="module")
def tn():
    spec = importlib.util.spec_from_file_location("typed_numbers", TOOL)
    mod = importlib.util.module_from_spec(spec)
    sys.modules["typed_numbers"] = mod  # dataclasses look their module up there
    try:
        spec.loader.exec_module(mod)
        yield mod
    finally:
        sys.modules.pop("typed_numbers", None)


def numbers(tn, text):
    return [h.number for h in tn.scan_text(text)]


def _notebook(path, *markdown):
    cells = [{"cell_type": "code", "execution_count": None, "id": "c0", "metadata": {},
              "outputs": [], "source": ["x = 28.835  # a number in code is not prose"]}]
    cells += [{"cell_type": "markdown", "id": f"m{i}", "metadata": {}, "source": text}
              for i, text in enumerate(markdown)]
    nb = {"cells": cells, "metadata": {}, "nbformat": 4, "nbformat_minor": 5}
    path.write_text(json.dumps(nb, indent=1) + "\n")
    return path


@pytest.mark.parametrize("text, expected", [
    ("The fused error settles near 26.4 m.", ["26.4"]),
    ("The three together are 20 % better.", ["20"]),
    ("It converges after 864 000 updates and 1,000 runs.", ["864 000", "1,000"]),
    ("A 30-day run with a 500-s interval.", ["30", "500"]),
    ("Detected 12 of 16 faults.", ["12", "16"]),
    ("every 3 s, a 5 km error", ["3", "5"]),  # small integers with a unit are hits
    ("about 2x faster", ["2"]),
    ("In 2000 km of arc", ["2000"]),  # a year-like number with a unit
])
def test_typed_results_are_flagged(tn, text, expected):
    assert numbers(tn, text) == expected


@pytest.mark.parametrize("text", [
    "The error is {glue:text}`ch05_fused_rms_m:.1f` m.",
    "The delay is $\\Delta t = 28.835$ s and $$x = 12.5$$ and {math}`y = 3.5`.",
    "$$\nP = 0.95\n$$ (ch5-eq)",
    "Inline math over lines $(5\\ \\mathrm{km})^2 / 4500\n\\approx 6$ stays math.",
    "Code `sigma = 12.5` and ``a `b` 44.1`` stay code.",
    "```python\nx = 123.4\n```",
    "See chapter 12, chapters 1-3, sections 0 and 3, eq. (6), eqs. (3)-(5), Fig. 13,"
    " table 11, exercise 14, part 2, step 42 and level 5; Appendix 12.",
    "the kinematics (5)-(11) of the paper, its ref. [21] and [22]",
    "Pulsars B1937+21, J0030+0451 and B1821-24; db3 and DE421, a 3D plot, x1, ch05-ex1, SO(3).",
    "In 2016 and 1998 the papers.",
    "Counted 3 subsystems, 4 pulsars and 10 levels; 6 degrees of freedom, a 3-sigma bound.",
    "The 95th percentile and the 3rd day.",
    "```{exercise}\n:label: ch05-ex12\n\nHow many?\n```",
    "```{solution-start} ch05-ex12\n:class: dropdown\n```",
    ":::{figure} fig_2025.png\n:width: 80%\n\nA caption.\n:::",
    "A [link to chapter 3](03_mars_orbit.ipynb#sec-42) and <https://example.org/1234>.",
    "<!-- 123.4 in a comment --> <img src='a.png' width=600>",
    "(sec-12)=\n# 12. Parity in a fuzzy world",
    "J2000 is 2000-01-01 12:00 TDB.",
    "*Journal of Astronautics* 38(1): 26-33. [doi:10.3873/j.issn.1000-1328.2017.01.004]",
    "A 9×9 matrix and a 3 x 3 block.",
])
def test_non_results_are_not_flagged(tn, text):
    assert numbers(tn, text) == []


def test_directive_body_is_prose(tn):
    text = "```{exercise}\n:label: ch05-ex1\n\nRun it for 0.02 day.\n```\n"
    assert numbers(tn, text) == ["0.02"]


def test_planted_notebook_cell_is_reported(tn, tmp_path, capsys):
    page = _notebook(tmp_path / "05_x.ipynb", "## Model\nSee chapter 3.",
                     "The fused error is 26.4 m after {glue:text}`ch05_days:.0f` days.")
    allow = tmp_path / "allow.txt"
    allow.write_text("# nothing allowed\n")
    assert tn.main(["--allow", str(allow), str(page)]) == 1
    out = capsys.readouterr().out.strip().splitlines()
    assert len(out) == 1
    assert out[0].startswith(f"{tn.display_path(page)}:cell 2: 26.4 ... ")
    assert "26.4 m after" in out[0]


def test_md_page_reports_lines_and_skips_code_cells(tn, tmp_path, capsys):
    page = tmp_path / "page.md"
    page.write_text("---\nmystnb:\n  execution_timeout: 1800\n---\n\n# Page\n\n"
                    "```{code-cell} ipython3\nx = 55.5\n```\n\nIt took 42.5 s.\n")
    assert tn.main(["--allow", str(tmp_path / "none.txt"), str(page)]) == 1
    out = capsys.readouterr().out.strip()
    assert out.startswith(f"{tn.display_path(page)}:line 12: 42.5 ... ")
    assert out.endswith("It took 42.5 s.") and out.count("\n") == 0


def test_allow_list_entries(tn, tmp_path, capsys):
    page = _notebook(tmp_path / "06_x.ipynb", "The paper's 28.835 m and our 26.4 m; 30 days.")
    shown = tn.display_path(page)
    allow = tmp_path / "allow.txt"
    allow.write_text(f"# header\n{shown} | 28.835 | the paper's result (its abstract)\n"
                     "* | 30 | the paper's simulated span\n")
    assert tn.main(["--allow", str(allow), str(page)]) == 1
    out = capsys.readouterr().out.strip().splitlines()
    assert [line.split(": ")[1].split(" ")[0] for line in out] == ["26.4"]
    allow.write_text(allow.read_text() + f"{shown} | 26.4 | a definition for this test\n")
    assert tn.main(["--allow", str(allow), str(page)]) == 0


def test_entry_without_reason_is_refused(tn, tmp_path, capsys):
    page = _notebook(tmp_path / "07_x.ipynb", "Nothing typed.")
    allow = tmp_path / "allow.txt"
    for bad in ("* | 30 |\n", "* | 30\n", "* | 30 |   \n", "* | thirty | a word\n"):
        allow.write_text(bad)
        assert tn.main(["--allow", str(allow), str(page)]) == 2
        assert "typed_numbers:" in capsys.readouterr().err
        with pytest.raises(tn.BadAllowList):
            tn.load_allow(allow)


def test_bad_argument_exits_2(tn, tmp_path, capsys):
    assert tn.main([str(tmp_path / "missing.ipynb")]) == 2
    (tmp_path / "x.txt").write_text("1.5")
    assert tn.main([str(tmp_path / "x.txt")]) == 2
    assert tn.main(["--no-such-option"]) == 2
    capsys.readouterr()


def test_clean_page_exits_0(tn, tmp_path):
    page = _notebook(tmp_path / "08_x.ipynb", "Glued: {glue:text}`ch08_rms_m:.1f` m, in 2016.")
    assert tn.main(["--allow", str(tmp_path / "none.txt"), str(page)]) == 0


def test_the_real_allow_list_is_well_formed(tn):
    for entry in tn.load_allow(tn.ALLOW):
        assert entry.page == "*" or (tn.ROOT / entry.page).is_file(), entry
    sections = {line[2:].strip() for line in tn.ALLOW.read_text().splitlines()
                if line.startswith("# book/")}
    for page in tn.default_paths():  # a new page gets its (empty) section
        assert tn.display_path(page) in sections, f"no '# {tn.display_path(page)}' section"


def test_all_exempts_one_page_and_never_every_page(tn, tmp_path):
    page = tmp_path / "p.md"
    page.write_text("The paper reports 28.835 m and 36.587 m.\n")
    allow = tmp_path / "allow.txt"
    shown = tn.display_path(page)
    allow.write_text(f"{shown} | all | every number on this page is the paper's own\n")
    assert tn.main([str(page), "--allow", str(allow)]) == 0
    allow.write_text("* | all | no\n")
    assert tn.main([str(page), "--allow", str(allow)]) == 2
