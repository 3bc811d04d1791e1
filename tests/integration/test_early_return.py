"""FMI 3 early return: a master that allows it sees each event as a communication point."""
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi3 import FMU3Slave

from components import SpringBlock
from conftest import SEED_94, SEED_94_SPEED, coulomb_drag_reference
from fmus import build_fmu


@pytest.mark.parametrize("early_return_allowed", [True, False])
def test_do_step_returns_at_each_stick_and_slip(early_return_allowed):
    path = build_fmu(SpringBlock(**SEED_94))
    md = read_model_description(str(path))
    assert md.coSimulation.mightReturnEarlyFromDoStep
    vr = {v.name: v.valueReference for v in md.modelVariables}
    fmu = FMU3Slave(guid=md.guid, unzipDirectory=extract(str(path)),
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName="block")
    fmu.instantiate(earlyReturnAllowed=early_return_allowed)
    fmu.enterInitializationMode(tolerance=1e-10)
    fmu.exitInitializationMode()
    t, stop, returns = 0.0, 20.0, []
    while t < stop:
        # the driver's motion is polynomial: set at t, the FMU extrapolates it exactly
        fmu.setFloat64([vr["flange_a.s"], vr["flange_a.v"]], [SEED_94_SPEED * t, SEED_94_SPEED])
        _, _, early, reached = fmu.doStep(t, stop - t)  # one step for the whole run
        if early:
            returns.append(reached)
        t = reached
    fmu.terminate()
    fmu.freeInstance()
    phases, _ = coulomb_drag_reference(**SEED_94, v=SEED_94_SPEED, t_end=stop)
    switches = sorted({b for _, a, b in phases if 0 < b < stop} | {a for _, a, _ in phases if 0 < a < stop})
    if early_return_allowed:
        assert returns == pytest.approx(switches, abs=1e-8)  # t1 = 8, t2, t3 ... of seed 9.2
    else:
        assert returns == []
