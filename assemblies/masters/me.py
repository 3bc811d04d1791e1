"""The `me` master: every FMU as FMI 3 Model Exchange, all integrated by ONE solver.

The continuous states of all instances form one vector. Each right-hand-side call
sets time and states on every FMU, then evaluates the connections in dependency
order (an input is set before any output that depends on it is read, as the FMUs'
ModelStructure declares), then collects the derivatives. Event indicators of every
FMU are watched by :mod:`assemblies.hybrid`; at an event all FMUs enter event mode and
update their discrete states until neither they nor the inputs they see change.

Unlike co-simulation there is no communication step: inputs are exact at every
solver stage, so the error is the solver's alone.
"""
from __future__ import annotations

import ctypes
import time as wallclock
from typing import Callable

import numpy as np
from fmpy import extract
from fmpy.fmi3 import FMU3Model


from ..assembly import Assembly, AssemblyError
from ..experiment import check_experiment, output_times
from ..inputs import with_inputs
from ..foreign import check_own_only
from ..result import Result, Table
from .cosim import SimulationError, _Instance, _record_columns
from .hybrid import METHODS, EventOutcome, IntegrationError, integrate
from .loops import LoopError, coupling_groups, is_loop, solve_loop

# An algebraic loop's inputs are made consistent to this fraction of the solver's
# tolerance (relative, solve_loop's test): far below what the integration resolves.
# A loop linear in its inputs (locked clutches: the torques through the accelerations)
# takes one Newton step from the FMUs' directional derivatives.
LOOP_TOLERANCE = 1e-3
MAX_LOOP_ITERATIONS = 20

_DOUBLE_P = ctypes.POINTER(ctypes.c_double)


class _ModelInstance(_Instance):
    """One Model Exchange FMU instance; shares value access with the co-simulation one."""

    def __init__(self, name: str, component):  # noqa: super().__init__ would make a slave
        path, md = self._load(name, component)
        self.n_x = len(md.derivatives)
        self.n_z = md.numberOfEventIndicators or 0
        self._unzipped = extract(path)
        self.fmu = FMU3Model(guid=md.guid, unzipDirectory=self._unzipped,
                             modelIdentifier=md.modelExchange.modelIdentifier, instanceName=name)
        self.fmu.instantiate(loggingOn=False, logMessage=self._log)
        self._x = np.zeros(self.n_x)
        self._z = np.zeros(self.n_z)

    def set_states(self, t: float, x: np.ndarray) -> None:
        self.call("setTime", self.fmu.setTime, t)
        if self.n_x:
            x = np.ascontiguousarray(x, dtype=float)
            self.call("setContinuousStates", self.fmu.setContinuousStates,
                      x.ctypes.data_as(_DOUBLE_P), self.n_x)

    def states(self) -> np.ndarray:
        if self.n_x:
            self.call("getContinuousStates", self.fmu.getContinuousStates,
                      self._x.ctypes.data_as(_DOUBLE_P), self.n_x)
        return self._x.copy()

    def derivatives(self) -> np.ndarray:
        if self.n_x:
            self.call("getContinuousStateDerivatives", self.fmu.getContinuousStateDerivatives,
                      self._x.ctypes.data_as(_DOUBLE_P), self.n_x)
        return self._x.copy()

    def indicators(self) -> np.ndarray:
        if self.n_z:
            self.call("getEventIndicators", self.fmu.getEventIndicators,
                      self._z.ctypes.data_as(_DOUBLE_P), self.n_z)
        return self._z.copy()


class _CoupledSystem:
    """All instances as one hybrid ODE for :func:`assemblies.hybrid.integrate`."""

    def __init__(self, instances: dict[str, _ModelInstance], couplings, columns, name="",
                 tolerance=1e-8):
        self.instances, self.couplings, self.name = instances, list(couplings), name
        depends = {n: i.depends for n, i in instances.items()}
        inputs = {n: i.inputs for n, i in instances.items()}
        # strongly connected groups, each after the ones it needs; a group of several
        # couplings (or one feeding its own source) is an algebraic loop, solved per call
        self.groups = coupling_groups(self.couplings, depends, inputs)
        self.loops = [g for g in self.groups if is_loop(g, self.couplings, depends, inputs)]
        self.loop_options = dict(tolerance=LOOP_TOLERANCE * tolerance,
                                 max_iterations=MAX_LOOP_ITERATIONS)
        self.columns = columns
        self.slices, start = {}, 0
        for name, inst in instances.items():
            self.slices[name] = slice(start, start + inst.n_x)
            start += inst.n_x
        self.owner_of_indicator = [name for name, inst in instances.items() for _ in range(inst.n_z)]
        self._at = None  # (t, y bytes) the FMUs were last set to

    def _set(self, t, y):
        key = (t, y.tobytes())
        if key == self._at:
            return
        for name, inst in self.instances.items():
            inst.set_states(t, y[self.slices[name]])
        self.propagate()
        self._at = key

    def _value(self, inst, var):
        return self.instances[inst].get([var])[0]

    def _set_value(self, inst, var, value):
        self.instances[inst].set(var, value)

    def propagate(self) -> list[float]:
        """Every input set from its source, loops solved; the inputs' values."""
        for group in self.groups:
            if group in self.loops:
                try:
                    solve_loop(group, self.couplings, self._value, self._set_value, self._value,
                               lambda i, o, u: self.instances[i].partial(o, u),
                               **self.loop_options)
                except LoopError as exc:
                    raise SimulationError(f"assembly '{self.name}': {exc}") from None
            else:
                c = self.couplings[group[0]]
                self._set_value(*c.target, c.gain * self._value(*c.source))
        return [self._value(*c.target) for c in self.couplings]

    def rhs(self, t, y):
        self._set(t, y)
        return np.concatenate([inst.derivatives() for inst in self.instances.values()]) \
            if self.instances else np.zeros(0)

    def indicators(self, t, y):
        self._set(t, y)
        parts = [inst.indicators() for inst in self.instances.values()]
        return np.concatenate(parts) if parts else np.zeros(0)

    def sample(self, t, y):
        self._set(t, y)
        row = {}
        for name, inst in self.instances.items():
            wanted = [v for i, v in self.columns if i == name]
            row.update(zip(((name, v) for v in wanted), inst.get(wanted)))
        return [t] + [row[c] for c in self.columns]

    def event_iteration(self, t, y, changed, first=False) -> EventOutcome:
        """Event mode for every FMU; discrete updates until the coupled inputs settle."""
        if not first:
            self._set(t, y)
            for inst in self.instances.values():
                inst.call(f"enterEventMode at t = {t:g}", inst.fmu.enterEventMode)
        self._at = None  # the jumps change states behind our back
        terminate, next_time = None, None
        inputs = self.propagate()
        for _ in range(100):
            for name, inst in self.instances.items():
                for _ in range(100):
                    needs, stop, _, _, defined, when = inst.call(
                        f"updateDiscreteStates at t = {t:g}", inst.fmu.updateDiscreteStates)
                    if stop and terminate is None:
                        terminate = (name, inst.messages[-1] if inst.messages else "")
                    if defined:
                        next_time = when if next_time is None else min(next_time, when)
                    if not needs:
                        break
                else:
                    raise SimulationError(f"{name}: discrete states do not settle at t = {t:g}")
            new_inputs = self.propagate()
            if new_inputs == inputs:
                break
            inputs = new_inputs
        else:
            raise SimulationError(f"the event iteration at t = {t:g} does not settle "
                                  "between the connected FMUs")
        owners = {self.owner_of_indicator[i] for i in np.flatnonzero(changed)}
        for name in owners:
            inst = self.instances[name]
            inst.event_rows.append([t] + inst.get(inst.outputs))
        for inst in self.instances.values():
            inst.call("enterContinuousTimeMode", inst.fmu.enterContinuousTimeMode)
        y_new = np.concatenate([inst.states() for inst in self.instances.values()]) \
            if self.instances else np.zeros(0)
        self._at = None
        message = None
        if terminate is not None:
            self.terminated_by = terminate[0]
            message = terminate[1]
        return EventOutcome(y_new, message, next_time)

    def handle_event(self, t, y, changed):
        return self.event_iteration(t, y, changed)


def simulate_me(assembly: Assembly, stop_time: float, step: float, tolerance: float = 1e-8,
                record: list[str] | None = None, method: str = "DOP853",
                progress: Callable[[float], None] | None = None, start_time: float = 0.0,
                inputs=None) -> Result:
    """Integrate `assembly` as Model Exchange FMUs from `start_time`; the table holds
    every `step` seconds. `inputs`: a table feeding open inputs (:mod:`assemblies.inputs`)."""
    check_experiment(stop_time, step, tolerance, "output step", start_time)
    assembly = with_inputs(assembly, inputs)
    check_own_only(assembly, "simulate_me")
    if method not in METHODS:
        raise AssemblyError(f"method must be one of {', '.join(METHODS)}, not '{method}'")
    couplings = assembly.couplings()  # resolves the causality profiles
    instances: dict[str, _ModelInstance] = {}
    started = wallclock.perf_counter()
    try:
        for name, comp in assembly.components.items():
            instances[name] = _ModelInstance(name, comp)
        columns = _record_columns(instances, record)
        system = _CoupledSystem(instances, couplings, columns, assembly.name, tolerance)
        for inst in instances.values():
            for key, value in {**inst.component.values, **inst.component.starts}.items():
                inst.set(key, value)
            inst.call("enter initialization", inst.fmu.enterInitializationMode,
                      tolerance, start_time, stop_time)
        for _ in range(len(instances)):  # settles any loop-free chain of outputs
            system.propagate()
        for inst in instances.values():
            inst.call("exit initialization", inst.fmu.exitInitializationMode)
        # FMI 3: after initialization an ME FMU is in event mode; settle it like any event
        n_z = sum(inst.n_z for inst in instances.values())
        y0 = np.concatenate([inst.states() for inst in instances.values()])
        outcome = system.event_iteration(start_time, y0, np.zeros(n_z, dtype=bool), first=True)
        times = output_times(stop_time, step, start_time)
        terminated, stats = None, None
        if outcome.terminate is not None:
            rows = [system.sample(start_time, outcome.y)]
            terminated = (start_time, outcome.terminate)
        else:
            rows, stats, terminated = integrate(
                system, outcome.y, stop_time, times, method=method, rtol=tolerance,
                atol=tolerance * 1e-2, progress=progress)
        names = ["time"] + [f"{i}.{v}" for i, v in columns]
        table = Table.from_rows(names, rows)
        events = {name: Table.from_rows(["time"] + [f"{name}.{v}" for v in inst.outputs],
                                        inst.event_rows)
                  for name, inst in instances.items() if inst.event_rows}
        settings = {"start_time": start_time, "stop_time": stop_time, "step": step,
                    "tolerance": tolerance, "scheme": "me",
                    "method": method, "wall_s": wallclock.perf_counter() - started,
                    "terminated": None if terminated is None else
                    {"instance": getattr(system, "terminated_by", ""), "time": terminated[0],
                     "message": terminated[1]}}
        if stats is not None:
            settings.update(steps=stats.steps, events=stats.events, rhs_calls=stats.rhs_calls)
        return Result({n: table[n] for n in names}, events, settings)
    except IntegrationError as exc:
        raise SimulationError(f"assembly '{assembly.name}': {exc}") from None
    finally:
        for inst in instances.values():
            inst.free()
