"""Rotational elements (MSL ``Modelica.Mechanics.Rotational.Components``): inertia,
fixed housing, gear, springs, damper, backlash, friction elements and the motor.

Names are imported on first use (PEP 562), like the top-level ``components``. Names
MSL shares with Translational carry the prefix ``Rotational`` here and at the top
level (their modules also export MSL's own name).
"""
from __future__ import annotations

from ..lazy import lazy_exports

# name -> the module that defines it
WHERE = {
    "BearingFriction": ".friction",
    "Clutch": ".friction",
    "ElastoBacklash": ".backlash",
    "ElastoBacklash2": ".backlash",
    "RotationalBrake": ".friction",
    "IdealGear": ".rigid",
    "Inertia": ".rigid",
    "Motor": ".elements",
    "OneWayClutch": ".friction",
    "RotationalDamper": ".elements",
    "RotationalFixed": ".rigid",
    "RotationalJunction": ".rigid",
    "RotationalSpring": ".elements",
    "RotationalSpringDamper": ".elements",
    "TorsionalSpring": ".elements",
}

__all__ = sorted(WHERE)
__getattr__, __dir__ = lazy_exports(__name__, WHERE)
