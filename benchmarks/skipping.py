"""What a run skips (issue 13): a stiff law found by the solver itself, and no steps once
nothing moves.

    python -m benchmarks.skipping [--repeats N] [--json FILE]

1. ``mechfmu run stick_slip --param block.friction=smooth|tanh --param block.eps=1e-8``
   through ``run_scene`` (the command's call): the engine's integration time (wall_s:
   without building or loading FMUs), communication steps, and whether every figure
   passes against exact Coulomb friction within what the law allows. Target: under 1 s
   of integration.
2. ``friction_damping`` to 20 s and to 1e4 s (the block sticks for good at 5 pi s) in
   each mode: the whole ``run_scene`` call, best of N, and the ratio. Target: the
   second at most 1.5 x the first. The 1e4 s run still writes its 1e5 output rows.
"""
from __future__ import annotations

import argparse
import json
import time

from assemblies.run import run_scene_full

from .run_all import HERE, replace_section

RESULTS = HERE / "RESULTS.md"

LAWS = ("smooth", "tanh")
EPS = 1e-8
MODES = ("cosim", "me", "monolithic")
TARGET_SMOOTH_S = 1.0
TARGET_REST_RATIO = 1.5


def smooth_laws(repeats: int) -> list[dict]:
    rows = []
    for law in LAWS:
        params = {"block.friction": law, "block.eps": EPS}
        run_scene_full("stick_slip", params=params)  # builds and loads; untimed
        runs = [run_scene_full("stick_slip", params=params) for _ in range(repeats)]
        best = min(runs, key=lambda r: r.result.settings["wall_s"])
        rows.append({"law": law, "eps": EPS, "integration_s": best.result.settings["wall_s"],
                     "steps": best.result.settings["steps"],
                     "figures_pass": all(f.passed for f in best.figures),
                     "figures": {f.name: [f.measured, f.reference, f.accuracy]
                                 for f in best.figures},
                     "meets_target": best.result.settings["wall_s"] < TARGET_SMOOTH_S})
    return rows


def _call(mode: str, stop_time: float, repeats: int) -> tuple[float, dict]:
    run_scene_full("friction_damping", stop_time=stop_time, mode=mode)
    best, settings = float("inf"), {}
    for _ in range(repeats):
        started = time.perf_counter()
        run = run_scene_full("friction_damping", stop_time=stop_time, mode=mode)
        elapsed = time.perf_counter() - started
        if elapsed < best:
            best, settings = elapsed, run.result.settings
    return best, settings


def at_rest(repeats: int) -> list[dict]:
    rows = []
    for mode in MODES:
        short, s_settings = _call(mode, 20.0, repeats)
        long_, l_settings = _call(mode, 1e4, repeats)
        work = "do_steps" if "do_steps" in s_settings else "steps"
        rows.append({"mode": mode, "call_20_s": short, "call_1e4_s": long_,
                     "ratio": long_ / short, "steps_20": s_settings[work],
                     "steps_1e4": l_settings[work], "at_rest_from": l_settings["at_rest_from"],
                     "meets_target": long_ / short <= TARGET_REST_RATIO})
    return rows


def results_section(data: dict, command: str) -> list[str]:
    """The RESULTS.md section of these figures (its heading keeps it through run_all)."""
    out = ["## Skipping what a run does not need (issue 13)", "",
           f"`{command}` (best of the repeats; integration = the engine's wall time, without "
           "building or loading FMUs).", "",
           f"| stick_slip, law (eps = {EPS:g}) | integration [s] | steps | figures vs exact "
           "Coulomb, within what the law allows |", "| --- | --- | --- | --- |"]
    out += [f"| {r['law']} | {r['integration_s']:.4f} | {r['steps']} | "
            f"{'all pass' if r['figures_pass'] else 'FAIL'} |" for r in data["smooth_laws"]]
    out += ["", "| friction_damping, mode | call to 20 s [ms] | call to 1e4 s [ms] | ratio "
            "(target <= 1.5) | steps (20 s / 1e4 s) | at rest from [s] |",
            "| --- | --- | --- | --- | --- | --- |"]
    out += [f"| {r['mode']} | {1e3 * r['call_20_s']:.2f} | {1e3 * r['call_1e4_s']:.2f} | "
            f"{r['ratio']:.2f} | {r['steps_20']} / {r['steps_1e4']} | {r['at_rest_from']:.6g} |"
            for r in data["at_rest"]]
    return out + [""]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--json", default="benchmarks/skipping.json")
    args = parser.parse_args(argv)
    laws, rest = smooth_laws(args.repeats), at_rest(args.repeats)
    print(f"stick_slip with a smooth law, eps = {EPS:g} (target: under {TARGET_SMOOTH_S:g} s)")
    print(f"{'law':<8}{'integration [s]':>17}{'steps':>8}  figures")
    for r in laws:
        print(f"{r['law']:<8}{r['integration_s']:>17.4f}{r['steps']:>8}  "
              f"{'all pass' if r['figures_pass'] else 'FAIL'}")
    print(f"\nfriction_damping to 20 s and to 1e4 s (target: ratio <= {TARGET_REST_RATIO:g})")
    print(f"{'mode':<12}{'20 s [ms]':>11}{'1e4 s [ms]':>12}{'ratio':>8}{'steps':>14}  at rest from")
    for r in rest:
        print(f"{r['mode']:<12}{1e3 * r['call_20_s']:>11.2f}{1e3 * r['call_1e4_s']:>12.2f}"
              f"{r['ratio']:>8.2f}{r['steps_20']:>7}/{r['steps_1e4']:<6}  {r['at_rest_from']:.6g} s")
    data = {"smooth_laws": laws, "at_rest": rest}
    with open(args.json, "w") as f:
        json.dump(data, f, indent=1)
    replace_section(RESULTS, results_section(data, "python -m benchmarks.skipping"))
    print(f"\nwrote {args.json} and its section of {RESULTS}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
