"""Default co-simulation against our own fixed steps and the composite FMU, at the same
error (issue 27).

    python -m benchmarks.cosim_fixed [--scenes NAME …] [--repeats N] [--json FILE]
                                     [--extrapolation 0|1|2|3]

Targets: on every joined scene the default co-simulation (adaptive, the default's input
extrapolation, events synchronised) costs no more than the cheapest fixed communication
step that reaches the same error (ratio <= 1), and at most 20x the composite FMU (the
assembly joined into one FMU, ``--mode monolithic``) at the error of its run at
tolerance 1e-4.

Every run is the compiled engine's master called on the scene's pruned assembly (what
``run_scene`` runs, without evaluating the figures), FMUs built and loaded by an untimed
first call. Fixed steps are h = step / n (n = 1, 2, 3, 4, 6, 8, …; the same extrapolation
as the adaptive runs, ``--extrapolation``, by default DEFAULT_SCHEME's), their rows at
every n-th step compared; n stops growing once a run is far dearer than every
co-simulation run. The error is :func:`benchmarks.joined.deviation` against the
composite FMU at 1e-12. Times are process CPU times (the benchmark's own heap frozen out
of the garbage collector, :func:`benchmarks.chain.cpu_seconds`), taken round-robin over
every run of a scene ``--repeats`` times (the machine is shared): the median, with the
spread (max - min) / median; each ratio with its range over the repeats (the extremes
of one run's times over the other's). "doSteps per step" counts: doSteps over communication
steps tried (accepted and rejected) and instances, 1 for a fixed step, 3 for step
doubling, less where unjudged steps follow an accepted estimate (COAST_STEPS, growing
to COAST_MAX while the error is steady, in assemblies/masters/adaptive.py) and where
the master evaluates a member itself with no doStep (a source from time, a spring as a
linear map). "fixed/comp": the cheapest fixed step at the cosim run's error over the
composite at that error, what co-simulation with no estimate at all would cost with
uniform steps; not a bound on adaptive steps, which spend them where the error is made
(benchmarks/cosim_bound.py measures the bound that holds). "interp.": the
cosim run over a fixed step of exactly its error (:func:`fixed_cost_at`).
"""
from __future__ import annotations

import argparse
import json
import math
import statistics
import sys

import numpy as np

from assemblies.engine.cosim import DEFAULT_SCHEME, cosimulate
from assemblies.engine.me import simulate_monolithic
from assemblies.pruning import prune_unrecorded
from assemblies.result import Result
from assemblies.scenes import scene as get_scene

from .chain import cpu_seconds
from .joined import REFERENCE_TOLERANCE, SCENES, deviation, reference

COSIM_TOLERANCES = (1e-2, 1e-3, 1e-4, 1e-5)
COMPOSITE_TOLERANCES = (1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10)
# h = step / n: about a factor sqrt(2) apart (integers, so that every n-th row is on the
# scene's output grid), so that "the cheapest fixed step at this error" is not a factor 2 off
DIVISIONS = (1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64, 96, 128, 192, 256, 384, 512)
COMPOSITE_TOL = 1e-4          # the cosim run compared with the composite FMU
TARGET_FIXED = 1.0
TARGET_COMPOSITE = 20.0


def _every_nth(result: Result, n: int) -> Result:
    return Result({c: np.asarray(result[c])[::n] for c in result.columns})


def runners(name: str, extrapolation: int = DEFAULT_SCHEME["extrapolation"]
            ) -> tuple[list[dict], list[dict], int]:
    """The runs of one scene as records with a `call` (returns the result on the scene's
    output grid), the fixed-step runs (finest last), and the number of instances."""
    sc = get_scene(name)
    asm, _ = prune_unrecorded(sc.build(), sc.record)
    common = dict(stop_time=sc.stop_time, tolerance=sc.tolerance, record=sc.record)

    def cosim(tol):
        return lambda: cosimulate(asm, step=sc.step, adaptive=True, tol=tol,
                                  extrapolation=extrapolation,
                                  **common)

    def fixed(n):
        return lambda: _every_nth(cosimulate(asm, step=sc.step / n, adaptive=False,
                                             extrapolation=extrapolation, **common), n)

    def composite(tol):
        return lambda: simulate_monolithic(asm, step=sc.step, **dict(common, tolerance=tol))

    runs = [{"mode": "cosim", "setting": t, "call": cosim(t)} for t in COSIM_TOLERANCES]
    runs += [{"mode": "composite", "setting": t, "call": composite(t)}
             for t in COMPOSITE_TOLERANCES]
    fixed_runs = [{"mode": "fixed", "setting": n, "call": fixed(n)} for n in DIVISIONS]
    return runs, fixed_runs, len(asm.components)


def _first(run: dict, ref, n_instances: int) -> None:
    """The untimed call: error, counts, and a first CPU time (to prune fixed steps)."""
    run["call"]()  # loads; untimed
    run["cpu_first"], result = cpu_seconds(run["call"])
    run["error"] = deviation(result, ref)
    s = result.settings
    if run["mode"] == "cosim":
        tried = s["steps"] + s.get("rejected", 0)
        run.update(do_steps=s["do_steps"], steps=s["steps"], rejected=s.get("rejected", 0),
                   doubled_steps=s.get("doubled_steps"),
                   do_steps_per_step=s["do_steps"] / max(1, tried) / n_instances)


def measure_scene(name: str, repeats: int,
                  extrapolation: int = DEFAULT_SCHEME["extrapolation"]) -> list[dict]:
    ref = reference(name)
    runs, fixed_runs, n_instances = runners(name, extrapolation)
    for run in runs:
        _first(run, ref, n_instances)
    cosims = [r for r in runs if r["mode"] == "cosim"]
    dearest = max(r["cpu_first"] for r in cosims)
    finest = min(r["error"] for r in cosims)
    for run in fixed_runs:  # finer until far dearer than any cosim run or finer than all
        _first(run, ref, n_instances)
        runs.append(run)
        if run["cpu_first"] > 3.0 * dearest or run["error"] < 0.5 * finest:
            break
    samples = {id(r): [] for r in runs}
    for _ in range(repeats):  # round-robin: the machine's load falls on every run alike
        for run in runs:
            samples[id(run)].append(cpu_seconds(run["call"])[0])
    out = []
    for run in runs:
        cpu = samples[id(run)] or [run["cpu_first"]]
        med = statistics.median(cpu)
        rec = {k: v for k, v in run.items() if k != "call"}
        rec.update(scene=name, cpu_s=med, spread=(max(cpu) - min(cpu)) / med if med else 0.0,
                   cpu_samples=cpu)
        out.append(rec)
    return out


def cheapest_at(records: list[dict], mode: str, error: float) -> dict | None:
    fits = [r for r in records if r["mode"] == mode and r["error"] <= error]
    return min(fits, key=lambda r: r["cpu_s"]) if fits else None


def ratio_range(a: dict, b: dict) -> tuple[float, float]:
    """The extremes of a's CPU time over b's across the repeats (round-robin)."""
    sa, sb = a.get("cpu_samples") or [a["cpu_s"]], b.get("cpu_samples") or [b["cpu_s"]]
    return min(sa) / max(sb), max(sa) / min(sb)


def fixed_cost_at(records: list[dict], error: float) -> float:
    """CPU time of a fixed step with exactly this error: log-log between the two fixed
    runs that bracket it (their error goes as a power of h, and so does their cost);
    NaN outside the runs measured. The cheapest run that reaches the error (what the
    target is judged on) can be up to one rung of DIVISIONS dearer than this."""
    pts = sorted((r["error"], r["cpu_s"]) for r in records
                 if r["mode"] == "fixed" and 0.0 < r["error"] < math.inf)
    for (e1, c1), (e2, c2) in zip(pts, pts[1:]):
        if e1 <= error <= e2 and e1 < e2:
            w = math.log(error / e1) / math.log(e2 / e1)
            return math.exp(math.log(c1) + w * math.log(c2 / c1))
    return math.nan


def compare(records: list[dict]) -> list[dict]:
    rows = []
    for r in records:
        if r["mode"] != "cosim":
            continue
        same = [c for c in records if c["scene"] == r["scene"]]
        fixed, comp = cheapest_at(same, "fixed", r["error"]), cheapest_at(same, "composite", r["error"])
        row = dict(scene=r["scene"], tol=r["setting"], error=r["error"], cpu_s=r["cpu_s"],
                   spread=r["spread"], do_steps_per_step=r["do_steps_per_step"],
                   fixed_n=fixed["setting"] if fixed else None,
                   fixed_cpu_s=fixed["cpu_s"] if fixed else None,
                   vs_fixed=r["cpu_s"] / fixed["cpu_s"] if fixed else math.nan,
                   composite_tol=comp["setting"] if comp else None,
                   composite_cpu_s=comp["cpu_s"] if comp else None,
                   vs_composite=r["cpu_s"] / comp["cpu_s"] if comp else math.nan)
        row["vs_fixed_range"] = ratio_range(r, fixed) if fixed else None
        row["vs_fixed_interpolated"] = r["cpu_s"] / fixed_cost_at(same, r["error"])
        row["vs_composite_range"] = ratio_range(r, comp) if comp else None
        # what a master with no estimate at all (fixed steps of the right length) costs
        # against the composite at this error: the bound of any step control on the
        # same coupling (zero-order / linear extrapolation, one doStep per step)
        row["fixed_vs_composite"] = (fixed["cpu_s"] / comp["cpu_s"] if fixed and comp
                                     else math.nan)
        # no fixed step reaches the error within the budget: fixed steps lose
        row["fixed_met"] = not fixed or row["vs_fixed"] <= TARGET_FIXED
        row["composite_met"] = (r["setting"] != COMPOSITE_TOL
                                or (comp is not None and row["vs_composite"] <= TARGET_COMPOSITE))
        rows.append(row)
    return rows


def report(rows: list[dict], records: list[dict]) -> str:
    lines = [f"{'scene':22s} {'tol':>6s} {'error':>9s} {'cpu ms':>9s} {'spread':>6s} "
             f"{'doSt/st':>7s} {'fixed (h=step/n)':>19s} {'vs fixed (range)':>20s} "
             f"{'interp.':>7s} {'composite':>19s} {'vs comp (range)':>22s} {'fixed/comp':>10s}"]

    def rng(value, bounds, width):
        text = f"{value:.2f}" + (f" ({bounds[0]:.2f}-{bounds[1]:.2f})" if bounds else "")
        return f"{text:>{width}s}"
    for r in rows:
        fixed = (f"{r['fixed_cpu_s'] * 1e3:8.1f} ms n={r['fixed_n']:<4d}" if r["fixed_n"]
                 else f"{'none reaches it':>19s}")
        comp = (f"{r['composite_cpu_s'] * 1e3:8.1f} ms @{r['composite_tol']:.0e}"
                if r["composite_tol"] else f"{'none reaches it':>19s}")
        lines.append(f"{r['scene']:22s} {r['tol']:6.0e} {r['error']:9.2e} {r['cpu_s'] * 1e3:9.1f} "
                     f"{r['spread']:6.2f} {r['do_steps_per_step']:7.2f} {fixed:>19s} "
                     f"{rng(r['vs_fixed'], r.get('vs_fixed_range'), 20)} "
                     f"{r.get('vs_fixed_interpolated', math.nan):7.2f} {comp:>19s} "
                     f"{rng(r['vs_composite'], r.get('vs_composite_range'), 22)} "
                     f"{r.get('fixed_vs_composite', math.nan):10.2f}"
                     f"{'' if r['fixed_met'] else '  SLOWER THAN FIXED'}"
                     f"{'' if r['composite_met'] else '  > 20x COMPOSITE'}")
    lines.append("")
    lines.append("fixed steps (error, CPU):")
    for r in records:
        if r["mode"] == "fixed":
            lines.append(f"  {r['scene']:22s} n={r['setting']:<4d} error {r['error']:.2e}, "
                         f"{r['cpu_s'] * 1e3:.1f} ms (spread {r['spread']:.2f})")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.cosim_fixed",
                                 description=__doc__.split("\n")[0])
    ap.add_argument("--scenes", nargs="+", default=list(SCENES), choices=SCENES)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--json", default="benchmarks/cosim_fixed.json")
    ap.add_argument("--extrapolation", type=int, choices=(0, 1, 2, 3),
                    default=DEFAULT_SCHEME["extrapolation"],
                    help="input extrapolation of every run, adaptive and fixed (default: "
                         "the default co-simulation's)")
    args = ap.parse_args(argv)
    records = []
    for name in args.scenes:
        records += measure_scene(name, args.repeats, args.extrapolation)
        print(f"  {name} measured", file=sys.stderr, flush=True)
    rows = compare(records)
    print(report(rows, records))
    with open(args.json, "w") as fh:
        json.dump({"records": records, "comparison": rows, "reference_tolerance":
                   REFERENCE_TOLERANCE, "extrapolation": args.extrapolation, "targets": {"vs_fixed": TARGET_FIXED,
                                                    "vs_composite": TARGET_COMPOSITE}},
                  fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
