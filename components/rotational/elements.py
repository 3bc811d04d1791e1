"""MSL-style compliant rotational elements (Spring, Damper, SpringDamper), the seed's
torsional spring and a DC motor.

The compliant elements are MSL's ``PartialCompliant``: both flanges take the motion in
and give the torque out, so they sit between components that compute motion (an
inertia, a source, a rotor). Where MSL's name exists in Translational too, the class
carries the prefix ``Rotational`` (the FMU's model identifier is the class name and
must be unique); MSL's name is an alias at the bottom of this module.
"""
from __future__ import annotations

from ..component import Component
from ..interfaces import FORCE_IN, MOTION_IN, ROTATIONAL, Parameter, Port, Profile, State
from ..lazy import lazy

ca = lazy("casadi")  # loaded by the first equation written, not by an import


_COMPLIANT_PORTS = (Port("flange_a", ROTATIONAL, "driving end"),
                    Port("flange_b", ROTATIONAL, "driven end"))
_COMPLIANT_PROFILES = (Profile("between_inertias", "motion of both ends in, torques out",
                               {"flange_a": MOTION_IN, "flange_b": MOTION_IN}),)
_C = Parameter("c", 1.0, "N.m/rad", "torsional stiffness", min=0.0)
_PHI_REL0 = Parameter("phi_rel0", 0.0, "rad", "unstrained relative angle")
_D = Parameter("d", 1.0, "N.m.s/rad", "damping constant (MSL gives no default)", min=0.0)
_LOSS = State("W_loss", 0.0, "J", "energy dissipated by the damper since t = 0")


def _compliant(e, c, d):
    """MSL PartialCompliant with ``tau = c (phi_rel - phi_rel0) + d w_rel`` (c or d 0 to
    leave a term out); with a damper, ``W_loss`` integrates its power for energy balances."""
    a, b = e.port("flange_a"), e.port("flange_b")
    phi_rel, w_rel = b.phi - a.phi, b.w - a.w
    twist = phi_rel - e.p.phi_rel0 if c is not None else 0
    tau = (c * twist if c is not None else 0) + (d * w_rel if d is not None else 0)
    # a flow is the torque ON this component: twisted forward at b, it is turned +n there
    e.residual(b.tau - tau)
    e.residual(a.tau + tau)
    e.output("tau", tau, "N.m", "torque in the element, positive when phi_b > phi_a "
             "(or w_b > w_a)")
    e.output("phi_rel", phi_rel, "rad", "flange_b.phi - flange_a.phi")
    e.output("w_rel", w_rel, "rad/s", "flange_b.w - flange_a.w")
    if c is not None:
        e.output("E", c * twist**2 / 2, "J", "elastic energy")
    if d is not None:
        e.output("lossPower", d * w_rel**2, "W", "power dissipated by the damper")
        if "W_loss" in vars(e.x):
            e.residual(e.der.W_loss - d * w_rel**2)


class TorsionalSpring(Component):
    """Linear massless torsional spring (MSL Rotational.Components.Spring), optional damper.

    ``tau = c (phi_rel - phi_rel0) + d w_rel`` with ``phi_rel = flange_b.phi - flange_a.phi``.
    Parameters: ``c`` [N.m/rad], ``d`` [N.m.s/rad], ``phi_rel0`` [rad].
    Connectors: ``flange_a``, ``flange_b`` — motion in, torque out (connect each to a
    component that computes motion: a motor rotor, a body on an axle).
    Outputs: ``tau`` [N.m] spring torque (acts +n on flange_b's side), ``phi_rel`` [rad],
    ``E`` [J] elastic energy, ``P_loss`` [W] power dissipated by the damper.
    """

    parameters = (_C, Parameter("d", 0.0, "N.m.s/rad", "damping parallel to the spring",
                                min=0.0), _PHI_REL0)
    ports, profiles = _COMPLIANT_PORTS, _COMPLIANT_PROFILES

    def equations(self, e):
        p, a, b = e.p, e.port("flange_a"), e.port("flange_b")
        phi_rel = b.phi - a.phi
        tau = p.c * (phi_rel - p.phi_rel0) + p.d * (b.w - a.w)
        e.residual(b.tau - tau)
        e.residual(a.tau + tau)
        e.output("tau", tau, "N.m", "spring torque, positive when twisted phi_b > phi_a")
        e.output("phi_rel", phi_rel, "rad", "flange_b.phi - flange_a.phi")
        e.output("E", p.c * (phi_rel - p.phi_rel0)**2 / 2, "J", "elastic energy")
        e.output("P_loss", p.d * (b.w - a.w)**2, "W", "power dissipated by the damper")


class RotationalSpring(Component):
    """Linear torsional spring (MSL Rotational.Components.Spring; registered as RotationalSpring).

    ``tau = c (phi_rel - phi_rel0)``, ``phi_rel = flange_b.phi - flange_a.phi``.
    Parameters: ``c`` [N.m/rad] (MSL gives no default; 1 here), ``phi_rel0`` [rad].
    Connectors: ``flange_a``, ``flange_b`` — motion in, torque out.
    Outputs: ``tau`` [N.m], ``phi_rel`` [rad], ``w_rel`` [rad/s], ``E`` [J] elastic energy.
    """

    parameters = (_C, _PHI_REL0)
    ports, profiles = _COMPLIANT_PORTS, _COMPLIANT_PROFILES

    def equations(self, e):
        _compliant(e, e.p.c, None)


class RotationalDamper(Component):
    """Linear rotational damper (MSL Rotational.Components.Damper; registered as RotationalDamper).

    ``tau = d w_rel``, ``w_rel = flange_b.w - flange_a.w``.
    Parameter: ``d`` [N.m.s/rad] (MSL gives no default; 1 here). State: ``W_loss`` [J] energy dissipated (its integral
    of lossPower, for energy balances). Connectors: ``flange_a``, ``flange_b`` — motion
    in, torque out. Outputs: ``tau``, ``phi_rel``, ``w_rel``, ``lossPower`` [W].
    """

    parameters = (_D,)
    states = (_LOSS,)
    ports, profiles = _COMPLIANT_PORTS, _COMPLIANT_PROFILES

    def equations(self, e):
        _compliant(e, None, e.p.d)


class RotationalSpringDamper(Component):
    """Spring and damper in parallel (MSL Rotational.Components.SpringDamper; registered as
    RotationalSpringDamper).

    ``tau = c (phi_rel - phi_rel0) + d w_rel``. Parameters: ``c`` [N.m/rad], ``d``
    [N.m.s/rad], ``phi_rel0`` [rad]. State: ``W_loss`` [J] energy dissipated.
    Connectors: ``flange_a``, ``flange_b`` — motion in, torque out.
    Outputs: ``tau``, ``phi_rel``, ``w_rel``, ``E`` [J], ``lossPower`` [W].
    """

    parameters = (_C, _D, _PHI_REL0)
    states = (_LOSS,)
    ports, profiles = _COMPLIANT_PORTS, _COMPLIANT_PROFILES

    def equations(self, e):
        _compliant(e, e.p.c, e.p.d)


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


# MSL's names inside the rotational package
Spring, Damper, SpringDamper = RotationalSpring, RotationalDamper, RotationalSpringDamper
