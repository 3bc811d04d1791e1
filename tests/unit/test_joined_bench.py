"""benchmarks.joined: a mode is held against the cheapest composite run at least as
accurate as it, and the deviation measure sees a late event."""
import math

import numpy as np

from assemblies.result import Result
from benchmarks.joined import TARGET_RATIO, compare, deviation


def _rec(mode, tol, error, wall):
    return {"scene": "s", "mode": mode, "tolerance": tol, "error": error, "wall_s": wall,
            "figures_passed": True}


def test_a_mode_is_held_against_the_cheapest_composite_run_as_accurate_as_it():
    records = [_rec("composite", 1e-4, 1e-3, 0.001), _rec("composite", 1e-8, 1e-7, 0.004),
               _rec("composite", 1e-10, 1e-9, 0.009),
               _rec("me", 1e-8, 2e-7, 0.012), _rec("cosim", 1e-5, 1e-10, 1.0)]
    rows = {r["mode"]: r for r in compare(records)}
    assert rows["me"]["composite_tolerance"] == 1e-8 and rows["me"]["ratio"] == 3.0
    assert rows["me"]["target_met"] and 3.0 <= TARGET_RATIO
    # nothing composite is as accurate: no ratio, and the target is not claimed
    assert math.isnan(rows["cosim"]["ratio"]) and not rows["cosim"]["target_met"]


def _result(values):
    t = np.linspace(0.0, 1.0, len(values))
    return Result({"time": t, "a.s": np.asarray(values, float), "a.mode": np.ones(len(values))})


def test_deviation_weighs_by_the_column_size_and_ignores_modes():
    ref = _result([0.0, 2.0, 4.0, 4.0])
    late = _result([0.0, 2.0, 2.0, 4.0])  # one sample behind an event: off by 2 of 4
    assert deviation(late, ref) == 0.5
    assert deviation(ref, ref) == 0.0
    assert deviation(_result([0.0, math.nan, 4.0, 4.0]), ref) == math.inf
