"""From an acausal component and one causality profile to an explicit hybrid ODE.

A component writes residuals ``0 = r(der(x), w, x, q, u, p, t)`` in its unknowns
(state derivatives, algebraic variables and whichever port variables the profile
makes outputs). Mechanical equations are linear in those unknowns (accelerations,
forces, multipliers), so they are solved here once, symbolically, and everything
downstream — C code, reference integrators — works on the explicit form

    xdot = f(t, x, q, u, p),   y = h(t, x, q, u, p),   z = zc(t, x, q, u, p),
    (x, q) <- jump(t, x, q, u, p)   at events, iterated until nothing changes.

A profile under which the equations are nonlinear in the unknowns, or have as
many equations as unknowns but a singular Jacobian, is rejected with its name.
"""
from __future__ import annotations

import functools
import itertools
from dataclasses import dataclass, field
from types import SimpleNamespace

from .component import Component
from .interfaces import (FIXED, FORCE_IN, MOTION_IN, SIGNAL_IN, SIGNAL_OUT, ComponentError, Mode)
from .lazy import lazy

ca = lazy("casadi")  # loaded by the first equation written, not by an import
np = lazy("numpy")  # loaded by the first array: listing the components needs none


@dataclass
class Variable:
    """One named scalar of the flat model, with what the FMU needs to declare it."""
    name: str
    unit: str
    description: str
    start: float = 0.0
    derivative_input: int | None = None  # for inputs: index of the input that is its time derivative
    rate_of: int | None = None  # a rate input: index of the chain's end it extrapolates (no equation reads it)
    nominal: float = 1.0


def _rate_unit(unit: str, order: int) -> str:
    """N -> N/s, N/s2, N/s3; m/s2 -> m/s3, m/s4, m/s5."""
    base, per_second, power = unit.partition("/s")
    seconds = (int(power) if power else 1) if per_second else 0
    return f"{base}/s{seconds + order if seconds + order > 1 else ''}"


@dataclass
class FlatModel:
    """The explicit hybrid ODE of one component under one profile (all CasADi SX)."""
    component: Component
    t: ca.SX
    x: ca.SX
    q: ca.SX
    u: ca.SX
    p: ca.SX
    xdot: ca.SX
    y: ca.SX
    z: ca.SX
    jump_x: ca.SX
    jump_q: ca.SX
    g: ca.SX
    states: list[Variable]
    modes: list[Variable]
    inputs: list[Variable]
    parameters: list[Variable]
    outputs: list[Variable]
    indicators: list[Variable]
    constraints: list = field(default_factory=list)
    state_outputs: list[bool] = field(default_factory=list)
    # (mode index, why) of each mode that, once nonzero, ends the run: one for a component
    # with terminate_when, one per such member in a joined model, none for most
    terminate: tuple[tuple[int, str], ...] = ()

    @property
    def args(self):
        return [self.t, self.x, self.q, self.u, self.p]

    def functions(self) -> dict[str, ca.Function]:
        """The model functions of fmus/runtime/model.h, named as the C code expects."""
        args, names = self.args, ["t", "x", "q", "u", "p"]
        jac = ca.densify(ca.jacobian(self.xdot, self.x))
        return {
            "ode": ca.Function("mf_ode", args, [ca.densify(self.xdot)], names, ["xdot"]),
            "out": ca.Function("mf_out", args, [ca.densify(self.y)], names, ["y"]),
            "zc": ca.Function("mf_zc", args, [ca.densify(self.z)], names, ["z"]),
            "jump": ca.Function("mf_jump", args, [ca.densify(self.jump_x), ca.densify(self.jump_q)],
                                names, ["x_new", "q_new"]),
            "check": ca.Function("mf_check", args, [ca.densify(self.g)], names, ["g"]),
            "jac": ca.Function("mf_jac", args, [jac], names, ["jac"]),
        }

    def start_vectors(self):
        """Numeric (x0, q0, u0, p0) from the component's current values."""
        return (np.array([v.start for v in self.states]), np.array([v.start for v in self.modes]),
                np.array([v.start for v in self.inputs]), np.array([v.start for v in self.parameters]))


class _Namespace(SimpleNamespace):
    """Attribute access to symbols, with an error that names what exists."""

    def __init__(self, owner: str, kind: str, **symbols):
        super().__init__(**symbols)
        self._owner, self._kind = owner, kind

    def __getattr__(self, name):  # only called when the attribute is missing
        if name.startswith("_"):
            raise AttributeError(name)
        known = ", ".join(k for k in vars(self) if not k.startswith("_"))
        raise ComponentError(f"{self._owner}: no {self._kind} named '{name}' (known: {known})")


class EquationBuilder:
    """What ``Component.equations(e)`` writes into."""

    def __init__(self, component: Component):
        self.component = component
        where = component._where()
        self.t = ca.SX.sym("t")
        self.p = _Namespace(where, "parameter",
                            **{p.name: ca.SX.sym(p.name) for p in component.parameters})
        self.x = _Namespace(where, "state", **{s.name: ca.SX.sym(s.name) for s in component.states})
        self.der = _Namespace(where, "state",
                              **{s.name: ca.SX.sym(f"der_{s.name}") for s in component.states})
        self.q = _Namespace(where, "mode", **{m.name: ca.SX.sym(m.name) for m in component.modes})
        self.residuals: list[ca.SX] = []
        self.unknowns: list[ca.SX] = [getattr(self.der, s.name) for s in component.states]
        self.outputs: list[tuple[Variable, ca.SX]] = []
        self.indicators: list[tuple[Variable, ca.SX]] = []
        self.jumps: dict[str, ca.SX] = {}
        self.extra_modes: list[tuple[Mode, ca.SX]] = []  # modes the builder adds itself
        self.terminate: list[tuple[str, str]] = []  # (mode name, why): see terminate_on
        self.inputs: list[tuple[Variable, ca.SX]] = []
        self._ports = {}
        for port in component.ports:
            causality = component.profile.ports.get(port.name)
            if causality is None:
                raise ComponentError(f"{where}: profile '{component.profile.name}' "
                                     f"gives no causality to port '{port.name}'")
            self._ports[port.name] = self._make_port(port, causality)

    def _make_port(self, port, causality):
        dom, ns = port.domain, {}
        if dom.flow is None:  # plain signal
            name, unit, desc = port.name, dom.across[0][1], port.description
            sym = ca.SX.sym(name)
            if causality == SIGNAL_IN:
                self.inputs.append((Variable(name, unit, desc), sym))
            elif causality == SIGNAL_OUT:
                self.unknowns.append(sym)
                self.outputs.append((Variable(name, unit, desc), sym))
            else:
                raise ComponentError(f"{self.component._where()}: signal port '{port.name}' "
                                     f"must be '{SIGNAL_IN}' or '{SIGNAL_OUT}', not '{causality}'")
            return sym
        flow_name, flow_unit, flow_desc = dom.flow
        flow = ca.SX.sym(f"{port.name}.{flow_name}")
        ns[flow_name] = flow
        first_input = len(self.inputs)
        for k, (name, unit, desc) in enumerate(dom.across):
            full = f"{port.name}.{name}"
            if causality == FIXED:
                ns[name] = ca.SX(0)
                continue
            sym = ca.SX.sym(full)
            ns[name] = sym
            var = Variable(full, unit, f"{desc} ({port.description})")
            if causality == MOTION_IN:
                if k > 0:  # v is the derivative of s, a of v: the runtime extrapolates with them
                    self.inputs[first_input + k - 1][0].derivative_input = first_input + k
                self.inputs.append((var, sym))
                if k == len(dom.across) - 1:
                    self._rates(port, name, unit, var)
            elif causality == FORCE_IN:
                self.unknowns.append(sym)
                self.outputs.append((var, sym))
            else:
                raise ComponentError(f"{self.component._where()}: flange '{port.name}' must be "
                                     f"'{MOTION_IN}', '{FORCE_IN}' or '{FIXED}', not '{causality}'")
        flow_var = Variable(f"{port.name}.{flow_name}", flow_unit, f"{flow_desc} ({port.description})")
        if causality == FORCE_IN:
            self.inputs.append((flow_var, flow))
            self._rates(port, flow_name, flow_unit, flow_var)
        else:
            self.unknowns.append(flow)  # solved always; exported unless the port is grounded
            if causality == MOTION_IN:
                self.outputs.append((flow_var, flow))
        return _Namespace(f"{self.component._where()} port {port.name}", "port variable", **ns)

    def _rates(self, port, name, unit, last):
        """The first three time derivatives of the last input of a flange's chain (its
        force, or the acceleration of a motion), as inputs along which the FMU
        extrapolates it over a co-simulation step (FMI 3's way of input derivatives, as
        v and a are s's): a master that knows how the input moves sets them, any other
        leaves them at 0 and the input is held. No equation reads them."""
        previous, of = last, len(self.inputs) - 1
        for order, which in ((1, "rate"), (2, "second rate"), (3, "third rate")):
            suffix = "_rate" if order == 1 else f"_rate{order}"
            var = Variable(f"{port.name}.{name}{suffix}", _rate_unit(unit, order),
                           f"{which} of {name} over a co-simulation step, 0: held "
                           f"({port.description})", rate_of=of)
            previous.derivative_input = len(self.inputs)
            self.inputs.append((var, ca.SX.sym(var.name)))
            previous = var

    # --- the vocabulary of equations() ----------------------------------------
    def port(self, name: str):
        if name not in self._ports:
            raise ComponentError(f"{self.component._where()}: no port named '{name}'")
        return self._ports[name]

    def option(self, name: str) -> str:
        return self.component.option(name)

    def unknown(self, name: str) -> ca.SX:
        """An algebraic variable, determined by the residuals."""
        sym = ca.SX.sym(name)
        self.unknowns.append(sym)
        return sym

    def residual(self, expr) -> None:
        self.residuals.append(ca.SX(expr))

    def output(self, name: str, expr, unit: str, description: str) -> None:
        self.outputs.append((Variable(name, unit, description), ca.SX(expr)))

    def indicator(self, expr, description: str) -> None:
        """An event indicator: the runtime stops at each sign change and runs the jumps."""
        name = f"event_indicator_{len(self.indicators) + 1}"
        self.indicators.append((Variable(name, "", description), ca.SX(expr)))

    def terminate_when(self, margin, message: str) -> None:
        """End the simulation, saying `message`, once `margin` falls to zero or below.

        For states where the model stops being valid (a coin fallen flat): the
        runtime locates the crossing like any event and reports terminateSimulation.
        """
        if any(mode == "terminated" for mode, _ in self.terminate):  # its flag's name is taken
            raise ComponentError(f"{self.component._where()}: only one terminate condition")
        flag = ca.SX.sym("terminated")
        self.extra_modes.append((Mode("terminated", 0, f"1 once the run has ended: {message}",
                                      values=(0, 1)), flag))
        self.indicator(margin, f"margin before: {message}")
        self.jumps["terminated"] = ca.if_else(margin <= 0, 1, flag)
        self.terminate.append(("terminated", message))

    def terminate_on(self, mode: str, message: str) -> None:
        """End the simulation, saying `message`, once the declared mode `mode` is nonzero.

        For a model whose jumps already set such a flag: a joined model carries each
        member's terminate flag this way, under the member's reason.
        """
        if mode not in vars(self.q):
            known = ", ".join(k for k in vars(self.q) if not k.startswith("_")) or "none"
            raise ComponentError(f"{self.component._where()}: terminate on unknown mode "
                                 f"'{mode}' (its modes: {known})")
        self.terminate.append((mode, message))

    def jump(self, name: str, expr) -> None:
        """New value of a state or mode at an event (iterated until nothing changes)."""
        if name not in vars(self.x) and name not in vars(self.q):
            raise ComponentError(f"{self.component._where()}: jump of unknown state '{name}'")
        self.jumps[name] = ca.SX(expr)


def _solve_linear(r, w, where):
    """Solve ``r(w) = 0``, linear in w, block by block in block-triangular order.

    Solving each block of the BLT form by substitution keeps trivial equations exact
    (a stuck block's ``a = 0`` stays 0.0, not 1e-16 from a dense factorisation).
    """
    if w.numel() == 0:
        return w
    J = ca.jacobian(r, w)
    if ca.depends_on(J, w):
        raise ComponentError(f"{where}: equations are nonlinear in the unknowns")
    n_blocks, rowperm, colperm, rowblock, colblock, *_ = J.sparsity().btf()
    if ca.sprank(J.sparsity()) < w.numel():
        raise ComponentError(f"{where}: the equations do not determine every unknown")
    solved = {}
    column_of = {w[c].element_hash(): c for c in range(w.numel())}
    for b in range(n_blocks):
        rows = [rowperm[i] for i in range(rowblock[b], rowblock[b + 1])]
        cols = [colperm[i] for i in range(colblock[b], colblock[b + 1])]
        wb = ca.vertcat(*[w[c] for c in cols])
        rb = ca.vertcat(*[r[i] for i in rows])
        # only the solved unknowns this block reads: all solved so far, per block, cost
        # their number each time, quadratic in a joined chain's blocks (a composite of
        # 300 FaultBlocks: 905 blocks, 425,000 element reads)
        known = [c for c in (column_of.get(s.element_hash()) for s in ca.symvar(rb))
                 if c in solved]
        if known:
            rb = ca.substitute(rb, ca.vertcat(*[w[c] for c in known]),
                               ca.vertcat(*[solved[c] for c in known]))
        Jb = ca.jacobian(rb, wb)
        r0 = ca.substitute(rb, wb, ca.DM.zeros(wb.shape))
        if Jb.is_constant():
            Jn = np.array(ca.DM(Jb))
            if abs(np.linalg.det(Jn)) == 0.0:
                raise ComponentError(f"{where}: the equations do not determine every unknown")
            xb = -ca.mtimes(ca.DM(np.linalg.inv(Jn)), r0) if len(cols) > 1 else -r0 / Jn[0, 0]
        else:
            xb = -ca.solve(Jb, r0) if len(cols) > 1 else -r0 / Jb
        for k, c in enumerate(cols):
            solved[c] = xb[k]
    return ca.vertcat(*[solved[i] for i in range(w.numel())])


def _solve_by_mode(r, w, e, component, where):
    """Solve for the unknowns once per combination of mode values, then select by mode.

    Fixing the modes first lets the if_else branches fold away, so each mode gets
    its own exact structure (stuck: ``a = 0``; sliding: ``f = -mu_k m g``).
    """
    q = [getattr(e.q, m.name) for m in component.modes]
    if not q or not ca.depends_on(ca.jacobian(r, w), ca.vertcat(*q)):
        return _solve_linear(r, w, where)
    solution = None
    for values in itertools.product(*[m.values for m in component.modes]):
        rq = ca.substitute(r, ca.vertcat(*q), ca.DM(values))
        branch = _solve_linear(rq, w, f"{where} in modes {values}")
        if solution is None:
            solution = branch
            continue
        selected = functools.reduce(ca.logic_and, [m.selects(qi, v) for m, qi, v
                                                   in zip(component.modes, q, values)])
        solution = ca.if_else(selected, branch, solution)
    return solution


def flatten(component: Component) -> FlatModel:
    """Solve the component's residuals for its unknowns under its profile."""
    e = EquationBuilder(component)
    component.equations(e)
    where = f"{component._where()} (profile '{component.profile.name}')"
    w, r = ca.vertcat(*e.unknowns), ca.vertcat(*e.residuals)
    if w.numel() != r.numel():
        raise ComponentError(f"{where}: {r.numel()} equations for {w.numel()} unknowns")
    solution = _solve_by_mode(r, w, e, component, where)

    def explicit(expr):
        return ca.substitute(ca.SX(expr), w, solution) if w.numel() else ca.SX(expr)

    x = ca.vertcat(*[getattr(e.x, s.name) for s in component.states])
    modes = list(component.modes) + [m for m, _ in e.extra_modes]
    q = ca.vertcat(*[getattr(e.q, m.name) for m in component.modes], *[sym for _, sym in e.extra_modes])
    p = ca.vertcat(*[getattr(e.p, pp.name) for pp in component.parameters])
    u = ca.vertcat(*[sym for _, sym in e.inputs])
    xdot = explicit(ca.vertcat(*[getattr(e.der, s.name) for s in component.states]))
    y = explicit(ca.vertcat(*[expr for _, expr in e.outputs]))
    z = explicit(ca.vertcat(*[expr for _, expr in e.indicators]))
    jump_x = explicit(ca.vertcat(*[e.jumps.get(s.name, getattr(e.x, s.name)) for s in component.states]))
    jump_q = explicit(ca.vertcat(*[e.jumps.get(m.name, q[i]) for i, m in enumerate(modes)]))
    constraints = component.parameter_constraints()
    # start-value constraints read states too; the FMU evaluates them at the start values
    knowns = SimpleNamespace(**{k: v for ns in (e.p, e.x) for k, v in vars(ns).items()
                                if not k.startswith("_")})
    g = ca.vertcat(*[ca.SX(c.g(knowns)) for c in constraints])
    return FlatModel(
        component=component, t=e.t, x=x, q=q, u=u, p=p, xdot=xdot, y=y, z=z,
        jump_x=jump_x, jump_q=jump_q, g=g,
        states=[Variable(s.name, s.unit, s.description, component.starts[s.name], nominal=s.nominal)
                for s in component.states],
        state_outputs=[s.output for s in component.states],
        modes=[Variable(m.name, "", m.description, float(m.start)) for m in modes],
        terminate=tuple(([m.name for m in modes].index(mode), why) for mode, why in e.terminate),
        inputs=[v for v, _ in e.inputs],
        parameters=[Variable(pp.name, pp.unit, pp.description, component.values[pp.name])
                    for pp in component.parameters],
        outputs=[v for v, _ in e.outputs],
        indicators=[v for v, _ in e.indicators],
        constraints=constraints,
    )
