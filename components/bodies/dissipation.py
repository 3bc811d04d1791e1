"""Seed 8.3.1's closing remark made a component: a torque-free body that loses energy inside."""
from __future__ import annotations

from ..component import Component
from ..interfaces import Parameter, State
from .rigid_bodies import ATTITUDE, FREE, PRINCIPAL_INERTIAS, quaternion_rotation
from ..lazy import lazy

ca = lazy("casadi")  # loaded by the first equation written, not by an import



class NutationDamperBody(Component):
    """Torque-free rigid body carrying a viscous spherical nutation damper at G (seed 8.3.1).

    Physical model (Kane's spherical damper): a uniform sphere of moment ``J`` turns in a
    spherical cavity at G, dragged by a viscous film of coefficient ``c``; sigma is its
    angular velocity relative to the body. In body axes: ``I w' + w x I w = c sigma``
    (body), ``J (w' + sigma') + J w x sigma = -c sigma`` (sphere). The film's torques are
    internal, so the total H = I w + J (w + sigma) is fixed in the ground frame exactly,
    and the kinetic energy falls at ``c |sigma|^2`` (>= 0) until the two turn together:
    pure spin about the major axis with T = H^2 / (2 (I_max + J)). ``W_d`` integrates the
    loss so that ``T + W_d`` is conserved. Attitude as in TorqueFreeBody (quaternion).
    Parameters: ``I_xx, I_yy, I_zz`` [kg.m2] principal moments of the body without the
    sphere (triangle inequalities), ``J`` [kg.m2] the sphere's moment, ``c`` [N.m.s/rad].
    States: ``q0..q3`` [1], ``w_x, w_y, w_z`` [rad/s] body rates, ``s_x, s_y, s_z``
    [rad/s] sigma in body axes, ``W_d`` [J] energy dissipated. Outputs: ``H_X, H_Y, H_Z``
    [N.m.s/rad] ground axes, ``H``, ``h_x, h_y, h_z`` body axes, ``T`` [J] body plus
    sphere, ``P_d`` [W] = c |sigma|^2, ``beta`` [rad] angle between H and the line of the
    major axis, ``q_norm_error`` [1].
    """

    parameters = (
        Parameter("I_xx", 1.0, "kg.m2", "principal moment of the body (sphere excluded) about x",
                  min=0.0, min_strict=True),
        Parameter("I_yy", 2.0, "kg.m2", "principal moment of the body (sphere excluded) about y",
                  min=0.0, min_strict=True),
        Parameter("I_zz", 3.0, "kg.m2", "principal moment of the body (sphere excluded) about z",
                  min=0.0, min_strict=True),
        Parameter("J", 0.5, "kg.m2", "moment of inertia of the damper sphere", min=0.0,
                  min_strict=True),
        Parameter("c", 0.5, "N.m.s/rad", "viscous coefficient between sphere and body", min=0.0),
    )
    constraints = PRINCIPAL_INERTIAS
    states = (
        *ATTITUDE,
        State("w_x", 1.0, "rad/s", "angular velocity of the body about body x"),
        State("w_y", 0.05, "rad/s", "angular velocity of the body about body y"),
        State("w_z", 0.05, "rad/s", "angular velocity of the body about body z"),
        State("s_x", 0.0, "rad/s", "angular velocity of the sphere relative to the body, x"),
        State("s_y", 0.0, "rad/s", "angular velocity of the sphere relative to the body, y"),
        State("s_z", 0.0, "rad/s", "angular velocity of the sphere relative to the body, z"),
        State("W_d", 0.0, "J", "energy dissipated in the damper's film"),
    )
    profiles = FREE
    default_stop_time = 400.0

    def equations(self, e):
        p, s, d = e.p, e.x, e.der
        I = ca.vertcat(p.I_xx, p.I_yy, p.I_zz)
        w, sigma = ca.vertcat(s.w_x, s.w_y, s.w_z), ca.vertcat(s.s_x, s.s_y, s.s_z)
        dw, dsigma = ca.vertcat(d.w_x, d.w_y, d.w_z), ca.vertcat(d.s_x, d.s_y, d.s_z)
        body = I * dw + ca.cross(w, I * w) - p.c * sigma
        sphere = p.J * (dw + dsigma) + p.J * ca.cross(w, sigma) + p.c * sigma
        for k in range(3):
            e.residual(body[k])
            e.residual(sphere[k])
        q0, q1, q2, q3 = s.q0, s.q1, s.q2, s.q3
        wx, wy, wz = s.w_x, s.w_y, s.w_z
        e.residual(d.q0 - (-q1 * wx - q2 * wy - q3 * wz) / 2)
        e.residual(d.q1 - (q0 * wx + q2 * wz - q3 * wy) / 2)
        e.residual(d.q2 - (q0 * wy + q3 * wx - q1 * wz) / 2)
        e.residual(d.q3 - (q0 * wz + q1 * wy - q2 * wx) / 2)
        loss = p.c * ca.sumsqr(sigma)
        e.residual(d.W_d - loss)
        h = I * w + p.J * (w + sigma)
        H = quaternion_rotation(q0, q1, q2, q3) @ h
        for k, axis in enumerate("XYZ"):
            e.output(f"H_{axis}", H[k], "N.m.s/rad",
                     f"angular momentum about G, ground {axis} part")
        for k, axis in enumerate("xyz"):
            e.output(f"h_{axis}", h[k], "N.m.s/rad", f"angular momentum about G, body {axis} part")
        e.output("H", ca.norm_2(h), "N.m.s/rad", "magnitude of the angular momentum")
        e.output("T", (ca.dot(I * w, w) + p.J * ca.sumsqr(w + sigma)) / 2, "J",
                 "kinetic energy of body and sphere")
        e.output("P_d", loss, "W", "power dissipated in the damper's film")
        # the other two components straight from h, not |H|^2 - h_major^2: no cancellation
        # when H is within 1e-8 of the axis
        z_major = ca.logic_and(p.I_zz >= p.I_yy, p.I_zz >= p.I_xx)
        y_major = p.I_yy >= p.I_xx
        major = ca.if_else(z_major, h[2], ca.if_else(y_major, h[1], h[0]))
        zx = ca.norm_2(ca.vertcat(h[0], h[2]))
        across = ca.if_else(z_major, ca.norm_2(h[:2]), ca.if_else(y_major, zx, ca.norm_2(h[1:])))
        e.output("beta", ca.atan2(across, ca.fabs(major)), "rad",
                 "angle between H and the line of the major principal axis")
        e.output("q_norm_error", q0**2 + q1**2 + q2**2 + q3**2 - 1, "1",
                 "drift of the quaternion's squared norm from 1")
