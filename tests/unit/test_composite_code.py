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


def _compiled_model(text, tmp_path):
    """The generated model.c as a shared library whose mf_* functions ctypes can call
    (the FMU's flags but for hidden visibility, plus -Werror)."""
    import ctypes
    import subprocess
    from pathlib import Path
    source, library = tmp_path / "model.c", tmp_path / "model.so"
    source.write_text(text)
    runtime = Path(__file__).resolve().parents[2] / "fmus" / "runtime"
    subprocess.run(["gcc", "-std=c99", "-O2", "-fPIC", "-shared", "-Wall", "-Werror",
                    f"-I{runtime}", "-o", str(library), str(source), "-lm"], check=True)
    return ctypes.CDLL(str(library))


def _c_call(lib, name, point, n_res):
    """mf_<name> at `point` = [t, x, q, u, p], with the work sizes it asks for."""
    import ctypes
    dbl, i64 = ctypes.c_double, ctypes.c_longlong
    sizes = [i64() for _ in range(4)]
    assert getattr(lib, f"mf_{name}_work")(*[ctypes.byref(s) for s in sizes]) == 0
    args = [np.ascontiguousarray(np.atleast_1d(np.asarray(a, dtype=float))) for a in point]
    arg = (ctypes.POINTER(dbl) * max(5, sizes[0].value))(
        *[a.ctypes.data_as(ctypes.POINTER(dbl)) for a in args])
    res_arrays = [np.full(n, np.nan) for n in n_res]
    res = (ctypes.POINTER(dbl) * max(len(n_res), sizes[1].value))(
        *[r.ctypes.data_as(ctypes.POINTER(dbl)) for r in res_arrays])
    iw = (i64 * max(1, sizes[2].value))()
    w = (dbl * max(1, sizes[3].value))()
    assert getattr(lib, f"mf_{name}")(arg, res, iw, w, 0) == 0
    return res_arrays


@pytest.mark.parametrize("name", ["two_block_belt", "conveyor", "beam_tip_force", "chain"])
def test_member_loops_in_c_compute_what_the_flattened_model_computes(name, monkeypatch,
                                                                     tmp_path):
    """The C that calls each kind's function member by member in place (MemberC: ode,
    out, zc, jump) gives the flattened expression's values to rounding, compiled with
    the FMU's flags and -Werror, on scenes with gains of -1, open inputs and
    feedthrough, and on the benchmark's chain."""
    monkeypatch.setattr(composite_code, "FLAT_LIMIT", 0)  # maps at every size
    asm = bench_chain(5) if name == "chain" else SCENES[name].build()
    comp = composite(asm)
    model = flatten(comp)
    text = generate_c(model, "chain", "token")
    assert "MemberC" in text
    lib, ref = _compiled_model(text, tmp_path), _reference(model)
    rng = np.random.default_rng(11)
    n_out = {"ode": [model.x.numel()], "zc": [model.z.numel()],
             "out": [model.y.numel() + model.z.numel()],
             "jump": [model.x.numel(), model.q.numel()]}
    for _ in range(3):
        point = [rng.uniform(0, 2), rng.normal(size=model.x.numel()),
                 rng.integers(-1, 2, size=model.q.numel()).astype(float),
                 rng.normal(size=model.u.numel()), rng.uniform(0.2, 2.0, size=model.p.numel())]
        for key, sizes in n_out.items():
            for got, want in zip(_c_call(lib, key, point, sizes), _dense(ref[key](*point))):
                np.testing.assert_allclose(got, want.ravel(), rtol=1e-12, atol=1e-12,
                                           equal_nan=True, err_msg=f"{name}: {key}")


def test_the_chain_derivatives_take_one_call_per_kind_and_level(monkeypatch):
    """What a mapped composite's right-hand side costs is its calls (each sets up its
    arguments and gathers its inputs for a few flops): the chain's derivatives take one
    per member kind and level (the sources' travel with their outputs, the blocks'
    positions and velocities, the links' forces, the blocks' accelerations with their
    derivatives), not one per group of outputs that read the same inputs and one more
    per derivative function (7 calls before)."""
    monkeypatch.setattr(composite_code, "FLAT_LIMIT", 0)
    comp = composite(bench_chain(5))
    code = member_functions(comp.joined, flatten(comp), c_code=True)["c"]
    needed = code._needed([r for rows in code.results["ode"] for r in rows])
    assert [code.calls[i].k for i in needed] == [6, 5, 5, 5]  # wall and belts, blocks, links
    assert [code.calls[i].fn.name().endswith("_ode") for i in needed] == [True, False, False, True]
