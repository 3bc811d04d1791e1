"""mfEvaluateAt, the engine's one-call path into an FMU of ours run alone (issue 27): at
any point it gives what fmi3SetTime, fmi3SetContinuousStates,
fmi3GetContinuousStateDerivatives and fmi3GetEventIndicators give through fmpy on the
same instance, bit for bit; where one of those would refuse, it refuses as that call does,
with its message. mfEvaluateOff gives the same values without moving the instance (the
integrator's trial points). An engine run that takes them (FMI 3) and one
that cannot (FMI 2 has no such export) integrate the same model to the same bits."""
from ctypes import POINTER, c_double, c_int, c_size_t, c_void_p

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi3 import FMU3Model

from assemblies import Assembly
from assemblies.engine.me import simulate_me
from assemblies.masters.monolithic import composite
from assemblies.scenes import scene
from components import RollingCoin, SpringBlock
from fmus import build_fmu

ERROR = 3  # fmi3Error


class Me3:
    """One FMI 3 Model Exchange instance of `component` in Continuous-Time Mode."""

    def __init__(self, component, tmp_path):
        path = build_fmu(component, tmp_path / "m.fmu", fmi_version=3)
        md = read_model_description(str(path))
        self.n_x, self.n_z = len(md.derivatives), md.numberOfEventIndicators
        self.messages = []
        self.fmu = f = FMU3Model(guid=md.instantiationToken, unzipDirectory=extract(str(path)),
                                 modelIdentifier=type(component).__name__, instanceName="ea")
        f.instantiate(logMessage=lambda env, status, category, message:
                      self.messages.append(message.decode()))
        f.enterInitializationMode()
        f.exitInitializationMode()
        f.updateDiscreteStates()
        f.enterContinuousTimeMode()
        fn = f.dll.mfEvaluateAt  # AttributeError before issue 27: no such export
        fn.argtypes = [c_void_p, c_double, POINTER(c_double), c_size_t, POINTER(c_double),
                       POINTER(c_double), c_size_t]
        fn.restype = c_int
        self.evaluate_at = fn

    def standard(self, t, x):
        """(dx, z) through the four FMI calls."""
        dx, z = (c_double * self.n_x)(), (c_double * max(1, self.n_z))()
        self.fmu.setTime(t)
        self.fmu.setContinuousStates((c_double * self.n_x)(*x), self.n_x)
        self.fmu.getContinuousStateDerivatives(dx, self.n_x)
        if self.n_z:
            self.fmu.getEventIndicators(z, self.n_z)
        return np.array(dx), np.array(z[:self.n_z])

    def one_call(self, t, x, want_dx=True, want_z=True):
        """(status, dx, z) through mfEvaluateAt."""
        dx, z = (c_double * self.n_x)(), (c_double * max(1, self.n_z))()
        status = self.evaluate_at(self.fmu.component, t, (c_double * self.n_x)(*x), self.n_x,
                                  dx if want_dx else None, z if want_z and self.n_z else None,
                                  self.n_z)
        return status, np.array(dx), np.array(z[:self.n_z])

    def off_call(self, t, x, want_dx=True, want_z=True):
        """(status, dx, z) through mfEvaluateOff."""
        off = self.fmu.dll.mfEvaluateOff  # AttributeError before: no such export
        off.argtypes = [c_void_p, c_double, POINTER(c_double), POINTER(c_double),
                        POINTER(c_double)]
        off.restype = c_int
        dx, z = (c_double * self.n_x)(), (c_double * max(1, self.n_z))()
        status = off(self.fmu.component, t, (c_double * self.n_x)(*x),
                     dx if want_dx else None, z if want_z and self.n_z else None)
        return status, np.array(dx), np.array(z[:self.n_z])

    def where(self):
        """The instance's states and its derivatives there, as the FMI calls read them."""
        x, dx = (c_double * self.n_x)(), (c_double * self.n_x)()
        self.fmu.getContinuousStates(x, self.n_x)
        self.fmu.getContinuousStateDerivatives(dx, self.n_x)
        return np.array(x), np.array(dx)


@pytest.mark.parametrize("make", [lambda: SpringBlock(profile="driven_on_moving_support"),
                                  RollingCoin], ids=["block", "coin"])
def test_off_the_instance_gives_the_four_calls_bits_and_leaves_it_where_it_was(make, tmp_path):
    """mfEvaluateOff, the integrator's trial points (issue 27): the values of the four
    calls at (t, x), while the instance stays at the point it was set to, its states and
    derivatives there unchanged."""
    inst = Me3(make(), tmp_path)
    rng = np.random.default_rng(2727)
    for k in range(20):
        t, x = float(rng.uniform(0, 5)), rng.uniform(-1, 1, inst.n_x)
        want_dx, want_z = inst.standard(t, x)
        home_t, home_x = t + 1.0, -x
        inst.standard(home_t, home_x)  # the instance's own point from here on
        before = inst.where()
        status, dx, z = inst.off_call(t, x)
        assert status == 0
        assert dx.tobytes() == want_dx.tobytes() and z.tobytes() == want_z.tobytes()
        status, dx, _ = inst.off_call(t, x, want_z=False)
        assert status == 0 and dx.tobytes() == want_dx.tobytes()
        status, _, z = inst.off_call(t, x, want_dx=False)
        assert status == 0 and z.tobytes() == want_z.tobytes()
        after = inst.where()
        assert after[0].tobytes() == before[0].tobytes() == home_x.tobytes()
        assert after[1].tobytes() == before[1].tobytes()
    # a point the separate calls would refuse: declined, nothing logged (they say why)
    status, _, _ = inst.off_call(0.5, [float("nan")] + [0.0] * (inst.n_x - 1))
    assert status == 1
    status, _, _ = inst.off_call(float("inf"), [0.0] * inst.n_x)
    assert status == 1
    assert inst.messages == []


@pytest.mark.parametrize("make", [lambda: SpringBlock(profile="driven_on_moving_support"),
                                  RollingCoin], ids=["block", "coin"])
def test_one_call_gives_the_four_calls_bits(make, tmp_path):
    inst = Me3(make(), tmp_path)
    rng = np.random.default_rng(27)
    for k in range(20):
        t, x = float(rng.uniform(0, 5)), rng.uniform(-1, 1, inst.n_x)
        # the standard calls first at another point, so that nothing cached answers for it
        inst.standard(t + 1.0, -x)
        status, dx, z = inst.one_call(t, x)
        want_dx, want_z = inst.standard(t, x)
        assert status == 0
        assert dx.tobytes() == want_dx.tobytes() and z.tobytes() == want_z.tobytes()
        # the derivatives alone, then the indicators alone, at a fresh point each
        status, dx, _ = inst.one_call(t + 2.0, x, want_z=False)
        assert status == 0 and dx.tobytes() == inst.standard(t + 2.0, x)[0].tobytes()
        status, _, z = inst.one_call(t + 3.0, x, want_dx=False)
        assert status == 0 and z.tobytes() == inst.standard(t + 3.0, x)[1].tobytes()
    assert inst.messages == []


def test_a_point_the_four_calls_refuse_is_refused_as_they_refuse_it(tmp_path):
    """A state that is not finite: the status and the message of fmi3SetContinuousStates
    itself (the one-call path declines such points and makes the calls)."""
    inst = Me3(SpringBlock(profile="driven_on_moving_support"), tmp_path)
    bad = [float("nan")] + [0.0] * (inst.n_x - 1)
    status, _, _ = inst.one_call(0.5, bad)
    assert status == ERROR
    said = inst.messages[-1]
    assert said.startswith("fmi3SetContinuousStates: ") and "is not finite" in said
    inst.messages.clear()
    with pytest.raises(FMICallException):
        inst.fmu.setContinuousStates((c_double * inst.n_x)(*bad), inst.n_x)
    assert inst.messages == [said]
    status, _, _ = inst.one_call(float("inf"), [0.0] * inst.n_x)
    assert status == ERROR and inst.messages[-1].startswith("fmi3SetTime: ")


def test_an_engine_run_through_it_is_the_run_without_it():
    """stick_slip joined into one component, run alone: FMI 3 (the one-call path) and
    FMI 2 (separate calls) hold the same generated model, so the same steps,
    right-hand sides, located events and rows, to the bit."""
    runs = []
    for version in (3, 2):
        asm = Assembly("ea_stick_slip")
        asm.add("joined", composite(scene("stick_slip").build()))
        runs.append(simulate_me(asm, 20.0, 0.1, 1e-8, fmi_version=version))
    a, b = runs
    assert a.settings["events"] >= 3  # stick and slip, located in the dense output
    for key in ("steps", "rhs_calls", "events", "rejected"):
        assert a.settings[key] == b.settings[key], key
    for column in a.columns:
        assert np.asarray(a[column]).tobytes() == np.asarray(b[column]).tobytes(), column
