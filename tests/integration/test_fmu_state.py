"""FMI 3 state round trip and declared nominal values."""
import math
from ctypes import c_double

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi3 import FMU3Model, FMU3Slave

from components import Component, SpringBlock
from components.interfaces import Parameter, Profile, State
from conftest import SEED_94, SEED_94_SPEED
from fmus import build_fmu


def _open(component, cls=FMU3Slave):
    path = build_fmu(component)
    md = read_model_description(str(path))
    fmu = cls(guid=md.guid, unzipDirectory=extract(str(path)),
              modelIdentifier=md.coSimulation.modelIdentifier, instanceName="block")
    fmu.instantiate()
    return fmu, md, {v.name: v.valueReference for v in md.modelVariables}


def _run(fmu, vr, t0, t1, h):
    rows, t = [], t0
    while t < t1 - 1e-12:
        fmu.setFloat64([vr["flange_a.s"], vr["flange_a.v"]], [SEED_94_SPEED * t, SEED_94_SPEED])
        fmu.doStep(t, h)
        t += h
        rows.append(fmu.getFloat64([vr["x"], vr["v"], vr["f_friction"]]) + fmu.getInt32([vr["mode"]]))
    return np.array(rows)


def test_state_round_trip_and_serialization_fmi3():
    """Run to t1, save, run to t2, restore, run to t2 again: identical outputs, also
    after serializing into a fresh instance; the interval crosses slip and stick."""
    fmu, _, vr = _open(SpringBlock(**SEED_94))
    fmu.enterInitializationMode(tolerance=1e-10)
    fmu.exitInitializationMode()
    _run(fmu, vr, 0.0, 7.0, 0.5)
    state = fmu.getFMUState()
    first = _run(fmu, vr, 7.0, 14.0, 0.5)
    assert set(first[:, 3]) == {0.0, 1.0}
    fmu.setFMUState(state)
    np.testing.assert_array_equal(_run(fmu, vr, 7.0, 14.0, 0.5), first)
    blob = fmu.serializeFMUState(state)
    fmu.freeFMUState(state)
    fresh, _, vr2 = _open(SpringBlock(**SEED_94))
    restored = fresh.deserializeFMUState(blob)
    fresh.setFMUState(restored)
    fresh.freeFMUState(restored)
    np.testing.assert_array_equal(_run(fresh, vr2, 7.0, 14.0, 0.5), first)
    for f in (fmu, fresh):
        f.terminate()
        f.freeInstance()


class _Scaled(Component):
    """Two states of very different size, each with its nominal value declared."""
    parameters = (Parameter("w", 2.0, "1/s", "angular frequency", min=0.0, min_strict=True),)
    states = (State("s", 1e-3, "m", "small displacement", nominal=1e-3),
              State("v", 0.0, "m/s", "its rate", nominal=2e-3))
    profiles = (Profile("free", "no ports"),)

    def equations(self, e):
        e.residual(e.der.s - e.x.v)
        e.residual(e.der.v + e.p.w ** 2 * e.x.s)


def test_declared_nominals_reach_the_xml_and_the_importer():
    path = build_fmu(_Scaled())
    md = read_model_description(str(path))
    declared = {v.name: float(v.nominal) for v in md.modelVariables if v.name in ("s", "v")}
    assert declared == {"s": 1e-3, "v": 2e-3}
    fmu = FMU3Model(guid=md.guid, unzipDirectory=extract(str(path)),
                    modelIdentifier=md.modelExchange.modelIdentifier, instanceName="scaled")
    fmu.instantiate()
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    nominals = (c_double * 2)()
    fmu.getNominalsOfContinuousStates(nominals, 2)
    assert list(nominals) == [1e-3, 2e-3]
    fmu.terminate()
    fmu.freeInstance()


def _me_instance(component):
    path = build_fmu(component)
    md = read_model_description(str(path))
    fmu = FMU3Model(guid=md.guid, unzipDirectory=extract(str(path)),
                    modelIdentifier=md.modelExchange.modelIdentifier, instanceName="m")
    fmu.instantiate()
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    fmu.enterContinuousTimeMode()
    return fmu, {v.name: v.valueReference for v in md.modelVariables}


def test_setting_the_time_recomputes_what_depends_on_it():
    """Setting the time alone keeps what a time-invariant model computed (the runtime
    skips that work, model.h time_invariant); a model written in terms of time must see
    each new time at once, even with its states unchanged."""
    from components.sources.motion import SineMotion
    fmu, vr = _me_instance(SineMotion(name="drive"))  # U = 0.1, omega = 20
    for t in (0.3, 0.7, 0.7, 0.05):
        fmu.setTime(t)
        s, v = fmu.getFloat64([vr["flange.s"], vr["flange.v"]])
        assert s == pytest.approx(0.1 * math.sin(20 * t), abs=1e-15)
        assert v == pytest.approx(2.0 * math.cos(20 * t), abs=1e-14)
    fmu.terminate()
    fmu.freeInstance()
    # and a time-invariant one gives the same derivatives at any time
    fmu, vr = _me_instance(_Scaled())
    slopes = []
    for t in (0.0, 5.0):
        fmu.setTime(t)
        dx = (c_double * 2)()
        fmu.getContinuousStateDerivatives(dx, 2)
        slopes.append(list(dx))
    assert slopes[0] == slopes[1] and slopes[0][1] != 0.0
    fmu.terminate()
    fmu.freeInstance()


def test_the_generated_model_says_whether_time_appears():
    from components.sources.motion import SineMotion
    from fmus.codegen import generate_c
    from components.dae import flatten
    for component, invariant in ((SineMotion(name="drive"), 0), (_Scaled(), 1)):
        text = generate_c(flatten(component), "m", "token")
        fields = [f.strip().rstrip(",") for f in
                  text[text.index("const mf_model MF_MODEL"):].split("\n")]
        # time_invariant is the field before the dd pattern's
        assert fields[fields.index("mf_dd_sparsity_out") - 1] == str(invariant), fields[-6:]
