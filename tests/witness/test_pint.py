"""The time-transfer terms against PINT, for a spacecraft around Mars.

PINT evaluates its delays at the spacecraft positions we give it (its ``spacecraft``
observatory, :func:`xnavlab.mars.timing.pint_bridge.pint_delays`), for the paper's four pulsars
at several epochs and positions around Mars. Each tolerance states the agreement measured
when it was set; the bounds keep a margin of ten or more above it.
"""

import numpy as np
import pytest

from xnavlab.core import ephemeris
from xnavlab.mars.models import dynamics
from xnavlab.mars.timing import pint_bridge, pulsars, toa

pytestmark = pytest.mark.witness

N, D = pulsars.directions()


@pytest.fixture(scope="module")
def case():
    """Twelve epochs over two Mars years, each at a different point of a 4000-km sphere."""
    rng = np.random.default_rng(7)
    t = dynamics.MARS_T0 + np.linspace(-2.0e7, 6.0e7, 12)
    u = rng.normal(size=(12, 3))
    r = 4.0e6 * u / np.linalg.norm(u, axis=1)[:, None] + ephemeris.position("mars", t)
    return t, r, pint_bridge.pint_delays(r, t, N, D, planets=True)


def test_pint_evaluates_where_we_ask(case):
    t, r, out = case
    # PINT's DE421 (skyfield-data's SPK file) against ours (the de421 package): measured 31 um, 28 um
    assert np.abs(out["r_ssb"] - r).max() < 1e-3
    assert np.abs(out["r_sun_ssb"] - ephemeris.position("sun", t)).max() < 1e-3


def test_roemer_against_pint(case):
    _, r, out = case
    # measured 0.23 ps (float64 rounding of 500-s numbers: 0.06-0.11 ps per ulp)
    assert np.abs(toa.roemer(r, N) - out["roemer"]).max() < 5e-12


def test_parallax_against_pint(case):
    _, r, out = case
    assert np.all(out["parallax"] < 0) and np.abs(out["parallax"]).max() > 1e-7  # a real term
    # measured 0.056 ps: PINT's difference of two 500-s delays, rounding-limited
    assert np.abs(toa.parallax(r, N, D) - out["parallax"]).max() < 2e-12


def test_exact_shapiro_against_pint_after_the_reference_offset(case):
    t, r, out = case
    r_sun = ephemeris.position("sun", t)
    ours = toa.shapiro(r, N, r_sun) - toa.shapiro_offset_to_pint(N, r_sun)
    # measured 0.01 ps (PINT's GM_sun differs from ours by 3e-11 relative)
    assert np.abs(ours - out["shapiro"]).max() < 1e-12
    # the paper's form is another function: measured 0.46 ns to 6.3 us away here
    paper = toa.shapiro_paper(r, N, r_sun) - toa.shapiro_offset_to_pint(N, r_sun)
    assert np.abs(paper - out["shapiro"]).max() > 1e-10


def test_planets_shapiro_on_the_paper_orbit():
    """Jupiter, Saturn, Venus, Uranus and Neptune: tens of ns, and their orbit-periodic part tiny."""
    grid = dynamics.MARS_T0 + np.arange(0.0, 30 * 86400.0 + 1.0, 60.0)  # the chapters' cached truth
    t, x = grid[::4320], dynamics.truth(grid)[::4320]  # every third day
    r = ephemeris.position("mars", t) + x[:, :3]
    planets = pint_bridge.planet_shapiro(r, t, N)
    total = planets["total"]
    assert total.shape == (t.size, 4)
    np.testing.assert_allclose(total, sum(planets[p] for p in pint_bridge.PLANETS), rtol=1e-15)
    # measured 16.9-24.4 ns (referred to 1 au, PINT's convention; Jupiter 9.5-17.7 ns)
    assert np.all((total > 5e-9) & (total < 1e-7))


def test_planets_must_be_a_bool():  # review 35d D21
    r = np.array([1.5e11, 1e10, 1e9])
    with pytest.raises(ValueError, match="planets must be True or False, got .no."):
        pint_bridge.pint_delays(r, dynamics.MARS_T0, N[:1], planets="no")


@pytest.mark.parametrize(("content", "words"), [
    (b"PSR J0000\xff\n", "is not UTF-8 text (byte 0xff at position 9)"),
    (b"", "PINT cannot read the timing model"),
    (b"hello world\nF0 abc\n", "PINT cannot read the timing model"),
])
def test_timing_parameters_names_the_file_it_cannot_read(tmp_path, content, words):
    # review 35d D19: a raw codec error, PINT's AssertionError, a message without the file
    path = tmp_path / "bad.par"
    path.write_bytes(content)
    with pytest.raises(ValueError) as info:
        pint_bridge.timing_parameters(path)
    assert words in str(info.value) and str(path) in str(info.value)
    with pytest.raises(ValueError, match="a str or Path"):
        pint_bridge.timing_parameters(5)


def test_pint_delays_names_t_and_n_in_its_own_words():  # review 35d D20
    r = np.array([1.5e11, 1e10, 1e9])
    with pytest.raises(ValueError, match=r"t must lie in \[.*the coverage of DE421"):
        pint_bridge.pint_delays(r, -1e12, N[:1])
    with pytest.raises(ValueError, match=r"n must hold unit vectors, but n\[0\] has norm 5"):
        pint_bridge.pint_delays(r, dynamics.MARS_T0, 5 * N[:1])


@pytest.mark.parametrize("bad", [{}, None, 3, ""])
def test_examples_path_refuses_what_is_no_file_name(bad):  # review 35d D37's class: TypeError
    with pytest.raises(ValueError, match=r"^name must be a file name in PINT's examples, got "):
        pint_bridge.examples_path(bad)


@pytest.mark.parametrize("name", ["nope.par", "B1855+09_NANOGrav_9yv1.gls.pa", "../__init__.py", ".."])
def test_examples_path_names_a_file_pint_does_not_ship(name):
    """Review 35j (1) 24: a file PINT does not ship was a FileNotFoundError; a path that climbs
    out of the examples ('../__init__.py') was returned."""
    with pytest.raises(ValueError, match=r"^name must be an example file PINT [\d.]+ ships, got .*; the \d+ "
                                         r"files in .*: B1855\+09_NANOGrav_9yv1\.gls\.par, "):
        pint_bridge.examples_path(name)
    if name.endswith(".gls.pa"):
        with pytest.raises(ValueError, match=r"\(nearest: 'B1855\+09_NANOGrav_9yv1\.gls\.par'\)"):
            pint_bridge.examples_path(name)


@pytest.mark.parametrize("name", ["x" * 300, "a\x00b", "B1855+09_NANOGrav_9yv1.tim/"])
def test_review_35k_1_21_examples_path_names_the_os_refuses(name):
    """Review 35k (1) 21: a name the OS refuses (300 characters) was an OSError 'File name too
    long' (a NUL a ValueError of the file system): looked up among the files, never opened."""
    with pytest.raises(ValueError, match=r"^name must be an example file PINT [\d.]+ ships, got "):
        pint_bridge.examples_path(name)
