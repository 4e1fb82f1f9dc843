"""core.plotting tables: no cell's content can break a row (markdown escapes, HTML escapes)."""

from html.parser import HTMLParser

import pytest

from xnavlab.core.plotting import SafeHTML, html_table, markdown_table


def test_markdown_table_escapes_pipes_and_newlines():
    text = markdown_table([{"a|b": "x | y", "b": "two\nlines"}, {"a|b": "pre\\|escaped", "b": 1.5}],
                          ["a|b", "b"])
    lines = text.splitlines()
    assert lines == ["| a\\|b | b |", "|---|---|", "| x \\| y | two lines |",
                     "| pre\\|escaped | 1.5 |"]
    for line in lines:  # every row has exactly two cell separators between its borders
        assert line.replace("\\|", "").count("|") == 3


def test_markdown_table_accepts_sequences():
    assert markdown_table([(1, None)], ["a", "b"]).splitlines()[-1] == "| 1 | - |"
    with pytest.raises(ValueError, match="rows"):
        markdown_table([(1,)], ["a", "b"])


class _Cells(HTMLParser):
    def __init__(self):
        super().__init__()
        self.rows, self.text = [], None

    def handle_starttag(self, tag, attrs):
        if tag == "tr":
            self.rows.append([])
        elif tag in ("td", "th"):
            self.text = []

    def handle_endtag(self, tag):
        if tag in ("td", "th"):
            self.rows[-1].append("".join(self.text))
            self.text = None

    def handle_data(self, data):
        if self.text is not None:
            self.text.append(data)


def test_html_table_escapes_every_cell():
    nasty = ["a | b", "<td>x</td>", "1 & 2\nthree", "</table>"]
    page = html_table(["c|1", "<c2>"], [nasty[:2], {"c|1": nasty[2], "<c2>": nasty[3]},
                                        [0.123456, None]], digits=3)
    assert isinstance(page, SafeHTML) and page._repr_html_() == page
    assert page.count("<table") == 1 and page.count("</table>") == 1
    assert page.count("<tr>") == 4 and page.count("<td>") == 6
    parser = _Cells()
    parser.feed(page)
    assert parser.rows == [["c|1", "<c2>"], nasty[:2], nasty[2:], ["0.123", "-"]]


def test_html_table_checks_its_arguments():
    with pytest.raises(ValueError, match="rows"):
        html_table(["a", "b"], [[1, 2, 3]])
    with pytest.raises(ValueError, match="missing"):
        html_table(["a", "b"], [{"a": 1}])
    with pytest.raises(ValueError, match="digits"):
        html_table(["a"], [[1]], digits=0)


def test_sparse_log_minors_reach_log_axes_and_secondary_axes_only():
    from matplotlib.ticker import LogLocator

    from xnavlab.core.plotting import LOG_MINOR_SUBS, figure, sparse_log_minors

    fig, (lin, log) = figure(1, 2)
    log.set(yscale="log", ylim=(1e-4, 1e3))
    sec = log.secondary_yaxis("right", functions=(lambda u: 2.0 * u, lambda m: m / 2.0))
    default_lin = lin.yaxis.get_minor_locator()
    sparse_log_minors(lin, log)
    assert lin.yaxis.get_minor_locator() is default_lin
    for axis in (log.yaxis, sec.yaxis):
        locator = axis.get_minor_locator()
        assert isinstance(locator, LogLocator)
        inside = [float(v) for v in locator.tick_values(1.0, 1e3) if 1.0 < v < 1e3]
        assert inside == [s * 10.0**k for k in range(3) for s in LOG_MINOR_SUBS]
    ticks = [v for v in log.yaxis.get_minorticklocs() if 1e-4 < v < 1e3]
    assert len(ticks) == 2 * 7


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), float("-inf")])
def test_a_table_refuses_a_non_finite_cell_naming_its_row_and_column(bad):
    for table in (lambda rows: html_table(["a", "b"], rows),
                  lambda rows: markdown_table(rows, ["a", "b"])):
        with pytest.raises(ValueError, match=r"rows\[1\]\['b'\] is .*inf|rows\[1\]\['b'\] is nan"):
            table([[1, 2.0], [3, bad]])
    assert "-" in html_table(["a"], [[None]])   # a missing value is None


def test_figure_names_a_misspelt_subplots_keyword():
    """Review 35j (1) 2-4, the class: figure's **kwargs went to Figure.subplots unchecked."""
    from xnavlab.core.plotting import figure

    with pytest.raises(ValueError, match=r"^sharx is not a keyword of figure or of FigureBase.subplots, "
                                         r".*\(did you mean sharex\?\)"):
        figure(1, 2, sharx=True)
    assert figure(1, 2, sharex=True)[1].shape == (2,)


def test_check_axes_is_the_rule_of_every_plots_ax():
    """Review 35m (1) 3: one rule for ax: a 2-D rectilinear Axes of a figure (3-D, polar and
    removed Axes were matplotlib's TypeError, NotImplementedError, AttributeError mid-plot)."""
    from matplotlib.figure import Figure

    from xnavlab.core.plotting import check_axes, sparse_log_minors

    fig = Figure()
    ax = fig.add_subplot(2, 2, 1)
    assert check_axes("ax", ax) == (fig, ax)
    inset = ax.inset_axes([0.5, 0.5, 0.3, 0.3])
    assert check_axes("ax", inset) == (fig, inset)  # a child Axes belongs to the figure
    sub = Figure()
    sub_ax = sub.subfigures(1, 2)[1].subplots()
    assert check_axes("ax", sub_ax) == (sub, sub_ax)  # a subfigure's: its root figure
    for bad, why in ((fig.add_subplot(2, 2, 2, projection="3d"), "got a '3d' Axes"),
                     (fig.add_subplot(2, 2, 3, projection="polar"), "got a 'polar' Axes"),
                     ("ax", "got str 'ax'"), (fig, "got Figure")):
        with pytest.raises(ValueError, match=rf"^axes\[1\] must be a 2-D rectilinear matplotlib Axes, {why}"):
            check_axes("axes[1]", bad)
    gone = fig.add_subplot(2, 2, 4)
    gone.remove()
    with pytest.raises(ValueError, match=r"^ax must be a 2-D rectilinear matplotlib Axes of a figure, "
                                         r"got an Axes removed"):
        check_axes("ax", gone)
    with pytest.raises(ValueError, match=r"^axes\[1\] must be an Axes of the same figure as the others"):
        check_axes("axes[1]", sub_ax, fig)
    with pytest.raises(ValueError, match=r"^axes\[1\] must be a 2-D rectilinear matplotlib Axes, got str"):
        sparse_log_minors(ax, "x")  # was AttributeError 'no attribute child_axes'


def test_figure_and_a_frame_refuse_a_figsize_of_too_many_pixels():
    """Review 35 Q13: figure(figsize=(150, 150)) was passed on unchecked, and one frame of it
    took 10.6 s and about 1 GB ((600, 600): about 15 GB)."""
    from matplotlib.figure import Figure

    from xnavlab.core.plotting import MAX_PIXELS, check_figsize, figure
    from xnavlab.core.widgets import live_png

    with pytest.raises(ValueError, match=r"^figsize must make 1 to 50,000,000 pixels at 100 dpi "
                                         r".*got \(150, 150\) inches: 225,000,000 pixels$"):
        figure(figsize=(150, 150))
    with pytest.raises(ValueError, match=r"^figsize must make 1 to 50,000,000 pixels at 100 dpi"):
        figure(figsize=(1e-3, 5.0))  # not one pixel wide
    with pytest.raises(ValueError, match=r"^figsize must be a pair \(width, height\) of inches"):
        figure(figsize=6.0)
    with pytest.raises(ValueError, match=r"^figsize\[1\] must be a real number in \(0, inf\), got nan$"):
        figure(figsize=(6.0, float("nan")))
    fig, _ = figure(figsize=(6, 3.5))
    assert tuple(fig.get_size_inches()) == (6.0, 3.5)
    assert check_figsize((70, 70), 100) == (70.0, 70.0) and 70 * 70 * 100**2 <= MAX_PIXELS
    with pytest.raises(ValueError, match=r"^figsize must make 1 to 50,000,000 pixels at 100 dpi"):
        live_png(Figure(figsize=(150, 150), dpi=100))
    with pytest.raises(ValueError, match=r"^figsize must make 1 to 50,000,000 pixels at 1000 dpi"):
        from xnavlab.core.widgets import SteadyLayout

        SteadyLayout().png(Figure(figsize=(10, 10)), dpi=1000)
