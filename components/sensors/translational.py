"""Sensors: a flange's motion or the force through it, read into a signal (MSL Translational.Sensors).

A sensor takes nothing from what it measures: ``PositionSensor`` and ``SpeedSensor``
take the flange's motion in and give back zero force (``motion`` causality, like a
spring with no stiffness), so they hang off any flange that computes motion.
``ForceSensor`` sits in the force path between two flanges: it passes the motion from
one side to the other and the force back, whichever side computes the motion.
"""
from __future__ import annotations

from ..component import Component
from ..interfaces import (FORCE_IN, MOTION_IN, SIGNAL_OUT, TRANSLATIONAL, Port, Profile,
                         signal)


def _reading(port: str, across: str, unit: str, description: str):
    """(ports, profiles) of a sensor that reads one across variable of its flange."""
    ports = (Port("flange", TRANSLATIONAL, "the measured flange"),
             Port(port, signal(unit), description))
    profiles = (Profile("sensing", f"motion in, zero force out; {across} out",
                        {"flange": MOTION_IN, port: SIGNAL_OUT}),)
    return ports, profiles


class PositionSensor(Component):
    """Absolute position of a flange as a signal (MSL Translational.Sensors.PositionSensor).

    Connector: ``flange`` — motion in, zero force out. Output: ``s`` [m].
    """

    ports, profiles = _reading("s", "position", "m", "absolute position of the flange")

    def equations(self, e):
        flange = e.port("flange")
        e.residual(flange.f)
        e.residual(e.port("s") - flange.s)


class SpeedSensor(Component):
    """Absolute velocity of a flange as a signal (MSL Translational.Sensors.SpeedSensor).

    Connector: ``flange`` — motion in, zero force out. Output: ``v`` [m/s].
    """

    ports, profiles = _reading("v", "speed", "m/s", "absolute velocity of the flange")

    def equations(self, e):
        flange = e.port("flange")
        e.residual(flange.f)
        e.residual(e.port("v") - flange.v)


class ForceSensor(Component):
    """Force transmitted between two flanges as a signal (MSL Translational.Sensors.ForceSensor).

    Massless and rigid: both flanges move alike, ``flange_a.f + flange_b.f = 0``, and
    ``f = flange_a.f`` (MSL's sign: the force pushing into flange_a, along +s towards b).
    Connectors: ``flange_a``, ``flange_b`` — one takes the motion in and gives the
    force out, the other passes that motion on and takes the force in; the profile
    says which (``motion_at_a`` or ``motion_at_b``), the assembly picks it.
    Output: ``f`` [N].
    """

    ports = (Port("flange_a", TRANSLATIONAL, "left flange"),
             Port("flange_b", TRANSLATIONAL, "right flange"),
             Port("f", signal("N"), "force from flange_a to flange_b"))
    profiles = (Profile("motion_at_a", "motion in at flange_a, passed on at flange_b",
                        {"flange_a": MOTION_IN, "flange_b": FORCE_IN, "f": SIGNAL_OUT}),
                Profile("motion_at_b", "motion in at flange_b, passed on at flange_a",
                        {"flange_a": FORCE_IN, "flange_b": MOTION_IN, "f": SIGNAL_OUT}))

    def equations(self, e):
        a, b = e.port("flange_a"), e.port("flange_b")
        for name in ("s", "v", "a"):
            e.residual(getattr(a, name) - getattr(b, name))
        e.residual(a.f + b.f)
        e.residual(e.port("f") - a.f)
