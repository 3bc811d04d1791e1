"""Scenes that join elements into real engineering situations (issue 6).

- ``two_block_belt``: two blocks on one moving belt, each tied to a wall by a spring-
  damper and to each other by a spring, each with exact Coulomb friction (seed 9.2's
  stick-slip with several frictional contacts). The belt is two constant-speed
  sources, one per block's ``support`` (a connection joins exactly two ports).
- ``axle_motor``: seed 8.5's disk on its inclined axle, with Coulomb bearing
  friction, lifted by a DC motor through a torsional spring until it comes to rest.
- ``beam_friction_damper``: the classic dry-friction vibration damper. A cantilever
  (AssumedModesBeam, poly2, released from a static tip deflection) whose tip (motion
  out, profile free_tip) drives a Jenkins element — a contact spring in series with a
  Coulomb slider: SpringBlock's flange_a (motion in, force out) with a light pad and
  g = N/m for the normal preload. The pad slips, re-sticks and reverses while the beam's
  energy goes into friction, until the spring force stays below mu_s N: the pad sticks
  for good and the beam vibrates freely on the contact spring as on a tip spring.

Causality (picked by the assembly from the graph): masses, rotors, the beam tip and
kinematic sources compute motion; springs and the friction element take motion in
and give forces out.
"""
from __future__ import annotations

import math

import numpy as np

from components.bodies.beam import AssumedModesBeam
from components.rotational.elements import Motor, TorsionalSpring
from components.sources.translational import ConstantSpeed
from components.translational.spring_block import SpringBlock
from components.translational.elements import MassWithFriction, Spring, SpringDamper

from ..assembly import Assembly
from ..result import Result
from .axle import seed_disk
from .damper_references import REFERENCE_TOL, Beam, Pad, damper_solution
from .scene import Figure, Scene, solver_accuracy

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
    # t_slip: an event located by the solver, in every mode (the 1e-6). The end
    # positions: the masses (1 kg) and their equal dampers (0.05 N.s/m) damp every mode
    # at d / 2m, so by 300 s the transient of steady sliding is exp(-7.5) = 5.5e-4 of its
    # start, below 0.25 m: 1.4e-4, inside the 1e-3
    return [Figure("t_slip", f"first slip time of {first} [s] vs (mu_s m g - d v)/(c v)",
                   slips[0] if slips else math.nan, t_slip, 1e-6,
                   source="closed form (mu_s m g - d v)/(c v) (ours: the seed's 9.2 block, extended to two)"),
            Figure("s1_end", "block1 position at the stop time [m] vs K^-1 mu_k m g",
                   float(result["block1.s"][-1]), float(s_eq[0]), 1e-3,
                   source="closed form K^-1 mu_k m g (ours: the two-block statics, not the seed's)"),
            Figure("s2_end", "block2 position at the stop time [m] vs K^-1 mu_k m g",
                   float(result["block2.s"][-1]), float(s_eq[1]), 1e-3,
                   source="closed form K^-1 mu_k m g (ours: the two-block statics, not the seed's)")]


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
    twist = _twist_accuracy(result, asm)
    theta_end = float(result["body.theta"][-1])
    _, dV, _, _ = body._functions()(theta_end)
    # at rest the rotor's torque balance leaves the spring carrying exactly the stall
    # torque; the bearing must hold what the spring and gravity do not balance
    holding = abs(tau_stall - dV)
    t = result["time"]
    E_body = result["body.E"]
    # dissipated in the bearing and the shaft's damper, by the trapezoid rule on the samples
    # (body.bearing_friction = none: no bearing torque, no column)
    bearing = result["body.tau_bearing"] if "body.tau_bearing" in result else 0.0
    power_lost = -bearing * result["body.omega"] + result["shaft.P_loss"]
    losses = np.trapezoid(power_lost, t)
    stored = (E_body[-1] - E_body[0]) + result["motor.E"][-1] + result["shaft.E"][-1]
    W = float(result["motor.W"][-1])
    # the losses' trapezoid rule errs by about (I_h - I_2h) / 3 (Richardson); allow 3 x that
    quadrature = _trapezoid_accuracy(t, power_lost)
    return [Figure("phi_rel", "shaft twist at the stop time [rad] vs -tau_stall/c",
                   float(result["shaft.phi_rel"][-1]), -tau_stall / c, twist,
                   source="statics (stall torque / shaft stiffness, derived here)"),
            # the torque balance holds to what the spring's twist does: c x its accuracy
            Figure("hold_excess", "bearing torque needed to hold the disk beyond tau_c [N.m]",
                   max(0.0, holding - body.values["tau_c"]), 0.0, c * twist,
                   source="statics (torque balance, derived here)"),
            Figure("W_motor", "motor work [J] vs stored energy + bearing and shaft losses",
                   W, float(stored + losses), quadrature + solver_accuracy(result, W),
                   source="energy balance (work = stored + dissipated)")]


def _twist_accuracy(result: Result, asm: Assembly) -> float:
    """How close the shaft's twist can be to -tau_stall / c at the stop time.

    Once the disk sticks for good (its last event), the rotor rings on the shaft alone,
    damped by the shaft's damper and the motor's torque-speed slope: its envelope falls
    like exp(-(d + tau_stall / w_free) t / 2J) from at most the largest departure seen.
    NaN (the figure fails) if the disk still turns at the stop time.
    """
    motor, shaft = asm.component("motor").values, asm.component("shaft").values
    events, t = _events(result, "body"), result["time"]
    if "body.mode" not in result:  # no bearing friction: nothing holds the disk
        return math.nan
    if result["body.mode"][-1] != 0 or not events or events[-1][1] != 0:
        return math.nan
    slope = motor["tau_stall"] / motor["w_free"] if motor["w_free"] > 0 else 0.0
    decay = (shaft["d"] + slope) / (2 * motor["J"])
    target = -motor["tau_stall"] / shaft["c"]
    departure = float(np.abs(result["shaft.phi_rel"] - target).max())
    return (departure * math.exp(-decay * (float(t[-1]) - float(events[-1][0])))
            + solver_accuracy(result, target))


def _trapezoid_accuracy(t: np.ndarray, f: np.ndarray) -> float:
    """|I_h - I_2h| of the trapezoid rule on the samples (an even number of intervals):
    three times the Richardson estimate of the error of I_h."""
    n = len(t) - 1 - (len(t) - 1) % 2
    return float(abs(np.trapezoid(f[:n + 1], t[:n + 1]) - np.trapezoid(f[:n + 1:2], t[:n + 1:2])))


# --- beam_friction_damper -----------------------------------------------------------
# The beam: EI = 1 N.m2, L = 1 m, m = 1 kg (tip stiffness 3 N/m, first mode 3.52 rad/s),
# released from w_tip = 0.1 m. The damper: a 50 g pad pressed with N = 0.05 N on a fixed
# surface (g = N/m = 1 m/s2; mu_k = 0.3, mu_s = 0.4, so the pad slips above 0.02 N),
# tied to the tip by a contact spring of 1 N/m. Why these values: co-simulation holds the
# spring force over each communication step, and that held force acts on the beam like
# an explicitly integrated tip spring, so the coupling frequency is set by the contact
# stiffness: a soft spring (1 N/m, a third of the beam's own tip stiffness) keeps the
# stuck system's frequencies at 4.07 and 34.9 rad/s. A LIGHT pad helps too (measured, not
# the other way round): while it slides its spring force stays close to the constant
# kinetic friction mu_k N, so the held force is nearly right; a heavier pad rings on
# its spring (sqrt(k/m)) and the held force misses that. Measured zero-order-hold Jacobi
# error (w_tip, 20 s) at h = 0.1, 0.05, 0.025, 0.0125 s: pad 0.05 kg: 4.7e-2 2.0e-2
# 7.4e-3 3.5e-3 (stable at every step); pad 0.2 kg, k = 2: 1.7 at 0.1 s, 2.0e-2 at
# 0.0125 s; the prototype (0.2 kg, k = 10) was unstable at h >= 0.025 s.
# The pad starts at x = 0, the beam's rest position: the tip, pulled to 0.1 m and let
# go, slips the pad at once and the pad ends stuck at 8.7 s.
# The beam integrates its assumed coordinates, not the modal default (the same physics):
# the adaptive co-simulation judges a step by the change of the FMUs' states, and modal
# amplitudes carry the tip velocity divided by ω, so the controller sees less of the
# coupling error and takes 4x fewer steps; E_lost then misses its 1e-8 (7.3e-8 measured,
# against 2.9e-9 in the assumed coordinates). One solver (me, monolithic) passes in both.
DAMPER_W0 = 0.1


def _beam_friction_damper() -> Assembly:
    asm = Assembly("beam_friction_damper")
    asm.add("beam", AssumedModesBeam(basis="poly2", coordinates="assumed", EI=1.0, L=1.0, m=1.0,
                                     w_tip0=DAMPER_W0))
    pad_mass, preload = 0.05, 0.05
    asm.add("pad", SpringBlock(m=pad_mass, k=1.0, g=preload / pad_mass, mu_k=0.3, mu_s=0.4))
    asm.connect("beam.tip", "pad.flange_a")
    return asm


def damper_sliding_distance(result: Result, instance: str = "pad") -> float:
    """Total distance the pad slid, exactly, from its events and its final state.

    Within a slip phase the pad moves one way only (it slides in the direction of its
    mode until its speed reaches zero), so the distance is the sum of |x| differences
    between the events that start and end each slip phase, plus the last partial slide
    if the run ends while it slips.
    """
    mode, x_start = float(result[f"{instance}.mode"][0]), float(result[f"{instance}.x"][0])
    distance = 0.0
    for _, x, new_mode in _events_x(result, instance):
        if new_mode == mode:
            continue
        if mode != 0:
            distance += abs(x - x_start)
        mode, x_start = new_mode, x
    if mode != 0:
        distance += abs(float(result[f"{instance}.x"][-1]) - x_start)
    return distance


def _events_x(result: Result, instance: str):
    """(time, x, mode) after each event of `instance`, in order."""
    if instance not in result.events:
        return []
    ev = result.events[instance]
    return list(zip(ev["time"], ev[f"{instance}.x"], ev[f"{instance}.mode"]))


def _pad_energy(result: Result, pad: dict, i: int) -> float:
    """kinetic energy of the pad + energy in its contact spring (no dashpot: d = 0)."""
    return (pad["m"] * float(result["pad.v"][i]) ** 2 / 2
            + float(result["pad.f_spring"][i]) ** 2 / (2 * pad["k"]))


def _beam_friction_damper_figures(result: Result, asm: Assembly) -> list[Figure]:
    pad = asm.component("pad").values
    E = result["beam.E"]
    work = pad["mu_k"] * pad["m"] * pad["g"] * damper_sliding_distance(result)
    held = _pad_energy(result, pad, -1) - _pad_energy(result, pad, 0)
    # every term exact (the distance from the located events): the solver's error is left
    # a pad dashpot (d > 0) dissipates what no event records: no reference then (NaN fails)
    reference = work + held if pad["d"] == 0.0 else math.nan
    figures = [Figure("E_lost", "beam energy lost [J] vs mu_k N x sliding distance (from the "
                      "pad's events) + change of pad and contact-spring energy (pad d = 0)",
                      float(E[0] - E[-1]), reference, solver_accuracy(result, work + held),
                      source="energy balance (friction work from the located events)")]
    # the final stuck state: after the last event the pad holds still and the contact
    # spring is a tip spring to ground at the pad's position
    events = _events_x(result, "pad")
    t = result["time"]
    t_last = float(events[-1][0]) if events else 0.0
    stuck = result["pad.mode"][-1] == 0 and t[-1] - t_last > 0
    beam, pad_ref, start = _damper_models(asm)
    omega = _stuck_frequency(result, t_last) if stuck else math.nan
    # a least-squares fit of the stuck system's exact two-mode motion: the 1e-6
    figures.append(Figure("omega_stuck", "tip frequency once the pad sticks for good [rad/s] "
                          "vs beam with k_tip = pad k, first mode", omega,
                          float(beam.frequencies(pad["k"])[0]), 1e-6,
                          source="eigenvalue of the seed's M and K, written here in closed form "
                          "from the shapes (damper_references)"))
    return figures + _damper_event_figures(result, beam, pad_ref, start)


def _damper_models(asm: Assembly):
    """The damper as the reference writes it: (Beam, Pad, start) from the assembly's
    values, the start being (a, a', x, v, mode) at t = 0."""
    b, p = asm.component("beam"), asm.component("pad")
    bv, pv = b.values, p.values
    beam = Beam.of(b.option("basis"), b.option("n_modes"), bv["EI"], bv["L"], bv["m"],
                   k_tip=bv["k_tip"], alpha=bv["alpha"], beta=bv["beta"], zeta=bv["zeta"])
    pad = Pad(m=pv["m"], k=pv["k"], d=pv["d"], N=pv["m"] * pv["g"], mu_s=pv["mu_s"],
              mu_k=pv["mu_k"])
    b.validate()  # the release from w_tip0 sets the start coordinates
    # the initial condition the run starts from, in the seed's coordinates (a modal
    # beam's amplitudes converted): the state both solutions begin with
    a, a_dot = b.assumed_motion(lambda name: [b.starts.get(name, 0.0)], [0.0])
    return beam, pad, (a[:, 0], a_dot[:, 0], p.starts["x"], p.starts["v"], 0)


def _mode_changes(result: Result, instance: str) -> list[tuple[float, int]]:
    """(t, mode after) at each event after t = 0 that changed `instance`'s mode."""
    previous, changes = int(result[f"{instance}.mode"][0]), []
    for t, _, mode in _events_x(result, instance):
        if int(mode) != previous and t > result["time"][0]:
            changes.append((float(t), int(mode)))
        previous = int(mode)
    return changes


def _coupled_tolerance(result: Result) -> float:
    """The relative error a run controls. Co-simulated, the contact force crosses
    between the FMUs once per communication step: adaptive steps bound that coupling
    error by their own tolerance; fixed steps hold or extrapolate it with an error of
    order h (not bounded here: NaN, so a figure on it fails rather than pass unstated)."""
    s = result.settings
    if s.get("scheme") in ("jacobi", "gauss-seidel"):
        return max(s["tolerance"], s["tol"]) if s.get("adaptive") else math.nan
    return s["tolerance"]


def _damper_event_figures(result: Result, beam: Beam, pad: Pad, start) -> list[Figure]:
    """The pad's mode changes against the independent event-driven integration.

    An event is where an indicator I (the pad's speed at a stop, the static margin
    mu_s N - |f_s| at a break-away) crosses zero; a solution whose state errs by e
    there locates it off by e |dI/dstate| / |dI/dt|. Each solution's state error at an
    event is 100 x its tolerance (solver_accuracy's rule), so the two event times may
    differ by (100 tol_run + 100 tol_ref) |dI/dstate| / |dI/dt|, the rate taken from the
    reference just before the event.
    """
    t_end = float(result["time"][-1])
    changes, _ = damper_solution(beam, pad, *start, t_end)
    # the reference's break-away at t = 0 is the run's initialisation: not an event there
    changes = [c for c in changes if c.t > 0.0]
    run = _mode_changes(result, "pad")
    tol = 100 * (_coupled_tolerance(result) + REFERENCE_TOL)
    bounds = [tol * c.scale / c.rate for c in changes]
    same = len(run) == len(changes) and all(m == c.mode for (_, m), c in zip(run, changes))
    worst = (max((abs(t - c.t) / bound for (t, _), c, bound in zip(run, changes, bounds)),
                 default=0.0) if same else math.nan)
    stuck = same and bool(changes) and changes[-1].mode == 0
    t_run, t_ref = (run[-1][0], changes[-1].t) if stuck else (math.nan, math.nan)
    source = ("independent event-driven integration (scipy DOP853, tol 1e-12, written from "
              "the beam's and the pad's equations: damper_references)")
    return [
        Figure("mode_changes", "pad mode changes after t = 0 (slip, stick, reversal) vs the "
               "reference's, same modes in the same order (a different sequence: nan in "
               "t_events)", float(len(run)), float(len(changes)), 0.0, source=source),
        Figure("t_events", "largest |t_run - t_ref| over the mode changes, each divided by its "
               "bound (100 x both tolerances x |dI/dstate| / |dI/dt| of its indicator I) [1]",
               worst, 0.0, 1.0, source=source),
        Figure("t_stick", "time the pad sticks for good [s] (nan if either solution ends "
               "sliding or their mode sequences differ)", t_run, t_ref,
               bounds[-1] if stuck else math.nan, source=source)]


def _stuck_frequency(result: Result, t_last: float) -> float:
    """First angular frequency of the tip's free vibration after `t_last` [rad/s].

    The stuck system is linear with the poly2 beam's two modes, so w_tip is
    c + Σ (A_i cos ω_i t + B_i sin ω_i t) exactly; a least-squares fit of that, started
    from the two largest peaks of the samples' spectrum, gives ω_1. (Counting zero
    crossings does not: the second mode, 1/6 of the first at the tip here, adds
    crossings of its own.)
    """
    from scipy.optimize import least_squares

    t = result["time"]
    keep = t > t_last
    t, w = t[keep] - t[keep][0], result["beam.w_tip"][keep]
    if len(t) < 64:
        return math.nan
    pad = 16 * len(w)
    spectrum = np.abs(np.fft.rfft((w - w.mean()) * np.hanning(len(w)), pad))
    freq = 2 * math.pi * np.fft.rfftfreq(pad, t[1] - t[0])
    w1 = freq[np.argmax(spectrum)]
    w2 = freq[np.argmax(spectrum * (freq > 3 * w1))]

    def residual(q):
        c, a1, b1, o1, a2, b2, o2 = q
        return (c + a1 * np.cos(o1 * t) + b1 * np.sin(o1 * t) + a2 * np.cos(o2 * t)
                + b2 * np.sin(o2 * t) - w)

    fit = least_squares(residual, [w.mean(), w[0] - w.mean(), 0.0, w1, 0.0, 0.0, w2],
                        xtol=1e-15, ftol=1e-15, gtol=1e-15)
    return float(fit.x[3])

JOINED_SCENES: dict[str, Scene] = {
    "two_block_belt": Scene(
        "two_block_belt", "two blocks on a moving belt, springs to the walls and between them, "
        "Coulomb friction: stick, slip, re-stick, then steady sliding",
        _two_block_belt, stop_time=300.0, step=0.1, tolerance=1e-10,
        record=["block1.s", "block1.v", "block1.mode", "block1.f_friction",
                "block2.s", "block2.v", "block2.mode", "block2.f_friction", "coupling.f"],
        figures=_two_block_belt_figures, plot=["block1.s", "block2.s", "block1.v", "block2.v"],
        seed="9.2", reference="first slip time, final stretch"),
    "axle_motor": Scene(
        "axle_motor", "seed 8.5's disk with Coulomb bearing friction, lifted by a DC motor "
        "through a torsional spring until it stalls",
        _axle_motor, stop_time=20.0, step=0.01, tolerance=1e-10,
        # every output: body.mode and body.tau_bearing exist only with bearing friction,
        # and --param body.bearing_friction=none must still run
        record=None,
        figures=_axle_motor_figures, plot=["body.theta", "motor.phi", "shaft.phi_rel"], seed="8.5",
        reference="motor work = stored energy + losses"),
    "beam_friction_damper": Scene(
        "beam_friction_damper", "cantilever released from a tip deflection, its tip rubbing "
        "on a spring-loaded friction pad (Jenkins element) until the pad sticks for good",
        _beam_friction_damper, stop_time=30.0, step=0.0125, tolerance=1e-10,
        record=["beam.w_tip", "beam.E", "pad.x", "pad.v", "pad.mode", "pad.f_spring",
                "pad.f_friction"],
        figures=_beam_friction_damper_figures, plot=["beam.w_tip", "pad.x", "pad.f_spring"],
        seed="7.5, 9.2", reference="beam energy lost = friction work; every slip and stick "
        "time against an independent event-driven integration; once the pad sticks for good, "
        "the beam-with-tip-spring frequency"),
}
