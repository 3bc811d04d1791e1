"""Assemblies of FMU instances, co-simulated through fmpy, and the named scenes."""
from .assembly import Assembly, AssemblyError
from .masters.cosim import SimulationError, cosimulate
from .masters.me import simulate_me
from .masters.monolithic import composite, simulate_monolithic
from .result import Result, Table
from .run import run_scene, run_scene_full
from .scenes import SCENES, scene

__all__ = ["Assembly", "AssemblyError", "Result", "SCENES", "SimulationError", "Table",
           "composite", "cosimulate", "run_scene", "run_scene_full", "scene", "simulate_me",
           "simulate_monolithic"]
