"""The fmpy-driven Python masters (``engine="fmpy"``): the reference implementation the
compiled engine is tested against, and proof that our FMUs co-simulate through fmpy."""
from .cosim import SimulationError, cosimulate
from .me import simulate_me
from .monolithic import composite, join, simulate_monolithic

__all__ = ["SimulationError", "composite", "cosimulate", "join", "simulate_me",
           "simulate_monolithic"]
