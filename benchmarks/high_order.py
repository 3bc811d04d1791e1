"""DOP853 against DOPRI5 in the engine, counted in evaluations (issue 27).

    python -m benchmarks.high_order [--scenes stick_slip ...] [--json FILE]

For each scene of benchmarks/single_limit.py, both explicit methods (``method="DOPRI5"``
and ``"DOP853"``) run the scene's prepared monolithic call at tolerances 1e-4 ... 1e-12;
each run's error is its largest deviation from the scene's reference
(benchmarks.runners.max_error). The table gives, at tolerances 1e-6, 1e-7 and 1e-9,
DOP853's evaluations of the right-hand side over those DOPRI5 needs for the same error
(log-log interpolation on DOPRI5's curve). Counts, not times: the same on any machine,
and what engine.h's ENG_HIGH_ORDER_TOLERANCE is chosen from (DOP853 pays where the
ratio is under 1 on every scene).
"""
from __future__ import annotations

import argparse
import json
import math

from .runners import max_error
from .scenes import SCENES
from .single_limit import SCENE_NAMES

TOLERANCES = tuple(10.0**-k for k in range(4, 13))
SHOWN = (1e-6, 1e-7, 1e-9)
METHODS = ("DOPRI5", "DOP853")


def curve(scene: str, method: str) -> list[tuple[float, float, int]]:
    """(tolerance, error, evaluations) of one method over TOLERANCES."""
    from assemblies.engine import me as engine
    case = SCENES[scene]()
    asm, column, times = case.masters.assembly, case.masters.column, case.times
    points = []
    for tol in TOLERANCES:
        res = engine.prepare_monolithic(asm, times[-1], times[1] - times[0], tol,
                                        record=[column], method=method)()
        points.append((tol, max_error(res[column], case.reference), res.settings["rhs_calls"]))
    return points


def evaluations_at(points, error: float) -> float | None:
    """The evaluations a curve needs for `error`, interpolated in log-log between the two
    tolerances around it; None outside the curve."""
    for (_, e1, c1), (_, e2, c2) in zip(points, points[1:]):
        if e2 <= error <= e1 and e1 > e2 > 0:
            return c1 * (c2 / c1) ** (math.log(e1 / error) / math.log(e1 / e2))
    return None


def measure(scene: str) -> list[dict]:
    low, high = curve(scene, "DOPRI5"), curve(scene, "DOP853")
    rows = []
    for tol, error, evaluations in high:
        if not any(math.isclose(tol, s) for s in SHOWN):
            continue
        dopri5 = evaluations_at(low, error)
        rows.append({"scene": scene, "tolerance": tol, "dop853_error": error,
                     "dop853_evaluations": evaluations, "dopri5_evaluations": dopri5,
                     "ratio": evaluations / dopri5 if dopri5 else None})
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.high_order", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scenes", nargs="+", default=list(SCENE_NAMES), choices=SCENE_NAMES)
    ap.add_argument("--json", default="benchmarks/high_order.json")
    args = ap.parse_args(argv)
    rows = [row for scene in args.scenes for row in measure(scene)]
    print("DOP853 against DOPRI5: evaluations for the error DOPRI5 reaches, at DOP853's "
          "tolerance")
    print(f"{'scene':<15} {'tol':>6} {'DOP853 error':>12} {'DOP853':>7} {'DOPRI5':>7} "
          f"{'ratio':>6}")
    for r in rows:
        dopri5 = "-" if r["dopri5_evaluations"] is None else f"{r['dopri5_evaluations']:.0f}"
        ratio = "-" if r["ratio"] is None else f"{r['ratio']:.2f}"
        print(f"{r['scene']:<15} {r['tolerance']:>6.0e} {r['dop853_error']:>12.2e} "
              f"{r['dop853_evaluations']:>7d} {dopri5:>7} {ratio:>6}")
    with open(args.json, "w") as fh:
        json.dump({"command": "python -m benchmarks.high_order", "rows": rows}, fh, indent=1)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
