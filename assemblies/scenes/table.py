"""Scenes of seed 9.6: a block with dry friction on a table that oscillates, the table
being its own FMU (a kinematic source connected to the block's ``support`` flange).

The block is :class:`SpringBlock` with ``k = 0``: its states ``x``, ``v`` are relative
to the table (the seed's frame in 9.6); its spring end is anchored to ground by a
fixed kinematic source only because the block's spring flange is a required motion
input (with k = 0 it exerts no force). Absolute velocity = block.v + table.flange.v.
"""
from __future__ import annotations

import math

import numpy as np

from components.motion_sources import HarmonicMotion, SineMotion
from components.sources import ConstantSpeed
from components.spring_block import SpringBlock

from ..assembly import Assembly
from ..result import Result
from .scene import Figure, Scene

U, OMEGA, MU, G, M = 0.1, 20.0, 0.4, 1.0, 1.0
PERIOD = 2 * math.pi / OMEGA
CONVEYOR = (1.0, -0.33, 0.08)  # the seed's harmonic coefficients of the table's position


def _table_block(name, table, v_absolute) -> Assembly:
    asm = Assembly(name)
    asm.add("table", table)
    asm.add("anchor", ConstantSpeed(v=0.0))
    v_table0 = float(table.values["U"] * table.values["omega"]
                     * sum(k * c for k, c in enumerate(_coefficients(table), start=1)))
    asm.add("block", SpringBlock(m=M, k=0.0, g=G, mu_k=MU, mu_s=MU, v=v_absolute - v_table0))
    asm.connect("anchor.flange", "block.flange_a")
    asm.connect("table.flange", "block.support")  # picks profile driven_on_moving_support
    return asm


def _coefficients(table):
    if isinstance(table, HarmonicMotion):
        return [table.values["c1"], table.values["c2"], table.values["c3"]]
    return [1.0]


def cycle_averaged_velocity(result: Result, period: float):
    """(mid-cycle times, mean absolute velocity over each whole cycle) from block.s."""
    t, s = result["time"], result["block.s"]
    starts = np.arange(0.0, t[-1] - period + 1e-9, period)
    s_at = np.interp(np.concatenate([starts, starts + period]), t, s)
    n = len(starts)
    return starts + period / 2, (s_at[n:] - s_at[:n]) / period


# --- moving_table: seed 9.6 example 1 -------------------------------------------------
def _moving_table() -> Assembly:
    return _table_block("moving_table", SineMotion(U=U, omega=OMEGA), v_absolute=1.5)


def _moving_table_figures(result: Result, asm: Assembly) -> list[Figure]:
    p = asm.component("table").values
    mu = asm.component("block").values["mu_k"]
    g = asm.component("block").values["g"]
    period = 2 * math.pi / p["omega"]
    tc, vc = cycle_averaged_velocity(result, period)
    # the seed's rate is for V << U omega; fit ln V where V < U omega / 4
    small = (vc > 0) & (vc < p["U"] * p["omega"] / 4)
    rate = -np.polyfit(tc[small], np.log(vc[small]), 1)[0] if small.sum() >= 3 else math.nan
    # the seed's averaged law before linearising: dV/dt = -(2 mu g / pi) arcsin(V / (U omega))
    return [Figure("decay_rate", "decay rate of the cycle-averaged velocity, V < U omega/4 [1/s]",
                   rate, 2 * mu * g / (math.pi * p["omega"] * p["U"])),
            Figure("V_first", "mean absolute velocity over the first cycle [m/s]", vc[0],
                   _averaged_law_first_cycle(1.5, mu * g, p["U"] * p["omega"], period))]


def _averaged_law_first_cycle(v0, mu_g, u_omega, period):
    """Mean over [0, T] of the seed's averaged law V' = -(2 mu g/pi) arcsin(V/(U omega))."""
    from scipy.integrate import solve_ivp
    sol = solve_ivp(lambda t, v: [-(2 * mu_g / math.pi) * math.asin(min(1.0, v[0] / u_omega))],
                    (0, period), [v0], dense_output=True, rtol=1e-10, atol=1e-12)
    tt = np.linspace(0, period, 201)
    return float(np.trapezoid(sol.sol(tt)[0], tt) / period)


# --- conveyor: seed 9.6 example 2 -----------------------------------------------------
def _conveyor() -> Assembly:
    c1, c2, c3 = CONVEYOR
    return _table_block("conveyor", HarmonicMotion(U=U, omega=OMEGA, c1=c1, c2=c2, c3=c3),
                        v_absolute=0.0)


def conveyor_median_velocity(U: float, omega: float, c) -> float:
    """The seed's steady speed: the median over a cycle of the table's velocity.

    Sliding friction pushes the block toward the table's velocity; the average force is
    zero when the table is faster for half the cycle and slower for the other half.
    """
    tau = (np.arange(200_000) + 0.5) * 2 * math.pi / 200_000
    v = U * omega * sum(ck * k * np.cos(k * tau) for k, ck in enumerate(c, start=1))
    return float(np.median(v))


def _conveyor_figures(result: Result, asm: Assembly) -> list[Figure]:
    p = asm.component("table").values
    period = 2 * math.pi / p["omega"]
    # the steady motion is not T-periodic: cycle means wander between ~1.00 and ~1.07
    # over about seven cycles, so average over everything after the run-up (40 cycles)
    t, s = result["time"], result["block.s"]
    t0 = 40 * period
    mean = (s[-1] - np.interp(t0, t, s)) / (t[-1] - t0)
    return [Figure("V_steady", "mean absolute velocity after 40 cycles of run-up [m/s]",
                   float(mean),
                   conveyor_median_velocity(p["U"], p["omega"], (p["c1"], p["c2"], p["c3"])))]


_RECORD = ["block.x", "block.v", "block.s", "block.mode", "block.f_friction",
           "table.flange.s", "table.flange.v"]

TABLE_SCENES: dict[str, Scene] = {
    "moving_table": Scene(
        "moving_table", "seed 9.6 ex. 1: block sliding on a table shaken as U sin(wt)",
        _moving_table, stop_time=64 * PERIOD, step=PERIOD / 16, tolerance=1e-8,
        record=_RECORD, figures=_moving_table_figures, plot=["block.s", "block.v"]),
    "conveyor": Scene(
        "conveyor", "seed 9.6 ex. 2: asymmetric shaking conveys the block at a steady speed",
        _conveyor, stop_time=120 * PERIOD, step=PERIOD / 16, tolerance=1e-8,
        record=_RECORD, figures=_conveyor_figures, plot=["block.s", "block.v"]),
}
