"""A foreign FMU in a scene: an external PI controller holds a sliding block at a set speed.

The controller is the FMU CasADi's own ``DaeBuilder.export_fmu`` makes (FMI 3.0 Model
Exchange, CasADi's wrapper, not our runtime; built once per machine by
:mod:`.pi_controller`). A ``SpeedSensor`` reads the block's speed into it, its output
``f`` drives a ``Force`` on the block, and the block slides against kinetic Coulomb
friction on a fixed floor. The controller is Model Exchange only, so the scene runs in
mode ``me`` (its default); ``cosim`` and ``monolithic`` are refused with one line.

The references are the loop solved by hand (:func:`.pi_controller.pi_on_sliding_mass`):
while the block slides forward the speed error e = v_ref - v obeys
m e'' + k e' + (k/Ti) e = 0, and it settles where the speed is the set point and the
controller's force is the kinetic friction mu_k m g.
"""
from __future__ import annotations

import math

import numpy as np

from components.sources.force import Force
from components.sensors.translational import SpeedSensor
from components.translational.elements import MassWithFriction

from ..assembly import Assembly
from ..foreign import FMU
from ..result import Result
from .pi_controller import (casadi_pi_fmu, pi_error_envelope, pi_first_turning_point,
                            pi_on_sliding_mass)
from .scene import Figure, Scene, solver_accuracy

# the controller's own defaults (v_ref 1 m/s, k 2 N.s/m, Ti 0.5 s), stated here so that
# the scene reads as it runs; the block: friction mu_k m g = 0.981 N, and the first
# force k v_ref = 2 N beats the static mu_s m g = 1.47 N, so it breaks away at t = 0
CONTROLLER = dict(v_ref=1.0, k=2.0, Ti=0.5)
BLOCK = dict(m=1.0, g=9.81, mu_k=0.1, mu_s=0.15)


def pi_speed_loop(name: str, controller: FMU, block: MassWithFriction) -> Assembly:
    """`block` held at speed by the PI `controller` FMU (input v, output f): a
    SpeedSensor reads the block, a Force pushes it. Instances: ctrl, force, block, speed."""
    asm = Assembly(name)
    asm.add("ctrl", controller)
    asm.add("force", Force())
    asm.add("block", block)
    asm.add("speed", SpeedSensor())
    asm.connect("force.flange", "block.flange_a")
    asm.connect("speed.flange", "block.flange_b")
    asm.connect("speed.v", "ctrl.v")
    asm.connect("ctrl.f", "force.f")
    return asm


def _speed_control() -> Assembly:
    return pi_speed_loop("speed_control", FMU(casadi_pi_fmu(), **CONTROLLER),
                         MassWithFriction(**BLOCK))


def loop_parameters(asm: Assembly) -> dict:
    """The closed loop's numbers as the assembly holds them (after any --param): the
    arguments of :func:`.pi_controller.pi_on_sliding_mass`."""
    ctrl, block = asm.component("ctrl").values, asm.component("block").values
    return dict(m=block["m"], friction=block["mu_k"] * block["m"] * block["g"],
                v_ref=ctrl["v_ref"], k=ctrl["k"], Ti=ctrl["Ti"])


def _speed_control_figures(result: Result, asm: Assembly) -> list[Figure]:
    loop = loop_parameters(asm)
    t, v, f = result["time"], result["block.v_abs"], result["ctrl.f"]
    sliding = result["block.mode"]
    v_hand, f_hand = pi_on_sliding_mass(t, **loop)
    omega0 = math.sqrt(loop["k"] / (loop["m"] * loop["Ti"]))  # |s| of the error's poles
    envelope = pi_error_envelope(0.0, **loop)
    # the overshoot's peak, from the cubic Hermite interpolant of (v, v'), v' from the
    # block's own forces: (f + f_friction) / m. Its error on an oscillation of amplitude
    # A and rate omega0 is at most h^4 omega0^4 A / 384 (h the output interval)
    dv = (f + result["block.f_friction"]) / loop["m"]
    # here: a figure's reference; scipy loads in 0.1-0.5 s
    from scipy.interpolate import CubicHermiteSpline
    spline = CubicHermiteSpline(t, v, dv)
    turns = spline.derivative().roots(extrapolate=False)
    turns = turns[turns > t[0]]
    peak = float(spline(turns[0])) if len(turns) else math.nan
    t_peak, v_peak = pi_first_turning_point(**loop)
    hermite = result.settings["step"] ** 4 * omega0**4 * envelope / 384
    # at the end the transient has left at most envelope exp(-sigma T) in e, and omega0
    # times that in e' (so m omega0 times that in f = friction - m e')
    left = pi_error_envelope(float(t[-1]), **loop)
    scale_f = loop["k"] * envelope + loop["friction"]  # |f| <= k |e| + k |I| / Ti
    return [
        Figure("v_loop", "largest |v - v_hand| [m/s] over the run (v_hand: m e'' + k e' + "
               "(k/Ti) e = 0 solved by hand)", float(np.abs(v - v_hand).max()), 0.0,
               solver_accuracy(result, loop["v_ref"]),
               source="closed form (the loop's linear ODE solved by hand)"),
        Figure("f_loop", "largest |f - f_hand| [N], the controller FMU's force over the run",
               float(np.abs(f - f_hand).max()), 0.0, solver_accuracy(result, scale_f),
               source="closed form (the loop's linear ODE solved by hand)"),
        Figure("v_peak", f"overshoot: peak speed [m/s] (closed form: at t = {t_peak:.4f} s)",
               peak, v_peak, solver_accuracy(result, loop["v_ref"]) + hermite,
               source="closed form (the loop's first turning point)"),
        Figure("v_end", "speed at the end [m/s] vs the set point v_ref", float(v[-1]),
               loop["v_ref"], solver_accuracy(result, loop["v_ref"]) + left,
               source="set point (integral action: no steady error)"),
        Figure("f_end", "controller force at the end [N] vs kinetic friction mu_k m g",
               float(f[-1]), loop["friction"],
               solver_accuracy(result, scale_f) + loop["m"] * omega0 * left,
               source="statics (kinetic friction mu_k m g)"),
        # the closed form holds while the block slides forward: it must never stick
        Figure("not_sliding", "output points where the block is not sliding forward "
               "(the closed form's premise)", float(np.count_nonzero(sliding != 1)), 0.0, 0.0,
               source="premise of the closed form"),
    ]


SPEED_CONTROL_SCENES: dict[str, Scene] = {
    "speed_control": Scene(
        "speed_control", "a foreign PI controller FMU (CasADi export, FMI 3 ME) holds a block "
        "sliding on a rough floor at 1 m/s",
        _speed_control, stop_time=25.0, step=0.01, tolerance=1e-10,
        record=["block.v_abs", "block.f_friction", "block.mode", "ctrl.f", "ctrl.I"],
        figures=_speed_control_figures, plot=["block.v_abs", "ctrl.f"], mode="me",
        seed="—", reference="a foreign PI controller FMU (CasADi, FMI 3 ME; mode `me`) holding "
        "a sliding block at 1 m/s: the loop m e'' + k e' + (k/Ti) e = 0 solved by hand, its "
        "overshoot peak; steady state v = v_ref, controller force = μk m g"),
}

__all__ = ["SPEED_CONTROL_SCENES", "loop_parameters"]
