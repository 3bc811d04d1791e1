"""Three one-degree-of-freedom bodies from Chatterjee, Intermediate Dynamics: 8.1, 8.2 and 9.6."""
from __future__ import annotations

from ..component import Component
from ..interfaces import Constraint, Option, Parameter, Profile, State
from ..lazy import lazy

ca = lazy("casadi")  # loaded by the first equation written, not by an import

_FREE = (Profile("free", "no connectors: released from its start values"),)


class InclinedCylinder(Component):
    """Uniform cylinder rolling without slip down an incline (seed 8.1, Eq. 8.2).

    ``s'' = (2/3) g sin(alpha)``; the seed calls the incline angle theta, here ``alpha``
    so that it is not taken for a coordinate. Parameters: ``m`` [kg], ``R`` [m],
    ``g`` [m/s2], ``alpha`` [rad]. States: ``s`` [m] distance of the centre down the
    slope, ``v`` [m/s]. Outputs: ``phi`` [rad] = s / R (Eq. 8.1 with s0 = 0),
    ``a`` [m/s2], ``f_friction`` [N] the friction the no-slip contact needs (up the slope),
    ``N`` [N] the normal force; rolling holds while |f_friction| <= mu N, which is the
    importer's to check.
    """

    parameters = (Parameter("m", 1.0, "kg", "mass of the cylinder", min=0.0, min_strict=True),
                  Parameter("R", 0.1, "m", "radius of the cylinder", min=0.0, min_strict=True),
                  Parameter("g", 9.81, "m/s2", "gravity", min=0.0),
                  Parameter("alpha", 0.5, "rad", "angle of the incline to the horizontal",
                            min=-1.5707963267948966, max=1.5707963267948966))
    states = (State("s", 0.0, "m", "distance of the centre down the slope"),
              State("v", 0.0, "m/s", "speed of the centre down the slope"))
    profiles = _FREE

    def equations(self, e):
        p, v, a = e.p, e.x.v, e.der.v
        friction = e.unknown("f_friction")
        e.residual(e.der.s - v)
        e.residual(p.m * a - p.m * p.g * ca.sin(p.alpha) + friction)
        # the friction's moment alone spins the cylinder: J phi'' = F R, with phi'' = a / R
        e.residual(p.m * p.R**2 / 2 * a / p.R - friction * p.R)
        e.output("phi", e.x.s / p.R, "rad", "angle rolled through")
        e.output("a", a, "m/s2", "acceleration of the centre down the slope")
        e.output("f_friction", friction, "N", "friction force on the cylinder, up the slope")
        e.output("N", p.m * p.g * ca.cos(p.alpha), "N", "normal force of the incline")


class HemisphericalShell(Component):
    """Thin hemispherical shell rocking on a table, planar (seed 8.2), fully nonlinear.

    G lies R/2 below the centre O; I_zz at G is 5 m R^2 / 12. Option ``contact``:
    ``rolling`` (no slip: ``(5/3 - cos phi) phi'' + sin(phi) phi'^2 / 2 + g sin(phi) / (2R)
    = 0``, small oscillations w^2 = 3g/(4R)) or ``frictionless`` (``(13/24 - cos(2 phi)/8)
    phi'' + sin(2 phi) phi'^2 / 8 + g sin(phi) / (2R) = 0``, w^2 = 6g/(5R); no horizontal
    force, so G keeps its horizontal position — a uniform drift of G is a Galilean shift
    and is left out). Valid while the rim stays off the table, |phi| < pi/2 (the run ends
    there), and while the normal force ``N`` stays positive (an output to check).
    Parameters: ``m`` [kg], ``R`` [m], ``g`` [m/s2]. States: ``phi`` [rad] tilt,
    ``w`` [rad/s], ``x_G`` [m] horizontal position of G. Outputs: ``y_G`` [m], ``x_contact``
    [m], ``N`` [N], ``E`` [J].
    """

    options = (Option("contact", "rolling", ("rolling", "frictionless"),
                      "contact with the table: rolling without slip, or frictionless"),)
    parameters = (Parameter("m", 1.0, "kg", "mass of the shell", min=0.0, min_strict=True),
                  Parameter("R", 1.0, "m", "radius of the shell", min=0.0, min_strict=True),
                  Parameter("g", 9.81, "m/s2", "gravity", min=0.0))
    states = (State("phi", 0.0, "rad", "tilt of the shell from upright"),
              State("w", 0.0, "rad/s", "angular velocity of the shell"),
              State("x_G", 0.0, "m", "horizontal position of the centre of mass"))
    profiles = _FREE

    def equations(self, e):
        p, phi, w, dw = e.p, e.x.phi, e.x.w, e.der.w
        rolling = e.option("contact") == "rolling"
        # from the seed's positions of G: x_G = R phi - R sin(phi)/2 (rolling) or fixed
        dx_dphi = p.R - p.R / 2 * ca.cos(phi) if rolling else 0
        y_G = p.R - p.R / 2 * ca.cos(phi)
        J = 5 * p.m * p.R**2 / 12
        # Lagrange: T = (m (x_G'^2 + y_G'^2) + J w^2) / 2 = M(phi) w^2 / 2
        M = p.m * (dx_dphi**2 + (p.R / 2 * ca.sin(phi))**2) + J
        dM = ca.jacobian(M, phi)
        dV = p.m * p.g * p.R / 2 * ca.sin(phi)
        e.residual(e.der.phi - w)
        e.residual(M * dw + dM * w**2 / 2 + dV)
        e.residual(e.der.x_G - dx_dphi * w)
        # vertical momentum of G: N - m g = m y_G''
        y_dd = p.R / 2 * (ca.sin(phi) * dw + ca.cos(phi) * w**2)
        e.output("y_G", y_G, "m", "height of the centre of mass above the table")
        e.output("x_contact", e.x.x_G + p.R / 2 * ca.sin(phi), "m", "contact point (below O)")
        e.output("N", p.m * (p.g + y_dd), "N", "normal force of the table")
        e.output("E", M * w**2 / 2 + p.m * p.g * y_G, "J", "kinetic plus potential energy")
        e.terminate_when(ca.pi / 2 - ca.fabs(phi), "the rim touched the table (|phi| = pi/2)")


class RodOnRollers(Component):
    """Rod on two counter-rotating rollers: a frictional harmonic oscillator (seed 9.6, ex. 3).

    ``x'' = -(2 g mu / D) x`` while both contacts slip steadily in opposite directions (the
    rollers' surface speed exceeds |v|) and both normal forces ``N_1 = m g (D/2 - x)/D``,
    ``N_2 = m g (D/2 + x)/D`` are positive, i.e. |x| < D/2, and the rod rests on both
    rollers, |x| < (L - D)/2. The run ends (terminateSimulation, with the reason) where
    ``margin`` = min(D/2, (L - D)/2) - |x| reaches zero; the rod's speed against the
    rollers' is not known to the model and stays the importer's to check.
    Parameters: ``m`` [kg], ``L`` [m] > D, ``D`` [m] roller spacing, ``mu`` [1], ``g`` [m/s2].
    States: ``x`` [m] rod centre right of the midpoint, ``v`` [m/s].
    """

    parameters = (Parameter("m", 1.0, "kg", "mass of the rod", min=0.0, min_strict=True),
                  Parameter("L", 2.0, "m", "length of the rod", min=0.0, min_strict=True),
                  Parameter("D", 1.0, "m", "distance between the rollers", min=0.0, min_strict=True),
                  Parameter("mu", 0.3, "1", "friction coefficient at each roller", min=0.0),
                  Parameter("g", 9.81, "m/s2", "gravity", min=0.0))
    constraints = (Constraint(lambda p: p.L - p.D, "L > D (the rod spans both rollers)", strict=True),)
    states = (State("x", 0.0, "m", "rod centre, right of the midpoint between the rollers"),
              State("v", 0.0, "m/s", "velocity of the rod"))
    profiles = _FREE

    def equations(self, e):
        p, x = e.p, e.x.x
        N_1, N_2 = e.unknown("N_1"), e.unknown("N_2")
        e.residual(N_1 + N_2 - p.m * p.g)  # no vertical acceleration
        e.residual(N_1 * (p.D / 2 + x) - N_2 * (p.D / 2 - x))  # no rotation about G
        e.residual(p.m * e.der.v - p.mu * (N_1 - N_2))  # left roller pushes right, right left
        e.residual(e.der.x - e.x.v)
        e.output("N_1", N_1, "N", "normal force of the left roller")
        e.output("N_2", N_2, "N", "normal force of the right roller")
        margin = ca.fmin(p.D / 2, (p.L - p.D) / 2) - ca.fabs(x)
        e.output("margin", margin, "m", "distance to the edge of the model's validity")
        e.terminate_when(margin, "the rod left |x| < min(D/2, (L - D)/2): it tips or falls off")


def _rotation(axis: str, angle):
    """Rotation matrix about a body axis x, y or z (CasADi)."""
    c, s = ca.cos(angle), ca.sin(angle)
    if axis == "x":
        return ca.vertcat(ca.horzcat(1, 0, 0), ca.horzcat(0, c, -s), ca.horzcat(0, s, c))
    if axis == "y":
        return ca.vertcat(ca.horzcat(c, 0, s), ca.horzcat(0, 1, 0), ca.horzcat(-s, 0, c))
    return ca.vertcat(ca.horzcat(c, -s, 0), ca.horzcat(s, c, 0), ca.horzcat(0, 0, 1))


class ConeOnIncline(Component):
    """Uniform right circular cone rolling without slip on an incline (seed 8.6, exercise 2).

    The cone lies on its side: its slant line from the apex A to the base rim touches the
    plane. No slip along the whole line pins the apex, so A is a fixed point and the one
    coordinate is ``phi``, the angle of the contact line in the plane from straight down
    the slope. Rolling ties the spin about the cone's own axis to phi (the base rim rolls
    on the circle of radius h the rim point traces): ``psi = -phi / sin(beta)``, beta the
    half-angle, sin(beta) = R / h, which makes the constraint holonomic. The equation of
    motion is written by Lagrange from the body itself, not from a derived inertia:
    attitude ``Q = Rz(phi) Ry(-beta) Rx(psi)`` in incline axes (x down the slope, z the
    plane's normal), the inertia tensor about the apex in body axes (x the cone's axis)
    ``diag(3 m R^2 / 10, I_t, I_t)``, ``I_t = 3 m (R^2 / 4 + H^2) / 5``, H = h cos(beta)
    the height, the angular velocity from ``Q' Q^T`` and G at 3H/4 along the axis.
    Valid while the cone rolls (friction enough) and stays on its side.
    Parameters: ``m`` [kg], ``R`` [m] base radius, ``h`` [m] slant height > R, ``g``
    [m/s2], ``alpha`` [rad] the incline's angle. States: ``phi`` [rad], ``w`` [rad/s].
    Outputs: ``z_G`` [m] height of G above the plane (constant: the plane's normal force
    does no work), ``E`` [J] kinetic plus potential energy (zero with G level with A),
    ``omega`` [rad/s] the magnitude of the angular velocity, along the contact line.
    """

    parameters = (Parameter("m", 1.0, "kg", "mass of the cone", min=0.0, min_strict=True),
                  Parameter("R", 0.1, "m", "radius of the base circle", min=0.0, min_strict=True),
                  Parameter("h", 0.3, "m", "slant height, apex to the base rim",
                            min=0.0, min_strict=True),
                  Parameter("g", 9.81, "m/s2", "gravity", min=0.0),
                  Parameter("alpha", 0.3, "rad", "angle of the incline to the horizontal",
                            min=0.0, max=1.5707963267948966))
    constraints = (Constraint(lambda p: p.h - p.R, "h > R (the slant is longer than the radius)",
                              strict=True),)
    states = (State("phi", 0.0, "rad", "contact line's angle in the plane from down the slope"),
              State("w", 0.0, "rad/s", "rate of phi"))
    profiles = _FREE

    def equations(self, e):
        p, phi, w = e.p, e.x.phi, e.x.w
        sin_b = p.R / p.h
        cos_b = ca.sqrt(1 - sin_b**2)
        beta = ca.asin(sin_b)
        H = p.h * cos_b
        Q = _rotation("z", phi) @ _rotation("y", -beta) @ _rotation("x", -phi / sin_b)
        # angular velocity per unit phi': vee(dQ/dphi Q^T), in incline axes
        W = ca.jacobian(ca.reshape(Q, 9, 1), phi)
        W = ca.reshape(W, 3, 3) @ Q.T
        Omega = ca.vertcat(W[2, 1], W[0, 2], W[1, 0])
        I_t = 3 * p.m * (p.R**2 / 4 + H**2) / 5
        I_body = ca.diag(ca.vertcat(3 * p.m * p.R**2 / 10, I_t, I_t))
        M = Omega.T @ Q @ I_body @ Q.T @ Omega  # T = M phi'^2 / 2, about the fixed apex
        r_G = Q @ ca.vertcat(3 * H / 4, 0, 0)
        gravity = p.g * ca.vertcat(ca.sin(p.alpha), 0, -ca.cos(p.alpha))
        V = -p.m * ca.dot(gravity, r_G)
        e.residual(e.der.phi - w)
        e.residual(M * e.der.w + ca.jacobian(M, phi) * w**2 / 2 + ca.jacobian(V, phi))
        e.output("z_G", r_G[2], "m", "height of the centre of mass above the plane")
        e.output("E", M * w**2 / 2 + V, "J", "kinetic plus potential energy")
        e.output("omega", ca.norm_2(Omega) * ca.fabs(w), "rad/s",
                 "magnitude of the angular velocity (along the contact line)")
