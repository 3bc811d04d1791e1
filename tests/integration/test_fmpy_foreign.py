"""Foreign FMUs in the fmpy reference co-simulation master (engine "fmpy"), checked
against the compiled engine and against the closed loop computed here.

The loop of tests/integration/test_foreign_fmus.py: pythonfmu's PI speed controller (FMI
2.0 Co-Simulation, canGetAndSetFMUstate false; ``f = k (v_ref - v + I/Ti)``, ``I' = v_ref
- v``, defaults v_ref = 1 m/s, k = 2 N.s/m, Ti = 0.5 s) reads a mass's speed through our
``SpeedSensor`` and pushes it through our ``Force``; the mass (m = 1 kg, kinetic and static
friction 0.3 N) starts at rest and slides forward throughout. The references are built
here from those equations alone (no code shared with the FMUs or the masters).
"""
import numpy as np
import pytest
from scipy.linalg import expm

from assemblies import FMU, Assembly, AssemblyError
from assemblies.engine.cosim import cosimulate as engine_cosimulate
from assemblies.experiment import FixedStepFallback
from assemblies.masters.cosim import cosimulate as fmpy_cosimulate
from assemblies.scenes.speed_control import pi_speed_loop
from components import MassWithFriction

M, FRICTION, V_REF, K, TI = 1.0, 0.3, 1.0, 2.0, 0.5
FALLBACK = (r"adaptive co-simulation rolls steps back, but FMU instance 'ctrl' cannot get "
            r"and set its state \(canGetAndSetFMUstate is false\): ran fixed communication "
            r"steps of 0.02 s")


def pi_loop(controller) -> Assembly:
    return pi_speed_loop("pi_loop", FMU(controller),
                         MassWithFriction(m=M, g=1.0, mu_k=FRICTION, mu_s=FRICTION))


def euler(n_steps: int, h: float):
    """(v, f) at t = 0, h, ..., n h with the inputs held over each communication step
    (Jacobi, no extrapolation): the mass under a held force gains exactly h (f - F)/m,
    the controller integrates a held error exactly, so the loop is forward Euler on (v, I)."""
    v, integral = np.zeros(n_steps + 1), 0.0
    f = np.zeros(n_steps + 1)
    for n in range(n_steps + 1):
        f[n] = K * (V_REF - v[n] + integral / TI)
        if n < n_steps:
            v[n + 1] = v[n] + h * (f[n] - FRICTION) / M
            integral += h * (V_REF - v[n])
    return v, f


def exact_speed(t):
    """v of the continuous loop: x = (v, I), x' = A x + b, from x(0) = 0, by the matrix
    exponential of the augmented system (sliding forward throughout: friction constant)."""
    a = np.array([[-K / M, K / (TI * M), (K * V_REF - FRICTION) / M],
                  [-1.0, 0.0, V_REF],
                  [0.0, 0.0, 0.0]])
    return np.array([(expm(a * ti) @ [0.0, 0.0, 1.0])[0] for ti in t])


@pytest.mark.parametrize("scheme, extrapolation", [("jacobi", 0), ("gauss-seidel", 2)])
def test_fmpy_master_runs_a_foreign_fmi2_fmu_as_the_engine_does(pythonfmu_pi, scheme,
                                                                extrapolation):
    """engine "fmpy" with pythonfmu's FMI 2 CS controller: asking for adaptive steps falls
    back to fixed ones (the same warning and settings note as the engine), and every
    recorded column equals the engine's to round-off, asserted 1e-12 (measured 0 with
    Jacobi, 2.2e-16 with Gauss-Seidel and quadratic extrapolation): the two masters
    take the same steps in the same order on the same binaries; only the order of a
    few floating-point operations in the extrapolation may differ (Python vs C)."""
    h, stop = 0.02, 4.0
    runs = {}
    for name, run in (("fmpy", fmpy_cosimulate), ("c", engine_cosimulate)):
        with pytest.warns(FixedStepFallback, match=FALLBACK):
            runs[name] = run(pi_loop(pythonfmu_pi), stop, h, 1e-10, adaptive=True,
                             scheme=scheme, extrapolation=extrapolation)
        assert not runs[name].settings["adaptive"] and not runs[name].settings["event_sync"]
    fmpy, c = runs["fmpy"], runs["c"]
    assert fmpy.settings["fallback"] == c.settings["fallback"]
    assert fmpy.settings["steps"] == c.settings["steps"] == round(stop / h)
    assert set(fmpy.columns) == set(c.columns) and len(fmpy["time"]) == len(c["time"])
    for column in c.columns:
        assert np.abs(fmpy[column] - c[column]).max() <= 1e-12, column


def test_fmpy_master_with_a_foreign_fmu_is_forward_euler_on_the_loop(pythonfmu_pi):
    """Fixed steps (no fallback asked for, so no warning), Jacobi, inputs held: exactly
    forward Euler on (v, I), asserted to 1e-12 (round-off over 200-400 steps). Against the
    continuous loop the error is first order: below h and halving with h (ratio 1.9-2.1)."""
    errors = []
    stop = 4.0
    for h in (0.02, 0.01):
        res = fmpy_cosimulate(pi_loop(pythonfmu_pi), stop, h, 1e-10, extrapolation=0,
                              record=["block.v_abs", "ctrl.f"])
        assert res.settings["fallback"] is None
        n = len(res["time"]) - 1
        assert n == round(stop / h)
        v_euler, f_euler = euler(n, h)
        assert np.abs(res["block.v_abs"] - v_euler).max() <= 1e-12
        assert np.abs(res["ctrl.f"] - f_euler).max() <= 1e-12
        errors.append(np.abs(res["block.v_abs"] - exact_speed(res["time"])).max())
        assert errors[-1] < h
    assert 1.9 < errors[0] / errors[1] < 2.1


def test_fmpy_master_refuses_a_model_exchange_only_fmu_as_the_engine_does(casadi_pi):
    asm = Assembly("loop")
    asm.add("ctrl", FMU(casadi_pi))  # CasADi's export: Model Exchange only
    with pytest.raises(AssemblyError) as err:
        fmpy_cosimulate(asm, 1.0, 0.1)
    assert str(err.value) == ("assembly 'loop': mode 'cosim' steps Co-Simulation FMUs, but "
                              "instance 'ctrl' (PIController.fmu) is ModelExchange only; run "
                              "it with mode 'me'")


def test_an_fmi2_fmu_that_logs_after_the_run_does_not_reach_a_dead_logger(pythonfmu_pi, tmp_path):
    """fmpy's FMI 2 logging goes through one process-wide proxy to the Python logger
    registered last; the master's must outlive its instances, or the next FMU that logs
    calls freed memory (this crashed the interpreter). Here: a run, its instances
    collected, then another FMI 2 FMU made to log an error."""
    import gc

    from fmpy import extract, read_model_description
    from fmpy.fmi1 import FMICallException
    from fmpy.fmi2 import FMU2Slave

    from components import SpringBlock
    from fmus import build_fmu

    fmpy_cosimulate(pi_loop(pythonfmu_pi), 0.1, 0.05, 1e-10, extrapolation=0)
    gc.collect()
    path = str(build_fmu(SpringBlock(), fmi_version=2))
    md = read_model_description(path)
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=extract(path, str(tmp_path / "sb")),
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName="other")
    fmu.instantiate()
    with pytest.raises(FMICallException):
        fmu.doStep(0.0, 0.1)  # before initialisation: refused, with a logged message
    fmu.freeInstance()
