"""The two embedded Co-Simulation solvers, selected by the runtime's `solver` parameter,
and the automatic choice between them (the default).

DOPRI5 (0, explicit) and RODAS3 (1, Rosenbrock with CasADi's Jacobian) must give the
same answer to the tolerance where both work — the exact Coulomb cases of seed 9.2
and 9.4, events included — and RODAS3 must be far cheaper where the model is stiff:
the tanh friction law (seed Eq. 9.7) with eps = 1e-6, whose slope at v = 0 makes
d a / d v about -1e6 while the block creeps. The automatic choice (2) must find that
stiffness by itself (switching to RODAS3 and back as the block sticks and slips) and
cost about what RODAS3 does, and must be DOPRI5 itself where nothing is stiff.
"""
import re

import casadi as ca
import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException

from components import SpringBlock
from components.dae import flatten
from conftest import SEED_94, SEED_94_SPEED, coulomb_drag_reference, exact_friction_damping
from cs_slave import initialize, open_slave
from fmus import build_fmu

VERSIONS = (2, 3)
DOPRI5, RODAS3, AUTO = 0, 1, 2
WORK = re.compile(r"(\d+) steps, (\d+) rejected, (\d+) derivative evaluations, "
                  r"(\d+) Jacobians, (\d+) events")
STEEP = dict(m=1, k=1, g=1, mu_k=0.3, mu_s=0.4, friction="tanh", eps=1e-6)


def _open(component, version, log=None):
    fmu, vr = open_slave(component, version, log)
    if version == 3:
        fmu.setDebugLogging(True, ["logSolver"])  # the work counts (WORK) come from these
    return fmu, vr


def _run(component, version, solver, tol, stop, step, inputs):
    """(final x, final v, work) of a run driven by constant inputs; work (FMI 3 only) is
    summed from the logSolver line that every doStep writes."""
    work = np.zeros(5, dtype=int)

    def log(message):
        m = WORK.search(message.decode())
        if m:
            work[:] += [int(g) for g in m.groups()]

    fmu, vr = _open(component, version, log)
    set_int = fmu.setInteger if version == 2 else fmu.setInt32
    set_float, get_float = (fmu.setReal, fmu.getReal) if version == 2 else (fmu.setFloat64, fmu.getFloat64)
    set_int([vr["solver"]], [solver])
    starts = {**component.values, **component.starts, **inputs}
    names = [k for k in starts if k in vr]
    set_float([vr[k] for k in names], [float(starts[k]) for k in names])
    initialize(fmu, version, tol)
    for i in range(round(stop / step)):
        fmu.doStep(i * step, step)
    x, v = get_float([vr["x"], vr["v"]])
    fmu.terminate()
    fmu.freeInstance()
    return x, v, dict(zip(("steps", "rejected", "rhs", "jac", "events"), work.tolist()))


def _cvodes_reference(component, speed, stop):
    """x, v at `stop` of the flat model driven at s = speed t, by SUNDIALS CVODES (BDF)."""
    fm = flatten(component)
    x0, q0, _, p0 = fm.start_vectors()
    drive = {"flange_a.s": speed * fm.t, "flange_a.v": speed, "flange_a.a": 0}
    # (the rate inputs only extrapolate a within a co-simulation step: none here)
    u = ca.vertcat(*[drive.get(v.name, 0) if v.rate_of is not None else drive[v.name]
                     for v in fm.inputs])
    ode = ca.substitute(fm.xdot, ca.vertcat(fm.u, fm.q, fm.p), ca.vertcat(u, ca.DM(q0), ca.DM(p0)))
    F = ca.integrator("F", "cvodes", {"x": fm.x, "t": fm.t, "ode": ode}, 0.0, [stop],
                      {"abstol": 1e-13, "reltol": 1e-13, "max_num_steps": 10**7})
    return np.array(F(x0=x0)["xf"]).ravel()


@pytest.mark.parametrize("version", VERSIONS)
def test_steep_friction_is_far_cheaper_implicitly_and_both_are_right(version):
    block = SpringBlock(**STEEP)
    ref = _cvodes_reference(block, SEED_94_SPEED, 20.0)
    runs = {s: _run(block, version, s, 1e-8, 20.0, 0.1, {"flange_a.v": SEED_94_SPEED})
            for s in (DOPRI5, RODAS3, AUTO)}
    for solver, (x, v, work) in runs.items():
        assert abs(x - ref[0]) < 1e-6 and abs(v - ref[1]) < 1e-6, (solver, x - ref[0], v - ref[1])
    if version == 2:
        return  # same runtime; the work is counted through FMI 3's logger
    explicit, implicit = runs[DOPRI5][2], runs[RODAS3][2]
    # measured: DOPRI5 about 7e6 evaluations and 1.1e6 steps (stability-bound, chattering
    # about v = 0), RODAS3 about 3.6e3 evaluations and 900 steps
    assert implicit["rhs"] * 100 < explicit["rhs"], (explicit, implicit)
    assert implicit["steps"] * 100 < explicit["steps"], (explicit, implicit)
    assert implicit["jac"] == implicit["steps"]  # one per step; rejections reuse it
    assert explicit["jac"] == 0
    # the automatic choice finds the stiffness itself: no dearer than RODAS3 alone
    # (measured: 1.5e3 evaluations against RODAS3's 3.8e3, DOPRI5 taking the slips),
    # with the same mode changes (an explicit step at its stability edge near the steep
    # part rings and would add spurious ones)
    automatic = runs[AUTO][2]
    assert automatic["rhs"] < 2 * implicit["rhs"], (automatic, implicit)
    assert 0 < automatic["jac"] < automatic["steps"], automatic  # it went both ways
    assert automatic["events"] == implicit["events"], (automatic, implicit)


@pytest.mark.parametrize("version", VERSIONS)
def test_automatic_choice_is_dopri5_itself_where_nothing_is_stiff(version):
    """Seed 9.4 stick-slip (exact Coulomb, events): DOPRI5's steps are accuracy-bound, its
    stiffness test never fires, and the automatic run repeats DOPRI5's bit for bit. The
    work it reports differs only by the periodic stiffness check's Jacobians (one per 200
    explicit steps, counted since issue 27), none of them a RODAS3 step's."""
    block = SpringBlock(**SEED_94)
    explicit, automatic = (_run(block, version, s, 1e-8, 20.0, 0.1, {"flange_a.v": SEED_94_SPEED})
                           for s in (DOPRI5, AUTO))
    assert explicit[:2] == automatic[:2]
    checks = automatic[2].pop("jac")
    explicit[2].pop("jac")
    assert explicit[2] == automatic[2]
    if version == 3:
        assert checks <= automatic[2]["steps"] // 200 and automatic[2]["events"] >= 2, automatic


@pytest.mark.parametrize("version", VERSIONS)
def test_both_solvers_follow_friction_damping_with_its_events(version):
    block = SpringBlock(m=1, k=1, g=1, mu_k=0.6, mu_s=0.6, x=6.55)
    path = build_fmu(block, fmi_version=version)
    results = {}
    for solver in (DOPRI5, RODAS3):
        res = simulate_fmu(str(path), fmi_type="CoSimulation", stop_time=18.0, output_interval=0.01,
                           relative_tolerance=1e-10,
                           start_values={**block.values, **block.starts, "solver": solver},
                           output=["x", "v", "mode"])
        assert np.abs(res["x"] - exact_friction_damping(res["time"])).max() < 1e-8, solver
        results[solver] = res
    assert np.array_equal(results[DOPRI5]["mode"], results[RODAS3]["mode"])
    assert np.abs(results[DOPRI5]["x"] - results[RODAS3]["x"]).max() < 1e-8


@pytest.mark.parametrize("version", VERSIONS)
def test_both_solvers_follow_stick_slip_with_its_events(version):
    block = SpringBlock(**SEED_94)
    _, x_exact = coulomb_drag_reference(**SEED_94, v=SEED_94_SPEED, t_end=40.0)
    path = build_fmu(block, fmi_version=version)
    for solver in (DOPRI5, RODAS3):
        res = simulate_fmu(str(path), fmi_type="CoSimulation", stop_time=40.0, output_interval=0.1,
                           relative_tolerance=1e-10,
                           start_values={**block.values, **block.starts, "solver": solver,
                                         "flange_a.v": SEED_94_SPEED},
                           output=["x"])
        assert np.abs(res["x"] - x_exact(res["time"])).max() < 1e-7, solver


@pytest.mark.parametrize("version", VERSIONS)
def test_solver_is_a_fixed_parameter_with_three_values(version):
    block = SpringBlock()
    md = read_model_description(str(build_fmu(block, fmi_version=version)))
    solver = md.modelVariables[-1]
    assert (solver.name, solver.causality, solver.variability, solver.start) == \
        ("solver", "parameter", "fixed", "2")
    assert solver.valueReference == max(v.valueReference for v in md.modelVariables)
    messages = []
    fmu, vr = _open(block, version, messages.append)
    set_int = fmu.setInteger if version == 2 else fmu.setInt32
    with pytest.raises(FMICallException):
        set_int([vr["solver"]], [3])
    if version == 3:
        assert (b"must be 0 (DOPRI5, explicit), 1 (RODAS3, implicit) or 2 (automatic: "
                b"switches between them on stiffness)") in messages[-1]
    set_int([vr["solver"]], [1])
    if version == 2:
        fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    with pytest.raises(FMICallException):  # fixed: not after initialisation
        set_int([vr["solver"]], [0])
    get_int = fmu.getInteger if version == 2 else fmu.getInt32
    assert get_int([vr["solver"]]) == [1]
    fmu.doStep(0.0, 1.0)
    if version == 3:
        assert b"RODAS3" in messages[-1]
    fmu.terminate()
    fmu.freeInstance()


def test_the_solver_setting_reaches_a_scene_and_its_settings():
    """--param block.solver=...: a name or a number, checked, set on the FMU, reported."""
    from assemblies.run import run_scene_full
    from components import ComponentError
    for given, reported in ((None, "auto"), ("implicit", "RODAS3"), (0, "DOPRI5")):
        params = {} if given is None else {"block.solver": given}
        run = run_scene_full("stick_slip", params=params)
        assert run.result.settings["solver"]["block"] == reported
        assert all(f.passed for f in run.figures)
    with pytest.raises(ComponentError, match=r"solver = 'fast' is not allowed; solver must "
                                             r"be 0 \(DOPRI5, explicit\), 1 \(RODAS3"):
        run_scene_full("stick_slip", params={"block.solver": "fast"})
