"""xnavlab.core.prose: glued values as the prose's ``{eval}`` roles show them.

The entries must read exactly as myst-nb's ``{glue:text}`` showed the same value (the
conversion of a chapter changes no number on its page), show without quotes in every
reader, and the tools must find exactly the expressions JupyterLab and the book evaluate.
"""

import re

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from IPython.lib.pretty import pretty
from myst_nb.core.variables import format_plain_text

from xnavlab.core import prose
from xnavlab.core.prose import EVAL_NAME, Glued, Text, eval_expressions, format_value

FLOAT_SPECS = ["", ".0f", ".1f", ".2f", ".3f", "g", ".3g", ".2e", ".0e", ",.0f", ".0%", ".1%"]
INT_SPECS = ["", "d", ",d", ".0f", "g"]


@given(st.floats(allow_nan=False, allow_infinity=False, width=64), st.sampled_from(FLOAT_SPECS))
def test_a_float_reads_as_glue_text_showed_it(x, spec):
    # {glue:text}`name:spec` formatted the value's text/plain (repr) with myst-nb's rule;
    # no spec at all was "s"
    assert format_value(x, spec) == format_plain_text(repr(x), spec or "s")


@given(st.integers(-10**12, 10**12), st.sampled_from(INT_SPECS))
def test_an_int_reads_as_glue_text_showed_it(n, spec):
    assert format_value(n, spec) == format_plain_text(repr(n), spec or "s")


@pytest.mark.parametrize("text", ["REPRODUCED", "Fan et al.'s 44.7 m", 'a "quoted" word', "a\\b"])
def test_a_string_reads_as_glue_text_showed_it(text):
    assert format_value(text) == format_plain_text(repr(text), "s") == text
    assert format_value(text, "s") == text


def test_a_numpy_scalar_is_formatted_as_the_number_it_holds():
    assert format_value(np.float64(44.69474756323566), ".1f") == "44.7"
    assert format_value(np.float64(0.5)) == "0.5"          # not "np.float64(0.5)"
    assert format_value(np.int64(156)) == "156"
    assert format_value(np.int64(12_000), ",d") == "12,000"


def test_a_spec_that_does_not_apply_names_the_spec():
    with pytest.raises(ValueError, match=r"spec '\.1f' does not format the value 'abc'"):
        format_value("abc", ".1f")
    with pytest.raises(ValueError, match="spec must be"):
        format_value(1.0, 3)


@pytest.mark.parametrize("text", ["5,000", "it's", 'say "no"', "a\\b", "μs"])
def test_text_shows_as_written_in_ipython_and_repr(text):
    # an {eval} shows the value's text/plain: IPython's pretty printer, i.e. the repr
    assert repr(Text(text)) == text
    assert pretty(Text(text)) == text
    assert isinstance(Text(text), str) and Text(text) == text


def test_glued_entries_are_formatted_text():
    table = Glued()
    table.glue("ch99_x_m", 1234.5678)
    table.glue("ch99_n", 12)
    table.glue("ch99_verdict", "REPRODUCED")
    assert table["ch99_x_m:.1f"] == "1234.6" and isinstance(table["ch99_x_m:.1f"], Text)
    assert table["ch99_x_m:,.0f"] == "1,235"
    assert table["ch99_n"] == "12" and table["ch99_n:d"] == "12"
    assert repr(table["ch99_verdict"]) == "REPRODUCED"
    assert list(table) == ["ch99_x_m", "ch99_n", "ch99_verdict"] and len(table) == 3
    assert table.value("ch99_x_m") == 1234.5678
    table.glue("ch99_n", 13)  # glued again: the table holds the last value
    assert table["ch99_n"] == "13"


def test_a_missing_name_says_what_is_glued():
    table = Glued()
    table.glue("ch99_a", 1.0)
    with pytest.raises(KeyError, match=r"nothing glued as 'ch99_b' \(1 names glued: ch99_a\)"):
        table["ch99_b:.1f"]
    with pytest.raises(KeyError, match="nothing glued"):
        table.value("ch99_b")
    with pytest.raises(KeyError, match="'name' or 'name:spec'"):
        table[3]


@pytest.mark.parametrize("name", ["", "9lives", "ch 07", "ch07:x", None])
def test_a_name_must_be_an_identifier(name):
    with pytest.raises(ValueError, match="name must be an identifier"):
        Glued().glue(name, 1.0)


def test_glue_with_display_shows_the_value(capsys):
    Glued().glue("ch99_shown", 2.5, display=True)
    assert "2.5" in capsys.readouterr().out


def test_the_module_table_is_what_glue_fills():
    assert prose.glue.__self__ is prose.glued
    prose.glue("ch99_module_table", 3.0)
    assert prose.glued["ch99_module_table:.1f"] == "3.0"


@pytest.mark.parametrize("expr, ok", [
    ('glued["ch07_sigma_m:g"]', True),
    ('glued["ch07_sigma_m"]', True),
    ('glued["ch07_x:,.0f"]', True),
    ('glued["ch07_x:.0%"]', True),
    ("glued['ch07_x']", False),                # one spelling only: double quotes
    ('glued["ch07_x"].upper()', False),
    ('__import__("os").getcwd()', False),
    ('glued["ch07 x"]', False),
    ('x', False),
])
def test_the_book_evaluates_only_entries_of_the_table(expr, ok):
    assert bool(re.match(EVAL_NAME, expr)) is ok


def test_eval_expressions_finds_roles_in_prose_and_directives_not_in_code():
    cell = "\n".join([
        'The mean {eval}`glued["a:.0f"]` km, `{eval}` as code, {eval}`glued["b"]`.',
        "```{exercise}",
        ":label: ch99-ex1",
        "",
        'Inside: {eval}`glued["c:.1f"]` and `code {eval}` and ``{eval}`x` ``.',
        "```",
        "```python",
        'glued["d"]  # {eval}`glued["d"]` in a code block',
        "```",
        ":::{note}",
        'A note {eval}`glued["e"]`, again {eval}`glued["a:.0f"]`.',
        ":::",
        '| {eval}`glued["f"]` | {eval}``glued["g"]`` |',
    ])
    assert eval_expressions(cell) == ['glued["a:.0f"]', 'glued["b"]', 'glued["c:.1f"]',
                                      'glued["e"]', 'glued["f"]', 'glued["g"]']
    assert eval_expressions("No roles, `code`, {glue:text}`ch07_x:.1f`.") == []


@pytest.mark.parametrize("value", [float("nan"), float("inf"), -float("inf"), np.float64(np.nan),
                                   complex(1.0, float("nan"))])
@pytest.mark.parametrize("spec", ["", ".1f", "g", ".0%"])
def test_a_non_finite_number_never_reaches_the_prose(value, spec):
    # review 35d D23: glued["ch01_x:.1f"] gave the text "nan"; glue keeps the value, the entry
    # refuses it, naming itself
    table = Glued()
    table.glue("ch99_x", value)
    key = f"ch99_x:{spec}" if spec else "ch99_x"
    with pytest.raises(ValueError) as exc:
        table[key]
    words = str(exc.value)
    assert words.startswith(f"glued[{key!r}]: the non-finite value ") and len(words.splitlines()) == 1
    assert "would reach the prose" in words


@given(st.floats(allow_nan=False, allow_infinity=False, width=64).filter(lambda x: x != int(x)),
       st.sampled_from(["d", ",d", "x", "b"]))
def test_an_integer_spec_never_truncates_a_float(x, spec):
    # review 35d D24: format_value(1.5, "d") gave "1"
    with pytest.raises(ValueError, match=rf"^spec '{spec}' would truncate the value "):
        format_value(x, spec)


def test_a_whole_float_takes_an_integer_spec():
    assert format_value(3.0, "d") == "3" and format_value(np.float64(12000.0), ",d") == "12,000"


@pytest.mark.parametrize("display", ["no", 1, None])
def test_display_must_be_a_bool(display):  # review 35d D25: "no" displayed
    with pytest.raises(ValueError, match="display must be True or False"):
        Glued().glue("ch99_y", 1.0, display=display)


@pytest.mark.parametrize("markdown", [None, b"{eval}`glued[\"a\"]`", ["text"], 3])
def test_eval_expressions_refuses_what_is_no_str(markdown):  # review 35d D25: TypeError
    with pytest.raises(ValueError, match=r"^markdown must be a str \(a markdown cell's source\), "
                                         r"got "):
        eval_expressions(markdown)
