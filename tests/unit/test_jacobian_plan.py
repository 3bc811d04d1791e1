"""The engine's Jacobian plan (assemblies/engine/c/jacobian.c) on synthetic specs, compiled
with gcc into a small driver (jacobian_plan.c) that loads no FMU: the pattern it finds
and the work it takes to find it, counted (the dependencies it looks at), never timed."""
import shutil
import subprocess
from pathlib import Path

import pytest

pytestmark = pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")

ROOT = Path(__file__).parents[2]


@pytest.fixture(scope="module")
def plan(tmp_path_factory):
    engine = ROOT / "assemblies" / "engine" / "c"
    exe = tmp_path_factory.mktemp("jacobian_plan") / "jacobian_plan"
    subprocess.run(["gcc", "-std=c99", "-O2", "-Wall", "-Werror", f"-I{engine}", "-o", str(exe),
                    str(ROOT / "tests" / "unit" / "jacobian_plan.c"), str(engine / "jacobian.c")],
                   check=True)

    def run(kind, n):
        out = subprocess.run([str(exe), kind, str(n)], check=True, capture_output=True,
                             text=True).stdout.split()
        return [int(v) for v in out]
    return run


@pytest.mark.parametrize("n", [50, 400])
def test_a_dense_instance_costs_its_entries_not_their_cube(plan, n):
    """One instance whose every derivative may depend on every state (a composite FMU of
    a whole chain lists nothing finer): the pattern is full, one column per group, and
    finding it looks at each (column, derivative) pair once, n^2 in all. It looked at
    every unknown against every known marked so far per column (about n^3 / 4: half a
    256-block chain's monolithic run, 769 states, went into this plan)."""
    groups, kl, ku, checks = plan("dense", n)
    assert (groups, kl, ku) == (n, n - 1, n - 1)
    assert checks <= n * n


@pytest.mark.parametrize("n", [10, 1000])
def test_a_chain_costs_linearly_and_is_banded(plan, n):
    """n instances of 2 states, each one's derivatives reading the one before through a
    listed input: state j of instance i reaches the derivatives of i and i + 1, so the
    pattern is a band 3 below and 1 above the diagonal, a few groups cover it whatever
    n is, and the plan's work is a few dependencies per column."""
    groups, kl, ku, checks = plan("chain", n)
    assert (kl, ku) == (3, 1)
    assert groups <= 4
    assert checks <= 8 * (2 * n)
