"""The co-simulation master: FMI 3 Co-Simulation FMUs driven through fmpy.

Fixed communication step, Jacobi (default) or Gauss–Seidel. Inputs set at a
communication point are, for the FMU, values at that point: our FMUs extrapolate
kinematic inputs over the step through their derivative inputs (s with v and a),
which is why Jacobi is the accurate default for kinematic chains. Events that an
FMU locates inside a step are recorded through FMI 3 intermediate update.
"""
from __future__ import annotations

import math
import time as wallclock
from typing import Callable

from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi3 import FMU3Slave

from fmus import build_fmu

from .assembly import Assembly, AssemblyError
from .result import Result, Table


class SimulationError(RuntimeError):
    """An FMU refused a call; the message carries what the FMU logged."""


class _Instance:
    """One FMU instance in a running co-simulation."""

    def __init__(self, name: str, component, tolerance: float):
        self.name = name
        self.component = component
        # built with class defaults, so parameter studies reuse one compiled FMU
        defaults = type(component)(name=name, profile=component.profile.name,
                                   **component.option_values)
        path = build_fmu(defaults)
        md = read_model_description(path)
        self.variables = {v.name: v for v in md.modelVariables}
        self.outputs = [v.name for v in md.modelVariables if v.causality == "output"]
        self.messages: list[str] = []
        self.event_rows: list[list[float]] = []
        self._unzipped = extract(path)
        self.fmu = FMU3Slave(guid=md.guid, unzipDirectory=self._unzipped,
                             modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        self.fmu.instantiate(loggingOn=False, logMessage=self._log,
                             intermediateUpdate=self._intermediate_update)
        self.tolerance = tolerance

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

    def free(self) -> None:
        try:
            self.fmu.terminate()
        except Exception:
            pass
        try:
            self.fmu.freeInstance()
        except Exception:
            pass


def cosimulate(assembly: Assembly, stop_time: float, step: float, tolerance: float = 1e-8,
               record: list[str] | None = None, scheme: str = "jacobi",
               progress: Callable[[float], None] | None = None) -> Result:
    """Co-simulate `assembly` from 0 to `stop_time` with communication step `step`."""
    if not (math.isfinite(stop_time) and stop_time > 0):
        raise AssemblyError(f"stop time must be a positive finite number, not {stop_time}")
    if not (math.isfinite(step) and step > 0):
        raise AssemblyError(f"communication step must be a positive finite number, not {step}")
    if not (math.isfinite(tolerance) and 0 < tolerance < 1):
        raise AssemblyError(f"tolerance must be in (0, 1), not {tolerance}")
    if scheme not in ("jacobi", "gauss-seidel"):
        raise AssemblyError(f"scheme must be 'jacobi' or 'gauss-seidel', not '{scheme}'")
    couplings = assembly.couplings()
    instances: dict[str, _Instance] = {}
    started = wallclock.perf_counter()
    try:
        for name, comp in assembly.components.items():
            instances[name] = _Instance(name, comp, tolerance)
        columns = _record_columns(instances, record)

        def propagate(targets=None):
            for c in couplings:
                if targets is None or c.target[0] in targets:
                    value = instances[c.source[0]].get([c.source[1]])[0]
                    instances[c.target[0]].set(c.target[1], c.gain * value)

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
        for _ in range(len(instances)):  # settles any loop-free chain of outputs
            propagate()
        for inst in instances.values():
            inst.call("exit initialization", inst.fmu.exitInitializationMode)
        propagate()
        rows = [sample(0.0)]
        n_steps = max(1, math.ceil(stop_time / step - 1e-9))
        order = assembly.order()
        terminated = None

        def step_one(name, t, h):
            nonlocal terminated
            inst = instances[name]
            _, stop, _, reached = inst.call(f"doStep at t = {t:g}", inst.fmu.doStep, t, h)
            if stop and terminated is None:  # the model says it cannot go on (why: in its log)
                terminated = {"instance": name, "time": reached,
                              "message": inst.messages[-1] if inst.messages else ""}

        for k in range(n_steps):
            t = k * step
            h = min(step, stop_time - t) if k < n_steps - 1 else stop_time - t
            if scheme == "jacobi":
                for name in instances:
                    step_one(name, t, h)
                propagate()
            else:
                for name in order:
                    propagate({name})
                    step_one(name, t, h)
                propagate()
            rows.append(sample(t + h))
            if progress is not None:
                progress(t + h)
            if terminated is not None:
                break
        names = ["time"] + [f"{i}.{v}" for i, v in columns]
        table = Table.from_rows(names, rows)
        events = {name: Table.from_rows(["time"] + [f"{name}.{v}" for v in inst.outputs],
                                        inst.event_rows)
                  for name, inst in instances.items() if inst.event_rows}
        settings = {"stop_time": stop_time, "step": step, "tolerance": tolerance, "scheme": scheme,
                    "wall_s": wallclock.perf_counter() - started, "terminated": terminated}
        return Result({n: table[n] for n in names}, events, settings)
    finally:
        for inst in instances.values():
            inst.free()


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
