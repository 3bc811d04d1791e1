"""Rotational elements (MSL ``Modelica.Mechanics.Rotational.Components``): torsional
springs and the motor.

Names are imported on first use (PEP 562), like the top-level ``components``.
"""
from __future__ import annotations

from ..lazy import lazy_exports

# name -> the module that defines it
WHERE = {
    "Motor": ".elements",
    "TorsionalSpring": ".elements",
}

__all__ = sorted(WHERE)
__getattr__, __dir__ = lazy_exports(__name__, WHERE)
