"""The wheel works outside the checkout: built with `python -m build --wheel`, installed with
its dependencies into a virtual environment of its own, it runs `mechfmu run stick_slip`
and `mechfmu build SpringBlock` from a folder that is not the repository, compiling the
engine and the FMUs from the C sources it carries (README: Installing from a wheel).

The environment's dependencies (casadi, fmpy, numpy, scipy, matplotlib) come from the
package index once per machine and dependency list: the environment is kept in the cache,
named by a hash of the wheel's requirements and the Python version, and each run installs
the new wheel into it (pip first installs whatever requirement is new). On a busy 2-core
machine the first run took 76 s (43 s of pip), later ones 42 s (mostly the compiles of the
engine and three FMUs into an empty cache).
"""
from __future__ import annotations

import fcntl
import hashlib
import os
import shutil
import subprocess
import sys
import zipfile
from email.parser import Parser
from pathlib import Path

import pytest

from fmus.build import cache_dir

ROOT = Path(__file__).resolve().parents[2]
# what a checkout holds that is not source: never copied into the build
NOT_SOURCE = shutil.ignore_patterns(".git", ".venv", "build", "dist", "out", "*.egg-info",
                                    "__pycache__", ".pytest_cache", "api")

pytest.importorskip("build", reason="the wheel is built with `build`: pip install -e '.[test]'")


def run(cmd, **kw):
    done = subprocess.run([str(c) for c in cmd], capture_output=True, text=True,
                          timeout=600, **kw)
    assert done.returncode == 0, f"{' '.join(map(str, cmd))}:\n{done.stdout}\n{done.stderr}"
    return done


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    """The wheel, built from a copy of the checkout (the build writes build/ and egg-info
    beside the sources; the checkout stays as it is)."""
    tmp = tmp_path_factory.mktemp("wheel")
    source = tmp / "src"
    shutil.copytree(ROOT, source, ignore=NOT_SOURCE)
    run([sys.executable, "-m", "build", "--wheel", "--outdir", tmp / "dist", source])
    (found,) = (tmp / "dist").glob("mechfmu-*.whl")
    return found


@pytest.fixture(scope="module")
def venv(wheel):
    """A virtual environment outside the checkout with `wheel` installed, and the lock that
    keeps a parallel session from reinstalling it while this one runs it."""
    with zipfile.ZipFile(wheel) as zf:
        meta = next(n for n in zf.namelist() if n.endswith(".dist-info/METADATA"))
        requires = Parser().parsestr(zf.read(meta).decode()).get_all("Requires-Dist") or []
    key = hashlib.sha256("\n".join([sys.version, *sorted(requires)]).encode()).hexdigest()
    home = cache_dir() / "test-wheel-venv" / key[:16]
    home.parent.mkdir(parents=True, exist_ok=True)
    with open(home.parent / f"{key[:16]}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        python = home / "bin" / "python"
        if not (home / ".complete").exists():
            shutil.rmtree(home, ignore_errors=True)
            # the base interpreter, not this one's venv: nothing of the checkout's environment
            base = Path(sys.base_prefix) / "bin" / f"python{sys.version_info[0]}.{sys.version_info[1]}"
            run([base, "-m", "venv", home])
            run([python, "-m", "pip", "install", "-q", wheel])  # and its dependencies
            (home / ".complete").touch()
        run([python, "-m", "pip", "install", "-q", wheel])  # a requirement that is new
        run([python, "-m", "pip", "install", "-q", "--no-deps", "--force-reinstall", wheel])
        yield home


def clean_env(**extra) -> dict:
    """The environment of a user's shell: no PYTHONPATH pointing into the checkout."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    return {**env, **extra}


def test_the_wheel_carries_the_c_sources_and_the_benchmarks(wheel):
    """Every C file and header the builds compile, and every module of the packages."""
    with zipfile.ZipFile(wheel) as zf:
        names = set(zf.namelist())
    wanted = [p.relative_to(ROOT).as_posix() for folder in
              ("fmus/runtime", "assemblies/engine/c", "assemblies/engine/fmu",
               "assemblies/engine/fault_c", "benchmarks")
              for p in (ROOT / folder).glob("*.[ch]")]
    wanted += [p.relative_to(ROOT).as_posix() for top in
               ("components", "fmus", "assemblies", "benchmarks")
               for p in (ROOT / top).rglob("*.py") if "__pycache__" not in p.parts]
    assert len(wanted) > 100
    missing = sorted(set(wanted) - names)
    assert not missing, f"the wheel lacks {missing}"
    assert {"fmus/runtime/runtime.c", "assemblies/engine/c/me.c", "benchmarks/c_limit.c",
            "benchmarks/__init__.py"} <= names
    assert not any(n.startswith(("tests/", "docs/")) for n in names)
    entry = next(n for n in names if n.endswith("entry_points.txt"))
    with zipfile.ZipFile(wheel) as zf:
        assert "mechfmu = assemblies.cli:main" in zf.read(entry).decode()


def test_the_installed_wheel_runs_and_builds_outside_the_checkout(venv, tmp_path):
    """From a folder outside the checkout, with an empty cache: the engine and the FMUs are
    compiled from the installed sources, the scene passes, the FMU is a valid FMI 3 one; a
    second run needs no compiler, and a build without one ends in one line."""
    import fmpy
    from fmpy.validation import validate_fmu

    python, mechfmu = venv / "bin" / "python", venv / "bin" / "mechfmu"
    work = tmp_path / "work"
    work.mkdir()
    env = clean_env(MECHFMU_CACHE=str(tmp_path / "cache"))
    where = run([python, "-c", "import assemblies, fmus, components, benchmarks; "
                 "print(assemblies.__file__)"], cwd=work, env=env).stdout.strip()
    assert Path(where).is_relative_to(venv) and not Path(where).is_relative_to(ROOT)

    first = run([mechfmu, "run", "stick_slip"], cwd=work, env=env)
    assert first.stdout.strip().splitlines()[-1] == "all 3 figures pass"
    assert "compiling the engine" in first.stderr and "building the FMU of SpringBlock" in first.stderr
    assert (work / "out" / "stick_slip.csv").exists()

    run([mechfmu, "build", "SpringBlock", "-o", "X.fmu"], cwd=work, env=env)
    assert fmpy.read_model_description(str(work / "X.fmu")).fmiVersion == "3.0"
    assert validate_fmu(str(work / "X.fmu")) == []

    # the cache holds what the run needs: no gcc on PATH, and it runs as before
    no_gcc = {**env, "PATH": str(tmp_path / "empty")}
    again = run([mechfmu, "run", "stick_slip", "--out", "again"], cwd=work, env=no_gcc)
    assert again.stdout.strip().splitlines()[-1] == "all 3 figures pass" and not again.stderr
    # a component not built yet needs gcc: one line saying so, exit status 2
    done = subprocess.run([mechfmu, "build", "SpringBlock", "--param", "friction=tanh",
                           "-o", "Y.fmu"], cwd=work, env=no_gcc, capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 2 and "Traceback" not in done.stderr
    error = done.stderr.strip().splitlines()[-1]
    assert error.startswith("mechfmu: error: cannot build SpringBlock: gcc is not on PATH")
    assert not (work / "Y.fmu").exists()
