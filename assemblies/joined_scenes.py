"""Scenes that join elements into real engineering situations (issue 6).

- ``two_block_belt``: two blocks on one moving belt, each tied to a wall by a spring-
  damper and to each other by a spring, each with exact Coulomb friction (seed 9.2's
  stick-slip with several frictional contacts). The belt is two constant-speed
  sources, one per block's ``support`` (a connection joins exactly two ports).
- ``axle_motor``: seed 8.5's disk on its inclined axle, with Coulomb bearing
  friction, lifted by a DC motor through a torsional spring until it comes to rest.
- ``beam_friction_damper`` (issue 6) is NOT here yet. Planned: the beam tip (motion
  out) driving a Jenkins element (spring in series with a Coulomb slider: SpringBlock's
  flange_a, motion in, force out, with a light pad and g = N/m for the normal preload).

Causality (picked by the assembly from the graph): masses, rotors, the beam tip and
kinematic sources compute motion; springs and the friction element take motion in
and give forces out.
"""
from __future__ import annotations

import math

import numpy as np

from components.rotational import Motor, TorsionalSpring
from components.sources import ConstantSpeed
from components.translational import MassWithFriction, Spring, SpringDamper

from .assembly import Assembly
from .axle_scenes import seed_disk
from .result import Result
from .scenes import Figure, Scene

# --- two_block_belt ---------------------------------------------------------------
BELT_SPEED = 0.3


def _two_block_belt() -> Assembly:
    asm = Assembly("two_block_belt")
    asm.add("wall_a", ConstantSpeed(v=0.0))
    asm.add("wall_b", ConstantSpeed(v=0.0))
    asm.add("belt_1", ConstantSpeed(v=BELT_SPEED))
    asm.add("belt_2", ConstantSpeed(v=BELT_SPEED))
    asm.add("block1", MassWithFriction(m=1.0, g=1.0, mu_k=0.3, mu_s=0.4))
    asm.add("block2", MassWithFriction(m=1.0, g=1.0, mu_k=0.3, mu_s=0.4))
    asm.add("spring1", SpringDamper(c=1.0, d=0.05))
    asm.add("coupling", Spring(c=1.0))
    asm.add("spring2", SpringDamper(c=2.0, d=0.05))
    asm.connect("wall_a.flange", "spring1.flange_a")
    asm.connect("spring1.flange_b", "block1.flange_a")
    asm.connect("block1.flange_b", "coupling.flange_a")
    asm.connect("coupling.flange_b", "block2.flange_a")
    asm.connect("block2.flange_b", "spring2.flange_a")
    asm.connect("spring2.flange_b", "wall_b.flange")
    asm.connect("belt_1.flange", "block1.support")
    asm.connect("belt_2.flange", "block2.support")
    return asm


def belt_first_slip(asm: Assembly) -> tuple[float, str]:
    """(time, block) of the first slip, both blocks carried by the belt from s = 0.

    While both are stuck, s1 = s2 = v t: the coupling is unstretched and block i feels
    -(c_i v t + d_i v) from its wall spring-damper, so it slips when that reaches
    mu_s m g.
    """
    v = asm.component("belt_1").values["v"]
    times = {}
    for block, spring in (("block1", "spring1"), ("block2", "spring2")):
        b, s = asm.component(block).values, asm.component(spring).values
        times[block] = (b["mu_s"] * b["m"] * b["g"] - s["d"] * v) / (s["c"] * v)
    first = min(times, key=times.get)
    return times[first], first


def belt_sliding_equilibrium(asm: Assembly) -> np.ndarray:
    """(s1, s2) where both blocks stand still while the belt slides under them.

    Kinetic friction mu_k m g pushes each block along the belt; the springs hold it:
    K s = mu_k m g with K the stiffness matrix of wall-spring, coupling, wall-spring.
    """
    c1, c2 = asm.component("spring1").values["c"], asm.component("spring2").values["c"]
    cc = asm.component("coupling").values["c"]
    K = np.array([[c1 + cc, -cc], [-cc, c2 + cc]])
    load = [asm.component(b).values["mu_k"] * asm.component(b).values["m"]
            * asm.component(b).values["g"] for b in ("block1", "block2")]
    return np.linalg.solve(K, load)


def _two_block_belt_figures(result: Result, asm: Assembly) -> list[Figure]:
    t_slip, first = belt_first_slip(asm)
    slips = [row[0] for row in _events(result, first) if row[1] != 0]
    s_eq = belt_sliding_equilibrium(asm)
    return [Figure("t_slip", f"first slip time of {first} [s] vs (mu_s m g - d v)/(c v)",
                   slips[0] if slips else math.nan, t_slip),
            Figure("s1_end", "block1 position at the stop time [m] vs K^-1 mu_k m g",
                   float(result["block1.s"][-1]), float(s_eq[0])),
            Figure("s2_end", "block2 position at the stop time [m] vs K^-1 mu_k m g",
                   float(result["block2.s"][-1]), float(s_eq[1]))]


def _events(result: Result, instance: str):
    """(time, mode) after each event of `instance`, in order."""
    if instance not in result.events:
        return []
    ev = result.events[instance]
    return list(zip(ev["time"], ev[f"{instance}.mode"]))


# --- axle_motor ---------------------------------------------------------------------
def _axle_motor() -> Assembly:
    asm = Assembly("axle_motor")
    body = seed_disk(bearing_friction="coulomb", tau_c=0.2, c=0.05)
    theta_eq = body.equilibrium_angle()
    body.set("theta", theta_eq)
    # half the largest gravity torque: the motor lifts the disk part way and stalls there
    asm.add("motor", Motor(J=0.1, tau_stall=0.5 * _peak_gravity_torque(body), w_free=20.0,
                           phi=theta_eq))
    asm.add("shaft", TorsionalSpring(c=5.0, d=0.2))
    asm.add("body", body)
    asm.connect("motor.flange", "shaft.flange_a")
    asm.connect("shaft.flange_b", "body.axle")
    return asm


def _peak_gravity_torque(body) -> float:
    """max over theta of |dV/dtheta| = sqrt(A^2 + B^2) for V = A cos + B sin + C."""
    _, dV0, d2V0, _ = body._functions()(0.0)
    return math.hypot(d2V0, dV0)


def _axle_motor_figures(result: Result, asm: Assembly) -> list[Figure]:
    motor, body, shaft = (asm.component(n) for n in ("motor", "body", "shaft"))
    tau_stall, c = motor.values["tau_stall"], shaft.values["c"]
    theta_end = float(result["body.theta"][-1])
    _, dV, _, _ = body._functions()(theta_end)
    # at rest the rotor's torque balance leaves the spring carrying exactly the stall
    # torque; the bearing must hold what the spring and gravity do not balance
    holding = abs(tau_stall - dV)
    t = result["time"]
    E_body = result["body.E"]
    # dissipated in the bearing and the shaft's damper, by the trapezoid rule on the samples
    losses = (-np.trapezoid(result["body.tau_bearing"] * result["body.omega"], t)
              + np.trapezoid(result["shaft.P_loss"], t))
    stored = (E_body[-1] - E_body[0]) + result["motor.E"][-1] + result["shaft.E"][-1]
    return [Figure("phi_rel", "shaft twist at the stop time [rad] vs -tau_stall/c",
                   float(result["shaft.phi_rel"][-1]), -tau_stall / c),
            Figure("hold_excess", "bearing torque needed to hold the disk beyond tau_c [N.m]",
                   max(0.0, holding - body.values["tau_c"]), 0.0),
            Figure("W_motor", "motor work [J] vs stored energy + bearing and shaft losses",
                   float(result["motor.W"][-1]), float(stored + losses))]


JOINED_SCENES: dict[str, Scene] = {
    "two_block_belt": Scene(
        "two_block_belt", "two blocks on a moving belt, springs to the walls and between them, "
        "Coulomb friction: stick, slip, re-stick, then steady sliding",
        _two_block_belt, stop_time=300.0, step=0.1, tolerance=1e-10,
        record=["block1.s", "block1.v", "block1.mode", "block1.f_friction",
                "block2.s", "block2.v", "block2.mode", "block2.f_friction", "coupling.f"],
        figures=_two_block_belt_figures, plot=["block1.s", "block2.s", "block1.v", "block2.v"]),
    "axle_motor": Scene(
        "axle_motor", "seed 8.5's disk with Coulomb bearing friction, lifted by a DC motor "
        "through a torsional spring until it stalls",
        _axle_motor, stop_time=20.0, step=0.01, tolerance=1e-10,
        record=["body.theta", "body.omega", "body.mode", "body.E", "body.tau_bearing",
                "motor.phi", "motor.w", "motor.W", "motor.E", "shaft.phi_rel", "shaft.E",
                "shaft.P_loss"],
        figures=_axle_motor_figures, plot=["body.theta", "motor.phi", "shaft.phi_rel"]),
}
