"""RODAS3's continuous extension (fmus/runtime/solver_implicit.c), compiled with gcc
into a small driver (rodas_dense.c) that takes one step of a given size: 3rd order on
smooth problems, and bounded on a stiff one however large h rho is."""
import shutil
import subprocess

import pytest
from conftest import runtime_driver

pytestmark = pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")


@pytest.fixture(scope="module")
def driver(tmp_path_factory):
    exe = runtime_driver(tmp_path_factory.mktemp("rodas"), "rodas_dense.c",
                         "solver_implicit.c", "dense_lu.c")

    def errors(*args):
        out = subprocess.run([str(exe), *map(str, args)], check=True, capture_output=True,
                             text=True).stdout.split()
        return [float(v) for v in out]
    return errors


@pytest.mark.parametrize("problem, h", [(0, 0.025), (1, 0.00625), (2, 0.0125)],
                         ids=["oscillator", "tanh", "exp-sin-t"])
def test_the_dense_output_is_third_order(driver, problem, h):
    """Local error O(h^4) inside the step: 16 per halving (a 2nd-order extension gives 8;
    from K1..K4 alone no 3rd-order one exists for this tableau)."""
    coarse, fine = driver(problem, h)[:3], driver(problem, h / 2)[:3]
    ratios = [c / f for c, f in zip(coarse, fine)]
    assert all(r > 11 for r in ratios), ratios


def test_the_dense_output_stays_bounded_on_a_stiff_component(driver):
    """x' = -rho (x - sin t) + cos t from 1e-10 off the slow manifold, h = 0.1: the
    error inside the step is the quadratic interpolation of sin t through the step
    (2e-5), whatever h rho. A Hermite cubic through the end slopes (rho times the end
    point's distance from the manifold) reached 0.15 at h rho = 1e10."""
    h = 0.1
    errs = {hr: driver(3, h, hr / h, 1e-10) for hr in (1e4, 1e6, 1e10)}
    for hr, e in errs.items():
        assert max(e[:3]) < 3e-5, (hr, e)
        assert max(e[:3]) < 1.5 * max(errs[1e4][:3]), (hr, e)
