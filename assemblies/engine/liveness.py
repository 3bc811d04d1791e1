"""Which couplings the continuous-time evaluation of an assembly needs.

Between events, the engine's one integrator needs every instance's state derivatives,
its event indicators and the recorded columns; nothing else. A coupling whose target
input none of these depends on, directly or through the outputs it feeds, can wait for
the next event or initialisation, where every coupling is propagated (an event update
may read any input). In a chain of flanges that is the reaction forces sent back to
position sources and the accelerations sent to springs: a third of two_block_belt's
couplings, and a second evaluation of each block's outputs per right-hand side.

An output row needs less still: the recorded columns and what they depend on
(row_couplings). In two_block_belt the blocks' positions need the belts' travel and
nothing of the springs, the walls or the forces.

The dependencies come from each FMU's ModelStructure; one that does not list them
depends on every input, so a foreign FMU loses nothing.
"""
from __future__ import annotations


def needed_inputs(fmus: dict, couplings, record, dynamics: bool = True) -> dict[str, set]:
    """Per instance, the inputs that its derivatives, indicators (unless not
    `dynamics`) and the recorded columns (`record`: (instance, variable) pairs) depend
    on, through the couplings."""
    need = {name: set() for name in fmus}
    for name, fmu in fmus.items() if dynamics else ():
        if fmu.n_states:
            need[name] |= fmu.derivatives_depend
        if fmu.n_event_indicators:
            need[name] |= fmu.indicators_depend
    for name, var in record:
        need[name] |= inputs_behind(fmus[name], var)
    changed = True
    while changed:
        changed = False
        for c in couplings:
            (source, out), (target, inp) = c.source, c.target
            if inp in need[target]:
                behind = inputs_behind(fmus[source], out)
                if not behind <= need[source]:
                    need[source] |= behind
                    changed = True
    return need


def indicator_couplings(fmus: dict, couplings) -> dict[str, list[int]]:
    """Per instance with event indicators, the indices (in `couplings`' order) of the
    couplings its indicators depend on, directly or through the outputs they feed:
    what event location sets to look at that instance alone (eng_me_spec.indicator_start).
    A walk back from the instance's inputs, so a chain costs its neighbours, not itself
    again per block."""
    into: dict[tuple[str, str], list[int]] = {}
    for k, c in enumerate(couplings):
        into.setdefault(tuple(c.target), []).append(k)
    out = {}
    for name, fmu in fmus.items():
        if not fmu.n_event_indicators:
            continue
        seen, used = set(), set()
        pending = [(name, inp) for inp in fmu.indicators_depend]
        while pending:
            target = pending.pop()
            if target in seen:
                continue
            seen.add(target)
            for k in into.get(target, ()):
                used.add(k)
                source, var = couplings[k].source
                pending += [(source, inp) for inp in inputs_behind(fmus[source], var)]
        out[name] = sorted(used)
    return out


def continuous_couplings(fmus: dict, couplings, record) -> list[bool]:
    """For each of `couplings`, in their order: whether the evaluation between events
    needs it (module doc)."""
    need = needed_inputs(fmus, couplings, record)
    return [c.target[1] in need[c.target[0]] for c in couplings]


def row_couplings(fmus: dict, couplings, record) -> list[bool]:
    """For each of `couplings`, in their order: whether the recorded columns depend on
    it (module doc)."""
    need = needed_inputs(fmus, couplings, record, dynamics=False)
    return [c.target[1] in need[c.target[0]] for c in couplings]


def inputs_behind(fmu, var: str) -> set:
    """The inputs `var` of `fmu` depends on: an output's listed dependencies, an input
    itself, the derivatives' inputs for a derivative, none for a state; all inputs for
    anything else (a variable the ModelStructure does not describe)."""
    if var in fmu.depends:
        return fmu.depends[var]
    if var in fmu.inputs:
        return {var}
    if var in fmu.derivatives:
        return fmu.derivatives_depend
    if var in fmu.states:
        return set()
    return set(fmu.inputs)
