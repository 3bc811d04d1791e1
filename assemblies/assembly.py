"""An assembly: named component instances and the connections between their ports.

Connections follow Modelica: a flange connects to a flange of the same domain,
across variables are equal and flows sum to zero. For co-simulation one side of
each flange connection computes the motion (its port is ``force`` in its profile)
and the other the force (``motion``); an assembly checks this when connecting.
"""
from __future__ import annotations

from dataclasses import dataclass

from components.component import Component
from components.interfaces import (FIXED, FORCE_IN, MOTION_IN, SIGNAL_IN, SIGNAL_OUT,
                                   ComponentError, Port)


class AssemblyError(ValueError):
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
        self.name = name
        self.components: dict[str, Component] = {}
        self.connections: list[Connection] = []

    def add(self, instance: str, component: Component) -> Component:
        if not instance.isidentifier():
            raise AssemblyError(f"assembly '{self.name}': instance name '{instance}' "
                                "must be an identifier (letters, digits, _)")
        if instance in self.components:
            raise AssemblyError(f"assembly '{self.name}': instance '{instance}' already exists")
        component.name = instance
        self.components[instance] = component
        return component

    def component(self, instance: str) -> Component:
        if instance not in self.components:
            raise AssemblyError(f"assembly '{self.name}': no instance '{instance}'; "
                                f"instances: {', '.join(self.components)}")
        return self.components[instance]

    def _port(self, ref: str) -> tuple[str, Port, str]:
        instance, _, port_name = ref.partition(".")
        comp = self.component(instance)
        for port in comp.ports:
            if port.name == port_name:
                return instance, port, comp.profile.ports[port.name]
        raise AssemblyError(f"assembly '{self.name}': {type(comp).__name__} '{instance}' has no "
                            f"port '{port_name}'; ports: {', '.join(p.name for p in comp.ports)}")

    def connect(self, a: str, b: str) -> None:
        """Connect two ports, e.g. ``connect("driver.flange", "block.flange_a")``."""
        (ia, pa, ca), (ib, pb, cb) = self._port(a), self._port(b)
        if pa.domain != pb.domain:
            raise AssemblyError(f"cannot connect {a} ({pa.domain.name}) to {b} ({pb.domain.name}): "
                                "ports must be of the same domain and unit")
        if FIXED in (ca, cb):
            fixed = a if ca == FIXED else b
            raise AssemblyError(f"cannot connect {a} to {b}: {fixed} is grounded in its profile")
        if {ca, cb} not in ({MOTION_IN, FORCE_IN}, {SIGNAL_IN, SIGNAL_OUT}):
            raise AssemblyError(
                f"cannot connect {a} ({ca}) to {b} ({cb}): one side must compute the motion "
                f"(profile '{FORCE_IN}') and the other the force (profile '{MOTION_IN}'), "
                "or a signal output must feed a signal input")
        self.connections.append(Connection(a, b))

    def couplings(self) -> list[Coupling]:
        """The connections as scalar input <- output assignments."""
        out, fed = [], {}
        for conn in self.connections:
            (ia, pa, ca), (ib, pb, cb) = self._port(conn.a), self._port(conn.b)
            if pa.domain.flow is None:
                src, dst = ((ia, pa), (ib, pb)) if ca == SIGNAL_OUT else ((ib, pb), (ia, pa))
                out.append(Coupling((src[0], src[1].name), (dst[0], dst[1].name)))
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
