"""Model Exchange and monolithic runs in the compiled engine (engine="c").

``simulate_me``: every instance as a Model Exchange FMU, all continuous states in the
engine's one integrator (c/me.c). ``simulate_monolithic``: the assembly joined into one
composite FMU (:func:`assemblies.masters.monolithic.composite`), run by the same master
as a single instance. Both take the arguments and return the Result shape of the fmpy
reference masters (:mod:`assemblies.masters.me`, :mod:`assemblies.masters.monolithic`).
``prepare_me`` and ``prepare_monolithic`` take the same arguments and return the run as
a call without arguments: the checks and look-ups once, for many runs.
"""
from __future__ import annotations

import ctypes as C
import functools
import math
import threading
import time as wallclock
import warnings
from operator import itemgetter
from typing import Callable

import numpy as np

from components.component import SOLVER_METHODS, Component
from components.dae import flatten
from components.lazy import lazy
from fmus.build import component_facts, fmu_recipe, recipes

from ..assembly import Assembly, AssemblyError
from ..experiment import check_experiment, output_times
from ..foreign import check_mode
from ..inputs import with_inputs
from ..limits import check_output_values
from ..masters.loops import loop_order
from ..result import Result, Table
from ..value_types import STRING
from . import binding as B
from .build import library
from .liveness import continuous_couplings, indicator_couplings, row_couplings
from .prepare import (binary_key, class_defaults, member_termination, prepared,
                      prepared_composite, record_columns, rest_groups, structure_key)

ca = lazy("casadi")  # loaded by the first equation written, not by an import

# Event location per instance (eng_me_spec.indicator_start) from this many instances with
# event indicators on: each instance's look costs it and the instances it reads, the
# whole assembly's look costs everything once per sample, and only a large assembly has
# enough indicators near zero at once to make the second dearer (friction chain, CPU
# per run, per instance / whole: 8 blocks 2.49 / 2.19 ms, 32: 11.8 / 13.4, 128: 57 / 74)
LOCAL_EVENTS_FROM = 16

#: the integrators; "auto" starts with the explicit method and switches to RODAS3 where
#: stiffness shows and back where it is gone (fmus/runtime/stiffness.h). Its explicit
#: method is DOPRI5, or DOP853 (8th order) at tolerances up to 1e-8 (engine.h,
#: ENG_HIGH_ORDER_TOLERANCE) where the steps are not capped (step_limit_needed), until
#: events come every few steps; settings["explicit_method"] says which. The C's ENG_*
#: values:
METHODS = {**{name: value for value, name in SOLVER_METHODS.items()}, "DOP853": 3}
EXPLICIT_METHODS = {5: "DOPRI5", 8: "DOP853",  # eng_stats.explicit_order
                    85: "DOP853, then DOPRI5 (events every few steps)"}
# at most this many interior points per step, sampled only where an indicator's values and
# rates at the step's ends leave room for it to cross twice inside (events.h)
EVENT_SUBSAMPLES = 4
#: the Jacobian RODAS3 and the stiffness check use (engine.h, ENG_JACOBIAN_*): "auto",
#: directional derivatives unless a foreign FMU's disagree with differences at the first
#: point or fail; "fd", finite differences; "exact", directional derivatives or an error
JACOBIANS = {"auto": 0, "fd": 1, "exact": 2}


class JacobianFallback(UserWarning):
    """A run left an FMU's directional derivatives for finite differences (they disagree
    with differences at the first point, or a call failed); ``settings["jacobian_note"]``
    says which instance and why."""


class _Plan:
    """Everything of one engine call that depends only on the assembly's structure (its
    instances' classes, profiles and options, its connections, what is recorded): the
    FMUs and the C descriptions of instances, couplings, columns and event groups.
    Built once and reused, so that a repeated run costs its C call and little else;
    only the start values are refilled per run (parameter studies change them)."""

    def __init__(self, instances, couplings, columns, groups, continuous=None, rows=None):
        """instances: (name, PreparedFmu, start keys); couplings: ordered assembly
        Couplings; columns: (instance index, variable); groups: (instance index, first
        indicator, count, outputs); continuous: per coupling, whether the evaluation
        between events needs it (liveness.continuous_couplings; None: all); rows: per
        coupling, whether the recorded columns need it (liveness.row_couplings; None:
        an output row sets what the evaluation between events does)."""
        self.lock = threading.Lock()  # a plan's start values are one run's at a time
        self.capped = True  # steps no longer than the output interval (step_limit_needed)
        self.rest_group = None  # eng_me_spec.rest_group (prepare.rest_groups); None: no rest
        self.grid = None  # ((stop time, step), buffers) of the last run (_buffers)
        self.member_lists = None  # a composite's start keys as (member, name): set_member_starts
        self.float_runs = None  # its Float64 keys by member (_runs_by_member), made at first use
        self.spec = None  # the MeSpec of the runs, its per-run fields set by each (run)
        self.spec_fields = None  # those fields as the last run set them
        self.stats = B.Stats()  # each run's, read before the next (the C zeroes it first)
        self.keep = keep = B.Keep()
        self.names = [n for n, _, _ in instances]
        self.fmus = [f for _, f, _ in instances]
        index = {n: i for i, n in enumerate(self.names)}
        self.start_keys, self.start_arrays = [], []
        specs = []
        for name, fmu, keys in instances:
            spec = B.instance_spec(keep, name, fmu, True, {k: 0 for k in keys})
            # the keys in the order typed_starts splits them: each list's values are
            # refilled per run in place (set_starts)
            lists = ([], [], [], [])
            for k in keys:
                lists[fmu.start_list(name, k)].append(k)
            f_values, i_values = np.zeros(max(1, len(lists[0]))), np.zeros(max(1, len(lists[1])),
                                                                           dtype=np.int32)
            t_values = np.zeros(max(1, len(lists[2])))
            spec.float_start_values = keep.numpy(f_values, C.c_double)
            spec.int_start_values = keep.numpy(i_values, C.c_int32)
            spec.typed_start_values = keep.numpy(t_values, C.c_double)
            self.start_keys.append(lists)
            self.start_arrays.append((f_values, i_values, t_values))
            specs.append(spec)
        self.specs = (B.InstanceSpec * len(specs))(*specs)
        self.string_keep = [B.Keep() for _ in specs]  # each instance's String starts, per run

        def variable(inst_name, var):
            return B.variable(self.fmus[index[inst_name]], inst_name, index[inst_name], var)

        self.n_couplings = len(couplings)
        self.couplings = (B.Coupling * max(1, len(couplings)))(*[
            B.Coupling(variable(*c.source), variable(*c.target), c.gain) for c in couplings])
        for c in self.couplings[:len(couplings)]:
            if B.needs_difference_jacobian(c.source, c.target):
                for i in (c.source.instance, c.target.instance):
                    self.specs[i].provides_directional_derivative = 0
        self.continuous = None if continuous is None else keep.array(
            C.c_int, [int(needed) for needed in continuous])
        self.rows = None if rows is None else keep.array(C.c_int, [int(needed) for needed in rows])
        self.indicator_start = self.indicator_coupling = None  # set_indicator_couplings
        self.loops = []  # set_loops
        self.time_function = None  # eng_me_spec.time_function (set_time_functions)
        self.from_time = []  # their names
        self.time_free = None  # eng_me_spec.time_free (set_time_functions)
        self.linear_map = None  # eng_me_spec.linear_map (set_time_functions)
        self.event_free = None  # eng_me_spec.event_free (set_event_free)
        self.linear = []  # their names
        self.deferred = [f"{'.'.join(c.source)} -> {'.'.join(c.target)}" for c, needed
                         in zip(couplings, continuous or []) if not needed]
        self.column_names = [f"{self.names[i]}.{v}" for i, v in columns]
        self.labels = self.column_names  # the result's column names (a composite's: its own)
        self.column_vars = [(self.fmus[i], v) for i, v in columns]
        self.string_columns = [k for k, (fmu, v) in enumerate(self.column_vars)
                               if fmu.variables[v][1] == STRING]
        # a run can leave String values in the engine's table only through an FMU that
        # has any (clearing it costs a short run a microsecond)
        self.strings = any(v[1] == STRING for fmu in self.fmus for v in fmu.variables.values())
        self.columns = (B.Variable * max(1, len(columns)))(*[
            variable(self.names[i], v) for i, v in columns])
        self.column_state = keep.array(C.c_int, [
            self.fmus[i].states.index(v) if v in self.fmus[i].states else -1
            for i, v in columns])
        self.groups = groups
        gs = []
        for i, first, count, outputs in groups:
            gs.append(B.EventGroup(i, first, count, len(outputs), keep.array(B.Variable, [
                B.variable(self.fmus[i], self.names[i], i, v) for v in outputs])))
        self.group_array = (B.EventGroup * max(1, len(gs)))(*gs)

    def set_starts(self, starts: list[dict]) -> None:
        """This run's parameters and start values, instance by instance."""
        for i, ((floats, ints, typed, strings), (f_values, i_values, t_values), values) in \
                enumerate(zip(self.start_keys, self.start_arrays, starts)):
            f_values[:len(floats)] = [values[k] for k in floats]
            if ints:  # (an empty slice's assignment costs a short run ~0.5 us)
                i_values[:len(ints)] = [int(values[k]) for k in ints]
            if typed:
                t_values[:len(typed)] = [values[k] for k in typed]
            if strings:
                self.string_keep[i] = keep = B.Keep()
                B.set_strings(keep, self.specs[i], [
                    (self.fmus[i].variable(self.names[i], k)[0], values[k]) for k in strings])

    def set_member_starts(self, components: dict) -> None:
        """A composite's run (one instance, its keys "member.name"): its parameters and
        start values read from the members' own, as set_starts([{"member.name": value}])
        but with no key built per run (that dict cost a short run ~5 us)."""
        floats, ints, typed, strings = self.member_lists
        if strings:  # a member's String: set_starts keeps what C points to
            self.set_starts([{f"{name}.{k}": v for name, c in components.items()
                              for k, v in {**c.values, **c.starts}.items()}])
            return
        merged = {name: {**c.values, **c.starts} for name, c in components.items()}
        f_values, i_values, t_values = self.start_arrays[0]
        if self.float_runs is None:
            self.float_runs = _runs_by_member(floats)
        for name, a, b, get in self.float_runs:  # a C loop per member, not a list per key
            f_values[a:b] = get(merged[name])
        if ints:
            i_values[:len(ints)] = [int(merged[name][k]) for name, k in ints]
        if typed:
            t_values[:len(typed)] = [merged[name][k] for name, k in typed]

    def _buffers(self, start_time, stop_time, step):
        """The output times, the buffers the C writes (rows, when each instance fell
        asleep, until when each was taken from time or as a linear map) and their
        addresses: kept for the next run of the same grid, since numpy's ctypes addresses
        cost microseconds each, as much as a short run's integration (the plan's lock
        makes the buffers one run's at a time)."""
        if self.grid is None or self.grid[0] != (start_time, stop_time, step):
            times = output_times(stop_time, step, start_time)
            check_output_values(len(times), len(self.column_names), "the output table")
            out = np.empty((len(times), len(self.column_names)))
            asleep, taken = np.empty(len(self.names)), np.empty(len(self.names))
            dp = C.POINTER(C.c_double)
            self.grid = ((start_time, stop_time, step), (times, out, asleep, taken, tuple(
                a.ctypes.data_as(dp) for a in (times, out, asleep, taken))))
        return self.grid[1]

    def set_rest_groups(self, groups: list[int]) -> None:
        if any(g >= 0 for g in groups):
            self.rest_group = self.keep.array(C.c_int, groups)

    def set_loops(self, assembly: str, loops: list[tuple[int, int, str]]) -> None:
        """eng_me_spec's algebraic loops (loops.loop_order): (first coupling, count, name).
        Newton moves Float64 scalars: a loop through another type is refused, named."""
        for first, count, name in loops:
            for c in self.couplings[first:first + count]:
                if not all(end.type == 0 and end.size <= 1 for end in (c.source, c.target)):
                    raise AssemblyError(f"assembly '{assembly}': algebraic loop {name}: a "
                                        "coupling of it is not a Float64 scalar, and the "
                                        "engine's me solves loops of Float64 scalars only")
        self.loops = loops
        self.loop_first = self.keep.array(C.c_int, [first for first, _, _ in loops])
        self.loop_count = self.keep.array(C.c_int, [count for _, count, _ in loops])
        self.loop_name = self.keep.array(C.c_char_p, [name.encode() for _, _, name in loops])

    def set_time_functions(self, flags: list[int], free: list[int], linear: list[int]) -> None:
        if any(flags):
            self.time_function = self.keep.array(C.c_int, flags)
            self.from_time = [n for n, f in zip(self.names, flags) if f]
        if any(free):
            self.time_free = self.keep.array(C.c_int, free)
        if any(linear):
            self.linear_map = self.keep.array(C.c_int, linear)
            self.linear = [n for n, f in zip(self.names, linear) if f]

    def set_event_free(self, flags: list[int]) -> None:
        if any(flags):
            self.event_free = self.keep.array(C.c_int, flags)

    def set_indicator_couplings(self, names: list[str], by_instance: dict) -> None:
        """eng_me_spec.indicator_start/_coupling from liveness.indicator_couplings."""
        starts, flat = [0], []
        for name in names:
            flat += by_instance.get(name, [])
            starts.append(len(flat))
        self.indicator_start = self.keep.array(C.c_int, starts)
        self.indicator_coupling = self.keep.array(C.c_int, flat)

    def run(self, name, stop_time, step, tolerance, method, progress, event_subsamples,
            scheme, jacobian="auto", start_time=0.0) -> tuple[dict, list, dict]:
        """One engine call: (columns, event rows per group, settings)."""
        lib = _engine()
        times, out, asleep, taken, pointers = self._buffers(start_time, stop_time, step)
        asleep.fill(np.inf)
        prog = B.Progress(progress)
        spec = self.spec
        if spec is None:  # what never changes between runs, once (a MeSpec costs ~3 us)
            spec = self.spec = B.MeSpec(
                len(self.names), self.specs, self.n_couplings, self.couplings,
                len(self.column_names), self.columns, len(self.groups), self.group_array,
                progress=prog.callback, rest_group=self.rest_group,
                continuous=self.continuous, column_state=self.column_state,
                row_coupling=self.rows, indicator_start=self.indicator_start,
                indicator_coupling=self.indicator_coupling, time_function=self.time_function,
                time_free=self.time_free, linear_map=self.linear_map,
                event_free=self.event_free)
            if self.loops:
                spec.n_loops, spec.loop_first, spec.loop_count, spec.loop_name = (
                    len(self.loops), self.loop_first, self.loop_count, self.loop_name)
        # the spec itself too: one made again (a changed plan) has none of them set
        fields = (spec, pointers, stop_time, tolerance, method, event_subsamples, jacobian, step)
        if fields != self.spec_fields:  # (a run of the same call sets none: ~1.5 us)
            spec.n_times, spec.times, spec.out, spec.asleep_since, spec.taken_until = (
                len(times), *pointers)
            spec.stop_time, spec.tolerance, spec.method = stop_time, tolerance, METHODS[method]
            spec.event_subsamples, spec.jacobian = event_subsamples, JACOBIANS[jacobian]
            spec.max_step = step if self.capped else 0.0
            self.spec_fields = fields
        stats = self.stats
        if self.strings:
            lib.eng_strings_clear()  # String values of this run only (c/engine.h)
        started = wallclock.perf_counter()
        with prog.sigint():
            run = lib.eng_simulate_me(C.byref(spec), C.byref(stats))
        wall = wallclock.perf_counter() - started
        try:
            events = [B.run_events(lib, run, g) for g in range(len(self.groups))] if run else []
        finally:
            lib.eng_run_free(run)
        prog.reraise()
        f = B.stats_numbers(stats)
        status = f.status
        message = stats.message.decode("utf-8", "replace") if status in (B.FAILED, B.TERMINATED) \
            else ""  # (only those two keep it)
        if status == B.FAILED:
            raise B.EngineError(f"assembly '{name}': {message}")
        note = stats.jacobian_note
        note = note.decode("utf-8", "replace") if note else ""
        if note:
            warnings.warn(f"assembly '{name}': {note}; the run takes finite differences "
                          "(jacobian='exact' insists, 'fd' skips the check)", JacobianFallback,
                          stacklevel=4)
        n = f.n_rows
        rows = out[:n].copy()  # the buffers serve the plan's next run
        table = {"time": times[:n].copy()}
        for k, column in enumerate(self.labels):
            table[column] = rows[:, k]
        for k in self.string_columns:  # string-table indices as the text they are
            fmu, var = self.column_vars[k]
            table[self.labels[k]] = B.typed_column(lib, fmu, var, rows[:, k])
        # the settings are made when first read (Result.settings): their dict costs a
        # short run ~5 us, and a parameter study's runs mostly never read them; what
        # they take from the plan's buffers is copied now, before its next run
        run_of = (start_time, stop_time, step, tolerance, scheme, method, wall, jacobian,
                  event_subsamples, f, message, note, asleep.tolist(), taken.tolist())
        return table, events, lambda: self._settings(*run_of)

    def _settings(self, start_time, stop_time, step, tolerance, scheme, method, wall, jacobian,
                  event_subsamples, f, message, note, asleep, taken) -> dict:
        """A run's settings (Result.settings) from what run kept of it."""
        by = f.terminated_by
        until = dict(zip(self.names, taken))
        return {
            "start_time": start_time, "stop_time": stop_time, "step": step,
            "tolerance": tolerance, "scheme": scheme,
            "method": method, "engine": "c", "wall_s": wall, "engine_s": wall,
            "steps": f.steps, "rejected": f.rejected, "events": f.events,
            "rhs_calls": f.rhs_calls, "jacobians": f.jacobians,
            "method_switches": f.method_switches,
            "explicit_method": EXPLICIT_METHODS.get(f.explicit_order),
            "jacobian_groups": f.jacobian_groups,
            "jacobian_evaluations": f.jacobian_evaluations,
            "jacobian_band": f.jacobian_band,
            "algebraic_loops": [name for _, _, name in self.loops],
            "loop_iterations": f.loop_iterations, "loop_matrices": f.loop_matrices,
            "event_instances": f.event_instances,
            "jacobian": "directional derivatives" if f.exact_jacobian
            else "finite differences",
            "jacobian_setting": jacobian, "jacobian_note": note or None,
            "at_rest_from": None if math.isinf(f.at_rest_from) else f.at_rest_from,
            "asleep": {n: t for n, t in zip(self.names, asleep) if math.isfinite(t)},
            "event_subsamples": event_subsamples, "interrupted": f.status == B.STOPPED,
            "event_location": "whole assembly" if self.indicator_start is None else "per instance",
            "set_at_events_only": list(self.deferred),
            # what the engine really took so (it refuses some and drops one whose read
            # fails at an event), not what was asked of it
            "evaluated_from_time": [n for n in self.from_time if not math.isnan(until[n])],
            "evaluated_as_linear_maps": [n for n in self.linear if not math.isnan(until[n])],
            "evaluated_until": {n: until[n] for n in self.from_time + self.linear
                                if math.isfinite(until[n])},
            "terminated": None if f.status != B.TERMINATED else
            {"instance": self.names[by] if by >= 0 else "", "time": f.t_end,
             "message": message}}


def _runs_by_member(keys: list[tuple[str, str]]) -> list[tuple[str, int, int, Callable]]:
    """(member, first, end, getter) for each run of consecutive (member, name) keys: the
    getter takes the member's values dict to the tuple of those names' values."""
    runs, a = [], 0
    for b in range(1, len(keys) + 1):
        if b == len(keys) or keys[b][0] != keys[a][0]:
            names = [k for _, k in keys[a:b]]
            get = itemgetter(*names) if len(names) > 1 else (lambda d, k=names[0]: (d[k],))
            runs.append((keys[a][0], a, b, get))
            a = b
    return runs


_plans: dict = {}


@functools.lru_cache(maxsize=None)
def _engine():
    lib = library()
    B.declare(lib)
    return lib


def indicators_follow_time(component) -> bool:
    """Is one of the component's event indicators written in terms of time? Then it can
    move while every state stands still. (A fact of its class, profile and options,
    kept in the recipe store: read without flattening once known.)"""
    return component_facts(class_defaults(component))["indicators_follow_time"]


def time_paths(component) -> dict:
    """Where time enters `component`'s model, for the step cap's question across couplings:
    {"indicators": (written in terms of time?, [the inputs they read]), "outputs":
    {name: (the same for that output, a state or a mode)}}. Dependencies are structural
    (CasADi's depends_on), as the joined model's would be. A fact of its class, profile
    and options, kept in the recipe store beside the FMU's facts (read without flattening
    once known)."""
    def paths(m):
        def reads(expr):
            return (bool(ca.depends_on(expr, m.t)),
                    [v.name for i, v in enumerate(m.inputs) if ca.depends_on(expr, m.u[i])])
        return {"indicators": reads(m.z) if m.z.numel() else (False, []),
                "outputs": {v.name: reads(m.y[i]) for i, v in enumerate(m.outputs)}}
    return _model_fact(component, "time_paths", paths)


def is_time_function(component) -> bool:
    """Are the component's states and outputs exact functions of time between events?
    Its state derivatives are constants (of parameters and modes), its outputs affine in
    the states and free of time and inputs, and it has no event indicators: a kinematic
    source such as ConstantSpeed (travel' = v, s = s0 + travel). The engine then reads
    its derivatives and each coupled output's value and rate at every event and takes
    the outputs from time in between, calling it no more (eng_me_spec.time_function).
    A fact of its class, profile and options, as time_paths."""
    def affine(m):
        moving = ca.vertcat(m.t, m.x, m.u)
        return bool(m.z.numel() == 0 and not ca.depends_on(m.xdot, moving)
                    and not ca.depends_on(m.y, ca.vertcat(m.t, m.u))
                    and not ca.depends_on(ca.jacobian(m.y, m.x), moving))
    return bool(_model_fact(component, "time_function", affine))


def is_event_free(component) -> bool:
    """Has an event nothing to update in the component when only its inputs change? No
    event indicators and no modes (discrete states): a spring, a mass, a kinematic
    source. Such a member whose continuous inputs an event changes is given them in
    continuous-time mode and not taken through event mode (eng_me_spec.event_free). A
    fact of its class, profile and options, as time_paths."""
    return bool(_model_fact(component, "event_free",
                            lambda m: m.z.numel() == 0 and m.q.numel() == 0))


def linear_outputs(component) -> list[str]:
    """The outputs of a component with no states, modes, indicators or time that are
    affine in its inputs with coefficients of the parameters only (a spring's forces, not
    its energy); none for any other component. Where every output an assembly couples
    is one, the member is a fixed linear map between events: the engine takes those
    outputs from their values and directional derivatives at the last event and the
    inputs' change since, calling it no more (eng_me_spec.linear_map). A fact of its
    class, profile and options, as time_paths."""
    def linear(m):
        if m.x.numel() or m.q.numel() or m.z.numel():
            return []
        moving = ca.vertcat(m.t, m.u)
        return [v.name for i, v in enumerate(m.outputs) if not ca.depends_on(m.y[i], m.t)
                and not ca.depends_on(ca.jacobian(m.y[i], m.u), moving)]
    return list(_model_fact(component, "linear_outputs", linear))


def is_linear_map(component, coupled: set) -> bool:
    """Every output of `component` in `coupled` is a linear one (linear_outputs)."""
    return bool(coupled) and coupled <= set(linear_outputs(component))


def _model_fact(component, name: str, compute: Callable):
    """compute(flat model) of the component's class, profile and options: kept in the
    recipe store beside the FMU's facts, so that it is read without flattening once
    known, and in memory for the process."""
    memo = _facts.get((name, binary_key(component)))
    if memo is not None:
        return memo
    defaults = class_defaults(component)
    key = fmu_recipe(defaults)
    known = recipes().get(key).get(name) if key is not None else None
    if known is None:
        known = compute(flatten(defaults))
        if key is not None:
            recipes().update(key, **{name: known})
    _facts[(name, binary_key(component))] = known
    return known


_facts: dict = {}


def evaluated_members(assembly: Assembly, fmus: dict, columns: list, couplings,
                      linear: bool, cosim: bool = False) -> list[int]:
    """eng_me_spec.time_function (is_time_function) or, with `linear`, .linear_map
    (is_linear_map, on the outputs `couplings` read) per instance: ours, with the
    directional derivatives that give each coupled output's rate, no step end to be told
    of, and, for a time function, no recorded column (a column reads the instance, which
    is not called between events; a linear map's inputs are set before a row instead).
    `cosim`: the same for the co-simulation master (eng_cosim_spec), through the FMUs'
    Co-Simulation interface, which has no step end to tell."""
    recorded = {name for name, _ in columns}
    read = {name: set() for name in fmus}
    for c in couplings:
        read[c.source[0]].add(c.source[1])
    flags = []
    for name, comp in assembly.components.items():
        fmu = fmus[name]
        flags.append(int(isinstance(comp, Component) and (linear or name not in recorded)
                         and fmu.n_event_indicators == 0
                         and (fmu.provides_directional_derivative if cosim
                              else fmu.completed_step_not_needed and fmu.me_directional_derivative)
                         and len(fmu.states) == len(fmu.derivatives) == fmu.n_states
                         and (is_linear_map(comp, read[name]) if linear
                              else is_time_function(comp))))
    return flags


def step_limit_needed(assembly: Assembly) -> bool:
    """Can an event indicator move while every state stands still? Then a step that grows
    long while a contact sticks could carry an excursion of the indicator between its
    samples (a shaken table's acceleration moving the static margin), and steps are
    capped at the output interval. Across couplings an indicator moves alone when time
    reaches it: written in terms of time, or reading an input whose source output is
    (a driver's motion, a shaking), directly or through further couplings. Followed on
    each member kind's time_paths over the couplings, in time linear in the assembly
    (joining the members to ask the joined model cost minutes at a thousand instances);
    a structural path is a dependency the joined model has too, short of a cancellation.
    An FMU we did not generate cannot tell: capped."""
    components = assembly.components
    if not all(isinstance(c, Component) for c in components.values()):
        return True
    if len(components) == 1 and not assembly.connections:
        return indicators_follow_time(next(iter(components.values())))
    feeds = {c.target: c.source for c in assembly.couplings()}
    paths = {name: time_paths(comp) for name, comp in components.items()}
    # depth-first over (instance, variable), a loop with its own stack: a long chain's
    # couplings would nest one frame per instance
    todo, seen = [], set()
    for name, p in paths.items():
        follows, inputs = p["indicators"]
        if follows:
            return True
        todo += [(name, u) for u in inputs]
    while todo:
        node = todo.pop()
        if node in seen:
            continue
        seen.add(node)
        if node in feeds:  # a fed input: its source's value
            todo.append(feeds[node])
            continue
        name, var = node
        follows, inputs = paths[name]["outputs"].get(var, (False, []))  # a state, a mode
        if follows:
            return True
        todo += [(name, u) for u in inputs]
    return False


def _plan(key, build) -> _Plan:
    plan = _plans.get(key)
    if plan is None:
        plan = _plans[key] = build()
    return plan


def _check(stop_time, step, tolerance, method, start_time, jacobian="auto"):
    check_experiment(stop_time, step, tolerance, "output step", start_time)
    if method is not None and method not in METHODS:
        raise AssemblyError(f"method must be one of {', '.join(METHODS)}, not '{method}'")
    if jacobian not in JACOBIANS:
        raise AssemblyError(f"jacobian must be one of {', '.join(JACOBIANS)}, not {jacobian!r}")


def _check_exact(jacobian, plan: _Plan) -> None:
    """jacobian='exact' where an instance the Jacobian passes through (states, or a Real
    coupling) has no directional derivatives: named (c/jacobian.c's eng_jacobian_plan)."""
    if jacobian != "exact":
        return
    coupled = {end.instance for c in plan.couplings[:plan.n_couplings]
               for end in (c.source, c.target)
               if c.source.type == c.target.type == 0 and c.source.size <= 1 >= c.target.size}
    for i, (name, fmu) in enumerate(zip(plan.names, plan.fmus)):
        if (fmu.n_states or i in coupled) and not (
                fmu.me_directional_derivative
                and len(fmu.states) == len(fmu.derivatives) == fmu.n_states):
            raise AssemblyError(f"jacobian='exact': {name}'s FMU gives no directional "
                                "derivatives; 'auto' or 'fd' take differences")


def integrator(assembly: Assembly, method: str | None) -> str:
    """The one integrator for every instance: `method` where given; else what the
    instances' `solver` settings ask (one that needs the implicit method gets it for
    all, since a stiff member makes the joined system stiff); else "auto"."""
    if method is not None:
        return method
    asked = {getattr(c, "solver", None) for c in assembly.components.values()} - {None}
    if 1 in asked:
        return "RODAS3"
    return SOLVER_METHODS[asked.pop()] if len(asked) == 1 else "auto"


def simulate_me(assembly: Assembly, stop_time: float, step: float, tolerance: float = 1e-8,
                record: list[str] | None = None, method: str | None = None,
                progress: Callable[[float], None] | None = None,
                event_subsamples: int = EVENT_SUBSAMPLES, fmi_version: int = 3,
                jacobian: str = "auto", start_time: float = 0.0, inputs=None) -> Result:
    """Integrate `assembly` as Model Exchange FMUs in the engine; a row every `step` s.

    Same result as :func:`assemblies.masters.me.simulate_me`. `event_subsamples`:
    interior points of each step where the indicators are sampled, so that one
    crossing twice inside a step is found (0: step ends only). `jacobian`: see
    :data:`JACOBIANS` (a fallback warns with :class:`JacobianFallback`). The run starts
    at `start_time`; `inputs`, a table feeding open inputs (:mod:`assemblies.inputs`).
    Many runs of one assembly: :func:`prepare_me` checks and looks up once.
    """
    return prepare_me(assembly, stop_time, step, tolerance, record, method, progress,
                      event_subsamples, fmi_version, jacobian, start_time, inputs)()


def prepare_me(assembly: Assembly, stop_time: float, step: float, tolerance: float = 1e-8,
               record: list[str] | None = None, method: str | None = None,
               progress: Callable[[float], None] | None = None,
               event_subsamples: int = EVENT_SUBSAMPLES, fmi_version: int = 3,
               jacobian: str = "auto", start_time: float = 0.0,
               inputs=None) -> Callable[[], Result]:
    """:func:`simulate_me` in two halves: this call checks the arguments, builds or looks
    up the FMUs and the engine's plan; each call of what it returns runs once, with the
    parameters and start values the instances have then (a parameter study changes
    them between calls), and gives the Result simulate_me would. What the assembly is
    made of (its instances, their classes, options and connections) is taken as it is
    now: after a change of those, prepare again. A repeated run then costs its C call
    and little else (stick_slip: about 20 us of Python less per call than simulate_me).
    """
    _check(stop_time, step, tolerance, method, start_time, jacobian)
    assembly = with_inputs(assembly, inputs)
    check_mode(assembly, "me")  # a Co-Simulation-only FMU: named, with the modes that apply
    started = wallclock.perf_counter()

    def build():
        couplings = assembly.couplings()  # resolves the causality profiles
        fmus = {name: prepared(comp, fmi_version) for name, comp in assembly.components.items()}
        for name, fmu in fmus.items():
            if fmu.me_identifier is None:
                raise AssemblyError(f"{name}: its FMU has no Model Exchange interface")
        names = list(fmus)
        recorded = record_columns(fmus, record)
        columns = [(names.index(i), v) for i, v in recorded]
        groups = [(i, 0, fmus[n].n_event_indicators, fmus[n].outputs)
                  for i, n in enumerate(names) if fmus[n].n_event_indicators]
        # every value set before initialisation (a foreign FMU's Strings too)
        keys = [(n, fmus[n], [*c.fmu_starts()]) for n, c in assembly.components.items()]
        # an algebraic loop's couplings together, solved by Newton at each evaluation
        ordered, loops = loop_order(couplings, fmus)
        plan = _Plan(keys, ordered, columns, groups, continuous_couplings(fmus, ordered, recorded),
                     row_couplings(fmus, ordered, recorded))
        plan.set_loops(assembly.name, loops)
        if sum(1 for f in fmus.values() if f.n_event_indicators) >= LOCAL_EVENTS_FROM:
            plan.set_indicator_couplings(names, indicator_couplings(fmus, ordered))
        plan.capped = step_limit_needed(assembly)
        plan.set_rest_groups(rest_groups(names, couplings, fmus))
        # a loop's Newton solve sets and reads its members itself: none is a linear map
        # (me.c allocate_linear drops them too; this keeps settings to what runs)
        in_loops = {end[0] for first, count, _ in loops for c in ordered[first:first + count]
                    for end in (c.source, c.target)}
        linear = [flag and name not in in_loops for flag, name in
                  zip(evaluated_members(assembly, fmus, recorded, ordered, True), names)]
        plan.set_time_functions(evaluated_members(assembly, fmus, recorded, ordered, False),
                                [int(f.autonomous and f.n_states == 0) for f in fmus.values()],
                                [int(flag) for flag in linear])
        plan.set_event_free([int(isinstance(comp, Component) and fmus[name].n_event_indicators == 0
                                 and is_event_free(comp))
                             for name, comp in assembly.components.items()])
        return plan

    # the names set before initialisation shape the plan's start lists: an instance given
    # `solver` in one run and not in the next needs a plan of its own
    starts = tuple(tuple(c.fmu_starts()) for c in assembly.components.values())
    key = ("me", structure_key(assembly), None if record is None else tuple(record), fmi_version,
           starts)
    plan = _plan(key, build)
    _check_exact(jacobian, plan)
    _engine()  # compiled on a machine's first run: setup, like the FMUs
    # the run's wall time leaves out building and loading the FMUs (seconds once, then cached)
    setup_s = wallclock.perf_counter() - started
    components = assembly.components

    def run() -> Result:
        started = wallclock.perf_counter()
        with plan.lock:
            plan.set_starts([c.fmu_starts() for c in components.values()])
            table, events, described = plan.run(assembly.name, stop_time, step, tolerance,
                                                integrator(assembly, method), progress,
                                                event_subsamples, "me", jacobian, start_time)
        tables = {plan.names[i]: Table({name: B.typed_column(_engine(), plan.fmus[i], v,
                                                             rows[:, j])
                                        for j, (name, v) in enumerate(
                                            [("time", None)]
                                            + [(f"{plan.names[i]}.{v}", v) for v in outputs])})
                  for (i, _, _, outputs), rows in zip(plan.groups, events) if len(rows)}
        wall = wallclock.perf_counter() - started
        return Result.of_columns(table, tables, lambda: dict(described(), wall_s=wall,
                                                               setup_s=setup_s))
    return run


def simulate_monolithic(assembly: Assembly, stop_time: float, step: float,
                        tolerance: float = 1e-10, record: list[str] | None = None,
                        method: str | None = None,
                        progress: Callable[[float], None] | None = None,
                        event_subsamples: int = EVENT_SUBSAMPLES,
                        jacobian: str = "auto", start_time: float = 0.0,
                        inputs=None) -> Result:
    """The assembly joined into one composite FMU, run by the engine as a single FMU.

    Same result as :func:`assemblies.masters.monolithic.simulate_monolithic`; each
    member's events are told apart by the composite's indicators that member owns.
    `jacobian`, `start_time` and `inputs`: as for :func:`simulate_me`. Many runs of
    one assembly: :func:`prepare_monolithic` checks and looks up once.
    """
    return prepare_monolithic(assembly, stop_time, step, tolerance, record, method, progress,
                              event_subsamples, jacobian, start_time, inputs)()


def prepare_monolithic(assembly: Assembly, stop_time: float, step: float,
                       tolerance: float = 1e-10, record: list[str] | None = None,
                       method: str | None = None,
                       progress: Callable[[float], None] | None = None,
                       event_subsamples: int = EVENT_SUBSAMPLES, jacobian: str = "auto",
                       start_time: float = 0.0, inputs=None) -> Callable[[], Result]:
    """:func:`simulate_monolithic` in two halves, as :func:`prepare_me`: the checks,
    the composite FMU and the plan now; each call of what it returns runs once with the
    members' parameters and start values of then, and gives simulate_monolithic's
    Result. After a change of what the assembly is made of, prepare again."""
    _check(stop_time, step, tolerance, method, start_time, jacobian)
    assembly = with_inputs(assembly, inputs)
    check_mode(assembly, "monolithic")  # a foreign FMU has no equations to join
    started = wallclock.perf_counter()

    def build():
        joined, fmu = prepared_composite(assembly)
        if record is None:
            columns = [(0, f"{name}.{v}") for name, vs in joined.outputs.items() for v in vs
                       if f"{name}.{v}" in fmu.variables]
        else:
            for ref in record:
                if ref not in fmu.variables:
                    instance = ref.partition(".")[0]
                    known = [n for n in fmu.variables if n.startswith(instance + ".")]
                    raise AssemblyError(f"cannot record '{ref}': the joined model has no such "
                                        f"variable; {instance} has: "
                                        f"{', '.join(known) or '(no instance of that name)'}")
            columns = [(0, ref) for ref in record]
        groups, members = [], []
        for name in assembly.components:
            owned = [i for i, owner in enumerate(joined.owner_of_indicator) if owner == name]
            if not owned:
                continue
            if owned != list(range(owned[0], owned[-1] + 1)):
                raise AssemblyError(f"{name}: its indicators are not contiguous in the composite")
            groups.append((0, owned[0], len(owned),
                           [v for v in fmu.outputs if v.startswith(f"{name}.")]))
            members.append(name)
        member_key = {f"{name}.{k}": (name, k) for name, c in assembly.components.items()
                      for k in [*c.values, *c.starts]}
        plan = _Plan([("assembly", fmu, list(member_key))], [], columns, groups)
        plan.member_lists = [[member_key[k] for k in keys] for keys in plan.start_keys[0]]
        plan.set_rest_groups(rest_groups(["assembly"], [], {"assembly": fmu}))
        plan.members = members
        plan.layout = joined
        plan.capped = joined.indicators_follow_time
        plan.labels = [ref for _, ref in columns]  # the members' names, not "assembly.<ref>"
        return plan

    key = ("monolithic", structure_key(assembly), None if record is None else tuple(record))
    plan = _plan(key, build)
    _check_exact(jacobian, plan)
    _engine()  # compiled on a machine's first run: setup, like the FMUs
    # the run's wall time leaves out building and loading the FMUs (seconds once, then cached)
    setup_s = wallclock.perf_counter() - started
    components = assembly.components

    def run() -> Result:
        started = wallclock.perf_counter()
        with plan.lock:
            plan.set_member_starts(components)
            table, events, described = plan.run(assembly.name, stop_time, step, tolerance,
                                                integrator(assembly, method), progress,
                                                event_subsamples, "monolithic", jacobian,
                                                start_time)
        tables = {member: Table.from_array(["time"] + outputs, rows)
                  for member, (_, _, _, outputs), rows in zip(plan.members, plan.groups, events)
                  if len(rows)}
        wall = wallclock.perf_counter() - started

        def settings():
            s = described()
            s["terminated"] = member_termination(s["terminated"], plan.layout.terminate,
                                                 "assembly")
            return dict(s, wall_s=wall, setup_s=setup_s)
        return Result.of_columns(table, tables, settings)
    return run
