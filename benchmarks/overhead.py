"""What surrounds the integration: fmpy's ctypes cost per call, build times, memory.

The per-call figures explain the work–precision plots: a Co-Simulation FMU pays one
doStep (plus one get) per output interval through ctypes, a Model Exchange FMU driven
from Python pays three calls per right-hand-side evaluation.
"""
from __future__ import annotations

import ctypes
import json
import os
import tempfile
import time

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi3 import FMU3Model, FMU3Slave

from assemblies.masters.monolithic import composite
from assemblies.scenes import scene
from components.bodies.beam import AssumedModesBeam
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
    """Seconds per call, on the stick_slip model (the block's 2 states and the driver's
    travel; the math itself is nanoseconds)."""
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
    x, dx = np.zeros(nx), np.zeros(nx)  # the composite's states, whatever their number

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

    def rhs_numpy(t=1.0, y=np.zeros(2)):  # what benchmarks.baselines writes for the block
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


# --- before the first step, and what is not recorded (issue 13) ------------------------
# `python -m benchmarks.overhead`: a table, and benchmarks/overhead.json for RESULTS.md

STARTUP_SCENES = ("stick_slip", "two_block_belt", "resonance_below", "beam_free_vibration")
PRUNING_SCENES = ("stick_slip", "two_block_belt")
HERE = os.path.dirname(os.path.abspath(__file__))
JSON_PATH = os.path.join(HERE, "overhead.json")

_PROBE = r'''
import json, sys, time
import assemblies.engine.cosim as cosim, assemblies.engine.me as me
from assemblies.engine.build import library
from assemblies.run import run_scene_full
from assemblies.scenes import scene

marks = []

class TimedCall:  # the engine's entry point, noting when the C call starts and returns
    def __init__(self, fn): object.__setattr__(self, "fn", fn)
    def __getattr__(self, name): return getattr(self.fn, name)
    def __setattr__(self, name, value): setattr(self.fn, name, value)
    def __call__(self, *args):
        marks.append(time.perf_counter()); out = self.fn(*args)
        marks.append(time.perf_counter()); return out

class TimedLibrary:
    def __init__(self, lib): object.__setattr__(self, "lib", lib)
    def __getattr__(self, name):
        attr = getattr(self.lib, name)
        return TimedCall(attr) if name in ("eng_cosimulate", "eng_simulate_me") else attr
    def __setattr__(self, name, value): setattr(self.lib, name, value)

proxy = []
def timed_library():  # loading the engine stays inside the measured call
    if not proxy: proxy.append(TimedLibrary(library()))
    return proxy[0]
cosim.library = me.library = timed_library

name = sys.argv[1]
out = []
for call in range(2):
    del marks[:]
    started = time.perf_counter()
    try:
        run_scene_full(name, stop_time=scene(name).step)
    except Exception:  # a figure that needs the whole run; the timing is taken
        pass
    out.append({"to_engine_s": marks[0] - started, "to_first_output_s": marks[1] - started})
print(json.dumps(out))
'''


def startup_times(scenes=STARTUP_SCENES, repeats: int = 5) -> dict:
    """Per scene, seconds from the run_scene call to the C engine's entry and to the end
    of its first output interval (an upper bound of "to the first step": it includes
    loading the FMUs, instantiating and initialising them, and integrating one output
    interval), for the first call in a fresh process (FMUs on disk, imports done) and
    the second call; best and median of `repeats` processes."""
    import statistics
    import subprocess
    import sys

    from assemblies.run import run_scene_full
    from assemblies.scenes import scene
    root = os.path.dirname(HERE)
    env = dict(os.environ, PYTHONPATH=root + os.pathsep + os.environ.get("PYTHONPATH", ""))
    result = {}
    for name in scenes:
        try:  # FMUs on disk and filed by recipe before any timing
            run_scene_full(name, stop_time=scene(name).step)
        except Exception:  # noqa: BLE001 - a figure that needs the whole run
            pass
        runs = []
        for _ in range(repeats):
            text = subprocess.run([sys.executable, "-c", _PROBE, name], env=env, cwd=root,
                                  capture_output=True, text=True, check=True).stdout
            runs.append(json.loads(text.strip().splitlines()[-1]))
        entry = {}
        for call, label in ((0, "first"), (1, "second")):
            for what in ("to_engine_s", "to_first_output_s"):
                values = [r[call][what] for r in runs]
                entry[f"{label}_{what}"] = {"best": min(values),
                                            "median": statistics.median(values)}
        result[name] = entry
    return result


def _beside_a_chain(name):
    """Scene `name` with a second driven spring-block beside it, connected to nothing
    the scene records."""
    from components import ConstantSpeed, SpringBlock

    from assemblies.scenes import SCENES

    def build():
        asm = SCENES[name].build()
        asm.add("extra_driver", ConstantSpeed(v=0.2))
        asm.add("extra_block", SpringBlock(m=2.0, mu_k=0.1, mu_s=0.2))
        asm.connect("extra_driver.flange", "extra_block.flange_a")
        return asm
    return build


def pruning_times(scenes=PRUNING_SCENES, modes=("cosim", "me"), repeats: int = 30) -> dict:
    """Best-of-`repeats` wall time of run_scene (a user's whole call, FMUs loaded) for
    the scene, the scene with an unrecorded chain beside it (pruned), and the same
    without pruning; the ratio pruned / alone is the target's (<= 1.10)."""
    import dataclasses

    from assemblies.run import run_scene
    from assemblies.scenes import SCENES
    result = {}
    for name in scenes:
        beside = f"{name}_beside_a_chain"
        SCENES[beside] = dataclasses.replace(SCENES[name], name=beside,
                                             build=_beside_a_chain(name))
        try:
            for mode in modes:
                def best(scene_name, **kw):
                    run_scene(scene_name, mode=mode, **kw)  # warm: built, loaded, planned
                    times = []
                    for _ in range(repeats):
                        started = time.perf_counter()
                        res = run_scene(scene_name, mode=mode, **kw)
                        times.append(time.perf_counter() - started)
                    return min(times), res
                alone, base = best(name)
                pruned, res = best(beside)
                unpruned, _ = best(beside, prune=False)
                same = all(np.array_equal(res[c], base[c]) for c in base.columns)
                result[f"{name} ({mode})"] = {
                    "alone_s": alone, "pruned_s": pruned, "not_pruned_s": unpruned,
                    "ratio": pruned / alone, "ratio_not_pruned": unpruned / alone,
                    "pruned": res.settings["pruned"], "identical_columns": bool(same)}
        finally:
            del SCENES[beside]
    return result


def startup_section(data: dict) -> list[str]:
    """RESULTS.md's lines for the figures of overhead.json."""
    out = ["## Before the first step, and what is not recorded", "",
           f"From `python -m benchmarks.overhead` ({data.get('when', '')}, "
           f"{data.get('machine', '')}); raw: `benchmarks/overhead.json`. Timings are "
           "best of N on a shared machine.", "",
           "Call to first step of a cached scene (target < 20 ms): from the `run_scene` call "
           "to the C engine's entry, and to the end of its first output interval (FMUs "
           "loaded, instantiated, initialised, one interval integrated: an upper bound). "
           "*First*: the first call in a fresh process, the FMUs on disk (imports done); "
           "*second*: the next call in that process. Best (median) of "
           f"{data.get('startup_repeats', '?')} processes.", "",
           "| scene | first: to engine [ms] | first: to first output [ms] "
           "| second: to first output [ms] | < 20 ms |", "|---|---|---|---|---|"]
    for name, e in data.get("startup", {}).items():
        first, second = e["first_to_first_output_s"], e["second_to_first_output_s"]
        out.append(f"| {name} | {e['first_to_engine_s']['best'] * 1e3:.1f} "
                   f"({e['first_to_engine_s']['median'] * 1e3:.1f}) "
                   f"| {first['best'] * 1e3:.1f} ({first['median'] * 1e3:.1f}) "
                   f"| {second['best'] * 1e3:.2f} ({second['median'] * 1e3:.2f}) "
                   f"| {'yes' if first['best'] < 0.020 else 'NO'} |")
    out += ["", "A scene with an unrecorded component (a second driven spring-block beside "
            "it) against the scene alone (target: within 10 %): best of "
            f"{data.get('pruning_repeats', '?')} whole `run_scene` calls.", "",
            "| scene (mode) | alone [ms] | with the chain, pruned [ms] | ratio "
            "| not pruned [ms] | ratio | identical columns |", "|---|---|---|---|---|---|---|"]
    for name, e in data.get("pruning", {}).items():
        out.append(f"| {name} | {e['alone_s'] * 1e3:.2f} | {e['pruned_s'] * 1e3:.2f} "
                   f"| {e['ratio']:.2f} | {e['not_pruned_s'] * 1e3:.2f} "
                   f"| {e['ratio_not_pruned']:.2f} | {'yes' if e['identical_columns'] else 'no'} |")
    return out + [""]


def main(argv=None) -> int:
    import argparse

    import platform
    ap = argparse.ArgumentParser(description="Time before the first step of a cached scene, "
                                             "and the cost of an unrecorded component.")
    ap.add_argument("--repeats", type=int, default=5, help="fresh processes per scene")
    ap.add_argument("--runs", type=int, default=30, help="calls per pruning figure (best of)")
    ap.add_argument("--json", default=JSON_PATH)
    args = ap.parse_args(argv)
    data = {"when": time.strftime("%Y-%m-%d"),
            "machine": f"{platform.node()}, {os.cpu_count()} cores",
            "startup_repeats": args.repeats, "pruning_repeats": args.runs,
            "startup": startup_times(repeats=args.repeats),
            "pruning": pruning_times(repeats=args.runs)}
    print("\n".join(startup_section(data)))
    with open(args.json, "w") as fh:
        json.dump(data, fh, indent=1)
    print(f"wrote {args.json}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
