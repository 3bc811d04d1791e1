"""Algebraic loops between direct-feedthrough outputs, for the co-simulation master.

Coupling c2 *needs* c1 when c1 sets an input of c2's source FMU that c2's source
output depends on (the output dependencies of the model description). The
strongly connected components of that graph, in dependency order, tell the
master how to make every input consistent with every output at a communication
point: a single coupling is just assigned; a component of several couplings is
an algebraic loop, solved for its inputs u by

    r(u) = u - G(u) = 0,   G_i(u) = gain_i * y_source(i)(u)

with Newton's method, the Jacobian dG/du assembled from the FMUs' directional
derivatives dy/du (fmi3GetDirectionalDerivative). A loop whose gain exceeds one
(a light beam tip carrying a heavy block) makes plain fixed-point iteration
diverge; Newton solves a linear loop in one step.
"""
from __future__ import annotations

import numpy as np

from components.errors import MechfmuError

from ..assembly import AssemblyError


class LoopError(MechfmuError, RuntimeError):
    """A loop did not converge; the message names the FMUs and the couplings."""


def strongly_connected(nodes, successors) -> list[list]:
    """The strongly connected components (Tarjan) of the graph that `successors(node)`
    gives, each emitted after every component it reaches; roots taken from `nodes` in
    order. A loop with its own stack, not one Python frame per node, so that a long chain
    of dependencies cannot overflow the interpreter's stack."""
    index, low, on_stack, stack, groups = {}, {}, set(), [], []

    def enter(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        return v, iter(successors(v))

    for root in nodes:
        if root in index:
            continue
        work = [enter(root)]
        while work:
            v, todo = work[-1]
            for w in todo:
                if w not in index:
                    work.append(enter(w))
                    break
                if w in on_stack:
                    low[v] = min(low[v], index[w])
            else:  # every successor of v seen: v is done
                work.pop()
                if work:
                    parent = work[-1][0]
                    low[parent] = min(low[parent], low[v])
                if low[v] == index[v]:
                    group = []
                    while True:
                        w = stack.pop()
                        on_stack.discard(w)
                        group.append(w)
                        if w == v:
                            break
                    groups.append(group)
    return groups


def coupling_groups(couplings, depends, inputs) -> list[list[int]]:
    """Indices of `couplings` grouped into strongly connected components, sources first.

    `depends[instance][output]` is the set of inputs that output depends on (None:
    all of `inputs[instance]`). Tarjan's algorithm yields components with every
    component after the ones it needs.
    """
    def deps(inst, out):
        d = depends[inst].get(out)
        return set(inputs[inst]) if d is None else d

    # by target instance, so that the graph costs O(couplings), not its square (a chain
    # of 32 blocks has ~200 couplings)
    feeding: dict[str, list[int]] = {}
    for j, c1 in enumerate(couplings):
        feeding.setdefault(c1.target[0], []).append(j)
    needs = {}
    for i, c2 in enumerate(couplings):
        d = deps(*c2.source)
        needs[i] = [j for j in feeding.get(c2.source[0], ()) if couplings[j].target[1] in d]
    return [sorted(group) for group in strongly_connected(range(len(couplings)), needs.__getitem__)]


def is_loop(group, couplings, depends, inputs) -> bool:
    if len(group) > 1:
        return True
    c = couplings[group[0]]  # a single coupling feeding its own source through feedthrough
    d = depends[c.source[0]].get(c.source[1])
    return c.target[0] == c.source[0] and (d is None or c.target[1] in d)


def describe(group, couplings) -> str:
    return " -> ".join(f"{'.'.join(couplings[i].source)} => {'.'.join(couplings[i].target)}"
                       for i in group)


def solve_loop(group, couplings, get_input, set_input, get_output, partial, *,
               tolerance: float, max_iterations: int, newton: bool = True) -> tuple[int, float]:
    """Make the loop's inputs consistent; returns (iterations, final residual).

    get_input/set_input/get_output take (instance, variable); partial(instance,
    output, input) is d output / d input of one FMU at its current point. The
    residual is max |u - G(u)|, converged when below ``tolerance * (1 + max |u|)``.
    """
    cs = [couplings[i] for i in group]
    u = np.array([get_input(*c.target) for c in cs])

    def residual(u):
        for c, value in zip(cs, u):
            set_input(*c.target, value)
        return u - np.array([c.gain * get_output(*c.source) for c in cs])

    r = residual(u)
    for iteration in range(max_iterations + 1):
        res = float(np.max(np.abs(r)))
        if res <= tolerance * (1.0 + float(np.max(np.abs(u)))):
            return iteration, res
        if iteration == max_iterations:
            break
        if newton:
            jac = np.eye(len(cs))
            for i, ci in enumerate(cs):
                for j, cj in enumerate(cs):
                    if cj.target[0] == ci.source[0]:
                        jac[i, j] -= ci.gain * partial(ci.source[0], ci.source[1], cj.target[1])
            try:
                step = np.linalg.solve(jac, -r)
            except np.linalg.LinAlgError:
                raise LoopError(f"algebraic loop {describe(group, couplings)} has a singular "
                                "Jacobian (I - dG/du): no unique consistent input") from None
            u = u + step
        else:
            u = u - r  # u <- G(u)
        if not np.all(np.isfinite(u)):
            break
        r = residual(u)
    instances = sorted({c.source[0] for c in cs} | {c.target[0] for c in cs})
    raise LoopError(f"algebraic loop between FMUs {', '.join(instances)} did not converge in "
                    f"{max_iterations} {'Newton' if newton else 'fixed-point'} iterations "
                    f"(residual {float(np.max(np.abs(r))):.3g}): {describe(group, couplings)}")


__all__ = ["LoopError", "coupling_groups", "describe", "is_loop", "loop_order", "solve_loop"]


def _needs(couplings, instances) -> dict:
    """Per coupling, the couplings that set an input its source output depends on."""
    # the couplings into each instance, indexed once: a pass over every coupling per
    # coupling was quadratic (7 s of a 500-block chain's me run)
    into = {}
    for j, c1 in enumerate(couplings):
        into.setdefault(c1.target[0], []).append(j)
    needs = {}
    for i, c2 in enumerate(couplings):
        source = instances[c2.source[0]]
        reads = source.depends.get(c2.source[1])
        reads = set(source.inputs) if reads is None else reads
        needs[i] = [j for j in into.get(c2.source[0], ()) if couplings[j].target[1] in reads]
    return needs


def loop_order(couplings, instances) -> tuple[list, list[tuple[int, int, str]]]:
    """The couplings sorted so that each is evaluated after every coupling its source
    needs, with each algebraic loop's couplings together; and the loops as (first
    index in that order, count, description naming the instances and couplings).

    Coupling c2 needs c1 when c1 sets an input of c2's source instance that c2's source
    output depends on (direct feedthrough); a strongly connected group of them is a loop
    (or one coupling that feeds its own source). The order is by dependency level of
    the groups (outputs that need no coupled input first), and within a level by source
    instance: a master can then read a whole level before setting any of it, and each
    FMU computes its outputs once per level rather than once per read.
    """
    needs = _needs(couplings, instances)
    groups = strongly_connected(range(len(couplings)), needs.__getitem__)  # needed first
    group_of = {i: g for g, members in enumerate(groups) for i in members}
    level = []
    for g, members in enumerate(groups):  # each after every group it needs
        level.append(1 + max((level[group_of[j]] for i in members for j in needs[i]
                              if group_of[j] != g), default=-1))
    first_seen = {}
    for c in couplings:
        first_seen.setdefault(c.source[0], len(first_seen))
    order, loops = [], []
    for g in sorted(range(len(groups)), key=lambda g: (
            level[g], first_seen[couplings[min(groups[g])].source[0]], min(groups[g]))):
        members = sorted(groups[g])
        if len(members) > 1 or members[0] in needs[members[0]]:
            instances_in = sorted({c.source[0] for c in (couplings[i] for i in members)}
                                  | {c.target[0] for c in (couplings[i] for i in members)})
            loops.append((len(order), len(members), f"between FMUs {', '.join(instances_in)}: "
                          f"{describe(members, couplings)}"))
        order += members
    return [couplings[i] for i in order], loops

