"""Choosing every component's causality profile from the connection graph.

Modelica connects flanges acausally; an FMU needs to know which side computes the
motion and which the force (MSL exports a *direct* mass, force in and motion out,
and an *inverse* one, motion in and force out). Here each component offers its
declared profiles, or only the one the user named, and a small backtracking search
picks one per component so that

- every flange connection has exactly one ``force`` side (it takes the force and
  returns the motion) and one ``motion`` side (it takes the motion, returns the force);
- every signal connection joins an ``output`` to an ``input``;
- no port is left unconnected as a required input. An unconnected flange follows
  Modelica: its flow is zero, so ``force`` (a free flange, its force input stays at
  its start value 0) and ``fixed`` (grounded) are fine, but ``motion`` would need a
  motion nobody computes; an unconnected signal ``input`` likewise, unless its port
  is ``optional`` (an FMU's input, which FMI gives a start value to keep).

Among the valid assignments the search returns the first in declaration order (a
component's first profile is its usual one), so results are deterministic. Components
have one to three profiles, so the search is tiny.
"""
from __future__ import annotations

from dataclasses import dataclass

from components.errors import MechfmuError
from components.interfaces import FIXED, FORCE_IN, MOTION_IN, SIGNAL_IN, SIGNAL_OUT

# what may face what across one connection
_FLANGE_PAIR = {FORCE_IN, MOTION_IN}
_SIGNAL_PAIR = {SIGNAL_IN, SIGNAL_OUT}
# what an unconnected port may be: anything that needs no input from outside
UNCONNECTED_OK = (FIXED, FORCE_IN, SIGNAL_OUT)


class CausalityError(MechfmuError, ValueError):
    """No profile assignment satisfies the connections; the message names the ports."""


def compatible(ca: str, cb: str) -> bool:
    return {ca, cb} in (_FLANGE_PAIR, _SIGNAL_PAIR)


def candidates(component) -> list:
    """The profiles an assembly may give `component`: the user's choice, or all of them."""
    if getattr(component, "profile_explicit", True):
        return [component.profile]
    return list(component.profiles)


def port_causalities(component, port: str) -> list[str]:
    """The causalities `port` can take, in profile order, without repeats."""
    seen = []
    for profile in candidates(component):
        c = profile.ports.get(port)
        if c is not None and c not in seen:
            seen.append(c)
    return seen


@dataclass(frozen=True)
class Link:
    """A connection between two ports: (instance, port) on each side."""
    a: tuple[str, str]
    b: tuple[str, str]

    def __str__(self):
        return f"{'.'.join(self.a)} - {'.'.join(self.b)}"


def _search(names, options, links, check_dangling, supplied):
    """First assignment (instance -> profile) satisfying every link, or None."""
    # each instance's links, in one pass (one pass per instance was quadratic: 2 s of a
    # 500-block chain)
    by_instance = {n: [] for n in names}
    for lk in links:
        for end in dict.fromkeys((lk.a[0], lk.b[0])):
            if end in by_instance:
                by_instance[end].append(lk)
    chosen: dict = {}

    def ok(name):
        profile = chosen[name]
        for lk in by_instance[name]:
            other = lk.b[0] if lk.a[0] == name else lk.a[0]
            if other in chosen and not compatible(chosen[lk.a[0]].ports.get(lk.a[1]),
                                                  chosen[lk.b[0]].ports.get(lk.b[1])):
                return False
        if check_dangling:
            for port, causality in profile.ports.items():
                if (name, port) not in supplied and causality not in UNCONNECTED_OK:
                    return False
        return True

    # depth-first over the instances in order, as a loop (one frame per instance would
    # overflow Python's stack in an assembly of a thousand instances): tried[i] is the
    # number of names[i]'s profiles tried on the current branch
    tried = [0] * len(names)
    i = 0
    while 0 <= i < len(names):
        profiles = options[names[i]]
        while tried[i] < len(profiles):
            chosen[names[i]] = profiles[tried[i]]
            tried[i] += 1
            if ok(names[i]):
                i += 1
                break
        else:  # no profile fits the ones before it: back to the previous instance
            chosen.pop(names[i], None)
            tried[i] = 0
            i -= 1
    return dict(chosen) if i == len(names) else None


def resolve(assembly_name: str, components: dict, links: list[Link],
            open_signals: bool = False) -> dict:
    """Instance -> chosen Profile; raises CausalityError naming the ports when impossible.

    `open_signals`: an unconnected signal port is fed from outside the assembly (an
    exported assembly FMU's inputs), so it needs no connection."""
    names = list(components)
    options = {n: candidates(components[n]) for n in names}
    # ports that need nothing from outside: the connected ones, and the optional ones
    # (which keep their start value when left open)
    supplied = ({lk.a for lk in links} | {lk.b for lk in links}
                | {(n, p.name) for n in names for p in components[n].ports
                   if p.optional or (open_signals and p.domain.flow is None)})
    # a port that is a required input in every available profile can never be left open
    for name in names:
        comp = components[name]
        for port in comp.ports:
            if (name, port.name) in supplied:
                continue
            kinds = port_causalities(comp, port.name)
            if kinds and not any(k in UNCONNECTED_OK for k in kinds):
                raise CausalityError(
                    f"assembly '{assembly_name}': {name}.{port.name} is a dangling required input "
                    f"({'/'.join(kinds)} in every profile {_profile_list(comp)}); connect it to a "
                    "port that supplies it, or use a component whose profile grounds it")
    solution = _search(names, options, links, True, supplied)
    if solution is not None:
        return solution
    # name the first connection that cannot be added to the ones before it
    for k in range(1, len(links) + 1):
        if _search(names, options, links[:k], False, supplied) is None:
            culprit = links[k - 1]
            related = [str(lk) for lk in links[:k - 1]
                       if {lk.a[0], lk.b[0]} & {culprit.a[0], culprit.b[0]}]
            offered = "; ".join(f"{n}: {_profile_list(components[n])}"
                                for n in dict.fromkeys([culprit.a[0], culprit.b[0]]))
            raise CausalityError(
                f"assembly '{assembly_name}': connection {culprit} leaves no way to give every "
                "connection one motion side and one force side"
                + (f" together with {', '.join(related)}" if related else "")
                + f" (profiles available: {offered})")
    # every connection fits, but only with a required input left open somewhere
    first = _search(names, options, links, False, supplied)
    open_inputs = [f"{n}.{port} ({c})" for n, profile in first.items()
                   for port, c in profile.ports.items()
                   if (n, port) not in supplied and c not in UNCONNECTED_OK]
    raise CausalityError(
        f"assembly '{assembly_name}': every choice of profiles that fits the connections leaves a "
        f"required input dangling, e.g. {', '.join(open_inputs)}; connect it")


def _profile_list(component) -> str:
    return "[" + ", ".join(f"{p.name}: " + ", ".join(f"{k}={v}" for k, v in p.ports.items())
                           for p in candidates(component)) + "]"
