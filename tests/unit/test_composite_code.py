"""The composite FMU's functions as maps over member kinds (assemblies/masters/composite_code)
compute what the flattened joined model computes, and their C does not grow with the
assembly."""
import re

import numpy as np
import pytest

from assemblies.masters import composite_code
from assemblies.masters.composite_code import member_functions, worth_mapping
from assemblies.masters.monolithic import composite
from assemblies.scenes import SCENES
from benchmarks.chain import bench_chain
from components.dae import flatten
from components.lazy import lazy
from fmus.codegen import computed_outputs, directional_jacobian, generate_c

ca = lazy("casadi")

# every joined scene (gains of -1 on reaction forces, open inputs, feedthrough through
# springs to accelerations) and the benchmark's chain, whose last flange is open
JOINED = ["two_block_belt", "moving_table", "conveyor", "axle_motor", "stick_slip_damped",
          "distinguished_limit", "resonance_below", "beam_tip_force"]


def _reference(model):
    """The flattened model's own functions (join's substitution into one expression)."""
    ref = model.functions()
    ref["out"] = ca.Function("out", model.args, [ca.densify(computed_outputs(model))])
    ref["dd"] = directional_jacobian(model)
    return ref


def _dense(value):
    values = value if isinstance(value, (list, tuple)) else [value]
    return [np.asarray(ca.densify(v)) for v in values]


@pytest.mark.parametrize("name", JOINED + ["chain"])
def test_member_maps_compute_what_the_flattened_model_computes(name):
    asm = bench_chain(5) if name == "chain" else SCENES[name].build()
    comp = composite(asm)
    model = flatten(comp)
    ours, ref = member_functions(comp.joined, model), _reference(model)
    assert sorted(ours) == ["dd", "jac", "jump", "ode", "out", "zc"]
    assert ours["dd"].sparsity_out(0) == ref["dd"].sparsity_out(0)
    rng = np.random.default_rng(7)
    for _ in range(3):
        point = [rng.uniform(0, 2), rng.normal(size=model.x.numel()),
                 rng.integers(-1, 2, size=model.q.numel()).astype(float),
                 rng.normal(size=model.u.numel()), rng.uniform(0.2, 2.0, size=model.p.numel())]
        for key, fn in ours.items():
            for got, want in zip(_dense(fn(*point)), _dense(ref[key](*point))):
                np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12, equal_nan=True,
                                           err_msg=f"{name}: {key}")


def test_the_generated_code_does_not_grow_with_the_chain(monkeypatch):
    """The same C functions for 4 and 16 blocks, and nearly the same code: what grows is
    data (index tables, the variable table) and comments, not what gcc optimises. The
    flattened expression grew by about 3,300 lines of code per block."""
    monkeypatch.setattr(composite_code, "FLAT_LIMIT", 0)  # maps at every size
    def code(n):
        text = generate_c(flatten(composite(bench_chain(n))), "chain", "token")
        functions = text.count("static int casadi_f")
        text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
        text = re.sub(r"static const [^;]*;", "", text, flags=re.S)
        return functions, len([line for line in text.splitlines() if line.strip()])
    (f4, lines4), (f16, lines16) = code(4), code(16)
    assert f4 == f16
    assert (lines16 - lines4) / 12 < 30  # one variable-table row per variable, ~20 a block


def test_small_assemblies_keep_the_flattened_expression():
    """Every scene compiles as one expression (faster C, a build of seconds) but
    coupled_clutches, whose solved loop is large; a chain of 32 blocks (7,194
    instructions in the shared graph, 30 s of gcc flattened) is mapped. The join's
    shared graph shrank these counts about fivefold without shrinking gcc's time, so
    the decisions stay where they were: a chain's flat/mapped split lies between 18 and
    19 blocks as before."""
    assert not worth_mapping(flatten(composite(SCENES["distinguished_limit_n4"].build())))
    assert not worth_mapping(flatten(composite(SCENES["translational_friction"].build())))
    assert not worth_mapping(flatten(composite(bench_chain(16))))
    assert worth_mapping(flatten(composite(bench_chain(32))))
    assert not worth_mapping(flatten(composite(bench_chain(18))))
    assert worth_mapping(flatten(composite(bench_chain(19))))


def test_the_same_chain_writes_the_same_c_in_every_process():
    """The mapped members come in the assembly's order, not in the order of a set of
    names (string hashes: a new order in each process, so each build wrote other index
    tables for the same assembly, scattered where the members' slots run in strides)."""
    import hashlib
    import os
    import subprocess
    import sys
    script = ("import hashlib; from assemblies.masters import composite_code as cc; "
              "cc.FLAT_LIMIT = 0; from assemblies.masters.monolithic import composite; "
              "from benchmarks.chain import bench_chain; from components.dae import flatten; "
              "from fmus.codegen import generate_c; "
              "print(hashlib.sha256(generate_c(flatten(composite(bench_chain(6))), 'chain', "
              "'token').encode()).hexdigest())")
    digests = {subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                              check=True, env={**os.environ, "PYTHONHASHSEED": seed}
                              ).stdout.strip() for seed in ("1", "2", "3")}
    assert len(digests) == 1, digests
    assert hashlib.sha256(b"").hexdigest() not in digests
