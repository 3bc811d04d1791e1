"""The seed's 3-D rigid bodies as scenes: the rolling coin (ch. 6), a torque-free flip (8.3)
and the skate (5.5), each with its conservation figures and one physical prediction."""
from __future__ import annotations

import math

import numpy as np

from components.bodies.rigid_bodies import Skate, TorqueFreeBody
from components.bodies.rolling_coin import (RollingCoin, critical_spin_squared, disk_inertias,
                                     steady_precession)

from ..assembly import Assembly
from ..result import Result
from .axle import period_from_crossings, zero_crossings
from .coin_plot import plot_coin
from .scene import DRIFT, Figure, Scene, solver_accuracy

COIN_OUTPUTS = ["x", "y", "z", "phi", "theta", "psi", "phi_dot", "theta_dot", "psi_dot", "lean",
                "x_C", "y_C", "F_x", "F_y", "N", "E", "v_C_x", "v_C_y", "v_C_z"]
UPRIGHT_LEAN = 1e-3      # rad: small enough for the linearised lean to hold to ~1e-6
UPRIGHT_SPEED_RATIO = 1.1
CIRCLE_THETA, CIRCLE_SPIN = math.pi / 3, -8.0


def _coin(name: str, **starts) -> Assembly:
    asm = Assembly(name)
    asm.add("coin", RollingCoin(m=1.0, R=1.0, g=9.81, **starts))
    return asm


def _drift(values: np.ndarray, relative: bool = True) -> float:
    scale = abs(values[0]) if relative and values[0] != 0 else 1.0
    return float(np.abs(values - values[0]).max() / scale)


def _conservation_figures(result: Result, asm: Assembly) -> list[Figure]:
    slip = max(float(np.abs(result[f"coin.v_C_{k}"]).max()) for k in "xyz")
    speed = asm.component("coin").values["R"] * float(np.abs(result["coin.psi_dot"]).max())
    # conserved exactly by the equations: what is left is the solver's error, accumulated
    return [Figure("E_drift", "largest |E - E(0)| / |E(0)| (no dissipation: 0)",
                   _drift(result["coin.E"]), 0.0, solver_accuracy(result, 1.0, DRIFT),
                   source="conservation law (exact: 0)"),
            Figure("v_C_max", "largest |velocity of the contact point| [m/s] (no slip: 0)",
                   slip, 0.0, solver_accuracy(result, speed, DRIFT),
                   source="rolling constraint (kinematics: 0)")]


# --- coin_rolling: any start given with --param coin.NAME=VALUE ---------------
def _coin_rolling() -> Assembly:
    return _coin("coin_rolling")


# --- coin_upright: straight rolling just above the critical speed ------------------
def _coin_upright() -> Assembly:
    p = RollingCoin().values
    spin = UPRIGHT_SPEED_RATIO * math.sqrt(critical_spin_squared(p["m"], p["R"], p["g"]))
    return _coin("coin_upright", theta=math.pi / 2 - UPRIGHT_LEAN, phi_dot=0.0, theta_dot=0.0,
                 psi_dot=-spin)


def _coin_upright_figures(result: Result, asm: Assembly) -> list[Figure]:
    """Linearised (see critical_spin_squared), with phi' = 0 at the start:
    lean'' = b lean - k W^2 (lean - lean0), k = I_a (I_a + m R^2) / (I_d (I_d + m R^2)),
    b = m g R / (I_d + m R^2). The lean oscillates at sqrt(k W^2 - b) = sqrt(k (W^2 - W_c^2))
    about k W^2 lean0 / (k W^2 - b): the measured frequency gives back the critical speed,
    to be compared with sqrt(g R / 3), and the largest lean is twice that centre less lean0."""
    coin = asm.component("coin")
    m, R, g = (coin.values[k] for k in ("m", "R", "g"))
    I_d, I_a = disk_inertias(m, R)
    k = I_a * (I_a + m * R**2) / (I_d * (I_d + m * R**2))
    b = m * g * R / (I_d + m * R**2)
    spin = abs(coin.starts["psi_dot"])
    lean = result["coin.lean"]
    stiffness = k * spin**2 - b
    if not stiffness > 1e-9 * b:
        # at (to rounding) or below the critical speed the linearised lean has no restoring
        # stiffness: it does not oscillate but grows, so there is no frequency to measure
        # and no bounded largest lean to predict (a sweep over the spin runs here); both
        # figures fail, saying so
        return [Figure("v_crit", "critical speed [m/s] from the lean frequency: undefined, "
                       "the rolling speed R |psi'| is not above the critical speed sqrt(g R / 3)",
                       math.nan, math.sqrt(g * R / 3),
                       source="seed 6 (critical speed sqrt(g R / 3)), measured through our linearisation"),
                Figure("lean_max", "largest |lean| / start lean: the linear lean grows without "
                       "bound at or below the critical speed (reference inf)",
                       float(np.abs(lean).max()) / abs(lean[0]), math.inf,
                       source="closed form (linearised lean about the upright, derived here; not the seed's)"),
                *_conservation_figures(result, asm)]
    period = period_from_crossings(result["time"], lean - lean.mean(), -result["coin.theta_dot"])
    frequency = 2 * math.pi / period
    measured = R * math.sqrt(max(spin**2 - frequency**2 / k, 0.0))
    lean_text = ("largest |lean| / start lean vs linear: oscillation about "
                 "k W^2 lean0 / (k W^2 - b), b = m g R / (I_d + m R^2)")
    lean_max = abs(2 * k * spin**2 / stiffness - 1)
    # the linearisation drops terms O(lean^2) of k W^2 and b; the restoring stiffness
    # k W^2 - b, a near cancellation just above the critical speed, magnifies them by
    # k W^2 / (k W^2 - b) (5.8 at 1.1 x critical): relative error ~ that x lean_max^2
    linear = k * spin**2 / stiffness * (lean_max * abs(lean[0])) ** 2
    return [Figure("v_crit", "critical speed [m/s] from the lean frequency vs sqrt(g R / 3)",
                   measured, math.sqrt(g * R / 3), linear, relative=True,
                   source="seed 6 (critical speed sqrt(g R / 3)), measured through our linearisation"),
            Figure("lean_max", lean_text,
                   float(np.abs(lean).max()) / abs(lean[0]), lean_max, linear, relative=True,
                   source="closed form (linearised lean about the upright, derived here; not the seed's)"),
            *_conservation_figures(result, asm)]


# --- coin_circle: steady circular rolling ------------------------------------
def _coin_circle() -> Assembly:
    p = RollingCoin().values
    precession = min(steady_precession(CIRCLE_THETA, CIRCLE_SPIN, p["R"], p["g"]), key=abs)
    return _coin("coin_circle", theta=CIRCLE_THETA, phi_dot=precession, theta_dot=0.0,
                 psi_dot=CIRCLE_SPIN)


def contact_circle_radius(theta: float, phi_dot: float, psi_dot: float, R: float) -> float:
    """Steady rolling: G circles at radius |V / phi'| (V = -R (psi' + phi' cos theta), its
    speed), and C lies R cos(theta) further out along the same radius, opposite the centre
    offset a_G / phi'^2 = (V / phi') j at phi = 0."""
    if phi_dot == 0.0:  # no turning: C runs along a straight line, a circle of no curvature
        return math.inf
    V = -R * (psi_dot + phi_dot * math.cos(theta))
    return abs(V / phi_dot + R * math.cos(theta))


def fitted_circle_radius(x: np.ndarray, y: np.ndarray) -> float:
    """Least-squares circle through points: x^2 + y^2 = 2 a x + 2 b y + c."""
    A = np.column_stack([2 * x, 2 * y, np.ones_like(x)])
    (a, b, c), *_ = np.linalg.lstsq(A, x**2 + y**2, rcond=None)
    return float(math.sqrt(c + a * a + b * b))


def _coin_circle_figures(result: Result, asm: Assembly) -> list[Figure]:
    s, R = asm.component("coin").starts, asm.component("coin").values["R"]
    radius = contact_circle_radius(s["theta"], s["phi_dot"], s["psi_dot"], R)
    # an exact steady motion, neutrally stable: the solver's error accumulates along it
    return [Figure("lean_drift", "largest |theta - theta(0)| [rad] (steady: 0)",
                   _drift(result["coin.theta"], relative=False), 0.0,
                   solver_accuracy(result, s["theta"], DRIFT),
                   source="steady motion (derived here from the coin's equations; not the seed's numbers)"),
            Figure("r_contact", "radius of the contact path [m] vs the steady-motion relation",
                   fitted_circle_radius(result["coin.x_C"], result["coin.y_C"]), radius,
                   solver_accuracy(result, radius, DRIFT),
                   source="closed form (steady-motion contact circle, derived here; not the seed's)"),
            *_conservation_figures(result, asm)]


# --- torque_free_flip: spin about the intermediate axis ------------------------
FLIP_NUDGE = 1e-3


def _torque_free_flip() -> Assembly:
    asm = Assembly("torque_free_flip")
    asm.add("body", TorqueFreeBody(I_xx=1.0, I_yy=2.0, I_zz=3.0, w_x=FLIP_NUDGE, w_y=1.0, w_z=0.0))
    return asm


def _torque_free_flip_figures(result: Result, asm: Assembly) -> list[Figure]:
    """Linearised about w = (0, W, 0): w_x = xi0 cosh(lambda t), lambda^2 =
    W^2 (I_yy - I_xx)(I_zz - I_yy) / (I_xx I_zz); measured where w_x reaches 10 xi0."""
    body = asm.component("body")
    p, W, xi0 = body.values, body.starts["w_y"], body.starts["w_x"]
    lam = abs(W) * math.sqrt((p["I_yy"] - p["I_xx"]) * (p["I_zz"] - p["I_yy"]) / (p["I_xx"] * p["I_zz"]))
    # where w_x reaches 10 xi0, on the cubic Hermite interpolant of w_x with its exact
    # derivative (Euler's Eq. 8.3): O(h^4), not the samples' own spacing
    t, side = result["time"], math.copysign(1.0, xi0)
    wy, wz = result["body.w_y"], result["body.w_z"]
    dwx = -(p["I_zz"] - p["I_yy"]) * wy * wz / p["I_xx"]
    roots = zero_crossings(t, side * result["body.w_x"] - 10 * abs(xi0), side * dwx)
    measured = math.acosh(10.0) / float(roots[0]) if len(roots) else math.nan
    # the interpolant errs by h^4 / 384 times max |w_x''''| ~ lam^4 e^(lam h) 10 xi0 over
    # the interval, which moves the crossing by that over w_x' ~ lam 10 xi0: relative to
    # t = acosh(10) / lam, (lam h)^4 e^(lam h) / (384 acosh(10))
    h = float(np.max(np.diff(t))) if len(t) > 1 else math.inf
    interpolation = (lam * h) ** 4 * math.exp(lam * h) / (384 * math.acosh(10.0))
    # the linearisation drops terms O((w_x / W)^2) = (10 xi0 / W)^2 at the measuring point
    # (w_y^2 falls by that much); the exact flip: on the orbit about the minor axis w_y is
    # extreme where w_z = 0, and then energy and |H| give back w_y = -w_y(0) exactly
    return [Figure("growth", "departure rate from intermediate-axis spin [1/s] vs linearised",
                   measured, lam, (10 * xi0 / W) ** 2 + interpolation
                   + solver_accuracy(result), relative=True,
                   source="closed form (linearised intermediate-axis growth rate, textbook; seed 8.3 states instability)"),
            Figure("H_drift", "largest relative change of |H|", _drift(result["body.H"]), 0.0,
                   solver_accuracy(result, 1.0, DRIFT),
                   source="conservation law (exact: 0)"),
            Figure("T_drift", "largest relative change of the kinetic energy",
                   _drift(result["body.T"]), 0.0, solver_accuracy(result, 1.0, DRIFT),
                   source="conservation law (exact: 0)"),
            Figure("flipped", "smallest w_y / w_y(0) vs -1 (energy and |H| where w_z = 0)",
                   float(result["body.w_y"].min() / W), -1.0,
                   solver_accuracy(result, 1.0, DRIFT),
                   source="conservation of energy and |H| (exact flip)")]


# --- skate: seed 5.5 ----------------------------------------------------------
def _skate() -> Assembly:
    asm = Assembly("skate")
    asm.add("skate", Skate())
    return asm


def _skate_turn(u0: float, omega0: float, m: float, J: float, L: float):
    """(sqrt K / L, a, t0) of the skate's turn (see skate_settled_heading)."""
    K = (J + m * L**2) / m
    V = math.sqrt(u0**2 + K * omega0**2)
    a = L * V / K
    return math.sqrt(K) / L, a, math.atanh(u0 / V) / a


def skate_settled_heading(theta0: float, u0: float, omega0: float, m: float, J: float,
                          L: float) -> float:
    """Where the seed's skate ends up pointing. With u the knife edge's speed along the
    blade, u' = -L omega^2 and (J + m L^2) omega' = m L u omega; energy gives
    u^2 + K omega^2 = V^2, K = (J + m L^2)/m, so u = -V tanh(a (t - t0)) with a = L V / K,
    tanh(a t0) = u0 / V, omega ~ sech, and the heading turns in all by
    sign(omega0) (sqrt K / L) (pi/2 + atan(sinh(a t0)))."""
    scale, a, t0 = _skate_turn(u0, omega0, m, J, L)
    return theta0 + math.copysign(1.0, omega0) * scale * (
        math.pi / 2 + math.atan(math.sinh(a * t0)))


def skate_heading_to_go(u0: float, omega0: float, m: float, J: float, L: float,
                        t: float) -> float:
    """How far the heading still turns after time t: the sech of omega integrates to
    (sqrt K / L) (pi/2 - atan(sinh(a (t - t0)))), exponentially small once a (t - t0) >> 1."""
    scale, a, t0 = _skate_turn(u0, omega0, m, J, L)
    return scale * (math.pi / 2 - math.atan(math.sinh(a * (t - t0))))


def _skate_figures(result: Result, asm: Assembly) -> list[Figure]:
    sk = asm.component("skate")
    p, s = sk.values, sk.starts
    th = s["theta"]
    u0 = s["v_x"] * math.cos(th) + s["v_y"] * math.sin(th)
    settled = skate_settled_heading(th, u0, s["omega"], p["m"], p["J"], p["L"])
    speed = math.hypot(s["v_x"], s["v_y"])
    return [Figure("theta_end", "heading at the stop time [rad] vs the settled heading",
                   float(result["skate.theta"][-1]), settled,
                   skate_heading_to_go(u0, s["omega"], p["m"], p["J"], p["L"],
                                       float(result["time"][-1]))
                   + solver_accuracy(result, settled, DRIFT),
                   source="closed form (settled heading from seed 5.5's equations, integrated by hand here)"),
            Figure("E_drift", "largest relative change of the energy", _drift(result["skate.E"]),
                   0.0, solver_accuracy(result, 1.0, DRIFT),
                   source="conservation law (exact: 0)"),
            Figure("constraint", "largest |Eq. 5.19 residual| [m/s] (0)",
                   float(np.abs(result["skate.constraint"]).max()), 0.0,
                   solver_accuracy(result, speed, DRIFT),
                   source="seed Eq. 5.19 (knife-edge constraint: 0)")]


def _record(instance: str, names: list[str]) -> list[str]:
    return [f"{instance}.{n}" for n in names]


COIN_SCENES: dict[str, Scene] = {
    "coin_rolling": Scene(
        "coin_rolling", "seed ch. 6: a coin rolling without slip from a given state",
        _coin_rolling, stop_time=10.0, step=0.01, tolerance=1e-12,
        record=_record("coin", COIN_OUTPUTS), figures=_conservation_figures,
        plot=["coin.lean", "coin.N", "coin.E"], picture=plot_coin,
        seed="6", reference="energy and contact-point speed"),
    "coin_upright": Scene(
        "coin_upright", "seed ch. 6: straight upright rolling at 1.1 x the critical speed",
        _coin_upright, stop_time=20.0, step=0.01, tolerance=1e-12,
        record=_record("coin", COIN_OUTPUTS), figures=_coin_upright_figures,
        plot=["coin.lean", "coin.phi_dot", "coin.E"], picture=plot_coin,
        seed="6", reference="critical speed sqrt(gR/3); energy and contact-point speed"),
    "coin_circle": Scene(
        "coin_circle", "seed ch. 6: steady circular rolling at a 30 degree lean",
        _coin_circle, stop_time=10.0, step=0.01, tolerance=1e-12,
        record=_record("coin", COIN_OUTPUTS), figures=_coin_circle_figures,
        plot=["coin.lean", "coin.N", "coin.E"], picture=plot_coin,
        seed="6", reference="steady lean; energy and contact-point speed"),
    "torque_free_flip": Scene(
        "torque_free_flip", "seed 8.3: spin about the intermediate axis turns the body over",
        _torque_free_flip, stop_time=30.0, step=0.01, tolerance=1e-12,
        record=_record("body", ["w_x", "w_y", "w_z", "H", "T", "H_X", "H_Y", "H_Z", "x_X", "x_Y",
                                "x_Z"]),
        figures=_torque_free_flip_figures, plot=["body.w_x", "body.w_y", "body.w_z"], seed="8.3",
        reference="growth rate about the intermediate axis; |H| and T conserved"),
    "skate": Scene(
        "skate", "seed 5.5: skate with a knife edge on ice, its heading settles",
        _skate, stop_time=20.0, step=0.01, tolerance=1e-12,
        record=_record("skate", ["x", "y", "theta", "omega", "u", "lambda", "E", "constraint"]),
        figures=_skate_figures, plot=["skate.theta", "skate.omega", "skate.u"], seed="5.5",
        reference="settled heading; energy and Eq. 5.19 conserved"),
}

__all__ = ["COIN_SCENES", "contact_circle_radius", "fitted_circle_radius", "skate_heading_to_go",
           "skate_settled_heading"]
