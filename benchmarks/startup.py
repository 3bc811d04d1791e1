"""How long a command takes as a whole process: `python -m benchmarks.startup [--runs N]`.

A user feels the whole process (interpreter, imports, FMUs loaded, the run, the files),
not the simulation alone: each command below is started afresh `--runs` times on a warm
cache (one untimed run of each first builds and files its FMUs and warms the OS's file
cache and the bytecode of every module), and its wall time reported as median, min and
max, with the median CPU time beside. `mechfmu` is run as ``python -m assemblies.cli``
of this interpreter, so the checkout on ``PYTHONPATH`` is what is timed. Writes
benchmarks/startup.json (``--json``) and, with ``--results``, the section "Startup of a
command (issue 26)" of benchmarks/RESULTS.md.

The times depend on the machine and on its load; no test asserts them (the imports each
path makes are checked instead: tests/unit/test_import_paths.py).
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).parent
ROOT = HERE.parent
JSON_PATH = HERE / "startup.json"
MECHFMU = [sys.executable, "-m", "assemblies.cli"]
API_RUN = ("import assemblies; "
           "assemblies.run_scene('stick_slip', out={out!r}, plot=False)")

# (label, argv with {out} for a scratch folder, target [s] or None)
CASES = (
    ("python -c pass", [sys.executable, "-c", "pass"], None),
    ("mechfmu --help", [*MECHFMU, "--help"], None),
    ("mechfmu scenes", [*MECHFMU, "scenes"], 0.3),
    ("mechfmu components", [*MECHFMU, "components"], 0.3),
    ("mechfmu show SpringBlock", [*MECHFMU, "show", "SpringBlock"], 0.3),
    ("mechfmu run stick_slip --no-plot",
     [*MECHFMU, "run", "stick_slip", "--no-plot", "--out", "{out}"], 0.4),
    ("mechfmu run stick_slip", [*MECHFMU, "run", "stick_slip", "--out", "{out}"], 1.2),
    ("mechfmu run two_block_belt --no-plot",
     [*MECHFMU, "run", "two_block_belt", "--no-plot", "--out", "{out}"], None),
    ("python: import assemblies; run_scene (no plot)",
     [sys.executable, "-c", API_RUN], 0.4),
)


def _environment() -> dict:
    env = dict(os.environ)
    # as installed Python runs: modules compiled once, their bytecode cached (without it,
    # each process compiles every module of ours again: 0.2-0.5 s of a run)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT), env.get("PYTHONPATH")) if p)
    env.setdefault("MPLBACKEND", "Agg")
    return env


def _cpu_of_children() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def _once(argv: list[str], out: str, env: dict) -> tuple[float, float]:
    """(wall, CPU) seconds of one process running `argv`."""
    argv = [a.format(out=out) for a in argv]
    cpu, started = _cpu_of_children(), time.perf_counter()
    done = subprocess.run(argv, cwd=ROOT, env=env, capture_output=True, text=True)
    elapsed, cpu = time.perf_counter() - started, _cpu_of_children() - cpu
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(argv)} exited {done.returncode}: "
                           f"{(done.stderr or done.stdout).strip().splitlines()[-1:]}")
    return elapsed, cpu


def measure(runs: int = 7, cases=CASES) -> list[dict]:
    """One row per case: median, min and max wall time [s] of `runs` fresh processes,
    after one untimed run (builds, recipes, file cache), and their median CPU time (user
    and system: what a quiet machine's wall time would be near, as the commands run on
    one core)."""
    env = _environment()
    rows = []
    with tempfile.TemporaryDirectory(prefix="mechfmu-startup-") as out:
        for label, argv, target in cases:
            try:
                _once(argv, out, env)  # warm: FMUs built and filed, files in the OS cache
                times, cpus = zip(*[_once(argv, out, env) for _ in range(runs)])
            except RuntimeError as exc:  # a command this checkout lacks: said, not timed
                rows.append({"command": label, "error": str(exc), "target_s": target,
                             "met": None})
                continue
            median = statistics.median(times)
            rows.append({"command": label, "median_s": median, "min_s": min(times),
                         "max_s": max(times), "cpu_median_s": statistics.median(cpus),
                         "runs": runs, "target_s": target,
                         "met": None if target is None else median <= target})
    return rows


def table(rows: list[dict]) -> str:
    lines = [f"{'command':<48} {'median [s]':>10} {'min':>7} {'max':>7} {'CPU':>7} "
             f"{'target':>7}  verdict"]
    for r in rows:
        target = "-" if r["target_s"] is None else f"{r['target_s']:.2f}"
        if "error" in r:
            lines.append(f"{r['command']:<48} failed: {r['error']}")
            continue
        verdict = "" if r["met"] is None else ("met" if r["met"] else "MISSED")
        lines.append(f"{r['command']:<48} {r['median_s']:>10.3f} {r['min_s']:>7.3f} "
                     f"{r['max_s']:>7.3f} {r['cpu_median_s']:>7.3f} {target:>7}  {verdict}")
    return "\n".join(lines)


def results_section(data: dict) -> list[str]:
    """RESULTS.md's lines for startup.json."""
    out = ["## Startup of a command (issue 26)", "",
           f"From `python -m benchmarks.startup --runs {data['runs']} --results` "
           f"({data['when']}, {data['machine']}); raw: `benchmarks/startup.json`. Each "
           "command is a fresh process on a warm cache (one untimed run first); median "
           "(min-max) wall time. `mechfmu` is `python -m assemblies.cli`. Load average "
           f"{data['load_average'][0]:.1f} before and {data['load_average'][1]:.1f} after "
           "the runs: a busy machine stretches every row alike, `python -c pass` shows by "
           "how much; the CPU time (user and system, median) is what a quiet machine's "
           "wall time comes near.", "",
           "| command | median [s] | min-max [s] | CPU [s] | target [s] | |",
           "|---|---|---|---|---|---|"]
    for r in data["rows"]:
        target = "-" if r["target_s"] is None else f"≤ {r['target_s']:g}"
        if "error" in r:
            out.append(f"| `{r['command']}` | failed | | | {target} | |")
            continue
        verdict = "" if r["met"] is None else ("met" if r["met"] else "**missed**")
        out.append(f"| `{r['command']}` | {r['median_s']:.3f} | {r['min_s']:.3f}-"
                   f"{r['max_s']:.3f} | {r['cpu_median_s']:.3f} | {target} | {verdict} |")
    return out + [""]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.startup",
                                 description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=7, help="timed processes per command "
                                                        "(default: 7)")
    ap.add_argument("--json", default=str(JSON_PATH), help="where to write the figures "
                                                          "(default: benchmarks/startup.json)")
    ap.add_argument("--results", action="store_true",
                    help="also write the section of benchmarks/RESULTS.md")
    args = ap.parse_args(argv)
    if args.runs < 1:
        ap.error("--runs must be at least 1")
    load_before = os.getloadavg()[0]
    rows = measure(args.runs)
    print(table(rows))
    data = {"when": time.strftime("%Y-%m-%d %H:%M"),
            "machine": f"{platform.node()}, {os.cpu_count()} cores, "
                       f"Python {platform.python_version()}",
            # a busy machine stretches every figure alike: `python -c pass` shows by how much
            "load_average": [load_before, os.getloadavg()[0]],
            "runs": args.runs, "rows": rows}
    print(f"load average {load_before:.1f} before, {os.getloadavg()[0]:.1f} after "
          f"({os.cpu_count()} cores)")
    Path(args.json).write_text(json.dumps(data, indent=1) + "\n")
    print(f"wrote {args.json}")
    if args.results:
        from .run_all import replace_section
        replace_section(HERE / "RESULTS.md", results_section(data))
        print(f"wrote {HERE / 'RESULTS.md'}")
    return 0  # a missed target is a figure, not a failure: it depends on the machine's load


if __name__ == "__main__":
    raise SystemExit(main())
