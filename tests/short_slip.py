"""A friction event that a step-end sign check misses: a slip shorter than a solver step.

The assembly (:func:`short_slip_assembly`): a block with exact Coulomb friction
(mu_s = 0.999, mu_k = 0.99, g = 1) on a table shaken as s = sin(t) (peak acceleration
1). The block sticks while |a_table| <= mu_s g; near each peak of |a_table| the table
outruns the static limit for 0.09 s, the block slips for 0.31 s and sticks again for
2.8 s. While it sticks its states (relative to the table) are constant, so an
error-controlled solver's steps grow tenfold each and soon span the whole excursion
of the static margin above and back below zero: a check of the indicators' signs at
step ends sees no event at all.

The exact phases (:func:`exact_short_slip_phases`) come from the event-driven exact
solution in :mod:`assemblies.scenes.table`, which shares nothing with the FMUs or the
masters; the first break-away is also closed form, asin(mu_s g / (U omega^2)) / omega.

Usage (any master; compare the mode changes of the block's event table)::

    from short_slip import (SHORT_SLIP_STEP, SHORT_SLIP_STOP, exact_short_slip_phases,
                            mode_changes, short_slip_assembly)
    res = simulate_me(short_slip_assembly(), SHORT_SLIP_STOP, SHORT_SLIP_STEP, 1e-10)
    found = mode_changes(res.events["block"]["time"], res.events["block"]["block.mode"])
    exact = exact_short_slip_phases()      # [(t, mode)], 8 phases over two periods
"""
from __future__ import annotations

import math

import numpy as np

from assemblies import Assembly
from assemblies.scenes.table import CoulombOnTable, HarmonicTable
from components import ConstantSpeed, SpringBlock
from components.sources.motion import SineMotion

SHORT_SLIP = dict(U=1.0, omega=1.0, mu_s=0.999, mu_k=0.99, g=1.0)
SHORT_SLIP_STOP = 4 * math.pi  # two table periods: four slips, each 0.31 s
SHORT_SLIP_STEP = 1.0          # output (or communication) step, longer than a slip


def short_slip_assembly(name: str = "short_slip") -> Assembly:
    p = SHORT_SLIP
    asm = Assembly(name)
    asm.add("table", SineMotion(U=p["U"], omega=p["omega"]))
    asm.add("anchor", ConstantSpeed(v=0.0))  # the spring's end; k = 0: no force
    # at rest relative to the table (stuck): the table starts at speed U omega
    asm.add("block", SpringBlock(m=1.0, k=0.0, g=p["g"], mu_s=p["mu_s"], mu_k=p["mu_k"], v=0.0))
    asm.connect("anchor.flange", "block.flange_a")
    asm.connect("table.flange", "block.support")
    return asm


def exact_short_slip_phases(stop_time: float = SHORT_SLIP_STOP) -> list[tuple[float, int]]:
    """[(time, mode)] of every phase that begins in (0, stop_time], exactly."""
    p = SHORT_SLIP
    block = CoulombOnTable(HarmonicTable(p["U"], p["omega"], (1.0,)), p["mu_s"], p["mu_k"], p["g"])
    start = block.start(0.0, p["U"] * p["omega"])
    _, _, phases = block.advance(start, stop_time)
    return [(ph.t, ph.mode) for ph in phases]


def first_break_away() -> float:
    """Closed form: the stuck block lets go where |a_table| = U omega^2 |sin(omega t)|
    first reaches mu_s g."""
    p = SHORT_SLIP
    return math.asin(p["mu_s"] * p["g"] / (p["U"] * p["omega"] ** 2)) / p["omega"]


def mode_changes(times, modes) -> list[tuple[float, int]]:
    """The (time, new mode) rows of an event table where the mode actually changed."""
    out, last = [], 0.0  # the block starts stuck
    for t, q in zip(np.asarray(times, dtype=float), np.asarray(modes, dtype=float)):
        if q != last:
            out.append((float(t), int(q)))
            last = q
    return out
