"""Seed 8.6, exercises 2-5: the cone on an incline, the wobbling disk from arbitrary
angles, the inertia matrix recovered from axle experiments and the body hung by a damped
string, each against a closed form derived here or a conservation law."""
from __future__ import annotations

import math

import numpy as np

from components.bodies.axle import RigidBodyOnAxle
from components.bodies.rigid_bodies import WobblingDisk
from components.bodies.seed_bodies import ConeOnIncline
from components.bodies.string_body import RigidBodyOnString

from ..assembly import Assembly
from ..result import Result
from .axle import pendulum_period, period_from_crossings
from .bodies_seed import _DISK_RECORD, _thrown_figures, disk_attitude
from .scene import DRIFT, Figure, Scene, solver_accuracy


def _crossing_error(omega: float, step: float) -> float:
    """Relative error of a period read off zero crossings of the cubic Hermite
    interpolant: ~(omega h)^4 / 384 (see axle.py)."""
    return (omega * step) ** 4 / 384


# --- cone_incline: 8.6 exercise 2 ---------------------------------------------------
CONE = dict(m=1.0, R=0.1, h=0.3, g=9.81, alpha=0.3)
CONE_PHI0 = 0.3


def _cone() -> Assembly:
    asm = Assembly("cone_incline")
    asm.add("cone", ConeOnIncline(phi=CONE_PHI0, **CONE))
    return asm


def cone_frequency(R: float, h: float, g: float, alpha: float) -> float:
    """Small oscillations of the rolling cone, derived by hand. The apex A is fixed; the
    contact line turns at phi' in the plane and is the instantaneous axis, so the cone
    turns about it at |omega| = phi' cot(beta) (a point of the axis at distance d from A
    moves at phi' d cos(beta) and lies d sin(beta) off the contact line). About the
    contact line, I_L = I_axis cos^2(beta) + I_t sin^2(beta) with I_axis = 3 m R^2 / 10,
    I_t = 3 m (R^2 / 4 + H^2) / 5 about A: I_L cot^2(beta) = (3/20) m h^2 cos^2(beta)
    (1 + 5 cos^2(beta)). G, 3H/4 along the axis, lies (3/4) h cos^2(beta) down the
    contact line in the plane: V = -(3/4) m g h cos^2(beta) sin(alpha) cos(phi). So the
    equation of motion is the pendulum
    (3/20) h (1 + 5 cos^2 beta) phi'' + (3/4) g sin(alpha) sin(phi) = 0, and
    omega0^2 = 5 g sin(alpha) / (h (1 + 5 cos^2 beta)) = 5 g h sin(alpha) / (6 h^2 - 5 R^2)."""
    return math.sqrt(5 * g * h * math.sin(alpha) / (6 * h**2 - 5 * R**2))


def _cone_figures(result: Result, asm: Assembly) -> list[Figure]:
    cone = asm.component("cone")
    p, s = cone.values, cone.starts
    omega0 = cone_frequency(p["R"], p["h"], p["g"], p["alpha"])
    amplitude = abs(s["phi"]) if s["w"] == 0 else math.nan  # released from rest
    t, phi, w, E = result["time"], result["cone.phi"], result["cone.w"], result["cone.E"]
    measured = float(period_from_crossings(t, phi, w))
    # on a level plane (alpha = 0) nothing restores it: no period to compare
    period = float(pendulum_period(omega0, amplitude)) if omega0 > 0 else math.nan
    crossing = _crossing_error(omega0, result.settings["step"])
    shift = amplitude**2 / 16  # a pendulum's period grows by amplitude^2 / 16 (Lindstedt)
    sin_b = p["R"] / p["h"]
    H = p["h"] * math.sqrt(1 - sin_b**2)
    z_G = 3 * H / 4 * sin_b
    return [
        Figure("T", "period [s] from zero crossings vs the pendulum's 4K(sin(A/2))/omega0",
               measured, period, solver_accuracy(result, period) + period * crossing,
               source="closed form derived here (cone_frequency) and the pendulum's exact "
               "period"),
        Figure("omega0", "linear frequency [rad/s] from the period x T(A)/T(0) vs "
               "sqrt(5 g h sin(alpha) / (6 h^2 - 5 R^2))",
               omega0 * period / measured, omega0,
               solver_accuracy(result, omega0) + omega0 * crossing,
               source="closed form derived here for seed 8.6 ex. 2 (energy about the apex)"),
        Figure("omega_A", f"frequency at the amplitude [rad/s] vs the linear one (amplitude "
               f"shift {-shift:+.1e})", 2 * math.pi / measured, omega0,
               shift + 2 * shift**2 + solver_accuracy(result, 1.0), relative=True,
               source="closed form derived here, with Lindstedt's amplitude shift"),
        Figure("z_G", "largest |z_G - (3H/4) sin(beta)| [m] (G's height: constant)",
               float(np.abs(result["cone.z_G"] - z_G).max()), 0.0,
               solver_accuracy(result, p["h"]), source="geometry of the cone on its side"),
        Figure("E_drift", "largest |E - E(0)| [J] (rolling does no work: 0)",
               float(np.abs(E - E[0]).max()), 0.0,
               solver_accuracy(result, p["m"] * p["g"] * p["h"], DRIFT),
               source="conservation law (rolling does no work)"),
    ]


# --- wobble_exercise: 8.6 exercise 3 --------------------------------------------------
WOBBLE_ANGLES = dict(phi=1.0, theta=1.3, psi=-0.4)  # the seed's
WOBBLE_NUDGE = 0.05  # rad/s, the "small perturbation not parallel to n"


def wobble_start(phi: float, theta: float, psi: float, nudge: float) -> dict:
    """Euler rates for omega(0) = n + nudge e, n = R1(phi) R3(theta) R1(psi) i the disk's
    axis and e the unit horizontal normal to it (n x Z, normalised): omega = phi' X
    + theta' R1(phi) z + psi' n, a 3x3 system in the rates."""
    one = np.array([1.0])
    R, _ = disk_attitude(one * phi, one * theta, one * psi, 0 * one, 0 * one, 0 * one)
    n = R[0, :, 0]
    e = np.cross(n, [0.0, 0.0, 1.0])
    e /= np.linalg.norm(e)
    columns = np.column_stack([[1.0, 0.0, 0.0], [0.0, -math.sin(phi), math.cos(phi)], n])
    rates = np.linalg.solve(columns, n + nudge * e)
    return dict(phi_dot=rates[0], theta_dot=rates[1], psi_dot=rates[2])


def _wobble_exercise() -> Assembly:
    asm = Assembly("wobble_exercise")
    asm.add("disk", WobblingDisk(**WOBBLE_ANGLES,
                                 **wobble_start(**WOBBLE_ANGLES, nudge=WOBBLE_NUDGE)))
    return asm


def _wobble_exercise_figures(result: Result, asm: Assembly) -> list[Figure]:
    """Exercise 3: the axis n (the rotated i) and omega(0) = n + nudge (n x Z) checked
    from the recorded angles by the rotations; then 8.3.2's exact cone about H."""
    angles = [result[f"disk.{k}"][:1] for k in
              ("phi", "theta", "psi", "phi_dot", "theta_dot", "psi_dot")]
    R, omega = disk_attitude(*angles)
    a = WOBBLE_ANGLES
    n = np.array([math.cos(a["theta"]), math.sin(a["theta"]) * math.cos(a["phi"]),
                  math.sin(a["theta"]) * math.sin(a["phi"])])  # R1(phi) R3(theta) i by hand
    e = np.cross(n, [0.0, 0.0, 1.0])
    return [Figure("n0", "|n(0) - (cos th, sin th cos ph, sin th sin ph)| (the rotated i)",
                   float(np.linalg.norm(R[0, :, 0] - n)), 0.0, 1e-14,
                   source="seed 8.6 ex. 3 (n = n_ref after the (1,3,1) rotation), by hand"),
            Figure("omega0", "|omega(0) - n - nudge (n x Z) / |n x Z|| [rad/s] (the start)",
                   float(np.linalg.norm(omega[0] - n - WOBBLE_NUDGE * e / np.linalg.norm(e))), 0.0,
                   1e-13, source="seed 8.6 ex. 3 (omega(0) = n plus a small perturbation)"),
            *_thrown_figures(result, asm)]


# --- axle_inertia: 8.6 exercise 4 ------------------------------------------------------
AXLE_MASS = 2.0
AXLE_R_GP = (0.1, 0.2, -0.15)  # P to G, found by balancing the body
AXLE_INERTIA = dict(I_xx=0.30, I_yy=0.25, I_zz=0.40, I_xy=0.05, I_xz=-0.03, I_yz=0.04)
# six axle directions, none vertical, whose n n^T span the symmetric matrices
AXLE_DIRECTIONS = ((1, 0, 0), (0, 1, 0), (1, 1, 0), (1, 0, 1), (0, 1, 1), (1, 1, 1))
AXLE_AMPLITUDE = 0.1  # rad, each released from rest this far from where it hangs


def _unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def hanging_angle(n: np.ndarray, r: np.ndarray) -> float:
    """Where the body hangs on the axle n: the turn about n that brings r's part normal to
    n straight below the axle, opposite k's part normal to n."""
    k = np.array([0.0, 0.0, 1.0])
    r_perp = r - (r @ n) * n
    k_perp = k - (k @ n) * n
    e1 = r_perp / np.linalg.norm(r_perp)
    e2 = np.cross(n, e1)
    return math.atan2(-(k_perp @ e2), -(k_perp @ e1))


def _axle_inertia() -> Assembly:
    asm = Assembly("axle_inertia")
    r = np.array(AXLE_R_GP)
    for i, direction in enumerate(AXLE_DIRECTIONS, 1):
        n = _unit(direction)
        asm.add(f"axle_{i}", RigidBodyOnAxle(
            m=AXLE_MASS, **AXLE_INERTIA, r_x=r[0], r_y=r[1], r_z=r[2], n_x=n[0], n_y=n[1],
            n_z=n[2], theta0=hanging_angle(n, r) + AXLE_AMPLITUDE))
    return asm


def inertia_rows(directions) -> np.ndarray:
    """n^T I n = rows . (I_xx, I_yy, I_zz, I_xy, I_xz, I_yz) for each unit n."""
    return np.array([[n[0]**2, n[1]**2, n[2]**2, 2 * n[0] * n[1], 2 * n[0] * n[2],
                      2 * n[1] * n[2]] for n in map(_unit, directions)])


def recover_inertia(m: float, g: float, r: np.ndarray, directions, periods,
                    amplitudes) -> np.ndarray:
    """Seed 8.5 turned round: on axle n the body is a pendulum with omega0^2 = m g
    |k_perp| |r_perp| / J_n, J_n = n^T I_cm n + m |r_perp|^2 (parts normal to n). A period
    T at amplitude A gives omega0 = 4 K(sin(A/2)) / T exactly, so each experiment gives
    n^T I_cm n; six directions whose n n^T are independent give the six entries."""
    k = np.array([0.0, 0.0, 1.0])
    values = []
    for n, T, A in zip(map(_unit, directions), periods, amplitudes):
        omega0 = pendulum_period(1.0, A) / T  # 4 K(sin(A/2)) / T
        r_perp = np.linalg.norm(r - (r @ n) * n)
        k_perp = np.linalg.norm(k - (k @ n) * n)
        values.append(m * g * k_perp * r_perp / omega0**2 - m * r_perp**2)
    return np.linalg.solve(inertia_rows(directions), np.array(values))


def _axle_inertia_figures(result: Result, asm: Assembly) -> list[Figure]:
    names = [f"axle_{i}" for i in range(1, len(AXLE_DIRECTIONS) + 1)]
    bodies = [asm.component(name) for name in names]
    p = bodies[0].values
    r = np.array([p["r_x"], p["r_y"], p["r_z"]])
    directions = [(b.values["n_x"], b.values["n_y"], b.values["n_z"]) for b in bodies]
    t, periods, amplitudes, slack = result["time"], [], [], []
    for name, body, n in zip(names, bodies, directions):
        theta, omega = result[f"{name}.theta"], result[f"{name}.omega"]
        hang = hanging_angle(_unit(n), r)
        periods.append(float(period_from_crossings(t, theta - hang, omega)))
        amplitudes.append(abs(body.starts["theta"] - hang))
        # J_n = V'' T^2 / (2 pi K-factor)^2: twice the period's relative error
        w = 2 * math.pi / periods[-1]
        slack.append(2 * (solver_accuracy(result, 1.0)
                          + _crossing_error(w, result.settings["step"])))
    I = recover_inertia(p["m"], p["g"], r, directions, periods, amplitudes)
    rows = inertia_rows(directions)
    # each n^T I n is off by at most slack x J_n; the solve spreads that by |rows^-1|
    J = [m_T_I + p["m"] * np.linalg.norm(r - (r @ _unit(n)) * _unit(n)) ** 2
         for m_T_I, n in zip(rows @ I, directions)]
    bound = np.abs(np.linalg.inv(rows)) @ (np.array(slack) * np.array(J))
    keys = ("I_xx", "I_yy", "I_zz", "I_xy", "I_xz", "I_yz")
    return [Figure(key, f"{key} [kg.m2] recovered from six axle periods vs the body's",
                   float(value), p[key], float(err),
                   source="the body's own I_cm (what seed 8.6 ex. 4 asks to measure)")
            for key, value, err in zip(keys, I, bound)]


# --- string_body: 8.6 exercise 5 ---------------------------------------------------------
STRING_START = dict(x=0.3, y=0.1, z=-1.15, v_x=0.0, v_y=0.6, v_z=0.0,
                    w_x=1.5, w_y=-1.0, w_z=3.0)


def _string_body() -> Assembly:
    asm = Assembly("string_body")
    asm.add("body", RigidBodyOnString(**STRING_START))
    return asm


def string_rest_energy(m: float, g: float, k: float, L0: float, b: float) -> float:
    """The least E: hanging still, B straight below O and G straight below B, the string
    stretched by m g / k: V = -m g (L0 + m g / k + |b|) + (m g)^2 / (2 k)."""
    return -m * g * (L0 + m * g / k + b) + (m * g) ** 2 / (2 * k)


def _string_figures(result: Result, asm: Assembly) -> list[Figure]:
    """Exercise 5: the string's pull passes through O and gravity is vertical, so H_Z
    about O is conserved; E + W_d is constant. E cannot fall to the rest energy: by
    Cauchy-Schwarz, H_Z^2 <= I_OZ (2 T), so E - E_rest >= T >= H_Z^2 / (2 I_OZ) > 0."""
    p = asm.component("body").values
    b = math.hypot(p["b_x"], p["b_y"], p["b_z"])
    E_rest = string_rest_energy(p["m"], p["g"], p["k"], p["L0"], b)
    E, W_d, H_Z = result["body.E"], result["body.W_d"], result["body.H_Z"]
    excess = E - E_rest
    floor = H_Z[0] ** 2 / (2 * result["body.I_OZ"])
    scale = float(excess[0])
    return [
        Figure("H_Z", "largest |H_Z - H_Z(0)| / |H_Z(0)| (the string pulls through O: 0)",
               float(np.abs(H_Z - H_Z[0]).max() / abs(H_Z[0])), 0.0,
               solver_accuracy(result, 1.0, DRIFT),
               source="conservation law (seed 8.6 ex. 5: vertical H about the support)"),
        Figure("E_balance", "largest |E + W_d - E(0)| / (E(0) - E_rest) (the string takes "
               "what E loses)", float(np.abs(E + W_d - E[0]).max()) / scale, 0.0,
               solver_accuracy(result, 1.0, DRIFT), source="energy balance (work of the string)"),
        Figure("E_rise", "largest rise of E between outputs / (E(0) - E_rest) (damping: 0)",
               max(0.0, float(np.diff(E).max())) / scale, 0.0,
               solver_accuracy(result, 1.0, DRIFT), source="energy balance (W_d' >= 0)"),
        Figure("E_floor", f"largest (H_Z^2/2I_OZ - (E - E_rest)) / (E(0) - E_rest), 0 if E "
               f"stays above the floor (end: E - E_rest = {excess[-1]:.3g} J >= "
               f"{floor[-1]:.3g} J, not 0)",
               max(0.0, float((floor - excess).max())) / scale, 0.0,
               solver_accuracy(result, 1.0, DRIFT),
               source="bound derived here (Cauchy-Schwarz on the conserved H_Z)"),
        Figure("q_norm", "largest | |q|^2 - 1 | (the attitude stays a rotation)",
               float(np.abs(result["body.q_norm_error"]).max()), 0.0,
               solver_accuracy(result, 1.0, DRIFT), source="invariant |q| = 1 of q' = q (x) w / 2"),
    ]


_STRING_RECORD = [f"body.{k}" for k in (
    "x", "y", "z", "E", "T", "W_d", "H_Z", "I_OZ", "l", "tension", "q_norm_error",
    "B_X", "B_Y", "B_Z", *(f"{a}_{b}" for a in "xyz" for b in "XYZ"))]

EXERCISE_SCENES: dict[str, Scene] = {
    "cone_incline": Scene(
        "cone_incline", "seed 8.6 ex. 2: a uniform cone rolls without slip on an incline, "
        "rocking about its fixed apex", _cone, stop_time=12.0, step=0.01, tolerance=1e-12,
        record=["cone.phi", "cone.w", "cone.z_G", "cone.E", "cone.omega"],
        figures=_cone_figures, plot=["cone.phi", "cone.E"],
        seed="8.6 ex. 2", reference="ω0² = 5gh sin α/(6h² − 5R²) (derived); the pendulum's "
        "exact period; G's height; energy"),
    "wobble_exercise": Scene(
        "wobble_exercise", "seed 8.6 ex. 3: the disk from phi = 1.0, theta = 1.3, psi = -0.4 "
        "spun about its axis, nudged: it wobbles at twice its spin",
        _wobble_exercise, stop_time=10.0, step=0.01, tolerance=1e-12, record=_DISK_RECORD,
        figures=_wobble_exercise_figures, plot=["disk.theta", "disk.spin"],
        seed="8.6 ex. 3", reference="n(0) and ω(0) by the rotations; the axis cones about H "
        "at |H|/I_s, 2/cos b × spin; H, T, spin conserved"),
    "axle_inertia": Scene(
        "axle_inertia", "seed 8.6 ex. 4: a body's inertia matrix recovered from its periods "
        "on six axles (section 8.5 turned round)",
        _axle_inertia, stop_time=15.0, step=0.01, tolerance=1e-12,
        record=[f"axle_{i}.{k}" for i in range(1, len(AXLE_DIRECTIONS) + 1)
                for k in ("theta", "omega")],
        figures=_axle_inertia_figures, plot=["axle_1.theta", "axle_6.theta"],
        seed="8.6 ex. 4", reference="the body's own I_cm; the pendulum's exact period"),
    "string_body": Scene(
        "string_body", "seed 8.6 ex. 5: a box hung from a point on its surface by a damped "
        "elastic string: energy falls, not to zero; vertical H about the support kept",
        _string_body, stop_time=30.0, step=0.01, tolerance=1e-10, record=_STRING_RECORD,
        figures=_string_figures, plot=["body.E", "body.H_Z"],
        seed="8.6 ex. 5", reference="H_Z about the support conserved; E + W_d constant; "
        "E − E_rest ≥ H_Z²/2I_OZ (Cauchy–Schwarz)"),
}

__all__ = ["EXERCISE_SCENES", "cone_frequency", "hanging_angle", "inertia_rows",
           "recover_inertia", "string_rest_energy", "wobble_start"]
