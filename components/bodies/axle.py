"""An arbitrary rigid body turning on a fixed axle under gravity: Chatterjee 8.5, not linearised."""
from __future__ import annotations

import math

from ..component import Component
from ..friction import coulomb_modes
from ..interfaces import (FORCE_IN, MOTION_IN, ROTATIONAL, ComponentError, Constraint, Mode,
                         Option, Parameter, Port, Profile, State)
from ..lazy import lazy

ca = lazy("casadi")  # loaded by the first equation written, not by an import
np = lazy("numpy")  # loaded by the first array: listing the components needs none

_INERTIA = ("I_xx", "I_yy", "I_zz", "I_xy", "I_xz", "I_yz")
# relative slack for the semidefinite (equality-allowed) checks: a flat disk sits exactly on
# the triangle inequality, and its rounded inertia must not be rejected for 1e-17
_RELATIVE_SLACK = 1e-12
_UNIT_TOLERANCE = 1e-9


def _inertia_matrix(p):
    """I_cm in the reference configuration, from the six scalar parameters (any numeric type)."""
    return [[p.I_xx, p.I_xy, p.I_xz], [p.I_xy, p.I_yy, p.I_yz], [p.I_xz, p.I_yz, p.I_zz]]


def _minor(A, rows):
    if len(rows) == 1:
        return A[rows[0]][rows[0]]
    if len(rows) == 2:
        i, j = rows
        return A[i][i] * A[j][j] - A[i][j] * A[j][i]
    return (A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1])
            - A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0])
            + A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]))


def _second_moment(p):
    """tr(I)/2 * 1 - I = integral of rho r r^T: semidefinite exactly when the triangle
    inequalities I_i + I_j >= I_k hold for the principal moments (its eigenvalues are
    (I_i + I_j - I_k) / 2), so the inequalities become polynomial checks the FMU can run."""
    A = _inertia_matrix(p)
    half_trace = (p.I_xx + p.I_yy + p.I_zz) / 2
    return [[(half_trace if i == j else 0) - A[i][j] for j in range(3)] for i in range(3)]


def _inertia_constraints():
    out = [Constraint(lambda p, k=k: _minor(_inertia_matrix(p), list(range(k))),
                      f"I_cm positive definite (leading principal minor {k} > 0)", strict=True)
           for k in (1, 2, 3)]
    for rows in ((0,), (1,), (2,), (0, 1), (0, 2), (1, 2), (0, 1, 2)):
        def g(p, rows=rows):
            scale = (p.I_xx + p.I_yy + p.I_zz) ** len(rows)
            return _minor(_second_moment(p), list(rows)) + _RELATIVE_SLACK * scale
        out.append(Constraint(g, "triangle inequalities of the principal moments of I_cm "
                                 f"(principal minor {rows} of tr(I_cm)/2 - I_cm >= 0)"))
    return tuple(out)


class RigidBodyOnAxle(Component):
    """Rigid body on a massless axle through a fixed point P along n, under gravity -g k.

    Seed 8.5 without its linearisation. With P at the origin, ``R(n, theta)`` from
    Rodrigues' formula, ``r = R r_GP`` and ``omega = theta' n``, angular momentum about
    the fixed point P along the fixed n gives exactly
    ``J_n theta'' = -m g k.(n x r) + tau_axle + tau_bearing``, with
    ``J_n = n.I_cm n + m |n x r_GP|^2`` constant (R leaves n fixed) and
    ``n.(omega x I omega) = 0``. The gravity term is ``-dV/dtheta`` of
    ``V = m g k.r = A cos(theta) + B sin(theta) + C``: every body on a non-vertical axle is
    a simple pendulum about the equilibrium where V is least, which need not be theta = 0.

    Reference configuration: theta = 0 is the pose in which ``r_GP`` and ``I_cm`` are given,
    whether or not it is an equilibrium; ``equilibrium_angle()`` finds the stable one.
    Parameters: ``m`` [kg]; ``I_xx .. I_yz`` [kg.m2], I_cm at G in the reference pose
    (checked: positive definite, principal moments obey the triangle inequalities —
    ``tr(I)/2 - I`` is the body's second moment of mass, so it must be semidefinite);
    ``r_x, r_y, r_z`` [m] r_GP from P to G; ``n_x, n_y, n_z`` [1], |n| = 1 within 1e-9
    (then normalised to round-off), not vertical; ``g`` [m/s2]; ``c`` [N.m.s/rad] viscous
    and ``tau_c`` [N.m] Coulomb bearing friction.
    Option ``bearing_friction``: ``none`` (tau_c unused) or ``coulomb``: exact, with a mode
    (-1, 0 stuck, +1) switched by events as in SpringBlock; static = kinetic = tau_c.
    States: ``theta`` [rad] (start alias ``theta0``), ``omega`` [rad/s].
    Connector ``axle`` (rotational; tau positive along n). ``driven_by_torque``: tau in,
    motion out. ``driven_by_motion``: phi, w, a in, tau out — the body follows the flange,
    every output is computed from the flange's motion and the states merely integrate it
    (with Coulomb friction the mode reports the sign of w, and while w = 0 friction holds
    as much of the gravity torque as tau_c allows, the drive the rest).
    Outputs: G_x..z [m] (G relative to P), R_x..z [N] net bearing force on the body,
    M_x..z [N.m] net bearing moment about P perpendicular to n, tau_bearing [N.m]
    friction torque along n, E [J] = J_n omega^2 / 2 + m g z_G.
    """

    options = (Option("bearing_friction", "none", ("none", "coulomb"),
                      "bearing friction besides viscous c: none, or exact Coulomb tau_c with modes"),)
    parameters = (
        Parameter("m", 1.0, "kg", "mass of the body", min=0.0, min_strict=True),
        *(Parameter(name, default, "kg.m2", f"{name} of the inertia tensor at G, reference pose")
          for name, default in zip(_INERTIA, (0.25, 0.25, 0.5, 0.0, 0.0, 0.0))),
        Parameter("r_x", 0.0, "m", "x of r_GP, from axle point P to centre of mass G, reference pose"),
        Parameter("r_y", 1.0, "m", "y of r_GP, from axle point P to centre of mass G, reference pose"),
        Parameter("r_z", 0.0, "m", "z of r_GP, from axle point P to centre of mass G, reference pose"),
        Parameter("n_x", 0.0, "1", "x of the unit vector along the axle"),
        Parameter("n_y", math.sqrt(0.5), "1", "y of the unit vector along the axle"),
        Parameter("n_z", math.sqrt(0.5), "1", "z of the unit vector along the axle"),
        Parameter("g", 9.81, "m/s2", "gravity, along -z", min=0.0),
        Parameter("c", 0.0, "N.m.s/rad", "viscous bearing damping", min=0.0),
        Parameter("tau_c", 0.0, "N.m", "Coulomb bearing friction torque (bearing_friction = coulomb)",
                  min=0.0),
    )
    constraints = (
        *_inertia_constraints(),
        Constraint(lambda p: _UNIT_TOLERANCE - abs(p.n_x**2 + p.n_y**2 + p.n_z**2 - 1),
                   "|n| = 1 within 1e-9"),
        Constraint(lambda p: p.n_x**2 + p.n_y**2 - _UNIT_TOLERANCE**2,
                   "axle not vertical (n_x^2 + n_y^2 > 1e-18)", strict=True),
    )
    states = (State("theta", 0.0, "rad", "rotation about n from the reference pose",
                    start_name="theta0"),
              State("omega", 0.0, "rad/s", "angular velocity about n"))
    ports = (Port("axle", ROTATIONAL, "the axle, turning with the body"),)
    profiles = (
        Profile("driven_by_torque", "drive torque in, motion of the body out", {"axle": FORCE_IN}),
        Profile("driven_by_motion", "rotation prescribed, drive torque out", {"axle": MOTION_IN}),
    )
    default_stop_time = 10.0

    @property
    def modes(self):
        if self.option("bearing_friction") == "coulomb":
            return (Mode("mode", 0, "bearing: -1 turning backward, 0 stuck, +1 turning forward"),)
        return ()

    # --- geometry, shared by the equations and the Python-side analysis ----------
    def _geometry(self, p, theta):
        """(n, r(theta), I_P(reference), J_n) as CasADi expressions."""
        n = ca.vertcat(p.n_x, p.n_y, p.n_z)
        n = n / ca.norm_2(n)
        r_ref = ca.vertcat(p.r_x, p.r_y, p.r_z)
        r = (ca.cos(theta) * r_ref + ca.sin(theta) * ca.cross(n, r_ref)
             + (1 - ca.cos(theta)) * ca.dot(n, r_ref) * n)  # Rodrigues
        I_cm = ca.SX(3, 3)
        for i, row in enumerate(_inertia_matrix(p)):
            for j, value in enumerate(row):
                I_cm[i, j] = value
        I_P = I_cm + p.m * (ca.dot(r_ref, r_ref) * ca.SX.eye(3) - ca.mtimes(r_ref, r_ref.T))
        J_n = ca.dot(n, ca.mtimes(I_P, n))
        return n, r, r_ref, I_P, J_n

    def _rotate(self, n, theta, v):
        return (ca.cos(theta) * v + ca.sin(theta) * ca.cross(n, v)
                + (1 - ca.cos(theta)) * ca.dot(n, v) * n)

    def equations(self, e):
        p, theta, omega, alpha = e.p, e.x.theta, e.x.omega, e.der.omega
        axle = e.port("axle")
        driven = self.profile.name == "driven_by_torque"
        # the motion every output is computed from: the states, or the prescribed flange
        th, w, a = (theta, omega, alpha) if driven else (axle.phi, axle.w, axle.a)
        n, r, _, I_P_ref, J_n = self._geometry(p, th)
        k = ca.vertcat(0, 0, 1)
        tau_gravity = -p.m * p.g * ca.dot(k, ca.cross(n, r))
        tau_f = e.unknown("tau_f")  # Coulomb part of the bearing torque
        e.residual(e.der.theta - (omega if driven else axle.w))
        e.residual(J_n * a - tau_gravity - axle.tau + p.c * w - tau_f)
        if driven:
            e.residual(axle.phi - theta)
            e.residual(axle.w - omega)
            e.residual(axle.a - alpha)
        else:
            e.residual(alpha - axle.a)
        self._bearing_friction(e, tau_gravity + axle.tau - p.c * w, tau_gravity, tau_f, w, a,
                               driven)
        # Newton and Euler about the fixed point P give the reactions the bearings supply
        a_G = a * ca.cross(n, r) + w**2 * ca.cross(n, ca.cross(n, r))
        reaction = p.m * a_G + p.m * p.g * k
        I_P_n = self._rotate(n, th, ca.mtimes(I_P_ref, n))  # R I_P,ref R^T n, as R^T n = n
        dH_dt = a * I_P_n + w**2 * ca.cross(n, I_P_n)
        moment = dH_dt + p.m * p.g * ca.cross(r, k)
        moment = moment - ca.dot(n, moment) * n
        for i, axis in enumerate("xyz"):
            e.output(f"G_{axis}", r[i], "m", f"{axis} of centre of mass G relative to P")
        for i, axis in enumerate("xyz"):
            e.output(f"R_{axis}", reaction[i], "N", f"{axis} of the net bearing force on the body")
        for i, axis in enumerate("xyz"):
            e.output(f"M_{axis}", moment[i], "N.m",
                     f"{axis} of the net bearing moment about P, perpendicular to n")
        e.output("tau_bearing", tau_f - p.c * w, "N.m", "bearing friction torque along n")
        e.output("E", J_n * w**2 / 2 + p.m * p.g * r[2], "J",
                 "kinetic plus potential energy (potential zero with G at the height of P)")

    def _bearing_friction(self, e, tau_applied, tau_gravity, tau_f, w, a, driven):
        """Residual for the Coulomb torque tau_f, with the mode machine of SpringBlock."""
        p = e.p
        if e.option("bearing_friction") == "none":
            e.residual(tau_f)
            return
        if not driven:  # the motion is given: friction opposes it, holds what it can at rest
            held = ca.fmin(ca.fmax(-tau_gravity, -p.tau_c), p.tau_c)
            e.residual(tau_f - ca.if_else(w == 0, held, -p.tau_c * ca.sign(w)))
            e.indicator(w, "prescribed angular velocity (reported as mode)")
            e.jump("mode", ca.sign(w))
            return
        coulomb_modes(e, speed="omega", acceleration=a, friction=tau_f, applied=tau_applied,
                      static_limit=p.tau_c, kinetic_limit=p.tau_c)

    # --- construction checks and analysis -----------------------------------------
    def validate(self) -> None:
        v = self.values
        I_cm = np.array(_inertia_matrix(type("P", (), v)))
        moments = np.linalg.eigvalsh(I_cm)
        if not moments[0] > 0:
            raise ComponentError(f"{self._where()}: I_cm must be positive definite; its principal "
                                 f"moments are {', '.join(f'{x:g}' for x in moments)} kg.m2")
        if moments[0] + moments[1] < moments[2] * (1 - _RELATIVE_SLACK):
            raise ComponentError(
                f"{self._where()}: principal moments {', '.join(f'{x:g}' for x in moments)} kg.m2 "
                "violate the triangle inequality (no mass distribution has them): the largest "
                "must not exceed the sum of the other two")
        n = np.array([v["n_x"], v["n_y"], v["n_z"]])
        if abs(n @ n - 1) > _UNIT_TOLERANCE:
            raise ComponentError(f"{self._where()}: axle direction n = ({n[0]:g}, {n[1]:g}, "
                                 f"{n[2]:g}) must be a unit vector (|n| = 1 within 1e-9)")
        if math.hypot(n[0], n[1]) <= _UNIT_TOLERANCE:
            raise ComponentError(f"{self._where()}: axle direction n = ({n[0]:g}, {n[1]:g}, "
                                 f"{n[2]:g}) is vertical (parallel to gravity): no restoring "
                                 "torque; n_x^2 + n_y^2 must be > 1e-18")
        super().validate()

    def _functions(self):
        p = type("P", (), {q.name: ca.SX.sym(q.name) for q in self.parameters})
        theta = ca.SX.sym("theta")
        n, r, _, _, J_n = self._geometry(p, theta)
        V = p.m * p.g * r[2]
        syms = [getattr(p, q.name) for q in self.parameters]
        f = ca.Function("axle_analysis", [theta, ca.vertcat(*syms)],
                        [V, ca.gradient(V, theta), ca.hessian(V, theta)[0], J_n])
        values = [self.values[q.name] for q in self.parameters]
        return lambda th: [float(x) for x in f(th, values)]

    def equilibrium_angle(self) -> float:
        """The stable equilibrium in (-pi, pi], where V = A cos + B sin + C is least.

        V is sinusoidal in theta (see the class docstring), so its minimum is found exactly:
        A = V(0) - C and B = V'(0). With G on the axle (A = B = 0) every angle is an
        equilibrium and 0 is returned.
        """
        evaluate = self._functions()
        _, B, V_pp_0, _ = evaluate(0.0)
        A = -V_pp_0  # V'' = -A cos - B sin
        if A == 0 and B == 0:
            return 0.0
        return math.atan2(-B, -A)

    def small_oscillation_frequency(self) -> float:
        """sqrt(V''(theta_eq) / J_n) [rad/s] about the stable equilibrium (0 if neutral)."""
        V, dV, d2V, J_n = self._functions()(self.equilibrium_angle())
        return math.sqrt(max(d2V, 0.0) / J_n)
