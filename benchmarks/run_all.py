"""Refresh benchmarks/RESULTS.md, its plots and results.json: `python -m benchmarks.run_all [--quick]`.

Every figure in RESULTS.md is computed here from this run's records; the prose around
them says what each figure means, and which way each target went is decided by the data.
"""
from __future__ import annotations

import argparse
import json
import math
import platform
import re
import sys
import time
from pathlib import Path

import numpy as np
from scipy.linalg import eigh

from . import analysis, overhead, references
from .scenes import (BEAM_SIZES, FULL_TOLERANCES, QUICK_TOLERANCES, SCENES, beam_stop_time,
                     output_times)
from .suite import TIGHTEST, plot, run, table, write_json

HERE = Path(__file__).parent


def _ms(seconds):
    return "-" if seconds is None or not math.isfinite(seconds) else f"{seconds * 1e3:.1f} ms"


def _run_line(hit):
    if hit is None:
        return "no run reached the error"
    wall, method, tol, err = hit
    return f"`{method}` at tolerance {tol:.0e}: {_ms(wall)}, error {err:.1e}"


def _speedup_lines(records, calls, scene) -> list[str]:
    """The first round's FMU-vs-scipy speed-up (20× at error 1e-6) on one scene."""
    res = analysis.speedup_target(records, scene)
    head = f"- {scene}, fastest FMU path against the fastest scipy at error 1e-6 (was ≥ 20×): "
    if res["ratio"] is None:
        return [head + "one side never reached 1e-6 in this run."]
    n_out = len(output_times(scene)) - 1
    floor = n_out * (calls["doStep"] + calls["get"])
    wall = res["ours"][0]
    return [head + f"{res['ratio']:.1f}×; ours {_run_line(res['ours'])}, scipy "
            f"{_run_line(res['scipy'])}. One doStep per output interval is {n_out} doStep + "
            f"get calls through fmpy, {_ms(floor)} at the measured "
            f"{calls['doStep'] * 1e6:.1f} + {calls['get'] * 1e6:.1f} µs "
            f"({100 * min(1.0, floor / wall):.0f}% of the run)."]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--quick", action="store_true", help="three tolerances instead of eight")
    ap.add_argument("--scenes", nargs="*", default=list(SCENES), help="subset of scenes")
    ap.add_argument("--from-json", action="store_true",
                    help="rewrite RESULTS.md and plots from results.json and meta.json "
                         "(measures the call overheads and builds only where meta.json "
                         "lacks them)")
    args = ap.parse_args(argv)
    started = time.perf_counter()
    if args.from_json:
        # the target rows at the end are derived: recomputed from the records below
        records = [r for r in json.loads((HERE / "results.json").read_text()) if "method" in r]
        for r in records:  # JSON null stands for a failed run
            r["error"] = math.inf if r["error"] is None else r["error"]
            r["wall_s"] = math.nan if r["wall_s"] is None else r["wall_s"]
        meta = json.loads((HERE / "meta.json").read_text())
        args.scenes = list(dict.fromkeys(r["scene"] for r in records))
    else:
        records, meta = run(args.scenes, quick=args.quick)
        meta.update(quick=args.quick, elapsed_s=time.perf_counter() - started)
        write_json(records, HERE / "results.json")
    args.quick = meta["quick"]
    plots = {name: plot(records, name, HERE / "plots" / f"{name}.png") for name in args.scenes}
    # measured with the run they describe and kept with it, so a rewrite from the JSON
    # states the same numbers rather than a later, differently loaded machine's
    if "calls" not in meta or "builds" not in meta:
        meta["calls"] = overhead.call_overheads()
        meta["builds"] = overhead.build_times(overhead.default_build_set())
    (HERE / "meta.json").write_text(json.dumps(meta, indent=1))
    calls, builds = meta["calls"], meta["builds"]
    text = report(records, meta, calls, builds, plots, args, meta["elapsed_s"])
    (HERE / "RESULTS.md").write_text(text)
    print(table(records))
    print(f"wrote {HERE / 'RESULTS.md'}, {HERE / 'results.json'} and {len(plots)} plots")
    return 0


def kept_sections(path) -> list[str]:
    """The sections other benchmark commands wrote into RESULTS.md (a heading ending in
    "(issue N)", e.g. `python -m benchmarks.beam_scaling`), kept as they are: this run
    does not measure them, and must not drop them."""
    if not path.exists():
        return []
    kept, keep = [], False
    for line in path.read_text().splitlines():
        if line.startswith("## "):
            keep = re.search(r"\(issue \d+\)\s*$", line) is not None
        if keep:
            kept.append(line)
    return kept


def replace_section(path, lines: list[str]) -> None:
    """Write a section (`lines`, its heading first) into RESULTS.md in place of the one
    with the same heading, or before the closing "Known weaknesses" section."""
    text = path.read_text().splitlines() if path.exists() else []
    heading, out, i = lines[0], [], 0
    while i < len(text) and text[i] != heading:
        i += 1
    if i < len(text):  # replace: up to the next heading
        j = i + 1
        while j < len(text) and not text[j].startswith("## "):
            j += 1
        out = text[:i] + lines + text[j:]
    else:
        k = next((n for n, line in enumerate(text) if line.startswith("## Known weaknesses")),
                 len(text))
        out = text[:k] + lines + text[k:]
    path.write_text("\n".join(out) + "\n")



# when each set of targets was set: the first round's (commit 30feae1) and issue 10's
# (commit aa90acb) replaced its FMU-vs-scipy one; issue 13's beam section replaced its beam one
TARGETS_SET = {"first": "2026-11-22", "limit": "2026-11-23", "beam": "2026-11-23"}


def history(records, args, c) -> list[str]:
    """The first round's targets, no longer in force, with this run's numbers against them
    (for comparison with the round that set them: no verdicts)."""
    out = [f"## History: the first round's targets (set {TARGETS_SET['first']}, replaced)", "",
           f"Set by the first benchmark round on {TARGETS_SET['first']} and no longer targets: "
           "the FMU-through-fmpy speed-up over scipy (≥ 20×) was replaced on "
           f"{TARGETS_SET['limit']} by the public call against c_limit and scipy (issue 10: "
           "what a user runs is the engine, not one fmpy call per doStep); the assumed-modes "
           f"beam's cost ∝ N^1.5 on {TARGETS_SET['beam']} by the modal beam's N^1.2 "
           "(issue 13); the co-simulated moving_table within 3× of the Python monolithic "
           "master compared the two reference masters, which no target covers now. This "
           "run's numbers against them, for comparison only:", ""]
    for scene in ("stick_slip", "axle_pendulum"):
        if scene in args.scenes:
            out += _speedup_lines(records, c, scene)
    res = analysis.assembly_target(records) if "moving_table" in args.scenes else None
    if res is not None and res["ratio"] is not None:
        out.append(f"- moving_table, co-simulation against monolithic at the best error "
                   f"co-simulation reaches, {res['error']:.1e} (was ≤ 3×): {res['ratio']:.2f}×; "
                   f"{_run_line(res['cosim'])} against {_run_line(res['monolithic'])}. The "
                   "co-simulation error is set by the communication step, not the FMUs' "
                   "tolerance.")
    beam = analysis.beam_exponents(records, stop_time=beam_stop_time(args.quick))
    fmu = {n: min((b["cost_per_s"][n] for m, b in beam.items()
                   if m.startswith("fmu_") and n in b["cost_per_s"]), default=None)
           for n in BEAM_SIZES}
    fmu = {n: v for n, v in fmu.items() if v is not None}
    if len(fmu) >= 2:
        ns = np.array(sorted(fmu))
        slope = float(np.polyfit(np.log(ns), np.log([fmu[n] for n in ns]), 1)[0])
        omega_max = {}
        for n in BEAM_SIZES:  # K u = ω² M u
            M, K, _ = references.beam_matrices(n)
            omega_max[n] = float(np.sqrt(eigh(K, M, eigvals_only=True)[-1]))
        out += [f"- assumed-modes beam, cost per simulated second of the fastest FMU path at "
                f"1e-8 against N = {', '.join(map(str, ns))} (was ≤ N^1.5): N^{slope:.2f}. "
                "Its highest mode ω_max = " + ", ".join(f"{omega_max[n]:.3g}" for n in BEAM_SIZES)
                + " rad/s grows as N², the release from a static shape excites it, and each "
                "step's right-hand side is a dense (N+1)² product; modal coordinates (diagonal "
                "K) are what issue 13 measured instead.", "",
                "Cost per simulated second at tolerance 1e-8, fitted exponent of N:", "",
                "| method | " + " | ".join(f"N={n}" for n in BEAM_SIZES) + " | exponent |",
                "| --- | " + " | ".join("---" for _ in BEAM_SIZES) + " | --- |"]
        for method, b in beam.items():
            out.append(f"| {method} | " + " | ".join(_ms(b['cost_per_s'].get(n)) for n in BEAM_SIZES)
                       + f" | {b['exponent']:.2f} |")
    return out + [""]


def _flat_ends(records) -> list[str]:
    """A line naming the curves that end flat (the same error and work at their last two
    tolerances): records from before the suite followed such a curve on (suite.TIGHTEST)."""
    ends = {}
    for r in records:
        ends.setdefault((r["scene"], r["method"]), []).append(r)
    flat = [f"{scene} `{method}`" for (scene, method), rows in ends.items() if len(rows) >= 2
            and math.isfinite(rows[-1]["error"]) and all(rows[-1][k] == rows[-2][k] for k in ("error", "rhs_evals", "steps"))
            and rows[-1]["tolerance"] > TIGHTEST]
    if not flat:
        return []
    return ["- Curves that end flat, the same error and work at their last two tolerances "
            "(the tolerance never bound): " + ", ".join(flat) + ". These records predate the "
            "suite's following such a curve to tighter tolerances; the next run of "
            "`python -m benchmarks.run_all --quick` adds those points."]


def report(records, meta, calls, builds, plots, args, elapsed) -> str:
    key = calls
    c = {"doStep": next(v for k, v in key.items() if k.startswith("doStep")),
         "get": next(v for k, v in key.items() if k.startswith("getFloat64")),
         "numpy": next(v for k, v in key.items() if k.startswith("hand-written")),
         "me": next(v for k, v in key.items() if k.startswith("ME right")),
         "casadi": next(v for k, v in key.items() if k.startswith("CasADi"))}
    tols = QUICK_TOLERANCES if args.quick else FULL_TOLERANCES
    out = ["# Benchmarks: run time against error", "",
           f"Generated by `python -m benchmarks.run_all{' --quick' if args.quick else ''}` "
           f"on {platform.node() or 'this machine'} ({platform.processor() or platform.machine()}, "
           f"Python {sys.version.split()[0]}) in {elapsed:.0f} s. "
           + ("**Quick run**: tolerances " + ", ".join(f"{t:.0e}" for t in tols)
              + " only; the full sweep (1e-3 … 1e-10) is `python -m benchmarks.run_all`."
              if args.quick else "Full sweep: tolerances 1e-3 … 1e-10."),
           "", "Wall time is the integration alone: FMUs are built (and models joined) once "
           "before, and reported under *Build*. Error is max |value − reference| at the output "
           "times against each scene's independent reference. Raw records: `results.json`; "
           "one scene: `mechfmu bench SCENE [--quick] [--json FILE]`.", "",
           "Methods: `fmu_cs_dopri5`/`fmu_cs_rodas3` our Co-Simulation FMU (embedded solver 0/1) "
           "driven by fmpy, one doStep per output interval (which bounds the solver's step: "
           "where one step per doStep already meets the tolerance, its rows repeat, and the "
           f"sweep follows the method on to tighter tolerances, down to {TIGHTEST:g}, until "
           "the tolerance binds); `fmu_me_cvode` our Model Exchange FMU "
           "under `fmpy.simulate_fmu` (CVode; fmpy sets atol = rtol); `casadi_cvodes` CasADi's "
           "integrator on the same flat model (event-free scenes); `master_me`, `master_monolithic` "
           "(DOP853); `master_cosim_xM` the co-simulation master with M communication steps per "
           "output interval; `scipy_*` the hand-written numpy baseline "
           "(benchmarks/baselines.py) with terminal stick/slip events and restarts; "
           "`c_limit` the FMU's own generated C under the runtime's DOPRI5 and event "
           "location, free steps, dense output, no FMI and no Python in the loop "
           "(benchmarks/c_limit.c, one ctypes call per run); `engine_me`, "
           "`engine_monolithic` the compiled engine (assemblies.engine.me: the Model "
           "Exchange FMUs in one integrator, or the one composite FMU), called as a user "
           "calls it, FMUs built by an earlier call in the process.", ""]

    out += ["## Targets", "",
            "The targets in force: the public call against `c_limit` and scipy (issue 10, "
            f"set {TARGETS_SET['limit']}) below, and the beam's cost in modal coordinates "
            "(issue 13) in *Beam scaling (issue 13)*. The first round's targets, which these "
            "replaced, are under *History* with this run's numbers beside them.", ""]
    limits = analysis.limit_targets(records)
    if limits:
        out += [f"### Public call against c_limit and scipy at error {analysis.LIMIT_ERROR:g}", "",
                "Wall time at the error interpolated (log–log) on each method's curve.", "",
                "| scene | ratio | value | target | verdict | numerator | denominator |",
                "| --- | --- | --- | --- | --- | --- | --- |"]
        for r in limits:
            def side(x):
                return ("not reached" if x is None
                        else f"`{x['method']}` {x['wall_s'] * 1e3:.3g} ms")  # c_limit: 0.1 ms
            out.append(f"| {r['scene']} | {r['target']} | "
                       + ("-" if r["ratio"] is None else f"{r['ratio']:.2f}×")
                       + f" | {r['bound']} | **{'met' if r['met'] else 'missed'}** | "
                       f"{side(r['numerator'])} | {side(r['denominator'])} |")
        out += [f"- note: {n}" for n in dict.fromkeys(r["note"] for r in limits if r["note"])]
        out.append("")
    else:
        out += ["No scene of this run has `c_limit` records: no target to state.", ""]

    startup = HERE / "overhead.json"  # written by `python -m benchmarks.overhead`
    if startup.exists():
        out += overhead.startup_section(json.loads(startup.read_text()))
    out += ["## Overheads (fmpy through ctypes)", "", "| call | time per call |", "| --- | --- |"]
    out += [f"| {k} | {v * 1e6:.2f} µs |" for k, v in calls.items()]
    out += ["", "## Build (one-time, excluded from the wall times)", "",
            "| FMU | cold (empty cache) | cached |", "| --- | --- | --- |"]
    out += [f"| {k} | {v['cold_s']:.2f} s | {v['cached_s']:.2f} s |" for k, v in builds.items()]
    out += ["", "A cached component FMU is found from its recipe (its class, options and build "
                "settings: fmus/recipe.py) without flattening or generating code; a composite "
                "(monolithic) FMU has no recipe (its class is made per assembly), so its lookup "
                "flattens the joined model and generates its C code to hash it (the cached "
                "column); the masters here reuse one lookup per run "
                "(benchmarks.runners.builds_memoised).",
            "", "## Peak memory", "",
            "Process peak RSS (ru_maxrss) after each scene, cumulative: " +
            ", ".join(f"{k} {v:.0f} MB" for k, v in meta["peak_rss_mb"].items()) + ".", ""]
    quick_file = HERE / "quick_timings.json"
    if quick_file.exists():  # measured by hand, see the file's "command"
        quick = json.loads(quick_file.read_text())
        out += ["## Quick mode timings", "",
                f"`{quick['command']}`, {quick['machine']}; total is the whole command's wall "
                "time (Python start, setup with cached FMU lookups and references, the sweep, "
                "the plot); setup is the suite's own line. Target: under a minute per scene.", "",
                "| scene | total | setup (build lookup, reference) | note |",
                "| --- | --- | --- | --- |"]
        out += [f"| {k} | {v['total_s']:.1f} s | {v['setup_s']:.1f} s | {v.get('note', '')} |"
                for k, v in quick["scenes"].items()]
        out.append("")
    out += ["## Work–precision per scene", ""]
    for name, path in plots.items():
        rows = [r for r in records if r["scene"] == name]
        out += [f"### {name}", "", f"![{name}](plots/{path.name})", "",
                "| method | tolerance | error | wall | rhs evals | steps |",
                "| --- | --- | --- | --- | --- | --- |"]
        for r in rows:
            out.append(f"| {r['method']} | {r['tolerance']:.0e} | {r['error']:.2e} | "
                       f"{_ms(r['wall_s'])} | {r['rhs_evals'] if r['rhs_evals'] is not None else '-'} | "
                       f"{r['steps'] if r['steps'] is not None else '-'} |")
        out.append("")
    out += history(records, args, c)
    out += kept_sections(HERE / "RESULTS.md")
    out += ["## Known weaknesses of this suite", "",
            "- `coin_rolling`'s reference is the joined CasADi model at rtol 1e-13, so its "
            "errors are not independent of our equations; the hand-written numpy coin "
            "(benchmarks/baselines.py, Newton–Euler about C) agrees with that model's "
            "derivatives to round-off (tests/integration/test_bench.py)"
            + ("" if any(r["scene"] == "coin_rolling" and r["method"].startswith("scipy_")
                         for r in records)
               else ", but results.json predates it: its scipy rows come with the next full "
                    "run") + ".",
            *_flat_ends(records),
            "- `moving_table`'s reference is the monolithic master at rtol 1e-12, so the "
            "monolithic rows at tight tolerance compare with themselves.",
            "- `fmu_me_cvode` steps are not exposed by `fmpy.simulate_fmu` (null); its RHS "
            "count comes from fmpy's FMI call log. CasADi's counts are its integrator stats.",
            "- Wall times are the best of the runs repeated while they took under 0.3 s in "
            "all, at most 50 (a slower run is timed once), on a shared machine."]
    return "\n".join(out) + "\n"


if __name__ == "__main__":
    sys.exit(main())
