"""What every component is made of: parameters, states, modes, ports, causality profiles.

A component declares these as class attributes and writes its physics in
``equations(e)`` against the symbols that :class:`components.dae.EquationBuilder`
hands it. Nothing here knows about FMI; :mod:`components.dae` turns a component and
one causality profile into an explicit, mode-switched ODE.
"""
from __future__ import annotations

import functools
import math
import numbers
from dataclasses import dataclass, field
from typing import Callable

from .errors import ComponentError  # noqa: F401  (defined there, under the root error)
from .lazy import lazy

ca = lazy("casadi")  # for Mode.selects's conditions; not loaded by an import


@dataclass(frozen=True)
class Parameter:
    """A numeric parameter, exported to the FMU as a fixed parameter."""
    name: str
    default: float
    unit: str
    description: str
    min: float = -math.inf
    max: float = math.inf
    min_strict: bool = False  # True: value must be > min, not >= min

    def label(self) -> str:
        """``description, unit`` for messages (the unit left out where there is none)."""
        return f"{self.description}, {self.unit}" if self.unit else self.description

    def allowed(self) -> str:
        lo = "" if self.min == -math.inf else f"{'>' if self.min_strict else '>='} {self.min:g}"
        hi = "" if self.max == math.inf else f"<= {self.max:g}"
        return " and ".join(s for s in (lo, hi) if s) or "any finite value"

    def violates(self, value: float) -> bool:
        if not math.isfinite(value):
            return True
        if self.min_strict and not value > self.min:
            return True
        return not (self.min <= value <= self.max)


@dataclass(frozen=True)
class Option:
    """A structural choice fixed when the FMU is built (it changes the equations).

    String options list their `choices`; integer options (e.g. a number of modes)
    give ``choices=range(lo, hi + 1)``.
    """
    name: str
    default: str | int
    choices: tuple[str, ...] | range
    description: str

    def parse(self, value) -> str | int:
        """The value as the option's type, or None if it is not one of the choices."""
        if isinstance(self.choices, range):
            # an int, or its digits as text (the command line); a float is no count of
            # anything, even 2.0, and a bool is no integer to count with
            if isinstance(value, numbers.Integral) and not isinstance(value, bool):
                number = int(value)
            elif isinstance(value, str) and value.strip().lstrip("+-").isdigit():
                number = int(value.strip())
            else:
                return None
            return number if number in self.choices else None
        return value if value in self.choices else None

    def allowed(self) -> str:
        if isinstance(self.choices, range):
            return f"an integer from {self.choices.start} to {self.choices.stop - 1}"
        return "one of " + ", ".join(self.choices)


@dataclass(frozen=True)
class State:
    """A continuous state with its start value; ``output`` exposes it to the importer."""
    name: str
    start: float
    unit: str
    description: str
    output: bool = True
    start_name: str | None = None  # another name its start value answers to, e.g. theta0
    nominal: float = 1.0  # typical magnitude: importers scale their error control by it


@dataclass(frozen=True)
class Mode:
    """A discrete state, changed only at events (an Int32 output of the FMU)."""
    name: str
    start: int
    description: str
    values: tuple[int, ...] = (-1, 0, 1)  # every value it can take
    # values it can take with the equations of values[0] (a start decided by the first
    # event, MSL's Free of a clutch): solved per mode, so a member of a joined model in
    # one of them leaves the others' equations as they are
    also: tuple[int, ...] = ()

    def selects(self, q, value):
        """The condition under which the mode `q` (a symbol) has the equations of `value`."""
        if value != self.values[0] or not self.also:
            return q == value
        return functools.reduce(ca.logic_or, [q == v for v in (value, *self.also)])


@dataclass(frozen=True)
class Constraint:
    """A relation between parameters that must hold: ``g(p) >= 0`` (``> 0`` if strict)."""
    g: Callable  # (parameter namespace) -> expression
    message: str  # what is allowed, e.g. "mu_k <= mu_s"
    strict: bool = False


# --- connectors -------------------------------------------------------------
@dataclass(frozen=True)
class Domain:
    """An MSL-style connector type: across variables (with their derivatives) and one flow."""
    name: str
    across: tuple[tuple[str, str, str], ...]  # (name, unit, description), highest derivative last
    flow: tuple[str, str, str] | None          # None for plain signals
    value_type: str = "Float64"                # FMI type of the variables (a signal: any
                                               # FMI type, assemblies.value_types)


TRANSLATIONAL = Domain(
    "translational",
    across=(("s", "m", "absolute position of the flange"),
            ("v", "m/s", "absolute velocity of the flange"),
            ("a", "m/s2", "absolute acceleration of the flange")),
    flow=("f", "N", "cut force acting on the component at the flange (positive along +s)"))

ROTATIONAL = Domain(
    "rotational",
    across=(("phi", "rad", "absolute rotation angle of the flange"),
            ("w", "rad/s", "absolute angular velocity of the flange"),
            ("a", "rad/s2", "absolute angular acceleration of the flange")),
    flow=("tau", "N.m", "cut torque acting on the component at the flange"))


def signal(unit: str, value_type: str = "Float64") -> Domain:
    """A plain signal of one unit and FMI type (a Float64 signal, the usual kind, is
    named by its unit alone). ``unit=""``: the FMU it comes from declares no unit."""
    shown = unit or "no unit"
    name = f"signal[{shown}]" if value_type == "Float64" else f"signal[{value_type}, {shown}]"
    return Domain(name, across=(("", unit, "signal value"),), flow=None, value_type=value_type)


def connectable(a: Domain, b: Domain) -> bool:
    """Ports of these domains may be connected: the same domain, or signals of one type
    where one side declares no unit (tools often leave units out, and FMI then says
    nothing about them; the side that declares one is taken at its word)."""
    if a == b:
        return True
    return (a.flow is None and b.flow is None and a.value_type == b.value_type
            and "" in (a.across[0][1], b.across[0][1]))


def describe_signal(domain: Domain) -> str:
    """``Float64 [N]``, ``Int32 [1]``, ``Float64 (no unit)``: a signal's type and unit."""
    unit = domain.across[0][1]
    return f"{domain.value_type} [{unit}]" if unit else f"{domain.value_type} (no unit)"


@dataclass(frozen=True)
class Port:
    name: str
    domain: Domain
    description: str
    # True: the port may stay unconnected even where its causality is a required input
    # (an FMU's input keeps its start value, as FMI defines); our components' inputs
    # must always be connected
    optional: bool = False
    # an FMI 3 array signal: its shape; connected whole, element by element in row-major
    # order (assemblies.value_types.element_names); () for a scalar
    shape: tuple = ()


# How a port crosses the FMU boundary.
MOTION_IN = "motion"  # across variables are inputs, the flow is an output (MSL "inverse")
FORCE_IN = "force"    # the flow is an input, across variables are outputs (MSL "direct")
FIXED = "fixed"       # grounded: across variables are zero, nothing crosses the boundary
SIGNAL_IN = "input"
SIGNAL_OUT = "output"
CAUSALITIES = (MOTION_IN, FORCE_IN, FIXED, SIGNAL_IN, SIGNAL_OUT)


@dataclass(frozen=True)
class Profile:
    """A named causality assignment for every port of a component."""
    name: str
    description: str
    ports: dict[str, str] = field(default_factory=dict)  # port name -> causality
