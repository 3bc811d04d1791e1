"""Cost per communication step: our co-simulation against the C++ engines on PyPI (issue 10).

The same assembly is exported as SSP 1.0 (``assemblies.ssp.export_ssp``: one FMI 2.0 CS
FMU of ours per instance, values baked in, flows coupled through a -1
LinearTransformation) and run for N fixed communication steps of the same size by:

- ``libcosim``  libcosimpy, OSP's libcosim (C++): ``CosimExecution.from_ssp_file``, fixed
  step (its times are integer nanoseconds), a last-value observer attached;
- ``ecos``      ecospy, Ecos (C++): ``EcosSimulation(ssp_path=…, step_size=h)``, no listener;
- ``fmpy ssp``  fmpy's own ``fmpy.ssp.simulation.simulate_ssp`` (Python loop, records
  every connector each step; it drops the -1 flow factor, see ``assemblies/ssp.py``);
- ``ours fmpy`` ``assemblies.masters.cosim.cosimulate`` (fmpy-driven, FMI 3 FMUs of the
  same components, Jacobi, zero-order hold), recording the compared outputs only;
- ``ours engine`` ``assemblies.engine.cosim.cosimulate`` (the compiled engine, same
  signature), when this checkout has it; otherwise skipped with a note.

Every tool is Jacobi with fixed step and a zero-order hold, and every FMU's embedded
solver runs at relative tolerance 1e-8 (the runtime's default, which FMI 2 tools get;
``tolerance=1e-8`` for ours). One difference remains: libcosim and ecos hand on each
output as it was at the end of the step, while ours makes the inputs consistent at each
communication point (motion first, then the spring forces that depend on it directly),
so the forces held over the next step are current. Where no output feeds through
(stick_slip) all tools agree to round-off; where springs feed through they agree to the
coupling error. The table gives, for the compared outputs at the stop time, the largest
difference from ``ours fmpy`` and the error against the joined model as one FMU at
tolerance 1e-10.

Time per step excludes loading and instantiation, reported separately as setup:
libcosim and ecos are timed around their own N-step call (libcosim initializes inside
its first step, so that step counts as setup); ours (fmpy) from the progress callback
after the first step to the one after the last; fmpy ssp and the engine, which are one
call each, by the difference of an N-step and a 1-step run (setup = T(N) - N x per-step);
for the engine the difference is taken on its one C call (``eng_cosimulate``), since the
Python that prepares it jitters by more than the N steps cost.
The C++ engines and the engine are timed best of ``--repeat``; fmpy-driven tools once,
after a warm-up call (FMUs built, the build lookup memoised as in the suite).

    python -m benchmarks.cosim_compare [--json FILE] [--steps N] [--cases …]

libcosimpy, ecospy (and tbb: ecospy's library links libtbb.so.12, which its wheel lacks)
are the optional dependency group ``compare``: ``pip install -e .[compare]``. A tool that
is not installed or refuses the SSP is reported with its error, not hidden.
"""
from __future__ import annotations

import argparse
import contextlib
import ctypes
import glob
import io
import json
import os
import sys
import tempfile
import time
from pathlib import Path
from typing import Callable

from assemblies.assembly import Assembly

from .chain import bench_chain, positions

STEP, STEPS, TOLERANCE = 0.1, 1000, 1e-8
CHAIN_N = 8


def cases() -> dict[str, tuple[Callable[[], Assembly], list[str]]]:
    """{case: (assembly builder, compared outputs as 'instance.variable')}."""
    from assemblies.scenes import scene
    return {
        "stick_slip": (lambda: scene("stick_slip").build(), ["block.x", "block.v"]),
        "two_block_belt": (lambda: scene("two_block_belt").build(),
                           ["block1.s", "block2.s", "coupling.f"]),
        f"chain{CHAIN_N}": (lambda: bench_chain(CHAIN_N),
                            [positions(CHAIN_N)[0], positions(CHAIN_N)[-1]]),
    }


def split_ref(ref: str) -> tuple[str, str]:
    instance, _, variable = ref.partition(".")
    return instance, variable


# --- the tools ----------------------------------------------------------------------
def run_libcosim(ssp: Path, step: float, n_steps: int, compared: list[str]) -> dict:
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver

    log_output_level(CosimLogLevel.ERROR)  # it warns on every start value bound to an output
    step_ns = round(step * 1e9)  # libcosim's time is integer nanoseconds
    started = time.perf_counter()
    execution = CosimExecution.from_ssp_file(str(ssp), step_size=step_ns)
    observer = CosimObserver.create_last_value()
    execution.add_observer(observer)
    ok = execution.step(1)  # initialization happens inside the first step
    stepping = time.perf_counter()
    ok = execution.step(n_steps - 1) and ok
    done = time.perf_counter()
    status = execution.status()
    if not ok or status.current_time != n_steps * step_ns:
        raise RuntimeError(f"libcosim stopped at {status.current_time * 1e-9} s "
                           f"({status.error_code})")
    final = dict(zip(compared, libcosim_reader(execution, observer, compared)()))
    return {"setup_s": stepping - started, "per_step_s": (done - stepping) / (n_steps - 1),
            "final": final}


def libcosim_reader(execution, observer, compared: list[str]):
    """A call returning the `compared` outputs ('instance.variable') as libcosim's
    last-value `observer` holds them now."""
    where = []
    for ref in compared:
        instance, variable = split_ref(ref)
        index = execution.slave_index_from_instance_name(instance)
        vr = {v.name.decode(): v.reference for v in execution.slave_variables(index)}[variable]
        where.append((index, vr))
    return lambda: [float(observer.last_real_values(i, [vr])[0]) for i, vr in where]


def load_ecospy():
    """Import ecospy; its libecosc.so needs libtbb.so.12, which the tbb wheel puts in the
    environment's lib/ (not on the loader's path): load it globally first."""
    for path in sorted(glob.glob(os.path.join(sys.prefix, "lib", "libtbb.so.12*"))):
        ctypes.CDLL(path, mode=os.RTLD_GLOBAL)
        break
    import ecospy
    return ecospy


def run_ecos(ssp: Path, step: float, n_steps: int, compared: list[str]) -> dict:
    ecospy = load_ecospy()
    ecospy.EcosLib.set_log_level("err")
    started = time.perf_counter()
    sim = ecospy.EcosSimulation(ssp_path=str(ssp), step_size=step)
    try:
        sim.init()
        stepping = time.perf_counter()
        sim.step(n_steps)
        done = time.perf_counter()
        reached = sim.get_time()
        if abs(reached - n_steps * step) > 1e-9 * n_steps * step:
            raise RuntimeError(f"ecos stopped at {reached} s")
        final = {ref: float(sim.get_real("::".join(split_ref(ref)))) for ref in compared}
    finally:
        sim.terminate()
        sim.free()
    return {"setup_s": stepping - started, "per_step_s": (done - stepping) / n_steps,
            "final": final}


def _by_difference(call, n_steps: int, repeat: int, timed_part=None) -> dict:
    """Time per step of a one-call tool: (T(N) - T(1)) / (N - 1), each T best of `repeat`,
    so that steps 2 .. N are timed as for the other tools. `timed_part()`, if given, says
    how long the last call spent in its compiled core (the rest is preparation in Python,
    whose jitter would swamp a few microseconds a step)."""
    def best(n):
        walls, cores, final = [], [], None
        for _ in range(repeat):
            started = time.perf_counter()
            final = call(n)
            walls.append(time.perf_counter() - started)
            cores.append(timed_part() if timed_part else walls[-1])
        return min(walls), min(cores), final

    _, core_1, _ = best(1)
    wall_n, core_n, final = best(n_steps)
    per_step = (core_n - core_1) / (n_steps - 1)
    return {"setup_s": wall_n - n_steps * per_step, "per_step_s": per_step, "final": final}


def run_fmpy_ssp(ssp: Path, step: float, n_steps: int, compared: list[str]) -> dict:
    from fmpy.ssp.simulation import simulate_ssp

    def call(n):
        # its loop runs while time < stop with time += step: stop half a step early for n steps
        rows = simulate_ssp(str(ssp), stop_time=(n - 0.5) * step, step_size=step)
        assert len(rows) == n, (len(rows), n)
        return {ref: float(rows[ref][-1]) for ref in compared}  # the last row: end of step n

    return _by_difference(call, n_steps, repeat=1)


def run_ours_fmpy(build, step: float, n_steps: int, compared: list[str]) -> dict:
    from assemblies.masters.cosim import cosimulate

    from .runners import builds_memoised

    with builds_memoised():
        cosimulate(build(), 2 * step, step, TOLERANCE, record=compared)  # warm-up: builds
        stamps = []
        started = time.perf_counter()
        result = cosimulate(build(), n_steps * step, step, TOLERANCE, record=compared,
                            progress=lambda t: stamps.append(time.perf_counter()))
    assert len(stamps) == n_steps
    per_step = (stamps[-1] - stamps[0]) / (n_steps - 1)
    return {"setup_s": stamps[0] - started - per_step, "per_step_s": per_step,
            "final": {ref: float(result[ref][-1]) for ref in compared}}


def run_engine(build, step: float, n_steps: int, compared: list[str], repeat: int) -> dict:
    import assemblies.engine.cosim as engine  # written in parallel: may be missing

    def call(n):
        result = engine.cosimulate(build(), n * step, step, TOLERANCE, record=compared)
        return {ref: float(result[ref][-1]) for ref in compared}

    call(2)  # warm-up: builds the engine and the FMUs
    with _c_call_timer(engine) as c_seconds:
        return _by_difference(call, n_steps, repeat,
                              timed_part=(lambda: c_seconds[-1]) if c_seconds is not None else None)


@contextlib.contextmanager
def _c_call_timer(engine):
    """Time the engine's one C call (``eng_cosimulate``: load, instantiate, run) apart from
    its Python preparation, by handing ``cosimulate`` a library whose entry is timed. None
    (whole calls are timed) if the binding is not shaped as expected."""
    get_lib = getattr(engine, "_lib", None)
    lib = get_lib() if callable(get_lib) else None
    if lib is None or not hasattr(lib, "eng_cosimulate"):
        yield None
        return
    seconds: list[float] = []

    class Timed:
        def __getattr__(self, name):
            return getattr(lib, name)

        def eng_cosimulate(self, *args):
            started = time.perf_counter()
            try:
                return lib.eng_cosimulate(*args)
            finally:
                seconds.append(time.perf_counter() - started)

    timed = Timed()
    engine._lib = lambda: timed
    try:
        yield seconds
    finally:
        engine._lib = get_lib


# --- the comparison -----------------------------------------------------------------
def compare_case(name: str, build, compared: list[str], step: float, n_steps: int,
                 repeat: int, workdir: Path, log=print) -> dict:
    from assemblies.ssp import export_ssp

    ssp = export_ssp(build(), workdir / f"{name}.ssp", n_steps * step)
    asm = build()
    rows = {"fmus": len(asm.components), "couplings": len(asm.couplings()), "tools": {}}
    tools = {
        "libcosim": lambda: _best(run_libcosim, repeat, ssp, step, n_steps, compared),
        "ecos": lambda: _best(run_ecos, repeat, ssp, step, n_steps, compared),
        "fmpy ssp": lambda: run_fmpy_ssp(ssp, step, n_steps, compared),
        "ours fmpy": lambda: run_ours_fmpy(build, step, n_steps, compared),
        "ours engine": lambda: run_engine(build, step, n_steps, compared, repeat),
    }
    for tool, run in tools.items():
        try:
            with contextlib.redirect_stdout(io.StringIO()):  # fmpy prints its clean-up
                rows["tools"][tool] = run()
        except Exception as exc:
            rows["tools"][tool] = {"error": f"{type(exc).__name__}: {exc}".splitlines()[0][:300]}
        r = rows["tools"][tool]
        log(f"  {name:16s} {tool:12s} " + (f"{r['per_step_s'] * 1e6:10.1f} us/step, setup "
                                           f"{r['setup_s'] * 1e3:8.1f} ms" if "error" not in r
                                           else f"not measured: {r['error']}"))
    reference = rows["tools"].get("ours fmpy", {}).get("final")
    exact = exact_final(build, step, n_steps, compared)
    rows["exact"] = exact
    for r in rows["tools"].values():
        if "final" in r and reference:
            r["max_abs_diff_vs_ours_fmpy"] = max(abs(r["final"][k] - reference[k]) for k in compared)
        if "final" in r:
            r["max_abs_error"] = max(abs(r["final"][k] - exact[k]) for k in compared)
    return rows


def exact_final(build, step: float, n_steps: int, compared: list[str]) -> dict[str, float]:
    """The compared outputs at the stop time without coupling error: the joined model as one
    FMU at tolerance 1e-10 (what every co-simulation above approximates at O(step))."""
    from assemblies.masters.monolithic import simulate_monolithic
    result = simulate_monolithic(build(), n_steps * step, step, 1e-10, record=compared,
                                 engine="fmu")
    return {ref: float(result[ref][-1]) for ref in compared}


def _best(run, repeat, *args):
    results = [run(*args) for _ in range(repeat)]
    return min(results, key=lambda r: r["per_step_s"])


def report(data: dict) -> str:
    lines = [f"co-simulation, {data['steps']} fixed steps of {data['step']:g} s, Jacobi, FMU "
             f"tolerance {TOLERANCE:g}: wall time per communication step (setup apart)",
             f"{'case':16s}{'FMUs':>5s} {'tool':12s}{'us/step':>10s}{'us/step/FMU':>13s}"
             f"{'setup ms':>10s}{'x engine':>10s}{'|vs ours fmpy|':>16s}{'|error|':>12s}"]
    for name, case in data["cases"].items():
        engine = case["tools"].get("ours engine", {}).get("per_step_s")
        for tool, r in case["tools"].items():
            if "error" in r:
                lines.append(f"{name:16s}{case['fmus']:5d} {tool:12s}  not measured: {r['error']}")
                continue
            ratio = f"{r['per_step_s'] / engine:10.2f}" if engine else f"{'-':>10s}"
            diff, error = r.get("max_abs_diff_vs_ours_fmpy"), r.get("max_abs_error")
            lines.append(f"{name:16s}{case['fmus']:5d} {tool:12s}{r['per_step_s'] * 1e6:10.1f}"
                         f"{r['per_step_s'] * 1e6 / case['fmus']:13.2f}{r['setup_s'] * 1e3:10.1f}"
                         f"{ratio}{'' if diff is None else f'{diff:16.2e}'}"
                         f"{'' if error is None else f'{error:12.2e}'}")
    lines += ["x engine: the tool's time per step over the compiled engine's (> 1: the engine is "
              "cheaper). |vs ours fmpy|, |error|: largest difference of the compared outputs at the "
              "stop time from ours (fmpy) and from the joined model at tolerance 1e-10.",
              "fmpy ssp drops the SSP's -1 flow factor: where a force drives a mass its result is "
              "wrong (assemblies/ssp.py). libcosim and ecos pass each output as it was at the end of "
              "the step; ours first sets the motion inputs and then reads the forces that depend on "
              "them directly (springs), so the forces held over the next step are the current ones."]
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.cosim_compare",
                                 description="per-step cost of our co-simulation vs libcosim, "
                                             "Ecos and fmpy on the same SSP")
    ap.add_argument("--json", help="write the measurements to this file")
    ap.add_argument("--steps", type=int, default=STEPS, help="communication steps N")
    ap.add_argument("--step", type=float, default=STEP, help="communication step [s]")
    ap.add_argument("--repeat", type=int, default=3, help="best of this many (C++ tools, engine)")
    ap.add_argument("--cases", nargs="+", help=f"subset of: {', '.join(cases())}")
    args = ap.parse_args(argv)
    if args.steps < 2:
        ap.error("--steps must be at least 2")
    chosen = cases()
    if args.cases:
        unknown = set(args.cases) - set(chosen)
        if unknown:
            ap.error(f"unknown case(s) {', '.join(sorted(unknown))}; known: {', '.join(chosen)}")
        chosen = {k: chosen[k] for k in args.cases}
    data = {"step": args.step, "steps": args.steps, "tolerance": TOLERANCE, "cases": {}}
    with tempfile.TemporaryDirectory() as tmp:
        for name, (build, compared) in chosen.items():
            data["cases"][name] = compare_case(name, build, compared, args.step, args.steps,
                                               args.repeat, Path(tmp))
    print(report(data))
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(data, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
