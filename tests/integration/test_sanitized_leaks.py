"""FreeInstance frees everything the instance allocated (FMI 2 and 3: "frees all the
allocated memory ... allocated by the functions of the FMU interface"), also the FMU
states an importer got and never freed: checked by LeakSanitizer on a SpringBlock FMU
built with MECHFMU_SANITIZE=1 (as `make asan` builds it), driven in a child process
with the ASan runtime preloaded. Before, each such state leaked (found by the leak
check of `make asan`: snap_alloc via mf_get_state)."""
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
    fmu.freeInstance()
print("done")
'''


def _runtime(name):
    found = subprocess.run(["gcc", f"-print-file-name={name}"], capture_output=True, text=True)
    path = found.stdout.strip()
    return path if os.path.isabs(path) and os.path.exists(path) else None


@pytest.mark.skipif(not _runtime("libasan.so"), reason="gcc has no AddressSanitizer runtime")
def test_free_instance_frees_the_states_the_importer_kept(tmp_path):
    logs = tmp_path / "logs"
    logs.mkdir()
    env = dict(os.environ, MECHFMU_SANITIZE="1",
               PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]))
    # built first without the preload (gcc under the ASan runtime is slow, and quiet)
    build = subprocess.run([sys.executable, "-c", "from components import SpringBlock\n"
                            "from fmus import build_fmu\n"
                            "for v in (2, 3): build_fmu(SpringBlock(), fmi_version=v)"],
                           env=env, cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert build.returncode == 0, build.stderr[-2000:]
    env.update(LD_PRELOAD=f"{_runtime('libasan.so')} {_runtime('libstdc++.so') or ''}".strip(),
               ASAN_OPTIONS=f"detect_leaks=1:log_path={logs}/leak", LSAN_OPTIONS="exitcode=0")
    run = subprocess.run([sys.executable, "-c", CHILD], env=env, cwd=ROOT, capture_output=True,
                         text=True, timeout=600)
    assert run.returncode == 0 and "done" in run.stdout, run.stderr[-2000:]
    texts = [p.read_text(errors="replace") for p in logs.iterdir()]
    assert texts, "LeakSanitizer wrote no log: is leak detection available here?"
    found = {k: sum((classify(t)[k] for t in texts), []) for k in ("asan", "ubsan", "leaks")}
    assert found == {"asan": [], "ubsan": [], "leaks": []}, found
