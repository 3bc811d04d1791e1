"""The compiled engine (engine="c"): assemblies run by C masters over the FMI C API.

One ctypes call per run; the FMUs are prepared once per process (:mod:`.prepare`), the
library is built once per machine (:mod:`.build`). ``cosimulate``,
``simulate_me`` and ``simulate_monolithic`` take the arguments and return the Result shape of the
fmpy-driven reference masters in :mod:`assemblies.masters`.
"""
from .binding import EngineError
from .cosim import cosimulate
from .me import prepare_me, prepare_monolithic, simulate_me, simulate_monolithic

__all__ = ["EngineError", "cosimulate", "prepare_me", "prepare_monolithic", "simulate_me",
           "simulate_monolithic"]
