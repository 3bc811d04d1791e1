"""Every scene x every settable name of its instances x every mode: runs, or one line.

    python -m benchmarks.param_matrix [--scenes a,b] [--modes cosim,me] [--quick] [--json F]

What `mechfmu show` documents for an instance (parameters, options with their allowed
values, start values, the FMU's `solver`, and the start-value aliases such as the
beam's w_tip0) is what a user may pass as ``--param INSTANCE.NAME=VALUE``. For each
scene and mode (cosim, me, monolithic) the runs are, over a short stop time:

- ``nudged``: every numeric parameter and start value of every instance moved at once to
  a valid value nearby (1 % up, or another step its range allows: `nudge`);
- ``aliases``: every start-value alias at once, where the scene has any;
- one run per option value that is not the scene's own (string options: every value;
  integer options: their least and largest value and any word they take, such as
  n_modes='auto'; --quick: the least value other than the default, and the words, each
  on every instance of a kind at once), and one per FMU solver setting, on every
  instance at once; --quick runs these in the scene's own mode only (option values of a
  joined scene in me: `cases`).

A run passes when it returns a result (its figures may fail: the physics changed) or is
refused with one line: a MechfmuError whose message is a single line. Anything else (a
KeyError from a figure, a traceback from the engine, a message over several lines) is a
failure. tests/integration/test_param_matrix.py runs the --quick cases of every scene;
this command runs them all, 879 runs (380 with --quick: seconds on a warm FMU cache,
minutes of gcc on a cold one, most of it for joined models: coupled_clutches' takes
60-100 s to compile). Most of the full run's time is building FMUs for option
values the cache has not seen; the largest beam is the extreme: n_modes=128 builds in
about 20 s modal, but many minutes of gcc in the assumed coordinates (beam_tip_force)
and as a joined model (monolithic beam_free_vibration, over 12 min on a busy machine):
--scenes and --modes leave them out. Exit status 1 if any run fails.
"""
from __future__ import annotations

import argparse
import json
import sys
import time
import traceback
from dataclasses import asdict, dataclass

MODES = ("cosim", "me", "monolithic")
SOLVER_VALUES = ("0", "1", "2")


@dataclass
class Case:
    label: str
    params: dict
    modes: tuple = MODES  # the modes it runs in


@dataclass
class Outcome:
    scene: str
    mode: str
    case: str
    verdict: str  # ran, refused or failed
    seconds: float
    message: str = ""
    error: str = ""  # the class of what was raised

    @property
    def ok(self) -> bool:
        return self.verdict != "failed"


def short_stop(sc) -> float:
    """A stop time long enough for a few output points and short enough that ninety
    runs take seconds: five output intervals, the scene's own time if shorter."""
    return min(sc.stop_time, 5 * sc.step)


def _accepts(inst, name: str, value) -> bool:
    """Whether `inst` takes `value` for `name` on its own (checked on a copy)."""
    from copy import deepcopy

    from components.errors import MechfmuError
    trial = deepcopy(inst)
    try:
        trial.set(name, value)
        trial.validate()
    except MechfmuError:
        return False
    return True


def nudge(inst, name: str, value: float):
    """A valid value near `value` for `name`: 1 % up, 1 % down, then one up or down (an
    integer variable), then 0.01 from zero; `value` itself where the instance takes none
    of them alone (a name tied to others: a unit axis n, a thin disk's inertia on the
    triangle inequality's edge), so that the name is still set; None if not even that."""
    candidates = ([value * 1.01, value * 0.99, value + 1, value - 1] if value != 0
                  else [0.01, -0.01, 1, -1])
    return next((c for c in candidates + [value] if _accepts(inst, name, c)), None)


def _option_values(option, quick: bool) -> list:
    if isinstance(option.choices, range):
        lo, hi = option.choices.start, option.choices.stop - 1
        # quick: the least value other than the default (a default at the least value,
        # a friction table's rows = 1, would otherwise leave the option untried)
        least = lo if option.default != lo or hi == lo else lo + 1
        return ([least] if quick else [lo, hi]) + list(getattr(option, "words", ()))
    if not option.choices:  # a number (the beam's accuracy): a valid one nearby
        number = float(option.default)
        return [number / 10 if option.parse(number / 10) is not None else number * 1.01]
    return list(option.choices)


def cases(sc, quick: bool = False) -> list[Case]:
    """The runs of scene `sc` (see the module's docstring). With `quick`, an option value
    or solver setting runs in the scene's own mode only, as `--param` without `--mode`
    would: each value in another mode is another FMU to build, and the nudged runs
    already take every mode through every name; an option value of a scene joined into
    one model (monolithic) runs in me instead, where it builds its component's FMU
    alone, not a joined model per value; and an option value is set on every instance
    of a kind in one run."""
    from components.component import Component
    asm = sc.build()
    nudged, aliases = {}, {}
    optional: dict[tuple, Case] = {}
    components = [(name, inst) for name, inst in asm.components.items()]
    for name, inst in components:
        numbers = {**inst.values, **inst.starts}
        options = {o.name: o for o in inst.options}
        for key in inst.settable_names():
            if key in options or key == "solver":
                continue
            if key in numbers:
                value = nudge(inst, key, numbers[key])
                if value is not None:
                    nudged[f"{name}.{key}"] = value
            else:  # an alias of start values (theta0, w_tip0, a modal beam's a_i)
                value = nudge(inst, key, 0.001)
                if value is not None:
                    aliases[f"{name}.{key}"] = value
        for option in inst.options:
            for value in _option_values(option, quick):
                if value == inst.option(option.name):
                    continue
                # quick: a value goes to every instance of the kind at once (one joined
                # model to build in monolithic, not one per clutch of coupled_clutches,
                # 80 s of gcc each); the full matrix tries each instance on its own
                key = ((type(inst).__name__, option.name, repr(value)) if quick
                       else (name, option.name, repr(value)))
                case = optional.setdefault(key, Case("", {}))
                case.params[f"{name}.{option.name}"] = value
                owners = ",".join(param.rsplit(".", 1)[0] for param in case.params)
                case.label = f"{owners}.{option.name}={value}"
    solvers = [Case(f"solver={value}", {f"{name}.solver": value for name, inst in components
                                        if isinstance(inst, Component)})
               for value in SOLVER_VALUES]
    runs = [Case("nudged", nudged)] + ([Case("aliases", aliases)] if aliases else [])
    options, solvers = list(optional.values()), [s for s in solvers if s.params]
    if quick:
        for case in solvers:
            case.modes = (sc.mode,)
        # an option value shapes its component's binary: in me that is the one component's
        # FMU (seconds of gcc), in monolithic the whole joined model again (coupled_clutches:
        # 80 s). The joined models' own options are the full matrix's.
        for case in options:
            case.modes = ("me",) if sc.mode == "monolithic" else (sc.mode,)
    return runs + options + solvers


def run_case(name: str, mode: str, case: Case) -> Outcome:
    """One run, judged: ran, refused in one line, or failed (anything else)."""
    from assemblies.run import run_scene_full
    from assemblies.scenes import SCENES
    from components.errors import MechfmuError
    started = time.perf_counter()
    try:
        run_scene_full(name, mode=mode, stop_time=short_stop(SCENES[name]), params=case.params)
        verdict, message = "ran", ""
    except MechfmuError as exc:
        message, error = str(exc), type(exc).__name__
        verdict = "refused" if message.strip() and "\n" not in message.strip() else "failed"
    except Exception as exc:  # noqa: BLE001 - what this matrix is looking for
        verdict, message, error = "failed", traceback.format_exc(), type(exc).__name__
    else:
        error = ""
    return Outcome(name, mode, case.label, verdict, time.perf_counter() - started, message,
                   error)


def run_matrix(names, modes=MODES, quick: bool = False, report=None) -> list[Outcome]:
    from assemblies.scenes import SCENES
    outcomes = []
    for name in names:
        for case in cases(SCENES[name], quick):
            for mode in (m for m in modes if m in case.modes):
                outcome = run_case(name, mode, case)
                outcomes.append(outcome)
                if report is not None:
                    report(outcome)
    return outcomes


def _line(o: Outcome) -> str:
    first = o.message.strip().splitlines()[-1] if o.message.strip() else ""
    return f"{o.scene:<22} {o.mode:<10} {o.case:<34} {o.verdict:<8} {o.seconds:6.2f} s  {first[:150]}"


def main(argv=None) -> int:
    from assemblies.scenes import SCENES
    parser = argparse.ArgumentParser(prog="python -m benchmarks.param_matrix",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", help="comma-separated scene names (default: every scene)")
    parser.add_argument("--modes", default=",".join(MODES), help="comma-separated modes")
    parser.add_argument("--quick", action="store_true", help="the test's cases only")
    parser.add_argument("--json", help="write every outcome to this file")
    args = parser.parse_args(argv)
    names = args.scenes.split(",") if args.scenes else list(SCENES)
    unknown = [n for n in names if n not in SCENES]
    if unknown:
        parser.error(f"unknown scene(s) {', '.join(unknown)}; scenes: {', '.join(SCENES)}")
    started = time.perf_counter()
    outcomes = run_matrix(names, args.modes.split(","), args.quick,
                          report=lambda o: print(_line(o), flush=True))
    failed = [o for o in outcomes if not o.ok]
    counts = {v: sum(o.verdict == v for o in outcomes) for v in ("ran", "refused", "failed")}
    print(f"{len(outcomes)} runs in {time.perf_counter() - started:.1f} s: "
          + ", ".join(f"{n} {v}" for v, n in counts.items()))
    for o in failed:
        print(f"\nFAILED {o.scene} {o.mode} {o.case}:\n{o.message}")
    if args.json:
        with open(args.json, "w") as handle:
            json.dump([asdict(o) for o in outcomes], handle, indent=1)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
