"""The `mechfmu` command: list, show, build, run, export and bench. Bad input is one line
on stderr, exit 2; a scene run whose figures miss their accuracy exits 1.

Each command imports what it needs when it runs: CasADi, numpy and fmpy take seconds to
load, and ``--help``, ``--version`` and a mistyped option must answer at once. Keep
module-level imports here to the standard library (a test checks it).
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from assemblies.scene_names import SCENE_INDEX, SCENE_NAMES


class UsageError(ValueError):
    """A command-line mistake found by a command (argparse finds the others)."""


FIGURES_FAILED = 1  # the run went through but a figure missed its accuracy (usage errors: 2)
USAGE = 2  # bad input, on the command line or in a value it passes on
INTERRUPTED = 130  # Ctrl-C: the shell's code for SIGINT; what was computed is kept


class _Parser(argparse.ArgumentParser):
    """argparse with its errors on one line, like every other error of the command (argparse
    prints the whole usage first; ``--help`` still shows it)."""

    def error(self, message: str):
        self.exit(USAGE, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def _version() -> str:
    from assemblies.version import mechfmu_version
    return mechfmu_version()


class _Version(argparse.Action):
    """--version, its number looked up only when asked for: importlib.metadata takes
    0.03-0.1 s, which every other command would pay."""

    def __call__(self, parser, namespace, values, option_string=None):
        print(f"mechfmu {_version()}")  # on stdout, as argparse's own version action
        parser.exit()


def _scene_name(name: str) -> str:
    if name not in SCENE_NAMES:
        raise argparse.ArgumentTypeError(f"unknown scene '{name}'; scenes: {', '.join(SCENE_NAMES)}")
    return name


def _parse_params(pairs: list[str]) -> dict[str, str]:
    params = {}
    for pair in pairs or []:
        name, eq, value = pair.partition("=")
        if not eq or not name or not value:
            raise UsageError(f"--param '{pair}' must be NAME=VALUE")
        params[name.strip()] = value.strip()
    return params


def _output_folder(path: str, option: str) -> Path:
    """`path` as a folder the run can write into, made now: a mistake here is found before
    a long run, not after it."""
    from components.errors import writable_folder
    return writable_folder(path, option, UsageError)


def _output_file(path: str, option: str, suffix: str) -> Path:
    """`path` as a file that can be written, checked now (before a build of seconds)."""
    from components.errors import writable_file
    return writable_file(path, option, suffix, UsageError)


def _component_class(name: str):
    from components import COMPONENTS
    if name not in COMPONENTS:
        raise UsageError(f"unknown component '{name}'; components: {', '.join(COMPONENTS)}")
    return COMPONENTS[name]


def _cmd_components(args) -> int:
    from components import COMPONENTS
    for name, cls in COMPONENTS.items():
        profiles = ", ".join(p.name for p in cls.profiles)
        print(f"{name:<20} {cls.describe()} [profiles: {profiles}]")
    return 0


def _cmd_show(args) -> int:
    from components.listing import sheet
    print(sheet(_component_class(args.component)))
    return 0


def _cmd_scenes(args) -> int:
    if args.markdown:
        from assemblies.scenes.listing import markdown_table
        print(markdown_table())
        return 0
    # from the index, not the registry: listing 30 scenes must not import them all
    for name, (_, description) in SCENE_INDEX.items():
        print(f"{name:<18} {description}")
    return 0


def _say_when_building() -> None:
    """Print a line on stderr whenever an FMU is compiled: a build takes seconds."""
    import fmus.build
    fmus.build.announce = lambda line: print(line, file=sys.stderr, flush=True)


def _cmd_build(args) -> int:
    output = _output_file(args.output, "-o/--output", ".fmu")
    cls = _component_class(args.component)
    _say_when_building()
    from fmus import build_fmu
    component = cls(profile=args.profile, **_parse_params(args.param))
    path = build_fmu(component, output, fmi_version=args.fmi)
    print(path)
    return 0


def _run_arguments(args) -> dict:
    """run_scene_full's arguments: the command line's, or with --from the file's with
    each option given on the command line in its place."""
    given = dict(stop_time=args.stop_time, step=args.step, tolerance=args.tolerance,
                 scheme=args.scheme, mode=args.mode,
                 adaptive=False if args.fixed_step else args.adaptive,
                 extrapolation=args.extrapolation, engine=args.engine, jacobian=args.jacobian,
                 start_time=args.start_time, inputs=args.inputs)
    params = _parse_params(args.param)
    if args.from_file is None:
        if args.scene is None:
            raise UsageError("the following arguments are required: scene (or --from "
                             "FILE.json, a run's JSON file, to repeat that run)")
        return dict(given, name=args.scene, params=params, engine=args.engine or "c")
    from assemblies.runfile import read_run, run_arguments
    record = read_run(args.from_file)
    if args.scene is not None and args.scene != record["run"]["scene"]:
        raise UsageError(f"--from {args.from_file} is a run of scene "
                         f"'{record['run']['scene']}', not '{args.scene}'; leave the scene out")
    return run_arguments(record, params, **given)


def _cmd_run(args) -> int:
    out = _output_folder(args.out, "--out")
    kwargs = _run_arguments(args)
    _say_when_building()
    from assemblies.progress import ProgressReport
    from assemblies.run import run_scene_full
    from assemblies.scenes import scene
    sc = scene(kwargs["name"]) if isinstance(kwargs["name"], str) else kwargs["name"]
    if args.animate:  # checked before the run: a wrong file or scene answers at once
        from dataclasses import replace
        from assemblies.scenes.animate import animation_record, check_animation_file
        check_animation_file(args.animate)
        kwargs["name"] = sc = replace(sc, record=animation_record(sc))
    stop = kwargs["stop_time"] if kwargs["stop_time"] is not None else sc.stop_time
    progress = ProgressReport(stop, start_time=kwargs["start_time"] or 0.0)
    try:
        run = run_scene_full(**kwargs, out=out, progress=progress, plot=not args.no_plot)
    finally:
        progress.close()
    print(run.table(verdict=False))
    written = [out / f"{run.name}.{kind}" for kind in ("csv", "png", "json")
               if kind != "png" or not args.no_plot]
    if args.animate:
        from assemblies.scenes.animate import animate
        animate(run.result, run.result.assembly, args.animate, f"{run.name}: {sc.description}")
        written.append(args.animate)
    print("wrote " + ", ".join(map(str, written))
          + (" (no plot: --no-plot)" if args.no_plot else ""))
    print(run.verdict())  # last, so that it is what a reader or a log tail sees
    if run.result.settings.get("interrupted"):
        return INTERRUPTED
    return 0 if run.passed else FIGURES_FAILED


def _cmd_export(args) -> int:
    # checked before the imports and builds (seconds): a mistake answers at once
    if not (args.ssp or args.fmu or args.composite):
        raise UsageError("export needs --ssp FILE.ssp, --fmu FILE.fmu and/or --composite FILE.fmu")
    targets = [(_output_file(path, option, suffix) if path else None) for path, option, suffix in
               ((args.ssp, "--ssp", ".ssp"), (args.fmu, "--fmu", ".fmu"),
                (args.composite, "--composite", ".fmu"))]
    params = _parse_params(args.param)
    _say_when_building()
    from assemblies.fmu_export import export_fmu
    from assemblies.masters.monolithic import composite
    from assemblies.scenes import scene
    from assemblies.ssp import export_ssp
    from fmus import build_fmu
    sc = scene(args.scene)
    exports = (
        lambda a, p: export_ssp(a, p, sc.stop_time),
        # the scene's own master inside doStep (a monolithic scene's members co-simulate)
        lambda a, p: export_fmu(a, p, fmi=args.fmi, outputs=sc.record, stop_time=sc.stop_time,
                                step=sc.step, tolerance=sc.tolerance,
                                mode=sc.mode if sc.mode == "me" else None),
        lambda a, p: build_fmu(composite(a), p, fmi_version=args.fmi))
    for path, export in zip(targets, exports):
        if path:
            asm = sc.build()
            for key, value in params.items():
                asm.set(key, value)
            print(export(asm, path))
    return 0


def _cmd_bench(args) -> int:
    # benchmarks is installed beside the packages (pyproject), so this works off a checkout
    # and from an installed mechfmu alike
    out = _output_folder(args.out, "--out")
    json_path = _output_file(args.json, "--json", ".json") if args.json else None
    try:
        from benchmarks.scenes import GROUPS, SCENES, expand
        from benchmarks.suite import plot, run, table, write_json
    except ModuleNotFoundError as exc:  # an install older than the benchmarks package
        raise UsageError(f"bench needs mechfmu's benchmarks package ({exc}); reinstall "
                         "mechfmu (pip install -e . in a checkout)") from None
    if args.scene in SCENE_NAMES and args.scene not in SCENES:
        raise UsageError(f"scene '{args.scene}' has no work-precision case; bench takes "
                         f"{', '.join([*SCENES, *GROUPS])}")
    try:
        names = expand(args.scene)
    except KeyError as exc:
        raise UsageError(exc.args[0]) from None
    records, _ = run(names, quick=args.quick)
    print(table(records))
    for name in names:
        print(f"wrote {plot(records, name, out / f'bench_{name}.png')}")
    if json_path:
        write_json(records, json_path)
        print(f"wrote {json_path}")
    return 0


def _cmd_sweep(args) -> int:
    """A parameter study on Dask: the table on stdout, CSV, JSON and a plot in --out."""
    try:
        from assemblies.sweep import sweep, write_sweep  # its errors are AssemblyErrors: exit 2
    except ModuleNotFoundError as exc:
        raise UsageError(f"sweep needs {exc.name}: pip install 'mechfmu[sweep]'") from None
    params = {}
    for pair in args.param or []:
        name, eq, spec = pair.partition("=")
        if not eq or not name or not spec:
            raise UsageError(f"--param '{pair}' must be INSTANCE.NAME=START:STOP:COUNT, "
                             "A,B,C or VALUE")
        params[name.strip()] = spec.strip()
    if not params:
        raise UsageError("sweep needs at least one --param INSTANCE.NAME=START:STOP:COUNT")
    _output_folder(args.out, "--out")  # made and checked before the study, not after
    table = sweep(args.scene, params, random=args.random, seed=args.seed,
                  outputs=args.output or (), workers=args.workers, scheduler=args.scheduler,
                  stop_time=args.stop_time, mode=args.mode, start_time=args.start_time)
    paths = write_sweep(table, args.out, args.plot)
    shown = ["run", *params, "status", *table.attrs["outputs"],
             *[c for c in table.columns if f"{c}.ref" in table.columns], "error"]
    print(table[[c for c in dict.fromkeys(shown) if c in table.columns]].to_string(index=False))
    a = table.attrs
    print(f"{a['runs']} runs ({a['design']}), {a['failed']} failed, on {a['workers']} "
          f"worker(s) at {a['scheduler']}: {a['wall_s']:.3g} s, {a['runs_per_s']:.3g} runs/s")
    print("wrote " + ", ".join(str(p) for p in paths))
    return 0


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="mechfmu", description="Mechanical components as FMUs: build them, "
                     "join them into assemblies, run the named scenes of the seed.")
    parser.add_argument("--version", action=_Version, nargs=0,
                        help="show program's version number and exit")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    sub.add_parser("components", help="list the components: the names build and show take") \
        .set_defaults(fn=_cmd_components)
    s = sub.add_parser("show", help="one component's parameters (unit, default, range, meaning), "
                                    "options, states, ports and profiles")
    s.add_argument("component", help="a component's name, as `mechfmu components` lists them")
    s.set_defaults(fn=_cmd_show)
    scenes = sub.add_parser("scenes", help="list the scenes: the names run, export and bench take")
    scenes.add_argument("--markdown", action="store_true",
                        help="README's table: scene, seed section(s), references")
    scenes.set_defaults(fn=_cmd_scenes)
    b = sub.add_parser("build", help="build one component into an FMU")
    b.add_argument("component", help="a component's name, as `mechfmu components` lists them")
    b.add_argument("-o", "--output", required=True, help="the .fmu file to write")
    b.add_argument("--fmi", type=int, choices=(2, 3), default=3,
                   help="FMI version of the FMU (default: 3, as every command and function "
                        "that writes an FMU)")
    b.add_argument("--profile", help="causality profile (default: the component's first; "
                                     "`mechfmu show COMPONENT` lists them)")
    b.add_argument("--param", action="append", metavar="NAME=VALUE",
                   help="parameter, option or start value (repeatable; `mechfmu show "
                        "COMPONENT` lists them with their ranges)")
    b.set_defaults(fn=_cmd_build)
    scene_list = "scenes: " + ", ".join(SCENE_NAMES)
    r = sub.add_parser("run", help="run a scene: writes DIR/SCENE.csv, .png (unless --no-plot) "
                                   "and .json; exits 1 if a figure misses its accuracy",
                       epilog=scene_list)
    r.add_argument("scene", type=_scene_name, nargs="?",
                   help="the scene to run (listed below; `mechfmu scenes` says what each is); "
                        "with --from, the file's")
    r.add_argument("--from", dest="from_file", metavar="FILE.json",
                   help="repeat the run a JSON file of `mechfmu run` records (DIR/SCENE.json: "
                        "its scene, options, every instance's parameters, options and start "
                        "values, and its inputs file, which must be unchanged); each option "
                        "given here overrides the file's (--param is set after its values; a "
                        "new --mode drops its co-simulation options and --jacobian, a new "
                        "--engine its --jacobian). Same mechfmu version only")
    r.add_argument("--stop-time", type=float, metavar="SECONDS",
                   help="end of the run [s] (default: the scene's own)")
    r.add_argument("--start-time", type=float, metavar="SECONDS",
                   help="start of the run [s], before the stop time (default: 0)")
    r.add_argument("--step", type=float, metavar="SECONDS",
                   help="communication step [s] with --fixed-step, else the output interval "
                        "(default: the scene's own)")
    r.add_argument("--inputs", metavar="FILE.csv",
                   help="a table feeding the scene's open signal inputs: a header row "
                        "'time,INSTANCE.INPUT,...' and a row per time; linear between rows "
                        "(discrete inputs held), two rows at one time a step")
    r.add_argument("--tolerance", type=float,
                   help="relative tolerance of the FMUs' solvers, in [1e-14, 1) (default: the "
                        "scene's own)")
    r.add_argument("--param", action="append", metavar="INSTANCE.NAME=VALUE",
                   help="parameter, option or start value (repeatable); NAME=VALUE with no "
                        "instance sets a parameter of the scene itself (burridge_knopoff's "
                        "n, ...: a wrong name lists them)")
    r.add_argument("--scheme", choices=("jacobi", "gauss-seidel"),
                   help="co-simulation sweep (mode cosim only; default: jacobi)")
    r.add_argument("--extrapolation", type=int, choices=(0, 1, 2, 3),
                   help="order of the polynomial a coupled force or acceleration follows "
                        "over a step: 0 constant, 1 linear, 2 quadratic, 3 cubic (mode cosim "
                        "only; default: 3 when adaptive, 0 with --fixed-step)")
    steps = r.add_mutually_exclusive_group()
    steps.add_argument("--adaptive", type=float, nargs="?", const=1e-5, metavar="TOL",
                       help="adaptive communication step with step-doubling error control to "
                            "TOL in (0, 1) (absolute; the default, with TOL 1e-5); --step is the "
                            "output interval (mode cosim only)")
    steps.add_argument("--fixed-step", action="store_true",
                       help="a fixed communication step of --step seconds, no error control "
                            "(mode cosim only)")
    r.add_argument("--mode", choices=("cosim", "me", "monolithic", "fault"),
                   help="master: co-simulation, one solver over Model Exchange FMUs, or the "
                        "joined model; fault: burridge_knopoff's event-driven fault solver "
                        "(default: the scene's own, cosim for most)")
    r.add_argument("--engine", choices=("c", "fmpy"),
                   help="c: the compiled engine, one C call per run (default); fmpy: the "
                        "Python reference masters driving the same FMUs through fmpy (in "
                        "mode monolithic: the joined CasADi model under scipy, no FMU)")
    r.add_argument("--jacobian", choices=("auto", "fd", "exact"),
                   help="the implicit solver's Jacobian (modes me and monolithic): auto, "
                        "directional derivatives unless a foreign FMU's disagree with "
                        "differences at the start (default); fd, finite differences; exact, "
                        "directional derivatives always")
    r.add_argument("--out", default="out", metavar="DIR",
                   help="output folder, made if missing (default: out)")
    r.add_argument("--no-plot", action="store_true",
                   help="write the CSV and JSON only, no .png (and no matplotlib to load: "
                        "the quicker run for scripts)")
    r.add_argument("--animate", metavar="FILE.gif|mp4",
                   help="also render the scene's bodies in 3-D from their recorded attitude "
                        "(to scale, with their paths and the time): .gif, or .mp4 with ffmpeg")
    r.set_defaults(fn=_cmd_run)
    x = sub.add_parser("export", help="export a scene as an SSP file and/or one FMU",
                       epilog=scene_list)
    x.add_argument("scene", type=_scene_name, help="the scene to export (listed below)")
    x.add_argument("--ssp", metavar="FILE.ssp", help="SSP 1.0: the FMUs and SystemStructure.ssd")
    x.add_argument("--fmu", metavar="FILE.fmu",
                   help="the assembly as one FMU: its member FMUs in resources/, the engine "
                        "in doStep (co-simulation, or the one integrator where the scene runs "
                        "'me'; then Model Exchange too)")
    x.add_argument("--composite", metavar="FILE.fmu",
                   help="the joined (monolithic) model of our components as one FMU")
    x.add_argument("--fmi", type=int, choices=(2, 3), default=3,
                   help="FMI version of --fmu and --composite (default: 3, as every command "
                        "and function that writes an FMU; --ssp's members are FMI 2, what "
                        "fmpy's SSP runner instantiates)")
    x.add_argument("--param", action="append", metavar="INSTANCE.NAME=VALUE",
                   help="parameter, option or start value (repeatable)")
    x.set_defaults(fn=_cmd_export)
    k = sub.add_parser("bench", help="work-precision benchmark of a scene: table, log-log plot "
                                     "(needs a source checkout: benchmarks/)")
    k.add_argument("scene", help="a scene run takes that has a benchmark case (stick_slip, "
                                 "stick_slip_smooth, axle_pendulum, coin_rolling, moving_table), "
                                 "beam_N4, beam_N8, beam_N16, beam_N32, beam (all four) or all")
    k.add_argument("--quick", action="store_true", help="three tolerances instead of eight")
    k.add_argument("--json", metavar="FILE", help="write the records as a JSON list")
    k.add_argument("--out", default="out", metavar="DIR",
                   help="folder for the plot (default: out)")
    k.set_defaults(fn=_cmd_bench)
    w = sub.add_parser("sweep", help="parameter study of a scene on Dask: grid or Latin "
                                     "hypercube, a table, CSV, JSON and a plot")
    w.add_argument("scene", type=_scene_name, help="the scene to vary (mechfmu scenes lists them)")
    w.add_argument("--param", action="append", metavar="INSTANCE.NAME=START:STOP:COUNT",
                   help="a parameter, start value or option to vary (repeatable): "
                        "START:STOP:COUNT, A,B,C, or one VALUE held fixed; with --random, "
                        "START:STOP")
    w.add_argument("--random", type=int, metavar="N",
                   help="N runs of a Latin hypercube instead of the grid")
    w.add_argument("--seed", type=int, help="seed of the --random design (repeatable studies)")
    where = w.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, metavar="N",
                       help="worker processes of a local Dask cluster (default: one per core; at "
                            "most two per core; 0 runs in this process)")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="a running Dask scheduler, e.g. tcp://127.0.0.1:8786")
    w.add_argument("--output", action="append", metavar="NAME@T",
                   help="a recorded column at time T, or NAME@end, @max, @min, @absmax "
                        "(repeatable); the scene's figures are always recorded")
    w.add_argument("--plot", action="append", metavar="COLUMN",
                   help="a column to plot (repeatable; default: the outputs, else figures)")
    w.add_argument("--start-time", type=float, metavar="SECONDS",
                   help="start of each run [s] (default: 0)")
    w.add_argument("--stop-time", type=float, help="simulated time of each run [s] "
                                                   "(default: the scene's)")
    w.add_argument("--mode", choices=("cosim", "me", "monolithic"),
                   help="master of each run (default: the scene's)")
    w.add_argument("--out", default="out", help="output folder (default: out)")
    w.set_defaults(fn=_cmd_sweep)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    # here, not at the top: the module-level imports stay the standard library's (a test
    # checks it); components.errors itself loads nothing heavy
    from components.errors import MechfmuError
    try:
        return args.fn(args)
    except (UsageError, MechfmuError) as exc:
        print(f"mechfmu: error: {exc}", file=sys.stderr)
        return USAGE
    except KeyboardInterrupt:  # the fmpy masters, or Ctrl-C outside an engine call
        print("\nmechfmu: interrupted", file=sys.stderr)
        return INTERRUPTED


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
