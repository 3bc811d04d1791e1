"""The engine's shared library: compiled by gcc once per machine, cached like the FMUs.

The library is every C file in ``assemblies/engine/c`` plus the FMU runtime's solver
and event-location sources it shares (one copy of DOPRI5, RODAS3 and event location
for FMUs and engine alike). The cache key is the content of those sources and the
compiler flags, so an edit rebuilds and an unchanged tree never does.
"""
from __future__ import annotations

import ctypes
import functools
import hashlib
import os
from pathlib import Path

from fmus.build import CFLAGS, FMI_HEADERS, RUNTIME_DIR, cache_dir, compile_library

C_DIR = Path(__file__).parent / "c"
# the FMU runtime's sources the engine links: solvers, their LU, event location
SHARED_RUNTIME = ("dense_lu", "events", "solver", "solver_implicit")


def sources() -> list[Path]:
    """Every file that goes into the library (C and headers), in a fixed order."""
    engine = sorted(C_DIR.glob("*.[ch]"))
    shared = [RUNTIME_DIR / f"{name}.{ext}" for name in SHARED_RUNTIME for ext in ("c", "h")]
    return engine + shared


def library_path() -> Path:
    """The compiled library, built now if this content has never been built here."""
    h = hashlib.sha256()
    for path in sources():
        h.update(path.name.encode() + b"\0" + path.read_bytes() + b"\0")
    h.update(" ".join(CFLAGS).encode())
    target = cache_dir() / "engine" / f"libmfengine-{h.hexdigest()[:16]}.so"
    if not target.exists():
        target.parent.mkdir(parents=True, exist_ok=True)
        partial = target.with_suffix(f".{os.getpid()}.partial")
        compile_library([p for p in sources() if p.suffix == ".c"], partial,
                        [C_DIR, RUNTIME_DIR, FMI_HEADERS], "the engine")
        partial.replace(target)  # atomic: a parallel build never loads half a library
    return target


@functools.lru_cache(maxsize=None)
def library() -> ctypes.CDLL:
    """The engine, loaded once per process."""
    return ctypes.CDLL(str(library_path()))
