"""Defects only a sanitizer sees, each checked in a child process running code built
with MECHFMU_SANITIZE=1 (as `make asan` builds it) with the ASan runtime preloaded;
benchmarks/sanitizer_reports.py reads what AddressSanitizer, UBSan and LeakSanitizer
wrote. (`make asan` runs whole test files this way; these two stay in the default suite.)
"""
import os
import subprocess
import sys
from pathlib import Path

import pytest

from benchmarks.sanitizer_reports import classify

ROOT = Path(__file__).resolve().parents[2]

CHILD = r'''
import sys
from components import SpringBlock
from fmus import build_fmu
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave
for version in (2, 3):
    path = str(build_fmu(SpringBlock(), fmi_version=version))
    md = read_model_description(path)
    cls = FMU2Slave if version == 2 else FMU3Slave
    fmu = cls(guid=md.guid, unzipDirectory=extract(path),
              modelIdentifier=md.coSimulation.modelIdentifier, instanceName="leaks")
    fmu.freeLibrary = lambda: None  # keep the library mapped, so that LSan names frames
    fmu.instantiate()
    for _ in range(3):
        fmu.getFMUState()  # never freed by the importer
    state = fmu.getFMUState()
    blob = fmu.serializeFMUState(state)
    fmu.freeFMUState(state)
    fmu.deserializeFMUState(blob)  # nor this one
    try:  # a corrupt one is refused, and not freed twice by FreeInstance
        fmu.deserializeFMUState(blob[:-8] + b"\xff" * 8)
    except Exception:
        pass
    fmu.freeInstance()
print("done")
'''


def _runtime(name):
    found = subprocess.run(["gcc", f"-print-file-name={name}"], capture_output=True, text=True)
    path = found.stdout.strip()
    return path if os.path.isabs(path) and os.path.exists(path) else None


def sanitized(tmp_path, build: str, code: str) -> dict[str, list[str]]:
    """Runs `build` (compiles, loads nothing) and then `code` with sanitizers, leak
    detection included; the reports of each kind that count (sanitizer_reports)."""
    logs = tmp_path / "logs"
    logs.mkdir()
    env = dict(os.environ, MECHFMU_SANITIZE="1",
               PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]))
    # built first without the preload (gcc under the ASan runtime is slow, and quiet)
    done = subprocess.run([sys.executable, "-c", build], env=env, cwd=ROOT, capture_output=True,
                          text=True, timeout=900)
    assert done.returncode == 0, done.stderr[-2000:]
    env.update(LD_PRELOAD=f"{_runtime('libasan.so')} {_runtime('libstdc++.so') or ''}".strip(),
               ASAN_OPTIONS=f"detect_leaks=1:log_path={logs}/asan", LSAN_OPTIONS="exitcode=0",
               UBSAN_OPTIONS=f"print_stacktrace=1:log_path={logs}/ubsan")
    run = subprocess.run([sys.executable, "-c", code], env=env, cwd=ROOT, capture_output=True,
                         text=True, timeout=900)
    assert run.returncode == 0 and "done" in run.stdout, run.stderr[-2000:]
    texts = [p.read_text(errors="replace") for p in logs.iterdir()]
    assert texts, "LeakSanitizer wrote no log: is leak detection available here?"
    return {k: sum((classify(t)[k] for t in texts), []) for k in ("asan", "ubsan", "leaks")}


NOTHING = {"asan": [], "ubsan": [], "leaks": []}
needs_asan = pytest.mark.skipif(not _runtime("libasan.so"),
                                reason="gcc has no AddressSanitizer runtime")


@needs_asan
def test_free_instance_frees_the_states_the_importer_kept(tmp_path):
    """FreeInstance frees everything the instance allocated (FMI 2 and 3: "frees all the
    allocated memory ... allocated by the functions of the FMU interface"), also the FMU
    states an importer got and never freed. Before, each such state leaked (found by the
    leak check of `make asan`: snap_alloc via mf_get_state)."""
    build = ("from components import SpringBlock\nfrom fmus import build_fmu\n"
             "for v in (2, 3): build_fmu(SpringBlock(), fmi_version=v)")
    assert sanitized(tmp_path, build, CHILD) == NOTHING


ME_RUN = r'''
import math, sys, tempfile
import fmpy.fmi1
fmpy.fmi1._FMU.freeLibrary = lambda self: None  # keep libraries mapped: LSan names frames
from fmpy import simulate_fmu
from assemblies import export_fmu
sys.path.insert(0, "benchmarks")
from benchmarks.fuzz import pushed_block
path = export_fmu(pushed_block(), tempfile.mkdtemp() + "/pushed.fmu", fmi=3, mode="me",
                  outputs=["block.s"], stop_time=1.0, step=0.1)
res = simulate_fmu(str(path), stop_time=1.0, output_interval=0.1)
print("done" if res["block.s"][-1] == 0.0 else "a block at rest moved")
'''


@needs_asan
def test_the_engine_plans_a_jacobian_with_a_stateless_member_without_undefined_behaviour(tmp_path):
    """eng_jacobian_plan copied a member's state references with memcpy from NULL (0
    bytes: still undefined, and UBSan says so) when the member has no states: in an
    assembly FMU of mode 'me', whose description gives the engine no state references,
    a force source coupled to a block (the pushed block, at rest with no force)."""
    assert sanitized(tmp_path, "", ME_RUN) == NOTHING
