"""Kinematic sources: flanges moved along a prescribed path, whatever force that takes."""
from __future__ import annotations

from .component import Component
from .interfaces import FORCE_IN, TRANSLATIONAL, Parameter, Port, Profile


class ConstantSpeed(Component):
    """Translational flange moved at constant speed: s = s0 + v t (the seed's driver in 9.2).

    Parameters: ``v`` [m/s] speed, ``s0`` [m] position at t = 0.
    Connector: ``flange`` — outputs its motion (s, v, a), takes the force needed to
    move it as an input (reported, never fed back into the motion).
    """

    parameters = (Parameter("v", 0.05, "m/s", "prescribed speed"),
                  Parameter("s0", 0.0, "m", "position at t = 0"))
    ports = (Port("flange", TRANSLATIONAL, "the driven flange"),)
    profiles = (Profile("kinematic", "motion out, reaction force in", {"flange": FORCE_IN}),)

    def equations(self, e):
        flange = e.port("flange")
        e.residual(flange.s - (e.p.s0 + e.p.v * e.t))
        e.residual(flange.v - e.p.v)
        e.residual(flange.a)
