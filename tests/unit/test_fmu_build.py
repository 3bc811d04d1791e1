"""FMUs are real: gcc-built, valid for fmpy, FMI symbols only, cached by content."""
import subprocess
import zipfile

import pytest
from fmpy import read_model_description
from fmpy.validation import validate_fmu

from components import COMPONENTS, SpringBlock, flatten
from fmus import build, build_fmu

VARIANTS = [(cls, profile.name, options) for cls in COMPONENTS.values() for profile in cls.profiles
            for options in ([{"friction": law} for law in ("coulomb", "smooth", "tanh")]
                            if cls is SpringBlock else [{}])]


@pytest.mark.parametrize("cls, profile, options", VARIANTS,
                         ids=[f"{c.__name__}-{p}-{'-'.join(o.values())}" for c, p, o in VARIANTS])
def test_every_fmu_validates_cleanly(cls, profile, options, tmp_path):
    component = cls(profile=profile, **options)
    path = build_fmu(component, tmp_path / "model.fmu")
    assert validate_fmu(str(path)) == []
    md = read_model_description(str(path))
    assert md.fmiVersion == "3.0" and md.modelExchange and md.coSimulation
    declared = {u.name for u in md.unitDefinitions}
    # a signal of no unit by design (a TimeTable feeds any signal input) declares none
    fm = flatten(component)
    unitless = {v.name for v in (*fm.parameters, *fm.inputs, *fm.outputs) if v.unit == ""}
    for v in md.modelVariables:
        assert v.description, v.name
        if v.type == "Float64" and not v.name.startswith("event_indicator"):
            assert v.unit in declared or (v.unit is None and v.name in unitless), v.name


def test_library_exports_only_fmi_symbols(tmp_path):
    path = build_fmu(SpringBlock(), tmp_path / "block.fmu")
    with zipfile.ZipFile(path) as zf:
        names = [n for n in zf.namelist() if n.endswith(".so")]
        assert len(names) == 1
        zf.extract(names[0], tmp_path)
    out = subprocess.run(["nm", "-D", "--defined-only", str(tmp_path / names[0])],
                         capture_output=True, text=True, check=True).stdout
    symbols = [line.split()[-1] for line in out.splitlines() if line.strip()]
    # FMI's functions and our documented extensions (the engine's thin path)
    assert symbols and all(s.startswith("fmi3") or s in ("mfEvaluateAt", "mfEvaluateOff")
                           for s in symbols), symbols


def test_dependencies_are_structural(tmp_path):
    md = read_model_description(str(build_fmu(SpringBlock(), tmp_path / "b.fmu")))
    by_vr = {v.valueReference: v.name for v in md.modelVariables}
    outputs = {by_vr[o.variable.valueReference]: {d.name for d in o.dependencies or []}
               for o in md.outputs if o.dependencies is not None}
    assert outputs["flange_a.f"] == {"x", "v", "flange_a.s", "flange_a.v"}
    assert outputs["x"] == {"x"}


def test_unchanged_component_costs_no_compile(monkeypatch, tmp_path):
    monkeypatch.setenv("MECHFMU_CACHE", str(tmp_path / "cache"))
    calls = []
    real = build._compile
    monkeypatch.setattr(build, "_compile", lambda *a: (calls.append(a), real(*a)))
    first = build_fmu(SpringBlock(mu_s=0.5))
    second = build_fmu(SpringBlock(mu_s=0.5))
    assert first == second and len(calls) == 1
    build_fmu(SpringBlock(mu_s=0.6))  # a different start value is a different FMU
    assert len(calls) == 2


def test_the_directional_jacobian_holds_its_structural_nonzeros_only():
    """mf_dd returns the nonzeros of d[xdot; y]/d[x; u] (the runtime scatters them by
    mf_dd_sparsity_out). In a joined chain of 8 blocks 848 of its 5304 entries can be
    nonzero; written entry by entry, the dense matrix of 16 blocks was two thirds of the
    model's C and of gcc's time (25.6 s, now 8.5 s)."""
    import casadi as ca
    from assemblies.engine.prepare import defaults_assembly
    from assemblies.masters.monolithic import composite
    from benchmarks.chain import bench_chain
    from components.dae import flatten
    from fmus.codegen import directional_jacobian
    flat = flatten(composite(defaults_assembly(bench_chain(8))))
    dd = directional_jacobian(flat)
    pattern = dd.sparsity_out(0)
    dense = pattern.size1() * pattern.size2()
    assert pattern.nnz() < dense / 4, (pattern.nnz(), dense)
    symbolic = ca.jacobian(ca.vertcat(flat.xdot, flat.y, flat.z), ca.vertcat(flat.x, flat.u))
    assert pattern.nnz() == symbolic.nnz()


def test_inputs_read_are_those_an_equation_uses_and_never_a_rate():
    # The runtime extrapolates, at every right-hand side, only the inputs the model
    # reads (model.h input_read): a friction block's forces and its support's motion
    # are read, the rate inputs that only carry them along (components/dae.py rate_of)
    # are not, and nothing else is left out.
    from components import MassWithFriction
    from fmus.codegen import inputs_read

    model = flatten(MassWithFriction(m=1.0, g=1.0, mu_k=0.3, mu_s=0.4))
    read = dict(zip((v.name for v in model.inputs), inputs_read(model)))
    rates = {n for n in read if "_rate" in n}
    assert rates and not any(read[n] for n in rates)
    assert all(read[n] for n in read if n not in rates), read
