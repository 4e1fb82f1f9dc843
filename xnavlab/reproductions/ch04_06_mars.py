"""Main paper (Fan et al. 2016), Fig. 2: the fault-free federated Mars navigation run.

IDs: ``mars-sensors`` (section 4.1: the sensor accuracies, chapter 4),
``mars-subsystems`` (sections 0 and 3: each subsystem alone and the fused result,
chapter 5) and ``mars-nofault`` (Fig. 2, chapter 6).

``mars-nofault``: the paper's 30-day scenario (section 4.1) with the three
subsystems (XNAV, UV sensor, CNS), one EKF each, fused by the federated filter in
reset mode, no faults and no detector. The paper reports a position error of
28.835 m and a velocity error of 0.02149 m/s without saying how the numbers were
formed.

Our metric: the RMS over time of the norm of the fused position (velocity) error,
from day 1 to day 30 (:meth:`xnavlab.mars.scenarios.MarsRun.metrics`). The RMS of the norm
summarises a curve like Fig. 2 in one number, weighs every axis and epoch equally and
leaves out the 5-km initial transient, which has died out well before day 1.
Acceptance: the paper's numbers come from one run, so each is judged as one draw from our
single runs over 32 noise seeds (:func:`xnavlab.reproduce.check_draw`, the runs of
:func:`xnavlab.mars.headline.headline_numbers`): reproduced when it falls inside their 95 %
range. The paper gives neither its process noise nor its metric; ours are stated in the note.
"""

from __future__ import annotations

import math

import numpy as np

from xnavlab.core.constants import C
from xnavlab.mars import dynamics, pulsars, scenarios, sensors
from xnavlab.reproduce import (
    Result,
    check_draw,
    check_measure,
    check_sanity,
    check_true,
    register,
    save_figure,
)
from xnavlab.reproduce import figure as _figure

__all__ = ["PAPER_POSITION_ERROR_M", "PAPER_VELOCITY_ERROR_MPS", "PAPER_SENSORS",
           "mars_sensors", "mars_subsystems", "mars_nofault"]

#: Paper section 4.1: sensor accuracies (1 sigma).
PAPER_SENSORS = {
    "UV range (m)": 5000.0,
    "UV direction per axis (deg)": 0.1,
    "star sensor per axis (arcsec)": 3.0,
    "horizon sensor per axis (deg)": 0.05,
    "B0531+21 ranging (m)": 109.0,
    "B1937+21 ranging (m)": 344.0,
    "B1957+20 ranging (m)": 1866.0,
    "B1821-24 ranging (m)": 325.0,
}

#: Paper section 4.2, Fig. 2: fault-free position error, m.
PAPER_POSITION_ERROR_M = 28.835
#: Paper section 4.2, Fig. 2: fault-free velocity error, m/s.
PAPER_VELOCITY_ERROR_MPS = 0.02149



@register("mars-sensors", title="simulated sensor noise at the paper's accuracies",
          source="Fan et al. 2016, section 4.1", chapter="04_optical_geometry")
def mars_sensors(out=None, n=40_000, seed=0):
    """Monte Carlo of the three sensor models at the paper's initial state."""
    rng = np.random.default_rng(seed)
    x = dynamics.MARS_STATE0
    states = np.tile(x, (n, 1))
    uv, cns = sensors.UVSensor(), sensors.CNSSensor()
    zu = uv.simulate(states, rng=rng)
    e1, e2 = sensors.tangent_basis(uv.h(x)[1:])
    du = zu[:, 1:] - uv.h(x)[1:]
    dir_deg = math.degrees(0.5 * (np.std(du @ e1) + np.std(du @ e2)))
    zc = cns.simulate(states, rng=rng)
    ang = zc - cns.h(x)
    xs = sensors.XNAVSensor()
    t = np.full(n, dynamics.MARS_T0)
    zx = xs.simulate(t[:2000], states[:2000], rng=rng) - xs.h(x, dynamics.MARS_T0)
    tol = 0.02  # 40,000 draws: the sample sigma's own scatter is 0.35 %
    corr = float(np.abs(np.corrcoef(ang.T)[np.triu_indices(3, 1)]).max())

    def same(name, paper, ours, within):
        return check_sanity(name, paper, ours, abs(ours - paper) <= within * paper,
                            f"within {100 * within:g} % of the set-up's value")

    checks = [  # our simulators against the set-up of section 4.1: checks, not claims
        same("UV range (m)", 5000.0, float(np.std(zu[:, 0] - uv.h(x)[0])), tol),
        same("UV direction per axis (deg)", 0.1, dir_deg, tol),
        same("starlight angle (deg), horizon 0.05 deg + star 3 arcsec", 0.05,
             math.degrees(float(np.mean(np.std(ang, axis=0)))), tol),
        check_sanity("starlight-angle errors share the horizon error (max |correlation|)",
                     "correlated", corr, corr > 0.1, "> 0.1: R is not diagonal"),
    ]
    for i, p in enumerate(pulsars.PAPER_PULSARS):
        paper = PAPER_SENSORS[f"{p} ranging (m)"]
        checks.append(same(f"{p} ranging (m)", paper, float(xs.sigma[i] * C), 0.01))
        checks.append(same(f"{p} simulated delay scatter x c (m)", paper,
                           float(np.std(zx[:, i]) * C), 0.05))
    note = (
        f"{n} draws of each sensor at the paper's initial state. Direction noise is applied as a "
        "rotation of the true unit vector by a small random angle (two independent tangent "
        "components, each N(0, sigma^2)); the UV direction check measures those tangent "
        "components. A starlight angle combines the horizon sensor (0.05 deg, common to the three "
        "stars) and the star sensor (3 arcsec, per star): its scatter is "
        "sqrt(0.05^2 + (3/3600)^2) deg = 0.05 deg, and the three angles are correlated through "
        "the shared horizon error, which the filter's R accounts for. XNAV accuracies come from "
        "the Sheikh et al. (2006) formula of chapter 1 (500 s, 1 m^2, 0.005 ph/cm^2/s)."
    )
    return Result("mars-sensors", checks, note, {"uv": zu, "cns": ang})


@register("mars-subsystems", title="each subsystem alone vs the federated fusion (3 days)",
          source="Fan et al. 2016, sections 0 and 3 (claims)", chapter="05_ekf_ukf")
def mars_subsystems(out=None, days=3.0, seed=0):
    """Each subsystem's EKF alone and the three fused: bounded errors, fusion best."""
    rms = {}
    runs = {}
    for subs in (("xnav",), ("uv",), ("cns",), scenarios.SUBSYSTEMS):
        res = scenarios.run(days=days, seed=seed, subsystems=subs)
        label = "+".join(subs)
        d, pe = res.t_days, res.position_error()
        late = d >= days - 1.0
        mid = (d >= days - 2.0) & ~late
        rms[label] = (float(np.sqrt(np.mean(pe[mid] ** 2))), float(np.sqrt(np.mean(pe[late] ** 2))))
        runs[label] = (d, pe)
    fused = rms["xnav+uv+cns"][1]
    best_single = min(rms[s][1] for s in ("xnav", "uv", "cns"))
    checks = [
        check_true(f"{s}: error does not grow (last day vs the day before, m)", "bounded",
                   rms[s][1], rms[s][1] <= 1.1 * rms[s][0],
                   "last-day RMS at most 1.1 times the day before's: one seed's day-to-day "
                   "scatter is a few per cent")
        for s in ("xnav", "uv", "cns", "xnav+uv+cns")
    ]
    checks.append(check_true("fused better than the best subsystem alone (m)", "higher accuracy",
                             fused, fused < best_single,
                             f"below the best single subsystem's {best_single:.1f} m"))
    note = (
        "The paper argues (sections 0 and 3) that XNAV, UV and CNS navigation all have errors "
        "that do not grow with time and that federated fusion gives higher accuracy than each; "
        "it shows no figure for the single subsystems. Each runs here as its own EKF (the "
        f"federated code with one local, sharing factor 1) for {days:g} days; RMS of |position "
        "error| over the last day and the day before: "
        + ", ".join(f"{k} {v[1]:.1f} m ({v[0]:.1f} m)" for k, v in rms.items()) + "."
    )
    return Result("mars-subsystems", checks, note, {"runs": runs, "rms": rms})


@register("mars-nofault", title="fault-free 30-day federated XNAV/UV/CNS run around Mars",
          source="Fan et al. 2016, section 4.2 and Fig. 2", chapter="06_federated")
def mars_nofault(out=None, days=30.0, seed=0, settle_days=1.0, mode="reset"):
    """Run the paper's scenario and compare the error metrics with Fig. 2."""
    sc = scenarios.MarsScenario(days=days, seed=seed, mode=mode)
    res = scenarios.run(sc)
    m = res.metrics(settle_days=settle_days)
    pos, vel = m["position_error_m"], m["velocity_error_mps"]
    min_eig = float(res.min_eigenvalue().min())
    sym = float(np.max(np.abs(res.P - np.swapaxes(res.P, 1, 2))))
    after = res.t_days >= settle_days
    inside = float(np.mean(res.position_error()[after] <= 3.0 * res.sigma_position()[after]))
    checks = []
    if (days, settle_days, mode) == (30.0, 1.0, "reset"):
        # the paper's numbers are single runs: judged among ours over 32 seeds
        from xnavlab.mars import headline

        runs = headline.headline_numbers(n_seeds=32)["runs"]
        checks += [
            check_draw("fused position error (m), RMS after day 1", PAPER_POSITION_ERROR_M,
                       runs["fused_position_m"]),
            check_draw("fused velocity error (m/s), RMS after day 1", PAPER_VELOCITY_ERROR_MPS,
                       runs["fused_velocity_mps"]),
        ]
    checks += [
        check_measure(f"fused position error of the plotted run, seed {seed} (m)", pos,
                      "one single run, the one whose curves the chapter plots",
                      paper=PAPER_POSITION_ERROR_M),
        check_sanity("covariance SPD over the run (smallest eigenvalue)", "> 0", min_eig,
                     min_eig > 0.0 and sym == 0.0, "symmetric, all eigenvalues > 0"),
        check_sanity("|position error| within 3 sigma after day 1 (fraction)", ">= 0.99", inside,
                     inside >= 0.99, "the filter's covariance covers its error"),
    ]
    note = (
        f"Metric (the paper defines none): RMS over time of the norm of the fused error from "
        f"day {settle_days:g} to day {days:g}. Ours {pos:.2f} m and {vel:.4f} m/s against the "
        f"paper's {PAPER_POSITION_ERROR_M} m and {PAPER_VELOCITY_ERROR_MPS} m/s "
        f"(ratios {pos / PAPER_POSITION_ERROR_M:.2f} and {vel / PAPER_VELOCITY_ERROR_MPS:.2f}). "
        "Set-up as section 4.1 (initial state, 5000 m and 1 m/s initial error per axis, the four "
        "pulsars at 109/344/1866/325 m every 500 s, UV 0.1 deg and 5000 m every 3 s, CNS 3 arcsec "
        "and 0.05 deg every 3 s, 30 days, Mars + Sun + Jupiter); epoch 2016-01-01 TDB; three "
        "Hipparcos stars picked by xnavlab.mars.stars.pick_three; federated filter in reset mode with "
        "equal sharing factors, fused every epoch. The paper gives no process noise: we use white "
        f"acceleration noise q = {sc.q_acc:g} m^2/s^3 (1e-7 m/s^2 over ~1000 s); the result moves "
        "from about 20 m (q = 1e-12) to 52 m (q = 1e-9), which with the undefined metric is the "
        "main reason for any gap. Both errors keep the paper's ratio: the velocity error is the "
        "position error times the orbital mean motion (7.6e-4 rad/s), the signature of errors "
        "that ride along the orbit."
    )
    data = {
        "t_days": res.t_days, "position_error": res.position_error(),
        "velocity_error": res.velocity_error(), "sigma_position": res.sigma_position(),
        "local_position_error": np.linalg.norm(res.x_local[:, :, :3] - res.truth[:, None, :3],
                                               axis=2),
        "subsystems": res.scenario.subsystems, "metrics": m, "run_time_s": res.wall_time,
        "q_acc": sc.q_acc,
    }
    result = Result("mars-nofault", checks, note, data)
    if out is not None:
        fig, axes = _figure(2, 1, figsize=(8, 5), sharex=True)
        axes[0].semilogy(res.t_days, res.position_error(), lw=0.6, label="fused |error|")
        axes[0].semilogy(res.t_days, res.sigma_position(), lw=0.8, label="filter 1-sigma")
        axes[0].axhline(PAPER_POSITION_ERROR_M, color="k", ls="--", lw=0.8, label="paper")
        axes[0].set(ylabel="position error (m)")
        axes[0].legend(fontsize=8)
        axes[1].semilogy(res.t_days, res.velocity_error(), lw=0.6)
        axes[1].axhline(PAPER_VELOCITY_ERROR_MPS, color="k", ls="--", lw=0.8)
        axes[1].set(xlabel="time (days)", ylabel="velocity error (m/s)")
        fig.suptitle("mars-nofault (Fan et al. 2016, Fig. 2)")
        result.figures.append(save_figure(fig, out, "mars-nofault"))
    return result
