"""Seed 9.2 and 9.4: one spring-block with Coulomb friction, dragged or let go."""
from __future__ import annotations

import math

from components import ConstantSpeed, SpringBlock
from components.translational.spring_block import SLIDING_AT

from ..assembly import Assembly
from ..result import Result
from .friction_references import (creep_speed, smooth_law_peak, smooth_mode_slip_bracket,
                                  smooth_turning_allowance)
from .located import continue_to_rest, continue_to_speed
from .references import friction_damping_turning_points, stick_slip_first_cycle
from .scene import Figure, Scene, solver_accuracy


def _mode_events(result: Result, instance: str):
    """(time, x, mode) at each event the instance's FMU located."""
    if instance not in result.events:
        return []
    ev = result.events[instance]
    return list(zip(ev["time"], ev[f"{instance}.x"], ev[f"{instance}.mode"]))


# --- stick_slip: seed 9.2 ----------------------------------------------------
def _stick_slip() -> Assembly:
    asm = Assembly("stick_slip")
    asm.add("driver", ConstantSpeed(v=0.05))
    asm.add("block", SpringBlock(m=1, k=1, g=1, mu_k=0.3, mu_s=0.4))
    asm.connect("driver.flange", "block.flange_a")
    return asm


def _stick_slip_figures(result: Result, asm: Assembly) -> list[Figure]:
    block = asm.component("block")
    p, speed = block.values, asm.component("driver").values["v"]
    exact = stick_slip_first_cycle(p["m"], p["k"], p["g"], p["mu_k"], p["mu_s"], speed)
    events = _mode_events(result, "block")
    slip = next(((t, x) for t, x, mode in events if mode == 1), (math.nan, math.nan))
    stick = next(((t, x) for t, x, mode in events if mode == 0 and t > slip[0]), (math.nan, math.nan))
    law = block.option("friction")
    # exact Coulomb friction: closed forms against located events, only the solver's
    # error is left; a smooth law is held to the same closed forms within what it allows
    allowed = (0.0, 0.0, 0.0) if law == "coulomb" else _smooth_law_allowance(law, p, speed)
    what = "" if law == "coulomb" else f" ({law} law, eps = {p['eps']:g}: vs exact Coulomb)"
    first = Figure("t1", f"first slip time [s]{what}", slip[0], exact[0],
                   allowed[0] + solver_accuracy(result, exact[0]),
                   source="seed 9.2, Eq. 9.4 (t1 = mu_s m g/(k v))")
    if law == "tanh":
        # Eq. 9.7 has no stiction: its limit is Coulomb friction with mu_s = mu_k, whose
        # slide only touches rest (tangentially) and never sticks again. The law's block
        # dips into |x'| < 1.5 eps there (its mode turns 0, a located event), but at rest
        # its friction vanishes while the spring, stretched by about mu_k m g / k, pulls
        # on: x' never reaches 0. Each dip is followed from its event to where the mode
        # leaves 0 again, and counts if x' reaches 0 in it
        return [first, Figure("rests", "times the block comes to rest (x' = 0) after the "
                              "first slip (Eq. 9.7 has no stiction: none, unlike Coulomb's "
                              f"re-stick at t2 = {exact[1]:.4f} s)",
                              _rests(result, asm, slip[0]), 0, 0.0,
                              source="seed 9.2 (Eq. 9.7 has no stiction: no rest)")]
    return [first,
            Figure("t2", f"first re-stick time [s]{what}", stick[0], exact[1],
                   allowed[1] + solver_accuracy(result, exact[1]),
                   source="closed form (re-stick of the seed's Eq. 9.4 block, derived here)"),
            Figure("x(t2)", f"position at re-stick [m]{what}", stick[1], exact[2],
                   allowed[2] + solver_accuracy(result, exact[2]),
                   source="closed form (re-stick of the seed's Eq. 9.4 block, derived here)")]


def _rests(result: Result, asm: Assembly, after: float, end: str = "driver") -> float:
    """How many of the smooth law's dips into |x'| < 1.5 eps after `after` reach x' = 0,
    each followed by the block's own equation (its spring's end moved by `end`) from the
    event where the mode turned 0 to the next event (or the end of the run); NaN if the
    first slip never came."""
    if math.isnan(after):
        return math.nan
    events = _mode_events(result, "block")
    v = result.events["block"]["block.v"]
    t_stop = float(result["time"][-1])
    rests = 0
    for i, (t, x, mode) in enumerate(events):
        if t <= after or mode != 0:
            continue
        until = events[i + 1][0] if i + 1 < len(events) else t_stop
        if not math.isnan(continue_to_speed(asm, "block", end, t, x, v[i], 0.0,
                                            until - t)[0]):
            rests += 1
    return float(rests)


def _smooth_law_allowance(law: str, p: dict, speed: float) -> tuple[float, float, float]:
    """How far a smooth law's first cycle may lie from exact Coulomb friction's (t1, t2,
    x(t2)). t1: rigorously, the bracket of the mode's first flip (the law's own bounds,
    friction_references.smooth_mode_slip_bracket) taken about the exact t1. t2 and x(t2):
    as eps -> 0 the law is Coulomb friction with mu_s replaced by the law's supremum (the
    peak of Eq. 9.5, mu_k for Eq. 9.7): that shift is a closed form; to it come the
    slip's later start (the t1 bracket's width, carried over) and the time the block
    takes to cross the band where it counts as stuck as it stops. An estimate, not a
    bound."""
    m, k, g, mu_k, mu_s, eps = (p[n] for n in ("m", "k", "g", "mu_k", "mu_s", "eps"))
    exact = stick_slip_first_cycle(m, k, g, mu_k, mu_s, speed)
    lo, hi = smooth_mode_slip_bracket(law, m, k, g, mu_k, mu_s, speed, eps)
    mu_sup = smooth_law_peak(mu_k, mu_s)[1] if law == "smooth" else mu_k
    limit = stick_slip_first_cycle(m, k, g, mu_k, mu_sup, speed)
    w = math.sqrt(k / m)
    # the block crosses the band |x'| < 1.5 eps as it stops: over its deceleration, the
    # friction's excess over the pull, or, where it stops tangentially, sqrt(2 c / v) / w
    c = SLIDING_AT * eps / 2
    deceleration = (mu_sup - mu_k) * g
    band = (c / deceleration if deceleration > 0 else 0.0) + math.sqrt(2 * c / speed) / w
    t1 = max(abs(exact[0] - lo), abs(exact[0] - hi))
    t2 = abs(exact[1] - limit[1]) + (hi - lo) + band
    x2 = abs(exact[2] - limit[2]) + speed * ((hi - lo) + band)
    return t1, t2, x2


# --- friction_damping: seed 9.4 ----------------------------------------------
def _friction_damping() -> Assembly:
    asm = Assembly("friction_damping")
    asm.add("wall", ConstantSpeed(v=0.0))
    asm.add("block", SpringBlock(m=1, k=1, g=1, mu_k=0.6, mu_s=0.6, x=6.55))
    asm.connect("wall.flange", "block.flange_a")
    return asm


def _turning_points(result: Result, asm: Assembly) -> list[tuple[float, float]]:
    """(t, x) where the block's velocity is zero, from its located events, the release
    from rest at t = 0 first.

    Coulomb friction: a turning point is an event where the block stops (mode to 0) or
    reverses (mode flips sign), located by the FMU at x' = 0 itself; leaving rest (0 to
    +-1) is not one. A smooth law never stops exactly: its mode turns 0 where |x'| falls
    below 1.5 eps, a located event a little before the turn (|x'| / x'' ~ 2e-4 s
    for the scene's eps); from that event's state the block's own equation of motion is
    integrated the rest of the way to x' = 0 (located.continue_to_rest), so the turning
    point carries the solver's error at the event and nothing of the output grid."""
    block = asm.component("block")
    law = block.option("friction")
    points = [(0.0, result["block.x"][0])]
    previous = result["block.mode"][0]
    events = result.events.get("block")
    for i in range(len(events) if events is not None else 0):
        mode = events["block.mode"][i]
        if law == "coulomb":
            if mode != previous and (mode == 0 or mode * previous < 0):
                points.append((events["time"][i], events["block.x"][i]))
        elif mode == 0 and previous != 0:
            points.append(continue_to_rest(asm, "block", "wall", events["time"][i],
                                           events["block.x"][i], events["block.v"][i]))
        previous = mode
    return points


def _friction_damping_figures(result: Result, asm: Assembly) -> list[Figure]:
    block = asm.component("block")
    p, law = block.values, block.option("friction")
    x0 = block.starts["x"]
    reference = friction_damping_turning_points(p["m"], p["k"], p["g"], p["mu_k"], x0)
    measured = _turning_points(result, asm)
    # against located turning points only the solver's error is left, and, for a smooth
    # law, what its band |x'| < 20 eps does differently from Coulomb at each turn
    if law == "coulomb":
        allowed = [(0.0, 0.0)] * len(reference)
        creep = 0.0
    else:
        allowed = smooth_turning_allowance(law, p["m"], p["k"], p["g"], p["mu_k"],
                                           p["mu_s"], p["eps"], [x for _, x in reference])
        # after the last turn it creeps towards the wall, never faster than the law lets
        # the spring at that turn drive it (Coulomb's block sticks there for good)
        last_t, last_x = reference[-1]
        speed = creep_speed(law, p["m"], p["g"], p["mu_k"], p["mu_s"], p["eps"],
                            p["k"] * abs(last_x))
        creep = speed * max(0.0, result["time"][-1] - (last_t - allowed[-1][0]))
    what = "" if law == "coulomb" else f" ({law} law, eps = {p['eps']:g}: vs exact Coulomb)"
    figures = []
    for n, (t_ref, x_ref) in enumerate(reference):
        t, x = measured[n] if n < len(measured) else (math.nan, math.nan)
        figures.append(Figure(f"A{n}", f"turning point {n} [m]{what}", x, x_ref,
                              allowed[n][1] + solver_accuracy(result, x_ref),
                              source="seed 9.4 (turning points fall by 2 mu m g/k each half period)"))
        if n:
            figures.append(Figure(f"t_A{n}", f"time of turning point {n} [s]{what}", t, t_ref,
                                  allowed[n][0] + solver_accuracy(result, t_ref),
                                  source="seed 9.4 (a half period pi/w0 per swing)"))
    x_end = reference[-1][1]
    figures.append(Figure("x_end", f"position at the stop time [m]{what}",
                          result["block.x"][-1], x_end,
                          allowed[-1][1] + creep + solver_accuracy(result, x_end),
                          source="seed 9.4 (rest at the last turning point)"))
    return figures


FRICTION_SCENES: dict[str, Scene] = {
    "stick_slip": Scene(
        "stick_slip", "seed 9.2: block pulled through a spring at constant speed, stick-slip",
        _stick_slip, stop_time=40.0, step=0.1, tolerance=1e-10,
        record=["block.x", "block.v", "block.f_friction", "block.mode", "driver.flange.s"],
        figures=_stick_slip_figures, plot=["block.x", "block.v", "block.f_friction"],
        seed="9.2, Eq. 9.4",
        reference="t1 = 8, t2 = 12.0689, x(t2) = 0.40344 (closed form)"),
    "friction_damping": Scene(
        "friction_damping", "seed 9.4: free vibration with dry friction, amplitudes fall linearly",
        _friction_damping, stop_time=20.0, step=0.1, tolerance=1e-10,
        record=["block.x", "block.v", "block.f_friction", "block.mode"],
        figures=_friction_damping_figures, plot=["block.x", "block.v"], seed="9.4",
        reference="turning points 6.55, −5.35, 4.15, −2.95, 1.75, −0.55 at t = 0, π, …, 5π"),
}
