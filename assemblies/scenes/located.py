"""Instants a scene's figures need that no event lies on, located from one that does.

A smooth friction law (SpringBlock's Eq. 9.5 or 9.7) switches its mode where |x'|
passes a multiple of eps (3 eps sliding, 1.5 eps stuck), so the FMU locates those
instants to its solver's accuracy; the seed's quantities lie a little away: a turning
point at x' = 0, a gross slip where x' passes the law's peak. The gap is short (|dv| /
x'', ~1e-4 s for eps = 1e-3), and over it the block's own equation of motion, started
from the located event's state and integrated to 1e-13 by an 8th-order method, carries
the event's accuracy to the wanted instant unchanged: the value read off the output
grid, or off an interpolant of it across the law's fast band, errs by far more.
"""
from __future__ import annotations

import math

from ..assembly import Assembly


def _end_motion(asm: Assembly, end: str):
    """(s(t), v(t)) of the instance that moves the spring's free end: a ConstantSpeed
    (s0 + v t) or a SineMotion (s0 + U sin(omega t))."""
    comp = asm.component(end)
    p, kind = comp.values, type(comp).__name__
    if kind == "ConstantSpeed":
        return (lambda t: p["s0"] + p["v"] * t), (lambda t: p["v"])
    if kind == "SineMotion":
        return ((lambda t: p["s0"] + p["U"] * math.sin(p["omega"] * t)),
                (lambda t: p["U"] * p["omega"] * math.cos(p["omega"] * t)))
    raise ValueError(f"instance '{end}' is a {kind}: the spring's end must be a ConstantSpeed "
                     "or a SineMotion to continue the block's motion from an event")


def continue_to_speed(asm: Assembly, block: str, end: str, t0: float, x0: float, v0: float,
                      target: float, span: float) -> tuple[float, float]:
    """(t, x) where the block's velocity x' first reaches `target` from (t0, x0, v0),
    integrating ``m x'' = k (s_end - x) + d (v_end - x') - mu(x'/eps) m g`` (SpringBlock
    under its smooth law on a fixed surface, its spring's end moved by `end`) forwards
    (span > 0) or backwards (span < 0) over at most |span| seconds. NaN where x' does not
    get there within the span, or only grazes it."""
    from scipy.integrate import solve_ivp

    from .friction_references import law_coefficient

    comp = asm.component(block)
    p, law = comp.values, comp.option("friction")
    if law == "coulomb":
        raise ValueError(f"instance '{block}': Coulomb friction switches mode at the instant "
                         "itself; continue_to_speed is for the smooth laws")
    m, k, d, g, eps = p["m"], p["k"], p["d"], p["g"], p["eps"]
    s_end, v_end = _end_motion(asm, end)

    def motion(t, y):
        x, v = y
        spring = k * (s_end(t) - x) + d * (v_end(t) - v)
        mu = float(law_coefficient(law, v / eps, p["mu_k"], p["mu_s"]))
        return [v, (spring - mu * m * g) / m]

    def reached(t, y):
        return y[1] - target
    reached.terminal = True
    if v0 == target:
        return t0, x0
    if span == 0:
        return math.nan, math.nan
    sol = solve_ivp(motion, (t0, t0 + span), [x0, v0], method="DOP853", events=reached,
                    rtol=1e-13, atol=1e-16 * max(1.0, abs(x0)))
    if not len(sol.t_events[0]):
        return math.nan, math.nan
    t, (x, v) = float(sol.t_events[0][0]), sol.y_events[0][0]
    # a crossing, not a graze: x' passes the target with an acceleration the forces
    # make, not one a rounding error makes on a speed that only approaches it
    # (a free block's x' decays towards 0 for ever and dithers about it at 1e-17)
    scale = g * max(p["mu_k"], p["mu_s"]) + abs(k * (s_end(t) - x) + d * v_end(t)) / m
    if abs(motion(t, [x, v])[1]) <= 1e-9 * scale:
        return math.nan, math.nan
    return t, float(x)


def continue_to_rest(asm: Assembly, block: str, end: str, t0: float, x0: float,
                     v0: float) -> tuple[float, float]:
    """(t, x) of the turning point (x' = 0) that follows a located event (t0, x0, v0) on
    a block slowing down: the spring then decelerates it by about k |s_end - x| / m or
    more (friction opposes the motion too), so x' reaches 0 within about |v0| m / (k
    |s_end - x|); twice that is searched. NaN where it creeps on instead."""
    s_end, _ = _end_motion(asm, end)
    p = asm.component(block).values
    pull = p["k"] * abs(s_end(t0) - x0) / p["m"]
    span = 2 * abs(v0) / pull if pull > 0 else 0.0
    return continue_to_speed(asm, block, end, t0, x0, v0, 0.0, span)


__all__ = ["continue_to_rest", "continue_to_speed"]
