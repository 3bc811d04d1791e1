"""The figures RESULTS.md states, computed from benchmark records (never typed in)."""
from __future__ import annotations

import math

import numpy as np

from .scenes import BEAM_SIZES

FMU_PREFIX, SCIPY_PREFIX = "fmu_", "scipy_"


def fastest(records, scene, prefix, error):
    """(wall, method, tolerance, error) of the quickest run of `prefix` methods within `error`."""
    hits = [(r["wall_s"], r["method"], r["tolerance"], r["error"]) for r in records
            if r["scene"] == scene and r["method"].startswith(prefix) and r["error"] <= error]
    return min(hits) if hits else None


def speedup_target(records, scene, error=1e-6, target=20.0):
    ours, theirs = fastest(records, scene, FMU_PREFIX, error), fastest(records, scene, SCIPY_PREFIX, error)
    if ours is None or theirs is None:
        return {"scene": scene, "ours": ours, "scipy": theirs, "ratio": None, "met": False}
    ratio = theirs[0] / ours[0]
    return {"scene": scene, "ours": ours, "scipy": theirs, "ratio": ratio, "met": ratio >= target}


def assembly_target(records, scene="moving_table", target=3.0):
    """The co-simulation master (any communication step) against master_monolithic, at the
    best error co-simulation reaches."""
    cosim = [r for r in records if r["scene"] == scene and r["method"].startswith("master_cosim")
             and math.isfinite(r["error"])]
    if not cosim:
        return None
    error = min(r["error"] for r in cosim)
    ours = fastest(records, scene, "master_cosim", error)
    mono = fastest(records, scene, "master_monolithic", error)
    ratio = None if mono is None else ours[0] / mono[0]
    return {"scene": scene, "error": error, "cosim": ours, "monolithic": mono, "ratio": ratio,
            "met": ratio is not None and ratio <= target}


def beam_exponents(records, stop_time: float, tolerance=1e-8):
    """Per method: cost per simulated second at each N and the fitted exponent of N."""
    out = {}
    methods = dict.fromkeys(r["method"] for r in records if r["scene"].startswith("beam_N"))
    for method in methods:
        costs = {}
        for n in BEAM_SIZES:
            hit = [r for r in records if r["scene"] == f"beam_N{n}" and r["method"] == method
                   and math.isclose(r["tolerance"], tolerance) and math.isfinite(r["wall_s"])]
            if hit:
                costs[n] = hit[0]["wall_s"] / stop_time
        if len(costs) >= 2:
            ns = np.array(sorted(costs))
            slope = np.polyfit(np.log(ns), np.log([costs[n] for n in ns]), 1)[0]
            out[method] = {"cost_per_s": costs, "exponent": float(slope)}
    return out


# --- the c_limit targets (issue 10): the public call against the floor and against scipy ---
LIMIT_SCENES = ("stick_slip", "axle_pendulum", "coin_rolling")
LIMIT_ERROR = 1e-6
PUBLIC_OVER_LIMIT_MAX = 3.0    # the public call at most 3x c_limit
SCIPY_OVER_PUBLIC_MIN = 30.0   # and at least 30x faster than the fastest scipy method


def wall_at_error(records, scene, method, error=LIMIT_ERROR):
    """Wall time at which `method` reaches `error` on its work–precision curve.

    Between two adjacent tolerances whose errors bracket `error`, log wall is
    interpolated linearly in log error; a run already within `error` counts as it is.
    The least of these, or None if no run reaches `error`."""
    runs = sorted(((r["tolerance"], r["error"], r["wall_s"]) for r in records
                   if r["scene"] == scene and r["method"] == method
                   and math.isfinite(r["error"]) and math.isfinite(r["wall_s"])), reverse=True)
    candidates = [w for _, e, w in runs if e <= error]
    for (_, e0, w0), (_, e1, w1) in zip(runs, runs[1:]):
        if (e0 - error) * (e1 - error) < 0 and e0 > 0 and e1 > 0 and w0 > 0 and w1 > 0:
            s = (math.log(error) - math.log(e0)) / (math.log(e1) - math.log(e0))
            candidates.append(math.exp(math.log(w0) + s * (math.log(w1) - math.log(w0))))
    return min(candidates) if candidates else None


def _fastest_at_error(records, scene, methods, error):
    walls = [(wall_at_error(records, scene, m, error), m) for m in methods]
    walls = [(w, m) for w, m in walls if w is not None]
    return min(walls) if walls else None


def limit_targets(records, error=LIMIT_ERROR) -> list[dict]:
    """For each scene of LIMIT_SCENES whose records include c_limit: (public call) / c_limit
    (target <= 3) and (fastest scipy) / (public call) (target >= 30), at `error`.

    The public call is the fastest `engine_*` method (the compiled engine, as run_scene
    calls it in mode me or monolithic); where the run has no engine record, the fastest
    FMU path stands in, and the row says so."""
    rows = []
    for scene in LIMIT_SCENES:
        methods = list(dict.fromkeys(r["method"] for r in records if r["scene"] == scene))
        if "c_limit" not in methods:
            continue
        engine = [m for m in methods if m.startswith("engine")]
        public_methods = engine or [m for m in methods if m.startswith(FMU_PREFIX)]
        note = None if engine else "engine not measured: the fastest fmu_* path stands in"
        limit = _fastest_at_error(records, scene, ["c_limit"], error)
        public = _fastest_at_error(records, scene, public_methods, error)
        scipy = _fastest_at_error(records, scene,
                                  [m for m in methods if m.startswith(SCIPY_PREFIX)], error)
        for name, num, den, bound, at_most in (
                ("public/c_limit", public, limit, PUBLIC_OVER_LIMIT_MAX, True),
                ("scipy/public", scipy, public, SCIPY_OVER_PUBLIC_MIN, False)):
            ratio = num[0] / den[0] if num and den else None
            met = ratio is not None and (ratio <= bound if at_most else ratio >= bound)
            rows.append({"scene": scene, "target": name, "error": error,
                         "numerator": num and {"method": num[1], "wall_s": num[0]},
                         "denominator": den and {"method": den[1], "wall_s": den[0]},
                         "ratio": ratio, "bound": f"{'<=' if at_most else '>='} {bound:g}",
                         "met": met, "note": note})
    return rows


def limit_lines(rows) -> list[str]:
    """One printed line per target row."""
    lines = []
    for r in rows:
        def side(s):
            return "not reached" if s is None else f"{s['method']} {s['wall_s'] * 1e3:.3f} ms"
        ratio = "n/a" if r["ratio"] is None else f"{r['ratio']:.2f}x"
        lines.append(f"{r['scene']:<14} {r['target']:<15} at error {r['error']:.0e}: {ratio:>9} "
                     f"(target {r['bound']}) {'met' if r['met'] else 'MISSED'}: "
                     f"{side(r['numerator'])} / {side(r['denominator'])}"
                     + (f" [{r['note']}]" if r["note"] else ""))
    return lines
