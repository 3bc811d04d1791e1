"""A joined scene in ``me`` against its composite FMU, CPU time round-robin (issue 27).

    python -m benchmarks.me_composite [--scene two_block_belt] [--tolerances 1e-5 1e-7 1e-9]
                                      [--rounds 7] [--json FILE]

The target: ``two_block_belt`` in me within 5x of its composite at 1e-5, 1e-7 and 1e-9,
with margin (<= 4x). At each solver tolerance both paths run the scene's assembly,
experiment and recorded columns through the engine's public calls (``simulate_me``, and
``simulate_monolithic``: the composite FMU run by the same engine; FMUs built by an
untimed first call, the scene's figures not evaluated), in rounds that time each path
once (so a change in the shared machine's load touches both alike), with the process
CPU time of the call. The ratio is me / composite per round; the row gives
its median and its spread (lowest..highest over the rounds), and each path's error
against the composite FMU at tolerance 1e-12 (benchmarks.joined.deviation: largest
weighed deviation of every recorded output at every output point), so that a cheaper
path that is also less accurate shows as such.
"""
from __future__ import annotations

import argparse
import json
import sys

import numpy as np

from assemblies.engine import simulate_me, simulate_monolithic
from assemblies.scenes import SCENES

from .chain import cpu_seconds
from .joined import deviation, reference

TOLERANCES = (1e-5, 1e-7, 1e-9)
TARGET, MARGIN = 5.0, 4.0
PATHS = {"me": simulate_me, "composite": simulate_monolithic}


def measure(scene: str, tolerances=TOLERANCES, rounds: int = 7, log=print) -> dict:
    ref, sc = reference(scene), SCENES[scene]
    rows = []
    for tol in tolerances:
        calls = {path: (lambda fn=fn, tol=tol: fn(sc.build(), sc.stop_time, sc.step, tol,
                                                   record=sc.record))
                 for path, fn in PATHS.items()}
        errors = {path: deviation(call(), ref) for path, call in calls.items()}  # untimed: builds
        cpu = {path: [] for path in calls}
        for _ in range(rounds):
            for path, call in calls.items():
                cpu[path].append(cpu_seconds(call)[0])
        ratios = np.array(cpu["me"]) / np.array(cpu["composite"])
        row = {"tolerance": tol, "error": errors,
               "cpu_s": {p: float(min(v)) for p, v in cpu.items()},
               "cpu_all_s": cpu, "ratio_median": float(np.median(ratios)),
               "ratio_lo": float(ratios.min()), "ratio_hi": float(ratios.max())}
        row["target_met"] = row["ratio_hi"] <= TARGET
        row["margin_met"] = row["ratio_median"] <= MARGIN
        rows.append(row)
        log(f"  {scene} tol {tol:.0e}: me {row['cpu_s']['me'] * 1e3:.2f} ms, composite "
            f"{row['cpu_s']['composite'] * 1e3:.2f} ms, ratio {row['ratio_median']:.2f} "
            f"({row['ratio_lo']:.2f}..{row['ratio_hi']:.2f})")
    return {"scene": scene, "rounds": rounds, "clock": "process CPU time (time.process_time)",
            "reference": "composite FMU at tolerance 1e-12", "rows": rows,
            "target": TARGET, "margin": MARGIN}


def report(data: dict) -> str:
    lines = [f"{data['scene']}: me / composite FMU (engine), CPU time of one run, "
             f"{data['rounds']} rounds round-robin; ratio median (lowest..highest); error vs "
             f"{data['reference']}",
             f"{'tol':>7s} {'me ms':>8s} {'comp ms':>8s} {'ratio':>7s} {'spread':>13s} "
             f"{'me error':>9s} {'comp err':>9s}  <= {data['target']:g}x  <= {data['margin']:g}x"]
    for r in data["rows"]:
        lines.append(f"{r['tolerance']:7.0e} {r['cpu_s']['me'] * 1e3:8.2f} "
                     f"{r['cpu_s']['composite'] * 1e3:8.2f} {r['ratio_median']:7.2f} "
                     f"{r['ratio_lo']:6.2f}..{r['ratio_hi']:<5.2f} {r['error']['me']:9.1e} "
                     f"{r['error']['composite']:9.1e}  {'met' if r['target_met'] else 'MISSED':6s}"
                     f"{'met' if r['margin_met'] else 'MISSED'}")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.me_composite",
                                 description=__doc__.split("\n")[0])
    ap.add_argument("--scene", default="two_block_belt")
    ap.add_argument("--tolerances", type=float, nargs="+", default=list(TOLERANCES))
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--json", help="write the measurements to this file")
    args = ap.parse_args(argv)
    data = measure(args.scene, args.tolerances, args.rounds)
    print(report(data))
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(data, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
