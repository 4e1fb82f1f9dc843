"""Schematics of the Mars system, drawn from the model's own quantities.

Four drawings the chapters explain the system with. Each is a pure function that returns a
:class:`matplotlib.figure.Figure` (not registered with pyplot) and takes the numbers it shows
from the package, so the drawing stays true to the model:

:func:`plot_xnav_geometry`
    the SSB, the Sun, Mars and the spacecraft at the scenario's epoch (the JPL ephemeris and
    the main paper's initial state, :data:`xnavlab.mars.models.dynamics.MARS_STATE0`), the pulsar
    direction ``n`` and the three delay terms of the time-transfer equation with their values
    from :func:`xnavlab.mars.timing.toa.terms` (chapter 2, eq. ``ch2-toa``);
:func:`plot_optical_geometry`
    the UV sensor's range and direction to the Mars centre, the apparent radius of the limb
    and one starlight angle, at the paper's initial state with the first CNS star of
    :func:`xnavlab.mars.models.stars.pick_three` (chapter 4);
:func:`plot_federated_filter`
    the three local filters with their information shares ``beta_i``, the master's fusion and
    the reset that feeds the master back to the locals (chapter 6), with the scenario's
    update intervals, shares and mode (:class:`xnavlab.mars.navigation.scenarios.MarsScenario`);
:func:`plot_isolate_rejoin`
    the isolation and rejoining rule of the fault-tolerant filter (chapter 8): the detector
    switches a subsystem out, it does time updates only, and it rejoins when its detector is
    clear and its innovation chi-square over the last ``W`` measurements is quiet, with the
    defaults of :func:`xnavlab.mars.faults.fault_tolerance.run_fault_tolerant`.

Each drawing lies in the plane that holds the vectors it is about (``n`` and ``R``; ``r`` and
``s_j``), so its lengths and angles are true; what is not to scale says so on the drawing.

Examples
--------
>>> fig = plot_federated_filter()
>>> type(fig).__name__
'Figure'
"""

from __future__ import annotations

import inspect
import math

import numpy as np

from xnavlab.core.constants import AU, KPC, R_MARS
from xnavlab.core.validate import check_choice, check_real

__all__ = [
    "READMIT_WINDOWS",
    "figure_texts",
    "plot_xnav_geometry",
    "plot_optical_geometry",
    "plot_federated_filter",
    "plot_isolate_rejoin",
]

#: Samples in the rejoining test's NIS window per subsystem, ``W``: the defaults of
#: :func:`xnavlab.mars.faults.fault_tolerance.run_fault_tolerant` (``readmit_samples``), checked against
#: its source by ``tests/mars/navigation/test_schematics.py``.
READMIT_WINDOWS = {"xnav": 4, "uv": 100, "cns": 100}

_NAMES = {"xnav": "XNAV", "uv": "UV", "cns": "CNS"}
_R_SUN = 6.957e8  # m, the nominal solar radius (IAU 2015 Resolution B3)


def figure_texts(fig):
    """Every non-empty text drawn on ``fig`` (titles, labels, annotations), sorted.

    Examples
    --------
    >>> from matplotlib.figure import Figure
    >>> fig = Figure(); ax = fig.add_subplot(); _ = ax.set_title("a"); _ = ax.text(0, 0, "b")
    >>> figure_texts(fig)
    ['a', 'b']
    """
    from matplotlib.text import Text

    out = [t.get_text() for t in fig.findobj(Text)]
    return sorted(t for t in out if t)


def _box(ax, xy, text, color, width=2.6, height=1.0, fontsize=8):
    from matplotlib.patches import FancyBboxPatch

    x, y = xy
    ax.add_patch(FancyBboxPatch((x - width / 2, y - height / 2), width, height,
                                boxstyle="round,pad=0.05,rounding_size=0.15", fc=color, ec="0.25",
                                lw=1.0))
    ax.text(x, y, text, ha="center", va="center", fontsize=fontsize)


def _arrow(ax, start, end, text="", style="-|>", color="0.2", ls="-", rad=0.0, fontsize=7.5,
           text_xy=None, ha="center"):
    ax.annotate("", xy=end, xytext=start,
                arrowprops=dict(arrowstyle=style, color=color, lw=1.2, ls=ls, shrinkA=2,
                                shrinkB=2, connectionstyle=f"arc3,rad={rad}"))
    if text:
        if text_xy is None:
            text_xy = ((start[0] + end[0]) / 2, (start[1] + end[1]) / 2)
        ax.text(*text_xy, text, ha=ha, va="center", fontsize=fontsize, color=color)


def _paper_orbit_points(state, gm, n=200):
    """Two-body ellipse through a Mars-centred state, (n, 3) m (perifocal parametrisation)."""
    r, v = state[:3], state[3:]
    h = np.cross(r, v)
    e_vec = np.cross(v, h) / gm - r / np.linalg.norm(r)
    e = np.linalg.norm(e_vec)
    p_hat = e_vec / e
    q_hat = np.cross(h / np.linalg.norm(h), p_hat)
    nu = np.linspace(0.0, 2.0 * math.pi, n)
    rad = (h @ h / gm) / (1.0 + e * np.cos(nu))  # r = p / (1 + e cos nu)
    return rad[:, None] * (np.cos(nu)[:, None] * p_hat + np.sin(nu)[:, None] * q_hat)


def plot_xnav_geometry(pulsar="B1937+21"):
    """The XNAV geometry and the three delay terms, at the scenario's epoch; a Figure.

    Drawn in the plane that holds the pulsar direction ``n`` (to the right) and the
    spacecraft's barycentric position ``R``, in au, so that the Roemer delay is the horizontal
    coordinate of the spacecraft: the SSB, the Sun (JPL DE421 at
    :data:`~xnavlab.mars.models.dynamics.MARS_T0`), Mars's orbit over one Mars year (projected on that
    plane), Mars and the spacecraft (the main paper's initial state), the plane wavefronts, and
    the three terms of the time-transfer delay (chapter 2) with their values there: the Roemer
    delay ``n . R / c``, the parallax term (the curvature of the wavefront, drawn with the
    pulsar 4 au away so that it shows) and the Shapiro delay (the Sun's potential on the
    pulse's path). A second panel shows the paper's orbit about Mars in 10^3 km.

    Parameters
    ----------
    pulsar : str
        A pulsar of :data:`xnavlab.mars.timing.pulsars.CATALOGUE` (default B1937+21, whose line of
        sight is far from perpendicular to ``R`` at the epoch).

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> fig = plot_xnav_geometry()
    >>> texts = " ".join(figure_texts(fig))
    >>> all(w in texts for w in ("SSB", "Sun", "Mars", "Roemer", "parallax", "Shapiro"))
    True
    """
    from matplotlib.figure import Figure
    from matplotlib.patches import Circle

    from xnavlab.core import ephemeris
    from xnavlab.core.constants import GM_MARS
    from xnavlab.mars.models import dynamics
    from xnavlab.mars.timing import pulsars, toa

    p = pulsars.get(pulsar)
    t0 = dynamics.MARS_T0
    r_mars, r_sun = ephemeris.position("mars", t0), ephemeris.position("sun", t0)
    R = r_mars + dynamics.MARS_STATE0[:3]  # R = r_M + r
    terms = {k: float(v[0]) for k, v in
             toa.terms(R, p.direction[None], np.array([p.distance]), r_sun).items()}
    e1 = p.direction
    e2 = R - (R @ e1) * e1
    e2 = e2 / np.linalg.norm(e2)

    def plane(v):  # (..., 3) m -> (..., 2) au in the (n, R) plane
        return np.stack([v @ e1, v @ e2], axis=-1) / AU

    days = t0 + np.linspace(0.0, 687.0, 160) * 86400.0
    orbit = plane(ephemeris.position("mars", days))
    sc, sun, mars = plane(R), plane(r_sun), plane(r_mars)

    fig = Figure(figsize=(9.0, 5.6), layout="constrained")
    ax, ax2 = fig.subplots(1, 2, width_ratios=[2.6, 1])
    ax.plot(*orbit.T, color="C3", lw=0.8, alpha=0.5, label="Mars's orbit (DE421, projected)")
    for k in (0.1, 0.2, 0.3):  # the Sun's potential well, drawn
        ax.add_patch(Circle(sun, k, fill=False, ec="goldenrod", lw=0.6, ls=":"))
    ax.add_patch(Circle(sun, 0.05, color="gold", zorder=3))
    ax.plot(0, 0, "k+", ms=12, mew=1.5, zorder=4)
    ax.annotate(f"SSB, {np.linalg.norm(r_sun) / _R_SUN:.2f} solar radii\nfrom the Sun's centre",
                (0, 0), (0.25, -0.75), fontsize=8, arrowprops=dict(arrowstyle="-", lw=0.6))
    ax.annotate("Sun", sun, (-0.3, -0.45), fontsize=8, arrowprops=dict(arrowstyle="-", lw=0.6))
    ax.plot(*mars, "o", color="C3", ms=9, zorder=4)
    ax.text(*(mars + [0.1, 0.08]), "Mars and the spacecraft\n(2016-01-01, the scenario's start)",
            fontsize=8)
    # n, the plane wavefronts, the rays to the SSB and the spacecraft
    _arrow(ax, (0.2, 1.75), (1.3, 1.75), color="k")
    ax.text(0.75, 1.85, f"$\\mathbf{{n}}$ to {p.name} ({p.distance / KPC:.1f} kpc)",
            fontsize=8, ha="center")
    for x in (1.45, 1.6, 1.75):
        ax.plot([x, x], [-1.2, 1.55], color="0.6", lw=0.8)
    ax.text(1.6, -1.3, "plane\nwavefronts", fontsize=7, color="0.4", ha="center", va="top")
    for y in (0.0, sc[1]):
        _arrow(ax, (1.4, y), (sc[0] if y else 0.05, y), color="0.55", ls=":")
    # R and the Roemer delay
    _arrow(ax, (0, 0), sc, color="C0")
    ax.text(*(0.5 * sc + [0.12, -0.08]), "$\\mathbf{R} = \\mathbf{r}_M + \\mathbf{r}$",
            color="C0", fontsize=9)
    ax.plot([sc[0], sc[0]], [sc[1], 0], color="C0", ls="--", lw=0.8)
    ax.plot([0, sc[0]], [0, 0], color="C2", lw=4, alpha=0.6, solid_capstyle="butt")
    ax.text(sc[0] / 2 - 0.15, -0.12, f"Roemer $\\mathbf{{n}}\\cdot\\mathbf{{R}}/c$ = {terms['roemer']:.1f} s",
            color="C2", fontsize=8, ha="center", va="top")
    # parallax: the spherical wavefront through the spacecraft against the plane one
    d_fake = 4.0  # au: the pulsar drawn 4 au away so that the curvature shows
    rad = float(np.hypot(d_fake - sc[0], sc[1]))
    ang = np.linspace(math.pi - math.asin(min(1.0, (sc[1] + 0.2) / rad)), math.pi + 0.1, 60)
    ax.plot(d_fake + rad * np.cos(ang), rad * np.sin(ang), color="C1", lw=1.0)
    ax.plot([sc[0], sc[0]], [sc[1] + 0.25, -0.35], color="0.6", lw=0.8)
    _arrow(ax, (sc[0], 0.0), (d_fake - rad, 0.0), style="<->", color="C1")
    ax.text(d_fake - rad, -0.72,
            "parallax: the wavefront's curvature\n(pulsar drawn 4 au away)\n"
            "$[(\\mathbf{n}\\cdot\\mathbf{R})^2 - |\\mathbf{R}|^2]/(2cD_0)$"
            f" = {terms['parallax'] * 1e6:.2f} µs", color="C1", fontsize=8, ha="center",
            va="top")
    ax.text(sun[0] + 0.35, sun[1] + 0.3,
            f"Shapiro: the Sun's potential\non the path = {terms['shapiro'] * 1e6:.1f} µs",
            color="goldenrod", fontsize=8, ha="left")
    ax.set(aspect="equal", xlim=(-2.3, 2.0), ylim=(-1.8, 2.0),
           xlabel="along $\\mathbf{n}$ (au)", ylabel="across $\\mathbf{n}$, towards $\\mathbf{R}$ (au)",
           title=f"The time-transfer delay for {p.name} at the scenario's start")
    ax.legend(loc="lower left", fontsize=8)
    # the spacecraft's orbit about Mars, in the same plane
    pts = plane(_paper_orbit_points(dynamics.MARS_STATE0, GM_MARS)) * AU / 1e6
    r2 = plane(dynamics.MARS_STATE0[:3]) * AU / 1e6
    ax2.plot(*pts.T, color="C0", lw=0.8, label="the paper's orbit (projected)")
    ax2.add_patch(Circle((0, 0), R_MARS / 1e6, color="C3", alpha=0.5))
    ax2.annotate("", r2, (0, 0), arrowprops=dict(arrowstyle="-|>", color="C0", lw=1.0))
    ax2.text(*(r2 * 0.5 + [0.2, 0.2]), "$\\mathbf{r}$", color="C0", fontsize=9)
    ax2.set(aspect="equal", xlim=(-6, 6), ylim=(-6, 6.5), xlabel="along $\\mathbf{n}$ ($10^3$ km)",
            ylabel="across $\\mathbf{n}$ ($10^3$ km)", title="about Mars")
    ax2.legend(loc="upper center", fontsize=7, frameon=False)
    return fig


def plot_optical_geometry(star=None):
    """The UV and starlight-angle geometry at the paper's initial state; a Figure.

    Drawn true, in the plane that holds the spacecraft's position ``r`` (Mars-centred) and the
    star direction ``s_j``: the Mars limb (radius ``R_M``), the range ``r = |r|``, the unit
    vector ``u = -r / r`` to the Mars centre that the UV sensor measures, the apparent radius
    ``arcsin(R_M / r)`` of the disc, and the starlight angle ``z_j = arccos(u . s_j)`` of the
    CNS (chapter 4, eqs. ``ch4-uv`` and ``ch4-cns``).

    Parameters
    ----------
    star : str, optional
        A star of :mod:`xnavlab.mars.models.stars`; default the first of the paper's CNS stars
        (:func:`~xnavlab.mars.models.stars.pick_three` at the scenario's epoch).

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> fig = plot_optical_geometry()
    >>> texts = " ".join(figure_texts(fig))
    >>> all(w in texts for w in ("limb", "apparent radius", "starlight angle", "range"))
    True
    """
    from matplotlib.figure import Figure
    from matplotlib.patches import Arc, Circle

    from xnavlab.mars.models import dynamics, stars

    t0 = dynamics.MARS_T0
    name = stars.pick_three(t=t0)[0] if star is None else stars.get(star).name
    s = stars.direction(name, t0)
    r = dynamics.MARS_STATE0[:3]
    rn = float(np.linalg.norm(r))
    e1 = r / rn
    e2 = s - (s @ e1) * e1
    e2 = e2 / np.linalg.norm(e2)
    u = -e1
    z = math.degrees(math.acos(float(u @ s)))  # paper eq. (6)
    rho = math.degrees(math.asin(R_MARS / rn))
    km = 1e6  # drawing unit, 10^3 km
    sc = np.array([rn / km, 0.0])
    s2 = np.array([s @ e1, s @ e2])

    fig = Figure(figsize=(7.5, 4.6), layout="constrained")
    ax = fig.add_subplot()
    ax.add_patch(Circle((0, 0), R_MARS / km, fc="C3", alpha=0.35, ec="C3", lw=1.5))
    ax.text(0, -R_MARS / km - 0.35, f"Mars limb, $R_M$ = {R_MARS / 1e3:.0f} km", ha="center",
            fontsize=8, color="C3")
    ax.plot(0, 0, "k.", ms=4)
    ax.plot(*sc, "ks", ms=6)
    ax.text(sc[0] + 0.1, -0.35, "spacecraft", fontsize=8)
    # range, u and the tangent lines to the limb
    _arrow(ax, sc, (0, 0), color="C0")
    ax.text(sc[0] / 2, 0.2, f"range $r$ = {rn / 1e3:.0f} km (UV)", fontsize=8, color="C0",
            ha="center")
    ax.text(sc[0] - 1.6, -0.45, "$\\mathbf{u} = -\\mathbf{r}/r$", fontsize=9, color="C0")
    for sign in (1, -1):
        a = math.radians(180.0 - sign * rho)
        end = sc + 1.05 * math.sqrt(rn**2 - R_MARS**2) / km * np.array([math.cos(a), math.sin(a)])
        ax.plot(*np.array([sc, end]).T, color="0.4", lw=0.8, ls="--")
    ax.add_patch(Arc(sc, 2.2, 2.2, theta1=180.0 - rho, theta2=180.0, color="0.3", lw=1.0))
    ax.text(sc[0] - 1.5, 0.62, f"apparent radius\narcsin($R_M/r$) = {rho:.1f}°", fontsize=8,
            ha="right", color="0.3")
    # the star and the starlight angle
    tip = sc + 3.0 * s2
    _arrow(ax, sc, tip, color="C2")
    ax.text(*(tip + 0.1 * s2), f"$\\mathbf{{s}}_j$ ({name})", fontsize=8, color="C2")
    th_s = math.degrees(math.atan2(s2[1], s2[0]))
    lo, hi = sorted((th_s, 180.0))
    ax.add_patch(Arc(sc, 3.2, 3.2, theta1=lo, theta2=hi, color="C2", lw=1.2))
    mid = math.radians((lo + hi) / 2)
    ax.text(*(sc + 2.6 * np.array([math.cos(mid), math.sin(mid)])),
            f"starlight angle\n$z_j$ = arccos($\\mathbf{{u}}\\cdot\\mathbf{{s}}_j$) = {z:.1f}°",
            fontsize=8, color="C2", ha="center", va="center")
    ax.set(aspect="equal", xlabel="$10^3$ km", ylabel="$10^3$ km",
           title="UV range and direction, and a CNS starlight angle (the paper's initial state)")
    pts = np.array([[-R_MARS / km, -R_MARS / km], [R_MARS / km, R_MARS / km], sc, tip + 0.5 * s2])
    ax.set(xlim=(pts[:, 0].min() - 0.4, pts[:, 0].max() + 1.2),
           ylim=(pts[:, 1].min() - 0.6, pts[:, 1].max() + 0.4))
    return fig


def plot_federated_filter(scenario=None):
    """The federated filter with its reset: locals, shares ``beta_i``, master; a Figure.

    Each subsystem's sensor feeds its local EKF, which holds the share ``beta_i`` of the
    information (prior ``P / beta_i``, process noise ``Q / beta_i``); the master fuses the
    connected locals in information form (chapter 6, eq. ``ch6-fusion``) and, in the reset
    mode, restarts every local from the fused estimate with ``P_f / beta_i``. The update
    intervals, the shares and the mode are the scenario's.

    Parameters
    ----------
    scenario : xnavlab.mars.navigation.scenarios.MarsScenario, optional
        Default the paper's (:class:`xnavlab.mars.navigation.scenarios.MarsScenario`).

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> texts = " ".join(figure_texts(plot_federated_filter()))
    >>> all(w in texts for w in ("XNAV", "UV", "CNS", "master", "reset", "beta"))
    True
    """
    from matplotlib.figure import Figure

    from xnavlab.mars.navigation import scenarios

    sc = scenarios.MarsScenario() if scenario is None else scenario
    subs = tuple(sc.subsystems)
    beta = (np.full(len(subs), 1.0 / len(subs)) if sc.beta is None
            else np.asarray(sc.beta, dtype=float) / np.sum(sc.beta))
    sensor = {"xnav": f"X-ray detector\n{len(sc.pulsars)} pulsars, every {sc.dt_xnav:g} s",
              "uv": f"UV sensor: range, direction\nevery {sc.dt_uv:g} s",
              "cns": f"star + horizon sensors\n3 starlight angles, every {sc.dt_cns:g} s"}
    fig = Figure(figsize=(8.5, 4.8), layout="constrained")
    ax = fig.add_subplot()
    ys = np.linspace(4.6, 0.6, len(subs))
    for k, (name, y, b) in enumerate(zip(subs, ys, beta, strict=True), start=1):
        _box(ax, (1.4, y), sensor[name], "0.93", width=2.6, height=0.95, fontsize=7.5)
        _box(ax, (4.7, y), f"local EKF {k}: {_NAMES[name]}\nshare $\\beta_{k}$ = {b:.3g}\n"
             f"$\\mathbf{{P}}/\\beta_{k}$, $\\mathbf{{Q}}/\\beta_{k}$", "#dbe9f6", width=2.4,
             height=1.0)
        _arrow(ax, (2.75, y), (3.45, y), "$\\mathbf{z}$", text_xy=(3.1, y + 0.17))
        end = (7.4, 2.75 + 0.25 * (1 - k) + 0.12)
        _arrow(ax, (5.95, y + 0.12), end, f"$\\hat{{\\mathbf{{x}}}}_{k}, \\mathbf{{P}}_{k}$",
               text_xy=(6.45, y + 0.12 + (end[1] - y - 0.12) * 0.35 + 0.2), ha="center")
        if sc.mode == "reset":
            _arrow(ax, (7.4, 2.5 + 0.25 * (1 - k) - 0.12), (5.95, y - 0.2), color="C3", ls="--",
                   rad=-0.25)
    _box(ax, (8.6, 2.6), "master filter\n(fusion)\n"
         "$\\mathbf{P}_f^{-1} = \\sum_i \\mathbf{P}_i^{-1}$\n"
         "$\\hat{\\mathbf{x}}_f = \\mathbf{P}_f \\sum_i \\mathbf{P}_i^{-1}\\hat{\\mathbf{x}}_i$",
         "#fde2c8", width=2.2, height=1.6)
    _arrow(ax, (8.6, 3.45), (8.6, 4.6), "", color="k")
    ax.text(8.6, 4.8, "navigation solution $\\hat{\\mathbf{x}}_f, \\mathbf{P}_f$", ha="center",
            fontsize=8)
    reset = sc.mode == "reset"
    ax.text(8.6, 0.85, "reset mode: after each fusion\nevery local restarts from\n"
            "$\\hat{\\mathbf{x}}_i \\leftarrow \\hat{\\mathbf{x}}_f$, "
            "$\\mathbf{P}_i \\leftarrow \\mathbf{P}_f/\\beta_i$ (dashed red)" if reset else
            "no-reset mode: the locals run\non their own; the master\nonly fuses",
            fontsize=8, color="C3" if reset else "0.3", ha="center")
    ax.set(xlim=(0, 10), ylim=(-0.3, 5.2),
           title=f"The federated filter: {len(subs)} local filters, one master, and the reset")
    ax.axis("off")
    return fig


def plot_isolate_rejoin(subsystem="uv"):
    """The isolation and rejoining rule of the fault-tolerant filter, as a state diagram.

    A connected subsystem does time and measurement updates and is fused; when its detector
    flags an onset it is switched out: time updates only, left out of the fusion, its share
    renormalised over the others. Every ``check_every`` epochs it may rejoin, when (1) its
    detector is clear and (2) the sum of its last ``W`` normalised innovations squared is
    below ``chi2.isf(readmit_alpha, W m)`` (chapter 8, our rule; the paper gives none). ``W``,
    ``m``, ``readmit_alpha`` and ``check_every`` are the defaults of
    :func:`xnavlab.mars.faults.fault_tolerance.run_fault_tolerant`.

    Parameters
    ----------
    subsystem : {"xnav", "uv", "cns"}
        Whose window and threshold are written out (all three are listed).

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> texts = " ".join(figure_texts(plot_isolate_rejoin()))
    >>> all(w in texts for w in ("IN", "OUT", "time update only", "detector clear", "W = 100"))
    True
    """
    from matplotlib.figure import Figure
    from scipy.stats import chi2

    from xnavlab.mars.faults import fault_tolerance
    from xnavlab.mars.navigation import scenarios
    from xnavlab.mars.timing import pulsars

    subsystem = check_choice("subsystem", subsystem, tuple(READMIT_WINDOWS))
    defaults = inspect.signature(fault_tolerance.run_fault_tolerant).parameters
    alpha = check_real("readmit_alpha", defaults["readmit_alpha"].default, 0.0, 1.0)
    every = defaults["check_every"].default
    sc = scenarios.MarsScenario()
    dof = {"xnav": len(pulsars.PAPER_PULSARS), "uv": 3, "cns": 3}
    W, m = READMIT_WINDOWS[subsystem], dof[subsystem]

    fig = Figure(figsize=(8.5, 4.4), layout="constrained")
    ax = fig.add_subplot()
    _box(ax, (2.0, 3.0), "IN (connected)\ntime update + measurement update\nfused by the master",
         "#d9f0d3", width=3.2, height=1.2, fontsize=8.5)
    _box(ax, (8.0, 3.0), "OUT (isolated)\ntime update only\nnot fused; its share goes\n"
         "to the connected locals;\nheld at the master's estimate", "#f6d5d5", width=3.2,
         height=1.4, fontsize=8.5)
    _arrow(ax, (3.6, 3.35), (6.4, 3.35), "detector flags an onset\n(the flagged measurement "
           "is left out)", text_xy=(5.0, 3.95), rad=-0.15, color="C3")
    _arrow(ax, (6.4, 2.65), (3.6, 2.65), "", rad=-0.15, color="C2")
    ax.text(5.0, 1.7, f"every {every} epochs of {sc.dt_uv:g} s ({every * sc.dt_uv:g} s):"
            "\n(1) detector clear AND\n(2) innovation chi-square quiet:\n"
            f"$\\sum_{{l=k-W+1}}^{{k}} \\nu_l^T S_l^{{-1}} \\nu_l < \\chi^2_{{1-\\alpha_r}}(Wm)$",
            ha="center", va="center", fontsize=8.5, color="C2")
    _arrow(ax, (7.6, 3.72), (8.4, 3.72), "", rad=-1.4, color="0.4")
    ax.text(8.0, 4.45, "otherwise stay out", fontsize=7.5, color="0.4", ha="center")
    _arrow(ax, (1.6, 3.62), (2.4, 3.62), "", rad=-1.4, color="0.4")
    ax.text(2.0, 4.35, "detector quiet: stay in", fontsize=7.5, color="0.4", ha="center")
    rows = [f"{_NAMES[k]}: W = {READMIT_WINDOWS[k]}, m = {dof[k]}, threshold "
            f"{chi2.isf(alpha, READMIT_WINDOWS[k] * dof[k]):.1f}" for k in READMIT_WINDOWS]
    ax.text(5.0, 0.2, f"$\\alpha_r$ = {alpha:g};  " + ";  ".join(rows), ha="center",
            fontsize=7.5)
    ax.set(xlim=(0, 10), ylim=(-0.1, 4.8),
           title=f"Isolating and rejoining a subsystem ({_NAMES[subsystem]}: W = {W}, m = {m})")
    ax.axis("off")
    return fig
