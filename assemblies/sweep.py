"""Parameter studies: a scene run over a grid or a Latin hypercube of its parameters,
start values and options, on Dask, one row per run in a labelled table.

Dask runs the study: a local cluster of worker processes by default, or any running
scheduler (``scheduler="tcp://host:8786"``). Runs go to the workers in chunks, since
one run of a friction scene takes a few milliseconds, as much as Dask's own cost of a
task. A worker process keeps what the engine prepares once per process and reuses it
for every later run: each FMU built or found in the cache, extracted and its model
description read once (:mod:`assemblies.engine.prepare`, keyed by class, profile and
options, so an option that shapes the binary gets its own), its shared library loaded
once and never unloaded, and the engine's plan of a structure (:mod:`assemblies.engine.me`).
Only the parameter and start values change from run to run. The engine instantiates
each FMU afresh for a run instead of resetting it: measured on stick_slip, a run's whole
fixed cost (assembly, values, instantiation, initialisation, freeing) is 0.5 ms, against
about 70 ms for the first run in a process, which prepares and loads.

A run that fails (an unphysical combination: a negative mass, a static friction below
the kinetic one) is a row with ``status == "failed"`` and its one-line error; the other
runs go on. Results: :func:`sweep` returns a pandas DataFrame, :func:`write_sweep`
writes it as CSV with a JSON of the study beside it and a plot (:mod:`.sweep_plot`).
"""
from __future__ import annotations

import contextlib
import copy
import functools
import itertools
import json
import logging
import math
import os
import socket
import time as wallclock
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np
import pandas as pd

from components.errors import SimulationError, writable_folder
from components.interfaces import ComponentError

from .assembly import Assembly, AssemblyError
from .limits import check_sweep_runs, check_workers
from .scenes import Scene, scene

REDUCTIONS = ("end", "max", "min", "absmax")
SMALLEST_SHARE = 16  # the smallest task holds a 16th of one worker's share of the runs


class SweepError(AssemblyError):
    """A study that cannot start: a parameter or output it names, its design, its Dask."""


# --- what a study reads from each run ----------------------------------------------------
@dataclass(frozen=True)
class Output:
    """One number of a run's result: `column` at time `at`, or reduced over the run
    (``end``, ``max``, ``min``, ``absmax``); written ``column@at``."""
    column: str
    at: str = "end"

    @property
    def label(self) -> str:
        return f"{self.column}@{self.at}"

    def read(self, result) -> float:
        values = result[self.column]
        if self.at == "end":
            return float(values[-1])
        if self.at == "max":
            return float(np.max(values))
        if self.at == "min":
            return float(np.min(values))
        if self.at == "absmax":
            return float(np.max(np.abs(values)))
        t = float(self.at)
        times = result["time"]
        if not times[0] <= t <= times[-1]:  # a run that ended early (terminated) has no value
            return math.nan
        return float(np.interp(t, times, values))


def parse_output(text: str) -> Output:
    """``NAME@T`` (T a time in s, or end, max, min, absmax); a bare NAME is its end value."""
    column, at, where = text.partition("@")
    where = where.strip() or "end"
    if not column.strip() or (at and not where):
        raise SweepError(f"output '{text}' must be NAME@T, T a time or one of "
                         f"{', '.join(REDUCTIONS)}")
    if where not in REDUCTIONS:
        try:
            float(where)
        except ValueError:
            raise SweepError(f"output '{text}': '{where}' is neither a time nor one of "
                             f"{', '.join(REDUCTIONS)}") from None
    return Output(column.strip(), where)


# --- the design: which runs ----------------------------------------------------------------
def _number(name: str, text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise SweepError(f"--param {name}: '{text}' is not a number") from None


def parse_values(name: str, spec) -> list:
    """One parameter's values as given: ``"START:STOP:COUNT"`` (evenly spaced, ends
    included), ``"START:STOP"`` (a range, for a random design), ``"A,B,C"``, one value,
    or in Python any sequence of values or a single value."""
    if not isinstance(spec, str):
        values = list(np.atleast_1d(np.asarray(spec, dtype=object)))
        if not values:
            raise SweepError(f"parameter {name}: no values given")
        return values
    parts = spec.split(":")
    if len(parts) == 1:
        return [v.strip() for v in spec.split(",")]
    if len(parts) == 2:
        return [_number(name, parts[0]), _number(name, parts[1])]
    if len(parts) != 3:
        raise SweepError(f"--param {name}={spec}: must be START:STOP:COUNT, A,B,C or a value")
    start, stop = _number(name, parts[0]), _number(name, parts[1])
    try:
        count = int(parts[2])
    except ValueError:
        count = 0
    if count < 1:
        raise SweepError(f"--param {name}={spec}: COUNT must be a whole number >= 1, "
                         f"not '{parts[2]}'")
    check_sweep_runs(count, f"--param {name}={spec}")  # before its values are made
    return list(np.linspace(start, stop, count)) if count > 1 else [start]


def design(params: dict, random: int | None = None, seed: int | None = None) -> list[dict]:
    """The runs, each a dict of values by parameter name.

    A grid by default: every combination of the parameters' values, the first parameter
    varying slowest. With `random` = N: N points of a Latin hypercube (`seed` makes it
    repeatable), each parameter with several values varying over [min, max] of them
    (``START:STOP`` or ``START:STOP:COUNT``, COUNT then unused); one value stays fixed.
    """
    axes = {name: parse_values(name, spec) for name, spec in params.items()}
    if random is None:
        check_sweep_runs(math.prod(len(v) for v in axes.values()),
                         "the grid of " + " x ".join(f"{len(v)} {n}" for n, v in axes.items()))
        return [dict(zip(axes, combo)) for combo in itertools.product(*axes.values())]
    if not (isinstance(random, (int, np.integer)) and not isinstance(random, bool)
            and random >= 1):
        raise SweepError(f"--random must be a whole number of runs >= 1, not {random!r}")
    check_sweep_runs(random, f"--random {random}")
    from scipy.stats import qmc
    ranges = {}
    for name, values in axes.items():
        if len(values) > 1:
            try:
                numbers = [float(v) for v in values]
            except (TypeError, ValueError):
                raise SweepError(f"parameter {name}: a random design varies numbers, not "
                                 f"{', '.join(map(str, values))}") from None
            ranges[name] = (min(numbers), max(numbers))
    unit = qmc.LatinHypercube(d=max(1, len(ranges)), rng=seed).random(int(random))
    fixed = {name: values[0] for name, values in axes.items() if name not in ranges}
    return [{**fixed, **{name: lo + u * (hi - lo) for (name, (lo, hi)), u in zip(ranges.items(),
                                                                                 point)}}
            for point in unit]


# --- one run, on a worker ------------------------------------------------------------------
def _no_figures(result, asm) -> list:
    return []


def as_scene(target, stop_time: float | None = None, step: float | None = None,
             tolerance: float | None = None) -> Scene:
    """A scene name, a Scene, or an Assembly (then `stop_time` and `step` are needed; it
    has no figures, a study reads its outputs) as the Scene a study runs."""
    if isinstance(target, str):
        return scene(target)
    if isinstance(target, Scene):
        return target
    if isinstance(target, Assembly):
        if stop_time is None or step is None:
            raise SweepError(f"assembly '{target.name}': a study of an assembly needs "
                             "stop_time and step (a scene has its own)")
        return Scene(target.name, f"assembly {target.name}", functools.partial(copy.deepcopy,
                                                                                target),
                     stop_time, step, tolerance or 1e-8, None, _no_figures)
    raise SweepError(f"a study runs a scene name, a Scene or an Assembly, not "
                     f"{type(target).__name__}")


def one_line(exc: BaseException) -> str:
    """The error of a failed run as the table keeps it: our errors are one line already,
    anything else is named by its type."""
    text = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
    if isinstance(exc, (ComponentError, AssemblyError, SimulationError)):
        return text
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


_runs_here = 0  # runs done in this process: what worker_state reports


def run_one(sc: Scene, index: int, values: dict, settings: dict, outputs=(),
            measure: Callable | None = None) -> dict:
    """One run of the study as a row: its values, its figures' measured values (and
    ``NAME.ref``, the reference), the outputs, what `measure(result, values)` returns,
    ``passed`` (every figure within its accuracy), ``status`` and ``error``."""
    from .run import run_scene_full  # here: the registry is imported once a worker runs
    global _runs_here
    _runs_here += 1
    started = wallclock.perf_counter()
    row = {"run": index, **values, "status": "ok", "error": ""}
    try:
        run = run_scene_full(sc, params=values, **settings)
        for f in run.figures:
            row[f.name], row[f"{f.name}.ref"] = float(f.measured), float(f.reference)
        # taken out of the row into the table's attrs by sweep()
        row["units"] = {f.name: f.unit for f in run.figures if f.unit}
        row["passed"] = run.passed if run.figures else math.nan
        for out in outputs:
            row[out.label] = out.read(run.result)
        if measure is not None:
            row.update(measure(run.result, values))
    except Exception as exc:  # noqa: BLE001 - a failed run is a row, the study goes on
        row["status"], row["error"] = "failed", one_line(exc)
    row["wall_s"] = wallclock.perf_counter() - started
    row["worker"] = f"{socket.gethostname()}:{os.getpid()}"
    return row


def run_chunk(sc: Scene, runs: list, settings: dict, outputs=(), measure=None) -> list[dict]:
    """A worker's task: several runs one after another, in one process."""
    return [run_one(sc, i, values, settings, outputs, measure) for i, values in runs]


def worker_state() -> dict:
    """What this process has prepared and run (``client.run(worker_state)`` asks every
    worker): FMU files extracted and read, engine plans kept, runs done."""
    from .engine import me
    from .engine.prepare import prepared_path
    return {"pid": os.getpid(), "fmus_loaded": prepared_path.cache_info().currsize,
            "plans": len(me._plans), "runs": _runs_here}


# --- the study -------------------------------------------------------------------------------
@contextlib.contextmanager
def dask_client(workers: int | None = None, scheduler=None):
    """A Dask client: to `scheduler` (an address; a Client is used as it is and left
    open), else to a local cluster of `workers` processes (default: one per core) that
    is closed afterwards."""
    from distributed import Client, LocalCluster
    if scheduler is not None and workers is not None:
        raise SweepError("give workers (a local cluster) or scheduler (a running one), not both")
    if scheduler is not None and not isinstance(scheduler, str):
        yield scheduler
        return
    if scheduler is not None:
        try:
            client = Client(scheduler, timeout="10s")
        except (OSError, TimeoutError) as exc:
            raise SweepError(f"cannot reach the Dask scheduler at {scheduler}: "
                             f"{one_line(exc)}") from None
        try:
            yield client
        finally:
            client.close()
        return
    n = (os.cpu_count() or 1) if workers is None else check_workers(workers)
    # no dashboard; the scheduler's HTTP server (it always has one) on a free port, not on
    # 8787, which another cluster on the machine may hold
    with LocalCluster(n_workers=int(n), threads_per_worker=1, processes=True,
                      dashboard_address=None, silence_logs=logging.ERROR,
                      scheduler_kwargs={"dashboard_address": "127.0.0.1:0"}) as cluster, \
            Client(cluster) as client:
        yield client


def _check_names(sc: Scene, names, outputs) -> Assembly:
    """Every parameter and output the study names exists: one line now, not a failed
    run per point. Returns the scene's assembly."""
    asm = sc.build()
    for name in names:
        instance, dot, key = name.partition(".")
        if not dot or not key:
            raise SweepError(f"parameter '{name}' must be INSTANCE.NAME, e.g. block.mu_s")
        comp = asm.component(instance)
        settable = comp.settable_names() if hasattr(comp, "settable_names") else None
        if settable is not None and key not in settable:
            raise SweepError(f"parameter '{name}': {instance} has no '{key}'; settable: "
                             f"{', '.join(settable)}")
    if sc.record is not None:
        recorded = ["time", *sc.record]
        for out in outputs:
            if out.column not in recorded:
                raise SweepError(f"output '{out.label}': scene '{sc.name}' records "
                                 f"{', '.join(recorded)}")
    return asm


def _units(asm: Assembly, params, outputs, rows) -> dict[str, str]:
    """The unit of each column that has one: a parameter's or an output's as its component
    declares it, a figure's (and its reference's) as its description states it."""
    from .plot import column_units
    declared = column_units(asm, [*params, *(o.column for o in outputs)])
    units = {name: declared[name] for name in params if name in declared}
    units.update({o.label: declared[o.column] for o in outputs if o.column in declared})
    for row in rows:
        for name, unit in row.pop("units", {}).items():
            units[name] = units[f"{name}.ref"] = unit
    return units


def _check_settings(sc: Scene, stop_time, step, tolerance, mode, engine, outputs,
                    workers, chunk, start_time) -> None:
    """What every run of the study shares, checked once before the first: a bad setting
    is one line now, not the same failed row for every run."""
    from .experiment import check_experiment  # the masters' own checks, and limits
    from .run import check_choices
    stop = sc.stop_time if stop_time is None else stop_time
    start = 0.0 if start_time is None else start_time
    check_experiment(stop, sc.step if step is None else step,
                     sc.tolerance if tolerance is None else tolerance, "output step", start)
    check_choices(sc.mode if mode is None else mode, engine)
    sc.check_mode(sc.mode if mode is None else mode, sc.name)  # once, not a row per run
    for out in outputs:
        if out.at not in REDUCTIONS and not start <= float(out.at) <= stop:
            raise SweepError(f"output '{out.label}': {out.at} s is not in the run, which "
                             f"goes from {start:g} s to the stop time {stop:g} s")
    if workers not in (None, 0):
        check_workers(workers)
    if chunk is not None and (isinstance(chunk, bool) or not isinstance(chunk, (int, np.integer))
                              or chunk < 1):
        raise SweepError(f"chunk must be a whole number of runs per task >= 1, not {chunk!r}")


def sweep(target, params: dict, *, random: int | None = None, seed: int | None = None,
          outputs=(), measure: Callable | None = None, workers: int | None = None,
          scheduler=None, stop_time: float | None = None, step: float | None = None,
          tolerance: float | None = None, mode: str | None = None, engine: str = "c",
          progress: bool | Callable[[int], None] = True, chunk: int | None = None,
          out: str | Path | None = None, plot: list[str] | None = None,
          start_time: float | None = None) -> pd.DataFrame:
    """Run `target` (a scene name, a Scene, or an Assembly) over `params` on Dask.

    `params`: ``{"INSTANCE.NAME": values}``, values as :func:`parse_values` reads them
    (``"0.6:1.0:9"``, a list, one value); a grid, or with `random` a Latin hypercube of
    that many runs (:func:`design`). `outputs`: ``"NAME@T"`` texts or :class:`Output`s;
    `measure(result, values) -> {column: number}`, a module-level function, reads any
    other number. `workers`: processes of a local cluster (default one per core; 0 runs
    in this process, without Dask); `scheduler`: a running scheduler's address, or a
    ``distributed.Client``; `chunk`: runs per Dask task (default guided, long tasks first,
    :func:`chunk_sizes`). `progress`: a bar over runs on a terminal (a line every few
    seconds in a log), or a callable given the number of runs done. With `out`, writes
    the table, its JSON and a plot of `plot` columns there (:func:`write_sweep`).
    `start_time`: where each run starts (None: 0).

    What every run shares (stop time, step, tolerance, mode, engine, output times, the
    study's size against :data:`assemblies.limits.MAX_SWEEP_RUNS`, `workers` against
    :data:`assemblies.limits.WORKERS_PER_CORE`, `out`) is checked before the first run:
    a mistake there is one SweepError or AssemblyError, not a failed row per run.

    Returns one row per run, in design order: ``run``, the parameters, ``status``
    (``ok``/``failed``), ``error``, the scene's figures (measured; ``NAME.ref`` the
    reference), ``passed``, the outputs, ``wall_s`` and ``worker``; ``table.attrs``
    describes the study.
    """
    sc = as_scene(target, stop_time, step, tolerance)
    outputs = [o if isinstance(o, Output) else parse_output(o) for o in outputs]
    _check_settings(sc, stop_time, step, tolerance, mode, engine, outputs, workers, chunk,
                    start_time)
    if out is not None:  # before the study, not after it
        out = writable_folder(out, "out", SweepError)
    runs = design(params, random, seed)
    asm = _check_names(sc, list(params), outputs)
    settings = {k: v for k, v in dict(stop_time=stop_time, step=step, tolerance=tolerance,
                                      mode=mode, engine=engine,
                                      start_time=start_time).items() if v is not None}
    report = _progress(progress, len(runs))
    started = wallclock.perf_counter()
    try:
        if workers == 0 and scheduler is None:
            rows, where, n_workers = [], "this process", 0
            for i, values in enumerate(runs):
                rows.append(run_one(sc, i, values, settings, outputs, measure))
                report(i + 1)
        else:
            with dask_client(workers, scheduler) as client:
                rows, where, n_workers = _on_dask(client, sc, runs, settings, outputs,
                                                  measure, chunk, report)
    finally:
        getattr(report, "close", lambda: None)()
    wall = wallclock.perf_counter() - started
    units = _units(asm, list(params), outputs, rows)
    table = pd.DataFrame(sorted(rows, key=lambda r: r["run"]))
    table.attrs = {"scene": sc.name, "description": sc.description,
                   "design": "grid" if random is None else "latin hypercube",
                   "random": random, "seed": seed,
                   "params": {k: v if isinstance(v, str) else
                              [x if isinstance(x, str) else float(x) for x in
                               parse_values(k, v)] for k, v in params.items()},
                   "varying": [k for k in params if len({str(r[k]) for r in runs}) > 1],
                   "outputs": [o.label for o in outputs], "units": units,
                   "settings": settings,
                   "runs": len(runs), "failed": int((table["status"] == "failed").sum()),
                   "workers": n_workers, "scheduler": where, "wall_s": wall,
                   "runs_per_s": len(runs) / wall if wall > 0 else math.inf}
    if out is not None:
        write_sweep(table, out, plot)
    return table


def _progress(progress, total: int):
    if callable(progress):
        return progress
    if not progress:
        return lambda done: None
    from .progress import ProgressReport
    return ProgressReport(total, name="runs", unit="")


def chunk_sizes(n_runs: int, n_workers: int, chunk: int | None = None) -> list[int]:
    """How many runs each task takes, in the order the tasks go out (`chunk`: all alike).

    Guided, as OpenMP schedules loops: each task takes half a worker's fair share of the
    runs still left, down to a 16th of a worker's share. The first tasks are long, so
    Dask's cost per task (a few ms, as much as a run) is paid rarely; the last are short, so
    the workers finish within a few runs of each other although runs differ in cost (a
    study of equal chunks lost 10-15 % of two workers' time waiting for the last chunk)."""
    if chunk:
        return [chunk] * (n_runs // chunk) + ([n_runs % chunk] if n_runs % chunk else [])
    smallest = max(1, n_runs // (n_workers * SMALLEST_SHARE))
    sizes, left = [], n_runs
    while left > 0:
        sizes.append(min(left, max(smallest, math.ceil(left / (2 * n_workers)))))
        left -= sizes[-1]
    return sizes


def _on_dask(client, sc, runs, settings, outputs, measure, chunk, report):
    from distributed import as_completed
    try:
        client.wait_for_workers(1, timeout=30)
    except TimeoutError:
        raise SweepError(f"the Dask scheduler at {client.scheduler.address} has no worker "
                         "after 30 s") from None
    n_workers = len(client.scheduler_info()["workers"])
    indexed = enumerate(runs)
    chunks = [list(itertools.islice(indexed, size))
              for size in chunk_sizes(len(runs), n_workers, chunk)]
    # the scene goes with each task: it pickles to under a kB (its build and figures go
    # by reference), less than scattering it costs in round trips before the first run
    futures = {client.submit(run_chunk, sc, c, settings, outputs, measure,
                             pure=False): c for c in chunks}
    rows = []
    for future in as_completed(futures):
        try:
            rows.extend(future.result())
        except Exception as exc:  # noqa: BLE001 - a worker lost (a crash inside an FMU):
            # its runs are failed rows, after Dask's own retries on other workers
            rows.extend({"run": i, **values, "status": "failed",
                         "error": f"its worker was lost: {one_line(exc)}"}
                        for i, values in futures[future])
        report(len(rows))
    return rows, client.scheduler.address, n_workers


# --- what a study finds ----------------------------------------------------------------------
def crossings(table: pd.DataFrame, param: str, column: str, level: float = 0.0) -> list[float]:
    """Where `column` crosses `level` along `param` (one parameter varying): linear
    interpolation between neighbouring runs that lie on either side."""
    ok = table[(table["status"] == "ok") & table[column].notna()].sort_values(param)
    x, y = ok[param].to_numpy(float), ok[column].to_numpy(float) - level
    found = []
    for i in range(len(x) - 1):
        if y[i] == 0:
            found.append(float(x[i]))
        elif y[i] * y[i + 1] < 0:
            found.append(float(x[i] - y[i] * (x[i + 1] - x[i]) / (y[i + 1] - y[i])))
    return found


@dataclass
class Boundary:
    """Where a property of the runs changes along one parameter: between `lo` and `hi`
    (the property holds at `lo`'s side as it held at the first bracket's start)."""
    lo: float
    hi: float
    table: pd.DataFrame  # every run of every round

    @property
    def value(self) -> float:
        return (self.lo + self.hi) / 2


def refine(target, param: str, start: float, stop: float, holds: Callable[[pd.Series], bool],
           *, rounds: int = 3, points: int = 5, fixed: dict | None = None,
           workers: int | None = None, scheduler=None, **options) -> Boundary:
    """Bisect for where `holds(row)` changes along `param` between `start` and `stop`:
    each round is a :func:`sweep` of `points` runs across the bracket (in parallel),
    and the next bracket is the two neighbours where it changes. `fixed`: other
    parameters, as :func:`sweep` takes them; `options`: sweep's other keywords."""
    if points < 2:
        raise SweepError(f"refine needs at least 2 points a round, not {points}")
    tables, lo, hi = [], start, stop
    with dask_client(workers, scheduler) if workers != 0 else contextlib.nullcontext(0) as client:
        where = dict(workers=0) if client == 0 else dict(scheduler=client)
        for _ in range(rounds):
            table = sweep(target, {**(fixed or {}), param: np.linspace(lo, hi, points)},
                          **where, **options)
            tables.append(table)
            failed = table[table["status"] == "failed"]
            if len(failed):
                raise SweepError(f"refine over {param}: run at {param} = "
                                 f"{failed[param].iloc[0]} failed: {failed['error'].iloc[0]}")
            verdicts = [bool(holds(row)) for _, row in table.iterrows()]
            change = next((i for i in range(points - 1) if verdicts[i] != verdicts[i + 1]), None)
            if change is None:
                raise SweepError(f"refine over {param}: no change between {lo:g} and {hi:g} "
                                 f"(it {'holds' if verdicts[0] else 'fails'} at every point)")
            lo, hi = float(table[param].iloc[change]), float(table[param].iloc[change + 1])
    return Boundary(lo, hi, pd.concat(tables, ignore_index=True))


# --- files -----------------------------------------------------------------------------------
def write_sweep(table: pd.DataFrame, out: str | Path, plot: list[str] | None = None) -> list[Path]:
    """``sweep_SCENE.csv`` (the table), ``sweep_SCENE.json`` (the study: design, settings,
    timing, failed runs with their errors) and, with one or two parameters varying,
    ``sweep_SCENE.png``; returns the paths written."""
    from .sweep_plot import check_columns, default_columns, plot_sweep
    check_columns(table, plot or [])  # a plot that cannot be made leaves no files behind
    out = writable_folder(out, "out", SweepError)
    stem = out / f"sweep_{table.attrs.get('scene', 'study')}"
    paths = [stem.with_suffix(".csv"), stem.with_suffix(".json")]
    table.to_csv(paths[0], index=False)
    failed = table[table["status"] == "failed"]
    summary = {**table.attrs, "columns": list(table.columns),
               "failed_runs": [{"run": int(r["run"]), "error": r["error"]}
                               for _, r in failed.iterrows()]}
    paths[1].write_text(json.dumps(summary, indent=2, default=float) + "\n")
    varying = table.attrs.get("varying", [])
    if 1 <= len(varying) <= 2:
        columns = plot or default_columns(table)
        if columns:
            plot_sweep(table, varying, columns, stem.with_suffix(".png"))
            paths.append(stem.with_suffix(".png"))
    return paths


__all__ = ["Boundary", "Output", "SweepError", "crossings", "dask_client", "design",
           "parse_output", "parse_values", "refine", "sweep", "worker_state", "write_sweep"]
