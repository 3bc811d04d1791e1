"""Test helpers for FMUs this project did not generate.

The PI controller FMUs and the closed loop they are checked against live in the package
(:mod:`assemblies.scenes.pi_controller`, also the ``speed_control`` scene's controller);
they are re-exported here. :func:`openmodelica_fmu` takes an OpenModelica FMU out of a
PyPI wheel. :func:`fake_fmu` makes hand-made archives for the loader's checks.
"""
from __future__ import annotations

import zipfile
from pathlib import Path

from assemblies.scenes.pi_controller import (PI_DEFAULTS, casadi_pi_fmu,  # noqa: F401
                                             euler_pi_on_sliding_mass, pi_on_sliding_mass,
                                             pythonfmu_pi_fmu)
from benchmarks.foreign_fmus import gemseo_fmu


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
# benchmarks/foreign_fmus.py fetches the wheel with pip alone (--no-deps: gemseo itself is
# never installed) and extracts the FMU once per machine; its sha256 is pinned because the
# tests' references are written from this model's equations and parameters.
def openmodelica_fmu(name: str = "Mass_Damper.fmu") -> Path:
    """`name` from the gemseo-fmu wheel, cached in ``$MECHFMU_CACHE/foreign/gemseo-fmu-3.1.1/``.
    Raises RuntimeError with one line if the wheel cannot be had or the file differs."""
    return gemseo_fmu(name)
