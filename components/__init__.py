"""Acausal CasADi DAE components with MSL-style ports.

``COMPONENTS`` maps the names that ``mechfmu build`` takes to component classes.
"""
from .component import Block, Component
from .dae import FlatModel, flatten
from .interfaces import ComponentError, Parameter, Port, Profile, State
from .axle import RigidBodyOnAxle
from .beam import AssumedModesBeam
from .dissipation import NutationDamperBody
from .force_sources import ConstantForce, Force
from .motion_sources import HarmonicMotion, SineMotion
from .rigid_bodies import Skate, TorqueFreeBody, WobblingDisk
from .rolling_coin import RollingCoin
from .seed_bodies import HemisphericalShell, InclinedCylinder, RodOnRollers
from .sensors import ForceSensor, PositionSensor, SpeedSensor
from .sources import ConstantSpeed, Position, Speed
from .spring_block import SpringBlock
from .table_sources import TimeTable
from .rotational import Motor, TorsionalSpring
from .translational import MassWithFriction, Spring, SpringDamper

COMPONENTS = {cls.__name__: cls for cls in (
    SpringBlock, ConstantSpeed, SineMotion, HarmonicMotion, ConstantForce, AssumedModesBeam,
    RigidBodyOnAxle, InclinedCylinder, HemisphericalShell, RodOnRollers, RollingCoin,
    TorqueFreeBody, NutationDamperBody, WobblingDisk, Skate, MassWithFriction, Spring,
    SpringDamper, TorsionalSpring, Motor, Force, Position, Speed, PositionSensor, SpeedSensor, ForceSensor,
    TimeTable)}

__all__ = ["AssumedModesBeam", "Block", "COMPONENTS", "Component", "ComponentError",
           "ConstantForce", "ConstantSpeed", "FlatModel", "Force", "ForceSensor",
           "HarmonicMotion", "SineMotion", "HemisphericalShell", "InclinedCylinder",
           "MassWithFriction", "Motor", "NutationDamperBody", "Parameter", "Port", "Position",
           "PositionSensor", "Profile", "RigidBodyOnAxle", "RodOnRollers", "RollingCoin", "Skate", "Speed",
           "SpeedSensor", "Spring", "SpringBlock", "SpringDamper", "State", "TimeTable", "TorsionalSpring",
           "TorqueFreeBody", "WobblingDisk", "flatten"]
