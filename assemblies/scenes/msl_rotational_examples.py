"""``Modelica.Mechanics.Rotational.Examples`` First and Backlash rebuilt from our components.

MSL's parameters, start values and stop times; every figure is held to a reference of
:mod:`.msl_rotational_examples_references` (closed forms, or scipy integrations written
from MSL's documented equations) or to the energy balance. Both run in every mode: no
element here feeds an acceleration back (no algebraic loop between FMUs).

- ``rotational_first``: a 10 N.m, 5 Hz sine torque drives the motor inertia (0.1 kg.m2)
  through a 10:1 gear into inertia2 (2 kg.m2), held to the housing by a 10 N.m.s/rad
  bearing damper, and a 1e4 N.m/rad spring on to the load (2 kg.m2), from rest. The
  motor inertia and inertia2 are one rigid body through the ideal gear, so they are one
  Inertia here, ``J2 + ratio^2 Jmotor = 12 kg.m2`` (components/rotational/rigid.py: two
  FMUs that compute motion cannot share one; the motor's motion is the gear's flange_a).
  Where MSL joins inertia2, the spring and the damper at one point, a RotationalJunction.
- ``rotational_backlash``: three 5 kg.m2 inertias released at 90 deg, each on its own
  element fixed at the other end (c = 20e3 N.m/rad, d = 50 N.m.s/rad): a SpringDamper,
  an ElastoBacklash and an ElastoBacklash2 (b = 45 deg). The backlash makes the motion
  a flight through the gap between contacts, and the damping never pulls.
"""
from __future__ import annotations

import math

import numpy as np

from components.rotational.backlash import ElastoBacklash, ElastoBacklash2
from components.rotational.elements import (RotationalDamper, RotationalSpring,
                                           RotationalSpringDamper)
from components.rotational.rigid import IdealGear, Inertia, RotationalFixed, RotationalJunction
from components.sources.rotational import Torque
from components.sources.signals import Sine

from ..assembly import Assembly
from ..result import Result
from . import msl_rotational_examples_references as ref
from .msl_translational import solver_accuracy
from .scene import DRIFT, Figure, Scene

SOURCE_FIRST = ("independent integration (scipy of MSL's First: gear, damper and spring "
                "equations)")
SOURCE_BACKLASH = ("independent integration (branch by branch, scipy, of MSL's documented "
                   "ElastoBacklash laws)")
SOURCE_ENERGY = "conservation law (work of the sources = kinetic + elastic + dissipated)"


# --- First ------------------------------------------------------------------------------
def _first() -> Assembly:
    p = ref.FIRST
    asm = Assembly("rotational_first")
    asm.add("sine", Sine(amplitude=p["amplitude"], f=p["f"]))
    asm.add("torque", Torque())
    asm.add("idealGear", IdealGear(ratio=p["ratio"]))
    # inertia1 (the motor) rides on inertia2 through the rigid gear: one body
    asm.add("inertia2", Inertia(J=p["J2"] + p["ratio"]**2 * p["Jmotor"], phi=0.0, w=0.0))
    asm.add("joint", RotationalJunction())
    asm.add("spring", RotationalSpring(c=p["c"]))
    asm.add("inertia3", Inertia(J=p["Jload"], phi=0.0, w=0.0))  # phi_rel(fixed = true) = 0
    asm.add("damper", RotationalDamper(d=p["damping"]))
    asm.add("fixed", RotationalFixed())
    for a, b in (("sine.y", "torque.tau"), ("torque.flange", "idealGear.flange_a"),
                 ("idealGear.flange_b", "inertia2.flange_a"),
                 ("inertia2.flange_b", "joint.flange_a"), ("joint.flange_b", "spring.flange_a"),
                 ("spring.flange_b", "inertia3.flange_a"), ("joint.flange_c", "damper.flange_a"),
                 ("damper.flange_b", "fixed.flange")):
        asm.connect(a, b)
    return asm


def _first_figures(result: Result, asm: Assembly) -> list[Figure]:
    t = np.asarray(result["time"])
    r = ref.first(t)
    figures = []
    for name, key in (("inertia2", "2"), ("inertia3", "3")):
        phi_ref, w_ref = r[f"phi{key}"], r[f"w{key}"]
        w_scale = float(np.max(np.abs(w_ref)))
        phi_scale = float(np.max(np.abs(phi_ref)))
        figures += [
            Figure(f"{name}_w_end", f"{name}.w at {t[-1]:g} s [rad/s]",
                   float(result[f"{name}.w"][-1]), float(w_ref[-1]),
                   solver_accuracy(result, w_scale), source=SOURCE_FIRST),
            Figure(f"{name}_phi_end", f"{name}.phi at {t[-1]:g} s [rad]",
                   float(result[f"{name}.phi"][-1]), float(phi_ref[-1]),
                   solver_accuracy(result, phi_scale), source=SOURCE_FIRST),
            Figure(f"{name}_w_err", f"{name}.w: largest deviation from the reference over "
                   "the run [rad/s]", float(np.max(np.abs(result[f"{name}.w"] - w_ref))), 0.0,
                   solver_accuracy(result, w_scale), source=SOURCE_FIRST)]
    figures.append(Figure("motor_w_end", f"motor speed (idealGear.flange_a.w) at {t[-1]:g} s "
                          "[rad/s] vs ratio x inertia2's",
                          float(result["idealGear.flange_a.w"][-1]),
                          float(r["w1"][-1]), solver_accuracy(result, np.max(np.abs(r["w1"]))),
                          source=SOURCE_FIRST))
    # the torque's work = kinetic energy of both bodies + the spring's + the damper's loss
    W = float(result["torque.W"][-1])
    stored = sum(float(result[f"{k}.E"][-1]) for k in ("inertia2", "inertia3", "spring"))
    loss = float(result["damper.W_loss"][-1])
    figures.append(Figure("work", "work of the torque source [J] vs kinetic + elastic energy "
                          "+ damper loss", W, stored + loss,
                          solver_accuracy(result, max(abs(W), stored + loss), factor=DRIFT),
                          source=SOURCE_ENERGY))
    figures.append(Figure("work_ref", "work of the torque source at the stop time [J] vs the "
                          "reference's", W, float(r["work"][-1]),
                          solver_accuracy(result, np.max(np.abs(r["work"])), factor=DRIFT),
                          source=SOURCE_FIRST))
    return figures


# --- Backlash ---------------------------------------------------------------------------
_ROWS = (("springDamper", "inertia1", None), ("elastoBacklash", "inertia2", True),
         ("elastoBacklash2", "inertia3", False))


def _backlash() -> Assembly:
    p = ref.BACKLASH
    asm = Assembly("rotational_backlash")
    common = dict(c=p["c"], d=p["d"])
    elements = {"springDamper": RotationalSpringDamper(**common),
                "elastoBacklash": ElastoBacklash(**common, b=p["b"]),
                "elastoBacklash2": ElastoBacklash2(**common, b=p["b"])}
    for k, (element, inertia, _) in enumerate(_ROWS, start=1):
        asm.add(f"fixed{k}", RotationalFixed())
        asm.add(element, elements[element])
        asm.add(inertia, Inertia(J=p["J"], phi=p["phi0"], w=0.0))
        asm.connect(f"fixed{k}.flange", f"{element}.flange_a")
        asm.connect(f"{element}.flange_b", f"{inertia}.flange_a")
    return asm


def _contacts(result: Result, element: str) -> list[tuple[float, int]]:
    """(time, contact) at each event of `element` that changed whether (and where) it
    pushes: contact +-1 while tau != 0, else 0."""
    ev = result.events.get(element)
    if ev is None:
        return []
    out = []
    last = int(result[f"{element}.contact"][0]) if result[f"{element}.tau"][0] else 0
    for t, q, tau in zip(ev["time"], ev[f"{element}.contact"], ev[f"{element}.tau"]):
        now = int(q) if tau != 0 else 0
        if now != last:
            out.append((float(t), now))
            last = now
    return out


def _backlash_figures(result: Result, asm: Assembly) -> list[Figure]:
    p = ref.BACKLASH
    t = np.asarray(result["time"])
    figures = []
    for element, inertia, bounded in _ROWS:
        # a backlash row's motion is a chain of 21 contacts: each restarts the motion from a
        # state that carries the global error of the steps before it, which adds up over
        # the run's thousands of steps (scene.DRIFT); the smooth spring-damper keeps the
        # error of a few steps (100 x tol)
        factor = 100.0 if bounded is None else DRIFT
        if bounded is None:
            phi_ref, w_ref = ref.spring_damper(t)
            source, contacts = "closed form (damped oscillator from rest, derived here)", None
        else:
            sol = ref.backlash(t, bounded)
            phi_ref, w_ref, source, contacts = sol.phi, sol.w, SOURCE_BACKLASH, sol.contacts
        w_scale = float(np.max(np.abs(w_ref)))
        figures += [
            Figure(f"{inertia}_phi_end", f"{inertia}.phi at {t[-1]:g} s [rad] ({element})",
                   float(result[f"{inertia}.phi"][-1]), float(phi_ref[-1]),
                   solver_accuracy(result, p["phi0"], factor), source=source),
            Figure(f"{inertia}_w_end", f"{inertia}.w at {t[-1]:g} s [rad/s] ({element})",
                   float(result[f"{inertia}.w"][-1]), float(w_ref[-1]),
                   solver_accuracy(result, w_scale, factor), source=source),
            Figure(f"{inertia}_phi_err", f"{inertia}.phi: largest deviation from the "
                   "reference over the run [rad]",
                   float(np.max(np.abs(result[f"{inertia}.phi"] - phi_ref))), 0.0,
                   solver_accuracy(result, p["phi0"], factor), source=source)]
        if contacts is not None:
            ours = _contacts(result, element)
            figures.append(Figure(f"{element}_contacts", f"{element}: changes of contact "
                                  "(start and end of pushing) [1]", len(ours), len(contacts),
                                  0.0, source=source))
            for n, (t_ref, q_ref) in enumerate(contacts):
                got = [tt for tt, q in ours[n:n + 1] if q == q_ref]  # the same change, in order
                what = {1: "pushes beyond +b/2", -1: "pushes beyond -b/2", 0: "lets go"}[q_ref]
                figures.append(Figure(f"{element}_{n + 1}", f"{element} {what} at [s]",
                                      got[0] if got else math.nan, t_ref,
                                      solver_accuracy(result, 1.0, factor), source=source))
            # MSL's rule: the contact torque never pulls (its sign is the edge's)
            tau, side = np.asarray(result[f"{element}.tau"]), np.sign(result[f"{element}.tau_c"])
            figures.append(Figure(f"{element}_pull", f"{element}: largest pulling torque "
                                  "[N.m]", float(max(0.0, np.max(-tau * side))), 0.0, 0.0,
                                  source="MSL's ElastoBacklash law: contact only pushes"))
        # nothing acts from outside: the start's elastic energy = kinetic + elastic + loss
        gap = p["b"] / 2 if bounded is not None else 0.0
        e0 = p["c"] * (p["phi0"] - gap)**2 / 2
        total = sum(float(result[c][-1]) for c in (f"{inertia}.E", f"{element}.E",
                                                   f"{element}.W_loss"))
        figures.append(Figure(f"{element}_energy", f"{element}: kinetic + elastic energy + "
                              f"loss at {t[-1]:g} s [J] vs the start's elastic energy", total, e0,
                              solver_accuracy(result, e0, factor=DRIFT), source=SOURCE_ENERGY))
    return figures


MSL_ROTATIONAL_EXAMPLE_SCENES: dict[str, Scene] = {
    "rotational_first": Scene(
        "rotational_first", "MSL Rotational.Examples.First: a sine torque drives a motor "
        "through a gear, a damped bearing and a spring into a load",
        _first, stop_time=ref.FIRST["stop"], step=1e-3, tolerance=1e-8, record=None,
        figures=_first_figures, plot=["inertia2.w", "inertia3.w"], mode="monolithic",
        seed="MSL", reference="scipy integration of MSL's First; work = energy + loss"),
    "rotational_backlash": Scene(
        "rotational_backlash", "MSL Rotational.Examples.Backlash: inertias released on a "
        "spring-damper, an ElastoBacklash and an ElastoBacklash2",
        _backlash, stop_time=ref.BACKLASH["stop"], step=1e-3, tolerance=1e-8, record=None,
        figures=_backlash_figures, plot=["inertia1.phi", "inertia2.phi", "inertia3.phi"],
        mode="monolithic", seed="MSL",
        reference="closed form (spring-damper); branch-by-branch scipy of MSL's backlash "
                  "laws; energy balance"),
}
