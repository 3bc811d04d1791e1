"""valgrind memcheck of real FMU runs: `python benchmarks/memcheck.py`.

Builds the FMI 2 and FMI 3 FMUs of SpringBlock (events, both Co-Simulation solvers)
and RollingCoin (ends its run by terminate), compiles memcheck_harness.c for each
FMI version, runs it under `valgrind --error-exitcode=1 --leak-check=full` and prints
one row per FMU: memcheck errors, bytes definitely/indirectly lost, the harness's
own verdict on every status it got. Exit code 0 only if every row is clean.
Not part of the test suite: it needs valgrind and takes about a minute.
"""
from __future__ import annotations

import re
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from fmpy import read_model_description  # noqa: E402

from components import RollingCoin, SpringBlock  # noqa: E402
from fmus.build import FMI_HEADERS, build_fmu  # noqa: E402

HARNESS = Path(__file__).with_name("memcheck_harness.c")
# (component, the state to start away from rest, its start value)
CASES = [(SpringBlock(m=1, k=1, g=1, mu_k=0.6, mu_s=0.6), "x", 6.55),  # seed 9.4: 5 events
         (RollingCoin(), None, None)]


def _harness(version: int, tmp: Path) -> Path:
    exe = tmp / f"harness{version}"
    subprocess.run(["gcc", "-std=c99", "-g", "-O0", "-Wall", f"-DFMI_VERSION={version}",
                    f"-I{FMI_HEADERS}", str(HARNESS), "-o", str(exe), "-ldl", "-lm"], check=True)
    return exe


def _library(fmu: Path, tmp: Path) -> Path:
    with zipfile.ZipFile(fmu) as zf:
        name = next(n for n in zf.namelist() if n.startswith("binaries/") and n.endswith(".so"))
        zf.extract(name, tmp / fmu.stem)
    return tmp / fmu.stem / name


def main() -> int:
    rows, clean = [], True
    with tempfile.TemporaryDirectory(prefix="mechfmu-memcheck-") as tmp:
        tmp = Path(tmp)
        for version in (2, 3):
            exe = _harness(version, tmp)
            for component, state, start in CASES:
                fmu = build_fmu(component, fmi_version=version)
                md = read_model_description(str(fmu))
                vr = {v.name: v.valueReference for v in md.modelVariables}
                state = state or next(v.name for v in md.modelVariables
                                      if v.causality in ("local", "output") and v.initial == "exact")
                start = start if start is not None else float(getattr(component, "starts")[state])
                cmd = ["valgrind", "--error-exitcode=1", "--leak-check=full",
                       "--errors-for-leak-kinds=definite,indirect", str(exe),
                       str(_library(fmu, tmp)), md.guid, str(vr["solver"]), str(vr[state]),
                       repr(start)]
                run = subprocess.run(cmd, capture_output=True, text=True)
                errors = int(re.search(r"ERROR SUMMARY: (\d+) errors", run.stderr).group(1))
                lost = {k: int(re.search(rf"{k} lost: ([\d,]+) bytes", run.stderr).group(1)
                               .replace(",", "")) if f"{k} lost:" in run.stderr else 0
                        for k in ("definitely", "indirectly")}
                statuses = "ok" if "unexpected status" not in run.stderr else "UNEXPECTED"
                ok = run.returncode == 0 and errors == 0 and not any(lost.values())
                clean &= ok
                rows.append((type(component).__name__, f"FMI {version}", errors,
                             lost["definitely"], lost["indirectly"], statuses,
                             "clean" if ok else f"FAIL (exit {run.returncode})"))
                if not ok:
                    print(run.stderr[-4000:], file=sys.stderr)
    header = ("FMU", "version", "errors", "def. lost", "ind. lost", "statuses", "verdict")
    widths = [max(len(str(r[i])) for r in [header, *rows]) for i in range(len(header))]
    for r in [header, *rows]:
        print("  ".join(str(c).ljust(w) for c, w in zip(r, widths)))
    return 0 if clean else 1


if __name__ == "__main__":
    sys.exit(main())
