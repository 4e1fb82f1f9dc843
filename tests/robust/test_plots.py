"""The ephemeris-error figures (xnavlab.robust.plots)."""


import pytest


def test_plot_filter_comparison_is_a_pure_figure_and_checks_its_input():
    from xnavlab.robust import plots as rplots

    fig = rplots.plot_filter_comparison(300.0, 100.0, "all four")
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert labels == ["UKF", "ASUKF", "TDUKF", "RKF"]
    with pytest.raises(ValueError, match="pulsar_set"):
        rplots.plot_filter_comparison(300.0, 100.0, "three of them")
    with pytest.raises(ValueError, match="size"):
        rplots.plot_filter_comparison(-1.0)


def test_filter_comparison_gives_compare_filters_numbers_and_keeps_them():
    """The slider's cached runs equal one compare_filters call, also after an eps move."""
    import numpy as np

    from xnavlab.robust import comparison, filters
    from xnavlab.robust import plots as rplots

    key = "B0531+21, B1821-24, B1957+20"
    rplots.filter_comparison(700.0, 30.0, key)           # RKF at another eps, kept first
    out = rplots.filter_comparison(700.0, 300.0, key)
    ref = comparison.compare_filters("mars", error="growing", size=700.0, eps=300.0,
                                     pulsar_names=rplots.PULSAR_SETS[key], seeds=(0,))
    assert out["rmse"] == ref["rmse"]
    assert np.array_equal(out["tau"], ref["tau"])
    for f in filters.FILTERS:
        assert np.array_equal(out["error"][f], ref["error"][f])
    again = rplots.filter_comparison(700.0, 300.0, key)
    assert again["error"]["rkf"] is out["error"]["rkf"]   # the kept run, not a new one
    with pytest.raises(ValueError, match="eps"):
        rplots.filter_comparison(700.0, 0.0, key)


def test_bound_table_gives_compare_bounds_numbers_and_stores_them(tmp_path, monkeypatch):
    """Each case's rows are compare_bounds' (the real error with the prior from the ephemeris
    difference); a second call reads the disk cache; bad arguments name themselves."""
    from xnavlab.robust import coverage
    from xnavlab.robust import plots as rplots

    monkeypatch.setenv("XNAVLAB_CACHE", str(tmp_path))
    kw = {"seeds": (0,), "sources": ("residual", "prior"), "n_steps": 40}
    table = rplots.bound_table(**kw)
    assert list(table) == list(rplots.BOUND_CASES)
    real = coverage.compare_bounds((0,), ("residual", "prior"), body="mars", error="de405",
                                   n_steps=40, bias_max=coverage.prior_bias_max("mars", span=40 * 500.0))
    for got, ref in zip(table["real DE421 - DE405 error"], real, strict=True):
        assert got["source"] == ref["source"] and got["is_bound"] == ref["is_bound"]
        for k in rplots.BOUND_STATS:
            assert got[k] == pytest.approx(ref[k], rel=1e-12)
    assert len(list(tmp_path.glob("bound-table-*.npz"))) == 1
    monkeypatch.setattr(coverage, "compare_bounds", None)   # a cache hit computes nothing
    assert rplots.bound_table(**kw) == table
    for bad, message in (({"seeds": ()}, r"^seeds must name at least one seed"),
                         ({"seeds": (0, 0.5)}, r"^seeds\[1\] must be an integer"),
                         ({"seeds": "0"}, r"^seeds must be a list of seeds, got the string '0'"),
                         ({"sources": ("prior", "kalman")}, r"^sources\[1\] must be one of"),
                         ({"sources": "prior"}, r"^sources must be a list of sources, got the string"),
                         ({"sources": ("prior", "prior")}, r"^sources lists prior twice"),
                         ({"n_steps": 1}, r"^n_steps")):
        with pytest.raises(ValueError, match=message):
            rplots.bound_table(**{**kw, **bad}, cache=False)


def test_bound_table_html_has_one_escaped_row_per_case_and_source():
    from xnavlab.robust import plots as rplots

    row = {"source": "residual", "coverage": 0.099, "median_ratio": 4.74, "nees": 145.3,
           "rmse_m": 1738.0, "median_sigma_m": 333.0, "is_bound": False}
    page = rplots.bound_table_html({"a <case>": [row, {**row, "source": "ukf"}]})
    assert page.count("<tr>") == 3 and "a &lt;case&gt;" in page
    assert "9.9" in page and "1.74" in page and ">no<" in page


def test_bound_table_takes_cache_as_a_bool_only():
    """Review 35e: cache="no" read and wrote the disk cache (a non-empty string is true)."""
    from xnavlab.robust import plots as rplots

    with pytest.raises(ValueError, match=r"^cache must be True or False, got 'no'$"):
        rplots.bound_table(seeds=(0,), sources=("prior",), n_steps=40, cache="no")


@pytest.mark.parametrize(("table", "words"), [
    ([], r"^table must be bound_table\(\)'s dict"), (True, r"^table must be bound_table\(\)'s dict"),
    ({"case": [{"source": "prior"}]}, r"^table\['case'\]\[0\] must be a bound row"),
])
def test_bound_table_html_names_the_table(table, words):
    from xnavlab.robust import plots as rplots

    with pytest.raises(ValueError, match=words):
        rplots.bound_table_html(table)


def test_bound_table_html_refuses_nan_and_a_non_bool_is_bound():
    """Review 35i: a NaN rendered as "nan" and is_bound "no" rendered as yes."""
    from xnavlab.robust import plots as rplots

    row = {"source": "prior", "coverage": 1.0, "median_ratio": 0.3, "nees": 0.4, "rmse_m": 1172.7,
           "median_sigma_m": 3092.0, "is_bound": True}
    with pytest.raises(ValueError, match=r"^table\['real'\]\[0\]\['coverage'\] must be a real number"):
        rplots.bound_table_html({"real": [dict(row, coverage=float("nan"))]})
    with pytest.raises(ValueError, match=r"^table\['real'\]\[0\]\['nees'\] must be"):
        rplots.bound_table_html({"real": [dict(row, nees=float("inf"))]})
    with pytest.raises(ValueError, match=r"^table\['real'\]\[0\]\['is_bound'\] must be True or False"):
        rplots.bound_table_html({"real": [dict(row, is_bound="no")]})
