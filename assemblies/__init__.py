"""Assemblies of FMU instances and the named scenes.

``cosimulate``, ``simulate_me`` and ``simulate_monolithic`` run in the compiled engine
(:mod:`assemblies.engine`); :mod:`assemblies.masters` has the fmpy-driven Python
masters of the same names, the reference the engine is tested against. ``export_fmu``
writes an assembly as one FMU that runs the engine in its doStep.

The names below are imported on first use (PEP 562), so that ``import assemblies.cli``
(the ``mechfmu`` command) answers ``--help`` without loading CasADi, numpy and fmpy.
"""
from __future__ import annotations

from components.lazy import lazy_exports

# name -> the module that defines it
_WHERE = {
    "Assembly": ".assembly", "AssemblyError": ".assembly",
    "EngineError": ".engine", "cosimulate": ".engine", "simulate_me": ".engine",
    "simulate_monolithic": ".engine",
    "export_fmu": ".fmu_export",
    "FMU": ".foreign", "FmuError": ".foreign",
    "SimulationError": "components.errors",
    "composite": ".masters.monolithic",
    "Result": ".result", "Table": ".result",
    "run_scene": ".run", "run_scene_full": ".run", "rerun": ".runfile",
    "SCENES": ".scenes", "scene": ".scenes",
}

__all__ = sorted(_WHERE)


__getattr__, __dir__ = lazy_exports(__name__, _WHERE)
