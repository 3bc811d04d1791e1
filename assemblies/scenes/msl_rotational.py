"""Scenes that rebuild MSL's Modelica.Mechanics.Rotational.Examples from our components.

- ``coupled_clutches``: MSL's CoupledClutches, the FMI community's friction benchmark:
  four inertias, three clutches engaged by a cosine (clutch1) and two steps (clutch2 at
  0.4 s, clutch3 at 0.9 s), J1 driven by 10 sin(2 pi 5 t) N.m, stop time 1.5 s, MSL's
  parameters and start values (J1.w = 10 rad/s). Each clutch carries its driven inertia
  (J2, J3, J4: see components/rotational/friction.py), so a locked clutch is an
  algebraic loop through the accelerations, which the monolithic master solves per
  combination of the clutch modes, so the scene runs monolithic (the composite FMU).
  Mode me, in both engines, solves the loop across the separate FMUs at every
  evaluation (Newton on the FMUs' directional derivatives: one step, the loop is linear
  in its inputs for given modes; the compiled engine keeps the factors while they
  converge, c/loop.c) and meets every figure. Mode cosim (both engines) solves the loop J1 -> clutch1 ->
  clutch2 -> clutch3 at each communication point; a clutch locked to an FMU upstream
  follows its driver's acceleration as an input extrapolated over the step, so the lock
  holds to the communication step's error control.

Figures: every lock and break-away time of an engaged clutch and the final speeds, held
to the event-driven reference of :mod:`.msl_rotational_references` (written from MSL's
documented clutch law; event times to ~1e-10 s) with the solver's accuracy,
100 x tolerance (scene.solver_accuracy), co-simulated 100 x the larger of the FMUs' and
the adaptive communication step's tolerances (scene.coupling_accuracy; one step added
on fixed steps).
"""
from __future__ import annotations

import math

import numpy as np

from components.friction import FREE
from components.rotational.friction import Clutch
from components.rotational.rigid import Inertia
from components.sources.rotational import Torque
from components.sources.signals import Sine, Step

from ..assembly import Assembly
from ..result import Result
from .msl_rotational_references import CoupledClutches, coupled_clutches
from .scene import Figure, Scene, coupling_accuracy

_CC = CoupledClutches()
_CLUTCHES = ("clutch1", "clutch2", "clutch3")


# where every figure's reference comes from
SOURCE = "independent integration (event-driven scipy of MSL's documented clutch law)"


def _coupled_clutches() -> Assembly:
    m = _CC
    asm = Assembly("coupled_clutches")
    asm.add("sin1", Sine(amplitude=m.amplitude, f=m.f1))
    asm.add("torque", Torque())
    asm.add("J1", Inertia(J=m.J[0], w=m.w0[0]))
    asm.add("sin2", Sine(amplitude=1.0, f=m.f2, phase=math.pi / 2))
    asm.add("step1", Step(startTime=m.T2))
    asm.add("step2", Step(startTime=m.T3))
    for k, name in enumerate(_CLUTCHES):  # clutch k drives inertia J(k+2)
        asm.add(name, Clutch(J=m.J[k + 1], w=m.w0[k + 1], peak=m.peak, fn_max=m.fn_max,
                             cgeo=m.cgeo, **{"mu_pos[1,2]": m.mu}))
    asm.connect("sin1.y", "torque.tau")
    asm.connect("torque.flange", "J1.flange_a")
    asm.connect("J1.flange_b", "clutch1.flange_a")
    asm.connect("clutch1.flange_b", "clutch2.flange_a")
    asm.connect("clutch2.flange_b", "clutch3.flange_a")
    asm.connect("sin2.y", "clutch1.f_normalized")
    asm.connect("step1.y", "clutch2.f_normalized")
    asm.connect("step2.y", "clutch3.f_normalized")
    return asm


def mode_changes(result: Result, instance: str, engaged_only: bool = True,
                 triggers: tuple[str, ...] = (), away: float = 0.0):
    """(time, settled mode) of each change of `instance`'s mode while engaged (fn > 0;
    every change with `engaged_only` false: a one-way clutch's freewheel), at its own
    events and at those of the instances `triggers` (a signal whose jump switches it).

    The settled mode after an event is read from the first output row after it and
    compared with the last row before it, and events less than 1e-9 s apart are one:
    an event row records the mode its own iteration reached, and an assembly whose
    iteration passes through a transient mode (as clutches in series did before a
    stuck clutch followed its driver's jumps) is still read right. Events between the
    same two rows are one change too: the rows cannot show more. `away`: the rows read
    are at least that far from the event (the events' time accuracy): a change undone
    within it (a lock and release where the relative speed touches 0) is none.
    """
    tables = [result.events[k] for k in (instance, *triggers) if k in result.events]
    if not tables:
        return []
    t, mode = np.asarray(result["time"]), np.asarray(result[f"{instance}.mode"])
    fn = np.asarray(result[f"{instance}.fn"]) if engaged_only else np.ones_like(t)
    out, cluster, read = [], -math.inf, None
    for te in np.sort(np.concatenate([np.asarray(ev["time"]) for ev in tables])):
        if te - cluster < 1e-9:
            continue
        cluster = te
        before = np.searchsorted(t, te - away, side="left") - 1
        after = np.searchsorted(t, te + away, side="right")
        # the rows show one change between them however many events lie there (a
        # co-simulated contact touching w_rel = 0 at a torque's zero chatters there)
        if after == len(t) or before < 0 or (before, after) == read:
            continue
        # being pressed again (out of MSL's free mode) is neither a lock nor a break-away
        if mode[after] != mode[before] and fn[after] > 0 and mode[before] != FREE:
            out.append((float(te), int(mode[after])))
            read = (before, after)
    return out


def _coupled_clutches_figures(result: Result, asm: Assembly) -> list[Figure]:
    ref = coupled_clutches(_CC)
    figures = []
    for k, name in enumerate(_CLUTCHES, start=1):
        expected = [(t, q) for t, c, q in ref.events if c == k]
        measured = mode_changes(result, name)
        figures.append(Figure(f"{name}_events", f"lock and break-away events of {name} [1]",
                              len(measured), len(expected), 0.0,
                              source=SOURCE))
        for n, (t_ref, q_ref) in enumerate(expected):
            kind = "locks" if q_ref == 0 else "breaks away"
            got = [t for t, q in measured[n:n + 1] if q == q_ref]  # the same change, in order
            figures.append(Figure(f"{name}_{n + 1}", f"{name} {kind} at [s]",
                                  got[0] if got else math.nan, t_ref,
                                  coupling_accuracy(result, 1.0),
                                  source=SOURCE))
    w_end = ref.w[-1]
    for k, column in enumerate(("J1.w", "clutch1.w", "clutch2.w", "clutch3.w")):
        figures.append(Figure(f"w{k + 1}_end", f"J{k + 1}.w at {_CC.stop:g} s [rad/s]",
                              float(result[column][-1]), float(w_end[k]),
                              coupling_accuracy(result, w_end[k]),
                              source=SOURCE))
    return figures


MSL_ROTATIONAL_SCENES = {
    "coupled_clutches": Scene(
        "coupled_clutches", "MSL Rotational.Examples.CoupledClutches: four inertias, three "
        "clutches engaging and releasing in turn (exact lock/break-away events)",
        _coupled_clutches, stop_time=_CC.stop, step=1e-3, tolerance=1e-6,
        record=["J1.w", "clutch1.w", "clutch2.w", "clutch3.w", "clutch1.mode", "clutch2.mode",
                "clutch3.mode", "clutch1.tau", "clutch2.tau", "clutch3.tau", "clutch1.fn",
                "clutch2.fn", "clutch3.fn"],
        figures=_coupled_clutches_figures, plot=["J1.w", "clutch1.w", "clutch2.w", "clutch3.w"],
        mode="monolithic", seed="MSL",
        reference="lock and break-away times, final speeds: event-driven scipy solution of "
                  "MSL's clutch law"),
}
