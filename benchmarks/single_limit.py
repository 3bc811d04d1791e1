"""The public single-component call against the C limit and the best scipy (issue 27).

    python -m benchmarks.single_limit [--rounds 5] [--scenes stick_slip ...] [--json PATH]
    python -m benchmarks.single_limit --split [--scenes ...]   # where the public call's time goes

For stick_slip, axle_pendulum and coin_rolling: the compiled engine as a user calls it
(`engine_me`, `engine_monolithic`: simulate_me and simulate_monolithic, one call per run;
`prepared_me`, `prepared_monolithic`: what prepare_me and prepare_monolithic return,
prepared once per tolerance before the timing, as the FMUs are built: the calls of a
parameter study; the public call is the fastest of the four at each error, `simulate`
the faster of the first two), `c_limit` (benchmarks/c_limit.c: the same generated model
under plain DOPRI5) and scipy's solve_ivp on the hand-written right-hand sides, in numpy
and numba-compiled (`scipy_numba_*`, when numba is installed: the `bench` extra). Each
round runs every method at every tolerance, round-robin, and takes process CPU time (a
run shorter than MIN_CPU_S is repeated and averaged, so the clock's grain does not
count); in each round the CPU time at errors 1e-3, 1e-6 and 1e-9 is interpolated on
each method's curve (analysis.wall_at_error) and the ratios are taken within that round.
The table gives each ratio's median and its spread (least to greatest) over the rounds.
"""
from __future__ import annotations

import argparse
import json
import math
import statistics
import time
from pathlib import Path

from .analysis import wall_at_error
from .runners import max_error
from .scenes import SCENES

SCENE_NAMES = ("stick_slip", "axle_pendulum", "coin_rolling")
ERRORS = (1e-3, 1e-6, 1e-9)
TOLERANCES = tuple(10.0**-k for k in range(2, 13))   # 1e-2 ... 1e-12
SCIPY_TOLERANCES = tuple(10.0**-k for k in range(2, 12))
# solve_ivp's methods that can be the best here (Radau is the stiff one: never, and slow)
SCIPY_METHODS = ("RK45", "DOP853", "LSODA")
MIN_CPU_S = 0.01
LIMIT_MAX, SCIPY_MIN = 2.0, 50.0   # the targets


def _cpu(fn, tol):
    """(values, CPU seconds per run)."""
    runs, started = 0, time.process_time()
    while True:
        values = fn(tol, False)[0]
        runs += 1
        spent = time.process_time() - started
        if spent >= MIN_CPU_S:
            return values, spent / runs


def _prepared(case, mode: str):
    """The run of prepare_me or prepare_monolithic as a method (tol, count) -> (values,
    rhs_calls, steps): prepared here for every tolerance, so the timed calls are runs."""
    from assemblies.engine import me as engine
    prepare = engine.prepare_me if mode == "me" else engine.prepare_monolithic
    asm, column, times = case.masters.assembly, case.masters.column, case.times
    runs = {tol: prepare(asm, times[-1], times[1] - times[0], tol, record=[column])
            for tol in TOLERANCES}

    def call(tol, count):
        res = runs[tol]()
        if not count:  # the settings are made only when read (Result.settings)
            return res[column], None, None
        return (res[column], res.settings.get("rhs_calls"), res.settings.get("steps"))
    return call


SIMULATE = ("engine_me", "engine_monolithic")
PUBLIC = SIMULATE + ("prepared_me", "prepared_monolithic")


def _methods(case):
    names = ["c_limit", *SIMULATE]
    names += [f"scipy_{m}" for m in SCIPY_METHODS]
    names += [f"scipy_numba_{m}" for m in SCIPY_METHODS]
    methods = {n: case.methods[n] for n in names if n in case.methods}
    if "engine_monolithic" in methods:
        methods["prepared_me"] = _prepared(case, "me")
        methods["prepared_monolithic"] = _prepared(case, "monolithic")
    return methods


def _best(records, scene, methods, error):
    walls = [(wall_at_error(records, scene, m, error), m) for m in methods]
    walls = [w for w in walls if w[0] is not None]
    return min(walls) if walls else None


def measure(scene: str, rounds: int, log=print) -> list[dict]:
    """One row per (round, error): the CPU time of each side and the ratios."""
    case = SCENES[scene]()
    methods = _methods(case)
    for name, fn in methods.items():  # builds, loads, compiles: never timed
        fn(1e-6, False)
    rows = []
    for rnd in range(rounds):
        records = []
        for tol in TOLERANCES:
            for name, fn in methods.items():
                if name.startswith("scipy") and tol not in SCIPY_TOLERANCES:
                    continue
                try:
                    values, cpu = _cpu(fn, tol)
                    error = max_error(values, case.reference)
                except Exception as exc:  # a failed run is a point off the curve
                    log(f"  {scene} {name} at {tol:g} failed: {exc}")
                    error, cpu = math.inf, math.nan
                records.append({"scene": scene, "method": name, "tolerance": tol,
                                "error": error, "wall_s": cpu})
        for error in ERRORS:
            limit = _best(records, scene, ["c_limit"], error)
            public = _best(records, scene, list(PUBLIC), error)
            simulate = _best(records, scene, list(SIMULATE), error)
            scipy = _best(records, scene, [m for m in methods if m.startswith("scipy")], error)
            numba = _best(records, scene, [m for m in methods if m.startswith("scipy_numba")],
                          error)
            rows.append({"scene": scene, "round": rnd, "error": error,
                         "c_limit": limit, "public": public, "simulate": simulate,
                         "scipy": scipy, "numba": numba,
                         "public/c_limit": public[0] / limit[0] if public and limit else None,
                         "simulate/c_limit": simulate[0] / limit[0]
                         if simulate and limit else None,
                         "scipy/public": scipy[0] / public[0] if scipy and public else None,
                         "numba/public": numba[0] / public[0] if numba and public else None})
        log(f"  {scene}: round {rnd + 1}/{rounds} done")
    return rows


def _spread(values):
    values = [v for v in values if v is not None]
    if not values:
        return "not reached"
    return f"{statistics.median(values):.2f}x ({min(values):.2f}-{max(values):.2f})"


def table(rows) -> str:
    lines = ["| scene | error | public/c_limit (<= 2) | simulate/c_limit | "
             "best scipy/public (>= 50) | numba scipy/public | public [ms] | public call "
             "| c_limit [ms] | best scipy |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for scene in dict.fromkeys(r["scene"] for r in rows):
        for error in ERRORS:
            sel = [r for r in rows if r["scene"] == scene and r["error"] == error]

            def ms(side):
                got = [r[side][0] * 1e3 for r in sel if r[side]]
                return f"{statistics.median(got):.3f}" if got else "-"
            def most(side):
                got = [r[side][1] for r in sel if r.get(side)]
                return max(set(got), key=got.count) if got else "-"
            lines.append(f"| {scene} | {error:.0e} | {_spread(r['public/c_limit'] for r in sel)} "
                         f"| {_spread(r.get('simulate/c_limit') for r in sel)} "
                         f"| {_spread(r['scipy/public'] for r in sel)} "
                         f"| {_spread(r['numba/public'] for r in sel)} | {ms('public')} "
                         f"| {most('public')} | {ms('c_limit')} | {most('scipy')} |")
    return "\n".join(lines)


SPLIT_TOLERANCES = (1e-4, 1e-7, 1e-10)  # about errors 1e-3, 1e-6, 1e-9 on these scenes
SPLIT_REPEATS = 200


def split(scene: str, log=print) -> list[dict]:
    """Where the public call's time goes, per tolerance: its CPU time; the wall time of
    its C call alone (settings["engine_s"]) and so the Python around it; the same for
    the call prepare_monolithic returns; the public call with event_subsamples=0 (step
    ends only, as c_limit locates events); and c_limit. Round-robin, SPLIT_REPEATS runs
    each, the 20th percentile of each (a loaded machine's upper tail is other work)."""
    from assemblies.engine import me as engine
    case = SCENES[scene]()
    asm, column = case.masters.assembly, case.masters.column
    times = case.times
    rows = []
    for tol in SPLIT_TOLERANCES:
        def public(subsamples=engine.EVENT_SUBSAMPLES):
            return engine.simulate_monolithic(asm, times[-1], times[1] - times[0], tol,
                                              record=[column], event_subsamples=subsamples)
        prepared = engine.prepare_monolithic(asm, times[-1], times[1] - times[0], tol,
                                             record=[column])
        sides = {"public": public, "public_sub0": lambda: public(0), "prepared": prepared,
                 "c_limit": lambda: case.methods["c_limit"](tol, False)}
        for fn in sides.values():
            fn()
        spent = {name: [] for name in sides}
        c_call, c_prepared = [], []
        for _ in range(SPLIT_REPEATS):
            for name, fn in sides.items():
                started = time.process_time()
                result = fn()
                spent[name].append(time.process_time() - started)
                if name == "public":
                    c_call.append(result.settings["engine_s"])
                if name == "prepared":
                    c_prepared.append(result.settings["engine_s"])
        q = {name: statistics.quantiles(v, n=5)[0] for name, v in spent.items()}
        c = statistics.quantiles(c_call, n=5)[0]
        cp = statistics.quantiles(c_prepared, n=5)[0]
        row = {"scene": scene, "tolerance": tol, "public_cpu_s": q["public"], "c_call_s": c,
               "python_s": q["public"] - c, "prepared_cpu_s": q["prepared"],
               "prepared_python_s": q["prepared"] - cp,
               "prepared/c_limit": q["prepared"] / q["c_limit"],
               "public_sub0_cpu_s": q["public_sub0"],
               "c_limit_cpu_s": q["c_limit"], "public/c_limit": q["public"] / q["c_limit"],
               "public_sub0/c_limit": q["public_sub0"] / q["c_limit"],
               "python/c_limit": (q["public"] - c) / q["c_limit"]}
        rows.append(row)
        log(f"  {scene} {tol:g}: public {q['public'] * 1e6:.0f} us (C call {c * 1e6:.0f}, "
            f"Python {(q['public'] - c) * 1e6:.0f}), prepared {q['prepared'] * 1e6:.0f} "
            f"(Python {(q['prepared'] - cp) * 1e6:.0f}), event_subsamples=0 "
            f"{q['public_sub0'] * 1e6:.0f}, c_limit {q['c_limit'] * 1e6:.0f}: "
            f"{row['public/c_limit']:.2f}x, prepared {row['prepared/c_limit']:.2f}x, "
            f"{row['public_sub0/c_limit']:.2f}x")
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--scenes", nargs="+", default=list(SCENE_NAMES), choices=SCENE_NAMES)
    ap.add_argument("--json", type=Path, default=Path(__file__).with_name("single_limit.json"))
    ap.add_argument("--split", action="store_true",
                    help="where the public call's time goes (C call, Python, event sampling)")
    args = ap.parse_args(argv)
    if args.rounds < 1:
        ap.error("--rounds must be at least 1")
    if args.split:
        rows = [r for scene in args.scenes for r in split(scene)]
        args.json.with_name("single_split.json").write_text(json.dumps(rows, indent=1))
        return
    rows = []
    for scene in args.scenes:
        rows += measure(scene, args.rounds)
    print(table(rows))
    args.json.write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
