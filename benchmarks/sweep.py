"""Throughput of parameter studies: runs per second of the same study of stick_slip (seed 9.2,
a grid over the driver's speed and the static friction) run

  (a) serially, a loop over the runs in this process (the sweep's own run function);
  (b) by ``assemblies.sweep.sweep`` on a local Dask cluster of 1, 2, ... worker processes;
  (c) the way fmpy's own example of a Dask parameter study does it
      (``fmpy/examples/parameter_variation.py``): a dask bag in chunks, one FMU3Slave per
      chunk, instantiated once and reset between runs, a doStep loop in Python that feeds
      the block's spring end, on the same SpringBlock FMU, on the same cluster;
  (d) the same bag calling ``fmpy.simulate_fmu`` once per run (what most users write).

and, beside them, (e) the machine's ceiling for the same number of workers: as many
independent processes, started beforehand, each a serial loop over its share of the runs,
with no scheduler at all. On a shared virtual machine two processes do not always get
two cores' worth of work done; "x ceiling" says how much of what the machine gave the
sweep kept, and "busy" what share of the workers' wall time went into runs.

Each approach is timed on a warm cluster (workers started, imports done, FMUs prepared by a
first study), best of N turns taken in one window of time per worker count; the cold time of
the first sweep (cluster start included) is reported beside it.

    python -m benchmarks.sweep [--quick] [--workers 1,2] [--json FILE] [--results]
"""
from __future__ import annotations

import argparse
import json
import math
import os
import platform
import sys
import time as wallclock
from pathlib import Path

import numpy as np

SCENE = "stick_slip"
STOP_TIME, STEP = 40.0, 0.1  # the scene's experiment; the fmpy loops step at its output step


def grid(quick: bool) -> dict:
    n = 10 if quick else 20
    return {"driver.v": np.linspace(0.03, 0.1, n), "block.mu_s": np.linspace(0.35, 0.6, n)}


def _best(fn, repeats: int) -> float:
    best = math.inf
    for _ in range(repeats):
        started = wallclock.perf_counter()
        fn()
        best = min(best, wallclock.perf_counter() - started)
    return best


# --- (c) fmpy's example, on our SpringBlock FMU ------------------------------------------------
def _block_fmu() -> dict:
    """The stick_slip block's FMU (the engine's prepared copy: built once, extracted once),
    as the FMU3Slave constructor and the loop need it."""
    from assemblies.engine.prepare import prepared
    from assemblies.scenes import scene
    asm = scene(SCENE).build()
    asm.resolve_causality()
    block = asm.component("block")
    fmu = prepared(block)
    vr = {name: fmu.variables[name][0] for name in fmu.variables}
    return {"path": fmu.path, "unzip_dir": fmu.unzip_dir, "guid": fmu.token,
            "identifier": fmu.cs_identifier, "vr": vr,
            "values": {**block.values, **block.starts}}


def fmpy_example_chunk(runs: list, fmu: dict) -> list:
    """fmpy's parameter_variation.simulate_fmu for our block: one slave per chunk, reset
    between runs, the spring end s = v t fed at every step; returns (index, first slip
    time) per run, the first step at which the block's mode left stick."""
    import fmpy
    from fmpy.fmi3 import FMU3Slave
    vr = fmu["vr"]
    slave = FMU3Slave(guid=fmu["guid"], unzipDirectory=fmu["unzip_dir"],
                      modelIdentifier=fmu["identifier"], instanceName="block")
    slave.instantiate()
    inputs = [vr["flange_a.s"], vr["flange_a.v"], vr["flange_a.a"]]
    names = [k for k in fmu["values"] if k in vr]
    out = []
    for i, values in runs:
        start = {**fmu["values"], "mu_s": values["block.mu_s"]}
        v = values["driver.v"]
        slave.reset()
        slave.setFloat64([vr[k] for k in names], [float(start[k]) for k in names])
        slave.enterInitializationMode(tolerance=1e-10, startTime=0.0, stopTime=STOP_TIME)
        slave.setFloat64(inputs, [0.0, v, 0.0])
        slave.exitInitializationMode()
        t, slip = 0.0, math.nan
        for k in range(round(STOP_TIME / STEP)):
            t = k * STEP
            slave.setFloat64(inputs, [v * t, v, 0.0])
            slave.doStep(t, STEP)
            if math.isnan(slip) and slave.getInt32([vr["mode"]])[0] != 0:
                slip = t + STEP
        out.append((i, slip))
    slave.terminate()
    slave.fmi3FreeInstance(slave.component)
    fmpy.freeLibrary(slave.dll._handle)  # as the example does
    return out


def fmpy_simulate_run(run, fmu: dict):
    """One run by fmpy.simulate_fmu: the scene's block values (the FMU's own defaults are
    the class's, g = 9.81) and the spring end's ramp given as an input table."""
    import fmpy
    i, values = run
    v = values["driver.v"]
    signals = np.array([(0.0, 0.0, v, 0.0), (STOP_TIME, v * STOP_TIME, v, 0.0)],
                       dtype=[("time", float), ("flange_a.s", float), ("flange_a.v", float),
                              ("flange_a.a", float)])
    result = fmpy.simulate_fmu(fmu["path"], fmi_type="CoSimulation", stop_time=STOP_TIME,
                               output_interval=STEP, relative_tolerance=1e-10, input=signals,
                               start_values={**fmu["values"], "mu_s": values["block.mu_s"]},
                               output=["x", "mode"])
    moving = np.nonzero(result["mode"] != 0)[0]
    return i, float(result["time"][moving[0]]) if len(moving) else math.nan


# --- the machine's own ceiling ------------------------------------------------------------
def _share(runs: list) -> None:
    """A serial loop over some of the runs (the sweep's run function), in a pool process."""
    from assemblies.sweep import as_scene, run_chunk
    run_chunk(as_scene(SCENE), runs, {})


def _processes(pool, runs: list, w: int) -> float:
    """Wall time of `w` processes, started and warmed beforehand, each looping over a
    w-th of the runs: what the machine gives w workers with no scheduler at all."""
    started = wallclock.perf_counter()
    for future in [pool.submit(_share, runs[k::w]) for k in range(w)]:
        future.result()
    return wallclock.perf_counter() - started


# --- the benchmark -------------------------------------------------------------------------
def default_repeats(quick: bool) -> int:
    return 3 if quick else 5


def run(quick: bool = False, workers: tuple[int, ...] = (1, 2), repeats: int | None = None):
    """The records of every approach. Each worker count is one window of time in which the
    serial loop, the independent processes, the sweep and fmpy's example take turns,
    `repeats` times, best of each: on a shared machine the speed drifts by tens of per
    cent over a minute, so a ratio is only taken between runs of one window."""
    import dask.bag as bag
    from concurrent.futures import ProcessPoolExecutor
    from multiprocessing import get_context

    from assemblies.sweep import chunk_sizes, dask_client, design, sweep
    params = grid(quick)
    runs = list(enumerate(design(params)))
    n = len(runs)
    repeats = repeats or default_repeats(quick)
    records = []

    def t1_error(pairs) -> float:
        """Largest |first slip - mu_s m g / (k v)| (seed 9.2, m = k = g = 1): each
        approach computes the study, not only spends time on it."""
        return max(abs(slip - runs[i][1]["block.mu_s"] / runs[i][1]["driver.v"])
                   for i, slip in pairs)

    def ours(table):
        return t1_error(zip(table["run"], table["t1"]))

    def serial():
        return sweep(SCENE, params, workers=0, progress=False)

    serial_error = ours(serial())
    fmu = _block_fmu()
    for w in workers:
        window = []

        def record(approach, wall, error, cold=None, note="", count=n, **extra):
            window.append({"approach": approach, "workers": w, "runs": count, "wall_s": wall,
                           "runs_per_s": count / wall, "t1_error": error, "cold_s": cold,
                           "note": note, **extra})

        started = wallclock.perf_counter()
        with dask_client(w) as client, \
                ProcessPoolExecutor(w, mp_context=get_context("spawn")) as pool:
            # a first study: workers import the package and prepare the FMUs
            error = ours(sweep(SCENE, params, scheduler=client, progress=False))
            cold = wallclock.perf_counter() - started
            _processes(pool, runs, w)  # the pool's processes start and prepare
            chunks = len(chunk_sizes(n, w))  # as many tasks as the sweep makes
            example = bag.from_sequence(runs, npartitions=chunks).map_partitions(
                fmpy_example_chunk, fmu)
            example_error = t1_error(example.compute())  # and warm: workers import fmpy
            few = runs[: max(2 * w, n // 8)]  # slow: a share of the runs, the rate is what counts
            simulate = bag.from_sequence(few, npartitions=chunks).map(fmpy_simulate_run, fmu)
            simulate_error = t1_error(simulate.compute())
            best = {key: math.inf for key in ("serial", "processes", "sweep", "example",
                                              "simulate")}
            busy = math.nan
            for _ in range(repeats):
                best["serial"] = min(best["serial"], _best(serial, 1))
                best["processes"] = min(best["processes"], _processes(pool, runs, w))
                t0 = wallclock.perf_counter()
                table = sweep(SCENE, params, scheduler=client, progress=False)
                wall = wallclock.perf_counter() - t0
                if wall < best["sweep"]:
                    # the workers' share of the wall time spent inside runs: what Dask
                    # itself costs, apart from how fast the machine runs each run
                    best["sweep"] = wall
                    busy = float(table["wall_s"].sum()) / (w * wall)
                best["example"] = min(best["example"], _best(example.compute, 1))
                best["simulate"] = min(best["simulate"], _best(simulate.compute, 1))
        record("serial loop in this process", best["serial"], serial_error)
        record("independent processes, no scheduler (ceiling)", best["processes"],
               serial_error, note="the machine's own limit for this many workers")
        record("mechfmu sweep (local Dask cluster)", best["sweep"], error, cold,
               "cold: cluster start and first study", busy=busy)
        record("fmpy example: bag of chunks, FMU3Slave reset per run", best["example"],
               example_error, note=f"fixed steps of {STEP} s fed from Python: t1 to a step")
        record("fmpy.simulate_fmu per run (dask bag)", best["simulate"], simulate_error,
               note=f"{len(few)} of the {n} runs; t1 to an output step", count=len(few))
        for r in window:
            r["vs_serial"] = r["runs_per_s"] / (n / best["serial"])
            r["vs_ceiling"] = r["runs_per_s"] / (n / best["processes"])
        records.extend(window)
    return records


def table(records) -> str:
    lines = [f"{'approach':<54} {'workers':>7} {'runs':>5} {'wall [s]':>9} {'runs/s':>8} "
             f"{'x serial':>8} {'x ceiling':>9} {'t1 error':>9} {'cold [s]':>9} {'busy':>5}"]
    for r in records:
        cold = f"{r['cold_s']:9.2f}" if r["cold_s"] is not None else f"{'':>9}"
        busy = f"{r['busy']:5.0%}" if "busy" in r else f"{'':>5}"
        lines.append(f"{r['approach']:<54} {r['workers']:>7} {r['runs']:>5} "
                     f"{r['wall_s']:9.3f} {r['runs_per_s']:8.1f} {r['vs_serial']:8.2f} "
                     f"{r['vs_ceiling']:9.2f} {r['t1_error']:9.1e} {cold} {busy}")
    return "\n".join(lines)


def results_section(data: dict, command: str) -> list[str]:
    """The RESULTS.md section of one invocation: the table and what it says."""
    records = data["records"]
    lines = ["## Parameter studies on Dask (issue 14)", "",
             f"`{command}`: {records[0]['runs']} runs of {data['scene']} (about "
             f"{1e3 * records[0]['wall_s'] / records[0]['runs']:.1f} ms each), best of "
             f"{data['repeats']} turns per worker count, on {data['cores']} cores at load "
             f"{data['load_at_start']:.1f}. \"x ceiling\" compares with as many independent "
             "processes with no scheduler, timed in the same window; \"busy\" is the share of "
             "the workers' wall time spent inside runs.", "", "```", table(records), "```", ""]
    for r in records:
        if r["approach"].startswith("mechfmu sweep") and r["workers"] > 1:
            lines.append(f"- {r['workers']} workers: {r['vs_serial']:.2f}x the serial loop, "
                         f"{r['vs_ceiling']:.2f} of what {r['workers']} independent processes "
                         f"get done in the same window, workers {r['busy']:.0%} busy.")
    if max(r["workers"] for r in records) < 16:
        lines.append("- `--workers 1,2,4,8,16` measures the scaling on a machine with as many "
                     "cores; none was lent to the sessions that ran this.")
    return lines + [""]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="100 runs instead of 400")
    parser.add_argument("--workers", default="1,2",
                        help="comma-separated worker counts (default 1,2; e.g. 1,2,4,8,16)")
    parser.add_argument("--repeats", type=int, help="best of this many (default 5, quick 3)")
    parser.add_argument("--json", metavar="FILE", help="write the records and the machine")
    parser.add_argument("--results", action="store_true",
                        help="write this run's section of benchmarks/RESULTS.md")
    args = parser.parse_args(argv)
    workers = tuple(int(w) for w in args.workers.split(","))
    repeats = args.repeats or default_repeats(args.quick)
    load = os.getloadavg()[0]
    records = run(args.quick, workers, repeats)
    print(f"{SCENE}: {records[0]['runs']} runs, best of {repeats}"
          f"; {os.cpu_count()} cores, load average {load:.1f} at the start")
    print(table(records))
    data = {"scene": SCENE, "cores": os.cpu_count(), "load_at_start": load,
            "repeats": repeats,
            "machine": platform.platform(), "records": records}
    if args.json:
        Path(args.json).write_text(json.dumps(data, indent=2) + "\n")
        print(f"wrote {args.json}")
    if args.results:
        from .run_all import HERE, replace_section
        command = " ".join(["python -m benchmarks.sweep", *(argv if argv is not None
                                                             else sys.argv[1:])])
        replace_section(HERE / "RESULTS.md", results_section(data, command))
        print(f"wrote its section of {HERE / 'RESULTS.md'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
