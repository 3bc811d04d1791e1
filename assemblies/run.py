"""Running a scene: parameters applied, co-simulated, figures measured, files written."""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path

from components.errors import writable_folder
from components.sources.table import TimeTable

from .assembly import AssemblyError
from .engine.cosim import DEFAULT_SCHEME as DEFAULT_COSIM
from .foreign import check_mode
from .inputs import with_inputs
from .pruning import prune_unrecorded
from .result import Result
from .runfile import run_record, set_instance_values
from .scenes import Figure, Scene, scene


@dataclass
class SceneRun:
    name: str
    result: Result
    figures: list[Figure]
    #: what repeats the run (assemblies.runfile.run_record): its options and every value
    record: dict = field(default_factory=dict)

    @property
    def failed(self) -> list[Figure]:
        return [f for f in self.figures if not f.passed]

    @property
    def passed(self) -> bool:
        return not self.failed

    def verdict(self) -> str:
        """One line: every figure within its accuracy, or which are not."""
        if self.passed:
            return f"all {len(self.figures)} figures pass"
        return (f"FAILED: {len(self.failed)} of {len(self.figures)} figures outside their "
                f"accuracy: {', '.join(f.name for f in self.failed)}")

    def summary(self) -> dict:
        return {"scene": self.name, **self.record, "settings": self.result.settings,
                "passed": self.passed,
                "figures": [{"name": f.name, "description": f.description, "measured": f.measured,
                             "reference": f.reference, "error": f.error,
                             "accuracy": f.accuracy, "relative": f.relative, "bound": f.bound,
                             "passed": f.passed, "source": f.source} for f in self.figures]}

    def table(self, verdict: bool = True) -> str:
        """The figures, each with its error, the error it may have (`accuracy`, absolute)
        and pass/FAIL, its description and its reference's source; the run's settings; and, with
        `verdict`, that as the last line."""
        lines = [f"{'figure':<12} {'measured':>16} {'reference':>16} {'error':>10} "
                 f"{'accuracy':>10}  {'pass':<4}  description"]
        for f in self.figures:
            bound = f"{f.bound:10.2e}" if math.isfinite(f.bound) else f"{'not stated':>10}"
            lines.append(f"{f.name:<12} {f.measured:>16.10g} {f.reference:>16.10g} "
                         f"{f.error:>10.2e} {bound}  {'pass' if f.passed else 'FAIL':<4}  "
                         f"{f.description}; source: {f.source or 'not stated'}")
        s = self.result.settings
        if s.get("terminated"):
            lines.append(f"terminated by {s['terminated']['instance']} at t = "
                         f"{s['terminated']['time']:.10g}: {s['terminated']['message']}")
        # only a fixed-step co-simulation has a step of its own; elsewhere it is the output grid
        fixed_step = s.get("scheme") in ("jacobi", "gauss-seidel") and not s.get("adaptive")
        step = "step" if fixed_step else "output every"
        lines.append(f"stop time {s['stop_time']:g} s, {step} {s['step']:g} s, tolerance "
                     f"{s['tolerance']:g}, {s['scheme']}, engine {s.get('engine', '?')}"
                     + (f" ({s['master']})" if s.get("master") else "")
                     + f", wall time {s['wall_s']:.3g} s"
                     + (f" (FMU builds and loading: {s['setup_s']:.3g} s more)"
                        if s.get("setup_s", 0) >= 0.05 else ""))
        if s.get("interrupted"):
            lines.append(f"interrupted (Ctrl-C) at t = {self.result['time'][-1]:.10g} s: the "
                         "table and figures cover the run up to there")
        lines.extend(s.get("lines", []))  # what a scene's own solver reports of its run
        if s.get("adaptive"):
            lines.append(f"adaptive to tol {s['tol']:g} (extrapolation {s['extrapolation']}): "
                         f"{s['steps']} steps taken, {s['rejected']} rejected")
        if verdict:
            lines.append(self.verdict())
        return "\n".join(lines)


MODES = ("cosim", "me", "monolithic")
ENGINES = ("c", "fmpy")


def _masters(engine: str):
    """(cosimulate, simulate_me, simulate_monolithic) of the chosen engine: ``c``, the
    compiled engine (one C call per run), or ``fmpy``, the Python reference masters
    that drive the same FMUs through fmpy."""
    if engine == "fmpy":  # here: fmpy and scipy's integrators load in 0.3-0.5 s
        from .masters.cosim import cosimulate
        from .masters.me import simulate_me
        from .masters.monolithic import simulate_monolithic
        return cosimulate, simulate_me, simulate_monolithic
    from .engine.cosim import cosimulate as c_cosimulate
    from .engine.me import simulate_me as c_simulate_me, simulate_monolithic as c_monolithic
    return c_cosimulate, c_simulate_me, c_monolithic


def run_scene(name: str, stop_time: float | None = None, step: float | None = None,
              tolerance: float | None = None, params: dict | None = None,
              out: str | Path | None = None, scheme: str | None = None, progress=None,
              mode: str | None = None, adaptive: bool | float | None = None,
              extrapolation: int | None = None, engine: str = "c", prune: bool = True,
              jacobian: str | None = None, start_time: float | None = None,
              inputs=None, plot: bool = True) -> Result:
    """Run a scene and return its result table (``res['block.x']``).

    `mode` picks the master: ``cosim`` (Co-Simulation FMUs), ``me`` (Model Exchange FMUs
    under one solver) or ``monolithic`` (the joined model as one FMU); for the last two
    `step` is only the output interval; None, the scene's own (``cosim`` for most, ``me``
    for a scene with a Model-Exchange-only foreign FMU). `engine` runs it in the compiled
    engine (``c``, default) or in the fmpy-driven Python masters (``fmpy``, the reference).

    Co-simulation by default controls its error: adaptive communication steps to
    ``DEFAULT_COSIM['tol']`` with cubic input extrapolation and events synchronised
    across FMUs (`step` is then the output interval), and a scene of one FMU runs as a
    single FMU whose solver steps freely. ``adaptive=False`` asks for a fixed
    communication step `step`, ``adaptive=TOL`` for another tolerance; `extrapolation`
    (0, 1, 2) is the input extrapolation order; `scheme` the sweep, ``jacobi`` (default) or
    ``gauss-seidel``. These three belong to ``cosim``: another mode refuses them.
    With `out`, also writes ``out/NAME.csv``, ``out/NAME.png`` and ``out/NAME.json``;
    ``plot=False`` leaves the .png out (and matplotlib unloaded: 0.5-1 s of a short run).
    The measured figures are on ``res.figures``.

    Instances that cannot influence the recorded outputs are not run
    (:mod:`assemblies.pruning`; ``settings["pruned"]`` names them); ``prune=False``
    runs every instance.

    `jacobian` (the compiled engine's one-solver runs: ``me``, ``monolithic``, a single
    FMU): ``auto`` (default) takes directional derivatives unless a foreign FMU's
    disagree with differences at the first point, ``fd`` finite differences, ``exact``
    directional derivatives whatever happens.

    The run starts at `start_time` (None: 0). `inputs` feeds the scene's open signal
    inputs from a table: a numpy structured array or pandas DataFrame with a ``time``
    column, or a CSV path; each other column names an input, ``INSTANCE.INPUT``
    (:mod:`assemblies.inputs`: fmpy's interpolation rules, an event at every row).
    """
    return run_scene_full(name, stop_time, step, tolerance, params, out, scheme, progress,
                          mode, adaptive, extrapolation, engine, prune, jacobian=jacobian,
                          start_time=start_time, inputs=inputs, plot=plot).result


def cosim_scheme(adaptive: bool | float | None, extrapolation: int | None) -> dict:
    """The co-simulation settings a run asked for, the defaults filled in (see run_scene):
    ``{"adaptive": bool, "tol": float, "extrapolation": int}``."""
    if adaptive is None and extrapolation is None:
        return dict(DEFAULT_COSIM)
    if adaptive is None or adaptive is False:
        return {"adaptive": False, "tol": DEFAULT_COSIM["tol"],
                "extrapolation": 0 if extrapolation is None else extrapolation}
    # a number is the tolerance (0 included: refused by the master, never read as "off")
    if isinstance(adaptive, str) or not hasattr(adaptive, "__float__"):  # a run file's text
        raise AssemblyError(f"adaptive (--adaptive/--fixed-step) must be True, False or a "
                            f"tolerance in (0, 1), not {type(adaptive).__name__} {adaptive!r}")
    tol = DEFAULT_COSIM["tol"] if adaptive is True else float(adaptive)
    return {"adaptive": True, "tol": tol,
            "extrapolation": DEFAULT_COSIM["extrapolation"] if extrapolation is None
            else extrapolation}


# what the command line calls each co-simulation setting, for messages both read
COSIM_ONLY = {"scheme": "--scheme", "adaptive": "--adaptive/--fixed-step",
              "extrapolation": "--extrapolation"}


def check_cosim_only(mode: str, **settings) -> None:
    """Refuse a co-simulation setting given to another mode, which would ignore it."""
    for name, value in settings.items():
        if value is not None and mode != "cosim":
            raise AssemblyError(
                f"{name} ({COSIM_ONLY[name]}) applies to mode 'cosim' only, and this run's "
                f"mode is '{mode}', which has no communication step (its accuracy is set by "
                "tolerance, --tolerance); leave it out or run mode 'cosim'")


def check_choices(mode: str, engine: str, own: tuple[str, ...] = (), scene: str = "") -> None:
    """Refuse a master or an engine that does not exist, naming those that do (`own`: the
    modes `scene` runs with a solver of its own)."""
    if mode not in MODES + tuple(own):
        where = f" for scene '{scene}'" if scene else ""
        raise AssemblyError(f"mode must be one of {', '.join(MODES + tuple(own))}{where}, "
                            f"not '{mode}'")
    if engine not in ENGINES:
        raise AssemblyError(f"engine must be one of {', '.join(ENGINES)}, not '{engine}'")


def run_scene_full(name, stop_time=None, step=None, tolerance=None, params=None, out=None,
                   scheme=None, progress=None, mode=None, adaptive=None,
                   extrapolation=None, engine="c", prune=True, jacobian=None, start_time=None,
                   inputs=None, values=None, plot=True) -> SceneRun:
    """As :func:`run_scene`, with the figures; `name` may also be a :class:`Scene` that is
    not in the registry (a parameter study runs an assembly given to it as one).
    `values`: every instance's values as a run's JSON file records them
    (:mod:`assemblies.runfile`), set before `params`; :func:`assemblies.rerun` passes them."""
    sc = name if isinstance(name, Scene) else scene(name)
    name = sc.name
    mode = sc.mode if mode is None else mode
    check_choices(mode, engine, tuple(sc.solvers), name)
    check_cosim_only(mode, scheme=scheme, adaptive=adaptive, extrapolation=extrapolation)
    if params is not None and not isinstance(params, dict):
        raise AssemblyError(f"params must be a dict of 'INSTANCE.NAME': value, e.g. "
                            f"{{'block.m': 2}}, not {type(params).__name__} {params!r}")
    # NAME=VALUE with no instance: the scene's own (its assembly's shape), checked and
    # bounded per mode before anything is built
    shape = {k: v for k, v in (params or {}).items() if "." not in k}
    try:
        arguments = sc.arguments(shape, mode)
        run_to, run_from = stop_time if stop_time is not None else sc.stop_time, start_time or 0.0
        if all(isinstance(v, (int, float)) for v in (run_to, run_from)):  # else refused later
            sc.check_budget(mode, arguments, run_to - run_from)
    except ValueError as exc:
        raise AssemblyError(str(exc)) from None
    if out is not None:  # a folder that cannot be written is found before the run
        out = writable_folder(out, "out", AssemblyError)
    asm = sc.assemble(arguments, shape)
    sc.check_mode(mode, asm.name)
    if values is not None:
        set_instance_values(asm, values)
    for key, value in (params or {}).items():
        if key not in shape:
            asm.set(key, value)
    own = sc.solvers.get(mode)
    if own is None:
        check_mode(asm, mode)  # a foreign FMU the mode cannot run: one line, before any work
    # tables first: pruning then drops a table whose input is not needed
    fed = with_inputs(asm, inputs)
    # the figures read the whole assembly's values; the masters run what the record needs
    run_asm, pruned = (prune_unrecorded(fed, sc.record) if prune and own is None
                       else (fed, []))
    common = dict(stop_time=stop_time if stop_time is not None else sc.stop_time,
                  step=step if step is not None else sc.step,
                  tolerance=tolerance if tolerance is not None else sc.tolerance,
                  record=sc.record, progress=progress,
                  start_time=0.0 if start_time is None else start_time)
    run_cosim, run_me, run_monolithic = _masters(engine)
    # a single FMU fed by tables is still one FMU to run: the tables' events join its own
    members = [c for c in run_asm.components.values() if not isinstance(c, TimeTable)]
    single_fmu = (engine == "c" and len(members) == 1 and adaptive is None
                  and extrapolation is None and scheme is None)
    if jacobian is not None:
        if engine != "c" or own is not None or (mode == "cosim" and not single_fmu):
            raise AssemblyError(f"jacobian (--jacobian) applies to the compiled engine's "
                                f"one-solver runs (mode 'me' or 'monolithic', or a single "
                                f"FMU), and this run is mode '{mode}' in engine '{engine}'")
        common["jacobian"] = jacobian
    if own is not None:
        if engine != "c":
            raise AssemblyError(f"mode '{mode}' runs scene '{name}' with a solver of its "
                                f"own, which has no engine '{engine}'; leave --engine out")
        result = own(run_asm, arguments, **common)
    elif mode == "cosim" and single_fmu:
        # one FMU and nothing to couple: no communication step to choose, so its solver
        # steps freely and outputs come from its dense output
        result = run_me(run_asm, **common)
        result.settings["scheme"] = "single FMU (free steps, dense output)"
    elif mode == "cosim":
        result = run_cosim(run_asm, scheme=scheme or "jacobi",
                           **cosim_scheme(adaptive, extrapolation), **common)
    elif mode == "me":
        result = run_me(run_asm, **common)
    else:
        result = run_monolithic(run_asm, **common)
    result.settings.setdefault("engine", engine)
    result.settings["pruned"] = pruned
    # the values used and the options as asked (None: the default, which may differ by
    # path: a single FMU runs free only where no co-simulation setting was given)
    record = run_record(name, dict(common, mode=mode, engine=engine, scheme=scheme,
                                   adaptive=adaptive, extrapolation=extrapolation,
                                   jacobian=jacobian, prune=prune), params, inputs, asm,
                        # a scene's own solver loads no FMU: no causality to record
                        fed.resolve_causality() if own is None else dict.fromkeys(asm.components))
    run = SceneRun(name, result, sc.figures(result, asm), record)
    result.figures = run.figures
    result.assembly = asm  # the values the run used: a picture draws with them (--param)
    if out is not None:
        result.to_csv(out / f"{name}.csv")
        title, png = f"{name}: {sc.description}", out / f"{name}.png"
        if plot and sc.picture is not None:
            sc.picture(result, title, png)
        elif plot:
            from .plot import column_units, plot_result  # matplotlib: only for a plot
            plot_result(result, sc.plot, title, png, column_units(asm, sc.plot))
        (out / f"{name}.json").write_text(json.dumps(run.summary(), indent=2) + "\n")
    return run
