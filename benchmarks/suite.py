"""Sweep tolerances over every method of a scene: records, a table, a log–log plot, JSON."""
from __future__ import annotations

import json
import math
import resource
import time
from pathlib import Path

from .analysis import limit_lines, limit_targets
from .runners import engine_missing, max_error
from .scenes import FULL_TOLERANCES, QUICK_SKIP, QUICK_TOLERANCES, SCENES, expand

FIELDS = ("scene", "method", "tolerance", "error", "wall_s", "rhs_evals", "steps")
# each point is the best of the runs made while they have taken less than this in all, at
# most _MAX_RUNS: a slow method gets more than one try too, and a sub-millisecond one
# enough that a shared machine's busy moments (tens of per cent within a minute here) do
# not fall on one side of a ratio alone (a run over it is timed once)
_REPEAT_WITHIN_S = 0.3
_MAX_RUNS = 50
# a method whose run takes longer than this skips its tighter tolerances (they only cost
# more); --quick's leaves room for the Python monolithic master's 1.9-2.2 s on
# moving_table, which one of the targets compares against
BUDGET_S = {True: 3.0, False: 20.0}
# A method whose error and work come out the same at the sweep's two tightest tolerances
# is held by something other than its tolerance: the Co-Simulation FMU, stepped once per
# output interval, takes one solver step per doStep until its tolerance asks for less than
# that step already gives (stick_slip's DOPRI5 at 0.1 s meets 1e-8: one point at 1e-4,
# 1e-6 and 1e-8). Its curve is followed on, at the sweep's spacing, to where the tolerance
# binds, but not below this.
TIGHTEST = 1e-12


def _timed(fn, tol):
    best, spent, result = math.inf, 0.0, None
    for _ in range(_MAX_RUNS):
        started = time.perf_counter()
        result = fn(tol, False)
        wall = time.perf_counter() - started
        best, spent = min(best, wall), spent + wall
        if spent >= _REPEAT_WITHIN_S:
            break
    return result, best


def run_scene(name: str, quick: bool = False, log=print, methods=None, tolerances=None,
              case=None) -> list[dict]:
    """Every method of one scene at every tolerance; a failed run is a record with error inf.

    `methods` and `tolerances` narrow the sweep (the light test runs one of each);
    `case` reuses an already built scene."""
    started = time.perf_counter()
    if case is None:  # only the beams shorten their run for --quick
        case = SCENES[name](quick=True) if quick and name.startswith("beam_N") else SCENES[name]()
    log(f"# {name}: reference = {case.reference_kind} (setup {time.perf_counter() - started:.1f} s)")
    records = []
    missing = engine_missing()
    if missing:
        log(f"  {missing}")
    for method in (m for m in case.methods if m.startswith("engine")
                   and (methods is None or m in methods)):
        try:  # "second call in one process": the first builds and loads the FMUs
            case.methods[method](1e-6, False)
        except Exception as exc:  # its timed runs will record the failure
            log(f"  {method} warm-up failed: {exc}")
    skipped = [m for m in QUICK_SKIP.get(name, ()) if quick and methods is None]
    if skipped:
        log(f"  --quick skips {', '.join(skipped)} on {name} (the full sweep runs them)")
    # the targets' ratios set the engine's public call against c_limit and scipy: these
    # are measured back to back, ahead of the seconds of the Python masters and fmpy
    # runs, so that the machine's drift (tens of per cent within a minute on a shared
    # VM) falls on both sides of a ratio alike
    def pairing(m):
        return 0 if m == "c_limit" or m.startswith("engine") else 1 if m.startswith("scipy") else 2
    paired = sorted(case.methods, key=pairing)
    for method in paired:
        fn = case.methods[method]
        if (methods is not None and method not in methods) or method in skipped:
            continue
        sweep = list(tolerances or (QUICK_TOLERANCES if quick else FULL_TOLERANCES))
        for tol in sweep:  # grows while the method's curve is flat (_follow_flat)
            if records and records[-1]["method"] == method and records[-1]["wall_s"] > BUDGET_S[quick]:
                log(f"  {method}: {tol:g} and tighter skipped (the last run took "
                    f"{records[-1]['wall_s']:.1f} s > {BUDGET_S[quick]:g} s)")
                break
            try:
                (values, rhs, steps), wall = _timed(fn, tol)
                if rhs is None and steps is None and method.startswith("fmu_"):
                    _, rhs, steps = fn(tol, True)  # an untimed run that counts the work
                error = max_error(values, case.reference)
            except Exception as exc:  # a method that fails is a result, not a crash
                log(f"  {method} at {tol:g} failed: {exc}")
                error, wall, rhs, steps = math.inf, math.nan, None, None
            records.append(dict(zip(FIELDS, (name, method, tol, error, wall, rhs, steps))))
            if tol == sweep[-1]:
                _follow_flat(records, sweep, log)
    return records


def _follow_flat(records: list[dict], sweep: list[float], log) -> None:
    """Append the next tighter tolerance to `sweep` when the last two records (one
    method's) have the same error and work: the tolerance did not bind (TIGHTEST)."""
    if len(records) < 2 or len(sweep) < 2:
        return
    last, before = records[-1], records[-2]
    same = all(last[k] == before[k] for k in ("method", "error", "rhs_evals", "steps"))
    tighter = sweep[-1] * min(sweep[-1] / sweep[-2], 0.1)
    if same and math.isfinite(last["error"]) and tighter >= TIGHTEST * (1 - 1e-9):
        log(f"  {last['method']}: {before['tolerance']:g} and {last['tolerance']:g} gave the "
            f"same error and work (the tolerance did not bind); on to {tighter:g}")
        sweep.append(tighter)


def run(scene_names: list[str], quick: bool = False, log=print) -> tuple[list[dict], dict]:
    records, meta = [], {"peak_rss_mb": {}}
    for group in scene_names:
        for name in expand(group):
            started = time.perf_counter()
            records += run_scene(name, quick, log)
            log(f"  {name}: {time.perf_counter() - started:.0f} s in all")
            # ru_maxrss is in KiB on Linux and never falls: the peak so far, after this scene
            meta["peak_rss_mb"][name] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return records, meta


def _fmt(value, spec):
    return "-" if value is None else format(value, spec)


def table(records: list[dict]) -> str:
    lines = [f"{'scene':<18} {'method':<20} {'tolerance':>9} {'error':>10} {'wall_s':>10} "
             f"{'rhs_evals':>10} {'steps':>8}"]
    for r in records:
        lines.append(f"{r['scene']:<18} {r['method']:<20} {r['tolerance']:>9.0e} "
                     f"{r['error']:>10.2e} {r['wall_s']:>10.6f} {_fmt(r['rhs_evals'], 'd'):>10} "
                     f"{_fmt(r['steps'], 'd'):>8}")
    targets = limit_lines(limit_targets(records))
    if targets:
        lines += ["", "targets (wall time at the error, interpolated on each method's curve):",
                  *targets]
    return "\n".join(lines)


def plot(records: list[dict], scene_name: str, path: Path) -> Path:
    """Error against wall time, log–log, one line per method (runs that failed are left out)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9, 5))
    ax.set_prop_cycle(color=plt.get_cmap("tab20").colors)  # up to 13 methods: no repeats
    rows = [r for r in records if r["scene"] == scene_name]
    for method in dict.fromkeys(r["method"] for r in rows):
        # joined in tolerance order, loose to tight, as a work–precision line is read
        pts = [(r["wall_s"], r["error"]) for r in sorted(rows, key=lambda r: -r["tolerance"])
               if r["method"] == method and r["error"] is not None and r["wall_s"] is not None
               and math.isfinite(r["error"]) and r["error"] > 0 and r["wall_s"] > 0]
        if pts:
            style = "-o" if method.startswith(("fmu", "master", "engine", "c_limit")) else "--s"
            ax.loglog(*zip(*pts), style, label=method, markersize=4)
    ax.set_xlabel("wall time [s]")
    ax.set_ylabel("max |error| at the output times")
    ax.set_title(f"{scene_name}: work–precision")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path


def write_json(records: list[dict], path: Path) -> None:
    """The records (FIELDS), then one row per c_limit target the records allow
    (analysis.limit_targets: keys scene, target, ratio, met, ...; no "method")."""
    def clean(v):  # JSON has no inf/nan: a failed run's error and wall time become null
        return None if isinstance(v, float) and not math.isfinite(v) else v
    path.parent.mkdir(parents=True, exist_ok=True)
    rows = [{k: clean(v) for k, v in r.items()} for r in records] + limit_targets(records)
    path.write_text(json.dumps(rows, indent=1))
