"""FMI 2.0 FMUs: valid for every component, fmi2* symbols only, and misuse answered with
Error (or Discard where FMI 2 says so) and a logged reason, through fmpy's low-level API."""
import itertools
import math
import subprocess
import zipfile
from ctypes import byref, c_double, c_int

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (FMU2Model, FMU2Slave, fmi2Discard, fmi2Error, fmi2LastSuccessfulTime,
                       fmi2Terminated, fmi2ValueReference)
from fmpy.validation import validate_fmu

from assemblies.cli import main as mechfmu
from components import COMPONENTS, SpringBlock
from conftest import drop_component
from cs_slave import fmi2_callbacks
from fmus import build_fmu


def _variants():
    """Every component x profile x combination of its string options; integer options
    (sizes such as a number of modes) stay at their default."""
    out = []
    for cls in COMPONENTS.values():
        choices = [o for o in cls.options if not isinstance(o.choices, range)]
        for profile in cls.profiles:
            for combo in itertools.product(*[o.choices for o in choices]):
                out.append((cls, profile.name, {o.name: c for o, c in zip(choices, combo)}))
    return out


VARIANTS = _variants()


def _exported_symbols(fmu_path, tmp_path):
    with zipfile.ZipFile(fmu_path) as zf:
        libraries = [n for n in zf.namelist() if n.startswith("binaries/")
                     and n.endswith((".so", ".dylib", ".dll"))]
        assert len(libraries) == 1, libraries
        zf.extract(libraries[0], tmp_path)
    out = subprocess.run(["nm", "-D", "--defined-only", str(tmp_path / libraries[0])],
                         capture_output=True, text=True, check=True).stdout
    return libraries[0], [line.split()[-1] for line in out.splitlines() if line.strip()]


@pytest.mark.parametrize("cls, profile, options", VARIANTS,
                         ids=[f"{c.__name__}-{p}-{'-'.join(map(str, o.values()))}" for c, p, o in VARIANTS])
def test_every_fmi2_fmu_validates_and_exports_only_fmi2(cls, profile, options, tmp_path):
    component = cls(profile=profile, **options)
    path = build_fmu(component, tmp_path / "model.fmu", fmi_version=2)
    assert validate_fmu(str(path)) == []
    md = read_model_description(str(path))
    assert md.fmiVersion == "2.0" and md.modelExchange and md.coSimulation
    library, symbols = _exported_symbols(path, tmp_path)
    assert library.startswith("binaries/linux64/")
    assert symbols and all(s.startswith("fmi2") for s in symbols), symbols
    # one variable table for both versions: same names, same value references
    md3 = read_model_description(str(build_fmu(component)))
    assert {v.name: v.valueReference for v in md.modelVariables} == \
        {v.name: v.valueReference for v in md3.modelVariables if v.name != "time"}
    for v in md.modelVariables:  # derivative="index" points at the right state
        if v.derivative is not None:
            assert v.name == f"der({v.derivative.name})"


def test_build_command_takes_the_fmi_version(tmp_path, capsys):
    assert mechfmu(["build", "SpringBlock", "--fmi", "2", "-o", str(tmp_path / "b2.fmu")]) == 0
    assert mechfmu(["build", "SpringBlock", "-o", str(tmp_path / "b3.fmu")]) == 0
    assert read_model_description(str(tmp_path / "b2.fmu")).fmiVersion == "2.0"
    assert read_model_description(str(tmp_path / "b3.fmu")).fmiVersion == "3.0"
    # the cache keeps the versions apart
    assert build_fmu(SpringBlock(), fmi_version=2) != build_fmu(SpringBlock(), fmi_version=3)
    with pytest.raises(SystemExit):
        mechfmu(["build", "SpringBlock", "--fmi", "1", "-o", str(tmp_path / "b1.fmu")])
    assert "invalid choice" in capsys.readouterr().err


# --- the low-level API -------------------------------------------------------------


Drop = drop_component()


T_HIT = math.sqrt(2 * 2.0 / 9.81)  # h = 2 - g t^2 / 2


MESSAGES: list = []


def _registered():
    """Fresh callbacks, registered now as the proxy's recipient (cs_slave.fmi2_callbacks):
    all of them record (status, text) into MESSAGES, and each check looks at the messages
    its call added."""
    return fmi2_callbacks(lambda status, message: MESSAGES.append((status, message.decode())))


def _open(component, kind, guid=None):
    path = build_fmu(component, fmi_version=2)
    md = read_model_description(str(path))
    fmu = kind(guid=guid or md.guid, unzipDirectory=extract(str(path)),
               modelIdentifier=md.coSimulation.modelIdentifier, instanceName="blk")
    fmu.instantiate(callbacks=_registered())
    return fmu, {v.name: v.valueReference for v in md.modelVariables}, MESSAGES


@pytest.fixture
def slave():
    fmu, vrs, messages = _open(SpringBlock(), FMU2Slave)
    yield fmu, vrs, messages
    fmu.freeInstance()


@pytest.fixture
def model():
    fmu, vrs, messages = _open(SpringBlock(), FMU2Model)
    yield fmu, vrs, messages
    fmu.freeInstance()


def _fails(messages, call, *words, status=fmi2Error):
    before = len(messages)
    with pytest.raises(FMICallException) as info:
        call()
    assert info.value.status == status
    assert len(messages) > before, "the refusal must be explained through the logger"
    level, text = messages[-1]
    assert level == status, (level, text)
    for word in words:
        assert word in text, text


def test_wrong_call_order_is_refused(slave, model):
    fmu, vrs, messages = slave
    _fails(messages, lambda: fmu.doStep(0.0, 0.1), "fmi2DoStep", "Instantiated")
    _fails(messages, fmu.exitInitializationMode, "fmi2ExitInitializationMode")
    fmu.setupExperiment(tolerance=1e-8)
    fmu.enterInitializationMode()
    _fails(messages, lambda: fmu.setupExperiment(tolerance=1e-6), "fmi2SetupExperiment",
           "Initialization Mode")
    me, _, me_messages = model
    _fails(me_messages, me.enterContinuousTimeMode, "fmi2EnterContinuousTimeMode")
    x = (c_double * 2)()
    _fails(me_messages, lambda: me.fmi2SetContinuousStates(me.component, x, 2),
           "fmi2SetContinuousStates")


def test_unknown_references_and_absent_types_are_refused(slave):
    fmu, vrs, messages = slave
    _fails(messages, lambda: fmu.getReal([9999]), "fmi2GetReal", "9999")
    _fails(messages, lambda: fmu.getInteger([vrs["x"]]), "'x'", "Real, not Integer")
    _fails(messages, lambda: fmu.getBoolean([vrs["x"]]), "Boolean")
    _fails(messages, lambda: fmu.setString([vrs["x"]], ["a"]), "String")
    _fails(messages, lambda: fmu.setReal([vrs["der(x)"]], [1.0]), "der(x)", "cannot be set")


def test_non_finite_input_negative_step_and_late_parameter_are_refused(slave):
    fmu, vrs, messages = slave
    fmu.setupExperiment(tolerance=1e-8)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    fmu.setReal([vrs["flange_a.s"]], [0.25])
    _fails(messages, lambda: fmu.setReal([vrs["flange_a.s"]], [math.nan]), "flange_a.s",
           "not finite")
    assert fmu.getReal([vrs["flange_a.s"]]) == [0.25]
    _fails(messages, lambda: fmu.doStep(0.0, -0.1), "communicationStepSize")
    _fails(messages, lambda: fmu.doStep(0.0, 0.0), "communicationStepSize")
    _fails(messages, lambda: fmu.doStep(1.0, 0.1), "currentCommunicationPoint")
    _fails(messages, lambda: fmu.setReal([vrs["m"]], [2.0]), "'m'")
    fmu.doStep(0.0, 0.1)  # still usable after refused calls
    assert fmu.getReal([vrs["x"]])[0] == 0.0  # held by static friction


def test_unphysical_parameter_is_refused_at_exit_initialization(slave):
    fmu, vrs, messages = slave
    fmu.setReal([vrs["m"]], [-1.0])
    fmu.setupExperiment()
    fmu.enterInitializationMode()
    _fails(messages, fmu.exitInitializationMode, "m (mass of the block, kg) must be > 0")
    _fails(messages, lambda: fmu.doStep(0.0, 0.1), "fmi2DoStep")


def test_bad_experiment_and_unsupported_functions_are_refused(slave):
    fmu, vrs, messages = slave
    _fails(messages, lambda: fmu.setupExperiment(tolerance=-1.0), "tolerance")
    _fails(messages, lambda: fmu.setupExperiment(startTime=math.inf), "startTime")
    _fails(messages, lambda: fmu.getDirectionalDerivative([vrs["a"]], [vrs["x"]], [1.0]),
           "fmi2GetDirectionalDerivative")
    _fails(messages, lambda: fmu.setRealInputDerivatives([vrs["flange_a.s"]], [1], [0.1]),
           "canInterpolateInputs")
    _fails(messages, lambda: fmu.fmi2CancelStep(fmu.component), "fmi2CancelStep")
    value = c_double()
    _fails(messages, lambda: fmu.fmi2GetRealStatus(fmu.component, fmi2Terminated, byref(value)),
           "fmi2LastSuccessfulTime")


def test_instantiate_checks_guid_and_fmu_type():
    path = build_fmu(SpringBlock(), fmi_version=2)
    md = read_model_description(str(path))
    fmu = FMU2Slave(guid="{not-this-one}", unzipDirectory=extract(str(path)),
                    modelIdentifier="SpringBlock", instanceName="blk")
    with pytest.raises(Exception, match="Failed to instantiate"):
        fmu.instantiate(callbacks=_registered())
    assert "GUID '{not-this-one}'" in MESSAGES[-1][1] and md.guid in MESSAGES[-1][1]
    bad_type = fmu.fmi2Instantiate(b"blk", 7, md.guid.encode(), b"", byref(_registered()), 0, 0)
    assert not bad_type and "fmuType 7" in MESSAGES[-1][1]
    fmu.freeLibrary()


def test_null_instance_is_an_error_not_a_crash(slave):
    fmu, vrs, messages = slave
    for call in (lambda: fmu.fmi2DoStep(None, 0.0, 0.1, 1),
                 lambda: fmu.fmi2EnterInitializationMode(None),
                 lambda: fmu.fmi2GetReal(None, (fmi2ValueReference * 1)(1), 1, (c_double * 1)())):
        with pytest.raises(FMICallException) as info:
            call()
        assert info.value.status == fmi2Error


def _damped_block():
    return SpringBlock(m=1, k=1, g=1, mu_k=0.6, mu_s=0.6, x=6.55)


def test_setup_experiment_tolerance_and_start_time_reach_the_solver():
    # the first half-cycle of seed 9.4: x = 0.6 + 5.95 cos(t - 5)
    errors = {}
    for tol in (1e-3, 1e-11):
        fmu, vrs, messages = _open(_damped_block(), FMU2Slave)
        fmu.setupExperiment(tolerance=tol, startTime=5.0)
        fmu.enterInitializationMode()
        fmu.exitInitializationMode()
        fmu.doStep(5.0, 3.0)  # starts at 5: a doStep from 0 would be refused
        errors[tol] = abs(fmu.getReal([vrs["x"]])[0] - (0.6 + 5.95 * math.cos(3.0)))
        fmu.terminate()
        fmu.freeInstance()
    assert errors[1e-11] < 1e-9 and errors[1e-3] > 100 * errors[1e-11], errors


def test_model_that_ends_the_run_answers_discard_with_terminated_status():
    fmu, vrs, messages = _open(Drop(), FMU2Slave)
    fmu.setupExperiment(tolerance=1e-10)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    fmu.doStep(0.0, 0.5)
    with pytest.raises(FMICallException) as info:
        fmu.doStep(0.5, 0.5)
    assert info.value.status == fmi2Discard
    assert any("hit the ground" in text for _, text in messages)
    terminated, reached = c_int(), c_double()
    fmu.fmi2GetBooleanStatus(fmu.component, fmi2Terminated, byref(terminated))
    fmu.fmi2GetRealStatus(fmu.component, fmi2LastSuccessfulTime, byref(reached))
    assert terminated.value == 1 and reached.value == pytest.approx(T_HIT, abs=1e-9)
    assert fmu.getReal([vrs["h"]])[0] == pytest.approx(0.0, abs=1e-9)
    # and stays ended: the FMI 2 state machine allows no doStep once the slave said it
    # terminated (only fmi2Terminate), so a further one is an Error with the reason logged
    logged = len(messages)
    with pytest.raises(FMICallException) as info:
        fmu.doStep(reached.value, 0.5)
    assert info.value.status == fmi2Error
    assert any("hit the ground" in text for _, text in messages[logged:])
    fmu.terminate()
    fmu.freeInstance()


def test_model_exchange_new_discrete_states_reports_termination():
    fmu, vrs, messages = _open(Drop(), FMU2Model)
    fmu.setupExperiment()
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    assert fmu.newDiscreteStates()[:2] == (0, 0)  # no more iteration needed, not terminated
    fmu.enterContinuousTimeMode()
    fmu.setTime(T_HIT + 1e-3)
    h = 2.0 - 9.81 * (T_HIT + 1e-3) ** 2 / 2
    x = (c_double * 2)(h, -9.81 * (T_HIT + 1e-3))
    fmu.setContinuousStates(x, 2)
    fmu.enterEventMode()
    assert fmu.newDiscreteStates()[1] == 1  # terminateSimulation
    fmu.terminate()
    fmu.freeInstance()


def _run(fmu, vrs, t0, t1, h):
    out, t = [], t0
    while t < t1 - 1e-12:
        fmu.setReal([vrs["flange_a.s"], vrs["flange_a.v"]], [0.05 * t, 0.05])
        fmu.doStep(t, h)
        t += h
        out.append(fmu.getReal([vrs["x"], vrs["v"], vrs["f_friction"]]) + fmu.getInteger([vrs["mode"]]))
    return np.array(out)


def test_fmu_state_round_trip_and_serialization():
    """Run to t1, save, run to t2, restore, run to t2 again: the same outputs, bit for bit,
    also after serializing into a fresh instance. The interval crosses slip and stick."""
    fmu, vrs, _ = _open(SpringBlock(m=1, k=1, g=1, mu_k=0.3, mu_s=0.4), FMU2Slave)
    fmu.setupExperiment(tolerance=1e-10)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    _run(fmu, vrs, 0.0, 7.0, 0.5)
    state = fmu.getFMUstate()
    first = _run(fmu, vrs, 7.0, 14.0, 0.5)
    assert set(first[:, 3]) == {0.0, 1.0}  # stuck, sliding, stuck again
    fmu.setFMUstate(state)
    np.testing.assert_array_equal(_run(fmu, vrs, 7.0, 14.0, 0.5), first)
    blob = fmu.serializeFMUstate(state)
    fmu.freeFMUstate(state)

    fresh, vrs2, messages = _open(SpringBlock(m=1, k=1, g=1, mu_k=0.3, mu_s=0.4), FMU2Slave)
    _fails(messages, lambda: fresh.deSerializeFMUstate(blob[:-1]), "fmi2DeSerializeFMUstate")
    restored = fresh.deSerializeFMUstate(blob)
    fresh.setFMUstate(restored)
    fresh.freeFMUstate(restored)
    np.testing.assert_array_equal(_run(fresh, vrs2, 7.0, 14.0, 0.5), first)
    for f in (fmu, fresh):
        f.terminate()
        f.freeInstance()
