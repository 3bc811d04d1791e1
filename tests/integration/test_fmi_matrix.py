"""{FMI 2.0, FMI 3.0} x {Model Exchange, Co-Simulation}: the same FMU physics in every cell.

Restricted, for now, to the spring-block with dry friction, whose exact solutions are
known: seed 9.4 (friction damping: half-cycles about +-mu, then stuck) through
fmpy.simulate_fmu, and seed 9.2 (stick-slip driven at v t) through a hand-written
Co-Simulation loop with communication steps up to the whole run.
"""
import math

import numpy as np
import pytest
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave
from fmpy.validation import validate_fmu
from scipy.optimize import brentq

from components import SpringBlock
from conftest import SEED_94, SEED_94_SPEED, coulomb_drag_reference, exact_friction_damping
from fmus import build_fmu

VERSIONS = (2, 3)


# exact Coulomb: CS locates events inside doStep to the solver tolerance; ME goes
# through fmpy's CVode and its event handling. tanh (eps = 1e-3) is a smooth law,
# close to Coulomb but not it: after sticking it creeps, so 1e-2 is its own accuracy.
CELLS = [(version, fmi_type, law, atol)
         for version in VERSIONS
         for fmi_type, law, atol in [("CoSimulation", "coulomb", 1e-8),
                                     ("ModelExchange", "coulomb", 1e-6),
                                     ("CoSimulation", "tanh", 1e-2),
                                     ("ModelExchange", "tanh", 1e-2)]]


@pytest.mark.parametrize("version, fmi_type, law, atol", CELLS,
                         ids=[f"fmi{v}-{t}-{law}" for v, t, law, _ in CELLS])
def test_friction_damping_in_every_cell(version, fmi_type, law, atol):
    block = SpringBlock(m=1, k=1, g=1, mu_k=0.6, mu_s=0.6, x=6.55, friction=law)
    path = build_fmu(block, fmi_version=version)
    assert validate_fmu(str(path)) == []
    res = simulate_fmu(str(path), fmi_type=fmi_type, stop_time=18.0, output_interval=0.01,
                       relative_tolerance=1e-10, start_values={**block.values, **block.starts},
                       output=["x", "v"])
    assert res["time"][-1] == pytest.approx(18.0)
    assert np.abs(res["x"] - exact_friction_damping(res["time"])).max() < atol


def _stick_slip_exact(t):
    """x, v of seed 9.2 (m = k = g = 1, mu_k = 0.3, mu_s = 0.4, end driven at 0.05 t) for a t
    in the second sliding phase, derived from the sliding law: with xi = x - vt + mu_k g,
    xi'' = -xi. Every slip starts from xi = (mu_k - mu_s) g, xi' = -v, so each slip lasts
    the same tau*, and sticking ends when the spring force k (vt - x) reaches mu_s g."""
    v, mu_k, mu_s = SEED_94_SPEED, SEED_94["mu_k"], SEED_94["mu_s"]
    xi0, dxi0 = mu_k - mu_s, -v

    def slide(tau):  # x - v t0 and x' along a slip that started at t0
        return (-mu_k + xi0 * math.cos(tau) + dxi0 * math.sin(tau) + v * tau,
                v - xi0 * math.sin(tau) + dxi0 * math.cos(tau))

    # x' = v (1 - cos tau) + (mu_s - mu_k) g sin tau first returns to 0 in (pi, 2 pi)
    tau_stop = brentq(lambda tau: slide(tau)[1], math.pi, 2 * math.pi - 1e-3, xtol=1e-15)
    t1 = mu_s / v
    t2 = t1 + tau_stop
    x2 = v * t1 + slide(tau_stop)[0]
    t3 = (mu_s + x2) / v
    assert t3 < t < t3 + tau_stop
    dx, xdot = slide(t - t3)
    return t2, x2, v * t3 + dx, xdot


def _drive(slave_kind, version, step, stop=20.0):
    path = build_fmu(SpringBlock(**SEED_94), fmi_version=version)
    md = read_model_description(str(path))
    fmu = slave_kind(guid=md.guid, unzipDirectory=extract(str(path)),
                     modelIdentifier=md.coSimulation.modelIdentifier, instanceName="block")
    vrs = {v.name: v.valueReference for v in md.modelVariables}
    drive = [vrs["flange_a.s"], vrs["flange_a.v"]]
    fmu.instantiate()
    if version == 2:
        fmu.setupExperiment(tolerance=1e-10, startTime=0.0)
        fmu.enterInitializationMode()
        setter, getter = fmu.setReal, fmu.getReal
    else:
        fmu.enterInitializationMode(tolerance=1e-10, startTime=0.0)
        setter, getter = fmu.setFloat64, fmu.getFloat64
    fmu.exitInitializationMode()
    n = round(stop / step)
    for i in range(n):
        t = i * step
        setter(drive, [SEED_94_SPEED * t, SEED_94_SPEED])
        fmu.doStep(t, step)
    x, v = getter([vrs["x"], vrs["v"]])
    fmu.terminate()
    fmu.freeInstance()
    return x, v


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("step", [0.1, 1.0, 20.0])
def test_stick_slip_reaches_the_analytic_state_at_20(version, step):
    t2, x2, x20, v20 = _stick_slip_exact(20.0)
    # the seed's printed numbers, and the library-independent reference of conftest
    assert abs(t2 - 12.0688878715914) < 1e-12 and abs(x2 - 0.4034443936) < 1e-10
    _, x_of_t = coulomb_drag_reference(**SEED_94, v=SEED_94_SPEED, t_end=20.0)
    assert abs(x_of_t(np.array([20.0]))[0] - x20) < 1e-12
    x, v = _drive(FMU2Slave if version == 2 else FMU3Slave, version, step)
    assert abs(x - x20) < 1e-6 and abs(v - v20) < 1e-6, (x - x20, v - v20)
