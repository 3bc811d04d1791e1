"""The co-simulation master: FMI 3 Co-Simulation FMUs driven through fmpy.

Communication steps are fixed, or adaptive (step doubling from saved FMU states,
rollback on rejection: :mod:`assemblies.adaptive`). Sweeps are Jacobi (default) or
Gauss–Seidel. Inputs set at a communication point are, for the FMU, values at that
point: our FMUs extrapolate kinematic inputs over the step through their derivative
inputs (s with v and a), which is why Jacobi is the accurate default for kinematic
chains; inputs at the end of such a chain and inputs with no derivative input (forces,
signals) are held constant by the FMU, and the master chooses that constant from the
source's past values (:mod:`assemblies.extrapolation`). At every communication point
the inputs are made consistent with the outputs, algebraic loops between
direct-feedthrough outputs included (:mod:`assemblies.loops`). Events that an FMU
locates inside a step are recorded through FMI 3 intermediate update.
"""
from __future__ import annotations

import math
import time as wallclock
from typing import Callable

from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi3 import FMU3Slave

import numpy as np

from components.dae import flatten
from fmus import build_fmu

from ..assembly import Assembly, AssemblyError
from ..experiment import check_cosim_settings, check_experiment
from ..result import Result, Table
from .adaptive import StepController
from .extrapolation import step_mean
from .loops import LoopError, coupling_groups, is_loop, solve_loop


class SimulationError(RuntimeError):
    """An FMU refused a call; the message carries what the FMU logged."""


class _Instance:
    """One FMU instance in a running co-simulation."""

    def __init__(self, name: str, component, tolerance: float):
        path, md = self._load(name, component)
        self.states = [u.variable.derivative.name for u in md.derivatives]
        # inputs the FMU extrapolates itself (they have a derivative input: s by v, v by a);
        # the model description does not say so, the flattened component does
        self.chained = {v.name for v in flatten(component).inputs if v.derivative_input is not None}
        self._unzipped = extract(path)
        self.fmu = FMU3Slave(guid=md.guid, unzipDirectory=self._unzipped,
                             modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        self.fmu.instantiate(loggingOn=False, logMessage=self._log,
                             intermediateUpdate=self._intermediate_update)
        self.tolerance = tolerance

    def _load(self, name: str, component):
        """Build (or fetch) the FMU and read what a master needs from its description.

        Built with the class defaults, so parameter studies reuse one compiled FMU; the
        instance's own values are set as start values.
        """
        self.name, self.component = name, component
        defaults = type(component)(name=name, profile=component.profile.name,
                                   **component.option_values)
        path = build_fmu(defaults)
        md = read_model_description(path)
        self.variables = {v.name: v for v in md.modelVariables}
        self.outputs = [v.name for v in md.modelVariables if v.causality == "output"]
        self.inputs = [v.name for v in md.modelVariables if v.causality == "input"]
        # output -> the inputs it depends on (direct feedthrough: algebraic loops, and the
        # order in which a master must set inputs); no list in the XML means all of them
        self.depends = {u.variable.name: (set(self.inputs) if u.dependencies is None else
                                          {d.name for d in u.dependencies if d.causality == "input"})
                        for u in md.outputs}
        self.messages: list[str] = []
        self.event_rows: list[list[float]] = []
        return path, md

    # callbacks from C: keep them short and never raise
    def _log(self, env, status, category, message):
        text = message.decode("utf-8", "replace") if isinstance(message, bytes) else str(message)
        self.messages.append(text)

    def _intermediate_update(self, env, t, set_requested, get_allowed, step_finished,
                             can_return_early, early_return_requested, last_successful_time):
        early_return_requested[0] = False
        if get_allowed and not step_finished:  # an event inside the step
            try:
                self.event_rows.append([t] + self.get(self.outputs))
            except Exception as exc:  # pragma: no cover - reported after the step
                self.messages.append(f"recording the event at t = {t}: {exc}")

    def call(self, what: str, fn, *args):
        try:
            return fn(*args)
        except FMICallException as exc:
            logged = "; ".join(self.messages[-3:]) or str(exc)
            raise SimulationError(f"{self.name}: {what} failed: {logged}") from None

    def vr(self, name: str):
        if name not in self.variables:
            raise AssemblyError(f"{self.name} has no variable '{name}'")
        return self.variables[name]

    def get(self, names: list[str]) -> list[float]:
        """Values of `names`, with one FMI call per variable type (ctypes calls are slow)."""
        values = [0.0] * len(names)
        for type_name, getter in (("Float64", self.fmu.getFloat64), ("Int32", self.fmu.getInt32)):
            picked = [(i, self.vr(n).valueReference) for i, n in enumerate(names)
                      if (self.vr(n).type == "Int32") == (type_name == "Int32")]
            if picked:
                got = self.call(f"get {type_name} outputs", getter, [vr for _, vr in picked])
                for (i, _), value in zip(picked, got):
                    values[i] = float(value)
        return values

    def set(self, name: str, value: float) -> None:
        v = self.vr(name)
        if v.type == "Int32":
            self.call(f"set {name}", self.fmu.setInt32, [v.valueReference], [int(value)])
        else:
            self.call(f"set {name} = {value}", self.fmu.setFloat64, [v.valueReference], [float(value)])

    def partial(self, output: str, input_: str) -> float:
        """d output / d input at the current point (fmi3GetDirectionalDerivative)."""
        return self.call(f"directional derivative d{output}/d{input_}",
                         self.fmu.getDirectionalDerivative,
                         [self.vr(output).valueReference], [self.vr(input_).valueReference], [1.0])[0]

    def save(self):
        return self.call("getFMUState", self.fmu.getFMUState)

    def restore(self, state) -> None:
        self.call("setFMUState", self.fmu.setFMUState, state)

    def discard(self, state) -> None:
        self.call("freeFMUState", self.fmu.freeFMUState, state)

    def free(self) -> None:
        try:
            self.fmu.terminate()
        except Exception:
            pass
        try:
            self.fmu.freeInstance()
        except Exception:
            pass


class _Master:
    """The coupling state of a running co-simulation: consistency, extrapolation, rollback."""

    def __init__(self, assembly_name, instances, couplings, sweep_order, scheme, extrapolation,
                 loop_tolerance, max_loop_iterations, newton):
        self.instances, self.couplings = instances, couplings
        self.sweep_order, self.scheme, self.extrapolation = sweep_order, scheme, extrapolation
        self.loop_options = dict(tolerance=loop_tolerance, max_iterations=max_loop_iterations,
                                 newton=newton)
        depends = {n: i.depends for n, i in instances.items()}
        inputs = {n: i.inputs for n, i in instances.items()}
        self.groups = coupling_groups(couplings, depends, inputs)
        self.loops = [g for g in self.groups if is_loop(g, couplings, depends, inputs)]
        self.in_loop = {i for g in self.loops for i in g}
        # the inputs the FMU holds constant over a step: the master picks the constant
        self.held = {i for i, c in enumerate(couplings)
                     if c.target[1] not in instances[c.target[0]].chained
                     and instances[c.target[0]].vr(c.target[1]).type == "Float64"}
        self.history: dict[int, list[tuple[float, float]]] = {i: [] for i in self.held}
        self.terminated = None
        self.do_steps = 0
        self.loop_iterations = 0
        self.loop_residual = 0.0

    def _get(self, inst, var):
        return self.instances[inst].get([var])[0]

    def _set(self, inst, var, value):
        self.instances[inst].set(var, value)

    def consistent(self, t: float) -> None:
        """Set every input to its source's output at `t`, solving algebraic loops."""
        for group in self.groups:
            if group in self.loops:
                try:
                    its, res = solve_loop(group, self.couplings, self._get, self._set, self._get,
                                          lambda i, o, u: self.instances[i].partial(o, u),
                                          **self.loop_options)
                except LoopError as exc:
                    raise SimulationError(f"at t = {t:g}: {exc}") from None
                self.loop_iterations += its
                self.loop_residual = max(self.loop_residual, res)
            else:
                c = self.couplings[group[0]]
                self._set(*c.target, c.gain * self._get(*c.source))
        for i in self.held:
            value = self._get(*self.couplings[i].target)
            points = [p for p in self.history[i] if p[0] < t - 1e-12 * max(1.0, abs(t))]
            self.history[i] = (points + [(t, value)])[-3:]

    def _held_value(self, i: int, t: float, h: float, t_source: float, now: float) -> float:
        """The constant for held input `i` over [t, t + h]; `now` is its source's value at
        `t_source` (t, or t + h where Gauss–Seidel stepped the source already)."""
        if self.extrapolation == 0 and t_source == t:
            return now
        eps = 1e-12 * max(1.0, abs(t_source))
        points = [p for p in self.history[i] if p[0] < t_source - eps] + [(t_source, now)]
        return step_mean(points, t, h, self.extrapolation)

    def _do_step(self, name: str, t: float, h: float) -> None:
        inst = self.instances[name]
        self.do_steps += 1
        _, stop, _, reached = inst.call(f"doStep at t = {t:g}", inst.fmu.doStep, t, h)
        if stop and self.terminated is None:  # the model says it cannot go on (why: in its log)
            self.terminated = {"instance": name, "time": reached,
                               "message": inst.messages[-1] if inst.messages else ""}

    def step(self, t: float, h: float) -> None:
        """One communication step from `t` (inputs consistent at t) to t + h."""
        if self.scheme == "jacobi":
            if self.extrapolation:
                for i in self.held:
                    c = self.couplings[i]
                    self._set(*c.target, self._held_value(i, t, h, t, self.history[i][-1][1]))
            for name in self.instances:
                self._do_step(name, t, h)
        else:
            done = set()
            for name in self.sweep_order:
                for i, c in enumerate(self.couplings):
                    if c.target[0] != name:
                        continue
                    ahead = c.source[0] in done
                    if i in self.in_loop and not (i in self.held and self.extrapolation):
                        continue  # keeps the loop's consistent value from t
                    now = c.gain * self._get(*c.source) if (ahead or i not in self.in_loop) \
                        else self.history[i][-1][1]
                    value = self._held_value(i, t, h, t + h if ahead else t, now) \
                        if i in self.held else now
                    self._set(*c.target, value)
                self._do_step(name, t, h)
                done.add(name)
        if self.terminated is None:
            self.consistent(t + h)

    def state_vector(self) -> np.ndarray:
        return np.array([v for inst in self.instances.values() for v in inst.get(inst.states)])

    # --- rollback for the adaptive step -------------------------------------------
    def save(self):
        return ({n: i.save() for n, i in self.instances.items()},
                {k: list(v) for k, v in self.history.items()},
                {n: len(i.event_rows) for n, i in self.instances.items()}, self.terminated)

    def restore(self, snap) -> None:
        states, history, n_events, terminated = snap
        for name, inst in self.instances.items():
            inst.restore(states[name])
            del inst.event_rows[n_events[name]:]  # events of a step that did not count
        self.history = {k: list(v) for k, v in history.items()}
        self.terminated = terminated

    def discard(self, snap) -> None:
        for name, inst in self.instances.items():
            inst.discard(snap[0][name])


def cosimulate(assembly: Assembly, stop_time: float, step: float, tolerance: float = 1e-8,
               record: list[str] | None = None, scheme: str = "jacobi",
               progress: Callable[[float], None] | None = None, extrapolation: int = 0,
               adaptive: bool = False, tol: float = 1e-4, loop_tolerance: float = 1e-10,
               max_loop_iterations: int = 20, newton: bool = True) -> Result:
    """Co-simulate `assembly` from 0 to `stop_time`.

    `step` is the communication step; with ``adaptive=True`` it is the output interval
    and the largest step, and steps are chosen so that the estimated global error of
    the FMUs' states stays near `tol` (absolute, :mod:`assemblies.adaptive`).
    `tolerance` is the FMUs' own solver tolerance. `extrapolation` (0, 1, 2) is the
    order of the polynomial whose step mean is held on inputs the FMUs hold constant
    (:mod:`assemblies.extrapolation`). Algebraic loops are solved at every
    communication point to `loop_tolerance` in at most `max_loop_iterations` Newton
    iterations (plain fixed-point iteration with ``newton=False``).
    """
    check_experiment(stop_time, step, tolerance)
    check_cosim_settings(scheme, extrapolation, adaptive, tol)
    couplings = assembly.couplings()
    instances: dict[str, _Instance] = {}
    started = wallclock.perf_counter()
    try:
        for name, comp in assembly.components.items():
            instances[name] = _Instance(name, comp, tolerance)
        columns = _record_columns(instances, record)
        master = _Master(assembly.name, instances, couplings, assembly.order(), scheme,
                         extrapolation, loop_tolerance, max_loop_iterations, newton)

        def sample(t):
            row = {}
            for name in instances:
                wanted = [v for i, v in columns if i == name]
                row.update(zip(((name, v) for v in wanted), instances[name].get(wanted)))
            return [t] + [row[c] for c in columns]

        for inst in instances.values():
            comp = inst.component
            for key, value in {**comp.values, **comp.starts}.items():
                inst.set(key, value)
            inst.call("enter initialization", inst.fmu.enterInitializationMode, tolerance, 0.0, stop_time)
        master.consistent(0.0)
        for inst in instances.values():
            inst.call("exit initialization", inst.fmu.exitInitializationMode)
        master.consistent(0.0)
        rows = [sample(0.0)]
        n_out = max(1, math.ceil(stop_time / step - 1e-9))
        out_times = [min((k + 1) * step, stop_time) for k in range(n_out)]
        out_times[-1] = stop_time
        stats = {"steps": 0, "rejected": 0}
        if not adaptive:
            t = 0.0
            for t_next in out_times:
                master.step(t, t_next - t)
                stats["steps"] += 1
                rows.append(sample(t_next))
                if progress is not None:
                    progress(t_next)
                t = t_next
                if master.terminated is not None:
                    break
        else:
            stats.update(_adaptive(master, out_times, step, tol, extrapolation, rows, sample,
                                   progress))
        names = ["time"] + [f"{i}.{v}" for i, v in columns]
        table = Table.from_rows(names, rows)
        events = {name: Table.from_rows(["time"] + [f"{name}.{v}" for v in inst.outputs],
                                        inst.event_rows)
                  for name, inst in instances.items() if inst.event_rows}
        settings = {"stop_time": stop_time, "step": step, "tolerance": tolerance, "scheme": scheme,
                    "extrapolation": extrapolation, "adaptive": bool(adaptive),
                    "wall_s": wallclock.perf_counter() - started,
                    "terminated": master.terminated, "do_steps": master.do_steps, **stats,
                    "loops": [" -> ".join(".".join(couplings[i].source) for i in g)
                              for g in master.loops],
                    "loop_iterations": master.loop_iterations,
                    "loop_residual": master.loop_residual}
        if adaptive:
            settings["tol"] = tol
        return Result({n: table[n] for n in names}, events, settings)
    finally:
        for inst in instances.values():
            inst.free()


def _adaptive(master: _Master, out_times, step, tol, extrapolation, rows, sample, progress):
    """Step doubling with rollback through FMU state; rows are appended at `out_times`."""
    # global order of the coupling: 1 with a zero-order hold, 2 with a step-mean
    # extrapolation (see assemblies.extrapolation for why not 3 with quadratic)
    ctrl = StepController(tol, 1 if extrapolation == 0 else 2, out_times[-1], step)
    t, h = 0.0, step / 4
    h_used = []
    for target in out_times:
        while t < target - 1e-12 * max(1.0, target):
            if target - (t + h) < 0.25 * h:  # no sliver before an output point
                h = target - t
            snap = master.save()
            try:
                master.step(t, h)
                coarse = master.state_vector()
                master.restore(snap)
                master.step(t, h / 2)
                if master.terminated is None:
                    master.step(t + h / 2, h / 2)
                if master.terminated is not None:  # the model ended the run: keep what it did
                    t = master.terminated["time"]
                    break
                error = ctrl.estimate(coarse, master.state_vector())
                ok, h_next = ctrl.judge(error, h)
                if ok:
                    t = target if abs(target - (t + h)) < 1e-12 * max(1.0, target) else t + h
                    h_used.append(h)
                else:
                    master.restore(snap)
            finally:
                master.discard(snap)
            h = h_next
            if h < ctrl.h_min:
                raise SimulationError(f"adaptive step fell below {ctrl.h_min:.3g} s at t = {t:g} "
                                      f"(tol {tol:g} cannot be met)")
        rows.append(sample(t))
        if progress is not None:
            progress(t)
        if master.terminated is not None:
            break
    return {"steps": ctrl.accepted, "rejected": ctrl.rejected,
            "h_min": min(h_used, default=math.nan), "h_max": max(h_used, default=math.nan),
            "error_ratio_max": ctrl.max_ratio}


def _record_columns(instances: dict[str, _Instance], record: list[str] | None):
    if record is None:
        return [(name, v) for name, inst in instances.items() for v in inst.outputs]
    columns = []
    for ref in record:
        instance, _, var = ref.partition(".")
        if instance not in instances:
            raise AssemblyError(f"cannot record '{ref}': no instance '{instance}'; "
                                f"instances: {', '.join(instances)}")
        instances[instance].vr(var)
        columns.append((instance, var))
    return columns


__all__ = ["SimulationError", "cosimulate"]
