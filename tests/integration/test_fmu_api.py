"""The FMU answers misuse with Error and a message, never a crash (FMI 3 low-level API)."""
import math

import pytest
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi3 import FMU3Slave

from components import SpringBlock
from fmus import build_fmu


@pytest.fixture
def slave():
    path = build_fmu(SpringBlock())
    md = read_model_description(str(path))
    fmu = FMU3Slave(guid=md.guid, unzipDirectory=extract(str(path)),
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName="blk")
    messages = []
    fmu.instantiate(logMessage=lambda env, status, cat, msg: messages.append(msg.decode()))
    vrs = {v.name: v.valueReference for v in md.modelVariables}
    yield fmu, vrs, messages
    fmu.freeInstance()


def _fails(messages, call, *words):
    with pytest.raises(FMICallException):
        call()
    assert messages, "an Error must be explained through the logger"
    for word in words:
        assert word in messages[-1], messages[-1]


def test_wrong_order_and_unknown_references(slave):
    fmu, vrs, messages = slave
    _fails(messages, lambda: fmu.doStep(0.0, 0.1), "fmi3DoStep")
    _fails(messages, lambda: fmu.getFloat64([9999]), "9999")
    _fails(messages, lambda: fmu.setFloat64([vrs["der(x)"]], [1.0]), "der(x)")


def test_non_finite_input_is_refused_and_not_stored(slave):
    fmu, vrs, messages = slave
    fmu.enterInitializationMode(tolerance=1e-8)
    fmu.exitInitializationMode()
    fmu.setFloat64([vrs["flange_a.s"]], [0.25])
    _fails(messages, lambda: fmu.setFloat64([vrs["flange_a.s"]], [math.nan]), "flange_a.s")
    assert fmu.getFloat64([vrs["flange_a.s"]])[0] == 0.25
    _fails(messages, lambda: fmu.doStep(0.0, -0.1), "communicationStepSize")
    _fails(messages, lambda: fmu.setFloat64([vrs["m"]], [2.0]), "m")
    fmu.doStep(0.0, 0.1)  # still usable after refused calls


def test_unphysical_parameter_is_refused_at_initialisation(slave):
    fmu, vrs, messages = slave
    fmu.setFloat64([vrs["m"]], [-1.0])
    fmu.enterInitializationMode(tolerance=1e-8)
    _fails(messages, fmu.exitInitializationMode, "m (mass of the block, kg) must be > 0")


def test_parameter_relation_is_checked_inside_the_fmu(slave):
    fmu, vrs, messages = slave
    fmu.setFloat64([vrs["mu_s"]], [0.1])  # below the default mu_k = 0.3
    fmu.enterInitializationMode(tolerance=1e-8)
    _fails(messages, fmu.exitInitializationMode, "mu_k <= mu_s")
