"""What the library says about its components in words: one component's sheet (what
``mechfmu show NAME`` prints) and README's table of all of them (generated, so that the
two cannot drift: ``python -m assemblies.scenes.listing README.md``)."""
from __future__ import annotations

import math

from . import COMPONENTS
from .component import SOLVER_CHOICES, Block, Component
from .interfaces import Domain


def _range(lo: float, hi: float, lo_strict: bool) -> str:
    if lo == -math.inf and hi == math.inf:
        return "any"
    left = "-inf" if lo == -math.inf else f"{lo:g}"
    right = "inf" if hi == math.inf else f"{hi:g}"
    return f"{'(' if lo_strict or lo == -math.inf else '['}{left}, {right}{')' if hi == math.inf else ']'}"


def _domain(domain: Domain) -> str:
    if domain.flow is None:
        unit = domain.across[0][1]
        return f"signal {domain.value_type} [{unit or 'no unit'}]"
    return domain.name


def sheet(cls: type[Block]) -> str:
    """Every name a component takes, with unit, default, allowed range and meaning; its
    ports and causality profiles."""
    lines = [f"{cls.__name__}: {cls.describe()}", ""]
    if cls.parameters:
        lines.append("parameters (--param NAME=VALUE):")
        width = max(len(p.name) for p in cls.parameters)
        for p in cls.parameters:
            lines.append(f"  {p.name:<{width}}  {p.default:>10g} {p.unit or '1':<8} "
                         f"{_range(p.min, p.max, p.min_strict):<14} {p.description}")
    if cls.options:
        lines.append("options (--param NAME=VALUE, fixed when the FMU is built):")
        for o in cls.options:
            lines.append(f"  {o.name} = {o.default} ({o.allowed()}): {o.description}")
    if issubclass(cls, Component):
        lines.append(f"solver (--param solver=VALUE, the FMU's own): {SOLVER_CHOICES}")
    if cls.states:
        lines.append("states (start values: --param NAME=VALUE):")
        width = max(len(s.name) for s in cls.states)
        for s in cls.states:
            alias = f" (also {s.start_name})" if s.start_name else ""
            lines.append(f"  {s.name:<{width}}  {s.start:>10g} {s.unit or '1':<8} "
                         f"{s.description}{alias}")
    # start values a component converts into its states' (the beam's w_tip0)
    for name, description in getattr(cls, "start_aliases", ()):
        lines.append(f"  {name}: {description}")
    if cls.ports:
        lines.append("ports:")
        for port in cls.ports:
            lines.append(f"  {port.name}: {_domain(port.domain)}, {port.description}")
    lines.append("profiles (--profile NAME; the first is the default):")
    for profile in cls.profiles:
        ports = ", ".join(f"{k} {v}" for k, v in profile.ports.items())
        lines.append(f"  {profile.name}: {profile.description}" + (f" [{ports}]" if ports else ""))
    return "\n".join(lines)


MARKER = ("<!-- generated from the component registry: "
          "python -m assemblies.scenes.listing README.md -->")
HEADER = ("| component | what it is | ports | profiles |", "| --- | --- | --- | --- |")


def _cell(text: str) -> str:
    # a bare | would end the cell; a line break would end the row
    return " ".join(text.split()).replace("|", "\\|")


def markdown_table() -> str:
    """One row per component, in the registry's order (``mechfmu components``)."""
    rows = []
    for name, cls in COMPONENTS.items():
        ports = ", ".join(f"`{p.name}` ({_domain(p.domain)})" for p in cls.ports) or "none"
        profiles = ", ".join(p.name for p in cls.profiles)
        rows.append(f"| `{name}` | {_cell(cls.describe())} | {_cell(ports)} | {profiles} |")
    return "\n".join([*HEADER, *rows])
