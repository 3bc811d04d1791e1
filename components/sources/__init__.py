"""Sources (MSL ``Sources``): prescribed motion, force, time tables and signals.

Names are imported on first use (PEP 562), like the top-level ``components``.
"""
from __future__ import annotations

from ..lazy import lazy_exports

# name -> the module that defines it
WHERE = {
    "Constant": ".signals",
    "ConstantForce": ".force",
    "Force": ".force",
    "HarmonicMotion": ".motion",
    "Product": ".math",
    "SineMotion": ".motion",
    "Ramp": ".signals",
    "Sine": ".signals",
    "Step": ".signals",
    "TimeTable": ".table",
    "ConstantTorque": ".rotational",
    "QuadraticSpeedDependentTorque": ".rotational",
    "RotationalPosition": ".rotational",
    "RotationalSpeed": ".rotational",
    "Torque": ".rotational",
    "ConstantSpeed": ".translational",
    "Position": ".translational",
    "Speed": ".translational",
}

__all__ = sorted(WHERE)
__getattr__, __dir__ = lazy_exports(__name__, WHERE)
