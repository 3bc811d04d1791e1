"""MSL-style translational elements: the housing, springs, dampers, a gap and a mass with Coulomb friction.

``Spring`` and ``SpringDamper`` are MSL's ``PartialCompliant`` pair: both flanges take
the motion in and give the force out (``motion`` causality), so they sit between two
components that compute motion. ``MassWithFriction`` is the counterpart that computes
motion: both its flanges take the force in and give s, v, a out (MSL's *direct*
mass), and it rides on a ``support`` (ground or a moving belt) with exact Coulomb
stick/slip modes, the mode machine of :class:`components.translational.spring_block.SpringBlock`.
"""
from __future__ import annotations

from types import SimpleNamespace

from ..component import Component
from ..friction import coulomb_modes
from ..interfaces import (FIXED, FORCE_IN, MOTION_IN, TRANSLATIONAL, Constraint, Mode, Parameter,
                         Port, Profile, State)
from ..lazy import lazy

ca = lazy("casadi")  # loaded by the first equation written, not by an import

_COMPLIANT_PORTS = (Port("flange_a", TRANSLATIONAL, "left end"),
                    Port("flange_b", TRANSLATIONAL, "right end"))
_COMPLIANT_PROFILES = (Profile("between_masses", "motion of both ends in, forces out",
                               {"flange_a": MOTION_IN, "flange_b": MOTION_IN}),)


def _compliant(e, force, p):
    """MSL PartialCompliant: f acts +s on flange_b's side, -s on flange_a's."""
    a, b = e.port("flange_a"), e.port("flange_b")
    s_rel = b.s - a.s
    f = force(s_rel - p.s_rel0, b.v - a.v)
    # a flow is the force ON this component: a stretched spring is pulled +s at b, -s at a
    e.residual(b.f - f)
    e.residual(a.f + f)
    e.output("f", f, "N", "force, positive in tension")
    e.output("s_rel", s_rel, "m", "flange_b.s - flange_a.s")
    return s_rel


class Spring(Component):
    """Linear massless spring between two flanges (MSL Translational.Components.Spring).

    ``f = c (s_rel - s_rel0)`` with ``s_rel = flange_b.s - flange_a.s``.
    Parameters: ``c`` [N/m] stiffness, ``s_rel0`` [m] unstretched length.
    Connectors: ``flange_a``, ``flange_b`` — motion in, force out (connect each to a
    component that computes motion: a mass, a kinematic source, a beam tip).
    Outputs: ``f`` [N] tension, ``s_rel`` [m], ``E`` [J] elastic energy.
    """

    parameters = (Parameter("c", 1.0, "N/m", "stiffness", min=0.0),
                  Parameter("s_rel0", 0.0, "m", "unstretched length"))
    ports, profiles = _COMPLIANT_PORTS, _COMPLIANT_PROFILES

    def equations(self, e):
        p = e.p
        s_rel = _compliant(e, lambda stretch, _: p.c * stretch, p)
        e.output("E", p.c * (s_rel - p.s_rel0)**2 / 2, "J", "elastic energy")


class SpringDamper(Component):
    """Spring and dashpot in parallel (MSL Translational.Components.SpringDamper).

    ``f = c (s_rel - s_rel0) + d (v_b - v_a)``.
    Parameters: ``c`` [N/m], ``d`` [N.s/m], ``s_rel0`` [m].
    Connectors: ``flange_a``, ``flange_b`` — motion in, force out.
    Outputs: ``f`` [N], ``s_rel`` [m], ``E`` [J] elastic energy, ``P_loss`` [W] power
    dissipated by the dashpot.
    """

    parameters = (Parameter("c", 1.0, "N/m", "stiffness", min=0.0),
                  Parameter("d", 0.1, "N.s/m", "damping coefficient", min=0.0),
                  Parameter("s_rel0", 0.0, "m", "unstretched length"))
    ports, profiles = _COMPLIANT_PORTS, _COMPLIANT_PROFILES

    def equations(self, e):
        p = e.p
        a, b = e.port("flange_a"), e.port("flange_b")
        s_rel = _compliant(e, lambda stretch, v_rel: p.c * stretch + p.d * v_rel, p)
        e.output("E", p.c * (s_rel - p.s_rel0)**2 / 2, "J", "elastic energy")
        e.output("P_loss", p.d * (b.v - a.v)**2, "W", "power dissipated by the dashpot")


class Fixed(Component):
    """Flange fixed in the housing at a given position (MSL Translational.Components.Fixed).

    Parameter: ``s0`` [m] position of the flange. Connector: ``flange`` — outputs
    s = s0, v = 0, a = 0 and takes in the force the housing holds (``flange.f``).
    Where MSL connects one Fixed to several flanges, use one Fixed per flange (a
    connection joins two ports): they are the same housing.
    """

    parameters = (Parameter("s0", 0.0, "m", "fixed offset position of the housing"),)
    ports = (Port("flange", TRANSLATIONAL, "flange fixed in the housing"),)
    profiles = (Profile("housing", "position out, reaction force in", {"flange": FORCE_IN}),)

    def equations(self, e):
        flange = e.port("flange")
        e.residual(flange.s - e.p.s0)
        e.residual(flange.v)
        e.residual(flange.a)


class Damper(Component):
    """Linear massless damper (MSL Translational.Components.Damper).

    ``f = d (v_b - v_a)``.
    Parameter: ``d`` [N.s/m]. Connectors: ``flange_a``, ``flange_b`` — motion in, force out.
    Outputs: ``f`` [N], ``s_rel`` [m], ``lossPower`` [W] power dissipated.
    """

    parameters = (Parameter("d", 0.0, "N.s/m", "damping constant", min=0.0),)
    ports, profiles = _COMPLIANT_PORTS, _COMPLIANT_PROFILES

    def equations(self, e):
        p = e.p
        a, b = e.port("flange_a"), e.port("flange_b")
        _compliant(e, lambda _, v_rel: p.d * v_rel, SimpleNamespace(s_rel0=0.0))
        e.output("lossPower", p.d * (b.v - a.v)**2, "W", "power dissipated by the damper")


class ElastoGap(Component):
    """Spring and damper that act only in contact, pushing, never pulling (MSL Translational.Components.ElastoGap).

    In contact (``s_rel < s_rel0``): ``f_c = -c |s_rel - s_rel0|^n``, ``f_d`` = ``d v_rel``
    bounded to ``|f_d| <= |f_c|`` (so the force is continuous at first touch and never
    pulls), ``f = f_c + f_d``; out of contact ``f = 0``. Events mark contact and the
    bound switching in and out, so the solver never steps across a kink.
    Parameters: ``c`` [N/m], ``d`` [N.s/m], ``s_rel0`` [m] gap, ``n`` [1] exponent (>= 1).
    Connectors: ``flange_a``, ``flange_b`` — motion in, force out.
    Outputs: ``f`` [N] (negative: pushing the flanges apart), ``s_rel`` [m],
    ``contact`` [1], ``E`` [J] elastic energy, ``lossPower`` [W].
    """

    parameters = (Parameter("c", 1.0, "N/m", "spring constant", min=0.0),
                  Parameter("d", 1.0, "N.s/m", "damping constant", min=0.0),
                  Parameter("s_rel0", 0.0, "m", "unstretched spring length"),
                  Parameter("n", 1.0, "1", "exponent of the spring force", min=1.0))
    ports, profiles = _COMPLIANT_PORTS, _COMPLIANT_PROFILES

    def equations(self, e):
        p = e.p
        a, b = e.port("flange_a"), e.port("flange_b")
        depth = ca.fmax(p.s_rel0 - (b.s - a.s), 0)  # penetration, 0 out of contact
        contact = depth > 0
        f_c = -p.c * depth**p.n
        f_d2 = p.d * (b.v - a.v)
        f_d = ca.if_else(contact, ca.fmin(ca.fmax(f_d2, f_c), -f_c), 0)
        _compliant(e, lambda *_: f_c + f_d, p)
        e.indicator(p.s_rel0 - (b.s - a.s), "penetration: contact while positive")
        e.indicator(ca.if_else(contact, f_d2 - f_c, 1), "in contact: damper above its bound -|f_c|")
        e.indicator(ca.if_else(contact, -f_c - f_d2, 1), "in contact: damper below its bound |f_c|")
        e.output("contact", ca.if_else(contact, 1, 0), "1", "1 in contact, 0 apart")
        e.output("E", p.c * depth**(p.n + 1) / (p.n + 1), "J", "elastic energy")
        e.output("lossPower", f_d * (b.v - a.v), "W", "power dissipated by the damper")


def on_support(e, m, position: str):
    """A rigid mass `m` whose flanges ride on its ``support``, at the state `position`
    and the speed ``v`` relative to it: the residuals, and (friction from the support,
    an unknown; every other force on the mass in the support's frame) for the friction
    law to close."""
    x, v, a = getattr(e.x, position), e.x.v, e.der.v
    fa, fb, support = e.port("flange_a"), e.port("flange_b"), e.port("support")
    friction = e.unknown("f")
    e.residual(getattr(e.der, position) - v)
    e.residual(m * (support.a + a) - fa.f - fb.f - friction)
    for flange in (fa, fb):
        e.residual(flange.s - (support.s + x))
        e.residual(flange.v - (support.v + v))
        e.residual(flange.a - (support.a + a))
    e.residual(support.f - friction)
    return friction, fa.f + fb.f - m * support.a


class MassWithFriction(Component):
    """Sliding mass with exact Coulomb friction against a support (cf. MSL MassWithStopAndFriction).

    ``m (support.a + x'') = flange_a.f + flange_b.f + f`` with normal load ``m g`` and
    ``f`` the friction from the support: stuck (mode 0) the block moves with the
    support and ``|f| <= mu_s m g``; sliding (mode ±1) ``f = -mu_k m g mode``. Events
    switch the modes exactly as in SpringBlock (incipient sliding at the static limit,
    re-stick when the relative velocity reaches zero).
    Parameters: ``m`` [kg], ``g`` [m/s2], ``mu_k``, ``mu_s`` [1].
    States: ``x`` [m], ``v`` [m/s] relative to the support (so "stuck" is exactly v = 0
    however the support moves).
    Mode: ``mode`` -1 sliding backward, 0 stuck, +1 sliding forward (relative to support).
    Connectors: ``flange_a``, ``flange_b`` — the block (force in; s, v, a out);
    ``support`` — the surface: ``fixed`` (ground) or motion in, friction reaction out.
    Outputs: ``s`` [m] absolute position, ``v_abs`` [m/s], ``f_friction`` [N],
    ``P_friction`` [W] power dissipated by friction (``-f v``, >= 0).
    """

    parameters = (
        Parameter("m", 1.0, "kg", "mass of the block", min=0.0, min_strict=True),
        Parameter("g", 9.81, "m/s2", "gravity, pressing the block on the support", min=0.0),
        Parameter("mu_k", 0.3, "1", "kinetic friction coefficient", min=0.0),
        Parameter("mu_s", 0.4, "1", "static friction coefficient", min=0.0),
    )
    constraints = (Constraint(lambda p: p.mu_s - p.mu_k, "mu_k <= mu_s"),)
    states = (State("x", 0.0, "m", "position of the block relative to the support"),
              State("v", 0.0, "m/s", "velocity of the block relative to the support"))
    modes = (Mode("mode", 0, "friction mode: -1 sliding backward, 0 stuck, +1 sliding forward"),)
    ports = (Port("flange_a", TRANSLATIONAL, "left side of the block"),
             Port("flange_b", TRANSLATIONAL, "right side of the block"),
             Port("support", TRANSLATIONAL, "surface the block slides on"))
    profiles = (
        Profile("on_ground", "forces in, motion out; fixed surface",
                {"flange_a": FORCE_IN, "flange_b": FORCE_IN, "support": FIXED}),
        Profile("on_moving_support", "forces in, motion out; surface moved by an input",
                {"flange_a": FORCE_IN, "flange_b": FORCE_IN, "support": MOTION_IN}),
    )

    def equations(self, e):
        p, x, v = e.p, e.x.x, e.x.v
        support = e.port("support")
        f, f_applied = on_support(e, p.m, "x")
        normal = p.m * p.g
        coulomb_modes(e, speed="v", acceleration=e.der.v, friction=f, applied=f_applied,
                      static_limit=p.mu_s * normal, kinetic_limit=p.mu_k * normal)
        e.output("s", support.s + x, "m", "absolute position of the block")
        e.output("v_abs", support.v + v, "m/s", "absolute velocity of the block")
        e.output("f_friction", f, "N", "friction force on the block")
        e.output("P_friction", -f * v, "W", "power dissipated by friction")
