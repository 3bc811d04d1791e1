"""Sensors (MSL ``Sensors``): position, speed and force of a flange as output signals.

Names are imported on first use (PEP 562), like the top-level ``components``.
"""
from __future__ import annotations

from ..lazy import lazy_exports

# name -> the module that defines it
WHERE = {
    "ForceSensor": ".translational",
    "PositionSensor": ".translational",
    "SpeedSensor": ".translational",
}

__all__ = sorted(WHERE)
__getattr__, __dir__ = lazy_exports(__name__, WHERE)
