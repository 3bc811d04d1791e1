"""Rigid rotational elements (MSL Rotational.Components): Inertia, Fixed, IdealGear, and
the junction of three flanges that MSL writes as one connection set.

An ``Inertia`` computes motion (MSL's *direct* inertia for FMU export: the torques at
both flanges in; phi, w, a out); ``Fixed`` holds a flange at a constant angle and
takes whatever torque it must; ``IdealGear`` passes motion through one way and torque
back the other, so it sits between a component that computes motion and one that
takes it (an inertia on one side, a spring or a sensor on the other). Two inertias
joined rigidly (through a gear, a locked clutch) are one body: their FMUs would form
an algebraic loop through the accelerations, which a separate-FMU master cannot close
exactly, so such inertias are lumped (``J1 ratio^2 + J2`` seen from flange_b).
"""
from __future__ import annotations

from ..component import Component
from ..interfaces import (FORCE_IN, MOTION_IN, ROTATIONAL, Constraint, Parameter, Port, Profile,
                          State)
from ..lazy import lazy
from ..translational.rigid import _through

ca = lazy("casadi")  # loaded by the first equation written, not by an import


class Inertia(Component):
    """Rotating body with inertia J (MSL Rotational.Components.Inertia).

    ``J a = flange_a.tau + flange_b.tau``, ``w = phi'``, ``a = w'``; both flanges move
    with the body. Parameter: ``J`` [kg.m2] (> 0). States: ``phi`` [rad], ``w``
    [rad/s] (MSL's state names and start values 0).
    Connectors: ``flange_a``, ``flange_b`` — torque in; phi, w, a out (an open flange
    keeps its torque input at 0, Modelica's free flange).
    Outputs: ``a`` [rad/s2], ``E`` [J] kinetic energy.
    """

    parameters = (Parameter("J", 1.0, "kg.m2", "moment of inertia", min=0.0, min_strict=True),)
    states = (State("phi", 0.0, "rad", "absolute rotation angle"),
              State("w", 0.0, "rad/s", "absolute angular velocity"))
    ports = (Port("flange_a", ROTATIONAL, "left flange"),
             Port("flange_b", ROTATIONAL, "right flange"))
    profiles = (Profile("direct", "torques in, motion out",
                        {"flange_a": FORCE_IN, "flange_b": FORCE_IN}),)

    def equations(self, e):
        a_, b_ = e.port("flange_a"), e.port("flange_b")
        a = e.der.w
        e.residual(e.der.phi - e.x.w)
        e.residual(e.p.J * a - a_.tau - b_.tau)
        for flange in (a_, b_):
            e.residual(flange.phi - e.x.phi)
            e.residual(flange.w - e.x.w)
            e.residual(flange.a - a)
        e.output("a", a, "rad/s2", "absolute angular acceleration")
        e.output("E", e.p.J * e.x.w**2 / 2, "J", "kinetic energy")


class RotationalFixed(Component):
    """Flange fixed in the housing at angle phi0 (MSL Rotational.Components.Fixed;
    registered as RotationalFixed).

    Parameter: ``phi0`` [rad]. Connector: ``flange`` — torque in (the reaction the
    housing takes, reported), phi = phi0, w = a = 0 out.
    """

    parameters = (Parameter("phi0", 0.0, "rad", "fixed offset angle of the housing"),)
    ports = (Port("flange", ROTATIONAL, "flange fixed in the housing"),)
    profiles = (Profile("kinematic", "angle phi0 out, reaction torque in", {"flange": FORCE_IN}),)

    def equations(self, e):
        flange = e.port("flange")
        e.residual(flange.phi - e.p.phi0)
        e.residual(flange.w)
        e.residual(flange.a)


class IdealGear(Component):
    """Ideal gear without inertia, elasticity or loss (MSL Rotational.Components.IdealGear).

    ``flange_a.phi = ratio flange_b.phi``, ``0 = ratio flange_a.tau + flange_b.tau``
    (power in = power out). Parameter: ``ratio`` [1] (nonzero; MSL's useSupport = false:
    the housing is fixed). Connectors: ``flange_a``, ``flange_b`` — one takes the
    motion in, the other passes it on (scaled) and takes the torque in; the profile
    says which (``motion_at_a`` or ``motion_at_b``), the assembly picks it.
    """

    parameters = (Parameter("ratio", 1.0, "1", "transmission ratio flange_a.phi / flange_b.phi"),)
    ports = (Port("flange_a", ROTATIONAL, "driving shaft"),
             Port("flange_b", ROTATIONAL, "driven shaft"))
    profiles = (Profile("motion_at_a", "motion in at flange_a, passed on at flange_b",
                        {"flange_a": MOTION_IN, "flange_b": FORCE_IN}),
                Profile("motion_at_b", "motion in at flange_b, passed on at flange_a",
                        {"flange_a": FORCE_IN, "flange_b": MOTION_IN}))
    constraints = (Constraint(lambda p: p.ratio**2, "ratio != 0", strict=True),)

    def equations(self, e):
        a, b, ratio = e.port("flange_a"), e.port("flange_b"), e.p.ratio
        for name in ("phi", "w", "a"):
            e.residual(getattr(a, name) - ratio * getattr(b, name))
        e.residual(ratio * a.tau + b.tau)


class RotationalJunction(Component):
    """Three rotational flanges rigidly joined at one point (a Modelica connection set of three).

    Every flange has the same phi, w, a; ``flange_a.tau + flange_b.tau + flange_c.tau = 0``.
    A connection here joins two ports (an FMU's torque input takes one source), so where
    MSL connects three flanges (an inertia to a spring and to a damper on the housing)
    this joins them. Connectors: ``flange_a``, ``flange_b``, ``flange_c`` — one takes the
    motion in and gives the sum of the others' torques out, the other two pass the motion
    on and take their torques in (profiles ``motion_at_a``, ``_b``, ``_c``; the assembly
    picks one).
    """

    ports = tuple(Port(f"flange_{k}", ROTATIONAL, f"flange {k} of the joint") for k in "abc")
    profiles = _through(("flange_a", "flange_b", "flange_c"))

    def equations(self, e):
        a, b, c = (e.port(f"flange_{k}") for k in "abc")
        for other in (b, c):
            for name in ("phi", "w", "a"):
                e.residual(getattr(other, name) - getattr(a, name))
        e.residual(a.tau + b.tau + c.tau)


Fixed = RotationalFixed  # MSL's name inside the rotational package
