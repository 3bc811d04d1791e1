"""Our side of the benchmark: FMUs through fmpy, the `me` and `monolithic` masters, CasADi.

Every runner returns (values of the observed variable at the output times, rhs_evals,
steps), with None for a count the method does not expose. Wall time is taken by the
caller around the runner alone: building FMUs (and joining models) happens once, before.
"""
from __future__ import annotations

import contextlib
import math
import re

import casadi as ca
import numpy as np
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi3 import FMU3Slave

import assemblies.masters.cosim as cosim_module
from assemblies.masters.cosim import cosimulate
from assemblies.masters.hybrid import integrate
from assemblies.masters.me import simulate_me
from assemblies.masters.monolithic import _columns, _JoinedSystem, join
from components.dae import flatten
from fmus import build_fmu

SOLVERS = {"DOPRI5": 0, "RODAS3": 1}  # values of the FMU's Int32 parameter `solver`
_WORK = re.compile(r"(\d+) steps, (\d+) rejected, (\d+) derivative evaluations")


def class_default_fmu(component):
    """The FMU the masters use: built with class defaults and the instance's options, so one
    compiled FMU serves every parameter value (values are set at run time)."""
    defaults = type(component)(name=component.name, profile=component.profile.name,
                               **component.option_values)
    return build_fmu(defaults)


@contextlib.contextmanager
def builds_memoised():
    """Let the masters find their FMUs without re-flattening and re-hashing each run: the
    build (and its cache lookup, which regenerates the C code) is a one-time cost. Every
    master loads its FMUs through the co-simulation module's loader."""
    memo, original = {}, cosim_module.build_fmu

    def lookup(component, *args, **kwargs):
        key = (type(component).__name__, component.profile.name,
               tuple(sorted(component.option_values.items())), args, tuple(kwargs.items()))
        if key not in memo:
            memo[key] = original(component, *args, **kwargs)
        return memo[key]

    cosim_module.build_fmu = lookup
    try:
        yield
    finally:
        cosim_module.build_fmu = original


class SingleFmu:
    """One component's FMU, extracted once, run by hand through fmpy's low-level classes.

    The component has no inputs that vary (a scene's driver is joined into it with
    assemblies.masters.monolithic.composite): fmpy's Model Exchange loop holds inputs constant
    between output points, which would be the error measured, not the solver's."""

    def __init__(self, component, observed: str):
        component.validate()
        self.component, self.observed = component, observed
        self.path = class_default_fmu(component)
        self.md = read_model_description(self.path)
        self.dir = extract(self.path)
        self.vars = {v.name: v for v in self.md.modelVariables}
        self.start = {**component.values, **component.starts}

    # --- Co-Simulation: one doStep per output interval -------------------------------
    def _slave(self, tol, solver, stop_time, log=None):
        fmu = FMU3Slave(guid=self.md.guid, unzipDirectory=self.dir,
                        modelIdentifier=self.md.coSimulation.modelIdentifier, instanceName="bench")
        fmu.instantiate(loggingOn=False, logMessage=log)
        if log is not None:
            fmu.setDebugLogging(True, ["logSolver"])
        floats = [(self.vars[k].valueReference, float(v)) for k, v in self.start.items()
                  if self.vars[k].type == "Float64"]
        fmu.setFloat64([vr for vr, _ in floats], [v for _, v in floats])
        ints = {k: int(v) for k, v in self.start.items() if self.vars[k].type == "Int32"}
        ints["solver"] = solver
        fmu.setInt32([self.vars[k].valueReference for k in ints], list(ints.values()))
        return fmu

    def cosim(self, times, tol, solver: str, count: bool = False):
        """values at `times`; with count=True also parse the runtime's logSolver lines."""
        work = [0, 0]

        def log(env, status, category, message):
            found = _WORK.search(message.decode() if isinstance(message, bytes) else message)
            if found:
                work[0] += int(found.group(1))
                work[1] += int(found.group(3))

        fmu = self._slave(tol, SOLVERS[solver], times[-1], log if count else None)
        vr_out = [self.vars[self.observed].valueReference]
        out = np.empty(len(times))
        try:
            fmu.enterInitializationMode(tolerance=tol, startTime=times[0], stopTime=times[-1])
            fmu.exitInitializationMode()
            out[0] = fmu.getFloat64(vr_out)[0]
            for i in range(1, len(times)):
                fmu.doStep(times[i - 1], times[i] - times[i - 1])
                out[i] = fmu.getFloat64(vr_out)[0]
            fmu.terminate()
        finally:
            fmu.freeInstance()
        return out, (work[1] if count else None), (work[0] if count else None)

    # --- Model Exchange under fmpy's CVode -----------------------------------------
    def cvode(self, times, tol, count: bool = False):
        calls = [0]

        def call_logger(message):
            if "GetContinuousStateDerivatives" in message:
                calls[0] += 1

        start = {k: v for k, v in self.start.items() if k in self.vars}
        res = simulate_fmu(self.dir, validate=False, model_description=self.md,
                           fmi_type="ModelExchange", solver="CVode", relative_tolerance=tol,
                           start_time=times[0], stop_time=times[-1],
                           output_interval=times[1] - times[0], start_values=start,
                           output=[self.observed],
                           fmi_call_logger=call_logger if count else None)
        # rows at events repeat a time; the last row at each output time is the value there
        t, y = res["time"], res[self.observed]
        idx = np.clip(np.searchsorted(t, times + 1e-12 * (1 + abs(times)), side="right") - 1,
                      0, len(t) - 1)
        return y[idx], (calls[0] if count else None), None

    # --- CasADi's own integrator on the same flat model (smooth models only) ------
    def casadi(self, times, tol):
        # the flat model is a one-time cost, like an FMU build: made once, outside the timing
        if not hasattr(self, "_flat"):
            self._flat = flatten(self.component)
        model = self._flat
        _, q0, u0, p0 = model.start_vectors()
        x0 = np.array([self.component.starts[v.name] for v in model.states])
        # modes held at their start: only models whose modes do not enter xdot come here
        ode = ca.substitute(model.xdot, ca.vertcat(model.q, model.u, model.p),
                            ca.vertcat(ca.DM(q0), ca.DM(u0), ca.DM(p0)))
        F = ca.integrator("F", "cvodes", {"t": model.t, "x": model.x, "ode": ode},
                          float(times[0]), [float(t) for t in times[1:]],
                          {"reltol": tol, "abstol": tol * 1e-2, "max_num_steps": 10**7})
        X = np.hstack([x0[:, None], np.asarray(F(x0=x0)["xf"])])
        names = [v.name for v in model.states]
        if self.observed in names:
            values = X[names.index(self.observed)]
        else:
            out = model.functions()["out"].map(len(times))
            T = ca.DM(times).T
            k = [v.name for v in model.outputs].index(self.observed)
            values = np.asarray(out(T, X, *(ca.repmat(ca.DM(v), 1, len(times))
                                            for v in (q0, u0, p0))))[k]
        stats = F.stats()
        return values, stats.get("nfevals"), stats.get("nsteps")


class Masters:
    """The assembly-level masters: `me`, `monolithic` (joined once) and `cosim`."""

    def __init__(self, assembly, column: str):
        self.assembly, self.column = assembly, column
        self.joined = join(assembly)

    def me(self, times, tol, method="DOP853"):
        with builds_memoised():
            res = simulate_me(self.assembly, times[-1], times[1] - times[0], tol,
                              record=[self.column], method=method)
        return (np.asarray(res[self.column]), res.settings.get("rhs_calls"),
                res.settings.get("steps"))

    def cosim(self, times, tol, substeps: int = 1):
        """Co-simulation with `substeps` communication steps per output interval: the
        communication step, not the FMUs' tolerance, bounds a co-simulation's accuracy."""
        with builds_memoised():
            res = cosimulate(self.assembly, times[-1], (times[1] - times[0]) / substeps, tol,
                             record=[self.column])
        values = np.asarray(res[self.column])[::substeps]
        if len(values) != len(times):
            raise RuntimeError(f"co-simulation gave {len(values)} rows for {len(times)} times")
        return values, None, None

    def engine(self, times, tol, mode="me", count=True):
        """The compiled engine's run of the assembly (`me`: its Model Exchange FMUs in one
        integrator; `monolithic`: the one composite FMU), called as a user calls it: no
        build memo, the FMUs already built by an earlier (untimed) call in this process.
        count=False leaves the settings unread, as a user who wants the values does (they
        are made when first read: Result.settings)."""
        from assemblies.engine import me as engine
        simulate = engine.simulate_me if mode == "me" else engine.simulate_monolithic
        res = simulate(self.assembly, times[-1], times[1] - times[0], tol, record=[self.column])
        if not count:
            return np.asarray(res[self.column]), None, None
        return (np.asarray(res[self.column]), res.settings.get("rhs_calls"),
                res.settings.get("steps"))

    def monolithic(self, times, tol, method="DOP853"):
        model = self.joined
        system = _JoinedSystem(model, _columns(model, [self.column]))
        system.p = np.array(model.p0)
        y0 = system.jumps(0.0, model.x0.copy())
        rows, stats, _ = integrate(system, y0, times[-1], times, method=method, rtol=tol,
                                   atol=tol * 1e-2)
        return np.array([r[1] for r in rows]), stats.rhs_calls, stats.steps


def engine_missing() -> str | None:
    """Why the compiled engine cannot be benchmarked here, or None when it can."""
    try:
        from assemblies.engine.me import simulate_me, simulate_monolithic  # noqa: F401
    except ImportError as exc:
        return f"engine skipped: assemblies.engine.me is not importable ({exc})"
    return None


def max_error(values, reference) -> float:
    err = np.abs(np.asarray(values, float) - np.asarray(reference, float))
    return float(np.max(err)) if np.all(np.isfinite(err)) else math.inf
