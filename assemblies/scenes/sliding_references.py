"""Independent references for seed 9.8, planar sliding: the seed's friction integrals,
evaluated here by scipy's adaptive quadrature (the rod) and by the ring integrals in
closed form (the disk), integrated by scipy's solve_ivp. Nothing here calls the
library's models or uses Eqs. 9.14-9.16.

For a ring of radius r on a body whose centre moves at speed a with spin omega
(b = omega r), the friction's unit vectors integrate over the ring, in the frame whose
x axis is along v_G, to (seed 9.8's integrand, theta from that axis)
  int (a - b sin t) / |v_P| dt = (2/a) ((a - b) K(k) + (a + b) E(k)),
  int (b - a sin t) / |v_P| dt = (2/b) ((b - a) K(k) + (a + b) E(k)),
with |v_P|^2 = a^2 + b^2 - 2ab sin t and k^2 = 4ab / (a + b)^2 (K, E complete elliptic
integrals): the first is the drag per unit friction along -v_G, the second the torque
per unit friction and radius. The y component vanishes by symmetry, so an axisymmetric
pressure keeps v_G's direction fixed.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from components.bodies.planar_sliding import disk_friction_sums, disk_pressure_shape


def ring_integrals(a: float, b: float) -> tuple[float, float]:
    """(drag, torque) integrals of the unit friction over a ring (see the module)."""
    from scipy.special import ellipe, ellipk
    if a == 0.0:
        return 0.0, 2 * math.pi
    if b == 0.0:
        return 2 * math.pi, 0.0
    m = 4 * a * b / (a + b) ** 2
    K, E = (ellipk(m), ellipe(m)) if m < 1 else (math.inf, 1.0)
    if m >= 1:  # a == b: the integrand (1 - sin t) / sqrt(2 - 2 sin t) is sqrt(1 - sin t)/sqrt 2
        return 4.0, 4.0
    return 2 / a * ((a - b) * K + (a + b) * E), 2 / b * ((b - a) * K + (a + b) * E)


def disk_friction(v: float, omega: float, R: float, pressure: str, mu_N: float,
                  epsrel: float = 1e-11) -> tuple[float, float]:
    """(drag force, torque) on the disk moving at speed v >= 0 and spin omega >= 0,
    mu_N = mu m g: integral over r of mu p(r) r times the ring integrals, by adaptive
    quadrature with the kink at r = v / omega (where the ring passes the instantaneous
    centre) as a break point."""
    from scipy.integrate import quad
    scale = mu_N / (math.pi * R**2)

    def drag(r):
        return float(disk_pressure_shape(pressure, r / R)) * r * ring_integrals(v, omega * r)[0]

    def torque(r):
        return (float(disk_pressure_shape(pressure, r / R)) * r * r
                * ring_integrals(v, omega * r)[1])
    points = [v / omega] if omega > 0 and 0 < v / omega < R else None
    F = quad(drag, 0.0, R, points=points, epsabs=0, epsrel=epsrel, limit=200)[0]
    M = quad(torque, 0.0, R, points=points, epsabs=0, epsrel=epsrel, limit=200)[0]
    return scale * F, scale * M


def disk_rule_friction(v: float, omega: float, R: float, pressure: str,
                       mu_N: float) -> tuple[float, float]:
    """The same by the model's fixed rule (:func:`disk_friction_sums`, evaluated in
    numpy), for the rule's own error against :func:`disk_friction`."""
    drag, torque = disk_friction_sums(v, omega * R, pressure, min, math.sqrt)
    return mu_N * drag, mu_N * R * torque


@dataclass(frozen=True)
class Stop:
    """Where a slider's speed measure |v_G| + |omega| a reached the stop level."""
    t: float          # [s]
    ratio: float      # |v_G| / (|omega| a) there
    work: float       # work done against friction until then [J]
    samples: tuple    # (t, v, omega) along the way, for the rule's error


def disk_stop(m: float, R: float, mu: float, g: float, pressure: str, v0: float,
              omega0: float, level: float, tol: float = 1e-11, rule: bool = False) -> Stop:
    """The disk from speed v0 and spin omega0 (>= 0 both) to |v| + omega R = level:
    m v' = -F, (m R^2 / 2) omega' = -M, W' = F v + M omega; the forces from the ring
    integrals (:func:`disk_friction`), or with `rule` from the model's quadrature rule
    (:func:`disk_rule_friction`: what the rule alone changes)."""
    from scipy.integrate import solve_ivp
    I = m * R**2 / 2
    friction = disk_rule_friction if rule else disk_friction

    def rhs(t, y):
        v, w = max(y[0], 0.0), max(y[1], 0.0)
        F, M = friction(v, w, R, pressure, mu * m * g)
        return [-F / m, -M / I, F * v + M * w]

    def stop(t, y):
        return y[0] + y[1] * R - level
    stop.terminal, stop.direction = True, -1
    t_max = 2 * (m * v0 + I * omega0 / R) / (mu * m * g) + 1.0  # generous: both stop by then
    sol = solve_ivp(rhs, (0.0, t_max), [v0, omega0, 0.0], method="DOP853", events=stop,
                    rtol=tol, atol=tol * level, dense_output=False)
    if not len(sol.t_events[0]):
        raise ValueError("disk_stop: the disk did not come to rest")
    v, w, W = sol.y_events[0][0]
    return Stop(float(sol.t_events[0][0]), v / (w * R), float(W),
                tuple(zip(sol.t, sol.y[0], sol.y[1])))


def rod_friction(vx, vy, omega, theta, L, mu_N):
    """(F_x, F_y, torque, power) on the rod from the seed's integrals over r in
    [-L/2, L/2] (uniform reaction mu_N / L per length), in closed form derived here, not
    the seed's Eqs. 9.14-9.16: along the rod (unit e = (cos, sin)) the velocity of the
    point at r is d e + q n, n = (-sin, cos), with d = v_G . e fixed and q = A3 + omega r
    linear in r, so with u = sqrt(d^2 + q^2) and dq = omega dr
      int dr / u = asinh(q / |d|) / omega,       int q dr / u = u / omega,
      int r q dr / u = (q u / 2 - d^2 asinh(q / |d|) / 2 - A3 u) / omega^2,
      int u dr = (q u / 2 + d^2 asinh(q / |d|) / 2) / omega;
    the friction is -mu_N / L times (d e int 1/u + n int q/u), its torque about G
    -mu_N / L int r q / u, the power it takes mu_N / L int u."""
    c, s = math.cos(theta), math.sin(theta)
    d, A3 = vx * c + vy * s, vy * c - vx * s

    def antiderivatives(r):
        q = A3 + omega * r
        u = math.hypot(d, q)
        ash = math.asinh(q / abs(d)) if d else 0.0
        return np.array([d * ash / omega, u / omega,
                         (q * u / 2 - d * d * ash / 2 - A3 * u) / omega**2,
                         (q * u / 2 + d * d * ash / 2) / omega])
    along, across, torque, power = antiderivatives(L / 2) - antiderivatives(-L / 2)
    k = -mu_N / L
    return (k * (along * c - across * s), k * (along * s + across * c), k * torque,
            -k * power)


def rod_stop(m, L, mu, g, theta0, vx0, vy0, omega0, level, tol=1e-11) -> Stop:
    """The rod of seed 9.8 from its start to |v_G| + |omega| L / 2 = level, with the
    forces from :func:`rod_friction`."""
    from scipy.integrate import solve_ivp
    I = m * L**2 / 12

    def rhs(t, y):
        theta, vx, vy, w, _ = y
        Fx, Fy, M, P = rod_friction(vx, vy, w, theta, L, mu * m * g)
        return [w, Fx / m, Fy / m, M / I, P]

    def stop(t, y):
        return math.hypot(y[1], y[2]) + abs(y[3]) * L / 2 - level
    stop.terminal, stop.direction = True, -1
    t_max = 2 * (m * math.hypot(vx0, vy0) + I * abs(omega0) * 2 / L) / (mu * m * g) + 1.0
    sol = solve_ivp(rhs, (0.0, t_max), [theta0, vx0, vy0, omega0, 0.0], method="DOP853",
                    events=stop, rtol=tol, atol=tol * level)
    if not len(sol.t_events[0]):
        raise ValueError("rod_stop: the rod did not come to rest")
    _, vx, vy, w, W = sol.y_events[0][0]
    return Stop(float(sol.t_events[0][0]), math.hypot(vx, vy) / (abs(w) * L / 2), float(W),
                tuple(zip(sol.t, np.hypot(sol.y[1], sol.y[2]), sol.y[3])))


__all__ = ["Stop", "disk_friction", "disk_rule_friction", "disk_stop", "ring_integrals",
           "rod_friction", "rod_stop"]
