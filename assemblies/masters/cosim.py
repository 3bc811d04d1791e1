"""The co-simulation master: Co-Simulation FMUs driven through fmpy.

Our components run as FMI 3 FMUs rebuilt from them; a foreign FMU
(:class:`assemblies.foreign.FMU`, FMI 2.0 or 3.0 Co-Simulation) runs from its file, so
this master is the reference for assemblies with foreign members too (an FMI 2 FMU
reports no events inside a step: there is no intermediate update in FMI 2).

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
locates inside a step are recorded through FMI 3 intermediate update; with event
synchronisation (on by default with adaptive steps) a step is retaken to end at the
first such event, and an event an FMU handles at the start of a step is moved back to
where the coupled system crossed (:mod:`assemblies.masters.events`). The stepping is
the compiled engine's (assemblies/engine/c/cosim.c), so that the two give the same
results.
"""
from __future__ import annotations

import math
import struct
import time as wallclock
import warnings
import weakref
from ctypes import byref
from dataclasses import dataclass
from typing import Callable

from fmpy import calloc, extract, free, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (FMU2Slave, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                       fmi2CallbackFunctions, fmi2CallbackLoggerTYPE, fmi2Discard,
                       fmi2LastSuccessfulTime, fmi2Terminated, printLogMessage)
from fmpy.fmi3 import FMU3Slave, fmi3Boolean, fmi3Discard, fmi3Float64
from fmpy.logging import addLoggerProxy

import numpy as np

from components.errors import SimulationError
from fmus import build_fmu

from ..assembly import Assembly, AssemblyError
from ..value_types import CONTINUOUS, canonical
from ..experiment import (FixedStepFallback, check_cosim_settings, check_experiment,
                          fixed_step_fallback, output_times, restore_mismatch)
from ..foreign import FMU, check_mode
from ..inputs import with_inputs
from ..result import Result, Table
from .adaptive import (COAST_GUARDED, COAST_KEEP, COAST_MAX, COAST_STEADY, COAST_STEPS,
                       ORDER_MAX, StepController, cells, defect_allowance)
from .events import (EVENT_TOL, MAX_SETTLE_STEPS, earliest_event_in_step, events_at_start,
                     fires_at_start, locate_start_event, probe_step)
from .extrapolation import (RATES, chain_order, derivative_couplings, derivative_inputs,
                            end_value, is_held, rate_inputs, step_mean, taylor)
from .loops import LoopError, coupling_groups, is_loop, solve_loop


def _scaled(gain: float, value):
    """gain * value for a number (gain is 1 but for flows); a String passes as it is."""
    return value if isinstance(value, str) else gain * value


# FMI 2 logging. fmpy's native proxy (it formats the variadic message, which ctypes
# cannot) forwards every FMI 2 message, process-wide, to the one Python logger registered
# last, and keeps only a pointer to it: a logger that died with its instance would crash
# the next FMU that logs. So there is one logger for the process, registered once, here;
# it routes a message to the live instance of that name and leaves the others to fmpy's
# own printer, as fmpy's default callbacks would.
_FMI2_LOGGING: "weakref.WeakValueDictionary[str, _Instance]" = weakref.WeakValueDictionary()


def _fmi2_log(env, instance_name, status, category, message):
    name = instance_name.decode("utf-8", "replace") if instance_name else ""
    instance = _FMI2_LOGGING.get(name)
    if instance is None:
        printLogMessage(env, instance_name, status, category, message)
    else:
        instance._log(env, status, category, message)


_FMI2_CALLBACKS = fmi2CallbackFunctions()
_FMI2_CALLBACKS.logger = fmi2CallbackLoggerTYPE(_fmi2_log)
_FMI2_CALLBACKS.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
_FMI2_CALLBACKS.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
addLoggerProxy(byref(_FMI2_CALLBACKS))


class _Instance:
    """One FMU instance in a running co-simulation.

    Ours are FMI 3 FMUs rebuilt from their component; a foreign FMU
    (:class:`assemblies.foreign.FMU`) is loaded from its file, FMI 3 through FMU3Slave,
    FMI 2 through FMU2Slave. FMI 2 Co-Simulation has no intermediate update: such an
    FMU reports no events, so event synchronisation sees none of its events (they land
    at the communication point after them), and it records no event rows.
    """

    def __init__(self, name: str, component, tolerance: float):
        path, md = self._load(name, component)
        self.states = [u.variable.derivative.name for u in md.derivatives]
        self._unzipped = extract(path)
        common = dict(guid=md.guid, unzipDirectory=self._unzipped,
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        if self.fmi_version == 2:
            self.fmu = FMU2Slave(**common)
            _FMI2_LOGGING[name] = self
            self.fmu.instantiate(callbacks=_FMI2_CALLBACKS, loggingOn=False)
        else:
            self.fmu = FMU3Slave(**common)
            self.fmu.instantiate(loggingOn=False, logMessage=self._log,
                                 intermediateUpdate=self._intermediate_update)
        self.tolerance = tolerance

    def _load(self, name: str, component):
        """Build (or fetch) the FMU and read what a master needs from its description.

        Ours are built with the class defaults, so parameter studies reuse one compiled
        FMU; the instance's own values are set as start values. A foreign FMU is its
        file, its description read unvalidated (other tools write descriptions fmpy's
        validation rejects, as the engine's ``prepared_path`` does).
        """
        self.name, self.component = name, component
        if isinstance(component, FMU):
            path = str(component.path)
            md = read_model_description(path, validate=False)
            # inputs the FMU extrapolates itself over a step: ours take s with v and a
            # (derivative inputs); a foreign FMU has none of those, and FMI 2's input
            # derivatives (canInterpolateInputs) are not set by this master, so it holds
            # every input constant and the master picks the constant (as in the engine)
            self.chained = {}
        else:
            defaults = type(component)(name=name, profile=component.profile.name,
                                       **component.option_values)
            path = build_fmu(defaults)
            md = read_model_description(path)
            # the model description does not say which inputs have a derivative input
            # (s by v, v by a); the flattened component does
            self.chained = derivative_inputs(component)
        self.fmi_version = int(md.fmiVersion[0])
        self.has_indicators = bool(md.eventIndicators if self.fmi_version == 3
                                   else md.numberOfEventIndicators)
        self.variables = {v.name: v for v in md.modelVariables}
        # each variable is got and set through its own type's call (value_types); the
        # discrete ones are held over a step, never extrapolated
        self.integers = {v.name for v in md.modelVariables
                         if canonical(v.type) not in CONTINUOUS}
        self.can_get_set_state = bool(md.coSimulation.canGetAndSetFMUstate)
        self.outputs = [v.name for v in md.modelVariables if v.causality == "output"]
        self.inputs = [v.name for v in md.modelVariables if v.causality == "input"]
        # output -> the inputs it depends on (direct feedthrough: algebraic loops, and the
        # order in which a master must set inputs); no list in the XML means all of them
        self.depends = {u.variable.name: (set(self.inputs) if u.dependencies is None else
                                          {d.name for d in u.dependencies if d.causality == "input"})
                        for u in md.outputs}
        self.messages: list[str] = []
        self.event_rows: list[list[float]] = []
        # what event synchronisation needs to know about the doStep in progress
        self.step_start = 0.0  # its currentCommunicationPoint
        self.clear_event_flags()
        return path, md

    def clear_event_flags(self) -> None:
        self.event_at_start = False  # an event handled at the step's start (inputs moved)
        self.event_in_step = math.inf  # the earliest event located inside the step

    # callbacks from C: keep them short and never raise
    def _log(self, env, status, category, message):
        text = message.decode("utf-8", "replace") if isinstance(message, bytes) else str(message)
        self.messages.append(text)

    def _intermediate_update(self, env, t, set_requested, get_allowed, step_finished,
                             can_return_early, early_return_requested, last_successful_time):
        early_return_requested[0] = False
        if not get_allowed or step_finished:
            return
        # an event: at the step's start (the inputs set at the communication point
        # crossed a switching condition) or located inside the step
        if t <= self.step_start + 1e-12 * max(1.0, abs(self.step_start)):
            self.event_at_start = True
        elif t < self.event_in_step:
            self.event_in_step = t
        try:
            self.event_rows.append([t] + self.get(self.outputs))
        except Exception as exc:  # pragma: no cover - reported after the step
            self.messages.append(f"recording the event at t = {t}: {exc}")

    def enter_initialization(self, tolerance: float, start_time: float = 0.0) -> None:
        # no stop time: event location probes an FMU with a tiny doStep past where it
        # stands (fires_at_start), also at the end of the run, and an FMU must refuse to
        # compute past a stop time it was given (fmi2SetupExperiment)
        self.step_start = start_time
        if self.fmi_version == 2:
            self.call("setup experiment", self.fmu.setupExperiment, tolerance, start_time,
                      None)
            self.call("enter initialization", self.fmu.enterInitializationMode)
        else:
            self.call("enter initialization", self.fmu.enterInitializationMode,
                      tolerance, start_time, None)

    def do_step(self, t: float, h: float, final: bool = False) -> tuple[bool, float]:
        """doStep from `t` over `h`: (the model asks to terminate, time reached).
        `final`: no state from before t + h will be set again (the run cannot roll
        back), which the FMU is told (noSetFMUStatePriorToCurrentPoint). The model ends
        the run the FMI 2 way (Discard, then fmi2Terminated and fmi2LastSuccessfulTime)
        or the FMI 3 way (terminateSimulation, with OK or Discard); any other step an
        FMU discards fails the run, as in the engine."""
        self.step_start = t
        what = f"doStep at t = {t:g}"
        if self.fmi_version == 2:
            try:
                self.fmu.doStep(t, h, final)
                return False, t + h
            except FMICallException as exc:
                if exc.status != fmi2Discard or not self._fmi2_status(
                        self.fmu.getBooleanStatus, fmi2Terminated, False):
                    raise self.failure(what, exc) from None
                return True, _within(self._fmi2_status(self.fmu.getRealStatus,
                                                       fmi2LastSuccessfulTime, t + h), t, h)
        # fmpy's doStep drops the out arguments when it raises: called here directly
        event, stop, early, reached = (fmi3Boolean(), fmi3Boolean(), fmi3Boolean(),
                                       fmi3Float64(t + h))
        try:
            self.fmu.fmi3DoStep(self.fmu.component, t, h, fmi3Boolean(final), byref(event),
                                byref(stop), byref(early), byref(reached))
        except FMICallException as exc:
            if exc.status != fmi3Discard or not stop.value:
                raise self.failure(what, exc) from None
        return bool(stop.value), _within(reached.value, t, h) if stop.value else reached.value

    @staticmethod
    def _fmi2_status(getter, kind, default):
        """An FMI 2 status query; `default` where the FMU does not answer it."""
        try:
            return getter(kind)
        except FMICallException:
            return default

    def call(self, what: str, fn, *args):
        try:
            return fn(*args)
        except FMICallException as exc:
            raise self.failure(what, exc) from None

    def failure(self, what: str, exc: FMICallException) -> SimulationError:
        logged = "; ".join(self.messages[-3:]) or str(exc)
        return SimulationError(f"{self.name}: {what} failed: {logged}")

    def vr(self, name: str):
        if name not in self.variables:
            array = name.partition("[")[0]
            if name.endswith("]") and getattr(self.variables.get(array), "dimensions", None):
                raise AssemblyError(f"{self.name}: the fmpy reference master does not get or "
                                    f"set FMI 3 arrays ({name}); run it in the compiled "
                                    "engine (engine 'c')")
            raise AssemblyError(f"{self.name} has no variable '{name}'")
        return self.variables[name]

    def _call_type(self, name: str) -> str:
        """The type in the name of the FMI call of variable `name`: an Enumeration is FMI 2's
        Integer and FMI 3's Int64."""
        t = self.vr(name).type
        return {"Enumeration": "Integer" if self.fmi_version == 2 else "Int64"}.get(t, t)

    def get(self, names: list[str]) -> list:
        """Values of `names` (numbers as floats, Strings as text), with one FMI call per
        variable type (ctypes calls are slow)."""
        values = [0.0] * len(names)
        for type_name in dict.fromkeys(self._call_type(n) for n in names):
            picked = [(i, self.vr(n).valueReference) for i, n in enumerate(names)
                      if self._call_type(n) == type_name]
            got = self.call(f"get {type_name} outputs", getattr(self.fmu, f"get{type_name}"),
                            [vr for _, vr in picked])
            for (i, _), value in zip(picked, got):
                values[i] = value.decode() if isinstance(value, bytes) else \
                    value if isinstance(value, str) else float(value)
        return values

    def is_int(self, name: str) -> bool:
        """A discrete variable (any type but Float64/Float32): held, not extrapolated."""
        self.vr(name)
        return name in self.integers

    def set(self, name: str, value) -> None:
        v, type_name = self.vr(name), self._call_type(name)
        cast = {"String": str, "Boolean": bool}.get(type_name, int if self.is_int(name) else float)
        self.call(f"set {name} = {value!r}", getattr(self.fmu, f"set{type_name}"),
                  [v.valueReference], [cast(value)])

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


@dataclass
class _Snapshot:
    """Everything a rollback restores: the FMUs' states and the master's own memory."""
    states: dict  # instance -> FMU state
    history: dict[int, list[tuple[float, float]]]
    n_events: dict[str, int]  # event rows each instance had
    terminated: dict | None
    t: float


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
        coupled = {}
        for c in couplings:
            coupled.setdefault(c.target[0], set()).add(c.target[1])
        self.held = {i for i, c in enumerate(couplings)
                     if is_held(c.target[1], instances[c.target[0]].chained,
                                instances[c.target[0]].is_int(c.target[1]), coupled[c.target[0]])}
        self.history: dict[int, list[tuple[float, float]]] = {i: [] for i in self.held}
        # held inputs whose target takes their rates: the polynomial itself goes into
        # the step, not its mean (cosim.c set_held); the rates last set, per input
        self.rates = {i: r for i in self.held
                      if (r := rate_inputs(couplings[i].target[1],
                                           instances[couplings[i].target[0]].chained,
                                           coupled[couplings[i].target[0]]))}
        self.rate_values = {i: [0.0] * RATES for i in self.rates}
        # the chains an FMU extrapolates itself (s -> v -> a): how far the motion it
        # extrapolated strays from its source's by a step's end bounds the adaptive
        # step (cosim.c chain_defect says why)
        self.derivative = derivative_couplings(couplings, {n: i.chained
                                                           for n, i in instances.items()})
        self.chain_order = [chain_order(self.derivative, k) for k in range(len(couplings))]
        for k in range(len(couplings)):  # rates at a chain's end: the polynomial's order
            if self._chain_end(k) in self.rates:
                self.chain_order[k] += extrapolation
        # rated inputs into FMUs that fire events: judged as chains (cosim.c chain_defect)
        self.judged_end = {k for k in self.rates
                           if instances[couplings[k].target[0]].has_indicators
                           and instances[couplings[k].source[0]].fmi_version >= 3}
        self.defect_tol = math.inf  # the adaptive tolerance (set by the stepper)
        self.defect, self.defect_order = 0.0, 1  # the last step's (chain_defect)
        self.coupling_defect = 0.0  # ... worst coupling off its extrapolation (chain_defect)
        self.terminated = None
        # no step is ever rolled back (fixed steps): each doStep says so to its FMU
        self.final = False
        # this step holds the sources' values (no extrapolation): set by event
        # synchronisation when an extrapolated input would fire an event too early
        self.hold_raw = False
        self.do_steps = 0
        self.events_located = 0
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
                self._set(*c.target, _scaled(c.gain, self._get(*c.source)))
        for i in self.held:
            value = self._get(*self.couplings[i].target)
            points = [p for p in self.history[i] if p[0] < t - 1e-12 * max(1.0, abs(t))]
            self.history[i] = (points + [(t, value)])[-(RATES + 1):]

    def held_inputs(self) -> dict[int, float]:
        return {i: self._get(*self.couplings[i].target) for i in self.held}

    def restart_history(self, before: dict[int, float]) -> None:
        """Keep only the last point of the history of each held input that moved from
        `before` by more than the tolerance relative to its value (cosim.c settle): its
        values before are another branch, and a polynomial through both extrapolates
        the jump."""
        for i, was in before.items():
            now = self._get(*self.couplings[i].target)
            if abs(now - was) > self.defect_tol * (1.0 + abs(now)):
                self.history[i] = self.history[i][-1:]

    @property
    def all_rated(self) -> bool:
        """Every held input takes its rates: the coupling's order is the extrapolation's
        + 1 (cosim.c all_rated)."""
        return all(i in self.rates for i in self.held)

    def _chain_end(self, k: int) -> int:
        d, links = k, 0
        while self.derivative[d] >= 0 and links <= len(self.couplings):
            d, links = self.derivative[d], links + 1
        return d

    def _set_rates(self, i: int, rates: list[float]) -> None:
        target = self.couplings[i].target[0]
        for name, value in zip(self.rates[i], rates):
            self._set(target, name, value)
        # (0 beyond the rates the target takes, as the FMU's chain has none there)
        self.rate_values[i] = [r if j < len(self.rates[i]) else 0.0 for j, r in enumerate(rates)]

    def _set_held(self, i: int, t: float, h: float, t_source: float, now: float) -> None:
        """Set held input `i` for [t, t + h]: the extrapolating polynomial itself where
        its target takes the rates, its step mean otherwise; `now` is its source's value
        at `t_source` (t, or t + h where Gauss–Seidel stepped the source already)."""
        target = self.couplings[i].target
        if self.extrapolation == 0 and t_source == t and i not in self.rates:
            self._set(*target, now)
            return
        eps = 1e-12 * max(1.0, abs(t_source))
        points = [p for p in self.history[i] if p[0] < t_source - eps] + [(t_source, now)]
        if i not in self.rates:
            self._set(*target, step_mean(points, t, h, self.extrapolation))
            return
        value, *rates = taylor(points, t, h, self.extrapolation)
        self._set(*target, value)
        self._set_rates(i, rates)

    def _clear_rates(self, i: int) -> None:
        """Held input `i`'s rates back to 0 (the input held constant), where any is not."""
        if i in self.rates and any(self.rate_values[i]):
            self._set_rates(i, [0.0] * RATES)

    def _set_raw(self, i: int, value: float) -> None:
        """Set input `i` to its source's value, held over the step."""
        self._set(*self.couplings[i].target, value)
        self._clear_rates(i)

    def _do_step(self, name: str, t: float, h: float) -> None:
        inst = self.instances[name]
        self.do_steps += 1
        stop, reached = inst.do_step(t, h, self.final)
        if stop and self.terminated is None:  # the model says it cannot go on (why: in its log)
            self.terminated = {"instance": name, "time": reached,
                               "message": inst.messages[-1] if inst.messages else ""}

    def step(self, t: float, h: float) -> None:
        """One communication step from `t` (inputs consistent at t) to t + h."""
        extrapolate = self.extrapolation and not self.hold_raw
        for inst in self.instances.values():
            inst.clear_event_flags()
        if self.scheme == "jacobi":
            for i in self.held:
                if extrapolate:
                    self._set_held(i, t, h, t, self.history[i][-1][1])
                else:  # (held raw, the input stands where consistent() set it)
                    self._clear_rates(i)
            for name in self.instances:
                self._do_step(name, t, h)
        else:
            done = set()
            for name in self.sweep_order:
                for i, c in enumerate(self.couplings):
                    if c.target[0] != name:
                        continue
                    ahead = c.source[0] in done
                    if i in self.in_loop and not (i in self.held and extrapolate):
                        continue  # keeps the loop's consistent value from t
                    now = _scaled(c.gain, self._get(*c.source)) if (ahead or i not in self.in_loop) \
                        else self.history[i][-1][1]
                    if i in self.held and extrapolate:
                        self._set_held(i, t, h, t + h if ahead else t, now)
                    elif i in self.held:
                        self._set_raw(i, now)
                    else:
                        self._set(*c.target, now)
                self._do_step(name, t, h)
                done.add(name)
        if self.terminated is None:
            predicted = {}
            if math.isfinite(self.defect_tol):
                for k, d in enumerate(self.derivative):
                    if d >= 0:
                        predicted[k] = self._chain_end_value(k, h)
                    elif k in self.held:
                        predicted[k] = end_value(self.history[k], h, self.extrapolation)
            self.consistent(t + h)
            self._chain_defect(predicted)

    def _chain_end_value(self, k: int, h: float) -> float:
        """Where the target FMU's Taylor chain puts chained input `k` at the end of a
        step of `h`, from the values set for the step (runtime.c inputs_at)."""
        value, term, d, order = self._get(*self.couplings[k].target), 1.0, self.derivative[k], 1
        while d >= 0 and order <= len(self.couplings):
            term *= h / order
            order += 1
            rate = self._get(*self.couplings[d].target)
            if rate != 0.0:
                value += rate * term
            d = self.derivative[d]
        for rate in self.rate_values.get(self._chain_end(k), ()):  # the end's own rates
            term *= h / order
            order += 1
            if rate != 0.0:
                value += rate * term
        return value

    def _source_had_event(self, k: int) -> bool:
        """Whether an FMU feeding chain `k` (the input or one of its derivatives) had an
        event in the step just taken (cosim.c source_had_event)."""
        while k >= 0:
            inst = self.instances[self.couplings[k].source[0]]
            if inst.event_at_start or math.isfinite(inst.event_in_step):
                return True
            k = self.derivative[k]
        return False

    def _target_had_event(self, k: int) -> bool:
        """Whether coupling `k`'s target FMU had an event in the step just taken."""
        inst = self.instances[self.couplings[k].target[0]]
        return inst.event_at_start or math.isfinite(inst.event_in_step)

    def _chain_defect(self, predicted: dict[int, float]) -> None:
        """The worst chained input's defect at the step's end over its allowance
        (defect_tol relative to the value), and that chain's order; and the coupling
        defect, every predicted coupling's (held inputs too) relative to the value. A
        coupling whose source had an event in the step is left out (cosim.c
        chain_defect says why)."""
        self.defect, self.defect_order, self.coupling_defect = 0.0, 1, 0.0
        for k, p in predicted.items():
            if self._source_had_event(k):
                continue
            u = self._get(*self.couplings[k].target)
            self.coupling_defect = max(self.coupling_defect, abs(u - p) / (1.0 + abs(u)))
            if self.derivative[k] < 0 and not (k in self.judged_end
                                               and self._target_had_event(k)):
                continue
            ratio = abs(u - p) / (self.defect_tol * (1.0 + abs(u)))
            if ratio > self.defect:
                self.defect, self.defect_order = ratio, self.chain_order[k]

    def state_vector(self) -> np.ndarray:
        return np.array([v for inst in self.instances.values() for v in inst.get(inst.states)])

    # --- rollback: adaptive steps and event synchronisation --------------------------
    def save(self, t: float) -> _Snapshot:
        return _Snapshot({n: i.save() for n, i in self.instances.items()},
                         {k: list(v) for k, v in self.history.items()},
                         {n: len(i.event_rows) for n, i in self.instances.items()},
                         self.terminated, t)

    def restore(self, snap: _Snapshot) -> None:
        for name, inst in self.instances.items():
            inst.restore(snap.states[name])
            del inst.event_rows[snap.n_events[name]:]  # events of a step that did not count
        self.history = {k: list(v) for k, v in snap.history.items()}
        self.terminated = snap.terminated

    def discard(self, snap: _Snapshot | None) -> None:
        if snap is not None:
            for name, inst in self.instances.items():
                inst.discard(snap.states[name])


def cosimulate(assembly: Assembly, stop_time: float, step: float, tolerance: float = 1e-8,
               record: list[str] | None = None, scheme: str = "jacobi",
               progress: Callable[[float], None] | None = None, extrapolation: int = 0,
               adaptive: bool = False, tol: float = 1e-4, loop_tolerance: float = 1e-10,
               max_loop_iterations: int = 20, newton: bool = True,
               event_sync: bool | None = None, start_time: float = 0.0,
               inputs=None) -> Result:
    """Co-simulate `assembly` from `start_time` to `stop_time`; `inputs`, a table
    feeding open inputs (:mod:`assemblies.inputs`).

    `step` is the communication step; with ``adaptive=True`` it is the output interval
    and the largest step, and steps are chosen so that the estimated global error of
    the FMUs' states stays near `tol` (absolute, :mod:`assemblies.adaptive`).
    `tolerance` is the FMUs' own solver tolerance. `extrapolation` (0, 1, 2, 3) is the
    order of the polynomial whose step mean is held on inputs the FMUs hold constant
    (:mod:`assemblies.extrapolation`). Algebraic loops are solved at every
    communication point to `loop_tolerance` in at most `max_loop_iterations` Newton
    iterations (plain fixed-point iteration with ``newton=False``). `event_sync`
    (None: on exactly when `adaptive`, as in the compiled engine): steps end at the
    events the FMUs locate, and events the FMUs handle at a communication point are
    moved back to where the coupled system crossed (to ``EVENT_TOL``,
    :mod:`assemblies.masters.events`), where the FMUs' modes settle before the next step
    (probe-length steps until none fires at its start: a clutch released by an input
    jump leaves its stick, and the loops are solved with it free). Adaptive steps and event synchronisation roll
    back through FMU state; where an FMU cannot get and set its state (a foreign one,
    say), or a foreign FMU's restore proves inexact when checked before the run
    (:func:`_restore_problem`; ``settings["inexact_restore"]``), the run falls back to
    fixed steps of `step` without event synchronisation, warns
    (:class:`assemblies.experiment.FixedStepFallback`) and says so in
    ``settings["fallback"]``, as the compiled engine does. Fixed steps tell each doStep
    that no earlier state will be set again (noSetFMUStatePriorToCurrentPoint). A model
    that ends the run the FMI way ends it where it stopped, with the rows so far
    (``settings["terminated"]``). A foreign FMI 2 FMU has no
    intermediate update: event synchronisation sees no events located inside its steps.
    A Model-Exchange-only foreign FMU is refused (:func:`assemblies.foreign.check_mode`).
    """
    check_experiment(stop_time, step, tolerance, start_time=start_time)
    check_cosim_settings(scheme, extrapolation, adaptive, tol)
    assembly = with_inputs(assembly, inputs)
    event_sync = bool(adaptive) if event_sync is None else bool(event_sync)
    check_mode(assembly, "cosim")  # a Model-Exchange-only FMU: named, with the modes that apply
    couplings = assembly.couplings()
    instances: dict[str, _Instance] = {}
    started = wallclock.perf_counter()
    fallback = None
    inexact = {}
    try:
        for name, comp in assembly.components.items():
            # a foreign FMU's restore is checked before the run's instance exists (the
            # check's instance has the same name, which routes FMI 2 log messages)
            if (adaptive or event_sync) and isinstance(comp, FMU):
                problem = _restore_problem(name, comp, tolerance, step)
                if problem is not None:
                    inexact[name] = problem
            instances[name] = _Instance(name, comp, tolerance)
        stateless = [n for n, i in instances.items() if not i.can_get_set_state]
        if (adaptive or event_sync) and (stateless or inexact):  # as the engine does
            fallback = fixed_step_fallback(adaptive, stateless, step, inexact)
            warnings.warn(fallback, FixedStepFallback, stacklevel=2)
            adaptive = event_sync = False
        columns = _record_columns(instances, record)
        master = _Master(assembly.name, instances, couplings, assembly.order(), scheme,
                         extrapolation, loop_tolerance, max_loop_iterations, newton)
        master.final = not (adaptive or event_sync)

        def sample(t):
            row = {}
            for name in instances:
                wanted = [v for i, v in columns if i == name]
                row.update(zip(((name, v) for v in wanted), instances[name].get(wanted)))
            return [t] + [row[c] for c in columns]

        for inst in instances.values():
            comp = inst.component
            for key, value in comp.fmu_starts().items():
                inst.set(key, value)
            inst.enter_initialization(tolerance, start_time)
        master.consistent(start_time)
        for inst in instances.values():
            inst.call("exit initialization", inst.fmu.exitInitializationMode)
        master.consistent(start_time)
        out_times = output_times(stop_time, step, start_time)[1:].tolist()
        stepper = _Stepper(master, out_times, step, tolerance, adaptive=bool(adaptive), tol=tol,
                           extrapolation=extrapolation, event_sync=event_sync, sample=sample,
                           progress=progress, start_time=start_time)
        rows = stepper.run()
        names = ["time"] + [f"{i}.{v}" for i, v in columns]
        table = Table.from_rows(names, rows)
        events = {name: Table.from_rows(["time"] + [f"{name}.{v}" for v in inst.outputs],
                                        inst.event_rows)
                  for name, inst in instances.items() if inst.event_rows}
        settings = {"start_time": start_time, "stop_time": stop_time, "step": step,
                    "tolerance": tolerance, "scheme": scheme,
                    "extrapolation": extrapolation, "adaptive": bool(adaptive),
                    "event_sync": event_sync, "wall_s": wallclock.perf_counter() - started,
                    "terminated": master.terminated, "do_steps": master.do_steps,
                    **stepper.stats(),
                    "loops": [" -> ".join(".".join(couplings[i].source) for i in g)
                              for g in master.loops],
                    "loop_iterations": master.loop_iterations,
                    "loop_residual": master.loop_residual, "fallback": fallback,
                    "inexact_restore": inexact or None}
        if adaptive:
            settings["tol"] = tol
        return Result({n: table[n] for n in names}, events, settings)
    finally:
        for inst in instances.values():
            inst.free()


def _restore_problem(name: str, component, tolerance: float, step: float) -> str | None:
    """Why a foreign FMU's state restore cannot be trusted, or None: the engine's check
    (assemblies/engine/c/restore_check.h) through fmpy, on an instance of its own.
    Saved at t = 0, one doStep of `step`, restored: the outputs and states must read
    as at t = 0, and after the same doStep again as after the first, bit for bit."""
    probe = _Instance(name, component, tolerance)
    state = None
    try:
        if not probe.can_get_set_state:
            return None
        for key, value in component.fmu_starts().items():
            probe.set(key, value)
        probe.enter_initialization(tolerance)
        probe.call("exit initialization", probe.fmu.exitInitializationMode)
        names = [v for v in dict.fromkeys(probe.outputs + probe.states)
                 if probe.variables[v].type in ("Real", "Float64", "Integer", "Int32")]
        ended = ("its restore could not be checked: it ended the run in its doStep of "
                 f"{step:g} s from t = 0")
        start = probe.get(names)
        state = probe.save()
        if probe.do_step(0.0, step)[0]:
            return ended
        first = probe.get(names)
        probe.restore(state)
        differs = _first_difference(names, start, probe.get(names))
        if differs is not None:
            return restore_mismatch(differs[0], False, *differs[1:])
        if probe.do_step(0.0, step)[0]:
            return ended
        differs = _first_difference(names, first, probe.get(names))
        if differs is not None:
            return restore_mismatch(differs[0], True, *differs[1:])
        return None
    except SimulationError as exc:
        return f"its restore could not be checked: {exc}"
    finally:
        if state is not None:
            try:
                probe.discard(state)
            except SimulationError:
                pass
        probe.free()


def _first_difference(names, before, after):
    """(name, before, after) of the first value whose bits changed, or None."""
    for name, a, b in zip(names, before, after):
        if struct.pack("d", a) != struct.pack("d", b):
            return name, a, b
    return None


def _within(reached: float, t: float, h: float) -> float:
    """Where a terminating FMU stopped, within its step [t, t + h] (as the engine)."""
    return max(t, min(reached, t + h))


def _close(a: float, b: float) -> bool:
    """Times equal to round-off (relative 1e-12, absolute below 1 s)."""
    return abs(a - b) < 1e-12 * max(1.0, abs(b))


class _Stepper:
    """The run after initialisation: communication steps to the output times, a row at
    each. Steps are fixed (the interval to the next output time) or adaptive (step
    doubling, :mod:`assemblies.masters.adaptive`); with event synchronisation a step
    ends at the first event an FMU locates in it, and an event an FMU handles at the
    start of a step is moved back into the step before it
    (:mod:`assemblies.masters.events`). Step by step the compiled engine's ``run``
    (assemblies/engine/c/cosim.c), so that the two masters give the same results.
    """

    def __init__(self, master: _Master, out_times: list[float], step: float,
                 tolerance: float, *, adaptive: bool, tol: float, extrapolation: int,
                 event_sync: bool, sample, progress, start_time: float = 0.0):
        self.master, self.out_times, self.tolerance = master, out_times, tolerance
        self.adaptive, self.event_sync, self.extrapolation = adaptive, event_sync, extrapolation
        self.rollback = adaptive or event_sync
        self.sample, self.progress = sample, progress
        # global order of the coupling: 1 with a zero-order hold, 2 with a step-mean
        # extrapolation (see assemblies.extrapolation for why not 3 with quadratic), the
        # extrapolation's + 1 where every held input takes its rates, at most ORDER_MAX
        # (cosim.c says why)
        self.ctrl = StepController(tol, 1 if extrapolation == 0
                                   else min(extrapolation + 1, ORDER_MAX) if master.all_rated
                                   else 2,
                                   out_times[-1] - start_time, step)
        master.defect_tol = tol
        self.t = start_time
        self.h = step / 4 if adaptive else step  # the next adaptive step
        self.rows = [sample(start_time)]
        self.snap: _Snapshot | None = None  # the state at the start of the step in progress
        self.prev: _Snapshot | None = None  # ... of the step before it (None: no step yet)
        self.h_prev = 0.0  # the length of the step before
        # the time a start event was last moved back to: the event fires at the start of
        # the next step by design, and is not to be moved back again
        self.located_at = -math.inf
        self.coast, self.h_coast = 0, 0.0  # unjudged steps left, and their length
        # settling the modes after an event was cut at an output point (_settle), and
        # the held inputs where it began
        self.unsettled, self.settle_from = False, {}
        self.coast_run = COAST_STEPS  # the next run's length (adaptive.py COAST_MAX)
        # the last run ran to its end (1), or the coupling defect ended it (COAST_GUARDED)
        self.coast_done = 0
        self.coast_extended = False  # the run went on past its end to an output point
        self.defect_ref = 0.0  # the coupling defect at the last accepted estimate
        self.defect_ref_h = math.inf  # ... and the length of the half step it was taken at
        self.shortened = False  # the last step was shortened to end at an event in it
        self.steps = 0
        self.events_synchronised = 0
        self.h_min, self.h_max = math.inf, 0.0

    def run(self) -> list[list[float]]:
        """Step to the last output time (or where the model terminated); the rows."""
        m = self.master
        try:
            while len(self.rows) <= len(self.out_times):
                target = self.out_times[len(self.rows) - 1]
                if _close(self.t, target) or self.t > target or m.terminated is not None:
                    self.rows.append(self.sample(self.t if m.terminated is not None else target))
                    if self.progress is not None:
                        self.progress(self.t)
                    if m.terminated is not None:
                        break
                    continue
                self._step_towards(target)
        finally:
            m.discard(self.snap)
            m.discard(self.prev)
        return self.rows

    def stats(self) -> dict:
        stats = {"steps": self.steps, "rejected": self.ctrl.rejected,
                 "events_synchronised": self.events_synchronised,
                 "events_located": self.master.events_located}
        if self.adaptive:
            none = self.h_max == 0.0
            stats.update(h_min=math.nan if none else self.h_min,
                         h_max=math.nan if none else self.h_max,
                         error_ratio_max=self.ctrl.max_ratio)
        return stats

    def _step_towards(self, target: float) -> None:
        """One communication step from self.t towards `target`: taken, and kept or
        rolled back (rejected, or a start event moved the run back)."""
        m = self.master
        coasting = self.adaptive and self.coast > 0  # COAST_STEPS (adaptive.py)
        if (self.adaptive and not coasting and self.coast_done == 1 and not self.coast_extended
                and cells(target - self.t, self.h / 2, not self.ctrl.rejected_last) < 2.0):
            # the estimate's two halves do not fit before the output point: the run goes
            # on to it, and the estimate is taken from there (adaptive.py)
            coasting, self.coast, self.coast_extended = True, 1, True
        h_wanted = self.h_coast if coasting else self.h  # before the output grid fits it
        h_try = self._trial_length(target, h_wanted, coasting)
        if self.unsettled:  # settling was cut at an output point: it goes on from here
            t = self.t
            self._settle(target)
            if self.t > t:
                self.coast, self.coast_run, self.coast_done = 0, COAST_STEPS, 0
                self._resample_after(self.located_at)
                return
            # no room for a settle step before target: step on
            self.unsettled = False
            m.restart_history(self.settle_from)
        if self.rollback:
            m.discard(self.snap)
            self.snap = m.save(self.t)
        h_try = self._step_to_first_event(h_try, target)
        if h_try is None:  # the run went back to a start event inside the previous step
            m.hold_raw = False
            return
        if self.adaptive and coasting:
            # the motion strayed, or the couplings move unlike when the estimate was made
            ok = m.defect <= 1.0 and m.coupling_defect <= defect_allowance(
                self.defect_ref, self.defect_ref_h, h_try, m.extrapolation, self.tolerance)
            if ok:
                self.steps += 1
            else:  # estimate again from here
                m.restore(self.snap)
                self.ctrl.rejected += 1
                self.ctrl.rejected_last = True
                # a chain's defect says the step is too long; the coupling's only that
                # the estimate is due (its halves are this step)
                self.h = h_try if m.defect > 1.0 else 2.0 * h_try
            self.coast = 0 if self.shortened or not ok else self.coast - 1
            self.coast_done = (0 if self.coast > 0 or self.shortened
                               else 1 if ok else COAST_GUARDED if m.defect <= 1.0 else 0)
            if not self.coast_done and self.coast == 0:
                self.coast_run = COAST_STEPS
        elif self.adaptive:
            ok, h_try = self._judge(h_try, h_wanted)
            if m.terminated is not None:  # the model ended the run: keep what it did
                self.t = m.terminated["time"]
                return
        else:
            ok = True
            self.steps += 1
        m.hold_raw = False
        if m.terminated is not None:  # the last row is where the model stopped
            self.t = m.terminated["time"]
        elif ok:
            self._advance(h_try, target)

    def _trial_length(self, target: float, h_wanted: float, coasting: bool) -> float:
        """The step fitted to the output grid (adaptive.py cells): an unjudged one of
        the equal steps that fill the interval; an estimate two of them, or all that is
        left. No stretch right after a rejection at that length."""
        left = target - self.t
        if not self.adaptive:
            return left
        stretch = not self.ctrl.rejected_last
        if coasting:
            return left / cells(left, h_wanted, stretch)
        n = cells(left, h_wanted / 2, stretch)
        return 2.0 * left / n if n >= 2.0 else left

    def _step_to_first_event(self, h_try: float, target: float) -> float | None:
        """The step from self.t, shortened to end at the first event inside it; its
        length, or None where an event at its start was moved back into the step
        before (self.t is then that event's time)."""
        m, t = self.master, self.t
        shortened = self.shortened = False
        while True:
            m.step(t, h_try)
            if not self.event_sync:
                return h_try
            which = events_at_start(m)
            if which and t > self.located_at:
                if self._start_event(which, target):
                    return None
                continue  # the step again, from the state restored there
            te = earliest_event_in_step(m)
            if not shortened and te - t > EVENT_TOL and te < t + h_try:
                # the other FMUs must see the event's outputs from the event on, not
                # from the end of the step: retake it to end just past the event (by a
                # margin, so that the FMU that located it handles it inside the step)
                margin = min(EVENT_TOL, 0.5 * (t + h_try - te))
                m.restore(self.snap)
                h_try = te - t + margin
                shortened = self.shortened = True
                self.events_synchronised += 1
                continue
            return h_try

    def _start_event(self, which: set[str], target: float) -> bool:
        """An event fired at the start of the step from self.t, in the instances
        `which`: move it back to where it first fires in the previous step (True: the
        run is there now), or restore the step's start to retake it (False)."""
        m, t = self.master, self.t
        if self.extrapolation and not m.hold_raw:
            # an extrapolated held input runs ahead of its source (it is the mean over
            # the coming step): if the sources' own values at t do not fire the event,
            # it is premature, and the step is redone holding them
            m.restore(self.snap)
            if not fires_at_start(m, which, t, probe_step(t)):
                m.hold_raw = True
                return False
        if self.prev is None:  # at the start of the run: nothing to go back into
            m.restore(self.snap)
            t_event = t
        else:
            t_event = locate_start_event(m, self.prev, self.h_prev, which)
            self.h_prev = t_event - self.prev.t
        self.located_at = self.t = t_event
        self._settle(target)  # the modes change there, before the next step
        self.coast, self.coast_run, self.coast_done = 0, COAST_STEPS, 0
        self._resample_after(t_event)
        return True

    def _resample_after(self, t_event: float) -> None:
        """Rows sampled at or after the event's time are sampled again, from where it
        settled (past them, or at them to round-off): a row at or after an event shows
        the modes after it."""
        k = len(self.rows) - 1
        while k > 0 and self.out_times[k - 1] >= t_event:
            k -= 1
        del self.rows[k + 1:]

    def _settle(self, target: float) -> None:
        """Let the modes change at an event at the start of the step from self.t, and
        the loops settle with them: steps of probe length, each followed by
        consistency, until one in which no FMU fires at its start (cosim.c settle
        says why); each is a step of the run. They never pass `target`: settling cut
        there goes on from there (self.unsettled). Settled, a held input that jumped
        meanwhile restarts its history (_Master.restart_history)."""
        m = self.master
        if not self.unsettled:
            self.settle_from = m.held_inputs()
        self.unsettled = True
        held_raw, m.hold_raw = m.hold_raw, True
        settled, n = False, 0
        try:
            while n < MAX_SETTLE_STEPS:
                h = min(probe_step(self.t), target - self.t)
                if not (h > 0.0 and self.t + h > self.t):
                    break  # at the output point: the next step goes on
                n += 1
                m.discard(self.prev)
                self.prev = m.save(self.t)
                m.step(self.t, h)
                self.h_prev = h
                if m.terminated is not None:
                    self.t = m.terminated["time"]
                else:
                    self.t = target if h == target - self.t else self.t + h
                if m.terminated is not None or not events_at_start(m):
                    settled = True
                    break
        finally:
            m.hold_raw = held_raw
        if settled or n == MAX_SETTLE_STEPS:
            self.unsettled = False
            m.restart_history(self.settle_from)

    def _judge(self, h_try: float, h_wanted: float) -> tuple[bool, float]:
        """Step doubling on the step of `h_try` just taken (`h_wanted` before an output
        point cut it): redone as two halves, kept (the halves) or rolled back;
        (accepted?, the length kept). Sets the next step and the next run of unjudged
        steps (adaptive.py COAST_MAX)."""
        m, t, ctrl = self.master, self.t, self.ctrl
        self.coast_extended = False
        coarse = m.state_vector()
        defect, defect_order = m.defect, m.defect_order  # the whole step's, as judged
        m.restore(self.snap)
        m.step(t, h_try / 2)
        if m.terminated is None:
            m.step(t + h_try / 2, h_try / 2)
        if m.terminated is not None:
            return False, h_try
        if self.event_sync and events_at_start(m) and t + h_try / 2 > self.located_at:
            # an event fired where the two half steps meet: the coupled system crossed
            # inside the first half, and the whole step's error is the event's, not
            # the coupling's. The first half is tried again as a step of its own,
            # judged like any other (kept unjudged, a first step of 0.03 s left
            # axle_motor 5e-3 off whatever the tolerance); the step after it fires the
            # event at its start and moves it back there. Only a half within EVENT_TOL
            # is kept as it is (no coupling error; and an event that fires at every
            # point would otherwise halve the step without end).
            m.restore(self.snap)
            self.h = h_try / 2
            if self.h > EVENT_TOL:
                ctrl.rejected += 1
                ctrl.rejected_last = True
                return False, h_try
            m.step(t, self.h)
            self.steps += 1
            return True, self.h
        fine = m.state_vector()
        ok, self.h = ctrl.judge(ctrl.estimate(coarse, fine), h_try,
                                ctrl.noise(fine, self.tolerance, h_try), defect, defect_order)
        if ok and not self.shortened:  # the half step found good, kept a while
            ratio = self.h / h_wanted
            steady = bool(self.coast_done) and ratio >= COAST_STEADY and COAST_STEADY * ratio <= 1.0
            self.coast_run = (COAST_STEPS if not steady else self.coast_run
                              if self.coast_done == COAST_GUARDED
                              else min(2 * self.coast_run, COAST_MAX))
            # the second half step's coupling defect (it has the unjudged steps' length);
            # from an output interval on the largest since the run last reset (cosim.c
            # says why)
            self.defect_ref = (max(m.coupling_defect, self.defect_ref)
                               if steady and self.h >= ctrl.h_max else m.coupling_defect)
            self.defect_ref_h = h_try / 2
            # the run's steps from the step asked for (fitted to the grid as taken;
            # longer than the estimate's halves only once the estimates are steady)
            self.coast = self.coast_run
            self.h_coast = min(h_wanted, self.h, ctrl.h_cap if steady else ctrl.h_max) / 2
            self.coast_done = 0
        elif ok or not self.coast_done or self.h < COAST_KEEP * h_wanted:
            self.coast_run, self.coast_done = COAST_STEPS, 0
        # (else a mild rejection after a run: the step shrinks, the run stays as long)
        if not ok and h_try <= ctrl.min_step(t):  # rejected at the shortest step there is
            raise SimulationError(f"adaptive step fell below {ctrl.min_step(t):.3g} s at t = "
                                  f"{t:g} (tol {ctrl.tol:g} cannot be met)")
        if ok:
            self.steps += 1
        else:
            m.restore(self.snap)
        self.h = max(self.h, ctrl.min_step(t))
        return ok, h_try

    def _advance(self, h_try: float, target: float) -> None:
        """The step of `h_try` from self.t is kept."""
        self.h_min, self.h_max = min(self.h_min, h_try), max(self.h_max, h_try)
        self.t = target if _close(self.t + h_try, target) else self.t + h_try
        if self.rollback:
            # the step's start becomes the previous step's: where a start event in the
            # next step is looked for
            self.master.discard(self.prev)
            self.prev, self.snap = self.snap, None
            self.h_prev = h_try


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
