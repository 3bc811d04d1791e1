"""Acausal CasADi DAE components with MSL-style ports.

``COMPONENTS`` maps the names that ``mechfmu build`` takes to component classes.

The names below are imported on first use (PEP 562): ``from components.errors import
MechfmuError`` (every command does) loads the errors, not numpy and the twenty modules
of components.
"""
from __future__ import annotations

from .lazy import lazy_exports

# name -> the module that defines it
_WHERE = {
    "Block": ".component", "Component": ".component",
    "FlatModel": ".dae", "flatten": ".dae",
    "ComponentError": ".interfaces", "Parameter": ".interfaces", "Port": ".interfaces",
    "Profile": ".interfaces", "State": ".interfaces",
    "RigidBodyOnAxle": ".axle", "AssumedModesBeam": ".beam",
    "NutationDamperBody": ".dissipation",
    "ConstantForce": ".force_sources", "Force": ".force_sources",
    "HarmonicMotion": ".motion_sources", "SineMotion": ".motion_sources",
    "Skate": ".rigid_bodies", "TorqueFreeBody": ".rigid_bodies", "WobblingDisk": ".rigid_bodies",
    "RollingCoin": ".rolling_coin",
    "HemisphericalShell": ".seed_bodies", "InclinedCylinder": ".seed_bodies",
    "RodOnRollers": ".seed_bodies",
    "ForceSensor": ".sensors", "PositionSensor": ".sensors", "SpeedSensor": ".sensors",
    "ConstantSpeed": ".sources", "Position": ".sources", "Speed": ".sources",
    "SpringBlock": ".spring_block", "TimeTable": ".table_sources",
    "Motor": ".rotational", "TorsionalSpring": ".rotational",
    "MassWithFriction": ".translational", "Spring": ".translational",
    "SpringDamper": ".translational",
}

# the components `mechfmu build` and `show` take, in the order `mechfmu components` lists them
_REGISTERED = (
    "SpringBlock", "ConstantSpeed", "SineMotion", "HarmonicMotion", "ConstantForce",
    "AssumedModesBeam", "RigidBodyOnAxle", "InclinedCylinder", "HemisphericalShell",
    "RodOnRollers", "RollingCoin", "TorqueFreeBody", "NutationDamperBody", "WobblingDisk",
    "Skate", "MassWithFriction", "Spring", "SpringDamper", "TorsionalSpring", "Motor", "Force",
    "Position", "Speed", "PositionSensor", "SpeedSensor", "ForceSensor", "TimeTable")

__all__ = sorted([*_WHERE, "COMPONENTS"])


__getattr__, __dir__ = lazy_exports(__name__, _WHERE, {
    "COMPONENTS": lambda: {key: __getattr__(key) for key in _REGISTERED}})
