"""Scenes of seed 9.6: a block with dry friction on a table that oscillates, the table
being its own FMU (a kinematic source connected to the block's ``support`` flange).

The block is :class:`SpringBlock` with ``k = 0``: its states ``x``, ``v`` are relative
to the table (the seed's frame in 9.6); its spring end is anchored to ground by a
fixed kinematic source only because the block's spring flange is a required motion
input (with k = 0 it exerts no force). Absolute velocity = block.v + table.flange.v.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from components.sources.motion import HarmonicMotion, SineMotion
from components.sources.translational import ConstantSpeed
from components.translational.spring_block import SpringBlock

from ..assembly import Assembly
from ..result import Result
from .references import earliest_zero
from .scene import Figure, Scene, solver_accuracy
from .table_plot import plot_table

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
    # The seed averages the friction force over a cycle of the table, an expansion in
    # eps = mu g / (U omega^2) (0.01): the averaged law is right to O(eps) of the rate.
    # Linearising it, arcsin(x) ~ x, errs by up to x^2 / 6 of the rate at the top of the
    # fitted range, x = V / (U omega) < 1/4.
    eps = mu * g / (p["U"] * p["omega"] ** 2)
    # Over the first cycle the averaging drops a ripple P(omega t) mu g / omega whose mean
    # over a cycle is zero and which vanishes at t = 0 (the table starts at phase 0, where
    # P is odd); what is left is its change as V drifts by 2 pi mu g / omega over that
    # cycle, O(eps^2): about (mu g / omega) (2 pi mu g / omega) / (U omega) = 2 pi eps^2 U omega.
    return [Figure("decay_rate", "decay rate of the cycle-averaged velocity, V < U omega/4 [1/s]",
                   rate, 2 * mu * g / (math.pi * p["omega"] * p["U"]), eps + 0.25**2 / 6,
                   relative=True,
                   source="seed 9.6 ex. 1 (averaged law, rate 2 mu g/(pi omega U))"),
            # the seed's averaged law before linearising: V' = -(2 mu g / pi) arcsin(V / (U omega))
            # (NaN, a FAIL, where the run stops within the first cycle)
            Figure("V_first", "mean absolute velocity over the first cycle [m/s]",
                   vc[0] if len(vc) else math.nan,
                   _averaged_law_first_cycle(1.5, mu * g, p["U"] * p["omega"], period),
                   2 * math.pi * eps**2 * p["U"] * p["omega"],
                   source="seed 9.6 ex. 1 (averaged law before linearising, integrated here)")]


def _averaged_law_first_cycle(v0, mu_g, u_omega, period):
    """Mean over [0, T] of the seed's averaged law V' = -(2 mu g/pi) arcsin(V/(U omega))."""
    from scipy.integrate import solve_ivp
    sol = solve_ivp(lambda t, v: [-(2 * mu_g / math.pi) * math.asin(min(1.0, v[0] / u_omega))],
                    (0, period), [v0], dense_output=True, rtol=1e-10, atol=1e-12)
    tt = np.linspace(0, period, 201)
    return float(np.trapezoid(sol.sol(tt)[0], tt) / period)


# --- still_table: seed 9.6 example 1 without the shaking --------------------------------
def _still_table() -> Assembly:
    return _table_block("still_table", SineMotion(U=0.0, omega=OMEGA), v_absolute=1.5)


def _stick_time(result: Result) -> tuple[float, float]:
    """(t, s) of the located event where the block first comes to rest on the table."""
    ev = result.events.get("block")
    if ev is None:
        return math.nan, math.nan
    stuck = np.flatnonzero(ev["block.mode"] == 0)
    return ((float(ev["time"][stuck[0]]), float(ev["block.s"][stuck[0]])) if len(stuck)
            else (math.nan, math.nan))


def _still_table_figures(result: Result, asm: Assembly) -> list[Figure]:
    """The seed's remark under example 1: without the table's oscillation the velocity
    falls linearly, v = v0 - mu g t, to rest at v0 / (mu g), having slid v0^2 / (2 mu g);
    the shaken block of moving_table still moves at v0 exp(-0.1273 t) then."""
    block = asm.component("block")
    mu_g = block.values["mu_k"] * block.values["g"]
    v_abs = result["block.v"] + result["table.flange.v"]
    v0 = float(v_abs[0])
    t_stop, s_stop = _stick_time(result)
    t_ref, s_ref = v0 / mu_g, v0**2 / (2 * mu_g)
    t = result["time"]
    sliding = t < t_ref
    # the least-squares slope of the samples before the stop: exact for a straight line,
    # so only the solver's error per sample moves it, by at most sum |weights| times it
    tt, vv = t[sliding], v_abs[sliding]
    weights = (tt - tt.mean()) / np.sum((tt - tt.mean()) ** 2)
    slope = float(np.sum(weights * vv))
    return [Figure("t_stop", "time the block comes to rest [s] vs v0 / (mu g)", t_stop, t_ref,
                   solver_accuracy(result, t_ref),
                   source="seed 9.6 ex. 1 (without oscillation the velocity falls linearly)"),
            Figure("s_stop", "distance slid [m] vs v0^2 / (2 mu g)", s_stop, s_ref,
                   solver_accuracy(result, s_ref),
                   source="closed form (constant deceleration mu g, derived here)"),
            Figure("decel", "slope of v_abs before the stop [m/s2] vs -mu g", slope, -mu_g,
                   float(np.sum(np.abs(weights))) * solver_accuracy(result, v0),
                   source="seed 9.6 ex. 1 (linear decrease at mu g)"),
            Figure("v_end", "absolute velocity at the stop time [m/s] (at rest: 0)",
                   float(v_abs[-1]), 0.0, solver_accuracy(result, v0),
                   source="statics (at rest on a still table, friction holds it)")]


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


# --- the exact Coulomb motion of a block on a harmonically shaken table ----------------
# Independent of the FMUs and the masters: the block's absolute velocity is piecewise
# linear while it slides (acceleration -mu_k g mode) and equals the table's while it
# sticks, so the motion is a sequence of phases whose ends are roots of smooth functions.
# Each root is found as the EARLIEST one with a rigorous exclusion test (a bound on the
# function's second derivative), so no short phase can be skipped: that is the property
# the event drivers under test must have too.
class HarmonicTable:
    """The table's path s(t) = U sum_k c_k sin(k omega t) and its derivatives."""

    def __init__(self, U: float, omega: float, c):
        self.U, self.omega = float(U), float(omega)
        self.terms = [(k * self.omega, float(ck)) for k, ck in enumerate(c, start=1) if ck]

    def derivative(self, n: int, t: float) -> float:
        """The n-th time derivative of the position (n = 0: the position)."""
        shift = n * math.pi / 2
        return self.U * sum(ck * kw**n * math.sin(kw * t + shift) for kw, ck in self.terms)

    def velocity_change(self, t0: float, t: float) -> float:
        """v(t) - v(t0) without cancellation (a product of sines), so that the relative
        velocity of a slide that starts at the table's velocity has the right sign even
        a few ulps after the start."""
        return -2 * self.U * sum(ck * kw * math.sin(kw * (t + t0) / 2) * math.sin(kw * (t - t0) / 2)
                                 for kw, ck in self.terms)

    def bound(self, n: int) -> float:
        """An upper bound of |n-th derivative| over all t."""
        return self.U * sum(abs(ck) * kw**n for kw, ck in self.terms)


@dataclass
class TablePhase:
    """One phase of the block's motion: from `t` on, in friction `mode`, with absolute
    velocity `v` (mode as the component's: -1 sliding backward relative to the table,
    0 stuck, +1 sliding forward)."""
    t: float
    mode: int
    v: float


class CoulombOnTable:
    """A block with exact Coulomb friction (mu_s, mu_k, gravity g) on a HarmonicTable."""

    def __init__(self, table: HarmonicTable, mu_s: float, mu_k: float, g: float):
        self.table, self.mu_s, self.mu_k, self.g = table, mu_s, mu_k, g

    def _departure(self, t):
        """The mode the block takes when its velocity equals the table's at time t."""
        a = self.table.derivative(2, t)
        return 0 if abs(a) <= self.mu_s * self.g else -int(math.copysign(1, a))

    def start(self, t: float, v: float) -> TablePhase:
        v_rel = v - self.table.derivative(1, t)
        return TablePhase(t, self._departure(t) if v_rel == 0 else int(math.copysign(1, v_rel)), v)

    def end_of(self, phase: TablePhase, t_limit: float) -> float | None:
        """When `phase` ends (the earliest time in (phase.t, t_limit]), or None."""
        tab, t0 = self.table, phase.t
        if phase.mode == 0:  # stuck until the table's acceleration exceeds mu_s g
            limit = self.mu_s * self.g
            ends = [earliest_zero(lambda t, s=s: limit - s * tab.derivative(2, t),
                                   lambda t, s=s: -s * tab.derivative(3, t), tab.bound(4),
                                   t0, t_limit, 1) for s in (1, -1)]
            ends = [e for e in ends if e is not None]
            return min(ends) if ends else None
        slope = -self.mu_k * self.g * phase.mode
        v_rel0 = phase.v - tab.derivative(1, t0)  # exactly 0 where a phase ended
        return earliest_zero(lambda t: v_rel0 + slope * (t - t0) - tab.velocity_change(t0, t),
                              lambda t: slope - tab.derivative(2, t), tab.bound(3),
                              t0, t_limit, phase.mode)

    def velocity(self, phase: TablePhase, t: float) -> float:
        if phase.mode == 0:
            return self.table.derivative(1, t)
        return phase.v - self.mu_k * self.g * phase.mode * (t - phase.t)

    def displacement(self, phase: TablePhase, t: float) -> float:
        """How far the block moves from phase.t to t within the phase."""
        if phase.mode == 0:
            return self.table.derivative(0, t) - self.table.derivative(0, phase.t)
        dt = t - phase.t
        return phase.v * dt - 0.5 * self.mu_k * self.g * phase.mode * dt * dt

    def advance(self, phase: TablePhase, t_stop: float):
        """(phase at t_stop, displacement over [phase.t, t_stop], phases begun after phase.t)."""
        moved, begun = 0.0, []
        while True:
            t_end = self.end_of(phase, t_stop)
            if t_end is None:
                moved += self.displacement(phase, t_stop)
                return TablePhase(t_stop, phase.mode, self.velocity(phase, t_stop)), moved, begun
            moved += self.displacement(phase, t_end)
            # every phase ends with the block at the table's velocity; a stick ends where
            # |a_table| reaches mu_s g, so it always gives way to a slide (rounding at the
            # root must not make it stick again)
            mode = self._departure(t_end)
            if phase.mode == 0:
                mode = -int(math.copysign(1, self.table.derivative(2, t_end)))
            phase = TablePhase(t_end, mode, self.table.derivative(1, t_end))
            begun.append(phase)


@dataclass
class PeriodicMotion:
    """The block's periodic motion on the table: its mean speed, the number of table
    periods it took from the start to become periodic, and its state (absolute
    velocity and mode) at the start of every period from then on."""
    speed: float
    periods: int
    v_start: float
    mode_start: int


def table_periodic_speed(U: float, omega: float, c, mu_s: float, mu_k: float, g: float,
                         v0: float = 0.0, tol: float = 1e-13,
                         max_periods: int = 20_000) -> PeriodicMotion:
    """The exact mean speed of the block's periodic motion on a HarmonicTable.

    Starts at t = 0 with absolute velocity v0 and maps the state (velocity, mode) over
    one table period T at a time until two successive states agree to `tol` (the
    convergence check); the speed is the displacement over that last period divided
    by T, exact to the root finder's tolerance (~1e-15 in time). Raises RuntimeError
    if the motion does not settle to one period within `max_periods`.
    """
    block = CoulombOnTable(HarmonicTable(U, omega, c), mu_s, mu_k, g)
    period = 2 * math.pi / omega
    phase = block.start(0.0, v0)
    for n in range(1, max_periods + 1):
        new, moved, _ = block.advance(phase, n * period)
        if new.mode == phase.mode and abs(new.v - phase.v) <= tol:
            return PeriodicMotion(moved / period, n, new.v, new.mode)
        phase = new
    raise RuntimeError(f"the motion is not periodic with the table's period after {max_periods} "
                       f"periods (velocity at the period's start still changes by "
                       f"{abs(new.v - phase.v):.3g})")


# The exact motion is T-periodic after about 50 periods (the state at the start of a period
# then repeats to 1e-13; the contraction is about 7x per period), so a run of 120 periods
# measures the speed over its last 40.
CONVEYOR_MEASURED_PERIODS = 40
# What every mode is required to meet (issue 10: the speed equal across modes to 1e-4).
# Measured over 120 periods with every friction event found: me and monolithic at
# tolerance 1e-8 are 3e-10 off; cosim, first order in its step, 4.6e-4 at T/64 and
# 4.8e-6 at T/256 (8.6e-3 at the scene's T/16: that run fails this figure).
CONVEYOR_ACCURACY = 1e-4


@functools.lru_cache(maxsize=16)
def conveyor_exact_speed(U: float, omega: float, c: tuple, mu_s: float, mu_k: float,
                         g: float) -> float:
    """The exact mean speed of the conveyor's periodic motion (seed 9.6 ex. 2), starting
    from rest as the scene does; see :func:`table_periodic_speed` (cached: ~1 s)."""
    return table_periodic_speed(U, omega, c, mu_s, mu_k, g, v0=0.0).speed


def _conveyor_figures(result: Result, asm: Assembly) -> list[Figure]:
    p = asm.component("table").values
    block = asm.component("block").values
    period = 2 * math.pi / p["omega"]
    t, s = result["time"], result["block.s"]
    t0 = t[-1] - CONVEYOR_MEASURED_PERIODS * period
    mean = (s[-1] - np.interp(t0, t, s)) / (t[-1] - t0) if t0 >= 0 else math.nan
    exact = conveyor_exact_speed(p["U"], p["omega"], (p["c1"], p["c2"], p["c3"]),
                                 block["mu_s"], block["mu_k"], block["g"])
    return [Figure("V_steady", f"mean absolute velocity over the last {CONVEYOR_MEASURED_PERIODS} "
                               "periods vs the exact periodic Coulomb motion [m/s]",
                   float(mean), exact, CONVEYOR_ACCURACY,
                   source="exact periodic Coulomb motion (event-driven, derived here; the seed estimates 1.069)")]


_RECORD = ["block.x", "block.v", "block.s", "block.mode", "block.f_friction",
           "table.flange.s", "table.flange.v"]

TABLE_SCENES: dict[str, Scene] = {
    "moving_table": Scene(
        "moving_table", "seed 9.6 ex. 1: block sliding on a table shaken as U sin(wt)",
        _moving_table, stop_time=64 * PERIOD, step=PERIOD / 16, tolerance=1e-8,
        record=_RECORD, figures=_moving_table_figures, picture=plot_table,
        seed="9.6 ex. 1", reference="decay rate 2μ/(πωU) = 0.1273"),
    "still_table": Scene(
        "still_table", "seed 9.6 ex. 1 without the shaking: the same block on a still table "
        "slows linearly and stops (the reference case moving_table is measured against)",
        _still_table, stop_time=64 * PERIOD, step=PERIOD / 16, tolerance=1e-8,
        record=_RECORD, figures=_still_table_figures, picture=plot_table,
        seed="9.6 ex. 1", reference="v = v0 − μ g t: rest at v0/(μg) = 3.75 s after "
        "v0²/(2μg) = 2.8125 m (the shaken block: v0 e^(−0.1273 t))"),
    "conveyor": Scene(
        "conveyor", "seed 9.6 ex. 2: asymmetric shaking conveys the block at a steady speed",
        _conveyor, stop_time=120 * PERIOD, step=PERIOD / 16, tolerance=1e-8,
        record=_RECORD, figures=_conveyor_figures, picture=plot_table,
        seed="9.6 ex. 2",
        reference="the exact periodic Coulomb speed 1.070164 (the seed's median estimate: 1.069)"),
}
