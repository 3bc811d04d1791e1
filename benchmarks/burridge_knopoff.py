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

TOL = 1e-8
TARGET_S, TARGET_N, TARGET_EVENTS = 60.0, 1000, 10_000
SIZES = (10, 30, 100, 300, 1000)
SCALING_EVENTS = 3000
SCIPY_N, SCIPY_SLIDES = 100, 300
ALPHAS = (1.5, 2.5, 3.5, 4.5)


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


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.burridge_knopoff",
                                 description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--json", default="benchmarks/burridge_knopoff.json")
    ap.add_argument("--plots", type=Path)
    ap.add_argument("--no-sweep", action="store_true", help="leave the Dask sweep out")
    ap.add_argument("--quick", action="store_true", help="small sizes: a smoke run")
    a = ap.parse_args(argv)
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
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
