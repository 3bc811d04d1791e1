"""The `monolithic` master: the components' flat models joined into ONE hybrid ODE.

Each component is flattened under the profile the causality resolution gave it;
every connected input is then replaced by ``gain * (the source's output
expression)``, recursively, so the joined model has no coupling left: its inputs
are only the ports nobody connected (free flanges, force input 0). An input that
depends, through direct feedthrough, on an output that depends on that input is an
algebraic loop; a linear one (rigidly joined inertias, a locked clutch) is solved
symbolically, per combination of the modes its coefficients depend on.

Two ways to run it:

- ``engine="reference"`` (default): scipy's error-controlled solvers on the CasADi
  functions of the joined model, events located on the indicators' domains and the
  jump functions iterated, by :mod:`assemblies.hybrid`. No C, no FMI: the accuracy
  reference the other masters are measured against.
- ``engine="fmu"``: the joined model as one FMU (:func:`composite`, built by the
  ordinary ``fmus.build_fmu``) co-simulated alone by the cosim master.
"""
from __future__ import annotations

import functools
import itertools
import time as wallclock
from dataclasses import dataclass
from types import SimpleNamespace
from typing import Callable

import numpy as np

from components.component import Component
from components.dae import _solve_linear, flatten
from components.interfaces import (FORCE_IN, ComponentError, Constraint, Mode, Parameter, Port,
                                   Profile, State)
from components.lazy import lazy

from ..assembly import Assembly, AssemblyError
from ..experiment import check_experiment, output_times
from ..inputs import with_inputs
from ..foreign import check_mode
from ..result import Result, Table
from .hybrid import METHODS, IntegrationError, integrate
from .loops import strongly_connected

ca = lazy("casadi")  # loaded by the first equation written, not by an import


@dataclass
class JoinedModel:
    """The assembly's explicit hybrid ODE; names are ``instance.variable``."""
    t: ca.SX
    x: ca.SX
    q: ca.SX
    u: ca.SX          # the open (unconnected) inputs
    p: ca.SX
    xdot: ca.SX
    z: ca.SX
    jump_x: ca.SX
    jump_q: ca.SX
    signals: dict     # every recordable name -> expression (states, modes, outputs, inputs)
    x0: np.ndarray
    q0: np.ndarray
    u0: np.ndarray
    p0: np.ndarray
    members: dict     # instance -> its FlatModel (for names, units, descriptions)
    outputs: dict     # instance -> names of its FMU outputs, in FMU order
    owner_of_indicator: list[str]
    open_inputs: list[tuple[str, str]]   # (instance, input) in u order
    terminate: list[tuple[int, str, str]]  # (index in q, instance, message)
    couplings: tuple = ()  # the assembly's resolved couplings (source -> target, gain)
    looped: frozenset = frozenset()  # inputs on an algebraic loop, solved in the join


def join(assembly: Assembly) -> JoinedModel:
    """Flatten every component and substitute the connections (see the module doc)."""
    check_mode(assembly, "monolithic")  # a foreign FMU has no equations to flatten
    couplings = assembly.couplings()  # resolves the causality profiles
    members = {name: flatten(comp) for name, comp in assembly.components.items()}
    t = ca.SX.sym("t")

    def symbol_table(m):
        names = {}
        for i, v in enumerate(m.states):
            names[v.name] = m.x[i]
        for i, v in enumerate(m.modes):
            names[v.name] = m.q[i]
        for i, v in enumerate(m.outputs):
            names[v.name] = m.y[i]
        for i, v in enumerate(m.inputs):
            names[v.name] = m.u[i]
        return names

    tables = {name: symbol_table(m) for name, m in members.items()}
    feeds = {c.target: c for c in couplings}
    resolved, looped = _resolve_couplings(assembly, members, tables, feeds)

    # one substitution per member: its time, and its connected inputs by their sources
    open_inputs, u_syms, u0 = [], [], []
    old, new = [], []
    for name, m in members.items():
        old.append(m.t)
        new.append(t)
        for i, v in enumerate(m.inputs):
            if v.rate_of is not None:  # only a co-simulation step reads it
                old.append(m.u[i])
                new.append(ca.SX(0))
            elif (name, v.name) in feeds:
                old.append(m.u[i])
                new.append(resolved[(name, v.name)])
            else:
                open_inputs.append((name, v.name))
                u_syms.append(m.u[i])
                u0.append(v.start)
    cat = lambda attr: ca.vertcat(*[getattr(m, attr) for m in members.values()])  # noqa: E731
    names = [f"{name}.{v}" for name in members for v in tables[name]]
    # twice: a resolved input carries its source member's time symbol
    xdot, z, jump_x, jump_q, *values = substitute_all(
        [cat("xdot"), cat("z"), cat("jump_x"), cat("jump_q"),
         *[sym for name in members for sym in tables[name].values()]],
        ca.vertcat(*old), ca.vertcat(*new), times=2)
    signals, outputs, owners, terminate = dict(zip(names, values)), {}, [], []
    q_offset = 0
    for name, m in members.items():
        outputs[name] = ([v.name for v, out in zip(m.states, m.state_outputs) if out]
                         + [v.name for v in m.outputs] + [v.name for v in m.modes])
        owners += [name] * m.z.numel()
        terminate += [(q_offset + index, name, why) for index, why in m.terminate]
        q_offset += m.q.numel()
    return JoinedModel(
        t=t, x=cat("x"), q=cat("q"), u=ca.vertcat(*u_syms), p=cat("p"),
        xdot=xdot, z=z, jump_x=jump_x, jump_q=jump_q, signals=signals,
        x0=np.concatenate([[v.start for v in m.states] for m in members.values()] + [[]]),
        q0=np.concatenate([[v.start for v in m.modes] for m in members.values()] + [[]]),
        u0=np.array(u0, dtype=float),
        p0=np.concatenate([[v.start for v in m.parameters] for m in members.values()] + [[]]),
        members=members, outputs=outputs, owner_of_indicator=owners,
        open_inputs=open_inputs, terminate=terminate, couplings=tuple(couplings),
        looped=frozenset(looped))


def substitute_all(exprs: list, old: ca.SX, new: ca.SX, times: int = 1) -> list:
    """Each of `exprs` with the symbols `old` replaced by `new`, `times` over, in one
    substitution of them all: one per expression costs the length of `old` each, which
    grows with the assembly, so a pass over every member's expressions was quadratic
    (15 s of a 250-block chain's join)."""
    shapes = [ca.SX(e).shape for e in exprs]
    stacked = ca.vertcat(*[ca.vec(ca.SX(e)) for e in exprs])
    for _ in range(times):
        stacked = ca.substitute(stacked, old, new)
    out, k = [], 0
    for rows, cols in shapes:
        out.append(ca.reshape(stacked[k:k + rows * cols], rows, cols))
        k += rows * cols
    return out


def _resolve_couplings(assembly, members, tables, feeds) -> tuple[dict, set]:
    """(every connected input as an expression in states, modes, parameters, time and open
    inputs: its source's output, with the source's own connected inputs substituted,
    recursively. Inputs on a cycle of direct feedthrough (two inertias held together by
    a gear or a locked clutch: each one's acceleration needs the torque the other's
    acceleration sets) are an algebraic loop; mechanical loops are linear in the loop's
    inputs for given modes, so they are solved here, once per combination of the modes
    the loop's coefficients depend on, and selected by mode (as flatten() solves one
    component's equations); and the inputs on a loop).
    """
    def reads(target):  # the fed inputs `target`'s source output reads directly
        inst, var = feeds[target].source
        if var not in tables[inst]:
            raise AssemblyError(f"assembly '{assembly.name}': {inst} has no variable '{var}'")
        m, expr = members[inst], tables[inst][var]
        return [(inst, v.name) for i, v in enumerate(m.inputs)
                if (inst, v.name) in feeds and ca.depends_on(expr, m.u[i])]

    graph = {target: reads(target) for target in feeds}
    looped = _on_cycles(graph)
    holders = {t: ca.SX.sym(f"loop:{t[0]}.{t[1]}") for t in looped}
    resolved: dict[tuple[str, str], ca.SX] = {}

    def resolve(target):
        if target in resolved:
            return resolved[target]
        inst, var = feeds[target].source
        expr, m = tables[inst][var], members[inst]
        for i, v in enumerate(m.inputs):
            source = (inst, v.name)
            if source in feeds and ca.depends_on(expr, m.u[i]):
                value = holders[source] if source in holders else resolve(source)
                expr = ca.substitute(expr, m.u[i], value)
        resolved[target] = feeds[target].gain * expr
        return resolved[target]

    for target in feeds:
        resolve(target)
    if not holders:
        return resolved, looped
    unknowns = ca.vertcat(*holders.values())
    residual = ca.vertcat(*[holders[t] - resolved[t] for t in holders])
    solution = _solve_loop(assembly, members, residual, unknowns, list(holders))
    return {t: ca.substitute(expr, unknowns, solution) for t, expr in resolved.items()}, looped


def _on_cycles(graph: dict) -> set:
    """The nodes of `graph` (node -> nodes it reads) that lie on a cycle."""
    out = set()
    for component in strongly_connected(graph, lambda v: graph.get(v, ())):
        if len(component) > 1 or component[0] in graph.get(component[0], ()):
            out.update(component)
    return out


def _solve_loop(assembly, members, residual, unknowns, targets):
    """Solve the linear loop ``residual(unknowns) = 0`` per combination of the modes its
    coefficients depend on, selected by mode; one line naming the loop where it cannot."""
    shown = ", ".join(f"{i}.{v}" for i, v in targets)
    where = f"assembly '{assembly.name}': algebraic loop through {shown}"
    J = ca.jacobian(residual, unknowns)
    modes = [(m.q[k], mode) for m in members.values()
             for k, mode in enumerate(m.component.modes) if ca.depends_on(J, m.q[k])]
    try:
        if not modes:
            return _solve_linear(residual, unknowns, where)
        symbols = ca.vertcat(*[q for q, _ in modes])
        solution = None
        for values in itertools.product(*[mode.values for _, mode in modes]):
            fixed = ca.substitute(residual, symbols, ca.DM(values))
            branch = _solve_linear(fixed, unknowns, f"{where} in modes {values}")
            if solution is None:
                solution = branch
                continue
            chosen = functools.reduce(ca.logic_and, [mode.selects(q, v)
                                                     for (q, mode), v in zip(modes, values)])
            solution = ca.if_else(chosen, branch, solution)
        return solution
    except ComponentError as exc:
        raise AssemblyError(f"{exc}; the monolithic master solves linear loops only") from None


# --- the reference integration ------------------------------------------------
class _CasadiStepper:
    """CasADi's own CVODES on the joined model, stepping like a scipy OdeSolver so that the
    shared event driver (:mod:`assemblies.hybrid`) can use it: one step per output
    interval, and "dense output" by integrating again from the step's start, so event
    location sees CVODES's solution to its tolerance, not an interpolant.
    """

    methods = ("CVODES",)

    def __init__(self, system, step, method, t, y, bound, rtol, atol):
        self.system, self.h = system, step
        self.t, self.y, self.t_bound, self.t_old = t, np.asarray(y, dtype=float), bound, None
        self.status = "running"
        self._F = system.cvodes(rtol, atol)

    def _flow(self, t0, y0, t1):
        s = self.system
        p = np.concatenate([s.q, s.u, s.p, [t0, t1 - t0]])
        return np.asarray(self._F(x0=y0, p=p)["xf"]).ravel()

    def step(self):
        t1 = min(self.t + self.h, self.t_bound)
        self.t_old, y_old = self.t, self.y
        self.y, self.t = self._flow(self.t_old, y_old, t1), t1
        self._y_old = y_old
        if self.t >= self.t_bound:
            self.status = "finished"
        return None

    def dense_output(self):
        t0, y0 = self.t_old, self._y_old
        return lambda tt: y0 if tt == t0 else self._flow(t0, y0, tt)


class _JoinedSystem:
    """A JoinedModel as a hybrid system for :func:`assemblies.hybrid.integrate`."""

    def __init__(self, model: JoinedModel, columns: list[str]):
        args = [model.t, model.x, model.q, model.u, model.p]
        self.model = model
        self.ode = ca.Function("ode", args, [model.xdot])
        self.jac = ca.Function("ode_jacobian", args, [ca.jacobian(model.xdot, model.x)])
        self.zc = ca.Function("zc", args, [model.z])
        self.jump = ca.Function("jump", args, [model.jump_x, model.jump_q])
        self.record = ca.Function("record", args, [ca.vertcat(*[model.signals[c] for c in columns])])
        self.outputs = {name: ca.Function(f"out_{name}", args, [ca.vertcat(
            *[model.signals[f"{name}.{v}"] for v in names])]) for name, names in model.outputs.items()}
        self.q, self.u, self.p = model.q0.copy(), model.u0, model.p0
        self.event_rows = {name: [] for name in model.outputs}
        self._cvodes = {}

    def cvodes(self, rtol, atol):
        """CVODES over the unit interval tau, with t = t0 + tau dt: built once, reused for
        every step and every bisection (modes, inputs, parameters, t0 and dt are its p)."""
        if (rtol, atol) not in self._cvodes:
            m = self.model
            tau, t0, dt = ca.SX.sym("tau"), ca.SX.sym("t0"), ca.SX.sym("dt")
            ode = dt * ca.substitute(m.xdot, m.t, t0 + tau * dt)
            dae = {"x": m.x, "t": tau, "p": ca.vertcat(m.q, m.u, m.p, t0, dt), "ode": ode}
            self._cvodes[(rtol, atol)] = ca.integrator(
                "monolithic_cvodes", "cvodes", dae, 0.0, 1.0,
                {"reltol": rtol, "abstol": atol, "max_num_steps": 1_000_000})
        return self._cvodes[(rtol, atol)]

    def rhs(self, t, y):
        return np.asarray(self.ode(t, y, self.q, self.u, self.p)).ravel()

    def jacobian(self, t, y):
        return np.asarray(self.jac(t, y, self.q, self.u, self.p))

    def indicators(self, t, y):
        return np.asarray(self.zc(t, y, self.q, self.u, self.p)).ravel()

    def sample(self, t, y):
        return [t] + np.asarray(self.record(t, y, self.q, self.u, self.p)).ravel().tolist()

    def jumps(self, t, y):
        """Apply the jump functions until nothing changes (the FMUs' event iteration)."""
        for _ in range(100):
            x_new, q_new = (np.asarray(v).ravel() for v in self.jump(t, y, self.q, self.u, self.p))
            if np.array_equal(x_new, y) and np.array_equal(q_new, self.q):
                return y
            y, self.q = x_new, q_new
        raise IntegrationError(f"the jumps do not settle at t = {t:g}")

    def handle_event(self, t, y, changed):
        from .hybrid import EventOutcome
        y = self.jumps(t, y)
        for name in {self.model.owner_of_indicator[i] for i in np.flatnonzero(changed)}:
            row = np.asarray(self.outputs[name](t, y, self.q, self.u, self.p)).ravel().tolist()
            self.event_rows[name].append([t] + row)
        for index, name, message in self.model.terminate:
            if self.q[index] != 0:
                self.terminated_by = name
                return EventOutcome(y, message)
        return EventOutcome(y)


def simulate_monolithic(assembly: Assembly, stop_time: float, step: float, tolerance: float = 1e-10,
                        record: list[str] | None = None, method: str = "DOP853",
                        engine: str = "reference",
                        progress: Callable[[float], None] | None = None,
                        start_time: float = 0.0, inputs=None) -> Result:
    """Simulate the joined model from `start_time`; the table holds every `step` seconds
    (see the module doc). `inputs`: a table feeding open inputs (:mod:`assemblies.inputs`)."""
    check_experiment(stop_time, step, tolerance, "output step", start_time)
    assembly = with_inputs(assembly, inputs)
    if engine == "fmu":
        return _simulate_composite_fmu(assembly, stop_time, step, tolerance, record, progress,
                                       start_time)
    if engine != "reference":
        raise AssemblyError(f"engine must be 'reference' or 'fmu', not '{engine}'")
    if method not in METHODS and method not in _CasadiStepper.methods:
        raise AssemblyError(f"method must be one of {', '.join((*METHODS, *_CasadiStepper.methods))}, "
                            f"not '{method}'")
    solver = "CasADi's CVODES" if method in _CasadiStepper.methods else f"scipy's {method}"
    started = wallclock.perf_counter()
    model = join(assembly)
    columns = _columns(model, record)
    system = _JoinedSystem(model, columns)
    system.stepper = functools.partial(_CasadiStepper, system, step)
    system.stepper_methods = _CasadiStepper.methods
    # the components' current values, not only their defaults at flatten time
    x0 = model.x0.copy()
    system.p = np.array(model.p0)
    y0 = system.jumps(start_time, x0)  # the event iteration at initialization, as the FMUs do
    times = output_times(stop_time, step, start_time)
    try:
        rows, stats, terminated = integrate(system, y0, stop_time, times, method=method,
                                            rtol=tolerance, atol=tolerance * 1e-2,
                                            progress=progress)
    except IntegrationError as exc:
        from .cosim import SimulationError
        raise SimulationError(f"assembly '{assembly.name}': {exc}") from None
    names = ["time"] + columns
    table = Table.from_rows(names, rows)
    events = {name: Table.from_rows(["time"] + [f"{name}.{v}" for v in model.outputs[name]], rows_)
              for name, rows_ in system.event_rows.items() if rows_}
    settings = {"start_time": start_time, "stop_time": stop_time, "step": step,
                "tolerance": tolerance, "scheme": "monolithic", "method": method,
                # the Python masters' engine, and what this one of them ran: no FMU at all
                "engine": "fmpy", "master": f"the joined CasADi model under {solver}, no FMU",
                "wall_s": wallclock.perf_counter() - started,
                "steps": stats.steps, "events": stats.events, "rhs_calls": stats.rhs_calls,
                "terminated": None if terminated is None else
                {"instance": getattr(system, "terminated_by", ""), "time": terminated[0],
                 "message": terminated[1]}}
    return Result({n: table[n] for n in names}, events, settings)


def _columns(model: JoinedModel, record):
    if record is None:
        return [f"{name}.{v}" for name, names in model.outputs.items() for v in names]
    for ref in record:
        if ref not in model.signals:
            instance = ref.partition(".")[0]
            known = [n for n in model.signals if n.startswith(instance + ".")]
            raise AssemblyError(f"cannot record '{ref}': the joined model has no such variable; "
                                f"{instance} has: {', '.join(known) or '(no instance of that name)'}")
    return list(record)


# --- the joined model as one component, hence one FMU -----------------------------
class Composite(Component):
    """An assembly joined into one model (built per assembly by :func:`composite`)."""

    joined: JoinedModel
    open_ports: tuple = ()  # (port name in the composite, instance, port)

    def vectorised_functions(self, model) -> dict:
        # a large assembly: one function per member kind, mapped over the members, so
        # that the C grows with the kinds, not with the flattened expression; a loop is
        # solved across members in the join, which no member's own function can express
        from .composite_code import member_functions, worth_mapping
        if self.joined.looped or not worth_mapping(model):
            return {}
        return member_functions(self.joined, model, c_code=True)

    def equations(self, e):
        m = self.joined
        old = [m.t]
        new = [e.t]
        for name, member in m.members.items():
            for i, v in enumerate(member.states):
                old.append(member.x[i])
                new.append(getattr(e.x, f"{name}.{v.name}"))
            for i, v in enumerate(member.modes):
                old.append(member.q[i])
                new.append(getattr(e.q, f"{name}.{v.name}"))
            for i, v in enumerate(member.parameters):
                old.append(member.p[i])
                new.append(getattr(e.p, f"{name}.{v.name}"))
        ports = {(inst, port): e.port(full) for full, inst, port in self.open_ports}
        for k, (inst, var) in enumerate(m.open_inputs):
            port, _, flow = var.rpartition(".")
            old.append(m.u[k])
            new.append(getattr(ports[(inst, port)], flow))
        # every expression the composite states, substituted at once (substitute_all)
        shown = [f"{name}.{v.name}" for name, member in m.members.items()
                 for v in member.outputs]
        xdot, jx, jq, z, *values = substitute_all(
            [m.xdot, m.jump_x, m.jump_q, m.z, *[m.signals[full] for full in shown]],
            ca.vertcat(*old), ca.vertcat(*new))
        signal = dict(zip(shown, values))
        k = 0
        for name, member in m.members.items():
            for v in member.states:
                e.residual(getattr(e.der, f"{name}.{v.name}") - xdot[k])
                k += 1
        for name, member in m.members.items():
            for v in member.outputs:
                port, _, across = v.name.rpartition(".")
                full = f"{name}.{v.name}"
                if (name, port) in ports:  # an open flange: its motion is the port's output
                    e.residual(getattr(ports[(name, port)], across) - signal[full])
                else:
                    e.output(full, signal[full], v.unit, v.description)
        for i, owner in enumerate(m.owner_of_indicator):
            e.indicator(z[i], f"{owner}: indicator")
        k = 0
        for name, member in m.members.items():
            for v in member.states:
                e.jump(f"{name}.{v.name}", jx[k])
                k += 1
        modes = [f"{name}.{v.name}" for name, member in m.members.items() for v in member.modes]
        for k, name in enumerate(modes):
            e.jump(name, jq[k])
        # the member's flag ends the joined run where it would end the member's own, and
        # the reason names the member: one FMU has one instance name for all of them
        for index, name, why in m.terminate:
            e.terminate_on(modes[index], f"{name}: {why}")


def composite(assembly: Assembly) -> Composite:
    """The assembly as one Component, so ``fmus.build_fmu`` builds it into one FMU.

    Parameters, states and modes are the members' with ``instance.`` prefixed, their
    current values as defaults; unconnected flanges become the composite's ports.
    """
    model = join(assembly)
    parameters, states, modes, ports, constraints, open_ports = [], [], [], [], [], []
    for name, comp in assembly.components.items():
        for p in comp.parameters:
            parameters.append(Parameter(f"{name}.{p.name}", comp.values[p.name], p.unit,
                                        f"{name}: {p.description}", p.min, p.max, p.min_strict))
        for s in comp.states:
            states.append(State(f"{name}.{s.name}", comp.starts[s.name], s.unit,
                                f"{name}: {s.description}", s.output))
        # the values a mode can take: as the member declares them; the flags the builder
        # adds (terminate_when) are 0 or 1
        declared = {mode.name: mode for mode in comp.modes}
        for v in model.members[name].modes:
            mode = declared.get(v.name)
            modes.append(Mode(f"{name}.{v.name}", int(v.start), f"{name}: {v.description}",
                              mode.values if mode else (0, 1), mode.also if mode else ()))
        for c in comp.constraints:
            names = [p.name for p in comp.parameters]
            constraints.append(Constraint(
                lambda ns, c=c, name=name, names=names: c.g(SimpleNamespace(
                    **{n: getattr(ns, f"{name}.{n}") for n in names})),
                f"{name}: {c.message}", c.strict))
        for port in comp.ports:
            if port.name in {v.name.rpartition(".")[0] for v in model.members[name].inputs} and \
                    any(i == name and v.startswith(port.name + ".") for i, v in model.open_inputs):
                if comp.profile.ports[port.name] != FORCE_IN:
                    raise AssemblyError(f"{name}.{port.name}: an open port of a composite must "
                                        f"be a free flange ('{FORCE_IN}')")
                ports.append(Port(f"{name}.{port.name}", port.domain, f"{name}: {port.description}"))
                open_ports.append((f"{name}.{port.name}", name, port.name))
    doc = f"The assembly '{assembly.name}' as one model: {', '.join(assembly.components)}."
    cls = type(assembly.name, (Composite,), {
        "__doc__": doc, "joined": model, "open_ports": tuple(open_ports),
        "parameters": tuple(parameters), "states": tuple(states), "modes": tuple(modes),
        "ports": tuple(ports), "constraints": tuple(constraints),
        "profiles": (Profile("assembled", "connections inside; open flanges take a force",
                             {p.name: FORCE_IN for p in ports}),),
        "default_stop_time": max(c.default_stop_time for c in assembly.components.values())})
    return cls()


def _simulate_composite_fmu(assembly, stop_time, step, tolerance, record, progress,
                            start_time=0.0):
    from .cosim import cosimulate
    single = Assembly(assembly.name)
    joined = single.add("assembly", composite(assembly)).joined
    inner = None if record is None else [f"assembly.{r}" for r in record]
    res = cosimulate(single, stop_time, step, tolerance, record=inner, progress=progress,
                     start_time=start_time)
    columns = {("time" if n == "time" else n.removeprefix("assembly.")): res[n] for n in res.columns}
    # one FMU cannot say which member an event belongs to: every member sees all of them
    events = {}
    if "assembly" in res.events:
        ev = res.events["assembly"]
        for name in assembly.components:
            cols = {"time": ev["time"]}
            cols.update({n.removeprefix("assembly."): ev[n] for n in ev.columns
                         if n.startswith(f"assembly.{name}.")})
            events[name] = Table(cols)
    from ..engine.prepare import member_termination
    settings = dict(res.settings, scheme="monolithic", engine="fmpy",
                    master="the joined model as one FMU, co-simulated through fmpy",
                    terminated=member_termination(res.settings.get("terminated"),
                                                  [(n, why) for _, n, why in joined.terminate],
                                                  "assembly"))
    return Result(columns, events, settings)
