"""DOP853 (assemblies/engine/c/dop853.c), compiled with gcc into a small driver
(dop853_step.c) on problems with exact solutions: the step is 8th order and its
continuous extension 7th, and a whole run meets its tolerance with fewer evaluations
than DOPRI5 at tight tolerances, which is what the engine takes it for."""
import shutil
import subprocess
from pathlib import Path

import pytest

from assemblies.engine.build import C_DIR
from fmus.build import RUNTIME_DIR

pytestmark = pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")
PROBLEMS = {"oscillator": 0, "tanh": 1, "exp-sin-t": 2}


@pytest.fixture(scope="module")
def driver(tmp_path_factory):
    exe = tmp_path_factory.mktemp("dop853") / "dop853_step"
    subprocess.run(["gcc", "-std=c99", "-O2", "-Wall", "-Werror", f"-I{RUNTIME_DIR}",
                    f"-I{C_DIR}", "-o", str(exe), str(Path(__file__).parent / "dop853_step.c"),
                    str(C_DIR / "dop853.c"), str(RUNTIME_DIR / "solver.c"), "-lm"], check=True)

    def numbers(*args):
        out = subprocess.run([str(exe), *map(str, args)], check=True, capture_output=True,
                             text=True).stdout.split()
        return [float(v) for v in out]
    return numbers


@pytest.mark.parametrize("problem, h", [("oscillator", 0.5), ("tanh", 0.5), ("exp-sin-t", 0.25)])
def test_one_step_is_eighth_order_and_its_extension_seventh(driver, problem, h):
    """Local errors O(h^9) at the step's end (512 per halving) and O(h^8) inside it
    (256): a 7th-order step would give 256 and 128, a wrong coefficient of the
    extension 32 or less."""
    coarse, fine = driver("step", PROBLEMS[problem], h), driver("step", PROBLEMS[problem], h / 2)
    inside = [c / f for c, f in zip(coarse[:3], fine[:3])]
    assert coarse[3] / fine[3] > 300, (coarse, fine)
    assert all(r > 170 for r in inside), inside


@pytest.mark.parametrize("problem", ["oscillator", "tanh"])
def test_a_run_meets_its_tolerance_with_fewer_evaluations_than_dopri5(driver, problem):
    """Ten time units at tolerance 1e-9 and 1e-12: the global error at 100 points of the
    continuous extension within 10x the tolerance (the local control's usual relation on
    these non-expanding problems), and fewer evaluations than DOPRI5 at the same
    tolerance: 2.6x and 4.7x fewer on the oscillator, 1.3x and 2.4x on tanh when this
    was written (every step's extension made, as for rows inside every step)."""
    for tol in (1e-9, 1e-12):
        err, rhs, err5, rhs5 = driver("run", PROBLEMS[problem], tol)
        assert err < 10 * tol, (tol, err)
        assert rhs < rhs5, (tol, rhs, rhs5)
