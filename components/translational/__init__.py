"""Translational elements (MSL ``Modelica.Mechanics.Translational.Components``): springs,
dampers, a gap, masses with friction, stops and brakes, the seed's spring-block and the
Burridge-Knopoff block.

Names are imported on first use (PEP 562), like the top-level ``components``.
"""
from __future__ import annotations

from ..lazy import lazy_exports

# name -> the module that defines it
WHERE = {
    "FaultBlock": ".fault_block",
    "Brake": ".brakes",
    "SupportFriction": ".brakes",
    "Damper": ".elements",
    "ElastoGap": ".elements",
    "Fixed": ".elements",
    "Junction": ".rigid",
    "Rod": ".rigid",
    "Mass": ".masses",
    "MassWithStopAndFriction": ".masses",
    "MassWithFriction": ".elements",
    "Spring": ".elements",
    "SpringDamper": ".elements",
    "SpringBlock": ".spring_block",
}

__all__ = sorted(WHERE)
__getattr__, __dir__ = lazy_exports(__name__, WHERE)
