"""The fmpy-driven Python masters (``engine="fmpy"``): the reference implementation the
compiled engine is tested against, and proof that our FMUs co-simulate through fmpy.

The names below are imported on first use (PEP 562): the engine's binding needs only
``SimulationError`` from ``.cosim``, and the Model Exchange masters load scipy's
integrators (0.3 s) that a run of the compiled engine never uses.
"""
from __future__ import annotations

import importlib

# name -> the module that defines it
_WHERE = {"SimulationError": ".cosim", "cosimulate": ".cosim", "simulate_me": ".me",
          "composite": ".monolithic", "join": ".monolithic",
          "simulate_monolithic": ".monolithic"}

__all__ = sorted(_WHERE)


def __getattr__(name: str):
    if name not in _WHERE:
        raise AttributeError(f"module 'assemblies.masters' has no attribute '{name}'")
    value = getattr(importlib.import_module(_WHERE[name], __name__), name)
    globals()[name] = value  # once: later lookups do not come back here
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_WHERE))
