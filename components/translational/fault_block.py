"""A block of the Burridge-Knopoff fault: Carlson & Langer's velocity-weakening friction."""
from __future__ import annotations

from ..component import Component
from ..friction import coulomb_modes
from ..interfaces import (FORCE_IN, MOTION_IN, TRANSLATIONAL, Constraint, Mode, Parameter, Port,
                          Profile, State)
from ..lazy import lazy

ca = lazy("casadi")  # loaded by the first equation written, not by an import

#: the weakening's denominator is held at or above this: the law's smooth continuation
#: just past a stop (inside a solver step that overshoots it) never divides by ~0
WEAKENING_FLOOR = 0.5


class FaultBlock(Component):
    """Block of a Burridge-Knopoff chain on a fixed rough surface, pulled from the plate.

    ``m x'' = flange_a.f + flange_b.f + kp (plate.s - x) + f`` where the leaf spring
    ``kp`` ties the block to the driving plate and the neighbours' coupling springs act
    through the flanges. Friction ``f`` is Carlson & Langer's (Phys. Rev. A 40, 6470,
    1989, Eq. 2.4 in their units: F0 = 1, velocity in F0/sqrt(kp m)): stuck, ``x' = 0``
    exactly while the applied force stays within the static threshold ``F_s``; sliding
    with ``q = sign(x')``, ``f = -q F_s (1 - sigma) / (1 + 2 alpha q x' / ((1 - sigma)
    v_w))``: a drop by ``sigma F_s`` at the onset of slip, then weakening with speed.
    Modes as SpringBlock's (``components/friction.py``): a slide ends where ``x'``
    reaches 0, stuck if the applied force is within ``F_s`` there.
    Parameters: ``m`` [kg], ``kp`` [N/m] leaf spring, ``F_s`` [N] static threshold,
    ``sigma`` [1] drop at the onset of slip, ``alpha`` [1] weakening, ``v_w`` [m/s]
    the weakening's velocity scale (C&L: ``F0 / sqrt(kp m)``).
    States: ``x`` [m] position, ``v`` [m/s] velocity (the surface is fixed).
    Connectors: ``flange_a``, ``flange_b`` (force in; s, v, a out): the coupling springs;
    ``plate`` (motion in, force out): the leaf spring's far end.
    Outputs: ``f_friction`` [N], ``f_leaf`` [N], ``P_friction`` [W] power dissipated.
    """

    parameters = (
        Parameter("m", 1.0, "kg", "mass of the block", min=0.0, min_strict=True),
        Parameter("kp", 1.0, "N/m", "stiffness of the leaf spring to the plate", min=0.0),
        Parameter("F_s", 1.0, "N", "static friction threshold", min=0.0, min_strict=True),
        Parameter("sigma", 0.01, "1", "drop from static to kinetic friction at the onset of "
                  "slip, as a fraction of F_s", min=0.0),
        Parameter("alpha", 2.5, "1", "velocity weakening of the kinetic friction", min=0.0),
        Parameter("v_w", 1.0, "m/s", "velocity scale of the weakening", min=0.0,
                  min_strict=True),
    )
    constraints = (Constraint(lambda p: 1 - p.sigma, "sigma < 1", strict=True),)
    states = (State("x", 0.0, "m", "position of the block"),
              State("v", 0.0, "m/s", "velocity of the block"))
    modes = (Mode("mode", 0, "friction mode: -1 sliding backward, 0 stuck, +1 sliding forward"),)
    ports = (Port("flange_a", TRANSLATIONAL, "left side of the block"),
             Port("flange_b", TRANSLATIONAL, "right side of the block"),
             Port("plate", TRANSLATIONAL, "far end of the leaf spring, on the driving plate"))
    profiles = (Profile("in_chain", "coupling forces in, motion out; plate motion in",
                        {"flange_a": FORCE_IN, "flange_b": FORCE_IN, "plate": MOTION_IN}),)

    def equations(self, e):
        p, x, v, a = e.p, e.x.x, e.x.v, e.der.v
        fa, fb, plate = e.port("flange_a"), e.port("flange_b"), e.port("plate")
        f = e.unknown("f")
        f_leaf = p.kp * (plate.s - x)
        applied = fa.f + fb.f + f_leaf
        e.residual(e.der.x - v)
        e.residual(p.m * a - applied - f)
        for flange in (fa, fb):
            e.residual(flange.s - x)
            e.residual(flange.v - v)
            e.residual(flange.a - a)
        e.residual(plate.f - f_leaf)
        q = e.q.mode
        weakening = ca.fmax(1 + 2 * p.alpha * q * v / ((1 - p.sigma) * p.v_w), WEAKENING_FLOOR)
        coulomb_modes(e, speed="v", acceleration=a, friction=f, applied=applied,
                      static_limit=p.F_s, kinetic_limit=p.F_s * (1 - p.sigma) / weakening)
        e.output("f_friction", f, "N", "friction force on the block")
        e.output("f_leaf", f_leaf, "N", "leaf spring force on the block")
        e.output("P_friction", -f * v, "W", "power dissipated by friction")
