"""An assembly: named component instances and the connections between their ports.

Connections follow Modelica: a flange connects to a flange of the same domain,
across variables are equal and flows sum to zero. For co-simulation one side of
each flange connection computes the motion (its port is ``force`` in its profile)
and the other the force (``motion``). ``connect`` rejects a pair that no profile
could ever fit; ``resolve_causality`` (called by every master, through
``couplings``) then picks each component's profile from the whole graph
(:mod:`assemblies.causality`), keeping the ones the user named.
"""
from __future__ import annotations

from dataclasses import dataclass

from components.component import Block
from components.errors import MechfmuError
from components.interfaces import (FIXED, FORCE_IN, SIGNAL_IN, SIGNAL_OUT, ComponentError,
                                   Port, connectable, describe_signal)

from .causality import CausalityError, Link, compatible, port_causalities, resolve
from .value_types import article, coupling_rule, element_names, feeds


class AssemblyError(MechfmuError, ValueError):
    """Bad input to an assembly: the message names the instance, port or variable."""


@dataclass(frozen=True)
class Coupling:
    """One scalar of a connection: ``target.input = gain * source.output``."""
    source: tuple[str, str]  # (instance, variable)
    target: tuple[str, str]
    gain: float = 1.0


@dataclass(frozen=True)
class Connection:
    a: str  # "instance.port"
    b: str


class Assembly:
    def __init__(self, name: str):
        if not isinstance(name, str) or not name.isidentifier():
            # it names the composite or exported FMU, its model identifier and its files
            raise AssemblyError(f"assembly name {name!r} must be an identifier (letters, "
                                "digits, _; not starting with a digit)")
        self.name = name
        self.components: dict[str, Block] = {}
        self.connections: list[Connection] = []
        # set while the assembly is exported as one FMU: its open signal inputs are then
        # the FMU's inputs, fed from outside, instead of dangling
        self.signals_from_outside = False

    def add(self, instance: str, component: Block) -> Block:
        """Add `component` (one of ours, or any FMU: :class:`assemblies.foreign.FMU`)."""
        if not isinstance(instance, str) or not instance.isidentifier():
            raise AssemblyError(f"assembly '{self.name}': instance name '{instance}' "
                                "must be an identifier (letters, digits, _)")
        if instance in self.components:
            raise AssemblyError(f"assembly '{self.name}': instance '{instance}' already exists")
        if not isinstance(component, Block):
            raise AssemblyError(f"assembly '{self.name}': instance '{instance}' must be a "
                                "component (e.g. SpringBlock()) or an assemblies.FMU, not "
                                f"{type(component).__name__} {component!r}")
        component.name = instance
        self.components[instance] = component
        return component

    def component(self, instance: str) -> Block:
        if instance not in self.components:
            raise AssemblyError(f"assembly '{self.name}': no instance '{instance}'; "
                                f"instances: {', '.join(self.components)}")
        return self.components[instance]

    def _port(self, ref: str) -> tuple[str, Port, str]:
        """(instance, port, causality under the component's current profile)."""
        instance, _, port_name = ref.partition(".")
        comp = self.component(instance)
        for port in comp.ports:
            if port.name == port_name:
                return instance, port, comp.profile.ports[port.name]
        raise AssemblyError(f"assembly '{self.name}': {comp._where()} has no port "
                            f"'{port_name}'; ports: {', '.join(p.name for p in comp.ports)}")

    def connect(self, a: str, b: str) -> None:
        """Connect two ports, e.g. ``connect("driver.flange", "block.flange_a")``.

        Any two ports of one domain may be connected if some pair of the components'
        available profiles fits them; which pair is decided by ``resolve_causality``.
        """
        (ia, pa, _), (ib, pb, _) = self._port(a), self._port(b)
        if pa.shape != pb.shape:
            def shown(port):
                return f"an array {list(port.shape)}" if port.shape else "a scalar"
            raise AssemblyError(f"cannot connect {a} to {b}: {a} is {shown(pa)}, {b} is "
                                f"{shown(pb)}; arrays connect whole, to an array of one shape")
        if self._signal_types_differ(a, pa, b, pb):
            pass  # checked (one line, naming both) by _signal_types_differ
        elif not connectable(pa.domain, pb.domain):
            if pa.domain.flow is None and pb.domain.flow is None:
                raise AssemblyError(
                    f"cannot connect {a} to {b}: {a} is {describe_signal(pa.domain)}, {b} is "
                    f"{describe_signal(pb.domain)}; a connection joins signals of one type and unit")
            raise AssemblyError(f"cannot connect {a} ({pa.domain.name}) to {b} ({pb.domain.name}): "
                                "ports must be of the same domain and unit")
        kinds_a = port_causalities(self.components[ia], pa.name)
        kinds_b = port_causalities(self.components[ib], pb.name)
        for ref, kinds, comp in ((a, kinds_a, self.components[ia]), (b, kinds_b, self.components[ib])):
            if kinds == [FIXED]:
                where = "its profile" if len(comp.profiles) == 1 or comp.profile_explicit \
                    else "every profile"
                raise AssemblyError(f"cannot connect {a} to {b}: {ref} is grounded in {where}")
        for ref, port, kinds in ((a, pa, kinds_a), (b, pb, kinds_b)):
            # an input takes one source: say so now, naming both, not at the first run
            if port.domain.flow is None and kinds == [SIGNAL_IN]:
                for c in self.connections:
                    if ref in (c.a, c.b):
                        raise AssemblyError(
                            f"cannot connect {a} to {b}: input {ref} is already fed by "
                            f"{c.b if c.a == ref else c.a}; an input takes one source")
        if not any(compatible(x, y) for x in kinds_a for y in kinds_b):
            ca, cb = "/".join(k for k in kinds_a if k != FIXED), "/".join(k for k in kinds_b if k != FIXED)
            raise AssemblyError(
                f"cannot connect {a} ({ca}) to {b} ({cb}): one side must compute the motion "
                f"(profile '{FORCE_IN}') and the other the force (profile 'motion'), "
                "or a signal output must feed a signal input")
        self.connections.append(Connection(a, b))

    def _signal_types_differ(self, a: str, pa: Port, b: str, pb: Port) -> bool:
        """Two signals of different FMI types: True where the output's type may feed the
        input's (value_types.feeds) and the units agree; an AssemblyError otherwise."""
        da, db = pa.domain, pb.domain
        if da.flow is not None or db.flow is not None or da.value_type == db.value_type:
            return False
        ka, kb = (port_causalities(self.components[i], p.name)
                  for i, p in ((a.partition(".")[0], pa), (b.partition(".")[0], pb)))
        if ka == [SIGNAL_IN] and kb == [SIGNAL_OUT]:
            (a, da), (b, db) = (b, db), (a, da)
        elif not (ka == [SIGNAL_OUT] and kb == [SIGNAL_IN]):
            return False  # no direction to judge: connectable() names the type clash
        if not feeds(da.value_type, db.value_type):
            raise AssemblyError(f"cannot connect {a} to {b}: {article(da.value_type)} output "
                                f"cannot feed {article(db.value_type)} input; {coupling_rule()}")
        ua, ub = da.across[0][1], db.across[0][1]
        if ua and ub and ua != ub:
            raise AssemblyError(f"cannot connect {a} to {b}: {a} is {describe_signal(da)}, {b} "
                                f"is {describe_signal(db)}; a connection joins signals of one unit")
        return True

    def resolve_causality(self) -> dict[str, str]:
        """Give every component a profile that fits the connections; instance -> profile name.

        Components made with ``profile=...`` keep theirs; the others get the first of
        their profiles (in declaration order) that makes every connection one motion
        side against one force side and leaves no required input unconnected.
        """
        links = []
        for conn in self.connections:
            (ia, pa, _), (ib, pb, _) = self._port(conn.a), self._port(conn.b)
            links.append(Link((ia, pa.name), (ib, pb.name)))
        try:
            chosen = resolve(self.name, self.components, links, self.signals_from_outside)
        except CausalityError as exc:
            raise AssemblyError(str(exc)) from None
        for name, profile in chosen.items():
            self.components[name].profile = profile
        return {name: profile.name for name, profile in chosen.items()}

    def couplings(self) -> list[Coupling]:
        """The connections as scalar input <- output assignments (profiles resolved first)."""
        self.resolve_causality()
        out, fed = [], {}
        for conn in self.connections:
            (ia, pa, ca), (ib, pb, _) = self._port(conn.a), self._port(conn.b)
            if pa.domain.flow is None:
                src, dst = ((ia, pa), (ib, pb)) if ca == SIGNAL_OUT else ((ib, pb), (ia, pa))
                # an array couples element by element, in the same (row-major) order
                for s, d in zip(element_names(src[1].name, src[1].shape),
                                element_names(dst[1].name, dst[1].shape)):
                    out.append(Coupling((src[0], s), (dst[0], d)))
                continue
            # the motion side (port FORCE_IN) feeds its across variables to the other side
            (im, pm), (if_, pf) = ((ia, pa), (ib, pb)) if ca == FORCE_IN else ((ib, pb), (ia, pa))
            for name, _, _ in pa.domain.across:
                out.append(Coupling((im, f"{pm.name}.{name}"), (if_, f"{pf.name}.{name}")))
            flow = pa.domain.flow[0]
            # flows sum to zero: the force on one side is minus the force on the other
            out.append(Coupling((if_, f"{pf.name}.{flow}"), (im, f"{pm.name}.{flow}"), -1.0))
        for c in out:
            if c.target in fed:
                raise AssemblyError(f"assembly '{self.name}': input {'.'.join(c.target)} is fed twice "
                                    f"(by {'.'.join(fed[c.target])} and {'.'.join(c.source)})")
            fed[c.target] = c.source
        return out

    def set(self, name: str, value) -> None:
        """Set ``instance.parameter`` (or a start value or an option), with checks."""
        instance, dot, key = name.partition(".")
        if not dot or not key:
            raise AssemblyError(f"'{name}' must be INSTANCE.NAME, e.g. block.mu_s")
        comp = self.component(instance)
        comp.set(key, value)
        comp.validate()

    def order(self) -> list[str]:
        """Instances with the ones that feed others first (a Gauss–Seidel sweep order)."""
        deps = {name: set() for name in self.components}
        for c in self.couplings():
            if c.source[0] != c.target[0]:
                deps[c.target[0]].add(c.source[0])
        ordered, seen = [], set()

        def visit(name, stack=()):
            if name in seen or name in stack:
                return
            for dep in sorted(deps[name]):
                visit(dep, stack + (name,))
            seen.add(name)
            ordered.append(name)

        for name in self.components:
            visit(name)
        return ordered


__all__ = ["Assembly", "AssemblyError", "ComponentError", "Coupling", "Connection"]
