"""Two processes asking for the same FMU on a cold cache build it once: the second waits
for the first's (fmus.build.build_once) instead of compiling it too, as pytest-xdist and
Dask workers do on a fresh machine."""
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

CHILD = r'''
import fmus.build as build
from components import SpringBlock
build.announce = lambda line: print("BUILT", line, flush=True)
path = build.build_fmu(SpringBlock())
print("PATH", path, flush=True)
'''


def test_the_same_fmu_asked_for_by_two_processes_is_compiled_once(tmp_path):
    env = dict(os.environ, MECHFMU_CACHE=str(tmp_path / "cache"))
    children = [subprocess.Popen([sys.executable, "-c", CHILD], cwd=ROOT, env=env,
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
                for _ in range(2)]
    outputs = [child.communicate(timeout=600) for child in children]
    assert all(child.returncode == 0 for child in children), [err for _, err in outputs]
    lines = [line for out, _ in outputs for line in out.splitlines()]
    paths = {line.split(" ", 1)[1] for line in lines if line.startswith("PATH ")}
    built = [line for line in lines if line.startswith("BUILT ") and "FMU of SpringBlock" in line]
    assert len(paths) == 1 and Path(paths.pop()).is_file()
    # two here when the builds overlap without the lock (as both tries did before it)
    assert len(built) == 1, lines
