"""The banded LU of the implicit solver (fmus/runtime/dense_lu.c), compiled with gcc into
a small driver (band_lu.c): on random banded systems, with row swaps, it solves what the
dense LU solves, and A x = b holds."""
import shutil
import subprocess

import pytest
from conftest import runtime_driver

pytestmark = pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")


@pytest.fixture(scope="module")
def driver(tmp_path_factory):
    exe = runtime_driver(tmp_path_factory.mktemp("band"), "band_lu.c", "dense_lu.c")

    def run(n, kl, ku):
        out = subprocess.run([str(exe), str(n), str(kl), str(ku)], check=True,
                             capture_output=True, text=True).stdout.split()
        return [float(v) for v in out]
    return run


@pytest.mark.parametrize("n, kl, ku", [(40, 3, 5), (37, 4, 5), (60, 1, 1), (25, 0, 3),
                                       (10, 9, 9)])
def test_banded_lu_solves_what_the_dense_one_solves(driver, n, kl, ku):
    diff, residual = driver(n, kl, ku)
    assert diff < 1e-12
    assert residual < 1e-12
