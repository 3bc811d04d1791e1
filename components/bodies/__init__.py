"""The seed's bodies: the rigid body on an axle, the assumed-modes beam, the rolling coin,
the torque-free and dissipative rigid bodies, the bodies of chapters 5-8 and the flat
sliders of 9.8.

Names are imported on first use (PEP 562), like the top-level ``components``.
"""
from __future__ import annotations

from ..lazy import lazy_exports

# name -> the module that defines it
WHERE = {
    "RigidBodyOnAxle": ".axle",
    "AssumedModesBeam": ".beam",
    "NutationDamperBody": ".dissipation",
    "Skate": ".rigid_bodies",
    "TorqueFreeBody": ".rigid_bodies",
    "WobblingDisk": ".rigid_bodies",
    "RigidBodyOnString": ".string_body",
    "RollingCoin": ".rolling_coin",
    "ConeOnIncline": ".seed_bodies",
    "HemisphericalShell": ".seed_bodies",
    "InclinedCylinder": ".seed_bodies",
    "RodOnRollers": ".seed_bodies",
    "SlidingDisk": ".planar_sliding",
    "SlidingRod": ".planar_sliding",
}

__all__ = sorted(WHERE)
__getattr__, __dir__ = lazy_exports(__name__, WHERE)
