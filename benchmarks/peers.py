"""Peer co-simulation masters on the same FMUs, each at the step that reaches an error (issue 27).

    python -m benchmarks.peers [--targets 1e-3 1e-5] [--repeats 3] [--budget 20] [--results]

Every joined scene the peers can run (its members are FMI 2 CS FMUs of ours, wired by
the scene's SSP: ``assemblies.ssp.export_ssp``, what ``mechfmu export SCENE --ssp``
writes) is run by

- ``libcosim``   libcosimpy (OSP's libcosim, C++), fixed step, Jacobi, zero-order hold;
- ``ecos``       ecospy (Ecos, C++), the same;
- ``fmpy loop``  a plain Python master over fmpy's FMI 2 calls on the same FMUs
  (:func:`run_fmpy_loop`: Jacobi, zero-order hold, the SSP's -1 flow factor applied;
  fmpy's own SSP runner drops that factor, so its belt is wrong at every step);
- ``ours fixed`` the compiled engine at a fixed communication step, as
  ``--fixed-step`` runs it (Jacobi, zero-order hold: the peers' scheme);
- ``ours``       the compiled engine's default co-simulation (adaptive steps, quadratic
  extrapolation, events synchronised), its knob the step tolerance ``tol``.

The error of a run is the largest deviation of the compared outputs (the bodies'
positions and velocities) from the scene's composite FMU at tolerance 1e-12
(``benchmarks.joined.reference``: one solver, no coupling error, nothing shared with a
co-simulation master) on a grid of SAMPLE s, each column weighed by max(1, its largest
|value|) (``benchmarks.joined.deviation``). Every FMU's own solver runs at relative
tolerance 1e-8 (the runtime's default, what an FMI 2 tool gets; ``tolerance=1e-8`` for
ours).

The step search (:func:`search`), for each tool and target error: the communication
step is h = SAMPLE / k with k a divisor of SAMPLE in nanoseconds (libcosim's clock), k
growing about 2x a try until the error is at most the target, then bisected between the
last k that missed and the first that met it; for ``ours`` the tolerance falls 10x a
try, then bisects in log(tol). A tool whose next try would cost more than ``--budget``
CPU seconds (estimated from the last try's cost per step), or whose error stopped
falling, cannot reach the target: its row says so, with the smallest error it reached.

Timing: CPU time (``time.process_time``: every thread of this process, the C++ engines'
included), the chosen setting of every tool run ``--repeats`` times round-robin, median
and range. A peer's time is its stepping only (loading the SSP and instantiating apart,
as setup); ours is the whole call (its FMUs loaded and instantiated inside it), so a
ratio favours the peers. Per communication step: the stepping time over the
communication steps taken (ours adaptive: accepted steps; each costs several doSteps).
Writes benchmarks/peers.json and, with ``--results``, the section "Peer co-simulation
masters (issue 27)" of benchmarks/RESULTS.md. No test asserts a time.
"""
from __future__ import annotations

import argparse
import contextlib
import io
import json
import math
import os
import platform
import statistics
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import numpy as np

from .cosim_compare import TOLERANCE, libcosim_reader, load_ecospy, split_ref

HERE = Path(__file__).parent
JSON_PATH = HERE / "peers.json"
SAMPLE = 0.5            # the error grid [s]; every step divides it
TARGETS = (1e-3, 1e-5)
# the joined scenes whose every member is one of our components (FMI 2 CS in the SSP),
# with the outputs compared: the bodies' motion
SCENES = {
    "two_block_belt": ["block1.s", "block1.v", "block2.s", "block2.v"],
    "axle_motor": ["body.theta", "body.omega", "motor.phi", "motor.w"],
    "beam_friction_damper": ["beam.w_tip", "pad.x", "pad.v"],
    "moving_table": ["block.x", "block.v", "table.flange.s", "table.flange.v"],
    "conveyor": ["block.x", "block.v", "table.flange.s", "table.flange.v"],
}
PEERS = ("libcosim", "ecos", "fmpy loop", "ours fixed")
OURS = "ours"
TOLS = tuple(10.0 ** -e for e in range(2, 10))  # ours: the step tolerances tried


# --- the error ------------------------------------------------------------------------
class Columns(dict):
    """Sampled outputs as ``benchmarks.joined.deviation`` reads a result."""

    @property
    def columns(self):
        return list(self)


def sample_rows(times, values: dict, grid: np.ndarray) -> Columns:
    """The rows of `values` (columns over `times`) at the times of `grid`; a grid time
    the run did not reach gives NaN (an error of inf)."""
    times = np.asarray(times, float)
    index = np.searchsorted(times, grid - 1e-9)
    found = (index < len(times)) & (np.abs(times[np.minimum(index, len(times) - 1)] - grid)
                                    <= 1e-9 * max(1.0, float(grid[-1])))
    out = Columns()
    for name, column in values.items():
        column = np.asarray(column, float)
        out[name] = np.where(found, column[np.minimum(index, len(column) - 1)], np.nan)
    return out


def error(run: Columns, ref: Columns) -> float:
    """Largest weighed deviation of `run` from `ref` (module doc); inf if not finite."""
    from .joined import deviation
    return deviation(run, ref)


def sample_grid(stop: float, sample: float = SAMPLE) -> np.ndarray:
    return sample * np.arange(1, round(stop / sample) + 1)


def reference(scene: str, compared: list[str], grid: np.ndarray) -> Columns:
    """The composite FMU at benchmarks.joined's reference tolerance, output on `grid`
    (a scene's own output step need not divide it: moving_table's is pi/160 s)."""
    from assemblies.run import run_scene_full

    from .joined import REFERENCE_TOLERANCE
    sample = float(grid[1] - grid[0]) if len(grid) > 1 else float(grid[0])
    result = run_scene_full(scene, mode="monolithic", tolerance=REFERENCE_TOLERANCE,
                            step=sample, stop_time=float(grid[-1]), plot=False).result
    return sample_rows(result["time"], {c: result[c] for c in compared}, grid)


# --- the runs: each returns {"values": Columns, "setup_s", "run_s", "steps"} ------------
def _ssd(ssp: Path):
    """(components {name: resources path}, connections [(source, target, factor)]) of the
    SSP, read here because fmpy's reader drops the LinearTransformation."""
    ns = {"ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription",
          "ssc": "http://ssp-standard.org/SSP1/SystemStructureCommon"}
    with zipfile.ZipFile(ssp) as archive:
        root = ET.fromstring(archive.read("SystemStructure.ssd"))
    components = {c.get("name"): c.get("source")
                  for c in root.iterfind("ssd:System/ssd:Elements/ssd:Component", ns)}
    connections = []
    for c in root.iterfind("ssd:System/ssd:Connections/ssd:Connection", ns):
        transform = c.find("ssc:LinearTransformation", ns)
        factor = 1.0 if transform is None else float(transform.get("factor", "1"))
        connections.append(((c.get("startElement"), c.get("startConnector")),
                            (c.get("endElement"), c.get("endConnector")), factor))
    return components, connections


def run_fmpy_loop(ssp: Path, h: float, stop: float, sample: float, compared: list[str],
                  workdir: Path) -> dict:
    """A plain fixed-step Jacobi master over fmpy's FMI 2 calls: at each communication
    point every connected output is read, multiplied by its factor and set, then every
    FMU steps h; the inputs are exchanged once after initialization."""
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave

    started = time.process_time()
    components, connections = _ssd(ssp)
    with zipfile.ZipFile(ssp) as archive:
        archive.extractall(workdir)
    fmus, vrs = {}, {}
    for name, source in components.items():
        path = workdir / source
        md = read_model_description(path)
        vrs[name] = {v.name: v.valueReference for v in md.modelVariables}
        fmu = FMU2Slave(guid=md.guid, unzipDirectory=extract(path, unzipdir=workdir / name),
                        modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        fmu.instantiate()
        fmu.setupExperiment(startTime=0.0)
        fmu.enterInitializationMode()
        fmu.exitInitializationMode()
        fmus[name] = fmu
    # per FMU: the value references it is read at, and those it is set at (with where
    # each input's value comes from: an index into the values read)
    reads = {n: [] for n in fmus}
    where = []
    for (sn, sv), (tn, tv), factor in connections:
        reads[sn].append(vrs[sn][sv])
        where.append((sn, len(reads[sn]) - 1, tn, vrs[tn][tv], factor))
    writes = {n: ([vr for s, i, t, vr, f in where if t == n],
                  [(s, i, f) for s, i, t, vr, f in where if t == n]) for n in fmus}
    wanted = [(split_ref(c)[0], vrs[split_ref(c)[0]][split_ref(c)[1]]) for c in compared]

    def exchange():
        got = {n: fmus[n].getReal(r) if r else [] for n, r in reads.items()}
        for n, (refs, sources) in writes.items():
            if refs:
                fmus[n].setReal(refs, [got[s][i] * f for s, i, f in sources])

    per, rows = round(sample / h), []
    stepping = time.process_time()
    t, n_samples = 0.0, round(stop / sample)
    for j in range(n_samples):
        for i in range(per):
            exchange()
            for fmu in fmus.values():
                fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
            t = (j * per + i + 1) * h
        rows.append([fmus[n].getReal([vr])[0] for n, vr in wanted])
    done = time.process_time()
    for fmu in fmus.values():
        fmu.terminate()
        fmu.freeInstance()
    rows = np.asarray(rows, float)
    return {"values": Columns({c: rows[:, k] for k, c in enumerate(compared)}),
            "setup_s": stepping - started, "run_s": done - stepping, "steps": per * n_samples}


def run_libcosim(ssp: Path, h: float, stop: float, sample: float, compared: list[str],
                 workdir: Path) -> dict:
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver

    log_output_level(CosimLogLevel.ERROR)
    step_ns, sample_ns = round(h * 1e9), round(sample * 1e9)
    if sample_ns % step_ns:
        raise ValueError(f"the step {h!r} s does not divide the sample {sample!r} s in ns")
    per, n_samples = sample_ns // step_ns, round(stop / sample)
    started = time.process_time()
    execution = CosimExecution.from_ssp_file(str(ssp), step_size=step_ns)
    observer = CosimObserver.create_last_value()
    execution.add_observer(observer)
    read = libcosim_reader(execution, observer, compared)
    stepping = time.process_time()
    rows = []
    for _ in range(n_samples):
        if not execution.step(per):
            raise RuntimeError(f"libcosim failed at {execution.status().current_time * 1e-9} s")
        rows.append(read())
    done = time.process_time()
    rows = np.asarray(rows, float)
    return {"values": Columns({c: rows[:, k] for k, c in enumerate(compared)}),
            "setup_s": stepping - started, "run_s": done - stepping, "steps": per * n_samples}


def run_ecos(ssp: Path, h: float, stop: float, sample: float, compared: list[str],
             workdir: Path) -> dict:
    ecospy = load_ecospy()
    ecospy.EcosLib.set_log_level("err")
    per, n_samples = round(sample / h), round(stop / sample)
    names = ["::".join(split_ref(c)) for c in compared]
    started = time.process_time()
    sim = ecospy.EcosSimulation(ssp_path=str(ssp), step_size=h)
    try:
        sim.init()
        stepping = time.process_time()
        rows = []
        for _ in range(n_samples):
            sim.step(per)
            rows.append([sim.get_real(n) for n in names])
        done = time.process_time()
        if abs(sim.get_time() - stop) > 1e-6 * stop:
            raise RuntimeError(f"ecos stopped at {sim.get_time()} s, not {stop} s")
    finally:
        sim.terminate()
        sim.free()
    rows = np.asarray(rows, float)
    return {"values": Columns({c: rows[:, k] for k, c in enumerate(compared)}),
            "setup_s": stepping - started, "run_s": done - stepping, "steps": per * n_samples}


def run_ours(build, h: float | None, stop: float, sample: float, compared: list[str],
             tol: float | None = None, fmu_tolerance: float = TOLERANCE) -> dict:
    """The compiled engine: fixed steps of `h` (tol None), or its default scheme at step
    tolerance `tol` (output every `sample`), the FMUs' solvers at `fmu_tolerance`. The
    whole call is timed."""
    from assemblies.engine.cosim import DEFAULT_SCHEME, cosimulate
    scheme = (dict(adaptive=False, extrapolation=0) if tol is None
              else dict(DEFAULT_SCHEME, tol=tol))
    asm = build()
    started = time.process_time()
    result = cosimulate(asm, stop, sample if tol is not None else h, fmu_tolerance,
                        record=compared, **scheme)
    spent = time.process_time() - started
    grid = sample_grid(stop, sample)
    return {"values": sample_rows(result["time"], {c: result[c] for c in compared}, grid),
            "setup_s": result.settings["setup_s"], "run_s": spent,
            "steps": int(result.settings["steps"]), "do_steps": int(result.settings["do_steps"])}


# --- the step search ------------------------------------------------------------------
def divisors(n: int) -> list[int]:
    small = [d for d in range(1, math.isqrt(n) + 1) if n % d == 0]
    return sorted(set(small + [n // d for d in small]))


def step_ladder(sample: float, finest: float = 1e-6) -> list[int]:
    """The k (h = sample / k, h a whole number of ns) tried, each about 2x the last."""
    ks, out = [k for k in divisors(round(sample * 1e9)) if sample / k >= finest], []
    for k in ks:
        if not out or k >= 1.9 * out[-1]:
            out.append(k)
    return out


def search(try_run, knobs: list, target: float, budget_s: float, between=lambda a, b: [],
           cost=lambda knob, last: None) -> dict:
    """The cheapest knob that reaches `target` (module doc). `knobs` go from coarse to
    fine; `try_run(knob)` returns a run with "error" and "run_s"; `between(a, b)` lists
    the knobs strictly between two neighbours, coarse to fine (the bisection's);
    `cost(knob, last)` estimates a knob's CPU seconds from the last try (None: unknown).
    Returns {"reached", "chosen" (when reached) or "why", "best", "tried"}, each try as
    (knob, error, run_s, run)."""
    tried, best, previous, hit, why = [], None, None, None, "the finest setting tried"

    def attempt(knob):
        nonlocal best
        run = try_run(knob)
        tried.append((knob, run["error"], run["run_s"], run))
        if best is None or run["error"] < best[1]:
            best = tried[-1]
        return run["error"] <= target

    for knob in knobs:
        estimate = cost(knob, tried[-1] if tried else None)
        if estimate is not None and estimate > budget_s:
            why = f"the next step would cost ~{estimate:.0f} s CPU (over the {budget_s:g} s budget)"
            # the finest setting short of that rung that the budget affords, once
            last = tried[-1]
            affordable = [k for k in between(previous, knob) if cost(k, last) <= budget_s]
            if previous is None or not affordable:
                break
            knob = affordable[-1]
            if not attempt(knob):
                break
            hit = len(tried) - 1
            break
        if attempt(knob):
            hit = len(tried) - 1
            break
        previous = knob
        # the error stopped falling: two tries in a row no better than 0.9 x the best before
        if len(tried) >= 3 and not min(t[1] for t in tried[-2:]) < 0.9 * min(
                t[1] for t in tried[:-2]):  # (never below: inf, a run never right)
            why = "the error stopped falling"
            break
    if hit is None:
        return {"reached": False, "why": why, "best": best, "tried": tried}
    chosen = tried[hit]
    candidates = between(previous, chosen[0]) if previous is not None else []
    lo, hi = -1, len(candidates)  # candidates[lo] misses, candidates[hi] meets
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if attempt(candidates[mid]):
            hi, chosen = mid, tried[-1]
        else:
            lo = mid
    return {"reached": True, "chosen": chosen, "best": best, "tried": tried}


# --- one scene ------------------------------------------------------------------------
def tools(scene_name: str, build, ssp: Path, stop: float, sample: float,
          compared: list[str], workdir: Path) -> dict:
    """{tool: run(knob)} where the knob is k (h = sample / k) for the fixed steps and
    (step tolerance, FMU tolerance) for ours."""
    def peer(runner):
        def run(k):
            with tempfile.TemporaryDirectory(dir=workdir) as tmp, \
                    contextlib.redirect_stdout(io.StringIO()):
                return runner(ssp, sample / k, stop, sample, compared, Path(tmp))
        return run
    return {"libcosim": peer(run_libcosim), "ecos": peer(run_ecos),
            "fmpy loop": peer(run_fmpy_loop),
            "ours fixed": lambda k: run_ours(build, sample / k, stop, sample, compared),
            OURS: lambda knob: run_ours(build, None, stop, sample, compared, tol=knob[0],
                                        fmu_tolerance=knob[1])}


def measure_scene(scene_name: str, compared: list[str], targets, repeats: int,
                  budget_s: float, workdir: Path, log=print, stop: float | None = None,
                  sample: float = SAMPLE, only=None) -> dict:
    from assemblies.scenes import scene
    from assemblies.ssp import export_ssp

    sc = scene(scene_name)
    # the scene's stop time, down to the error grid (moving_table's is a number of periods)
    stop = sample * math.floor(sc.stop_time / sample + 1e-9) if stop is None else stop
    grid = sample_grid(stop, sample)
    ref = reference(scene_name, compared, grid)
    ssp = export_ssp(sc.build(), workdir / f"{scene_name}.ssp", stop)
    runs = tools(scene_name, sc.build, ssp, stop, sample, compared, workdir)
    # ours: the FMUs' default tolerance first (the peers'), then the scene's where the
    # first cannot reach the target
    fmu_tolerances = sorted({TOLERANCE, sc.tolerance}, reverse=True)
    if only:
        runs = {t: r for t, r in runs.items() if t in only}
    ladder, every_k = step_ladder(sample), divisors(round(sample * 1e9))

    def steps_between(a, b):
        return [k for k in every_k if a < k < b]

    def tols_between(a, b):  # a fifth of a decade apart, the FMU tolerance kept
        n = max(1, round(5 * math.log10(a[0] / b[0])))
        return [(a[0] * (b[0] / a[0]) ** (i / n), a[1]) for i in range(1, n)]
    out = {"scene": scene_name, "when": time.strftime("%Y-%m-%d %H:%M"),
           "repeats": repeats, "budget_s": budget_s,
           "load_average_before": os.getloadavg()[0], "stop_time": stop, "sample": sample,
           "compared": compared,
           "fmus": len(sc.build().components), "ours_fmu_tolerance": sc.tolerance,
           "targets": {}}
    done: dict = {}  # (tool, knob) -> run: a setting tried for one target serves the next
    errors: dict[str, str] = {}
    for target in targets:
        rows = {}
        for tool, run in runs.items():
            if tool in errors:
                rows[tool] = {"error": errors[tool]}
                continue

            def try_run(knob, run=run, tool=tool):
                if (tool, knob) in done:
                    return done[tool, knob]
                r = done[tool, knob] = run(knob)
                r["error"] = error(r["values"], ref)
                log(f"  {scene_name} {tool:10s} {_knob_text(tool, knob, sample)}: error "
                    f"{r['error']:.2e}, {r['run_s']:.3f} s CPU, {r['steps']} steps")
                return r

            def cost(knob, last, tool=tool):
                if tool == OURS or last is None:
                    return None
                return last[2] * knob / last[0]  # CPU per step times the steps
            try:
                if tool == OURS:
                    for fmu_tol in fmu_tolerances:
                        knobs = [(tol, fmu_tol) for tol in TOLS]
                        this = search(try_run, knobs, target, budget_s, tols_between, cost)
                        if this["reached"]:
                            found = this
                            break
                        if fmu_tol == fmu_tolerances[0] or this["best"][1] < found["best"][1]:
                            found = this
                else:
                    found = search(try_run, ladder, target, budget_s, steps_between, cost)
            except Exception as exc:  # a tool that refuses the SSP: reported, not hidden
                errors[tool] = f"{type(exc).__name__}: {exc}".splitlines()[0][:300]
                rows[tool] = {"error": errors[tool]}
                log(f"  {scene_name} {tool}: not measured: {errors[tool]}")
                continue
            rows[tool] = _row(tool, found, sample)
        _time_round_robin(rows, runs, repeats, sample)
        out["targets"][f"{target:g}"] = rows
    return out


def _knob_text(tool: str, knob, sample: float) -> str:
    return (f"tol {knob[0]:.0e}, FMUs {knob[1]:.0e}" if tool == OURS
            else f"h {sample / knob:.3g} s")


def _row(tool: str, found: dict, sample: float) -> dict:
    tried = [{"knob": k, "error": e, "run_s": s} for k, e, s, _ in found["tried"]]
    best = found["best"]
    row = {"reached": found["reached"], "tried": tried,
           "smallest_error": best[1] if best else None}
    if not found["reached"]:
        row["why"] = found["why"]
        return row
    knob, err, _, run = found["chosen"]
    row.update(knob=knob, error_reached=err, steps=run["steps"], setup_s=run["setup_s"],
               do_steps=run.get("do_steps"))
    if tool == OURS:
        row["tol"], row["fmu_tolerance"] = knob
    else:
        row["h"] = sample / knob
    return row


def _time_round_robin(rows: dict, runs: dict, repeats: int, sample: float) -> None:
    """Each reached setting again `repeats` times, the tools in turn (module doc)."""
    chosen = {t: r["knob"] for t, r in rows.items() if r.get("reached")}
    times = {t: [] for t in chosen}
    for _ in range(repeats):
        for tool, knob in chosen.items():
            with contextlib.redirect_stdout(io.StringIO()):
                times[tool].append(runs[tool](knob)["run_s"])
    for tool, ts in times.items():
        r = rows[tool]
        r["cpu_s"] = ts
        r["cpu_median_s"] = statistics.median(ts)
        r["per_step_us"] = r["cpu_median_s"] / r["steps"] * 1e6


# --- the report -----------------------------------------------------------------------
def ratios(rows: dict) -> dict:
    """{tool: (median ratio, low, high)} of each tool's CPU time over ours (> 1: ours is
    faster); the range from the extremes of the repeats."""
    ours = rows.get(OURS, {})
    if "cpu_s" not in ours:
        return {}
    out = {}
    for tool, r in rows.items():
        if tool != OURS and "cpu_s" in r:
            out[tool] = (r["cpu_median_s"] / ours["cpu_median_s"],
                         min(r["cpu_s"]) / max(ours["cpu_s"]),
                         max(r["cpu_s"]) / min(ours["cpu_s"]))
    return out


def table_rows(data: dict) -> list[list[str]]:
    """One row per scene, target and tool: the cells of the report's table."""
    out = []
    for scene in data["scenes"]:
        for target, rows in scene["targets"].items():
            rat = ratios(rows)
            for tool, r in rows.items():
                if "error" in r:
                    out.append([scene["scene"], target, tool, "not run", "", "", "", "", "",
                                r["error"]])
                    continue
                if not r["reached"]:
                    out.append([scene["scene"], target, tool, "cannot reach", "", "", "", "",
                                "", f"smallest error {r['smallest_error']:.2e}: {r['why']}"])
                    continue
                setting = (f"tol {r['tol']:.0e}, FMUs {r['fmu_tolerance']:.0e}" if tool == OURS
                           else f"h = {r['h']:.3g} s")
                ratio = rat.get(tool)
                note = (f"{r['do_steps'] / r['steps']:.1f} doSteps a step; setup "
                        f"{r['setup_s'] * 1e3:.1f} ms (wall)" if r.get("do_steps")
                        else f"setup {r['setup_s'] * 1e3:.1f} ms")
                out.append([scene["scene"], target, tool, setting, f"{r['error_reached']:.2e}",
                            f"{r['cpu_median_s'] * 1e3:.1f} ({min(r['cpu_s']) * 1e3:.1f}-"
                            f"{max(r['cpu_s']) * 1e3:.1f})",
                            f"{r['steps']}", f"{r['per_step_us']:.2f}",
                            "" if ratio is None else f"{ratio[0]:.1f} ({ratio[1]:.1f}-{ratio[2]:.1f})",
                            note])
    return out


HEADER = ["scene", "error ≤", "tool", "setting", "error", "CPU ms median (range)",
          "comm. steps", "µs / comm. step", "x ours (range)", "note"]


def table(data: dict) -> str:
    rows = [HEADER] + table_rows(data)
    widths = [max(len(r[i]) for r in rows) for i in range(len(HEADER) - 1)]
    return "\n".join("  ".join(c.ljust(w) for c, w in zip(r, widths)) + "  " + r[-1]
                     for r in rows)


def results_section(data: dict) -> list[str]:
    out = ["## Peer co-simulation masters (issue 27)", "",
           "From `python -m benchmarks.peers [--scenes …] [--repeats N] [--budget S] "
           f"--results` ({data['machine']}; each scene's run below); raw: "
           "`benchmarks/peers.json`. The same FMI 2 CS FMUs of ours, wired by the scene's SSP, "
           "run by libcosim (libcosimpy), Ecos (ecospy), a plain Python master over fmpy's FMI "
           "calls, our engine at fixed steps (`--fixed-step`: Jacobi, zero-order hold, the "
           "peers' scheme) and our default co-simulation (adaptive, quadratic extrapolation, "
           "events synchronised). The peers' FMUs and ours at fixed steps solve at the "
           f"FMUs' default tolerance {data['fmu_tolerance']:g} (what an FMI 2 tool gets); ours "
           "adaptive too where that reaches the target, else at the scene's tolerance (what "
           "`mechfmu run SCENE` uses). "
           "Each at the largest step (ours: the largest tolerance) whose "
           "error is within the target: the largest deviation of the bodies' positions and "
           f"velocities on a {data['sample']:g} s grid from the composite FMU at tolerance "
           "1e-12, weighed by max(1, |largest value|). CPU time (process time, every thread) "
           "of N runs round-robin, median (range); a peer's stepping only "
           "(SSP loading and instantiation apart), ours the whole call. x ours: the tool's "
           "CPU time over ours (range: extremes of the repeats). A tool that cannot reach an "
           "error says why (a try estimated above the budget of CPU seconds is not run) and "
           "the smallest error it reached.", "",
           "| " + " | ".join(HEADER) + " |", "|" + "---|" * len(HEADER)]
    out += ["| " + " | ".join(r) + " |" for r in table_rows(data)]
    out.append("")
    for sc in data["scenes"]:
        out.append(f"- {sc['scene']}: {sc['fmus']} FMUs, 0 to {sc['stop_time']:g} s, compared "
                   f"{', '.join(sc['compared'])}; the scene's tolerance "
                   f"{sc['ours_fmu_tolerance']:g}; measured {sc.get('when', '?')}, load "
                   f"{sc.get('load_average_before', math.nan):.1f}, "
                   f"{sc.get('repeats', data['repeats'])} repeats, budget "
                   f"{sc.get('budget_s', data['budget_s']):g} s.")
    return out + [""]


def merged(data: dict, path: Path) -> dict:
    """`data` with the scenes an earlier run wrote into `path` and this one did not
    measure (each scene says when and under what load it was measured)."""
    try:
        before = json.loads(path.read_text())
        earlier = before["scenes"]
    except (OSError, ValueError, KeyError, TypeError):
        return data
    ran = {s["scene"] for s in data["scenes"]}
    order = list(SCENES)
    # a kept scene keeps the settings of the run that measured it
    scenes = [dict({k: before[k] for k in ("repeats", "budget_s") if k in before}, **s)
              for s in earlier if s.get("scene") in SCENES and s["scene"] not in ran]
    scenes = sorted(scenes + data["scenes"], key=lambda s: order.index(s["scene"]))
    return dict(data, scenes=scenes)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.peers",
                                 description=__doc__.splitlines()[0])
    ap.add_argument("--scenes", nargs="+", default=list(SCENES), choices=list(SCENES))
    ap.add_argument("--targets", nargs="+", type=float, default=list(TARGETS))
    ap.add_argument("--repeats", type=int, default=3, help="timed runs of each tool, "
                                                          "round-robin (default 3)")
    ap.add_argument("--budget", type=float, default=60.0,
                    help="CPU seconds a try may be estimated to cost (default 60)")
    ap.add_argument("--stop", type=float, help="stop time [s] (default: the scene's)")
    ap.add_argument("--tools", nargs="+", choices=[*PEERS, OURS], help="a subset of tools")
    ap.add_argument("--json", default=str(JSON_PATH))
    ap.add_argument("--results", action="store_true",
                    help="also write the section of benchmarks/RESULTS.md")
    ap.add_argument("--from-json", action="store_true",
                    help="measure nothing: the table (and with --results the section) "
                         "from the JSON file an earlier run wrote")
    args = ap.parse_args(argv)
    if args.from_json:
        data = json.loads(Path(args.json).read_text())
        print(table(data))
        if args.results:
            from .run_all import replace_section
            replace_section(HERE / "RESULTS.md", results_section(data))
            print(f"wrote {HERE / 'RESULTS.md'}")
        return 0
    if args.repeats < 1:
        ap.error("--repeats must be at least 1")
    if any(not 0 < t < 1 for t in args.targets):
        ap.error("--targets must lie in (0, 1)")
    if args.stop is not None and (args.stop < SAMPLE or abs(args.stop / SAMPLE
                                                           - round(args.stop / SAMPLE)) > 1e-9):
        ap.error(f"--stop must be a positive multiple of the {SAMPLE:g} s error grid")
    load_before = os.getloadavg()[0]
    data = {"when": time.strftime("%Y-%m-%d %H:%M"),
            "machine": f"{platform.node()}, {os.cpu_count()} cores, "
                       f"Python {platform.python_version()}",
            "repeats": args.repeats, "budget_s": args.budget, "sample": SAMPLE,
            "fmu_tolerance": TOLERANCE, "scenes": []}
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.scenes:
            data["scenes"].append(measure_scene(
                name, SCENES[name], sorted(args.targets, reverse=True), args.repeats,
                args.budget, Path(tmp), log=lambda s: print(s, file=sys.stderr, flush=True),
                stop=args.stop, only=args.tools))
            data["load_average"] = [load_before, os.getloadavg()[0]]
            # after each scene: a long run stopped later keeps what it measured
            Path(args.json).write_text(json.dumps(merged(data, Path(args.json)), indent=1,
                                                  default=float) + "\n")
    print(table(data))
    data = merged(data, Path(args.json))
    Path(args.json).write_text(json.dumps(data, indent=1, default=float) + "\n")
    print(f"wrote {args.json}")
    if args.results:
        from .run_all import replace_section
        replace_section(HERE / "RESULTS.md", results_section(data))
        print(f"wrote {HERE / 'RESULTS.md'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
