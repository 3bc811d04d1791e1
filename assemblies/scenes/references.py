"""Closed-form results from the seed (Chatterjee, Intermediate Dynamics, ch. 9) for scenes.

These are what a scene's measured figures are compared with, and the root search the
exact event-driven references share. Tests derive their references on their own; these
functions only label a run's table.
"""
from __future__ import annotations

import math


def stick_slip_first_cycle(m, k, g, mu_k, mu_s, v):
    """Seed 9.2 from rest: first slip time t1, re-stick time t2, and x(t2)."""
    w = math.sqrt(k / m)
    t1 = mu_s * m * g / (k * v)
    # v (1 - cos θ) + (g/ω)(μs - μk) sin θ = 0 for θ = ω (t - t1) > 0: tan(θ/2) = -b / v
    b = g * (mu_s - mu_k) / w
    theta = 2 * math.pi - 2 * math.atan2(b, v)
    t2 = t1 + theta / w
    x2 = v * t2 - (v / w) * math.sin(theta) - (g / w**2) * (mu_k + (mu_s - mu_k) * math.cos(theta))
    return t1, t2, x2


def friction_damping_turning_points(m, k, g, mu, x0):
    """Seed 9.4: amplitudes A0, -A1, A2, ... each 2 mu m g / k smaller, half a period apart.

    Returns [(t, x)] up to the turning point where the spring can no longer beat friction.
    """
    w, drop, stuck = math.sqrt(k / m), 2 * mu * m * g / k, mu * m * g / k
    points, x, t = [(0.0, x0)], x0, 0.0
    while abs(x) > stuck:
        x = -math.copysign(abs(x) - drop, x)
        t += math.pi / w
        points.append((t, x))
    return points


def earliest_zero(f, df, curvature, t0, t1, side):
    """The earliest t in (t0, t1] where side * f(t) <= 0, or None.

    `curvature` bounds |f''|, so side*f(a) + side*f'(a) tau - curvature tau^2 / 2 is a
    lower bound of side*f(a + tau): an interval where it stays positive has no zero.
    Where that cannot be shown the interval is halved; a sign change on an interval
    where f' provably keeps its sign is one simple zero, refined by Brent's method.
    """
    from scipy.optimize import brentq

    a, h = t0, (t1 - t0) / 64
    floor = 1e-14 * max(1.0, abs(t1))
    while a < t1:
        b = min(a + h, t1)
        fa, dfa = side * f(a), side * df(a)
        width = b - a
        if (fa > 0 or (fa == 0 and dfa > 0)) and fa + width * (dfa - curvature * width / 2) > 0:
            a, h = b, 2 * h  # provably no zero in (a, b]
            continue
        fb = side * f(b)
        if fb <= 0 and (abs(dfa) > curvature * width or width <= floor):
            if fa <= 0:  # f already at or past zero at a (only at a tangency)
                return a
            return brentq(lambda t: side * f(t), a, b, xtol=1e-15, rtol=8.9e-16)
        if width <= floor:  # a touch of zero without crossing it
            a, h = b, 2 * floor
            continue
        h = width / 2
    return None
