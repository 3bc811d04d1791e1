"""Flat bodies sliding and spinning on a table with Coulomb friction (seed 9.8).

The rod follows the seed's Eqs. 9.14-9.16 (uniform normal reaction along it);
the disk, whose integrals the seed leaves unevaluated, integrates its friction by a
fixed quadrature rule inside the model, for a radial pressure p(r). Both end their run
(terminateSimulation) once their speeds fall to ``v_stop``: at rest the sliding
equations are 0/0, and a flat slider comes to rest, translation and rotation together,
at a finite time (the friction force and torque stay finite as the speeds vanish).
"""
from __future__ import annotations

import math

from ..component import Component
from ..interfaces import Constraint, Option, Parameter, Profile, State
from ..lazy import lazy

ca = lazy("casadi")  # loaded by the first equation written, not by an import

_FREE = (Profile("free", "no connectors: released from its start values"),)
_PLANAR = (
    State("x", 0.0, "m", "centre of mass G along the table's x axis"),
    State("y", 0.0, "m", "centre of mass G along the table's y axis"),
    State("theta", 0.0, "rad", "angle of the body from the x axis"),
    State("v_x", 1.0, "m/s", "velocity of G along x"),
    State("v_y", 0.0, "m/s", "velocity of G along y"),
)
#: the constant in A4's v_Gy^2 term: + 6 from the seed's integral, where Eq. 9.16 prints - 6
SEED_A4_TYPO_FIXED = 6.0
_WORK = State("W", 0.0, "J", "work done against friction so far")
_V_STOP = Parameter("v_stop", 1e-6, "m/s", "the run ends once |v_G| + |omega| a falls to this "
                    "(a: half the rod's length, the disk's radius)", min=0.0, min_strict=True)


def _common(e, m, inertia, size, force_x, force_y, torque) -> None:
    """Momentum balances, kinematics, energy, the work done against friction (the power
    the friction takes from the body), and the end of the run at rest."""
    s, d = e.x, e.der
    e.residual(m * d.v_x - force_x)
    e.residual(m * d.v_y - force_y)
    e.residual(inertia * d.omega - torque)
    e.residual(d.x - s.v_x)
    e.residual(d.y - s.v_y)
    e.residual(d.theta - s.omega)
    e.residual(d.W + force_x * s.v_x + force_y * s.v_y + torque * s.omega)
    speed = ca.sqrt(s.v_x**2 + s.v_y**2)
    e.output("E", (m * speed**2 + inertia * s.omega**2) / 2, "J", "kinetic energy")
    e.output("speed", speed, "m/s", "speed of G")
    e.output("ratio", speed / (ca.fabs(s.omega) * size), "1",
             "speed of G / (|omega| times half the rod's length or the disk's radius)")
    # the rates at which the speed and the spin fall: each over its value is the time
    # left until it would vanish at that rate
    e.output("speed_rate", (force_x * s.v_x + force_y * s.v_y) / (m * ca.fmax(speed, 1e-300)),
             "m/s2", "d|v_G|/dt")
    e.output("alpha", torque / inertia, "rad/s2", "angular acceleration")
    e.terminate_when(speed + ca.fabs(s.omega) * size - e.p.v_stop,
                     "the slider came to rest (|v_G| + |omega| a <= v_stop)")


class SlidingRod(Component):
    """Uniform rod sliding and spinning on a table, seed 9.8, Eqs. 9.14-9.16.

    The normal reaction is taken uniform along the rod (m g / L per length; the seed's
    assumption: the problem is statically indeterminate), each element's friction
    opposes its own velocity. The seed's closed forms take the rod turning
    counterclockwise: omega > 0 at the start, and they stay valid while it keeps turning
    (the run ends at rest, where both speeds vanish together). The equations are the
    seed's as printed but for the log's argument, evaluated through an identity where
    the printed form cancels, and A4's v_Gy^2 term, (2 cos 2theta + 6) where the seed
    prints - 6: the seed's own integral gives + 6 (see ``equations``).
    Parameters: ``m`` [kg], ``L`` [m], ``mu`` [1], ``g`` [m/s2], ``v_stop`` [m/s].
    States: ``x, y`` [m] G on the table, ``theta`` [rad], ``v_x, v_y`` [m/s], ``omega``
    [rad/s], ``W`` [J] work done against friction.
    Outputs: ``E`` [J] kinetic energy, ``speed`` [m/s] of G, ``ratio`` = |v_G| / (omega L/2).
    """

    parameters = (Parameter("m", 1.0, "kg", "mass of the rod", min=0.0, min_strict=True),
                  Parameter("L", 1.0, "m", "length of the rod", min=0.0, min_strict=True),
                  Parameter("mu", 0.3, "1", "friction coefficient", min=0.0, min_strict=True),
                  Parameter("g", 9.81, "m/s2", "gravity", min=0.0, min_strict=True),
                  _V_STOP)
    states = (*_PLANAR, State("omega", 4.0, "rad/s", "angular velocity (counterclockwise)"), _WORK)
    start_constraints = (Constraint(lambda ns: ns.omega, "omega > 0 (seed Eqs. 9.14-9.16 take "
                                    "the rod turning counterclockwise)", strict=True),)
    profiles = _FREE
    # the default starts come to rest at 0.59 s (rod) and 0.46 s (disk), where the
    # sliding equations end (0/0): the FMU's default experiment stops short of it
    default_stop_time = 0.4

    def equations(self, e):
        p, s = e.p, e.x
        L, w, vx, vy, th = p.L, s.omega, s.v_x, s.v_y, s.theta
        sin, cos = ca.sin(th), ca.cos(th)
        A1 = ca.sqrt(w**2 * L**2 - 4 * vx * w * L * sin + 4 * vy * w * L * cos
                     + 4 * vx**2 + 4 * vy**2)
        A2 = ca.sqrt(w**2 * L**2 + 4 * vx * w * L * sin - 4 * vy * w * L * cos
                     + 4 * vx**2 + 4 * vy**2)
        A3 = vy * cos - vx * sin
        # The log's argument, as printed, is (q- + u-) / (q+ + u+) with q the velocity
        # across the rod and u the speed at each end (A1 = 2 u+, A2 = 2 u-). Where q < 0
        # and the velocity along it, d, is small, q + u cancels to nothing in floating
        # point (log 0 times a vanishing factor: NaN, though the limit is finite); the
        # identity (2u)^2 - (2q)^2 = 4 d^2 gives the same number without cancelling.
        along2 = (vx * cos + vy * sin) ** 2

        def q_plus_u(q2, A):  # 2q + A, for 2q = q2
            return ca.if_else(q2 >= 0, q2 + A, 4 * along2 / ca.fmax(A - q2, 1e-300))
        log = ca.log(q_plus_u(2 * A3 - w * L, A2) / q_plus_u(2 * A3 + w * L, A1))
        # The seed prints (2 cos 2theta - 6) vy^2 in A4; its own integral (the torque of
        # f(r) about G) gives + 6: the braces are then 4 (v_G . e)^2, e along the rod, as
        # Eqs. 9.14-9.15's logs carry. With - 6, A4 is off by 12 vy^2 log and the spin
        # runs down too fast (tests/unit/test_planar_sliding.py checks both)
        A4 = (-((2 * ca.cos(2 * th) + SEED_A4_TYPO_FIXED) * vy**2 - 8 * A3 * cos * vy
                + (2 * ca.cos(2 * th) + 2) * vx**2) * log
              + 2 * A3 * (A1 - A2) - w * L * (A1 + A2))
        scale = p.mu * p.g / (2 * w * L)
        ax = scale * ((2 * vx + 2 * A3 * sin) * log + (A1 - A2) * sin)   # Eq. 9.14
        ay = scale * ((2 * vy - 2 * A3 * cos) * log - (A1 - A2) * cos)   # Eq. 9.15
        alpha = 3 * p.mu * p.g / (2 * w**2 * L**3) * A4                 # Eq. 9.16
        inertia = p.m * L**2 / 12
        _common(e, p.m, inertia, L / 2, p.m * ax, p.m * ay, inertia * alpha)


#: the disk's quadrature: Gauss-Legendre in r on each side of the ring through the
#: instantaneous centre, and in theta over a half turn (see SlidingDisk)
DISK_NODES_R, DISK_NODES_THETA = 8, 12
PRESSURES = ("uniform", "parabolic")


def disk_pressure_shape(pressure: str, rho):
    """p(r) / (m g / (pi R^2)) at rho = r / R: 1 (uniform), or 2 (1 - rho^2), a
    paraboloid with the same total (its integral over the disk is m g either way)."""
    return 1.0 + 0.0 * rho if pressure == "uniform" else 2.0 * (1.0 - rho**2)


def disk_quadrature_rule(n_r: int = DISK_NODES_R, n_theta: int = DISK_NODES_THETA):
    """((t, w_t), (sin(theta), w_theta)): Gauss-Legendre nodes and weights on [0, 1] for
    r (scaled onto each piece), and over the half turn -pi/2..pi/2 for theta, its weights
    doubled for the whole turn (the integrands depend on theta through sin(theta))."""
    import numpy as np
    x, w = np.polynomial.legendre.leggauss(n_r)
    y, w_y = np.polynomial.legendre.leggauss(n_theta)
    return ((x + 1) / 2, w / 2), (np.sin(y * math.pi / 2), w_y * math.pi)


def disk_friction_sums(a, omega_R, pressure: str, fmin, sqrt):
    """(drag, torque / R) per unit mu m g, by the rule, for |v_G| = a and omega R; `fmin`
    and `sqrt` are casadi's in the model, numpy's in the references. The r pieces meet
    at the ring through the instantaneous centre, rho* = a / |omega R| (capped at 1),
    where the integrand has its kink: each piece is smooth inside."""
    (t, w_t), (sin, w_theta) = disk_quadrature_rule()
    rho_star = fmin(a / fmax_abs(omega_R), 1.0)
    drag, torque = 0.0, 0.0
    for lo, hi in ((0.0, rho_star), (rho_star, 1.0)):
        for t_i, w_i in zip(t, w_t):
            rho = lo + (hi - lo) * t_i
            share = (hi - lo) * w_i * rho * disk_pressure_shape(pressure, rho) / math.pi
            b = omega_R * rho
            for sn, w_j in zip(sin, w_theta):
                k = share * w_j / sqrt(a * a + b * b - 2 * a * b * sn + 1e-300)
                drag = drag + k * (a - b * sn)
                torque = torque + k * rho * (b - a * sn)
    return drag, torque


def fmax_abs(x):
    """|x|, floored away from zero (a spin of 0 puts rho* at the rim)."""
    return (x * x + 1e-300) ** 0.5


class SlidingDisk(Component):
    """Flat uniform disk sliding and spinning on a table, seed 9.8, with a radial pressure.

    The seed's momentum balances, m v_G' = integral of f over the disk and
    (m R^2 / 2) omega' = integral of (r x f) . k, with the friction per area
    f = -mu p(r) v_P / |v_P|, v_P = v_G + omega k x r. Measured from v_G's direction, a
    point at (r, theta) moves at (a - b sin(theta), b cos(theta)), a = |v_G|,
    b = omega r: the friction's part across v_G cancels between theta and pi - theta
    (an axisymmetric pressure never turns v_G), and along v_G and in the torque the
    integrands, (a - b sin) / |v_P| and r (b - a sin) / |v_P|, depend on sin(theta)
    alone, so a half turn counts twice. The model takes them by a fixed product rule:
    8-point Gauss-Legendre in r on each side of the ring through the instantaneous
    centre (r = a / |omega|, where the r-integrand has its kink, (a - b) log|a - b|),
    and 12-point Gauss-Legendre in theta over -pi/2..pi/2, where the centre itself
    (v_P = 0, sin(theta) = 1) sits at an end of the interval, among the crowded nodes.
    Quadrature error: with the centre outside the disk the integrand is analytic and
    the rule converges geometrically; inside, the kinks at the pieces' ends make it
    converge algebraically.
    The scenes evaluate the rule against the ring integrals in closed form (complete
    elliptic integrals, :mod:`assemblies.scenes.sliding_references`) over the states the
    motion passes through and carry that error into their accuracies.
    Option ``pressure``: ``uniform`` (p = m g / (pi R^2)) or ``parabolic``
    (p = 2 m g (1 - r^2 / R^2) / (pi R^2)).
    Parameters: ``m`` [kg], ``R`` [m], ``mu`` [1], ``g`` [m/s2], ``v_stop`` [m/s].
    States: ``x, y`` [m], ``theta`` [rad], ``v_x, v_y`` [m/s], ``omega`` [rad/s], ``W`` [J].
    Outputs: ``E`` [J], ``speed`` [m/s], ``ratio`` = |v_G| / (|omega| R).
    """

    parameters = (Parameter("m", 1.0, "kg", "mass of the disk", min=0.0, min_strict=True),
                  Parameter("R", 0.1, "m", "radius of the disk", min=0.0, min_strict=True),
                  Parameter("mu", 0.3, "1", "friction coefficient", min=0.0, min_strict=True),
                  Parameter("g", 9.81, "m/s2", "gravity", min=0.0, min_strict=True),
                  _V_STOP)
    options = (Option("pressure", "uniform", PRESSURES, "radial pressure distribution p(r)"),)
    states = (*_PLANAR, State("omega", 10.0, "rad/s", "angular velocity"), _WORK)
    profiles = _FREE
    # the default starts come to rest at 0.59 s (rod) and 0.46 s (disk), where the
    # sliding equations end (0/0): the FMU's default experiment stops short of it
    default_stop_time = 0.4

    def equations(self, e):
        p, s = e.p, e.x
        # the floor: at rest (a = 0) the direction of v_G is moot, its force 0 x anything
        a = ca.fmax(ca.sqrt(s.v_x**2 + s.v_y**2), 1e-300)
        drag, torque = disk_friction_sums(a, s.omega * p.R, self.option("pressure"),
                                          ca.fmin, ca.sqrt)
        N = p.mu * p.m * p.g
        _common(e, p.m, p.m * p.R**2 / 2, p.R, -N * drag * s.v_x / a, -N * drag * s.v_y / a,
                -N * p.R * torque)


__all__ = ["SEED_A4_TYPO_FIXED", "DISK_NODES_R", "DISK_NODES_THETA", "PRESSURES", "SlidingDisk", "SlidingRod",
           "disk_friction_sums", "disk_pressure_shape",
           "disk_quadrature_rule"]
