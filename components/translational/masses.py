"""MSL's sliding masses (Translational.Components.Mass, MassWithStopAndFriction).

Both compute motion from the forces on their flanges (MSL's *direct* mass, the
profile ``GenerationOfFMUs`` exports): ``flange_a`` and ``flange_b`` take the force in
and give s, v, a out, each at its end of the body, L/2 either side of the centre s.
"""
from __future__ import annotations

from ..component import Component
from ..friction import coulomb_modes, hard_stops
from ..interfaces import (FORCE_IN, TRANSLATIONAL, Constraint, Mode, Parameter, Port, Profile,
                          State)
from ..lazy import lazy

ca = lazy("casadi")  # loaded by the first equation written, not by an import

_FLANGES = (Port("flange_a", TRANSLATIONAL, "left end of the mass (s - L/2)"),
            Port("flange_b", TRANSLATIONAL, "right end of the mass (s + L/2)"))
_DIRECT = (Profile("direct", "forces in, motion out (MSL's direct mass)",
                   {"flange_a": FORCE_IN, "flange_b": FORCE_IN}),)
_L = Parameter("L", 0.0, "m", "length of the component, from flange_a to flange_b", min=0.0)
_STATES = (State("s", 0.0, "m", "absolute position of the centre of the mass"),
           State("v", 0.0, "m/s", "absolute velocity of the mass"))
#: MassWithStopAndFriction's f0_max = 1.001 f0: sticking holds up to 0.1 % above the
#: friction at the start of sliding, so that a break-away is always a strict excess
PEAK = 1.001


def _rigid(e, a):
    """Both flanges move with the body: MSL's PartialRigid."""
    p, s, v = e.p, e.x.s, e.x.v
    e.residual(e.der.s - v)
    for name, offset in (("flange_a", -p.L / 2), ("flange_b", p.L / 2)):
        flange = e.port(name)
        e.residual(flange.s - (s + offset))
        e.residual(flange.v - v)
        e.residual(flange.a - a)


class Mass(Component):
    """Sliding mass with inertia (MSL Translational.Components.Mass).

    ``m der(v) = flange_a.f + flange_b.f``.
    Parameters: ``m`` [kg], ``L`` [m] length (flange_a at s - L/2, flange_b at s + L/2).
    States: ``s`` [m] centre, ``v`` [m/s]. Connectors: ``flange_a``, ``flange_b`` —
    force in; s, v, a out. Outputs: ``a`` [m/s2], ``E`` [J] kinetic energy.
    """

    parameters = (Parameter("m", 1.0, "kg", "mass of the sliding mass", min=0.0,
                            min_strict=True), _L)
    states, ports, profiles = _STATES, _FLANGES, _DIRECT

    def equations(self, e):
        a, fa, fb = e.der.v, e.port("flange_a"), e.port("flange_b")
        _rigid(e, a)
        e.residual(e.p.m * a - fa.f - fb.f)
        e.output("a", a, "m/s2", "absolute acceleration of the mass")
        e.output("E", e.p.m * e.x.v**2 / 2, "J", "kinetic energy")


class MassWithStopAndFriction(Component):
    """Sliding mass with hard stops and Stribeck friction (MSL Translational.Components.MassWithStopAndFriction).

    ``m der(v) = flange_a.f + flange_b.f - f`` on a fixed surface. Sliding (mode ±1):
    ``f = F_prop v + sign(v) (F_Coulomb + F_Stribeck exp(-fexp |v|))``; stuck (mode 0,
    v = 0 exactly) ``f`` is whatever holds the mass, up to 1.001 (F_Coulomb + F_Stribeck)
    (MSL's f0_max); a stop at ``smin + L/2`` and ``smax - L/2`` for ``s`` sets v = 0
    and sticks (MSL's reinit). Events switch the modes (components.friction).
    Parameters: ``m`` [kg], ``L`` [m], ``smax``, ``smin`` [m], ``F_prop`` [N.s/m],
    ``F_Coulomb``, ``F_Stribeck`` [N], ``fexp`` [s/m].
    States: ``s`` [m] centre, ``v`` [m/s]. Mode: ``mode`` -1 backward, 0 stuck, +1 forward.
    Connectors: ``flange_a``, ``flange_b`` — force in; s, v, a out.
    Outputs: ``a`` [m/s2], ``f`` [N] friction (positive against +v), ``lossPower`` [W].
    """

    parameters = (Parameter("m", 1.0, "kg", "mass", min=0.0, min_strict=True), _L,
                  Parameter("smax", 25.0, "m", "right stop for the right end of the mass"),
                  Parameter("smin", -25.0, "m", "left stop for the left end of the mass"),
                  Parameter("F_prop", 1.0, "N.s/m", "velocity dependent friction", min=0.0),
                  Parameter("F_Coulomb", 5.0, "N", "constant friction: Coulomb force", min=0.0),
                  Parameter("F_Stribeck", 10.0, "N", "Stribeck effect", min=0.0),
                  Parameter("fexp", 2.0, "s/m", "exponential decay of the Stribeck effect",
                            min=0.0))
    constraints = (Constraint(lambda p: p.F_Coulomb + p.F_Stribeck, "F_Coulomb + F_Stribeck > 0 "
                              "(a mass without sticking friction is a Mass)", strict=True),
                   Constraint(lambda p: p.smax - p.smin - p.L, "smax - smin >= L"))
    start_constraints = (Constraint(lambda ns: ns.s - ns.L / 2 - ns.smin, "s - L/2 >= smin"),
                         Constraint(lambda ns: ns.smax - ns.s - ns.L / 2, "s + L/2 <= smax"))
    states, ports, profiles = _STATES, _FLANGES, _DIRECT
    modes = (Mode("mode", 0, "friction mode: -1 sliding backward, 0 stuck, +1 sliding forward"),)

    def equations(self, e):
        p, v, a = e.p, e.x.v, e.der.v
        fa, fb = e.port("flange_a"), e.port("flange_b")
        friction = e.unknown("friction")  # on the mass: MSL's -f
        f0 = p.F_Coulomb + p.F_Stribeck
        _rigid(e, a)
        e.residual(p.m * a - fa.f - fb.f - friction)
        speed = ca.fabs(v)  # while sliding: q v
        coulomb_modes(e, speed="v", acceleration=a, friction=friction, applied=fa.f + fb.f,
                      static_limit=PEAK * f0,
                      kinetic_limit=p.F_prop * speed + p.F_Coulomb
                      + p.F_Stribeck * ca.exp(-p.fexp * speed))
        hard_stops(e, position="s", speed="v", low=p.smin + p.L / 2, high=p.smax - p.L / 2)
        e.output("a", a, "m/s2", "absolute acceleration of the mass")
        e.output("f", -friction, "N", "friction force, positive when it opposes +v")
        e.output("lossPower", -friction * v, "W", "power dissipated by friction")
