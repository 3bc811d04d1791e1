"""`c_limit`: the same model's arithmetic with nothing around it, the floor of every path.

The component's generated model.c (the very C its FMU is built from), the runtime's
DOPRI5 and event location (fmus/runtime/solver.c, events.c) and the driver
benchmarks/c_limit.c are compiled with the FMUs' flags into one shared library, cached by
content hash beside the FMUs, and called once per run through ctypes: free steps, located
events, outputs from dense output into a numpy buffer. No FMI and no Python in the run.

A scene whose component takes inputs is first joined with its sources
(assemblies.masters.monolithic.composite), so the model has none left that vary.
"""
from __future__ import annotations

import ctypes
import os
import tempfile
from pathlib import Path

import numpy as np

from components.dae import flatten
from fmus.build import RUNTIME_DIR, cache_dir, compile_library, content_hash
from fmus.codegen import generate_c, variable_table

DRIVER = Path(__file__).with_name("c_limit.c")
# the runtime's shared sources the driver links: one copy of DOPRI5 and event location
SHARED_SOURCES = ("solver.c", "events.c")
_STATE, _COMPUTED = 0, 1   # the driver's RECORD_* codes
_RESULTS = {-1: "out of memory", -2: "a model function failed or was not finite",
            -3: "the solver failed (step underflow or too many steps)",
            -4: "event iteration did not settle"}


def build_c_limit(model, identifier: str) -> Path:
    """The cached shared library of `model` (a FlatModel) with the c_limit driver."""
    source = generate_c(model, identifier, "c_limit")
    digest = content_hash("c_limit", source, DRIVER.read_text())
    target = cache_dir() / "c_limit" / f"{identifier}-{digest[:16]}.so"
    if target.exists():
        return target
    target.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="mechfmu-c-limit-") as tmp:
        model_c = Path(tmp) / "model.c"
        model_c.write_text(source)
        library = Path(tmp) / target.name
        sources = [model_c, *(RUNTIME_DIR / name for name in SHARED_SOURCES), DRIVER]
        compile_library(sources, library, [RUNTIME_DIR], f"c_limit of {identifier}")
        os.replace(library, target)  # atomic: a parallel build never sees half a library
    return target


class CLimit:
    """One component's c_limit library, loaded once; `run` records `observed` columns."""

    def __init__(self, component, observed: str | list[str]):
        component.validate()
        model = flatten(component)
        self.observed = [observed] if isinstance(observed, str) else list(observed)
        self.path = build_c_limit(model, type(component).__name__)
        self._lib = ctypes.CDLL(str(self.path))
        fn = self._lib.mf_c_limit_run
        dp, ip = ctypes.POINTER(ctypes.c_double), ctypes.POINTER(ctypes.c_int)
        fn.argtypes = [ctypes.c_double, dp, ctypes.c_int, ip, ip, ctypes.c_int, dp,
                       ctypes.POINTER(ctypes.c_long), dp, ctypes.c_int]
        fn.restype = ctypes.c_int
        self._fn = fn
        rows = {row.name: row for row in variable_table(model)}
        self.event_columns = (["time"] + [v.name for v in model.states]
                              + [v.name for v in model.modes])
        kinds, indices = [], []
        for name in self.observed:
            row = rows.get(name)
            if row is None or row.kind not in ("MF_STATE", "MF_COMPUTED"):
                recordable = [r.name for r in rows.values()
                              if r.kind in ("MF_STATE", "MF_COMPUTED")]
                raise KeyError(f"c_limit of {type(component).__name__}: '{name}' is not a state "
                               f"or output; recordable: {', '.join(recordable)}")
            kinds.append(_STATE if row.kind == "MF_STATE" else _COMPUTED)
            indices.append(row.index)
        self._kind = np.array(kinds, dtype=np.intc)
        self._index = np.array(indices, dtype=np.intc)

    def run(self, times, tol: float, max_events: int = 0):
        """(values, shape (len(times), len(observed)); work counts; events). Rows after a
        model's own end of run are NaN. `events`: the first `max_events` located events,
        a dict of arrays over `event_columns` (time, then states and modes after it)."""
        times = np.ascontiguousarray(times, dtype=float)
        out = np.empty((len(times), len(self.observed)))
        log = np.full((max(max_events, 1), len(self.event_columns)), np.nan)
        stats = (ctypes.c_long * 4)()
        dp, ip = ctypes.POINTER(ctypes.c_double), ctypes.POINTER(ctypes.c_int)
        rc = self._fn(float(tol), times.ctypes.data_as(dp), len(times),
                      self._kind.ctypes.data_as(ip), self._index.ctypes.data_as(ip),
                      len(self.observed), out.ctypes.data_as(dp), stats,
                      log.ctypes.data_as(dp) if max_events else None, max_events)
        if rc < 0:
            raise RuntimeError(f"c_limit ({self.path.name}) at tolerance {tol:g}: "
                               f"{_RESULTS.get(rc, f'error {rc}')}")
        work = dict(zip(("steps", "rhs_evals", "rejected", "events"), stats))
        log = log[:min(max_events, work["events"])]
        return out, work, dict(zip(self.event_columns, log.T))

    def column(self, times, tol: float):
        """The benchmark runner's convention: (values of the one observed variable,
        rhs_evals, steps)."""
        values, work, _ = self.run(times, tol)
        return values[:, 0], work["rhs_evals"], work["steps"]
