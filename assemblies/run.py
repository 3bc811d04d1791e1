"""Running a scene: parameters applied, co-simulated, figures measured, files written."""
from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

from .assembly import AssemblyError
from .masters.cosim import cosimulate
from .masters.me import simulate_me
from .masters.monolithic import simulate_monolithic
from .plot import plot_result
from .result import Result
from .scenes import Figure, scene


@dataclass
class SceneRun:
    name: str
    result: Result
    figures: list[Figure]

    def summary(self) -> dict:
        return {"scene": self.name, "settings": self.result.settings,
                "figures": [{"name": f.name, "description": f.description, "measured": f.measured,
                             "reference": f.reference, "error": f.error} for f in self.figures]}

    def table(self) -> str:
        lines = [f"{'figure':<10} {'measured':>16} {'reference':>16} {'error':>10}  description"]
        for f in self.figures:
            lines.append(f"{f.name:<10} {f.measured:>16.10g} {f.reference:>16.10g} {f.error:>10.2e}  "
                         f"{f.description}")
        s = self.result.settings
        if s.get("terminated"):
            lines.append(f"terminated by {s['terminated']['instance']} at t = "
                         f"{s['terminated']['time']:.10g}: {s['terminated']['message']}")
        lines.append(f"stop time {s['stop_time']:g} s, step {s['step']:g} s, tolerance "
                     f"{s['tolerance']:g}, {s['scheme']}, wall time {s['wall_s']:.2f} s")
        if s.get("adaptive"):
            lines.append(f"adaptive to tol {s['tol']:g} (extrapolation {s['extrapolation']}): "
                         f"{s['steps']} steps taken, {s['rejected']} rejected")
        return "\n".join(lines)


MODES = ("cosim", "me", "monolithic")


def run_scene(name: str, stop_time: float | None = None, step: float | None = None,
              tolerance: float | None = None, params: dict | None = None,
              out: str | Path | None = None, scheme: str = "jacobi", progress=None,
              mode: str = "cosim", adaptive: bool | float = False,
              extrapolation: int = 0) -> Result:
    """Run a scene and return its result table (``res['block.x']``).

    `mode` picks the master: ``cosim`` (Co-Simulation FMUs, fixed communication step
    `step`), ``me`` (Model Exchange FMUs under one solver) or ``monolithic`` (the joined
    CasADi model, the reference); for the last two `step` is only the output interval.
    With `out`, also writes ``out/NAME.csv``, ``out/NAME.png`` and ``out/NAME.json``.
    The measured figures are on ``res.figures``. For ``cosim``, `extrapolation` (0, 1, 2)
    is the input extrapolation order and `adaptive` (True, or the error tolerance as a
    number; True means 1e-4) makes `step` the output interval of an adaptive step.
    """
    return run_scene_full(name, stop_time, step, tolerance, params, out, scheme, progress,
                          mode, adaptive, extrapolation).result


def run_scene_full(name, stop_time=None, step=None, tolerance=None, params=None, out=None,
                   scheme="jacobi", progress=None, mode="cosim", adaptive=False,
                   extrapolation=0) -> SceneRun:
    if mode not in MODES:
        raise AssemblyError(f"mode must be one of {', '.join(MODES)}, not '{mode}'")
    sc = scene(name)
    asm = sc.build()
    for key, value in (params or {}).items():
        asm.set(key, value)
    common = dict(stop_time=stop_time if stop_time is not None else sc.stop_time,
                  step=step if step is not None else sc.step,
                  tolerance=tolerance if tolerance is not None else sc.tolerance,
                  record=sc.record, progress=progress)
    if mode == "cosim":
        tol = 1e-4 if adaptive is True else float(adaptive or 1e-4)
        result = cosimulate(asm, scheme=scheme, extrapolation=extrapolation,
                            adaptive=adaptive is not False and adaptive is not None, tol=tol,
                            **common)
    elif mode == "me":
        result = simulate_me(asm, **common)
    else:
        result = simulate_monolithic(asm, **common)
    run = SceneRun(name, result, sc.figures(result, asm))
    result.figures = run.figures
    if out is not None:
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        result.to_csv(out / f"{name}.csv")
        title, png = f"{name}: {sc.description}", out / f"{name}.png"
        if sc.picture is not None:
            sc.picture(result, title, png)
        else:
            plot_result(result, sc.plot, title, png)
        (out / f"{name}.json").write_text(json.dumps(run.summary(), indent=2) + "\n")
    return run
