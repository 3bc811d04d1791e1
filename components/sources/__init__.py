"""Sources (MSL ``Sources``): prescribed motion, force and time tables.

Names are imported on first use (PEP 562), like the top-level ``components``.
"""
from __future__ import annotations

from ..lazy import lazy_exports

# name -> the module that defines it
WHERE = {
    "ConstantForce": ".force",
    "Force": ".force",
    "HarmonicMotion": ".motion",
    "SineMotion": ".motion",
    "TimeTable": ".table",
    "ConstantSpeed": ".translational",
    "Position": ".translational",
    "Speed": ".translational",
}

__all__ = sorted(WHERE)
__getattr__, __dir__ = lazy_exports(__name__, WHERE)
