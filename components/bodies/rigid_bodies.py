"""Free 3-D rigid bodies and the skate of Chatterjee, Intermediate Dynamics: 8.3, 8.4 and 5.5."""
from __future__ import annotations

from ..component import Component
from ..interfaces import Constraint, Parameter, Profile, State
from ..lazy import lazy

ca = lazy("casadi")  # loaded by the first equation written, not by an import

FREE = (Profile("free", "no connectors: released from its start values"),)
# what every body given by principal moments and an attitude quaternion declares
PRINCIPAL_INERTIAS = (
    Constraint(lambda p: p.I_xx + p.I_yy - p.I_zz, "I_zz <= I_xx + I_yy (triangle inequality)"),
    Constraint(lambda p: p.I_yy + p.I_zz - p.I_xx, "I_xx <= I_yy + I_zz (triangle inequality)"),
    Constraint(lambda p: p.I_zz + p.I_xx - p.I_yy, "I_yy <= I_zz + I_xx (triangle inequality)"),
)
ATTITUDE = (
    State("q0", 1.0, "1", "attitude quaternion, scalar part"),
    State("q1", 0.0, "1", "attitude quaternion, x part"),
    State("q2", 0.0, "1", "attitude quaternion, y part"),
    State("q3", 0.0, "1", "attitude quaternion, z part"),
)


def quaternion_rotation(q0, q1, q2, q3):
    """Rotation matrix of the quaternion (q0; q1, q2, q3), divided by |q|^2 so that a
    quaternion whose norm drifted by the integration error still gives a rotation."""
    n = q0**2 + q1**2 + q2**2 + q3**2
    return ca.vertcat(
        ca.horzcat(q0**2 + q1**2 - q2**2 - q3**2, 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2)),
        ca.horzcat(2 * (q1 * q2 + q0 * q3), q0**2 - q1**2 + q2**2 - q3**2, 2 * (q2 * q3 - q0 * q1)),
        ca.horzcat(2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), q0**2 - q1**2 - q2**2 + q3**2),
    ) / n


class TorqueFreeBody(Component):
    """Rigid body with no torque about its centre of mass: Euler's equations and attitude.

    Seed 8.3, Eqs. 8.3–8.5 in principal body axes, ``I_xx w_x' = -(I_zz - I_yy) w_y w_z``
    and cyclically, with the attitude as a unit quaternion q (body to ground axes),
    ``q' = q (x) (0, w) / 2``: the angular velocity alone does not say where the body
    points, and a quaternion has no singular attitude. Its norm is not re-imposed; the
    rotation matrix divides by |q|^2 and ``q_norm_error`` reports the drift.
    Parameters: ``I_xx, I_yy, I_zz`` [kg.m2] principal moments, each > 0 and obeying the
    triangle inequalities ``I_i + I_j >= I_k`` (a body's second moment of mass is
    semidefinite; a flat plate sits on the boundary).
    States: ``q0..q3`` [1] attitude (start 1, 0, 0, 0: body axes along ground axes),
    ``w_x, w_y, w_z`` [rad/s] angular velocity in body axes.
    Outputs: ``H_X, H_Y, H_Z`` [N.m.s/rad] angular momentum in ground axes (constant),
    ``H`` its magnitude, ``T`` [J] kinetic energy, ``x_X, x_Y, x_Z`` [1] the body x axis
    in ground axes, ``q_norm_error`` [1] = |q|^2 - 1.
    """

    parameters = (
        Parameter("I_xx", 1.0, "kg.m2", "principal moment of inertia about body x",
                  min=0.0, min_strict=True),
        Parameter("I_yy", 2.0, "kg.m2", "principal moment of inertia about body y",
                  min=0.0, min_strict=True),
        Parameter("I_zz", 3.0, "kg.m2", "principal moment of inertia about body z",
                  min=0.0, min_strict=True),
    )
    constraints = PRINCIPAL_INERTIAS
    states = (
        *ATTITUDE,
        State("w_x", 0.01, "rad/s", "angular velocity about body x"),
        State("w_y", 1.0, "rad/s", "angular velocity about body y"),
        State("w_z", 0.0, "rad/s", "angular velocity about body z"),
    )
    profiles = FREE
    default_stop_time = 20.0

    def equations(self, e):
        p, s, d = e.p, e.x, e.der
        q0, q1, q2, q3, wx, wy, wz = s.q0, s.q1, s.q2, s.q3, s.w_x, s.w_y, s.w_z
        e.residual(p.I_xx * d.w_x + (p.I_zz - p.I_yy) * wy * wz)  # Eq. 8.3
        e.residual(p.I_yy * d.w_y + (p.I_xx - p.I_zz) * wx * wz)  # Eq. 8.4
        e.residual(p.I_zz * d.w_z + (p.I_yy - p.I_xx) * wx * wy)  # Eq. 8.5
        # q' = q (x) (0, w) / 2, w in body axes
        e.residual(d.q0 - (-q1 * wx - q2 * wy - q3 * wz) / 2)
        e.residual(d.q1 - (q0 * wx + q2 * wz - q3 * wy) / 2)
        e.residual(d.q2 - (q0 * wy + q3 * wx - q1 * wz) / 2)
        e.residual(d.q3 - (q0 * wz + q1 * wy - q2 * wx) / 2)
        rotation = quaternion_rotation(q0, q1, q2, q3)
        H_body = ca.vertcat(p.I_xx * wx, p.I_yy * wy, p.I_zz * wz)
        H = rotation @ H_body
        for k, axis in enumerate("XYZ"):
            e.output(f"H_{axis}", H[k], "N.m.s/rad", f"angular momentum about G, ground {axis} part")
        e.output("H", ca.norm_2(H_body), "N.m.s/rad", "magnitude of the angular momentum")
        e.output("T", (p.I_xx * wx**2 + p.I_yy * wy**2 + p.I_zz * wz**2) / 2, "J",
                 "kinetic energy of rotation")
        for k, axis in enumerate("XYZ"):
            e.output(f"x_{axis}", rotation[k, 0], "1", f"body x axis, ground {axis} part")
        e.output("q_norm_error", q0**2 + q1**2 + q2**2 + q3**2 - 1, "1",
                 "drift of the quaternion's squared norm from 1")


class WobblingDisk(Component):
    """Torque-free uniform disk with (1,3,1) Euler angles: seed 8.4, Eqs. 8.14–8.16.

    The centre is held still; I_cm = diag(2 I_s, I_s, I_s), so the equations hold for any
    I_s and it enters only the outputs. phi turns about the fixed X axis, theta about the
    once-rotated z, psi about the disk's own axis; ``n = (cos th, sin th cos ph,
    sin th sin ph)`` is the disk's axis in ground axes, theta its wobble angle from X and
    phi' the wobble rate. theta = 0 is singular (phi and psi turn about the same axis):
    start with the disk's axis off X. Steady wobble: ``phi' = -2 psi' / cos(theta)``.
    Parameters: ``I_s`` [kg.m2] moment about a diameter; ``theta_min`` [rad]: the run ends
    (terminateSimulation, with a message) once sin(theta) < sin(theta_min), never NaN.
    States: ``phi, theta, psi`` [rad],
    ``phi_dot, theta_dot, psi_dot`` [rad/s]. Outputs: ``n_X, n_Y, n_Z`` [1], ``spin``
    [rad/s] the angular velocity about the disk's axis ``psi' + cos(theta) phi'``,
    ``T`` [J] kinetic energy.
    """

    parameters = (Parameter("I_s", 0.25, "kg.m2", "moment of inertia about a diameter",
                            min=0.0, min_strict=True),
                  Parameter("theta_min", 1e-3, "rad", "the run ends when the wobble angle gets "
                            "this close to 0 or pi, where the angles are singular",
                            min=0.0, min_strict=True, max=0.5))
    states = (
        State("phi", 0.0, "rad", "first (1,3,1) Euler angle, about the ground X axis"),
        State("theta", 0.05, "rad", "second Euler angle: wobble of the disk's axis from X"),
        State("psi", 0.0, "rad", "third Euler angle, about the disk's axis"),
        State("phi_dot", 2.0, "rad/s", "wobble rate"),
        State("theta_dot", 0.0, "rad/s", "rate of theta"),
        State("psi_dot", -0.99875, "rad/s", "rate of psi"),
    )
    profiles = FREE

    def equations(self, e):
        s, d = e.x, e.der
        th, ph_d, th_d, ps_d = s.theta, s.phi_dot, s.theta_dot, s.psi_dot
        e.residual(d.phi - ph_d)
        e.residual(d.theta - th_d)
        e.residual(d.psi - ps_d)
        e.residual((3 + ca.cos(2 * th)) / 2 * d.phi_dot + 2 * ca.cos(th) * d.psi_dot
                   - ca.sin(2 * th) * ph_d * th_d - 2 * ca.sin(th) * th_d * ps_d)  # Eq. 8.14
        e.residual(d.theta_dot + ca.sin(2 * th) / 2 * ph_d**2
                   + 2 * ca.sin(th) * ph_d * ps_d)  # Eq. 8.15
        e.residual(d.psi_dot + ca.cos(th) * d.phi_dot - ca.sin(th) * ph_d * th_d)  # Eq. 8.16
        e.output("n_X", ca.cos(th), "1", "disk axis, ground X part")
        e.output("n_Y", ca.sin(th) * ca.cos(s.phi), "1", "disk axis, ground Y part")
        e.output("n_Z", ca.sin(th) * ca.sin(s.phi), "1", "disk axis, ground Z part")
        spin = ps_d + ca.cos(th) * ph_d
        e.output("spin", spin, "rad/s", "angular velocity about the disk's own axis")
        e.output("T", e.p.I_s / 2 * (2 * spin**2 + th_d**2 + ca.sin(th)**2 * ph_d**2), "J",
                 "kinetic energy")
        # Eqs. 8.14 and 8.16 have determinant sin(theta)^2: stop before it vanishes
        e.terminate_when(ca.sin(th)**2 - ca.sin(e.p.theta_min)**2,
                         "disk axis reached the X axis, where (1,3,1) Euler angles are singular")


class Skate(Component):
    """Skate on a frictionless level plane, knife edge at P, L ahead of G: seed 5.5.

    Lagrange with a multiplier (seed Eqs. 5.17–5.19): ``J theta'' = -lambda L``,
    ``m x'' = lambda sin(theta)``, ``m y'' = -lambda cos(theta)``, with the knife-edge
    constraint ``sin(theta) x' - cos(theta) y' - L theta' = 0`` (Eq. 5.19) held at
    acceleration level, so lambda is an unknown solved with the accelerations. The
    constraint itself is then an invariant: ``constraint`` reports it, and the start
    values must satisfy it (e.g. ``v_y = sin(theta) v_x / cos(theta) - L omega /
    cos(theta)``); a start that violates it keeps its violation.
    Parameters: ``m`` [kg], ``J`` [kg.m2] about G, ``L`` [m] from G to the knife edge.
    States: ``x, y`` [m] G, ``theta`` [rad] heading of the blade, ``v_x, v_y`` [m/s],
    ``omega`` [rad/s]. Outputs: ``lambda`` [N] the knife edge's force along
    n = (sin th, -cos th), ``u`` [m/s] speed of P along the blade, ``E`` [J],
    ``constraint`` [m/s] the left side of Eq. 5.19.
    """

    parameters = (Parameter("m", 1.0, "kg", "mass of the skate", min=0.0, min_strict=True),
                  Parameter("J", 0.1, "kg.m2", "moment of inertia about G, vertical axis",
                            min=0.0, min_strict=True),
                  Parameter("L", 0.5, "m", "distance from G to the knife edge", min=0.0))
    states = (State("x", 0.0, "m", "x of the centre of mass"),
              State("y", 0.0, "m", "y of the centre of mass"),
              State("theta", 0.0, "rad", "heading of the blade from the x axis"),
              State("v_x", 1.0, "m/s", "velocity of G, x part"),
              State("v_y", -0.5, "m/s", "velocity of G, y part (Eq. 5.19 with the other starts)"),
              State("omega", 1.0, "rad/s", "turning rate theta'"))
    profiles = FREE
    default_stop_time = 20.0

    def equations(self, e):
        p, s, d = e.p, e.x, e.der
        st, ct = ca.sin(s.theta), ca.cos(s.theta)
        lam = e.unknown("lambda")
        e.residual(d.x - s.v_x)
        e.residual(d.y - s.v_y)
        e.residual(d.theta - s.omega)
        e.residual(p.J * d.omega + lam * p.L)
        e.residual(p.m * d.v_x - lam * st)
        e.residual(p.m * d.v_y + lam * ct)
        # Eq. 5.19 differentiated once
        e.residual(st * d.v_x - ct * d.v_y - p.L * d.omega + s.omega * (ct * s.v_x + st * s.v_y))
        e.output("lambda", lam, "N", "knife-edge force along (sin theta, -cos theta)")
        e.output("u", ct * s.v_x + st * s.v_y, "m/s", "speed of the knife edge along the blade")
        e.output("E", p.m / 2 * (s.v_x**2 + s.v_y**2) + p.J / 2 * s.omega**2, "J",
                 "kinetic energy")
        e.output("constraint", st * s.v_x - ct * s.v_y - p.L * s.omega, "m/s",
                 "knife-edge constraint, Eq. 5.19 (0 when it holds)")
