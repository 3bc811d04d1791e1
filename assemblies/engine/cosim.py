"""Co-simulation through the compiled engine (engine="c"): one C call per run.

The structure of the coupling is worked out here, with the same code the fmpy
reference master uses (``Assembly.couplings``/``order``, :mod:`assemblies.masters.loops`),
and handed to the C master (``c/cosim.c``) in one configuration: the couplings, their
dependency groups and algebraic loops, the Gauss–Seidel order, which inputs the FMUs
hold constant over a step, the states the adaptive step estimates its error on. The C
master loads the FMUs, runs the experiment and writes the outputs into numpy buffers.

It is the reference master's algorithm (:func:`assemblies.masters.cosim.cosimulate`)
step for step, in every scheme. ``event_sync`` (on by default with ``adaptive``) adds what a friction assembly needs to be right: a step in
which an FMU locates an event is redone to end at the event, and an event an FMU
handles at the start of a step because its inputs moved across a switching condition
(a held spring force passing the static friction limit) is moved back to where the
coupled system crossed, by bisecting the step before it through rollback.
"""
from __future__ import annotations

import ctypes as C
import math
import threading
import time as wallclock
import warnings
from collections import OrderedDict
from dataclasses import dataclass
from typing import Callable

import numpy as np

from components.component import SOLVER_METHODS, Component

from ..assembly import Assembly, AssemblyError
from ..experiment import (FixedStepFallback, check_cosim_settings, check_experiment,
                          fixed_step_fallback, output_times)
from ..foreign import check_mode
from ..inputs import with_inputs
from ..limits import check_output_values
from ..masters.extrapolation import RATES, derivative_couplings, is_held, rate_inputs
from ..masters.loops import coupling_groups, describe, is_loop
from ..result import Result, Table
from ..value_types import CODES, CONTINUOUS
from .binding import (FAILED, PROGRESS_FN, STOPPED, TERMINATED, Coupling, EngineError,
                      InstanceSpec, Keep, Progress, Stats, Variable, declare, typed_column,
                      instance_spec, run_events)
from .build import library
from .me import evaluated_members
from .prepare import prepared, record_columns, rest_groups, structure_key
from .restore import inexact_restores

EVENT_TOL = 1e-10  # width of the final bracket when an event is moved back [s]

# What a default co-simulation should run (measured on the friction scenes, see the
# report of issue 10): a fixed step holding spring forces constant adds negative
# damping of about c h / 2 (two_block_belt's steady sliding goes unstable at h = 0.1
# with d = 0.05), and an event an FMU handles at a communication point lands up to a
# step late. Linear extrapolation removes the first, event synchronisation the
# second, and step doubling keeps the global error of the states near `tol` (1e-5:
# the tightest scene figure, beam_friction_damper's energy balance to 1e-8 J, needs it;
# every joined scene then runs in about a second). Cubic extrapolation, the cubic itself
# carried into each FMU by its rate inputs (assemblies.masters.extrapolation): a
# coupling of order 4 between events where holding the quadratic's step mean was of
# order 2 (issue 27, benchmarks/cosim_fixed.py --extrapolation 2 / 3 and RESULTS.md).
DEFAULT_SCHEME = {"adaptive": True, "extrapolation": 3, "tol": 1e-5}

# Members the master evaluates itself between the points that need their FMUs (cosim.h
# eng_cosim_spec.time_function / .linear_map): kinematic sources from time, stateless
# springs and sensors as linear maps of their inputs, as the engine's me does
# (me.evaluated_members). In exact arithmetic this changes nothing; False steps every
# member, which tests use as the independent path to compare with.
EVALUATE_MEMBERS = True

_P = C.POINTER
_INT = _P(C.c_int)
CONTINUOUS_CODES = {CODES[t] for t in CONTINUOUS}


class _Spec(C.Structure):  # cosim.h: eng_cosim_spec
    _fields_ = [("n_instances", C.c_int), ("instances", _P(InstanceSpec)),
                ("n_couplings", C.c_int), ("couplings", _P(Coupling)), ("held", _INT),
                ("derivative", _INT), ("rates", _P(Variable)),
                ("n_groups", C.c_int), ("group_start", _INT), ("group_members", _INT),
                ("group_is_loop", _INT), ("sweep_order", _INT),
                ("n_states", C.c_int), ("states", _P(Variable)),
                ("n_columns", C.c_int), ("columns", _P(Variable)),
                ("n_times", C.c_long), ("times", _P(C.c_double)), ("out", _P(C.c_double)),
                ("stop_time", C.c_double), ("tolerance", C.c_double), ("step", C.c_double),
                ("scheme", C.c_int), ("extrapolation", C.c_int), ("adaptive", C.c_int),
                ("tol", C.c_double), ("loop_tolerance", C.c_double),
                ("max_loop_iterations", C.c_int), ("newton", C.c_int), ("event_sync", C.c_int),
                ("event_tol", C.c_double), ("progress", PROGRESS_FN),
                ("progress_ctx", C.c_void_p), ("derivatives", _P(Variable)),
                ("rest_group", _INT), ("asleep_since", _P(C.c_double)),
                ("time_function", _INT), ("linear_map", _INT), ("evaluated", _INT)]


class _CosimStats(C.Structure):  # cosim.h: eng_cosim_stats
    _fields_ = [("do_steps", C.c_long), ("loop_iterations", C.c_long),
                ("loop_residual", C.c_double), ("h_min", C.c_double), ("h_max", C.c_double),
                ("error_ratio_max", C.c_double), ("events_synchronised", C.c_long),
                ("events_located", C.c_long), ("loop_failed_group", C.c_int),
                ("loop_singular", C.c_int), ("loop_failed_time", C.c_double),
                ("at_rest_from", C.c_double)]


@dataclass
class CouplingPlan:
    """An assembly's structure as the C master takes it: every variable as (instance
    index, value reference, type code, element, array size: binding.Variable's fields).
    Shared by a run and by an exported assembly FMU,
    which hands the same numbers to the same master in its doStep."""
    index: dict                # instance name -> index
    fmus: dict                 # instance name -> PreparedFmu
    pairs: list                # per coupling: (source, target, gain)
    held: list                 # per coupling: 1 if the FMU holds the input over a step
    derivative: list           # per coupling: the coupling setting its target's derivative
                               # input (the FMU extrapolates along that chain), or -1
    rates: list                # per coupling: its target's rate inputs the master sets
    groups: list               # coupling indices per dependency group, sources first
    loops: list                # the groups that are algebraic loops
    sweep_order: list          # instance indices, Gauss-Seidel order
    states: list               # the continuous states the adaptive step estimates on

    def variable(self, instance: str, name: str) -> tuple[int, int, int, int, int]:
        return (self.index[instance], *self.fmus[instance].variable(instance, name))


def coupling_plan(assembly: Assembly, fmus: dict) -> CouplingPlan:
    couplings = assembly.couplings()
    names = list(assembly.components)
    plan = CouplingPlan({n: i for i, n in enumerate(names)}, fmus, [], [], [], [], [], [], [], [])
    set_by_coupling = {}
    for c in couplings:
        set_by_coupling.setdefault(c.target[0], set()).add(c.target[1])
    for c in couplings:
        source, target = plan.variable(*c.source), plan.variable(*c.target)
        plan.pairs.append((source, target, c.gain))
        chained, coupled = fmus[c.target[0]].chained, set_by_coupling[c.target[0]]
        # an input the FMU extrapolates itself (s with its v and a) is set as it is
        plan.held.append(int(is_held(c.target[1], chained, target[2] not in CONTINUOUS_CODES,
                                     coupled)))
        rates = rate_inputs(c.target[1], chained, coupled) if plan.held[-1] else []
        plan.rates.append([plan.variable(c.target[0], r) for r in rates])
    plan.derivative = derivative_couplings(couplings, {n: fmus[n].chained for n in names})
    depends = {n: fmus[n].depends for n in names}
    inputs = {n: fmus[n].inputs for n in names}
    plan.groups = coupling_groups(couplings, depends, inputs)
    plan.loops = [g for g in plan.groups if is_loop(g, couplings, depends, inputs)]
    plan.sweep_order = [plan.index[n] for n in assembly.order()]
    plan.states = [plan.variable(n, x) for n in names for x in fmus[n].states]
    return plan


@dataclass
class RunShape:
    """What a run hands the C master that depends on the assembly's structure alone."""
    couplings: list
    plan: CouplingPlan
    rest_groups: list          # per instance: the group that may come to rest, or -1
    time_function: list        # per instance: 1 where the master evaluates it from time
    linear_map: list           # per instance: 1 where it evaluates it as a linear map


@dataclass
class _Structure:
    """A structure's checked couplings, and its RunShape per set of prepared FMUs."""
    couplings: list
    shapes: dict  # ids of the prepared FMUs -> RunShape (which holds them: ids stay theirs)


_shapes: OrderedDict = OrderedDict()  # (structure_key, signals_from_outside) -> _Structure
_shapes_lock = threading.Lock()
SHAPES_KEPT = 64  # a sweep over many assemblies keeps the latest, not all
FMU_SETS_KEPT = 4  # per structure (a set changes only where an FMU was built again)


def checked_couplings(assembly: Assembly) -> tuple[tuple, list]:
    """(the structure's key, the assembly's couplings): checked on the first run of a
    structure (an input fed twice is named there, before any FMU is built), then
    memoised by the assembly's structure_key (names, binaries, profiles, connections).
    The assembly's profiles are resolved (the key holds them)."""
    key = (structure_key(assembly), assembly.signals_from_outside)
    with _shapes_lock:
        known = _shapes.get(key)
        if known is not None:
            _shapes.move_to_end(key)
            return key, known.couplings
    couplings = assembly.couplings()
    with _shapes_lock:
        _remember(key, couplings)
    return key, couplings


def _remember(key: tuple, couplings: list) -> _Structure:
    """The memo's entry for `key`, added with `couplings` where it is not there (or was
    dropped meanwhile), the oldest dropped past SHAPES_KEPT. Under _shapes_lock."""
    known = _shapes.setdefault(key, _Structure(couplings, {}))
    while len(_shapes) > SHAPES_KEPT:
        _shapes.popitem(last=False)
    return known


def run_shape(assembly: Assembly, fmus: dict, key: tuple | None = None) -> RunShape:
    """The run's structure, memoised by `key` (checked_couplings') and the prepared FMUs:
    a scene run again with new values built it again each time, 1 of the 2.2 ms
    two_block_belt's call spent outside the C (26 ms in all at tol 1e-4)."""
    if key is None:
        key, _ = checked_couplings(assembly)
    ids = tuple(id(f) for f in fmus.values())
    with _shapes_lock:
        known = _shapes.get(key)
        shape = known.shapes.get(ids) if known is not None else None
    if shape is not None:
        return shape
    couplings = known.couplings if known is not None else assembly.couplings()
    names = list(assembly.components)
    shape = RunShape(couplings, coupling_plan(assembly, fmus), rest_groups(names, couplings, fmus),
                     evaluated_members(assembly, fmus, [], couplings, False, cosim=True),
                     evaluated_members(assembly, fmus, [], couplings, True, cosim=True))
    with _shapes_lock:
        known = _remember(key, couplings)
        if len(known.shapes) >= FMU_SETS_KEPT:
            known.shapes.clear()
        known.shapes[ids] = shape
    return shape


def _lib():
    """The engine library with the cosim entry point's signature declared."""
    lib = library()
    if lib.eng_cosimulate.restype is not C.c_void_p:
        declare(lib)
        lib.eng_cosimulate.argtypes = [_P(_Spec), _P(Stats), _P(_CosimStats)]
        lib.eng_cosimulate.restype = C.c_void_p
    return lib


def cosimulate(assembly: Assembly, stop_time: float, step: float, tolerance: float = 1e-8,
               record: list[str] | None = None, scheme: str = "jacobi",
               progress: Callable[[float], None] | None = None, extrapolation: int = 0,
               adaptive: bool = False, tol: float = 1e-4, loop_tolerance: float = 1e-10,
               max_loop_iterations: int = 20, newton: bool = True,
               event_sync: bool | None = None, start_time: float = 0.0,
               inputs=None) -> Result:
    """Co-simulate `assembly` from `start_time` to `stop_time` in the compiled engine.

    Same arguments and result as :func:`assemblies.masters.cosim.cosimulate` (see
    there), plus `event_sync` (None: on exactly when `adaptive`): steps end at the
    events the FMUs locate, and events the FMUs handle at a communication point are
    moved back to where the coupled system crossed (to 1e-10 s), where the FMUs' modes
    settle before the next step (cosim.c settle). Adaptive steps and
    event synchronisation roll back through FMU state; where an FMU cannot get and set
    its state (a foreign one, say), or a foreign FMU's restore proves inexact when
    checked once (:mod:`assemblies.engine.restore`; ``settings["inexact_restore"]``
    names it and what differed), the run falls back to fixed steps of `step` without
    event synchronisation, warns (:class:`FixedStepFallback`) and says so in
    ``settings["fallback"]``. Fixed steps tell each doStep that no earlier state will
    be set again (noSetFMUStatePriorToCurrentPoint). A model that ends the run (FMI 2:
    doStep Discard with fmi2Terminated; FMI 3: terminateSimulation) ends it where it
    stopped, with the rows so far and ``settings["terminated"]`` (instance, time, message). `progress(t)` is called about every 0.25 s of wall time;
    Ctrl-C (or an exception in `progress`, raised again afterwards) stops the run
    cleanly, keeping the rows computed (``settings["stopped"]``). With
    ``**DEFAULT_SCHEME`` a friction assembly comes out right (module doc). `inputs`:
    a table feeding open inputs (:mod:`assemblies.inputs`). Kinematic sources whose
    outputs are exact functions of time (ConstantSpeed) and members with no states whose
    coupled outputs are fixed linear maps of their inputs (springs, sensors) are not
    stepped: the master evaluates them, and brings their FMUs up to date where a row
    records them (EVALUATE_MEMBERS; ``settings["evaluated_from_time"]`` and
    ``["evaluated_as_linear_maps"]`` name them).
    """
    check_experiment(stop_time, step, tolerance, start_time=start_time)
    assembly = with_inputs(assembly, inputs)
    check_cosim_settings(scheme, extrapolation, adaptive, tol)
    if not (isinstance(max_loop_iterations, int) and max_loop_iterations >= 1):
        raise AssemblyError(f"max_loop_iterations must be an integer >= 1, not {max_loop_iterations!r}")
    event_sync = bool(adaptive) if event_sync is None else bool(event_sync)
    check_mode(assembly, "cosim")  # a Model-Exchange-only FMU: named, with the modes that apply
    setup = wallclock.perf_counter()
    assembly.resolve_causality()  # the profiles the FMUs and the run's shape are of
    # a wiring mistake is named before any FMU is built
    structure, _ = checked_couplings(assembly)
    names = list(assembly.components)
    fmus = {n: prepared(assembly.components[n]) for n in names}
    _lib()  # compiled on a machine's first run: setup, like the FMUs
    stateless = [n for n in names if not fmus[n].can_get_set_state]
    # a foreign FMU's restore is trusted once checked (once per process: setup too)
    inexact = inexact_restores(assembly, fmus, step, tolerance) if adaptive or event_sync else {}
    # the run's wall time leaves out building and loading the FMUs (seconds once, then cached)
    started = wallclock.perf_counter()
    setup_s = started - setup
    fallback = None
    if (adaptive or event_sync) and (stateless or inexact):
        fallback = fixed_step_fallback(adaptive, stateless, step, inexact)
        warnings.warn(fallback, FixedStepFallback, stacklevel=2)
        adaptive = event_sync = False

    shape = run_shape(assembly, fmus, structure)
    couplings, plan = shape.couplings, shape.plan
    groups, loops = plan.groups, plan.loops

    def var(inst, name) -> Variable:
        return Variable(*plan.variable(inst, name))

    keep = Keep()  # every array the spec points into, alive until the call returns
    specs = (InstanceSpec * len(names))(*[
        instance_spec(keep, n, fmus[n], False,
                      assembly.components[n].fmu_starts(),
                      fmus[n].outputs) for n in names])

    spec = _Spec()
    spec.n_instances, spec.instances = len(names), specs
    spec.n_couplings = len(couplings)
    spec.couplings = keep.array(Coupling, [Coupling(Variable(*s), Variable(*t), gain)
                                           for s, t, gain in plan.pairs])
    spec.held = keep.array(C.c_int, plan.held)
    spec.derivative = keep.array(C.c_int, plan.derivative)
    if any(plan.rates):
        none = Variable(-1, 0, 0, 0, 0)
        spec.rates = keep.array(Variable, [Variable(*r[j]) if j < len(r) else none
                                           for r in plan.rates for j in range(RATES)])
    spec.n_groups = len(groups)
    spec.group_start = keep.array(C.c_int, np.cumsum([0] + [len(g) for g in groups]).tolist())
    spec.group_members = keep.array(C.c_int, [k for g in groups for k in g])
    spec.group_is_loop = keep.array(C.c_int, [int(g in loops) for g in groups])
    spec.sweep_order = keep.array(C.c_int, plan.sweep_order)
    spec.n_states = len(plan.states)
    spec.states = keep.array(Variable, [Variable(*v) for v in plan.states])
    groups_at_rest = shape.rest_groups
    if any(g >= 0 for g in groups_at_rest):
        # a group of instances coupled only to one another, all ours and without explicit
        # time, stands still for good where all its derivatives are zero: the engine stops
        # stepping it, and stops altogether when every instance rests (cosim.h)
        spec.derivatives = keep.array(Variable, [Variable(*plan.variable(n, d)) for n in names
                                                 for d in fmus[n].derivatives])
        spec.rest_group = keep.array(C.c_int, groups_at_rest)
    asleep = np.full(len(names), np.inf)
    spec.asleep_since = keep.numpy(asleep, C.c_double)
    columns = record_columns(fmus, record)
    spec.n_columns, spec.columns = len(columns), keep.array(Variable, [var(i, v) for i, v in columns])
    evaluated = np.zeros(len(names), dtype=np.intc)
    if EVALUATE_MEMBERS:
        # a time function's recorded columns are read after one doStep over the time it
        # lagged, a linear map's after its inputs are set: recorded ones qualify too
        spec.time_function = keep.array(C.c_int, shape.time_function)
        spec.linear_map = keep.array(C.c_int, shape.linear_map)
        spec.evaluated = keep.numpy(evaluated, C.c_int)

    times = output_times(stop_time, step, start_time)
    check_output_values(len(times), 1 + len(columns), f"assembly '{assembly.name}'")
    out = np.empty((len(times), 1 + len(columns)))  # the C writes rows [0, n_rows)
    spec.n_times, spec.times = len(times), keep.numpy(times, C.c_double)
    spec.out = keep.numpy(out, C.c_double)
    spec.stop_time, spec.tolerance, spec.step = stop_time, tolerance, step
    spec.scheme = 0 if scheme == "jacobi" else 1
    spec.extrapolation, spec.adaptive, spec.tol = extrapolation, int(bool(adaptive)), tol
    spec.loop_tolerance, spec.max_loop_iterations = loop_tolerance, max_loop_iterations
    spec.newton, spec.event_sync, spec.event_tol = int(bool(newton)), int(event_sync), EVENT_TOL

    progress_cb = Progress(progress)
    spec.progress = progress_cb.callback
    lib = _lib()
    stats, cstats = Stats(), _CosimStats()
    lib.eng_strings_clear()  # String values of this run only (c/engine.h)
    with progress_cb.sigint():
        run = lib.eng_cosimulate(C.byref(spec), C.byref(stats), C.byref(cstats))
    try:
        if stats.status == FAILED:
            raise EngineError(_failure(stats, cstats, couplings, groups, newton,
                                       max_loop_iterations))
        progress_cb.reraise()
        if not run:
            raise EngineError("out of memory for the event tables")
        events = {}
        for i, n in enumerate(names):
            rows = run_events(lib, run, i)
            if len(rows):
                events[n] = Table({name: typed_column(lib, fmus[n], o, rows[:, j]) for j, (name, o)
                                   in enumerate([("time", None)] + [(f"{n}.{o}", o) for o
                                                                   in fmus[n].outputs])})
    finally:
        lib.eng_run_free(run)
    terminated = None
    if stats.status == TERMINATED:
        terminated = {"instance": names[stats.terminated_by], "time": stats.t_end,
                      "message": stats.message.decode("utf-8", "replace")}
    out = out[:stats.n_rows]
    header = ["time"] + [f"{i}.{v}" for i, v in columns]
    settings = {"engine": "c", "start_time": start_time, "stop_time": stop_time, "step": step, "tolerance": tolerance,
                "scheme": scheme, "extrapolation": extrapolation, "adaptive": bool(adaptive),
                "event_sync": event_sync, "wall_s": wallclock.perf_counter() - started,
                "setup_s": setup_s,
                "terminated": terminated, "do_steps": cstats.do_steps, "steps": stats.steps,
                "rejected": stats.rejected,
                "loops": [" -> ".join(".".join(couplings[k].source) for k in g) for g in loops],
                "loop_iterations": cstats.loop_iterations, "loop_residual": cstats.loop_residual,
                "events_synchronised": cstats.events_synchronised,
                "events_located": cstats.events_located, "fallback": fallback,
                "inexact_restore": inexact or None,
                "at_rest_from": None if math.isinf(cstats.at_rest_from) else cstats.at_rest_from,
                "asleep": {n: float(t) for n, t in zip(names, asleep) if math.isfinite(t)},
                # the members the master took from time or as linear maps (as me's settings)
                "evaluated_from_time": [n for n, e in zip(names, evaluated) if e == 1],
                "evaluated_as_linear_maps": [n for n, e in zip(names, evaluated) if e == 2],
                # each of our FMUs' own solver; "auto" switches inside the FMU (its
                # logSolver messages say which method each doStep ended with)
                "solver": {n: SOLVER_METHODS[2 if c.solver is None else c.solver]
                           for n, c in assembly.components.items() if isinstance(c, Component)}}
    if stats.status == STOPPED:
        settings["stopped"] = f"at t = {out[-1, 0]:g}" + (
            " by Ctrl-C" if progress_cb.interrupted else " by the progress callback")
    if adaptive:
        settings.update(tol=tol, h_min=cstats.h_min, h_max=cstats.h_max,
                        error_ratio_max=cstats.error_ratio_max)
    kinds = [None] + [(fmus[i], v) for i, v in columns]
    return Result({name: out[:, j] if kinds[j] is None else typed_column(lib, *kinds[j], out[:, j])
                   for j, name in enumerate(header)}, events, settings)


def _failure(stats, cstats, couplings, groups, newton, max_iterations) -> str:
    """The C master's failure as one line; loop failures named with their variables."""
    if cstats.loop_failed_group < 0:
        return stats.message.decode("utf-8", "replace")
    g = groups[cstats.loop_failed_group]
    if cstats.loop_singular:
        text = (f"algebraic loop {describe(g, couplings)} has a singular Jacobian (I - dG/du): "
                "no unique consistent input")
    else:
        instances = sorted({couplings[k].source[0] for k in g} | {couplings[k].target[0] for k in g})
        text = (f"algebraic loop between FMUs {', '.join(instances)} did not converge in "
                f"{max_iterations} {'Newton' if newton else 'fixed-point'} iterations "
                f"(residual {cstats.loop_residual:.3g}): {describe(g, couplings)}")
    return f"at t = {cstats.loop_failed_time:g}: {text}"


__all__ = ["DEFAULT_SCHEME", "CouplingPlan", "FixedStepFallback", "RunShape",
           "checked_couplings", "coupling_plan", "cosimulate", "run_shape"]
