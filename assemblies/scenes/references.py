"""Closed-form results from the seed (Chatterjee, Intermediate Dynamics, ch. 9) for scenes.

These are what a scene's measured figures are compared with. Tests derive their
references on their own; these functions only label a run's table.
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
