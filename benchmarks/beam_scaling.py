"""How the assumed-modes beam's cost grows with N (issue 13): build time and run cost.

Case: the undamped cantilever (EI = L = m = 1, sine basis, N sine terms, N + 1
coordinates) released at rest from its static shape under a tip load, w_tip(0) = 0.1 m,
run in the compiled engine (one Co-Simulation FMU, its embedded DOPRI5) with the tip
recorded every ``STEP`` s. For each N and formulation (``coordinates``):

- cold build [s]: flatten + C generation + gcc, into an empty FMU cache;
- the loosest FMU tolerance of 1e-4, 1e-5, ... 1e-12 at which the largest tip error over
  the run is <= 1e-6 m, against the exact solution of the same discretised model
  computed here with numpy (generalised eigenproblem K u = ω² M u of the assumed-modes
  M and K, modal superposition): independent of the modal code under test;
- run cost per simulated second at that tolerance: (best wall time of a run to 2 T minus
  best of a run to T) / T, which removes the fixed cost of loading the FMU (best of 3;
  the machine is shared, so single timings are noisy).

The fitted exponent p of cost ~ N^p is least squares in log-log over the rows with a
cost. The issue's target: p <= 1.2 for N = 4 ... 64 and N = 64 built in under 30 s.
The old formulation (``assumed``: dense M⁻¹K, unrolled by CasADi) is run for the small
N only: its build grows like N³ (minutes at N = 32).

    python -m benchmarks.beam_scaling [--quick] [--json FILE]

``--quick``: N = 4, 16, 64 (modal) and 4, 8 (assumed), T = 5 s (else T = 10 s).

``--methods`` (issue 27): the benchmark scenes' beam (benchmarks.scenes beam_N*: assumed
coordinates, the hard case, released from the static shape, w_tip(0) = 0.1 m, 2 s,
output every 0.01 s) in the engine's ``simulate_me`` with its default method (the
automatic choice) and with DOPRI5 and RODAS3 forced, against the C limit
(benchmarks/c_limit.py: the same generated C under a bare DOPRI5). Each at the loosest
tolerance 1e-4 ... 1e-12 whose largest tip error against the exact modal solution
(benchmarks.references) is <= 1e-6 m; then process CPU time, round-robin over the
methods, best and spread of ``--repeats``; ratios against the C limit and the automatic
method against the better of DOPRI5 and RODAS3, within the one run. Also the default
(modal) coordinates' default run for comparison. Targets: default <= 2x the C limit at
every N, automatic <= 1.2x the better forced method.

    python -m benchmarks.beam_scaling --methods [--sizes 4 8 16 32 64] [--repeats 5] [--json FILE]
"""
from __future__ import annotations

import argparse
import json
import math
import os
import tempfile
import time

import numpy as np
from scipy.linalg import eigh

from assemblies.assembly import Assembly
from components.bodies.beam import AssumedModesBeam
from fmus import build_fmu

W_TIP0 = 0.1
STEP = 0.01
TARGET = 1e-6
TOLERANCES = [10.0**-k for k in range(4, 13)]
FULL = {"modal": (4, 8, 16, 32, 64, 128), "assumed": (4, 8, 16)}
QUICK = {"modal": (4, 16, 64), "assumed": (4, 8)}


def exact_tip(beam: AssumedModesBeam, times: np.ndarray) -> np.ndarray:
    """w(L, t) of the discretised beam released at rest from its start coordinates."""
    mass, stiffness = beam.matrices()
    basis = beam.basis()
    a0 = np.array([beam.starts.get(n, 0.0) for n in basis.names])
    if beam.option("coordinates") == "modal":  # the same release, in the seed's coordinates
        shape = beam.static_shape(1.0)
        a0 = shape * (W_TIP0 / (basis.tip_value @ shape))
    eigenvalues, modes = eigh(stiffness, mass)
    amplitudes = modes.T @ mass @ a0
    tip = basis.tip_value @ modes
    return (tip * amplitudes) @ np.cos(np.sqrt(eigenvalues)[:, None] * times[None, :])


def _beam(n: int, coordinates: str) -> AssumedModesBeam:
    return AssumedModesBeam(basis="sine", n_modes=n, coordinates=coordinates, w_tip0=W_TIP0)


def _run(beam, stop: float, tolerance: float):
    from assemblies.engine.cosim import cosimulate
    asm = Assembly("beam_scaling")
    asm.add("beam", beam)
    started = time.perf_counter()
    res = cosimulate(asm, stop, STEP, tolerance, record=["beam.w_tip"])
    return time.perf_counter() - started, np.asarray(res["time"]), np.asarray(res["beam.w_tip"])


def _best(beam, stop, tolerance, repeats=3) -> float:
    return min(_run(beam, stop, tolerance)[0] for _ in range(repeats))


def measure(n: int, coordinates: str, stop: float) -> dict:
    beam = _beam(n, coordinates)
    with tempfile.TemporaryDirectory(prefix="beam-scaling-") as cache:
        previous = os.environ.get("MECHFMU_CACHE")
        os.environ["MECHFMU_CACHE"] = cache
        try:
            started = time.perf_counter()
            build_fmu(beam)
            build = time.perf_counter() - started
        finally:
            if previous is None:
                del os.environ["MECHFMU_CACHE"]
            else:
                os.environ["MECHFMU_CACHE"] = previous
    build_fmu(beam)  # into the ordinary cache, where the runs find it
    row = {"N": n, "coordinates": coordinates, "states": len(beam.states),
           "build_s": build, "tolerance": None, "tip_error": None, "cost_per_s": None}
    for tolerance in TOLERANCES:
        _, times, tip = _run(beam, 2 * stop, tolerance)
        error = float(np.abs(tip - exact_tip(beam, times)).max())
        if error <= TARGET:
            row["tolerance"], row["tip_error"] = tolerance, error
            long_run, short_run = _best(beam, 2 * stop, tolerance), _best(beam, stop, tolerance)
            row["cost_per_s"] = max(long_run - short_run, 1e-9) / stop
            break
    return row


def exponent(rows: list[dict], low: int = 4, high: int = 64) -> float:
    pts = [(r["N"], r["cost_per_s"]) for r in rows
           if r["cost_per_s"] and low <= r["N"] <= high]
    if len(pts) < 2:
        return math.nan
    n, cost = np.log([p[0] for p in pts]), np.log([p[1] for p in pts])
    return float(np.polyfit(n, cost, 1)[0])


METHOD_SIZES = (4, 8, 16, 32, 64)
METHOD_TARGET = 1e-6
ENGINE_METHODS = ("auto", "DOPRI5", "DOP853", "RODAS3")


def _method_runners(n: int) -> tuple[dict, dict]:
    """{method: run(tol) -> (cpu seconds, tip error, settings)} for one N."""
    from assemblies.engine.me import simulate_me
    from benchmarks import references
    from benchmarks.c_limit import CLimit
    from benchmarks.scenes import GRIDS, output_times
    stop = GRIDS["beam"][0]
    times = output_times("beam_N", False)
    _, w_tip = references.beam_free_vibration(n, W_TIP0)
    exact = w_tip(times)
    runners = {}
    for coordinates in ("assumed", "modal"):
        beam = AssumedModesBeam(name="beam", basis="sine", n_modes=n, w_tip0=W_TIP0,
                                coordinates=coordinates)
        asm = Assembly(f"beam_N{n}")
        asm.add("beam", beam)
        for method in ENGINE_METHODS if coordinates == "assumed" else ("auto",):
            def run(tol, asm=asm, method=method):
                started = time.process_time()
                res = simulate_me(asm, stop, GRIDS["beam"][1], tol, record=["beam.w_tip"],
                                  method=None if method == "auto" else method)
                cpu = time.process_time() - started
                tip = np.asarray(res["beam.w_tip"])
                return cpu, float(np.abs(tip - exact).max()), dict(res.settings)
            key = method if coordinates == "assumed" else "auto (modal)"
            runners[key] = run
    limit = CLimit(AssumedModesBeam(name="beam", basis="sine", n_modes=n, w_tip0=W_TIP0,
                                    coordinates="assumed"), "w_tip")

    def c_limit(tol):
        started = time.process_time()
        values, rhs, steps = limit.column(times, tol)
        cpu = time.process_time() - started
        return cpu, float(np.abs(values - exact).max()), {"rhs_calls": rhs, "steps": steps}
    runners["c_limit"] = c_limit
    return runners


def measure_methods(n: int, repeats: int) -> dict:
    runners = _method_runners(n)
    chosen = {}
    for name, run in runners.items():
        for tol in TOLERANCES:
            _, error, settings = run(tol)  # also the untimed first run: plan, load
            if error <= METHOD_TARGET:
                chosen[name] = {"tolerance": tol, "tip_error": error,
                                "steps": settings.get("steps"),
                                "jacobians": settings.get("jacobians"),
                                "method_switches": settings.get("method_switches")}
                break
    cpu = {name: [] for name in chosen}
    for _ in range(repeats):  # round-robin: the machine's load falls on every method alike
        for name in chosen:
            cpu[name].append(runners[name](chosen[name]["tolerance"])[0])
    for name, row in chosen.items():
        row["cpu_s"] = min(cpu[name])
        row["cpu_spread"] = max(cpu[name]) / max(min(cpu[name]), 1e-9)
    limit = chosen.get("c_limit", {}).get("cpu_s")
    better = min((chosen[m]["cpu_s"] for m in ("DOPRI5", "RODAS3") if m in chosen),
                 default=None)
    ratios = {}
    if limit:
        ratios.update({f"{m}/c_limit": chosen[m]["cpu_s"] / limit for m in chosen
                       if m != "c_limit"})
    if better and "auto" in chosen:
        ratios["auto/better forced"] = chosen["auto"]["cpu_s"] / better
    return {"N": n, "methods": chosen, "ratios": ratios}


def main_methods(sizes, repeats: int, json_path: str | None) -> int:
    print(f"beam_N (assumed coordinates), engine simulate_me, 2 s, tip error <= "
          f"{METHOD_TARGET:g} m, process CPU time, best of {repeats} round-robin")
    print(f"{'N':>3} {'method':<13} {'tol':>6} {'tip err':>8} {'steps':>7} {'jacs':>6} "
          f"{'switch':>6} {'cpu [s]':>8} {'spread':>6} {'/c_limit':>8}")
    rows = []
    for n in sizes:
        row = measure_methods(n, repeats)
        rows.append(row)
        limit = row["methods"].get("c_limit", {}).get("cpu_s")
        for name, m in row["methods"].items():
            ratio = f"{m['cpu_s'] / limit:.2f}" if limit else "-"
            print(f"{n:>3} {name:<13} {m['tolerance']:>6.0e} {m['tip_error']:>8.1e} "
                  f"{m['steps'] or 0:>7} {m['jacobians'] or 0:>6} {m['method_switches'] or 0:>6} "
                  f"{m['cpu_s']:>8.4f} {m['cpu_spread']:>6.2f} {ratio:>8}", flush=True)
        if "auto/better forced" in row["ratios"]:
            print(f"{n:>3} automatic / better of DOPRI5, RODAS3: "
                  f"{row['ratios']['auto/better forced']:.2f}", flush=True)
    if json_path:
        with open(json_path, "w") as fh:
            json.dump({"rows": rows, "target_tip_error": METHOD_TARGET, "repeats": repeats,
                       "clock": "process CPU time"}, fh, indent=1)
    return 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.beam_scaling",
                                 description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer N, a shorter run")
    ap.add_argument("--json", help="write the measurements to this file")
    ap.add_argument("--methods", action="store_true",
                    help="default, DOPRI5, RODAS3 in simulate_me against the C limit (issue 27)")
    ap.add_argument("--sizes", type=int, nargs="+", default=list(METHOD_SIZES),
                    help="N for --methods")
    ap.add_argument("--repeats", type=int, default=5, help="timed runs of each, for --methods")
    args = ap.parse_args(argv)
    if args.methods:
        return main_methods(args.sizes, args.repeats, args.json)
    sizes, stop = (QUICK, 5.0) if args.quick else (FULL, 10.0)
    rows = []
    print(f"beam free vibration, w_tip(0) = {W_TIP0} m, output every {STEP} s, "
          f"tip error <= {TARGET:g} m against the exact modal solution (numpy)")
    print(f"{'coordinates':<11} {'N':>4} {'states':>6} {'build [s]':>10} {'tolerance':>10} "
          f"{'tip error':>10} {'cost [ms per s]':>16}")
    for coordinates, ns in sizes.items():
        for n in ns:
            row = measure(n, coordinates, stop)
            rows.append(row)
            cost = "-" if row["cost_per_s"] is None else f"{1e3 * row['cost_per_s']:.3f}"
            tol = "none" if row["tolerance"] is None else f"{row['tolerance']:.0e}"
            err = "-" if row["tip_error"] is None else f"{row['tip_error']:.1e}"
            print(f"{coordinates:<11} {n:>4} {row['states']:>6} {row['build_s']:>10.1f} "
                  f"{tol:>10} {err:>10} {cost:>16}", flush=True)
    fits = {c: exponent([r for r in rows if r["coordinates"] == c]) for c in sizes}
    for coordinates, p in fits.items():
        print(f"fitted exponent of cost ~ N^p, N = 4 ... 64, {coordinates}: p = {p:.2f}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"rows": rows, "exponents": fits, "stop_time": stop, "step": STEP,
                       "target_tip_error": TARGET}, fh, indent=1)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
