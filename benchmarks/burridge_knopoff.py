"""The Burridge-Knopoff fault at scale (issue 30): the event-driven fault solver.

    python -m benchmarks.burridge_knopoff [--repeats R] [--json FILE] [--plots DIR]
                                          [--no-sweep] [--quick]

1. The target: n = 1000 blocks, 10,000 slip events (after the warm-up of
   ``fault_study``) in under 60 s of integration: the C call's process CPU time, least
   of R, its spread, and the run's figures (energy balance, C&L's b) and the share of
   the time each block slept (stuck: no work).
2. Cost per event against n = 10 ... 1000 (3000 events each), R rounds round-robin over
   n: CPU per event, the events' own size (blocks per event, and the block-seconds of
   sliding per event: the space-time extent of the slides, whatever the solver), the
   solver's block evaluations per event, and the exponents p of each ~ n^p (least
   squares in log-log). Target: p(cost) <= p(sliding block-seconds) + 0.1 and the cost
   per sliding block-second flat (within 2x) over n. Also: the b figure of 1. for
   three draws of the thresholds (seeds 1, 2, 3), since a run's b wanders.
3. The same model as a user writes it: scipy's solve_ivp (RK45 at the same tolerance)
   over every block with one event function per possible switch
   (assemblies/scenes/fault_references.scipy_slides), n = 100, from the same warmed-up
   state, to its 300th slide; the fault solver over the same span of time: the CPU
   ratio, and the largest difference of the slides' end times.
4. A Dask sweep over the weakening alpha (n = 300, 5000 events each): b, the share of
   delocalised events, the largest moment; with ``--plots``, the distributions.
5. (``--fmu-modes``, alone) the scene as FMUs in me and monolithic at n = 250, 500,
   1000: CPU of the first run, of its plan and of the engine alone (fmu_modes).

CPU times are ``time.process_time`` around the one C call (the fault solver) or the whole
scipy loop; the machine is shared, so each figure is the least of R rounds. Every run is
Carlson & Langer's model (no backward slides), as fault_study runs it.
"""
from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from assemblies.engine.fault import carlson_langer, run_fault, thresholds
from assemblies.scenes.burridge_knopoff import fault_study, plot_fault, plot_sweep, weakening_sweep
from assemblies.scenes.fault_references import scipy_slides
from benchmarks.run_all import replace_section

TOL = 1e-8
TARGET_S, TARGET_N, TARGET_EVENTS = 60.0, 1000, 10_000
SIZES = (10, 30, 100, 300, 1000)
SCALING_EVENTS = 3000
SCIPY_N, SCIPY_SLIDES = 100, 300
ALPHAS = (1.5, 2.5, 3.5, 4.5)
FMU_SIZES = (250, 500, 1000)


def _fit(n, y) -> float:
    return float(np.polyfit(np.log(n), np.log(y), 1)[0])


def target(repeats: int, n: int = TARGET_N, events: int = TARGET_EVENTS):
    runs = [fault_study(n, events, tol=TOL) for _ in range(repeats)]
    cpu = [r.settings["cpu_s"] for r, _ in runs]
    run, figures = runs[int(np.argmin(cpu))]
    s = run.settings
    return run, {"n": n, "events": s["events"], "cpu_s": min(cpu), "cpu_spread_s": [min(cpu),
                                                                                   max(cpu)],
                 "simulated_time": run.totals["time"], "steps": s["steps"],
                 "slept_fraction": s["slept_fraction"],
                 "warmup_travel": s["warmup_travel"],
                 "figures": {f.name: {"measured": f.measured, "reference": f.reference,
                                      "bound": f.bound, "passed": f.passed} for f in figures},
                 "meets_target": min(cpu) < TARGET_S and s["events"] >= events}


def b_over_seeds(seeds=(1, 2, 3), n: int = TARGET_N, events: int = TARGET_EVENTS) -> list:
    """The b figure of the target run for other threshold draws: how much it wanders."""
    rows = []
    for seed in seeds:
        _, figures = fault_study(n, events, tol=TOL, seed=seed)
        b = figures[1]
        rows.append({"seed": seed, "b": b.measured, "bound": b.bound, "passed": b.passed})
    return rows


def _warm(n: int, seed: int = 1):
    """A chain past its start (fault_study's warm-up), and its thresholds and law."""
    F, law = thresholds(n, 1.0, 0.01, seed), carlson_langer()
    x, travelled = np.zeros(n), 0.0
    while travelled < 2.5:
        r = run_fault(F, **law, tol=TOL, max_events=1000, x0=x, slides=0, backward=False)
        x = r.x - law["V"] * r.totals["time"]
        travelled += law["V"] * r.totals["time"]
    return F, law, x


def scaling(repeats: int, sizes=SIZES, events: int = SCALING_EVENTS) -> dict:
    warm = {n: _warm(n) for n in sizes}
    cpu = {n: [] for n in sizes}
    last = {}
    for _ in range(repeats):  # round-robin: a change in the machine's load touches every n
        for n in sizes:
            F, law, x = warm[n]
            r = run_fault(F, **law, tol=TOL, max_events=events, x0=x, slides=0,
                          backward=False)
            cpu[n].append(r.settings["cpu_s"] / r.settings["events"])
            last[n] = r
    rows = []
    for n in sizes:
        r = last[n]
        ev = r.settings["events"]
        rows.append({"n": n, "events": ev, "cpu_per_event_s": min(cpu[n]),
                     "cpu_per_event_spread_s": [min(cpu[n]), max(cpu[n])],
                     "blocks_per_event": float(r.catalogue["blocks"].mean()),
                     "block_evaluations_per_event": r.totals["block_rhs"] / ev,
                     "sliding_block_seconds_per_event": r.totals["sliding"] / ev,
                     "cpu_per_sliding_block_second_s": min(cpu[n]) * ev / r.totals["sliding"],
                     "cpu_per_block_evaluation_s": min(cpu[n]) * ev / r.totals["block_rhs"],
                     "slept_fraction": r.settings["slept_fraction"]})
    ns = [row["n"] for row in rows]
    p_cost = _fit(ns, [row["cpu_per_event_s"] for row in rows])
    p_evals = _fit(ns, [row["block_evaluations_per_event"] for row in rows])
    p_size = _fit(ns, [row["sliding_block_seconds_per_event"] for row in rows])
    p_blocks = _fit(ns, [row["blocks_per_event"] for row in rows])
    per_size = [row["cpu_per_sliding_block_second_s"] for row in rows]
    # the same fit on each round's times alone: how much the machine moved it
    rounds = [_fit(ns, [cpu[n][k] for n in ns]) for k in range(repeats)]
    return {"rows": rows, "p_cost": p_cost, "p_cost_rounds": [min(rounds), max(rounds)],
            "p_sliding_block_seconds": p_size, "p_block_evaluations": p_evals,
            "p_blocks": p_blocks,
            "cost_per_sliding_block_second_ratio": max(per_size) / min(per_size),
            "meets_target": p_cost <= p_size + 0.1 and max(per_size) / min(per_size) <= 2.0}


def versus_scipy(repeats: int, n: int = SCIPY_N, slides: int = SCIPY_SLIDES) -> dict:
    F, law, x = _warm(n)
    started = time.process_time()
    ref, _ = scipy_slides(F, **law, stop_time=1e9, x0=x, rtol=TOL, atol=TOL,
                          max_slides=slides, method="RK45", backward=False)
    cpu_scipy = time.process_time() - started
    span = ref[-1][2]
    cpu = []
    for _ in range(repeats):
        r = run_fault(F, **law, tol=TOL, stop_time=span, x0=x, backward=False)
        cpu.append(r.settings["cpu_s"])
    ends_ref = np.array([s[2] for s in ref])
    ends = np.sort(r.slides["t1"])
    k = min(ends.size, ends_ref.size)
    return {"n": n, "slides": len(ref), "simulated_time": span, "scipy_cpu_s": cpu_scipy,
            "fault_cpu_s": min(cpu), "fault_cpu_spread_s": [min(cpu), max(cpu)],
            "speed_ratio": cpu_scipy / min(cpu),
            "largest_end_time_difference_s": float(np.max(np.abs(ends[:k] - ends_ref[:k]))),
            "slides_fault": int(r.slides.size)}


def _cpu() -> float:
    """This process's CPU and its finished children's (gcc building an FMU)."""
    import resource
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.process_time() + children.ru_utime + children.ru_stime


def _plan(seconds: float) -> str:
    """A plan's CPU, the difference of two runs: "~0" within the runs' own spread (the
    machine is shared; an engine run of 25 s moves by a few seconds)."""
    return f"{seconds:.1f}" if seconds > 1.0 else "~0"


def fmu_modes(sizes=FMU_SIZES, modes=("me", "monolithic")) -> list[dict]:
    """The scene as FMUs (its default run, 75 s at tolerance 1e-10) at each n, past the
    scene's per-mode limits: CPU of the first run (the plan: causality, FMUs loaded or
    built, the step cap; then the engine) and of a second run of the same plan in the
    process (the engine alone); the difference is the plan's. FMUs come from the cache
    as found: `built` says whether this run compiled one (gcc's CPU counted)."""
    from assemblies.engine.me import simulate_me, simulate_monolithic
    from assemblies.scenes import scene
    from assemblies.scenes.burridge_knopoff import _scene_chain
    sc = scene("burridge_knopoff")
    simulate = {"me": simulate_me, "monolithic": simulate_monolithic}
    rows = []
    for mode in modes:
        for n in sizes:
            asm = _scene_chain(n)
            runs = []
            for _ in range(2):
                started, own = _cpu(), time.process_time()
                res = simulate[mode](asm, sc.stop_time, sc.step, sc.tolerance)
                total = _cpu() - started
                runs.append((total, total - (time.process_time() - own)))  # gcc's share
            s = res.settings
            rows.append({"mode": mode, "n": n, "first_cpu_s": runs[0][0],
                         "engine_cpu_s": runs[1][0], "plan_cpu_s": runs[0][0] - runs[1][0],
                         "built": runs[0][1] > 0.5, "steps": s["steps"], "events": s["events"],
                         "rhs_calls": s["rhs_calls"], "under_60_s": runs[0][0] < TARGET_S})
            print(f"   {mode:>10} n = {n:>5}: first run {runs[0][0]:7.1f} s CPU (plan "
                  f"{_plan(runs[0][0] - runs[1][0])} s, engine {runs[1][0]:6.1f} s"
                  f"{', an FMU built' if runs[0][1] > 0.5 else ''}), {s['steps']} steps, "
                  f"{s['events']} events", flush=True)
    return rows


def results_section(data: dict) -> list[str]:
    """The "Burridge-Knopoff fault (issue 30)" section of RESULTS.md from the JSON."""
    big, sc, vs = data["target"], data["scaling"], data["versus_scipy"]
    lines = ["## Burridge-Knopoff fault (issue 30)", "",
             f"From `{data['command']} --results` (CPU time; tolerance {data['tolerance']:g}); "
             "raw: `benchmarks/burridge_knopoff.json`. The event-driven fault solver "
             "(assemblies.engine.fault): stuck blocks cost nothing, break-aways in closed "
             "form, sliding groups integrated on their own clocks.", "",
             f"- n = {big['n']}, {big['events']} slip events over {big['simulated_time']:.4g} s: "
             f"{big['cpu_s']:.3g} s CPU ({big['cpu_spread_s'][0]:.3g}-{big['cpu_spread_s'][1]:.3g}"
             f"), target < {TARGET_S:g} s: {'met' if big['meets_target'] else 'missed'}; blocks "
             f"stuck {100 * big['slept_fraction']['mean']:.1f}% of the time on average (least "
             f"{100 * big['slept_fraction']['min']:.1f}%)."]
    for name, f in big["figures"].items():
        lines.append(f"- {name}: {f['measured']:.8g} against {f['reference']:.8g} (bound "
                     f"{f['bound']:.2g}): {'pass' if f['passed'] else 'FAIL'}")
    if "b_over_seeds" in big:
        lines.append("- Gutenberg-Richter b over threshold draws: " + ", ".join(
            f"{r['b']:.3f} (bound {r['bound']:.2g})" for r in big["b_over_seeds"])
            + " (Carlson & Langer: 1)")
    lines += ["", "| n | CPU per event [us] | blocks per event | sliding block-s per event | "
              "CPU per sliding block-s [us] | stuck % |", "|---|---|---|---|---|---|"]
    for row in sc["rows"]:
        lines.append(f"| {row['n']} | {1e6 * row['cpu_per_event_s']:.1f} | "
                     f"{row['blocks_per_event']:.2f} | "
                     f"{row['sliding_block_seconds_per_event']:.2f} | "
                     f"{1e6 * row['cpu_per_sliding_block_second_s']:.2f} | "
                     f"{100 * row['slept_fraction']['mean']:.1f} |")
    lines += ["", f"Cost per event ~ n^{sc['p_cost']:.2f} against the events' own size "
              f"(sliding block-seconds) n^{sc['p_sliding_block_seconds']:.2f}; cost per sliding "
              f"block-second varies {sc['cost_per_sliding_block_second_ratio']:.2f}x over n: "
              f"{'met' if sc['meets_target'] else 'missed'}. A plain scipy `solve_ivp` with "
              f"events over all blocks (n = {vs['n']}, {vs['slides']} slides): "
              f"{vs['scipy_cpu_s']:.3g} s against {1e3 * vs['fault_cpu_s']:.3g} ms, "
              f"**{vs['speed_ratio']:.0f}x** (scipy timed once).", ""]
    if data.get("fmu_modes"):
        lines += ["The scene as FMUs (`--fmu-modes`; its default 75 s at tolerance 1e-10, CPU "
                  "of the first run in a process, the engine's share from a second run):", "",
                  "| mode | n | CPU [s] | plan [s] | engine [s] | steps | events |",
                  "|---|---|---|---|---|---|---|"]
        for r in data["fmu_modes"]:
            lines.append(f"| {r['mode']} | {r['n']} | {r['first_cpu_s']:.1f}"
                         f"{' (FMU built)' if r['built'] else ''} | {_plan(r['plan_cpu_s'])} | "
                         f"{r['engine_cpu_s']:.1f} | {r['steps']} | {r['events']} |")
        lines.append("")
    return lines


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.burridge_knopoff",
                                 description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--json", default="benchmarks/burridge_knopoff.json")
    ap.add_argument("--plots", type=Path)
    ap.add_argument("--no-sweep", action="store_true", help="leave the Dask sweep out")
    ap.add_argument("--quick", action="store_true", help="small sizes: a smoke run")
    ap.add_argument("--results", action="store_true",
                    help="also write the section of benchmarks/RESULTS.md")
    ap.add_argument("--from-json", action="store_true",
                    help="only write the RESULTS.md section from the JSON (no run)")
    ap.add_argument("--fmu-modes", nargs="*", metavar="MODE=N,N",
                    help="only section 5, the scene as FMUs, e.g. me=250,500 monolithic=250 "
                         "(none given: both modes at 250,500,1000), merged into the JSON")
    a = ap.parse_args(argv)
    if a.fmu_modes is not None:
        plan = {m: FMU_SIZES for m in ("me", "monolithic")}
        if a.fmu_modes:
            plan = {m: tuple(int(v) for v in sizes.split(","))
                    for m, _, sizes in (arg.partition("=") for arg in a.fmu_modes)}
        print("5. the scene as FMUs (CPU: first run, its plan, the engine alone)")
        path = Path(a.json)
        data = json.loads(path.read_text()) if path.exists() else {}
        data["fmu_modes"] = [row for mode, sizes in plan.items()
                             for row in fmu_modes(sizes, (mode,))]
        path.write_text(json.dumps(data, indent=1, default=float) + "\n")
        print(f"\nwrote {a.json}")
        return 0
    if a.from_json:
        replace_section(Path(__file__).parent / "RESULTS.md",
                        results_section(json.loads(Path(a.json).read_text())))
        return 0
    quick = a.quick
    run, big = target(a.repeats, *((100, 1000) if quick else ()))
    print(f"1. n = {big['n']}, {big['events']} events: CPU {big['cpu_s']:.3g} s (spread "
          f"{big['cpu_spread_s'][0]:.3g}..{big['cpu_spread_s'][1]:.3g}), {big['steps']} steps, "
          f"{big['simulated_time']:.6g} s simulated; blocks stuck "
          f"{100 * big['slept_fraction']['mean']:.1f}% of the time (least "
          f"{100 * big['slept_fraction']['min']:.1f}%); target < {TARGET_S:g} s: "
          f"{'met' if big['meets_target'] else 'MISSED'}")
    for name, f in big["figures"].items():
        print(f"   {name}: {f['measured']:.8g} vs {f['reference']:.8g} (bound {f['bound']:.2g}) "
              f"{'pass' if f['passed'] else 'FAIL'}")
    seeds = b_over_seeds((1, 2) if quick else (1, 2, 3), *((100, 1000) if quick else ()))
    print("   b over threshold draws: " + ", ".join(
        f"seed {r['seed']}: {r['b']:.3f} (bound {r['bound']:.2g}, "
        f"{'pass' if r['passed'] else 'FAIL'})" for r in seeds))
    big["b_over_seeds"] = seeds
    sc = scaling(a.repeats, (10, 30, 100) if quick else SIZES, 500 if quick else SCALING_EVENTS)
    print(f"\n2. cost per event against n ({sc['rows'][0]['events']}+ events each)")
    print(f"{'n':>6} {'CPU/event us':>13} {'blocks/event':>13} {'sliding bl.s/event':>19} "
          f"{'us/sliding bl.s':>16} {'block evals/event':>18} {'ns/block eval':>14} "
          f"{'stuck %':>8}")
    for row in sc["rows"]:
        print(f"{row['n']:>6} {1e6 * row['cpu_per_event_s']:>13.1f} "
              f"{row['blocks_per_event']:>13.2f} {row['sliding_block_seconds_per_event']:>19.2f} "
              f"{1e6 * row['cpu_per_sliding_block_second_s']:>16.2f} "
              f"{row['block_evaluations_per_event']:>18.0f} "
              f"{1e9 * row['cpu_per_block_evaluation_s']:>14.1f} "
              f"{100 * row['slept_fraction']['mean']:>8.1f}")
    print(f"   p(cost) = {sc['p_cost']:.2f} (rounds {sc['p_cost_rounds'][0]:.2f}.."
          f"{sc['p_cost_rounds'][1]:.2f}), p(sliding block-seconds) = "
          f"{sc['p_sliding_block_seconds']:.2f}, p(block evaluations) = "
          f"{sc['p_block_evaluations']:.2f}, p(blocks) = {sc['p_blocks']:.2f}; cost per sliding "
          f"block-second varies {sc['cost_per_sliding_block_second_ratio']:.2f}x over n: target "
          f"{'met' if sc['meets_target'] else 'MISSED'}")
    vs = versus_scipy(a.repeats, 30 if quick else SCIPY_N, 50 if quick else SCIPY_SLIDES)
    print(f"\n3. n = {vs['n']}, {vs['slides']} slides ({vs['simulated_time']:.4g} s): scipy "
          f"solve_ivp {vs['scipy_cpu_s']:.3g} s, fault solver {vs['fault_cpu_s'] * 1e3:.3g} ms: "
          f"{vs['speed_ratio']:.0f}x; slide end times differ by at most "
          f"{vs['largest_end_time_difference_s']:.2g} s")
    data = {"command": "python -m benchmarks.burridge_knopoff" + (" --quick" if quick else ""),
            "tolerance": TOL, "target": big, "scaling": sc, "versus_scipy": vs}
    if not a.no_sweep:
        sweep = weakening_sweep((1.5, 2.5) if quick else ALPHAS, n=100 if quick else 300,
                                events=500 if quick else 5000, workers=2)
        print("\n4. Dask sweep over alpha")
        for p in sweep["points"]:
            print(f"   alpha {p['alpha']:g}: {p['events']} events, b = {p['b']:.3f} "
                  f"(+-{p['b_accuracy']:.2g}), delocalised {100 * p['delocalised']:.2f}%, "
                  f"largest moment {p['largest_moment']:.3g}, mean blocks {p['mean_blocks']:.2f}")
        data["sweep"] = sweep
        if a.plots:
            a.plots.mkdir(parents=True, exist_ok=True)
            plot_sweep(sweep, a.plots / "burridge_knopoff_sweep.png")
    if a.plots:
        a.plots.mkdir(parents=True, exist_ok=True)
        plot_fault(run, f"Burridge-Knopoff, n = {big['n']}, {big['events']} events",
                   a.plots / "burridge_knopoff.png")
    Path(a.json).write_text(json.dumps(data, indent=1, default=float) + "\n")
    print(f"\nwrote {a.json}")
    if a.results:
        replace_section(Path(__file__).parent / "RESULTS.md", results_section(data))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
