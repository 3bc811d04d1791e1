"""Assemblies of FMU instances, co-simulated through fmpy, and the named scenes."""
from .assembly import Assembly, AssemblyError
from .cosim import SimulationError, cosimulate
from .result import Result, Table
from .run import run_scene, run_scene_full
from .scenes import SCENES, scene

__all__ = ["Assembly", "AssemblyError", "Result", "SCENES", "SimulationError", "Table",
           "cosimulate", "run_scene", "run_scene_full", "scene"]
