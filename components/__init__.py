"""Acausal CasADi DAE components with MSL-style ports.

``COMPONENTS`` maps the names that ``mechfmu build`` takes to component classes.

The names below are imported on first use (PEP 562): ``from components.errors import
MechfmuError`` (every command does) loads the errors, not numpy and the modules of
the elements.
"""
from __future__ import annotations

from . import bodies as _bodies, rotational as _rotational, sensors as _sensors
from . import sources as _sources, translational as _translational
from .lazy import lazy_exports

# name -> the module that defines it: the shared pieces here, the elements in the
# subpackages laid out as MSL lays out Mechanics (each subpackage keeps its own map)
_WHERE = {
    "Block": ".component", "Component": ".component",
    "FlatModel": ".dae", "flatten": ".dae",
    "ComponentError": ".interfaces", "Parameter": ".interfaces", "Port": ".interfaces",
    "Profile": ".interfaces", "State": ".interfaces",
}
for _package, _names in ((".translational", _translational), (".rotational", _rotational),
                         (".bodies", _bodies), (".sources", _sources), (".sensors", _sensors)):
    _WHERE.update({name: _package for name in _names.WHERE})

# the components `mechfmu build` and `show` take, in the order `mechfmu components` lists them
_REGISTERED = (
    "SpringBlock", "ConstantSpeed", "SineMotion", "HarmonicMotion", "ConstantForce",
    "AssumedModesBeam", "RigidBodyOnAxle", "InclinedCylinder", "HemisphericalShell",
    "RodOnRollers", "ConeOnIncline", "RollingCoin", "TorqueFreeBody", "NutationDamperBody",
    "WobblingDisk", "RigidBodyOnString", "Skate", "SlidingRod", "SlidingDisk",
    "MassWithFriction", "Spring", "SpringDamper", "TorsionalSpring", "Motor", "Force",
    "Position", "Speed", "PositionSensor", "SpeedSensor", "ForceSensor", "TimeTable",
    "FaultBlock", "Constant", "Step", "Ramp", "Sine",
    "Fixed", "Mass", "Damper", "ElastoGap", "MassWithStopAndFriction",
    "SupportFriction", "Brake", "Rod", "Junction",
    "Inertia", "RotationalFixed", "IdealGear", "RotationalSpring", "RotationalDamper",
    "RotationalSpringDamper", "Torque", "ConstantTorque", "QuadraticSpeedDependentTorque",
    "RotationalSpeed", "RotationalPosition", "AngleSensor", "RotationalSpeedSensor",
    "TorqueSensor", "RotationalPowerSensor", "BearingFriction", "RotationalBrake", "Clutch",
    "OneWayClutch", "Product", "ElastoBacklash", "ElastoBacklash2", "RotationalJunction")

__all__ = sorted([*_WHERE, "COMPONENTS"])


__getattr__, __dir__ = lazy_exports(__name__, _WHERE, {
    "COMPONENTS": lambda: {key: __getattr__(key) for key in _REGISTERED}})
