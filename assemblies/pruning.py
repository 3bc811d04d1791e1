"""No work for what is not recorded: the instances a run can leave out.

An instance influences another when a coupling carries one of its outputs to the
other's inputs: a signal connection one way, a flange connection both ways (motion one
way, force back). What a run records is influenced only by the recorded instances and
by every instance with a path of couplings to one of them; the others are left out of
the run, so the engine neither loads, steps nor reads them, and their states no longer
steer the shared error control (the run is the one of the assembly without them).

Kept whatever their connections, as an instance can end or stop everyone's run:
an FMU we did not generate (it may ask to terminate, and says nothing of when), one of
ours that can end a run (``terminate_when``), and whatever feeds those.
"""
from __future__ import annotations

from components.component import Component

from .assembly import Assembly
from .engine.prepare import binary_key, class_defaults, structure_key

_ends_run: dict = {}  # binary_key -> can end the run (a fact of class, profile and options)
_decisions: dict = {}  # structure, record -> the instances to keep (None: all of them)


def influences(assembly: Assembly) -> dict[str, set[str]]:
    """instance -> the instances whose inputs its outputs feed (profiles resolved)."""
    feeds = {name: set() for name in assembly.components}
    for c in assembly.couplings():
        if c.source[0] != c.target[0]:
            feeds[c.source[0]].add(c.target[0])
    return feeds


def can_end_the_run(component) -> bool:
    """Can this instance end the run for everyone? Always so for a foreign FMU."""
    if not isinstance(component, Component):
        return True
    key = binary_key(component)
    if key not in _ends_run:
        from fmus.build import component_facts
        _ends_run[key] = component_facts(class_defaults(component))["can_terminate"]
    return _ends_run[key]


def needed_instances(assembly: Assembly, record: list[str] | None) -> list[str]:
    """The instances that can influence the recorded columns (all of them when
    everything is recorded, or when `record` names an instance the assembly lacks, for
    the master to name in its error), in the assembly's order."""
    names = list(assembly.components)
    if record is None:
        return names
    recorded = {ref.partition(".")[0] for ref in record}
    if not recorded <= set(names):
        return names
    fed_by = {name: set() for name in names}
    for source, targets in influences(assembly).items():
        for target in targets:
            fed_by[target].add(source)
    needed = set(recorded)
    needed |= {n for n in names if n not in needed and can_end_the_run(assembly.components[n])}
    pending = list(needed)
    while pending:
        for source in fed_by[pending.pop()]:
            if source not in needed:
                needed.add(source)
                pending.append(source)
    return [n for n in names if n in needed]


def prune_unrecorded(assembly: Assembly, record: list[str] | None) -> tuple[Assembly, list[str]]:
    """(the assembly to run, the instances left out). The assembly itself when nothing
    can be left out; else one of the same instances (the same objects, values included)
    and the connections among them. Every kept instance keeps the causality profile it
    has in the whole assembly, or nothing is left out.

    The decision depends on the structure alone (classes, profiles, options, connections,
    what is recorded), so it is made once per structure: a parameter study or a repeated
    run pays only for assembling the kept instances."""
    key = (structure_key(assembly), None if record is None else tuple(record),
           assembly.signals_from_outside)
    if key not in _decisions:
        _decisions[key] = _decide(assembly, record)
    keep = _decisions[key]
    if keep is None:
        return assembly, []
    kept = set(keep)
    return _assemble(assembly, keep), [n for n in assembly.components if n not in kept]


def _assemble(assembly: Assembly, keep: list[str]) -> Assembly:
    pruned = Assembly(assembly.name)
    pruned.signals_from_outside = assembly.signals_from_outside
    for name in keep:
        pruned.add(name, assembly.components[name])
    kept = set(keep)
    pruned.connections = [c for c in assembly.connections
                          if c.a.partition(".")[0] in kept and c.b.partition(".")[0] in kept]
    return pruned


def _decide(assembly: Assembly, record: list[str] | None) -> list[str] | None:
    """The instances to keep, or None where nothing may be left out."""
    keep = needed_instances(assembly, record)
    if len(keep) == len(assembly.components):
        return None
    profiles = assembly.resolve_causality()
    if any(profiles[n] != p for n, p in _assemble(assembly, keep).resolve_causality().items()):
        # a kept instance would take another profile without the others; the instances
        # are shared, so they get back the profiles the whole assembly gives them
        assembly.resolve_causality()
        return None
    return keep
