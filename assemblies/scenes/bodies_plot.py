"""Pictures of the seed's exercise bodies, drawn as the book draws them: the cylinder on
its incline (8.1), the shell on its table (fig. 8.1), the rod on its rollers (fig. 9.11),
the disk's axis coning (fig. 8.3) and the energy and momentum ellipsoids (fig. 8.2)."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..plot import pyplot
from ..result import Result

SNAPSHOTS = 5  # bodies drawn along a run: enough to read the motion, few enough to see
WIDTHS = {"width_ratios": [1, 1.3]}  # the drawing beside its graph


def _save(fig, title: str, path: str | Path) -> None:
    plt = pyplot()
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _snapshots(n: int) -> np.ndarray:
    return np.linspace(0, n - 1, SNAPSHOTS).astype(int)


def _against_closed_form(graph, t, measured, label: str, closed_form, form_label: str,
                         ylabel: str) -> None:
    """The right-hand panel: a measured curve over time, its closed form dashed on it."""
    graph.plot(t, measured, lw=2.5, label=label)
    graph.plot(t, closed_form, "k--", lw=1, label=form_label)
    graph.set_xlabel("time [s]")
    graph.set_ylabel(ylabel)
    graph.grid(alpha=0.3)
    graph.legend(fontsize=8, loc="upper right")


def _reference(result: Result, name: str) -> float:
    """The reference of the run's figure `name`: a picture draws the closed form its
    figures were held to, so it follows any --param (a run sets figures before pictures)."""
    return next((f.reference for f in getattr(result, "figures", []) if f.name == name), math.nan)


def plot_cylinder(result: Result, title: str, path: str | Path, instance: str = "cylinder") -> None:
    """Left: the incline with the cylinder drawn at equal time steps, a radius marking the
    angle it rolled through (phi = s / R, Eq. 8.1). Right: s(t) beside Eq. 8.2's parabola
    and a frictionless slide's, (3/2) x steeper."""
    plt = pyplot()
    t, s, phi = result["time"], result[f"{instance}.s"], result[f"{instance}.phi"]
    a = _reference(result, "a")
    alpha = math.atan(3 * _reference(result, "mu_min"))  # friction / N = tan(alpha) / 3
    R = float(s[-1] / phi[-1])
    fig, (side, graph) = plt.subplots(1, 2, figsize=(12, 4.8))
    down = np.array([math.cos(alpha), -math.sin(alpha)])
    normal = np.array([math.sin(alpha), math.cos(alpha)])
    far = float(s.max()) + R
    side.plot([-R * down[0], far * down[0]], [-R * down[1], far * down[1]], color="0.3", lw=1.5)
    side.plot([-R * down[0], far * down[0]], [far * down[1]] * 2, color="0.7", lw=0.8)
    for k, i in enumerate(_snapshots(len(t))):
        centre = s[i] * down + R * normal
        shade = plt.cm.viridis(k / (SNAPSHOTS - 1))
        side.add_patch(plt.Circle(tuple(centre), R, fill=False, color=shade, lw=1.5))
        # a radius fixed in the cylinder: it starts along the normal and turns clockwise
        # (rolling down to the right) by phi
        mark = centre + R * (math.cos(phi[i]) * normal + math.sin(phi[i]) * down)
        side.plot([centre[0], mark[0]], [centre[1], mark[1]], color=shade, lw=1.2)
        side.annotate(f"{t[i]:.2g} s", tuple(centre + 1.5 * R * normal), ha="center", fontsize=8)
    side.set_aspect("equal", adjustable="datalim")
    side.set_title("the cylinder at equal time steps")
    side.set_xlabel("x [m]")
    side.set_ylabel("y [m]")
    graph.plot(t, s, lw=2.5, label="s(t) measured")
    graph.plot(t, s[0] + result[f"{instance}.v"][0] * t + a * t**2 / 2, "k--", lw=1,
               label="rolling: s'' = (2/3) g sin θ (Eq. 8.2)")
    graph.plot(t, s[0] + result[f"{instance}.v"][0] * t + 1.5 * a * t**2 / 2, ":",
               color="tab:red", label="sliding without friction: s'' = g sin θ")
    graph.set_xlabel("time [s]")
    graph.set_ylabel("distance down the slope [m]")
    graph.grid(alpha=0.3)
    graph.legend(fontsize=8)
    _save(fig, title, path)


def _shell_outline(x_O: float, R: float, phi: float) -> tuple[np.ndarray, np.ndarray]:
    """The shell's section, a half circle open side up at phi = 0, turned by phi about its
    centre O = (x_O, R); G = O + (R/2)(-sin phi, -cos phi), as the seed places it."""
    u = np.linspace(-math.pi / 2, math.pi / 2, 80)
    return x_O - R * np.sin(phi + u), R - R * np.cos(phi + u)


def plot_shell(result: Result, title: str, path: str | Path, instance: str = "shell") -> None:
    """Left: the shell at the start, upright and at the other extreme, G marked (fig. 8.1).
    Right: the tilt against time beside the seed's linear oscillation at the same
    amplitude, which drifts ahead by the amplitude's frequency shift."""
    plt = pyplot()
    t, phi = result["time"], result[f"{instance}.phi"]
    x_G, y_G, x_O = (result[f"{instance}.{k}"] for k in ("x_G", "y_G", "x_contact"))
    R = float(y_G[0] / (1 - math.cos(phi[0]) / 2))  # y_G = R - (R/2) cos(phi)
    fig, (side, graph) = plt.subplots(1, 2, figsize=(12, 4.8), gridspec_kw=WIDTHS)
    # within the first period (2 pi / omega0, the linear one, to a few per cent): the
    # first upright crossing and the far extreme
    period = int(np.searchsorted(t, 2 * math.pi / _reference(result, "omega0"))) or len(t)
    upright = int(np.argmin(np.abs(phi[:period // 2])))
    extreme = int(np.argmax(-math.copysign(1.0, phi[0]) * phi[:period]))
    for i, colour in zip((0, upright, extreme), ("tab:blue", "tab:green", "tab:orange")):
        xs, ys = _shell_outline(float(x_O[i]), R, float(phi[i]))
        side.plot(xs, ys, color=colour, lw=2, label=f"t = {t[i]:.3g} s, φ = {phi[i]:+.2f}")
        side.plot(x_G[i], y_G[i], "o", color=colour, ms=5)
    side.axhline(0.0, color="0.3", lw=1)
    side.set_aspect("equal", adjustable="datalim")
    side.set_title("shell on the table (dots: G)")
    side.set_xlabel("x [m]")
    side.set_ylabel("y [m]")
    side.legend(fontsize=8, loc="upper right")
    _against_closed_form(graph, t, phi, "φ(t) measured",
                         phi[0] * np.cos(_reference(result, "omega0") * t),
                         "the seed's linearisation", "tilt φ [rad]")
    _save(fig, title, path)


def plot_rod(result: Result, title: str, path: str | Path, instance: str = "rod") -> None:
    """Left: the rod on its rollers at its two extremes and in the middle, the rollers'
    spin marked (fig. 9.11). Right: x(t) beside the closed form."""
    plt = pyplot()
    t, x = result["time"], result[f"{instance}.x"]
    w = _reference(result, "omega")
    N_1, N_2 = result[f"{instance}.N_1"], result[f"{instance}.N_2"]
    far = int(np.argmax(np.abs(x)))
    D = float(2 * x[far] * (N_1[far] + N_2[far]) / (N_2[far] - N_1[far]))  # N_2 - N_1 = 2 m g x / D
    reach = float(result[f"{instance}.margin"][far] + abs(x[far]))  # min(D/2, (L - D)/2)
    L = D + 2 * reach if reach < D / 2 - 1e-12 else 2 * D  # L >= 2D: only a lower bound is known
    fig, (side, graph) = plt.subplots(1, 2, figsize=(12, 4.2), gridspec_kw=WIDTHS)
    r = D / 8
    for centre, spin in ((-D / 2, "↻"), (D / 2, "↺")):
        side.add_patch(plt.Circle((centre, -r), r, fill=False, color="0.3", lw=1.5))
        side.annotate(spin, (centre, -r), ha="center", va="center", fontsize=14)
    for i, colour, lift in ((int(np.argmax(x)), "tab:red", 0.0), (int(np.argmin(x)), "tab:blue",
                                                                 0.04 * D)):
        side.plot([x[i] - L / 2, x[i] + L / 2], [lift, lift], color=colour, lw=4, alpha=0.7,
                  label=f"x = {x[i]:+.3f} m")
        side.plot(x[i], lift, "k|", ms=12)
    side.set_aspect("equal", adjustable="datalim")
    side.set_title("rod on counter-rotating rollers")
    side.set_xlabel("x [m]")
    side.legend(fontsize=8, loc="upper right")
    v0 = result[f"{instance}.v"][0]
    _against_closed_form(graph, t, x, "x(t) measured",
                         x[0] * np.cos(w * t) + v0 / w * np.sin(w * t),
                         "x0 cos(ωt) + (v0/ω) sin(ωt), ω² = 2gμ/D", "rod centre x [m]")
    _save(fig, title, path)


def plot_wobble(result: Result, title: str, path: str | Path, instance: str = "disk") -> None:
    """Left: the disk's axis seen along X, its tip going round H (fig. 8.3's cone), H's
    direction marked. Right: the angle the axis has turned about H and the angle the disk
    has spun about its axis, against time: the first climbs twice as fast."""
    plt = pyplot()
    from .bodies_seed import cone_angle, disk_angular_momentum  # the figures' own measures
    t = result["time"]
    n = np.stack([result[f"{instance}.n_{a}"] for a in "XYZ"], axis=1)
    # H's direction does not depend on I_s
    H = disk_angular_momentum(*(result[f"{instance}.{k}"][:1] for k in
                                ("phi", "theta", "psi", "phi_dot", "theta_dot", "psi_dot")), 1.0)[0]
    axis = H / np.linalg.norm(H)
    fig, (end, graph) = plt.subplots(1, 2, figsize=(12, 5), gridspec_kw=WIDTHS)
    end.plot(n[:, 1], n[:, 2], lw=1.5, color="tab:blue", label="tip of the disk's axis n")
    end.plot(n[:1, 1], n[:1, 2], "o", color="tab:green", label="start")
    end.plot([axis[1]], [axis[2]], "k+", ms=12, label="H (fixed)")
    end.plot([0], [0], "x", color="0.5", label="X axis")
    end.set_aspect("equal", adjustable="datalim")
    end.set_xlabel("n_Y")
    end.set_ylabel("n_Z")
    end.set_title("the disk's axis seen along X")
    end.grid(alpha=0.3)
    end.legend(fontsize=8, loc="upper right")
    wobble = cone_angle(n, axis)
    spin_rate = result[f"{instance}.spin"]
    spin = np.concatenate([[0.0], np.cumsum(np.diff(t) * (spin_rate[1:] + spin_rate[:-1]) / 2)])
    graph.plot(t, wobble - wobble[0], lw=2.5, label="wobble: angle of n about H")
    graph.plot(t, spin, lw=2.5, label="spin: angle about the disk's axis")
    graph.plot(t, 2 * spin, "k--", lw=1, label="2 x spin (seed 8.3.2, 8.4)")
    graph.set_xlabel("time [s]")
    graph.set_ylabel("angle [rad]")
    graph.grid(alpha=0.3)
    graph.legend(fontsize=8)
    _save(fig, title, path)


def plot_damper(result: Result, title: str, path: str | Path, instance: str = "body") -> None:
    """Left: seed fig. 8.2 in three dimensions: the body's rates locked to its sphere,
    w = h / (I + J), lie on the H ellipsoid (I w)^2 = H^2, and move from its minor-axis tip
    to its major-axis tip as the T ellipsoid shrinks. Right: T falling to H^2 / (2 I_max)
    and the angle of H from the major axis."""
    plt = pyplot()
    t, T = result["time"], result[f"{instance}.T"]
    h = np.stack([result[f"{instance}.h_{a}"] for a in "xyz"], axis=1)
    w = np.stack([result[f"{instance}.w_{a}"] for a in "xyz"], axis=1)
    # the locked moments from the start, where the sphere turns with the body: h = (I + J) w
    locked = np.abs(h[0] / np.where(np.abs(w[0]) > 1e-9, w[0], np.nan))
    H = float(np.linalg.norm(h[0]))
    fig = plt.figure(figsize=(12, 5.2))
    space = fig.add_subplot(1, 2, 1, projection="3d")
    u, v = np.meshgrid(np.linspace(0, 2 * math.pi, 40), np.linspace(0, math.pi, 20))
    semi = H / locked
    space.plot_wireframe(semi[0] * np.cos(u) * np.sin(v), semi[1] * np.sin(u) * np.sin(v),
                         semi[2] * np.cos(v), color="0.75", lw=0.4)
    rates = h / locked
    space.plot(rates[:, 0], rates[:, 1], rates[:, 2], color="tab:blue", lw=0.9,
               label="w = h / (I + J)")
    space.plot(*rates[:1].T, "o", color="tab:green", label="start: near the minor axis")
    space.plot(*rates[-1:].T, "s", color="tab:red", label="end: the major axis")
    space.set_xlabel("ω_x")
    space.set_ylabel("ω_y")
    space.set_zlabel("ω_z")
    space.set_box_aspect(tuple(np.nan_to_num(semi, nan=1.0)))
    space.set_title("on the H ellipsoid (seed fig. 8.2)")
    space.legend(fontsize=8, loc="upper left")
    energy = fig.add_subplot(1, 2, 2)
    energy.plot(t, T, lw=2, label="kinetic energy T")
    energy.axhline(_reference(result, "T_end"), color="k", ls="--", lw=1, label="H² / 2 I_max")
    energy.set_xlabel("time [s]")
    energy.set_ylabel("T [J]")
    energy.grid(alpha=0.3)
    angle = energy.twinx()
    angle.semilogy(t, np.maximum(result[f"{instance}.beta"], 1e-12), color="tab:purple", lw=1,
                   label="angle of H from the major axis")
    angle.set_ylabel("angle from the major axis [rad]", color="tab:purple")
    lines, more = energy.get_legend_handles_labels(), angle.get_legend_handles_labels()
    energy.legend(lines[0] + more[0], lines[1] + more[1], fontsize=8, loc="center right")
    _save(fig, title, path)
