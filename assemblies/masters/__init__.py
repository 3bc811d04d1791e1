"""The fmpy-driven Python masters (``engine="fmpy"``): the reference implementation the
compiled engine is tested against, and proof that our FMUs co-simulate through fmpy.

The names below are imported on first use (PEP 562): the engine's binding needs only
``SimulationError`` from ``.cosim``, and the Model Exchange masters load scipy's
integrators (0.3 s) that a run of the compiled engine never uses.
"""
from __future__ import annotations

from components.lazy import lazy_exports

# name -> the module that defines it
_WHERE = {"SimulationError": ".cosim", "cosimulate": ".cosim", "simulate_me": ".me",
          "composite": ".monolithic", "join": ".monolithic",
          "simulate_monolithic": ".monolithic"}

__all__ = sorted(_WHERE)


__getattr__, __dir__ = lazy_exports(__name__, _WHERE)
