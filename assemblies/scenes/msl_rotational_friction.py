"""Scenes that rebuild MSL's Rotational.Examples.Friction and .OneWayClutch.

- ``rotational_friction``: MSL's Friction, "drive train with clutch and brake":
  inertia3 (J = 1, w = 100 rad/s) driven by 200 sin(100 t) N.m until 0.5 s (a sine
  times a step, MSL's Product), a clutch always engaged (fn_max = 160 N) to inertia2
  (J = 0.05, w = 90), a spring-damper (c = 160, d = 1) to inertia1 (J = 1, w = 90) in
  a brake (fn_max = 1600 N) engaged by a step at 0.5 s; MSL's friction defaults
  (mu_pos = [0, 0.5], peak = 1, cgeo = 1), stop time 3 s.
- ``rotational_one_way_clutch``: MSL's OneWayClutch: inertiaIn (J = 1, w = -0.5) driven
  by 10 sin(2 pi 3 t), a one-way clutch (peak = 25, fn_max = 3) to inertiaOut (J = 1,
  at rest), engaged by MSL's Pulse (width 50 %, period 1.3 s, from 0.3 s; a table
  source holding the pulse's values), stop time 2 s.

As in CoupledClutches (:mod:`.msl_rotational`), each clutch and the brake carry the
inertia they drive (clutch: inertia2, one-way clutch: inertiaOut, brake: inertia1:
see components/rotational/friction.py), and a locked clutch joins its driver's inertia
to it: an algebraic loop through the accelerations, which the monolithic master solves
per combination of the modes, and mode me (either engine) by Newton across the separate
FMUs at every evaluation. Both scenes run monolithic (the composite FMU) by default, in
mode me, and co-simulated, where the loop is solved at each communication point and a
lock across FMUs holds to the adaptive step's tolerance (the event and final figures then
state scene.coupling_accuracy: 100 x 1e-5). The one-way clutch's release when the pulse
ends at 0.95 s is an input that jumps at a communication point while the clutch is
locked: the master lets the clutch leave its stick and the loop settle with the free
clutch there before it steps on (assemblies/engine/c/cosim.c settle).

Figures: every stick/slip change of an engaged clutch or brake (and every lock and
overrun of the one-way clutch, engaged or a bare freewheel), the final angles and
speeds, held to the event-driven reference of :mod:`.msl_rotational_friction_references`
(written from MSL's documented equations; event times to ~1e-10 s) with the solver's
accuracy (100 x tolerance, scene.solver_accuracy; co-simulated, the coupling's); and the energy balance (work of the
motor + initial kinetic energy = kinetic + elastic + dissipated) within DRIFT x tolerance
of the energy involved. The modes are read that accuracy away from each event:
OneWayClutch's w_rel touches 0 at 1.5 s with zero relative acceleration, a lock and
release a method sees or not by its rounding.
"""
from __future__ import annotations

import math

import numpy as np

from components.rotational.elements import RotationalSpringDamper
from components.rotational.friction import Clutch, OneWayClutch, RotationalBrake
from components.rotational.rigid import Inertia
from components.sources.math import Product
from components.sources.rotational import Torque
from components.sources.signals import Constant, Sine, Step
from components.sources.table import TimeTable

from ..assembly import Assembly
from ..result import Result
from .msl_rotational import mode_changes
from .msl_rotational_friction_references import Friction, OneWayClutchExample
from .scene import DRIFT, Figure, Scene, coupling_accuracy, solver_accuracy

_FR = Friction()
_OWC = OneWayClutchExample()

# where every figure's reference comes from
SOURCE = "independent integration (event-driven scipy of MSL's documented friction laws)"
BALANCE = "conservation law (work of the motor = change of kinetic + elastic energy + losses)"


def _friction() -> Assembly:
    m = _FR
    asm = Assembly("rotational_friction")
    asm.add("sine", Sine(amplitude=m.amplitude, f=m.f))
    asm.add("step2", Step(height=-1.0, offset=1.0, startTime=m.start_time))
    asm.add("product", Product())
    asm.add("torque", Torque())
    asm.add("inertia3", Inertia(J=m.J3, w=m.w0[0]))
    asm.add("const", Constant(k=1.0))
    asm.add("clutch", Clutch(J=m.J2, w=m.w0[1], fn_max=m.fn_clutch))  # drives inertia2
    asm.add("spring", RotationalSpringDamper(c=m.c, d=m.d))
    asm.add("step", Step(startTime=m.start_time))
    asm.add("brake", RotationalBrake(J=m.J1, w=m.w0[2], fn_max=m.fn_brake))  # holds inertia1
    asm.connect("sine.y", "product.u1")
    asm.connect("step2.y", "product.u2")
    asm.connect("product.y", "torque.tau")
    asm.connect("torque.flange", "inertia3.flange_a")
    asm.connect("inertia3.flange_b", "clutch.flange_a")
    asm.connect("const.y", "clutch.f_normalized")
    asm.connect("clutch.flange_b", "spring.flange_a")
    asm.connect("spring.flange_b", "brake.flange_a")
    asm.connect("step.y", "brake.f_normalized")
    return asm


def _one_way_clutch() -> Assembly:
    m = _OWC
    edges = m.pulse_edges()
    rows = [(0.0, 0.0)] + [(t, m.engaged(t + 1e-9)) for t in edges]
    asm = Assembly("rotational_one_way_clutch")
    asm.add("signalTorque", Sine(amplitude=m.amplitude, f=m.f))
    asm.add("torque", Torque())
    asm.add("inertiaIn", Inertia(J=m.J_in, w=m.w0[0]))
    asm.add("signalEngagement", TimeTable(table=rows, interpolation="hold"))
    asm.add("oneWayClutch", OneWayClutch(J=m.J_out, w=m.w0[1], peak=m.peak,
                                         fn_max=m.fn_max))  # drives inertiaOut
    asm.connect("signalTorque.y", "torque.tau")
    asm.connect("torque.flange", "inertiaIn.flange_a")
    asm.connect("inertiaIn.flange_b", "oneWayClutch.flange_a")
    asm.connect("signalEngagement.y", "oneWayClutch.f_normalized")
    return asm


def _event_figures(result, ref_events, contacts, engaged_only, triggers=()) -> list[Figure]:
    """One figure for the count of each contact's mode changes, one per change; the
    modes read from rows the events' accuracy away from each event (mode_changes'
    `away`: OneWayClutch's w_rel touches 0 at 1.5 s with zero relative acceleration,
    a lock and release that a method sees or not by its rounding)."""
    figures = []
    kinds = {0: "locks", 1: "slides forward", -1: "slides backward"}
    width = coupling_accuracy(result, 1.0)
    for k, name in enumerate(contacts):
        expected = [(t, q) for t, c, q in ref_events if c == k]
        measured = mode_changes(result, name, engaged_only=engaged_only, triggers=triggers,
                                away=width)
        figures.append(Figure(f"{name}_events", f"stick/slip changes of {name} [1]",
                              len(measured), len(expected), 0.0, source=SOURCE))
        for n, (t_ref, q_ref) in enumerate(expected):
            got = [t for t, q in measured[n:n + 1] if q == q_ref]  # the same change, in order
            figures.append(Figure(f"{name}_{n + 1}", f"{name} {kinds[q_ref]} at [s]",
                                  got[0] if got else math.nan, t_ref, width, source=SOURCE))
    return figures


def _final_figures(result, ref, columns) -> list[Figure]:
    figures = []
    end = ref.y[-1]
    for k, (label, column, unit) in enumerate(columns):
        figures.append(Figure(label, f"{column} at {ref.t[-1]:g} s [{unit}]",
                              float(result[column][-1]), float(end[k]),
                              coupling_accuracy(result, end[k]), source=SOURCE))
    return figures


def _balance_figure(result, work, kinetic, other, losses, scale) -> Figure:
    """Largest |W_motor + E_kin(0) - E_kin - E_elastic - losses| over the run [J]."""
    col = {c: np.asarray(result[c]) for c in (work, *kinetic, *other, *losses)}
    energy = sum(col[c] for c in (*kinetic, *other))
    balance = col[work] + energy[0] - energy - sum(col[c] for c in losses)
    return Figure("energy_balance", "max |work - change of energy - losses| [J]",
                  float(np.abs(balance).max()), 0.0,
                  solver_accuracy(result, scale, DRIFT), source=BALANCE)


def _friction_figures(result: Result, asm: Assembly) -> list[Figure]:
    ref = _FR.solve()
    figures = _event_figures(result, ref.events, ("clutch", "brake"), engaged_only=True,
                             triggers=("step", "step2"))
    figures += _final_figures(result, ref, [
        ("phi3_end", "inertia3.phi", "rad"), ("phi2_end", "clutch.phi", "rad"),
        ("phi1_end", "brake.phi", "rad"), ("w3_end", "inertia3.w", "rad/s"),
        ("w2_end", "clutch.w", "rad/s"), ("w1_end", "brake.w", "rad/s")])
    e0 = sum(J * w**2 / 2 for J, w in zip((_FR.J3, _FR.J2, _FR.J1), _FR.w0))
    figures.append(_balance_figure(result, "torque.W", ("inertia3.E", "clutch.E", "brake.E"),
                                   ("spring.E",), ("clutch.W_loss", "brake.W_loss",
                                                   "spring.W_loss"), e0))
    return figures


def _one_way_clutch_figures(result: Result, asm: Assembly) -> list[Figure]:
    ref = _OWC.solve()
    # the freewheel locks and releases with no normal force too: every change counts, the
    # ones the pulse's edges cause as well
    figures = _event_figures(result, ref.events, ("oneWayClutch",), engaged_only=False,
                             triggers=("signalEngagement",))
    figures += _final_figures(result, ref, [
        ("phi_in_end", "inertiaIn.phi", "rad"), ("phi_out_end", "oneWayClutch.phi", "rad"),
        ("w_in_end", "inertiaIn.w", "rad/s"), ("w_out_end", "oneWayClutch.w", "rad/s")])
    e0 = _OWC.J_in * _OWC.w0[0]**2 / 2 + _OWC.J_out * _OWC.w0[1]**2 / 2
    work = float(np.abs(np.asarray(result["torque.W"])).max())
    figures.append(_balance_figure(result, "torque.W", ("inertiaIn.E", "oneWayClutch.E"), (),
                                   ("oneWayClutch.W_loss",), max(e0, work)))
    return figures


MSL_ROTATIONAL_FRICTION_SCENES = {
    "rotational_friction": Scene(
        "rotational_friction", "MSL Rotational.Examples.Friction: a driven inertia, a clutch, "
        "a spring-damper and a brake engaged at 0.5 s (exact stick/slip events)",
        _friction, stop_time=_FR.stop, step=1e-3, tolerance=1e-8,
        record=["inertia3.phi", "inertia3.w", "clutch.phi", "clutch.w", "brake.phi", "brake.w",
                "clutch.mode", "brake.mode", "clutch.fn", "brake.fn", "clutch.tau", "brake.tau",
                "spring.tau", "torque.W", "inertia3.E", "clutch.E", "brake.E", "spring.E",
                "clutch.W_loss", "brake.W_loss", "spring.W_loss"],
        figures=_friction_figures, plot=["inertia3.w", "clutch.w", "brake.w", "clutch.tau",
                                         "brake.tau", "spring.tau"],
        mode="monolithic", seed="MSL",
        reference="stick/slip times, final angles and speeds: event-driven scipy solution of "
                  "MSL's friction laws; energy balance"),
    "rotational_one_way_clutch": Scene(
        "rotational_one_way_clutch", "MSL Rotational.Examples.OneWayClutch: a one-way clutch "
        "engaged by a pulse between two inertias (exact lock/overrun events, freewheel)",
        _one_way_clutch, stop_time=_OWC.stop, step=1e-3, tolerance=1e-8,
        record=["inertiaIn.phi", "inertiaIn.w", "oneWayClutch.phi", "oneWayClutch.w",
                "oneWayClutch.mode", "oneWayClutch.fn", "oneWayClutch.tau",
                "oneWayClutch.w_rel", "oneWayClutch.lossPower", "torque.W", "inertiaIn.E",
                "oneWayClutch.E", "oneWayClutch.W_loss"],
        figures=_one_way_clutch_figures, plot=["inertiaIn.w", "oneWayClutch.w",
                                               "oneWayClutch.fn", "oneWayClutch.lossPower"],
        mode="monolithic", seed="MSL",
        reference="lock and overrun times, final angles and speeds: event-driven scipy "
                  "solution of MSL's one-way clutch law; energy balance"),
}
