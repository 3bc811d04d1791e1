"""What surrounds the integration: fmpy's ctypes cost per call, build times, memory.

The per-call figures explain the work–precision plots: a Co-Simulation FMU pays one
doStep (plus one get) per output interval through ctypes, a Model Exchange FMU driven
from Python pays three calls per right-hand-side evaluation.
"""
from __future__ import annotations

import ctypes
import os
import tempfile
import time

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi3 import FMU3Model, FMU3Slave

from assemblies.masters.monolithic import composite
from assemblies.scenes import scene
from components.beam import AssumedModesBeam
from components.dae import flatten

from .runners import class_default_fmu

_DOUBLE_P = ctypes.POINTER(ctypes.c_double)


def _per_call(fn, n):
    fn()  # warm
    started = time.perf_counter()
    for _ in range(n):
        fn()
    return (time.perf_counter() - started) / n


def call_overheads(n: int = 20000) -> dict[str, float]:
    """Seconds per call, on the stick_slip model (2 states; the math itself is nanoseconds)."""
    asm = scene("stick_slip").build()
    comp = composite(asm)
    path = class_default_fmu(comp)
    md, unzipped = read_model_description(path), extract(path)
    vr_x = [next(v.valueReference for v in md.modelVariables if v.name == "block.x")]
    out = {}

    slave = FMU3Slave(guid=md.guid, unzipDirectory=unzipped,
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName="cs")
    slave.instantiate()
    slave.enterInitializationMode(tolerance=1e-6, startTime=0.0, stopTime=1e9)
    slave.exitInitializationMode()
    out["getFloat64 (one variable), CS"] = _per_call(lambda: slave.getFloat64(vr_x), n)
    clock = [0.0]

    def step():  # stuck for the first 8 s: a doStep of 1e-4 s is one trivial solver step
        slave.doStep(clock[0], 1e-4)
        clock[0] += 1e-4
    out["doStep (h = 1e-4 s, stuck: one solver step)"] = _per_call(step, min(n, 50000))
    slave.terminate()
    slave.freeInstance()

    model = FMU3Model(guid=md.guid, unzipDirectory=unzipped,
                      modelIdentifier=md.modelExchange.modelIdentifier, instanceName="me")
    model.instantiate()
    model.enterInitializationMode(tolerance=1e-6, startTime=0.0, stopTime=1e9)
    model.exitInitializationMode()
    model.enterContinuousTimeMode()
    nx = len(md.derivatives)
    x, dx = np.array([0.0, 0.0]), np.zeros(nx)

    def rhs_me():
        model.setTime(1.0)
        model.setContinuousStates(x.ctypes.data_as(_DOUBLE_P), nx)
        model.getContinuousStateDerivatives(dx.ctypes.data_as(_DOUBLE_P), nx)
    out["ME right-hand side (setTime + setContinuousStates + getDerivatives)"] = _per_call(rhs_me, n)
    model.terminate()
    model.freeInstance()

    ode = flatten(comp).functions()["ode"]
    flat = flatten(comp)
    q0, u0, p0 = (np.array([v.start for v in vs]) for vs in (flat.modes, flat.inputs, flat.parameters))
    out["CasADi Function call from Python (the monolithic master's RHS)"] = _per_call(
        lambda: ode(1.0, x, q0, u0, p0), n)

    def rhs_numpy(t=1.0, y=x):  # what benchmarks.baselines writes for this model
        return np.array([y[1], (1.0 * (0.05 * t - y[0]) - 0.3 * 1.0) / 1.0])
    out["hand-written numpy right-hand side"] = _per_call(rhs_numpy, n)
    return out


def build_times(components: dict) -> dict[str, dict[str, float]]:
    """Cold (empty cache: flatten, C generation, gcc, zip) and cached (hash lookup) builds."""
    result = {}
    previous = os.environ.get("MECHFMU_CACHE")
    with tempfile.TemporaryDirectory(prefix="mechfmu-bench-cache-") as tmp:
        os.environ["MECHFMU_CACHE"] = tmp
        try:
            for name, make in components.items():
                started = time.perf_counter()
                class_default_fmu(make())
                cold = time.perf_counter() - started
                started = time.perf_counter()
                class_default_fmu(make())
                result[name] = {"cold_s": cold, "cached_s": time.perf_counter() - started}
        finally:
            if previous is None:
                os.environ.pop("MECHFMU_CACHE", None)
            else:
                os.environ["MECHFMU_CACHE"] = previous
    return result


def default_build_set(beam_sizes=(4, 8, 16, 32)) -> dict:
    return {
        "stick_slip (composite)": lambda: composite(scene("stick_slip").build()),
        **{f"beam N={n}": (lambda n=n: AssumedModesBeam(name="beam", n_modes=n))
           for n in beam_sizes},
        "axle_pendulum": lambda: scene("axle_pendulum").build().component("body"),
        "coin_rolling": lambda: scene("coin_rolling").build().component("coin"),
        "moving_table (composite)": lambda: composite(scene("moving_table").build()),
    }
