"""Kinematic sources: flanges moved along a prescribed path, whatever force that takes."""
from __future__ import annotations

import math

from ..component import Component
from ..interfaces import (FORCE_IN, SIGNAL_IN, TRANSLATIONAL, Parameter, Port, Profile, State,
                         signal)


class ConstantSpeed(Component):
    """Translational flange moved at constant speed: s = s0 + v t (the seed's driver in 9.2).

    Parameters: ``v`` [m/s] speed, ``s0`` [m] position at t = 0.
    Connector: ``flange`` — outputs its motion (s, v, a), takes the force needed to
    move it as an input (reported, never fed back into the motion).

    The distance travelled is a state, travel' = v, rather than v t written in time:
    the model is then autonomous, so an assembly held by a wall (v = 0) is seen to
    stand still for good once nothing else moves, and a driver's motion moves a state
    the solvers see; every solver integrates travel' = v exactly (to rounding).
    """

    parameters = (Parameter("v", 0.05, "m/s", "prescribed speed"),
                  Parameter("s0", 0.0, "m", "position at t = 0"))
    states = (State("travel", 0.0, "m", "distance moved since t = 0: s = s0 + travel"),)
    ports = (Port("flange", TRANSLATIONAL, "the driven flange"),)
    profiles = (Profile("kinematic", "motion out, reaction force in", {"flange": FORCE_IN}),)

    def equations(self, e):
        flange = e.port("flange")
        e.residual(e.der.travel - e.p.v)
        e.residual(flange.s - (e.p.s0 + e.x.travel))
        e.residual(flange.v - e.p.v)
        e.residual(flange.a)


# MSL's Position and Speed filter their input by default (exact=false): an FMU sees its
# input's value only, never its derivatives, so exact=true (v = der(s_ref), which a
# Modelica tool gets by differentiating the input symbolically) has no FMU equivalent.
# The filters give s, v and a that are exact derivatives of one another, so what the
# flange drives (a mass on it as its support, a spring extrapolating s with v and a)
# sees a consistent motion; the price is a lag of about 1/w_crit behind the signal.
_AF, _BF = 1.3617, 0.6180  # MSL's critically damped (Bessel) second-order filter coefficients
_F_CRIT = Parameter("f_crit", 50.0, "Hz", "critical frequency of the filter on the input",
                    min=0.0, min_strict=True)
_SOURCE_STATES = (State("s", 0.0, "m", "absolute position of the flange"),
                  State("v", 0.0, "m/s", "absolute velocity of the flange"))


def _drive(e):
    """The flange follows the states: s, v and a = der(v)."""
    flange = e.port("flange")
    e.residual(e.der.s - e.x.v)
    e.residual(flange.s - e.x.s)
    e.residual(flange.v - e.x.v)
    e.residual(flange.a - e.der.v)


class Position(Component):
    """Flange moved to follow a position signal through a filter (MSL Translational.Sources.Position).

    ``s`` follows ``s_ref`` through MSL's critically damped second-order filter
    (exact = false): ``a = ((s_ref - s) w_crit - 1.3617 v) w_crit / 0.6180``,
    ``w_crit = 2 pi f_crit``; at steady state s = s_ref.
    Parameter: ``f_crit`` [Hz]. States: ``s`` [m], ``v`` [m/s] (start at rest at 0).
    Input: ``s_ref`` [m]. Connector: ``flange`` — outputs s, v, a; the force it takes
    to move it is an input (reported, never fed back into the motion).
    """

    parameters = (_F_CRIT,)
    states = _SOURCE_STATES
    ports = (Port("s_ref", signal("m"), "reference position of the flange"),
             Port("flange", TRANSLATIONAL, "the driven flange"))
    profiles = (Profile("kinematic", "position signal in; motion out, reaction force in",
                        {"s_ref": SIGNAL_IN, "flange": FORCE_IN}),)

    def equations(self, e):
        w = 2 * math.pi * e.p.f_crit
        _drive(e)
        e.residual(e.der.v - ((e.port("s_ref") - e.x.s) * w - _AF * e.x.v) * (w / _BF))


class Speed(Component):
    """Flange moved to follow a speed signal through a filter (MSL Translational.Sources.Speed).

    ``v`` follows ``v_ref`` through MSL's first-order filter (exact = false):
    ``a = (v_ref - v) w_crit``, ``w_crit = 2 pi f_crit``; ``s`` is the integral of v.
    Parameter: ``f_crit`` [Hz]. States: ``s`` [m], ``v`` [m/s] (start at rest at 0).
    Input: ``v_ref`` [m/s]. Connector: ``flange`` — outputs s, v, a; force in.
    """

    parameters = (_F_CRIT,)
    states = _SOURCE_STATES
    ports = (Port("v_ref", signal("m/s"), "reference speed of the flange"),
             Port("flange", TRANSLATIONAL, "the driven flange"))
    profiles = (Profile("kinematic", "speed signal in; motion out, reaction force in",
                        {"v_ref": SIGNAL_IN, "flange": FORCE_IN}),)

    def equations(self, e):
        _drive(e)
        e.residual(e.der.v - (e.port("v_ref") - e.x.v) * (2 * math.pi * e.p.f_crit))
