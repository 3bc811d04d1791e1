"""The rolling coin of Chatterjee, Intermediate Dynamics, chapter 6: Newton–Euler, Eqs. 6.1–6.5."""
from __future__ import annotations

import math

from ..component import Component
from ..interfaces import Constraint, Parameter, Profile, State
from ..lazy import lazy

ca = lazy("casadi")  # loaded by the first equation written, not by an import


def rotation_313(phi, theta, psi):
    """R_f of the seed's (3,1,3) Euler angles, R3(phi) R1(theta) R3(psi) (seed 6.1)."""
    cf, sf, ct, st, cp, sp = (ca.cos(phi), ca.sin(phi), ca.cos(theta), ca.sin(theta),
                              ca.cos(psi), ca.sin(psi))
    return ca.vertcat(
        ca.horzcat(cp * cf - sp * ct * sf, -cp * sf * ct - sp * cf, st * sf),
        ca.horzcat(sp * ct * cf + cp * sf, cp * cf * ct - sp * sf, -st * cf),
        ca.horzcat(sp * st, cp * st, ct))


def angular_velocity_313(phi, theta, phi_dot, theta_dot, psi_dot):
    """omega in ground axes from the (3,1,3) rates (seed Eq. 4.6, as printed in 6.1)."""
    return ca.vertcat(ca.cos(phi) * theta_dot + ca.sin(theta) * ca.sin(phi) * psi_dot,
                      ca.sin(phi) * theta_dot - ca.sin(theta) * ca.cos(phi) * psi_dot,
                      phi_dot + ca.cos(theta) * psi_dot)


def disk_inertias(m, R):
    """(I_d, I_a): a thin uniform disk's moments about a diameter and about its axis."""
    return m * R**2 / 4, m * R**2 / 2


def critical_spin_squared(m, R, g):
    """Omega^2 above which straight upright rolling is stable (linearised lean/heading).

    Lean beta = pi/2 - theta, heading rate phi', spin Omega about the coin's axis:
    heading  I_d phi'' = I_a Omega beta'   ->  phi' = (I_a / I_d) Omega beta,
    lean     (I_d + m R^2) beta'' = m g R beta - (I_a + m R^2) Omega phi',
    so beta'' = -[(I_a (I_a + m R^2) / I_d) Omega^2 - m g R] / (I_d + m R^2) beta.
    For the thin disk this is g / (3 R), i.e. v^2 = g R / 3.
    """
    I_d, I_a = disk_inertias(m, R)
    return m * g * R * I_d / (I_a * (I_a + m * R**2))


def steady_precession(theta, psi_dot, R, g):
    """The precession rates phi' of steady rolling at constant theta with spin psi'.

    Angular momentum about G, with everything turning about the vertical at phi':
    sin(theta) phi' [(I_a + m R^2) psi' + (I_a + m R^2 - I_d) cos(theta) phi']
    + m g R cos(theta) = 0; for the disk, divided by m R^2:
    (5/4) s c phi'^2 + (3/2) s psi' phi' + (g/R) c = 0. Returns both real roots
    (an empty tuple if the spin is too slow for any steady circle at this lean).
    """
    s, c = math.sin(theta), math.cos(theta)
    a, b, k = 1.25 * s * c, 1.5 * s * psi_dot, g / R * c
    if a == 0.0:
        return (-k / b,) if b else ()
    disc = b * b - 4 * a * k
    if disc < 0:
        return ()
    root = math.sqrt(disc)
    return ((-b + root) / (2 * a), (-b - root) / (2 * a))


_THETA_RANGE = ("theta_min < theta < pi - theta_min (theta is the tilt of the coin's normal "
                "from vertical, pi/2 upright; 0 lies flat, and a lean to the other side is "
                "phi + pi, not theta < 0)")


class RollingCoin(Component):
    """Thin uniform disk rolling without slip on level ground (seed ch. 6, Eqs. 6.1–6.5).

    Formulation — an ODE in 8 states reached through Newton–Euler with the contact force
    as an unknown, the seed's 6.3:
    * z is eliminated by the holonomic constraint z = R sin(theta) (integral of Eq. 6.3),
      so z is an output, never a start value: a coin must touch the ground.
    * x and y are states whose derivatives are the no-slip constraints 6.1–6.2 at velocity
      level. Holding the constraint where it is stated, rather than differentiating it once
      more into a multiplier DAE, leaves nothing to drift: the contact point's velocity
      stays zero to round-off for as long as the run lasts.
    * Euler angles and their rates are states; Eq. 6.5 (angular momentum about C) gives the
      three Euler accelerations with the contact force eliminated, Eq. 6.4 the force. Both
      are linear in those unknowns, and dae.py solves them. a_G and alpha are the time
      derivatives of v_G (from 6.1–6.3) and of omega (Eq. 4.6), i.e. Eq. 4.10.
    I_cm = R_f diag(I_d, I_d, I_a) R_f^T, I_d = m R^2/4, I_a = m R^2/2 (built here as the
    product: the seed's printed (1,2) entry is garbled).

    The (3,1,3) angles are singular where the coin lies flat (sin(theta) = 0), and so is
    the physics (the contact point is lost). The run ends, by an event located like any
    other, when sin(theta) falls to sin(theta_min): the FMU reports terminateSimulation with
    "coin fell flat at t = ...". Nothing is integrated past that point, so no NaN is ever
    produced.

    Parameters: ``m`` [kg], ``R`` [m], ``g`` [m/s2], ``theta_min`` [rad] the lean from the
    ground at which the coin counts as fallen (default 0.01 rad: the equations carry
    1/sin(theta), still only 100 there).
    States (all settable start values): ``x, y`` [m] centre; ``phi, theta, psi`` [rad]
    (3,1,3) Euler angles, theta = pi/2 upright, 0 flat; ``phi_dot, theta_dot, psi_dot``
    [rad/s]. Outputs: ``z`` [m], ``lean`` [rad] = pi/2 - theta, ``x_C, y_C`` [m] contact
    point, ``F_x, F_y`` [N] friction and ``N`` [N] normal part of the contact force F,
    ``E`` [J] total energy, ``v_C_x, v_C_y, v_C_z`` [m/s] velocity of the coin's material
    point at C from the vector form v_G - omega x r_G/C (zero when 6.1–6.3 are right).
    """

    parameters = (
        Parameter("m", 1.0, "kg", "mass of the coin", min=0.0, min_strict=True),
        Parameter("R", 1.0, "m", "radius of the coin", min=0.0, min_strict=True),
        Parameter("g", 9.81, "m/s2", "gravity", min=0.0),
        Parameter("theta_min", 0.01, "rad", "tilt from the ground at which the coin has fallen",
                  min=0.0, max=0.5, min_strict=True),
    )
    states = (
        State("x", 0.0, "m", "x of the coin's centre"),
        State("y", 0.0, "m", "y of the coin's centre"),
        State("phi", 0.0, "rad", "first (3,1,3) Euler angle: heading of the coin's tilt axis"),
        State("theta", 1.3, "rad", "second Euler angle: tilt of the normal from vertical "
                                    "(pi/2 upright, 0 flat)"),
        State("psi", 0.0, "rad", "third Euler angle: spin about the coin's axis"),
        State("phi_dot", 0.5, "rad/s", "rate of phi (turning of the heading)"),
        State("theta_dot", 0.0, "rad/s", "rate of theta"),
        State("psi_dot", -4.0, "rad/s", "rate of psi (spin; negative rolls towards +x at phi = 0)"),
    )
    # The contact point of 6.2 is the rim's lowest point only for sin(theta) > 0: at
    # theta = 0 the coin lies flat (no contact point, 0/0), and a negative theta would put
    # the "contact" at the top of the rim, the coin hanging below the ground. A lean to the
    # other side is the same theta with phi + pi. Above theta_min, since below it the
    # coin has already fallen.
    start_constraints = (Constraint(
        lambda ns: ns.theta - ns.theta_min, _THETA_RANGE, strict=True), Constraint(
        lambda ns: (math.pi - ns.theta_min) - ns.theta, _THETA_RANGE, strict=True))
    profiles = (Profile("free", "no connectors: released from its start values"),)

    def equations(self, e):
        p, s, d = e.p, e.x, e.der
        angles = ca.vertcat(s.phi, s.theta, s.psi)
        rates = ca.vertcat(s.phi_dot, s.theta_dot, s.psi_dot)
        accelerations = ca.vertcat(d.phi_dot, d.theta_dot, d.psi_dot)  # the unknowns
        cf, sf, ct, st = ca.cos(s.phi), ca.sin(s.phi), ca.cos(s.theta), ca.sin(s.theta)
        e.residual(d.phi - s.phi_dot)
        e.residual(d.theta - s.theta_dot)
        e.residual(d.psi - s.psi_dot)
        # Eqs. 6.1-6.3: the centre's velocity that keeps the contact point at rest
        v_G = -p.R * ca.vertcat(cf * ct * s.phi_dot - st * sf * s.theta_dot + cf * s.psi_dot,
                                sf * ct * s.phi_dot + st * cf * s.theta_dot + sf * s.psi_dot,
                                -ct * s.theta_dot)
        e.residual(d.x - v_G[0])
        e.residual(d.y - v_G[1])

        def time_derivative(expr):  # of an expression in the angles and rates
            return ca.jtimes(expr, angles, rates) + ca.jtimes(expr, rates, accelerations)

        a_G = time_derivative(v_G)
        omega = angular_velocity_313(s.phi, s.theta, s.phi_dot, s.theta_dot, s.psi_dot)
        alpha = time_derivative(omega)  # Eq. 4.10
        R_f = rotation_313(s.phi, s.theta, s.psi)
        I_d, I_a = disk_inertias(p.m, p.R)
        I_cm = R_f @ ca.diag(ca.vertcat(I_d, I_d, I_a)) @ R_f.T
        r_GC = p.R * ca.vertcat(-sf * ct, cf * ct, st)  # seed 6.2, from G's side of C
        e3 = ca.DM([0, 0, 1])
        for row in range(3):  # Eq. 6.5: angular momentum balance about C
            e.residual((-p.m * p.g * ca.cross(r_GC, e3) - p.m * ca.cross(r_GC, a_G)
                        - I_cm @ alpha - ca.cross(omega, I_cm @ omega))[row])
        F = ca.vertcat(e.unknown("F_x"), e.unknown("F_y"), e.unknown("N"))
        for row in range(3):  # Eq. 6.4: linear momentum balance
            e.residual((F - p.m * p.g * e3 - p.m * a_G)[row])

        # the contact point and its material velocity from the seed's vector form, not from
        # the trigonometry above: v_C = v_G - omega x r_G/C, r_G/C = R/|p| S(p) R_f e3
        normal = R_f @ e3
        p_vec = ca.cross(normal, e3)
        r_GC_vector = p.R / ca.norm_2(p_vec) * ca.cross(p_vec, normal)
        v_C = v_G - ca.cross(omega, r_GC_vector)
        z = p.R * st
        e.output("z", z, "m", "height of the centre (R sin(theta): not a free coordinate)")
        e.output("lean", math.pi / 2 - s.theta, "rad", "lean from upright, pi/2 - theta")
        e.output("x_C", s.x - r_GC_vector[0], "m", "x of the contact point on the ground")
        e.output("y_C", s.y - r_GC_vector[1], "m", "y of the contact point on the ground")
        e.output("F_x", F[0], "N", "friction force of the ground on the coin, x part")
        e.output("F_y", F[1], "N", "friction force of the ground on the coin, y part")
        e.output("N", F[2], "N", "normal force of the ground on the coin")
        e.output("E", p.m / 2 * ca.dot(v_G, v_G) + omega.T @ I_cm @ omega / 2 + p.m * p.g * z,
                 "J", "kinetic plus potential energy")
        for axis, component in zip("xyz", range(3)):
            e.output(f"v_C_{axis}", v_C[component], "m/s",
                     f"velocity of the coin's point at the contact, {axis} part (no slip: 0)")
        e.terminate_when(st - ca.sin(p.theta_min), "coin fell flat")
