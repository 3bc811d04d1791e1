"""MSL-style rotational elements for joining scenes: a torsional spring and a DC motor."""
from __future__ import annotations

from ..component import Component
from ..interfaces import FORCE_IN, MOTION_IN, ROTATIONAL, Parameter, Port, Profile, State
from ..lazy import lazy

ca = lazy("casadi")  # loaded by the first equation written, not by an import


class TorsionalSpring(Component):
    """Linear massless torsional spring (MSL Rotational.Components.Spring), optional damper.

    ``tau = c (phi_rel - phi_rel0) + d w_rel`` with ``phi_rel = flange_b.phi - flange_a.phi``.
    Parameters: ``c`` [N.m/rad], ``d`` [N.m.s/rad], ``phi_rel0`` [rad].
    Connectors: ``flange_a``, ``flange_b`` — motion in, torque out (connect each to a
    component that computes motion: a motor rotor, a body on an axle).
    Outputs: ``tau`` [N.m] spring torque (acts +n on flange_b's side), ``phi_rel`` [rad],
    ``E`` [J] elastic energy, ``P_loss`` [W] power dissipated by the damper.
    """

    parameters = (Parameter("c", 1.0, "N.m/rad", "torsional stiffness", min=0.0),
                  Parameter("d", 0.0, "N.m.s/rad", "damping parallel to the spring", min=0.0),
                  Parameter("phi_rel0", 0.0, "rad", "unstrained relative angle"))
    ports = (Port("flange_a", ROTATIONAL, "driving end"),
             Port("flange_b", ROTATIONAL, "driven end"))
    profiles = (Profile("between_inertias", "motion of both ends in, torques out",
                        {"flange_a": MOTION_IN, "flange_b": MOTION_IN}),)

    def equations(self, e):
        p, a, b = e.p, e.port("flange_a"), e.port("flange_b")
        phi_rel = b.phi - a.phi
        tau = p.c * (phi_rel - p.phi_rel0) + p.d * (b.w - a.w)
        # a flow is the torque ON this component: twisted forward at b, it is turned +n there
        e.residual(b.tau - tau)
        e.residual(a.tau + tau)
        e.output("tau", tau, "N.m", "spring torque, positive when twisted phi_b > phi_a")
        e.output("phi_rel", phi_rel, "rad", "flange_b.phi - flange_a.phi")
        e.output("E", p.c * (phi_rel - p.phi_rel0)**2 / 2, "J", "elastic energy")
        e.output("P_loss", p.d * (b.w - a.w)**2, "W", "power dissipated by the damper")


class Motor(Component):
    """DC motor with a linear torque-speed line driving its rotor inertia.

    ``J phi'' = tau_m + flange.tau`` with ``tau_m = tau_stall (1 - w / w_free)``: stall
    torque at rest, none at the free-running speed (a permanent-magnet DC motor at
    constant voltage). ``w_free = 0`` is read as an ideal torque source, ``tau_m = tau_stall``.
    Parameters: ``J`` [kg.m2] rotor inertia, ``tau_stall`` [N.m], ``w_free`` [rad/s].
    States: ``phi`` [rad], ``w`` [rad/s] of the rotor; ``W`` [J] work the motor torque
    has done on the rotor (``W' = tau_m w``), for energy balances.
    Connector: ``flange`` — the shaft: load torque in, motion out (MSL *direct* inertia).
    Outputs: ``tau_m`` [N.m] motor torque, ``E`` [J] rotor kinetic energy.
    """

    parameters = (Parameter("J", 0.01, "kg.m2", "rotor inertia", min=0.0, min_strict=True),
                  Parameter("tau_stall", 1.0, "N.m", "torque at zero speed"),
                  Parameter("w_free", 0.0, "rad/s", "free-running speed (0: ideal torque source)",
                            min=0.0))
    states = (State("phi", 0.0, "rad", "rotor angle"),
              State("w", 0.0, "rad/s", "rotor angular velocity"),
              State("W", 0.0, "J", "work done by the motor torque"))
    ports = (Port("flange", ROTATIONAL, "motor shaft"),)
    profiles = (Profile("driving", "load torque in, shaft motion out", {"flange": FORCE_IN}),)

    def equations(self, e):
        p, w, flange = e.p, e.x.w, e.port("flange")
        slope = ca.if_else(p.w_free > 0, p.tau_stall / ca.fmax(p.w_free, 1e-300), 0)
        tau_m = p.tau_stall - slope * w
        e.residual(e.der.phi - w)
        e.residual(p.J * e.der.w - tau_m - flange.tau)
        e.residual(e.der.W - tau_m * w)
        e.residual(flange.phi - e.x.phi)
        e.residual(flange.w - w)
        e.residual(flange.a - e.der.w)
        e.output("tau_m", tau_m, "N.m", "motor torque on the rotor")
        e.output("E", p.J * w**2 / 2, "J", "rotor kinetic energy")
