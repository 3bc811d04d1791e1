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
