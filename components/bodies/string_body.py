"""A rigid body hung by an extensible, damped string from a fixed support: seed 8.6, exercise 5."""
from __future__ import annotations

from ..component import Component
from ..interfaces import Parameter, State
from ..lazy import lazy
from .rigid_bodies import ATTITUDE, FREE, PRINCIPAL_INERTIAS, quaternion_rotation

ca = lazy("casadi")  # loaded by the first equation written, not by an import


class RigidBodyOnString(Component):
    """Rigid body hung from the fixed support O by a string tied to a point B of the body.

    Newton for G and Euler about G in principal body axes, attitude by a unit quaternion
    (as TorqueFreeBody). The string is a spring ``k`` and a dashpot ``c`` in parallel of
    rest length ``L0``; a string cannot push, so its tension is
    ``max(0, k (l - L0)^+ + c l')``, l the distance O-B. The string's force acts along
    the line through O and gravity is vertical, so the vertical angular momentum about O
    is conserved exactly; ``W_d`` integrates the power the string takes out, so that
    ``E + W_d`` is constant (E with the string's elastic energy ``k ((l - L0)^+)^2 / 2``).
    Parameters: ``m`` [kg]; ``I_xx, I_yy, I_zz`` [kg.m2] principal moments at G (triangle
    inequalities checked); ``b_x, b_y, b_z`` [m] the string's point B from G in body
    axes; ``k`` [N/m], ``c`` [N.s/m], ``L0`` [m]; ``g`` [m/s2] along -Z.
    States: ``x, y, z`` [m] G from O in ground axes, ``v_x, v_y, v_z`` [m/s],
    ``q0..q3`` attitude, ``w_x, w_y, w_z`` [rad/s] in body axes, ``W_d`` [J].
    Outputs: ``l`` [m], ``tension`` [N], ``E`` [J] (potential zero at O's height),
    ``T`` [J] kinetic energy, ``H_Z`` [N.m.s/rad] vertical angular momentum about O,
    ``I_OZ`` [kg.m2] the moment of inertia about the vertical through O,
    ``B_X, B_Y, B_Z`` [m] the string's point, ``e_X..e_Z`` [1] body x, y, z axes' ground
    parts as ``x_X, x_Y, x_Z, y_X, ...`` (for pictures), ``q_norm_error`` [1].
    """

    parameters = (
        Parameter("m", 1.0, "kg", "mass of the body", min=0.0, min_strict=True),
        Parameter("I_xx", 0.0108, "kg.m2", "principal moment of inertia about body x",
                  min=0.0, min_strict=True),
        Parameter("I_yy", 0.0167, "kg.m2", "principal moment of inertia about body y",
                  min=0.0, min_strict=True),
        Parameter("I_zz", 0.0208, "kg.m2", "principal moment of inertia about body z",
                  min=0.0, min_strict=True),
        Parameter("b_x", 0.2, "m", "string's point B from G, body x"),
        Parameter("b_y", 0.06, "m", "string's point B from G, body y"),
        Parameter("b_z", -0.04, "m", "string's point B from G, body z"),
        Parameter("k", 200.0, "N/m", "stiffness of the string", min=0.0, min_strict=True),
        Parameter("c", 2.0, "N.s/m", "damping of the string", min=0.0),
        Parameter("L0", 1.0, "m", "unstretched length of the string", min=0.0, min_strict=True),
        Parameter("g", 9.81, "m/s2", "gravity, along -Z", min=0.0),
    )
    constraints = PRINCIPAL_INERTIAS
    states = (
        # B 10 cm off the vertical, the string near its static stretch: it swings and
        # spins but stays taut
        State("x", -0.1, "m", "G from the support, ground X"),
        State("y", -0.06, "m", "G from the support, ground Y"),
        State("z", -1.01, "m", "G from the support, ground Z (up)"),
        State("v_x", 0.0, "m/s", "velocity of G, X"),
        State("v_y", 0.0, "m/s", "velocity of G, Y"),
        State("v_z", 0.0, "m/s", "velocity of G, Z"),
        *ATTITUDE,
        State("w_x", 0.0, "rad/s", "angular velocity about body x"),
        State("w_y", 0.0, "rad/s", "angular velocity about body y"),
        State("w_z", 1.0, "rad/s", "angular velocity about body z"),
        State("W_d", 0.0, "J", "work the string's damping has taken out"),
    )
    profiles = FREE
    default_stop_time = 20.0

    def equations(self, e):
        p, s, d = e.p, e.x, e.der
        Q = quaternion_rotation(s.q0, s.q1, s.q2, s.q3)
        w = ca.vertcat(s.w_x, s.w_y, s.w_z)
        r_G = ca.vertcat(s.x, s.y, s.z)
        v_G = ca.vertcat(s.v_x, s.v_y, s.v_z)
        b = ca.vertcat(p.b_x, p.b_y, p.b_z)
        r_B = r_G + Q @ b
        l = ca.norm_2(r_B)
        u = r_B / l
        l_dot = ca.dot(u, v_G + Q @ ca.cross(w, b))
        stretch = ca.fmax(l - p.L0, 0)
        tension = ca.fmax(p.k * stretch + p.c * l_dot, 0)
        force = -tension * u  # on the body at B, toward O
        e.residual(d.x - s.v_x)
        e.residual(d.y - s.v_y)
        e.residual(d.z - s.v_z)
        e.residual(p.m * d.v_x - force[0])
        e.residual(p.m * d.v_y - force[1])
        e.residual(p.m * d.v_z - force[2] + p.m * p.g)
        I = ca.vertcat(p.I_xx, p.I_yy, p.I_zz)
        torque = ca.cross(b, Q.T @ force)  # about G, body axes
        gyro = ca.cross(w, I * w)
        e.residual(p.I_xx * d.w_x + gyro[0] - torque[0])
        e.residual(p.I_yy * d.w_y + gyro[1] - torque[1])
        e.residual(p.I_zz * d.w_z + gyro[2] - torque[2])
        q0, q1, q2, q3, wx, wy, wz = s.q0, s.q1, s.q2, s.q3, s.w_x, s.w_y, s.w_z
        e.residual(d.q0 - (-q1 * wx - q2 * wy - q3 * wz) / 2)
        e.residual(d.q1 - (q0 * wx + q2 * wz - q3 * wy) / 2)
        e.residual(d.q2 - (q0 * wy + q3 * wx - q1 * wz) / 2)
        e.residual(d.q3 - (q0 * wz + q1 * wy - q2 * wx) / 2)
        # E' = -(tension - k stretch) l': the dashpot's share, and a tension clipped at 0
        # while the spring is stretched (the string goes slack faster than it relaxes)
        e.residual(d.W_d - (tension - p.k * stretch) * l_dot)
        T = (p.m * ca.dot(v_G, v_G) + ca.dot(w, I * w)) / 2
        H_G = Q @ (I * w)
        I_ground = Q @ ca.diag(I) @ Q.T
        e.output("l", l, "m", "length of the string")
        e.output("tension", tension, "N", "tension in the string")
        e.output("E", T + p.m * p.g * s.z + p.k * stretch**2 / 2, "J",
                 "kinetic, gravity and string energy (zero at the support's height, unstretched)")
        e.output("T", T, "J", "kinetic energy")
        e.output("H_Z", p.m * (s.x * s.v_y - s.y * s.v_x) + H_G[2], "N.m.s/rad",
                 "angular momentum about the support, vertical part")
        e.output("I_OZ", I_ground[2, 2] + p.m * (s.x**2 + s.y**2), "kg.m2",
                 "moment of inertia about the vertical through the support")
        for k, axis in enumerate("XYZ"):
            e.output(f"B_{axis}", r_B[k], "m", f"string's point on the body, ground {axis}")
        for j, body_axis in enumerate("xyz"):
            for k, axis in enumerate("XYZ"):
                e.output(f"{body_axis}_{axis}", Q[k, j], "1",
                         f"body {body_axis} axis, ground {axis} part")
        e.output("q_norm_error", q0**2 + q1**2 + q2**2 + q3**2 - 1, "1",
                 "drift of the quaternion's squared norm from 1")
