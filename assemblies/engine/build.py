"""The engine's shared library: compiled by gcc once per machine, cached like the FMUs.

The library is every C file in ``assemblies/engine/c`` plus the FMU runtime's solver
and event-location sources it shares (one copy of DOPRI5, RODAS3 and event location
for FMUs and engine alike). The cache key is the content of those sources and the
compiler flags, so an edit rebuilds and an unchanged tree never does.
"""
from __future__ import annotations

import ctypes
import functools
from pathlib import Path

from fmus.build import FMI_HEADERS, RUNTIME_DIR, BuildError, cached_library

C_DIR = Path(__file__).parent / "c"
# the FMU runtime's sources the engine links: solvers, their LU, event location
SHARED_RUNTIME = ("dense_lu", "events", "solver", "solver_implicit", "stiffness")


def sources() -> list[Path]:
    """Every file that goes into the library (C and headers), in a fixed order."""
    engine = sorted(C_DIR.glob("*.[ch]"))
    shared = [RUNTIME_DIR / f"{name}.{ext}" for name in SHARED_RUNTIME for ext in ("c", "h")]
    return engine + shared


def library_path() -> Path:
    """The compiled library, built now if this content has never been built here."""
    return cached_library("engine", "libmfengine", sources(), [C_DIR, RUNTIME_DIR, FMI_HEADERS],
                          "the engine")


@functools.lru_cache(maxsize=None)
def library() -> ctypes.CDLL:
    """The engine, loaded once per process."""
    path = library_path()  # checked against the checksum its build recorded
    try:
        return ctypes.CDLL(str(path))
    except OSError as exc:  # intact but unloadable: a different machine wrote the cache
        raise BuildError(f"cannot load the engine library {path} ({exc}); remove it and "
                         "run again to rebuild it") from None
