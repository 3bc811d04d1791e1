"""How cheap can this co-simulation scheme be at the error the default reaches at tol
1e-4? A decomposition and a lower bound against the composite FMU (issue 27).

    python -m benchmarks.cosim_bound [--scenes NAME …] [--repeats N] [--json FILE]

The target "default co-simulation <= 20x the composite FMU at 1e-4" is missed on
conveyor, moving_table and two_block_belt (``benchmarks.cosim_fixed``). This asks
whether any step-size sequence of the same coupling scheme could meet it. The scheme:
Jacobi, non-iterative, each input held over a step at the mean of its quadratic
extrapolation from the last three communication points (k = 2, DEFAULT_SCHEME), no
input derivatives (FMI 3 Co-Simulation has none), events synchronised. For each scene, at e* = the error (benchmarks.joined
deviation against the composite FMU at 1e-12) of the default run at tol 1e-4:

(a) the composite FMU at the cheapest tolerance reaching e*: integrator steps, CPU per
    step;
(b) the default co-simulation: communication steps (accepted + rejected), doSteps per
    step and instance, CPU per step and per doStep;
(c) the coupling's convergence order p: fixed communication steps h = step / n of the
    same scheme (same extrapolation, events synchronised too), the slope of log error
    against log h over the finest runs;
(d) the fewest communication steps any step-size sequence of this scheme needs for e*:
    with local coupling error C(t) h^(p+1) summing to the global error, minimising
    N = integral dt/h subject to integral C h^p dt = e gives h ~ C^(-1/(p+1)) and
    N_min = (integral C^(1/(p+1)) dt)^((p+1)/p) / e^(1/p)  (:func:`equidistributed_steps`).
    C(t) is estimated from a fixed-step run of step h0 on the output grid: the growth
    of its running-largest error over each output interval, over h0^p times the
    interval (:func:`local_error_density`). A run must also stop at every output point
    and synchronised event, so N_min is at least that many steps. Times the cheapest
    CPU per communication step measured (a fixed step: one doStep per instance, no
    estimate; the least over the fixed runs) it bounds the scheme's CPU from below;
    over the composite's CPU at e* it is the best ratio this scheme can reach.

Where the bound stays above 20x, no step control of this scheme reaches the target;
where it is below, the default loses by (its steps / N_min) in the step sequence and
(its CPU per step / the cheapest) in the cost per step; "steps at 20x" is how many
communication steps at the cheapest cost fit in 20x the composite's CPU.

What the model is worth: the C(t) estimate assumes local errors add up without growth,
cancellation or reset (a friction contact that sticks resets the velocity error), and
one order p everywhere; an event (extrapolation restarted, a mode switched) puts much of
the error in a few output intervals ("top 1 %"), which a sequence of short steps at the
event resolves for a few steps, not at the density's price. A scene where the default
run itself takes fewer steps than N_min is flagged: there the model bounds nothing, and
only the floor (output points + events) is a bound. N_min with the top 1 % of
intervals free says what the smooth part alone asks for. "First 2 % / 10 %": how
much of the finest fixed run's largest error is there already early in the run, where
the extrapolation starts with no history (its first steps hold plain constants); an
error made early persists and shows later, so the density estimate spreads it over the
run. p = 2 is the scheme's own order: a held input is the extrapolated polynomial's mean
over the step, its integral exact to O(h^(k+2)) but the displacement it causes only to
O(h^3), so k = 1 and k = 2 both give global order 2 (assemblies/masters/extrapolation.py).
CPU: process time, round-robin over the runs ``--repeats`` times, median.
"""
from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
import time

import numpy as np

from assemblies.engine.cosim import DEFAULT_SCHEME, cosimulate
from assemblies.engine.me import simulate_monolithic
from assemblies.pruning import prune_unrecorded
from assemblies.scenes import scene as get_scene

from .cosim_fixed import COMPOSITE_TOLERANCES, TARGET_COMPOSITE, _every_nth
from .joined import REFERENCE_TOLERANCE, reference, row_deviation

SCENES = ("conveyor", "moving_table", "two_block_belt")
COSIM_TOL = 1e-4
DIVISIONS = (16, 24, 32, 48, 64, 96, 128, 192, 256, 384, 512)
SLOPE_POINTS = 4          # the finest fixed runs the order p is fitted over
FIXED_BUDGET_S = 3.0      # a fixed run dearer than this (first call) ends the ladder


def equidistributed_steps(density, dt, p: float, error: float) -> float:
    """The fewest steps of a method with local error C(t) h^(p+1) (errors adding up) for a
    global error `error`: (sum C_j^(1/(p+1)) dt_j)^((p+1)/p) / error^(1/p), `density` C_j
    constant over intervals of lengths `dt`. For C constant it is T / h_uniform, h_uniform
    solving C T h^p = error."""
    c, w = np.asarray(density, float), np.asarray(dt, float)
    if p <= 0 or error <= 0 or np.any(c < 0) or np.any(w <= 0):
        raise ValueError(f"need p > 0, error > 0, C >= 0 and dt > 0 (p={p}, error={error})")
    integral = float(np.sum(c ** (1.0 / (p + 1.0)) * w))
    return integral ** ((p + 1.0) / p) / error ** (1.0 / p)


def local_error_density(times, errors, h: float, p: float) -> tuple[np.ndarray, np.ndarray]:
    """C_j on each interval between output points from one fixed-step run of step `h`:
    the growth of the running-largest error `errors` (per output point) over the
    interval, over h^p times its length. Returns (C_j, dt_j); sum C_j h^p dt_j is the
    run's largest error."""
    t, e = np.asarray(times, float), np.asarray(errors, float)
    envelope = np.maximum.accumulate(e)
    dt = np.diff(t)
    return np.diff(envelope) / (h ** p * dt), dt


def order_fit(hs, errors) -> float:
    """Slope of log error against log h (least squares)."""
    return float(np.polyfit(np.log(hs), np.log(errors), 1)[0])


def _timed(call):
    started = time.process_time()
    result = call()
    return result, time.process_time() - started


def measure_scene(name: str, repeats: int) -> dict:
    sc = get_scene(name)
    asm, _ = prune_unrecorded(sc.build(), sc.record)
    n_inst = len(asm.components)
    k = DEFAULT_SCHEME["extrapolation"]
    common = dict(stop_time=sc.stop_time, tolerance=sc.tolerance, record=sc.record)
    ref = reference(name)
    T = sc.stop_time

    runs = {}
    cosim = lambda: cosimulate(asm, step=sc.step, adaptive=True, tol=COSIM_TOL,  # noqa: E731
                               extrapolation=k, **common)
    cosim()  # loads; untimed
    res, _ = _timed(cosim)
    s = res.settings
    err = float(row_deviation(res, ref).max())
    runs["cosim"] = cosim
    cos = dict(error=err, steps=s["steps"], rejected=s.get("rejected", 0),
               do_steps=s["do_steps"], events=s.get("events_synchronised", 0))

    comp = None
    for tol in COMPOSITE_TOLERANCES:  # the loosest composite reaching e*
        call = (lambda t: lambda: simulate_monolithic(asm, step=sc.step, **dict(common, tolerance=t)))(tol)
        call()
        r, _ = _timed(call)
        e = float(row_deviation(r, ref).max())
        if e <= err:
            comp = dict(tol=tol, error=e, steps=r.settings["steps"],
                        rejected=r.settings.get("rejected", 0))
            runs["composite"] = call
            break

    fixed = []
    for n in DIVISIONS:
        h = sc.step / n
        call = (lambda hh: lambda: cosimulate(
            asm, step=hh, adaptive=False, event_sync=True, extrapolation=k, **common))(h)
        call()
        raw, cpu = _timed(call)
        r = _every_nth(raw, n)  # the rows on the scene's output grid
        e_rows = row_deviation(r, ref)
        steps = raw.settings["steps"]
        fixed.append(dict(n=n, h=h, error=float(e_rows.max()), steps=steps,
                          do_steps=raw.settings["do_steps"], e_rows=e_rows, time=np.asarray(r["time"])))
        runs[f"fixed{n}"] = call
        if cpu > FIXED_BUDGET_S or e_rows.max() < 0.5 * err:
            break

    samples = {key: [] for key in runs}
    for _ in range(repeats):  # round-robin: the machine's load falls on every run alike
        for key, call in runs.items():
            samples[key].append(_timed(call)[1])
    med = {key: statistics.median(v) for key, v in samples.items()}
    spread = {key: (max(v) - min(v)) / med[key] if med[key] else 0.0 for key, v in samples.items()}

    cos.update(cpu_s=med["cosim"], spread=spread["cosim"])
    tried = cos["steps"] + cos["rejected"]
    cos.update(do_steps_per_step=cos["do_steps"] / tried / n_inst,
               cpu_per_step_us=cos["cpu_s"] / tried * 1e6,
               cpu_per_do_step_us=cos["cpu_s"] / cos["do_steps"] * 1e6)
    if comp:
        comp.update(cpu_s=med["composite"], spread=spread["composite"],
                    cpu_per_step_us=med["composite"] / (comp["steps"] + comp["rejected"]) * 1e6)
    for f in fixed:
        f.update(cpu_s=med[f"fixed{f['n']}"], spread=spread[f"fixed{f['n']}"])
        f["cpu_per_step_us"] = f["cpu_s"] / f["steps"] * 1e6
        f["cpu_per_do_step_us"] = f["cpu_s"] / f["do_steps"] * 1e6

    fits = [f for f in fixed if 0 < f["error"] < math.inf][-SLOPE_POINTS:]
    p = order_fit([f["h"] for f in fits], [f["error"] for f in fits])
    # C(t) from each of the two finest runs: if they agree, the runs are asymptotic
    estimates = []
    for f in fits[-2:]:
        c, dt = local_error_density(f["time"], f["e_rows"], f["h"], p)
        estimates.append(equidistributed_steps(c, dt, p, err))
    n_grid = round(T / sc.step) + cos["events"]
    n_min = max(min(estimates), n_grid)
    cheapest_us = min(f["cpu_per_step_us"] for f in fixed)
    bound_s = n_min * cheapest_us * 1e-6
    # how concentrated the fixed runs' error growth is: its share in the 1 % of output
    # intervals where it grows most (events: an extrapolation restarted, a mode switched)
    c, dt = local_error_density(fits[-1]["time"], fits[-1]["e_rows"], fits[-1]["h"], p)
    growth = np.sort(c * dt)[::-1]
    top = max(1, len(growth) // 100)
    top_share = float(growth[:top].sum() / growth.sum())
    # the same bound with those intervals free (as if a step sequence resolved each event
    # at no cost): what the smooth part of the error alone asks for
    smooth = np.where(c * dt >= growth[top - 1], 0.0, c)
    n_smooth = equidistributed_steps(smooth, dt, p, err)
    # how much of the fixed run's error is there already early in the run (its first
    # steps extrapolate from no history): the share of its largest error reached by then
    t_fine, e_fine = fits[-1]["time"], fits[-1]["e_rows"]
    early = {f"{frac:g}": float(e_fine[t_fine <= frac * T].max() / e_fine.max())
             for frac in (0.02, 0.1)}
    uniform = [f for f in fixed if f["error"] <= err]
    out = dict(scene=name, instances=n_inst, stop_time=T, output_step=sc.step, error=err,
               extrapolation=k, cosim=cos, composite=comp, order_p=p,
               order_fit_n=[f["n"] for f in fits],
               n_min_estimates=estimates, n_grid=n_grid, n_min=n_min,
               cheapest_step_us=cheapest_us, bound_cpu_s=bound_s, top1_share=top_share,
               n_smooth=n_smooth, early_share=early,
               # the model holds only if no run of the scheme beats it: the default must not
               model_violated=cos["steps"] + cos["rejected"] < n_min,
               floor_cpu_s=n_grid * cheapest_us * 1e-6,
               uniform_steps=uniform[0]["steps"] if uniform else None,
               fixed=[{k2: v for k2, v in f.items() if k2 not in ("e_rows", "time")} for f in fixed])
    if comp:
        out.update(bound_vs_composite=bound_s / comp["cpu_s"],
                   floor_vs_composite=n_grid * cheapest_us * 1e-6 / comp["cpu_s"],
                   cosim_vs_composite=cos["cpu_s"] / comp["cpu_s"],
                   # steps per run over the composite's, cost per step over the composite's
                   steps_vs_composite=tried / (comp["steps"] + comp["rejected"]),
                   step_cost_vs_composite=cos["cpu_per_step_us"] / comp["cpu_per_step_us"],
                   # the most communication steps at the cheapest cost within the target
                   steps_at_target=TARGET_COMPOSITE * comp["cpu_s"] / (cheapest_us * 1e-6))
    out.update(step_sequence_loss=tried / n_min,
               cost_per_step_loss=cos["cpu_per_step_us"] / cheapest_us)
    return out


def report(rows: list[dict]) -> str:
    lines = [f"{'scene':15s} {'error':>8s} {'comp steps':>10s} {'us/st':>6s} {'comp ms':>8s} "
             f"{'cosim steps':>11s} {'doSt/st':>7s} {'us/st':>6s} {'us/doSt':>7s} {'cosim ms':>8s} "
             f"{'p':>5s} {'N_min':>9s} {'fix us/st':>9s} {'bound ms':>8s} {'bound/comp':>10s} "
             f"{'cosim/comp':>10s} {'steps/N_min':>11s} {'cost/cheapest':>13s}"]
    for r in rows:
        c, m = r["cosim"], r["composite"] or {}
        lines.append(
            f"{r['scene']:15s} {r['error']:8.2e} {m.get('steps', 0):10d} "
            f"{m.get('cpu_per_step_us', math.nan):6.2f} {m.get('cpu_s', math.nan) * 1e3:8.2f} "
            f"{c['steps'] + c['rejected']:11d} {c['do_steps_per_step']:7.2f} "
            f"{c['cpu_per_step_us']:6.2f} {c['cpu_per_do_step_us']:7.3f} {c['cpu_s'] * 1e3:8.1f} "
            f"{r['order_p']:5.2f} {r['n_min']:9.0f} {r['cheapest_step_us']:9.2f} "
            f"{r['bound_cpu_s'] * 1e3:8.2f} {r.get('bound_vs_composite', math.nan):10.2f} "
            f"{r.get('cosim_vs_composite', math.nan):10.2f} {r['step_sequence_loss']:11.2f} "
            f"{r['cost_per_step_loss']:13.2f}"
            + ("  MODEL BEATEN by the default: no bound" if r["model_violated"] else
               "  BOUND > 20x: unreachable by this scheme"
               if r.get("bound_vs_composite", 0) > TARGET_COMPOSITE else ""))
    lines.append("")
    lines.append("decomposition: cosim/comp = (cosim steps / comp steps) x (cosim us/step / comp "
                 "us/step); floor: output points + events at the cheapest step (a bound of any "
                 "step sequence); steps at 20x: the most communication steps at the cheapest "
                 "cost within 20x the composite")
    for r in rows:
        lines.append(f"{r['scene']:15s} cosim/comp {r.get('cosim_vs_composite', math.nan):6.1f} = "
                     f"{r.get('steps_vs_composite', math.nan):6.1f} x "
                     f"{r.get('step_cost_vs_composite', math.nan):5.2f}; floor/comp "
                     f"{r.get('floor_vs_composite', math.nan):5.2f}; steps at 20x "
                     f"{r.get('steps_at_target', math.nan):8.0f} (the default takes "
                     f"{r['cosim']['steps'] + r['cosim']['rejected']}); error growth in the top 1 % "
                     f"of output intervals {r['top1_share']:.0%}, N_min without it {r['n_smooth']:.0f}; "
                     f"finest fixed run's error reached in the first 2 % / 10 % of the run "
                     f"{r['early_share']['0.02']:.0%} / {r['early_share']['0.1']:.0%}")
    lines.append("")
    for r in rows:
        lines.append(f"{r['scene']}: p fitted over n = {r['order_fit_n']}; N_min from the two "
                     f"finest fixed runs {', '.join(f'{x:.0f}' for x in r['n_min_estimates'])}; "
                     f"output points + events {r['n_grid']}; uniform fixed step reaching e*: "
                     f"{r['uniform_steps'] if r['uniform_steps'] else 'none measured'} steps")
        for f in r["fixed"]:
            lines.append(f"  fixed n={f['n']:<4d} h={f['h']:.3e} error {f['error']:.2e} "
                         f"steps {f['steps']} CPU {f['cpu_s'] * 1e3:.1f} ms "
                         f"({f['cpu_per_step_us']:.2f} us/step, spread {f['spread']:.2f})")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.cosim_bound",
                                 description=__doc__.split("\n")[0])
    ap.add_argument("--scenes", nargs="+", default=list(SCENES))
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--json", default="benchmarks/cosim_bound.json")
    args = ap.parse_args(argv)
    rows = []
    for name in args.scenes:
        rows.append(measure_scene(name, args.repeats))
        print(f"  {name} measured", file=sys.stderr, flush=True)
    print(report(rows))
    with open(args.json, "w") as fh:
        json.dump({"rows": rows, "cosim_tol": COSIM_TOL, "reference_tolerance": REFERENCE_TOLERANCE,
                   "target_vs_composite": TARGET_COMPOSITE}, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
