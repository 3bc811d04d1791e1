"""Sensors (MSL ``Sensors``): a flange's motion, force, torque or power as output signals.

Names are imported on first use (PEP 562), like the top-level ``components``.
"""
from __future__ import annotations

from ..lazy import lazy_exports

# name -> the module that defines it
WHERE = {
    "AngleSensor": ".rotational",
    "RotationalPowerSensor": ".rotational",
    "RotationalSpeedSensor": ".rotational",
    "TorqueSensor": ".rotational",
    "ForceSensor": ".translational",
    "PositionSensor": ".translational",
    "SpeedSensor": ".translational",
}

__all__ = sorted(WHERE)
__getattr__, __dir__ = lazy_exports(__name__, WHERE)
