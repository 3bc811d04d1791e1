"""Shared test helpers: the seed's parameter sets and an independent Coulomb reference."""
from __future__ import annotations

import math

import numpy as np
import pytest

from benchmarks.references import coulomb_drag

# seed Eq. 9.4
SEED_94 = dict(m=1.0, k=1.0, g=1.0, mu_k=0.3, mu_s=0.4)
SEED_94_SPEED = 0.05


coulomb_drag_reference = coulomb_drag  # the exact piecewise solution of seed 9.2


@pytest.fixture(scope="session")
def fresh_cache(tmp_path_factory):
    return tmp_path_factory.mktemp("fmu-cache")


def simulate_in_fmpy(component, fmi_type, stop_time, output_interval, tolerance=1e-10,
                     output=None, tmp_path=None):
    """Run a component's FMU through fmpy.simulate_fmu alone (no master of ours).

    The component's parameter values and state starts are passed as start values,
    as any importer would set them.
    """
    from fmpy import simulate_fmu

    from fmus import build_fmu

    path = build_fmu(component)
    starts = {**component.values, **component.starts}
    return simulate_fmu(str(path), fmi_type=fmi_type, stop_time=stop_time,
                        output_interval=output_interval, relative_tolerance=tolerance,
                        start_values=starts, output=output, record_events=True)


def cli(capsys, *argv):
    """(exit code, stderr lines) of `mechfmu argv`, run in this process."""
    from assemblies.cli import main

    try:
        code = main(list(argv))
    except SystemExit as exc:  # argparse's own errors exit
        code = exc.code
    return code, capsys.readouterr().err.strip().splitlines()


def one_line_error(capsys, argv, words):
    code, lines = cli(capsys, *argv)
    assert code == 2
    assert len(lines) == 1, lines
    assert "Traceback" not in lines[0]
    for word in words:
        assert word in lines[0], (word, lines[0])
    return lines[0]


def quick_refusal(call, *words):
    """`call` raises one of our ValueErrors (a MechfmuError), one line holding `words`, in
    under a second: how every bad input must end (issue 25). Returns the message."""
    import time

    from components.errors import MechfmuError

    started = time.perf_counter()
    with pytest.raises(MechfmuError) as caught:
        call()
    assert time.perf_counter() - started < 1.0
    assert isinstance(caught.value, ValueError)
    message = str(caught.value)
    assert "\n" not in message
    for word in words:
        assert word in message, (word, message)
    return message


# seed 9.4 with m = k = g = 1, mu_s = mu_k = 0.6, x(0) = 6.55
FRICTION_DAMPING_TURNING = [6.55, -5.35, 4.15, -2.95, 1.75, -0.55]


def exact_friction_damping(t, mu=0.6):
    """Seed 9.4 by hand: half-cycle n is x = c + (A - c) cos(t - n pi) about c = sign(A) mu,
    then stuck at the last turning point."""
    turning = FRICTION_DAMPING_TURNING
    x = np.full_like(t, turning[-1])
    for n, amplitude in enumerate(turning[:-1]):
        centre = math.copysign(mu, amplitude)
        inside = (t >= n * math.pi) & (t <= (n + 1) * math.pi)
        x[inside] = centre + (amplitude - centre) * np.cos(t[inside] - n * math.pi)
    return x


def drop_component():
    """A point mass falling from 2 m; the model ends its run when it reaches the ground."""
    from components import Component
    from components.interfaces import Parameter, Profile, State

    class Drop(Component):
        """Point mass falling from a height; the model ends when it reaches the ground."""

        parameters = (Parameter("g", 9.81, "m/s2", "gravity", min=0.0, min_strict=True),)
        states = (State("h", 2.0, "m", "height above the ground"),
                  State("w", 0.0, "m/s", "upward velocity"))
        profiles = (Profile("free", "no ports"),)

        def equations(self, e):
            e.residual(e.der.h - e.x.w)
            e.residual(e.der.w + e.p.g)
            e.terminate_when(e.x.h, "the mass hit the ground")

    return Drop


# --- FMUs this project did not generate (assemblies/scenes/pi_controller.py), built once ---
@pytest.fixture(scope="session")
def casadi_pi():
    """A PI speed controller exported by CasADi's DaeBuilder.export_fmu (FMI 3 ME)."""
    from foreign_fmus import casadi_pi_fmu
    return casadi_pi_fmu()


@pytest.fixture(scope="session")
def pythonfmu_pi():
    """The same controller built by pythonfmu (FMI 2 CS, canGetAndSetFMUstate false)."""
    from foreign_fmus import pythonfmu_pi_fmu
    return pythonfmu_pi_fmu()


def runtime_driver(folder, driver, *runtime_files: str):
    """A test's C driver (tests/unit/DRIVER) compiled with gcc, warnings as errors, into an
    executable in `folder`, linked with the named sources of the FMU runtime
    (fmus/runtime): a unit test of the runtime's C code that needs no FMU."""
    import subprocess
    from pathlib import Path
    tests = Path(__file__).parent
    runtime = tests.parent / "fmus" / "runtime"
    exe = Path(folder) / Path(driver).stem
    subprocess.run(["gcc", "-std=c99", "-O2", "-Wall", "-Werror", f"-I{runtime}", "-o", str(exe),
                    str(tests / "unit" / driver), *(str(runtime / f) for f in runtime_files),
                    "-lm"], check=True)
    return exe
