"""The Mars scenario: numba = numpy, filter consistency (NEES/NIS), the 30-day run, the CLI."""

import dataclasses
import json
import os
import subprocess
import sys

import numpy as np
import pytest

from xnavlab import reproduce
from xnavlab.cli import main
from xnavlab.mars.kernel.kernels import FilterDivergence
from xnavlab.mars.models import series
from xnavlab.mars.navigation import plots as mars_plots
from xnavlab.mars.navigation import scenarios

SHORT = dict(days=0.02, record_dt=3.0)   # 576 epochs, three XNAV updates


def _rel(a, b):
    """Largest difference relative to the size of the state (position and velocity apart)."""
    pos = np.abs(a[:, :3] - b[:, :3]).max() / np.abs(b[:, :3]).max()
    vel = np.abs(a[:, 3:] - b[:, 3:]).max() / np.abs(b[:, 3:]).max()
    return max(pos, vel)


# record_dt = 3 s records every epoch: the kernel runs the locals in full at every epoch;
# 60 s (as the 30-day run): in reset mode it fuses through the information identity at 19
# epochs of 20 (xnavlab.mars.kernel.kernels), so both forms are compared with the numpy loop.
@pytest.mark.parametrize("record_dt", [3.0, 60.0])
@pytest.mark.parametrize("mode", ["reset", "no-reset"])
def test_numba_and_numpy_give_the_same_estimates(mode, record_dt):
    inp = scenarios.prepare(mode=mode, **(SHORT | {"record_dt": record_dt}))
    a = scenarios.run(inputs=inp, backend="numba")
    b = scenarios.run(inputs=inp, backend="numpy")
    assert _rel(a.x, b.x) < 1e-9
    assert _rel(a.x_local.reshape(-1, 6), b.x_local.reshape(-1, 6)) < 1e-9
    np.testing.assert_allclose(a.P, b.P, rtol=1e-6, atol=1e-9 * np.abs(b.P).max())
    np.testing.assert_allclose(a.P_local_diag, b.P_local_diag, rtol=1e-6)
    np.testing.assert_allclose(a.nis, b.nis, rtol=1e-6, equal_nan=True)
    assert np.array_equal(a.flags, b.flags)


@pytest.mark.parametrize("record_dt", [3.0, 60.0])
def test_numba_and_numpy_agree_with_switching_and_gating(record_dt):
    inp = scenarios.prepare(**(SHORT | {"record_dt": record_dt}))
    active = np.ones((inp.n, 3), dtype=bool)
    active[100:300, 1] = False          # UV switched out, then back in
    active[250:400, 0] = False          # XNAV out across its 1000-s update
    active[450:460] = False             # everything out: the master coasts
    gate = [np.inf, np.inf, 4.0]        # CNS rejects innovations with NIS > 4
    a = scenarios.run(inputs=inp, backend="numba", active=active, gate=gate)
    b = scenarios.run(inputs=inp, backend="numpy", active=active, gate=gate)
    assert _rel(a.x, b.x) < 1e-9
    np.testing.assert_allclose(a.nis, b.nis, rtol=1e-6, equal_nan=True)
    assert np.array_equal(a.flags, b.flags)
    assert not (a.flags[100:300, 1] == 1).any() and (a.flags[100:300, 1] == 3).sum() > 190
    assert (a.flags[:, 2] == 2).any()


@pytest.mark.parametrize("record_dt", [3.0, 60.0])
def test_numba_and_numpy_agree_for_other_measurement_sizes(record_dt):
    """Two stars and three pulsars: the kernel's code for any measurement size."""
    inp = scenarios.prepare(days=0.02, record_dt=record_dt, stars=("Sirius", "Vega"),
                            pulsars=("B0531+21", "B1937+21", "B1821-24"))
    a = scenarios.run(inputs=inp, backend="numba")
    b = scenarios.run(inputs=inp, backend="numpy")
    assert _rel(a.x, b.x) < 1e-9
    np.testing.assert_allclose(a.nis, b.nis, rtol=1e-6, equal_nan=True)
    assert np.array_equal(a.flags, b.flags)


def test_kernel_in_chunks_equals_one_call():
    """The fault-tolerant runs call the kernel epoch range by epoch range on one state."""
    inp = scenarios.prepare(days=0.02, record_dt=60.0)
    whole = scenarios.run(inputs=inp)
    active, gate, beta = scenarios.run_options(inp, None, None)
    out = scenarios.alloc_records(inp)
    rec_pos = np.full(inp.n, -1, dtype=np.int64)
    rec_pos[inp.record] = np.arange(inp.record.size)
    state = scenarios.filter_state(inp, beta)
    records = (out["x"], out["P"], out["xl"], out["Pl"])
    for a, b in [(0, 1), (1, 137), (137, 138), (138, 400), (400, inp.n)]:
        scenarios.run_kernel(inp, state, a, b, active, beta, gate, rec_pos, records,
                             out["nis"], out["flags"])
    assert _rel(out["x"], whole.x) < 1e-12
    np.testing.assert_allclose(out["nis"], whole.nis, rtol=1e-9, equal_nan=True)


def test_compiled_measurement_series_equal_the_sensor_models():
    rng = np.random.default_rng(7)
    r = rng.normal(size=(500, 3)) * 4e6
    r[0] = [0.0, 0.0, 4e6]                       # along z: the other tangent basis
    r[1] = [1e-3, 0.0, -4e6]
    states = np.hstack([r, rng.normal(size=(500, 3))])
    sc = scenarios.MarsScenario()
    sens = sc.sensors()
    uv, cns = sens["uv"], sens["cns"]
    w_uv, w_cns = rng.standard_normal((500, 3)), rng.standard_normal((500, 2 + 2 * cns.dim))
    z_uv = series.simulate_uv(states, w_uv, uv.sigma_range, uv.sigma_dir, np.empty((500, 4)))
    z_cns = series.simulate_cns(states, w_cns, cns.star_dirs, cns.sigma_star,
                                 cns.sigma_horizon, np.empty((500, cns.dim)))
    # same operations; the sine, cosine and arctangent may differ in the last bit
    np.testing.assert_allclose(z_uv, uv.simulate(states, noise=w_uv), rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(z_cns, cns.simulate(states, noise=w_cns), rtol=0, atol=1e-14)


def test_prepare_draws_the_series_as_one_draw(monkeypatch):
    """Chunked draws give the noise of one ``standard_normal((n, k))`` call, in order."""
    monkeypatch.setattr(scenarios, "_CHUNK", 100)      # several chunks on a short run
    inp = scenarios.prepare(days=0.02, seed=5)
    sens = inp.sensors
    rng = np.random.default_rng(5)
    k = {s: np.searchsorted(inp.times, inp.t_meas[s]) for s in scenarios.SUBSYSTEMS}
    rng.standard_normal((k["xnav"].size, sens["xnav"].dim))  # the XNAV draws come first
    w_uv = rng.standard_normal((k["uv"].size, 3))
    w_cns = rng.standard_normal((k["cns"].size, 2 + 2 * sens["cns"].dim))
    np.testing.assert_allclose(inp.z["uv"], sens["uv"].simulate(inp.truth[k["uv"]], noise=w_uv),
                               rtol=1e-13)
    np.testing.assert_allclose(inp.z["cns"],
                               sens["cns"].simulate(inp.truth[k["cns"]], noise=w_cns), atol=1e-14)


def test_import_is_light():
    """Importing the package, the Mars scenario and the CLI compiles nothing, loads no ephemeris."""
    code = ("import sys, xnavlab, xnavlab.cli, xnavlab.cli.runners\n"
            "assert 'numba' not in sys.modules, 'import xnavlab pulls numba'\n"
            "from xnavlab.mars.kernel import kernels\n"
            "from xnavlab.mars.models import series\n"
            "from xnavlab.mars.navigation import scenarios\n"
            "assert not kernels.run_epochs.signatures and not series.simulate_uv.signatures\n"
            "assert 'jplephem' not in sys.modules and 'scipy.stats' not in sys.modules\n")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=False)
    assert proc.returncode == 0, proc.stderr


def test_switching_out_costs_accuracy_but_stays_consistent():
    inp = scenarios.prepare(days=0.2, record_dt=60.0)
    full = scenarios.run(inputs=inp)
    active = np.ones((inp.n, 3), dtype=bool)
    active[:, 1:] = False                                    # XNAV alone
    xnav = scenarios.run(inputs=inp, active=active)
    assert xnav.metrics(0.1)["position_error_m"] > full.metrics(0.1)["position_error_m"]
    eig = np.linalg.eigvalsh(xnav.P)
    assert np.all(eig[:, 0] > 1e-12 * eig[:, -1])  # PD far above rounding


def test_prepare_is_reproducible_and_seeded():
    a = scenarios.prepare(days=0.01, seed=3)
    b = scenarios.prepare(days=0.01, seed=3)
    c = scenarios.prepare(days=0.01, seed=4)
    for s in ("xnav", "uv", "cns"):
        assert np.array_equal(a.z[s], b.z[s])
        assert not np.array_equal(a.z[s], c.z[s])
    assert a.times[0] == scenarios.MarsScenario().t0
    assert np.allclose(a.x0 - a.truth[0], [5000, 5000, 5000, 1, 1, 1])


def test_grid_holds_every_sensor_epoch():
    inp = scenarios.prepare(days=0.02)
    off = inp.times - inp.times[0]
    assert set(np.arange(3.0, 1728.1, 3.0)) <= set(np.round(off, 6))
    assert set(np.round(inp.t_meas["xnav"] - inp.times[0], 6)) == {500.0, 1000.0, 1500.0}
    assert np.all(np.diff(inp.times) > 0)


def test_thirty_day_reproduction_runs_and_covariance_stays_spd():
    res = reproduce.run("mars-nofault")
    res.assert_ok()
    assert res.ours["covariance SPD over the run (smallest eigenvalue)"] > 0
    assert res.check("fused position error (m), RMS after day 1").claimed
    assert res.data["position_error"].size == 43201


def test_scenario_validation():
    with pytest.raises(ValueError, match=r"days must be a real number in \(0, 365\]"):
        scenarios.MarsScenario(days=0)
    with pytest.raises(ValueError, match="subsystem"):
        scenarios.MarsScenario(subsystems=("gps",))
    with pytest.raises(ValueError, match="xnav_sigma_m must hold 4"):
        scenarios.MarsScenario(xnav_sigma_m=(100.0,))
    inp = scenarios.prepare(days=0.01)
    with pytest.raises(ValueError, match=r"active must hold True/False flags \(or 1/0\), shape "
                                         r"\(290, 3\) .*, got shape \(3, 3\)$"):
        scenarios.run(inputs=inp, active=np.ones((3, 3), bool))
    with pytest.raises(ValueError, match="backend"):
        scenarios.run(inputs=inp, backend="fortran")


def test_filter_ephemeris_may_differ_from_truth():
    same = scenarios.run(days=0.1)
    other = scenarios.run(days=0.1, filter_ephem="de405")
    assert np.all(np.isfinite(other.x))
    assert not np.array_equal(same.x, other.x)


def test_cli_json_and_out(tmp_path, capsys):
    assert main(["run", "mars", "--days", "0.05", "--seed", "2", "--json",
                 "--out", str(tmp_path)]) == 0
    payload = json.loads(capsys.readouterr().out)
    assert {"position_error_m", "velocity_error_mps", "run_time_s"} <= set(payload)
    assert payload["seed"] == 2
    data = np.load(tmp_path / "mars_run.npz")
    assert data["x"].shape[1] == 6 and data["position_error"].size == data["t"].size
    assert json.loads((tmp_path / "mars_summary.json").read_text())["days"] == 0.05


@pytest.mark.parametrize("argv,word", [
    (["--days", "-1"], "days"), (["--days", "abc"], "days"), (["--seed", "x"], "seed"),
    (["--seed", "-3"], "seed"), (["--mode", "sometimes"], "mode"), (["--bogus"], "bogus"),
])
def test_cli_bad_values_one_line_exit_2(argv, word, capsys):
    assert main(["run", "mars", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and word in err


def test_cli_module_entry_point():
    proc = subprocess.run([sys.executable, "-m", "xnavlab", "run", "mars", "--days", "-1"],
                          capture_output=True, text=True, check=False)
    assert proc.returncode == 2
    assert proc.stderr.strip().startswith("xnavlab: error: --days")


def test_plot_subsystem_is_the_single_subsystem_run():
    fig = mars_plots.plot_subsystem("uv", 2.0, 6, days=0.05)
    band, line = fig.axes[0].collections[0], fig.axes[0].lines[0]
    res = scenarios.run(days=0.05, subsystems=("uv",), record_dt=30.0, sigma_range_m=1e4,
                        sigma_dir_deg=0.2, dt_uv=6.0)
    np.testing.assert_allclose(line.get_ydata(), res.position_error())
    assert fig.axes[0].get_title() == "uv: noise x 2, every 6 s"
    assert band.get_paths()  # the 3-sigma band is drawn
    # XNAV never updates faster than every 30 s
    assert mars_plots.plot_subsystem("xnav", 1.0, 3, days=0.02).axes[0].get_title().endswith("30 s")
    with pytest.raises(ValueError, match="subsystem"):
        mars_plots.plot_subsystem("gps")
    with pytest.raises(ValueError, match="noise_scale"):
        mars_plots.plot_subsystem("uv", 0.0)


def test_plot_sharing_reset_mode_ignores_the_shares():
    def error(beta, mode):
        return mars_plots.plot_sharing(beta, mode, days=0.05).axes[0].lines[0].get_ydata()

    np.testing.assert_allclose(error(0.2, "reset"), error(0.8, "reset"), rtol=1e-3)
    assert not np.allclose(error(0.2, "no-reset"), error(0.8, "no-reset"), rtol=1e-3)
    with pytest.raises(ValueError, match="beta_xnav"):
        mars_plots.plot_sharing(1.0)
    with pytest.raises(ValueError, match="mode"):
        mars_plots.plot_sharing(0.5, "sometimes")


# ------------------------------------------- faults on the command line (run mars --faults)


def test_cli_faults_json_lists_faults_and_detections(capsys):
    spec = "uv.range:step:40000@50000+3000,xnav.1:ramp:2e-9@60000+5000"
    assert main(["run", "mars", "--days", "1", "--faults", spec, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["detector"] == "combined"
    assert [f["spec"] for f in out["faults"]] == ["uv.range:step:40000@50000+3000",
                                                  "xnav.B1937:ramp:2e-09@60000+5000"]
    assert all(set(d) == {"sensor", "detected_onset", "detected_end", "detector"}
               for d in out["detections"])
    uv = [d for d in out["detections"] if d["sensor"] == "uv"]
    assert 50000.0 <= uv[0]["detected_onset"] < 50300.0
    assert {"position_error_m", "velocity_error_mps"} <= set(out)


def test_cli_faults_paper_needs_the_days_of_its_last_onset(capsys):
    """A schedule whose faults lie after the run's end is refused, never cut in silence."""
    assert main(["run", "mars", "--days", "7", "--faults", "paper", "--json"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "run at least --days 27.84 (this run: 7 days)" in err
    assert main(["run", "mars", "--days", "2", "--faults", "xnav:step:1e-5@500000+5000"]) == 2
    err = capsys.readouterr().err.strip()
    assert "outside this run [0, 172800) s" in err and "--days 5.85" in err


def test_cli_faults_of_the_paper_with_chi2(capsys):
    from xnavlab.core.faults import format_spec
    from xnavlab.mars.faults.fault_tolerance import components, paper_schedule

    first_two = format_spec(paper_schedule()[:2], components())
    assert main(["run", "mars", "--days", "7", "--faults", first_two, "--detector", "chi2",
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["detector"] == "chi2"
    assert [f["onset"] for f in out["faults"]] == [500000.0, 600000.0]
    sensors = {d["sensor"] for d in out["detections"] if d["detected_onset"] >= 500000.0}
    assert {"xnav", "cns"} <= sensors


@pytest.mark.parametrize("spec,part", [
    ("uv.range:step:5000@700000", "uv.range:step:5000@700000"),
    ("uv.range:step:5000@1+2,foo:step:1@1+1", "foo"),
    ("uv.range:jump:5000@1+2", "kind"),
    ("cns.angle9:step:1@1+2", "angle9"),
])
def test_cli_malformed_fault_spec_is_one_line_exit_2(spec, part, capsys):
    assert main(["run", "mars", "--days", "0.01", "--faults", spec]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and part in err


def test_cli_bad_detector_is_one_line_exit_2(capsys):
    assert main(["run", "mars", "--days", "0.01", "--detector", "median"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "detector" in err


def test_cli_out_that_is_a_file_is_one_line_exit_2(tmp_path, capsys):
    path = tmp_path / "taken"
    path.write_text("")
    assert main(["run", "mars", "--days", "0.05", "--out", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "out must be a directory" in err


def test_fault_spec_takes_full_pulsar_names_and_help_lists_the_grammar(capsys):
    from xnavlab.cli.runners import FAULT_HELP
    from xnavlab.mars.faults.fault_tolerance import parse_faults

    full, = parse_faults("xnav.B1937+21:step:1e-5@200000+5000")
    short, = parse_faults("xnav.B1937:step:1e-5@200000+5000")
    assert full == short and full.component == 1 and full.duration == 5000.0
    for word in ("xnav", "uv", "cns", "range", "angle0", "B1937+21", "step", "ramp", "spike",
                 "stuck", "noise", "rad", "example:"):
        assert word in FAULT_HELP
    with pytest.raises(SystemExit):
        main(["run", "mars", "--help"])
    assert "fault spec:" in capsys.readouterr().out


def test_python_and_cli_summaries_of_the_same_run_are_equal(capsys):
    """One source of defaults: the API's summary() settles as the command line does."""
    from xnavlab.mars.navigation.scenarios import MarsScenario, default_settle_days, run

    res = run(MarsScenario(days=0.2, seed=3))
    api = res.summary()
    assert main(["run", "mars", "--days", "0.2", "--seed", "3", "--json"]) == 0
    cli = json.loads(capsys.readouterr().out)
    assert api["settle_days"] == cli["settle_days"] == default_settle_days(0.2) == 0.1
    for key in ("position_error_m", "velocity_error_mps", "position_error_max_m", "epochs"):
        assert api[key] == cli[key], key


# ---- issue 35: lists and lengths refused by the user's own parameter name ---------------------

@pytest.mark.parametrize(("field", "value", "words"), [
    ("days", 1e-5, r"^days must span at least one measurement interval \(3 s"),   # was settle_days
    ("subsystems", "xnav", r"^subsystems must be a list of subsystems, got the string 'xnav'"),
    ("subsystems", ("uv", "uv"), r"^subsystems lists uv twice"),
    ("subsystems", (), r"^subsystems must name at least one subsystem"),
    ("stars", "Vega", r"^stars must be a list of stars, got the string 'Vega'"),
    ("stars", ("Vega", "Sirius", "Vega"), r"^stars lists Vega twice \(items 0 and 2\)"),
    ("stars", (), r"^stars must name at least one star"),
    ("beta", 0.5, r"^beta must be a list of numbers, got 0.5"),
    ("beta", (0.5, "a", 0.2), r"^beta\[1\] must be a real number in \[0.001, 1\]"),
    ("xnav_sigma_m", 100.0, r"^xnav_sigma_m must be a list of numbers"),
    ("pulsars", ["B1937+21", "B1937+21"], r"^pulsars lists B1937\+21 twice"),
])
def test_a_bad_list_or_too_short_a_run_is_one_line_naming_the_field(field, value, words):
    with pytest.raises(ValueError, match=words) as err:
        scenarios.MarsScenario(**{field: value})
    assert "\n" not in str(err.value)


def test_the_shortest_run_is_one_measurement():
    assert scenarios.MarsScenario(days=3.0 / 86400.0).span == 3.0
    with pytest.raises(ValueError, match=r"^days must span .* \(500 s"):
        scenarios.MarsScenario(days=0.001, subsystems=("xnav",))


@pytest.mark.parametrize("call, match", [
    (lambda: scenarios.MarsScenario(state0=np.zeros((1, 6))),
     r"^state0 must be a 1-D array \(shape \(6,\)\), got shape \(1, 6\)"),
    (lambda: scenarios.MarsScenario(state0=np.zeros((2, 6))), r"^state0 must be a 1-D array"),
    (lambda: scenarios.run({"days": 1}), r"^scenario must be a MarsScenario, got dict"),
    (lambda: scenarios.prepare("paper"), r"^scenario must be a MarsScenario, got str"),
    (lambda: scenarios.prepare(None, dayz=1), r"^unknown override dayz: not a field of MarsScenario"),
    (lambda: scenarios.run(dayz=1), r"^unknown override dayz"),
])
def test_a_wrong_shape_type_or_field_is_one_value_error_naming_it(call, match):
    """Review 35 E.19-E.21: TypeError and AttributeError from deep inside before."""
    with pytest.raises(ValueError, match=match):
        call()


def test_save_npz_writes_the_file_it_is_given_or_refuses_by_name(tmp_path):
    """Review 35 C.10: a folder got a sibling file (numpy adds .npz); a missing parent a raw
    FileNotFoundError from zipfile."""
    res = scenarios.run(scenarios.MarsScenario(days=0.01))
    (tmp_path / "dir.npz").mkdir()
    with pytest.raises(ValueError, match=r"^path .* is a folder, not a file"):
        res.save_npz(tmp_path / "dir.npz")
    with pytest.raises(ValueError, match=r"^path must name a file ending in \.npz, got"):
        res.save_npz(tmp_path)
    assert not (tmp_path.parent / f"{tmp_path.name}.npz").exists()
    res.save_npz(tmp_path / "no" / "dir" / "run.npz")          # a missing parent is made
    assert np.load(tmp_path / "no" / "dir" / "run.npz")["t"].shape == res.t.shape
    (tmp_path / "file").write_text("")
    with pytest.raises(ValueError, match=r"^path .*: a part of its folder is a file"):
        res.save_npz(tmp_path / "file" / "run.npz")


def test_a_noise_model_beside_given_sigmas_is_refused_not_ignored():
    """Review 35 B.6: xnav_noise = 'crlb' with xnav_sigma_m was accepted and unused."""
    with pytest.raises(ValueError, match=r"^xnav_noise = 'crlb' is unused: xnav_sigma_m gives "
                                         r"the ranging noise it would compute"):
        scenarios.MarsScenario(xnav_noise="crlb", xnav_sigma_m=(1.0, 2.0, 3.0, 4.0))
    from xnavlab.mars.navigation import scenario_files

    with pytest.raises(ValueError, match=r"^scenario file: \[xnav\] noise = 'crlb' is unused: "
                                         r"\[xnav\] sigma_m gives"):
        scenario_files.loads('[xnav]\nnoise = "crlb"\nsigma_m = [1.0, 2.0, 3.0, 4.0]\n')


def test_xnav_and_cns_settings_without_their_subsystem_are_refused_not_ignored():
    """Review 35 B.6: xnav_sigma_m with subsystems=("uv",) and stars without cns were accepted
    and unused (every field: tests/mars/navigation/test_unused_inputs.py)."""
    with pytest.raises(ValueError, match=r"^xnav_sigma_m is set but subsystems = \['uv'\] runs "
                                         r"no xnav: leave it out or add 'xnav'$"):
        scenarios.MarsScenario(subsystems=("uv",), xnav_sigma_m=(1.0,) * 4)
    with pytest.raises(ValueError, match=r"^stars is set but subsystems = \['xnav', 'uv'\] runs "
                                         r"no cns: leave it out or add 'cns'$"):
        scenarios.MarsScenario(subsystems=("xnav", "uv"), stars=("Sirius", "Vega", "Canopus"))
    # a default value is the same run as none: accepted (replace keeps working)
    sc = dataclasses.replace(scenarios.MarsScenario(), subsystems=("uv",))
    assert sc.subsystems == ("uv",) and sc.dt_xnav == 500.0


def test_study_names_an_unknown_field():
    """MarsScenario.study(dayz=1) raised the constructor's raw TypeError."""
    with pytest.raises(ValueError, match=r"^unknown override dayz: not a field of MarsScenario "
                                         r"\(the fields: days, "):
        scenarios.MarsScenario.study(dayz=1)


def test_a_run_outside_the_ephemeris_is_refused_naming_t0():
    """Review 35b N6: t0 = -1e12 was built, and the run then named an internal 't'."""
    with pytest.raises(ValueError, match=r"^t0 must be in \[-3158136000 \(1899-12-04T00:00:00 TDB\), "
                                         r"6311476800 \(2200-01-02T00:00:00 TDB\)\] s TDB past J2000 "
                                         r"\(the run, t0 to t0 \+ days, in DE421\), "
                                         r"got -1000000000000\.0$"):
        scenarios.MarsScenario(t0=-1e12)
    # review 35q Q19: at six digits the value (6.31407e+09) was shown inside the range shown;
    # the bound is the one on t0 itself (the coverage's end less the run's span)
    with pytest.raises(ValueError, match=r"^t0 must be in \[.*, 6314067936 \(2200-01-31T23:45:36 "
                                         r"TDB\)\] .*, got 6314068400 \(2200-01-31T23:53:20 TDB\)$"):
        scenarios.MarsScenario(t0=6314068400.0, days=0.01)  # the start inside, the end past it


def test_a_run_ends_at_t0_plus_days_where_no_step_ends_there():
    """Review 35q Q3: with 86,400-s steps a run of 1.9 days stopped at its last measurement
    (1.0 day) while its summary said 1.9; the span's end is now an epoch of its own, where the
    filter only propagates."""
    steps = dict(dt_xnav=86400.0, dt_uv=86400.0, dt_cns=86400.0)
    for kw in (dict(days=1.9, **steps), dict(days=0.0101, dt_uv=500.0, dt_cns=500.0)):
        run = scenarios.run(**kw)
        span = kw["days"] * 86400.0
        assert run.t[-1] - run.t[0] == pytest.approx(span, abs=1e-6)
        assert run.times[-1] - run.times[0] == pytest.approx(span, abs=1e-6)
        assert run.summary()["days"] == kw["days"]
        assert not np.any(run.flags[-1])  # no measurement at the end: propagated only
    inp = scenarios.prepare(days=0.02)  # steps that end on the span: no extra epoch
    measured = np.concatenate([[inp.times[0]], *inp.t_meas.values()])
    assert np.array_equal(inp.times, np.unique(measured)) and inp.times[-1] - inp.times[0] == 1728.0


def test_a_filter_the_kernel_cannot_carry_stops_with_one_clear_error():
    # review 35d D44: a UV noise of 1e-6 m against a 5-km initial error
    sc = scenarios.MarsScenario(days=0.05, subsystems=("uv",), sigma_range_m=1e-6,
                                sigma_dir_deg=1e-9)
    # review 35f #7: the message named pos_err0_m only; it names the settings moved now
    with pytest.raises(FilterDivergence, match=r"the compiled filter stopped: a "
                       r"covariance lost positive definiteness near epoch \d+ .*the noise "
                       r"settings away from their defaults: sigma_range_m = 1e-06 \(default "
                       r"5000.0\); sigma_dir_deg = 1e-09 \(default 0.1\) \(move them back\), "
                       r"or run the numpy backend"):
        scenarios.run(sc)


def test_a_share_factor_a_local_covariance_cannot_carry_is_refused():
    # review 35f #1: beta = 5e-324 ended in a ZeroDivisionError (P0 / beta) after --check
    with pytest.raises(ValueError, match=r"^beta\[0\] must be a real number in \[0.001, 1\], "
                                         r"got 5e-324"):
        scenarios.MarsScenario(beta=(5e-324, 1.0, 1.0))


def test_a_state0_inside_mars_is_refused_by_the_scenario_itself():
    # review 35d D3: scenario --check passed it; only the run refused it, without the file's key
    with pytest.raises(ValueError, match=r"state0 position must lie outside Mars .* got \|r\| = 1 m"):
        scenarios.MarsScenario(state0=(1.0, 0.0, 0.0, 0.0, 0.0, 0.0))


def test_a_state0_faster_than_any_craft_bound_to_the_sun_is_refused():
    # review 35d D5: 3 c was accepted and run
    with pytest.raises(ValueError, match=r"state0 speed must be below 65164.5 m/s at \|r\| = "
                                         r"4e\+06 m .* got 9e\+08 m/s"):
        scenarios.MarsScenario(state0=(4e6, 0.0, 0.0, 9e8, 0.0, 0.0))


def test_run_takes_progress_as_a_bool_only():
    """Review 35e: progress="no" drew a progress bar (a non-empty string is true)."""
    with pytest.raises(ValueError, match=r"^progress must be True or False, got 'no'$"):
        scenarios.run(scenarios.MarsScenario(days=0.02), progress="no")


def test_a_real_given_as_a_fraction_or_numpy_scalar_is_kept_as_a_float():
    # review 35f #28: Fraction(3, 1) passed the check and failed in numpy's rint
    from fractions import Fraction

    sc = scenarios.MarsScenario(days=np.float32(0.5), dt_uv=Fraction(3, 1), area_m2=np.int64(1))
    assert all(type(getattr(sc, n)) is float for n in ("days", "dt_uv", "area_m2"))
    assert sc.dt_uv == 3.0 and sc == scenarios.MarsScenario(days=float(np.float32(0.5)))


def test_check_scenario_refuses_a_name_that_is_no_text():
    """Issue 35 (review 35h): ``check_scenario(True, None)`` was taken (the name is the
    caller's parameter, for the message)."""
    with pytest.raises(ValueError, match=r"^name must be text \(a str\), got True$"):
        scenarios.check_scenario(True, None)
    with pytest.raises(ValueError, match=r"^scenario must be a MarsScenario, got bool True$"):
        scenarios.check_scenario("scenario", True)


def test_overrides_that_are_no_dict_are_refused_by_name():
    """Review 35j (1) 12: check_overrides([1]) raised str.join's TypeError."""
    with pytest.raises(ValueError, match=r"^overrides must be a dict of MarsScenario fields "
                                         r"\(\{name: value\}\), got list \[1\]$"):
        scenarios.check_overrides([1])
    with pytest.raises(ValueError, match=r"^unknown override 1: not a field of MarsScenario"):
        scenarios.check_overrides({1: 2.0})


def test_inputs_that_are_no_inputs_are_refused_by_name():
    """Review 35j (1) 13: run(inputs={...}) raised AttributeError 'dict' object has no
    attribute 'scenario'; the kernel's helpers took any object too."""
    with pytest.raises(ValueError, match=r"^inputs must be an Inputs from prepare\(\), got dict"):
        scenarios.run(inputs={"a": 1})
    for call in (scenarios.alloc_records, lambda inp: scenarios.run_options(inp, None, None),
                 lambda inp: scenarios.filter_state(inp, np.ones(3))):
        with pytest.raises(ValueError, match=r"^inp must be an Inputs from prepare\(\), got str"):
            call("x")


@pytest.fixture(scope="module")
def two():
    """The inputs of a short run of two subsystems."""
    return scenarios.prepare(days=0.02, subsystems=("uv", "cns"))


@pytest.mark.parametrize(("gate", "message"), [
    (-1.0, r"^gate must hold one NIS threshold a subsystem, shape \(2,\) for subsystems "
           r"\['uv', 'cns'\] \(numbers, inf for no gate\), got the number -1.0$"),
    ([1.0, 2.0, 3.0], r"^gate must hold one NIS threshold a subsystem, shape \(2,\) .*, got "
                      r"shape \(3,\)$"),
    ("x", r"^gate must hold one NIS threshold a subsystem, .*, got str 'x'$"),
    ([1.0, -2.0], r"^gate\[1\] must be a non-negative NIS threshold \(inf for no gate; subsystem "
                  r"cns\), got -2.0$"),
    ([np.nan, 1.0], r"^gate\[0\] must be a non-negative NIS threshold .*, got nan$"),
])
def test_a_gate_of_the_wrong_kind_sign_or_length_is_refused_by_its_rule(two, gate, message):
    """Review 35j (2) 9-11: numpy's reshape or float messages, and the sign never reported."""
    with pytest.raises(ValueError, match=message):
        scenarios.run(inputs=two, gate=gate)


def test_one_number_gates_a_run_of_one_subsystem():
    inp = scenarios.prepare(days=0.02, subsystems=("uv",))
    assert scenarios.run_options(inp, None, 9.0)[1].tolist() == [9.0]


def test_active_flags_that_are_no_flags_are_refused_not_cast(two):
    """Review 35j (5) 13: active=0.5 was cast to True without a word."""
    with pytest.raises(ValueError, match=r"^active must hold True/False flags \(or 1/0\), shape "
                                         r"\(\d+, 2\) .*, got active\[0, 0\] = 0.5 \(a flag is "
                                         r"not cast from another number\)$"):
        scenarios.run(inputs=two, active=np.full((two.n, 2), 0.5))
    with pytest.raises(ValueError, match=r"^active must hold .*, got str 'x'$"):
        scenarios.run(inputs=two, active="x")
    ones = scenarios.run_options(two, np.ones((two.n, 2), dtype=int), None)[0]
    assert ones.dtype == bool and ones.all()


def test_save_npz_refuses_an_extra_array_named_as_one_of_the_runs(tmp_path):
    """Review 35j (class of (1) 19): extra t=... raised savez's 'multiple values' TypeError."""
    res = scenarios.run(days=0.02, subsystems=("uv",))
    for name in ("t", "file"):
        with pytest.raises(ValueError, match=rf"^extra\['{name}'\] takes a name the npz already "
                                             r"uses \(taken: t, x, P, "):
            res.save_npz(tmp_path / "r.npz", **{name: np.ones(2)})
    with pytest.raises(ValueError, match=r"^path must be a path \(a str or pathlib.Path\), got dict"):
        res.save_npz({})
    res.save_npz(str(tmp_path / "r.npz"), mine=np.ones(2))
    assert np.load(tmp_path / "r.npz")["mine"].tolist() == [1.0, 1.0]


def test_filter_state_refuses_beta_of_the_wrong_length_or_sign(two):
    with pytest.raises(ValueError, match=r"^beta must have shape \(2,\) \(one a subsystem of "
                                         r"\['uv', 'cns'\]\), got shape \(3,\)$"):
        scenarios.filter_state(two, np.ones(3) / 3)
    with pytest.raises(ValueError, match=r"^beta must hold positive information-sharing factors"):
        scenarios.filter_state(two, np.array([1.0, 0.0]))


def test_numpy_scalars_are_stored_as_floats():
    """Review 35k (1) 1: MarsScenario(days=np.float16(0.5)) kept the float16 and overflowed
    in days * DAY (RuntimeWarning); the checked value is stored as a float (seed as an int)."""
    import numpy as np

    sc = scenarios.MarsScenario(days=np.float16(0.5), seed=np.int64(3), q_acc=np.float32(1e-9))
    assert type(sc.days) is float and sc.days == 0.5 and type(sc.seed) is int
    assert type(sc.q_acc) is float
    with pytest.raises(ValueError, match=r"^days must be a real number in \(0, 365\]"):
        scenarios.MarsScenario(days="1.0")


def test_masked_active_flags_are_refused_not_read_as_data(two):
    """Review 35m (5) 1: np.asarray dropped the mask and the masked flags were used."""
    active = np.ma.masked_array(np.ones((two.n, 2), dtype=bool))
    active[3, 1] = np.ma.masked
    with pytest.raises(ValueError, match=r"^active has masked entries \(no flag to use"):
        scenarios.run_options(two, active, None)
    unmasked = scenarios.run_options(two, np.ma.masked_array(np.ones((two.n, 2), dtype=bool)), None)[0]
    assert type(unmasked) is np.ndarray and unmasked.all()


def test_run_checks_inputs_edited_by_hand():
    """Review 35o (1) 3, (1) 4, (3) 2, (5) 1 (pattern S): an Inputs edited with
    dataclasses.replace gave an IndexError (a cut z, a record past the end), ekf_update's names
    (x0, z) on numpy, a FilterDivergence blaming pos_err0_m on numba, or a compiled kernel
    reading past a shortened z (the edit silently ignored)."""
    inp = scenarios.prepare(days=0.01)
    rep = dataclasses.replace
    uv = inp.z["uv"]
    nan_uv = uv.copy()
    nan_uv[5, 0] = np.nan
    cases = [
        (rep(inp, z={**inp.z, "uv": uv[:-1]}), r"^inputs\.z\['uv'\] has 287 rows; inputs\.meas_idx"
                                               r"\[:, 1\] uses 288"),
        (rep(inp, z={**inp.z, "uv": uv[:10].copy()}), r"^inputs\.z\['uv'\] has 10 rows"),
        (rep(inp, z={**inp.z, "uv": uv[:, :3]}), r"^inputs\.z\['uv'\] must have shape \(m, 4\), "
                                                 r"got shape \(288, 3\)"),
        (rep(inp, z={**inp.z, "uv": nan_uv}), r"^inputs\.z\['uv'\] must contain only finite "
                                              r"numbers, got inputs\.z\['uv'\]\[5, 0\] = nan"),
        (rep(inp, z={k: v for k, v in inp.z.items() if k != "cns"}),
         r"^inputs\.z must have one entry a subsystem of the scenario \['xnav', 'uv', 'cns'\]"),
        (rep(inp, x0=np.full(6, np.nan)), r"^inputs\.x0 must contain only finite numbers"),
        (rep(inp, x0=np.zeros((1, 6))), r"^inputs\.x0 must have shape \(6,\), got shape \(1, 6\)"),
        (rep(inp, record=np.array([0, 10**6])), r"^inputs\.record must hold epoch indices in "
                                                r"\[0, 289\] \(n = 290 epochs\), got inputs\."
                                                r"record\[1\] = 1000000"),
        (rep(inp, record=inp.record[::-1].copy()), r"^inputs\.record must increase"),
        (rep(inp, truth=inp.truth[:-1]), r"^inputs\.truth must have shape \(290, 6\)"),
        (rep(inp, times=inp.times[::-1].copy()), r"^inputs\.times must increase"),
    ]
    for bad, msg in cases:
        for backend in ("numba", "numpy"):
            with pytest.raises(ValueError, match=msg):
                scenarios.run(inputs=bad, backend=backend)
    assert inp.check() is inp  # prepare's own: taken, and the numbers unchanged
    a, b = scenarios.run(inputs=inp), scenarios.run(days=0.01)
    assert np.array_equal(a.x, b.x) and np.array_equal(a.P, b.P)


def test_save_npz_refuses_what_np_load_cannot_read_and_unexpanded_or_unwritable_paths(tmp_path,
                                                                                        monkeypatch):
    """Review 35o (5) 2, (7) 1, (7) 2: meta={'a': 1} or None were pickled (np.load refused
    them), names '' and 'a/b' written as members, '~/x.npz' made a folder named '~', and
    /proc/x.npz raised zipfile's FileNotFoundError."""
    res = scenarios.run(days=0.01, subsystems=("uv",))
    monkeypatch.chdir(tmp_path)
    for value, kind in (({"a": 1}, "dict"), (None, "NoneType"), (np.array([{}]), "ndarray")):
        with pytest.raises(ValueError, match=rf"^extra\['meta'\] must be an array of numbers, "
                                             rf"bools or strings .*, got {kind} "):
            res.save_npz("m.npz", meta=value)
    for name in ("", "a/b"):
        with pytest.raises(ValueError, match=rf"^extra\['{name}'\]: an array name must be an "
                                             r"identifier"):
            res.save_npz("m.npz", **{name: np.ones(2)})
    with pytest.raises(ValueError, match=r"^path '~/x\.npz' starts with '~', which is not "
                                         r"expanded here .*os\.path\.expanduser"):
        res.save_npz("~/x.npz")
    if os.path.isdir("/proc/self"):  # Linux: a folder where no file can be made
        with pytest.raises(ValueError, match=r"^path '/proc/x\.npz' cannot be written: no file "
                                             r"can be made in '/proc'"):
            res.save_npz("/proc/x.npz")
    assert sorted(p.name for p in tmp_path.iterdir()) == []  # nothing written, no '~' folder
    res.save_npz("ok.npz", note=np.array("text"), flags2=[True, False])
    with np.load("ok.npz") as data:
        assert str(data["note"]) == "text" and data["flags2"].tolist() == [True, False]


def test_an_input_array_of_another_layout_is_refused_not_compiled_for():
    """Review 35q Q12: a strided z['xnav'] made numba compile a second kernel (80 s, no notice)."""
    inp = scenarios.prepare(days=0.02)
    strided = dict(inp.z, xnav=np.repeat(inp.z["xnav"], 2, axis=0)[::2])
    with pytest.raises(ValueError, match=r"^inputs\.z\['xnav'\] must be a C-contiguous array as "
                                         r"prepare\(\) makes it .*, got a strided array: pass "
                                         r"np\.ascontiguousarray\(inputs\.z\['xnav'\]\)$"):
        scenarios.run(inputs=dataclasses.replace(inp, z=strided))
    with pytest.raises(ValueError, match=r"^inputs\.truth must be .*, got a Fortran-ordered"):
        scenarios.run(inputs=dataclasses.replace(inp, truth=np.asfortranarray(inp.truth)),
                      backend="numpy")


def test_the_shared_truth_is_read_only_so_no_run_changes_another():
    """Review 35r R1: prepare handed out the truth cache's own writeable array; an edit of
    inp.truth moved every later run of the same settings (919 m to 365 km)."""
    first = scenarios.run(days=0.02).summary()["position_error_m"]
    inp = scenarios.prepare(days=0.02)
    with pytest.raises(ValueError, match="read-only"):
        inp.truth[:, :3] += 1e6
    assert scenarios.run(days=0.02).summary()["position_error_m"] == first
    other = scenarios.prepare(days=0.02, subsystems=("uv",))  # another grid: its own truth
    assert other.truth is not inp.truth or np.array_equal(other.times, inp.times)
