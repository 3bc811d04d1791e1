"""CoupledClutches (MSL Rotational.Examples) at tolerance 1e-6: our engine running the
composite FMU beside fmpy running the same composite FMU, and the scipy reference master.

    python -m benchmarks.msl_examples [--repeats N] [--shifted] [--json FILE]

The assembly's clutches hold their driven inertias, so a lock is an algebraic loop the
monolithic join solves; mode monolithic (the composite FMU) is the mode that runs it
exactly, so the comparison is of three runners of the same joined model: the engine (``run_scene`` in
mode monolithic, the user's call), fmpy's ``simulate_fmu`` on the same composite FMU
(Model Exchange with CVode, and Co-Simulation with our FMU's own solver), and the
joined CasADi model under scipy (``engine="reference"``). Times are CPU seconds of this
process (time.process_time), round-robin over the runners, least and spread over the
repeats; FMUs are built by an untimed first call. Each row keeps the largest error of
J1..J4.w against the event-driven reference of MSL's clutch law, solved on the run's
own output times (fmpy's ME rows include its event instants, where interpolating the
1 ms reference would add an error of its own).

Each mode of our engine has a row: ``me`` runs the separate Model Exchange FMUs in one
integrator, the loop solved by Newton at every evaluation (c/loop.c, the factors kept
while they converge); ``cosim`` runs the separate Co-Simulation FMUs (adaptive Jacobi to the
scene's communication tolerance, the loop solved at each communication point, a lock
across FMUs held to that tolerance). fmpy runs the same assembly of separate FMUs in the
reference me master (``engine="fmpy"``), which solves the loop at every evaluation, and
in the reference cosim master. The runners of the composite FMU run again with
output every 1.1 ms (``--shifted``): clutch1's torque has a kink where its normal force
cos(2 pi 0.2 t) crosses 0 at t = 1.25 s (no event marks it), and a step across it
carries an error the step's error estimate does not see (~3e-8 rad/s at 1 ms); fmpy's
CS communication points at every 1 ms land on 1.25 s exactly, the 1.1 ms points do not.
"""
from __future__ import annotations

import argparse
import json
import sys
import time

import numpy as np

from assemblies.scenes import scene
from assemblies.scenes.msl_rotational_references import coupled_clutches

TOLERANCE = 1e-6
COLUMNS = ("J1.w", "clutch1.w", "clutch2.w", "clutch3.w")


def _runners(step=None):
    """{row name: run() -> (time, J1..J4.w)} at output interval `step` (None: the
    scene's 1 ms)."""
    import fmpy

    from assemblies.engine.prepare import prepared_composite
    from assemblies.masters.monolithic import simulate_monolithic as reference
    from assemblies.run import run_scene
    sc = scene("coupled_clutches")
    step = sc.step if step is None else step
    suffix = "" if step == sc.step else f", output {step * 1e3:g} ms"
    asm = sc.build()
    _, fmu = prepared_composite(asm)
    names = list(COLUMNS)
    # the composite FMU is shared by every assembly of this structure: its values are set
    # per run, as the engine sets them (MSL's start values: J1.w = 10 rad/s)
    starts = {f"{inst}.{key}": value for inst, comp in asm.components.items()
              for key, value in comp.fmu_starts().items() if key != "solver"}

    def engine(mode, which="c"):
        def run():
            res = run_scene("coupled_clutches", mode=mode, tolerance=TOLERANCE, step=step,
                            engine=which)
            return np.asarray(res["time"]), np.column_stack([res[c] for c in COLUMNS])
        return run

    def fmpy_run(fmi_type):
        def run():
            res = fmpy.simulate_fmu(fmu.path, fmi_type=fmi_type, stop_time=sc.stop_time,
                                    output_interval=step, relative_tolerance=TOLERANCE,
                                    start_values=starts, output=names)
            return np.asarray(res["time"]), np.column_stack([res[c] for c in names])
        return run

    def scipy_reference():
        res = reference(sc.build(), sc.stop_time, step, TOLERANCE, record=list(COLUMNS))
        return np.asarray(res["time"]), np.column_stack([res[c] for c in COLUMNS])

    runners = {f"engine, mode {mode}{' (composite FMU)' if mode == 'monolithic' else ''}"
               f"{suffix}": engine(mode) for mode in ("monolithic", "me", "cosim")}
    runners[f"fmpy ME (composite FMU, CVode){suffix}"] = fmpy_run("ModelExchange")
    runners[f"fmpy CS (composite FMU){suffix}"] = fmpy_run("CoSimulation")
    if not suffix:
        runners["scipy reference master"] = scipy_reference
        # fmpy driving the separate FMUs: the reference me master, the loop solved per call
        runners["fmpy me master (separate FMUs)"] = engine("me", "fmpy")
        runners["fmpy cosim master (separate FMUs)"] = engine("cosim", "fmpy")
    return runners


def _error(t, w) -> float:
    """Largest |w - reference| over J1..J4, the reference solved on the run's own times
    (interpolating the 1 ms reference would add its own error, ~1e-6 rad/s)."""
    ref = coupled_clutches()  # the 1 ms grid's, solved once
    if len(t) != len(ref.t) or not np.array_equal(t, ref.t):
        ref = coupled_clutches(grid=t)
    if len(ref.t) != len(t):
        raise AssertionError(f"reference on {len(ref.t)} times, run on {len(t)}")
    return float(np.abs(w - ref.w).max())


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--json", default=None)
    ap.add_argument("--shifted", action="store_true",
                    help="also run the composite FMU's runners with output every 1.1 ms")
    args = ap.parse_args(argv)
    runners = _runners()
    if args.shifted:
        runners.update((k, v) for k, v in _runners(1.1e-3).items() if not k.startswith(
            ("engine, mode me", "engine, mode cosim")))
    errors, times, failed = {}, {name: [] for name in runners}, {}
    for name, run in list(runners.items()):  # untimed: builds, loads
        try:
            t, w = run()
        except Exception as exc:  # a runner that fails is a row saying so, not a crash
            failed[name] = f"{type(exc).__name__}: {str(exc).splitlines()[0]}"
            del runners[name]
            continue
        errors[name] = _error(t, w)
    for _ in range(args.repeats):
        for name, run in runners.items():
            start = time.process_time()
            run()
            times[name].append(time.process_time() - start)
    rows = [{"runner": n, "cpu_s_min": min(v), "cpu_s_max": max(v), "max_error_rad_s": errors[n]}
            for n, v in times.items() if v]
    base = rows[0]["cpu_s_min"]
    print(f"CoupledClutches, tolerance {TOLERANCE:g}, stop 1.5 s, {args.repeats} repeats "
          "(CPU s of this process)")
    print(f"{'runner':48s} {'min':>9s} {'max':>9s} {'x engine':>9s} {'max |w - ref|':>14s}")
    for r in rows:
        print(f"{r['runner']:48s} {r['cpu_s_min']:9.4f} {r['cpu_s_max']:9.4f} "
              f"{r['cpu_s_min'] / base:9.1f} {r['max_error_rad_s']:14.2e}")
    for name, why in failed.items():
        print(f"{name:48s} failed: {why}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"tolerance": TOLERANCE, "repeats": args.repeats, "rows": rows,
                       "failed": failed}, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
