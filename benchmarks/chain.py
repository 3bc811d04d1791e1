"""A chain of n friction blocks: how the cost of each mode grows with n (issue 10).

    wall ─SD─ block1 ─SD─ block2 ─SD─ … ─SD─ blockn      SD: SpringDamper (link1 … linkn);
              belt1       belt2              beltn        the right end is free

(one ConstantSpeed per belt support: a connection joins exactly two ports)

Every block rides on the belt (exact Coulomb friction, mu_s > mu_k). With the default
``stretch=0`` each starts stuck with every spring at rest: the belt carries the chain
away from the wall, only the wall's spring-damper stretches, block1 slips first at a
closed-form time, the others follow, and the chain settles to the sliding equilibrium
K s = mu_k m g (blocks at rest, belt sliding under them), with K the tridiagonal
stiffness of wall link and couplings; damping in every link (D = (d/c) K) makes the
transient decay like a modally damped chain. Those two closed forms are the physics
check (tests/integration/test_chain.py). The bench case starts each block displaced by
``stretch`` = 0.5 m alternately back and forth on the belt, so every link pulls harder
than static friction holds and ALL n blocks slip, ring and re-stick within the run (at
rest springs, only block1 and block2 would move in 10 s: an idle chain is no test of how
a master scales). 3n + 1 FMU instances, 2n continuous states, n friction modes.

``python -m benchmarks.chain [--json FILE] [--sizes 2 4 …] [--stop T] [--repeats R]
[--only MODE …] [--budget S] [--composite-up-to N]`` runs the chain for n = 2, 4, …, 256
in every mode it can reach and prints the process CPU time of one run per (mode, n),
least of R rounds (default 5) taken round-robin over the modes (so a change in the
shared machine's load touches every mode alike; the assemblies are built before the
clock starts, the FMUs and composite FMUs by a warm-up call), and the exponent p of
cpu ~ n^p per mode: a least-squares fit in log-log over all n measured, its spread (the
same fit of each round's times alone, lowest..highest), and the fit over n >= 4. The
issue's target (27) is p <= 1.15 in every mode over n = 2 … 256.

Where a mode says how many steps its integrator took (the engine's me and monolithic:
``settings["steps"]``, one integrator for the whole chain), each row keeps them, and
the report splits p into the exponent of the steps and that of the CPU time per step:
a single integrator ends a step at every event of any block, so the steps grow with the
number of distinct event times (physics: 4 events at n = 2, 54 from n = 64 on, where the
chain's ends no longer reach its middle within the run), while the cost per step is
what the master's own overhead decides, and should grow like n.

Modes: the fmpy-driven masters (``assemblies.masters``: cosim, me, monolithic with
CasADi called from Python) and the composite FMU (``simulate_monolithic(engine="fmu")``,
one FMU for the whole joined chain, driven as a CS FMU: the reference cost the joined
modes are held against); the compiled engine's cosim / me / monolithic when
``assemblies.engine`` provides them (imported lazily; a missing one is reported and
skipped); for the engine's cosim also its one C call alone (``engine cosim: C call only
(wall)``: FMUs loaded, instantiated and run, without the Python that prepares the call).
A mode whose run exceeds ``--budget`` CPU seconds (default 5) is not run at larger n,
nor a mode built from a composite FMU beyond ``--composite-up-to`` blocks (default 256:
beyond about 18 blocks the composite's C is one function per member kind mapped over the
members (assemblies/masters/composite_code.py), so its build no longer explodes: n = 256
in 10 s of gcc CPU (43 s in all on the loaded machine), where the flattened expression
took over ten minutes at n = 64).
Each row also gives the largest |s_i(T) - s_i^ref(T)| over the blocks against the
composite FMU at tolerance 1e-10 (beyond ``--composite-up-to``: the engine's me at
1e-10): what the mode computes, not only how fast.
"""
from __future__ import annotations

import argparse
import gc
import json
import math
import sys
import time
from typing import Callable

import numpy as np

from assemblies.assembly import Assembly
from components.sources.translational import ConstantSpeed
from components.translational.elements import MassWithFriction, SpringDamper

SIZES = (2, 4, 8, 16, 32, 64, 128, 256)
# the composite FMU of the whole chain is CasADi code compiled by gcc: one function per
# member kind mapped over the members beyond FLAT_LIMIT, so every size builds (n = 256:
# under a minute once, then cached)
COMPOSITE_UP_TO = 256
STOP_TIME, STEP, TOLERANCE = 10.0, 0.1, 1e-6
STRETCH = 0.5  # [m] alternating start offsets of the bench case: every block slips at t = 0
REFERENCE_TOLERANCE = 1e-10


def friction_chain(n: int, *, m: float = 1.0, g: float = 1.0, mu_k: float = 0.3,
                   mu_s: float = 0.4, c: float = 1.0, d: float = 1.0,
                   belt_speed: float = 0.1, stretch: float = 0.0) -> Assembly:
    """`n` MassWithFriction blocks on a belt, tied to a wall and to each other (module doc);
    block i starts at x = stretch (-1)^i relative to the belt."""
    if not (isinstance(n, int) and n >= 1):
        raise ValueError(f"friction_chain: n must be an integer >= 1, not {n!r}")
    # the name tells a composite FMU's memoised build apart from another start state's
    asm = Assembly(f"friction_chain_{n}" if stretch == 0 else f"friction_chain_{n}_stretched")
    asm.add("wall", ConstantSpeed(v=0.0))
    left = "wall.flange"
    for i in range(1, n + 1):
        asm.add(f"link{i}", SpringDamper(c=c, d=d))
        asm.add(f"block{i}", MassWithFriction(m=m, g=g, mu_k=mu_k, mu_s=mu_s,
                                              x=stretch * (-1) ** i))
        asm.add(f"belt{i}", ConstantSpeed(v=belt_speed))
        asm.connect(left, f"link{i}.flange_a")
        asm.connect(f"link{i}.flange_b", f"block{i}.flange_a")
        asm.connect(f"belt{i}.flange", f"block{i}.support")
        left = f"block{i}.flange_b"
    return asm


def chain_size(asm: Assembly) -> int:
    return sum(1 for name in asm.components if name.startswith("block"))


def chain_first_slip(asm: Assembly) -> float:
    """Time block1 first slips, for a chain started at rest (stretch 0): while all blocks
    ride the belt at v, only the wall link stretches (s1 = v t) and pulls block1 back
    with c v t + d v; it slips at mu_s m g."""
    if any(asm.component(n).starts["x"] != 0.0 for n in asm.components if n.startswith("block")):
        raise ValueError("chain_first_slip: the closed form needs every block to start at x = 0")
    b, link = asm.component("block1").values, asm.component("link1").values
    v = asm.component("belt1").values["v"]
    return (b["mu_s"] * b["m"] * b["g"] - link["d"] * v) / (link["c"] * v)


def chain_sliding_equilibrium(asm: Assembly) -> np.ndarray:
    """Positions s_i where every block stands still while the belt slides under it:
    K s = mu_k m g, K tridiagonal from the links (link i joins block i-1, or the wall, to
    block i; the right end is free)."""
    n = chain_size(asm)
    k = [asm.component(f"link{i}").values["c"] for i in range(1, n + 1)]
    K = np.zeros((n, n))
    for i in range(n):
        K[i, i] += k[i]
        if i + 1 < n:
            K[i, i] += k[i + 1]
            K[i, i + 1] = K[i + 1, i] = -k[i + 1]
    load = [asm.component(f"block{i}").values["mu_k"] * asm.component(f"block{i}").values["m"]
            * asm.component(f"block{i}").values["g"] for i in range(1, n + 1)]
    return np.linalg.solve(K, load)


def positions(n: int) -> list[str]:
    return [f"block{i}.s" for i in range(1, n + 1)]


# --- modes ---------------------------------------------------------------------------
Runner = Callable[[Assembly, float, float, float, list], object]


def modes() -> tuple[dict[str, Runner], list[str]]:
    """{mode: runner(assembly, stop, step, tolerance, record) -> Result}, and notes on the
    modes that could not be imported."""
    from assemblies.masters.cosim import cosimulate
    from assemblies.masters.me import simulate_me
    from assemblies.masters.monolithic import simulate_monolithic

    found: dict[str, Runner] = {
        "fmpy cosim": lambda a, T, h, tol, rec: cosimulate(a, T, h, tol, record=rec),
        "fmpy me": lambda a, T, h, tol, rec: simulate_me(a, T, h, tol, record=rec),
        "monolithic (CasADi in Python)":
            lambda a, T, h, tol, rec: simulate_monolithic(a, T, h, tol, record=rec),
        "composite FMU (fmpy)":
            lambda a, T, h, tol, rec: simulate_monolithic(a, T, h, tol, record=rec, engine="fmu"),
    }
    notes = []
    engine = _engine_callables()
    for mode, (fn, why) in engine.items():
        if fn is None:
            notes.append(f"engine {mode}: not measured ({why})")
        else:
            found[f"engine {mode}"] = (lambda f: lambda a, T, h, tol, rec:
                                       f(a, T, h, tol, record=rec))(fn)
    return found, notes


def _engine_callables() -> dict[str, tuple[Callable | None, str]]:
    """The compiled engine's entry points, if this checkout has them (written in parallel
    with this module: imported lazily, from the package or its mode module)."""
    out = {}
    for mode, name, modules in (("cosim", "cosimulate", ("assemblies.engine.cosim",)),
                                ("me", "simulate_me", ("assemblies.engine", "assemblies.engine.me")),
                                ("monolithic", "simulate_monolithic",
                                 ("assemblies.engine", "assemblies.engine.me"))):
        out[mode] = (None, "")
        for module in modules:
            try:
                out[mode] = (getattr(__import__(module, fromlist=[name]), name), "")
                break
            except Exception as exc:  # ImportError, or a build of the engine that failed
                out[mode] = (None, f"{module}.{name}: {type(exc).__name__}: {exc}".splitlines()[0])
    return out


# --- the sweep -------------------------------------------------------------------------
def bench_chain(n: int) -> Assembly:
    return friction_chain(n, stretch=STRETCH)


def best_of(call, budget_s: float = 1.0, most: int = 5):
    """(least wall seconds over up to `most` calls, stopping once `budget_s` is spent, the
    last result): the minimum is the run least disturbed by the machine's other work."""
    walls, result = [], None
    while len(walls) < most and (not walls or sum(walls) < budget_s):
        started = time.perf_counter()
        result = call()
        walls.append(time.perf_counter() - started)
    return min(walls), result


def cpu_seconds(call) -> tuple[float, object]:
    """(process CPU seconds of one call, its result): the engine and fmpy run in this
    process, so a loaded machine's other work does not count. What this process held
    before the call (the FMU builds, the references, earlier results) is frozen out of
    the garbage collector's scans (gc.freeze) while it runs: a collection the call
    triggers then scans what the call made, not the benchmark's heap, which is not the
    mode's cost (the engine cosim's public call at n = 256 triggered full collections:
    206 ms CPU beside a 1.5-million-object heap, 142 ms with it frozen, 59 ms at n = 128
    either way). No collection before the call: one walks the whole heap and leaves
    the caches cold for the call (n = 2, monolithic: 0.12 ms plain, 0.14 frozen, 0.40
    collected and frozen)."""
    gc.freeze()
    try:
        started = time.process_time()
        result = call()
        return time.process_time() - started, result
    finally:
        gc.unfreeze()


def engine_cosim_core(n: int, stop: float, step: float, tolerance: float,
                      repeats: int = 3) -> float | None:
    """Wall seconds of the engine cosim's one C call alone (FMUs loaded, instantiated,
    run), without the Python that prepares it, least of `repeats`: where the public
    call's time goes (wall time: the timer wraps the C entry point)."""
    import assemblies.engine.cosim as engine

    from .cosim_compare import _c_call_timer
    with _c_call_timer(engine) as seconds:
        if seconds is None:
            return None
        for _ in range(repeats):
            engine.cosimulate(bench_chain(n), stop, step, tolerance, record=positions(n))
        return min(seconds)


def fit_exponent(sizes, cpus, large: int = 4) -> dict[str, float]:
    """p of cpu ~ n^p: least squares in log-log over all sizes, and over n >= `large`
    (where per-run fixed costs no longer hide the growth)."""
    def fit(pts):
        if len(pts) < 2:
            return math.nan
        return float(np.polyfit(np.log([p[0] for p in pts]), np.log([p[1] for p in pts]), 1)[0])
    pts = [(n, w) for n, w in zip(sizes, cpus) if w is not None and w > 0]
    return {"all": fit(pts), "tail": fit([p for p in pts if p[0] >= large])}


def exponent_spread(rows: dict[int, dict]) -> dict[str, float]:
    """The fit over all sizes of the least CPU time per n, and its spread: the same fit
    of each repeat's own times (repeat r of every n), lowest and highest."""
    sizes = sorted(n for n, r in rows.items() if r.get("cpu_s"))
    p = fit_exponent(sizes, [rows[n]["cpu_s"] for n in sizes])
    repeats = min((len(rows[n]["cpu_all_s"]) for n in sizes), default=0)
    each = [fit_exponent(sizes, [rows[n]["cpu_all_s"][r] for n in sizes])["all"]
            for r in range(repeats)]
    each = [e for e in each if not math.isnan(e)]
    return {**p, "lo": min(each, default=math.nan), "hi": max(each, default=math.nan),
            "sizes": [sizes[0], sizes[-1]] if sizes else []}


def reference_positions(n: int, stop: float, step: float, composite_up_to: int):
    """(s_i(T) of the composite FMU at tolerance 1e-10, what computed it); beyond
    `composite_up_to` blocks the composite's build takes minutes, and the engine's me at
    1e-10 stands in (then the me row's error is against itself at a tighter tolerance)."""
    if n <= composite_up_to:
        from assemblies.masters.monolithic import simulate_monolithic
        ref = simulate_monolithic(bench_chain(n), stop, step, REFERENCE_TOLERANCE,
                                  record=positions(n), engine="fmu")
        what = "composite FMU"
    else:
        from assemblies.engine import simulate_me
        ref = simulate_me(bench_chain(n), stop, step, REFERENCE_TOLERANCE, record=positions(n))
        what = "engine me"
    return np.array([ref[c][-1] for c in positions(n)]), what


def sweep(sizes=SIZES, stop: float = STOP_TIME, step: float = STEP, tolerance: float = TOLERANCE,
          budget: float = 5.0, only: list[str] | None = None, repeats: int = 5,
          composite_up_to: int = COMPOSITE_UP_TO, log=print) -> dict:
    """Every mode at every n, round-robin: after one warm-up call per mode (builds and
    loads), `repeats` rounds each time every mode once, so a change in the machine's load
    touches all modes alike. The assemblies are built before the clock starts (the same
    Python for every mode). A mode slower than `budget` CPU seconds is not run at larger
    n, nor is one built from a composite FMU beyond `composite_up_to` blocks."""
    from .runners import builds_memoised

    runners, notes = modes()
    if only:
        runners = {k: v for k, v in runners.items() if any(o in k for o in only)}
    table: dict[str, dict[int, dict]] = {mode: {} for mode in runners}
    composite = ("monolithic", "composite")
    with builds_memoised():
        for n in sizes:
            s_ref, ref_by = reference_positions(n, stop, step, composite_up_to)
            rec, live = positions(n), []
            for mode, run in runners.items():
                done = table[mode]
                if any(c in mode for c in composite) and n > composite_up_to:
                    done[n] = {"cpu_s": None, "note": "skipped: the composite FMU of "
                               f"n > {composite_up_to} blocks takes minutes to build"}
                elif done and max(r.get("cpu_s") or 0 for r in done.values()) > budget:
                    done[n] = {"cpu_s": None, "note": f"skipped: a smaller n took > {budget:g} s"}
                else:
                    try:  # one step: builds and loads everything
                        run(bench_chain(n), step, step, tolerance, rec)
                        live.append(mode)
                        done[n] = {"cpu_all_s": []}
                    except Exception as exc:
                        done[n] = {"cpu_s": None, "note": f"{type(exc).__name__}: {exc}"[:200]}
                        log(f"  n={n:3d} {mode:32s} FAILED {done[n]['note']}")
            results = {}
            for _ in range(repeats):
                for mode in list(live):
                    asm = bench_chain(n)
                    cpu, results[mode] = cpu_seconds(
                        lambda: runners[mode](asm, stop, step, tolerance, rec))
                    table[mode][n]["cpu_all_s"].append(cpu)
                    if cpu > budget:  # one timing says enough at this size
                        live.remove(mode)
            for mode, res in results.items():
                row = table[mode][n]
                s = np.array([res[c][-1] for c in rec])
                row.update(cpu_s=min(row["cpu_all_s"]), cpu_median_s=float(np.median(row["cpu_all_s"])),
                           max_ds_vs_ref=float(np.max(np.abs(s - s_ref))), reference=ref_by)
                steps = getattr(res, "settings", {}).get("steps")
                if isinstance(steps, int) and steps > 0:  # one integrator's: me, monolithic
                    row.update(steps=steps, events=res.settings.get("events"),
                               cpu_per_step_s=row["cpu_s"] / steps)
                log(f"  n={n:3d} {mode:32s} {row['cpu_s'] * 1e3:10.1f} ms CPU (median "
                    f"{row['cpu_median_s'] * 1e3:.1f}, {len(row['cpu_all_s'])} runs)   "
                    f"max|s - s_ref| {row['max_ds_vs_ref']:.2e} ({ref_by})")
            if "engine cosim" in results:
                core = engine_cosim_core(n, stop, step, tolerance)
                table.setdefault("engine cosim: C call only (wall)", {})[n] = {
                    "cpu_s": core, "cpu_all_s": [core] if core else [],
                    "max_ds_vs_ref": table["engine cosim"][n]["max_ds_vs_ref"]}
    exponents = {mode: exponent_spread(rows) for mode, rows in table.items()}
    per_step = {mode: step_exponents(rows) for mode, rows in table.items()}
    return {"stop_time": stop, "step": step, "tolerance": tolerance, "stretch": STRETCH,
            "repeats": repeats, "clock": "process CPU time (time.process_time)",
            "reference": f"composite FMU at tolerance {REFERENCE_TOLERANCE:g} up to n = "
                         f"{composite_up_to}, engine me at {REFERENCE_TOLERANCE:g} beyond",
            "sizes": list(sizes), "modes": {m: {str(n): r for n, r in rows.items()}
                                            for m, rows in table.items()},
            "exponents": exponents, "per_step": {m: e for m, e in per_step.items() if e},
            "notes": notes}


def step_exponents(rows: dict[int, dict]) -> dict[str, float]:
    """Where every n has its step count: the fits (over all n) of steps ~ n^p and of the
    least CPU time per step ~ n^p; their sum is the cost's p. {} where steps are not known."""
    sizes = sorted(n for n, r in rows.items() if r.get("cpu_s"))
    if len(sizes) < 2 or not all(rows[n].get("steps") for n in sizes):
        return {}
    fits = {"steps": fit_exponent(sizes, [rows[n]["steps"] for n in sizes])["all"],
            "cpu_per_step": fit_exponent(sizes, [rows[n]["cpu_per_step_s"] for n in sizes])["all"]}
    if all(rows[n].get("events") for n in sizes):  # what makes the steps grow
        fits["events"] = fit_exponent(sizes, [rows[n]["events"] for n in sizes])["all"]
    return fits


def report(data: dict) -> str:
    sizes = data["sizes"]
    head = f"{'mode':32s}" + "".join(f"{'n=' + str(n):>9s}" for n in sizes) + \
        f"{'p (all)':>9s}{'spread':>13s}{'p (n>=4)':>9s}"
    lines = [f"friction chain (stretch {data['stretch']:g} m), stop {data['stop_time']:g} s, "
             f"step {data['step']:g} s, tolerance {data['tolerance']:g}: CPU time of one run "
             f"[ms], least of {data['repeats']} round-robin; p: fit of cpu ~ n^p over the "
             "sizes measured, spread: the same fit of each round alone", head]
    for mode, rows in data["modes"].items():
        cells = []
        for n in sizes:
            w = rows.get(str(n), {}).get("cpu_s")
            cells.append(f"{w * 1e3:9.1f}" if w is not None else f"{'-':>9s}")
        p = data["exponents"][mode]
        lines.append(f"{mode:32s}" + "".join(cells) + f"{p['all']:9.2f}"
                     + f"{p['lo']:6.2f}..{p['hi']:<5.2f}{p['tail']:9.2f}")
    per_step = data.get("per_step", {})
    if per_step:
        lines.append("steps per run (me, monolithic: the one integrator's; cosim: communication "
                     "steps), CPU per step [us]; p of steps ~ n^p and of CPU per step ~ n^p "
                     "(their sum is p (all)):")
    for mode, p in per_step.items():
        rows = data["modes"][mode]
        lines.append(f"{mode + ' steps':32s}" + "".join(
            f"{rows.get(str(n), {}).get('steps') or '-':>9}" for n in sizes) + f"{p['steps']:9.2f}")
        if "events" in p:  # each event ends a step of the one integrator: steps = events + a few
            lines.append(f"{mode + ' events':32s}" + "".join(
                f"{rows.get(str(n), {}).get('events') or '-':>9}" for n in sizes)
                + f"{p['events']:9.2f}")
        lines.append(f"{mode + ' us/step':32s}" + "".join(
            f"{rows[str(n)]['cpu_per_step_s'] * 1e6:9.1f}" if rows.get(str(n), {}).get(
                "cpu_per_step_s") else f"{'-':>9s}" for n in sizes) + f"{p['cpu_per_step']:9.2f}")
    lines.append("largest |s_i(T) - s_i^ref(T)| [m] vs " + data["reference"] + ":")
    for mode, rows in data["modes"].items():
        cells = [rows.get(str(n), {}).get("max_ds_vs_ref") for n in sizes]
        lines.append(f"{mode:32s}" + "".join(f"{c:9.1e}" if c is not None else f"{'-':>9s}"
                                             for c in cells))
    for mode, rows in data["modes"].items():
        for n, r in rows.items():
            if r.get("note"):
                lines.append(f"  {mode}, n={n}: {r['note']}")
    lines += [f"  {note}" for note in data["notes"]]
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.chain",
                                 description="time every mode on a chain of n friction blocks")
    ap.add_argument("--json", help="write the measurements to this file")
    ap.add_argument("--sizes", type=int, nargs="+", default=list(SIZES))
    ap.add_argument("--stop", type=float, default=STOP_TIME, help="stop time [s]")
    ap.add_argument("--step", type=float, default=STEP, help="communication/output step [s]")
    ap.add_argument("--budget", type=float, default=5.0,
                    help="a mode slower than this [CPU s] is not run at larger n")
    ap.add_argument("--repeats", type=int, default=5, help="round-robin rounds per n")
    ap.add_argument("--composite-up-to", type=int, default=COMPOSITE_UP_TO,
                    help="largest n whose composite FMU is built (monolithic modes, reference)")
    ap.add_argument("--only", nargs="+", help="run only the modes whose name contains one of these")
    args = ap.parse_args(argv)
    data = sweep(args.sizes, args.stop, args.step, budget=args.budget, only=args.only,
                 repeats=args.repeats, composite_up_to=args.composite_up_to)
    print(report(data))
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(data, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
