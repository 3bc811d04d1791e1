"""Assemblies of FMU instances and the named scenes.

``cosimulate``, ``simulate_me`` and ``simulate_monolithic`` run in the compiled engine
(:mod:`assemblies.engine`); :mod:`assemblies.masters` has the fmpy-driven Python
masters of the same names, the reference the engine is tested against. ``export_fmu``
writes an assembly as one FMU that runs the engine in its doStep.
"""
from .assembly import Assembly, AssemblyError
from .engine import EngineError, cosimulate, simulate_me, simulate_monolithic
from .fmu_export import export_fmu
from .foreign import FMU, FmuError
from .masters.cosim import SimulationError
from .masters.monolithic import composite
from .result import Result, Table
from .run import run_scene, run_scene_full
from .scenes import SCENES, scene

__all__ = ["Assembly", "AssemblyError", "EngineError", "FMU", "FmuError", "Result", "SCENES",
           "SimulationError", "Table", "composite", "cosimulate", "export_fmu", "run_scene",
           "run_scene_full",
           "scene", "simulate_me", "simulate_monolithic"]
