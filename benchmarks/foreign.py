"""Foreign FMUs through the engine and through fmpy: `python -m benchmarks.foreign [--quick]
[--json FILE] [--results]`.

A case is one FMU through one of its interfaces (ME or CS) in one FMI version; the FMUs come
from other tools (benchmarks/foreign_fmus.py: PyPI wheels, and FMUs built here by other
tools' exporters). Each case is run by

- ``fmpy``: ``fmpy.simulate_fmu`` with that interface (ME: CVode at rtol TOL; CS: fixed
  communication steps of the case's step);
- ``engine``: the engine's default for the interface, on a one-instance Assembly
  (``FMU(path)``): CS in ``cosimulate`` with ``DEFAULT_SCHEME`` (adaptive steps, which fall
  back to fixed ones, with a warning, where the FMU cannot restore its state); ME in
  ``simulate_me`` (mode ``me``) at tolerance TOL;
- ``engine fixed`` (CS only): ``cosimulate`` with fixed steps of the case's step, the run
  fmpy's CS run is directly comparable with.

References, best first: the closed form of the model where the exporter steps it exactly or
it is Model Exchange (the PI controllers, the lag, the oscillator, the adder); the embedded
FMU run alone by fmpy at the container's internal step (containers); otherwise fmpy at a
tight tolerance (ME: CVode at REF_TOL) or at the case's own communication step (CS: the
FMU's own integrator defines the result, so the reference is its result at that step).

Metric: the largest error over the output grid and the compared outputs (every Float64
scalar output of the FMU), each relative to the output's size (the larger of its range and
its largest magnitude in the reference). The accuracy a run must meet follows from how it
was asked to run, never from what it got: ME at TOL: 100 TOL (as the project's scene
figures state for its solvers); a fixed-step CS run at the reference's steps: 1e-9 (the
same steps by the same binary: round-off); the engine's adaptive CS run: its scheme's tol.

Each run is a child process with a time limit, so a foreign binary that crashes or hangs is
a row ("crash"), not the end of the benchmark. A run is ``pass`` (within its accuracy),
``wrong`` (completed outside it, or stopped early without a word), ``error`` (ended with a
message; its first line is kept) or ``crash``.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import platform
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

TOL = 1e-6          # the tolerance both importers' ME runs are asked for
REF_TOL = 1e-10     # fmpy's CVode for ME references
ME_FACTOR = 100     # ME accuracy = ME_FACTOR * TOL
SAME_STEPS = 1e-9   # a fixed-step CS run at the reference's steps: round-off
RUN_LIMIT_S = 120   # a run longer than this is a hang
IMPORTERS = ("fmpy", "engine", "engine fixed")


# --- closed forms ------------------------------------------------------------------------------
def _pi_ramp(t):
    """A PI controller (v_ref 1, k 2, Ti 0.5) whose speed input v stays at its start 0:
    I = t, f = k (v_ref + I / Ti)."""
    return {"f": 2.0 * (1.0 + t / 0.5)}


def _lag(t):
    return {"x": 1.0 - np.exp(-t / 0.5)}


def _oscillator(t, w=3.0, zeta=0.1):
    """x'' + 2 zeta w x' + w^2 x = 0 from x = 1, x' = 0."""
    wd = w * math.sqrt(1 - zeta ** 2)
    decay = np.exp(-zeta * w * t)
    return {"x": decay * (np.cos(wd * t) + zeta * w / wd * np.sin(wd * t)),
            "v": -w ** 2 / wd * decay * np.sin(wd * t)}


def _bouncing_ball(t, h0=1.0, g=9.81, e=0.8):
    """Dropped from h0 at rest; each impact sends it up at e times its impact speed."""
    h, v = np.empty_like(t), np.empty_like(t)
    fall = math.sqrt(2 * h0 / g)
    first = t <= fall
    h[first], v[first] = h0 - g * t[first] ** 2 / 2, -g * t[first]
    start, speed = fall, e * g * fall  # launch time and upward speed of the next flight
    while start < t[-1]:
        inside = (t > start) & (t <= start + 2 * speed / g)
        tau = t[inside] - start
        h[inside], v[inside] = speed * tau - g * tau ** 2 / 2, speed - g * tau
        start, speed = start + 2 * speed / g, e * speed
    return {"h": h, "v": v}


def _ramp(start_time=0.0, duration=1.0):
    """Modelica.Blocks.Sources.Ramp (height 1, offset 0)."""
    return lambda t: {"out": np.clip((t - start_time) / duration, 0.0, 1.0)}


def _drop(t, h0=2.0, g=9.81):
    return {"h": h0 - g * t ** 2 / 2, "v": -g * t}


def _adder(t):
    return {"y": np.full_like(t, 3.0)}  # y = k1 u1 + k2 u2 with k = 1, u1 = 1, u2 = 2


# --- the cases ---------------------------------------------------------------------------------
@dataclass(frozen=True)
class Case:
    name: str
    tool: str
    fmu: Callable[[], Path]          # obtains the FMU (download or build, cached)
    interface: str                   # "ME" or "CS"
    stop: float
    step: float
    starts: dict = field(default_factory=dict)
    exact: Callable | None = None    # closed form: t -> {output: values}
    inner: Callable[[], Path] | None = None  # a container's embedded FMU, run at inner_step
    inner_step: float | None = None
    quick: bool = False
    note: str = ""
    start: float = 0.0               # start time (the experiment runs start..stop)
    ends: float | None = None        # where the FMU itself ends the run (terminate)

    @property
    def reference(self) -> str:
        if self.exact is not None:
            return "closed form"
        if self.inner is not None:
            return f"inner FMU, fmpy CS h={self.inner_step:g}"
        return f"fmpy CVode {REF_TOL:g}" if self.interface == "ME" else \
            f"fmpy CS h={self.step:g}"


def tool_name(tool: str) -> str:
    """The exporting tool without its version ("PythonFMU3 0.3.4" -> "PythonFMU3")."""
    words = tool.split(" ")
    return " ".join(words[:-1]) if len(words) > 1 and words[-1][:1].isdigit() else tool


def _gemseo(name):
    from .foreign_fmus import gemseo_fmu
    return lambda: gemseo_fmu(name)


def _pythonfmu3(name):
    from .foreign_fmus import pythonfmu3_fmu
    return lambda: pythonfmu3_fmu(name)


def _container(version, step):
    from .foreign_fmus import gemseo_fmu, toolbox_container
    return lambda: toolbox_container(gemseo_fmu("Mass_Damper.fmu"), version, step)


def _fmpy_container(step):
    from .foreign_fmus import fmpy_container, gemseo_fmu
    return lambda: fmpy_container(gemseo_fmu("Mass_Damper.fmu"), step)


def _casadi():
    from assemblies.scenes.pi_controller import casadi_pi_fmu
    return casadi_pi_fmu()


def _pythonfmu(handle_state):
    from assemblies.scenes.pi_controller import pythonfmu_pi_fmu
    return lambda: pythonfmu_pi_fmu(handle_state=handle_state)


OM = "OpenModelica"
CASES = [
    Case("Mass_Damper ME", OM, _gemseo("Mass_Damper.fmu"), "ME", 1.0, 1e-3, quick=True),
    Case("Mass_Damper CS", OM, _gemseo("Mass_Damper.fmu"), "CS", 1.0, 1e-3, quick=True),
    Case("MassSpringSystem ME", OM, _gemseo("MassSpringSystem.fmu"), "ME", 1.0, 1e-2),
    Case("MassSpringSystem CS", OM, _gemseo("MassSpringSystem.fmu"), "CS", 1.0, 1e-2),
    Case("ramp ME", OM, _gemseo("ramp.fmu"), "ME", 1.0, 1e-2),
    Case("ramp CS", OM, _gemseo("ramp.fmu"), "CS", 1.0, 1e-2),
    Case("ramp ME parameters", OM, _gemseo("ramp.fmu"), "ME", 1.0, 0.01,
         {"ramp.startTime": 0.3, "ramp.duration": 0.4}, exact=_ramp(0.3, 0.4),
         note="parameters set; time events at 0.3 and 0.7"),
    Case("ramp ME from t=0.5", OM, _gemseo("ramp.fmu"), "ME", 1.5, 0.01, exact=_ramp(),
         start=0.5, note="start time 0.5; the FMU itself reports out = 0 after initialising "
                         "with fmi2SetupExperiment(startTime=0.5) (0.5 once fmi2SetTime(0.5) "
                         "is called in continuous-time mode)"),
    Case("add ME", OM, _gemseo("add.fmu"), "ME", 1.0, 0.1, {"u1": 1.0, "u2": 2.0},
         exact=_adder),
    Case("add CS", OM, _gemseo("add.fmu"), "CS", 1.0, 0.1, {"u1": 1.0, "u2": 2.0},
         exact=_adder),
    Case("FMU3Model CS", "PythonFMU3 0.2.2", _gemseo("FMU3Model.fmu"), "CS", 1.0, 0.1,
         note="arrays, Int64, Boolean, String, Enumeration variables"),
    Case("Lag3 CS", "PythonFMU3 0.3.4", _pythonfmu3("Lag3"), "CS", 2.0, 0.05, exact=_lag,
         quick=True),
    Case("Oscillator3 ME", "PythonFMU3 0.3.4", _pythonfmu3("Oscillator3"), "ME", 5.0, 0.05,
         exact=_oscillator),
    Case("BouncingBall3 ME", "PythonFMU3 0.3.4", _pythonfmu3("BouncingBall3"), "ME", 2.0, 0.05,
         exact=_bouncing_ball, note="state events"),
    Case("Drop3 ME", "PythonFMU3 0.3.4", _pythonfmu3("Drop3"), "ME", 2.0, 0.05, exact=_drop,
         ends=math.sqrt(4 / 9.81), note="terminates at the ground (t = 0.639)"),
    Case("Robertson3 ME", "PythonFMU3 0.3.4", _pythonfmu3("Robertson3"), "ME", 40.0, 0.4,
         note="stiff"),
    Case("PIControllerPy CS", "PythonFMU 0.7.0", _pythonfmu(False), "CS", 2.0, 0.01,
         exact=_pi_ramp),
    Case("PIControllerPy CS state", "PythonFMU 0.7.0", _pythonfmu(True), "CS", 2.0, 0.01,
         exact=_pi_ramp, note="--handle-state: canGetAndSetFMUstate"),
    Case("PIController ME", "CasADi 3.8", _casadi, "ME", 2.0, 0.01, exact=_pi_ramp,
         quick=True),
    Case("Container2 Mass_Damper CS", "FMU Manipulation Toolbox 2.0", _container(2, 1e-3),
         "CS", 1.0, 1e-2, inner=_gemseo("Mass_Damper.fmu"), inner_step=1e-3),
    Case("Container3 Mass_Damper CS", "FMU Manipulation Toolbox 2.0", _container(3, 1e-3),
         "CS", 1.0, 1e-2, inner=_gemseo("Mass_Damper.fmu"), inner_step=1e-3, quick=True),
    Case("FmpyContainer Mass_Damper CS", "FMPy container_fmu 0.3.32", _fmpy_container(1e-3),
         "CS", 1.0, 1e-2, inner=_gemseo("Mass_Damper.fmu"), inner_step=1e-3),
]


def _description(path: Path):
    # not validated: an FMU fmpy's checks refuse is still a case (fmpy's run says why)
    from fmpy import read_model_description
    return read_model_description(str(path), validate=False)


def compared_outputs(md) -> list[str]:
    """Every Float64 output, arrays included: what the metric compares."""
    return [v.name for v in md.modelVariables if v.causality == "output"
            and v.type in ("Real", "Float64")]


def _column(cols: dict, name: str, like: np.ndarray):
    """Output `name` of a run shaped as the reference's `like`: an array output either as
    one 2-D column or as its elements ``name[1]``, ``name[2]``... (FMI's structured names)."""
    if name in cols:
        return cols[name]
    if like.ndim == 2:
        elements = [f"{name}[{k}]" for k in range(1, like.shape[1] + 1)]
        if all(e in cols for e in elements):
            return np.stack([cols[e] for e in elements], axis=1)
    return None


# --- one run, in a child process ---------------------------------------------------------------
def _one_line(exc: BaseException) -> str:
    """The exception as one line (a message of several lines joined with " | ", so that the
    cause a later line names is kept; `message_lines` in the row says how many it had)."""
    lines = [line.strip() for line in str(exc).strip().splitlines() if line.strip()] or [""]
    text = f"{type(exc).__name__}: {' | '.join(lines)}"
    return text if len(text) <= 400 else text[:397] + "..."


def _engine_run(case: Case, path: Path, fixed: bool):
    from assemblies import FMU, Assembly, cosimulate, simulate_me
    from assemblies.engine.cosim import DEFAULT_SCHEME
    asm = Assembly("foreign")
    asm.add("fmu", FMU(path, **case.starts))
    # asked only where the case starts later: an engine without it answers in one line
    start = {"start_time": case.start} if case.start else {}
    if case.interface == "ME":
        res = simulate_me(asm, case.stop, case.step, TOL, **start)
    elif fixed:
        res = cosimulate(asm, case.stop, case.step, **start)
    else:
        res = cosimulate(asm, case.stop, case.step, **DEFAULT_SCHEME, **start)
    columns = {"time": np.asarray(res["time"])}
    for c in res.columns:
        if c.startswith("fmu."):
            columns[c[4:]] = np.asarray(res[c], dtype=float)
    s = res.settings
    info = {k: s.get(k) for k in ("fallback", "terminated", "stopped", "adaptive", "steps",
                                  "rejected", "method") if s.get(k) is not None}
    return columns, info


def _fmpy_run(path: Path, interface: str, start: float, stop: float, step: float, starts: dict,
              tol: float, validate: bool = True):
    """fmpy as users call it (validating the model description, as it does by default);
    the references skip the validation, which judges the file, not the model."""
    from fmpy import simulate_fmu
    fmi_type = "ModelExchange" if interface == "ME" else "CoSimulation"
    kwargs = dict(solver="CVode", relative_tolerance=tol) if interface == "ME" else {}
    r = simulate_fmu(str(path), fmi_type=fmi_type, start_time=start, stop_time=stop,
                     output_interval=step,
                     start_values=dict(starts), validate=validate, record_events=False,
                     **kwargs)
    return {n: np.asarray(r[n], dtype=float) for n in r.dtype.names}, {}


def _worker(argv: list[str]) -> int:
    """`--run CASE WHAT FMU OUT`: one run (WHAT: an importer or "reference"), its columns
    and what it said saved to OUT (.npz + .json); exceptions become a one-line message."""
    import faulthandler
    import warnings
    # before the parent's limit: the Python stack of a hang goes to stderr, then exit, so
    # that the row can say where it hung (a native frame shows as its ctypes call)
    dump_s = float(os.environ.get("FOREIGN_DUMP_S", "0"))
    if dump_s > 0:
        faulthandler.dump_traceback_later(dump_s, exit=True)
    name, what, path, out = argv
    case = next(c for c in CASES if c.name == name)
    path = Path(path)
    meta = {"status": "done", "message": None, "warnings": [], "info": {}}
    columns = {}
    started = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            if what == "fmpy":
                columns, meta["info"] = _fmpy_run(path, case.interface, case.start, case.stop,
                                                  case.step, case.starts, TOL)
            elif what == "reference" and case.inner is not None:
                columns, _ = _fmpy_run(path, "CS", case.start, case.stop, case.inner_step,
                                       case.starts, 0, validate=False)
            elif what == "reference":
                columns, _ = _fmpy_run(path, case.interface, case.start, case.stop, case.step,
                                       case.starts, REF_TOL, validate=False)
            else:
                columns, meta["info"] = _engine_run(case, path, fixed=what == "engine fixed")
        except Exception as exc:  # any failure of a run is its row's message
            meta.update(status="error", message=_one_line(exc),
                        message_lines=len(str(exc).strip().splitlines()))
    meta["wall_s"] = time.perf_counter() - started
    meta["warnings"] = sorted({f"{w.category.__name__}: {str(w.message).splitlines()[0]}"
                               for w in caught})
    np.savez(out + ".npz", **columns)
    Path(out + ".json").write_text(json.dumps(meta))
    faulthandler.cancel_dump_traceback_later()
    return 0


def run_child(case: Case, what: str, path: Path, limit_s: float, work: Path) -> dict:
    """Run `what` of `case` in a child process; its meta plus columns, or a crash row."""
    out = str(work / f"{abs(hash((case.name, what)))}")
    cmd = [sys.executable, "-m", "benchmarks.foreign", "--run", case.name, what, str(path), out]
    started = time.perf_counter()
    dump_s = 0.9 * limit_s if limit_s >= 10 else 0
    try:
        done = subprocess.run(cmd, capture_output=True, text=True, timeout=limit_s,
                              env={**os.environ, "FOREIGN_DUMP_S": str(dump_s),
                                   "PYTHONPATH": os.pathsep.join(
                                       [str(Path(__file__).resolve().parent.parent),
                                        os.environ.get("PYTHONPATH", "")])})
    except subprocess.TimeoutExpired:
        return {"status": "crash", "message": f"no answer within {limit_s:g} s (killed)",
                "wall_s": limit_s}
    wall = time.perf_counter() - started
    if done.returncode != 0 or not Path(out + ".json").exists():
        frames = [line.strip() for line in done.stderr.splitlines()
                  if line.startswith("  File ") and not line.startswith('  File "<')]
        if "Timeout (" in done.stderr and frames:  # faulthandler: most recent call first
            why = f"no answer within {dump_s:g} s; stopped in {frames[0]}"
        elif done.returncode < 0:
            why = f"killed by {signal.Signals(-done.returncode).name}"
        else:
            tail = (done.stderr.strip().splitlines() or ["no message"])[-1]
            why = f"exit status {done.returncode}: {tail}"
        return {"status": "crash", "message": why, "wall_s": wall}
    meta = json.loads(Path(out + ".json").read_text())
    with np.load(out + ".npz") as z:
        meta["columns"] = {k: z[k] for k in z.files}
    return meta


# --- judging -----------------------------------------------------------------------------------
def accuracy(case: Case, what: str) -> float:
    """What a run of `what` must meet, from how it was asked to run."""
    from assemblies.engine.cosim import DEFAULT_SCHEME
    if case.interface == "ME":
        return ME_FACTOR * TOL
    if what == "engine":
        return DEFAULT_SCHEME["tol"]
    return SAME_STEPS


def judge(case: Case, what: str, run: dict, ref: dict, outputs: list[str]) -> dict:
    """The row cell of a run: status, error, accuracy and the one line that explains it."""
    acc = accuracy(case, what)
    cell = {"status": run["status"], "message": run.get("message"),
            "message_lines": run.get("message_lines", 1), "accuracy": acc,
            "error": None, "warnings": run.get("warnings", []), "info": run.get("info", {}),
            "wall_s": run.get("wall_s")}
    if run["status"] != "done":
        return cell
    cols = run["columns"]
    t, t_ref = cols.get("time", np.array([])), ref["time"]
    ended = cell["info"].get("terminated") or cell["info"].get("stopped")
    if isinstance(ended, dict):  # the engine's terminated: instance, time, message
        ended = ended.get("message") or f"terminated by {ended.get('instance')}"
    if len(t) == 0 or t[-1] < t_ref[-1] - 1e-9 * case.step:
        last = t[-1] if len(t) else float("nan")
        if ended:
            cell.update(status="error", message=f"stopped at t = {last:g}: {ended}")
        else:
            cell.update(status="wrong", message=f"stopped at t = {last:g} without a message "
                                                f"(reference to {t_ref[-1]:g})")
        return cell
    values = {o: _column(cols, o, ref[o]) for o in outputs}
    missing = [o for o, x in values.items() if x is None or x.shape[1:] != ref[o].shape[1:]]
    if missing:
        cell.update(status="wrong", message=f"output(s) {', '.join(missing)} not recorded "
                                            "(or not in the reference's shape)")
        return cell
    errors = {}
    for o in outputs:
        r = ref[o]
        # the run's value at each reference time (both on the grid k*step; exact match)
        idx = np.searchsorted(t, t_ref - 1e-9 * case.step)
        idx = np.clip(idx, 0, len(t) - 1)
        if np.any(np.abs(t[idx] - t_ref) > 1e-9 * max(case.step, 1.0)):
            cell.update(status="wrong", message="output times off the reference's grid")
            return cell
        scale = max(float(np.max(np.abs(r))), float(np.ptp(r)), 1e-12)
        errors[o] = float(np.max(np.abs(values[o][idx] - r))) / scale
    worst = max(errors, key=errors.get) if errors else None
    err = errors[worst] if worst else 0.0
    cell["error"] = err
    if not np.isfinite(err) or err > acc:
        k = None
        if worst:
            idx = np.clip(np.searchsorted(t, t_ref - 1e-9 * case.step), 0, len(t) - 1)
            diff = np.abs(values[worst][idx] - ref[worst])
            k = int(np.argmax(diff.reshape(len(diff), -1).max(axis=1)))
        cell.update(status="wrong", message=f"{worst}: error {err:.2g} > {acc:.0e} "
                                            f"(worst at t = {t_ref[k]:g})" if worst else
                    "no output to compare")
    else:
        cell["status"] = "pass"
    return cell


def reference_columns(case: Case, work: Path, limit_s: float) -> tuple[dict | None, str]:
    """(columns, description) of the case's reference; None and why where it failed."""
    if case.exact is not None:
        n = round((case.stop - case.start) / case.step)
        t = case.start + case.step * np.arange(n + 1)
        if case.ends is not None:  # the rows up to where the model ends its run
            t = t[t <= case.ends]
        return {"time": t, **case.exact(t)}, case.reference
    path = case.inner() if case.inner is not None else case.fmu()
    run = run_child(case, "reference", path, limit_s, work)
    if run["status"] != "done":
        return None, f"{case.reference} failed: {run['message']}"
    cols = run["columns"]
    if case.inner is not None:  # sample the inner run on the container's grid
        keep = np.abs(cols["time"] / case.step - np.round(cols["time"] / case.step)) < 1e-6
        cols = {k: v[keep] for k, v in cols.items()}
    return cols, case.reference


def run_case(case: Case, limit_s: float = RUN_LIMIT_S) -> dict:
    row = {"case": case.name, "tool": case.tool, "interface": case.interface,
           "fmi": None, "reference": case.reference, "note": case.note, "runs": {}}
    try:
        path = case.fmu()
        md = _description(path)
    except Exception as exc:  # not obtained, or no model description to read
        row["setup_error"] = _one_line(exc)
        return row
    row["fmi"] = md.fmiVersion
    outputs = compared_outputs(md)
    row["outputs"] = outputs
    with tempfile.TemporaryDirectory() as work:
        ref, described = reference_columns(case, Path(work), limit_s)
        row["reference"] = described
        if ref is not None:
            outputs = [o for o in outputs if o in ref]
            row["outputs"] = outputs
        for what in IMPORTERS:
            if what == "engine fixed" and case.interface != "CS":
                continue
            run = run_child(case, what, path, limit_s, Path(work))
            if ref is None:
                row["runs"][what] = {"status": run["status"] if run["status"] != "done" else
                                     "unjudged", "message": run.get("message"),
                                     "warnings": run.get("warnings", [])}
            else:
                row["runs"][what] = judge(case, what, run, ref, outputs)
    return row


# --- report -----------------------------------------------------------------------------------
def _cell(run: dict | None) -> str:
    if run is None:
        return "-"
    if run["status"] in ("pass", "wrong") and run.get("error") is not None:
        return f"{run['status']} {run['error']:.1e}"
    return run["status"]


def rates(rows: list[dict]) -> list[tuple[str, int, int]]:
    """(label, passed, cases) for each importer over the cases it can run."""
    out = []
    for label, what, interface in (("fmpy", "fmpy", None), ("engine default", "engine", None),
                                   ("fmpy, ME cases", "fmpy", "ME"),
                                   ("engine me", "engine", "ME"),
                                   ("fmpy, CS cases", "fmpy", "CS"),
                                   ("engine cosim (default scheme)", "engine", "CS"),
                                   ("engine cosim fixed step", "engine fixed", "CS")):
        chosen = [r for r in rows if interface in (None, r["interface"])]
        passed = sum(1 for r in chosen if r["runs"].get(what, {}).get("status") == "pass")
        out.append((label, passed, len(chosen)))
    return out


def table(rows: list[dict]) -> str:
    head = f"{'case':28} {'tool':30} {'FMI':4} {'if':3} {'fmpy':13} {'engine':13} " \
           f"{'engine fixed':13} reference"
    lines = [head]
    for r in rows:
        runs = r["runs"]
        lines.append(f"{r['case']:28} {r['tool']:30} {r['fmi'] or '?':4} {r['interface']:3} "
                     f"{_cell(runs.get('fmpy')):13} {_cell(runs.get('engine')):13} "
                     f"{_cell(runs.get('engine fixed')):13} {r['reference']}")
    return "\n".join(lines)


def failures(rows: list[dict]) -> list[str]:
    """One line per run that did not pass: case, importer, status and cause."""
    out = []
    for r in rows:
        if r.get("setup_error"):
            out.append(f"{r['case']}: could not be obtained: {r['setup_error']}")
        for what, run in r["runs"].items():
            if run["status"] != "pass":
                said = "; ".join(run.get("warnings", []))
                out.append(f"{r['case']} / {what}: {run['status']}: {run.get('message')}"
                           + (f" (warned: {said})" if said else ""))
    return out


def results_section(rows: list[dict], command: str, elapsed: float) -> list[str]:
    tools = sorted({tool_name(r["tool"]) for r in rows})
    lines = ["## Foreign FMUs (issue 24)", "",
             f"`{command}`: {len(rows)} cases (an FMU through one interface) from "
             f"{len(tools)} exporting tools ({', '.join(tools)}), every run a child process "
             f"limited to {RUN_LIMIT_S} s; {elapsed:.0f} s in all. ME runs at tolerance "
             f"{TOL:g} must come within {ME_FACTOR * TOL:g} of the reference, fixed-step CS "
             f"runs within {SAME_STEPS:g} (the reference's own steps), the engine's adaptive "
             "CS run within its scheme's tol; the error is the largest over the grid and the "
             "Float64 outputs, relative to each output's size. Cells: status and error. Where "
             "the reference is fmpy's own CS run at the case's step (no closed form, no "
             "embedded FMU to run alone), fmpy's pass says only that it completed.", "",
             "```", table(rows), "```", "", "Pass rates:", ""]
    lines += [f"- {label}: {p}/{n}" for label, p, n in rates(rows)]
    lines += ["", "What some cases exercise:", ""]
    lines += [f"- {r['case']}: {r['note']}" for r in rows if r.get("note")]
    lines += ["", "Every run that did not pass, with its cause:", ""]
    lines += [f"- {f}" for f in failures(rows)] or ["- none"]
    return lines + [""]


def _jsonable(rows: list[dict]) -> list[dict]:
    return json.loads(json.dumps(rows, default=lambda o: o.tolist() if hasattr(o, "tolist")
                                 else str(o)))


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["--run"]:
        return _worker(argv[1:])
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="only the cases marked quick")
    parser.add_argument("--case", action="append", help="only this case (repeatable)")
    parser.add_argument("--json", metavar="FILE", help="write the rows as JSON")
    parser.add_argument("--results", action="store_true",
                        help="write this run's section of benchmarks/RESULTS.md")
    parser.add_argument("--from-json", metavar="FILE",
                        help="run nothing: write the RESULTS.md section of a saved --json")
    args = parser.parse_args(argv)
    if args.from_json:
        from .run_all import HERE, replace_section
        saved = json.loads(Path(args.from_json).read_text())
        replace_section(HERE / "RESULTS.md", results_section(saved["rows"], saved["command"],
                                                             saved["elapsed_s"]))
        print(f"wrote its section of {HERE / 'RESULTS.md'} from {args.from_json}")
        return 0
    cases = [c for c in CASES if (not args.quick or c.quick)
             and (not args.case or c.name in args.case)]
    started = time.perf_counter()
    rows = []
    for case in cases:
        rows.append(run_case(case))
        print(table(rows[-1:]).splitlines()[-1], flush=True)
    elapsed = time.perf_counter() - started
    print()
    print(table(rows))
    for label, p, n in rates(rows):
        print(f"{label}: {p}/{n}")
    for f in failures(rows):
        print(f"- {f}")
    command = " ".join(["python -m benchmarks.foreign", *argv])
    if args.json:
        Path(args.json).write_text(json.dumps({"machine": platform.platform(), "tol": TOL,
                                               "command": command, "elapsed_s": elapsed,
                                               "rows": _jsonable(rows)}, indent=1) + "\n")
        print(f"wrote {args.json}")
    if args.results:
        from .run_all import HERE, replace_section
        replace_section(HERE / "RESULTS.md", results_section(rows, command, elapsed))
        print(f"wrote its section of {HERE / 'RESULTS.md'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
