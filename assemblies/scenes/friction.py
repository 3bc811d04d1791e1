"""Seed 9.2 and 9.4: one spring-block with Coulomb friction, dragged or let go."""
from __future__ import annotations

import math

from components import ConstantSpeed, SpringBlock

from ..assembly import Assembly
from ..result import Result
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
    p, speed = asm.component("block").values, asm.component("driver").values["v"]
    t1, t2, x2 = stick_slip_first_cycle(p["m"], p["k"], p["g"], p["mu_k"], p["mu_s"], speed)
    events = _mode_events(result, "block")
    slip = next(((t, x) for t, x, mode in events if mode == 1), (math.nan, math.nan))
    stick = next(((t, x) for t, x, mode in events if mode == 0 and t > slip[0]), (math.nan, math.nan))
    # closed forms against located events: only the solver's error is left
    return [Figure("t1", "first slip time [s]", slip[0], t1, solver_accuracy(result, t1)),
            Figure("t2", "first re-stick time [s]", stick[0], t2, solver_accuracy(result, t2)),
            Figure("x(t2)", "position at re-stick [m]", stick[1], x2, solver_accuracy(result, x2))]


# --- friction_damping: seed 9.4 ----------------------------------------------
def _friction_damping() -> Assembly:
    asm = Assembly("friction_damping")
    asm.add("wall", ConstantSpeed(v=0.0))
    asm.add("block", SpringBlock(m=1, k=1, g=1, mu_k=0.6, mu_s=0.6, x=6.55))
    asm.connect("wall.flange", "block.flange_a")
    return asm


def _friction_damping_figures(result: Result, asm: Assembly) -> list[Figure]:
    p = asm.component("block").values
    x0 = asm.component("block").starts["x"]
    reference = friction_damping_turning_points(p["m"], p["k"], p["g"], p["mu_k"], x0)
    # a turning point is an event where the block stops (mode to 0) or reverses (mode
    # flips sign); leaving rest (0 to +-1) is not one: a smooth law, whose mode is 0
    # within |v| <= eps, passes 0 at each turn and leaves it just after
    measured = [(0.0, result["block.x"][0])]
    previous = result["block.mode"][0]
    for t, x, mode in _mode_events(result, "block"):
        if mode != previous and (mode == 0 or mode * previous < 0):
            measured.append((t, x))
        previous = mode
    # exact piecewise solution against located events: only the solver's error is left
    figures = []
    for n, (t_ref, x_ref) in enumerate(reference):
        t, x = measured[n] if n < len(measured) else (math.nan, math.nan)
        figures.append(Figure(f"A{n}", f"turning point {n} [m]", x, x_ref,
                              solver_accuracy(result, x_ref)))
        if n:
            figures.append(Figure(f"t_A{n}", f"time of turning point {n} [s]", t, t_ref,
                                  solver_accuracy(result, t_ref)))
    figures.append(Figure("x_end", "position at the stop time [m]", result["block.x"][-1],
                          reference[-1][1], solver_accuracy(result, reference[-1][1])))
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
