"""Acausal CasADi DAE components with MSL-style ports.

``COMPONENTS`` maps the names that ``mechfmu build`` takes to component classes.
"""
from .component import Component
from .dae import FlatModel, flatten
from .interfaces import ComponentError, Parameter, Port, Profile, State
from .sources import ConstantSpeed
from .spring_block import SpringBlock

COMPONENTS = {cls.__name__: cls for cls in (SpringBlock, ConstantSpeed)}

__all__ = ["COMPONENTS", "Component", "ComponentError", "ConstantSpeed", "FlatModel",
           "Parameter", "Port", "Profile", "SpringBlock", "State", "flatten"]
