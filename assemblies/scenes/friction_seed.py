"""Seed 9.2, 9.3 and 9.5 as scenes: steady sliding, stick-slip with a dashpot and with the
smooth law (Fig. 9.4), the distinguished limit, and resonance (Figs. 9.6, 9.7).

Every block is :class:`SpringBlock` or a chain of :class:`MassWithFriction`, each driven
through its own source (a connection joins exactly two ports). The references are
derived in :mod:`.friction_references` without the library's models; the pictures are
in :mod:`.friction_seed_plot`.

The resonance scenes run exact Coulomb friction. The seed's Figs. 9.6 and 9.7 solve
Eq. 9.10, mu tanh(v / 0.001), which drops the factor 3 of Eq. 9.7: that is SpringBlock's
``tanh`` law with eps = 0.003 (``--param block.friction=tanh --param block.eps=0.003``);
its growth is the same 0.118, its turning points are not exact Coulomb's, so the figures
fail under it.
"""
from __future__ import annotations

import functools
import math
from types import SimpleNamespace

import numpy as np
from scipy.interpolate import CubicHermiteSpline

from components.sources.motion import SineMotion
from components.sources.translational import ConstantSpeed
from components.translational.spring_block import SpringBlock
from components.translational.elements import MassWithFriction, Spring

from ..assembly import Assembly
from ..result import Result
from .friction_references import (LAW_BAND, DrivenCoulombBlock, chain_first_slip,
                                  damped_first_slip, damped_stick_slip, eq_9_10,
                                  eq_9_5_gross_slip, smooth_mode_slip_bracket,
                                  half_period_turning_points, perturbation_decay_rate,
                                  resonance_growth_rate, richardson_bound, slide_ends,
                                  sliding_perturbation, smooth_law_peak, smooth_slip_bracket,
                                  steady_sliding_lag, two_halves_rear_slip)
from .friction_seed_plot import (plot_distinguished_limit, plot_resonance, plot_smooth,
                                 plot_sliding)
from .located import continue_to_speed
from .references import stick_slip_first_cycle
from .scene import Figure, Scene

SEED = dict(m=1.0, k=1.0, g=1.0)          # chapter 9's units
DRIFT_910 = 1e4  # a smooth motion's error over ~1e5 steps, as scene.DRIFT
RATE_910_FROM = 40.0  # [s] the growth's fit starts once the motion is near its lock
DRAG = dict(mu_k=0.3, mu_s=0.4)           # Eq. 9.4
SPEED = 0.05                              # Eq. 9.4's driven end [m/s]


# --- what a run promises ---------------------------------------------------------------
def _coupling_error(result: Result, drive: tuple[float, float, float] | None) -> float:
    """How far co-simulating a sine drive may move the block's state [m, m/s].

    `drive` = (U, omega, w0): the drive's amplitude and angular frequency, the block's
    sqrt(k / m). Over a communication step the block's FMU runs the drive's motion
    from its s, v and a at the step's start, with a along the polynomial of degree
    d <= p (the ``extrapolation``; 0 where a step holds it) through a's last values at
    communication points (its rate inputs). That polynomial misses a = -U omega^2
    sin(omega t) by at most U omega^(d+3) / (d+1)! x tau (tau + h) ... (tau + d h)
    <= U omega^(d+3) tau h^d after tau <= h (points at most h = h_max apart), so the
    spring end by U omega^(d+3) h^(d+3) / 6, and the spring gives a velocity impulse
    of at most w0^2 U omega^(d+3) h^(d+4) / 24 over the step; with omega h <= 1 the
    worst degree is 0. A Coulomb oscillator carries an impulse dv on as a change of at
    most dv in its speed and dv / w0 in its position (its motion between events is a
    rotation in (x, v / w0), and a turning point, where v = 0, moves x to second order
    only), so summed over the run (the steps' lengths add up to t_end), without
    cancellation, the state errs by at most w0^2 U omega^3 h^3 max(1, (omega h)^p)
    t_end / 24 x max(1, 1 / w0). Zero for a run that is not co-simulated."""
    s = result.settings
    if drive is None or s.get("scheme") not in ("jacobi", "gauss-seidel"):
        return 0.0
    U, omega, w0 = drive
    p = int(s.get("extrapolation") or 0)
    h = s.get("h_max") or s["step"]
    t_end = float(result["time"][-1] - result["time"][0])
    return (w0**2 * U * (omega * h) ** 3 * max(1.0, (omega * h) ** p) * t_end / 24
            * max(1.0, 1 / w0))


def _accuracy(result: Result, scale: float = 1.0, factor: float = 100.0,
              drive: tuple[float, float, float] | None = None) -> float:
    """As :func:`.scene.solver_accuracy` (100 x the tolerance: event times and states at
    events), plus the coupling's error where a sine `drive` is co-simulated
    (:func:`_coupling_error`)."""
    return factor * result.settings["tolerance"] * max(1.0, abs(scale)) + _coupling_error(result, drive)


def _held_input_delay(result: Result) -> float:
    """How late a co-simulated FMU may see an input that it holds over fixed steps
    (extrapolation 0): one step. Extrapolated linearly (or adaptive, which extrapolates
    by default) a ramp such as a spring pulled at constant speed is exact."""
    s = result.settings
    held = (s.get("scheme") in ("jacobi", "gauss-seidel") and not s.get("adaptive")
            and not s.get("extrapolation"))
    return s["step"] if held else 0.0


def mode_changes(result: Result, instance: str) -> list[tuple[float, float, int, int]]:
    """(t, x, mode before, mode after) at each event that changed the friction mode."""
    if instance not in result.events:
        return []
    ev, previous, out = result.events[instance], int(result[f"{instance}.mode"][0]), []
    for t, x, mode in zip(ev["time"], ev[f"{instance}.x"], ev[f"{instance}.mode"]):
        if int(mode) != previous:
            out.append((float(t), float(x), previous, int(mode)))
            previous = int(mode)
    return out


def turning_points(result: Result, instance: str) -> list[tuple[float, float]]:
    """(t, x) where a slide ended: the block came to rest, to stay or to turn back."""
    return [(t, x) for t, x, before, _ in mode_changes(result, instance) if before != 0]


def slip_times(result: Result, instance: str) -> list[float]:
    """Times a stick ended: the block broke free."""
    return [t for t, _, before, after in mode_changes(result, instance) if before == 0 != after]


def _fit_slope(t, y) -> tuple[float, float]:
    """(least-squares slope, sum of |weights|): an error of at most e in every y moves the
    slope by at most e times that sum."""
    t, y = np.asarray(t, dtype=float), np.asarray(y, dtype=float)
    if len(t) < 3:
        return math.nan, math.nan
    w = (t - t.mean()) / np.sum((t - t.mean()) ** 2)
    return float(np.sum(w * y)), float(np.sum(np.abs(w)))


def _nth(items, n, width=2):
    return items[n] if 0 <= n < len(items) else (math.nan,) * width


# --- 9.5 resonance ---------------------------------------------------------------------
RESONANCE = dict(mu_k=0.6, mu_s=0.6, x=10.0)  # mu_s = mu_k = mu, the seed's x(0) = 10
PHASE_LOCK = 1e-3  # [rad] turning points within this of w0 t = j pi count as locked
EXACT_DRIVEN = ("exact event-driven Coulomb solution (closed form per phase, derived here from "
                "seed Eqs. 9.8-9.9)")
HALF_PERIOD_LAW = "seed 9.5's half-period law (each slide lasts pi / w0)"


def _driven_block(asm: Assembly, drive: str, name: str, U: float, x0: float) -> None:
    asm.add(drive, SineMotion(U=U, omega=1.0))
    asm.add(name, SpringBlock(**SEED, **{**RESONANCE, "x": x0}))
    asm.connect(f"{drive}.flange", f"{name}.flange_a")


def _resonance_growth() -> Assembly:
    asm = Assembly("resonance_growth")
    _driven_block(asm, "drive", "block", U=1.0, x0=10.0)
    return asm


def _resonance_below() -> Assembly:
    asm = Assembly("resonance_below")
    _driven_block(asm, "drive", "block", U=0.4, x0=10.0)
    _driven_block(asm, "drive_locked", "locked", U=0.4, x0=-10.0)
    return asm


def _driven(result: Result, asm: Assembly, drive: str, block: str) -> dict:
    """The driven block's numbers as the assembly holds them (after any --param), and
    `acc`: the accuracy a run promises for a figure of a given size."""
    b, s = asm.component(block).values, asm.component(drive).values
    return dict(m=b["m"], k=b["k"], g=b["g"], mu_s=b["mu_s"], mu_k=b["mu_k"], U=s["U"],
                omega=s["omega"], x0=asm.component(block).starts["x"],
                v0=asm.component(block).starts["v"],
                acc=lambda scale: _accuracy(result, scale,
                                            drive=(s["U"], s["omega"], math.sqrt(b["k"] / b["m"]))))


def _exact(p: dict, t_end: float):
    block = DrivenCoulombBlock(p["m"], p["k"], p["g"], p["mu_s"], p["mu_k"], p["U"], p["omega"])
    return block, block.solve(p["x0"], p["v0"], t_end)


def _half_period_figures(result, p, instance) -> list[Figure]:
    """The turning points of the seed's half-period law against the run's first ones."""
    run = turning_points(result, instance)
    law = half_period_turning_points(p["m"], p["k"], p["g"], p["mu_k"], p["U"], p["x0"],
                                     result["time"][-1])[1:]
    figures = []
    for j, (t_j, x_j) in enumerate(law, start=1):
        t, x = _nth(run, j - 1)
        figures += [Figure(f"A{j}", f"{instance}: turning point {j} [m], one more half period "
                           "of the law", x, x_j, p["acc"](max(abs(x_j), abs(p["x0"]))),
                           source=HALF_PERIOD_LAW),
                    Figure(f"t_A{j}", f"{instance}: its time, j pi / w0 [s]", t, t_j,
                           p["acc"](t_j),
                           source=HALF_PERIOD_LAW)]
    return figures


def _event_count_figure(result, instance, phases) -> Figure:
    return Figure("turns", f"{instance}: slides that ended in the run vs the exact "
                  "event-driven solution", float(len(turning_points(result, instance))),
                  float(len(slide_ends(phases))), 0.0,
                  source=EXACT_DRIVEN)


def _locked_window(phases, w0: float):
    """The exact solution's turning points from where the motion is locked: after the
    last stick, every one within PHASE_LOCK of w0 t = j pi."""
    last_stick = max((ph.t for ph in phases if ph.mode == 0), default=0.0)
    late = [ph for ph in slide_ends(phases) if ph.t > last_stick]
    i = len(late)
    def phase(t):
        return abs(w0 * t - math.pi * round(w0 * t / math.pi))
    while i and phase(late[i - 1].t) <= PHASE_LOCK:
        i -= 1
    return late[i:]


def _lock_truncation(p: dict, window) -> float:
    """How far a turning point of the exact motion may lie from the seed's half-period
    law's straight line in |x| at the law's times j pi / w0, over a window whose turning
    points all lie within PHASE_LOCK of w0 t = j pi.

    Sliding at resonance, x + s mu m g/k = E(t) cos(w0 t) + D sin(w0 t) with
    E = C - (U w0 / 2) t; a slide that starts at rest at phase delta from j pi ends at
    phase delta' from (j + 1) pi with |x + s mu m g/k| = E / cos(delta) + (U / 2) sin(delta)
    at each end (E tan(delta) is carried over). Against the law (delta = 0: the change
    U pi / 2 - 2 mu m g/k exactly) a slide therefore adds E' (sec(delta') - 1) -
    E (sec(delta) - 1) + (U / 2)((sin(delta') - delta') - (sin(delta) - delta)): the first
    terms telescope over the window, the last add up. With |delta| <= PHASE_LOCK = Phi
    and E <= the largest |x| + mu m g/k, each point is off the line by at most
    2 E (sec(Phi) - 1) + n U (Phi - sin(Phi)) after n slides.
    """
    phi = PHASE_LOCK
    if not window:
        return math.nan
    E = max(abs(ph.x) for ph in window) + p["mu_k"] * p["m"] * p["g"] / p["k"]
    return 2 * E * (1 / math.cos(phi) - 1) + len(window) * p["U"] * (phi - math.sin(phi))


def _law_times(points, w0: float):
    """The seed's half-period law's time j pi / w0 of each turning point (t, x): its
    nearest multiple (a fit against the measured times would fold the lock's phase
    drift, ~1e-3 rad here, into the slope)."""
    return [math.pi / w0 * round(w0 * t / math.pi) for t, _ in points]


def _resonance_growth_figures(result: Result, asm: Assembly) -> list[Figure]:
    p = _driven(result, asm, "drive", "block")
    _, phases = _exact(p, float(result["time"][-1]))
    figures = _half_period_figures(result, p, "block")
    w0 = math.sqrt(p["k"] / p["m"])
    # the fit takes the run's turning points where the exact motion is phase-locked only:
    # the law holds there to the lock's truncation bound, not before
    window = _locked_window(phases, w0)
    t_lock = window[0].t if window else math.inf
    rate = resonance_growth_rate(p["m"], p["k"], p["g"], p["mu_k"], p["U"])
    run = [(t, abs(x)) for t, x in turning_points(result, "block")
           if t > t_lock - math.pi / (2 * w0)]
    slope, spread = (_fit_slope(_law_times(run, w0), [x for _, x in run]) if run
                     else (math.nan, math.nan))
    exact_slope, _ = _fit_slope(_law_times([(ph.t, ph.x) for ph in window], w0),
                                [abs(ph.x) for ph in window])
    # each fitted point errs by the solver's accuracy at the window's largest |x| and
    # sits off the law's line by at most the lock's truncation: the slope by the sum of
    # the fit's |weights| times that
    solver = p["acc"](max((abs(ph.x) for ph in window), default=1.0))
    turns = slide_ends(phases)
    last_run = _nth(turning_points(result, "block"), len(turns) - 1)
    # a run stopped before the first slide ends has no last turning point: NaN, a FAIL
    last_x, last_t = (turns[-1].x, turns[-1].t) if turns else (math.nan, math.nan)
    return figures + [
        Figure("rate", f"growth of |x| at turning points [m/s], fitted at t = j pi / w0 over "
               f"the phase-locked window (t >= {t_lock:.1f} s, within {PHASE_LOCK:g} rad), vs "
               "(U pi - 4 mu m g/k) w0/(2 pi); accuracy: the lock's truncation bound plus the "
               "solver's", slope, rate, spread * (_lock_truncation(p, window) + solver),
               source="seed 9.5 (the growth rate, Fig. 9.7)"),
        Figure("rate_exact", "the same fit vs the exact event-driven solution's over the same "
               "turning points [m/s]", slope, exact_slope, spread * solver,
               source=EXACT_DRIVEN),
        Figure("A_last", "last turning point [m] vs the exact event-driven solution",
               last_run[1], last_x, p["acc"](max(abs(last_x), abs(p["x0"]))),
               source=EXACT_DRIVEN),
        Figure("t_last", "its time [s]", last_run[0], last_t, p["acc"](last_t),
               source=EXACT_DRIVEN),
        _event_count_figure(result, "block", phases)]


def _resonance_below_figures(result: Result, asm: Assembly) -> list[Figure]:
    p = _driven(result, asm, "drive", "block")
    exact, phases = _exact(p, float(result["time"][-1]))
    figures = _half_period_figures(result, p, "block")
    figures.append(_event_count_figure(result, "block", phases))
    # no growth: the largest |x| over the last forcing period, the run's and the exact
    # solution's at the same output times (so sampling adds nothing)
    t = result["time"]
    last = t >= t[-1] - 2 * math.pi / p["omega"]
    figures.append(Figure("amp_last", "largest |x| over the last forcing period [m] vs the "
                          "exact solution at the same times",
                          float(np.abs(result["block.x"][last]).max()),
                          float(np.abs(exact.position(phases, t[last])).max()), p["acc"](p["x0"]),
                          source=EXACT_DRIVEN))
    # in phase from x(0) = -10: every slide lasts a half period, the seed's rate is exact
    q = _driven(result, asm, "drive_locked", "locked")
    law = half_period_turning_points(q["m"], q["k"], q["g"], q["mu_k"], q["U"], q["x0"],
                                     float(t[-1]))[1:]
    run = turning_points(result, "locked")
    # a run stopped before the law's first turning point has nothing to hold: NaN, a FAIL
    # in phase the law is exact: the fit at its times errs by the solver's error alone
    slope, spread = (_fit_slope([tt for tt, _ in law], [abs(x) for _, x in run[:len(law)]])
                     if law and len(run) >= len(law) else (math.nan, math.nan))
    t_end, x_end = law[-1] if law else (math.nan, math.nan)
    t_run, x_run = _nth(run, len(law) - 1)
    return figures + [
        Figure("rate_locked", f"locked: change of |x| over its {len(law)} turning points "
               "[m/s] vs (U pi - 4 mu m g/k) w0/(2 pi) < 0: no resonance", slope,
               resonance_growth_rate(q["m"], q["k"], q["g"], q["mu_k"], q["U"]),
               spread * q["acc"](q["x0"]),
               source="seed 9.5 (growth rate (U pi - 4 mu m g/k) w0/(2 pi))"),
        Figure("locked_A_end", "locked: last turning point of the half-period law [m]",
               x_run, x_end, q["acc"](q["x0"]),
               source=HALF_PERIOD_LAW),
        Figure("locked_t_end", "locked: its time [s]", t_run, t_end, q["acc"](t_end),
               source=HALF_PERIOD_LAW)]


# --- 9.5 Eq. 9.10 as the seed runs it ---------------------------------------------------
EQ_9_10_EPS = 3e-3  # SpringBlock's tanh law is mu tanh(3 v / eps): Eq. 9.10's tanh(v / 0.001)
EQ_9_10 = ("independent integration of seed Eq. 9.10 as printed (scipy Radau, rtol 1e-12, "
           "written from the equation)")


def _resonance_eq_9_10() -> Assembly:
    asm = Assembly("resonance_eq_9_10")
    for name, U in (("below", 0.4), ("growth", 1.0)):
        asm.add(f"{name}_drive", SineMotion(U=U, omega=1.0))
        asm.add(name, SpringBlock(**SEED, **{**RESONANCE, "x": 10.0}, friction="tanh",
                                  eps=EQ_9_10_EPS))
        asm.connect(f"{name}_drive.flange", f"{name}.flange_a")
    return asm


@functools.lru_cache(maxsize=8)
def _eq_9_5(m, k, g, mu_k, mu_s, v, eps, t_end):
    """Eq. 9.5's gross-slip instants, once per block and run length (scipy: ~1 s)."""
    return eq_9_5_gross_slip(m, k, g, mu_k, mu_s, v, eps, t_end)


@functools.lru_cache(maxsize=8)
def _eq_9_10(U, x0, mu, scale, t):
    """The reference, once per drive, start, law and output grid (scipy takes seconds)."""
    return eq_9_10(U, x0, 0.0, np.array(t), mu=mu, scale=scale)


def _turns_of(t, x, v, a):
    """(t, x) at each zero of x' on the cubic Hermite interpolant of (v, a); none on
    fewer than two samples (a run stopped before the window)."""
    if len(t) < 2:
        return np.empty(0), np.empty(0)
    spline = CubicHermiteSpline(t, v, a)
    roots = spline.roots(extrapolate=False)
    roots = roots[(roots > t[0]) & (roots < t[-1])]
    return roots, CubicHermiteSpline(t, x, v)(roots)


def _resonance_eq_9_10_figures(result: Result, asm: Assembly) -> list[Figure]:
    t = result["time"]
    figures, refs = [], {}
    for name in ("below", "growth"):
        b, U = asm.component(name).values, asm.component(f"{name}_drive").values["U"]
        x0 = asm.component(name).starts["x"]
        refs[name] = x_ref, _ = _eq_9_10(U, x0, b["mu_k"], b["eps"] / 3, tuple(t))
        # a smooth law's motion is continuous in its start and the solver keeps its
        # local error at tol: accumulated over the run like a conservation figure's
        figures.append(Figure(f"{name}_x", f"U = {U:g}: largest |x - x_Eq.9.10| over the run "
                              "[m]", float(np.abs(result[f"{name}.x"] - x_ref).max()), 0.0,
                              _accuracy(result, x0, DRIFT_910,
                                        drive=(U, asm.component(f"{name}_drive").values["omega"],
                                               math.sqrt(b["k"] / b["m"]))),
                              source=EQ_9_10))
    # Fig. 9.6's claim: no resonant growth at U = 0.4, |x| over the last forcing period
    # far below its start (the reference's, at the same output times)
    last = t >= t[-1] - 2 * math.pi
    x0 = asm.component("below").starts["x"]
    below = asm.component("below").values
    U_below = asm.component("below_drive").values["U"]
    omega_below = asm.component("below_drive").values["omega"]
    w0_below = math.sqrt(below["k"] / below["m"])
    figures.append(Figure("below_amp", "U = 0.4: largest |x| over the last forcing period "
                          "[m] (no growth: far below x(0) = 10)",
                          float(np.abs(result["below.x"][last]).max()),
                          float(np.abs(refs["below"][0][last]).max()),
                          _accuracy(result, x0, DRIFT_910, drive=(U_below, omega_below, w0_below)),
                          source=EQ_9_10))
    # growth: the seed's resonant rate from the run's turning points once locked, as in
    # resonance_growth; the tanh law departs from Coulomb's only while |x'| < 20 x 0.001
    # (beyond, |tanh - sign| < 1e-17), which each reversal crosses in at most
    # 2 V / a_min, a_min = min |x| - U - mu: the friction impulse, and with it the
    # amplitude, is off by at most 2 mu g that / w0 a half period, the slope by w0 / pi
    # times that; the lock's truncation (its phase read off the reference) adds the rest
    b, U = asm.component("growth").values, asm.component("growth_drive").values["U"]
    late = t >= RATE_910_FROM
    turn_t, turn_x = _turns_of(t[late], result["growth.x"][late], result["growth.v"][late],
                               result["growth.a"][late])
    j = np.round(turn_t / math.pi)
    slope, spread = _fit_slope(j * math.pi, np.abs(turn_x)) if len(j) else (math.nan, math.nan)
    x_ref, v_ref = refs["growth"]
    a_ref = -x_ref + U * np.sin(t) - b["mu_k"] * np.tanh(3 * v_ref / b["eps"])
    ref_t, ref_x = _turns_of(t[late], x_ref[late], v_ref[late], a_ref[late])
    phi = float(np.abs(ref_t - math.pi * np.round(ref_t / math.pi)).max()) if len(ref_t) else math.nan
    a_min = float(np.abs(ref_x).min()) - U - b["mu_k"] if len(ref_x) else math.nan
    band = 2 * b["mu_k"] * b["g"] * 2 * (LAW_BAND * b["eps"] / 3) / a_min
    lock = 2 * (float(np.abs(ref_x).max()) + b["mu_k"]) * (1 / math.cos(phi) - 1) \
        + len(ref_t) * U * (phi - math.sin(phi)) if len(ref_x) else math.nan
    figures.append(Figure("rate", f"U = {U:g}: growth of |x| at its turning points after "
                          f"t = {RATE_910_FROM:g} s [m/s] vs (U pi - 4 mu) / (2 pi)", slope,
                          resonance_growth_rate(b["m"], b["k"], b["g"], b["mu_k"], U),
                          band / math.pi + spread * lock + spread * _accuracy(
                              result, 10.0, drive=(U, asm.component("growth_drive").values["omega"],
                                                   math.sqrt(b["k"] / b["m"]))),
                          source="seed 9.5 (the rate is Coulomb's; Eq. 9.10 smooths it within "
                          "the band bound)"))
    return figures


# --- 9.3 the distinguished limit -------------------------------------------------------
STIFFNESSES = (1e2, 1e3, 1e4)  # K [N/m] of the springs inside the block


def _chain(asm: Assembly, prefix: str, n: int, K: float) -> None:
    """driver -(k)- mass1 -(K)- mass2 ... massn, each m/n with the seed's friction; mass1
    is the front, pulled through the spring `pull` whose end moves at SPEED."""
    asm.add(f"{prefix}driver", ConstantSpeed(v=SPEED))
    asm.add(f"{prefix}pull", Spring(c=SEED["k"]))
    asm.connect(f"{prefix}driver.flange", f"{prefix}pull.flange_a")
    left = f"{prefix}pull.flange_b"
    for i in range(1, n + 1):
        asm.add(f"{prefix}mass{i}", MassWithFriction(m=SEED["m"] / n, g=SEED["g"], **DRAG))
        asm.connect(left, f"{prefix}mass{i}.flange_b")
        if i < n:
            asm.add(f"{prefix}link{i}", Spring(c=K))
            asm.connect(f"{prefix}mass{i}.flange_a", f"{prefix}link{i}.flange_b")
            left = f"{prefix}link{i}.flange_a"


def _prefix(K: float) -> str:
    return f"K{round(math.log10(K))}_"  # K2_: K = 1e2 N/m


def _distinguished(n: int):
    def build() -> Assembly:
        asm = Assembly(f"distinguished_limit_{n}")
        for K in STIFFNESSES:
            _chain(asm, _prefix(K), n, K)
        return asm
    return build


def _chain_numbers(asm: Assembly, K: float) -> dict:
    """m (the whole block), k, g, mu_k, mu_s, v of the chain with inner springs K."""
    pre = _prefix(K)
    masses = [asm.component(name).values for name in asm.components
              if name.startswith(f"{pre}mass")]
    return dict(m=sum(b["m"] for b in masses), k=asm.component(f"{pre}pull").values["c"],
                v=asm.component(f"{pre}driver").values["v"],
                **{key: masses[0][key] for key in ("g", "mu_k", "mu_s")})


def _distinguished_figures(n: int):
    def figures(result: Result, asm: Assembly) -> list[Figure]:
        out = []
        for K in STIFFNESSES:
            c, name = _chain_numbers(asm, K), _prefix(K)[:-1]
            t_ref = chain_first_slip(n, c["m"], c["k"], c["g"], c["mu_s"], c["v"])
            firsts = [(slip_times(result, f"{name}_mass{i}") or [math.inf])[0]
                      for i in range(1, n + 1)]
            first = min(firsts) if math.isfinite(min(firsts)) else math.nan
            out += [Figure(f"t_slip_{name}", f"K = {K:g} N/m: first slip in the block of {n} "
                           "masses [s] vs mu_s m g / (n k v)", first, t_ref,
                           _accuracy(result, t_ref) + _held_input_delay(result),
                           source="closed form (seed 9.3: only the front mass is loaded before it slips)"),
                    Figure(f"first_{name}", f"K = {K:g} N/m: which mass slips first (1: the "
                           "front, the one pulled)",
                           float(firsts.index(min(firsts)) + 1) if first == first else math.nan,
                           1.0, 0.0,
                           source="seed 9.3 (the front slips first)")]
        if n == 2:
            out.append(_rear_slip_figure(result, asm))
        return out
    return figures


REAR_ORDER = 0.5  # the rear half's slip time approaches its limit like K^-1/2 (fast period)


def _rear_slip_figure(result: Result, asm: Assembly) -> Figure:
    """The whole block slides (the rear half slips) at the stiffest K, against the K -> oo
    limit of the staircase, with a convergence study from the next stiffness down."""
    stiff, softer = STIFFNESSES[-1], STIFFNESSES[-2]
    rear = {K: (slip_times(result, f"{_prefix(K)}mass2") or [math.nan])[0] for K in (stiff, softer)}
    c = _chain_numbers(asm, stiff)
    limit = two_halves_rear_slip(c["m"], c["k"], c["g"], c["mu_k"], c["mu_s"], c["v"])
    return Figure(f"t_rear_{_prefix(stiff)[:-1]}", f"K = {stiff:g} N/m: the rear half's first "
                  "slip [s] vs its K -> oo limit (the front's staircase); accuracy: K/10 -> K "
                  "convergence, order 1/2", rear[stiff], limit,
                  richardson_bound(rear[softer], rear[stiff], stiff / softer, REAR_ORDER)
                  + _accuracy(result, limit),
                  source="closed form (the K -> oo staircase limit, derived here from seed 9.3)")


def _distinguished_record(n: int) -> list[str]:
    cols = []
    for K in STIFFNESSES:
        pre = _prefix(K)
        cols += [f"{pre}pull.f"] + [f"{pre}link{i}.f" for i in range(1, n)]
        cols += [f"{pre}mass{i}.{c}" for i in range(1, n + 1) for c in ("s", "mode")]
    return cols


# --- 9.2 steady sliding ----------------------------------------------------------------
ETA0 = 0.03      # [m] start off steady sliding; |eta'| <= w0 ETA0 < SPEED: it keeps sliding
DAMPING = 0.2    # [N.s/m] the dashpot of the damped block: decay rate d / 2m = 0.1 /s


def _sliding_block(asm: Assembly, name: str, d: float, eta0: float) -> None:
    x_ss = steady_sliding_lag(SEED["m"], SEED["k"], SEED["g"], DRAG["mu_k"])
    asm.add(f"{name}_end", ConstantSpeed(v=SPEED))
    # on x = v t - x_ss + eta with x' = v: the initialisation finds it sliding forward
    asm.add(name, SpringBlock(**SEED, **DRAG, d=d, x=-x_ss + eta0, v=SPEED))
    asm.connect(f"{name}_end.flange", f"{name}.flange_a")


def _steady_sliding() -> Assembly:
    asm = Assembly("steady_sliding")
    _sliding_block(asm, "steady", 0.0, 0.0)
    _sliding_block(asm, "neutral", 0.0, ETA0)
    _sliding_block(asm, "damped", DAMPING, ETA0)
    return asm


def _eta(result: Result, asm: Assembly, name: str):
    """(p, eta, eta'): the deviation from steady sliding and its rate, from the run."""
    b, v = asm.component(name).values, asm.component(f"{name}_end").values["v"]
    x_ss = steady_sliding_lag(b["m"], b["k"], b["g"], b["mu_k"])
    t = result["time"]
    eta0 = asm.component(name).starts["x"] + x_ss
    return (dict(b, v=v, x_ss=x_ss, eta0=eta0, deta0=asm.component(name).starts["v"] - v),
            result[f"{name}.x"] - (v * t - x_ss), result[f"{name}.v"] - v)


def _extremes(t, eta, deta):
    """(times, values) of the extremes of eta, from its cubic Hermite interpolant with
    eta' = x' - v: error ~ h^4 w0^4 |eta| / 384 for the output interval h."""
    spline = CubicHermiteSpline(t, eta, deta)
    roots = spline.derivative().roots(extrapolate=False)
    roots = roots[(roots > t[0]) & (roots < t[-1])]
    return roots, spline(roots)


def _steady_sliding_figures(result: Result, asm: Assembly) -> list[Figure]:
    t, h = result["time"], result.settings["step"]
    p, _, _ = _eta(result, asm, "steady")
    lag = p["v"] * t[-1] - result["steady.x"][-1]
    figures = [Figure("lag", "steady block: v t - x at the end [m] vs x_ss = mu_k m g / k",
                      float(lag), p["x_ss"], _accuracy(result, p["v"] * t[-1]),
                      source="seed 9.2 (x_ss = mu_k m g / k)")]
    # neutral: the deviation keeps its amplitude (a centre, seed 9.2)
    p, eta, deta = _eta(result, asm, "neutral")
    w0 = math.sqrt(p["k"] / p["m"])
    _, values = _extremes(t, eta, deta)
    hermite = (h * w0) ** 4 / 384
    scale = p["v"] * t[-1]
    figures.append(Figure("eta_neutral", "neutral (no damping): |eta| at its last extreme [m] "
                          "vs its start: no decay, no growth", float(abs(values[-1])) if len(values)
                          else math.nan, abs(p["eta0"]),
                          _accuracy(result, scale) + hermite * abs(p["eta0"]),
                          source="seed 9.2 (a neutral centre without damping)"))
    # damped: the extremes fall as exp(-d t / 2m)
    p, eta, deta = _eta(result, asm, "damped")
    times, values = _extremes(t, eta, deta)
    rate, spread = _fit_slope(times, np.log(np.abs(values)))
    smallest = float(np.abs(values).min()) if len(values) else math.nan
    figures.append(Figure("decay_rate", "damped: decay rate of |eta| at its extremes [1/s] vs "
                          "d / 2m", -rate, perturbation_decay_rate(p["m"], p["d"]),
                          spread * (_accuracy(result, scale) / smallest + hermite),
                          source="closed form d/2m (seed 9.2's damped perturbation)"))
    eta_end = float(sliding_perturbation(t[-1], p["m"], p["k"], p["d"], p["eta0"], p["deta0"])[0])
    figures.append(Figure("eta_damped_end", "damped: eta at the end [m] vs the closed form",
                          float(eta[-1]), eta_end, _accuracy(result, scale),
                          source="closed form (damped perturbation of steady sliding, derived here)"))
    # the closed forms hold while every block slides forward (friction -mu_k m g)
    off = sum(int(np.count_nonzero(result[f"{n}.mode"] != 1))
              for n in ("steady", "neutral", "damped"))
    figures.append(Figure("not_sliding", "output points where a block is not sliding forward "
                          "(the closed forms' premise)", float(off), 0.0, 0.0,
                          source="premise of the closed forms"))
    return figures


# --- 9.2 stick-slip with a dashpot -----------------------------------------------------
# [N.s/m] below and above the 0.2907 where the first slide stops re-sticking (bisection on
# damped_stick_slip, seed Eq. 9.4's numbers)
LIGHT, HEAVY = 0.05, 0.5


def _stick_slip_damped() -> Assembly:
    asm = Assembly("stick_slip_damped")
    for name, d in (("light", LIGHT), ("heavy", HEAVY)):
        asm.add(f"{name}_end", ConstantSpeed(v=SPEED))
        asm.add(name, SpringBlock(**SEED, **DRAG, d=d))
        asm.connect(f"{name}_end.flange", f"{name}.flange_a")
    return asm


def _stick_slip_damped_figures(result: Result, asm: Assembly) -> list[Figure]:
    b, v = asm.component("light").values, asm.component("light_end").values["v"]
    cycle = damped_stick_slip(b["m"], b["k"], b["d"], b["g"], b["mu_k"], b["mu_s"], v)
    T = float(result["time"][-1])
    slips = slip_times(result, "light")
    sticks = [(t, x) for t, x, before, after in mode_changes(result, "light") if after == 0]
    count = math.floor((T - cycle.t1) / cycle.period) + 1
    t2, x2 = _nth(sticks, 0)
    figures = [
        Figure("t1", "light: first slip [s] vs (mu_s m g - d v) / (k v)",
               slips[0] if slips else math.nan, cycle.t1, _accuracy(result, cycle.t1),
               source="closed form (mu_s m g - d v)/(k v) (seed 9.2 with a dashpot, derived here)"),
        Figure("t2", "light: first re-stick [s], the damped slide's x' = 0", t2, cycle.t2,
               _accuracy(result, cycle.t2),
               source="closed form (damped slide's first x' = 0, derived here from seed 9.2)"),
        Figure("x(t2)", "light: position at the re-stick [m]", x2, cycle.x2,
               _accuracy(result, cycle.x2),
               source="closed form (damped slide, derived here from seed 9.2)"),
        Figure("period", "light: second slip - first slip [s] vs x(t2) / v",
               slips[1] - slips[0] if len(slips) > 1 else math.nan, cycle.period,
               2 * _accuracy(result, T),
               source="closed form x(t2)/v (derived here from seed 9.2)"),
        Figure("slips", "light: slips in the run (stick-slip persists)", float(len(slips)),
               float(count), 0.0,
               source="closed form (periodic cycle, derived here from seed 9.2)"),
        Figure("t_last_slip", "light: the last slip [s] vs t1 + (slips - 1) period",
               slips[-1] if slips else math.nan, cycle.t1 + (count - 1) * cycle.period,
               _accuracy(result, T),
               source="closed form (periodic cycle, derived here from seed 9.2)"),
    ]
    # heavy: slips once and slides on, eta a damped free oscillation from the slip
    b, v = asm.component("heavy").values, asm.component("heavy_end").values["v"]
    t1, eta0, deta0 = damped_first_slip(b["m"], b["k"], b["d"], b["g"], b["mu_k"], b["mu_s"], v)
    eta_end = float(sliding_perturbation(T - t1, b["m"], b["k"], b["d"], eta0, deta0)[0])
    x_ss = steady_sliding_lag(b["m"], b["k"], b["g"], b["mu_k"])
    lag = v * T - result["heavy.x"][-1]
    figures += [
        Figure("heavy_slips", "heavy: slips in the run (one: then it slides steadily)",
               float(len(slip_times(result, "heavy"))), 1.0, 0.0,
               source="closed form (derived here: d = 0.5 > 0.2907 slides on after one slip)"),
        Figure("heavy_lag", "heavy: v t - x at the end [m] vs x_ss - eta(t), eta the damped "
               "slide from the slip", float(lag), x_ss - eta_end, _accuracy(result, v * T),
               source="closed form (damped slide from the slip, derived here from seed 9.2)"),
    ]
    return figures


# --- 9.3 the two orders of the limits ---------------------------------------------------
ORDER_K = 1e4  # [N/m] the stiffest chain of distinguished_limit


def _limits_order() -> Assembly:
    """K -> oo first: the rigid block (a chain with K = oo is one mass) under Eq. 9.5 at
    eps = 1e-3 and 1e-4, eps -> 0 after; eps -> 0 first: the two halves with exact
    Coulomb friction, K = 1e4 N/m."""
    asm = Assembly("limits_order")
    for name, eps in (("rigid3", SMOOTH_EPS), ("rigid4", FINER_EPS)):
        asm.add(f"{name}_end", ConstantSpeed(v=SPEED))
        asm.add(name, SpringBlock(**SEED, **DRAG, friction="smooth", eps=eps))
        asm.connect(f"{name}_end.flange", f"{name}.flange_a")
    _chain(asm, _prefix(ORDER_K), 2, ORDER_K)
    return asm


def _limits_order_figures(result: Result, asm: Assembly) -> list[Figure]:
    figures = []
    for name in ("rigid3", "rigid4"):
        b, v = asm.component(name).values, asm.component(f"{name}_end").values["v"]
        lo, hi = smooth_mode_slip_bracket("smooth", b["m"], b["k"], b["g"], b["mu_k"],
                                          b["mu_s"], v, b["eps"])
        slips = slip_times(result, name)
        figures.append(Figure(f"t_{name}", f"K -> oo first, eps = {b['eps']:g}: the rigid "
                              f"block's first slip [s] within [{lo:.4f}, {hi:.4f}] (-> "
                              "mu_s m g / (k v) = 8 as eps -> 0)",
                              slips[0] if slips else math.nan, (lo + hi) / 2,
                              (hi - lo) / 2 + _accuracy(result, hi),
                              source="bounds derived here from seed Eq. 9.5 (the rigid "
                              "block's order of the limits, seed 9.3)"))
    c, pre = _chain_numbers(asm, ORDER_K), _prefix(ORDER_K)
    t_ref = chain_first_slip(2, c["m"], c["k"], c["g"], c["mu_s"], c["v"])
    slips = slip_times(result, f"{pre}mass1")
    figures.append(Figure("t_halves", f"eps -> 0 first (exact Coulomb), K = {ORDER_K:g} N/m: "
                          "the front half's first slip [s] vs mu_s m g / (2 k v) = 4",
                          slips[0] if slips else math.nan, t_ref,
                          _accuracy(result, t_ref) + _held_input_delay(result),
                          source="closed form (seed 9.3: only the front half is loaded)"))
    # the two orders disagree by the factor n = 2 the seed points to: sliding starts earlier
    rigid = figures[1].measured
    figures.append(Figure("order_gap", "rigid block's slip (eps = 1e-4) / the halves' "
                          "(orders of the limits differ: 2 as eps -> 0)",
                          rigid / figures[2].measured, 2.0,
                          2.0 * (figures[1].bound + abs(figures[1].reference - 8.0))
                          / figures[2].reference + 2.0 * figures[2].bound / figures[2].reference,
                          source="seed 9.3 (the distinguished limit: n times earlier)"))
    return figures


# --- 9.2 the smooth law, Fig. 9.4 ------------------------------------------------------
SMOOTH_EPS, FINER_EPS = 1e-3, 1e-4  # [m/s] the seed's eps, and a tenth of it
DELAY_ORDER = 2 / 3  # the slowest of the smooth law's errors: passing the fold of its peak


def _stick_slip_smooth() -> Assembly:
    asm = Assembly("stick_slip_smooth")
    for name, eps in (("smooth", SMOOTH_EPS), ("finer", FINER_EPS)):
        asm.add(f"{name}_end", ConstantSpeed(v=SPEED))
        asm.add(name, SpringBlock(**SEED, **DRAG, friction="smooth", eps=eps))
        asm.connect(f"{name}_end.flange", f"{name}.flange_a")
    return asm


GROSS_SLIP_SEARCH = 1.0  # [s] how far from a mode event its gross-slip instant is sought


def _gross_slip(result: Result, asm: Assembly, name: str, level: float) -> tuple[float, float]:
    """(start, end) of the first gross slip: x' first rises through `level`, then falls
    back through it. Both lie just beside the mode's located events, the first slip (x'
    up through 3 eps) and the first stick after it (x' down through 1.5 eps): from each
    the block's equation of motion carries the event's state to x' = level, backwards
    and forwards (:func:`.located.continue_to_speed`), so both are located to the
    solver's accuracy whatever the output step."""
    changes = mode_changes(result, name)
    slip = next((c for c in changes if c[2] == 0 and c[3] != 0), None)
    stick = next((c for c in changes if slip and c[0] > slip[0] and c[3] == 0), None)
    ev = result.events.get(name)

    def located(change, direction):
        if change is None:
            return math.nan
        i = int(np.flatnonzero(ev["time"] == change[0])[0])
        return continue_to_speed(asm, name, f"{name}_end", change[0], change[1],
                                 ev[f"{name}.v"][i], level, direction * GROSS_SLIP_SEARCH)[0]
    return located(slip, -1), located(stick, 1)


def _stick_slip_smooth_figures(result: Result, asm: Assembly) -> list[Figure]:
    b, v = asm.component("smooth").values, asm.component("smooth_end").values["v"]
    eps, eps_fine = b["eps"], asm.component("finer").values["eps"]
    u_star, mu_max = smooth_law_peak(b["mu_k"], b["mu_s"])
    coarse = _gross_slip(result, asm, "smooth", u_star * eps)
    fine = _gross_slip(result, asm, "finer", u_star * eps_fine)
    exact = stick_slip_first_cycle(b["m"], b["k"], b["g"], b["mu_k"], b["mu_s"], v)
    # As eps -> 0 Eq. 9.5 is Coulomb friction with mu_s replaced by its peak mu_max: that
    # shift is a closed form. What eps adds delays both instants (the creep before the slip
    # slackens the spring, ~eps; passing the fold at the peak takes ~eps^(2/3); the slide
    # starts that much later), so its terms share a sign and the convergence study against
    # the finer block bounds them
    limit = stick_slip_first_cycle(b["m"], b["k"], b["g"], b["mu_k"], mu_max, v)
    figures = []
    for i, name, what in ((0, "t1", "first slip (x' rises through u* eps)"),
                          (1, "t2", "first stick (x' falls back through u* eps)")):
        # (no convergence study, no stated accuracy: a finer eps that is not finer fails)
        study = (richardson_bound(coarse[i], fine[i], eps / eps_fine, DELAY_ORDER)
                 if eps > eps_fine else math.nan)
        accuracy = abs(exact[i] - limit[i]) + study + _accuracy(result, exact[i])
        figures.append(Figure(name, f"eps = {eps:g}: {what} [s] vs the exact Coulomb time",
                              coarse[i], exact[i], accuracy,
                              source="seed Eq. 9.4 exact Coulomb times (closed form), with Eq. 9.5's peak deficit and an eps -> eps/10 study"))
    # the same instants against Eq. 9.5 itself, integrated independently: what the ten
    # printed digits of t1 and t2 are good for (the solver's accuracy at located events)
    law = _eq_9_5(b["m"], b["k"], b["g"], b["mu_k"], b["mu_s"], v, eps,
                  float(result["time"][-1]))
    for i, name in ((0, "t1_law"), (1, "t2_law")):
        figures.append(Figure(name, f"eps = {eps:g}: the same instant [s] vs Eq. 9.5 "
                              "integrated independently", coarse[i], law[i],
                              _accuracy(result, law[i]),
                              source="independent integration of seed Eq. 9.5 (scipy Radau, "
                              "rtol 1e-12, written from the equation)"))
    for name, start, e in (("smooth", coarse[0], eps), ("finer", fine[0], eps_fine)):
        lo, hi = smooth_slip_bracket(b["m"], b["k"], b["g"], b["mu_k"], b["mu_s"], v, e)
        figures.append(Figure(f"t1_bounds_{name}", f"eps = {e:g}: first slip [s] within "
                              f"[{lo:.4f}, {hi:.4f}], bounds derived from the law",
                              start, (lo + hi) / 2, (hi - lo) / 2 + _accuracy(result, hi),
                              source="bounds derived here from seed Eq. 9.5"))
    return figures


# --- the registry's entries --------------------------------------------------------------
def _blocks_record(names, columns) -> list[str]:
    return [f"{n}.{c}" for n in names for c in columns]


SEED_FRICTION_SCENES: dict[str, Scene] = {
    "steady_sliding": Scene(
        "steady_sliding", "seed 9.2: steady sliding x = v t - mu_k m g/k; a disturbance keeps "
        "its amplitude without damping and dies out at d/2m with it (exact Coulomb friction)",
        _steady_sliding, stop_time=40.0, step=0.05, tolerance=1e-10,
        record=_blocks_record(("steady", "neutral", "damped"), ("x", "v", "mode")),
        figures=_steady_sliding_figures, picture=plot_sliding, seed="9.2",
        reference="lag x_ss = μk m g/k = 0.3; a disturbance keeps its amplitude without "
                  "damping, decays at d/2m = 0.1 with it (closed forms)"),
    "stick_slip_damped": Scene(
        "stick_slip_damped", "seed 9.2: stick-slip survives a little damping in the spring "
        "(d = 0.05), not a lot (d = 0.5 slides steadily after one slip); exact Coulomb friction",
        _stick_slip_damped, stop_time=60.0, step=0.1, tolerance=1e-10,
        record=_blocks_record(("light", "heavy"), ("x", "v", "mode")),
        figures=_stick_slip_damped_figures, plot=["light.x", "light.v", "heavy.v"], seed="9.2",
        reference="d = 0.05: t1 = (μs m g − d v)/(k v) = 7.95, t2 = 12.0860, x(t2) = 0.39194, "
                  "period x(t2)/v = 7.8388 (closed form, one root); d = 0.5 > 0.2907: one "
                  "slip, then steady sliding"),
    "stick_slip_smooth": Scene(
        "stick_slip_smooth", "seed 9.2, Fig. 9.4: the smooth friction law Eq. 9.5 "
        "(eps = 1e-3, and 1e-4) against the exact stick-slip's t1 and t2",
        _stick_slip_smooth, stop_time=30.0, step=0.01, tolerance=1e-8,
        record=_blocks_record(("smooth", "finer"), ("x", "v", "a", "f_friction", "mode")),
        figures=_stick_slip_smooth_figures, picture=plot_smooth, seed="9.2, Fig. 9.4",
        reference="exact t1 = 8, t2 = 12.0689, within Eq. 9.5's peak deficit (μmax = 0.39868) "
                  "and an ε → ε/10 convergence bound; rigorous bounds on the slip onset"),
    "resonance_eq_9_10": Scene(
        "resonance_eq_9_10", "seed 9.5, Figs. 9.6 and 9.7 as the seed computes them: Eq. 9.10, "
        "mu tanh(x'/0.001) (SpringBlock's tanh law with eps = 0.003), U = 0.4 and U = 1 from "
        "x(0) = 10",
        _resonance_eq_9_10, stop_time=80.0, step=0.05, tolerance=1e-10,
        record=_blocks_record(("below", "growth"), ("x", "v", "a")),
        figures=_resonance_eq_9_10_figures, plot=["below.x", "growth.x"], mode="me",
        seed="9.5, Eq. 9.10, Figs. 9.6–9.7",
        reference="x(t) of Eq. 9.10 integrated independently (scipy Radau); U = 1 grows at "
                  "(Uπ − 4μ)/(2π) = 0.118 within the tanh band's bound"),
    "distinguished_limit": Scene(
        "distinguished_limit", "seed 9.3: the block as two halves m/2 joined by a stiff "
        "spring K = 1e2, 1e3, 1e4 N/m, pulled as in 9.2 (exact Coulomb friction): the front "
        "half slips at t1/2 = 4 s, before the rigid block's 8 s, whatever K",
        _distinguished(2), stop_time=6.5, step=0.01, tolerance=1e-9,
        record=_distinguished_record(2), figures=_distinguished_figures(2),
        picture=plot_distinguished_limit, mode="me", seed="9.3",
        reference="first slip μs m g/(n k v) = 4 for K = 1e2, 1e3, 1e4 (closed form: only the "
                  "front half is loaded before it slips); the rear half's slip → 6 as K → ∞ "
                  "(staircase limit, K^-1/2 convergence)"),
    "limits_order": Scene(
        "limits_order", "seed 9.3, the other order of the limits: K -> oo first (the rigid "
        "block under Eq. 9.5, eps = 1e-3 and 1e-4) slips at ~8 s, eps -> 0 first (two halves, "
        "exact Coulomb, K = 1e4 N/m) at 4 s",
        _limits_order, stop_time=9.0, step=0.01, tolerance=1e-9,
        record=[*_blocks_record(("rigid3", "rigid4"), ("x", "v", "mode")),
                *[f"K4_mass{i}.{c}" for i in (1, 2) for c in ("s", "mode")]],
        figures=_limits_order_figures, plot=["rigid4.v", "K4_mass1.s", "K4_mass2.s"],
        mode="me", seed="9.3",
        reference="K → ∞ then ε → 0: first slip within rigorous bounds from Eq. 9.5 → "
                  "μs m g/(k v) = 8; ε → 0 then K → ∞: μs m g/(2 k v) = 4 (closed form)"),
    "distinguished_limit_n4": Scene(
        "distinguished_limit_n4", "seed 9.3: the block as n = 4 masses m/4 joined by stiff "
        "springs K = 1e2, 1e3, 1e4 N/m (exact Coulomb friction): the front mass slips "
        "earlier still, at t1/4 = 2 s, whatever K",
        _distinguished(4), stop_time=6.5, step=0.01, tolerance=1e-9,
        record=_distinguished_record(4), figures=_distinguished_figures(4),
        picture=plot_distinguished_limit, mode="me", seed="9.3",
        reference="first slip μs m g/(n k v) = 2 for K = 1e2, 1e3, 1e4 (closed form)"),
    "resonance_growth": Scene(
        "resonance_growth", "seed 9.5, Fig. 9.7: spring end moved as U sin t, U = 1, mu = 0.6, "
        "x(0) = 10; exact Coulomb friction (the seed's figure uses Eq. 9.10, mu tanh(v/0.001), "
        "without Eq. 9.7's factor 3): |x| grows at (U pi - 4 mu)/(2 pi) = 0.118",
        _resonance_growth, stop_time=80.0, step=0.05, tolerance=1e-10,
        record=["block.x", "block.v", "block.mode", "drive.flange.s"],
        figures=_resonance_growth_figures, picture=plot_resonance, mode="me", seed="9.5, Fig. 9.7",
        reference="growth (Uπ − 4μ)/(2π) = 0.1180 once phase-locked; turning points 7.229, "
                  "4.458, 1.688 at π, 2π, 3π; the exact event-driven Coulomb solution"),
    "resonance_below": Scene(
        "resonance_below", "seed 9.5, Fig. 9.6: U = 0.4 < 4 mu / pi, exact Coulomb friction "
        "(the seed's figure uses Eq. 9.10, mu tanh(v/0.001)): from x(0) = 10 no resonant "
        "growth; from x(0) = -10, in phase, |x| falls at (U pi - 4 mu)/(2 pi) = -0.182",
        _resonance_below, stop_time=60.0, step=0.05, tolerance=1e-10,
        record=_blocks_record(("block", "locked"), ("x", "v", "mode")),
        figures=_resonance_below_figures, picture=plot_resonance, mode="me", seed="9.5, Fig. 9.6",
        reference="U < 4μ/π = 0.764: turning points 8.172 … 0.858 at π … 5π, then the exact "
                  "event-driven solution (no growth); in phase from x(0) = −10, rate "
                  "(Uπ − 4μ)/(2π) = −0.182"),
}

__all__ = ["SEED_FRICTION_SCENES"]
