"""Test helpers for FMUs this project did not generate.

The PI controller FMUs and the closed loop they are checked against live in the package
(:mod:`assemblies.scenes.pi_controller`, also the ``speed_control`` scene's controller);
they are re-exported here. :func:`openmodelica_fmu` takes an OpenModelica FMU out of a
PyPI wheel. :func:`fake_fmu` makes hand-made archives for the loader's checks.
"""
from __future__ import annotations

import hashlib
import os
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

from assemblies.scenes.pi_controller import (PI_DEFAULTS, casadi_pi_fmu,  # noqa: F401
                                             euler_pi_on_sliding_mass, pi_on_sliding_mass,
                                             pythonfmu_pi_fmu)


def fake_fmu(path: Path, model_description: str | None, binaries=("x86_64-linux",),
             identifier: str = "Model") -> Path:
    """A hand-made FMU archive for the loader's checks (nothing in it runs): the given
    modelDescription.xml (none if None) and an empty shared library per binaries folder."""
    with zipfile.ZipFile(path, "w") as zf:
        if model_description is not None:
            zf.writestr("modelDescription.xml", model_description)
        for folder in binaries:
            ext = ".dll" if "win" in folder else ".so"
            zf.writestr(f"binaries/{folder}/{identifier}{ext}", b"")
    return path


# --- FMUs that OpenModelica generated, shipped in a PyPI wheel -------------------------------
# gemseo-fmu 3.1.1 carries FMI 2.0 FMUs exported by OpenModelica (Model Exchange and
# Co-Simulation in one archive; linux64 binaries needing only libc, libm, libpthread).
# The wheel is fetched with pip alone (--no-deps: gemseo itself is never installed) and the FMU
# extracted once per machine; its sha256 is pinned because the tests' references are
# written from this model's equations and parameters.
GEMSEO_FMU = "gemseo-fmu==3.1.1"
OPENMODELICA_FMUS = {
    "Mass_Damper.fmu": "319a1417576bc63ca148e688dd25cc1e834e0c112172405fc0f18132073f136e",
}


def openmodelica_fmu(name: str = "Mass_Damper.fmu") -> Path:
    """`name` from the gemseo-fmu wheel, cached in ``$MECHFMU_CACHE/foreign/gemseo-fmu-3.1.1/``.
    Raises RuntimeError with one line if the wheel cannot be had or the file differs."""
    from fmus.build import cache_dir

    digest = OPENMODELICA_FMUS[name]
    folder = cache_dir() / "foreign" / GEMSEO_FMU.replace("==", "-")
    target = folder / name
    if target.exists() and hashlib.sha256(target.read_bytes()).hexdigest() == digest:
        return target
    folder.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=folder) as work:
        done = subprocess.run([sys.executable, "-m", "pip", "download", "--no-deps",
                               "--disable-pip-version-check", "-q", "--retries", "2",
                               GEMSEO_FMU, "-d", work],
                              capture_output=True, text=True)
        wheels = list(Path(work).glob("gemseo_fmu-*.whl"))
        if done.returncode != 0 or not wheels:
            why = (done.stderr.strip().splitlines() or ["no wheel downloaded"])[-1]
            raise RuntimeError(f"cannot download {GEMSEO_FMU} from PyPI (it ships the "
                               f"OpenModelica FMU {name}): {why}")
        member = f"gemseo_fmu/problems/fmu_files/linux/{name}"
        with zipfile.ZipFile(wheels[0]) as zf:
            if member not in zf.namelist():
                raise RuntimeError(f"{wheels[0].name} has no {member}")
            data = zf.read(member)
        if hashlib.sha256(data).hexdigest() != digest:
            raise RuntimeError(f"{member} in {wheels[0].name} is not the FMU the tests were "
                               f"written for (sha256 {hashlib.sha256(data).hexdigest()}, "
                               f"expected {digest})")
        (Path(work) / name).write_bytes(data)
        os.replace(Path(work) / name, target)  # atomic: a half-written FMU is never seen
    return target
