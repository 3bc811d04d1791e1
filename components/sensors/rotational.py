"""Rotational sensors (MSL Rotational.Sensors): angle, speed, torque and power as signals.

``AngleSensor`` and ``RotationalSpeedSensor`` take the flange's motion in and give zero
torque back (they hang off any flange that computes motion). ``TorqueSensor`` and
``RotationalPowerSensor`` sit in the torque path, rigid and massless: they pass the
motion from one flange to the other and the torque back, whichever side computes the
motion (profile ``motion_at_a`` or ``motion_at_b``). Where MSL's name exists in
Translational the class carries the prefix ``Rotational``; MSL's names are aliases.
"""
from __future__ import annotations

from ..component import Component
from ..interfaces import FORCE_IN, MOTION_IN, ROTATIONAL, SIGNAL_OUT, Port, Profile, signal


def _reading(port: str, unit: str, description: str):
    ports = (Port("flange", ROTATIONAL, "the measured flange"), Port(port, signal(unit), description))
    profiles = (Profile("sensing", f"motion in, zero torque out; {port} out",
                        {"flange": MOTION_IN, port: SIGNAL_OUT}),)
    return ports, profiles


def _through(port: str, unit: str, description: str):
    ports = (Port("flange_a", ROTATIONAL, "left flange"),
             Port("flange_b", ROTATIONAL, "right flange"), Port(port, signal(unit), description))
    profiles = (Profile("motion_at_a", "motion in at flange_a, passed on at flange_b",
                        {"flange_a": MOTION_IN, "flange_b": FORCE_IN, port: SIGNAL_OUT}),
                Profile("motion_at_b", "motion in at flange_b, passed on at flange_a",
                        {"flange_a": FORCE_IN, "flange_b": MOTION_IN, port: SIGNAL_OUT}))
    return ports, profiles


def _rigid(e):
    a, b = e.port("flange_a"), e.port("flange_b")
    for name in ("phi", "w", "a"):
        e.residual(getattr(a, name) - getattr(b, name))
    e.residual(a.tau + b.tau)
    return a


class AngleSensor(Component):
    """Absolute angle of a flange (MSL Rotational.Sensors.AngleSensor). Output: ``phi`` [rad]."""

    ports, profiles = _reading("phi", "rad", "absolute angle of the flange")

    def equations(self, e):
        e.residual(e.port("flange").tau)
        e.residual(e.port("phi") - e.port("flange").phi)


class RotationalSpeedSensor(Component):
    """Absolute angular velocity of a flange (MSL Rotational.Sensors.SpeedSensor; registered
    as RotationalSpeedSensor). Output: ``w`` [rad/s]."""

    ports, profiles = _reading("w", "rad/s", "absolute angular velocity of the flange")

    def equations(self, e):
        e.residual(e.port("flange").tau)
        e.residual(e.port("w") - e.port("flange").w)


class TorqueSensor(Component):
    """Torque in the shaft between two flanges (MSL Rotational.Sensors.TorqueSensor).

    ``tau = flange_a.tau`` (MSL's sign: the torque driving into flange_a, passed on to
    flange_b). Output: ``tau`` [N.m].
    """

    ports, profiles = _through("tau", "N.m", "torque transmitted from flange_a to flange_b")

    def equations(self, e):
        e.residual(e.port("tau") - _rigid(e).tau)


class RotationalPowerSensor(Component):
    """Power through the shaft between two flanges (MSL Rotational.Sensors.PowerSensor;
    registered as RotationalPowerSensor).

    ``power = flange_a.tau flange_a.w``. Output: ``power`` [W].
    """

    ports, profiles = _through("power", "W", "power transmitted from flange_a to flange_b")

    def equations(self, e):
        a = _rigid(e)
        e.residual(e.port("power") - a.tau * a.w)


SpeedSensor, PowerSensor = RotationalSpeedSensor, RotationalPowerSensor  # MSL's names
