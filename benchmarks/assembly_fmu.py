"""Scenes exported as one FMU (assemblies/fmu_export.py) against the same scene run from
Python: agreement and run time, FMI 2 and 3.

    python -m benchmarks.assembly_fmu [--scenes NAME …] [--json FILE]

Each scene is exported with its own experiment, outputs and master (mode 'me' where the
scene runs 'me', 'cosim' otherwise), validated by fmpy, and run by ``fmpy.simulate_fmu``
through its Co-Simulation interface (and, in mode 'me', its Model Exchange interface,
CVode at relative tolerance 1e-10). The deviation is the largest difference of any
recorded column from the Python-side run with the same settings, weighed by max(1, the
column's largest |value|); the stated accuracy is round-off (1e-12) where the FMU runs
the same master on the same steps, and 1e4 x the tolerance where fmpy's CVode integrates
(its global error is not bounded by its tolerance). Wall times are the least of a few
calls (the machine is shared); the fmpy side includes its per-run setup.
"""
from __future__ import annotations

import argparse
import json
import tempfile
from pathlib import Path

import numpy as np
from fmpy import simulate_fmu
from fmpy.validation import validate_fmu

from assemblies.engine.cosim import DEFAULT_SCHEME, cosimulate
from assemblies.engine.me import simulate_me
from assemblies.fmu_export import export_fmu
from assemblies.scenes import scene

from .chain import best_of

SCENES = ("stick_slip", "two_block_belt", "beam_friction_damper", "conveyor", "moving_table",
          "axle_motor", "speed_control")
CVODE_TOLERANCE = 1e-10


def deviation(fmu_result, python_result, columns) -> float:
    worst = 0.0
    for c in columns:
        b = python_result[c]
        a = np.interp(python_result["time"], fmu_result["time"], fmu_result[c])
        worst = max(worst, float(np.abs(a - b).max()) / max(1.0, float(np.abs(b).max())))
    return worst


def measure(name: str, fmi: int, folder: Path) -> list[dict]:
    sc = scene(name)
    mode = "me" if sc.mode == "me" else "cosim"
    path = export_fmu(sc.build(), folder / f"{name}-{fmi}.fmu", fmi=fmi, outputs=sc.record,
                      stop_time=sc.stop_time, step=sc.step, tolerance=sc.tolerance, mode=mode)
    messages = validate_fmu(str(path))
    if mode == "me":
        python_s, python = best_of(lambda: simulate_me(sc.build(), sc.stop_time, sc.step,
                                                       sc.tolerance, record=sc.record))
    else:
        python_s, python = best_of(lambda: cosimulate(sc.build(), sc.stop_time, sc.step,
                                                      sc.tolerance, record=sc.record,
                                                      **DEFAULT_SCHEME))
    interfaces = ["CoSimulation"] + (["ModelExchange"] if mode == "me" else [])
    rows = []
    for interface in interfaces:
        fmu_s, res = best_of(lambda: simulate_fmu(
            str(path), fmi_type=interface, stop_time=sc.stop_time, output_interval=sc.step,
            relative_tolerance=CVODE_TOLERANCE, record_events=False))
        accuracy = 1e-12 if interface == "CoSimulation" else 1e4 * CVODE_TOLERANCE
        error = deviation(res, python, sc.record)
        rows.append(dict(scene=name, fmi=fmi, mode=mode, interface=interface,
                         validate=len(messages), deviation=error, accuracy=accuracy,
                         passed=bool(error <= accuracy and not messages), fmu_s=fmu_s,
                         python_s=python_s))
    return rows


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", nargs="+", default=list(SCENES))
    parser.add_argument("--json", default="benchmarks/assembly_fmu.json")
    args = parser.parse_args(argv)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.scenes:
            for fmi in (2, 3):
                rows += measure(name, fmi, Path(tmp))
    print(f"{'scene':<22}{'fmi':>4} {'mode':<6}{'interface':<14}{'msgs':>5}{'deviation':>11}"
          f"{'accuracy':>10}{'fmu s':>9}{'python s':>10}  verdict")
    for r in rows:
        print(f"{r['scene']:<22}{r['fmi']:>4} {r['mode']:<6}{r['interface']:<14}{r['validate']:>5}"
              f"{r['deviation']:>11.2e}{r['accuracy']:>10.0e}{r['fmu_s']:>9.3f}{r['python_s']:>10.3f}"
              f"  {'pass' if r['passed'] else 'FAIL'}")
    Path(args.json).write_text(json.dumps(rows, indent=1))
    print(f"wrote {args.json}")
    return 0 if all(r["passed"] for r in rows) else 1


if __name__ == "__main__":
    raise SystemExit(main())
